/* spring_dashpot: the linear spring-dashpot normal contact force of the thesis (2.4-2.6),
 *   F_n = k_s xi - gamma_n (v12 . n),  xi = d - |r12| > 0,
 * in two modes:
 *  - clamp = false (the thesis): gamma_n from eq. 2.6, which gives exactly the requested eps_n
 *    because the contact ends when the overlap returns to zero; the dashpot then pulls the
 *    particles together at the end of the contact (an attractive force).
 *  - clamp = true: F_n = max(0, F_n), never attractive. The contact ends when the force vanishes
 *    and the restitution is that of Schwager & Poeschel (2007); gamma_n is found by inverting it,
 *    so the requested eps_n still holds exactly in continuous time.
 * docs/models.md compares both. */
#include <math.h>
#include <stddef.h>

#include "core/restitution.h"
#include "granule/model.h"

static const gr_param params[] = {
    {"k_s", "N/m", GR_PARAM_DOUBLE, 5e5, 0.0, INFINITY, true, true,
     "normal spring constant (2.4); Table 2.2: 5e5", offsetof(gr_contact_params, k_s)},
    {"eps_n", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "normal coefficient of restitution (2.2); 1 = elastic, 0 = sticking (unclamped only)",
     offsetof(gr_contact_params, eps_n)},
    {"clamp", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "true: normal force never attractive, gamma_n from the exact clamped restitution "
     "(Schwager & Poeschel 2007); false: thesis eq. 2.6",
     offsetof(gr_contact_params, clamp)},
};

static int prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                   gr_error *err)
{
    (void)dt;
    c->normal = GR_NORMAL_SPRING_DASHPOT;
    c->k_s = p->k_s;
    c->m12 = m12;
    c->clamp = p->clamp;
    c->w0 = sqrt(p->k_s / m12);
    if (p->clamp) {
        if (p->eps_n <= 0.0) {
            return GR_FAIL(err, GR_EINVAL,
                           "[model] eps_n = 0 cannot be reached with clamp = true (it needs an "
                           "infinite dashpot); allowed range with clamping: (0, 1]; use clamp = "
                           "false for a sticking contact");
        }
        c->zeta = gr_zeta_clamped(p->eps_n);
        c->t_c = gr_duration_clamped(c->zeta) / c->w0;
        c->eps_n_exact = gr_eps_clamped(c->zeta);
    } else {
        c->zeta = gr_zeta_unclamped(p->eps_n); /* eq. 2.6 */
        c->t_c = gr_duration_unclamped(c->zeta) / c->w0;
        c->eps_n_exact = p->eps_n;
    }
    c->gamma_n = 2.0 * c->zeta * sqrt(p->k_s * m12);
    return GR_OK;
}

const gr_model gr_model_spring_dashpot = {
    .name = "spring_dashpot",
    .summary = "linear spring-dashpot normal force (thesis 2.4-2.6), optionally clamped repulsive",
    .kind = GR_MODEL_NORMAL,
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .prepare = prepare,
};
