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
 * the margin factor c (a test hook) and, in 2D, the candidate-pair list with the positions it was
 * built at and its cutoff (it is rebuilt only when somebody moved far enough, so it is state;
 * active.c). */
#include <stdlib.h>
#include <string.h>

#include "integrators/hybrid/hy_internal.h"

#define HYBRID_STATE_TAG 0x48594231u /* "HYB1": bump when the layout below changes */

int gr_hybrid_save_state(const gr_sim *s, gr_blob *b, gr_error *err)
{
    const gr_hybrid_state *h = gr_hy(s);
    gr_blob_put_u32(b, HYBRID_STATE_TAG);
    gr_blob_put_i64(b, h->m);
    gr_blob_put_i64(b, h->kicks);
    gr_blob_put_f64(b, h->margin_c);
    gr_blob_put_i64(b, h->windows);
    gr_blob_put_i64(b, h->rollbacks);
    gr_blob_put_i64(b, h->steps);
    gr_blob_put_i64(b, h->active_steps);
    if (s->dim == 2) {
        gr_blob_put_f64(b, h->rc_pairs);
        gr_blob_put_i64(b, h->npairs);
        gr_blob_put(b, h->pi, sizeof(int) * (size_t)h->npairs);
        gr_blob_put(b, h->pj, sizeof(int) * (size_t)h->npairs);
        gr_blob_put_f64s(b, h->xl, s->n);
        gr_blob_put_f64s(b, h->yl, s->n);
    }
    return gr_blob_ok(b, err);
}

int gr_hybrid_load_state(gr_sim *s, gr_blob_reader *r, gr_error *err)
{
    gr_hybrid_state *h = gr_hy(s);
    const int n = s->n;
    uint32_t tag = gr_blob_get_u32(r);
    if (!r->bad && tag != HYBRID_STATE_TAG) {
        gr_blob_fail(r, "hybrid state layout %08x, this build reads %08x", tag, HYBRID_STATE_TAG);
    }
    int64_t m = gr_blob_get_i64(r), kicks = gr_blob_get_i64(r);
    if (!r->bad && (m != h->m || kicks != h->kicks)) {
        gr_blob_fail(r, "hybrid windows of %lld steps (%s) in the checkpoint, %d steps (%s) for this scene", (long long)m,
                     kicks ? "kicks" : "exact", h->m, h->kicks ? "kicks" : "exact");
    }
    h->margin_c = gr_blob_get_f64(r);
    h->windows = gr_blob_get_i64(r);
    h->rollbacks = gr_blob_get_i64(r);
    h->steps = gr_blob_get_i64(r);
    h->active_steps = gr_blob_get_i64(r);
    if (!r->bad && (h->windows < 0 || h->rollbacks < 0 || h->steps < 0 || h->active_steps < 0)) {
        gr_blob_fail(r, "hybrid counters are negative");
    }
    if (s->dim == 2) {
        h->rc_pairs = gr_blob_get_f64(r);
        int64_t np = gr_blob_get_i64(r);
        if (!r->bad && (np < 0 || np > (int64_t)n * (int64_t)(n - 1) / 2 || np > (int64_t)INT32_MAX)) {
            gr_blob_fail(r, "hybrid candidate list of %lld pairs is impossible for %d particles", (long long)np, n);
        }
        if (r->bad) {
            return gr_blob_done(r, err);
        }
        if (np > h->cap_pairs) { /* the growth collect_pairs would have done */
            int *pi = realloc(h->pi, sizeof(int) * (size_t)np);
            if (pi) {
                h->pi = pi;
            }
            int *pj = pi ? realloc(h->pj, sizeof(int) * (size_t)np) : NULL;
            if (pj) {
                h->pj = pj;
            }
            if (!pi || !pj) {
                return GR_FAIL(err, GR_ENOMEM, "out of memory for a hybrid candidate list of %lld pairs", (long long)np);
            }
            h->cap_pairs = np;
        }
        h->npairs = np;
        h->adj_ok = 0;
        gr_blob_get(r, h->pi, sizeof(int) * (size_t)np);
        gr_blob_get(r, h->pj, sizeof(int) * (size_t)np);
        for (int64_t q = 0; q < np && !r->bad; q++) {
            if (h->pi[q] < 0 || h->pi[q] >= h->pj[q] || h->pj[q] >= n) {
                gr_blob_fail(r, "hybrid candidate pair %lld is (%d, %d), allowed 0 <= i < j < %d", (long long)q, h->pi[q],
                             h->pj[q], n);
            }
        }
        gr_blob_get_f64s(r, h->xl, n);
        gr_blob_get_f64s(r, h->yl, n);
        if (!r->bad && !(h->rc_pairs >= 0.0)) {
            gr_blob_fail(r, "hybrid candidate cutoff %.17g is negative", h->rc_pairs);
        }
    }
    if (r->bad) {
        return gr_blob_done(r, err);
    }
    memset(h->forced, 0, (size_t)n);
    return GR_OK;
}

int64_t gr_hybrid_window_steps(const gr_sim *s)
{
    return gr_hy(s) ? gr_hy(s)->m : 1;
}
