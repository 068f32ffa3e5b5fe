/* Drive one observable type directly (create, sample, events, finish) in tests:
 * frames from arrays, the summary member and CSV rows read back. */
#ifndef OBS_HARNESS_H
#define OBS_HARNESS_H

#include <check.h>

#include "check_main.h" /* its ck_assert_msg: a passed assertion writes nothing */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/observe.h"
#include "granule/scene.h"

static inline void *h_create(const gr_observable_type *t, const gr_scene *sc)
{
    void *st = NULL;
    gr_error err = {0};
    int rc = gr_scene_observable(t, sc, &st, &err);
    ck_assert_msg(rc == GR_OK, "%s create: %s", t->name, err.message);
    return st;
}

static inline void h_sample(const gr_observable_type *t, void *st, const gr_scene *sc,
                            const double *x, const double *y, const double *vx, const double *vy,
                            double time)
{
    gr_particles p = {.n = sc->N,
                      .dim = sc->dim,
                      .L = sc->L,
                      .radius = sc->radius,
                      .mass = sc->mass,
                      .x = x,
                      .y = sc->dim == 2 ? y : NULL,
                      .vx = vx,
                      .vy = sc->dim == 2 ? vy : NULL};
    gr_error err = {0};
    int rc = t->sample(st, &p, time, &err);
    ck_assert_msg(rc == GR_OK, "%s sample: %s", t->name, err.message);
}

/* Finish into a fresh folder; returns the "analysis" object (caller frees) and,
 * in `csv`, the CSV's data rows (no comments, no column line) as parsed
 * doubles, `ncol` per row. */
typedef struct h_table {
    int rows, cols;
    double *v; /* rows * cols */
    char columns[512];
} h_table;

static inline cJSON *h_finish(const gr_observable_type *t, void *st, const gr_scene *sc,
                              const char *csv_name, h_table *tab)
{
    char dir[] = "/tmp/test_obs_XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    cJSON *summary = cJSON_CreateObject();
    gr_output out = {.dir = dir,
                     .source = sc->source,
                     .seed = sc->seed,
                     .scene_hash = 1,
                     .summary = summary,
                     .plots = false};
    gr_error err = {0};
    int rc = t->finish(st, &out, &err);
    ck_assert_msg(rc == GR_OK, "%s finish: %s", t->name, err.message);
    gr_observable_free(st);
    char path[256], line[4096];
    snprintf(path, sizeof path, "%s/%s", dir, csv_name);
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "no %s", path);
    memset(tab, 0, sizeof *tab);
    int cap = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            continue;
        }
        if (!tab->columns[0]) {
            snprintf(tab->columns, sizeof tab->columns, "%s", line);
            tab->cols = 1;
            for (char *c = line; *c; c++) {
                tab->cols += *c == ',';
            }
            continue;
        }
        if (tab->rows == cap) {
            cap = cap ? 2 * cap : 64;
            tab->v = realloc(tab->v, sizeof(double) * (size_t)cap * (size_t)tab->cols);
        }
        char *s = line;
        for (int c = 0; c < tab->cols; c++) {
            char *end;
            double x = strtod(s, &end);
            tab->v[tab->rows * tab->cols + c] = end == s ? (double)NAN : x; /* text cells: NAN */
            s = strchr(s, ',');
            s = s ? s + 1 : line + strlen(line);
        }
        tab->rows++;
    }
    fclose(f);
    remove(path);
    rmdir(dir);
    return summary;
}

static inline void h_done(h_table *t, cJSON *summary)
{
    free(t->v);
    cJSON_Delete(summary);
}

static inline double h_at(const h_table *t, int row, int col) { return t->v[row * t->cols + col]; }

/* summary number at a.b (b may be NULL); NAN for null */
static inline double h_num(const cJSON *o, const char *a, const char *b)
{
    const cJSON *it = cJSON_GetObjectItem(o, a);
    if (b) {
        it = cJSON_GetObjectItem(it, b);
    }
    ck_assert_msg(it != NULL, "summary has no %s%s%s", a, b ? "." : "", b ? b : "");
    return cJSON_IsNumber(it) ? it->valuedouble : (double)NAN;
}

static inline void h_scene(gr_scene *sc, int dim, int N, double L, double radius)
{
    gr_scene_default(sc);
    sc->dim = dim;
    sc->N = N;
    sc->L = L;
    sc->radius = radius;
    snprintf(sc->source, sizeof sc->source, "test_obs");
}

#endif
