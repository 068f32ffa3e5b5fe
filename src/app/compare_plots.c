/* The overlaid plots of a comparison (include/granule/compare.h): T(t) of every model and the
 * collapse of the velocity distributions (5.4). One palette colour and dash type per model, the
 * legend outside the data so that 2-8 curves stay readable. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/compare.h"
#include "io/files.h"
#include "io/plot.h"

/* Columns `xcol` and `ycol` of a CSV with one header line (and possibly '#' comments). */
static int read_columns(const char *path, const char *xcol, const char *ycol, double **x,
                        double **y)
{
    FILE *f = gr_input_fopen(path, &(int){0});
    *x = *y = NULL;
    if (!f) {
        return 0;
    }
    char line[4096];
    int ix = -1, iy = -1, n = 0, cap = 0;
    bool header = true;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            continue;
        }
        line[strcspn(line, "\n")] = 0;
        int c = 0;
        double vx = NAN, vy = NAN;
        char *save = NULL;
        for (char *tok = strtok_r(line, ",", &save); tok; tok = strtok_r(NULL, ",", &save), c++) {
            if (header) {
                ix = !strcmp(tok, xcol) ? c : ix;
                iy = !strcmp(tok, ycol) ? c : iy;
            } else {
                vx = c == ix ? atof(tok) : vx;
                vy = c == iy ? atof(tok) : vy;
            }
        }
        if (header) {
            header = false;
            if (ix < 0 || iy < 0) {
                break;
            }
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            double *nx = realloc(*x, sizeof(double) * (size_t)cap),
                   *ny = nx ? realloc(*y, sizeof(double) * (size_t)cap) : NULL;
            *x = nx ? nx : *x;
            *y = ny ? ny : *y;
            if (!nx || !ny) {
                break;
            }
        }
        (*x)[n] = vx;
        (*y)[n] = vy;
        n++;
    }
    fclose(f);
    return n;
}

/* P at |v| = v_rms: mean of the bins nearest +1 and -1 (v in units of v_rms) */
static double at_one(const double *x, const double *y, int n)
{
    double best_p = INFINITY, best_m = INFINITY, yp = NAN, ym = NAN;
    for (int i = 0; i < n; i++) {
        if (fabs(x[i] - 1.0) < best_p) {
            best_p = fabs(x[i] - 1.0);
            yp = y[i];
        }
        if (fabs(x[i] + 1.0) < best_m) {
            best_m = fabs(x[i] + 1.0);
            ym = y[i];
        }
    }
    return 0.5 * (yp + ym);
}

/* "plot " and one line per model: the file `fmt_file` (printf'd with the model's folder), the
 * gnuplot `using` clause, the model's palette style and its spec as the title. */
static size_t overlay(char *body, size_t size, size_t len, const gr_compare_spec *specs, int n,
                      const char *fmt_file, const char *using)
{
    len += (size_t)snprintf(body + len, len < size ? size - len : 0, "plot ");
    for (int k = 0; k < n && len < size; k++) {
        char style[80], file[300];
        gr_plot_series_style(k, style, sizeof style);
        snprintf(file, sizeof file, fmt_file, specs[k].label);
        len += (size_t)snprintf(body + len, size - len,
                                "%s'%s' %s with lines %s title '%s' noenhanced", k ? ", " : "",
                                file, using, style, specs[k].text);
    }
    return len;
}

/* The data collapse of (5.4): P'(v) = P(v) P_0(1) / P(1), v in units of v_rms, P_0 = the first
 * model, so that the tails of all models compare in shape (needs the pv observable). */
static void pv_collapse(const char *out, const gr_compare_spec *specs, int n, char *note,
                        size_t note_size)
{
    double *xs[GR_COMPARE_MAX] = {0}, *ys[GR_COMPARE_MAX] = {0}, scale[GR_COMPARE_MAX];
    int len[GR_COMPARE_MAX] = {0}, have = 0;
    char path[1400];
    for (int k = 0; k < n; k++) {
        snprintf(path, sizeof path, "%s/%s/pv.csv", out, specs[k].label);
        len[k] = read_columns(path, "v_over_vrms", "density_scaled", &xs[k], &ys[k]);
        have += len[k] > 0;
    }
    if (have == n) {
        const double p0 = at_one(xs[0], ys[0], len[0]);
        for (int k = 0; k < n; k++) {
            const double pk = at_one(xs[k], ys[k], len[k]);
            scale[k] = pk > 0.0 ? p0 / pk : (double)NAN;
        }
        gr_file f;
        gr_error err = {0};
        if (gr_file_open(&f, out, "pv_collapse.csv", &err) == GR_OK) {
            gr_file_note(&f,
                         "granule compare: P'(v) = P(v) P_0(1)/P(1) (5.4), v in units of v_rms, "
                         "P_0 = %s; one row per "
                         "model and bin with P > 0 (a long table: filter on model)",
                         specs[0].text);
            gr_file_header(&f, "model [],v_over_vrms [1],P_scaled [1]");
            for (int k = 0; k < n; k++) {
                for (int i = 0; i < len[k]; i++) {
                    if (ys[k][i] > 0.0 && isfinite(scale[k])) {
                        gr_csv_text(f.f, specs[k].text, false);
                        fprintf(f.f, ",%.6g,%.6g\n", xs[k][i], ys[k][i] * scale[k]);
                    }
                }
            }
            if (gr_file_commit(&f, &err) == GR_OK) {
                char body[6000];
                size_t blen = (size_t)snprintf(
                    body, sizeof body,
                    "set logscale y\nset format y '10^{%%L}'\nset key below\n"
                    "set xlabel 'v / v_{rms}'\nset ylabel \"P'(v) = P(v) P_0(1) / P(1)\"\n"
                    "set title \"Velocity distributions of the models, matched at v = "
                    "v_{rms}\\n{/*0.75 "
                    "eq. (5.4); P_0: the first model}\"\nplot ");
                for (int k = 0; k < n && blen < sizeof body; k++) {
                    char style[80];
                    gr_plot_series_style(k, style, sizeof style);
                    blen += (size_t)snprintf(body + blen, sizeof body - blen,
                                             "%s'pv_collapse.csv' skip 1 using 2:(strcol(1) eq "
                                             "'%s' ? $3 : 1/0) with lines %s "
                                             "title '%s' noenhanced",
                                             k ? ", " : "", specs[k].text, style, specs[k].text);
                }
                gr_plot_script(out, "pv_collapse.png", body, note, note_size);
            } else {
                snprintf(note, note_size, "pv_collapse.csv: %s", err.message);
            }
        }
    }
    for (int k = 0; k < n; k++) {
        free(xs[k]);
        free(ys[k]);
    }
}

void gr_compare_plots(const char *out, const gr_compare_spec *specs, int n, char *note,
                      size_t note_size)
{
    note[0] = 0;
    char body[6000];
    size_t len =
        (size_t)snprintf(body, sizeof body,
                         "set title 'Granular temperature under each model'\nset key below\n"
                         "set xlabel 't (s)'\nset ylabel 'T (m^2/s^2)'\nset format y '%%g'\n");
    len = overlay(body, sizeof body, len, specs, n, "%s/temperature.csv", "skip 1 using 1:2");
    if (len < sizeof body) {
        gr_plot_script(out, "temperature.png", body, note, note_size);
    }
    pv_collapse(out, specs, n, note, note_size);
}
