/* sliding_friction: Coulomb sliding friction of the thesis (2.7), a tangential force of magnitude
 * mu |F_n| opposing the tangential relative velocity.
 *
 * At zero tangential velocity the force is zero (no static friction, no tangential spring). An
 * explicit step would make v_t chatter around zero with amplitude mu |F_n| dt / m12, so the
 * kernel limits the force to what stops the tangential relative motion within one step:
 *   F_t = -sign(v_t) min(mu |F_n|, m12 |v_t| / dt).
 * Hence v_t never reverses and the impulse never exceeds mu times the normal impulse. For a
 * binary impact without rotation eps_t = max(0, 1 - mu (1 + eps_n) |v_n| / |v_t|). */
#ifndef GR_MODELS_SLIDING_FRICTION_H
#define GR_MODELS_SLIDING_FRICTION_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_sliding_friction;

/* The pair law (2.7), chatter-free: f_t = -sign(g_t) min(mu |f_n|, m12 |g_t| / dt). It dissipates
 * -f_t g_t >= 0, booked as friction. */
enum { GR_BOOK_sliding_friction = GR_BOOK_FRICTION };
GR_LAW gr_tangential_force gr_tangential_sliding_friction(const gr_contact_coeffs *c,
                                                          const gr_tangential_in in)
{
    const double g_t = in.g_t;
    const double cap = in.m12_dt * fabs(g_t), slide = c->mu * fabs(in.f_n);
    const double mag = slide < cap ? slide : cap;
    const double f = g_t > 0.0 ? -mag : (g_t < 0.0 ? mag : 0.0);
    return (gr_tangential_force){.f = f, .p = -(f * g_t)};
}

#endif /* GR_MODELS_SLIDING_FRICTION_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_SLIDING_FRICTION_IMPL)
#define GR_MODELS_SLIDING_FRICTION_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

#include "models/reference.h"

static const gr_param sliding_friction_params[] = {
    {"mu", "", GR_PARAM_DOUBLE, 0.5, 0.0, INFINITY, false, true,
     "sliding-friction coefficient (2.7)", offsetof(gr_contact_params, mu)},
    GR_ROTATION_PARAMS,
};

static int sliding_friction_prepare(const gr_contact_params *p, double m12, double dt,
                                    gr_contact_coeffs *c, gr_error *err)
{
    (void)m12;
    (void)dt;
    (void)err;
    c->mu = p->mu;
    return GR_OK;
}

/* Its restitution law (binary impact without rotation): the tangential impulse is mu int |F_n| dt
 * until g_t stops, so eps_t = max(0, 1 - mu (int |F_n| dt / m12) / v_t), i.e.
 * max(0, 1 - mu (1 + eps_n) v_n / v_t) for a repulsive normal force (physics notes sec. 4.2). */
static double sliding_friction_restitution_t(const gr_contact_coeffs *c, gr_normal_impact n,
                                             double v_n, double v_t)
{
    /* with rotation the tangential impulse J changes the contact point's velocity by J / m_t */
    return fmax(0.0, 1.0 - c->mu * n.impulse_abs * (c->m12 / c->m_t) * v_n / v_t);
}

#include "models/sliding_friction_reference.h"

/* mu = 0: no friction, the kernel without it runs */
static bool sliding_friction_inert(const gr_contact_coeffs *c) { return c->mu == 0.0; }

const gr_model gr_model_sliding_friction = {
    .name = "sliding_friction",
    .summary = "Coulomb sliding friction mu |F_n| (thesis 2.7), chatter-free at v_t = 0",
    .kind = GR_MODEL_TANGENTIAL,
    .params = sliding_friction_params,
    .n_params = sizeof sliding_friction_params / sizeof sliding_friction_params[0],
    .prepare = sliding_friction_prepare,
    .inert = sliding_friction_inert,
    .contact_point = true,
    .restitution_t = sliding_friction_restitution_t,
    .reference = &sliding_friction_reference,
    .elastic = "mu=0",
};
#endif /* GR_MODEL_IMPL */
