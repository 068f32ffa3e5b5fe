/* Time correlations over a ring of recent frames (see obs_lag.h). */
#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_lag.h"
#include "analysis/obs_util.h"

int gr_lag_init(gr_lag *g, int n, int dim, int lags, gr_lag_kind kind, gr_error *err)
{
    memset(g, 0, sizeof *g);
    g->n = n;
    g->dim = dim;
    g->lags = lags;
    g->kind = kind;
    g->ring = calloc(gr_lag_stride(g) * (size_t)n * (size_t)(lags + 1),
                     sizeof(double)); /* zeroed: checkpoints save every slot */
    g->acc = malloc(sizeof(gr_blocking) * (size_t)(lags + 1));
    if (!g->ring || !g->acc) {
        gr_lag_free(g);
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d lags of %d particles", lags, n);
    }
    for (int l = 0; l <= lags; l++) {
        gr_blocking_init(&g->acc[l]);
    }
    return GR_OK;
}

void gr_lag_free(gr_lag *g)
{
    free(g->ring);
    free(g->acc);
    free(g->acc_s);
    g->ring = NULL;
    g->acc = NULL;
    g->acc_s = NULL;
}

int gr_lag_species(gr_lag *g, int ns, gr_error *err)
{
    if (ns < 2 || ns > GR_MAX_SPECIES) {
        return GR_FAIL(err, GR_EINVAL, "%d species; allowed: 2 to %d", ns, GR_MAX_SPECIES);
    }
    g->ns = ns;
    g->acc_s = malloc(sizeof(gr_blocking) * (size_t)(g->lags + 1) * (size_t)ns);
    if (!g->acc_s) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d lags of %d species", g->lags, ns);
    }
    for (int k = 0; k < (g->lags + 1) * ns; k++) {
        gr_blocking_init(&g->acc_s[k]);
    }
    return GR_OK;
}

gr_lag gr_lag_species_view(const gr_lag *g, int a)
{
    gr_lag v = *g;
    v.acc = g->acc_s + (size_t)(g->lags + 1) * (size_t)a;
    v.ns = 0;
    v.acc_s = NULL;
    return v;
}

/* gr_lag_add, with the species' sums when sp is given. */
static int lag_add(gr_lag *g, const int *sp, const double *a, const double *b, const double *c,
                   double t)
{
    const int slots = g->lags + 1, n = g->n, w = gr_lag_stride(g);
    double *now = g->ring + (size_t)w * (size_t)n * (size_t)(g->frames % slots);
    for (int i = 0; i < n; i++) {
        now[w * i] = a[i];
        now[w * i + 1] = b ? b[i] : 0.0;
        if (w == 3) {
            now[w * i + 2] = c[i];
        }
    }
    int64_t lmax = g->frames < g->lags ? g->frames : g->lags;
    for (int64_t l = 0; l <= lmax; l++) {
        const double *then = g->ring + (size_t)w * (size_t)n * (size_t)((g->frames - l) % slots);
        double s = 0.0, ss[GR_MAX_SPECIES] = {0};
        for (int k = 0; k < w * n; k++) {
            const double x =
                g->kind == GR_LAG_DOT ? now[k] * then[k] : (now[k] - then[k]) * (now[k] - then[k]);
            s += x;
            if (sp) {
                ss[sp[k / w]] += x;
            }
        }
        gr_blocking_add(&g->acc[l], s / n);
        for (int q = 0; sp && q < g->ns; q++) {
            if (g->count[q] > 0) {
                gr_blocking_add(&g->acc_s[(size_t)(g->lags + 1) * q + (size_t)l],
                                ss[q] / g->count[q]);
            }
        }
    }
    if (g->frames == 0) {
        g->t_first = t;
    }
    g->t_last = t;
    g->frames++;
    return GR_OK;
}

int gr_lag_add(gr_lag *g, const double *a, const double *b, const double *c, double t,
               gr_error *err)
{
    (void)err;
    return lag_add(g, NULL, a, b, c, t);
}

int gr_lag_add_species(gr_lag *g, const char *what, const gr_particles *p, const double *a,
                       const double *b, const double *c, double t, gr_error *err)
{
    bool ok = p->species && p->n_species == g->ns && p->n == g->n;
    for (int i = 0; ok && i < g->n; i++) {
        ok = p->species[i] >= 0 && p->species[i] < g->ns;
    }
    if (!ok) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: the frames carry %d species of %d grains, the scene %d of %d "
                       "([species]; docs/mixtures.md)",
                       what, p->species ? p->n_species : 0, p->n, g->ns, g->n);
    }
    if (g->frames == 0) { /* the species' counts, from the first frame */
        memset(g->count, 0, sizeof g->count);
        for (int i = 0; i < g->n; i++) {
            g->count[p->species[i]]++;
        }
    }
    return lag_add(g, p->species, a, b, c, t);
}

double gr_lag_interval(const gr_lag *g)
{
    return g->frames > 1 ? (g->t_last - g->t_first) / (double)(g->frames - 1) : 0.0;
}

double gr_lag_mean(const gr_lag *g, int l, double *stderr_out, int64_t *samples)
{
    const gr_blocking *b = &g->acc[l];
    int64_t count = b->count[0];
    if (stderr_out) {
        *stderr_out = gr_obs_stderr(b);
    }
    if (samples) {
        *samples = count;
    }
    return gr_blocking_mean(b);
}

int gr_lag_fit_line(const gr_lag *g, int lo, int hi, gr_fit *fit, gr_error *err)
{
    static_assert(GR_LAG_MAX < 4096, "lag fit arrays");
    double x[GR_LAG_MAX + 1], y[GR_LAG_MAX + 1], s[GR_LAG_MAX + 1];
    int m = 0;
    const double dt = gr_lag_interval(g);
    for (int l = lo; l <= hi && l <= g->lags; l++) {
        int64_t c;
        double e, v = gr_lag_mean(g, l, &e, &c);
        if (c >= 2 && isfinite(v) && isfinite(e) && e > 0.0) {
            x[m] = l * dt;
            y[m] = v;
            s[m] = e;
            m++;
        }
    }
    if (m < 3) {
        return GR_FAIL(err, GR_EINVAL, "%d usable lags (need 3)", m);
    }
    return gr_fit_line(x, y, s, m, fit, err);
}

static void release(void *g) { gr_lag_free(g); }

int gr_lag_init_owned(void *state, gr_lag *g, int n, int dim, int lags, gr_lag_kind kind,
                      gr_error *err)
{
    int rc = gr_lag_init(g, n, dim, lags, kind, err);
    if (!rc) {
        gr_obs_own(state, release, g);
    }
    return rc;
}

void gr_lag_io(gr_blob_io *io, gr_lag *g, const char *what)
{
    gr_blob_io_check(io, what, g->lags);
    gr_blob_io_i64(io, &g->frames);
    gr_blob_io_f64(io, &g->t_first);
    gr_blob_io_f64(io, &g->t_last);
    gr_blob_io_f64s(io, g->ring, gr_lag_stride(g) * (int64_t)g->n * (g->lags + 1));
    gr_obs_io_blockings(io, g->acc, g->lags + 1);
    if (g->ns) { /* a mixture's (one species: the checkpoint as before) */
        for (int a = 0; a < g->ns; a++) {
            gr_blob_io_int(io, &g->count[a]);
        }
        gr_obs_io_blockings(io, g->acc_s, (g->lags + 1) * g->ns);
    }
}
