/* [driving] kind = langevin: a Langevin thermostat. Each particle feels a viscous drag and an
 * independent white-noise force (docs/systems-driving.md),
 *
 *     M dv/dt = F_contact - (M / tau) v + eta(t),   <eta_a(t) eta_b(t')> = 2 D_L delta_ab delta(t - t'),
 *
 * per component a. Without contacts each component is an Ornstein-Uhlenbeck process whose
 * stationary variance is <v_a^2> = D_L tau / M^2. The fluctuation-dissipation relation (Einstein
 * 1905; Kubo, Rep. Prog. Phys. 29, 255 (1966)) fixes D_L by the bath: <v_a^2> = T_bath / dim, so
 *
 *     D_L = M^2 T_bath / (dim tau),
 *
 * with T_bath in the units of the granular temperature T (2.19), which sums the dim components
 * (k_B T per degree of freedom = M T_bath / dim). An elastic gas then relaxes to T = T_bath
 * (equipartition), whatever its collisions; an inelastic one settles below.
 *
 * Over a step dt the OU process is integrated exactly (Gillespie, Phys. Rev. E 54, 2084 (1996)):
 *
 *     v <- v e^{-dt/tau} + sqrt(T_bath / dim (1 - e^{-2 dt/tau})) xi,   xi standard normal,
 *
 * applied where the random force's kick is (docs/integrator.md), so free flight has the exact
 * velocity statistics at any dt/tau; prepare turns (T_bath, tau, dt, dim) into the two factors
 * once per run. */
#include <math.h>

#include "granule/driving.h"

static const gr_param langevin_params[] = {
    {"T_bath", "m^2/s^2", GR_PARAM_DOUBLE, 0.01, 0.0, INFINITY, false, true,
     "(langevin) bath temperature in the units of T (2.19), summed over components: an elastic gas "
     "settles at "
     "T = T_bath, T_bath / dim per component; 0 = pure drag",
     offsetof(gr_driving_params, T_bath)},
    {"tau", "s", GR_PARAM_DOUBLE, 0.1, 0.0, INFINITY, true, true,
     "(langevin) drag time constant M / gamma: the drag is -M v / tau; velocities relax to the "
     "bath as "
     "e^{-t/tau}, the temperature as e^{-2t/tau}",
     offsetof(gr_driving_params, tau)},
};

static int langevin_prepare(const gr_driving_params *p, int dim, double dt, gr_driving_coeffs *c,
                            gr_error *err)
{
    if (!(p->tau > 0.0) || !(p->T_bath >= 0.0) || !isfinite(p->T_bath) || dim < 1) {
        return GR_FAIL(err, GR_EINVAL,
                       "[driving] langevin needs tau in (0, inf) s and T_bath in [0, inf) m^2/s^2; "
                       "given tau = %g, T_bath = %g",
                       p->tau, p->T_bath);
    }
    c->decay = exp(-dt / p->tau);
    c->kick = sqrt(p->T_bath / dim *
                   -expm1(-2.0 * dt / p->tau)); /* 1 - e^{-2 dt/tau}, exact for small dt/tau */
    return GR_OK;
}

void gr_bath_ou_step(const gr_driving_coeffs *c, double m1, int n, int dim, double *const v[3],
                     const double *mass_i, double M, const double *g, double *added,
                     double *dragged)
{
    double in = 0.0, out = 0.0;
    for (int i = 0; i < n; i++) {
        const double mi = mass_i ? mass_i[i] : M;
        const double ki = mass_i ? c->kick * sqrt(m1 / mi) : c->kick;
        for (int a = 0; a < dim; a++) {
            const double vi = v[a][i], vd = c->decay * vi, dv = ki * g[(size_t)i * dim + a];
            out += 0.5 * mi * (vi * vi - vd * vd);
            in += mi * dv * (vd + 0.5 * dv);
            v[a][i] = vd + dv;
        }
    }
    *added += in;
    *dragged += out;
}

const gr_driving_type gr_driving_langevin = {
    .name = "langevin",
    .summary =
        "Langevin thermostat: drag -M v / tau plus white noise of strength M^2 T_bath / (dim tau) "
        "(fluctuation-dissipation), so an elastic gas settles at T = T_bath; every integrator",
    .update = GR_DRIVE_BATH,
    .drag = true,
    .params = langevin_params,
    .n_params = (int)(sizeof langevin_params / sizeof langevin_params[0]),
    .prepare = langevin_prepare,
};
