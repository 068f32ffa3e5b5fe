/* vacf: the velocity autocorrelation function per component,
 *     C(tau) = <v_i(t0) . v_i(t0 + tau)> / dim,
 * over particles and time origins (every sample; tau = l Delta, l = 0 ..
 * vacf_lags), with block-averaging errors over origins, and its Green-Kubo
 * integral D_GK = int_0^tau_max C(tau) dtau      (trapezoid rule over the
 * lags), the self-diffusion coefficient to compare with msd's long-time slope
 * (D_self = MSD / (2 dim tau)). Velocities are the lab-frame ones (the
 * symmetrised noise keeps the total momentum at zero).
 *
 * Known answers: free RFM particles (no collisions) have Wiener velocities,
 * independent increments of zero mean, so C(tau) = <v(t0)^2> per component at
 * every lag (flat); a Langevin particle (friction gamma, temperature T) has C =
 * (T/M) exp(-gamma tau) and D_GK = T/(M gamma) when tau_max >> 1/gamma. The
 * error of D_GK adds the lags' errors in quadrature (the lags are correlated,
 * so it is indicative). Memory is N * vacf_lags.
 *
 * A mixture of species ([species] lists, docs/mixtures.md) also averages each species' grains:
 * summary.json -> vacf.species_D_green_kubo and species_C0_per_component. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_lag.h"
#include "analysis/obs_util.h"

typedef struct vacf_params {
    int vacf_lags;
} vacf_params;

static const gr_param params[] = {
    {"vacf_lags", "", GR_PARAM_INT, 50, 2, GR_LAG_MAX, false, false,
     "lags of the velocity autocorrelation, in sampling intervals (memory N x "
     "vacf_lags)",
     offsetof(vacf_params, vacf_lags)},
};

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    const vacf_params *a = params_block;
    int rc = gr_lag_init_owned(state, state, setup->N, setup->dim, a->vacf_lags, GR_LAG_DOT, err);
    return rc || setup->n_species < 2 ? rc : gr_lag_species(state, setup->n_species, err);
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    gr_lag *g = state;
    int bad = gr_obs_check_frame("vacf", p, g->n, err);
    if (bad) {
        return bad;
    }
    return g->ns
               ? gr_lag_add_species(g, "vacf", p, p->vx, p->dim >= 2 ? p->vy : NULL, p->vz, t, err)
               : gr_lag_add(g, p->vx, p->dim >= 2 ? p->vy : NULL, p->vz, t, err);
}

/* The largest lag with at least 2 time origins (the run may be shorter than
 * vacf_lags). */
static int last_lag(const gr_lag *g)
{
    int last = 0;
    for (int l = 1; l <= g->lags; l++) {
        int64_t c;
        gr_lag_mean(g, l, NULL, &c);
        last = c >= 2 ? l : last;
    }
    return last;
}

/* Green-Kubo: the trapezoid integral of C up to lag `last` (lag means sum the
 * components: / dim). */
static double green_kubo(const gr_lag *g, int last, double *error)
{
    const double dt = gr_lag_interval(g);
    double sum = 0.0, var = 0.0;
    for (int l = 0; l <= last; l++) {
        double e, v = gr_lag_mean(g, l, &e, NULL);
        double w = (l == 0 || l == last ? 0.5 : 1.0) * dt / g->dim;
        sum += w * v;
        var += w * w * (isfinite(e) ? e * e : 0.0);
    }
    *error = sqrt(var);
    return last > 0 ? sum : (double)NAN;
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    gr_lag *g = state;
    const char *what = "velocity autocorrelation <v(t0) . v(t0 + tau)> summed "
                       "over components (m^2/s^2; / dim for "
                       "C(tau) per component), averaged over particles and time "
                       "origins; block-averaging errors";
    cJSON *j = cJSON_AddObjectToObject(out->summary, "vacf");
    int rc = gr_obs_lag_csv(out, g, "vacf.csv", what,
                            "tau [s],vv [m2 s-2],vv_stderr [m2 s-2],origins [1]", j, err);
    if (rc) {
        return rc;
    }
    const int last = last_lag(g);
    double e, D = green_kubo(g, last, &e);
    cJSON *d = cJSON_AddObjectToObject(j, "D_green_kubo");
    gr_obs_add_number(d, "value", D);
    gr_obs_add_number(d, "error", e);
    gr_obs_add_number(d, "tau_max", last * gr_lag_interval(g));
    int64_t c0;
    double v0 = gr_lag_mean(g, 0, NULL, &c0), vl = gr_lag_mean(g, last, NULL, NULL);
    gr_obs_add_number(j, "C0_per_component", c0 ? v0 / g->dim : (double)NAN);
    gr_obs_add_number(j, "C_end_over_C0", c0 && last > 0 ? vl / v0 : (double)NAN);
    if (g->ns) { /* each species' Green-Kubo integral and C(0), up to the same lag */
        cJSON *ds = cJSON_AddObjectToObject(j, "species_D_green_kubo");
        cJSON *jv = cJSON_AddArrayToObject(ds, "value"), *je = cJSON_AddArrayToObject(ds, "error");
        cJSON *jc = cJSON_AddArrayToObject(j, "species_C0_per_component");
        for (int a = 0; a < g->ns; a++) {
            const gr_lag v = gr_lag_species_view(g, a);
            double ea, Da = green_kubo(&v, last, &ea);
            const double c = c0 ? gr_lag_mean(&v, 0, NULL, NULL) / g->dim : (double)NAN;
            cJSON_AddItemToArray(jv, isfinite(Da) ? cJSON_CreateNumber(Da) : cJSON_CreateNull());
            cJSON_AddItemToArray(je, isfinite(ea) ? cJSON_CreateNumber(ea) : cJSON_CreateNull());
            cJSON_AddItemToArray(jc, isfinite(c) ? cJSON_CreateNumber(c) : cJSON_CreateNull());
        }
    }
    if (out->plots && g->frames > 1) {
        gr_obs_plot(out, "vacf.png",
                    "set xlabel 'lag tau (s)'\nset ylabel 'C(tau) / C(0)'\nset "
                    "title 'Velocity autocorrelation'\n"
                    "stats 'vacf.csv' skip 1 every ::0::0 using 2 nooutput\nc0 = "
                    "STATS_max\n"
                    "plot 'vacf.csv' skip 1 using 1:($2/c0):($3/c0) with "
                    "yerrorbars title 'C(tau) / C(0)', "
                    "0 lc rgb 'gray' notitle");
    }
    return GR_OK;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    gr_lag_io(io, state, "vacf_lags");
    return GR_OK;
}

const gr_observable_type gr_obs_vacf = {
    .name = "vacf",
    .summary = "velocity autocorrelation C(tau) and its Green-Kubo integral "
               "(self-diffusion, compare with msd)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(vacf_params),
    .state_size = sizeof(gr_lag),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
