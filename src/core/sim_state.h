/* The complete state of a simulation as bytes, for exact restarts (docs/checkpoints.md): the
 * core's part, then the integrator's own (its save / load hooks). Private to the tree:
 * src/app/run_checkpoint.c writes the bytes to a file, tests use it. */
#ifndef GR_SIM_STATE_H
#define GR_SIM_STATE_H

#include "granule/sim.h"
#include "core/blob.h"

/* GR_OK if this simulation's state can be saved (every registered integrator can); otherwise
 * GR_EINVAL with the reason. */
int gr_sim_checkpointable(const gr_sim *s, gr_error *err);

/* How many steps the next gr_sim_step call should take when the caller would like `want` and
 * must stop after `todo` (e.g. at the next sample): min(want, todo), adjusted by the integrator's
 * call_steps hook (event: widened to what a call interrupted by a stop still owes; hybrid: moved
 * to a window boundary, or todo) so that the results do not depend on how the steps are split
 * (which run.c chooses from the wall clock). */
int64_t gr_sim_call_steps(const gr_sim *s, int64_t want, int64_t todo);

/* Append everything the next gr_sim_step depends on. Call between gr_sim_step calls. */
int gr_sim_save_state(const gr_sim *s, gr_blob *out, gr_error *err);

/* Overwrite the state of `s`, freshly created from the same scene (and with contact tracking
 * switched on if the saved one had it), with a saved one. Checks that N, dim, dt, L, d, mass and
 * the kernel agree bit for bit; on any error `s` must be freed by the caller. */
int gr_sim_load_state(gr_sim *s, gr_blob_reader *in, gr_error *err);

#endif
