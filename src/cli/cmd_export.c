/* granule export lammps SCENE [--out DIR] [--set ...] [--force]: write a LAMMPS deck and data file for the
 * scene (the mapping lives in src/scene/lammps_deck.c; docs/lammps.md). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/export.h"
#include "granule/scene.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: granule export lammps SCENE [--out DIR] [--set section.key=value ...] [--force]\n\n"
               "Writes DIR/in.granule (LAMMPS input deck), DIR/data.granule (the initial particles granule\n"
               "itself would start from) and DIR/scene.ini. Run it with `mpirun -n RANKS lmp -in in.granule`\n"
               "inside DIR, then `granule analyse DIR --lammps-dump DIR/dump.granule.lammpstrj`.\n"
               "DIR defaults to OUTPUT/lammps, OUTPUT being the scene's output.dir. docs/lammps.md maps\n"
               "every scene key; 1D, event-driven/hybrid integrators, hard spheres and sliding friction\n"
               "are refused. A DIR holding a result (an earlier export, a run, a comparison) is refused unless\n"
               "--force, which replaces its contents as a whole.\n");
}

int cmd_export(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_REFUSED : EXIT_OK;
    }
    if (strcmp(argv[1], "lammps") != 0) {
        cli_error("export: unknown format %s (known: lammps)", argv[1]);
        return EXIT_REFUSED;
    }
    const char *scene_path = NULL, *out_dir = NULL;
    const char **sets = calloc((size_t)argc + 1, sizeof(char *));
    int n_sets = 0;
    bool force = false;
    for (int i = 2; i < argc; i++) {
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
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            if (!cli_missing_value("export", argv[i], "--set --out", i + 1 >= argc)) {
                cli_error("export: unexpected argument %s", argv[i]);
            }
            free(sets);
            return EXIT_REFUSED;
        }
    }
    if (!scene_path) {
        usage(stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    gr_scene scene;
    gr_error err = {0};
    int rc = gr_scene_load(&scene, scene_path, sets, n_sets, &err);
    free(sets);
    if (rc) {
        cli_error("export: %s", err.message);
        return EXIT_REFUSED;
    }
    char dir[1100];
    snprintf(dir, sizeof dir, "%s", out_dir ? out_dir : "");
    if (!out_dir) {
        snprintf(dir, sizeof dir, "%.1080s/lammps", scene.out_dir);
    }
    gr_lammps_export info;
    rc = gr_export_lammps(&scene, dir, force, &info, &err);
    if (rc) {
        cli_error("%s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    printf("%s, %s: N = %d, %lld + %lld steps, dump every %lld steps to %s\n", info.deck, info.data, scene.N,
           (long long)info.warmup_steps, (long long)info.run_steps, (long long)info.sample_steps, info.dump);
    printf("gran/hooke Kn = %.6g N/m, gamman = %.6g 1/s, gammat = %.6g 1/s; noise sigma = %.6g N\n", info.kn,
           info.gamman, info.gammat, info.noise_sigma);
    return EXIT_OK;
}
