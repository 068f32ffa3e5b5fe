/* Integrators: how a simulation advances in time ([integrator] kind). Each is a registered
 * gr_integrator_type (src/integrators/NAME/, the list in src/integrators/registry.c), the way
 * observables are gr_observable_types: the core (src/core) keeps the particles, forces and ledger
 * and calls these hooks, and knows no integrator by name.
 *
 *   verlet  soft-sphere velocity Verlet, the random force as a mid-step kick (docs/integrator.md)
 *   event   event-driven hard spheres with free flight under the random force (docs/event-driven.md)
 *   hybrid  free flight for particles that cannot touch anybody, soft-sphere steps for the
 *           others, in windows of kick_interval (docs/hybrid.md)
 *
 * docs/architecture.md, "How to add an integrator", walks through writing one. */
#ifndef GRANULE_INTEGRATOR_H
#define GRANULE_INTEGRATOR_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/status.h"

typedef struct gr_sim gr_sim;
struct gr_blob_io; /* src/core/blob.h: saving and loading the state a checkpoint is made of */

/* One number an integrator reports about a run (summary.json). */
typedef struct gr_integrator_figure {
    const char *name;
    double value;
} gr_integrator_figure;

typedef struct gr_integrator_type {
    const char *name;    /* [integrator] kind */
    const char *summary; /* one line for the scene-key documentation */
    /* Contacts are instantaneous collision rules ([model] normal = hard_sphere, no tangential
     * law) rather than force laws; the scene checks the model against this. */
    bool instantaneous;
    /* Particles fly freely between contacts under the random force, with the scene's
     * [integrator] free_flight and kick_interval (event, hybrid). */
    bool free_flight;
    /* Kicks the angular velocities with the torques (gr_sim omega, tq) when a scene has rotation
     * ([model] rotation = true); an integrator without it refuses such a scene. */
    bool rotation;
    /* Carries a tangential spring's per-contact history (models/list.h: a law with history) from
     * step to step; an integrator without it refuses such a scene. */
    bool contact_history;
    /* Applies a viscous drag with its bath noise ([driving] kind = langevin, granule/driving.h);
     * an integrator without it refuses such a scene. */
    bool drag;
    /* Models flat walls and gravity ([boundary], [gravity]; gr_sim_params.walls, .gravity); an
     * integrator without it refuses such a scene. */
    bool walls;
    /* Draws the random force with [noise] precision = single (gr_noise_normals_f32) when the
     * scene asks; an integrator without it refuses such a scene. */
    bool single_noise;
    /* Steps spheres in a periodic cube ([system] dim = 3, docs/three-dimensions.md: the force laws'
     * normal part, the random force or no driving); an integrator without it refuses dim = 3. */
    bool spheres;
    /* Steps grains of several species, each with its own radius and mass ([species],
     * docs/mixtures.md); an integrator without it refuses a scene with species. */
    bool species;
    /* Runs its step on the threads of gr_team (docs/performance.md, "Threads"); without it a run
     * steps on one thread whatever --threads asks, and says so. */
    bool threads;

    /* Build the integrator's state (into the simulation's integrator_state) once positions,
     * velocities, coefficients, the time step and the first forces are set. NULL: none. */
    int (*create)(gr_sim *s, gr_error *err);
    /* Advance by nsteps * dt; on return the positions and velocities are those at that time and
     * the step counter has advanced by nsteps (except after a stop request, see set_stop). */
    int (*step)(gr_sim *s, int64_t nsteps, gr_error *err);
    /* Free the state built by create. NULL: nothing to free. */
    void (*free)(gr_sim *s);

    /* Optional hooks (NULL when the integrator has nothing to do there). */
    /* The steps the next call should take, given n = min(wanted, todo) and the steps todo before
     * the caller must stop (gr_sim_call_steps). */
    int64_t (*call_steps)(const gr_sim *s, int64_t n, int64_t todo);
    /* The integrator's own state after the core's (checkpoints), listed once: with io->out set
     * it appends, with io->in set it reads back in the same order (src/core/blob.h, gr_blob_io). */
    int (*state_io)(gr_sim *s, struct gr_blob_io *io, gr_error *err);
    /* Poll *stop during a long step and return early (step counter unchanged) when it is set. */
    void (*set_stop)(gr_sim *s, volatile sig_atomic_t *stop);
    /* Events processed since creation (event-driven integrators). */
    int64_t (*events)(const gr_sim *s);
    /* Up to cap figures for summary.json, in the object named `section`; returns how many. */
    int (*describe)(const gr_sim *s, gr_integrator_figure *out, int cap);
    const char *section;
} gr_integrator_type;

/* The registry: every integrator, NULL-terminated, in documentation order. */
extern const gr_integrator_type *const gr_integrators[];
/* The integrator called name, or NULL. */
const gr_integrator_type *gr_integrator_find(const char *name);
/* The registered names joined by sep ("verlet|event|hybrid"), for messages and docs. */
void gr_integrator_names(char *buf, size_t cap, const char *sep);

#endif
