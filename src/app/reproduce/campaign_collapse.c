/* COLLAPSE (Fig. 3.3): the points of a power_law result, each compensated by its own group's fitted
 * exponent, y x^xi(group), drawn against the group's value b or 1 - b^2, one series per x. Sec.
 * 3.1.3: "the values of xi_2, given in figure 3.2, can be used to collapse the second moments as a
 * function of 1 - eps^2, onto a single curve for all systems": <v^2> = lambda(eps) N^-xi_2(eps)
 * (3.8), so <v^2> N^xi_2(eps) = lambda(eps) for every N where the power law holds. The points and
 * exponents are those of the power_law result itself (campaign_power_law run again), so by
 * construction the scatter about one curve is that fit's residuals: the figure shows the shape of
 * lambda(eps) and how well one power law per eps describes every N. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/scene.h"
#include "app/reproduce/campaign_points.h"

#define MAX_COLLAPSE 1024

typedef struct collapse_point {
    double x, against, value, error;
} collapse_point;

static const gr_campaign_result *compensating_fit(const gr_campaign *c, const char *id)
{
    for (int k = 0; k < c->n_results; k++) {
        if (!strcmp(c->results[k].id, id)) {
            return &c->results[k];
        }
    }
    return NULL;
}

static const campaign_row *fit_of(const campaign_rows *fits, const char *group)
{
    for (int k = 0; k < fits->n; k++) {
        if (!strcmp(fits->r[k].group, group)) {
            return &fits->r[k];
        }
    }
    return NULL;
}

static int by_against(const void *a, const void *b)
{
    const collapse_point *p = a, *q = b;
    return p->x != q->x               ? (p->x > q->x) - (p->x < q->x)
           : p->against != q->against ? (p->against > q->against) - (p->against < q->against)
                                      : 0;
}

/* RESULTS/ID_series.dat (a block per x, along the abscissa) and the figure ID.png */
static void draw(const char *results, const gr_campaign_result *r, const char *by_key,
                 const char *x_short, collapse_point *pt, int n)
{
    qsort(pt, (size_t)n, sizeof *pt, by_against);
    char name[80];
    snprintf(name, sizeof name, "%s_series.dat", r->id);
    gr_file f;
    gr_error ignore = {0};
    if (gr_file_open(&f, results, name, &ignore)) {
        return;
    }
    int blocks = 0;
    for (int i = 0; i < n; i++) {
        if (i == 0 || pt[i].x != pt[i - 1].x) {
            fprintf(f.f, "%s\"%s = %g\"\n", i ? "\n\n" : "", x_short, pt[i].x);
            blocks++;
        }
        fprintf(f.f, "%.9g %.9g %.9g\n", pt[i].against, pt[i].value, pt[i].error);
    }
    if (gr_file_commit(&f, &ignore) || !blocks) {
        return;
    }
    char xlab[96]; /* the axis as a physicist names it: 1 - eps_n^2, not 1 - model.eps_n^2 */
    const char *dot = strrchr(by_key, '.'), *b = dot ? dot + 1 : by_key;
    if (!strcmp(r->against, "1-by^2")) {
        snprintf(xlab, sizeof xlab, "1 - %.80s^2", b);
    } else {
        snprintf(xlab, sizeof xlab, "%.90s", b);
    }
    char ylab[128];
    snprintf(ylab, sizeof ylab, r->unit[0] ? "%.60s (%.40s)" : "%.60s", r->quantity, r->unit);
    char body[2048];
    snprintf(body, sizeof body,
             "set datafile separator whitespace\nset logscale xy\nset format x '%%g'\n"
             "set xlabel '%s' noenhanced\nset ylabel '%s' noenhanced\n"
             "set key below height 1.5 noenhanced\nset title \"%s\" noenhanced\n"
             "plot for [i=0:%d] '%s_series.dat' index i using 1:2:3 with yerrorlines pt 7 "
             "lc i+1 title columnheader(1)\n",
             xlab, ylab, r->title, blocks - 1, r->id);
    campaign_draw(results, r->id, "", body);
}

int campaign_collapse(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                      campaign_rows *rows, const char *results, gr_file *data, gr_error *err)
{
    const gr_campaign_result *fit = compensating_fit(c, r->compensate); /* checked at load */
    if (!fit) {
        return GR_FAIL(err, GR_EINVAL, "[result %s] compensate = %s: no such result", r->id,
                       r->compensate);
    }
    /* the power law's own points and exponents: its data table, written to a scratch file */
    campaign_rows fits = {0};
    gr_file scratch = {.f = tmpfile()};
    if (!scratch.f) {
        return GR_FAIL(err, GR_EIO, "[result %s]: cannot open a temporary file", r->id);
    }
    int rc = campaign_power_law(c, fit, pts, &fits, &scratch, err);
    const char *dot = strrchr(fit->x, '.');
    const char *x_short = dot ? dot + 1 : fit->x;
    char y_unit[64];
    const char *yu = campaign_y_unit(fit, y_unit, sizeof y_unit), *xu = gr_scene_key_unit(fit->x);
    const char *cu =
        xu && (!xu[0] || !strcmp(xu, "1")) ? yu : NULL; /* y x^xi: y's unit if x has none */
    campaign_header(data, "group", "", "b", "1", "against", "1", "x", xu, "y", yu, "y_error", yu,
                    "exponent", "1", "compensated", cu, "compensated_error", cu, NULL);
    static collapse_point pt[MAX_COLLAPSE];
    int n = 0;
    char line[512];
    rewind(scratch.f);
    for (bool header = true; !rc && fgets(line, sizeof line, scratch.f); header = false) {
        char group[160];
        int m, seeds, in_fit, used = 0;
        double x, y, e;
        const char *close = line[0] == '"' ? strchr(line + 1, '"') : NULL;
        if (header || !close ||
            sscanf(close + 1, ",%d,%lf,%lf,%lf,%d,%d%n", &m, &x, &y, &e, &seeds, &in_fit, &used) <
                6 ||
            !in_fit) {
            continue;
        }
        snprintf(group, sizeof group, "%.*s", (int)(close - line - 1), line + 1);
        const campaign_row *f = fit_of(&fits, group);
        const char *eq = strrchr(group, '=');
        if (!f || !eq || n == MAX_COLLAPSE) {
            continue;
        }
        campaign_row *w = campaign_rows_add(rows);
        snprintf(w->group, sizeof w->group, "%.100s, %.20s=%g", group, x_short, x);
        w->n_seeds = seeds;
        w->n_x = f->n_x;
        if (!isfinite(f->value)) { /* no exponent (fewer than 3 points): no value, as the fit */
            continue;
        }
        const double b = atof(eq + 1), xi = f->value;
        const double against = strcmp(r->against, "1-by^2") ? b : 1.0 - b * b;
        const double k = pow(x, xi); /* y = lambda x^-xi (3.8): y x^xi = lambda */
        pt[n] = (collapse_point){x, against, y * k, e * k};
        gr_csv_text(data->f, group, true);
        fprintf(data->f, ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", b, against, x, y, e, xi,
                pt[n].value, pt[n].error);
        w->value = pt[n].value;
        w->error = w->error_fit = pt[n].error; /* the point's; the exponent's error is not in it */
        w->chi2_red = f->chi2_red;             /* the scatter about one curve is the fit's */
        w->x_lo = f->x_lo;
        w->x_hi = f->x_hi;
        snprintf(w->x_unit, sizeof w->x_unit, "%s", xu && xu[0] ? xu : "1");
        campaign_row_thesis(r, w);
        n++;
    }
    gr_file_abandon(&scratch);
    campaign_rows_free(&fits);
    if (!rc && n) {
        draw(results, r, fit->by, x_short, pt, n);
    }
    return rc;
}
