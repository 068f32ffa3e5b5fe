/* The multiplicative bisection process (thesis sec. 3.4) against its closed forms: P_n(x) of the
 * uniform process is (3.36) (chi-square over the histogram, Kolmogorov-Smirnov on -ln x, which is
 * Gamma(n, 1)), the moments are (1+m)^-n (3.37) and zeta_m = ln(1+m)/ln 2 (3.38), the partitions of
 * one realisation sum to 1 at every level, the power-law U_0 is a normalised density sampled
 * correctly, the collapse 3.39-3.40 maps (3.36) onto -ln R, and bad inputs are refused. Fixed
 * seeds; each statistical check has a negative control showing it can fail. */
#include <check.h>
#include <cjson/cJSON.h>
#include <float.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_gamma.h>
#include <gsl/gsl_sf_psi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/bisect.h"
#include "io/files.h"
#include "check_main.h"

/* ---------- helpers ---------- */

static char tmp_dir[64];

static void make_tmp_dir(void)
{
    snprintf(tmp_dir, sizeof tmp_dir, "/tmp/granule-test-bisect-XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(tmp_dir));
}

static void remove_tree(const char *dir)
{
    char cmd[200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    ck_assert_int_eq(system(cmd), 0);
}

/* Write text to tmp_dir/name; returns the path in a static buffer. */
static const char *write_file(const char *name, const char *text)
{
    static char path[200];
    snprintf(path, sizeof path, "%s/%s", tmp_dir, name);
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Kolmogorov distribution tail Q_KS(lambda) = 2 sum (-1)^(k-1) exp(-2 k^2 lambda^2), with
 * Stephens' finite-n correction lambda = (sqrt(n) + 0.12 + 0.11/sqrt(n)) D. */
static double ks_p_value(double D, size_t n)
{
    double sn = sqrt((double)n), lambda = (sn + 0.12 + 0.11 / sn) * D;
    if (lambda < 0.2) {
        return 1.0;
    }
    double sum = 0.0;
    for (int k = 1; k <= 100; k++) {
        sum += (k % 2 ? 2.0 : -2.0) * exp(-2.0 * k * k * lambda * lambda);
    }
    return fmin(fmax(sum, 0.0), 1.0);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* D = sup |F_empirical - F| for sorted samples. */
static double ks_statistic(double *v, size_t n, double (*cdf)(double, void *), void *user)
{
    qsort(v, n, sizeof *v, cmp_double);
    double D = 0.0;
    for (size_t i = 0; i < n; i++) {
        double F = cdf(v[i], user);
        D = fmax(D, fmax(F - (double)i / (double)n, (double)(i + 1) / (double)n - F));
    }
    return D;
}

static double gamma_cdf(double z, void *user)
{
    return gsl_cdf_gamma_P(z, *(const double *)user, 1.0);
}

static void run_uniform(int levels, int64_t reps, uint64_t seed, gr_bisect_result *res)
{
    gr_bisect_settings s;
    gr_bisect_settings_default(&s);
    s.levels = levels;
    s.repetitions = reps;
    s.seed = seed;
    gr_bisect_u0 u;
    gr_bisect_u0_uniform(&u);
    gr_error err = {0};
    ck_assert_msg(gr_bisect_run(&s, &u, res, &err) == GR_OK, "%s", err.message);
}

/* ---------- P_n(x) of the uniform process (3.36) ---------- */

START_TEST(test_pn_chi_square)
{
    /* all 2^6 partitions of 20000 realisations, bins expecting >= 50 partitions; the variance of each
     * bin's count is measured over realisations (siblings share their parent's length) */
    gr_bisect_result res;
    run_uniform(6, 20000, 11, &res);
    gr_bisect_gof g;
    gr_error err = {0};
    ck_assert_int_eq(gr_bisect_pn_gof(&res, 50.0, &g, &err), GR_OK);
    ck_assert_msg(g.dof >= 40, "only %d bins", g.dof);
    ck_assert_msg(g.p_value > 1e-3, "P_6 vs (3.36): chi2 = %g for %d bins, p = %g", g.chi2, g.dof,
                  g.p_value);
    ck_assert_msg(fabs(g.chi2 / g.dof - 1.0) < 0.5, "chi2/dof = %g", g.chi2 / g.dof);
    ck_assert_double_eq(res.pn.total, 20000.0 * 64.0);
    /* negative control: the same histogram is far from P_7 and P_5 */
    res.levels = 7;
    ck_assert_int_eq(gr_bisect_pn_gof(&res, 50.0, &g, &err), GR_OK);
    ck_assert_msg(g.p_value < 1e-12, "P_6 data accepted as P_7: p = %g", g.p_value);
    res.levels = 5;
    ck_assert_int_eq(gr_bisect_pn_gof(&res, 50.0, &g, &err), GR_OK);
    ck_assert_msg(g.p_value < 1e-12, "P_6 data accepted as P_5: p = %g", g.p_value);
    res.levels = 6;
    /* the bin densities themselves: the bin with the most counts within 5 of its errors */
    int best = 0;
    for (int b = 0; b < res.pn.nbins; b++) {
        best = res.pn.count[b] > res.pn.count[best] ? b : best;
    }
    double lo = gr_histogram_lower(&res.pn, best), hi = gr_histogram_upper(&res.pn, best);
    double expect = gr_bisect_pn_uniform_mass(6, lo, hi) / (hi - lo);
    double sigma = sqrt(20000.0 * res.pn_count_var[best]) / (res.pn.total * (hi - lo));
    ck_assert_msg(fabs(gr_histogram_density(&res.pn, best) - expect) < 4.5 * sigma,
                  "peak bin density %g +- %g vs %g", gr_histogram_density(&res.pn, best), sigma,
                  expect);
    gr_bisect_result_free(&res);
}
END_TEST

START_TEST(test_pn_ks)
{
    /* one partition per realisation (a different index each time) is an independent sample of
     * P_n: its -ln x is Gamma(n, 1) (3.36) */
    const int n = 5;
    const size_t R = 20000, N = (size_t)1 << n;
    gr_bisect_u0 u;
    gr_bisect_u0_uniform(&u);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    double x[1 << 5], *z = malloc(sizeof(double) * R);
    gr_error err = {0};
    for (size_t i = 0; i < R; i++) {
        ck_assert_int_eq(gr_bisect_realise(&u, n, r, x, &err), GR_OK);
        z[i] = -log(x[i % N]);
    }
    double shape = n, D = ks_statistic(z, R, gamma_cdf, &shape);
    double p = ks_p_value(D, R);
    ck_assert_msg(p > 1e-3, "KS of -ln x against Gamma(%d, 1): D = %g, p = %g", n, D, p);
    /* negative controls: Gamma(n +- 1, 1) must be rejected */
    shape = n + 1;
    D = ks_statistic(z, R, gamma_cdf, &shape);
    ck_assert_msg(ks_p_value(D, R) < 1e-6, "accepted Gamma(%d): D = %g", n + 1, D);
    shape = n - 1;
    D = ks_statistic(z, R, gamma_cdf, &shape);
    ck_assert_msg(ks_p_value(D, R) < 1e-6, "accepted Gamma(%d): D = %g", n - 1, D);
    free(z);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_pn_closed_form)
{
    /* 3.33-3.36: P_1 = 1, P_2 = -ln x, P_3 = (ln x)^2 / 2; each integrates to 1 */
    for (double x = 0.01; x < 1.0; x += 0.07) {
        ck_assert_double_eq_tol(gr_bisect_pn_uniform(1, x), 1.0, 1e-15);
        ck_assert_double_eq_tol(gr_bisect_pn_uniform(2, x), -log(x), 1e-14);
        ck_assert_double_eq_tol(gr_bisect_pn_uniform(3, x), 0.5 * log(x) * log(x), 1e-13);
    }
    for (int n = 1; n <= 12; n++) {
        ck_assert_double_eq_tol(gr_bisect_pn_uniform_mass(n, 0.0, 1.0), 1.0, 1e-14);
        double a = gr_bisect_pn_uniform_mass(n, 1e-3, 0.2),
               b = gr_bisect_pn_uniform_mass(n, 0.2, 0.5);
        ck_assert_double_eq_tol(a + b, gr_bisect_pn_uniform_mass(n, 1e-3, 0.5), 1e-14);
        ck_assert_double_eq_tol(gr_bisect_moment_uniform(n, 2.0), pow(3.0, -n), 1e-300);
    }
    /* the mass of a narrow bin is the density times the width */
    ck_assert_double_eq_tol(gr_bisect_pn_uniform_mass(9, 0.01, 0.01 * (1 + 1e-6)) / (0.01e-6),
                            gr_bisect_pn_uniform(9, 0.01), 1e-5 * gr_bisect_pn_uniform(9, 0.01));
    ck_assert_double_eq_tol(gr_bisect_zeta_uniform(2.0), log(3.0) / log(2.0), 1e-15);
    double e;
    ck_assert_double_eq(gr_bisect_zeta_rfm_table31(2, &e), 1.729);
    ck_assert_double_eq(e, 0.008);
    ck_assert(isnan(gr_bisect_zeta_rfm_table31(6, &e)));
}
END_TEST

/* ---------- moments (3.37) and zeta_m (3.38) ---------- */

START_TEST(test_moments_uniform)
{
    const int n = 6;
    gr_bisect_result res;
    run_uniform(n, 20000, 3, &res);
    double zmax = 0.0;
    for (int k = 1; k <= n; k++) {
        double e1, m1 = gr_bisect_result_moment(&res, k, 1, &e1);
        ck_assert_msg(fabs(m1 * ldexp(1.0, k) - 1.0) < 1e-13, "level %d: <x> 2^k = %.17g", k,
                      m1 * ldexp(1.0, k));
        for (int m = 2; m <= res.moments_max; m++) {
            double err, v = gr_bisect_result_moment(&res, k, m, &err);
            double z = (v - gr_bisect_moment_uniform(k, m)) / err;
            ck_assert_msg(fabs(z) < 4.5,
                          "level %d, m = %d: <x^m> = %g +- %g vs (1+m)^-k = %g (z = %.2f)", k, m, v,
                          err, gr_bisect_moment_uniform(k, m), z);
            ck_assert_double_eq_tol(res.moment_pred[k * res.moments_max + m - 1],
                                    gr_bisect_moment_uniform(k, m),
                                    1e-14 * gr_bisect_moment_uniform(k, m));
            zmax = fmax(zmax, fabs(z));
        }
    }
    /* negative control: (1+m)^-(n+1) is many errors away at m = 2 */
    double err, v = gr_bisect_result_moment(&res, n, 2, &err);
    ck_assert_msg(fabs(v - pow(3.0, -(n + 1))) / err > 20.0, "cannot tell level n from n+1");
    ck_assert(zmax > 0.0);
    gr_bisect_result_free(&res);
}
END_TEST

START_TEST(test_zeta_uniform)
{
    gr_bisect_result res;
    run_uniform(8, 10000, 21, &res);
    for (int m = 1; m <= 4; m++) {
        const gr_bisect_zeta *z = &res.zeta[m - 1];
        double expect = log1p(m) / log(2.0);
        ck_assert_double_eq_tol(z->predicted, expect, 1e-12);
        ck_assert_msg(isfinite(z->err_fit) && isfinite(z->err_jackknife) && z->err_jackknife < 0.05,
                      "m = %d: errors %g (fit), %g (jackknife)", m, z->err_fit, z->err_jackknife);
        double tol = m == 1 ? 1e-10 : 4.0 * z->err_jackknife;
        ck_assert_msg(fabs(z->zeta - expect) < tol, "zeta_%d = %.5f +- %.5f vs ln(1+m)/ln 2 = %.5f",
                      m, z->zeta, z->err_jackknife, expect);
        if (m >= 2) { /* and it is distinguishable from the RFM's Table 3.1 value */
            ck_assert_msg(fabs(z->zeta - gr_bisect_zeta_rfm_table31(m, NULL)) >
                              4.0 * z->err_jackknife,
                          "zeta_%d cannot tell the process from the RFM", m);
        }
    }
    gr_bisect_result_free(&res);
}
END_TEST

/* ---------- the total length ---------- */

static double neumaier_sum(const double *x, size_t n)
{
    double s = 0.0, c = 0.0;
    for (size_t i = 0; i < n; i++) {
        double t = s + x[i];
        c += fabs(s) >= fabs(x[i]) ? (s - t) + x[i] : (x[i] - t) + s;
        s = t;
    }
    return s + c;
}

START_TEST(test_total_length)
{
    /* every level of one realisation: the partitions sum to 1 within one rounding per level, each
     * split's two halves to their parent within one rounding, and no partition is empty */
    const char *specs[] = {"uniform", "power:0.5", "power:0.95", "power:-3"};
    const int n = 16;
    double *x = malloc(sizeof(double) << n), *parent = malloc(sizeof(double) << n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 99);
    gr_error err = {0};
    for (size_t sp = 0; sp < sizeof specs / sizeof specs[0]; sp++) {
        gr_bisect_u0 u;
        ck_assert_int_eq(gr_bisect_u0_parse(&u, specs[sp], &err), GR_OK);
        x[0] = 1.0;
        for (int k = 0; k < n; k++) {
            size_t count = (size_t)1 << k;
            memcpy(parent, x, sizeof(double) * count);
            gr_bisect_level(&u, r, x, count);
            for (size_t i = 0; i < count; i++) {
                ck_assert_msg(x[2 * i] > 0.0 && x[2 * i + 1] > 0.0, "%s: empty partition",
                              specs[sp]);
                ck_assert_msg(fabs(x[2 * i] + x[2 * i + 1] - parent[i]) <= DBL_EPSILON * parent[i],
                              "%s level %d: %.17g + %.17g != %.17g", specs[sp], k + 1, x[2 * i],
                              x[2 * i + 1], parent[i]);
            }
            double total = neumaier_sum(x, 2 * count);
            ck_assert_msg(fabs(total - 1.0) <= (k + 2) * DBL_EPSILON, "%s level %d: sum - 1 = %g",
                          specs[sp], k + 1, total - 1.0);
        }
        gr_bisect_u0_free(&u);
    }
    /* and gr_bisect_run checks it on every realisation */
    gr_bisect_result res;
    run_uniform(10, 200, 4, &res);
    ck_assert_msg(res.sum_error_max <= 11 * DBL_EPSILON, "sum error %g", res.sum_error_max);
    ck_assert_double_eq(res.underflows, 0);
    gr_bisect_result_free(&res);
    free(x);
    free(parent);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_reproducible)
{
    gr_bisect_result a, b, c;
    run_uniform(5, 500, 77, &a);
    run_uniform(5, 500, 77, &b);
    run_uniform(5, 500, 78, &c);
    size_t n = (size_t)(a.levels + 1) * (size_t)a.moments_max;
    ck_assert_int_eq(memcmp(a.moment, b.moment, sizeof(double) * n), 0);
    ck_assert_int_eq(memcmp(a.pn.count, b.pn.count, sizeof(double) * (size_t)a.pn.nbins), 0);
    ck_assert_int_ne(memcmp(a.moment, c.moment, sizeof(double) * n), 0);
    gr_bisect_result_free(&a);
    gr_bisect_result_free(&b);
    gr_bisect_result_free(&c);
}
END_TEST

/* ---------- U_0: the power law and tables ---------- */

static double density_fn(double a, void *u) { return gr_bisect_u0_density(u, a); }

/* integral of U_0 over [lo, hi] by QAGS (independent of the library's quadrature) */
static double integrate_density(const gr_bisect_u0 *u, double lo, double hi)
{
    gsl_integration_workspace *w = gsl_integration_workspace_alloc(1000);
    gsl_function F = {density_fn, (void *)u};
    double total = 0.0, mid = 0.5 * (lo + hi);
    double cut[3] = {lo, lo < 0.5 && hi > 0.5 ? 0.5 : mid, hi};
    for (int i = 0; i < 2; i++) {
        double v, e;
        ck_assert_int_eq(
            gsl_integration_qags(&F, cut[i], cut[i + 1], 1e-13, 1e-11, 1000, w, &v, &e),
            GSL_SUCCESS);
        total += v;
    }
    gsl_integration_workspace_free(w);
    return total;
}

typedef struct weighted {
    const gr_bisect_u0 *u;
    int what, m;
} weighted;

static double weighted_fn(double a, void *p)
{
    const weighted *w = p;
    double g = w->what == 0 ? pow(a, w->m) : w->what == 1 ? -log(a) : log(a) * log(a);
    return gr_bisect_u0_density(w->u, a) * g;
}

/* integral of U_0(a) g(a): g = a^m (0), -ln a (1), ln^2 a (2), by QAGS on each half (it extrapolates
 * the integrable end-point singularities a^-A ln^2 a and (1-a)^-A); U_0 is symmetric, so this is the
 * symmetrised mean. */
static double integrate_weighted(const gr_bisect_u0 *u, int what, int m, double *tol)
{
    weighted w = {u, what, m};
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(2000);
    gsl_function F = {weighted_fn, &w};
    double v1, v2, e1, e2;
    int s1 = gsl_integration_qags(&F, 0.0, 0.5, 0.0, 1e-11, 2000, ws, &v1, &e1);
    int s2 = gsl_integration_qags(&F, 0.5, 1.0, 0.0, 1e-11, 2000, ws, &v2, &e2);
    ck_assert_msg((s1 == GSL_SUCCESS || (s1 == GSL_EROUND && e1 < 1e-6 * fabs(v1))) &&
                      (s2 == GSL_SUCCESS || (s2 == GSL_EROUND && e2 < 1e-6 * fabs(v2))),
                  "quadrature (A %g, what %d, m %d) failed: %d %d", u->A, what, m, s1, s2);
    gsl_integration_workspace_free(ws);
    *tol = 1e-9 + 10.0 * (e1 + e2) / fabs(v1 + v2); /* relative */
    return v1 + v2;
}

START_TEST(test_power_normalised)
{
    const double As[] = {-100.0, -5.0, -1.0, -0.5, 0.0, 0.3, 0.7, 0.9, 0.95};
    gr_error err = {0};
    for (size_t i = 0; i < sizeof As / sizeof As[0]; i++) {
        const double A = As[i];
        gr_bisect_u0 u;
        ck_assert_int_eq(gr_bisect_u0_power(&u, A, &err), GR_OK);
        ck_assert_double_eq_tol(integrate_density(&u, 0.0, 1.0), 1.0, 1e-9);
        ck_assert_double_eq_tol(gr_bisect_u0_density(&u, 0.3), gr_bisect_u0_density(&u, 0.7),
                                1e-12); /* 3.30 */
        ck_assert_double_eq(gr_bisect_u0_density(&u, -0.1), 0.0);
        ck_assert_double_eq(gr_bisect_u0_density(&u, 1.1), 0.0);
        /* mu_m = <(a^m + (1-a)^m)/2> and <-ln a>, <ln^2 a> against quadrature of the density */
        double tol, tol2;
        for (int m = 1; m <= 6; m++) {
            double mu, expect = integrate_weighted(&u, 0, m, &tol);
            ck_assert_int_eq(gr_bisect_u0_moment(&u, m, &mu, &err), GR_OK);
            ck_assert_msg(fabs(mu / expect - 1.0) < tol, "A = %g, m = %d: mu = %.15g vs %.15g", A,
                          m, mu, expect);
        }
        double mean, var;
        ck_assert_msg(gr_bisect_u0_log_stats(&u, &mean, &var, &err) == GR_OK, "A = %g: %s", A,
                      err.message);
        double l1 = integrate_weighted(&u, 1, 0, &tol), l2 = integrate_weighted(&u, 2, 0, &tol2);
        ck_assert_msg(fabs(mean / l1 - 1.0) < tol, "A = %g: <-ln a> = %.12g vs %.12g", A, mean, l1);
        ck_assert_msg(fabs(var - (l2 - l1 * l1)) < 1e-6 * var + tol2 * l2,
                      "A = %g: var = %.12g vs %.12g", A, var, l2 - l1 * l1);
    }
    /* A = 0 and A = -1 are the uniform density */
    gr_bisect_u0 u0, u1;
    gr_bisect_u0_power(&u0, 0.0, &err);
    gr_bisect_u0_power(&u1, -1.0, &err);
    for (double a = 0.05; a < 1.0; a += 0.1) {
        ck_assert_double_eq_tol(gr_bisect_u0_density(&u0, a), 1.0, 1e-15);
        ck_assert_double_eq_tol(gr_bisect_u0_density(&u1, a), 1.0, 1e-15);
    }
}
END_TEST

static double power_cdf(double a, void *user)
{
    /* CDF of (1-A)/2 (a^-A + (1-a)^-A): (a^(1-A) + 1 - (1-a)^(1-A)) / 2 */
    double A = *(const double *)user;
    return 0.5 * (pow(a, 1.0 - A) + 1.0 - pow(1.0 - a, 1.0 - A));
}

static double power_min_cdf(double f, void *user)
{
    /* CDF of f = min(a, 1 - a) under the symmetric U_0: 2 F(f), f <= 1/2 */
    return fmin(2.0 * power_cdf(f, user), 1.0);
}

START_TEST(test_power_sampler)
{
    /* the split the process uses: f = min(a, 1-a) against 2 F(f), the side a fair coin */
    const double As[] = {-4.0, -0.5, 0.4, 0.9, 0.95};
    const size_t n = 40000;
    double *f = malloc(sizeof(double) * n), *a = malloc(sizeof(double) * n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 17);
    gr_error err = {0};
    for (size_t i = 0; i < sizeof As / sizeof As[0]; i++) {
        double A = As[i];
        gr_bisect_u0 u;
        ck_assert_int_eq(gr_bisect_u0_power(&u, A, &err), GR_OK);
        size_t left = 0;
        for (size_t j = 0; j < n; j++) {
            bool small_left;
            f[j] = gr_bisect_u0_draw(&u, r, &small_left);
            ck_assert(f[j] > 0.0 && f[j] <= 0.5);
            left += small_left;
            a[j] = gr_bisect_u0_sample(&u, r);
            ck_assert(a[j] > 0.0 && a[j] <= 1.0);
        }
        double D = ks_statistic(f, n, power_min_cdf, &A);
        ck_assert_msg(ks_p_value(D, n) > 1e-3, "power:%g split: KS D = %g, p = %g", A, D,
                      ks_p_value(D, n));
        double z = ((double)left - 0.5 * n) / sqrt(0.25 * n);
        ck_assert_msg(fabs(z) < 4.5, "power:%g: the smaller piece went left %zu of %zu times", A,
                      left, n);
        if (A < 0.5) { /* a itself, where none of its mass is closer to 1 than 2^-53 */
            D = ks_statistic(a, n, power_cdf, &A);
            ck_assert_msg(ks_p_value(D, n) > 1e-3, "power:%g sampler: KS D = %g, p = %g", A, D,
                          ks_p_value(D, n));
        }
        double wrong = A + 0.5 * (1.0 - A); /* negative control */
        D = ks_statistic(f, n, power_min_cdf, &wrong);
        ck_assert_msg(ks_p_value(D, n) < 1e-4, "power:%g splits accepted as power:%g", A, wrong);
    }
    free(f);
    free(a);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_power_moments)
{
    /* the process with a power-law U_0: <x_n^m> = mu_m^n within sampling error */
    gr_bisect_settings s;
    gr_bisect_settings_default(&s);
    s.levels = 5;
    s.repetitions = 20000;
    s.seed = 8;
    gr_bisect_u0 u;
    gr_error err = {0};
    ck_assert_int_eq(gr_bisect_u0_parse(&u, "power:0.5", &err), GR_OK);
    gr_bisect_result res;
    ck_assert_int_eq(gr_bisect_run(&s, &u, &res, &err), GR_OK);
    for (int m = 2; m <= 5; m++) {
        double e, v = gr_bisect_result_moment(&res, 5, m, &e), expect = pow(res.mu[m], 5);
        ck_assert_msg(fabs(v - expect) < 4.5 * e, "m = %d: %g +- %g vs mu_m^5 = %g", m, v, e,
                      expect);
        /* and the power law is not the uniform process */
        ck_assert_msg(fabs(v - gr_bisect_moment_uniform(5, m)) > 10.0 * e,
                      "m = %d: power:0.5 looks uniform", m);
        ck_assert_msg(fabs(res.zeta[m - 1].zeta - res.zeta[m - 1].predicted) <
                          4.5 * res.zeta[m - 1].err_jackknife,
                      "zeta_%d = %g +- %g vs %g", m, res.zeta[m - 1].zeta,
                      res.zeta[m - 1].err_jackknife, res.zeta[m - 1].predicted);
    }
    gr_bisect_result_free(&res);
}
END_TEST

static double triangle_cdf(double a, void *user)
{
    (void)user;
    return a < 0.5 ? 2.0 * a * a : 1.0 - 2.0 * (1.0 - a) * (1.0 - a);
}

START_TEST(test_table_u0)
{
    make_tmp_dir();
    gr_error err = {0};
    /* a flat table is the uniform process */
    gr_bisect_u0 u;
    ck_assert_int_eq(
        gr_bisect_u0_parse(&u, write_file("flat.csv", "# flat\na,U\n0,3\n0.5,3\n1,3\n"), &err),
        GR_OK);
    ck_assert_double_eq_tol(u.table_norm, 3.0, 1e-15);
    ck_assert_double_eq_tol(u.asymmetry, 0.0, 1e-15);
    for (int m = 1; m <= 6; m++) {
        double mu;
        ck_assert_int_eq(gr_bisect_u0_moment(&u, m, &mu, &err), GR_OK);
        ck_assert_double_eq_tol(mu, 1.0 / (1.0 + m), 1e-10);
    }
    gr_bisect_u0_free(&u);
    /* an unnormalised hump (no header, spaces): the triangle density, sampled by exact inversion */
    ck_assert_int_eq(gr_bisect_u0_parse(&u, write_file("hump.csv", "0 0\n0.5 1\n1 0\n"), &err),
                     GR_OK);
    ck_assert_double_eq_tol(gr_bisect_u0_density(&u, 0.25), 1.0, 1e-14); /* peak 2 at a = 1/2 */
    ck_assert_double_eq_tol(integrate_density(&u, 0.0, 1.0), 1.0, 1e-10);
    double mu2;
    ck_assert_int_eq(gr_bisect_u0_moment(&u, 2.0, &mu2, &err), GR_OK);
    ck_assert_double_eq_tol(mu2, 7.0 / 24.0, 1e-10); /* <a^2> = 7/24 for the symmetric triangle */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 23);
    const size_t n = 40000;
    double *a = malloc(sizeof(double) * n);
    for (size_t j = 0; j < n; j++) {
        a[j] = gr_bisect_u0_sample(&u, r);
    }
    double D = ks_statistic(a, n, triangle_cdf, NULL);
    ck_assert_msg(ks_p_value(D, n) > 1e-3, "triangle sampler: D = %g", D);
    double A = 0.0;
    D = ks_statistic(a, n, power_cdf, &A); /* negative control: not uniform */
    ck_assert_msg(ks_p_value(D, n) < 1e-6, "triangle samples accepted as uniform");
    free(a);
    gsl_rng_free(r);
    gr_bisect_u0_free(&u);
    /* an asymmetric table is accepted and its asymmetry reported */
    ck_assert_int_eq(gr_bisect_u0_parse(&u, write_file("ramp.csv", "a,U\n0,0\n1,2\n"), &err),
                     GR_OK);
    ck_assert_double_eq_tol(u.asymmetry, 1.0, 1e-12);
    gr_bisect_u0_free(&u);
    remove_tree(tmp_dir);
}
END_TEST

/* ---------- the collapse (3.39-3.40) ---------- */

START_TEST(test_collapse)
{
    /* (3.36) itself, written as an RFM table at N = 2^7, collapses onto -ln R at every R */
    make_tmp_dir();
    const int n = 7;
    char text[40000];
    int len = snprintf(text, sizeof text,
                       "# exact P_7 as a G_1 table\n# system: N = 128, eps = 0.1\nR,G\n");
    for (int i = 1; i < 100; i++) {
        double R = i / 100.0;
        len += snprintf(text + len, sizeof text - (size_t)len, "%.17g,%.17g\n", R,
                        gr_bisect_pn_uniform(n, R));
    }
    gr_error err = {0};
    gr_bisect_g1 g;
    ck_assert_msg(gr_bisect_g1_load(&g, write_file("g1.csv", text), &err) == GR_OK, "%s",
                  err.message);
    ck_assert_double_eq(g.N, 128.0);
    ck_assert_ptr_null(g.G_err);
    double G0;
    ck_assert_int_eq(gr_bisect_g1_at(&g, 0.7, &G0, &err), GR_OK);
    ck_assert_double_eq_tol(G0, gr_bisect_pn_uniform(n, 0.7), 1e-15);
    double A = gr_bisect_collapse_factor(log2(g.N), 0.7, G0);
    ck_assert_double_eq_tol(A, pow(gsl_sf_fact(n - 1), 1.0 / (n - 1)), 1e-12); /* A_N of (3.36) */
    for (int i = 0; i < g.n_points; i++) {
        ck_assert_double_eq_tol(gr_bisect_collapse_map(log2(g.N), A, g.G[i]), -log(g.R[i]), 1e-12);
    }
    gr_bisect_g1_free(&g);
    /* the same table in granule's histogram format at L' = 2 (R doubled, G halved) reads identically */
    len = snprintf(text, sizeof text,
                   "# N = 128, reduced_length = 2\nR_lo,R_hi,R,count,density,density_error\n");
    for (int i = 1; i < 100; i++) {
        double R = i / 100.0;
        len +=
            snprintf(text + len, sizeof text - (size_t)len, "0,0,%.17g,10,%.17g,%.17g\n", 2.0 * R,
                     0.5 * gr_bisect_pn_uniform(n, R), 0.05 * gr_bisect_pn_uniform(n, R));
    }
    ck_assert_msg(gr_bisect_g1_load(&g, write_file("g1h.csv", text), &err) == GR_OK, "%s",
                  err.message);
    ck_assert_ptr_nonnull(g.G_err);
    ck_assert_double_eq(g.reduced_length, 2.0);
    ck_assert_int_eq(gr_bisect_g1_at(&g, 0.7, &G0, &err), GR_OK);
    ck_assert_double_eq_tol(G0, gr_bisect_pn_uniform(n, 0.7), 1e-14);
    ck_assert_double_eq_tol(g.G_err[10], 0.1 * g.G[10], 1e-15);
    gr_bisect_g1_free(&g);
    /* a run folder of the gaps observable: gaps.csv (every h, linear and log bins, R in m) and N, L'
     * in summary.json; the folder and the file both read as the h = 1 log-binned rows at L' = 1 */
    char run[200];
    snprintf(run, sizeof run, "%s/run", tmp_dir);
    ck_assert_int_eq(mkdir(run, 0777), 0);
    write_file("run/summary.json",
               "{\"status\": \"completed\", \"gaps\": {\"N\": 128, \"reduced_length\": 0.5}}\n");
    len = snprintf(
        text, sizeof text,
        "# granule: G_h(R;N) (3.21, 3.24); x = R N / (h L')\n# scene s.ini, seed 1\n"
        "h,binning,R_lo,R_hi,R,count,density,density_error,neg_ln_R,x,density_x,density_x_error\n");
    for (int h = 1; h <= 2; h++) {
        for (int b = 0; b < 2; b++) {
            for (int i = 1; i < 60; i++) {
                double R = b ? pow(10.0, -6.0 + i / 10.0) : i / 60.0; /* reduced */
                double G = h == 1 && b ? gr_bisect_pn_uniform(n, R) : 1.0;
                len += snprintf(text + len, sizeof text - (size_t)len,
                                "%d,%s,0,0,%.17g,5,%.17g,%.17g,0,0,0,0\n", h, b ? "log" : "lin",
                                0.5 * R, 2.0 * G, 0.2 * G);
            }
        }
    }
    write_file("run/gaps.csv", text);
    for (int k = 0; k < 2; k++) {
        char path[300];
        snprintf(path, sizeof path, "%s%s", run, k ? "/gaps.csv" : "");
        ck_assert_msg(gr_bisect_g1_load(&g, path, &err) == GR_OK, "%s: %s", path, err.message);
        ck_assert_int_eq(g.n_points, 59);
        ck_assert_double_eq(g.N, 128.0);
        ck_assert_double_eq(g.reduced_length, 0.5);
        ck_assert_double_eq_tol(g.R[0], 1e-6 * pow(10.0, 0.1), 1e-20);
        ck_assert_int_eq(gr_bisect_g1_at(&g, 0.7, &G0, &err), GR_OK);
        /* between log bins 0.63 and 0.79, exact for (3.36) (linear interpolation would be 2.7 times off) */
        ck_assert_double_eq_tol(G0 / gr_bisect_pn_uniform(n, 0.7), 1.0, 1e-12);
        ck_assert_double_eq_tol(g.G[30], gr_bisect_pn_uniform(n, g.R[30]), 1e-12 * g.G[30]);
        gr_bisect_g1_free(&g);
    }
    remove_tree(tmp_dir);
}
END_TEST

/* ---------- outputs ---------- */

static char *slurp(const char *dir, const char *name)
{
    char path[300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "missing %s", path);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    rewind(f);
    char *text = malloc((size_t)size + 1);
    ck_assert_uint_eq(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = 0;
    fclose(f);
    return text;
}

START_TEST(test_write)
{
    make_tmp_dir();
    gr_bisect_settings s;
    gr_bisect_settings_default(&s);
    s.levels = 4;
    s.repetitions = 300;
    gr_bisect_u0 u;
    gr_bisect_u0_uniform(&u);
    gr_error err = {0};
    gr_bisect_result res;
    ck_assert_int_eq(gr_bisect_run(&s, &u, &res, &err), GR_OK);
    char text[4000];
    int len = snprintf(text, sizeof text, "# N = 16\nR,G,G_err\n");
    for (int i = 1; i < 50; i++) {
        len += snprintf(text + len, sizeof text - (size_t)len, "%g,%g,0.01\n", i / 50.0,
                        gr_bisect_pn_uniform(4, i / 50.0));
    }
    gr_bisect_g1 g;
    ck_assert_int_eq(gr_bisect_g1_load(&g, write_file("g1.csv", text), &err), GR_OK);
    char out[200];
    snprintf(out, sizeof out, "%s/out", tmp_dir);
    ck_assert_int_eq(gr_output_dir_prepare(out, GR_OUTPUT_RESULT, false, &err), GR_OK);
    gr_bisect_output o = {.g1 = &g, .n_g1 = 1, .plots = false};
    ck_assert_msg(gr_bisect_write(out, &s, &u, &res, &o, &err) == GR_OK, "%s", err.message);
    const char *files[] = {"pn.csv", "moments.csv", "zeta.csv", "collapse.csv"};
    for (size_t i = 0; i < 4; i++) {
        char *t = slurp(out, files[i]);
        ck_assert_msg(t[0] != '#' && strchr(t, ',') && strchr(t, ',') < strchr(t, '\n'),
                      "%s: not a plain CSV", files[i]);
        free(t);
        char meta[64];
        snprintf(meta, sizeof meta, "%.*s.meta.json", (int)(strlen(files[i]) - 4), files[i]);
        t = slurp(out, meta);
        ck_assert_msg(strstr(t, "granule bisect"), "%s lacks the notes", meta);
        free(t);
    }
    char *t = slurp(out, "summary.json");
    cJSON *j = cJSON_Parse(t);
    free(t);
    ck_assert_ptr_nonnull(j);
    ck_assert_str_eq(cJSON_GetObjectItem(j, "status")->valuestring, "completed");
    ck_assert_int_eq(cJSON_GetObjectItem(j, "levels")->valueint, 4);
    ck_assert_int_eq(cJSON_GetArraySize(cJSON_GetObjectItem(j, "zeta")), s.moments_max);
    cJSON *g1 =
        cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "collapse"), "g1"), 0);
    ck_assert_double_eq(cJSON_GetObjectItem(g1, "N")->valuedouble, 16.0);
    cJSON_Delete(j);
    /* a second run into the same folder is refused unless forced */
    ck_assert_int_eq(gr_output_dir_prepare(out, GR_OUTPUT_RESULT, false, &err), GR_EINVAL);
    /* an anchor outside the G_1 table is refused before anything is written */
    s.anchor = 0.99;
    char out2[200];
    snprintf(out2, sizeof out2, "%s/out2", tmp_dir);
    ck_assert_int_eq(gr_output_dir_prepare(out2, GR_OUTPUT_RESULT, false, &err), GR_OK);
    ck_assert_int_eq(gr_bisect_write(out2, &s, &u, &res, &o, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "R = 0.99") != NULL, "%s", err.message);
    char path[300];
    snprintf(path, sizeof path, "%s/pn.csv", out2);
    ck_assert_int_ne(access(path, F_OK), 0);
    gr_bisect_g1_free(&g);
    gr_bisect_result_free(&res);
    remove_tree(tmp_dir);
}
END_TEST

/* ---------- bad input ---------- */

START_TEST(test_bad_u0)
{
    make_tmp_dir();
    gr_bisect_u0 u;
    gr_error err = {0};
    const char *bad_specs[] = {"",           "power:",     "power:abc", "power:1",
                               "power:0.96", "power:-101", "power:nan", "power:0.5x"};
    for (size_t i = 0; i < sizeof bad_specs / sizeof bad_specs[0]; i++) {
        ck_assert_msg(gr_bisect_u0_parse(&u, bad_specs[i], &err) == GR_EINVAL, "accepted '%s'",
                      bad_specs[i]);
        ck_assert_msg(err.message[0] && !strchr(err.message, '\n'), "message for '%s'",
                      bad_specs[i]);
    }
    snprintf(err.message, sizeof err.message, "%s", "");
    char missing[200];
    snprintf(missing, sizeof missing, "%s/no-such-file.csv", tmp_dir);
    ck_assert_int_eq(gr_bisect_u0_parse(&u, missing, &err), GR_EIO);
    ck_assert_msg(strstr(err.message, "no-such-file.csv") != NULL, "%s", err.message);
    const struct {
        const char *text, *expect;
    } tables[] = {
        {"a,U\n0,1\n", "at least 2"},
        {"a,U\n0,1\n0.5,1\n0.4,1\n1,1\n", "does not increase"},
        {"a,U\n0,1\n0.5,-1\n1,1\n", "not a density"},
        {"a,U\n-0.1,1\n1,1\n", "outside [0, 1]"},
        {"a,U\n0,1\n1.5,1\n", "outside [0, 1]"},
        {"a,U\n0,0\n1,0\n", "integrates to 0"},
        {"a,U\n0,1\n0.5,x\n1,1\n", ":3:"},
        {"a,U\n0,1\n0.5\n1,1\n", "columns"},
        {"a,U\n0,1\n0.5,inf\n1,1\n", "finite"},
        {"# nothing\n", "at least 2"},
    };
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; i++) {
        const char *path = write_file("bad.csv", tables[i].text);
        ck_assert_msg(gr_bisect_u0_parse(&u, path, &err) == GR_EINVAL, "accepted table %zu", i);
        ck_assert_msg(strstr(err.message, tables[i].expect) && strstr(err.message, "bad.csv"),
                      "table %zu: '%s' lacks '%s' or the path", i, err.message, tables[i].expect);
    }
    remove_tree(tmp_dir);
}
END_TEST

START_TEST(test_bad_settings)
{
    gr_bisect_u0 u;
    gr_bisect_u0_uniform(&u);
    gr_error err = {0};
    gr_bisect_result res;
    for (int i = 0; i < 14; i++) {
        gr_bisect_settings s;
        gr_bisect_settings_default(&s);
        switch (i) {
        case 0: s.levels = 0; break;
        case 1: s.levels = GR_BISECT_MAX_LEVELS + 1; break;
        case 2: s.repetitions = 1; break;
        case 3: s.repetitions = -5; break;
        case 4: s.moments_max = 0; break;
        case 5: s.moments_max = GR_BISECT_MAX_MOMENTS + 1; break;
        case 6: s.bins_per_decade = 0; break;
        case 7: s.fit_level_min = s.levels; break;
        case 8: s.fit_level_min = 0; break;
        case 9: s.jackknife_groups = 1; break;
        case 10: s.anchor = 1.0; break;
        case 11: s.anchor = 0.0; break;
        case 12: s.anchor = NAN; break;
        default: s.anchor_min_count = 0.0; break;
        }
        ck_assert_msg(gr_bisect_run(&s, &u, &res, &err) == GR_EINVAL, "case %d accepted", i);
        ck_assert_ptr_null(res.moment);
    }
    /* extreme but legal: one level (P_1 = 1, no zeta fit), two realisations */
    gr_bisect_settings s;
    gr_bisect_settings_default(&s);
    s.levels = 1;
    s.repetitions = 2;
    ck_assert_msg(gr_bisect_run(&s, &u, &res, &err) == GR_OK, "%s", err.message);
    ck_assert(isnan(res.zeta[1].zeta));
    ck_assert_double_eq_tol(gr_bisect_result_moment(&res, 1, 1, NULL), 0.5, 1e-16);
    gr_bisect_result_free(&res);
    /* other bad arguments */
    double mu;
    ck_assert_int_eq(gr_bisect_u0_moment(&u, -1.0, &mu, &err), GR_EINVAL);
    double x[4];
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    ck_assert_int_eq(gr_bisect_realise(&u, -1, r, x, &err), GR_EINVAL);
    gsl_rng_free(r);
    ck_assert(isnan(gr_bisect_result_moment(&res, 0, 1, NULL)));
}
END_TEST

START_TEST(test_bad_g1)
{
    make_tmp_dir();
    gr_bisect_g1 g;
    gr_error err = {0};
    const struct {
        const char *text, *expect;
    } tables[] = {
        {"R,G\n0.1,1\n0.7,1\n", "N = <particles>"},
        {"# N = 2\nR,G\n0.1,1\n0.7,1\n", "N > 2"},
        {"# N_t = 100\nR,G\n0.1,1\n0.7,1\n", "N = <particles>"},
        {"# N = 64, reduced_length = -1\nR,G\n0.1,1\n0.7,1\n", "reduced_length"},
        {"# N = 64\nR,G\n0.5,1\n0.4,1\n", "increase"},
        {"# N = 64\nR,G\n0.1,-1\n0.7,1\n", ">= 0"},
        {"# N = 64\nR,G\n0.1,1\n", "at least 2"},
    };
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; i++) {
        const char *path = write_file("g1.csv", tables[i].text);
        ck_assert_msg(gr_bisect_g1_load(&g, path, &err) == GR_EINVAL, "accepted G_1 table %zu", i);
        ck_assert_msg(strstr(err.message, tables[i].expect) != NULL, "table %zu: '%s' lacks '%s'",
                      i, err.message, tables[i].expect);
        ck_assert_ptr_null(g.R);
    }
    ck_assert_int_eq(
        gr_bisect_g1_load(&g, write_file("g1.csv", "# N = 64\nR,G\n0.1,1\n0.5,1\n"), &err), GR_OK);
    double G0;
    ck_assert_int_eq(gr_bisect_g1_at(&g, 0.7, &G0, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "[0.1, 0.5]") != NULL, "%s", err.message);
    gr_bisect_g1_free(&g);
    remove_tree(tmp_dir);
}
END_TEST

static Suite *bisect_suite(void)
{
    Suite *s = suite_create("bisect");
    TCase *p = tcase_create("physics");
    tcase_set_timeout(p, 120);
    tcase_add_test(p, test_pn_chi_square);
    tcase_add_test(p, test_pn_ks);
    tcase_add_test(p, test_pn_closed_form);
    tcase_add_test(p, test_moments_uniform);
    tcase_add_test(p, test_zeta_uniform);
    tcase_add_test(p, test_total_length);
    tcase_add_test(p, test_reproducible);
    suite_add_tcase(s, p);
    TCase *u = tcase_create("u0");
    tcase_set_timeout(u, 120);
    tcase_add_test(u, test_power_normalised);
    tcase_add_test(u, test_power_sampler);
    tcase_add_test(u, test_power_moments);
    tcase_add_test(u, test_table_u0);
    suite_add_tcase(s, u);
    TCase *c = tcase_create("collapse_and_outputs");
    tcase_set_timeout(c, 120);
    tcase_add_test(c, test_collapse);
    tcase_add_test(c, test_write);
    suite_add_tcase(s, c);
    TCase *b = tcase_create("bad_input");
    tcase_add_test(b, test_bad_u0);
    tcase_add_test(b, test_bad_settings);
    tcase_add_test(b, test_bad_g1);
    suite_add_tcase(s, b);
    return s;
}

int main(void)
{
    gsl_set_error_handler_off();
    return gr_test_run(bisect_suite());
}
