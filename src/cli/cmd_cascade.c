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
 *   sk.png, field.png, placement.png   gnuplot */
#include <cjson/cJSON.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/cascade.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/snapshot.h"

#define FIELD_CSV_MAX_LEVELS 8 /* field.csv: at most 256 x 256 values */

static void usage(FILE *f)
{
    gr_cascade_settings s;
    gr_cascade_settings_default(&s);
    fprintf(f,
            "usage: granule cascade [--levels n] [--variant NAME] [--p p1,p2,p3,p4] [--configurations C]\n"
            "                       [--seed S] [--out DIR] [--box L] [--fit-min Q] [--fit-max Q]\n"
            "                       [--place N [--radius r] [--max-attempts A]] [--force] [--quiet]\n\n"
            "Multiplicative cascade process (thesis sec. 6.2): breaks a box of side L into 2^n x 2^n squares\n"
            "level by level, sharing each square's probability among its four children (6.2)-(6.4). Averages\n"
            "the structure factor S(k) (6.5) over C configurations on k = 2 pi (i, j)/L, circularly in integer\n"
            "|k| L / 2 pi bins, fits S = A k^-D_f over bins Q_min..Q_max (4.4) and compares with Table 6.2 and\n"
            "with the exact configuration average. --place puts N discs of radius r without overlap where the\n"
            "first field is likely (Fig. 6.3) and writes them as an extended-XYZ snapshot.\n\n"
            "  --levels n          grid 2^n x 2^n, 1..%d (default %d: the thesis's 256 x 256)\n"
            "  --variant NAME      ucp (default), unoncp, symmetrised, meakin1..meakin4 (Table 6.1),\n"
            "                      meakin (with --p), uniform (control: every child gets m/4)\n"
            "  --p p1,p2,p3,p4     the four Meakin numbers (>= 0) for --variant meakin\n"
            "  --configurations C  configurations averaged (default %d)\n"
            "  --seed S            seed of GSL's mt19937, 0..4294967295 (default %lu)\n"
            "  --out DIR           output folder (default out/cascade)\n"
            "  --box L             box side in m (default %g; Fig. 6.3 uses 0.2)\n"
            "  --fit-min Q         first |k| L / 2 pi bin of the D_f fit (default 1)\n"
            "  --fit-max Q         last bin (default 2^(n-3), at least 4)\n"
            "  --place N           place N discs from the first configuration's field\n"
            "  --radius r          disc radius in m (default 1.5e-3)\n"
            "  --max-attempts A    draws allowed for the placement (default 10^6 + 10^4 N)\n"
            "  --force             overwrite the results of an earlier run in DIR\n"
            "  --quiet             no progress line\n\n"
            "Writes DIR/summary.json, sk.csv, levels.csv, field.csv, sk.png, field.png and, with --place,\n"
            "snapshots/snap_000000.xyz, scene.ini (so granule analyse DIR reads them) and placement.png.\n"
            "Docs: docs/theory-cascade.md. Exit status: 0 done, 2 refused input (one line on stderr; also\n"
            "when the placement is impossible), 1 other failures.\n",
            GR_CASCADE_MAX_LEVELS, s.levels, s.configurations, s.seed, s.L);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* an integer option in [lo, hi] */
static bool int_option(const char *opt, const char *text, double lo, double hi, double *out)
{
    if (!cli_number(opt, text, out)) {
        return false;
    }
    if (!(*out >= lo && *out <= hi) || *out != floor(*out)) {
        cli_error("cascade: %s must be an integer in [%.0f, %.0f], got %s", opt, lo, hi, text);
        return false;
    }
    return true;
}

static bool parse_p(const char *text, double p[4])
{
    char *end;
    const char *c = text;
    for (int i = 0; i < 4; i++) {
        p[i] = strtod(c, &end);
        if (end == c || (i < 3 && *end != ',') || (i == 3 && *end != '\0')) {
            cli_error("cascade: --p needs four comma-separated numbers, e.g. 0.02,0.32,0.32,0.34; got '%s'", text);
            return false;
        }
        c = end + 1;
    }
    return true;
}

/* splitmix64: the placement's generator is seeded apart from the field's */
static unsigned long derived_seed(unsigned long seed)
{
    uint64_t z = (uint64_t)seed + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (unsigned long)((z ^ (z >> 31)) & 0xffffffffull);
}

typedef struct run_info {
    const gr_cascade_settings *s;
    const gr_cascade_variant_info *vi;
    const char *dir;
} run_info;

static void csv_header(gr_file *f, const run_info *ri, const char *what)
{
    const gr_cascade_settings *s = ri->s;
    gr_file_note(f, "# granule cascade (%s, %s): %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f, "# variant %s (%s), levels %d (%d x %d squares), L = %.9g m, %d configurations, seed %lu (gsl mt19937)\n",
            ri->vi->name, ri->vi->label, s->levels, 1 << s->levels, 1 << s->levels, s->L, s->configurations, s->seed);
}

static int write_sk(const run_info *ri, const gr_cascade_sk_bin *b, int nb, double q_min, double q_max, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "sk.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, ri, "structure factor S(k) of eq. 6.5, circular average (sec. 4.1)");
    gr_file_note(&f, "# q: bin q-1/2 <= |k| L/(2 pi) < q+1/2; k: mean |k| of its lattice vectors, 1/m; vectors: how many;\n"
                 "# S, S_err: configuration average and its standard error; S_expected: exact average (second moments);\n"
                 "# in_fit: 1 for the bins of the D_f fit\n");
    fprintf(f.f, "q,k,vectors,S,S_err,S_expected,in_fit\n");
    for (int i = 0; i < nb; i++) {
        fprintf(f.f, "%d,%.9g,%d,%.9g,%.6g,%.9g,%d\n", b[i].q, b[i].k, b[i].vectors, b[i].S, b[i].S_err,
                b[i].S_expected, b[i].q >= q_min && b[i].q <= q_max);
    }
    return gr_file_commit(&f, err);
}

static int write_levels(const run_info *ri, const double *mean, const double *m2, const double *lo,
                        const double *hi, int C, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "levels.csv", err);
    if (rc) {
        return rc;
    }
    double mu[4], second[4][4];
    gr_cascade_moments(ri->s, mu, second);
    const double growth = mu[0] + mu[1] + mu[2] + mu[3];
    csv_header(&f, ri, "total probability sum m_{i,j}(l) at each level l over the configurations");
    gr_file_note(&f, "# expected: (sum_c E[w_c])^l; sd: standard deviation over configurations (0 for a conserving variant)\n");
    fprintf(f.f, "level,side,total_mean,total_sd,total_min,total_max,expected\n");
    for (int l = 0; l <= ri->s->levels; l++) {
        fprintf(f.f, "%d,%d,%.17g,%.6g,%.17g,%.17g,%.17g\n", l, 1 << l, mean[l], C > 1 ? sqrt(m2[l] / (C - 1)) : 0.0,
                lo[l], hi[l], pow(growth, l));
    }
    return gr_file_commit(&f, err);
}

/* The field relative to uniform, 4^l m, coarse-grained by block sums to level
 * l = min(levels, FIELD_CSV_MAX_LEVELS) (out: 4^l values, row-major). */
static int coarse_field(const gr_cascade_field *fld, double *out)
{
    const int l = fld->levels < FIELD_CSV_MAX_LEVELS ? fld->levels : FIELD_CSV_MAX_LEVELS;
    const int n = 1 << l, block = fld->side / n;
    const double scale = ldexp(1.0, 2 * l);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            double sum = 0.0;
            for (int b = 0; b < block; b++) {
                const double *row = fld->m + (size_t)(j * block + b) * (size_t)fld->side + (size_t)(i * block);
                for (int a = 0; a < block; a++) {
                    sum += row[a];
                }
            }
            out[j * n + i] = scale * sum;
        }
    }
    return l;
}

static int write_field(const run_info *ri, const double *coarse, int l, gr_error *err)
{
    const int n = 1 << l, block = 1 << (ri->s->levels - l);
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "field.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, ri, "the first configuration's field");
    gr_file_note(&f, "# %d x %d squares (blocks of %d x %d finest squares summed); x, y: square centre (6.1), m;\n"
                 "# density = 4^%d m, the probability relative to a uniform field\n",
            n, n, block, block, l);
    fprintf(f.f, "x,y,density\n");
    const double h = ri->s->L / n;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            fprintf(f.f, "%.9g,%.9g,%.9g\n", (i + 0.5) * h, (j + 0.5) * h, coarse[j * n + i]);
        }
    }
    return gr_file_commit(&f, err);
}

static void add_number_or_null(cJSON *o, const char *key, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, key, v);
    } else {
        cJSON_AddNullToObject(o, key);
    }
}

static void progress_line(int done, int total, double elapsed)
{
    const int eta = done > 0 ? (int)(elapsed * (total - done) / done + 0.5) : 0;
    fprintf(stderr, "\rcascade: configuration %d / %d  %3.0f%%  ETA %d:%02d:%02d   ", done, total,
            100.0 * done / total, eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

int cmd_cascade(int argc, char **argv)
{
    gr_cascade_settings s;
    gr_cascade_settings_default(&s);
    gr_cascade_placement place;
    gr_cascade_placement_default(&place);
    const char *out = "out/cascade", *variant = "ucp", *p_text = NULL;
    bool force = false, quiet = false, do_place = false, radius_given = false, attempts_given = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--force")) {
            force = true;
        } else if (!strcmp(a, "--quiet")) {
            quiet = true;
        } else if (!v || strncmp(a, "--", 2) != 0) {
            cli_error("cascade: unknown or incomplete option %s (see granule cascade --help)", a);
            return EXIT_REFUSED;
        } else {
            i++;
            if (!strcmp(a, "--out")) {
                out = v;
            } else if (!strcmp(a, "--variant")) {
                variant = v;
            } else if (!strcmp(a, "--p")) {
                p_text = v;
            } else if (!strcmp(a, "--levels")) {
                if (!int_option(a, v, 1, GR_CASCADE_MAX_LEVELS, &x)) {
                    return EXIT_REFUSED;
                }
                s.levels = (int)x;
            } else if (!strcmp(a, "--configurations")) {
                if (!int_option(a, v, 1, 1e9, &x)) {
                    return EXIT_REFUSED;
                }
                s.configurations = (int)x;
            } else if (!strcmp(a, "--seed")) {
                if (!int_option(a, v, 0, 4294967295.0, &x)) {
                    return EXIT_REFUSED;
                }
                s.seed = (unsigned long)x;
            } else if (!strcmp(a, "--place")) {
                if (!int_option(a, v, 1, 1e8, &x)) {
                    return EXIT_REFUSED;
                }
                place.n = (int)x;
                do_place = true;
            } else if (!strcmp(a, "--max-attempts")) {
                if (!int_option(a, v, 1, 1e15, &x)) {
                    return EXIT_REFUSED;
                }
                place.max_attempts = (int64_t)x;
                attempts_given = true;
            } else if (!strcmp(a, "--fit-min") || !strcmp(a, "--fit-max")) {
                if (!int_option(a, v, 1, 1e9, &x)) {
                    return EXIT_REFUSED;
                }
                *(!strcmp(a, "--fit-min") ? &s.fit_q_min : &s.fit_q_max) = x;
            } else if (!strcmp(a, "--box") || !strcmp(a, "--radius")) {
                if (!cli_number(a, v, &x)) {
                    return EXIT_REFUSED;
                }
                if (!(x > 0.0) || !isfinite(x)) {
                    cli_error("cascade: %s must be a length > 0 m, got %s", a, v);
                    return EXIT_REFUSED;
                }
                if (!strcmp(a, "--box")) {
                    s.L = x;
                } else {
                    place.radius = x;
                    radius_given = true;
                }
            } else {
                cli_error("cascade: unknown option %s (see granule cascade --help)", a);
                return EXIT_REFUSED;
            }
        }
    }
    gr_error err = {0};
    if (gr_cascade_variant_parse(variant, &s.variant, &err)) {
        cli_error("cascade: --variant: %s", err.message);
        return EXIT_REFUSED;
    }
    if (p_text && s.variant != GR_CASCADE_MEAKIN) {
        cli_error("cascade: --p applies to --variant meakin only (meakin1..4 use Table 6.1)");
        return EXIT_REFUSED;
    }
    if (s.variant == GR_CASCADE_MEAKIN && !p_text) {
        cli_error("cascade: --variant meakin needs --p p1,p2,p3,p4");
        return EXIT_REFUSED;
    }
    if (p_text && !parse_p(p_text, s.p)) {
        return EXIT_REFUSED;
    }
    if ((radius_given || attempts_given) && !do_place) {
        cli_error("cascade: --radius and --max-attempts need --place N");
        return EXIT_REFUSED;
    }
    if (strlen(out) > 900) {
        cli_error("cascade: --out %s: path too long", out);
        return EXIT_REFUSED;
    }
    if (gr_cascade_settings_check(&s, &err)) {
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (do_place && gr_cascade_placement_check(&place, s.L, &err)) { /* before any work */
        cli_error("%s", err.message);
        return EXIT_REFUSED;
    }
    const gr_cascade_variant_info *vi = gr_cascade_variant_get(s.variant);
    double *totals = NULL, *t_mean = NULL, *t_m2 = NULL, *t_lo = NULL, *t_hi = NULL, *px = NULL, *py = NULL, *pv = NULL;
    double *coarse = NULL;
    int field_level = 0;
    gr_cascade_field *field = NULL;
    gr_cascade_sk *sk = NULL;
    gr_cascade_sk_bin *bins = NULL;
    gsl_rng *rng = NULL, *prng = NULL;
    int rc = gr_output_dir_prepare(out, force, &err);
    int status = EXIT_OK;
    if (rc) {
        cli_error("%s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    const int nl = s.levels + 1;
    totals = calloc((size_t)nl, sizeof(double));
    t_mean = calloc((size_t)nl, sizeof(double));
    t_m2 = calloc((size_t)nl, sizeof(double));
    t_lo = calloc((size_t)nl, sizeof(double));
    t_hi = calloc((size_t)nl, sizeof(double));
    coarse = malloc(sizeof(double) << (2 * (s.levels < FIELD_CSV_MAX_LEVELS ? s.levels : FIELD_CSV_MAX_LEVELS)));
    rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (!totals || !t_mean || !t_m2 || !t_lo || !t_hi || !coarse || !rng) {
        cli_error("cascade: out of memory");
        status = EXIT_FAILED;
        goto done;
    }
    for (int l = 0; l < nl; l++) {
        t_lo[l] = (double)INFINITY;
        t_hi[l] = -(double)INFINITY;
    }
    gsl_rng_set(rng, s.seed);
    if ((rc = gr_cascade_field_alloc(s.levels, s.L, &field, &err)) || (rc = gr_cascade_sk_alloc(&s, &sk, &err))) {
        cli_error("%s", err.message);
        status = rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
        goto done;
    }

    const double start = now();
    double last_report = start, place_seconds = 0.0;
    const bool progress = !quiet && cli_interactive();
    gr_cascade_placement_result pres = {0};
    for (int c = 0; c < s.configurations; c++) {
        if ((rc = gr_cascade_generate(&s, rng, field, totals, &err)) || (rc = gr_cascade_sk_add(sk, field, &err))) {
            cli_error("%s", err.message);
            status = EXIT_FAILED;
            goto done;
        }
        for (int l = 0; l < nl; l++) { /* Welford over configurations */
            const double d = totals[l] - t_mean[l];
            t_mean[l] += d / (c + 1);
            t_m2[l] += d * (totals[l] - t_mean[l]);
            t_lo[l] = fmin(t_lo[l], totals[l]);
            t_hi[l] = fmax(t_hi[l], totals[l]);
        }
        if (c == 0) {
            field_level = coarse_field(field, coarse);
            if (do_place) { /* Fig. 6.3, from the first field, before the long part */
                const double t0 = now();
                px = malloc(sizeof(double) * (size_t)place.n);
                py = malloc(sizeof(double) * (size_t)place.n);
                pv = calloc((size_t)place.n, sizeof(double));
                prng = gsl_rng_alloc(gsl_rng_mt19937);
                if (!px || !py || !pv || !prng) {
                    cli_error("cascade: out of memory for %d discs", place.n);
                    status = EXIT_FAILED;
                    goto done;
                }
                gsl_rng_set(prng, derived_seed(s.seed));
                if ((rc = gr_cascade_place(field, &place, prng, px, py, &pres, &err))) {
                    cli_error("%s", err.message);
                    status = rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
                    goto done;
                }
                place_seconds = now() - t0;
            }
        }
        if (progress && (now() - last_report > 0.5 || c + 1 == s.configurations)) {
            last_report = now();
            progress_line(c + 1, s.configurations, now() - start - place_seconds);
        }
    }
    if (progress) {
        fputc('\n', stderr);
    }
    const double wall = now() - start;

    const int nb = gr_cascade_sk_nbins(sk);
    bins = malloc(sizeof *bins * (size_t)nb);
    if (!bins) {
        cli_error("cascade: out of memory");
        status = EXIT_FAILED;
        goto done;
    }
    gr_cascade_sk_bins(sk, bins);
    double q_min, q_max;
    gr_cascade_fit_range(&s, &q_min, &q_max);
    gr_cascade_fit fit = {0}, fit_exp = {0};
    char fit_note[800] = "";
    gr_error fit_err = {0};
    double S_max = 0.0;
    for (int b = 0; b < nb; b++) {
        S_max = fmax(S_max, bins[b].S);
    }
    bool have_fit = false;
    if (!(S_max > 1e-20 * t_mean[s.levels] * t_mean[s.levels])) {
        snprintf(fit_note, sizeof fit_note, "no D_f: S(k) vanishes for k != 0 (a uniform field)");
    } else if (gr_cascade_fit_df(bins, nb, q_min, q_max, false, &fit, &fit_err) ||
               gr_cascade_fit_df(bins, nb, q_min, q_max, true, &fit_exp, &fit_err)) {
        snprintf(fit_note, sizeof fit_note, "no D_f: %s", fit_err.message);
    } else {
        have_fit = true;
    }

    run_info ri = {&s, vi, out};
    gr_error io_err = {0};
    int io = write_sk(&ri, bins, nb, q_min, q_max, &io_err);
    io = io ? io : write_levels(&ri, t_mean, t_m2, t_lo, t_hi, s.configurations, &io_err);
    io = io ? io : write_field(&ri, coarse, field_level, &io_err);
    char snapdir[1000] = "";
    if (!io && do_place) {
        snprintf(snapdir, sizeof snapdir, "%s/snapshots", out);
        if (mkdir(snapdir, 0777) != 0 && access(snapdir, W_OK) != 0) {
            io = GR_FAIL(&io_err, GR_EIO, "cannot create %s", snapdir);
        } else {
            gr_particles p = {.n = place.n, .dim = 2, .L = s.L, .radius = place.radius, .mass = 3.53e-5,
                              .x = px, .y = py, .vx = pv, .vy = pv};
            io = gr_snapshot_write(snapdir, 0, &p, 0.0, 0, &io_err);
        }
        if (!io) { /* the system, so that `granule analyse DIR` can read the snapshot */
            gr_scene scene;
            gr_scene_default(&scene);
            scene.dim = 2;
            scene.N = place.n;
            scene.L = s.L;
            scene.radius = place.radius;
            snprintf(scene.out_dir, sizeof scene.out_dir, "%s", out);
            snprintf(scene.source, sizeof scene.source, "granule cascade --variant %s --levels %d --seed %lu --place %d",
                     vi->name, s.levels, s.seed, place.n);
            io = gr_scene_save(&scene, out, &io_err);
        }
    }
    if (io) {
        cli_error("%s", io_err.message);
        status = EXIT_FAILED;
        goto done;
    }

    /* plots */
    char plots[600] = "", note[300], body[3000];
    const int skip_sk = 1; /* sk.csv: the column names (notes are in sk.meta.json) */
    char thesis[64] = "none";
    if (isfinite(vi->thesis_D_f)) {
        snprintf(thesis, sizeof thesis, "%.3f +- %.3f", vi->thesis_D_f, vi->thesis_D_f_err);
    }
    if (have_fit) {
        snprintf(body, sizeof body,
                 "set logscale xy\nset format y '10^{%%L}'\nset key bottom left\n"
                 "set xlabel 'k (1/m)'\nset ylabel 'S(k)'\n"
                 "set title \"Multiplicative cascade %s, n = %d, %d configurations: D_f = %.3f +- %.3f "
                 "(Table 6.2: %s)\"\n"
                 "A = %.17g\nD = %.17g\n"
                 "plot 'sk.csv' skip %d using 2:4:5 with yerrorbars pt 7 ps 0.5 lc rgb '#224466' title 'S(k), eq. 6.5', "
                 "'' skip %d using 2:6 with lines lc rgb '#cc6600' dt 2 title 'exact configuration average', "
                 "[%.9g:%.9g] A * x**(-D) with lines lw 2 lc rgb '#cc2222' title 'fit A k^{-D_f}'\n",
                 vi->label, s.levels, s.configurations, fit.D_f, fit.D_f_err, thesis, fit.A, fit.D_f, skip_sk,
                 skip_sk, fit.k_min, fit.k_max);
    } else {
        snprintf(body, sizeof body,
                 "set logscale x\nset xlabel 'k (1/m)'\nset ylabel 'S(k)'\n"
                 "set title \"Multiplicative cascade %s, n = %d, %d configurations (%s)\"\n"
                 "plot 'sk.csv' skip %d using 2:4 with points pt 7 ps 0.5 title 'S(k), eq. 6.5'\n",
                 vi->label, s.levels, s.configurations, fit_note, skip_sk);
    }
    strcat(plots, gr_plot_script(out, "sk.png", body, note, sizeof note) ? note : "sk.png");
    snprintf(body, sizeof body,
             "set size ratio -1\nset xrange [0:%.9g]\nset yrange [0:%.9g]\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n"
             "set palette defined (0 'white', 1 '#99aabb', 2 '#224466', 3 'black')\nset cblabel 'log_{10}(4^{%d} m_{i,j})'\nset cbrange [-4:4]\n"
             "set title \"Cascade field %s, configuration 1 (%d x %d)\"\n"
             "plot 'field.csv' skip 1 using 1:2:($3 > 0 ? log10($3) : 1/0) with image notitle\n",
             s.L, s.L, field_level, vi->label, 1 << field_level, 1 << field_level);
    strcat(plots, ", ");
    strcat(plots, gr_plot_script(out, "field.png", body, note, sizeof note) ? note : "field.png");
    if (do_place) {
        snprintf(body, sizeof body,
                 "set datafile separator whitespace\nset size ratio -1\nset xrange [0:%.9g]\nset yrange [0:%.9g]\n"
                 "set xlabel 'x (m)'\nset ylabel 'y (m)'\nunset grid\n"
                 "set title \"%d discs (r = %g m, phi = %.3f) placed from the %s field (Fig. 6.3)\"\n"
                 "plot 'snapshots/snap_000000.xyz' skip 2 using 2:3:8 with circles fill solid 0.6 noborder "
                 "lc rgb '#224466' notitle\n",
                 s.L, s.L, place.n, place.radius, pres.phi, vi->label);
        strcat(plots, ", ");
        strcat(plots, gr_plot_script(out, "placement.png", body, note, sizeof note) ? note : "placement.png");
    }

    /* summary.json */
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "completed");
    cJSON_AddStringToObject(j, "command", "cascade");
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddStringToObject(j, "variant", vi->name);
    cJSON_AddStringToObject(j, "variant_label", vi->label);
    if (s.variant == GR_CASCADE_MEAKIN || (s.variant >= GR_CASCADE_MEAKIN1 && s.variant <= GR_CASCADE_MEAKIN4)) {
        cJSON_AddItemToObject(j, "p", cJSON_CreateDoubleArray(s.variant == GR_CASCADE_MEAKIN ? s.p : vi->p, 4));
    }
    cJSON_AddNumberToObject(j, "levels", s.levels);
    cJSON_AddNumberToObject(j, "grid", 1 << s.levels);
    cJSON_AddNumberToObject(j, "L", s.L);
    cJSON_AddNumberToObject(j, "configurations", s.configurations);
    cJSON_AddNumberToObject(j, "seed", (double)s.seed);
    cJSON_AddStringToObject(j, "rng", "gsl_rng_mt19937");
    add_number_or_null(j, "D_f", have_fit ? fit.D_f : (double)NAN);
    add_number_or_null(j, "D_f_err", have_fit ? fit.D_f_err : (double)NAN);
    add_number_or_null(j, "D_f_exact_average", have_fit ? fit_exp.D_f : (double)NAN);
    add_number_or_null(j, "D_2", s.variant == GR_CASCADE_UNIFORM ? (double)NAN : gr_cascade_d2(&s));
    add_number_or_null(j, "thesis_D_f", vi->thesis_D_f);
    add_number_or_null(j, "thesis_D_f_err", vi->thesis_D_f_err);
    cJSON *fo = cJSON_AddObjectToObject(j, "fit");
    cJSON_AddStringToObject(fo, "model", "S(k) = A k^-D_f (eq. 4.4), chi-square line in ln k, ln S weighted by S_err");
    cJSON_AddNumberToObject(fo, "q_min", q_min);
    cJSON_AddNumberToObject(fo, "q_max", q_max);
    if (have_fit) {
        cJSON_AddNumberToObject(fo, "k_min", fit.k_min);
        cJSON_AddNumberToObject(fo, "k_max", fit.k_max);
        cJSON_AddNumberToObject(fo, "points", fit.points);
        cJSON_AddNumberToObject(fo, "A", fit.A);
        cJSON_AddNumberToObject(fo, "A_err", fit.A_err);
        add_number_or_null(fo, "chi2_red", fit.chi2_red);
        cJSON_AddNumberToObject(fo, "exact_average_D_f_err", fit_exp.D_f_err);
    } else {
        cJSON_AddStringToObject(fo, "note", fit_note);
    }
    cJSON *to = cJSON_AddObjectToObject(j, "total_probability");
    cJSON_AddNumberToObject(to, "mean", t_mean[s.levels]);
    cJSON_AddNumberToObject(to, "sd", s.configurations > 1 ? sqrt(t_m2[s.levels] / (s.configurations - 1)) : 0.0);
    cJSON_AddNumberToObject(to, "min", t_lo[s.levels]);
    cJSON_AddNumberToObject(to, "max", t_hi[s.levels]);
    cJSON_AddBoolToObject(to, "conserving", vi->conserving);
    cJSON_AddNumberToObject(j, "wall_seconds", wall);
    cJSON_AddNumberToObject(j, "seconds_per_configuration", (wall - place_seconds) / s.configurations);
    if (do_place) {
        cJSON *po = cJSON_AddObjectToObject(j, "placement");
        cJSON_AddNumberToObject(po, "N", place.n);
        cJSON_AddNumberToObject(po, "radius", place.radius);
        cJSON_AddNumberToObject(po, "L", s.L);
        cJSON_AddNumberToObject(po, "phi", pres.phi);
        cJSON_AddNumberToObject(po, "attempts", (double)pres.attempts);
        cJSON_AddNumberToObject(po, "rejected_overlaps", (double)pres.rejected);
        cJSON_AddNumberToObject(po, "seed", (double)derived_seed(s.seed));
        cJSON_AddStringToObject(po, "snapshot", "snapshots/snap_000000.xyz");
        cJSON_AddNumberToObject(po, "wall_seconds", place_seconds);
    }
    cJSON_AddStringToObject(j, "plots", plots);
    char *text = cJSON_Print(j);
    cJSON_Delete(j);
    gr_file f;
    io = text ? gr_file_open(&f, out, "summary.json", &io_err) : GR_FAIL(&io_err, GR_ENOMEM, "cascade: out of memory");
    if (!io) {
        fputs(text, f.f);
        fputc('\n', f.f);
        io = gr_file_commit(&f, &io_err);
    }
    cJSON_free(text);
    if (io) {
        cli_error("%s", io_err.message);
        status = EXIT_FAILED;
        goto done;
    }
    if (have_fit) {
        printf("%s: %s, %d levels, %d configuration%s: D_f = %.3f +- %.3f over k L/2pi = %g..%g "
               "(exact average %.3f, D_2 = %.3f; Table 6.2: %s) in %.2f s\n",
               out, vi->label, s.levels, s.configurations, s.configurations == 1 ? "" : "s", fit.D_f, fit.D_f_err, q_min, q_max, fit_exp.D_f,
               gr_cascade_d2(&s), thesis, wall);
    } else {
        printf("%s: %s, %d levels, %d configuration%s: %s; %.2f s\n", out, vi->label, s.levels, s.configurations,
               s.configurations == 1 ? "" : "s", fit_note, wall);
    }
    if (do_place) {
        printf("%s: %d discs placed (phi = %.3f, %lld attempts) -> %s/snap_000000.xyz\n", out, place.n, pres.phi,
               (long long)pres.attempts, snapdir);
    }

done:
    free(totals);
    free(t_mean);
    free(t_m2);
    free(t_lo);
    free(t_hi);
    free(px);
    free(py);
    free(pv);
    free(coarse);
    free(bins);
    gr_cascade_field_free(field);
    gr_cascade_sk_free(sk);
    if (rng) {
        gsl_rng_free(rng);
    }
    if (prng) {
        gsl_rng_free(prng);
    }
    return status;
}
