/* A simulation: particle state (structure of arrays), the chosen contact kernel, the random
 * force, neighbour finding and the energy ledger. Create one from a resolved scene, advance it
 * by steps, read its state.
 *
 * Time stepping (docs/integrator.md): velocity Verlet in kick-drift-kick form. The random
 * force of one step enters as a velocity kick between the two half kicks, so positions are
 * exactly those of the thesis's position Verlet (2.3) with a(t) = (F_contact + eta)/M; the
 * dashpot forces see the half-step velocity, the only one known before the force evaluation. */
#ifndef GRANULE_SIM_H
#define GRANULE_SIM_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/model.h"
#include "granule/particles.h"
#include "granule/scene.h"
#include "granule/status.h"

typedef struct gr_sim gr_sim;

/* Energies in J, accumulated since the simulation was created. */
typedef struct gr_ledger {
    double kinetic;        /* current kinetic energy sum M v^2 / 2 */
    double elastic;        /* current spring energy sum k_s xi^2 / 2 */
    double initial;        /* kinetic + elastic at creation */
    double injected;       /* work done by the random force */
    double dissipated_normal;     /* normal dashpot (2.5) */
    double dissipated_tangential; /* tangential dashpot (2.9) */
    double dissipated_friction;   /* sliding friction (2.7) */
    double removed_com;    /* kinetic energy removed by centre-of-mass resets (com noise mode) */
} gr_ledger;

/* Everything dissipated, by any mechanism. */
double gr_ledger_dissipated(const gr_ledger *l);
/* (kinetic + elastic) - initial - injected + dissipated + removed_com: zero for an exact
 * integrator; for ours the velocity-Verlet energy error of the springs, second order in dt
 * (docs/integrator.md, tests/test_sim.c). */
double gr_ledger_residual(const gr_ledger *l);


/* Build a simulation from a resolved scene: place the particles (sec. 2.1.4), give them small
 * random velocities, prepare the models and choose the kernel. Refuses overlapping placements
 * and time steps too large for the contact (unless the scene forces them). */
int gr_sim_create(const gr_scene *scene, gr_sim **out, gr_error *err);

/* Same, with positions and velocities given (n particles, y/vy ignored in 1D). Used by
 * `granule collide` and tests; the scene's N and placement are ignored. */
int gr_sim_create_with_state(const gr_scene *scene, int n, const double *x, const double *y,
                             const double *vx, const double *vy, gr_sim **out, gr_error *err);

/* Same as gr_sim_create_with_state, with the particles first put into a canonical order (1D: by
 * x; 2D: by cell of a grid of side >= d, row-major, then x, then y), so that the trajectory does
 * not depend on the order they are given in: gr_sim_particles then lists them in that order. */
int gr_sim_create_canonical(const gr_scene *scene, int n, const double *x, const double *y,
                            const double *vx, const double *vy, gr_sim **out, gr_error *err);

void gr_sim_free(gr_sim *sim);

/* Advance by nsteps time steps. Returns GR_EUNSTABLE with a diagnosis (step, time, particle,
 * quantity) if a non-finite value or runaway overlap appears; the state is then left as it was
 * at the failing step. */
int gr_sim_step(gr_sim *sim, int64_t nsteps, gr_error *err);

gr_particles gr_sim_particles(const gr_sim *sim);
/* The contact forces of the last force evaluation, N (n entries each; *fy is NULL in 1D). The
 * arrays, like those of gr_sim_particles, live as long as the simulation and are updated in place
 * by every step (the Python module hands them out as numpy views). */
void gr_sim_forces(const gr_sim *sim, const double **fx, const double **fy);
/* Threads for the simulation core (all simulations of the process): n >= 1, or 0 for the
 * default, which is 1 unless the environment sets OMP_NUM_THREADS (then that). `--threads N`
 * calls it. Results do not depend on the thread count (docs/performance.md, "Threads"). */
void gr_set_threads(int n);
/* The setting resolved: threads the core and the costly observables (S(k), g(R)) may use. */
int gr_get_threads(void);
/* Threads a step of sim uses now: the setting above, but 1 in 1D, for at most 1024 particles
 * (one block), without OpenMP, or when called from inside a parallel region. */
int gr_sim_threads(const gr_sim *sim);
double gr_sim_time(const gr_sim *sim);
int64_t gr_sim_steps(const gr_sim *sim);
double gr_sim_dt(const gr_sim *sim);
const gr_contact_coeffs *gr_sim_coeffs(const gr_sim *sim);
const char *gr_sim_kernel(const gr_sim *sim);
/* Contacts started since creation (a pair coming into overlap). */
int64_t gr_sim_collisions(const gr_sim *sim);
/* Neighbour-list rebuilds since creation. */
int64_t gr_sim_rebuilds(const gr_sim *sim);
/* Events processed by the event-driven integrator (collisions, cell crossings, per-particle
 * noise updates) since creation; 0 for the other integrators. */
int64_t gr_sim_events_processed(const gr_sim *sim);
/* Current ledger (kinetic and elastic energies evaluated now). */
gr_ledger gr_sim_ledger(gr_sim *sim);
/* Granular temperature (2.19): T = (1/N) sum |v_i - <v>|^2, all components. */
double gr_sim_temperature(const gr_sim *sim);
/* Largest overlap (d - r) / d among pairs in contact now. */
double gr_sim_max_overlap(gr_sim *sim);
/* Record contact events (see gr_contact_event) from now on; costs one pass over the contacts per
 * step, so it is off unless an observable needs it. */
int gr_sim_track_contacts(gr_sim *sim, gr_error *err);
/* The events recorded since the last gr_sim_clear_events. */
const gr_contact_event *gr_sim_events(const gr_sim *sim, int64_t *n);
void gr_sim_clear_events(gr_sim *sim);

/* Total momentum, kg m/s (p[1] = 0 in 1D). */
void gr_sim_momentum(const gr_sim *sim, double p[2]);

#endif
