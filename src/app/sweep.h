/* granule sweep internals: the sweep file and its points (sweep_file.c), one point's run and its
 * manifest (sweep_point.c), the local scheduler (sweep_run.c), MPI distribution (sweep_mpi.c) and
 * the merge with the power-law fits (sweep_collect.c). Whichever way a point is run (serial, forked,
 * an MPI rank, a batch-array task) it is the same child process writing the same folder, so the
 * results do not depend on how the sweep was distributed. */
#ifndef GR_CLI_SWEEP_H
#define GR_CLI_SWEEP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/types.h>

#include "granule/scene.h"

#define SWEEP_MAX_KEYS 8
#define SWEEP_MAX_VALUES 64
#define SWEEP_MAX_SETS 64
#define SWEEP_MAX_LINKED 8  /* keys varied together: [vary] a+b = 1/2, 3/4 */
#define SWEEP_VALUE_LEN 128 /* one [vary] value, linked parts included */
#define SWEEP_MAX_OVERRIDES (SWEEP_MAX_SETS + SWEEP_MAX_LINKED * SWEEP_MAX_KEYS + 1)
#define SWEEP_MAX_POINTS 100000L
#define SWEEP_MAX_JOBS 4096 /* --jobs of sweep and reproduce: 1..SWEEP_MAX_JOBS */

typedef struct sweep {
    char file[1024]; /* the sweep file as given */
    char scene[1024], out[1024];
    int jobs;
    int n_seeds;
    unsigned long long seeds[SWEEP_MAX_VALUES];
    bool seeds_given; /* [sweep] seeds was written */
    int seed_key; /* the [vary] key that is run.seed (then it names every point's seed), or -1 */
    int n_keys;
    char key[SWEEP_MAX_KEYS][128];
    int n_values[SWEEP_MAX_KEYS];
    char value[SWEEP_MAX_KEYS][SWEEP_MAX_VALUES][SWEEP_VALUE_LEN];
    int n_sets;
    char set[SWEEP_MAX_SETS][256];
    long n_points;
    bool force; /* rerun finished points too */
    char error[600];
} sweep;

/* --- sweep_file.c --- */
/* Parse FILE into s (scene resolved relative to FILE's folder). EXIT_OK, or EXIT_REFUSED with the
 * reason printed (file, line, key, allowed values). */
int sweep_load(sweep *s, const char *file);
/* Point k: the value index of each varied key (last key fastest) and the seed index (fastest). */
void sweep_decode(const sweep *s, long k, int idx[SWEEP_MAX_KEYS], int *seed);
/* The seed point k runs with: its [vary] run.seed value, or its entry of [sweep] seeds. */
unsigned long long sweep_point_seed(const sweep *s, long k);
/* The --set overrides of point k: [set] lines, then the varied keys, then run.seed. */
int sweep_overrides(const sweep *s, long k, char store[][256], const char **ptrs);
/* Load point k's scene (the sweep's scene with the point's overrides). */
int sweep_point_scene(const sweep *s, long k, gr_scene *sc, gr_error *err);
void sweep_point_dir(const sweep *s, long k, char *dir, size_t len);
/* Point folders in s->out numbered beyond this sweep's points (left by another sweep file):
 * refused (-1, why says so) unless force, which deletes them; otherwise how many were deleted. */
int sweep_foreign_points(const sweep *s, bool force, char *why, size_t len);
/* --list: one line per point, index and overrides. */
void sweep_list(const sweep *s, FILE *f);

/* --- sweep_point.c --- */
typedef enum {
    POINT_MISSING,   /* never started (no manifest) */
    POINT_RUNNING,   /* started, not finished, and no process holds its claim: killed */
    POINT_COMPLETED, /* finished with these settings: never rerun */
    POINT_FAILED,    /* the run failed or was refused; the manifest holds the error */
    POINT_UNSTABLE,  /* the run stopped as unstable (exit 3); outputs kept */
    POINT_STALE,     /* finished, but with other settings (the scene hash differs) */
    POINT_CLAIMED,   /* started, not finished, and a live process holds its claim: running now */
    POINT_STOPPED, /* stopped by a signal or wall limit with a checkpoint: the next run continues it */
} point_state;

/* How a point run ended, as point.json and the progress lines name it (EXIT_* of cli/cli.h). */
const char *sweep_exit_name(int code);
const char *sweep_state_name(point_state st);
/* The state of point k on disk; why gets the manifest's error or the hash mismatch. */
point_state sweep_point_state(const sweep *s, long k, uint64_t hash, char *why, size_t len);

/* A point being run in a child process. */
typedef struct sweep_child {
    pid_t pid;
    long k;
    int fd;    /* read end of the pipe carrying the child's error message */
    double t0; /* monotonic start */
    char started[32];
    uint64_t hash;
    double
        cpu_before; /* CPU seconds of earlier sessions of this point (it continues a checkpoint) */
    double cpu;     /* CPU seconds of this child (user + system, from wait4) */
    int lock_fd;    /* the claim on the point's folder (its .lock), held until the final manifest */
} sweep_child;

/* sweep_point_start's answers when it started nothing (besides GR_OK and the GR_E* errors) */
enum {
    SWEEP_CLAIMED_ELSEWHERE = 1, /* a live process runs the point (err names it) */
    SWEEP_FINISHED_ELSEWHERE = 2 /* another process finished it since its state was read */
};

/* Prepare point k's folder, claim it, write its manifest (status "running") and fork the child
 * running it. runner names who runs it ("local", "mpi rank 1 of 2", "array SLURM_ARRAY_TASK_ID=3").
 * GR_OK, SWEEP_CLAIMED_ELSEWHERE / SWEEP_FINISHED_ELSEWHERE, or an error (nothing forked). */
int sweep_point_start(const sweep *s, long k, const char *runner, sweep_child *c, gr_error *err);
/* After the child's exit (wait_status and usage from wait4): write the final manifest, with the
 * point's CPU seconds over all its sessions; returns the point's exit code (EXIT_OK, EXIT_FAILED,
 * EXIT_REFUSED, EXIT_UNSTABLE). */
int sweep_point_finish(const sweep *s, const char *runner, sweep_child *c, int wait_status,
                       const struct rusage *usage);
/* CPU seconds point k has cost so far (its manifest's cpu_seconds), NAN if not recorded. */
double sweep_point_cpu(const sweep *s, long k);
/* A rough prediction of a point's CPU seconds from its scene (particle-steps times a default cost
 * per particle-step), used for ETAs until finished points calibrate it. */
double sweep_point_cost_guess(const gr_scene *sc);
/* start + wait + finish: the point's EXIT_* code, or SWEEP_LEFT when a live process holds its
 * claim (said on stderr; nothing done). */
enum { SWEEP_LEFT = -1 };
int sweep_point_run(const sweep *s, long k, const char *runner);

/* --- sweep_run.c --- */
typedef struct sweep_queue {
    const sweep *s;
    const uint64_t *hash; /* scene hash of every point */
    const double *guess;  /* predicted CPU seconds of every point (NULL: no ETA) */
    long next;
    long skipped, run, failed;
    long elsewhere;              /* points left to another process that holds their claim */
    double cpu_done, guess_done; /* finished points: measured CPU s and their prediction */
    double guess_left;           /* prediction for the points not finished */
    long finished;               /* points completed, in this run or before */
    long stopped;                /* points stopped by a signal or a wall limit, with a checkpoint */
    int jobs;
} sweep_queue;

/* Set by SIGINT/SIGTERM in the sweep process (cmd_sweep.c): start no new point, pass the stop to
 * the running ones (each writes its checkpoint) and wait for them. */
#include <signal.h>
extern volatile sig_atomic_t sweep_stop_requested;

/* The next point to run (finished points are skipped with a log line), or -1 when none is left. */
long sweep_queue_next(sweep_queue *q);
/* Record a finished point's exit code: log line with the CPU time spent and the ETA, counters. */
void sweep_queue_done(sweep_queue *q, long k, int code, const char *who);
/* Before running: sum the predictions, count the points finished earlier with their CPU time, and
 * print the progress line. */
void sweep_queue_start(sweep_queue *q);
/* After running: the stdout line "OUT/sweep.csv: N points, R run now, S already finished, F failed"
 * (and how many were left to other processes). */
void sweep_queue_report(const sweep_queue *q);
/* One line on stderr: points finished, CPU-hours spent and, scaled by how the finished points
 * compare with their prediction, the CPU-hours left and the wall time at q->jobs parallel runs. */
void sweep_queue_progress(const sweep_queue *q);
/* Hands out points to remote workers while the local loop runs; returns how many workers are
 * still busy (0 when none or all are done). */
typedef int (*sweep_serve_fn)(void *ctx, sweep_queue *q);
/* Run the queue with jobs local children (and serve remote workers if serve is not NULL). */
void sweep_run_local(sweep_queue *q, int jobs, const char *runner, sweep_serve_fn serve, void *ctx);

/* --- sweep_collect.c --- */
/* Read every point folder, write OUT/sweep.csv, OUT/exponents.csv (+ plot); report missing and
 * failed points on stderr. *n_bad = number of points not completed. EXIT_OK or EXIT_FAILED. */
int sweep_collect(const sweep *s, const uint64_t *hash, long *n_bad);

/* --- sweep_mpi.c --- */
/* The number of ranks if this process was started by an MPI launcher (mpirun, mpiexec, srun),
 * else 0; var names the variable seen. */
int sweep_mpi_launched(const char **var);
/* Distribute the points over the ranks (rank 0 hands them out and runs some itself, printing the
 * CPU-hours spent and left from guess), then rank 0 collects. Returns this rank's exit code. */
int sweep_mpi_run(sweep *s, const uint64_t *hash, const double *guess, int *argc, char ***argv);
/* True when built with MPI. */
bool sweep_mpi_available(void);

/* Wall-clock time as ISO 8601 UTC, and a monotonic clock in seconds. */
void sweep_now_iso(char out[32]);
double sweep_monotonic(void);

#endif
