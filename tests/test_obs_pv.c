/* Tests of the pv observable (src/analysis/obs_pv.c): the velocity distribution P(v) per component
 * (thesis App. A.1), its stretched-exponential tail fits (5.5) with the acceptance window of
 * Table 5.1, the crossover function P_0(v) (5.32) and the output files.
 *
 * The type's create/sample/finish are called directly (the observable need not be registered) with
 * frames of synthetic velocities drawn with GSL generators from fixed seeds, so every outcome is
 * deterministic yet would fail for a wrong histogram, normalisation or fit. One test feeds frames of
 * a tiny real 1D simulation; it also goes through gr_run once pv is in the registry. Every test
 * writes into a fresh folder made with mkdtemp, removed at the end (GRANULE_KEEP_TMP=1 keeps it). */
#include <check.h>
#include <cjson/cJSON.h>
#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/observe.h"
#include "granule/run.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_pv;

/* ---------- a fresh temporary folder per test ---------- */

static char g_root[240];
static char g_dir[256];

static void setup(void)
{
    snprintf(g_dir, sizeof g_dir, "%s/test-XXXXXX", g_root);
    ck_assert_msg(mkdtemp(g_dir) != NULL, "mkdtemp: %s", strerror(errno));
}

static void teardown(void)
{
    if (g_dir[0]) {
        gr_test_rm_tree(g_dir);
        g_dir[0] = 0;
    }
}

static bool exists(const char *dir, const char *name)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

/* ---------- scenes, frames, finishing ---------- */

static void pv_scene(gr_scene *s, int dim, int bins, double range)
{
    gr_scene_default(s);
    s->dim = dim;
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "pv_bins", bins, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "pv_range", range, NULL), GR_OK);
}

typedef void (*draw_fn)(gsl_rng *r, void *ctx, double *vx, double *vy);

/* Feed `frames` frames of n particles whose velocities come from `draw`. */
static void feed(const gr_observable_type *t, void *state, int dim, int n, int frames, gsl_rng *r,
                 draw_fn draw, void *ctx)
{
    double *vx = malloc(sizeof(double) * (size_t)n), *vy = malloc(sizeof(double) * (size_t)n);
    double *x = calloc((size_t)n, sizeof(double)), *y = calloc((size_t)n, sizeof(double));
    ck_assert(vx && vy && x && y);
    for (int f = 0; f < frames; f++) {
        for (int i = 0; i < n; i++) {
            double a = 0.0, b = 0.0;
            draw(r, ctx, &a, &b);
            vx[i] = a;
            vy[i] = b;
        }
        gr_particles p = {.n = n,
                          .dim = dim,
                          .L = 1.0,
                          .radius = 1.5e-3,
                          .mass = 3.53e-5,
                          .x = x,
                          .y = dim == 2 ? y : NULL,
                          .vx = vx,
                          .vy = dim == 2 ? vy : NULL};
        gr_error err = {0};
        ck_assert_msg(t->sample(state, &p, 1e-3 * f, &err) == GR_OK, "sample: %s", err.message);
    }
    free(vx);
    free(vy);
    free(x);
    free(y);
}

/* Run finish into g_dir; returns the summary's "pv" member (owned by *root). */
static cJSON *finish_into(void *state, const gr_scene *s, bool plots, cJSON **root)
{
    *root = cJSON_CreateObject();
    gr_output out = {.dir = g_dir,
                     .source = s->source,
                     .seed = s->seed,
                     .scene_hash = 0x1234abcdULL,
                     .summary = *root,
                     .plots = plots};
    gr_error err = {0};
    ck_assert_msg(gr_obs_pv.finish(state, &out, &err) == GR_OK, "finish: %s", err.message);
    cJSON *pv = cJSON_GetObjectItem(*root, "pv");
    ck_assert_ptr_nonnull(pv);
    return pv;
}

static double num(const cJSON *o, const char *path)
{
    /* dotted path, e.g. "tail.free.alpha"; NAN when missing or null */
    char buf[200];
    snprintf(buf, sizeof buf, "%s", path);
    const cJSON *cur = o;
    for (char *save = NULL, *tok = strtok_r(buf, ".", &save); tok && cur;
         tok = strtok_r(NULL, ".", &save)) {
        cur = cJSON_GetObjectItem(cur, tok);
    }
    return cur && cJSON_IsNumber(cur) ? cur->valuedouble : (double)NAN;
}

/* A CSV of the observable: checks the two-line commented header and the column line; returns the
 * rows (cols numbers each, "nan" allowed) in a malloc'ed array. */
typedef struct csv {
    int rows, cols;
    double *v;
    char columns[4096];
} csv;

static void read_csv(const char *name, csv *c)
{
    char path[600], line[4096];
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "%s not written", path);
    /* the notes are in NAME.meta.json; the CSV starts with its column names */
    snprintf(path, sizeof path, "%s/%.*s.meta.json", g_dir, (int)(strlen(name) - 4), name);
    FILE *meta = fopen(path, "r");
    ck_assert_msg(meta != NULL, "%s not written", path);
    size_t got = fread(line, 1, sizeof line - 1, meta);
    line[got] = 0;
    fclose(meta);
    ck_assert_msg(strstr(line, "\"granule ") &&
                      strstr(line, "\"scene <defaults>, hash 000000001234abcd, seed "),
                  "%s: %s", path, line);
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    ck_assert(fgets(line, sizeof line, f));
    line[strcspn(line, "\n")] = 0;
    snprintf(c->columns, sizeof c->columns, "%s", line);
    c->cols = 1;
    for (const char *p = line; *p; p++) {
        c->cols += *p == ',';
    }
    int cap = 64;
    c->rows = 0;
    c->v = malloc(sizeof(double) * (size_t)(cap * c->cols));
    while (fgets(line, sizeof line, f)) {
        if (c->rows == cap) {
            cap *= 2;
            c->v = realloc(c->v, sizeof(double) * (size_t)(cap * c->cols));
        }
        char *p = line;
        for (int k = 0; k < c->cols; k++) {
            char *end;
            c->v[c->rows * c->cols + k] = strtod(p, &end);
            ck_assert_msg(end != p, "%s row %d column %d unreadable: %s", name, c->rows, k, line);
            p = *end == ',' ? end + 1 : end;
        }
        c->rows++;
    }
    fclose(f);
}

#define AT(c, r, k) ((c)->v[(r) * (c)->cols + (k)])

/* ---------- velocity generators ---------- */

typedef struct gauss_ctx {
    double sx, sy;
} gauss_ctx;

static void draw_gauss(gsl_rng *r, void *ctx, double *vx, double *vy)
{
    gauss_ctx *g = ctx;
    *vx = 0.05 + gsl_ran_gaussian(r, g->sx); /* a drift the frame mean removes */
    *vy = -0.02 + gsl_ran_gaussian(r, g->sy);
}

/* generalised Gaussian: density proportional to exp(-(|v|/b)^alpha) per component */
typedef struct gen_ctx {
    double b, alpha;
} gen_ctx;

static double gen_one(gsl_rng *r, const gen_ctx *g)
{
    double m = g->b * pow(gsl_ran_gamma(r, 1.0 / g->alpha, 1.0), 1.0 / g->alpha);
    return gsl_rng_uniform(r) < 0.5 ? -m : m;
}

static void draw_gen(gsl_rng *r, void *ctx, double *vx, double *vy)
{
    *vx = gen_one(r, ctx);
    *vy = gen_one(r, ctx);
}

/* ---------- P(v) of Gaussian velocities ---------- */

/* Chi-square per degree of freedom of pv.csv against a density given by its CDF, on the bins
 * expecting at least 20 counts (Pearson errors from the expected counts). */
typedef double (*cdf_fn)(double v, const void *ctx);

static double chi2_against(const csv *c, double total, cdf_fn F, const void *ctx, int *dof)
{
    double chi2 = 0.0;
    int n = 0;
    for (int i = 0; i < c->rows; i++) {
        double lo = AT(c, i, 4), hi = AT(c, i, 5), w = hi - lo;
        double expect = total * (F(hi, ctx) - F(lo, ctx));
        if (expect < 20.0) {
            continue;
        }
        double d = AT(c, i, 1) - expect / (total * w);
        double e = sqrt(expect) / (total * w);
        chi2 += d * d / (e * e);
        n++;
    }
    *dof = n;
    return n ? chi2 / n : (double)NAN;
}

typedef struct mix {
    double s1, s2; /* equal mixture of two centred Gaussians (s2 = 0: one) */
} mix;

static double cdf_mix(double v, const void *ctx)
{
    const mix *m = ctx;
    return m->s2 > 0.0 ? 0.5 * (gsl_cdf_gaussian_P(v, m->s1) + gsl_cdf_gaussian_P(v, m->s2))
                       : gsl_cdf_gaussian_P(v, m->s1);
}

START_TEST(gaussian_1d_matches_density_and_alpha_2)
{
    const int n = 1000, frames = 400;
    const double sigma = 0.3;
    gr_scene s;
    pv_scene(&s, 1, 400, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 2024);
    gauss_ctx g = {sigma, sigma};
    feed(&gr_obs_pv, st, 1, n, frames, r, draw_gauss, &g);
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);

    csv c;
    read_csv("pv.csv", &c);
    ck_assert_int_eq(c.rows, 400);
    ck_assert_str_eq(c.columns, "v,density,density_error,counts,v_lo,v_hi,v_over_vrms,density_"
                                "scaled,fit_stretched,fit_crossover,"
                                "fit_crossover_log");
    /* velocities relative to the frame mean: each is N(0, sigma^2 (1 - 1/n)) */
    mix m = {sigma * sqrt(1.0 - 1.0 / n), 0.0};
    int dof;
    double total = (double)n * frames;
    double chi = chi2_against(&c, total, cdf_mix, &m, &dof);
    ck_assert_msg(dof > 80 && chi < 1.3, "P(v) against the Gaussian: chi2/dof = %g over %d bins",
                  chi, dof);
    /* the test can tell a 3% wider Gaussian apart */
    mix wrong = {1.03 * m.s1, 0.0};
    double chi_wrong = chi2_against(&c, total, cdf_mix, &wrong, &dof);
    ck_assert_msg(chi_wrong > 2.0, "a 3%% wider Gaussian passes too: chi2/dof = %g", chi_wrong);

    /* tails (5.5): a Gaussian is alpha = 2 with v0 = sqrt(2) sigma, accepted by the Table 5.1 window */
    double alpha = num(pv, "tail.free.alpha"), alpha_err = num(pv, "tail.free.alpha_err");
    ck_assert_msg(fabs(alpha - 2.0) < 0.05, "free alpha %g +- %g", alpha, alpha_err);
    ck_assert_msg(alpha_err > 0.0 && alpha_err < 0.05, "alpha error %g", alpha_err);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "accepted")));
    cJSON *range = cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "alpha_range");
    ck_assert_int_eq(cJSON_GetArraySize(range), 2);
    double lo = cJSON_GetArrayItem(range, 0)->valuedouble,
           hi = cJSON_GetArrayItem(range, 1)->valuedouble;
    ck_assert_msg(lo <= 2.0 + 1e-9 && hi >= 2.0 - 1e-9 && hi - lo < 0.4,
                  "accepted alpha range [%g, %g]", lo, hi);
    ck_assert_msg(fabs(num(pv, "tail.v0") / (sqrt(2.0) * sigma) - 1.0) < 0.03, "v0 %g",
                  num(pv, "tail.v0"));
    ck_assert_msg(num(pv, "tail.chi2_red") < 1.2, "chi2_red %g", num(pv, "tail.chi2_red"));
    ck_assert_msg(fabs(num(pv, "v_rms") / sigma - 1.0) < 0.01, "v_rms %g", num(pv, "v_rms"));
    /* independent samples: X(v) - X(-v) scatters as Poisson counts */
    double phi = num(pv, "tail.dispersion_corrected.dispersion");
    ck_assert_msg(phi > 0.6 && phi < 1.5, "dispersion %g of independent samples", phi);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(
        cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "dispersion_corrected"), "accepted")));
    /* the crossover (5.32) of a Gaussian: v_r = sqrt(2) sigma, crossover far out */
    ck_assert_msg(fabs(num(pv, "crossover.v_r") / (sqrt(2.0) * sigma) - 1.0) < 0.05, "v_r %g",
                  num(pv, "crossover.v_r"));
    ck_assert_msg(num(pv, "crossover.v_c_over_v_r") > 2.0, "v_c/v_r = %g for a Gaussian",
                  num(pv, "crossover.v_c_over_v_r"));
    free(c.v);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

START_TEST(gaussian_2d_pools_components)
{
    /* x and y with different widths: the pooled P(v) is the equal mixture of the two */
    const int n = 500, frames = 400;
    gr_scene s;
    pv_scene(&s, 2, 400, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 77);
    gauss_ctx g = {0.2, 0.3};
    feed(&gr_obs_pv, st, 2, n, frames, r, draw_gauss, &g);
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    double total = 2.0 * n * frames;
    ck_assert_double_eq(num(pv, "components"), total);
    ck_assert_double_eq(num(pv, "frames"), frames);
    /* T of (2.19) sums both components: T_ref ~ 0.2^2 + 0.3^2 from the first 8 frames */
    double T = (0.04 + 0.09) * (1.0 - 1.0 / n);
    ck_assert_msg(fabs(num(pv, "T_ref") / T - 1.0) < 0.05, "T_ref %g, expected about %g",
                  num(pv, "T_ref"), T);
    ck_assert_int_eq((int)num(pv, "T_ref_frames"), 8);
    ck_assert_double_eq_tol(num(pv, "v_max"), 12.0 * sqrt(num(pv, "T_ref")), 1e-12);
    ck_assert_msg(fabs(num(pv, "T_mean") / T - 1.0) < 0.01, "T_mean %g", num(pv, "T_mean"));

    csv c;
    read_csv("pv.csv", &c);
    double sum = 0.0;
    for (int i = 0; i < c.rows; i++) {
        sum += AT(&c, i, 3);
    }
    ck_assert_double_eq(sum + num(pv, "out_of_range_fraction") * total, total);
    mix m = {0.2 * sqrt(1.0 - 1.0 / n), 0.3 * sqrt(1.0 - 1.0 / n)};
    int dof;
    double chi = chi2_against(&c, total, cdf_mix, &m, &dof);
    ck_assert_msg(dof > 80 && chi < 1.3,
                  "pooled P(v) against the mixture: chi2/dof = %g over %d bins", chi, dof);
    mix only_x = {m.s1, 0.0};
    ck_assert_msg(chi2_against(&c, total, cdf_mix, &only_x, &dof) > 10.0,
                  "x alone fits the pooled P(v)");
    free(c.v);

    /* scaled speeds: c = |v| / sqrt(<|v|^2>) has <c^2> = 1 and unit integral (nothing out of range) */
    read_csv("pv_speed.csv", &c);
    ck_assert_str_eq(c.columns, "c,density,density_error,counts,c_lo,c_hi,speed");
    double norm = 0.0, m2 = 0.0;
    for (int i = 0; i < c.rows; i++) {
        double w = AT(&c, i, 5) - AT(&c, i, 4);
        norm += AT(&c, i, 1) * w;
        m2 += AT(&c, i, 0) * AT(&c, i, 0) * AT(&c, i, 1) * w;
    }
    ck_assert_double_eq_tol(norm, 1.0, 1e-7);
    ck_assert_msg(fabs(m2 - 1.0) < 2e-3, "<c^2> = %g", m2);
    free(c.v);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

/* ---------- stretched-exponential tails ---------- */

static cJSON *run_generalised(int dim, double b, double alpha, int n, int frames,
                              unsigned long seed, cJSON **root, void **st)
{
    gr_scene s;
    pv_scene(&s, dim, 400, 12.0);
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    gen_ctx g = {b, alpha};
    feed(&gr_obs_pv, *st, dim, n, frames, r, draw_gen, &g);
    gsl_rng_free(r);
    return finish_into(*st, &s, false, root);
}

START_TEST(exponential_tails_give_alpha_1)
{
    /* v = sign * Exp(b): P(v) = exp(-|v|/b) / (2b), the Laplace distribution (A.8 with alpha = 1) */
    cJSON *root;
    void *st;
    cJSON *pv = run_generalised(1, 0.1, 1.0, 10000, 40, 5, &root, &st);
    double alpha = num(pv, "tail.free.alpha");
    ck_assert_msg(fabs(alpha - 1.0) < 0.05, "free alpha %g +- %g", alpha,
                  num(pv, "tail.free.alpha_err"));
    ck_assert_msg(fabs(num(pv, "tail.free.v0") / 0.1 - 1.0) < 0.05, "v0 %g",
                  num(pv, "tail.free.v0"));
    cJSON *range = cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "alpha_range");
    ck_assert_int_eq(cJSON_GetArraySize(range), 2);
    double lo = cJSON_GetArrayItem(range, 0)->valuedouble,
           hi = cJSON_GetArrayItem(range, 1)->valuedouble;
    ck_assert_msg(lo <= 1.0 + 1e-9 && hi >= 1.0 - 1e-9, "accepted alpha range [%g, %g] misses 1",
                  lo, hi);
    ck_assert_msg(hi < 1.3, "accepted alpha range [%g, %g] reaches towards a Gaussian", lo, hi);
    /* the Gaussian start of the crossover fit must not hide an exponential: v_A = v_r^2/v_c = b */
    ck_assert_msg(
        cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "crossover"), "converged")),
        "crossover fit");
    ck_assert_msg(fabs(num(pv, "crossover.v_A") / 0.1 - 1.0) < 0.1, "v_A %g",
                  num(pv, "crossover.v_A"));
    cJSON_Delete(root);
    gr_observable_free(st);
}
END_TEST

START_TEST(overdispersed_counts_detected)
{
    /* every frame sampled 10 times over: counts come in multiples of 10, their variance is 10 X, and
     * the thesis's sqrt(X) errors are sqrt(10) too small. The mirror-bin dispersion finds the factor,
     * the thesis's acceptance rejects the true alpha = 1, the dispersion-corrected one keeps it. */
    gr_scene s;
    pv_scene(&s, 1, 400, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 31);
    const int n = 5000;
    double *vx = malloc(sizeof(double) * n), dummy;
    gen_ctx g = {0.1, 1.0};
    for (int f = 0; f < 20; f++) {
        for (int i = 0; i < n; i++) {
            draw_gen(r, &g, &vx[i], &dummy);
        }
        gr_particles p = {.n = n, .dim = 1, .L = 1.0, .vx = vx};
        for (int k = 0; k < 10; k++) {
            ck_assert_int_eq(gr_obs_pv.sample(st, &p, 10 * f + k, &err), GR_OK);
        }
    }
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    double phi = num(pv, "tail.dispersion_corrected.dispersion");
    ck_assert_msg(phi > 6.0 && phi < 16.0, "dispersion %g, expected about 10", phi);
    ck_assert_msg(num(pv, "tail.chi2_red") > 3.0, "chi2_red %g with sqrt(X) errors",
                  num(pv, "tail.chi2_red"));
    ck_assert(!cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "accepted")) ||
              num(pv, "tail.alpha_halfwidth") < 0.02);
    cJSON *dc = cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "dispersion_corrected");
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(dc, "accepted")));
    double mid = num(dc, "alpha"), half = num(dc, "alpha_halfwidth");
    ck_assert_msg(fabs(mid - 1.0) <= half + 1e-9, "dispersion-corrected alpha %g +- %g misses 1",
                  mid, half);
    ck_assert_msg(fabs(num(pv, "tail.free.alpha") - 1.0) < 0.1, "free alpha %g",
                  num(pv, "tail.free.alpha"));
    free(vx);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

START_TEST(stretched_tails_give_alpha_1_5_in_2d)
{
    cJSON *root;
    void *st;
    cJSON *pv = run_generalised(2, 0.05, 1.5, 5000, 40, 11, &root, &st);
    double alpha = num(pv, "tail.free.alpha"), e = num(pv, "tail.free.alpha_err");
    ck_assert_msg(fabs(alpha - 1.5) < 0.06 && fabs(alpha - 1.5) < 4.0 * e, "free alpha %g +- %g",
                  alpha, e);
    ck_assert_msg(fabs(num(pv, "tail.free.v0") / 0.05 - 1.0) < 0.05, "v0 %g",
                  num(pv, "tail.free.v0"));
    double mid = num(pv, "tail.alpha"), half = num(pv, "tail.alpha_halfwidth");
    ck_assert_msg(fabs(mid - 1.5) <= half + 1e-9 && half < 0.2, "accepted alpha %g +- %g", mid,
                  half);
    /* the Table A.1 window (two decades) is reported too and agrees */
    ck_assert_double_eq(num(pv, "tail_a1.window.counts_max"), 5000.0);
    ck_assert_msg(fabs(num(pv, "tail_a1.free.alpha") - 1.5) < 0.1, "A.1 alpha %g",
                  num(pv, "tail_a1.free.alpha"));
    cJSON_Delete(root);
    gr_observable_free(st);
}
END_TEST

/* ---------- the crossover function (5.32) ---------- */

/* Inverse-CDF sampling of P_0(v) = D exp(-(v/v_r)^2 / (1 + |v|/v_c)) from a fine table. */
typedef struct xo_ctx {
    int n;
    double vmax, *cdf;
} xo_ctx;

static void xo_init(xo_ctx *x, double vr, double vc)
{
    x->n = 400001;
    x->vmax = 80.0 * vr * vr / vc;
    x->cdf = malloc(sizeof(double) * (size_t)x->n);
    double h = 2.0 * x->vmax / (x->n - 1), prev = 0.0, acc = 0.0;
    for (int i = 0; i < x->n; i++) {
        double v = -x->vmax + i * h, p = exp(-(v / vr) * (v / vr) / (1.0 + fabs(v) / vc));
        acc += i ? 0.5 * (p + prev) * h : 0.0;
        x->cdf[i] = acc;
        prev = p;
    }
    for (int i = 0; i < x->n; i++) {
        x->cdf[i] /= acc;
    }
}

static void draw_xo(gsl_rng *r, void *ctx, double *vx, double *vy)
{
    xo_ctx *x = ctx;
    double u = gsl_rng_uniform(r);
    int a = 0, b = x->n - 1;
    while (b - a > 1) {
        int m = (a + b) / 2;
        if (x->cdf[m] <= u) {
            a = m;
        } else {
            b = m;
        }
    }
    double h = 2.0 * x->vmax / (x->n - 1), f = (u - x->cdf[a]) / (x->cdf[b] - x->cdf[a]);
    *vx = -x->vmax + (a + f) * h;
    *vy = 0.0;
}

START_TEST(crossover_fit_recovers_vr_vc)
{
    /* Table 5.3's first row: v_c / v_r = 1.524 */
    const double vr = 0.2, vc = 0.3048;
    xo_ctx x;
    xo_init(&x, vr, vc);
    gr_scene s;
    pv_scene(&s, 1, 400, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 3);
    feed(&gr_obs_pv, st, 1, 10000, 100, r, draw_xo, &x);
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    cJSON *xo = cJSON_GetObjectItem(pv, "crossover");
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(xo, "converged")));
    double fvr = num(xo, "v_r"), fvc = num(xo, "v_c");
    ck_assert_msg(fabs(fvr / vr - 1.0) < 0.03, "v_r %g +- %g, true %g", fvr, num(xo, "v_r_err"),
                  vr);
    ck_assert_msg(fabs(fvc / vc - 1.0) < 0.08, "v_c %g +- %g, true %g", fvc, num(xo, "v_c_err"),
                  vc);
    ck_assert_msg(num(xo, "chi2_red") < 1.3, "chi2_red %g", num(xo, "chi2_red"));
    double q = fvc / fvr;
    ck_assert_double_eq_tol(num(xo, "P_vc_over_P0"), exp(-0.5 * q * q), 1e-12);
    ck_assert_double_eq_tol(num(xo, "v_A"), fvr * fvr / fvc, 1e-12);
    /* Table 5.3: P(v_c)/P(0) = 0.313 for v_c/v_r = 1.524 */
    ck_assert_msg(fabs(num(xo, "P_vc_over_P0") - 0.313) < 0.03, "P(v_c)/P(0) = %g",
                  num(xo, "P_vc_over_P0"));
    /* the fit on log axes (equal weights on ln X) recovers the same P_0: on data that follow (5.32)
     * the two weightings differ by their noise only; its bins of 50 counts carry 14 % noise on ln X,
     * so its v_c is looser */
    cJSON *xl = cJSON_GetObjectItem(pv, "crossover_log");
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(xl, "converged")));
    double lvr = num(xl, "v_r"), lvc = num(xl, "v_c");
    ck_assert_msg(fabs(lvr / vr - 1.0) < 0.03, "log fit: v_r %g +- %g, true %g", lvr,
                  num(xl, "v_r_err"), vr);
    ck_assert_msg(fabs(lvc / vc - 1.0) < 0.1, "log fit: v_c %g +- %g, true %g", lvc,
                  num(xl, "v_c_err"), vc);
    ck_assert_msg(fabs(lvr - vr) < 4.0 * num(xl, "v_r_err") &&
                      fabs(lvc - vc) < 4.0 * num(xl, "v_c_err"),
                  "log fit errors too small: v_r %g +- %g, v_c %g +- %g", lvr, num(xl, "v_r_err"),
                  lvc, num(xl, "v_c_err"));
    ck_assert_double_eq_tol(num(xl, "P_vc_over_P0"), exp(-0.5 * (lvc / lvr) * (lvc / lvr)), 1e-12);
    /* the same fit over fewer decades below the peak (counts >= 50, 500, ...): the first is the fit
     * above, each next one has fewer bins, and on data that follow (5.32) every depth finds the
     * true v_r within its error (the depth moves v_r on the RFM's P(v), not on P_0's own) */
    const cJSON *depths = cJSON_GetObjectItem(xl, "by_depth"), *d;
    ck_assert_int_ge(cJSON_GetArraySize(depths), 3);
    double cmin = 0.0;
    int n_prev = 1 << 30;
    cJSON_ArrayForEach(d, depths)
    {
        ck_assert_double_eq_tol(num(d, "counts_min"), cmin > 0.0 ? 10.0 * cmin : 50.0, 1e-9);
        cmin = num(d, "counts_min");
        const int n = (int)num(d, "n_points");
        ck_assert_int_lt(n, n_prev);
        n_prev = n;
        if (cmin == 50.0) {
            ck_assert_double_eq(num(d, "v_r"), lvr);
            ck_assert_double_eq_tol(num(d, "v_c_over_v_r"), lvc / lvr, 1e-12);
        }
        if (cJSON_IsTrue(cJSON_GetObjectItem(d, "converged")) && n >= 10) {
            ck_assert_msg(fabs(num(d, "v_r") - vr) < 4.0 * num(d, "v_r_err"),
                          "counts >= %g: v_r %g +- %g, true %g", cmin, num(d, "v_r"),
                          num(d, "v_r_err"), vr);
        }
    }
    free(x.cdf);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

/* ---------- normalisation ---------- */

START_TEST(histogram_integrates_to_in_range_fraction)
{
    /* a narrow range (1.5 sqrt(T_ref)) leaves about 13% of the Gaussian outside */
    const int n = 2000, frames = 50;
    gr_scene s;
    pv_scene(&s, 1, 101, 1.5);
    void *st;
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 99);
    gauss_ctx g = {1.0, 1.0};
    /* keep the frames to count the in-range values independently */
    double *all = malloc(sizeof(double) * (size_t)(n * frames));
    double *vx = malloc(sizeof(double) * (size_t)n);
    for (int f = 0; f < frames; f++) {
        double mean = 0.0, dummy;
        for (int i = 0; i < n; i++) {
            draw_gauss(r, &g, &vx[i], &dummy);
            mean += vx[i];
        }
        mean /= n;
        for (int i = 0; i < n; i++) {
            all[f * n + i] = vx[i] - mean;
        }
        gr_particles p = {.n = n, .dim = 1, .L = 1.0, .vx = vx};
        ck_assert_msg(gr_obs_pv.sample(st, &p, f, &err) == GR_OK, "%s", err.message);
    }
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    double vmax = num(pv, "v_max");
    ck_assert_double_eq_tol(vmax, 1.5 * sqrt(num(pv, "T_ref")), 1e-12);
    long inside = 0;
    for (int k = 0; k < n * frames; k++) {
        inside += all[k] >= -vmax && all[k] < vmax;
    }
    double frac = (double)inside / (n * frames);
    csv c;
    read_csv("pv.csv", &c);
    ck_assert_int_eq(c.rows, 101);
    double integral = 0.0;
    for (int i = 0; i < c.rows; i++) {
        integral += AT(&c, i, 1) * (AT(&c, i, 5) - AT(&c, i, 4));
    }
    ck_assert_msg(fabs(integral - frac) < 1e-9, "integral %.12g, in-range fraction %.12g", integral,
                  frac);
    ck_assert_double_eq_tol(num(pv, "out_of_range_fraction"), 1.0 - frac, 1e-12);
    ck_assert_msg(fabs(frac - 0.8664) < 0.01, "in-range fraction %g, erf(1.5/sqrt(2)) = 0.866",
                  frac);
    /* odd bins: one bin centred on v = 0 */
    ck_assert_double_eq_tol(AT(&c, 50, 0), 0.0, 1e-12);
    free(c.v);
    free(all);
    free(vx);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

/* ---------- files and summary ---------- */

START_TEST(files_and_summary)
{
    cJSON *root;
    void *st;
    cJSON *pv = run_generalised(2, 0.1, 1.2, 2000, 50, 21, &root, &st);
    ck_assert_str_eq(cJSON_GetObjectItem(pv, "file")->valuestring, "pv.csv");
    const char *fields[] = {"frames",
                            "components",
                            "bins",
                            "range",
                            "v_max",
                            "bin_width",
                            "T_ref",
                            "T_ref_frames",
                            "T_mean",
                            "v_rms",
                            "out_of_range_fraction",
                            "P0"};
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
        ck_assert_msg(isfinite(num(pv, fields[k])), "pv.%s missing", fields[k]);
    }
    ck_assert_double_eq(num(pv, "bins"), 400);
    ck_assert_double_eq(num(pv, "range"), 12);
    /* the thesis's acceptance window (Table 5.1) and the fit results */
    ck_assert_double_eq(num(pv, "tail.window.counts_min"), 50.0);
    ck_assert_double_eq(num(pv, "tail.window.counts_max"), 50000.0);
    ck_assert_double_eq(num(pv, "tail.window.chi2_red_max"), 1.2);
    const char *tail_fields[] = {"tail.n_points",
                                 "tail.v_min",
                                 "tail.v_max",
                                 "tail.decades",
                                 "tail.alpha",
                                 "tail.alpha_halfwidth",
                                 "tail.alpha_best",
                                 "tail.chi2_red",
                                 "tail.v0",
                                 "tail.A",
                                 "tail.free.alpha",
                                 "tail.free.alpha_err",
                                 "tail.free.v0",
                                 "tail.free.chi2_red",
                                 "crossover.v_r",
                                 "crossover.v_c",
                                 "crossover.v_c_over_v_r",
                                 "crossover.P_vc_over_P0",
                                 "crossover.v_A",
                                 "crossover.chi2_red",
                                 "crossover_log.v_r",
                                 "crossover_log.v_c",
                                 "crossover_log.v_c_over_v_r",
                                 "crossover_log.P_vc_over_P0",
                                 "moon.C_alpha_2",
                                 "moon.C_alpha_1_5",
                                 "moon.C_alpha_1_16",
                                 "speed.rms"};
    for (size_t k = 0; k < sizeof tail_fields / sizeof tail_fields[0]; k++) {
        ck_assert_msg(isfinite(num(pv, tail_fields[k])), "pv.%s missing", tail_fields[k]);
    }
    ck_assert_int_eq(
        cJSON_GetArraySize(cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "alpha_range")), 2);
    cJSON *local = cJSON_GetObjectItem(cJSON_GetObjectItem(pv, "tail"), "decades_local");
    ck_assert_msg(cJSON_GetArraySize(local) >= 2, "%d local decades", cJSON_GetArraySize(local));
    ck_assert_msg(fabs(num(pv, "tail.free.alpha") - 1.2) < 0.1, "free alpha %g",
                  num(pv, "tail.free.alpha"));
    /* the summary serialises (no NaN) and parses back */
    char *text = cJSON_PrintUnformatted(root);
    cJSON *back = cJSON_Parse(text);
    ck_assert_msg(back != NULL, "summary does not parse back: %s", text);
    cJSON_Delete(back);
    free(text);

    /* files: commented header, columns; the tail plot's variable (5.6) */
    csv c;
    read_csv("pv_tail.csv", &c);
    ck_assert_str_eq(
        c.columns,
        "v_over_vrms,ln_v_over_vrms,density_sym,density_sym_error,counts,P_over_P0,moon");
    ck_assert(c.rows > 50);
    for (int i = 0; i < c.rows; i++) {
        ck_assert_double_eq_tol(AT(&c, i, 1), log(AT(&c, i, 0)), 1e-6);
        double ratio = AT(&c, i, 5);
        if (ratio > 0.0 && ratio < 1.0) {
            ck_assert_double_eq_tol(AT(&c, i, 6), -log(-log(ratio)), 1e-6);
        }
    }
    free(c.v);
    ck_assert(exists(g_dir, "pv_speed.csv"));
    cJSON_Delete(root);
    gr_observable_free(st);
}
END_TEST

START_TEST(plots_drawn_or_noted)
{
    gr_scene s;
    pv_scene(&s, 1, 200, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_OK, "%s", err.message);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 8);
    gen_ctx g = {0.1, 1.0};
    feed(&gr_obs_pv, st, 1, 1000, 50, r, draw_gen, &g);
    cJSON *root;
    finish_into(st, &s, true, &root);
    bool gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
    if (gnuplot) {
        ck_assert_msg(exists(g_dir, "pv.png") && exists(g_dir, "pv_tail.png") &&
                          exists(g_dir, "pv_speed.png"),
                      "plots missing although gnuplot is installed: %s",
                      cJSON_PrintUnformatted(cJSON_GetObjectItem(root, "plot_notes")));
        ck_assert_ptr_null(cJSON_GetObjectItem(root, "plot_notes"));
    } else {
        ck_assert_int_eq(cJSON_GetArraySize(cJSON_GetObjectItem(root, "plot_notes")), 3);
    }
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

/* ---------- parameters and refusals ---------- */

START_TEST(bad_params_refused)
{
    ck_assert_str_eq(gr_obs_pv.name, "pv");
    ck_assert_uint_eq(gr_obs_pv.dims, 7u); /* 1D, 2D and 3D */
    ck_assert_int_eq(gr_obs_pv.n_params, 2);
    ck_assert_str_eq(gr_obs_pv.params[0].name, "pv_bins");
    ck_assert_int_eq(gr_obs_pv.params[0].type, GR_PARAM_INT);
    ck_assert_double_eq(gr_obs_pv.params[0].def, 400);
    ck_assert_uint_le(gr_obs_pv.params[0].offset + sizeof(int), gr_obs_pv.params_size);
    ck_assert_str_eq(gr_obs_pv.params[1].name, "pv_range");
    ck_assert_int_eq(gr_obs_pv.params[1].type, GR_PARAM_DOUBLE);
    ck_assert_double_eq(gr_obs_pv.params[1].def, 12);
    ck_assert_uint_le(gr_obs_pv.params[1].offset + sizeof(double), gr_obs_pv.params_size);

    struct {
        int dim, bins;
        double range;
        const char *needle;
    } bad[] = {
        {1, 0, 12.0, "pv_bins"},   {1, -5, 12.0, "pv_bins"},
        {2, 9, 12.0, "pv_bins"},   {1, 1000001, 12.0, "pv_bins"},
        {1, 400, 0.0, "pv_range"}, {1, 400, -3.0, "pv_range"},
        {2, 400, 0.5, "pv_range"}, {1, 400, (double)NAN, "pv_range"},
        {1, 400, 1e9, "pv_range"}, {4, 400, 12.0, "dim"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        gr_scene s;
        pv_scene(&s, bad[k].dim, bad[k].bins, bad[k].range);
        void *st = NULL;
        gr_error err = {0};
        ck_assert_msg(gr_scene_observable(&gr_obs_pv, &s, &st, &err) == GR_EINVAL,
                      "case %zu accepted", k);
        ck_assert_msg(strstr(err.message, bad[k].needle), "case %zu: message '%s' does not name %s",
                      k, err.message, bad[k].needle);
    }
    /* frames that do not match the scene */
    gr_scene s;
    pv_scene(&s, 2, 400, 12.0);
    void *st;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    double v[3] = {0.1, -0.2, 0.3};
    gr_particles p1 = {.n = 3, .dim = 1, .vx = v};
    ck_assert_int_eq(gr_obs_pv.sample(st, &p1, 0.0, &err), GR_EINVAL);
    gr_particles p0 = {.n = 0, .dim = 2, .vx = v, .vy = v};
    ck_assert_int_eq(gr_obs_pv.sample(st, &p0, 0.0, &err), GR_EINVAL);
    double bad_v[3] = {0.1, (double)NAN, 0.3};
    gr_particles pn = {.n = 3, .dim = 2, .vx = v, .vy = bad_v};
    ck_assert_int_eq(gr_obs_pv.sample(st, &pn, 0.0, &err), GR_EINVAL);
    gr_observable_free(st);

    /* frames at rest (T = 0) cannot set the binning */
    pv_scene(&s, 1, 400, 12.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    double same[3] = {0.5, 0.5, 0.5};
    gr_particles ps = {.n = 3, .dim = 1, .vx = same};
    for (int f = 0; f < 3; f++) {
        ck_assert_int_eq(gr_obs_pv.sample(st, &ps, f, &err), GR_OK);
    }
    cJSON *root = cJSON_CreateObject();
    gr_output out = {.dir = g_dir, .source = s.source, .seed = s.seed, .summary = root};
    ck_assert_int_eq(gr_obs_pv.finish(st, &out, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "T_ref"), "%s", err.message);
    cJSON_Delete(root);
    gr_observable_free(st);

    /* no frames at all: no files, a note */
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    root = cJSON_CreateObject();
    out.summary = root;
    ck_assert_int_eq(gr_obs_pv.finish(st, &out, &err), GR_OK);
    ck_assert(!exists(g_dir, "pv.csv"));
    ck_assert_double_eq(num(cJSON_GetObjectItem(root, "pv"), "frames"), 0);
    cJSON_Delete(root);
    gr_observable_free(st);
}
END_TEST

/* ---------- the reference temperature and the count windows ---------- */

static int bins_with_counts(const csv *c, double lo, double hi)
{
    int n = 0;
    for (int i = 0; i < c->rows; i++) {
        n += AT(c, i, 3) >= lo && AT(c, i, 3) <= hi;
    }
    return n;
}

START_TEST(reference_from_first_frames)
{
    /* 8 frames at sigma = 1 fix the binning; later frames at sigma = 2 do not move it */
    gr_scene s;
    pv_scene(&s, 1, 400, 3.0);
    void *st;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 4);
    gauss_ctx g1 = {1.0, 1.0}, g2 = {2.0, 2.0};
    feed(&gr_obs_pv, st, 1, 1000, 8, r, draw_gauss, &g1);
    feed(&gr_obs_pv, st, 1, 1000, 92, r, draw_gauss, &g2);
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    ck_assert_int_eq((int)num(pv, "T_ref_frames"), 8);
    ck_assert_msg(fabs(num(pv, "T_ref") - 1.0) < 0.05, "T_ref %g", num(pv, "T_ref"));
    ck_assert_msg(fabs(num(pv, "T_mean") - (8.0 + 92.0 * 4.0) / 100.0) < 0.1, "T_mean %g",
                  num(pv, "T_mean"));
    /* |v| > 3 happens for 0.27% at sigma 1 and 13.4% at sigma 2 */
    double expect = (8.0 * 0.0027 + 92.0 * 0.1336) / 100.0;
    ck_assert_msg(fabs(num(pv, "out_of_range_fraction") - expect) < 0.01,
                  "out of range %g, expected %g", num(pv, "out_of_range_fraction"), expect);
    cJSON_Delete(root);
    gr_observable_free(st);

    /* fewer than 8 frames: finish fixes the binning from those */
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    feed(&gr_obs_pv, st, 1, 1000, 3, r, draw_gauss, &g2);
    pv = finish_into(st, &s, false, &root);
    ck_assert_int_eq((int)num(pv, "T_ref_frames"), 3);
    ck_assert_msg(fabs(num(pv, "T_ref") - 4.0) < 0.3, "T_ref %g", num(pv, "T_ref"));
    ck_assert_double_eq(num(pv, "components"), 3000);
    cJSON_Delete(root);
    gr_observable_free(st);

    /* a frame larger than the reference buffer (2^20 numbers) sets T_ref alone; with 2.4e6
     * components the peak holds more than 50 000 counts, so the windows cut the fitted bins */
    pv_scene(&s, 2, 400, 12.0);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    feed(&gr_obs_pv, st, 2, 600000, 2, r, draw_gauss, &g1);
    pv = finish_into(st, &s, false, &root);
    ck_assert_int_eq((int)num(pv, "T_ref_frames"), 1);
    ck_assert_msg(fabs(num(pv, "T_ref") - 2.0) < 0.02, "T_ref %g", num(pv, "T_ref"));
    ck_assert_double_eq(num(pv, "components"), 2.4e6);
    csv c;
    read_csv("pv.csv", &c);
    int n51 = bins_with_counts(&c, 50.0, 50000.0), na1 = bins_with_counts(&c, 50.0, 5000.0);
    ck_assert_msg(bins_with_counts(&c, 50.0, 1e12) > n51 && n51 > na1,
                  "windows do not cut: %d, %d bins", n51, na1);
    ck_assert_int_eq((int)num(pv, "tail.n_points"), n51);
    ck_assert_int_eq((int)num(pv, "tail_a1.n_points"), na1);
    free(c.v);
    cJSON_Delete(root);
    gr_observable_free(st);
    gsl_rng_free(r);
}
END_TEST

/* ---------- frames of a real (tiny) simulation ---------- */

START_TEST(tiny_real_run)
{
    /* 1D RFM: N = 100 on a ring of reduced length 0.1 m, eps = 0.1, 0.3 s */
    const char *set[] = {"system.dim=1",
                         "system.N=100",
                         "system.reduced_length=0.1",
                         "placement.kind=uniform",
                         "model.tangential=none",
                         "model.eps_n=0.1",
                         "run.seed=5",
                         "run.progress=false",
                         "output.plots=false"};
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, NULL, set, sizeof set / sizeof set[0], &err) == GR_OK, "%s",
                  err.message);
    ck_assert_int_eq(gr_analysis_set(&s.analysis, "pv_bins", 200, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&s.analysis, "pv_range", 12.0, NULL), GR_OK);
    gr_sim *sim;
    ck_assert_msg(gr_sim_create(&s, &sim, &err) == GR_OK, "%s", err.message);
    void *st;
    ck_assert_int_eq(gr_scene_observable(&gr_obs_pv, &s, &st, &err), GR_OK);
    ck_assert_msg(gr_sim_step(sim, 100000, &err) == GR_OK, "%s", err.message); /* 0.1 s warm-up */
    double Tsum = 0.0;
    for (int k = 0; k < 200; k++) {
        ck_assert_msg(gr_sim_step(sim, 1000, &err) == GR_OK, "%s", err.message);
        gr_particles p = gr_sim_particles(sim);
        Tsum += gr_sim_temperature(sim);
        ck_assert_msg(gr_obs_pv.sample(st, &p, gr_sim_time(sim), &err) == GR_OK, "%s", err.message);
    }
    cJSON *root;
    cJSON *pv = finish_into(st, &s, false, &root);
    ck_assert_double_eq(num(pv, "frames"), 200);
    ck_assert_double_eq(num(pv, "components"), 20000);
    /* T of (2.19) as the engine measures it */
    ck_assert_msg(fabs(num(pv, "T_mean") / (Tsum / 200) - 1.0) < 1e-9, "T_mean %g vs %g",
                  num(pv, "T_mean"), Tsum / 200);
    ck_assert_msg(num(pv, "out_of_range_fraction") < 1e-3, "out of range %g",
                  num(pv, "out_of_range_fraction"));
    csv c;
    read_csv("pv.csv", &c);
    double integral = 0.0, first = 0.0;
    for (int i = 0; i < c.rows; i++) {
        integral += AT(&c, i, 1) * (AT(&c, i, 5) - AT(&c, i, 4));
        first += AT(&c, i, 0) * AT(&c, i, 3);
    }
    ck_assert_double_eq_tol(integral, 1.0 - num(pv, "out_of_range_fraction"), 1e-9);
    /* velocities are relative to the frame mean: the histogram's mean is ~0 (to the bin width) */
    ck_assert_msg(fabs(first / 20000) < num(pv, "bin_width"), "mean of P(v) %g", first / 20000);
    ck_assert_msg(num(pv, "tail.n_points") >= 5, "%g points in the window",
                  num(pv, "tail.n_points"));
    double a = num(pv, "tail.alpha_best");
    ck_assert_msg(a >= 0.2 && a <= 3.0, "alpha_best %g", a);
    free(c.v);
    cJSON_Delete(root);
    gr_observable_free(st);
    gr_sim_free(sim);

    /* through gr_run, once pv is registered (before that, observables = pv is refused) */
    if (!gr_observable_find("pv")) {
        return;
    }
    char out[400];
    snprintf(out, sizeof out, "%s/run", g_dir);
    snprintf(s.out_dir, sizeof s.out_dir, "%s", out);
    snprintf(s.observables, sizeof s.observables, "pv");
    s.warmup = 0.05;
    s.duration = 0.1;
    gr_run_result res;
    ck_assert_msg(gr_run(&s, NULL, &res, &err) == GR_OK, "%s", err.message);
    ck_assert(exists(out, "pv.csv"));
    char path[600];
    snprintf(path, sizeof path, "%s/summary.json", out);
    FILE *f = fopen(path, "r");
    ck_assert_ptr_nonnull(f);
    static char text[1 << 20];
    size_t len = fread(text, 1, sizeof text - 1, f);
    text[len] = 0;
    fclose(f);
    cJSON *sum = cJSON_Parse(text);
    ck_assert_ptr_nonnull(sum);
    cJSON *jpv = cJSON_GetObjectItem(cJSON_GetObjectItem(sum, "analysis"), "pv");
    ck_assert_ptr_nonnull(jpv);
    ck_assert_double_eq(num(jpv, "frames"), (double)res.samples);
    cJSON_Delete(sum);
}
END_TEST

static Suite *pv_suite(void)
{
    Suite *s = suite_create("obs_pv");
    TCase *dist = tcase_create("distribution");
    tcase_add_checked_fixture(dist, setup, teardown);
    tcase_set_timeout(dist, 120);
    tcase_add_test(dist, gaussian_1d_matches_density_and_alpha_2);
    tcase_add_test(dist, gaussian_2d_pools_components);
    tcase_add_test(dist, histogram_integrates_to_in_range_fraction);
    tcase_add_test(dist, reference_from_first_frames);
    suite_add_tcase(s, dist);

    TCase *fits = tcase_create("fits");
    tcase_add_checked_fixture(fits, setup, teardown);
    tcase_set_timeout(fits, 120);
    tcase_add_test(fits, exponential_tails_give_alpha_1);
    tcase_add_test(fits, overdispersed_counts_detected);
    tcase_add_test(fits, stretched_tails_give_alpha_1_5_in_2d);
    tcase_add_test(fits, crossover_fit_recovers_vr_vc);
    suite_add_tcase(s, fits);

    TCase *io = tcase_create("io");
    tcase_add_checked_fixture(io, setup, teardown);
    tcase_set_timeout(io, 120);
    tcase_add_test(io, files_and_summary);
    tcase_add_test(io, plots_drawn_or_noted);
    tcase_add_test(io, bad_params_refused);
    tcase_add_test(io, tiny_real_run);
    suite_add_tcase(s, io);
    return s;
}

int main(void)
{
    gsl_set_error_handler_off();
    if (gr_test_tmp_root(g_root, sizeof g_root, "test_obs_pv", "pv") != 0) {
        return EXIT_FAILURE;
    }
    int status = gr_test_run(pv_suite());
    gr_test_tmp_root_done(g_root, "test_obs_pv");
    return status;
}
