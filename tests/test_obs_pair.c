/* The pair observable (g(R) 4.10, C(R) 4.15, n(R) 4.17, D_f), driven directly through its type's
 * functions on synthetic 2D configurations with fixed seeds:
 *   - an ideal gas (uniform random points) gives g = 1 within errors (chi-square), errors that
 *     match the exact binomial spread of the counts, and n(R) = 0;
 *   - a square lattice gives peaks at 1, sqrt 2, 2 lattice units with 4 neighbours each;
 *   - the cell-list pair counts equal a brute-force count (clustered and uniform points, positions
 *     outside [0, L), few and many cells);
 *   - with R_max = L/2 the pairs counted plus the brute-force pairs beyond L/2 (the box corners)
 *     are N(N-1)/2 per frame, and g integrates back to the counts;
 *   - points on a line give D_f = 1;
 *   - bad parameters and bad frames are refused.
 * PAIR_TEST_VERBOSE=1 prints the ideal-gas and line statistics the bounds are checked against. */
#include <check.h>
#include <cjson/cJSON.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/observe.h"
#include "granule/scene.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_pair;

typedef struct row {
    double R, Rd, g, ge, C, n, ne, lo, hi, pairs;
} row;

typedef struct result {
    int nrows;
    row *rows;
    cJSON *summary; /* the "analysis" object; "pair" inside */
    cJSON *pair;
} result;

static void make_scene(gr_scene *sc, int N, double L, double radius, int bins, double rmax)
{
    gr_scene_default(sc);
    sc->dim = 2;
    sc->N = N;
    sc->L = L;
    sc->radius = radius;
    ck_assert_int_eq(gr_analysis_set(&sc->analysis, "gr_bins", bins, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc->analysis, "gr_rmax", rmax, NULL), GR_OK);
    snprintf(sc->source, sizeof sc->source, "test_obs_pair");
}

static double param(const gr_scene *sc, const char *key)
{
    double v = NAN;
    ck_assert_int_eq(gr_analysis_get(&sc->analysis, key, &v, NULL), GR_OK);
    return v;
}

static int gr_bins(const gr_scene *sc) { return (int)param(sc, "gr_bins"); }

static double r_max(const gr_scene *sc)
{
    return fmin(param(sc, "gr_rmax") * 2.0 * sc->radius, 0.5 * sc->L);
}

static double num(const cJSON *o, const char *path1, const char *path2);

static void *create_ok(const gr_scene *sc)
{
    void *st = NULL;
    gr_error err = {0};
    int rc = gr_scene_observable(&gr_obs_pair, sc, &st, &err);
    ck_assert_msg(rc == GR_OK, "create: %s", err.message);
    return st;
}

static void sample_ok(void *st, const gr_scene *sc, const double *x, const double *y)
{
    gr_particles p = {
        .n = sc->N, .dim = 2, .L = sc->L, .radius = sc->radius, .mass = 1.0, .x = x, .y = y};
    gr_error err = {0};
    int rc = gr_obs_pair.sample(st, &p, 0.0, &err);
    ck_assert_msg(rc == GR_OK, "sample: %s", err.message);
}

/* finish into a fresh folder, read pair.csv and keep the summary */
static result finish_read(void *st, const gr_scene *sc)
{
    char dir[] = "/tmp/test_obs_pair_XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    result r = {0};
    r.summary = cJSON_CreateObject();
    gr_output out = {.dir = dir,
                     .source = sc->source,
                     .seed = sc->seed,
                     .scene_hash = 1,
                     .summary = r.summary,
                     .plots = false};
    gr_error err = {0};
    int rc = gr_obs_pair.finish(st, &out, &err);
    ck_assert_msg(rc == GR_OK, "finish: %s", err.message);
    gr_observable_free(st);
    r.pair = cJSON_GetObjectItem(r.summary, "pair");
    ck_assert_ptr_nonnull(r.pair);
    char path[256], line[1024];
    snprintf(path, sizeof path, "%s/pair.csv", dir);
    FILE *f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    int cap = 64;
    r.rows = malloc(sizeof(row) * (size_t)cap);
    bool header = false;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            continue;
        }
        if (!header) {
            ck_assert_msg(strncmp(line, "R,R_over_d,g,g_error,C,n,", 25) == 0, "header %s", line);
            header = true;
            continue;
        }
        if (r.nrows == cap) {
            cap *= 2;
            r.rows = realloc(r.rows, sizeof(row) * (size_t)cap);
        }
        row *w = &r.rows[r.nrows++];
        int got = sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &w->R, &w->Rd, &w->g,
                         &w->ge, &w->C, &w->n, &w->ne, &w->lo, &w->hi, &w->pairs);
        ck_assert_int_eq(got, 10);
    }
    fclose(f);
    remove(path);
    rmdir(dir);
    ck_assert_int_eq(r.nrows, num(r.pair, "frames", NULL) > 0 ? gr_bins(sc) : 0);
    return r;
}

static void result_free(result *r)
{
    free(r->rows);
    cJSON_Delete(r->summary);
}

static double num(const cJSON *o, const char *path1, const char *path2)
{
    const cJSON *it = cJSON_GetObjectItem(o, path1);
    if (path2) {
        it = cJSON_GetObjectItem(it, path2);
    }
    ck_assert_msg(it != NULL, "summary has no %s%s%s", path1, path2 ? "." : "", path2 ? path2 : "");
    return cJSON_IsNumber(it) ? it->valuedouble : (double)NAN;
}

static void uniform(gsl_rng *rng, int n, double L, double *x, double *y)
{
    for (int i = 0; i < n; i++) {
        x[i] = L * gsl_rng_uniform(rng);
        y[i] = L * gsl_rng_uniform(rng);
    }
}

/* brute-force histogram with the observable's binning: b = floor(R nbins / R_max), R < R_max;
 * returns the pairs at R >= R_max */
static long long brute(const gr_scene *sc, const double *x, const double *y, double *hist)
{
    double L = sc->L, rm = r_max(sc), inv = gr_bins(sc) / rm;
    long long beyond = 0;
    for (int i = 0; i < sc->N; i++) {
        for (int j = i + 1; j < sc->N; j++) {
            double dx = x[j] - x[i], dy = y[j] - y[i];
            dx -= L * round(dx / L);
            dy -= L * round(dy / L);
            double r = sqrt(dx * dx + dy * dy);
            if (r < rm) {
                int b = (int)(r * inv);
                hist[b < gr_bins(sc) ? b : gr_bins(sc) - 1] += 1.0;
            } else {
                beyond++;
            }
        }
    }
    return beyond;
}

START_TEST(test_ideal_gas)
{
    /* N = 200 uniform points, 1000 independent frames: g = 1 and n = 0 within the errors. N is
     * small on purpose: 4.10's N^2 normalisation would bias g by -1/N = -0.5 % (8 sigma of the
     * weighted mean) and n(R_max) by -pi R_max^2 / L^2 (8 sigma) */
    gr_scene sc;
    const int N = 200, frames = 1000, bins = 40;
    make_scene(&sc, N, 1.0, 0.005, bins, 20.0); /* R_max = 0.2 */
    void *st = create_ok(&sc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 20240501);
    double x[200], y[200];
    for (int k = 0; k < frames; k++) {
        uniform(rng, N, sc.L, x, y);
        sample_ok(st, &sc, x, y);
    }
    gsl_rng_free(rng);
    result r = finish_read(st, &sc);
    ck_assert_double_eq(num(r.pair, "frames", NULL), frames);
    ck_assert_str_eq(cJSON_GetObjectItem(r.pair, "errors")->valuestring,
                     "block averaging over frames");
    double chi2 = 0.0, wsum = 0.0, wdev = 0.0, ratio_min = INFINITY, ratio_max = 0.0;
    double npairs = 0.5 * N * (N - 1);
    int nz = 0;
    for (int b = 0; b < bins; b++) {
        const row *w = &r.rows[b];
        ck_assert_msg(w->ge > 0.0, "bin %d: g error %g", b, w->ge);
        chi2 += (w->g - 1.0) * (w->g - 1.0) / (w->ge * w->ge);
        wsum += 1.0 / (w->ge * w->ge);
        wdev += (w->g - 1.0) / (w->ge * w->ge);
        /* exact spread of an ideal-gas bin count on the torus: binomial (pairs sharing a particle
         * are independent), p = A_b / L^2 */
        double p = M_PI * (w->hi * w->hi - w->lo * w->lo) / (sc.L * sc.L);
        double exact = sqrt(npairs * p * (1.0 - p)) / (npairs * p) / sqrt((double)frames);
        ratio_min = fmin(ratio_min, w->ge / exact);
        ratio_max = fmax(ratio_max, w->ge / exact);
        /* n(R_hi) = 0 within its error at every R */
        ck_assert_msg(fabs(w->n) < 4.5 * w->ne, "bin %d: n = %g +- %g", b, w->n, w->ne);
        nz += fabs(w->n) > 2.0 * w->ne;
    }
    int dof = bins;
    if (getenv("PAIR_TEST_VERBOSE")) {
        fprintf(stderr,
                "ideal gas: chi2 %g / %d, mean dev %g +- %g, error ratios [%g, %g], |n| > 2 sigma "
                "in %d bins\n",
                chi2, dof, wdev / wsum, 1.0 / sqrt(wsum), ratio_min, ratio_max, nz);
    }
    ck_assert_msg(chi2 < dof + 4.0 * sqrt(2.0 * dof) && chi2 > 0.3 * dof, "chi2 = %g for %d bins",
                  chi2, dof);
    double mean_dev = wdev / wsum, mean_err = 1.0 / sqrt(wsum);
    ck_assert_msg(fabs(mean_dev) < 4.0 * mean_err, "weighted mean of g - 1 = %g +- %g", mean_dev,
                  mean_err);
    /* blocking errors take the largest level of the plateau: slightly above the exact spread */
    ck_assert_msg(ratio_min > 0.8 && ratio_max < 1.6,
                  "g errors / exact binomial spread in [%g, %g]", ratio_min, ratio_max);
    ck_assert_msg(nz <= 8, "%d of %d bins have |n| > 2 sigma", nz, bins);
    /* the C error at R_max against the exact binomial spread of 2 P / N */
    double p = M_PI * 0.2 * 0.2,
           cexact = 2.0 / N * sqrt(npairs * p * (1.0 - p)) / sqrt((double)frames);
    ck_assert_msg(r.rows[bins - 1].ne > 0.8 * cexact && r.rows[bins - 1].ne < 1.6 * cexact,
                  "C error %g, exact %g", r.rows[bins - 1].ne, cexact);
    ck_assert_msg(fabs(r.rows[bins - 1].C - (N - 1) * p) < 4.0 * cexact,
                  "C(R_max) = %g, expected %g", r.rows[bins - 1].C, (N - 1) * p);
    /* the tail mean of g is 1 */
    double gt = num(r.pair, "g_tail", "value"), gte = num(r.pair, "g_tail", "error");
    ck_assert_msg(fabs(gt - 1.0) < 4.0 * gte && gte < 0.01, "g_tail = %g +- %g", gt, gte);
    result_free(&r);
}
END_TEST

START_TEST(test_square_lattice)
{
    /* 20 x 20 lattice of spacing a = 1 = d in a box L = 20, shifted by random offsets (positions
     * outside [0, L) included); bins of width 0.055 keep 1, sqrt 2, 2 off the bin edges */
    gr_scene sc;
    const int M = 20, N = M * M, bins = 40, frames = 3;
    make_scene(&sc, N, 20.0, 0.5, bins, 2.2); /* below sqrt 5 */
    void *st = create_ok(&sc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 77);
    double x[400], y[400];
    for (int k = 0; k < frames; k++) {
        double ox = 60.0 * (gsl_rng_uniform(rng) - 0.5), oy = 60.0 * (gsl_rng_uniform(rng) - 0.5);
        for (int i = 0; i < N; i++) {
            x[i] = (i % M) + ox;
            y[i] = (i / M) + oy;
        }
        sample_ok(st, &sc, x, y);
    }
    gsl_rng_free(rng);
    result r = finish_read(st, &sc);
    const double dist[3] = {1.0, sqrt(2.0), 2.0};
    const double width = 2.2 / bins, norm = 0.5 * N * (N - 1) / (sc.L * sc.L);
    int peak_bin[3];
    for (int q = 0; q < 3; q++) {
        peak_bin[q] = (int)(dist[q] / width);
        ck_assert_msg(r.rows[peak_bin[q]].lo < dist[q] && r.rows[peak_bin[q]].hi > dist[q],
                      "bin of %g", dist[q]);
    }
    double c_prev = 0.0;
    int q = 0;
    for (int b = 0; b < bins; b++) {
        const row *w = &r.rows[b];
        if (q < 3 && b == peak_bin[q]) {
            /* 4 neighbours at this distance: N * 4 / 2 pairs per frame, C rises by 4 */
            ck_assert_double_eq(w->pairs, frames * N * 4 / 2);
            ck_assert_double_eq_tol(w->C - c_prev, 4.0, 1e-9);
            double area = M_PI * (w->hi * w->hi - w->lo * w->lo);
            ck_assert_double_eq_tol(w->g, N * 2.0 / (norm * area), 1e-9 * w->g);
            /* fewer than 16 frames: sqrt(count) errors */
            ck_assert_double_eq_tol(w->ge, sqrt(w->pairs) / (frames * norm * area), 1e-5 * w->ge);
            q++;
        } else {
            ck_assert_msg(w->pairs == 0.0 && w->g == 0.0, "bin %d (R = %g): %g pairs", b, w->R,
                          w->pairs);
        }
        ck_assert_double_eq_tol(w->C, 4.0 * q, 1e-9);
        /* n = C - (N-1)/L^2 pi R_hi^2 */
        ck_assert_double_eq_tol(w->n, w->C - (N - 1) / (sc.L * sc.L) * M_PI * w->hi * w->hi, 1e-9);
        c_prev = w->C;
    }
    ck_assert_int_eq(q, 3);
    ck_assert_str_eq(cJSON_GetObjectItem(r.pair, "errors")->valuestring,
                     "sqrt(counts) (fewer than 16 frames for block averaging)");
    double pk = num(r.pair, "first_peak", "R_over_d");
    ck_assert_msg(fabs(pk - 1.0) <= 0.5 * width + 1e-12, "first peak at %g d", pk);
    ck_assert_double_eq_tol(num(r.pair, "first_peak", "g"), r.rows[peak_bin[0]].g, 1e-9);
    result_free(&r);
}
END_TEST

/* cell-list counts against brute force; clustered and uniform points; positions shifted by
 * multiples of L and just outside the box */
static void compare_brute(int N, double L, double radius, double rmax, int bins, bool clustered,
                          unsigned long seed)
{
    gr_scene sc;
    make_scene(&sc, N, L, radius, bins, rmax);
    void *st = create_ok(&sc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, seed);
    double *x = malloc(sizeof(double) * (size_t)N), *y = malloc(sizeof(double) * (size_t)N);
    double *hist = calloc((size_t)bins, sizeof(double));
    const int frames = 3;
    for (int k = 0; k < frames; k++) {
        if (clustered) {
            double cx[5], cy[5];
            for (int c = 0; c < 5; c++) {
                cx[c] = L * gsl_rng_uniform(rng);
                cy[c] = L * gsl_rng_uniform(rng);
            }
            for (int i = 0; i < N; i++) {
                int c = (int)gsl_rng_uniform_int(rng, 5);
                x[i] = cx[c] + gsl_ran_gaussian(rng, 0.03 * L);
                y[i] = cy[c] + gsl_ran_gaussian(rng, 0.03 * L);
            }
        } else {
            uniform(rng, N, L, x, y);
        }
        for (int i = 0; i < N; i += 7) { /* images and points just outside [0, L) */
            x[i] += L * (double)((int)gsl_rng_uniform_int(rng, 5) - 2);
            y[i] = (i % 2) ? -1e-9 * L * gsl_rng_uniform(rng) : y[i];
        }
        brute(&sc, x, y, hist);
        sample_ok(st, &sc, x, y);
    }
    gsl_rng_free(rng);
    result r = finish_read(st, &sc);
    double total = 0.0;
    for (int b = 0; b < bins; b++) {
        ck_assert_msg(r.rows[b].pairs == hist[b],
                      "N = %d, L = %g, R_max = %g: bin %d has %g pairs, brute force %g", N, L,
                      r_max(&sc), b, r.rows[b].pairs, hist[b]);
        total += hist[b];
    }
    ck_assert_msg(N < 50 || total > 0.0, "no pairs in range");
    result_free(&r);
    free(x);
    free(y);
    free(hist);
}

START_TEST(test_brute_force)
{
    compare_brute(600, 1.0, 0.004, 5.0, 60, false, 1); /* R_max = 0.04: many cells, 5x5 stencil */
    compare_brute(600, 1.0, 0.004, 5.0, 60, true, 2);  /* clustered: crowded cells */
    compare_brute(400, 1.0, 0.01, 12.0, 50, false,
                  3); /* R_max = 0.24: 4 cells per side, aliased stencil */
    compare_brute(400, 1.0, 0.05, 20.0, 50, true, 4); /* clamped to L/2 */
    compare_brute(300, 2.5, 0.02, 7.3, 33, false, 5); /* 8 cells per side */
    compare_brute(2, 1.0, 0.1, 2.0, 10, false, 6);    /* two particles, one cell */
    compare_brute(3, 1.0, 0.2, 1.0, 7, false, 7);
}
END_TEST

START_TEST(test_full_range)
{
    /* R_max = L/2 (gr_rmax clamped): all pairs within L/2 are counted; the box corners
     * L/2 <= R < L/sqrt 2 hold the rest, a fraction 1 - pi/4 for uniform points */
    gr_scene sc;
    const int N = 400, frames = 20, bins = 50;
    make_scene(&sc, N, 1.0, 0.01, bins, 1e3);
    void *st = create_ok(&sc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 99);
    double x[400], y[400], hist[50] = {0};
    long long beyond = 0;
    for (int k = 0; k < frames; k++) {
        uniform(rng, N, sc.L, x, y);
        beyond += brute(&sc, x, y, hist);
        sample_ok(st, &sc, x, y);
    }
    gsl_rng_free(rng);
    result r = finish_read(st, &sc);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(r.pair, "R_max_clamped_to_half_box")));
    ck_assert_double_eq_tol(num(r.pair, "R_max_over_d", NULL), 25.0, 1e-9);
    double counted = 0.0, from_g = 0.0, all = (double)frames * 0.5 * N * (N - 1);
    double norm = 0.5 * N * (N - 1) / (sc.L * sc.L);
    for (int b = 0; b < bins; b++) {
        counted += r.rows[b].pairs;
        from_g +=
            r.rows[b].g * norm * M_PI * (r.rows[b].hi * r.rows[b].hi - r.rows[b].lo * r.rows[b].lo);
    }
    ck_assert_double_eq(counted + (double)beyond, all);
    /* g integrates back to the counts (4.10 normalisation) and C(L/2) = 2 pairs / N */
    ck_assert_double_eq_tol(from_g * frames, counted, 1e-9 * counted);
    ck_assert_double_eq_tol(r.rows[bins - 1].C, 2.0 * counted / frames / N,
                            1e-9 * r.rows[bins - 1].C);
    /* corners: the disc of radius L/2 covers pi/4 of the box */
    double f = counted / all, sd = sqrt(M_PI / 4 * (1 - M_PI / 4) / all);
    ck_assert_msg(fabs(f - M_PI / 4) < 5.0 * sd, "fraction within L/2 = %g, pi/4 = %g (sd %g)", f,
                  M_PI / 4, sd);
    result_free(&r);
}
END_TEST

START_TEST(test_line_fractal_dimension)
{
    /* points on one straight line (D_f = 1): C(R) = 2 (N-1) R / L, and over the fit window
     * [R_max/4, R_max/2] = [0.005, 0.01] m the subtracted (N-1) pi R^2 / L^2 lowers the log-log
     * slope by only ~1 % */
    gr_scene sc;
    const int N = 2000, frames = 64;
    make_scene(&sc, N, 1.0, 0.0005, 100, 20.0); /* R_max = 0.02 */
    void *st = create_ok(&sc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 5);
    double *x = malloc(sizeof(double) * N), *y = malloc(sizeof(double) * N);
    for (int k = 0; k < frames; k++) {
        double y0 = gsl_rng_uniform(rng);
        for (int i = 0; i < N; i++) {
            x[i] = gsl_rng_uniform(rng);
            y[i] = y0;
        }
        sample_ok(st, &sc, x, y);
    }
    gsl_rng_free(rng);
    free(x);
    free(y);
    result r = finish_read(st, &sc);
    double df = num(r.pair, "D_f", "value"), e = num(r.pair, "D_f", "error");
    if (getenv("PAIR_TEST_VERBOSE")) {
        fprintf(stderr, "line: D_f %g +- %g (fit %g, jackknife %g), chi2_red %g\n", df, e,
                num(r.pair, "D_f", "fit_error"), num(r.pair, "D_f", "jackknife_error"),
                num(r.pair, "D_f", "chi2_red"));
    }
    ck_assert_msg(fabs(df - 1.0) < 0.03, "D_f = %g +- %g on a line", df, e);
    /* and it matches the local slope of the exact n(R) = 2 (N-1) R / L - (N-1) pi R^2 / L^2,
     * d ln n / d ln R = 1 - (pi R / 2L) / (1 - pi R / 2L), at the window's geometric centre */
    double rc = sqrt(0.005 * 0.01), q = M_PI * rc / 2.0, slope = 1.0 - q / (1.0 - q);
    ck_assert_msg(fabs(df - slope) < fmax(5.0 * e, 0.003), "D_f = %g +- %g, exact local slope %g",
                  df, e, slope);
    ck_assert_msg(e > 0.0 && e < 0.03, "D_f error %g", e);
    ck_assert_msg(num(r.pair, "D_f", "jackknife_batches") >= 16, "jackknife batches");
    ck_assert_double_eq_tol(num(r.pair, "D_f", "R_from_over_d"), 5.0, 1e-9);
    ck_assert_double_eq_tol(num(r.pair, "D_f", "R_to_over_d"), 10.0, 1e-9);
    result_free(&r);
}
END_TEST

START_TEST(test_bad_params)
{
    gr_scene sc;
    void *st = NULL;
    gr_error err = {0};
    struct {
        int dim, N, bins;
        double L, radius, rmax;
    } bad[] = {
        {1, 100, 100, 1.0, 0.01, 10.0}, {2, 100, 0, 1.0, 0.01, 10.0},
        {2, 100, -5, 1.0, 0.01, 10.0},  {2, 100, 8193, 1.0, 0.01, 10.0},
        {2, 100, 100, 1.0, 0.01, 0.0},  {2, 100, 100, 1.0, 0.01, -1.0},
        {2, 100, 100, 1.0, 0.01, NAN},  {2, 100, 100, 1.0, 0.01, INFINITY},
        {2, 100, 100, 1.0, 0.0, 10.0},  {2, 1, 100, 1.0, 0.01, 10.0},
        {2, 100, 100, 0.0, 0.01, 10.0},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        make_scene(&sc, bad[k].N, bad[k].L, bad[k].radius, bad[k].bins, bad[k].rmax);
        sc.dim = bad[k].dim;
        st = NULL;
        err = (gr_error){0};
        ck_assert_msg(gr_scene_observable(&gr_obs_pair, &sc, &st, &err) == GR_EINVAL,
                      "case %zu accepted", k);
        ck_assert_ptr_null(st);
        ck_assert_msg(strstr(err.message, "pair") != NULL, "case %zu: message '%s'", k,
                      err.message);
    }
    /* the declared defaults (as the scene loader applies them) are valid */
    make_scene(&sc, 100, 1.0, 0.01, 0, 0.0);
    gr_analysis_defaults(&sc.analysis);
    double def_bins, def_rmax;
    ck_assert_int_eq(gr_analysis_get(&sc.analysis, "gr_bins", &def_bins, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_get(&sc.analysis, "gr_rmax", &def_rmax, NULL), GR_OK);
    ck_assert_double_eq(def_bins, 400);
    ck_assert_double_eq(def_rmax, 20.0);
    ck_assert_uint_eq(gr_obs_pair.dims, 6u); /* 2D and 3D */
    ck_assert_str_eq(gr_obs_pair.name, "pair");
    st = create_ok(&sc);
    /* frames that do not match the scene, or hold non-finite positions, are refused */
    double x[100] = {0}, y[100] = {0};
    gr_particles p = {.n = 99, .dim = 2, .L = 1.0, .radius = 0.01, .mass = 1.0, .x = x, .y = y};
    ck_assert_int_eq(gr_obs_pair.sample(st, &p, 0.0, &err), GR_EINVAL);
    p.n = 100;
    p.L = 1.5;
    ck_assert_int_eq(gr_obs_pair.sample(st, &p, 0.0, &err), GR_EINVAL);
    p.L = 1.0;
    x[3] = NAN;
    ck_assert_int_eq(gr_obs_pair.sample(st, &p, 0.0, &err), GR_EINVAL);
    x[3] = 0.0;
    p.dim = 1;
    p.y = NULL;
    ck_assert_int_eq(gr_obs_pair.sample(st, &p, 0.0, &err), GR_EINVAL);
    /* no frames: an empty table and a summary saying so */
    result r = finish_read(st, &sc);
    ck_assert_double_eq(num(r.pair, "frames", NULL), 0.0);
    result_free(&r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_pair");
    TCase *t = tcase_create("pair");
    tcase_set_timeout(t, 120);
    tcase_add_test(t, test_ideal_gas);
    tcase_add_test(t, test_square_lattice);
    tcase_add_test(t, test_brute_force);
    tcase_add_test(t, test_full_range);
    tcase_add_test(t, test_line_fractal_dimension);
    tcase_add_test(t, test_bad_params);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
