/* The reference integration of one binary contact: gr_collide_reference integrates the relative
 * motion of two identical discs through a single contact with SUNDIALS CVODE (variable-order
 * Adams, Newton iteration with a dense 7x7 solver, rtol 1e-12) and root-finding, so the engine's
 * time-stepped kernels and the exact restitution formulas can be checked against an independent,
 * essentially exact answer (`granule collide --reference` and the collision tests).
 *
 * Physics (thesis sec. 2.1.2), in the relative frame r = x2 - x1, g = v2 - v1, m12 = M/2:
 *   m12 dg/dt = F_n n + F_t t,   dr/dt = g,   n = r/|r|,  t = n rotated by +90 deg (2.8),
 *   F_n = k_s xi - gamma_n g.n,  xi = d - |r| > 0                                   (2.4-2.5)
 *   or any power law F_n = k xi^a - gamma xi^p g.n the model declares (gr_contact_coeffs pow_a,
 *   pow_p): hertz has a = 3/2, p = 1/2 (viscoelastic) or 1/4 (Tsuji)
 *   F_t the tangential law's own, from its model file (gr_model.reference, models/reference.h:
 *   its force, state components, regime at the touch, roots and events), e.g. the dashpot
 *   F_t = -gamma_t g.t (2.9), sliding friction F_t = -mu |F_n| sign(g.t) until g.t stops (2.7),
 *   the Cundall-Strack spring's stick and slip (models/tangential_spring_reference.h). There is
 *   no switch over the laws here: a tangential law without a reference force is refused.
 * The unclamped contact ends when xi returns to 0 (the thesis); with clamping, F_n = max(0, F_n),
 * it ends when F_n falls to 0 while the pair separates, after which the pair moves apart
 * force-free (Schwager & Poeschel, Granular Matter 9, 465 (2007)). The tangential force acts in
 * the same window (xi > 0 unclamped, F_n > 0 clamped).
 *
 * Numerics. The state is nondimensionalised with the undamped contact frequency w0 = sqrt(k/m12)
 * (a power law: w0 = (k V^(a-1) / m12)^(1/(a+1)), which makes the scaled spring force X^a)
 * and the impact speed V = |g|: time w0 t, velocity g / V, length (r - r_c) w0 / V where r_c is
 * the separation at first touch (|r_c| = d exactly), so every component is O(1) and one scalar
 * atol serves all. The overlap is computed without cancellation as
 *   xi = d - |r_c + u| = -(2 r_c.u + u.u) / (d + |r_c + u|).
 * The contact starts at the analytic touching time of the free flight (ray-circle), at xi = 0.
 * Events are CVODE roots: the end of the contact (xi or F_n crossing 0 downwards), the maximum
 * overlap (g.n crossing 0 upwards, so max_overlap is exact to the root tolerance, not sampled),
 * and the tangential law's own roots (sliding_friction: the end of sliding, g.t crossing 0, where
 * the law switches to F_t = 0, g is projected on n and CVODE restarts; the sign change of F_n
 * inside |F_n| for an unclamped law). The right-hand side always uses the smooth continuation of
 * the current regime, so each event is a clean root rather than a kink inside a step. The impulses are integrated as two extra state
 * components, J_n = int |F_n| dt and J_t = int |F_t| dt (projections on the instantaneous n and
 * t), so "friction impulse <= mu x normal impulse" also holds when the unclamped law pulls.
 *
 * Rotation (gr_contact_coeffs.rotation, discs of moment of inertia I = q M r^2 at rest before):
 * the tangential law sees the contact point's velocity g.t + S, S = -a (w1 + w2) in this t's
 * sign (the engine's t is the opposite, models/law.h), a = |r| / 2 the lever arm of both discs,
 * and the torques a F_t on both give d(w1 + w2)/dt = -2 a F_t / I. W = (w1 + w2) / w0 is a
 * seventh state component (scaled: dW/dtau = -2 |r| f_t / (q D^2), D the scaled diameter; at
 * |r| = d, dS/dt = F_t / (q m12)), so the contact point's restitution, the spins and the energy
 * they carry come out of the same integration. The end of sliding is then g.t + S = 0.
 *
 * Refused (GR_EINVAL / GR_EUNSTABLE, never integrated to a wrong answer): an unclamped contact
 * at critical or over-damping (zeta >= 1: xi decays to 0 but never returns to it, the pair
 * sticks), a contact still running after 1000 undamped contact times, and an overlap that
 * reaches 95% of the diameter (the normal is about to become undefined).
 *
 * The geometry is the full one: n turns while the discs overlap, so oblique results differ from
 * the small-overlap formulas (2.13)-(2.14) by O(xi_max / d) (1e-4 at xi/d = 1e-4; several per cent
 * for Table 2.1's 1 kg discs at k_s = 5e5 N/m, whose overlaps reach a third of d). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "granule/collide.h"
#include "models/reference.h"

enum { REF_NEQ = 12, REF_NROOT = 8 };
/* Y_S, Y_KS the tangential law's own state components (GR_REF_Y_STATE, GR_REF_Y_QUAD: the
 * spring's s and the Mindlin spring's int k_t s ds), Y_DN the energy the normal law dissipates,
 * Y_WT the work of the tangential force on the contact point's motion, Y_R the relative spin
 * (w1 - w2) / w0 a rolling law acts on */
enum { Y_U0 = 0, Y_U1, Y_G0, Y_G1, Y_JN, Y_JT, Y_W, Y_S, Y_DN, Y_WT, Y_KS, Y_R };
static const int y_law[GR_REF_NY] = {[GR_REF_Y_STATE] = Y_S, [GR_REF_Y_QUAD] = Y_KS};
/* ROOT_LAW0..3 the tangential law's roots 0..3 (models/reference.h) */
enum {
    ROOT_END = 0,
    ROOT_MAX_OVERLAP,
    ROOT_LAW0,
    ROOT_LAW1,
    ROOT_DEGENERATE,
    ROOT_LAW2,
    ROOT_LAW3,
    ROOT_ROLL /* the rolling law's relative spin reaching 0 */
};
static const int root_law[GR_REF_NROOTS] = {ROOT_LAW0, ROOT_LAW1, ROOT_LAW2, ROOT_LAW3};

#define REF_ATOL 1e-14            /* nondimensional: state components are O(1) */
#define REF_GUARD_CONTACTS 1000.0 /* give up after this many undamped contact times pi/w0 */
#define REF_MAX_STEPS 1000000L    /* per CVode call */
#define REF_TANGENT_FLOOR 1e-12   /* |g.t| / |g| below this counts as zero (head-on) */
#define REF_AXIAL_FLOOR 0.05      /* give up when r.n0 falls to this fraction of d */

typedef struct ref_ctx {
    double D;                    /* diameter in units of V / w0 */
    double n0[2];                /* unit normal at first touch, from 1 to 2 */
    double c_n;                  /* gamma_n len^p / (m12 w0) (= 2 zeta for the linear law) */
    double pow_a, pow_p;         /* the normal law's powers (1, 0 linear) */
    bool rot;                    /* rotation: the law sees g.t - (|r| / 2) W */
    double q;                    /* rotation: I / (M r^2) */
    const gr_reference_law *law; /* the tangential law's force (NULL: none) */
    gr_ref_tangential lt;        /* its constants and regime */
    /* the rolling law (NULL: none): its torque M(|F_n|, r_eff) in SI from the coefficients; the
     * relative spin changes at -roll_rate M (units w0^2 / (N m)) against itself while `rolling` */
    const gr_reference_rolling *roll;
    const gr_contact_coeffs *coeffs;
    double force_unit, r_eff, roll_rate, roll_sign;
    bool rolling;
    bool clamp;
    bool degenerate; /* the centres met: n undefined */
    char msg[256];   /* last SUNDIALS error or warning */
} ref_ctx;

typedef struct ref_state {
    double n[2], t[2]; /* instantaneous normal and tangent */
    double xi;         /* overlap, units V / w0 */
    double axial;      /* r . n0 / d: 1 at the touch, 0 when the centres meet */
    double gn, gt;     /* relative velocity along n and t, units V */
    double gc;         /* the contact point's tangential velocity, gt (- |r| W / 2 with rotation) */
    double rn;         /* |r|, units V / w0 */
    double fn, ft;     /* forces along n and t, units m12 w0 V */
    gr_ref_point law;  /* what the tangential law saw and returned */
} ref_state;

/* The rate dF_n/dt of F_n = X^a - c_n X^p g.n (the clamp only ends the contact where F_n = 0),
 * from d xi/dt = -g.n and d(g.n)/dt = F_n + (g.t)^2 / |r| (F_t along t leaves g.n alone), for a
 * tangential law whose force depends on it (the spring's Coulomb limit, mu |F_n|) */
static double ref_fn_rate(const ref_ctx *c, double xi, double gn, double fn, double gp2, double rn)
{
    /* gp2 = |g - (g.n) n|^2 ((g.t)^2 in the plane): d(g.n)/dt = F_n + gp2 / |r| */
    const double X = fmax(xi, 0.0), dxi = -gn;
    if (c->pow_a == 1.0 && c->pow_p == 0.0) {
        return dxi - c->c_n * (fn + gp2 / rn);
    }
    /* X^(p-1): singular at X = 0 (a damping ~ X^p grows infinitely fast from the touch); 0 past
     * the end, where CVODE may try a point and the contact no longer acts */
    const double xp1 = X > 0.0 && c->pow_p != 0.0 ? c->pow_p * pow(X, c->pow_p - 1.0) : 0.0;
    return c->pow_a * pow(X, c->pow_a - 1.0) * dxi -
           c->c_n * (xp1 * dxi * gn + pow(X, c->pow_p) * (fn + gp2 / rn));
}

/* The rolling law's torque pair's magnitude at the scaled normal force fn, times roll_rate: the
 * rate at which it changes the scaled relative spin (w1 - w2) / w0 */
static double ref_roll_rate(const ref_ctx *c, double fn)
{
    return c->roll ? c->roll_rate * c->roll->torque(c->coeffs, fabs(fn) * c->force_unit, c->r_eff)
                   : 0.0;
}

/* Geometry and forces of the current regime at state y (smooth in y). */
static int ref_eval(ref_ctx *c, const double *y, ref_state *s)
{
    double rx = c->D * c->n0[0] + y[Y_U0];
    double ry = c->D * c->n0[1] + y[Y_U1];
    double rn = hypot(rx, ry);
    /* The centres met (xi = d) or the line of centres turned by 90 degrees: no sensible normal. */
    s->axial = (rx * c->n0[0] + ry * c->n0[1]) / c->D;
    if (!(s->axial > 1e-6)) {
        c->degenerate = true;
        return -1;
    }
    s->n[0] = rx / rn;
    s->n[1] = ry / rn;
    s->t[0] = -s->n[1];
    s->t[1] = s->n[0];
    double u_dot_rc = c->D * (c->n0[0] * y[Y_U0] + c->n0[1] * y[Y_U1]);
    double uu = y[Y_U0] * y[Y_U0] + y[Y_U1] * y[Y_U1];
    s->xi = -(2.0 * u_dot_rc + uu) / (c->D + rn);
    s->gn = y[Y_G0] * s->n[0] + y[Y_G1] * s->n[1];
    s->gt = y[Y_G0] * s->t[0] + y[Y_G1] * s->t[1];
    s->rn = rn;
    s->gc = c->rot ? s->gt - 0.5 * rn * y[Y_W] : s->gt;
    if (c->pow_a == 1.0 && c->pow_p == 0.0) {
        s->fn = s->xi - c->c_n * s->gn; /* k_s xi - gamma_n g.n over m12 w0 V (2.4-2.5) */
    } else {
        const double X = fmax(s->xi, 0.0); /* CVODE may try a point just past the end */
        s->fn = pow(X, c->pow_a) - c->c_n * pow(X, c->pow_p) * s->gn;
    }
    s->law = (gr_ref_point){0};
    if (c->law) {
        gr_ref_point *p = &s->law;
        p->xi = s->xi;
        p->gn = s->gn;
        p->gt = s->gt;
        p->gc = s->gc;
        p->rn = rn;
        p->fn = s->fn;
        p->dfn = ref_fn_rate(c, s->xi, s->gn, s->fn, s->gt * s->gt, rn);
        for (int k = 0; k < GR_REF_NY; k++) {
            p->y[k] = y[y_law[k]];
        }
        p->rot = c->rot;
        p->W = y[Y_W];
        p->q = c->q;
        p->D = c->D;
        c->law->force(&c->lt, p);
    }
    s->ft = s->law.ft;
    return 0;
}

static int ref_rhs(sunrealtype t, N_Vector yv, N_Vector ydotv, void *user)
{
    (void)t;
    ref_ctx *c = user;
    const double *y = N_VGetArrayPointer(yv);
    double *yd = N_VGetArrayPointer(ydotv);
    ref_state s;
    if (ref_eval(c, y, &s) != 0) {
        return 1; /* recoverable: CVODE retries a smaller step, fails if the path goes there */
    }
    yd[Y_U0] = y[Y_G0];
    yd[Y_U1] = y[Y_G1];
    yd[Y_G0] = s.fn * s.n[0] + s.ft * s.t[0];
    yd[Y_G1] = s.fn * s.n[1] + s.ft * s.t[1];
    yd[Y_JN] = fabs(s.fn);
    yd[Y_JT] = fabs(s.ft);
    yd[Y_W] = c->rot ? -2.0 * s.rn * s.ft / (c->q * c->D * c->D) : 0.0;
    /* energy: the normal law's non-conservative force -(F_n - X^a) works -(F_n - X^a) g.n; the
     * tangential force works F_t g_c, of which a spring stores int k_t s ds, k_t s^2 / 2 at the
     * end for a constant k_t (so only the Mindlin spring integrates it, Y_KS: its k_t(xi)
     * changes the stored k_t s^2 / 2 by s^2 dk_t/dt / 2 besides, without any work) */
    for (int k = 0; k < GR_REF_NY; k++) {
        yd[y_law[k]] = s.law.ydot[k];
    }
    const bool linear = c->pow_a == 1.0 && c->pow_p == 0.0; /* its F_n is smooth across xi = 0 */
    yd[Y_DN] = -(s.fn - (linear ? s.xi : pow(fmax(s.xi, 0.0), c->pow_a))) * s.gn;
    yd[Y_WT] = -s.ft * s.gc;
    /* the rolling torques (equal and opposite) change w1 - w2 only, against its sign, until it
     * reaches 0 (ROOT_ROLL); in the plane nothing drives it again */
    yd[Y_R] = c->rolling ? -c->roll_sign * ref_roll_rate(c, s.fn) : 0.0;
    return 0;
}

static int ref_roots(sunrealtype t, N_Vector yv, sunrealtype *gout, void *user)
{
    (void)t;
    ref_ctx *c = user;
    ref_state s;
    if (ref_eval(c, N_VGetArrayPointer(yv), &s) != 0) {
        return -1;
    }
    gout[ROOT_END] = c->clamp ? s.fn : s.xi;
    gout[ROOT_MAX_OVERLAP] = s.gn;
    gout[ROOT_DEGENERATE] = s.axial - REF_AXIAL_FLOOR;
    double g[GR_REF_NROOTS] = {1.0, 1.0, 1.0, 1.0};
    if (c->law && c->law->roots) {
        c->law->roots(&c->lt, &s.law, g);
    }
    for (int k = 0; k < GR_REF_NROOTS; k++) {
        gout[root_law[k]] = g[k];
    }
    gout[ROOT_ROLL] = c->rolling ? c->roll_sign * N_VGetArrayPointer(yv)[Y_R] : 1.0;
    return 0;
}

static void ref_err_handler(int code, const char *module, const char *function, char *msg,
                            void *user)
{
    (void)code;
    ref_ctx *c = user;
    snprintf(c->msg, sizeof c->msg, "%s/%s: %s", module ? module : "?", function ? function : "?",
             msg ? msg : "");
}

/* Record a failed SUNDIALS call; the flag name comes from CVODE (malloc'ed, freed here). */
static int ref_fail_flag(gr_error *err, const ref_ctx *c, const char *what, int flag)
{
    char *name = CVodeGetReturnFlagName(flag);
    int rc = GR_FAIL(err, GR_EIO, "reference collision: %s failed (%s)%s%s", what,
                     name ? name : "unknown flag", c->msg[0] ? ": " : "", c->msg);
    free(name);
    return rc;
}

#define REF_CHECK(call, what)                                                                      \
    do {                                                                                           \
        int flag_ = (call);                                                                        \
        if (flag_ < 0) {                                                                           \
            rc = ref_fail_flag(err, &ctx, (what), flag_);                                          \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

/* The solver's objects (Adams with a dense Newton solver of neq equations), freed by ref_free
 * whatever was allocated. */
typedef struct ref_solver {
    SUNContext sunctx;
    N_Vector y;
    SUNMatrix A;
    SUNLinearSolver LS;
    void *mem;
} ref_solver;

static int ref_alloc(ref_solver *v, int neq, gr_error *err)
{
    *v = (ref_solver){0};
    if (SUNContext_Create(NULL, &v->sunctx) != 0 || !v->sunctx) {
        v->sunctx = NULL;
        return GR_FAIL(err, GR_ENOMEM, "reference collision: SUNContext_Create failed");
    }
    v->y = N_VNew_Serial(neq, v->sunctx);
    v->A = v->y ? SUNDenseMatrix(neq, neq, v->sunctx) : NULL;
    v->LS = v->A ? SUNLinSol_Dense(v->y, v->A, v->sunctx) : NULL;
    v->mem = v->LS ? CVodeCreate(CV_ADAMS, v->sunctx) : NULL;
    return v->mem ? GR_OK
                  : GR_FAIL(err, GR_ENOMEM,
                            "reference collision: could not allocate the CVODE "
                            "solver");
}

static void ref_free(ref_solver *v)
{
    if (v->mem) {
        CVodeFree(&v->mem);
    }
    if (v->LS) {
        SUNLinSolFree(v->LS);
    }
    if (v->A) {
        SUNMatDestroy(v->A);
    }
    if (v->y) {
        N_VDestroy(v->y);
    }
    if (v->sunctx) {
        SUNContext_Free(&v->sunctx);
    }
}

/* ---- spheres with spins about any axis (dim = 3, the contact out of the impact's plane) ---- *
 *
 * The same relative motion with vectors: r = r_c + u (3 components), g, W = (w1 + w2) / w0 (the
 * difference w1 - w2 takes no torque without a rolling law), in the units above. The contact
 * point's tangential velocity is g_c = g - (g.n) n + (|r| / 2) n x W (src/core/kernels_3d.c),
 * and each sphere takes the torque -(|r| / 2) n x F_t, so dW/dtau = -2 |r| (n x f_t) / (q D^2). A
 * law whose state or force is a vector in the tangent plane gives its own 3D force, state, roots
 * and events (gr_reference_law3, models/reference.h; its state in Z_LAW..): the history spring,
 * and sliding friction (F_t = -mu |F_n| along g_c until |g_c| falls below GR_REF3_STOP_FLOOR, the
 * root that stops the sliding, where the vector impulse that cancels g_c is applied, as the
 * plane's scalar one; then the force that holds g_c at 0 while it is within the limit). Any other
 * (the tangential dashpot) acts along -g_c with the magnitude its plane force gives at |g_c|, as
 * the engine applies a law without history. */
enum {
    Z_U = 0,
    Z_G = 3,
    Z_W = 6,
    Z_JN = 9,
    Z_JT = 10,
    Z_DN = 11,
    Z_WT = 12,
    Z_LAW = 13,               /* the vector law's GR_REF3_NY components */
    Z_R = Z_LAW + GR_REF3_NY, /* (w1 - w2) / w0, which only a rolling law changes */
    Z_NEQ = Z_R + 3
};
enum {
    Z_ROOT_END = 0,
    Z_ROOT_MAX_OVERLAP = 1,
    Z_ROOT_LAW0 = 2,
    Z_ROOT_ROLL = 2 + GR_REF_NROOTS, /* rolling: arrested; arrested: rolling again */
    Z_NROOT
};

typedef struct ref3_ctx {
    ref_ctx base; /* D, c_n, the powers, q, rot, clamp, the law; messages (ref_err_handler) */
    double rc[3]; /* the separation at the touch, |rc| = D */
    const gr_reference_law3 *vec; /* the law's vector form (NULL: along -g_c at |g_c|) */
    double rtol;
    double roll_floor; /* |Rp| where a rolling law's rolling counts as stopped */
} ref3_ctx;

typedef struct ref3_state {
    double n[3], rn, xi, gn, fn, gc[3], ft[3], gcm;
    gr_ref_point law;   /* the law's point (|g_c| for g_c), as its force left it */
    gr_ref_point3 law3; /* or the vector law's */
    double e, e_work;   /* the law's stored energy and int F ds of it (either form) */
} ref3_state;

static double ref3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void ref3_cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static int ref3_eval(ref3_ctx *c, const double *y, ref3_state *s)
{
    const ref_ctx *b = &c->base;
    double r[3];
    for (int k = 0; k < 3; k++) {
        r[k] = c->rc[k] + y[Z_U + k];
    }
    s->rn = sqrt(ref3_dot(r, r));
    if (!(ref3_dot(r, c->rc) / (b->D * b->D) > REF_AXIAL_FLOOR)) {
        c->base.degenerate = true; /* the centres (nearly) met: no sensible normal */
        return -1;
    }
    for (int k = 0; k < 3; k++) {
        s->n[k] = r[k] / s->rn;
    }
    const double *u = y + Z_U, *g = y + Z_G;
    s->xi = -(2.0 * ref3_dot(u, c->rc) + ref3_dot(u, u)) / (b->D + s->rn);
    s->gn = ref3_dot(g, s->n);
    if (b->pow_a == 1.0 && b->pow_p == 0.0) {
        s->fn = s->xi - b->c_n * s->gn;
    } else {
        const double X = fmax(s->xi, 0.0);
        s->fn = pow(X, b->pow_a) - b->c_n * pow(X, b->pow_p) * s->gn;
    }
    double nw[3] = {0.0, 0.0, 0.0};
    if (b->rot) {
        ref3_cross(s->n, y + Z_W, nw);
    }
    for (int k = 0; k < 3; k++) {
        s->gc[k] = g[k] - s->gn * s->n[k] + 0.5 * s->rn * nw[k];
        s->ft[k] = 0.0;
    }
    const double gcm = sqrt(ref3_dot(s->gc, s->gc));
    s->gcm = gcm;
    s->e = s->e_work = 0.0;
    if (c->vec) {
        gr_ref_point3 *p = &s->law3;
        *p = (gr_ref_point3){.xi = s->xi,
                             .gn = s->gn,
                             .rn = s->rn,
                             .fn = s->fn,
                             .rot = b->rot,
                             .q = b->q,
                             .D = b->D};
        double gp2 = 0.0;
        for (int k = 0; k < 3; k++) {
            p->n[k] = s->n[k];
            p->g[k] = g[k];
            p->gc[k] = s->gc[k];
            p->W[k] = b->rot ? y[Z_W + k] : 0.0;
            const double gp = g[k] - s->gn * s->n[k];
            gp2 += gp * gp;
        }
        for (int k = 0; k < GR_REF3_NY; k++) {
            p->y[k] = y[Z_LAW + k];
        }
        p->dfn = ref_fn_rate(b, s->xi, s->gn, s->fn, gp2, s->rn);
        c->vec->force(&b->lt, p);
        memcpy(s->ft, p->ft, sizeof s->ft);
        s->e = p->e;
        s->e_work = p->e_work;
        return 0;
    }
    s->law = (gr_ref_point){.xi = s->xi,
                            .gn = s->gn,
                            .gt = gcm,
                            .gc = gcm,
                            .rn = s->rn,
                            .fn = s->fn,
                            .rot = b->rot,
                            .q = b->q,
                            .D = b->D};
    if (b->law && gcm > 0.0) {
        b->law->force(&b->lt, &s->law);
        for (int k = 0; k < 3; k++) {
            s->ft[k] = s->law.ft / gcm * s->gc[k];
        }
        s->e = s->law.e;
        s->e_work = s->law.e_work;
    }
    return 0;
}

/* The rolling law between spheres: R = (w1 - w2) / w0, its part across n, Rp = R - (R.n) n, is
 * what the torque pair acts on (the twist R.n it leaves alone; src/core/kernels_3d.c). Rolling,
 * R changes at the full rate against Rp (`ref_roll_rate`) until |Rp| falls to `roll_floor` (a
 * rolling velocity of 1e-10 V), where the rest is cancelled and the rolling is arrested: R then
 * turns with n (dR/dt = (R.n) dn/dt, dn/dt = g_p / |r|, which keeps Rp at 0, the engine's cap
 * as dt -> 0) while the torque that takes, |R.n| |dn/dt| over the rate, stays within the law's;
 * beyond it rolling resumes, against the direction the turning normal drags Rp. Sets the rate of
 * R and the root's value (falling through 0 at either switch). */
static void ref3_roll(const ref3_ctx *c, const double *y, const ref3_state *s, double rate[3],
                      double *root)
{
    const double *R = y + Z_R;
    const double Rn = ref3_dot(R, s->n);
    double Rp[3], nd[3];
    const double gn = ref3_dot(y + Z_G, s->n);
    for (int k = 0; k < 3; k++) {
        Rp[k] = R[k] - Rn * s->n[k];
        nd[k] = (y[Z_G + k] - gn * s->n[k]) / s->rn;
    }
    const double rpm = sqrt(ref3_dot(Rp, Rp)), full = ref_roll_rate(&c->base, s->fn);
    const double drag = fabs(Rn) * sqrt(ref3_dot(nd, nd)); /* the rate that holds Rp at 0 */
    if (c->base.rolling) {
        double e[3] = {0.0, 0.0, 0.0};
        const double dm = sqrt(ref3_dot(nd, nd));
        for (int k = 0; k < 3; k++) { /* at Rp = 0 the normal's turn drags it along -(R.n) dn/dt */
            e[k] = rpm > 0.0 ? Rp[k] / rpm
                             : (dm > 0.0 && Rn != 0.0 ? -Rn * nd[k] / (fabs(Rn) * dm) : 0.0);
            rate[k] = -full * e[k];
        }
        *root = rpm - c->roll_floor;
    } else {
        for (int k = 0; k < 3; k++) {
            rate[k] = Rn * nd[k];
        }
        *root = full - drag;
    }
}

static int ref3_rhs(sunrealtype t, N_Vector yv, N_Vector ydotv, void *user)
{
    (void)t;
    ref3_ctx *c = user;
    const double *y = N_VGetArrayPointer(yv);
    double *yd = N_VGetArrayPointer(ydotv);
    ref3_state s;
    if (ref3_eval(c, y, &s) != 0) {
        return 1;
    }
    double nf[3];
    ref3_cross(s.n, s.ft, nf);
    for (int k = 0; k < 3; k++) {
        yd[Z_U + k] = y[Z_G + k];
        yd[Z_G + k] = s.fn * s.n[k] + s.ft[k];
        yd[Z_W + k] = c->base.rot ? -2.0 * s.rn * nf[k] / (c->base.q * c->base.D * c->base.D) : 0.0;
    }
    yd[Z_JN] = fabs(s.fn);
    yd[Z_JT] = sqrt(ref3_dot(s.ft, s.ft));
    const bool linear = c->base.pow_a == 1.0 && c->base.pow_p == 0.0;
    yd[Z_DN] = -(s.fn - (linear ? s.xi : pow(fmax(s.xi, 0.0), c->base.pow_a))) * s.gn;
    yd[Z_WT] = -ref3_dot(s.ft, s.gc);
    for (int k = 0; k < GR_REF3_NY; k++) {
        yd[Z_LAW + k] = c->vec ? s.law3.ydot[k] : 0.0;
    }
    double rr[3] = {0.0, 0.0, 0.0}, root;
    if (c->base.roll) {
        ref3_roll(c, y, &s, rr, &root);
    }
    for (int k = 0; k < 3; k++) {
        yd[Z_R + k] = rr[k];
    }
    return 0;
}

static int ref3_roots(sunrealtype t, N_Vector yv, sunrealtype *gout, void *user)
{
    (void)t;
    ref3_ctx *c = user;
    ref3_state s;
    if (ref3_eval(c, N_VGetArrayPointer(yv), &s) != 0) {
        return -1;
    }
    gout[Z_ROOT_END] = c->base.clamp ? s.fn : s.xi;
    gout[Z_ROOT_MAX_OVERLAP] = s.gn;
    double g[GR_REF_NROOTS] = {1.0, 1.0, 1.0, 1.0};
    if (c->vec) {
        c->vec->roots(&c->base.lt, &s.law3, g);
    } else if (c->base.law && c->base.law->roots) {
        gr_ref_point p = s.law;
        p.gc = p.gt = s.gcm - GR_REF3_STOP_FLOOR; /* crosses 0 where |g_c| reaches the floor */
        c->base.law->roots(&c->base.lt, &p, g);
    }
    for (int k = 0; k < GR_REF_NROOTS; k++) {
        gout[Z_ROOT_LAW0 + k] = g[k];
    }
    gout[Z_ROOT_ROLL] = 1.0;
    if (c->base.roll) {
        double rr[3];
        ref3_roll(c, N_VGetArrayPointer(yv), &s, rr, &gout[Z_ROOT_ROLL]);
    }
    return 0;
}

/* The error weights (CVEwtFn): CVODE's 1 / (rtol |y| + atol), but the quadrature left out (as in
 * the plane) and the vector law's state weighed by what its error costs (gr_ref_point3.yscale:
 * slipping, the state is the force's direction, whose error matters only as much as the force,
 * which vanishes where F_n changes sign or the contact ends; there that direction turns on a
 * time scale that vanishes too, and weighing it as a length would stall the integration). */
static int ref3_weights(N_Vector yv, N_Vector ewtv, void *user)
{
    ref3_ctx *c = user;
    const double *y = N_VGetArrayPointer(yv);
    double *w = N_VGetArrayPointer(ewtv);
    double scale = 1.0;
    ref3_state s;
    if (c->vec && ref3_eval(c, y, &s) == 0) {
        scale = s.law3.yscale;
    }
    for (int k = 0; k < Z_NEQ; k++) {
        const double a = fabs(y[k]);
        if (k == Z_LAW + GR_REF3_Y_QUAD) {
            w[k] = 1e-300;
        } else if (k >= Z_LAW + GR_REF3_Y_VEC && k < Z_LAW + GR_REF3_Y_VEC + 3) {
            w[k] = fmax(scale / (c->rtol * a * scale + REF_ATOL), 1e-300);
        } else {
            w[k] = 1.0 / (c->rtol * a + REF_ATOL);
        }
    }
    return 0;
}

/* Integrate the 3D contact from the touch: ctx set up as for the plane (its n0 the normal at the
 * touch in the plane z = 0), G0 = g / V; fills out as gr_collide_reference does. */
static int ref3_integrate(ref_ctx *base, const gr_collide_setup *s, const gr_collision_case *cs,
                          const gr_contact_coeffs *coeffs, double w0, double len, double speed,
                          const double G0[2], gr_collide_result *out, gr_error *err)
{
    const double m12 = 0.5 * s->mass;
    ref3_ctx ctx = {.base = *base,
                    .rc = {base->D * base->n0[0], base->D * base->n0[1], 0.0},
                    .vec = base->law ? base->law->sphere : NULL};
    const double n0[3] = {base->n0[0], base->n0[1], 0.0}, g0[3] = {G0[0], G0[1], 0.0};
    double W0[3];
    for (int k = 0; k < 3; k++) {
        W0[k] = (s->w1[k] + s->w2[k]) / w0;
    }
    ref_solver v;
    int rc = ref_alloc(&v, Z_NEQ, err);
    if (rc) {
        ref_free(&v);
        return rc;
    }
    void *mem = v.mem;
    N_Vector y = v.y;
    double *yd = N_VGetArrayPointer(y);
    memset(yd, 0, sizeof(double) * Z_NEQ);
    double R0[3] = {0.0, 0.0, 0.0}; /* the relative spin a rolling law acts on */
    for (int k = 0; k < 3; k++) {
        yd[Z_G + k] = g0[k];
        yd[Z_W + k] = base->rot ? W0[k] : 0.0;
        R0[k] = base->roll ? (s->w1[k] - s->w2[k]) / w0 : 0.0;
        yd[Z_R + k] = R0[k];
    }
    ctx.roll_floor = GR_REF3_STOP_FLOOR / (0.25 * base->D); /* r_eff |Rp| w0 = 1e-10 V */
    int rootdir[Z_NROOT] = {[Z_ROOT_END] = -1, [Z_ROOT_MAX_OVERLAP] = 1, [Z_ROOT_ROLL] = -1};
    for (int k = 0; k < GR_REF_NROOTS; k++) {
        rootdir[Z_ROOT_LAW0 + k] = -1; /* the law's roots cross 0 downwards */
    }
    /* the law's regime at the touch, from |g_c| there (the plane's start took the plane's g_c) */
    {
        double nw[3] = {0.0, 0.0, 0.0};
        if (base->rot) {
            ref3_cross(n0, W0, nw);
        }
        const double gn = ref3_dot(g0, n0);
        double gc[3];
        for (int k = 0; k < 3; k++) {
            gc[k] = g0[k] - gn * n0[k] + 0.5 * base->D * nw[k];
        }
        const double gcm = sqrt(ref3_dot(gc, gc));
        if (ctx.base.law && ctx.base.law->start) {
            ctx.base.law->start(&ctx.base.lt, gn, gcm, gcm >= REF_TANGENT_FLOOR);
        }
    }
    ref3_state st;
    if (ctx.vec) { /* the vector law's state at the touch */
        if (ref3_eval(&ctx, yd, &st) != 0) {
            rc =
                GR_FAIL(err, GR_EUNSTABLE, "reference collision: degenerate geometry at the touch");
            goto done3;
        }
        ctx.vec->start(&ctx.base.lt, &st.law3);
        memcpy(yd + Z_LAW, st.law3.y, sizeof st.law3.y);
    }
    if (ctx.base.roll) { /* rolling at the touch unless arrested there (its root's value >= 0) */
        double rr[3], root;
        if (ref3_eval(&ctx, yd, &st) != 0) {
            rc =
                GR_FAIL(err, GR_EUNSTABLE, "reference collision: degenerate geometry at the touch");
            goto done3;
        }
        ctx.base.rolling = false;
        ref3_roll(&ctx, yd, &st, rr, &root);
        const double Rn = ref3_dot(R0, n0);
        const double rp2 = ref3_dot(R0, R0) - Rn * Rn;
        ctx.base.rolling = sqrt(fmax(rp2, 0.0)) > ctx.roll_floor || root < 0.0;
    }
    int flag;
#define REF3_CHECK(call, what)                                                                     \
    if ((flag = (call)) < 0) {                                                                     \
        rc = ref_fail_flag(err, &ctx.base, (what), flag);                                          \
        goto done3;                                                                                \
    }
    REF3_CHECK(CVodeSetErrHandlerFn(mem, ref_err_handler, &ctx.base), "CVodeSetErrHandlerFn");
    REF3_CHECK(CVodeInit(mem, ref3_rhs, 0.0, y), "CVodeInit");
    ctx.rtol = s->ref_rtol > 0.0 ? s->ref_rtol : 1e-12;
    REF3_CHECK(CVodeWFtolerances(mem, ref3_weights), "CVodeWFtolerances");
    REF3_CHECK(CVodeSetUserData(mem, &ctx), "CVodeSetUserData");
    REF3_CHECK(CVodeSetLinearSolver(mem, v.LS, v.A), "CVodeSetLinearSolver");
    REF3_CHECK(CVodeSetMaxNumSteps(mem, REF_MAX_STEPS), "CVodeSetMaxNumSteps");
    REF3_CHECK(CVodeRootInit(mem, Z_NROOT, ref3_roots), "CVodeRootInit");
    REF3_CHECK(CVodeSetRootDirection(mem, rootdir), "CVodeSetRootDirection");
    REF3_CHECK(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn");
#undef REF3_CHECK
    double tau = 0.0, xi_max = 0.0;
    for (;;) {
        flag = CVode(mem, REF_GUARD_CONTACTS * M_PI, y, &tau, CV_NORMAL);
        if (flag < 0) {
            rc = ctx.base.degenerate
                     ? GR_FAIL(err, GR_EUNSTABLE,
                               "reference collision: the particle centres met; k_s = %g N/m is "
                               "too soft for this impact speed",
                               coeffs->k_s)
                     : ref_fail_flag(err, &ctx.base, "CVode", flag);
            goto done3;
        }
        ctx.base.degenerate = false;
        if (flag != CV_ROOT_RETURN) {
            rc = GR_FAIL(err, GR_EINVAL,
                         "reference collision: contact did not end within %g undamped contact "
                         "times",
                         REF_GUARD_CONTACTS);
            goto done3;
        }
        int found[Z_NROOT];
        CVodeGetRootInfo(mem, found);
        if (ref3_eval(&ctx, yd, &st) == 0 && found[Z_ROOT_MAX_OVERLAP]) {
            xi_max = fmax(xi_max, st.xi);
        }
        if (found[Z_ROOT_END]) {
            break;
        }
        bool found_law[GR_REF_NROOTS];
        bool any = false;
        for (int k = 0; k < GR_REF_NROOTS; k++) {
            found_law[k] = found[Z_ROOT_LAW0 + k] != 0;
            any = any || found_law[k];
        }
        const gr_reference_law *law = ctx.base.law;
        int ev = 0;
        if (any && ctx.vec) {
            ev = ctx.vec->event(&ctx.base.lt, found_law, &st.law3);
            memcpy(yd + Z_LAW, st.law3.y, sizeof st.law3.y);
        } else if (any && law && law->event) {
            ev = law->event(&ctx.base.lt, found_law, &st.law);
        }
        if (ev & GR_REF_STOP) {
            /* sliding stopped: the impulse J (units m12 V, in the tangent plane) that cancels the
             * residual g_c: J on g, -2 rho (n x J) / (q |r|) on W, rho = (|r| / D)^2, so g_c
             * changes by J (1 + rho / q) */
            const double rho = base->rot ? st.rn * st.rn / (base->D * base->D) : 0.0;
            const double f = base->rot ? 1.0 / (1.0 + rho / base->q) : 1.0;
            double J[3], nJ[3];
            for (int k = 0; k < 3; k++) {
                J[k] = -f * st.gc[k];
            }
            ref3_cross(st.n, J, nJ);
            for (int k = 0; k < 3; k++) {
                yd[Z_G + k] += J[k];
                if (base->rot) {
                    yd[Z_W + k] -= 2.0 * (rho / base->q) * nJ[k] / st.rn;
                }
            }
        }
        if (found[Z_ROOT_ROLL] && ctx.base.roll) {
            if (ctx.base.rolling) { /* arrested: cancel the rest of Rp (an angular impulse) */
                const double Rn = ref3_dot(yd + Z_R, st.n);
                for (int k = 0; k < 3; k++) {
                    yd[Z_R + k] = Rn * st.n[k];
                }
            }
            ctx.base.rolling = !ctx.base.rolling;
            ev |= GR_REF_RESTART;
        }
        if (ev & GR_REF_RESTART) {
            if ((flag = CVodeReInit(mem, tau, y)) < 0) {
                rc = ref_fail_flag(err, &ctx.base, "CVodeReInit", flag);
                goto done3;
            }
        }
    }
    if (ref3_eval(&ctx, yd, &st) != 0) {
        rc = GR_FAIL(err, GR_EUNSTABLE, "reference collision: degenerate geometry at the end");
        goto done3;
    }
    memset(out, 0, sizeof *out);
    const double *G1 = yd + Z_G;
    double w1a[3], w2a[3];
    for (int k = 0; k < 3; k++) { /* w1 = (W + R) w0 / 2, w2 = (W - R) w0 / 2 */
        const double dw = base->rot ? 0.5 * (yd[Z_W + k] - W0[k]) * w0 : 0.0;
        const double dr = 0.5 * (yd[Z_R + k] - R0[k]) * w0;
        w1a[k] = s->w1[k] + dw + dr;
        w2a[k] = s->w2[k] + dw - dr;
    }
    const double spin_scale = base->rot ? 0.5 * base->q * base->D * base->D / (w0 * w0) : 0.0;
    const double spin_e0 = spin_scale * (ref3_dot(s->w1, s->w1) + ref3_dot(s->w2, s->w2));
    const double spin_e = spin_scale * (ref3_dot(w1a, w1a) + ref3_dot(w2a, w2a));
    const double gg0 = ref3_dot(g0, g0), gg1 = ref3_dot(G1, G1), e0 = 0.5 * (gg0 + spin_e0);
    out->energy_loss = 1.0 - (gg1 + spin_e) / (gg0 + spin_e0);
    out->spin_loss = (spin_e0 - spin_e) / (gg0 + spin_e0);
    /* as in the plane: the spring's stored energy at the end is lost with the contact, and its
     * int F ds is work stored, not dissipated */
    out->diss_normal = yd[Z_DN] / e0;
    out->diss_tangential = (yd[Z_WT] - st.e_work) / e0;
    out->stored_lost = (pow(fmax(st.xi, 0.0), base->pow_a + 1.0) / (base->pow_a + 1.0) + st.e) / e0;
    out->work_free = (st.e - st.e_work) / e0;
    out->diss_rolling =
        0.25 * spin_scale * (ref3_dot(R0, R0) - ref3_dot(yd + Z_R, yd + Z_R)) * w0 * w0 / e0;
    const double gn0 = ref3_dot(g0, n0);
    out->impact_angle = atan2(sqrt(fmax(gg0 - gn0 * gn0, 0.0)), -gn0) * (180.0 / M_PI);
    out->expected_loss = (double)NAN; /* the restitution laws assume no spin before */
    out->contact_time = tau / w0;
    out->max_overlap = xi_max * len;
    out->eps_n_measured = -st.gn / gn0;
    /* the contact point's tangential restitution, as the engine measures it (collide.c) */
    double gc0[3], nw0[3] = {0.0, 0.0, 0.0};
    if (base->rot) {
        ref3_cross(n0, W0, nw0);
    }
    for (int k = 0; k < 3; k++) {
        gc0[k] = g0[k] - gn0 * n0[k] + 0.5 * base->D * nw0[k];
    }
    double u[3] = {gc0[0], gc0[1], gc0[2]};
    const double un = ref3_dot(u, st.n);
    for (int k = 0; k < 3; k++) {
        u[k] -= un * st.n[k];
    }
    const double gc0m = sqrt(ref3_dot(gc0, gc0)), um = sqrt(ref3_dot(u, u));
    out->eps_t_measured =
        gc0m >= REF_TANGENT_FLOOR && um > 0.0 ? ref3_dot(st.gc, u) / (um * gc0m) : (double)NAN;
    out->tangential_reversed = ref3_dot(st.gc, gc0) < 0.0;
    out->normal_impulse = fabs(yd[Z_JN]) * m12 * speed;
    out->tangential_impulse = fabs(yd[Z_JT]) * m12 * speed;
    for (int k = 0; k < 3; k++) {
        const double P = m12 * speed * (G1[k] - g0[k]), v1 = k < 2 ? cs->v1[k] : 0.0,
                     v2 = k < 2 ? cs->v2[k] : 0.0;
        out->v1[k] = v1 - P / s->mass;
        out->v2[k] = v2 + P / s->mass;
        out->w1[k] = w1a[k];
        out->w2[k] = w2a[k];
    }
    out->omega1 = w1a[2];
    out->omega2 = w2a[2];
    if (!isfinite(out->energy_loss) || !isfinite(out->eps_n_measured)) {
        rc = GR_FAIL(err, GR_EUNSTABLE, "reference collision: non-finite result");
    }
done3:
    ref_free(&v);
    return rc;
}

static int reference_run(const gr_collide_setup *s, const gr_collision_case *cs,
                         gr_collide_result *out, gr_error *err, bool sphere3d);

/* Spheres (dim = 3). The case lies in the plane z = 0; when the spins' sum w1 + w2 is along z,
 * the contact point's velocity g - (g.n) n + a n x (w1 + w2) stays in the plane too, so the
 * contact is exactly the 2D one with the spins' z components (their x and y components, equal
 * and opposite, give the contact point no velocity and take no torque; with a rolling law, which
 * would act on their difference, there are none). The reference then integrates that contact and
 * puts the spheres' x and y spins back, their energy counted in the fractions' denominator.
 * Other spins move the contact out of the plane: integrated in 3D (ref3_integrate above), the
 * history spring with its vector state, a rolling law on w1 - w2 across n. */
static int reference_3d(const gr_collide_setup *s, const gr_collision_case *cs,
                        gr_collide_result *out, gr_error *err)
{
    const bool spun = s->w1[0] != 0.0 || s->w1[1] != 0.0 || s->w1[2] != 0.0 || s->w2[0] != 0.0 ||
                      s->w2[1] != 0.0 || s->w2[2] != 0.0;
    if (spun && !(s->contact.rotation && s->tangential)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: initial spins need rotation ([model] rotation = true "
                       "with a tangential law; allowed without: 0,0,0)");
    }
    const bool rolls_xy = s->rolling && (s->w1[0] != s->w2[0] || s->w1[1] != s->w2[1]);
    if (s->w1[0] + s->w2[0] != 0.0 || s->w1[1] + s->w2[1] != 0.0 || rolls_xy) {
        return reference_run(s, cs, out, err, true);
    }
    gr_collide_setup plane = *s;
    plane.dim = 2;
    plane.omega1 = s->w1[2];
    plane.omega2 = s->w2[2];
    int rc = reference_run(&plane, cs, out, err, false);
    if (rc) {
        return rc;
    }
    /* the fractions of E: E = m12 |g|^2 / 2 + I |w1|^2 / 2 + I |w2|^2 / 2, the x and y spins'
     * share unchanged by the contact */
    const double I = s->contact.inertia_factor * s->mass * s->radius * s->radius;
    const double g[2] = {cs->v2[0] - cs->v1[0], cs->v2[1] - cs->v1[1]};
    const double e_plane =
        0.25 * s->mass * (g[0] * g[0] + g[1] * g[1]) +
        (s->contact.rotation ? 0.5 * I * (plane.omega1 * plane.omega1 + plane.omega2 * plane.omega2)
                             : 0.0);
    const double e_xy = s->contact.rotation ? 0.5 * I *
                                                  (s->w1[0] * s->w1[0] + s->w1[1] * s->w1[1] +
                                                   s->w2[0] * s->w2[0] + s->w2[1] * s->w2[1])
                                            : 0.0;
    const double f = e_plane / (e_plane + e_xy);
    if (e_xy > 0.0) {
        out->expected_loss = (double)NAN; /* the restitution laws assume no spin before */
    }
    out->energy_loss *= f;
    out->spin_loss *= f;
    out->diss_normal *= f;
    out->diss_tangential *= f;
    out->stored_lost *= f;
    out->work_free *= f;
    out->v1[2] = out->v2[2] = 0.0;
    for (int k = 0; k < 2; k++) {
        out->w1[k] = s->w1[k];
        out->w2[k] = s->w2[k];
    }
    out->w1[2] = out->omega1;
    out->w2[2] = out->omega2;
    return GR_OK;
}

int gr_collide_reference(const gr_collide_setup *s, const gr_collision_case *cs,
                         gr_collide_result *out, gr_error *err)
{
    if (!s || !cs || !out) {
        return GR_FAIL(err, GR_EINVAL, "reference collision: NULL argument");
    }
    return s->dim == 3 ? reference_3d(s, cs, out, err) : reference_run(s, cs, out, err, false);
}

/* sphere3d: the 3D contact out of the plane (ref3_integrate; s->dim = 3), else the 1D or 2D
 * contact */
static int reference_run(const gr_collide_setup *s, const gr_collision_case *cs,
                         gr_collide_result *out, gr_error *err, bool sphere3d)
{
    if (!s->normal) {
        return GR_FAIL(err, GR_EINVAL, "reference collision: no normal collision model given");
    }
    if (s->tangential && !(s->tangential->reference && s->tangential->reference->setup &&
                           s->tangential->reference->force)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: the tangential law '%s' gives no reference force "
                       "(gr_model.reference, models/reference.h); the CVODE reference integrates "
                       "only laws that do",
                       s->tangential->name);
    }
    if (s->rolling && !(s->rolling->reference_rolling && s->rolling->reference_rolling->torque)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: the rolling law '%s' gives no reference torque "
                       "(gr_model.reference_rolling, models/reference.h)",
                       s->rolling->name);
    }
    if (!(s->mass > 0.0) || !isfinite(s->mass) || !(s->radius > 0.0) || !isfinite(s->radius)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: mass (%g kg) and radius (%g m) must be positive",
                       s->mass, s->radius);
    }
    if (s->dim != 1 && s->dim != 2 && !sphere3d) {
        return GR_FAIL(err, GR_EINVAL, "reference collision: dim must be 1, 2 or 3, not %d",
                       s->dim);
    }

    const double m12 = 0.5 * s->mass;
    const double d = 2.0 * s->radius;
    gr_contact_coeffs coeffs;
    int rc = gr_contact_prepare(s->normal, s->tangential, &s->contact, m12, 0.0, &coeffs, err);
    if (rc == GR_OK && s->rolling) {
        rc = gr_contact_prepare_rolling(s->rolling, &s->contact, m12, 0.0, &coeffs, err);
    }
    if (rc != GR_OK) {
        return rc;
    }
    if (!(coeffs.pow_a >= 1.0) || !(coeffs.pow_p >= 0.0) || (s->normal->kind & GR_MODEL_EVENT)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "reference collision: '%s' is not a power-law force (k xi^a - gamma xi^p g.n); "
            "the CVODE reference integrates force laws only",
            s->normal->name);
    }
    const bool linear = coeffs.pow_a == 1.0 && coeffs.pow_p == 0.0;
    if (!(coeffs.k_s > 0.0) || !isfinite(coeffs.k_s) || !(coeffs.gamma_n >= 0.0) ||
        !isfinite(coeffs.gamma_n) || !(coeffs.gamma_t >= 0.0) || !isfinite(coeffs.gamma_t) ||
        !(coeffs.mu >= 0.0) || !isfinite(coeffs.mu)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: invalid coefficients (k_s %g, gamma_n %g, gamma_t "
                       "%g, mu %g)",
                       coeffs.k_s, coeffs.gamma_n, coeffs.gamma_t, coeffs.mu);
    }

    /* Unclamped and critically (or over-) damped, zeta >= 1, the overlap decays towards 0 but
     * never returns to it: the pair sticks and the contact never ends. Integrating would only
     * find a spurious crossing once xi sinks below the tolerance, so refuse up front. */
    const double zeta = coeffs.gamma_n / (2.0 * sqrt(coeffs.k_s * m12));
    if (linear && !coeffs.clamp && zeta >= 1.0) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: contact did not end (the pair sticks: critical "
                       "damping, zeta = %g >= 1 with clamp = false)",
                       zeta);
    }

    /* Relative free flight r(t) = r + g t; 1D keeps the x components only (head-on). */
    double r[2] = {cs->x2[0] - cs->x1[0], cs->x2[1] - cs->x1[1]};
    double g[2] = {cs->v2[0] - cs->v1[0], cs->v2[1] - cs->v1[1]};
    if (s->dim == 1) {
        r[1] = 0.0;
        g[1] = 0.0;
    }
    const double speed = hypot(g[0], g[1]);
    const double sep = hypot(r[0], r[1]);
    if (!isfinite(speed) || !isfinite(sep)) {
        return GR_FAIL(err, GR_EINVAL, "reference collision: non-finite initial state");
    }
    if (sep < d) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: the particles overlap initially (distance %g m < "
                       "diameter %g m)",
                       sep, d);
    }
    /* |r + g t| = d: |g|^2 t^2 + 2 (r.g) t + (|r|^2 - d^2) = 0, first root t >= 0. */
    const double b = r[0] * g[0] + r[1] * g[1];
    const double cq = (sep - d) * (sep + d);
    const double disc = b * b - speed * speed * cq;
    if (!(speed > 0.0) || !(b < 0.0) || !(disc > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "reference collision: the particles never touch (they %s)",
                       !(speed > 0.0) ? "have no relative velocity"
                       : !(b < 0.0)   ? "move apart"
                                      : "miss each other or only graze");
    }
    const double t_touch = cq / (-b + sqrt(disc));
    double rc_vec[2] = {r[0] + g[0] * t_touch, r[1] + g[1] * t_touch};
    const double rc_len = hypot(rc_vec[0], rc_vec[1]);

    const double w0 =
        linear ? sqrt(coeffs.k_s / m12)
               : pow(coeffs.k_s * pow(speed, coeffs.pow_a - 1.0) / m12, 1.0 / (coeffs.pow_a + 1.0));
    const double len = speed / w0; /* length unit V / w0 */
    ref_ctx ctx = {
        .D = d / len,
        .n0 = {rc_vec[0] / rc_len, rc_vec[1] / rc_len},
        .c_n = coeffs.gamma_n * (linear ? 1.0 : pow(len, coeffs.pow_p)) / (m12 * w0),
        .pow_a = coeffs.pow_a,
        .pow_p = coeffs.pow_p,
        .law = s->tangential ? s->tangential->reference : NULL,
        .rot = coeffs.rotation && s->tangential,
        .q = coeffs.q,
        .clamp = coeffs.clamp,
        .roll = s->rolling ? s->rolling->reference_rolling : NULL,
        .coeffs = &coeffs,
        .force_unit = m12 * w0 * speed,
        .r_eff = 0.5 * s->radius, /* r_i r_j / (r_i + r_j), as the kernels */
        /* the torque pair changes w1 - w2 at -2 M / I, I = q M r^2 = 2 q m12 r^2 */
        .roll_rate = 2.0 / (2.0 * coeffs.q * m12 * s->radius * s->radius * w0 * w0),
    };
    ctx.lt = (gr_ref_tangential){
        .c_n = ctx.c_n, .pow_a = ctx.pow_a, .pow_p = ctx.pow_p, .clamp = ctx.clamp, .fn_sign = 1.0};
    if (ctx.law) {
        ctx.law->setup(&coeffs, m12, w0, len, &ctx.lt);
    }
    const double t0[2] = {-ctx.n0[1], ctx.n0[0]};
    const double G0[2] = {g[0] / speed, g[1] / speed};
    const double gn0 = G0[0] * ctx.n0[0] + G0[1] * ctx.n0[1];
    /* initial spins (rotation only): W0 = (w1 + w2) / w0, and the contact point's tangential
     * velocity before, gt0 = g.t + S0, S0 = -(D / 2) W0 at the touch (|r| = D) */
    if (!ctx.rot && (s->omega1 != 0.0 || s->omega2 != 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "reference collision: initial spins need rotation ([model] rotation = true "
                       "with a tangential law; allowed without: 0)");
    }
    const double W0 = ctx.rot ? (s->omega1 + s->omega2) / w0 : 0.0;
    /* the relative spin a rolling law acts on (rolling needs rotation: prepare refused it without) */
    const double R0 = ctx.roll ? (s->omega1 - s->omega2) / w0 : 0.0;
    ctx.rolling = R0 != 0.0;
    ctx.roll_sign = R0 < 0.0 ? -1.0 : 1.0;
    const double gt0 = G0[0] * t0[0] + G0[1] * t0[1] - 0.5 * ctx.D * W0;
    const bool has_tangent = fabs(gt0) >= REF_TANGENT_FLOOR;
    if (ctx.law && ctx.law->start) {
        ctx.law->start(&ctx.lt, gn0, gt0, has_tangent);
    }

    if (sphere3d) {
        return ref3_integrate(&ctx, s, cs, &coeffs, w0, len, speed, G0, out, err);
    }
    ref_solver v;
    N_Vector atol = NULL;
    rc = ref_alloc(&v, REF_NEQ, err);
    void *mem = v.mem;
    N_Vector y = v.y;
    if (!rc && !(atol = N_VNew_Serial(REF_NEQ, v.sunctx))) {
        rc = GR_FAIL(err, GR_ENOMEM, "reference collision: could not allocate the CVODE solver");
    }
    if (rc) {
        goto done;
    }
    double *yd = N_VGetArrayPointer(y);
    yd[Y_U0] = 0.0;
    yd[Y_U1] = 0.0;
    yd[Y_G0] = G0[0];
    yd[Y_G1] = G0[1];
    yd[Y_JN] = 0.0;
    yd[Y_JT] = 0.0;
    yd[Y_W] = W0;
    yd[Y_S] = 0.0;
    yd[Y_DN] = 0.0;
    yd[Y_WT] = 0.0;
    yd[Y_KS] = 0.0;
    yd[Y_R] = R0;

    int rootdir[REF_NROOT];
    rootdir[ROOT_END] = -1;
    rootdir[ROOT_MAX_OVERLAP] = 1;
    rootdir[ROOT_DEGENERATE] = -1;
    rootdir[ROOT_ROLL] = -1;
    for (int k = 0; k < GR_REF_NROOTS; k++) {
        rootdir[root_law[k]] = -1; /* the law's roots cross 0 downwards */
    }

    REF_CHECK(CVodeSetErrHandlerFn(mem, ref_err_handler, &ctx), "CVodeSetErrHandlerFn");
    REF_CHECK(CVodeInit(mem, ref_rhs, 0.0, y), "CVodeInit");
    /* Y_KS (Mindlin only) is a quadrature left out of the error test (an absolute tolerance so
     * large that its weight vanishes, as CVODE's own quadratures without error control): slipping,
     * its integrand k_t s ds/dt follows d(mu |F_n|)/dt, singular (though integrable) at the ends
     * of a contact with a damping ~ xi^p, which no step across the end would resolve. It follows
     * the steps the motion needs (tests/test_spring_reference.c checks the balance). */
    double *av = N_VGetArrayPointer(atol);
    for (int k = 0; k < REF_NEQ; k++) {
        av[k] = k == y_law[GR_REF_Y_QUAD] ? 1e300 : REF_ATOL;
    }
    REF_CHECK(CVodeSVtolerances(mem, s->ref_rtol > 0.0 ? s->ref_rtol : 1e-12, atol),
              "CVodeSVtolerances");
    REF_CHECK(CVodeSetUserData(mem, &ctx), "CVodeSetUserData");
    REF_CHECK(CVodeSetLinearSolver(mem, v.LS, v.A), "CVodeSetLinearSolver");
    REF_CHECK(CVodeSetMaxNumSteps(mem, REF_MAX_STEPS), "CVodeSetMaxNumSteps");
    REF_CHECK(CVodeRootInit(mem, REF_NROOT, ref_roots), "CVodeRootInit");
    REF_CHECK(CVodeSetRootDirection(mem, rootdir), "CVodeSetRootDirection");
    REF_CHECK(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn");

    const double tau_max = REF_GUARD_CONTACTS * M_PI;
    double tau = 0.0;
    double xi_max = 0.0;
    bool have_max = false;
    ref_state st;
    for (;;) {
        int flag = CVode(mem, tau_max, y, &tau, CV_NORMAL);
        if (flag < 0 && ctx.degenerate) {
            rc = GR_FAIL(err, GR_EUNSTABLE,
                         "reference collision: the particle centres met (overlap reached the "
                         "diameter %g m); k_s = %g N/m is too soft for this impact speed",
                         d, coeffs.k_s);
            goto done;
        }
        if (flag < 0) {
            rc = ref_fail_flag(err, &ctx, "CVode", flag);
            goto done;
        }
        ctx.degenerate = false; /* only rejected trial points strayed there */
        if (ref_eval(&ctx, yd, &st) == 0 && st.xi > xi_max) {
            xi_max = st.xi; /* fallback only; the maximum-overlap root is exact */
        }
        if (flag != CV_ROOT_RETURN) {
            rc = GR_FAIL(err, GR_EINVAL,
                         "reference collision: contact did not end within %g undamped contact "
                         "times (zeta = %g)",
                         REF_GUARD_CONTACTS, zeta);
            goto done;
        }
        int found[REF_NROOT];
        REF_CHECK(CVodeGetRootInfo(mem, found), "CVodeGetRootInfo");
        if (found[ROOT_DEGENERATE]) {
            ctx.degenerate = true;
            rc = GR_FAIL(err, GR_EUNSTABLE,
                         "reference collision: the particle centres nearly met (overlap %.0f%% "
                         "of the diameter %g m); k_s = %g N/m is too soft for this impact speed",
                         100.0 * (1.0 - REF_AXIAL_FLOOR), d, coeffs.k_s);
            goto done;
        }
        if (found[ROOT_MAX_OVERLAP] && !have_max) {
            have_max = true;
            xi_max = st.xi;
        }
        if (found[ROOT_END]) {
            break;
        }
        bool found_law[GR_REF_NROOTS];
        bool any = false;
        for (int k = 0; k < GR_REF_NROOTS; k++) {
            found_law[k] = found[root_law[k]] != 0;
            any = any || found_law[k];
        }
        int ev = any && ctx.law && ctx.law->event ? ctx.law->event(&ctx.lt, found_law, &st.law) : 0;
        for (int k = 0; k < GR_REF_NY && ev; k++) {
            yd[y_law[k]] = st.law.y[k]; /* the law's state as its event left it */
        }
        if (ev & GR_REF_STOP) {
            /* the law stopped the contact point's sliding: cancel its residual g_c at the root */
            if (ctx.rot) {
                /* the impulse J that cancels the residual gc at the root: J / m12 on g.t and
                 * rho J / (q m12) on S = -|r| W / 2, rho = (|r| / D)^2 */
                const double rho = st.rn * st.rn / (ctx.D * ctx.D);
                const double j = -st.gc / (1.0 + rho / ctx.q);
                yd[Y_G0] += j * st.t[0];
                yd[Y_G1] += j * st.t[1];
                yd[Y_W] -= 2.0 * (rho / ctx.q) * j / st.rn;
            } else {
                yd[Y_G0] = st.gn * st.n[0];
                yd[Y_G1] = st.gn * st.n[1];
            }
        }
        bool restart = (ev & GR_REF_RESTART) != 0;
        if (found[ROOT_ROLL] && ctx.rolling) {
            yd[Y_R] = 0.0; /* the rolling arrested: nothing turns the discs apart again */
            ctx.rolling = false;
            restart = true;
        }
        if (restart) {
            REF_CHECK(CVodeReInit(mem, tau, y), "CVodeReInit");
        }
    }

    /* Outgoing relative velocity (force-free from here on) and the frame at the end. */
    if (ref_eval(&ctx, yd, &st) != 0) {
        rc = GR_FAIL(err, GR_EUNSTABLE, "reference collision: degenerate geometry at the end");
        goto done;
    }
    const double G1[2] = {yd[Y_G0], yd[Y_G1]};
    const double gg0 = G0[0] * G0[0] + G0[1] * G0[1];
    const double gg1 = G1[0] * G1[0] + G1[1] * G1[1];

    memset(out, 0, sizeof *out);
    /* rotation: equal torques on both discs change each spin by half the change of W; the spin
     * energy I (w1^2 + w2^2) / 2 over m12 V^2 / 2 is 2 q (D / 2)^2 (w1^2 + w2^2) / w0^2 */
    /* w1 = (W + R) w0 / 2, w2 = (W - R) w0 / 2: the contact's torques change W, the rolling
     * law's R */
    const double dW = yd[Y_W] - W0, dR = yd[Y_R] - R0;
    const double w1a = s->omega1 + 0.5 * (dW + dR) * w0, w2a = s->omega2 + 0.5 * (dW - dR) * w0;
    const double spin_scale = 0.5 * ctx.q * ctx.D * ctx.D / (w0 * w0);
    const double spin_e = ctx.rot ? spin_scale * (w1a * w1a + w2a * w2a) : 0.0;
    const double spin_e0 =
        ctx.rot ? spin_scale * (s->omega1 * s->omega1 + s->omega2 * s->omega2) : 0.0;
    const bool spun = W0 != 0.0 || spin_e0 != 0.0;
    out->energy_loss = 1.0 - (gg1 + spin_e) / (gg0 + spin_e0);
    /* where the energy went (fractions of E; units m12 V^2 over E = (gg0 + spin_e0) / 2): the
     * elastic energy still in the contact at its end is lost with it (a clamped normal law
     * separates at xi > 0, the spring's k_t s^2 / 2 is forgotten) */
    const double e0 = 0.5 * (gg0 + spin_e0), X_end = fmax(st.xi, 0.0);
    const double u_spring = st.law.e;      /* the tangential law's stored energy, forgotten */
    const double stored_t = st.law.e_work; /* int F ds of its stored share (int k_t s ds) */
    out->diss_normal = yd[Y_DN] / e0;
    out->diss_tangential = (yd[Y_WT] - stored_t) / e0;
    out->stored_lost = (pow(X_end, ctx.pow_a + 1.0) / (ctx.pow_a + 1.0) + u_spring) / e0;
    out->work_free = (u_spring - stored_t) / e0;
    /* the rolling torques' work: the spins' energy I (w1^2 + w2^2) / 2 = I (W^2 + R^2) w0^2 / 4
     * loses the R part's change */
    out->diss_rolling = 0.25 * spin_scale * (R0 * R0 - yd[Y_R] * yd[Y_R]) * w0 * w0 / e0;
    const double gtt0 = G0[0] * t0[0] + G0[1] * t0[1]; /* the centres' g.t, for the impact angle */
    out->impact_angle = atan2(fabs(gtt0), -gn0) * (180.0 / M_PI);
    /* the models' restitution laws assume discs without spin before the impact */
    out->expected_loss =
        spun ? (double)NAN : gr_contact_expected_loss(&coeffs, speed, out->impact_angle);
    out->contact_time = tau / w0;
    out->max_overlap = xi_max * len;
    out->eps_n_measured = -st.gn / gn0;
    out->eps_t_measured = has_tangent ? st.gc / gt0 : (double)NAN;
    out->tangential_reversed = has_tangent && st.gc * gt0 < 0.0 && fabs(st.gc) >= REF_TANGENT_FLOOR;
    if (ctx.rot) {
        out->omega1 = w1a;
        out->omega2 = w2a;
    }
    out->normal_impulse = fabs(yd[Y_JN]) * m12 * speed;
    out->tangential_impulse = fabs(yd[Y_JT]) * m12 * speed;
    out->dt = 0.0;

    /* Particle velocities from the impulse on 2, P = m12 (g' - g); momentum is conserved by
     * construction, so this only guards the bookkeeping. */
    double p_before = 0.0, p_change = 0.0;
    for (int k = 0; k < s->dim; k++) {
        double P = m12 * speed * (G1[k] - G0[k]);
        double v1 = cs->v1[k] - P / s->mass, v2 = cs->v2[k] + P / s->mass;
        double pb = s->mass * (cs->v1[k] + cs->v2[k]);
        double pa = s->mass * (v1 + v2);
        out->v1[k] = v1;
        out->v2[k] = v2;
        p_before += pb * pb;
        p_change += (pa - pb) * (pa - pb);
    }
    double p_scale = sqrt(p_before);
    if (!(p_scale > 0.0)) {
        p_scale = s->mass * (hypot(cs->v1[0], s->dim == 2 ? cs->v1[1] : 0.0) +
                             hypot(cs->v2[0], s->dim == 2 ? cs->v2[1] : 0.0));
    }
    out->momentum_error = p_scale > 0.0 ? sqrt(p_change) / p_scale : 0.0;

    if (!isfinite(out->energy_loss) || !isfinite(out->eps_n_measured) ||
        !isfinite(out->max_overlap)) {
        rc = GR_FAIL(err, GR_EUNSTABLE, "reference collision: non-finite result");
        goto done;
    }
    rc = GR_OK;

done:
    if (atol) {
        N_VDestroy(atol);
    }
    ref_free(&v);
    return rc;
}
