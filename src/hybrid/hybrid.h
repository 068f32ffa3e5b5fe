/* The hybrid integrator ([integrator] kind = hybrid): free flight event-driven,
 * contacts integrated by the soft-sphere model (docs/hybrid.md).
 * Called by src/core/sim.c and src/core/step.c; the state lives behind gr_sim.hy. */
#ifndef GR_HYBRID_H
#define GR_HYBRID_H

#include <stdint.h>

#include "core/sim_internal.h"

/* Build the event state after positions, velocities and coefficients are set. */
int gr_hybrid_init(gr_sim *s, gr_error *err);
/* Advance by nsteps * s->dt of simulated time; on return s->x, vx (y, vy) hold the state at that
 * time and s->step has advanced by nsteps. */
int gr_hybrid_step(gr_sim *s, int64_t nsteps, gr_error *err);
void gr_hybrid_free(gr_sim *s);

#endif
