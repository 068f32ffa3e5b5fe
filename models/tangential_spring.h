/* tangential_spring: the Cundall-Strack tangential spring with history (issue 13), the pair law.
 *
 * Wired into the engine (models/list.h, GR_HISTORY_MODELS): the kernels keep s per contact in the
 * store of src/core/contact_history.c (one slot per touching pair, carried across neighbour-list
 * rebuilds and checkpoints). With rotation (`rotation = true`) g_t is the contact point's, surface
 * velocities included (models/law.h), and the force's torque a F_t acts on both discs; the
 * spring's share a (-k_t s) is conservative, and the kernels keep it out of the torque work the
 * spin kicks book as dissipation (src/integrators/verlet/step.c, spin_kicks). Not yet: the Mindlin
 * stiffness k_t ~ sqrt(xi), the CVODE reference of src/collide/reference.c (docs/models.md,
 * "tangential_spring").
 *
 * The contact remembers s, the tangential displacement accumulated since it formed, kept along the
 * current tangent t (in 2D s is a scalar along t; exchanging i and j reverses n, t and g but
 * leaves g_t = g.t and hence s unchanged). Per step, as LAMMPS's `tangential linear_history`
 * (src/GRANULAR/gran_sub_mod_tangential.cpp, GranSubModTangentialLinearHistory):
 *   s <- s + g_t dt;   F_t = -k_t s - gamma_t g_t;
 *   if |F_t| > mu |F_n|:  F_t <- mu |F_n| sign(F_t),  s <- -(F_t + gamma_t g_t) / k_t
 * (slip: the spring is shortened so that spring plus dashpot give exactly the Coulomb force;
 * LAMMPS leaves s untouched when it is 0 and then sets F_t = 0). The history is dropped (s = 0)
 * as soon as the normal force no longer acts.
 *
 * Energy: the spring stores U_t = k_t s^2 / 2 (returned as `e`, J). Over the step the force does
 * the work F_t g_t dt on the relative motion, so what the step dissipates (dashpot + slip) is
 * -F_t g_t dt - (U_t(new) - U_t(old)), returned as the power p (>= 0 up to rounding). */
#ifndef GR_MODELS_TANGENTIAL_SPRING_H
#define GR_MODELS_TANGENTIAL_SPRING_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_tangential_spring;

/* the constants of the law, in gr_contact_coeffs.law_t */
enum { GR_SPRING_KT = 0, GR_SPRING_GAMMA = 1, GR_SPRING_DT = 2 };

/* The step of the law: in.hist[0] holds s on entry and the updated s on return (the kernel passes
 * a copy and commits it once per pair and step). */
enum { GR_BOOK_tangential_spring = GR_BOOK_FRICTION };
GR_LAW gr_tangential_force gr_tangential_tangential_spring(const gr_contact_coeffs *c, const gr_tangential_in in)
{
    gr_tangential_force o = {.f = 0.0, .p = 0.0, .e = 0.0};
    const double s_old = in.hist[0];
    const double k = c->law_t[GR_SPRING_KT], gamma = c->law_t[GR_SPRING_GAMMA], dt = c->law_t[GR_SPRING_DT];
    if (!in.acts) {
        in.hist[0] = 0.0; /* the contact broke (or the clamp holds F_n at 0): forget it */
        /* the stored energy is lost with it, and the work the last force did over the step
         * (trapezoid, see the slip below: s_trial = s_old + g_t dt, s_new = 0) */
        o.lost = 0.5 * k * s_old * (s_old + in.g_t * dt);
        o.p = o.lost / dt;
        return o;
    }
    double s = s_old + in.g_t * dt;
    double f = -k * s - gamma * in.g_t;
    const double f_max = c->mu * fabs(in.f_n);
    if (fabs(f) > f_max) {
        if (s != 0.0) {
            f = copysign(f_max, f);
            const double s_slip = -(f + gamma * in.g_t) / k;
            /* slip: the energy the rescale drops, as the kicks see it. The kernel's force works on
             * the relative motion like a trapezoid, -k (s_old + s_new) / 2 g_t dt over the step, so
             * what the spring loses beyond that work is k (s_old + s_new) / 2 (s_trial - s_new)
             * (s_trial = s_old + g_t dt; with no slip it is 0 and the work is exactly -dU) */
            o.lost = 0.5 * k * (s_old + s_slip) * (s - s_slip);
            s = s_slip;
        } else {
            f = 0.0; /* as LAMMPS: no spring yet, no force */
        }
    }
    in.hist[0] = s;
    o.f = f;
    o.fc = -k * s;
    o.e = 0.5 * k * s * s;
    o.p = -f * in.g_t - (o.e - 0.5 * k * s_old * s_old) / dt;
    return o;
}

#ifdef GR_MODEL_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

static const gr_param tangential_spring_params[] = {
    {"kt_ratio", "", GR_PARAM_DOUBLE, 2.0 / 7.0, 0.0, INFINITY, true, true,
     "tangential stiffness k_t = kt_ratio m12 w0^2: kt_ratio k_s for spring_dashpot, for hertz its stiffness "
     "linearised at the v_max impact (2/7: the usual DEM choice, after solid spheres); ignored when k_t > 0",
     offsetof(gr_contact_params, kt_ratio)},
    {"k_t", "N/m", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "tangential spring constant; 0: from kt_ratio",
     offsetof(gr_contact_params, k_t)},
    {"gamma_t", "kg/s", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "tangential dashpot in parallel with the spring (LAMMPS linear_history's damping); 0: none",
     offsetof(gr_contact_params, gamma_t)},
    {"mu", "", GR_PARAM_DOUBLE, 0.5, 0.0, INFINITY, false, true,
     "Coulomb limit |F_t| <= mu |F_n|: beyond it the contact slips and the spring is shortened",
     offsetof(gr_contact_params, mu)},
    GR_ROTATION_PARAMS,
};

static int tangential_spring_prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                                     gr_error *err)
{
    (void)m12;
    c->tangential = GR_TANGENTIAL_SPRING;
    c->mu = p->mu;
    /* k_t = kt_ratio m12 w0^2: kt_ratio k_s for the linear law; for hertz w0 is its contact
     * linearised at the v_max impact (models/hertz.h) */
    double k_t = p->k_t;
    if (k_t == 0.0) {
        k_t = p->kt_ratio * (c->pow_a == 1.0 ? c->k_s : c->m12 * c->w0 * c->w0);
    }
    /* a contact never lasts forever here: the tangential oscillation w_t = sqrt(k_t / m_t) and the
     * dashpot are explicit in the kernel, so the step must resolve them */
    const double w_t = sqrt(k_t / c->m_t);
    if (dt > 0.0 && w_t * dt > 2.0 * M_PI / 10.0) {
        return GR_FAIL(err, GR_EINVAL, "[model] tangential_spring: k_t = %g N/m oscillates with period %.4g s, "
                       "fewer than 10 steps of dt = %g s; allowed k_t <= %.4g N/m (or a smaller dt)",
                       k_t, 2.0 * M_PI / w_t, dt, c->m_t * pow(2.0 * M_PI / (10.0 * dt), 2));
    }
    if (dt > 0.0 && p->gamma_t * dt >= c->m_t) {
        return GR_FAIL(err, GR_EINVAL, "[model] gamma_t = %g kg/s is too large for dt = %g s (explicit "
                       "damping); allowed gamma_t < m_t / dt = %.4g kg/s", p->gamma_t, dt, c->m_t / dt);
    }
    c->law_t[GR_SPRING_KT] = k_t;
    c->law_t[GR_SPRING_GAMMA] = p->gamma_t;
    c->law_t[GR_SPRING_DT] = dt > 0.0 ? dt : 1.0; /* dt = 0: the continuous law (no kernel runs) */
    return GR_OK;
}

/* mu = 0: no tangential force at all (the Coulomb limit is 0), the kernel without it runs */
static bool tangential_spring_inert(const gr_contact_coeffs *c) { return c->mu == 0.0; }

const gr_model gr_model_tangential_spring = {
    .name = "tangential_spring",
    .summary = "Cundall-Strack tangential spring with history and Coulomb limit (LAMMPS linear_history)",
    .kind = GR_MODEL_TANGENTIAL,
    .params = tangential_spring_params,
    .n_params = sizeof tangential_spring_params / sizeof tangential_spring_params[0],
    .prepare = tangential_spring_prepare,
    .inert = tangential_spring_inert,
    .contact_point = true,
    .elastic = "mu=0",
};
#endif /* GR_MODEL_IMPL */

#endif
