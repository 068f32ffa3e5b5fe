/* tangential_spring: the Cundall-Strack tangential spring with history (issue 13), the pair law.
 *
 * Wired into the engine (models/list.h, GR_HISTORY_MODELS): the kernels keep s per contact in the
 * store of src/core/contact_history.c (one slot per touching pair, carried across neighbour-list
 * rebuilds and checkpoints). Its restitution law (models/tangential_spring_restitution.h) and its
 * force in the CVODE reference (models/tangential_spring_reference.h) integrate the
 * continuous-time stick-slip. Options: a
 * Mindlin stiffness k_t = km sqrt(xi) (`mindlin = true`, hertz only; LAMMPS `tangential mindlin`).
 * With rotation (`rotation = true`) g_t is the contact point's, surface velocities included
 * (models/law.h), and the force's torque a F_t acts on both discs; the spring's share a (-k_t s) is
 * conservative, and the kernels keep it out of the torque work the spin kicks book as dissipation
 * (src/integrators/verlet/step.c, spin_kicks) (docs/models.md, "tangential_spring").
 *
 * The contact remembers s, the tangential displacement accumulated since it formed, kept along the
 * current tangent t (in 2D s is a scalar along t; exchanging i and j reverses n, t and g but
 * leaves g_t = g.t and hence s unchanged). Per step, as LAMMPS's `tangential linear_history`
 * (src/GRANULAR/gran_sub_mod_tangential.cpp, GranSubModTangentialLinearHistory):
 *   s <- s + g_t dt;   F_t = -k_t s - gamma_t g_t;
 *   if |F_t| > mu |F_n|:  F_t <- mu |F_n| sign(F_t),  s <- -(F_t + gamma_t g_t) / k_t
 * (slip: the spring is shortened so that spring plus dashpot give exactly the Coulomb force;
 * LAMMPS leaves s untouched when it is 0 and then sets F_t = 0). The history is dropped (s = 0)
 * as soon as the normal force no longer acts. One departure from LAMMPS: in the step where the
 * contact forms, s grows by g_t dt / 2, the mean time since the touch (below).
 *
 * Energy: the spring stores U_t = k_t s^2 / 2 (returned as `e`, J). Over the step the force does
 * the work F_t g_t dt on the relative motion, so what the step dissipates (dashpot + slip) is
 * -F_t g_t dt - (U_t(new) - U_t(old)), returned as the power p (>= 0 up to rounding). */
#ifndef GR_MODELS_TANGENTIAL_SPRING_H
#define GR_MODELS_TANGENTIAL_SPRING_H

#include <math.h>

#include "models/hertz.h" /* hertz_own: Mindlin reads v_max */
#include "models/law.h"

extern const gr_model gr_model_tangential_spring;

/* its own parameters (gr_contact_params.own) */
typedef struct tangential_spring_own {
    double kt_ratio; /* k_t / k_s (linear normal law) */
    double k_t;      /* tangential spring constant, N/m (0: kt_ratio k_s) */
    double gamma_t;  /* tangential dashpot in parallel with the spring, kg/s */
    bool mindlin;    /* k_t ~ sqrt(xi) (Mindlin; normal = hertz only) */
} tangential_spring_own;

/* the constants of the law, in gr_contact_coeffs.law_t: k_t = KT + KM sqrt(xi) (linear: KM = 0;
 * Mindlin: KT = 0) */
enum { GR_SPRING_KT = 0, GR_SPRING_GAMMA = 1, GR_SPRING_DT = 2, GR_SPRING_KM = 3 };

/* k_t now (*k) and at the previous step (*k_old): constant, or Mindlin's k_t ~ sqrt(xi), where the
 * previous overlap is xi + g_n dt (the kernel's g_n is the velocity that drifted the step). */
GR_LAW void gr_spring_stiffness(const gr_contact_coeffs *c, const double xi, const double g_n,
                                double *k, double *k_old)
{
    const double km = c->law_t[GR_SPRING_KM];
    *k = *k_old = c->law_t[GR_SPRING_KT];
    if (km != 0.0) {
        *k = km * sqrt(fmax(xi, 0.0));
        *k_old = km * sqrt(fmax(xi + g_n * c->law_t[GR_SPRING_DT], 0.0));
    }
}

/* The step of the law: in.hist[0] holds s on entry and the updated s on return (the kernel passes
 * a copy and commits it once per pair and step). */
enum { GR_BOOK_tangential_spring = GR_BOOK_FRICTION };
GR_LAW gr_tangential_force gr_tangential_tangential_spring(const gr_contact_coeffs *c,
                                                           const gr_tangential_in in)
{
    gr_tangential_force o = {.f = 0.0, .p = 0.0, .e = 0.0};
    const double s_old = in.hist[0];
    const double gamma = c->law_t[GR_SPRING_GAMMA], dt = c->law_t[GR_SPRING_DT];
    double k, k_old;
    gr_spring_stiffness(c, in.xi, in.g_n, &k, &k_old);
    if (!in.acts) {
        in.hist[0] = 0.0; /* the contact broke (or the clamp holds F_n at 0): forget it */
        /* the stored energy is lost with it, and the work the last force did over the step
         * (trapezoid, see the slip below: s_trial = s_old + g_t dt, s_new = 0) */
        o.lost = 0.5 * k_old * s_old * (s_old + in.g_t * dt);
        o.p = o.lost / dt;
        return o;
    }
    /* a contact that formed during this step has moved only since it touched, half a step ago on
     * average over where the touch falls: LAMMPS adds the full g_t dt, a one-signed shift that
     * makes the restitution's error first order with a coefficient of about 0.25 dt / t_c against
     * the CVODE reference (0.02-0.04 with the half step). The time since the touch, xi / |g_n|,
     * would do as well on average but makes s depend on the positions' rounding with the
     * sensitivity 1 / |g_n| (grazing touches): many-body runs then diverge from rounding 200
     * times faster (tests/test_history_engine.c, skin 0 against 5: 2.5e-6 against 1.3e-8) */
    const double dt_s = s_old == 0.0 ? 0.5 * dt : dt;
    double s = s_old + in.g_t * dt_s;
    double f = -k * s - gamma * in.g_t;
    const double f_max = c->mu * fabs(in.f_n);
    if (fabs(f) > f_max) {
        if (s != 0.0 && k > 0.0) {
            f = copysign(f_max, f);
            s = -(f + gamma * in.g_t) / k; /* slip: the spring shortened to the limit */
        } else {
            f = 0.0; /* as LAMMPS: no spring yet, no force */
        }
    }
    in.hist[0] = s;
    o.f = f;
    o.fc = -k * s;
    o.e = 0.5 * k * s * s;
    o.p = -f * in.g_t - (o.e - 0.5 * k_old * s_old * s_old) / dt;
    /* the energy the step drops beyond the work of the spring, as the kicks see it: the kernel's
     * conservative force works like a trapezoid, (k_old s_old + k s) / 2 g_t dt, against the
     * change k s^2 / 2 - k_old s_old^2 / 2 of the stored energy. 0 while sticking with a constant
     * k_t; the slip's drop k (s_old + s) (s_trial - s) / 2 (s_trial = s_old + g_t dt) at the limit;
     * with Mindlin also -(k - k_old) s_old s / 2, the energy k_t's change adds without work */
    if (s != s_old + in.g_t * dt || k != k_old) {
        o.lost = 0.5 * (k_old * s_old + k * s) * in.g_t * dt - (o.e - 0.5 * k_old * s_old * s_old);
    }
    return o;
}

/* The same step with s a 3-vector (3D, models/law.h: gr_tangential_in3; the kernel has turned s
 * into the current tangent plane and rescaled it to its length, as LAMMPS's pair granular does):
 *   s <- s + g_c dt;   F_t = -k_t s - gamma_t g_c;
 *   if |F_t| > mu |F_n|:  F_t <- mu |F_n| F_t / |F_t|,  s <- -(F_t + gamma_t g_c) / k_t,
 * the Coulomb limit on the vector's length; the energy terms as above with products turned into
 * dot products. A contact in a plane (s, g_c along one tangent) gives the scalar step's numbers. */
static inline double gr_spring_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

GR_LAW gr_tangential_force3 gr_tangential3_tangential_spring(const gr_contact_coeffs *c,
                                                             const gr_tangential_in3 in)
{
    gr_tangential_force3 o = {.p = 0.0};
    double *h = in.hist;
    const double s_old[3] = {h[0], h[1], h[2]};
    const double gamma = c->law_t[GR_SPRING_GAMMA], dt = c->law_t[GR_SPRING_DT];
    double k, k_old;
    gr_spring_stiffness(c, in.xi, in.g_n, &k, &k_old);
    const double ss_old = gr_spring_dot3(s_old, s_old), e_old = 0.5 * k_old * ss_old;
    if (!in.acts) {
        h[0] = h[1] = h[2] = 0.0;
        o.lost = 0.5 * k_old * (ss_old + gr_spring_dot3(s_old, in.g) * dt);
        o.p = o.lost / dt;
        return o;
    }
    const double dt_s = ss_old == 0.0 ? 0.5 * dt : dt; /* as the scalar step: the touch's half */
    double s[3], f[3];
    for (int a = 0; a < 3; a++) {
        s[a] = s_old[a] + in.g[a] * dt_s;
        f[a] = -k * s[a] - gamma * in.g[a];
    }
    const double f_max = c->mu * fabs(in.f_n), f2 = gr_spring_dot3(f, f);
    if (f2 > f_max * f_max) {
        const bool spring = (s[0] != 0.0 || s[1] != 0.0 || s[2] != 0.0) && k > 0.0;
        const double scale = spring ? f_max / sqrt(f2) : 0.0;
        for (int a = 0; a < 3; a++) {
            f[a] *= scale; /* no spring yet: no force, as LAMMPS */
            if (spring) {
                s[a] = -(f[a] + gamma * in.g[a]) / k; /* slip: the spring shortened to the limit */
            }
        }
    }
    bool moved = k != k_old;
    for (int a = 0; a < 3; a++) {
        moved = moved || s[a] != s_old[a] + in.g[a] * dt;
        h[a] = s[a];
        o.f[a] = f[a];
        o.fc[a] = -k * s[a];
    }
    o.e = 0.5 * k * gr_spring_dot3(s, s);
    o.p = -gr_spring_dot3(f, in.g) - (o.e - e_old) / dt;
    if (moved) {
        double w = 0.0; /* (k_old s_old + k s) . g_c */
        for (int a = 0; a < 3; a++) {
            w += (k_old * s_old[a] + k * s[a]) * in.g[a];
        }
        o.lost = 0.5 * w * dt - (o.e - e_old);
    }
    return o;
}

#endif /* GR_MODELS_TANGENTIAL_SPRING_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_TANGENTIAL_SPRING_IMPL)
#define GR_MODELS_TANGENTIAL_SPRING_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>
#include <string.h>

static const gr_param tangential_spring_params[] = {
    {"kt_ratio", "", GR_PARAM_DOUBLE, 2.0 / 7.0, 0.0, INFINITY, true, true,
     "tangential stiffness k_t = kt_ratio m12 w0^2: kt_ratio k_s for spring_dashpot, for hertz its "
     "stiffness "
     "linearised at the v_max impact (2/7: the usual DEM choice, after solid spheres); mindlin = "
     "true: "
     "k_t = kt_ratio (3/2) k_h sqrt(xi); ignored when k_t > 0",
     GR_OWN_KEY(tangential_spring, kt_ratio)},
    {"k_t", "N/m", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "tangential spring constant; 0: from kt_ratio; mindlin = true: k_t sqrt(xi / x0), x0 the "
     "overlap unit of "
     "the v_max impact, (m12 v_max^2 / k_h)^(2/5)",
     GR_OWN_KEY(tangential_spring, k_t)},
    {"gamma_t", "kg/s", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "tangential dashpot in parallel with the spring (LAMMPS linear_history's damping); 0: none",
     GR_OWN_KEY(tangential_spring, gamma_t)},
    {"mu", "", GR_PARAM_DOUBLE, 0.5, 0.0, INFINITY, false, true,
     "Coulomb limit |F_t| <= mu |F_n|: beyond it the contact slips and the spring is shortened",
     offsetof(gr_contact_params, mu)},
    {"mindlin", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "true (normal = hertz only): Mindlin stiffness k_t ~ sqrt(xi), as LAMMPS tangential mindlin's "
     "8 G_eff a, a = sqrt(R_eff xi) (s kept, not rescaled); false: constant k_t",
     GR_OWN_KEY(tangential_spring, mindlin)},
    GR_ROTATION_PARAMS,
};

/* hertz's overlap unit x0 = (m12 v^2 / k_h)^(2/5) at the v_max impact (models/hertz.h): the
 * Mindlin stiffness equals the linear one, kt_ratio m12 w0^2 or k_t, at xi = x0; the undamped
 * v_max impact reaches xi = (5/4)^(2/5) x0 at most */
#define SPRING_HERTZ_XMAX 1.0934

static int tangential_spring_prepare(const gr_contact_params *p, double m12, double dt,
                                     gr_contact_coeffs *c, gr_error *err)
{
    const tangential_spring_own *o = GR_OWN(p, tangential_spring);
    (void)m12;
    c->mu = p->mu;
    /* k_t = kt_ratio m12 w0^2: kt_ratio k_s for the linear law; for hertz w0 is its contact
     * linearised at the v_max impact (models/hertz.h) */
    double k_t = o->k_t;
    if (k_t == 0.0) {
        k_t = o->kt_ratio * (c->pow_a == 1.0 ? c->k_s : c->m12 * c->w0 * c->w0);
    }
    double k_max = k_t, km = 0.0; /* the stiffest k_t of a v_max contact, for the step check */
    if (o->mindlin) {
        const char *nn = c->normal_model ? c->normal_model->name : "none";
        if (strcmp(nn, "hertz") != 0) {
            return GR_FAIL(
                err, GR_EINVAL,
                "[model] mindlin = true needs normal = hertz (given %s): the Mindlin "
                "stiffness k_t ~ sqrt(xi) is the Hertz contact's; allowed: mindlin = false with %s",
                nn, nn);
        }
        /* k_t(xi) = km sqrt(xi), equal to the linear k_t at xi = x0: with kt_ratio, km = kt_ratio
         * (3/2) k_h, i.e. kt_ratio times the Hertz law's own stiffness dF_n/dxi */
        const double x0 =
            pow(c->m12 * GR_OWN(p, hertz)->v_max * GR_OWN(p, hertz)->v_max / c->k_s, 0.4);
        km = k_t / sqrt(x0);
        k_max = km * sqrt(SPRING_HERTZ_XMAX * x0);
        k_t = 0.0;
    }
    /* a contact never lasts forever here: the tangential oscillation w_t = sqrt(k_t / m_t) and the
     * dashpot are explicit in the kernel, so the step must resolve them */
    const double w_t = sqrt(k_max / c->m_t);
    if (dt > 0.0 && w_t * dt > 2.0 * M_PI / 10.0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "[model] tangential_spring: k_t = %g N/m%s oscillates with period %.4g s, "
            "fewer than 10 steps of dt = %g s; allowed k_t <= %.4g N/m (or a smaller dt)",
            k_max, o->mindlin ? " (Mindlin, at the v_max impact's largest overlap)" : "",
            2.0 * M_PI / w_t, dt, c->m_t * pow(2.0 * M_PI / (10.0 * dt), 2));
    }
    if (dt > 0.0 && o->gamma_t * dt >= c->m_t) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] gamma_t = %g kg/s is too large for dt = %g s (explicit "
                       "damping); allowed gamma_t < m_t / dt = %.4g kg/s",
                       o->gamma_t, dt, c->m_t / dt);
    }
    c->law_t[GR_SPRING_KT] = k_t;
    c->law_t[GR_SPRING_GAMMA] = o->gamma_t;
    c->law_t[GR_SPRING_DT] = dt > 0.0 ? dt : 1.0; /* dt = 0: the continuous law (no kernel runs) */
    c->law_t[GR_SPRING_KM] = km;
    return GR_OK;
}

#include "models/tangential_spring_restitution.h"
#include "models/tangential_spring_reference.h"

/* mu = 0: no tangential force at all (the Coulomb limit is 0), the kernel without it runs */
static bool tangential_spring_inert(const gr_contact_coeffs *c) { return c->mu == 0.0; }

/* the conformance suite tests both stiffnesses (Mindlin with the normal laws that accept it) */
static const char *const tangential_spring_variants[] = {"mindlin=false", "mindlin=true", NULL};

const gr_model gr_model_tangential_spring = {
    .name = "tangential_spring",
    .summary =
        "Cundall-Strack tangential spring with history and Coulomb limit (LAMMPS linear_history)",
    .kind = GR_MODEL_TANGENTIAL,
    .params = tangential_spring_params,
    .n_params = sizeof tangential_spring_params / sizeof tangential_spring_params[0],
    .prepare = tangential_spring_prepare,
    .inert = tangential_spring_inert,
    .restitution_t = tangential_spring_restitution_t,
    .reference = &tangential_spring_reference,
    .contact_point = true,
    .elastic = "mu=0",
    .variants = tangential_spring_variants,
};
#endif /* GR_MODEL_IMPL */
