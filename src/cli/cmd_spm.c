/* granule spm circle|full|predict: the Single Particle Model of thesis sec. 5.2-5.3.
 *
 *   circle   Q(v, l) in a disc (interval) of fixed radius, its collapse under v / l^(1/3) and the
 *            Gaussian tail 5.12 (sec. 5.3.1)
 *   full     the SPM P(v) with l drawn from P_l(l) (a measured table or the fitted form 4.25),
 *            optionally against a Random Force Model run's P(v) (sec. 5.2.3, Fig. 5.10)
 *   predict  alpha (5.29), S and v_A (5.27), the power h of H(v) (5.30-5.31), and the numerical
 *            integral 5.13 against its steepest-descent form 5.26
 *
 * Every mode writes CSV files with commented headers, summary.json and PNG plots into --out, each
 * file atomically (io/files.h), and prints a few result lines on stdout. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "granule/analysis.h"
#include "granule/spm.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

#define MAX_RADII 32
/* C of 4.25 measured for phi = 0.530, L = 0.6 m, eps = 0.1 (thesis sec. 5.3.3) */
#define THESIS_C 121.0
#define THESIS_DF 1.63

/* ------------------------------------------------------------------------------------------- */

static void usage_main(FILE *f)
{
    fprintf(f,
            "usage: granule spm circle|full|predict [options]   (granule spm MODE --help for each)\n\n"
            "The Single Particle Model of thesis sec. 5.2-5.3: one particle starts at rest at the centre\n"
            "of a disc (2D) or interval (1D) of radius l and is driven by the random force until it\n"
            "first reaches the boundary; its velocity is sampled uniformly in time.\n"
            "  circle   Q(v,l) for fixed radii: collapse under v / l^(1/3), Gaussian tail 5.12\n"
            "  full     P(v) with l drawn from P_l(l) (--pl FILE or --df D_f [--C C], eq. 4.25);\n"
            "           --compare-run DIR overlays a Random Force Model run's P(v)\n"
            "  predict  alpha = 6(D_f - 1)/(3 D_f - 1) (5.29), v_A (5.27), H(v) ~ v^h (5.30-5.31)\n"
            "Free flight is sampled exactly; see docs/theory-spm.md for the model, the options, the\n"
            "output files and measured results.\n"
            "Exit status: 0 done, 2 bad input, 1 other failure.\n");
}

#define COMMON_HELP                                                                                          \
    "  --dim 1|2         interval or disc (default 2)\n"                                                      \
    "  --mass M          particle mass, kg (default 3.53e-5, Table 2.2)\n"                                    \
    "  --D D             noise strength, N^2 s (default 1e-8, Table 2.2)\n"                                   \
    "  --walks N         walks (repetitions of the walk) (default %s)\n"                                       \
    "  --step S          sampling interval in units of t_l = (M^2 l^2 / 2D)^(1/3) (default 3e-3)\n"           \
    "  --dt DT           a fixed sampling interval in seconds instead of --step (the thesis' way)\n"          \
    "  --refine K        exact bridge points looked at between samples near the boundary: K levels\n"       \
    "                    of bisection (default 10; 0: look at the samples only)\n"                          \
    "  --batches B       independent batches of walks for the error bars (default 20)\n"                   \
    "  --seed S          random seed (default 1); results are reproducible from it\n"                      \
    "  --bins N          histogram bins (default %d)\n"                                                       \
    "  --out DIR         output folder (default %s)\n"                                                        \
    "  --force           overwrite the results of an earlier run in DIR\n"                                  \
    "  --no-plots        skip the PNG plots\n"                                                               \
    "  --quiet           no progress line\n"

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
            COMMON_HELP
            "Writes q.csv, q_radii.csv, summary.json, q_collapse.png, q_raw.png.\n",
            "20000 per radius", 90, "out/spm-circle");
}

static void usage_full(FILE *f)
{
    fprintf(f,
            "usage: granule spm full (--pl FILE | --df D_f [--C C]) [--compare-run DIR] [options]\n"
            "       granule spm full --compare-run DIR [options]   (P_l from DIR/freepath.csv)\n\n"
            "The SPM of thesis sec. 5.2.3: every walk draws its radius l from the free-path\n"
            "distribution P_l(l); the velocity distribution P(v) of one component is sampled\n"
            "uniformly in time over all walks (integral identity 5.10).\n"
            "  --pl FILE         measured P_l: CSV with a header naming columns l (m) and P (or\n"
            "                    density; optional P_err or density_error); '#' lines are comments;\n"
            "                    or a run's freepath.csv (l_over_d: diameters, see --diameter)\n"
            "  --diameter D      particle diameter, m, for l_over_d (default: the run folder's)\n"
            "  --df D_f          use the fitted form 4.25, P_l ~ l^(D_f-2) exp(-C l^(D_f-1))\n"
            "  --C C             its constant, m^-(D_f-1) (default 121: phi = 0.530, thesis sec. 5.3.3)\n"
            "  --tail-from L     fit 4.25 to the --pl table for l >= L, m (default: the longest 10%%\n"
            "                    of the paths)\n"
            "  --weight time|walk  sample uniformly in time (default, the thesis' simulation) or weigh\n"
            "                    every walk equally (5.10 with Q normalised per walk)\n"
            "  --tilt K          importance sampling of long free paths (default 1: none; e.g. 4\n"
            "                    reaches several more decades of the tail)\n"
            "  --vmax V          histogram range of |v|, m/s (default: from P_l and --walks)\n"
            "  --fit-from V      tail fits of P(v) over v >= V, m/s (default 3 v_rms of the SPM)\n"
            "  --compare-run DIR a granule run folder: P(v) per component from DIR/snapshots/snap_*.xyz\n"
            "                    (frames after the warm-up), compared with the SPM; M, D and dim\n"
            "                    default to the run's\n"
            "  --t-from T        use snapshots with Time >= T s (default: the run's warm-up)\n"
            "  --compare-from V  fit the vertical scale over v >= V, m/s (default 2 v_rms of the run)\n"
            "  --z-max Z         bins agree when |P_rfm - k P_spm| <= Z sigma (default 3)\n"
            COMMON_HELP
            "Writes p_v.csv, pl.csv, compare.csv (with --compare-run), summary.json, p_v.png, pl.png.\n",
            "200000", 100, "out/spm-full");
}

static void usage_predict(FILE *f)
{
    fprintf(f,
            "usage: granule spm predict (--df D_f | --pl FILE) [--C C] [--b B] [options]\n\n"
            "The asymptotic tail of P(v) from the SPM integral identity (thesis sec. 5.3.2):\n"
            "  alpha = 6 (D_f - 1) / (3 D_f - 1)                       (5.29)\n"
            "  S = B (gamma/2F)^(2/(gamma+2)) + C (2F/gamma)^(gamma/(gamma+2)), v_A = S^(-1/alpha),\n"
            "  F = B/C, gamma = 3 (D_f - 1), P(v) ~ v^h exp(-S |v|^alpha)  (5.27)\n"
            "  h = 3 (D_f - 1) / (3 D_f - 1)                            (5.30-5.31)\n"
            "  --df D_f          fractal dimension (e.g. 1.63)\n"
            "  --pl FILE         or fit 4.25 to a measured P_l table (columns l, P; or a run's\n"
            "                    freepath.csv, columns l_over_d, density) for D_f and C\n"
            "  --diameter D      particle diameter, m, for l_over_d (default: the run folder's)\n"
            "  --tail-from L     fit over l >= L, m (default: the longest 10%% of the paths)\n"
            "  --C C             C of 4.25, m^-(D_f-1) (default 121 with --df: thesis sec. 5.3.3)\n"
            "  --b B             Q's Gaussian tail coefficient of 5.12 (default 0.98; granule spm\n"
            "                    circle measures it); B = b (M^2/2D)^(2/3)\n"
            "  --mass M, --D D   as for the other modes (Table 2.2 defaults)\n"
            "  --vmax V          range of the tabulated integral 5.13, m/s (default 20 v_A)\n"
            "  --out DIR         output folder (default out/spm-predict); --force, --no-plots\n"
            "Writes prediction.csv (5.13 integrated numerically against 5.26), summary.json,\n"
            "prediction.png.\n");
}

/* ------------------------------------------------------------------------------------------- */

typedef struct options {
    gr_spm_settings s;
    const char *out;
    bool force, quiet, plots;
    bool mass_set, D_set, dim_set;
    int bins;
} options;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static bool integer_option(const char *opt, double x, double lo, double hi)
{
    if (!(x >= lo && x <= hi) || x != floor(x)) {
        cli_error("spm: %s must be an integer in [%.0f, %.0f], got %g", opt, lo, hi, x);
        return false;
    }
    return true;
}

/* Options shared by the modes. Returns 1 if argv[*i] was one (consuming its value), 0 if not,
 * -1 after printing an error. */
static int common_option(int argc, char **argv, int *i, options *o)
{
    const char *a = argv[*i];
    if (!strcmp(a, "--force")) {
        o->force = true;
        return 1;
    }
    if (!strcmp(a, "--quiet")) {
        o->quiet = true;
        return 1;
    }
    if (!strcmp(a, "--no-plots")) {
        o->plots = false;
        return 1;
    }
    static const char *const with_value[] = {"--out", "--dim", "--mass", "--D", "--walks", "--step", "--dt",
                                             "--refine", "--batches", "--seed", "--bins"};
    bool known = false;
    for (size_t k = 0; k < sizeof with_value / sizeof with_value[0]; k++) {
        known |= !strcmp(a, with_value[k]);
    }
    if (!known) {
        return 0;
    }
    if (*i + 1 >= argc) {
        cli_error("spm: %s needs a value", a);
        return -1;
    }
    const char *v = argv[++*i];
    if (!strcmp(a, "--out")) {
        if (strlen(v) >= 1000) {
            cli_error("spm: --out %s: path too long", v);
            return -1;
        }
        o->out = v;
        return 1;
    }
    double x;
    if (!cli_number(a, v, &x)) {
        return -1;
    }
    if (!strcmp(a, "--dim")) {
        if (x != 1.0 && x != 2.0) {
            cli_error("spm: --dim must be 1 or 2, got %s", v);
            return -1;
        }
        o->s.dim = (int)x;
        o->dim_set = true;
    } else if (!strcmp(a, "--mass")) {
        o->s.mass = x;
        o->mass_set = true;
    } else if (!strcmp(a, "--D")) {
        o->s.D = x;
        o->D_set = true;
    } else if (!strcmp(a, "--walks")) {
        if (!integer_option(a, x, 2, 1e12)) {
            return -1;
        }
        o->s.walks = (int64_t)x;
    } else if (!strcmp(a, "--step")) {
        o->s.step = x;
    } else if (!strcmp(a, "--dt")) {
        o->s.dt = x;
    } else if (!strcmp(a, "--refine")) {
        if (!integer_option(a, x, 0, 30)) {
            return -1;
        }
        o->s.refine = (int)x;
    } else if (!strcmp(a, "--batches")) {
        if (!integer_option(a, x, 2, 10000)) {
            return -1;
        }
        o->s.batches = (int)x;
    } else if (!strcmp(a, "--seed")) {
        if (!integer_option(a, x, 0, 9007199254740992.0)) {
            return -1;
        }
        o->s.seed = (uint64_t)x;
    } else if (!strcmp(a, "--bins")) {
        if (!integer_option(a, x, 4, 100000)) {
            return -1;
        }
        o->bins = (int)x;
    }
    return 1;
}

/* Parse the value of a mode option as a number (the option is argv[*i]). */
static bool value_number(int argc, char **argv, int *i, double *x)
{
    if (*i + 1 >= argc) {
        cli_error("spm: %s needs a value", argv[*i]);
        return false;
    }
    const char *opt = argv[*i];
    return cli_number(opt, argv[++*i], x);
}

static void unknown(const char *mode, const char *a)
{
    cli_error("spm %s: unknown option %s (granule spm %s --help lists them)", mode, a, mode);
}

typedef struct progress_state {
    const char *label;
    int part, parts;
    double t0;
    bool on;
} progress_state;

static void progress(double fraction, void *user)
{
    progress_state *p = user;
    double done = ((double)p->part + fraction) / (double)p->parts, wall = now() - p->t0;
    int eta = done > 0.0 ? (int)(wall * (1.0 - done) / done + 0.5) : 0;
    fprintf(stderr, "\r%s %3.0f%%  ETA %d:%02d:%02d   ", p->label, 100.0 * done, eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

static void progress_end(progress_state *p)
{
    if (p->on) {
        fprintf(stderr, "\r%*s\r", 60, "");
        fflush(stderr);
    }
}

static int exit_code(const gr_error *err) { return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED; }

static void csv_head(gr_file *f, const char *what, const options *o)
{
    const gr_spm_settings *s = &o->s;
    gr_file_note(f, "# granule %s (%s) spm: %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f, "# dim %d, M = %g kg, D = %g N^2 s, %s = %g, refine %d, walks %lld, batches %d, seed %llu\n", s->dim,
            s->mass, s->D, s->dt > 0.0 ? "dt (s)" : "step (t_l)", s->dt > 0.0 ? s->dt : s->step, s->refine,
            (long long)s->walks, s->batches, (unsigned long long)s->seed);
}

static void json_settings(cJSON *j, const options *o)
{
    const gr_spm_settings *s = &o->s;
    cJSON *st = cJSON_AddObjectToObject(j, "settings");
    cJSON_AddNumberToObject(st, "dim", s->dim);
    cJSON_AddNumberToObject(st, "mass", s->mass);
    cJSON_AddNumberToObject(st, "D", s->D);
    cJSON_AddNumberToObject(st, "step", s->step);
    cJSON_AddNumberToObject(st, "dt", s->dt);
    cJSON_AddNumberToObject(st, "refine", s->refine);
    cJSON_AddNumberToObject(st, "walks", (double)s->walks);
    cJSON_AddNumberToObject(st, "batches", s->batches);
    cJSON_AddNumberToObject(st, "seed", (double)s->seed);
    cJSON_AddNumberToObject(st, "bins", o->bins);
}

static void json_num(cJSON *o, const char *key, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, key, v);
    } else {
        cJSON_AddNullToObject(o, key);
    }
}

static cJSON *json_head(const char *mode)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "mode", mode);
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    return j;
}

static void json_stats(cJSON *o, const gr_spm_walk_stats *st)
{
    cJSON_AddNumberToObject(o, "walks", (double)st->walks);
    cJSON_AddNumberToObject(o, "samples", (double)st->steps);
    json_num(o, "exit_time_mean_t_l", st->exit_time_mean);
    json_num(o, "exit_time_err_t_l", st->exit_time_err);
    json_num(o, "w2_time_mean", st->w2_time_mean);
    json_num(o, "exit_speed2_over_exit_time", st->exit_speed2_mean / st->exit_time_mean);
    cJSON_AddNumberToObject(o, "bridge_points", (double)st->bridge_points);
    cJSON_AddNumberToObject(o, "exits_found_by_refinement", (double)st->bridge_exits);
}

/* Draw a plot; on failure note why in the summary's plot_notes. */
static void plot(const options *o, cJSON *j, const char *png, const char *body)
{
    cJSON *plots = cJSON_GetObjectItem(j, "plots");
    if (!o->plots) {
        return;
    }
    char note[300];
    if (gr_plot_script(o->out, png, body, note, sizeof note) == 0) {
        cJSON_AddItemToArray(plots, cJSON_CreateString(png));
    } else {
        cJSON *notes = cJSON_GetObjectItem(j, "plot_notes");
        if (!notes) {
            notes = cJSON_AddArrayToObject(j, "plot_notes");
        }
        cJSON_AddItemToArray(notes, cJSON_CreateString(note));
    }
}

static int settings_ok(const options *o, gr_error *err)
{
    return gr_spm_settings_check(&o->s, err);
}

/* ------------------------------------------------------------------------------------------- *
 * circle */

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
    options o = {.out = "out/spm-circle", .plots = true, .bins = 90};
    gr_spm_settings_default(&o.s);
    double radii[MAX_RADII] = {0.0036, 0.01, 0.02, 0.04}, wmax = 4.5, fit_from = 2.5;
    int nr = 4;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage_circle(stdout);
            return EXIT_OK;
        }
        int c = common_option(argc, argv, &i, &o);
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
            if (parse_list(argv[++i], radii, MAX_RADII, &nr)) {
                return EXIT_REFUSED;
            }
        } else if (!strcmp(a, "--wmax") || !strcmp(a, "--fit-from")) {
            double x;
            if (!value_number(argc, argv, &i, &x)) {
                return EXIT_REFUSED;
            }
            if (!strcmp(a, "--wmax")) {
                wmax = x;
            } else {
                fit_from = x;
            }
        } else {
            unknown("circle", a);
            return EXIT_REFUSED;
        }
    }
    gr_error err = {0};
    if (settings_ok(&o, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (!(wmax > 0.0 && wmax <= 100.0) || !(fit_from >= 0.0 && fit_from < wmax)) {
        cli_error("spm circle: need 0 < --wmax <= 100 and 0 <= --fit-from < --wmax, got %g and %g", wmax, fit_from);
        return EXIT_REFUSED;
    }
    for (int r = 0; r < nr; r++) {
        double tl = gr_spm_time_scale(&o.s, radii[r]);
        if (o.s.dt > 0.0 && o.s.dt > 10.0 * tl) {
            cli_error("spm circle: --dt %g s is %g t_l for the radius %g m (t_l = %g s); use a smaller --dt", o.s.dt,
                      o.s.dt / tl, radii[r], tl);
            return EXIT_REFUSED;
        }
    }
    if (gr_output_dir_prepare(o.out, o.force, &err)) {
        cli_error("%s", err.message);
        return exit_code(&err);
    }

    double t0 = now();
    progress_state ps = {.label = "spm circle", .parts = nr, .t0 = t0, .on = !o.quiet && cli_interactive()};
    if (ps.on) {
        o.s.progress = progress;
        o.s.user = &ps;
    }
    gr_spm_q q[MAX_RADII];
    int done = 0, rc = GR_OK;
    for (int r = 0; r < nr && !rc; r++) {
        ps.part = r;
        rc = gr_spm_circle(&o.s, radii[r], r, o.bins, wmax, &q[r], &err);
        if (!rc) {
            done++;
        }
    }
    progress_end(&ps);
    if (rc) {
        for (int r = 0; r < done; r++) {
            gr_spm_q_free(&q[r]);
        }
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    double wall = now() - t0;

    /* pooled: batch b of every radius into batch b (same scaled bins) */
    gr_spm_q pooled = {0};
    rc = gr_spm_dist_init(&pooled.q, o.s.batches, o.bins, wmax, &err);
    for (int r = 0; r < nr && !rc; r++) {
        for (int b = 0; b < o.s.batches && !rc; b++) {
            rc = gr_histogram_merge(&pooled.q.batch[b], &q[r].q.batch[b], &err);
        }
        if (!rc) {
            rc = gr_histogram_merge(&pooled.q.all, &q[r].q.all, &err);
        }
    }
    gr_spm_tail_fit fits[MAX_RADII], pfit = {0};
    gr_spm_collapse col[MAX_RADII];
    char fit_note[MAX_RADII][sizeof(((gr_error *)0)->message)];
    const double min_count = 20.0;
    for (int r = 0; r < nr && !rc; r++) {
        fit_note[r][0] = 0;
        gr_error e2 = {0};
        if (gr_spm_q_tail_fit(&q[r], fit_from, min_count, &fits[r], &e2)) {
            snprintf(fit_note[r], sizeof fit_note[r], "%s", e2.message);
            fits[r].b = fits[r].b_err = fits[r].A = fits[r].chi2_red = fits[r].beta = fits[r].beta_err = fits[r].wto = (double)NAN;
        }
        memset(&col[r], 0, sizeof col[r]);
        if (r > 0 && gr_spm_q_collapse(&q[0], &q[r], min_count, 2000, &col[r], &e2)) {
            col[r].chi2_red = col[r].p_value = col[r].p_chi2 = (double)NAN;
        }
    }
    char pooled_note[sizeof(((gr_error *)0)->message)] = "";
    if (!rc) {
        gr_error e2 = {0};
        if (gr_spm_q_tail_fit(&pooled, fit_from, min_count, &pfit, &e2)) {
            snprintf(pooled_note, sizeof pooled_note, "%s", e2.message);
            pfit.b = pfit.b_err = pfit.A = pfit.chi2_red = (double)NAN;
        }
    }

    /* q.csv */
    gr_file f;
    if (!rc) {
        rc = gr_file_open(&f, o.out, "q.csv", &err);
    }
    if (!rc) {
        csv_head(&f, "Q(v,l) of sec. 5.3.1, one velocity component, sampled uniformly in time", &o);
        gr_file_note(&f, "# w = |v| / u_l, u_l = (2 D l / M^2)^(1/3); Q_scaled = u_l Q(v,l) (density of the signed scaled\n"
                     "# component: collapses under v / l^(1/3)); Q in s/m; errors from the spread between batches\n"
                     "# (_poisson: the sqrt(X) error of App. A.1, too small because samples of one walk correlate)\n");
        fprintf(f.f, "radius_index,radius,w_lo,w_hi,w,v,samples,Q_scaled,Q_scaled_err,Q_scaled_err_poisson,Q,Q_err\n");
        for (int r = 0; r < nr; r++) {
            const gr_histogram *h = &q[r].q.all;
            for (int i = 0; i < h->nbins; i++) {
                double w = gr_histogram_center(h, i), p = gr_spm_dist_density(&q[r].q, i),
                       e = gr_spm_dist_error(&q[r].q, i);
                fprintf(f.f, "%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.6g,%.4g\n", r, radii[r],
                        gr_histogram_lower(h, i), gr_histogram_upper(h, i), w, w * q[r].u, h->count[i], p, e,
                        gr_spm_dist_poisson_error(&q[r].q, i), p / q[r].u, e / q[r].u);
            }
        }
        rc = gr_file_commit(&f, &err);
    }
    if (!rc) {
        rc = gr_file_open(&f, o.out, "q_radii.csv", &err);
    }
    if (!rc) {
        csv_head(&f, "per radius: scales, first-passage time, Gaussian tail fit (5.12), collapse against the first radius", &o);
        gr_file_note(&f, "# u_l in m/s, t_l in s, tau = sampling interval / t_l; exit_time and w2 (<w^2> per component in\n"
                     "# time) in the walk's units; b of Q ~ A exp(-b w^2) over w >= %g (thesis: 0.98); beta: free-exponent fit;\n"
                     "# chi2 between the scaled Q of this radius and of the first one over bins with >= %g samples in both\n",
                fit_from, min_count);
        fprintf(f.f, "radius,u_l,t_l,tau,walks,exit_time,exit_time_err,w2,b,b_err,A,fit_chi2_red,beta,beta_err,"
                     "collapse_chi2,collapse_dof,collapse_p\n");
        for (int r = 0; r < nr; r++) {
            const gr_spm_walk_stats *st = &q[r].stats;
            fprintf(f.f, "%.6g,%.6g,%.6g,%.6g,%lld,%.6g,%.3g,%.6g,%.5g,%.3g,%.5g,%.3g,%.4g,%.3g,%.5g,%d,%.4g\n", radii[r],
                    q[r].u, q[r].t_scale, q[r].tau, (long long)st->walks, st->exit_time_mean, st->exit_time_err,
                    st->w2_time_mean, fits[r].b, fits[r].b_err, fits[r].A, fits[r].chi2_red, fits[r].beta,
                    fits[r].beta_err, r ? col[r].chi2 : 0.0, r ? col[r].dof : 0, r ? col[r].p_value : 1.0);
        }
        rc = gr_file_commit(&f, &err);
    }

    /* summary.json */
    cJSON *j = json_head("circle");
    json_settings(j, &o);
    cJSON_AddNumberToObject(j, "wmax", wmax);
    cJSON_AddNumberToObject(j, "fit_from", fit_from);
    cJSON *ra = cJSON_AddArrayToObject(j, "radii");
    for (int r = 0; r < nr && !rc; r++) {
        cJSON *x = cJSON_CreateObject();
        cJSON_AddNumberToObject(x, "radius", radii[r]);
        cJSON_AddNumberToObject(x, "u_l", q[r].u);
        cJSON_AddNumberToObject(x, "t_l", q[r].t_scale);
        cJSON_AddNumberToObject(x, "tau_over_t_l", q[r].tau);
        json_stats(x, &q[r].stats);
        cJSON *tf = cJSON_AddObjectToObject(x, "tail_fit");
        json_num(tf, "b", fits[r].b);
        json_num(tf, "b_err", fits[r].b_err);
        json_num(tf, "A", fits[r].A);
        json_num(tf, "chi2_red", fits[r].chi2_red);
        json_num(tf, "w_to", fits[r].wto);
        json_num(tf, "free_exponent", fits[r].beta);
        json_num(tf, "free_exponent_err", fits[r].beta_err);
        if (fit_note[r][0]) {
            cJSON_AddStringToObject(tf, "note", fit_note[r]);
        }
        /* B of 5.12-5.13 in SI units for this b */
        json_num(tf, "B", gr_spm_B(&o.s, fits[r].b));
        if (r > 0) {
            cJSON *c = cJSON_AddObjectToObject(x, "collapse_vs_first");
            json_num(c, "chi2", col[r].chi2);
            cJSON_AddNumberToObject(c, "dof", col[r].dof);
            json_num(c, "chi2_red", col[r].chi2_red);
            json_num(c, "p_value_permutation", col[r].p_value);
            cJSON_AddNumberToObject(c, "permutations", col[r].permutations);
            json_num(c, "p_value_chi2_law", col[r].p_chi2);
            json_num(c, "max_abs_z", col[r].max_abs_z);
        }
        cJSON_AddItemToArray(ra, x);
    }
    cJSON *pj = cJSON_AddObjectToObject(j, "pooled_tail_fit");
    json_num(pj, "b", pfit.b);
    json_num(pj, "b_err", pfit.b_err);
    json_num(pj, "A", pfit.A);
    json_num(pj, "chi2_red", pfit.chi2_red);
    json_num(pj, "w_from", fit_from);
    json_num(pj, "w_to", pfit.wto);
    json_num(pj, "free_exponent", pfit.beta);
    json_num(pj, "free_exponent_err", pfit.beta_err);
    json_num(pj, "B", gr_spm_B(&o.s, pfit.b));
    cJSON_AddNumberToObject(pj, "thesis_b", GR_SPM_THESIS_B_COEF);
    if (pooled_note[0]) {
        cJSON_AddStringToObject(pj, "note", pooled_note);
    }
    cJSON_AddNumberToObject(j, "wall_seconds", wall);
    cJSON_AddArrayToObject(j, "plots");

    if (!rc) {
        /* plots: the collapse and the raw Q(v, l) */
        char body[8192], *p = body;
        size_t left = sizeof body;
        int k = snprintf(p, left,
                         "set title 'Q(v,l) rescaled: collapse under v / l^{1/3} (sec. 5.3.1), %dD'\n"
                         "set xlabel 'w = |v| / u_l,  u_l = (2Dl/M^2)^{1/3}'\nset ylabel 'u_l Q(v,l)'\n"
                         "set logscale y\nset format y '10^{%%L}'\nset key top right\n"
                         "A = %.10g\nb = %.10g\nbt = %.10g\n"
                         "plot ",
                         o.s.dim, isfinite(pfit.A) ? pfit.A : 1.0, isfinite(pfit.b) ? pfit.b : 1.0, GR_SPM_THESIS_B_COEF);
        p += k;
        left -= (size_t)k;
        for (int r = 0; r < nr; r++) {
            k = snprintf(p, left, "'q.csv' using 5:(($1==%d && $8>0) ? $8 : 1/0):9 with yerrorbars pt 7 ps 0.5 title 'l = %g m', ",
                         r, radii[r]);
            p += k;
            left -= (size_t)k;
        }
        snprintf(p, left,
                 "[x=%g:%g] A*exp(-b*x**2) lw 2 lc rgb 'black' title sprintf('pooled fit A exp(-%%.3f w^2)', b), "
                 "[x=%g:%g] A*exp(-bt*x**2) dt 2 lc rgb 'black' title 'b = 0.98 (5.12)'\n",
                 fit_from, wmax, fit_from, wmax);
        plot(&o, j, "q_collapse.png", body);
        p = body;
        left = sizeof body;
        k = snprintf(p, left,
                     "set title 'Q(v,l) for fixed radii (sec. 5.3.1), %dD'\nset xlabel '|v| (m/s)'\nset ylabel 'Q(v,l) (s/m)'\n"
                     "set logscale y\nset format y '10^{%%L}'\nset key top right\nplot ",
                     o.s.dim);
        p += k;
        left -= (size_t)k;
        for (int r = 0; r < nr; r++) {
            k = snprintf(p, left, "'q.csv' using 6:(($1==%d && $11>0) ? $11 : 1/0) with linespoints pt 7 ps 0.4 title 'l = %g m'%s",
                         r, radii[r], r + 1 < nr ? ", " : "\n");
            p += k;
            left -= (size_t)k;
        }
        plot(&o, j, "q_raw.png", body);
        rc = gr_json_write(o.out, "summary.json", j, &err);
    }
    cJSON_Delete(j);
    if (!rc) {
        printf("%s: Q(v,l) for %d radii, %dD, %lld walks each, %.1f s\n", o.out, nr, o.s.dim, (long long)o.s.walks, wall);
        for (int r = 0; r < nr; r++) {
            printf("  l = %g m: u_l = %.4g m/s, <T> = %.4f +- %.4f t_l, <w^2> = %.4f, b = %.4f +- %.4f (w >= %g)", radii[r],
                   q[r].u, q[r].stats.exit_time_mean, q[r].stats.exit_time_err, q[r].stats.w2_time_mean, fits[r].b,
                   fits[r].b_err, fit_from);
            if (r > 0) {
                printf(", collapse vs l = %g: chi2/dof = %.3g (%d bins, p = %.3g)", radii[0], col[r].chi2_red, col[r].dof,
                       col[r].p_value);
            }
            printf("\n");
        }
        printf("  pooled Gaussian tail (5.12): b = %.4f +- %.4f (thesis 0.98), i.e. B = %.4g s^2 m^-4/3; free exponent %.3f +- %.3f\n",
               pfit.b, pfit.b_err, gr_spm_B(&o.s, pfit.b), pfit.beta, pfit.beta_err);
    }
    for (int r = 0; r < nr; r++) {
        gr_spm_q_free(&q[r]);
    }
    gr_spm_q_free(&pooled);
    if (rc) {
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    return EXIT_OK;
}

/* ------------------------------------------------------------------------------------------- *
 * full */

/* Mass, D, dim, warm-up and particle diameter from a run folder's summary.json (any may stay
 * unknown: NAN or 0). */
static void run_scene(const char *dir, double *mass, double *D, int *dim, double *warmup, double *diameter)
{
    *mass = *D = *warmup = *diameter = (double)NAN;
    *dim = 0;
    gr_error err = {0};
    cJSON *j = gr_summary_read(dir, &err);
    if (!j) {
        return;
    }
    cJSON *sc = cJSON_GetObjectItem(j, "scene");
    cJSON *x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "mass");
    if (cJSON_IsNumber(x)) {
        *mass = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "dim");
    if (cJSON_IsNumber(x)) {
        *dim = x->valueint;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "noise"), "D");
    if (cJSON_IsNumber(x)) {
        *D = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "run"), "warmup");
    if (cJSON_IsNumber(x)) {
        *warmup = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "radius");
    if (cJSON_IsNumber(x)) {
        *diameter = 2.0 * x->valuedouble;
    }
    cJSON_Delete(j);
}

/* The particle diameter for a P_l file in diameters: --diameter, else the run folder's around it. */
static double pl_diameter(const char *pl_path, double given)
{
    if (given > 0.0) {
        return given;
    }
    char dir[1300];
    snprintf(dir, sizeof dir, "%.1200s", pl_path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        *slash = 0;
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    double m, D, w, d;
    int dim;
    run_scene(dir, &m, &D, &dim, &w, &d);
    return d > 0.0 ? d : 0.0;
}

/* A0 v^h exp(-S v^alpha) with the predicted alpha fixed: ln P - ... linear in (1, ln v, v^alpha);
 * q = (ln A0, h, S) */
static double tail_531(double v, const double *q, double *g, void *user)
{
    double alpha = *(const double *)user, va = pow(v, alpha), lv = log(v);
    if (g) {
        g[0] = 1.0;
        g[1] = lv;
        g[2] = -va;
    }
    return q[0] + q[1] * lv - q[2] * va;
}

typedef struct pv_fit_par {
    double from, alpha, S, h;
    double chi2_red; /* of the fit to all batches (the first call) */
    int points;
    int calls;
} pv_fit_par;

static int pv_select(const pv_fit_par *q, const double *x, const double *p, const double *e, const double *count, int n,
                     double *vx, double *vy, double *vs)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (x[i] >= q->from && p[i] > 0.0 && e[i] > 0.0 && isfinite(e[i]) && count[i] > 0.0) {
            vx[m] = x[i];
            vy[m] = p[i];
            vs[m] = e[i];
            m++;
        }
    }
    return m;
}

/* A exp(-(v/v_A)^alpha): out = (A, v_A, alpha) */
static int pv_stretched(const double *x, const double *p, const double *e, const double *count, int n, double *out, void *user)
{
    pv_fit_par *q = user;
    double *vx = malloc(sizeof(double) * (size_t)n * 3);
    if (!vx) {
        return 1;
    }
    double *vy = vx + n, *vs = vy + n;
    int m = pv_select(q, x, p, e, count, n, vx, vy, vs);
    gr_fit f;
    gr_error e2 = {0};
    double p0[3] = {m ? vy[0] * exp(1.0) : 1.0, m ? vx[0] : 1.0, 1.0};
    int rc = m >= 4 ? gr_fit_stretched_exp(vx, vy, vs, m, p0, &f, &e2) : 1;
    free(vx);
    if (rc) {
        return 1;
    }
    for (int k = 0; k < 3; k++) {
        out[k] = f.p[k];
    }
    if (q->calls++ == 0) {
        q->chi2_red = f.chi2_red;
        q->points = m;
    }
    return 0;
}

/* ln P = ln A0 + h ln v - S v^alpha with alpha fixed: out = (ln A0, h, S) */
static int pv_531(const double *x, const double *p, const double *e, const double *count, int n, double *out, void *user)
{
    pv_fit_par *q = user;
    double *vx = malloc(sizeof(double) * (size_t)n * 3);
    if (!vx) {
        return 1;
    }
    double *vy = vx + n, *vs = vy + n;
    int m = pv_select(q, x, p, e, count, n, vx, vy, vs);
    for (int i = 0; i < m; i++) {
        vs[i] /= vy[i];
        vy[i] = log(vy[i]);
    }
    gr_fit f;
    gr_error e2 = {0};
    double q0[3] = {m ? vy[0] + q->S * pow(vx[0], q->alpha) - q->h * log(vx[0]) : 0.0, q->h, q->S};
    int rc = m >= 4 ? gr_fit_nonlinear(tail_531, &q->alpha, vx, vy, vs, m, 3, q0, &f, &e2) : 1;
    free(vx);
    if (rc) {
        return 1;
    }
    for (int k = 0; k < 3; k++) {
        out[k] = f.p[k];
    }
    if (q->calls++ == 0) {
        q->chi2_red = f.chi2_red;
        q->points = m;
    }
    return 0;
}

static int cmd_full(int argc, char **argv)
{
    options o = {.out = "out/spm-full", .plots = true, .bins = 100};
    gr_spm_settings_default(&o.s);
    o.s.walks = 200000;
    const char *pl_path = NULL, *run_dir = NULL;
    double df = (double)NAN, C = (double)NAN, tail_from = 0.0, vmax = (double)NAN, fit_from = (double)NAN, t_from = (double)NAN,
           compare_from = (double)NAN, z_max = 3.0, diameter = (double)NAN;
    bool weight_time = true;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage_full(stdout);
            return EXIT_OK;
        }
        int c = common_option(argc, argv, &i, &o);
        if (c < 0) {
            return EXIT_REFUSED;
        }
        if (c > 0) {
            continue;
        }
        if (!strcmp(a, "--pl") || !strcmp(a, "--compare-run") || !strcmp(a, "--weight")) {
            if (i + 1 >= argc) {
                cli_error("spm: %s needs a value", a);
                return EXIT_REFUSED;
            }
            const char *v = argv[++i];
            if (!strcmp(a, "--pl")) {
                pl_path = v;
            } else if (!strcmp(a, "--compare-run")) {
                run_dir = v;
            } else if (!strcmp(v, "time") || !strcmp(v, "walk")) {
                weight_time = !strcmp(v, "time");
            } else {
                cli_error("spm full: --weight must be time or walk, got %s", v);
                return EXIT_REFUSED;
            }
            continue;
        }
        double x;
        static const char *const nums[] = {"--df", "--C", "--tail-from", "--vmax", "--fit-from", "--t-from",
                                           "--compare-from", "--z-max", "--tilt", "--diameter"};
        bool known = false;
        for (size_t k = 0; k < sizeof nums / sizeof nums[0]; k++) {
            known |= !strcmp(a, nums[k]);
        }
        if (!known) {
            unknown("full", a);
            return EXIT_REFUSED;
        }
        if (!value_number(argc, argv, &i, &x)) {
            return EXIT_REFUSED;
        }
        if (!strcmp(a, "--df")) {
            df = x;
        } else if (!strcmp(a, "--C")) {
            C = x;
        } else if (!strcmp(a, "--tail-from")) {
            tail_from = x;
        } else if (!strcmp(a, "--vmax")) {
            vmax = x;
        } else if (!strcmp(a, "--fit-from")) {
            fit_from = x;
        } else if (!strcmp(a, "--t-from")) {
            t_from = x;
        } else if (!strcmp(a, "--compare-from")) {
            compare_from = x;
        } else if (!strcmp(a, "--z-max")) {
            z_max = x;
        } else if (!strcmp(a, "--diameter")) {
            diameter = x;
        } else {
            o.s.tilt = x;
        }
    }
    char auto_pl[1200];
    if (!pl_path && isnan(df) && run_dir) {
        /* Fig. 5.10: the run's own free paths (the freepath observable) */
        snprintf(auto_pl, sizeof auto_pl, "%s/freepath.csv", run_dir);
        FILE *probe = fopen(auto_pl, "r");
        if (!probe) {
            cli_error("spm full: %s has no freepath.csv (run it with [analysis] observables = freepath); give --pl FILE or --df D_f",
                      run_dir);
            return EXIT_REFUSED;
        }
        fclose(probe);
        pl_path = auto_pl;
    }
    if ((pl_path != NULL) == !isnan(df)) {
        cli_error("spm full: give either --pl FILE or --df D_f");
        return EXIT_REFUSED;
    }
    if (!isnan(diameter) && !(diameter > 0.0 && isfinite(diameter))) {
        cli_error("spm full: --diameter must be > 0 m, got %g", diameter);
        return EXIT_REFUSED;
    }
    if (pl_path && !isnan(C)) {
        cli_error("spm full: --C belongs to --df (the fitted form 4.25), not to --pl");
        return EXIT_REFUSED;
    }
    if (!isnan(vmax) && !(vmax > 0.0 && isfinite(vmax))) {
        cli_error("spm full: --vmax must be > 0 m/s, got %g", vmax);
        return EXIT_REFUSED;
    }
    if ((!isnan(fit_from) && !(fit_from >= 0.0)) || (!isnan(t_from) && !isfinite(t_from)) ||
        (!isnan(compare_from) && !(compare_from >= 0.0)) || !(z_max > 0.0)) {
        cli_error("spm full: --fit-from and --compare-from must be >= 0, --t-from finite, --z-max > 0");
        return EXIT_REFUSED;
    }
    if ((!isnan(t_from) || !isnan(compare_from)) && !run_dir) {
        cli_error("spm full: --t-from and --compare-from need --compare-run DIR");
        return EXIT_REFUSED;
    }
    double run_mass = (double)NAN, run_D = (double)NAN, warmup = (double)NAN, run_d = (double)NAN;
    int run_dim = 0;
    if (run_dir) {
        run_scene(run_dir, &run_mass, &run_D, &run_dim, &warmup, &run_d);
        if (!o.mass_set && run_mass > 0.0) {
            o.s.mass = run_mass;
        }
        if (!o.D_set && run_D > 0.0) {
            o.s.D = run_D;
        }
        if (!o.dim_set && (run_dim == 1 || run_dim == 2)) {
            o.s.dim = run_dim;
        }
        if (isnan(t_from)) {
            t_from = warmup >= 0.0 ? warmup : 0.0;
        }
    }
    gr_error err = {0};
    if (settings_ok(&o, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    gr_spm_pl pl;
    gr_spm_pl_fit plfit = {0};
    bool have_plfit = false;
    char plfit_note[sizeof(((gr_error *)0)->message)] = "";
    if (pl_path) {
        if (gr_spm_pl_load(&pl, pl_path, pl_diameter(pl_path, isnan(diameter) ? 0.0 : diameter), &err)) {
            cli_error("%s%s", err.message, strstr(err.message, "diameter") ? " (give --diameter D in m)" : "");
            return exit_code(&err);
        }
        gr_error e2 = {0};
        have_plfit = gr_spm_pl_fit_tail(&pl, tail_from, &plfit, &e2) == 0;
        if (!have_plfit) {
            snprintf(plfit_note, sizeof plfit_note, "%s", e2.message);
        }
    } else {
        if (isnan(C)) {
            C = THESIS_C;
        }
        if (gr_spm_pl_fitted(&pl, df, C, &err)) {
            cli_error("%s", err.message);
            return EXIT_REFUSED;
        }
    }
    double pred_df = pl_path ? (have_plfit ? plfit.df : (double)NAN) : df, pred_C = pl_path ? (have_plfit ? plfit.C : (double)NAN) : C;
    gr_spm_prediction pred;
    bool have_pred = isfinite(pred_df) && gr_spm_predict(pred_df, gr_spm_B(&o.s, GR_SPM_THESIS_B_COEF), pred_C, &pred, &err) == 0;

    /* the RFM's snapshots: checked before any work, and their largest |v| for the range */
    gr_spm_rfm_info info = {0};
    if (run_dir) {
        gr_histogram probe;
        if (gr_histogram_init(&probe, 1, 0.0, 1e-300, false, &err) ||
            gr_spm_rfm_histogram(run_dir, t_from, &probe, &info, &err)) {
            gr_histogram_free(&probe);
            gr_spm_pl_free(&pl);
            cli_error("%s", err.message);
            return exit_code(&err);
        }
        gr_histogram_free(&probe);
        if (info.dim != o.s.dim) {
            gr_spm_pl_free(&pl);
            cli_error("spm full: the run is %dD but --dim %d was asked for", info.dim, o.s.dim);
            return EXIT_REFUSED;
        }
    }
    if (isnan(vmax)) {
        /* 3 u_l at the largest free path expected among the walks (tilted: quantile 1 - N^-tilt) */
        double lbig = gr_spm_pl_quantile(&pl, 1.0 - pow((double)o.s.walks, -o.s.tilt));
        vmax = 3.0 * gr_spm_velocity_scale(&o.s, lbig);
        if (run_dir) {
            vmax = fmax(vmax, 1.02 * info.v_max); /* the run's fastest component fits too */
        }
    }
    if (gr_output_dir_prepare(o.out, o.force, &err)) {
        gr_spm_pl_free(&pl);
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    double t0 = now();
    progress_state ps = {.label = "spm full", .parts = 1, .t0 = t0, .on = !o.quiet && cli_interactive()};
    if (ps.on) {
        o.s.progress = progress;
        o.s.user = &ps;
    }
    gr_spm_full_result res;
    int rc = gr_spm_full(&o.s, &pl, weight_time, o.bins, vmax, &res, &err);
    progress_end(&ps);
    if (rc) {
        gr_spm_pl_free(&pl);
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    double wall = now() - t0;
    const int nb = o.bins;
    double *v = calloc((size_t)nb * 8, sizeof(double));
    if (!v) {
        gr_spm_full_result_free(&res);
        gr_spm_pl_free(&pl);
        cli_error("out of memory");
        return EXIT_FAILED;
    }
    double *ps_ = v + nb, *es = ps_ + nb, *pr = es + nb, *er = pr + nb;
    for (int i = 0; i < nb; i++) {
        v[i] = gr_histogram_center(&res.p.all, i);
        ps_[i] = gr_spm_dist_density(&res.p, i);
        es[i] = gr_spm_dist_error(&res.p, i);
    }
    double v_rms = sqrt(res.v2_mean);
    if (isnan(fit_from)) {
        fit_from = 3.0 * v_rms;
    }
    /* tail fits of the SPM P(v), jackknife errors: a free stretched exponential, and 5.31 with
     * alpha fixed at the prediction */
    pv_fit_par fp = {fit_from, have_pred ? pred.alpha : 1.0, have_pred ? pred.S : 10.0, have_pred ? pred.h : 0.5, 0.0, 0, 0};
    double sfit[3], sfit_err[3], f531[3], f531_err[3];
    gr_error e2 = {0};
    bool have_sfit = gr_spm_dist_jackknife(&res.p, pv_stretched, &fp, 3, sfit, sfit_err, &e2) == 0;
    double sfit_chi2 = fp.chi2_red;
    int sfit_points = fp.points;
    fp.calls = 0;
    bool have_531 = have_pred && gr_spm_dist_jackknife(&res.p, pv_531, &fp, 3, f531, f531_err, &e2) == 0;
    double f531_chi2 = fp.chi2_red;
    double v_data = 0.0; /* the largest v with SPM data */
    for (int i = 0; i < nb; i++) {
        if (ps_[i] > 0.0) {
            v_data = gr_histogram_upper(&res.p.all, i);
        }
    }

    /* the RFM */
    gr_spm_compare cmp = {0}, cmp2 = {0};
    bool have_cmp = false, have_cmp2 = false;
    gr_histogram rh = {0};
    if (run_dir) {
        rc = gr_histogram_init(&rh, nb, 0.0, vmax, false, &err);
        if (!rc) {
            rc = gr_spm_rfm_histogram(run_dir, t_from, &rh, &info, &err);
        }
        if (!rc && info.dim != o.s.dim) {
            rc = GR_FAIL(&err, GR_EINVAL, "spm full: the run is %dD but --dim %d was asked for", info.dim, o.s.dim);
        }
        if (!rc) {
            for (int i = 0; i < nb; i++) {
                pr[i] = 0.5 * gr_histogram_density(&rh, i);
                er[i] = 0.5 * gr_histogram_density_error(&rh, i);
            }
            if (isnan(compare_from)) {
                compare_from = 2.0 * sqrt(info.v2_mean);
            }
            have_cmp = gr_spm_compare_tails(v, ps_, es, pr, er, nb, compare_from, z_max, false, &cmp, &e2) == 0;
            have_cmp2 = gr_spm_compare_tails(v, ps_, es, pr, er, nb, compare_from, z_max, true, &cmp2, &e2) == 0;
        }
    }
    /* the free-path scale the fitted velocity scale s stands for: l -> s^3 l */
    double implied_C = pl.kind == GR_SPM_PL_FITTED && have_cmp2 ? pl.C * pow(cmp2.s, -3.0 * pl.beta) : (double)NAN;

    /* p_v.csv */
    gr_file f;
    if (!rc) {
        rc = gr_file_open(&f, o.out, "p_v.csv", &err);
    }
    if (!rc) {
        csv_head(&f, "P(v) of the full SPM (sec. 5.2.3), one velocity component", &o);
        gr_file_note(&f, "# P_l: %s; weight %s; tilt %g\n", pl.source, weight_time ? "uniform in time" : "per walk", o.s.tilt);
        gr_file_note(&f, "# v in m/s, P in s/m (density of the signed component); errors from the spread between batches;\n"
                     "# P_531: A0 v^h exp(-S v^alpha) of 5.31 with alpha = %g and S, h, A0 fitted over %g <= v <= %g m/s\n",
                have_pred ? pred.alpha : (double)NAN, fit_from, v_data);
        fprintf(f.f, "v_lo,v_hi,v,samples,P,P_err,P_err_poisson,P_531\n");
        for (int i = 0; i < nb; i++) {
            double p531 = have_531 && v[i] >= fit_from && v[i] <= v_data ? exp(tail_531(v[i], f531, NULL, &fp.alpha)) : (double)NAN;
            fprintf(f.f, "%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.6g\n", gr_histogram_lower(&res.p.all, i),
                    gr_histogram_upper(&res.p.all, i), v[i], res.p.all.count[i], ps_[i], es[i],
                    gr_spm_dist_poisson_error(&res.p, i), p531);
        }
        rc = gr_file_commit(&f, &err);
    }
    /* pl.csv: the free-path density used */
    if (!rc) {
        rc = gr_file_open(&f, o.out, "pl.csv", &err);
    }
    if (!rc) {
        csv_head(&f, "the free-path distribution P_l(l) the walks drew from (sec. 4.3)", &o);
        gr_file_note(&f, "# %s; l in m, P in 1/m (normalised); P_fit: 4.25 fitted to the table's tail (if any)\n", pl.source);
        fprintf(f.f, "l,P,P_fit\n");
        if (pl.kind == GR_SPM_PL_TABLE) {
            for (int i = 0; i < pl.n; i++) {
                double fit = have_plfit && pl.l[i] >= plfit.lfrom && pl.l[i] <= plfit.lto
                                 ? plfit.A0 * pow(pl.l[i], plfit.beta - 1.0) * exp(-plfit.C * pow(pl.l[i], plfit.beta))
                                 : (double)NAN;
                fprintf(f.f, "%.6g,%.6g,%.6g\n", pl.l[i], pl.p[i], fit);
            }
        } else {
            double lo = gr_spm_pl_quantile(&pl, 1e-6), hi = gr_spm_pl_quantile(&pl, 1.0 - 1e-12);
            for (int i = 0; i <= 200; i++) {
                double l = lo * pow(hi / lo, i / 200.0);
                fprintf(f.f, "%.6g,%.6g,%.6g\n", l, gr_spm_pl_density(&pl, l), gr_spm_pl_density(&pl, l));
            }
        }
        rc = gr_file_commit(&f, &err);
    }
    if (!rc && run_dir) {
        rc = gr_file_open(&f, o.out, "compare.csv", &err);
        if (!rc) {
            csv_head(&f, "SPM P(v) against the Random Force Model's P(v) per component (Fig. 5.10)", &o);
            gr_file_note(&f, "# run %s: %d frames with Time >= %g s (%d skipped), %lld particles, %dD; P_rfm errors sqrt(X)\n", run_dir,
                    info.frames, t_from, info.frames_skipped, (long long)info.particles, info.dim);
            gr_file_note(&f, "# P_spm_scaled = k P_spm, k = %g +- %g fitted over v >= %g m/s; P_spm_fit = k2 P_spm(v/s)/s, k2 = %g,\n"
                         "# s = %g +- %g (velocity scale fitted too); agree: |z| <= %g in the contiguous tail\n",
                    cmp.k, cmp.k_err, compare_from, cmp2.k, cmp2.s, cmp2.s_err, z_max);
            fprintf(f.f, "v,P_spm,P_spm_err,P_spm_scaled,P_rfm,P_rfm_err,z,agree,P_spm_fit,z_fit,agree_fit\n");
            for (int i = 0; i < nb; i++) {
                double m1e, m1 = gr_spm_compare_model(&cmp, v, ps_, es, nb, i, &m1e);
                double m2e, m2 = gr_spm_compare_model(&cmp2, v, ps_, es, nb, i, &m2e);
                double z1 = m1 > 0.0 && pr[i] > 0.0 ? (pr[i] - m1) / sqrt(er[i] * er[i] + m1e * m1e) : (double)NAN;
                double z2 = m2 > 0.0 && pr[i] > 0.0 ? (pr[i] - m2) / sqrt(er[i] * er[i] + m2e * m2e) : (double)NAN;
                int a1 = have_cmp && cmp.agree_bins > 0 && v[i] >= cmp.v_agree_lo && v[i] <= cmp.v_agree_hi;
                int a2 = have_cmp2 && cmp2.agree_bins > 0 && v[i] >= cmp2.v_agree_lo && v[i] <= cmp2.v_agree_hi;
                fprintf(f.f, "%.6g,%.6g,%.4g,%.6g,%.6g,%.4g,%.4g,%d,%.6g,%.4g,%d\n", v[i], ps_[i], es[i], m1, pr[i], er[i], z1,
                        a1, m2, z2, a2);
            }
            rc = gr_file_commit(&f, &err);
        }
    }

    cJSON *j = json_head("full");
    json_settings(j, &o);
    cJSON_AddNumberToObject(cJSON_GetObjectItem(j, "settings"), "tilt", o.s.tilt);
    cJSON_AddStringToObject(j, "weight", weight_time ? "time" : "walk");
    cJSON *pj = cJSON_AddObjectToObject(j, "free_paths");
    cJSON_AddStringToObject(pj, "source", pl.source);
    json_num(pj, "mean", gr_spm_pl_mean(&pl));
    json_num(pj, "mean_drawn", res.l_mean);
    if (pl_path) {
        cJSON *t = cJSON_AddObjectToObject(pj, "tail_fit_4_25");
        if (have_plfit) {
            json_num(t, "l_from", plfit.lfrom);
            json_num(t, "l_to", plfit.lto);
            json_num(t, "D_f", plfit.df);
            json_num(t, "D_f_err", plfit.df_err);
            json_num(t, "C", plfit.C);
            json_num(t, "C_err", plfit.C_err);
            json_num(t, "chi2_red", plfit.chi2_red);
            cJSON_AddNumberToObject(t, "points", plfit.n_points);
        } else {
            cJSON_AddStringToObject(t, "note", plfit_note);
        }
    } else {
        cJSON_AddNumberToObject(pj, "D_f", df);
        cJSON_AddNumberToObject(pj, "C", C);
    }
    cJSON *rj = cJSON_AddObjectToObject(j, "spm");
    json_stats(rj, &res.stats);
    json_num(rj, "vmax", vmax);
    json_num(rj, "v_max_with_data", v_data);
    json_num(rj, "v_rms", v_rms);
    json_num(rj, "fit_from", fit_from);
    if (have_sfit) {
        cJSON *t = cJSON_AddObjectToObject(rj, "stretched_exp_fit");
        json_num(t, "alpha", sfit[2]);
        json_num(t, "alpha_err", sfit_err[2]);
        json_num(t, "v_A", sfit[1]);
        json_num(t, "v_A_err", sfit_err[1]);
        json_num(t, "chi2_red", sfit_chi2);
        cJSON_AddNumberToObject(t, "points", sfit_points);
    }
    if (have_pred) {
        cJSON *t = cJSON_AddObjectToObject(rj, "prediction_5_27_5_31");
        json_num(t, "D_f", pred.df);
        json_num(t, "alpha", pred.alpha);
        json_num(t, "h", pred.h);
        json_num(t, "B_b_0_98", pred.B);
        json_num(t, "C", pred.C);
        json_num(t, "S", pred.S);
        json_num(t, "v_A", pred.v_A);
        if (have_531) {
            json_num(t, "fit_S", f531[2]);
            json_num(t, "fit_S_err", f531_err[2]);
            json_num(t, "fit_h", f531[1]);
            json_num(t, "fit_h_err", f531_err[1]);
            json_num(t, "fit_chi2_red", f531_chi2);
        }
    }
    if (run_dir) {
        cJSON *t = cJSON_AddObjectToObject(j, "rfm");
        cJSON_AddStringToObject(t, "run", run_dir);
        cJSON_AddNumberToObject(t, "frames", info.frames);
        cJSON_AddNumberToObject(t, "frames_skipped", info.frames_skipped);
        json_num(t, "t_from", t_from);
        cJSON_AddNumberToObject(t, "particles", (double)info.particles);
        json_num(t, "v_rms", sqrt(info.v2_mean));
        json_num(t, "v_max", info.v_max);
        json_num(t, "mass_of_run", run_mass);
        json_num(t, "D_of_run", run_D);
        json_num(t, "compare_from", compare_from);
        json_num(t, "z_max", z_max);
        if (info.frames < GR_MIN_FRAMES) {
            cJSON_AddStringToObject(t, "warning", "fewer frames than the 16 a comparison needs: no agreement verdict");
        }
        for (int w = 0; w < 2; w++) {
            const gr_spm_compare *c = w ? &cmp2 : &cmp;
            if (!(w ? have_cmp2 : have_cmp)) {
                continue;
            }
            cJSON *x = cJSON_AddObjectToObject(t, w ? "amplitude_and_velocity_scale" : "amplitude_only");
            json_num(x, "k", c->k);
            json_num(x, "k_err", c->k_err);
            json_num(x, "s", c->s);
            json_num(x, "s_err", c->s_err);
            if (w) {
                json_num(x, "implied_C", implied_C);
            }
            json_num(x, "chi2_red", c->chi2_red);
            cJSON_AddNumberToObject(x, "points", c->n_points);
            json_num(x, "agree_v_lo", c->v_agree_lo);
            json_num(x, "agree_v_hi", c->v_agree_hi);
            cJSON_AddNumberToObject(x, "agree_bins", c->agree_bins);
            json_num(x, "agree_decades", c->decades);
            json_num(x, "fraction_of_tail_bins_within_z_max", c->frac_within);
        }
    }
    cJSON_AddNumberToObject(j, "wall_seconds", wall);
    cJSON_AddArrayToObject(j, "plots");
    if (!rc) {
        char body[4096];
        int k = snprintf(body, sizeof body,
                         "set title 'P(v) of the Single Particle Model (sec. 5.2.3), %dD'\n"
                         "set xlabel '|v| (m/s)'\nset ylabel 'P(v) (s/m)'\nset logscale y\nset format y '10^{%%L}'\n"
                         "set key top right\nset xrange [0:%g]\n"
                         "plot 'p_v.csv' using 3:($5>0 ? $5 : 1/0):($5-$6 > 0 ? $5-$6 : $5/10):($5+$6) with yerrorbars "
                         "pt 7 ps 0.4 title 'SPM'",
                         o.s.dim, run_dir ? fmax(v_data, 1.02 * info.v_max) : v_data);
        if (have_531) {
            k += snprintf(body + k, sizeof body - (size_t)k, ", '' using 3:8 with lines lw 2 lc rgb 'black' "
                                                             "title 'fit of 5.31, alpha = %.3f fixed'",
                          pred.alpha);
        }
        if (run_dir) {
            k += snprintf(body + k, sizeof body - (size_t)k,
                          ", 'compare.csv' using 1:($5>0 ? $5 : 1/0):($5-$6 > 0 ? $5-$6 : $5/10):($5+$6) with yerrorbars "
                          "pt 6 ps 0.6 title 'RFM run', "
                          "'' using 1:($4>0 ? $4 : 1/0) with lines dt 2 lw 2 title 'SPM x %.3g', "
                          "'' using 1:($9>0 ? $9 : 1/0) with lines dt 3 lw 2 title 'SPM x %.3g, v scaled by %.3g'",
                          cmp.k, cmp2.k, cmp2.s);
        }
        snprintf(body + k, sizeof body - (size_t)k, "\n");
        plot(&o, j, "p_v.png", body);
        snprintf(body, sizeof body,
                 "set title 'Free-path distribution P_l(l) used (sec. 4.3)'\nset xlabel 'l (m)'\nset ylabel 'P_l(l) (1/m)'\n"
                 "set logscale xy\nset format y '10^{%%L}'\nset format x '10^{%%L}'\nset key top right\n"
                 "plot 'pl.csv' using 1:($2>0 ? $2 : 1/0) with linespoints pt 7 ps 0.4 title 'P_l', "
                 "'' using 1:($3>0 ? $3 : 1/0) with lines lw 2 dt 2 title '4.25'\n");
        plot(&o, j, "pl.png", body);
        rc = gr_json_write(o.out, "summary.json", j, &err);
    }
    cJSON_Delete(j);
    if (!rc) {
        printf("%s: SPM P(v), %dD, %lld walks (%s), l from %s, %.1f s\n", o.out, o.s.dim, (long long)o.s.walks,
               weight_time ? "uniform in time" : "per walk", pl.source, wall);
        printf("  <l> = %.4g m, v_rms = %.4g m/s, data up to %.3g m/s, mean first-passage time %.4f t_l\n", res.l_mean, v_rms,
               v_data, res.stats.exit_time_mean);
        if (pl_path && have_plfit) {
            printf("  P_l tail (4.25) over l >= %.3g m: D_f = %.3f +- %.3f, C = %.4g +- %.2g\n", plfit.lfrom, plfit.df,
                   plfit.df_err, plfit.C, plfit.C_err);
        }
        if (have_sfit) {
            printf("  tail v >= %.3g m/s: stretched exponential alpha = %.3f +- %.3f (jackknife; chi2/dof %.2f)\n", fit_from,
                   sfit[2], sfit_err[2], sfit_chi2);
        }
        if (have_pred) {
            printf("  prediction: alpha = %.4f (5.29), h = %.4f (5.31), S = %.4g, v_A = %.4g m/s (5.27, b = 0.98)", pred.alpha,
                   pred.h, pred.S, pred.v_A);
            if (have_531) {
                printf("; fitted with alpha fixed: S = %.4g +- %.2g, h = %.3f +- %.3f", f531[2], f531_err[2], f531[1],
                       f531_err[1]);
            }
            printf("\n");
        }
        if (run_dir) {
            printf("  RFM %s: %d frames, %lld particles, v_rms = %.4g m/s\n", run_dir, info.frames, (long long)info.particles,
                   sqrt(info.v2_mean));
            const bool few = info.frames < GR_MIN_FRAMES; /* error bars of P_rfm not to be trusted */
            if (few) {
                printf("    WARNING: no verdict: %d frames, fewer than the %d a comparison needs (run longer or sample "
                       "more often)\n", info.frames, GR_MIN_FRAMES);
            }
            if (have_cmp && !few) {
                printf("    SPM x %.4g: agrees (|z| <= %g) for %.3g <= v <= %.3g m/s, %.2f decades of P(v); %.0f%% of the bins "
                       "v >= %.3g within\n",
                       cmp.k, z_max, cmp.v_agree_lo, cmp.v_agree_hi, cmp.decades, 100.0 * cmp.frac_within, compare_from);
            }
            if (have_cmp2 && !few) {
                printf("    SPM x %.4g, v x %.4g +- %.2g", cmp2.k, cmp2.s, cmp2.s_err);
                if (isfinite(implied_C)) {
                    printf(" (C = %.4g)", implied_C);
                }
                printf(": agrees for %.3g <= v <= %.3g m/s, %.2f decades; %.0f%% of the tail bins within\n", cmp2.v_agree_lo,
                       cmp2.v_agree_hi, cmp2.decades, 100.0 * cmp2.frac_within);
            }
            if (!have_cmp && !have_cmp2 && !few) {
                printf("    no comparison possible (no common tail bins)\n");
            }
        }
    }
    gr_histogram_free(&rh);
    free(v);
    gr_spm_full_result_free(&res);
    gr_spm_pl_free(&pl);
    if (rc) {
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    return EXIT_OK;
}

/* ------------------------------------------------------------------------------------------- *
 * predict */

static int cmd_predict(int argc, char **argv)
{
    options o = {.out = "out/spm-predict", .plots = true, .bins = 0};
    gr_spm_settings_default(&o.s);
    const char *pl_path = NULL;
    double df = (double)NAN, C = (double)NAN, b = GR_SPM_THESIS_B_COEF, tail_from = 0.0, vmax = (double)NAN,
           diameter = 0.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage_predict(stdout);
            return EXIT_OK;
        }
        if (!strcmp(a, "--force")) {
            o.force = true;
            continue;
        }
        if (!strcmp(a, "--no-plots")) {
            o.plots = false;
            continue;
        }
        if (!strcmp(a, "--quiet")) {
            continue;
        }
        if (i + 1 >= argc) {
            if (!strcmp(a, "--out") || !strcmp(a, "--pl") || !strcmp(a, "--df") || !strcmp(a, "--C") || !strcmp(a, "--b") ||
                !strcmp(a, "--mass") || !strcmp(a, "--D") || !strcmp(a, "--tail-from") || !strcmp(a, "--vmax") ||
                !strcmp(a, "--diameter")) {
                cli_error("spm: %s needs a value", a);
            } else {
                unknown("predict", a);
            }
            return EXIT_REFUSED;
        }
        if (!strcmp(a, "--out")) {
            o.out = argv[++i];
            continue;
        }
        if (!strcmp(a, "--pl")) {
            pl_path = argv[++i];
            continue;
        }
        double x;
        static const char *const nums[] = {"--df", "--C", "--b", "--mass", "--D", "--tail-from", "--vmax", "--diameter"};
        bool known = false;
        for (size_t k = 0; k < sizeof nums / sizeof nums[0]; k++) {
            known |= !strcmp(a, nums[k]);
        }
        if (!known) {
            unknown("predict", a);
            return EXIT_REFUSED;
        }
        if (!value_number(argc, argv, &i, &x)) {
            return EXIT_REFUSED;
        }
        if (!strcmp(a, "--df")) {
            df = x;
        } else if (!strcmp(a, "--C")) {
            C = x;
        } else if (!strcmp(a, "--b")) {
            b = x;
        } else if (!strcmp(a, "--mass")) {
            o.s.mass = x;
        } else if (!strcmp(a, "--D")) {
            o.s.D = x;
        } else if (!strcmp(a, "--tail-from")) {
            tail_from = x;
        } else if (!strcmp(a, "--diameter")) {
            diameter = x;
        } else {
            vmax = x;
        }
    }
    if ((pl_path != NULL) == !isnan(df)) {
        cli_error("spm predict: give either --df D_f or --pl FILE");
        return EXIT_REFUSED;
    }
    if (!(b > 0.0) || !isfinite(b)) {
        cli_error("spm predict: --b must be > 0, got %g", b);
        return EXIT_REFUSED;
    }
    if (!isnan(vmax) && !(vmax > 0.0 && isfinite(vmax))) {
        cli_error("spm predict: --vmax must be > 0 m/s, got %g", vmax);
        return EXIT_REFUSED;
    }
    if (strlen(o.out) >= 1000) {
        cli_error("spm: --out %s: path too long", o.out);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    if (settings_ok(&o, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    gr_spm_pl_fit plfit = {0};
    if (pl_path) {
        gr_spm_pl pl;
        if (gr_spm_pl_load(&pl, pl_path, pl_diameter(pl_path, diameter), &err)) {
            cli_error("%s%s", err.message, strstr(err.message, "diameter") ? " (give --diameter D in m)" : "");
            return exit_code(&err);
        }
        int rc = gr_spm_pl_fit_tail(&pl, tail_from, &plfit, &err);
        gr_spm_pl_free(&pl);
        if (rc) {
            cli_error("%s", err.message);
            return EXIT_REFUSED;
        }
        df = plfit.df;
        if (isnan(C)) {
            C = plfit.C;
        }
    } else if (isnan(C)) {
        C = THESIS_C;
    }
    if (!(C > 0.0) || !isfinite(C)) {
        cli_error("spm predict: --C must be > 0, got %g", C);
        return EXIT_REFUSED;
    }
    gr_spm_prediction p;
    if (gr_spm_predict(df, gr_spm_B(&o.s, b), C, &p, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (gr_output_dir_prepare(o.out, o.force, &err)) {
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    if (isnan(vmax)) {
        vmax = 20.0 * p.v_A;
    }
    /* the numerical integral 5.13 against the steepest-descent form 5.26 */
    gr_file f;
    int rc = gr_file_open(&f, o.out, "prediction.csv", &err);
    double last_delta = (double)NAN;
    if (!rc) {
        gr_file_note(&f, "# granule %s (%s) spm: the SPM integral identity's tail (sec. 5.3.2)\n", GR_VERSION, GR_COMMIT);
        gr_file_note(&f, "# D_f = %g, alpha = %g, h = %g, B = %g (b = %g, M = %g kg, D = %g N^2 s), C = %g, S = %g, v_A = %g m/s\n",
                p.df, p.alpha, p.h, p.B, b, o.s.mass, o.s.D, p.C, p.S, p.v_A);
        gr_file_note(&f, "# ln_I: ln of 5.13 (A_2 = 1) integrated numerically; ln_asym: 5.26 = -S v^alpha + ln sqrt(2 pi / -f''(y_m));\n"
                     "# P_531 = v^h exp(-S v^alpha) (5.31 with A_0 = 1); v in m/s\n");
        fprintf(f.f, "v,ln_I,ln_asym,delta,P_531\n");
        for (int i = 1; i <= 200 && !rc; i++) {
            double v = vmax * i / 200.0, li;
            rc = gr_spm_integral_log(&p, v, &li, &err);
            if (!rc) {
                double la = gr_spm_asymptotic_log(&p, v);
                last_delta = li - la;
                fprintf(f.f, "%.6g,%.10g,%.10g,%.6g,%.6g\n", v, li, la, li - la, pow(v, p.h) * exp(-p.S * pow(v, p.alpha)));
            }
        }
        if (rc) {
            gr_file_abandon(&f);
        } else {
            rc = gr_file_commit(&f, &err);
        }
    }
    cJSON *j = json_head("predict");
    cJSON *in = cJSON_AddObjectToObject(j, "input");
    json_num(in, "D_f", df);
    json_num(in, "C", C);
    json_num(in, "b", b);
    json_num(in, "mass", o.s.mass);
    json_num(in, "D", o.s.D);
    if (pl_path) {
        cJSON *t = cJSON_AddObjectToObject(in, "tail_fit_4_25");
        cJSON_AddStringToObject(t, "file", pl_path);
        json_num(t, "l_from", plfit.lfrom);
        json_num(t, "l_to", plfit.lto);
        json_num(t, "D_f", plfit.df);
        json_num(t, "D_f_err", plfit.df_err);
        json_num(t, "C", plfit.C);
        json_num(t, "C_err", plfit.C_err);
        json_num(t, "chi2_red", plfit.chi2_red);
        cJSON_AddNumberToObject(t, "points", plfit.n_points);
    }
    cJSON *r = cJSON_AddObjectToObject(j, "prediction");
    json_num(r, "beta", p.beta);
    json_num(r, "gamma", p.gamma);
    json_num(r, "alpha", p.alpha);
    if (pl_path) {
        /* d alpha / d D_f = 12 / (3 D_f - 1)^2 */
        json_num(r, "alpha_err", 12.0 / ((3.0 * df - 1.0) * (3.0 * df - 1.0)) * plfit.df_err);
    }
    json_num(r, "h", p.h);
    json_num(r, "B", p.B);
    json_num(r, "F", p.F);
    json_num(r, "S", p.S);
    json_num(r, "v_A", p.v_A);
    json_num(r, "integral_minus_asymptotic_at_vmax", last_delta);
    cJSON_AddArrayToObject(j, "plots");
    if (!rc) {
        char body[2048];
        snprintf(body, sizeof body,
                 "set title 'SPM integral 5.13 (numerical) and its steepest-descent form 5.26'\n"
                 "set xlabel 'v (m/s)'\nset ylabel 'ln I(v)'\nset key top right\n"
                 "plot 'prediction.csv' using 1:2 with lines lw 2 title 'ln I, numerical', "
                 "'' using 1:3 with lines dt 2 lw 2 title 'steepest descent 5.26: -S v^{%.3f} + ln (2 pi / |f_{yy}|)^{1/2}'\n",
                 p.alpha);
        plot(&o, j, "prediction.png", body);
        rc = gr_json_write(o.out, "summary.json", j, &err);
    }
    cJSON_Delete(j);
    if (rc) {
        cli_error("%s", err.message);
        return exit_code(&err);
    }
    printf("%s: D_f = %.4g%s\n", o.out, df, pl_path ? " (fitted to the P_l tail)" : "");
    if (pl_path) {
        printf("  P_l tail (4.25) over %.3g <= l <= %.3g m: D_f = %.3f +- %.3f, C = %.4g +- %.2g, chi2/dof %.2f\n",
               plfit.lfrom, plfit.lto, plfit.df, plfit.df_err, plfit.C, plfit.C_err, plfit.chi2_red);
    }
    printf("  alpha = 6(D_f - 1)/(3 D_f - 1) = %.4f (5.29)\n", p.alpha);
    printf("  H(v) ~ v^h, h = 3(D_f - 1)/(3 D_f - 1) = %.4f (5.30-5.31)\n", p.h);
    printf("  B = %.4g (b = %g), C = %.4g: S = %.4g (m/s)^-alpha, v_A = S^(-1/alpha) = %.4g m/s (5.27)\n", p.B, b, p.C, p.S,
           p.v_A);
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
        return cmd_full(argc - 1, argv + 1);
    }
    if (!strcmp(m, "predict")) {
        return cmd_predict(argc - 1, argv + 1);
    }
    cli_error("spm: unknown mode %s (circle, full or predict; granule spm --help)", m);
    return EXIT_REFUSED;
}
