/* granule cascade: the multiplicative cascade process of thesis sec. 6.2. Generates C configurations
 * of a 2^n x 2^n cascade field, averages their structure factor (6.5), fits D_f (4.4) and compares
 * it with Table 6.2 and with the exact configuration average; optionally places discs from the
 * first field as in Fig. 6.3. Outputs (docs/theory-cascade.md), each written atomically:
 *   summary.json   D_f with its error, the fit, D_2, the thesis value, timings, placement
 *   sk.csv         circular average of S(k) with errors and the exact expectation
 *   levels.csv     total probability per level over the configurations (UCP: exactly 1)
 *   field.csv      the first configuration's field (coarse-grained to at most 256 x 256)
 *   snapshots/snap_000000.xyz   with --place: the discs, extended XYZ as `granule run` writes,
 *                  and scene.ini (dim 2, N, L, radius) so that `granule analyse DIR` reads them
 *   sk.png, field.png, placement.png   gnuplot
 * This file parses options and prints; the study is gr_cascade_study_run/write
 * (granule/cascade_study.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/cascade_study.h"
#include "io/files.h"

typedef struct cascade_args {
    gr_cascade_settings s;
    const char *variant, *p;
    uint64_t seed;
    int place, fit_min, fit_max; /* 0: not given */
    double radius;               /* 0: not given */
    int64_t max_attempts;        /* 0: not given */
    cli_theory th;
} cascade_args;

static const cli_opt cascade_opts[] = {
    {"--levels", CLI_INT, "n", offsetof(cascade_args, s.levels), 1, GR_CASCADE_MAX_LEVELS, 0, "8",
     "grid 2^n x 2^n (8: the thesis's 256 x 256)", NULL},
    {"--variant", CLI_STRING, "NAME", offsetof(cascade_args, variant), 0, 0, 0, "ucp",
     "ucp, unoncp, symmetrised, meakin1..meakin4 (Table 6.1), meakin (with --p), uniform (control: "
     "every child gets m/4)",
     NULL},
    {"--p", CLI_STRING, "p1,p2,p3,p4", offsetof(cascade_args, p), 0, 0, 0, NULL,
     "the four Meakin numbers (>= 0) for --variant meakin", NULL},
    {"--configurations", CLI_INT, "C", offsetof(cascade_args, s.configurations), 1, 1e9, 0, "200",
     "configurations averaged", NULL},
    {"--seed", CLI_UINT64, "S", offsetof(cascade_args, seed), 0, 4294967295.0, 0, "1",
     "seed of GSL's mt19937", NULL},
    {"--box", CLI_DOUBLE, "L", offsetof(cascade_args, s.L), 0, INFINITY, CLI_MIN_OPEN, "1",
     "box side in m (Fig. 6.3 uses 0.2)", NULL},
    {"--fit-min", CLI_INT, "Q", offsetof(cascade_args, fit_min), 1, 1e9, 0, "1",
     "first |k| L / 2 pi bin of the D_f fit", NULL},
    {"--fit-max", CLI_INT, "Q", offsetof(cascade_args, fit_max), 1, 1e9, 0, "2^(n-3), at least 4",
     "last bin of the D_f fit", NULL},
    {"--place", CLI_INT, "N", offsetof(cascade_args, place), 1, 1e8, 0, NULL,
     "place N discs from the first configuration's field", NULL},
    {"--radius", CLI_DOUBLE, "r", offsetof(cascade_args, radius), 0, INFINITY, CLI_MIN_OPEN,
     "1.5e-3", "disc radius in m (with --place)", NULL},
    {"--max-attempts", CLI_INT64, "A", offsetof(cascade_args, max_attempts), 1, 1e15, 0,
     "10^6 + 10^4 N", "draws allowed for the placement (with --place)", NULL},
    CLI_THEORY_OPTS(cascade_args, th, "out/cascade"),
};

const cli_command cli_cmd_cascade = {
    .name = "cascade",
    .usage =
        "granule cascade [--levels n] [--variant NAME] [--p p1,p2,p3,p4] [--configurations C]\n"
        "                       [--seed S] [--out DIR] [--box L] [--fit-min Q] [--fit-max Q]\n"
        "                       [--place N [--radius r] [--max-attempts A]] [--force] [--no-plots] "
        "[--format F]\n"
        "                       [--quiet]",
    .about = "Multiplicative cascade process (thesis sec. 6.2): breaks a box of side L into 2^n x "
             "2^n squares\n"
             "level by level, sharing each square's probability among its four children "
             "(6.2)-(6.4). Averages\n"
             "the structure factor S(k) (6.5) over C configurations on k = 2 pi (i, j)/L, "
             "circularly in integer\n"
             "|k| L / 2 pi bins, fits S = A k^-D_f over bins Q_min..Q_max (4.4) and compares with "
             "Table 6.2 and\n"
             "with the exact configuration average. --place puts N discs of radius r without "
             "overlap where the\n"
             "first field is likely (Fig. 6.3) and writes them as an extended-XYZ snapshot.\n",
    .epilog = "Writes DIR/summary.json, sk.csv, levels.csv, field.csv, sk.png, field.png and, with "
              "--place,\n"
              "snapshots/snap_000000.xyz, scene.ini (so granule analyse DIR reads them) and "
              "placement.png.\n"
              "Docs: docs/theory-cascade.md. Exit status: 0 done, 2 refused input (one line on "
              "stderr; also\n"
              "when the placement is impossible), 1 other failures.\n",
    CLI_OPTS(cascade_opts),
};

static bool parse_p(const char *text, double p[4])
{
    char *end;
    const char *c = text;
    for (int i = 0; i < 4; i++) {
        p[i] = strtod(c, &end);
        if (end == c || (i < 3 && *end != ',') || (i == 3 && *end != '\0')) {
            app_error("cascade: --p needs four comma-separated numbers, e.g. 0.02,0.32,0.32,0.34; "
                      "got '%s'",
                      text);
            return false;
        }
        c = end + 1;
    }
    return true;
}

static void progress_line(int done, int total, double elapsed, void *user)
{
    (void)user;
    const int eta = done > 0 ? (int)(elapsed * (total - done) / done + 0.5) : 0;
    fprintf(stderr, "\rcascade: configuration %d / %d  %3.0f%%  ETA %d:%02d:%02d   ", done, total,
            100.0 * done / total, eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

static void print_result(const char *out, const gr_cascade_study_params *p,
                         const gr_cascade_study *st)
{
    const gr_cascade_settings *s = &p->s;
    const gr_cascade_variant_info *vi = gr_cascade_variant_get(s->variant);
    const char *plural = s->configurations == 1 ? "" : "s";
    char thesis[64] = "none";
    if (isfinite(vi->thesis_D_f)) {
        snprintf(thesis, sizeof thesis, "%.3f +- %.3f", vi->thesis_D_f, vi->thesis_D_f_err);
    }
    if (!st->have_fit) {
        printf("%s: %s, %d levels, %d configuration%s: %s; %.2f s\n", out, vi->label, s->levels,
               s->configurations, plural, st->fit_note, st->wall_seconds);
    } else {
        const gr_cascade_fit *h = gr_cascade_study_headline(st);
        printf("%s: %s, %d levels, %d configuration%s: D_f = %.3f +- %.3f%s over k L/2pi = %g..%g "
               "(exact average %.3f, D_2 = %.3f; Table 6.2: %s) in %.2f s\n",
               out, vi->label, s->levels, s->configurations, plural, h->D_f, h->D_f_err,
               st->headline_unweighted ? " (unweighted fit)" : "", st->q_min, st->q_max,
               st->fit_exp.D_f, gr_cascade_d2(s), thesis, st->wall_seconds);
        if (st->headline_unweighted) {
            printf("  weighted by S_err: D_f = %.3f +- %.3f, chi2/dof = %.3g; headlined: the "
                   "unweighted fit, because %s\n",
                   st->fit.D_f, st->fit.D_f_err, st->fit.chi2_red, st->headline_why);
        }
    }
    if (p->place) {
        printf("%s: %d discs placed (phi = %.3f, %lld attempts) -> %s/snapshots/snap_000000.xyz\n",
               out, p->placement.n, st->pres.phi, (long long)st->pres.attempts, out);
    }
    printf("wrote %s\n", out);
}

int cmd_cascade(int argc, char **argv)
{
    gr_cascade_study_params sp = {0};
    gr_cascade_settings_default(&sp.s);
    gr_cascade_placement_default(&sp.placement);
    cascade_args args = {.s = sp.s, .variant = "ucp", .seed = sp.s.seed, .th.out = "out/cascade"};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_cascade, argc, argv, &args, &pos);
    if (parsed >= 0 || cli_theory_set_refused(&cli_cmd_cascade, &args.th)) {
        cli_list_free(&args.th.sets);
        return parsed >= 0 ? parsed : EXIT_REFUSED;
    }
    gr_cascade_settings s = args.s;
    s.seed = (unsigned long)args.seed;
    s.fit_q_min = args.fit_min ? args.fit_min : s.fit_q_min;
    s.fit_q_max = args.fit_max ? args.fit_max : s.fit_q_max;
    gr_cascade_placement place = sp.placement;
    const bool do_place = args.place > 0, radius_given = args.radius > 0.0,
               attempts_given = args.max_attempts > 0;
    place.n = do_place ? args.place : place.n;
    place.radius = radius_given ? args.radius : place.radius;
    place.max_attempts = attempts_given ? args.max_attempts : place.max_attempts;
    const char *out = args.th.out, *variant = args.variant, *p_text = args.p;
    const bool force = args.th.force, quiet = args.th.quiet, plots_on = !args.th.no_plots;
    gr_error err = {0};
    if (gr_cascade_variant_parse(variant, &s.variant, &err)) {
        app_error("cascade: --variant: %s", err.message);
        return EXIT_REFUSED;
    }
    if (p_text && s.variant != GR_CASCADE_MEAKIN) {
        app_error("cascade: --p applies to --variant meakin only (meakin1..4 use Table 6.1)");
        return EXIT_REFUSED;
    }
    if (s.variant == GR_CASCADE_MEAKIN && !p_text) {
        app_error("cascade: --variant meakin needs --p p1,p2,p3,p4");
        return EXIT_REFUSED;
    }
    if (p_text && !parse_p(p_text, s.p)) {
        return EXIT_REFUSED;
    }
    if ((radius_given || attempts_given) && !do_place) {
        app_error("cascade: --radius and --max-attempts need --place N");
        return EXIT_REFUSED;
    }
    if (strlen(out) > 900) {
        app_error("cascade: --out %s: path too long", out);
        return EXIT_REFUSED;
    }
    if (gr_cascade_settings_check(&s, &err)) {
        app_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (do_place && gr_cascade_placement_check(&place, s.L, &err)) { /* before any work */
        app_error("%s", err.message);
        return EXIT_REFUSED;
    }
    sp.s = s;
    sp.placement = place;
    sp.place = do_place;
    sp.no_plots = !plots_on;
    gr_error werr = {0};
    if (gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force, &werr)) {
        app_error("%s", werr.message);
        return werr.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    const bool progress = !quiet && app_interactive();
    if (progress) {
        sp.progress = progress_line;
    }
    gr_cascade_study st;
    int rc = gr_cascade_study_run(&sp, &st, &werr);
    if (progress) {
        fputc('\n', stderr);
    }
    if (rc) {
        app_error("%s", werr.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    char plots[600];
    rc = gr_cascade_study_write(out, &sp, &st, plots, sizeof plots, &werr);
    if (rc) {
        app_error("%s", werr.message);
    } else {
        print_result(out, &sp, &st);
    }
    gr_cascade_study_free(&st);
    return rc ? EXIT_FAILED : EXIT_OK;
}
