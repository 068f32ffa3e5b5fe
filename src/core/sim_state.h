/* The complete state of a soft-sphere (Verlet) simulation as bytes, for exact restarts
 * (docs/checkpoints.md). Private to the tree: src/io/checkpoint.c and tests use it. */
#ifndef GR_SIM_STATE_H
#define GR_SIM_STATE_H

#include "granule/sim.h"
#include "io/blob.h"

/* GR_OK if this simulation's state can be saved; otherwise GR_EINVAL naming the integrator
 * that cannot (the event-driven and hybrid integrators keep state this file does not know). */
int gr_sim_checkpointable(const gr_sim *s, gr_error *err);

/* Append everything the next gr_sim_step depends on. Call between gr_sim_step calls. */
int gr_sim_save_state(const gr_sim *s, gr_blob *out, gr_error *err);

/* Overwrite the state of `s`, freshly created from the same scene (and with contact tracking
 * switched on if the saved one had it), with a saved one. Checks that N, dim, dt, L, d, mass and
 * the kernel agree bit for bit; on any error `s` must be freed by the caller. */
int gr_sim_load_state(gr_sim *s, gr_blob_reader *in, gr_error *err);

#endif
