/* MPI distribution of a sweep (meson -Dmpi=enabled): MPI only hands out point indices, it never
 * carries results. Rank 0 is the dispatcher: it skips finished points, answers each worker's
 * request with the next point (a worker asks again when its point is done, so long runs do not
 * hold up short ones), runs points itself in between, and collects when every rank is done.
 * Every point is the same child process writing the same folder and manifest as a local or
 * batch-array run, so the results are those of a serial sweep; the output folder must be on a
 * file system all ranks see. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/report.h"
#include "app/sweep.h"
#include "io/files.h"

int sweep_mpi_launched(const char **var)
{
    static const char *const size_vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE",
                                            "MPI_LOCALNRANKS"};
    for (size_t i = 0; i < sizeof size_vars / sizeof size_vars[0]; i++) {
        const char *v = getenv(size_vars[i]);
        if (v && atoi(v) > 0) {
            *var = size_vars[i];
            return atoi(v);
        }
    }
    if (getenv("PMIX_RANK")) { /* srun --mpi=pmix: the size is known only after MPI_Init */
        *var = "PMIX_RANK";
        const char *n = getenv("SLURM_NTASKS");
        return n && atoi(n) > 0 ? atoi(n) : 2;
    }
    *var = NULL;
    return 0;
}

#ifdef GR_HAVE_MPI
#include <mpi.h>

enum { TAG_REQUEST = 1, TAG_POINT = 2 };

bool sweep_mpi_available(void) { return true; }

typedef struct dispatcher {
    int active; /* workers that have not been told to stop */
} dispatcher;

/* Rank 0: answer every pending request; a request carries the worker's last point and its exit
 * code (point -1 on the first request). */
static int serve(void *ctx, sweep_queue *q)
{
    dispatcher *d = ctx;
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_REQUEST, MPI_COMM_WORLD, &flag, &st);
        if (!flag) {
            break;
        }
        long msg[2];
        MPI_Recv(msg, 2, MPI_LONG, st.MPI_SOURCE, TAG_REQUEST, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (msg[0] >= 0) {
            char who[32];
            snprintf(who, sizeof who, "rank %d", st.MPI_SOURCE);
            sweep_queue_done(q, msg[0], (int)msg[1], who);
        }
        long k = sweep_queue_next(q);
        MPI_Send(&k, 1, MPI_LONG, st.MPI_SOURCE, TAG_POINT, MPI_COMM_WORLD);
        d->active -= k < 0;
    }
    return d->active;
}

int sweep_mpi_run(sweep *s, const uint64_t *hash, const double *guess, int *argc, char ***argv)
{
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited && MPI_Init(argc, argv) != MPI_SUCCESS) {
        app_error("sweep: MPI_Init failed");
        return EXIT_FAILED;
    }
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    char runner[64];
    snprintf(runner, sizeof runner, "mpi rank %d of %d", rank, size);
    int rc = EXIT_OK;
    if (rank == 0) {
        gr_error err = {0};
        if (gr_output_dir_prepare(s->out, GR_OUTPUT_SWEEP, s->force, &err)) {
            app_error("sweep: %s", err.message);
            MPI_Abort(MPI_COMM_WORLD, app_exit_code(err.code));
        }
        char why[900];
        if (sweep_foreign_points(s, s->force, why, sizeof why) < 0) {
            app_error("sweep: %s", why);
            MPI_Abort(MPI_COMM_WORLD, EXIT_REFUSED);
        }
        app_note("sweep: %ld points (%d keys x %d seeds) over %d MPI ranks, into %s\n", s->n_points,
                 s->n_keys, s->n_seeds, size, s->out);
        sweep_queue q = {.s = s, .hash = hash, .guess = guess, .jobs = size};
        sweep_queue_start(&q);
        dispatcher d = {.active = size - 1};
        sweep_run_local(&q, 1, runner, serve, &d);
        long bad = 0;
        rc = sweep_collect(s, hash, &bad);
        sweep_queue_report(&q);
        rc = rc ? rc : bad ? EXIT_FAILED : EXIT_OK;
    } else {
        long msg[2] = {-1, 0};
        for (;;) {
            long k;
            MPI_Send(msg, 2, MPI_LONG, 0, TAG_REQUEST, MPI_COMM_WORLD);
            MPI_Recv(&k, 1, MPI_LONG, 0, TAG_POINT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (k < 0) {
                break;
            }
            msg[0] = k;
            msg[1] = sweep_point_run(s, k, runner);
        }
    }
    MPI_Finalize();
    return rc;
}

#else

bool sweep_mpi_available(void) { return false; }

int sweep_mpi_run(sweep *s, const uint64_t *hash, const double *guess, int *argc, char ***argv)
{
    (void)s;
    (void)hash;
    (void)argc;
    (void)argv;
    app_error("sweep: this granule was built without MPI; rebuild with meson setup -Dmpi=enabled "
              "(Debian: apt-get install "
              "libopenmpi-dev openmpi-bin), or run the points as a batch array (--point K, "
              "docs/cluster.md)");
    return EXIT_REFUSED;
}

#endif
