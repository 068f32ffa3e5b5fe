/* The hybrid integrator: windows, rollbacks, the centre-of-mass correction, the ledger
 * (docs/hybrid.md).
 *
 * One window of m steps (tau = m dt) covers steps [k m, (k + 1) m); the end of a gr_sim_step call
 * or a com reset cuts it short (then the next window runs to the next multiple of m):
 *   1. choose the active set from the state now (active.c; never from this window's noise);
 *   2. draw every particle's noise for the window (window_noise.c): free particles leap the
 *      window exactly (velocity and position increments with the law of m Verlet kicks on a free
 *      particle), active ones are stepped m times by the soft-sphere scheme (child.c) with kicks
 *      bridged to the same increments;
 *   3. misses: a pair with a free member that overlaps (1D: or crossed) at the end -> restore the
 *      window's start state, make that pair active, redo. The noise is a pure function of the
 *      counters, so the redo replays the same noise paths (no bias from the rejection);
 *   4. symmetrised noise (2.18), see below; then s->step += m.
 *
 * Symmetrised noise. The thesis subtracts the mean random force over all particles from every
 * particle every step (2.18). That is the same uniform acceleration A(t) = -(1/N) sum_i eta_i / M
 * for every particle. Contact forces depend only on relative positions and velocities, which a
 * uniform acceleration does not change, so the symmetrised trajectories are the raw-noise ones
 * seen from the frame that moves with the centre of mass: x_i^sym(t) = x_i(t) - X(t),
 * v_i^sym(t) = v_i(t) - V(t), where V and X are the centre-of-mass velocity and displacement
 * the raw noise produced (total momentum is zero at the window start and contacts conserve it).
 * So we integrate with raw noise and, at each window end, subtract V from every velocity and X
 * from every position. The kinetic energy this removes, N M V^2 / 2 (exactly, since
 * sum v_i = N V), is subtracted from `injected`: the injected energy is then the work of the
 * symmetrised force, as for Verlet (dim D/M (1 - 1/N) per particle and second on average), and
 * the ledger closes as before. The dissipation is the same in both frames because internal
 * forces sum to zero (sum G_i . V = 0).
 * com mode: raw noise, and the centre-of-mass velocity is removed at the window ends that fall on
 * multiples of com_interval (windows are cut there), booked in removed_com as for Verlet. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/noise.h"
#include "integrators/hybrid/hy_internal.h"

static double *dalloc(int n)
{
    size_t bytes = ((sizeof(double) * (size_t)(n > 0 ? n : 1)) + 63) & ~(size_t)63;
    double *p = aligned_alloc(64, bytes);
    if (p) {
        memset(p, 0, bytes);
    }
    return p;
}

void gr_hybrid_free(gr_sim *s)
{
    gr_hybrid_state *h = s ? gr_hy(s) : NULL;
    if (!h) {
        return;
    }
    gr_sim_free(h->child);
    double *d[] = {h->x0,  h->y0,   h->vx0,  h->vy0,  h->fx0,    h->fy0,    h->gx0,
                   h->gy0, h->c_lo, h->c_hi, h->c_xi, h->env_lo, h->env_hi, h->env_pack,
                   h->ff,  h->kick, h->tmp,  h->lam,  h->xl,     h->yl,     h->z0,
                   h->vz0, h->fz0,  h->gz0,  h->zl,   h->w0,     h->t0,     h->bath_g};
    for (size_t k = 0; k < sizeof d / sizeof d[0]; k++) {
        free(d[k]);
    }
    free(h->active);
    free(h->forced);
    free(h->list);
    free(h->env_list);
    free(h->uf);
    free(h->pi);
    free(h->pj);
    free(h->adj_start);
    free(h->adj);
    free(h->mem_head);
    free(h->mem_tail);
    free(h->mem_next);
    free(h->mem_size);
    free(h->queue);
    free(h->inq);
    free(h->speed);
    free(h->cell_head);
    free(h->cell_next);
    free(h->sorted);
    free(h->xs);
    free(h->ys);
    free(h->zs);
    free(h);
    s->integrator_state = NULL;
}

int gr_hybrid_init(gr_sim *s, gr_error *err)
{
    const gr_sim_params *sc = &s->params;
    const double tau = sc->kick_interval, ratio = tau / s->dt;
    /* a window left at its default is the nearest whole number of steps (dt follows the contact
     * time, so it rarely divides 1e-4 s); a window the scene gives must be one */
    const int64_t m = sc->kick_interval_default && ratio < 0.5 ? 1 : llround(ratio);
    if (!(m >= 1) || (!sc->kick_interval_default && fabs(ratio - (double)m) > 1e-6 * ratio)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [integrator] kick_interval = %g s must be a whole multiple (>= 1) of "
            "dt = %g s for kind = hybrid "
            "(e.g. %g or %g s; left unset, the default 1e-4 s is rounded to whole steps)",
            sc->source, tau, s->dt, fmax(1.0, floor(ratio)) * s->dt,
            fmax(1.0, ceil(ratio)) * s->dt);
    }
    if ((double)m * (double)s->n > 4294967295.0 || m > 1000000) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kick_interval = %g s is %lld steps; kind = hybrid needs N "
                       "x steps per window <= 2^32 "
                       "and at most 1e6 steps per window (use kick_interval <= %g s)",
                       sc->source, tau, (long long)m, fmin(1e6, 4294967295.0 / s->n) * s->dt);
    }
    const bool noise = sc->noise_mode != GR_NOISE_NONE && sc->D > 0.0;
    if (s->walls_on && s->dim == 1) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kind = hybrid runs walls and gravity in 2D and 3D (its 1D "
                       "active set is built on the periodic ring); allowed in 1D: verlet or event",
                       sc->source);
    }
    if (s->walls_on && noise && sc->noise_mode == GR_NOISE_SYMMETRISED) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [noise] mode = symmetrised with walls and kind = hybrid: the hybrid "
            "symmetrises by moving to the centre-of-mass frame, which would carry grains "
            "through the walls; allowed with walls: mode = com or none",
            sc->source);
    }
    if (s->nsp >= 1) {
        /* a mixture (docs/hybrid.md, "Mixtures"): species lists or a radius distribution, with
         * noise whose kicks leave the pairs' relative motion alone (com or none) */
        const char *what = noise && sc->noise_mode == GR_NOISE_SYMMETRISED
                               ? "[noise] mode = symmetrised (subtracting the mean force "
                                 "accelerates grains of unequal mass unequally, which the "
                                 "hybrid's centre-of-mass frame cannot represent)"
                               : NULL;
        if (what) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: %s: not available with [species] and kind = hybrid; the hybrid "
                           "runs mixtures with [noise] mode = com or none (docs/hybrid.md, "
                           "\"Mixtures\")",
                           sc->source, what);
        }
    }
    gr_hybrid_state *h = calloc(1, sizeof *h);
    if (!h) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    s->integrator_state = h;
    h->m = (int)m;
    h->m_noise = s->mass;
    h->w0_max = s->cc.w0;
    double m_max = s->mass;
    for (int i = 0; s->mass_i && i < s->n; i++) { /* a mixture: bounds over its grains */
        h->m_noise = fmin(h->m_noise, s->mass_i[i]);
        m_max = fmax(m_max, s->mass_i[i]);
    }
    h->spread = GR_HYBRID_SPREAD + (s->mass_i ? (m_max - h->m_noise) / (m_max + h->m_noise) : 0.0);
    for (int ab = 0; s->cc_pair && ab < s->nsp * s->nsp; ab++) {
        h->w0_max = fmax(h->w0_max, s->cc_pair[ab].w0);
    }
    if (s->rad && !s->cc_pair) {
        /* a radius distribution: each pair's law is the reference's scaled (gr_size_scaled), w0 by
         * sqrt(sk m_ref / M) with the stiffness factor sk = (R / r_ref)^(a - 1); bounded by the
         * lightest pair (M = m_min / 2) and the largest sk over R in [r_min, r_max] / 2 */
        double r_min = s->rad[0], r_max = s->rad[0];
        for (int i = 1; i < s->n; i++) {
            r_min = fmin(r_min, s->rad[i]);
            r_max = fmax(r_max, s->rad[i]);
        }
        const double a = s->cc.pow_a;
        const double sk = a == 1.0 ? 1.0
                                   : fmax(pow(0.5 * r_min / s->cont_r, a - 1.0),
                                          pow(0.5 * r_max / s->cont_r, a - 1.0));
        h->w0_max = fmax(h->w0_max, s->cc.w0 * sqrt(sk * s->cont_m12 / (0.5 * h->m_noise)));
    }
    h->margin_c = GR_HYBRID_MARGIN_SIGMAS;
    h->kicks = sc->free_flight == GR_FREE_FLIGHT_KICKS;
    const int n = s->n, dim = s->dim;
    h->bath = s->drive == GR_DRIVE_BATH; /* gr_sim set D = 0: the bath replaces the random force */
    if (h->bath) {
        h->bath_g = dalloc(dim * n);
        if (!h->bath_g) {
            return GR_FAIL(err, GR_ENOMEM, "hybrid: out of memory for %d particles", n);
        }
        /* the kick's grain: the first species (a distribution: the mean mass), as in verlet */
        h->bath_m1 = !s->mass_i || sc->size_distribution ? s->mass : sc->species_mass[0];
    }
    h->x0 = dalloc(n);
    h->vx0 = dalloc(n);
    h->fx0 = dalloc(n);
    h->gx0 = dalloc(n);
    if (dim >= 2) {
        h->y0 = dalloc(n);
        h->vy0 = dalloc(n);
        h->fy0 = dalloc(n);
        h->gy0 = dalloc(n);
        h->xl = dalloc(n);
        h->yl = dalloc(n);
    }
    if (dim == 3) {
        h->z0 = dalloc(n);
        h->vz0 = dalloc(n);
        h->fz0 = dalloc(n);
        h->gz0 = dalloc(n);
        h->zl = dalloc(n);
    }
    double *w[3], *t[3];
    const int nw = gr_hy_spins(s, w, t);
    if (nw) {
        h->w0 = dalloc(nw * n);
        h->t0 = dalloc(nw * n);
    }
    h->c_lo = dalloc(n);
    h->c_hi = dalloc(n);
    h->c_xi = dalloc(n);
    h->env_lo = dalloc(n);
    h->env_hi = dalloc(n);
    h->env_pack = dalloc(5 * n);
    h->ff = dalloc(2 * dim * n);
    h->lam = dalloc(2 * dim * n);
    h->tmp = dalloc(2 * n);
    h->active = calloc((size_t)n, 1);
    h->forced = calloc((size_t)n, 1);
    h->list = malloc(sizeof(int) * (size_t)n);
    h->env_list = malloc(sizeof(int) * (size_t)n);
    h->uf = malloc(sizeof(int) * (size_t)n);
    h->cell_next = malloc(sizeof(int) * (size_t)n);
    if (!h->x0 || !h->vx0 || !h->fx0 || !h->gx0 ||
        (dim >= 2 && (!h->y0 || !h->vy0 || !h->fy0 || !h->gy0 || !h->xl || !h->yl)) ||
        (dim == 3 && (!h->z0 || !h->vz0 || !h->fz0 || !h->gz0 || !h->zl)) || !h->c_lo || !h->c_hi ||
        !h->c_xi || !h->env_lo || !h->env_hi || !h->env_pack || !h->ff || !h->lam || !h->tmp ||
        !h->active || !h->forced || !h->list || !h->env_list || !h->uf || !h->cell_next ||
        (nw && (!h->w0 || !h->t0))) {
        return GR_FAIL(err, GR_ENOMEM, "hybrid: out of memory for %d particles", n);
    }
    int rc = gr_hy_child_create(s, h, err);
    if (rc) {
        return rc;
    }
    char soft[sizeof s->kernel_name];
    snprintf(soft, sizeof soft, "%s", s->kernel_name); /* the soft-sphere kernel the child runs */
    snprintf(s->kernel_name, sizeof s->kernel_name, "hybrid-%dd-%s(window %g s)/%.100s", dim,
             h->bath    ? "bath"
             : h->kicks ? "kicks"
                        : "exact",
             (double)m * s->dt, soft);
    return GR_OK;
}

void gr_hybrid_set_margin(gr_sim *s, double sigmas)
{
    if (gr_hy(s)) {
        gr_hy(s)->margin_c = sigmas;
    }
}

int gr_sim_hybrid_stats(const gr_sim *s, gr_hybrid_stats *st)
{
    memset(st, 0, sizeof *st);
    const gr_hybrid_state *h = gr_hy(s);
    if (!h) {
        return 0;
    }
    st->windows = h->windows;
    st->rollbacks = h->rollbacks;
    st->steps = h->steps;
    st->active_steps = h->active_steps;
    st->active_fraction = h->steps > 0 ? (double)h->active_steps / ((double)h->steps * s->n) : 0.0;
    st->margin_sigmas = h->margin_c;
    st->window = h->m * s->dt;
    return 1;
}

/* The ledger and counters a window changes. */
typedef struct saved {
    double injected, diss_n, diss_t, diss_f, removed_com, elastic, share[3];
    double wall_work, wall_impulse[6];
    int64_t collisions, rebuilds;
    gr_force_report last;
} saved;

static void save(gr_sim *s, gr_hybrid_state *h, saved *v)
{
    const size_t b = sizeof(double) * (size_t)s->n;
    memcpy(h->x0, s->x, b);
    memcpy(h->vx0, s->vx, b);
    memcpy(h->fx0, s->fx, b);
    memcpy(h->gx0, s->gx, b);
    if (s->dim >= 2) {
        memcpy(h->y0, s->y, b);
        memcpy(h->vy0, s->vy, b);
        memcpy(h->fy0, s->fy, b);
        memcpy(h->gy0, s->gy, b);
    }
    if (s->dim == 3) {
        memcpy(h->z0, s->z, b);
        memcpy(h->vz0, s->vz, b);
        memcpy(h->fz0, s->fz, b);
        memcpy(h->gz0, s->gz, b);
    }
    double *w[3], *t[3];
    for (int c = 0, nw = gr_hy_spins(s, w, t); c < nw; c++) {
        memcpy(h->w0 + (size_t)c * s->n, w[c], b);
        memcpy(h->t0 + (size_t)c * s->n, t[c], b);
    }
    *v = (saved){.injected = s->injected,
                 .diss_n = s->diss_n,
                 .diss_t = s->diss_t,
                 .diss_f = s->diss_f,
                 .removed_com = s->removed_com,
                 .elastic = s->elastic,
                 .wall_work = s->wall_work,
                 .collisions = s->collisions,
                 .rebuilds = s->rebuilds,
                 .last = s->last};
    memcpy(v->share, s->share, sizeof v->share);
    memcpy(v->wall_impulse, s->wall_impulse, sizeof v->wall_impulse);
}

static void restore(gr_sim *s, gr_hybrid_state *h, const saved *v)
{
    const size_t b = sizeof(double) * (size_t)s->n;
    memcpy(s->x, h->x0, b);
    memcpy(s->vx, h->vx0, b);
    memcpy(s->fx, h->fx0, b);
    memcpy(s->gx, h->gx0, b);
    if (s->dim >= 2) {
        memcpy(s->y, h->y0, b);
        memcpy(s->vy, h->vy0, b);
        memcpy(s->fy, h->fy0, b);
        memcpy(s->gy, h->gy0, b);
    }
    if (s->dim == 3) {
        memcpy(s->z, h->z0, b);
        memcpy(s->vz, h->vz0, b);
        memcpy(s->fz, h->fz0, b);
        memcpy(s->gz, h->gz0, b);
    }
    double *w[3], *t[3];
    for (int c = 0, nw = gr_hy_spins(s, w, t); c < nw; c++) {
        memcpy(w[c], h->w0 + (size_t)c * s->n, b);
        memcpy(t[c], h->t0 + (size_t)c * s->n, b);
    }
    s->injected = v->injected;
    s->diss_n = v->diss_n;
    s->diss_t = v->diss_t;
    s->diss_f = v->diss_f;
    s->removed_com = v->removed_com;
    s->elastic = v->elastic;
    s->wall_work = v->wall_work;
    memcpy(s->wall_impulse, v->wall_impulse, sizeof s->wall_impulse);
    s->collisions = v->collisions;
    s->rebuilds = v->rebuilds;
    s->last = v->last;
    memcpy(s->share, v->share, sizeof s->share);
}

/* Contact events of the child (child indices) into the parent's record (parent indices). */
static int take_events(gr_sim *s, gr_hybrid_state *h, gr_error *err)
{
    gr_sim *c = h->child;
    if (!s->contacts || !c->contacts || h->n_active == 0) {
        return GR_OK;
    }
    for (int64_t k = 0; k < c->n_events; k++) {
        gr_contact_event e = c->events[k];
        e.i = h->list[e.i];
        int rc = gr_events_append(s, e, err);
        if (rc) {
            return rc;
        }
    }
    c->n_events = 0;
    for (int q = 0; q < h->n_active; q++) {
        s->contacts[h->list[q]] = c->contacts[q];
    }
    return GR_OK;
}

/* Symmetrised mode: go to the centre-of-mass frame (see the top of this file). The sums run in
 * 8 fixed lanes (vectorised, the same order on every machine). */
static void centre(gr_sim *s, gr_hybrid_state *h)
{
    const int n = s->n, two = s->dim >= 2; /* periodic in every axis from 2D on */
    const double L = s->L, half = 0.5 * L;
    double *pos[3] = {s->x, s->y, s->z}, *vel[3] = {s->vx, s->vy, s->vz},
           *start[3] = {h->x0, h->y0, h->z0};
    for (int c = 0; c < s->dim; c++) {
        double *restrict x = pos[c], *restrict v = vel[c];
        const double *restrict x0 = start[c];
        double Vl[8] = {0}, Xl[8] = {0};
        for (int i0 = 0; i0 < n; i0 += 8) {
            const int lanes = n - i0 < 8 ? n - i0 : 8;
#pragma omp simd
            for (int l = 0; l < lanes; l++) {
                double dx = x[i0 + l] - x0[i0 + l];
                dx += two ? (dx > half ? -L : (dx < -half ? L : 0.0)) : 0.0;
                Vl[l] += v[i0 + l];
                Xl[l] += dx;
            }
        }
        double V = 0.0, X = 0.0;
        for (int l = 0; l < 8; l++) {
            V += Vl[l];
            X += Xl[l];
        }
        V /= n;
        X /= n;
#pragma omp simd
        for (int i = 0; i < n; i++) {
            v[i] -= V;
            double xn = x[i] - X;
            xn += two ? (xn < 0.0 ? L : (xn >= L ? -L : 0.0)) : 0.0;
            x[i] = xn;
        }
        s->injected -= 0.5 * s->mass * n * V * V;
    }
}

/* 1 when every position and velocity is finite: 0 x is 0 for finite x and NaN otherwise, so
 * one vectorised sum answers (the caller then finds the culprit). */
static int all_finite(const gr_sim *s)
{
    const double *restrict x = s->x, *restrict v = s->vx, *restrict y = s->y, *restrict w = s->vy;
    double z = 0.0;
    if (s->dim == 1) {
#pragma omp simd reduction(+ : z)
        for (int i = 0; i < s->n; i++) {
            z += 0.0 * (x[i] + v[i]);
        }
    } else if (s->dim == 3) {
        const double *restrict r = s->z, *restrict u = s->vz;
#pragma omp simd reduction(+ : z)
        for (int i = 0; i < s->n; i++) {
            z += 0.0 * (x[i] + v[i] + y[i] + w[i] + r[i] + u[i]);
        }
    } else {
#pragma omp simd reduction(+ : z)
        for (int i = 0; i < s->n; i++) {
            z += 0.0 * (x[i] + v[i] + y[i] + w[i]);
        }
    }
    return z == 0.0;
}

/* The Langevin bath over the window of m steps that starts at step `start` ([driving] kind =
 * langevin, driving_langevin.c): the window ran without it (free grains leaped ballistically,
 * active ones stepped with their contacts), and now every velocity takes the exact
 * Ornstein-Uhlenbeck step of the whole window, v <- e^{-m dt/tau} v + sqrt(T_bath / dim (1 -
 * e^{-2 m dt/tau})) xi (times sqrt(m_1 / m_i) for grain i), xi from the random force's stream at
 * counter `start` (unused by the hybrid otherwise). A leaped grain and a stepped one without
 * contacts end the window alike, so the bath keeps the hybrid's equivalence of the two; the
 * splitting of drag and contacts is that of the event integrator (docs/event-driven.md, "Langevin
 * bath"). Books the drag's loss and the noise's work. */
static int bath_window(gr_sim *s, gr_hybrid_state *h, int m, int64_t start, gr_error *err)
{
    gr_driving_coeffs c = {0};
    int rc =
        s->params.driving->prepare(&s->params.driving_params, s->dim, (double)m * s->dt, &c, err);
    if (rc) {
        return rc;
    }
    const int n = s->n, dim = s->dim;
    gr_noise_normals(s->params.seed, GR_STREAM_NOISE, (uint64_t)start, 0, n, dim, h->bath_g);
    double *const v[3] = {s->vx, s->vy, s->vz};
    double added = 0.0, dragged = 0.0;
    gr_bath_ou_step(&c, h->bath_m1, n, dim, v, s->mass_i, s->mass, h->bath_g, &added, &dragged);
    s->injected += added;
    s->diss_drag += dragged;
    return GR_OK;
}

static int window(gr_sim *s, gr_hybrid_state *h, int m, gr_error *err)
{
    const int64_t start = s->step;
    saved sv;
    save(s, h, &sv);
    gr_hy_draw_window(s, h, start);
    for (int attempt = 0;; attempt++) {
        if (attempt > GR_HYBRID_MAX_ROLLBACKS) {
            memset(h->forced, 1, (size_t)s->n); /* cannot miss */
        }
        int missed = 0;
        int rc = gr_hy_select(s, h, m, err);
        if (!rc) {
            rc = gr_hy_active_kicks(s, h, start, m, err);
        }
        if (!rc) {
            if (h->n_active == 0) {
                s->elastic = 0.0;
                s->last = (gr_force_report){.worst_i = -1, .worst_j = -1};
            }
            rc = gr_hy_child_run(s, h, m, &missed, err);
        }
        if (rc) {
            restore(s, h, &sv);
            return rc;
        }
        if (!missed) {
            s->injected += gr_hy_leap_free(s, h, m);
            rc = gr_hy_misses(s, h, err, &missed);
            if (rc) {
                return rc;
            }
        }
        if (!missed) {
            break;
        }
        h->rollbacks++;
        restore(s, h, &sv);
    }
    int rc = take_events(s, h, err);
    if (rc) {
        return rc;
    }
    memset(h->forced, 0, (size_t)s->n);
    const int noise = s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
    if (h->bath && (rc = bath_window(s, h, m, start, err))) {
        return rc;
    }
    s->step += m;
    if (noise && s->params.noise_mode == GR_NOISE_SYMMETRISED && s->n > 1) {
        centre(s, h);
    } else if (s->params.noise_mode == GR_NOISE_COM && s->step % s->com_every == 0) {
        s->removed_com += gr_remove_com(s);
    }
    h->windows++;
    h->steps += m;
    h->active_steps += (int64_t)h->n_active * m;
    if (all_finite(s)) {
        return GR_OK;
    }
    for (int i = 0; i < s->n; i++) {
        double sum = s->x[i] + s->vx[i] + (s->dim >= 2 ? s->y[i] + s->vy[i] : 0.0) +
                     (s->dim == 3 ? s->z[i] + s->vz[i] : 0.0);
        if (!isfinite(sum)) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: particle %d has a non-finite position or velocity at "
                           "step %lld (t = %.6g s)",
                           i, (long long)s->step, gr_sim_time(s));
        }
    }
    return GR_OK;
}

int gr_hybrid_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    gr_hybrid_state *h = gr_hy(s);
    int64_t done = 0;
    while (done < nsteps) {
        /* windows are [k m, (k + 1) m) (cut at call ends and com resets): where they fall does not
         * depend on where earlier calls ended */
        int64_t m = h->m - s->step % h->m;
        m = m < nsteps - done ? m : nsteps - done;
        if (s->params.noise_mode == GR_NOISE_COM) { /* cut windows at the resets */
            const int64_t next = (s->step / s->com_every + 1) * s->com_every;
            m = m < next - s->step ? m : next - s->step;
        }
        int rc = window(s, h, (int)m, err);
        if (rc) {
            return rc;
        }
        done += m;
    }
    return GR_OK;
}
