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

static void usage(FILE *f)
{
    fprintf(f,
            "usage: granule fokker-planck [--length L] [--D D] [--mass M] [--walkers W] [--seed S]\n"
            "                             [--steps N] [--refine K] [--start uniform|centre] [--bins N]\n"
            "                             [--exit-bins N] [--vmax X] [--epsrel E] [--inner-quadrature]\n"
            "                             [--points N] [--min-walks N] [--no-sim] [--no-plots] [--format F] [--quiet]\n"
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
            "  --no-plots        no plots\n"
            "  --format F        plots as png (default), svg or pdf\n"
            "  --quiet           no progress line\n"
            "  --force           overwrite the results of an earlier run in DIR\n"
            "  --out DIR         output folder (default out/fokker-planck)\n"
            "Writes q_curve.csv, exit_curve.csv, q.csv, exit.csv, summary.json, q.png, q_log.png, exit.png.\n"
            "docs/theory-fokker-planck.md derives the solution and lists measured agreement.\n"
            "Exit status: 0 done, 2 bad input, 1 other failure.\n");
}

typedef struct options {
    gr_fp_study_params p;
    const char *out;
    bool force, plots, quiet;
} options;

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
    fprintf(stderr, "\rfokker-planck: simulating %3.0f%%  ETA %d:%02d:%02d   ", 100.0 * fraction, eta / 3600,
            eta / 60 % 60, eta % 60);
    fflush(stderr);
    return 0;
}

static int exit_code(const gr_error *err) { return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED; }

static int parse(int argc, char **argv, options *o, int *done)
{
    *done = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        int k;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            *done = 1;
            return EXIT_OK;
        } else if (!strcmp(a, "--inner-quadrature")) {
            o->p.s.inner_quadrature = true;
        } else if (!strcmp(a, "--no-sim")) {
            o->p.sim = false;
        } else if ((k = cli_theory_option("fokker-planck", argc, argv, &i, &o->force, &o->quiet, &o->plots)) != 0) {
            if (k < 0) {
                return EXIT_REFUSED;
            }
        } else if (!strcmp(a, "--out") && v) {
            o->out = v;
            i++;
        } else if (!strcmp(a, "--start") && v) {
            if (!strcmp(v, "uniform")) {
                o->p.s.start = GR_FP_START_UNIFORM;
            } else if (!strcmp(v, "centre") || !strcmp(v, "center")) {
                o->p.s.start = GR_FP_START_CENTRE;
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
                o->p.s.L = x;
            } else if (!strcmp(a, "--D")) {
                o->p.s.D = x;
            } else if (!strcmp(a, "--mass")) {
                o->p.s.M = x;
            } else if (!strcmp(a, "--walkers")) {
                o->p.s.walkers = (int64_t)x;
            } else if (!strcmp(a, "--seed")) {
                o->p.s.seed = (uint64_t)x;
            } else if (!strcmp(a, "--steps")) {
                o->p.s.steps_per_T0 = x;
            } else if (!strcmp(a, "--refine")) {
                o->p.s.refine = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--bins")) {
                o->p.s.bins = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--exit-bins")) {
                o->p.s.exit_bins = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--vmax")) {
                o->p.s.vmax_V = x;
            } else if (!strcmp(a, "--epsrel")) {
                o->p.s.epsrel = x;
            } else if (!strcmp(a, "--points")) {
                o->p.points = x > 1e6 ? 1000001 : (int)x;
            } else if (!strcmp(a, "--min-walks")) {
                o->p.min_walks = x;
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
    if (gr_fp_settings_check(&o->p.s, &err)) {
        cli_error("fokker-planck: %s", err.message);
        return EXIT_REFUSED;
    }
    if (o->p.points < 3 || o->p.points > 100000) {
        cli_error("fokker-planck: --points must lie in [3, 100000], got %d", o->p.points);
        return EXIT_REFUSED;
    }
    if (!(o->p.min_walks >= 1.0)) {
        cli_error("fokker-planck: --min-walks must be >= 1, got %g", o->p.min_walks);
        return EXIT_REFUSED;
    }
    return EXIT_OK;
}

static void print_simulation(const options *o, const gr_fp_study *st)
{
    const gr_fp_sim_result *r = &st->r;
    printf("simulation (%s start): %lld walkers, %lld steps in %.2f s: <T_exit> = %.6g +- %.2g s, <v^2> = %.6g +- %.2g\n",
           st->uniform ? "uniform" : "centre", (long long)r->walkers, (long long)r->steps, r->wall_seconds,
           r->mean_exit_time, r->mean_exit_time_err, r->v_moment[2], r->v_moment_err[2]);
    printf("%s: Q chi2 = %.1f over %d bins (nu_eff %.1f, p = %.3g); exits chi2 = %.1f over %d bins (p = %.3g)\n",
           st->uniform ? "simulation vs quadrature" : "centre start vs uniform-start quadrature", st->cq.chi2, st->cq.dof,
           st->cq.dof_eff, st->cq.p_value, st->ce.chi2, st->ce.dof, st->ce.p_value);
    if (r->truncated > 0) {
        printf("warning: %lld walks were still inside after %g T0 and were cut off\n", (long long)r->truncated,
               o->p.s.max_T0);
    }
}

int cmd_fokker_planck(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    gr_fp_settings_default(&o.p.s);
    o.out = "out/fokker-planck";
    o.plots = true;
    o.p.sim = true;
    o.p.points = 201;
    o.p.min_walks = 100.0;
    int done, code = parse(argc, argv, &o, &done);
    if (code != EXIT_OK || done) {
        return code;
    }
    gsl_set_error_handler_off();
    gr_error err = {0};
    if (gr_output_dir_prepare(o.out, GR_OUTPUT_RESULT, o.force, &err)) {
        cli_error("fokker-planck: %s", err.message);
        return exit_code(&err);
    }
    gr_fp_study st;
    if (gr_fp_study_quadrature(o.out, &o.p, &st, &err)) {
        gr_fp_study_free(&st);
        cli_error("fokker-planck: quadrature: %s", err.message);
        return EXIT_FAILED;
    }
    const gr_fp_settings *s = &o.p.s;
    printf("fokker-planck: L = %g m, D = %g N^2 s, M = %g kg: V = %.6g m/s, T0 = %.6g s\n", s->L, s->D, s->M, st.V, st.T0);
    printf("quadrature (uniform start): <T_exit> = %.6g s = %.6f T0, <v^2> = %.6g (m/s)^2, Q_pdf(0) = %.6g s/m (%.2f s)\n",
           st.T_quad, st.T_quad / st.T0, st.v2, st.Q0, st.quad_seconds);
    double t0 = now();
    const bool show = o.p.sim && !o.quiet && cli_interactive();
    if (show) {
        o.p.progress = progress;
        o.p.user = &t0;
    }
    int rc = gr_fp_study_simulate(o.out, &o.p, &st, &err);
    if (show) {
        fprintf(stderr, "\r%60s\r", "");
        fflush(stderr);
    }
    if (rc) {
        gr_fp_study_free(&st);
        cli_error("fokker-planck: simulation: %s", err.message);
        return exit_code(&err);
    }
    if (gr_fp_study_compare(o.out, &o.p, &st, &err)) {
        gr_fp_study_free(&st);
        cli_error("fokker-planck: %s", err.message);
        return exit_code(&err);
    }
    if (st.have_sim) {
        print_simulation(&o, &st);
    }
    rc = gr_fp_study_summary(o.out, &o.p, &st, o.plots, &err);
    gr_fp_study_free(&st);
    if (rc) {
        cli_error("fokker-planck: %s", err.message);
        return EXIT_FAILED;
    }
    printf("wrote %s\n", o.out);
    return EXIT_OK;
}
