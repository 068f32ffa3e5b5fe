/* The random force over one window of m steps (docs/hybrid.md, "Noise").
 *
 * The soft-sphere step gives a particle the velocity kick a g_k in step k (a = sqrt(2 D dt)/M,
 * g_k standard normal, k = 0..m-1) before its drift, so a particle that touches nobody ends the
 * window with
 *   dv = a S1,  dx = x(tau) - x(0) - v(0) tau = a dt S2,  S1 = sum g_k,  S2 = sum (m - k) g_k,
 * jointly Gaussian with covariance G = [[m, m(m+1)/2], [m(m+1)/2, m(m+1)(2m+1)/6]]. We draw
 * (S1, S2) exactly from two normals (g1, g2) by the Cholesky factor of G:
 *   S1 = sqrt(m) g1,  S2 = (m+1) sqrt(m)/2 g1 + sqrt(m (m+1)(m-1)/12) g2,
 * i.e. dv = sqrt(2 D tau)/M g1 and dx = (m+1) dt/2 dv + sqrt(D tau^3/6)/M sqrt(1 - 1/m^2) g2.
 * This is include/granule/free_flight.h's exact random-acceleration sampler with tau/2 replaced
 * by (m+1) dt/2 and a factor sqrt(1 - 1/m^2) on g2: the law of the Verlet kicks themselves, so
 * Var(dx) is 2 D tau^3/(3 M^2) (1 + 3/(2m) + 1/(2m^2)) instead of the continuum's
 * 2 D tau^3/(3 M^2), and the two agree as m = tau/dt grows (free_flight.h is the m -> infinity
 * limit). Matching the discrete law makes a free leap exactly equal in law to m soft-sphere steps.
 *
 * Active particles need the kicks of every step. They are drawn as m fresh normals g_k and then
 * conditioned on the particle's (S1, S2) (a Gaussian bridge):
 *   g'_k = g_k + l1 + l2 (m - k),  (l1, l2) = G^-1 ((S1, S2) - (sum g_k, sum (m - k) g_k)),
 * which is again exactly i.i.d. standard normal in law and reproduces (S1, S2). So each particle's
 * noise in a window is one fixed path, a pure function of (seed, window start, particle id),
 * whether the particle is leaped or stepped: an active particle that touches nobody ends exactly
 * where its leap would have put it, and redoing a window with a larger active set (rollback)
 * replays the same noise, so the redo is not biased by what made it necessary.
 *
 * Counters (stream GR_STREAM_HYBRID, include/granule/noise.h): the free-flight normals of
 * particle p, component c use step = window start | w << 62 with w = 0, 1, 3 for x, y, z (not 2:
 * 2 << 62 is the kicks' flag), id = p, components 0 and 1; the raw kicks use
 * step = window start | 1 << 63, id = p m + k, component c.
 *
 * Gravity g (with walls, 2D and 3D): a constant force, which kick-drift-kick integrates exactly, so a
 * leap adds g tau to v and g tau^2 / 2 to x, and leaves the force M g; the energy a leap books as
 * injected is the change of kinetic plus potential energy (potential -M g . x),
 * M [dv . (v + dv / 2) + g . (tau dv - dx)], dx the noise's part of the displacement (it is 0
 * without gravity, so those runs are as before).
 *
 * free_flight = kicks: instead of acting every step the noise of a window is one velocity kick
 * dv = sqrt(2 D tau)/M g1 at step m/2 (so dx = (m - m/2) dt dv); active particles get the same
 * single kick, so again leaping and stepping agree. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/noise.h"
#include "integrators/hybrid/hy_internal.h"

#define KICK_FLAG (UINT64_C(1) << 63)

static inline int has_noise(const gr_sim *s)
{
    return s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
}

void gr_hy_draw_window(const gr_sim *s, gr_hybrid_state *h, int64_t start)
{
    if (!has_noise(s)) {
        return;
    }
    for (int c = 0; c < s->dim; c++) {
        /* per = 2: out[p * 2 + {0,1}] for particle p; components stored next to each other */
        double *tmp = h->tmp;
        uint64_t step = (uint64_t)start | ((uint64_t)(c == 2 ? 3 : c) << 62);
        if (s->dim == 1) {
            gr_noise_normals(s->params.seed, GR_STREAM_HYBRID, step, 0, s->n, 2, h->ff);
        } else {
            gr_noise_normals(s->params.seed, GR_STREAM_HYBRID, step, 0, s->n, 2, tmp);
            for (int p = 0; p < s->n; p++) {
                h->ff[(p * s->dim + c) * 2] = tmp[2 * p];
                h->ff[(p * s->dim + c) * 2 + 1] = tmp[2 * p + 1];
            }
        }
    }
}

/* (S1, S2) of particle p, component c, in units of the kick a, from its two normals. */
static inline void sums(const gr_hybrid_state *h, int dim, int m, int p, int c, double *s1,
                        double *s2)
{
    const double g1 = h->ff[(p * dim + c) * 2], g2 = h->ff[(p * dim + c) * 2 + 1];
    const double dm = (double)m, r = sqrt(dm);
    *s1 = r * g1;
    *s2 = 0.5 * (dm + 1.0) * r * g1 + sqrt(dm * (dm + 1.0) * (dm - 1.0) / 12.0) * g2;
}

void gr_hy_free_increment(const gr_sim *s, const gr_hybrid_state *h, int m, int p, int c,
                          double *dv, double *dx)
{
    if (!has_noise(s)) {
        *dv = *dx = 0.0;
        return;
    }
    const double a = sqrt(2.0 * s->params.D * s->dt) * (s->inv_m ? s->inv_m[p] : 1.0 / s->mass);
    double s1, s2;
    sums(h, s->dim, m, p, c, &s1, &s2);
    *dv = a * s1;
    *dx = h->kicks ? *dv * (double)(m - m / 2) * s->dt : a * s->dt * s2;
}

/* gr_hy_leap_free for a mixture (species lists): each grain's noise increments scaled by its own
 * 1 / m_i and its weight m_i g, component by component (not the vectorised lanes of one mass);
 * returns the kinetic energy the noise and gravity's work added, sum_i m_i (...). */
static double leap_free_species(gr_sim *s, const gr_hybrid_state *h, int m)
{
    const int n = s->n, dim = s->dim, noise = has_noise(s);
    const double tau = m * s->dt, L = s->L, dm = (double)m;
    const double a = noise ? sqrt(2.0 * s->params.D * s->dt) : 0.0; /* times 1 / m_i below */
    const double c1 = a * sqrt(dm);
    const double c21 =
        h->kicks ? c1 * (double)(m - m / 2) * s->dt : a * s->dt * 0.5 * (dm + 1.0) * sqrt(dm);
    const double c22 = h->kicks ? 0.0 : a * s->dt * sqrt(dm * (dm + 1.0) * (dm - 1.0) / 12.0);
    double *const pos[3] = {s->x, s->y, s->z}, *const vel[3] = {s->vx, s->vy, s->vz},
                  *const frc[3] = {s->fx, s->fy, s->fz}, *const gnc[3] = {s->gx, s->gy, s->gz};
    double added = 0.0;
    for (int p = 0; p < n; p++) {
        if (h->active[p]) {
            continue;
        }
        const double im = s->inv_m[p];
        double part = 0.0;
        for (int c = 0; c < dim; c++) {
            const double g = s->params.gravity[c], g1 = h->ff[(p * dim + c) * 2],
                         g2 = h->ff[(p * dim + c) * 2 + 1], u = vel[c][p];
            const double dv = im * c1 * g1, e = im * (c21 * g1 + c22 * g2);
            double xn = pos[c][p] + u * tau + e + 0.5 * g * tau * tau;
            if (dim >= 2) { /* the ring (1D) keeps unwrapped positions */
                xn += xn < 0.0 ? L : (xn >= L ? -L : 0.0);
            }
            part += dv * (u + 0.5 * dv) + g * (tau * dv - e);
            pos[c][p] = xn;
            vel[c][p] = u + dv + g * tau;
            frc[c][p] = s->mass_i[p] * g;
            gnc[c][p] = 0.0;
        }
        added += s->mass_i[p] * part;
    }
    return added;
}

double gr_hy_leap_free(gr_sim *s, gr_hybrid_state *h, int m)
{
    const int n = s->n, dim = s->dim, noise = has_noise(s);
    const double tau = m * s->dt, L = s->L, M = s->mass;
    const double a = noise ? sqrt(2.0 * s->params.D * s->dt) / M : 0.0, dm = (double)m;
    /* dv = a S1, dx = a dt S2 with (S1, S2) from sums(); kicks: dx = (m - m/2) dt dv */
    const double c1 = a * sqrt(dm);
    const double c21 =
        h->kicks ? c1 * (double)(m - m / 2) * s->dt : a * s->dt * 0.5 * (dm + 1.0) * sqrt(dm);
    const double c22 = h->kicks ? 0.0 : a * s->dt * sqrt(dm * (dm + 1.0) * (dm - 1.0) / 12.0);
    const uint8_t *act = h->active;
    const double *ff = h->ff;
    /* gravity (0 without): velocity g tau, displacement g tau^2 / 2, the force M g */
    const double gxa = s->params.gravity[0], gya = s->params.gravity[1], gza = s->params.gravity[2];
    const double hx = 0.5 * gxa * tau * tau, hy = 0.5 * gya * tau * tau, hz = 0.5 * gza * tau * tau;
    const double mgx = M * gxa, mgy = M * gya, mgz = M * gza;
    if (s->inv_m) {
        return leap_free_species(s, h, m);
    }
    /* Every particle in 8 fixed lanes, the active ones left as they are, so the loop vectorises;
     * h->ff is zero without noise (never drawn). Positions stay in [0, L) by one conditional
     * shift (a leap is much shorter than L). */
    double adl[8] = {0};
    double *restrict x = s->x, *restrict vx = s->vx, *restrict fx = s->fx, *restrict gx = s->gx;
    double *restrict y = s->y, *restrict vy = s->vy, *restrict fy = s->fy, *restrict gy = s->gy;
    for (int p0 = 0; p0 < n; p0 += 8) {
        const int lanes = n - p0 < 8 ? n - p0 : 8;
        if (dim == 1) {
#pragma omp simd
            for (int l = 0; l < lanes; l++) {
                const int p = p0 + l, leap = !act[p];
                const double g1 = ff[2 * p], g2 = ff[2 * p + 1], v0 = vx[p];
                const double dv = c1 * g1, xn = x[p] + v0 * tau + (c21 * g1 + c22 * g2);
                adl[l] += leap ? dv * (v0 + 0.5 * dv) : 0.0;
                x[p] = leap ? xn : x[p];
                vx[p] = leap ? v0 + dv : v0;
                fx[p] = leap ? 0.0 : fx[p];
                gx[p] = leap ? 0.0 : gx[p];
            }
        } else if (dim == 3) {
            double *restrict z = s->z, *restrict vz = s->vz, *restrict fz = s->fz,
                             *restrict gz = s->gz;
#pragma omp simd
            for (int l = 0; l < lanes; l++) {
                const int p = p0 + l, leap = !act[p];
                const double *g = ff + 6 * p; /* (g1, g2) of x, y, z */
                const double ux = vx[p], uy = vy[p], uz = vz[p], dvx = c1 * g[0], dvy = c1 * g[2],
                             dvz = c1 * g[4];
                const double ex = c21 * g[0] + c22 * g[1], ey = c21 * g[2] + c22 * g[3],
                             ez = c21 * g[4] + c22 * g[5];
                double xn = x[p] + ux * tau + ex + hx, yn = y[p] + uy * tau + ey + hy,
                       zn = z[p] + uz * tau + ez + hz;
                xn += xn < 0.0 ? L : (xn >= L ? -L : 0.0);
                yn += yn < 0.0 ? L : (yn >= L ? -L : 0.0);
                zn += zn < 0.0 ? L : (zn >= L ? -L : 0.0);
                adl[l] += leap ? dvx * (ux + 0.5 * dvx) + dvy * (uy + 0.5 * dvy) +
                                     dvz * (uz + 0.5 * dvz) +
                                     (gxa * (tau * dvx - ex) + gya * (tau * dvy - ey) +
                                      gza * (tau * dvz - ez))
                               : 0.0;
                x[p] = leap ? xn : x[p];
                y[p] = leap ? yn : y[p];
                z[p] = leap ? zn : z[p];
                vx[p] = leap ? ux + dvx + gxa * tau : ux;
                vy[p] = leap ? uy + dvy + gya * tau : uy;
                vz[p] = leap ? uz + dvz + gza * tau : uz;
                fx[p] = leap ? mgx : fx[p];
                fy[p] = leap ? mgy : fy[p];
                fz[p] = leap ? mgz : fz[p];
                gx[p] = leap ? 0.0 : gx[p];
                gy[p] = leap ? 0.0 : gy[p];
                gz[p] = leap ? 0.0 : gz[p];
            }
        } else {
#pragma omp simd
            for (int l = 0; l < lanes; l++) {
                const int p = p0 + l, leap = !act[p];
                const double g1 = ff[4 * p], g2 = ff[4 * p + 1], h1 = ff[4 * p + 2],
                             h2 = ff[4 * p + 3];
                const double ux = vx[p], uy = vy[p], dvx = c1 * g1, dvy = c1 * h1;
                const double ex = c21 * g1 + c22 * g2, ey = c21 * h1 + c22 * h2;
                double xn = x[p] + ux * tau + ex + hx, yn = y[p] + uy * tau + ey + hy;
                xn += xn < 0.0 ? L : (xn >= L ? -L : 0.0);
                yn += yn < 0.0 ? L : (yn >= L ? -L : 0.0);
                adl[l] += leap ? dvx * (ux + 0.5 * dvx) + dvy * (uy + 0.5 * dvy) +
                                     (gxa * (tau * dvx - ex) + gya * (tau * dvy - ey))
                               : 0.0;
                x[p] = leap ? xn : x[p];
                y[p] = leap ? yn : y[p];
                vx[p] = leap ? ux + dvx + gxa * tau : ux;
                vy[p] = leap ? uy + dvy + gya * tau : uy;
                fx[p] = leap ? mgx : fx[p];
                fy[p] = leap ? mgy : fy[p];
                gx[p] = leap ? 0.0 : gx[p];
                gy[p] = leap ? 0.0 : gy[p];
            }
        }
    }
    double added = 0.0;
    for (int l = 0; l < 8; l++) {
        added += adl[l];
    }
    return M * added;
}

/* sum g_k and sum (m - k) g_k of g_k = raw[k * stride], k < m, in four partial sums (independent
 * chains, the same result on every machine). The weights m - k are whole numbers, exact in double
 * whether computed from k or counted down. Inlined with stride a constant. */
static inline __attribute__((always_inline)) void raw_sums(const double *restrict raw,
                                                           const int stride, int m, double a1[4],
                                                           double a2[4])
{
    const double dm = (double)m;
    for (int u = 0; u < 4; u++) {
        a1[u] = a2[u] = 0.0;
    }
    int k = 0;
    for (; k + 4 <= m; k += 4) {
        const double w = dm - (double)k;
        for (int u = 0; u < 4; u++) {
            const double gk = raw[(k + u) * stride];
            a1[u] += gk;
            a2[u] += (w - (double)u) * gk;
        }
    }
    for (; k < m; k++) {
        const double gk = raw[k * stride];
        a1[0] += gk;
        a2[0] += (dm - k) * gk;
    }
}

int gr_hy_active_kicks(const gr_sim *s, gr_hybrid_state *h, int64_t start, int m, gr_error *err)
{
    const int dim = s->dim, na = h->n_active, md = m * dim;
    const int64_t need = (int64_t)md * na;
    if (need > h->cap_kick) {
        double *k = realloc(h->kick, sizeof(double) * (size_t)need);
        if (!k) {
            return GR_FAIL(err, GR_ENOMEM, "hybrid: out of memory for %lld kicks", (long long)need);
        }
        h->kick = k;
        h->cap_kick = need;
    }
    if (need == 0) {
        return GR_OK;
    }
    if (!has_noise(s)) {
        h->kick_amp = 0.0;
        memset(h->kick, 0, sizeof(double) * (size_t)need);
        memset(h->lam, 0, sizeof(double) * 2 * (size_t)dim * (size_t)na);
        return GR_OK;
    }
    /* a mixture: the child scales the kicks by each grain's 1 / m_i (child.c) */
    h->kick_amp = sqrt(2.0 * s->params.D * s->dt) / (s->inv_m ? 1.0 : s->mass);
    const double dm = (double)m;
    const double G11 = dm, G12 = 0.5 * dm * (dm + 1.0),
                 G22 = dm * (dm + 1.0) * (2.0 * dm + 1.0) / 6.0;
    const double det = G11 * G22 - G12 * G12;
    const double r_m = sqrt(dm), c2 = sqrt(dm * (dm + 1.0) * (dm - 1.0) / 12.0);
    const int single = h->kicks || m == 1; /* one kick carries all of the window's noise */
    int q0 = 0;
    while (q0 < na) {
        /* a run of consecutive particle ids: their raw kicks (ids p m + k) are one contiguous draw,
         * stored particle-major: raw[(q m + k) dim + c] */
        int q1 = q0 + 1;
        while (q1 < na && h->list[q1] == h->list[q1 - 1] + 1) {
            q1++;
        }
        double *raw = h->kick + (size_t)q0 * md;
        if (!single) {
            gr_noise_normals(s->params.seed, GR_STREAM_HYBRID, (uint64_t)start | KICK_FLAG,
                             (uint32_t)((int64_t)h->list[q0] * m), (q1 - q0) * m, dim, raw);
        } else {
            memset(raw, 0, sizeof(double) * (size_t)(q1 - q0) * (size_t)md);
        }
        for (int q = q0; q < q1; q++, raw += md) {
            const int p = h->list[q];
            for (int c = 0; c < dim; c++) {
                const double g1 = h->ff[(p * dim + c) * 2], g2 = h->ff[(p * dim + c) * 2 + 1];
                const double t1 = r_m * g1, t2 = 0.5 * (dm + 1.0) * r_m * g1 + c2 * g2;
                double *lam = h->lam + 2 * ((size_t)q * dim + c);
                if (single) {
                    raw[(m / 2) * dim + c] = t1;
                    lam[0] = lam[1] = 0.0;
                    continue;
                }
                double a1[4], a2[4];
                if (dim == 1) { /* contiguous: the loop vectorises */
                    raw_sums(raw, 1, m, a1, a2);
                } else {
                    raw_sums(raw + c, dim, m, a1, a2);
                }
                const double r1 = t1 - ((a1[0] + a1[1]) + (a1[2] + a1[3]));
                const double r2 = t2 - ((a2[0] + a2[1]) + (a2[2] + a2[3]));
                lam[0] = (G22 * r1 - G12 * r2) / det;
                lam[1] = (G11 * r2 - G12 * r1) / det;
            }
        }
        q0 = q1;
    }
    return GR_OK;
}
