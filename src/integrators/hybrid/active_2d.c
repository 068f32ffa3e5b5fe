/* The active set of a 2D or 3D window (docs/hybrid.md, "Active set"; the rules are at the top of
 * active.c): candidate pairs from a cell grid kept with a skin, the pair rule over them, and the
 * closure over clusters as a work list on the active particles' candidate partners. Discs and
 * spheres share the code: the z terms are there only when dim = 3 (three), so 2D sums the same
 * terms in the same order as before. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/hybrid/hy_internal.h"

static int find(int *uf, int i)
{
    while (uf[i] != i) {
        uf[i] = uf[uf[i]];
        i = uf[i];
    }
    return i;
}

static void unite(int *uf, int i, int j)
{
    i = find(uf, i);
    j = find(uf, j);
    if (i != j) {
        if (i < j) {
            uf[j] = i;
        } else {
            uf[i] = j;
        }
    }
}

static inline int push_pair(gr_hybrid_state *h, int i, int j, gr_error *err)
{
    if (h->npairs == h->cap_pairs) {
        int64_t cap = h->cap_pairs ? 2 * h->cap_pairs : 1024;
        int *a = realloc(h->pi, sizeof(int) * (size_t)cap);
        if (a) {
            h->pi = a;
        }
        int *b = a ? realloc(h->pj, sizeof(int) * (size_t)cap) : NULL;
        if (!a || !b) {
            return GR_FAIL(err, GR_ENOMEM, "hybrid: out of memory for %lld candidate pairs",
                           (long long)cap);
        }
        h->pj = b;
        h->cap_pairs = cap;
    }
    h->pi[h->npairs] = i < j ? i : j;
    h->pj[h->npairs++] = i < j ? j : i;
    return GR_OK;
}

/* Squared minimum-image distance of i and j in the plane (2D) or space (3D). */
static inline double dist2(const gr_sim *s, int three, int i, int j)
{
    const double L = s->L, dx = gr_hy_wrap(s->x[j] - s->x[i], L),
                 dy = gr_hy_wrap(s->y[j] - s->y[i], L);
    const double r2 = dx * dx + dy * dy;
    if (!three) {
        return r2;
    }
    const double dz = gr_hy_wrap(s->z[j] - s->z[i], L);
    return r2 + dz * dz;
}

/* Every pair closer than rc (minimum image) into h->pi/pj: cells of side >= rc, each pair once
 * from the half stencil (2D: own, E, NE, N, NW; 3D: own and the 13 neighbours after it in
 * (z, y, x) order); all pairs when fewer than 3 cells fit per side. */
int gr_hy_collect_pairs(gr_sim *s, gr_hybrid_state *h, double rc, gr_error *err)
{
    const int n = s->n, three = s->dim == 3;
    const double L = s->L, rc2 = rc * rc, *x = s->x, *y = s->y, *z = three ? s->z : s->y;
    h->npairs = 0;
    h->adj_ok = 0;
    int side = (int)floor(L / rc);
    const int max_side = three ? (int)ceil(cbrt(2.0 * n)) + 1 : (int)ceil(sqrt(2.0 * n)) + 1;
    side = side < max_side ? side : max_side;
    if (side < 3) {
        for (int i = 0; i < n; i++) {
            for (int j = i + 1; j < n; j++) {
                if (dist2(s, three, i, j) < rc2 && push_pair(h, i, j, err)) {
                    return GR_ENOMEM;
                }
            }
        }
        return GR_OK;
    }
    const int nc = three ? side * side * side : side * side;
    if (nc + 1 > h->ncells_alloc) {
        int *hd = realloc(h->cell_head, sizeof(int) * ((size_t)nc + 1));
        if (!hd) {
            return GR_FAIL(err, GR_ENOMEM, "hybrid: out of memory for %d cells", nc);
        }
        h->cell_head = hd;
        h->ncells_alloc = nc + 1;
    }
    if (!h->sorted) {
        h->sorted = malloc(sizeof(int) * (size_t)n);
        h->xs = malloc(sizeof(double) * (size_t)n);
        h->ys = malloc(sizeof(double) * (size_t)n);
        h->zs = three ? malloc(sizeof(double) * (size_t)n) : NULL;
        if (!h->sorted || !h->xs || !h->ys || (three && !h->zs)) {
            free(h->sorted);
            h->sorted = NULL;
            return GR_FAIL(err, GR_ENOMEM,
                           "hybrid: out of memory for the cell grid of %d particles", n);
        }
    }
    /* counting sort by cell: cell q holds sorted[start[q] .. start[q + 1]), positions copied
     * alongside (xs, ys) so the pair loops read them contiguously */
    int *start = h->cell_head, *cell = h->cell_next, *sorted = h->sorted;
    double *xs = h->xs, *ys = h->ys, *zs = three ? h->zs : h->ys; /* zs read only in 3D */
    memset(start, 0, sizeof(int) * ((size_t)nc + 1));
    const double inv = side / L;
    for (int i = 0; i < n; i++) {
        int cx = (int)(x[i] * inv), cy = (int)(y[i] * inv), cz = three ? (int)(z[i] * inv) : 0;
        cx = cx < 0 ? 0 : (cx >= side ? side - 1 : cx);
        cy = cy < 0 ? 0 : (cy >= side ? side - 1 : cy);
        cz = cz < 0 ? 0 : (cz >= side ? side - 1 : cz);
        cell[i] = (cz * side + cy) * side + cx;
        start[cell[i] + 1]++;
    }
    for (int q = 0; q < nc; q++) {
        start[q + 1] += start[q];
    }
    for (int i = 0; i < n; i++) {
        const int k = start[cell[i]]++;
        sorted[k] = i;
        xs[k] = x[i];
        ys[k] = y[i];
        if (three) {
            zs[k] = z[i];
        }
    }
    for (int q = nc; q > 0; q--) {
        start[q] = start[q - 1];
    }
    start[0] = 0;
    /* each pair once from the half stencil: 2D own, E, NE, N, NW; 3D own, then the plane z
     * (E, NE, N, NW) and the 9 cells of the plane above */
    static const int sx_[14] = {0, 1, 1, 0, -1, -1, 0, 1, -1, 0, 1, -1, 0, 1},
                     sy_[14] = {0, 0, 1, 1, 1, -1, -1, -1, 0, 0, 0, 1, 1, 1},
                     sz_[14] = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    const int nst = three ? 14 : 5;
    for (int cz = 0; cz < (three ? side : 1); cz++) {
        for (int cy = 0; cy < side; cy++) {
            for (int cx = 0; cx < side; cx++) {
                const int q = (cz * side + cy) * side + cx;
                for (int st = 0; st < nst; st++) {
                    int ox = cx + sx_[st], oy = cy + sy_[st], oz = cz + sz_[st];
                    ox = ox >= side ? ox - side : (ox < 0 ? ox + side : ox);
                    oy = oy >= side ? oy - side : (oy < 0 ? oy + side : oy);
                    oz = oz >= side ? oz - side : oz;
                    const int o = (oz * side + oy) * side + ox;
                    for (int a = start[q]; a < start[q + 1]; a++) {
                        for (int b = st == 0 ? a + 1 : start[o]; b < start[o + 1]; b++) {
                            const double dx = gr_hy_wrap(xs[b] - xs[a], L),
                                         dy = gr_hy_wrap(ys[b] - ys[a], L),
                                         dz = three ? gr_hy_wrap(zs[b] - zs[a], L) : 0.0;
                            const double r2 =
                                three ? dx * dx + dy * dy + dz * dz : dx * dx + dy * dy;
                            if (r2 < rc2 && push_pair(h, sorted[a], sorted[b], err)) {
                                return GR_ENOMEM;
                            }
                        }
                    }
                }
            }
        }
    }
    return GR_OK;
}

/* Closest distance of r + u t to the origin for t in [0, tau] (2D: rz = uz = 0). */
static inline double closest(double rx, double ry, double rz, double ux, double uy, double uz,
                             double tau)
{
    const double uu = ux * ux + uy * uy + uz * uz;
    double t = uu > 0.0 ? -(rx * ux + ry * uy + rz * uz) / uu : 0.0;
    t = t < 0.0 ? 0.0 : (t > tau ? tau : t);
    const double px = rx + ux * t, py = ry + uy * t, pz = rz + uz * t;
    return sqrt(px * px + py * py + pz * pz);
}

/* Largest displacement since the candidate list was built (minimum image). */
double gr_hy_max_disp(const gr_sim *s, const gr_hybrid_state *h)
{
    const int n = s->n;
    const double L = s->L, *restrict x = s->x, *restrict y = s->y, *restrict xl = h->xl,
                 *restrict yl = h->yl;
    double wl[8] = {0}; /* 8 fixed lanes, so the loop vectorises */
    if (s->dim == 3) {
        const double *restrict z = s->z, *restrict zl = h->zl;
        for (int i0 = 0; i0 < n; i0 += 8) {
            const int lanes = n - i0 < 8 ? n - i0 : 8;
#pragma omp simd
            for (int l = 0; l < lanes; l++) {
                const double dx = gr_hy_wrap(x[i0 + l] - xl[i0 + l], L),
                             dy = gr_hy_wrap(y[i0 + l] - yl[i0 + l], L),
                             dz = gr_hy_wrap(z[i0 + l] - zl[i0 + l], L);
                const double r2 = dx * dx + dy * dy + dz * dz;
                wl[l] = r2 > wl[l] ? r2 : wl[l];
            }
        }
    }
    for (int i0 = 0; i0 < n && s->dim != 3; i0 += 8) {
        const int lanes = n - i0 < 8 ? n - i0 : 8;
#pragma omp simd
        for (int l = 0; l < lanes; l++) {
            const double dx = gr_hy_wrap(x[i0 + l] - xl[i0 + l], L),
                         dy = gr_hy_wrap(y[i0 + l] - yl[i0 + l], L);
            const double r2 = dx * dx + dy * dy;
            wl[l] = r2 > wl[l] ? r2 : wl[l];
        }
    }
    double worst = 0.0;
    for (int l = 0; l < 8; l++) {
        worst = wl[l] > worst ? wl[l] : worst;
    }
    return sqrt(worst);
}

/* The 2D selection's work arrays, allocated on first use (h->speed set means all are there). */
static int alloc_work(gr_hybrid_state *h, int n, gr_error *err)
{
    int **ints[] = {&h->adj_start, &h->mem_head, &h->mem_tail,
                    &h->mem_next,  &h->mem_size, &h->queue};
    int ok = 1;
    for (size_t k = 0; k < sizeof ints / sizeof ints[0]; k++) {
        free(*ints[k]); /* left by an earlier failed attempt */
        *ints[k] = malloc(sizeof(int) * ((size_t)n + 1));
        ok = ok && *ints[k];
    }
    free(h->inq);
    h->inq = calloc((size_t)n, 1);
    double *speed = malloc(sizeof(double) * (size_t)n);
    if (!ok || !h->inq || !speed) {
        free(speed);
        return GR_FAIL(err, GR_ENOMEM,
                       "hybrid: out of memory for the active-set selection of %d particles", n);
    }
    h->speed = speed;
    return GR_OK;
}

/* Candidate partners of every particle (compressed rows over h->pi/pj): rebuilt after each
 * collect_pairs or restore (h->adj_ok = 0 there). */
static int build_adjacency(gr_hybrid_state *h, int n, gr_error *err)
{
    if (!h->adj || 2 * h->npairs > h->cap_adj) { /* also with no pairs at all (dilute) */
        free(h->adj);
        h->cap_adj = 2 * h->cap_pairs + 2;
        h->adj = malloc(sizeof(int) * (size_t)h->cap_adj);
    }
    if (!h->adj_start || !h->adj) {
        h->cap_adj = 0;
        return GR_FAIL(err, GR_ENOMEM,
                       "hybrid: out of memory for the partners of %lld candidate pairs",
                       (long long)h->npairs);
    }
    int *st = h->adj_start;
    memset(st, 0, sizeof(int) * ((size_t)n + 1));
    for (int64_t q = 0; q < h->npairs; q++) {
        st[h->pi[q] + 1]++;
        st[h->pj[q] + 1]++;
    }
    for (int i = 0; i < n; i++) {
        st[i + 1] += st[i];
    }
    for (int64_t q = 0; q < h->npairs; q++) { /* fill, then shift the starts back */
        h->adj[st[h->pi[q]]++] = h->pj[q];
        h->adj[st[h->pj[q]]++] = h->pi[q];
    }
    for (int i = n; i > 0; i--) {
        st[i] = st[i - 1];
    }
    st[0] = 0;
    h->adj_ok = 1;
    return GR_OK;
}

/* The work list of the 2D closure (select_2d). */
struct closure {
    gr_hybrid_state *h;
    double f, csv, w0; /* reach of a cluster: f max|v| + c sv + w0 max overlap */
    int head, len, n;
    int *queue;
};

static inline double reach(const struct closure *w, int root)
{
    return w->f * w->h->c_hi[root] + w->csv + w->w0 * w->h->c_lo[root];
}

static void push(struct closure *w, int i)
{
    if (!w->h->inq[i]) {
        w->h->inq[i] = 1;
        int t = w->head + w->len;
        w->queue[t < w->n ? t : t - w->n] = i;
        w->len++;
    }
}

/* Merge the clusters with roots a and b and return the new root. The larger cluster's root
 * stays; the smaller one's members are relabelled, so h->uf[i] is always i's root here. The
 * members of a cluster whose reach grew are examined again. */
static int merge(struct closure *w, int a, int b)
{
    gr_hybrid_state *h = w->h;
    const double ra = reach(w, a), rb = reach(w, b);
    const int r = h->mem_size[a] >= h->mem_size[b] ? a : b, o = r == a ? b : a;
    h->c_hi[r] = h->c_hi[a] > h->c_hi[b] ? h->c_hi[a] : h->c_hi[b];
    h->c_lo[r] = h->c_lo[a] > h->c_lo[b] ? h->c_lo[a] : h->c_lo[b];
    const double rn = reach(w, r);
    for (int side = 0; side < 2; side++) {
        if (rn > (side ? rb : ra)) {
            for (int i = h->mem_head[side ? b : a]; i >= 0; i = h->mem_next[i]) {
                push(w, i);
            }
        }
    }
    for (int i = h->mem_head[o]; i >= 0; i = h->mem_next[i]) {
        h->uf[i] = r;
    }
    h->mem_next[h->mem_tail[r]] = h->mem_head[o];
    h->mem_tail[r] = h->mem_tail[o];
    h->mem_size[r] += h->mem_size[o];
    return r;
}

int gr_hy_select_2d(gr_sim *s, gr_hybrid_state *h, int m, gr_error *err)
{
    const int n = s->n;
    const double tau = m * s->dt, c = h->margin_c, sx = gr_hy_noise_sx(s, h, m),
                 sv = gr_hy_noise_sv(s, h, m);
    const double d = s->d, L = s->L, w0 = h->w0_max, f = 1.0 + h->spread;
    const int three = s->dim == 3; /* z, vz read only in 3D (valid arrays in 2D all the same) */
    const double *x = s->x, *y = s->y, *vx = s->vx, *vy = s->vy, *z = three ? s->z : s->y,
                 *vz = three ? s->vz : s->vy;
    uint8_t *act = h->active;
    if (!h->speed && alloc_work(h, n, err)) {
        return GR_ENOMEM;
    }
    double *restrict speed = h->speed;
    int *restrict uf = h->uf;
    double vml[8] = {0}; /* max speed in 8 fixed lanes, so the loop vectorises */
    for (int i0 = 0; i0 < n && three; i0 += 8) {
        const int lanes = n - i0 < 8 ? n - i0 : 8;
#pragma omp simd
        for (int l = 0; l < lanes; l++) {
            const int i = i0 + l;
            speed[i] = sqrt(vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]);
            vml[l] = speed[i] > vml[l] ? speed[i] : vml[l];
            uf[i] = i;
        }
    }
    for (int i0 = 0; i0 < n && !three; i0 += 8) {
        const int lanes = n - i0 < 8 ? n - i0 : 8;
#pragma omp simd
        for (int l = 0; l < lanes; l++) {
            const int i = i0 + l;
            speed[i] = sqrt(vx[i] * vx[i] + vy[i] * vy[i]);
            vml[l] = speed[i] > vml[l] ? speed[i] : vml[l];
            uf[i] = i;
        }
    }
    double vmax = 0.0;
    for (int l = 0; l < 8; l++) {
        vmax = vml[l] > vmax ? vml[l] : vmax;
    }
    memset(h->c_xi, 0, sizeof(double) * (size_t)n);
    /* Cheap rejections below compare squared distances with bounds from the speeds, widened by
     * this relative slack so that rounding can never reject a pair the exact test would take. */
    const double slack = 1.0 + 1e-9;
    const double xi_all = s->last.max_overlap * d;
    const double s_all = f * vmax + c * sv + w0 * xi_all;
    const double rc = d + c * M_SQRT2 * sx + 2.0 * tau * s_all;
    /* The candidate list is kept with a skin (like the Verlet list of src/core/neighbours.c):
     * built with cutoff rc + skin, it holds every pair closer than rc as long as nobody has
     * moved more than (cutoff - rc)/2 since the build. */
    const double moved = gr_hy_max_disp(s, h);
    if (!(h->rc_pairs > 0.0 && rc + 2.0 * moved <= h->rc_pairs)) {
        h->rc_pairs = rc + GR_HYBRID_LIST_SKIN * d;
        int rc_ = gr_hy_collect_pairs(s, h, h->rc_pairs, err);
        if (rc_) {
            h->rc_pairs = 0.0;
            return rc_;
        }
        memcpy(h->xl, x, sizeof(double) * (size_t)n);
        memcpy(h->yl, y, sizeof(double) * (size_t)n);
        if (three) {
            memcpy(h->zl, z, sizeof(double) * (size_t)n);
        }
    }
    if (!h->adj_ok) {
        int rc_ = build_adjacency(h, n, err);
        if (rc_) {
            return rc_;
        }
    }
    const double margin_free = c * M_SQRT2 * sx;
    for (int64_t q = 0; q < h->npairs; q++) {
        const int i = h->pi[q], j = h->pj[q];
        /* the pair's own contact distance (a mixture's r_i + r_j; d for one species) */
        const double dij = gr_pair_d(s, i, j), free_reach = dij + margin_free;
        const double rx = gr_hy_wrap(x[j] - x[i], L), ry = gr_hy_wrap(y[j] - y[i], L),
                     rz = three ? gr_hy_wrap(z[j] - z[i], L) : 0.0,
                     r2 = rx * rx + ry * ry + rz * rz;
        if (r2 < dij * dij) {
            const double ov = dij - sqrt(r2);
            h->c_xi[i] = ov > h->c_xi[i] ? ov : h->c_xi[i];
            h->c_xi[j] = ov > h->c_xi[j] ? ov : h->c_xi[j];
        }
        /* cheap rejects: the pair cannot close in more than |u| tau <= (|v_i| + |v_j|) tau */
        const double bound = free_reach + tau * (speed[i] + speed[j]);
        if (r2 > bound * bound * slack) {
            continue;
        }
        const double ux = vx[j] - vx[i], uy = vy[j] - vy[i], uz = three ? vz[j] - vz[i] : 0.0,
                     reach = free_reach + tau * sqrt(ux * ux + uy * uy + uz * uz);
        if (r2 >= reach * reach) {
            continue;
        }
        if (closest(rx, ry, rz, ux, uy, uz, tau) < free_reach) {
            act[i] = act[j] = 1;
            unite(h->uf, i, j);
        }
    }
    /* Closure, as a work list: a particle is (re)examined when it becomes active or when its
     * cluster's reach grows; each examination tests its candidate partners against the current
     * reach. Every test can only add particles or merge clusters, and a larger cluster only
     * reaches further, so the result (the smallest closed set) does not depend on the order;
     * it is the same set the earlier pass-until-nothing-changes loop gave. */
    struct closure w = {h, f, c * sv, w0, 0, 0, n, h->queue};
    int *al = h->list, na = 0; /* the active particles, in the order they became active */
    for (int i = 0; i < n; i++) {
        if (act[i]) {
            al[na++] = i;
        }
    }
    for (int e = 0; e < na; e++) {
        const int r = find(h->uf, al[e]);
        h->c_hi[r] = 0.0; /* max speed of the cluster */
        h->c_lo[r] = 0.0; /* max overlap of the cluster */
        h->mem_tail[r] = -1;
        h->mem_size[r] = 0;
    }
    for (int e = 0; e < na; e++) {
        const int i = al[e], r = find(h->uf, i);
        h->uf[i] = r; /* flat from here on: merge() relabels */
        h->mem_size[r]++;
        h->c_hi[r] = speed[i] > h->c_hi[r] ? speed[i] : h->c_hi[r];
        h->c_lo[r] = h->c_xi[i] > h->c_lo[r] ? h->c_xi[i] : h->c_lo[r];
        h->mem_next[i] = -1; /* member lists: head at the root, appended at the tail */
        if (h->mem_tail[r] < 0) {
            h->mem_head[r] = i;
        } else {
            h->mem_next[h->mem_tail[r]] = i;
        }
        h->mem_tail[r] = i;
        push(&w, i);
    }
    while (w.len > 0) {
        const int A = w.queue[w.head];
        w.head = w.head + 1 < n ? w.head + 1 : 0;
        w.len--;
        h->inq[A] = 0;
        for (int k = h->adj_start[A]; k < h->adj_start[A + 1]; k++) {
            const int F = h->adj[k];
            const int a = h->uf[A], b = act[F] ? h->uf[F] : -1;
            if (a == b) {
                continue;
            }
            const double rx = gr_hy_wrap(x[F] - x[A], L), ry = gr_hy_wrap(y[F] - y[A], L),
                         rz = three ? gr_hy_wrap(z[F] - z[A], L) : 0.0; /* r from A to F */
            const double r2 = rx * rx + ry * ry + rz * rz, ra = reach(&w, a),
                         dAF = gr_pair_d(s, A, F);
            if (b >= 0) {
                const double rb = reach(&w, b), bound = dAF + (ra + rb) * tau;
                if (r2 <= bound * bound * slack && sqrt(r2) - (ra + rb) * tau < dAF) {
                    merge(&w, a, b);
                }
                continue;
            }
            /* A active, F free: F's straight path (closest approach >= |r| - |v_F| tau) against
             * A's reach */
            const double bound = dAF + c * sx + (ra + speed[F]) * tau;
            if (r2 <= bound * bound * slack &&
                closest(rx, ry, rz, vx[F], vy[F], three ? vz[F] : 0.0, tau) - ra * tau <
                    dAF + c * sx) {
                act[F] = 1;
                al[na++] = F;
                h->c_hi[F] = speed[F];
                h->c_lo[F] = h->c_xi[F];
                h->mem_head[F] = h->mem_tail[F] = F;
                h->mem_next[F] = -1;
                h->mem_size[F] = 1;
                h->uf[F] = F;
                push(&w, F);
                merge(&w, a, F);
            }
        }
    }
    /* envelopes: active particles with a free candidate partner must stay within s_C t */
    for (int e = 0; e < na; e++) {
        const int A = al[e], a = find(h->uf, A);
        h->env_lo[A] = -(double)INFINITY;
        h->env_hi[A] = (double)INFINITY;
        for (int k = h->adj_start[A]; k < h->adj_start[A + 1]; k++) {
            if (!act[h->adj[k]]) {
                h->env_hi[A] = reach(&w, a);
                break;
            }
        }
    }
    return GR_OK;
}
