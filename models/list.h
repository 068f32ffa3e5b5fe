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

#define GR_OWN_BLOCK(A, NAME) NAME##_own NAME;
typedef struct gr_own_layout {
    GR_OWN_MODELS(GR_OWN_BLOCK, )
} gr_own_layout;
_Static_assert(
    sizeof(gr_own_layout) <= GR_CONTACT_OWN_BYTES,
    "the models' own parameters outgrow gr_contact_params.own: raise GR_CONTACT_OWN_BYTES");

#endif
