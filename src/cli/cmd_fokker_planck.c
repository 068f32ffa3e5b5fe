/* granule fokker-planck: the randomly accelerated particle in a 1D absorbing interval of thesis
 * App. B. Evaluates the stationary solution (B.32) and Q(v, L) (B.33-B.34) by quadrature,
 * simulates the same walkers, compares the two (Figs. B.1-B.2) and writes CSV tables with
 * commented headers, summary.json and PNG plots into --out, each file atomically (io/files.h).
 * This file parses options and prints; the study is gr_fp_study_* (granule/fokker_planck_study.h). */
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "granule/fokker_planck_study.h"
#include "io/files.h"

typedef struct options {
    gr_fp_study_params p;
    const char *start;
    bool no_sim;
    cli_theory th;
} options;

#define FP_INT_MAX                                                                                 \
    1e6 /* far beyond every integer setting; gr_fp_settings_check has the finer ranges */

static const cli_opt fp_opts[] = {
    {"--length", CLI_DOUBLE, "L", offsetof(options, p.s.L), 0, 0, 0, "1",
     "interval length, m (L = 2 l of B.33)", NULL},
    {"--D", CLI_DOUBLE, "D", offsetof(options, p.s.D), 0, 0, 0, "1", "noise strength, N^2 s", NULL},
    {"--mass", CLI_DOUBLE, "M", offsetof(options, p.s.M), 0, 0, 0, "1",
     "particle mass, kg (the thesis figures use L = D = M = 1)", NULL},
    {"--walkers", CLI_INT64, "W", offsetof(options, p.s.walkers), 0, 1e15, 0, "200000",
     "walkers to release", NULL},
    {"--seed", CLI_UINT64, "S", offsetof(options, p.s.seed), 0, 0, 0, "1", "gsl_rng_mt19937 seed",
     NULL},
    {"--steps", CLI_DOUBLE, "N", offsetof(options, p.s.steps_per_T0), 0, 0, 0, "200",
     "time steps per T0 (the results do not move within their errors down to 40, see the docs)",
     NULL},
    {"--refine", CLI_INT, "K", offsetof(options, p.s.refine), 0, FP_INT_MAX, 0, "8",
     "levels of exact bridge bisection that look for exits inside a step near the walls (0: the "
     "Hermite test on whole "
     "steps only)",
     NULL},
    {"--start", CLI_CHOICE, "uniform|centre|center", offsetof(options, start), 0, 0, 0, "uniform",
     "release point: uniform in (0, L), the model B.32 solves, or the centre (the Single Particle "
     "Model, sec. 5.3.1; B.32 "
     "does not describe it and only exact identities are checked then)",
     NULL},
    {"--bins", CLI_INT, "N", offsetof(options, p.s.bins), 0, FP_INT_MAX, 0, "100",
     "velocity bins of Q over [-vmax, vmax] (even)", NULL},
    {"--exit-bins", CLI_INT, "N", offsetof(options, p.s.exit_bins), 0, FP_INT_MAX, 0, "50",
     "bins of the exit speed over [0, vmax]", NULL},
    {"--vmax", CLI_DOUBLE, "X", offsetof(options, p.s.vmax_V), 0, 0, 0, "5",
     "histogram range in units of V", NULL},
    {"--epsrel", CLI_DOUBLE, "E", offsetof(options, p.s.epsrel), 0, 0, 0, "1e-9",
     "relative tolerance of the quadratures", NULL},
    {"--inner-quadrature", CLI_FLAG, NULL, offsetof(options, p.s.inner_quadrature), 0, 0, 0, NULL,
     "evaluate B.34's inner integral by QAG instead of its closed form", NULL},
    {"--points", CLI_INT, "N", offsetof(options, p.points), 3, 100000, 0, "201",
     "points of the quadrature curves", NULL},
    {"--min-walks", CLI_DOUBLE, "N", offsetof(options, p.min_walks), 1, INFINITY, 0, "100",
     "Q bins enter the chi-square when N walks visited them", NULL},
    {"--no-sim", CLI_FLAG, NULL, offsetof(options, no_sim), 0, 0, 0, NULL, "quadrature only", NULL},
    CLI_THEORY_OPTS(options, th, "out/fokker-planck"),
};

const cli_command cli_cmd_fokker_planck = {
    .name = "fokker-planck",
    .usage = "granule fokker-planck [--length L] [--D D] [--mass M] [--walkers W] [--seed S]\n"
             "                             [--steps N] [--refine K] [--start uniform|centre] "
             "[--bins N]\n"
             "                             [--exit-bins N] [--vmax X] [--epsrel E] "
             "[--inner-quadrature]\n"
             "                             [--points N] [--min-walks N] [--no-sim] [--no-plots] "
             "[--format F] [--quiet]\n"
             "                             [--force] [--out DIR]",
    .about =
        "Thesis App. B: particles start at rest in [0, L], are driven by white noise of strength "
        "D\n"
        "(<eta eta'> = 2 D delta) and are absorbed at x = 0 and x = L. Evaluates the stationary\n"
        "Fokker-Planck solution P(x, v) (B.32) and the time-uniform velocity distribution\n"
        "Q(v, L) = int P dx (B.33-B.34) by adaptive quadrature (GSL QAGS/QAG, 2F1(-1/3,1;5/6;.)),\n"
        "simulates the same walkers (exact Gaussian steps, velocities sampled uniformly in time,\n"
        "exits found by exact bridge bisection near the walls) and compares them: Fig. B.2 (Q)\n"
        "and Fig. B.1 (the density of arrivals at x = L divided by v). The printed B.32/B.34\n"
        "prefactor is 2 3^(1/3) too large (it violates particle conservation); granule uses the\n"
        "corrected one and also tabulates the printed form. Scales: V = (D L / M^2)^(1/3),\n"
        "T0 = L / V.\n",
    .epilog = "Writes q_curve.csv, exit_curve.csv, q.csv, exit.csv, summary.json, q.png, "
              "q_log.png, exit.png.\n"
              "docs/theory-fokker-planck.md derives the solution and lists measured agreement.\n"
              "Exit status: 0 done, 2 bad input, 1 other failure.\n",
    CLI_OPTS(fp_opts),
};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int progress(double fraction, void *user)
{
    const double *t0 = user;
    double wall = now() - *t0;
    int eta = fraction > 0.0 ? (int)(wall * (1.0 - fraction) / fraction + 0.5) : 0;
    fprintf(stderr, "\rfokker-planck: simulating %3.0f%%  ETA %d:%02d:%02d   ", 100.0 * fraction,
            eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
    return 0;
}

static int exit_code(const gr_error *err)
{
    return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
}

/* -1 to go on, else the exit status */
static int parse(int argc, char **argv, options *o)
{
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_fokker_planck, argc, argv, o, &pos);
    if (parsed >= 0 || cli_theory_set_refused(&cli_cmd_fokker_planck, &o->th)) {
        cli_list_free(&o->th.sets);
        return parsed >= 0 ? parsed : EXIT_REFUSED;
    }
    o->p.s.start = !strcmp(o->start, "uniform") ? GR_FP_START_UNIFORM : GR_FP_START_CENTRE;
    o->p.sim = !o->no_sim;
    gr_error err = {0};
    if (gr_fp_settings_check(&o->p.s, &err)) {
        app_error("fokker-planck: %s", err.message);
        return EXIT_REFUSED;
    }
    return -1;
}

static void print_simulation(const options *o, const gr_fp_study *st)
{
    const gr_fp_sim_result *r = &st->r;
    printf("simulation (%s start): %lld walkers, %lld steps in %.2f s: <T_exit> = %.6g +- %.2g s, "
           "<v^2> = %.6g +- %.2g\n",
           st->uniform ? "uniform" : "centre", (long long)r->walkers, (long long)r->steps,
           r->wall_seconds, r->mean_exit_time, r->mean_exit_time_err, r->v_moment[2],
           r->v_moment_err[2]);
    printf("%s: Q chi2 = %.1f over %d bins (nu_eff %.1f, p = %.3g); exits chi2 = %.1f over %d bins "
           "(p = %.3g)\n",
           st->uniform ? "simulation vs quadrature" : "centre start vs uniform-start quadrature",
           st->cq.chi2, st->cq.dof, st->cq.dof_eff, st->cq.p_value, st->ce.chi2, st->ce.dof,
           st->ce.p_value);
    if (r->truncated > 0) {
        printf("warning: %lld walks were still inside after %g T0 and were cut off\n",
               (long long)r->truncated, o->p.s.max_T0);
    }
}

int cmd_fokker_planck(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    gr_fp_settings_default(&o.p.s);
    o.th.out = "out/fokker-planck";
    o.start = "uniform";
    o.p.points = 201;
    o.p.min_walks = 100.0;
    const int code = parse(argc, argv, &o);
    if (code >= 0) {
        return code;
    }
    gsl_set_error_handler_off();
    gr_error err = {0};
    if (gr_output_dir_prepare(o.th.out, GR_OUTPUT_RESULT, o.th.force, &err)) {
        app_error("fokker-planck: %s", err.message);
        return exit_code(&err);
    }
    gr_fp_study st;
    if (gr_fp_study_quadrature(o.th.out, &o.p, &st, &err)) {
        gr_fp_study_free(&st);
        app_error("fokker-planck: quadrature: %s", err.message);
        return EXIT_FAILED;
    }
    const gr_fp_settings *s = &o.p.s;
    printf("fokker-planck: L = %g m, D = %g N^2 s, M = %g kg: V = %.6g m/s, T0 = %.6g s\n", s->L,
           s->D, s->M, st.V, st.T0);
    printf("quadrature (uniform start): <T_exit> = %.6g s = %.6f T0, <v^2> = %.6g (m/s)^2, "
           "Q_pdf(0) = %.6g s/m (%.2f s)\n",
           st.T_quad, st.T_quad / st.T0, st.v2, st.Q0, st.quad_seconds);
    double t0 = now();
    const bool show = o.p.sim && !o.th.quiet && app_interactive();
    if (show) {
        o.p.progress = progress;
        o.p.user = &t0;
    }
    int rc = gr_fp_study_simulate(o.th.out, &o.p, &st, &err);
    if (show) {
        fprintf(stderr, "\r%60s\r", "");
        fflush(stderr);
    }
    if (rc) {
        gr_fp_study_free(&st);
        app_error("fokker-planck: simulation: %s", err.message);
        return exit_code(&err);
    }
    if (gr_fp_study_compare(o.th.out, &o.p, &st, &err)) {
        gr_fp_study_free(&st);
        app_error("fokker-planck: %s", err.message);
        return exit_code(&err);
    }
    if (st.have_sim) {
        print_simulation(&o, &st);
    }
    rc = gr_fp_study_summary(o.th.out, &o.p, &st, !o.th.no_plots, &err);
    gr_fp_study_free(&st);
    if (rc) {
        app_error("fokker-planck: %s", err.message);
        return EXIT_FAILED;
    }
    printf("wrote %s\n", o.th.out);
    return EXIT_OK;
}
