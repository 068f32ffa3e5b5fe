/* granule bisect: the multiplicative bisection process of thesis sec. 3.4 (P_n(x) against 3.36,
 * moments against 3.37-3.38, zeta_m as Table 3.1, the collapse 3.39-3.40 over RFM G_1 tables). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "granule/bisect.h"
#include "io/files.h"

#define MAX_G1 16

typedef struct bisect_args {
    gr_bisect_settings s;
    const char *u0;
    cli_list g1;
    cli_theory th;
} bisect_args;

static const cli_opt bisect_opts[] = {
    {"--levels", CLI_INT, "N", offsetof(bisect_args, s.levels), 1, GR_BISECT_MAX_LEVELS, 0, "9",
     "levels n: 2^n partitions (9: 512, Figs. 3.15-3.16)", NULL},
    {"--repetitions", CLI_INT64, "R", offsetof(bisect_args, s.repetitions), 2, 1e15, 0, "10000",
     "realisations", NULL},
    {"--u0", CLI_STRING, "SPEC", offsetof(bisect_args, u0), 0, 0, 0, "uniform",
     "uniform; power:A for U_0 = (1-A)/2 (a^-A + (1-a)^-A), " CLI_STR(
         GR_BISECT_POWER_A_MIN) " <= A <= " CLI_STR(GR_BISECT_POWER_A_MAX) "; or a CSV file of a,U "
                                                                           "points (piecewise "
                                                                           "linear, normalised)",
     NULL},
    {"--seed", CLI_UINT64, "S", offsetof(bisect_args, s.seed), 0, 0, 0, "1", "gsl_rng_mt19937 seed",
     NULL},
    {"--g1", CLI_LIST, "FILE", offsetof(bisect_args, g1), 0, 0, 0, NULL,
     "a 1D RFM nearest-neighbour distribution G_1(R;N) to collapse with the process (repeatable, "
     "up to " CLI_STR(
         MAX_G1) "): CSV R,G[,G_err] with a '# N = <particles>' comment (docs/theory-bisect.md)",
     NULL},
    {"--moments", CLI_INT, "M", offsetof(bisect_args, s.moments_max), 1, GR_BISECT_MAX_MOMENTS, 0,
     "6", "moments m = 1..M", NULL},
    {"--bins-per-decade", CLI_INT, "B", offsetof(bisect_args, s.bins_per_decade), 1, 1000, 0, "10",
     "bins of P_n(x)", NULL},
    {"--fit-from", CLI_INT, "K", offsetof(bisect_args, s.fit_level_min), 1, GR_BISECT_MAX_LEVELS, 0,
     "1", "fit zeta_m over levels K..N", NULL},
    {"--jackknife", CLI_INT, "G", offsetof(bisect_args, s.jackknife_groups), 2, 1024, 0, "32",
     "groups of realisations for the jackknife errors", NULL},
    {"--anchor", CLI_DOUBLE, "R0", offsetof(bisect_args, s.anchor), 0, 0, 0, "0.7",
     "R_0 of A_N (3.40)", NULL},
    CLI_THEORY_OPTS(bisect_args, th, "out/bisect"),
};

const cli_command cli_cmd_bisect = {
    .name = "bisect",
    .usage =
        "granule bisect [--out DIR] [--levels N] [--repetitions R] [--u0 uniform|power:A|FILE]\n"
        "                      [--seed S] [--g1 FILE ...] [--moments M] [--bins-per-decade B]\n"
        "                      [--fit-from K] [--jackknife G] [--anchor R0] [--no-plots] [--format "
        "F] [--force] [--quiet]",
    .about =
        "Bisects the unit interval N times (2^N partitions), every partition at a fraction a drawn "
        "from\n"
        "U_0(a) (thesis eqs. 3.26-3.28), R times, and writes into DIR:\n"
        "  pn.csv        P_n(x) at level N (log bins, sqrt(X) errors) beside (-ln x)^(N-1)/(N-1)! "
        "(3.36)\n"
        "  moments.csv   <x^m> at every level k against mu_m^k ((1+m)^-k for the uniform U_0, "
        "3.37)\n"
        "  zeta.csv      zeta_m of <x^m> = A (2^k)^-zeta_m with fit and jackknife errors, beside\n"
        "                ln(1+m)/ln 2 (3.38) and the RFM's Table 3.1\n"
        "  collapse.csv  A_N G^(1/(n-1)) against -ln R (3.39-3.40) for the process and each --g1 "
        "table\n"
        "  summary.json, and pn.png, moments.png, moments_N.png, collapse.png (gnuplot)\n",
    .epilog = "Exit status: 0 done, 2 bad input (options, U_0 or G_1 file, DIR holds a run), 1 "
              "other failure.\n",
    CLI_OPTS(bisect_opts),
};

typedef struct progress_state {
    double start, last;
} progress_state;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress(int64_t done, int64_t total, void *user)
{
    progress_state *p = user;
    double t = wall();
    if (t - p->last < 0.25 && done < total) {
        return;
    }
    p->last = t;
    int eta = (int)((t - p->start) * (double)(total - done) / (double)done + 0.5);
    fprintf(stderr, "\rbisect: %lld / %lld realisations  %3.0f%%  ETA %d:%02d:%02d   ",
            (long long)done, (long long)total, 100.0 * (double)done / (double)total, eta / 3600,
            eta / 60 % 60, eta % 60);
    fflush(stderr);
}

int cmd_bisect(int argc, char **argv)
{
    bisect_args args = {.u0 = "uniform", .th.out = "out/bisect"};
    gr_bisect_settings_default(&args.s);
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_bisect, argc, argv, &args, &pos);
    if (parsed >= 0 || cli_theory_set_refused(&cli_cmd_bisect, &args.th)) {
        cli_list_free(&args.g1);
        cli_list_free(&args.th.sets);
        return parsed >= 0 ? parsed : EXIT_REFUSED;
    }
    if (args.g1.n > MAX_G1) {
        app_error("bisect: at most %d --g1 tables", MAX_G1);
        cli_list_free(&args.g1);
        return EXIT_REFUSED;
    }
    gr_bisect_settings s = args.s;
    const char *out = args.th.out, *u0_spec = args.u0, *g1_paths[MAX_G1];
    const int n_g1 = args.g1.n;
    for (int k = 0; k < n_g1; k++) {
        g1_paths[k] = args.g1.items[k];
    }
    cli_list_free(&args.g1);
    const bool force = args.th.force, quiet = args.th.quiet, plots = !args.th.no_plots;
    if (strlen(out) > 1000) {
        app_error("bisect: --out %.40s...: path too long", out);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    if (gr_bisect_settings_check(&s, &err)) {
        app_error("bisect: %s", err.message);
        return EXIT_REFUSED;
    }
    /* inputs first: a bad U_0 or G_1 table is refused before any output or work */
    gr_bisect_u0 u0;
    if (gr_bisect_u0_parse(&u0, u0_spec, &err)) {
        app_error("bisect: --u0: %s", err.message);
        return EXIT_REFUSED;
    }
    gr_bisect_g1 g1[MAX_G1];
    int loaded = 0, rc = EXIT_OK;
    for (; loaded < n_g1; loaded++) {
        if (gr_bisect_g1_load(&g1[loaded], g1_paths[loaded], &err) ||
            gr_bisect_g1_at(&g1[loaded], s.anchor, &(double){0}, &err)) {
            if (g1[loaded].R) {
                loaded++;
            }
            app_error("bisect: --g1: %s", err.message);
            rc = EXIT_REFUSED;
            break;
        }
    }
    if (!rc && u0.kind == GR_BISECT_U0_TABLE && u0.asymmetry > 1e-6) {
        fprintf(stderr,
                "granule: warning: U_0 table %s is not symmetric (max |U(a) - U(1-a)| = %.3g of "
                "its peak); "
                "3.30 asks U_0(a) = U_0(1-a), and the statistics see only (U(a) + U(1-a))/2\n",
                u0.name, u0.asymmetry);
    }
    if (!rc && gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force, &err)) {
        app_error("bisect: %s", err.message);
        rc = err.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    gr_bisect_result res;
    progress_state ps = {wall(), 0.0};
    if (!rc) {
        if (!quiet && app_interactive()) {
            s.progress = progress;
            s.user = &ps;
        }
        int st = gr_bisect_run(&s, &u0, &res, &err);
        if (s.progress) {
            fputc('\n', stderr);
        }
        if (st) {
            app_error("bisect: %s", err.message);
            rc = st == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
        }
    }
    if (!rc) {
        gr_bisect_output o = {.g1 = g1, .n_g1 = n_g1, .plots = plots};
        if (gr_bisect_write(out, &s, &u0, &res, &o, &err)) {
            app_error("bisect: %s", err.message);
            rc = err.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
        } else {
            const gr_bisect_zeta *z2 = s.moments_max >= 2 ? &res.zeta[1] : &res.zeta[0];
            char zeta[160] = "no zeta fit with one level";
            if (isfinite(z2->zeta)) {
                snprintf(zeta, sizeof zeta, "zeta_%d = %.4f +- %.4f (predicted %.4f)", z2->m,
                         z2->zeta, z2->err_jackknife, z2->predicted);
            }
            printf("%s: n = %d, %lld realisations (%.4g partitions) in %.3g s; %s; plots: %s\n",
                   out, s.levels, (long long)s.repetitions, res.segments, res.wall_seconds, zeta,
                   o.plots_note);
            printf("wrote %s\n", out);
        }
        gr_bisect_result_free(&res);
    }
    for (int k = 0; k < loaded; k++) {
        gr_bisect_g1_free(&g1[k]);
    }
    gr_bisect_u0_free(&u0);
    return rc;
}
