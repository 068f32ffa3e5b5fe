/* Private state of the hybrid integrator (docs/hybrid.md). Split by job:
 *   hybrid.c  windows, rollbacks, centre-of-mass correction, ledger, stats
 *   active.c  which particles are integrated step by step (1D ring, 2D cell grid), misses
 *   child.c   the child simulation of active particles and its soft-sphere stepping
 *   window_noise.c  the free-flight draw of a window and the kicks bridged to it */
#ifndef GR_HY_INTERNAL_H
#define GR_HY_INTERNAL_H

#include <stdint.h>

#include "integrators/hybrid/hybrid.h"

/* Velocities in an active cluster stay within [min, max] of the cluster's start velocities
 * widened by this fraction of the spread (plus noise and spring release); docs/hybrid.md. */
#define GR_HYBRID_SPREAD 0.5
/* More rollbacks than this in one window: make everybody active (cannot miss). */
#define GR_HYBRID_MAX_ROLLBACKS 8
/* Skin of the 2D candidate-pair list, in diameters (rebuilt when somebody moved half of it). */
#define GR_HYBRID_LIST_SKIN 0.3

typedef struct gr_hybrid_state {
    gr_sim *child;   /* the active particles, capacity N; integrator verlet, no noise of its own */
    int m;           /* steps per full window */
    double margin_c; /* c: margins are c standard deviations of the noise displacement */
    /* bounds over a mixture's grains (species lists, docs/hybrid.md "Mixtures"): the smallest mass
     * (whose noise spreads farthest) and the largest sqrt(k_s / m12) of any pair; M and cc.w0
     * for one species */
    double m_noise, w0_max;
    /* the clusters' velocity widening: GR_HYBRID_SPREAD, plus (m_max - m_min) / (m_max + m_min) for
     * a mixture (a grain of mass m_max hitting one of m_min can push it that fraction of their
     * relative velocity beyond the pair's range; docs/hybrid.md, "Mixtures") */
    double spread;
    int kicks; /* free_flight = kicks */

    /* state at the window start (for rollbacks) */
    double *x0, *y0, *vx0, *vy0, *fx0, *fy0, *gx0, *gy0;
    double *z0, *vz0, *fz0, *gz0; /* 3D only (NULL otherwise) */
    /* rotation ([model] rotation = true): the angular velocity and torque components at the
     * window start, component c of particle i at [c * N + i] (NULL without rotation) */
    double *w0, *t0;
    /* active set: flags, list (parent indices in order), forced-active flags from rollbacks */
    uint8_t *active, *forced;
    int *list, n_active;
    /* union-find parent and per-root bounds for the chain/cluster closure */
    int *uf;
    double *c_lo, *c_hi, *c_xi; /* 1D: velocity bounds; 2D: c_hi = max speed, c_xi = max overlap */
    /* envelopes the active particles must stay in (checked every step by the child): 1D
     * env_lo t <= x(t) - x(0) <= env_hi t; 2D |r(t) - r(0)| <= env_hi t; +-INFINITY = unchecked */
    double *env_lo, *env_hi;
    int *env_list;    /* child indices of the particles whose envelope is checked */
    double *env_pack; /* their start x, y, z, env_lo, env_hi side by side (5 N; child.c) */
    /* 2D candidate pairs (i < j) and the cell grid */
    int *pi, *pj;
    int64_t npairs, cap_pairs;
    double rc_pairs;      /* cutoff of the candidate list (0: none) */
    double *xl, *yl, *zl; /* positions when it was built (zl: 3D only) */
    int *cell_head, *cell_next,
        ncells_alloc; /* cell starts (counting sort) and each particle's cell */
    int *sorted;      /* particles in cell order, with their positions xs, ys, zs (3D) */
    double *xs, *ys, *zs;
    /* the candidate partners of each particle: adj[adj_start[i] .. adj_start[i + 1]) */
    int *adj_start, *adj, adj_ok;
    /* the 2D closure's work list and cluster member lists (active.c) */
    int *mem_head, *mem_tail, *mem_next, *mem_size, *queue;
    uint8_t *inq;
    double *speed; /* |v| of every particle at the window start */
    int64_t cap_adj;

    /* window noise: 2 * dim normals per particle (free-flight draw), kicks of the active set */
    double *ff;   /* ff[(p * dim + c) * 2 + {0,1}] */
    double *kick; /* raw normals of the active particles, kick[(a * m + k) * dim + c] */
    int64_t cap_kick;
    double *
        lam; /* bridge coefficients (l1, l2) of active particle a, component c: lam[2 (a dim + c)] */
    double kick_amp; /* a = sqrt(2 D dt)/M (0 without noise): kick = a (raw + l1 + l2 (m - k)) */
    double *tmp;     /* m * dim raw normals of one particle */

    /* [driving] kind = langevin: the exact Ornstein-Uhlenbeck step of each window at its end, on
     * every grain (hybrid.c, bath_window); bath_g its dim normals per grain; bath_m1 the mass whose
     * kick the bath's coefficients are (a grain of mass m_i: times sqrt(bath_m1 / m_i)) */
    bool bath;
    double *bath_g, bath_m1;

    /* counters */
    int64_t windows, rollbacks, steps, active_steps;
} gr_hybrid_state;

/* active.c */
/* Choose the active set for a window of m steps from the state now (never this window's noise):
 * pairs whose deterministic paths come within d + margin, closed over clusters; plus forced. */
int gr_hy_select(gr_sim *s, gr_hybrid_state *h, int m, gr_error *err);
/* Standard deviations of a free particle's noise displacement and velocity over m steps. */
double gr_hy_noise_sx(const gr_sim *s, const gr_hybrid_state *h, int m);
double gr_hy_noise_sv(const gr_sim *s, const gr_hybrid_state *h, int m);

/* active_2d.c */
/* The 2D active set of a window of m steps (into h->active, envelopes into h->env_hi). */
int gr_hy_select_2d(gr_sim *s, gr_hybrid_state *h, int m, gr_error *err);
/* Every pair closer than rc (minimum image) into h->pi/pj. */
int gr_hy_collect_pairs(gr_sim *s, gr_hybrid_state *h, double rc, gr_error *err);
/* Largest displacement since the candidate list was built (minimum image). */
double gr_hy_max_disp(const gr_sim *s, const gr_hybrid_state *h);

/* Rotation: the simulation's angular velocity and torque components into w and t (2D: omega and
 * tq; 3D: wx, wy, omega and tqx, tqy, tq); returns their count, 0 without rotation. A free
 * particle's spin does not change during a leap (no contact, no torque); the active ones' are
 * kicked by the child as step.c kicks them. */
static inline int gr_hy_spins(gr_sim *s, double *w[3], double *t[3])
{
    if (!s->omega) {
        return 0;
    }
    if (s->dim == 3) {
        w[0] = s->wx;
        w[1] = s->wy;
        w[2] = s->omega;
        t[0] = s->tqx;
        t[1] = s->tqy;
        t[2] = s->tq;
        return 3;
    }
    w[0] = s->omega;
    t[0] = s->tq;
    return 1;
}

static inline double gr_hy_wrap(double dx, double L)
{
    return dx > 0.5 * L ? dx - L : (dx < -0.5 * L ? dx + L : dx);
}

/* active.c */
/* After a window: 1 if some pair with a free member overlaps (1D: or crossed); marks the members
 * of every such pair in h->forced. */
int gr_hy_misses(gr_sim *s, gr_hybrid_state *h, gr_error *err, int *found);

/* window_noise.c */
/* The free-flight normals of all particles for the window starting at step `start`. */
void gr_hy_draw_window(const gr_sim *s, gr_hybrid_state *h, int64_t start);
/* Velocity and position increments (dv, dx beyond v0 tau) of particle p, component c over m
 * steps: exactly the law of m Verlet kicks on a free particle. */
void gr_hy_free_increment(const gr_sim *s, const gr_hybrid_state *h, int m, int p, int c,
                          double *dv, double *dx);
/* Leap every particle that is not active over the window (exact free flight); returns the
 * kinetic energy the noise added. */
double gr_hy_leap_free(gr_sim *s, gr_hybrid_state *h, int m);
/* Per-step kicks of the active particles, bridged to their free-flight increments: raw normals
 * and bridge coefficients (h->kick, h->lam, h->kick_amp); the child forms the kicks. */
int gr_hy_active_kicks(const gr_sim *s, gr_hybrid_state *h, int64_t start, int m, gr_error *err);

/* child.c */
int gr_hy_child_create(gr_sim *s, gr_hybrid_state *h, gr_error *err);
/* Load the active particles into the child, step it m steps, write them back into s. Sets
 * *missed (and h->forced) when an active particle left its envelope: then s is not written. */
int gr_hy_child_run(gr_sim *s, gr_hybrid_state *h, int m, int *missed, gr_error *err);
/* A particle left its envelope: force the free particles it could have reached. */
void gr_hy_envelope_miss(gr_sim *s, gr_hybrid_state *h, int p, int side);

#endif
