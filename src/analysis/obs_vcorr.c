/* vcorr (2D, 3D): spatial velocity correlations against distance. For every pair
 * closer than R_max = min(vcorr_rmax d, L/2) (minimum image), with r_hat the
 * unit vector from i to j and u = v - <v>_frame the velocities relative to the
 * frame's mean, C_L(r) = <(u_i . r_hat)(u_j . r_hat)>,   C_T(r) = <(u_i x
 * r_hat)(u_j x r_hat)>, the longitudinal and transverse correlations, averaged
 * over the pairs in each of vcorr_bins equal bins of r and normalised per frame
 * by <|u|^2>/2 (the per-component variance, T/M of 2.19), so C = 1 for
 * velocities moving together and 0 for independent ones. Each frame's
 * normalised bin averages are time-averaged with block-averaging errors
 * (memory: bins only). In 3D the transverse part has two components: C_T(r) =
 * <u_i . u_j - (u_i . r_hat)(u_j . r_hat)> / 2, per transverse component, and the
 * normalisation is <|u|^2>/3, so C = 1 still means moving together. Known answers: independent random velocities give C_L =
 * C_T = 0 within errors (the mean subtraction leaves -1/(N-1)); a pair with u_1
 * = -u_2 gives C_L = -2 u_par^2 / |u|^2. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_cells.h"
#include "analysis/obs_util.h"
#include "granule/analysis.h"

#define VCORR_MAX_BINS 2000

typedef struct vcorr_params {
    int vcorr_bins;
    double vcorr_rmax;
} vcorr_params;

static const gr_param params[] = {
    {"vcorr_bins", "", GR_PARAM_INT, 50, 2, VCORR_MAX_BINS, false, false,
     "(2D, 3D) bins of the spatial velocity correlations C_L(r), C_T(r)",
     offsetof(vcorr_params, vcorr_bins)},
    {"vcorr_rmax", "d", GR_PARAM_DOUBLE, 10, 0, 1e6, true, false,
     "(2D, 3D) largest distance of the velocity correlations, in diameters (at "
     "most L/2)",
     offsetof(vcorr_params, vcorr_rmax)},
};

typedef struct vcorr {
    int bins;
    double rmax, w, d; /* m */
    bool mixture;      /* d is the mixture's mean collision diameter (gr_obs_collision_diameter) */
    int dim;
    const double *ux, *uy, *uz; /* the frame being visited */
    double *ux_buf, *uy_buf, *uz_buf, *sl, *st, *cnt;
    gr_blocking *bl, *bt;
    gr_cells cells;
    int64_t frames;
} vcorr;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)err;
    const vcorr_params *a = params_block;
    vcorr *s = state;
    s->bins = a->vcorr_bins;
    s->d = gr_obs_collision_diameter(setup); /* 2 radius; a mixture's mean over random pairs */
    s->mixture = setup->sizes;
    s->rmax = fmin(a->vcorr_rmax * s->d, 0.5 * setup->L);
    s->w = s->rmax / s->bins;
    size_t b = (size_t)s->bins, n = (size_t)setup->N;
    s->ux_buf = gr_obs_calloc(s, n, sizeof(double));
    s->uy_buf = gr_obs_calloc(s, n, sizeof(double));
    s->dim = setup->dim;
    s->uz_buf = setup->dim == 3 ? gr_obs_calloc(s, n, sizeof(double)) : NULL;
    s->sl = gr_obs_calloc(s, b, sizeof(double));
    s->st = gr_obs_calloc(s, b, sizeof(double));
    s->cnt = gr_obs_calloc(s, b, sizeof(double));
    s->bl = gr_obs_calloc(s, b, sizeof(gr_blocking));
    s->bt = gr_obs_calloc(s, b, sizeof(gr_blocking));
    gr_cells_own(s, &s->cells);
    return GR_OK;
}

static void visit(int i, int j, const double dr[3], double r2, void *user)
{
    vcorr *s = user;
    double r = sqrt(r2);
    int k = (int)(r / s->w);
    if (k >= s->bins || r == 0.0) {
        return;
    }
    double ex = dr[0] / r, ey = dr[1] / r;
    if (s->dim == 3) { /* two transverse components: (u_i . u_j - u_i,L u_j,L) / 2 */
        const double ez = dr[2] / r;
        const double li = s->ux[i] * ex + s->uy[i] * ey + s->uz[i] * ez,
                     lj = s->ux[j] * ex + s->uy[j] * ey + s->uz[j] * ez;
        s->sl[k] += li * lj;
        s->st[k] +=
            0.5 * (s->ux[i] * s->ux[j] + s->uy[i] * s->uy[j] + s->uz[i] * s->uz[j] - li * lj);
        s->cnt[k] += 1.0;
        return;
    }
    s->sl[k] += (s->ux[i] * ex + s->uy[i] * ey) * (s->ux[j] * ex + s->uy[j] * ey);
    s->st[k] += (s->ux[i] * ey - s->uy[i] * ex) * (s->ux[j] * ey - s->uy[j] * ex);
    s->cnt[k] += 1.0;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    vcorr *s = state;
    double mean[3], c0 = 0.0;
    gr_obs_mean_velocity(p, mean);
    for (int i = 0; i < p->n; i++) {
        s->ux_buf[i] = p->vx[i] - mean[0];
        s->uy_buf[i] = p->vy[i] - mean[1];
        if (p->dim == 3) {
            s->uz_buf[i] = p->vz[i] - mean[2];
            c0 += (s->ux_buf[i] * s->ux_buf[i] + s->uy_buf[i] * s->uy_buf[i] +
                   s->uz_buf[i] * s->uz_buf[i]) /
                  3.0;
            continue;
        }
        c0 += 0.5 * (s->ux_buf[i] * s->ux_buf[i] + s->uy_buf[i] * s->uy_buf[i]);
    }
    c0 /= p->n;
    if (!(c0 > 0.0)) {
        return GR_OK; /* nothing moves: no correlation to normalise */
    }
    s->ux = s->ux_buf;
    s->uy = s->uy_buf;
    s->uz = s->uz_buf;
    for (int k = 0; k < s->bins; k++) {
        s->sl[k] = s->st[k] = s->cnt[k] = 0.0;
    }
    int rc = gr_cells_pairs(&s->cells, p, s->rmax, visit, s, err);
    if (rc) {
        return rc;
    }
    for (int k = 0; k < s->bins; k++) {
        if (s->cnt[k] > 0.0) {
            gr_blocking_add(&s->bl[k], s->sl[k] / s->cnt[k] / c0);
            gr_blocking_add(&s->bt[k], s->st[k] / s->cnt[k] / c0);
        }
    }
    s->frames++;
    return GR_OK;
}

static void rows(FILE *f, const void *ctx)
{
    const vcorr *s = ctx;
    for (int k = 0; k < s->bins; k++) {
        if (s->bl[k].count[0] > 0) {
            fprintf(f, "%.8g,%.8g,%.10g,%.6g,%.10g,%.6g,%lld\n", (k + 0.5) * s->w,
                    (k + 0.5) * s->w / s->d, gr_blocking_mean(&s->bl[k]), gr_obs_stderr(&s->bl[k]),
                    gr_blocking_mean(&s->bt[k]), gr_obs_stderr(&s->bt[k]),
                    (long long)s->bl[k].count[0]);
        }
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    vcorr *s = state;
    cJSON *j = gr_obs_summary(out, "vcorr", "vcorr.csv");
    cJSON_AddNumberToObject(j, "frames", (double)s->frames);
    cJSON_AddNumberToObject(j, "r_max", s->rmax);
    if (s->mixture) {
        gr_obs_note_diameter(j, s->d, s->dim);
    }
    /* the nearest bin with pairs: the correlation at contact range */
    for (int k = 0; k < s->bins; k++) {
        if (s->bl[k].count[0] > 0) {
            gr_obs_add_number(j, "r_first", (k + 0.5) * s->w);
            gr_obs_add_number(j, "C_L_first", gr_blocking_mean(&s->bl[k]));
            gr_obs_add_number(j, "C_L_first_error", gr_obs_stderr(&s->bl[k]));
            gr_obs_add_number(j, "C_T_first", gr_blocking_mean(&s->bt[k]));
            gr_obs_add_number(j, "C_T_first_error", gr_obs_stderr(&s->bt[k]));
            break;
        }
    }
    const gr_obs_table t = {
        .name = "vcorr.csv",
        .what = s->dim == 3 ? "spatial velocity correlations (3D): longitudinal C_L and "
                              "transverse C_T (per transverse component) against the pair "
                              "distance r (m), normalised by <|u|^2>/3 per frame, u relative "
                              "to the frame's mean; "
                              "block-averaging errors over frames"
                            : "spatial velocity correlations (2D): longitudinal C_L and "
                              "transverse C_T against the pair "
                              "distance r (m), normalised by <|u|^2>/2 per frame, u relative "
                              "to the frame's mean; "
                              "block-averaging errors over frames",
        .columns = "r [m],r_over_d [1],C_L [1],C_L_stderr [1],C_T [1],C_T_stderr [1],frames [1]",
        .rows = rows,
        .ctx = s,
        .png = s->frames > 0 ? "vcorr.png" : NULL,
        .plot = "set xlabel 'distance r (m)'\nset ylabel 'C(r), normalised'\nset "
                "title 'Spatial velocity correlations'\n"
                "plot 'vcorr.csv' skip 1 using 1:3:4 with yerrorbars title "
                "'longitudinal C_L', "
                "'' skip 1 using 1:5:6 with yerrorbars title 'transverse C_T', 0 "
                "lc rgb 'gray' notitle",
    };
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    vcorr *s = state;
    gr_blob_io_check(io, "vcorr_bins", s->bins);
    gr_blob_io_i64(io, &s->frames);
    gr_obs_io_blockings(io, s->bl, s->bins);
    gr_obs_io_blockings(io, s->bt, s->bins);
    return GR_OK;
}

const gr_observable_type gr_obs_vcorr = {
    .name = "vcorr",
    .summary = "spatial velocity correlations, longitudinal C_L(r) and "
               "transverse C_T(r) (2D, 3D)",
    .dims = 6, /* 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(vcorr_params),
    .state_size = sizeof(vcorr),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
