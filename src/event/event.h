/* The event-driven integrator ([integrator] kind = event, [model] normal = hard_sphere):
 * instantaneous collisions (2.1, 2.2, 2.10) between free flights driven by the random force.
 * Called by src/core/sim.c and src/core/step.c; the state lives behind gr_sim.ev. */
#ifndef GR_EVENT_H
#define GR_EVENT_H

#include <stdint.h>

#include "core/sim_internal.h"

/* Build the event state after positions, velocities and coefficients are set. */
int gr_event_init(gr_sim *s, gr_error *err);
/* Advance by nsteps * s->dt of simulated time; on return s->x, vx (y, vy) hold the state at that
 * time and s->step has advanced by nsteps. */
int gr_event_step(gr_sim *s, int64_t nsteps, gr_error *err);
void gr_event_free(gr_sim *s);

#endif
