/* The observable registry and the set of observables a scene enables. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/observe.h"
#include "granule/scene.h"
#include "analysis/blob_stats.h"

extern const gr_observable_type gr_obs_moments;
extern const gr_observable_type gr_obs_freepath;
extern const gr_observable_type gr_obs_postcollision;
extern const gr_observable_type gr_obs_gaps;
extern const gr_observable_type gr_obs_sk;
extern const gr_observable_type gr_obs_pair;
extern const gr_observable_type gr_obs_pv;
extern const gr_observable_type gr_obs_msd;
extern const gr_observable_type gr_obs_vacf;
extern const gr_observable_type gr_obs_vcorr;
extern const gr_observable_type gr_obs_clusters;
extern const gr_observable_type gr_obs_pressure;
extern const gr_observable_type gr_obs_collisions;

const gr_observable_type *const gr_observables[] = {
    &gr_obs_moments,
    &gr_obs_freepath,
    &gr_obs_postcollision,
    &gr_obs_gaps,
    &gr_obs_sk,
    &gr_obs_pair,
    &gr_obs_pv,
    &gr_obs_msd,
    &gr_obs_vacf,
    &gr_obs_vcorr,
    &gr_obs_clusters,
    &gr_obs_pressure,
    &gr_obs_collisions,
    NULL,
};

const gr_observable_type *gr_observable_find(const char *name)
{
    for (int i = 0; gr_observables[i]; i++) {
        if (strcmp(gr_observables[i]->name, name) == 0) {
            return gr_observables[i];
        }
    }
    return NULL;
}

#define MAX_OBSERVERS 16

struct gr_observer {
    int n;
    const gr_observable_type *type[MAX_OBSERVERS];
    void *state[MAX_OBSERVERS];
};

int gr_observer_create(const gr_scene *scene, gr_observer **out, gr_error *err)
{
    gr_observer *o = calloc(1, sizeof *o);
    if (!o) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    char buf[256];
    snprintf(buf, sizeof buf, "%s", scene->observables);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        const gr_observable_type *t = gr_observable_find(tok);
        if (!t) {
            gr_observer_free(o);
            return GR_FAIL(err, GR_EINVAL, "[analysis] observables: unknown observable '%s'", tok);
        }
        if (!(t->dims & (1u << (scene->dim - 1)))) {
            gr_observer_free(o);
            return GR_FAIL(err, GR_EINVAL, "%s: [analysis] observables: %s is not defined for dim = %d",
                           scene->source, tok, scene->dim);
        }
        bool dup = false;
        for (int i = 0; i < o->n; i++) {
            dup |= o->type[i] == t;
        }
        if (dup || o->n == MAX_OBSERVERS) {
            continue;
        }
        int rc = t->create(scene, &o->state[o->n], err);
        if (rc) {
            gr_observer_free(o);
            return rc;
        }
        o->type[o->n++] = t;
    }
    *out = o;
    return GR_OK;
}

/* A frame every observable can take: a finite time, a positive finite box, finite velocities and
 * coordinates within GR_COORD_MAX_BOXES box lengths of the origin. Farther coordinates (1e308 is
 * finite) cannot be wrapped into the box: x / L overflows, and the cell and grid indices computed
 * from it (sk, clusters, pressure, pair, ...) would address memory far outside their arrays. */
static int check_frame(const gr_particles *p, double t, gr_error *err)
{
    if (!isfinite(t)) {
        return GR_FAIL(err, GR_EINVAL, "frame time t = %g s is not a finite number", t);
    }
    if (!(p->L > 0.0) || !isfinite(p->L)) {
        return GR_FAIL(err, GR_EINVAL, "frame at t = %.17g s: box length L = %g m is not a positive finite number", t, p->L);
    }
    const double lim = GR_COORD_MAX_BOXES * p->L;
    for (int i = 0; i < p->n; i++) {
        const double c[4] = {p->x[i], p->dim == 2 ? p->y[i] : 0.0, p->vx[i], p->dim == 2 ? p->vy[i] : 0.0};
        static const char *const name[4] = {"x", "y", "vx", "vy"};
        for (int k = 0; k < 4; k++) {
            if (k < 2 && !(fabs(c[k]) <= lim)) {
                return GR_FAIL(err, GR_EINVAL, "frame at t = %.17g s: particle %d has %s = %g m, outside the range "
                               "|%s| <= %g L = %g m that can be wrapped into the box", t, i, name[k], c[k], name[k],
                               GR_COORD_MAX_BOXES, lim);
            }
            if (k >= 2 && !isfinite(c[k])) {
                return GR_FAIL(err, GR_EINVAL, "frame at t = %.17g s: particle %d has %s = %g m/s, not a finite number",
                               t, i, name[k], c[k]);
            }
        }
    }
    return GR_OK;
}

int gr_observer_sample(gr_observer *o, const gr_particles *p, double t, gr_error *err)
{
    int bad = o->n > 0 ? check_frame(p, t, err) : GR_OK;
    if (bad) {
        return bad;
    }
    for (int i = 0; i < o->n; i++) {
        int rc = o->type[i]->sample(o->state[i], p, t, err);
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

int gr_observer_finish(gr_observer *o, const gr_output *out, gr_error *err)
{
    int first = GR_OK;
    for (int i = 0; i < o->n; i++) {
        int rc = o->type[i]->finish(o->state[i], out, err);
        first = first ? first : rc; /* keep writing the others */
    }
    return first;
}

int gr_observer_count(const gr_observer *o) { return o ? o->n : 0; }

bool gr_observer_needs_events(const gr_observer *o)
{
    for (int i = 0; o && i < o->n; i++) {
        if (o->type[i]->events) {
            return true;
        }
    }
    return false;
}

int gr_observer_events(gr_observer *o, const gr_contact_event *ev, int64_t n, gr_error *err)
{
    for (int i = 0; i < o->n; i++) {
        if (o->type[i]->events) {
            int rc = o->type[i]->events(o->state[i], ev, n, err);
            if (rc) {
                return rc;
            }
        }
    }
    return GR_OK;
}

int gr_observer_save(const gr_observer *o, gr_blob *out, gr_error *err)
{
    gr_blob_put_u64(out, (uint64_t)gr_observer_count(o));
    for (int i = 0; o && i < o->n; i++) {
        if (!o->type[i]->save) {
            return GR_FAIL(err, GR_EINVAL, "[analysis] observables: %s cannot be checkpointed yet", o->type[i]->name);
        }
        gr_blob one = {0};
        int rc = o->type[i]->save(o->state[i], &one, err);
        rc = rc ? rc : gr_blob_ok(&one, err);
        if (!rc) {
            gr_blob_put_str(out, o->type[i]->name);
            gr_blob_put_u64(out, one.len);
            gr_blob_put(out, one.data, one.len);
        }
        gr_blob_free(&one);
        if (rc) {
            return rc;
        }
    }
    return gr_blob_ok(out, err);
}

int gr_observer_load(gr_observer *o, const void *data, size_t len, gr_error *err)
{
    gr_blob_reader r;
    gr_blob_reader_init(&r, data, len, "OBS (observables)");
    uint64_t n = gr_blob_get_u64(&r);
    if (!r.bad && n != (uint64_t)gr_observer_count(o)) {
        gr_blob_fail(&r, "%llu observables in the checkpoint, %d enabled in the scene", (unsigned long long)n,
                     gr_observer_count(o));
    }
    for (int i = 0; !r.bad && i < o->n; i++) {
        char name[64];
        gr_blob_get_str(&r, name, sizeof name);
        uint64_t one_len = gr_blob_get_u64(&r);
        if (!r.bad && strcmp(name, o->type[i]->name) != 0) {
            gr_blob_fail(&r, "observable %d is %s in the checkpoint, %s in the scene", i + 1, name, o->type[i]->name);
        }
        const void *one = gr_blob_view(&r, (size_t)one_len);
        if (!r.bad && one_len > len) {
            gr_blob_fail(&r, "observable %s claims %llu bytes", name, (unsigned long long)one_len);
        }
        if (r.bad) {
            break;
        }
        if (!o->type[i]->load) {
            return GR_FAIL(err, GR_EINVAL, "[analysis] observables: %s cannot be restored from a checkpoint", name);
        }
        gr_blob_reader sub;
        char what[96];
        snprintf(what, sizeof what, "OBS/%s", name);
        gr_blob_reader_init(&sub, one, (size_t)one_len, what);
        int rc = o->type[i]->load(o->state[i], &sub, err);
        if (rc) {
            return rc;
        }
        rc = gr_blob_done(&sub, err);
        if (rc) {
            return rc;
        }
    }
    return gr_blob_done(&r, err);
}

void gr_observer_free(gr_observer *o)
{
    if (!o) {
        return;
    }
    for (int i = 0; i < o->n; i++) {
        o->type[i]->destroy(o->state[i]);
    }
    free(o);
}
