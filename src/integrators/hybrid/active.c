/* The active set of a window and the check for misses (docs/hybrid.md, "Active set").
 *
 * Decided from the state at the window start only, never from the window's noise, so the choice
 * cannot bias the noise a particle sees. With sx the standard deviation of a free particle's
 * noise displacement over the window (window_noise.c: sqrt(2 D tau^3 / (3 M^2)) times
 * sqrt(1 + 3/(2m) + 1/(2m^2))) and sv = sqrt(2 D tau)/M that of its velocity:
 *
 * 1. Free pairs: both members of a pair become active when their deterministic paths
 *    x + v t, t in [0, tau], come within d + c sqrt(2) sx (sqrt(2): two independent particles).
 *    Pairs in contact now are included (their distance is already below d).
 * 2. Closure. An active particle can be knocked by its partners, so its velocity is not v.
 *    Active particles are grouped into clusters (1D: runs of consecutive active particles;
 *    2D: union-find over pairs that may touch). Inside a cluster every velocity is bounded by
 *    the cluster's start velocities widened by a fraction GR_HYBRID_SPREAD of their spread
 *    (h->spread: more for a mixture, whose light grains a heavy one can knock beyond that range)
 *    (1D: [vmin, vmax] -> [vmin - f (vmax - vmin), vmax + f (vmax - vmin)]; 2D: speed <= (1 + f)
 *    max |v|; binary collisions keep 1D velocities inside [vmin, vmax] and 2D speeds below
 *    sqrt(2) max |v|), plus c sv for the noise and w0 xi_max for the release of the largest
 *    spring compression in the cluster (w0 = sqrt(k_s / m12)). A free particle that such a cluster
 *    member could reach within d + c sx during the window joins the cluster; two clusters that
 *    could reach each other merge. Repeated until nothing changes.
 *
 * A rule this conservative still cannot exclude everything (chains of soft contacts can push a
 * particle slightly outside the bounds, and the noise has unbounded tails): gr_hy_misses checks
 * every pair with a free member at the window end, and hybrid.c redoes the window with the
 * offenders active. The remaining error is a free pair that overlaps and separates again inside
 * one window: probability below the Gaussian tail at c sigmas. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/hybrid/hy_internal.h"

double gr_hy_noise_sx(const gr_sim *s, const gr_hybrid_state *h, int m)
{
    if (s->params.noise_mode == GR_NOISE_NONE || s->params.D <= 0.0) {
        return 0.0;
    }
    const double tau = m * s->dt, sv = sqrt(2.0 * s->params.D * tau) / h->m_noise;
    if (h->kicks) {
        return sv * (double)(m - m / 2) * s->dt;
    }
    const double dm = (double)m;
    return sqrt(2.0 * s->params.D * tau * tau * tau / (3.0 * h->m_noise * h->m_noise) *
                (1.0 + 1.5 / dm + 0.5 / (dm * dm)));
}

double gr_hy_noise_sv(const gr_sim *s, const gr_hybrid_state *h, int m)
{
    if (s->params.noise_mode == GR_NOISE_NONE || s->params.D <= 0.0) {
        return 0.0;
    }
    return sqrt(2.0 * s->params.D * m * s->dt) / h->m_noise;
}

/* ---- 1D: the ring ------------------------------------------------------------------------- */

static inline double gap_1d(const gr_sim *s, const double *x, int i)
{
    const int j = i + 1 < s->n ? i + 1 : 0;
    return (j ? x[j] - x[i] : x[0] + s->L - x[i]) - gr_pair_d(s, i, j);
}

static void select_1d(gr_sim *s, gr_hybrid_state *h, int m)
{
    const int n = s->n;
    const double tau = m * s->dt, c = h->margin_c, sx = gr_hy_noise_sx(s, h, m),
                 sv = gr_hy_noise_sv(s, h, m);
    const double w0 = h->w0_max, free_margin = c * M_SQRT2 * sx, one_margin = c * sx;
    const double *x = s->x, *v = s->vx;
    double *restrict g = h->c_xi; /* gaps g[i] between i and i + 1 (mod n) */
    uint8_t *act = h->active;
    for (int i = 0; i + 1 < n; i++) {
        g[i] = x[i + 1] - x[i] - s->d;
    }
    g[n - 1] = x[0] + s->L - x[n - 1] - s->d;
    for (int i = 0; i < n; i++) {
        const int j = i + 1 < n ? i + 1 : 0;
        const double rel = (v[j] - v[i]) * tau;
        if (g[i] + (rel < 0.0 ? rel : 0.0) < free_margin) {
            act[i] = act[j] = 1;
        }
    }
#define W(i) ((i) >= n ? (i)-n : (i))
    for (int pass = 0; pass < n; pass++) {
        int f0 = -1;
        for (int i = 0; i < n; i++) {
            if (!act[i]) {
                f0 = i;
                break;
            }
        }
        if (f0 < 0) { /* everybody active: nobody to miss */
            for (int i = 0; i < n; i++) {
                h->env_lo[i] = -(double)INFINITY;
                h->env_hi[i] = (double)INFINITY;
            }
            return;
        }
        /* walk the ring once from the free particle f0 (unwrapped positions f0+1 .. f0+n-1); each
         * run of active particles grows right and left until it reaches nobody new (absorbing
         * the runs it meets); f0 itself (positions f0 and f0+n) is only ever a neighbour */
        int k = f0 + 1;
        while (k < f0 + n) {
            if (!act[W(k)]) {
                k++;
                continue;
            }
            int bk = k, e = k; /* unwrapped ends of the run */
            double vmin = v[W(k)], vmax = v[W(k)], xi = 0.0;
#define ABSORB(pos, gap)                                                                           \
    do {                                                                                           \
        const double g_ = (gap), v_ = v[W(pos)];                                                   \
        xi = -g_ > xi ? -g_ : xi;                                                                  \
        vmin = v_ < vmin ? v_ : vmin;                                                              \
        vmax = v_ > vmax ? v_ : vmax;                                                              \
    } while (0)
            for (int grew = 1; grew;) {
                grew = 0;
                const double widen = h->spread * (vmax - vmin) + c * sv + w0 * xi;
                const double hi = vmax + widen, lo = vmin - widen;
                /* right: positions e+1 .. f0+n-1; position f0+n is f0 */
                if (e + 1 <= f0 + n && !(e + 1 == f0 + n && act[f0])) {
                    const int r = W(e + 1);
                    const double rel = (v[r] - hi) * tau;
                    if (act[r] || g[W(e)] + (rel < 0.0 ? rel : 0.0) < one_margin) {
                        act[r] = 1;
                        if (e + 1 < f0 + n) {
                            ABSORB(e + 1, g[W(e)]);
                            e++;
                            grew = 1;
                        }
                    }
                }
                /* left: positions bk-1 .. f0+1; position f0 is f0 */
                if (bk - 1 >= f0 && !(bk - 1 == f0 && act[f0])) {
                    const int l = W(bk - 1);
                    const double rel = (lo - v[l]) * tau;
                    if (act[l] || g[l] + (rel < 0.0 ? rel : 0.0) < one_margin) {
                        act[l] = 1;
                        if (bk - 1 > f0) {
                            ABSORB(bk - 1, g[l]);
                            bk--;
                            grew = 1;
                        }
                    }
                }
            }
#undef ABSORB
            /* envelopes: the ends of the run face free particles (the last pass's values stand) */
            const double widen = h->spread * (vmax - vmin) + c * sv + w0 * xi;
            for (int q = bk; q <= e; q++) {
                h->env_lo[W(q)] = q == bk ? vmin - widen : -(double)INFINITY;
                h->env_hi[W(q)] = q == e ? vmax + widen : (double)INFINITY;
            }
            k = e + 1;
        }
        /* every run was grown on both sides with its final bounds, absorbing the runs it met; only
         * growth onto f0 (the walk's end) needs another walk from a new free particle */
        if (!act[f0]) {
            return;
        }
    }
#undef W
}

void gr_hy_envelope_miss(gr_sim *s, gr_hybrid_state *h, int p, int side)
{
    const int n = s->n;
    h->forced[p] = 1;
    if (s->dim == 1) {
        h->forced[side > 0 ? (p + 1 < n ? p + 1 : 0) : (p > 0 ? p - 1 : n - 1)] = 1;
        return;
    }
    for (int64_t q = 0; q < h->npairs; q++) {
        if (h->pi[q] == p || h->pj[q] == p) {
            h->forced[h->pi[q]] = h->forced[h->pj[q]] = 1;
        }
    }
}

/* Walls and gravity (2D, 3D; docs/hybrid.md, "Walls and gravity"): a grain whose path over the
 * window along a wall axis, x0 + v t + g t^2 / 2 for t in [0, tau], comes within its radius plus
 * c noise standard deviations of a wall (of the vibrating wall anywhere in its stroke) is active,
 * since only the child's force pass models walls. Gravity is uniform: it moves no pair relative to
 * another, so the pair rule below does not see it. */
static void near_walls(gr_sim *s, gr_hybrid_state *h, int m)
{
    const double tau = m * s->dt, L = s->L;
    const double reach = 0.5 * s->d + h->margin_c * gr_hy_noise_sx(s, h, m);
    const double *pos[3] = {s->x, s->y, s->z}, *vel[3] = {s->vx, s->vy, s->vz};
    uint8_t *act = h->active;
    for (int a = 0; a < s->dim; a++) {
        if (!s->params.walls[a]) {
            continue;
        }
        const double g = s->params.gravity[a];
        const double lo = (s->params.vibrate == a + 1 ? s->params.amplitude : 0.0) + reach,
                     hi = L - reach;
        for (int i = 0; i < s->n; i++) {
            const double x0 = pos[a][i], v = vel[a][i], x1 = x0 + v * tau + 0.5 * g * tau * tau;
            double lowest = fmin(x0, x1), highest = fmax(x0, x1);
            const double te = g != 0.0 ? -v / g : -1.0; /* the apex (or lowest point) */
            if (te > 0.0 && te < tau) {
                const double xe = x0 + 0.5 * v * te;
                lowest = fmin(lowest, xe);
                highest = fmax(highest, xe);
            }
            act[i] |= (uint8_t)((lowest <= lo) | (highest >= hi));
        }
    }
}

int gr_hy_select(gr_sim *s, gr_hybrid_state *h, int m, gr_error *err)
{
    const int n = s->n;
    memcpy(h->active, h->forced, (size_t)n);
    if (s->walls_on && h->margin_c < 1e6) {
        near_walls(s, h, m);
    }
    if (h->margin_c >= 1e6) { /* tests: everybody */
        memset(h->active, 1, (size_t)n);
        for (int i = 0; i < n; i++) {
            h->env_lo[i] = -(double)INFINITY;
            h->env_hi[i] = (double)INFINITY;
        }
    } else if (s->dim == 1) {
        select_1d(s, h, m);
    } else {
        int rc = gr_hy_select_2d(s, h, m, err);
        if (rc) {
            return rc;
        }
    }
    h->n_active = 0;
    for (int i = 0; i < n; i++) {
        if (h->active[i]) {
            h->list[h->n_active++] = i;
        }
    }
    return GR_OK;
}

int gr_hy_misses(gr_sim *s, gr_hybrid_state *h, gr_error *err, int *found)
{
    const int n = s->n;
    const double d = s->d;
    *found = 0;
    if (h->n_active == n) {
        return GR_OK;
    }
    const uint8_t *restrict act = h->active;
    const double *restrict x = s->x, *restrict y = s->y;
    if (s->dim == 1) {
        /* a vectorised test first (misses are rare), then the offenders */
        int any = n > 1 && (!act[n - 1] || !act[0]) && gap_1d(s, x, n - 1) < 0.0;
#pragma omp simd reduction(| : any)
        for (int i = 0; i < n - 1; i++) {
            any |= (x[i + 1] - x[i] - s->d < 0.0) & !(act[i] & act[i + 1]);
        }
        for (int i = 0; i < n && n > 1 && any; i++) {
            const int j = i + 1 < n ? i + 1 : 0;
            if ((!act[i] || !act[j]) && gap_1d(s, x, i) < 0.0) {
                h->forced[i] = h->forced[j] = 1;
                *found = 1;
            }
        }
        return GR_OK;
    }
    if (s->walls_on) { /* a free grain that ended within its radius of a wall: redo it active */
        const double *pos[3] = {s->x, s->y, s->z};
        for (int a = 0; a < s->dim; a++) {
            const double lo = (s->params.vibrate == a + 1 ? s->params.amplitude : 0.0) + 0.5 * d,
                         hi = s->L - 0.5 * d;
            for (int i = 0; i < n && s->params.walls[a]; i++) {
                const double ri = gr_grain_r(s, i) - 0.5 * d; /* 0, or below for a smaller grain */
                if (!act[i] && (pos[a][i] <= lo + ri || pos[a][i] >= hi - ri)) {
                    h->forced[i] = 1;
                    *found = 1;
                }
            }
        }
    }
    /* The candidate list holds every pair closer than rc_pairs at its build; if nobody moved
     * more than (rc_pairs - d)/2 since, it holds every pair closer than d now. */
    const double L = s->L;
    if (!(h->rc_pairs > 0.0 && d + 2.0 * gr_hy_max_disp(s, h) <= h->rc_pairs)) {
        h->rc_pairs = 0.0; /* the list below is not a candidate list */
        int rc = gr_hy_collect_pairs(s, h, d, err);
        if (rc) {
            return rc;
        }
    }
    const double d2 = d * d;
    const int *restrict pi = h->pi, *restrict pj = h->pj;
    int any = 0;
    if (s->dim == 3) {
        const double *restrict z = s->z;
#pragma omp simd reduction(| : any)
        for (int64_t q = 0; q < h->npairs; q++) {
            const int i = pi[q], j = pj[q];
            const double dx = gr_hy_wrap(x[j] - x[i], L), dy = gr_hy_wrap(y[j] - y[i], L),
                         dz = gr_hy_wrap(z[j] - z[i], L);
            any |= (dx * dx + dy * dy + dz * dz < d2) & !(act[i] & act[j]);
        }
    }
#pragma omp simd reduction(| : any)
    for (int64_t q = 0; q < (s->dim == 3 ? 0 : h->npairs); q++) {
        const int i = pi[q], j = pj[q];
        const double dx = gr_hy_wrap(x[j] - x[i], L), dy = gr_hy_wrap(y[j] - y[i], L);
        any |= (dx * dx + dy * dy < d2) & !(act[i] & act[j]);
    }
    for (int64_t q = 0; q < h->npairs && any; q++) {
        const int i = pi[q], j = pj[q];
        if (act[i] && act[j]) {
            continue;
        }
        const double dx = gr_hy_wrap(x[j] - x[i], L), dy = gr_hy_wrap(y[j] - y[i], L),
                     dz = s->dim == 3 ? gr_hy_wrap(s->z[j] - s->z[i], L) : 0.0;
        const double dij = gr_pair_d(s, i, j); /* a mixture's pair: r_i + r_j <= d */
        if (dx * dx + dy * dy + dz * dz < dij * dij) {
            h->forced[i] = h->forced[j] = 1;
            *found = 1;
        }
    }
    return GR_OK;
}
