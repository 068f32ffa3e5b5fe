/* pv on a mixture (obs_pv_species.h): each species' distribution of one velocity component, on the
 * bins of the pooled P(v) and relative to the same frame mean, so that the species' counts add up
 * to the pooled counts bin by bin. The pooled distribution of a mixture is a sum of distributions
 * of different widths, whose tails are no one species' (docs/mixtures.md): this file is where each
 * species' own shape is read, its flatness <v^4> / <v^2>^2 (3 for a Gaussian component) the first
 * number to look at. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_pv_species.h"

void pv_species_init(void *state, pv_species *s, const gr_obs_setup *setup)
{
    s->ns = setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES ? setup->n_species : 0;
    for (int a = 0; a < s->ns; a++) {
        gr_obs_own_histogram(state, &s->h[a]); /* binned with the pooled one */
    }
    gr_obs_own_pointer(state, &s->buf);
}

int pv_species_check(const pv_species *s, const gr_particles *p, gr_error *err)
{
    return s->ns ? gr_obs_frame_species("pv", p, s->ns, p->n, NULL, err) : GR_OK;
}

int pv_species_buffer(pv_species *s, const gr_particles *p, gr_error *err)
{
    if (!s->ns) {
        return GR_OK;
    }
    if (s->nbuf + (size_t)p->n > s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 4 * (size_t)p->n;
        cap = cap < s->nbuf + (size_t)p->n ? s->nbuf + (size_t)p->n : cap;
        unsigned char *nb = realloc(s->buf, cap);
        if (!nb) {
            return GR_FAIL(err, GR_ENOMEM, "pv: out of memory for the reference frames' species");
        }
        s->buf = nb;
        s->cap = cap;
    }
    for (int i = 0; i < p->n; i++) {
        s->buf[s->nbuf++] = (unsigned char)p->species[i];
    }
    return GR_OK;
}

int pv_species_fix(pv_species *s, const gr_histogram *pooled, gr_error *err)
{
    for (int a = 0; a < s->ns; a++) {
        int rc = gr_histogram_init(&s->h[a], pooled->nbins, pooled->lo, pooled->hi, false, err);
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

void pv_species_add(pv_species *s, int a, int dim, double ux, double uy, double uz)
{
    gr_histogram_add(&s->h[a], ux, 1.0);
    if (dim >= 2) {
        gr_histogram_add(&s->h[a], uy, 1.0);
    }
    if (dim == 3) {
        gr_histogram_add(&s->h[a], uz, 1.0);
    }
}

void pv_species_io(pv_species *s, gr_blob_io *io, bool fixed)
{
    if (!s->ns) {
        return;
    }
    gr_blob_io_check(io, "pv species", s->ns);
    if (fixed) {
        for (int a = 0; a < s->ns && !gr_blob_io_bad(io); a++) {
            if (!gr_obs_io_histogram_new(io, &s->h[a])) {
                gr_blob_io_fail(io, "pv: species %d's histogram", a + 1);
            }
        }
        return;
    }
    int64_t n = (int64_t)s->nbuf;
    gr_blob_io_i64(io, &n);
    if (gr_blob_io_loading(io)) {
        if (n < 0 || (uint64_t)n > gr_blob_io_left(io)) {
            gr_blob_io_fail(io, "%lld buffered species do not fit", (long long)n);
            return;
        }
        free(s->buf);
        s->buf = malloc((size_t)(n > 0 ? n : 1));
        if (!s->buf) {
            gr_blob_io_fail(io, "out of memory for %lld buffered species", (long long)n);
            return;
        }
        s->nbuf = s->cap = (size_t)n;
    }
    gr_blob_io_bytes(io, s->buf, (size_t)n);
}

typedef struct rows_ctx {
    const pv_species *s;
} rows_ctx;

static void rows(FILE *f, const void *ctx)
{
    const pv_species *s = ((const rows_ctx *)ctx)->s;
    const gr_histogram *h0 = &s->h[0];
    for (int i = 0; i < h0->nbins; i++) {
        fprintf(f, "%.10g", gr_histogram_center(h0, i));
        for (int a = 0; a < s->ns; a++) {
            const gr_histogram *h = &s->h[a];
            fprintf(f, ",%.10g,%.6g,%.0f", gr_histogram_density(h, i),
                    gr_histogram_density_error(h, i), h->count[i]);
        }
        fputc('\n', f);
    }
}

int pv_species_finish(const pv_species *s, const gr_output *out, cJSON *pv, gr_error *err)
{
    if (!s->ns) {
        return GR_OK;
    }
    cJSON *arr = cJSON_AddArrayToObject(pv, "species");
    char columns[GR_MAX_SPECIES * 96 + 32];
    size_t n = (size_t)snprintf(columns, sizeof columns, "v [m s-1]");
    for (int a = 0; a < s->ns; a++) {
        const gr_histogram *h = &s->h[a];
        double m2 = 0.0, m4 = 0.0, in = 0.0;
        for (int i = 0; i < h->nbins; i++) { /* the bins' centres: <v^2>, <v^4> of the component */
            const double v = gr_histogram_center(h, i), v2 = v * v;
            m2 += h->count[i] * v2;
            m4 += h->count[i] * v2 * v2;
            in += h->count[i];
        }
        m2 = in > 0.0 ? m2 / in : (double)NAN;
        m4 = in > 0.0 ? m4 / in : (double)NAN;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "species", a + 1);
        cJSON_AddNumberToObject(o, "components", h->total);
        gr_obs_add_number(o, "v2", m2);
        gr_obs_add_number(o, "flatness", m2 > 0.0 ? m4 / (m2 * m2) : (double)NAN);
        gr_obs_add_number(o, "out_of_range_fraction",
                          h->total > 0.0 ? (h->below + h->above) / h->total : (double)NAN);
        cJSON_AddItemToArray(arr, o);
        n += (size_t)snprintf(columns + n, sizeof columns - n,
                              ",density_%d [s m-1],density_error_%d [s m-1],counts_%d [1]", a + 1,
                              a + 1, a + 1);
    }
    cJSON_AddStringToObject(pv, "species_file", "pv_species.csv");
    const rows_ctx ctx = {s};
    const gr_obs_table t = {
        .name = "pv_species.csv",
        .what = "P(v) of one velocity component of each species of a mixture, on pv.csv's bins and "
                "relative to the same frame mean (the species' counts add up to pv.csv's); each "
                "density normalised to that species' sampled components, density_error = "
                "sqrt(counts)/(N_s dv) (A.5)",
        .columns = columns,
        .rows = rows,
        .ctx = &ctx,
    };
    return gr_obs_table_write(out, &t, err);
}
