/* The run driver's stages (gr_run, src/app/run.c): one context carried through
 *
 *   set-up     run.c       resume or prepare the folder, create the simulation, observables,
 *                          schedule, streamed tables and trajectory
 *   warm-up    run_loop.c  step to each warm-up sample, record T and the ledger
 *   sampling   run_loop.c  the same, plus block averages, observables, checkpoints, progress
 *   stop       run_loop.c  a stop request (signal, wall budget) ends in a checkpoint
 *   finish     run_finish.c  commit the tables, plots, observables, summary.json; the status
 *
 * Private to src/app/run*.c. */
#ifndef GR_RUN_INTERNAL_H
#define GR_RUN_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/run.h"
#include "app/run_checkpoint.h"
#include "app/run_schedule.h"

typedef struct gr_run_ctx {
    /* inputs */
    const gr_scene *scene; /* the caller's, or `resumed` */
    gr_scene resumed;
    const gr_run_options *opt;
    gr_run_result *res;
    gr_error *err;
    bool resume;
    const char *dir;
    int lock_fd; /* RUN_LOCK in dir, held while the run writes there (io/dir_lock.h); -1 if none */
    /* the run */
    gr_sim *sim;
    gr_observer *obs;
    double dt;
    gr_run_schedule plan;
    uint64_t hash;
    gr_checkpoint ck; /* resume: the checkpoint read, in ck_buf */
    void *ck_buf;
    /* outputs being written */
    gr_file ft, fl;           /* temperature.csv, ledger.csv */
    gr_blocking blk;          /* T block averages */
    int64_t haff_n, haff_cap; /* an undriven (cooling) run keeps its T(t) for the Haff's-law fit */
    double *haff_t, *haff_T;
    int64_t next_snap;
    int snap_index;
    gr_traj_writer traj;
    /* walls (docs/systems-walls-gravity.md): the mean normal force on each wall over each sample
     * interval, from the impulse it took (gr_sim_wall_impulse: x at 0, L, then y, then z), block-averaged
     * while sampling; wall_prev the impulse at the last sample */
    gr_blocking wall_blk[6];
    double wall_prev[6];
    gr_run_ckpt ckst; /* the driver state a checkpoint keeps */
    /* checkpoints and stopping */
    gr_error ck_err; /* why this run cannot checkpoint, if it cannot */
    bool can_checkpoint;
    int64_t steps_at_start;
    double t_enter, start, stepping, last_report, last_ckpt, chunk_wall, ckpt_cost;
    int64_t chunk, chunk_cap; /* steps per gr_sim_step call, adapted to about 0.1 s */
    int stop;                 /* 1: signal, 2: wall-clock budget */
    bool stopped_early;
    /* outcome */
    int rc;
    const char *status;
    char diagnosis[800];
    gr_error step_err;
} gr_run_ctx;

/* run.c */
double gr_run_now(void);
/* GRANULE_TEST_PAUSE_AT_STEP = K: once step K is passed, wait for a stop request or a kill. */
void gr_run_test_pause(const gr_sim *sim, const gr_run_options *opt);
void gr_run_csv_header(gr_file *f, const char *what, const gr_scene *s, uint64_t hash);
/* Close a streamed table without moving it into place (a resume continues it). */
void gr_run_stream_leave(gr_file *f);

/* run_loop.c: samples k_from..k_to (warm-up: up to plan.warm_samples; sampling: the rest);
 * false when the run must not go on (a failure, an unstable run or a stop request). */
bool gr_run_samples(gr_run_ctx *c, int64_t k_from, int64_t k_to);
/* After the loop: a stop request between samples writes a checkpoint; true when the run ended
 * there (c->rc is then its status), false when the outputs must be finished. */
bool gr_run_stop(gr_run_ctx *c);

/* run_finish.c: results, the tables, plots, observables and summary.json; the return status. */
int gr_run_finish(gr_run_ctx *c);

#endif
