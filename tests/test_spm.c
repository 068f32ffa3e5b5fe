/* The Single Particle Model (thesis sec. 5.2-5.3): exact free flight, the random-acceleration
 * bridge, Q(v,l) and its collapse under v / l^(1/3), the free-path distributions, the full SPM's
 * time weighting, the asymptotic prediction (5.27-5.31), the RFM snapshot reader, the tail
 * comparison, reproducibility and refusals. Fixed seeds throughout; GRANULE_TEST_QUICK=1 shrinks
 * the sample sizes (for sanitizer builds). */
#include <check.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_gamma.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/spm.h"
#include "granule/spm_study.h"
#include "check_main.h"

static bool quick(void)
{
    const char *q = getenv("GRANULE_TEST_QUICK");
    return q && *q && strcmp(q, "0") != 0;
}

static const double M = GR_SPM_MASS_DEFAULT, Dn = GR_SPM_D_DEFAULT;

/* ------------------------------------------------------------------------------------------- */

START_TEST(test_free_flight_moments)
{
    /* From rest, over t: <v^2> = 2 D t / M^2, Var x = 2 D t^3 / (3 M^2), Cov(x, v) = D t^2 / M^2
     * (physics notes sec. 1.2). Once as one interval and once composed of 10 (exactness: the
     * sampler composes without error), with z-scores of the sample moments. */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 2024);
    const int n = quick() ? 40000 : 200000;
    const double t = 0.01, sigma = sqrt(2.0 * Dn) / M;
    const double vv = 2.0 * Dn * t / (M * M), xx = 2.0 * Dn * t * t * t / (3.0 * M * M),
                 xv = Dn * t * t / (M * M);
    for (int pieces = 1; pieces <= 10; pieces += 9) {
        double s_v2 = 0.0, s_x2 = 0.0, s_xv = 0.0, s_x = 0.0, s_v = 0.0;
        for (int i = 0; i < n; i++) {
            double x = 0.0, v = 0.0;
            for (int k = 0; k < pieces; k++) {
                double g1 = gsl_ran_gaussian_ziggurat(r, 1.0),
                       g2 = gsl_ran_gaussian_ziggurat(r, 1.0);
                gr_spm_free_flight(x, v, t / pieces, sigma, g1, g2, &x, &v);
            }
            s_v2 += v * v;
            s_x2 += x * x;
            s_xv += x * v;
            s_x += x;
            s_v += v;
        }
        double mv2 = s_v2 / n, mx2 = s_x2 / n, mxv = s_xv / n;
        double z_v2 = (mv2 - vv) / (sqrt(2.0 / n) * vv);
        double z_x2 = (mx2 - xx) / (sqrt(2.0 / n) * xx);
        double z_xv = (mxv - xv) / sqrt((xx * vv + xv * xv) / n);
        double z_x = (s_x / n) / sqrt(xx / n), z_v = (s_v / n) / sqrt(vv / n);
        ck_assert_msg(fabs(z_v2) < 5.0, "%d pieces: <v^2> = %g, expected %g (z = %.2f)", pieces,
                      mv2, vv, z_v2);
        ck_assert_msg(fabs(z_x2) < 5.0, "%d pieces: <x^2> = %g, expected %g (z = %.2f)", pieces,
                      mx2, xx, z_x2);
        ck_assert_msg(fabs(z_xv) < 5.0, "%d pieces: <xv> = %g, expected %g (z = %.2f)", pieces, mxv,
                      xv, z_xv);
        ck_assert_msg(fabs(z_x) < 5.0 && fabs(z_v) < 5.0, "%d pieces: means z = %.2f, %.2f", pieces,
                      z_x, z_v);
    }
    /* the deterministic part: no noise, x1 = x0 + v0 tau */
    double x1, v1;
    gr_spm_free_flight(0.25, -1.5, 0.1, sigma, 0.0, 0.0, &x1, &v1);
    ck_assert(fabs(x1 - (0.25 - 0.15)) < 1e-15 && v1 == -1.5);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_bridge_midpoint)
{
    /* Two exact half-steps give (x_m, v_m) and the end; given the ends the midpoint must scatter
     * about the cubic Hermite interpolant with variances sigma^2 h^3/24 and sigma^2 h/8,
     * uncorrelated with the ends. */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 77);
    const int n = quick() ? 40000 : 200000;
    const double h = 0.3, sigma = 1.7;
    double sx2 = 0.0, sv2 = 0.0, sxe = 0.0, sve = 0.0, se2 = 0.0;
    for (int i = 0; i < n; i++) {
        double x0 = gsl_ran_gaussian(r, 1.0), v0 = gsl_ran_gaussian(r, 1.0), xm, vm, x1, v1;
        gr_spm_free_flight(x0, v0, h, sigma, gsl_ran_gaussian(r, 1.0), gsl_ran_gaussian(r, 1.0),
                           &xm, &vm);
        gr_spm_free_flight(xm, vm, h, sigma, gsl_ran_gaussian(r, 1.0), gsl_ran_gaussian(r, 1.0),
                           &x1, &v1);
        double mx, mv;
        gr_spm_bridge_midpoint(x0, v0, x1, v1, h, sigma, 0.0, 0.0, &mx, &mv);
        double rx = xm - mx, rv = vm - mv, e = v1 - v0;
        sx2 += rx * rx;
        sv2 += rv * rv;
        sxe += rx * e;
        sve += rv * e;
        se2 += e * e;
    }
    double ex = sigma * sigma * h * h * h / 24.0, ev = sigma * sigma * h / 8.0;
    ck_assert_msg(fabs(sx2 / n / ex - 1.0) < 5.0 * sqrt(2.0 / n), "Var x_m = %g, expected %g",
                  sx2 / n, ex);
    ck_assert_msg(fabs(sv2 / n / ev - 1.0) < 5.0 * sqrt(2.0 / n), "Var v_m = %g, expected %g",
                  sv2 / n, ev);
    double ee = se2 / n;
    ck_assert_msg(fabs(sxe / n) < 5.0 * sqrt(ex * ee / n),
                  "residual x correlates with the ends: %g", sxe / n);
    ck_assert_msg(fabs(sve / n) < 5.0 * sqrt(ev * ee / n),
                  "residual v correlates with the ends: %g", sve / n);
    /* the sampled midpoint has the right spread too */
    double xm, vm;
    gr_spm_bridge_midpoint(0.0, 0.0, 0.0, 0.0, h, sigma, 1.0, 0.0, &xm, &vm);
    ck_assert(fabs(vm - sigma * sqrt(h / 8.0)) < 1e-15 && xm == 0.0);
    gsl_rng_free(r);
}
END_TEST

/* ------------------------------------------------------------------------------------------- */

static void circle(gr_spm_settings *s, double l, int index, gr_spm_q *q)
{
    gr_error err = {0};
    ck_assert_msg(gr_spm_circle(s, l, index, 45, 4.5, q, &err) == 0, "%s", err.message);
}

START_TEST(test_constants_convention)
{
    /* c and c' in the thesis' convention, <v_x^2> = c (D l/M^2)^(2/3) and <T_fp> = c' (l^2 M^2/D)^(1/3),
     * checked in SI units against what they summarise: <v_x^2> from the time-sampled velocity
     * histogram Q(v, l) (second moment of the signed component, m^2/s^2) and the mean
     * first-passage time in seconds. A wrong power of 2 in either conversion is off by >= 26%. */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = quick() ? 2000 : 6000;
    s.seed = 11;
    const double l = 0.02;
    gr_spm_q q;
    circle(&s, l, 0, &q);
    gr_spm_constants c;
    gr_spm_constants_of(&q.stats, &c);
    double v2 = 0.0; /* Q is the density of the signed scaled component: 2 int_0^wmax Q w^2 dw */
    const gr_histogram *h = &q.q.all;
    for (int i = 0; i < h->nbins; i++) {
        double w = gr_histogram_center(h, i),
               dw = gr_histogram_upper(h, i) - gr_histogram_lower(h, i);
        v2 += 2.0 * gr_spm_dist_density(&q.q, i) * w * w * dw;
    }
    v2 *= q.u * q.u;
    const double v2_c = c.c * pow(s.D * l / (s.mass * s.mass), 2.0 / 3.0);
    ck_assert_msg(fabs(v2_c / v2 - 1.0) < 0.03, "<v_x^2> = %g from c, %g from Q", v2_c, v2);
    const double T = q.stats.exit_time_mean * q.t_scale,
                 T_c = c.c_prime * cbrt(l * l * s.mass * s.mass / s.D);
    ck_assert_msg(fabs(T_c / T - 1.0) < 1e-12, "<T_fp> = %g s from c', %g s measured", T_c, T);
    ck_assert(c.c_err > 0.0 && c.c_err < 0.05 * c.c && c.c_prime_err > 0.0 &&
              c.c_prime_err < 0.05 * c.c_prime);
    /* pooling: an inverse-variance mean lies between its inputs with a smaller error */
    gr_spm_constants per[2] = {{1.0, 0.1, 2.0, 0.2}, {1.2, 0.1, 2.4, 0.1}}, pooled;
    gr_spm_constants_pool(per, 2, &pooled);
    ck_assert(fabs(pooled.c - 1.1) < 1e-12 && fabs(pooled.c_err - 0.1 / sqrt(2.0)) < 1e-12);
    ck_assert(fabs(pooled.c_prime - (2.0 / 0.04 + 2.4 / 0.01) / (1 / 0.04 + 1 / 0.01)) < 1e-12);
    gr_spm_q_free(&q);
}
END_TEST

START_TEST(test_w2_error_calibrated)
{
    /* The error bar of <w^2> (ratio estimator over independent walks) against the scatter of
     * <w^2> over independent seeds: their ratio must be 1 within the sampling error of a
     * standard deviation from K seeds (relative 1/sqrt(2(K-1)) = 0.16 for K = 20; bounds ~3 sigma). */
    const int K = 20;
    double m[20], e_mean = 0.0, mean = 0.0, var = 0.0;
    for (int k = 0; k < K; k++) {
        gr_spm_settings s;
        gr_spm_settings_default(&s);
        s.walks = quick() ? 600 : 1500;
        s.seed = 100 + (uint64_t)k;
        gr_spm_q q;
        circle(&s, 0.01, 0, &q);
        m[k] = q.stats.w2_time_mean;
        e_mean += q.stats.w2_time_err / K;
        mean += m[k] / K;
        gr_spm_q_free(&q);
    }
    for (int k = 0; k < K; k++) {
        var += (m[k] - mean) * (m[k] - mean) / (K - 1);
    }
    const double ratio = sqrt(var) / e_mean;
    ck_assert_msg(ratio > 0.55 && ratio < 1.5, "scatter of <w^2> over seeds / its error bar = %g",
                  ratio);
}
END_TEST

START_TEST(test_study_defaults)
{
    /* the library call behind `granule spm predict` / `full`: no free paths given -> the thesis'
     * D_f = 1.63 (and says so); D_f with a table -> refused; the same prediction as gr_spm_predict */
    gr_spm_predict_params p;
    gr_spm_predict_params_default(&p);
    gr_spm_predict_report r;
    gr_error err = {0};
    ck_assert_msg(gr_spm_predict_prepare(&p, &r, &err) == 0, "%s", err.message);
    ck_assert(r.df_defaulted && p.df == GR_SPM_THESIS_DF && p.C == GR_SPM_THESIS_C);
    ck_assert(fabs(r.p.alpha - 6.0 * 0.63 / (3.0 * 1.63 - 1.0)) < 1e-12);
    gr_spm_predict_params_default(&p);
    p.df = 1.5;
    ck_assert(gr_spm_predict_prepare(&p, &r, &err) == 0 && !r.df_defaulted);
    p.pl_path = "no-such-file.csv";
    ck_assert_int_eq(gr_spm_predict_prepare(&p, &r, &err), GR_EINVAL);
    ck_assert(strstr(err.message, "not both") != NULL);
    gr_spm_full_params f;
    gr_spm_full_params_default(&f);
    gr_spm_full_report fr;
    ck_assert_msg(gr_spm_full_prepare(&f, &fr, &err) == 0, "%s", err.message);
    ck_assert(fr.df_defaulted && f.df == GR_SPM_THESIS_DF && fr.have_pred && f.vmax > 0.0);
    gr_spm_full_report_free(&fr);
}
END_TEST

START_TEST(test_collapse)
{
    /* Q(v, l) for two radii a factor 8 apart (u_l a factor 2), with one fixed time step dt in
     * seconds (so the walks are not the same walks in scaled units): u_l Q collapses onto one
     * curve within errors (permutation p-value of the chi-square between the histograms); a 1D
     * Q compared with the 2D one must fail the same test. */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = quick() ? 3000 : 8000;
    s.batches = 20;
    s.seed = 5;
    s.dt = 0.004 *
           gr_spm_time_scale(&s, 0.005); /* 0.004 t_l for the small radius, 0.001 for the large */
    gr_spm_q a, b, c;
    circle(&s, 0.005, 0, &a);
    circle(&s, 0.04, 1, &b);
    ck_assert(fabs(b.u / a.u - 2.0) < 1e-12);
    ck_assert(fabs(b.tau / a.tau - 0.25) < 1e-12);
    gr_spm_collapse col;
    gr_error err = {0};
    ck_assert_msg(gr_spm_q_collapse(&a, &b, 20.0, 500, &col, &err) == 0, "%s", err.message);
    ck_assert_msg(col.dof >= 25, "only %d bins compared", col.dof);
    ck_assert_msg(col.p_value > 0.002,
                  "no collapse: chi2/dof = %.3f over %d bins, permutation p = %.4f", col.chi2_red,
                  col.dof, col.p_value);
    /* the mean first-passage time in units of t_l agrees too */
    double dT = a.stats.exit_time_mean - b.stats.exit_time_mean;
    ck_assert_msg(fabs(dT) < 4.0 * hypot(a.stats.exit_time_err, b.stats.exit_time_err),
                  "exit times %g, %g t_l", a.stats.exit_time_mean, b.stats.exit_time_mean);
    /* Ito: E|v_T|^2 = dim E[T] (units of the walk), up to the detection of the exit */
    ck_assert_msg(fabs(a.stats.exit_speed2_mean / a.stats.exit_time_mean / 2.0 - 1.0) < 0.05,
                  "E|v_T|^2 / E T = %g", a.stats.exit_speed2_mean / a.stats.exit_time_mean);
    /* negative control: a different shape (1D) is told apart */
    gr_spm_settings s1 = s;
    s1.dim = 1;
    circle(&s1, 0.005, 2, &c);
    ck_assert_msg(gr_spm_q_collapse(&a, &c, 20.0, 500, &col, &err) == 0, "%s", err.message);
    ck_assert_msg(col.p_value < 0.01 && col.chi2_red > 3.0,
                  "1D and 2D Q not told apart: chi2/dof %.3f, p %.4f", col.chi2_red, col.p_value);
    gr_spm_q_free(&a);
    gr_spm_q_free(&b);
    gr_spm_q_free(&c);
}
END_TEST

/* One walk in physical units, written independently of the library's scaled walker: exact free
 * flight (gr_spm_free_flight) with sigma = sqrt(2D)/M at a fixed dt, stopped at the first sample
 * outside the disc; every sample (weight 1: uniform in time) of |v_x|, |v_y| goes to h[j] after
 * division by scale[j]. */
static void physical_walk(gsl_rng *r, double l, double dt, const double scale[3],
                          gr_histogram *h[3])
{
    const double sigma = sqrt(2.0 * Dn) / M;
    double x[2] = {0.0, 0.0}, v[2] = {0.0, 0.0};
    for (;;) {
        for (int j = 0; j < 3; j++) {
            gr_histogram_add(h[j], fabs(v[0]) / scale[j], 1.0);
            gr_histogram_add(h[j], fabs(v[1]) / scale[j], 1.0);
        }
        for (int c = 0; c < 2; c++) {
            double g1 = gsl_ran_gaussian_ziggurat(r, 1.0), g2 = gsl_ran_gaussian_ziggurat(r, 1.0);
            gr_spm_free_flight(x[c], v[c], dt, sigma, g1, g2, &x[c], &v[c]);
        }
        if (x[0] * x[0] + x[1] * x[1] >= l * l) {
            return;
        }
    }
}

/* Q of radius l in physical units, histogrammed in v / (k l^(1/3) f[j]), k = (2D/M^2)^(1/3) */
static void physical_q(gsl_rng *r, double l, const double f[3], int walks, int batches,
                       gr_spm_q q[3])
{
    gr_error err = {0};
    for (int j = 0; j < 3; j++) {
        memset(&q[j], 0, sizeof q[j]);
        ck_assert(gr_spm_dist_init(&q[j].q, batches, 45, 4.5, &err) == 0);
    }
    const double k = cbrt(2.0 * Dn / (M * M)), dt = 2e-5;
    const double scale[3] = {k * cbrt(l) * f[0], k * cbrt(l) * f[1], k * cbrt(l) * f[2]};
    for (int w = 0; w < walks; w++) {
        gr_histogram *h[3] = {&q[0].q.batch[w % batches], &q[1].q.batch[w % batches],
                              &q[2].q.batch[w % batches]};
        physical_walk(r, l, dt, scale, h);
    }
    for (int j = 0; j < 3; j++) {
        for (int b = 0; b < batches; b++) {
            ck_assert(gr_histogram_merge(&q[j].q.all, &q[j].q.batch[b], &err) == 0);
        }
    }
}

START_TEST(test_collapse_physical_units)
{
    /* The thesis' statement (sec. 5.3.1) checked without the library's scaled walker: walks in
     * seconds and metres for l = 2.5 mm and 2 cm (dt = 20 us for both). Histogrammed in
     * v / l^(1/3) they collapse; in v / l^(1/2) they do not; and they agree with the library's
     * Q for 2.5 mm, whose velocity axis is w u_l (this checks u_l = (2 D l / M^2)^(1/3)). */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 31);
    const int walks = quick() ? 1200 : 3000, B = 20;
    const double la = 0.0025, lb = 0.02, lg = sqrt(la * lb);
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = walks;
    s.batches = B;
    s.dt = 2e-5;
    /* q[1]: the wrong exponent, v / l^(1/2), written as v / (l^(1/3) (l / l_g)^(1/6)) to keep the
     * range; q[2]: v / u_l with the library's u_l */
    const double k = cbrt(2.0 * Dn / (M * M));
    const double fa[3] = {1.0, pow(la / lg, 1.0 / 6.0),
                          gr_spm_velocity_scale(&s, la) / (k * cbrt(la))};
    const double fb[3] = {1.0, pow(lb / lg, 1.0 / 6.0),
                          gr_spm_velocity_scale(&s, lb) / (k * cbrt(lb))};
    gr_spm_q a[3], b[3], lib;
    physical_q(r, la, fa, walks, B, a);
    physical_q(r, lb, fb, walks, B, b);
    gr_spm_collapse col;
    gr_error err = {0};
    ck_assert_msg(gr_spm_q_collapse(&a[0], &b[0], 20.0, 500, &col, &err) == 0, "%s", err.message);
    ck_assert_msg(col.p_value > 0.002,
                  "v / l^(1/3) does not collapse: chi2/dof %.3f (%d bins), p = %.4f", col.chi2_red,
                  col.dof, col.p_value);
    ck_assert_msg(gr_spm_q_collapse(&a[1], &b[1], 20.0, 500, &col, &err) == 0, "%s", err.message);
    ck_assert_msg(col.p_value < 0.002 && col.chi2_red > 3.0,
                  "v / l^(1/2) collapses too: chi2/dof %.3f, p = %.4f", col.chi2_red, col.p_value);
    circle(&s, la, 0, &lib);
    ck_assert_msg(gr_spm_q_collapse(&a[2], &lib, 20.0, 500, &col, &err) == 0, "%s", err.message);
    ck_assert_msg(
        col.p_value > 0.002,
        "library Q(v, 2.5 mm) differs from the physical-unit walks: chi2/dof %.3f, p = %.4f",
        col.chi2_red, col.p_value);
    for (int j = 0; j < 3; j++) {
        gr_spm_q_free(&a[j]);
        gr_spm_q_free(&b[j]);
    }
    gr_spm_q_free(&lib);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_gaussian_tail)
{
    /* The tail of Q is close to Gaussian (5.12): fitted over w >= 2.5 the coefficient is near the
     * thesis' 0.98 and the free exponent near 2. Loose bounds: this documents the model, the
     * measured numbers are in docs/theory-spm.md. */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = quick() ? 10000 : 40000;
    s.step = 0.01;
    s.seed = 3;
    gr_spm_q q;
    circle(&s, 0.01, 0, &q);
    gr_spm_tail_fit f;
    gr_error err = {0};
    ck_assert_msg(gr_spm_q_tail_fit(&q, 2.5, 20.0, &f, &err) == 0, "%s", err.message);
    ck_assert_msg(f.b > 0.8 && f.b < 1.15, "b = %g +- %g", f.b, f.b_err);
    ck_assert_msg(f.b_err > 0.0 && f.b_err < 0.1, "b error %g", f.b_err);
    ck_assert_msg(fabs(f.b - 0.98) < 4.0 * f.b_err + 0.05, "b = %g +- %g against 0.98", f.b,
                  f.b_err);
    /* <w^2> in time and the mean exit time (measured: 0.512, 1.48) */
    ck_assert_msg(fabs(q.stats.w2_time_mean - 0.512) < 0.02, "<w^2> = %g", q.stats.w2_time_mean);
    ck_assert_msg(fabs(q.stats.exit_time_mean - 1.48) < 0.05, "<T> = %g t_l",
                  q.stats.exit_time_mean);
    gr_spm_q_free(&q);
}
END_TEST

START_TEST(test_reproducible)
{
    /* the same seed gives the same histogram, whatever the number of batches; another seed not */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = 400;
    s.step = 0.01;
    s.seed = 9;
    gr_spm_q a, b, c;
    circle(&s, 0.02, 0, &a);
    s.batches = 7;
    circle(&s, 0.02, 0, &b);
    s.seed = 10;
    circle(&s, 0.02, 0, &c);
    bool differ = false;
    for (int i = 0; i < a.q.all.nbins; i++) {
        ck_assert_msg(fabs(a.q.all.count[i] - b.q.all.count[i]) <=
                          1e-9 * fmax(1.0, a.q.all.count[i]),
                      "bin %d: %g vs %g", i, a.q.all.count[i], b.q.all.count[i]);
        differ |= a.q.all.count[i] != c.q.all.count[i];
    }
    ck_assert(a.stats.exit_time_mean == b.stats.exit_time_mean);
    ck_assert(differ);
    gr_spm_q_free(&a);
    gr_spm_q_free(&b);
    gr_spm_q_free(&c);
}
END_TEST

START_TEST(test_refinement_knob)
{
    /* a coarse step misses exits between the looks; the bridge refinement finds some of them and
     * leaves the statistics unchanged within errors */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = quick() ? 2000 : 6000;
    s.step = 0.1;
    s.refine = 0;
    gr_spm_q a, b;
    circle(&s, 0.01, 0, &a);
    s.refine = 12;
    circle(&s, 0.01, 0, &b);
    ck_assert_int_eq(a.stats.bridge_points, 0);
    ck_assert(b.stats.bridge_points > 0);
    ck_assert(b.stats.exit_time_mean <= a.stats.exit_time_mean);
    ck_assert_msg(fabs(a.stats.exit_time_mean - b.stats.exit_time_mean) < 0.02, "%g vs %g",
                  a.stats.exit_time_mean, b.stats.exit_time_mean);
    gr_spm_q_free(&a);
    gr_spm_q_free(&b);
}
END_TEST

/* ------------------------------------------------------------------------------------------- */

START_TEST(test_alpha_and_prediction)
{
    /* 5.29: alpha(1.63) = 3.78 / 3.89 = 0.97 to two decimals */
    double a = gr_spm_alpha(1.63);
    ck_assert_msg(fabs(a - 0.97) < 0.005, "alpha(1.63) = %g", a);
    ck_assert(fabs(a - 3.78 / 3.89) < 1e-12);
    gr_spm_prediction p;
    gr_error err = {0};
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    /* B = 0.98 (M^2/2D)^(2/3) = 0.154 with Table 2.2 (thesis sec. 5.3.3) */
    double B = gr_spm_B(&s, 0.98);
    ck_assert_msg(fabs(B - 0.154) < 0.0005, "B = %g", B);
    ck_assert(gr_spm_predict(1.63, B, 121.0, &p, &err) == 0);
    ck_assert(fabs(p.alpha - a) < 1e-15);
    /* 5.30-5.31: h = 3(D_f - 1)/(3 D_f - 1) = 0.49 */
    ck_assert_msg(fabs(p.h - 0.486) < 0.001, "h = %g", p.h);
    ck_assert(fabs(p.h - 0.5 * p.alpha) < 1e-15);
    /* 5.27: the thesis quotes 9.48 and 11.60 for C = 121 and 179 (as "v_A"; S here) */
    ck_assert_msg(fabs(p.S - 9.48) < 0.02, "S(C = 121) = %g", p.S);
    ck_assert_msg(fabs(p.v_A - pow(p.S, -1.0 / p.alpha)) < 1e-12, "v_A");
    ck_assert(gr_spm_predict(1.63, B, 179.0, &p, &err) == 0);
    ck_assert_msg(fabs(p.S - 11.60) < 0.03, "S(C = 179) = %g", p.S);
    /* 5.26: the numerical integral 5.13 approaches its steepest-descent form */
    ck_assert(gr_spm_predict(1.63, B, 121.0, &p, &err) == 0);
    double prev = INFINITY;
    for (double v = 0.25; v <= 4.0; v *= 2.0) {
        double li;
        ck_assert_msg(gr_spm_integral_log(&p, v, &li, &err) == 0, "%s", err.message);
        double d = fabs(li - gr_spm_asymptotic_log(&p, v));
        ck_assert_msg(d < prev, "ln I - asymptotic grows at v = %g: %g", v, d);
        prev = d;
    }
    ck_assert_msg(prev < 0.02, "ln I - asymptotic at v = 4: %g", prev);
}
END_TEST

/* ------------------------------------------------------------------------------------------- */

static char tmpdir[256];

static void write_file(const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    ck_assert(f != NULL);
    fputs(text, f);
    fclose(f);
}

START_TEST(test_free_paths)
{
    gr_error err = {0};
    gr_spm_pl w;
    ck_assert(gr_spm_pl_fitted(&w, 1.63, 121.0, &err) == 0);
    /* the quantile inverts the distribution function 1 - exp(-C l^beta) */
    for (double u = 0.05; u < 1.0; u += 0.1) {
        double l = gr_spm_pl_quantile(&w, u);
        ck_assert(fabs(1.0 - exp(-121.0 * pow(l, 0.63)) - u) < 1e-12);
    }
    double mean = pow(121.0, -1.0 / 0.63) * gsl_sf_gamma(1.0 + 1.0 / 0.63);
    ck_assert(fabs(gr_spm_pl_mean(&w) / mean - 1.0) < 1e-12);
    /* a table of the same density, on a log grid: mean, quantiles and the tail fit agree */
    char *text = malloc(200000);
    ck_assert(text != NULL);
    int k = sprintf(text, "# a test table\nl,P,P_err\n");
    for (int i = 0; i <= 600; i++) {
        /* with 1% scatter, as a measured table has (gr_fit_nonlinear does not converge on exact
         * data: its residual is zero) */
        double l = 1e-12 * pow(1e11, i / 600.0), p = gr_spm_pl_density(&w, l),
               g = sin(i * 12.9898) * 43758.5453;
        g = 2.0 * (g - floor(g)) - 1.0;
        k += sprintf(text + k, "%.12g,%.12g,%.12g\n", l, p * (1.0 + 0.01 * g), 0.01 * p);
    }
    write_file("pl.csv", text);
    free(text);
    char path[512];
    snprintf(path, sizeof path, "%s/pl.csv", tmpdir);
    gr_spm_pl t;
    ck_assert_msg(gr_spm_pl_load(&t, path, 0.0, &err) == 0, "%s", err.message);
    ck_assert_int_eq(t.n, 601);
    ck_assert(t.perr != NULL);
    ck_assert_msg(fabs(gr_spm_pl_mean(&t) / mean - 1.0) < 0.01, "table mean %g vs %g",
                  gr_spm_pl_mean(&t), mean);
    for (double u = 0.1; u < 0.95; u += 0.2) {
        double a = gr_spm_pl_quantile(&t, u), b = gr_spm_pl_quantile(&w, u);
        ck_assert_msg(fabs(a / b - 1.0) < 0.01, "quantile %g: %g vs %g", u, a, b);
    }
    gr_spm_pl_fit fit;
    ck_assert_msg(gr_spm_pl_fit_tail(&t, 1e-4, &fit, &err) == 0, "%s", err.message);
    ck_assert_msg(fabs(fit.df - 1.63) < 0.01 && fabs(fit.C / 121.0 - 1.0) < 0.03,
                  "fit D_f = %g, C = %g", fit.df, fit.C);
    gr_spm_pl_free(&t);
    /* the time-weighted full SPM: <v^2> = <w^2>_Q (2D/M^2)^(2/3) E[l^(4/3)] / E[l^(2/3)], since a walk of
     * radius l lasts ~ t_l ~ l^(2/3) and has velocities ~ u_l ~ l^(1/3) */
    gr_spm_settings s;
    gr_spm_settings_default(&s);
    s.walks = quick() ? 20000 : 60000;
    s.step = 0.01;
    gr_spm_full_result r;
    ck_assert_msg(gr_spm_full(&s, &w, true, 60, 3.0, &r, &err) == 0, "%s", err.message);
    double beta = 0.63, Cc = 121.0;
    double El43 = pow(Cc, -(4.0 / 3.0) / beta) * gsl_sf_gamma(1.0 + (4.0 / 3.0) / beta);
    double El23 = pow(Cc, -(2.0 / 3.0) / beta) * gsl_sf_gamma(1.0 + (2.0 / 3.0) / beta);
    double expect = 0.512 * pow(2.0 * Dn / (M * M), 2.0 / 3.0) * El43 / El23;
    ck_assert_msg(fabs(r.v2_mean / expect - 1.0) < 0.06, "<v^2> = %g, expected %g", r.v2_mean,
                  expect);
    ck_assert_msg(fabs(r.l_mean / mean - 1.0) < 0.05, "<l> drawn %g vs %g", r.l_mean, mean);
    /* importance sampling of long free paths leaves <v^2> unchanged within errors */
    s.tilt = 4.0;
    gr_spm_full_result r4;
    ck_assert_msg(gr_spm_full(&s, &w, true, 60, 3.0, &r4, &err) == 0, "%s", err.message);
    ck_assert_msg(fabs(r4.v2_mean / expect - 1.0) < 0.06, "tilted <v^2> = %g, expected %g",
                  r4.v2_mean, expect);
    gr_spm_full_result_free(&r);
    gr_spm_full_result_free(&r4);
}
END_TEST

START_TEST(test_rfm_reader_and_compare)
{
    char sd[512];
    snprintf(sd, sizeof sd, "%s/run/snapshots", tmpdir);
    char rd[512];
    snprintf(rd, sizeof rd, "%s/run", tmpdir);
    mkdir(rd, 0777);
    mkdir(sd, 0777);
    const char *head = "3\nLattice=\"0.2 0 0 0 0.2 0 0 0 1\" pbc=\"T T F\" Time=%g "
                       "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1\n";
    char text[2048], name[64];
    for (int f = 0; f < 3; f++) {
        int k = snprintf(text, sizeof text, head, 0.5 * f);
        k += snprintf(text + k, sizeof text - (size_t)k, "G 0.1 0.1 0 0.5 -0.25 0 0.0015\n");
        k += snprintf(text + k, sizeof text - (size_t)k, "G 0.1 0.12 0 -1.5 0.75 0 0.0015\n");
        snprintf(text + k, sizeof text - (size_t)k, "G 0.13 0.1 0 0.05 0 0 0.0015\n");
        snprintf(name, sizeof name, "run/snapshots/snap_%06d.xyz", f);
        write_file(name, text);
    }
    gr_histogram h;
    gr_error err = {0};
    ck_assert(gr_histogram_init(&h, 20, 0.0, 2.0, false, &err) == 0);
    gr_spm_rfm_info info;
    ck_assert_msg(gr_spm_rfm_histogram(rd, 0.4, &h, &info, &err) == 0, "%s", err.message);
    ck_assert_int_eq(info.frames, 2);
    ck_assert_int_eq(info.frames_skipped, 1);
    ck_assert_int_eq(info.dim, 2);
    ck_assert_int_eq(info.particles, 3);
    ck_assert(h.total == 12.0);
    ck_assert(fabs(info.v_max - 1.5) < 1e-15);
    ck_assert(h.count[15] == 2.0 && h.count[0] == 4.0); /* |-1.5| twice; 0.05 and 0 twice each */
    double v2 = (0.25 + 0.0625 + 2.25 + 0.5625 + 0.0025) / 6.0;
    ck_assert(fabs(info.v2_mean - v2) < 1e-12);
    gr_histogram_free(&h);
    /* no snapshots: refused */
    ck_assert(gr_histogram_init(&h, 20, 0.0, 2.0, false, &err) == 0);
    ck_assert(gr_spm_rfm_histogram(tmpdir, 0.0, &h, &info, &err) == GR_EINVAL);
    ck_assert(gr_spm_rfm_histogram(rd, 5.0, &h, &info, &err) == GR_EINVAL); /* all in the warm-up */
    gr_histogram_free(&h);

    /* tails: P_rfm = 2 P_spm exactly -> k = 2, every bin agrees; a velocity scale is found back */
    enum { N = 80 };
    double v[N], ps[N], es[N], pr[N], er[N];
    for (int i = 0; i < N; i++) {
        v[i] = 0.025 + 0.05 * i;
        ps[i] = exp(-3.0 * v[i]);
        es[i] = 0.01 * ps[i];
        pr[i] = 2.0 * ps[i];
        er[i] = 0.02 * pr[i];
    }
    gr_spm_compare c;
    ck_assert(gr_spm_compare_tails(v, ps, es, pr, er, N, 0.5, 3.0, false, &c, &err) == 0);
    ck_assert_msg(fabs(c.k - 2.0) < 1e-6, "k = %g", c.k);
    ck_assert_int_eq(c.agree_bins, N);
    ck_assert(fabs(c.decades - 3.0 * 0.05 * (N - 1) / log(10.0)) < 1e-9);
    for (int i = 0; i < N; i++) {
        pr[i] = 0.7 * exp(-3.0 * v[i] / 1.25) / 1.25; /* k = 0.7, s = 1.25 */
        er[i] = 0.02 * pr[i];
    }
    ck_assert(gr_spm_compare_tails(v, ps, es, pr, er, N, 0.5, 3.0, true, &c, &err) == 0);
    ck_assert_msg(fabs(c.s - 1.25) < 0.01 && fabs(c.k - 0.7) < 0.02, "s = %g, k = %g", c.s, c.k);
    ck_assert(gr_spm_compare_tails(v, ps, es, pr, er, N, 0.5, 3.0, false, &c, &err) == 0);
    ck_assert_msg(c.decades < 1.0 && c.frac_within < 0.5, "an unscaled curve agreed: %g decades",
                  c.decades);
}
END_TEST

START_TEST(test_refusals)
{
    gr_error err = {0};
    gr_spm_settings s, b;
    gr_spm_settings_default(&s);
    ck_assert(gr_spm_settings_check(&s, &err) == 0);
    struct {
        const char *what;
        void (*set)(gr_spm_settings *);
    } bad[] = {
        {"dim 3", NULL},     {"mass 0", NULL},   {"D < 0", NULL},     {"step 0", NULL},
        {"step 0.5", NULL},  {"dt < 0", NULL},   {"refine 31", NULL}, {"walks 1", NULL},
        {"batches 1", NULL}, {"tilt 0.5", NULL},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        b = s;
        switch (i) {
        case 0: b.dim = 3; break;
        case 1: b.mass = 0.0; break;
        case 2: b.D = -1.0; break;
        case 3: b.step = 0.0; break;
        case 4: b.step = 0.5; break;
        case 5: b.dt = -1.0; break;
        case 6: b.refine = 31; break;
        case 7: b.walks = 1; break;
        case 8: b.batches = 1; break;
        default: b.tilt = 0.5; break;
        }
        err.message[0] = 0;
        ck_assert_msg(gr_spm_settings_check(&b, &err) == GR_EINVAL, "%s accepted", bad[i].what);
        ck_assert_msg(err.message[0] && !strchr(err.message, '\n'), "%s: no one-line message",
                      bad[i].what);
    }
    gr_spm_q q;
    ck_assert(gr_spm_circle(&s, 0.0, 0, 45, 4.5, &q, &err) == GR_EINVAL);
    ck_assert(gr_spm_circle(&s, -1.0, 0, 45, 4.5, &q, &err) == GR_EINVAL);
    ck_assert(gr_spm_circle(&s, 0.01, 0, 1, 4.5, &q, &err) == GR_EINVAL);
    ck_assert(gr_spm_circle(&s, 0.01, 0, 45, 0.0, &q, &err) == GR_EINVAL);
    b = s;
    b.dt = 1.0; /* 1 s is hundreds of t_l for 1 cm */
    ck_assert(gr_spm_circle(&b, 0.01, 0, 45, 4.5, &q, &err) == GR_EINVAL);
    gr_spm_pl pl;
    ck_assert(gr_spm_pl_fitted(&pl, 1.0, 121.0, &err) == GR_EINVAL);
    ck_assert(gr_spm_pl_fitted(&pl, 1.63, 0.0, &err) == GR_EINVAL);
    gr_spm_prediction p;
    ck_assert(gr_spm_predict(0.9, 0.154, 121.0, &p, &err) == GR_EINVAL);
    ck_assert(gr_spm_predict(1.63, -1.0, 121.0, &p, &err) == GR_EINVAL);
    ck_assert(gr_spm_predict(1.63, 0.0, 0.0, &p, &err) == 0 && isnan(p.S)); /* alpha only */
    char path[512];
    struct {
        const char *text;
        const char *why;
    } files[] = {
        {"l,P\n0.1,1\n0.2,0.5\n", "too few rows"},
        {"x,y\n0.1,1\n0.2,0.5\n0.3,0.1\n", "no l and P columns"},
        {"l,P\n0.1,1\n0.1,0.5\n0.3,0.1\n", "l not increasing"},
        {"l,P\n0.1,1\n0.2,-0.5\n0.3,0.1\n", "negative P"},
        {"l,P\n0.1,1\n0.2,abc\n0.3,0.1\n", "not a number"},
        {"l,P\n0.1,0\n0.2,0\n0.3,0\n", "zero integral"},
        {"# only a comment\n", "no header"},
    };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        write_file("bad.csv", files[i].text);
        snprintf(path, sizeof path, "%s/bad.csv", tmpdir);
        ck_assert_msg(gr_spm_pl_load(&pl, path, 0.0, &err) == GR_EINVAL, "%s accepted",
                      files[i].why);
        ck_assert_msg(strstr(err.message, "bad.csv") != NULL,
                      "%s: message does not name the file: %s", files[i].why, err.message);
    }
    snprintf(path, sizeof path, "%s/missing.csv", tmpdir);
    ck_assert(gr_spm_pl_load(&pl, path, 0.0, &err) != 0);
    /* "density" and "density_error" (gr_histogram_write_csv's names) are accepted */
    write_file(
        "hist.csv",
        "# c\nl_lo,l_hi,l,count,density,density_error\n0,0.2,0.1,5,1,0.1\n0.2,0.4,0.3,3,0.5,0.1\n"
        "0.4,0.6,0.5,1,0.25,0.1\n");
    snprintf(path, sizeof path, "%s/hist.csv", tmpdir);
    ck_assert_msg(gr_spm_pl_load(&pl, path, 0.0, &err) == 0, "%s", err.message);
    ck_assert(pl.n == 3 && pl.perr != NULL);
    gr_spm_pl_free(&pl);
    /* a run's freepath.csv: free paths in diameters, converted with the diameter */
    write_file("freepath.csv",
               "# c\nl_over_d_lo,l_over_d_hi,l_over_d,count,density,density_error\n"
               "0,0.2,0.1,5,1,0.1\n0.2,0.4,0.3,3,0.5,0.1\n0.4,0.6,0.5,1,0.25,0.1\n");
    snprintf(path, sizeof path, "%s/freepath.csv", tmpdir);
    ck_assert(gr_spm_pl_load(&pl, path, 0.0, &err) == GR_EINVAL);
    ck_assert_msg(gr_spm_pl_load(&pl, path, 0.003, &err) == 0, "%s", err.message);
    ck_assert(fabs(pl.l[1] - 0.0009) < 1e-15 &&
              fabs(gr_spm_pl_mean(&pl) / 0.003 - 0.0575 / 0.225) < 1e-9);
    gr_spm_pl_free(&pl);
}
END_TEST

int main(void)
{
    gsl_set_error_handler_off();
    snprintf(tmpdir, sizeof tmpdir, "%s/granule-test-spm-XXXXXX",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return EXIT_FAILURE;
    }
    Suite *s = suite_create("spm");
    TCase *t = tcase_create("spm");
    tcase_set_timeout(t, 300);
    tcase_add_test(t, test_free_flight_moments);
    tcase_add_test(t, test_bridge_midpoint);
    tcase_add_test(t, test_constants_convention);
    tcase_add_test(t, test_w2_error_calibrated);
    tcase_add_test(t, test_study_defaults);
    tcase_add_test(t, test_collapse);
    tcase_add_test(t, test_collapse_physical_units);
    tcase_add_test(t, test_gaussian_tail);
    tcase_add_test(t, test_reproducible);
    tcase_add_test(t, test_refinement_knob);
    tcase_add_test(t, test_alpha_and_prediction);
    tcase_add_test(t, test_free_paths);
    tcase_add_test(t, test_rfm_reader_and_compare);
    tcase_add_test(t, test_refusals);
    suite_add_tcase(s, t);
    int status = gr_test_run(s);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) {
        fprintf(stderr, "could not remove %s\n", tmpdir);
    }
    return status;
}
