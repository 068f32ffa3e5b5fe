/* The curve analysis of reproduction campaigns (src/app/reproduce/campaign_curve.c): a run's series is
 * read from its table with the `where` filter, and the bisection collapse (thesis 3.39-3.40) maps
 * the uniform bisection process's distribution G_1 = A (-ln R)^(n-1) (3.36) onto the line -ln R. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/analysis.h"
#include "app/reproduce/campaign_points.h"
#include "check_main.h"

START_TEST(test_collapse_of_uniform_bisection_is_minus_ln_R)
{
    enum { n = 60 };
    const double N = 1024.0, nb = 10.0; /* N = 2^n */
    double x[n], y[n], e[n];
    for (int i = 0; i < n; i++) {
        x[i] = pow(10.0, -7.0 + 6.5 * i / (n - 1)); /* R = 1e-7 ... 0.3 */
        y[i] = 3.7e-4 * pow(-log(x[i]), nb - 1.0);
        e[i] = 0.01 * y[i];
    }
    const double x0 = x[40];
    ck_assert(campaign_bisection_collapse(N, x0, x, y, e, n));
    for (int i = 0; i < n; i++) {
        ck_assert_double_eq_tol(y[i], x[i], 1e-9 * x[i]); /* the mapped curve is -ln R itself */
        ck_assert_double_eq_tol(e[i], 0.01 * y[i] / (nb - 1.0),
                                1e-12 * y[i]); /* dY = Y dG / ((n-1) G) */
    }
    gr_fit fit;
    gr_error err = {0};
    ck_assert_int_eq(gr_fit_power_law(x, y, NULL, n, &fit, &err), GR_OK);
    ck_assert_double_eq_tol(fit.p[1], 1.0, 1e-9);
}
END_TEST

START_TEST(test_collapse_detects_another_power)
{
    /* G_1 = (-ln R)^(2(n-1)) is not the uniform bisection process: the mapped slope is 2 */
    enum { n = 40 };
    double x[n], y[n], e[n];
    for (int i = 0; i < n; i++) {
        x[i] = pow(10.0, -6.0 + 5.0 * i / (n - 1));
        y[i] = pow(-log(x[i]), 2.0 * 7.0);
        e[i] = 0.0;
    }
    ck_assert(campaign_bisection_collapse(256.0, 1e-3, x, y, e, n));
    gr_fit fit;
    gr_error err = {0};
    ck_assert_int_eq(gr_fit_power_law(x, y, NULL, n, &fit, &err), GR_OK);
    ck_assert_double_eq_tol(fit.p[1], 2.0, 1e-9);
    /* nothing to normalise at: G = 0 at x0 */
    double zx[2] = {0.1, 0.01}, zy[2] = {0.0, 0.0}, ze[2] = {0.0, 0.0};
    ck_assert(!campaign_bisection_collapse(256.0, 0.1, zx, zy, ze, 2));
    ck_assert_double_eq(zx[0], 0.1);
}
END_TEST

/* log_ratio (Moon, Swift and Swinney's axes, thesis 5.6): P = P(0) exp(-c v^alpha) becomes c v^alpha,
 * so the power-law slope is alpha; bins at v <= 0 and above P(0) go. */
START_TEST(test_log_ratio_turns_a_stretched_exponential_into_its_exponent)
{
    enum { n = 81 };
    double x[n], y[n], e[n];
    for (int i = 0; i < n; i++) {
        x[i] = -4.0 + 0.1 * i; /* a symmetric grid through 0 */
        y[i] = 2.5 * exp(-0.7 * pow(fabs(x[i]), 1.3));
        e[i] = 0.02 * y[i];
    }
    gr_campaign_result r = {0};
    snprintf(r.transform, sizeof r.transform, "log_ratio");
    campaign_point p = {0};
    const int m = campaign_curve_transform(&r, &p, x, y, e, n);
    ck_assert_int_eq(m, 40); /* v = 0.1 ... 4.0 */
    ck_assert_double_eq_tol(x[0], 0.1, 1e-12);
    for (int i = 0; i < m; i++) {
        ck_assert_double_eq_tol(y[i], 0.7 * pow(x[i], 1.3), 1e-12);
        ck_assert_double_eq_tol(e[i], 0.02, 1e-12); /* d(-ln P) = dP / P */
    }
    gr_fit fit;
    gr_error err = {0};
    ck_assert_int_eq(gr_fit_power_law(x, y, NULL, m, &fit, &err), GR_OK);
    ck_assert_double_eq_tol(fit.p[1], 1.3, 1e-9);
    /* a Gaussian is the line of slope 2 */
    for (int i = 0; i < n; i++) {
        x[i] = -4.0 + 0.1 * i;
        y[i] = exp(-x[i] * x[i] / 2.0);
        e[i] = 0.0;
    }
    const int g = campaign_curve_transform(&r, &p, x, y, e, n);
    ck_assert_int_eq(gr_fit_power_law(x, y, NULL, g, &fit, &err), GR_OK);
    ck_assert_double_eq_tol(fit.p[1], 2.0, 1e-9);
    /* no bin on either side of 0: no P(0), no curve */
    double px[2] = {1.0, 2.0}, py[2] = {0.5, 0.1}, pe[2] = {0.0, 0.0};
    ck_assert_int_eq(campaign_curve_transform(&r, &p, px, py, pe, 2), 0);
}
END_TEST

/* scale_at (5.4, Fig. 5.3): every curve passes through (x0, 1); its shape and relative errors stay. */
START_TEST(test_scale_at_puts_every_curve_through_one)
{
    double x[5] = {0.0, 0.5, 1.0, 1.5, 2.0}, y[5], e[5];
    for (int i = 0; i < 5; i++) {
        y[i] = 3.0 * exp(-x[i] * x[i]);
        e[i] = 0.1 * y[i];
    }
    gr_campaign_result r = {0};
    snprintf(r.transform, sizeof r.transform, "scale_at");
    r.collapse_at = 1.25; /* between bins: ln y interpolated, exact for exp(-x^2) only at bins */
    campaign_point p = {0};
    ck_assert_int_eq(campaign_curve_transform(&r, &p, x, y, e, 5), 5);
    const double y125 = exp(0.5 * log(3.0 * exp(-1.0)) + 0.5 * log(3.0 * exp(-2.25)));
    for (int i = 0; i < 5; i++) {
        ck_assert_double_eq_tol(y[i], 3.0 * exp(-x[i] * x[i]) / y125, 1e-12);
        ck_assert_double_eq_tol(e[i], 0.1 * y[i], 1e-12);
    }
    r.collapse_at = 1.0;
    for (int i = 0; i < 5; i++) {
        y[i] = 3.0 * exp(-x[i] * x[i]);
    }
    ck_assert_int_eq(campaign_curve_transform(&r, &p, x, y, e, 5), 5);
    ck_assert_double_eq_tol(y[2], 1.0, 1e-12);
    r.collapse_at = 7.0; /* outside the curve */
    ck_assert_int_eq(campaign_curve_transform(&r, &p, x, y, e, 5), 0);
}
END_TEST

/* moment_scale (sec. 3.2.3, Figs. 3.6-3.7): v -> v / <|v|^m>^(1/m), P -> P <|v|^m>^(1/m). Gaussians of
 * any width are one family, so both widths land on one curve for any m: for m = 2 on the unit
 * normal, for m = 7 on it stretched by c = (<|z|^7>)^(1/7) = (2^3.5 3! / sqrt(pi))^(1/7). */
START_TEST(test_moment_scale_collapses_gaussians_of_any_width)
{
    const double c7 = pow(pow(2.0, 3.5) * 6.0 / sqrt(M_PI), 1.0 / 7.0);
    for (int m = 2; m <= 7; m += 5) {
        for (double sigma = 0.3; sigma < 3.0; sigma *= 4.0) {
            char json[256];
            snprintf(json, sizeof json,
                     "{\"analysis\": {\"moments\": {\"speed\": {\"m2\": %.17g, \"m7\": %.17g}}}}",
                     sigma * sigma, pow(sigma * c7, 7.0));
            campaign_point p = {.summary = cJSON_Parse(json)};
            ck_assert_ptr_nonnull(p.summary);
            gr_campaign_result r = {0};
            snprintf(r.transform, sizeof r.transform, "moment_scale");
            r.scale_moment = m;
            double x[4] = {0.0, 0.5 * sigma, sigma, 2.5 * sigma}, y[4], e[4];
            for (int i = 0; i < 4; i++) {
                y[i] = exp(-0.5 * x[i] * x[i] / (sigma * sigma)) / (sqrt(2.0 * M_PI) * sigma);
                e[i] = 0.01 * y[i];
            }
            ck_assert_int_eq(campaign_curve_transform(&r, &p, x, y, e, 4), 4);
            const double c = m == 2 ? 1.0 : c7; /* the unit normal, stretched by c */
            for (int i = 0; i < 4; i++) {
                const double z = c * x[i];
                ck_assert_double_eq_tol(y[i], c * exp(-0.5 * z * z) / sqrt(2.0 * M_PI), 1e-12);
                ck_assert_double_eq_tol(e[i], 0.01 * y[i], 1e-14);
            }
            r.scale_moment = 5; /* a moment the summary does not hold: the curve is left out */
            ck_assert_int_eq(campaign_curve_transform(&r, &p, x, y, e, 4), 0);
            cJSON_Delete(p.summary);
        }
    }
}
END_TEST

/* select: values of one key are alternatives, different keys must all hold. */
START_TEST(test_select_ors_one_key_and_ands_keys)
{
    const char *sel = "eps_n+eps_t=0.2/1.0, eps_n+eps_t=0.4/1.0";
    ck_assert(campaign_curve_selected(sel, "eps_n+eps_t=0.2/1.0"));
    ck_assert(campaign_curve_selected(sel, "eps_n+eps_t=0.4/1.0"));
    ck_assert(!campaign_curve_selected(sel, "eps_n+eps_t=0.4/0.1"));
    ck_assert(!campaign_curve_selected(sel, "eps_n+eps_t=0.2/1.00"));
    ck_assert(campaign_curve_selected("eps_n=0.1, eps_n=0.4, N=100", "eps_n=0.4, N=100"));
    ck_assert(!campaign_curve_selected("eps_n=0.1, eps_n=0.4, N=100", "eps_n=0.4, N=1000"));
    ck_assert(!campaign_curve_selected("eps_n=0.1, N=100", "eps_n=0.9, N=100"));
    ck_assert(campaign_curve_selected("", "anything"));
    /* "*" parts of a linked value match anything, the others exactly, part for part */
    const char *any_n = "N+eps_n+eps_t=*/0.4/1.0";
    ck_assert(campaign_curve_selected(any_n, "N+eps_n+eps_t=32000/0.4/1.0"));
    ck_assert(campaign_curve_selected(any_n, "N+eps_n+eps_t=375/0.4/1.0"));
    ck_assert(!campaign_curve_selected(any_n, "N+eps_n+eps_t=48000/0.2/1.0"));
    ck_assert(!campaign_curve_selected(any_n, "N+eps_n+eps_t=48000/0.4/1.00"));
    ck_assert(!campaign_curve_selected(any_n, "N+eps_n=32000/0.4"));
    ck_assert(!campaign_curve_selected("N+eps_n+eps_t=*/0.4", "N+eps_n+eps_t=32000/0.4/1.0"));
    ck_assert(campaign_curve_selected("N+eps_n+eps_t=48000/*/1.0", "N+eps_n+eps_t=48000/0.6/1.0"));
    ck_assert(!campaign_curve_selected("N+eps_n+eps_t=48000/*/1.0", "N+eps_n+eps_t=4800/0.6/1.0"));
    /* a key is the whole name before '=': N does not match N+L */
    ck_assert(!campaign_curve_selected("N=3000", "N+L=3000/0.2"));
}
END_TEST

/* overlay = power_law: the thesis's A k^-1.63 with only A fitted over the window. */
START_TEST(test_overlay_amplitude_with_fixed_exponent)
{
    enum { n = 30 };
    double x[n], y[n];
    for (int i = 0; i < n; i++) {
        x[i] = 10.0 * pow(1.1, i);
        y[i] = 5.0 * pow(x[i], -1.63) * (i % 2 ? 1.1 : 1.0 / 1.1); /* scatter around the line */
    }
    gr_campaign_result r = {0};
    r.overlay_exponent = -1.63;
    r.x_min = 12.0; /* x = 12.1 ... 108.3: 24 points */
    r.x_max = 110.0;
    /* ln A is the mean of ln y + 1.63 ln x over the window's points: here 5 (the +-ln 1.1 cancel
     * over an even count) */
    int in = 0;
    for (int i = 0; i < n; i++) {
        in += x[i] >= r.x_min && x[i] <= r.x_max;
    }
    ck_assert_int_eq(in % 2, 0);
    ck_assert_double_eq_tol(campaign_curve_overlay_amplitude(&r, x, y, n), 5.0, 1e-9);
    r.x_min = 1e6;
    r.x_max = 2e6;
    ck_assert(isnan(campaign_curve_overlay_amplitude(&r, x, y, n)));
}
END_TEST

START_TEST(test_series_from_table_with_filter)
{
    char dir[] = "/tmp/granule-curve-XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/gaps.csv", dir);
    FILE *f = fopen(path, "w");
    fprintf(f, "h,binning,R,density,density_error\n"
               "1,lin,0.5,9,1\n"
               "1,log,0.001,100,2\n"
               "2,log,0.001,50,3\n"
               "1,log,0.01,10,0.5\n");
    fclose(f);
    campaign_point p = {0};
    snprintf(p.dir, sizeof p.dir, "%s", dir);
    gr_campaign_result r = {0};
    snprintf(r.table, sizeof r.table, "gaps.csv");
    snprintf(r.where, sizeof r.where, "h=1, binning=log");
    snprintf(r.x, sizeof r.x, "R");
    snprintf(r.y, sizeof r.y, "density");
    snprintf(r.y_err, sizeof r.y_err, "density_error");
    double x[4096], y[4096], e[4096];
    ck_assert_int_eq(campaign_curve_series(&p, &r, x, y, e), 2);
    ck_assert_double_eq(x[0], 0.001);
    ck_assert_double_eq(y[0], 100.0);
    ck_assert_double_eq(e[0], 2.0);
    ck_assert_double_eq(x[1], 0.01);
    ck_assert_double_eq(y[1], 10.0);
    snprintf(r.where, sizeof r.where, "h=2, binning=log");
    ck_assert_int_eq(campaign_curve_series(&p, &r, x, y, e), 1);
    ck_assert_double_eq(y[0], 50.0);
    /* a placeholder takes the point's varied value: h = N / 512 (renormalisation, 3.25) */
    p.manifest = cJSON_Parse("{\"keys\": {\"system.N\": \"1024\"}}");
    snprintf(r.where, sizeof r.where, "h={system.N/512}, binning=log");
    ck_assert_int_eq(campaign_curve_series(&p, &r, x, y, e), 1);
    ck_assert_double_eq(y[0], 50.0);
    cJSON_Delete(p.manifest);
    p.manifest = NULL;
    snprintf(r.y, sizeof r.y, "no_such_column");
    ck_assert_int_eq(campaign_curve_series(&p, &r, x, y, e), 0);
    unlink(path);
    rmdir(dir);
}
END_TEST

/* A thesis value with no quoted error that ours equals to rounding (Table 3.1's zeta_1 = 1 came
 * out 0.999996 +- 1e-6, z = -3.9) is exact: no z. A real difference, or a quoted error, keeps it. */
START_TEST(test_exact_match_has_no_z)
{
    ck_assert(gr_campaign_exact_match(0.999996, 1.0, NAN));
    ck_assert(gr_campaign_exact_match(1.0, 1.0, 0.0));
    ck_assert(!gr_campaign_exact_match(0.999, 1.0, NAN));
    ck_assert(!gr_campaign_exact_match(1.0, 1.0, 0.01));
    ck_assert(!gr_campaign_exact_match(NAN, 1.0, NAN));
    ck_assert(!gr_campaign_exact_match(1e-9, 0.0, NAN)); /* no relative scale at 0 */
}
END_TEST

/* Kinds of comparison (docs/campaigns/README.md): only a thesis value with an error gives a z. */
static campaign_row judged(const char *thesis, double value, double error)
{
    static gr_campaign_result r;
    memset(&r, 0, sizeof r);
    snprintf(r.thesis, sizeof r.thesis, "%s", thesis);
    campaign_rows rows = {0};
    campaign_row *w = campaign_rows_add(&rows);
    snprintf(w->group, sizeof w->group, "eps_n=0.1");
    w->value = value;
    w->error = error;
    campaign_row_thesis(&r, w);
    campaign_row out = *w;
    campaign_rows_free(&rows);
    return out;
}

START_TEST(test_kinds_of_comparison)
{
    campaign_row w = judged("eps_n=0.1: 1.729 +- 0.008", 1.695, 0.012);
    ck_assert_str_eq(w.comparison, "z");
    ck_assert_double_eq_tol(w.z, (1.695 - 1.729) / hypot(0.012, 0.008), 1e-12);
    ck_assert_int_eq(w.agrees, -1);
    /* a value without an error: no z, within ours +- 2 errors and half its last digit */
    w = judged("eps_n=0.1: 0.528 (the constant fit)", 0.4987, 0.0095);
    ck_assert_str_eq(w.comparison, "stated");
    ck_assert(isnan(w.z));
    ck_assert_double_eq_tol(w.tolerance, 5e-4, 1e-15);
    ck_assert_int_eq(w.agrees, 0); /* 0.0293 > 2 x 0.0095 + 0.0005 */
    ck_assert_str_eq(w.thesis_note, "(the constant fit)");
    ck_assert_int_eq(judged("eps_n=0.1: 0.528", 0.51, 0.0095).agrees, 1);
    ck_assert_double_eq_tol(judged("eps_n=0.1: 7.78e-4", 7.78e-4, NAN).tolerance, 5e-7, 1e-20);
    ck_assert_double_eq_tol(judged("eps_n=0.1: 12", 0.24, 0.001).tolerance, 0.5, 1e-15);
    ck_assert_int_eq(judged("eps_n=0.1: 12", 0.24, 0.001).agrees, 0);
    /* about: to one significant figure */
    w = judged("eps_n=0.1: about 1 (one second)", 0.2, 0.05);
    ck_assert_str_eq(w.comparison, "about");
    ck_assert(isnan(w.z));
    ck_assert_int_eq(w.agrees, 0); /* 0.8 > 0.5 + 0.1 */
    ck_assert_int_eq(judged("eps_n=0.1: about 1", 0.999, 0.12).agrees, 1);
    /* a range */
    w = judged("eps_n=0.1: range 0.53 .. 0.667 (3.9)", 0.650, 0.002);
    ck_assert_str_eq(w.comparison, "range");
    ck_assert_double_eq(w.thesis_hi, 0.667);
    ck_assert_int_eq(w.agrees, 1);
    ck_assert_int_eq(judged("eps_n=0.1: range 0.53 .. 0.667", 0.70, 0.01).agrees, 0);
    /* a model's value and a quantity equal by construction */
    w = judged("eps_n=0.1: model 6.644 (bisection: log2 N)", 6.267, 0.016);
    ck_assert_str_eq(w.comparison, "model");
    ck_assert(isnan(w.z));
    ck_assert_int_eq(w.agrees, 0);
    w = judged("eps_n=0.1: exact -1.0 (by construction)", -1.0, 1e-9);
    ck_assert_str_eq(w.comparison, "construction");
    ck_assert(isnan(w.z));
    ck_assert_int_eq(w.agrees, -1);
    /* without an error of ours (one run) nothing is judged */
    w = judged("eps_n=0.1: 1.914", 1.899, NAN);
    ck_assert_str_eq(w.comparison, "stated");
    ck_assert_int_eq(w.agrees, -1);
    ck_assert_int_eq(judged("eps_n=0.1: about 1", 0.0, 0.0).agrees,
                     0); /* an error of 0 is an error */
    /* another group's value does not apply */
    ck_assert_str_eq(judged("eps_n=0.5: 0.528", 0.5, 0.01).comparison, "");
}
END_TEST

/* The local slopes and their trend (campaign_analyse.c): points whose local exponent grows as
 * xi(N) = xi0 + t ln(N / N_c), ln y = ln A - xi0 u - (t / 2) u^2 with u = ln(N / N_c), three
 * seeds at 0.99, 1 and 1.01 of the law (their mean exact). The trend row recovers t and the
 * exponent at the centre, the local slopes the exponent at each pair's midpoint in ln N, and so do
 * the wide ones (slope_span = 3) with a third of the error; with t = 0 the trend is 0 within its
 * error. */
START_TEST(test_local_slopes_and_their_trend)
{
    enum { NX = 6, NS = 3 };
    const double xs[NX] = {1000, 1585, 2512, 3981, 6310, 10000}, xi0 = 0.55;
    for (int pass = 0; pass < 2; pass++) {
        const double t = pass ? 0.0 : 0.02;
        double uc = 0.0;
        for (int j = 0; j < NX; j++) {
            uc += log(xs[j]) / NX;
        }
        campaign_point p[NX * NS];
        campaign_points pts = {.n = NX * NS, .p = p};
        memset(p, 0, sizeof p);
        for (int j = 0, k = 0; j < NX; j++) {
            const double u = log(xs[j]) - uc, law = 3.0 * exp(-xi0 * u - 0.5 * t * u * u);
            for (int s = 1; s <= NS; s++, k++) {
                char m[200], sm[256];
                snprintf(
                    m, sizeof m,
                    "{\"keys\": {\"model.eps_n\": \"0.1\", \"system.N\": \"%g\"}, \"seed\": %d}",
                    xs[j], s);
                snprintf(sm, sizeof sm,
                         "{\"analysis\": {\"moments\": {\"speed\": {\"m2\": %.17g}, "
                         "\"speed_stderr\": {\"m2\": %.17g}}}}",
                         law * (1.0 + 0.01 * (s - 2)), 0.001 * law);
                p[k].manifest = cJSON_Parse(m);
                p[k].summary = cJSON_Parse(sm);
            }
        }
        gr_campaign_result r = {0};
        snprintf(r.id, sizeof r.id, "fig");
        r.kind = GR_RESULT_POWER_LAW;
        snprintf(r.y, sizeof r.y, "analysis.moments.speed.m2");
        snprintf(r.y_err, sizeof r.y_err, "analysis.moments.speed_stderr.m2");
        snprintf(r.x, sizeof r.x, "system.N");
        snprintf(r.by, sizeof r.by, "model.eps_n");
        r.x_max = INFINITY;
        r.local_slopes = true;
        r.slope_span = pass ? 0 : 3;
        const int nw = pass ? 0 : NX - 3; /* wide pairs: 1000-3981, 1585-6310, 2512-10000 */
        char dir[] = "/tmp/granule-slopes-XXXXXX";
        ck_assert_ptr_nonnull(mkdtemp(dir));
        gr_file data;
        gr_error err = {0};
        ck_assert_int_eq(gr_file_open(&data, dir, "fig_data.csv", &err), GR_OK);
        campaign_rows rows = {0};
        ck_assert_int_eq(campaign_power_law(NULL, &r, &pts, &rows, &data, &err), GR_OK);
        ck_assert_int_eq(gr_file_commit(&data, &err), GR_OK);
        ck_assert_int_eq(rows.n, 1 + (NX - 1) + nw + 1); /* fit, local and wide slopes, trend */
        ck_assert_int_eq(rows.r[0].role, 0);
        for (int i = 1; i < NX; i++) { /* exact for a quadratic: the slope at the midpoint */
            const campaign_row *w = &rows.r[i];
            ck_assert_int_eq(w->role, 'l');
            const double mid = 0.5 * (log(w->x_lo) + log(w->x_hi)) - uc;
            ck_assert_double_eq_tol(w->value, xi0 + t * mid, 1e-9);
            /* each seed's factor is the same at both sizes: per seed the slope is exact, so the
             * seeds' own spread is 0 and the headline error the propagated one */
            ck_assert_int_eq(w->n_seeds, NS);
            ck_assert(w->error_seeds < 1e-9);
            ck_assert_double_eq(w->error, w->error_fit);
        }
        for (int i = NX; i < NX + nw; i++) { /* three sizes apart: a lever arm three times longer */
            const campaign_row *w = &rows.r[i];
            ck_assert_int_eq(w->role, 'w');
            ck_assert_double_eq_tol(w->x_hi, xs[i - NX + 3], 1e-9);
            const double mid = 0.5 * (log(w->x_lo) + log(w->x_hi)) - uc;
            ck_assert_double_eq_tol(w->value, xi0 + t * mid, 1e-9);
            ck_assert_double_eq_tol(w->error * log(w->x_hi / w->x_lo),
                                    rows.r[1].error * log(rows.r[1].x_hi / rows.r[1].x_lo), 1e-12);
        }
        const campaign_row *tr = &rows.r[NX + nw];
        ck_assert_int_eq(tr->role, 't');
        ck_assert_str_eq(tr->group, "eps_n=0.1, trend N=1000-10000");
        ck_assert_int_eq(tr->n_x, NX);
        ck_assert_double_eq_tol(tr->value, t, 1e-9);
        ck_assert_double_eq_tol(tr->centre_value, xi0, 1e-9);
        ck_assert_double_eq_tol(log(tr->centre_x), uc, 1e-12);
        /* each size's mean has the seeds' standard error 0.01 / sqrt(3) of y: the trend's error is
         * that of a quadratic's coefficient, finite and far below t = 0.02 */
        ck_assert(tr->error > 0.0 && tr->error < 0.01);
        ck_assert_int_eq(tr->n_seeds, NS);
        ck_assert(tr->error_seeds < 1e-9);
        /* the figure's table: the local slopes at their sizes' geometric means */
        campaign_slopes_plot(dir, &r, &rows);
        char path[300], line[256];
        snprintf(path, sizeof path, "%s/fig_slopes.dat", dir);
        FILE *f = fopen(path, "r");
        ck_assert_ptr_nonnull(f);
        int n = 0;
        double x, lo, hi, v, e;
        while (fgets(line, sizeof line, f) && line[0] != '\n') {
            if (sscanf(line, "%lf %lf %lf %lf %lf", &x, &lo, &hi, &v, &e) == 5) {
                ck_assert_double_eq_tol(x, sqrt(lo * hi), 1e-6 * x);
                n++;
            }
        }
        ck_assert_int_eq(n, NX - 1);
        int n_wide = 0;
        while (nw && fgets(line, sizeof line, f)) { /* the next block: the wide slopes */
            if (strstr(line, "wide_local_slope")) {
                while (fgets(line, sizeof line, f) && line[0] != '\n') {
                    n_wide += sscanf(line, "%lf %lf %lf %lf %lf", &x, &lo, &hi, &v, &e) == 5;
                }
                break;
            }
        }
        fclose(f);
        ck_assert_int_eq(n_wide, nw);
        for (int i = 0; i < pts.n; i++) {
            cJSON_Delete(p[i].manifest);
            cJSON_Delete(p[i].summary);
        }
        campaign_rows_free(&rows);
    }
}
END_TEST

/* Fig. 3.3's collapse (campaign_collapse.c): points y = lambda(b) x^-xi(b), a different exponent
 * per group b, three seeds scattered about it, come out as lambda(b) at every x, against 1 - b^2,
 * with the fit's exponent beside them; the figure's series has a block per x. */
START_TEST(test_collapse_compensates_each_group_by_its_own_exponent)
{
    enum { NB = 2, NX = 3, NS = 3 };
    const double b[NB] = {0.1, 0.9}, lambda[NB] = {4.0, 10.0}, xi[NB] = {0.5, 0.6};
    const double xs[NX] = {400, 1000, 2500};
    campaign_point p[NB * NX * NS];
    campaign_points pts = {.n = NB * NX * NS, .p = p};
    memset(p, 0, sizeof p);
    int k = 0;
    for (int i = 0; i < NB; i++) {
        for (int j = 0; j < NX; j++) {
            for (int s = 1; s <= NS; s++, k++) { /* seeds at 0.99, 1, 1.01 of the law: mean exact */
                const double y = lambda[i] * pow(xs[j], -xi[i]) * (1.0 + 0.01 * (s - 2));
                char m[256], sm[256];
                snprintf(
                    m, sizeof m,
                    "{\"keys\": {\"model.eps_n\": \"%g\", \"system.N\": \"%g\"}, \"seed\": %d}",
                    b[i], xs[j], s);
                snprintf(sm, sizeof sm,
                         "{\"analysis\": {\"moments\": {\"speed\": {\"m2\": %.17g}, "
                         "\"speed_stderr\": {\"m2\": %.17g}}}}",
                         y, 0.01 * y);
                p[k].manifest = cJSON_Parse(m);
                p[k].summary = cJSON_Parse(sm);
            }
        }
    }
    static gr_campaign c;
    memset(&c, 0, sizeof c);
    c.n_results = 2;
    gr_campaign_result *fit = &c.results[0], *col = &c.results[1];
    snprintf(fit->id, sizeof fit->id, "fig");
    fit->kind = GR_RESULT_POWER_LAW;
    snprintf(fit->y, sizeof fit->y, "analysis.moments.speed.m2");
    snprintf(fit->y_err, sizeof fit->y_err, "analysis.moments.speed_stderr.m2");
    snprintf(fit->x, sizeof fit->x, "system.N");
    snprintf(fit->by, sizeof fit->by, "model.eps_n");
    fit->x_max = INFINITY;
    snprintf(col->id, sizeof col->id, "collapsed");
    col->kind = GR_RESULT_COLLAPSE;
    snprintf(col->compensate, sizeof col->compensate, "fig");
    snprintf(col->against, sizeof col->against, "1-by^2");
    snprintf(col->quantity, sizeof col->quantity, "y N^xi");

    char dir[] = "/tmp/granule-collapse-XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    gr_file data;
    gr_error err = {0};
    ck_assert_int_eq(gr_file_open(&data, dir, "collapsed_data.csv", &err), GR_OK);
    campaign_rows rows = {0};
    ck_assert_int_eq(campaign_collapse(&c, col, &pts, &rows, dir, &data, &err), GR_OK);
    ck_assert_int_eq(gr_file_commit(&data, &err), GR_OK);
    ck_assert_int_eq(rows.n, NB * NX);
    for (int r = 0; r < rows.n; r++) { /* groups in order: b = 0.1 at every x, then 0.9 */
        const int i = r / NX, j = r % NX;
        char want[64];
        snprintf(want, sizeof want, "eps_n=%g, N=%g", b[i], xs[j]);
        ck_assert_str_eq(rows.r[r].group, want);
        ck_assert_double_eq_tol(rows.r[r].value, lambda[i], 1e-7 * lambda[i]); /* 9 digits */
        /* three seeds at 1 +- 0.01: the seeds' standard error 0.01 / sqrt(3), times x^xi */
        ck_assert_double_eq_tol(rows.r[r].error, 0.01 / sqrt(3.0) * lambda[i], 1e-7 * lambda[i]);
        ck_assert_int_eq(rows.r[r].n_seeds, NS);
    }
    /* the data table: the group's value, 1 - b^2, x, y, its exponent and the compensated y */
    char path[256], line[512];
    snprintf(path, sizeof path, "%s/collapsed_data.csv", dir);
    FILE *f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    ck_assert_ptr_nonnull(fgets(line, sizeof line, f));
    ck_assert_str_eq(line, "group,b,against,x,y,y_error,exponent,compensated,compensated_error\n");
    int rows_read = 0;
    while (fgets(line, sizeof line, f)) {
        double bb, against, x, y, e, ex, comp;
        ck_assert_int_eq(sscanf(strchr(line + 1, '"') + 1, ",%lf,%lf,%lf,%lf,%lf,%lf,%lf", &bb,
                                &against, &x, &y, &e, &ex, &comp),
                         7);
        const int i = bb > 0.5;
        ck_assert_double_eq_tol(against, 1.0 - b[i] * b[i], 1e-12);
        ck_assert_double_eq_tol(ex, xi[i], 1e-8);
        ck_assert_double_eq_tol(comp, y * pow(x, ex), 1e-7 * comp);
        rows_read++;
    }
    fclose(f);
    ck_assert_int_eq(rows_read, NB * NX);
    /* the figure's series: one block per x, titled, each along 1 - b^2 (0.19 before 0.99) */
    snprintf(path, sizeof path, "%s/collapsed_series.dat", dir);
    f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    int titles = 0;
    double last = -1.0;
    while (fgets(line, sizeof line, f)) {
        double a, v, e;
        if (line[0] == '"') {
            titles++;
            last = -1.0;
        } else if (sscanf(line, "%lf %lf %lf", &a, &v, &e) == 3) {
            ck_assert(a > last);
            last = a;
        }
    }
    fclose(f);
    ck_assert_int_eq(titles, NX);
    /* two points in the window: no exponent, so a row per point without a value, as the fit's */
    fit->x_min = 1000;
    campaign_rows_free(&rows);
    ck_assert_int_eq(gr_file_open(&data, dir, "collapsed_data.csv", &err), GR_OK);
    ck_assert_int_eq(campaign_collapse(&c, col, &pts, &rows, dir, &data, &err), GR_OK);
    ck_assert_int_eq(gr_file_commit(&data, &err), GR_OK);
    ck_assert_int_eq(rows.n, NB * 2);
    for (int r = 0; r < rows.n; r++) {
        ck_assert(isnan(rows.r[r].value));
        ck_assert_int_eq(rows.r[r].n_seeds, NS);
    }
    for (int i = 0; i < pts.n; i++) {
        cJSON_Delete(p[i].manifest);
        cJSON_Delete(p[i].summary);
    }
    campaign_rows_free(&rows);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ck_assert_int_eq(system(cmd), 0);
}
END_TEST

/* A collapse needs a power law of the same campaign to take its exponents from, and one of the
 * two abscissae: anything else is refused at load, naming the result and what it needs. */
START_TEST(test_collapse_refused_without_a_power_law)
{
    static const char *const bad[][2] = {
        {"compensate = means", "needs compensate = the id of a power_law result"},
        {"compensate = nothing", "needs compensate = the id of a power_law result"},
        {"compensate = fit\nagainst = b^2", "against = b^2: allowed by, 1-by^2"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char path[] = "/tmp/granule-collapse-XXXXXX.ini";
        int fd = mkstemps(path, 4);
        ck_assert_int_ge(fd, 0);
        FILE *f = fdopen(fd, "w");
        fprintf(f,
                "[campaign]\ntitle = t\nscene = rfm-1d.ini\n[vary.full]\nsystem.N = 100, 200\n"
                "[vary.quick]\nsystem.N = 100, 200\n"
                "[result fit]\nkind = power_law\ny = analysis.moments.speed.m2\nx = system.N\n"
                "by = model.eps_n\n"
                "[result means]\nkind = mean\ny = analysis.moments.speed.m2\n"
                "[result col]\nkind = collapse\n%s\n",
                bad[k][0]);
        fclose(f);
        static gr_campaign c;
        gr_error err = {0};
        ck_assert_int_ne(gr_campaign_load(&c, path, &err), GR_OK);
        ck_assert_msg(strstr(err.message, "[result col]") && strstr(err.message, bad[k][1]), "%s",
                      err.message);
        unlink(path);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("campaign_curve");
    TCase *t = tcase_create("curve");
    tcase_add_test(t, test_collapse_of_uniform_bisection_is_minus_ln_R);
    tcase_add_test(t, test_collapse_detects_another_power);
    tcase_add_test(t, test_log_ratio_turns_a_stretched_exponential_into_its_exponent);
    tcase_add_test(t, test_scale_at_puts_every_curve_through_one);
    tcase_add_test(t, test_moment_scale_collapses_gaussians_of_any_width);
    tcase_add_test(t, test_select_ors_one_key_and_ands_keys);
    tcase_add_test(t, test_overlay_amplitude_with_fixed_exponent);
    tcase_add_test(t, test_series_from_table_with_filter);
    tcase_add_test(t, test_exact_match_has_no_z);
    tcase_add_test(t, test_kinds_of_comparison);
    tcase_add_test(t, test_local_slopes_and_their_trend);
    tcase_add_test(t, test_collapse_compensates_each_group_by_its_own_exponent);
    tcase_add_test(t, test_collapse_refused_without_a_power_law);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
