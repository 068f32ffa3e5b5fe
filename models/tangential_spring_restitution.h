/* tangential_spring's restitution law (gr_model.restitution_t), included by models/tangential_spring.h
 * inside GR_MODEL_IMPL: the tangential restitution of a binary impact of two equal discs without
 * spin, eps_t = g_c' / g_c of the contact point's tangential velocity, in continuous time with the
 * line of centres held fixed (the small-overlap picture of the other laws' restitution laws; the
 * CVODE reference of src/collide/reference.c integrates the full geometry independently).
 *
 * No closed form exists with a Coulomb limit that moves with F_n(t), so this integrates the
 * impact in the normal law's own units (x0 = (m12 v_n^2 / k)^(1/(a+1)), t0 = x0 / v_n, forces
 * k x0^a): X'' = -f, f = X^a + c_n X^p X' (the normal law's pow_a, pow_p), together with the
 * contact point's U = g_c / v_n, U' = (m12 / m_t) f_t, and the spring S = s / x0:
 *   sticking  S' = U, f_t = -(k S + c_t U), while |k S + c_t U| < mu |f|;
 *   slipping  f_t = -sig mu |f|, S the algebraic value k S + c_t U = sig mu |f| (the limit of the
 *             engine's rescale as dt -> 0), while the free rate of k S + c_t U (with S' = U)
 *             outruns the limit: phi = sig (k U + c_t U' + S dk/dt) - mu d|f|/dt > 0.
 * k = k_t + k_m sqrt(X) (Mindlin: k_t = 0). RK4 on a mesh graded towards X = 0 (as
 * models/hertz.h: X^p and sqrt(X) are not smooth there); every switch (stick -> slip, slip ->
 * stick, f changing sign in an unclamped law, the end of the contact) is located by bisection
 * inside its step, so the result is accurate to ~1e-10, not to the step. */
#ifndef GR_MODELS_TANGENTIAL_SPRING_RESTITUTION_H
#define GR_MODELS_TANGENTIAL_SPRING_RESTITUTION_H

#define SPRING_RT_STEP 2e-4    /* largest RK4 step, units t0 */
#define SPRING_RT_TMAX 1e4     /* give up (NaN) after this long (or 1.5 normal contacts) */
#define SPRING_RT_EVENTS 10000 /* and after this many switches */

typedef struct spring_rt {
    double a, p, cn; /* the normal law, scaled: f = X^a + cn X^p V */
    int clamp;
    double kt, km, ct, mu, rho; /* k = kt + km sqrt(X); dashpot; Coulomb; m12 / m_t */
    int slip;
    double sig, fsign; /* slipping direction; sign of f (|f| = fsign f) */
} spring_rt;

typedef struct spring_rt_val {
    double f, ft, S, trial, lim, rate, phi;
} spring_rt_val;

enum { RT_END, RT_FSIGN, RT_UP, RT_DOWN, RT_STICK, RT_N };

/* X^e; the linear law's exponents 0 and 1 without pow (the same numbers: pow is exact there) */
static inline double spring_rt_pow(const double X, const double e)
{
    return e == 0.0 ? 1.0 : e == 1.0 ? X : pow(X, e);
}

/* forces and switch values at y = (X, V, S, U); dy the derivatives if not NULL */
static spring_rt_val spring_rt_eval(const spring_rt *c, const double y[4], double dy[4])
{
    spring_rt_val o;
    /* max(X, 0) as fmax gives it (0 for NaN) but inline: this runs ~1e5 times per impact */
    const double X = y[0] > 0.0 ? y[0] : 0.0, V = y[1], U = y[3], sq = sqrt(X);
    const double Xp = spring_rt_pow(X, c->p);
    o.f = spring_rt_pow(X, c->a) + c->cn * Xp * V;
    /* X^(p-1) is singular at X = 0 (0 at or past the end, where the contact no longer acts) */
    const double xp1 = X > 0.0 && c->p != 0.0 ? c->p * spring_rt_pow(X, c->p - 1.0) : 0.0;
    const double df = c->a * spring_rt_pow(X, c->a - 1.0) * V + c->cn * (xp1 * V * V - Xp * o.f);
    const double kk = c->kt + c->km * sq, dk = sq > 0.0 ? 0.5 * c->km / sq * V : 0.0;
    o.lim = c->mu * c->fsign * o.f;
    if (c->slip) {
        o.ft = -c->sig * o.lim;
        o.S = kk > 0.0 ? (c->sig * o.lim - c->ct * U) / kk : 0.0;
    } else {
        o.S = y[2];
        o.ft = -(kk * o.S + c->ct * U);
    }
    o.trial = kk * o.S + c->ct * U;
    const double dU = c->rho * o.ft;
    o.rate = kk * U + c->ct * dU + o.S * dk;
    o.phi = c->sig * o.rate - c->mu * c->fsign * df;
    if (dy) {
        dy[0] = V;
        dy[1] = -o.f;
        dy[2] = c->slip ? 0.0 : U;
        dy[3] = dU;
    }
    return o;
}

static void spring_rt_switches(const spring_rt *c, const double y[4], double g[RT_N])
{
    const spring_rt_val v = spring_rt_eval(c, y, NULL);
    g[RT_END] = c->clamp ? v.f : y[0];
    g[RT_FSIGN] = c->clamp ? 1.0 : c->fsign * v.f;
    g[RT_UP] = c->slip ? 1.0 : v.lim - v.trial;
    g[RT_DOWN] = c->slip ? 1.0 : v.lim + v.trial;
    g[RT_STICK] = c->slip ? v.phi : 1.0;
}

static void spring_rt_rk4(const spring_rt *c, const double y[4], double h, double out[4])
{
    double k1[4], k2[4], k3[4], k4[4], t[4];
    spring_rt_eval(c, y, k1);
    for (int i = 0; i < 4; i++)
        t[i] = y[i] + 0.5 * h * k1[i];
    spring_rt_eval(c, t, k2);
    for (int i = 0; i < 4; i++)
        t[i] = y[i] + 0.5 * h * k2[i];
    spring_rt_eval(c, t, k3);
    for (int i = 0; i < 4; i++)
        t[i] = y[i] + h * k3[i];
    spring_rt_eval(c, t, k4);
    for (int i = 0; i < 4; i++)
        out[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

/* the regime where the limit is 0 (F_n changing sign): slipping along the free rate if it beats
 * the limit's growth, sticking otherwise */
static void spring_rt_turn(spring_rt *c, double y[4])
{
    if (c->slip) {
        y[2] = spring_rt_eval(c, y, NULL).S;
        c->slip = 0;
    }
    c->sig = spring_rt_eval(c, y, NULL).rate < 0.0 ? -1.0 : 1.0;
    c->slip = 1;
    c->slip = spring_rt_eval(c, y, NULL).phi > 0.0;
}

static double tangential_spring_restitution_t(const gr_contact_coeffs *c, gr_normal_impact n,
                                              double v_n, double v_t)
{
    if (!(v_t > 0.0) || !(v_n > 0.0) || c->mu == 0.0) {
        return 1.0;
    }
    if (!isfinite(n.t_c)) {
        return (double)NAN; /* the pair sticks: the contact never ends */
    }
    const double a = c->pow_a, k = c->k_s;
    const double x0 = pow(c->m12 * v_n * v_n / k, 1.0 / (a + 1.0)), F0 = k * pow(x0, a);
    /* the normal law's own contact, t_c / t0 in these units, with room to spare */
    const double t_end = fmin(SPRING_RT_TMAX, 1.5 * n.t_c * v_n / x0 + 1.0);
    spring_rt r = {
        .a = a,
        .p = c->pow_p,
        .cn = c->gamma_n * pow(x0, c->pow_p) * v_n / F0,
        .clamp = c->clamp,
        .kt = c->law_t[GR_SPRING_KT] * x0 / F0,
        .km = c->law_t[GR_SPRING_KM] * sqrt(x0) * x0 / F0,
        .ct = c->law_t[GR_SPRING_GAMMA] * v_n / F0,
        .mu = c->mu,
        .rho = c->m12 / c->m_t,
        .sig = 1.0,
        .fsign = 1.0,
    };
    const double U0 = v_t / v_n;
    double y[4] = {0.0, 1.0, 0.0, U0};
    {
        /* at the touch both |k S + c_t U| and mu |f| start from 0 or c_t U, cn as powers of the
         * time: their ratio just after it decides the first regime */
        const double e = 1e-8, f = pow(e, a) + r.cn * pow(e, r.p);
        const double trial = (r.kt + r.km * sqrt(e)) * U0 * e + r.ct * U0;
        r.slip = fabs(trial) > r.mu * fabs(f);
        r.sig = trial < 0.0 ? -1.0 : 1.0;
    }
    double t = 0.0, g0[RT_N];
    int events = 0, fresh = 0; /* fresh: g0 holds the switches at y (the last step's g1) */
    while (t < t_end && events < SPRING_RT_EVENTS) {
        /* the graded step, min(STEP, max(1e-10, 0.05 X / max(|V|, 1e-3))) as fmin and fmax give
         * it, inline */
        const double av = fabs(y[1]), q = 0.05 * y[0] / (av > 1e-3 ? av : 1e-3);
        const double hq = q > 1e-10 ? q : 1e-10, h = hq < SPRING_RT_STEP ? hq : SPRING_RT_STEP;
        double g1[RT_N], y1[4];
        if (!fresh) {
            spring_rt_switches(&r, y, g0);
        }
        spring_rt_rk4(&r, y, h, y1);
        spring_rt_switches(&r, y1, g1);
        int crossed = 0;
        for (int i = 0; i < RT_N; i++) {
            crossed |= g0[i] > 0.0 && g1[i] <= 0.0;
        }
        if (!crossed) {
            memcpy(y, y1, sizeof y);
            memcpy(g0, g1, sizeof g0);
            fresh = 1;
            t += h;
            continue;
        }
        fresh = 0; /* a switch changes the regime, and so the switch values at y */
        /* the first switch inside the step, by bisection on the step's length */
        double lo = 0.0, hi = 1.0;
        for (int it = 0; it < 60; it++) {
            const double mid = 0.5 * (lo + hi);
            double ym[4], gm[RT_N];
            spring_rt_rk4(&r, y, mid * h, ym);
            spring_rt_switches(&r, ym, gm);
            int any = 0;
            for (int i = 0; i < RT_N; i++) {
                any |= g0[i] > 0.0 && gm[i] <= 0.0;
            }
            if (any) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        spring_rt_rk4(&r, y, hi * h, y1);
        spring_rt_switches(&r, y1, g1);
        memcpy(y, y1, sizeof y);
        t += hi * h;
        events++;
        if (g0[RT_END] > 0.0 && g1[RT_END] <= 0.0) {
            return y[3] / U0;
        }
        if (g0[RT_STICK] > 0.0 && g1[RT_STICK] <= 0.0) {
            y[2] = spring_rt_eval(&r, y, NULL).S; /* sticks where the constraint left the spring */
            r.slip = 0;
        } else if ((g0[RT_UP] > 0.0 && g1[RT_UP] <= 0.0) ||
                   (g0[RT_DOWN] > 0.0 && g1[RT_DOWN] <= 0.0)) {
            r.sig = g1[RT_UP] <= 0.0 ? 1.0 : -1.0;
            r.slip = 1;
        }
        if (g0[RT_FSIGN] > 0.0 && g1[RT_FSIGN] <= 0.0) {
            r.fsign = -r.fsign;
            spring_rt_turn(&r, y);
        }
    }
    return (double)NAN; /* the pair sticks (or the regimes chatter): no restitution */
}

#endif
