/* freepath: the free-path distribution P_l(l) (sec. 4.3): l_i = |r_i(t0 + tau) - r_i(t0)| (4.18),
 * the displacement of a particle between the end of one contact (it has no contact left) and the
 * start of the next (it touches a particle again), from the engine's contact events, so soft and
 * event-driven runs are measured alike. Histogram in logarithmic bins of l / d with sqrt(X)
 * errors, and a fit of the tail form (4.25) P_l(l) = A0 exp(-C l^(D_f - 1)) l^(D_f - 2).
 * In 2D and 3D the displacement is taken under the minimum image: a free path longer than L/2 is
 * folded (only possible in very dilute systems; the count of paths longer than L/4 is reported).
 * In 3D the path is |r| of the three components, binned up to sqrt(3) L / 2.
 * A mixture of species lists (docs/mixtures.md) also gives each species' mean free path: every
 * grain's paths are summed on their own, and at the end grouped by the grain's species (the first
 * sample's), so weighted by their numbers of paths the species' means are the pooled mean. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "analysis/obs_util.h"
#include "io/plot.h"
#include "granule/analysis.h"

typedef struct freepath_params {
    int freepath_bins;
    double freepath_min;
} freepath_params;

static const gr_param params[] = {
    {"freepath_bins", "", GR_PARAM_INT, 60, 4, 10000, false, false,
     "logarithmic bins of the free-path distribution P_l(l) (4.18)",
     offsetof(freepath_params, freepath_bins)},
    {"freepath_min", "d", GR_PARAM_DOUBLE, 1e-3, 0, 1e3, true, false,
     "smallest binned free path, in diameters", offsetof(freepath_params, freepath_min)},
};

typedef struct freepath {
    int n, dim;
    double L, d;
    bool mixture; /* d is the mixture's mean collision diameter (gr_obs_collision_diameter) */
    double *x0, *y0, *z0;      /* z0: 3D only */
    unsigned char *free_since; /* 1: the particle's last contact ended at (x0, y0, z0) */
    gr_histogram h;            /* in units of d */
    double sum, long_paths;
    int64_t paths;
    /* a mixture of species lists (ns >= 2; 0 otherwise): each grain's species (the first frame's,
     * once `frames` > 0), the sum of its free paths (m) and their number */
    int ns, frames;
    int *species;
    double *grain_sum, *grain_paths;
} freepath;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    freepath *f = state;
    const freepath_params *a = params_block;
    f->n = setup->N;
    f->dim = setup->dim;
    f->L = setup->L;
    f->d = gr_obs_collision_diameter(setup); /* 2 radius; a mixture's mean over random pairs */
    f->mixture = setup->sizes;
    f->x0 = gr_obs_calloc(f, (size_t)f->n, sizeof(double));
    f->y0 = gr_obs_calloc(f, (size_t)f->n, sizeof(double));
    f->z0 = f->dim == 3 ? gr_obs_calloc(f, (size_t)f->n, sizeof(double)) : NULL;
    f->free_since = gr_obs_calloc(f, (size_t)f->n, 1);
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        f->ns = setup->n_species;
        f->species = gr_obs_calloc(f, (size_t)f->n, sizeof(int));
        f->grain_sum = gr_obs_calloc(f, (size_t)f->n, sizeof(double));
        f->grain_paths = gr_obs_calloc(f, (size_t)f->n, sizeof(double));
    }
    double hi = (f->dim == 3 ? 0.5 * sqrt(3.0) : f->dim == 2 ? 0.5 * sqrt(2.0) : 1.0) * f->L / f->d;
    return gr_obs_histogram(f, &f->h, a->freepath_bins, a->freepath_min, hi, true, err);
}

static int events(void *state, const gr_contact_event *ev, int64_t n, gr_error *err)
{
    (void)err;
    freepath *f = state;
    for (int64_t k = 0; k < n; k++) {
        int i = ev[k].i;
        if (ev[k].kind < 0) {
            f->x0[i] = ev[k].x;
            f->y0[i] = ev[k].y;
            if (f->dim == 3) {
                f->z0[i] = ev[k].z;
            }
            f->free_since[i] = 1;
        } else if (f->free_since[i]) {
            double dx = ev[k].x - f->x0[i], dy = ev[k].y - f->y0[i];
            if (f->dim >= 2) {
                dx -= f->L * rint(dx / f->L);
                dy -= f->L * rint(dy / f->L);
            }
            double l = sqrt(dx * dx + dy * dy); /* eq. 4.18 */
            if (f->dim == 3) {
                double dz = ev[k].z - f->z0[i];
                dz -= f->L * rint(dz / f->L);
                l = sqrt(dx * dx + dy * dy + dz * dz);
            }
            gr_histogram_add(&f->h, l / f->d, 1.0);
            f->sum += l;
            f->long_paths += l > 0.25 * f->L;
            f->paths++;
            f->free_since[i] = 0;
            if (f->ns) {
                f->grain_sum[i] += l;
                f->grain_paths[i] += 1.0;
            }
        }
    }
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    freepath *f = state; /* built from contact events; a mixture's species from the first frame */
    if (f->ns && f->frames++ == 0) {
        return gr_obs_frame_species("freepath", p, f->ns, f->n, f->species, err);
    }
    return GR_OK;
}

/* (4.25) in units of d: P = A0 exp(-C l^(Df-1)) l^(Df-2), p = (ln A0, ln C, Df) */
static double tail(double l, const double *p, double *g, void *user)
{
    (void)user;
    double A0 = exp(p[0]), C = exp(p[1]), Df = p[2];
    double ll = log(l), u = exp((Df - 1.0) * ll);
    double y = A0 * exp(-C * u + (Df - 2.0) * ll);
    if (g) {
        g[0] = y;
        g[1] = -y * C * u;
        g[2] = y * (-C * u * ll + ll);
    }
    return y;
}

const char gr_obs_freepath_columns[] =
    "l_over_d_lo [1],l_over_d_hi [1],l_over_d [1],count [1],density [1],density_error [1]";

static int finish(void *state, const gr_output *out, gr_error *err)
{
    freepath *f = state;
    const gr_obs_table table = {
        .name = "freepath.csv",
        .what = "free-path distribution P_l(l) (4.18): l in units of d, density per unit l/d, "
                "sqrt(X) errors; "
                "paths from the end of a particle's last contact to the start of its next",
        .columns = gr_obs_freepath_columns,
        .rows = gr_obs_histogram_rows,
        .ctx = &f->h,
    };
    int rc = gr_obs_table_write(out, &table, err); /* the summary is written either way */
    cJSON *j = cJSON_AddObjectToObject(out->summary, "freepath");
    cJSON_AddNumberToObject(j, "paths", (double)f->paths);
    cJSON_AddNumberToObject(j, "mean_over_d", f->paths ? f->sum / f->paths / f->d : 0.0);
    if (f->mixture) {
        gr_obs_note_diameter(j, f->d, f->dim);
    }
    cJSON_AddNumberToObject(j, "longer_than_quarter_box", f->long_paths);
    if (f->ns && f->frames > 0) { /* each species' paths and their mean, in the same d */
        double sum[GR_MAX_SPECIES] = {0}, cnt[GR_MAX_SPECIES] = {0};
        for (int i = 0; i < f->n; i++) {
            sum[f->species[i]] += f->grain_sum[i];
            cnt[f->species[i]] += f->grain_paths[i];
        }
        cJSON *jn = cJSON_AddArrayToObject(j, "species_paths");
        cJSON *jm = cJSON_AddArrayToObject(j, "species_mean_over_d");
        for (int a = 0; a < f->ns; a++) {
            cJSON_AddItemToArray(jn, cJSON_CreateNumber(cnt[a]));
            cJSON_AddItemToArray(jm, cnt[a] > 0.0 ? cJSON_CreateNumber(sum[a] / cnt[a] / f->d)
                                                  : cJSON_CreateNull());
        }
    }
    cJSON_AddStringToObject(j, "file", "freepath.csv");
    if (f->paths == 0) {
        gr_obs_note_no_events(j, "free paths");
    }
    /* the tail fit over bins with at least 10 counts beyond the most probable free path */
    int peak = 0;
    for (int i = 0; i < f->h.nbins; i++) {
        peak = f->h.count[i] > f->h.count[peak] ? i : peak;
    }
    double x[10000], y[10000], s[10000];
    int m = 0;
    for (int i = peak; i < f->h.nbins && m < 10000; i++) {
        if (f->h.count[i] >= 10.0) {
            x[m] = gr_histogram_center(&f->h, i);
            y[m] = gr_histogram_density(&f->h, i);
            s[m] = gr_histogram_density_error(&f->h, i);
            m++;
        }
    }
    gr_fit fit;
    gr_error ferr = {0};
    bool fitted = false;
    if (m >= 5) {
        double p0[3] = {log(y[0] * pow(x[0], 0.4)), log(1.0 / pow(x[m / 2], 0.6)), 1.6};
        if (gr_fit_nonlinear(tail, NULL, x, y, s, m, 3, p0, &fit, &ferr) == GR_OK) {
            cJSON *t = cJSON_AddObjectToObject(j, "tail_fit_4_25");
            cJSON_AddNumberToObject(t, "D_f", fit.p[2]);
            cJSON_AddNumberToObject(t, "D_f_error", fit.err[2]);
            cJSON_AddNumberToObject(t, "C", exp(fit.p[1]));
            cJSON_AddNumberToObject(t, "chi2_red", fit.chi2_red);
            cJSON_AddNumberToObject(t, "l_min_over_d", x[0]);
            cJSON_AddNumberToObject(t, "l_max_over_d", x[m - 1]);
            cJSON_AddNumberToObject(t, "bins", m);
            cJSON_AddNumberToObject(t, "A0", exp(fit.p[0]));
            fitted = true;
        } else {
            cJSON_AddStringToObject(j, "tail_fit_4_25", ferr.message);
        }
    }
    if (!rc && out->plots && f->paths) {
        char body[1200], fitline[600] = "";
        if (fitted) {
            char legend[120];
            gr_plot_legend_value("fit (4.25), D_f", fit.p[2], fit.err[2], legend, sizeof legend);
            snprintf(fitline, sizeof fitline,
                     ", [%.6g:%.6g] %.8g * exp(-%.8g * x**(%.8g - 1)) * x**(%.8g - 2) with lines "
                     "lw 3 lt 2 title '%s'",
                     x[0], x[m - 1], exp(fit.p[0]), exp(fit.p[1]), fit.p[2], fit.p[2], legend);
        }
        snprintf(body, sizeof body,
                 "set logscale xy\nset xlabel 'free path l / d'\nset ylabel 'P_l(l)'\n"
                 "set title \"Distribution of free paths between contacts\\n{/*0.75 eq. (4.18); "
                 "fit of the tail (4.25)}\"\n"
                 "set samples 400\nplot 'freepath.csv' skip 1 using 3:($4>0?$5:1/0):6 with "
                 "yerrorbars lt 1 title 'P_l(l)'%s",
                 fitline);
        gr_obs_plot(out, "freepath.png", body);
    }
    return rc;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    freepath *f = state;
    gr_blob_io_f64s(io, f->x0, f->n);
    gr_blob_io_f64s(io, f->y0, f->n);
    if (f->dim == 3) {
        gr_blob_io_f64s(io, f->z0, f->n);
    }
    gr_blob_io_check(io, "N", f->n);
    gr_blob_io_bytes(io, f->free_since, (size_t)f->n);
    gr_obs_io_histogram(io, &f->h);
    gr_blob_io_f64(io, &f->sum);
    gr_blob_io_f64(io, &f->long_paths);
    gr_blob_io_i64(io, &f->paths);
    if (f->ns) { /* a mixture's (one species: the checkpoint as before) */
        gr_blob_io_int(io, &f->frames);
        gr_obs_io_species(io, "freepath", f->species, f->n, f->ns);
        gr_blob_io_f64s(io, f->grain_sum, f->n);
        gr_blob_io_f64s(io, f->grain_paths, f->n);
    }
    return GR_OK;
}

const gr_observable_type gr_obs_freepath = {
    .name = "freepath",
    .summary = "free-path distribution P_l(l) between contacts (4.18) with the tail fit (4.25); "
               "needs a run (contact events)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(freepath_params),
    .state_size = sizeof(freepath),
    .init = init,
    .sample = sample,
    .finish = finish,
    .events = events,
    .io = io,
};
