/* granule fokker-planck: the randomly accelerated particle in a 1D absorbing interval of thesis
 * App. B. Evaluates the stationary solution (B.32) and Q(v, L) (B.33-B.34) by quadrature,
 * simulates the same walkers, compares the two (Figs. B.1-B.2) and writes CSV tables with
 * commented headers, summary.json and PNG plots into --out, each file atomically (io/files.h). */
#include <cjson/cJSON.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "granule/analysis.h"
#include "granule/fokker_planck.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/plot.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: granule fokker-planck [--length L] [--D D] [--mass M] [--walkers W] [--seed S]\n"
            "                             [--steps N] [--refine K] [--start uniform|centre] [--bins N]\n"
            "                             [--exit-bins N] [--vmax X] [--epsrel E] [--inner-quadrature]\n"
            "                             [--points N] [--min-walks N] [--no-sim] [--no-plots] [--quiet]\n"
            "                             [--force] [--out DIR]\n\n"
            "Thesis App. B: particles start at rest in [0, L], are driven by white noise of strength D\n"
            "(<eta eta'> = 2 D delta) and are absorbed at x = 0 and x = L. Evaluates the stationary\n"
            "Fokker-Planck solution P(x, v) (B.32) and the time-uniform velocity distribution\n"
            "Q(v, L) = int P dx (B.33-B.34) by adaptive quadrature (GSL QAGS/QAG, 2F1(-1/3,1;5/6;.)),\n"
            "simulates the same walkers (exact Gaussian steps, velocities sampled uniformly in time,\n"
            "exits found by exact bridge bisection near the walls) and compares them: Fig. B.2 (Q)\n"
            "and Fig. B.1 (the density of arrivals at x = L divided by v). The printed B.32/B.34\n"
            "prefactor is 2 3^(1/3) too large (it violates particle conservation); granule uses the\n"
            "corrected one and also tabulates the printed form. Scales: V = (D L / M^2)^(1/3),\n"
            "T0 = L / V.\n"
            "  --length L        interval length, m (default 1; L = 2 l of B.33)\n"
            "  --D D             noise strength, N^2 s (default 1)\n"
            "  --mass M          particle mass, kg (default 1; the thesis figures use L = D = M = 1)\n"
            "  --walkers W       walkers to release (default 200000)\n"
            "  --seed S          gsl_rng_mt19937 seed (default 1)\n"
            "  --steps N         time steps per T0 (default 200; the results do not move within their\n"
            "                    errors down to 40, see the docs)\n"
            "  --refine K        levels of exact bridge bisection that look for exits inside a step\n"
            "                    near the walls (default 8; 0: the Hermite test on whole steps only)\n"
            "  --start uniform|centre  release point: uniform in (0, L), the model B.32 solves (default),\n"
            "                    or the centre (the Single Particle Model, sec. 5.3.1; B.32 does not\n"
            "                    describe it and only exact identities are checked then)\n"
            "  --bins N          velocity bins of Q over [-vmax, vmax] (even, default 100)\n"
            "  --exit-bins N     bins of the exit speed over [0, vmax] (default 50)\n"
            "  --vmax X          histogram range in units of V (default 5)\n"
            "  --epsrel E        relative tolerance of the quadratures (default 1e-9)\n"
            "  --inner-quadrature  evaluate B.34's inner integral by QAG instead of its closed form\n"
            "  --points N        points of the quadrature curves (default 201)\n"
            "  --min-walks N     Q bins enter the chi-square when N walks visited them (default 100)\n"
            "  --no-sim          quadrature only\n"
            "  --no-plots        skip the PNG plots\n"
            "  --quiet           no progress line\n"
            "  --force           overwrite the results of an earlier run in DIR\n"
            "  --out DIR         output folder (default out/fokker-planck)\n"
            "Writes q_curve.csv, exit_curve.csv, q.csv, exit.csv, summary.json, q.png, q_log.png, exit.png.\n"
            "docs/theory-fokker-planck.md derives the solution and lists measured agreement.\n"
            "Exit status: 0 done, 2 bad input, 1 other failure.\n");
}

typedef struct options {
    gr_fp_settings s;
    const char *out;
    bool force, plots, quiet, sim;
    int points;
    double min_walks;
} options;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct progress_state {
    double t0;
} progress_state;

static int progress(double fraction, void *user)
{
    progress_state *p = user;
    double wall = now() - p->t0;
    int eta = fraction > 0.0 ? (int)(wall * (1.0 - fraction) / fraction + 0.5) : 0;
    fprintf(stderr, "\rfokker-planck: simulating %3.0f%%  ETA %d:%02d:%02d   ", 100.0 * fraction, eta / 3600,
            eta / 60 % 60, eta % 60);
    fflush(stderr);
    return 0;
}

static int exit_code(const gr_error *err) { return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED; }

static void json_num(cJSON *o, const char *key, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, key, v);
    } else {
        cJSON_AddNullToObject(o, key);
    }
}

static void csv_head(gr_file *f, const char *what, const options *o, double V, double T0)
{
    const gr_fp_settings *s = &o->s;
    gr_file_note(f, "# granule %s (%s) fokker-planck: %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f, "# L = %.9g m, D = %.9g N^2 s, M = %.9g kg, V = (D L/M^2)^(1/3) = %.9g m/s, T0 = L/V = %.9g s, "
               "start %s, walkers %lld, steps per T0 %g, refine %d, seed %llu, epsrel %g\n",
            s->L, s->D, s->M, V, T0, s->start == GR_FP_START_CENTRE ? "centre" : "uniform", (long long)s->walkers,
            s->steps_per_T0, s->refine, (unsigned long long)s->seed, s->epsrel);
}

static void plot(const options *o, cJSON *plots, cJSON *notes, const char *png, const char *body)
{
    char note[300];
    if (gr_plot_script(o->out, png, body, note, sizeof note) == 0) {
        cJSON_AddItemToArray(plots, cJSON_CreateString(png));
    } else {
        cJSON_AddItemToArray(notes, cJSON_CreateString(note));
    }
}

static double z_score(double x, double err, double expect)
{
    return err > 0.0 ? (x - expect) / err : (double)NAN;
}

/* Stretched-exponential fit A exp(-(|v|/v0)^beta) to the tail |v| in [a, b] (the shared GSL fit of
 * granule/analysis.h): of the quadrature curve (1% weights, a shape measure), or of the simulated
 * histogram folded over v -> -v (errors from the walk covariance; bins visited by min_walks walks),
 * or, when `model` (bin means of the quadrature) is given, of the model on the same bins with the
 * same errors, so that the two fits can be compared. */
static int tail_fit(gr_fp_quad *q, const gr_fp_sim_result *r, const double *model, double vscale, double min_walks,
                    double a, double b, gr_fit *f, gr_error *err)
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
            double var = r->q_cov[(size_t)i * nb + i] + r->q_cov[(size_t)m * nb + m] + 2.0 * r->q_cov[(size_t)i * nb + m];
            x[n] = c;
            y[n] = model ? 0.5 * (model[i] + model[m]) : 0.5 * (gr_histogram_density(h, i) + gr_histogram_density(h, m));
            sg[n++] = 0.5 * sqrt(fmax(var, 0.0));
        }
        if (n < 4) {
            return GR_FAIL(err, GR_EINVAL, "tail fit: only %d well-populated bins in [%g, %g]", n, a, b);
        }
    }
    double p0[3] = {1.0 / vscale, vscale, 2.0}; /* (1, 1, 2) in units of V: converges for every range used */
    return gr_fit_stretched_exp(x, y, sg, n, p0, f, err);
}

static cJSON *fit_json(const gr_fit *f, double V, double a, double b)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "from_over_V", a / V);
    cJSON_AddNumberToObject(j, "to_over_V", b / V);
    json_num(j, "A", f->p[0]);
    json_num(j, "v0_over_V", f->p[1] / V);
    json_num(j, "v0_over_V_err", f->err[1] / V);
    json_num(j, "beta", f->p[2]);
    json_num(j, "beta_err", f->err[2]);
    json_num(j, "chi2_red", f->chi2_red);
    return j;
}

static int parse(int argc, char **argv, options *o, int *done)
{
    *done = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            *done = 1;
            return EXIT_OK;
        } else if (!strcmp(a, "--inner-quadrature")) {
            o->s.inner_quadrature = true;
        } else if (!strcmp(a, "--no-sim")) {
            o->sim = false;
        } else if (!strcmp(a, "--no-plots")) {
            o->plots = false;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = true;
        } else if (!strcmp(a, "--force")) {
            o->force = true;
        } else if (!strcmp(a, "--out") && v) {
            o->out = v;
            i++;
        } else if (!strcmp(a, "--start") && v) {
            if (!strcmp(v, "uniform")) {
                o->s.start = GR_FP_START_UNIFORM;
            } else if (!strcmp(v, "centre") || !strcmp(v, "center")) {
                o->s.start = GR_FP_START_CENTRE;
            } else {
                cli_error("fokker-planck: --start must be uniform or centre, got '%s'", v);
                return EXIT_REFUSED;
            }
            i++;
        } else if (v && a[0] == '-' && a[1] == '-') {
            if (!cli_number(a, v, &x)) {
                return EXIT_REFUSED;
            }
            i++;
            bool integral = !strcmp(a, "--walkers") || !strcmp(a, "--seed") || !strcmp(a, "--bins") ||
                            !strcmp(a, "--exit-bins") || !strcmp(a, "--points") || !strcmp(a, "--min-walks") ||
                            !strcmp(a, "--refine");
            if (integral && (!(x >= 0.0 && x <= 1e15) || x != floor(x))) {
                cli_error("fokker-planck: %s needs a whole number >= 0, got '%s'", a, v);
                return EXIT_REFUSED;
            }
            if (!strcmp(a, "--length")) {
                o->s.L = x;
            } else if (!strcmp(a, "--D")) {
                o->s.D = x;
            } else if (!strcmp(a, "--mass")) {
                o->s.M = x;
            } else if (!strcmp(a, "--walkers")) {
                o->s.walkers = (int64_t)x;
            } else if (!strcmp(a, "--seed")) {
                o->s.seed = (uint64_t)x;
            } else if (!strcmp(a, "--steps")) {
                o->s.steps_per_T0 = x;
            } else if (!strcmp(a, "--refine")) {
                o->s.refine = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--bins")) {
                o->s.bins = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--exit-bins")) {
                o->s.exit_bins = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--vmax")) {
                o->s.vmax_V = x;
            } else if (!strcmp(a, "--epsrel")) {
                o->s.epsrel = x;
            } else if (!strcmp(a, "--points")) {
                o->points = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--min-walks")) {
                o->min_walks = x;
            } else {
                cli_error("fokker-planck: unknown option %s (granule fokker-planck --help lists them)", a);
                return EXIT_REFUSED;
            }
        } else {
            cli_error("fokker-planck: unknown or incomplete option %s (granule fokker-planck --help lists them)", a);
            return EXIT_REFUSED;
        }
    }
    gr_error err = {0};
    if (gr_fp_settings_check(&o->s, &err)) {
        cli_error("fokker-planck: %s", err.message);
        return EXIT_REFUSED;
    }
    if (o->points < 3 || o->points > 100000) {
        cli_error("fokker-planck: --points must lie in [3, 100000], got %d", o->points);
        return EXIT_REFUSED;
    }
    if (!(o->min_walks >= 1.0)) {
        cli_error("fokker-planck: --min-walks must be >= 1, got %g", o->min_walks);
        return EXIT_REFUSED;
    }
    return EXIT_OK;
}

/* The quadrature curves: Q(v, L) over [-vmax, vmax] and P(L, v) over [0, vmax]. */
static int write_curves(const options *o, gr_fp_quad *q, double V, double T0, gr_error *err)
{
    const double vmax = o->s.vmax_V * V;
    gr_file f;
    int rc = gr_file_open(&f, o->out, "q_curve.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f, "Q(v, L) of (B.33-B.34) by quadrature. Q_pdf: the time-uniform velocity density, 1/(m/s); "
                  "Q_per_R: int_0^L P(x, v) dx per unit injection rate R (1/(m s)), s^2; Q_thesis_per_R: the same "
                  "with (B.34) as printed (prefactor R/Gamma(2/3), 2 3^(1/3) too large); abserr: GSL's estimate for Q_per_R",
             o, V, T0);
    fprintf(f.f, "v,v_over_V,Q_pdf,Q_per_R,Q_thesis_per_R,abserr\n");
    for (int k = 0; k < o->points && !rc; k++) {
        double v = -vmax + 2.0 * vmax * k / (o->points - 1), pdf, Q, Qt, ae;
        rc = gr_fp_Q_pdf(q, v, &pdf, NULL, err);
        if (!rc) rc = gr_fp_Q(q, v, &Q, &ae, err);
        if (!rc) rc = gr_fp_Q_thesis(q, v, &Qt, NULL, err);
        if (!rc) fprintf(f.f, "%.10g,%.10g,%.12g,%.12g,%.12g,%.3g\n", v, v / V, pdf, Q, Qt, ae);
    }
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    rc = gr_file_commit(&f, err);
    if (rc) {
        return rc;
    }
    rc = gr_file_open(&f, o->out, "exit_curve.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f, "arrivals at x = L (Fig. B.1) by quadrature of (B.32). P_L_over_RL: P(L, v) / (R L), the density of "
                  "arrival velocities per released particle divided by v, s^2/m^2; exit_pdf: v P(L, v)/(R L), the "
                  "arrival-velocity density at x = L (integrates to 1/2); P_L_thesis_over_RL: (B.32) as printed",
             o, V, T0);
    fprintf(f.f, "v,v_over_V,P_L_over_RL,exit_pdf,P_L_thesis_over_RL\n");
    int n = o->points / 2 + 1;
    for (int k = 0; k < n && !rc; k++) {
        double v = vmax * k / (n - 1), P, Pt;
        rc = gr_fp_exit_over_v(q, v, &P, NULL, err);
        if (!rc) rc = gr_fp_density_thesis(q, o->s.L, v, &Pt, NULL, err);
        if (!rc) fprintf(f.f, "%.10g,%.10g,%.12g,%.12g,%.12g\n", v, v / V, P, v * P, Pt / o->s.L);
    }
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    return gr_file_commit(&f, err);
}

/* The simulation tables: q.csv (Fig. B.2) and exit.csv (Fig. B.1). */
static int write_tables(const options *o, const gr_fp_sim_result *r, const double *qm, const double *em, double V,
                        double T0, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, o->out, "q.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f, "simulated Q(v, L): velocities sampled uniformly in time (every step survived). density: 1/(m/s); "
                  "error: from the walk-to-walk scatter (the walk is the independent unit); error_sqrtX: sqrt(X) / "
                  "(total width), too small here because the samples of one walk are correlated; quadrature: bin mean "
                  "of (B.34) normalised (uniform start); pull = (density - quadrature) / error",
             o, V, T0);
    const gr_histogram *h = &r->q;
    fprintf(f.f, "v_lo,v_hi,v,count,walks,density,error,error_sqrtX,quadrature,pull\n");
    for (int i = 0; i < h->nbins; i++) {
        double d = gr_histogram_density(h, i), e = r->q_err[i];
        fprintf(f.f, "%.10g,%.10g,%.10g,%.10g,%.0f,%.10g,%.6g,%.6g,%.10g,%.4g\n", gr_histogram_lower(h, i),
                gr_histogram_upper(h, i), gr_histogram_center(h, i), h->count[i], r->q_walks[i], d, e,
                gr_histogram_density_error(h, i), qm[i], e > 0.0 ? (d - qm[i]) / e : 0.0);
    }
    rc = gr_file_commit(&f, err);
    if (rc) {
        return rc;
    }
    rc = gr_file_open(&f, o->out, "exit.csv", err);
    if (rc) {
        return rc;
    }
    csv_head(&f, "simulated arrival speeds |v| at both ends, pooled (Property II: x = 0 mirrors x = L). density: per "
                  "released walker per m/s, integrates to the exit fraction; error: sqrt(X) (exits are independent); "
                  "P_L_over_RL = density / (2 v) at the bin centre, the quantity of Fig. B.1; quadrature: bin mean of 2 v P(L, v)/(R L)",
             o, V, T0);
    const gr_histogram *hr = &r->exit_right, *hl = &r->exit_left;
    const double W = hr->total;
    fprintf(f.f, "v_lo,v_hi,v,count_right,count_left,density,error,P_L_over_RL,P_L_over_RL_error,quadrature,pull\n");
    for (int i = 0; i < hr->nbins; i++) {
        double lo = gr_histogram_lower(hr, i), hi = gr_histogram_upper(hr, i), c = gr_histogram_center(hr, i);
        double X = hr->count[i] + hl->count[i], d = X / (W * (hi - lo)), e = sqrt(X) / (W * (hi - lo));
        fprintf(f.f, "%.10g,%.10g,%.10g,%.0f,%.0f,%.10g,%.6g,%.10g,%.6g,%.10g,%.4g\n", lo, hi, c, hr->count[i],
                hl->count[i], d, e, d / (2.0 * c), e / (2.0 * c), em[i], e > 0.0 ? (d - em[i]) / e : 0.0);
    }
    return gr_file_commit(&f, err);
}

int cmd_fokker_planck(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    gr_fp_settings_default(&o.s);
    o.out = "out/fokker-planck";
    o.plots = true;
    o.sim = true;
    o.points = 201;
    o.min_walks = 100.0;
    int done, code = parse(argc, argv, &o, &done);
    if (code != EXIT_OK || done) {
        return code;
    }
    gsl_set_error_handler_off();
    gr_error err = {0};
    if (gr_output_dir_prepare(o.out, o.force, &err)) {
        cli_error("fokker-planck: %s", err.message);
        return exit_code(&err);
    }
    const double V = gr_fp_velocity_scale(&o.s), T0 = gr_fp_time_scale(&o.s);
    const bool uniform = o.s.start == GR_FP_START_UNIFORM;

    /* quadrature */
    double t0 = now();
    gr_fp_quad *q = NULL;
    double T_quad = NAN, v2 = NAN, vabs = NAN, v4 = NAN, e1 = NAN, e2 = NAN, Q0 = NAN, PL_half = NAN;
    int rc = gr_fp_quad_alloc(&o.s, &q, &err);
    if (!rc) {
        T_quad = gr_fp_mean_exit_time(q);
        rc = gr_fp_moment(q, 2.0, &v2, &err);
    }
    if (!rc) rc = gr_fp_moment(q, 1.0, &vabs, &err);
    if (!rc) rc = gr_fp_moment(q, 4.0, &v4, &err);
    if (!rc) rc = gr_fp_exit_moment(q, 1.0, &e1, &err);
    if (!rc) rc = gr_fp_exit_moment(q, 2.0, &e2, &err);
    if (!rc) rc = gr_fp_Q_pdf(q, 0.0, &Q0, NULL, &err);
    if (!rc) rc = gr_fp_exit_over_v(q, 0.5 * V, &PL_half, NULL, &err);
    if (!rc) rc = write_curves(&o, q, V, T0, &err);
    const double quad_seconds = now() - t0;
    if (rc) {
        gr_fp_quad_free(q);
        cli_error("fokker-planck: quadrature: %s", err.message);
        return EXIT_FAILED;
    }

    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "completed");
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON *st = cJSON_AddObjectToObject(j, "settings");
    cJSON_AddNumberToObject(st, "L", o.s.L);
    cJSON_AddNumberToObject(st, "D", o.s.D);
    cJSON_AddNumberToObject(st, "M", o.s.M);
    cJSON_AddStringToObject(st, "start", uniform ? "uniform" : "centre");
    cJSON_AddNumberToObject(st, "walkers", o.sim ? (double)o.s.walkers : 0.0);
    cJSON_AddNumberToObject(st, "seed", (double)o.s.seed);
    cJSON_AddStringToObject(st, "rng", "gsl_rng_mt19937");
    cJSON_AddNumberToObject(st, "steps_per_T0", o.s.steps_per_T0);
    cJSON_AddNumberToObject(st, "refine", o.s.refine);
    cJSON_AddNumberToObject(st, "bins", o.s.bins);
    cJSON_AddNumberToObject(st, "exit_bins", o.s.exit_bins);
    cJSON_AddNumberToObject(st, "vmax_over_V", o.s.vmax_V);
    cJSON_AddNumberToObject(st, "epsrel", o.s.epsrel);
    cJSON_AddBoolToObject(st, "inner_quadrature", o.s.inner_quadrature);
    cJSON_AddNumberToObject(st, "min_walks", o.min_walks);
    cJSON *sc = cJSON_AddObjectToObject(j, "scales");
    cJSON_AddNumberToObject(sc, "Gamma", o.s.D / (o.s.M * o.s.M));
    cJSON_AddNumberToObject(sc, "V", V);
    cJSON_AddNumberToObject(sc, "T0", T0);
    cJSON *qj = cJSON_AddObjectToObject(j, "quadrature");
    cJSON_AddStringToObject(qj, "applies_to", "uniform start (B.1 with R delta(v), App. B)");
    json_num(qj, "mean_exit_time", T_quad);
    json_num(qj, "mean_exit_time_over_T0", T_quad / T0);
    json_num(qj, "v2_mean", v2);
    json_num(qj, "abs_v_mean", vabs);
    json_num(qj, "v4_mean", v4);
    json_num(qj, "Q_pdf_at_0", Q0);
    json_num(qj, "exit_speed_mean", e1);
    json_num(qj, "exit_speed2_mean", e2);
    json_num(qj, "P_L_over_RL_at_half_V", PL_half);
    cJSON_AddNumberToObject(qj, "thesis_prefactor_ratio", gr_fp_thesis_prefactor_ratio());
    cJSON_AddNumberToObject(qj, "kappa", gr_fp_kappa());
    cJSON_AddNumberToObject(qj, "seconds", quad_seconds);
    /* effective tail exponents of the quadrature (the asymptote is beta = 3, see the docs) */
    const double fit_ranges[3][2] = {{1.0, 3.0}, {1.5, 4.0}, {3.0, 6.0}};
    cJSON *tf = cJSON_AddArrayToObject(qj, "tail_fits");
    for (int k = 0; k < 3; k++) {
        gr_fit fit;
        gr_error ferr = {0};
        if (tail_fit(q, NULL, NULL, V, 0.0, fit_ranges[k][0] * V, fit_ranges[k][1] * V, &fit, &ferr) == 0) {
            cJSON_AddItemToArray(tf, fit_json(&fit, V, fit_ranges[k][0] * V, fit_ranges[k][1] * V));
        }
    }
    cJSON *plots = cJSON_AddArrayToObject(j, "plots");
    cJSON *notes = cJSON_CreateArray();

    printf("fokker-planck: L = %g m, D = %g N^2 s, M = %g kg: V = %.6g m/s, T0 = %.6g s\n", o.s.L, o.s.D, o.s.M, V, T0);
    printf("quadrature (uniform start): <T_exit> = %.6g s = %.6f T0, <v^2> = %.6g (m/s)^2, Q_pdf(0) = %.6g s/m (%.2f s)\n",
           T_quad, T_quad / T0, v2, Q0, quad_seconds);

    gr_fp_sim_result r;
    memset(&r, 0, sizeof r);
    if (!o.sim) { /* tables of an earlier run in this folder would no longer match summary.json */
        char stale[1200];
        const char *names[] = {"q.csv", "exit.csv"};
        for (int k = 0; k < 2; k++) {
            snprintf(stale, sizeof stale, "%s/%s", o.out, names[k]);
            remove(stale);
        }
    }
    double *qm = NULL, *em = NULL;
    if (o.sim) {
        progress_state ps = {.t0 = now()};
        bool show = !o.quiet && cli_interactive();
        rc = gr_fp_simulate(&o.s, show ? progress : NULL, &ps, &r, &err);
        if (show) {
            fprintf(stderr, "\r%60s\r", "");
            fflush(stderr);
        }
        if (rc) {
            cJSON_Delete(j);
            cJSON_Delete(notes);
            gr_fp_quad_free(q);
            cli_error("fokker-planck: simulation: %s", err.message);
            return exit_code(&err);
        }
        t0 = now();
        qm = malloc((size_t)r.q.nbins * sizeof(double));
        em = malloc((size_t)r.exit_right.nbins * sizeof(double));
        gr_fp_chi2 cq = {0}, ce = {0};
        double q0fit = NAN, q0fit_err = NAN;
        if (!qm || !em) {
            rc = GR_FAIL(&err, GR_ENOMEM, "out of memory");
        }
        if (!rc) rc = gr_fp_compare_Q(q, &r, o.min_walks, qm, &cq, &err);
        if (!rc) rc = gr_fp_compare_exit(q, &r, 20.0, em, &ce, &err);
        gr_error fit_err = {0};
        if (!rc && gr_fp_sim_Q0(&r, &q0fit, &q0fit_err, &fit_err)) {
            cJSON_AddItemToArray(notes, cJSON_CreateString(fit_err.message));
        }
        gr_fit sim_fit, quad_fit;
        bool have_fit = false;
        if (!rc) {
            /* the range the simulation resolves: |v| in [1.5 V, 3.5 V] */
            gr_error ferr = {0};
            have_fit = tail_fit(q, &r, NULL, V, o.min_walks, 1.5 * V, fmin(3.5, o.s.vmax_V) * V, &sim_fit, &ferr) == 0 &&
                       tail_fit(q, &r, qm, V, o.min_walks, 1.5 * V, fmin(3.5, o.s.vmax_V) * V, &quad_fit, &ferr) == 0;
            if (!have_fit) {
                cJSON_AddItemToArray(notes, cJSON_CreateString(ferr.message));
            }
        }
        const double compare_seconds = now() - t0;
        if (!rc) rc = write_tables(&o, &r, qm, em, V, T0, &err);
        if (rc) {
            free(qm);
            free(em);
            gr_fp_sim_result_free(&r);
            cJSON_Delete(j);
            cJSON_Delete(notes);
            gr_fp_quad_free(q);
            cli_error("fokker-planck: %s", err.message);
            return exit_code(&err);
        }
        const double Gamma = o.s.D / (o.s.M * o.s.M);
        cJSON *sj = cJSON_AddObjectToObject(j, "simulation");
        cJSON_AddNumberToObject(sj, "walkers", (double)r.walkers);
        cJSON_AddNumberToObject(sj, "right_exits", (double)r.right_exits);
        cJSON_AddNumberToObject(sj, "left_exits", (double)r.left_exits);
        cJSON_AddNumberToObject(sj, "truncated", (double)r.truncated);
        cJSON_AddNumberToObject(sj, "steps", (double)r.steps);
        cJSON_AddNumberToObject(sj, "tau", r.tau);
        json_num(sj, "mean_exit_time", r.mean_exit_time);
        json_num(sj, "mean_exit_time_err", r.mean_exit_time_err);
        json_num(sj, "v_mean", r.v_moment[1]);
        json_num(sj, "v_mean_err", r.v_moment_err[1]);
        json_num(sj, "v2_mean", r.v_moment[2]);
        json_num(sj, "v2_mean_err", r.v_moment_err[2]);
        json_num(sj, "v3_mean", r.v_moment[3]);
        json_num(sj, "v3_mean_err", r.v_moment_err[3]);
        json_num(sj, "v4_mean", r.v_moment[4]);
        json_num(sj, "v4_mean_err", r.v_moment_err[4]);
        json_num(sj, "abs_v_mean", r.abs_v_mean);
        json_num(sj, "abs_v_mean_err", r.abs_v_mean_err);
        json_num(sj, "exit_speed_mean", r.exit_speed_mean);
        json_num(sj, "exit_speed_err", r.exit_speed_err);
        json_num(sj, "exit_speed2_mean", r.exit_speed2_mean);
        json_num(sj, "exit_speed2_err", r.exit_speed2_err);
        json_num(sj, "Q_pdf_at_0_fit", q0fit);
        json_num(sj, "Q_pdf_at_0_fit_err", q0fit_err);
        cJSON_AddNumberToObject(sj, "seconds", r.wall_seconds);
        cJSON_AddNumberToObject(sj, "cpu_seconds", r.cpu_seconds);
        cJSON_AddNumberToObject(sj, "steps_per_cpu_second", r.cpu_seconds > 0.0 ? (double)r.steps / r.cpu_seconds : 0.0);
        /* exact identities of the process, any symmetric start (docs): Q(0) = <|v_exit|>/(2 Gamma <T>),
         * <v^2> = Gamma L Q(0) */
        cJSON *id = cJSON_AddObjectToObject(j, "identities");
        double q0_id = r.exit_speed_mean / (2.0 * Gamma * r.mean_exit_time);
        double q0_id_err = q0_id * hypot(r.exit_speed_err / r.exit_speed_mean, r.mean_exit_time_err / r.mean_exit_time);
        json_num(id, "Q_pdf_at_0_from_exits", q0_id);
        json_num(id, "Q_pdf_at_0_from_exits_err", q0_id_err);
        json_num(id, "Q_pdf_at_0_fit", q0fit);
        json_num(id, "z_Q0_fit_vs_exits", z_score(q0fit, hypot(q0fit_err, q0_id_err), q0_id));
        json_num(id, "v2_over_Gamma_L", r.v_moment[2] / (Gamma * o.s.L));
        json_num(id, "z_v2_over_Gamma_L_vs_Q0_fit",
                 z_score(r.v_moment[2] / (Gamma * o.s.L), hypot(r.v_moment_err[2] / (Gamma * o.s.L), q0fit_err), q0fit));
        cJSON *cj = cJSON_AddObjectToObject(j, "comparison");
        if (uniform) {
            cJSON_AddStringToObject(cj, "note", "simulation of the uniform start against the quadrature of the same model");
            json_num(cj, "z_mean_exit_time", z_score(r.mean_exit_time, r.mean_exit_time_err, T_quad));
            json_num(cj, "z_v2_mean", z_score(r.v_moment[2], r.v_moment_err[2], v2));
            json_num(cj, "z_abs_v_mean", z_score(r.abs_v_mean, r.abs_v_mean_err, vabs));
            json_num(cj, "z_v4_mean", z_score(r.v_moment[4], r.v_moment_err[4], v4));
            json_num(cj, "z_exit_speed_mean", z_score(r.exit_speed_mean, r.exit_speed_err, e1));
            json_num(cj, "z_exit_speed2_mean", z_score(r.exit_speed2_mean, r.exit_speed2_err, e2));
            json_num(cj, "z_Q_pdf_at_0", z_score(q0fit, q0fit_err, Q0));
        } else {
            cJSON_AddStringToObject(cj, "note", "centre start: (B.32)-(B.34) describe the uniform start, so the chi-squares below "
                                                "measure the difference between the two models, not an error");
        }
        json_num(cj, "z_v_mean_zero", z_score(r.v_moment[1], r.v_moment_err[1], 0.0));
        json_num(cj, "z_v3_mean_zero", z_score(r.v_moment[3], r.v_moment_err[3], 0.0));
        double nexit = (double)(r.right_exits + r.left_exits);
        json_num(cj, "z_right_left", nexit > 0 ? ((double)r.right_exits - 0.5 * nexit) / (0.5 * sqrt(nexit)) : (double)NAN);
        cJSON *cqj = cJSON_AddObjectToObject(cj, "Q");
        json_num(cqj, "chi2", cq.chi2);
        cJSON_AddNumberToObject(cqj, "bins", cq.dof);
        json_num(cqj, "dof_eff", cq.dof_eff);
        json_num(cqj, "p_value", cq.p_value);
        json_num(cqj, "max_abs_pull", cq.max_abs_z);
        json_num(cqj, "chi2_full_covariance", cq.chi2_full);
        json_num(cqj, "p_full_covariance", cq.p_full);
        cJSON *cej = cJSON_AddObjectToObject(cj, "exit");
        json_num(cej, "chi2", ce.chi2);
        cJSON_AddNumberToObject(cej, "bins", ce.dof);
        json_num(cej, "p_value", ce.p_value);
        json_num(cej, "max_abs_pull", ce.max_abs_z);
        if (have_fit) {
            cJSON_AddItemToObject(cj, "tail_fit_simulation", fit_json(&sim_fit, V, 1.5 * V, fmin(3.5, o.s.vmax_V) * V));
            cJSON_AddItemToObject(cj, "tail_fit_quadrature", fit_json(&quad_fit, V, 1.5 * V, fmin(3.5, o.s.vmax_V) * V));
        }
        cJSON_AddNumberToObject(cj, "seconds", compare_seconds);

        printf("simulation (%s start): %lld walkers, %lld steps in %.2f s: <T_exit> = %.6g +- %.2g s, <v^2> = %.6g +- %.2g\n",
               uniform ? "uniform" : "centre", (long long)r.walkers, (long long)r.steps, r.wall_seconds,
               r.mean_exit_time, r.mean_exit_time_err, r.v_moment[2], r.v_moment_err[2]);
        printf("%s: Q chi2 = %.1f over %d bins (nu_eff %.1f, p = %.3g); exits chi2 = %.1f over %d bins (p = %.3g)\n",
               uniform ? "simulation vs quadrature" : "centre start vs uniform-start quadrature", cq.chi2, cq.dof,
               cq.dof_eff, cq.p_value, ce.chi2, ce.dof, ce.p_value);
        if (r.truncated > 0) {
            printf("warning: %lld walks were still inside after %g T0 and were cut off\n", (long long)r.truncated, o.s.max_T0);
        }
    }

    if (o.plots) {
        char body[4096];
        const char *simlabel = uniform ? "simulation (uniform start)" : "simulation (centre start)";
        const char *qlabel = uniform ? "quadrature B.34" : "quadrature B.34 (uniform start, reference)";
        char simpart[512] = "";
        if (o.sim) {
            snprintf(simpart, sizeof simpart,
                     ", 'q.csv' skip 1 using 3:6:7 with yerrorbars pt 7 ps 0.6 lc rgb '#1f5fbf' title '%s (walk-scatter errors)'",
                     simlabel);
        }
        snprintf(body, sizeof body,
                 "set title 'Q(v, L): velocity sampled uniformly in time until the first exit (Fig. B.2)'\n"
                 "set xlabel 'v (m/s)'\nset ylabel 'Q(v, L) (s/m, normalised)'\nset key top right\n"
                 "plot 'q_curve.csv' skip 1 using 1:3 with lines lw 2 lc rgb '#cc3333' title '%s'%s\n",
                 qlabel, simpart);
        plot(&o, plots, notes, "q.png", body);
        snprintf(body, sizeof body,
                 "set title 'Q(v, L), logarithmic (tail: exp(-|v|^3 M^2/(9 D L)) times a power of v)'\n"
                 "set xlabel 'v (m/s)'\nset ylabel 'Q(v, L) (s/m, normalised)'\nset logscale y\nset key bottom center\n"
                 "plot 'q_curve.csv' skip 1 using 1:($3 > 0 ? $3 : 1/0) with lines lw 2 lc rgb '#cc3333' title '%s'%s\n",
                 qlabel, o.sim ? ", 'q.csv' skip 1 using 3:($6 > 0 ? $6 : 1/0):7 with yerrorbars pt 7 ps 0.5 lc rgb '#1f5fbf' title 'simulation'" : "");
        plot(&o, plots, notes, "q_log.png", body);
        snprintf(body, sizeof body,
                 "set title 'Arrivals at x = L: P(L, v) / (R L) (Fig. B.1)'\n"
                 "set xlabel 'v (m/s)'\nset ylabel 'P(L, v) / (R L)  (s^2/m^2)'\nset key top right\n"
                 "plot 'exit_curve.csv' skip 1 using 1:3 with lines lw 2 lc rgb '#cc3333' title '%s'%s\n",
                 uniform ? "quadrature B.32" : "quadrature B.32 (uniform start, reference)",
                 o.sim ? ", 'exit.csv' skip 1 using 3:8:9 with yerrorbars pt 7 ps 0.6 lc rgb '#1f5fbf' title 'simulation, both ends pooled (sqrt(X) errors)', "
                         "'' skip 1 using 3:($10 / (2 * $3)) with points pt 6 ps 1.1 lc rgb '#cc3333' title 'quadrature, bin means treated alike'"
                       : "");
        plot(&o, plots, notes, "exit.png", body);
    }
    if (cJSON_GetArraySize(notes) > 0) {
        cJSON_AddItemToObject(j, "notes", notes);
    } else {
        cJSON_Delete(notes);
    }
    char *text = cJSON_Print(j);
    gr_file f;
    rc = text ? gr_file_open(&f, o.out, "summary.json", &err) : GR_FAIL(&err, GR_ENOMEM, "out of memory");
    if (!rc) {
        fputs(text, f.f);
        fputc('\n', f.f);
        rc = gr_file_commit(&f, &err);
    }
    cJSON_free(text);
    cJSON_Delete(j);
    free(qm);
    free(em);
    if (o.sim) {
        gr_fp_sim_result_free(&r);
    }
    gr_fp_quad_free(q);
    if (rc) {
        cli_error("fokker-planck: %s", err.message);
        return EXIT_FAILED;
    }
    printf("wrote %s\n", o.out);
    return EXIT_OK;
}
