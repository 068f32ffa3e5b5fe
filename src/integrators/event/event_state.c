/* Saving and restoring the event-driven integrator's state for exact restarts
 * (docs/checkpoints.md, "Other integrators"). Appended by src/core/sim_state.c after the
 * soft-sphere part (which holds s->x, vx, the step counter and the ledger totals).
 *
 * Between two gr_sim_step calls the reported positions are synchronised, but the event state is
 * not: every particle keeps its own base time t0 inside the current kick window, and the window's
 * noise was drawn at its start. The next call depends on: the window index, the local time and
 * phase of the last processed event; per particle the base (t0, x, v; y, vy in 2D; also z, vz in
 * 3D), the `past`
 * flag, the window's accelerations a1, a2 and jumps J, and the time of the last collision (TC
 * rule); the calendar's keys (time, phase) per entry; in 2D and 3D each entry's partner and the
 * partner's collision count at prediction, the collision counts, and the cell list itself (cell
 * of each particle and the linked lists, whose order fixes the order of predictions); the
 * counters, the booked free-flight work and the floor energy, the progress guard's counters;
 * and the target step of a call that returned early on a stop request.
 *
 * The calendar's heap layout is not stored: entries pop in the total order (time, phase,
 * index), which does not depend on the layout, so gr_heap_build on the stored keys pops exactly
 * the same sequence (in whichever calendar GRANULE_EVENT_CALENDAR picks now, calendar.c). The noise
 * normals are scratch (a window's draw is kept as a1, a2, J). */
#include <math.h>
#include <string.h>

#include "integrators/event/event_internal.h"

#define EVENT_STATE_TAG 0x45565431u /* "EVT1": bump when the layout below changes */

/* n ints as a counted array (i64 count, then the ints); the count must agree on load. */
static void i32s_io(gr_blob_io *io, int *v, int64_t n, const char *what)
{
    int64_t k = n;
    gr_blob_io_i64(io, &k);
    if (io->in && !io->in->bad && k != n) {
        gr_blob_fail(io->in, "event state: %s has %lld entries, %lld expected", what, (long long)k,
                     (long long)n);
    }
    gr_blob_io_bytes(io, v, sizeof(int) * (size_t)n);
}

/* v[k] in [lo, hi) for every k, else fail naming the array */
static void check_range(gr_blob_reader *r, const int *v, int64_t n, int lo, int hi,
                        const char *what)
{
    for (int64_t k = 0; k < n && !r->bad; k++) {
        if (v[k] < lo || v[k] >= hi) {
            gr_blob_fail(r, "event state: %s[%lld] = %d, allowed range [%d, %d)", what,
                         (long long)k, v[k], lo, hi);
        }
    }
}

/* Loading, 2D and 3D: the cell lists must partition the particles by cell_of (the predictions
 * walk them). */
static void check_cells(const struct gr_event_state *e, gr_blob_reader *r)
{
    const int64_t n = e->n;
    const int cells = e->ncell * e->ncell * (e->dim == 3 ? e->ncell : 1);
    /* -1 - face: cell faces 0 .. 2 dim - 1, with walls also the walls 2 dim .. 4 dim - 1
     * (event_cells.h) */
    check_range(r, e->partner, n,
                e->wall[0] || e->wall[1] || e->wall[2] ? -4 * e->dim : -2 * e->dim, (int)n,
                "partner");
    check_range(r, e->cell_of, n, 0, cells, "cell_of");
    check_range(r, e->head, cells, -1, (int)n, "head");
    check_range(r, e->next, n, -1, (int)n, "next");
    check_range(r, e->prev, n, -1, (int)n, "prev");
    int64_t seen = 0;
    for (int c = 0; c < cells && !r->bad; c++) {
        int before = -1;
        for (int i = e->head[c]; i >= 0 && !r->bad; i = e->next[i]) {
            if (e->cell_of[i] != c || e->prev[i] != before || ++seen > n) {
                gr_blob_fail(r,
                             "event state: the cell list of cell %d is inconsistent at particle %d",
                             c, i);
            }
            before = i;
        }
    }
    if (!r->bad && seen != n) {
        gr_blob_fail(r, "event state: the cell lists hold %lld of %lld particles", (long long)seen,
                     (long long)n);
    }
}

/* The event-driven state, listed once for saving and loading (core/blob.h, gr_blob_io); loading
 * checks each part as it arrives. */
int gr_event_state_io(gr_sim *s, gr_blob_io *io, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    gr_blob_reader *r = io->in; /* NULL when saving */
    const int64_t n = e->n;
    gr_blob_io_tag(io, "event-driven state", EVENT_STATE_TAG);
    int64_t n_saved = n, dim = e->dim;
    double tau = e->tau;
    gr_blob_io_i64(io, &n_saved);
    gr_blob_io_i64(io, &dim);
    gr_blob_io_f64(io, &tau);
    if (r && !r->bad && (n_saved != n || dim != e->dim || memcmp(&tau, &e->tau, sizeof tau) != 0)) {
        gr_blob_fail(r,
                     "event state of %lld particles in %lld D with window %.17g s, the scene has "
                     "%lld in %d D with %.17g s",
                     (long long)n_saved, (long long)dim, tau, (long long)n, e->dim, e->tau);
    }
    gr_blob_io_i64(io, &e->win);
    gr_blob_io_f64(io, &e->now);
    int64_t phase = e->phase;
    gr_blob_io_i64(io, &phase);
    if (r && !r->bad &&
        (e->win < 0 || !(e->now >= 0.0 && e->now <= e->tau) || (phase != 0 && phase != 1))) {
        gr_blob_fail(r, "event state: window %lld, local time %.17g s, phase %lld are impossible",
                     (long long)e->win, e->now, (long long)phase);
    }
    e->phase = (int)phase;
    int64_t *const counts[] = {&e->collisions, &e->crossings,    &e->kicks,
                               &e->invalid,    &e->tc_elastic,   &e->floors,
                               &e->guard_n,    &e->guard_mark_n, &e->owed_to};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        gr_blob_io_i64(io, counts[k]);
    }
    if (e->wall[0] || e->wall[1] || e->wall[2]) { /* only then: periodic runs' checkpoints are
                                                       unchanged */
        gr_blob_io_i64(io, &e->wall_hits);
    }
    double totals[] = {e->injected, e->floor_energy, e->guard_mark_t, e->t_start};
    gr_blob_io_f64s(io, totals, (int64_t)(sizeof totals / sizeof totals[0]));
    if (r) {
        e->injected = totals[0];
        e->floor_energy = totals[1];
        e->guard_mark_t = totals[2];
        e->guard_floor_mark = e->floors;
        e->t_start = totals[3];
    }
    double *const base[] = {e->t0, e->bx, e->bv, e->a1x, e->a2x, e->jx, e->last};
    for (size_t k = 0; k < sizeof base / sizeof base[0]; k++) {
        gr_blob_io_f64s(io, base[k], n);
    }
    gr_blob_io_bytes(io, e->past, (size_t)n);
    if (e->dim >= 2) {
        double *const base_2d[] = {e->by, e->bw, e->a1y, e->a2y, e->jy};
        for (size_t k = 0; k < sizeof base_2d / sizeof base_2d[0]; k++) {
            gr_blob_io_f64s(io, base_2d[k], n);
        }
    }
    if (e->dim == 3) {
        double *const base_3d[] = {e->bz, e->bu, e->a1z, e->a2z, e->jz};
        for (size_t k = 0; k < sizeof base_3d / sizeof base_3d[0]; k++) {
            gr_blob_io_f64s(io, base_3d[k], n);
        }
    }
    for (int64_t i = 0; r && i < n && !r->bad; i++) {
        if (e->past[i] > 1 || !(e->t0[i] >= 0.0 && e->t0[i] <= e->now)) {
            gr_blob_fail(r,
                         "event state: particle %lld has base time %.17g s (past %d) after the "
                         "last event at %.17g s",
                         (long long)i, e->t0[i], e->past[i], e->now);
        }
    }
    /* calendar keys */
    gr_heap *h = &e->heap;
    gr_blob_io_f64s(io, h->t, h->cap);
    gr_blob_io_bytes(io, h->ph, (size_t)h->cap);
    for (int k = 0; r && k < h->cap && !r->bad; k++) {
        if (h->ph[k] > 1 || !(h->t[k] >= e->now)) { /* +inf (never due) passes */
            gr_blob_fail(
                r,
                "event state: calendar entry %d at %.17g s (phase %d) lies before the last event",
                k, h->t[k], h->ph[k]);
        }
    }
    if (e->dim >= 2) {
        i32s_io(io, e->partner, n, "partner");
        gr_blob_io_bytes(io, e->count, sizeof(int64_t) * (size_t)n);
        gr_blob_io_bytes(io, e->ev_count, sizeof(int64_t) * (size_t)n);
        int64_t ncell = e->ncell;
        gr_blob_io_i64(io, &ncell);
        if (r && !r->bad && ncell != e->ncell) {
            gr_blob_fail(r, "event state: %lld cells per side in the checkpoint, %d for this scene",
                         (long long)ncell, e->ncell);
        }
        i32s_io(io, e->cell_of, n, "cell_of");
        i32s_io(io, e->head, (int64_t)e->ncell * e->ncell * (e->dim == 3 ? e->ncell : 1), "head");
        i32s_io(io, e->next, n, "next");
        i32s_io(io, e->prev, n, "prev");
        if (r) {
            check_cells(e, r);
        }
        if (e->rough) { /* rough discs: the spins (free flight keeps them; only collisions change them) */
            gr_blob_io_f64s(io, s->omega, n);
            for (int64_t i = 0; r && i < n && !r->bad; i++) {
                if (!isfinite(s->omega[i])) {
                    gr_blob_fail(r, "event state: particle %lld has angular velocity %g",
                                 (long long)i, s->omega[i]);
                }
            }
        }
    }
    if (!r) {
        return gr_blob_ok(io->out, err);
    }
    if (r->bad) {
        return gr_blob_done(r, err);
    }
    gr_heap_build(h);
    return GR_OK;
}

int64_t gr_event_owed_steps(const gr_sim *s)
{
    return gr_ev(s) && gr_ev(s)->owed_to > s->step ? gr_ev(s)->owed_to - s->step : 0;
}
