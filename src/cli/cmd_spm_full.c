/* granule spm full: the SPM P(v) with l drawn from P_l (thesis sec. 5.2.3), optionally against a
 * Random Force Model run (Fig. 5.10). Parses options and prints; the study is
 * gr_spm_full_prepare/run/write (granule/spm_study.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/spm_cli.h"
#include "granule/spm_study.h"
#include "io/files.h"

int cmd_spm_full(int argc, char **argv);

typedef struct full_args {
    gr_spm_full_params p;
    spm_options spm;
    const char *weight;
} full_args;

static const cli_opt full_opts[] = {
    {"--pl", CLI_STRING, "FILE", offsetof(full_args, p.pl_path), 0, 0, 0, NULL,
     "measured P_l: CSV with a header naming columns l (m) and P (or density; optional P_err or "
     "density_error); '#' "
     "lines are comments; or a run's freepath.csv (l_over_d: diameters, see --diameter)",
     NULL},
    {"--diameter", CLI_DOUBLE, "D", offsetof(full_args, p.diameter), 0, 0, 0, "the run folder's",
     "particle diameter, m, for l_over_d", NULL},
    {"--df", CLI_DOUBLE, "D_f", offsetof(full_args, p.df), 0, 0, 0, NULL,
     "use the fitted form 4.25, P_l ~ l^(D_f-2) exp(-C l^(D_f-1)); without --pl and --compare-run "
     "D_f defaults to 1.63 "
     "(the thesis' D_f, sec. 4.2)",
     NULL},
    {"--C", CLI_DOUBLE, "C", offsetof(full_args, p.C), 0, 0, 0,
     "121: phi = 0.530, thesis sec. 5.3.3", "its constant, m^-(D_f-1)", NULL},
    {"--tail-from", CLI_DOUBLE, "L", offsetof(full_args, p.tail_from), 0, 0, 0,
     "the longest 10% of the paths", "fit 4.25 to the --pl table for l >= L, m", NULL},
    {"--weight", CLI_CHOICE, "time|walk", offsetof(full_args, weight), 0, 0, 0, "time",
     "sample uniformly in time (the thesis' simulation) or weigh every walk equally (5.10 with Q "
     "normalised per walk)",
     NULL},
    {"--tilt", CLI_DOUBLE, "K", offsetof(full_args, p.s.tilt), 0, 0, 0, "1: none",
     "importance sampling of long free paths (e.g. 4 reaches several more decades of the tail)",
     NULL},
    {"--vmax", CLI_DOUBLE, "V", offsetof(full_args, p.vmax), 0, 0, 0, "from P_l and --walks",
     "histogram range of |v|, m/s", NULL},
    {"--fit-from", CLI_DOUBLE, "V", offsetof(full_args, p.fit_from), 0, 0, 0, "3 v_rms of the SPM",
     "tail fits of P(v) over v >= V, m/s", NULL},
    {"--compare-run", CLI_STRING, "DIR", offsetof(full_args, p.run_dir), 0, 0, 0, NULL,
     "a granule run folder: P(v) per component from DIR/snapshots/snap_*.xyz (frames after the "
     "warm-up), compared with "
     "the SPM; M, D and dim default to the run's",
     NULL},
    {"--t-from", CLI_DOUBLE, "T", offsetof(full_args, p.t_from), 0, 0, 0, "the run's warm-up",
     "use snapshots with Time >= T s", NULL},
    {"--compare-from", CLI_DOUBLE, "V", offsetof(full_args, p.compare_from), 0, 0, 0,
     "2 v_rms of the run", "fit the vertical scale over v >= V, m/s", NULL},
    {"--z-max", CLI_DOUBLE, "Z", offsetof(full_args, p.z_max), 0, 0, 0, "3",
     "bins agree when |P_rfm - k P_spm| <= Z sigma", NULL},
    SPM_COMMON_OPTS(full_args, "200000", "100", "out/spm-full"),
};

const cli_command cli_cmd_spm_full = {
    .name = "spm full",
    .usage = "granule spm full [--pl FILE | --df D_f [--C C]] [--compare-run DIR] [options]\n"
             "       granule spm full --compare-run DIR [options]   (P_l from DIR/freepath.csv)",
    .about = "The SPM of thesis sec. 5.2.3: every walk draws its radius l from the free-path\n"
             "distribution P_l(l); the velocity distribution P(v) of one component is sampled\n"
             "uniformly in time over all walks (integral identity 5.10).\n",
    .epilog = "Writes p_v.csv, pl.csv, compare.csv (with --compare-run), summary.json, p_v.png, "
              "pl.png.\n",
    CLI_OPTS(full_opts),
};

static void print_rfm(const gr_spm_full_params *p, const gr_spm_full_report *r)
{
    const gr_spm_compare *c1 = &r->cmp, *c2 = &r->cmp2;
    printf("  RFM %s: %d frames, %lld particles, v_rms = %.4g m/s\n", p->run_dir, r->info.frames,
           (long long)r->info.particles, sqrt(r->info.v2_mean));
    const bool few = r->info.frames < GR_MIN_FRAMES; /* error bars of P_rfm not to be trusted */
    if (few) {
        printf("    WARNING: no verdict: %d frames, fewer than the %d a comparison needs (run "
               "longer or sample "
               "more often)\n",
               r->info.frames, GR_MIN_FRAMES);
        return;
    }
    if (r->have_cmp) {
        printf("    k P_spm(v), amplitude k = %.4g fitted: agrees (|z| <= %g) for %.3g <= v <= "
               "%.3g m/s, %.2f decades of P(v); %.0f%% of the bins "
               "v >= %.3g within\n",
               c1->k, p->z_max, c1->v_agree_lo, c1->v_agree_hi, c1->decades,
               100.0 * c1->frac_within, p->compare_from);
    }
    if (r->have_cmp2) {
        printf("    k P_spm(v/s)/s, amplitude k = %.4g and velocity scale s = %.4g +- %.2g fitted",
               c2->k, c2->s, c2->s_err);
        if (isfinite(r->implied_C)) {
            printf(" (C = %.4g)", r->implied_C);
        }
        printf(": agrees for %.3g <= v <= %.3g m/s, %.2f decades; %.0f%% of the tail bins within\n",
               c2->v_agree_lo, c2->v_agree_hi, c2->decades, 100.0 * c2->frac_within);
    }
    if (!r->have_cmp && !r->have_cmp2) {
        printf("    no comparison possible (no common tail bins)\n");
    }
}

static void print_report(const char *out, const gr_spm_full_params *p, const gr_spm_full_report *r)
{
    printf("%s: SPM P(v), %dD, %lld walks (%s), l from %s, %.1f s\n", out, p->s.dim,
           (long long)p->s.walks, p->weight_time ? "uniform in time" : "per walk", r->pl.source,
           r->wall_seconds);
    if (r->df_defaulted) {
        printf("  D_f = 1.63: the default, the thesis' D_f = 1.63 +- 0.03 (sec. 4.2); give --df, "
               "--pl or --compare-run to change it\n");
    }
    printf(
        "  <l> = %.4g m, v_rms = %.4g m/s, data up to %.3g m/s, mean first-passage time %.4f t_l\n",
        r->res.l_mean, r->v_rms, r->v_data, r->res.stats.exit_time_mean);
    spm_print_constants(&r->constants, "every walk in the units of its own l");
    if (p->pl_path && r->have_plfit) {
        printf("  P_l tail (4.25) over l >= %.3g m: D_f = %.3f +- %.3f, C = %.4g +- %.2g\n",
               r->plfit.lfrom, r->plfit.df, r->plfit.df_err, r->plfit.C, r->plfit.C_err);
    }
    if (r->have_sfit) {
        printf("  tail v >= %.3g m/s: stretched exponential alpha = %.3f +- %.3f (jackknife; "
               "chi2/dof %.2f)\n",
               p->fit_from, r->sfit[2], r->sfit_err[2], r->sfit_chi2);
    }
    if (r->have_pred) {
        const gr_spm_prediction *q = &r->pred;
        printf("  prediction: alpha = %.4f (5.29), h = %.4f (5.31), S = %.4g, v_A = %.4g m/s "
               "(5.27, b = 0.98)",
               q->alpha, q->h, q->S, q->v_A);
        if (r->have_531) {
            printf("; fitted with alpha fixed: S = %.4g +- %.2g, h = %.3f +- %.3f", r->f531[2],
                   r->f531_err[2], r->f531[1], r->f531_err[1]);
        }
        printf("\n");
    }
    if (p->run_dir) {
        print_rfm(p, r);
    }
}

int cmd_spm_full(int argc, char **argv)
{
    gr_spm_full_params p;
    gr_spm_full_params_default(&p);
    full_args args = {
        .p = p, .spm = {.mass = NAN, .D = NAN, .th.out = "out/spm-full"}, .weight = "time"};
    const int parsed = spm_parse(&cli_cmd_spm_full, argc, argv, &args, &args.spm, &args.p.s);
    if (parsed >= 0) {
        return parsed;
    }
    p = args.p;
    spm_options o = args.spm;
    o.s = &p.s;
    p.weight_time = !strcmp(args.weight, "time");
    gr_error err = {0};
    gr_spm_full_report r;
    int rc = gr_spm_full_prepare(&p, &r, &err);
    if (!rc) {
        rc = gr_output_dir_prepare(o.th.out, GR_OUTPUT_RESULT, o.th.force, &err);
    }
    if (!rc) {
        spm_progress_on(&o, "spm full");
        rc = gr_spm_full_run(&p, &r, &err);
        spm_progress_off(&o);
    }
    if (!rc) {
        rc = gr_spm_full_write(o.th.out, &p, &r, !o.th.no_plots, &err);
    }
    if (!rc) {
        print_report(o.th.out, &p, &r);
        printf("wrote %s\n", o.th.out);
    }
    gr_spm_full_report_free(&r);
    if (rc) {
        app_error("%s", err.message);
        return spm_exit_code(&err);
    }
    return EXIT_OK;
}
