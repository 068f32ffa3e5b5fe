/* granule sweep FILE: one scene over lists of keys (e.g. N x eps as in sec. 3.1.2) and seeds, with
 * one table of results and the fitted exponents of the velocity moments in N (xi_m of eqs. 3.8 and
 * 3.13). The points run on local cores (fork), over MPI ranks (mpirun -n P granule sweep FILE, when
 * built with MPI), or one per batch-array task (--point K, or the array index a scheduler puts in
 * the environment), each into its own folder with a manifest; --collect merges them. Finished
 * points are never rerun, a failed point is recorded and the others go on (docs/cluster.md). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "app/sweep.h"
#include "io/files.h"
#include "scene/scene_json.h"

/* --point, --array-base: far beyond any sweep (at most 64 values of 8 linked keys each) */
#define SWEEP_MAX_INDEX 1e12

typedef struct sweep_args {
    int jobs;
    int64_t point, base;
    bool force, collect, list, all, mpi;
} sweep_args;

static const cli_opt sweep_opts[] = {
    {"--jobs", CLI_INT, "J", offsetof(sweep_args, jobs), 1, SWEEP_MAX_JOBS, 0,
     "[sweep] jobs, or the number of cores", "parallel runs on this machine", NULL},
    {"--point", CLI_INT64, "K", offsetof(sweep_args, point), 0, SWEEP_MAX_INDEX, 0, NULL,
     "run point K only (0-based)", NULL},
    {"--array-base", CLI_INT64, "B", offsetof(sweep_args, base), 0, SWEEP_MAX_INDEX, 0, "0",
     "in a batch-array task, run point = array index - B", NULL},
    {"--force", CLI_FLAG, NULL, offsetof(sweep_args, force), 0, 0, 0, NULL,
     "rerun finished points; overwrite what another kind of output left in OUT", NULL},
    {"--collect", CLI_FLAG, NULL, offsetof(sweep_args, collect), 0, 0, 0, NULL,
     "merge the finished points and fit", NULL},
    {"--list", CLI_FLAG, NULL, offsetof(sweep_args, list), 0, 0, 0, NULL,
     "list the points, to size an array", NULL},
    {"--all", CLI_FLAG, NULL, offsetof(sweep_args, all), 0, 0, 0, NULL,
     "every point, even inside a batch-array task (ignore the scheduler's array index)", NULL},
    {"--mpi", CLI_FLAG, NULL, offsetof(sweep_args, mpi), 0, 0, 0, NULL,
     "call MPI_Init even when no launcher variable is seen (built with -Dmpi)", NULL},
};

const cli_command cli_cmd_sweep = {
    .name = "sweep",
    .usage =
        "granule sweep FILE [--jobs J] [--force]                  all points on this machine\n"
        "       mpirun -n P granule sweep FILE                          over MPI ranks (built with "
        "-Dmpi)\n"
        "       granule sweep FILE --point K [--force]                  point K only (0-based)\n"
        "       granule sweep FILE [--array-base B]                     in a batch-array task: "
        "point = index - B\n"
        "       granule sweep FILE --collect                            merge the finished points, "
        "fit\n"
        "       granule sweep FILE --list                               the points, to size an "
        "array",
    .about = "FILE (INI):\n"
             "  [sweep]\n  scene = rfm-1d.ini        ; relative to FILE's folder\n"
             "  out = out/sweep           ; relative to the working folder\n"
             "  seeds = 1, 2, 3\n  jobs = 2                  ; parallel runs (default: number of "
             "cores)\n"
             "  [vary]                    ; every combination is run, for every seed\n"
             "  system.N = 100, 158, 251\n  model.eps_n = 0.1, 0.5\n"
             "  [set]                     ; fixed overrides for every point\n"
             "  run.duration = 20\n  analysis.observables = moments\n",
    .epilog = "Points are numbered from 0, seed fastest, then the last [vary] key (--list). Each "
              "runs into\n"
              "OUT/pNNNN with point.json (overrides, scene hash, version, host, times, status, "
              "error); a point\n"
              "whose manifest says completed for the same scene hash is never rerun (--force "
              "reruns it); a failed\n"
              "point is recorded and the others go on, and the exit status is 1 naming it. A point "
              "being run\n"
              "by another process (its claim, OUT/pNNNN/.point.lock) is left to it, so sweeps "
              "started side by side\n"
              "over one OUT share its points. Without --point the array index is read from\n"
              "SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX, PBS_ARRAYID, SGE_TASK_ID or LSB_JOBINDEX "
              "(--all ignores\n"
              "them). Writes OUT/sweep.csv (one row per point) and, when system.N varies, "
              "OUT/exponents.csv:\n"
              "<|v|^m> ~ N^-xi_m fitted per combination of the other keys (3.8, 3.13), averaging "
              "seeds, with\n"
              "errors and reduced chi-square. Recipes: docs/cluster.md.\n",
    .pos_name = "sweep file",
    .max_pos = 1,
    CLI_OPTS(sweep_opts),
};

/* The batch-array index from the environment of common schedulers; -1 if none. SGE writes
 * "undefined" and LSF 0 outside array jobs. */
static long array_index(const char **var, const char **text)
{
    static const char *const vars[] = {"SLURM_ARRAY_TASK_ID", "PBS_ARRAY_INDEX", "PBS_ARRAYID",
                                       "SGE_TASK_ID", "LSB_JOBINDEX"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++) {
        const char *v = getenv(vars[i]);
        if (!v || !v[0] || !strcmp(v, "undefined") ||
            (!strcmp(vars[i], "LSB_JOBINDEX") && !strcmp(v, "0"))) {
            continue;
        }
        *var = vars[i];
        *text = v;
        char *end;
        long k = strtol(v, &end, 10);
        return *end || k < 0 ? -2 : k;
    }
    return -1;
}

/* Load (and so validate) the scene of every point in [from, to) and keep its hash and its
 * predicted CPU seconds (guess may be NULL). */
static int hash_points(const sweep *s, uint64_t *hash, double *guess, long from, long to)
{
    for (long k = from; k < to; k++) {
        gr_scene sc;
        gr_error err = {0};
        if (sweep_point_scene(s, k, &sc, &err)) {
            app_error("sweep: %s: point %ld: %s", s->file, k, err.message);
            return EXIT_REFUSED;
        }
        hash[k] = gr_scene_hash(&sc);
        if (guess) {
            guess[k] = sweep_point_cost_guess(&sc);
        }
    }
    return EXIT_OK;
}

static void on_sweep_stop(int sig)
{
    (void)sig;
    sweep_stop_requested = 1;
}

static int run_one(const sweep *s, long k, const uint64_t *hash, const char *runner)
{
    gr_error err = {0};
    if (gr_output_dir_prepare(s->out, GR_OUTPUT_SWEEP, s->force, &err)) {
        app_error("sweep: %s", err.message);
        return app_exit_code(err.code);
    }
    char why[800];
    if (!s->force && sweep_point_state(s, k, hash[k], why, sizeof why) == POINT_COMPLETED) {
        fprintf(stderr, "sweep: skipping finished point %ld\n", k);
        return EXIT_OK;
    }
    int code = sweep_point_run(s, k, runner);
    if (code == SWEEP_LEFT) { /* claimed by another process, which sweep_point_run named */
        return EXIT_FAILED;
    }
    char dir[1100];
    sweep_point_dir(s, k, dir, sizeof dir);
    fprintf(stderr, "sweep: point %ld %s (%s/point.json)\n", k, sweep_exit_name(code), dir);
    return code;
}

int cmd_sweep(int argc, char **argv)
{
    sweep_args args = {.point = -1};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_sweep, argc, argv, &args, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    const char *file = pos.n ? pos.v[0] : NULL;
    const int jobs = args.jobs;
    const bool force = args.force, collect = args.collect, list = args.list, all = args.all,
               mpi = args.mpi;
    long point = (long)args.point;
    const long base = (long)args.base;
    if (!file) {
        cli_help(&cli_cmd_sweep, stderr);
        return EXIT_REFUSED;
    }
    sweep *s = calloc(1, sizeof *s);
    uint64_t *hash = NULL;
    int rc = sweep_load(s, file);
    if (rc) {
        free(s);
        return rc;
    }
    s->force = force;
    if (list) {
        sweep_list(s, stdout);
        free(s);
        return EXIT_OK;
    }
    hash = calloc((size_t)s->n_points, sizeof *hash);
    double *guess = calloc((size_t)s->n_points, sizeof *guess);
    const char *mpi_var = NULL;
    int ranks = sweep_mpi_launched(&mpi_var);
    const char *arr_var = NULL, *arr_text = NULL;
    long arr = collect || all || point >= 0 ? -1 : array_index(&arr_var, &arr_text);
    if (arr == -2) {
        app_error("sweep: %s=%s: expected a non-negative integer array index", arr_var, arr_text);
        rc = EXIT_REFUSED;
        goto done;
    }
    if (arr >= 0) {
        point = arr - base;
        fprintf(stderr,
                "sweep: point %ld from %s=%s%s (--point K to choose, --all for the whole sweep)\n",
                point, arr_var, arr_text, base ? " minus --array-base" : "");
        if (point < 0) {
            app_error("sweep: %s=%s minus --array-base %ld is negative", arr_var, arr_text, base);
            rc = EXIT_REFUSED;
            goto done;
        }
    }
    if (point >= s->n_points) {
        app_error("sweep: %s: point %ld does not exist; points 0..%ld (granule sweep %s --list)",
                  file, point, s->n_points - 1, file);
        rc = EXIT_REFUSED;
        goto done;
    }
    if (point >= 0 && ranks > 1) {
        app_error("sweep: one point (%ld) was asked for but %s says %d MPI ranks would all run it; "
                  "start one process per "
                  "point, or drop --point (and pass --all in a batch-array task) to spread the "
                  "sweep over the ranks",
                  point, mpi_var, ranks);
        rc = EXIT_REFUSED;
        goto done;
    }
    if (point >= 0) {
        rc = hash_points(s, hash, NULL, point, point + 1);
        if (!rc) {
            char runner[128] = "point";
            if (arr_var) {
                snprintf(runner, sizeof runner, "array %.40s=%.60s", arr_var, arr_text);
            }
            rc = run_one(s, point, hash, runner);
        }
        goto done;
    }
    rc = hash_points(s, hash, guess, 0, s->n_points);
    if (rc) {
        goto done;
    }
    if (collect) {
        long bad = 0;
        rc = sweep_collect(s, hash, &bad);
        printf("%s/sweep.csv: %ld points, %ld finished, %ld not finished or failed\n", s->out,
               s->n_points, s->n_points - bad, bad);
        rc = rc ? rc : bad ? EXIT_FAILED : EXIT_OK;
        goto done;
    }
    if (ranks > 1 || mpi) {
        if (ranks > 1 && !sweep_mpi_available()) {
            app_error("sweep: started by an MPI launcher (%s = %d ranks) but this granule was "
                      "built without MPI: every rank "
                      "would run the whole sweep; rebuild with meson setup -Dmpi=enabled, or see "
                      "docs/cluster.md",
                      mpi_var, ranks);
            rc = EXIT_REFUSED;
            goto done;
        }
        rc = sweep_mpi_run(s, hash, guess, &argc, &argv);
        goto done;
    }
    if (jobs > 0) {
        s->jobs = jobs;
    }
    if (s->jobs <= 0) {
        s->jobs = (int)sysconf(_SC_NPROCESSORS_ONLN);
    }
    gr_error err = {0};
    if (gr_output_dir_prepare(s->out, GR_OUTPUT_SWEEP, s->force, &err)) {
        app_error("sweep: %s", err.message);
        rc = app_exit_code(err.code);
        goto done;
    }
    char why[900];
    if (sweep_foreign_points(s, s->force, why, sizeof why) < 0) {
        app_error("sweep: %s", why);
        rc = EXIT_REFUSED;
        goto done;
    }
    fprintf(stderr, "sweep: %ld points (%d keys x %d seeds), %d parallel runs, into %s\n",
            s->n_points, s->n_keys, s->n_seeds, s->jobs, s->out);
    sweep_queue q = {.s = s, .hash = hash, .guess = guess, .jobs = s->jobs};
    sweep_queue_start(&q);
    /* Ctrl-C or SIGTERM: the running points write their checkpoints, no new one starts (a second
     * signal kills the sweep; its runs still stop with a checkpoint, PR_SET_PDEATHSIG) */
    struct sigaction sa = {.sa_handler = on_sweep_stop, .sa_flags = SA_RESETHAND};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sweep_run_local(&q, s->jobs, "local", NULL, NULL);
    long bad = 0;
    rc = sweep_collect(s, hash, &bad);
    sweep_queue_report(&q);
    rc = rc ? rc : bad ? EXIT_FAILED : EXIT_OK;
    if (sweep_stop_requested) {
        fprintf(stderr,
                "sweep: stopped by a signal: %ld point%s stopped with a checkpoint; run the same "
                "command to continue "
                "(finished points are kept, stopped ones continue from their checkpoints)\n",
                q.stopped, q.stopped == 1 ? "" : "s");
        rc = EXIT_STOPPED;
    }
done:
    free(guess);
    free(hash);
    free(s);
    return rc;
}
