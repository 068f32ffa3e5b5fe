/* The child simulation: the active particles of a window, stepped by the soft-sphere scheme
 * (docs/integrator.md) with the engine's own force kernels (gr_forces), neighbour list and
 * contact events.
 *
 * The child is a gr_sim of capacity N created once from the parent's initial state (which passed
 * the overlap check) with noise off. Each window overwrites its first n_active particles with the
 * active ones, in parent order: in 1D the child ring keeps the parent's L and order, so a child
 * pair (q, q+1) whose members are not parent neighbours has free particles between them and
 * cannot touch; in 2D the box is the same. The forces at the window start are the parent's (the
 * last evaluation: every contact then had both members active, so they are the forces of the
 * whole system), so a particle that stays active sees exactly the Verlet sequence of forces.
 *
 * The step is step.c's kick-drift-kick with the noise kick between the half kicks; the kicks come
 * from window_noise.c (bridged to each particle's free-flight draw) instead of GR_STREAM_NOISE.
 * The ledger is booked exactly as step.c books it (a kick dv adds M dv (v + dv/2); a half kick
 * of non-conservative force G does G . vbar dt / 2) straight into the parent's totals;
 * hybrid.c restores them on a rollback. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/hybrid/hy_internal.h"
#include "integrators/verlet/verlet.h"

#define RUNAWAY_OVERLAP 0.5 /* as step.c */

int gr_hy_child_create(gr_sim *s, gr_hybrid_state *h, gr_error *err)
{
    gr_sim_params sc = s->params;
    sc.integrator = &gr_integrator_verlet;
    sc.noise_mode = GR_NOISE_NONE;
    const double *const r[3] = {s->x, s->y, s->z}, *const v[3] = {s->vx, s->vy, s->vz};
    /* a mixture starts from a placement only: the child repeats the parent's (the same seed and
     * species deal), and each window overwrites its first grains with the active ones, their
     * species, radii and masses included (load) */
    int rc = s->nsp >= 1 ? gr_sim_new(&sc, &h->child, err)
             : s->dim == 3
                 ? gr_sim_new_with_state_3d(&sc, s->n, r, v, &h->child, err)
                 : gr_sim_new_with_state(&sc, s->n, s->x, s->y, s->vx, s->vy, &h->child, err);
    if (rc) {
        return rc;
    }
    if (h->child->dt != s->dt || h->child->kernel.run != s->kernel.run) {
        return GR_FAIL(
            err, GR_EINVAL,
            "hybrid: internal error, child time step or kernel differs from the parent's");
    }
    return GR_OK;
}

/* Set the child's particle count; the per-block and threading caches of src/core depend on it. */
static void child_resize(gr_sim *c, int na)
{
    c->n = na;
    c->nblk = na > 0 ? (na + GR_BLOCK - 1) / GR_BLOCK : 1;
    free(c->in_start); /* sized n + 1 when the cross lists are first built */
    c->in_start = NULL;
    c->par_threads = 0;
}

static void load(gr_sim *s, gr_hybrid_state *h, gr_sim *c)
{
    const int na = h->n_active;
    child_resize(c, na);
    for (int q = 0; q < na; q++) {
        const int p = h->list[q];
        c->x[q] = s->x[p];
        c->vx[q] = s->vx[p];
        c->fx[q] = s->fx[p];
        c->gx[q] = s->gx[p];
        if (s->dim >= 2) {
            c->y[q] = s->y[p];
            c->vy[q] = s->vy[p];
            c->fy[q] = s->fy[p];
            c->gy[q] = s->gy[p];
        }
        if (s->dim == 3) {
            c->z[q] = s->z[p];
            c->vz[q] = s->vz[p];
            c->fz[q] = s->fz[p];
            c->gz[q] = s->gz[p];
        }
        if (c->contacts) {
            c->contacts[q] = s->contacts[p];
        }
        if (s->species) {
            c->species[q] = s->species[p];
            c->rad[q] = s->rad[p];
            c->mass_i[q] = s->mass_i[p];
            c->inv_m[q] = s->inv_m[p];
            if (s->inertia_i) {
                c->inertia_i[q] = s->inertia_i[p];
            }
        }
    }
    double *sw[3], *st[3], *cw[3], *ct[3];
    const int nw = gr_hy_spins(s, sw, st);
    gr_hy_spins(c, cw, ct); /* the child rotates as the parent does (its parameters) */
    for (int a = 0; a < nw; a++) {
        for (int q = 0; q < na; q++) {
            cw[a][q] = sw[a][h->list[q]];
            ct[a][q] = st[a][h->list[q]];
        }
    }
    memcpy(c->share, s->share, sizeof c->share);
    c->elastic = s->elastic;
    c->last = s->last;
    c->n_events = 0;
    /* walls: this window's work, impulses and the moving wall's share of the dissipation (the walls
     * pass books them into the child), added to the parent's after it */
    c->wall_work = 0.0;
    c->diss_n = 0.0;
    memset(c->wall_impulse, 0, sizeof c->wall_impulse);
}

static void book(gr_sim *s, const double share[3], double work)
{
    s->diss_n -= work * share[0];
    s->diss_t -= work * share[1];
    s->diss_f -= work * share[2];
}

static void set_shares(double share[3], const gr_force_report *r)
{
    const double total = r->power_normal + r->power_tangential + r->power_friction;
    if (total > 0.0) {
        share[0] = r->power_normal / total;
        share[1] = r->power_tangential / total;
        share[2] = r->power_friction / total;
    } else {
        share[0] = 1.0;
        share[1] = share[2] = 0.0;
    }
}

/* Closing half kick of the last step; returns the work of the non-conservative forces. */
static double close_kick(gr_sim *c)
{
    const double hk0 = 0.5 * c->dt / c->mass, *im = c->inv_m;
    double w = 0.0;
    for (int q = 0; q < c->n; q++) {
        const double hk = im ? 0.5 * c->dt * im[q] : hk0; /* a mixture: each grain's 1 / m_i */
        const double dvx = hk * c->fx[q];
        w += c->gx[q] * (c->vx[q] + 0.5 * dvx);
        c->vx[q] += dvx;
        if (c->dim >= 2) {
            const double dvy = hk * c->fy[q];
            w += c->gy[q] * (c->vy[q] + 0.5 * dvy);
            c->vy[q] += dvy;
        }
        if (c->dim == 3) {
            const double dvz = hk * c->fz[q];
            w += c->gz[q] * (c->vz[q] + 0.5 * dvz);
            c->vz[q] += dvz;
        }
    }
    return 0.5 * c->dt * w;
}

/* The opening of step k (closing half kick of step k - 1, opening half kick, noise kick, drift)
 * for a mixture: the one-species loops below component by component, each grain's kicks scaled by
 * its own 1 / m_i and the noise's energy by its m_i. Adds the work of the non-conservative forces
 * (closing and opening halves), the kinetic energy the noise added and the largest squared
 * displacement since the list's build (2D, 3D). */
static void open_species(gr_sim *c, const gr_hybrid_state *h, int k, int m, const double lo[3],
                         const double hi[3], double *wc, double *wo, double *added, double *worst2)
{
    const int na = c->n, dim = c->dim;
    const double dt = c->dt, L = c->L, half = 0.5 * L, amp = h->kick_amp, mk = (double)(m - k);
    const size_t md = (size_t)m * dim;
    const double *raw = h->kick + (size_t)k * dim;
    double *r[3] = {c->x, c->y, c->z}, *v[3] = {c->vx, c->vy, c->vz};
    const double *f[3] = {c->fx, c->fy, c->fz}, *gn[3] = {c->gx, c->gy, c->gz},
                 *ref[3] = {c->x_ref, c->y_ref, c->z_ref};
    for (int q = 0; q < na; q++) {
        const double hk = 0.5 * dt * c->inv_m[q], aq = amp * c->inv_m[q];
        double d2 = 0.0, part = 0.0;
        for (int a = 0; a < dim; a++) {
            const double dvf = hk * f[a][q];
            double vi = v[a][q];
            if (k > 0) {
                *wc += gn[a][q] * (vi + 0.5 * dvf);
                vi += dvf;
            }
            *wo += gn[a][q] * (vi + 0.5 * dvf);
            vi += dvf;
            const size_t o = 2 * ((size_t)q * dim + (size_t)a);
            const double dv = aq * (raw[(size_t)q * md + a] + h->lam[o] + h->lam[o + 1] * mk);
            part += dv * (vi + 0.5 * dv);
            vi += dv;
            v[a][q] = vi;
            double xn = r[a][q] + vi * dt;
            if (dim >= 2) { /* the ring (1D) keeps unwrapped positions */
                xn += xn < lo[a] ? L : (xn >= hi[a] ? -L : 0.0);
                double dd = xn - ref[a][q];
                dd += dd > half ? -L : (dd < -half ? L : 0.0);
                d2 += dd * dd;
            }
            r[a][q] = xn;
        }
        *added += c->mass_i[q] * part;
        *worst2 = d2 > *worst2 ? d2 : *worst2;
    }
}

int gr_hy_child_run(gr_sim *s, gr_hybrid_state *h, int m, int *missed, gr_error *err)
{
    gr_sim *c = h->child;
    const int na = h->n_active, dim = s->dim;
    *missed = 0;
    if (na == 0) {
        return GR_OK;
    }
    load(s, h, c);
    if (s->contacts && !c->contacts) {
        /* the parent tracks contact events: so does the child, for its capacity N (not via
         * gr_sim_track_contacts, which sizes the arrays by the current n); counts are loaded
         * from the parent every window */
        c->contacts = calloc((size_t)s->n, sizeof(uint16_t));
        c->contacts_now = calloc((size_t)s->n, sizeof(uint16_t));
        c->cap_events = 1024;
        c->events = malloc(sizeof(gr_contact_event) * (size_t)c->cap_events);
        if (!c->contacts || !c->contacts_now || !c->events) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for contact events");
        }
        for (int q = 0; q < na; q++) {
            c->contacts[q] = s->contacts[h->list[q]];
        }
    }
    if (dim == 1) {
        for (int q = 0; q < na; q++) {
            const double g = q + 1 < na ? c->x[q + 1] - c->x[q] : c->x[0] + c->L - c->x[q];
            c->pair_contact[q] = na > 1 && g < gr_pair_d(c, q, q + 1 < na ? q + 1 : 0);
        }
    } else {
        c->step = 0; /* the list's contact flags: pairs overlapping now */
        int rc = gr_neighbours_build(c, err);
        if (rc) {
            return rc;
        }
    }
    c->step = s->step;
    const double hk = 0.5 * c->dt / c->mass, dt = c->dt, L = c->L, half = 0.5 * L;
    /* wrap into [0, L) along periodic axes only (step.c): along a wall axis a grain riding a floor
     * that vibrates below 0 keeps its coordinate */
    const double inf = (double)INFINITY;
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = c->period[a] < inf ? 0.0 : -inf;
        hi[a] = lo[a] == 0.0 ? L : inf;
    }
    const double skin_half2 = 0.25 * (c->cutoff - c->d) * (c->cutoff - c->d);
    /* the particles whose envelope is checked (those facing free particles) */
    int *env_q = h->env_list, n_env = 0;
    for (int q = 0; q < na; q++) {
        const int p = h->list[q];
        if (h->env_hi[p] < (double)INFINITY || h->env_lo[p] > -(double)INFINITY) {
            env_q[n_env++] = q;
        }
    }
    /* their start positions and bounds, side by side for the per-step check */
    double *ex = h->env_pack, *ey = ex + s->n, *ez = ey + s->n, *elo = ez + s->n, *ehi = elo + s->n;
    for (int e = 0; e < n_env; e++) {
        const int p = h->list[env_q[e]];
        ex[e] = h->x0[p];
        ey[e] = dim >= 2 ? h->y0[p] : 0.0;
        ez[e] = dim == 3 ? h->z0[p] : 0.0;
        elo[e] = h->env_lo[p];
        ehi[e] = h->env_hi[p];
    }
    double worst2 = 0.0;
    for (int k = 0; k < m; k++) {
        /* the kick of step k: a (raw + l1 + l2 (m - k)), window_noise.c */
        const double *restrict raw = h->kick + (size_t)k * dim, *restrict lam = h->lam;
        const double amp = h->kick_amp, mk = (double)(m - k);
        const size_t md = (size_t)m * dim;
        double wc = 0.0, wo = 0.0, added = 0.0;
        if (c->inv_m) {
            open_species(c, h, k, m, lo, hi, &wc, &wo, &added, &worst2);
        } else if (dim == 1) {
            double *restrict x = c->x, *restrict v = c->vx;
            const double *restrict f = c->fx, *restrict g = c->gx;
            /* LANES partial sums (as step.c) so the loop vectorises with a fixed summation order */
            double wcl[LANES] = {0}, wol[LANES] = {0}, adl[LANES] = {0};
            const int closing = k > 0;
#define CHILD_1D(q, l)                                                                             \
    do {                                                                                           \
        const double dvf = hk * f[q];                                                              \
        double vi = v[q];                                                                          \
        if (closing) {                                                                             \
            wcl[l] += g[q] * (vi + 0.5 * dvf);                                                     \
            vi += dvf;                                                                             \
        }                                                                                          \
        wol[l] += g[q] * (vi + 0.5 * dvf);                                                         \
        vi += dvf;                                                                                 \
        const double dv = amp * (raw[(q)*md] + lam[2 * (q)] + lam[2 * (q) + 1] * mk);              \
        adl[l] += dv * (vi + 0.5 * dv);                                                            \
        vi += dv;                                                                                  \
        v[q] = vi;                                                                                 \
        x[q] += vi * dt;                                                                           \
    } while (0)
            const int full = na / LANES * LANES;
            for (int q0 = 0; q0 < full; q0 += LANES) {
#pragma omp simd
                for (int l = 0; l < LANES; l++) {
                    CHILD_1D(q0 + l, l);
                }
            }
            for (int q = full; q < na; q++) {
                CHILD_1D(q, q - full);
            }
#undef CHILD_1D
            for (int l = 0; l < LANES; l++) {
                wc += wcl[l];
                wo += wol[l];
                added += adl[l];
            }
        } else if (dim == 3) {
            /* spheres: step.c's open_step_3d, component by component, kicks from the bridge */
            double *restrict r[3] = {c->x, c->y, c->z}, *restrict v[3] = {c->vx, c->vy, c->vz};
            const double *restrict f[3] = {c->fx, c->fy, c->fz}, *restrict gn[3] = {c->gx, c->gy,
                                                                                    c->gz};
            const double *restrict ref[3] = {c->x_ref, c->y_ref, c->z_ref};
            double wcl[LANES] = {0}, wol[LANES] = {0}, adl[LANES] = {0}, w2l[LANES] = {0};
            const int closing = k > 0;
            for (int q = 0; q < na; q++) {
                const int l = q % LANES;
                double d2 = 0.0;
                for (int a = 0; a < 3; a++) {
                    const double dvf = hk * f[a][q];
                    double vi = v[a][q];
                    if (closing) {
                        wcl[l] += gn[a][q] * (vi + 0.5 * dvf);
                        vi += dvf;
                    }
                    wol[l] += gn[a][q] * (vi + 0.5 * dvf);
                    vi += dvf;
                    const size_t o = 2 * ((size_t)q * 3 + (size_t)a);
                    const double dv = amp * (raw[(size_t)q * md + a] + lam[o] + lam[o + 1] * mk);
                    adl[l] += dv * (vi + 0.5 * dv);
                    vi += dv;
                    v[a][q] = vi;
                    double xn = r[a][q] + vi * dt;
                    xn += xn < lo[a] ? L : (xn >= hi[a] ? -L : 0.0);
                    r[a][q] = xn;
                    double dd = xn - ref[a][q];
                    dd += dd > half ? -L : (dd < -half ? L : 0.0);
                    d2 += dd * dd;
                }
                w2l[l] = d2 > w2l[l] ? d2 : w2l[l];
            }
            for (int l = 0; l < LANES; l++) {
                wc += wcl[l];
                wo += wol[l];
                added += adl[l];
                worst2 = w2l[l] > worst2 ? w2l[l] : worst2;
            }
        } else {
            double *restrict x = c->x, *restrict y = c->y, *restrict vx = c->vx,
                             *restrict vy = c->vy;
            const double *restrict fx = c->fx, *restrict fy = c->fy, *restrict gx = c->gx,
                                   *restrict gy = c->gy;
            const double *restrict xr = c->x_ref, *restrict yr = c->y_ref;
            double wcl[LANES] = {0}, wol[LANES] = {0}, adl[LANES] = {0}, w2l[LANES] = {0};
            const int closing = k > 0;
#define CHILD_2D(q, l)                                                                             \
    do {                                                                                           \
        const double dvx0 = hk * fx[q], dvy0 = hk * fy[q];                                         \
        double vxi = vx[q], vyi = vy[q];                                                           \
        if (closing) {                                                                             \
            wcl[l] += gx[q] * (vxi + 0.5 * dvx0) + gy[q] * (vyi + 0.5 * dvy0);                     \
            vxi += dvx0;                                                                           \
            vyi += dvy0;                                                                           \
        }                                                                                          \
        wol[l] += gx[q] * (vxi + 0.5 * dvx0) + gy[q] * (vyi + 0.5 * dvy0);                         \
        vxi += dvx0;                                                                               \
        vyi += dvy0;                                                                               \
        const double dvx = amp * (raw[(q)*md] + lam[4 * (q)] + lam[4 * (q) + 1] * mk);             \
        const double dvy = amp * (raw[(q)*md + 1] + lam[4 * (q) + 2] + lam[4 * (q) + 3] * mk);     \
        adl[l] += dvx * (vxi + 0.5 * dvx) + dvy * (vyi + 0.5 * dvy);                               \
        vxi += dvx;                                                                                \
        vyi += dvy;                                                                                \
        vx[q] = vxi;                                                                               \
        vy[q] = vyi;                                                                               \
        double xn = x[q] + vxi * dt, yn = y[q] + vyi * dt;                                         \
        xn += xn < lo[0] ? L : (xn >= hi[0] ? -L : 0.0);                                           \
        yn += yn < lo[1] ? L : (yn >= hi[1] ? -L : 0.0);                                           \
        x[q] = xn;                                                                                 \
        y[q] = yn;                                                                                 \
        double ddx = xn - xr[q], ddy = yn - yr[q];                                                 \
        ddx += ddx > half ? -L : (ddx < -half ? L : 0.0);                                          \
        ddy += ddy > half ? -L : (ddy < -half ? L : 0.0);                                          \
        const double d2 = ddx * ddx + ddy * ddy;                                                   \
        w2l[l] = d2 > w2l[l] ? d2 : w2l[l];                                                        \
    } while (0)
            const int full = na / LANES * LANES;
            for (int q0 = 0; q0 < full; q0 += LANES) {
#pragma omp simd
                for (int l = 0; l < LANES; l++) {
                    CHILD_2D(q0 + l, l);
                }
            }
            for (int q = full; q < na; q++) {
                CHILD_2D(q, q - full);
            }
#undef CHILD_2D
            for (int l = 0; l < LANES; l++) {
                wc += wcl[l];
                wo += wol[l];
                added += adl[l];
                worst2 = w2l[l] > worst2 ? w2l[l] : worst2;
            }
        }
        double spin_c = 0.0, spin_o = 0.0; /* rotation: step.c's spin kicks, after the drift */
        if (c->omega && !gr_verlet_spin_kicks(c, k > 0, 1, &spin_c, &spin_o)) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: non-finite angular velocity in the hybrid's active set "
                           "at step %lld (t = %.6g s)",
                           (long long)c->step, c->step * dt);
        }
        /* envelopes (active.c): a particle facing a free one must stay where the selection
         * assumed it would; otherwise that free particle might have been touched: redo */
        const double t = (k + 1) * dt;
        int out = 0;
        if (dim == 1) {
            const double *restrict x = c->x;
#pragma omp simd reduction(| : out)
            for (int e = 0; e < n_env; e++) {
                const double dx = x[env_q[e]] - ex[e];
                out |= (dx > ehi[e] * t) | (dx < elo[e] * t);
            }
        } else {
            const int three = dim == 3;
            /* z read only in 3D; in 2D a valid array, so a vectorised (masked) read cannot fault */
            const double *restrict x = c->x, *restrict y = c->y, *restrict z = three ? c->z : c->y;
#pragma omp simd reduction(| : out)
            for (int e = 0; e < n_env; e++) {
                double ddx = x[env_q[e]] - ex[e], ddy = y[env_q[e]] - ey[e],
                       ddz = three ? z[env_q[e]] - ez[e] : 0.0;
                ddx += ddx > half ? -L : (ddx < -half ? L : 0.0);
                ddy += ddy > half ? -L : (ddy < -half ? L : 0.0);
                ddz += ddz > half ? -L : (ddz < -half ? L : 0.0);
                const double reach = ehi[e] * t;
                out |= ddx * ddx + ddy * ddy + ddz * ddz > reach * reach;
            }
        }
        for (int e = 0; e < n_env && out; e++) { /* someone left: find and report them all */
            const int q = env_q[e], p = h->list[q];
            if (dim == 1) {
                const double dx = c->x[q] - h->x0[p];
                if (dx > h->env_hi[p] * t || dx < h->env_lo[p] * t) {
                    gr_hy_envelope_miss(s, h, p, dx > h->env_hi[p] * t ? 1 : -1);
                    *missed = 1;
                }
            } else {
                double ddx = c->x[q] - h->x0[p], ddy = c->y[q] - h->y0[p],
                       ddz = dim == 3 ? c->z[q] - h->z0[p] : 0.0;
                ddx += ddx > half ? -L : (ddx < -half ? L : 0.0);
                ddy += ddy > half ? -L : (ddy < -half ? L : 0.0);
                ddz += ddz > half ? -L : (ddz < -half ? L : 0.0);
                const double reach = h->env_hi[p] * t;
                if (ddx * ddx + ddy * ddy + ddz * ddz > reach * reach) {
                    gr_hy_envelope_miss(s, h, p, 0);
                    *missed = 1;
                }
            }
        }
        if (*missed) {
            return GR_OK; /* hybrid.c restores the window's start and redoes it */
        }
        book(s, c->share, 0.5 * dt * (wc + wo) + spin_c + spin_o);
        s->injected += (c->inv_m ? 1.0 : c->mass) * added; /* a mixture's is mass-weighted */
        if (!isfinite(wo + added)) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: non-finite velocity in the hybrid's active set at step "
                           "%lld (t = %.6g s)",
                           (long long)c->step, c->step * dt);
        }
        c->step++;
        if (dim >= 2 && (c->params.skin <= 0.0 || worst2 > skin_half2)) {
            int rc = gr_neighbours_build(c, err);
            if (rc) {
                return rc;
            }
            worst2 = 0.0;
            s->rebuilds++;
        }
        gr_force_report r;
        gr_forces(c, &r);
        set_shares(c->share, &r);
        if (c->contacts) {
            int rc = gr_events_update(c, err);
            if (rc) {
                return rc;
            }
        }
        c->elastic = r.elastic;
        c->last = r;
        s->collisions += r.new_contacts;
        if (r.max_overlap > RUNAWAY_OVERLAP) {
            const int wi = r.worst_i >= 0 && r.worst_i < na ? h->list[r.worst_i] : -1;
            const int wj = r.worst_j >= 0 && r.worst_j < na ? h->list[r.worst_j] : -1;
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: particles %d and %d overlap by %.3g d at step %lld (t = "
                           "%.6g s), beyond the %.2g d limit; "
                           "the springs (k_s = %g N/m) cannot hold them apart at this speed or "
                           "packing; use a stiffer k_s or a smaller dt",
                           wi, wj, r.max_overlap, (long long)c->step, c->step * dt, RUNAWAY_OVERLAP,
                           c->cc.k_s);
        }
    }
    double spin = 0.0, unused = 0.0;
    if (c->omega) {
        gr_verlet_spin_kicks(c, 1, 0, &spin, &unused); /* the closing spin kick */
    }
    book(s, c->share, close_kick(c) + spin);
    /* write back */
    for (int q = 0; q < na; q++) {
        const int p = h->list[q];
        s->x[p] = c->x[q];
        s->vx[p] = c->vx[q];
        s->fx[p] = c->fx[q];
        s->gx[p] = c->gx[q];
        if (dim >= 2) {
            s->y[p] = c->y[q];
            s->vy[p] = c->vy[q];
            s->fy[p] = c->fy[q];
            s->gy[p] = c->gy[q];
        }
        if (dim == 3) {
            s->z[p] = c->z[q];
            s->vz[p] = c->vz[q];
            s->fz[p] = c->fz[q];
            s->gz[p] = c->gz[q];
        }
    }
    double *sw[3], *st[3], *cw[3], *ct[3];
    const int nw = gr_hy_spins(s, sw, st);
    gr_hy_spins(c, cw, ct);
    for (int a = 0; a < nw; a++) {
        for (int q = 0; q < na; q++) {
            sw[a][h->list[q]] = cw[a][q];
            st[a][h->list[q]] = ct[a][q];
        }
    }
    s->wall_work += c->wall_work;
    s->diss_n += c->diss_n;
    for (int k = 0; k < 6; k++) {
        s->wall_impulse[k] += c->wall_impulse[k];
    }
    memcpy(s->share, c->share, sizeof s->share);
    s->elastic = c->elastic;
    s->last = c->last;
    if (s->last.worst_i >= 0 && s->last.worst_i < na) {
        s->last.worst_i = h->list[s->last.worst_i];
    }
    if (s->last.worst_j >= 0 && s->last.worst_j < na) {
        s->last.worst_j = h->list[s->last.worst_j];
    }
    return GR_OK;
}
