/* The sk observable (2D structure factor, thesis sec. 4.1, docs/analysis-structure-factor.md):
 * the S(k) engine checked against its oracle and against point sets of known S(k), and the
 * observable driven directly through gr_obs_sk's functions (fixed seeds), its results read back
 * from sk.csv, sk_shells.csv and the "sk" summary member.
 *
 *  - gridding (NUFFT) against the direct sum, and the direct sum against a plain sincos sum;
 *  - uniform random points (ideal gas): S(k) = 1 for every k != 0 of the lattice (4.3);
 *  - a perfect square lattice of m x m points: S = N on the reciprocal lattice (n = 0 mod m), 0
 *    elsewhere; two species on interpenetrating lattices: the partial S_ab of gr_sk_compute_rho;
 *  - a random multiplicative cascade of correlation dimension D_2 = -log2(sum p_i^2): S(k) ~ k^-D_2
 *    at small k, so the D_f fit (4.4) must land near D_2;
 *  - k_D, L_min, L_Eff (4.5-4.9) against the thesis's Tables 4.1-4.2, and the choice of k';
 *  - bad parameters and frames refused. */
#include <check.h>
#include <cjson/cJSON.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/model.h"
#include "granule/observe.h"
#include "granule/scene.h"

extern const gr_observable_type gr_obs_sk;

#include "analysis/sk.h"
#include "check_main.h"

#define MSP 8 /* GR_SK_MSP_DEFAULT */
#define CASCADE_N 16000

/* ------------------------------------------------------------------------------------------ */
/* helpers */

static void scene_2d(gr_scene *s, int N, double L, double radius, double kd_max)
{
    gr_scene_default(s);
    s->dim = 2;
    s->N = N;
    s->L = L;
    s->radius = radius;
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "sk_kd_max", kd_max, NULL), GR_OK);
    s->tangential = NULL;
    s->contact.eps_n = 0.1;
    snprintf(s->source, sizeof s->source, "test_obs_sk");
}

static void uniform(gsl_rng *r, int n, double L, double *x, double *y)
{
    for (int i = 0; i < n; i++) {
        x[i] = L * gsl_rng_uniform(r);
        y[i] = L * gsl_rng_uniform(r);
    }
}

static void *create_ok(const gr_scene *s)
{
    void *st = NULL;
    gr_error err = {0};
    int rc = gr_scene_observable(&gr_obs_sk, s, &st, &err);
    ck_assert_msg(rc == GR_OK, "create: %s", err.message);
    return st;
}

static void sample_ok(void *st, int n, double L, const double *x, const double *y)
{
    gr_particles p = {
        .n = n, .dim = 2, .L = L, .radius = 1e-3, .mass = 1.0, .x = x, .y = y, .vx = x, .vy = y};
    gr_error err = {0};
    int rc = gr_obs_sk.sample(st, &p, 0.0, &err);
    ck_assert_msg(rc == GR_OK, "sample: %s", err.message);
}

typedef struct row {
    double n, k, kd, S, S_err;
    int vectors, independent, in_fit;
} row;

typedef struct result {
    char dir[64];
    cJSON *analysis, *sk;
    row *bins, *shells;
    int n_bins, n_shells;
} result;

static FILE *open_csv(const char *dir, const char *name, char *header, size_t n)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "missing %s", path);
    char line[1024];
    /* the column names first; the notes (tool, what; scene, hash, seed) in NAME.meta.json */
    snprintf(path, sizeof path, "%s/%.*s.meta.json", dir, (int)(strlen(name) - 4), name);
    FILE *meta = fopen(path, "r");
    ck_assert_msg(meta && fgets(line, sizeof line, meta) && line[0] == '{', "missing or empty %s",
                  path);
    fclose(meta);
    ck_assert(fgets(header, (int)n, f) && header[0] != '#');
    return f;
}

static int read_rows(FILE *f, row **out, bool shells)
{
    int cap = 256, n = 0;
    row *rows = malloc(sizeof(row) * (size_t)cap);
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        if (n == cap) {
            cap *= 2;
            rows = realloc(rows, sizeof(row) * (size_t)cap);
        }
        row *w = &rows[n++];
        w->in_fit = 0;
        int got = sscanf(line, "%lf,%lf,%lf,%lf,%lf,%d,%d,%d", &w->n, &w->k, &w->kd, &w->S,
                         &w->S_err, &w->vectors, &w->independent, &w->in_fit);
        ck_assert_msg(got == (shells ? 8 : 7), "bad line: %s", line);
    }
    fclose(f);
    *out = rows;
    return n;
}

static void finish_ok(void *st, const gr_scene *s, bool plots, result *r)
{
    memset(r, 0, sizeof *r);
    snprintf(r->dir, sizeof r->dir, "/tmp/test_obs_sk_XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(r->dir));
    r->analysis = cJSON_CreateObject();
    gr_output out = {.dir = r->dir,
                     .source = s->source,
                     .seed = s->seed,
                     .scene_hash = 0x5c,
                     .summary = r->analysis,
                     .plots = plots};
    gr_error err = {0};
    int rc = gr_obs_sk.finish(st, &out, &err);
    ck_assert_msg(rc == GR_OK, "finish: %s", err.message);
    r->sk = cJSON_GetObjectItem(r->analysis, "sk");
    ck_assert_ptr_nonnull(r->sk);
    char header[512];
    FILE *f = open_csv(r->dir, "sk.csv", header, sizeof header);
    ck_assert_str_eq(header, "n,k,kd,S,S_err,vectors,independent_vectors\n");
    r->n_bins = read_rows(f, &r->bins, false);
    f = open_csv(r->dir, "sk_shells.csv", header, sizeof header);
    ck_assert_str_eq(header, "n2,k,kd,S,S_err,vectors,independent_vectors,in_fit\n");
    r->n_shells = read_rows(f, &r->shells, true);
}

static void result_free(result *r)
{
    const char *names[] = {"sk.csv", "sk_shells.csv", "sk.png"};
    char path[256];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", r->dir, names[i]);
        remove(path);
    }
    rmdir(r->dir);
    cJSON_Delete(r->analysis);
    free(r->bins);
    free(r->shells);
}

static double num(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(o, name);
    ck_assert_msg(v != NULL, "summary member %s missing", name);
    return cJSON_IsNumber(v) ? v->valuedouble : (double)NAN;
}

/* ------------------------------------------------------------------------------------------ */
/* the engine */

START_TEST(test_gridding_matches_direct)
{
    /* thesis density phi = 0.53 (r = 1.5 mm), every k with |k| d <= 4, N = 1000..4000 */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 42);
    const int sizes[] = {1000, 2500, 4000};
    for (int s = 0; s < 3; s++) {
        const int n = sizes[s];
        const double L = sqrt(n * M_PI * 1.5e-3 * 1.5e-3 / 0.53),
                     n_cut = 4.0 * L / (2.0 * M_PI * 3e-3);
        double *x = malloc(sizeof(double) * (size_t)n), *y = malloc(sizeof(double) * (size_t)n);
        uniform(r, n, L, x, y);
        gr_sk_plan *pl;
        gr_error err = {0};
        ck_assert_int_eq(gr_sk_plan_create(L, n_cut, MSP, &pl, &err), GR_OK);
        const int *nx, *ny;
        int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), &nx, &ny, NULL);
        double *Sg = malloc(sizeof(double) * (size_t)nv), *Sd = malloc(sizeof(double) * (size_t)nv);
        ck_assert_int_eq(gr_sk_compute(pl, GR_SK_GRIDDING, n, x, y, Sg, &err), GR_OK);
        ck_assert_int_eq(gr_sk_compute(pl, GR_SK_DIRECT, n, x, y, Sd, &err), GR_OK);
        double worst = 0.0;
        int at = 0;
        for (int v = 0; v < nv; v++) {
            if (fabs(Sg[v] - Sd[v]) > worst) {
                worst = fabs(Sg[v] - Sd[v]);
                at = v;
            }
        }
        ck_assert_msg(worst < 1e-4, "N = %d: max |dS| = %g at n = (%d, %d), S = %g", n, worst,
                      nx[at], ny[at], Sd[at]);
        /* the oracle against a plain sum of sincos on a few vectors, the largest |n| included */
        for (int v = 0; v < nv; v += nv / 7) {
            double re = 0.0, im = 0.0;
            for (int j = 0; j < n; j++) {
                double ph = 2.0 * M_PI * (nx[v] * x[j] + ny[v] * y[j]) / L;
                re += cos(ph);
                im -= sin(ph);
            }
            double S = (re * re + im * im) / n;
            ck_assert_msg(fabs(Sd[v] - S) < 1e-9 * (1.0 + S),
                          "direct sum %g, sincos %g at (%d, %d)", Sd[v], S, nx[v], ny[v]);
        }
        /* periodic: whole boxes added to the coordinates change nothing */
        for (int j = 0; j < n; j++) {
            x[j] += (j % 3 - 1) * L;
            y[j] -= (j % 5 - 2) * L;
        }
        ck_assert_int_eq(gr_sk_compute(pl, GR_SK_GRIDDING, n, x, y, Sd, &err), GR_OK);
        for (int v = 0; v < nv; v++) {
            ck_assert_msg(fabs(Sg[v] - Sd[v]) < 1e-9 * (1.0 + Sg[v]), "shifted by boxes: %g vs %g",
                          Sd[v], Sg[v]);
        }
        free(x);
        free(y);
        free(Sg);
        free(Sd);
        gr_sk_plan_free(pl);
    }
    gsl_rng_free(r);
}
END_TEST

START_TEST(test_half_plane_without_k0)
{
    /* every lattice vector 0 < |n| <= n_cut appears exactly once up to sign; k = 0 never */
    gr_sk_plan *pl;
    gr_error err = {0};
    const double n_cut = 17.3;
    ck_assert_int_eq(gr_sk_plan_create(1.0, n_cut, MSP, &pl, &err), GR_OK);
    static const int sentinel = 0;
    const int *nx, *ny, *nz = &sentinel; /* the shared getter must set it: NULL in 2D */
    int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), &nx, &ny, &nz);
    ck_assert_msg(nz == NULL, "a 2D plan's lattice has no n_z");
    const int m = 18, w = 2 * m + 1;
    int *seen = calloc((size_t)(w * w), sizeof(int));
    for (int v = 0; v < nv; v++) {
        ck_assert_msg(nx[v] != 0 || ny[v] != 0, "k = 0 listed");
        ck_assert(nx[v] * nx[v] + ny[v] * ny[v] <= n_cut * n_cut);
        seen[(nx[v] + m) * w + ny[v] + m]++;
        seen[(-nx[v] + m) * w - ny[v] + m]++;
    }
    int full = 0;
    for (int a = -m; a <= m; a++) {
        for (int b = -m; b <= m; b++) {
            bool inside = (a || b) && a * a + b * b <= n_cut * n_cut;
            ck_assert_int_eq(seen[(a + m) * w + b + m], inside ? 1 : 0);
            full += inside;
        }
    }
    ck_assert_int_eq(2 * nv, full);
    free(seen);
    gr_sk_plan_free(pl);
}
END_TEST

START_TEST(test_square_lattice_bragg)
{
    /* m x m points on a square lattice of spacing a = L/m: rho(k) = N when n = 0 mod m in both
     * components (the reciprocal lattice), else 0 */
    const int m = 16, n = m * m;
    const double L = 0.1;
    double x[16 * 16], y[16 * 16];
    for (int i = 0; i < n; i++) {
        x[i] = (i % m + 0.25) * L / m;
        y[i] = (i / m + 0.5) * L / m;
    }
    gr_sk_plan *pl;
    gr_error err = {0};
    ck_assert_int_eq(gr_sk_plan_create(L, 40.0, MSP, &pl, &err), GR_OK);
    const int *nx, *ny;
    int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), &nx, &ny, NULL), peaks = 0;
    double *S = malloc(sizeof(double) * (size_t)nv);
    for (int method = 0; method < 2; method++) {
        ck_assert_int_eq(gr_sk_compute(pl, method, n, x, y, S, &err), GR_OK);
        peaks = 0;
        for (int v = 0; v < nv; v++) {
            if (nx[v] % m == 0 && ny[v] % m == 0) {
                ck_assert_msg(fabs(S[v] / n - 1.0) < 1e-6,
                              "Bragg peak at (%d, %d): S = %g, want %d", nx[v], ny[v], S[v], n);
                peaks++;
            } else {
                ck_assert_msg(S[v] < 1e-8, "S(%d, %d) = %g, want 0", nx[v], ny[v], S[v]);
            }
        }
        /* half plane with |n| <= 40: (16,0) (32,0) (0,16) (0,32) (16,16) (16,-16) (16,32) (16,-32)
         * (32,16) (32,-16) */
        ck_assert_int_eq(peaks, 10);
    }
    free(S);
    gr_sk_plan_free(pl);

    /* the same through the observable: the circular bin of |n| = 16 holds the peaks (16,0) and
     * (0,16) among its vectors, S_bin = N * 2 / count; bins without a peak are 0 */
    gr_scene s;
    const double d = 4.0 * L / (2.0 * M_PI * 40.0); /* |k| d <= 4 is |n| <= 40 */
    scene_2d(&s, n, L, d / 2.0, 4.0);
    void *st = create_ok(&s);
    sample_ok(st, n, L, x, y);
    sample_ok(st, n, L, x, y);
    result r;
    finish_ok(st, &s, false, &r);
    ck_assert_int_eq(r.n_bins, 40);
    for (int b = 0; b < r.n_bins; b++) {
        const row *w = &r.bins[b];
        ck_assert_msg(w->n == b + 1 && w->k > 0.0, "bins start at |n| = 1 (k = 0 excluded)");
        ck_assert_double_eq_tol(w->kd, w->k * d, 1e-9 * w->kd);
        int expect_peaks = b + 1 == 16 || b + 1 == 32 ? 2 : b + 1 == 23 ? 2 : b + 1 == 36 ? 4 : 0;
        /* |(16,16)| = 22.6 (bin 23), |(16,32)| = |(32,16)| = 35.8 (bin 36) */
        double want = (double)n * expect_peaks / w->independent;
        ck_assert_msg(fabs(w->S - want) < 1e-6 * (1.0 + want), "bin %g: S = %g, want %g", w->n,
                      w->S, want);
        ck_assert_int_eq(w->vectors, 2 * w->independent);
    }
    result_free(&r);
    gr_observable_free(st);
}
END_TEST

START_TEST(test_partial_lattices)
{
    /* two species on interpenetrating square lattices of spacing a = L/m, B shifted from A by
     * delta = (a/2, a/2) (a centred square lattice): rho_a(k) = sum_{j in a} exp(-i k.r_j) is
     * N_A e^{-i k.r_0} on the reciprocal lattice n = 0 mod m and 0 elsewhere, so S_AA = S_BB = N_A
     * there and S_AB = Re rho_A conj(rho_B) / N_A = N_A cos(k.delta) = N_A (-1)^((n_x + n_y) / m);
     * A's first point at (a/4, a/2) gives rho_A(m, 0) = -i N_A (the sign of the exponent); and
     * |rho_A|^2 / N_A is gr_sk_compute's S */
    const int m = 16, n = m * m;
    const double L = 0.1, a = L / m;
    double xa[16 * 16], ya[16 * 16], xb[16 * 16], yb[16 * 16];
    for (int i = 0; i < n; i++) {
        xa[i] = (i % m + 0.25) * a;
        ya[i] = (i / m + 0.5) * a;
        xb[i] = xa[i] + 0.5 * a;
        yb[i] = ya[i] + 0.5 * a;
    }
    gr_sk_plan *pl;
    gr_error err = {0};
    ck_assert_int_eq(gr_sk_plan_create(L, 40.0, MSP, &pl, &err), GR_OK);
    const int *nx, *ny;
    const int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), &nx, &ny, NULL);
    double *ra = malloc(sizeof(double) * 5 * (size_t)nv), *ia = ra + nv, *rb = ra + 2 * nv,
           *ib = ra + 3 * nv, *S = ra + 4 * nv;
    for (int method = 0; method < 2; method++) {
        ck_assert_int_eq(gr_sk_compute_rho(pl, method, n, xa, ya, ra, ia, &err), GR_OK);
        ck_assert_int_eq(gr_sk_compute_rho(pl, method, n, xb, yb, rb, ib, &err), GR_OK);
        ck_assert_int_eq(gr_sk_compute(pl, method, n, xa, ya, S, &err), GR_OK);
        int peaks = 0;
        for (int v = 0; v < nv; v++) {
            const double saa = (ra[v] * ra[v] + ia[v] * ia[v]) / n,
                         sbb = (rb[v] * rb[v] + ib[v] * ib[v]) / n,
                         sab = (ra[v] * rb[v] + ia[v] * ib[v]) / n;
            ck_assert_msg(fabs(saa - S[v]) <= 1e-12 * (1.0 + S[v]), "|rho_A|^2 / N %g, S %g", saa,
                          S[v]);
            if (nx[v] % m == 0 && ny[v] % m == 0) {
                const double sign = ((nx[v] + ny[v]) / m) % 2 ? -1.0 : 1.0;
                ck_assert_msg(fabs(saa / n - 1.0) < 1e-6 && fabs(sbb / n - 1.0) < 1e-6 &&
                                  fabs(sab / n - sign) < 1e-6,
                              "method %d, n = (%d, %d): S_AA %g, S_BB %g, S_AB %g, want %d, %d, %g",
                              method, nx[v], ny[v], saa, sbb, sab, n, n, sign * n);
                if (nx[v] == m && ny[v] == 0) {
                    ck_assert_msg(fabs(ra[v]) < 1e-6 * n && fabs(ia[v] + n) < 1e-6 * n,
                                  "rho_A(m, 0) = %g + %g i, want -%d i", ra[v], ia[v], n);
                }
                peaks++;
            } else {
                ck_assert_msg(saa < 1e-8 && sbb < 1e-8 && fabs(sab) < 1e-8,
                              "n = (%d, %d): S_AA %g, S_BB %g, S_AB %g, want 0", nx[v], ny[v], saa,
                              sbb, sab);
            }
        }
        ck_assert_int_eq(peaks, 10);
    }
    /* no particle: rho = 0 (a species without grains in a frame) */
    ck_assert_int_eq(gr_sk_compute_rho(pl, GR_SK_GRIDDING, 0, NULL, NULL, ra, ia, &err), GR_OK);
    for (int v = 0; v < nv; v++) {
        ck_assert(ra[v] == 0.0 && ia[v] == 0.0);
    }
    free(ra);
    gr_sk_plan_free(pl);
}
END_TEST

/* ------------------------------------------------------------------------------------------ */
/* the observable */

START_TEST(test_ideal_gas)
{
    /* uniform random points: every lattice vector has <S(k)> = 1 (4.2 with <e^{ik.(r_i - r_j)}> = 0
     * for i != j), each frame's S exponentially distributed. 24 independent frames. */
    const int n = 3000, frames = 24;
    const double L = 0.2, radius = 1.5e-3;
    gr_scene s;
    scene_2d(&s, n, L, radius, 4.0);
    void *st = create_ok(&s);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    double *x = malloc(sizeof(double) * n), *y = malloc(sizeof(double) * n);
    for (int f = 0; f < frames; f++) {
        uniform(r, n, L, x, y);
        sample_ok(st, n, L, x, y);
    }
    result res;
    finish_ok(st, &s, true, &res);
    /* the bins: |n| = 1 .. 4 L / (2 pi d) = 42.4 */
    ck_assert_int_eq(res.n_bins, 42);
    double chi2 = 0.0, sum = 0.0, count = 0.0;
    int outliers = 0;
    for (int b = 0; b < res.n_bins; b++) {
        const row *w = &res.bins[b];
        ck_assert(w->k > 0.0 && w->S_err > 0.0);
        /* the error of a bin mean: S ~ Exp(1) per vector and frame -> 1/sqrt(count frames) */
        double expect = 1.0 / sqrt((double)w->independent * frames);
        ck_assert_msg(w->S_err > 0.5 * expect && w->S_err < 2.0 * expect,
                      "bin %g: error %g, expected ~%g", w->n, w->S_err, expect);
        double z = (w->S - 1.0) / w->S_err;
        chi2 += z * z;
        outliers += fabs(z) > 4.0;
        sum += w->S * w->independent;
        count += w->independent;
    }
    ck_assert_msg(outliers == 0, "%d bins more than 4 sigma from S = 1", outliers);
    ck_assert_msg(chi2 / res.n_bins > 0.5 && chi2 / res.n_bins < 1.7, "chi2/bins = %g",
                  chi2 / res.n_bins);
    double mean = sum / count, err_mean = 1.0 / sqrt(count * frames);
    ck_assert_msg(fabs(mean - 1.0) < 4.0 * err_mean, "mean S over all vectors %g +- %g", mean,
                  err_mean);
    /* exact shells: the same */
    for (int b = 0; b < res.n_shells; b++) {
        const row *w = &res.shells[b];
        ck_assert_msg(fabs(w->S - 1.0) < 5.0 * w->S_err, "shell n2 = %g: S = %g +- %g", w->n, w->S,
                      w->S_err);
    }
    /* summary: frames, method, and no structure to fit: D_f consistent with 0 */
    ck_assert_double_eq(num(res.sk, "frames"), frames);
    ck_assert_str_eq(cJSON_GetObjectItem(res.sk, "method")->valuestring, "gridding");
    const cJSON *fit = cJSON_GetObjectItem(res.sk, "fit");
    ck_assert_ptr_nonnull(fit);
    if (cJSON_GetObjectItem(fit, "D_f")) {
        ck_assert_msg(fabs(num(fit, "D_f")) < 4.0 * num(fit, "D_f_err") + 0.05,
                      "ideal gas D_f = %g +- %g", num(fit, "D_f"), num(fit, "D_f_err"));
    }
    if (system("command -v gnuplot >/dev/null 2>&1") == 0) {
        char png[128];
        snprintf(png, sizeof png, "%s/sk.png", res.dir);
        ck_assert_msg(access(png, F_OK) == 0 && !cJSON_GetObjectItem(res.analysis, "plot_notes"),
                      "sk.png not drawn");
    }
    result_free(&res);
    gr_observable_free(st);
    free(x);
    free(y);
    gsl_rng_free(r);
}
END_TEST

/* One realisation of a random multiplicative cascade on a 2^levels grid: each cell's mass goes to
 * its four quadrants in the proportions p (randomly permuted per cell); then n points drawn from
 * the measure. Its correlation dimension is D_2 = -log2(sum p_i^2). */
static void cascade(gsl_rng *r, int levels, const double p[4], int n, double L, double *x,
                    double *y, double *mass, double *next)
{
    int side = 1;
    mass[0] = 1.0;
    for (int l = 0; l < levels; l++) {
        for (int i = 0; i < side; i++) {
            for (int j = 0; j < side; j++) {
                size_t perm[4] = {0, 1, 2, 3};
                gsl_ran_shuffle(r, perm, 4, sizeof(size_t));
                double m = mass[i * side + j];
                for (int q = 0; q < 4; q++) {
                    next[(2 * i + q / 2) * 2 * side + 2 * j + q % 2] = m * p[perm[q]];
                }
            }
        }
        side *= 2;
        memcpy(mass, next, sizeof(double) * (size_t)side * (size_t)side);
    }
    for (int c = 1; c < side * side; c++) { /* cumulative */
        mass[c] += mass[c - 1];
    }
    for (int k = 0; k < n; k++) {
        double u = gsl_rng_uniform(r) * mass[side * side - 1];
        int lo = 0, hi = side * side - 1;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (mass[mid] > u) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        x[k] = (lo % side + gsl_rng_uniform(r)) * L / side;
        y[k] = (lo / side + gsl_rng_uniform(r)) * L / side;
    }
}

/* D_f of n points from `frames` independent cascades with proportions p, through the observable. */
static double cascade_fit(const double p[4], unsigned long seed, double *err, double *chi2_red)
{
    /* The window: eps_n = 0 and no tangential law (eps_t = 1) give k_D = 1 / (8 l_0) (4.5) with
     * l_0 = L^2 / (2 d N) (4.7), i.e. |n_D| = d N / (8 pi L): d = 64 pi L / N puts k_D at |n| = 8,
     * and L_Eff = 2 sqrt 2 L / 8 < L, so k' = k_D. */
    const int n = CASCADE_N, frames = 20, levels = 8;
    const double L = 1.0, d = 64.0 * M_PI * L / n;
    gr_scene s;
    scene_2d(&s, n, L, d / 2.0, 4.0);
    s.contact.eps_n = 0.0;
    void *st = create_ok(&s);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    double *x = malloc(sizeof(double) * n), *y = malloc(sizeof(double) * n);
    double *mass = malloc(sizeof(double) << (2 * levels)),
           *next = malloc(sizeof(double) << (2 * levels));
    for (int f = 0; f < frames; f++) {
        cascade(r, levels, p, n, L, x, y, mass, next);
        sample_ok(st, n, L, x, y);
    }
    result res;
    finish_ok(st, &s, false, &res);
    ck_assert_double_eq_tol(num(res.sk, "k_D"), 2.0 * M_PI * 8.0 / L, 1e-9);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(res.sk, "L_above_L_Eff")));
    ck_assert_double_eq_tol(num(res.sk, "k_prime"), num(res.sk, "k_D"), 1e-12);
    const cJSON *fit = cJSON_GetObjectItem(res.sk, "fit");
    /* the window: the shells |n|^2 < 64 (1, 2, 4, 5, 8, 9, 10, 13, ..., 58, 61: 28 values) */
    int in_fit = 0;
    for (int b = 0; b < res.n_shells; b++) {
        in_fit += res.shells[b].in_fit;
        ck_assert(res.shells[b].in_fit == (res.shells[b].n < 64.0));
    }
    ck_assert_int_eq(in_fit, 28);
    ck_assert_int_eq((int)num(fit, "points"), in_fit);
    ck_assert_double_eq_tol(num(fit, "k_lo"), 2.0 * M_PI / L, 1e-9);
    ck_assert_double_eq_tol(num(fit, "k_hi"), 2.0 * M_PI * sqrt(61.0) / L, 1e-9);
    double Df = num(fit, "D_f");
    *err = num(fit, "D_f_err");
    *chi2_red = num(fit, "chi2_red");
    result_free(&res);
    gr_observable_free(st);
    free(x);
    free(y);
    free(mass);
    free(next);
    gsl_rng_free(r);
    return Df;
}

START_TEST(test_cascade_fractal_dimension)
{
    /* two cascades: D_2 = -log2(0.30) = 1.737 and -log2(0.52) = 0.943. S(k) ~ k^-D_2 only
     * asymptotically (the first splits of the box and the log-periodic modulation of a cascade
     * bias a 3-octave window), so the band is +-0.25; the two must also be told apart. */
    const double p1[4] = {0.4, 0.3, 0.2, 0.1}, p2[4] = {0.7, 0.1, 0.1, 0.1};
    const double D1 = -log2(0.30), D2 = -log2(0.52);
    double e1, e2, c1, c2;
    double f1 = cascade_fit(p1, 2024, &e1, &c1), f2 = cascade_fit(p2, 2025, &e2, &c2);
    ck_assert_msg(fabs(f1 - D1) < 0.25 && e1 > 0.0 && e1 < 0.15 && isfinite(c1),
                  "cascade 1: D_f = %g +- %g, D_2 = %g", f1, e1, D1);
    ck_assert_msg(fabs(f2 - D2) < 0.25 && e2 > 0.0 && e2 < 0.15 && isfinite(c2),
                  "cascade 2: D_f = %g +- %g, D_2 = %g", f2, e2, D2);
    ck_assert_msg(f1 - f2 > 0.5, "D_f %g and %g not told apart", f1, f2);
}
END_TEST

START_TEST(test_dissipative_regime_thesis_numbers)
{
    /* Table 4.1: phi = 0.353, eps_n = eps_t = 0.1 -> k_D d = 0.223, L_min = 0.084 m, L_Eff = 0.240 m
     * (sec. 4.1.2, d = 3 mm); N = 8000, L = 0.4 m is a system of Fig. 4.2, L > L_Eff -> k' = k_D */
    gr_scene s;
    scene_2d(&s, 8000, 0.4, 1.5e-3, 4.0);
    s.tangential = gr_model_find("tangential_dashpot");
    ck_assert_ptr_nonnull(s.tangential);
    s.contact.eps_t = 0.1;
    void *st = create_ok(&s);
    result r;
    finish_ok(st, &s, true, &r); /* no frames: files with headers only, no fit */
    ck_assert_int_eq(r.n_bins, 0);
    ck_assert_double_eq_tol(num(r.sk, "k_D_d"), 0.223, 0.0005);
    ck_assert_double_eq_tol(num(r.sk, "L_min"), 0.0847, 0.0005);
    ck_assert_double_eq_tol(num(r.sk, "L_Eff"), 0.2396, 0.0005);
    ck_assert_double_eq_tol(num(r.sk, "l0"),
                            M_PI * 3e-3 / (8.0 * 8000 * M_PI * 1.5e-3 * 1.5e-3 / 0.16), 1e-12);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(r.sk, "L_above_L_Eff")));
    ck_assert_double_eq_tol(num(r.sk, "k_prime"), num(r.sk, "k_D"), 1e-12);
    ck_assert_ptr_null(cJSON_GetObjectItem(cJSON_GetObjectItem(r.sk, "fit"), "D_f"));
    result_free(&r);
    gr_observable_free(st);

    /* Table 4.2: phi = 0.530, eps_n = 0.4, eps_t = 1 (no tangential law) -> k_D d = 0.142,
     * L_Eff = 0.37 m; L = 0.2 m (N = 3000) is below L_Eff -> k' = 2 k_D */
    scene_2d(&s, 3000, 0.2, 1.5e-3, 4.0);
    s.contact.eps_n = 0.4;
    st = create_ok(&s);
    finish_ok(st, &s, false, &r);
    ck_assert_double_eq_tol(num(r.sk, "k_D_d"), 0.142, 0.0005);
    ck_assert_double_eq_tol(num(r.sk, "L_Eff"), 0.376, 0.001);
    ck_assert(cJSON_IsFalse(cJSON_GetObjectItem(r.sk, "L_above_L_Eff")));
    ck_assert_double_eq_tol(num(r.sk, "k_prime"), 2.0 * num(r.sk, "k_D"), 1e-12);
    ck_assert_double_eq(num(r.sk, "eps_t"), 1.0);
    result_free(&r);
    gr_observable_free(st);

    /* eps_t comes from a tangential law that declares it constant (gr_model.constant_eps_t), not
     * from its name: tangential_dashpot, and a copy of it under another name, give eps_t; a copy
     * without the flag gives eps_t = 1 */
    gr_model copy = *gr_model_find("tangential_dashpot");
    copy.name = "dashpot_copy";
    const gr_model *laws[3] = {gr_model_find("tangential_dashpot"), &copy, &copy};
    const char *from[3] = {"tangential_dashpot eps_t", "dashpot_copy eps_t", NULL};
    for (int k = 0; k < 3; k++) {
        copy.constant_eps_t = k < 2;
        scene_2d(&s, 3000, 0.2, 1.5e-3, 4.0);
        s.tangential = laws[k];
        s.contact.eps_t = 0.3;
        st = create_ok(&s);
        finish_ok(st, &s, false, &r);
        ck_assert_double_eq(num(r.sk, "eps_t"), from[k] ? 0.3 : 1.0);
        const char *got = cJSON_GetStringValue(cJSON_GetObjectItem(r.sk, "eps_t_from"));
        ck_assert_ptr_nonnull(got);
        if (from[k]) {
            ck_assert_str_eq(got, from[k]);
        }
        result_free(&r);
        gr_observable_free(st);
    }

    /* elastic: k_D = 0, no window, no fit (but S(k) still measured) */
    scene_2d(&s, 500, 0.1, 1.5e-3, 4.0);
    s.contact.eps_n = 1.0;
    st = create_ok(&s);
    double x[500], y[500];
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(g, 3);
    uniform(g, 500, 0.1, x, y);
    sample_ok(st, 500, 0.1, x, y);
    finish_ok(st, &s, false, &r);
    ck_assert(cJSON_IsNull(cJSON_GetObjectItem(r.sk, "k_D")));
    ck_assert_ptr_null(cJSON_GetObjectItem(cJSON_GetObjectItem(r.sk, "fit"), "D_f"));
    ck_assert_int_gt(r.n_bins, 0);
    /* one frame: errors from the spread over each bin's vectors */
    for (int b = 0; b < r.n_bins; b++) {
        ck_assert(isfinite(r.bins[b].S_err) && r.bins[b].S_err > 0.0);
    }
    result_free(&r);
    gr_observable_free(st);
    gsl_rng_free(g);
}
END_TEST

/* A mixture's k_D and k d use its mean collision diameter: 2 <r> in 2D (the mean of r_i + r_j over
 * random pairs), sqrt(2 <r^2> + 2 <r>^2) in 3D; one size keeps 2 radius. */
START_TEST(test_mixture_collision_diameter)
{
    gr_scene s;
    scene_2d(&s, 3000, 0.2, 2e-3, 4.0);
    s.n_species = 2;
    s.species_radius.n = 2;
    s.species_radius.v[0] = 1e-3;
    s.species_radius.v[1] = 2e-3;
    s.species_count[0] = 2000;
    s.species_count[1] = 1000;
    gr_obs_setup su;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_obs_setup(&s, &su, &err), GR_OK);
    ck_assert_double_eq_tol(su.radius_mean, 4e-3 / 3.0, 1e-15);
    ck_assert_double_eq_tol(su.radius_sq_mean, 6e-6 / 3.0, 1e-18);
    ck_assert_double_eq_tol(gr_obs_collision_diameter(&su), 8e-3 / 3.0, 1e-15);
    su.dim = 3; /* pi <(r_i + r_j)^2> = pi (2 <r^2> + 2 <r>^2) */
    ck_assert_double_eq_tol(gr_obs_collision_diameter(&su),
                            sqrt(2.0 * 6e-6 / 3.0 + 2.0 * 16e-6 / 9.0), 1e-15);
    su.sizes = false;
    ck_assert_double_eq(gr_obs_collision_diameter(&su), 4e-3);
    void *st = create_ok(&s);
    result r;
    finish_ok(st, &s, false, &r);
    const double d = 8e-3 / 3.0, l0 = 0.04 / (2.0 * d * 3000); /* (4.7) with d */
    ck_assert_double_eq_tol(num(r.sk, "d"), d, 1e-15);
    ck_assert_double_eq_tol(num(r.sk, "l0"), l0, 1e-15);
    ck_assert_double_eq_tol(num(r.sk, "k_D_d"), (2.0 - 0.01 - 1.0) / (8.0 * l0) * d, 1e-12);
    result_free(&r);
    gr_observable_free(st);
}
END_TEST

START_TEST(test_direct_method_by_environment)
{
    /* GRANULE_SK_METHOD=direct gives the oracle's numbers through the observable */
    const int n = 1500;
    const double L = 0.15;
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(g, 11);
    double *x = malloc(sizeof(double) * n), *y = malloc(sizeof(double) * n);
    uniform(g, n, L, x, y);
    gr_scene s;
    scene_2d(&s, n, L, 1.5e-3, 4.0);
    result r[2];
    for (int m = 0; m < 2; m++) {
        setenv("GRANULE_SK_METHOD", m ? "direct" : "gridding", 1);
        void *st = create_ok(&s);
        sample_ok(st, n, L, x, y);
        finish_ok(st, &s, false, &r[m]);
        ck_assert_str_eq(cJSON_GetObjectItem(r[m].sk, "method")->valuestring,
                         m ? "direct" : "gridding");
        gr_observable_free(st);
    }
    unsetenv("GRANULE_SK_METHOD");
    ck_assert_int_eq(r[0].n_bins, r[1].n_bins);
    for (int b = 0; b < r[0].n_bins; b++) {
        ck_assert_msg(fabs(r[0].bins[b].S - r[1].bins[b].S) < 1e-5, "bin %d: %g vs %g", b,
                      r[0].bins[b].S, r[1].bins[b].S);
    }
    result_free(&r[0]);
    result_free(&r[1]);
    free(x);
    free(y);
    gsl_rng_free(g);
}
END_TEST

START_TEST(test_bad_params_refused)
{
    gr_scene s;
    void *st = NULL;
    gr_error err = {0};
    /* 1D */
    scene_2d(&s, 100, 0.1, 1.5e-3, 4.0);
    s.dim = 1;
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "dim = 2") != NULL, "%s", err.message);
    ck_assert(!(gr_obs_sk.dims & 1u) && (gr_obs_sk.dims & 2u));
    /* sk_kd_max: not positive, not finite, above the table's maximum, or reaching no vector */
    const double bad_kd[] = {0.0, -1.0, NAN, INFINITY, 65.0, 0.05};
    for (size_t i = 0; i < sizeof bad_kd / sizeof bad_kd[0]; i++) {
        scene_2d(&s, 100, 0.1, 1.5e-3, bad_kd[i]);
        err.message[0] = 0;
        ck_assert_msg(gr_scene_observable(&gr_obs_sk, &s, &st, &err) == GR_EINVAL,
                      "sk_kd_max = %g accepted", bad_kd[i]);
        ck_assert_msg(strstr(err.message, "sk_kd_max") != NULL, "%s", err.message);
    }
    /* the system */
    scene_2d(&s, 0, 0.1, 1.5e-3, 4.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    scene_2d(&s, 100, 0.0, 1.5e-3, 4.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    scene_2d(&s, 100, 0.1, 0.0, 4.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    /* too many vectors for the grid limit */
    scene_2d(&s, 100, 100.0, 1.5e-3, 64.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    /* an unknown method */
    setenv("GRANULE_SK_METHOD", "fast", 1);
    scene_2d(&s, 100, 0.1, 1.5e-3, 4.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_sk, &s, &st, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "GRANULE_SK_METHOD") != NULL, "%s", err.message);
    unsetenv("GRANULE_SK_METHOD");
    /* the engine */
    gr_sk_plan *pl = NULL;
    ck_assert_int_eq(gr_sk_plan_create(1.0, 10.0, 0, &pl, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_plan_create(1.0, 10.0, 17, &pl, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_plan_create(1.0, 0.9, 6, &pl, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_plan_create(-1.0, 10.0, 6, &pl, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_plan_create(1.0, 2000.0, 6, &pl, &err), GR_EINVAL);
    ck_assert_ptr_null(pl);
    ck_assert_int_eq(gr_sk_plan_create(1.0, 10.0, 6, &pl, &err), GR_OK);
    double S[400], x[1] = {0.3}, y[1] = {0.4};
    ck_assert_int_eq(gr_sk_compute(pl, 2, 1, x, y, S, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_compute(pl, GR_SK_GRIDDING, 0, x, y, S, &err), GR_EINVAL);
    ck_assert_int_eq(gr_sk_compute(pl, GR_SK_GRIDDING, 1, x, y, S, &err), GR_OK);
    ck_assert_double_eq_tol(S[0], 1.0, 1e-6); /* one particle: S = 1 */
    gr_sk_plan_free(pl);
    /* frames that do not fit the scene */
    scene_2d(&s, 4, 0.1, 1.5e-3, 4.0);
    st = create_ok(&s);
    double px[4] = {0.01, 0.02, 0.03, 0.04};
    gr_particles p = {.n = 4, .dim = 2, .L = 0.2, .x = px, .y = px, .vx = px, .vy = px};
    ck_assert_int_eq(gr_obs_sk.sample(st, &p, 0.0, &err), GR_EINVAL);
    p.L = 0.1;
    p.dim = 1;
    p.y = NULL;
    ck_assert_int_eq(gr_obs_sk.sample(st, &p, 0.0, &err), GR_EINVAL);
    p.dim = 2;
    p.y = px;
    p.n = 0;
    ck_assert_int_eq(gr_obs_sk.sample(st, &p, 0.0, &err), GR_EINVAL);
    gr_observable_free(st);
    /* the parameter table the scene parser uses */
    ck_assert_int_eq(gr_obs_sk.n_params, 1);
    ck_assert_str_eq(gr_obs_sk.params[0].name, "sk_kd_max");
    ck_assert_int_eq(gr_obs_sk.params[0].type, GR_PARAM_DOUBLE);
    ck_assert(gr_obs_sk.params[0].min_open && gr_obs_sk.params[0].def == 4.0);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_sk");
    TCase *tc = tcase_create("sk");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_gridding_matches_direct);
    tcase_add_test(tc, test_half_plane_without_k0);
    tcase_add_test(tc, test_square_lattice_bragg);
    tcase_add_test(tc, test_partial_lattices);
    tcase_add_test(tc, test_ideal_gas);
    tcase_add_test(tc, test_cascade_fractal_dimension);
    tcase_add_test(tc, test_dissipative_regime_thesis_numbers);
    tcase_add_test(tc, test_mixture_collision_diameter);
    tcase_add_test(tc, test_direct_method_by_environment);
    tcase_add_test(tc, test_bad_params_refused);
    suite_add_tcase(s, tc);
    return gr_test_run(s);
}
