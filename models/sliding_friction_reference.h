/* sliding_friction's force in the CVODE reference (gr_model.reference, models/reference.h),
 * included by models/sliding_friction.h inside GR_MODEL_IMPL.
 *
 * Coulomb friction (2.7) in continuous time, as the engine's chatter-free step gives it as
 * dt -> 0. Sliding (`mode`): F_t = -mu |F_n| along g_c (in the plane, the sign it had at the
 * touch). Sliding stops where g_c reaches 0 (root 0; the reference cancels the rest of g_c). Then
 * the step's cap, the force that stops g_c within one step, holds g_c at 0: stuck, F_t is the
 * force that keeps dg_c/dt = 0 against the geometry (with rotation the turning line of centres
 * and the spins make g_c grow again by themselves: F_t = -(dg_c/dt at F_t = 0) / (1 + |r|^2 /
 * (q D^2)), gr_ref_gc_rate), for as long as that is within mu |F_n| (root 2); beyond it the
 * contact slides again, along the free rate of g_c. Without rotation that force is 0 and g_c
 * stays 0. Root 1: F_n changes sign (an unclamped law pulling at the end), so |F_n| = fn_sign F_n
 * stays smooth. Between spheres out of the plane the same with vectors (gr_reference_law3). */
#ifndef GR_MODELS_SLIDING_FRICTION_REFERENCE_H
#define GR_MODELS_SLIDING_FRICTION_REFERENCE_H

#include <math.h>

#include "models/reference.h"

enum { SLIDING_FRICTION_REF_MU = 0 };
enum { SLIDING_AUX_HOLD = 0, SLIDING_AUX_LIM = 1 }; /* the stuck force (plane), the limit */

static void sliding_friction_ref_setup(const gr_contact_coeffs *c, double m12, double w0,
                                       double len, gr_ref_tangential *l)
{
    (void)m12;
    (void)w0;
    (void)len;
    l->k[SLIDING_FRICTION_REF_MU] = c->mu;
}

static void sliding_friction_ref_start(gr_ref_tangential *l, double gn0, double gc0,
                                       bool has_tangent)
{
    (void)gn0;
    l->mode = has_tangent;
    l->sign = gc0 < 0.0 ? -1.0 : 1.0;
}

/* 1 + |r|^2 / (q D^2): how much more an impulse changes g_c with the spins than without */
static double sliding_ref_mass_factor(bool rot, double rn, double q, double D)
{
    return rot ? 1.0 + rn * rn / (q * D * D) : 1.0;
}

static void sliding_friction_ref_force(const gr_ref_tangential *l, gr_ref_point *p)
{
    const double lim = l->k[SLIDING_FRICTION_REF_MU] * l->fn_sign * p->fn;
    const double hold =
        -gr_ref_gc_rate(p, 0.0) / sliding_ref_mass_factor(p->rot, p->rn, p->q, p->D);
    p->ft = l->mode ? -lim * l->sign : hold; /* (2.7) */
    p->aux[SLIDING_AUX_HOLD] = hold;
    p->aux[SLIDING_AUX_LIM] = lim;
}

static void sliding_friction_ref_roots(const gr_ref_tangential *l, const gr_ref_point *p,
                                       double g[GR_REF_NROOTS])
{
    g[0] = l->mode ? l->sign * p->gc : 1.0;
    g[1] = !l->clamp ? l->fn_sign * p->fn : 1.0;
    g[2] = !l->mode ? p->aux[SLIDING_AUX_LIM] - fabs(p->aux[SLIDING_AUX_HOLD]) : 1.0;
    g[3] = 1.0;
}

static int sliding_friction_ref_event(gr_ref_tangential *l, const bool found[GR_REF_NROOTS],
                                      gr_ref_point *p)
{
    int r = 0;
    if (found[1]) {
        l->fn_sign = -l->fn_sign;
        r |= GR_REF_RESTART;
    }
    if (found[0] && l->mode) {
        l->mode = false; /* sliding stopped: the cap holds g_c at 0 from here */
        r |= GR_REF_RESTART | GR_REF_STOP;
    }
    if (!l->mode && (found[0] || found[1] || found[2])) {
        sliding_friction_ref_force(l, p); /* the holding force against the limit, now */
        const double hold = p->aux[SLIDING_AUX_HOLD];
        if (fabs(hold) > p->aux[SLIDING_AUX_LIM]) {
            l->mode = true; /* it cannot hold: slide along g_c's free rate, -hold */
            l->sign = hold > 0.0 ? -1.0 : 1.0;
            r |= GR_REF_RESTART;
        }
    }
    return r;
}

/* ---- spheres: the same with vectors (g_c, F_t in the tangent plane) ------------------------- */
enum { SLIDING_V_HOLD = 0 };

static double sliding_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* the force that keeps g_c at 0: -(dg_c/dt at F_t = 0) across n over the mass factor */
static void sliding_ref3_hold(const gr_ref_point3 *p, double hold[3])
{
    const double zero[3] = {0.0, 0.0, 0.0};
    double r[3];
    gr_ref_gc_rate3(p, zero, r);
    const double rn = sliding_dot3(r, p->n), f = sliding_ref_mass_factor(p->rot, p->rn, p->q, p->D);
    for (int a = 0; a < 3; a++) {
        hold[a] = -(r[a] - rn * p->n[a]) / f;
    }
}

static void sliding_friction_ref3_force(const gr_ref_tangential *l, gr_ref_point3 *p)
{
    const double lim = l->k[SLIDING_FRICTION_REF_MU] * l->fn_sign * p->fn;
    double hold[3];
    sliding_ref3_hold(p, hold);
    const double gcn = sqrt(sliding_dot3(p->gc, p->gc)), hn = sqrt(sliding_dot3(hold, hold));
    for (int a = 0; a < 3; a++) {
        /* sliding against g_c; where g_c is 0 (it resumes), against its free rate, -hold */
        const double e = gcn > GR_REF3_STOP_FLOOR ? p->gc[a] / gcn : hn > 0.0 ? -hold[a] / hn : 0.0;
        p->ft[a] = l->mode ? -lim * e : hold[a];
        p->vaux[SLIDING_V_HOLD][a] = hold[a];
    }
    p->yscale = 1.0;
    p->aux[SLIDING_AUX_HOLD] = hn;
    p->aux[SLIDING_AUX_LIM] = lim;
    p->aux[2] = gcn;
}

static void sliding_friction_ref3_start(const gr_ref_tangential *l, gr_ref_point3 *p)
{
    (void)l;
    (void)p; /* no state: the regime is the plane's start with |g_c| */
}

static void sliding_friction_ref3_roots(const gr_ref_tangential *l, const gr_ref_point3 *p,
                                        double g[GR_REF_NROOTS])
{
    g[0] = l->mode ? p->aux[2] - GR_REF3_STOP_FLOOR : 1.0; /* |g_c| reaches 0 without crossing */
    g[1] = !l->clamp ? l->fn_sign * p->fn : 1.0;
    g[2] = !l->mode ? p->aux[SLIDING_AUX_LIM] - p->aux[SLIDING_AUX_HOLD] : 1.0;
    g[3] = 1.0;
}

static int sliding_friction_ref3_event(gr_ref_tangential *l, const bool found[GR_REF_NROOTS],
                                       gr_ref_point3 *p)
{
    int r = 0;
    if (found[1]) {
        l->fn_sign = -l->fn_sign;
        r |= GR_REF_RESTART;
    }
    if (found[0] && l->mode) {
        l->mode = false;
        r |= GR_REF_RESTART | GR_REF_STOP;
    }
    if (!l->mode && (found[0] || found[1] || found[2])) {
        sliding_friction_ref3_force(l, p);
        if (p->aux[SLIDING_AUX_HOLD] > p->aux[SLIDING_AUX_LIM]) {
            l->mode = true;
            r |= GR_REF_RESTART;
        }
    }
    return r;
}

static const gr_reference_law3 sliding_friction_reference3 = {
    .start = sliding_friction_ref3_start,
    .force = sliding_friction_ref3_force,
    .roots = sliding_friction_ref3_roots,
    .event = sliding_friction_ref3_event,
};

static const gr_reference_law sliding_friction_reference = {
    .setup = sliding_friction_ref_setup,
    .start = sliding_friction_ref_start,
    .force = sliding_friction_ref_force,
    .roots = sliding_friction_ref_roots,
    .event = sliding_friction_ref_event,
    .sphere = &sliding_friction_reference3,
};

#endif
