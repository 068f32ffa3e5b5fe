/* The list of every collision model: one line per model, and the file that defines it.
 *
 * Adding a model: write models/NAME.h (copy the closest existing model; docs/architecture.md,
 * "How to add a collision model"), then add its #include below and its one entry to the list of
 * its kind (and to GR_OWN_MODELS if it has parameters of its own, a struct NAME_own). Everything
 * else is generated from these lists: the registry `gr_models` (models/registry.c), the
 * specialised force kernels (src/core/kernels.c: every normal law with no tangential law and
 * with each tangential law, clamped and not, in 2D; every normal law clamped and not on the 1D
 * ring), the layout of the models' own parameters and the conformance suite
 * (tests/test_models_conformance.c, which loops over `gr_models`).
 *
 * The lists are X-macros: GR_NORMAL_MODELS(X, A) expands X(A, NAME) for every normal force law,
 * and so on. `A` is passed through untouched so that a list can be expanded inside another
 * (the kernels pair each normal law with each tangential law). */
/* outside the guard: models/registry.c includes this file twice, the second time with
 * GR_MODEL_IMPL, which compiles each model's descriptor, prepare, ... (their own guards) */
#include "models/spring_dashpot.h"
#include "models/hertz.h"
#include "models/tangential_dashpot.h"
#include "models/sliding_friction.h"
#include "models/tangential_spring.h"
#include "models/hard_sphere.h"
#include "models/rolling_friction.h"

#ifndef GR_MODELS_LIST_H
#define GR_MODELS_LIST_H

/* normal force laws: models/NAME.h defines gr_normal_NAME and gr_model_NAME */
#define GR_NORMAL_MODELS(X, A)                                                                     \
    X(A, spring_dashpot)                                                                           \
    X(A, hertz)

/* tangential force laws: gr_tangential_NAME, GR_BOOK_NAME and gr_model_NAME */
#define GR_TANGENTIAL_MODELS(X, A)                                                                 \
    X(A, tangential_dashpot)                                                                       \
    X(A, sliding_friction)                                                                         \
    X(A, tangential_spring)

/* the tangential laws above that keep a per-contact history (gr_tangential_in.hist; the kernels
 * then carry one slot per pair, src/core/contact_history.c) */
#define GR_HISTORY_MODELS(X, A) X(A, tangential_spring)

/* rolling-resistance torques (rotation only): gr_rolling_NAME and gr_model_NAME */
#define GR_ROLLING_MODELS(X, A) X(A, rolling_friction)

/* instantaneous rules of the event-driven integrator: gr_model_NAME and the rule
 * gr_event_rule_NAME (models/law.h, gr_event_pair), called through gr_event_rule_apply below */
#define GR_EVENT_MODELS(X, A) X(A, hard_sphere)

/* the models with parameters of their own, a struct NAME_own in models/NAME.h: their blocks, one
 * after the other, in gr_contact_params.own (GR_OWN, GR_OWN_KEY of models/law.h) */
#define GR_OWN_MODELS(X, A)                                                                        \
    X(A, hertz)                                                                                    \
    X(A, tangential_spring)                                                                        \
    X(A, hard_sphere)                                                                              \
    X(A, rolling_friction)

/* Whether tangential law m keeps a per-contact history (listed in GR_HISTORY_MODELS). */
static inline bool gr_model_keeps_history(const gr_model *m)
{
#define GR_HISTORY_MATCH(A, NAME)                                                                  \
    if (m == &gr_model_##NAME) {                                                                   \
        return true;                                                                               \
    }
    GR_HISTORY_MODELS(GR_HISTORY_MATCH, )
#undef GR_HISTORY_MATCH
    return false;
}

/* The event rules' dispatch, generated from GR_EVENT_MODELS: a caller finds the rule of its
 * normal model once per run (gr_event_rule_of; -1: the model is no event rule) and applies it per
 * collision with gr_event_rule_apply, a switch over inline rules (no call through a pointer). */
#define GR_EVENT_RULE_ID(A, NAME) GR_EVENT_RULE_##NAME,
typedef enum { GR_EVENT_MODELS(GR_EVENT_RULE_ID, ) GR_EVENT_RULE_COUNT } gr_event_rule;

static inline int gr_event_rule_of(const gr_model *m)
{
#define GR_EVENT_RULE_MATCH(A, NAME)                                                               \
    if (m == &gr_model_##NAME) {                                                                   \
        return GR_EVENT_RULE_##NAME;                                                               \
    }
    GR_EVENT_MODELS(GR_EVENT_RULE_MATCH, )
    return -1;
}

static inline void gr_event_rule_apply(int rule, const gr_contact_coeffs *c, gr_event_pair *p)
{
    switch (rule) {
#define GR_EVENT_RULE_CASE(A, NAME)                                                                \
    case GR_EVENT_RULE_##NAME: gr_event_rule_##NAME(c, p); break;
        GR_EVENT_MODELS(GR_EVENT_RULE_CASE, )
    default: break;
    }
}

/* The rule on spheres (3D; the event core, src/integrators/event/event_cells.h, and `granule
 * collide --dim 3`): gr_event_rule_apply of `rule` with the coefficients cc on
 * spheres 1 and 2 of mass M, radius R, moment of inertia q M R^2 touching along the unit normal n
 * (from 1 to 2),
 * applied in the plane of n and the unit tangent t along the contact point's relative tangential
 * velocity (any t when it is 0: no tangential impulse then). Smooth spheres (w1 = NULL):
 * g_t = g - (g.n) n, g = v1 - v2. Rough spheres (w1, w2 the spin vectors, changed in place):
 * g_c = g_t + R (w1 + w2) x n, the velocity of 1's surface point minus 2's (the 2D rule's
 * g.t + R (w1 + w2) with the discs' spins along z). The impulse P lies in the plane of n and t and
 * turns both spins by R n x P / I, along e = n x t; so the plane's rule on (v.n, v.t) and the
 * spins' e components, w.e (the 2D spin in the frame n, t, e), is the 3D rule: v.e and the spins'
 * n and t components keep their values, and g_c keeps no component along e. */
static inline void gr_event_rule_3d(int rule, const gr_contact_coeffs *cc, double M, double R,
                                    double q, const double n[3], double v1[3], double v2[3],
                                    double *w1, double *w2, bool elastic, double *de_n,
                                    double *de_t)
{
    const double g[3] = {v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]};
    const double gn = g[0] * n[0] + g[1] * n[1] + g[2] * n[2];
    double t[3] = {g[0] - gn * n[0], g[1] - gn * n[1], g[2] - gn * n[2]};
    if (w1) { /* + R W x n, W = w1 + w2 */
        const double W[3] = {w1[0] + w2[0], w1[1] + w2[1], w1[2] + w2[2]};
        t[0] += R * (W[1] * n[2] - W[2] * n[1]);
        t[1] += R * (W[2] * n[0] - W[0] * n[2]);
        t[2] += R * (W[0] * n[1] - W[1] * n[0]);
    }
    const double gt = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int a = 0; a < 3; a++) {
        t[a] = gt > 0.0 ? t[a] / gt : 0.0;
    }
    const double n1 = v1[0] * n[0] + v1[1] * n[1] + v1[2] * n[2];
    const double t1 = v1[0] * t[0] + v1[1] * t[1] + v1[2] * t[2];
    const double n2 = v2[0] * n[0] + v2[1] * n[1] + v2[2] * n[2];
    const double t2 = v2[0] * t[0] + v2[1] * t[1] + v2[2] * t[2];
    gr_event_pair p = {.M = M,
                       .R = R,
                       .q = q,
                       .nx = 1.0,
                       .ny = 0.0,
                       .v1x = n1,
                       .v1y = t1,
                       .v2x = n2,
                       .v2y = t2,
                       .elastic = elastic};
    const double ax[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                          n[0] * t[1] - n[1] * t[0]}; /* e = n x t */
    double s1 = 0.0, s2 = 0.0;                        /* the spins' e components */
    if (w1) {
        s1 = w1[0] * ax[0] + w1[1] * ax[1] + w1[2] * ax[2];
        s2 = w2[0] * ax[0] + w2[1] * ax[1] + w2[2] * ax[2];
        p.w1 = &s1;
        p.w2 = &s2;
    }
    const double s10 = s1, s20 = s2;
    gr_event_rule_apply(rule, cc, &p);
    for (int a = 0; a < 3; a++) {
        v1[a] += (p.v1x - n1) * n[a] + (p.v1y - t1) * t[a];
        v2[a] += (p.v2x - n2) * n[a] + (p.v2y - t2) * t[a];
        if (w1) {
            w1[a] += (s1 - s10) * ax[a];
            w2[a] += (s2 - s20) * ax[a];
        }
    }
    *de_n = p.de_n;
    *de_t = p.de_t;
}

#define GR_OWN_BLOCK(A, NAME) NAME##_own NAME;
typedef struct gr_own_layout {
    GR_OWN_MODELS(GR_OWN_BLOCK, )
} gr_own_layout;
_Static_assert(
    sizeof(gr_own_layout) <= GR_CONTACT_OWN_BYTES,
    "the models' own parameters outgrow gr_contact_params.own: raise GR_CONTACT_OWN_BYTES");

#endif
