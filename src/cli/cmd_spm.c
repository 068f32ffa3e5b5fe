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
    fprintf(f,
            "usage: granule spm circle|full|predict [options]   (granule spm MODE --help for each)\n\n"
            "The Single Particle Model of thesis sec. 5.2-5.3: one particle starts at rest at the centre\n"
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

static void usage_circle(FILE *f)
{
    fprintf(f,
            "usage: granule spm circle [--radius L1,L2,...] [options]\n\n"
            "Q(v,l) of thesis sec. 5.3.1: for each radius, walks from rest at the centre to the first\n"
            "arrival at the boundary, velocities (one component) sampled uniformly in time. The\n"
            "histograms are of w = v / u_l, u_l = (2 D l / M^2)^(1/3), so that radii are compared bin by\n"
            "bin (collapse under v / l^(1/3)); the Gaussian tail Q ~ A exp(-b w^2) (5.12; the thesis\n"
            "finds b = 0.98) is fitted per radius and pooled.\n"
            "  --radius LIST     radii in m, comma-separated (default 0.0036,0.01,0.02,0.04)\n"
            "  --wmax W          histogram range of |w| (default 4.5)\n"
            "  --fit-from W      Gaussian tail fit over w >= W (default 2.5)\n"
            SPM_COMMON_HELP
            "Writes q.csv, q_radii.csv, summary.json, q_collapse.png, q_raw.png.\n",
            "20000 per radius", 90, "out/spm-circle");
}

static void usage_predict(FILE *f)
{
    fprintf(f,
            "usage: granule spm predict [--df D_f | --pl FILE] [--C C] [--b B] [options]\n\n"
            "The asymptotic tail of P(v) from the SPM integral identity (thesis sec. 5.3.2):\n"
            "  alpha = 6 (D_f - 1) / (3 D_f - 1)                       (5.29)\n"
            "  S = B (gamma/2F)^(2/(gamma+2)) + C (2F/gamma)^(gamma/(gamma+2)), v_A = S^(-1/alpha),\n"
            "  F = B/C, gamma = 3 (D_f - 1), P(v) ~ v^h exp(-S |v|^alpha)  (5.27)\n"
            "  h = 3 (D_f - 1) / (3 D_f - 1)                            (5.30-5.31)\n"
            "  --df D_f          fractal dimension (default 1.63 +- 0.03, the thesis' D_f, sec. 4.2)\n"
            "  --pl FILE         or fit 4.25 to a measured P_l table (columns l, P; or a run's\n"
            "                    freepath.csv, columns l_over_d, density) for D_f and C\n"
            "  --diameter D      particle diameter, m, for l_over_d (default: the run folder's)\n"
            "  --tail-from L     fit over l >= L, m (default: the longest 10%% of the paths)\n"
            "  --C C             C of 4.25, m^-(D_f-1) (default 121 with --df: thesis sec. 5.3.3)\n"
            "  --b B             Q's Gaussian tail coefficient of 5.12 (default 0.98; granule spm\n"
            "                    circle measures it); B = b (M^2/2D)^(2/3)\n"
            "  --mass M, --D D   as for the other modes (Table 2.2 defaults)\n"
            "  --vmax V          range of the tabulated integral 5.13, m/s (default 20 v_A)\n"
            "  --out DIR         output folder (default out/spm-predict); --force, --no-plots,\n"
            "                    --format png|svg|pdf, --quiet as the other modes\n"
            "Writes prediction.csv (5.13 integrated numerically against 5.26), summary.json,\n"
            "prediction.png.\n");
}

static int parse_list(const char *text, double *out, int max, int *n)
{
    char buf[2048];
    snprintf(buf, sizeof buf, "%s", text);
    *n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (*n >= max) {
            cli_error("spm: --radius takes at most %d radii", max);
            return -1;
        }
        char *end;
        double x = strtod(tok, &end);
        if (end == tok || *end || !(x > 0.0) || !isfinite(x)) {
            cli_error("spm: --radius needs positive numbers separated by commas (m), got '%s'", text);
            return -1;
        }
        out[(*n)++] = x;
    }
    if (*n == 0) {
        cli_error("spm: --radius needs at least one radius");
        return -1;
    }
    return 0;
}


static int cmd_circle(int argc, char **argv)
{
    gr_spm_circle_params p;
    gr_spm_circle_params_default(&p);
    spm_options o = {.s = &p.s, .out = "out/spm-circle", .plots = true, .bins = &p.bins};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage_circle(stdout);
            return EXIT_OK;
        }
        int c = spm_common_option(argc, argv, &i, &o);
        if (c < 0) {
            return EXIT_REFUSED;
        }
        if (c > 0) {
            continue;
        }
        if (!strcmp(a, "--radius")) {
            if (i + 1 >= argc) {
                cli_error("spm: --radius needs a value");
                return EXIT_REFUSED;
            }
            if (parse_list(argv[++i], p.radii, GR_SPM_MAX_RADII, &p.n_radii)) {
                return EXIT_REFUSED;
            }
        } else if (!strcmp(a, "--wmax") || !strcmp(a, "--fit-from")) {
            double x;
            if (!spm_value_number(argc, argv, &i, &x)) {
                return EXIT_REFUSED;
            }
            *(!strcmp(a, "--wmax") ? &p.wmax : &p.fit_from) = x;
        } else {
            spm_unknown("circle", a);
            return EXIT_REFUSED;
        }
    }
    gr_error err = {0};
    if (gr_spm_circle_prepare(&p, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (gr_output_dir_prepare(o.out, GR_OUTPUT_RESULT, o.force, &err)) {
        cli_error("%s", err.message);
        return spm_exit_code(&err);
    }
    gr_spm_circle_report r;
    spm_progress_on(&o, "spm circle");
    int rc = gr_spm_circle_run(&p, &r, &err);
    spm_progress_off(&o);
    if (rc) {
        cli_error("%s", err.message);
        return spm_exit_code(&err);
    }
    rc = gr_spm_circle_write(o.out, &p, &r, o.plots, &err);
    if (!rc) {
        const gr_spm_tail_fit *pf = &r.pooled_fit;
        printf("%s: Q(v,l) for %d radii, %dD, %lld walks each, %.1f s\n", o.out, p.n_radii, p.s.dim, (long long)p.s.walks,
               r.wall_seconds);
        for (int k = 0; k < p.n_radii; k++) {
            const gr_spm_walk_stats *st = &r.q[k].stats;
            printf("  l = %g m: u_l = %.4g m/s, <T> = %.4f +- %.4f t_l, <w^2> = %.4f +- %.4f, b = %.4f +- %.4f (w >= %g)",
                   p.radii[k], r.q[k].u, st->exit_time_mean, st->exit_time_err, st->w2_time_mean, st->w2_time_err,
                   r.fit[k].b, r.fit[k].b_err, p.fit_from);
            if (k > 0) {
                printf(", collapse vs l = %g: chi2/dof = %.3g (%d bins, p = %.3g)", p.radii[0], r.collapse[k].chi2_red,
                       r.collapse[k].dof, r.collapse[k].p_value);
            }
            printf("\n");
        }
        printf("  pooled Gaussian tail (5.12): b = %.4f +- %.4f (thesis 0.98), i.e. B = %.4g s^2 m^-4/3; free exponent %.3f +- %.3f\n",
               pf->b, pf->b_err, gr_spm_B(&p.s, pf->b), pf->beta, pf->beta_err);
        spm_print_constants(&r.pooled_constants, "inverse-variance mean over the radii");
        printf("wrote %s\n", o.out);
    }
    gr_spm_circle_report_free(&r);
    if (rc) {
        cli_error("%s", err.message);
        return spm_exit_code(&err);
    }
    return EXIT_OK;
}

static int cmd_predict(int argc, char **argv)
{
    gr_spm_predict_params p;
    gr_spm_predict_params_default(&p);
    const char *out = "out/spm-predict";
    bool force = false, plots = true, quiet = false; /* predict draws no progress line */
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage_predict(stdout);
            return EXIT_OK;
        }
        const int common = cli_theory_option("spm", argc, argv, &i, &force, &quiet, &plots);
        if (common < 0) {
            return EXIT_REFUSED;
        }
        if (common) {
            continue;
        }
        static const char *const nums[] = {"--df", "--C", "--b", "--mass", "--D", "--tail-from", "--vmax", "--diameter"};
        double *const dest[] = {&p.df, &p.C, &p.b, &p.s.mass, &p.s.D, &p.tail_from, &p.vmax, &p.diameter};
        int k = -1;
        for (int j = 0; j < (int)(sizeof nums / sizeof nums[0]); j++) {
            if (!strcmp(a, nums[j])) {
                k = j;
            }
        }
        bool text = !strcmp(a, "--out") || !strcmp(a, "--pl");
        if (k < 0 && !text) {
            spm_unknown("predict", a);
            return EXIT_REFUSED;
        }
        if (i + 1 >= argc) {
            cli_error("spm: %s needs a value", a);
            return EXIT_REFUSED;
        }
        if (text) {
            *(!strcmp(a, "--out") ? &out : &p.pl_path) = argv[++i];
        } else if (!spm_value_number(argc, argv, &i, dest[k])) {
            return EXIT_REFUSED;
        }
    }
    if (strlen(out) >= 1000) {
        cli_error("spm: --out %s: path too long", out);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    gr_spm_predict_report r;
    if (gr_spm_predict_prepare(&p, &r, &err)) {
        cli_error("%s", err.message);
        return spm_exit_code(&err);
    }
    if (gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force, &err) || gr_spm_predict_write(out, &p, &r, plots, &err)) {
        cli_error("%s", err.message);
        return spm_exit_code(&err);
    }
    const gr_spm_prediction *q = &r.p;
    printf("%s: D_f = %.4g%s\n", out, p.df,
           p.pl_path ? " (fitted to the P_l tail)"
                     : r.df_defaulted ? " (default: the thesis' D_f = 1.63 +- 0.03, sec. 4.2; give --df or --pl to change it)" : "");
    if (p.pl_path) {
        printf("  P_l tail (4.25) over %.3g <= l <= %.3g m: D_f = %.3f +- %.3f, C = %.4g +- %.2g, chi2/dof %.2f\n",
               r.plfit.lfrom, r.plfit.lto, r.plfit.df, r.plfit.df_err, r.plfit.C, r.plfit.C_err, r.plfit.chi2_red);
    }
    printf("  alpha = 6(D_f - 1)/(3 D_f - 1) = %.4f (5.29)\n", q->alpha);
    printf("  H(v) ~ v^h, h = 3(D_f - 1)/(3 D_f - 1) = %.4f (5.30-5.31)\n", q->h);
    printf("  B = %.4g (b = %g), C = %.4g: S = %.4g (m/s)^-alpha, v_A = S^(-1/alpha) = %.4g m/s (5.27)\n", q->B, p.b, q->C,
           q->S, q->v_A);
    printf("wrote %s\n", out);
    return EXIT_OK;
}

/* ------------------------------------------------------------------------------------------- */

int cmd_spm(int argc, char **argv)
{
    if (argc < 2) {
        cli_error("spm: give a mode: circle, full or predict (granule spm --help)");
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
    cli_error("spm: unknown mode %s (circle, full or predict; granule spm --help)", m);
    return EXIT_REFUSED;
}
