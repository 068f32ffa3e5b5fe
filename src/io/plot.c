/* Plots drawn by gnuplot (src/io/plot.h, docs/plots.md): one preamble for every picture, the
 * format (pngcairo, svg, pdfcairo), the run's temperature and ledger plots, and the list of
 * pictures a folder holds for its summary.json. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/compare.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

/* Okabe-Ito's colour-blind-safe set without its yellow, orange and sky blue, completed by black, wine,
 * brown and purple: every colour has a contrast ratio of at least 3:1 against white. */
const char *const gr_plot_palette[GR_PLOT_COLOURS] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                                      "#000000", "#882255", "#8c510a", "#5e3c99"};

static gr_plot_format g_format = GR_PLOT_PNG;
static const char *const extensions[] = {"png", "svg", "pdf"};

int gr_plot_format_parse(const char *name)
{
    for (int f = 0; f < 3; f++) {
        if (!strcmp(name, extensions[f])) {
            return f;
        }
    }
    return -1;
}

const char *gr_plot_extension(gr_plot_format f) { return extensions[(unsigned)f < 3 ? f : 0]; }

void gr_plot_set_format(gr_plot_format f) { g_format = (unsigned)f < 3 ? f : GR_PLOT_PNG; }

gr_plot_format gr_plot_get_format(void) { return g_format; }

void gr_plot_file_name(const char *png_name, char *buf, size_t size)
{
    const char *dot = strrchr(png_name, '.');
    const int stem = dot ? (int)(dot - png_name) : (int)strlen(png_name);
    snprintf(buf, size, "%.*s.%s", stem, png_name, gr_plot_extension(g_format));
}

void gr_plot_series_style(int k, char *buf, size_t size)
{
    k = k < 0 ? 0 : k;
    static const int dash[4] = {
        1, 2, 4, 5}; /* solid, dashed, dash-dot, dash-dot-dot: no dots, which vanish */
    snprintf(buf, size, "lc rgb '%s' dt %d lw 2", gr_plot_palette[k % GR_PLOT_COLOURS],
             dash[k % 4]);
}

/* Which of x and y the body puts on a log scale (log[0] = x, log[1] = y) and which it chooses the
 * tick format of (format[0], format[1]). */
static void scan_axes(const char *body, bool log[2], bool format[2])
{
    log[0] = log[1] = format[0] = format[1] = false;
    for (const char *line = body; line && *line;
         line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        while (*line == ' ') {
            line++;
        }
        const char *rest = NULL;
        bool *which = NULL;
        if (!strncmp(line, "set logscale", 12) || !strncmp(line, "set log ", 8)) {
            rest = line + (line[7] == 's' ? 12 : 8);
            which = log;
        } else if (!strncmp(line, "set format", 10)) {
            rest = line + 10;
            which = format;
        }
        if (!which) {
            continue;
        }
        while (*rest == ' ') {
            rest++;
        }
        /* "set logscale" alone or "set format '...'" apply to every axis */
        const bool all = *rest == '\n' || *rest == 0 || *rest == '\'' || *rest == '"';
        for (const char *c = rest; *c && *c != ' ' && *c != '\n' && *c != '\'' && *c != '"'; c++) {
            which[0] |= *c == 'x' && c[1] != '2';
            which[1] |= *c == 'y' && c[1] != '2';
        }
        which[0] |= all;
        which[1] |= all;
    }
}

/* How many lines of body start with `start` (after spaces). */
static int count_lines(const char *body, const char *start)
{
    int n = 0;
    for (const char *line = body; line && *line;
         line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        while (*line == ' ') {
            line++;
        }
        n += !strncmp(line, start, strlen(start));
    }
    return n;
}

static bool has_line(const char *body, const char *start) { return count_lines(body, start) > 0; }

char *gr_plot_compose(const char *body, const char *output, gr_plot_format f)
{
    static const char *const terminals[] = {
        "set terminal pngcairo size 1280,800 enhanced font 'Sans,18' linewidth 1.5",
        "set terminal svg size 1280,800 dynamic enhanced font 'Sans,18' linewidth 1.5 background "
        "'#ffffff'",
        "set terminal pdfcairo size 8in,5in enhanced font 'Sans,10' linewidth 1.5",
    };
    const size_t size = strlen(body) + strlen(output) + 4096;
    char *s = malloc(size);
    if (!s) {
        return NULL;
    }
    size_t len = (size_t)snprintf(
        s, size, "%s\nset encoding utf8\nset datafile separator ','\nset linetype cycle %d\n",
        terminals[(unsigned)f < 3 ? f : 0], GR_PLOT_COLOURS);
    /* the palette as line types (any "lc N" or default colour is one of them); points filled */
    for (int k = 0; k < GR_PLOT_COLOURS; k++) {
        len +=
            (size_t)snprintf(s + len, size - len, "set linetype %d lc rgb '%s' lw 2 pt 7 ps 0.8\n",
                             k + 1, gr_plot_palette[k]);
    }
    /* ticks: "%h" prints 1e-05 as 1x10^{-5} and 100 as 100, never 0.000010 or 100.0000000;
     * log axes read 10^{n}. Margins: autoscaled ranges reach 3-6 % beyond the data, so no point or
     * error bar sits on the frame. The body may override any of this. */
    bool log[2], format[2];
    scan_axes(body, log, format);
    len += (size_t)snprintf(
        s + len, size - len,
        "set format x '%s'\nset format y '%s'\n%s%sset offsets graph 0.03, graph 0.03, graph 0.06, "
        "graph 0.06\n"
        "set grid lc rgb '#d0d0d0' lw 1 dt 1\nset border lw 1.5\nset key noopaque samplen 2.5\n",
        log[0] && !format[0] ? "10^{%L}" : "%h", log[1] && !format[1] ? "10^{%L}" : "%h",
        log[0] ? "" : "set autoscale xfix\n", log[1] ? "" : "set autoscale yfix\n");
    /* a linear axis ends at the data plus the margin (the offsets); gnuplot would end an
     * autoscaled log axis at whole decades (1-100 for data at 1.7-18) and ignores the offsets
     * there, so a body with one plot and log axes of its own range is drawn once on a dummy
     * terminal to learn the data's range (GPVAL_DATA_*), and the log axes are then fitted to it
     * with a margin of a few % of the span; under two decades they get ticks at 1, 2, 5 x 10^n
     * so that they always carry labels. A one-panel multiplot (a title over the whole canvas) is
     * fitted alike, but drawn again from its body: replot does not repeat a multiplot */
    bool fit[2] = {log[0] && !has_line(body, "set xrange") && !strstr(body, "plot ["),
                   log[1] && !has_line(body, "set yrange") && !strstr(body, "plot [")};
    const bool multiplot = strstr(body, "multiplot") != NULL;
    if (!(fit[0] || fit[1]) || count_lines(body, "plot ") != 1 ||
        (multiplot && !strstr(body, "multiplot layout 1,1"))) {
        snprintf(s + len, size - len, "set output '%s'\n%s\nset output\n", output, body);
        return s;
    }
    len += (size_t)snprintf(s + len, size - len,
                            "set terminal push\nset terminal dumb\nset output '/dev/null'\n%s\n",
                            body);
    for (int a = 0; a < 2; a++) {
        const char axis = a ? 'y' : 'x';
        const char *const A = a ? "Y" : "X";
        if (fit[a]) {
            len += (size_t)snprintf(s + len, size - len,
                                    "gr_lo = GPVAL_DATA_%s_MIN; gr_hi = GPVAL_DATA_%s_MAX\n"
                                    "if (gr_lo > 0 && gr_hi > gr_lo) { gr_f = (gr_hi / gr_lo)**%s; "
                                    "set %crange [gr_lo / gr_f:gr_hi * gr_f]; "
                                    "if (gr_hi / gr_lo < 100) { set %ctics (1e300); do for [gr_n = "
                                    "floor(log10(gr_lo)) : "
                                    "ceil(log10(gr_hi))] { set %ctics add (10.0**gr_n, 2 * "
                                    "10.0**gr_n, 5 * 10.0**gr_n) }; "
                                    "set format %c '%%h' } }\n",
                                    A, A, a ? "0.06" : "0.03", axis, axis, axis, axis);
        }
    }
    snprintf(s + len, size - len, "set terminal pop\nset output '%s'\n%s\nset output\n", output,
             multiplot ? body : "replot");
    return s;
}

void gr_plot_legend_value(const char *name, double value, double error, char *buf, size_t size)
{
    char num[96];
    gr_compare_format(value, error, num, sizeof num);
    char *pm = strstr(num, " +- ");
    if (pm) { /* the plots are UTF-8 */
        char tail[96];
        snprintf(tail, sizeof tail, "%s", pm + 4);
        snprintf(pm, sizeof num - (size_t)(pm - num), " \u00b1 %s", tail);
    }
    snprintf(buf, size, "%s = %s", name, num);
}

static int gnuplot_available(void) { return system("command -v gnuplot >/dev/null 2>&1") == 0; }

int gr_plot_script(const char *dir, const char *png_name, const char *body, char *note,
                   size_t note_size)
{
    if (!gnuplot_available()) {
        snprintf(note, note_size, "skipped: gnuplot not found (apt-get install gnuplot-nox)");
        return 1;
    }
    char picture[300], gp[300];
    gr_plot_file_name(png_name, picture, sizeof picture);
    snprintf(gp, sizeof gp, "%.*s.gp", (int)(strrchr(picture, '.') - picture), picture);
    /* keep the body beside the picture so `granule plot DIR` can redraw it */
    gr_file script;
    gr_error gp_err = {0};
    if (gr_file_open(&script, dir, gp, &gp_err) == GR_OK) {
        fprintf(script.f,
                "# granule: gnuplot body of %s (run inside this folder); granule plot DIR redraws "
                "it\n%s\n",
                gp, body);
        if (gr_file_commit(&script, &gp_err) != GR_OK) {
            snprintf(note, note_size, "failed: %s", gp_err.message);
            return 1;
        }
    }
    char tmp[340];
    snprintf(tmp, sizeof tmp, "%s.tmp", picture);
    char *text = gr_plot_compose(body, tmp, g_format);
    if (!text) {
        snprintf(note, note_size, "failed: out of memory");
        return 1;
    }
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "cd '%s' && gnuplot >/dev/null 2>&1", dir);
    FILE *g = popen(cmd, "w");
    if (!g) {
        free(text);
        snprintf(note, note_size, "skipped: could not start gnuplot");
        return 1;
    }
    fputs(text, g);
    free(text);
    int rc = pclose(g);
    char from[1200], to[1200];
    snprintf(from, sizeof from, "%s/%s", dir, tmp);
    snprintf(to, sizeof to, "%s/%s", dir, picture);
    if (rc != 0 || rename(from, to) != 0) {
        remove(from);
        snprintf(note, note_size, "failed: gnuplot could not draw %s", picture);
        return 1;
    }
    return 0;
}

int gr_plot_run(const char *dir, int dim, char *note, size_t note_size)
{
    (void)dim;
    char palette[2][80];
    gr_plot_series_style(0, palette[0], sizeof palette[0]);
    gr_plot_series_style(1, palette[1], sizeof palette[1]);
    char body[2400];
    snprintf(
        body, sizeof body,
        "set title \"Granular temperature\\n{/*0.75 eq. (2.19); running mean over the sampling "
        "phase}\"\n"
        "set xlabel 't (s)'\nset ylabel 'T (m^2/s^2)'\nset key top right\n"
        "plot 'temperature.csv' skip 1 using 1:2 with lines lw 1 lc rgb '#a0a0a0' title 'T(t)', "
        "'' skip 1 using 1:3 with lines lw 3 lc rgb '%s' title 'running mean'\n",
        gr_plot_palette[1]);
    if (gr_plot_script(dir, "temperature.png", body, note, note_size)) {
        return 1;
    }
    snprintf(
        body, sizeof body,
        "set title \"Energy ledger\\n{/*0.75 residual = kinetic + elastic - initial - injected + "
        "dissipated}\"\n"
        "set xlabel 't (s)'\nset ylabel 'energy (J)'\nset key top left\n"
        "plot 'ledger.csv' skip 1 using 1:4 with lines lw 3 lt 1 title 'injected by noise', "
        "'' skip 1 using 1:($5+$6+$7) with lines lw 3 lt 2 title 'dissipated (all)', "
        "'' skip 1 using 1:5 with lines dt 2 lt 3 title 'dissipated normal', "
        "'' skip 1 using 1:($6+$7) with lines dt 4 lt 4 title 'dissipated tangential + friction', "
        "'' skip 1 using 1:($2+$3) with lines lt 6 title 'kinetic + elastic', "
        "'' skip 1 using 1:9 with lines lt 5 dt 3 title 'residual'\n");
    return gr_plot_script(dir, "ledger.png", body, note, note_size);
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The pictures directly in dir (names prefixed with `prefix`) added to names[*n]. */
static void scan_pictures(const char *dir, const char *prefix, char **names, int *n, int max)
{
    DIR *d = opendir(dir);
    if (!d) {
        return;
    }
    for (struct dirent *e; (e = readdir(d)) && *n < max;) {
        const char *dot = strrchr(e->d_name, '.');
        if (dot && gr_plot_format_parse(dot + 1) >= 0) {
            size_t len = strlen(prefix) + strlen(e->d_name) + 1;
            names[*n] = malloc(len);
            if (names[*n]) {
                snprintf(names[*n], len, "%s%s", prefix, e->d_name);
                (*n)++;
            }
        }
    }
    closedir(d);
}

int gr_plot_list(const char *dir, cJSON *list)
{
    char *names[512];
    int n = 0;
    char sub[1200];
    scan_pictures(dir, "", names, &n, 512);
    snprintf(sub, sizeof sub, "%s/analysis", dir);
    scan_pictures(sub, "analysis/", names, &n, 512);
    qsort(names, (size_t)n, sizeof names[0], compare_names);
    for (int i = 0; i < n; i++) {
        cJSON_AddItemToArray(list, cJSON_CreateString(names[i]));
        free(names[i]);
    }
    return n;
}

int gr_plot_summary_update(const char *dir)
{
    gr_error err = {0};
    cJSON *s = gr_summary_read(dir, &err);
    if (!s) {
        return err.code ? err.code : GR_EIO;
    }
    const cJSON *old = cJSON_GetObjectItem(s, "plots");
    /* the run's own text is a list of files ("temperature.png, ledger.png") or a note why not */
    if (cJSON_IsString(old) && !strstr(old->valuestring, ".png") &&
        strcmp(old->valuestring, "not requested")) {
        cJSON *notes = cJSON_GetObjectItem(s, "plot_notes");
        if (!notes) {
            notes = cJSON_AddArrayToObject(s, "plot_notes");
        }
        cJSON_AddItemToArray(notes, cJSON_CreateString(old->valuestring));
    }
    cJSON *list = cJSON_CreateArray();
    gr_plot_list(dir, list);
    cJSON_ReplaceItemInObject(s, "plots", list);
    int rc = gr_json_write(dir, "summary.json", s, &err);
    cJSON_Delete(s);
    return rc;
}
