/* The computation of granule cascade (thesis sec. 6.2); see granule/cascade_study.h. */
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "granule/cascade_study.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* splitmix64: the placement's generator is seeded apart from the field's */
unsigned long gr_cascade_place_seed(unsigned long seed)
{
    uint64_t z = (uint64_t)seed + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (unsigned long)((z ^ (z >> 31)) & 0xffffffffull);
}

const gr_cascade_fit *gr_cascade_study_headline(const gr_cascade_study *st)
{
    return st->headline_unweighted ? &st->fit_unweighted : &st->fit;
}

/* The field relative to uniform, 4^l m, coarse-grained by block sums to level
 * l = min(levels, GR_CASCADE_FIELD_CSV_MAX_LEVELS) (out: 4^l values, row-major). */
static int coarse_field(const gr_cascade_field *fld, double *out)
{
    const int l = fld->levels < GR_CASCADE_FIELD_CSV_MAX_LEVELS ? fld->levels
                                                                : GR_CASCADE_FIELD_CSV_MAX_LEVELS;
    const int n = 1 << l, block = fld->side / n;
    const double scale = ldexp(1.0, 2 * l);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            double sum = 0.0;
            for (int b = 0; b < block; b++) {
                const double *row =
                    fld->m + (size_t)(j * block + b) * (size_t)fld->side + (size_t)(i * block);
                for (int a = 0; a < block; a++) {
                    sum += row[a];
                }
            }
            out[j * n + i] = scale * sum;
        }
    }
    return l;
}

/* Fig. 6.3, from the first field */
static int place(const gr_cascade_study_params *p, const gr_cascade_field *field,
                 gr_cascade_study *st, gr_error *err)
{
    const double t0 = now();
    const int n = p->placement.n;
    st->px = malloc(sizeof(double) * (size_t)n);
    st->py = malloc(sizeof(double) * (size_t)n);
    gsl_rng *prng = gsl_rng_alloc(gsl_rng_mt19937);
    if (!st->px || !st->py || !prng) {
        if (prng) {
            gsl_rng_free(prng);
        }
        return GR_FAIL(err, GR_ENOMEM, "cascade: out of memory for %d discs", n);
    }
    st->place_seed = gr_cascade_place_seed(p->s.seed);
    gsl_rng_set(prng, st->place_seed);
    int rc = gr_cascade_place(field, &p->placement, prng, st->px, st->py, &st->pres, err);
    gsl_rng_free(prng);
    st->place_seconds = now() - t0;
    return rc;
}

/* the D_f fits; a note instead when there is none */
static void fits(const gr_cascade_settings *s, gr_cascade_study *st)
{
    gr_cascade_fit_range(s, &st->q_min, &st->q_max);
    gr_error fit_err = {0};
    double S_max = 0.0;
    for (int b = 0; b < st->nbins; b++) {
        S_max = fmax(S_max, st->bins[b].S);
    }
    const double total = st->t_mean[s->levels];
    if (!(S_max > 1e-20 * total * total)) {
        snprintf(st->fit_note, sizeof st->fit_note,
                 "no D_f: S(k) vanishes for k != 0 (a uniform field)");
        return;
    }
    if (gr_cascade_fit_df(st->bins, st->nbins, st->q_min, st->q_max, false, &st->fit, &fit_err) ||
        gr_cascade_fit_df(st->bins, st->nbins, st->q_min, st->q_max, true, &st->fit_exp,
                          &fit_err)) {
        snprintf(st->fit_note, sizeof st->fit_note, "no D_f: %s", fit_err.message);
        return;
    }
    st->have_fit = true;
    st->have_unweighted = gr_cascade_fit_df_unweighted(st->bins, st->nbins, st->q_min, st->q_max,
                                                       &st->fit_unweighted, &fit_err) == 0;
    st->headline_unweighted = st->have_unweighted && st->fit.chi2_red > GR_CASCADE_CHI2_LARGE;
    if (st->headline_unweighted) {
        snprintf(st->headline_why, sizeof st->headline_why,
                 "the weighted fit has chi2/dof = %.3g > %g: the scatter of S(k) about the power "
                 "law is the lattice's "
                 "shell structure, not noise, so each k shell weighs the same and the error comes "
                 "from the scatter",
                 st->fit.chi2_red, GR_CASCADE_CHI2_LARGE);
    } else {
        snprintf(st->headline_why, sizeof st->headline_why,
                 "the weighted fit has chi2/dof = %.3g <= %g: S_err describes the scatter",
                 st->fit.chi2_red, GR_CASCADE_CHI2_LARGE);
    }
}

static int alloc_levels(gr_cascade_study *st, int nl, gr_error *err)
{
    st->t_mean = calloc((size_t)nl, sizeof(double));
    st->t_m2 = calloc((size_t)nl, sizeof(double));
    st->t_lo = calloc((size_t)nl, sizeof(double));
    st->t_hi = calloc((size_t)nl, sizeof(double));
    if (!st->t_mean || !st->t_m2 || !st->t_lo || !st->t_hi) {
        return GR_FAIL(err, GR_ENOMEM, "cascade: out of memory");
    }
    for (int l = 0; l < nl; l++) {
        st->t_lo[l] = (double)INFINITY;
        st->t_hi[l] = -(double)INFINITY;
    }
    return GR_OK;
}

/* Welford over configurations */
static void add_totals(gr_cascade_study *st, const double *totals, int nl, int c)
{
    for (int l = 0; l < nl; l++) {
        const double d = totals[l] - st->t_mean[l];
        st->t_mean[l] += d / (c + 1);
        st->t_m2[l] += d * (totals[l] - st->t_mean[l]);
        st->t_lo[l] = fmin(st->t_lo[l], totals[l]);
        st->t_hi[l] = fmax(st->t_hi[l], totals[l]);
    }
}

int gr_cascade_study_run(const gr_cascade_study_params *p, gr_cascade_study *st, gr_error *err)
{
    memset(st, 0, sizeof *st);
    const gr_cascade_settings *s = &p->s;
    int rc = gr_cascade_settings_check(s, err);
    if (!rc && p->place) {
        rc = gr_cascade_placement_check(&p->placement, s->L, err);
    }
    if (rc) {
        return rc;
    }
    st->levels = s->levels;
    const int nl = s->levels + 1;
    double *totals = calloc((size_t)nl, sizeof(double));
    st->coarse = malloc(sizeof(double) << (2 * (s->levels < GR_CASCADE_FIELD_CSV_MAX_LEVELS
                                                    ? s->levels
                                                    : GR_CASCADE_FIELD_CSV_MAX_LEVELS)));
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gr_cascade_field *field = NULL;
    gr_cascade_sk *sk = NULL;
    rc = alloc_levels(st, nl, err);
    if (!rc && (!totals || !st->coarse || !rng)) {
        rc = GR_FAIL(err, GR_ENOMEM, "cascade: out of memory");
    }
    if (!rc) {
        gsl_rng_set(rng, s->seed);
        rc = gr_cascade_field_alloc(s->levels, s->L, &field, err);
    }
    if (!rc) {
        rc = gr_cascade_sk_alloc(s, &sk, err);
    }
    const double start = now();
    double last_report = start;
    for (int c = 0; c < s->configurations && !rc; c++) {
        rc = gr_cascade_generate(s, rng, field, totals, err);
        if (!rc) {
            rc = gr_cascade_sk_add(sk, field, err);
        }
        if (rc) {
            break;
        }
        add_totals(st, totals, nl, c);
        if (c == 0) {
            st->field_level = coarse_field(field, st->coarse);
            if (p->place) { /* before the long part */
                rc = place(p, field, st, err);
            }
        }
        if (!rc && p->progress && (now() - last_report > 0.5 || c + 1 == s->configurations)) {
            last_report = now();
            p->progress(c + 1, s->configurations, now() - start - st->place_seconds, p->user);
        }
    }
    st->wall_seconds = now() - start;
    if (!rc) {
        st->nbins = gr_cascade_sk_nbins(sk);
        st->bins = malloc(sizeof *st->bins * (size_t)st->nbins);
        if (!st->bins) {
            rc = GR_FAIL(err, GR_ENOMEM, "cascade: out of memory");
        } else {
            gr_cascade_sk_bins(sk, st->bins);
            fits(s, st);
        }
    }
    free(totals);
    gr_cascade_field_free(field);
    gr_cascade_sk_free(sk);
    if (rng) {
        gsl_rng_free(rng);
    }
    if (rc) {
        gr_cascade_study_free(st);
    }
    return rc;
}

void gr_cascade_study_free(gr_cascade_study *st)
{
    free(st->t_mean);
    free(st->t_m2);
    free(st->t_lo);
    free(st->t_hi);
    free(st->coarse);
    free(st->bins);
    free(st->px);
    free(st->py);
    memset(st, 0, sizeof *st);
}
