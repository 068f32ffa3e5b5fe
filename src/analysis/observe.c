/* The observable registry and the set of observables a scene enables. */
#include <stdlib.h>
#include <string.h>

#include "granule/observe.h"
#include "granule/scene.h"

extern const gr_observable_type gr_obs_moments;
extern const gr_observable_type gr_obs_freepath;
extern const gr_observable_type gr_obs_postcollision;
extern const gr_observable_type gr_obs_gaps;
extern const gr_observable_type gr_obs_sk;
extern const gr_observable_type gr_obs_pair;
extern const gr_observable_type gr_obs_pv;

const gr_observable_type *const gr_observables[] = {
    &gr_obs_moments,
    &gr_obs_freepath,
    &gr_obs_postcollision,
    &gr_obs_gaps,
    &gr_obs_sk,
    &gr_obs_pair,
    &gr_obs_pv,
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

int gr_observer_sample(gr_observer *o, const gr_particles *p, double t, gr_error *err)
{
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
