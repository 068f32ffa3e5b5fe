/* kind = curve (docs/campaigns/README.md): a distribution or profile that a run writes as a table
 * (e.g. G_1(R;N) in gaps.csv), averaged bin by bin over the seeds of every curve, optionally mapped
 * (transform) and summarised by the slope of a power law over a window.
 *
 * transform = bisection_collapse is the map of the thesis's Fig. 3.17 (3.39-3.40):
 *   x -> -ln x,   G -> A_N G^(1/(n-1)),   n = log2 N,   A_N = -ln(x_0) G(x_0)^(-1/(n-1)),
 * so every curve passes through (-ln x_0, -ln x_0). If the ring's structure were that of the uniform
 * bisection process, G_1 = A (-ln R)^(n-1) (3.36) and every mapped curve would be the line y = x:
 * a fitted slope of 1. The thesis finds the collapse onto one curve but not the slope 1 at large R.
 *
 * A run's series comes from its table, or, for points restored from a result set's archive, from
 * the series.json the archive keeps beside summary.json (campaign_archive.c). */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"
#include "analysis/obs_util.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

#define MAX_BINS 4096

void campaign_curve_key(const gr_campaign_result *r, char *out, size_t len)
{
    snprintf(out, len, "%s?%s#%s,%s,%s", r->table, r->where, r->x, r->y, r->y_err);
}

/* Does a CSV row satisfy every "column=value" of `where` (comma separated)? */
static bool row_matches(const char *where, char *const *fields, const int *col_of_where,
                        int n_where)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", where);
    char *save = NULL;
    int k = 0;
    for (char *tok = strtok_r(buf, ",", &save); tok && k < n_where;
         tok = strtok_r(NULL, ",", &save), k++) {
        const char *v = strchr(tok, '=') + 1;
        while (isspace((unsigned char)*v)) {
            v++;
        }
        if (col_of_where[k] < 0 || strcmp(fields[col_of_where[k]], v)) {
            return false;
        }
    }
    return true;
}

static int column_of(char *const *fields, int n, const char *name)
{
    while (isspace((unsigned char)*name)) {
        name++;
    }
    size_t len = strcspn(name, "= ");
    for (int i = 0; i < n; i++) {
        if (strlen(fields[i]) == len && !strncmp(fields[i], name, len)) {
            return i;
        }
    }
    return -1;
}

static int split(char *line, char **fields, int max)
{
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(line, ",\r\n", &save); tok && n < max;
         tok = strtok_r(NULL, ",\r\n", &save)) {
        fields[n++] = tok;
    }
    return n;
}

/* `where` with every {KEY} or {KEY/DIV} replaced by the point's value of the varied KEY (divided by
 * DIV and printed as an integer when DIV is given): "h={system.N/512}" is h=2 for N = 1024. */
static void expand_where(const campaign_point *p, const char *where, char *out, size_t len)
{
    size_t n = 0;
    for (const char *s = where; *s && n + 1 < len;) {
        const char *end = *s == '{' ? strchr(s, '}') : NULL;
        if (!end) {
            out[n++] = *s++;
            continue;
        }
        char key[96];
        snprintf(key, sizeof key, "%.*s", (int)(end - s - 1), s + 1);
        char *slash = strchr(key, '/');
        double div = 0.0;
        if (slash) {
            *slash = 0;
            div = atof(slash + 1);
        }
        const char *v = campaign_point_key(p, key);
        if (div > 0.0) {
            n += (size_t)snprintf(out + n, len - n, "%.0f", atof(v) / div);
        } else {
            n += (size_t)snprintf(out + n, len - n, "%s", v);
        }
        n = n < len ? n : len - 1;
        s = end + 1;
    }
    out[n] = 0;
}

static int read_table(const campaign_point *p, const gr_campaign_result *r, double *x, double *y,
                      double *e)
{
    char where[256];
    expand_where(p, r->where, where, sizeof where);
    char path[1300];
    snprintf(path, sizeof path, "%s/%s", p->dir, r->table);
    FILE *f = gr_input_fopen(path, &(int){0});
    if (!f) {
        return 0;
    }
    char line[2048], *fields[64];
    int cx = -1, cy = -1, ce = -1, cw[16], n_where = 0, n = 0;
    bool header = true;
    while (fgets(line, sizeof line, f) && n < MAX_BINS) {
        if (line[0] == '#') {
            continue;
        }
        int nf = split(line, fields, 64);
        if (header) {
            header = false;
            cx = column_of(fields, nf, r->x);
            cy = column_of(fields, nf, r->y);
            ce = r->y_err[0] ? column_of(fields, nf, r->y_err) : -1;
            char buf[256];
            snprintf(buf, sizeof buf, "%s", where);
            char *save = NULL;
            for (char *tok = strtok_r(buf, ",", &save); tok && n_where < 16;
                 tok = strtok_r(NULL, ",", &save)) {
                cw[n_where++] = column_of(fields, nf, tok);
            }
            if (cx < 0 || cy < 0) {
                break;
            }
            continue;
        }
        int need = cx > cy ? cx : cy;
        need = ce > need ? ce : need;
        for (int k = 0; k < n_where; k++) {
            need = cw[k] > need ? cw[k] : need;
        }
        if (nf <= need || !row_matches(where, fields, cw, n_where)) {
            continue;
        }
        /* read as the archive keeps them (campaign_archive.c): rows with a finite y, 6 digits, so
         * that a live run and a point restored elsewhere give the same rows, fits and bins */
        const double yv = atof(fields[cy]);
        if (!isfinite(yv)) {
            continue;
        }
        x[n] = campaign_archive_digits(atof(fields[cx]));
        y[n] = campaign_archive_digits(yv);
        e[n++] = ce >= 0 ? campaign_archive_digits(atof(fields[ce])) : (double)NAN;
    }
    fclose(f);
    return n;
}

int campaign_curve_series(const campaign_point *p, const gr_campaign_result *r, double *x,
                          double *y, double *e)
{
    char path[1200], key[512];
    snprintf(path, sizeof path, "%s/series.json", p->dir);
    campaign_curve_key(r, key, sizeof key);
    gr_error ignore = {0};
    FILE *probe = gr_input_fopen(path, &(int){0});
    if (probe) {
        fclose(probe);
        cJSON *j = gr_json_read(path, &ignore);
        const cJSON *s = cJSON_GetObjectItem(j, key);
        const cJSON *ax = cJSON_GetObjectItem(s, "x"), *ay = cJSON_GetObjectItem(s, "y"),
                    *ae = cJSON_GetObjectItem(s, "e");
        int n = 0;
        for (int i = 0; i < cJSON_GetArraySize(ax) && i < cJSON_GetArraySize(ay) && n < MAX_BINS;
             i++) {
            x[n] = cJSON_GetArrayItem(ax, i)->valuedouble;
            y[n] = cJSON_GetArrayItem(ay, i)->valuedouble;
            const cJSON *ei = cJSON_GetArrayItem(ae, i);
            e[n++] = cJSON_IsNumber(ei) ? ei->valuedouble : (double)NAN;
        }
        cJSON_Delete(j);
        if (n) {
            return n;
        }
    }
    return read_table(p, r, x, y, e);
}

/* Does a select value match a label value? Linked values ("48000/0.4/1.0") match part by part,
 * and a part that is a lone '*' matches any part (N+eps_n+eps_t = '*' then /0.4/1.0: every N at
 * eps_n = 0.4, eps_t = 1.0). */
static bool value_matches(const char *pattern, size_t plen, const char *value, size_t vlen)
{
    while (plen && vlen) {
        const char *ps = memchr(pattern, '/', plen), *vs = memchr(value, '/', vlen);
        const size_t pn = ps ? (size_t)(ps - pattern) : plen, vn = vs ? (size_t)(vs - value) : vlen;
        if (!(pn == 1 && pattern[0] == '*') && (pn != vn || strncmp(pattern, value, pn))) {
            return false;
        }
        if (!ps != !vs) { /* one has more parts than the other */
            return false;
        }
        if (!ps) {
            return true;
        }
        plen -= pn + 1;
        pattern += pn + 1;
        vlen -= vn + 1;
        value += vn + 1;
    }
    return !plen && !vlen;
}

/* Is the group label selected? Each key named in `select` ("k=v, k=w, j=u") must have one of its
 * listed values among the ", "-separated tokens of the label: values of one key are alternatives,
 * different keys must all hold ("eps_n=0.1, eps_n=0.4, N=100": eps_n 0.1 or 0.4, and N 100); a
 * linked value may hold "*" parts (value_matches). */
bool campaign_curve_selected(const char *select, const char *label)
{
    char buf[256], lab[200];
    snprintf(buf, sizeof buf, "%s", select); /* select holds at most 255 characters */
    snprintf(lab, sizeof lab, "%s", label);
    char *tok[32], *have[32], *save = NULL;
    int n = 0, nh = 0;
    for (char *t = strtok_r(buf, ", ", &save); t && n < 32; t = strtok_r(NULL, ", ", &save)) {
        tok[n++] = t;
    }
    for (char *t = strtok_r(lab, ", ", &save); t && nh < 32; t = strtok_r(NULL, ", ", &save)) {
        have[nh++] = t;
    }
    for (int i = 0; i < n; i++) { /* key of token i: some token with that key must match */
        const size_t klen = strcspn(tok[i], "=");
        bool any = false;
        for (int j = 0; j < n && !any; j++) {
            if (strcspn(tok[j], "=") != klen || strncmp(tok[i], tok[j], klen) || !tok[j][klen]) {
                continue;
            }
            for (int h = 0; h < nh && !any; h++) {
                const char *v = tok[j] + klen + 1, *w = have[h] + klen + 1;
                any = strcspn(have[h], "=") == klen && !strncmp(have[h], tok[j], klen) &&
                      have[h][klen] && value_matches(v, strlen(v), w, strlen(w));
            }
        }
        if (!any) {
            return false;
        }
    }
    return true;
}

/* y at x0, interpolated linearly in x and ln y between the bins around it (x ascending); NAN when
 * x0 is outside the curve or a neighbour is not positive. */
static double value_at(const double *x, const double *y, int n, double x0)
{
    for (int i = 0; i + 1 < n; i++) {
        if (x[i] <= x0 && x0 <= x[i + 1] && y[i] > 0.0 && y[i + 1] > 0.0) {
            const double w = x[i + 1] > x[i] ? (x0 - x[i]) / (x[i + 1] - x[i]) : 0.0;
            return exp((1.0 - w) * log(y[i]) + w * log(y[i + 1]));
        }
    }
    return NAN;
}

/* transform = scale_at: every curve divided by its value at x0, so that all pass through (x0, 1):
 * the vertical scaling of the thesis's Fig. 5.3 (5.4), which compares the shapes of P(v). */
static bool scale_at(double x0, double *y, double *e, const double *x, int n)
{
    const double y0 = value_at(x, y, n, x0);
    if (!(y0 > 0.0)) {
        return false;
    }
    for (int i = 0; i < n; i++) {
        y[i] /= y0;
        e[i] /= y0;
    }
    return true;
}

/* transform = log_ratio: y -> -ln(y / y(0)) at x > 0, the quantity of Moon, Swift and Swinney's plot
 * (thesis 5.6, Figs. 5.6-5.7): for P(v) = P(0) exp(-c v^alpha) it is c v^alpha, a line of slope
 * alpha on log-log axes, so the window's slope is the local exponent alpha of the tail. The bins at
 * x <= 0 (the distribution is even) and those within 1 % of y(0) (where -ln is rounding noise) are
 * dropped; the error is e / y. */
static int log_ratio(double *x, double *y, double *e, int n)
{
    const double y0 = value_at(x, y, n, 0.0);
    if (!(y0 > 0.0)) {
        return 0;
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (x[i] > 0.0 && y[i] > 0.0 && y[i] < 0.99 * y0) { /* the peak's top: noise on 1 */
            x[m] = x[i];
            e[m] = e[i] / y[i];
            y[m++] = -log(y[i] / y0);
        }
    }
    return m;
}

/* transform = moment_scale: v -> v / M and P -> P M with M = <|v|^m>^(1/m) the run's own moment
 * (analysis.moments.speed.m{m} of its summary): the thesis's attempted collapse of P(v) over N,
 * Figs. 3.6-3.7 (sec. 3.2.3, v -> v / <|v|^m>^(1/m)); the area under each curve stays 1. */
static bool moment_scale(const campaign_point *p, int m, double *x, double *y, double *e, int n)
{
    char path[64];
    snprintf(path, sizeof path, "analysis.moments.speed.m%d", m);
    const double mm = gr_summary_number(p->summary, path);
    if (!(mm > 0.0) || !isfinite(mm)) {
        return false;
    }
    const double M = pow(mm, 1.0 / m);
    for (int i = 0; i < n; i++) {
        x[i] /= M;
        y[i] *= M;
        e[i] *= M;
    }
    return true;
}

/* A series of one point in place by `transform`; returns its length (0: it cannot be mapped). */
int campaign_curve_transform(const gr_campaign_result *r, const campaign_point *p, double *x,
                             double *y, double *e, int n)
{
    if (!strcmp(r->transform, "bisection_collapse")) {
        return campaign_bisection_collapse(atof(campaign_point_key(p, "system.N")), r->collapse_at,
                                           x, y, e, n)
                   ? n
                   : 0;
    }
    if (!strcmp(r->transform, "scale_at")) {
        return scale_at(r->collapse_at, y, e, x, n) ? n : 0;
    }
    if (!strcmp(r->transform, "log_ratio")) {
        return log_ratio(x, y, e, n);
    }
    if (!strcmp(r->transform, "moment_scale")) {
        return moment_scale(p, (int)r->scale_moment, x, y, e, n) ? n : 0;
    }
    return n;
}

/* The collapse map (3.39-3.40) of one series in place (declared in campaign_points.h); x ascending. */
bool campaign_bisection_collapse(double N, double x0, double *x, double *y, double *e, int n)
{
    const double nb = log2(N), p = 1.0 / (nb - 1.0);
    double g0 = NAN; /* G(x0), interpolated linearly in ln x, ln G between the bins around x0 */
    for (int i = 0; i + 1 < n; i++) {
        if (x[i] > 0.0 && x[i] <= x0 && x0 <= x[i + 1] && y[i] > 0.0 && y[i + 1] > 0.0) {
            const double w = x[i + 1] > x[i] ? log(x0 / x[i]) / log(x[i + 1] / x[i]) : 0.0;
            g0 = exp((1.0 - w) * log(y[i]) + w * log(y[i + 1]));
            break;
        }
    }
    if (!(g0 > 0.0) || !(nb > 1.0)) {
        return false;
    }
    const double A = -log(x0) * pow(g0, -p);
    for (int i = 0; i < n; i++) {
        const double Y = y[i] > 0.0 ? A * pow(y[i], p) : (double)NAN;
        e[i] = y[i] > 0.0 ? Y * p * e[i] / y[i] : (double)NAN; /* dY = Y p dy / y */
        y[i] = Y;
        x[i] = x[i] > 0.0 && x[i] < 1.0 ? -log(x[i]) : (double)NAN;
    }
    return true;
}

/* Slope b of y = a x^b over the window (NAN with too few points); *err its error. */
static double slope(const gr_campaign_result *r, const double *x, const double *y, const double *e,
                    int n, double *err, int *used, double *chi2_red)
{
    double fx[MAX_BINS], fy[MAX_BINS], fe[MAX_BINS];
    int m = 0;
    bool weights = true;
    for (int i = 0; i < n; i++) {
        if (isfinite(x[i]) && isfinite(y[i]) && y[i] > 0.0 && x[i] >= r->x_min &&
            x[i] <= r->x_max) {
            fx[m] = x[i];
            fy[m] = y[i];
            fe[m] = e[i];
            weights &= isfinite(e[i]) && e[i] > 0.0;
            m++;
        }
    }
    *used = m;
    gr_fit fit;
    gr_error ignore = {0};
    if (m < GR_FIT_MIN_POINTS || gr_fit_power_law(fx, fy, weights ? fe : NULL, m, &fit, &ignore)) {
        *err = NAN;
        return NAN;
    }
    *chi2_red = weights ? fit.chi2_red : (double)NAN;
    *err = fit.err[1];
    return fit.p[1];
}

typedef struct curve_acc {
    double x[MAX_BINS], sum[MAX_BINS], sum2[MAX_BINS], err2[MAX_BINS];
    int count[MAX_BINS], n;
} curve_acc;

static void acc_add(curve_acc *a, const double *x, const double *y, const double *e, int n)
{
    if (a->n == 0) {
        a->n = n;
        memcpy(a->x, x, (size_t)n * sizeof *x);
    }
    for (int i = 0, k = 0; i < n; i++) { /* the runs share the bins: match them by abscissa */
        while (k < a->n && !(fabs(a->x[k] - x[i]) <= 1e-9 * fabs(x[i]))) {
            k++;
        }
        if (k == a->n) {
            k = 0;
            continue;
        }
        if (isfinite(y[i])) {
            a->sum[k] += y[i];
            a->sum2[k] += y[i] * y[i];
            a->err2[k] += isfinite(e[i]) ? e[i] * e[i] : 0.0;
            a->count[k]++;
        }
    }
}

double campaign_curve_overlay_amplitude(const gr_campaign_result *r, const double *x,
                                        const double *y, int n)
{
    double sum = 0.0;
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (x[i] > 0.0 && y[i] > 0.0 && x[i] >= r->x_min && x[i] <= r->x_max) {
            sum += log(y[i]) - r->overlay_exponent * log(x[i]);
            m++;
        }
    }
    return m ? exp(sum / m) : (double)NAN;
}

/* The dashed line beside one mean curve (x, y): overlay = power_law, A x^E with E fixed and ln A the
 * mean of ln y - E ln x over the window's points (the thesis's "power-law fits of A k^-1.63", Figs.
 * 4.3-4.5, and "linear fits of -alpha ln(v) + C", Figs. 5.6-5.7), drawn over the window; overlay =
 * column, the seed mean of the fit column the runs wrote (oacc). Returns the points written. */
static int overlay_block(FILE *f, const gr_campaign_result *r, const double *x, const double *y,
                         int n, const curve_acc *oacc)
{
    int written = 0;
    double lo = INFINITY, hi = -INFINITY; /* the curve's extent: the line is drawn over it */
    for (int i = 0; i < n; i++) {
        if (isfinite(x[i]) && y[i] > 0.0) {
            lo = fmin(lo, x[i]);
            hi = fmax(hi, x[i]);
        }
    }
    if (!strcmp(r->overlay, "column")) {
        for (int i = 0; i < oacc->n; i++) {
            const double v = oacc->count[i] ? oacc->sum[i] / oacc->count[i] : (double)NAN;
            if (isfinite(v) && v > 0.0 && oacc->x[i] >= lo && oacc->x[i] <= hi) {
                fprintf(f, "%.9g %.9g\n", oacc->x[i], v);
                written++;
            }
        }
        return written;
    }
    const double A = campaign_curve_overlay_amplitude(r, x, y, n);
    /* drawn beyond the window (to half its low end and twice its high end, within the curve) so
     * that where the curve leaves the thesis's form shows */
    for (int i = 0; isfinite(A) && i < n; i++) {
        if (x[i] > 0.0 && y[i] > 0.0 && x[i] >= 0.5 * r->x_min && x[i] <= 2.0 * r->x_max) {
            fprintf(f, "%.9g %.9g\n", x[i], A * pow(x[i], r->overlay_exponent));
            written++;
        }
    }
    return written;
}

int campaign_curve(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                   campaign_rows *rows, gr_file *data, gr_error *err)
{
    (void)c;
    (void)err;
    static char groups[MAX_GROUPS][160];
    const int ng = campaign_groups(pts, NULL, NULL, groups);
    const bool map = !strcmp(r->transform, "bisection_collapse"),
               ratio = r->transform[0] != 0; /* every transform leaves y without a unit */
    char xb[64],
        yb[64]; /* the table's units (the observable's column line); the collapse has none */
    const char *xu = map ? "1" : gr_obs_column_unit(r->table, r->x, xb, sizeof xb),
               *yu = ratio ? "1" : gr_obs_column_unit(r->table, r->y, yb, sizeof yb);
    gr_file
        over; /* ID_overlay.dat: the dashed line of every curve, one block each (the plot's index) */
    const bool overlay = !strcmp(r->overlay, "power_law") || !strcmp(r->overlay, "column");
    if (overlay) {
        char dir[1100], name[80];
        snprintf(dir, sizeof dir, "%s", data->path); /* the data file's folder */
        char *slash = strrchr(dir, '/');
        if (slash) {
            *slash = 0;
        } else {
            snprintf(dir, sizeof dir, ".");
        }
        snprintf(name, sizeof name, "%s_overlay.dat", r->id);
        const int rc = gr_file_open(&over, dir, name, err);
        if (rc) {
            return rc;
        }
    }
    gr_campaign_result col = *r; /* overlay = column: the same table's fit column */
    snprintf(col.y, sizeof col.y, "%s", r->overlay_y);
    col.y_err[0] = 0;
    int blocks = 0;
    campaign_header(data, "group", "", "m", "1", "x", xu, "mean", yu, "error", yu, "seeds", "1",
                    "in_fit", "1", NULL);
    double *x = malloc(3 * MAX_BINS * sizeof *x), *y = x + MAX_BINS, *e = y + MAX_BINS;
    curve_acc *acc = calloc(1, sizeof *acc), *oacc = calloc(1, sizeof *oacc);
    for (int g = 0; g < ng; g++) {
        if (r->select[0] && !campaign_curve_selected(r->select, groups[g])) {
            continue;
        }
        const campaign_point *members[MAX_SEEDS];
        const int nm = campaign_members(pts, groups[g], members, MAX_SEEDS);
        memset(acc, 0, sizeof *acc);
        memset(oacc, 0, sizeof *oacc);
        double slopes[MAX_SEEDS], slope_err_fit = NAN;
        int ns = 0, used = 0;
        campaign_row *row = campaign_group_row(rows, groups[g]);
        for (int k = 0; k < nm; k++) {
            if (!strcmp(r->overlay, "column")) {
                const int no = campaign_curve_series(members[k], &col, x, y, e);
                acc_add(oacc, x, y, e, no);
            }
            const int n = campaign_curve_transform(r, members[k], x, y, e,
                                                   campaign_curve_series(members[k], r, x, y, e));
            if (n == 0) {
                continue;
            }
            campaign_add_cost(row, members[k]);
            row->n_seeds++;
            acc_add(acc, x, y, e, n);
            double se, chi2;
            const double b = slope(r, x, y, e, n, &se, &used, &chi2);
            if (isfinite(b) && ns < MAX_SEEDS) {
                slopes[ns++] = b;
            }
        }
        for (int i = 0; i < acc->n;
             i++) { /* the mean curve: seeds' scatter, or the run's own error */
            const int m = acc->count[i];
            x[i] = acc->x[i];
            y[i] = m ? acc->sum[i] / m : (double)NAN;
            const double var = m >= 2 ? (acc->sum2[i] - m * y[i] * y[i]) / (m - 1) : (double)NAN;
            const double se_seeds = var > 0.0 ? sqrt(var / m) : (double)NAN,
                         se_runs = m ? sqrt(acc->err2[i]) / m : (double)NAN;
            e[i] = campaign_headline_error(se_seeds, se_runs, m);
        }
        if (r->x_min > 0.0 || isfinite(r->x_max)) {
            row->value = slope(r, x, y, e, acc->n, &slope_err_fit, &used, &row->chi2_red);
            row->n_x = used;
            row->x_lo = r->x_min;
            row->x_hi = r->x_max;
            snprintf(row->x_unit, sizeof row->x_unit, "%s", xu ? xu : "");
            row->error_fit = slope_err_fit;
            double mean_s;
            campaign_mean_sd(slopes, ns, &mean_s, &row->error_seeds);
            row->error = campaign_headline_error(row->error_seeds, slope_err_fit, ns);
        }
        campaign_row_thesis(r, row);
        int written = 0;
        for (int i = 0; i < acc->n; i++) {
            if (isfinite(x[i]) && isfinite(y[i]) && y[i] > 0.0) {
                const bool in = x[i] >= r->x_min && x[i] <= r->x_max;
                gr_csv_text(data->f, groups[g], true);
                fprintf(data->f, ",0,%.9g,%.9g,%.9g,%d,%d\n", x[i], y[i],
                        isfinite(e[i]) ? e[i] : 0.0, acc->count[i], in);
                written++;
            }
        }
        if (overlay && written) { /* a block per plotted curve, even an empty one (NaN) */
            fprintf(over.f, "%s", blocks++ ? "\n\n" : "");
            if (!overlay_block(over.f, r, x, y, acc->n, oacc)) {
                fprintf(over.f, "NaN NaN\n");
            }
        }
        if (!strcmp(r->overlay, "bisection") && nm > 0 &&
            acc->n > 0) { /* 3.36, beside the curve: seeds = 0 */
            const double nb = log2(atof(campaign_point_key(members[0], "system.N")));
            for (int i = 0; i < acc->n; i++) {
                if (acc->x[i] > 0.0 && acc->x[i] < 1.0 &&
                    acc->sum[i] > 0.0) { /* where the curve has data */
                    const double P = exp((nb - 1.0) * log(-log(acc->x[i])) - lgamma(nb));
                    fprintf(data->f, "\"uniform bisection (3.36); n = %.4g\",0,%.9g,%.9g,0,0,0\n",
                            nb, acc->x[i], P);
                }
            }
        }
    }
    free(acc);
    free(oacc);
    free(x);
    return overlay ? gr_file_commit(&over, err) : GR_OK;
}
