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

static void usage(FILE *f)
{
    fprintf(f,
            "usage: granule bisect [--out DIR] [--levels N] [--repetitions R] [--u0 uniform|power:A|FILE]\n"
            "                      [--seed S] [--g1 FILE ...] [--moments M] [--bins-per-decade B]\n"
            "                      [--fit-from K] [--jackknife G] [--anchor R0] [--no-plots] [--format F] [--force] [--quiet]\n\n"
            "Bisects the unit interval N times (2^N partitions), every partition at a fraction a drawn from\n"
            "U_0(a) (thesis eqs. 3.26-3.28), R times, and writes into DIR:\n"
            "  pn.csv        P_n(x) at level N (log bins, sqrt(X) errors) beside (-ln x)^(N-1)/(N-1)! (3.36)\n"
            "  moments.csv   <x^m> at every level k against mu_m^k ((1+m)^-k for the uniform U_0, 3.37)\n"
            "  zeta.csv      zeta_m of <x^m> = A (2^k)^-zeta_m with fit and jackknife errors, beside\n"
            "                ln(1+m)/ln 2 (3.38) and the RFM's Table 3.1\n"
            "  collapse.csv  A_N G^(1/(n-1)) against -ln R (3.39-3.40) for the process and each --g1 table\n"
            "  summary.json, and pn.png, moments.png, moments_N.png, collapse.png (gnuplot)\n\n"
            "  --levels N         levels n, 1..%d (default 9: 512 partitions, Figs. 3.15-3.16)\n"
            "  --repetitions R    realisations, >= 2 (default 10000)\n"
            "  --u0 SPEC          uniform (default); power:A for U_0 = (1-A)/2 (a^-A + (1-a)^-A),\n"
            "                     %g <= A <= %g; or a CSV file of a,U points (piecewise linear, normalised)\n"
            "  --seed S           gsl_rng_mt19937 seed (default 1)\n"
            "  --g1 FILE          a 1D RFM nearest-neighbour distribution G_1(R;N) to collapse with the\n"
            "                     process (repeatable, up to %d): CSV R,G[,G_err] with a '# N = <particles>'\n"
            "                     comment (docs/theory-bisect.md)\n"
            "  --moments M        moments m = 1..M (default 6, at most %d)\n"
            "  --bins-per-decade B  bins of P_n(x) (default 10)\n"
            "  --fit-from K       fit zeta_m over levels K..N (default 1)\n"
            "  --jackknife G      groups of realisations for the jackknife errors (default 32)\n"
            "  --anchor R0        R_0 of A_N (3.40; default 0.7)\n"
            "  --out DIR          output folder (default out/bisect)\n"
            "  --no-plots         no plots\n"
            "  --format F         plots as png (default), svg or pdf\n"
            "  --force            overwrite the results of an earlier run in DIR\n"
            "  --quiet            no progress line\n"
            "Exit status: 0 done, 2 bad input (options, U_0 or G_1 file, DIR holds a run), 1 other failure.\n",
            GR_BISECT_MAX_LEVELS, GR_BISECT_POWER_A_MIN, GR_BISECT_POWER_A_MAX, MAX_G1, GR_BISECT_MAX_MOMENTS);
}

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
    fprintf(stderr, "\rbisect: %lld / %lld realisations  %3.0f%%  ETA %d:%02d:%02d   ", (long long)done,
            (long long)total, 100.0 * (double)done / (double)total, eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

/* An integer option within [lo, hi]. */
static bool int_option(const char *opt, const char *text, double lo, double hi, double *out)
{
    if (!cli_number(opt, text, out)) {
        return false;
    }
    if (*out != floor(*out) || *out < lo || *out > hi) {
        cli_error("bisect: %s must be an integer in [%.0f, %.0f], got %s", opt, lo, hi, text);
        return false;
    }
    return true;
}

int cmd_bisect(int argc, char **argv)
{
    gr_bisect_settings s;
    gr_bisect_settings_default(&s);
    const char *out = "out/bisect", *u0_spec = "uniform", *g1_paths[MAX_G1];
    int n_g1 = 0;
    bool force = false, quiet = false, plots = true;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        int k;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return EXIT_OK;
        } else if ((k = cli_theory_option("bisect", argc, argv, &i, &force, &quiet, &plots)) != 0) {
            if (k < 0) {
                return EXIT_REFUSED;
            }
        } else if (!v || strncmp(a, "--", 2) != 0) {
            cli_error("bisect: unknown or incomplete option %s (granule bisect --help)", a);
            return EXIT_REFUSED;
        } else {
            i++;
            if (!strcmp(a, "--out")) {
                out = v;
            } else if (!strcmp(a, "--u0")) {
                u0_spec = v;
            } else if (!strcmp(a, "--g1")) {
                if (n_g1 == MAX_G1) {
                    cli_error("bisect: at most %d --g1 tables", MAX_G1);
                    return EXIT_REFUSED;
                }
                g1_paths[n_g1++] = v;
            } else if (!strcmp(a, "--seed")) {
                char *end;
                errno = 0;
                unsigned long long seed = strtoull(v, &end, 10);
                if (end == v || *end || errno || v[0] == '-') {
                    cli_error("bisect: --seed needs a non-negative integer, got '%s'", v);
                    return EXIT_REFUSED;
                }
                s.seed = seed;
            } else if (!strcmp(a, "--levels")) {
                if (!int_option(a, v, 1, GR_BISECT_MAX_LEVELS, &x)) {
                    return EXIT_REFUSED;
                }
                s.levels = (int)x;
            } else if (!strcmp(a, "--repetitions")) {
                if (!int_option(a, v, 2, 1e15, &x)) {
                    return EXIT_REFUSED;
                }
                s.repetitions = (int64_t)x;
            } else if (!strcmp(a, "--moments")) {
                if (!int_option(a, v, 1, GR_BISECT_MAX_MOMENTS, &x)) {
                    return EXIT_REFUSED;
                }
                s.moments_max = (int)x;
            } else if (!strcmp(a, "--bins-per-decade")) {
                if (!int_option(a, v, 1, 1000, &x)) {
                    return EXIT_REFUSED;
                }
                s.bins_per_decade = (int)x;
            } else if (!strcmp(a, "--fit-from")) {
                if (!int_option(a, v, 1, GR_BISECT_MAX_LEVELS, &x)) {
                    return EXIT_REFUSED;
                }
                s.fit_level_min = (int)x;
            } else if (!strcmp(a, "--jackknife")) {
                if (!int_option(a, v, 2, 1024, &x)) {
                    return EXIT_REFUSED;
                }
                s.jackknife_groups = (int)x;
            } else if (!strcmp(a, "--anchor")) {
                if (!cli_number(a, v, &x)) {
                    return EXIT_REFUSED;
                }
                s.anchor = x;
            } else {
                cli_error("bisect: unknown option %s (granule bisect --help)", a);
                return EXIT_REFUSED;
            }
        }
    }
    if (strlen(out) > 1000) {
        cli_error("bisect: --out %.40s...: path too long", out);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    if (gr_bisect_settings_check(&s, &err)) {
        cli_error("bisect: %s", err.message);
        return EXIT_REFUSED;
    }
    /* inputs first: a bad U_0 or G_1 table is refused before any output or work */
    gr_bisect_u0 u0;
    if (gr_bisect_u0_parse(&u0, u0_spec, &err)) {
        cli_error("bisect: --u0: %s", err.message);
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
            cli_error("bisect: --g1: %s", err.message);
            rc = EXIT_REFUSED;
            break;
        }
    }
    if (!rc && u0.kind == GR_BISECT_U0_TABLE && u0.asymmetry > 1e-6) {
        fprintf(stderr, "granule: warning: U_0 table %s is not symmetric (max |U(a) - U(1-a)| = %.3g of its peak); "
                        "3.30 asks U_0(a) = U_0(1-a), and the statistics see only (U(a) + U(1-a))/2\n",
                u0.name, u0.asymmetry);
    }
    if (!rc && gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force, &err)) {
        cli_error("bisect: %s", err.message);
        rc = err.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    gr_bisect_result res;
    progress_state ps = {wall(), 0.0};
    if (!rc) {
        if (!quiet && cli_interactive()) {
            s.progress = progress;
            s.user = &ps;
        }
        int st = gr_bisect_run(&s, &u0, &res, &err);
        if (s.progress) {
            fputc('\n', stderr);
        }
        if (st) {
            cli_error("bisect: %s", err.message);
            rc = st == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
        }
    }
    if (!rc) {
        gr_bisect_output o = {.g1 = g1, .n_g1 = n_g1, .plots = plots};
        if (gr_bisect_write(out, &s, &u0, &res, &o, &err)) {
            cli_error("bisect: %s", err.message);
            rc = err.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
        } else {
            const gr_bisect_zeta *z2 = s.moments_max >= 2 ? &res.zeta[1] : &res.zeta[0];
            char zeta[160] = "no zeta fit with one level";
            if (isfinite(z2->zeta)) {
                snprintf(zeta, sizeof zeta, "zeta_%d = %.4f +- %.4f (predicted %.4f)", z2->m, z2->zeta,
                         z2->err_jackknife, z2->predicted);
            }
            printf("%s: n = %d, %lld realisations (%.4g partitions) in %.3g s; %s; plots: %s\n", out, s.levels,
                   (long long)s.repetitions, res.segments, res.wall_seconds, zeta, o.plots_note);
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
