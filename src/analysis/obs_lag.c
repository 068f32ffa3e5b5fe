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
    g->ring = NULL;
    g->acc = NULL;
}

int gr_lag_add(gr_lag *g, const double *a, const double *b, const double *c, double t,
               gr_error *err)
{
    (void)err;
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
        double s = 0.0;
        for (int k = 0; k < w * n; k++) {
            s += g->kind == GR_LAG_DOT ? now[k] * then[k] : (now[k] - then[k]) * (now[k] - then[k]);
        }
        gr_blocking_add(&g->acc[l], s / n);
    }
    if (g->frames == 0) {
        g->t_first = t;
    }
    g->t_last = t;
    g->frames++;
    return GR_OK;
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
}
