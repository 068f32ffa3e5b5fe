/* sliding_friction: Coulomb sliding friction of the thesis (2.7), a tangential force of magnitude
 * mu |F_n| opposing the tangential relative velocity.
 *
 * At zero tangential velocity the force is zero (no static friction, no tangential spring). An
 * explicit step would make v_t chatter around zero with amplitude mu |F_n| dt / m12, so the
 * kernel limits the force to what stops the tangential relative motion within one step:
 *   F_t = -sign(v_t) min(mu |F_n|, m12 |v_t| / dt).
 * Hence v_t never reverses and the impulse never exceeds mu times the normal impulse. For a
 * binary impact without rotation eps_t = max(0, 1 - mu (1 + eps_n) |v_n| / |v_t|). */
#include <math.h>
#include <stddef.h>

#include "granule/model.h"

static const gr_param params[] = {
    {"mu", "", GR_PARAM_DOUBLE, 0.5, 0.0, INFINITY, false, true,
     "sliding-friction coefficient (2.7)", offsetof(gr_contact_params, mu)},
};

static int prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                   gr_error *err)
{
    (void)m12;
    (void)dt;
    (void)err;
    c->tangential = GR_TANGENTIAL_FRICTION;
    c->mu = p->mu;
    return GR_OK;
}

const gr_model gr_model_sliding_friction = {
    .name = "sliding_friction",
    .summary = "Coulomb sliding friction mu |F_n| (thesis 2.7), chatter-free at v_t = 0",
    .kind = GR_MODEL_TANGENTIAL,
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .prepare = prepare,
};
