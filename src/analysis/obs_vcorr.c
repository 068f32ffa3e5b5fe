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
 * = -u_2 gives C_L = -2 u_par^2 / |u|^2.
 *
 * A mixture of species lists (docs/mixtures.md) also gives, for every species pair a <= b,
 * C_L,ab(r) and C_T,ab(r) over the pairs of one grain of species a and one of b, normalised per
 * frame by sqrt(var_a var_b), var_s the species' per-component variance of u (relative to the same
 * frame mean), so C = 1 still means moving together (vcorr_species.csv). In one frame, with n_ab(r)
 * the pairs of the bin and n = sum_ab n_ab, c0 = <|u|^2>/dim = sum_s (N_s / N) var_s:
 *   c0 n C_L(r) = sum_ab n_ab sqrt(var_a var_b) C_L,ab(r)    (and C_T alike),
 * the total's un-normalised sum of products split by pair kind (tests/test_obs_mixture_structure.sh);
 * over several frames it holds frame by frame, not for the time averages of the ratios. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
    /* a mixture of species lists (ns >= 2; 0 otherwise): pair q = (a, b), a <= b, in the order 11,
     * 12, .., 22, ..; its bins at [q bins + k] */
    int ns;
    gr_obs_pairs pairs;
    const int *species;               /* the frame being visited */
    double *sl_sp, *st_sp, *cnt_sp;   /* this frame's sums and pairs (one block, sl_sp first) */
    double *pairs_sp;                 /* pairs summed over the frames (the block's last part) */
    gr_blocking *bl_sp, *bt_sp, *var; /* C_L,ab, C_T,ab; var[s]: each species' variance */
} vcorr;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
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
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        s->ns = setup->n_species;
        gr_obs_pairs_init(&s->pairs, s->ns);
        const size_t pb = (size_t)s->pairs.n * b;
        s->sl_sp = gr_obs_calloc(s, 4 * pb, sizeof(double)); /* sl, st, cnt (one frame), pairs */
        s->bl_sp = gr_obs_calloc(s, 2 * pb + (size_t)s->ns, sizeof(gr_blocking));
        if (s->sl_sp && s->bl_sp) {
            s->st_sp = s->sl_sp + pb;
            s->cnt_sp = s->sl_sp + 2 * pb;
            s->pairs_sp = s->sl_sp + 3 * pb;
            s->bt_sp = s->bl_sp + pb;
            s->var = s->bl_sp + 2 * pb;
        }
    }
    return gr_obs_alloc_ok(s, err);
}

static void visit(int i, int j, const double dr[3], double r2, void *user)
{
    vcorr *s = user;
    double r = sqrt(r2);
    int k = (int)(r / s->w);
    if (k >= s->bins || r == 0.0) {
        return;
    }
    double ex = dr[0] / r, ey = dr[1] / r, cl, ct;
    if (s->dim == 3) { /* two transverse components: (u_i . u_j - u_i,L u_j,L) / 2 */
        const double ez = dr[2] / r;
        const double li = s->ux[i] * ex + s->uy[i] * ey + s->uz[i] * ez,
                     lj = s->ux[j] * ex + s->uy[j] * ey + s->uz[j] * ez;
        cl = li * lj;
        ct = 0.5 * (s->ux[i] * s->ux[j] + s->uy[i] * s->uy[j] + s->uz[i] * s->uz[j] - li * lj);
    } else {
        cl = (s->ux[i] * ex + s->uy[i] * ey) * (s->ux[j] * ex + s->uy[j] * ey);
        ct = (s->ux[i] * ey - s->uy[i] * ex) * (s->ux[j] * ey - s->uy[j] * ex);
    }
    s->sl[k] += cl;
    s->st[k] += ct;
    s->cnt[k] += 1.0;
    if (s->ns) { /* a mixture: the same products by pair kind */
        const size_t q =
            (size_t)s->pairs.of[s->species[i] * s->ns + s->species[j]] * (size_t)s->bins +
            (size_t)k;
        s->sl_sp[q] += cl;
        s->st_sp[q] += ct;
        s->cnt_sp[q] += 1.0;
    }
}

/* A mixture's frame: each species' variance var_s (per component, u relative to the frame's mean)
 * and each pair kind's C_L,ab, C_T,ab of the bins, normalised by sqrt(var_a var_b). */
static void add_species(vcorr *s, int n)
{
    double var[GR_MAX_SPECIES] = {0}, count[GR_MAX_SPECIES] = {0};
    for (int i = 0; i < n; i++) {
        const double u2 =
            s->ux[i] * s->ux[i] + s->uy[i] * s->uy[i] + (s->dim == 3 ? s->uz[i] * s->uz[i] : 0.0);
        var[s->species[i]] += u2 / s->dim;
        count[s->species[i]] += 1.0;
    }
    for (int a = 0; a < s->ns; a++) {
        var[a] = count[a] > 0.0 ? var[a] / count[a] : 0.0;
        if (count[a] > 0.0) {
            gr_blocking_add(&s->var[a], var[a]);
        }
    }
    for (int q = 0; q < s->pairs.n; q++) {
        const double c = sqrt(var[s->pairs.a[q]] * var[s->pairs.b[q]]);
        for (int k = 0; k < s->bins; k++) {
            const size_t at = (size_t)q * (size_t)s->bins + (size_t)k;
            s->pairs_sp[at] += s->cnt_sp[at];
            if (s->cnt_sp[at] > 0.0 && c > 0.0) {
                gr_blocking_add(&s->bl_sp[at], s->sl_sp[at] / s->cnt_sp[at] / c);
                gr_blocking_add(&s->bt_sp[at], s->st_sp[at] / s->cnt_sp[at] / c);
            }
        }
    }
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    vcorr *s = state;
    double mean[3], c0 = 0.0;
    int rc = s->ns ? gr_obs_frame_species("vcorr", p, s->ns, p->n, NULL, err) : GR_OK;
    if (rc) {
        return rc;
    }
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
    if (s->ns) {
        s->species = p->species;
        memset(s->sl_sp, 0, 3 * (size_t)s->pairs.n * (size_t)s->bins * sizeof(double));
    }
    rc = gr_cells_pairs(&s->cells, p, s->rmax, visit, s, err);
    if (rc) {
        return rc;
    }
    for (int k = 0; k < s->bins; k++) {
        if (s->cnt[k] > 0.0) {
            gr_blocking_add(&s->bl[k], s->sl[k] / s->cnt[k] / c0);
            gr_blocking_add(&s->bt[k], s->st[k] / s->cnt[k] / c0);
        }
    }
    if (s->ns) {
        add_species(s, p->n);
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

/* vcorr_species.csv: per bin, C_L,ab and C_T,ab with errors and the mean pairs per frame of every
 * pair kind a <= b (nan where a kind had no pairs) */
static void species_rows(FILE *f, const void *ctx)
{
    const vcorr *s = ctx;
    for (int k = 0; k < s->bins; k++) {
        if (s->bl[k].count[0] == 0) {
            continue;
        }
        fprintf(f, "%.8g,%.8g", (k + 0.5) * s->w, (k + 0.5) * s->w / s->d);
        for (int q = 0; q < s->pairs.n; q++) {
            const size_t at = (size_t)q * (size_t)s->bins + (size_t)k;
            if (s->bl_sp[at].count[0] > 0) { /* 15 digits: the identity in the header comment */
                fprintf(f, ",%.15g,%.6g,%.15g,%.6g", gr_blocking_mean(&s->bl_sp[at]),
                        gr_obs_stderr(&s->bl_sp[at]), gr_blocking_mean(&s->bt_sp[at]),
                        gr_obs_stderr(&s->bt_sp[at]));
            } else {
                fputs(",nan,nan,nan,nan", f);
            }
            fprintf(f, ",%.15g", s->frames > 0 ? s->pairs_sp[at] / (double)s->frames : 0.0);
        }
        fputc('\n', f);
    }
}

/* A mixture's pair kinds: vcorr_species.csv, and in the summary the pairs, each species' variance
 * and each kind's correlations in the first bin. */
static int finish_species(const vcorr *s, const gr_output *out, cJSON *j, gr_error *err)
{
    char columns[32 + GR_OBS_MAX_PAIRS * 112];
    size_t len = (size_t)snprintf(columns, sizeof columns, "r [m],r_over_d [1]");
    for (int q = 0; q < s->pairs.n; q++) {
        const char *label = s->pairs.label[q];
        len += (size_t)snprintf(columns + len, sizeof columns - len,
                                ",C_L_%s [1],C_L_%s_stderr [1],C_T_%s [1],C_T_%s_stderr [1],"
                                "pairs_%s [1]",
                                label, label, label, label, label);
    }
    gr_obs_pairs_summary(&s->pairs, j);
    cJSON_AddStringToObject(j, "species_file", "vcorr_species.csv");
    cJSON *jv = cJSON_AddArrayToObject(j, "species_var"),
          *jve = cJSON_AddArrayToObject(j, "species_var_error");
    for (int a = 0; a < s->ns; a++) {
        const double v = s->var[a].count[0] > 0 ? gr_blocking_mean(&s->var[a]) : (double)NAN;
        const double e = gr_obs_stderr(&s->var[a]);
        cJSON_AddItemToArray(jv, isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull());
        cJSON_AddItemToArray(jve, isfinite(e) ? cJSON_CreateNumber(e) : cJSON_CreateNull());
    }
    for (int k = 0; k < s->bins; k++) { /* the total's first bin with pairs (r_first) */
        if (s->bl[k].count[0] == 0) {
            continue;
        }
        const char *names[4] = {"species_C_L_first", "species_C_L_first_error", "species_C_T_first",
                                "species_C_T_first_error"};
        for (int c = 0; c < 4; c++) {
            cJSON *arr = cJSON_AddArrayToObject(j, names[c]);
            for (int q = 0; q < s->pairs.n; q++) {
                const gr_blocking *b =
                    &(c < 2 ? s->bl_sp : s->bt_sp)[(size_t)q * (size_t)s->bins + (size_t)k];
                const double x = b->count[0] == 0 ? (double)NAN
                                 : c % 2          ? gr_obs_stderr(b)
                                                  : gr_blocking_mean(b);
                cJSON_AddItemToArray(arr, isfinite(x) ? cJSON_CreateNumber(x) : cJSON_CreateNull());
            }
        }
        break;
    }
    const gr_obs_table t = {
        .name = "vcorr_species.csv",
        .what = "spatial velocity correlations of a mixture by pair kind a <= b: C_L,ab and C_T,ab "
                "over the pairs of one grain of species a and one of b against the distance r (m), "
                "normalised per frame by sqrt(var_a var_b) (var_s: species s's per-component "
                "variance of u, u relative to the frame's mean); block-averaging errors over "
                "frames; pairs_ab: such pairs per frame in the bin",
        .columns = columns,
        .rows = species_rows,
        .ctx = s,
    };
    return gr_obs_table_write(out, &t, err);
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
    int rc = s->ns ? finish_species(s, out, j, err) : GR_OK;
    return rc ? rc : gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    vcorr *s = state;
    gr_blob_io_check(io, "vcorr_bins", s->bins);
    gr_blob_io_i64(io, &s->frames);
    gr_obs_io_blockings(io, s->bl, s->bins);
    gr_obs_io_blockings(io, s->bt, s->bins);
    if (s->ns) { /* a mixture's (one species: the checkpoint as before) */
        const int64_t pb = (int64_t)s->pairs.n * s->bins;
        gr_blob_io_check(io, "vcorr species pairs", s->pairs.n);
        gr_blob_io_f64s(io, s->pairs_sp, pb);
        gr_obs_io_blockings(io, s->bl_sp, (int)pb);
        gr_obs_io_blockings(io, s->bt_sp, (int)pb);
        gr_obs_io_blockings(io, s->var, s->ns);
    }
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
