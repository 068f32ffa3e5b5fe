/* msd: the mean-square displacement <|r_i(t0 + tau) - r_i(t0)|^2> over
 * particles and time origins (every sample is an origin; lags tau = l * Delta,
 * l = 1 .. msd_lags, Delta the sampling interval), with block-averaging errors
 * over origins, and the self-diffusion coefficient from the long-time slope,
 * MSD = 2 dim D_self tau + c fitted over the upper half of the lags.
 *
 * Positions are unwrapped here: between consecutive samples a particle's
 * displacement is taken under the minimum image (ring of length L in 1D, box in
 * 2D, cube in 3D) and accumulated, so crossings of the periodic boundary are followed as
 * long as no particle moves more than L/2 between samples; displacements beyond
 * L/4 are counted and reported ("suspect_jumps": sample more often).
 *
 * Known answers: a free RFM particle (no collisions) has v(t) a Wiener process
 * with <dv^2> = 2 D t / M^2 per component (2.15, 2.22), so from an origin t0
 * with <v(t0)^2> = v2 per component, MSD per component = v2 tau^2 + (2 D / M^2)
 * tau^3 / 3: it has no diffusive regime (D_self is not defined without
 * dissipation). A Langevin particle with friction gamma and temperature T has
 * D_self = T / (M gamma). Memory is N * msd_lags.
 *
 * A mixture of species ([species] lists, docs/mixtures.md) also averages each species' grains
 * and fits each species' D_self the same way (summary.json -> msd.species_D_self). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_lag.h"
#include "analysis/obs_util.h"
#include "io/plot.h"

typedef struct msd_params {
    int msd_lags;
} msd_params;

static const gr_param params[] = {
    {"msd_lags", "", GR_PARAM_INT, 50, 2, GR_LAG_MAX, false, false,
     "lags of the mean-square displacement, in sampling intervals (memory N x "
     "msd_lags)",
     offsetof(msd_params, msd_lags)},
};

typedef struct msd {
    int n, dim;
    double L;
    double *ux, *uy, *px, *py; /* unwrapped positions, last raw positions */
    double *uz, *pz;           /* 3D only (NULL otherwise) */
    int64_t jumps;
    gr_lag lag;
} msd;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    msd *m = state;
    m->n = setup->N;
    m->dim = setup->dim;
    m->L = setup->L;
    size_t n = (size_t)m->n;
    m->ux = gr_obs_calloc(m, n, sizeof(double));
    m->uy = gr_obs_calloc(m, n, sizeof(double));
    m->px = gr_obs_calloc(m, n, sizeof(double));
    m->py = gr_obs_calloc(m, n, sizeof(double));
    if (m->dim == 3) {
        m->uz = gr_obs_calloc(m, n, sizeof(double));
        m->pz = gr_obs_calloc(m, n, sizeof(double));
    }
    const msd_params *a = params_block;
    int rc = gr_lag_init_owned(m, &m->lag, m->n, m->dim, a->msd_lags, GR_LAG_DISPLACEMENT2, err);
    return rc || setup->n_species < 2 ? rc : gr_lag_species(&m->lag, setup->n_species, err);
}

static double step(double now, double *prev, double L, int64_t *jumps)
{
    double d = now - *prev;
    d -= L * rint(d / L);
    *jumps += fabs(d) > 0.25 * L;
    *prev = now;
    return d;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    msd *m = state;
    int bad = gr_obs_check_frame("msd", p, m->n, err);
    if (bad) {
        return bad;
    }
    for (int i = 0; i < m->n; i++) {
        if (m->lag.frames == 0) {
            m->ux[i] = m->px[i] = p->x[i];
            m->uy[i] = m->py[i] = p->dim >= 2 ? p->y[i] : 0.0;
            if (p->dim == 3) {
                m->uz[i] = m->pz[i] = p->z[i];
            }
            continue;
        }
        m->ux[i] += step(p->x[i], &m->px[i], m->L, &m->jumps);
        if (p->dim >= 2) {
            m->uy[i] += step(p->y[i], &m->py[i], m->L, &m->jumps);
        }
        if (p->dim == 3) {
            m->uz[i] += step(p->z[i], &m->pz[i], m->L, &m->jumps);
        }
    }
    return m->lag.ns ? gr_lag_add_species(&m->lag, "msd", p, m->ux, p->dim >= 2 ? m->uy : NULL,
                                          m->uz, t, err)
                     : gr_lag_add(&m->lag, m->ux, p->dim >= 2 ? m->uy : NULL, m->uz, t, err);
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    msd *m = state;
    const char *what = "mean-square displacement <|r(t0 + tau) - r(t0)|^2> (m^2) "
                       "of unwrapped positions, averaged over "
                       "particles and time origins (every sample); errors from "
                       "block averaging over origins";
    cJSON *j = cJSON_AddObjectToObject(out->summary, "msd");
    int rc = gr_obs_lag_csv(out, &m->lag, "msd.csv", what,
                            "tau [s],msd [m2],msd_stderr [m2],origins [1]", j, err);
    if (rc) {
        return rc;
    }
    cJSON_AddNumberToObject(j, "suspect_jumps", (double)m->jumps);
    gr_fit fit;
    gr_error ferr = {0};
    const int lo = m->lag.lags / 2 > 1 ? m->lag.lags / 2 : 1;
    char fitline[400] = "";
    if (gr_lag_fit_line(&m->lag, lo, m->lag.lags, &fit, &ferr) == GR_OK) {
        cJSON *d = cJSON_AddObjectToObject(j, "D_self");
        gr_obs_add_number(d, "value", fit.p[1] / (2.0 * m->dim));
        gr_obs_add_number(d, "error", fit.err[1] / (2.0 * m->dim));
        gr_obs_add_number(d, "chi2_red", fit.chi2_red);
        gr_obs_add_number(d, "tau_min", lo * gr_lag_interval(&m->lag));
        gr_obs_add_number(d, "tau_max", m->lag.lags * gr_lag_interval(&m->lag));
        cJSON_AddStringToObject(d, "note",
                                "MSD = 2 dim D_self tau + c over the upper half of "
                                "the lags; the lags are "
                                "correlated, so the error is indicative");
        char legend[120];
        gr_plot_legend_value("linear fit, D_{self} (m^2/s)", fit.p[1] / (2.0 * m->dim),
                             fit.err[1] / (2.0 * m->dim), legend, sizeof legend);
        snprintf(fitline, sizeof fitline,
                 ", [%.6g:%.6g] %.8g + %.8g * x with lines lw 3 lt 2 title '%s'",
                 lo * gr_lag_interval(&m->lag), m->lag.lags * gr_lag_interval(&m->lag), fit.p[0],
                 fit.p[1], legend);
    } else {
        cJSON_AddStringToObject(j, "D_self", ferr.message);
    }
    if (m->lag.ns) { /* each species' D_self, fitted over the same lags */
        cJSON *d = cJSON_AddObjectToObject(j, "species_D_self");
        cJSON *jv = cJSON_AddArrayToObject(d, "value"), *je = cJSON_AddArrayToObject(d, "error");
        for (int a = 0; a < m->lag.ns; a++) {
            const gr_lag v = gr_lag_species_view(&m->lag, a);
            gr_fit f = {0};
            const bool fitted = gr_lag_fit_line(&v, lo, v.lags, &f, &ferr) == GR_OK;
            const double D = f.p[1] / (2.0 * m->dim), e = f.err[1] / (2.0 * m->dim);
            cJSON_AddItemToArray(jv, fitted && isfinite(D) ? cJSON_CreateNumber(D)
                                                           : cJSON_CreateNull());
            cJSON_AddItemToArray(je, fitted && isfinite(e) ? cJSON_CreateNumber(e)
                                                           : cJSON_CreateNull());
        }
    }
    if (out->plots && m->lag.frames > 1) {
        char body[900];
        snprintf(
            body, sizeof body,
            "set logscale xy\nset format xy '10^{%%L}'\nset xlabel 'lag tau (s)'\nset ylabel 'MSD "
            "(m^2)'\nset key top left\n"
            "set title \"Mean-square displacement\\n{/*0.75 unwrapped positions; line: the fit "
            "over its window}\"\n"
            "plot 'msd.csv' skip 1 using 1:($4>0&&$1>0?$2:1/0):3 with "
            "yerrorbars title 'MSD'%s",
            fitline);
        gr_obs_plot(out, "msd.png", body);
    }
    return GR_OK;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    msd *m = state;
    gr_blob_io_f64s(io, m->ux, m->n);
    gr_blob_io_f64s(io, m->uy, m->n);
    gr_blob_io_f64s(io, m->px, m->n);
    gr_blob_io_f64s(io, m->py, m->n);
    if (m->dim == 3) {
        gr_blob_io_f64s(io, m->uz, m->n);
        gr_blob_io_f64s(io, m->pz, m->n);
    }
    gr_blob_io_i64(io, &m->jumps);
    gr_lag_io(io, &m->lag, "msd_lags");
    return GR_OK;
}

const gr_observable_type gr_obs_msd = {
    .name = "msd",
    .summary = "mean-square displacement of unwrapped positions and the "
               "self-diffusion coefficient (long-time slope)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(msd_params),
    .state_size = sizeof(msd),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
