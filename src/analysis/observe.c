/* The observable registry and the set of observables a scene enables. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_list.h"
#include "analysis/obs_util.h"
#include "granule/observe.h"
#include "analysis/blob_stats.h"

#define DECLARE(name) extern const gr_observable_type gr_obs_##name;
#define ENTRY(name) &gr_obs_##name,
GR_OBSERVABLE_LIST(DECLARE)

const gr_observable_type *const gr_observables[] = {GR_OBSERVABLE_LIST(ENTRY) NULL};

#define COUNT(name) +1
_Static_assert(0 GR_OBSERVABLE_LIST(COUNT) <= GR_OBS_MAX,
               "more observables than GR_OBS_MAX parameter blocks");

const gr_observable_type *gr_observable_find(const char *name)
{
    for (int i = 0; gr_observables[i]; i++) {
        if (strcmp(gr_observables[i]->name, name) == 0) {
            return gr_observables[i];
        }
    }
    return NULL;
}

/* ------------------------------------------------------------------------------------------
 * Parameter blocks */

static int registry_index(const gr_observable_type *t)
{
    for (int i = 0; gr_observables[i] && i < GR_OBS_MAX; i++) {
        if (gr_observables[i] == t) {
            return i;
        }
    }
    return -1;
}

void *gr_analysis_block(gr_analysis_params *a, const gr_observable_type *t)
{
    int i = registry_index(t);
    return i < 0 ? NULL : a->block[i].bytes;
}

const void *gr_analysis_block_const(const gr_analysis_params *a, const gr_observable_type *t)
{
    int i = registry_index(t);
    return i < 0 ? NULL : a->block[i].bytes;
}

void gr_analysis_defaults(gr_analysis_params *a)
{
    memset(a, 0, sizeof *a);
    for (int o = 0; gr_observables[o] && o < GR_OBS_MAX; o++) {
        for (int i = 0; i < gr_observables[o]->n_params; i++) {
            const gr_param *p = &gr_observables[o]->params[i];
            unsigned char *slot = a->block[o].bytes + p->offset;
            if (p->type == GR_PARAM_BOOL) {
                *(bool *)slot = p->def != 0.0;
            } else if (p->type == GR_PARAM_INT) {
                *(int *)slot = (int)p->def;
            } else {
                *(double *)slot = p->def;
            }
        }
    }
}

/* The descriptor of [analysis] key `key` and its slot in `a`. */
static const gr_param *find_param(const gr_analysis_params *a, const char *key,
                                  const unsigned char **slot)
{
    for (int o = 0; gr_observables[o] && o < GR_OBS_MAX; o++) {
        for (int i = 0; i < gr_observables[o]->n_params; i++) {
            const gr_param *p = &gr_observables[o]->params[i];
            if (strcmp(p->name, key) == 0) {
                *slot = a->block[o].bytes + p->offset;
                return p;
            }
        }
    }
    return NULL;
}

int gr_analysis_get(const gr_analysis_params *a, const char *key, double *value, gr_error *err)
{
    const unsigned char *slot;
    const gr_param *p = find_param(a, key, &slot);
    if (!p) {
        return GR_FAIL(err, GR_EINVAL, "[analysis] %s: no observable declares this key", key);
    }
    *value = p->type == GR_PARAM_BOOL  ? (double)*(const bool *)slot
             : p->type == GR_PARAM_INT ? (double)*(const int *)slot
                                       : *(const double *)slot;
    return GR_OK;
}

int gr_analysis_set(gr_analysis_params *a, const char *key, double value, gr_error *err)
{
    const unsigned char *slot;
    const gr_param *p = find_param(a, key, &slot);
    if (!p) {
        return GR_FAIL(err, GR_EINVAL, "[analysis] %s: no observable declares this key", key);
    }
    unsigned char *w = (unsigned char *)a + (slot - (const unsigned char *)a);
    if (p->type == GR_PARAM_BOOL) {
        *(bool *)w = value != 0.0;
    } else if (p->type == GR_PARAM_INT) {
        *(int *)w = (int)value;
    } else {
        *(double *)w = value;
    }
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * The skeleton: a head in front of every state records the type and what init asked to free. */

typedef struct owned {
    void (*release)(void *obj);
    void *obj;
} owned;

typedef struct head {
    const gr_observable_type *type;
    owned *own;
    int n_own, cap_own;
    bool oom; /* an allocation through gr_obs_calloc or gr_obs_own failed */
} head;

/* The head's size rounded up so that the state after it is aligned for any type. */
#define HEAD_BYTES                                                                                 \
    ((sizeof(head) + sizeof(max_align_t) - 1) / sizeof(max_align_t) * sizeof(max_align_t))

static head *head_of(const void *state) { return (head *)((char *)state - HEAD_BYTES); }

bool gr_obs_own(void *state, void (*release)(void *obj), void *obj)
{
    head *h = head_of(state);
    if (h->n_own == h->cap_own) {
        int cap = h->cap_own ? 2 * h->cap_own : 8;
        owned *grown = realloc(h->own, sizeof *grown * (size_t)cap);
        if (!grown) {
            release(obj);
            h->oom = true;
            return false;
        }
        h->own = grown;
        h->cap_own = cap;
    }
    h->own[h->n_own++] = (owned){release, obj};
    return true;
}

void *gr_obs_calloc(void *state, size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p) {
        head_of(state)->oom = true;
        return NULL;
    }
    return gr_obs_own(state, free, p) ? p : NULL;
}

int gr_obs_alloc_ok(const void *state, gr_error *err)
{
    const head *h = head_of(state);
    return h->oom ? GR_FAIL(err, GR_ENOMEM, "%s: out of memory", h->type->name) : GR_OK;
}

int gr_observable_create(const gr_observable_type *t, const gr_obs_setup *setup, void **state,
                         gr_error *err)
{
    *state = NULL;
    if (t->params_size > GR_OBS_PARAMS_BYTES) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: a parameter struct of %zu bytes (at most GR_OBS_PARAMS_BYTES = %d)",
                       t->name, t->params_size, GR_OBS_PARAMS_BYTES);
    }
    head *h = calloc(1, HEAD_BYTES + t->state_size);
    if (!h) {
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory", t->name);
    }
    h->type = t;
    void *s = (char *)h + HEAD_BYTES;
    int rc = t->init(s, setup, gr_analysis_block_const(setup->analysis, t), err);
    rc = rc ? rc : gr_obs_alloc_ok(s, err);
    if (rc) {
        gr_observable_free(s);
        return rc;
    }
    *state = s;
    return GR_OK;
}

void gr_observable_free(void *state)
{
    if (!state) {
        return;
    }
    head *h = head_of(state);
    for (int i = h->n_own - 1; i >= 0; i--) {
        h->own[i].release(h->own[i].obj);
    }
    free(h->own);
    free(h);
}

int gr_observable_save(const gr_observable_type *t, void *state, gr_blob *out, gr_error *err)
{
    if (!t->io) {
        return GR_FAIL(err, GR_EINVAL, "[analysis] observables: %s cannot be checkpointed yet",
                       t->name);
    }
    gr_blob_io io = {.out = out};
    int rc = t->io(state, &io, err);
    return rc ? rc : gr_blob_ok(out, err);
}

int gr_observable_load(const gr_observable_type *t, void *state, gr_blob_reader *in, gr_error *err)
{
    if (!t->io) {
        return GR_FAIL(err, GR_EINVAL,
                       "[analysis] observables: %s cannot be restored from a checkpoint", t->name);
    }
    gr_blob_io io = {.in = in};
    int rc = t->io(state, &io, err);
    return rc ? rc : gr_obs_alloc_ok(state, err);
}

#define MAX_OBSERVERS 16

struct gr_observer {
    int n;
    const gr_observable_type *type[MAX_OBSERVERS];
    void *state[MAX_OBSERVERS];
};

int gr_observer_create(const gr_obs_setup *setup, gr_observer **out, gr_error *err)
{
    gr_observer *o = calloc(1, sizeof *o);
    if (!o) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    char buf[256];
    snprintf(buf, sizeof buf, "%s", setup->observables ? setup->observables : "");
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        const gr_observable_type *t = gr_observable_find(tok);
        if (!t) {
            gr_observer_free(o);
            return GR_FAIL(err, GR_EINVAL, "[analysis] observables: unknown observable '%s'", tok);
        }
        if (!(t->dims & (1u << (setup->dim - 1)))) {
            gr_observer_free(o);
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [analysis] observables: %s is not defined for dim = %d",
                           setup->source, tok, setup->dim);
        }
        bool dup = false;
        for (int i = 0; i < o->n; i++) {
            dup |= o->type[i] == t;
        }
        if (dup || o->n == MAX_OBSERVERS) {
            continue;
        }
        int rc = gr_observable_create(t, setup, &o->state[o->n], err);
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
        return GR_FAIL(err, GR_EINVAL,
                       "frame at t = %.17g s: box length L = %g m is not a positive finite number",
                       t, p->L);
    }
    const double lim = GR_COORD_MAX_BOXES * p->L;
    for (int i = 0; i < p->n; i++) {
        const double c[6] = {p->x[i],  p->dim >= 2 ? p->y[i] : 0.0,  p->dim == 3 ? p->z[i] : 0.0,
                             p->vx[i], p->dim >= 2 ? p->vy[i] : 0.0, p->dim == 3 ? p->vz[i] : 0.0};
        static const char *const name[6] = {"x", "y", "z", "vx", "vy", "vz"};
        for (int k = 0; k < 6; k++) {
            if (k < 3 && !(fabs(c[k]) <= lim)) {
                return GR_FAIL(err, GR_EINVAL,
                               "frame at t = %.17g s: particle %d has %s = %g m, outside the range "
                               "|%s| <= %g L = %g m that can be wrapped into the box",
                               t, i, name[k], c[k], name[k], GR_COORD_MAX_BOXES, lim);
            }
            if (k >= 3 && !isfinite(c[k])) {
                return GR_FAIL(
                    err, GR_EINVAL,
                    "frame at t = %.17g s: particle %d has %s = %g m/s, not a finite number", t, i,
                    name[k], c[k]);
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
        gr_blob one = {0};
        int rc = gr_observable_save(o->type[i], o->state[i], &one, err);
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
        gr_blob_fail(&r, "%llu observables in the checkpoint, %d enabled in the scene",
                     (unsigned long long)n, gr_observer_count(o));
    }
    for (int i = 0; !r.bad && i < o->n; i++) {
        char name[64];
        gr_blob_get_str(&r, name, sizeof name);
        uint64_t one_len = gr_blob_get_u64(&r);
        if (!r.bad && strcmp(name, o->type[i]->name) != 0) {
            gr_blob_fail(&r, "observable %d is %s in the checkpoint, %s in the scene", i + 1, name,
                         o->type[i]->name);
        }
        const void *one = gr_blob_view(&r, (size_t)one_len);
        if (!r.bad && one_len > len) {
            gr_blob_fail(&r, "observable %s claims %llu bytes", name, (unsigned long long)one_len);
        }
        if (r.bad) {
            break;
        }
        gr_blob_reader sub;
        char what[96];
        snprintf(what, sizeof what, "OBS/%s", name);
        gr_blob_reader_init(&sub, one, (size_t)one_len, what);
        int rc = gr_observable_load(o->type[i], o->state[i], &sub, err);
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
        gr_observable_free(o->state[i]);
    }
    free(o);
}
