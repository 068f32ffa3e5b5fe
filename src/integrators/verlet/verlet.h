/* The soft-sphere integrator ([integrator] kind = verlet, docs/integrator.md): velocity Verlet in
 * kick-drift-kick form with the random force as a mid-step kick (step.c). It keeps no state of
 * its own beyond the core's, so its checkpoint is the core's. The hybrid integrator steps its
 * child simulation of active particles with the same scheme. */
#ifndef GR_VERLET_H
#define GR_VERLET_H

#include <stdint.h>

#include "core/sim_internal.h"

extern const gr_integrator_type gr_integrator_verlet;

/* Advance by nsteps time steps (gr_integrator_type.step). */
int gr_verlet_step(gr_sim *s, int64_t nsteps, gr_error *err);

#endif
