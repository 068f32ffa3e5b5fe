/* tangential_dashpot: F_t = -gamma_t (v12 . t) t while the normal contact acts (2.9), t = n
 * rotated by 90 degrees (2.8).
 *
 * Without rotation the tangential relative velocity decays as exp(-gamma_t t / m12) during the
 * contact, so eps_t = exp(-gamma_t t_c / m12). The thesis's eq. 2.12 takes t_c = pi sqrt(m12/k_s),
 * the undamped contact time; the real contact lasts pi/w (unclamped) or t_e (clamped), so we use
 * the actual duration of the chosen normal law: gamma_t = -m12 ln(eps_t) / t_c. Eq. 2.12 would
 * give eps_t^(1/sqrt(1 - zeta^2)) instead (docs/models.md). */
#include <math.h>
#include <stddef.h>

#include "granule/model.h"

static const gr_param params[] = {
    {"eps_t", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "tangential coefficient of restitution (2.10); 1 = no tangential dissipation",
     offsetof(gr_contact_params, eps_t)},
};

static int prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                   gr_error *err)
{
    (void)err;
    c->tangential = GR_TANGENTIAL_DASHPOT;
    double t_c = c->t_c;
    if (!isfinite(t_c)) {
        t_c = M_PI / c->w0; /* a sticking normal contact: fall back to eq. 2.12 */
    }
    /* An explicit step multiplies v_t by (1 - gamma_t dt / m12); gamma_t = m12 / dt removes it in
     * one step, the closest a time step can get to eps_t = 0. */
    double step = dt > 0.0 ? dt : t_c / 50.0;
    double gamma_max = m12 / step;
    double gamma = p->eps_t > 0.0 ? -m12 * log(p->eps_t) / t_c : gamma_max;
    c->gamma_t = fmin(gamma, gamma_max);
    return GR_OK;
}

const gr_model gr_model_tangential_dashpot = {
    .name = "tangential_dashpot",
    .summary = "tangential dashpot (thesis 2.9-2.12), gamma_t set for the actual contact duration",
    .kind = GR_MODEL_TANGENTIAL,
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .prepare = prepare,
};
