/* granule run SCENE [--out DIR] [--set section.key=value ...] [--force] [--quiet] [--wall-limit S] [--threads N]
 * granule run --resume DIR [--set run.wall_limit=S ...] [--quiet] [--threads N] */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "granule/run.h"
#include "io/plot.h"

typedef struct run_args {
    const char *out, *resume, *wall_limit;
    cli_list sets;
    bool force, quiet, no_plots;
} run_args;

static const cli_opt run_opts[] = {
    CLI_OPT_OUT(run_args, out, "the scene's output.dir"),
    CLI_OPT_SET(run_args, sets),
    CLI_OPT_FORCE(run_args, force),
    CLI_OPT_QUIET(run_args, quiet),
    CLI_OPT_THREADS,
    {"--format", CLI_CHOICE, "png|svg|pdf", CLI_NOWHERE, 0, 0, 0, "png",
     "the format of every plot (the snapshot picture stays PNG)", cli_apply_format},
    {"--no-plots", CLI_FLAG, NULL, offsetof(run_args, no_plots), 0, 0, 0, NULL,
     "draw no plots (same as --set output.plots=false)", NULL},
    {"--wall-limit", CLI_STRING, "S", offsetof(run_args, wall_limit), 0, 0, 0, NULL,
     "write a checkpoint and stop before S seconds of wall time (same as --set run.wall_limit=S)",
     NULL},
    {"--resume", CLI_STRING, "DIR", offsetof(run_args, resume), 0, 0, 0, NULL,
     "continue the interrupted run in DIR from DIR/checkpoint (docs/checkpoints.md); no SCENE, "
     "--out or --force",
     NULL},
};

const cli_command cli_cmd_run = {
    .name = "run",
    .usage = "granule run SCENE [--out DIR] [--set section.key=value ...] [--force] [--quiet] "
             "[--wall-limit S]\n"
             "                 [--threads N] [--format png|svg|pdf] [--no-plots]\n"
             "       granule run --resume DIR [--set run.wall_limit=S ...] [--quiet] [--threads N]",
    .about = "Runs SCENE (an INI file, see docs/scene-keys.md): warm-up, then sampling every\n"
             "run.sample_every. Writes DIR/summary.json, temperature.csv, blocks.csv, ledger.csv,\n"
             "walls.csv (a scene with [boundary] walls: the forces on the walls), snapshots/\n"
             "(output.snapshot_every) and plots (output.plots, docs/plots.md).\n",
    .epilog = "SIGTERM or SIGINT writes a checkpoint at the next step boundary and stops (a second "
              "one kills).\n"
              "Exit status: 0 completed, 2 scene refused, 3 run became unstable, 1 other failure,\n"
              "4 stopped for the wall-time limit, 5 stopped by a signal (both with a checkpoint to "
              "resume),\n"
              "6 an output could not be written, e.g. a full disk (checkpoint kept: free space, "
              "then --resume).\n",
    .pos_name = "scene",
    .max_pos = 1,
    CLI_OPTS(run_opts),
};

static void progress(const gr_progress *p, void *user)
{
    (void)user;
    int eta = (int)(p->eta + 0.5);
    fprintf(stderr, "\r%s t = %.4g / %.4g s  %3.0f%%  %.3g %s  ETA %d:%02d:%02d   ",
            p->warmup ? "warm-up " : "sampling", p->t, p->t_end, 100.0 * p->t / p->t_end,
            p->event_driven ? p->events_per_second : p->particle_steps_per_second,
            p->event_driven ? "events/s" : "particle-steps/s", eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

static void notice(const char *message, void *user)
{
    (void)user;
    app_error("warning: %s", message);
}

static volatile sig_atomic_t stop_requested;

static void on_stop_signal(int sig)
{
    (void)sig;
    stop_requested =
        1; /* the run checkpoints at the next step boundary; SA_RESETHAND: a second signal kills */
}

void cmd_run_catch_stop(void)
{
    struct sigaction sa = {.sa_handler = on_stop_signal, .sa_flags = SA_RESETHAND};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
}

int cmd_run(int argc, char **argv)
{
    run_args args = {0};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_run, argc, argv, &args, &pos);
    if (parsed >= 0) {
        cli_list_free(&args.sets);
        return parsed;
    }
    const char *scene_path = pos.n ? pos.v[0] : NULL, *out = args.out, *resume = args.resume;
    const bool force = args.force, quiet = args.quiet;
    char wall_set[80] = "";
    if (args.wall_limit) {
        snprintf(wall_set, sizeof wall_set, "run.wall_limit=%.60s", args.wall_limit);
    }
    /* after the --set options, as if given last */
    if ((args.wall_limit && !cli_list_add(&args.sets, wall_set)) ||
        (args.no_plots && !cli_list_add(&args.sets, "output.plots=false"))) {
        cli_list_free(&args.sets);
        return EXIT_FAILED;
    }
    const char **sets = args.sets.items;
    const int n_sets = args.sets.n;
    char resume_scene[1100];
    if (resume) {
        if (scene_path || out || force) {
            app_error("run: --resume %s continues the run in that folder with its own scene.ini; "
                      "give no SCENE, --out or --force",
                      resume);
            free(sets);
            return EXIT_REFUSED;
        }
        snprintf(resume_scene, sizeof resume_scene, "%s/scene.ini", resume);
        scene_path = resume_scene;
        out = resume;
    }
    if (!scene_path) {
        cli_help(&cli_cmd_run, stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    gr_scene scene;
    gr_error err = {0};
    int rc = gr_scene_load_whole(&scene, scene_path, sets, n_sets, &err);
    free(sets);
    if (rc) {
        app_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (out) {
        if (strlen(out) >= sizeof scene.out_dir) {
            app_error("--out %s: path too long", out);
            return EXIT_REFUSED;
        }
        snprintf(scene.out_dir, sizeof scene.out_dir, "%s", out);
    }
    if (scene.warnings[0]) {
        fprintf(stderr, "granule: warning: %s", scene.warnings);
    }
    gr_run_options opt = {
        .force = force, .resume = resume != NULL, .stop = &stop_requested, .notice = notice};
    if (!quiet && scene.progress && app_interactive()) {
        opt.progress = progress;
    }
    gr_run_result res;
    rc = gr_run(&scene, &opt, &res, &err);
    if (opt.progress) {
        fputc('\n', stderr);
    }
    for (const char *line = res.notes, *nl; *line; line = nl + 1) { /* one "note:" per line */
        nl = strchr(line, '\n');
        if (!nl) {
            fprintf(stderr, "granule: note: %s\n", line);
            break;
        }
        fprintf(stderr, "granule: note: %.*s\n", (int)(nl - line), line);
    }
    if (rc == GR_OK && !res.stopped) {
        gr_plot_summary_update(scene.out_dir); /* summary.json lists every picture drawn */
    }

    if (rc == GR_OK && res.stopped) {
        app_error("%s at step %lld (%lld samples): checkpoint written to %s/checkpoint; continue "
                  "with: granule run --resume %s",
                  res.stopped == 1 ? "stopped by a signal"
                                   : "stopped before the wall-time limit (run.wall_limit)",
                  (long long)res.steps, (long long)res.samples, scene.out_dir, scene.out_dir);
        return res.stopped == 1 ? EXIT_STOPPED : EXIT_WALL_LIMIT;
    }
    if (rc && res.stopped == GR_RUN_STOPPED_WRITE) {
        app_error("%s", err.message);
        return EXIT_WRITE_FAILED;
    }
    if (rc == GR_EUNSTABLE) {
        app_error("%s (outputs so far kept in %s)", err.message, scene.out_dir);
        return EXIT_UNSTABLE;
    }
    if (rc == GR_EINVAL) {
        app_error("%s", err.message);
        return EXIT_REFUSED;
    }
    if (rc) {
        app_error("%s", err.message);
        return EXIT_FAILED;
    }
    char T_text[200];
    cli_T_text(T_text, sizeof T_text, res.T_mean, res.T_stderr, res.T_stderr_converged);
    printf("%s: %s over %lld samples; %lld collisions; %.3g %s; kernel %s\n", scene.out_dir, T_text,
           (long long)res.samples, (long long)res.collisions,
           res.event_driven ? res.events_per_second : res.particle_steps_per_second,
           res.event_driven ? "events/s" : "particle-steps/s", res.kernel);
    return EXIT_OK;
}

void cli_T_text(char *buf, size_t size, double T_mean, double T_stderr, int converged)
{
    char err_text[32] = "n/a (< 16 samples)";
    if (T_stderr == T_stderr) {
        snprintf(err_text, sizeof err_text, "%.2g", T_stderr);
    }
    /* an error bar whose blocking never reached a plateau is a lower bound: say so on the same line */
    const char *unconverged =
        T_stderr == T_stderr && !converged
            ? " (WARNING: error bar not converged, T_stderr_converged = false: run longer)"
            : "";
    snprintf(buf, size, "T = %.6g +- %s m^2/s^2%s", T_mean, err_text, unconverged);
}
