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

struct cJSON;
struct gr_blob;
struct gr_blob_reader;

/* The [analysis] parameters: one block per registered observable (indexed as gr_observables),
 * holding that observable's own parameter struct. Each observable declares its scene keys in its
 * own file (gr_param offsets into its struct, params_size bytes), so adding one needs no field
 * here; the scene parser, `granule keys` and scene.ini read the descriptors from the registry. */
#define GR_OBS_MAX 24          /* registered observables at most */
#define GR_OBS_PARAMS_BYTES 64 /* one observable's parameter struct at most */
typedef struct gr_analysis_params {
    union {
        max_align_t align;
        unsigned char bytes[GR_OBS_PARAMS_BYTES];
    } block[GR_OBS_MAX];
} gr_analysis_params;

/* What the observables know of the system they measure: plain numbers the caller fills (from a
 * scene: gr_scene_obs_setup, include/granule/scene.h). The analysis layer sees no scene and no
 * collision model. */
typedef struct gr_obs_setup {
    const char *source;                 /* the scene's file, for messages */
    const char *observables;            /* [analysis] observables: comma-separated registry names */
    const gr_analysis_params *analysis; /* every observable's parameter block */
    int dim, N;
    double L, radius, mass; /* m, m, kg */
    double D;               /* noise strength, N^2 s (2.15, 2.22); 0 without the random force */
    double eps_n, eps_t;    /* the contact's restitution coefficients ([contact]) */
    const char *tangential; /* the tangential law's name, NULL without one */
    bool
        tangential_constant_eps_t; /* its eps_t is a constant restitution (gr_model.constant_eps_t) */
    /* the contact law's coefficients, for the force kernel's own law (gr_contact_virial, pressure's
     * virial); zero without a normal model. Observables never evaluate a law themselves. */
    gr_contact_coeffs contact;
    /* walls[a]: flat walls along axis a ([boundary]); positions there are not periodic (a floor
     * that vibrates below 0 carries grains below 0) */
    bool walls[3];
    /* a mixture (docs/mixtures.md): n_species >= 2 with [species] lists (0 for one species), and
     * sizes = true when the grains have radii and masses of their own (lists or a distribution:
     * the frames then carry radii and masses) */
    int n_species;
    bool sizes;
    /* the grains' number means <r> and <r^2> (m, m^2; with one size radius and radius^2; 0 when a
     * caller does not fill them): a mixture's mean collision diameter, 2 <r> in 1D and 2D and
     * sqrt(2 <r^2> + 2 <r>^2) in 3D (gr_obs_collision_diameter) */
    double radius_mean, radius_sq_mean;
    /* species lists: the normal law's coefficients of every pair (a, b) at [a * n_species + b], as
     * the force kernel has them (the pressure observable's virial); unset otherwise */
    gr_contact_coeffs contact_pair[GR_MAX_SPECIES * GR_MAX_SPECIES];
    /* a radius distribution: the reference pair's normal-law coefficients, reduced mass (kg) and
     * effective radius (m), which each pair's are scaled from as the force kernel does
     * (gr_contact_size_scaled); unset otherwise */
    gr_contact_coeffs size_contact;
    double size_m_ref, size_r_ref;
} gr_obs_setup;

/* The diameter a mixture's mean free path and k d are measured in: the mean over random pairs of
 * the contact distance r_i + r_j (1D, 2D: the cross-section is linear in it) or of its square (3D:
 * pi (r_i + r_j)^2); 2 radius for one size or when the means are not given. */
double gr_obs_collision_diameter(const gr_obs_setup *setup);

/* Where an observable writes its results. */
typedef struct gr_output {
    const char *dir;    /* existing folder */
    const char *source; /* the scene's file and seed, for the CSV headers */
    uint64_t seed;
    uint64_t scene_hash;
    struct cJSON *summary; /* the run's "analysis" object: add one member per observable */
    bool plots;            /* draw PNG plots */
} gr_output;

struct gr_blob_io;

/* An observable type: one file under src/analysis/ plus one line in the registry (observe.c);
 * docs/architecture.md, "How to add an observable". The shared skeleton (gr_observable_create,
 * gr_observable_free, gr_observable_save/load) allocates a zeroed state of state_size bytes,
 * hands init the observable's parameter block, frees whatever init registered with gr_obs_own
 * (src/analysis/obs_util.h), and saves and loads checkpoints through the one `io` function. */
typedef struct gr_observable_type {
    const char *name;    /* as listed in [analysis] observables */
    const char *summary; /* one line, with the thesis equations */
    unsigned
        dims; /* bit 1: 1D, bit 2: 2D, bit 4: 3D; other dimensions are refused with a message */
    const gr_param *params; /* its [analysis] keys: offsets into its own parameter struct */
    int n_params;
    size_t params_size; /* that struct's size (at most GR_OBS_PARAMS_BYTES) */
    size_t state_size;  /* the accumulator struct the skeleton allocates, zeroed */
    /* Fill a zeroed state for a system; `params` is the observable's parameter block. Refuse (GR_EINVAL,
     * naming the key and the allowed range) what it cannot compute; the skeleton frees on failure. */
    int (*init)(void *state, const gr_obs_setup *setup, const void *params, gr_error *err);
    /* One frame, sampled uniformly in time. */
    int (*sample)(void *state, const gr_particles *p, double t, gr_error *err);
    /* Write CSV (commented header), plots, and the summary member. */
    int (*finish)(void *state, const gr_output *out, gr_error *err);
    /* Optional: contact events (free paths, post-collision velocities) since the previous sample;
     * NULL for observables that only need frames. Events exist only while a run samples, not in
     * `granule analyse` (snapshots do not record contacts). */
    int (*events)(void *state, const gr_contact_event *ev, int64_t n, gr_error *err);
    /* Checkpoints (docs/checkpoints.md): list every accumulator once with the gr_blob_io_* calls
     * (src/core/blob.h); the same list saves them and restores them into a state just
     * created from the same setup, so that sampling continues bit for bit. NULL: the observable
     * cannot be checkpointed (a run using it refuses to). */
    int (*io)(void *state, struct gr_blob_io *io, gr_error *err);
} gr_observable_type;

/* The skeleton every observable shares: a state for `setup` (NULL on failure; its parameter block
 * is setup->analysis's), freed with gr_observable_free; its accumulators appended to a blob or
 * restored from one. */
int gr_observable_create(const gr_observable_type *t, const gr_obs_setup *setup, void **state,
                         gr_error *err);
void gr_observable_free(void *state);
int gr_observable_save(const gr_observable_type *t, void *state, struct gr_blob *out,
                       gr_error *err);
int gr_observable_load(const gr_observable_type *t, void *state, struct gr_blob_reader *in,
                       gr_error *err);

/* The registry, NULL-terminated. */
extern const gr_observable_type *const gr_observables[];
const gr_observable_type *gr_observable_find(const char *name);

/* Parameter blocks. The block of a registered type (NULL for a type not in the registry); every
 * block set to its observable's defaults; one parameter by scene key, as a double (GR_EINVAL
 * naming the key when no observable declares it). gr_analysis_set stores without the range
 * check of the scene parser (tests use it to reach an observable's own checks). */
void *gr_analysis_block(gr_analysis_params *a, const gr_observable_type *t);
const void *gr_analysis_block_const(const gr_analysis_params *a, const gr_observable_type *t);
void gr_analysis_defaults(gr_analysis_params *a);
int gr_analysis_get(const gr_analysis_params *a, const char *key, double *value, gr_error *err);
int gr_analysis_set(gr_analysis_params *a, const char *key, double value, gr_error *err);

/* The set of observables setup->observables enables. */
typedef struct gr_observer gr_observer;
int gr_observer_create(const gr_obs_setup *setup, gr_observer **out, gr_error *err);
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
 * back into an observer created from the same setup (names and order must agree). */
int gr_observer_save(const gr_observer *o, struct gr_blob *out, gr_error *err);
int gr_observer_load(gr_observer *o, const void *data, size_t len, gr_error *err);

#endif
