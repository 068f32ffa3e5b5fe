/* The event-driven integrator's noise windows against the run (noise_windows.h).
 *
 * Within a window of tau = kick_interval a free grain of mass m receives the random force's
 * impulse over tau, a velocity change of standard deviation sqrt(2 D tau) / m per component (eq.
 * 2.16 integrated over the window; docs/event-driven.md, "Free flight under the random force").
 * The windows stand for white noise only while that change is small against the grains' thermal
 * speed per component, sqrt(T / dim) with T of eq. 2.19, and while a grain rarely collides within
 * one window (tau nu << 1, nu the collision rate per grain): otherwise the collision rate is
 * wrong (exact free flight overcounts, kicks undercount: 2.3x apart at tau nu = 1.1 in the
 * table of event-driven.md) and with kicks of the order of the thermal speed T itself moves
 * with tau (a 3D lognormal gas whose lightest grains' kick variance was 3 T / dim moved 2.5 %
 * when only the clock tick changed). The lightest grain has the largest kicks, so on a mixture
 * it sets the first figure. */
#include "app/noise_windows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define KICK_LIMIT 0.5   /* warn above: kick sd over half the thermal speed per component */
#define WINDOW_LIMIT 0.5 /* warn above: a grain collides in every second window */

gr_noise_windows gr_noise_windows_of(const gr_scene *s, const gr_sim *sim, const gr_run_result *r)
{
    gr_noise_windows w = {0};
    const double t = gr_sim_time(sim);
    if (!r->event_driven || !(s->D > 0.0) || s->noise_mode == GR_NOISE_NONE ||
        !(s->kick_interval > 0.0) || !(r->T_mean > 0.0) || !(t > 0.0)) {
        return w;
    }
    const gr_particles p = gr_sim_particles(sim);
    double m_min = p.mass;
    for (int i = 0; p.masses && i < p.n; i++) {
        m_min = fmin(m_min, p.masses[i]);
    }
    w.applies = true;
    w.kick_over_thermal = sqrt(2.0 * s->D * s->kick_interval) / m_min / sqrt(r->T_mean / s->dim);
    w.collisions_per_window = 2.0 * (double)r->collisions / p.n / t * s->kick_interval;
    return w;
}

void gr_noise_windows_warn(const gr_noise_windows *w, const gr_scene *s, char *notes, size_t len)
{
    if (!w->applies) {
        return;
    }
    size_t at = strlen(notes);
    if (w->kick_over_thermal > KICK_LIMIT && at < len) {
        at += (size_t)snprintf(
            notes + at, len - at,
            "the noise windows are coarse: each window's velocity change (sd sqrt(2 D tau) / m = "
            "%.3g of the thermal speed per component%s) is not small, so T itself depends on "
            "integrator.kick_interval = %g s; rerun with a smaller kick_interval and compare "
            "(docs/event-driven.md, \"Accuracy and the kick interval\")\n",
            w->kick_over_thermal,
            s->n_species >= 2 || s->size_distribution ? ", lightest grain" : "", s->kick_interval);
    }
    if (w->collisions_per_window > WINDOW_LIMIT && at < len) {
        snprintf(notes + at, len - at,
                 "the noise windows are long: a grain collides %.3g times per window of "
                 "integrator.kick_interval = %g s, so the collision rate is off by tens of per "
                 "cent or more (exact free flight overcounts, kicks undercount); use a "
                 "kick_interval below %.2g s where collision statistics matter "
                 "(docs/event-driven.md)\n",
                 w->collisions_per_window, s->kick_interval,
                 s->kick_interval * 0.25 / w->collisions_per_window);
    }
}

void gr_noise_windows_json(const gr_noise_windows *w, const gr_scene *s, cJSON *summary)
{
    if (!w->applies) {
        return;
    }
    cJSON *j = cJSON_AddObjectToObject(summary, "noise_windows");
    cJSON_AddNumberToObject(j, "kick_interval", s->kick_interval);
    cJSON_AddNumberToObject(j, "kick_over_thermal", w->kick_over_thermal);
    cJSON_AddNumberToObject(j, "collisions_per_window", w->collisions_per_window);
    cJSON_AddNumberToObject(j, "kick_over_thermal_limit", KICK_LIMIT);
    cJSON_AddNumberToObject(j, "collisions_per_window_limit", WINDOW_LIMIT);
    cJSON_AddStringToObject(
        j, "definition",
        "kick_over_thermal = sqrt(2 D tau) / m_min / sqrt(T / dim), the velocity change per "
        "window of the lightest grain over the thermal speed per component; "
        "collisions_per_window = 2 collisions / N / simulated time x tau; a warning above the "
        "limits (docs/event-driven.md)");
}
