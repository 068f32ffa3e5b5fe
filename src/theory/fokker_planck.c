/* A randomly accelerated particle in a 1D absorbing interval (thesis App. B): the stationary
 * Fokker-Planck solution (B.32) and Q(v, L) (B.33-B.34) by adaptive quadrature, and a simulation
 * of the same walkers to compare with.
 *
 * Everything is computed in reduced units x' = x / L, v' = v / V, t' = t / T0 with
 * V = (Gamma L)^(1/3), T0 = L / V, Gamma = D / M^2, in which (B.1) reads
 *     v dP/dx - d^2P/dv^2 = delta(v)      (unit injection rate over the unit interval).
 *
 * The solution used here (derivation in docs/theory-fokker-planck.md), for v >= 0:
 *     P(x, v) = (c/2) [ E(x, v) - kappa int_0^x K(x - y, v) B(y) dy ],
 *     K(u, v) = u^(-2/3) exp(-v^3 / (9u)),   E(w, v) = int_0^w K(u, v) du = w^(1/3) E_{4/3}(v^3/(9w)),
 *     c = 3^(-1/3) / Gamma(2/3),  kappa = pi / (sqrt(3) Gamma(1/3) Gamma(5/6)^2),
 *     B(y) = [y(1-y)]^(-1/6) [2F1(-1/3,1;5/6;1-y) - 2F1(-1/3,1;5/6;y)]        (B.31),
 * and P(x, -v) = P(1 - x, v) (Property II). This is (B.32) with its prefactor R / Gamma(2/3)
 * replaced by 3^(-1/3) R / (2 Gamma(2/3)); the thesis's C = Gamma(1/6)/(2 sqrt3 Gamma(1/3) Gamma(5/6))
 * equals kappa, so the shape of (B.32) is right. Integrating over x (B.33-B.34):
 *     Q(v) = (c/2) int_0^1 [1 - kappa B(y)] E(1 - y, |v|) dy.
 * The velocity integrals of E are closed forms (int_0^inf v^m E(w, v) dv =
 * w^((m+2)/3) 9^((m+1)/3) Gamma((m+1)/3) / (m + 2)), so the normalisation (the mean exit time) and
 * the moments need one quadrature over y each. */
#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_gamma.h>
#include <gsl/gsl_sf_hyperg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "granule/fokker_planck.h"

#define THIRD (1.0 / 3.0)

void gr_fp_settings_default(gr_fp_settings *s)
{
    memset(s, 0, sizeof *s);
    s->L = 1.0;
    s->D = 1.0;
    s->M = 1.0;
    s->epsrel = 1e-9;
    s->limit = 1000;
    s->inner_quadrature = false;
    s->walkers = 200000;
    s->seed = 1;
    s->steps_per_T0 = 200.0;
    s->max_T0 = 200.0;
    s->refine = 8;
    s->start = GR_FP_START_UNIFORM;
    s->bins = 100;
    s->exit_bins = 50;
    s->vmax_V = 5.0;
}

static bool positive(double x) { return isfinite(x) && x > 0.0; }

int gr_fp_settings_check(const gr_fp_settings *s, gr_error *err)
{
    if (!positive(s->L)) {
        return GR_FAIL(err, GR_EINVAL, "length L must be a finite number > 0 (m), got %g", s->L);
    }
    if (!positive(s->D)) {
        return GR_FAIL(err, GR_EINVAL,
                       "noise strength D must be a finite number > 0 (N^2 s), got %g", s->D);
    }
    if (!positive(s->M)) {
        return GR_FAIL(err, GR_EINVAL, "mass M must be a finite number > 0 (kg), got %g", s->M);
    }
    double V = cbrt(s->D * s->L / (s->M * s->M));
    if (!positive(V) || !positive(s->L / V)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the scales V = (D L / M^2)^(1/3) = %g m/s and T0 = L / V are not finite and positive",
            V);
    }
    if (!(s->epsrel >= 1e-13 && s->epsrel <= 1e-2)) {
        return GR_FAIL(err, GR_EINVAL,
                       "quadrature tolerance epsrel must lie in [1e-13, 1e-2], got %g", s->epsrel);
    }
    if (s->limit < 50 || s->limit > 100000) {
        return GR_FAIL(err, GR_EINVAL,
                       "quadrature workspace limit must lie in [50, 100000], got %zu", s->limit);
    }
    if (s->walkers < 1 || s->walkers > (int64_t)1e12) {
        return GR_FAIL(err, GR_EINVAL, "walkers must lie in [1, 1e12], got %lld",
                       (long long)s->walkers);
    }
    if (!(s->steps_per_T0 >= 10.0 && s->steps_per_T0 <= 1e7)) {
        return GR_FAIL(err, GR_EINVAL, "steps per T0 must lie in [10, 1e7], got %g",
                       s->steps_per_T0);
    }
    if (!(s->max_T0 >= 1.0 && s->max_T0 <= 1e6)) {
        return GR_FAIL(err, GR_EINVAL,
                       "max_T0 (walk cut-off in units of T0) must lie in [1, 1e6], got %g",
                       s->max_T0);
    }
    if (s->refine < 0 || s->refine > 30) {
        return GR_FAIL(err, GR_EINVAL,
                       "refine (bridge bisection levels) must lie in [0, 30], got %d", s->refine);
    }
    if (s->start != GR_FP_START_UNIFORM && s->start != GR_FP_START_CENTRE) {
        return GR_FAIL(err, GR_EINVAL, "start must be uniform or centre");
    }
    if (s->bins < 2 || s->bins > 2000 || s->bins % 2) {
        return GR_FAIL(err, GR_EINVAL,
                       "bins must be an even number in [2, 2000] (an edge at v = 0), got %d",
                       s->bins);
    }
    if (s->exit_bins < 1 || s->exit_bins > 2000) {
        return GR_FAIL(err, GR_EINVAL, "exit bins must lie in [1, 2000], got %d", s->exit_bins);
    }
    if (!(s->vmax_V > 0.0 && s->vmax_V <= 50.0)) {
        return GR_FAIL(err, GR_EINVAL, "vmax must lie in (0, 50] (units of V), got %g", s->vmax_V);
    }
    return GR_OK;
}

double gr_fp_velocity_scale(const gr_fp_settings *s) { return cbrt(s->D * s->L / (s->M * s->M)); }
double gr_fp_time_scale(const gr_fp_settings *s) { return s->L / gr_fp_velocity_scale(s); }

/* ------------------------------------------------------------------------------------------
 * Constants */

/* kappa = pi / (sqrt3 Gamma(1/3) Gamma(5/6)^2): the solution of int_0^1 |x-y|^(-2/3) r(y) dy = 3 x^(1/3)
 * is r = kappa [x(1-x)]^(-1/6) 2F1(-1/3,1;5/6;1-x) (B.29, checked to 1e-10 in the tests). */
double gr_fp_kappa(void)
{
    return M_PI / (M_SQRT3 * tgamma(THIRD) * tgamma(5.0 / 6.0) * tgamma(5.0 / 6.0));
}

/* the thesis's constant of (B.32), Gamma(1/6) / (2 sqrt3 Gamma(1/3) Gamma(5/6)); equal to kappa */
static double thesis_C(void)
{
    return tgamma(1.0 / 6.0) / (2.0 * M_SQRT3 * tgamma(THIRD) * tgamma(5.0 / 6.0));
}

/* c = -1 / Ai'(0) * (2 3^(1/6) pi)^(-1) = 3^(-1/3) / Gamma(2/3): the weight of the Neumann kernel */
static double c_kernel(void) { return cbrt(1.0 / 3.0) / tgamma(2.0 * THIRD); }

double gr_fp_thesis_prefactor_ratio(void)
{
    return (1.0 / tgamma(2.0 * THIRD)) / (0.5 * c_kernel());
}

/* ------------------------------------------------------------------------------------------
 * The hypergeometric bracket of (B.31) */

/* Gauss series of 2F1(-1/3, 1; 5/6; z) for 0 <= z <= 1/2: with b = 1 the term ratio is
 * (k - 1/3) z / (k + 5/6); all terms after the first are negative, so there is no cancellation. */
static double hyp_series(double z)
{
    double t = 1.0, sum = 1.0;
    for (int k = 0; k < 200; k++) {
        t *= (k - THIRD) / (k + 5.0 / 6.0) * z;
        sum += t;
        if (fabs(t) < 1e-17 * fabs(sum)) {
            break;
        }
    }
    return sum;
}

static double a2_const(void);

/* gsl_sf_hyperg_2F1_e(-1/3, 1; 5/6; z), 0 <= z < 1, with its status checked. Two defects of
 * GSL 2.7.1 for these parameters are guarded against:
 *  - its error estimate is useless (err ~ 1 for values ~ 1 whose true error is ~1e-16; see the
 *    GSL bug reports on hyperg_2F1, e.g. savannah #54998), so the value is checked instead
 *    against the Gauss series (z <= 1/2) or the connection formula (z > 1/2), and a disagreement
 *    above 1e-12 is an error;
 *  - for 1 - z < ~1e-13 it returns Gauss's value 2F1(1) = -1 and drops the (1-z)^(1/6) term of
 *    the connection formula (measured: 1 - z = 1e-13 gives -1.0 for the true -0.98718), so there
 *    the connection formula is used. */
static int hyp(double z, double *out, gr_error *err)
{
    double check;
    if (z <= 0.5) {
        check = hyp_series(z);
    } else {
        double y =
            1.0 - z; /* exact for z in [1/2, 1]: 2F1(..; 1 - y) = -2F1(..; y) + a2 [y(1-y)]^(1/6) */
        check = -hyp_series(y) + a2_const() * pow(y * (1.0 - y), 1.0 / 6.0);
        if (y < 1e-12) {
            *out = check;
            return GR_OK;
        }
    }
    gsl_sf_result r;
    int st = gsl_sf_hyperg_2F1_e(-THIRD, 1.0, 5.0 / 6.0, z, &r);
    if (st != GSL_SUCCESS || !isfinite(r.val)) {
        return GR_FAIL(err, GR_EUNSTABLE, "gsl_sf_hyperg_2F1(-1/3, 1; 5/6; %.17g) failed: %s", z,
                       gsl_strerror(st));
    }
    if (!(fabs(r.val - check) <= 1e-12 * fmax(1.0, fabs(check)))) {
        return GR_FAIL(
            err, GR_EUNSTABLE,
            "gsl_sf_hyperg_2F1(-1/3, 1; 5/6; %.17g) = %.17g disagrees with the series value %.17g",
            z, r.val, check);
    }
    *out = r.val;
    return GR_OK;
}

/* a2 of the connection formula 2F1(a,b;c;1-y) = A1 2F1(a,b;a+b-c+1;y) + a2 y^(c-a-b) 2F1(c-a,c-b;c-a-b+1;y)
 * (Abramowitz & Stegun 15.3.6) with (a,b,c) = (-1/3,1,5/6): A1 = Gamma(5/6)Gamma(1/6)/(Gamma(7/6)Gamma(-1/6)) = -1,
 * a2 = Gamma(5/6)Gamma(-1/6)/Gamma(-1/3), and 2F1(7/6,-1/6;7/6;y) = (1-y)^(1/6). Hence
 * 2F1(-1/3,1;5/6;1-y) = -2F1(-1/3,1;5/6;y) + a2 [y(1-y)]^(1/6) and B(y) = a2 - 2 [y(1-y)]^(-1/6) 2F1(..;y). */
static double a2_const(void) { return tgamma(5.0 / 6.0) * tgamma(-1.0 / 6.0) / tgamma(-THIRD); }

/* B(u) with u and 1 - u given separately, so that u -> 1 keeps its precision (omu = 1 - u) */
static int bracket2(double u, double omu, bool literal, double *B, gr_error *err)
{
    if (!(u > 0.0 && omu > 0.0 && u <= 1.0 && omu <= 1.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "bracket B(u) of (B.31) needs 0 < u < 1, got u = %g (1 - u = %g)", u, omu);
    }
    const double w = pow(u * omu, -1.0 / 6.0);
    double F1 = 0.0, F2 = 0.0;
    int rc;
    if (literal) { /* as printed: [u(1-u)]^(-1/6) [2F1(..; 1 - u) - 2F1(..; u)] */
        rc = hyp(omu, &F1, err);
        if (!rc) {
            rc = hyp(u, &F2, err);
        }
        if (!rc) {
            *B = w * (F1 - F2);
        }
        return rc;
    }
    /* B(u) = a2 - 2 [u(1-u)]^(-1/6) 2F1(..; u) for u <= 1/2, and B(1 - u) = -B(u) */
    rc = hyp(u <= 0.5 ? u : omu, &F1, err);
    if (!rc) {
        *B = (u <= 0.5 ? 1.0 : -1.0) * (a2_const() - 2.0 * w * F1);
    }
    return rc;
}

int gr_fp_bracket(double u, double *B, gr_error *err)
{
    return bracket2(u, 1.0 - u, false, B, err);
}

int gr_fp_bracket_literal(double u, double *B, gr_error *err)
{
    return bracket2(u, 1.0 - u, true, B, err);
}

/* ------------------------------------------------------------------------------------------
 * Quadrature state */

struct gr_fp_quad {
    gr_fp_settings s;
    double V, T0, Gamma;
    double c, kappa, C_thesis, a2;
    double N;   /* int Q dv in reduced units = mean exit time / T0 (uniform start) */
    double J23; /* J(2/3) = int_0^1 [1 - kappa B(y)] (1-y)^(2/3) dy */
    gsl_integration_workspace *wv, *wy, *ws; /* v (bin means), y (B.32/B.34), s (inner z of B.34) */
    gr_error ferr;                           /* first failure inside an integrand */
    int failed;
};

typedef struct fp_args {
    gr_fp_quad *q;
    double x, v, p;
    bool thesis; /* literal bracket and thesis constant */
} fp_args;

static double bracket_in(gr_fp_quad *q, double y, double omy, bool literal)
{
    double B;
    if (q->failed) {
        return NAN;
    }
    int rc = bracket2(y, omy, literal, &B, &q->ferr);
    if (rc) {
        q->failed = rc;
        return NAN;
    }
    return B;
}

/* Run one GSL integration and translate its status. A result that missed the requested tolerance
 * but whose error estimate is still below 1e-6 relative is accepted (GSL then reports
 * GSL_EROUND near singular endpoints); anything else is an error naming the integral. */
static int integ_status(gr_fp_quad *q, int st, double result, double abserr, const char *what,
                        gr_error *err)
{
    if (q->failed) {
        int code = q->failed;
        q->failed = 0;
        if (err) {
            *err = q->ferr;
        }
        return code;
    }
    if (!isfinite(result)) {
        return GR_FAIL(err, GR_EUNSTABLE, "%s: non-finite result (%s)", what, gsl_strerror(st));
    }
    if (st != GSL_SUCCESS && !(abserr <= 1e-6 * fabs(result) + 1e-300)) {
        return GR_FAIL(err, GR_EUNSTABLE, "%s: %s (result %g, error estimate %g)", what,
                       gsl_strerror(st), result, abserr);
    }
    return GR_OK;
}

/* E_{4/3}(b) = int_1^inf t^(-4/3) exp(-b t) dt = b^(1/3) Gamma(-1/3, b), E_{4/3}(0) = 3.
 * For b < 1 GSL's gsl_sf_gamma_inc(-1/3, b) is wrong while claiming 1e-14 accuracy (measured with
 * GSL 2.7.1: b = 1e-6 gives 2.95401 for the true 2.95938, b = 1e-12 gives 2.204 for 2.9996), so
 * there the recurrence Gamma(a, b) = (Gamma(a+1, b) - b^a e^-b) / a is used:
 * E_{4/3}(b) = 3 [exp(-b) - b^(1/3) Gamma(2/3, b)] (no cancellation for b < 1). For b >= 1 the
 * direct value is accurate (the recurrence would cancel as 1/(3b)). */
static double E43(gr_fp_quad *q, double b)
{
    if (b == 0.0) {
        return 3.0;
    }
    if (b > 700.0) {
        return 0.0; /* E_{4/3}(b) < exp(-b)/b underflows */
    }
    gsl_sf_result r;
    const double a = b < 1.0 ? 2.0 * THIRD : -THIRD;
    int st = gsl_sf_gamma_inc_e(a, b, &r);
    if (st == GSL_EUNDRFLW) {
        return 0.0;
    }
    if (st != GSL_SUCCESS || !isfinite(r.val)) {
        if (!q->failed) {
            q->failed = GR_FAIL(&q->ferr, GR_EUNSTABLE, "gsl_sf_gamma_inc(%g, %g) failed: %s", a, b,
                                gsl_strerror(st));
        }
        return NAN;
    }
    return b < 1.0 ? 3.0 * (exp(-b) - cbrt(b) * r.val) : cbrt(b) * r.val;
}

static double inner_s(double s, void *p)
{
    const fp_args *a = p;
    if (s <= 0.0) {
        return a->v > 0.0 ? 0.0 : 3.0;
    }
    return 3.0 * exp(-a->v * a->v * a->v / (9.0 * s * s * s));
}

/* E(w, v) = int_0^w u^(-2/3) exp(-v^3/(9u)) du: closed form, or QAG after u = s^3 */
static double Ew(gr_fp_quad *q, double w, double v)
{
    if (w <= 0.0) {
        return 0.0;
    }
    if (!q->s.inner_quadrature || v == 0.0) {
        return cbrt(w) * E43(q, v * v * v / (9.0 * w));
    }
    if (q->failed) {
        return NAN;
    }
    fp_args a = {.q = q, .v = v};
    gsl_function f = {inner_s, &a};
    double r, e, r2 = 0.0, e2 = 0.0;
    const double top = cbrt(w), sc = fmin(v / cbrt(9.0), top); /* the switch-on of the integrand */
    int st = gsl_integration_qag(&f, 0.0, sc, 0.0, q->s.epsrel, q->s.limit, GSL_INTEG_GAUSS21,
                                 q->ws, &r, &e);
    if (st == GSL_SUCCESS && sc < top) {
        st = gsl_integration_qag(&f, sc, top, 0.0, q->s.epsrel, q->s.limit, GSL_INTEG_GAUSS21,
                                 q->ws, &r2, &e2);
    }
    r += r2;
    e += e2;
    if (st != GSL_SUCCESS && !(e <= 1e-6 * fabs(r) + 1e-300)) {
        q->failed =
            GR_FAIL(&q->ferr, GR_EUNSTABLE, "inner integral of (B.34) at w = %g, v = %g: %s", w, v,
                    gsl_strerror(st));
        return NAN;
    }
    return r;
}

/* integrand of the convolution in (B.32) after y = x - s^3: 3 exp(-v^3/(9 s^3)) B(x - s^3) */
static double conv_s(double s, void *p)
{
    const fp_args *a = p;
    const double s3 = s * s * s;
    const double y = a->x - s3, omy = (1.0 - a->x) + s3; /* 1 - y without cancellation at x = 1 */
    if (s <= 0.0 || !(y > 0.0) || !(omy > 0.0)) {
        return 0.0;
    }
    double e = a->v > 0.0 ? exp(-a->v * a->v * a->v / (9.0 * s * s * s)) : 1.0;
    if (e == 0.0) {
        return 0.0;
    }
    return 3.0 * e * bracket_in(a->q, y, omy, a->thesis);
}

/* reduced P(x, v) for v >= 0, 0 <= x <= 1 */
static int P_red(gr_fp_quad *q, double x, double v, bool thesis, double *P, double *abserr,
                 gr_error *err)
{
    if (v < 0.0) {
        x = 1.0 - x;
        v = -v;
    }
    if (x <= 0.0) {
        *P = 0.0; /* absorbing: nothing enters at x = 0 with v > 0 */
        if (abserr) {
            *abserr = 0.0;
        }
        return GR_OK;
    }
    fp_args a = {.q = q, .x = x, .v = v, .thesis = thesis};
    gsl_function f = {conv_s, &a};
    double I, e;
    q->failed = 0;
    /* exp(-v^3/(9 s^3)) switches on at s_c = v / 9^(1/3); for small v that is a narrow feature next
     * to the s^(-1/2) singularity of B(1 - s^3) at s = 0 (x = 1), which QAGS alone steps over
     * (measured: P(L, 1e-6 V) came out -5e-7 instead of +1.3e-3). So it is a breakpoint (QAGP). */
    const double top = cbrt(x), sc = v / cbrt(9.0);
    int st;
    if (sc > 0.0 && sc < 0.5 * top) {
        double pts[4] = {0.0, sc, 2.0 * sc, top};
        int np = 2.0 * sc < top ? 4 : 3;
        if (np == 3) {
            pts[2] = top;
        }
        st = gsl_integration_qagp(&f, pts, (size_t)np, 0.0, q->s.epsrel, q->s.limit, q->wy, &I, &e);
    } else {
        st = gsl_integration_qags(&f, 0.0, top, 0.0, q->s.epsrel, q->s.limit, q->wy, &I, &e);
    }
    int rc = integ_status(q, st, I, e, "convolution integral of (B.32)", err);
    if (rc) {
        return rc;
    }
    double E = Ew(q, x, v);
    if (q->failed) {
        return integ_status(q, GSL_SUCCESS, E, 0.0, "(B.32)", err);
    }
    double pre = thesis ? 1.0 / tgamma(2.0 * THIRD) : 0.5 * q->c;
    double k = thesis ? q->C_thesis : q->kappa;
    *P = pre * (E - k * I);
    if (abserr) {
        *abserr = pre * k * e;
    }
    return GR_OK;
}

/* integrand of (B.34): [1 - kappa B(y)] E(1 - y, v) */
static double q_y(double y, void *p)
{
    const fp_args *a = p;
    if (!(y > 0.0 && y < 1.0)) {
        return 0.0;
    }
    double E = Ew(a->q, 1.0 - y, a->v);
    if (E == 0.0) {
        return 0.0;
    }
    double k = a->thesis ? a->q->C_thesis : a->q->kappa;
    return (1.0 - k * bracket_in(a->q, y, 1.0 - y, a->thesis)) * E;
}

static int Q_red(gr_fp_quad *q, double v, bool thesis, double *Q, double *abserr, gr_error *err)
{
    fp_args a = {.q = q, .v = fabs(v), .thesis = thesis};
    gsl_function f = {q_y, &a};
    double r, e;
    q->failed = 0;
    int st = gsl_integration_qags(&f, 0.0, 1.0, 0.0, q->s.epsrel, q->s.limit, q->wy, &r, &e);
    int rc = integ_status(q, st, r, e, "outer integral of (B.34)", err);
    if (rc) {
        return rc;
    }
    double pre = thesis ? 1.0 / tgamma(2.0 * THIRD) : 0.5 * q->c;
    *Q = pre * r;
    if (abserr) {
        *abserr = pre * e;
    }
    return GR_OK;
}

/* int_0^1 w(y) (1 - y)^p dy with w = 1 - kappa B (with_one) or w = B */
static double pow_y(double y, void *p)
{
    const fp_args *a = p;
    if (!(y > 0.0 && y < 1.0)) {
        return 0.0;
    }
    double B = bracket_in(a->q, y, 1.0 - y, false);
    return (a->thesis ? 1.0 - a->q->kappa * B : B) * pow(1.0 - y, a->p);
}

static int y_moment(gr_fp_quad *q, double p, bool with_one, double *out, gr_error *err)
{
    fp_args a = {.q = q, .p = p, .thesis = with_one};
    gsl_function f = {pow_y, &a};
    double r, e;
    q->failed = 0;
    /* the integrand is O(1) and int_0^1 B(y) dy = 0 exactly (B is odd about 1/2): an absolute
     * tolerance as well */
    int st = gsl_integration_qags(&f, 0.0, 1.0, 1e-2 * q->s.epsrel, q->s.epsrel, q->s.limit, q->wy,
                                  &r, &e);
    int rc = integ_status(q, st, r, e, "moment integral over y", err);
    if (!rc) {
        *out = r;
    }
    return rc;
}

int gr_fp_quad_alloc(const gr_fp_settings *s, gr_fp_quad **out, gr_error *err)
{
    *out = NULL;
    int rc = gr_fp_settings_check(s, err);
    if (rc) {
        return rc;
    }
    gr_fp_quad *q = calloc(1, sizeof *q);
    if (!q) {
        return GR_FAIL(err, GR_ENOMEM, "fokker-planck: out of memory");
    }
    q->s = *s;
    q->Gamma = s->D / (s->M * s->M);
    q->V = gr_fp_velocity_scale(s);
    q->T0 = gr_fp_time_scale(s);
    q->c = c_kernel();
    q->kappa = gr_fp_kappa();
    q->C_thesis = thesis_C();
    q->a2 = a2_const();
    q->wv = gsl_integration_workspace_alloc(s->limit);
    q->wy = gsl_integration_workspace_alloc(s->limit);
    q->ws = gsl_integration_workspace_alloc(s->limit);
    if (!q->wv || !q->wy || !q->ws) {
        gr_fp_quad_free(q);
        return GR_FAIL(err, GR_ENOMEM,
                       "fokker-planck: cannot allocate GSL integration workspaces of %zu intervals",
                       s->limit);
    }
    /* normalisation: int Q dv = (c/2) 9^(1/3) Gamma(1/3) J(2/3) (reduced) = mean exit time / T0 */
    rc = y_moment(q, 2.0 * THIRD, true, &q->J23, err);
    if (rc) {
        gr_fp_quad_free(q);
        return rc;
    }
    q->N = 0.5 * q->c * cbrt(9.0) * tgamma(THIRD) * q->J23;
    *out = q;
    return GR_OK;
}

void gr_fp_quad_free(gr_fp_quad *q)
{
    if (!q) {
        return;
    }
    if (q->wv)
        gsl_integration_workspace_free(q->wv);
    if (q->wy)
        gsl_integration_workspace_free(q->wy);
    if (q->ws)
        gsl_integration_workspace_free(q->ws);
    free(q);
}

static int check_v(double v, const char *what, gr_error *err)
{
    if (!isfinite(v)) {
        return GR_FAIL(err, GR_EINVAL, "%s: velocity must be finite, got %g", what, v);
    }
    return GR_OK;
}

static int density_common(gr_fp_quad *q, double x, double v, bool thesis, double *P, double *abserr,
                          gr_error *err)
{
    if (!(x >= 0.0 && x <= q->s.L)) {
        return GR_FAIL(err, GR_EINVAL, "P(x, v): x must lie in [0, L] = [0, %g], got %g", q->s.L,
                       x);
    }
    int rc = check_v(v, "P(x, v)", err);
    if (rc) {
        return rc;
    }
    double Pr, e;
    rc = P_red(q, x / q->s.L, v / q->V, thesis, &Pr, &e, err);
    if (rc) {
        return rc;
    }
    /* P_dim = (R L / V^2) P_red(x/L, v/V); here per unit R */
    double scale = q->s.L / (q->V * q->V);
    *P = scale * Pr;
    if (abserr) {
        *abserr = scale * e;
    }
    return GR_OK;
}

int gr_fp_density(gr_fp_quad *q, double x, double v, double *P, double *abserr, gr_error *err)
{
    return density_common(q, x, v, false, P, abserr, err);
}

int gr_fp_density_thesis(gr_fp_quad *q, double x, double v, double *P, double *abserr,
                         gr_error *err)
{
    return density_common(q, x, v, true, P, abserr, err);
}

static int Q_common(gr_fp_quad *q, double v, bool thesis, double *Q, double *abserr, gr_error *err)
{
    int rc = check_v(v, "Q(v, L)", err);
    if (rc) {
        return rc;
    }
    double r, e;
    rc = Q_red(q, v / q->V, thesis, &r, &e, err);
    if (rc) {
        return rc;
    }
    double scale = q->s.L * q->s.L / (q->V * q->V); /* Q_dim = (R L^2 / V^2) Q_red(v/V) */
    *Q = scale * r;
    if (abserr) {
        *abserr = scale * e;
    }
    return GR_OK;
}

int gr_fp_Q(gr_fp_quad *q, double v, double *Q, double *abserr, gr_error *err)
{
    return Q_common(q, v, false, Q, abserr, err);
}

int gr_fp_Q_thesis(gr_fp_quad *q, double v, double *Q, double *abserr, gr_error *err)
{
    return Q_common(q, v, true, Q, abserr, err);
}

int gr_fp_Q_pdf(gr_fp_quad *q, double v, double *pdf, double *abserr, gr_error *err)
{
    int rc = check_v(v, "Q(v, L)", err);
    if (rc) {
        return rc;
    }
    double r, e;
    rc = Q_red(q, v / q->V, false, &r, &e, err);
    if (rc) {
        return rc;
    }
    *pdf = r / (q->N * q->V);
    if (abserr) {
        *abserr = e / (q->N * q->V);
    }
    return GR_OK;
}

double gr_fp_mean_exit_time(const gr_fp_quad *q) { return q->N * q->T0; }

/* bin means: QAG (Gauss-Kronrod 15) over the bin, nested around the y quadrature */
typedef struct bin_args {
    gr_fp_quad *q;
    int rc;
    gr_error err;
    bool exit;
} bin_args;

static double bin_f(double vr, void *p)
{
    bin_args *b = p;
    if (b->rc) {
        return NAN;
    }
    double r;
    if (b->exit) {
        b->rc = P_red(b->q, 1.0, vr, false, &r, NULL, &b->err);
        r *= vr;
    } else {
        b->rc = Q_red(b->q, vr, false, &r, NULL, &b->err);
    }
    return b->rc ? (double)NAN : r;
}

static int bin_mean(gr_fp_quad *q, double v1, double v2, bool exit, double *mean, gr_error *err)
{
    if (!isfinite(v1) || !isfinite(v2) || !(v2 > v1)) {
        return GR_FAIL(err, GR_EINVAL, "bin mean: need finite v1 < v2, got [%g, %g]", v1, v2);
    }
    if (exit && v1 < 0.0) {
        return GR_FAIL(err, GR_EINVAL, "exit-velocity bin mean: need v1 >= 0, got %g", v1);
    }
    bin_args b = {.q = q, .exit = exit};
    gsl_function f = {bin_f, &b};
    double r, e;
    double a = v1 / q->V, z = v2 / q->V;
    /* Q has a cusp at v = 0: split a bin that straddles it */
    int st;
    if (!exit && a < 0.0 && z > 0.0) {
        double r1, e1;
        st = gsl_integration_qag(&f, a, 0.0, 0.0, fmax(q->s.epsrel, 1e-8), q->s.limit,
                                 GSL_INTEG_GAUSS15, q->wv, &r1, &e1);
        if (st == GSL_SUCCESS && !b.rc) {
            st = gsl_integration_qag(&f, 0.0, z, 0.0, fmax(q->s.epsrel, 1e-8), q->s.limit,
                                     GSL_INTEG_GAUSS15, q->wv, &r, &e);
            r += r1;
            e += e1;
        } else {
            r = r1;
            e = e1;
        }
    } else {
        st = gsl_integration_qag(&f, a, z, 0.0, fmax(q->s.epsrel, 1e-8), q->s.limit,
                                 GSL_INTEG_GAUSS15, q->wv, &r, &e);
    }
    if (b.rc) {
        if (err) {
            *err = b.err;
        }
        return b.rc;
    }
    if (!isfinite(r) || (st != GSL_SUCCESS && !(e <= 1e-6 * fabs(r) + 1e-300))) {
        return GR_FAIL(err, GR_EUNSTABLE, "bin mean over [%g, %g]: %s", v1, v2, gsl_strerror(st));
    }
    /* reduced integral over v' -> mean over the physical bin */
    double width = v2 - v1;
    *mean = exit ? r / width : r / (q->N * width);
    return GR_OK;
}

int gr_fp_Q_pdf_bin(gr_fp_quad *q, double v1, double v2, double *mean, gr_error *err)
{
    return bin_mean(q, v1, v2, false, mean, err);
}

int gr_fp_exit_over_v(gr_fp_quad *q, double v, double *value, double *abserr, gr_error *err)
{
    if (!(isfinite(v) && v >= 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "P(L, v): need a finite v >= 0, got %g", v);
    }
    double r, e;
    int rc = P_red(q, 1.0, v / q->V, false, &r, &e, err);
    if (rc) {
        return rc;
    }
    /* P(L, v) / (R L) = P_red(1, v/V) / V^2 */
    *value = r / (q->V * q->V);
    if (abserr) {
        *abserr = e / (q->V * q->V);
    }
    return GR_OK;
}

int gr_fp_exit_pdf_bin(gr_fp_quad *q, double v1, double v2, double *mean, gr_error *err)
{
    return bin_mean(q, v1, v2, true, mean, err);
}

int gr_fp_moment(gr_fp_quad *q, double m, double *value, gr_error *err)
{
    if (!(isfinite(m) && m >= 0.0 && m <= 40.0)) {
        return GR_FAIL(err, GR_EINVAL, "moment order must lie in [0, 40], got %g", m);
    }
    double J;
    int rc = y_moment(q, (m + 2.0) / 3.0, true, &J, err);
    if (rc) {
        return rc;
    }
    /* <|v'|^m> = 9^(m/3) [Gamma((m+1)/3)/Gamma(1/3)] [2/(m+2)] J((m+2)/3) / J(2/3) */
    double r =
        pow(9.0, m / 3.0) * tgamma((m + 1.0) / 3.0) / tgamma(THIRD) * 2.0 / (m + 2.0) * J / q->J23;
    *value = pow(q->V, m) * r;
    return GR_OK;
}

int gr_fp_exit_moment(gr_fp_quad *q, double m, double *value, gr_error *err)
{
    if (!(isfinite(m) && m > -2.0 && m <= 40.0)) {
        return GR_FAIL(err, GR_EINVAL, "exit moment order must lie in (-2, 40], got %g", m);
    }
    double K;
    int rc = y_moment(q, m / 3.0, false, &K, err);
    if (rc) {
        return rc;
    }
    /* int_0^inf v'^(m+1) P(1, v') dv' = (c/2) 9^((m+2)/3) Gamma((m+2)/3)/3 [3/(m+3) - kappa K(m/3)];
     * per exit (both ends, each carrying half the particles) that is doubled */
    double r = 2.0 * 0.5 * q->c * pow(9.0, (m + 2.0) / 3.0) * tgamma((m + 2.0) / 3.0) / 3.0 *
               (3.0 / (m + 3.0) - q->kappa * K);
    *value = pow(q->V, m) * r;
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * Simulation */

/* Cubic Hermite interpolant on s in [0, 1] through (x0, tau v0) and (x1, tau v1). Returns true if
 * it leaves (0, 1); *s_out is the first crossing and *side is +1 (x = 1) or -1 (x = 0). */
static bool hermite_exit(double x0, double v0, double x1, double v1, double tau, double *s_out,
                         double *vel, int *side)
{
    const double a0 = x0, a1 = tau * v0, a2 = 3.0 * (x1 - x0) - 2.0 * tau * v0 - tau * v1,
                 a3 = 2.0 * (x0 - x1) + tau * v0 + tau * v1;
#define HX(s) (a0 + (s) * (a1 + (s) * (a2 + (s)*a3)))
#define HV(s) (a1 + (s) * (2.0 * a2 + (s)*3.0 * a3))
    /* monotone pieces between the roots of h'(s) = a1 + 2 a2 s + 3 a3 s^2 inside (0, 1) */
    double cut[4] = {0.0, 1.0, 1.0, 1.0};
    int n = 1;
    double A = 3.0 * a3, Bq = 2.0 * a2, Cq = a1;
    double roots[2];
    int nr = 0;
    if (fabs(A) > 1e-300) {
        double disc = Bq * Bq - 4.0 * A * Cq;
        if (disc > 0.0) {
            double sq = sqrt(disc);
            double qq = -0.5 * (Bq + copysign(sq, Bq));
            roots[nr++] = qq / A;
            if (qq != 0.0) {
                roots[nr++] = Cq / qq;
            }
        }
    } else if (fabs(Bq) > 1e-300) {
        roots[nr++] = -Cq / Bq;
    }
    if (nr == 2 && roots[0] > roots[1]) {
        double t = roots[0];
        roots[0] = roots[1];
        roots[1] = t;
    }
    for (int i = 0; i < nr; i++) {
        if (roots[i] > 0.0 && roots[i] < 1.0) {
            cut[n++] = roots[i];
        }
    }
    cut[n] = 1.0;
    for (int k = 0; k < n; k++) {
        double sa = cut[k], sb = cut[k + 1];
        double hb = HX(sb);
        int sd = hb >= 1.0 ? 1 : (hb <= 0.0 ? -1 : 0);
        if (!sd) {
            continue;
        }
        double target = sd > 0 ? 1.0 : 0.0;
        /* h is monotone on [sa, sb], inside at sa, outside at sb: bisect */
        double lo = sa, hi = sb;
        for (int it = 0; it < 60 && hi - lo > 1e-15; it++) {
            double mid = 0.5 * (lo + hi);
            double hm = HX(mid);
            if (sd > 0 ? hm >= target : hm <= target) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        *s_out = hi;
        *vel = HV(hi) / tau;
        *side = sd;
        return true;
    }
    return false;
#undef HX
#undef HV
}

/* The first exit within a step from (x0, v0) to (x1, v1) of length h (reduced units, Gamma = 1),
 * found by bisecting the exact bridge of the random-acceleration process: given both ends, the
 * midpoint is Gaussian with mean (the Hermite cubic at h/2)
 *     x_m = (x0 + x1)/2 + h (v0 - v1)/8,   v_m = 3 (x1 - x0)/(2h) - (v0 + v1)/4
 * and independent variances Var(x_m) = (h/2)^3 / 12, Var(v_m) = (h/2) / 4 (<eta eta'> = 2 delta).
 * Sub-intervals that cannot come near a wall (Hermite reach 4/27 h (|v0|+|v1|) plus 6 standard
 * deviations of the bridge) are skipped; after `depth` levels the Hermite test decides. Sampling
 * the midpoints from their exact conditional law leaves the step's end state unbiased. Returns
 * true with *t_out the exit time from the start of the step. */
static bool bridge_exit(gsl_rng *rng, double x0, double v0, double x1, double v1, double h,
                        int depth, double *t_out, double *vel, int *side)
{
    const double margin =
        (4.0 / 27.0) * h * (fabs(v0) + fabs(v1)) + (depth > 0 ? 6.0 * sqrt(h * h * h / 12.0) : 0.0);
    if (fmin(x0, x1) - margin > 0.0 && fmax(x0, x1) + margin < 1.0) {
        return false;
    }
    if (depth == 0) {
        double se;
        if (hermite_exit(x0, v0, x1, v1, h, &se, vel, side)) {
            *t_out = se * h;
            return true;
        }
        return false;
    }
    const double a = 0.5 * h;
    const double xm = 0.5 * (x0 + x1) + 0.125 * h * (v0 - v1) +
                      sqrt(a * a * a / 12.0) * gsl_ran_gaussian_ziggurat(rng, 1.0);
    const double vm = 1.5 * (x1 - x0) / h - 0.25 * (v0 + v1) +
                      sqrt(0.25 * a) * gsl_ran_gaussian_ziggurat(rng, 1.0);
    if (bridge_exit(rng, x0, v0, xm, vm, a, depth - 1, t_out, vel, side)) {
        return true;
    }
    if (bridge_exit(rng, xm, vm, x1, v1, a, depth - 1, t_out, vel, side)) {
        *t_out += a;
        return true;
    }
    return false;
}

typedef struct walk_acc {
    double sum_n, sum_n2;      /* samples per walk */
    double F[6], F2[6], FN[6]; /* per-walk sums of v, v^2, v^3, v^4 (1..4) and |v| (5) */
} walk_acc;

static void ratio_estimate(const walk_acc *a, int k, double *mean, double *err)
{
    double mu = a->F[k] / a->sum_n;
    double var = (a->F2[k] - 2.0 * mu * a->FN[k] + mu * mu * a->sum_n2) / (a->sum_n * a->sum_n);
    *mean = mu;
    *err = sqrt(fmax(var, 0.0));
}

static double now_seconds(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void gr_fp_sim_result_free(gr_fp_sim_result *r)
{
    gr_histogram_free(&r->q);
    gr_histogram_free(&r->exit_right);
    gr_histogram_free(&r->exit_left);
    free(r->q_err);
    r->q_err = NULL;
    free(r->q_cov);
    r->q_cov = NULL;
    free(r->q_walks);
    r->q_walks = NULL;
}

int gr_fp_simulate(const gr_fp_settings *s, gr_fp_progress progress, void *user,
                   gr_fp_sim_result *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    int rc = gr_fp_settings_check(s, err);
    if (rc) {
        return rc;
    }
    const double t_start = now_seconds(CLOCK_MONOTONIC),
                 cpu_start = now_seconds(CLOCK_THREAD_CPUTIME_ID);
    const double V = gr_fp_velocity_scale(s), T0 = gr_fp_time_scale(s);
    const double vmax = s->vmax_V * V;
    const int nb = s->bins;
    rc = gr_histogram_init(&out->q, nb, -vmax, vmax, false, err);
    if (!rc) {
        rc = gr_histogram_init(&out->exit_right, s->exit_bins, 0.0, vmax, false, err);
    }
    if (!rc) {
        rc = gr_histogram_init(&out->exit_left, s->exit_bins, 0.0, vmax, false, err);
    }
    if (rc) {
        gr_fp_sim_result_free(out);
        return rc;
    }
    /* per-walk bin counts (index nb: outside the range), the bins a walk touched, and the
     * walk-level sums for the covariance of the bin densities */
    double *local = calloc((size_t)nb + 1, sizeof(double));
    int *touched = malloc(((size_t)nb + 1) * sizeof(int));
    double *S_nN = calloc((size_t)nb, sizeof(double));
    out->q_err = calloc((size_t)nb, sizeof(double));
    out->q_cov = calloc((size_t)nb * (size_t)nb, sizeof(double));
    out->q_walks = calloc((size_t)nb, sizeof(double));
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (!local || !touched || !S_nN || !out->q_err || !out->q_cov || !out->q_walks || !rng) {
        free(local);
        free(touched);
        free(S_nN);
        if (rng)
            gsl_rng_free(rng);
        gr_fp_sim_result_free(out);
        return GR_FAIL(err, GR_ENOMEM, "fokker-planck simulation: out of memory for %d bins", nb);
    }
    gsl_rng_set(rng, (unsigned long)s->seed);
    double *S_nn = out->q_cov; /* sum over walks of n_i n_j, turned into the covariance below */

    /* reduced units: x in (0, 1), v in units of V, t in units of T0 (Gamma = 1) */
    const double tau = 1.0 / s->steps_per_T0;
    const double sig_v = sqrt(2.0 * tau);             /* sqrt(2 D tau)/M in units of V */
    const double sig_x = sqrt(tau * tau * tau / 6.0); /* sqrt(D tau^3 / 6)/M in units of L */
    const int64_t max_steps = (int64_t)ceil(s->max_T0 * s->steps_per_T0);
    const double bin_scale = nb / (2.0 * s->vmax_V);
    walk_acc acc;
    memset(&acc, 0, sizeof acc);
    double sum_T = 0.0, sum_T2 = 0.0, sum_ve = 0.0, sum_ve2 = 0.0, sum_ve4 = 0.0;
    int64_t n_exit = 0;
    const int64_t report_every = s->walkers / 200 > 0 ? s->walkers / 200 : 1;

    for (int64_t w = 0; w < s->walkers; w++) {
        if (progress && w % report_every == 0 && progress((double)w / (double)s->walkers, user)) {
            rc = GR_FAIL(err, GR_EINVAL, "fokker-planck simulation stopped after %lld walkers",
                         (long long)w);
            break;
        }
        double x = s->start == GR_FP_START_CENTRE ? 0.5 : gsl_rng_uniform_pos(rng);
        double v = 0.0, t_exit = 0.0, v_exit = 0.0;
        int side = 0, ntouched = 0;
        int64_t k = 0;
        double Fw[6] = {0};
        /* the first step has a random length phi tau, phi uniform in (0, 1]: the sampling times
         * phi tau, phi tau + tau, ... are then uniform in time over the ensemble, so the samples
         * estimate the time average without the O(sqrt(tau)) error that a grid anchored at the
         * start (where every walk has v = 0) leaves at the cusp of Q at v = 0 */
        const double phi = gsl_rng_uniform_pos(rng);
        double h = phi * tau, t = 0.0;
        for (k = 0; k < max_steps; k++) {
            double g1 = gsl_ran_gaussian_ziggurat(rng, 1.0);
            double g2 = gsl_ran_gaussian_ziggurat(rng, 1.0);
            double sv = k ? sig_v : sqrt(2.0 * h), sx = k ? sig_x : sqrt(h * h * h / 6.0);
            double dv = sv * g1;
            double x1 = x + v * h + 0.5 * h * dv + sx * g2;
            double v1 = v + dv;
            /* an exit inside the step: exact bridge bisection near the walls, then the Hermite
             * cubic (which stays within 4/27 h (|v| + |v1|) of [min, max] of the ends) */
            double te, ve;
            int sd;
            if (bridge_exit(rng, x, v, x1, v1, h, s->refine, &te, &ve, &sd)) {
                t_exit = t + te;
                v_exit = ve;
                side = sd;
                break;
            }
            t += h;
            h = tau;
            x = x1;
            v = v1;
            /* sample uniformly in time: the velocity at the end of every step survived */
            double u = (v + s->vmax_V) * bin_scale;
            int i = (u >= 0.0 && u < nb) ? (int)u : nb;
            if (local[i] == 0.0) {
                touched[ntouched++] = i;
            }
            local[i] += 1.0;
            double v2 = v * v;
            Fw[1] += v;
            Fw[2] += v2;
            Fw[3] += v2 * v;
            Fw[4] += v2 * v2;
            Fw[5] += fabs(v);
        }
        const double Nw = (double)k;
        out->steps += k + (side ? 1 : 0);
        /* fold the walk into the histogram and the walk-level sums */
        for (int a = 0; a < ntouched; a++) {
            int i = touched[a];
            double n = local[i];
            double at = i < nb ? gr_histogram_center(&out->q, i) : 2.0 * vmax;
            gr_histogram_add(&out->q, at, n);
            if (i < nb) {
                out->q_walks[i] += 1.0;
                S_nN[i] += n * Nw;
                for (int b2 = 0; b2 < ntouched; b2++) {
                    int j = touched[b2];
                    if (j < nb && j >= i) { /* upper triangle; mirrored below */
                        S_nn[(size_t)i * (size_t)nb + (size_t)j] += n * local[j];
                    }
                }
            }
        }
        for (int a = 0; a < ntouched; a++) {
            local[touched[a]] = 0.0;
        }
        acc.sum_n += Nw;
        acc.sum_n2 += Nw * Nw;
        for (int m = 1; m <= 5; m++) {
            acc.F[m] += Fw[m];
            acc.F2[m] += Fw[m] * Fw[m];
            acc.FN[m] += Fw[m] * Nw;
        }
        if (!side) {
            out->truncated++;
            gr_histogram_add(&out->exit_right, -1.0, 1.0);
            gr_histogram_add(&out->exit_left, -1.0, 1.0);
            continue;
        }
        double ve = fabs(v_exit) * V;
        if (side > 0) {
            out->right_exits++;
            gr_histogram_add(&out->exit_right, ve, 1.0);
            gr_histogram_add(&out->exit_left, -1.0, 1.0);
        } else {
            out->left_exits++;
            gr_histogram_add(&out->exit_left, ve, 1.0);
            gr_histogram_add(&out->exit_right, -1.0, 1.0);
        }
        n_exit++;
        double te = t_exit * T0;
        sum_T += te;
        sum_T2 += te * te;
        sum_ve += ve;
        sum_ve2 += ve * ve;
        sum_ve4 += ve * ve * ve * ve;
    }
    out->walkers = out->right_exits + out->left_exits + out->truncated;
    if (!rc && progress) {
        progress(1.0, user);
    }
    if (!rc && acc.sum_n <= 0.0) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "fokker-planck simulation: no velocity sample was recorded (all walks left "
                     "within one step; raise --steps)");
    }
    if (!rc) {
        /* bin densities p_i / w with covariance sum_walks (n_i - p_i N)(n_j - p_j N) / (S_N w)^2 */
        const double SN = acc.sum_n, w = 2.0 * vmax / nb;
        for (int i = 0; i < nb; i++) {
            for (int j = 0; j < i; j++) {
                S_nn[(size_t)i * (size_t)nb + (size_t)j] = S_nn[(size_t)j * (size_t)nb + (size_t)i];
            }
        }
        for (int i = 0; i < nb; i++) {
            double pi = out->q.count[i] / SN;
            for (int j = 0; j < nb; j++) {
                double pj = out->q.count[j] / SN;
                size_t ij = (size_t)i * (size_t)nb + (size_t)j;
                double c = S_nn[ij] - pi * S_nN[j] - pj * S_nN[i] + pi * pj * acc.sum_n2;
                S_nn[ij] = c / (SN * SN * w * w);
            }
        }
        for (int i = 0; i < nb; i++) {
            out->q_err[i] = sqrt(fmax(S_nn[(size_t)i * (size_t)nb + (size_t)i], 0.0));
        }
        for (int m = 1; m <= 4; m++) {
            ratio_estimate(&acc, m, &out->v_moment[m], &out->v_moment_err[m]);
            out->v_moment[m] *= pow(V, m);
            out->v_moment_err[m] *= pow(V, m);
        }
        ratio_estimate(&acc, 5, &out->abs_v_mean, &out->abs_v_mean_err);
        out->abs_v_mean *= V;
        out->abs_v_mean_err *= V;
        if (n_exit > 0) {
            double ne = (double)n_exit;
            out->mean_exit_time = sum_T / ne;
            out->exit_speed_mean = sum_ve / ne;
            out->exit_speed2_mean = sum_ve2 / ne;
            if (n_exit > 1) {
                out->mean_exit_time_err =
                    sqrt(fmax(sum_T2 / ne - out->mean_exit_time * out->mean_exit_time, 0.0) /
                         (ne - 1.0));
                out->exit_speed_err =
                    sqrt(fmax(sum_ve2 / ne - out->exit_speed_mean * out->exit_speed_mean, 0.0) /
                         (ne - 1.0));
                out->exit_speed2_err =
                    sqrt(fmax(sum_ve4 / ne - out->exit_speed2_mean * out->exit_speed2_mean, 0.0) /
                         (ne - 1.0));
            }
        }
        out->tau = tau * T0;
    }
    out->wall_seconds = now_seconds(CLOCK_MONOTONIC) - t_start;
    out->cpu_seconds = now_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu_start;
    free(local);
    free(touched);
    free(S_nN);
    gsl_rng_free(rng);
    if (rc) {
        gr_fp_sim_result_free(out);
    }
    return rc;
}

/* ------------------------------------------------------------------------------------------
 * Comparisons */

int gr_fp_compare_Q(gr_fp_quad *q, const gr_fp_sim_result *r, double min_walks, double *model,
                    gr_fp_chi2 *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    const gr_histogram *h = &r->q;
    const int nb = h->nbins;
    if (!r->q_err || !r->q_cov || !r->q_walks || nb < 1 || h->total <= 0.0) {
        return GR_FAIL(err, GR_EINVAL, "compare Q: the simulation result is empty");
    }
    double *m = malloc((size_t)nb * sizeof(double));
    int *use = malloc((size_t)nb * sizeof(int));
    if (!m || !use) {
        free(m);
        free(use);
        return GR_FAIL(err, GR_ENOMEM, "compare Q: out of memory");
    }
    int n = 0, rc = GR_OK;
    for (int i = 0; i < nb && !rc; i++) {
        double lo = gr_histogram_lower(h, i), hi = gr_histogram_upper(h, i);
        rc = gr_fp_Q_pdf_bin(q, lo, hi, &m[i], err);
        if (rc) {
            break;
        }
        if (model) {
            model[i] = m[i];
        }
        double expected = m[i] * (hi - lo) * h->total;
        if (expected >= min_walks && r->q_walks[i] >= min_walks && r->q_err[i] > 0.0) {
            double z = (gr_histogram_density(h, i) - m[i]) / r->q_err[i];
            out->chi2 += z * z;
            out->max_abs_z = fmax(out->max_abs_z, fabs(z));
            use[n++] = i;
        }
    }
    if (!rc && n == 0) {
        rc = GR_FAIL(err, GR_EINVAL, "compare Q: no bin was visited by %g walks", min_walks);
    }
    if (!rc) {
        /* Satterthwaite: sum over the correlation matrix squared */
        double sumR2 = 0.0;
        for (int a = 0; a < n; a++) {
            for (int b = 0; b < n; b++) {
                int i = use[a], j = use[b];
                double rij =
                    r->q_cov[(size_t)i * (size_t)nb + (size_t)j] / (r->q_err[i] * r->q_err[j]);
                sumR2 += rij * rij;
            }
        }
        out->dof = n;
        out->dof_eff = (double)n * (double)n / sumR2;
        out->p_value = gsl_cdf_chisq_Q(out->chi2 * out->dof_eff / n, out->dof_eff);
        /* full chi-square r^T C^-1 r with the walk-level covariance of the bin densities */
        out->chi2_full = NAN;
        out->p_full = NAN;
        gsl_matrix *C = gsl_matrix_alloc((size_t)n, (size_t)n);
        gsl_vector *res = gsl_vector_alloc((size_t)n), *sol = gsl_vector_alloc((size_t)n);
        if (!C || !res || !sol) {
            rc = GR_FAIL(err, GR_ENOMEM, "compare Q: out of memory");
        } else {
            for (int a = 0; a < n; a++) {
                int i = use[a];
                gsl_vector_set(res, (size_t)a, gr_histogram_density(h, i) - m[i]);
                for (int b = 0; b < n; b++) {
                    gsl_matrix_set(C, (size_t)a, (size_t)b,
                                   r->q_cov[(size_t)i * (size_t)nb + (size_t)use[b]]);
                }
            }
            int st = gsl_linalg_cholesky_decomp1(C);
            if (st == GSL_SUCCESS) {
                st = gsl_linalg_cholesky_solve(C, res, sol);
            }
            if (st == GSL_SUCCESS) {
                gsl_blas_ddot(res, sol, &out->chi2_full);
                out->p_full = gsl_cdf_chisq_Q(out->chi2_full, n);
            }
        }
        if (C)
            gsl_matrix_free(C);
        if (res)
            gsl_vector_free(res);
        if (sol)
            gsl_vector_free(sol);
    }
    free(m);
    free(use);
    return rc;
}

int gr_fp_compare_exit(gr_fp_quad *q, const gr_fp_sim_result *r, double min_expected, double *model,
                       gr_fp_chi2 *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    const gr_histogram *hr = &r->exit_right, *hl = &r->exit_left;
    if (hr->nbins < 1 || hr->nbins != hl->nbins || hr->total <= 0.0) {
        return GR_FAIL(err, GR_EINVAL, "compare exits: the simulation result is empty");
    }
    const double W = hr->total; /* released walkers */
    for (int i = 0; i < hr->nbins; i++) {
        double lo = gr_histogram_lower(hr, i), hi = gr_histogram_upper(hr, i), mean;
        int rc = gr_fp_exit_pdf_bin(q, lo, hi, &mean, err);
        if (rc) {
            return rc;
        }
        mean *= 2.0; /* both ends pooled */
        if (model) {
            model[i] = mean;
        }
        double X = hr->count[i] + hl->count[i], expected = mean * (hi - lo) * W;
        if (expected >= min_expected) {
            double sigma = sqrt(X > 0.0 ? X : expected) / (W * (hi - lo)); /* sqrt(X) */
            double z = (X / (W * (hi - lo)) - mean) / sigma;
            out->chi2 += z * z;
            out->max_abs_z = fmax(out->max_abs_z, fabs(z));
            out->dof++;
        }
    }
    if (out->dof == 0) {
        return GR_FAIL(err, GR_EINVAL, "compare exits: no bin has %g expected exits", min_expected);
    }
    out->dof_eff = out->dof;
    out->p_value = gsl_cdf_chisq_Q(out->chi2, out->dof);
    out->chi2_full = out->chi2;
    out->p_full = out->p_value;
    return GR_OK;
}

int gr_fp_sim_Q0(const gr_fp_sim_result *r, double *Q0, double *Q0_err, gr_error *err)
{
    const gr_histogram *h = &r->q;
    const int nb = h->nbins, half = nb / 2;
    if (!r->q_cov || nb < 4) {
        return GR_FAIL(err, GR_EINVAL,
                       "Q(0) from the histogram: need a simulation result with at least 4 bins");
    }
    /* the two innermost bins on each side (centres c and 3c), folded over v -> -v, extrapolated
     * linearly to v = 0: Q(0) = 1.5 d(c) - 0.5 d(3c) */
    const int idx[4] = {half, half - 1, half + 1, half - 2};
    const double w[4] = {0.75, 0.75, -0.25, -0.25};
    double q0 = 0.0, var = 0.0;
    for (int a = 0; a < 4; a++) {
        if (r->q_walks[idx[a]] < 1.0) {
            return GR_FAIL(err, GR_EINVAL,
                           "Q(0) from the histogram: the bins next to v = 0 are empty");
        }
        q0 += w[a] * gr_histogram_density(h, idx[a]);
        for (int b = 0; b < 4; b++) {
            var += w[a] * w[b] * r->q_cov[(size_t)idx[a] * (size_t)nb + (size_t)idx[b]];
        }
    }
    *Q0 = q0;
    *Q0_err = sqrt(fmax(var, 0.0));
    return GR_OK;
}
