/* The per-contact history store (issue 13): one double per entry of the 2D half Verlet list,
 * s->nl_hist[p] for the pair (i, nl_j[p]) of row i, allocated only for a tangential law that keeps
 * history (the Cundall-Strack spring of models/tangential_spring.h; NULL otherwise, so nothing
 * else changes). The slot belongs to the pair, not to the list entry: a rebuild may list the pair
 * from either particle and at another position, so gr_neighbours_build saves the non-zero slots
 * keyed by (i, j) before it rebuilds (gr_history_save) and puts them back into the new entries
 * afterwards (gr_history_restore). The value is a scalar along t, and exchanging i and j leaves it
 * unchanged (models/tangential_spring.h), so a pair listed the other way round keeps its value.
 * Both run on one thread, in list order: the result is the same for any thread count. A pair
 * that leaves the list had no contact (the list holds every pair closer than the cutoff), so
 * nothing non-zero is lost.
 *
 * 3D (src/core/kernels_3d.c): the slot is the vector s, three doubles per entry
 * (gr_history_width), defined with g = v_j - v_i, so a pair listed the other way round would take
 * -s (the 3D list always lists a pair from its lower index, so it never happens there). */
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"

int gr_history_enable(gr_sim *s, gr_error *err)
{
    if (s->nl_hist) {
        return GR_OK;
    }
    s->nl_hist = calloc((size_t)s->nl_cap * (size_t)gr_history_width(s), sizeof(double));
    if (!s->nl_hist) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the contact history of %lld list entries",
                       (long long)s->nl_cap);
    }
    return GR_OK;
}

/* 1 when the slot of w doubles at h holds anything. */
static int held(const double *h, int w)
{
    int any = 0;
    for (int a = 0; a < w; a++) {
        any |= h[a] != 0.0;
    }
    return any;
}

int gr_history_save(gr_sim *s, gr_error *err)
{
    const int n = s->n, w = gr_history_width(s);
    const int64_t pairs = s->nl_start[n];
    int64_t k = 0;
    for (int64_t p = 0; p < pairs; p++) {
        k += held(s->nl_hist + w * p, w);
    }
    free(s->hist_j);
    free(s->hist_v);
    s->hist_j = malloc(sizeof(int) * (size_t)(k + 1));
    s->hist_v = malloc(sizeof(double) * (size_t)w * (size_t)(k + 1));
    if (!s->hist_start) {
        s->hist_start = malloc(sizeof(int64_t) * ((size_t)n + 1));
    }
    if (!s->hist_j || !s->hist_v || !s->hist_start) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory saving the history of %lld contacts",
                       (long long)k);
    }
    k = 0;
    for (int i = 0; i < n; i++) { /* row i: the saved slots (i, j) in list order */
        s->hist_start[i] = k;
        for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
            if (held(s->nl_hist + w * (int64_t)p, w)) {
                s->hist_j[k] = s->nl_j[p];
                memcpy(s->hist_v + w * k++, s->nl_hist + w * (int64_t)p, sizeof(double) * w);
            }
        }
    }
    s->hist_start[n] = k;
    return GR_OK;
}

/* The saved slot of the pair (i, j) as row i listed it, NULL if none. */
static const double *saved(const gr_sim *s, int i, int j)
{
    for (int64_t k = s->hist_start[i]; k < s->hist_start[i + 1]; k++) {
        if (s->hist_j[k] == j) {
            return s->hist_v + gr_history_width(s) * k;
        }
    }
    return NULL;
}

void gr_history_restore(gr_sim *s)
{
    const int w = gr_history_width(s);
    for (int i = 0; i < s->n; i++) {
        for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
            const int j = s->nl_j[p];
            double *h = s->nl_hist + w * (int64_t)p;
            const double *v = saved(s, i, j), *u = v ? NULL : saved(s, j, i);
            for (int a = 0; a < w; a++) {
                /* 2D: s along t is the same either way; 3D: the vector s changes sign */
                h[a] = v ? v[a] : !u ? 0.0 : w == 3 ? -u[a] : u[a];
            }
        }
    }
}
