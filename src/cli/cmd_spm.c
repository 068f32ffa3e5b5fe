/* granule spm circle|full|predict: the Single Particle Model of thesis sec. 5.2-5.3.
 *
 *   circle   Q(v, l) in a disc (interval) of fixed radius, its collapse under v / l^(1/3) and the
 *            Gaussian tail 5.12 (sec. 5.3.1)
 *   full     the SPM P(v) with l drawn from P_l(l) (a measured table or the fitted form 4.25),
 *            optionally against a Random Force Model run's P(v) (sec. 5.2.3, Fig. 5.10); in
 *            cmd_spm_full.c
 *   predict  alpha (5.29), S and v_A (5.27), the power h of H(v) (5.30-5.31), and the numerical
 *            integral 5.13 against its steepest-descent form 5.26
 *
 * This file parses options and prints; the studies are library calls (granule/spm_study.h), which
 * write CSV files with commented headers, summary.json and PNG plots into --out. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/spm_cli.h"
#include "granule/spm_study.h"
#include "io/files.h"

int cmd_spm_full(int argc, char **argv);

static void usage_main(FILE *f)
{
    fprintf(
        f,
        "usage: granule spm circle|full|predict [options]   (granule spm MODE --help for each)\n\n"
        "The Single Particle Model of thesis sec. 5.2-5.3: one particle starts at rest at the "
        "centre\n"
        "of a disc (2D) or interval (1D) of radius l and is driven by the random force until it\n"
        "first reaches the boundary; its velocity is sampled uniformly in time.\n"
        "  circle   Q(v,l) for fixed radii: collapse under v / l^(1/3), Gaussian tail 5.12\n"
        "  full     P(v) with l drawn from P_l(l) (--pl FILE or --df D_f [--C C], eq. 4.25;\n"
        "           D_f defaults to the thesis' 1.63);\n"
        "           --compare-run DIR overlays a Random Force Model run's P(v)\n"
        "  predict  alpha = 6(D_f - 1)/(3 D_f - 1) (5.29), v_A (5.27), H(v) ~ v^h (5.30-5.31)\n"
        "Every mode writes into --out (default out/spm-MODE) and ends with 'wrote DIR'. The SPM's\n"
        "constants are printed in the thesis' convention: <v_x^2> = c (D l/M^2)^(2/3) and\n"
        "<T_fp> = c' (l^2 M^2/D)^(1/3), with their errors.\n"
        "Free flight is sampled exactly; see docs/theory-spm.md for the model, the options, the\n"
        "output files and measured results.\n"
        "Exit status: 0 done, 2 bad input, 1 other failure.\n");
}

typedef struct circle_args {
    gr_spm_circle_params p;
    spm_options spm;
    const char *radius;
} circle_args;

static const cli_opt circle_opts[] = {
    {"--radius", CLI_STRING, "LIST", offsetof(circle_args, radius), 0, 0, 0,
     "0.0036,0.01,0.02,0.04", "radii in m, comma-separated", NULL},
    {"--wmax", CLI_DOUBLE, "W", offsetof(circle_args, p.wmax), 0, 0, 0, "4.5",
     "histogram range of |w|", NULL},
    {"--fit-from", CLI_DOUBLE, "W", offsetof(circle_args, p.fit_from), 0, 0, 0, "2.5",
     "Gaussian tail fit over w >= W", NULL},
    SPM_COMMON_OPTS(circle_args, "20000 per radius", "90", "out/spm-circle"),
};

const cli_command cli_cmd_spm_circle = {
    .name = "spm circle",
    .usage = "granule spm circle [--radius L1,L2,...] [options]",
    .about =
        "Q(v,l) of thesis sec. 5.3.1: for each radius, walks from rest at the centre to the first\n"
        "arrival at the boundary, velocities (one component) sampled uniformly in time. The\n"
        "histograms are of w = v / u_l, u_l = (2 D l / M^2)^(1/3), so that radii are compared bin "
        "by\n"
        "bin (collapse under v / l^(1/3)); the Gaussian tail Q ~ A exp(-b w^2) (5.12; the thesis\n"
        "finds b = 0.98) is fitted per radius and pooled.\n",
    .epilog = "Writes q.csv, q_radii.csv, summary.json, q_collapse.png, q_raw.png.\n",
    CLI_OPTS(circle_opts),
};

typedef struct predict_args {
    gr_spm_predict_params p;
    cli_theory th;
} predict_args;

static const cli_opt predict_opts[] = {
    {"--df", CLI_DOUBLE, "D_f", offsetof(predict_args, p.df), 0, 0, 0,
     "1.63 +- 0.03, the thesis' D_f, sec. 4.2", "fractal dimension", NULL},
    {"--pl", CLI_STRING, "FILE", offsetof(predict_args, p.pl_path), 0, 0, 0, NULL,
     "or fit 4.25 to a measured P_l table (columns l, P; or a run's freepath.csv, columns "
     "l_over_d, density) for D_f and C",
     NULL},
    {"--diameter", CLI_DOUBLE, "D", offsetof(predict_args, p.diameter), 0, 0, 0, "the run folder's",
     "particle diameter, m, for l_over_d", NULL},
    {"--tail-from", CLI_DOUBLE, "L", offsetof(predict_args, p.tail_from), 0, 0, 0,
     "the longest 10% of the paths", "fit over l >= L, m", NULL},
    {"--C", CLI_DOUBLE, "C", offsetof(predict_args, p.C), 0, 0, 0,
     "121 with --df: thesis sec. 5.3.3", "C of 4.25, m^-(D_f-1)", NULL},
    {"--b", CLI_DOUBLE, "B", offsetof(predict_args, p.b), 0, 0, 0, "0.98",
     "Q's Gaussian tail coefficient of 5.12 (granule spm circle measures it); B = b (M^2/2D)^(2/3)",
     NULL},
    {"--mass", CLI_DOUBLE, "M", offsetof(predict_args, p.s.mass), 0, 0, 0, "3.53e-5, Table 2.2",
     "particle mass, kg", NULL},
    {"--D", CLI_DOUBLE, "D", offsetof(predict_args, p.s.D), 0, 0, 0, "1e-8, Table 2.2",
     "noise strength, N^2 s", NULL},
    {"--vmax", CLI_DOUBLE, "V", offsetof(predict_args, p.vmax), 0, 0, 0, "20 v_A",
     "range of the tabulated integral 5.13, m/s", NULL},
    CLI_THEORY_OPTS(predict_args, th, "out/spm-predict"),
};

const cli_command cli_cmd_spm_predict = {
    .name = "spm predict",
    .usage = "granule spm predict [--df D_f | --pl FILE] [--C C] [--b B] [options]",
    .about =
        "The asymptotic tail of P(v) from the SPM integral identity (thesis sec. 5.3.2):\n"
        "  alpha = 6 (D_f - 1) / (3 D_f - 1)                       (5.29)\n"
        "  S = B (gamma/2F)^(2/(gamma+2)) + C (2F/gamma)^(gamma/(gamma+2)), v_A = S^(-1/alpha),\n"
        "  F = B/C, gamma = 3 (D_f - 1), P(v) ~ v^h exp(-S |v|^alpha)  (5.27)\n"
        "  h = 3 (D_f - 1) / (3 D_f - 1)                            (5.30-5.31)\n",
    .epilog = "Writes prediction.csv (5.13 integrated numerically against 5.26), summary.json,\n"
              "prediction.png.\n",
    CLI_OPTS(predict_opts),
};

static int parse_list(const char *text, double *out, int max, int *n)
{
    char buf[2048];
    snprintf(buf, sizeof buf, "%s", text);
    *n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (*n >= max) {
            app_error("spm: --radius takes at most %d radii", max);
            return -1;
        }
        char *end;
        double x = strtod(tok, &end);
        if (end == tok || *end || !(x > 0.0) || !isfinite(x)) {
            app_error("spm: --radius needs positive numbers separated by commas (m), got '%s'",
                      text);
            return -1;
        }
        out[(*n)++] = x;
    }
    if (*n == 0) {
        app_error("spm: --radius needs at least one radius");
        return -1;
    }
    return 0;
}

static int cmd_circle(int argc, char **argv)
{
    gr_spm_circle_params p;
    gr_spm_circle_params_default(&p);
    circle_args args = {.p = p, .spm = {.mass = NAN, .D = NAN, .th.out = "out/spm-circle"}};
    const int parsed = spm_parse(&cli_cmd_spm_circle, argc, argv, &args, &args.spm, &args.p.s);
    if (parsed >= 0) {
        return parsed;
    }
    if (args.radius && parse_list(args.radius, args.p.radii, GR_SPM_MAX_RADII, &args.p.n_radii)) {
        return EXIT_REFUSED;
    }
    p = args.p;
    spm_options o = args.spm;
    o.s = &p.s;
    gr_error err = {0};
    if (gr_spm_circle_prepare(&p, &err)) {
        app_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (gr_output_dir_prepare(o.th.out, GR_OUTPUT_RESULT, o.th.force, &err)) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    gr_spm_circle_report r;
    spm_progress_on(&o, "spm circle");
    int rc = gr_spm_circle_run(&p, &r, &err);
    spm_progress_off(&o);
    if (rc) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    rc = gr_spm_circle_write(o.th.out, &p, &r, !o.th.no_plots, &err);
    if (!rc) {
        const gr_spm_tail_fit *pf = &r.pooled_fit;
        printf("%s: Q(v,l) for %d radii, %dD, %lld walks each, %.1f s\n", o.th.out, p.n_radii,
               p.s.dim, (long long)p.s.walks, r.wall_seconds);
        for (int k = 0; k < p.n_radii; k++) {
            const gr_spm_walk_stats *st = &r.q[k].stats;
            printf("  l = %g m: u_l = %.4g m/s, <T> = %.4f +- %.4f t_l, <w^2> = %.4f +- %.4f, b = "
                   "%.4f +- %.4f (w >= %g)",
                   p.radii[k], r.q[k].u, st->exit_time_mean, st->exit_time_err, st->w2_time_mean,
                   st->w2_time_err, r.fit[k].b, r.fit[k].b_err, p.fit_from);
            if (k > 0) {
                printf(", collapse vs l = %g: chi2/dof = %.3g (%d bins, p = %.3g)", p.radii[0],
                       r.collapse[k].chi2_red, r.collapse[k].dof, r.collapse[k].p_value);
            }
            printf("\n");
        }
        printf("  pooled Gaussian tail (5.12): b = %.4f +- %.4f (thesis 0.98), i.e. B = %.4g s^2 "
               "m^-4/3; free exponent %.3f +- %.3f\n",
               pf->b, pf->b_err, gr_spm_B(&p.s, pf->b), pf->beta, pf->beta_err);
        spm_print_constants(&r.pooled_constants, "inverse-variance mean over the radii");
        printf("wrote %s\n", o.th.out);
    }
    gr_spm_circle_report_free(&r);
    if (rc) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    return EXIT_OK;
}

static int cmd_predict(int argc, char **argv)
{
    gr_spm_predict_params p;
    gr_spm_predict_params_default(&p);
    predict_args args = {.p = p, .th.out = "out/spm-predict"};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_spm_predict, argc, argv, &args, &pos);
    if (parsed >= 0 || cli_theory_set_refused(&cli_cmd_spm_predict, &args.th)) {
        return parsed >= 0 ? parsed : EXIT_REFUSED;
    }
    p = args.p;
    const char *out = args.th.out;
    const bool force = args.th.force,
               plots = !args.th.no_plots; /* predict draws no progress line */
    if (strlen(out) >= 1000) {
        app_error("spm: --out %s: path too long", out);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    gr_spm_predict_report r;
    if (gr_spm_predict_prepare(&p, &r, &err)) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    if (gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force, &err) ||
        gr_spm_predict_write(out, &p, &r, plots, &err)) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    const gr_spm_prediction *q = &r.p;
    printf(
        "%s: D_f = %.4g%s\n", out, p.df,
        p.pl_path ? " (fitted to the P_l tail)"
        : r.df_defaulted
            ? " (default: the thesis' D_f = 1.63 +- 0.03, sec. 4.2; give --df or --pl to change it)"
            : "");
    if (p.pl_path) {
        printf("  P_l tail (4.25) over %.3g <= l <= %.3g m: D_f = %.3f +- %.3f, C = %.4g +- %.2g, "
               "chi2/dof %.2f\n",
               r.plfit.lfrom, r.plfit.lto, r.plfit.df, r.plfit.df_err, r.plfit.C, r.plfit.C_err,
               r.plfit.chi2_red);
    }
    printf("  alpha = 6(D_f - 1)/(3 D_f - 1) = %.4f (5.29)\n", q->alpha);
    printf("  H(v) ~ v^h, h = 3(D_f - 1)/(3 D_f - 1) = %.4f (5.30-5.31)\n", q->h);
    printf("  B = %.4g (b = %g), C = %.4g: S = %.4g (m/s)^-alpha, v_A = S^(-1/alpha) = %.4g m/s "
           "(5.27)\n",
           q->B, p.b, q->C, q->S, q->v_A);
    printf("wrote %s\n", out);
    return EXIT_OK;
}

/* ------------------------------------------------------------------------------------------- */

int cmd_spm(int argc, char **argv)
{
    if (argc < 2) {
        app_error("spm: give a mode: circle, full or predict (granule spm --help)");
        return EXIT_REFUSED;
    }
    const char *m = argv[1];
    if (!strcmp(m, "--help") || !strcmp(m, "-h") || !strcmp(m, "help")) {
        usage_main(stdout);
        return EXIT_OK;
    }
    if (!strcmp(m, "circle")) {
        return cmd_circle(argc - 1, argv + 1);
    }
    if (!strcmp(m, "full")) {
        return cmd_spm_full(argc - 1, argv + 1);
    }
    if (!strcmp(m, "predict")) {
        return cmd_predict(argc - 1, argv + 1);
    }
    app_error("spm: unknown mode %s (circle, full or predict; granule spm --help)", m);
    return EXIT_REFUSED;
}
