/* Fig. 6.3 (sec. 6.2.2): the RFM's configuration beside discs placed from a multiplicative cascade,
 * under the same S(k) analysis. The RFM rows are the MEAN of y over seeds (its D_f of S(k)); the
 * cascade row runs the sk observable of a run, with the runs' N, L and radius, over discs placed
 * without overlap from `configurations` independent UCP fields of 256 x 256 squares (sec. 6.2.1,
 * gr_cascade_study with --place), and fits the same D_f. RESULTS/ID_positions.csv holds an RFM
 * snapshot and the first placement for the figure; collected again from points restored from the
 * archive (which keeps no frames), it keeps the RFM snapshot it had. */
#include <dirent.h>
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/cascade_study.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "io/files.h"
#include "io/snapshot.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"
#include "app/reproduce/embedded.h"

#define CASCADE_GROUP "cascade placement (UCP)"

static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) {
        return;
    }
    struct dirent *e;
    char path[1400];
    while ((e = readdir(d))) {
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
    }
    closedir(d);
    rmdir(dir);
}

static void write_positions(FILE *f, const char *which, const double *x, const double *y, int n)
{
    for (int i = 0; i < n; i++) {
        fprintf(f, "%s,%.9g,%.9g\n", which, x[i], y[i]);
    }
}

/* The "rfm" rows of an earlier ID_positions.csv, copied to `to` (nothing if there is none). */
static void keep_rfm_rows(const char *path, FILE *to)
{
    FILE *from = gr_input_fopen(path, &(int){0});
    char line[256];
    while (from && fgets(line, sizeof line, from)) {
        if (!strncmp(line, "rfm,", 4)) {
            fputs(line, to);
        }
    }
    if (from) {
        fclose(from);
    }
}

/* The last snapshot of a run, when its folder still has one (archived points keep no frames). */
static bool last_snapshot(const campaign_point *p, gr_frame *f)
{
    char pattern[1200];
    snprintf(pattern, sizeof pattern, "%s/snapshots/snap_*.xyz", p->dir);
    glob_t g;
    bool ok = false;
    if (glob(pattern, 0, NULL, &g) == 0 && g.gl_pathc > 0) {
        gr_error err = {0};
        ok = gr_snapshot_read(g.gl_pathv[g.gl_pathc - 1], f, &err) == GR_OK;
    }
    globfree(&g);
    return ok;
}

/* D_f of the sk observable over `configurations` cascade placements of n discs. */
static int cascade_df(const gr_campaign *c, const gr_campaign_result *r, int n, double L,
                      double radius, FILE *positions, double *df, double *df_err, gr_error *err)
{
    char name[200], ov[3][64];
    snprintf(name, sizeof name, "scenes/%s", c->scene);
    snprintf(ov[0], sizeof ov[0], "system.N=%d", n);
    snprintf(ov[1], sizeof ov[1], "system.L=%.17g", L);
    snprintf(ov[2], sizeof ov[2], "system.radius=%.17g", radius);
    const char *overrides[] = {ov[0], ov[1], ov[2], "analysis.observables=sk",
                               "output.plots=false"};
    const char *text = gr_embedded_find(name);
    gr_scene sc;
    if (!text) {
        return GR_FAIL(err, GR_EINVAL, "cascade: the scene %s is not built in", c->scene);
    }
    int rc = gr_scene_load_buffer(&sc, name, text, strlen(text), overrides, 5, err);
    gr_observer *o = NULL;
    if (rc || (rc = gr_scene_observer(&sc, &o, err))) {
        return rc;
    }
    double *v0 = calloc((size_t)n, sizeof *v0);
    for (int k = 0; k < r->configurations && rc == GR_OK && v0; k++) {
        gr_cascade_study_params sp = {0};
        gr_cascade_settings_default(&sp.s);
        sp.s.L = L;
        sp.s.configurations = 1;
        sp.s.seed = (unsigned long)k + 1;
        sp.place = true;
        gr_cascade_placement_default(&sp.placement);
        sp.placement.n = n;
        sp.placement.radius = radius;
        gr_cascade_study st = {0};
        if ((rc = gr_cascade_study_run(&sp, &st, err)) == GR_OK) {
            gr_particles pp = {.n = n,
                               .dim = 2,
                               .L = L,
                               .radius = radius,
                               .mass = sc.mass,
                               .x = st.px,
                               .y = st.py,
                               .vx = v0,
                               .vy = v0};
            rc = gr_observer_sample(o, &pp, k, err);
            if (k == 0) {
                write_positions(positions, "cascade", st.px, st.py, n);
            }
        }
        gr_cascade_study_free(&st);
    }
    char tmp[] = "/tmp/granule-cascade-sk.XXXXXX";
    cJSON *summary = cJSON_CreateObject();
    if (rc == GR_OK && !mkdtemp(tmp)) {
        rc = GR_FAIL(err, GR_EIO, "cascade: no temporary folder for its S(k)");
    } else if (rc == GR_OK) {
        gr_output out = {
            .dir = tmp, .source = sc.source, .seed = sc.seed, .summary = summary, .plots = false};
        rc = gr_observer_finish(o, &out, err);
        remove_tree(tmp);
    }
    *df = gr_summary_number(summary, "sk.fit.D_f");
    *df_err = gr_summary_number(summary, "sk.fit.D_f_err");
    cJSON_Delete(summary);
    gr_observer_free(o);
    free(v0);
    return rc;
}

int campaign_cascade(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                     campaign_rows *rows, const char *results, gr_file *data, gr_error *err)
{
    int rc = campaign_mean(c, r, pts, rows, data, err);
    if (rc || pts->n == 0) {
        return rc;
    }
    const campaign_point *p0 = &pts->p[0];
    const int n = (int)gr_summary_number(p0->summary, "scene.system.N");
    const double L = gr_summary_number(p0->summary, "scene.system.L");
    const double radius = gr_summary_number(p0->summary, "scene.system.radius");
    if (!(n > 0 && L > 0.0 && radius > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade: the runs' summaries lack scene.system.N, L or radius");
    }
    char path[1200], name[96];
    snprintf(path, sizeof path, "%s/%s_positions.csv", results, r->id);
    snprintf(name, sizeof name, "%s_positions.csv", r->id);
    gr_file out;
    if ((rc = gr_file_open(&out, results, name, err))) {
        return rc;
    }
    FILE *positions = out.f;
    gr_file_header(&out, "which [],x [m],y [m]");
    gr_frame f = {0};
    if (last_snapshot(p0, &f)) {
        write_positions(positions, "rfm", f.x, f.y, f.n);
    } else {
        keep_rfm_rows(
            path, positions); /* a restored point has no frames: keep the snapshot written before */
    }
    gr_frame_free(&f);
    double df = NAN, df_err = NAN;
    rc = cascade_df(c, r, n, L, radius, positions, &df, &df_err, err);
    if (rc) {
        gr_file_abandon(&out);
        return rc;
    }
    if ((rc = gr_file_commit(&out, err))) {
        return rc;
    }
    campaign_row *row = campaign_group_row(rows, CASCADE_GROUP);
    row->value = df;
    row->error = row->error_fit = df_err; /* the fit of the configuration-averaged S(k) */
    row->n_seeds = r->configurations;
    campaign_row_thesis(r, row);
    gr_csv_text(data->f, CASCADE_GROUP, true);
    fprintf(data->f, ",0,%.9g,%.9g\n", df, df_err);
    return GR_OK;
}
