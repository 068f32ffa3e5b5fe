/* granule compare SCENE --models a,b@hybrid,hard_sphere@event,...: the same scene, initial state
 * and noise seed under each collision model and integrator; the headline table on the terminal,
 * the full table and overlaid plots in the output folder (include/granule/compare.h). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/compare.h"
#include "granule/integrator.h"
#include "granule/run.h"
#include "io/checkpoint.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

static volatile sig_atomic_t compare_stop = 0;

static void on_compare_stop(int sig)
{
    (void)sig;
    compare_stop = 1;
}

/* A model's run folder under --resume: 1 finished (kept), 2 stopped with a checkpoint (continued),
 * 0 anything else (run again from the start). */
static int run_state(const char *dir)
{
    gr_error err = {0};
    cJSON *sum = gr_summary_read(dir, &err);
    const cJSON *st = cJSON_GetObjectItem(sum, "status");
    const bool done = cJSON_IsString(st) && !strcmp(st->valuestring, "completed");
    cJSON_Delete(sum);
    if (done) {
        return 1;
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, GR_CHECKPOINT_NAME);
    return access(path, F_OK) == 0 ? 2 : 0;
}

typedef struct compare_args {
    const char *models, *out;
    cli_list sets;
    bool force, resume;
} compare_args;

static const cli_opt compare_opts[] = {
    {"--models", CLI_STRING, "SPEC[,SPEC...]", offsetof(compare_args, models), 0, 0, 0, NULL,
     "the models to compare (required; at most " CLI_STR(GR_COMPARE_MAX) ")", NULL},
    CLI_OPT_SET(compare_args, sets),
    CLI_OPT_OUT(compare_args, out, "out/compare"),
    {"--force", CLI_FLAG, NULL, offsetof(compare_args, force), 0, 0, 0, NULL,
     "overwrite an earlier comparison in DIR", NULL},
    CLI_OPT_FORMAT,
    {"--resume", CLI_FLAG, NULL, offsetof(compare_args, resume), 0, 0, 0, NULL,
     "after Ctrl-C: keep the finished models, continue the stopped one from its checkpoint, run "
     "the rest",
     NULL},
};

const cli_command cli_cmd_compare = {
    .name = "compare",
    .usage = "granule compare SCENE --models SPEC[,SPEC...] [--set section.key=value ...] [--out "
             "DIR] [--force]\n"
             "                      [--format png|svg|pdf] [--resume]",
    .about = "Runs SCENE once per model SPEC with the same initial state and the same noise (same "
             "seed):\n"
             "SPEC = NORMAL[+TANGENTIAL[+ROLLING]][@clamp][@rotation][@INTEGRATOR], INTEGRATOR = "
             "verlet | event | hybrid, e.g.\n"
             "  --models spring_dashpot,spring_dashpot@hybrid,hard_sphere@event\n"
             "  --models "
             "spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@clamp,spring_"
             "dashpot+sliding_friction\n"
             "  --models "
             "spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@rotation,hard_"
             "sphere@rotation\n"
             "@rotation: the discs rotate (model.rotation = true; false without it, whatever the "
             "scene says).\n"
             "Without @INTEGRATOR hard_sphere runs event-driven and a force law with the scene's "
             "integrator\n"
             "(verlet when the scene is event-driven).\n",
    .epilog =
        "Prints the headline table (T, P(v) tail exponent, D_f (2D) or the G_1 exponent n_N (1D),\n"
        "collisions, energy dissipated by mechanism, wall time, throughput in the integrator's "
        "unit;\n"
        "value +- error in one cell, the reason where there is no number) and writes DIR/<model>/ "
        "(a run\n"
        "folder each), DIR/compare.md (the headline), DIR/compare.csv and compare.json (the "
        "headline and\n"
        "every scalar of every run), DIR/temperature.png (T(t) overlaid) and, with the pv "
        "observable\n"
        "(--set analysis.observables=pv), the collapse of (5.4) in pv_collapse.csv/.png.\n"
        "docs/compare.md explains the table.\n"
        "Ctrl-C (or SIGTERM) stops the running model with a checkpoint; the same command with "
        "--resume keeps\n"
        "the finished models, continues the stopped one from its checkpoint and runs the rest.\n",
    .pos_name = "scene",
    .max_pos = 1,
    CLI_OPTS(compare_opts),
};

int cmd_compare(int argc, char **argv)
{
    compare_args args = {.out = "out/compare"};
    cli_pos pos;
    int rc = cli_parse(&cli_cmd_compare, argc, argv, &args, &pos);
    if (rc >= 0) {
        cli_list_free(&args.sets);
        return rc;
    }
    rc = EXIT_OK;
    const char *scene_path = pos.n ? pos.v[0] : NULL, *models = args.models, *out = args.out;
    const char **sets = args.sets.items;
    const int n_sets = args.sets.n;
    const bool force = args.force, resume = args.resume;
    if (!scene_path || !models) {
        cli_help(&cli_cmd_compare, stderr);
        rc = EXIT_REFUSED;
    }
    gr_error err = {0};
    gr_compare_spec specs[GR_COMPARE_MAX];
    static gr_scene scenes[GR_COMPARE_MAX];
    int n = 0;
    if (rc == EXIT_OK && gr_compare_specs_parse(models, specs, GR_COMPARE_MAX, &n, &err)) {
        app_error("compare: %s", err.message);
        rc = EXIT_REFUSED;
    }
    /* every spec's scene must load before anything runs */
    for (int k = 0; k < n && rc == EXIT_OK; k++) {
        if (gr_compare_scene_load(&specs[k], scene_path, sets, n_sets, out, &scenes[k], &err)) {
            app_error("compare: %s", err.message);
            rc = EXIT_REFUSED;
        }
    }
    free(sets);
    if (rc != EXIT_OK) {
        return rc;
    }
    if (resume && force) {
        app_error("compare: --resume continues the comparison in %s, --force replaces it: give one",
                  out);
        return EXIT_REFUSED;
    }
    /* only now is the folder touched; an earlier comparison is kept unless --force (or continued with --resume) */
    char what[1400];
    if (resume && !gr_compare_earlier(out, specs, n, what, sizeof what)) {
        app_error("compare: --resume: %s holds no comparison of these models to continue; run "
                  "without --resume",
                  out);
        return EXIT_REFUSED;
    }
    if (!resume && !force && gr_compare_earlier(out, specs, n, what, sizeof what)) {
        app_error("compare: %s already holds a comparison (%s); choose another folder, pass "
                  "--resume to continue it "
                  "(after Ctrl-C) or --force to overwrite it",
                  out, what);
        return EXIT_REFUSED;
    }
    if (!resume && gr_output_dir_prepare(out, GR_OUTPUT_COMPARE, force, &err)) {
        app_error("compare: %s", err.message);
        return app_exit_code(err.code);
    }
    /* Ctrl-C or SIGTERM: the running model stops with a checkpoint (a second signal kills) */
    struct sigaction sa = {.sa_handler = on_compare_stop, .sa_flags = SA_RESETHAND};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    int failures = 0;
    for (int k = 0; k < n && !compare_stop; k++) {
        const int state = resume ? run_state(scenes[k].out_dir) : 0;
        if (state == 1) {
            fprintf(stderr, "compare: %s (%d/%d): finished earlier, kept\n", specs[k].text, k + 1,
                    n);
            continue;
        }
        fprintf(stderr, "compare: %s (%d/%d, %s)%s\n", specs[k].text, k + 1, n,
                scenes[k].integrator ? scenes[k].integrator->name : "verlet",
                state == 2 ? ", continuing from its checkpoint" : "");
        gr_run_options opt = {
            .force = force || resume, .resume = state == 2, .stop = &compare_stop};
        gr_run_result res;
        if (gr_run(&scenes[k], &opt, &res, &err)) {
            app_error("compare: %s: %s", specs[k].text, err.message);
            failures++;
        } else if (res.stopped) {
            break;
        } else {
            gr_plot_summary_update(scenes[k].out_dir);
        }
    }
    if (compare_stop) {
        fprintf(stderr, "compare: stopped by a signal; the running model's run has a checkpoint: "
                        "run the same command with "
                        "--resume to keep the finished models and continue\n");
        return EXIT_STOPPED;
    }
    gr_compare_table *t = gr_compare_table_build(out, scene_path, scenes[0].dim, specs, n);
    if (!t || gr_compare_table_write(t, out, &err)) {
        app_error("compare: %s", t ? err.message : "out of memory");
        gr_compare_table_free(t);
        return EXIT_FAILED;
    }
    char note[300];
    gr_compare_plots(out, specs, n, note, sizeof note);
    if (note[0]) {
        fprintf(stderr, "compare: plots: %s\n", note);
    }
    gr_compare_table_print(t, stdout);
    printf("\n%s/compare.md (this table), %s/compare.csv and compare.json (every quantity)\n", out,
           out);
    gr_compare_table_free(t);
    return failures ? EXIT_FAILED : EXIT_OK;
}
