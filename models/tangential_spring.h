/* tangential_spring: the Cundall-Strack tangential spring with history (issue 13), the pair law.
 *
 * STATUS: the pair law only. It is NOT in models/list.h yet: the engine's per-contact history
 * store (one slot per touching pair, carried across neighbour-list rebuilds and checkpoints), the
 * CVODE reference of src/collide/reference.c and the restitution law the conformance suite needs
 * are not written (docs/models.md, "tangential_spring (work in progress)"). tests/test_tangential_spring.c
 * tests the law on its own.
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
        o.p = 0.5 * k * s_old * s_old / dt; /* the stored energy is lost with it */
        return o;
    }
    double s = s_old + in.g_t * dt;
    double f = -k * s - gamma * in.g_t;
    const double f_max = c->mu * fabs(in.f_n);
    if (fabs(f) > f_max) {
        if (s != 0.0) {
            f = copysign(f_max, f);
            s = -(f + gamma * in.g_t) / k;
        } else {
            f = 0.0; /* as LAMMPS: no spring yet, no force */
        }
    }
    in.hist[0] = s;
    o.f = f;
    o.e = 0.5 * k * s * s;
    o.p = -f * in.g_t - (o.e - 0.5 * k * s_old * s_old) / dt;
    return o;
}

#endif
