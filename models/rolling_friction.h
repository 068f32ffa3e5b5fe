/* rolling_friction: rolling resistance of the constant directional torque kind (Zhou, Wright,
 * Yang, Xu & Yu, Physica A 269, 403 (1999), model "A"; LIGGGHTS's `rolling_friction cdt`; the
 * torque limit of Luding, Granular Matter 10, 235 (2008) and of LAMMPS's `rolling sds`).
 *
 * Two discs in contact whose angular velocities differ roll on each other: the relative rolling
 * velocity is v_r = R_eff (w_i - w_j) (2D: a scalar; R_eff = r_i r_j / (r_i + r_j) = r / 2 for our
 * equal discs; the same convention as LAMMPS's vrl = R_eff (w_i - w_j) x n and LIGGGHTS's
 * w_r = w_1 - w_2). The contact resists it with a pair of opposite torques of magnitude
 *   M = mu_r |F_n| R_eff,      tau_i = -M sign(w_i - w_j),   tau_j = +M sign(w_i - w_j).
 * They sum to zero and exert no force, so momentum and angular momentum are conserved and the
 * translation is untouched; their power is -(tau_i w_i + tau_j w_j) = M |w_i - w_j| >= 0, all of
 * it taken from the spins.
 *
 * No chatter at w_i = w_j: an explicit step with the full torque would flip w_i - w_j each step
 * (amplitude 2 M dt / I). The torque pair changes w_i - w_j by -2 M dt / I per step, so the law
 * is limited to what stops the relative rolling within one step, as sliding_friction does for
 * v_t:
 *   M = min(mu_r |F_n| R_eff, I |w_i - w_j| / (2 dt)),
 * and w_i - w_j never reverses through one contact (a disc with several contacts can still be
 * pushed past by the sum; the pair then brakes it again next step). With the limit the relative
 * rolling stops exactly once the contact has delivered the angular impulse I |w_i - w_j|_0 / 2
 * (rolling arrested, "sticking"); there is no rolling spring, so a stuck contact stores no
 * energy and is released as soon as the spins are driven apart again.
 *
 * Ledger: the torque work is booked exactly by the integrator's spin kicks (the work of every
 * non-conservative torque); the rolling power M |w_i - w_j| is reported with the friction column
 * (diss_f), beside sliding friction. */
#ifndef GR_MODELS_ROLLING_FRICTION_H
#define GR_MODELS_ROLLING_FRICTION_H

#include <math.h>

#include "models/law.h"

extern const gr_model gr_model_rolling_friction;

/* its own parameter (gr_contact_params.own) */
typedef struct rolling_friction_own {
    double mu_r; /* coefficient of rolling resistance */
} rolling_friction_own;

/* its constant, in gr_contact_coeffs.law_r */
enum { ROLLING_FRICTION_MU_R = 0 };

/* The pair law: the torque on j (on i its opposite) and the power it dissipates, >= 0. */
GR_LAW gr_rolling_torque gr_rolling_rolling_friction(const gr_contact_coeffs *c,
                                                     const gr_rolling_in in)
{
    const double dw = in.dw;
    const double cap = in.i_2dt * fabs(dw),
                 full = c->law_r[ROLLING_FRICTION_MU_R] * fabs(in.f_n) * in.r_eff;
    const double mag = in.acts ? (full < cap ? full : cap) : 0.0;
    const double m = dw > 0.0 ? mag : (dw < 0.0 ? -mag : 0.0);
    return (gr_rolling_torque){.m = m, .p = m * dw};
}

#endif /* GR_MODELS_ROLLING_FRICTION_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_ROLLING_FRICTION_IMPL)
#define GR_MODELS_ROLLING_FRICTION_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <stddef.h>

#include "models/reference.h"

static const gr_param rolling_friction_params[] = {
    {"mu_r", "", GR_PARAM_DOUBLE, 0.1, 0.0, INFINITY, false, true,
     "coefficient of rolling resistance: a torque pair of magnitude mu_r F_n R_eff (F_n the normal "
     "force, "
     "R_eff = r / 2) against w_i - w_j; 0 = none",
     GR_OWN_KEY(rolling_friction, mu_r)},
};

static int rolling_friction_prepare(const gr_contact_params *p, double m12, double dt,
                                    gr_contact_coeffs *c, gr_error *err)
{
    (void)m12;
    (void)dt;
    if (!c->rotation) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] rolling = rolling_friction needs [model] rotation = true (a torque "
                       "on the spins); "
                       "allowed without rotation: rolling = none");
    }
    c->law_r[ROLLING_FRICTION_MU_R] = GR_OWN(p, rolling_friction)->mu_r;
    return GR_OK;
}

/* mu_r = 0: no torque, the kernel without it runs */
static bool rolling_friction_inert(const gr_contact_coeffs *c)
{
    return c->law_r[ROLLING_FRICTION_MU_R] == 0.0;
}

/* an enormous coefficient: the torque is then always the limit that stops the rolling in a step */
static const char *const rolling_friction_extremes[] = {"mu_r=1e9", NULL};

/* Its restitution-like law, for a binary impact (2D): the pair delivers the angular impulse
 * J = min(mu_r R_eff int |F_n| dt, I |dw_0| / 2) against the relative spin dw_0 = w_i - w_j
 * (each disc's spin changes by J / I towards the other's), so the spins lose
 * I (w_i^2 + w_j^2) / 2 before minus after = J |dw_0| - J^2 / I of their energy (the conformance
 * suite and tests/test_rolling.c check the engine against this). The translation is untouched. */
static double rolling_friction_spin_loss(const gr_contact_coeffs *c, double p_n, double r_eff,
                                         double inertia, double dw0)
{
    const double J =
        fmin(c->law_r[ROLLING_FRICTION_MU_R] * r_eff * fabs(p_n), 0.5 * inertia * fabs(dw0));
    return J * fabs(dw0) - J * J / inertia;
}

/* the torque the CVODE reference integrates (models/reference.h): M = mu_r |F_n| R_eff */
static double rolling_friction_ref_torque(const gr_contact_coeffs *c, double fn_abs, double r_eff)
{
    return c->law_r[ROLLING_FRICTION_MU_R] * fn_abs * r_eff;
}

static const gr_reference_rolling rolling_friction_reference = {
    .torque = rolling_friction_ref_torque,
};

const gr_model gr_model_rolling_friction = {
    .name = "rolling_friction",
    .summary = "rolling resistance: torques -+ mu_r |F_n| R_eff against w_i - w_j (constant "
               "directional torque)",
    .kind = GR_MODEL_ROLLING,
    .params = rolling_friction_params,
    .n_params = sizeof rolling_friction_params / sizeof rolling_friction_params[0],
    .prepare = rolling_friction_prepare,
    .inert = rolling_friction_inert,
    .spin_loss = rolling_friction_spin_loss,
    .reference_rolling = &rolling_friction_reference,
    .elastic = "mu_r=0",
    .extremes = rolling_friction_extremes,
};
#endif /* GR_MODEL_IMPL */
