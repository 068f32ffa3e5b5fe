/* The calibration run of `granule cost`: the scene at a given time step on this machine, from
 * its start, timed in blocks of simulated time; the wall time of a whole run is predicted from
 * the median block and its uncertainty from the spread of the blocks (include/granule/cost.h). */
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "granule/cost.h"
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

int gr_cost_calibrate(const gr_scene *scene, double dt, double seconds, gr_cost_answer *out, gr_error *err)
{
    gr_scene sc = *scene;
    sc.dt = dt;
    sc.force_dt = true;
    gr_sim *sim;
    if (gr_sim_create(&sc, &sim, err)) {
        return err->code;
    }
    /* a first block of ~1000 particle-steps' worth sizes the blocks: MIN_BLOCKS or more in the budget */
    int64_t chunk = 1 + 1000 / (sc.N > 0 ? sc.N : 1);
    double t0 = now();
    int rc = gr_sim_step(sim, chunk, err);
    double first = now() - t0;
    int64_t block_steps = chunk;
    if (first > 0.0) {
        block_steps = (int64_t)fmax(1.0, (double)chunk * (seconds / MIN_BLOCKS) / first);
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
    }
    const double wall = now() - start;
    gr_sim_free(sim);
    if (rc != GR_OK) {
        return rc;
    }
    qsort(rate, (size_t)n, sizeof rate[0], cmp_double);
    out->blocks = n;
    out->wall_per_simulated = quantile(rate, n, 0.5);
    out->wall_per_simulated_err = 0.5 * (quantile(rate, n, 0.84) - quantile(rate, n, 0.16));
    out->predicted_wall = out->wall_per_simulated * out->simulated_seconds;
    out->predicted_wall_err = out->wall_per_simulated_err * out->simulated_seconds;
    out->particle_steps_per_second = wall > 0.0 ? (double)steps * sc.N / wall : (double)NAN;
    return GR_OK;
}
