/* A campaign's result set: results.csv (one row per number, every field), results.json (the same
 * plus the campaign's description, cost and provenance), one data CSV per result and its figures
 * with the thesis's values overlaid. Small files, meant to be committed under docs/results/NAME. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "granule/campaign.h"
#include "granule/scene.h"
#include "granule_commit.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

static const char *kind_name(gr_result_kind k)
{
    return k == GR_RESULT_MEAN            ? "mean"
           : k == GR_RESULT_POWER_LAW     ? "power_law"
           : k == GR_RESULT_RUNNING       ? "running_mean"
           : k == GR_RESULT_CURVE         ? "curve"
           : k == GR_RESULT_CASCADE       ? "cascade"
           : k == GR_RESULT_SPM           ? "spm"
           : k == GR_RESULT_SPM_COMPARE   ? "spm_compare"
           : k == GR_RESULT_SPM_CIRCLE    ? "spm_circle"
           : k == GR_RESULT_CASCADE_FIELD ? "cascade_field"
           : k == GR_RESULT_SETTLE        ? "settle_time"
           : k == GR_RESULT_COLLAPSE      ? "collapse"
                                          : "rise_time";
}

static void add_num(cJSON *o, const char *name, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, name, v);
    } else {
        cJSON_AddNullToObject(o, name);
    }
}

static void csv_num(FILE *f, double v)
{
    if (isfinite(v)) {
        fprintf(f, ",%.6g", v);
    } else {
        fprintf(f, ",");
    }
}

/* A group label "k1=v1, k2=v2" split into its values "v1, v2" (the tick label) and its keys
 * "k1, k2" (the axis label); a token without '=' is a value with no key. */
static void split_group(const char *group, char *values, size_t nv, char *keys, size_t nk)
{
    char buf[200];
    snprintf(buf, sizeof buf, "%s", group);
    values[0] = keys[0] = '\0';
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ') {
            tok++;
        }
        char *eq = strchr(tok, '=');
        if (!eq) {
            snprintf(values + strlen(values), nv - strlen(values), "%s%s", values[0] ? ", " : "",
                     tok);
            continue;
        }
        *eq = '\0';
        /* linked keys N+L=3000/0.2: keys "N, L (m)", values "3000, 0.2" */
        char *ks = NULL, *vs = NULL;
        for (char *k = strtok_r(tok, "+", &ks), *v = strtok_r(eq + 1, "/", &vs); k && v;
             k = strtok_r(NULL, "+", &ks), v = strtok_r(NULL, "/", &vs)) {
            const char *unit = campaign_key_unit(k);
            snprintf(keys + strlen(keys), nk - strlen(keys), "%s%s%s%s%s", keys[0] ? ", " : "", k,
                     unit[0] ? " (" : "", unit, unit[0] ? ")" : "");
            snprintf(values + strlen(values), nv - strlen(values), "%s%s", values[0] ? ", " : "",
                     v);
        }
    }
}

/* Text for a gnuplot string in single quotes, where an apostrophe is written twice (the thesis's
 * form); cut at the buffer's end, never between the two. */
static void gp_quote_apostrophes(char *text, size_t size)
{
    char out[512];
    size_t n = 0;
    for (const char *c = text; *c; c++) {
        const size_t w = *c == '\'' ? 2 : 1;
        if (n + w >= size || n + w >= sizeof out) {
            break;
        }
        out[n++] = *c;
        if (w == 2) {
            out[n++] = '\'';
        }
    }
    memcpy(text, out, n);
    text[n] = '\0';
}

/* ours against the thesis: against a physical abscissa where the rows' keys give one
 * (campaign_compare_series.c), else one point per row with its label on the x axis */
static void plot_compare(const char *dir, const gr_campaign_result *r, const campaign_rows *rows)
{
    /* a curve's row holds the slope of its power law over the window, not the quantity */
    char ylabel[320];
    if (r->kind == GR_RESULT_CURVE && !strstr(r->quantity, "slope")) {
        snprintf(ylabel, sizeof ylabel, "slope of ln(%.100s) against ln(%.60s), %g-%g", r->quantity,
                 r->x_label[0] ? r->x_label : r->x, r->x_min, r->x_max);
    } else {
        snprintf(ylabel, sizeof ylabel, "%.200s%s%.60s", r->quantity, r->unit[0] ? " / " : "",
                 r->unit);
    }
    gp_quote_apostrophes(ylabel, sizeof ylabel); /* the label sits in single quotes */
    bool ours = false;
    for (int i = 0; i < rows->n; i++) {
        ours |= isfinite(rows->r[i].value);
    }
    if (ours && campaign_compare_series(dir, r, rows, ylabel)) {
        return;
    }
    char name[80];
    snprintf(name, sizeof name, "%s_compare.dat", r->id);
    gr_file f;
    gr_error err = {0};
    if (gr_file_open(&f, dir, name, &err)) {
        return;
    }
    char axis[200] = "";
    /* rows in order of their value when each is labelled by one number (eps_n = 0.01 ... 0.99),
     * otherwise in the campaign's order */
    int *order = malloc(sizeof(int) * (size_t)(rows->n > 0 ? rows->n : 1));
    if (!order) {
        gr_file_abandon(&f);
        return;
    }
    bool numeric = true;
    for (int i = 0; i < rows->n; i++) {
        char label[200], keys[200], *end;
        split_group(rows->r[i].group, label, sizeof label, keys, sizeof keys);
        strtod(label, &end);
        numeric &= end != label && !*end;
        order[i] = i;
    }
    for (int i = 1; i < rows->n && numeric; i++) { /* insertion sort: stable, m stays in order */
        const int k = order[i];
        const double xk = atof(strchr(rows->r[k].group, '=') ? strchr(rows->r[k].group, '=') + 1
                                                             : rows->r[k].group);
        int j = i;
        while (j > 0) {
            const campaign_row *p = &rows->r[order[j - 1]];
            const double xp = atof(strchr(p->group, '=') ? strchr(p->group, '=') + 1 : p->group);
            if (xp <= xk) {
                break;
            }
            order[j] = order[j - 1];
            j--;
        }
        order[j] = k;
    }
    for (int o = 0, i = 0; o < rows->n; o++) {
        const campaign_row *w = &rows->r[order[o]];
        if (w->role == 't') {
            continue; /* a trend (per unit ln x) is not on the exponent's scale: ID_slopes.png */
        }
        char label[200], keys[200];
        split_group(w->group, label, sizeof label, keys, sizeof keys);
        if (!axis[0]) {
            snprintf(axis, sizeof axis, "%s", keys);
        }
        if (w->m) {
            snprintf(label + strlen(label), sizeof label - strlen(label), " m=%d", w->m);
        }
        /* a thesis range is drawn as its middle +- half its width */
        const bool range = !strcmp(w->comparison, "range");
        const double tv = range ? 0.5 * (w->thesis + w->thesis_hi) : w->thesis;
        const double te = range                       ? 0.5 * (w->thesis_hi - w->thesis)
                          : isfinite(w->thesis_error) ? w->thesis_error
                                                      : 0.0;
        fprintf(f.f, "%d \"%s\" %.6g %.6g %.6g %.6g\n", i++, label, w->value, w->error, tv, te);
    }
    free(order);
    if (gr_file_commit(&f, &err)) {
        return;
    }
    bool thesis = false;
    for (int i = 0; i < rows->n; i++) {
        thesis |= isfinite(rows->r[i].thesis);
    }
    if (!ours) { /* a curve without a fit window has its figure in ID_data.png only */
        if (r->kind != GR_RESULT_CURVE) {
            campaign_note("%s: no value in any row, no figure", r->id);
        }
        return;
    }
    /* many rows (Table 5.1's 45): vertical, smaller tick labels */
    const char *tics = rows->n > 12 ? "set xtics rotate by 90 right font ',11' noenhanced"
                                    : "set xtics rotate by -40 noenhanced";
    char body[2048];
    snprintf(
        body, sizeof body,
        "set datafile separator whitespace\nset title \"%s\" noenhanced\nset ylabel '%s' "
        "noenhanced\n%s\n"
        "set xlabel '%s' noenhanced\nset key below height 1.5\nset offsets 0.5, 0.5, graph 0.06, "
        "graph "
        "0.06\nset grid ytics lc rgb '#dddddd'\n"
        "plot '%s' using 1:3:4:xtic(2) with yerrorbars pt 7 ps 1.2 lc rgb '#1f5fbf' title "
        "'granule'%s\n",
        r->title, ylabel, tics, axis, name,
        thesis
            ? ", '' using ($1+0.15):5:6 with yerrorbars pt 6 ps 1.2 lc rgb '#c0392b' title 'thesis'"
            : "");
    campaign_draw(dir, r->id, "", body);
}

/* One block of ID_thesis.dat: the thesis's law y ~ x^-xi over [x_lo, x_hi] through (x_hi, y_hi)
 * for the block (group, m), or "nan nan" where the thesis gives no single exponent. Returns
 * whether a line was drawn. */
static bool thesis_line(FILE *f, const gr_campaign_result *r, const char *group, int m,
                        const char *title, bool after, double x_lo, double x_hi, double y_hi)
{
    campaign_rows one = {0};
    campaign_row *w = campaign_rows_add(&one);
    snprintf(w->group, sizeof w->group, "%s", group);
    w->m = m;
    campaign_row_thesis(r, w);
    const bool drawn = isfinite(w->thesis) && strcmp(w->comparison, "range") &&
                       strcmp(w->comparison, "construction") && isfinite(x_lo) && x_hi > x_lo &&
                       y_hi > 0.0;
    const double xi = w->thesis * (r->per_m && m ? m : 1);
    campaign_rows_free(&one);
    fprintf(f, "%s\"%s\"\n", after ? "\n\n" : "", title);
    if (drawn) {
        fprintf(f, "%.9g %.9g\n%.9g %.9g\n", x_lo, y_hi * pow(x_lo / x_hi, -xi), x_hi, y_hi);
    } else {
        fprintf(f, "nan nan\n");
    }
    return drawn;
}

/* The power-law data regrouped as gnuplot index blocks, one per (group, m), each with a title
 * line; returns the number of blocks. For a power_law result with a thesis exponent, ID_thesis.dat
 * gets, per block, the thesis's law y ~ x^-xi drawn over the block's fit window through its
 * largest fitted point (two points; "nan" where the thesis gives no single exponent). */
/* A figure of many series is drawn in panels of a handful each (issue 37: "at most a handful of
 * series"): one panel per group when each group holds several series (the moments of one eps),
 * else consecutive runs of at most 6 (plot_data). */
enum { MAX_PANELS = 12, PLOT_CAP = 1200, SERIES_PER_PANEL = 8 };

/* the groups' labels as the panels of a figure title them (power_law_blocks fills them) */
typedef char group_label[96];

static int power_law_blocks(const char *dir, const gr_campaign_result *r, bool *thesis_lines,
                            int *groups, group_label *labels, const int max_labels)
{
    char path[1200], name[80], tname[80];
    snprintf(path, sizeof path, "%s/%s_data.csv", dir, r->id);
    snprintf(name, sizeof name, "%s_blocks.dat", r->id);
    snprintf(tname, sizeof tname, "%s_thesis.dat", r->id);
    *thesis_lines = false;
    *groups = 0;
    FILE *in = gr_input_fopen(path, &(int){0});
    gr_file f, t;
    gr_error err = {0};
    if (!in || gr_file_open(&f, dir, name, &err)) {
        if (in) {
            fclose(in);
        }
        return 0;
    }
    const bool want_thesis = r->kind == GR_RESULT_POWER_LAW && r->thesis[0];
    if (want_thesis && gr_file_open(&t, dir, tname, &err)) {
        fclose(in);
        gr_file_abandon(&f);
        return 0;
    }
    char line[512], prev[220] = "", prev_group[200] = "";
    int blocks = 0, prev_m = 0;
    double x_lo = NAN, x_hi = NAN, y_hi = NAN;
    bool header = true;
    while (fgets(line, sizeof line, in)) {
        if (header) {
            header = false;
            continue;
        }
        char *q = strchr(line + 1, '"'); /* group is quoted: "...",m,x,mean,error,seeds,in_fit */
        int m, n, in_fit;
        double x, y, e;
        if (!q || sscanf(q + 1, ",%d,%lf,%lf,%lf,%d,%d", &m, &x, &y, &e, &n, &in_fit) != 6) {
            continue;
        }
        char group[200], key[220]; /* the label as the campaign has it: "; " in the cell is ", " */
        snprintf(group, sizeof group, "%.*s", (int)(q - line - 1), line + 1);
        gr_csv_label(group);
        campaign_pretty_group(group, key, sizeof key - 16);
        snprintf(key + strlen(key), sizeof key - strlen(key), "%s%.0d", m ? ", m = " : "", m);
        if (strcmp(key, prev)) {
            if (want_thesis && blocks) {
                *thesis_lines |=
                    thesis_line(t.f, r, prev_group, prev_m, prev, blocks > 1, x_lo, x_hi, y_hi);
            }
            fprintf(f.f, "%s\"%s\"\n", blocks ? "\n\n" : "", key);
            snprintf(prev, sizeof prev, "%s", key);
            if (strcmp(group, prev_group) && *groups < max_labels) {
                campaign_pretty_group(group, labels[*groups], sizeof labels[0]);
            }
            *groups += strcmp(group, prev_group) != 0;
            snprintf(prev_group, sizeof prev_group, "%s", group);
            prev_m = m;
            x_lo = x_hi = y_hi = NAN;
            blocks++;
        }
        if (in_fit && isfinite(y)) {
            x_lo = isfinite(x_lo) && x_lo < x ? x_lo : x;
            if (!(x_hi >= x)) {
                x_hi = x;
                y_hi = y;
            }
        }
        fprintf(f.f, "%.9g %.9g %.9g %d\n", x, y, isfinite(e) ? e : 0.0, in_fit);
    }
    if (want_thesis && blocks) {
        *thesis_lines |=
            thesis_line(t.f, r, prev_group, prev_m, prev, blocks > 1, x_lo, x_hi, y_hi);
    }
    fclose(in);
    if (want_thesis && gr_file_commit(&t, &err)) {
        *thesis_lines = false;
    }
    return gr_file_commit(&f, &err) ? 0 : blocks;
}

/* Axis labels a physicist reads: the summary path of a power law's ordinate as the quantity it
 * holds, the varied key of its abscissa without its section, with its unit. */
static void axis_labels(const gr_campaign_result *r, char *x, size_t xl, char *y, size_t yl)
{
    const char *dot = strchr(r->x, '.');
    const char *unit = gr_scene_key_unit(r->x);
    snprintf(x, xl, "%s%s%s%s", dot ? dot + 1 : r->x,
             unit && unit[0] && strcmp(unit, "1") ? " (" : "",
             unit && unit[0] && strcmp(unit, "1") ? unit : "",
             unit && unit[0] && strcmp(unit, "1") ? ")" : "");
    if (strstr(r->y, "moments.speed.m")) {
        snprintf(y, yl, "%s", strstr(r->y, "{m}") ? "<|v|^m> ((m/s)^m)" : "<v^2> (m^2/s^2)");
    } else if (strstr(r->y, "gaps.moments.")) {
        snprintf(y, yl, "<R^m> of the neighbour separation (m^m)");
    } else {
        snprintf(y, yl, "%s", r->y);
    }
}

/* The panels of a figure of `blocks` series in `groups` groups: fills plots[k] (PLOT_CAP bytes
 * each, static) empty and returns their number (1: one plot); *by_group when each panel is one
 * group. */
static int panels(const int blocks, const int groups, char *plots[MAX_PANELS], bool *by_group)
{
    static char buf[MAX_PANELS][PLOT_CAP];
    for (int k = 0; k < MAX_PANELS; k++) {
        plots[k] = buf[k];
        buf[k][0] = 0;
    }
    *by_group = false;
    if (blocks <= SERIES_PER_PANEL) {
        return 1;
    }
    /* a panel per group when each group has several series (its moments m); one series per group
     * (a curve each): panels of six curves */
    *by_group = groups > 1 && groups <= MAX_PANELS && blocks % groups == 0 &&
                blocks / groups >= 2 && blocks / groups <= 9;
    const int np = *by_group ? groups : (blocks + 5) / 6;
    return np < MAX_PANELS ? np : MAX_PANELS;
}

/* The figure ID_data.png: head (the axes), then the panels' plots under the title (one panel: a
 * single plot with its key where `key` says). */
static void draw_panels(const char *dir, const char *id, const char *head, const char *key,
                        const char *title, char *const plots[], const int np)
{
    char body[16384];
    size_t n = (size_t)snprintf(body, sizeof body, "%s", head);
    if (np == 1) {
        /* the title over the whole canvas: over the plot alone a long one is cut when the key
         * stands outside */
        snprintf(body + n, sizeof body - n,
                 "set key %s noenhanced\nset multiplot layout 1,1 title \"%s\" noenhanced font "
                 "',13'\n%sunset multiplot\n",
                 key, title, plots[0]);
    } else {
        const int cols = np <= 4 ? 2 : 3, rows = (np + cols - 1) / cols;
        /* the key in an empty cell of the grid when there is one, else inside the first panel */
        const char *where = np < rows * cols ? "at screen 0.97, 0.06 right bottom font ',12'"
                                             : "top right font ',9'";
        n += (size_t)snprintf(body + n, sizeof body - n,
                              "set key %s noenhanced\nset tics font ',10'\nset title font ',12'\n"
                              "set xlabel font ',11'\nset ylabel font ',11'\n"
                              "set multiplot layout %d,%d title \"%s\" noenhanced font ',13'\n",
                              where, rows, cols, title);
        for (int k = 0; k < np && n < sizeof body; k++) { /* one key: the colours repeat */
            n += (size_t)snprintf(body + n, sizeof body - n, "%s%s", k == 1 ? "unset key\n" : "",
                                  plots[k]);
        }
        if (n < sizeof body) {
            snprintf(body + n, sizeof body - n, "unset multiplot\n");
        }
    }
    campaign_draw(dir, id, "_data", body);
}

/* the data behind a fit or a running average */
static void plot_data(const char *dir, const gr_campaign_result *r)
{
    char body[2048];
    if (r->kind == GR_RESULT_POWER_LAW) {
        bool thesis_lines;
        group_label labels[MAX_PANELS];
        int groups, blocks = power_law_blocks(dir, r, &thesis_lines, &groups, labels, MAX_PANELS);
        if (!blocks) {
            return;
        }
        char window[160] = "", xlab[96], ylab[96];
        axis_labels(r, xlab, sizeof xlab, ylab, sizeof ylab);
        const char *dot = strrchr(r->x, '.'); /* system.N: N */
        const char *x = dot ? dot + 1 : r->x;
        if (isfinite(r->x_max) && r->x_min > 0.0) {
            snprintf(window, sizeof window, " (open: outside the fit window %s = %g-%g)", x,
                     r->x_min, r->x_max);
        } else if (isfinite(r->x_max) || r->x_min > 0.0) {
            snprintf(window, sizeof window, " (open: outside the fit window %s %s %g)", x,
                     isfinite(r->x_max) ? "<=" : ">=", isfinite(r->x_max) ? r->x_max : r->x_min);
        }
        char head[1024], title[512];
        snprintf(title, sizeof title, "%s: the data of each fit%s",
                 r->quantity[0] ? r->quantity : r->id, window);
        snprintf(head, sizeof head,
                 "set datafile separator whitespace\nset logscale xy\nset xlabel '%s' "
                 "noenhanced\nset ylabel '%s' noenhanced\n",
                 xlab, ylab);
        char *plots[MAX_PANELS];
        bool by_group;
        const int np = panels(blocks, groups, plots, &by_group);
        const bool m_titles = by_group && r->m_lo > 0; /* each panel's series: m = m_lo, ... */
        for (int k = 0; k < np; k++) {
            const int lo = k * blocks / np, hi = (k + 1) * blocks / np - 1;
            char th[256] = "", series[96] = "columnheader(1)", lc[32] = "i+1", panel[160] = "";
            if (np > 1) { /* the same colours in every panel */
                snprintf(lc, sizeof lc, "i-%d+1", lo);
            }
            if (m_titles) {
                snprintf(series, sizeof series, "sprintf('m = %%d', %d + (i - %d) * %d)", r->m_lo,
                         lo, r->m_step > 0 ? r->m_step : 1);
            }
            if (by_group) {
                snprintf(panel, sizeof panel, "set title '%.95s' noenhanced\n", labels[k]);
            }
            if (thesis_lines) { /* the thesis's exponent drawn through each fit's largest point */
                snprintf(th, sizeof th,
                         ", for [i=%d:%d] '%s_thesis.dat' index i using 1:2 with lines dt 2 lw 2 "
                         "lc %s title (i == %d ? 'thesis exponent (dashed)' : '')",
                         lo, hi, r->id, lc, lo);
            }
            snprintf(plots[k], PLOT_CAP,
                     "%splot for [i=%d:%d] '%s_blocks.dat' index i using 1:($4 > 0 ? $2 : 1/0):3 "
                     "with yerrorbars pt 7 lc %s title %s, for [i=%d:%d] '' index i using 1:($4 > "
                     "0 ? 1/0 : $2) with points pt 6 lc %s notitle%s\n",
                     panel, lo, hi, r->id, lc, series, lo, hi, lc, th);
        }
        draw_panels(dir, r->id, head, "below height 1.5", title, plots, np);
        return;
    } else if (r->kind == GR_RESULT_CURVE) {
        bool unused;
        group_label labels[MAX_PANELS];
        int groups, blocks = power_law_blocks(dir, r, &unused, &groups, labels, MAX_PANELS);
        if (!blocks) {
            return;
        }
        const bool map = !strcmp(r->transform, "bisection_collapse");
        const char *axes = !strcmp(r->axes, "linear") ? ""
                           : !strcmp(r->axes, "linlog")
                               ? "set logscale y\nset format y '10^{%L}'\n"
                               : "set logscale xy\nset format y '10^{%L}'\n";
        char head[1024];
        snprintf(head, sizeof head,
                 "set datafile separator whitespace\n%sset format x '%%g'\n"
                 "set xlabel '%s' noenhanced\nset ylabel '%s' noenhanced\n",
                 axes,
                 map             ? "-ln R"
                 : r->x_label[0] ? r->x_label
                                 : r->x,
                 map ? "A_N G^{1/(n-1)}  (3.39)" : r->quantity);
        char *plots[MAX_PANELS];
        bool by_group;
        const int np = panels(blocks, groups, plots, &by_group);
        for (int k = 0; k < np; k++) {
            const int lo = k * blocks / np, hi = (k + 1) * blocks / np - 1;
            char dashed[400] = ""; /* overlay = power_law | column: each curve's line, its colour */
            if (!strcmp(r->overlay, "power_law") || !strcmp(r->overlay, "column")) {
                char words[120];
                if (r->overlay_title[0]) {
                    snprintf(words, sizeof words, "%.95s", r->overlay_title);
                } else if (r->overlay_y[0]) {
                    snprintf(words, sizeof words, "%.95s (dashed)", r->overlay_y);
                } else {
                    snprintf(words, sizeof words, "A x^%g fitted (dashed)", r->overlay_exponent);
                }
                gp_quote_apostrophes(words, sizeof words); /* the words sit in single quotes */
                snprintf(dashed, sizeof dashed,
                         ", for [i=%d:%d] '%s_overlay.dat' index i using 1:2 with lines dt 2 lw 2 "
                         "lc i-%d+1 title (i == %d ? '%s' : '')",
                         lo, hi, r->id, np > 1 ? lo : 0, lo, words);
            }
            /* with dashed lines beside them the curves are points, so that the lines show */
            snprintf(plots[k], PLOT_CAP,
                     "%splot for [i=%d:%d] '%s_blocks.dat' index i using 1:2 with %s pt 7 "
                     "ps 0.5 lc i-%d+1 title columnheader(1)%s%s\n",
                     np > 1 && k >= 1 ? "set key top right font ',9' noenhanced\n" : "", lo, hi,
                     r->id, dashed[0] ? "points" : "linespoints", np > 1 ? lo : 0,
                     map ? ", x with lines dt 2 lw 2 lc rgb 'black' title 'uniform bisection "
                           "(3.36): -ln R'"
                         : "",
                     dashed);
        }
        draw_panels(dir, r->id, head, map ? "inside top left" : "below height 1.5", r->title, plots,
                    np);
        return;
    } else if (r->kind == GR_RESULT_RUNNING) {
        snprintf(
            body, sizeof body,
            "set datafile separator ','\nset key below height 1.5\nset xlabel 'sampling time t "
            "(s)'\nset ylabel 'T (m^2/s^2)'\n"
            "set title 'Means over %g s (points) and the running average (lines), every seed' "
            "noenhanced\n"
            "plot '%s_data.csv' skip 1 using 3:4 with points pt 7 ps 0.6 lc rgb '#1f5fbf' "
            "title 'period means', "
            "'' skip 1 using 3:5 with lines lw 2 lc rgb '#c0392b' title 'running average'\n",
            r->period, r->id);
    } else if (r->kind == GR_RESULT_CASCADE) {
        snprintf(body, sizeof body,
                 "set datafile separator ','\nset size ratio -1\nunset key\nset xlabel 'x "
                 "(m)'\nset ylabel 'y (m)'\n"
                 "set multiplot layout 1,2 title 'The same system: a snapshot of the RFM (left) "
                 "and discs placed from a "
                 "multiplicative cascade (right)' noenhanced\n"
                 "plot '%s_positions.csv' skip 1 using 2:(strcol(1) eq 'rfm' ? $3 : 1/0) with "
                 "points pt 7 ps 0.5 lc rgb '#1f5fbf'\n"
                 "plot '%s_positions.csv' skip 1 using 2:(strcol(1) eq 'cascade' ? $3 : 1/0) with "
                 "points pt 7 ps 0.5 lc rgb '#c0392b'\n"
                 "unset multiplot\n",
                 r->id, r->id);
    } else if (r->kind == GR_RESULT_RISE || r->kind == GR_RESULT_SETTLE) {
        snprintf(
            body, sizeof body,
            "set key below height 1.5\nset xlabel 't (s)'\nset ylabel 'T (m^2/s^2)'\n"
            "set title 'T(t) from the start of every run (lines: its steady value)' noenhanced\n"
            "plot '%s_data.csv' skip 1 using 3:4 with points pt 7 ps 0.3 lc rgb '#1f5fbf' title "
            "'T(t)', "
            "'' skip 1 using 3:5 with lines lw 2 lc rgb '#c0392b' title 'steady T (second half)'\n",
            r->id);
    } else {
        return;
    }
    campaign_draw(dir, r->id, "_data", body);
}

static void row_json(cJSON *arr, const campaign_row *w)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "group", w->group);
    if (w->m) {
        cJSON_AddNumberToObject(o, "m", w->m);
    }
    add_num(o, "value", w->value);
    add_num(o, "error", w->error);
    add_num(o, "error_fit_or_run", w->error_fit);
    add_num(o, "error_seeds", w->error_seeds);
    cJSON_AddNumberToObject(o, "seeds", w->n_seeds);
    if (w->n_x) {
        cJSON_AddNumberToObject(o, "fit_points", w->n_x);
    }
    add_num(o, "chi2_red", w->chi2_red);
    add_num(o, "x_lo", w->x_lo);
    add_num(o, "x_hi", w->x_hi);
    if (w->role) { /* a power law's local slope, or their trend (d exponent / d ln x) */
        cJSON_AddStringToObject(o, "role", w->role == 't' ? "trend" : "local_slope");
    }
    if (w->role == 't') {
        add_num(o, "centre_x", w->centre_x);
        add_num(o, "exponent_at_centre", w->centre_value);
    }
    add_num(o, "thesis", w->thesis);
    add_num(o, "thesis_error", w->thesis_error);
    cJSON_AddStringToObject(o, "thesis_note", w->thesis_note);
    cJSON_AddStringToObject(o, "comparison", w->comparison);
    add_num(o, "thesis_high", w->thesis_hi);
    add_num(o, "tolerance", w->tolerance);
    if (w->agrees >= 0) {
        cJSON_AddBoolToObject(o, "agrees", w->agrees);
    } else {
        cJSON_AddNullToObject(o, "agrees");
    }
    add_num(o, "z", w->z);
    add_num(o, "simulated_seconds", w->sim_seconds);
    add_num(o, "cpu_seconds", w->cpu_seconds);
    cJSON_AddNumberToObject(o, "runs_not_converged", w->unconverged);
    cJSON_AddStringToObject(o, "scene_hashes", w->hashes);
    cJSON_AddItemToArray(arr, o);
}

static void row_csv(FILE *f, const gr_campaign *c, const gr_campaign_result *r,
                    const campaign_row *w)
{
    fprintf(f, "%s,%s,%s,", c->name, r->id, r->quantity);
    gr_csv_text(f, campaign_unit(r), true);
    fputc(',', f);
    gr_csv_text(f, w->group, true);
    fprintf(f, ",%d", w->m);
    csv_num(f, w->value);
    csv_num(f, w->error);
    csv_num(f, w->error_fit);
    csv_num(f, w->error_seeds);
    fprintf(f, ",%d,%d", w->n_seeds, w->n_x);
    csv_num(f, w->chi2_red);
    csv_num(f, w->x_lo);
    csv_num(f, w->x_hi);
    const char *xu = !isfinite(w->x_lo) ? NULL
                     : w->x_unit[0]     ? w->x_unit
                     : r->x[0]          ? gr_scene_key_unit(r->x)
                                        : NULL;
    fprintf(f, ",%s", xu ? (xu[0] ? xu : "1") : "");
    csv_num(f, w->thesis);
    csv_num(f, w->thesis_error);
    fprintf(f, ",%s", w->comparison);
    csv_num(f, w->thesis_hi);
    fprintf(f, ",%s", w->agrees < 0 ? "" : w->agrees ? "1" : "0");
    csv_num(f, w->z);
    csv_num(f, w->sim_seconds);
    csv_num(f, w->cpu_seconds);
    fprintf(f, ",%d,%s,%s\n", w->unconverged, w->hashes, GR_COMMIT);
}

static int analyse_one(const gr_campaign *c, gr_fidelity fid, const gr_campaign_result *r,
                       const campaign_points *pts, const char *results, campaign_rows *rows,
                       gr_error *err)
{
    char name[80];
    snprintf(name, sizeof name, "%s_data.csv", r->id);
    gr_file data;
    int rc = gr_file_open(&data, results, name, err);
    if (rc) {
        return rc;
    }
    rc = r->kind == GR_RESULT_MEAN        ? campaign_mean(c, r, pts, rows, &data, err)
         : r->kind == GR_RESULT_POWER_LAW ? campaign_power_law(c, r, pts, rows, &data, err)
         : r->kind == GR_RESULT_RUNNING   ? campaign_running(c, r, pts, rows, &data, err)
         : r->kind == GR_RESULT_CURVE     ? campaign_curve(c, r, pts, rows, &data, err)
         : r->kind == GR_RESULT_CASCADE   ? campaign_cascade(c, r, pts, rows, results, &data, err)
         : r->kind == GR_RESULT_SPM       ? campaign_spm(c, r, pts, rows, results, &data, err)
         : r->kind == GR_RESULT_SPM_COMPARE
             ? campaign_spm_compare(r, fid, pts, rows, results, &data, err)
         : r->kind == GR_RESULT_SPM_CIRCLE
             ? campaign_spm_circle(r, fid, pts, rows, results, &data, err)
         : r->kind == GR_RESULT_CASCADE_FIELD
             ? campaign_cascade_field(r, fid, rows, results, &data, err)
         : r->kind == GR_RESULT_COLLAPSE ? campaign_collapse(c, r, pts, rows, results, &data, err)
                                         : campaign_rise(c, r, pts, rows, &data, err);
    char lost[200];
    const int unmatched = rc || fid != GR_FIDELITY_FULL || pts->n < gr_campaign_points(c, fid)
                              ? 0 /* quick runs other systems; a partial set lacks groups */
                              : campaign_thesis_unmatched(r, rows, lost, sizeof lost);
    if (unmatched) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "campaign %s, [result %s]: %d thesis entr%s name%s a group no row has, "
                     "first \"%s\" (the complete campaign's groups are its rows; a misspelt group "
                     "would drop its comparison)",
                     c->name, r->id, unmatched, unmatched > 1 ? "ies" : "y",
                     unmatched > 1 ? "" : "s", lost);
    }
    if (rc || !rows->n) { /* no row yet (a partial campaign's table): no table of nothing */
        gr_file_abandon(&data);
        return rc;
    }
    return gr_file_commit(&data, err);
}

/* The kinds that read each run's T(t) (temperature.csv: running_mean, rise_time, settle_time) need
 * the runs themselves: the archive (campaign_archive.c) does not keep T(t), so from restored points
 * they would come out empty and overwrite the committed numbers with none. Refused before anything
 * is written. */
static int series_at_hand(const gr_campaign *c, const campaign_points *pts, const char *dir,
                          const char *results, gr_error *err)
{
    for (int k = 0; k < c->n_results; k++) {
        const gr_campaign_result *r = &c->results[k];
        if (r->kind != GR_RESULT_RUNNING && r->kind != GR_RESULT_RISE &&
            r->kind != GR_RESULT_SETTLE) {
            continue;
        }
        int missing = 0;
        for (int i = 0; i < pts->n; i++) {
            char path[1200];
            struct stat st;
            snprintf(path, sizeof path, "%.1100s/temperature.csv", pts->p[i].dir);
            missing += stat(path, &st) != 0;
        }
        if (missing) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: result %s reads each run's T(t) (temperature.csv), which the "
                           "archive in %s/points does not keep, and %d of the %d runs in %s have "
                           "none (restored from the archive): collect where the runs are, or "
                           "run the campaign again into a fresh --out; nothing was written",
                           c->name, r->id, results, missing, pts->n, dir);
        }
    }
    return GR_OK;
}

static int analyse_all(const gr_campaign *c, gr_fidelity fid, const char *dir, const char *results,
                       long *finished, gr_error *err)
{
    campaign_points pts;
    int rc = campaign_points_read(dir, &pts, err);
    if (rc) {
        return rc;
    }
    *finished = pts.n;
    if ((rc = series_at_hand(c, &pts, dir, results, err))) {
        campaign_points_free(&pts);
        return rc;
    }
    if ((rc = gr_output_dir_prepare(results, GR_OUTPUT_ANY, true, err))) {
        campaign_points_free(&pts);
        return rc;
    }
    double cpu = 0.0, sim = 0.0;
    for (int i = 0; i < pts.n; i++) {
        cpu += isfinite(pts.p[i].cpu_seconds) ? pts.p[i].cpu_seconds : 0.0;
        sim += isfinite(pts.p[i].sim_seconds) ? pts.p[i].sim_seconds : 0.0;
    }
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "campaign", c->name);
    cJSON_AddStringToObject(j, "title", c->title);
    cJSON_AddStringToObject(j, "covers", c->covers);
    cJSON_AddStringToObject(j, "about", c->about);
    cJSON_AddStringToObject(j, "fidelity", fid == GR_FIDELITY_FULL ? "full" : "quick");
    cJSON_AddStringToObject(j, "scene", c->scene);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddNumberToObject(j, "points_finished", pts.n);
    cJSON_AddNumberToObject(j, "points_total", (double)gr_campaign_points(c, fid));
    /* to the millisecond: a quick campaign can cost under half a second, which whole seconds
     * would report as free */
    cJSON_AddNumberToObject(j, "cpu_seconds", round(cpu * 1000.0) / 1000.0);
    cJSON_AddNumberToObject(j, "cpu_hours", round(cpu / 36.0) / 100.0);
    cJSON_AddNumberToObject(j, "simulated_seconds", sim);
    /* the warm-up: T over the first quarter of the sampling against the rest, over every run; not
     * for a campaign about the transient itself (Fig. 2.7 samples from t = 0 on purpose) */
    bool transient = false;
    for (int k = 0; k < c->n_results; k++) {
        transient |= c->results[k].kind == GR_RESULT_RISE || c->results[k].kind == GR_RESULT_SETTLE;
    }
    if (transient) {
        cJSON_AddStringToObject(cJSON_AddObjectToObject(j, "warmup_check"), "not_applicable",
                                "the campaign measures the rise of T from t = 0");
    }
    double drift[4096], run_var = 0.0;
    int nd = 0, nvar = 0;
    for (int i = 0; i < pts.n && nd < 4096 && !transient; i++) {
        double e, d = campaign_warmup_drift(&pts.p[i], &e);
        if (isfinite(d)) {
            drift[nd++] = d;
            if (isfinite(e)) {
                run_var += e * e;
                nvar++;
            }
        }
    }
    if (nd > 0) {
        /* the error: the seeds' scatter with three runs or more, else the larger of it and the
         * runs' own block errors (campaign_headline_error, as for every result) */
        double dm, de_seeds;
        campaign_mean_sd(drift, nd, &dm, &de_seeds);
        const double de_runs = nvar == nd ? sqrt(run_var) / nd : (double)NAN;
        const double de = campaign_headline_error(de_seeds, de_runs, nd);
        cJSON *w = cJSON_AddObjectToObject(j, "warmup_check");
        cJSON_AddStringToObject(
            w, "what",
            "mean over runs of <T>(first quarter of sampling) / <T>(rest) - 1; error: the "
            "seeds' scatter (3 runs or more), else the larger of it and the runs' own "
            "error from 8 blocks of each run's sampling");
        cJSON_AddNumberToObject(w, "runs", nd);
        if (nd < pts.n) { /* points archived before their drift was, without their T(t) */
            cJSON_AddNumberToObject(w, "runs_without_series", pts.n - nd);
        }
        add_num(w, "drift", dm);
        add_num(w, "drift_error", de);
        add_num(w, "drift_error_seeds", de_seeds);
        add_num(w, "drift_error_runs", de_runs);
        add_num(w, "z", isfinite(de) && de > 0.0 ? dm / de : (double)NAN);
    }
    if (nd == 0 && !transient && pts.n > 0) {
        cJSON_AddStringToObject(cJSON_AddObjectToObject(j, "warmup_check"), "not_available",
                                "no run's T(t) at hand: the points were restored from an archive "
                                "written before it kept each run's warm-up drift");
    }
    cJSON *commits = cJSON_AddArrayToObject(j, "run_commits");
    for (int i = 0; i < pts.n; i++) {
        const cJSON *cm = cJSON_GetObjectItem(pts.p[i].manifest, "commit");
        bool seen = false;
        const cJSON *e;
        cJSON_ArrayForEach(e, commits)
        {
            seen |= cJSON_IsString(cm) && !strcmp(e->valuestring, cm->valuestring);
        }
        if (cJSON_IsString(cm) && !seen) {
            cJSON_AddItemToArray(commits, cJSON_CreateString(cm->valuestring));
        }
    }
    cJSON *arr = cJSON_AddArrayToObject(j, "results");
    gr_file csv;
    if ((rc = gr_file_open(&csv, results, "results.csv", err))) {
        cJSON_Delete(j);
        campaign_points_free(&pts);
        return rc;
    }
    /* units in results.meta.json: a row's value, errors and thesis values are in its result's
     * unit (column unit, "1" for a pure number), the fit window in its abscissa's (x_unit) */
    gr_file_header(
        &csv,
        "campaign [],result [],quantity [],unit [],group [],m [1],value [@unit],error [@unit],"
        "error_fit_or_run [@unit],error_seeds [@unit],seeds [1],fit_points [1],chi2_red [1],x_lo "
        "[@x_unit],"
        "x_hi [@x_unit],x_unit [],thesis [@unit],thesis_error [@unit],comparison [],thesis_high "
        "[@unit],"
        "agrees [1],z [1],simulated_seconds [s],cpu_seconds [s],runs_not_converged "
        "[1],scene_hashes [],"
        "commit []");
    for (int i = 0; i < c->n_results && !rc; i++) {
        const gr_campaign_result *r = &c->results[i];
        campaign_rows rows = {0};
        rc = analyse_one(c, fid, r, &pts, results, &rows, err);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "id", r->id);
        cJSON_AddStringToObject(o, "title", r->title);
        cJSON_AddStringToObject(o, "kind", kind_name(r->kind));
        cJSON_AddStringToObject(o, "quantity", r->quantity);
        cJSON_AddStringToObject(o, "unit", r->unit);
        cJSON_AddStringToObject(o, "y", r->y);
        if (r->kind == GR_RESULT_POWER_LAW) {
            cJSON_AddStringToObject(o, "x", r->x);
            add_num(o, "x_min", r->x_min);
            add_num(o, "x_max", r->x_max);
            cJSON_AddBoolToObject(o, "per_m", r->per_m);
        }
        cJSON_AddStringToObject(o, "thesis_source", r->thesis_source);
        cJSON_AddStringToObject(o, "note", r->note);
        cJSON_AddStringToObject(o, "verdict", r->verdict);
        cJSON_AddStringToObject(o, "verdict_why", r->verdict_why);
        cJSON_AddStringToObject(o, "restates", r->restates);
        cJSON *ra = cJSON_AddArrayToObject(o, "rows");
        for (int k = 0; k < rows.n; k++) {
            row_json(ra, &rows.r[k]);
            row_csv(csv.f, c, r, &rows.r[k]);
        }
        cJSON_AddItemToArray(arr, o);
        if (!rc && rows.n && r->kind != GR_RESULT_COLLAPSE) { /* it draws its own */
            plot_compare(results, r, &rows);
            campaign_slopes_plot(results, r, &rows);
            plot_data(results, r);
        }
        campaign_rows_free(&rows);
    }
    if (rc) {
        gr_file_abandon(&csv);
    } else {
        rc = gr_file_commit(&csv, err);
    }
    if (!rc) {
        rc = gr_json_write(results, "results.json", j, err);
    }
    cJSON_Delete(j);
    if (!rc) {
        rc = campaign_archive(c, &pts, results, err);
    }
    campaign_points_free(&pts);
    return rc;
}

int gr_campaign_analyse(const gr_campaign *c, gr_fidelity fid, const char *dir, const char *results,
                        long *finished, char *notes, size_t notes_len, gr_error *err)
{
    char ignore[1];
    campaign_notes_take(ignore, sizeof ignore); /* start with none */
    const int rc = analyse_all(c, fid, dir, results, finished, err);
    campaign_notes_take(notes ? notes : ignore, notes ? notes_len : sizeof ignore);
    return rc;
}
