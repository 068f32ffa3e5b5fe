/* Reading a campaign's finished points back, and the row bookkeeping shared by the analyses. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/summary_read.h"
#include "reproduce/campaign_points.h"

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
        if (e->d_name[0] != 'p' || strspn(e->d_name + 1, "0123456789") != strlen(e->d_name + 1) || !e->d_name[1]) {
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
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItem(p->manifest, "keys"), key);
    return cJSON_IsString(v) ? v->valuestring : "";
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
    r->thesis = r->thesis_error = r->z = NAN;
    return r;
}

void campaign_rows_free(campaign_rows *rows)
{
    free(rows->r);
    memset(rows, 0, sizeof *rows);
}

/* The thesis list is "GROUP: value +- error (note); ..." where GROUP is the row's group, with
 * " m=K" appended for moments; "*" matches every group. */
void campaign_row_thesis(const gr_campaign_result *r, campaign_row *row)
{
    char want[200];
    if (row->m) {
        snprintf(want, sizeof want, "%s m=%d", row->group, row->m);
    } else {
        snprintf(want, sizeof want, "%s", row->group);
    }
    char buf[sizeof r->thesis];
    snprintf(buf, sizeof buf, "%s", r->thesis);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
        char *colon = strchr(tok, ':');
        if (!colon) {
            continue;
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
        if (strcmp(g, want) && strcmp(g, "*")) {
            continue;
        }
        double v = NAN, e = NAN;
        int used = 0;
        if (sscanf(colon + 1, " %lf +- %lf%n", &v, &e, &used) < 1) {
            continue;
        }
        if (!used) {
            sscanf(colon + 1, " %lf%n", &v, &used);
            e = NAN;
        }
        const char *note = colon + 1 + used;
        while (*note == ' ') {
            note++;
        }
        row->thesis = v;
        row->thesis_error = e;
        snprintf(row->thesis_note, sizeof row->thesis_note, "%.*s", (int)strcspn(note, "\n"), note);
        double var = row->error * row->error + (isfinite(e) ? e * e : 0.0);
        row->z = isfinite(row->value) && var > 0.0 && !gr_campaign_exact_match(row->value, v, e)
                     ? (row->value - v) / sqrt(var)
                     : (double)NAN;
        return;
    }
}
