/* The hybrid integrator ([integrator] kind = hybrid, docs/hybrid.md): time is cut into windows of
 * kick_interval; particles that cannot touch anybody during a window leap it in one exact
 * free-flight draw, the others (the "active" set) are integrated step by step by the soft-sphere
 * kernels in a private child simulation. A registered integrator (gr_integrator_hybrid,
 * hybrid_type.c); its state lives behind gr_sim.integrator_state. */
#ifndef GR_HYBRID_H
#define GR_HYBRID_H

#include <stdint.h>

#include "core/blob.h"
#include "core/sim_internal.h"

extern const gr_integrator_type gr_integrator_hybrid;

/* The hybrid state of s, or NULL when s is not a hybrid simulation. */
static inline struct gr_hybrid_state *gr_hy(const gr_sim *s)
{
    return s->integrator == &gr_integrator_hybrid ? (struct gr_hybrid_state *)s->integrator_state
                                                  : NULL;
}

/* Build the hybrid state after positions, velocities, coefficients and forces are set. */
int gr_hybrid_init(gr_sim *s, gr_error *err);
/* Advance by nsteps * s->dt of simulated time; on return s->x, vx (y, vy) hold the state at that
 * time, s->step has advanced by nsteps and the ledger is updated as for Verlet. */
int gr_hybrid_step(gr_sim *s, int64_t nsteps, gr_error *err);
void gr_hybrid_free(gr_sim *s);

/* Counters since creation (all zero for other integrators). */
typedef struct gr_hybrid_stats {
    int64_t windows;        /* windows completed */
    int64_t rollbacks;      /* windows redone because a free particle met somebody */
    int64_t steps;          /* time steps covered */
    int64_t active_steps;   /* particle-steps integrated by the soft-sphere child */
    double active_fraction; /* active_steps / (N steps) */
    double margin_sigmas;   /* c of the active-set rule */
    double window;          /* s */
} gr_hybrid_stats;

/* Returns 1 and fills *st for a hybrid simulation, 0 otherwise. */
int gr_sim_hybrid_stats(const gr_sim *s, gr_hybrid_stats *st);

/* Tests and benches: change the safety factor c of the active-set margin (default
 * GR_HYBRID_MARGIN_SIGMAS); a huge c makes every particle active. */
#define GR_HYBRID_MARGIN_SIGMAS 6.0
void gr_hybrid_set_margin(gr_sim *s, double sigmas);

/* Steps per full window (1 for other integrators). Windows are cut at multiples of it, at com
 * resets and at the ends of gr_sim_step calls, so a run is independent of how its steps are
 * split into calls as long as calls end on multiples of it (or where the caller must stop
 * anyway, e.g. at a sample): gr_sim_call_steps (src/core/sim_state.h) does that through the
 * call_steps hook (hybrid_type.c). */
int64_t gr_hybrid_window_steps(const gr_sim *s);

/* Exact restarts (hy_state.c, docs/checkpoints.md): append / read back the hybrid's own state
 * (the save / load hooks: src/core/sim_state.c calls them after the soft-sphere part) between
 * gr_sim_step calls. */
int gr_hybrid_state_io(gr_sim *s, gr_blob_io *io, gr_error *err);

#endif
