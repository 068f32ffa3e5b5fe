/* Saving and restoring the hybrid integrator's state for exact restarts (docs/checkpoints.md,
 * "Other integrators"). Appended by src/core/sim_state.c after the soft-sphere part, which holds
 * the whole particle state: between two gr_sim_step calls every window is complete, so positions,
 * velocities, forces and the ledger are synchronised there.
 *
 * What else the next window depends on: windows are cut at multiples of m steps (hybrid.c), so
 * the step counter fixes the window phase; the active set, the forced flags (zero between
 * windows), the window noise (a pure function of seed and step) and the child simulation (loaded
 * from the parent and its neighbour list rebuilt at every window start, child.c) are all
 * re-created per window. What persists: the counters (windows, rollbacks, steps, active steps),
 * the margin factor c (a test hook) and, in 2D and 3D, the candidate-pair list with the positions it was
 * built at and its cutoff (it is rebuilt only when somebody moved far enough, so it is state;
 * active.c). */
#include <stdlib.h>
#include <string.h>

#include "integrators/hybrid/hy_internal.h"

#define HYBRID_STATE_TAG 0x48594231u /* "HYB1": bump when the layout below changes */

/* The candidate pair list (2D), stored as it is; loading grows it as collect_pairs would. */
static int pairs_io(gr_sim *s, gr_hybrid_state *h, gr_blob_io *io, gr_error *err)
{
    const int n = s->n;
    gr_blob_io_f64(io, &h->rc_pairs);
    int64_t np = h->npairs;
    gr_blob_io_i64(io, &np);
    if (io->in) {
        gr_blob_reader *r = io->in;
        if (!r->bad &&
            (np < 0 || np > (int64_t)n * (int64_t)(n - 1) / 2 || np > (int64_t)INT32_MAX)) {
            gr_blob_fail(r, "hybrid candidate list of %lld pairs is impossible for %d particles",
                         (long long)np, n);
        }
        if (r->bad) {
            return gr_blob_done(r, err);
        }
        if (np > h->cap_pairs) {
            int *pi = realloc(h->pi, sizeof(int) * (size_t)np);
            if (pi) {
                h->pi = pi;
            }
            int *pj = pi ? realloc(h->pj, sizeof(int) * (size_t)np) : NULL;
            if (pj) {
                h->pj = pj;
            }
            if (!pi || !pj) {
                return GR_FAIL(err, GR_ENOMEM,
                               "out of memory for a hybrid candidate list of %lld pairs",
                               (long long)np);
            }
            h->cap_pairs = np;
        }
        h->npairs = np;
        h->adj_ok = 0;
    }
    gr_blob_io_bytes(io, h->pi, sizeof(int) * (size_t)np);
    gr_blob_io_bytes(io, h->pj, sizeof(int) * (size_t)np);
    for (int64_t q = 0; io->in && q < np && !io->in->bad; q++) {
        if (h->pi[q] < 0 || h->pi[q] >= h->pj[q] || h->pj[q] >= n) {
            gr_blob_fail(io->in, "hybrid candidate pair %lld is (%d, %d), allowed 0 <= i < j < %d",
                         (long long)q, h->pi[q], h->pj[q], n);
        }
    }
    gr_blob_io_f64s(io, h->xl, n);
    gr_blob_io_f64s(io, h->yl, n);
    if (s->dim == 3) {
        gr_blob_io_f64s(io, h->zl, n);
    }
    if (io->in && !io->in->bad && !(h->rc_pairs >= 0.0)) {
        gr_blob_fail(io->in, "hybrid candidate cutoff %.17g is negative", h->rc_pairs);
    }
    return GR_OK;
}

/* The hybrid integrator's state, listed once for saving and loading (core/blob.h, gr_blob_io). */
int gr_hybrid_state_io(gr_sim *s, gr_blob_io *io, gr_error *err)
{
    gr_hybrid_state *h = gr_hy(s);
    gr_blob_io_tag(io, "hybrid state", HYBRID_STATE_TAG);
    int64_t m = h->m, kicks = h->kicks;
    gr_blob_io_i64(io, &m);
    gr_blob_io_i64(io, &kicks);
    if (io->in && !io->in->bad && (m != h->m || kicks != h->kicks)) {
        gr_blob_fail(
            io->in,
            "hybrid windows of %lld steps (%s) in the checkpoint, %d steps (%s) for this scene",
            (long long)m, kicks ? "kicks" : "exact", h->m, h->kicks ? "kicks" : "exact");
    }
    gr_blob_io_f64(io, &h->margin_c);
    int64_t *const counters[] = {&h->windows, &h->rollbacks, &h->steps, &h->active_steps};
    for (size_t k = 0; k < sizeof counters / sizeof counters[0]; k++) {
        gr_blob_io_i64(io, counters[k]);
    }
    if (io->in && !io->in->bad &&
        (h->windows < 0 || h->rollbacks < 0 || h->steps < 0 || h->active_steps < 0)) {
        gr_blob_fail(io->in, "hybrid counters are negative");
    }
    if (s->dim >= 2) {
        int rc = pairs_io(s, h, io, err);
        if (rc) {
            return rc;
        }
    }
    if (!io->in) {
        return gr_blob_ok(io->out, err);
    }
    if (io->in->bad) {
        return gr_blob_done(io->in, err);
    }
    memset(h->forced, 0, (size_t)s->n);
    return GR_OK;
}

int64_t gr_hybrid_window_steps(const gr_sim *s) { return gr_hy(s) ? gr_hy(s)->m : 1; }
