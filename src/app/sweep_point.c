/* One sweep point: its folder OUT/pNNNN, its manifest point.json (what was run, by whom, where,
 * when, and how it ended) and the child process that runs it. A point whose manifest says
 * "completed" for the same scene hash, beside a completed summary.json, is finished and never
 * rerun; anything else (missing, killed while running, stopped, failed, unstable, other settings)
 * is run. A point whose folder holds a checkpoint (written every run.checkpoint_every /
 * checkpoint_wall, or when SIGTERM/SIGINT reached the run) continues from it, exactly as
 * `granule run --resume` would; a checkpoint that is refused (corrupt, other settings) is
 * discarded and the point starts again, with a note on stderr.
 *
 * A point is claimed before anything is written to its folder: an exclusive flock on
 * pNNNN/.point.lock (io/dir_lock.h), held until its final manifest is written. Two sweeps over one folder (a second
 * `granule sweep` or `reproduce` to use more cores, overlapping array tasks, two machines sharing
 * the folder) then share out the points: a point claimed by a live process is left to it, and
 * its folder is never written by two runs at once. The run inherits the claim, so it stays held
 * while the run writes its checkpoint even if the sweep itself was killed. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app/report.h"
#include "app/sweep.h"
#include "granule/run.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/checkpoint.h"
#include "io/dir_lock.h"
#include "io/files.h"
#include "io/plot.h"
#include "scene/scene_json.h"
#include "io/summary_read.h"

#define POINT_LOCK ".point.lock" /* the claim on a point folder */

void sweep_now_iso(char out[32])
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    struct tm tm;
    gmtime_r(&ts.tv_sec, &tm);
    char base[24];
    strftime(base, sizeof base, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(out, 32, "%.19s.%03dZ", base, (int)(ts.tv_nsec / 1000000L) % 1000);
}

double sweep_monotonic(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *sweep_exit_name(int code)
{
    return code == EXIT_OK         ? "completed"
           : code == EXIT_UNSTABLE ? "unstable"
           : code == EXIT_REFUSED  ? "refused"
           : code == EXIT_STOPPED || code == EXIT_WALL_LIMIT || code == EXIT_WRITE_FAILED
               ? "stopped"
               : "failed";
}

const char *sweep_state_name(point_state st)
{
    static const char *const names[] = {"missing",  "running", "completed", "failed",
                                        "unstable", "stale",   "running",   "stopped"};
    return names[st];
}

static const char *json_string(const cJSON *j, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(j, name);
    return cJSON_IsString(v) ? v->valuestring : NULL;
}

/* A point whose hash differs may still have run this physics: written by an older granule that
 * did not know keys added since (the hash covers every key). Compare its recorded scene. */
static bool same_physics(const sweep *s, long k, const char *dir, char *why, size_t len)
{
    gr_scene sc;
    gr_error err = {0};
    if (sweep_point_scene(s, k, &sc, &err)) {
        snprintf(why, len, "%.300s", err.message);
        return false;
    }
    cJSON *sum = gr_summary_read(dir, &err);
    bool same = sum && gr_scene_json_compatible(cJSON_GetObjectItem(sum, "scene"), &sc, why, len);
    if (!sum) {
        snprintf(why, len, "no summary.json to compare");
    }
    cJSON_Delete(sum);
    return same;
}

/* The state on disk; probe: look at the claim of a point whose manifest says running (a process
 * must not probe a claim it holds: where flock is emulated by POSIX locks, as on NFS, closing the
 * probe would drop its own claim). */
static point_state state_of(const sweep *s, long k, uint64_t hash, char *why, size_t len,
                            bool probe)
{
    char dir[1100], path[1200], want[20];
    sweep_point_dir(s, k, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/point.json", dir);
    snprintf(want, sizeof want, "%016llx", (unsigned long long)hash);
    why[0] = 0;
    char diff[400] = "";
    gr_error jerr = {0};
    cJSON *m = gr_json_read(path, &jerr); /* NULL: missing or unreadable, i.e. never run */
    const char *status = json_string(m, "status"), *have = json_string(m, "scene_hash");
    point_state st;
    if (!m || !status) {
        st = POINT_MISSING;
    } else if ((!have || strcmp(have, want) != 0) &&
               (strcmp(status, "completed") != 0 || !same_physics(s, k, dir, diff, sizeof diff))) {
        snprintf(why, len, "run with other settings (scene hash %s, now %s%s%s)",
                 have ? have : "none", want, diff[0] ? "; " : "", diff);
        st = POINT_STALE;
    } else if (!strcmp(status, "running")) {
        char holder[400] = "";
        bool held = probe && gr_dir_lock_held(dir, POINT_LOCK, holder, sizeof holder);
        if (held) {
            snprintf(why, len, "being run by %s", holder[0] ? holder : "another process");
        } else {
            snprintf(why, len, "started %s on %s, not finished, and no process runs it (killed)",
                     json_string(m, "started") ? json_string(m, "started") : "?",
                     json_string(m, "host") ? json_string(m, "host") : "?");
        }
        st = held ? POINT_CLAIMED : POINT_RUNNING;
    } else if (!strcmp(status, "completed")) {
        gr_error err = {0};
        cJSON *sum = gr_summary_read(dir, &err);
        const char *ss = json_string(sum, "status");
        st = ss && !strcmp(ss, "completed") ? POINT_COMPLETED : POINT_FAILED;
        if (st == POINT_FAILED) {
            snprintf(why, len, "point.json says completed but %s/summary.json does not", dir);
        }
        cJSON_Delete(sum);
    } else {
        const char *e = json_string(m, "error");
        snprintf(why, len, "%s", e ? e : status);
        st = !strcmp(status, "unstable")  ? POINT_UNSTABLE
             : !strcmp(status, "stopped") ? POINT_STOPPED
                                          : POINT_FAILED;
    }
    cJSON_Delete(m);
    return st;
}

point_state sweep_point_state(const sweep *s, long k, uint64_t hash, char *why, size_t len)
{
    return state_of(s, k, hash, why, len, true);
}

static void write_manifest(const sweep *s, long k, const char *dir, const char *runner,
                           const sweep_child *c, const char *finished, double wall,
                           const char *status, int code, const char *error)
{
    int idx[SWEEP_MAX_KEYS] = {0}, seed;
    sweep_decode(s, k, idx, &seed);
    char store[SWEEP_MAX_OVERRIDES][256];
    const char *ptrs[SWEEP_MAX_OVERRIDES];
    int n_over = sweep_overrides(s, k, store, ptrs);
    char hash[20], host[256] = "unknown";
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)c->hash);
    gethostname(host, sizeof host - 1);

    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "point", (double)k);
    cJSON_AddNumberToObject(j, "points", (double)s->n_points);
    cJSON_AddStringToObject(j, "status", status);
    if (code >= 0) {
        cJSON_AddNumberToObject(j, "exit_code", code);
    }
    if (error && error[0]) {
        cJSON_AddStringToObject(j, "error", error);
    }
    cJSON_AddStringToObject(j, "sweep", s->file);
    cJSON_AddStringToObject(j, "scene", s->scene);
    cJSON_AddStringToObject(j, "scene_hash", hash);
    cJSON *keys = cJSON_AddObjectToObject(j, "keys");
    for (int i = 0; i < s->n_keys; i++) {
        cJSON_AddStringToObject(keys, s->key[i], s->value[i][idx[i]]);
    }
    cJSON_AddNumberToObject(j, "seed", (double)sweep_point_seed(s, k));
    cJSON *over = cJSON_AddArrayToObject(j, "overrides");
    for (int i = 0; i < n_over; i++) {
        cJSON_AddItemToArray(over, cJSON_CreateString(ptrs[i]));
    }
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddStringToObject(j, "host", host);
    cJSON_AddStringToObject(j, "runner", runner);
    cJSON_AddStringToObject(j, "started", c->started);
    if (finished) {
        cJSON_AddStringToObject(j, "finished", finished);
        cJSON_AddNumberToObject(j, "wall_seconds", round(wall * 1000.0) / 1000.0);
    }
    cJSON_AddNumberToObject(j, "cpu_seconds", round((c->cpu_before + c->cpu) * 1000.0) / 1000.0);
    char *text = cJSON_Print(j);
    gr_file f;
    gr_error err = {0};
    if (text && !gr_file_open(&f, dir, "point.json", &err)) {
        fputs(text, f.f);
        fputc('\n', f.f);
        gr_file_commit(&f, &err);
    }
    if (err.message[0]) {
        app_note("granule sweep: point %ld: %s\n", k, err.message);
    }
    cJSON_free(text);
    cJSON_Delete(j);
}

/* The claims this process holds (one per running child): a child closes the others' so that a
 * claim ends with its own point's child, not with a sibling that inherited it. */
static int *claims;
static size_t n_claims, cap_claims;

/* Claim point k (its folder exists): GR_OK with *fd holding the claim, SWEEP_CLAIMED_ELSEWHERE
 * (who names the holder) when a live process holds it, or an error. */
static int claim(const char *dir, long k, int *fd, char *who, size_t who_len, gr_error *err)
{
    if (n_claims == cap_claims) {
        size_t cap = cap_claims ? 2 * cap_claims : 16;
        int *grown = realloc(claims, cap * sizeof *grown);
        if (!grown) {
            return GR_FAIL(err, GR_ENOMEM, "point %ld: out of memory", k);
        }
        claims = grown;
        cap_claims = cap;
    }
    int rc = gr_dir_lock(dir, POINT_LOCK, fd, who, who_len, err);
    if (rc == GR_LOCK_HELD) {
        return SWEEP_CLAIMED_ELSEWHERE;
    }
    if (!rc && *fd < 0) {
        static bool warned;
        if (!warned) {
            warned = true;
            app_note("sweep: warning: cannot lock %s/%s (no flock on this file system): points are "
                     "not claimed, "
                     "so do not run two sweeps over this folder at once\n",
                     dir, POINT_LOCK);
        }
    }
    if (!rc && *fd >= 0) {
        claims[n_claims++] = *fd;
    }
    return rc;
}

static void release(const sweep *s, sweep_child *c)
{
    if (c->lock_fd < 0) {
        return;
    }
    for (size_t i = 0; i < n_claims; i++) {
        if (claims[i] == c->lock_fd) {
            claims[i] = claims[--n_claims];
            break;
        }
    }
    char dir[1100];
    sweep_point_dir(s, c->k, dir, sizeof dir);
    gr_dir_unlock(
        dir, POINT_LOCK,
        &c->lock_fd); /* the claim ends with the last descriptor: this one, once the child is gone */
}

static void close_other_claims(int own)
{
    for (size_t i = 0; i < n_claims; i++) {
        if (claims[i] != own) {
            close(claims[i]);
        }
    }
}

/* In the child: run point k into dir; the error message (if any) goes down fd. */
static volatile sig_atomic_t point_stop;

static void on_point_stop(int sig)
{
    (void)sig;
    point_stop = 1;
}

static bool has_checkpoint(const char *dir)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, GR_CHECKPOINT_NAME);
    return access(path, F_OK) == 0;
}

static int child_run(const sweep *s, long k, const char *dir, int fd, pid_t parent)
{
    /* SIGTERM/SIGINT (a batch system ending the job, or the sweep's own death below) stop the run
     * at its next step with a checkpoint, which the next run of the sweep continues. Every such
     * signal only asks for that stop (no SA_RESETHAND, unlike granule run): a batch system or
     * kill -- -PGID signals the sweep and its runs together, and the sweep's death then sends the
     * run a second SIGTERM, which must not kill it before its checkpoint is written. */
    struct sigaction sa = {.sa_handler = on_point_stop};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    signal(SIGPIPE,
           SIG_IGN); /* a killed sweep's closed pipe must not kill the run mid-checkpoint */
    prctl(PR_SET_PDEATHSIG, SIGTERM); /* a killed sweep takes its runs with it */
    if (getppid() != parent) {
        return EXIT_FAILED;
    }
    gr_scene sc;
    gr_error err = {0};
    int code;
    if (sweep_point_scene(s, k, &sc, &err)) {
        code = EXIT_REFUSED;
    } else {
        snprintf(sc.out_dir, sizeof sc.out_dir, "%.1000s", dir);
        sc.progress = false;
        gr_run_options opt = {
            .force = true, .stop = &point_stop}; /* an unfinished point's folder is ours to redo */
        gr_run_result res;
        int rc;
        if (has_checkpoint(dir)) {
            app_note("granule sweep: point %ld: continuing from %s/%s\n", k, dir,
                     GR_CHECKPOINT_NAME);
            gr_run_options resume = {.resume = true, .stop = &point_stop};
            rc = gr_run(&sc, &resume, &res, &err);
            if (rc == GR_EINVAL && !point_stop) {
                app_note("granule sweep: point %ld: starting again, its checkpoint cannot be "
                         "continued: %s\n",
                         k, err.message);
                err = (gr_error){0};
                rc = gr_run(&sc, &opt, &res, &err);
            }
        } else {
            rc = gr_run(&sc, &opt, &res, &err);
        }
        if (rc == GR_OK && !res.stopped) {
            gr_plot_summary_update(dir); /* summary.json lists every picture drawn */
        }
        code = rc == GR_OK          ? EXIT_OK
               : rc == GR_EUNSTABLE ? EXIT_UNSTABLE
               : rc == GR_EINVAL    ? EXIT_REFUSED
               : res.stopped == GR_RUN_STOPPED_WRITE
                   ? EXIT_WRITE_FAILED /* checkpoint kept: the next run continues it */
                   : EXIT_FAILED;
        if (rc == GR_OK && res.stopped) {
            code = res.stopped == 1 ? EXIT_STOPPED : EXIT_WALL_LIMIT;
            snprintf(err.message, sizeof err.message,
                     "stopped %s at step %lld; checkpoint written to %.300s/%s, the next run of "
                     "the sweep continues it",
                     res.stopped == 1 ? "by a signal" : "before run.wall_limit",
                     (long long)res.steps, dir, GR_CHECKPOINT_NAME);
        }
    }
    if (code != EXIT_OK) {
        app_note("granule sweep: point %ld: %s\n", k, err.message);
        size_t len = strlen(err.message);
        if (write(fd, err.message, len) != (ssize_t)len) {
            code = code ? code : EXIT_FAILED;
        }
    }
    return code;
}

int sweep_point_start(const sweep *s, long k, const char *runner, sweep_child *c, gr_error *err)
{
    char dir[1100];
    sweep_point_dir(s, k, dir, sizeof dir);
    memset(c, 0, sizeof *c);
    c->k = k;
    c->fd = -1;
    c->lock_fd = -1;
    gr_scene sc;
    if (sweep_point_scene(s, k, &sc, err)) {
        return GR_EINVAL;
    }
    c->hash = gr_scene_hash(&sc);
    int rc = gr_output_dir_prepare(dir, GR_OUTPUT_ANY, true, err);
    char who[400] = "";
    rc = rc ? rc : claim(dir, k, &c->lock_fd, who, sizeof who, err);
    if (rc == SWEEP_CLAIMED_ELSEWHERE) {
        snprintf(err->message, sizeof err->message, "point %ld is being run by %s; left to it", k,
                 who[0] ? who : "another process");
    }
    if (rc) {
        return rc;
    }
    char why[800];
    if (!s->force && state_of(s, k, c->hash, why, sizeof why, false) == POINT_COMPLETED) {
        release(s, c); /* another process finished it since we looked */
        return SWEEP_FINISHED_ELSEWHERE;
    }
    sweep_now_iso(c->started);
    c->t0 = sweep_monotonic();
    if (has_checkpoint(dir)) { /* continuing: the CPU time of the earlier sessions counts too */
        double before = sweep_point_cpu(s, k);
        c->cpu_before = isfinite(before) ? before : 0.0;
    }
    write_manifest(s, k, dir, runner, c, NULL, 0.0, "running", -1, NULL);
    int p[2];
    if (pipe(p) != 0) {
        release(s, c);
        return GR_FAIL(err, GR_EIO, "point %ld: cannot create a pipe: %s", k, strerror(errno));
    }
    fflush(NULL);
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid == 0) {
        close(p[0]);
        close_other_claims(c->lock_fd);
        _exit(child_run(s, k, dir, p[1], parent));
    }
    close(p[1]);
    if (pid < 0) {
        close(p[0]);
        release(s, c);
        return GR_FAIL(err, GR_EIO, "point %ld: cannot fork: %s", k, strerror(errno));
    }
    c->pid = pid;
    c->fd = p[0];
    return GR_OK;
}

int sweep_point_finish(const sweep *s, const char *runner, sweep_child *c, int ws,
                       const struct rusage *ru)
{
    c->cpu = ru ? (double)ru->ru_utime.tv_sec + 1e-6 * (double)ru->ru_utime.tv_usec +
                      (double)ru->ru_stime.tv_sec + 1e-6 * (double)ru->ru_stime.tv_usec
                : 0.0;
    char msg[700] = "";
    ssize_t got = 0, n;
    while (c->fd >= 0 && got < (ssize_t)sizeof msg - 1 &&
           (n = read(c->fd, msg + got, sizeof msg - 1 - (size_t)got)) > 0) {
        got += n;
    }
    msg[got > 0 ? got : 0] = 0;
    if (c->fd >= 0) {
        close(c->fd);
        c->fd = -1;
    }
    int code;
    if (WIFEXITED(ws)) {
        code = WEXITSTATUS(ws);
        if (code != EXIT_OK && !msg[0]) {
            snprintf(msg, sizeof msg, "the run exited with status %d", code);
        }
    } else {
        code = EXIT_FAILED;
        int sig = WIFSIGNALED(ws) ? WTERMSIG(ws) : 0;
        snprintf(msg, sizeof msg, "the run was killed by signal %d (%s)", sig, strsignal(sig));
    }
    const char *status = sweep_exit_name(code);
    char dir[1100], finished[32];
    sweep_point_dir(s, c->k, dir, sizeof dir);
    sweep_now_iso(finished);
    write_manifest(s, c->k, dir, runner, c, finished, sweep_monotonic() - c->t0, status, code, msg);
    release(s, c);
    c->pid = 0;
    return code;
}

int sweep_point_run(const sweep *s, long k, const char *runner)
{
    sweep_child c;
    gr_error err = {0};
    int rc = sweep_point_start(s, k, runner, &c, &err);
    if (rc == SWEEP_FINISHED_ELSEWHERE) {
        app_note("sweep: point %ld was finished by another process meanwhile\n", k);
        return EXIT_OK;
    }
    if (rc == SWEEP_CLAIMED_ELSEWHERE) {
        app_note("sweep: %s\n", err.message);
        return SWEEP_LEFT;
    }
    if (rc) {
        app_note("granule sweep: point %ld: %s\n", k, err.message);
        return err.code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    int ws = 0;
    struct rusage ru = {0};
    while (wait4(c.pid, &ws, 0, &ru) < 0 && errno == EINTR) {
    }
    return sweep_point_finish(s, runner, &c, ws, &ru);
}

double sweep_point_cpu(const sweep *s, long k)
{
    char dir[1100], path[1200];
    sweep_point_dir(s, k, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/point.json", dir);
    gr_error err = {0};
    cJSON *m = gr_json_read(path, &err);
    double cpu = gr_summary_number(m, "cpu_seconds");
    cJSON_Delete(m);
    return cpu;
}

double sweep_point_cost_guess(const gr_scene *sc)
{
    /* ns per particle-step of the soft-sphere core on one core (docs/performance.md: 1D ~3.6,
     * 2D 11-20); the event-driven and hybrid integrators are usually cheaper, and the finished
     * points correct the guess anyway */
    double ns = sc->dim == 1 ? 4.0 : 16.0;
    double dt = sc->dt > 0.0 ? sc->dt : 1e-6;
    return 1e-9 * ns * (double)sc->N * (sc->warmup + sc->duration) / dt;
}
