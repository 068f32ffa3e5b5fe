/* Contact-force kernels. One pair loop, written once as an always-inline function, so the
 * compiler inlines the models' laws (models/NAME.h, interface in models/law.h). It is instantiated
 * with the laws as constants for the hot combinations (GR_HOT_KERNELS below), where every branch on
 * a law that is off disappears, and once per dimension with the laws read at run time (the generic
 * instances) for every other legal combination of models/list.h. The kernel is chosen once per run
 * (gr_kernel_choose); there is no per-pair indirect call. Adding a model needs no edit here.
 *
 * For a pair i < j at overlap xi = d - |r_ij| > 0, n = r_ij / |r_ij| (from i to j),
 * g = v_j - v_i, g_n = g.n (< 0 approaching), t = (n_y, -n_x) (n rotated by -90 degrees, 2.8),
 * g_t = g.t, the normal law gives f_n and its non-conservative part f_d, the tangential law f_t
 * and its dissipation; the force on j is f_n n + f_t t, on i its opposite (Newton's third law).
 * Rotation (instances with rot = 1, only with a tangential law): g_t is the contact point's
 * g.t + a (w_i + w_j) (models/law.h gives the sign), and f_t exerts the torque a f_t on i and on j
 * alike, a = |r_ij| / 2 (equal radii; the contact point is midway, at r_i + a n = r_j - a n:
 * (-a n) x (f_t t) = a f_t for j, (a n) x (-f_t t) = a f_t for i, since n x t = -1). The pair's
 * orbital torque (r_j - r_i) x (f_t t) = -2 a f_t cancels them: angular momentum is conserved.
 * Rolling laws (rotation instances only, RL_NAME; models/rolling_friction.h): a torque pair -m on
 * i, +m on j from w_i - w_j and f_n, no force; its power is booked with friction.
 * Ledger: the normal law's non-conservative part does work f_d g_n on the relative motion, so
 * it dissipates -f_d g_n (for the linear law gamma_n g_n^2 unclamped; the spring energy that
 * vanishes while the clamp holds f_n at zero is counted here too); a tangential law books its
 * own dissipation into its ledger column (GR_BOOK_NAME).
 *
 * Threads (2D): see KERNEL_2D below; every force is the same sequence of additions for any thread
 * count, and the ledger sums are formed per block of rows (docs/performance.md, "Threads"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"

/* In the generic instances the law ids are not constants, and GCC cannot see that pair_2d sets
 * every field of pair_out that the same ids later read (the conditions match), so it warns that
 * they may be used uninitialised. Zeroing the struct instead costs the hot instances 1.5 % of a 2D
 * step (measured, docs/performance.md "Kernel instances"), so the false warning is silenced here. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "core/kernel_laws.h" /* models/list.h, the normal laws' ids and normal_law */

/* One pair of the 2D list: the force on j (F, on i -F), its non-conservative part G, and the
 * ledger terms. Returns 0 (nothing set) when the pair does not overlap. */
typedef struct pair_out {
    double Fx, Fy, Gx, Gy, el, pn, pt, ov; /* pt: the tangential law's dissipation (its column) */
    double tq;                             /* rotation: the torque r f_t on i and on j */
    double
        tg; /* rotation with a history law: tq's non-conservative part, a (f_t - f_c) (tq without the spring) */
    double hs, et,
        lost;      /* history law: the pair's new slot, its stored energy (J), energy dropped (J) */
    double rq, pr; /* rolling law: its torque on j (-rq on i) and its power (booked as friction) */
} pair_out;

/* What every pair needs, loaded once per loop. */
typedef struct pair_ctx {
    const double *restrict x, *restrict y, *restrict vx, *restrict vy;
    const double *restrict w; /* omega (rotation only) */
    double L;
    GR_PAIR_CONSTS; /* d, d^2, m_t / dt, I / (2 dt), the laws' coefficients (kernel_laws.h) */
} pair_ctx;

static inline __attribute__((always_inline)) pair_ctx ctx_of(const gr_sim *s)
{
    return (pair_ctx){.x = s->x,
                      .y = s->y,
                      .vx = s->vx,
                      .vy = s->vy,
                      .w = s->omega,
                      .L = s->L,
                      GR_PAIR_CONSTS_OF(s)};
}

/* h: the pair's history slot (history laws; 0 otherwise), passed by value: the law updates a copy,
 * returned in o->hs, and the row loop writes it back once per pair. */
static inline __attribute__((always_inline)) int pair_2d(const pair_ctx c, const int i, const int j,
                                                         const int nl, const int tang,
                                                         const int clamp, const int rot,
                                                         const int roll, const double h,
                                                         pair_out *restrict o)
{
    const double L = c.L, d = c.d;
    const double dx = wrap_delta(c.x[j] - c.x[i], L), dy = wrap_delta(c.y[j] - c.y[i], L);
    const double r2 = dx * dx + dy * dy;
    if (r2 >= c.d2) {
        return 0;
    }
    const double dist = sqrt(r2);
    const double inv = 1.0 / dist;
    const double nx = dx * inv, ny = dy * inv, ov = d - dist;
    const double gx = c.vx[j] - c.vx[i], gy = c.vy[j] - c.vy[i];
    const double g_n = gx * nx + gy * ny;
    const gr_normal_force fn = normal_law(nl, &c.cc, ov, g_n, clamp);
    const double f_n = fn.f;
    o->el = fn.e;
    o->pn = fn.f_d * g_n;
    o->ov = ov;
    o->pt = 0.0;
    const double f_d = fn.f_d; /* non-conservative part of the normal force */
    double Gx = f_d * nx, Gy = f_d * ny;
    double Fx = f_n * nx, Fy = f_n * ny;
    if (tang != TL_none) {
        const double tx = ny, ty = -nx;
        double g_t = gx * tx + gy * ty;
        /* rotation: the lever arm of both discs is the distance of their centres to the contact
         * point, |r_ij| / 2 (not r): the orbital torque -|r_ij| f_t of the pair then cancels the
         * spin torques exactly (angular momentum is conserved), and the same arm in g_t keeps the
         * power of the pair f_n g_n + f_t g_t (the law's dissipation is the work done) */
        const double arm = 0.5 * dist;
        if (rot) {
            g_t += arm * (c.w[i] + c.w[j]); /* the surface velocities at the contact point */
        }
        double slot = h;
        const gr_tangential_in in = {.g_t = g_t,
                                     .f_n = f_n,
                                     .xi = ov,
                                     .g_n = g_n,
                                     .acts = !clamp || f_n > 0.0,
                                     .m12_dt = c.m12_dt,
                                     .hist = history_of(tang) ? &slot : NULL};
        const gr_tangential_force ft = tangential_law(tang, &c.cc, in);
        const double f_t = ft.f;
        o->pt = ft.p;
        if (rot) {
            o->tq = arm * f_t;
        }
        Fx += f_t * tx;
        Fy += f_t * ty;
        if (history_of(tang)) {
            /* the spring's part -k_t s is conservative (its energy is ft.e), the rest goes into G;
             * the energy the law dropped is booked directly, so the rate that sets the ledger's
             * shares is the power of G's tangential part alone (the dashpot's) */
            if (rot) {
                o->tg =
                    arm * (f_t - ft.fc); /* likewise for the torques (the spin kicks' booking) */
            }
            o->hs = slot;
            o->et = ft.e;
            o->lost = ft.lost;
            o->pt = -(f_t - ft.fc) * g_t;
            Gx += (f_t - ft.fc) * tx;
            Gy += (f_t - ft.fc) * ty;
        } else {
            Gx += f_t * tx;
            Gy += f_t * ty;
        }
    }
    if (roll != RL_none) {
        /* rolling resistance (rotation kernels only): opposite torques, no force */
        const gr_rolling_in rin = {.dw = c.w[i] - c.w[j],
                                   .f_n = f_n,
                                   .acts = !clamp || f_n > 0.0,
                                   .r_eff = 0.25 * d,
                                   .i_2dt = c.i_2dt};
        const gr_rolling_torque rt = rolling_law(roll, &c.cc, rin);
        o->tq = tang != TL_none ? o->tq : 0.0;
        o->rq = rt.m;
        o->pr = rt.p;
    }
    o->Fx = Fx;
    o->Fy = Fy;
    o->Gx = Gx;
    o->Gy = Gy;
    return 1;
}

/* Partial results of one block of rows, in s->blk (GR_BLK_FIELDS per block); B_ELT, B_LOST only
 * for a history law (past the noise sums of the step, fields 6 and 7). */
enum { B_EL, B_PN, B_PT, B_PF, B_WORST, B_FRESH, B_ELT = 8, B_LOST = 9 };

/* A history law's contact (i, j) that ended: the law forgets the slot and returns the energy it
 * held plus the work its last force did over the step (J), which needs g_t (rare: once per contact). */
static double forget(const pair_ctx *c, const int tang, const int i, const int j, const int rot,
                     double *slot)
{
    const double dx = wrap_delta(c->x[j] - c->x[i], c->L), dy = wrap_delta(c->y[j] - c->y[i], c->L);
    const double dist = sqrt(dx * dx + dy * dy);
    const double tx = dy / dist, ty = -dx / dist;
    double g_t = (c->vx[j] - c->vx[i]) * tx + (c->vy[j] - c->vy[i]) * ty;
    if (rot) {
        g_t += 0.5 * dist * (c->w[i] + c->w[j]);
    }
    /* the overlap (now negative) and g_n: a Mindlin spring's k_t of the previous step, when it held
     * the energy that goes, is k_t(xi + g_n dt) */
    const double g_n = ((c->vx[j] - c->vx[i]) * dx + (c->vy[j] - c->vy[i]) * dy) / dist;
    const gr_tangential_in in = {
        .g_t = g_t, .xi = c->d - dist, .g_n = g_n, .acts = 0, .hist = slot};
    return tangential_law(tang, &c->cc, in).lost;
}

/* The screen of the sublist's entries [k0, k1) (kernels_3d.c, screen_3d, in 2D): each pair's
 * squared distance by pair_2d's own expression; an entry apart clears its contact flag, a
 * touching one is appended to s->sl_hits from position k0. Returns the number appended. */
static inline __attribute__((always_inline)) int screen_2d(const pair_ctx c, gr_sim *restrict s,
                                                           const int k0, const int k1)
{
    const int *restrict entry = s->sl_p, *restrict row_of = s->sl_i, *restrict list = s->nl_j;
    uint8_t *restrict touching = s->nl_contact;
    int *restrict hits = s->sl_hits + k0;
    int m = 0;
    for (int k = k0; k < k1; k++) {
        const int p = entry[k], i = row_of[k], j = list[p];
        const double dx = wrap_delta(c.x[j] - c.x[i], c.L), dy = wrap_delta(c.y[j] - c.y[i], c.L);
        const int t = !(dx * dx + dy * dy >= c.d2); /* as pair_2d, NaN included */
        touching[p] &= (uint8_t)t;
        hits[m] = k;
        m += t;
    }
    return m;
}

/* Whether the rows screen the sublist's entries first: it is on, fewer than half of its entries
 * touched at its build (sublist.c), and no history law (whose ended contacts need each entry). A
 * constant of each call of rows_2d and rows_3d, so the loop without the screen is the plain one. */
static inline int screens_2d(const gr_sim *s, const int tang)
{
    return s->sl_on && s->sl_screen && !history_of(tang);
}

/* The rows [r0, r1) of the half list, scattering f[j] += F for j in [lo, hi) (all = 1: every j,
 * one thread) and f[i] -= sum of its row. Sums of the block in list order. */
static inline __attribute__((always_inline)) void rows_2d(gr_sim *restrict s, const int r0,
                                                          const int r1, const int lo, const int hi,
                                                          const int all, const int screened,
                                                          const int nl, const int tang,
                                                          const int clamp, const int rot,
                                                          const int roll, double *restrict part)
{
    double *restrict fx = s->fx, *restrict fy = s->fy, *restrict gx_ = s->gx, *restrict gy_ = s->gy;
    double *restrict tq = s->tq;
    double *restrict tg = s->tg; /* rotation with a history law: tq's non-conservative part */
    const int *restrict start = s->nl_start, *restrict list = s->nl_j;
    /* the contact sublist (core/sublist.c) when on: entries p of the list, the same touching
     * pairs in the same order */
    const int sub = s->sl_on;
    const int *restrict rows = sub ? s->sl_start : start, *restrict entry = s->sl_p;
    uint8_t *restrict touching = s->nl_contact;
    double *restrict hist = s->nl_hist; /* history laws only */
    const pair_ctx c = ctx_of(s);
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, worst = 0.0, el_t = 0.0, lost = 0.0;
    int64_t fresh = 0;
    /* screened (a constant of the call: screens_2d): the block's touching entries first, then
     * the rows that have one over those alone, as rows_3d (kernels_3d.c) */
    const int *restrict hits = screened ? s->sl_hits + rows[r0] : NULL;
    const int nhits = screened ? screen_2d(c, s, rows[r0], rows[r1]) : 0;
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
        double fxi = 0.0, fyi = 0.0, gxi = 0.0, gyi = 0.0, tqi = 0.0, tgi = 0.0;
        int hit = 0; /* a pair of the row touches */
        for (int kk = ka; kk < kb; kk++) {
            const int k = screened ? hits[kk] : kk;
            const int p = sub ? entry[k] : k, j = list[p];
            pair_out o; /* the fields its laws use are set by pair_2d (see the pragma above) */
            if (!pair_2d(c, i, j, nl, tang, clamp, rot, roll, history_of(tang) ? hist[p] : 0.0,
                         &o)) {
                touching[p] = 0;
                if (history_of(tang) && hist[p] != 0.0) {
                    lost += forget(&c, tang, i, j, rot,
                                   &hist[p]); /* the contact ended: its spring goes */
                }
                continue;
            }
            if (history_of(tang)) {
                hist[p] = o.hs; /* this thread's row: written once, after every read of it */
                el_t += o.et;
                lost += o.lost;
            }
            fresh += !touching[p];
            touching[p] = 1;
            hit = 1;
            elastic += o.el;
            pn -= o.pn;
            worst = o.ov > worst ? o.ov : worst;
            if (book_of(tang) == GR_BOOK_TANGENTIAL) {
                pt += o.pt;
            } else if (book_of(tang) == GR_BOOK_FRICTION) {
                pf += o.pt;
            }
            if (roll != RL_none) {
                pf += o.pr;
            }
            fxi -= o.Fx;
            fyi -= o.Fy;
            gxi -= o.Gx;
            gyi -= o.Gy;
            if (rot) {
                tqi += roll != RL_none ? o.tq - o.rq : o.tq;
            }
            if (rot && history_of(tang)) {
                tgi += roll != RL_none ? o.tg - o.rq : o.tg;
            }
            if (all || (j >= lo && j < hi)) {
                fx[j] += o.Fx;
                fy[j] += o.Fy;
                gx_[j] += o.Gx;
                gy_[j] += o.Gy;
                if (rot) {
                    tq[j] += roll != RL_none ? o.tq + o.rq : o.tq;
                }
                if (rot && history_of(tang)) {
                    tg[j] += roll != RL_none ? o.tg + o.rq : o.tg;
                }
            }
        }
        /* a row without a touching pair would add +0.0, which changes no force (rows_3d) */
        if (hit) {
            fx[i] += fxi;
            fy[i] += fyi;
            gx_[i] += gxi;
            gy_[i] += gyi;
            if (rot) {
                tq[i] += tqi;
            }
            if (rot && history_of(tang)) {
                tg[i] += tgi;
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
    if (history_of(tang)) {
        part[B_ELT] = el_t;
        part[B_LOST] = lost;
    }
}

static void zero_forces(gr_sim *s, int lo, int hi)
{
    const size_t m = sizeof(double) * (size_t)(hi - lo);
    memset(s->fx + lo, 0, m);
    memset(s->fy + lo, 0, m);
    memset(s->gx + lo, 0, m);
    memset(s->gy + lo, 0, m);
    if (s->tq) {
        memset(s->tq + lo, 0, m);
    }
    if (s->tg) {
        memset(s->tg + lo, 0, m);
    }
}

/* The split's weight of an incoming cross pair, in listed pairs: a thread evaluates (or reads) each
 * pair from the rows of another thread and adds it to its particle before its own rows, out of
 * the other core's cache, about 8.5 ns a pair on the issue-35 gas against about 1.7 ns per listed
 * pair or particle of a row; 5 balanced the two threads' kernel times there within a block of
 * rows, 3 and 7 did not (docs/performance.md, "Two threads on the 3D gas"). */
#define GR_CROSS_IN_WEIGHT 5

/* Split the rows into T ranges of whole blocks (row[0..T]) with about equal work: the pairs of
 * the list plus the particles of each range, plus extra[t] for thread t (its incoming cross
 * pairs, weighted); the boundaries go to the blocks closest to the goals. */
static void split_rows(const gr_sim *s, const int T, const int64_t *extra, int *row)
{
    const int n = s->n;
    const int *restrict start = s->nl_start;
    int64_t total = (int64_t)start[n] + n, before = 0;
    for (int t = 0; t < T; t++) {
        total += extra[t];
    }
    row[0] = 0;
    int b = 0;
    for (int t = 1; t < T; t++) {
        before += extra[t - 1];
        /* the rows' work up to boundary t: t/T of the whole, less the earlier threads' extra */
        const int64_t goal = total * t / T - before;
        while (b < s->nblk) {
            const int r = (b + 1) * GR_BLOCK < n ? (b + 1) * GR_BLOCK : n;
            const int64_t w = (int64_t)start[r] + r,
                          w0 = (int64_t)start[b * GR_BLOCK] + (int64_t)b * GR_BLOCK;
            if (w >= goal) {
                if (goal - w0 > w - goal) {
                    b++; /* the boundary after block b is closer */
                }
                break;
            }
            b++;
        }
        const int lo =
            b < row[t - 1] / GR_BLOCK + 1 ? row[t - 1] / GR_BLOCK + 1 : b; /* >= 1 block each */
        row[t] = lo * GR_BLOCK < n ? lo * GR_BLOCK : n;
        b = lo;
    }
    row[T] = n;
}

/* The cross pairs of a split (entries whose partner is another thread's), and each thread's
 * incoming ones (in[t], weighted by GR_CROSS_IN_WEIGHT). */
static int64_t count_cross(const gr_sim *s, const int T, const int *row, int64_t *in)
{
    const int *restrict start = s->nl_start, *restrict nl = s->nl_j;
    int64_t nc = 0;
    for (int t = 0; t < T; t++) {
        in[t] = 0;
    }
    for (int t = 0; t < T; t++) {
        for (int p = start[row[t]]; p < start[row[t + 1]]; p++) {
            const int j = nl[p];
            if (j < row[t] || j >= row[t + 1]) {
                nc++;
                int u = 0;
                while (j >= row[u + 1]) {
                    u++;
                }
                in[u] += GR_CROSS_IN_WEIGHT;
            }
        }
    }
    return nc;
}

/* Cross-pair lists for T threads (see sim_internal.h), after every list rebuild. Thread t owns a
 * contiguous range of whole blocks, chosen so that the threads get about equal work (split_rows:
 * clustered states put most pairs in a few blocks; with j > i in the list every cross pair is
 * added by a later thread, so the split is made again with each thread's incoming pairs counted).
 * Any block-aligned split gives the same sums (the order of additions per particle and per block
 * is fixed), so the split only changes the speed. The same lists serve the 3D kernel
 * (kernels_3d.c), whose cross pairs carry 3-vectors (pair_f: 6 doubles, pair_tq and pair_tg: 3
 * each, against 4, 1 and 1 in 2D). Returns 0 when out of memory (then one thread runs). */
static int build_cross(gr_sim *s, int T)
{
    const int n = s->n;
    const size_t fw = s->dim == 3 ? 6 : 4, tw = s->dim == 3 ? 3 : 1; /* doubles per cross pair */
    const int *restrict start = s->nl_start, *restrict nl = s->nl_j;
    int *row = realloc(s->par_row, sizeof(int) * (size_t)(T + 1));
    int *cs = row ? realloc(s->cross_start, sizeof(int) * (size_t)(T + 1)) : NULL;
    int *ls = cs ? realloc(s->in_list_start, sizeof(int) * (size_t)(T + 1)) : NULL;
    if (row) {
        s->par_row = row;
    }
    if (cs) {
        s->cross_start = cs;
    }
    if (ls) {
        s->in_list_start = ls;
    }
    if (!s->in_start) {
        s->in_start = calloc((size_t)n + 1, sizeof(int));
    }
    int64_t *extra = calloc((size_t)T, sizeof(int64_t));
    if (!row || !cs || !ls || !s->in_start || !extra) {
        free(extra);
        return 0;
    }
    split_rows(s, T, extra, row);
    count_cross(s, T, row, extra);
    split_rows(s, T, extra, row);
    const int64_t nc = count_cross(s, T, row, extra);
    free(extra);
    if (nc > s->cross_cap || !s->cross_p) {
        int64_t cap = nc + nc / 2 + 64;
        free(s->cross_p);
        free(s->cross_i);
        free(s->in_k);
        free(s->in_list);
        free(s->pair_f);
        free(s->pair_tq);
        free(s->pair_tg);
        s->pair_tq = s->pair_tg = NULL;
        s->cross_p = malloc(sizeof(int) * (size_t)cap);
        s->cross_i = malloc(sizeof(int) * (size_t)cap);
        s->in_k = malloc(sizeof(int) * (size_t)cap);
        s->in_list = malloc(sizeof(int) * (size_t)cap);
        s->pair_f = malloc(fw * sizeof(double) * (size_t)cap);
        if (s->tq) {
            s->pair_tq = malloc(tw * sizeof(double) * (size_t)cap);
        }
        if (s->tg) {
            s->pair_tg = malloc(tw * sizeof(double) * (size_t)cap);
        }
        s->cross_cap = cap;
        if (!s->cross_p || !s->cross_i || !s->in_k || !s->in_list || !s->pair_f ||
            (s->tq && !s->pair_tq) || (s->tg && !s->pair_tg)) {
            s->cross_cap = 0;
            return 0;
        }
    }
    int *in = s->in_start;
    memset(in, 0, sizeof(int) * ((size_t)n + 1));
    int k = 0;
    for (int t = 0; t < T; t++) {
        cs[t] = k;
        for (int i = row[t]; i < row[t + 1]; i++) {
            for (int p = start[i]; p < start[i + 1]; p++) {
                const int j = nl[p];
                if (j < row[t] || j >= row[t + 1]) {
                    s->cross_p[k] = p;
                    s->cross_i[k++] = i;
                    in[j + 1]++;
                }
            }
        }
    }
    cs[T] = k;
    for (int j = 0; j < n; j++) {
        in[j + 1] += in[j];
    }
    /* fill in ascending k: counting sort keeps the order; in[] is shifted back afterwards */
    for (int q = 0; q < k; q++) {
        s->in_k[in[nl[s->cross_p[q]]]++] = q;
    }
    for (int j = n; j > 0; j--) {
        in[j] = in[j - 1];
    }
    in[0] = 0;
    /* the particles that receive cross pairs (at most one per cross pair), by thread */
    int m = 0;
    for (int t = 0; t < T; t++) {
        ls[t] = m;
        for (int j = row[t]; j < row[t + 1]; j++) {
            if (in[j + 1] > in[j]) {
                s->in_list[m++] = j;
            }
        }
    }
    ls[T] = m;
    s->par_threads = T;
    s->par_rebuilds = s->rebuilds;
    return 1;
}

/* Add the cross pairs q in [q0, q1) of the incoming list of each particle j = in_list[l], l in
 * [l0, l1) (the thread's particles that have any; the others have nothing to add) (spring:
 * rotation with a history law, whose torques have a non-conservative part of their own, tg). */
static inline __attribute__((always_inline)) void add_incoming(gr_sim *restrict s, int l0, int l1,
                                                               int q0, int q1, const int rot,
                                                               const int spring)
{
    if (q0 >= q1) { /* none: the particles need not be visited (the last thread's later pairs) */
        return;
    }
    const int *restrict in = s->in_start, *restrict ink = s->in_k, *restrict list = s->in_list;
    const double *restrict pf = s->pair_f, *restrict ptq = s->pair_tq, *restrict ptg = s->pair_tg;
    for (int l = l0; l < l1; l++) {
        const int j = list[l];
        double ax = s->fx[j], ay = s->fy[j], bx = s->gx[j], by = s->gy[j],
               tj = rot ? s->tq[j] : 0.0;
        double uj = spring ? s->tg[j] : 0.0;
        for (int e = in[j]; e < in[j + 1]; e++) {
            const int q = ink[e];
            if (q >= q0 && q < q1) {
                ax += pf[4 * q];
                ay += pf[4 * q + 1];
                bx += pf[4 * q + 2];
                by += pf[4 * q + 3];
                if (rot) {
                    tj += ptq[q];
                }
                if (spring) {
                    uj += ptg[q];
                }
            }
        }
        s->fx[j] = ax;
        s->fy[j] = ay;
        s->gx[j] = bx;
        s->gy[j] = by;
        if (rot) {
            s->tq[j] = tj;
        }
        if (spring) {
            s->tg[j] = uj;
        }
    }
}

/* All 2D contact forces. One thread: the scatter over the whole list, f[j] += F in list order.
 * T threads: thread t sets the forces of its particles to the cross pairs from rows before its
 * own (in list order; with j > i in the list those rows are the earlier threads'), runs the
 * scatter over its rows (adding only to its own particles), then adds the cross pairs from rows
 * after its own. Without a history law it evaluates those cross pairs itself (add_direct: no
 * barrier); with one, the threads first share the cross pairs evenly and compute them into
 * pair_f, then add them after a barrier (add_incoming). Each force is thus the same sequence of
 * additions as with one thread (a cross pair that does not overlap adds +0.0, which changes no
 * sum that starts from +0.0), so the result is bit-identical for every T. Ledger sums are per
 * block and combined in block order. */
static inline __attribute__((always_inline)) void serial_2d(gr_sim *restrict s, const int nl,
                                                            const int tang, const int clamp,
                                                            const int rot, const int roll)
{
    const int n = s->n;
    zero_forces(s, 0, n);
    for (int b = 0; b < s->nblk; b++) {
        const int r1 = (b + 1) * GR_BLOCK < n ? (b + 1) * GR_BLOCK : n;
        double *part = s->blk + (size_t)b * GR_BLK_FIELDS;
        if (screens_2d(s, tang)) {
            rows_2d(s, b * GR_BLOCK, r1, 0, n, 1, 1, nl, tang, clamp, rot, roll, part);
        } else {
            rows_2d(s, b * GR_BLOCK, r1, 0, n, 1, 0, nl, tang, clamp, rot, roll, part);
        }
    }
}

/* As add_incoming without a history law, each cross pair evaluated here instead of read from
 * pair_f: the same pure function of the positions and velocities (pair_2d), so the same bits, and
 * no first phase, no barrier and no cross-core traffic through pair_f. */
static inline __attribute__((always_inline)) void add_direct(
    gr_sim *restrict s, const pair_ctx c, const int l0, const int l1, const int q0, const int q1,
    const int nl, const int tang, const int clamp, const int rot, const int roll)
{
    if (q0 >= q1) {
        return;
    }
    const int *restrict in = s->in_start, *restrict ink = s->in_k, *restrict list = s->in_list;
    for (int l = l0; l < l1; l++) {
        const int j = list[l];
        double ax = s->fx[j], ay = s->fy[j], bx = s->gx[j], by = s->gy[j],
               tj = rot ? s->tq[j] : 0.0;
        for (int e = in[j]; e < in[j + 1]; e++) {
            const int q = ink[e];
            pair_out o; /* the fields its laws use are set by pair_2d */
            if (q < q0 || q >= q1 ||
                !pair_2d(c, s->cross_i[q], j, nl, tang, clamp, rot, roll, 0.0, &o)) {
                continue; /* apart: +0.0 would change no sum */
            }
            ax += o.Fx;
            ay += o.Fy;
            bx += o.Gx;
            by += o.Gy;
            if (rot) {
                tj += roll != RL_none ? o.tq + o.rq : o.tq;
            }
        }
        s->fx[j] = ax;
        s->fy[j] = ay;
        s->gx[j] = bx;
        s->gy[j] = by;
        if (rot) {
            s->tq[j] = tj;
        }
    }
}

/* Thread t's particles: their forces set to the cross pairs from rows before theirs, their rows
 * (adding only to their own particles), then the cross pairs from rows after theirs; the cross
 * pairs evaluated here (direct) or read from pair_f. */
static inline __attribute__((always_inline)) void owner_2d(gr_sim *restrict s, const pair_ctx c,
                                                           const int T, const int t,
                                                           const int direct, const int nl,
                                                           const int tang, const int clamp,
                                                           const int rot, const int roll)
{
    const int lo = s->par_row[t], hi = s->par_row[t + 1];
    const int l0 = s->in_list_start[t], l1 = s->in_list_start[t + 1];
    const int spring = rot && history_of(tang);
    zero_forces(s, lo, hi);
    if (direct) {
        add_direct(s, c, l0, l1, 0, s->cross_start[t], nl, tang, clamp, rot, roll);
    } else {
        add_incoming(s, l0, l1, 0, s->cross_start[t], rot, spring);
    }
    for (int r0 = lo; r0 < hi; r0 += GR_BLOCK) {
        const int r1 = r0 + GR_BLOCK < hi ? r0 + GR_BLOCK : hi;
        double *part = s->blk + (size_t)(r0 / GR_BLOCK) * GR_BLK_FIELDS;
        if (screens_2d(s, tang)) {
            rows_2d(s, r0, r1, lo, hi, 0, 1, nl, tang, clamp, rot, roll, part);
        } else {
            rows_2d(s, r0, r1, lo, hi, 0, 0, nl, tang, clamp, rot, roll, part);
        }
    }
    if (direct) {
        add_direct(s, c, l0, l1, s->cross_start[t + 1], s->cross_start[T], nl, tang, clamp, rot,
                   roll);
    } else {
        add_incoming(s, l0, l1, s->cross_start[t + 1], s->cross_start[T], rot, spring);
    }
}

/* The part of thread tid of nth (inside a parallel region) of the T-thread evaluation; without a
 * history law each thread evaluates the cross pairs it receives itself (add_direct), with one the
 * two phases above (a cross pair's slot is written by the owner of its row, after every read). */
static inline __attribute__((always_inline)) void threaded_2d(gr_sim *restrict s, const int T,
                                                              const int tid, const int nth,
                                                              const int nl, const int tang,
                                                              const int clamp, const int rot,
                                                              const int roll)
{
    const pair_ctx c = ctx_of(s);
    if (!history_of(tang)) {
        for (int t = tid; t < T; t += nth) {
            owner_2d(s, c, T, t, 1, nl, tang, clamp, rot, roll);
        }
        return;
    }
    const int q0 = gr_cross_share(s, T, tid, nth, 0), q1 = gr_cross_share(s, T, tid, nth, 1);
    for (int q = q0; q < q1; q++) {
        pair_out o; /* the fields its laws use are set by pair_2d (see the pragma above) */
        double *f = s->pair_f + 4 * (size_t)q;
        /* a history law reads the slot of the cross pair's row: its owner writes the new value
         * in rows_2d after the barrier, from the same old value */
        const int p = s->cross_p[q];
        if (pair_2d(c, s->cross_i[q], s->nl_j[p], nl, tang, clamp, rot, roll, s->nl_hist[p], &o)) {
            f[0] = o.Fx;
            f[1] = o.Fy;
            f[2] = o.Gx;
            f[3] = o.Gy;
            if (rot) {
                s->pair_tq[q] = roll != RL_none ? o.tq + o.rq : o.tq;
                s->pair_tg[q] = roll != RL_none ? o.tg + o.rq : o.tg;
            }
        } else {
            f[0] = f[1] = f[2] = f[3] = 0.0;
            if (rot) {
                s->pair_tq[q] = 0.0;
                s->pair_tg[q] = 0.0;
            }
        }
    }
#pragma omp barrier
    for (int t = tid; t < T; t += nth) {
        owner_2d(s, c, T, t, 0, nl, tang, clamp, rot, roll);
    }
}

/* Threads for this evaluation (2D and 3D); builds the cross lists when the list or T changed. */
int gr_kernel_team(gr_sim *s)
{
    int T = gr_team(s);
    if (T > 1 && (s->par_threads != T || s->par_rebuilds != s->rebuilds) && !build_cross(s, T)) {
        T = 1;
    }
    return T;
}

/* Combine the block sums in block order into the report. */
static void report_2d(gr_sim *s, gr_force_report *r, const int hist)
{
    const int n = s->n, nb = s->nblk;
    const double d = s->d, L = s->L;
    const double *blk = s->blk;
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, worst = 0.0;
    int64_t fresh = 0;
    for (int b = 0; b < nb; b++) {
        const double *q = blk + (size_t)b * GR_BLK_FIELDS;
        elastic += q[B_EL];
        pn += q[B_PN];
        pt += q[B_PT];
        pf += q[B_PF];
        worst = q[B_WORST] > worst ? q[B_WORST] : worst;
        fresh += (int64_t)q[B_FRESH];
    }
    int wi = -1, wj = -1;
    if (worst > 0.0) {
        /* find the worst pair only when asked for a diagnosis (rare) */
        const int *start = s->nl_start, *nl = s->nl_j;
        for (int i = 0; i < n && wi < 0 && worst > 0.25 * d; i++) {
            for (int p = start[i]; p < start[i + 1]; p++) {
                int j = nl[p];
                double dx = wrap_delta(s->x[j] - s->x[i], L), dy = wrap_delta(s->y[j] - s->y[i], L);
                if (d - sqrt(dx * dx + dy * dy) >= 0.999 * worst) {
                    wi = i;
                    wj = j;
                    break;
                }
            }
        }
    }
    r->elastic = s->cc.e_scale * elastic;
    r->lost = 0.0;
    if (hist) { /* the tangential springs' energy (J) and what the law dropped, in block order */
        double el_t = 0.0, lost = 0.0;
        for (int b = 0; b < nb; b++) {
            el_t += blk[(size_t)b * GR_BLK_FIELDS + B_ELT];
            lost += blk[(size_t)b * GR_BLK_FIELDS + B_LOST];
        }
        r->elastic += el_t;
        r->lost = lost;
    }
    r->power_normal = pn;
    r->power_tangential = pt;
    r->power_friction = pf;
    r->new_contacts = fresh;
    r->max_overlap = worst / d;
    r->worst_i = wi;
    r->worst_j = wj;
}

enum { RING_LANES = 8 }; /* partial sums of the 1D ring loop */

/* sum of a[0..n) in RING_LANES lanes (element i in lane i % RING_LANES), lanes added in order */
static double ring_sum(const double *restrict a, const int n)
{
    double acc[RING_LANES] = {0};
    const int full = n / RING_LANES * RING_LANES;
    for (int i0 = 0; i0 < full; i0 += RING_LANES) {
        for (int l = 0; l < RING_LANES; l++) {
            acc[l] += a[i0 + l];
        }
    }
    for (int i = full; i < n; i++) {
        acc[i - full] += a[i];
    }
    double t = 0.0;
    for (int l = 0; l < RING_LANES; l++) {
        t += acc[l];
    }
    return t;
}

/* The first index of the largest of a[0..n) if it is > 0, else -1; a >= +0.0 and never NaN, so
 * the bit patterns as integers order as the values do, and the two integer reductions vectorise
 * (a floating-point max would need -ffinite-math-only). */
static int ring_deepest(const double *restrict a, const int n)
{
    int64_t top = 0;
    for (int i = 0; i < n; i++) {
        int64_t b;
        memcpy(&b, a + i, sizeof b);
        top = b > top ? b : top;
    }
    if (top == 0) {
        return -1;
    }
    int first = n;
    for (int i = 0; i < n; i++) {
        int64_t b;
        memcpy(&b, a + i, sizeof b);
        const int k = b == top ? i : n;
        first = k < first ? k : first;
    }
    return first;
}

/* The pairs i in [lo, hi) of the ring loop below: pair i joins (xl[i], vl[i]) to (xr[i], vr[i]) on
 * its right. Its own function with restrict parameters: that is what lets GCC vectorise it. */
static inline __attribute__((always_inline)) void ring_pairs(
    const int lo, const int hi, const double d, const int nl, const gr_contact_coeffs *restrict cc,
    const int clamp, const double *restrict xr, const double *restrict xl,
    const double *restrict vr, const double *restrict vl, double *restrict f, double *restrict fnc,
    double *restrict e, double *restrict p, double *restrict ovc)
{
    for (int i = lo; i < hi; i++) {
        const double gap = xr[i] - xl[i], g_n = vr[i] - vl[i], ov = d - gap;
        const gr_normal_force fn = normal_law(nl, cc, ov, g_n, clamp);
        const double pw = fn.f_d * g_n;
        f[i] = gap < d ? fn.f : 0.0;
        fnc[i] = gap < d ? fn.f_d : 0.0;
        e[i] = gap < d ? fn.e : 0.0;
        p[i] = gap < d ? pw : 0.0;
        ovc[i] = gap < d ? ov : 0.0;
    }
}

/* 1D ring: particle i touches only i+1 (mod n); positions are kept unwrapped and ordered, so the
 * gap of the last pair is x_0 + L - x_{n-1}.
 *
 * Plain loops without a data-dependent branch, so that each vectorises: the first writes the
 * force of pair (i, i+1) on i+1 into f[i] (its dashpot part into fnc[i]) and the pair's elastic
 * energy, dissipation rate and overlap into scratch arrays, all zero for a pair apart; the second
 * turns pair forces into particle forces in place, f_i = P_{i-1} - P_i, from the right so that
 * P_{i-1} is still there; the contact flags, the ledger's sums and the deepest overlap follow. A
 * contact's place on the ring is random, so the one-pass loop with a branch per pair that this
 * replaced spent much of its time in mispredicted branches (docs/performance.md, "The 1D ring").
 * Forces, flags and the deepest overlap are bit-identical to that loop; the elastic energy and the
 * dissipation rate are summed in RING_LANES lanes (the same on every machine) instead of in ring
 * order, so they may differ from it in the last bits. */
static inline __attribute__((always_inline)) void pair_loop_1d(gr_sim *restrict s,
                                                               gr_force_report *restrict r,
                                                               const int nl, const int clamp)
{
    const int n = s->n;
    const double L = s->L, d = s->d;
    const gr_contact_coeffs cc = s->cc;
    const double *restrict x = s->x, *restrict v = s->vx;
    double *restrict f = s->fx, *restrict fnc = s->gx;
    double *restrict e = s->ring_scratch, *restrict p = e + n, *restrict ovc = p + n;
    uint8_t *restrict touching = s->pair_contact;
    if (n < 2) {
        f[0] = fnc[0] = 0.0;
        *r = (gr_force_report){.worst_i = -1, .worst_j = -1};
        return;
    }
    const int m = n - 1; /* pairs (i, i+1) for i < m, then the wrap pair (m, 0) */
    ring_pairs(0, m, d, nl, &cc, clamp, x + 1, x, v + 1, v, f, fnc, e, p, ovc);
    const double xw = x[0] + L, vw = v[0];
    ring_pairs(0, 1, d, nl, &cc, clamp, &xw, x + m, &vw, v + m, f + m, fnc + m, e + m, p + m,
               ovc + m);
    int64_t fresh = 0;
    for (int i = 0; i < n; i++) { /* ov > 0 exactly when gap < d */
        const uint8_t now = ovc[i] > 0.0;
        fresh += now > touching[i];
        touching[i] = now;
    }
    const double wrap = f[m], wrap_d = fnc[m];
    for (int i = m; i > 0; i--) {
        f[i] = f[i - 1] - f[i];
        fnc[i] = fnc[i - 1] - fnc[i];
    }
    f[0] = (0.0 - f[0]) + wrap; /* the wrap pair pushes particle 0 */
    fnc[0] = (0.0 - fnc[0]) + wrap_d;
    const int w = ring_deepest(ovc, n);
    r->elastic = cc.e_scale * ring_sum(e, n);
    r->power_normal = -ring_sum(p, n);
    r->power_tangential = 0.0;
    r->power_friction = 0.0;
    r->lost = 0.0;
    r->new_contacts = fresh;
    r->max_overlap = w >= 0 ? ovc[w] / d : 0.0;
    r->worst_i = w;
    r->worst_j = w >= 0 ? (w + 1) % n : -1;
}

/* The instances. The hot combinations, one line each (dim, normal, tangential, clamp, rotation,
 * rolling), are compiled with their laws as constants: the Random Force Model's laws (the
 * spring-dashpot on the ring; in the plane alone and with the tangential dashpot, Fig. 2.8),
 * clamped and not; the ring for each normal law; and the combinations the contact-model
 * comparison runs (docs/campaigns/contact-models*.ini, unclamped), where the generic instance
 * measured 0.74-0.94x of a specialised one in 2D (light laws lose most; the 1D ring 0.98x;
 * docs/performance.md, "Kernel instances"). Every other legal combination runs through the
 * generic instance of its dimension: the same always-inline pair loop with the law ids read from
 * the simulation, so the laws are still inlined (no per-pair indirect call) and a pair branches
 * on which law is on. This list alone decides what is specialised; selection (gr_kernel_choose)
 * and the names in summary.json follow from the model lists, so a new law of any kind runs
 * (generically) with no edit here, and a measurement that shows it hot adds one line. */
#define GR_HOT_KERNELS(X)                                                                          \
    X(1, spring_dashpot, none, 0, 0, none)                                                         \
    X(1, spring_dashpot, none, 1, 0, none)                                                         \
    X(1, hertz, none, 0, 0, none)                                                                  \
    X(1, hertz, none, 1, 0, none)                                                                  \
    X(2, spring_dashpot, none, 0, 0, none)                                                         \
    X(2, spring_dashpot, none, 1, 0, none)                                                         \
    X(2, spring_dashpot, tangential_dashpot, 0, 0, none)                                           \
    X(2, spring_dashpot, tangential_dashpot, 1, 0, none)                                           \
    X(2, spring_dashpot, tangential_dashpot, 0, 1, none)                                           \
    X(2, spring_dashpot, tangential_dashpot, 0, 1, rolling_friction)                               \
    X(2, spring_dashpot, sliding_friction, 0, 1, none)                                             \
    X(2, spring_dashpot, tangential_spring, 0, 0, none)                                            \
    X(2, spring_dashpot, tangential_spring, 0, 1, none)                                            \
    X(2, hertz, none, 0, 0, none)                                                                  \
    X(2, hertz, tangential_dashpot, 0, 0, none)

/* The parallel region is written in each instance, so that the constants reach the body OpenMP
 * outlines. */
static inline __attribute__((always_inline)) void run_2d(gr_sim *s, gr_force_report *r,
                                                         const int nl, const int tl,
                                                         const int clamp, const int rot,
                                                         const int rl)
{
    const int T = gr_kernel_team(s);
    if (T == 1) {
        serial_2d(s, nl, tl, clamp, rot, rl);
    } else {
        _Pragma("omp parallel num_threads(T)")
            threaded_2d(s, T, GR_THREAD_ID, GR_THREAD_COUNT, nl, tl, clamp, rot, rl);
    }
    report_2d(s, r, history_of(tl));
}

static inline __attribute__((always_inline)) void run_kernel(gr_sim *s, gr_force_report *r,
                                                             const int dim, const int nl,
                                                             const int tl, const int clamp,
                                                             const int rot, const int rl)
{
    if (dim == 1) {
        pair_loop_1d(s, r, nl, clamp);
    } else {
        run_2d(s, r, nl, tl, clamp, rot, rl);
    }
}

#define GR_HOT_FN(DIM, NL, TL, CLAMP, ROT, RL)                                                     \
    static void kernel_##DIM##d_##NL##_##TL##_##CLAMP##ROT##_##RL(gr_sim *s, gr_force_report *r)   \
    {                                                                                              \
        run_kernel(s, r, DIM, NL_##NL, TL_##TL, CLAMP, ROT, RL_##RL);                              \
    }
GR_HOT_KERNELS(GR_HOT_FN)
#undef GR_HOT_FN

/* the generic instances: one per dimension, the laws read at run time */
static void kernel_generic_1d(gr_sim *s, gr_force_report *r)
{
    pair_loop_1d(s, r, s->kernel.nl, s->kernel.clamp);
}

static void kernel_generic_2d(gr_sim *s, gr_force_report *r)
{
    const gr_kernel k = s->kernel;
    run_2d(s, r, k.nl, k.tl, k.clamp, k.rot, k.rl);
}

typedef struct hot_entry {
    void (*run)(gr_sim *s, gr_force_report *r);
    int dim, nl, tl, clamp, rot, rl;
} hot_entry;
#define GR_HOT_ENTRY(DIM, NL, TL, CLAMP, ROT, RL)                                                  \
    {kernel_##DIM##d_##NL##_##TL##_##CLAMP##ROT##_##RL, DIM, NL_##NL, TL_##TL, CLAMP, ROT, RL_##RL},
static const hot_entry hot_kernels[] = {GR_HOT_KERNELS(GR_HOT_ENTRY)};
#undef GR_HOT_ENTRY
enum { N_HOT = sizeof hot_kernels / sizeof hot_kernels[0] };

/* the law ids and names, from the model lists */
#define GR_NAME_OF(A, NAME) #NAME,
static const char *const normal_names[] = {GR_NORMAL_MODELS(GR_NAME_OF, )};
static const char *const tangential_names[] = {"none", GR_TANGENTIAL_MODELS(GR_NAME_OF, )};
static const char *const rolling_names[] = {"none", GR_ROLLING_MODELS(GR_NAME_OF, )};
#undef GR_NAME_OF

static int id_of(const char *const *names, int n, const char *name)
{
    for (int k = 0; k < n; k++) {
        if (strcmp(names[k], name) == 0) {
            return k;
        }
    }
    return -1;
}

int gr_kernel_history(const gr_sim *s) { return history_of(s->kernel.tl); }

void gr_forces(gr_sim *s, gr_force_report *r)
{
    s->kernel.run(s, r); /* one call per force evaluation, not per pair */
    if (s->walls_on) {   /* walls and gravity (walls.c): a pass of its own, outside the pair loop */
        gr_walls_forces(s, r);
    }
}

double gr_kernel_normal(const gr_sim *s, const gr_contact_coeffs *c, double xi, double g_n,
                        double *f_d, double *e)
{
    const gr_normal_force fn = normal_law(s->kernel.nl, c, xi, g_n, s->kernel.clamp);
    *f_d = fn.f_d;
    *e = fn.e;
    return fn.f;
}

int gr_kernel_tangential_id(const gr_model *m)
{
    const int id = m ? id_of(tangential_names, TL_COUNT, m->name) : TL_none;
    return id > 0 ? id : TL_none;
}

int gr_kernel_tangential_history(const int tl) { return history_of(tl); }

gr_tangential_force gr_kernel_tangential(const int tl, const gr_contact_coeffs *c,
                                         const gr_tangential_in in, int *book, int *history)
{
    *book = book_of(tl);
    *history = history_of(tl);
    return tangential_law(tl, c, in);
}

int gr_kernel_instances(void) { return N_HOT + 5; }

int gr_kernel_choose(gr_sim *s, gr_error *err)
{
    const gr_contact_coeffs *c = &s->cc;
    const gr_model *normal = c->normal_model, *tangential = c->tangential_model;
    /* an event rule has no force law: it names the law that stands in (no overlaps arise) */
    const char *nname = normal && normal->force_law ? normal->force_law
                        : normal                    ? normal->name
                                                    : "";
    /* a tangential law whose coefficients make it do nothing (eps_t = 1, mu = 0): skip its work */
    const char *tname =
        tangential && !(tangential->inert && tangential->inert(c)) ? tangential->name : "none";
    /* a rolling law (rotation only) with mu_r = 0: none */
    const gr_model *rolling = c->rolling_model;
    const char *rname =
        s->omega && rolling && !(rolling->inert && rolling->inert(c)) ? rolling->name : "none";
    /* rotation with laws that do nothing (eps_t = 1, mu = 0, mu_r = 0): the spins stay as they are */
    const int rot = s->omega && (strcmp(tname, "none") != 0 || strcmp(rname, "none") != 0);
    gr_kernel k = {.dim = s->dim,
                   .nl = id_of(normal_names, NL_COUNT, nname),
                   .tl = s->dim == 1 ? TL_none : id_of(tangential_names, TL_COUNT, tname),
                   .clamp = (int)c->clamp,
                   .rot = s->dim == 1 ? 0 : rot,
                   .rl = s->dim == 1 ? RL_none : id_of(rolling_names, RL_COUNT, rname)};
    if (k.nl < 0 || k.tl < 0 || k.rl < 0 || (k.rl != RL_none && !k.rot) ||
        (k.dim != 1 && k.dim != 2 && k.dim != 3)) {
        /* unreachable: gr_sim_create checks the models before choosing. The library reports it to
         * its caller instead of printing. */
        return GR_FAIL(err, GR_EINVAL,
                       "internal error: no force kernel for %s/%s/%s in %dD%s%s (please report it)",
                       nname, tname, rname, s->dim, c->clamp ? ", clamped" : "",
                       rot ? ", rotating" : "");
    }
    /* 3D (kernels_3d.c): the normal law alone, or the instance with every law read at run time */
    const int bare = k.tl == TL_none && !k.rot && k.rl == RL_none;
    const int dashpots = k.nl == NL_spring_dashpot && k.tl == TL_tangential_dashpot && !k.clamp &&
                         !k.rot && k.rl == RL_none;
    k.run = k.dim == 1   ? kernel_generic_1d
            : k.dim == 2 ? kernel_generic_2d
            : bare       ? gr_kernel_run_3d
            : dashpots   ? gr_kernel_run_3d_dashpots
                         : gr_kernel_run_3d_full;
    for (int h = 0; h < N_HOT; h++) {
        const hot_entry *e = &hot_kernels[h];
        if (e->dim == k.dim && e->nl == k.nl && e->tl == k.tl && e->clamp == k.clamp &&
            e->rot == k.rot && e->rl == k.rl) {
            k.run = e->run;
        }
    }
    if (s->nsp) { /* species: the kernel of kernels_poly.c, the pair's own coefficients */
        k.run = gr_kernel_run_poly;
    }
    s->kernel = k;
    const char *noise = s->drive == GR_DRIVE_BATH ? "langevin" /* the bath ([driving]) */
                        : s->params.noise_mode == GR_NOISE_NONE ? "no-noise"
                        : s->params.noise_mode == GR_NOISE_COM  ? "noise-com"
                                                                : "noise-symmetrised";
    const char *nb = s->nsp        ? (s->dim == 1   ? "1d-ring-species"
                                      : s->dim == 2 ? "2d-verlet-list-species"
                                                    : "3d-verlet-list-species")
                     : s->dim == 1 ? "1d-ring"
                     : s->dim == 3 ? (s->params.skin > 0.0 ? "3d-verlet-list" : "3d-cell-list")
                                   : (s->params.skin > 0.0 ? "2d-verlet-list" : "2d-cell-list");
    snprintf(s->kernel_name, sizeof s->kernel_name, "%s/%s%s%s%s%s%s%s/%s", nb, normal_names[k.nl],
             k.clamp ? "[clamped]" : "", k.tl != TL_none ? "+" : "",
             k.tl != TL_none ? tangential_names[k.tl] : "", k.rot ? "+rotation" : "",
             k.rl != RL_none ? "+" : "", k.rl != RL_none ? rolling_names[k.rl] : "", noise);
    return GR_OK;
}

int gr_kernel_generic(const gr_sim *s)
{
    return s->kernel.run == kernel_generic_1d || s->kernel.run == kernel_generic_2d ||
           s->kernel.run == gr_kernel_run_3d || s->kernel.run == gr_kernel_run_3d_full;
}

int gr_kernel_force_generic(gr_sim *s)
{
    s->kernel.run = s->kernel.dim == 1   ? kernel_generic_1d
                    : s->kernel.dim == 2 ? kernel_generic_2d
                                         : gr_kernel_run_3d_full;
    return GR_OK;
}

const char *gr_contact_virial(const gr_contact_coeffs *c, double d, const gr_contact_pair *pairs,
                              int n, double w[3])
{
    const gr_model *m = c->normal_model;
    if (!m || !(m->kind & GR_MODEL_NORMAL)) {
        return NULL; /* an event rule exerts no force on a frame (its stand-in only keeps overlaps apart) */
    }
    const int nl = id_of(normal_names, NL_COUNT, m->name);
    if (nl < 0) {
        return NULL;
    }
    const int clamp = (int)c->clamp;
    for (int k = 0; k < n; k++) {
        const gr_contact_pair *q = &pairs[k];
        const double dist = sqrt(q->dx * q->dx + q->dy * q->dy);
        if (dist == 0.0) {
            continue;
        }
        const double nx = q->dx / dist, ny = q->dy / dist;
        const double f_n = normal_law(nl, c, d - dist, q->gx * nx + q->gy * ny, clamp).f;
        w[0] += dist * f_n * nx * nx;
        w[1] += dist * f_n * ny * ny;
        w[2] += dist * f_n * nx * ny;
    }
    return m->name;
}

/* The history slot of the pair (i, j) in the list, listed either way (0 if it is not listed). */
static double list_slot(const gr_sim *s, int i, int j)
{
    for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
        if (s->nl_j[p] == j) {
            return s->nl_hist[p];
        }
    }
    for (int p = s->nl_start[j]; p < s->nl_start[j + 1]; p++) {
        if (s->nl_j[p] == i) {
            return s->nl_hist[p];
        }
    }
    return 0.0;
}

/* Every pair by brute force with the chosen kernel's laws (runtime law ids: test code). */
void gr_forces_bruteforce(const gr_sim *s, double *fx, double *fy, double *elastic)
{
    const gr_kernel *e = &s->kernel;
    const double L = s->L, d = s->d, m12_dt = s->cc.m_t / s->dt;
    *elastic = 0.0;
    for (int i = 0; i < s->n; i++) {
        fx[i] = 0.0;
        if (fy) {
            fy[i] = 0.0;
        }
    }
    for (int i = 0; i < s->n; i++) {
        for (int j = i + 1; j < s->n; j++) {
            double dx = wrap_delta(s->x[j] - s->x[i], L);
            double dy = s->dim == 2 ? wrap_delta(s->y[j] - s->y[i], L) : 0.0;
            double dist = sqrt(dx * dx + dy * dy);
            if (dist >= d) {
                continue;
            }
            double nx = dx / dist, ny = dy / dist, ov = d - dist;
            double gx = s->vx[j] - s->vx[i], gy = s->dim == 2 ? s->vy[j] - s->vy[i] : 0.0;
            double g_n = gx * nx + gy * ny;
            gr_normal_force fn = normal_law(e->nl, &s->cc, ov, g_n, e->clamp);
            *elastic += s->cc.e_scale * fn.e;
            double Fx = fn.f * nx, Fy = fn.f * ny;
            if (e->tl != TL_none) {
                double tx = ny, ty = -nx, g_t = gx * tx + gy * ty;
                if (e->rot) {
                    g_t += 0.5 * d * (s->omega[i] + s->omega[j]);
                }
                double slot =
                    history_of(e->tl) ? list_slot(s, i, j) : 0.0; /* a copy: nothing changes */
                gr_tangential_in in = {.g_t = g_t,
                                       .f_n = fn.f,
                                       .xi = ov,
                                       .g_n = g_n,
                                       .acts = !e->clamp || fn.f > 0.0,
                                       .m12_dt = m12_dt,
                                       .hist = history_of(e->tl) ? &slot : NULL};
                double f_t = tangential_law(e->tl, &s->cc, in).f;
                Fx += f_t * tx;
                Fy += f_t * ty;
            }
            fx[i] -= Fx;
            fx[j] += Fx;
            if (fy) {
                fy[i] -= Fy;
                fy[j] += Fy;
            }
        }
    }
}
