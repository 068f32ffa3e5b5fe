/* tangential_dashpot: F_t = -gamma_t (v12 . t) t while the normal contact acts (2.9), t = n
 * rotated by 90 degrees (2.8).
 *
 * Without rotation the tangential relative velocity decays as exp(-gamma_t t / m12) during the
 * contact, so eps_t = exp(-gamma_t t_c / m12). The thesis's eq. 2.12 takes t_c = pi sqrt(m12/k_s),
 * the undamped contact time; the real contact lasts pi/w (unclamped) or t_e (clamped), so we use
 * the actual duration of the chosen normal law: gamma_t = -m12 ln(eps_t) / t_c. Eq. 2.12 would
 * give eps_t^(1/sqrt(1 - zeta^2)) instead (docs/models.md). */
#ifndef GR_MODELS_TANGENTIAL_DASHPOT_H
#define GR_MODELS_TANGENTIAL_DASHPOT_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_tangential_dashpot;

/* The pair law (2.9): f_t = -gamma_t g_t while the normal force acts; dissipates gamma_t g_t^2. */
enum { GR_BOOK_tangential_dashpot = GR_BOOK_TANGENTIAL };
GR_LAW gr_tangential_force gr_tangential_tangential_dashpot(const gr_contact_coeffs *c,
                                                            const gr_tangential_in in)
{
    gr_tangential_force o = {.f = 0.0, .p = 0.0};
    if (in.acts) {
        const double gt = c->gamma_t;
        o.f = -gt * in.g_t;
        o.p = gt * in.g_t * in.g_t;
    }
    return o;
}

#endif /* GR_MODELS_TANGENTIAL_DASHPOT_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_TANGENTIAL_DASHPOT_IMPL)
#define GR_MODELS_TANGENTIAL_DASHPOT_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

#include "models/reference.h"

static const gr_param tangential_dashpot_params[] = {
    {"eps_t", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "tangential coefficient of restitution (2.10); 1 = no tangential dissipation",
     offsetof(gr_contact_params, eps_t)},
    GR_ROTATION_PARAMS,
};

static int tangential_dashpot_prepare(const gr_contact_params *p, double m12, double dt,
                                      gr_contact_coeffs *c, gr_error *err)
{
    (void)err;
    double t_c = c->t_c;
    if (!isfinite(t_c)) {
        t_c = M_PI / c->w0; /* a sticking normal contact: fall back to eq. 2.12 */
    }
    /* An explicit step multiplies v_t by (1 - gamma_t dt / m12); gamma_t = m12 / dt removes it in
     * one step, the closest a time step can get to eps_t = 0. */
    /* With rotation the contact point's tangential velocity has the mass m_t (c->m_t, set before
     * prepare; m12 without rotation), so eps_t is always the restitution of that velocity. */
    (void)m12;
    const double m_t = c->m_t;
    double step = dt > 0.0 ? dt : t_c / 50.0;
    double gamma_max = m_t / step;
    double gamma = p->eps_t > 0.0 ? -m_t * log(p->eps_t) / t_c : gamma_max;
    c->gamma_t = fmin(gamma, gamma_max);
    return GR_OK;
}

/* Its restitution law: g_t (at the contact point) decays as exp(-gamma_t t / m_t) while the
 * normal force acts, for the contact duration t_c of the normal law (a sticking contact:
 * pi / w0); m_t = m12 without rotation, m12 q / (1 + q) with it. */
static double tangential_dashpot_restitution_t(const gr_contact_coeffs *c, gr_normal_impact n,
                                               double v_n, double v_t)
{
    (void)v_n;
    (void)v_t;
    double t_c = n.t_c;
    if (!isfinite(t_c)) {
        t_c = M_PI / c->w0;
    }
    return exp(-c->gamma_t * t_c / c->m_t);
}

/* The force the CVODE reference integrates (models/reference.h): F_t = -gamma_t g_c (2.9). */
enum { TANGENTIAL_DASHPOT_REF_CT = 0 }; /* gamma_t / (m12 w0) */
static void tangential_dashpot_ref_setup(const gr_contact_coeffs *c, double m12, double w0,
                                         double len, gr_ref_tangential *l)
{
    (void)len;
    l->k[TANGENTIAL_DASHPOT_REF_CT] = c->gamma_t / (m12 * w0);
}

static void tangential_dashpot_ref_force(const gr_ref_tangential *l, gr_ref_point *p)
{
    p->ft = -l->k[TANGENTIAL_DASHPOT_REF_CT] * p->gc;
}

static const gr_reference_law tangential_dashpot_reference = {
    .setup = tangential_dashpot_ref_setup,
    .force = tangential_dashpot_ref_force,
};

/* eps_t = 1 gives gamma_t = 0: the law does nothing, the kernel without it runs */
static bool tangential_dashpot_inert(const gr_contact_coeffs *c) { return c->gamma_t == 0.0; }

const gr_model gr_model_tangential_dashpot = {
    .name = "tangential_dashpot",
    .summary = "tangential dashpot (thesis 2.9-2.12), gamma_t set for the actual contact duration",
    .kind = GR_MODEL_TANGENTIAL,
    .params = tangential_dashpot_params,
    .n_params = sizeof tangential_dashpot_params / sizeof tangential_dashpot_params[0],
    .prepare = tangential_dashpot_prepare,
    .inert = tangential_dashpot_inert,
    .contact_point = true,
    .constant_eps_t = true,
    .lammps_pair = "gran/hooke",
    .restitution_t = tangential_dashpot_restitution_t,
    .reference = &tangential_dashpot_reference,
    .elastic = "eps_t=1",
};
#endif /* GR_MODEL_IMPL */
