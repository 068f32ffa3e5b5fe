/* granule export lammps SCENE [--out DIR] [--set ...] [--force]: write a LAMMPS deck and data file for the
 * scene (the mapping lives in src/scene/lammps_deck.c; docs/lammps.md). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/export.h"
#include "granule/scene.h"

typedef struct export_args {
    const char *out;
    cli_list sets;
    bool force;
} export_args;

static const cli_opt export_opts[] = {
    CLI_OPT_OUT(export_args, out, "OUTPUT/lammps, OUTPUT being the scene's output.dir"),
    CLI_OPT_SET(export_args, sets),
    {"--force", CLI_FLAG, NULL, offsetof(export_args, force), 0, 0, 0, NULL,
     "replace a result already in DIR (an earlier export, a run, a comparison)", NULL},
};

const cli_command cli_cmd_export = {
    .name = "export",
    .usage = "granule export lammps SCENE [--out DIR] [--set section.key=value ...] [--force]",
    .about = "Writes DIR/in.granule (LAMMPS input deck), DIR/data.granule (the initial particles "
             "granule\n"
             "itself would start from) and DIR/scene.ini. Run it with `mpirun -n RANKS lmp -in "
             "in.granule`\n"
             "inside DIR, then `granule analyse DIR --lammps-dump DIR/dump.granule.lammpstrj`.\n"
             "docs/lammps.md maps every scene key; 1D, event-driven/hybrid integrators, hard "
             "spheres and\n"
             "sliding friction are refused. A DIR holding a result is refused unless --force, "
             "which replaces\n"
             "its contents as a whole.\n",
    .pos_name = "scene",
    .max_pos = 2, /* the format (lammps), then the scene */
    CLI_OPTS(export_opts),
};

int cmd_export(int argc, char **argv)
{
    export_args args = {0};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_export, argc, argv, &args, &pos);
    if (parsed >= 0) {
        cli_list_free(&args.sets);
        return parsed;
    }
    if (pos.n == 0) {
        cli_help(&cli_cmd_export, stderr);
        return EXIT_REFUSED;
    }
    if (strcmp(pos.v[0], "lammps") != 0) {
        app_error("export: unknown format %s (known: lammps)", pos.v[0]);
        cli_list_free(&args.sets);
        return EXIT_REFUSED;
    }
    const char *scene_path = pos.n > 1 ? pos.v[1] : NULL, *out_dir = args.out;
    const char **sets = args.sets.items;
    const int n_sets = args.sets.n;
    const bool force = args.force;
    if (!scene_path) {
        cli_help(&cli_cmd_export, stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    gr_scene scene;
    gr_error err = {0};
    int rc = gr_scene_load(&scene, scene_path, sets, n_sets, &err);
    free(sets);
    if (rc) {
        app_error("export: %s", err.message);
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
        app_error("%s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    printf("%s, %s: N = %d, %lld + %lld steps, dump every %lld steps to %s\n", info.deck, info.data,
           scene.N, (long long)info.warmup_steps, (long long)info.run_steps,
           (long long)info.sample_steps, info.dump);
    if (scene.size_distribution) { /* pair_style granular, a pair_coeff per pair of grains */
        printf("%d atom types (one per grain of the radius distribution), pair_style granular "
               "hooke with each pair's stiffness and damping; noise sigma = %.6g N\n",
               scene.N, info.noise_sigma);
    } else if (scene.n_species >= 2) { /* pair_style granular, a pair_coeff per species pair */
        printf("%d atom types (species), pair_style granular hooke Kn = %.6g N/m with each "
               "pair's damping; noise sigma = %.6g N\n",
               scene.n_species, info.kn, info.noise_sigma);
    } else {
        printf("gran/hooke Kn = %.6g N/m, gamman = %.6g 1/s, gammat = %.6g 1/s; noise sigma = %.6g "
               "N\n",
               info.kn, info.gamman, info.gammat, info.noise_sigma);
    }
    return EXIT_OK;
}
