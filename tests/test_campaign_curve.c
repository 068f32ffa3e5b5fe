/* The curve analysis of reproduction campaigns (src/reproduce/campaign_curve.c): a run's series is
 * read from its table with the `where` filter, and the bisection collapse (thesis 3.39-3.40) maps
 * the uniform bisection process's distribution G_1 = A (-ln R)^(n-1) (3.36) onto the line -ln R. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/analysis.h"
#include "reproduce/campaign_points.h"
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
        ck_assert_double_eq_tol(e[i], 0.01 * y[i] / (nb - 1.0), 1e-12 * y[i]); /* dY = Y dG / ((n-1) G) */
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

int main(void)
{
    Suite *s = suite_create("campaign_curve");
    TCase *t = tcase_create("curve");
    tcase_add_test(t, test_collapse_of_uniform_bisection_is_minus_ln_R);
    tcase_add_test(t, test_collapse_detects_another_power);
    tcase_add_test(t, test_series_from_table_with_filter);
    tcase_add_test(t, test_exact_match_has_no_z);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
