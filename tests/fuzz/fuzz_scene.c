/* libFuzzer target: the scene parser (src/scene/scene.c) and `--set section.key=value` overrides,
 * then, for a scene the parser accepts, a tiny valid run (simulation, observers, scene JSON).
 *
 * Input: scene INI text, optionally followed by a line "#--set" and one override per line (at
 * most 16). "#--set" is an INI comment, so a plain scene file is a valid input as it stands.
 * Every input must end in a clean error (GR_FAIL message) or a valid run: never a crash, hang
 * or sanitizer report. The run is capped (N <= 32, <= 100 steps, <= 1e3 noise windows of the
 * event-driven integrators) to keep executions fast. */
#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/observe.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "scene/scene_json.h"

#define MAX_OVERRIDES 16
#define N_CAP 32
#define STEP_CAP 100
#define WINDOW_CAP 1e3

/* The resolved scene written as text (what a run saves as scene.ini) must load back to the
 * same scene: same hash. Catches values the parser accepts but stores as something else. */
static void round_trip(const gr_scene *s)
{
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    gr_scene_write(s, m);
    fclose(m);
    gr_scene back;
    gr_error err = {0};
    if (gr_scene_load_buffer(&back, "scene.ini", text, len, NULL, 0, &err) != GR_OK) {
        fprintf(stderr, "round trip refused: %s\n--- resolved scene:\n%s\n", err.message, text);
        abort();
    }
    if (gr_scene_hash(&back) != gr_scene_hash(s)) {
        char *a = cJSON_PrintUnformatted(gr_scene_to_json(s)),
             *b = cJSON_PrintUnformatted(gr_scene_to_json(&back));
        fprintf(stderr, "round trip changed the scene:\n%s\n%s\n", a, b);
        abort();
    }
    free(text);
}

static void tiny_run(const gr_scene *s)
{
    gr_error err = {0};
    round_trip(s);
    cJSON_Delete(gr_scene_to_json(s));
    (void)gr_scene_hash(s);
    gr_observer *obs = NULL;
    if (gr_scene_observer(s, &obs, &err) == GR_OK) {
        gr_observer_free(obs);
    }
    gr_sim *sim = NULL;
    if (gr_sim_create(s, &sim, &err) != GR_OK) {
        return; /* refused with a message: a clean error */
    }
    /* event/hybrid scenes are stepped too: the event-driven core refuses absurd speeds and stops
     * diverging event rates and a runaway contact floor with a diagnosis (past hangs:
     * corpus/scene/regress-event-*.ini, docs/event-driven.md "Progress guards") */
    int64_t steps = STEP_CAP;
    if (s->integrator->free_flight) {
        /* the event-driven integrators work per noise window (kick_interval) inside a step of dt:
         * cap the windows too, as N and the steps are capped */
        double windows = gr_sim_dt(sim) / s->kick_interval;
        steps = windows * STEP_CAP <= WINDOW_CAP ? STEP_CAP : (int64_t)(WINDOW_CAP / windows);
    }
    (void)gr_sim_step(sim, steps, &err); /* GR_EUNSTABLE with a diagnosis is a clean end too */
    gr_ledger l = gr_sim_ledger(sim);
    (void)gr_ledger_residual(&l);
    (void)gr_sim_temperature(sim);
    gr_sim_free(sim);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char sep[] = "#--set\n";
    const char *text = (const char *)data;
    size_t ini_len = size;
    const char *rest = NULL;
    for (size_t i = 0; i + sizeof sep - 1 <= size; i++) {
        if ((i == 0 || text[i - 1] == '\n') && memcmp(text + i, sep, sizeof sep - 1) == 0) {
            ini_len = i;
            rest = text + i + sizeof sep - 1;
            break;
        }
    }
    char *store = NULL;
    const char *ovr[MAX_OVERRIDES + 1];
    int n_ovr = 0;
    if (rest) {
        size_t rest_len = size - (size_t)(rest - text);
        store = malloc(rest_len + 1);
        memcpy(store, rest, rest_len);
        store[rest_len] = 0;
        for (char *line = store; line && n_ovr < MAX_OVERRIDES;) {
            char *nl = strchr(line, '\n');
            if (nl) {
                *nl = 0;
            }
            ovr[n_ovr++] = line;
            line = nl ? nl + 1 : NULL;
        }
    }
    gr_scene s;
    gr_error err = {0};
    if (gr_scene_load_buffer(&s, "fuzz.ini", text, ini_len, ovr, n_ovr, &err) == GR_OK) {
        if (s.N > N_CAP) {
            /* the same scene with fewer particles (the override is resolved like any other) */
            static char cap[] = "system.N=32";
            ovr[n_ovr] = cap;
            if (gr_scene_load_buffer(&s, "fuzz.ini", text, ini_len, ovr, n_ovr + 1, &err) !=
                GR_OK) {
                free(store);
                return 0;
            }
        }
        tiny_run(&s);
    } else if (!err.message[0]) {
        abort(); /* a refusal must say why */
    }
    free(store);
    return 0;
}
