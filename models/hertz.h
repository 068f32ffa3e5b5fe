/* hertz: the Hertzian normal contact force F_n = k_h xi^(3/2) plus a damping, in two modes:
 *  - viscoelastic = true (Brilliantov, Spahn, Hertzsch & Poeschel, Phys. Rev. E 53, 5382 (1996)):
 *      F_n = k_h xi^(3/2) + (3/2) A k_h sqrt(xi) xi',   xi' = -g_n,
 *    with the material's viscoelastic time A (visco_A). The restitution depends on the impact
 *    speed: scaling xi by x0 = (m12 v^2 / k_h)^(2/5) and t by t0 = x0 / v leaves
 *      X'' = -X^(3/2) - (3/2) beta sqrt(X) X',  X(0) = 0, X'(0) = 1,
 *    with the single parameter beta = A (k_h / m12)^(2/5) v^(1/5), so eps_n(v) = E(beta(v)):
 *    eps = 1 - C1 b + C2 b^2 - ..., b = 3 beta / 2, C1 = 1.15344, C2 = 0.79826 for weak damping
 *    (Schwager & Poeschel, PRE 57, 650 (1998); tests/test_collide.c checks it).
 *  - viscoelastic = false (Tsuji, Tanaka & Ishida, Powder Technol. 71, 239 (1992)):
 *      F_n = k_h xi^(3/2) + alpha sqrt(m12 k_h) xi^(1/4) xi',
 *    whose scaled equation X'' = -X^(3/2) - alpha X^(1/4) X' has no speed in it: the restitution is
 *    the same at every impact speed. alpha is found by an exact numerical inversion of E(alpha)
 *    = eps_n (bisection on the scaled contact, integrated below), not Tsuji's fitted curve.
 * clamp = true holds F_n >= 0: the contact then ends when the force vanishes (the restitution
 * inverted for is that of the clamped contact), otherwise when the overlap returns to zero (the
 * damping pulls at the end, as in the thesis's linear law).
 *
 * The contact duration t_c = T(beta) t0 falls as v^(-1/5) with the impact speed: the time step
 * resolves the fastest impact a scene declares, v_max (dt = t_c(v_max) / steps_per_contact, and a
 * dt giving fewer than 10 steps for that contact is refused); slower impacts get more steps.
 * docs/models.md tabulates eps(v) and t_c(v). */
#ifndef GR_MODELS_HERTZ_H
#define GR_MODELS_HERTZ_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_hertz;

/* its own parameters (gr_contact_params.own; hard_sphere's viscoelastic mode reads them too) */
typedef struct hertz_own {
    double k_h;        /* stiffness of F = k_h xi^(3/2), N/m^(3/2) */
    bool viscoelastic; /* damping of Brilliantov et al. (A), not calibrated to eps_n */
    double visco_A;    /* the viscoelastic time A, s */
    double v_max;      /* the fastest impact the time step must resolve, m/s */
} hertz_own;

/* The pair law: k_s = k_h, gamma_n the damping coefficient, law_n[0] = 1 for the xi^(1/4)
 * damping (Tsuji), 0 for sqrt(xi) (viscoelastic): f = k_h xi^(3/2) - gamma_n xi^p g_n. Elastic
 * energy (2/5) k_h xi^(5/2). */
GR_LAW gr_normal_force gr_normal_hertz(const gr_contact_coeffs *c, const double xi,
                                       const double g_n, const int clamp)
{
    const double s = sqrt(xi), k = c->k_s;
    const double spring = k * xi * s;
    const double xp = c->law_n[0] != 0.0 ? sqrt(s) : s;
    double f = spring - c->gamma_n * xp * g_n;
    if (clamp) {
        f = f > 0.0 ? f : 0.0;
    }
    return (gr_normal_force){.f = f, .f_d = f - spring, .e = xi * xi * s};
}

#endif /* GR_MODELS_HERTZ_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_HERTZ_IMPL)
#define GR_MODELS_HERTZ_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

#define HERTZ_STEP 2e-4  /* largest RK4 step of the scaled contact (elastic duration 3.2187) */
#define HERTZ_STICK 20.0 /* a scaled contact longer than this (6 elastic ones) counts as sticking */

/* The scaled contact X'' = -F, F = X^(3/2) + c X^p X' (p = 1/4 if quarter, else 1/2), from
 * X = 0, X' = 1 until X returns to 0 (or F to 0 with the clamp), by RK4. X^p is not smooth at
 * X = 0, so near both ends the step shrinks to 5% of the time X needs to reach 0 (a graded
 * mesh, down to 1e-10): the result then agrees with the CVODE reference to ~1e-9. Returns the impact:
 * eps = -X' at the end, t_c = the scaled duration, impulse_abs = int |F| dtau. */
static double hertz_force(double X, double V, double c, int quarter)
{
    const double s = sqrt(X > 0.0 ? X : 0.0); /* fmax(X, 0), inline */
    return X * s + c * (quarter ? sqrt(s) : s) * V;
}

static gr_normal_impact hertz_scaled_impact(double c, int quarter, int clamp)
{
    double X = 0.0, V = 1.0, tau = 0.0, jabs = 0.0, past_max = 0;
    for (;;) {
        /* min(STEP, max(1e-10, 0.05 X / max(|V|, 1e-3))) as fmin and fmax give it, inline */
        const double av = fabs(V), q = 0.05 * X / (av > 1e-3 ? av : 1e-3);
        const double hq = q > 1e-10 ? q : 1e-10, h = hq < HERTZ_STEP ? hq : HERTZ_STEP;
        const double k1x = V, k1v = -hertz_force(X, V, c, quarter);
        const double k2x = V + 0.5 * h * k1v,
                     k2v = -hertz_force(X + 0.5 * h * k1x, V + 0.5 * h * k1v, c, quarter);
        const double k3x = V + 0.5 * h * k2v,
                     k3v = -hertz_force(X + 0.5 * h * k2x, V + 0.5 * h * k2v, c, quarter);
        const double k4x = V + h * k3v, k4v = -hertz_force(X + h * k3x, V + h * k3v, c, quarter);
        const double X1 = X + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        const double V1 = V + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        past_max = past_max || V1 < 0.0;
        /* the end: X back to 0, or (clamped) the force down to 0 after the maximum overlap;
         * interpolate linearly inside the step (X'' vanishes there, so V is accurate) */
        const double g0 = clamp ? hertz_force(X, V, c, quarter) : X,
                     g1 = clamp ? hertz_force(X1, V1, c, quarter) : X1;
        if (past_max && g1 <= 0.0 && tau > 0.0) {
            const double w = g0 > g1 ? g0 / (g0 - g1) : 1.0;
            const double Ve = V + w * (V1 - V);
            jabs += fabs(V - Ve);
            return (gr_normal_impact){.eps_n = -Ve, .t_c = tau + w * h, .impulse_abs = jabs};
        }
        if (past_max && !clamp && fabs(V1) < 1e-9 && X1 > 0.0) {
            /* overdamped tail: the overlap creeps towards 0 and the pair sticks */
            return (gr_normal_impact){
                .eps_n = 0.0, .t_c = INFINITY, .impulse_abs = jabs + fabs(V1 - V)};
        }
        jabs += fabs(V1 - V); /* int |F| = total variation of X' (F changes sign at most once) */
        X = X1;
        V = V1;
        tau += h;
        if (tau > HERTZ_STICK) {
            return (gr_normal_impact){.eps_n = 0.0, .t_c = INFINITY, .impulse_abs = jabs};
        }
    }
}

/* x0 = (m12 v^2 / k_h)^(2/5), the scaled contact's length unit */
static double hertz_x0(const gr_contact_coeffs *c, double v)
{
    return pow(c->m12 * v * v / c->k_s, 0.4);
}

/* The damping parameter of the scaled equation at impact speed v: c = (3/2) beta (viscoelastic)
 * or alpha (Tsuji, the same at every v). */
static double hertz_scaled_damping(const gr_contact_coeffs *c, double v)
{
    if (c->law_n[0] != 0.0) {
        return c->gamma_n / sqrt(c->m12 * c->k_s);
    }
    const double t0 = hertz_x0(c, v) / v;
    return c->gamma_n / c->k_s / t0; /* (3/2) A / t0 */
}

/* hertz_scaled_impact, remembered per thread for the last HERTZ_MEMO arguments: one integration
 * takes 16000 to 100000 RK4 steps (a sticking contact), and every prepare of the same law (each
 * simulation, collision or sweep point) asks for the same v_max impact again. Same bits. */
#define HERTZ_MEMO 8
static gr_normal_impact hertz_scaled_impact_memo(double c, int quarter, int clamp)
{
    static _Thread_local struct {
        double c;
        int quarter, clamp;
        gr_normal_impact o;
    } memo[HERTZ_MEMO];
    static _Thread_local int filled, next;
    for (int i = 0; i < filled; i++) {
        if (memo[i].c == c && memo[i].quarter == quarter && memo[i].clamp == clamp) {
            return memo[i].o;
        }
    }
    const gr_normal_impact o = hertz_scaled_impact(c, quarter, clamp);
    memo[next].c = c;
    memo[next].quarter = quarter;
    memo[next].clamp = clamp;
    memo[next].o = o;
    next = (next + 1) % HERTZ_MEMO;
    filled += filled < HERTZ_MEMO;
    return o;
}

/* Its impact at normal speed v_n: the scaled contact in units x0, t0 = x0 / v_n, speed v_n. */
static gr_normal_impact hertz_impact(const gr_contact_coeffs *c, double v_n)
{
    gr_normal_impact o =
        hertz_scaled_impact_memo(hertz_scaled_damping(c, v_n), c->law_n[0] != 0.0, c->clamp);
    o.t_c *= hertz_x0(c, v_n) / v_n;
    return o;
}

/* alpha with E(alpha) = eps (Tsuji mode), by bisection: E falls monotonically from 1 at alpha = 0.
 * A bisection integrates ~60 contacts (sticking ones, near eps = 0, up to 1e5 RK4 steps each), so
 * the last HERTZ_ALPHA_CACHE (eps, clamp) are cached per thread: a comparison of models, a sweep
 * over eps or a test of hard cases asks for a few values over and over. */
#define HERTZ_ALPHA_CACHE 16
static double hertz_alpha_of(double eps, int clamp, gr_error *err, int *rc)
{
    static _Thread_local struct {
        double eps, alpha;
        int clamp;
    } cache[HERTZ_ALPHA_CACHE];
    static _Thread_local int cached, next;
    *rc = GR_OK;
    if (eps >= 1.0) {
        return 0.0;
    }
    for (int i = 0; i < cached; i++) {
        if (cache[i].eps == eps && cache[i].clamp == clamp) {
            return cache[i].alpha;
        }
    }
    double lo = 0.0, hi = 1.0;
    while (hertz_scaled_impact(hi, 1, clamp).eps_n > eps) {
        lo = hi;
        hi *= 2.0;
        if (hi > 1e4) {
            *rc = GR_FAIL(
                err, GR_EINVAL,
                "[model] eps_n = %g: hertz%s cannot reach it (alpha > 1e4); allowed range: "
                "eps_n >= %.3g",
                eps, clamp ? " with clamp = true" : "", hertz_scaled_impact(1e4, 1, clamp).eps_n);
            return 0.0;
        }
    }
    for (int it = 0; it < 50 && hi - lo > 1e-13 * hi; it++) {
        const double mid = 0.5 * (lo + hi);
        if (hertz_scaled_impact(mid, 1, clamp).eps_n > eps) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double alpha = 0.5 * (lo + hi);
    cache[next].eps = eps;
    cache[next].clamp = clamp;
    cache[next].alpha = alpha;
    next = (next + 1) % HERTZ_ALPHA_CACHE;
    cached += cached < HERTZ_ALPHA_CACHE;
    return alpha;
}

static const gr_param hertz_params[] = {
    {"k_h", "N/m^1.5", GR_PARAM_DOUBLE, 1e9, 0.0, INFINITY, true, true,
     "hertz: stiffness of F_n = k_h xi^(3/2); 1e9 gives the RFM discs about the linear law's "
     "overlap at 0.1 m/s",
     GR_OWN_KEY(hertz, k_h)},
    {"eps_n", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "normal coefficient of restitution (2.2); 1 = elastic, 0 = sticking (unclamped only)",
     offsetof(gr_contact_params, eps_n)},
    {"clamp", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "true: normal force never attractive, the contact ends when it vanishes (damping calibrated "
     "to that "
     "contact); false: it ends when the overlap does",
     offsetof(gr_contact_params, clamp)},
    {"viscoelastic", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "hertz: true = damping (3/2) A k_h sqrt(xi) xi' of Brilliantov et al. 1996, eps_n depends on "
     "the impact "
     "speed (eps_n ignored); false = damping ~ xi^(1/4) xi' calibrated to a constant eps_n (Tsuji "
     "1992, exact inversion)",
     GR_OWN_KEY(hertz, viscoelastic)},
    {"visco_A", "s", GR_PARAM_DOUBLE, 1e-6, 0.0, INFINITY, false, true,
     "hertz, viscoelastic = true: the viscoelastic time A; 0 = elastic",
     GR_OWN_KEY(hertz, visco_A)},
    {"v_max", "m/s", GR_PARAM_DOUBLE, 1.0, 0.0, INFINITY, true, true,
     "hertz: the fastest impact (normal relative speed) the time step must resolve; dt = "
     "t_c(v_max) / steps_per_contact",
     GR_OWN_KEY(hertz, v_max)},
};

static int hertz_prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                         gr_error *err)
{
    const hertz_own *o = GR_OWN(p, hertz);
    (void)dt;
    c->k_s = o->k_h;
    c->m12 = m12;
    c->clamp = p->clamp;
    c->pow_a = 1.5;
    if (o->viscoelastic) {
        c->law_n[0] = 0.0;
        c->pow_p = 0.5;
        c->gamma_n = 1.5 * o->visco_A * o->k_h;
    } else {
        if (p->clamp && !(p->eps_n > 0.0)) {
            return GR_FAIL(
                err, GR_EINVAL,
                "[model] eps_n = 0 cannot be reached with clamp = true (it needs an infinite "
                "damping); allowed range with clamping: (0, 1]");
        }
        int rc = GR_OK;
        const double alpha = hertz_alpha_of(p->eps_n, p->clamp, err, &rc);
        if (rc != GR_OK) {
            return rc;
        }
        c->law_n[0] = 1.0;
        c->pow_p = 0.25;
        c->gamma_n = alpha * sqrt(m12 * o->k_h);
    }
    const gr_normal_impact at_max = hertz_impact(c, o->v_max);
    c->t_c = at_max.t_c;
    c->eps_n_exact = at_max.eps_n;
    /* The contact linearised at the scaled overlap X = 1 of the v_max impact: stiffness
     * (3/2) X^(1/2) and damping c X^p in scaled units, i.e. w0 = sqrt(3/2) / t0 and a damping
     * ratio c / (2 sqrt(3/2)). The time step's explicit-damping checks (2 zeta w0 dt < 1, and
     * the half-step lag near critical damping) use them, so an overdamped contact gets a
     * smaller step or is refused instead of gaining energy. */
    const double t0 = hertz_x0(c, o->v_max) / o->v_max;
    c->w0 = sqrt(1.5) / t0;
    c->zeta = hertz_scaled_damping(c, o->v_max) / (2.0 * sqrt(1.5));
    c->e_scale = 0.4 * o->k_h; /* U = (2/5) k_h xi^(5/2) */
    return GR_OK;
}

static const char *const hertz_variants[] = {"viscoelastic=false", "viscoelastic=true", NULL};
/* beta ~ 300 (the pair sticks), and Tsuji damping for eps_n = 1e-3 */
static const char *const hertz_extremes[] = {"viscoelastic=true visco_A=1e-3",
                                             "viscoelastic=false eps_n=0.001", NULL};

const gr_model gr_model_hertz = {
    .name = "hertz",
    .summary = "Hertzian normal force k_h xi^(3/2), viscoelastic (eps(v), Brilliantov 1996) or "
               "calibrated to a "
               "constant eps_n (Tsuji 1992, exact inversion)",
    .kind = GR_MODEL_NORMAL,
    .params = hertz_params,
    .n_params = sizeof hertz_params / sizeof hertz_params[0],
    .prepare = hertz_prepare,
    .impact = hertz_impact,
    .elastic = "eps_n=1 visco_A=0",
    .variants = hertz_variants,
    .extremes = hertz_extremes,
};
#endif /* GR_MODEL_IMPL */
