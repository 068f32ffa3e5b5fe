/* The calibration run of `granule cost`: the scene at a given time step on this machine, from
 * its start, timed in blocks of simulated time, once per integrator (Verlet, and the hybrid over
 * a few windows); the wall time of a whole run is predicted from the cheapest one's median block
 * and its uncertainty from the spread of its blocks (include/granule/cost.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <time.h>

#include "granule/cost.h"
#include "granule/integrator.h"
#include "granule/sim.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* the q-quantile of sorted v[0..n) (linear interpolation) */
static double quantile(const double *v, int n, double q)
{
    double pos = q * (n - 1);
    int i = (int)floor(pos);
    return i + 1 < n ? v[i] + (pos - i) * (v[i + 1] - v[i]) : v[n - 1];
}

enum { MAX_BLOCKS = 64, MIN_BLOCKS = 8 };

/* Time one integrator for `seconds` of wall time (at least MIN_BLOCKS blocks). */
static int time_option(const gr_scene *sc, double seconds, gr_cost_option *o, gr_error *err)
{
    gr_sim *sim;
    if (gr_sim_create(sc, &sim, err)) {
        return err->code;
    }
    /* a first block of ~1000 particle-steps' worth sizes the blocks: MIN_BLOCKS or more in the budget */
    int64_t chunk = 1 + 1000 / (sc->N > 0 ? sc->N : 1);
    if (sc->integrator == gr_integrator_find("hybrid")) {
        const int64_t m = (int64_t)llround(sc->kick_interval / sc->dt); /* whole windows */
        chunk = m * (1 + chunk / m);
    }
    double t0 = now();
    int rc = gr_sim_step(sim, chunk, err);
    double first = now() - t0;
    int64_t block_steps = chunk;
    if (first > 0.0) {
        block_steps = (int64_t)fmax((double)chunk, (double)chunk * (seconds / MIN_BLOCKS) / first);
        block_steps -= block_steps % chunk;
    }
    double rate[MAX_BLOCKS];
    int n = 0;
    const double start = now();
    int64_t steps = 0;
    while (rc == GR_OK && n < MAX_BLOCKS && (n < MIN_BLOCKS || now() - start < seconds)) {
        double sim_t = gr_sim_time(sim), w = now();
        rc = gr_sim_step(sim, block_steps, err);
        double dw = now() - w, ds = gr_sim_time(sim) - sim_t;
        if (rc == GR_OK && ds > 0.0) {
            rate[n++] = dw / ds;
            steps += block_steps;
        }
        /* resize the blocks to seconds / MIN_BLOCKS each: a run's cost per step changes as it
         * leaves its start (the hybrid's first windows find every particle free) */
        if (dw > 0.0) {
            const double want = (double)block_steps * fmin(4.0, (seconds / MIN_BLOCKS) / dw);
            block_steps = (int64_t)fmax((double)chunk, want);
            block_steps -= block_steps % chunk;
        }
    }
    const double wall = now() - start;
    gr_sim_free(sim);
    if (rc != GR_OK) {
        return rc;
    }
    qsort(rate, (size_t)n, sizeof rate[0], cmp_double);
    o->ok = true;
    o->blocks = n;
    o->wall_per_simulated = quantile(rate, n, 0.5);
    o->wall_per_simulated_err = 0.5 * (quantile(rate, n, 0.84) - quantile(rate, n, 0.16));
    o->particle_steps_per_second = wall > 0.0 ? (double)steps * sc->N / wall : (double)NAN;
    return GR_OK;
}

int gr_cost_calibrate(const gr_scene *scene, double dt, double seconds, gr_cost_answer *out,
                      gr_error *err)
{
    const gr_integrator_type *verlet = gr_integrator_find("verlet"),
                             *hybrid = gr_integrator_find("hybrid");
    /* the options: Verlet, then the hybrid (the scene's own window first, if it is a hybrid scene) */
    double windows[GR_COST_MAX_OPTIONS];
    int nw = 0;
    if (scene->integrator == hybrid && scene->kick_interval > 0.0) {
        windows[nw++] = dt * fmax(1.0, round(scene->kick_interval / dt));
    }
    const double per[] = {10.0, 30.0, 100.0};
    for (int k = 0; k < 3 && nw < GR_COST_MAX_OPTIONS - 1; k++) {
        if (!(nw && fabs(windows[0] - per[k] * dt) < 0.5 * dt)) {
            windows[nw++] = per[k] * dt;
        }
    }
    out->n_options = 0;
    out->best_option = -1;
    const double share = seconds / (1 + nw);
    for (int k = 0; k <= nw; k++) {
        gr_cost_option *o = &out->option[out->n_options++];
        memset(o, 0, sizeof *o);
        o->wall_per_simulated = o->wall_per_simulated_err = o->particle_steps_per_second = NAN;
        gr_scene sc = *scene;
        sc.dt = dt;
        sc.force_dt = true;
        sc.integrator = k == 0 ? verlet : hybrid;
        o->window = k == 0 ? 0.0 : windows[k - 1];
        sc.kick_interval = k == 0 ? scene->kick_interval : o->window;
        snprintf(o->integrator, sizeof o->integrator, "%s", sc.integrator->name);
        gr_error e = {0};
        int rc = time_option(&sc, share, o, &e);
        if (rc && k == 0) {
            *err = e; /* Verlet is the reference: the scene itself does not run */
            return rc;
        }
        if (rc) { /* a scene the hybrid cannot run (history springs, event rules, ...): say why */
            snprintf(o->note, sizeof o->note, "%s", e.message);
        } else if (out->best_option < 0 ||
                   o->wall_per_simulated < out->option[out->best_option].wall_per_simulated) {
            out->best_option = out->n_options - 1;
        }
    }
    const gr_cost_option *b = &out->option[out->best_option];
    out->blocks = b->blocks;
    out->wall_per_simulated = b->wall_per_simulated;
    out->wall_per_simulated_err = b->wall_per_simulated_err;
    out->predicted_wall = out->wall_per_simulated * out->simulated_seconds;
    out->predicted_wall_err = out->wall_per_simulated_err * out->simulated_seconds;
    out->particle_steps_per_second = b->particle_steps_per_second;
    return GR_OK;
}
