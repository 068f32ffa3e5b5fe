/* The interface between a collision model's pair law and the engine's kernels.
 *
 * A model file (models/NAME.h, listed in models/list.h) defines its law as a static inline
 * function with one of the signatures below; src/core/kernels.c instantiates one pair loop per
 * legal combination of laws (normal x tangential x clamp, 1D and 2D) from the list, so every
 * call inlines and the compiler drops whatever a combination does not use. There is no call
 * through a pointer per pair. docs/architecture.md, "How to add a collision model", walks
 * through it.
 *
 * Geometry of a pair i < j (thesis sec. 2.1): overlap xi = d - |r_ij| > 0, n = r_ij / |r_ij|
 * from i to j, g = v_j - v_i, g_n = g.n (< 0 while approaching), t = n rotated by -90 degrees
 * (2.8), g_t = g.t. The engine applies F = f_n n + f_t t to j and -F to i. */
#ifndef GR_MODELS_LAW_H
#define GR_MODELS_LAW_H

#include <stddef.h>

#include "granule/model.h"

#define GR_LAW static inline __attribute__((always_inline))

/* A model's own parameters: models/NAME.h declares `typedef struct NAME_own {...} NAME_own;`
 * and lists NAME in GR_OWN_MODELS (models/list.h), which lays the blocks out inside
 * gr_contact_params.own. GR_OWN(p, NAME) is the model's block in the parameters p, and
 * GR_OWN_KEY(NAME, FIELD) the offset a descriptor (gr_param.offset) gives for one of its fields. */
#define GR_OWN(p, NAME)                                                                            \
    ((const NAME##_own *)(const void *)((p)->own + offsetof(gr_own_layout, NAME)))
#define GR_OWN_KEY(NAME, FIELD)                                                                    \
    (offsetof(gr_contact_params, own) + offsetof(gr_own_layout, NAME) + offsetof(NAME##_own, FIELD))

/* A normal law: gr_normal_NAME(const gr_contact_coeffs *c, double xi, double g_n, int clamp)
 * returns
 *   f   the normal force on j along n (repulsive > 0), clamped to >= 0 when clamp is set;
 *   f_d its non-conservative part, f minus the elastic force dU/dxi. The ledger books -f_d g_n
 *       as normal dissipation (with the clamp this includes the elastic energy that vanishes
 *       while the force is held at zero), and f_d goes into the engine's non-conservative force;
 *   e   the elastic energy of the contact in units of c->e_scale (U = e_scale * e): the kernel
 *       sums e over contacts and multiplies once (the linear law returns xi^2, e_scale = k/2).
 * `clamp` is a compile-time constant of the kernel instance (the copy of c->clamp), so the
 * branch vanishes. */
typedef struct gr_normal_force {
    double f, f_d, e;
} gr_normal_force;

/* What a tangential law sees at one contact.
 *   g_t    tangential relative velocity at the contact point: g.t without rotation; with
 *          rotation (kernels instantiated with rot = 1) g.t + a (w_i + w_j), the surface
 *          velocities included (sign: w counterclockwise, t = (n_y, -n_x); a = |r_ij| / 2 is
 *          the distance of either centre to the contact point, so the surface of i at the
 *          contact moves with v_i + w_i z x (a n) = v_i - a w_i t, that of j with v_j + a w_j t),
 *          so a law written against g_t needs no change. The force f t on j then exerts the
 *          torque a f on j and on i alike (angular momentum conserved exactly).
 *   f_n    the normal force the normal law just returned (after the clamp);
 *   acts   the normal contact acts: always with an unclamped law, f_n > 0 with the clamp;
 *   m12_dt the contact point's tangential mass over the time step (the impulse that stops g_t
 *          in one step is m12_dt |g_t|): m12 / dt without rotation, m_t / dt with it;
 *   hist   per-contact history slot, for a law listed in GR_HISTORY_MODELS (models/list.h; NULL
 *          for the others): the law reads and updates its state here (the Cundall-Strack spring's
 *          accumulated displacement s). The kernel passes a copy of the pair's slot and writes it
 *          back once per pair and evaluation; the storage (src/core/contact_history.c) is one
 *          slot per neighbour-list entry, carried by pair across rebuilds and checkpoints. */
typedef struct gr_tangential_in {
    double g_t, f_n;
    double xi, g_n; /* the overlap and the normal relative velocity (a stiffness that depends on
                       xi: tangential_spring's Mindlin option; 0 where the contact has ended) */
    int acts;
    double m12_dt;
    double *hist;
} gr_tangential_in;

/* A tangential law: gr_tangential_NAME(const gr_contact_coeffs *c, gr_tangential_in in)
 * returns the force on j along t and the power it dissipates (>= 0), which the kernel books
 * into the ledger column GR_BOOK_NAME (one of the two below, a constant in the model file), and
 * e, the elastic energy the law stores in the contact (J; 0 for a law without history, the
 * tangential spring of models/tangential_spring.h: k_t s^2 / 2).
 * A history law also returns
 *   fc   the conservative part of f (the spring, -k_t s): the kernel leaves it out of the
 *        non-conservative force, whose work the ledger books as dissipation, because its work
 *        shows up as the change of e instead;
 *   lost the stored energy the law dropped at this evaluation without any work (J): the spring
 *        shortened at the Coulomb limit, the history forgotten when the contact ends. The kernel
 *        reports it (gr_force_report.lost) and the integrator books it as friction.
 * Laws without history leave both 0 (designated initialisers). */
typedef struct gr_tangential_force {
    double f, p, e;
    double fc, lost;
} gr_tangential_force;

enum { GR_BOOK_TANGENTIAL = 1, GR_BOOK_FRICTION = 2 };

/* 3D (spheres, src/core/kernels_3d.c). A law without history acts along the contact point's
 * tangential velocity: the kernel calls it as above with g_t = |g_c| (g_c the tangential relative
 * velocity vector at the contact point) and applies f along g_c / |g_c| (nothing when g_c = 0),
 * so tangential_dashpot and sliding_friction run the same code as in 2D. A history law keeps a
 * vector s and has a vector step, gr_tangential3_NAME(const gr_contact_coeffs *c,
 * gr_tangential_in3 in), listed in GR_HISTORY_MODELS: the kernel passes s already turned into
 * the current tangent plane (its length kept), the law updates it in place. It returns the force
 * on j (f, a vector in the tangent plane), its conservative part fc, and p, e, lost as above. */
typedef struct gr_tangential_in3 {
    double g[3]; /* g_c, the contact point's tangential relative velocity (j relative to i) */
    double f_n, xi, g_n;
    int acts;
    double *hist; /* s, three doubles */
} gr_tangential_in3;

typedef struct gr_tangential_force3 {
    double f[3], fc[3];
    double p, e, lost;
} gr_tangential_force3;

/* What a rolling law sees at one contact (rotation kernels only; models/rolling_friction.h).
 *   dw     w_i - w_j, the relative spin (the rolling velocity is r_eff dw);
 *   f_n    the normal force after the clamp;  acts  as for a tangential law;
 *   r_eff  r_i r_j / (r_i + r_j), r / 2 for equal discs;
 *   i_2dt  I / (2 dt): the torque pair that stops dw within one step is i_2dt |dw|.
 * A rolling law returns m, the torque on j (-m on i: the pair exerts no net torque and no force),
 * and p, the power it dissipates, m dw >= 0 (booked with friction). */
typedef struct gr_rolling_in {
    double dw, f_n;
    int acts;
    double r_eff, i_2dt;
} gr_rolling_in;

typedef struct gr_rolling_torque {
    double m, p;
} gr_rolling_torque;

/* An event rule's instantaneous collision (gr_model.kind & GR_MODEL_EVENT; the rule NAME is
 * `GR_LAW void gr_event_rule_NAME(const gr_contact_coeffs *c, gr_event_pair *p)` in
 * models/NAME.h, listed in GR_EVENT_MODELS). Two equal discs of mass M, radius R and moment of
 * inertia q M R^2 touch along the unit normal (nx, ny) from 1 to 2; in 1D ny = 0 and the y
 * velocities are 0. The rule changes v1, v2 (and the spins *w1, *w2 when they are not NULL:
 * [model] rotation = true) in place and returns the kinetic energy it dissipated, split into the
 * normal and the tangential part, in de_n and de_t (J). `elastic` is the integrator's TC verdict
 * (docs/event-driven.md): the rule must then conserve energy. The caller of the rule is the
 * event-driven integrator (one call per collision, through gr_event_rule_apply of
 * models/list.h) and `granule collide`. */
typedef struct gr_event_pair {
    double M, R, q;
    double nx, ny;
    double v1x, v1y, v2x, v2y;
    double *w1, *w2;
    bool elastic;
    double de_n, de_t;
} gr_event_pair;

/* The scene keys of rotation, declared by every tangential law that acts at the contact point
 * (gr_model.contact_point): put GR_ROTATION_PARAMS into the law's parameter table. */
#define GR_ROTATION_PARAMS                                                                         \
    {"rotation",                                                                                   \
     "",                                                                                           \
     GR_PARAM_BOOL,                                                                                \
     0.0,                                                                                          \
     0.0,                                                                                          \
     1.0,                                                                                          \
     false,                                                                                        \
     false,                                                                                        \
     "true: the discs rotate (angular velocity, torque); the law acts on the contact point's "     \
     "tangential velocity g.t + a (w_i + w_j), a = |r_ij| / 2 (docs/models.md, Rotation); false: " \
     "no "                                                                                         \
     "rotation (the thesis)",                                                                      \
     offsetof(gr_contact_params, rotation)},                                                       \
    {                                                                                              \
        "inertia_factor", "", GR_PARAM_DOUBLE, 0.5, 0.0, 1.0, true, false,                         \
            "rotation: moment of inertia I = q M r^2, q in (0, 1]; 1/2 uniform disc (the 2D "      \
            "default), 2/5 solid sphere (the 3D default), 1 thin ring",                            \
            offsetof(gr_contact_params, inertia_factor)                                            \
    }

#endif
