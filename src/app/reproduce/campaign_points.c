/* Reading a campaign's finished points back, and the row bookkeeping shared by the analyses. */
#include <dirent.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

static int by_dir(const void *a, const void *b)
{
    return strcmp(((const campaign_point *)a)->dir, ((const campaign_point *)b)->dir);
}

int campaign_points_read(const char *dir, campaign_points *pts, gr_error *err)
{
    memset(pts, 0, sizeof *pts);
    char runs[1100];
    snprintf(runs, sizeof runs, "%.1000s/runs", dir);
    DIR *d = opendir(runs);
    if (!d) {
        return GR_FAIL(err, GR_EIO, "%s: no runs yet (run the campaign first)", runs);
    }
    int cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] != 'p' || strspn(e->d_name + 1, "0123456789") != strlen(e->d_name + 1) ||
            !e->d_name[1]) {
            continue;
        }
        campaign_point pt = {0};
        snprintf(pt.dir, sizeof pt.dir, "%.1000s/%.60s", runs, e->d_name);
        char path[1200];
        snprintf(path, sizeof path, "%s/point.json", pt.dir);
        gr_error ignore = {0};
        pt.manifest = gr_json_read(path, &ignore);
        const cJSON *status = cJSON_GetObjectItem(pt.manifest, "status");
        if (!cJSON_IsString(status) || strcmp(status->valuestring, "completed")) {
            cJSON_Delete(pt.manifest);
            continue;
        }
        pt.summary = gr_summary_read(pt.dir, &ignore);
        const cJSON *ss = cJSON_GetObjectItem(pt.summary, "status");
        if (!cJSON_IsString(ss) || strcmp(ss->valuestring, "completed")) {
            cJSON_Delete(pt.manifest);
            cJSON_Delete(pt.summary);
            continue;
        }
        pt.cpu_seconds = gr_summary_number(pt.manifest, "cpu_seconds");
        pt.sim_seconds = gr_summary_number(pt.summary, "simulated_seconds");
        if (pts->n == cap) {
            cap = cap ? 2 * cap : 64;
            pts->p = realloc(pts->p, (size_t)cap * sizeof *pts->p);
        }
        pts->p[pts->n++] = pt;
    }
    closedir(d);
    if (pts->n > 1) {
        qsort(pts->p, (size_t)pts->n, sizeof *pts->p, by_dir);
    }
    return GR_OK;
}

void campaign_points_free(campaign_points *pts)
{
    for (int i = 0; i < pts->n; i++) {
        cJSON_Delete(pts->p[i].manifest);
        cJSON_Delete(pts->p[i].summary);
    }
    free(pts->p);
    memset(pts, 0, sizeof *pts);
}

const char *campaign_point_key(const campaign_point *p, const char *key)
{
    const cJSON *v =
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItem(p->manifest, "keys"), key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static char notes[8192];
static size_t notes_used;

void campaign_note(const char *fmt, ...)
{
    if (notes_used + 1 >= sizeof notes) {
        return; /* the first notes are kept */
    }
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(notes + notes_used, sizeof notes - notes_used - 1, fmt, ap);
    va_end(ap);
    notes_used = n > 0 ? notes_used + (size_t)n : notes_used;
    notes_used = notes_used < sizeof notes - 2 ? notes_used : sizeof notes - 2;
    notes[notes_used++] = '\n';
    notes[notes_used] = 0;
}

void campaign_notes_take(char *out, size_t len)
{
    snprintf(out, len, "%s", notes);
    notes_used = 0;
    notes[0] = 0;
}

campaign_row *campaign_rows_add(campaign_rows *rows)
{
    if (rows->n == rows->cap) {
        rows->cap = rows->cap ? 2 * rows->cap : 32;
        rows->r = realloc(rows->r, (size_t)rows->cap * sizeof *rows->r);
    }
    campaign_row *r = &rows->r[rows->n++];
    memset(r, 0, sizeof *r);
    r->value = r->error = r->error_fit = r->error_seeds = r->chi2_red = r->x_lo = r->x_hi = NAN;
    r->thesis = r->thesis_error = r->z = r->thesis_hi = r->tolerance = NAN;
    r->agrees = -1;
    r->centre_x = r->centre_value = NAN;
    return r;
}

void campaign_rows_free(campaign_rows *rows)
{
    free(rows->r);
    memset(rows, 0, sizeof *rows);
}

/* Half a unit of the last digit a number was written with ("0.528" -> 5e-4, "12" -> 0.5,
 * "7.78e-4" -> 5e-7): the precision a value quoted without an error states. */
static double half_last_digit(const char *text)
{
    const char *dot = strchr(text, '.');
    size_t mantissa = strcspn(text, "eE");
    int decimals =
        dot && (size_t)(dot - text) < mantissa ? (int)(mantissa - (size_t)(dot - text) - 1) : 0;
    int exponent = mantissa < strlen(text) ? atoi(text + mantissa + 1) : 0;
    return 0.5 * pow(10.0, exponent - decimals);
}

/* Ours against the thesis's value by the row's kind of comparison (docs/campaigns/README.md):
 * only a value with an error gives a z; the others say whether ours agrees within ours +- 2 errors. */
static void compare(campaign_row *row)
{
    const double v = row->value, t = row->thesis, slack = 2.0 * row->error;
    row->z = NAN;
    row->agrees = -1;
    if (!isfinite(v) ||
        !(row->error >= 0.0)) { /* without an error of ours (one run) nothing is judged */
        return;
    }
    if (!strcmp(row->comparison, "z")) {
        const double var = row->error * row->error + row->thesis_error * row->thesis_error;
        row->z = var > 0.0 ? (v - t) / sqrt(var) : (double)NAN;
    } else if (!strcmp(row->comparison, "range")) {
        row->agrees = v + slack >= t && v - slack <= row->thesis_hi;
    } else if (strcmp(row->comparison, "construction")) { /* stated, about, model */
        row->agrees = fabs(v - t) <= row->tolerance + slack;
    }
}

/* The thesis list is "GROUP: [about|model|exact|range] value [+- error | .. high] (note); ..." where
 * GROUP is the row's group, with " m=K" appended for moments; "*" matches every group. */

/* A row's name in the thesis list. */
static void row_name(const campaign_row *row, char *out, size_t len)
{
    if (row->m) {
        snprintf(out, len, "%s m=%d", row->group, row->m);
    } else {
        snprintf(out, len, "%s", row->group);
    }
}

/* Entry tok of the list, cut at its colon: GROUP trimmed, *text what follows (blanks skipped);
 * NULL for an entry without a colon. */
static char *entry_group(char *tok, const char **text)
{
    char *colon = strchr(tok, ':');
    if (!colon) {
        return NULL;
    }
    *colon = 0;
    char *g = tok;
    while (*g == ' ') {
        g++;
    }
    size_t gl = strlen(g);
    while (gl && g[gl - 1] == ' ') {
        g[--gl] = 0;
    }
    for (*text = colon + 1; **text == ' '; (*text)++) {
    }
    return g;
}

int campaign_thesis_unmatched(const gr_campaign_result *r, const campaign_rows *rows, char *first,
                              size_t len)
{
    char buf[sizeof r->thesis];
    snprintf(buf, sizeof buf, "%s", r->thesis);
    int unmatched = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
        const char *text;
        const char *g = entry_group(tok, &text);
        bool found = !g || !strcmp(g, "*");
        for (int i = 0; i < rows->n && !found; i++) {
            char want[200];
            row_name(&rows->r[i], want, sizeof want);
            found = !strcmp(g, want);
        }
        if (!found && !unmatched++) {
            snprintf(first, len, "%s", g);
        }
    }
    return unmatched;
}

void campaign_row_thesis(const gr_campaign_result *r, campaign_row *row)
{
    char want[200];
    row_name(row, want, sizeof want);
    char buf[sizeof r->thesis];
    snprintf(buf, sizeof buf, "%s", r->thesis);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
        const char *text;
        const char *g = entry_group(tok, &text);
        if (!g || (strcmp(g, want) && strcmp(g, "*"))) {
            continue;
        }
        static const char *const words[] = {"about", "model", "exact", "range"};
        static const char *const kinds[] = {"about", "model", "construction", "range"};
        const char *kind = NULL;
        for (int k = 0; k < 4 && !kind; k++) {
            const size_t n = strlen(words[k]);
            if (!strncmp(text, words[k], n) && text[n] == ' ') {
                kind = kinds[k];
                text += n + 1;
            }
        }
        double v = NAN, e = NAN, hi = NAN;
        int used = 0;
        char number[64] = "";
        if (sscanf(text, " %63[-+0-9.eE]%n", number, &used) < 1 || sscanf(number, "%lf", &v) != 1) {
            continue;
        }
        int more = 0;
        if (kind && !strcmp(kind, "range")) {
            if (sscanf(text + used, " .. %lf%n", &hi, &more) < 1) {
                continue;
            }
        } else if (sscanf(text + used, " +- %lf%n", &e, &more) < 1) {
            e = NAN;
            more = 0;
        }
        used += more;
        if (!kind) {
            kind = isfinite(e) && e > 0.0 ? "z" : "stated";
        }
        const char *note = text + used;
        while (*note == ' ') {
            note++;
        }
        row->thesis = v;
        row->thesis_error = e;
        row->thesis_hi = hi;
        snprintf(row->comparison, sizeof row->comparison, "%s", kind);
        if (!strcmp(kind, "about")) { /* "about 1": ours rounds to it at one significant figure */
            row->tolerance = v != 0.0 ? 0.5 * pow(10.0, floor(log10(fabs(v)))) : 0.5;
        } else if (!strcmp(kind, "stated") || !strcmp(kind, "model")) {
            row->tolerance = half_last_digit(number);
        }
        snprintf(row->thesis_note, sizeof row->thesis_note, "%.*s", (int)strcspn(note, "\n"), note);
        compare(row);
        return;
    }
}

const char *campaign_key_unit(const char *key)
{
    static const char *const units[][2] = {
        {"L", "m"},  {"reduced_length", "m"}, {"radius", "m"}, {"mass", "kg"}, {"D", "N^2 s"},
        {"dt", "s"}, {"duration", "s"},       {"warmup", "s"}};
    for (size_t u = 0; u < sizeof units / sizeof units[0]; u++) {
        if (!strcmp(key, units[u][0])) {
            return units[u][1];
        }
    }
    return "";
}

/* A group label as a physicist writes it: "N+L=3000/0.2, eps_n=0.1" -> "N = 3000, L = 0.2 m,
 * eps_n = 0.1" (linked keys split, units of the lengths, masses and times added). */
void campaign_pretty_group(const char *group, char *out, size_t len)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", group);
    size_t n = 0;
    out[0] = 0;
    char *save = NULL;
    for (char *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        while (*item == ' ') {
            item++;
        }
        char *eq = strchr(item, '=');
        if (!eq) {
            n += (size_t)snprintf(out + n, n < len ? len - n : 0, "%s%s", n ? ", " : "", item);
            continue;
        }
        *eq = 0;
        char *ks = NULL, *vs = NULL;
        for (char *k = strtok_r(item, "+", &ks), *v = strtok_r(eq + 1, "/", &vs); k && v;
             k = strtok_r(NULL, "+", &ks), v = strtok_r(NULL, "/", &vs)) {
            const char *unit = campaign_key_unit(k);
            n += (size_t)snprintf(out + n, n < len ? len - n : 0, "%s%s = %s%s%s", n ? ", " : "", k,
                                  v, unit[0] ? " " : "", unit);
        }
    }
}
