/* pair on a mixture of [species] lists: the partial pair correlation functions (docs/mixtures.md).
 *
 * For species a and b (a <= b), with N_a grains of species a in a box of volume V,
 *
 *   g_ab(R) = P_ab(R) / (n_ab A(R)),  n_ab = N_a N_b / V (a != b),  N_a (N_a - 1) / (2 V) (a = b),
 *
 * P_ab the mean number of (unordered) a-b pairs per frame in the bin and A its shell area (volume
 * in 3D): the pooled g(R) of obs_pair.c (4.10) restricted to one kind of pair, normalised by that
 * kind's ideal-gas pair count, so g_ab = 1 for an ideal gas of any composition (Hansen and
 * McDonald, Theory of Simple Liquids, 3rd ed., sec. 2.5). The kinds' counts add up to the pooled
 * count in every bin, so sum_ab n_ab g_ab = N (N - 1) / (2 V) g: the sum rule the tests check.
 *
 * Contact values. The Enskog theory of a hard-sphere mixture needs g_ab at contact, R -> sigma_ab+
 * with sigma_ab = r_a + r_b (Jenkins and Mancini, J. Appl. Mech. 54, 27 (1987)); the pressure's
 * virial and the collision rates scale with it. It is estimated by a straight line, weighted by
 * the bins' errors, through g_ab of the bins lying wholly in [sigma_ab, (1 + CONTACT_WINDOW)
 * sigma_ab], evaluated at sigma_ab (soft grains overlap a little, so the bins below sigma_ab are
 * not the hard-sphere contact); with fewer than 3 such bins there is no value and the summary says
 * which bin width would give one. */
#include "analysis/obs_pair_species.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"

#define CONTACT_WINDOW 0.15 /* contact value: bins in [sigma, (1 + CONTACT_WINDOW) sigma] */
#define PEAK_MAX_SIGMA 1.5  /* a kind's first peak: the largest g_ab centred below 1.5 sigma_ab */
#define PLOT_KINDS_MAX 6    /* pair_species.png draws at most this many kinds */

int pair_species_init(void *state, pair_species *s, const gr_obs_setup *setup, int nbins,
                      double width, double volume, gr_error *err)
{
    memset(s, 0, sizeof *s);
    if (setup->n_species < 2 || setup->n_species > GR_MAX_SPECIES) {
        return GR_OK;
    }
    s->ns = setup->n_species;
    s->nbins = nbins;
    s->width = width;
    s->volume = volume;
    for (int a = 0; a < s->ns; a++) {
        for (int b = a; b < s->ns; b++) {
            s->kind_of[a * s->ns + b] = s->kind_of[b * s->ns + a] = s->nk++;
        }
    }
    size_t cells = (size_t)s->nk * (size_t)nbins;
    s->species = gr_obs_calloc(state, (size_t)setup->N, sizeof(int));
    s->frame_count = gr_obs_calloc(state, cells, sizeof(int64_t));
    s->total = gr_obs_calloc(state, cells, sizeof(double));
    s->g_blk = gr_obs_calloc(state, cells, sizeof(gr_blocking));
    if (!s->species || !s->frame_count || !s->total || !s->g_blk) {
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory for %d species pairs of %d bins", s->nk,
                       nbins);
    }
    return GR_OK;
}

int pair_species_begin(pair_species *s, const gr_particles *p, gr_error *err)
{
    if (!s->ns) {
        return GR_OK;
    }
    int rc = gr_obs_frame_species("pair", p, s->ns, p->n, s->species, err);
    if (rc) {
        return rc;
    }
    if (!p->radii) {
        return GR_FAIL(err, GR_EINVAL, "pair: the frames of a mixture carry no radii");
    }
    if (s->frames == 0) { /* the sizes, once: the species keep their grains and radii */
        memset(s->N_s, 0, sizeof s->N_s);
        for (int i = 0; i < p->n; i++) {
            s->N_s[s->species[i]]++;
            s->r_s[s->species[i]] = p->radii[i];
        }
    }
    memset(s->frame_count, 0, sizeof(int64_t) * (size_t)s->nk * (size_t)s->nbins);
    return GR_OK;
}

/* The ideal-gas pairs of kind (a, b) per unit volume. */
static double ideal_pairs(const pair_species *s, int a, int b)
{
    double na = s->N_s[a], nb = s->N_s[b];
    return (a == b ? 0.5 * na * (na - 1.0) : na * nb) / s->volume;
}

void pair_species_end(pair_species *s, const double *area)
{
    if (!s->ns) {
        return;
    }
    for (int a = 0; a < s->ns; a++) {
        for (int b = a; b < s->ns; b++) {
            const int k = pair_species_kind(s, a, b);
            const double norm = ideal_pairs(s, a, b);
            for (int q = 0; q < s->nbins; q++) {
                const size_t at = (size_t)k * (size_t)s->nbins + (size_t)q;
                const double cnt = (double)s->frame_count[at];
                s->total[at] += cnt;
                gr_blocking_add(&s->g_blk[at], norm > 0.0 ? cnt / (norm * area[q]) : 0.0);
            }
        }
    }
    s->frames++;
}

void pair_species_io(pair_species *s, gr_blob_io *io)
{
    if (!s->ns) {
        return;
    }
    const int64_t cells = (int64_t)s->nk * s->nbins;
    gr_blob_io_check(io, "pair species", s->ns);
    gr_obs_io_blockings(io, s->g_blk, (int)cells);
    gr_blob_io_f64s(io, s->total, cells);
    gr_blob_io_i64(io, &s->frames);
    for (int a = 0; a < s->ns; a++) {
        gr_blob_io_int(io, &s->N_s[a]);
        gr_blob_io_f64(io, &s->r_s[a]);
        if (gr_blob_io_loading(io) && (s->N_s[a] < 0 || !(s->r_s[a] >= 0.0))) {
            gr_blob_io_fail(io, "pair: species %d has %d grains of radius %g", a + 1, s->N_s[a],
                            s->r_s[a]);
        }
    }
}

/* ------------------------------------------------------------------------------------------
 * finish: g_ab with errors, each kind's contact value and first peak. */

typedef struct kind_result {
    int a, b;
    double sigma; /* contact distance r_a + r_b (m) */
    double contact, contact_error;
    int contact_bins; /* bins of the contact fit (< 3: no value) */
    int peak;         /* bin of the first peak */
} kind_result;

typedef struct species_result {
    const pair_species *s;
    double d;
    double *g, *ge; /* nk x nbins */
    kind_result kind[PAIR_KINDS_MAX];
} species_result;

static double bin_error(const pair_species *s, const gr_blocking *blk, double count, double norm,
                        double area)
{
    double e = gr_blocking_stderr(blk, NULL, NULL);
    return isfinite(e) ? e : sqrt(count) / (norm * area * (double)s->frames);
}

/* The contact value of one kind: a line through the bins in [sigma, (1 + CONTACT_WINDOW) sigma]. */
static void contact_fit(const pair_species *s, const double *g, const double *ge, kind_result *k)
{
    double x[64], y[64], e[64];
    int m = 0;
    const int first = (int)ceil(k->sigma / s->width - 1e-9);
    for (int q = first; q < s->nbins && m < 64; q++) {
        if ((q + 1) * s->width > (1.0 + CONTACT_WINDOW) * k->sigma * (1.0 + 1e-12)) {
            break;
        }
        if (ge[q] > 0.0 && isfinite(ge[q])) {
            x[m] = (q + 0.5) * s->width - k->sigma; /* the intercept is g at sigma */
            y[m] = g[q];
            e[m] = ge[q];
            m++;
        }
    }
    k->contact_bins = m;
    k->contact = k->contact_error = NAN;
    gr_fit fit;
    gr_error ferr = {0};
    if (m >= GR_FIT_MIN_POINTS && gr_fit_line(x, y, e, m, &fit, &ferr) == GR_OK) {
        k->contact = fit.p[0];
        k->contact_error = fit.err[0];
    }
}

static int compute(const pair_species *s, const double *area, species_result *r, gr_error *err)
{
    const size_t cells = (size_t)s->nk * (size_t)s->nbins;
    r->g = malloc(sizeof(double) * cells * 2);
    if (!r->g) {
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory for the species' g");
    }
    r->ge = r->g + cells;
    for (int a = 0; a < s->ns; a++) {
        for (int b = a; b < s->ns; b++) {
            const int k = pair_species_kind(s, a, b);
            const double norm = ideal_pairs(s, a, b);
            double *g = r->g + (size_t)k * s->nbins, *ge = r->ge + (size_t)k * s->nbins;
            for (int q = 0; q < s->nbins; q++) {
                const size_t at = (size_t)k * (size_t)s->nbins + (size_t)q;
                g[q] = gr_blocking_mean(&s->g_blk[at]);
                ge[q] = norm > 0.0 ? bin_error(s, &s->g_blk[at], s->total[at], norm, area[q])
                                   : (double)NAN;
            }
            kind_result *kr = &r->kind[k];
            kr->a = a;
            kr->b = b;
            kr->sigma = s->r_s[a] + s->r_s[b];
            contact_fit(s, g, ge, kr);
            int end = (int)ceil(PEAK_MAX_SIGMA * kr->sigma / s->width - 0.5);
            end = end < 1 ? s->nbins : (end < s->nbins ? end : s->nbins);
            kr->peak = 0;
            for (int q = 1; q < end; q++) {
                kr->peak = g[q] > g[kr->peak] ? q : kr->peak;
            }
        }
    }
    return GR_OK;
}

static void species_rows(FILE *f, const void *ctx)
{
    const species_result *r = ctx;
    const pair_species *s = r->s;
    for (int q = 0; q < s->nbins; q++) {
        const double R = (q + 0.5) * s->width;
        fprintf(f, "%.10g,%.10g", R, R / r->d);
        for (int k = 0; k < s->nk; k++) {
            const size_t at = (size_t)k * (size_t)s->nbins + (size_t)q;
            fprintf(f, ",%.10g,%.6g,%.0f", r->g[at], r->ge[at], s->total[at]);
        }
        fputc('\n', f);
    }
}

static void write_summary(const species_result *r, cJSON *j)
{
    const pair_species *s = r->s;
    cJSON *kinds = cJSON_AddArrayToObject(j, "pairs");
    cJSON *sig = cJSON_AddArrayToObject(j, "sigma");
    cJSON *cv = cJSON_AddArrayToObject(j, "contact_value");
    cJSON *ce = cJSON_AddArrayToObject(j, "contact_value_error");
    cJSON *cb = cJSON_AddArrayToObject(j, "contact_bins");
    cJSON *pr = cJSON_AddArrayToObject(j, "peak_R_over_sigma");
    cJSON *pg = cJSON_AddArrayToObject(j, "peak_g");
    bool coarse = false;
    for (int k = 0; k < s->nk; k++) {
        const kind_result *kr = &r->kind[k];
        char name[32];
        snprintf(name, sizeof name, "%d-%d", kr->a + 1, kr->b + 1);
        cJSON_AddItemToArray(kinds, cJSON_CreateString(name));
        cJSON_AddItemToArray(sig, cJSON_CreateNumber(kr->sigma));
        cJSON_AddItemToArray(cv, isfinite(kr->contact) ? cJSON_CreateNumber(kr->contact)
                                                       : cJSON_CreateNull());
        cJSON_AddItemToArray(ce, isfinite(kr->contact_error) ? cJSON_CreateNumber(kr->contact_error)
                                                             : cJSON_CreateNull());
        cJSON_AddItemToArray(cb, cJSON_CreateNumber(kr->contact_bins));
        const size_t at = (size_t)k * (size_t)s->nbins + (size_t)kr->peak;
        cJSON_AddItemToArray(pr, cJSON_CreateNumber((kr->peak + 0.5) * s->width / kr->sigma));
        cJSON_AddItemToArray(pg, cJSON_CreateNumber(r->g[at]));
        coarse |= kr->contact_bins < GR_FIT_MIN_POINTS;
    }
    cJSON_AddNumberToObject(j, "contact_window_over_sigma", CONTACT_WINDOW);
    if (coarse) {
        double smallest = INFINITY;
        for (int k = 0; k < s->nk; k++) {
            smallest = fmin(smallest, r->kind[k].sigma);
        }
        char note[300];
        snprintf(note, sizeof note,
                 "a contact value needs 3 bins within %.3g sigma_ab above contact: bins of at "
                 "most %.3g d (gr_rmax / gr_bins <= %.3g; now %.3g)",
                 CONTACT_WINDOW, CONTACT_WINDOW * smallest / 3.0 / r->d,
                 CONTACT_WINDOW * smallest / 3.0 / r->d, s->width / r->d);
        cJSON_AddStringToObject(j, "contact_note", note);
    }
    cJSON_AddStringToObject(
        j, "definition",
        "g_ab(R) = a-b pairs per frame / (n_ab shell area), n_ab = N_a N_b / V (a != b) or "
        "N_a (N_a - 1) / (2 V); sigma_ab = r_a + r_b (m); contact value g_ab(sigma_ab+): "
        "weighted straight line through the bins wholly in [sigma_ab, (1 + window) sigma_ab], "
        "evaluated at sigma_ab; first peak: largest g_ab centred below 1.5 sigma_ab");
}

static void write_plot(const species_result *r, const gr_output *out)
{
    const pair_species *s = r->s;
    char body[2400];
    int at = snprintf(body, sizeof body,
                      "set xlabel 'R / d'\nset ylabel 'g_{ab}(R)'\nset bars 0\n"
                      "set title \"Partial pair correlations, %lld frames\\n{/*0.75 d = the "
                      "mean collision diameter; contact at R = r_a + r_b}\"\n"
                      "set key top right\nplot ",
                      (long long)s->frames);
    const int kinds = s->nk < PLOT_KINDS_MAX ? s->nk : PLOT_KINDS_MAX;
    for (int k = 0; k < kinds && at < (int)sizeof body; k++) {
        at += snprintf(body + at, sizeof body - (size_t)at,
                       "'pair_species.csv' skip 1 using 2:%d with lines lt %d lw 2 title "
                       "'g_{%d%d}', ",
                       3 + 3 * k, k + 1, r->kind[k].a + 1, r->kind[k].b + 1);
    }
    if (at < (int)sizeof body) {
        snprintf(body + at, sizeof body - (size_t)at, "1 with lines dt 2 lt 0 title 'ideal gas'");
        gr_obs_plot(out, "pair_species.png", body);
    }
}

int pair_species_finish(const pair_species *s, const gr_output *out, cJSON *pair, double d,
                        const double *area, gr_error *err)
{
    if (!s->ns || s->frames == 0) {
        return GR_OK;
    }
    species_result r = {.s = s, .d = d};
    int rc = compute(s, area, &r, err);
    if (rc) {
        return rc;
    }
    char columns[PAIR_KINDS_MAX * 64 + 64];
    int at = snprintf(columns, sizeof columns, "R [m],R_over_d [1]");
    for (int k = 0; k < s->nk; k++) {
        const int a = r.kind[k].a + 1, b = r.kind[k].b + 1;
        at += snprintf(columns + at, sizeof columns - (size_t)at,
                       ",g_%d%d [1],g_%d%d_error [1],pairs_%d%d [1]", a, b, a, b, a, b);
    }
    gr_obs_table t = {.name = "pair_species.csv",
                      .what = "partial pair correlations g_ab(R) of species a <= b at the bin "
                              "centre R (the bins of pair.csv): a-b pairs per frame over the "
                              "ideal-gas count n_ab = N_a N_b / V (a != b) or N_a (N_a - 1) / "
                              "(2 V) per shell area (volume in 3D); pairs_ab = all frames' a-b "
                              "pairs in the bin (they add up to pair.csv's pairs); errors from "
                              "block averaging over frames (sqrt(count) below 16 frames)",
                      .columns = columns,
                      .rows = species_rows,
                      .ctx = &r};
    cJSON *j = cJSON_AddObjectToObject(pair, "species");
    cJSON_AddStringToObject(j, "file", "pair_species.csv");
    write_summary(&r, j);
    rc = gr_obs_table_write(out, &t, err);
    if (!rc && out->plots) {
        write_plot(&r, out);
    }
    free(r.g);
    return rc;
}
