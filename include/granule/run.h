/* `granule run` as a library call: warm-up, sampling at a fixed interval, outputs.
 *
 * Writes into the output folder (every file atomically: temporary file, fsync, rename; the
 * multi-frame trajectories grow in place, docs/trajectories.md):
 *   summary.json     SPEC sec. 7 keys, the ledger, the chosen kernel and the resolved scene
 *   temperature.csv  T(t) (2.19) with its running average, warm-up included
 *   blocks.csv       block-averaging analysis of T behind T_stderr (Fig. 2.8)
 *   ledger.csv       the energy ledger at every sample
 *   NAME.meta.json   beside every NAME.csv: what it holds, units, scene, hash, seed (the CSVs
 *                    themselves are plain: pandas.read_csv reads them without options)
 *   scene.ini        the resolved scene (rerun it, or `granule analyse DIR` reads it)
 *   snapshots/ or trajectory.h5  frames every snapshot_every (output.trajectory: extended XYZ
 *                    per frame or multi-frame, or H5MD; ASE, OVITO, MDAnalysis read them)
 *   <observable>.csv one or more per enabled [analysis] observable (docs/analysis.md)
 *   *.png, *.gp      plots and the gnuplot bodies `granule plot DIR` redraws them from;
 *                    snapshot.png / snapshots.png (cairo) when snapshots were written */
#ifndef GRANULE_RUN_H
#define GRANULE_RUN_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "granule/scene.h"
#include "granule/sim.h"
#include "granule/status.h"

typedef struct gr_progress {
    double t, t_end;  /* simulated time now and at the end, s */
    double wall, eta; /* s */
    double particle_steps_per_second;
    /* an event-driven run (events_per_second is its rate; particle-steps mean little there) */
    bool event_driven;
    double events_per_second; /* events processed per wall second of stepping */
    bool warmup;
} gr_progress;

typedef struct gr_run_options {
    bool force; /* overwrite the outputs of an earlier run in the same folder */
    /* called about twice a second of wall time; NULL for none */
    void (*progress)(const gr_progress *p, void *user);
    void *user;
    /* continue the interrupted run in scene->out_dir from its checkpoint (docs/checkpoints.md);
     * the scene must be the one the checkpoint was written with */
    bool resume;
    /* when *stop becomes non-zero (e.g. set by a SIGTERM handler) the run writes a checkpoint at
     * the next step boundary and returns with result.stopped = 1; NULL for none */
    volatile sig_atomic_t *stop;
    /* called when something goes wrong that the run survives (a periodic checkpoint that could
     * not be written, e.g. for lack of space), with the message, when it happens; NULL for none */
    void (*notice)(const char *message, void *user);
} gr_run_options;

#define GR_RUN_STOPPED_WRITE 3

typedef struct gr_run_result {
    double T_mean, T_stderr;
    int T_stderr_converged;
    int64_t samples, steps, collisions;
    double wall_seconds, particle_steps_per_second;
    /* an event-driven run's events processed and their rate per wall second (0 otherwise) */
    bool event_driven;
    int64_t events;
    double events_per_second;
    gr_ledger ledger;
    char kernel[160];
    /* 0 ran to the end (or became unstable); 1 stopped on request, 2 stopped before the
     * scene's wall_limit ran out: a checkpoint was written, resume with gr_run_options.resume;
     * GR_RUN_STOPPED_WRITE (with GR_EIO): an output could not be written (a full disk) and the
     * last checkpoint was kept: resume once there is space */
    int stopped;
    int64_t checkpoints;        /* written by this call */
    double checkpoint_seconds;  /* wall time spent writing them */
    char checkpoint_error[256]; /* first failed periodic checkpoint ("" if none) */
    char notes
        [1600]; /* schedule roundings, the noise windows' warnings; one per line ("" if none) */
} gr_run_result;

/* Run the scene into scene->out_dir. On an unstable run the outputs written so far are kept,
 * summary.json records "status": "unstable" with the diagnosis, and GR_EUNSTABLE is returned.
 * The folder is locked while the run writes it (out_dir/.run.lock, docs/checkpoints.md): a run
 * or resume into a folder another run is writing is refused with GR_EINVAL, naming that run. */
int gr_run(const gr_scene *scene, const gr_run_options *opt, gr_run_result *res, gr_error *err);

#endif
