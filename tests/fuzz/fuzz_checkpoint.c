/* libFuzzer target: the checkpoint reader (src/io/checkpoint.c: gr_checkpoint_read_buffer) and
 * what a resume does with the sections it finds: the scene text compare (SCEN), the simulation
 * state (SIM, src/core/sim_state.c) restored into a simulation of the harness's scene, then a few
 * steps, and the observables' state (OBS).
 *
 * Each input is read twice: as it is (magic, version, length, CRC-32 checks), and with its length
 * field and CRC-32 recomputed, so that mutations reach the section table and the section payloads
 * instead of all dying at the checksum. The committed corpus (tests/fuzz/corpus/checkpoint) holds
 * checkpoints written by `granule run` from FUZZ_SCENE below (tests/fuzz/gen-corpus-checkpoint.sh),
 * so a valid input restores completely. Never a crash, hang or sanitizer report. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/sim_state.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "analysis/blob_stats.h"
#include "io/checkpoint.h"
#include "app/run_checkpoint.h"

/* Keep in step with tests/fuzz/gen-corpus-checkpoint.sh. */
#define FUZZ_SCENE                                                                                 \
    "[system]\ndim = 2\nN = 16\npacking_fraction = 0.3\n[placement]\nkind = random\n"              \
    "[model]\ntangential = tangential_dashpot\n[integrator]\nsteps_per_contact = 20\n"             \
    "[run]\nwarmup = 0\nduration = 0.002\nsample_every = 1e-4\ncheckpoint_every = 5e-4\n"          \
    "[analysis]\nobservables = moments\n[output]\nplots = false\n"
#define LENGTH_AT 24 /* u64 total length after magic(8) version(4) order(4) sizes(4) zero(4) */

static gr_scene scene;
static int verbose; /* GRANULE_FUZZ_VERBOSE=1: print how far each input got */

static void note(const char *stage, int rc, const gr_error *err)
{
    if (verbose) {
        fprintf(stderr, "fuzz_checkpoint: %s: %s\n", stage, rc == GR_OK ? "ok" : err->message);
    }
}
static char *scene_text;
static size_t scene_text_len;

static void setup(void)
{
    static const char text[] = FUZZ_SCENE;
    gr_error err = {0};
    verbose = getenv("GRANULE_FUZZ_VERBOSE") != NULL;
    if (gr_scene_load_buffer(&scene, "fuzz.ini", text, sizeof text - 1, NULL, 0, &err) != GR_OK) {
        fprintf(stderr, "fuzz_checkpoint: %s\n", err.message);
        abort();
    }
    FILE *m = open_memstream(&scene_text, &scene_text_len);
    gr_scene_write(&scene, m);
    fclose(m);
}

static void restore(const gr_checkpoint *ck)
{
    gr_error err = {0};
    const gr_checkpoint_section *sec = gr_checkpoint_find(ck, "SCEN");
    if (sec) {
        note("SCEN", gr_scene_text_compare(sec->data, sec->len, scene_text, NULL, &err), &err);
    }
    sec = gr_checkpoint_find(ck, "SIM ");
    if (sec) {
        gr_sim *sim = NULL;
        if (gr_sim_create(&scene, &sim, &err) == GR_OK) {
            gr_blob_reader r;
            gr_blob_reader_init(&r, sec->data, sec->len, "SIM (simulation state)");
            int rc = gr_sim_load_state(sim, &r, &err);
            note("SIM", rc, &err);
            if (rc == GR_OK) {
                note("steps", gr_sim_step(sim, 20, &err), &err);
                (void)gr_sim_temperature(sim);
            } else if (!err.message[0]) {
                abort(); /* a refusal must say why */
            }
            gr_sim_free(sim);
        }
    }
    sec = gr_checkpoint_find(ck, "OBS ");
    if (sec) {
        gr_observer *obs = NULL;
        if (gr_scene_observer(&scene, &obs, &err) == GR_OK) {
            err.message[0] = 0;
            int rc = gr_observer_load(obs, sec->data, sec->len, &err);
            note("OBS", rc, &err);
            if (rc != GR_OK && !err.message[0]) {
                abort();
            }
            gr_observer_free(obs);
        }
    }
}

static void one(const void *buf, size_t len)
{
    gr_checkpoint ck;
    gr_error err = {0};
    int rc = gr_checkpoint_read_buffer(buf, len, &ck, &err);
    note("read", rc, &err);
    if (rc == GR_OK) {
        restore(&ck);
    } else if (!err.message[0]) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!scene_text) {
        setup();
    }
    one(data, size);
    if (size >= LENGTH_AT + 8 + 4) {
        unsigned char *p = malloc(size);
        memcpy(p, data, size);
        uint64_t total = size;
        memcpy(p + LENGTH_AT, &total, 8);
        uint32_t crc = (uint32_t)crc32(crc32(0L, Z_NULL, 0), p, (uInt)(size - 4));
        memcpy(p + size - 4, &crc, 4);
        one(p, size);
        free(p);
    }
    return 0;
}
