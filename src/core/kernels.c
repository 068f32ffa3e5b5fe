/* Contact-force kernels. One pair loop, written once as an always-inline function and
 * instantiated for each combination of contact laws the scene can ask for (normal only, normal +
 * tangential dashpot, normal + sliding friction, each clamped or not, and the 1D ring), so the
 * compiler removes every branch on a law that is off. The kernel is chosen once per run
 * (gr_kernel_choose); there is no per-pair indirect call.
 *
 * Contact laws for a pair i < j at overlap xi = d - |r_ij| > 0, n = r_ij / |r_ij| (from i to j),
 * g = v_j - v_i, g_n = g.n (< 0 approaching), t = n rotated by 90 degrees (2.8), g_t = g.t:
 *   normal (2.4-2.5):      F_n = k_s xi - gamma_n g_n, clamped to >= 0 if asked
 *   tangential dashpot (2.9): F_t = -gamma_t g_t while the normal force acts
 *   sliding friction (2.7): F_t = -sign(g_t) min(mu |F_n|, m12 |g_t| / dt)  (no chatter)
 * The force on j is F_n n + F_t t, on i its opposite (Newton's third law).
 * Dissipation rates for the ledger: the normal law's non-spring part F_d = F_n - k_s xi does work
 * F_d g_n on the relative motion, so it dissipates -F_d g_n (gamma_n g_n^2 unclamped; the spring
 * energy that vanishes while the clamp holds F_n at zero is counted here too).
 *
 * Threads (2D): see KERNEL_2D below; every force is the same sequence of additions for any thread
 * count, and the ledger sums are formed per block of rows (docs/performance.md, "Threads"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"

#ifdef _OPENMP
#include <omp.h>
#endif

enum { TANG_NONE = 0, TANG_DASHPOT = 1, TANG_FRICTION = 2 };

static inline double wrap_delta(double dx, double L)
{
    if (dx > 0.5 * L) {
        dx -= L;
    } else if (dx < -0.5 * L) {
        dx += L;
    }
    return dx;
}

/* One pair of the 2D list: the force on j (F, on i -F), its non-conservative part G, and the
 * ledger terms. Returns 0 (nothing set) when the pair does not overlap. */
typedef struct pair_out {
    double Fx, Fy, Gx, Gy, el, pn, pt, pf, ov;
} pair_out;

/* What every pair needs, loaded once per loop. */
typedef struct pair_ctx {
    const double *restrict x, *restrict y, *restrict vx, *restrict vy;
    double L, d, d2, k, gn, gt, mu, m12_dt;
} pair_ctx;

static inline __attribute__((always_inline)) pair_ctx ctx_of(const gr_sim *s)
{
    return (pair_ctx){.x = s->x, .y = s->y, .vx = s->vx, .vy = s->vy, .L = s->L, .d = s->d, .d2 = s->d * s->d,
                      .k = s->cc.k_s, .gn = s->cc.gamma_n, .gt = s->cc.gamma_t, .mu = s->cc.mu,
                      .m12_dt = s->cc.m12 / s->dt};
}

static inline __attribute__((always_inline)) int
pair_2d(const pair_ctx c, const int i, const int j, const int tang, const int clamp, pair_out *restrict o)
{
    const double L = c.L, d = c.d;
    const double k = c.k, gn = c.gn, gt = c.gt, mu = c.mu;
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
    double f_n = k * ov - gn * g_n;
    if (clamp) {
        f_n = f_n > 0.0 ? f_n : 0.0;
    }
    o->el = ov * ov;
    o->pn = (f_n - k * ov) * g_n;
    o->ov = ov;
    o->pt = 0.0;
    o->pf = 0.0;
    const double f_d = f_n - k * ov; /* non-conservative part of the normal force */
    double Gx = f_d * nx, Gy = f_d * ny;
    double Fx = f_n * nx, Fy = f_n * ny;
    if (tang != TANG_NONE) {
        const double tx = ny, ty = -nx;
        const double g_t = gx * tx + gy * ty;
        double f_t = 0.0;
        if (tang == TANG_DASHPOT) {
            if (!clamp || f_n > 0.0) {
                f_t = -gt * g_t;
                o->pt = gt * g_t * g_t;
            }
        } else {
            const double cap = c.m12_dt * fabs(g_t), slide = mu * fabs(f_n);
            const double mag = slide < cap ? slide : cap;
            f_t = g_t > 0.0 ? -mag : (g_t < 0.0 ? mag : 0.0);
            o->pf = f_t * g_t;
        }
        Fx += f_t * tx;
        Fy += f_t * ty;
        Gx += f_t * tx;
        Gy += f_t * ty;
    }
    o->Fx = Fx;
    o->Fy = Fy;
    o->Gx = Gx;
    o->Gy = Gy;
    return 1;
}

/* Partial results of one block of rows, in s->blk (GR_BLK_FIELDS per block). */
enum { B_EL, B_PN, B_PT, B_PF, B_WORST, B_FRESH };

/* The rows [r0, r1) of the half list, scattering f[j] += F for j in [lo, hi) (all = 1: every j,
 * one thread) and f[i] -= sum of its row. Sums of the block in list order. */
static inline __attribute__((always_inline)) void
rows_2d(gr_sim *restrict s, const int r0, const int r1, const int lo, const int hi, const int all, const int tang,
        const int clamp, double *restrict part)
{
    double *restrict fx = s->fx, *restrict fy = s->fy, *restrict gx_ = s->gx, *restrict gy_ = s->gy;
    const int *restrict start = s->nl_start, *restrict nl = s->nl_j;
    uint8_t *restrict touching = s->nl_contact;
    const pair_ctx c = ctx_of(s);
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, worst = 0.0;
    int64_t fresh = 0;
    for (int i = r0; i < r1; i++) {
        double fxi = 0.0, fyi = 0.0, gxi = 0.0, gyi = 0.0;
        for (int p = start[i]; p < start[i + 1]; p++) {
            const int j = nl[p];
            pair_out o;
            if (!pair_2d(c, i, j, tang, clamp, &o)) {
                touching[p] = 0;
                continue;
            }
            fresh += !touching[p];
            touching[p] = 1;
            elastic += o.el;
            pn -= o.pn;
            worst = o.ov > worst ? o.ov : worst;
            if (tang == TANG_DASHPOT) {
                pt += o.pt;
            } else if (tang == TANG_FRICTION) {
                pf -= o.pf;
            }
            fxi -= o.Fx;
            fyi -= o.Fy;
            gxi -= o.Gx;
            gyi -= o.Gy;
            if (all || (j >= lo && j < hi)) {
                fx[j] += o.Fx;
                fy[j] += o.Fy;
                gx_[j] += o.Gx;
                gy_[j] += o.Gy;
            }
        }
        fx[i] += fxi;
        fy[i] += fyi;
        gx_[i] += gxi;
        gy_[i] += gyi;
    }
    part[B_EL] = elastic;
    part[B_PN] = pn;
    part[B_PT] = pt;
    part[B_PF] = pf;
    part[B_WORST] = worst;
    part[B_FRESH] = (double)fresh;
}

static void zero_forces(gr_sim *s, int lo, int hi)
{
    const size_t m = sizeof(double) * (size_t)(hi - lo);
    memset(s->fx + lo, 0, m);
    memset(s->fy + lo, 0, m);
    memset(s->gx + lo, 0, m);
    memset(s->gy + lo, 0, m);
}

/* Cross-pair lists for T threads (see sim_internal.h), after every list rebuild. Thread t owns a
 * contiguous range of whole blocks, chosen so that the threads get about equal work (pairs of
 * the list plus particles): clustered states put most pairs in a few blocks. Any block-aligned
 * split gives the same sums (the order of additions per particle and per block is fixed), so
 * the split only changes the speed. Returns 0 when out of memory (then one thread runs). */
static int build_cross(gr_sim *s, int T)
{
    const int n = s->n;
    const int *restrict start = s->nl_start, *restrict nl = s->nl_j;
    int *row = realloc(s->par_row, sizeof(int) * (size_t)(T + 1));
    int *cs = row ? realloc(s->cross_start, sizeof(int) * (size_t)(T + 1)) : NULL;
    if (row) {
        s->par_row = row;
    }
    if (cs) {
        s->cross_start = cs;
    }
    if (!s->in_start) {
        s->in_start = calloc((size_t)n + 1, sizeof(int));
    }
    if (!row || !cs || !s->in_start) {
        return 0;
    }
    /* work of the rows before block b: pairs + particles; split at the blocks closest to t/T */
    const int64_t total = (int64_t)start[n] + n;
    row[0] = 0;
    int b = 0;
    for (int t = 1; t < T; t++) {
        const int64_t goal = total * t / T;
        while (b < s->nblk) {
            const int r = (b + 1) * GR_BLOCK < n ? (b + 1) * GR_BLOCK : n;
            const int64_t w = (int64_t)start[r] + r, w0 = (int64_t)start[b * GR_BLOCK] + (int64_t)b * GR_BLOCK;
            if (w >= goal) {
                if (goal - w0 > w - goal) {
                    b++; /* the boundary after block b is closer */
                }
                break;
            }
            b++;
        }
        const int lo = b < row[t - 1] / GR_BLOCK + 1 ? row[t - 1] / GR_BLOCK + 1 : b; /* >= 1 block each */
        row[t] = lo * GR_BLOCK < n ? lo * GR_BLOCK : n;
        b = lo;
    }
    row[T] = n;
    int64_t nc = 0;
    for (int t = 0; t < T; t++) {
        for (int p = start[row[t]]; p < start[row[t + 1]]; p++) {
            nc += nl[p] < row[t] || nl[p] >= row[t + 1];
        }
    }
    if (nc > s->cross_cap || !s->cross_p) {
        int64_t cap = nc + nc / 2 + 64;
        free(s->cross_p);
        free(s->cross_i);
        free(s->in_k);
        free(s->pair_f);
        s->cross_p = malloc(sizeof(int) * (size_t)cap);
        s->cross_i = malloc(sizeof(int) * (size_t)cap);
        s->in_k = malloc(sizeof(int) * (size_t)cap);
        s->pair_f = malloc(4 * sizeof(double) * (size_t)cap);
        s->cross_cap = cap;
        if (!s->cross_p || !s->cross_i || !s->in_k || !s->pair_f) {
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
    s->par_threads = T;
    s->par_rebuilds = s->rebuilds;
    return 1;
}

/* Add the cross pairs q in [q0, q1) of the incoming list of each particle in [lo, hi). */
static inline void add_incoming(gr_sim *restrict s, int lo, int hi, int q0, int q1)
{
    const int *restrict in = s->in_start, *restrict ink = s->in_k;
    const double *restrict pf = s->pair_f;
    for (int j = lo; j < hi; j++) {
        double ax = s->fx[j], ay = s->fy[j], bx = s->gx[j], by = s->gy[j];
        for (int e = in[j]; e < in[j + 1]; e++) {
            const int q = ink[e];
            if (q >= q0 && q < q1) {
                ax += pf[4 * q];
                ay += pf[4 * q + 1];
                bx += pf[4 * q + 2];
                by += pf[4 * q + 3];
            }
        }
        s->fx[j] = ax;
        s->fy[j] = ay;
        s->gx[j] = bx;
        s->gy[j] = by;
    }
}

/* All 2D contact forces. One thread: the scatter over the whole list, f[j] += F in list order.
 * T threads: (1) every thread computes its cross pairs into pair_f; (2) thread t sets the forces
 * of its particles to the cross pairs from rows before its own (in list order), runs the scatter
 * over its rows (adding only to its own particles), then adds the cross pairs from rows after
 * its own. Each force is thus the same sequence of additions as with one thread (a cross pair
 * that does not overlap adds +0.0, which changes no sum that starts from +0.0), so the result
 * is bit-identical for every T. Ledger sums are per block and combined in block order. */
static inline __attribute__((always_inline)) void
serial_2d(gr_sim *restrict s, const int tang, const int clamp)
{
    const int n = s->n;
    zero_forces(s, 0, n);
    for (int b = 0; b < s->nblk; b++) {
        const int r1 = (b + 1) * GR_BLOCK < n ? (b + 1) * GR_BLOCK : n;
        rows_2d(s, b * GR_BLOCK, r1, 0, n, 1, tang, clamp, s->blk + (size_t)b * GR_BLK_FIELDS);
    }
}

/* The part of thread tid of nth (inside a parallel region) of the T-thread evaluation. */
static inline __attribute__((always_inline)) void
threaded_2d(gr_sim *restrict s, const int T, const int tid, const int nth, const int tang, const int clamp)
{
    const pair_ctx c = ctx_of(s);
    for (int t = tid; t < T; t += nth) {
        for (int q = s->cross_start[t]; q < s->cross_start[t + 1]; q++) {
            pair_out o;
            double *f = s->pair_f + 4 * (size_t)q;
            if (pair_2d(c, s->cross_i[q], s->nl_j[s->cross_p[q]], tang, clamp, &o)) {
                f[0] = o.Fx;
                f[1] = o.Fy;
                f[2] = o.Gx;
                f[3] = o.Gy;
            } else {
                f[0] = f[1] = f[2] = f[3] = 0.0;
            }
        }
    }
#pragma omp barrier
    for (int t = tid; t < T; t += nth) {
        const int lo = s->par_row[t], hi = s->par_row[t + 1];
        zero_forces(s, lo, hi);
        add_incoming(s, lo, hi, 0, s->cross_start[t]);
        for (int r0 = lo; r0 < hi; r0 += GR_BLOCK) {
            const int r1 = r0 + GR_BLOCK < hi ? r0 + GR_BLOCK : hi;
            rows_2d(s, r0, r1, lo, hi, 0, tang, clamp, s->blk + (size_t)(r0 / GR_BLOCK) * GR_BLK_FIELDS);
        }
        add_incoming(s, lo, hi, s->cross_start[t + 1], s->cross_start[T]);
    }
}

/* Threads for this evaluation; builds the cross lists when the list or T changed. */
static int team_2d(gr_sim *s)
{
    int T = gr_team(s);
    if (T > 1 && (s->par_threads != T || s->par_rebuilds != s->rebuilds) && !build_cross(s, T)) {
        T = 1;
    }
    return T;
}

#ifdef _OPENMP
#define THREAD_ID omp_get_thread_num()
#define THREAD_COUNT omp_get_num_threads()
#else
#define THREAD_ID 0
#define THREAD_COUNT 1
#endif

/* Combine the block sums in block order into the report. */
static void report_2d(gr_sim *s, gr_force_report *r)
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
    r->elastic = 0.5 * s->cc.k_s * elastic;
    r->power_normal = pn;
    r->power_tangential = pt;
    r->power_friction = pf;
    r->new_contacts = fresh;
    r->max_overlap = worst / d;
    r->worst_i = wi;
    r->worst_j = wj;
}

/* 1D ring: particle i touches only i+1 (mod n); positions are kept unwrapped and ordered, so the
 * gap of the last pair is x_0 + L - x_{n-1}. */
static void pair_loop_1d(gr_sim *restrict s, gr_force_report *restrict r, const int clamp)
{
    const int n = s->n;
    const double L = s->L, d = s->d, k = s->cc.k_s, gn = s->cc.gamma_n;
    const double *restrict x = s->x, *restrict v = s->vx;
    double *restrict f = s->fx, *restrict fnc = s->gx;
    uint8_t *restrict touching = s->pair_contact;
    double elastic = 0.0, pn = 0.0, worst = 0.0;
    int64_t fresh = 0;
    int wi = -1;
    if (n < 2) {
        f[0] = fnc[0] = 0.0;
        *r = (gr_force_report){.worst_i = -1, .worst_j = -1};
        return;
    }
    /* f_i = P_{i-1} - P_i with P_i the force of pair (i, i+1) on i+1: one forward pass carrying
     * P_{i-1}, no zeroing and no scatter */
    double carry = 0.0, carry_d = 0.0;
    for (int i = 0; i < n; i++) {
        const int j = i + 1 < n ? i + 1 : 0;
        const double gap = i + 1 < n ? x[j] - x[i] : x[0] + L - x[i];
        double f_n = 0.0, f_d = 0.0;
        if (gap < d) {
            fresh += !touching[i];
            touching[i] = 1;
            const double ov = d - gap;
            const double g_n = v[j] - v[i];
            f_n = k * ov - gn * g_n;
            if (clamp) {
                f_n = f_n > 0.0 ? f_n : 0.0;
            }
            f_d = f_n - k * ov;
            elastic += ov * ov;
            pn -= f_d * g_n;
            if (ov > worst) {
                worst = ov;
                wi = i;
            }
        } else {
            touching[i] = 0;
        }
        f[i] = carry - f_n;
        fnc[i] = carry_d - f_d;
        carry = f_n;
        carry_d = f_d;
    }
    f[0] += carry; /* the wrap pair (n-1, 0) pushes particle 0 */
    fnc[0] += carry_d;
    r->elastic = 0.5 * k * elastic;
    r->power_normal = pn;
    r->power_tangential = 0.0;
    r->power_friction = 0.0;
    r->new_contacts = fresh;
    r->max_overlap = worst / d;
    r->worst_i = wi;
    r->worst_j = wi >= 0 ? (wi + 1) % n : -1;
}

/* One function per contact-law combination; the parallel region is written in each, so that the
 * constants reach the body OpenMP outlines. */
#define KERNEL_2D(name, TANG, CLAMP)                                                               \
    static void name(gr_sim *s, gr_force_report *r)                                                \
    {                                                                                              \
        const int T = team_2d(s);                                                                  \
        if (T == 1) {                                                                              \
            serial_2d(s, TANG, CLAMP);                                                             \
        } else {                                                                                   \
            _Pragma("omp parallel num_threads(T)") threaded_2d(s, T, THREAD_ID, THREAD_COUNT, TANG, CLAMP); \
        }                                                                                          \
        report_2d(s, r);                                                                           \
    }
KERNEL_2D(kernel_2d_n, TANG_NONE, 0)
KERNEL_2D(kernel_2d_n_clamp, TANG_NONE, 1)
KERNEL_2D(kernel_2d_nt, TANG_DASHPOT, 0)
KERNEL_2D(kernel_2d_nt_clamp, TANG_DASHPOT, 1)
KERNEL_2D(kernel_2d_nf, TANG_FRICTION, 0)
KERNEL_2D(kernel_2d_nf_clamp, TANG_FRICTION, 1)
#undef KERNEL_2D

void gr_forces(gr_sim *s, gr_force_report *r)
{
    switch (s->kernel) {
    case KERNEL_1D: pair_loop_1d(s, r, s->cc.clamp); break;
    case KERNEL_2D_N: kernel_2d_n(s, r); break;
    case KERNEL_2D_N_CLAMP: kernel_2d_n_clamp(s, r); break;
    case KERNEL_2D_NT: kernel_2d_nt(s, r); break;
    case KERNEL_2D_NT_CLAMP: kernel_2d_nt_clamp(s, r); break;
    case KERNEL_2D_NF: kernel_2d_nf(s, r); break;
    case KERNEL_2D_NF_CLAMP: kernel_2d_nf_clamp(s, r); break;
    }
}

void gr_kernel_choose(gr_sim *s)
{
    const gr_contact_coeffs *c = &s->cc;
    int clamp = c->clamp;
    int tang = c->tangential == GR_TANGENTIAL_DASHPOT ? TANG_DASHPOT
               : c->tangential == GR_TANGENTIAL_FRICTION ? TANG_FRICTION : TANG_NONE;
    /* a tangential dashpot with eps_t = 1 does nothing: skip its work */
    if (tang == TANG_DASHPOT && c->gamma_t == 0.0) {
        tang = TANG_NONE;
    }
    if (tang == TANG_FRICTION && c->mu == 0.0) {
        tang = TANG_NONE;
    }
    if (s->dim == 1) {
        s->kernel = KERNEL_1D;
    } else {
        static const gr_kernel_id table[3][2] = {{KERNEL_2D_N, KERNEL_2D_N_CLAMP},
                                                 {KERNEL_2D_NT, KERNEL_2D_NT_CLAMP},
                                                 {KERNEL_2D_NF, KERNEL_2D_NF_CLAMP}};
        s->kernel = table[tang][clamp];
    }
    static const char *tname[] = {"", "+tangential_dashpot", "+sliding_friction"};
    const char *noise = s->scene.noise_mode == GR_NOISE_NONE ? "no-noise"
                        : s->scene.noise_mode == GR_NOISE_COM ? "noise-com" : "noise-symmetrised";
    const char *nb = s->dim == 1 ? "1d-ring" : (s->scene.skin > 0.0 ? "2d-verlet-list" : "2d-cell-list");
    snprintf(s->kernel_name, sizeof s->kernel_name, "%s/spring_dashpot%s%s/%s", nb,
             clamp ? "[clamped]" : "", tname[tang], noise);
}

void gr_forces_bruteforce(const gr_sim *s, double *fx, double *fy, double *elastic)
{
    const double L = s->L, d = s->d, k = s->cc.k_s, gn = s->cc.gamma_n, gt = s->cc.gamma_t;
    const double mu = s->cc.mu, m12_dt = s->cc.m12 / s->dt;
    int tang = s->kernel == KERNEL_2D_NT || s->kernel == KERNEL_2D_NT_CLAMP ? TANG_DASHPOT
               : s->kernel == KERNEL_2D_NF || s->kernel == KERNEL_2D_NF_CLAMP ? TANG_FRICTION
                                                                                : TANG_NONE;
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
            double f_n = k * ov - gn * g_n;
            if (s->cc.clamp && f_n < 0.0) {
                f_n = 0.0;
            }
            *elastic += 0.5 * k * ov * ov;
            double Fx = f_n * nx, Fy = f_n * ny;
            if (tang) {
                double tx = ny, ty = -nx, g_t = gx * tx + gy * ty, f_t = 0.0;
                if (tang == TANG_DASHPOT && (!s->cc.clamp || f_n > 0.0)) {
                    f_t = -gt * g_t;
                } else if (tang == TANG_FRICTION) {
                    double mag = fmin(mu * fabs(f_n), m12_dt * fabs(g_t));
                    f_t = g_t > 0.0 ? -mag : (g_t < 0.0 ? mag : 0.0);
                }
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
