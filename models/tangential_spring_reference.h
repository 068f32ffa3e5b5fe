/* tangential_spring's force in the CVODE reference (gr_model.reference, models/reference.h),
 * included by models/tangential_spring.h inside GR_MODEL_IMPL.
 *
 * The Cundall-Strack spring in continuous time: F_t = -(k_t s + gamma_t g_c) with ds/dt = g_c while
 * |F_t| < mu |F_n| (sticking); at the limit (slipping, `mode`) F_t = -sign mu |F_n| and s is not a
 * state any more but the algebraic value that keeps k_t s + gamma_t g_c = sign mu |F_n| (what the
 * engine's rescale converges to as dt -> 0). The contact slips on while the free rate of
 * k_t s + gamma_t g_c (ds/dt = g_c) would carry it past the limit faster than the limit moves:
 * phi = sign (k_t g_c + gamma_t dg_c/dt + s dk_t/dt) - d(mu |F_n|)/dt > 0; it sticks again where
 * phi falls through 0. Both switches are roots (|k_t s + gamma_t g_c| reaching mu |F_n| sticking:
 * roots 2 and 3; phi reaching 0 slipping: root 0), so the right-hand side is smooth inside each
 * regime; root 1 is F_n changing sign (an unclamped law pulling at the end). k_t = kt0 + km
 * sqrt(xi) (Mindlin: kt0 = 0); the Mindlin spring also integrates int k_t s ds (GR_REF_Y_QUAD),
 * its stored energy but for what k_t(xi) adds by changing. */
#ifndef GR_MODELS_TANGENTIAL_SPRING_REFERENCE_H
#define GR_MODELS_TANGENTIAL_SPRING_REFERENCE_H

#include <math.h>

#include "models/reference.h"

/* constants (gr_ref_tangential.k) and scratch values (gr_ref_point.aux) */
enum { SPRING_REF_KT = 0, SPRING_REF_KM, SPRING_REF_CT, SPRING_REF_MU };
enum { SPRING_AUX_S = 0, SPRING_AUX_TRIAL, SPRING_AUX_LIM, SPRING_AUX_RATE, SPRING_AUX_PHI };

static void tangential_spring_ref_setup(const gr_contact_coeffs *c, double m12, double w0,
                                        double len, gr_ref_tangential *l)
{
    l->k[SPRING_REF_KT] = c->law_t[GR_SPRING_KT] / (m12 * w0 * w0);
    l->k[SPRING_REF_KM] = c->law_t[GR_SPRING_KM] * sqrt(len) / (m12 * w0 * w0);
    l->k[SPRING_REF_CT] = c->law_t[GR_SPRING_GAMMA] / (m12 * w0);
    l->k[SPRING_REF_MU] = c->mu;
}

/* The regime at the touch (s = 0, xi = 0): it sticks if |k_t s + gamma_t g_c| stays within
 * mu |F_n| just after the touch. Both sides start as powers of the time (F_n ~ t^a for an
 * undamped law, t^p with damping, k_t s ~ t or t^(3/2) with Mindlin), so their ratio at a tiny
 * time along the free flight decides. */
static void tangential_spring_ref_start(gr_ref_tangential *l, double gn0, double gc0,
                                        bool has_tangent)
{
    (void)has_tangent;
    const double e = 1e-8, X = -gn0 * e;
    const double fn = pow(X, l->pow_a) - l->c_n * pow(X, l->pow_p) * gn0;
    const double trial =
        (l->k[SPRING_REF_KT] + l->k[SPRING_REF_KM] * sqrt(X)) * gc0 * e + l->k[SPRING_REF_CT] * gc0;
    l->mode = fabs(trial) > l->k[SPRING_REF_MU] * fabs(fn);
    l->sign = trial < 0.0 ? -1.0 : 1.0;
}

static void tangential_spring_ref_force(const gr_ref_tangential *l, gr_ref_point *p)
{
    const double km = l->k[SPRING_REF_KM], ct = l->k[SPRING_REF_CT], mu = l->k[SPRING_REF_MU];
    const double X = fmax(p->xi, 0.0), sq = sqrt(X);
    const double kk = l->k[SPRING_REF_KT] + km * sq;
    const double dk = sq > 0.0 ? 0.5 * km / sq * -p->gn : 0.0;
    const double lim = mu * l->fn_sign * p->fn, dlim = mu * l->fn_sign * p->dfn;
    double s, ft;
    if (l->mode) {
        ft = -l->sign * lim;
        s = kk > 0.0 ? (l->sign * lim - ct * p->gc) / kk : 0.0;
    } else {
        s = p->y[GR_REF_Y_STATE];
        ft = -(kk * s + ct * p->gc);
    }
    const double trial = kk * s + ct * p->gc;
    const double dgc = gr_ref_gc_rate(p, ft);
    const double rate = kk * p->gc + ct * dgc + s * dk;
    const double sdot =
        l->mode ? (l->sign * dlim - ct * dgc - s * dk) / (kk > 0.0 ? kk : 1.0) : p->gc;
    p->ft = ft;
    p->ydot[GR_REF_Y_STATE] = l->mode ? 0.0 : p->gc;
    p->ydot[GR_REF_Y_QUAD] = km != 0.0 ? kk * s * sdot : 0.0;
    p->e = 0.5 * kk * s * s;
    p->e_work = km != 0.0 ? p->y[GR_REF_Y_QUAD] : p->e; /* int k_t s ds */
    p->aux[SPRING_AUX_S] = s;
    p->aux[SPRING_AUX_TRIAL] = trial;
    p->aux[SPRING_AUX_LIM] = lim;
    p->aux[SPRING_AUX_RATE] = rate;
    p->aux[SPRING_AUX_PHI] = l->sign * rate - dlim;
}

static void tangential_spring_ref_roots(const gr_ref_tangential *l, const gr_ref_point *p,
                                        double g[GR_REF_NROOTS])
{
    g[0] = l->mode ? p->aux[SPRING_AUX_PHI] : 1.0;
    g[1] = !l->clamp ? l->fn_sign * p->fn : 1.0;
    g[2] = !l->mode ? p->aux[SPRING_AUX_LIM] - p->aux[SPRING_AUX_TRIAL] : 1.0;
    g[3] = !l->mode ? p->aux[SPRING_AUX_LIM] + p->aux[SPRING_AUX_TRIAL] : 1.0;
}

static int tangential_spring_ref_event(gr_ref_tangential *l, const bool found[GR_REF_NROOTS],
                                       gr_ref_point *p)
{
    int r = 0;
    if (found[0] && l->mode) {
        /* it sticks again where the constraint left s */
        p->y[GR_REF_Y_STATE] = p->aux[SPRING_AUX_S];
        l->mode = false;
        r |= GR_REF_RESTART;
    }
    if ((found[2] || found[3]) && !l->mode) {
        l->mode = true; /* the spring force reached the Coulomb limit */
        l->sign = found[2] ? 1.0 : -1.0;
        r |= GR_REF_RESTART;
    }
    if (found[1]) {
        /* F_n changed sign: the limit mu |F_n| is 0 there, so the spring leaves it in whichever
         * regime its free rate allows: slipping (in the direction of the free rate of
         * k_t s + gamma_t g_c) if that rate beats the limit's growth, sticking otherwise */
        l->fn_sign = -l->fn_sign;
        if (l->mode) {
            p->y[GR_REF_Y_STATE] = p->aux[SPRING_AUX_S];
            l->mode = false;
        }
        tangential_spring_ref_force(l, p);
        l->sign = p->aux[SPRING_AUX_RATE] < 0.0 ? -1.0 : 1.0;
        l->mode = true;
        tangential_spring_ref_force(l, p);
        if (!(p->aux[SPRING_AUX_PHI] > 0.0)) {
            l->mode = false;
        }
        r |= GR_REF_RESTART;
    }
    return r;
}

static const gr_reference_law tangential_spring_reference = {
    .setup = tangential_spring_ref_setup,
    .start = tangential_spring_ref_start,
    .force = tangential_spring_ref_force,
    .roots = tangential_spring_ref_roots,
    .event = tangential_spring_ref_event,
    .plane_only = true,
};

#endif
