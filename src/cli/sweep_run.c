/* The local scheduler: points are handed out in index order to up to `jobs` child processes (and,
 * under MPI, to the other ranks through a serve callback); finished points are skipped. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include "cli/cli.h"
#include "cli/sweep.h"

long sweep_queue_next(sweep_queue *q)
{
    while (q->next < q->s->n_points) {
        long k = q->next++;
        char why[800];
        point_state st = sweep_point_state(q->s, k, q->hash[k], why, sizeof why);
        if (st == POINT_COMPLETED && !q->s->force) {
            fprintf(stderr, "sweep: skipping finished point %ld\n", k);
            q->skipped++;
            continue;
        }
        if (st == POINT_RUNNING || st == POINT_STALE) {
            fprintf(stderr, "sweep: point %ld: %s; running it again\n", k, why);
        }
        return k;
    }
    return -1;
}

void sweep_queue_done(sweep_queue *q, long k, int code, const char *who)
{
    q->run++;
    q->failed += code != EXIT_OK;
    const char *what = sweep_exit_name(code);
    fprintf(stderr, "sweep: point %ld %s%s%s (%ld/%ld)\n", k, what, who ? " on " : "", who ? who : "", q->run + q->skipped,
            q->s->n_points);
}

void sweep_run_local(sweep_queue *q, int jobs, const char *runner, sweep_serve_fn serve, void *ctx)
{
    sweep_child *slot = calloc((size_t)jobs, sizeof *slot);
    int running = 0, remote = 0;
    bool exhausted = false;
    for (;;) {
        while (!exhausted && running < jobs) {
            long k = sweep_queue_next(q);
            if (k < 0) {
                exhausted = true;
                break;
            }
            int free_slot = 0;
            while (slot[free_slot].pid) {
                free_slot++;
            }
            gr_error err = {0};
            if (sweep_point_start(q->s, k, runner, &slot[free_slot], &err)) {
                fprintf(stderr, "granule sweep: point %ld: %s\n", k, err.message);
                sweep_queue_done(q, k, EXIT_FAILED, NULL);
                continue;
            }
            running++;
        }
        if (serve) {
            remote = serve(ctx, q);
            exhausted = q->next >= q->s->n_points;
        }
        if (running == 0 && remote == 0 && exhausted) {
            break;
        }
        if (running == 0) { /* only remote workers left: poll them gently */
            nanosleep(&(struct timespec){.tv_nsec = 2000000}, NULL);
            continue;
        }
        int ws = 0;
        pid_t pid = waitpid(-1, &ws, serve ? WNOHANG : 0);
        if (pid < 0 && errno == EINTR) {
            continue;
        }
        if (pid < 0) {
            fprintf(stderr, "granule sweep: waitpid: %s\n", strerror(errno));
            break;
        }
        if (pid == 0) {
            nanosleep(&(struct timespec){.tv_nsec = 2000000}, NULL);
            continue;
        }
        for (int i = 0; i < jobs; i++) {
            if (slot[i].pid == pid) {
                long k = slot[i].k;
                int code = sweep_point_finish(q->s, runner, &slot[i], ws);
                sweep_queue_done(q, k, code, serve ? "rank 0" : NULL);
                running--;
            }
        }
    }
    free(slot);
}
