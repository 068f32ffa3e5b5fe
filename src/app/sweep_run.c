/* The local scheduler: points are handed out in index order to up to `jobs` child processes (and,
 * under MPI, to the other ranks through a serve callback); finished points are skipped, and so
 * are points another process is running (their folder's claim, sweep_point.c). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>

#include "app/report.h"
#include "app/sweep.h"

/* Point k is finished: move its prediction from "left" to "done", with its measured CPU time. */
static void account(sweep_queue *q, long k)
{
    if (!q->guess) {
        return;
    }
    double cpu = sweep_point_cpu(q->s, k);
    q->guess_left -= q->guess[k];
    if (isfinite(cpu)) {
        q->cpu_done += cpu;
        q->guess_done += q->guess[k];
    }
}

void sweep_queue_start(sweep_queue *q)
{
    if (!q->guess) {
        return;
    }
    for (long k = 0; k < q->s->n_points; k++) {
        q->guess_left += q->guess[k];
    }
    for (long k = 0; k < q->s->n_points && !q->s->force; k++) {
        char why[800];
        if (sweep_point_state(q->s, k, q->hash[k], why, sizeof why) == POINT_COMPLETED) {
            q->finished++;
            account(q, k);
        }
    }
    sweep_queue_progress(q);
}

void sweep_queue_progress(const sweep_queue *q)
{
    if (!q->guess) {
        return;
    }
    /* the finished points calibrate the prediction (the machine, the load, the integrator) */
    double scale = q->guess_done > 0.0 && q->cpu_done > 0.0 ? q->cpu_done / q->guess_done : 1.0;
    double left = q->finished >= q->s->n_points ? 0.0 : fmax(0.0, q->guess_left) * scale / 3600.0;
    int jobs = q->jobs > 0 ? q->jobs : 1;
    app_note("sweep: %ld/%ld points finished; %.3g CPU-h spent on them, about %.3g CPU-h left "
             "(%.3g h of wall time at %d "
             "parallel run%s%s)\n",
             q->finished, q->s->n_points, q->cpu_done / 3600.0, left, left / jobs, jobs,
             jobs == 1 ? "" : "s",
             q->guess_done > 0.0 ? "" : "; a first guess until a point finishes");
}

long sweep_queue_next(sweep_queue *q)
{
    while (q->next < q->s->n_points) {
        long k = q->next++;
        char why[800];
        point_state st = sweep_point_state(q->s, k, q->hash[k], why, sizeof why);
        if (st == POINT_COMPLETED && !q->s->force) {
            app_note("sweep: skipping finished point %ld\n", k);
            q->skipped++;
            continue;
        }
        if (st == POINT_CLAIMED) {
            app_note("sweep: point %ld is %s; left to it\n", k, why);
            q->elsewhere++;
            continue;
        }
        if (st == POINT_RUNNING || st == POINT_STALE) {
            app_note("sweep: point %ld: %s; running it again\n", k, why);
        }
        return k;
    }
    return -1;
}

volatile sig_atomic_t sweep_stop_requested = 0;

void sweep_queue_done(sweep_queue *q, long k, int code, const char *who)
{
    if (code == SWEEP_LEFT) { /* a worker found it claimed by another process (and said so) */
        q->elsewhere++;
        return;
    }
    q->run++;
    const bool stopped =
        code == EXIT_STOPPED || code == EXIT_WALL_LIMIT || code == EXIT_WRITE_FAILED;
    q->stopped += stopped;
    q->failed += code != EXIT_OK && !stopped;
    const char *what = sweep_exit_name(code);
    app_note("sweep: point %ld %s%s%s (%ld/%ld)\n", k, what, who ? " on " : "", who ? who : "",
             q->run + q->skipped, q->s->n_points);
    if (code == EXIT_OK) {
        q->finished++;
        account(q, k);
    }
    sweep_queue_progress(q);
}

void sweep_run_local(sweep_queue *q, int jobs, const char *runner, sweep_serve_fn serve, void *ctx)
{
    sweep_child *slot = calloc((size_t)jobs, sizeof *slot);
    int running = 0, remote = 0;
    bool exhausted = false, passed_on = false;
    for (;;) {
        if (sweep_stop_requested && !passed_on) {
            /* a signal to the sweep alone (kill PID) reaches its runs too; one from a terminal
             * (Ctrl-C, to the process group) already did, and a second one is harmless */
            for (int i = 0; i < jobs; i++) {
                if (slot[i].pid) {
                    kill(slot[i].pid, SIGTERM);
                }
            }
            passed_on = true;
        }
        exhausted |= sweep_stop_requested != 0;
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
            int rc = sweep_point_start(q->s, k, runner, &slot[free_slot], &err);
            if (rc == SWEEP_CLAIMED_ELSEWHERE) {
                app_note("sweep: %s\n", err.message);
                q->elsewhere++;
                continue;
            }
            if (rc == SWEEP_FINISHED_ELSEWHERE) {
                app_note("sweep: skipping point %ld, finished by another process meanwhile\n", k);
                q->skipped++;
                q->finished++;
                account(q, k);
                continue;
            }
            if (rc) {
                app_note("granule sweep: point %ld: %s\n", k, err.message);
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
        struct rusage ru = {0};
        pid_t pid = wait4(-1, &ws, serve ? WNOHANG : 0, &ru);
        if (pid < 0 && errno == EINTR) {
            continue;
        }
        if (pid < 0) {
            app_note("granule sweep: waitpid: %s\n", strerror(errno));
            break;
        }
        if (pid == 0) {
            nanosleep(&(struct timespec){.tv_nsec = 2000000}, NULL);
            continue;
        }
        for (int i = 0; i < jobs; i++) {
            if (slot[i].pid == pid) {
                long k = slot[i].k;
                int code = sweep_point_finish(q->s, runner, &slot[i], ws, &ru);
                sweep_queue_done(q, k, code, serve ? "rank 0" : NULL);
                running--;
            }
        }
    }
    free(slot);
}

void sweep_queue_report(const sweep_queue *q)
{
    app_result("%s/sweep.csv: %ld points, %ld run now, %ld already finished, %ld failed", q->s->out,
               q->s->n_points, q->run, q->skipped, q->failed);
    if (q->stopped) {
        app_result(", %ld stopped with a checkpoint", q->stopped);
    }
    if (q->elsewhere) {
        app_result(", %ld left to other processes running them", q->elsewhere);
    }
    app_result("\n");
}
