/* libFuzzer target: the campaign file parser of `granule reproduce FILE` (src/app/reproduce/
 * campaign_file.c: gr_campaign_load, gr_campaign_points, gr_campaign_materialise) and the sweep
 * file it writes for each fidelity, read back by sweep_load (src/app/sweep_file.c) as reproduce
 * does before running anything.
 *
 * gr_campaign_load reads a path, so each input is written to a private temporary folder first;
 * the materialised sweeps go to a folder beside it. No point is run. Every input must end in a
 * clean refusal (with a message) or an accepted campaign whose sweeps are accepted or refused with
 * a message: never a crash, hang or sanitizer report. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "fuzz_files.h"
#include "app/sweep.h"
#include "granule/campaign.h"

static char campaign_path[128], out_dir[128];

static void clean_out(void)
{
    static const char *const names[] = {"scene.ini", "sweep.ini"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[256];
        snprintf(path, sizeof path, "%s/%s", out_dir, names[i]);
        unlink(path);
    }
    rmdir(out_dir);
}

static void cleanup(void)
{
    clean_out();
    unlink(campaign_path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (fuzz_first("campaign", cleanup)) {
        snprintf(campaign_path, sizeof campaign_path, "%s/campaign.ini", fuzz_dir);
        snprintf(out_dir, sizeof out_dir, "%s/out", fuzz_dir);
    }
    fuzz_write_input(campaign_path, data, size);
    gr_campaign *c = calloc(1, sizeof *c);
    gr_error err = {0};
    if (gr_campaign_load(c, campaign_path, &err) != GR_OK) {
        if (!err.message[0]) {
            abort(); /* a refusal must say why */
        }
        free(c);
        return 0;
    }
    for (int fid = 0; fid < 2; fid++) {
        if (gr_campaign_points(c, (gr_fidelity)fid) < 1) {
            abort(); /* accepted, so each fidelity has points */
        }
        char sweep_path[256];
        gr_error merr = {0};
        if (gr_campaign_materialise(c, (gr_fidelity)fid, out_dir, sweep_path, sizeof sweep_path,
                                    &merr) != GR_OK) {
            if (!merr.message[0]) {
                abort();
            }
            continue;
        }
        sweep *s = calloc(1, sizeof *s);
        last_error[0] = 0;
        if (sweep_load(s, sweep_path) != EXIT_OK && !last_error[0]) {
            abort(); /* the written sweep is refused with a message, as reproduce reports it */
        }
        free(s);
        clean_out();
    }
    free(c);
    return 0;
}
