/* The gaps observable (1D neighbour separations in reduced coordinates, thesis sec. 3.3): driven
 * directly through gr_obs_gaps's functions with synthetic configurations of known structure
 * (fixed seeds), results read back from gaps.csv, gaps_moments.csv and the summary member.
 *
 * Poisson (uniformly random) points on the free ring of length L' have Dirichlet spacings: the
 * h-th neighbour separation is L' Beta(h, N - h) exactly, which tends to Gamma(h) with mean
 * h L'/N (G_1 exponential) for large N; both forms are checked. */
#include <check.h>
#include <cjson/cJSON.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_gamma.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/observe.h"
#include "granule/scene.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_gaps;

/* ------------------------------------------------------------------------------------------ */
/* helpers */

static void scene_1d(gr_scene *s, int N, double Lr, double radius, int h_max, int bins,
                     bool log_bins)
{
    gr_scene_default(s);
    s->dim = 1;
    s->N = N;
    s->radius = radius;
    s->L = Lr + N * 2.0 * radius;
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "gaps_h_max", h_max, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "gaps_bins", bins, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&s->analysis, "gaps_log", log_bins, NULL), GR_OK);
}

static void *create_ok(const gr_scene *s)
{
    void *st = NULL;
    gr_error err = {0};
    int rc = gr_scene_observable(&gr_obs_gaps, s, &st, &err);
    ck_assert_msg(rc == GR_OK, "create: %s", err.message);
    ck_assert_ptr_nonnull(st);
    return st;
}

static void sample_ok(void *st, const gr_scene *s, const double *x, double t)
{
    gr_particles p = {.n = s->N, .dim = 1, .L = s->L, .radius = s->radius, .mass = s->mass, .x = x};
    gr_error err = {0};
    int rc = gr_obs_gaps.sample(st, &p, t, &err);
    ck_assert_msg(rc == GR_OK, "sample: %s", err.message);
}

static int sample_rc(void *st, const gr_particles *p)
{
    gr_error err = {0};
    int rc = gr_obs_gaps.sample(st, p, 0.0, &err);
    ck_assert_msg(rc == GR_OK || err.message[0], "an error without a message");
    return rc;
}

/* One row of gaps.csv. */
typedef struct row {
    int h;
    char bin[8];
    double lo, hi, R, count, density, density_error, neg_ln_R, x, density_x, density_x_error;
} row;

/* One row of gaps_moments.csv. */
typedef struct mrow {
    int h, m;
    double moment, stderr_, reduced, reduced_stderr;
} mrow;

/* What finish() wrote. */
typedef struct result {
    char dir[64];
    cJSON *analysis; /* the summary object holding "gaps" */
    const cJSON *gaps;
    row *rows;
    int n_rows;
    mrow *mrows;
    int n_mrows;
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

static void finish_ok(void *st, const gr_scene *s, bool plots, result *r)
{
    memset(r, 0, sizeof *r);
    snprintf(r->dir, sizeof r->dir, "/tmp/test_obs_gaps_XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(r->dir));
    r->analysis = cJSON_CreateObject();
    gr_output out = {.dir = r->dir,
                     .source = s->source,
                     .seed = s->seed,
                     .scene_hash = 0x1234,
                     .summary = r->analysis,
                     .plots = plots};
    gr_error err = {0};
    int rc = gr_obs_gaps.finish(st, &out, &err);
    ck_assert_msg(rc == GR_OK, "finish: %s", err.message);
    r->gaps = cJSON_GetObjectItem(r->analysis, "gaps");
    ck_assert_ptr_nonnull(r->gaps);

    char header[512], line[1024];
    FILE *f = open_csv(r->dir, "gaps.csv", header, sizeof header);
    ck_assert_str_eq(
        header,
        "h,binning,R_lo,R_hi,R,count,density,density_error,neg_ln_R,x,density_x,density_x_error\n");
    int cap = 1024;
    r->rows = malloc(sizeof(row) * (size_t)cap);
    while (fgets(line, sizeof line, f)) {
        if (r->n_rows == cap) {
            cap *= 2;
            r->rows = realloc(r->rows, sizeof(row) * (size_t)cap);
        }
        row *w = &r->rows[r->n_rows++];
        int got = sscanf(line, "%d,%7[a-z],%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &w->h, w->bin,
                         &w->lo, &w->hi, &w->R, &w->count, &w->density, &w->density_error,
                         &w->neg_ln_R, &w->x, &w->density_x, &w->density_x_error);
        ck_assert_msg(got == 12, "bad gaps.csv line: %s", line);
    }
    fclose(f);

    f = open_csv(r->dir, "gaps_moments.csv", header, sizeof header);
    ck_assert_str_eq(header, "h,m,moment,stderr,reduced_moment,reduced_stderr,converged,samples\n");
    r->mrows = malloc(sizeof(mrow) * 12 * 256);
    while (fgets(line, sizeof line, f)) {
        ck_assert(r->n_mrows < 12 * 256);
        mrow *w = &r->mrows[r->n_mrows++];
        int got = sscanf(line, "%d,%d,%lf,%lf,%lf,%lf", &w->h, &w->m, &w->moment, &w->stderr_,
                         &w->reduced, &w->reduced_stderr);
        ck_assert_msg(got == 6, "bad gaps_moments.csv line: %s", line);
    }
    fclose(f);
}

static void result_free(result *r)
{
    const char *names[] = {"gaps.csv", "gaps_moments.csv", "gaps.png", "gaps_lnR.png",
                           "gaps_moments.png"};
    char path[256];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", r->dir, names[i]);
        remove(path);
    }
    rmdir(r->dir);
    cJSON_Delete(r->analysis);
    free(r->rows);
    free(r->mrows);
}

/* Rows of one G_h in one binning (consecutive in the file); returns their number. */
static const row *hist_rows(const result *r, int h, const char *bin, int *n)
{
    const row *first = NULL;
    *n = 0;
    for (int i = 0; i < r->n_rows; i++) {
        if (r->rows[i].h == h && !strcmp(r->rows[i].bin, bin)) {
            if (!first) {
                first = &r->rows[i];
            }
            (*n)++;
        }
    }
    ck_assert_msg(first != NULL, "no rows for h = %d, %s", h, bin);
    return first;
}

static const mrow *moment_row(const result *r, int h, int m)
{
    for (int i = 0; i < r->n_mrows; i++) {
        if (r->mrows[i].h == h && r->mrows[i].m == m) {
            return &r->mrows[i];
        }
    }
    ck_abort_msg("no moment row h = %d, m = %d", h, m);
    return NULL;
}

static double jnum(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(o, name);
    ck_assert_msg(cJSON_IsNumber(v), "summary member %s missing or not a number", name);
    return v->valuedouble;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* N uniformly random (Poisson) points on the free ring [0, L'), sorted, as particle positions
 * u_i + i d + shift: the reduced spacings are those of the uniform points. `unwrap` > 0 adds
 * integer multiples of L up to that many (as unwrapped positions may carry), otherwise the
 * positions are wrapped into [0, L). */
static void poisson_frame(gsl_rng *rng, const gr_scene *s, double *x, int unwrap)
{
    double d = 2.0 * s->radius, Lr = s->L - s->N * d, shift = gsl_rng_uniform(rng) * s->L;
    for (int i = 0; i < s->N; i++) {
        x[i] = gsl_rng_uniform(rng) * Lr;
    }
    qsort(x, (size_t)s->N, sizeof(double), cmp_double);
    for (int i = 0; i < s->N; i++) {
        x[i] += i * d + shift;
        if (unwrap > 0) {
            x[i] +=
                (double)((long)gsl_rng_uniform_int(rng, 2 * (unsigned long)unwrap + 1) - unwrap) *
                s->L;
        } else {
            x[i] = fmod(x[i], s->L);
        }
    }
}

static void wrap(const gr_scene *s, const double *in, double *out)
{
    for (int i = 0; i < s->N; i++) {
        out[i] = fmod(in[i], s->L);
        out[i] += out[i] < 0.0 ? s->L : 0.0;
        out[i] = out[i] >= s->L ? 0.0 : out[i];
    }
}

/* Pearson chi-square of a histogram's counts against a CDF F(R) (bins with expected >= 5; the rest,
 * including the weight outside the binned range, pooled into one cell). Returns the p-value.
 * The windows R_{i,i+h}, i = 1..N, of one frame overlap (neighbouring windows share h - 1 gaps),
 * so the counts are over-dispersed: a bin count's variance is at most 2h - 1 times the
 * independent one (Cauchy-Schwarz over the 2h - 1 windows sharing a gap with window i), and the
 * statistic is divided by that factor. For h = 1 the spacings are negatively correlated
 * (they sum to L'), and the plain statistic is conservative. */
typedef double (*cdf_fn)(double R, const double *par);

static double chi2_pvalue(const row *rows, int n, int h, double total, cdf_fn F, const double *par,
                          double *chi2_out, int *dof_out)
{
    double chi2 = 0.0, rest_obs = total, rest_exp = total;
    int cells = 0;
    for (int i = 0; i < n; i++) {
        double e = total * (F(rows[i].hi, par) - F(rows[i].lo, par));
        if (e >= 5.0) {
            chi2 += (rows[i].count - e) * (rows[i].count - e) / e;
            rest_obs -= rows[i].count;
            rest_exp -= e;
            cells++;
        }
    }
    if (rest_exp >= 5.0) {
        chi2 += (rest_obs - rest_exp) * (rest_obs - rest_exp) / rest_exp;
        cells++;
    }
    ck_assert_msg(cells >= 5, "too few cells for a chi-square test (%d)", cells);
    chi2 /= 2.0 * h - 1.0;
    *chi2_out = chi2;
    *dof_out = cells - 1;
    return gsl_cdf_chisq_Q(chi2, cells - 1);
}

/* par = {h, N, L'}: R / L' ~ Beta(h, N - h) (spacings of uniform points on a circle) */
static double cdf_beta(double R, const double *par)
{
    double u = R / par[2];
    return u <= 0.0 ? 0.0 : u >= 1.0 ? 1.0 : gsl_cdf_beta_P(u, par[0], par[1] - par[0]);
}

/* par = {h, N, L'}: Gamma(h) with scale L'/N (the large-N limit; exponential for h = 1) */
static double cdf_gamma(double R, const double *par)
{
    return R <= 0.0 ? 0.0 : gsl_cdf_gamma_P(R, par[0], par[2] / par[1]);
}

/* ------------------------------------------------------------------------------------------ */

START_TEST(test_even_spacing_single_spike)
{
    /* evenly spaced particles: every R_{i,i+h} = h L'/N, one bin per G_h holds all of them.
     * N = 37 and 30 bins on [0, L') keep h L'/N away from every bin edge (37 is prime). */
    gr_scene s;
    const int N = 37, frames = 12, h_max = 5;
    const double Lr = 0.8;
    scene_1d(&s, N, Lr, 2e-3, h_max, 30, true);
    void *st = create_ok(&s);
    double x[37], y[37];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 3);
    for (int f = 0; f < frames; f++) {
        double shift = gsl_rng_uniform(rng) * 5.0 * s.L;
        for (int i = 0; i < N; i++) {
            x[i] = shift + i * s.L / N; /* unwrapped: beyond L */
        }
        if (f % 2) {
            wrap(&s, x, y); /* wrapped into [0, L), the array starting anywhere on the ring */
            sample_ok(st, &s, y, f);
        } else {
            sample_ok(st, &s, x, f);
        }
    }
    gsl_rng_free(rng);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);

    const double mean = Lr / N;
    for (int h = 1; h <= h_max; h++) {
        const char *bins[] = {"lin", "log"};
        for (int b = 0; b < 2; b++) {
            int n, hit = -1, nonzero = 0;
            const row *rows = hist_rows(&r, h, bins[b], &n);
            ck_assert_int_eq(n, 30);
            for (int i = 0; i < n; i++) {
                if (rows[i].count > 0) {
                    nonzero++;
                    hit = i;
                }
            }
            ck_assert_msg(nonzero == 1, "h = %d %s: %d bins filled, expected one spike", h, bins[b],
                          nonzero);
            ck_assert_double_eq(rows[hit].count, (double)N * frames);
            ck_assert_msg(rows[hit].lo <= h * mean && h * mean < rows[hit].hi,
                          "h = %d %s: spike in [%g, %g), not at %g", h, bins[b], rows[hit].lo,
                          rows[hit].hi, h * mean);
            /* density integrates to one within the spike bin */
            ck_assert_double_eq_tol(rows[hit].density * (rows[hit].hi - rows[hit].lo), 1.0, 1e-6);
            /* mean-scaled column: the spike sits around x = 1 */
            ck_assert_double_eq_tol(rows[hit].x, rows[hit].R / (h * mean), 1e-6);
        }
        for (int m = 1; m <= 12; m++) {
            const mrow *mr = moment_row(&r, h, m);
            ck_assert_msg(fabs(mr->reduced - 1.0) < 1e-9,
                          "h = %d m = %d: reduced moment %.12g, expected 1", h, m, mr->reduced);
            ck_assert_msg(fabs(mr->moment / pow(h * mean, m) - 1.0) < 1e-9,
                          "h = %d m = %d: moment %g", h, m, mr->moment);
        }
    }
    ck_assert_double_eq_tol(jnum(r.gaps, "mean_signed_separation"), mean, 1e-13);
    ck_assert_double_eq(jnum(r.gaps, "overlap_fraction"), 0.0);
    ck_assert_double_eq_tol(jnum(r.gaps, "R1_min"), mean, 1e-12);
    ck_assert_double_eq_tol(jnum(r.gaps, "R1_max"), mean, 1e-12);
    ck_assert_double_eq(jnum(r.gaps, "samples"), frames);
    result_free(&r);
}
END_TEST

START_TEST(test_poisson_exact_beta_chi2)
{
    /* N = 100 uniform points: R_{i,i+h} / L' ~ Beta(h, N - h) exactly; chi-square of every G_h in
     * both binnings. The test has power: the same counts must reject Beta(h + 1, N - h - 1). */
    gr_scene s;
    const int N = 100, frames = 1000, h_max = 4;
    const double Lr = 1.0;
    scene_1d(&s, N, Lr, 5e-4, h_max, 200, true);
    void *st = create_ok(&s);
    double x[100];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 11);
    for (int f = 0; f < frames; f++) {
        poisson_frame(rng, &s, x, f % 3);
        sample_ok(st, &s, x, f * 1e-3);
    }
    gsl_rng_free(rng);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    for (int h = 1; h <= h_max; h++) {
        const char *bins[] = {"lin", "log"};
        for (int b = 0; b < 2; b++) {
            int n, dof;
            double chi2;
            const row *rows = hist_rows(&r, h, bins[b], &n);
            double par[3] = {h, N, Lr}, wrong[3] = {h + 1, N, Lr};
            double p = chi2_pvalue(rows, n, h, (double)N * frames, cdf_beta, par, &chi2, &dof);
            ck_assert_msg(
                p > 1e-3,
                "h = %d %s: chi2 / (2h - 1) = %.1f for %d dof against Beta(h, N - h), p = %.2g", h,
                bins[b], chi2, dof, p);
            double q = chi2_pvalue(rows, n, h, (double)N * frames, cdf_beta, wrong, &chi2, &dof);
            ck_assert_msg(q < 1e-6,
                          "h = %d %s: the wrong law Beta(h + 1) was not rejected (p = %.2g)", h,
                          bins[b], q);
        }
    }
    result_free(&r);
}
END_TEST

START_TEST(test_poisson_gamma_large_N)
{
    /* N = 2000 points on L' = 2 m: G_1 is exponential with mean L'/N and G_h is Gamma(h) with
     * scale L'/N (chi-square within errors), in the logarithmic and in fine linear bins */
    gr_scene s;
    const int N = 2000, frames = 100, h_max = 3;
    const double Lr = 2.0;
    scene_1d(&s, N, Lr, 1e-3, h_max, 4000, true);
    void *st = create_ok(&s);
    double *x = malloc(sizeof(double) * N);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 12345);
    for (int f = 0; f < frames; f++) {
        poisson_frame(rng, &s, x, 0);
        sample_ok(st, &s, x, f);
    }
    gsl_rng_free(rng);
    free(x);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    for (int h = 1; h <= h_max; h++) {
        const char *bins[] = {"lin", "log"};
        for (int b = 0; b < 2; b++) {
            int n, dof;
            double chi2;
            const row *rows = hist_rows(&r, h, bins[b], &n);
            double par[3] = {h, N, Lr};
            double p = chi2_pvalue(rows, n, h, (double)N * frames, cdf_gamma, par, &chi2, &dof);
            ck_assert_msg(
                p > 1e-3,
                "h = %d %s: chi2 / (2h - 1) = %.1f for %d dof against Gamma(%d, L'/N), p = %.2g", h,
                bins[b], chi2, dof, h, p);
        }
        /* G_1 near R = 0 is N/L' (exponential): the first linear bin holds its bin average */
        if (h == 1) {
            int n;
            const row *rows = hist_rows(&r, 1, "lin", &n);
            ck_assert_msg(fabs(rows[0].density / (N / Lr * (1.0 - exp(-N / Lr * rows[0].hi)) /
                                                  (N / Lr * rows[0].hi)) -
                               1.0) < 0.03,
                          "G_1 near R = 0: %g", rows[0].density);
        }
    }
    result_free(&r);
}
END_TEST

START_TEST(test_mean_exact_each_frame)
{
    /* (3.19): sum_i R_{i,i+1} = L' in every frame, so <R> = L'/N with zero spread across frames;
     * likewise <R_{i,i+h}> = h L'/N. Positions unwrapped over up to a thousand windings. */
    gr_scene s;
    const int N = 300, frames = 64, h_max = 7;
    const double Lr = 0.7;
    scene_1d(&s, N, Lr, 1.5e-3, h_max, 100, false);
    void *st = create_ok(&s);
    double x[300];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 99);
    for (int f = 0; f < frames; f++) {
        poisson_frame(rng, &s, x, 1000);
        sample_ok(st, &s, x, f);
    }
    gsl_rng_free(rng);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    for (int h = 1; h <= h_max; h++) {
        const mrow *mr = moment_row(&r, h, 1);
        double want = h * Lr / N;
        ck_assert_msg(fabs(mr->moment / want - 1.0) < 1e-10, "h = %d: <R> = %.15g, expected %.15g",
                      h, mr->moment, want);
        /* the block-averaging variance sum2/n - mean^2 cancels to ~sqrt(eps) of the mean */
        ck_assert_msg(mr->stderr_ < 1e-6 * want, "h = %d: <R> varies between frames (stderr %g)", h,
                      mr->stderr_);
    }
    const cJSON *m = cJSON_GetObjectItem(r.gaps, "moments");
    ck_assert_int_eq(cJSON_GetArraySize(m), 12);
    ck_assert_double_eq_tol(cJSON_GetArrayItem(m, 0)->valuedouble, Lr / N, 1e-10 * Lr / N);
    ck_assert_double_eq_tol(jnum(r.gaps, "mean_signed_separation"), Lr / N, 1e-12 * Lr / N);
    /* no "log" rows without gaps_log */
    for (int i = 0; i < r.n_rows; i++) {
        ck_assert_str_eq(r.rows[i].bin, "lin");
    }
    result_free(&r);
}
END_TEST

START_TEST(test_mixture_rods_own_lengths)
{
    /* a mixture of rods 2 mm and 6 mm long, alternating, with known free gaps g_i: each gap is the
     * centre distance less r_i + r_{i+1} and L' = L - sum_i 2 r_i, so R_{i,i+1} = g_i exactly and
     * <R> = L'/N (3.19); at one rod length (the largest) the gaps would come out 4 mm short */
    enum { N = 12 };
    gr_scene s;
    double r[N], g[N], x[N], len = 0.0, Lr = 0.0;
    for (int i = 0; i < N; i++) {
        r[i] = i % 2 ? 3e-3 : 1e-3;
        g[i] = 1e-3 * (1 + i % 5); /* 1-5 mm */
        len += 2.0 * r[i];
        Lr += g[i];
    }
    scene_1d(&s, N, Lr, 3e-3, 2, 50, false);
    s.L = Lr + len;
    s.n_species = 2;
    s.species_radius.n = 2;
    s.species_radius.v[0] = 1e-3;
    s.species_radius.v[1] = 3e-3;
    s.species_count[0] = s.species_count[1] = N / 2;
    void *st = create_ok(&s);
    x[0] = 0.05;
    for (int i = 1; i < N; i++) {
        x[i] = x[i - 1] + r[i - 1] + g[i - 1] + r[i];
    }
    /* the last gap closes the ring: x[0] + L - x[N-1] = r[N-1] + g[N-1] + r[0] */
    int sp[N];
    for (int i = 0; i < N; i++) {
        sp[i] = i % 2;
    }
    const gr_particles p = {.n = N,
                            .dim = 1,
                            .L = s.L,
                            .radius = 3e-3,
                            .mass = s.mass,
                            .x = x,
                            .radii = r,
                            .species = sp,
                            .n_species = 2};
    ck_assert_int_eq(sample_rc(st, &p), GR_OK);
    result res;
    finish_ok(st, &s, false, &res);
    gr_observable_free(st);
    ck_assert_double_eq_tol(jnum(res.gaps, "mean_signed_separation"), Lr / N, 1e-12);
    ck_assert_double_eq_tol(jnum(res.gaps, "R1_min"), 1e-3, 1e-12);
    ck_assert_double_eq_tol(jnum(res.gaps, "R1_max"), 5e-3, 1e-12);
    double m2 = 0.0;
    for (int i = 0; i < N; i++) {
        m2 += g[i] * g[i] / N;
    }
    ck_assert_double_eq_tol(moment_row(&res, 1, 2)->moment, m2, 1e-15);
    /* per species: the rods alternate, so every neighbour pair is of kind 1-2 and carries all */
    const cJSON *kinds = cJSON_GetObjectItem(res.gaps, "species_neighbours"),
                *mean = cJSON_GetObjectItem(res.gaps, "species_mean_R");
    ck_assert_int_eq(cJSON_GetArraySize(kinds), 3);
    ck_assert_double_eq(cJSON_GetArrayItem(kinds, 0)->valuedouble, 0.0);
    ck_assert_double_eq(cJSON_GetArrayItem(kinds, 1)->valuedouble, N);
    ck_assert(cJSON_IsNull(cJSON_GetArrayItem(mean, 0)));
    ck_assert_double_eq_tol(cJSON_GetArrayItem(mean, 1)->valuedouble, Lr / N, 1e-15);
    result_free(&res);
}
END_TEST

START_TEST(test_overlap_convention)
{
    /* soft particles in contact overlap: s_i = -delta. R = |s_i| (3.17); the signed mean stays
     * L'/N exactly (3.19) and the overlapping pair is counted */
    gr_scene s;
    const int N = 10;
    const double Lr = 1.0, d = 0.02, delta = 1e-4;
    scene_1d(&s, N, Lr, d / 2, 2, 50, true);
    void *st = create_ok(&s);
    double x[10];
    /* gaps: pair (0,1) overlaps by delta, the others share L' + delta */
    x[0] = 0.3;
    x[1] = x[0] + d - delta;
    for (int i = 2; i < N; i++) {
        x[i] = x[i - 1] + d + (Lr + delta) / (N - 1);
    }
    sample_ok(st, &s, x, 0.0);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    ck_assert_double_eq_tol(jnum(r.gaps, "mean_signed_separation"), Lr / N, 1e-14);
    ck_assert_double_eq_tol(jnum(r.gaps, "overlap_fraction"), 1.0 / N, 1e-14);
    ck_assert_double_eq_tol(jnum(r.gaps, "R1_min"), delta, 1e-12);
    ck_assert_double_eq_tol(moment_row(&r, 1, 1)->moment, Lr / N + 2.0 * delta / N, 1e-12);
    /* R_{0,2} = R_{9,1} = -delta + (L' + delta)/(N - 1) */
    int n;
    const row *rows = hist_rows(&r, 2, "lin", &n);
    double want = -delta + (Lr + delta) / (N - 1);
    bool found = false;
    for (int i = 0; i < n; i++) {
        found |= rows[i].count == 2.0 && rows[i].lo <= want && want < rows[i].hi;
    }
    ck_assert_msg(found, "R_{0,2} = %g not binned", want);
    result_free(&r);
}
END_TEST

START_TEST(test_wrapped_vs_unwrapped)
{
    /* the same configurations as unwrapped positions (random windings per particle), wrapped into
     * [0, L), and wrapped with the array rotated (another particle first): identical results */
    gr_scene s;
    const int N = 150, frames = 200, h_max = 6;
    scene_1d(&s, N, 1.3, 1e-3, h_max, 120, true);
    void *a = create_ok(&s), *b = create_ok(&s), *c = create_ok(&s);
    double x[150], y[150], z[150];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 2024);
    for (int f = 0; f < frames; f++) {
        poisson_frame(rng, &s, x, 5);
        wrap(&s, x, y);
        int k = (int)gsl_rng_uniform_int(rng, N);
        for (int i = 0; i < N; i++) {
            z[i] = y[(i + k) % N];
        }
        sample_ok(a, &s, x, f);
        sample_ok(b, &s, y, f);
        sample_ok(c, &s, z, f);
    }
    gsl_rng_free(rng);
    result ra, rb, rc;
    finish_ok(a, &s, false, &ra);
    finish_ok(b, &s, false, &rb);
    finish_ok(c, &s, false, &rc);
    gr_observable_free(a);
    gr_observable_free(b);
    gr_observable_free(c);
    ck_assert_int_eq(ra.n_rows, 6 * 2 * 120);
    ck_assert_int_eq(rb.n_rows, ra.n_rows);
    ck_assert_int_eq(rc.n_rows, ra.n_rows);
    for (int i = 0; i < ra.n_rows; i++) {
        ck_assert_msg(
            ra.rows[i].count == rb.rows[i].count && ra.rows[i].count == rc.rows[i].count,
            "row %d (h = %d %s R = %g): counts %g (unwrapped), %g (wrapped), %g (rotated)", i,
            ra.rows[i].h, ra.rows[i].bin, ra.rows[i].R, ra.rows[i].count, rb.rows[i].count,
            rc.rows[i].count);
    }
    ck_assert_int_eq(ra.n_mrows, 12 * h_max);
    for (int i = 0; i < ra.n_mrows; i++) {
        double u = ra.mrows[i].moment, v = rb.mrows[i].moment, w = rc.mrows[i].moment;
        ck_assert_msg(fabs(u / v - 1.0) < 1e-9 && fabs(w / v - 1.0) < 1e-12,
                      "h = %d m = %d: %.12g %.12g %.12g", ra.mrows[i].h, ra.mrows[i].m, u, v, w);
    }
    result_free(&ra);
    result_free(&rb);
    result_free(&rc);
}
END_TEST

START_TEST(test_poisson_moments_gamma)
{
    /* <R_{i,i+h}^m> of Poisson points against the Gamma(h) moments, in their exact finite-N form
     * L'^m Gamma(h + m) Gamma(N) / (Gamma(h) Gamma(N + m)) -> Gamma(h + m) / Gamma(h) (L'/N)^m,
     * m = 1..6 within 4 block-averaging errors (each below 10 %); m up to 12 finite */
    gr_scene s;
    const int N = 500, frames = 800, h_max = 3;
    const double Lr = 1.5;
    scene_1d(&s, N, Lr, 1e-3, h_max, 50, false);
    void *st = create_ok(&s);
    double x[500];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 77);
    for (int f = 0; f < frames; f++) {
        poisson_frame(rng, &s, x, 1);
        sample_ok(st, &s, x, f);
    }
    gsl_rng_free(rng);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    for (int h = 1; h <= h_max; h++) {
        for (int m = 1; m <= 12; m++) {
            const mrow *mr = moment_row(&r, h, m);
            double exact = exp(m * log(Lr) + gsl_sf_lngamma(h + m) + gsl_sf_lngamma(N) -
                               gsl_sf_lngamma(h) - gsl_sf_lngamma(N + m));
            double gamma_limit = exp(gsl_sf_lngamma(h + m) - gsl_sf_lngamma(h)) * pow(Lr / N, m);
            ck_assert_msg(isfinite(mr->moment) && mr->moment > 0.0 && isfinite(mr->stderr_),
                          "h = %d m = %d", h, m);
            /* the two forms agree to O(m^2 / N) */
            ck_assert(fabs(exact / gamma_limit - 1.0) < m * (m + h) / (double)N);
            if (m <= 6) {
                ck_assert_msg(fabs(mr->moment - exact) < 4.0 * mr->stderr_ + 1e-3 * exact,
                              "h = %d m = %d: <R^m> = %.6g +- %.2g, Gamma moment %.6g", h, m,
                              mr->moment, mr->stderr_, exact);
                ck_assert_msg(mr->stderr_ < 0.1 * exact,
                              "h = %d m = %d: error %.2g too large to test", h, m, mr->stderr_);
                ck_assert_double_eq_tol(mr->reduced, mr->moment / pow(h * Lr / N, m),
                                        1e-9 * mr->reduced);
            }
        }
    }
    /* summary: reduced moments of G_1 near m! (exponential) */
    const cJSON *red = cJSON_GetObjectItem(r.gaps, "moments_reduced");
    ck_assert_double_eq_tol(cJSON_GetArrayItem(red, 2)->valuedouble, 6.0, 0.15);
    result_free(&r);
}
END_TEST

START_TEST(test_decimation_renormalisation)
{
    /* (3.25) data: dropping every other particle of an N-particle ring (same L') gives an
     * N/2-particle ring whose G_1 is the N ring's G_2 restricted to even i. With both decimations
     * (even and odd particles), G_2(R;N) = G_1(R;N/2)_even + G_1(R;N/2)_odd bin by bin (same R
     * axis, same bins: no rescaling), and G_4(R;N) likewise from G_2(R;N/2). */
    const int N = 200, frames = 150;
    const double Lr = 1.0, d = 2e-3;
    gr_scene sa, sb;
    scene_1d(&sa, N, Lr, d / 2, 4, 400, true);
    scene_1d(&sb, N / 2, Lr, d / 2, 2, 400, true);
    void *a = create_ok(&sa), *even = create_ok(&sb), *odd = create_ok(&sb);
    double u[200], xa[200], xe[100], xo[100];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 5);
    for (int f = 0; f < frames; f++) {
        for (int i = 0; i < N; i++) {
            u[i] = gsl_rng_uniform(rng) * Lr; /* reduced positions */
        }
        qsort(u, N, sizeof(double), cmp_double);
        for (int i = 0; i < N; i++) {
            xa[i] = u[i] + i * d;
        }
        for (int j = 0; j < N / 2; j++) {
            xe[j] = u[2 * j] + j * d;
            xo[j] = u[2 * j + 1] + j * d;
        }
        sample_ok(a, &sa, xa, f);
        sample_ok(even, &sb, xe, f);
        sample_ok(odd, &sb, xo, f);
    }
    gsl_rng_free(rng);
    result ra, re, ro;
    finish_ok(a, &sa, false, &ra);
    finish_ok(even, &sb, false, &re);
    finish_ok(odd, &sb, false, &ro);
    gr_observable_free(a);
    gr_observable_free(even);
    gr_observable_free(odd);
    const char *bins[] = {"lin", "log"};
    for (int hb = 1; hb <= 2; hb++) {
        for (int b = 0; b < 2; b++) {
            int na, nb, nc;
            const row *A = hist_rows(&ra, 2 * hb, bins[b], &na),
                      *E = hist_rows(&re, hb, bins[b], &nb), *O = hist_rows(&ro, hb, bins[b], &nc);
            ck_assert_int_eq(na, nb);
            double filled = 0.0;
            for (int i = 0; i < na; i++) {
                ck_assert_double_eq_tol(A[i].R, E[i].R, 1e-12 * A[i].R);
                ck_assert_msg(A[i].count == E[i].count + O[i].count,
                              "G_%d(N) vs G_%d(N/2) %s bin %d: %g != %g + %g", 2 * hb, hb, bins[b],
                              i, A[i].count, E[i].count, O[i].count);
                /* densities: G_2h(R;N) is the mean of the two decimated G_h(R;N/2) */
                ck_assert_double_eq_tol(A[i].density, 0.5 * (E[i].density + O[i].density),
                                        1e-9 * (A[i].density + 1.0));
                filled += A[i].count > 0;
            }
            ck_assert(filled > 10);
        }
        for (int m = 1; m <= 12; m++) {
            double ma = moment_row(&ra, 2 * hb, m)->moment;
            double mb = 0.5 * (moment_row(&re, hb, m)->moment + moment_row(&ro, hb, m)->moment);
            ck_assert_msg(fabs(ma / mb - 1.0) < 1e-9, "<R^%d>: %.12g vs %.12g", m, ma, mb);
        }
    }
    result_free(&ra);
    result_free(&re);
    result_free(&ro);
}
END_TEST

START_TEST(test_bad_params_refused)
{
    gr_scene s;
    void *st = NULL;
    gr_error err = {0};
    struct {
        const char *what;
        int dim, N, h_max, bins;
        double Lr;
    } bad[] = {
        {"2D", 2, 50, 4, 100, 1.0},
        {"one particle", 1, 1, 1, 100, 1.0},
        {"no free length", 1, 50, 4, 100, 0.0},
        {"negative free length", 1, 50, 4, 100, -0.01},
        {"h_max 0", 1, 50, 0, 100, 1.0},
        {"h_max = N", 1, 50, 50, 100, 1.0},
        {"h_max above the limit", 1, 1000, 257, 100, 1.0},
        {"bins 1", 1, 50, 4, 1, 1.0},
        {"bins 0", 1, 50, 4, 0, 1.0},
        {"bins too many", 1, 50, 4, 10001, 1.0},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        scene_1d(&s, bad[k].N, bad[k].Lr, 1e-3, bad[k].h_max, bad[k].bins, true);
        s.dim = bad[k].dim;
        if (bad[k].Lr == 0.0) {
            s.L =
                s.N * (2.0 * s.radius); /* L' = L - N d = 0 exactly: the particles fill the ring */
        }
        st = NULL;
        memset(&err, 0, sizeof err);
        int rc = gr_scene_observable(&gr_obs_gaps, &s, &st, &err);
        ck_assert_msg(rc == GR_EINVAL, "%s: accepted (rc %d)", bad[k].what, rc);
        ck_assert_msg(st == NULL, "%s: state returned on failure", bad[k].what);
        ck_assert_msg(strstr(err.message, "gaps") != NULL,
                      "%s: message '%s' does not name the observable", bad[k].what, err.message);
    }
    /* the limits themselves are accepted */
    scene_1d(&s, 50, 1.0, 1e-3, 49, 2, false);
    st = create_ok(&s);
    gr_observable_free(st);

    /* bad frames are refused and leave the accumulated data alone */
    scene_1d(&s, 20, 1.0, 1e-3, 3, 40, true);
    st = create_ok(&s);
    double x[20];
    for (int i = 0; i < 20; i++) {
        x[i] = i * s.L / 20;
    }
    gr_particles p = {.n = 20, .dim = 1, .L = s.L, .radius = s.radius, .x = x};
    ck_assert_int_eq(sample_rc(st, &p), GR_OK);
    gr_particles q = p;
    q.n = 19;
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* wrong N */
    q = p;
    q.dim = 2;
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* 2D frame */
    q = p;
    q.L = 2.0 * s.L;
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* another ring */
    double y[20];
    memcpy(y, x, sizeof y);
    y[4] = x[5];
    y[5] = x[4];
    q = p;
    q.x = y;
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* not in ring order */
    for (int i = 0; i < 20; i++) {
        y[i] = x[19 - i];
    }
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* ring order reversed */
    memcpy(y, x, sizeof y);
    y[7] = NAN;
    ck_assert_int_eq(sample_rc(st, &q), GR_EINVAL); /* non-finite position */
    ck_assert_int_eq(sample_rc(st, &p), GR_OK);
    result r;
    finish_ok(st, &s, false, &r);
    gr_observable_free(st);
    ck_assert_double_eq(jnum(r.gaps, "samples"), 2.0);
    int n;
    const row *rows = hist_rows(&r, 1, "lin", &n);
    double total = 0.0;
    for (int i = 0; i < n; i++) {
        total += rows[i].count;
    }
    ck_assert_double_eq(total, 40.0);
    result_free(&r);
}
END_TEST

START_TEST(test_outputs_and_plots)
{
    /* the summary member, the type's descriptor and (when gnuplot is installed) the plots */
    ck_assert_str_eq(gr_obs_gaps.name, "gaps");
    ck_assert_uint_eq(gr_obs_gaps.dims, 1u);
    ck_assert_int_eq(gr_obs_gaps.n_params, 3);
    const char *names[] = {"gaps_h_max", "gaps_bins", "gaps_log"};
    for (int i = 0; i < 3; i++) {
        ck_assert_str_eq(gr_obs_gaps.params[i].name, names[i]);
    }
    gr_scene s;
    scene_1d(&s, 64, 1.0, 1e-3, 5, 60, true);
    void *st = create_ok(&s);
    double x[64];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 8);
    for (int f = 0; f < 200; f++) {
        poisson_frame(rng, &s, x, 0);
        sample_ok(st, &s, x, f);
    }
    gsl_rng_free(rng);
    bool gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
    result r;
    finish_ok(st, &s, gnuplot, &r);
    gr_observable_free(st);
    ck_assert_str_eq(cJSON_GetObjectItem(r.gaps, "file")->valuestring, "gaps.csv");
    ck_assert_str_eq(cJSON_GetObjectItem(r.gaps, "moments_file")->valuestring, "gaps_moments.csv");
    ck_assert_double_eq(jnum(r.gaps, "N"), 64);
    ck_assert_double_eq_tol(jnum(r.gaps, "reduced_length"), 1.0, 1e-12);
    ck_assert_double_eq_tol(jnum(r.gaps, "mean_separation"), 1.0 / 64, 1e-14);
    ck_assert_int_eq(cJSON_GetArraySize(cJSON_GetObjectItem(r.gaps, "neighbours")), 5);
    ck_assert_int_eq(cJSON_GetArraySize(cJSON_GetObjectItem(r.gaps, "moments_stderr")), 12);
    ck_assert(cJSON_IsObject(cJSON_GetObjectItem(r.gaps, "fit_3_22")));
    /* binning: gaps_bins linear bins on [0, L'), as many logarithmic bins on [1e-8 L', L') */
    for (int h = 1; h <= 5; h++) {
        int n;
        const row *lin = hist_rows(&r, h, "lin", &n);
        ck_assert_int_eq(n, 60);
        ck_assert_double_eq(lin[0].lo, 0.0);
        ck_assert_double_eq_tol(lin[59].hi, 1.0, 1e-12);
        ck_assert_double_eq_tol(lin[1].lo, 1.0 / 60, 1e-10); /* CSV has 10 digits */
        const row *lg = hist_rows(&r, h, "log", &n);
        ck_assert_int_eq(n, 60);
        ck_assert_double_eq_tol(lg[0].lo, 1e-8, 1e-18);
        ck_assert_double_eq_tol(lg[59].hi, 1.0, 1e-12);
        ck_assert_double_eq_tol(lg[30].lo, 1e-4, 1e-13);
        ck_assert_double_eq_tol(lg[10].R, sqrt(lg[10].lo * lg[10].hi), 1e-9 * lg[10].R);
        ck_assert_double_eq_tol(lg[10].neg_ln_R, -log(lg[10].R), 1e-8);
    }
    const cJSON *nb = cJSON_GetArrayItem(cJSON_GetObjectItem(r.gaps, "neighbours"), 2);
    ck_assert_double_eq(jnum(nb, "h"), 3);
    ck_assert_double_eq_tol(jnum(nb, "mean"), 3.0 / 64, 1e-12);
    ck_assert_double_eq_tol(jnum(nb, "below_log_range"), 0.0, 1e-6);
    ck_assert_double_eq(jnum(nb, "beyond_reduced_length"), 0.0);
    if (gnuplot) {
        const char *png[] = {"gaps.png", "gaps_lnR.png", "gaps_moments.png"};
        for (int i = 0; i < 3; i++) {
            char path[256];
            snprintf(path, sizeof path, "%s/%s", r.dir, png[i]);
            ck_assert_msg(access(path, R_OK) == 0, "%s not drawn (plot notes: %s)", png[i],
                          cJSON_GetObjectItem(r.analysis, "plot_notes") ? "present" : "none");
        }
        ck_assert_ptr_null(cJSON_GetObjectItem(r.analysis, "plot_notes"));
    }
    result_free(&r);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_gaps");
    TCase *tc = tcase_create("gaps");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_even_spacing_single_spike);
    tcase_add_test(tc, test_poisson_exact_beta_chi2);
    tcase_add_test(tc, test_poisson_gamma_large_N);
    tcase_add_test(tc, test_mean_exact_each_frame);
    tcase_add_test(tc, test_mixture_rods_own_lengths);
    tcase_add_test(tc, test_overlap_convention);
    tcase_add_test(tc, test_wrapped_vs_unwrapped);
    tcase_add_test(tc, test_poisson_moments_gamma);
    tcase_add_test(tc, test_decimation_renormalisation);
    tcase_add_test(tc, test_bad_params_refused);
    tcase_add_test(tc, test_outputs_and_plots);
    suite_add_tcase(s, tc);
    return gr_test_run(s);
}
