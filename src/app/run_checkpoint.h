/* Checkpoints of `granule run` (docs/checkpoints.md): what the run driver saves besides the
 * simulation and the observables, and how a run is resumed. Private to src/app/run.c. */
#ifndef GR_RUN_CHECKPOINT_H
#define GR_RUN_CHECKPOINT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/analysis.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "io/checkpoint.h"
#include "io/files.h"
#include "io/trajectory.h"

/* The run driver's own state at a step boundary. */
typedef struct gr_run_ckpt {
    int64_t k_next; /* the next sample to take (samples 0..k_next-1 are written) */
    int64_t per_sample, warm_samples, run_samples; /* checked on resume */
    gr_blocking *blk;                              /* T block averaging */
    int64_t *haff_n, haff_cap; /* cooling runs: T(t) kept for the Haff's-law fit */
    double *haff_t, *haff_T;
    int64_t *next_snap; /* step of the next snapshot */
    int *snap_index;
    gr_file *ft, *fl;     /* temperature.csv and ledger.csv, being streamed */
    gr_traj_writer *traj; /* the trajectory (its frame count is *snap_index) */
    /* with walls only (the periodic runs' checkpoints keep their layout): the walls' force
     * averages and the impulse at the last sample (4 each) */
    int walls; /* the walls' blocks: 4 (6 in 3D), 0 without walls */
    gr_blocking *wall_blk;
    double *wall_prev;
} gr_run_ckpt;

/* Write dir/checkpoint: the resolved scene text, the simulation, the observables and the
 * driver state; the streamed CSVs are flushed and fsync'ed first and their lengths recorded.
 * *seconds (wall) and *bytes report the cost. */
int gr_run_checkpoint_write(const char *dir, const gr_scene *scene, const gr_sim *sim,
                            const gr_observer *obs, const gr_run_ckpt *st, double *seconds,
                            size_t *bytes, gr_error *err);

/* Refuse to start a fresh run over an interrupted one (dir/checkpoint) unless `force`; changes
 * nothing, so it can run before the output folder is checked. */
int gr_run_checkpoint_guard(const char *dir, bool force, gr_error *err);
bool gr_run_checkpoint_present(const char *dir);

/* Delete dir/checkpoint and every partial file NAME.tmpPID in dir and dir/snapshots: where a
 * fresh run starts (after gr_run_checkpoint_guard) and where a run has finished. */
int gr_run_clear_leftovers(const char *dir, gr_error *err);

/* summary.json's status of a run stopped because an output could not be written (a full disk)
 * while its checkpoint was kept: the only status a resume accepts (docs/checkpoints.md). */
#define GR_RUN_STATUS_WRITE_FAILED "write_failed"

/* Open dir's checkpoint for a resume: refuses a folder whose run finished (summary.json), a
 * missing, truncated, corrupt or foreign checkpoint, and a scene that differs from the one the
 * checkpoint was written with (naming the first differing key). On success *buf holds the file
 * (free it after gr_run_resume_state) and scene->source is restored to the original. */
int gr_run_resume_open(const char *dir, gr_scene *scene, void **buf, gr_checkpoint *ck,
                       gr_error *err);

/* Restore the simulation (created from the scene, contact tracking already on if needed),
 * the observables and the driver state; reopen the streamed CSVs and cut them to the length
 * they had at the checkpoint. */
int gr_run_resume_state(const gr_checkpoint *ck, const char *dir, gr_sim *sim, gr_observer *obs,
                        gr_run_ckpt *st, gr_error *err);

/* Compare two resolved scene texts (gr_scene_write); GR_OK if they agree on every key that can
 * change results, else GR_EINVAL naming the first differing key and both values. A key that only
 * one text has (a checkpoint of an older granule, which did not know it) is compared with its
 * default; *defaulted (may be NULL) tells whether that happened. */
int gr_scene_text_compare(const char *checkpoint_text, size_t len, const char *scene_text,
                          bool *defaulted, gr_error *err);

#endif
