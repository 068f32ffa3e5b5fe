/* The RFM's P(v) against the SPM's asymptotic form (Figs. 5.12-5.13; src/theory/spm_rfm_tail.c) on
 * synthetic input whose answer is known: counts drawn (Poisson) from 5.31 with the S that
 * gr_spm_predict gives for the thesis's D_f = 1.63 and C = 121 give back S and A0 (and a wrong alpha
 * is rejected by chi2); the tail plot with P' = A0 of P = A0 exp(-S v^alpha) has slope -alpha
 * exactly, and with P' = P(0) < A0 a steeper one (the thesis's -1.15 against -1.0); the fold of a
 * symmetric histogram; C of 4.25 at fixed D_f recovered from a tabulated P_l. */
#include <check.h>
#include <gsl/gsl_fit.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>

#include "granule/spm.h"
#include "check_main.h"

#define NB 400

/* A symmetric histogram of one velocity component on [-vmax, vmax): expected counts N dv f(|v|), f
 * being 5.31 (normalisation irrelevant for the tail), drawn Poisson when rng is given. density and
 * sqrt(X) errors as the pv observable writes them (A.5). */
static void synthetic_pv(gsl_rng *rng, double N, double vmax, double lnA0, double h, double S,
                         double alpha, double *v, double *p, double *e)
{
    const double dv = 2.0 * vmax / NB;
    for (int i = 0; i < NB; i++) {
        v[i] = -vmax + (i + 0.5) * dv;
        const double a = fabs(v[i]);
        const double mean = N * dv * exp(gr_spm_tail531_log(lnA0, h, S, alpha, a));
        const double x = rng ? (double)gsl_ran_poisson(rng, mean) : mean;
        p[i] = x / (N * dv);
        e[i] = sqrt(x) / (N * dv);
    }
}

START_TEST(test_fold)
{
    double v[NB], p[NB], e[NB], vf[NB], pf[NB], ef[NB], cf[NB];
    synthetic_pv(NULL, 1e6, 2.0, 0.0, 0.0, 3.0, 1.0, v, p, e);
    p[0] *= 3.0; /* the mirror of the last bin: the fold averages the two */
    e[0] *= sqrt(3.0);
    const int n = gr_spm_fold_pv(v, p, e, NB, vf, pf, ef, cf);
    ck_assert_int_eq(n, NB / 2);
    ck_assert(fabs(vf[0] - v[NB / 2]) < 1e-12 && vf[n - 1] == v[NB - 1]);
    ck_assert(fabs(pf[n - 1] - 2.0 * p[NB - 1]) < 1e-12 * pf[n - 1]);
    /* counts: (P/e)^2 of both sides, the sqrt(X) counts of A.5 */
    const double dv = 4.0 / NB, expect = 1e6 * dv * exp(-3.0 * vf[10]) * 2.0;
    ck_assert_msg(fabs(cf[10] - expect) < 1e-9 * expect, "counts %g, expected %g", cf[10], expect);
    /* not symmetric about 0: refused */
    for (int i = 0; i < NB; i++) {
        v[i] += 0.3 * (4.0 / NB);
    }
    ck_assert_int_eq(gr_spm_fold_pv(v, p, e, NB, vf, pf, ef, cf), 0);
}
END_TEST

START_TEST(test_531_recovers_S)
{
    /* the thesis's phi = 0.530 system: D_f = 1.63, C = 121, B = 0.154 -> S = 9.48 (5.27) */
    gr_spm_settings st;
    gr_spm_settings_default(&st);
    gr_spm_prediction pred;
    gr_error err = {0};
    ck_assert(gr_spm_predict(1.63, gr_spm_B(&st, GR_SPM_THESIS_B_COEF), 121.0, &pred, &err) ==
              GR_OK);
    ck_assert(fabs(pred.S - 9.48) < 0.01);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 7);
    double v[NB], p[NB], e[NB], vf[NB], pf[NB], ef[NB], cf[NB];
    const double lnA0 = log(20.0), v_rms = 0.21, P0 = 2.1;
    int agree = 0;
    const int trials = 5;
    for (int k = 0; k < trials; k++) {
        synthetic_pv(rng, 3e7, 3.6, lnA0, pred.h, pred.S, pred.alpha, v, p, e);
        const int n = gr_spm_fold_pv(v, p, e, NB, vf, pf, ef, cf);
        gr_spm_tail531 t;
        ck_assert_msg(gr_spm_tail531_fit(vf, pf, ef, cf, n, P0, v_rms, pred.alpha, pred.h, 2.0,
                                         INFINITY, 50.0, pred.S, &t, &err) == GR_OK,
                      "%s", err.message);
        ck_assert_msg(t.n_points > 20 && t.v_lo >= 2.0 * v_rms && t.decades > 3.0,
                      "%d bins from %g m/s, %g decades", t.n_points, t.v_lo, t.decades);
        ck_assert_msg(t.S_err > 0.0 && t.S_err < 0.02 * pred.S, "S error %g", t.S_err);
        ck_assert_msg(t.chi2_red > 0.4 && t.chi2_red < 2.0, "chi2/dof %g for the true model",
                      t.chi2_red);
        agree += fabs(t.S - pred.S) < 2.0 * t.S_err && fabs(t.lnA0 - lnA0) < 2.0 * t.lnA0_err;
        ck_assert_msg(fabs(t.S - pred.S) < 4.0 * t.S_err, "S = %g +- %g, drawn with %g", t.S,
                      t.S_err, pred.S);
        ck_assert(fabs(t.A0_over_P0 - 20.0 / P0) < 4.0 * t.lnA0_err * 20.0 / P0);
        ck_assert(fabs(t.lnA0_at_S_pred - lnA0) < 0.01);
        /* a wrong alpha does not fit the same counts */
        gr_spm_tail531 w;
        ck_assert(gr_spm_tail531_fit(vf, pf, ef, cf, n, P0, v_rms, 0.8, pred.h, 2.0, INFINITY, 50.0,
                                     0.0, &w, &err) == GR_OK);
        ck_assert_msg(w.chi2_red > 3.0, "alpha = 0.8 fits the alpha = 0.97 counts: chi2/dof %g",
                      w.chi2_red);
    }
    ck_assert_msg(agree >= trials - 2, "S and A0 within 2 sigma in only %d of %d draws", agree,
                  trials);
    gsl_rng_free(rng);
}
END_TEST

START_TEST(test_tail_plot_slopes)
{
    /* P = A0 exp(-S v^alpha) exactly (h = 0): -ln(-ln(P/A0)) = -alpha ln v - ln S, slope -alpha; with
     * P' = P(0) = A0 / 7.5, -ln(S v^alpha - ln 7.5) falls faster: slope < -alpha (Fig. 5.13) */
    double v[NB], p[NB], e[NB], vf[NB], pf[NB], ef[NB], cf[NB];
    const double alpha = 0.9717, S = 9.48, A0 = 15.0;
    synthetic_pv(NULL, 1e9, 3.6, log(A0), 0.0, S, alpha, v, p, e);
    const int n = gr_spm_fold_pv(v, p, e, NB, vf, pf, ef, cf);
    gr_spm_tail531 t;
    gr_error err = {0};
    ck_assert(gr_spm_tail531_fit(vf, pf, ef, cf, n, A0 / 7.5, 0.2, alpha, 0.0, 2.0, 8.0, 50.0, 0.0,
                                 &t, &err) == GR_OK);
    ck_assert_msg(fabs(t.S - S) < 1e-9 && fabs(t.A0 - A0) < 1e-9 * A0, "S %g, A0 %g", t.S, t.A0);
    ck_assert(fabs(t.A0_over_P0 - 7.5) < 1e-9);
    ck_assert_msg(fabs(t.slope_A0 + alpha) < 1e-9, "slope with P' = A0: %.12g, expected %g",
                  t.slope_A0, -alpha);
    ck_assert_msg(t.slope_P0 < -alpha - 0.05, "slope with P' = P(0): %g, expected steeper than %g",
                  t.slope_P0, -alpha);
    ck_assert(t.v_hi <= 8.0 * 0.2 + 1e-12 && isnan(t.lnA0_at_S_pred));
    /* too few bins in the window: refused, with the window in the message */
    ck_assert_int_eq(gr_spm_tail531_fit(vf, pf, ef, cf, n, A0 / 7.5, 0.2, alpha, 0.0, 2.0, 2.01,
                                        50.0, 0.0, &t, &err),
                     GR_EINVAL);
    ck_assert_int_eq(
        gr_spm_tail531_fit(vf, pf, ef, cf, n, 0.0, 0.2, alpha, 0.0, 2.0, 8.0, 50.0, 0.0, &t, &err),
        GR_EINVAL);
}
END_TEST

START_TEST(test_errors_scaled_once)
{
    /* A fit that does not describe its data (alpha = 0.8 against alpha = 0.97 counts, chi2/dof >> 1)
     * reports its errors scaled by sqrt(chi2/dof) once, as every fit of granule does (the counting
     * error times the scatter's excess): S's error is the weighted line's own, from GSL here. */
    double v[NB], p[NB], e[NB], vf[NB], pf[NB], ef[NB], cf[NB];
    const double v_rms = 0.21, alpha = 0.8, h = 0.5;
    synthetic_pv(NULL, 3e7, 3.6, log(20.0), h, 9.48, 0.9717, v, p, e);
    const int n = gr_spm_fold_pv(v, p, e, NB, vf, pf, ef, cf);
    gr_spm_tail531 t;
    gr_error err = {0};
    ck_assert(gr_spm_tail531_fit(vf, pf, ef, cf, n, 2.1, v_rms, alpha, h, 2.0, INFINITY, 50.0, 0.0,
                                 &t, &err) == GR_OK);
    double x[NB], y[NB], w[NB];
    size_t m = 0;
    for (int i = 0; i < n; i++) {
        if (vf[i] / v_rms >= 2.0 && cf[i] >= 50.0 && pf[i] > 0.0 && ef[i] > 0.0) {
            x[m] = pow(vf[i], alpha);
            y[m] = log(pf[i]) - h * log(vf[i]);
            w[m] = pow(pf[i] / ef[i], 2.0);
            m++;
        }
    }
    double c0, c1, cov00, cov01, cov11, chi2;
    gsl_fit_wlinear(x, 1, w, 1, y, 1, m, &c0, &c1, &cov00, &cov01, &cov11, &chi2);
    const double chi2_red = chi2 / (double)(m - 2);
    ck_assert_msg(chi2_red > 3.0 && fabs(t.chi2_red - chi2_red) < 1e-9 * chi2_red,
                  "chi2/dof %g, %g", t.chi2_red, chi2_red);
    ck_assert_msg(fabs(t.S + c1) < 1e-9 * fabs(c1), "S %g against %g", t.S, -c1);
    const double want = sqrt(cov11 * chi2_red);
    ck_assert_msg(fabs(t.S_err - want) < 1e-6 * want,
                  "S error %g, expected %g (sqrt(chi2/dof) once)", t.S_err, want);
}
END_TEST

START_TEST(test_pl_fit_C)
{
    /* 4.25 tabulated on log bins: C back at the right D_f, not at a wrong one */
    double l[60], p[60], e[60];
    const double beta = 0.63, C = 121.0;
    for (int i = 0; i < 60; i++) {
        l[i] = 1e-4 * pow(10.0, i / 15.0);
        p[i] = 30.0 * pow(l[i], beta - 1.0) * exp(-C * pow(l[i], beta));
        e[i] = 1e-3 * p[i];
    }
    double c, c_err, chi2;
    gr_error err = {0};
    ck_assert(gr_spm_pl_fit_C(l, p, e, 60, beta, 1e-3, 0.05, &c, &c_err, &chi2, &err) == GR_OK);
    ck_assert_msg(fabs(c - C) < 1e-6 * C && chi2 < 1e-9, "C = %g (chi2/dof %g)", c, chi2);
    ck_assert(gr_spm_pl_fit_C(l, p, e, 60, 0.5, 1e-3, 0.05, &c, &c_err, &chi2, &err) == GR_OK);
    ck_assert_msg(chi2 > 100.0 && fabs(c - C) > 0.1 * C, "the wrong D_f fits: C = %g, chi2/dof %g",
                  c, chi2);
    ck_assert_int_eq(gr_spm_pl_fit_C(l, p, e, 60, 0.63, 1.0, 2.0, &c, &c_err, &chi2, &err),
                     GR_EINVAL);
}
END_TEST

/* Fig. 5.10 from the two series (gr_spm_compare_series): an SPM curve of the run's shape, 2.5 times
 * higher, gives k = 0.4, every tail bin within 3 sigma, and the same alpha for both; a Gaussian SPM
 * curve of the same v_rms does not agree and has alpha 2; v_rms is the distribution's. */
#define NC 200
static void stretched(gsl_rng *rng, double N, double v0, double a, double scale, double *v,
                      double *p, double *e)
{
    const double dv = 1.0 / NC, norm = v0 * tgamma(1.0 / a) / a; /* int_0^inf exp(-(v/v0)^a) dv */
    for (int i = 0; i < NC; i++) {
        v[i] = (i + 0.5) * dv;
        const double count = (double)gsl_ran_poisson(rng, N * dv * exp(-pow(v[i] / v0, a)) / norm);
        p[i] = scale * count / (N * dv);
        e[i] = scale * sqrt(count) / (N * dv);
    }
}

START_TEST(test_compare_series)
{
    double v[NC], pr[NC], er[NC], ps[NC], es[NC];
    const double v0 = 0.1, a = 1.3;
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 510);
    stretched(rng, 1e9, v0, a, 1.0, v, pr, er);
    stretched(rng, 1e10, v0, a, 2.5, v, ps, es);
    gr_spm_series_compare c;
    gr_error err = {0};
    ck_assert_int_eq(gr_spm_compare_series(v, ps, es, pr, er, NC, 2.0, 3.0, &c, &err), GR_OK);
    const double vrms = v0 * sqrt(tgamma(3.0 / a) / tgamma(1.0 / a));
    ck_assert_double_eq_tol(c.v_rms, vrms, 0.01 * vrms);
    ck_assert_double_eq_tol(c.v_from, 2.0 * c.v_rms, 1e-12);
    ck_assert_double_eq_tol(c.amp.k, 0.4, 1e-3);
    ck_assert(c.amp.frac_within > 0.95); /* Poisson counts: 3 sigma */
    ck_assert(c.amp.decades > 5.0);
    ck_assert_double_eq_tol(c.scaled.s, 1.0, 0.01);
    ck_assert_double_eq_tol(c.alpha_rfm, a, 0.03);
    ck_assert_double_eq_tol(c.alpha_spm, a, 0.03);
    /* a Gaussian of the same v_rms */
    const double dv = 1.0 / NC, sig = vrms;
    for (int i = 0; i < NC; i++) {
        const double count = (double)gsl_ran_poisson(
            rng, 1e10 * dv * exp(-0.5 * v[i] * v[i] / (sig * sig)) * sqrt(2.0 / M_PI) / sig);
        ps[i] = count / (1e10 * dv);
        es[i] = sqrt(count) / (1e10 * dv);
    }
    ck_assert_int_eq(gr_spm_compare_series(v, ps, es, pr, er, NC, 2.0, 3.0, &c, &err), GR_OK);
    ck_assert(c.amp.frac_within < 0.5);
    ck_assert_double_eq_tol(c.alpha_spm, 2.0, 0.05);
    ck_assert_double_eq_tol(c.alpha_rfm, a, 0.03);
    /* too few bins, a bad z_max: refused */
    ck_assert_int_eq(gr_spm_compare_series(v, ps, es, pr, er, 2, 2.0, 3.0, &c, &err), GR_EINVAL);
    ck_assert_int_eq(gr_spm_compare_series(v, ps, es, pr, er, NC, 2.0, 0.0, &c, &err), GR_EINVAL);
    gsl_rng_free(rng);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("spm_tail");
    TCase *t = tcase_create("spm_tail");
    tcase_add_test(t, test_fold);
    tcase_add_test(t, test_531_recovers_S);
    tcase_add_test(t, test_tail_plot_slopes);
    tcase_add_test(t, test_errors_scaled_once);
    tcase_add_test(t, test_pl_fit_C);
    tcase_add_test(t, test_compare_series);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
