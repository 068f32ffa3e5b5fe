/* hard_sphere: the instantaneous collision rule of the event-driven integrator (thesis 2.1, 2.2,
 * 2.10): momentum conserved, the normal relative velocity reversed and scaled by eps_n, the
 * tangential relative velocity scaled by eps_t (same sign, eq. 2.10), so a collision at impact
 * angle a loses (1 - eps_n^2) cos^2 a + (1 - eps_t^2) sin^2 a of the relative kinetic energy
 * (2.13, 2.14). The rule itself is src/event/rule.h.
 *
 * Inelastic collapse is cured by the TC model (Luding & McNamara, Granular Matter 1, 113 (1998);
 * ../shared/notes/physics-algorithms.md sec. 2): a collision is elastic if either particle
 * collided less than t_c ago. t_c defaults to the contact duration of the matching linear
 * spring-dashpot (k_s, eps_n; eq. 2.6, unclamped), so event-driven and soft-sphere runs stop
 * dissipating in the same multi-contact situations; `tc` overrides it. The matching contact also
 * sets the nominal clock tick dt = t_c / steps_per_contact (the step of gr_sim_step). */
#include <math.h>
#include <stddef.h>

#include "core/restitution.h"
#include "granule/model.h"

static const gr_param params[] = {
    {"k_s", "N/m", GR_PARAM_DOUBLE, 5e5, 0.0, INFINITY, true, true,
     "spring constant of the matching soft contact; sets the TC contact time t_c (2.6)",
     offsetof(gr_contact_params, k_s)},
    {"eps_n", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, true, false,
     "normal coefficient of restitution (2.2); 1 = elastic",
     offsetof(gr_contact_params, eps_n)},
    {"eps_t", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "tangential coefficient of restitution (2.10), 2D; 1 = no tangential dissipation (default shared with tangential_dashpot)",
     offsetof(gr_contact_params, eps_t)},
    {"tc", "s", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "TC-model time: a collision is elastic if either particle collided less than tc ago; 0 = the contact duration of the matching spring-dashpot (k_s, eps_n)",
     offsetof(gr_contact_params, tc)},
};

static int prepare(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                   gr_error *err)
{
    (void)dt;
    if (!(p->eps_n > 0.0)) {
        /* eps_n = 0 leaves a touching pair at zero normal velocity: the next event is at the same
         * instant and the calendar never advances */
        return GR_FAIL(err, GR_EINVAL,
                       "[model] eps_n = %g: hard_sphere needs eps_n in (0, 1] (a perfectly sticking "
                       "instantaneous collision leaves the pair touching at zero normal speed); use e.g. 0.001",
                       p->eps_n);
    }
    if (!(p->tc >= 0.0) || !isfinite(p->tc)) {
        return GR_FAIL(err, GR_EINVAL, "[model] tc = %g: allowed range [0, inf) s", p->tc);
    }
    c->normal = GR_NORMAL_HARD_SPHERE;
    c->m12 = m12;
    c->clamp = false;
    c->zeta = gr_zeta_unclamped(p->eps_n); /* the matching spring-dashpot, eq. 2.6 */
    c->w0 = sqrt(p->k_s / m12);
    if (p->tc > 0.0) {
        /* the soft contact that lasts tc: w0 from the duration pi / (w0 sqrt(1 - zeta^2)) */
        c->w0 = gr_duration_unclamped(c->zeta) / p->tc;
    }
    c->k_s = m12 * c->w0 * c->w0;
    c->t_c = gr_duration_unclamped(c->zeta) / c->w0;
    c->eps_n_exact = p->eps_n;
    c->gamma_n = 0.0; /* no force law: kernels see a hard sphere as force-free */
    c->gamma_t = 0.0;
    return GR_OK;
}

const gr_model gr_model_hard_sphere = {
    .name = "hard_sphere",
    .summary = "instantaneous collisions (2.1, 2.2, 2.10) with the TC model against collapse; needs [integrator] kind = event",
    .kind = GR_MODEL_NORMAL | GR_MODEL_EVENT,
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .prepare = prepare,
};
