/* granule compare SCENE --models a,b@hybrid,hard_sphere@event,...: the same scene, initial state
 * and noise seed under each collision model and integrator; the headline table on the terminal,
 * the full table and overlaid plots in the output folder (include/granule/compare.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/compare.h"
#include "granule/integrator.h"
#include "granule/run.h"
#include "io/files.h"
#include "io/plot.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: granule compare SCENE --models SPEC[,SPEC...] [--set section.key=value ...] [--out DIR] [--force]\n"
               "                      [--format png|svg|pdf]\n\n"
               "Runs SCENE once per model SPEC with the same initial state and the same noise (same seed):\n"
               "SPEC = NORMAL[+TANGENTIAL[+ROLLING]][@clamp][@rotation][@INTEGRATOR], INTEGRATOR = verlet | event | hybrid, e.g.\n"
               "  --models spring_dashpot,spring_dashpot@hybrid,hard_sphere@event\n"
               "  --models spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@clamp,spring_dashpot+sliding_friction\n"
               "  --models spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@rotation,hard_sphere@rotation\n"
               "@rotation: the discs rotate (model.rotation = true; false without it, whatever the scene says).\n"
               "Without @INTEGRATOR hard_sphere runs event-driven and a force law with the scene's integrator\n"
               "(verlet when the scene is event-driven). At most %d models.\n\n"
               "Prints the headline table (T, P(v) tail exponent, D_f (2D) or the G_1 exponent n_N (1D),\n"
               "collisions, energy dissipated by mechanism, wall time, throughput in the integrator's unit;\n"
               "value +- error in one cell, the reason where there is no number) and writes DIR/<model>/ (a run\n"
               "folder each), DIR/compare.md (the headline), DIR/compare.csv and compare.json (the headline and\n"
               "every scalar of every run), DIR/temperature.png (T(t) overlaid) and, with the pv observable\n"
               "(--set analysis.observables=pv), the collapse of (5.4) in pv_collapse.csv/.png.\n"
               "Default DIR: out/compare. docs/compare.md explains the table.\n",
            GR_COMPARE_MAX);
}

int cmd_compare(int argc, char **argv)
{
    const char *scene_path = NULL, *models = NULL, *out = "out/compare";
    const char **sets = calloc((size_t)argc + 4, sizeof(char *));
    int n_sets = 0, rc = EXIT_OK;
    bool force = false;
    for (int i = 1; i < argc && rc == EXIT_OK; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            free(sets);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--models") && i + 1 < argc) {
            models = argv[++i];
        } else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--force")) {
            force = true;
        } else if (!strcmp(argv[i], "--format") && i + 1 < argc) {
            rc = cli_plot_format(argv[++i]) ? EXIT_OK : EXIT_REFUSED;
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            if (!cli_missing_value("compare", argv[i], "--models --set --out --format", i + 1 >= argc)) {
                cli_error("compare: unexpected argument %s", argv[i]);
            }
            rc = EXIT_REFUSED;
        }
    }
    if (rc == EXIT_OK && (!scene_path || !models)) {
        usage(stderr);
        rc = EXIT_REFUSED;
    }
    gr_error err = {0};
    gr_compare_spec specs[GR_COMPARE_MAX];
    static gr_scene scenes[GR_COMPARE_MAX];
    int n = 0;
    if (rc == EXIT_OK && gr_compare_specs_parse(models, specs, GR_COMPARE_MAX, &n, &err)) {
        cli_error("compare: %s", err.message);
        rc = EXIT_REFUSED;
    }
    /* every spec's scene must load before anything runs */
    for (int k = 0; k < n && rc == EXIT_OK; k++) {
        if (gr_compare_scene_load(&specs[k], scene_path, sets, n_sets, out, &scenes[k], &err)) {
            cli_error("compare: %s", err.message);
            rc = EXIT_REFUSED;
        }
    }
    free(sets);
    if (rc != EXIT_OK) {
        return rc;
    }
    /* only now is the folder touched; an earlier comparison is kept unless --force */
    char what[1400];
    if (!force && gr_compare_earlier(out, specs, n, what, sizeof what)) {
        cli_error("compare: %s already holds a comparison (%s); choose another folder or pass --force to overwrite it", out, what);
        return EXIT_REFUSED;
    }
    if (gr_output_dir_prepare(out, GR_OUTPUT_COMPARE, force, &err)) {
        cli_error("compare: %s", err.message);
        return cli_exit_code(err.code);
    }
    int failures = 0;
    for (int k = 0; k < n; k++) {
        fprintf(stderr, "compare: %s (%d/%d, %s)\n", specs[k].text, k + 1, n,
                scenes[k].integrator ? scenes[k].integrator->name : "verlet");
        gr_run_options opt = {.force = force};
        gr_run_result res;
        if (gr_run(&scenes[k], &opt, &res, &err)) {
            cli_error("compare: %s: %s", specs[k].text, err.message);
            failures++;
        } else {
            gr_plot_summary_update(scenes[k].out_dir);
        }
    }
    gr_compare_table *t = gr_compare_table_build(out, scene_path, scenes[0].dim, specs, n);
    if (!t || gr_compare_table_write(t, out, &err)) {
        cli_error("compare: %s", t ? err.message : "out of memory");
        gr_compare_table_free(t);
        return EXIT_FAILED;
    }
    char note[300];
    gr_compare_plots(out, specs, n, note, sizeof note);
    if (note[0]) {
        fprintf(stderr, "compare: plots: %s\n", note);
    }
    gr_compare_table_print(t, stdout);
    printf("\n%s/compare.md (this table), %s/compare.csv and compare.json (every quantity)\n", out, out);
    gr_compare_table_free(t);
    return failures ? EXIT_FAILED : EXIT_OK;
}
