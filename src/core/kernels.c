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
 * energy that vanishes while the clamp holds F_n at zero is counted here too). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/sim_internal.h"

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

static inline __attribute__((always_inline)) void
pair_loop_2d(gr_sim *restrict s, gr_force_report *restrict r, const int tang, const int clamp)
{
    const int n = s->n;
    const double L = s->L, d = s->d, d2 = d * d;
    const double k = s->cc.k_s, gn = s->cc.gamma_n, gt = s->cc.gamma_t, mu = s->cc.mu;
    const double m12_dt = s->cc.m12 / s->dt;
    const double *restrict x = s->x, *restrict y = s->y, *restrict vx = s->vx, *restrict vy = s->vy;
    double *restrict fx = s->fx, *restrict fy = s->fy, *restrict gx_ = s->gx, *restrict gy_ = s->gy;
    const int *restrict start = s->nl_start, *restrict nl = s->nl_j;
    uint8_t *restrict touching = s->nl_contact;
    double elastic = 0.0, pn = 0.0, pt = 0.0, pf = 0.0, worst = 0.0;
    int64_t fresh = 0;
    int wi = -1, wj = -1;
    memset(fx, 0, sizeof(double) * (size_t)n);
    memset(fy, 0, sizeof(double) * (size_t)n);
    memset(gx_, 0, sizeof(double) * (size_t)n);
    memset(gy_, 0, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; i++) {
        const double xi = x[i], yi = y[i], vxi = vx[i], vyi = vy[i];
        double fxi = 0.0, fyi = 0.0, gxi = 0.0, gyi = 0.0;
        for (int p = start[i]; p < start[i + 1]; p++) {
            const int j = nl[p];
            const double dx = wrap_delta(x[j] - xi, L), dy = wrap_delta(y[j] - yi, L);
            const double r2 = dx * dx + dy * dy;
            if (r2 >= d2) {
                touching[p] = 0;
                continue;
            }
            fresh += !touching[p];
            touching[p] = 1;
            const double dist = sqrt(r2);
            const double inv = 1.0 / dist;
            const double nx = dx * inv, ny = dy * inv, ov = d - dist;
            const double gx = vx[j] - vxi, gy = vy[j] - vyi;
            const double g_n = gx * nx + gy * ny;
            double f_n = k * ov - gn * g_n;
            if (clamp) {
                f_n = f_n > 0.0 ? f_n : 0.0;
            }
            elastic += ov * ov;
            pn -= (f_n - k * ov) * g_n;
            worst = ov > worst ? ov : worst;
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
                        pt += gt * g_t * g_t;
                    }
                } else {
                    const double cap = m12_dt * fabs(g_t), slide = mu * fabs(f_n);
                    const double mag = slide < cap ? slide : cap;
                    f_t = g_t > 0.0 ? -mag : (g_t < 0.0 ? mag : 0.0);
                    pf -= f_t * g_t;
                }
                Fx += f_t * tx;
                Fy += f_t * ty;
                Gx += f_t * tx;
                Gy += f_t * ty;
            }
            fxi -= Fx;
            fyi -= Fy;
            fx[j] += Fx;
            fy[j] += Fy;
            gxi -= Gx;
            gyi -= Gy;
            gx_[j] += Gx;
            gy_[j] += Gy;
        }
        fx[i] += fxi;
        fy[i] += fyi;
        gx_[i] += gxi;
        gy_[i] += gyi;
    }
    if (worst > 0.0) {
        /* find the worst pair only when asked for a diagnosis (rare) */
        for (int i = 0; i < n && wi < 0 && worst > 0.25 * d; i++) {
            for (int p = start[i]; p < start[i + 1]; p++) {
                int j = nl[p];
                double dx = wrap_delta(x[j] - x[i], L), dy = wrap_delta(y[j] - y[i], L);
                if (d - sqrt(dx * dx + dy * dy) >= 0.999 * worst) {
                    wi = i;
                    wj = j;
                    break;
                }
            }
        }
    }
    r->elastic = 0.5 * k * elastic;
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

static void kernel_2d_n(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_NONE, 0); }
static void kernel_2d_n_clamp(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_NONE, 1); }
static void kernel_2d_nt(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_DASHPOT, 0); }
static void kernel_2d_nt_clamp(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_DASHPOT, 1); }
static void kernel_2d_nf(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_FRICTION, 0); }
static void kernel_2d_nf_clamp(gr_sim *s, gr_force_report *r) { pair_loop_2d(s, r, TANG_FRICTION, 1); }

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
