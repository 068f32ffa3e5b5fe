/* spring_dashpot: the linear spring-dashpot normal contact force of the thesis (2.4-2.6),
 *   F_n = k_s xi - gamma_n (v12 . n),  xi = d - |r12| > 0,
 * in two modes:
 *  - clamp = false (the thesis): gamma_n from eq. 2.6, which gives exactly the requested eps_n
 *    because the contact ends when the overlap returns to zero; the dashpot then pulls the
 *    particles together at the end of the contact (an attractive force).
 *  - clamp = true: F_n = max(0, F_n), never attractive. The contact ends when the force vanishes
 *    and the restitution is that of Schwager & Poeschel (2007); gamma_n is found by inverting it,
 *    so the requested eps_n still holds exactly in continuous time.
 * docs/models.md compares both. */
#ifndef GR_MODELS_SPRING_DASHPOT_H
#define GR_MODELS_SPRING_DASHPOT_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_spring_dashpot;

/* The pair law (2.4-2.5): f = k_s xi - gamma_n g_n, elastic energy k_s xi^2 / 2. */
GR_LAW gr_normal_force gr_normal_spring_dashpot(const gr_contact_coeffs *c, const double xi,
                                                const double g_n, const int clamp)
{
    const double k = c->k_s;
    double f = k * xi - c->gamma_n * g_n;
    if (clamp) {
        f = f > 0.0 ? f : 0.0;
    }
    return (gr_normal_force){.f = f, .f_d = f - k * xi, .e = xi * xi};
}

#endif /* GR_MODELS_SPRING_DASHPOT_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_SPRING_DASHPOT_IMPL)
#define GR_MODELS_SPRING_DASHPOT_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

#include "models/spring_dashpot_restitution.h"

static const gr_param spring_dashpot_params[] = {
    {"k_s", "N/m", GR_PARAM_DOUBLE, 5e5, 0.0, INFINITY, true, true,
     "normal spring constant (2.4); Table 2.2: 5e5", offsetof(gr_contact_params, k_s)},
    {"eps_n", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "normal coefficient of restitution (2.2); 1 = elastic, 0 = sticking (unclamped only)",
     offsetof(gr_contact_params, eps_n)},
    {"clamp", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "true: normal force never attractive, gamma_n from the exact clamped restitution "
     "(Schwager & Poeschel 2007); false: thesis eq. 2.6",
     offsetof(gr_contact_params, clamp)},
};

static int spring_dashpot_prepare(const gr_contact_params *p, double m12, double dt,
                                  gr_contact_coeffs *c, gr_error *err)
{
    (void)dt;
    c->k_s = p->k_s;
    c->m12 = m12;
    c->clamp = p->clamp;
    c->w0 = sqrt(p->k_s / m12);
    if (p->clamp) {
        if (p->eps_n <= 0.0) {
            return GR_FAIL(err, GR_EINVAL,
                           "[model] eps_n = 0 cannot be reached with clamp = true (it needs an "
                           "infinite dashpot); allowed range with clamping: (0, 1]; use clamp = "
                           "false for a sticking contact");
        }
        c->zeta = spring_dashpot_zeta_clamped(p->eps_n);
        c->t_c = spring_dashpot_duration_clamped(c->zeta) / c->w0;
        c->eps_n_exact = spring_dashpot_eps_clamped(c->zeta);
    } else {
        c->zeta = spring_dashpot_zeta_unclamped(p->eps_n); /* eq. 2.6 */
        c->t_c = spring_dashpot_duration_unclamped(c->zeta) / c->w0;
        c->eps_n_exact = p->eps_n;
    }
    c->gamma_n = 2.0 * c->zeta * sqrt(p->k_s * m12);
    c->e_scale = 0.5 * p->k_s; /* U = k_s xi^2 / 2 */
    c->pow_a = 1.0;
    c->pow_p = 0.0;
    return GR_OK;
}

/* Its impact: eps_n and t_c the same at every speed (2.6, or Schwager-Poeschel clamped). The
 * unclamped force turns attractive at the end of the contact, so int |F_n| dt exceeds the net
 * impulse m12 (1 + eps_n) v_n: with xi' = v e^(-beta t) (cos wt - (beta/w) sin wt), int |F_n| dt
 * = m12 (total variation of xi') = m12 v (1 - eps_n + 2 u), -u v the minimum of xi', reached
 * where xi'' = 0, at w t* = pi - atan2(2 beta w, w^2 - beta^2) (critical damping: beta t* = 2). */
static gr_normal_impact spring_dashpot_impact(const gr_contact_coeffs *c, double v_n)
{
    (void)v_n;
    gr_normal_impact o = {c->eps_n_exact, c->t_c, 1.0 + c->eps_n_exact};
    if (!c->clamp && c->zeta > 0.0) {
        const double beta = c->zeta * c->w0, w = c->w0 * sqrt(fmax(0.0, 1.0 - c->zeta * c->zeta));
        double u;
        if (w > 0.0) {
            const double ts = (M_PI - atan2(2.0 * beta * w, w * w - beta * beta)) / w;
            u = -exp(-beta * ts) * (cos(w * ts) - beta / w * sin(w * ts));
        } else {
            u = exp(-2.0); /* xi' = v e^(-beta t) (1 - beta t), minimum at beta t = 2 */
        }
        o.impulse_abs = 1.0 - c->eps_n_exact + 2.0 * u;
    }
    return o;
}

const gr_model gr_model_spring_dashpot = {
    .name = "spring_dashpot",
    .summary = "linear spring-dashpot normal force (thesis 2.4-2.6), optionally clamped repulsive",
    .kind = GR_MODEL_NORMAL,
    .params = spring_dashpot_params,
    .n_params = sizeof spring_dashpot_params / sizeof spring_dashpot_params[0],
    .prepare = spring_dashpot_prepare,
    .impact = spring_dashpot_impact,
    .elastic = "eps_n=1",
    .lammps_pair = "gran/hooke",
};
#endif /* GR_MODEL_IMPL */
