/* libFuzzer target: the sweep file parser of `granule sweep FILE` (src/app/sweep_file.c:
 * sweep_load, sweep_list) and the per-point overrides it builds (sweep_overrides), each resolved
 * by the scene parser against a small base scene.
 *
 * sweep_load reads a path, so each input is written to a private temporary folder first. The
 * sweep's own `scene =` is replaced by the base scene (the scene parser has its own target). At
 * most POINT_CAP points (the first and the last ones) are resolved per input. Every input must
 * end in a clean refusal or an accepted sweep: never a crash, hang or sanitizer report. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "fuzz_files.h"
#include "app/sweep.h"

#define POINT_CAP 8

static const char base_scene[] =
    "[system]\ndim = 1\nN = 10\nreduced_length = 0.1\n[placement]\nkind = uniform\n"
    "[run]\nduration = 0.01\nwarmup = 0\n";
static char sweep_path[128], scene_path[128];
static FILE *devnull;

static void setup(void)
{
    snprintf(sweep_path, sizeof sweep_path, "%s/sweep.ini", fuzz_dir);
    snprintf(scene_path, sizeof scene_path, "%s/base.ini", fuzz_dir);
    FILE *f = fopen(scene_path, "w");
    if (!f || fwrite(base_scene, 1, sizeof base_scene - 1, f) != sizeof base_scene - 1 ||
        fclose(f)) {
        abort();
    }
    devnull = fopen("/dev/null", "w");
}

static void cleanup(void)
{
    unlink(sweep_path);
    unlink(scene_path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_first("sweep", cleanup)) {
        setup();
    }
    fuzz_write_input(sweep_path, data, size);
    sweep *s = calloc(1, sizeof *s);
    last_error[0] = 0;
    if (sweep_load(s, sweep_path) != EXIT_OK) {
        if (!last_error[0]) {
            abort(); /* a refusal must say why */
        }
        free(s);
        return 0;
    }
    if (s->n_points < 1 || s->n_points > SWEEP_MAX_POINTS) {
        abort(); /* accepted, so the point count is in range */
    }
    if (s->n_points <= 1000) {
        sweep_list(s, devnull);
    }
    snprintf(s->scene, sizeof s->scene, "%s", scene_path);
    for (long j = 0; j < s->n_points && j < POINT_CAP; j++) {
        long k = j < POINT_CAP / 2 ? j : s->n_points - 1 - (j - POINT_CAP / 2);
        if (k < 0) {
            continue;
        }
        char pdir[1100];
        sweep_point_dir(s, k, pdir, sizeof pdir);
        gr_scene sc;
        gr_error err = {0};
        if (sweep_point_scene(s, k, &sc, &err) != GR_OK && !err.message[0]) {
            abort();
        }
    }
    free(s);
    return 0;
}
