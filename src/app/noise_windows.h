/* How coarse an event-driven run's noise windows were against its own state (docs/event-driven.md,
 * "Accuracy and the kick interval"): the noise increment per window against the thermal speed,
 * and the collisions a grain has per window. Both must be small for the windows to approximate the
 * white noise of eqs. 2.15-2.16; the run reports them and warns when they are not. */
#ifndef GRANULE_APP_NOISE_WINDOWS_H
#define GRANULE_APP_NOISE_WINDOWS_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>

#include "granule/run.h"
#include "granule/scene.h"
#include "granule/sim.h"

typedef struct gr_noise_windows {
    bool applies;                 /* an event-driven run with the random force and a measured T */
    double kick_over_thermal;     /* sqrt(2 D tau) / m_min over sqrt(T / dim) */
    double collisions_per_window; /* 2 collisions / N per grain and second, times tau */
} gr_noise_windows;

/* The figures of a finished run (r's T_mean and collisions, the simulated time of sim). */
gr_noise_windows gr_noise_windows_of(const gr_scene *s, const gr_sim *sim, const gr_run_result *r);
/* One warning line per figure beyond its limit appended to notes (size len). */
void gr_noise_windows_warn(const gr_noise_windows *w, const gr_scene *s, char *notes, size_t len);
/* summary.json's "noise_windows" (nothing when they do not apply). */
void gr_noise_windows_json(const gr_noise_windows *w, const gr_scene *s, cJSON *summary);

#endif
