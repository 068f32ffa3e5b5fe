/* The schedule of a run in whole steps: samples, warm-up, snapshots and checkpoints.
 *
 * Every interval becomes a whole number of time steps, every duration a whole number of sample
 * intervals, so the run does what the scene says (docs/scene-keys.md, "Schedule"):
 *   - run.sample_every and output.snapshot_every are rounded to the nearest whole number of
 *     steps of dt; shorter than dt is refused; a rounding that moves the interval by more than
 *     GR_SCHEDULE_NOTE (1 %) is stated in `note` (and in summary.json's warnings);
 *   - run.warmup and run.duration must be whole numbers of run.sample_every (to 1e-6), and the
 *     duration must hold at least one sample: otherwise refused, naming the key and what is allowed;
 *   - run.checkpoint_every is counted in samples, rounded up ("at the next sample"); longer than
 *     the run means no periodic checkpoint;
 *   - at most GR_SCHEDULE_MAX_STEPS steps in all (dt far too small for the run is refused).
 * Snapshots do not depend on samples: one every snap_every steps from step 0. */
#ifndef GR_IO_RUN_SCHEDULE_H
#define GR_IO_RUN_SCHEDULE_H

#include <stddef.h>
#include <stdint.h>

#include "granule/scene.h"
#include "granule/status.h"

#define GR_SCHEDULE_NOTE 0.01
#define GR_SCHEDULE_MAX_STEPS 4503599627370496.0 /* 2^52: exact in a double */

typedef struct gr_run_schedule {
    int64_t per_sample;   /* steps between samples */
    int64_t warm_samples; /* samples of the warm-up (not statistics) */
    int64_t run_samples;  /* samples of the sampling phase */
    int64_t snap_every;   /* steps between snapshots; 0 = none */
    int64_t ckpt_samples; /* samples between periodic checkpoints; 0 = none */
} gr_run_schedule;

/* GR_OK, or GR_EINVAL naming the key, its value and the allowed range. `note` receives the
 * roundings worth stating ("" when none). */
int gr_run_schedule_make(const gr_scene *s, double dt, gr_run_schedule *out, char *note,
                         size_t note_len, gr_error *err);

#endif
