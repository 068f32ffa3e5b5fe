/* postcollision: the post-collision velocity distribution P(v_0) (sec. 5.2, Fig. 5.9): the
 * velocity components of a particle at the moment it becomes free after a collision (from the
 * engine's contact events), beside the full P(v) of the sampled frames in the same bins, so the
 * two can be overlaid as in Fig. 5.9. Velocities are unscaled (m/s). The bins are those of the
 * pv observable's parameters (pv_bins, pv_range): |v| < pv_range sqrt(T_first), T of eq. 2.19 in
 * the first sampled frame.
 *
 * A mixture of species ([species] lists, docs/mixtures.md) also sums each species' squares:
 * summary.json -> postcollision.species_post_v2 and species_all_v2, the mean square velocity
 * component after a collision and of all sampled grains of each species (a grain's species is the
 * first sample's). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_util.h"
#include "granule/analysis.h"
#include "granule/sim.h"

typedef struct postcollision {
    int bins, dim;
    double range;
    bool ready;
    gr_histogram post, all;
    double post_v2, all_v2;
    int64_t post_n, all_n;
    /* a mixture (ns >= 2; 0 for one species): each grain's species and the species' sums */
    int ns, n;
    int *species;
    bool named; /* species[] holds the first sample's */
    double post_v2_s[GR_MAX_SPECIES], all_v2_s[GR_MAX_SPECIES];
    int64_t post_n_s[GR_MAX_SPECIES], all_n_s[GR_MAX_SPECIES];
} postcollision;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)params_block; /* it takes the pv observable's bins */
    postcollision *p = state;
    double bins, range;
    int rc = gr_analysis_get(setup->analysis, "pv_bins", &bins, err);
    rc = rc ? rc : gr_analysis_get(setup->analysis, "pv_range", &range, err);
    if (rc) {
        return rc;
    }
    p->bins = bins > 0 ? (int)bins : 200;
    p->range = range > 0.0 ? range : 10.0;
    p->dim = setup->dim;
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        p->ns = setup->n_species;
        p->n = setup->N;
        p->species = gr_obs_calloc(p, (size_t)p->n + 1, sizeof(int));
        rc = gr_obs_alloc_ok(p, err);
        if (rc) {
            return rc;
        }
    }
    gr_obs_own_histogram(p, &p->post); /* filled from the first frame that moves */
    gr_obs_own_histogram(p, &p->all);
    return GR_OK;
}

static int sample(void *state, const gr_particles *f, double t, gr_error *err)
{
    (void)t;
    postcollision *p = state;
    if (p->ns && !p->named) { /* a mixture: the grains' species, from the first frame */
        int rc = gr_obs_frame_species("postcollision", f, p->ns, p->n, p->species, err);
        if (rc) {
            return rc;
        }
        p->named = true;
    }
    double mean[3];
    gr_obs_mean_velocity(f, mean);
    if (!p->ready) {
        double T = 0.0;
        for (int i = 0; i < f->n; i++) {
            double ux = f->vx[i] - mean[0], uy = f->dim >= 2 ? f->vy[i] - mean[1] : 0.0;
            double uz = f->dim == 3 ? f->vz[i] - mean[2] : 0.0;
            T += f->dim == 3 ? ux * ux + uy * uy + uz * uz : ux * ux + uy * uy;
        }
        double vmax =
            p->range * sqrt(T / f->n); /* pv's convention: pv_range sqrt(T), T of eq. 2.19 */
        if (!(vmax > 0.0)) {
            return GR_OK; /* nothing moves yet: fix the range at a later frame */
        }
        int rc = gr_histogram_init(&p->post, p->bins, -vmax, vmax, false, err);
        rc = rc ? rc : gr_histogram_init(&p->all, p->bins, -vmax, vmax, false, err);
        if (rc) {
            return rc;
        }
        p->ready = true;
    }
    for (int i = 0; p->ns && i < f->n; i++) {
        const double ux = f->vx[i] - mean[0], uy = f->dim >= 2 ? f->vy[i] - mean[1] : 0.0;
        const double uz = f->dim == 3 ? f->vz[i] - mean[2] : 0.0;
        p->all_v2_s[p->species[i]] += ux * ux + uy * uy + uz * uz;
        p->all_n_s[p->species[i]] += f->dim;
    }
    for (int i = 0; i < f->n; i++) {
        gr_histogram_add(&p->all, f->vx[i] - mean[0], 1.0);
        p->all_v2 += (f->vx[i] - mean[0]) * (f->vx[i] - mean[0]);
        if (f->dim >= 2) {
            gr_histogram_add(&p->all, f->vy[i] - mean[1], 1.0);
            p->all_v2 += (f->vy[i] - mean[1]) * (f->vy[i] - mean[1]);
        }
        if (f->dim == 3) {
            gr_histogram_add(&p->all, f->vz[i] - mean[2], 1.0);
            p->all_v2 += (f->vz[i] - mean[2]) * (f->vz[i] - mean[2]);
        }
    }
    p->all_n += (int64_t)f->n * f->dim;
    return GR_OK;
}

static int events(void *state, const gr_contact_event *ev, int64_t n, gr_error *err)
{
    (void)err;
    postcollision *p = state;
    if (!p->ready) {
        return GR_OK;
    }
    for (int64_t k = 0; k < n; k++) {
        if (ev[k].kind < 0) { /* the particle has just become free: v_0 */
            gr_histogram_add(&p->post, ev[k].vx, 1.0);
            p->post_v2 += ev[k].vx * ev[k].vx;
            p->post_n++;
            if (p->dim >= 2) {
                gr_histogram_add(&p->post, ev[k].vy, 1.0);
                p->post_v2 += ev[k].vy * ev[k].vy;
                p->post_n++;
            }
            if (p->dim == 3) {
                gr_histogram_add(&p->post, ev[k].vz, 1.0);
                p->post_v2 += ev[k].vz * ev[k].vz;
                p->post_n++;
            }
            if (p->ns && ev[k].i >= 0 && ev[k].i < p->n) {
                const int a = p->species[ev[k].i];
                const double vy = p->dim >= 2 ? ev[k].vy : 0.0, vz = p->dim == 3 ? ev[k].vz : 0.0;
                p->post_v2_s[a] += ev[k].vx * ev[k].vx + vy * vy + vz * vz;
                p->post_n_s[a] += p->dim;
            }
        }
    }
    return GR_OK;
}

const char gr_obs_postcollision_columns[] =
    "v [m s-1],post_density [s m-1],post_error [s m-1],post_count [1],all_density [s m-1],"
    "all_error [s m-1],all_count [1]";

static void rows(FILE *f, const void *ctx)
{
    const postcollision *p = ctx;
    for (int i = 0; i < p->post.nbins; i++) {
        fprintf(f, "%.8g,%.8g,%.4g,%.0f,%.8g,%.4g,%.0f\n", gr_histogram_center(&p->post, i),
                gr_histogram_density(&p->post, i), gr_histogram_density_error(&p->post, i),
                p->post.count[i], gr_histogram_density(&p->all, i),
                gr_histogram_density_error(&p->all, i), p->all.count[i]);
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    postcollision *p = state;
    cJSON *j = cJSON_AddObjectToObject(out->summary, "postcollision");
    if (!p->ready) {
        cJSON_AddStringToObject(j, "note", "no frame sampled");
        return GR_OK;
    }
    const gr_obs_table t = {
        .name = "postcollision.csv",
        .what = "post-collision velocity distribution P(v_0) (Fig. 5.9) beside the full P(v), per "
                "component, "
                "v in m/s, densities per m/s with sqrt(X) errors",
        .columns = gr_obs_postcollision_columns,
        .rows = rows,
        .ctx = p,
        .png = "postcollision.png",
        .plot = "set logscale y\nset xlabel 'v (m/s)'\nset ylabel 'probability density'\n"
                "set title \"Velocities just after a collision and of all particles\\n{/*0.75 Fig. "
                "5.9}\"\n"
                "plot 'postcollision.csv' skip 1 using 1:($4>0?$2:1/0) with points pt 7 ps 0.5 "
                "title 'P(v_0) after "
                "collision', '' skip 1 using 1:($7>1?$5:1/0) with lines lw 2 title 'P(v)', '' skip "
                "1 using "
                "1:($7==1?$5:1/0) with points lt 2 pt 6 ps 0.5 notitle",
    };
    cJSON_AddNumberToObject(j, "post_samples", (double)p->post_n);
    if (p->post_n == 0) {
        gr_obs_note_no_events(j, "post-collision velocities");
    }
    cJSON_AddNumberToObject(j, "post_v2", p->post_n ? p->post_v2 / p->post_n : 0.0);
    cJSON_AddNumberToObject(j, "all_v2", p->all_n ? p->all_v2 / p->all_n : 0.0);
    if (p->ns) {
        cJSON *jp = cJSON_AddArrayToObject(j, "species_post_v2");
        cJSON *ja = cJSON_AddArrayToObject(j, "species_all_v2");
        for (int a = 0; a < p->ns; a++) {
            cJSON_AddItemToArray(
                jp, cJSON_CreateNumber(p->post_n_s[a] ? p->post_v2_s[a] / p->post_n_s[a] : 0.0));
            cJSON_AddItemToArray(
                ja, cJSON_CreateNumber(p->all_n_s[a] ? p->all_v2_s[a] / p->all_n_s[a] : 0.0));
        }
    }
    cJSON_AddStringToObject(j, "file", "postcollision.csv");
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    postcollision *p = state;
    uint32_t ready = p->ready;
    gr_blob_io_u32(io, &ready);
    if (ready) {
        bool ok = gr_obs_io_histogram_new(io, &p->post) && gr_obs_io_histogram_new(io, &p->all);
        p->ready = ok;
        if (ok && (p->post.nbins != p->bins || p->all.nbins != p->bins)) {
            gr_blob_io_fail(io, "%d bins in the checkpoint, pv_bins = %d in the scene",
                            p->post.nbins, p->bins);
        }
    }
    gr_blob_io_f64(io, &p->post_v2);
    gr_blob_io_f64(io, &p->all_v2);
    gr_blob_io_i64(io, &p->post_n);
    gr_blob_io_i64(io, &p->all_n);
    if (p->ns) { /* a mixture's (one species: the checkpoint as before) */
        uint32_t named = p->named;
        gr_blob_io_u32(io, &named);
        p->named = named != 0;
        gr_obs_io_species(io, "postcollision", p->species, p->n, p->ns);
        for (int a = 0; a < p->ns; a++) {
            gr_blob_io_f64(io, &p->post_v2_s[a]);
            gr_blob_io_f64(io, &p->all_v2_s[a]);
            gr_blob_io_i64(io, &p->post_n_s[a]);
            gr_blob_io_i64(io, &p->all_n_s[a]);
        }
    }
    return GR_OK;
}

const gr_observable_type gr_obs_postcollision = {
    .name = "postcollision",
    .summary = "post-collision velocity distribution P(v_0) beside P(v) (Fig. 5.9); needs a run "
               "(contact events)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = NULL,
    .n_params = 0,
    .state_size = sizeof(postcollision),
    .init = init,
    .sample = sample,
    .finish = finish,
    .events = events,
    .io = io,
};
