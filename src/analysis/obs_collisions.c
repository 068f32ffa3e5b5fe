/* collisions: the collision rate per particle and the distribution of the times
 * between a particle's successive collisions, from the engine's contact events
 * (a collision is a particle touching another for the first time since it was
 * last free, kind = +1), so it needs a run: `granule analyse` has no events and
 * reports that. The rate is counted per sampling interval, nu = (collisions in
 * the interval) / (N * interval), and time-averaged with block-averaging
 * errors; the times tau between collisions of the same particle are binned in
 * collision_bins logarithmic bins from 1e-9 s to 1e5 s (densities with sqrt(X)
 * errors). For a Poisson process of rate nu the density is nu exp(-nu tau) and
 * <tau> = 1 / nu. Memory: one time per particle and the bins.
 *
 * A mixture of species ([species] lists, docs/mixtures.md) also counts each species' collisions:
 * nu_s = (collisions of species-s grains in the interval) / (N_s * interval), time-averaged the
 * same way (summary.json -> collisions.species_rate_per_particle); weighted by N_s / N they add
 * up to nu. A grain's species is the first sample's. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_util.h"
#include "granule/analysis.h"
#include "granule/sim.h"

#define TAU_LO 1e-9 /* s */
#define TAU_HI 1e5

typedef struct collisions_params {
    int collision_bins;
} collisions_params;

static const gr_param params[] = {
    {"collision_bins", "", GR_PARAM_INT, 112, 4, 10000, false, false,
     "(collisions) log bins of the times between a particle's collisions, 1e-9 "
     "s .. 1e5 s",
     offsetof(collisions_params, collision_bins)},
};

typedef struct collisions {
    int n;
    double *last; /* time of each particle's last collision; NAN before the first */
    double t_first, t_prev, t_prev2; /* first sample, the last two samples */
    int64_t frames;
    int64_t since, total; /* collisions since the previous sample, and in all */
    double tau_sum;
    int64_t tau_n;
    gr_histogram h;
    gr_blocking rate;
    /* a mixture (ns >= 2; 0 for one species): each grain's species (the first frame's), the
     * species' grains, collisions since the previous sample and in all, and their rates */
    int ns;
    int *species;
    int count[GR_MAX_SPECIES];
    int64_t since_s[GR_MAX_SPECIES], total_s[GR_MAX_SPECIES];
    gr_blocking rate_s[GR_MAX_SPECIES];
} collisions;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    collisions *c = state;
    const collisions_params *a = params_block;
    c->n = setup->N;
    c->last = gr_obs_calloc(c, (size_t)c->n, sizeof(double));
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        c->ns = setup->n_species;
        c->species = gr_obs_calloc(c, (size_t)c->n + 1, sizeof(int));
        int rc = gr_obs_alloc_ok(c, err);
        if (rc) {
            return rc;
        }
    }
    int rc = gr_obs_histogram(c, &c->h, a->collision_bins, TAU_LO, TAU_HI, true, err);
    if (rc || !c->last) {
        return rc;
    }
    for (int i = 0; i < c->n; i++) {
        c->last[i] = NAN;
    }
    return GR_OK;
}

static int events(void *state, const gr_contact_event *ev, int64_t n, gr_error *err)
{
    collisions *c = state;
    for (int64_t k = 0; k < n; k++) {
        int i = ev[k].i;
        if (i < 0 || i >= c->n) {
            return GR_FAIL(err, GR_EINVAL, "collisions: event for particle %d of %d", i, c->n);
        }
        if (ev[k].kind <= 0 || c->frames == 0 || !(ev[k].t > c->t_first)) {
            continue; /* count from the first sample on */
        }
        if (isfinite(c->last[i])) {
            double tau = ev[k].t - c->last[i];
            gr_histogram_add(&c->h, tau, 1.0);
            c->tau_sum += tau;
            c->tau_n++;
        }
        c->last[i] = ev[k].t;
        c->since++;
        c->total++;
        if (c->ns) {
            c->since_s[c->species[i]]++;
            c->total_s[c->species[i]]++;
        }
    }
    return GR_OK;
}

/* The events of the interval (t_{k-1}, t_k] arrive after the sample at t_k
 * (src/app/run.c): at sample k + 1 `since` holds those of the interval that
 * ended at the previous sample. */
static void close_interval(collisions *c)
{
    if (c->frames >= 2 && c->t_prev > c->t_prev2) {
        gr_blocking_add(&c->rate, (double)c->since / (c->n * (c->t_prev - c->t_prev2)));
        for (int a = 0; a < c->ns; a++) {
            if (c->count[a] > 0) {
                gr_blocking_add(&c->rate_s[a],
                                (double)c->since_s[a] / (c->count[a] * (c->t_prev - c->t_prev2)));
            }
        }
    }
    c->since = 0;
    for (int a = 0; a < c->ns; a++) {
        c->since_s[a] = 0;
    }
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    collisions *c = state;
    if (c->ns && c->frames == 0) { /* a mixture: the grains' species, from the first frame */
        int rc = gr_obs_frame_species("collisions", p, c->ns, c->n, c->species, err);
        if (rc) {
            return rc;
        }
        for (int i = 0; i < c->n; i++) {
            c->count[c->species[i]]++;
        }
    }
    close_interval(c);
    if (c->frames == 0) {
        c->t_first = t;
    }
    c->t_prev2 = c->t_prev;
    c->t_prev = t;
    c->frames++;
    return GR_OK;
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    collisions *c = state;
    cJSON *j = gr_obs_summary(out, "collisions", "collisions.csv");
    close_interval(c); /* the last interval's events came after the last sample */
    cJSON_AddNumberToObject(j, "collisions", (double)c->total);
    double e = gr_blocking_stderr(&c->rate, NULL, NULL);
    bool any = c->total > 0;
    gr_obs_add_number(j, "rate_per_particle", any ? gr_blocking_mean(&c->rate) : (double)NAN);
    gr_obs_add_number(j, "rate_per_particle_error",
                      !any          ? (double)NAN
                      : isfinite(e) ? e
                                    : gr_blocking_stderr_at(&c->rate, 0));
    gr_obs_add_number(j, "mean_time_between", c->tau_n ? c->tau_sum / c->tau_n : (double)NAN);
    cJSON_AddNumberToObject(j, "intervals", (double)c->tau_n);
    if (c->total == 0) {
        gr_obs_note_no_events(j, "collision events");
    }
    if (c->ns) {
        cJSON *jn = cJSON_AddArrayToObject(j, "species_collisions");
        cJSON *jr = cJSON_AddArrayToObject(j, "species_rate_per_particle");
        cJSON *je = cJSON_AddArrayToObject(j, "species_rate_per_particle_error");
        for (int a = 0; a < c->ns; a++) {
            const double ea = gr_blocking_stderr(&c->rate_s[a], NULL, NULL);
            const bool some = c->total_s[a] > 0;
            cJSON_AddItemToArray(jn, cJSON_CreateNumber((double)c->total_s[a]));
            cJSON_AddItemToArray(jr, some ? cJSON_CreateNumber(gr_blocking_mean(&c->rate_s[a]))
                                          : cJSON_CreateNull());
            cJSON_AddItemToArray(
                je, !some          ? cJSON_CreateNull()
                    : isfinite(ea) ? cJSON_CreateNumber(ea)
                                   : cJSON_CreateNumber(gr_blocking_stderr_at(&c->rate_s[a], 0)));
        }
    }
    const gr_obs_table t = {
        .name = "collisions.csv",
        .what = "times tau (s) between successive collisions of the same "
                "particle, density per s in log "
                "bins, sqrt(X) errors",
        .columns = "tau_lo [s],tau_hi [s],tau [s],count [1],density [s-1],density_error [s-1]",
        .rows = gr_obs_histogram_rows,
        .ctx = &c->h,
        .png = c->tau_n > 0 ? "collisions.png" : NULL,
        .plot = "set logscale xy\nset format xy '10^{%L}'\nset xlabel 'time between collisions tau "
                "(s)'\nset ylabel 'P(tau) (1/s)'\n"
                "set title 'Times between collisions of a particle'\n"
                "plot 'collisions.csv' skip 1 using ($4>0?$3:1/0):5:6 with "
                "yerrorbars title 'P(tau)'",
    };
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    collisions *c = state;
    gr_blob_io_f64s(io, c->last, c->n);
    gr_blob_io_f64(io, &c->t_first);
    gr_blob_io_f64(io, &c->t_prev);
    gr_blob_io_f64(io, &c->t_prev2);
    gr_blob_io_i64(io, &c->frames);
    gr_blob_io_i64(io, &c->since);
    gr_blob_io_i64(io, &c->total);
    gr_blob_io_f64(io, &c->tau_sum);
    gr_blob_io_i64(io, &c->tau_n);
    gr_obs_io_histogram(io, &c->h);
    gr_obs_io_blockings(io, &c->rate, 1);
    if (c->ns) { /* a mixture's (one species: the checkpoint as before) */
        gr_obs_io_species(io, "collisions", c->species, c->n, c->ns);
        for (int a = 0; a < c->ns; a++) {
            gr_blob_io_int(io, &c->count[a]);
            gr_blob_io_i64(io, &c->since_s[a]);
            gr_blob_io_i64(io, &c->total_s[a]);
            gr_obs_io_blockings(io, &c->rate_s[a], 1);
        }
    }
    return GR_OK;
}

const gr_observable_type gr_obs_collisions = {
    .name = "collisions",
    .summary = "collision rate per particle and the distribution of times "
               "between a particle's collisions; needs a run",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(collisions_params),
    .state_size = sizeof(collisions),
    .init = init,
    .sample = sample,
    .finish = finish,
    .events = events,
    .io = io,
};
