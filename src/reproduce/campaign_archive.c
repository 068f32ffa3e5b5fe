/* The finished points of a campaign kept with its result set (RESULTS/points/pNNNN.json: the
 * point's manifest and summary.json, ~10 kB each), so that a committed result set carries its
 * campaign across machines and sessions: a later `granule reproduce` puts the archived points back
 * into its runs folder, the sweep sees them finished (same scene hash) and runs only the rest.
 * Only summary.json comes back: an analysis that reads a run's CSVs (running_mean) needs the runs. */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "reproduce/campaign_points.h"

int campaign_archive(const campaign_points *pts, const char *results, gr_error *err)
{
    char dir[1200];
    snprintf(dir, sizeof dir, "%.1100s/points", results);
    int rc = gr_output_dir_prepare(dir, true, err);
    for (int i = 0; i < pts->n && !rc; i++) {
        const char *base = strrchr(pts->p[i].dir, '/');
        char name[80];
        snprintf(name, sizeof name, "%.60s.json", base ? base + 1 : pts->p[i].dir);
        cJSON *j = cJSON_CreateObject();
        cJSON_AddItemReferenceToObject(j, "point", pts->p[i].manifest);
        cJSON_AddItemReferenceToObject(j, "summary", pts->p[i].summary);
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
            rc = j ? GR_FAIL(err, GR_EINVAL, "%s: not an archived point (point and summary objects)", path) : GR_EIO;
        } else if (!(rc = gr_output_dir_prepare(point_dir, true, err)) && !(rc = gr_json_write(point_dir, "summary.json", s, err))) {
            rc = gr_json_write(point_dir, "point.json", m, err); /* last: the point counts as finished only when both exist */
            *restored += !rc;
        }
        cJSON_Delete(j);
    }
    closedir(d);
    return rc;
}
