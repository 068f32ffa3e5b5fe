/* granule analyse DIR: feed a run's snapshots to the observables of the analysis layer (the same
 * code that samples during a run) and write the results into DIR/analysis (or --out). */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/scene_json.h"
#include "io/trajectory.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: granule analyse DIR [--set analysis.observables=a,b ...] [--set section.key=value ...]\n"
               "                       [--out OUT] [--force]\n\n"
               "Reads DIR/scene.ini and the trajectory of a finished run (DIR/trajectory.h5, DIR/snapshots/trajectory.xyz\n"
               "or DIR/snapshots/snap_*.xyz, as output.trajectory wrote it) and feeds\n"
               "every frame to the observables named in [analysis] observables (granule observables lists\n"
               "them; --set changes them or their parameters); frames of the warm-up (t <= run.warmup) are\n"
               "skipped, as in a run. Writes OUT (default DIR/analysis):\n"
               "summary.json and one CSV (and PNG) per observable, exactly as a run that sampled them.\n");
}

int cmd_analyse(int argc, char **argv)
{
    const char *dir = NULL, *out_dir = NULL;
    const char **sets = calloc((size_t)argc + 1, sizeof(char *));
    int n_sets = 0;
    bool force = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            free(sets);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out_dir = argv[++i];
        } else if (!strcmp(argv[i], "--force")) {
            force = true;
        } else if (argv[i][0] != '-' && !dir) {
            dir = argv[i];
        } else {
            cli_error("analyse: unexpected argument %s", argv[i]);
            usage(stderr);
            free(sets);
            return EXIT_REFUSED;
        }
    }
    if (!dir) {
        usage(stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    char path[1200], outbuf[1200];
    snprintf(path, sizeof path, "%s/scene.ini", dir);
    gr_scene scene;
    gr_error err = {0};
    int rc = gr_scene_load(&scene, path, sets, n_sets, &err);
    free(sets);
    if (rc) {
        cli_error("analyse: %s", err.message);
        return EXIT_REFUSED;
    }
    if (!scene.observables[0]) {
        cli_error("analyse: no observables chosen; add --set analysis.observables=NAME[,NAME] (granule observables lists them)");
        return EXIT_REFUSED;
    }
    gr_traj_reader *traj;
    int64_t n_frames = 0;
    rc = gr_traj_reader_open(dir, (int)scene.trajectory, &traj, &n_frames, &err);
    if (rc) {
        cli_error("analyse: %s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    if (!out_dir) {
        snprintf(outbuf, sizeof outbuf, "%s/analysis", dir);
        out_dir = outbuf;
    }
    gr_observer *obs = NULL;
    rc = gr_output_dir_prepare(out_dir, force, &err);
    if (!rc) {
        rc = gr_observer_create(&scene, &obs, &err);
    }
    if (rc) {
        gr_traj_reader_close(traj);
        cli_error("analyse: %s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    size_t frames = 0;
    for (int64_t k = 0; k < n_frames && !rc; k++) {
        gr_frame f;
        rc = gr_traj_reader_frame(traj, k, &f, &err);
        if (rc) {
            break;
        }
        if (f.t <= scene.warmup * (1.0 + 1e-12)) {
            gr_frame_free(&f); /* the warm-up is not sampled, as in a run */
            continue;
        }
        if (f.n != scene.N || f.dim != scene.dim) {
            rc = GR_FAIL(&err, GR_EINVAL, "%s, frame %lld: %d particles in %dD, but the scene has N = %d in %dD",
                         gr_traj_reader_source(traj), (long long)k, f.n, f.dim, scene.N, scene.dim);
        } else {
            gr_particles p = {.n = f.n, .dim = f.dim, .L = f.L, .radius = scene.radius, .mass = scene.mass,
                              .x = f.x, .y = f.y, .vx = f.vx, .vy = f.vy};
            rc = gr_observer_sample(obs, &p, f.t, &err);
            frames++;
        }
        gr_frame_free(&f);
        if (cli_interactive()) {
            fprintf(stderr, "\ranalyse: %lld / %lld frames", (long long)k + 1, (long long)n_frames);
        }
    }
    if (cli_interactive()) {
        fputc('\n', stderr);
    }
    gr_traj_reader_close(traj);
    if (rc) {
        gr_observer_free(obs);
        cli_error("analyse: %s", err.message);
        return EXIT_FAILED;
    }
    cJSON *sum = cJSON_CreateObject(), *analysis = cJSON_AddObjectToObject(sum, "analysis");
    gr_output out = {.dir = out_dir, .scene = &scene, .scene_hash = gr_scene_hash(&scene), .summary = analysis, .plots = scene.plots};
    rc = gr_observer_finish(obs, &out, &err);
    gr_observer_free(obs);
    cJSON_AddStringToObject(sum, "source", dir);
    cJSON_AddNumberToObject(sum, "frames", (double)frames);
    cJSON_AddStringToObject(sum, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(sum, "commit", GR_COMMIT);
    cJSON_AddItemToObject(sum, "scene", gr_scene_to_json(&scene));
    char *text = cJSON_Print(sum);
    cJSON_Delete(sum);
    gr_file f;
    gr_error ferr = {0};
    int rc_s = gr_file_open(&f, out_dir, "summary.json", &ferr);
    if (!rc_s) {
        fputs(text, f.f);
        fputc('\n', f.f);
        rc_s = gr_file_commit(&f, &ferr);
    }
    cJSON_free(text);
    if (rc || rc_s) {
        cli_error("analyse: %s", rc ? err.message : ferr.message);
        return EXIT_FAILED;
    }
    printf("%s: %zu frames analysed\n", out_dir, frames);
    return EXIT_OK;
}

int cmd_observables(int argc, char **argv)
{
    (void)argv;
    if (argc > 1) {
        printf("usage: granule observables\nLists the observables of the analysis layer, their dimensions and parameters.\n");
        return EXIT_OK;
    }
    for (int i = 0; gr_observables[i]; i++) {
        const gr_observable_type *t = gr_observables[i];
        printf("%s  [%s]\n  %s\n", t->name, t->dims == 3 ? "1D, 2D" : t->dims == 1 ? "1D" : "2D", t->summary);
        for (int k = 0; k < t->n_params; k++) {
            printf("    %-14s default %-8g %s\n", t->params[k].name, t->params[k].def, t->params[k].doc);
        }
    }
    return EXIT_OK;
}
