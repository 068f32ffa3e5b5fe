/* Scenes: one run's physical system, collision model, noise, integrator, run length and
 * outputs, read from an INI file (SPEC sec. 3) plus `--set section.key=value` overrides.
 *
 * Every key is described by a gr_param descriptor (src/scene/scene_keys.c for the engine's keys,
 * the models' own tables for [model]); the same tables validate input, fill defaults (Table 2.2)
 * and generate docs/scene-keys.md. Errors name the file, line, key and allowed range. */
#ifndef GRANULE_SCENE_H
#define GRANULE_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "granule/model.h"
#include "granule/observe.h"
#include "granule/sim.h"
#include "granule/status.h"
#include "granule/trajectory.h"

/* A list of numbers of a scene key ([species] radius = 1.5e-3, 3e-3): n of them, n = 0 unset. */
typedef struct gr_number_list {
    int n;
    double v[GR_MAX_SPECIES];
} gr_number_list;

typedef struct gr_scene {
    /* [system] */
    int dim;                 /* 1 or 2 */
    int N;                   /* number of particles */
    double L;                /* box side (2D) or ring length (1D), m */
    double packing_fraction; /* 2D alternative to L: phi = N pi r^2 / L^2 (2.24); 0 = unset */
    double reduced_length;   /* 1D alternative to L: L' = L - N d; < 0 = unset */
    double radius;           /* m */
    double mass;             /* kg */
    /* [placement] */
    gr_placement_kind placement;
    double v0;     /* initial velocities v0 * U(-0.5, 0.5) per component, m/s */
    double omega0; /* rotation: initial angular velocities omega0 * U(-0.5, 0.5), rad/s */
    /* [model] */
    const gr_model *normal;
    const gr_model *tangential; /* NULL: no tangential law */
    const gr_model *rolling;    /* NULL: no rolling resistance */
    gr_contact_params contact;
    /* [driving] (granule/driving.h): rfm = the [noise] random force below; none; langevin */
    const gr_driving_type *driving;
    gr_driving_params driving_params;
    /* [boundary] and [gravity] (docs/systems-walls-gravity.md): boundary[a] = 1 puts flat walls at 0
     * and L on axis a (0 = x, 1 = y, 2 = z; 0 = periodic); gravity[a], m/s^2, needs walls on its
     * axis */
    int boundary[3];
    double gravity[3];
    int vibrate;                 /* 0 none, 1 x, 2 y, 3 z: the wall at 0 of that axis vibrates */
    double amplitude, frequency; /* m, Hz */
    int motion;                  /* the vibrating wall's motion: 0 sine, 1 sawtooth */
    /* [boundary] eps_n, eps_t, mu: the walls' own contact coefficients; NAN until resolved, then
     * the [model] values (the particles') where the scene does not give them */
    double wall_eps_n, wall_eps_t, wall_mu;
    /* [species] (docs/mixtures.md): one value per species, n = 0 when not given; resolved into
     * n_species (0: one species, the [system] radius and mass) and the grains of each */
    gr_number_list species_radius, species_mass, species_density, species_fraction;
    int n_species;
    int species_count[GR_MAX_SPECIES];
    double species_masses[GR_MAX_SPECIES]; /* kg: mass, or from density */
    /* or a continuous radius distribution (GR_SIZE_*; density one value): bounds, lognormal
     * median (m) and sigma of ln r */
    int size_distribution;
    double radius_min, radius_max, radius_median, radius_sigma;
    /* [noise] */
    double D; /* noise strength, N^2 s (2.15, 2.22) */
    gr_noise_mode noise_mode;
    double com_interval; /* com mode: seconds between centre-of-mass velocity removals */
    gr_noise_precision noise_precision;
    /* [integrator] */
    const gr_integrator_type *integrator; /* from the registry (granule/integrator.h) */
    double dt;                            /* s; 0 = derive from steps_per_contact */
    double steps_per_contact;
    bool force_dt; /* accept dt > t_c / 10 */
    double skin;   /* Verlet-list skin in diameters; 0 = rebuild the cell list every step */
    gr_free_flight_noise free_flight; /* event/hybrid: exact sampling or velocity kicks */
    double kick_interval; /* event: s between noise updates; hybrid: s per window of free flight */
    /* kick_interval left at its default: the hybrid's window is then the nearest whole number of
     * steps (>= 1) instead of a refusal when dt does not divide it (docs/hybrid.md) */
    bool kick_interval_default;
    /* [run] */
    double warmup, duration, sample_every; /* s */
    uint64_t seed;
    bool progress; /* progress line on a terminal */
    double
        ledger_tolerance; /* stop when |ledger residual| exceeds this fraction of the energy moved; 0 = off */
    double checkpoint_every; /* simulated s between checkpoints; 0 = off (docs/checkpoints.md) */
    double checkpoint_wall;  /* wall-clock s between checkpoints; 0 = off */
    double wall_limit; /* wall-clock budget, s: checkpoint and stop before it runs out; 0 = none */
    /* [analysis] */
    char observables[256]; /* comma-separated names from the observable registry; "" = none */
    gr_analysis_params analysis;
    /* [output] */
    char out_dir[1024];
    double snapshot_every;           /* s; 0 = no snapshots */
    gr_trajectory_format trajectory; /* one file per frame, one multi-frame XYZ, or H5MD */
    bool plots;
    /* where the scene came from (for messages and summary.json) */
    char source[1024];
    /* keys that were accepted but have no effect (e.g. mu without sliding_friction), one per
     * line, for the CLI to print as warnings */
    char warnings[1024];
} gr_scene;

/* Defaults: Table 2.2 particles, SPEC sec. 3 values. */
void gr_scene_default(gr_scene *s);

/* An override `section.key=value` (from --set). */
typedef struct gr_scene_override {
    const char *assignment;
} gr_scene_override;

/* Read a scene file (path may be NULL for defaults only) and apply overrides, then validate and
 * resolve derived quantities (L from packing fraction, ...). */
int gr_scene_load(gr_scene *s, const char *path, const char *const *overrides, int n_overrides,
                  gr_error *err);
/* gr_scene_load for a scene a user hands to a command: also refuses a file that is empty or only
 * comments, or has no [system] section (gr_scene_load accepts partial scenes, e.g. in tests). */
int gr_scene_load_whole(gr_scene *s, const char *path, const char *const *overrides,
                        int n_overrides, gr_error *err);
/* The same from scene text in memory (text[0..len), not NUL-terminated; `name` stands for the
 * file in messages). Used by the fuzz harness (tests/fuzz) and anything holding a scene in memory. */
int gr_scene_load_buffer(gr_scene *s, const char *name, const char *text, size_t len,
                         const char *const *overrides, int n_overrides, gr_error *err);

/* Write the resolved scene as dir/scene.ini (atomically): every key with the value the run used,
 * so `granule run DIR/scene.ini` repeats the run and `granule analyse DIR` knows the system. */
int gr_scene_save(const gr_scene *s, const char *dir, gr_error *err);
/* The same text written to a stream (checkpoints keep it to check a resumed scene). */
void gr_scene_write(const gr_scene *s, FILE *f);
/* gr_scene_write keeps the load's warnings as comment lines with this prefix; a resume restores
 * them into s->warnings from DIR/scene.ini, so summary.json is that of an uninterrupted run. */
#define GR_SCENE_WARNING_PREFIX "; warning: "
void gr_scene_saved_warnings(gr_scene *s, const char *dir);

/* Write the reference of every scene key (engine keys and every model's parameters) as
 * Markdown; docs/scene-keys.md is this output. */
void gr_scene_keys_markdown(FILE *out);
/* The unit of a scene key "section.name" (engine keys, model and observable parameters) in the
 * UDUNITS-style notation of the CSV sidecars ("N m-1", "1" for a pure number, "" for a text or
 * list key); NULL for an unknown key. */
const char *gr_scene_key_unit(const char *key);

/* Reduced mass of two identical particles. */
static inline double gr_scene_m12(const gr_scene *s) { return 0.5 * s->mass; }

/* What the observables need of a scene (src/scene/scene_sim.c): the plain gr_obs_setup that
 * gr_observer_create takes (the analysis layer never sees gr_scene). Its pointers point into s.
 * Fails only if the scene's contact law cannot be prepared (GR_EINVAL, naming the key). */
int gr_scene_obs_setup(const gr_scene *s, gr_obs_setup *out, gr_error *err);
/* gr_observer_create for a scene's [analysis] observables (gr_scene_obs_setup first). */
int gr_scene_observer(const gr_scene *s, gr_observer **out, gr_error *err);
/* gr_observable_create of one observable type for a scene (tests, tools). */
int gr_scene_observable(const gr_observable_type *t, const gr_scene *s, void **state,
                        gr_error *err);

/* The simulation parameters of a scene (src/scene/scene_sim.c): what gr_sim_new needs. */
void gr_scene_sim_params(const gr_scene *s, gr_sim_params *p);

/* Build a simulation from a resolved scene (gr_sim_new with gr_scene_sim_params): place the
 * particles (sec. 2.1.4), give them small random velocities, prepare the models and choose the
 * kernel. Refuses overlapping placements and time steps too large for the contact (unless the
 * scene forces them). */
int gr_sim_create(const gr_scene *scene, gr_sim **out, gr_error *err);

/* Same, with positions and velocities given (n particles, y/vy ignored in 1D). Used by
 * `granule collide` and tests; the scene's N and placement are ignored. */
int gr_sim_create_with_state(const gr_scene *scene, int n, const double *x, const double *y,
                             const double *vx, const double *vy, gr_sim **out, gr_error *err);

/* Same as gr_sim_create_with_state, with the particles first put into a canonical order
 * (gr_sim_new_canonical). */
int gr_sim_create_canonical(const gr_scene *scene, int n, const double *x, const double *y,
                            const double *vx, const double *vy, gr_sim **out, gr_error *err);

#endif
