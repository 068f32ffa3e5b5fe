/* The computation of granule fokker-planck (thesis App. B): quadrature, simulation, comparison
 * and the output files; see granule/fokker_planck_study.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "granule/fokker_planck_study.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

const double gr_fp_study_tail_ranges[3][2] = {{1.0, 3.0}, {1.5, 4.0}, {3.0, 6.0}};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void note(gr_fp_study *st, const char *text)
{
    if (st->n_notes < GR_FP_STUDY_NOTES) {
        snprintf(st->notes[st->n_notes++], sizeof st->notes[0], "%.767s", text);
    }
}

static void csv_head(gr_file *f, const char *what, const gr_fp_study_params *o, double V, double T0)
{
    const gr_fp_settings *s = &o->s;
    gr_file_note(f, "# granule %s (%s) fokker-planck: %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f,
                 "# L = %.9g m, D = %.9g N^2 s, M = %.9g kg, V = (D L/M^2)^(1/3) = %.9g m/s, T0 = "
                 "L/V = %.9g s, "
                 "start %s, walkers %lld, steps per T0 %g, refine %d, seed %llu, epsrel %g\n",
                 s->L, s->D, s->M, V, T0, s->start == GR_FP_START_CENTRE ? "centre" : "uniform",
                 (long long)s->walkers, s->steps_per_T0, s->refine, (unsigned long long)s->seed,
                 s->epsrel);
}

/* Stretched-exponential fit A exp(-(|v|/v0)^beta) to the tail |v| in [a, b] (the shared GSL fit of
 * granule/analysis.h): of the quadrature curve (1% weights, a shape measure), or of the simulated
 * histogram folded over v -> -v (errors from the walk covariance; bins visited by min_walks walks),
 * or, when `model` (bin means of the quadrature) is given, of the model on the same bins with the
 * same errors, so that the two fits can be compared. */
static int tail_fit(gr_fp_quad *q, const gr_fp_sim_result *r, const double *model, double vscale,
                    double min_walks, double a, double b, gr_fit *f, gr_error *err)
{
    double x[400], y[400], sg[400];
    int n = 0;
    if (!r) {
        for (int k = 0; k < 60; k++) {
            double v = a + (b - a) * k / 59.0, p;
            int rc = gr_fp_Q_pdf(q, v, &p, NULL, err);
            if (rc) {
                return rc;
            }
            x[n] = v;
            y[n] = p;
            sg[n++] = 0.01 * p;
        }
    } else {
        const gr_histogram *h = &r->q;
        const int nb = h->nbins;
        for (int i = nb / 2; i < nb && n < 400; i++) {
            int m = nb - 1 - i;
            double c = gr_histogram_center(h, i);
            if (c < a || c > b || r->q_walks[i] < min_walks || r->q_walks[m] < min_walks) {
                continue;
            }
            double var = r->q_cov[(size_t)i * nb + i] + r->q_cov[(size_t)m * nb + m] +
                         2.0 * r->q_cov[(size_t)i * nb + m];
            x[n] = c;
            y[n] = model ? 0.5 * (model[i] + model[m])
                         : 0.5 * (gr_histogram_density(h, i) + gr_histogram_density(h, m));
            sg[n++] = 0.5 * sqrt(fmax(var, 0.0));
        }
        if (n < 4) {
            return GR_FAIL(err, GR_EINVAL, "tail fit: only %d well-populated bins in [%g, %g]", n,
                           a, b);
        }
    }
    double p0[3] = {1.0 / vscale, vscale,
                    2.0}; /* (1, 1, 2) in units of V: converges for every range used */
    return gr_fit_stretched_exp(x, y, sg, n, p0, f, err);
}

/* The quadrature curves: Q(v, L) over [-vmax, vmax] and P(L, v) over [0, vmax]. */
static int write_curves(const char *dir, const gr_fp_study_params *o, gr_fp_quad *q, double V,
                        double T0, gr_error *err)
{
    const double vmax = o->s.vmax_V * V;
    gr_file f;
    int rc = gr_file_open(&f, dir, "q_curve.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(
        &f,
        "Q(v, L) of (B.33-B.34) by quadrature. Q_pdf: the time-uniform velocity density, 1/(m/s); "
        "Q_per_R: int_0^L P(x, v) dx per unit injection rate R (1/(m s)), s^2; Q_thesis_per_R: the "
        "same "
        "with (B.34) as printed (prefactor R/Gamma(2/3), 2 3^(1/3) too large); abserr: GSL's "
        "estimate for Q_per_R",
        o, V, T0);
    gr_file_header(
        &f, "v [m s-1],v_over_V [1],Q_pdf [s m-1],Q_per_R [s2],Q_thesis_per_R [s2],abserr [s2]");
    for (int k = 0; k < o->points && !rc; k++) {
        double v = -vmax + 2.0 * vmax * k / (o->points - 1), pdf, Q, Qt, ae;
        rc = gr_fp_Q_pdf(q, v, &pdf, NULL, err);
        if (!rc)
            rc = gr_fp_Q(q, v, &Q, &ae, err);
        if (!rc)
            rc = gr_fp_Q_thesis(q, v, &Qt, NULL, err);
        if (!rc)
            fprintf(f.f, "%.10g,%.10g,%.12g,%.12g,%.12g,%.3g\n", v, v / V, pdf, Q, Qt, ae);
    }
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    rc = gr_file_commit(&f, err);
    if (rc) {
        return rc;
    }
    rc = gr_file_open(&f, dir, "exit_curve.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f,
             "arrivals at x = L (Fig. B.1) by quadrature of (B.32). P_L_over_RL: P(L, v) / (R L), "
             "the density of "
             "arrival velocities per released particle divided by v, s^2/m^2; exit_pdf: v P(L, "
             "v)/(R L), the "
             "arrival-velocity density at x = L (integrates to 1/2); P_L_thesis_over_RL: (B.32) as "
             "printed",
             o, V, T0);
    gr_file_header(
        &f,
        "v [m s-1],v_over_V [1],P_L_over_RL [s2 m-2],exit_pdf [s m-1],P_L_thesis_over_RL [s2 m-2]");
    int n = o->points / 2 + 1;
    for (int k = 0; k < n && !rc; k++) {
        double v = vmax * k / (n - 1), P, Pt;
        rc = gr_fp_exit_over_v(q, v, &P, NULL, err);
        if (!rc)
            rc = gr_fp_density_thesis(q, o->s.L, v, &Pt, NULL, err);
        if (!rc)
            fprintf(f.f, "%.10g,%.10g,%.12g,%.12g,%.12g\n", v, v / V, P, v * P, Pt / o->s.L);
    }
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    return gr_file_commit(&f, err);
}

/* The simulation tables: q.csv (Fig. B.2) and exit.csv (Fig. B.1). */
static int write_tables(const char *dir, const gr_fp_study_params *o, const gr_fp_sim_result *r,
                        const double *qm, const double *em, double V, double T0, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "q.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f,
             "simulated Q(v, L): velocities sampled uniformly in time (every step survived). "
             "density: 1/(m/s); "
             "error: from the walk-to-walk scatter (the walk is the independent unit); "
             "error_sqrtX: sqrt(X) / "
             "(total width), too small here because the samples of one walk are correlated; "
             "quadrature: bin mean "
             "of (B.34) normalised (uniform start); pull = (density - quadrature) / error",
             o, V, T0);
    const gr_histogram *h = &r->q;
    gr_file_header(&f, "v_lo [m s-1],v_hi [m s-1],v [m s-1],count [1],walks [1],density [s "
                       "m-1],error [s m-1],error_sqrtX [s m-1],quadrature [s m-1],pull [1]");
    for (int i = 0; i < h->nbins; i++) {
        double d = gr_histogram_density(h, i), e = r->q_err[i];
        fprintf(f.f, "%.10g,%.10g,%.10g,%.10g,%.0f,%.10g,%.6g,%.6g,%.10g,%.4g\n",
                gr_histogram_lower(h, i), gr_histogram_upper(h, i), gr_histogram_center(h, i),
                h->count[i], r->q_walks[i], d, e, gr_histogram_density_error(h, i), qm[i],
                e > 0.0 ? (d - qm[i]) / e : 0.0);
    }
    rc = gr_file_commit(&f, err);
    if (rc) {
        return rc;
    }
    rc = gr_file_open(&f, dir, "exit.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f,
             "simulated arrival speeds |v| at both ends, pooled (Property II: x = 0 mirrors x = "
             "L). density: per "
             "released walker per m/s, integrates to the exit fraction; error: sqrt(X) (exits are "
             "independent); "
             "P_L_over_RL = density / (2 v) at the bin centre, the quantity of Fig. B.1; "
             "quadrature: bin mean of 2 v P(L, v)/(R L)",
             o, V, T0);
    const gr_histogram *hr = &r->exit_right, *hl = &r->exit_left;
    const double W = hr->total;
    gr_file_header(
        &f,
        "v_lo [m s-1],v_hi [m s-1],v [m s-1],count_right [1],count_left [1],density [s m-1],error "
        "[s m-1],P_L_over_RL [s2 m-2],P_L_over_RL_error [s2 m-2],quadrature [s2 m-2],pull [1]");
    for (int i = 0; i < hr->nbins; i++) {
        double lo = gr_histogram_lower(hr, i), hi = gr_histogram_upper(hr, i),
               c = gr_histogram_center(hr, i);
        double X = hr->count[i] + hl->count[i], d = X / (W * (hi - lo)),
               e = sqrt(X) / (W * (hi - lo));
        fprintf(f.f, "%.10g,%.10g,%.10g,%.0f,%.0f,%.10g,%.6g,%.10g,%.6g,%.10g,%.4g\n", lo, hi, c,
                hr->count[i], hl->count[i], d, e, d / (2.0 * c), e / (2.0 * c), em[i],
                e > 0.0 ? (d - em[i]) / e : 0.0);
    }
    return gr_file_commit(&f, err);
}

int gr_fp_study_quadrature(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                           gr_error *err)
{
    memset(st, 0, sizeof *st);
    st->V = gr_fp_velocity_scale(&p->s);
    st->T0 = gr_fp_time_scale(&p->s);
    st->uniform = p->s.start == GR_FP_START_UNIFORM;
    st->T_quad = st->v2 = st->vabs = st->v4 = st->e1 = st->e2 = st->Q0 = st->PL_half = (double)NAN;
    st->q0fit = st->q0fit_err = (double)NAN;
    const double t0 = now();
    int rc = gr_fp_quad_alloc(&p->s, &st->q, err);
    if (!rc) {
        st->T_quad = gr_fp_mean_exit_time(st->q);
        rc = gr_fp_moment(st->q, 2.0, &st->v2, err);
    }
    if (!rc)
        rc = gr_fp_moment(st->q, 1.0, &st->vabs, err);
    if (!rc)
        rc = gr_fp_moment(st->q, 4.0, &st->v4, err);
    if (!rc)
        rc = gr_fp_exit_moment(st->q, 1.0, &st->e1, err);
    if (!rc)
        rc = gr_fp_exit_moment(st->q, 2.0, &st->e2, err);
    if (!rc)
        rc = gr_fp_Q_pdf(st->q, 0.0, &st->Q0, NULL, err);
    if (!rc)
        rc = gr_fp_exit_over_v(st->q, 0.5 * st->V, &st->PL_half, NULL, err);
    if (!rc)
        rc = write_curves(dir, p, st->q, st->V, st->T0, err);
    st->quad_seconds = now() - t0;
    /* effective tail exponents of the quadrature (the asymptote is beta = 3, see the docs) */
    for (int k = 0; k < 3 && !rc; k++) {
        gr_error ferr = {0};
        const double a = gr_fp_study_tail_ranges[k][0] * st->V,
                     b = gr_fp_study_tail_ranges[k][1] * st->V;
        st->quad_tail_ok[k] =
            tail_fit(st->q, NULL, NULL, st->V, 0.0, a, b, &st->quad_tail[k], &ferr) == 0;
    }
    return rc;
}

int gr_fp_study_simulate(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                         gr_error *err)
{
    if (!p->sim) { /* tables of an earlier run in this folder would no longer match summary.json */
        char stale[1200];
        const char *names[] = {"q.csv", "exit.csv"};
        for (int k = 0; k < 2; k++) {
            snprintf(stale, sizeof stale, "%s/%s", dir, names[k]);
            remove(stale);
        }
        return GR_OK;
    }
    int rc = gr_fp_simulate(&p->s, p->progress, p->user, &st->r, err);
    st->have_sim = rc == 0;
    return rc;
}

int gr_fp_study_compare(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                        gr_error *err)
{
    if (!st->have_sim) {
        return GR_OK;
    }
    const double t0 = now(), V = st->V;
    st->qm = malloc((size_t)st->r.q.nbins * sizeof(double));
    st->em = malloc((size_t)st->r.exit_right.nbins * sizeof(double));
    int rc = !st->qm || !st->em ? GR_FAIL(err, GR_ENOMEM, "out of memory") : GR_OK;
    if (!rc)
        rc = gr_fp_compare_Q(st->q, &st->r, p->min_walks, st->qm, &st->cq, err);
    if (!rc)
        rc = gr_fp_compare_exit(st->q, &st->r, 20.0, st->em, &st->ce, err);
    gr_error fit_err = {0};
    if (!rc && gr_fp_sim_Q0(&st->r, &st->q0fit, &st->q0fit_err, &fit_err)) {
        note(st, fit_err.message);
    }
    if (!rc) {
        /* the range the simulation resolves: |v| in [1.5 V, 3.5 V] */
        gr_error ferr = {0};
        const double a = 1.5 * V, b = fmin(3.5, p->s.vmax_V) * V;
        st->have_tail_fit =
            tail_fit(st->q, &st->r, NULL, V, p->min_walks, a, b, &st->sim_tail, &ferr) == 0 &&
            tail_fit(st->q, &st->r, st->qm, V, p->min_walks, a, b, &st->quad_tail_on_bins, &ferr) ==
                0;
        if (!st->have_tail_fit) {
            note(st, ferr.message);
        }
    }
    st->compare_seconds = now() - t0;
    if (!rc)
        rc = write_tables(dir, p, &st->r, st->qm, st->em, V, st->T0, err);
    return rc;
}

void gr_fp_study_free(gr_fp_study *st)
{
    free(st->qm);
    free(st->em);
    if (st->have_sim) {
        gr_fp_sim_result_free(&st->r);
    }
    gr_fp_quad_free(st->q);
    memset(st, 0, sizeof *st);
}
