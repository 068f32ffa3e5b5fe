/* The event-driven integrator: kick windows, free-flight noise, the 1D ring core,
 * the energy ledger and the hooks called by src/core (sim.c, step.c). The 2D and 3D cores are
 * event_cells.h (event_2d.c, event_3d.c); the collision rule is the model's (models/list.h). Design and measurements: docs/event-driven.md.
 *
 * Noise (stream GR_STREAM_FREE_FLIGHT): window k draws, per particle and component, g1 from
 * counter step 2k and (exact mode) g2 from step 2k + 1.
 *  - exact: (dv, dx) of the random-acceleration process over tau (gr_free_flight_sample,
 *    include/granule/free_flight.h: Var dv = 2 D tau / M^2, Cov = D tau^2 / M^2,
 *    Var dx = 2 D tau^3 / (3 M^2), Chandrasekhar 1943), followed as the piecewise-constant
 *    accelerations a1, a2 (gr_free_flight_accelerations) so collisions stay exact events;
 *  - kicks: a velocity jump sqrt(2 D tau) / M g1 at the middle of the window (notes sec. 1.2),
 *    ballistic flight in between.
 * Symmetrised mode (2.18): the mean over all particles of the sampled increments (dv, dx) is
 * subtracted per component and window, i.e. every particle's acceleration/kick loses the same
 * mean, so total momentum is conserved exactly as in the soft-sphere step. Com mode removes the
 * centre-of-mass velocity at window ends every com_interval (booked as removed_com).
 *
 * Ledger: every collision books its exact loss (rule.h) into diss_n / diss_t; the free-flight
 * work is the kinetic-energy change along each particle's trajectory between its successive base
 * states, booked whenever a base is replaced (collision, window end) and for the part since the
 * base when the state is reported, so the ledger closes to rounding (elastic energy is 0). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/event/event_internal.h"
#include "models/list.h"
#include "granule/free_flight.h"
#include "granule/noise.h"

/* ---------- contact events for the free-path and post-collision observables ---------- */

int gr_ev_record(gr_sim *s, int i, int kind, double t, double x, double y, double vx, double vy,
                 gr_error *err)
{
    return gr_events_append(
        s, (gr_contact_event){.i = i, .kind = kind, .t = t, .x = x, .y = y, .vx = vx, .vy = vy},
        err);
}

/* ---------- progress guards ---------- */

/* An event rate that diverges (a Zeno sequence: particles in exact contact passing momentum round
 * a closed cluster, an inelastic collapse, absurd speeds crossing cells) never ends a step: stop
 * it as unstable with a diagnosis. budget = 1e6 + 10 N events must take at least
 * min_span = 1e-6 kick_interval of simulated time, i.e. the guard fires above about
 * 1e16 events/s at the default tau = 1e-4 s; dense 2D runs of 1e4 discs stay below 1e8
 * (docs/event-driven.md, "Progress guards"). */
int gr_ev_guard_check(gr_sim *s, double t_abs, int i, int j, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    if (e->stop && *e->stop) {
        e->guard_n--; /* the entry is handled again by the next call */
        return GR_EV_STOPPED;
    }
    const int64_t events = e->guard_n - e->guard_mark_n;
    if (events < e->budget) {
        return 0;
    }
    const double span = t_abs - e->guard_mark_t;
    if (span < e->min_span) {
        char who[80]; /* j < 0: the particle's own event, -1 - face (event_cells.h: from 2 dim on
                       * the walls) */
        if (j >= 0) {
            snprintf(who, sizeof who, "between particles %d and %d", i, j);
        } else {
            snprintf(who, sizeof who, "of particle %d %s", i,
                     -1 - j >= 2 * e->dim ? "on a wall" : "crossing a cell");
        }
        return GR_FAIL(
            err, GR_EUNSTABLE,
            "event-driven run unstable: the event rate diverges: %lld events in %.3g s of "
            "simulated time "
            "(%.3g events/s, the guard allows %lld events per %.3g s) at step %lld, t = %.12g s, "
            "the last %s. Particles in exact contact (e.g. [placement] "
            "kind = "
            "hexagonal with L a multiple of d), an inelastic collapse without the TC rule (a "
            "grain coming to rest on a wall: set [model] tc), or absurd speeds "
            "cause this; use a placement with gaps (uniform, random) or check the speeds",
            (long long)events, span, span > 0.0 ? (double)events / span : GR_EV_INF,
            (long long)e->budget, e->min_span, (long long)s->step, t_abs, who);
    }
    /* Floor bouncing (exact free flight): a noise-pressed pair re-collides every ~tc, so at a tc far
     * below the mean free time (tc = 1e-12 s: 1e12 collisions per pair and second) the run crawls
     * at a finite rate the test above never sees (issue 37). Stop when a budget of events took less
     * than one kick interval and most of them were floor separations; legitimate exact runs have
     * floors in < 50 % of collisions and far fewer than `budget` events per window. */
    const int64_t floors = e->floors - e->guard_floor_mark;
    if (span < e->tau && 2 * floors > events) {
        return GR_FAIL(
            err, GR_EUNSTABLE,
            "event-driven run crawls: %lld of %lld events in %.3g s of simulated time (less than "
            "one "
            "kick_interval = %.3g s) were noise-pressed pairs bouncing on the contact floor, which "
            "separates them for the TC time tc = %.3g s only, at step %lld, t = %.12g s (particles "
            "%d and "
            "%d). tc is far below the mean free time: leave [model] tc out (the contact time of "
            "the "
            "matching spring-dashpot), raise it, or use [integrator] free_flight = kicks",
            (long long)floors, (long long)events, span, e->tau, e->tc, (long long)s->step, t_abs, i,
            j);
    }
    e->guard_mark_n = e->guard_n;
    e->guard_mark_t = t_abs;
    e->guard_floor_mark = e->floors;
    return 0;
}

/* The contact floor is a small stand-in for a sustained contact (measured: 0.1-1% of the injected
 * energy). A floor event adds about (tc / (2 tau))^2 of one particle's random-force work per
 * window, so at tc >> tau (a soft k_s) the floor, not the noise, drives the system and, with every
 * collision TC-elastic, nothing dissipates: the energy runs away. Stop when the floor has added
 * GR_EV_FLOOR_RATIO times the random force's mean work d D N t / M (t at least one window). */
#define GR_EV_FLOOR_RATIO 10.0

int gr_ev_floor_check(gr_sim *s, int i, int j, double t_abs, double floor_speed, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    const double work = e->work_rate * fmax(t_abs - e->t_start, e->tau);
    if (e->floor_energy <= GR_EV_FLOOR_RATIO * work) {
        return GR_OK;
    }
    return GR_FAIL(err, GR_EUNSTABLE,
                   "event-driven run unstable: the contact floor has injected %.3g J, more than %g "
                   "times the random force's "
                   "mean work %.3g J, at step %lld, t = %.12g s (particles %d and %d separated at "
                   "%.3g m/s, against the "
                   "noise increment %.3g m/s per window). The floor speed push * tc / 2 grows with "
                   "tc / kick_interval = "
                   "%.3g: lower [model] tc (or raise k_s) or [integrator] kick_interval, or use "
                   "free_flight = kicks; "
                   "floors at one instant over and over mean particles in exact contact (use a "
                   "placement with gaps)",
                   e->floor_energy, GR_EV_FLOOR_RATIO, work, (long long)s->step, t_abs, i, j,
                   floor_speed, sqrt(2.0 * s->params.D * e->tau) / e->M, e->tc / e->tau);
}

/* ---------- windows ---------- */

static inline double ke2(double vx, double vy) { return vx * vx + vy * vy; }

/* The Langevin bath over the window that just ended ([driving] kind = langevin, driving_langevin.c):
 * free flight between window ends is ballistic (under gravity, parabolic) and collisions are
 * exact events, and at each window end every base velocity takes the exact Ornstein-Uhlenbeck
 * step of the whole window, v <- e^{-tau/tau_b} v + sqrt(T_bath / dim (1 - e^{-2 tau/tau_b})) xi
 * (xi from counter 2 win of the free-flight stream; a grain of mass m_i: the kick times
 * sqrt(m_1 / m_i), as bath_poly in verlet/step_poly.c). Without collisions the velocities at the
 * window ends are exactly the OU process sampled every tau; the splitting of drag and collisions
 * is first order in tau (docs/event-driven.md, "Langevin bath"). Books the drag's loss and the
 * noise's work. */
static void bath_window(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    const int n = e->n, dim = e->dim;
    gr_noise_normals(s->params.seed, GR_STREAM_FREE_FLIGHT, 2 * (uint64_t)e->win, 0, n, dim, e->g);
    double *const v[3] = {e->bv, e->bw, e->bu};
    const gr_driving_coeffs c = {.decay = e->bath_decay, .kick = e->bath_kick};
    gr_bath_ou_step(&c, e->bath_m1, n, dim, v, e->m, e->M, e->g, &e->injected, &s->diss_drag);
}

/* Advance every particle to the end of the window (local time tau), booking the free-flight work,
 * and start the next window: base time 0, state at the old window's end. */
static void end_window(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    double work = 0.0;
    for (int i = 0; i < e->n; i++) {
        double x, v, y = 0.0, w = 0.0;
        const double mw = e->m ? e->m[i] / e->M : 1.0; /* species: its own mass (1.0: exact) */
        gr_ev_state_x(e, i, e->tau, 1, &x, &v);
        if (e->dim == 3) {
            double z, u;
            gr_ev_state_y(e, i, e->tau, 1, &y, &w);
            gr_ev_state_z(e, i, e->tau, 1, &z, &u);
            work += mw * (ke2(v, w) + u * u - ke2(e->bv[i], e->bw[i]) - e->bu[i] * e->bu[i] -
                          gr_ev_gravity_work_3d(e, x - e->bx[i], y - e->by[i], z - e->bz[i]));
            e->by[i] = y;
            e->bw[i] = w;
            e->bz[i] = z;
            e->bu[i] = u;
        } else if (e->dim == 2) {
            gr_ev_state_y(e, i, e->tau, 1, &y, &w);
            work += mw * (ke2(v, w) - ke2(e->bv[i], e->bw[i]) -
                          gr_ev_gravity_work(e, x - e->bx[i], y - e->by[i]));
            e->by[i] = y;
            e->bw[i] = w;
        } else {
            work += mw * (v * v - e->bv[i] * e->bv[i]);
            if (e->grav[0] != 0.0) { /* gravity along x (walls): its work is the potential's */
                work -= mw * gr_ev_gravity_work(e, x - e->bx[i], 0.0);
            }
        }
        e->bx[i] = x;
        e->bv[i] = v;
        e->t0[i] = 0.0;
        e->past[i] = 0;
    }
    e->injected += 0.5 * e->M * work;
    if (e->bath) {
        bath_window(s);
    }
    e->win++;
    e->now = 0.0;
    e->phase = 0;
    e->kicks += e->n;
}

/* Centre-of-mass reset (com noise mode) on the base velocities at a window start. */
static void remove_com(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    double before = 0.0, after = 0.0;
    double *v[3] = {e->bv, e->bw, e->bu};
    for (int c = 0; c < e->dim; c++) {
        double m = 0.0;
        for (int i = 0; i < e->n; i++) {
            m += v[c][i];
        }
        m /= e->n;
        for (int i = 0; i < e->n; i++) {
            before += v[c][i] * v[c][i];
            v[c][i] -= m;
            after += v[c][i] * v[c][i];
        }
    }
    s->removed_com += 0.5 * e->M * (before - after);
}

/* Draw the window's free-flight noise: a1, a2, J per particle and component. */
static void draw_noise(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    const int n = e->n, dim = e->dim;
    double *a1[3] = {e->a1x, e->a1y, e->a1z}, *a2[3] = {e->a2x, e->a2y, e->a2z},
           *j[3] = {e->jx, e->jy, e->jz};
    const double grav[3] = {e->grav[0], e->grav[1], e->grav[2]};
    if (!e->noise) {
        for (int c = 0; c < dim; c++) { /* gravity alone (0 without it) */
            for (int i = 0; i < n; i++) {
                a1[c][i] = a2[c][i] = grav[c];
            }
        }
        return;
    }
    const double D = s->params.D, tau = e->tau;
    double *g1 = e->g, *g2 = e->g + (size_t)n * dim;
    gr_noise_normals(s->params.seed, GR_STREAM_FREE_FLIGHT, 2 * (uint64_t)e->win, 0, n, dim, g1);
    if (e->exact) {
        gr_noise_normals(s->params.seed, GR_STREAM_FREE_FLIGHT, 2 * (uint64_t)e->win + 1, 0, n, dim,
                         g2);
    }
    const bool sym = s->params.noise_mode == GR_NOISE_SYMMETRISED;
    for (int c = 0; c < dim; c++) {
        double mdv = 0.0, mdx = 0.0;
        for (int i = 0; i < n; i++) {
            double dv, dx;
            gr_free_flight_sample(D, gr_ev_mass(e, i), tau, g1[i * dim + c],
                                  e->exact ? g2[i * dim + c] : 0.0, &dv, &dx);
            a1[c][i] = dv; /* increments first, accelerations below */
            a2[c][i] = dx;
            mdv += e->m ? e->m[i] * dv : dv; /* species: the impulses m_i dv_i */
            mdx += e->m ? e->m[i] * dx : dx;
        }
        mdv = sym ? mdv / n : 0.0;
        mdx = sym ? mdx / n : 0.0;
        for (int i = 0; i < n; i++) {
            double dv = a1[c][i] - mdv, dx = a2[c][i] - mdx; /* (2.18) */
            if (e->m) { /* species: the mean impulse, sum_i m_i dv_i = 0 (below) */
                dv = a1[c][i] - mdv / e->m[i];
                dx = a2[c][i] - mdx / e->m[i];
            }
            if (e->exact) {
                gr_free_flight_accelerations(tau, dv, dx, &a1[c][i], &a2[c][i]);
                j[c][i] = 0.0;
            } else {
                a1[c][i] = a2[c][i] = 0.0;
                j[c][i] = dv;
            }
            a1[c][i] += grav[c]; /* gravity: the same for all, so no pair sees it */
            a2[c][i] += grav[c];
        }
    }
}

/* ---------- 1D ring: only neighbours collide; one calendar entry per pair (k, k+1 mod n) ---------- */

static double predict_pair_1d(const struct gr_event_state *e, int k, int *phase)
{
    const int i = k, j = k + 1 < e->n ? k + 1 : 0;
    const double wrap = k + 1 < e->n ? 0.0 : e->L;
    double xi, vi, xj, vj;
    *phase = e->phase;
    if (e->no_collisions) {
        return GR_EV_INF;
    }
    gr_ev_state_x(e, i, e->now, e->phase, &xi, &vi);
    gr_ev_state_x(e, j, e->now, e->phase, &xj, &vj);
    const double d = gr_ev_d(e, i, j); /* the pair's contact distance */
    double f0 = xj + wrap - xi - d, f1 = vj - vi;
    if (e->phase == 0) {
        const double A = e->a1x[j] - e->a1x[i];
        double t = gr_ev_first_quadratic(f0, f1, 0.5 * A, e->h - e->now);
        if (t < GR_EV_INF) {
            return e->now + t;
        }
        /* second half: relative state at the middle, after the jump */
        gr_ev_state_x(e, i, e->h, 1, &xi, &vi);
        gr_ev_state_x(e, j, e->h, 1, &xj, &vj);
        f0 = xj + wrap - xi - d;
        f1 = vj - vi;
        *phase = 1;
        t = gr_ev_first_quadratic(f0, f1, 0.5 * (e->a2x[j] - e->a2x[i]), e->tau - e->h);
        return t < GR_EV_INF ? e->h + t : GR_EV_INF;
    }
    double t = gr_ev_first_quadratic(f0, f1, 0.5 * (e->a2x[j] - e->a2x[i]), e->tau - e->now);
    return t < GR_EV_INF ? e->now + t : GR_EV_INF;
}

/* 1D walls ([boundary] x = walls): calendar entries 0 .. n - 2 are the pairs (k, k + 1), entry
 * n - 1 the last grain's hit of the wall at L and entry n the first grain's hit of the wall at 0
 * (the vibrating one with [boundary] vibrate = x); no pair (n - 1, 0) closes the ring. */
static inline bool wall_entry_1d(const struct gr_event_state *e, int k)
{
    return e->wall[0] && k >= e->n - 1;
}

static double predict_wall_1d(const struct gr_event_state *e, int k, int *phase)
{
    const int side = k == e->n - 1, i = side ? e->n - 1 : 0;
    double t0 = e->now;
    *phase = e->phase;
    for (int piece = e->phase; piece < 2; piece++) {
        double q, v;
        gr_ev_state_x(e, i, t0, piece, &q, &v);
        const double acc = piece == 0 ? e->a1x[i] : e->a2x[i];
        const double t = gr_ev_wall_piece(e, 0, side, t0, q, v, acc,
                                          (piece == 0 ? e->h : e->tau) - t0, gr_ev_radius(e, i));
        if (t < GR_EV_INF) {
            *phase = piece;
            return t0 + t;
        }
        t0 = e->h;
    }
    return GR_EV_INF;
}

static void repredict_1d(struct gr_event_state *e, int k)
{
    int ph;
    e->heap.t[k] = wall_entry_1d(e, k) ? predict_wall_1d(e, k, &ph) : predict_pair_1d(e, k, &ph);
    e->heap.ph[k] = (uint8_t)ph;
    gr_heap_update(&e->heap, k);
}

static int check_1d(gr_sim *s, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    for (int k = 0; k < e->n - (e->wall[0] ? 1 : 0) && e->n > 1; k++) {
        const int j = k + 1 < e->n ? k + 1 : 0;
        double xi, vi, xj, vj;
        gr_ev_state_x(e, k, e->now, e->phase, &xi, &vi);
        gr_ev_state_x(e, j, e->now, e->phase, &xj, &vj);
        const double d = gr_ev_d(e, k, j);
        double gap = xj + (j == 0 ? e->L : 0.0) - xi - d;
        if (gap < -1e-9 * d) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "event check: particles %d and %d overlap by %.3g d at t = %.9g s", k, j,
                           -gap / d, (double)e->win * e->tau + e->now);
        }
    }
    return GR_OK;
}

/* Rebase particle i at the current instant with state (x, v), booking the free-flight work. */
static inline void rebase_1d(struct gr_event_state *e, int i, double x, double v_before,
                             double v_after)
{
    e->injected += 0.5 * gr_ev_mass(e, i) * (v_before * v_before - e->bv[i] * e->bv[i]);
    if (e->grav[0] != 0.0) { /* gravity along x (with walls): its work is the potential's */
        e->injected -= 0.5 * gr_ev_mass(e, i) * gr_ev_gravity_work(e, x - e->bx[i], 0.0);
    }
    e->t0[i] = e->now;
    e->bx[i] = x;
    e->bv[i] = v_after;
    e->past[i] = (uint8_t)e->phase;
}

/* Grain i hits a wall now (entry k: n - 1 the wall at L, n the wall at 0): the 2D wall_hit
 * (event_cells.h) on the line, the rule with the grain's mirror image, the walls' own eps_n
 * (eps_n(v) at the grain's own speed), in the vibrating wall's frame with its work booked, the TC
 * rule and the contact floor. Returns 0, 1 (no hit after all: predict again) or < 0. */
static int wall_hit_1d(gr_sim *s, int k, double t_abs, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    const int side = k == e->n - 1, i = side ? e->n - 1 : 0;
    double x, v;
    gr_ev_state_x(e, i, e->now, e->phase, &x, &v);
    const double nx = side ? 1.0 : -1.0, m = gr_ev_mass(e, i); /* species: its own mass */
    const bool moving = e->vib == 0 && !side;
    double vr = v, vw = 0.0, aw = 0.0; /* the velocity in the wall's frame */
    if (moving) {
        if (gr_ev_vib_wall(e, t_abs, x, gr_ev_radius(e, i), &vw, &aw) > 1e-9 * e->d) {
            return 1; /* a checkpoint of gr_ev_moving_wall_first, not a hit */
        }
        vr -= vw;
    }
    const double vn = vr * nx;                                          /* > 0: towards the wall */
    const double push = nx * ((e->phase ? e->a2x[i] : e->a1x[i]) - aw); /* > 0: pressed in */
    if (vn <= 0.0 && push <= 0.0) {
        return 1;
    }
    const bool elastic = t_abs - e->last[i] < e->tc;
    double u = vr, de_n = 0.0, de_t = 0.0;
    if (vn > 0.0) {
        gr_event_pair p = {.M = m, .nx = nx, .v1x = vr, .v2x = -vr, .elastic = elastic};
        gr_event_rule_apply(e->rule, gr_ev_wall_cc(s, e, vn), &p);
        u = p.v1x;
        de_n = 0.5 * p.de_n;
        de_t = 0.5 * p.de_t;
    }
    const double out = -u * nx; /* speed away from the wall, in its frame */
    if (moving) {
        u += vw;
        s->wall_work += gr_ev_wall_work(m, 0.0, 1, &v, &u, NULL, NULL, 0, elastic, de_n, de_t);
    }
    const double floor_speed = push > 0.0 ? 0.5 * push * e->tc : 0.0;
    if (out < floor_speed) {
        const double k0 = u * u;
        u -= (floor_speed - out) * nx;
        const double added = 0.5 * m * (u * u - k0);
        e->injected += added;
        e->floor_energy += added;
        e->floors++;
    }
    if (s->contacts) {
        int rc = gr_ev_record(s, i, +1, t_abs, x, 0.0, v, 0.0, err);
        rc = rc ? rc : gr_ev_record(s, i, -1, t_abs, x, 0.0, u, 0.0, err);
        if (rc) {
            return rc;
        }
    }
    s->wall_impulse[side] += m * (u - v) * -nx; /* the wall's impulse (walls.csv), as in 2D */
    rebase_1d(e, i, x, v, u);
    if (!elastic) {
        s->diss_n += de_n;
        s->diss_t += de_t;
    } else {
        e->tc_elastic++;
    }
    e->last[i] = t_abs;
    e->wall_hits++;
    return 0;
}

static int process_1d(gr_sim *s, double t_limit, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    gr_heap *hp = &e->heap;
    const double t_win = (double)e->win * e->tau;
    for (int k; (k = gr_heap_min(hp)) >= 0;) {
        const double t = hp->t[k];
        if (!(t <= t_limit)) {
            break;
        }
        if (wall_entry_1d(e, k)) {
            const int i = k == e->n - 1 ? e->n - 1 : 0;
            /* a wall as the guard's message sees one: -1 - face with face >= 2 dim */
            int grc = gr_ev_guard(s, e, t_win + t, i, -3 - (k == e->n - 1), err);
            if (grc) {
                return grc;
            }
            e->now = t;
            e->phase = hp->ph[k];
            int rc = wall_hit_1d(s, k, t_win + t, err);
            if (rc < 0) {
                return rc;
            }
            e->invalid += rc;
            repredict_1d(e, k);
            if (e->n == 1) {
                repredict_1d(e, 1 - k); /* the only grain: its other wall */
            } else if (rc == 0) {
                repredict_1d(e, i == 0 ? 0 : e->n - 2); /* its pair with its neighbour */
            }
            continue;
        }
        const int i = k, j = k + 1 < e->n ? k + 1 : 0;
        int grc = gr_ev_guard(s, e, t_win + t, i, j, err);
        if (grc) {
            return grc;
        }
        e->now = t;
        e->phase = hp->ph[k];
        double xi, vi, xj, vj;
        gr_ev_state_x(e, i, t, e->phase, &xi, &vi);
        gr_ev_state_x(e, j, t, e->phase, &xj, &vj);
        const double t_abs = t_win + t;
        double push = e->phase ? e->a2x[i] - e->a2x[j] : e->a1x[i] - e->a1x[j];
        if (vi - vj <= 0.0) {
            const double d = gr_ev_d(e, i, j);
            if (xj + (j == 0 ? e->L : 0.0) - xi - d > 1e-9 * d) {
                /* not approaching at the predicted instant (a root at a piece boundary): re-predict */
                e->invalid++;
                repredict_1d(e, k);
                continue;
            }
            if (!(e->a1x[i] != e->a1x[j] || e->a2x[i] != e->a2x[j])) {
                e->invalid++; /* touching, receding, no acceleration: nothing will happen */
                repredict_1d(e, k);
                continue;
            }
            push = fabs(push); /* touching, about to approach: separate as a pressed contact */
        }
        const bool approaching = vi - vj > 0.0;
        const bool elastic = gr_ev_tc_elastic(e, i, j, t_abs);
        double ui = vi, uj = vj, de_n = 0.0, de_t = 0.0;
        if (approaching) { /* a pressed pair that is not approaching only gets the floor */
            gr_event_pair p = {.nx = 1.0, .v1x = ui, .v2x = uj, .elastic = elastic};
            gr_ev_rule(e, i, j, &p); /* with species: the pair's masses and coefficients */
            ui = p.v1x;
            uj = p.v2x;
            de_n = p.de_n;
            de_t = p.de_t;
        }
        const double tc = gr_ev_tc(e, i, j);
        if (push > 0.0 && uj - ui < 0.5 * push * tc) {
            /* contact floor (docs/event-driven.md): a pair pressed together by the noise separates
             * fast enough to come back no sooner than tc, so it cannot stall time */
            const double k0 = ui * ui + uj * uj, ki = ui * ui, kj = uj * uj;
            double fi, fj; /* 1/2 each, or by the masses with species */
            gr_ev_floor_shares(e, i, j, &fi, &fj);
            const double dg = 0.5 * push * tc - (uj - ui);
            ui -= fi * dg;
            uj += fj * dg;
            const double added = e->m ? 0.5 * (e->m[i] * (ui * ui - ki) + e->m[j] * (uj * uj - kj))
                                      : 0.5 * e->M * (ui * ui + uj * uj - k0);
            e->injected += added;
            e->floor_energy += added;
            e->floors++;
            int rc = gr_ev_floor_check(s, i, j, t_abs, uj - ui, err);
            if (rc) {
                return rc;
            }
        }
        if (s->contacts) {
            int rc = gr_ev_record(s, i, +1, t_abs, xi, 0.0, vi, 0.0, err);
            rc = rc ? rc : gr_ev_record(s, j, +1, t_abs, xj, 0.0, vj, 0.0, err);
            rc = rc ? rc : gr_ev_record(s, i, -1, t_abs, xi, 0.0, ui, 0.0, err);
            rc = rc ? rc : gr_ev_record(s, j, -1, t_abs, xj, 0.0, uj, 0.0, err);
            if (rc) {
                return rc;
            }
        }
        rebase_1d(e, i, xi, vi, ui);
        rebase_1d(e, j, xj, vj, uj);
        if (!elastic) {
            s->diss_n += de_n;
            s->diss_t += de_t; /* 0 on the ring (no tangent), booked for any rule */
        } else {
            e->tc_elastic++;
        }
        e->last[i] = e->last[j] = t_abs;
        e->collisions++;
        s->collisions++;
        repredict_1d(e, k);
        if (e->wall[0]) { /* j's pair or its wall at L; i's pair with k - 1 or its wall at 0 */
            repredict_1d(e, j);
            repredict_1d(e, k > 0 ? k - 1 : e->n);
        } else if (e->n > 2) {
            repredict_1d(e, k > 0 ? k - 1 : e->n - 1);
            repredict_1d(e, j);
        } else if (e->n == 2) {
            repredict_1d(e, 1 - k);
        }
        if (e->check) {
            int rc = check_1d(s, err);
            if (rc) {
                return rc;
            }
        }
    }
    return GR_OK;
}

static void window_1d(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    const int n = e->n;
    if (e->wall[0]) { /* walls: the pairs and the two wall entries, the general predictors */
        for (int k = 0; k <= n; k++) {
            int ph;
            e->heap.t[k] =
                wall_entry_1d(e, k) ? predict_wall_1d(e, k, &ph) : predict_pair_1d(e, k, &ph);
            e->heap.ph[k] = (uint8_t)ph;
        }
        gr_heap_build(&e->heap);
        return;
    }
    if (n < 2) {
        return;
    }
    if (e->now != 0.0 || e->no_collisions) { /* not at a window start: the general predictor */
        for (int k = 0; k < n; k++) {
            int ph;
            e->heap.t[k] = predict_pair_1d(e, k, &ph);
            e->heap.ph[k] = (uint8_t)ph;
        }
        gr_heap_build(&e->heap);
        return;
    }
    /* window start: every base is at local time 0 before the middle; precompute the states at
     * the middle (after the jump) once per particle (the scratch normals are free again) */
    double *xh = e->g, *vh = e->g + n;
    const double h = e->h;
    for (int i = 0; i < n; i++) {
        xh[i] = e->bx[i] + h * (e->bv[i] + 0.5 * e->a1x[i] * h);
        vh[i] = e->bv[i] + e->a1x[i] * h + e->jx[i];
    }
    for (int k = 0; k < n; k++) {
        const int j = k + 1 < n ? k + 1 : 0;
        const double wrap = k + 1 < n ? 0.0 : e->L;
        const double d = gr_ev_d(e, k, j);
        double t = gr_ev_first_quadratic(e->bx[j] + wrap - e->bx[k] - d, e->bv[j] - e->bv[k],
                                         0.5 * (e->a1x[j] - e->a1x[k]), h);
        int ph = 0;
        if (!(t < GR_EV_INF)) {
            t = gr_ev_first_quadratic(xh[j] + wrap - xh[k] - d, vh[j] - vh[k],
                                      0.5 * (e->a2x[j] - e->a2x[k]), e->tau - h);
            t = t < GR_EV_INF ? h + t : GR_EV_INF;
            ph = 1;
        }
        e->heap.t[k] = t;
        e->heap.ph[k] = (uint8_t)ph;
    }
    gr_heap_build(&e->heap);
}

/* ---------- the hooks ---------- */

/* The calendar at a window start (or after set_debug): the dimension's core. */
static void window_any(gr_sim *s)
{
    if (s->dim == 1) {
        window_1d(s);
    } else if (s->dim == 2) {
        gr_ev2d_window(s);
    } else {
        gr_ev3d_window(s);
    }
}

static void start_window(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    if (s->params.noise_mode == GR_NOISE_COM && e->win > 0 && e->win % e->com_every == 0) {
        remove_com(s);
    }
    draw_noise(s);
    window_any(s);
}

/* Write the state at local time t into s->x, vx (y, vy) and bring s->injected up to date. */
static void report(gr_sim *s, double t)
{
    struct gr_event_state *e = gr_ev(s);
    double work = 0.0;
    const int phase = t > e->h || (t == e->h && e->phase);
    for (int i = 0; i < e->n; i++) {
        double x, v;
        const double mw = e->m ? e->m[i] / e->M : 1.0; /* species: its own mass (1.0: exact) */
        gr_ev_state_x(e, i, t, phase, &x, &v);
        s->x[i] = x;
        s->vx[i] = v;
        if (e->dim == 3) {
            double y, w, z, u;
            gr_ev_state_y(e, i, t, phase, &y, &w);
            gr_ev_state_z(e, i, t, phase, &z, &u);
            s->x[i] = e->vib == 0 ? x : x - e->L * floor(x / e->L); /* a vibrating wall's */
            s->y[i] = e->vib == 1 ? y : y - e->L * floor(y / e->L); /* grains may be below 0 */
            s->z[i] = e->vib == 2 ? z : z - e->L * floor(z / e->L);
            s->vy[i] = w;
            s->vz[i] = u;
            work += mw * (ke2(v, w) + u * u - ke2(e->bv[i], e->bw[i]) - e->bu[i] * e->bu[i] -
                          gr_ev_gravity_work_3d(e, x - e->bx[i], y - e->by[i], z - e->bz[i]));
        } else if (e->dim == 2) {
            double y, w;
            gr_ev_state_y(e, i, t, phase, &y, &w);
            s->x[i] = e->vib == 0 ? x : x - e->L * floor(x / e->L);
            s->y[i] = e->vib == 1 ? y : y - e->L * floor(y / e->L);
            s->vy[i] = w;
            work += mw * (ke2(v, w) - ke2(e->bv[i], e->bw[i]) -
                          gr_ev_gravity_work(e, x - e->bx[i], y - e->by[i]));
        } else {
            work += mw * (v * v - e->bv[i] * e->bv[i]);
            if (e->grav[0] != 0.0) { /* gravity along x (walls): its work is the potential's */
                work -= mw * gr_ev_gravity_work(e, x - e->bx[i], 0.0);
            }
        }
    }
    s->injected = e->injected + 0.5 * e->M * work;
}

/* Absurd speeds: a particle that would cross the box more than GR_EV_MAX_BOXES times per kick
 * interval makes ~N cells of crossing events per crossing and, far enough out, event times that
 * local time cannot resolve (4.3e95 m/s: 1e91 boxes per window). Refused at creation (bad input,
 * velocities from [placement] v0 or the given state), stopped as unstable at a window start (a
 * runaway). Non-finite velocities or positions are refused the same way. */
#define GR_EV_MAX_BOXES 1e3

static int check_speeds(const gr_sim *s, const double *x, const double *vx, const double *y,
                        const double *vy, const double *z, const double *vz, double tau,
                        bool at_start, gr_error *err)
{
    double vmax = 0.0;
    int worst = 0;
    for (int i = 0; i < s->n; i++) {
        const double wy = s->dim >= 2 ? vy[i] : 0.0, yy = s->dim >= 2 ? y[i] : 0.0;
        const double wz = s->dim == 3 ? vz[i] : 0.0, zz = s->dim == 3 ? z[i] : 0.0;
        const double v =
            s->dim == 3 ? sqrt(vx[i] * vx[i] + wy * wy + wz * wz) : sqrt(vx[i] * vx[i] + wy * wy);
        if (!isfinite(v) || !isfinite(x[i]) || !isfinite(yy) || !isfinite(zz)) {
            vmax = GR_EV_INF;
            worst = i;
            break;
        }
        if (v > vmax) {
            vmax = v;
            worst = i;
        }
    }
    if (!(vmax * tau > GR_EV_MAX_BOXES * s->L)) {
        return GR_OK;
    }
    if (at_start) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: particle %d starts with speed %.3g m/s: it would cross the box (L = %g "
                       "m) %.3g times per kick "
                       "interval %g s; the event-driven integrator allows at most %g (check "
                       "[placement] v0, allowed "
                       "range [0, %.3g] m/s for this box)",
                       s->params.source, worst, vmax, s->L, vmax * tau / s->L, tau, GR_EV_MAX_BOXES,
                       2.0 * GR_EV_MAX_BOXES * s->L / tau / sqrt(s->dim));
    }
    return GR_FAIL(
        err, GR_EUNSTABLE,
        "event-driven run unstable: particle %d reached speed %.3g m/s at step %lld, t = %.6g s: "
        "it crosses the "
        "box (L = %g m) %.3g times per kick interval (allowed %g); energy is running away",
        worst, vmax, (long long)s->step, gr_sim_time(s), s->L, vmax * tau / s->L, GR_EV_MAX_BOXES);
}

int gr_event_init(gr_sim *s, gr_error *err)
{
    /* a capability, not a name: the normal law must be an event rule (models/list.h) */
    const int rule = s->cc.normal_model ? gr_event_rule_of(s->cc.normal_model) : -1;
    if (rule < 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kind = event needs an event rule as [model] normal (%s "
                       "is a force law; granule models lists the rules)",
                       s->params.source, s->cc.normal_model ? s->cc.normal_model->name : "none");
    }
    if (!(s->params.kick_interval > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kick_interval = %g: allowed range (0, inf) s",
                       s->params.source, s->params.kick_interval);
    }
    struct gr_event_state *e = calloc(1, sizeof *e);
    if (!e) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    s->integrator_state = e;
    const int n = s->n;
    e->n = n;
    e->dim = s->dim;
    e->noise = s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
    e->bath = s->drive == GR_DRIVE_BATH; /* gr_sim set D = 0: the bath replaces the random force */
    /* without noise the windows only bound the predictions: make them long */
    e->tau = e->noise || e->bath ? s->params.kick_interval : fmax(s->params.kick_interval, 1.0);
    e->h = 0.5 * e->tau;
    e->M = s->mass;
    e->L = s->L;
    e->d = s->d;
    e->d2 = s->d * s->d;
    e->tc = s->cc.tc; /* as the rule's prepare set it ([model] tc, off, or its contact time) */
    e->rule = rule;
    e->cc = &s->cc;
    e->rough = s->omega != NULL; /* [model] rotation = true (2D, 3D: gr_sim refuses it in 1D) */
    e->q = s->cc.q;
    e->R = 0.5 * s->d;
    e->exact = s->params.free_flight == GR_FREE_FLIGHT_EXACT;
    e->vib = -1;  /* no vibrating wall */
    if (s->rad) { /* species (docs/mixtures.md): grains of their own radii and masses */
        e->m = s->mass_i;
        e->r = s->rad;
        if (s->cc_pair) { /* species lists: each pair's coefficients */
            e->sp = s->species;
            e->nsp = s->nsp;
            e->cc_pair = s->cc_pair;
        } else if (s->cc.tc > 0.0 && s->cc.tc == s->cc.t_c) { /* a distribution, tc by default */
            e->tc_m12 = s->cont_m12;
        }
    }
    if (s->walls_on) { /* gr_walls_prepare checked the scene; what this integrator adds: */
        const gr_sim_params *p = &s->params;
        /* a wall is the mirror image of the grain (event_cells.h, wall_hit): a rule whose eps_n
         * depends on the impact speed gets it from the grain's own speed against the wall
         * (gr_ev_wall_cc), as a constant eps_n of a copy of the walls' coefficients */
        const gr_model *nm = s->wall_cc.normal_model;
        const bool constant_eps =
            nm && nm->impact &&
            nm->impact(&s->wall_cc, 1e-3).eps_n == nm->impact(&s->wall_cc, 10.0).eps_n;
        if (!constant_eps) {
            if (s->rad) { /* eps_n(v) at a wall depends on the grain's mass and radius */
                return GR_FAIL(err, GR_EINVAL,
                               "%s: [integrator] kind = event: walls with an eps_n(v) rule "
                               "(viscoelastic = true) and [species] are not available yet; "
                               "allowed: a constant eps_n",
                               p->source);
            }
            if (e->rule != GR_EVENT_RULE_hard_sphere) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: [integrator] kind = event: walls with an eps_n(v) rule need "
                               "[model] normal = hard_sphere (given %s)",
                               p->source, nm->name);
            }
            e->wall_visco = true;
            e->wall_ccv = s->wall_cc;
            e->wall_ccv.law_n[GR_HARD_SPHERE_VISCO] = 0.0; /* eps_n_exact, set per hit */
        }
        for (int a = 0; a < s->dim; a++) {
            e->wall[a] = p->walls[a];
            e->grav[a] = p->gravity[a];
        }
        if (p->vibrate) { /* the wall at 0 of axis vibrate - 1 moves (gr_walls_motion) */
            const double w = 2.0 * M_PI * p->frequency;
            e->vib = p->vibrate - 1;
            e->vib_acc = p->motion == GR_WALL_SINE ? p->amplitude * w * w : 0.0;
            e->par = p;
        }
    }
    e->com_every = (int64_t)llround(s->params.com_interval / e->tau);
    e->com_every = e->com_every < 1 ? 1 : e->com_every;
    e->budget = 1000000 + 10 * (int64_t)n;
    e->min_span = 1e-6 * s->params.kick_interval;
    e->work_rate = e->noise ? s->dim * s->params.D * n / e->M : 0.0;
    double m_min = s->mass; /* the lightest grain gets the largest kicks */
    for (int i = 0; e->m && i < n; i++) {
        m_min = fmin(m_min, e->m[i]);
    }
    if (e->m && e->noise) { /* species: d D / m_i per grain */
        e->work_rate = 0.0;
        for (int i = 0; i < n; i++) {
            e->work_rate += s->dim * s->params.D / e->m[i];
        }
    }
    if (e->bath) { /* the bath's factors over one window (driving_langevin.c, with dt = tau) */
        gr_driving_coeffs c = {0};
        int rc = s->params.driving->prepare(&s->params.driving_params, s->dim, e->tau, &c, err);
        if (rc) {
            return rc;
        }
        e->bath_decay = c.decay;
        e->bath_kick = c.kick;
        /* the kick's grain: the first species (a distribution: the mean mass), as in verlet */
        e->bath_m1 = !e->m                         ? s->mass
                     : s->params.size_distribution ? s->mass
                                                   : s->params.species_mass[0];
        /* the floor guard's scale: the bath's mean work per window, dim kick^2 m_1 / 2 per grain */
        e->work_rate = 0.5 * s->dim * c.kick * c.kick * e->bath_m1 * n / e->tau;
    }
    const char *check = getenv("GRANULE_EVENT_CHECK");
    e->check = check && check[0] == '1';
    const char *cal = getenv("GRANULE_EVENT_CALENDAR"); /* benchmarks: calendar.c */
    gr_cal_kind kind;
    if (gr_heap_kind_parse(cal, &kind)) {
        return GR_FAIL(err, GR_EINVAL,
                       "environment variable GRANULE_EVENT_CALENDAR = '%.40s' is not an event "
                       "calendar: use bucket (the "
                       "default), sparse or full (docs/event-driven.md)",
                       cal);
    }
    size_t sz = sizeof(double) * (size_t)(n > 0 ? n : 1);
    double **arrays[] = {&e->t0,   &e->bx, &e->bv,  &e->a1x, &e->a2x, &e->jx,
                         &e->last, &e->by, &e->bw,  &e->a1y, &e->a2y, &e->jy,
                         &e->bz,   &e->bu, &e->a1z, &e->a2z, &e->jz};
    int n_arrays = s->dim == 3 ? 17 : s->dim == 2 ? 12 : 7;
    bool ok = true;
    for (int a = 0; a < n_arrays; a++) {
        *arrays[a] = calloc(1, sz);
        ok = ok && *arrays[a];
    }
    e->g = malloc(sz * 2 * (size_t)s->dim);
    e->past = calloc((size_t)(n > 0 ? n : 1), 1);
    ok = ok && e->g && e->past &&
         !gr_heap_alloc(&e->heap,
                        s->dim == 1 ? (e->wall[0] ? n + 1
                                       : n > 1    ? n
                                                  : 0)
                                    : n,
                        e->tau, kind);
    if (!ok) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the event-driven state of %d particles",
                       n);
    }
    int rc =
        check_speeds(s, s->x, s->vx, s->y, s->vy, s->z, s->vz, s->params.kick_interval, true, err);
    if (rc) {
        return rc;
    }
    /* the same limit for the noise: a 10-sigma velocity increment of one window,
     * sqrt(2 D tau) / M per component (free_flight.h), must not cross the box GR_EV_MAX_BOXES times */
    const double tau = s->params.kick_interval, vlim = GR_EV_MAX_BOXES * s->L / tau;
    if (10.0 * sqrt(2.0 * s->params.D * tau) / m_min > vlim) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [noise] D = %g N^2 s gives velocity kicks of %.3g m/s per kick "
                       "interval (%g s), which would "
                       "cross the box (L = %g m) more than %g times per interval; allowed range "
                       "for the event-driven "
                       "integrator here: [0, %.3g] N^2 s",
                       s->params.source, s->params.D, sqrt(2.0 * s->params.D * tau) / m_min, tau,
                       s->L, GR_EV_MAX_BOXES, pow(vlim * m_min / 10.0, 2) / (2.0 * tau));
    }
    for (int i = 0; i < n; i++) {
        e->bx[i] = s->x[i];
        e->bv[i] = s->vx[i];
        if (s->dim >= 2) {
            e->by[i] = s->y[i];
            e->bw[i] = s->vy[i];
        }
        if (s->dim == 3) {
            e->bz[i] = s->z[i];
            e->bu[i] = s->vz[i];
        }
        e->last[i] = -GR_EV_INF;
    }
    if (s->dim >= 2) {
        rc = s->dim == 2 ? gr_ev2d_alloc(s, err) : gr_ev3d_alloc(s, err);
        if (rc) {
            return rc;
        }
    }
    /* the window containing the current time (a run may start at step > 0 only via restarts) */
    double t = (double)s->step * s->dt;
    e->win = (int64_t)floor(t / e->tau);
    e->now = t - (double)e->win * e->tau; /* bases at the current time inside the window */
    for (int i = 0; i < n; i++) {
        e->t0[i] = e->now;
    }
    e->t_start = t;
    e->guard_mark_t = t;
    e->guard_floor_mark = e->floors;
    e->phase = e->now > e->h;
    for (int i = 0; i < n; i++) {
        e->past[i] = (uint8_t)e->phase;
    }
    start_window(s);
    s->elastic = 0.0;
    s->last = (gr_force_report){0};
    s->share[0] = 1.0;
    s->share[1] = s->share[2] = 0.0;
    snprintf(s->kernel_name, sizeof s->kernel_name, "event-%s%s-%s-tc",
             s->dim == 1   ? "1d-ring"
             : s->dim == 2 ? "2d-"
                           : "3d-",
             s->dim == 1 ? "" : (e->ncell > 1 ? "cells" : "allpairs"),
             e->bath     ? "bath"
             : !e->noise ? "nonoise"
             : e->exact  ? "exact"
                         : "kicks");
    return GR_OK;
}

int gr_event_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    const double T = (double)(s->step + nsteps) * s->dt;
    for (;;) {
        const double local = T - (double)e->win * e->tau;
        const double limit = local < e->tau ? local : e->tau;
        int rc = e->dim == 1   ? process_1d(s, limit, err)
                 : e->dim == 2 ? gr_ev2d_process(s, limit, err)
                               : gr_ev3d_process(s, limit, err);
        if (rc == GR_EV_STOPPED) {
            e->owed_to = s->step + nsteps; /* the next call must reach at least this step */
            return GR_OK; /* stop requested: s->step and the reported state stay where they were */
        }
        if (rc) {
            return rc;
        }
        if (local < e->tau) {
            report(s, local > e->now ? local : e->now);
            break;
        }
        end_window(s);
        rc = check_speeds(s, e->bx, e->bv, e->by, e->bw, e->bz, e->bu, s->params.kick_interval,
                          false, err);
        if (rc) {
            return rc;
        }
        start_window(s);
        if (e->stop && *e->stop) {
            e->owed_to = s->step + nsteps;
            return GR_OK; /* between windows: nothing lost either */
        }
    }
    s->step += nsteps;
    e->owed_to = 0;
    for (int i = 0; i < s->n; i++) {
        double sum = s->x[i] + s->vx[i] + (s->dim >= 2 ? s->y[i] + s->vy[i] : 0.0) +
                     (s->dim == 3 ? s->z[i] + s->vz[i] : 0.0);
        if (!isfinite(sum)) {
            return GR_FAIL(
                err, GR_EUNSTABLE,
                "event-driven run: particle %d has a non-finite position or velocity at t = %.6g s",
                i, gr_sim_time(s));
        }
    }
    return GR_OK;
}

void gr_event_free(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    if (!e) {
        return;
    }
    double *arrays[] = {e->t0,  e->bx, e->bv,   e->by, e->bw, e->a1x, e->a2x, e->jx,  e->a1y,
                        e->a2y, e->jy, e->last, e->g,  e->bz, e->bu,  e->a1z, e->a2z, e->jz};
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; a++) {
        free(arrays[a]);
    }
    free(e->past);
    gr_heap_free(&e->heap);
    free(e->partner);
    free(e->count);
    free(e->ev_count);
    free(e->cell_of);
    free(e->head);
    free(e->next);
    free(e->prev);
    free(e);
    s->integrator_state = NULL;
}

int64_t gr_event_processed(const gr_sim *s)
{
    return gr_ev(s) ? gr_ev(s)->collisions + gr_ev(s)->crossings + gr_ev(s)->kicks : 0;
}

const char *gr_event_calendar(const gr_sim *s)
{
    return gr_ev(s) ? gr_heap_name(&gr_ev(s)->heap) : "none";
}

void gr_event_stats(const gr_sim *s, gr_event_counts *c)
{
    const struct gr_event_state *e = gr_ev(s);
    *c = (gr_event_counts){0};
    if (e) {
        *c = (gr_event_counts){.collisions = e->collisions,
                               .crossings = e->crossings,
                               .kicks = e->kicks,
                               .invalid = e->invalid,
                               .tc_elastic = e->tc_elastic,
                               .floors = e->floors,
                               .floor_energy = e->floor_energy,
                               .walls = e->wall[0] || e->wall[1] || e->wall[2],
                               .wall_hits = e->wall_hits};
    }
}

void gr_event_set_stop(gr_sim *s, volatile sig_atomic_t *stop)
{
    if (gr_ev(s)) {
        gr_ev(s)->stop = stop;
    }
}

void gr_event_set_debug(gr_sim *s, bool check_overlaps, bool no_collisions)
{
    if (gr_ev(s)) {
        gr_ev(s)->check = check_overlaps;
        gr_ev(s)->no_collisions = no_collisions;
        window_any(s);
    }
}
