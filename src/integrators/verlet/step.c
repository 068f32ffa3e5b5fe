/* The time step: velocity Verlet in kick-drift-kick form with the random force as a mid-step
 * velocity kick (docs/integrator.md).
 *
 *   v += F_c(x_n, v_{n-1/2}) dt / 2M          close step n
 *   v += eta_n dt / M                          random force (2.16 / 2.23), symmetrised (2.18)
 *   x += v dt                                  drift
 *   F_c(x_{n+1}, v_{n+1/2})                    contact forces with the half-step velocity
 *   v += F_c dt / 2M
 *
 * Positions are identical to the thesis's position Verlet (2.3) with a = (F_c + eta) / M. The
 * dashpots see the half-step velocity, the only velocity known before the force evaluation; any
 * scheme is first order for these forces because they jump at the start and end of a contact
 * (Danby et al. 2013), and this one needs one force evaluation per step.
 *
 * The random force held over a step has standard deviation sqrt(2D/dt) per component, so the
 * velocity kick is sqrt(2 D dt) / M * g, g standard normal. Symmetrised mode subtracts the mean
 * kick (2.18); com mode removes the centre-of-mass velocity every com_interval instead
 * (sec. 2.3.1). The ledger records the exact kinetic energy each kick adds.
 *
 * A Langevin bath ([driving] kind = langevin, src/core/driving_langevin.c) takes the random
 * force's place in the step: the exact Ornstein-Uhlenbeck update v <- a v + b xi with
 * a = e^{-dt/tau}, b = sqrt(T_bath/dim (1 - a^2)), the same normals (stream, counter) unsymmetrised.
 * The ledger books the drag's part, M v^2 (1 - a^2) / 2, as dissipated_drag and the noise's,
 * M b xi (a v + b xi / 2), as injected: their difference is the exact change of kinetic energy.
 * The driving is chosen once per run: each (driving, closing) pair has its own loop, so the
 * random force's loop is the one it always was.
 *
 * 3D (spheres, docs/three-dimensions.md): the same step with a third component; the normals,
 * their means and the kick-drift pass run over blocks shared by the threads as in 2D, and the
 * forces on the threads (kernels_3d.c), so a run is the same for every thread count (the last
 * half kick of a call, half_kick_3d, runs on one thread).
 *
 * Threads (2D and 3D): the noise and the kick-drift pass run over blocks of GR_BLOCK particles shared by
 * the threads, and every sum is combined block by block in block order, so a run is bit-identical
 * for every thread count (docs/performance.md, "Threads"). */
#include <math.h>
#include <stdio.h>
#include <stdbool.h>
#include <string.h>

#include "granule/noise.h"
#include "integrators/verlet/verlet.h"

/* Rotation: the half kicks of the angular velocities, w += tau dt / 2I, in the same kick-drift-kick
 * rhythm as v (the torques tq of the last force evaluation). Returns the work of the
 * non-conservative torques, exactly as for v: tau_nc (w + dw/2) dt/2 per half kick, summed in
 * particle order, booked as dissipation with the translational work of G. The torques come from
 * the tangential and rolling laws; a dashpot's or friction's are all non-conservative (tau_nc =
 * tq), a history law's spring is not: its torque's work shows up as the change of the springs'
 * energy k_t s^2 / 2 (the spring integrates the contact point's g_t, surface velocities included),
 * so the kernel keeps tau_nc apart in s->tg. `closing` merges the previous step's closing kick as
 * open_step_* does; its work goes to *wc, the opening kick's to *wo. */
static bool spin_kicks_3d(gr_sim *s, const int closing, const int opening, double *wc, double *wo);

bool gr_verlet_spin_kicks(gr_sim *s, const int closing, const int opening, double *wc, double *wo)
{
    if (s->dim == 3) {
        return spin_kicks_3d(s, closing, opening, wc, wo);
    }
    const double h = 0.5 * s->dt / s->inertia, h0 = 0.5 * s->dt;
    const double *restrict inertia_i = s->inertia_i; /* a mixture's (the hybrid's child) */
    double *restrict w = s->omega;
    const double *restrict tq = s->tq;
    const double *restrict nc = s->tg ? s->tg : s->tq;
    double c = 0.0, o = 0.0, sum = 0.0;
    for (int i = 0; i < s->n; i++) {
        const double dw = inertia_i ? h0 / inertia_i[i] * tq[i] : h * tq[i];
        double wi = w[i];
        if (closing) {
            c += nc[i] * (wi + 0.5 * dw);
            wi += dw;
        }
        if (opening) {
            o += nc[i] * (wi + 0.5 * dw);
            wi += dw;
        }
        w[i] = wi;
        sum += wi;
    }
    *wc += 0.5 * s->dt * c;
    *wo += 0.5 * s->dt * o;
    return isfinite(sum) && isfinite(c) && isfinite(o);
}

/* The same for spheres: angular velocity vectors (wx, wy, omega = w_z) and torques (tqx, tqy,
 * tq; the non-conservative parts tgx, tgy, tg with a history law), each component as above. */
static bool spin_kicks_3d(gr_sim *s, const int closing, const int opening, double *wc, double *wo)
{
    const double h = 0.5 * s->dt / s->inertia, h0 = 0.5 * s->dt;
    const double *restrict inertia_i = s->inertia_i; /* a mixture's (the hybrid's child) */
    double *restrict w[3] = {s->wx, s->wy, s->omega};
    const double *restrict tq[3] = {s->tqx, s->tqy, s->tq};
    const double *restrict nc[3] = {s->tg ? s->tgx : s->tqx, s->tg ? s->tgy : s->tqy,
                                    s->tg ? s->tg : s->tq};
    double c = 0.0, o = 0.0, sum = 0.0;
    for (int i = 0; i < s->n; i++) {
        for (int a = 0; a < 3; a++) {
            const double dw = inertia_i ? h0 / inertia_i[i] * tq[a][i] : h * tq[a][i];
            double wi = w[a][i];
            if (closing) {
                c += nc[a][i] * (wi + 0.5 * dw);
                wi += dw;
            }
            if (opening) {
                o += nc[a][i] * (wi + 0.5 * dw);
                wi += dw;
            }
            w[a][i] = wi;
            sum += wi;
        }
    }
    *wc += 0.5 * s->dt * c;
    *wo += 0.5 * s->dt * o;
    return isfinite(sum) && isfinite(c) && isfinite(o);
}

/* The closing half kick of 3D (half_kick below), one thread, the same arithmetic per component
 * as open_step_3d's merged closing kick. */
static double half_kick_3d(gr_sim *s, bool *finite)
{
    const double h = 0.5 * s->dt / s->mass;
    double *restrict v[3] = {s->vx, s->vy, s->vz};
    const double *restrict f[3] = {s->fx, s->fy, s->fz}, *restrict g[3] = {s->gx, s->gy, s->gz};
    double wl[LANES] = {0}, sl[LANES] = {0};
    for (int i = 0; i < s->n; i++) {
        const int l = i % LANES;
        for (int c = 0; c < 3; c++) {
            const double dv = h * f[c][i];
            wl[l] += g[c][i] * (v[c][i] + 0.5 * dv);
            v[c][i] += dv;
            sl[l] += v[c][i];
        }
    }
    const double work = lanes_total(wl);
    *finite = isfinite(lanes_total(sl)) && isfinite(work);
    if (!s->omega) {
        return work * 0.5 * s->dt;
    }
    double spin = 0.0, unused = 0.0;
    *finite = spin_kicks_3d(s, 1, 0, &spin, &unused) && *finite;
    return work * 0.5 * s->dt + spin;
}

/* Closing half kick. Returns the work done on the particles by the non-conservative part of the
 * contact forces (dashpots, friction, a clamp), exactly: a kick dv changes the kinetic energy of
 * particle i by F_i . (v_i + dv_i/2) dt/2, so the part due to G_i = F_i - (spring forces) is
 * G_i . (v_i + dv_i/2) dt/2. The arithmetic (per particle, in this order) is exactly that of the
 * closing kick merged into open_step_*, so a run split over several calls is bit-identical. */
static double half_kick(gr_sim *s, bool *finite)
{
    const double h = 0.5 * s->dt / s->mass;
    const int n = s->n;
    double work = 0.0, sum = 0.0;
    if (s->dim == 3) {
        return half_kick_3d(s, finite);
    }
    if (s->dim == 1) {
        double *restrict v = s->vx;
        const double *restrict f = s->fx, *restrict g = s->gx;
        double wl[LANES] = {0}, sl[LANES] = {0};
        for (int i = 0; i < n; i++) {
            const int l = i % LANES;
            const double dv = h * f[i];
            wl[l] += g[i] * (v[i] + 0.5 * dv);
            v[i] += dv;
            sl[l] += v[i];
        }
        work = lanes_total(wl);
        sum = lanes_total(sl);
    } else {
        double *restrict vx = s->vx, *restrict vy = s->vy;
        const double *restrict fx = s->fx, *restrict fy = s->fy, *restrict gx = s->gx,
                               *restrict gy = s->gy;
        double wl[LANES] = {0}, sl[LANES] = {0};
        for (int i = 0; i < n; i++) {
            const int l = i % LANES;
            const double dvx = h * fx[i], dvy = h * fy[i];
            wl[l] += gx[i] * (vx[i] + 0.5 * dvx) + gy[i] * (vy[i] + 0.5 * dvy);
            vx[i] += dvx;
            vy[i] += dvy;
            sl[l] += vx[i] + vy[i];
        }
        work = lanes_total(wl);
        sum = lanes_total(sl);
    }
    *finite = isfinite(sum) && isfinite(work);
    if (!s->omega) {
        return work * 0.5 * s->dt;
    }
    double spin = 0.0, unused = 0.0;
    *finite = gr_verlet_spin_kicks(s, 1, 0, &spin, &unused) && *finite;
    return work * 0.5 * s->dt + spin;
}

/* Lane sums of g[0..m) (m a multiple of LANES except in the last block), even and odd lanes
 * apart: with dim = 2 the components alternate, so even lanes hold x and odd lanes y. */
static void noise_sums(const double *restrict g, const int m, const int dim, double out[2])
{
    double acc[LANES] = {0}; /* lanes: vectorised, same sum on every machine */
    const int full = m / LANES * LANES;
    for (int i0 = 0; i0 < full; i0 += LANES) {
        for (int l = 0; l < LANES; l++) {
            acc[l] += g[i0 + l];
        }
    }
    for (int i = full; i < m; i++) {
        acc[i - full] += g[i];
    }
    double m0 = 0.0, m1 = 0.0;
    for (int l = 0; l < LANES; l++) {
        if (dim == 1 || l % 2 == 0) {
            m0 += acc[l];
        } else {
            m1 += acc[l];
        }
    }
    out[0] = m0;
    out[1] = m1;
}

/* Fields of s->blk the noise sums use (apart from those of the opening pass, which may run
 * while other threads still read them). */
enum { B_NOISE0 = 6, B_NOISE1 = 7, B_NOISE2 = 8 };

/* Lane sums of the m particles' three components g[3 i + c], per component (3D). */
static void noise_sums_3d(const double *restrict g, const int m, double out[3])
{
    double a0[LANES] = {0}, a1[LANES] = {0}, a2[LANES] = {0};
    const int full = m / LANES * LANES;
    for (int i0 = 0; i0 < full; i0 += LANES) {
#pragma omp simd
        for (int l = 0; l < LANES; l++) {
            a0[l] += g[3 * (i0 + l)];
            a1[l] += g[3 * (i0 + l) + 1];
            a2[l] += g[3 * (i0 + l) + 2];
        }
    }
    for (int i = full; i < m; i++) {
        a0[i - full] += g[3 * i];
        a1[i - full] += g[3 * i + 1];
        a2[i - full] += g[3 * i + 2];
    }
    out[0] = lanes_total(a0);
    out[1] = lanes_total(a1);
    out[2] = lanes_total(a2);
}

/* The id offset of the third component's single-precision normals: gr_noise_normals_f32 draws
 * one or two components per particle, so component z of particle i is component 0 (per = 1) of
 * id i + 2^31, counters no particle's x and y use (N < 2^31). */
#define F32_Z_ID 0x80000000u

/* [noise] precision = single in 3D: m particles from id lo (m <= GR_BLOCK), x and y as 2D draws
 * them, z from the ids F32_Z_ID + lo..., interleaved into out (3 per particle). A pure function of
 * (seed, step, id, component) like the 2D draw, whatever the blocks and threads. */
static void normals_f32_3d(const uint64_t seed, const uint64_t step, const uint32_t lo, const int m,
                           double *out)
{
    double xy[2 * GR_BLOCK], zc[GR_BLOCK];
    gr_noise_normals_f32(seed, GR_STREAM_NOISE, step, lo, m, 2, xy);
    gr_noise_normals_f32(seed, GR_STREAM_NOISE, step, F32_Z_ID + lo, m, 1, zc);
    for (int i = 0; i < m; i++) {
        out[3 * i] = xy[2 * i];
        out[3 * i + 1] = xy[2 * i + 1];
        out[3 * i + 2] = zc[i];
    }
}

/* Draw the normals of block b (bs particles per block) and, if sym, its lane sums. */
static inline void draw_block(gr_sim *s, const int b, const int bs, const int sym)
{
    const int n = s->n, dim = s->dim, lo = b * bs, m = (b + 1) * bs < n ? bs : n - lo;
    /* [noise] precision: one branch per block of particles, not per particle */
    if (dim == 3 && s->params.noise_precision == GR_NOISE_SINGLE) {
        normals_f32_3d(s->params.seed, (uint64_t)s->step, (uint32_t)lo, m,
                       s->noise + (size_t)lo * dim);
    } else {
        (s->params.noise_precision == GR_NOISE_SINGLE ? gr_noise_normals_f32 : gr_noise_normals)(
            s->params.seed, GR_STREAM_NOISE, (uint64_t)s->step, (uint32_t)lo, m, dim,
            s->noise + (size_t)lo * dim);
    }
    if (sym && dim == 3) {
        noise_sums_3d(s->noise + (size_t)lo * dim, m,
                      s->blk + (size_t)b * GR_BLK_FIELDS + B_NOISE0);
    } else if (sym) {
        noise_sums(s->noise + (size_t)lo * dim, m * dim, dim,
                   s->blk + (size_t)b * GR_BLK_FIELDS + B_NOISE0);
    }
}

/* The means of the symmetrised mode from the block sums, in block order (mean[2]: 3D only). */
static void noise_mean(const gr_sim *s, const int nb, const int sym, double mean[3])
{
    mean[0] = mean[1] = mean[2] = 0.0;
    if (sym) {
        double m0 = 0.0, m1 = 0.0, m2 = 0.0;
        for (int b = 0; b < nb; b++) {
            m0 += s->blk[(size_t)b * GR_BLK_FIELDS + B_NOISE0];
            m1 += s->blk[(size_t)b * GR_BLK_FIELDS + B_NOISE1];
            m2 += s->dim == 3 ? s->blk[(size_t)b * GR_BLK_FIELDS + B_NOISE2] : 0.0;
        }
        mean[0] = m0 / s->n;
        mean[1] = m1 / s->n;
        mean[2] = m2 / s->n;
    }
}

static inline int symmetrised(const gr_sim *s)
{
    return s->params.noise_mode == GR_NOISE_SYMMETRISED && s->n > 1;
}

/* Draw this step's normals and the means the symmetrised mode subtracts (2.18): per block of
 * GR_BLOCK particles (T threads share the blocks), block sums combined in block order. (2D with
 * T > 1 threads draws inside the opening pass instead: noise_open_2d_*.) */
static void draw_noise(gr_sim *s, double mean[3], const int T)
{
    /* 1D runs on one thread: one block, as ever */
    const int n = s->n, bs = s->dim == 1 ? (n > 0 ? n : 1) : GR_BLOCK, nb = (n + bs - 1) / bs;
    const int sym = symmetrised(s);
    if (T > 1) {
#pragma omp parallel for schedule(static) num_threads(T)
        for (int b = 0; b < nb; b++) {
            draw_block(s, b, bs, sym);
        }
    } else {
        for (int b = 0; b < nb; b++) {
            draw_block(s, b, bs, sym);
        }
    }
    noise_mean(s, nb, sym, mean);
}

void gr_verlet_draw_noise(gr_sim *s, double mean[3], const int T) { draw_noise(s, mean, T); }

/* Open a step in one pass: (if `closing`) the previous step's closing half kick, the opening half
 * kick with the same forces, the driving (`noise`: DRIVE_KICK the random force's kick, DRIVE_OU
 * the bath's Ornstein-Uhlenbeck update, 0 nothing), the drift. Returns the kinetic energy the
 * noise added; sets the work of the non-conservative forces in each half kick (see half_kick),
 * the kinetic energy the bath's drag removed, whether all velocities are finite, and in 2D the
 * largest squared displacement since the last neighbour-list build. */
typedef struct open_report {
    double work_close, work_open, disp2, disp2s, drag; /* disp2s: since the sublist's build */
    bool finite;
} open_report;

enum { DRIVE_KICK = 1, DRIVE_OU = 2 }; /* `noise` of the opening pass (0: no driving) */

static inline __attribute__((always_inline)) double open_step_1d(gr_sim *restrict s,
                                                                 const int noise, const double mean,
                                                                 const int closing, open_report *o)
{
    const int n = s->n;
    const double h = 0.5 * s->dt / s->mass, dt = s->dt;
    const double amp = noise == DRIVE_KICK ? sqrt(2.0 * s->params.D * s->dt) / s->mass : 0.0;
    const double decay = s->drive_c.decay, kick = s->drive_c.kick;
    double *restrict x = s->x, *restrict v = s->vx;
    const double *restrict f = s->fx, *restrict g = s->noise, *restrict gnc = s->gx;
    double added[LANES] = {0}, wc[LANES] = {0}, wo[LANES] = {0}, sum[LANES] = {0},
           drag[LANES] = {0};
#define OPEN_1D(i, l)                                                                              \
    do {                                                                                           \
        const double dvf = h * f[i];                                                               \
        double vi = v[i];                                                                          \
        if (closing) {                                                                             \
            wc[l] += gnc[i] * (vi + 0.5 * dvf);                                                    \
            vi += dvf;                                                                             \
        }                                                                                          \
        wo[l] += gnc[i] * (vi + 0.5 * dvf);                                                        \
        vi += dvf;                                                                                 \
        if (noise == DRIVE_KICK) {                                                                 \
            const double dv = amp * (g[i] - mean);                                                 \
            added[l] += dv * (vi + 0.5 * dv);                                                      \
            vi += dv;                                                                              \
        } else if (noise == DRIVE_OU) {                                                            \
            const double vd = decay * vi, dv = kick * g[i];                                        \
            drag[l] += vi * vi - vd * vd;                                                          \
            added[l] += dv * (vd + 0.5 * dv);                                                      \
            vi = vd + dv;                                                                          \
        }                                                                                          \
        v[i] = vi;                                                                                 \
        sum[l] += vi;                                                                              \
        x[i] += vi * dt; /* unwrapped: the ring keeps its order */                                 \
    } while (0)
    const int full = n / LANES * LANES;
    for (int i0 = 0; i0 < full; i0 += LANES) {
#pragma omp simd
        for (int l = 0; l < LANES; l++) {
            OPEN_1D(i0 + l, l);
        }
    }
    for (int i = full; i < n; i++) {
        OPEN_1D(i, i - full);
    }
#undef OPEN_1D
    o->work_close = 0.5 * dt * lanes_total(wc);
    o->work_open = 0.5 * dt * lanes_total(wo);
    o->finite = isfinite(lanes_total(sum)) && isfinite(o->work_open);
    o->drag = noise == DRIVE_OU ? 0.5 * s->mass * lanes_total(drag) : 0.0;
    return s->mass * lanes_total(added);
}

/* open_step_2d on the particles [lo, hi) (lo a multiple of LANES); writes the block's sums to
 * part: added, work_close, work_open, velocity sum, largest squared displacement (and with the
 * bath, the drag's sum of v^2 - (a v)^2). */
enum { P_ADDED, P_WC, P_WO, P_SUM, P_DISP2, P_DRAG, P_DISP2S = 9 }; /* 6-8: the noise's sums */

/* A block's lane sums into its part of s->blk (open_range_2d, open_range_3d). */
static inline void block_sums(double *restrict part, const int noise, const double added[LANES],
                              const double wc[LANES], const double wo[LANES],
                              const double sum[LANES], const double worst[LANES],
                              const double worst_s[LANES], const double drag[LANES])
{
    double w = 0.0, ws = 0.0;
    for (int l = 0; l < LANES; l++) {
        w = worst[l] > w ? worst[l] : w;
        ws = worst_s[l] > ws ? worst_s[l] : ws;
    }
    part[P_DISP2] = w;
    part[P_DISP2S] = ws;
    part[P_WC] = lanes_total(wc);
    part[P_WO] = lanes_total(wo);
    part[P_SUM] = lanes_total(sum);
    part[P_ADDED] = lanes_total(added);
    if (noise == DRIVE_OU) {
        part[P_DRAG] = lanes_total(drag);
    }
}

static inline __attribute__((always_inline)) void open_range_2d(gr_sim *restrict s, const int lo,
                                                                const int hi, const int noise,
                                                                const double mean[2],
                                                                const int closing, const int listck,
                                                                double *restrict part)
{
    const double h = 0.5 * s->dt / s->mass, dt = s->dt, L = s->L, half = 0.5 * L;
    const double amp = noise == DRIVE_KICK ? sqrt(2.0 * s->params.D * s->dt) / s->mass : 0.0;
    const double decay = s->drive_c.decay, kick = s->drive_c.kick;
    const double m0 = mean[0], m1 = mean[1];
    /* wrap into [0, L) along periodic axes only: along a wall axis a grain riding a floor that
     * vibrates below 0 keeps its coordinate (walls.c; the neighbour list does not wrap there) */
    const double inf = (double)INFINITY;
    const double lo_x = s->period[0] < inf ? 0.0 : -inf, hi_x = lo_x == 0.0 ? L : inf;
    const double lo_y = s->period[1] < inf ? 0.0 : -inf, hi_y = lo_y == 0.0 ? L : inf;
    double *restrict x = s->x, *restrict y = s->y, *restrict vx = s->vx, *restrict vy = s->vy;
    const double *restrict fx = s->fx, *restrict fy = s->fy, *restrict g = s->noise;
    const double *restrict xr = s->x_ref, *restrict yr = s->y_ref;
    /* the sublist's reference (the list's when it is off: then the result is not read) */
    const double *restrict sxr = s->sl_on ? s->xs_ref : xr, *restrict syr =
                                                                s->sl_on ? s->ys_ref : yr;
    const double *restrict gx = s->gx, *restrict gy = s->gy;
    double added[LANES] = {0}, worst[LANES] = {0}, wc[LANES] = {0}, wo[LANES] = {0},
           sum[LANES] = {0}, worst_s[LANES] = {0};
    double drag[LANES] = {0};
#define OPEN_2D(i, l)                                                                              \
    do {                                                                                           \
        const double dvx0 = h * fx[i], dvy0 = h * fy[i];                                           \
        double vxi = vx[i], vyi = vy[i];                                                           \
        if (closing) {                                                                             \
            wc[l] += gx[i] * (vxi + 0.5 * dvx0) + gy[i] * (vyi + 0.5 * dvy0);                      \
            vxi += dvx0;                                                                           \
            vyi += dvy0;                                                                           \
        }                                                                                          \
        wo[l] += gx[i] * (vxi + 0.5 * dvx0) + gy[i] * (vyi + 0.5 * dvy0);                          \
        vxi += dvx0;                                                                               \
        vyi += dvy0;                                                                               \
        if (noise == DRIVE_KICK) {                                                                 \
            const double dvx = amp * (g[2 * (i)] - m0), dvy = amp * (g[2 * (i) + 1] - m1);         \
            added[l] += dvx * (vxi + 0.5 * dvx) + dvy * (vyi + 0.5 * dvy);                         \
            vxi += dvx;                                                                            \
            vyi += dvy;                                                                            \
        } else if (noise == DRIVE_OU) {                                                            \
            const double vdx = decay * vxi, vdy = decay * vyi;                                     \
            const double dvx = kick * g[2 * (i)], dvy = kick * g[2 * (i) + 1];                     \
            drag[l] += (vxi * vxi - vdx * vdx) + (vyi * vyi - vdy * vdy);                          \
            added[l] += dvx * (vdx + 0.5 * dvx) + dvy * (vdy + 0.5 * dvy);                         \
            vxi = vdx + dvx;                                                                       \
            vyi = vdy + dvy;                                                                       \
        }                                                                                          \
        vx[i] = vxi;                                                                               \
        vy[i] = vyi;                                                                               \
        sum[l] += vxi + vyi;                                                                       \
        double xn = x[i] + vxi * dt, yn = y[i] + vyi * dt;                                         \
        xn += xn < lo_x ? L : (xn >= hi_x ? -L : 0.0);                                             \
        yn += yn < lo_y ? L : (yn >= hi_y ? -L : 0.0);                                             \
        x[i] = xn;                                                                                 \
        y[i] = yn;                                                                                 \
        if (listck) {                                                                              \
            double ddx = xn - xr[i], ddy = yn - yr[i];                                             \
            ddx += ddx > half ? -L : (ddx < -half ? L : 0.0);                                      \
            ddy += ddy > half ? -L : (ddy < -half ? L : 0.0);                                      \
            const double d2 = ddx * ddx + ddy * ddy;                                               \
            worst[l] = d2 > worst[l] ? d2 : worst[l];                                              \
        }                                                                                          \
        double sdx = xn - sxr[i], sdy = yn - syr[i];                                               \
        sdx += sdx > half ? -L : (sdx < -half ? L : 0.0);                                          \
        sdy += sdy > half ? -L : (sdy < -half ? L : 0.0);                                          \
        const double s2 = sdx * sdx + sdy * sdy;                                                   \
        worst_s[l] = s2 > worst_s[l] ? s2 : worst_s[l];                                            \
    } while (0)
    const int full = lo + (hi - lo) / LANES * LANES;
    for (int i0 = lo; i0 < full; i0 += LANES) {
#pragma omp simd
        for (int l = 0; l < LANES; l++) {
            OPEN_2D(i0 + l, l);
        }
    }
#pragma omp simd /* the tail in the same lanes: each lane's operations are those of the
                    scalar loop, so the sums keep their bits (a small bed's tail is 6 of 150) */
    for (int i = full; i < hi; i++) {
        OPEN_2D(i, i - full);
    }
#undef OPEN_2D
    block_sums(part, noise, added, wc, wo, sum, worst, worst_s, drag);
}

/* The opening pass's block sums combined in block order: the kinetic energy the noise added (the
 * return value), the work of each half kick, the drag's loss, the largest squared displacement and
 * whether every velocity is finite. */
static double open_total(const gr_sim *s, const int noise, open_report *o)
{
    const int nb = s->nblk;
    const double *blk = s->blk;
    double added = 0.0, wc = 0.0, wo = 0.0, sum = 0.0, worst = 0.0, worst_s = 0.0, drag = 0.0;
    for (int b = 0; b < nb; b++) {
        const double *q = blk + (size_t)b * GR_BLK_FIELDS;
        drag += noise == DRIVE_OU ? q[P_DRAG] : 0.0;
        added += q[P_ADDED];
        wc += q[P_WC];
        wo += q[P_WO];
        sum += q[P_SUM];
        worst = q[P_DISP2] > worst ? q[P_DISP2] : worst;
        worst_s = q[P_DISP2S] > worst_s ? q[P_DISP2S] : worst_s;
    }
    o->disp2 = worst;
    o->disp2s = worst_s;
    o->work_close = 0.5 * s->dt * wc;
    o->work_open = 0.5 * s->dt * wo;
    o->finite = isfinite(sum) && isfinite(o->work_open);
    o->drag = 0.5 * s->mass * drag;
    return s->mass * added;
}

/* The 2D opening pass over blocks of GR_BLOCK particles (shared by T threads); block sums are
 * combined in block order, so the result does not depend on T. One function per (noise,
 * closing) pair, so that the constants reach the loop body that OpenMP outlines. */
#define OPEN_BLOCKS_2D(name, NOISE, CLOSING, LISTCK)                                               \
    static void name(gr_sim *restrict s, const double mean[2], const int T)                        \
    {                                                                                              \
        const int n = s->n, nb = s->nblk;                                                          \
        double *blk = s->blk;                                                                      \
        if (T > 1) {                                                                               \
            _Pragma("omp parallel for schedule(static) num_threads(T)") for (int b = 0; b < nb;    \
                                                                             b++)                  \
            {                                                                                      \
                const int lo = b * GR_BLOCK, hi = lo + GR_BLOCK < n ? lo + GR_BLOCK : n;           \
                open_range_2d(s, lo, hi, NOISE, mean, CLOSING, LISTCK,                             \
                              blk + (size_t)b * GR_BLK_FIELDS);                                    \
            }                                                                                      \
        } else {                                                                                   \
            for (int b = 0; b < nb; b++) {                                                         \
                const int lo = b * GR_BLOCK, hi = lo + GR_BLOCK < n ? lo + GR_BLOCK : n;           \
                open_range_2d(s, lo, hi, NOISE, mean, CLOSING, LISTCK,                             \
                              blk + (size_t)b * GR_BLK_FIELDS);                                    \
            }                                                                                      \
        }                                                                                          \
    }
OPEN_BLOCKS_2D(open_blocks_2d_00, 0, 0, 1)
OPEN_BLOCKS_2D(open_blocks_2d_01, 0, 1, 1)
OPEN_BLOCKS_2D(open_blocks_2d_10, DRIVE_KICK, 0, 1)
OPEN_BLOCKS_2D(open_blocks_2d_11, DRIVE_KICK, 1, 1)
OPEN_BLOCKS_2D(open_blocks_2d_20, DRIVE_OU, 0, 1)
OPEN_BLOCKS_2D(open_blocks_2d_21, DRIVE_OU, 1, 1)
/* the closing steps with the sublist on: the list's displacements are left to the bound (the
 * step loop, gr_sublist_list_moved2) */
OPEN_BLOCKS_2D(open_blocks_2d_01s, 0, 1, 0)
OPEN_BLOCKS_2D(open_blocks_2d_11s, DRIVE_KICK, 1, 0)
OPEN_BLOCKS_2D(open_blocks_2d_21s, DRIVE_OU, 1, 0)
#undef OPEN_BLOCKS_2D

/* With noise on T > 1 threads: draw the noise, form its means and run the opening pass in one
 * parallel region (one fork and join per step fewer); the arithmetic is that of draw_noise and
 * open_blocks_2d_1*. Returns the means in mean. */
#define NOISE_OPEN_2D(name, NOISE, CLOSING, LISTCK)                                                \
    static void name(gr_sim *restrict s, double mean[2], const int T)                              \
    {                                                                                              \
        const int n = s->n, nb = s->nblk, sym = symmetrised(s);                                    \
        double *blk = s->blk;                                                                      \
        _Pragma("omp parallel num_threads(T)")                                                     \
        {                                                                                          \
            _Pragma("omp for schedule(static)") for (int b = 0; b < nb; b++)                       \
            {                                                                                      \
                draw_block(s, b, GR_BLOCK, sym);                                                   \
            }                                                                                      \
            double m[3];                                                                           \
            noise_mean(s, nb, sym, m); /* every thread, the same numbers */                        \
            _Pragma("omp for schedule(static)") for (int b = 0; b < nb; b++)                       \
            {                                                                                      \
                const int lo = b * GR_BLOCK, hi = lo + GR_BLOCK < n ? lo + GR_BLOCK : n;           \
                open_range_2d(s, lo, hi, NOISE, m, CLOSING, LISTCK,                                \
                              blk + (size_t)b * GR_BLK_FIELDS);                                    \
            }                                                                                      \
            _Pragma("omp master")                                                                  \
            {                                                                                      \
                mean[0] = m[0];                                                                    \
                mean[1] = m[1];                                                                    \
            }                                                                                      \
        }                                                                                          \
    }
NOISE_OPEN_2D(noise_open_2d_0, DRIVE_KICK, 0, 1)
NOISE_OPEN_2D(noise_open_2d_1, DRIVE_KICK, 1, 1)
NOISE_OPEN_2D(noise_open_2d_20, DRIVE_OU, 0, 1)
NOISE_OPEN_2D(noise_open_2d_21, DRIVE_OU, 1, 1)
NOISE_OPEN_2D(noise_open_2d_1s, DRIVE_KICK, 1, 0)
NOISE_OPEN_2D(noise_open_2d_21s, DRIVE_OU, 1, 0)
#undef NOISE_OPEN_2D

/* The 2D opening pass; with noise on T > 1 threads it also draws the noise (mean is then
 * filled in), otherwise draw_noise has run. listck = 0 (closing steps only): the displacements
 * since the list's build are not measured (o->disp2 = 0). */
static double open_step_2d(gr_sim *restrict s, const int noise, double mean[3], const int closing,
                           const int listck, open_report *o, const int T)
{
    if (closing && !listck) {
        if (noise == DRIVE_KICK && T > 1) {
            noise_open_2d_1s(s, mean, T);
        } else if (noise == DRIVE_KICK) {
            open_blocks_2d_11s(s, mean, T);
        } else if (noise == DRIVE_OU && T > 1) {
            noise_open_2d_21s(s, mean, T);
        } else if (noise == DRIVE_OU) {
            open_blocks_2d_21s(s, mean, T);
        } else {
            open_blocks_2d_01s(s, mean, T);
        }
    } else if (noise == DRIVE_KICK && T > 1) {
        (closing ? noise_open_2d_1 : noise_open_2d_0)(s, mean, T);
    } else if (noise == DRIVE_KICK) {
        (closing ? open_blocks_2d_11 : open_blocks_2d_10)(s, mean, T);
    } else if (noise == DRIVE_OU && T > 1) {
        (closing ? noise_open_2d_21 : noise_open_2d_20)(s, mean, T);
    } else if (noise == DRIVE_OU) {
        (closing ? open_blocks_2d_21 : open_blocks_2d_20)(s, mean, T);
    } else {
        (closing ? open_blocks_2d_01 : open_blocks_2d_00)(s, mean, T);
    }
    return open_total(s, noise, o);
}

/* The opening pass of 3D (spheres, docs/three-dimensions.md): the arithmetic of
 * open_range_2d with a third component; the random force's kick (2.23 per component, symmetrised
 * by mean), the bath's Ornstein-Uhlenbeck update or none. Returns the kinetic energy the noise
 * added; fills o as open_step_2d does. Along a wall axis (walls.c) positions are not wrapped. */
/* One component c of particle i in open_step_3d (the lane l's sums; d2 the squared displacement):
 * the same arithmetic, in the same order, for x, y and z. */
#define OPEN_3D_C(R, V, F, GN, REF, SREF, LO, HI, c, i, l)                                         \
    do {                                                                                           \
        const double dvf = h * F[i];                                                               \
        double vi = V[i];                                                                          \
        if (closing) {                                                                             \
            wc[l] += GN[i] * (vi + 0.5 * dvf);                                                     \
            vi += dvf;                                                                             \
        }                                                                                          \
        wo[l] += GN[i] * (vi + 0.5 * dvf);                                                         \
        vi += dvf;                                                                                 \
        if (noise == DRIVE_KICK) {                                                                 \
            const double dv = amp * (g[3 * (size_t)(i) + c] - mean[c]);                            \
            added[l] += dv * (vi + 0.5 * dv);                                                      \
            vi += dv;                                                                              \
        } else if (noise == DRIVE_OU) {                                                            \
            const double vd = decay * vi, dv = kick * g[3 * (size_t)(i) + c];                      \
            drag[l] += vi * vi - vd * vd;                                                          \
            added[l] += dv * (vd + 0.5 * dv);                                                      \
            vi = vd + dv;                                                                          \
        }                                                                                          \
        V[i] = vi;                                                                                 \
        sum[l] += vi;                                                                              \
        double q = R[i] + vi * dt;                                                                 \
        q += q < LO ? L : (q >= HI ? -L : 0.0);                                                    \
        R[i] = q;                                                                                  \
        if (listck) {                                                                              \
            double dd = q - REF[i];                                                                \
            dd += dd > half ? -L : (dd < -half ? L : 0.0);                                         \
            d2 += dd * dd;                                                                         \
        }                                                                                          \
        double ds = q - SREF[i];                                                                   \
        ds += ds > half ? -L : (ds < -half ? L : 0.0);                                             \
        s2 += ds * ds;                                                                             \
    } while (0)
#define OPEN_3D(i, l)                                                                              \
    do {                                                                                           \
        double d2 = 0.0, s2 = 0.0;                                                                 \
        OPEN_3D_C(x, vx, fx, gx, xr, sxr, lo_x, hi_x, 0, i, l);                                    \
        OPEN_3D_C(y, vy, fy, gy, yr, syr, lo_y, hi_y, 1, i, l);                                    \
        OPEN_3D_C(z, vz, fz, gz, zr, szr, lo_z, hi_z, 2, i, l);                                    \
        worst[l] = d2 > worst[l] ? d2 : worst[l];                                                  \
        worst_s[l] = s2 > worst_s[l] ? s2 : worst_s[l];                                            \
    } while (0)

/* The opening pass of 3D on the particles [lo, hi) (lo a multiple of LANES), for constant
 * (noise, closing): named arrays per component and blocks of LANES particles, so the compiler
 * vectorises it (the loop over components through arrays of pointers stayed scalar: 29 % of a 3D
 * bed's step). Writes the block's sums to part, as open_range_2d. */
static inline __attribute__((always_inline)) void open_range_3d(gr_sim *restrict s, const int lo,
                                                                const int hi, const int noise,
                                                                const double mean[3],
                                                                const int closing, const int listck,
                                                                double *restrict part)
{
    const double h = 0.5 * s->dt / s->mass, dt = s->dt, L = s->L, half = 0.5 * s->L;
    const double amp = noise == DRIVE_KICK ? sqrt(2.0 * s->params.D * s->dt) / s->mass : 0.0;
    const double decay = s->drive_c.decay, kick = s->drive_c.kick;
    const double inf = (double)INFINITY;
    const double lo_x = s->period[0] < inf ? 0.0 : -inf, hi_x = lo_x == 0.0 ? L : inf;
    const double lo_y = s->period[1] < inf ? 0.0 : -inf, hi_y = lo_y == 0.0 ? L : inf;
    const double lo_z = s->period[2] < inf ? 0.0 : -inf, hi_z = lo_z == 0.0 ? L : inf;
    double *restrict x = s->x, *restrict y = s->y, *restrict z = s->z;
    double *restrict vx = s->vx, *restrict vy = s->vy, *restrict vz = s->vz;
    const double *restrict fx = s->fx, *restrict fy = s->fy, *restrict fz = s->fz;
    const double *restrict gx = s->gx, *restrict gy = s->gy, *restrict gz = s->gz;
    const double *restrict xr = s->x_ref, *restrict yr = s->y_ref, *restrict zr = s->z_ref;
    /* the sublist's reference (the list's when it is off: then the result is not read) */
    const double *restrict sxr = s->sl_on ? s->xs_ref : xr,
                           *restrict syr = s->sl_on ? s->ys_ref : yr,
                           *restrict szr = s->sl_on ? s->zs_ref : zr;
    const double *restrict g = s->noise;
    double added[LANES] = {0}, wc[LANES] = {0}, wo[LANES] = {0}, sum[LANES] = {0},
           worst[LANES] = {0}, worst_s[LANES] = {0}, drag[LANES] = {0};
    const int full = lo + (hi - lo) / LANES * LANES;
    for (int i0 = lo; i0 < full; i0 += LANES) {
#pragma omp simd
        for (int l = 0; l < LANES; l++) {
            OPEN_3D(i0 + l, l);
        }
    }
#pragma omp simd /* the tail in the same lanes, as in 2D */
    for (int i = full; i < hi; i++) {
        OPEN_3D(i, i - full);
    }
    block_sums(part, noise, added, wc, wo, sum, worst, worst_s, drag);
}
#undef OPEN_3D
#undef OPEN_3D_C

/* Block b of the 3D opening pass, open_range_3d chosen for the run's (noise, closing, listck): one
 * branch per block of GR_BLOCK particles (listck = 0 only on closing steps, as open_step_2d). */
static void open_block_3d(gr_sim *restrict s, const int b, const int noise, const double mean[3],
                          const int closing, const int listck)
{
    const int n = s->n, lo = b * GR_BLOCK, hi = lo + GR_BLOCK < n ? lo + GR_BLOCK : n;
    double *part = s->blk + (size_t)b * GR_BLK_FIELDS;
    if (closing && !listck) {
        switch (noise) {
        case DRIVE_KICK: open_range_3d(s, lo, hi, DRIVE_KICK, mean, 1, 0, part); break;
        case DRIVE_OU: open_range_3d(s, lo, hi, DRIVE_OU, mean, 1, 0, part); break;
        default: open_range_3d(s, lo, hi, 0, mean, 1, 0, part); break;
        }
        return;
    }
    switch (2 * noise + (closing != 0)) {
    case 2 * DRIVE_KICK + 1: open_range_3d(s, lo, hi, DRIVE_KICK, mean, 1, 1, part); break;
    case 2 * DRIVE_KICK: open_range_3d(s, lo, hi, DRIVE_KICK, mean, 0, 1, part); break;
    case 2 * DRIVE_OU + 1: open_range_3d(s, lo, hi, DRIVE_OU, mean, 1, 1, part); break;
    case 2 * DRIVE_OU: open_range_3d(s, lo, hi, DRIVE_OU, mean, 0, 1, part); break;
    case 1: open_range_3d(s, lo, hi, 0, mean, 1, 1, part); break;
    default: open_range_3d(s, lo, hi, 0, mean, 0, 1, part); break;
    }
}

/* The 3D opening pass over blocks of GR_BLOCK particles shared by T threads; the block sums are
 * combined in block order (open_total), so the result does not depend on T. With a driving on
 * T > 1 threads it draws the normals and forms their means first, in the same parallel region (as
 * noise_open_2d_*; mean is then filled in), otherwise draw_noise has run. */
static double open_step_3d(gr_sim *restrict s, const int noise, double mean[3], const int closing,
                           const int listck, open_report *o, const int T)
{
    const int nb = s->nblk;
    if (T > 1) {
        const int sym = symmetrised(s);
#pragma omp parallel num_threads(T)
        {
            double m[3] = {mean[0], mean[1], mean[2]};
            if (noise) {
#pragma omp for schedule(static)
                for (int b = 0; b < nb; b++) {
                    draw_block(s, b, GR_BLOCK, sym);
                }
                noise_mean(s, nb, sym, m); /* every thread, the same numbers */
            }
#pragma omp for schedule(static)
            for (int b = 0; b < nb; b++) {
                open_block_3d(s, b, noise, m, closing, listck);
            }
#pragma omp master
            {
                mean[0] = m[0];
                mean[1] = m[1];
                mean[2] = m[2];
            }
        }
    } else {
        for (int b = 0; b < nb; b++) {
            open_block_3d(s, b, noise, mean, closing, listck);
        }
    }
    return open_total(s, noise, o);
}

int gr_verlet_check_finite(gr_sim *s, gr_error *err)
{
    for (int i = 0; i < s->n; i++) {
        double sum = s->x[i] + s->vx[i] + (s->dim >= 2 ? s->y[i] + s->vy[i] : 0.0) +
                     (s->dim == 3 ? s->z[i] + s->vz[i] : 0.0);
        if (!isfinite(sum)) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: particle %d has a non-finite position or velocity at "
                           "step %lld (t = %.6g s); "
                           "dt = %g s may be too large for k_s = %g N/m (t_c = %.3g s)",
                           i, (long long)s->step, gr_sim_time(s), s->dt, s->cc.k_s, s->cc.t_c);
        }
    }
    return GR_OK;
}

int gr_verlet_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    s->sl_verlet = 1; /* its kernels may scan the contact sublist (core/sublist.c) */
    if (s->nsp) {     /* species: the step of step_poly.c, chosen once per call */
        return gr_verlet_step_poly(s, nsteps, err);
    }
    const bool noise = s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
    const bool bath = s->drive == GR_DRIVE_BATH; /* the driving, chosen once (its own loops) */
    const bool com = s->params.noise_mode == GR_NOISE_COM;
    const double skin_half2 = 0.25 * (s->cutoff - s->d) * (s->cutoff - s->d);
    const int team = gr_team(s); /* threads (results do not depend on it) */
    /* Velocities are synchronised (full step) between calls. Inside a call the closing half kick
     * of one step and the opening half kick of the next use the same forces and are applied as one
     * kick; the last step closes with a half kick. */
    for (int64_t k = 0; k < nsteps; k++) {
        double mean[3] = {0.0, 0.0, 0.0}; /* mean[2]: 3D only */
        const int closing = k > 0; /* velocities are half a kick behind (merged closing kick) */
        const bool com_now = com && s->step > 0 && s->step % s->com_every == 0;
        open_report o = {0};
        if (com_now) {
            if (closing) { /* the reset happens between steps, on synchronised velocities */
                bool finite;
                gr_verlet_book(s, half_kick(s, &finite));
            }
            s->removed_com += gr_remove_com(s);
        }
        if ((noise || bath) && (s->dim == 1 || team == 1)) { /* else drawn in the opening pass */
            draw_noise(s, mean, team);
        }
        const int close_here = closing && !com_now;
        /* with the sublist on, the opening pass measures the displacements since its build only;
         * those since the list's build are bounded from them below */
        const int listck = !(s->sl_on && close_here);
        if (s->dim == 3) { /* spheres: the random force, the bath or none */
            s->injected += open_step_3d(s,
                                        bath    ? DRIVE_OU
                                        : noise ? DRIVE_KICK
                                                : 0,
                                        mean, close_here, listck, &o, team);
            s->diss_drag += o.drag;
        } else if (s->dim == 1 && bath) {
            s->injected += close_here ? open_step_1d(s, DRIVE_OU, 0.0, 1, &o)
                                      : open_step_1d(s, DRIVE_OU, 0.0, 0, &o);
            s->diss_drag += o.drag;
        } else if (s->dim == 1) {
            s->injected += noise ? (close_here ? open_step_1d(s, 1, mean[0], 1, &o)
                                               : open_step_1d(s, 1, mean[0], 0, &o))
                                 : (close_here ? open_step_1d(s, 0, 0.0, 1, &o)
                                               : open_step_1d(s, 0, 0.0, 0, &o));
        } else if (bath) {
            s->injected += open_step_2d(s, DRIVE_OU, mean, close_here, listck, &o, team);
            s->diss_drag += o.drag;
        } else {
            s->injected += noise ? (close_here ? open_step_2d(s, 1, mean, 1, listck, &o, team)
                                               : open_step_2d(s, 1, mean, 0, 1, &o, team))
                                 : (close_here ? open_step_2d(s, 0, mean, 1, listck, &o, team)
                                               : open_step_2d(s, 0, mean, 0, 1, &o, team));
        }
        if (s->omega && !gr_verlet_spin_kicks(s, close_here, 1, &o.work_close, &o.work_open)) {
            o.finite = false;
        }
        if (close_here) {
            gr_verlet_book(s, o.work_close);
        }
        gr_verlet_book(s, o.work_open); /* the last forces, with their shares */
        /* without the pass's measurement: no particle has moved further from the list's reference
         * than the bound, or the exact value (sublist.c) */
        double disp2 = listck ? o.disp2 : gr_sublist_list_moved2(s, o.disp2s, skin_half2);
        if (!o.finite) {
            int rc = gr_verlet_check_finite(s, err); /* names the particle */
            return rc ? rc
                      : GR_FAIL(err, GR_EUNSTABLE, "unstable run: non-finite energy at step %lld",
                                (long long)s->step);
        }
        s->step++;
        if (s->dim >= 2 && (s->params.skin <= 0.0 || disp2 > skin_half2)) {
            int rc = gr_neighbours_build(s, err);
            if (rc) {
                return rc;
            }
            o.disp2s = 0.0; /* the build rebuilt the sublist too (or turned it off) */
        }
        /* the pairs that can touch: the same forces, fewer distances; the opening pass measured
         * the displacements since the sublist's build (1D has none) */
        gr_sublist_refresh_moved(s, o.disp2s);
        int rc = gr_verlet_forces(s, err);
        if (rc) {
            return rc;
        }
    }
    if (nsteps > 0) {
        bool finite;
        gr_verlet_book(s, half_kick(s, &finite));
    }
    return gr_verlet_check_finite(s, err);
}
