/* The three analyses of a campaign result (docs/campaigns/README.md). Error bars come from
 * independent seeds wherever a group has three or more: block averaging inside one run is
 * optimistic for a clustering gas (its correlation times are long), so the within-run error is
 * only used when there are fewer seeds, and then the larger of the two estimates is kept. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/scene.h"
#include "io/summary_read.h"
#include "io/plot.h"
#include "app/reproduce/campaign_points.h"

#define MAX_X 64

/* The path of y (or y_err) for moment m: {m} -> m, {m-1} -> m - 1. */
static void path_for(const char *pattern, int m, char *out, size_t len)
{
    const char *a = strstr(pattern, "{m-1}"), *b = strstr(pattern, "{m}");
    if (a) {
        snprintf(out, len, "%.*s%d%s", (int)(a - pattern), pattern, m - 1, a + 5);
    } else if (b) {
        snprintf(out, len, "%.*s%d%s", (int)(b - pattern), pattern, m, b + 3);
    } else {
        snprintf(out, len, "%s", pattern);
    }
}

/* A y path that leads nowhere in any finished point's summary.json (a misspelt path) would give an
 * empty result silently: refused, naming it. A path whose parent is there is kept: a fit that did
 * not succeed leaves out its numbers (its status says why), and the rows say so. */
static int y_present(const gr_campaign_result *r, const campaign_points *pts, gr_error *err)
{
    const int m_lo = r->m_lo ? r->m_lo : 0, m_hi = r->m_lo ? r->m_hi : 0;
    for (int m = m_lo; m <= m_hi; m += r->m_step > 0 ? r->m_step : 1) {
        char yp[160];
        path_for(r->y, m, yp, sizeof yp);
        char *dot = strrchr(yp, '.');
        for (int i = 0; i < pts->n; i++) {
            if (gr_summary_node(pts->p[i].summary, yp)) {
                return GR_OK;
            }
            if (dot) {
                *dot = '\0';
                const bool parent = gr_summary_node(pts->p[i].summary, yp) != NULL;
                *dot = '.';
                if (parent) {
                    return GR_OK;
                }
            }
        }
    }
    return pts->n == 0
               ? GR_OK
               : GR_FAIL(err, GR_EINVAL,
                         "[result %s] y = %s: no such entry in the summary.json of any of the %d "
                         "finished "
                         "points (a dotted path into it, such as T or analysis.moments.speed.2)",
                         r->id, r->y, pts->n);
}

static bool listed(const char *list, const char *key)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", list);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
        if (!strcmp(tok, key)) {
            return true;
        }
    }
    return false;
}

/* A varied key without its section: "model.eps_n" -> "eps_n", "system.packing_fraction+system.N"
 * -> "packing_fraction+N". */
static void short_key(const char *key, char *out, size_t len)
{
    size_t n = 0;
    const char *part = key;
    while (part && n + 1 < len) {
        const char *end = strchr(part, '+'), *dot = strchr(part, '.');
        const char *from = dot && (!end || dot < end) ? dot + 1 : part;
        n += (size_t)snprintf(out + n, len - n, "%s%.*s", n ? "+" : "",
                              (int)(end ? end - from : (long)strlen(from)), from);
        part = end ? end + 1 : NULL;
    }
}

/* "k=v, k=v" of the point's varied keys (without their sections): those in `only` (all if NULL),
 * minus `except`. */
void campaign_group_of(const campaign_point *p, const char *only, const char *except, char *out,
                       size_t len)
{
    out[0] = 0;
    size_t n = 0;
    const cJSON *k;
    cJSON_ArrayForEach(k, cJSON_GetObjectItem(p->manifest, "keys"))
    {
        if ((only && !listed(only, k->string)) || (except && !strcmp(except, k->string)) ||
            !cJSON_IsString(k)) {
            continue;
        }
        char sk[96];
        short_key(k->string, sk, sizeof sk);
        n += (size_t)snprintf(out + n, n < len ? len - n : 0, "%s%s=%s", n ? ", " : "", sk,
                              k->valuestring);
    }
    if (n == 0) {
        snprintf(out, len, "all");
    }
}

int campaign_seed_of(const campaign_point *p)
{
    return (int)gr_summary_number(p->manifest, "seed");
}

/* Two group labels ("eps_n=0.1, N=100", "N+L=500/0.1") in natural order: text by character,
 * numbers by value, so a figure's curves and a table's rows run 0.01, 0.1, 0.3 ... and
 * N = 100, 251, 1000, not in the order the sweep ran them. */
static int group_cmp(const void *a, const void *b)
{
    const char *p = a, *q = b;
    while (*p && *q) {
        if (isdigit((unsigned char)*p) && isdigit((unsigned char)*q)) {
            char *pe, *qe;
            const double x = strtod(p, &pe), y = strtod(q, &qe);
            if (x != y) {
                return x < y ? -1 : 1;
            }
            p = pe;
            q = qe;
            continue;
        }
        if (*p != *q) {
            return (unsigned char)*p < (unsigned char)*q ? -1 : 1;
        }
        p++;
        q++;
    }
    return (unsigned char)*p - (unsigned char)*q;
}

/* The distinct groups, in natural order of their labels (group_cmp). */
int campaign_groups(const campaign_points *pts, const char *only, const char *except, char g[][160])
{
    int n = 0;
    for (int i = 0; i < pts->n; i++) {
        char label[160];
        campaign_group_of(&pts->p[i], only, except, label, sizeof label);
        int j = 0;
        while (j < n && strcmp(g[j], label)) {
            j++;
        }
        if (j == n && n < MAX_GROUPS) {
            snprintf(g[n++], 160, "%s", label);
        }
    }
    qsort(g, (size_t)n, sizeof g[0], group_cmp);
    return n;
}

void campaign_mean_sd(const double *v, int n, double *mean, double *se)
{
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; i++) {
        s += v[i];
    }
    *mean = n ? s / n : (double)NAN;
    for (int i = 0; i < n; i++) {
        s2 += (v[i] - *mean) * (v[i] - *mean);
    }
    *se = n >= 2 ? sqrt(s2 / (n - 1) / n) : (double)NAN;
}

/* Seeds when there are three or more; otherwise the larger of what there is. */
double campaign_headline_error(double seeds, double other, int n_seeds)
{
    if (n_seeds >= 3 && isfinite(seeds)) {
        return seeds;
    }
    if (isfinite(seeds) && isfinite(other)) {
        return fmax(seeds, other);
    }
    return isfinite(seeds) ? seeds : other;
}

void campaign_add_cost(campaign_row *row, const campaign_point *p)
{
    row->cpu_seconds += isfinite(p->cpu_seconds) ? p->cpu_seconds : 0.0;
    row->sim_seconds += isfinite(p->sim_seconds) ? p->sim_seconds : 0.0;
    row->unconverged += cJSON_IsFalse(cJSON_GetObjectItem(p->summary, "T_stderr_converged"));
    const cJSON *h = cJSON_GetObjectItem(p->manifest, "scene_hash");
    if (cJSON_IsString(h) && !strstr(row->hashes, h->valuestring) &&
        strlen(row->hashes) + 18 < sizeof row->hashes) {
        size_t len = strlen(row->hashes);
        snprintf(row->hashes + len, sizeof row->hashes - len, "%s%s", len ? " " : "",
                 h->valuestring);
    }
}

int campaign_members(const campaign_points *pts, const char *group, const campaign_point **members,
                     int max)
{
    int n = 0;
    for (int i = 0; i < pts->n && n < max; i++) {
        char label[160];
        campaign_group_of(&pts->p[i], NULL, NULL, label, sizeof label);
        if (!strcmp(label, group)) {
            members[n++] = &pts->p[i];
        }
    }
    return n;
}

void campaign_draw(const char *dir, const char *id, const char *suffix, const char *body)
{
    char note[256], png[160];
    snprintf(png, sizeof png, "%.100s%.40s.png", id, suffix);
    if (gr_plot_script(dir, png, body, note, sizeof note)) {
        campaign_note("%s/%s not drawn: %s", dir, png, note);
    }
}

campaign_row *campaign_group_row(campaign_rows *rows, const char *group)
{
    campaign_row *row = campaign_rows_add(rows);
    snprintf(row->group, sizeof row->group, "%.159s", group);
    return row;
}

void campaign_header(gr_file *f, ...)
{
    va_list ap;
    va_start(ap, f);
    for (const char *name = va_arg(ap, const char *); name; name = va_arg(ap, const char *)) {
        gr_file_column(f, name, va_arg(ap, const char *));
    }
    va_end(ap);
    fputc('\n', f->f);
}

const char *campaign_unit(const gr_campaign_result *r) { return r->unit[0] ? r->unit : "1"; }

const char *campaign_y_unit(const gr_campaign_result *r, char *buf, size_t len)
{
    if (strstr(r->y, "{m")) { /* one moment per row: its power is the row's m */
        return strstr(r->y, "gaps.moments.")    ? "m^m"
               : strstr(r->y, "moments.speed.") ? "(m s-1)^m"
                                                : NULL;
    }
    return gr_summary_unit(r->y, buf, len);
}

int campaign_mean(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                  campaign_rows *rows, gr_file *data, gr_error *err)
{
    (void)c;
    int rc = y_present(r, pts, err);
    if (rc) {
        return rc;
    }
    static char g[MAX_GROUPS][160];
    int ng = campaign_groups(pts, NULL, NULL, g);
    campaign_header(data, "group", "", "seed", "1", "value", campaign_unit(r), "run_error",
                    campaign_unit(r), NULL);
    for (int gi = 0; gi < ng; gi++) {
        if (r->select[0] && !campaign_curve_selected(r->select, g[gi])) {
            continue; /* a campaign whose tables share runs: this result's rows only */
        }
        double v[MAX_SEEDS], e2 = 0.0;
        int n = 0, n_err = 0;
        campaign_row *row = campaign_group_row(rows, g[gi]);
        const campaign_point *m[MAX_SEEDS];
        int nm = campaign_members(pts, g[gi], m, MAX_SEEDS);
        for (int i = 0; i < nm; i++) {
            double y = gr_summary_number(m[i]->summary, r->y);
            if (!isfinite(y)) {
                continue;
            }
            double ye = r->y_err[0] ? gr_summary_number(m[i]->summary, r->y_err) : (double)NAN;
            gr_csv_text(data->f, g[gi], true);
            fprintf(data->f, ",%d,%.9g,%.9g\n", campaign_seed_of(m[i]), y, ye);
            v[n++] = y;
            if (isfinite(ye)) {
                e2 += ye * ye;
                n_err++;
            }
            campaign_add_cost(row, m[i]);
        }
        campaign_mean_sd(v, n, &row->value, &row->error_seeds);
        row->error_fit =
            n_err == n && n ? sqrt(e2) / n : (double)NAN; /* the runs' own errors, combined */
        row->error = campaign_headline_error(row->error_seeds, row->error_fit, n);
        row->n_seeds = n;
        campaign_row_thesis(r, row);
    }
    return GR_OK;
}

/* The seeds' own values at the fit's abscissae (a seed's runs at every size, in fit order), so
 * that a local slope or trend is also formed per seed: a seed's runs at two sizes share the noise
 * of their common particles (keyed by seed, step and index), so they need not be independent, and
 * the spread of the per-seed values is the error that allows for it. */
typedef struct seed_table {
    double (*v)[MAX_X]; /* v[s][xi]: seed s at abscissa xi (NAN if not run); not written */
    int n_seed;
    const int *fxi; /* fit index -> xi */
} seed_table;

/* The row's second estimate from the seeds' own values (error_seeds, n_seeds) with 3 or more, and
 * its headline error the larger of the two, as for the fit's own row. */
static void per_seed_error(campaign_row *w, const double *vals, int n)
{
    if (n < 3) {
        return;
    }
    double mean;
    campaign_mean_sd(vals, n, &mean, &w->error_seeds);
    w->n_seeds = n;
    w->error = fmax(w->error_fit, w->error_seeds);
}

/* Does the exponent still move with x? ln y = p0 + p1 u + p2 u^2 in u = ln x - u_c (u_c the mean
 * of ln x; errors sigma/y) has the local exponent -(p1 + 2 p2 u): its change per unit ln x is
 * -2 p2, one number from every size at once, where neighbouring local slopes share their sizes'
 * means and scatter. One row "GROUP, trend X=lo-hi" (role 't'); none below 4 sizes (a quadratic
 * through 3 points has no error). */
static void slope_trend(campaign_rows *rows, const char *group, int m, double scale,
                        const double *fx, const double *fy, const double *fe, int nf,
                        const char *short_x, const seed_table *st)
{
    if (nf < 4) {
        return;
    }
    double u[MAX_X], ly[MAX_X], ls[MAX_X], uc = 0.0, lo = fx[0], hi = fx[0];
    bool errors = true;
    for (int i = 0; i < nf; i++) {
        uc += log(fx[i]) / nf;
        lo = fmin(lo, fx[i]);
        hi = fmax(hi, fx[i]);
        errors &= isfinite(fe[i]) && fe[i] > 0.0;
    }
    for (int i = 0; i < nf; i++) {
        u[i] = log(fx[i]) - uc;
        ly[i] = log(fy[i]);
        ls[i] = fe[i] / fy[i];
    }
    gr_fit q;
    gr_error ignore = {0};
    if (gr_fit_poly(u, ly, errors ? ls : NULL, nf, 2, &q, &ignore)) {
        return;
    }
    campaign_row *w = campaign_rows_add(rows);
    snprintf(w->group, sizeof w->group, "%.100s, trend %.20s=%g-%g", group, short_x, lo, hi);
    w->m = m;
    w->role = 't';
    w->value = -2.0 * q.p[2] * scale;
    w->error = w->error_fit = 2.0 * q.err[2] * scale;
    w->chi2_red = q.chi2_red;
    w->n_x = nf;
    w->x_lo = lo;
    w->x_hi = hi;
    w->centre_x = exp(uc);
    w->centre_value = -q.p[1] * scale;
    double per[MAX_SEEDS];
    int ns = 0;
    for (int sd = 0; sd < st->n_seed; sd++) { /* the seeds run at every size */
        double ys[MAX_X];
        bool all = true;
        for (int i = 0; i < nf && all; i++) {
            ys[i] = log(st->v[sd][st->fxi[i]]);
            all = isfinite(ys[i]);
        }
        gr_fit qs;
        if (all && gr_fit_poly(u, ys, NULL, nf, 2, &qs, &ignore) == GR_OK) {
            per[ns++] = -2.0 * qs.p[2] * scale;
        }
    }
    per_seed_error(w, per, ns);
}

/* The exponent between abscissae a and b, xi = ln(y_a / y_b) / ln(x_b / x_a), with the error of
 * the two seed means propagated as if independent and, beside it, the seeds' own spread
 * (seed_table): one row "GROUP, X=x_a-x_b" of the given role. */
static void slope_row(campaign_rows *rows, const char *group, int m, double scale, const double *fx,
                      const double *fy, const double *fe, int a, int b, char role,
                      const char *short_x, const seed_table *st)
{
    campaign_row *w = campaign_rows_add(rows);
    snprintf(w->group, sizeof w->group, "%.100s, %.20s=%g-%g", group, short_x, fx[a], fx[b]);
    w->m = m;
    const double lx = log(fx[b] / fx[a]);
    w->value = log(fy[a] / fy[b]) / lx * scale;
    w->error = w->error_fit = hypot(fe[a] / fy[a], fe[b] / fy[b]) / lx * scale;
    w->n_x = 2;
    w->x_lo = fx[a];
    w->x_hi = fx[b];
    w->role = role;
    double per[MAX_SEEDS];
    int ns = 0;
    for (int sd = 0; sd < st->n_seed; sd++) {
        const double ya = st->v[sd][st->fxi[a]], yb = st->v[sd][st->fxi[b]];
        if (isfinite(ya) && isfinite(yb)) {
            per[ns++] = log(ya / yb) / lx * scale;
        }
    }
    per_seed_error(w, per, ns);
}

/* The local slopes: one row per pair of neighbouring abscissae (role 'l'); with slope_span = K
 * also one per pair K sizes apart (role 'w': the same means, but a lever arm ln(x_i+K / x_i) K
 * times longer, so an error about K times smaller); then their trend (slope_trend). Where the
 * power law only holds asymptotically, these show whether the slope still moves with x. */
static void local_slopes(const gr_campaign_result *r, campaign_rows *rows, const char *group, int m,
                         double scale, const double *fx, const double *fy, const double *fe, int nf,
                         const seed_table *st)
{
    int order[MAX_X];
    for (int i = 0; i < nf; i++) { /* x ascending */
        int j = i;
        while (j > 0 && fx[order[j - 1]] > fx[i]) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = i;
    }
    char short_x[64];
    const char *dot = strrchr(r->x, '.');
    snprintf(short_x, sizeof short_x, "%s", dot ? dot + 1 : r->x);
    for (int k = 0; k + 1 < nf; k++) {
        slope_row(rows, group, m, scale, fx, fy, fe, order[k], order[k + 1], 'l', short_x, st);
    }
    for (int k = 0; r->slope_span > 1 && k + r->slope_span < nf; k++) {
        slope_row(rows, group, m, scale, fx, fy, fe, order[k], order[k + r->slope_span], 'w',
                  short_x, st);
    }
    slope_trend(rows, group, m, scale, fx, fy, fe, nf, short_x, st);
}

int campaign_power_law(const gr_campaign *c, const gr_campaign_result *r,
                       const campaign_points *pts, campaign_rows *rows, gr_file *data,
                       gr_error *err)
{
    (void)c;
    int rc = y_present(r, pts, err);
    if (rc) {
        return rc;
    }
    static char g[MAX_GROUPS][160];
    int ng = campaign_groups(pts, r->by[0] ? r->by : NULL, r->by[0] ? NULL : r->x, g);
    int m_lo = r->m_lo ? r->m_lo : 0, m_hi = r->m_lo ? r->m_hi : 0;
    char y_unit[64];
    const char *yu = campaign_y_unit(r, y_unit, sizeof y_unit);
    campaign_header(data, "group", "", "m", "1", "x", gr_scene_key_unit(r->x), "mean", yu, "error",
                    yu, "seeds", "1", "in_fit", "1", NULL);
    for (int gi = 0; gi < ng; gi++) {
        for (int m = m_lo; m <= m_hi; m += r->m_step > 0 ? r->m_step : 1) {
            char yp[160], ep[160];
            path_for(r->y, m, yp, sizeof yp);
            path_for(r->y_err, m, ep, sizeof ep);
            double xs[MAX_X], ys[MAX_X], es[MAX_X], per_seed[MAX_SEEDS][MAX_X];
            int seeds[MAX_SEEDS], n_seed = 0, nx = 0, counts[MAX_X];
            bool all_errors = true;
            campaign_row *row = campaign_rows_add(rows);
            snprintf(row->group, sizeof row->group, "%.159s", g[gi]);
            row->m = m;
            /* the abscissae of this group, in the order met */
            for (int i = 0; i < pts->n; i++) {
                char label[160];
                campaign_group_of(&pts->p[i], r->by[0] ? r->by : NULL, r->by[0] ? NULL : r->x,
                                  label, sizeof label);
                double x = atof(campaign_point_key(&pts->p[i], r->x));
                double y = gr_summary_number(pts->p[i].summary, yp);
                if (strcmp(label, g[gi]) || !(x > 0.0) || !isfinite(y)) {
                    continue;
                }
                int xi = 0;
                while (xi < nx && xs[xi] != x) {
                    xi++;
                }
                if (xi == nx && nx < MAX_X) {
                    xs[nx] = x;
                    counts[nx] = 0;
                    ys[nx] = es[nx] = 0.0;
                    for (int s = 0; s < MAX_SEEDS; s++) {
                        per_seed[s][nx] = NAN;
                    }
                    nx++;
                }
                if (xi == nx) {
                    continue;
                }
                int seed = campaign_seed_of(&pts->p[i]), si = 0;
                while (si < n_seed && seeds[si] != seed) {
                    si++;
                }
                if (si == n_seed && n_seed < MAX_SEEDS) {
                    seeds[n_seed++] = seed;
                }
                if (si < n_seed) {
                    per_seed[si][xi] = y;
                }
                ys[xi] += y;
                es[xi] += r->y_err[0] ? gr_summary_number(pts->p[i].summary, ep)
                                      : (double)NAN; /* summed below */
                counts[xi]++;
                if (xs[xi] >= r->x_min && xs[xi] <= r->x_max) {
                    campaign_add_cost(row, &pts->p[i]);
                }
            }
            /* per abscissa: the seed mean and its error */
            double fx[MAX_X], fy[MAX_X], fe[MAX_X];
            int nf = 0, min_seeds = MAX_SEEDS, fxi[MAX_X];
            for (int xi = 0; xi < nx; xi++) {
                double v[MAX_SEEDS], mean, se;
                int n = 0;
                for (int s = 0; s < n_seed; s++) {
                    if (isfinite(per_seed[s][xi])) {
                        v[n++] = per_seed[s][xi];
                    }
                }
                campaign_mean_sd(v, n, &mean, &se);
                double run_err = n ? es[xi] / n / sqrt((double)n)
                                   : (double)NAN; /* mean of run errors / sqrt(n) */
                double e = campaign_headline_error(se, run_err, n);
                bool in = xs[xi] >= r->x_min && xs[xi] <= r->x_max;
                gr_csv_text(data->f, g[gi], true);
                fprintf(data->f, ",%d,%.9g,%.9g,%.9g,%d,%d\n", m, xs[xi], mean, e, n, in);
                if (in) {
                    fxi[nf] = xi;
                    fx[nf] = xs[xi];
                    fy[nf] = mean;
                    fe[nf] = e;
                    all_errors &= isfinite(e) && e > 0.0;
                    min_seeds = n < min_seeds ? n : min_seeds;
                    nf++;
                }
            }
            row->n_x = nf;
            row->n_seeds = nf ? min_seeds : 0;
            if (nf < 3) {
                campaign_row_thesis(r, row); /* the thesis's value is shown even without ours */
                continue;                    /* a line through two points has no error: no value */
            }
            row->x_lo = fx[0];
            row->x_hi = fx[0];
            for (int i = 1; i < nf; i++) {
                row->x_lo = fmin(row->x_lo, fx[i]);
                row->x_hi = fmax(row->x_hi, fx[i]);
            }
            gr_fit fit;
            if (gr_fit_power_law(fx, fy, all_errors ? fe : NULL, nf, &fit, err)) {
                return err->code;
            }
            double scale = r->per_m && m ? 1.0 / m : 1.0;
            row->value = -fit.p[1] * scale;
            row->error_fit = fit.err[1] * scale;
            row->chi2_red = fit.chi2_red;
            /* the exponent of every seed on its own, and their spread */
            double ex[MAX_SEEDS];
            int ne = 0;
            for (int s = 0; s < n_seed; s++) {
                double sx[MAX_X], sy[MAX_X];
                int ns = 0;
                for (int xi = 0; xi < nx; xi++) {
                    if (xs[xi] >= r->x_min && xs[xi] <= r->x_max && isfinite(per_seed[s][xi])) {
                        sx[ns] = xs[xi];
                        sy[ns++] = per_seed[s][xi];
                    }
                }
                gr_fit fs;
                gr_error ignore = {0};
                if (ns == nf && gr_fit_power_law(sx, sy, NULL, ns, &fs, &ignore) == GR_OK) {
                    ex[ne++] = -fs.p[1] * scale;
                }
            }
            double mean_e;
            campaign_mean_sd(ex, ne, &mean_e, &row->error_seeds);
            row->error = campaign_headline_error(row->error_seeds, row->error_fit, ne);
            if (isfinite(row->error_seeds) && isfinite(row->error_fit)) {
                row->error = fmax(row->error_seeds,
                                  row->error_fit); /* both are honest estimates: keep the larger */
            }
            campaign_row_thesis(r, row);
            if (r->local_slopes) {
                const seed_table st = {per_seed, n_seed, fxi};
                local_slopes(r, rows, g[gi], m, scale, fx, fy, fe, nf, &st);
            }
        }
    }
    return GR_OK;
}

int campaign_name_index(const char *const *names, int n, const char *y)
{
    for (int i = 0; i < n; i++) {
        if (!strcmp(y, names[i])) {
            return i;
        }
    }
    return -1;
}

void campaign_row_of_runs(const gr_campaign_result *r, campaign_row *row, const double *v, int n,
                          double err2_sum, int n_err)
{
    campaign_mean_sd(v, n, &row->value, &row->error_seeds);
    row->error_fit = n_err == n && n ? sqrt(err2_sum) / n : (double)NAN;
    row->error = campaign_headline_error(row->error_seeds, row->error_fit, n);
    row->n_seeds = n;
    campaign_row_thesis(r, row);
}
