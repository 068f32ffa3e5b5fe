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
#include <string.h>

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

/* k_t = kt0 + km sqrt(xi) and its rate, the Coulomb limit mu |F_n| and its rate at a point */
typedef struct spring_ref_at {
    double kk, dk, lim, dlim;
} spring_ref_at;

static spring_ref_at spring_ref_at_point(const gr_ref_tangential *l, double xi, double gn,
                                         double fn, double dfn)
{
    const double km = l->k[SPRING_REF_KM], mu = l->k[SPRING_REF_MU], sq = sqrt(fmax(xi, 0.0));
    return (spring_ref_at){.kk = l->k[SPRING_REF_KT] + km * sq,
                           .dk = sq > 0.0 ? 0.5 * km / sq * -gn : 0.0,
                           .lim = mu * l->fn_sign * fn,
                           .dlim = mu * l->fn_sign * dfn};
}

static void tangential_spring_ref_force(const gr_ref_tangential *l, gr_ref_point *p)
{
    const double km = l->k[SPRING_REF_KM], ct = l->k[SPRING_REF_CT];
    const spring_ref_at at = spring_ref_at_point(l, p->xi, p->gn, p->fn, p->dfn);
    const double kk = at.kk, dk = at.dk, lim = at.lim, dlim = at.dlim;
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

/* ---- spheres: s a vector in the tangent plane (gr_reference_law3) ------------------------------
 *
 * The engine's 3D step (models/tangential_spring.h, gr_tangential3_tangential_spring) turns s into
 * the current tangent plane, adds g_c dt and cuts k_t s + gamma_t g_c back to mu |F_n| along its
 * own direction. As dt -> 0: sticking, s stays normal to n, ds/dt = g_c - (s.dn/dt) n with
 * s.dn/dt = s.g / |r| (the turn costs only O(dt^2) of the length the kernel restores), and
 * F_t = -T, T = k_t s + gamma_t g_c. Slipping, F_t = -mu |F_n| e with e the direction of T,
 * which the free rate T' = s dk_t/dt + k_t ds/dt + gamma_t dg_c/dt (s from k_t s = mu |F_n| e -
 * gamma_t g_c) turns at the rate of its part across e over mu |F_n|, as the step's cut does. The
 * state is then a vector V along e whose length stays what it was set to: dV/dt = |V| (T' -
 * (e.T') e) / (mu |F_n|). Only the direction is integrated: the limit's own rate, singular at the
 * end of a contact with a damping ~ xi^p, enters the root phi = e.T' - d(mu |F_n|)/dt only (as in
 * the plane, where slipping integrates nothing). Where the limit is 0 (the touch of an undamped
 * law, F_n changing sign) the cut leaves T' alone, so e starts along T'. The switches are the
 * plane's: sticking ends where |T| reaches mu |F_n| (root 2), slipping where phi falls through 0
 * (root 0), and F_n changing sign (root 1) restarts the spring in the regime its free rate
 * allows. */
enum { SPRING_V_S = 0, SPRING_V_TF = 1 }; /* gr_ref_point3.vaux: s and the free rate of T */
enum { SPRING_AUX_TNORM = SPRING_AUX_PHI + 1 };

static double spring_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void tangential_spring_ref3_force(const gr_ref_tangential *l, gr_ref_point3 *p)
{
    const double km = l->k[SPRING_REF_KM], ct = l->k[SPRING_REF_CT];
    const spring_ref_at at = spring_ref_at_point(l, p->xi, p->gn, p->fn, p->dfn);
    const double kk = at.kk, dk = at.dk, lim = at.lim, dlim = at.dlim;
    double s[3], e[3] = {0.0, 0.0, 0.0}, ft[3], T[3];
    if (l->mode) {
        const double qn = sqrt(spring_dot3(p->y, p->y)), gcn = sqrt(spring_dot3(p->gc, p->gc));
        for (int a = 0; a < 3; a++) {
            e[a] = qn > 0.0 ? p->y[a] / qn : gcn > 0.0 ? p->gc[a] / gcn : 0.0;
            ft[a] = -lim * e[a];
            s[a] = kk > 0.0 ? (lim * e[a] - ct * p->gc[a]) / kk : 0.0;
        }
    } else {
        for (int a = 0; a < 3; a++) {
            s[a] = p->y[a];
            ft[a] = -(kk * s[a] + ct * p->gc[a]);
        }
    }
    double dgc[3], sdot[3], Tf[3];
    gr_ref_gc_rate3(p, ft, dgc);
    const double sg = spring_dot3(s, p->g) / p->rn; /* s.dn/dt */
    for (int a = 0; a < 3; a++) {
        T[a] = kk * s[a] + ct * p->gc[a];
        sdot[a] = p->gc[a] - sg * p->n[a]; /* the free rate of s: the touch point's drift, turned */
        Tf[a] = dk * s[a] + kk * sdot[a] + ct * dgc[a];
    }
    const double eT = spring_dot3(e, Tf), phi = eT - dlim;
    const double vn = sqrt(spring_dot3(p->y, p->y)), turn = lim > 0.0 ? vn / lim : 0.0;
    for (int a = 0; a < 3; a++) {
        p->ft[a] = ft[a];
        const double across = Tf[a] - eT * e[a]; /* mu |F_n| de/dt */
        p->ydot[GR_REF3_Y_VEC + a] = l->mode ? turn * across : sdot[a];
        if (l->mode) { /* k_t ds/dt = d(mu |F_n| e)/dt - gamma_t dg_c/dt - s dk_t/dt */
            sdot[a] = (dlim * e[a] + across - ct * dgc[a] - dk * s[a]) / (kk > 0.0 ? kk : 1.0);
        }
        p->vaux[SPRING_V_S][a] = s[a];
        p->vaux[SPRING_V_TF][a] = Tf[a];
    }
    p->ydot[GR_REF3_Y_QUAD] = km != 0.0 ? kk * spring_dot3(s, sdot) : 0.0;
    p->yscale = l->mode ? fmax(lim, 0.0) : 1.0; /* slipping, the state is e: F_t = -lim e */
    p->e = 0.5 * kk * spring_dot3(s, s);
    p->e_work = km != 0.0 ? p->y[GR_REF3_Y_QUAD] : p->e;
    p->aux[SPRING_AUX_LIM] = lim;
    p->aux[SPRING_AUX_PHI] = phi;
    p->aux[SPRING_AUX_TNORM] = sqrt(spring_dot3(T, T));
}

static void spring_ref3_set(gr_ref_point3 *p, const double v[3], double scale)
{
    for (int a = 0; a < 3; a++) {
        p->y[GR_REF3_Y_VEC + a] = scale * v[a];
    }
}

/* slipping where the limit is 0: e along T' (s = -gamma_t g_c / k_t there, whatever e is) */
static void spring_ref3_along_rate(const gr_ref_tangential *l, gr_ref_point3 *p)
{
    tangential_spring_ref3_force(l, p);
    const double *Tf = p->vaux[SPRING_V_TF];
    const double tn = sqrt(spring_dot3(Tf, Tf));
    if (tn > 0.0) {
        spring_ref3_set(p, Tf, 1.0 / tn);
    }
}

/* at the touch (s = 0): sticking, s = 0; slipping, e along g_c (the direction of
 * T = gamma_t g_c + k_t g_c dt / 2 after the engine's first step), or along T' where the limit
 * is 0 there */
static void tangential_spring_ref3_start(const gr_ref_tangential *l, gr_ref_point3 *p)
{
    const double gcn = sqrt(spring_dot3(p->gc, p->gc));
    spring_ref3_set(p, p->gc, l->mode && gcn > 0.0 ? 1.0 / gcn : 0.0);
    if (l->mode && !(l->k[SPRING_REF_MU] * fabs(p->fn) > 0.0)) {
        spring_ref3_along_rate(l, p);
    }
}

static void tangential_spring_ref3_roots(const gr_ref_tangential *l, const gr_ref_point3 *p,
                                         double g[GR_REF_NROOTS])
{
    g[0] = l->mode ? p->aux[SPRING_AUX_PHI] : 1.0;
    g[1] = !l->clamp ? l->fn_sign * p->fn : 1.0;
    g[2] = !l->mode ? p->aux[SPRING_AUX_LIM] - p->aux[SPRING_AUX_TNORM] : 1.0;
    g[3] = 1.0;
}

static int tangential_spring_ref3_event(gr_ref_tangential *l, const bool found[GR_REF_NROOTS],
                                        gr_ref_point3 *p)
{
    int r = 0;
    if (found[0] && l->mode) { /* it sticks again where the constraint left s */
        spring_ref3_set(p, p->vaux[SPRING_V_S], 1.0);
        l->mode = false;
        r |= GR_REF_RESTART;
    }
    if (found[2] && !l->mode) { /* |T| reached the Coulomb limit: e along T there */
        double T[3];
        const double kk = spring_ref_at_point(l, p->xi, p->gn, p->fn, p->dfn).kk;
        for (int a = 0; a < 3; a++) {
            T[a] = kk * p->y[GR_REF3_Y_VEC + a] + l->k[SPRING_REF_CT] * p->gc[a];
        }
        const double tn = sqrt(spring_dot3(T, T));
        spring_ref3_set(p, T, tn > 0.0 ? 1.0 / tn : 0.0);
        l->mode = true;
        r |= GR_REF_RESTART;
    }
    if (found[1]) {
        /* F_n changed sign, the limit is 0 there: slip along the free rate of T if that beats the
         * limit's growth, else stick (the plane's event with a direction for the sign) */
        l->fn_sign = -l->fn_sign;
        if (l->mode) {
            spring_ref3_set(p, p->vaux[SPRING_V_S], 1.0);
            l->mode = false;
        }
        double s[3];
        memcpy(s, p->y, sizeof s);
        l->mode = true;
        spring_ref3_along_rate(l, p);
        tangential_spring_ref3_force(l, p);
        if (!(p->aux[SPRING_AUX_PHI] > 0.0)) {
            spring_ref3_set(p, s, 1.0);
            l->mode = false;
        }
        r |= GR_REF_RESTART;
    }
    return r;
}

static const gr_reference_law3 tangential_spring_reference3 = {
    .start = tangential_spring_ref3_start,
    .force = tangential_spring_ref3_force,
    .roots = tangential_spring_ref3_roots,
    .event = tangential_spring_ref3_event,
};

static const gr_reference_law tangential_spring_reference = {
    .setup = tangential_spring_ref_setup,
    .start = tangential_spring_ref_start,
    .force = tangential_spring_ref_force,
    .roots = tangential_spring_ref_roots,
    .event = tangential_spring_ref_event,
    .sphere = &tangential_spring_reference3,
};

#endif
