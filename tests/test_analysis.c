/* The shared analysis primitives: block averaging, histograms (App. A.1) and GSL fits, checked
 * against analytic answers and synthetic data with known parameters (fixed seeds). */
#include <check.h>
#include <cjson/cJSON.h>
#include <stdio.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"

START_TEST(test_blocking_white_noise)
{
    /* independent samples: the error of the mean is sigma / sqrt(n) at every level */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    gr_blocking b;
    gr_blocking_init(&b);
    const int n = 1 << 16;
    for (int i = 0; i < n; i++) {
        gr_blocking_add(&b, 3.0 + gsl_ran_gaussian(r, 2.0));
    }
    double expect = 2.0 / sqrt((double)n);
    ck_assert_msg(fabs(gr_blocking_mean(&b) - 3.0) < 5.0 * expect, "mean %g", gr_blocking_mean(&b));
    /* level 0 error estimate has relative precision ~1/sqrt(2n) */
    ck_assert_msg(fabs(gr_blocking_stderr_at(&b, 0) / expect - 1.0) < 0.02,
                  "level-0 error %g vs %g", gr_blocking_stderr_at(&b, 0), expect);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_blocking_correlated)
{
    /* AR(1) with a = 0.9: the true error of the mean is larger than the naive one by
     * sqrt((1 + a)/(1 - a)) = sqrt(19); blocking must find it, the naive level must not */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    gr_blocking b;
    gr_blocking_init(&b);
    const int n = 1 << 18;
    const double a = 0.9;
    double x = 0.0;
    for (int i = 0; i < n; i++) {
        x = a * x + gsl_ran_gaussian(r, 1.0);
        gr_blocking_add(&b, x);
    }
    double var = 1.0 / (1.0 - a * a);
    double naive = sqrt(var / n), truth = naive * sqrt((1.0 + a) / (1.0 - a));
    int level, converged;
    double e = gr_blocking_stderr(&b, &level, &converged);
    ck_assert_msg(fabs(gr_blocking_stderr_at(&b, 0) / naive - 1.0) < 0.05, "naive level %g vs %g",
                  gr_blocking_stderr_at(&b, 0), naive);
    ck_assert_msg(e > 0.8 * truth && e < 1.5 * truth, "blocking error %g, true %g", e, truth);
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_histogram_density)
{
    gr_histogram h;
    gr_error err = {0};
    ck_assert_int_eq(gr_histogram_init(&h, 10, 0.0, 1.0, false, &err), 0);
    for (int i = 0; i < 1000; i++) {
        gr_histogram_add(&h, (i + 0.5) / 1000.0, 1.0);
    }
    gr_histogram_add(&h, -1.0, 1.0);
    gr_histogram_add(&h, 2.0, 1.0);
    double integral = 0.0;
    for (int i = 0; i < h.nbins; i++) {
        ck_assert_double_eq_tol(h.count[i], 100.0, 1e-12);
        integral +=
            gr_histogram_density(&h, i) * (gr_histogram_upper(&h, i) - gr_histogram_lower(&h, i));
        ck_assert_double_eq_tol(gr_histogram_density_error(&h, i), sqrt(100.0) / (1002.0 * 0.1),
                                1e-12);
    }
    /* normalised to every sample, so the in-range integral is 1000/1002 */
    ck_assert_double_eq_tol(integral, 1000.0 / 1002.0, 1e-12);
    ck_assert_double_eq(h.below, 1.0);
    ck_assert_double_eq(h.above, 1.0);
    gr_histogram_free(&h);
    /* log bins: edges geometric, centre the geometric mean */
    ck_assert_int_eq(gr_histogram_init(&h, 4, 1.0, 1e4, true, &err), 0);
    ck_assert_double_eq_tol(gr_histogram_lower(&h, 2), 100.0, 1e-9);
    ck_assert_double_eq_tol(gr_histogram_center(&h, 0), sqrt(10.0), 1e-12);
    gr_histogram_add(&h, 999.0, 1.0);
    ck_assert_double_eq(h.count[2], 1.0);
    gr_histogram_free(&h);
    ck_assert_int_eq(gr_histogram_init(&h, 4, 0.0, 1.0, true, &err), GR_EINVAL);
}
END_TEST

START_TEST(test_power_law_fit)
{
    /* y = 2 x^-1.5 with 1% errors: recovered within 3 reported sigma, chi2/dof near 1 */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 3);
    enum { N = 40 };
    double x[N], y[N], s[N];
    for (int i = 0; i < N; i++) {
        x[i] = pow(10.0, 2.0 * i / (N - 1));
        double t = 2.0 * pow(x[i], -1.5);
        s[i] = 0.01 * t;
        y[i] = t + gsl_ran_gaussian(r, s[i]);
    }
    gr_fit f;
    gr_error err = {0};
    ck_assert_int_eq(gr_fit_power_law(x, y, s, N, &f, &err), 0);
    ck_assert_msg(fabs(f.p[1] + 1.5) < 3.0 * f.err[1], "b = %g +- %g", f.p[1], f.err[1]);
    ck_assert_msg(fabs(f.p[0] - 2.0) < 3.0 * f.err[0], "A = %g +- %g", f.p[0], f.err[0]);
    ck_assert_msg(f.chi2_red > 0.5 && f.chi2_red < 1.6, "chi2/dof = %g", f.chi2_red);
    gsl_rng_free(r);
}
END_TEST

/* Runs at the same x are averaged before the fit; the mean's sigma is the seeds' standard error
 * (here larger than the runs' own errors) and a run with no value is left out. */
START_TEST(test_power_law_fit_over_seeds)
{
    const double Ns[4] = {100, 200, 400, 800};
    double x[13], y[13], e[13];
    int n = 0;
    for (int i = 0; i < 4; i++) {
        for (int s = 0; s < 3; s++) { /* three seeds: +-5 % around 2 N^-0.5 */
            x[n] = Ns[i];
            y[n] = 2.0 * pow(Ns[i], -0.5) * (1.0 + 0.05 * (s - 1));
            e[n++] = 1e-6;
        }
    }
    x[n] = 1600;
    y[n] = NAN; /* a failed run */
    e[n++] = NAN;
    gr_fit fit;
    gr_error err = {0};
    int n_x = 0;
    ck_assert_int_eq(gr_fit_power_law_seeds(x, y, e, n, &fit, &n_x, &err), GR_OK);
    ck_assert_int_eq(n_x, 4);
    ck_assert_double_eq_tol(fit.p[1], -0.5, 1e-12); /* the seeds' means lie exactly on the law */
    ck_assert_double_eq_tol(fit.p[0], 2.0, 1e-10);
    /* the error of each mean is the seeds' standard error, 0.05 y / sqrt(3) (relative), not 1e-6 */
    gr_fit plain;
    double mx[4], my[4], ms[4];
    for (int i = 0; i < 4; i++) {
        mx[i] = Ns[i];
        my[i] = 2.0 * pow(Ns[i], -0.5);
        ms[i] = 0.05 * my[i] / sqrt(3.0);
    }
    ck_assert_int_eq(gr_fit_power_law(mx, my, ms, 4, &plain, &err), GR_OK);
    ck_assert_double_eq_tol(fit.err[1], plain.err[1], 1e-12);
    /* two sizes are not a fit */
    ck_assert_int_eq(gr_fit_power_law_seeds(x, y, e, 6, &fit, &n_x, &err), GR_EINVAL);
    ck_assert_int_eq(n_x, 2);
}
END_TEST

START_TEST(test_stretched_exp_fit)
{
    /* physics notes sec. 6.2: A = 1, tau = 2.5, beta = 0.6, 200 points, 1% noise, from
     * (0.5, 10, 1): recovered within 3 reported sigma */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    enum { N = 200 };
    double x[N], y[N], s[N];
    for (int i = 0; i < N; i++) {
        x[i] = 0.05 + 20.0 * i / N;
        double t = exp(-pow(x[i] / 2.5, 0.6));
        s[i] = 0.01 * t;
        y[i] = t + gsl_ran_gaussian(r, s[i]);
    }
    gr_fit f;
    gr_error err = {0};
    const double p0[3] = {0.5, 10.0, 1.0};
    ck_assert_msg(gr_fit_stretched_exp(x, y, s, N, p0, &f, &err) == 0, "%s", err.message);
    ck_assert_msg(fabs(f.p[0] - 1.0) < 3.0 * f.err[0], "A = %g +- %g", f.p[0], f.err[0]);
    ck_assert_msg(fabs(f.p[1] - 2.5) < 3.0 * f.err[1], "tau = %g +- %g", f.p[1], f.err[1]);
    ck_assert_msg(fabs(f.p[2] - 0.6) < 3.0 * f.err[2], "beta = %g +- %g", f.p[2], f.err[2]);
    ck_assert_msg(f.chi2_red > 0.7 && f.chi2_red < 1.4, "chi2/dof = %g", f.chi2_red);
    gsl_rng_free(r);
}
END_TEST

/* Two particles on a ring of length L, elastic, no noise, approaching at +-v: they collide, part,
 * travel round and collide again on the other side (the ring's wrap pair). Between collisions each
 * crosses half the free length, so every free path is (L - 2d)/2, to within a step's travel v dt. */
START_TEST(test_contact_events_and_free_path)
{
    extern const gr_observable_type gr_obs_freepath;
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = 1;
    sc.N = 2;
    sc.L = 0.1;
    sc.D = 0.0;
    sc.noise_mode = GR_NOISE_NONE;
    sc.contact.eps_n = 1.0;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "freepath_bins", 400, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "freepath_min", 1.0, NULL), GR_OK);
    const double d = 2.0 * sc.radius, v = 0.5;
    double x[2] = {0.02, 0.02 + d + 0.01}, vx[2] = {v, -v};
    gr_sim *s;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create_with_state(&sc, 2, x, NULL, vx, NULL, &s, &err) == 0, "%s",
                  err.message);
    ck_assert_int_eq(gr_sim_track_contacts(s, &err), 0);
    void *state;
    ck_assert_int_eq(gr_scene_observable(&gr_obs_freepath, &sc, &state, &err), 0);
    /* first contact after 0.01 / (2v), then one every (L - 2d)/(2v): run through 5 contacts */
    int64_t steps =
        (int64_t)((0.01 / (2.0 * v) + 4.5 * (sc.L - 2.0 * d) / (2.0 * v)) / gr_sim_dt(s));
    ck_assert_int_eq(gr_sim_step(s, steps, &err), 0);
    int64_t n;
    const gr_contact_event *ev = gr_sim_events(s, &n);
    int starts = 0, ends = 0;
    for (int64_t k = 0; k < n; k++) {
        starts += ev[k].kind > 0;
        ends += ev[k].kind < 0;
    }
    /* 5 collisions, each starts and ends a contact for both particles */
    ck_assert_int_eq(gr_sim_collisions(s), 5);
    ck_assert_int_eq(starts, 10);
    ck_assert_int_eq(ends, 10);
    ck_assert_int_eq(gr_obs_freepath.events(state, ev, n, &err), 0);
    /* 4 free paths per particle (the first contact has no preceding end) */
    char tmpl[] = "/tmp/granule-fp-XXXXXX";
    char *dir = mkdtemp(tmpl);
    ck_assert_ptr_nonnull(dir);
    cJSON *sum = cJSON_CreateObject();
    gr_output out = {
        .dir = dir, .source = sc.source, .seed = sc.seed, .summary = sum, .plots = false};
    ck_assert_int_eq(gr_obs_freepath.finish(state, &out, &err), 0);
    const cJSON *j = cJSON_GetObjectItem(sum, "freepath");
    ck_assert_int_eq((int)cJSON_GetObjectItem(j, "paths")->valuedouble, 8);
    double mean = cJSON_GetObjectItem(j, "mean_over_d")->valuedouble * d;
    double expect = 0.5 * (sc.L - 2.0 * d), tol = 2.0 * v * gr_sim_dt(s) + 2e-3 * d;
    ck_assert_msg(fabs(mean - expect) < tol, "mean free path %.9g, expected %.9g +- %.3g", mean,
                  expect, tol);
    cJSON_Delete(sum);
    gr_observable_free(state);
    gr_sim_free(s);
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ck_assert_int_eq(system(cmd), 0);
}
END_TEST

/* exact data: the fit must still succeed (zero residual never meets relative tolerances) */
START_TEST(test_stretched_exp_exact_data)
{
    enum { N = 50 };
    double x[N], y[N];
    for (int i = 0; i < N; i++) {
        x[i] = 0.1 + 0.2 * i;
        y[i] = 2.0 * exp(-pow(x[i] / 1.5, 0.8));
    }
    gr_fit f;
    gr_error err = {0};
    const double p0[3] = {1.0, 1.0, 1.0};
    ck_assert_msg(gr_fit_stretched_exp(x, y, NULL, N, p0, &f, &err) == 0, "%s", err.message);
    ck_assert_double_eq_tol(f.p[0], 2.0, 1e-8);
    ck_assert_double_eq_tol(f.p[1], 1.5, 1e-8);
    ck_assert_double_eq_tol(f.p[2], 0.8, 1e-8);
}
END_TEST

/* Coverage: over many synthetic data sets the reported 1-sigma errors must contain the true
 * parameter about 68.3 % of the time (binomial 3-sigma band for 400 trials: +-7 %). */
START_TEST(test_fit_error_coverage)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 17);
    enum { TRIALS = 400, N = 30 };
    int cover_b = 0, cover_beta = 0;
    gr_error err = {0};
    for (int k = 0; k < TRIALS; k++) {
        double x[N], y[N], s[N];
        for (int i = 0; i < N; i++) {
            x[i] = pow(10.0, 2.0 * i / (N - 1));
            double t = 3.0 * pow(x[i], -0.7);
            s[i] = 0.02 * t;
            y[i] = t + gsl_ran_gaussian(r, s[i]);
        }
        gr_fit f;
        ck_assert_int_eq(gr_fit_power_law(x, y, s, N, &f, &err), 0);
        cover_b += fabs(f.p[1] + 0.7) <= f.err[1];
        for (int i = 0; i < N; i++) {
            x[i] = 0.2 + 0.3 * i;
            double t = 1.0 * exp(-pow(x[i] / 2.0, 0.8));
            s[i] = 0.01 * t + 1e-4;
            y[i] = t + gsl_ran_gaussian(r, s[i]);
        }
        const double p0[3] = {0.8, 1.5, 1.0};
        ck_assert_int_eq(gr_fit_stretched_exp(x, y, s, N, p0, &f, &err), 0);
        cover_beta += fabs(f.p[2] - 0.8) <= f.err[2];
    }
    double fb = (double)cover_b / TRIALS, fbeta = (double)cover_beta / TRIALS;
    /* the errors are scaled by max(1, sqrt(chi2/dof)), which can only widen them: allow up to 80 % */
    ck_assert_msg(fb > 0.61 && fb < 0.80, "power-law exponent covered in %.3f of trials", fb);
    ck_assert_msg(fbeta > 0.61 && fbeta < 0.80,
                  "stretched-exponential beta covered in %.3f of trials", fbeta);
    gsl_rng_free(r);
}
END_TEST

/* The moments observable on Gaussian velocities: 2D speeds are Rayleigh distributed, so
 * <|v|^m> = (2 s^2)^(m/2) Gamma(1 + m/2) for per-component variance s^2 (the frame mean is removed,
 * a relative correction of order 1/N). */
/* Every registered observable: a complete type, its parameter struct inside its block of the
 * scene's gr_analysis_params, its keys unique, defaults readable by key (gr_analysis_get) and
 * settable (gr_analysis_set); an oversized parameter struct is refused by the skeleton. */
START_TEST(test_registry_parameter_blocks)
{
    gr_analysis_params a;
    gr_analysis_defaults(&a);
    int n = 0;
    for (int o = 0; gr_observables[o]; o++, n++) {
        const gr_observable_type *t = gr_observables[o];
        ck_assert_msg(t->init && t->sample && t->finish && t->state_size > 0, "%s: incomplete type",
                      t->name);
        ck_assert_msg(t->dims >= 1 && t->dims <= 7, "%s: dims = %u", t->name,
                      t->dims); /* 1D, 2D, 3D bits */
        ck_assert_msg(t->params_size <= GR_OBS_PARAMS_BYTES, "%s: %zu-byte parameters", t->name,
                      t->params_size);
        ck_assert_ptr_eq(gr_observable_find(t->name), t);
        ck_assert_ptr_nonnull(gr_analysis_block(&a, t));
        for (int k = 0; k < t->n_params; k++) {
            const gr_param *p = &t->params[k];
            size_t size = p->type == GR_PARAM_BOOL  ? sizeof(bool)
                          : p->type == GR_PARAM_INT ? sizeof(int)
                                                    : sizeof(double);
            ck_assert_msg(p->offset + size <= t->params_size, "%s: %s outside its parameter struct",
                          t->name, p->name);
            for (int q = 0; q <= o; q++) {
                for (int m = 0; m < (q < o ? gr_observables[q]->n_params : k); m++) {
                    ck_assert_msg(strcmp(gr_observables[q]->params[m].name, p->name) != 0,
                                  "key %s declared twice", p->name);
                }
            }
            double v = NAN;
            ck_assert_int_eq(gr_analysis_get(&a, p->name, &v, NULL), GR_OK);
            double def = p->type == GR_PARAM_INT    ? (double)(int)p->def
                         : p->type == GR_PARAM_BOOL ? (double)(p->def != 0.0)
                                                    : p->def;
            ck_assert_msg(v == def, "%s: default %g read back as %g", p->name, p->def, v);
            ck_assert_int_eq(gr_analysis_set(&a, p->name, p->max, NULL), GR_OK);
            ck_assert_int_eq(gr_analysis_get(&a, p->name, &v, NULL), GR_OK);
            ck_assert_msg(v == (p->type == GR_PARAM_BOOL ? 1.0 : p->max), "%s: set %g, read %g",
                          p->name, p->max, v);
        }
    }
    ck_assert_int_le(n, GR_OBS_MAX);
    gr_error err = {0};
    double v;
    ck_assert_int_eq(gr_analysis_get(&a, "no_such_key", &v, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "no_such_key"));
    gr_observable_type big = *gr_observables[0];
    big.params_size = GR_OBS_PARAMS_BYTES + 1;
    gr_scene sc;
    gr_scene_default(&sc);
    void *st = &big;
    ck_assert_int_eq(gr_scene_observable(&big, &sc, &st, &err), GR_EINVAL);
    ck_assert_ptr_null(st);
    ck_assert_ptr_nonnull(strstr(err.message, "GR_OBS_PARAMS_BYTES"));
}
END_TEST

START_TEST(test_moments_gaussian)
{
    extern const gr_observable_type gr_obs_moments;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 23);
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = 2;
    sc.N = 20000;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "moments_max", 6, NULL), GR_OK);
    void *state;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_observable(&gr_obs_moments, &sc, &state, &err), 0);
    double *vx = malloc(sizeof(double) * sc.N), *vy = malloc(sizeof(double) * sc.N),
           *x = calloc(sc.N, sizeof(double));
    const double sd = 0.3;
    for (int frame = 0; frame < 32; frame++) {
        for (int i = 0; i < sc.N; i++) {
            vx[i] = gsl_ran_gaussian(r, sd);
            vy[i] = gsl_ran_gaussian(r, sd);
        }
        gr_particles p = {.n = sc.N,
                          .dim = 2,
                          .L = 1.0,
                          .radius = 1e-3,
                          .mass = 1.0,
                          .x = x,
                          .y = x,
                          .vx = vx,
                          .vy = vy};
        ck_assert_int_eq(gr_obs_moments.sample(state, &p, 0.0, &err), 0);
    }
    char tmpl[] = "/tmp/granule-mom-XXXXXX";
    char *dir = mkdtemp(tmpl);
    cJSON *sum = cJSON_CreateObject();
    gr_output out = {
        .dir = dir, .source = sc.source, .seed = sc.seed, .summary = sum, .plots = false};
    ck_assert_int_eq(gr_obs_moments.finish(state, &out, &err), 0);
    const cJSON *speed = cJSON_GetObjectItem(cJSON_GetObjectItem(sum, "moments"), "speed");
    const cJSON *speed_err =
        cJSON_GetObjectItem(cJSON_GetObjectItem(sum, "moments"), "speed_stderr");
    for (int m = 1; m <= 6; m++) {
        char key[8];
        snprintf(key, sizeof key, "m%d", m);
        double got = cJSON_GetObjectItem(speed, key)->valuedouble,
               e = cJSON_GetObjectItem(speed_err, key)->valuedouble;
        double want = pow(2.0 * sd * sd, 0.5 * m) * tgamma(1.0 + 0.5 * m);
        ck_assert_msg(fabs(got - want) < 5.0 * e + 1e-3 * want,
                      "m = %d: %.6g +- %.2g, Rayleigh %.6g", m, got, e, want);
    }
    cJSON_Delete(sum);
    gr_observable_free(state);
    free(vx);
    free(vy);
    free(x);
    gsl_rng_free(r);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ck_assert_int_eq(system(cmd), 0);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("analysis");
    TCase *t = tcase_create("primitives");
    tcase_set_timeout(t, 120);
    tcase_add_test(t, test_blocking_white_noise);
    tcase_add_test(t, test_blocking_correlated);
    tcase_add_test(t, test_histogram_density);
    tcase_add_test(t, test_power_law_fit);
    tcase_add_test(t, test_power_law_fit_over_seeds);
    tcase_add_test(t, test_stretched_exp_fit);
    tcase_add_test(t, test_contact_events_and_free_path);
    tcase_add_test(t, test_stretched_exp_exact_data);
    tcase_add_test(t, test_fit_error_coverage);
    tcase_add_test(t, test_moments_gaussian);
    tcase_add_test(t, test_registry_parameter_blocks);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
