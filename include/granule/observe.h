/* Observables: the shared analysis layer (SPEC sec. 4). Every statistic is an observable type
 * listed once in a registry; a scene enables the ones it wants ([analysis] observables = ...),
 * and the same instances are fed either while a run samples (uniformly in time) or afterwards
 * from snapshots (`granule analyse DIR`). Accumulators are streaming: memory does not grow with
 * the run length. Observables see particle views only, never a collision model. */
#ifndef GRANULE_OBSERVE_H
#define GRANULE_OBSERVE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/model.h"
#include "granule/particles.h"
#include "granule/status.h"

struct gr_scene;
struct cJSON;
struct gr_blob;
struct gr_blob_reader;

/* Parameters of every observable, set from the scene's [analysis] section. Each observable type
 * declares which of them it reads (gr_param offsets into this struct). */
typedef struct gr_analysis_params {
    int moments_max;      /* highest velocity moment <|v|^m> (3.11) */
    int pv_bins;          /* P(v) bins per component (App. A.1) */
    double pv_range;      /* P(v) covers |v| < pv_range * sqrt(T) */
    int gaps_h_max;       /* 1D: highest neighbour order h of G_h (3.24) */
    int gaps_bins;        /* 1D: bins of G_h and of the separations */
    bool gaps_log;        /* 1D: logarithmic binning of G_h (Fig. 3.12) */
    double sk_kd_max;     /* 2D: S(k) for |k| d up to this (4.2-4.3) */
    int gr_bins;          /* 2D: bins of g(R), C(R), n(R) (4.10, 4.15-4.17) */
    double gr_rmax;       /* 2D: largest R in diameters */
    int freepath_bins;    /* free-path distribution P_l(l), log bins (4.18) */
    double freepath_min;  /* smallest binned free path, in diameters */
    int msd_lags;         /* msd: lags (in sample intervals) of the mean-square displacement */
    int vacf_lags;        /* vacf: lags of the velocity autocorrelation */
    int vcorr_bins;       /* 2D: bins of the spatial velocity correlations */
    double vcorr_rmax;    /* 2D: largest distance of the velocity correlations, in diameters */
    double cluster_distance; /* density clusters: centres closer than this many diameters */
    int collision_bins;   /* log bins of the times between collisions */
} gr_analysis_params;

/* Where an observable writes its results. */
typedef struct gr_output {
    const char *dir;            /* existing folder */
    const struct gr_scene *scene;
    uint64_t scene_hash;
    struct cJSON *summary;      /* the run's "analysis" object: add one member per observable */
    bool plots;                 /* draw PNG plots */
} gr_output;

typedef struct gr_observable_type {
    const char *name;    /* as listed in [analysis] observables */
    const char *summary; /* one line, with the thesis equations */
    unsigned dims;       /* bit 1: 1D, bit 2: 2D */
    const gr_param *params;
    int n_params;
    int (*create)(const struct gr_scene *scene, void **state, gr_error *err);
    /* One frame, sampled uniformly in time. */
    int (*sample)(void *state, const gr_particles *p, double t, gr_error *err);
    /* Write CSV (commented header), plots, and the summary member. */
    int (*finish)(void *state, const gr_output *out, gr_error *err);
    void (*destroy)(void *state);
    /* Optional: contact events (free paths, post-collision velocities) since the previous sample;
     * NULL for observables that only need frames. Events exist only while a run samples, not in
     * `granule analyse` (snapshots do not record contacts). */
    int (*events)(void *state, const gr_contact_event *ev, int64_t n, gr_error *err);
    /* Checkpoints (docs/checkpoints.md): append every accumulator to `out` (src/analysis/blob_stats.h), and
     * restore them into a state just created from the same scene, so that sampling continues
     * bit for bit. NULL: the observable cannot be checkpointed (a run using it refuses to). */
    int (*save)(const void *state, struct gr_blob *out, gr_error *err);
    int (*load)(void *state, struct gr_blob_reader *in, gr_error *err);
} gr_observable_type;

/* The registry, NULL-terminated. */
extern const gr_observable_type *const gr_observables[];
const gr_observable_type *gr_observable_find(const char *name);

/* A set of enabled observables for one scene. */
typedef struct gr_observer gr_observer;
int gr_observer_create(const struct gr_scene *scene, gr_observer **out, gr_error *err);
/* Feed one frame to every enabled observable. A frame with a time, box length or velocity that is
 * not finite, or a coordinate farther than GR_COORD_MAX_BOXES box lengths from the origin, is
 * refused (GR_EINVAL naming the particle and value) before any observable sees it. */
#define GR_COORD_MAX_BOXES 1e9
int gr_observer_sample(gr_observer *o, const gr_particles *p, double t, gr_error *err);
int gr_observer_finish(gr_observer *o, const gr_output *out, gr_error *err);
int gr_observer_count(const gr_observer *o);
/* Whether any enabled observable takes contact events. */
bool gr_observer_needs_events(const gr_observer *o);
int gr_observer_events(gr_observer *o, const gr_contact_event *ev, int64_t n, gr_error *err);
void gr_observer_free(gr_observer *o);
/* All enabled observables' accumulators (name, length, payload each), for a checkpoint; and
 * back into an observer created from the same scene (names and order must agree). */
int gr_observer_save(const gr_observer *o, struct gr_blob *out, gr_error *err);
int gr_observer_load(gr_observer *o, const void *data, size_t len, gr_error *err);

#endif
