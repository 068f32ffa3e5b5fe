/* A result's comparison figure (ID.png) drawn against a physical abscissa instead of one label
 * per row: the moment order m with one series per group (xi_m / m against m, as the thesis's
 * Fig. 3.5), or the one varied key that is a number (xi_2 against eps), or, when the rows vary
 * two keys, the one with more values as x and one series per value of the other (n_N against N
 * for each eps). Ours are filled, the thesis's open in the series' colour. Rows that fit none of
 * these (a local slope between two sizes, three varied keys, more than a handful of series) keep
 * the labelled axis of campaign_results.c. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "app/reproduce/campaign_points.h"

enum { MAX_KEYS = 4, MAX_SERIES = 8 };

typedef struct row_keys {
    int n;
    char key[MAX_KEYS][48], value[MAX_KEYS][48];
    int item[MAX_KEYS]; /* linked keys (N+L=3000/0.2) share an item */
} row_keys;

/* "eps_n=0.1, N+L=3000/0.2" -> (eps_n, 0.1, 0), (N, 3000, 1), (L, 0.2, 1); false if an item has
 * no '=' or there are too many keys. */
static bool split_keys(const char *group, row_keys *k)
{
    char buf[200];
    snprintf(buf, sizeof buf, "%s", group);
    k->n = 0;
    char *save = NULL;
    int item = 0;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save), item++) {
        while (*tok == ' ') {
            tok++;
        }
        char *eq = strchr(tok, '=');
        if (!eq) {
            return false;
        }
        *eq = '\0';
        char *ks = NULL, *vs = NULL;
        for (char *key = strtok_r(tok, "+", &ks), *v = strtok_r(eq + 1, "/", &vs); key && v;
             key = strtok_r(NULL, "+", &ks), v = strtok_r(NULL, "/", &vs)) {
            if (k->n == MAX_KEYS) {
                return false;
            }
            snprintf(k->key[k->n], sizeof k->key[0], "%s", key);
            snprintf(k->value[k->n], sizeof k->value[0], "%s", v);
            k->item[k->n++] = item;
        }
    }
    return k->n > 0;
}

static bool is_number(const char *s, double *x)
{
    char *end;
    *x = strtod(s, &end);
    return end != s && !*end && isfinite(*x);
}

/* the rows drawn: not a local slope or its trend (those are ID_slopes.png) */
static bool drawn(const campaign_row *w) { return w->role == 0; }

/* The abscissa and the series of the figure, chosen from the rows' keys. */
typedef struct layout {
    bool by_m;         /* x = m, series = the whole group */
    int x, s;          /* key positions of x and of the series (-1: one series) */
    char x_label[120]; /* "eps_n = eps_t" for linked keys always equal */
    char s_label[120];
    bool log_x;
} layout;

static bool choose_layout(const campaign_rows *rows, layout *L, row_keys *keys)
{
    memset(L, 0, sizeof *L);
    L->x = L->s = -1;
    int n = 0, with_m = 0, first = -1;
    for (int i = 0; i < rows->n; i++) {
        if (!drawn(&rows->r[i])) {
            continue;
        }
        if (!split_keys(rows->r[i].group, &keys[i])) {
            return false;
        }
        first = first < 0 ? i : first;
        if (keys[i].n != keys[first].n) {
            return false;
        }
        n++;
        with_m += rows->r[i].m > 0;
    }
    if (n < 3) {
        return false;
    }
    if (with_m == n) { /* one series per group, x = m */
        L->by_m = true;
        snprintf(L->x_label, sizeof L->x_label, "m");
        return true;
    }
    if (with_m) {
        return false;
    }
    /* keys that repeat the one before them in the same item in every row merge into it */
    const row_keys *k0 = &keys[first];
    bool merged[MAX_KEYS] = {false};
    int free_keys[MAX_KEYS], nf = 0;
    for (int j = 0; j < k0->n; j++) {
        merged[j] = j > 0 && k0->item[j] == k0->item[j - 1];
        for (int i = 0; i < rows->n && merged[j]; i++) {
            merged[j] = !drawn(&rows->r[i]) || (!strcmp(keys[i].key[j], k0->key[j]) &&
                                                !strcmp(keys[i].value[j], keys[i].value[j - 1]));
        }
        if (!merged[j]) {
            free_keys[nf++] = j;
        }
    }
    if (nf > 2) {
        return false;
    }
    /* distinct values of each free key */
    int distinct[2] = {0, 0};
    for (int f = 0; f < nf; f++) {
        for (int i = 0; i < rows->n; i++) {
            if (!drawn(&rows->r[i]) || strcmp(keys[i].key[free_keys[f]], k0->key[free_keys[f]])) {
                if (drawn(&rows->r[i])) {
                    return false; /* the rows vary different keys */
                }
                continue;
            }
            bool seen = false;
            for (int p = 0; p < i && !seen; p++) {
                seen = drawn(&rows->r[p]) &&
                       !strcmp(keys[p].value[free_keys[f]], keys[i].value[free_keys[f]]);
            }
            distinct[f] += !seen;
        }
    }
    const int fx = nf == 2 && distinct[0] > distinct[1] ? 0 : nf - 1;
    L->x = free_keys[fx];
    /* linked keys that never repeat (N+L at fixed phi) make one series, not one per point */
    L->s = nf == 2 && distinct[1 - fx] < n ? free_keys[1 - fx] : -1;
    if (L->s >= 0 && distinct[1 - fx] > MAX_SERIES) {
        return false;
    }
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < rows->n; i++) {
        double x;
        if (!drawn(&rows->r[i])) {
            continue;
        }
        if (!is_number(keys[i].value[L->x], &x)) {
            return false;
        }
        lo = fmin(lo, x);
        hi = fmax(hi, x);
    }
    L->log_x = lo > 0.0 && hi / lo >= 20.0;
    for (int side = 0; side < 2; side++) {
        const int j = side ? L->s : L->x;
        char *out = side ? L->s_label : L->x_label;
        if (j < 0) {
            continue;
        }
        char names[MAX_KEYS * 52] = ""; /* the key and the keys merged into it: "eps_n = eps_t" */
        for (int m = j; m < k0->n && (m == j || merged[m]); m++) {
            strcat(names, m > j ? " = " : "");
            strncat(names, k0->key[m], 47);
        }
        const char *unit = campaign_key_unit(k0->key[j]);
        if (unit[0] && !side) {
            snprintf(out, sizeof L->x_label, "%.100s (%.12s)", names, unit);
        } else {
            snprintf(out, sizeof L->x_label, "%.119s", names);
        }
    }
    return true;
}

/* The series label of row i: "eps_n = 0.1" (or its whole group for x = m), "" for one series. */
static void series_of(const campaign_row *w, const row_keys *k, const layout *L, char *out,
                      size_t len)
{
    if (L->by_m) {
        campaign_pretty_group(w->group, out, len);
    } else if (L->s >= 0) {
        const char *unit = campaign_key_unit(k->key[L->s]);
        snprintf(out, len, "%.60s = %.40s%s%.12s", L->s_label, k->value[L->s], unit[0] ? " " : "",
                 unit);
    } else {
        snprintf(out, len, "granule");
    }
}

static int by_x(const void *a, const void *b)
{
    const double *p = a, *q = b;
    return (p[0] > q[0]) - (p[0] < q[0]);
}

bool campaign_compare_series(const char *dir, const gr_campaign_result *r,
                             const campaign_rows *rows, const char *ylabel)
{
    row_keys *keys = calloc((size_t)(rows->n > 0 ? rows->n : 1), sizeof *keys);
    double *pts = malloc(sizeof(double) * 5 * (size_t)(rows->n > 0 ? rows->n : 1));
    layout L;
    bool ok = keys && pts && choose_layout(rows, &L, keys);
    char series[MAX_SERIES][120];
    int ns = 0;
    for (int i = 0; ok && i < rows->n; i++) { /* the series, in the campaign's order */
        if (!drawn(&rows->r[i])) {
            continue;
        }
        char s[120];
        series_of(&rows->r[i], &keys[i], &L, s, sizeof s);
        int k = 0;
        while (k < ns && strcmp(series[k], s)) {
            k++;
        }
        if (k == ns) {
            ok = ns < MAX_SERIES;
            if (ok) {
                snprintf(series[ns++], sizeof series[0], "%s", s);
            }
        }
    }
    char name[80];
    snprintf(name, sizeof name, "%s_compare.dat", r->id);
    gr_file f;
    gr_error err = {0};
    if (!ok || gr_file_open(&f, dir, name, &err)) {
        free(keys);
        free(pts);
        return false;
    }
    bool thesis = false;
    for (int k = 0; k < ns; k++) { /* one index block per series: its title, then x-sorted rows */
        int n = 0;
        for (int i = 0; i < rows->n; i++) {
            const campaign_row *w = &rows->r[i];
            char s[120];
            if (!drawn(w)) {
                continue;
            }
            series_of(w, &keys[i], &L, s, sizeof s);
            if (strcmp(s, series[k])) {
                continue;
            }
            /* a thesis range is drawn as its middle +- half its width */
            const bool range = !strcmp(w->comparison, "range");
            double *p = &pts[5 * n++];
            p[0] = L.by_m ? w->m : strtod(keys[i].value[L.x], NULL);
            p[1] = w->value;
            p[2] = w->error;
            p[3] = range ? 0.5 * (w->thesis + w->thesis_hi) : w->thesis;
            p[4] = range                       ? 0.5 * (w->thesis_hi - w->thesis)
                   : isfinite(w->thesis_error) ? w->thesis_error
                                               : 0.0;
            thesis |= isfinite(p[3]);
        }
        qsort(pts, (size_t)n, 5 * sizeof(double), by_x);
        fprintf(f.f, "%s\"%s\"\n", k ? "\n\n" : "", series[k]);
        for (int i = 0; i < n; i++) {
            const double *p = &pts[5 * i];
            fprintf(f.f, "%.6g %.6g %.6g %.6g %.6g\n", p[0], p[1], p[2], p[3], p[4]);
        }
    }
    free(keys);
    free(pts);
    if (gr_file_commit(&f, &err)) {
        return false;
    }
    char body[2048];
    snprintf(
        body, sizeof body,
        "set datafile separator whitespace\nset title \"%s\" noenhanced\nset ylabel '%s' "
        "noenhanced\nset xlabel '%s' noenhanced\n%s"
        "set key below height 1.5\nset offsets graph 0.04, graph 0.04, graph 0.06, graph "
        "0.06\nset grid ytics lc rgb '#dddddd'\n"
        "plot for [i=0:%d] '%s' index i using 1:2:3 with yerrorlines pt 7 ps 1.2 lw 1 lc i+1 title "
        "columnheader(1)%s%s\n",
        r->title, ylabel, L.x_label, L.log_x ? "set logscale x\n" : "", ns - 1, name,
        thesis ? ", for [i=0:" : "", "");
    if (thesis) {
        const size_t len = strlen(body) - 1; /* drop the newline, add the thesis's open symbols */
        snprintf(body + len, sizeof body - len,
                 "%d] '' index i using 1:4:5 with yerrorbars pt 6 ps 2 lc i+1 notitle, NaN with "
                 "points pt 6 ps 2 lc rgb 'black' title 'thesis (open)'\n",
                 ns - 1);
    }
    campaign_draw(dir, r->id, "", body);
    return true;
}
