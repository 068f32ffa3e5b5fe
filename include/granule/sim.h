/* A simulation: particle state (structure of arrays), the chosen contact kernel, the random
 * force, neighbour finding and the energy ledger. Create one from a plain parameter struct
 * (gr_sim_params; a scene fills one: gr_scene_sim_params, or gr_sim_create in scene.h), advance
 * it by steps with its integrator (granule/integrator.h), read its state.
 *
 * Time stepping (docs/integrator.md): velocity Verlet in kick-drift-kick form. The random
 * force of one step enters as a velocity kick between the two half kicks, so positions are
 * exactly those of the thesis's position Verlet (2.3) with a(t) = (F_contact + eta)/M; the
 * dashpot forces see the half-step velocity, the only one known before the force evaluation. */
#ifndef GRANULE_SIM_H
#define GRANULE_SIM_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/driving.h"
#include "granule/model.h"
#include "granule/particles.h"
#include "granule/integrator.h"
#include "granule/status.h"

typedef struct gr_sim gr_sim;

/* GR_MAX_SPECIES (granule/particles.h): species of a polydisperse simulation at most */

/* Energies in J, accumulated since the simulation was created. */
typedef struct gr_ledger {
    double kinetic;    /* current kinetic energy sum M v^2 / 2 (+ sum I w^2 / 2 with rotation) */
    double rotational; /* its rotational part sum I w^2 / 2 (0 without rotation) */
    double elastic;    /* current spring energy sum k_s xi^2 / 2 */
    double initial;    /* kinetic + elastic (+ potential) at creation */
    double injected;   /* work done by the random force */
    double dissipated_normal;     /* normal dashpot (2.5) */
    double dissipated_tangential; /* tangential dashpot (2.9) */
    double dissipated_friction;   /* sliding friction (2.7) */
    double removed_com; /* kinetic energy removed by centre-of-mass resets (com noise mode) */
    double
        dissipated_drag; /* the Langevin bath's viscous drag ([driving] kind = langevin; 0 otherwise) */
    double
        potential; /* current potential energy in gravity, -M sum g . r_i ([gravity]; 0 without) */
    double wall_work; /* work of the moving walls on the grains ([boundary] vibrate; 0 without) */
} gr_ledger;

/* Everything dissipated, by any mechanism (collisions and the bath's drag). */
double gr_ledger_dissipated(const gr_ledger *l);
/* (kinetic + elastic + potential) - initial - injected - wall_work + dissipated + removed_com: zero
 * for an exact
 * integrator; for ours the velocity-Verlet energy error of the springs, second order in dt
 * (docs/integrator.md, tests/test_sim.c). */
double gr_ledger_residual(const gr_ledger *l);

typedef enum {
    GR_PLACE_HEXAGONAL,
    GR_PLACE_SQUARE,
    GR_PLACE_UNIFORM,
    GR_PLACE_CLUSTER,
    GR_PLACE_RANDOM,
    GR_PLACE_CUBIC, /* 3D: simple cubic lattice (docs/three-dimensions.md) */
    GR_PLACE_FCC    /* 3D: face-centred cubic lattice */
} gr_placement_kind;
typedef enum { GR_WALL_SINE = 0, GR_WALL_SAWTOOTH = 1 } gr_wall_motion;
typedef enum { GR_NOISE_NONE, GR_NOISE_SYMMETRISED, GR_NOISE_COM } gr_noise_mode;
/* The random force's normals: gr_noise_normals (double) or gr_noise_normals_f32 (single). */
typedef enum { GR_NOISE_DOUBLE, GR_NOISE_SINGLE } gr_noise_precision;
/* How the random force drives free flight in the event-driven and hybrid integrators. */
typedef enum { GR_FREE_FLIGHT_EXACT, GR_FREE_FLIGHT_KICKS } gr_free_flight_noise;

/* Names for enums, for summaries and messages. */
const char *gr_placement_name(gr_placement_kind k);
const char *gr_noise_mode_name(gr_noise_mode m);

/* Everything the engine needs to build and advance a simulation, in SI units: the scene's
 * [system], [placement], [model], [noise] and [integrator] keys and the seed (docs/scene-keys.md
 * documents each). Fill it by hand to drive the library without the scene parser. */
typedef struct gr_sim_params {
    int dim;             /* 1, 2 or 3 (spheres: docs/three-dimensions.md) */
    int N;               /* particles (gr_sim_new) */
    double L;            /* box side (2D, 3D) or ring length (1D), m */
    double radius, mass; /* m, kg */
    gr_placement_kind placement;
    double v0;     /* initial velocities v0 * U(-0.5, 0.5) per component, m/s */
    double omega0; /* rotation: initial angular velocities omega0 * U(-0.5, 0.5), rad/s */
    const gr_model *normal;
    const gr_model *tangential; /* NULL: none */
    const gr_model *rolling;    /* rolling resistance (needs contact.rotation); NULL: none */
    gr_contact_params contact;
    double D; /* noise strength, N^2 s (2.15, 2.22) */
    gr_noise_mode noise_mode;
    double com_interval;                /* com mode: s between centre-of-mass velocity removals */
    gr_noise_precision noise_precision; /* verlet only; the default (0) is double */
    /* [driving] (granule/driving.h): NULL = rfm, the random force above. none switches it off;
     * langevin replaces it by the bath of driving_params (needs an integrator with .drag). */
    const gr_driving_type *driving;
    gr_driving_params driving_params;
    /* [boundary] and [gravity] (docs/systems-walls-gravity.md): walls[a] puts flat walls at 0 and L
     * on axis a (0 = x, 1 = y, 2 = z) instead of the periodic images; gravity is a constant acceleration,
     * m/s^2, allowed only along an axis with walls. All false / 0 (the default) is the thesis's
     * periodic box, run by the same loops as before. Needs an integrator with .walls (verlet). */
    bool walls[3];
    double gravity[3];
    /* A vibrating wall: vibrate = 1 (x), 2 (y) or 3 (z) moves the wall at 0 of that axis (which needs
     * walls) as amplitude sin(2 pi frequency t), m and Hz; its work is booked as injected. 0 = none */
    int vibrate;
    double amplitude, frequency;
    /* The vibrating wall's motion: GR_WALL_SINE (the default), A sin(2 pi f t), or
     * GR_WALL_SAWTOOTH, rising at the constant speed 2 A f from -A to A over each period 1 / f and
     * dropping back instantly at its end (docs/systems-walls-gravity.md). */
    int motion;
    /* The walls' own contact coefficients ([boundary] eps_n, eps_t, mu): with wall_coeffs the wall
     * contact is prepared from [model]'s parameters with these three replaced; false (the
     * default): the particles' own (contact.eps_n, eps_t, mu). */
    bool wall_coeffs;
    double wall_eps_n, wall_eps_t, wall_mu;
    const gr_integrator_type *integrator; /* gr_integrator_find("verlet"), ... */
    double dt;                            /* s; 0 = t_c / steps_per_contact */
    double steps_per_contact;
    bool force_dt;                    /* accept dt > t_c / 10 */
    double skin;                      /* Verlet-list skin in diameters */
    gr_free_flight_noise free_flight; /* event / hybrid */
    double kick_interval;             /* event / hybrid, s */
    bool kick_interval_default;       /* not given: the hybrid rounds its window to whole steps */
    uint64_t seed;
    char source[1024]; /* names the input in messages (a scene file, "python", ...) */
    /* Species ([species], docs/mixtures.md): n_species >= 2 gives each grain the radius and mass
     * of its species, species_count[s] grains of species s (gr_species_counts), assigned to the
     * grains in an order shuffled by the seed; radius and mass above are then unused. 0 (the
     * default) or 1: every grain has radius and mass (the monodisperse path, unchanged). 1D and
     * 2D, verlet, a normal law alone, periodic, the random force or none (gr_sim_new refuses the
     * rest). */
    int n_species;
    double species_radius[GR_MAX_SPECIES], species_mass[GR_MAX_SPECIES]; /* m, kg */
    int species_count[GR_MAX_SPECIES];
    /* A continuous radius distribution instead ([species] distribution, docs/mixtures.md):
     * size_distribution GR_SIZE_UNIFORM or GR_SIZE_LOGNORMAL gives grain i the radius
     * gr_size_radius(p, i) in [size_min, size_max] (lognormal: median size_median, sigma
     * size_sigma of ln r, truncated to the bounds) and the mass size_density pi r^2 (2D) or
     * size_density 2 r (1D); n_species must then be 0. GR_SIZE_NONE (0, the default): none. */
    int size_distribution;
    double size_min, size_max, size_median, size_sigma, size_density;
} gr_sim_params;

enum { GR_SIZE_NONE = 0, GR_SIZE_UNIFORM = 1, GR_SIZE_LOGNORMAL = 2 };

/* The radius of grain i under a continuous distribution: a pure function of the seed and i
 * (kind, bounds, median and sigma as in gr_sim_params), m. */
double gr_size_radius(int kind, double rmin, double rmax, double median, double sigma,
                      uint64_t seed, int i);
/* The mass of a distribution's grain of radius r at the [species] density: 2 r rho in 1D (kg/m),
 * pi r^2 rho in 2D (kg/m^2), 4/3 pi r^3 rho in 3D (kg/m^3). */
double gr_size_mass(int dim, double density, double r);

/* Grains per species from number fractions (fraction[0..ns), summing to 1): round(f_s N), the
 * rounding error given to the last species, so the counts sum to N. Returns 0, or GR_EINVAL when
 * a count would be negative. */
int gr_species_counts(int N, int ns, const double *fraction, int *count);

/* The normal law's coefficients of species pair (a, b) of a run's parameters (species lists), as
 * the force kernel has them: the pair's reduced mass, hertz's k_h at its effective radius (for
 * the pressure observable's virial). */
int gr_species_pair_coeffs(const gr_sim_params *p, int a, int b, gr_contact_coeffs *out,
                           gr_error *err);

/* A radius distribution's reference contact, which every pair's coefficients are scaled from
 * (gr_contact_size_scaled): the normal law's coefficients prepared for the reference pair (as
 * gr_species_pair_coeffs, at dt = 0), its reduced mass m_ref (kg) and effective radius r_ref (m), as
 * the force kernel has them (the pressure observable's virial). */
int gr_size_reference_coeffs(const gr_sim_params *p, gr_contact_coeffs *out, double *m_ref,
                             double *r_ref, gr_error *err);

/* Build a simulation: place the particles (sec. 2.1.4), give them small random velocities,
 * prepare the models, choose the kernel and create the integrator's state. Refuses overlapping
 * placements and time steps too large for the contact (unless p->force_dt). */
int gr_sim_new(const gr_sim_params *p, gr_sim **out, gr_error *err);

/* Same, with positions and velocities given (n particles, y/vy ignored in 1D); p->N and the
 * placement are ignored. 1D and 2D only: dim = 3 is refused (gr_sim_new_with_state_3d). */
int gr_sim_new_with_state(const gr_sim_params *p, int n, const double *x, const double *y,
                          const double *vx, const double *vy, gr_sim **out, gr_error *err);

/* The same for spheres (dim = 3): positions r[0..2] (x, y, z, wrapped into the cube) and
 * velocities v[0..2] of n particles (granule collide --dim 3). */
int gr_sim_new_with_state_3d(const gr_sim_params *p, int n, const double *const r[3],
                             const double *const v[3], gr_sim **out, gr_error *err);

/* Same as gr_sim_new_with_state, with the particles first put into a canonical order (1D: by
 * x; 2D: by cell of a grid of side >= d, row-major, then x, then y), so that the trajectory does
 * not depend on the order they are given in: gr_sim_particles then lists them in that order. */
int gr_sim_new_canonical(const gr_sim_params *p, int n, const double *x, const double *y,
                         const double *vx, const double *vy, gr_sim **out, gr_error *err);

void gr_sim_free(gr_sim *sim);

/* Advance by nsteps time steps with the simulation's integrator. Returns GR_EUNSTABLE with a diagnosis (step, time, particle,
 * quantity) if a non-finite value or runaway overlap appears; the state is then left as it was
 * at the failing step. */
int gr_sim_step(gr_sim *sim, int64_t nsteps, gr_error *err);

gr_particles gr_sim_particles(const gr_sim *sim);
/* The contact forces of the last force evaluation, N (n entries each; *fy is NULL in 1D). The
 * arrays, like those of gr_sim_particles, live as long as the simulation and are updated in place
 * by every step (the Python module hands them out as numpy views). */
void gr_sim_forces(const gr_sim *sim, const double **fx, const double **fy);

/* The angular velocities, rad/s ([model] rotation = true; all NULL without rotation): *wz the
 * spin about z (2D: the discs' counterclockwise w, gr_particles.omega), *wx and *wy its x and y
 * components in 3D (NULL in 2D). n entries each, valid until the next step. */
void gr_sim_spins(const gr_sim *sim, const double **wx, const double **wy, const double **wz);
/* Threads for the simulation core (all simulations of the process): n >= 1, or 0 for the
 * default, which is 1 unless the environment sets OMP_NUM_THREADS (then that). `--threads N`
 * calls it. Results do not depend on the thread count (docs/performance.md, "Threads"). */
void gr_set_threads(int n);
/* The setting resolved: threads the core and the costly observables (S(k), g(R)) may use. */
int gr_get_threads(void);
/* Threads a step of sim uses now: the setting above, but 1 when the reason below applies,
 * without OpenMP, or when called from inside a parallel region. */
int gr_sim_threads(const gr_sim *sim);
/* Why a step of sim runs on one thread whatever the setting (1D, the event-driven integrator,
 * at most 1024 particles), in words; NULL when it uses the setting's threads. */
const char *gr_sim_one_thread_reason(const gr_sim *sim);
double gr_sim_time(const gr_sim *sim);
int64_t gr_sim_steps(const gr_sim *sim);
double gr_sim_dt(const gr_sim *sim);
const gr_contact_coeffs *gr_sim_coeffs(const gr_sim *sim);
/* A mixture's ([species] lists, docs/mixtures.md) coefficients of species pair (a, b), prepared
 * with the pair's reduced mass (and radius); NULL without species lists or out of range. */
const gr_contact_coeffs *gr_sim_species_coeffs(const gr_sim *sim, int a, int b);
/* The normal law's coefficients against a wall (reduced mass M; docs/systems-walls-gravity.md);
 * NULL without walls or for an integrator with its own wall events. */
const gr_contact_coeffs *gr_sim_wall_coeffs(const gr_sim *sim);
/* A mixture's ([species] lists) wall coefficients of species a (its own mass against the wall);
 * NULL without species lists, walls, or a soft integrator's wall contacts. */
const gr_contact_coeffs *gr_sim_species_wall_coeffs(const gr_sim *sim, int a);
const char *gr_sim_kernel(const gr_sim *sim);
/* Contacts started since creation (a pair coming into overlap). */
int64_t gr_sim_collisions(const gr_sim *sim);
/* Neighbour-list rebuilds since creation. */
int64_t gr_sim_rebuilds(const gr_sim *sim);
/* Rebuilds of the contact sublist, the list's pairs that can touch soon (docs/integrator.md): 0
 * while it is off. */
int64_t gr_sim_sublist_rebuilds(const gr_sim *sim);
/* The integrator (its type: name, hooks). */
const gr_integrator_type *gr_sim_integrator(const gr_sim *sim);
/* Poll *stop (e.g. set by a SIGTERM handler) during long steps, for integrators that can return
 * early (event: see gr_integrator_type.set_stop); NULL for none. */
void gr_sim_set_stop(gr_sim *sim, volatile sig_atomic_t *stop);
/* Events processed by the event-driven integrator (collisions, cell crossings, per-particle
 * noise updates) since creation; 0 for the other integrators. */
int64_t gr_sim_events_processed(const gr_sim *sim);
/* Current ledger (kinetic and elastic energies evaluated now). */
gr_ledger gr_sim_ledger(gr_sim *sim);
/* Granular temperature (2.19): T = (1/N) sum |v_i - <v>|^2, all components (three in 3D). */
double gr_sim_temperature(const gr_sim *sim);
/* With rotation: T_rot = I <w^2> / M, m^2/s^2, the rotational degree of freedom in the units of
 * T (equipartition: T_rot = T / 2 in 2D, since T sums two translational ones); NaN without. */
double gr_sim_rotational_temperature(const gr_sim *sim);
/* Largest overlap (d - r) / d among pairs in contact now. */
double gr_sim_max_overlap(gr_sim *sim);
/* Record contact events (see gr_contact_event) from now on; costs one pass over the contacts per
 * step, so it is off unless an observable needs it. */
int gr_sim_track_contacts(gr_sim *sim, gr_error *err);
/* The events recorded since the last gr_sim_clear_events. */
const gr_contact_event *gr_sim_events(const gr_sim *sim, int64_t *n);
void gr_sim_clear_events(gr_sim *sim);

/* The complete state of a simulation as bytes, for exact restarts in memory or in a file of the
 * caller's (checkpoints: docs/checkpoints.md): *data (free() it) holds everything the next
 * gr_sim_step depends on, the integrator's part included, and a trailer with their CRC-32. Call
 * between gr_sim_step calls. */
int gr_sim_state_save(const gr_sim *sim, void **data, size_t *len, gr_error *err);
/* Overwrite the state of sim, freshly created from the same parameters (and with contact
 * tracking on if the saved one had it), with saved bytes; stepping on is then bit-identical to
 * stepping the saved simulation. Refuses bytes of another system (N, dim, dt, L, d, mass, kernel,
 * integrator), truncated or changed ones (the CRC-32 trailer does not match) with GR_EINVAL; sim
 * must then be freed. */
int gr_sim_state_load(gr_sim *sim, const void *data, size_t len, gr_error *err);

/* The normal impulse each wall has taken from the grains since creation, N s: J[0], J[1] the walls
 * at x = 0 and x = L, J[2], J[3] those at y = 0 and y = L, J[4], J[5] those at z = 0 and z = L
 * (0 for a periodic axis or one the dimension lacks). The force of
 * every evaluation counts for one step dt, so (J(t2) - J(t1)) / (t2 - t1) is the wall's mean normal
 * force over [t1, t2] (> 0: the grains push it outwards). */
void gr_sim_wall_impulse(const gr_sim *sim, double J[6]);

/* Total momentum, kg m/s (p[1] = 0 in 1D; in 3D its x and y components: z from gr_sim_particles'
 * vz). */
void gr_sim_momentum(const gr_sim *sim, double p[2]);

#endif
