/* Spheres in a periodic cube ([system] dim = 3, docs/three-dimensions.md): the neighbour list and
 * the generic 3D force kernel.
 *
 * Neighbours. A cell list with cells of side >= cutoff = d (1 + skin) (at most about 2 cells per
 * particle) feeds a half Verlet list in the CSR arrays the 2D list uses (nl_start, nl_j,
 * nl_contact): row i lists every j > i closer than the cutoff, found in the 27 cells around i's
 * (so each pair once, from its lower index; the rows are in particle order and each row in a
 * fixed cell order, so the list is a pure function of the positions). Fewer than 3 cells per
 * edge would alias neighbour cells: then every pair is checked. The list is rebuilt when some
 * particle has moved skin/2 since the last build (verlet/step.c), as in 2D.
 *
 * Kernel. For a listed pair i < j at overlap xi = d - |r_ij| > 0, n = r_ij / |r_ij| (from i to
 * j), g = v_j - v_i, g_n = g.n: the normal law (the same always-inline normal_law as in 1D and
 * 2D, core/kernel_laws.h) gives f_n and its non-conservative part f_d; the force on j is f_n n, on
 * i its opposite, and G = f_d n is kept apart for the ledger (it dissipates -f_d g_n).
 *
 * Tangential laws, rotation, rolling (docs/three-dimensions.md). With a = |r_ij| / 2 (the contact
 * point lies midway for equal spheres) and w the angular velocity vectors, the contact point's
 * tangential relative velocity is g_c = g - g_n n + a n x (w_i + w_j) (the surface of i there
 * moves with v_i + w_i x (a n), that of j with v_j - w_j x (a n)). A law without history acts
 * along g_c with its 2D scalar code at |g_c|; the history law's vector step keeps s in the
 * current tangent plane (turned and rescaled to its length, as LAMMPS pair granular). The force
 * F_t on j (-F_t on i) at the contact point exerts the torque -a n x F_t on both spheres; the
 * pair's orbital torque 2 a n x F_t cancels them, so angular momentum is conserved. The rolling
 * law takes the relative spin in the tangent plane. Two instances: the normal law alone, and
 * every law read from the simulation (a branch per pair on the law, no indirect call).
 *
 * Threads: as in 2D (kernels.c, serial_2d), with the same cross lists (build_cross): each thread
 * owns a range of particles and adds, in list order, exactly the additions one thread makes; the ledger sums are formed per block of rows and combined in block
 * order. Forces, torques, history vectors and the ledger are bit-identical for every thread
 * count. The neighbour list's rows are built on the threads too (gr_neighbours_rows). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* As in kernels.c: with the law ids read at run time GCC cannot see that pair_3d sets every field
 * the same ids later read, and warns of uninitialised use; the warning is false. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "core/kernel_laws.h"

int gr_neighbours_alloc_3d(gr_sim *s, gr_error *err)
{
    const int n = s->n;
    s->cutoff = s->d * (1.0 + s->params.skin);
    const double side = floor(s->L / s->cutoff);
    const int max_side = (int)ceil(cbrt(2.0 * n)) + 1; /* more cells only cost memory and time */
    const int nc = side >= 3.0 ? (side < max_side ? (int)side : (max_side >= 3 ? max_side : 3)) : 0;
    s->ncell = nc;
    const size_t ncells = nc ? (size_t)nc * nc * nc : 1;
    s->cell_start = calloc(2 * (ncells + 1), sizeof(int)); /* second half: fill pointers */
    s->cell_of = malloc(sizeof(int) * (size_t)(n + 1));
    s->cell_order = malloc(sizeof(int) * (size_t)(n + 1));
    s->nl_start = calloc((size_t)n + 1, sizeof(int));
    s->x_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->y_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->z_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->nl_cap = 16 * (int64_t)n + 64;
    s->nl_j = malloc(sizeof(int) * (size_t)s->nl_cap);
    s->nl_contact = calloc((size_t)s->nl_cap, 1);
    if (!s->cell_start || !s->cell_of || !s->cell_order || !s->nl_start || !s->x_ref || !s->y_ref ||
        !s->z_ref || !s->nl_j || !s->nl_contact) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the neighbour list of %d spheres", n);
    }
    return GR_OK;
}

/* The contact flag of a new entry (i, j) at separation (dx, dy, dz): whether it overlapped at the
 * last force evaluation, one drift ago (r - g dt), so a contact that begins in the step of a
 * rebuild is still counted as new. */
static inline uint8_t was_touching_3d(const gr_sim *s, const int i, const int j, const double dx,
                                      const double dy, const double dz, const double r2)
{
    /* species: the pair's own contact distance */
    const double d2 = s->rad ? (s->rad[i] + s->rad[j]) * (s->rad[i] + s->rad[j]) : s->d * s->d;
    if (s->step == 0) {
        return r2 < d2;
    }
    const double dt = s->dt, px = dx - (s->vx[j] - s->vx[i]) * dt,
                 py = dy - (s->vy[j] - s->vy[i]) * dt, pz = dz - (s->vz[j] - s->vz[i]) * dt;
    return px * px + py * py + pz * pz < d2;
}

/* Append pair (i, j) if closer than the cutoff, with its contact flag (all pairs: no cells). */
static inline int consider(gr_sim *s, const int i, const int j, int64_t *count, gr_error *err)
{
    const double rc2 = s->cutoff * s->cutoff;
    const double dx = wrap_delta(s->x[j] - s->x[i], s->period[0]),
                 dy = wrap_delta(s->y[j] - s->y[i], s->period[1]),
                 dz = wrap_delta(s->z[j] - s->z[i], s->period[2]);
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= rc2) {
        return GR_OK;
    }
    int rc = gr_neighbours_grow(s, *count + 1, err);
    if (rc) {
        return rc;
    }
    s->nl_contact[*count] = was_touching_3d(s, i, j, dx, dy, dz, r2);
    s->nl_j[(*count)++] = j;
    return GR_OK;
}

/* The rows [r0, r1) of the list from the cell list (gr_list_rows): each j > i in the 27 cells
 * around i's, in a fixed cell order. Returns 0 when out of memory. */
static int rows_3d_cells(gr_sim *s, const int r0, const int r1, gr_rows_buf *b)
{
    const int nc = s->ncell;
    const int *start = s->cell_start, *order = s->cell_order, *cell_of = s->cell_of;
    const double rc2 = s->cutoff * s->cutoff;
    const double *x = s->x, *y = s->y, *z = s->z, *P = s->period;
    int64_t count = b->count;
    for (int i = r0; i < r1; i++) {
        s->nl_start[i] = (int)count;
        const int ci = cell_of[i], cx = ci % nc, cy = ci / nc % nc, cz = ci / nc / nc;
        /* the three neighbouring columns, rows and layers, wrapped once per particle (the
         * modulo per cell cost 6 % of a bed's step) */
        int wx[3], wy[3], wz[3];
        for (int o = 0; o < 3; o++) {
            wx[o] = (cx + o - 1 + nc) % nc;
            wy[o] = nc * ((cy + o - 1 + nc) % nc);
            wz[o] = nc * nc * ((cz + o - 1 + nc) % nc);
        }
        for (int oz = 0; oz < 3; oz++) {
            for (int oy = 0; oy < 3; oy++) {
                for (int ox = 0; ox < 3; ox++) {
                    const int c = wx[ox] + wy[oy] + wz[oz];
                    for (int k = start[c]; k < start[c + 1]; k++) {
                        const int j = order[k];
                        if (j <= i) {
                            continue;
                        }
                        const double dx = wrap_delta(x[j] - x[i], P[0]),
                                     dy = wrap_delta(y[j] - y[i], P[1]),
                                     dz = wrap_delta(z[j] - z[i], P[2]);
                        const double r2 = dx * dx + dy * dy + dz * dz;
                        if (r2 >= rc2) {
                            continue;
                        }
                        if (count + 1 > b->cap && !gr_rows_reserve(s, b, count + 1)) {
                            b->count = count;
                            return 0;
                        }
                        b->c[count] = was_touching_3d(s, i, j, dx, dy, dz, r2);
                        b->j[count++] = j;
                    }
                }
            }
        }
    }
    b->count = count;
    return 1;
}

/* Put every coordinate into [0, L) (a particle that moved out of the box in one step) and refuse
 * non-finite ones; along a wall axis (walls.c) a coordinate stays as it is (a grain on a floor
 * vibrating below 0). */
static int wrap_positions(gr_sim *s, gr_error *err)
{
    const double L = s->L;
    double *r[3] = {s->x, s->y, s->z};
    for (int i = 0; i < s->n; i++) {
        for (int a = 0; a < 3; a++) {
            double *q = &r[a][i];
            if ((*q >= 0.0 && *q < L) || (s->period[a] > L && isfinite(*q))) {
                continue;
            }
            if (!isfinite(*q)) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "unstable run: particle %d has a non-finite position (%g, %g, %g) "
                               "at step %lld",
                               i, s->x[i], s->y[i], s->z[i], (long long)s->step);
            }
            const double q0 = *q;
            *q -= L * floor(*q / L);
            *q = *q >= L ? 0.0 : *q;
            if (!(*q >= 0.0)) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "unstable run: particle %d moved %g box lengths in one step, at "
                               "step %lld",
                               i, fabs(q0) / L, (long long)s->step);
            }
        }
    }
    return GR_OK;
}

int gr_neighbours_build_3d(gr_sim *s, gr_error *err)
{
    const int n = s->n, nc = s->ncell;
    int64_t count = 0;
    int rc = wrap_positions(s, err);
    if (!rc && s->nl_hist) { /* keep each contact's history by pair across the rebuild */
        rc = gr_history_save(s, err);
    }
    if (rc) {
        return rc;
    }
    if (nc == 0) {
        for (int i = 0; i < n; i++) {
            s->nl_start[i] = (int)count;
            for (int j = i + 1; j < n && !rc; j++) {
                rc = consider(s, i, j, &count, err);
            }
        }
    } else {
        /* counting sort of the particles by cell (x fastest, then y, then z) */
        const double inv = nc / s->L;
        const size_t ncells = (size_t)nc * nc * nc;
        int *start = s->cell_start, *fill = s->cell_start + ncells + 1;
        memset(start, 0, sizeof(int) * (ncells + 1));
        for (int i = 0; i < n; i++) {
            int c[3] = {(int)(s->x[i] * inv), (int)(s->y[i] * inv), (int)(s->z[i] * inv)};
            for (int a = 0; a < 3; a++) {
                c[a] = c[a] >= nc ? nc - 1 : c[a] < 0 ? 0 : c[a]; /* < 0: below a vibrating floor */
            }
            s->cell_of[i] = c[0] + nc * (c[1] + nc * c[2]);
            start[s->cell_of[i] + 1]++;
        }
        for (size_t c = 0; c < ncells; c++) {
            start[c + 1] += start[c];
        }
        memcpy(fill, start, sizeof(int) * ncells);
        for (int i = 0; i < n; i++) {
            s->cell_order[fill[s->cell_of[i]]++] = i;
        }
        rc = gr_neighbours_rows(s, gr_team(s), rows_3d_cells, &count, err);
    }
    if (rc) {
        return rc;
    }
    s->nl_start[n] = (int)count;
    if (s->nl_hist) {
        gr_history_restore(s);
    }
    memcpy(s->x_ref, s->x, sizeof(double) * (size_t)n);
    memcpy(s->y_ref, s->y, sizeof(double) * (size_t)n);
    memcpy(s->z_ref, s->z, sizeof(double) * (size_t)n);
    s->rebuilds++;
    return GR_OK;
}

/* What every pair needs, loaded once per evaluation. */
typedef struct ctx3 {
    const double *restrict x, *restrict y, *restrict z, *restrict vx, *restrict vy, *restrict vz;
    const double *restrict wx, *restrict wy, *restrict wz; /* rotation only */
    double P[3];    /* the periods: L, or INFINITY along a wall axis (walls.c) */
    GR_PAIR_CONSTS; /* d, d^2, m_t / dt, I / (2 dt), the laws' coefficients (kernel_laws.h) */
} ctx3;

/* One pair's results: the force on j (F; -F on i) and its non-conservative part G; the torque of
 * the tangential force on i and on j alike (T) and its non-conservative part (TG, history laws);
 * the rolling torque on j (R; -R on i); the ledger terms; a history law's new vector (hs). */
typedef struct pair3 {
    double F[3], G[3], T[3], TG[3], R[3], hs[3];
    double el, pn, pt, pr, ov, et, lost;
} pair3;

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* c = a x b */
static inline void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The pair's unit normal n (i to j), distance, and the contact point's tangential relative
 * velocity g_c = g - (g.n) n + a n x (w_i + w_j) (rotation; a = |r_ij| / 2), with g = v_j - v_i.
 * Returns r^2 (the caller compares it with d^2 first: n, g_c are set only when r2 < d2). */
static inline __attribute__((always_inline)) double geometry(const ctx3 *c, const int i,
                                                             const int j, const int rot,
                                                             double n[3], double *dist, double *g_n,
                                                             double gc[3])
{
    const double dx = wrap_delta(c->x[j] - c->x[i], c->P[0]),
                 dy = wrap_delta(c->y[j] - c->y[i], c->P[1]),
                 dz = wrap_delta(c->z[j] - c->z[i], c->P[2]);
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= c->d2) {
        return r2;
    }
    *dist = sqrt(r2);
    const double inv = 1.0 / *dist;
    n[0] = dx * inv;
    n[1] = dy * inv;
    n[2] = dz * inv;
    const double g[3] = {c->vx[j] - c->vx[i], c->vy[j] - c->vy[i], c->vz[j] - c->vz[i]};
    *g_n = dot3(g, n);
    for (int a = 0; a < 3; a++) {
        gc[a] = g[a] - *g_n * n[a];
    }
    if (rot) {
        const double W[3] = {c->wx[i] + c->wx[j], c->wy[i] + c->wy[j], c->wz[i] + c->wz[j]};
        double nw[3];
        cross3(n, W, nw);
        const double arm = 0.5 * *dist;
        for (int a = 0; a < 3; a++) {
            gc[a] += arm * nw[a];
        }
    }
    return r2;
}

/* One listed pair i < j: 0 when it does not overlap (nothing set), else 1 with o filled. h: the
 * pair's history vector (history laws), copied in and returned in o->hs. */
static inline __attribute__((always_inline)) int pair_3d(const ctx3 *c, const int i, const int j,
                                                         const int nl, const int tl,
                                                         const int clamp, const int rot,
                                                         const int rl, const double *h, pair3 *o)
{
    double n[3], dist = 0.0, g_n = 0.0, gc[3];
    if (geometry(c, i, j, rot && tl != TL_none, n, &dist, &g_n, gc) >= c->d2) {
        return 0;
    }
    const double ov = c->d - dist;
    const gr_normal_force fn = normal_law(nl, &c->cc, ov, g_n, clamp);
    o->el = fn.e;
    o->pn = fn.f_d * g_n;
    o->ov = ov;
    o->pt = 0.0;
    for (int a = 0; a < 3; a++) {
        o->F[a] = fn.f * n[a];
        o->G[a] = fn.f_d * n[a];
    }
    const int acts = !clamp || fn.f > 0.0;
    if (tl != TL_none) {
        double Ft[3], Fn[3]; /* the tangential force on j and its non-conservative part */
        if (history_of(tl)) {
            double s[3] = {h[0], h[1], h[2]};
            gr_to_plane(s, n);
            const gr_tangential_in3 in = {.g = {gc[0], gc[1], gc[2]},
                                          .f_n = fn.f,
                                          .xi = ov,
                                          .g_n = g_n,
                                          .acts = acts,
                                          .hist = s};
            const gr_tangential_force3 ft = tangential3_law(tl, &c->cc, in);
            for (int a = 0; a < 3; a++) {
                Ft[a] = ft.f[a];
                Fn[a] = ft.f[a] - ft.fc[a];
                o->hs[a] = s[a];
            }
            o->et = ft.e;
            o->lost = ft.lost;
            o->pt = -dot3(Fn, gc);
        } else {
            /* a law without history acts along g_c: its scalar law at |g_c| (models/law.h) */
            const double gm = sqrt(dot3(gc, gc));
            const gr_tangential_in in = {.g_t = gm,
                                         .f_n = fn.f,
                                         .xi = ov,
                                         .g_n = g_n,
                                         .acts = acts,
                                         .m12_dt = c->m12_dt,
                                         .hist = NULL};
            const gr_tangential_force ft = tangential_law(tl, &c->cc, in);
            const double along = gm > 0.0 ? ft.f / gm : 0.0;
            for (int a = 0; a < 3; a++) {
                Ft[a] = Fn[a] = along * gc[a];
            }
            o->pt = ft.p;
        }
        for (int a = 0; a < 3; a++) {
            o->F[a] += Ft[a];
            o->G[a] += Fn[a];
        }
        if (rot) {
            /* the force acts at the contact point, a = |r_ij| / 2 from both centres: the torque
             * on i, (a n) x (-F_t), equals that on j, (-a n) x F_t, = -a n x F_t; the pair's
             * orbital torque r_ij x F_t = 2 a n x F_t cancels them */
            const double arm = 0.5 * dist;
            cross3(n, Ft, o->T);
            cross3(n, Fn, o->TG);
            for (int a = 0; a < 3; a++) {
                o->T[a] *= -arm;
                o->TG[a] *= -arm;
            }
        }
    }
    if (rl != RL_none) {
        /* rolling resistance: against the relative spin about axes in the tangent plane,
         * dw_perp = (w_i - w_j) - ((w_i - w_j).n) n (the rolling velocity is R_eff dw_perp x n;
         * the spin about n, twisting, is left alone): the scalar law at |dw_perp|, the torque
         * +m along dw_perp on j, -m on i */
        const double dw[3] = {c->wx[i] - c->wx[j], c->wy[i] - c->wy[j], c->wz[i] - c->wz[j]};
        const double dn = dot3(dw, n);
        const double dp[3] = {dw[0] - dn * n[0], dw[1] - dn * n[1], dw[2] - dn * n[2]};
        const double m = sqrt(dot3(dp, dp));
        const gr_rolling_in rin = {
            .dw = m, .f_n = fn.f, .acts = acts, .r_eff = 0.25 * c->d, .i_2dt = c->i_2dt};
        const gr_rolling_torque rt = rolling_law(rl, &c->cc, rin);
        const double along = m > 0.0 ? rt.m / m : 0.0;
        for (int a = 0; a < 3; a++) {
            o->R[a] = along * dp[a];
        }
        o->pr = rt.p;
    }
    return 1;
}

/* A history law's contact (i, j) that ended: the law forgets the vector and returns the energy it
 * held plus the work its last force did over the step (J); rare, once per contact. */
static double forget_3d(const ctx3 *c, const int tl, const int i, const int j, const int rot,
                        double *h)
{
    const double dx = wrap_delta(c->x[j] - c->x[i], c->P[0]),
                 dy = wrap_delta(c->y[j] - c->y[i], c->P[1]),
                 dz = wrap_delta(c->z[j] - c->z[i], c->P[2]);
    const double dist = sqrt(dx * dx + dy * dy + dz * dz);
    const double n[3] = {dx / dist, dy / dist, dz / dist};
    const double g[3] = {c->vx[j] - c->vx[i], c->vy[j] - c->vy[i], c->vz[j] - c->vz[i]};
    const double g_n = dot3(g, n);
    double gc[3] = {g[0] - g_n * n[0], g[1] - g_n * n[1], g[2] - g_n * n[2]};
    if (rot) {
        const double W[3] = {c->wx[i] + c->wx[j], c->wy[i] + c->wy[j], c->wz[i] + c->wz[j]};
        double nw[3];
        cross3(n, W, nw);
        for (int a = 0; a < 3; a++) {
            gc[a] += 0.5 * dist * nw[a];
        }
    }
    gr_to_plane(h, n);
    const gr_tangential_in3 in = {
        .g = {gc[0], gc[1], gc[2]}, .xi = c->d - dist, .g_n = g_n, .acts = 0, .hist = h};
    return tangential3_law(tl, &c->cc, in).lost;
}

/* Partial results of one block of rows, in s->blk (GR_BLK_FIELDS per block): the ledger sums,
 * the deepest overlap and its pair (fields 6 and 7: the 2D step's noise sums, which 3D does not
 * use), a history law's energy and losses. */
enum { B_EL, B_PN, B_PT, B_PF, B_WORST, B_FRESH, B_WI, B_WJ, B_ELT, B_LOST };

static inline __attribute__((always_inline)) ctx3 ctx3_of(const gr_sim *s)
{
    return (ctx3){.x = s->x,
                  .y = s->y,
                  .z = s->z,
                  .vx = s->vx,
                  .vy = s->vy,
                  .vz = s->vz,
                  .wx = s->wx,
                  .wy = s->wy,
                  .wz = s->omega,
                  .P = {s->period[0], s->period[1], s->period[2]},
                  GR_PAIR_CONSTS_OF(s)};
}

/* What a pair adds to j: the torque t + R and its non-conservative part TG + R (rotation; on i
 * t - R and TG - R). The same expressions in the row loop and for the cross pairs. */
static inline __attribute__((always_inline)) void torques_on_j(const pair3 *o, const int tl,
                                                               const int rl, double tj[3],
                                                               double uj[3])
{
    for (int a = 0; a < 3; a++) {
        const double t = tl != TL_none ? o->T[a] : 0.0, R = rl != RL_none ? o->R[a] : 0.0;
        tj[a] = t + R;
        uj[a] = history_of(tl) ? o->TG[a] + R : 0.0;
    }
}

/* The screen of the sublist's entries [k0, k1) (k in list order; the sublist on, no history
 * law): each pair's squared distance by geometry()'s own expression, so the same pairs touch; an
 * entry apart clears its contact flag (as the row loop does), a touching one is appended to
 * s->sl_hits from position k0 (each block its own range, so threads do not share). Returns the
 * number appended. Branch-free: on a bed most entries are apart and the row loop's branch on
 * each, with the rows' own overhead, was most of the kernel. */
static inline __attribute__((always_inline)) int screen_3d(const ctx3 *c, gr_sim *restrict s,
                                                           const int k0, const int k1)
{
    const int *restrict entry = s->sl_p, *restrict row_of = s->sl_i, *restrict list = s->nl_j;
    const double *restrict x = c->x, *restrict y = c->y, *restrict z = c->z;
    const double P0 = c->P[0], P1 = c->P[1], P2 = c->P[2], d2 = c->d2;
    const double h0 = 0.5 * P0, h1 = 0.5 * P1, h2 = 0.5 * P2;
    uint8_t *restrict touching = s->nl_contact;
    uint8_t *restrict flag = s->sl_flag + k0; /* the build's scratch, free until the next build */
    int *restrict hits = s->sl_hits + k0;
    /* the distances in vector lanes: wrap_delta's arithmetic as selects (d - P, d + P or d +
     * 0.0, which squares to the same), so the same bits; INFINITY along a wall axis adds 0.0 */
#pragma omp simd
    for (int k = k0; k < k1; k++) {
        const int p = entry[k], i = row_of[k], j = list[p];
        double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
        dx += dx > h0 ? -P0 : (dx < -h0 ? P0 : 0.0);
        dy += dy > h1 ? -P1 : (dy < -h1 ? P1 : 0.0);
        dz += dz > h2 ? -P2 : (dz < -h2 ? P2 : 0.0);
        flag[k - k0] = !(dx * dx + dy * dy + dz * dz >= d2); /* as geometry(), NaN included */
    }
    int m = 0;
    for (int k = k0; k < k1; k++) {
        const uint8_t t = flag[k - k0];
        touching[entry[k]] &= t;
        hits[m] = k;
        m += t;
    }
    return m;
}

/* GCC (12) reports o.hs of rows_3d as used uninitialised in the instance without a history law,
 * where the write-back that reads it is dead code (hist = 0); the warning is false. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
/* The rows [r0, r1) of the half list, scattering to j in [lo, hi) (all = 1: every j, one thread)
 * and to each row's i the sum of its row. Sums of the block in list order, into part. */
static inline __attribute__((always_inline)) void rows_3d(gr_sim *restrict s, const int r0,
                                                          const int r1, const int lo, const int hi,
                                                          const int all, const int screened,
                                                          const int nl, const int tl,
                                                          const int clamp, const int rot,
                                                          const int rl, double *restrict part)
{
    const int hist = history_of(tl);
    const ctx3 c = ctx3_of(s);
    double *restrict f[3] = {s->fx, s->fy, s->fz}, *restrict g[3] = {s->gx, s->gy, s->gz};
    double *restrict tq[3] = {s->tqx, s->tqy, s->tq}, *restrict tg[3] = {s->tgx, s->tgy, s->tg};
    const int *restrict start = s->nl_start, *restrict list = s->nl_j;
    /* the contact sublist (core/sublist.c) when on: entries p of the list, the same touching
     * pairs in the same order */
    const int sub = s->sl_on;
    const int *restrict rows = sub ? s->sl_start : start, *restrict entry = s->sl_p;
    uint8_t *restrict touching = s->nl_contact;
    double *restrict hs = s->nl_hist;
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, el_t = 0.0, lost = 0.0, worst = 0.0;
    int64_t fresh = 0;
    int wi = -1, wj = -1;
    static const double none[3] = {0.0, 0.0, 0.0};
    /* screened (a constant of the call; kernels.c, screens_2d): first the block's touching
     * entries, branch-free, then the rows that have one, each over its touching entries alone (the
     * same pairs in the same order: the rest add nothing) */
    const int *restrict hits = screened ? s->sl_hits + rows[r0] : NULL;
    int nhits = 0;
    if (screened) {
        nhits = screen_3d(&c, s, rows[r0], rows[r1]);
    }
    for (int i = r0, h = 0;;) {
        int ka, kb; /* the row's entries: k in [ka, kb), or hits[ka..kb) when screened */
        if (screened) {
            if (h >= nhits) {
                break;
            }
            i = s->sl_i[hits[h]];
            for (ka = h; h < nhits && s->sl_i[hits[h]] == i; h++) {
            }
            kb = h;
        } else {
            if (i >= r1) {
                break;
            }
            ka = rows[i];
            kb = rows[i + 1];
        }
        double fi[3] = {0.0, 0.0, 0.0}, gi[3] = {0.0, 0.0, 0.0}, ti[3] = {0.0, 0.0, 0.0},
               ui[3] = {0.0, 0.0, 0.0};
        int hit = 0; /* a pair of the row touches */
        for (int kk = ka; kk < kb; kk++) {
            const int k = screened ? hits[kk] : kk;
            const int p = sub ? entry[k] : k, j = list[p];
            double *hp = hist ? hs + 3 * (int64_t)p : NULL;
            pair3 o;
            if (!pair_3d(&c, i, j, nl, tl, clamp, rot, rl, hist ? hp : none, &o)) {
                touching[p] = 0;
                if (hist && (hp[0] != 0.0 || hp[1] != 0.0 || hp[2] != 0.0)) {
                    lost += forget_3d(&c, tl, i, j, rot, hp); /* the contact ended */
                }
                continue;
            }
            if (hist) { /* this thread's row: written once, after every read of it */
                hp[0] = o.hs[0];
                hp[1] = o.hs[1];
                hp[2] = o.hs[2];
                el_t += o.et;
                lost += o.lost;
            }
            fresh += !touching[p];
            touching[p] = 1;
            hit = 1;
            elastic += o.el;
            pn -= o.pn;
            if (o.ov > worst) {
                worst = o.ov;
                wi = i;
                wj = j;
            }
            if (tl != TL_none && book_of(tl) == GR_BOOK_TANGENTIAL) {
                pt += o.pt;
            } else if (tl != TL_none && book_of(tl) == GR_BOOK_FRICTION) {
                pf += o.pt;
            }
            if (rl != RL_none) {
                pf += o.pr;
            }
            const int mine = all || (j >= lo && j < hi);
            for (int a = 0; a < 3; a++) {
                fi[a] -= o.F[a];
                gi[a] -= o.G[a];
                if (mine) {
                    f[a][j] += o.F[a];
                    g[a][j] += o.G[a];
                }
            }
            if (rot) {
                double tj[3], uj[3];
                torques_on_j(&o, tl, rl, tj, uj);
                for (int a = 0; a < 3; a++) {
                    const double t = tl != TL_none ? o.T[a] : 0.0, R = rl != RL_none ? o.R[a] : 0.0;
                    ti[a] += t - R;
                    if (mine) {
                        tq[a][j] += tj[a];
                    }
                    if (hist) {
                        ui[a] += o.TG[a] - R;
                        if (mine) {
                            tg[a][j] += uj[a];
                        }
                    }
                }
            }
        }
        /* a row without a touching pair (on a bed, most rows) would add +0.0, which changes no
         * force: a force is never -0.0 (it starts at +0.0, and a sum that cancels exactly is +0.0) */
        for (int a = 0; hit && a < 3; a++) {
            f[a][i] += fi[a];
            g[a][i] += gi[a];
            if (rot) {
                tq[a][i] += ti[a];
            }
            if (rot && hist) {
                tg[a][i] += ui[a];
            }
        }
        i += !screened;
    }
    part[B_EL] = elastic;
    part[B_PN] = pn;
    part[B_PT] = pt;
    part[B_PF] = pf;
    part[B_WORST] = worst;
    part[B_FRESH] = (double)fresh;
    part[B_WI] = wi;
    part[B_WJ] = wj;
    part[B_ELT] = el_t;
    part[B_LOST] = lost;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/* Zero the forces (and torques, as the laws need them) of particles [lo, hi). */
static void zero_3d(gr_sim *s, const int lo, const int hi, const int rot, const int hist)
{
    double *f[] = {s->fx, s->fy, s->fz, s->gx, s->gy, s->gz};
    double *t[] = {s->tqx, s->tqy, s->tq, s->tgx, s->tgy, s->tg};
    const size_t bytes = sizeof(double) * (size_t)(hi - lo);
    for (int a = 0; a < 6; a++) {
        memset(f[a] + lo, 0, bytes);
        if (rot && (a < 3 || hist)) {
            memset(t[a] + lo, 0, bytes);
        }
    }
}

/* One thread: the blocks of rows in order, scattering to every particle. */
static inline __attribute__((always_inline)) void serial_3d(gr_sim *restrict s, const int nl,
                                                            const int tl, const int clamp,
                                                            const int rot, const int rl)
{
    const int n = s->n;
    zero_3d(s, 0, n, rot, history_of(tl));
    for (int b = 0; b < s->nblk; b++) {
        const int r1 = (b + 1) * GR_BLOCK < n ? (b + 1) * GR_BLOCK : n;
        double *part = s->blk + (size_t)b * GR_BLK_FIELDS;
        if (s->sl_on && s->sl_screen && !history_of(tl)) { /* kernels.c, screens_2d */
            rows_3d(s, b * GR_BLOCK, r1, 0, n, 1, 1, nl, tl, clamp, rot, rl, part);
        } else {
            rows_3d(s, b * GR_BLOCK, r1, 0, n, 1, 0, nl, tl, clamp, rot, rl, part);
        }
    }
}

/* Add the cross pairs q in [q0, q1) acting on each particle j = in_list[l], l in [l0, l1), in
 * ascending q (list order): forces and, with rotation, torques (and their non-conservative
 * parts with a history law). */
static inline __attribute__((always_inline)) void add_incoming_3d(gr_sim *restrict s, const int l0,
                                                                  const int l1, const int q0,
                                                                  const int q1, const int rot,
                                                                  const int hist)
{
    if (q0 >= q1) { /* none: the particles need not be visited (the last thread's later pairs) */
        return;
    }
    const int *restrict in = s->in_start, *restrict ink = s->in_k, *restrict list = s->in_list;
    const double *restrict pf = s->pair_f, *restrict ptq = s->pair_tq, *restrict ptg = s->pair_tg;
    double *restrict f[6] = {s->fx, s->fy, s->fz, s->gx, s->gy, s->gz};
    double *restrict tq[3] = {s->tqx, s->tqy, s->tq}, *restrict tg[3] = {s->tgx, s->tgy, s->tg};
    for (int l = l0; l < l1; l++) {
        const int j = list[l];
        double a[6], t[3] = {0.0, 0.0, 0.0}, u[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 6; k++) {
            a[k] = f[k][j];
        }
        for (int k = 0; k < 3; k++) {
            t[k] = rot ? tq[k][j] : 0.0;
            u[k] = rot && hist ? tg[k][j] : 0.0;
        }
        for (int e = in[j]; e < in[j + 1]; e++) {
            const int q = ink[e];
            if (q >= q0 && q < q1) {
                for (int k = 0; k < 6; k++) {
                    a[k] += pf[6 * (size_t)q + k];
                }
                for (int k = 0; k < 3 && rot; k++) {
                    t[k] += ptq[3 * (size_t)q + k];
                    if (hist) {
                        u[k] += ptg[3 * (size_t)q + k];
                    }
                }
            }
        }
        for (int k = 0; k < 6; k++) {
            f[k][j] = a[k];
        }
        for (int k = 0; k < 3 && rot; k++) {
            tq[k][j] = t[k];
            if (hist) {
                tg[k][j] = u[k];
            }
        }
    }
}

/* As add_incoming_3d without a history law, each cross pair evaluated here instead of read from
 * pair_f: the same pure function of the positions and velocities (pair_3d), so the same bits, and
 * no phase before the rows, no barrier and no cross-core traffic through pair_f. */
static inline __attribute__((always_inline)) void add_direct_3d(
    gr_sim *restrict s, const ctx3 *c, const int l0, const int l1, const int q0, const int q1,
    const int nl, const int tl, const int clamp, const int rot, const int rl)
{
    if (q0 >= q1) {
        return;
    }
    static const double none[3] = {0.0, 0.0, 0.0};
    const int *restrict in = s->in_start, *restrict ink = s->in_k, *restrict list = s->in_list;
    double *restrict f[6] = {s->fx, s->fy, s->fz, s->gx, s->gy, s->gz};
    double *restrict tq[3] = {s->tqx, s->tqy, s->tq};
    for (int l = l0; l < l1; l++) {
        const int j = list[l];
        double a[6], t[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 6; k++) {
            a[k] = f[k][j];
        }
        for (int k = 0; k < 3; k++) {
            t[k] = rot ? tq[k][j] : 0.0;
        }
        for (int e = in[j]; e < in[j + 1]; e++) {
            const int q = ink[e];
            pair3 o;
            if (q < q0 || q >= q1 ||
                !pair_3d(c, s->cross_i[q], j, nl, tl, clamp, rot, rl, none, &o)) {
                continue; /* apart: +0.0 would change no sum (threaded_3d) */
            }
            for (int k = 0; k < 3; k++) {
                a[k] += o.F[k];
                a[3 + k] += o.G[k];
            }
            if (rot) {
                double tj[3], uj[3];
                torques_on_j(&o, tl, rl, tj, uj);
                for (int k = 0; k < 3; k++) {
                    t[k] += tj[k];
                }
            }
        }
        for (int k = 0; k < 6; k++) {
            f[k][j] = a[k];
        }
        for (int k = 0; k < 3 && rot; k++) {
            tq[k][j] = t[k];
        }
    }
}

/* Thread t's particles, as owner_2d (kernels.c): the cross pairs from earlier rows, the rows, the
 * cross pairs from later rows; evaluated here (direct, no history law) or read from pair_f. */
static inline __attribute__((always_inline)) void owner_3d(gr_sim *restrict s, const ctx3 *c,
                                                           const int T, const int t,
                                                           const int direct, const int nl,
                                                           const int tl, const int clamp,
                                                           const int rot, const int rl)
{
    const int hist = history_of(tl);
    const int lo = s->par_row[t], hi = s->par_row[t + 1];
    const int l0 = s->in_list_start[t], l1 = s->in_list_start[t + 1];
    zero_3d(s, lo, hi, rot, hist);
    if (direct) {
        add_direct_3d(s, c, l0, l1, 0, s->cross_start[t], nl, tl, clamp, rot, rl);
    } else {
        add_incoming_3d(s, l0, l1, 0, s->cross_start[t], rot, hist);
    }
    for (int r0 = lo; r0 < hi; r0 += GR_BLOCK) {
        const int r1 = r0 + GR_BLOCK < hi ? r0 + GR_BLOCK : hi;
        double *part = s->blk + (size_t)(r0 / GR_BLOCK) * GR_BLK_FIELDS;
        if (s->sl_on && s->sl_screen && !hist) {
            rows_3d(s, r0, r1, lo, hi, 0, 1, nl, tl, clamp, rot, rl, part);
        } else {
            rows_3d(s, r0, r1, lo, hi, 0, 0, nl, tl, clamp, rot, rl, part);
        }
    }
    if (direct) {
        add_direct_3d(s, c, l0, l1, s->cross_start[t + 1], s->cross_start[T], nl, tl, clamp, rot,
                      rl);
    } else {
        add_incoming_3d(s, l0, l1, s->cross_start[t + 1], s->cross_start[T], rot, hist);
    }
}

/* The part of thread tid of nth (inside a parallel region) of the T-thread evaluation, as in 2D
 * (kernels.c, serial_2d): each thread sets its particles' forces to the cross pairs from earlier
 * rows, runs its rows adding only to its own particles, then adds the cross pairs from later rows:
 * every force, torque and history vector is the same sequence of operations as with one thread.
 * Without a history law it evaluates those cross pairs itself (add_direct_3d). With one, (1) the
 * cross pairs, shared evenly by the threads, go into pair_f first (0 for a pair apart: adding +0.0
 * changes no sum that starts from +0.0), (2) after a barrier as above through add_incoming_3d. */
static inline __attribute__((always_inline)) void threaded_3d(gr_sim *restrict s, const int T,
                                                              const int tid, const int nth,
                                                              const int nl, const int tl,
                                                              const int clamp, const int rot,
                                                              const int rl)
{
    const ctx3 c = ctx3_of(s);
    if (!history_of(
            tl)) { /* each thread evaluates the cross pairs it receives itself: no barrier */
        for (int t = tid; t < T; t += nth) {
            owner_3d(s, &c, T, t, 1, nl, tl, clamp, rot, rl);
        }
        return;
    }
    const int q0 = gr_cross_share(s, T, tid, nth, 0), q1 = gr_cross_share(s, T, tid, nth, 1);
    for (int q = q0; q < q1; q++) {
        /* a history law reads the vector of the cross pair's row: its owner writes the new
         * value in rows_3d after the barrier, from the same old value */
        const int p = s->cross_p[q];
        double *fq = s->pair_f + 6 * (size_t)q;
        double tj[3] = {0.0, 0.0, 0.0}, uj[3] = {0.0, 0.0, 0.0};
        pair3 o;
        if (pair_3d(&c, s->cross_i[q], s->nl_j[p], nl, tl, clamp, rot, rl,
                    s->nl_hist + 3 * (int64_t)p, &o)) {
            for (int a = 0; a < 3; a++) {
                fq[a] = o.F[a];
                fq[3 + a] = o.G[a];
            }
            if (rot) {
                torques_on_j(&o, tl, rl, tj, uj);
            }
        } else {
            for (int a = 0; a < 6; a++) {
                fq[a] = 0.0;
            }
        }
        for (int a = 0; a < 3 && rot; a++) {
            s->pair_tq[3 * (size_t)q + a] = tj[a];
            s->pair_tg[3 * (size_t)q + a] = uj[a];
        }
    }
#pragma omp barrier
    for (int t = tid; t < T; t += nth) {
        owner_3d(s, &c, T, t, 0, nl, tl, clamp, rot, rl);
    }
}

/* The block sums combined in block order; the deepest pair is the first of the largest overlap
 * in list order, as one pass finds it. */
static void report_3d(const gr_sim *s, gr_force_report *r)
{
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, el_t = 0.0, lost = 0.0, worst = 0.0;
    int64_t fresh = 0;
    int wi = -1, wj = -1;
    for (int b = 0; b < s->nblk; b++) {
        const double *q = s->blk + (size_t)b * GR_BLK_FIELDS;
        elastic += q[B_EL];
        pn += q[B_PN];
        pt += q[B_PT];
        pf += q[B_PF];
        el_t += q[B_ELT];
        lost += q[B_LOST];
        fresh += (int64_t)q[B_FRESH];
        if (q[B_WORST] > worst) {
            worst = q[B_WORST];
            wi = (int)q[B_WI];
            wj = (int)q[B_WJ];
        }
    }
    *r = (gr_force_report){.elastic = s->cc.e_scale * elastic + el_t,
                           .power_normal = pn,
                           .power_tangential = pt,
                           .power_friction = pf,
                           .lost = lost,
                           .new_contacts = fresh,
                           .max_overlap = worst / s->d,
                           .worst_i = wi,
                           .worst_j = wj};
}

/* The pair loop on the scene's threads (gr_kernel_team), bit-identical for every thread count.
 * The laws are arguments that the instances below fix or read from the simulation; the
 * parallel region is written here, inside each instance, so that the constants reach the body
 * OpenMP outlines. */
static inline __attribute__((always_inline)) void run_3d(gr_sim *s, gr_force_report *r,
                                                         const int nl, const int tl,
                                                         const int clamp, const int rot,
                                                         const int rl)
{
    const int T = gr_kernel_team(s);
    if (T == 1) {
        serial_3d(s, nl, tl, clamp, rot, rl);
    } else {
        _Pragma("omp parallel num_threads(T)")
            threaded_3d(s, T, GR_THREAD_ID, GR_THREAD_COUNT, nl, tl, clamp, rot, rl);
    }
    report_3d(s, r);
}

gr_tangential_force3 gr_kernel_tangential3(const int tl, const gr_contact_coeffs *c,
                                           const gr_tangential_in3 in, int *book)
{
    *book = book_of(tl);
    return tangential3_law(tl, c, in);
}

/* The instances: the normal law alone (the law read from the simulation, tangential, rotation
 * and rolling off as constants, so the loop is the normal-only one it was), and every law read
 * from the simulation. */
void gr_kernel_run_3d(gr_sim *s, gr_force_report *r)
{
    run_3d(s, r, s->kernel.nl, TL_none, s->kernel.clamp, 0, RL_none);
}

/* The issue-35 scene's laws (spring-dashpot, tangential dashpot, unclamped, no rotation) as
 * constants: about 1.17x the instance reading them at run time on its 32000-sphere scene
 * (docs/performance.md, "Three dimensions"); the same bits. */
void gr_kernel_run_3d_dashpots(gr_sim *s, gr_force_report *r)
{
    run_3d(s, r, NL_spring_dashpot, TL_tangential_dashpot, 0, 0, RL_none);
}

void gr_kernel_run_3d_full(gr_sim *s, gr_force_report *r)
{
    const gr_kernel k = s->kernel;
    run_3d(s, r, k.nl, k.tl, k.clamp, k.rot, k.rl);
}
