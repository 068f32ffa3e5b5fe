/* Private state of the event-driven core (src/integrators/event/). docs/event-driven.md describes the design.
 *
 * Time is cut into global kick windows [k tau, (k + 1) tau). Inside window k every particle
 * follows a known trajectory: acceleration a1 on the first half, a velocity jump J at the middle,
 * acceleration a2 on the second half (exact free flight: a1, a2 of gr_free_flight_accelerations,
 * J = 0; kicks: a1 = a2 = 0, J = the kick), interrupted only by collisions. A particle's trajectory
 * is stored as its state (x, v) at its own base time t0 (local time, offset from the window
 * start) plus `past` (1: the mid-window change is already behind the base). Only events inside
 * the current window are predicted; at the window end everybody is advanced, new noise is drawn
 * and everything is predicted again. Events at the same time are ordered by (time, phase, index),
 * phase 0 meaning "before the mid-window change" at time tau / 2. */
#ifndef GR_EVENT_INTERNAL_H
#define GR_EVENT_INTERNAL_H

#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/sim_internal.h"
#include "integrators/event/event.h"
#include "models/list.h"

#define GR_EV_INF ((double)INFINITY)

/* The event calendar over entries 0..cap-1 keyed by (t, phase, index): calendar.c. */
typedef enum { GR_CAL_SPARSE, GR_CAL_FULL, GR_CAL_BUCKET } gr_cal_kind;
typedef struct gr_heap {
    int m, cap;       /* entries in the calendar, entries in all */
    gr_cal_kind kind; /* GRANULE_EVENT_CALENDAR: bucket (default), sparse or full */
    int *node;        /* heap: node[k] = entry at heap position k */
    int *pos;         /* heap: heap position of entry e; bucket: its bucket; -1 = not in */
    double *t;        /* key of entry e */
    uint8_t *ph;      /* phase of entry e */
    /* bucket: nb buckets of width span / nb over the window, doubly linked lists */
    double span, inv_w;
    int nb, cur; /* buckets, first possibly non-empty one */
    int *head, *next, *prev;
} gr_heap;

struct gr_event_state {
    int n, dim;
    double tau, h; /* window length and its middle */
    int64_t win;   /* current window; it starts at win * tau */
    double now;    /* local time of the last processed event */
    int phase;     /* phase of now */
    double M, L, d, d2;
    double tc; /* the rule's TC time (gr_contact_coeffs.tc; 0: no TC rule) */
    /* the collision: the normal model's event rule (gr_event_rule_of, models/list.h) with the
     * sim's coefficients; rough discs and spheres ([model] rotation = true, 2D and 3D) pass it
     * their spins */
    int rule;
    const gr_contact_coeffs *cc; /* the sim's coefficients (gr_sim.cc) */
    bool rough;
    double q, R;
    /* species ([species] lists, docs/mixtures.md; all NULL without): each grain's mass and
     * radius, its species, and every species pair's coefficients (nsp x nsp, prepared with the
     * pair's reduced mass: its eps_n(v) and TC time). A pair touches at r_i + r_j; d is the
     * largest contact distance (the cells), M the mean mass. */
    const double *m, *r;
    const int *sp;
    int nsp;
    const gr_contact_coeffs *cc_pair;
    /* a radius distribution (m and r set, cc_pair NULL): every pair runs the sim's rule (a
     * constant eps_n; the masses enter through M_ij), and when the TC time is the matching
     * contact's duration, each pair's is tc sqrt(M_ij / tc_m12) (t_c ~ sqrt(M_ij) at one k_s;
     * tc_m12 the reference pair's reduced mass, 0 for a tc given or off) */
    double tc_m12;
    bool exact; /* free_flight = exact */
    bool noise;
    /* [driving] kind = langevin: the bath's exact Ornstein-Uhlenbeck velocity update over one
     * window, applied at each window's end (event.c, bath_window): e^{-tau/tau_b}, the kick of a
     * grain of mass bath_m1 (others: times sqrt(bath_m1 / m_i)) */
    bool bath;
    double bath_decay, bath_kick, bath_m1;
    /* walls and gravity (1D, 2D, 3D; docs/systems-walls-gravity.md, "Event-driven"): wall[a] = flat
     * walls at 0 and L along axis a (no periodic image there), grav[a] the constant acceleration
     * added to every particle's a1, a2; its work is booked as the change of the potential energy,
     * not as injected */
    bool wall[3];
    double grav[3];
    int64_t wall_hits;
    /* the vibrating wall ([boundary] vibrate): the wall at 0 of axis vib (-1: none) stands at
     * gr_walls_motion(par, t) (core/walls.c, as for the verlet integrator); vib_acc bounds its
     * acceleration (A w^2 for a sine, 0 for a sawtooth, whose drops only move it away). Grains on
     * it may go below 0: that axis is not wrapped and its first cell reaches down to -inf. */
    int vib;
    double vib_acc;
    const gr_sim_params *par;
    /* the walls' coefficients as the rule gets them (gr_ev_wall_cc): the sim's wall_cc, or with
     * an eps_n(v) rule (viscoelastic = true) a copy whose constant eps_n is set per hit to the
     * impact's eps_n(v_n) of the grain (mass M) against the infinite wall, since the mirror image
     * doubles the relative speed the rule would see */
    bool wall_visco;
    gr_contact_coeffs wall_ccv;
    /* trajectories */
    double *t0, *bx, *bv, *by, *bw; /* base time, x, vx, y, vy */
    double *bz, *bu;                /* 3D: z, vz (NULL otherwise) */
    uint8_t *past;
    double *a1x, *a2x, *jx, *a1y, *a2y, *jy;
    double *a1z, *a2z, *jz; /* 3D */
    double *last;           /* absolute time of each particle's last collision (TC rule) */
    double *g;              /* scratch for normals, 2 n dim */
    /* calendar */
    gr_heap heap;
    /* 2D, 3D: per-particle event (partner >= 0: collision, -1 - face: cell crossing; faces
     * 0 .. 2 dim - 1, then the walls) */
    int *partner;
    int64_t *count, *ev_count;
    int ncell;   /* cells per side (1 = all pairs, no crossing events); ncell^dim cells */
    double cell; /* cell side */
    int *cell_of, *head, *next, *prev;
    /* statistics */
    int64_t collisions, crossings, kicks, invalid, tc_elastic, floors;
    double injected;     /* booked free-flight work up to each particle's base */
    double floor_energy; /* added by the contact floor (included in injected) */
    int64_t com_every;   /* windows between centre-of-mass resets (com mode) */
    /* test hooks */
    bool check;         /* check for overlaps after every event */
    bool no_collisions; /* free flight only */
    /* progress guard (event.c, gr_ev_guard): every event counts; every GR_EV_POLL events the
     * stop flag is polled, every `budget` events the simulated time they took is checked */
    int64_t guard_n, guard_mark_n, budget;
    double guard_mark_t; /* absolute time at the last check */
    int64_t
        guard_floor_mark; /* floors at the last check (not in checkpoints: set to floors on load) */
    double min_span;      /* shortest time `budget` events may take: 1e-6 kick_interval */
    double work_rate;     /* mean random-force power, W (floor guard) */
    double t_start;       /* absolute time at creation */
    int64_t owed_to;      /* target step of a call that returned early on a stop (0: none) */
    volatile sig_atomic_t *stop; /* gr_event_set_stop: return early when it becomes non-zero */
};

#define GR_EV_POLL 4096
#define GR_EV_STOPPED 1 /* a process function's return: the stop flag was seen, nothing lost */

/* Slow path of gr_ev_guard (event.c): polls the stop flag; every `budget` events fails with a
 * diagnosis if they took less than min_span of simulated time (a diverging event rate). */
int gr_ev_guard_check(gr_sim *s, double t_abs, int i, int j, gr_error *err);

/* min(x, 0) exactly as glibc's fmin(x, 0.0) gives it on x86-64 (0 for NaN, +0 for -0), but
 * inline: fmin is a library call, and the collision-time bounds below run for every pair tested */
static inline double gr_ev_min0(const double x) { return x < 0.0 ? x : 0.0; }

/* Call once per processed calendar entry (collision, crossing, stale entry) before handling it:
 * 0 go on, GR_EV_STOPPED stop requested (the entry stays in the calendar), < 0 unstable. */
static inline int gr_ev_guard(gr_sim *s, struct gr_event_state *e, double t_abs, int i, int j,
                              gr_error *err)
{
    if (++e->guard_n % GR_EV_POLL != 0) {
        return 0;
    }
    return gr_ev_guard_check(s, t_abs, i, j, err);
}

/* After the contact floor added energy (event.c): fails when the floor has injected more than the
 * random force's mean work since creation (at least one window's worth). */
int gr_ev_floor_check(gr_sim *s, int i, int j, double t_abs, double floor_speed, gr_error *err);

/* One component of particle i's trajectory at local time t in the given phase (0: first half of
 * the window, 1: second half). */
static inline void gr_ev_traj(const struct gr_event_state *e, double t0, double bx, double bv,
                              int past, double a1, double a2, double j, double t, int phase,
                              double *x, double *v)
{
    if (past || !phase) { /* the phase, not t, decides: t = h may be off by rounding */
        const double a = past ? a2 : a1, s = t - t0;
        *x = bx + s * (bv + 0.5 * a * s);
        *v = bv + a * s;
    } else {
        const double s1 = e->h - t0, s2 = t - e->h;
        const double xh = bx + s1 * (bv + 0.5 * a1 * s1);
        const double vh = bv + a1 * s1 + j;
        *x = xh + s2 * (vh + 0.5 * a2 * s2);
        *v = vh + a2 * s2;
    }
}

static inline void gr_ev_state_x(const struct gr_event_state *e, int i, double t, int phase,
                                 double *x, double *v)
{
    gr_ev_traj(e, e->t0[i], e->bx[i], e->bv[i], e->past[i], e->a1x[i], e->a2x[i], e->jx[i], t,
               phase, x, v);
}

static inline void gr_ev_state_y(const struct gr_event_state *e, int i, double t, int phase,
                                 double *y, double *v)
{
    gr_ev_traj(e, e->t0[i], e->by[i], e->bw[i], e->past[i], e->a1y[i], e->a2y[i], e->jy[i], t,
               phase, y, v);
}

static inline void gr_ev_state_z(const struct gr_event_state *e, int i, double t, int phase,
                                 double *z, double *v)
{
    gr_ev_traj(e, e->t0[i], e->bz[i], e->bu[i], e->past[i], e->a1z[i], e->a2z[i], e->jz[i], t,
               phase, z, v);
}

/* First time in [0, T] at which f(t) = f0 + f1 t + c t^2 is <= 0 while decreasing (a contact or
 * a crossing), or GR_EV_INF. f0 <= 0 and f1 < 0: now (an overlapping pair that approaches,
 * Bannerman et al. 2014); f0 <= 0 and not approaching: the first time it starts to approach
 * while still overlapping, or the next down-crossing. Roots use the cancellation-free forms
 * (../shared/notes/physics-algorithms.md sec. 3.3). */
static inline double gr_ev_first_quadratic(double f0, double f1, double c, double T)
{
    if (f0 <= 0.0) {
        if (f1 < 0.0) {
            return 0.0;
        }
        if (c >= 0.0) {
            return GR_EV_INF;
        }
        const double ts = -0.5 * f1 / c; /* f' = 0 */
        if (ts > T) {
            return GR_EV_INF;
        }
        if (f0 + ts * (f1 + c * ts) <= 0.0) {
            return ts;
        }
        /* positive in between: the larger root */
        const double disc = f1 * f1 - 4.0 * c * f0;
        const double q = -0.5 * (f1 + sqrt(disc > 0.0 ? disc : 0.0));
        const double t = q / c;
        return t <= T ? t : GR_EV_INF;
    }
    if (f0 + T * (gr_ev_min0(f1) + T * gr_ev_min0(c)) > 0.0) {
        return GR_EV_INF; /* a lower bound of f on [0, T] stays positive */
    }
    if (c == 0.0) {
        const double t = -f0 / f1;
        return t <= T ? t : GR_EV_INF;
    }
    const double disc = f1 * f1 - 4.0 * c * f0;
    if (disc < 0.0) {
        return GR_EV_INF;
    }
    double t;
    if (f1 < 0.0) {
        t = f0 / (0.5 * (-f1 + sqrt(disc))); /* the smaller positive root */
    } else {
        t = -0.5 * (f1 + sqrt(disc)) / c; /* c < 0: the only positive root */
    }
    return t <= T ? t : GR_EV_INF;
}

/* First time in [0, T] at which the quartic f(t) = sum_k c[k] t^k is <= 0 while decreasing:
 * monotone pieces of f are isolated by the real roots of f' (which come from those of f''),
 * then bisection with Newton steps. event_solve.c. */
double gr_ev_first_quartic(const double c[5], double T);

/* The vibrating wall (wall_time in event_cells.h): the first time u in [0, T] at which the gap
 * h(u) = q0 + v0 u + acc u^2 / 2 - r - q_w(tw + u) is <= 0 while decreasing, q_w the wall of
 * gr_walls_motion(p, .) and C >= |h''| (|acc| + vib_acc), or GR_EV_INF. May return an earlier
 * time at which h > 0 (a checkpoint after GR_EV_WALL_STEPS steps): the caller predicts again
 * from there. event_solve.c. */
#define GR_EV_WALL_STEPS 64
double gr_ev_moving_wall_first(const gr_sim_params *p, double tw, double q0, double v0, double acc,
                               double r, double C, double T);

/* The first hit within one piece of constant acceleration acc (length T, starting at local time
 * t0 with the grain at q moving at v along axis a) of the wall at 0 (side 0; the vibrating one on
 * axis vib) or at L (side 1): the centre reaching r = d / 2 from it while moving towards it
 * (gr_ev_first_quadratic; gr_ev_moving_wall_first for the vibrating wall), or GR_EV_INF. */
static inline double gr_ev_wall_piece(const struct gr_event_state *e, int a, int side, double t0,
                                      double q, double v, double acc, double T, double r)
{
    if (side) {
        return gr_ev_first_quadratic(e->L - r - q, -v, -0.5 * acc, T);
    }
    return a == e->vib ? gr_ev_moving_wall_first(e->par, (double)e->win * e->tau + t0, q, v, acc, r,
                                                 fabs(acc) + e->vib_acc, T)
                       : gr_ev_first_quadratic(q - r, v, 0.5 * acc, T);
}

/* A vibrating wall's state at absolute time t: *vw its velocity, *aw its acceleration along its
 * axis; returns the gap of a grain of radius r at q to it. */
static inline double gr_ev_vib_wall(const struct gr_event_state *e, double t, double q, double r,
                                    double *vw, double *aw)
{
    double qw;
    gr_walls_motion(e->par, t, &qw, vw);
    const double w = 2.0 * M_PI * e->par->frequency;
    *aw = e->par->motion == GR_WALL_SINE ? -w * w * qw : 0.0;
    return q - r - qw;
}

/* The energy the moving wall gave a grain in a hit: the change of its kinetic energy (translation
 * v -> u over dim components, and spin w0 -> w1 of rough grains over k components) plus the
 * hit's losses. */
static inline double gr_ev_wall_work(double m, double inertia, int dim, const double *v,
                                     const double *u, const double *w0, const double *w1, int k,
                                     bool elastic, double de_n, double de_t)
{
    double dk = 0.0, dr = 0.0;
    for (int a = 0; a < dim; a++) {
        dk += u[a] * u[a] - v[a] * v[a];
    }
    for (int a = 0; a < k; a++) {
        dr += w1[a] * w1[a] - w0[a] * w0[a];
    }
    return 0.5 * m * dk + 0.5 * inertia * dr + (elastic ? 0.0 : de_n + de_t);
}

/* The walls' coefficients for a hit at the normal speed vn (> 0) towards the wall. */
static inline const gr_contact_coeffs *gr_ev_wall_cc(gr_sim *s, struct gr_event_state *e, double vn)
{
    if (!e->wall_visco) {
        return &s->wall_cc;
    }
    e->wall_ccv.eps_n_exact = s->wall_cc.normal_model->impact(&s->wall_cc, vn).eps_n;
    return &e->wall_ccv;
}

/* calendar (calendar.c) */
/* "bucket" (also NULL or ""), "sparse" or "full" into *kind; -1 for anything else */
int gr_heap_kind_parse(const char *name, gr_cal_kind *kind);
const char *gr_heap_name(const gr_heap *h);
int gr_heap_alloc(gr_heap *h, int cap, double span, gr_cal_kind kind); /* 0 or -1 (out of memory) */
void gr_heap_free(gr_heap *h);
void gr_heap_build(gr_heap *h);         /* after every key was set (window start, restore) */
void gr_heap_update(gr_heap *h, int e); /* after entry e's key changed */
int gr_heap_min(gr_heap *h);            /* the next entry, -1 if none */

/* common helpers (event.c) */
int gr_ev_record(gr_sim *s, int i, int kind, double t, double x, double y, double vx, double vy,
                 gr_error *err);
/* The contact distance of i and j: r_i + r_j with species, d without. */
static inline double gr_ev_d(const struct gr_event_state *e, int i, int j)
{
    return e->r ? e->r[i] + e->r[j] : e->d;
}

/* Particle i's mass: its own with species, M without. */
static inline double gr_ev_mass(const struct gr_event_state *e, int i)
{
    return e->m ? e->m[i] : e->M;
}

/* Particle i's radius: its own with species, d / 2 without. */
static inline double gr_ev_radius(const struct gr_event_state *e, int i)
{
    return e->r ? e->r[i] : 0.5 * e->d;
}

/* Particle i's moment of inertia (rough grains): q m_i r_i^2 with species, the sim's without. */
static inline double gr_ev_inertia(const gr_sim *s, const struct gr_event_state *e, int i)
{
    return e->m ? e->q * e->m[i] * e->r[i] * e->r[i] : s->inertia;
}

/* The TC time of the pair i, j: its species pair's (the matching contact of its reduced mass,
 * unless [model] tc gives one for all), a distribution's pair's (tc_m12 above), the sim's without
 * species. */
static inline double gr_ev_tc(const struct gr_event_state *e, int i, int j)
{
    if (e->cc_pair) {
        return e->cc_pair[e->sp[i] * e->nsp + e->sp[j]].tc;
    }
    if (e->tc_m12 > 0.0) {
        return e->tc * sqrt(e->m[i] * e->m[j] / (e->m[i] + e->m[j]) / e->tc_m12);
    }
    return e->tc;
}

/* The event rule's coefficients for the pair i, j: its species pair's with species lists, the
 * sim's otherwise (one species, or a radius distribution). */
static inline const gr_contact_coeffs *gr_ev_pair_cc(const struct gr_event_state *e, int i, int j)
{
    return e->cc_pair ? &e->cc_pair[e->sp[i] * e->nsp + e->sp[j]] : e->cc;
}

/* TC rule: restitution coefficients of a collision between i and j at absolute time t */
static inline bool gr_ev_tc_elastic(const struct gr_event_state *e, int i, int j, double t)
{
    const double tc = gr_ev_tc(e, i, j);
    return t - e->last[i] < tc || t - e->last[j] < tc;
}

/* The model's event rule on the pair i (p->v1) and j (p->v2). Without species: the rule as
 * written, two grains of mass M. With species the rule runs with the pair's coefficients on two
 * equal grains of mass 2 M_ij (M_ij = m_i m_j / (m_i + m_j), the reduced mass): a Galilean
 * invariant rule then gives the relative velocity the change it gives any pair of reduced mass
 * M_ij, through the impulse P = M_ij dg it computed (its losses de_n, de_t are the pair's), and
 * the velocities are rebuilt from P with the real masses: v_i += (2 m_j / (m_i + m_j)) dv1 =
 * P / m_i, v_j likewise, so m_i v_i + m_j v_j is conserved.
 *
 * Rough discs (p->w1, 2D): the contact point divides r_i + r_j as r_i : r_j, so its relative
 * tangential velocity is g.t + r_i w_i + r_j w_j and Walton's rule holds with the pair's tangential
 * mass m_t = M_ij q / (1 + q) (1 / m_t = 1 / m_i + 1 / m_j + r_i^2 / I_i + r_j^2 / I_j, I_i =
 * q m_i r_i^2). The rule runs on the surface speeds u = r w with R = 1 (its g_ct is then exactly
 * that sum) and changes both u by -P_t / (q 2 M_ij); grain i's spin changes by the torque's
 * -P_t r_i / I_i = (2 m_j / (m_i + m_j)) du / r_i, the weight of its velocity, over its radius. */
static inline void gr_ev_rule(const struct gr_event_state *e, int i, int j, gr_event_pair *p)
{
    if (!e->m) {
        p->M = e->M;
        gr_event_rule_apply(e->rule, e->cc, p);
        return;
    }
    const double mi = e->m[i], mj = e->m[j], v1x = p->v1x, v1y = p->v1y, v2x = p->v2x, v2y = p->v2y;
    double *w1 = p->w1, *w2 = p->w2, u[2] = {0.0, 0.0};
    if (w1) { /* rough: the surface speeds r_i w_i, r_j w_j */
        u[0] = e->r[i] * *w1;
        u[1] = e->r[j] * *w2;
        p->w1 = &u[0];
        p->w2 = &u[1];
        p->R = 1.0;
    }
    const double u0[2] = {u[0], u[1]};
    p->M = 2.0 * mi * mj / (mi + mj);
    gr_event_rule_apply(e->rule, gr_ev_pair_cc(e, i, j), p);
    const double wi = 2.0 * mj / (mi + mj), wj = 2.0 * mi / (mi + mj);
    p->v1x = v1x + wi * (p->v1x - v1x);
    p->v1y = v1y + wi * (p->v1y - v1y);
    p->v2x = v2x + wj * (p->v2x - v2x);
    p->v2y = v2y + wj * (p->v2y - v2y);
    if (w1) {
        *w1 += wi * (u[0] - u0[0]) / e->r[i];
        *w2 += wj * (u[1] - u0[1]) / e->r[j];
        p->w1 = w1;
        p->w2 = w2;
    }
}

/* The contact floor's share of a relative normal speed change for i (*fi) and j (*fj): 1/2 each
 * without species, m_j / (m_i + m_j) and m_i / (m_i + m_j) with (momentum conserved). */
static inline void gr_ev_floor_shares(const struct gr_event_state *e, int i, int j, double *fi,
                                      double *fj)
{
    *fi = e->m ? e->m[j] / (e->m[i] + e->m[j]) : 0.5;
    *fj = e->m ? e->m[i] / (e->m[i] + e->m[j]) : 0.5;
}

/* Gravity's work on a particle displaced by (dx, dy) since its base, in the units of the
 * injected-energy sums (velocity^2: booked as 0.5 M * ...): 2 g . dr. The free-flight work
 * booked as injected is the change of kinetic energy minus this. */
static inline double gr_ev_gravity_work(const struct gr_event_state *e, double dx, double dy)
{
    return 2.0 * (e->grav[0] * dx + e->grav[1] * dy);
}

/* The same for spheres: 0 without gravity (so a periodic 3D run's sums are what they were). */
static inline double gr_ev_gravity_work_3d(const struct gr_event_state *e, double dx, double dy,
                                           double dz)
{
    const bool on = e->grav[0] != 0.0 || e->grav[1] != 0.0 || e->grav[2] != 0.0;
    return on ? 2.0 * (e->grav[0] * dx + e->grav[1] * dy + e->grav[2] * dz) : 0.0;
}

/* 2D and 3D cores: event_cells.h instantiated for discs (event_2d.c) and spheres (event_3d.c) */
int gr_ev2d_alloc(gr_sim *s, gr_error *err);
void gr_ev2d_window(gr_sim *s); /* cells and all predictions at a window start */
int gr_ev2d_process(gr_sim *s, double t_limit, gr_error *err);
int gr_ev3d_alloc(gr_sim *s, gr_error *err);
void gr_ev3d_window(gr_sim *s);
int gr_ev3d_process(gr_sim *s, double t_limit, gr_error *err);

#endif
