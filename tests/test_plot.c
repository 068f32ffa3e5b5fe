/* Tests of the plots (src/io/plot.c, the observables' gnuplot bodies): asserted on the gnuplot
 * text, not on pixels. The shared preamble (palette as line types, tick formats "%h" and 10^{n} on
 * log axes, margins, terminals per format); every body a 1D and a 2D run write: no fixed-point
 * tick formats, colours from the palette or greys only, titles whose first line has no equation
 * number, fits drawn over their window with value and error, explicit ranges that cover the data;
 * --format svg/pdf files; summary.json listing every picture. */
#include <check.h>
#include <cjson/cJSON.h>
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/run.h"
#include "granule/scene.h"
#include "io/plot.h"
#include "io/summary_read.h"
#include "check_main.h"

static char g_dir[256];

static void setup(void)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(g_dir, sizeof g_dir, "%s/granule-test-plot-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    ck_assert_msg(mkdtemp(g_dir) != NULL, "mkdtemp: %s", strerror(errno));
    gr_plot_set_format(GR_PLOT_PNG);
}

static void teardown(void)
{
    if (!gr_test_keep_tmp()) {
        gr_test_rm_tree(g_dir);
    }
    gr_plot_set_format(GR_PLOT_PNG);
}

static bool have_gnuplot(void) { return system("command -v gnuplot >/dev/null 2>&1") == 0; }

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "%s: %s", path, strerror(errno));
    char *buf = calloc(1, 1 << 17);
    size_t n = fread(buf, 1, (1 << 17) - 1, f);
    fclose(f);
    buf[n] = 0;
    return buf;
}

START_TEST(test_compose)
{
    char *s = gr_plot_compose("set logscale xy\nplot 'a.csv' using 1:2", "a.png", GR_PLOT_PNG);
    ck_assert(strstr(s, "set terminal pngcairo"));
    ck_assert(strstr(s, "set format x '10^{%L}'") && strstr(s, "set format y '10^{%L}'"));
    ck_assert(strstr(s, "set offsets graph"));
    for (int k = 0; k < GR_PLOT_COLOURS; k++) {
        char lt[80];
        snprintf(lt, sizeof lt, "set linetype %d lc rgb '%s'", k + 1, gr_plot_palette[k]);
        ck_assert_msg(strstr(s, lt), "no line type %d from the palette", k + 1);
    }
    /* log axes: drawn once on a dummy terminal, fitted to the data's range, then drawn for real */
    ck_assert(strstr(s, "set terminal dumb\nset output '/dev/null'\nset logscale xy"));
    ck_assert(strstr(s, "GPVAL_DATA_X_MIN") && strstr(s, "GPVAL_DATA_Y_MIN") &&
              strstr(s, "set xtics add (10.0**gr_n"));
    ck_assert(strstr(s, "set terminal pop\nset output 'a.png'\nreplot\nset output\n"));
    free(s);
    /* a one-panel multiplot is fitted alike but drawn again from its body (replot would draw
     * only its last plot); one of several panels is not (one range would not suit them all) */
    s = gr_plot_compose("set logscale y\nset multiplot layout 1,1 title 'T'\nplot 'a.csv' using "
                        "1:2\nunset multiplot",
                        "m.png", GR_PLOT_PNG);
    ck_assert(strstr(s, "GPVAL_DATA_Y_MIN") && !strstr(s, "replot") &&
              strstr(s, "set terminal pop\nset output 'm.png'\nset logscale y\nset multiplot"));
    free(s);
    s = gr_plot_compose("set logscale y\nset multiplot layout 1,2\nplot 'a.csv' using "
                        "1:2\nunset multiplot",
                        "m2.png", GR_PLOT_PNG);
    ck_assert(!strstr(s, "GPVAL_DATA_Y_MIN") && !strstr(s, "replot"));
    free(s);
    /* a body with its own range, or no log axis, is drawn once as it is */
    s = gr_plot_compose("set logscale x\nset xrange [1:10]\nplot x", "r.png", GR_PLOT_PNG);
    ck_assert(!strstr(s, "replot") && strstr(s, "set output 'r.png'\nset logscale x"));
    free(s);
    /* a linear axis reads %h; a log axis whose format the body chooses keeps the body's */
    s = gr_plot_compose("set logscale y\nset format y '%g'\nplot x", "b.svg", GR_PLOT_SVG);
    ck_assert(strstr(s, "set terminal svg") && strstr(s, "set format x '%h'") &&
              strstr(s, "set format y '%h'"));
    free(s);
    s = gr_plot_compose("set log x\nplot x", "c.pdf", GR_PLOT_PDF);
    ck_assert(strstr(s, "set terminal pdfcairo") && strstr(s, "set format x '10^{%L}'") &&
              strstr(s, "set format y '%h'"));
    free(s);
    s = gr_plot_compose("set logscale\nplot x", "d.png", GR_PLOT_PNG);
    ck_assert(strstr(s, "set format x '10^{%L}'") && strstr(s, "set format y '10^{%L}'"));
    free(s);
    /* formats and file names */
    ck_assert_int_eq(gr_plot_format_parse("svg"), GR_PLOT_SVG);
    ck_assert_int_eq(gr_plot_format_parse("jpeg"), -1);
    char name[64];
    gr_plot_set_format(GR_PLOT_PDF);
    gr_plot_file_name("gaps_lnR.png", name, sizeof name);
    ck_assert_str_eq(name, "gaps_lnR.pdf");
    /* legends: value +- error as in the compare table */
    char legend[96];
    gr_plot_legend_value("D_f", 1.6312, 0.0412, legend, sizeof legend);
    ck_assert_str_eq(legend, "D_f = 1.631 \u00b1 0.041");
    gr_plot_legend_value("alpha", 1.5, NAN, legend, sizeof legend);
    ck_assert_str_eq(legend, "alpha = 1.5");
}
END_TEST

/* A log axis ends at the data (plus a few %), not at whole decades: data at 1.7-18 gave 1-100
 * (gaps_lnR, issue 38); under two decades its ticks are 1, 2, 5 x 10^n, so it carries labels. So
 * too in a one-panel multiplot (a campaign's data figure), which had spanned 10^-3..10^1 for data
 * at 0.04-0.23. */
START_TEST(test_log_axis_fits_data)
{
    if (!have_gnuplot()) {
        return;
    }
    char path[400], cmd[900];
    snprintf(path, sizeof path, "%s/lg.csv", g_dir);
    FILE *f = fopen(path, "w");
    fprintf(f, "x,y\n1.7,1e-3\n3,1e-2\n10,0.1\n18,0.05\n");
    fclose(f);
    const char *bodies[] = {
        "set logscale xy\nplot 'lg.csv' skip 1 using 1:2 with linespoints",
        "set logscale xy\nset multiplot layout 1,1 title 'one panel'\nplot 'lg.csv' skip 1 using "
        "1:2 with linespoints\nunset multiplot"};
    for (int b = 0; b < 2; b++) {
        char *s = gr_plot_compose(bodies[b], "lg.svg", GR_PLOT_SVG);
        snprintf(path, sizeof path, "%s/lg.plt", g_dir);
        f = fopen(path, "w");
        fprintf(
            f, "%sset print 'lg.range'\nprint GPVAL_X_MIN, GPVAL_X_MAX, GPVAL_Y_MIN, GPVAL_Y_MAX\n",
            s);
        fclose(f);
        free(s);
        snprintf(cmd, sizeof cmd, "cd '%s' && rm -f lg.svg && gnuplot lg.plt 2>/dev/null", g_dir);
        ck_assert_int_eq(system(cmd), 0);
        snprintf(path, sizeof path, "%s/lg.range", g_dir);
        double x0, x1, y0, y1;
        f = fopen(path, "r");
        ck_assert_ptr_nonnull(f);
        ck_assert_int_eq(fscanf(f, "%lf %lf %lf %lf", &x0, &x1, &y0, &y1), 4);
        fclose(f);
        ck_assert_msg(x0 > 1.5 && x0 < 1.7 && x1 > 18.0 && x1 < 21.0,
                      "body %d: x axis %g..%g for data at 1.7..18", b, x0, x1);
        ck_assert_msg(y0 > 5e-4 && y0 < 1e-3 && y1 > 0.1 && y1 < 0.2,
                      "body %d: y axis %g..%g for data at 1e-3..0.1", b, y0, y1);
        snprintf(path, sizeof path, "%s/lg.svg", g_dir);
        char *svg = slurp(path);
        ck_assert_msg(strstr(svg, "<svg"), "body %d: no SVG drawn", b);
        free(svg);
    }
}
END_TEST

/* --format svg and pdf draw real SVG and PDF files (and the body is kept as NAME.gp) */
START_TEST(test_formats)
{
    if (!have_gnuplot()) {
        return;
    }
    FILE *f;
    char path[400], note[300];
    snprintf(path, sizeof path, "%s/d.csv", g_dir);
    f = fopen(path, "w");
    fprintf(f, "x,y\n1,1\n2,4\n3,9\n");
    fclose(f);
    const char *body =
        "set title 'Squares'\nplot 'd.csv' skip 1 using 1:2 with linespoints title 'y'";
    const gr_plot_format fmts[] = {GR_PLOT_SVG, GR_PLOT_PDF, GR_PLOT_PNG};
    const char *magic[] = {"<svg", "%PDF", "\x89PNG"};
    for (int i = 0; i < 3; i++) {
        gr_plot_set_format(fmts[i]);
        ck_assert_msg(gr_plot_script(g_dir, "d.png", body, note, sizeof note) == 0, "%s", note);
        snprintf(path, sizeof path, "%s/d.%s", g_dir, gr_plot_extension(fmts[i]));
        char *text = slurp(path);
        ck_assert_msg(fmts[i] == GR_PLOT_SVG ? strstr(text, magic[i]) != NULL
                                             : !memcmp(text, magic[i], 4),
                      "%s is no %s", path, gr_plot_extension(fmts[i]));
        free(text);
    }
    snprintf(path, sizeof path, "%s/d.gp", g_dir);
    char *gp = slurp(path);
    ck_assert(strstr(gp, body));
    free(gp);
    cJSON *list = cJSON_CreateArray();
    ck_assert_int_eq(gr_plot_list(g_dir, list), 3);
    ck_assert_str_eq(cJSON_GetArrayItem(list, 0)->valuestring, "d.pdf");
    cJSON_Delete(list);
}
END_TEST

/* the title's first line: from `set title "` or `'` to the first \n (escaped) or the closing quote */
static void title_first_line(const char *body, char *out, size_t size)
{
    out[0] = 0;
    const char *t = strstr(body, "set title ");
    if (!t) {
        return;
    }
    t += 10;
    const char quote = *t++;
    size_t n = 0;
    while (*t && *t != quote && !(t[0] == '\\' && t[1] == 'n') && n + 1 < size) {
        out[n++] = *t++;
    }
    out[n] = 0;
}

static bool palette_or_grey(const char *hex)
{
    if (!strncmp(hex, "gray'", 5) || !strncmp(hex, "grey'", 5) || !strncmp(hex, "black'", 6)) {
        return true;
    }
    for (int k = 0; k < GR_PLOT_COLOURS; k++) {
        if (!strncasecmp(hex, gr_plot_palette[k], 7)) {
            return true;
        }
    }
    unsigned r, g, b;
    return sscanf(hex, "#%2x%2x%2x", &r, &g, &b) == 3 && r == g && g == b;
}

/* Every body in dir: composed, it has no fixed-point tick format; its colours are the palette's
 * or greys; its title's first line is words (no equation number); the names found are returned
 * in `seen`. */
static void check_bodies(const char *dir, char *seen, size_t seen_size)
{
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    for (struct dirent *e; (e = readdir(d));) {
        size_t len = strlen(e->d_name);
        if (len < 4 || strcmp(e->d_name + len - 3, ".gp")) {
            continue;
        }
        snprintf(seen + strlen(seen), seen_size - strlen(seen), "%s ", e->d_name);
        char path[600];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        char *body = slurp(path);
        char *script = gr_plot_compose(body, "x.png", GR_PLOT_PNG);
        for (const char *p = script; (p = strstr(p, "set format")); p++) {
            const char *q = strchr(p, '\'');
            q = q ? q : strchr(p, '"');
            ck_assert_msg(q && !strstr(q, "f'") && !strstr(q, "f\"") && strncmp(q + 1, "%.", 2),
                          "%s: tick format %.40s", e->d_name, p);
        }
        for (const char *p = body; (p = strstr(p, "rgb '")); p++) {
            ck_assert_msg(palette_or_grey(p + 5),
                          "%s: colour %.12s is neither the palette's nor a grey", e->d_name, p + 5);
        }
        char title[300];
        title_first_line(body, title, sizeof title);
        for (const char *c = title; *c; c++) {
            ck_assert_msg(!(c[0] == '(' && isdigit((unsigned char)c[1]) && c[2] == '.'),
                          "%s: equation number in the title '%s'", e->d_name, title);
            ck_assert_msg(strncmp(c, "Fig.", 4) && strncmp(c, "App.", 4),
                          "%s: reference in the title '%s'", e->d_name, title);
        }
        free(script);
        free(body);
    }
    closedir(d);
}

static void run_scene(const char *name, const char *text)
{
    char path[400];
    snprintf(path, sizeof path, "%s/%s.ini", g_dir, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, path, NULL, 0, &err) == GR_OK, "%s", err.message);
    snprintf(s.out_dir, sizeof s.out_dir, "%s/%s", g_dir, name);
    gr_run_options opt = {0};
    gr_run_result res;
    ck_assert_msg(gr_run(&s, &opt, &res, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_plot_summary_update(s.out_dir), GR_OK);
}

/* a body's value of `what` (e.g. "set xrange [") as two numbers */
static bool range_of(const char *body, const char *what, double *lo, double *hi)
{
    const char *p = strstr(body, what);
    return p && sscanf(p + strlen(what), "%lf:%lf", lo, hi) == 2;
}

START_TEST(test_run_bodies)
{
    if (!have_gnuplot()) {
        return;
    }
    run_scene("one", "[system]\ndim = 1\nN = 100\nreduced_length = 0.5\n[placement]\nkind = "
                     "uniform\n[noise]\nD = 1e-8\n[integrator]\ndt = 1e-6\n"
                     "[run]\nwarmup = 0.02\nduration = 0.1\nsample_every = 1e-3\n"
                     "[analysis]\nobservables = moments, pv, freepath, gaps, msd, vacf, clusters, "
                     "collisions, postcollision\n"
                     "[output]\nplots = true\nsnapshot_every = 0.01\n");
    run_scene("two", "[system]\ndim = 2\nN = 300\nL = 0.1\n[model]\ntangential = "
                     "tangential_dashpot\n[noise]\nD = 1e-8\n"
                     "[run]\nwarmup = 0.002\nduration = 0.01\nsample_every = 1e-3\n"
                     "[analysis]\nobservables = moments, pv, sk, pair, vcorr, "
                     "pressure\n[output]\nplots = true\n");
    char seen[4096] = "", dir[400];
    snprintf(dir, sizeof dir, "%s/one", g_dir);
    check_bodies(dir, seen, sizeof seen);
    snprintf(dir, sizeof dir, "%s/two", g_dir);
    check_bodies(dir, seen, sizeof seen);
    const char *must[] = {"temperature.gp", "ledger.gp",   "moments.gp", "pv.gp", "gaps.gp",
                          "gaps_lnR.gp",    "freepath.gp", "msd.gp",     "sk.gp", "pair_g.gp"};
    for (size_t i = 0; i < sizeof must / sizeof must[0]; i++) {
        ck_assert_msg(strstr(seen, must[i]), "no %s among %s", must[i], seen);
    }
    char path[500];
    /* fits over their window, value +- error in the legend */
    snprintf(path, sizeof path, "%s/one/gaps_lnR.gp", g_dir);
    char *b = slurp(path);
    ck_assert_msg(strstr(b, "n_N = ") && strstr(b, "\u00b1"), "%s", b);
    double lo, hi;
    ck_assert_msg(range_of(b, ", [", &lo, &hi) && lo > 0.0 && hi > lo,
                  "gaps_lnR: the fit has no window: %s", b);
    free(b);
    snprintf(path, sizeof path, "%s/one/msd.gp", g_dir);
    b = slurp(path);
    ck_assert_msg(range_of(b, ", [", &lo, &hi) && hi > lo && strstr(b, "D_{self} (m^2/s) = ") &&
                      strstr(b, "\u00b1"),
                  "%s", b);
    free(b);
    snprintf(path, sizeof path, "%s/one/pv.gp", g_dir);
    b = slurp(path);
    ck_assert_msg(strstr(b, "abs($1) >= ") && strstr(b, "\u03b1"),
                  "pv: the tail fit is not limited to its window: %s", b);
    /* pv's explicit x range covers every bin with counts */
    ck_assert(range_of(b, "set xrange [", &lo, &hi));
    free(b);
    snprintf(path, sizeof path, "%s/one/pv.csv", g_dir);
    b = slurp(path);
    char *line = strchr(b, '\n');
    int rows = 0;
    while (line && *++line) {
        double v, dens, derr, counts;
        if (sscanf(line, "%lf,%lf,%lf,%lf", &v, &dens, &derr, &counts) == 4 && counts > 0.0) {
            ck_assert_msg(v > lo && v < hi, "pv bin at v = %g outside the plotted range [%g, %g]",
                          v, lo, hi);
            rows++;
        }
        line = strchr(line, '\n');
    }
    ck_assert_int_gt(rows, 10);
    free(b);
    /* S(k): both the circular average and the shells carry error bars, legends in words */
    snprintf(path, sizeof path, "%s/two/sk.gp", g_dir);
    b = slurp(path);
    ck_assert_msg(
        strstr(b, "'sk_shells.csv' skip 1 using 3:($4 > 0 ? $4 : 1/0):5 with yerrorbars") &&
            strstr(b, "circular average") && strstr(b, "exact shells"),
        "%s", b);
    free(b);
    /* moments: no explicit range, so the margins of the preamble hold (no point on the frame) */
    snprintf(path, sizeof path, "%s/one/moments.gp", g_dir);
    b = slurp(path);
    ck_assert(!strstr(b, "set xrange") && !strstr(b, "set yrange"));
    free(b);
    /* gaps: series in palette line types, h = 8 (5th series) black, not gnuplot's yellow */
    snprintf(path, sizeof path, "%s/one/gaps.gp", g_dir);
    b = slurp(path);
    ck_assert_msg(strstr(b, "lt 5 pt 7 ps 0.5 title 'h = 8'") && !strstr(b, "lc 5"), "%s", b);
    free(b);
    /* summary.json lists every picture of the folder */
    for (int k = 0; k < 2; k++) {
        snprintf(dir, sizeof dir, "%s/%s", g_dir, k ? "two" : "one");
        gr_error err = {0};
        cJSON *s = gr_summary_read(dir, &err);
        const cJSON *plots = cJSON_GetObjectItem(s, "plots");
        ck_assert(cJSON_IsArray(plots));
        cJSON *want = cJSON_CreateArray();
        ck_assert_int_eq(gr_plot_list(dir, want), cJSON_GetArraySize(plots));
        ck_assert_int_gt(cJSON_GetArraySize(plots), k ? 8 : 12);
        for (int i = 0; i < cJSON_GetArraySize(plots); i++) {
            ck_assert_str_eq(cJSON_GetArrayItem(plots, i)->valuestring,
                             cJSON_GetArrayItem(want, i)->valuestring);
        }
        bool has_snapshots = false;
        for (int i = 0; i < cJSON_GetArraySize(plots); i++) {
            has_snapshots |= !strcmp(cJSON_GetArrayItem(plots, i)->valuestring, "snapshots.png");
        }
        ck_assert(has_snapshots == (k == 0));
        cJSON_Delete(want);
        cJSON_Delete(s);
    }
}
END_TEST

static Suite *plot_suite(void)
{
    Suite *s = suite_create("plot");
    TCase *tc = tcase_create("plot");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_compose);
    tcase_add_test(tc, test_log_axis_fits_data);
    tcase_add_test(tc, test_formats);
    tcase_add_test(tc, test_run_bodies);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(plot_suite()); }
