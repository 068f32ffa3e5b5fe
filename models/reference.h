/* The interface between a tangential law and the CVODE reference of one binary contact
 * (src/collide/reference.c: `granule collide --reference`, and the conformance suite's ground
 * truth for the engine and for the law's own restitution law).
 *
 * The reference integrates the relative motion of two discs in continuous time; it owns the
 * geometry, the normal law (the power-law form F_n = k xi^a - gamma xi^p g.n its prepare
 * declares, gr_contact_coeffs pow_a, pow_p) and the spins. Every tangential law gives it the force
 * it adds, as a `gr_reference_law` in its own file (gr_model.reference): the reference has no
 * switch over the laws, and a law without one is refused by the registry at build time
 * (models/registry.c) and by the conformance suite, never integrated with F_t = 0.
 *
 * Everything is in the reference's units: time 1/w0, velocity V (the impact speed), length
 * V / w0, force m12 w0 V (w0 the normal law's contact frequency at this impact). A law whose
 * force switches regime (sliding stops, a spring sticks or slips, |F_n| changes sign) keeps the
 * regime in `gr_ref_tangential` and reports each switch as a root, so the right-hand side stays
 * smooth between roots and every switch is located exactly. Between spheres whose spins take the
 * contact out of the impact's plane the reference integrates vectors: a law without state acts
 * along -g_c with its plane force at |g_c|, a law with a vector state gives a gr_reference_law3. */
#ifndef GR_MODELS_REFERENCE_H
#define GR_MODELS_REFERENCE_H

#include <stdbool.h>

#include "granule/model.h"

/* the law's own state components: GR_REF_Y_STATE is integrated with error control (the spring's
 * s), GR_REF_Y_QUAD is a quadrature left out of the error test (Mindlin's int k_t s ds) */
enum { GR_REF_Y_STATE = 0, GR_REF_Y_QUAD = 1, GR_REF_NY = 2 };
/* at most this many roots per law (values crossing 0 downwards), and scratch values */
enum { GR_REF_NROOTS = 4, GR_REF_NAUX = 8 };

/* The law's constants and regime. `setup` sets the constants (k[], in the reference's units) and
 * `start` the regime at the touch; only `event` changes the regime afterwards. The reference
 * fills the normal law's scaled form before `setup`. The model's file names the slots. */
typedef struct gr_ref_tangential {
    /* the normal law, set by the reference: F_n = X^pow_a - c_n X^pow_p g.n */
    double c_n, pow_a, pow_p;
    bool clamp;     /* the normal law is clamped (the contact ends where F_n = 0) */
    double k[4];    /* the law's constants */
    bool mode;      /* the law's regime flag (sliding_friction: sliding; the spring: slipping) */
    double sign;    /* the law's regime sign (the direction of sliding or slipping) */
    double fn_sign; /* sign of F_n in the current regime (|F_n| = fn_sign F_n); 1 at the touch */
} gr_ref_tangential;

/* One point of the contact: the reference fills the inputs, `force` the outputs. */
typedef struct gr_ref_point {
    /* inputs */
    double xi;           /* overlap */
    double gn, gt;       /* relative velocity along n and t (t = n rotated by +90 degrees) */
    double gc;           /* the contact point's tangential velocity (gt with the spins' share) */
    double rn;           /* |r| */
    double fn, dfn;      /* the normal force and its rate dF_n/dt */
    double y[GR_REF_NY]; /* the law's own state components */
    /* the rate of gc given the law's force: gr_ref_gc_rate (the geometry's and the spins' share) */
    bool rot;
    double W, q, D; /* rotation: (w1 + w2) / w0, I / (M r^2), the diameter */
    /* outputs */
    double ft;              /* the tangential force along t */
    double ydot[GR_REF_NY]; /* rates of the law's state components */
    double e;               /* the elastic energy the law stores here (the spring's k_t s^2 / 2) */
    double e_work; /* the force's work stored so far (int k_t s ds; e for a constant k_t) */
    double aux[GR_REF_NAUX]; /* the law's scratch values, for its roots and events */
} gr_ref_point;

/* dg_c/dt at the point when the law exerts ft: d(g.t)/dt = F_t - (g.n)(g.t) / |r|, and with
 * rotation g_c = g.t - |r| W / 2 adds -(g.n) W / 2 + |r|^2 F_t / (q D^2) */
static inline double gr_ref_gc_rate(const gr_ref_point *p, double ft)
{
    double dgc = ft - p->gn * p->gt / p->rn;
    if (p->rot) {
        dgc += -0.5 * p->gn * p->W + p->rn * p->rn * ft / (p->q * p->D * p->D);
    }
    return dgc;
}

/* what `event` asks of the reference */
enum {
    GR_REF_RESTART = 1, /* the regime changed: restart the integration here */
    GR_REF_STOP = 2     /* cancel the contact point's tangential velocity (sliding stopped; the
                           reference applies the impulse, to the spins too with rotation) */
};

typedef struct gr_reference_law {
    /* the law's constants in the reference's units, from the prepared coefficients; m12, w0 and
     * len = V / w0 convert them (a force k x becomes k x / (m12 w0 V), so a spring constant is
     * divided by m12 w0^2, a dashpot by m12 w0) */
    void (*setup)(const gr_contact_coeffs *c, double m12, double w0, double len,
                  gr_ref_tangential *l);
    /* optional: the regime at the touch, from g.n and g_c there (has_tangent: g_c is not 0) */
    void (*start)(gr_ref_tangential *l, double gn0, double gc0, bool has_tangent);
    /* F_t at the point, the rates of y, e and e_work (the reference zeroes the outputs first) */
    void (*force)(const gr_ref_tangential *l, gr_ref_point *p);
    /* optional: the values of the law's roots at the point after `force` (1: not in use) */
    void (*roots)(const gr_ref_tangential *l, const gr_ref_point *p, double g[GR_REF_NROOTS]);
    /* optional: at a root (found[k]: root k was reached; p as `force` left it), change the regime
     * and p->y; returns GR_REF_RESTART and GR_REF_STOP bits */
    int (*event)(gr_ref_tangential *l, const bool found[GR_REF_NROOTS], gr_ref_point *p);
    /* optional, a law whose state is a vector in the tangent plane (the history spring): the
     * same five with vectors, for a 3D contact out of the impact's plane (gr_ref_point3 below).
     * A law without them is integrated there along -g_c with its plane force at |g_c|. */
    const struct gr_reference_law3 *sphere;
} gr_reference_law;

/* ---- spheres: the contact out of the impact's plane (src/collide/reference.c, ref3) ---------- *
 * The law's own state components: GR_REF3_Y_VEC..+2 a vector in the tangent plane (integrated with
 * error control), GR_REF3_Y_QUAD a quadrature left out of the error test, as in the plane. */
enum { GR_REF3_Y_VEC = 0, GR_REF3_Y_QUAD = 3, GR_REF3_NY = 4 };

/* |g_c| (units of V) below which sliding counts as stopped: |g_c| reaches 0 without crossing it,
 * so a root is placed just above, and the impulse then cancels the rest */
#define GR_REF3_STOP_FLOOR 1e-10

/* One point of a 3D contact: vectors in the frame of the box, in the reference's units. */
typedef struct gr_ref_point3 {
    /* inputs */
    double xi, gn, rn, fn, dfn; /* overlap, g.n, |r|, F_n and dF_n/dt */
    double n[3], g[3];          /* the normal from 1 to 2, the relative velocity v2 - v1 */
    double gc[3];               /* the contact point's tangential velocity */
    double y[GR_REF3_NY];       /* the law's own state components */
    bool rot;
    double W[3], q, D; /* rotation: (w1 + w2) / w0, I / (M r^2), the diameter */
    /* outputs */
    double ft[3];            /* the tangential force */
    double ydot[GR_REF3_NY]; /* rates of the law's state components */
    double e, e_work;        /* as gr_ref_point's */
    double yscale; /* what an error in the vector state costs: 1 (the state is a length), or the
                      force it turns (a direction: the reference weighs its error by this) */
    double aux[GR_REF_NAUX]; /* the law's scalar scratch values */
    double vaux[2][3];       /* and vector ones */
} gr_ref_point3;

/* dg_c/dt at the point when the law exerts ft, for g_c = g - (g.n) n + (|r| / 2) n x W:
 * dn/dt = g_p / |r| (g_p = g - (g.n) n), so g_p changes at ft - (|g_p|^2 n + (g.n) g_p) / |r|, and
 * with rotation (|r| / 2) n x W at ((g.n) n x W + g_p x W) / 2 + |r|^2 ft / (q D^2) (the torque
 * -(|r| / 2) n x F_t on each sphere), (g x W) / 2 + |r|^2 ft / (q D^2) in all. In the plane its
 * component along t is gr_ref_gc_rate. */
static inline void gr_ref_gc_rate3(const gr_ref_point3 *p, const double ft[3], double dgc[3])
{
    double gp[3];
    double gp2 = 0.0;
    for (int a = 0; a < 3; a++) {
        gp[a] = p->g[a] - p->gn * p->n[a];
        gp2 += gp[a] * gp[a];
    }
    for (int a = 0; a < 3; a++) {
        dgc[a] = ft[a] - (gp2 * p->n[a] + p->gn * gp[a]) / p->rn;
    }
    if (p->rot) {
        /* (g.n) n x W + g_p x W = g x W */
        const double *W = p->W, *g = p->g;
        const double c[3] = {g[1] * W[2] - g[2] * W[1], g[2] * W[0] - g[0] * W[2],
                             g[0] * W[1] - g[1] * W[0]};
        const double rr = p->rn * p->rn / (p->q * p->D * p->D);
        for (int a = 0; a < 3; a++) {
            dgc[a] += 0.5 * c[a] + rr * ft[a];
        }
    }
}

typedef struct gr_reference_law3 {
    /* the state at the touch: p evaluated there with y = 0 (the regime from the law's `start`
     * with |g_c|); sets p->y */
    void (*start)(const gr_ref_tangential *l, gr_ref_point3 *p);
    void (*force)(const gr_ref_tangential *l, gr_ref_point3 *p);
    void (*roots)(const gr_ref_tangential *l, const gr_ref_point3 *p, double g[GR_REF_NROOTS]);
    /* changes the regime and p->y; returns GR_REF_RESTART and GR_REF_STOP bits (the reference
     * cancels g_c with the vector impulse) */
    int (*event)(gr_ref_tangential *l, const bool found[GR_REF_NROOTS], gr_ref_point3 *p);
} gr_reference_law3;

/* ---- rolling laws ----------------------------------------------------------------------------- *
 * A rolling law's torque pair acts on the relative spin dw = w1 - w2 only (equal and opposite on
 * the two particles, no force), across n: the engine applies magnitude M against the part of dw
 * across n (in 2D all of it), limited to what stops the rolling within a step. The reference
 * integrates dw under the full torque while the particles roll on each other, and where its part
 * across n reaches 0 (a root) it is arrested: held there by the torque that takes, the step's cut
 * in continuous time, for as long as that stays within M (3D: the turning normal drags a twist
 * dw.n across; in 2D dw stays 0). */
typedef struct gr_reference_rolling {
    /* the magnitude M of the torque pair (N m) at the normal force |F_n| (N) and the effective
     * radius r_eff (m), from the prepared coefficients (gr_contact_coeffs.law_r) */
    double (*torque)(const gr_contact_coeffs *c, double fn_abs, double r_eff);
} gr_reference_rolling;

#endif
