/* 2D neighbour finding: a cell list (sec. 2.1.2, Fig. 2.3) feeding a half Verlet list.
 *
 * Cells have side >= cutoff = d (1 + skin); a pair is listed once, from the particle whose cell
 * comes first in the half stencil (own cell, E, NE, N, NW: the "four neighbouring boxes" of
 * Fig. 2.3b). The list holds every pair closer than the cutoff and stays valid until some
 * particle has moved skin/2 (then no unlisted pair can have come into contact). With skin = 0 the
 * list is rebuilt every step, i.e. plain cell lists (kept for the benchmark that compares both).
 * Fewer than 3 cells per side would alias neighbour cells: then every pair is checked. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/kernel_laws.h" /* wrap_delta */
#include "core/sim_internal.h"

int gr_neighbours_alloc(gr_sim *s, gr_error *err)
{
    if (s->dim == 3) {
        return gr_neighbours_alloc_3d(s, err);
    }
    int n = s->n;
    s->cutoff = s->d * (1.0 + s->params.skin);
    int side = (int)floor(s->L / s->cutoff);
    /* more cells than about 2 per particle only cost memory and time */
    int max_side = (int)ceil(sqrt(2.0 * n)) + 1;
    s->ncell = side >= 3 ? (side < max_side ? side : (max_side >= 3 ? max_side : 3)) : 0;
    size_t ncells = s->ncell ? (size_t)s->ncell * (size_t)s->ncell : 1;
    s->cell_start = calloc(2 * (ncells + 1), sizeof(int)); /* second half: fill pointers */
    s->cell_of = malloc(sizeof(int) * (size_t)n);
    s->cell_order = malloc(sizeof(int) * (size_t)n);
    s->nl_start = calloc((size_t)n + 1, sizeof(int));
    s->x_ref = malloc(sizeof(double) * (size_t)n);
    s->y_ref = malloc(sizeof(double) * (size_t)n);
    s->nl_cap = 8 * (int64_t)n + 64;
    s->nl_j = malloc(sizeof(int) * (size_t)s->nl_cap);
    s->nl_contact = calloc((size_t)s->nl_cap, 1);
    if (!s->cell_start || !s->cell_of || !s->cell_order || !s->nl_start || !s->x_ref || !s->y_ref ||
        !s->nl_j || !s->nl_contact) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the neighbour list of %d particles", n);
    }
    return GR_OK;
}

int gr_neighbours_grow(gr_sim *s, int64_t need, gr_error *err)
{
    if (need <= s->nl_cap) {
        return GR_OK;
    }
    int64_t cap = need + need / 2;
    int *j = realloc(s->nl_j, sizeof(int) * (size_t)cap);
    if (!j) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory growing the neighbour list to %lld pairs",
                       (long long)cap);
    }
    s->nl_j = j;
    uint8_t *c = realloc(s->nl_contact, (size_t)cap);
    if (!c) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory growing the neighbour list to %lld pairs",
                       (long long)cap);
    }
    s->nl_contact = c;
    if (s->nl_hist) { /* contact history (contact_history.c): a slot (3D: a vector) per entry */
        const size_t per = s->dim == 3 ? 3 : 1;
        double *h = realloc(s->nl_hist, sizeof(double) * per * (size_t)cap);
        if (!h) {
            return GR_FAIL(err, GR_ENOMEM,
                           "out of memory growing the contact history to %lld pairs",
                           (long long)cap);
        }
        s->nl_hist = h;
    }
    s->nl_cap = cap;
    return GR_OK;
}

/* Contact flag of a new list entry: whether the pair overlapped at the last force evaluation,
 * one drift ago (x - v dt), so a contact that begins in the step of a rebuild is still counted. */
static inline uint8_t was_touching(const gr_sim *s, int i, int j, double dx, double dy, double r2,
                                   double d2)
{
    if (s->rad) { /* species: the pair's own contact distance */
        d2 = (s->rad[i] + s->rad[j]) * (s->rad[i] + s->rad[j]);
    }
    if (s->step == 0) {
        return r2 < d2;
    }
    double px = dx - (s->vx[j] - s->vx[i]) * s->dt, py = dy - (s->vy[j] - s->vy[i]) * s->dt;
    return px * px + py * py < d2;
}

int gr_rows_reserve(gr_sim *s, gr_rows_buf *b, int64_t need)
{
    if (need <= b->cap) {
        return 1;
    }
    if (b->own) {
        gr_error e;
        if (gr_neighbours_grow(s, need, &e)) {
            return 0;
        }
        b->j = s->nl_j;
        b->c = s->nl_contact;
        b->cap = s->nl_cap;
        return 1;
    }
    int64_t cap = need + need / 2 + 64;
    int *j = realloc(b->j, sizeof(int) * (size_t)cap);
    if (j) {
        b->j = j;
    }
    uint8_t *c = j ? realloc(b->c, (size_t)cap) : NULL;
    if (c) {
        b->c = c;
    }
    if (!j || !c) {
        return 0;
    }
    b->cap = cap;
    return 1;
}

/* The rows [r0, r1) of the half list from the cell list (the half stencil of each particle's
 * cell, cells in stencil order, particles in cell order), appended to b; s->nl_start[i] gets each
 * row's start in b. A row depends only on its particle, so rows built in pieces and put one after
 * the other are the list built in one pass. Returns 0 when out of memory. */
static int list_rows(gr_sim *s, int r0, int r1, gr_rows_buf *b)
{
    static const int stencil[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}};
    const int nc = s->ncell;
    /* the periods per axis: L, or INFINITY across walls (walls.c), where no image pair exists */
    const double Lx = s->period[0], Ly = s->period[1], rc2 = s->cutoff * s->cutoff,
                 d2 = s->d * s->d;
    const double *x = s->x, *y = s->y;
    const int *start = s->cell_start, *order = s->cell_order, *cell_of = s->cell_of;
    int *restrict row_start = s->nl_start, *restrict js = b->j;
    uint8_t *restrict touching = b->c;
    int64_t count = b->count, cap = b->cap;
    for (int i = r0; i < r1; i++) {
        row_start[i] = (int)count;
        int ci = cell_of[i], cx = ci % nc, cy = ci / nc;
        for (int k = 0; k < 5; k++) {
            int c = (cx + stencil[k][0] + nc) % nc + nc * ((cy + stencil[k][1]) % nc);
            for (int p = start[c]; p < start[c + 1]; p++) {
                int j = order[p];
                if (k == 0 && j <= i) {
                    continue;
                }
                double dx = wrap_delta(x[j] - x[i], Lx), dy = wrap_delta(y[j] - y[i], Ly);
                double r2 = dx * dx + dy * dy;
                if (r2 < rc2) {
                    if (count + 1 > cap) {
                        if (!gr_rows_reserve(s, b, count + 1)) {
                            b->count = count;
                            return 0;
                        }
                        js = b->j;
                        touching = b->c;
                        cap = b->cap;
                    }
                    touching[count] = was_touching(s, i, j, dx, dy, r2, d2);
                    js[count++] = j;
                }
            }
        }
    }
    b->count = count;
    return 1;
}

/* Rows of about equal work (pairs of the previous list plus particles) for T threads; any split
 * gives the same list. */
static void split_rows(const gr_sim *s, const int T, int *split)
{
    const int n = s->n;
    const int64_t total = (int64_t)s->nl_start[n] + n;
    int i = 0;
    split[0] = 0;
    for (int t = 1; t < T; t++) {
        const int64_t goal = total * t / T;
        while (i < n && (int64_t)s->nl_start[i] + i < goal) {
            i++;
        }
        split[t] = i;
    }
    split[T] = n;
}

/* The list on T threads (sim_internal.h): thread t builds the rows split[t] .. split[t+1] into a
 * buffer of its own with `rows`; the buffers are then copied one after the other into the list
 * (with one thread: straight into it). Sets *count to the number of pairs. */
int gr_neighbours_rows(gr_sim *s, const int T, gr_list_rows rows, int64_t *count, gr_error *err)
{
    if (T <= 1) {
        gr_rows_buf own = {
            .j = s->nl_j, .c = s->nl_contact, .cap = s->nl_cap, .count = 0, .own = 1};
        int ok = rows(s, 0, s->n, &own);
        *count = own.count;
        return ok ? GR_OK
                  : GR_FAIL(err, GR_ENOMEM,
                            "out of memory growing the neighbour list beyond %lld pairs",
                            (long long)own.count);
    }
    int *split = malloc(sizeof(int) * (size_t)(T + 1));
    int64_t *off = malloc(sizeof(int64_t) * (size_t)(T + 1));
    gr_rows_buf *buf = calloc((size_t)T, sizeof *buf);
    if (!split || !off || !buf) {
        free(split);
        free(off);
        free(buf);
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the neighbour-list buffers of %d threads",
                       T);
    }
    split_rows(s, T, split);
    int failed = 0;
#pragma omp parallel num_threads(T)
    {
        for (int t = GR_THREAD_ID; t < T; t += GR_THREAD_COUNT) {
            if (!rows(s, split[t], split[t + 1], &buf[t])) {
#pragma omp atomic write
                failed = 1;
            }
        }
#pragma omp barrier
#pragma omp single
        {
            off[0] = 0;
            for (int t = 0; t < T; t++) {
                off[t + 1] = off[t] + buf[t].count;
            }
            gr_error e;
            if (!failed && gr_neighbours_grow(s, off[T], &e)) {
                failed = 1;
            }
        } /* implied barrier: the list has room for every buffer */
        for (int t = GR_THREAD_ID; t < T && !failed; t += GR_THREAD_COUNT) {
            if (buf[t].count > 0) { /* a thread's rows may hold no pair (an empty buffer is NULL) */
                memcpy(s->nl_j + off[t], buf[t].j, sizeof(int) * (size_t)buf[t].count);
                memcpy(s->nl_contact + off[t], buf[t].c, (size_t)buf[t].count);
            }
            for (int i = split[t]; i < split[t + 1]; i++) {
                s->nl_start[i] += (int)off[t];
            }
        }
    }
    *count = off[T];
    for (int t = 0; t < T; t++) {
        free(buf[t].j);
        free(buf[t].c);
    }
    free(split);
    free(off);
    free(buf);
    return failed ? GR_FAIL(err, GR_ENOMEM,
                            "out of memory building the neighbour list on %d threads", T)
                  : GR_OK;
}

static int build_2d(gr_sim *s, gr_error *err);

int gr_neighbours_build(gr_sim *s, gr_error *err)
{
    const int rc = s->dim == 3 ? gr_neighbours_build_3d(s, err) : build_2d(s, err);
    if (!rc) {
        gr_sublist_after_build(s);
    }
    return rc;
}

static int build_2d(gr_sim *s, gr_error *err)
{
    const int n = s->n, nc = s->ncell;
    const double L = s->L, rc2 = s->cutoff * s->cutoff, d2 = s->d * s->d;
    const double *x = s->x, *y = s->y;
    int64_t count = 0;
    if (s->nl_hist) { /* keep each contact's history by pair across the rebuild */
        int rc = gr_history_save(s, err);
        if (rc) {
            return rc;
        }
    }
    if (nc == 0) {
        for (int i = 0; i < n; i++) {
            s->nl_start[i] = (int)count;
            for (int j = i + 1; j < n; j++) {
                double dx = wrap_delta(x[j] - x[i], s->period[0]),
                       dy = wrap_delta(y[j] - y[i], s->period[1]);
                double r2 = dx * dx + dy * dy;
                if (r2 < rc2) {
                    int rc = gr_neighbours_grow(s, count + 1, err);
                    if (rc) {
                        return rc;
                    }
                    s->nl_contact[count] = was_touching(s, i, j, dx, dy, r2, d2);
                    s->nl_j[count++] = j;
                }
            }
        }
    } else {
        /* every position along a periodic axis must lie in [0, L) for the cell index: wrap
         * stragglers (a particle that moved more than L in one step) and refuse non-finite ones */
        double *xw = s->x, *yw = s->y;
        /* a wall axis is not wrapped (a vibrating floor may carry grains below 0): its cells
         * clamp the coordinate below */
        const bool wrap_x = s->period[0] < (double)INFINITY,
                   wrap_y = s->period[1] < (double)INFINITY;
        for (int i = 0; i < n; i++) {
            if (!(isfinite(xw[i]) && isfinite(yw[i]))) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "unstable run: particle %d has a non-finite position (%g, %g) at "
                               "step %lld",
                               i, xw[i], yw[i], (long long)s->step);
            }
            if (!((!wrap_x || (xw[i] >= 0.0 && xw[i] < L)) &&
                  (!wrap_y || (yw[i] >= 0.0 && yw[i] < L)))) {
                const double x0 = xw[i], y0 = yw[i];
                if (wrap_x) {
                    xw[i] -= L * floor(xw[i] / L);
                    xw[i] = xw[i] >= L ? 0.0 : xw[i];
                }
                if (wrap_y) {
                    yw[i] -= L * floor(yw[i] / L);
                    yw[i] = yw[i] >= L ? 0.0 : yw[i];
                }
                if (!((!wrap_x || xw[i] >= 0.0) &&
                      (!wrap_y || yw[i] >= 0.0))) { /* |x| >> L: floor lost the box (tests/fuzz) */
                    return GR_FAIL(
                        err, GR_EUNSTABLE,
                        "unstable run: particle %d moved %g box lengths in one step, at step %lld",
                        i, fmax(fabs(x0), fabs(y0)) / L, (long long)s->step);
                }
            }
        }
        /* counting sort of particles by cell */
        const double inv = nc / L;
        int *start = s->cell_start;
        memset(start, 0, sizeof(int) * ((size_t)nc * nc + 1));
        for (int i = 0; i < n; i++) {
            int cx = (int)(x[i] * inv), cy = (int)(y[i] * inv);
            cx = cx >= nc ? nc - 1 : (cx < 0 ? 0 : cx); /* < 0, >= nc: a wall axis (above) */
            cy = cy >= nc ? nc - 1 : (cy < 0 ? 0 : cy);
            s->cell_of[i] = cx + nc * cy;
            start[s->cell_of[i] + 1]++;
        }
        for (int c = 0; c < nc * nc; c++) {
            start[c + 1] += start[c];
        }
        int *fill = start + (size_t)nc * nc + 1;
        memcpy(fill, start, sizeof(int) * (size_t)nc * nc);
        for (int i = 0; i < n; i++) {
            s->cell_order[fill[s->cell_of[i]]++] = i;
        }
        int rc = gr_neighbours_rows(s, gr_team(s), list_rows, &count, err);
        if (rc) {
            return rc;
        }
    }
    s->nl_start[n] = (int)count;
    if (s->nl_hist) {
        gr_history_restore(s);
    }
    memcpy(s->x_ref, x, sizeof(double) * (size_t)n);
    memcpy(s->y_ref, y, sizeof(double) * (size_t)n);
    s->rebuilds++;
    return GR_OK;
}
