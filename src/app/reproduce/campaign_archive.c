/* The finished points of a campaign kept with its result set (RESULTS/points/pNNNN.json: the
 * point's manifest and summary.json, ~10 kB each), so that a committed result set carries its
 * campaign across machines and sessions: a later `granule reproduce` puts the archived points back
 * into its runs folder, the sweep sees them finished (same scene hash) and runs only the rest.
 * summary.json comes back, and the series of every curve result (series.json, 6 significant
 * digits) and the run's warm-up drift (warmup.json: the campaign's warm-up check); an analysis that
 * reads T(t) itself (running_mean, rise_time) needs the runs. */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

double campaign_archive_digits(double v)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%.6g", v);
    return atof(buf);
}

/* {"KEY": {"x": [...], "y": [...], "e": [...]}, ...} of the campaign's curve results for one point */
static cJSON *curve_series(const gr_campaign *c, const campaign_point *p)
{
    cJSON *all = cJSON_CreateObject();
    double *x = malloc(3 * 4096 * sizeof *x), *y = x + 4096, *e = y + 4096;
    gr_campaign_result extra[4];
    int n_extra = 0;
    bool has_spm = false, has_compare = false;
    for (int i = 0; i < c->n_results; i++) {
        has_spm |= c->results[i].kind == GR_RESULT_SPM;
        has_compare |= c->results[i].kind == GR_RESULT_SPM_COMPARE;
    }
    for (int w = 0; w < 2; w++) {
        if (has_spm) {
            campaign_spm_series(w, &extra[n_extra++]);
        }
        if (has_compare) {
            campaign_spm_compare_series(w, &extra[n_extra++]);
        }
    }
    /* the curve results' series (and the fit columns an overlay = column draws), then those the
     * spm kinds read (pv.csv, freepath.csv; spm_compare.csv) */
    for (int i = 0; i < 2 * c->n_results + n_extra; i++) {
        gr_campaign_result col;
        const gr_campaign_result *r = i < c->n_results       ? &c->results[i]
                                      : i < 2 * c->n_results ? &c->results[i - c->n_results]
                                                             : &extra[i - 2 * c->n_results];
        if (i >= c->n_results && i < 2 * c->n_results) {
            if (strcmp(r->overlay, "column")) {
                continue;
            }
            col = *r;
            snprintf(col.y, sizeof col.y, "%s", r->overlay_y);
            col.y_err[0] = 0;
            r = &col;
        }
        char key[512];
        campaign_curve_key(r, key, sizeof key);
        if (r->kind != GR_RESULT_CURVE || cJSON_GetObjectItem(all, key)) {
            continue;
        }
        const int n = campaign_curve_series(p, r, x, y, e);
        if (n == 0) {
            continue;
        }
        cJSON *o = cJSON_AddObjectToObject(all, key);
        cJSON *ax = cJSON_AddArrayToObject(o, "x"), *ay = cJSON_AddArrayToObject(o, "y"),
              *ae = cJSON_AddArrayToObject(o, "e");
        for (
            int k = 0; k < n;
            k++) { /* already at 6 digits, finite y only (zeros too: the seed average counts them) */
            cJSON_AddItemToArray(ax, cJSON_CreateNumber(x[k]));
            cJSON_AddItemToArray(ay, cJSON_CreateNumber(y[k]));
            cJSON_AddItemToArray(ae,
                                 isfinite(e[k]) ? cJSON_CreateNumber(e[k]) : cJSON_CreateNull());
        }
    }
    free(x);
    if (!all->child) {
        cJSON_Delete(all);
        return NULL;
    }
    return all;
}

int campaign_archive(const gr_campaign *c, const campaign_points *pts, const char *results,
                     gr_error *err)
{
    char dir[1200];
    snprintf(dir, sizeof dir, "%.1100s/points", results);
    int rc = gr_output_dir_prepare(dir, GR_OUTPUT_ANY, true, err);
    for (int i = 0; i < pts->n && !rc; i++) {
        const char *base = strrchr(pts->p[i].dir, '/');
        char name[80];
        snprintf(name, sizeof name, "%.60s.json", base ? base + 1 : pts->p[i].dir);
        cJSON *j = cJSON_CreateObject();
        cJSON_AddItemReferenceToObject(j, "point", pts->p[i].manifest);
        cJSON_AddItemReferenceToObject(j, "summary", pts->p[i].summary);
        cJSON *series = curve_series(c, &pts->p[i]);
        if (series) {
            cJSON_AddItemToObject(j, "series", series);
        }
        double drift_err, drift = campaign_warmup_drift(&pts->p[i], &drift_err);
        if (isfinite(drift)) { /* the warm-up check of a later collect, without the run's T(t) */
            cJSON *w = cJSON_AddObjectToObject(j, "warmup");
            cJSON_AddNumberToObject(w, "drift", drift);
            cJSON_AddItemToObject(w, "error",
                                  isfinite(drift_err) ? cJSON_CreateNumber(drift_err)
                                                      : cJSON_CreateNull());
        }
        rc = gr_json_write(dir, name, j, err);
        cJSON_Delete(j);
    }
    return rc;
}

int gr_campaign_restore(const char *dir, const char *results, long *restored, gr_error *err)
{
    *restored = 0;
    char arch[1200];
    snprintf(arch, sizeof arch, "%.1100s/points", results);
    DIR *d = opendir(arch);
    if (!d) {
        return GR_OK; /* nothing archived yet */
    }
    struct dirent *e;
    int rc = GR_OK;
    while (!rc && (e = readdir(d))) {
        size_t len = strlen(e->d_name);
        if (e->d_name[0] != 'p' || len < 6 || strcmp(e->d_name + len - 5, ".json")) {
            continue;
        }
        char point_dir[1300], path[1400];
        snprintf(point_dir, sizeof point_dir, "%.1000s/runs/%.*s", dir, (int)(len - 5), e->d_name);
        snprintf(path, sizeof path, "%s/point.json", point_dir);
        gr_error ignore = {0};
        cJSON *have = gr_json_read(path, &ignore);
        const cJSON *st = cJSON_GetObjectItem(have, "status");
        bool done = cJSON_IsString(st) && !strcmp(st->valuestring, "completed");
        cJSON_Delete(have);
        if (done) {
            continue; /* the runs folder has its own */
        }
        snprintf(path, sizeof path, "%s/%s", arch, e->d_name);
        cJSON *j = gr_json_read(path, err);
        const cJSON *m = cJSON_GetObjectItem(j, "point"), *s = cJSON_GetObjectItem(j, "summary");
        if (!cJSON_IsObject(m) || !cJSON_IsObject(s)) {
            rc = j ? GR_FAIL(err, GR_EINVAL,
                             "%s: not an archived point (point and summary objects)", path)
                   : GR_EIO;
        } else if (!(rc = gr_output_dir_prepare(point_dir, GR_OUTPUT_ANY, true, err)) &&
                   !(rc = gr_json_write(point_dir, "summary.json", s, err)) &&
                   !(rc = cJSON_IsObject(cJSON_GetObjectItem(j, "series"))
                              ? gr_json_write(point_dir, "series.json",
                                              cJSON_GetObjectItem(j, "series"), err)
                              : GR_OK) &&
                   !(rc = cJSON_IsObject(cJSON_GetObjectItem(j, "warmup"))
                              ? gr_json_write(point_dir, "warmup.json",
                                              cJSON_GetObjectItem(j, "warmup"), err)
                              : GR_OK)) {
            rc = gr_json_write(point_dir, "point.json", m,
                               err); /* last: the point counts as finished only when both exist */
            *restored += !rc;
        }
        cJSON_Delete(j);
    }
    closedir(d);
    return rc;
}
