/* A power law's local slopes against the abscissa (ID_slopes.png): does the exponent still move
 * with N? Each local slope (role 'l') is drawn at the geometric mean of its two sizes with a
 * horizontal bar spanning them, on a logarithmic axis, and a wide one (role 'w', slope_span) as an
 * open symbol with its longer bar; beside them the trend of the quadratic fit
 * (role 't', a straight line in ln N), the exponent of the whole fit (dotted) and the thesis's value
 * (dashed). One colour per group and moment, so a campaign's few series stay apart. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "io/files.h"
#include "io/plot.h"
#include "app/reproduce/campaign_points.h"

#define MAX_SERIES 8

/* The fit row a local slope or trend belongs to: the same m, its group the start of theirs. */
static const campaign_row *fit_of(const campaign_rows *rows, const campaign_row *w)
{
    for (int i = 0; i < rows->n; i++) {
        const campaign_row *f = &rows->r[i];
        const size_t len = strlen(f->group);
        if (!f->role && f->m == w->m && !strncmp(f->group, w->group, len) &&
            !strncmp(w->group + len, ", ", 2)) {
            return f;
        }
    }
    return NULL;
}

void campaign_slopes_plot(const char *dir, const gr_campaign_result *r, const campaign_rows *rows)
{
    if (r->kind != GR_RESULT_POWER_LAW || !r->local_slopes) {
        return;
    }
    char name[80];
    snprintf(name, sizeof name, "%s_slopes.dat", r->id);
    gr_file f;
    gr_error err = {0};
    if (gr_file_open(&f, dir, name, &err)) {
        return;
    }
    /* per series (a fit row with local slopes): block base[k] the slopes, then the wide slopes
     * when it has any (wide[k]), then the trend line, the whole fit's exponent over its range and
     * the thesis's value over it (or one NAN point) */
    const campaign_row *series[MAX_SERIES];
    int ns = 0, base[MAX_SERIES], block = 0;
    bool wide[MAX_SERIES];
    for (int i = 0; i < rows->n && ns < MAX_SERIES; i++) {
        const campaign_row *fit = &rows->r[i];
        if (fit->role || !isfinite(fit->x_lo)) {
            continue;
        }
        const campaign_row *trend = NULL;
        int nl = 0, nw = 0;
        for (int j = 0; j < rows->n; j++) {
            const campaign_row *w = &rows->r[j];
            if (w->role && fit_of(rows, w) == fit) {
                nl += w->role == 'l' && isfinite(w->value);
                nw += w->role == 'w' && isfinite(w->value);
                trend = w->role == 't' && isfinite(w->value) ? w : trend;
            }
        }
        if (!nl) {
            continue;
        }
        for (int pass = 0; pass < (nw ? 2 : 1); pass++) {
            fprintf(f.f, "%s# %s m=%d: x x_lo x_hi %slocal_slope error\n", ns || pass ? "\n\n" : "",
                    fit->group, fit->m, pass ? "wide_" : "");
            for (int j = 0; j < rows->n; j++) {
                const campaign_row *w = &rows->r[j];
                if (w->role == (pass ? 'w' : 'l') && isfinite(w->value) && fit_of(rows, w) == fit) {
                    fprintf(f.f, "%.9g %.9g %.9g %.9g %.9g\n", sqrt(w->x_lo * w->x_hi), w->x_lo,
                            w->x_hi, w->value, w->error);
                }
            }
        }
        fprintf(f.f, "\n\n# trend: exponent at x from the quadratic in ln x\n");
        for (int e = 0; e < 2; e++) {
            const double x = e ? fit->x_hi : fit->x_lo;
            fprintf(f.f, "%.9g %.9g\n", x,
                    trend ? trend->centre_value + trend->value * log(x / trend->centre_x)
                          : (double)NAN);
        }
        fprintf(f.f, "\n\n# the whole fit's exponent\n%.9g %.9g\n%.9g %.9g\n", fit->x_lo,
                fit->value, fit->x_hi, fit->value);
        fprintf(f.f, "\n\n# the thesis's value\n%.9g %.9g\n%.9g %.9g\n", fit->x_lo, fit->thesis,
                fit->x_hi, fit->thesis);
        base[ns] = block;
        wide[ns] = nw > 0;
        block += 4 + wide[ns];
        series[ns++] = fit;
    }
    if (!ns) {
        gr_file_abandon(&f);
        return;
    }
    if (gr_file_commit(&f, &err)) {
        return;
    }
    char body[4096], xlab[96];
    const char *dot = strrchr(r->x, '.');
    snprintf(xlab, sizeof xlab, "%s", dot ? dot + 1 : r->x);
    int len =
        snprintf(body, sizeof body,
                 "set datafile separator whitespace\nset title \"The local slopes of %s against "
                 "%s\" noenhanced\nset logscale x\nset xlabel '%s' noenhanced\n"
                 "set ylabel 'local %s' noenhanced\nset key below height 1.5\n"
                 "set grid ytics lc rgb '#dddddd'\nplot ",
                 r->quantity, xlab, xlab, r->quantity);
    char trend_title[128];
    snprintf(trend_title, sizeof trend_title, "trend (quadratic in ln %s)", xlab);
    bool wide_titled = false;
    for (int k = 0; k < ns && len < (int)sizeof body - 900; k++) {
        char style[96], label[200];
        gr_plot_series_style(k, style, sizeof style);
        char *lc = strstr(style, " dt "); /* the colour alone, for points and lines */
        if (lc) {
            *lc = '\0';
        }
        campaign_pretty_group(series[k]->group, label, sizeof label - 16);
        if (series[k]->m) {
            snprintf(label + strlen(label), sizeof label - strlen(label), ", m = %d", series[k]->m);
        }
        /* series side by side: each drawn a little right of the last, so their bars stay apart */
        const double shift = 1.0 + 0.015 * (k - 0.5 * (ns - 1));
        int b = base[k];
        len += snprintf(body + len, sizeof body - (size_t)len,
                        "%s'%s' index %d using ($1*%.4f):4:2:3:($4-$5):($4+$5) with xyerrorbars "
                        "pt 7 %s title '%s'",
                        k ? ", " : "", name, b++, shift, style, label);
        if (wide[k]) {
            char wide_title[128];
            snprintf(wide_title, sizeof wide_title, "between sizes %d apart (open)", r->slope_span);
            len += snprintf(body + len, sizeof body - (size_t)len,
                            ", '' index %d using ($1*%.4f):4:2:3:($4-$5):($4+$5) with xyerrorbars "
                            "pt 6 ps 1.5 %s title '%s'",
                            b++, shift * 1.02, style, wide_titled ? "" : wide_title);
            wide_titled = true;
        }
        len +=
            snprintf(body + len, sizeof body - (size_t)len,
                     ", '' index %d using 1:2 with lines %s lw 2 title '%s', "
                     "'' index %d using 1:2 with lines %s dt 3 title '%s', '' index %d using 1:2 "
                     "with lines lc rgb '#c0392b' dt 2 lw 2 title '%s'",
                     b, style, k ? "" : trend_title, b + 1, style,
                     k ? "" : "exponent of the whole fit", b + 2, k ? "" : "thesis");
    }
    snprintf(body + len, sizeof body - (size_t)len, "\n");
    campaign_draw(dir, r->id, "_slopes", body);
}
