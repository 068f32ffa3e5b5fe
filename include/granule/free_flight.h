/* Free flight under the random force: the random-acceleration process.
 *
 * A free particle driven by white noise of strength D (<eta eta> = 2 D delta, eqs. 2.15/2.22,
 * no friction) over an interval tau has, per component, jointly Gaussian increments
 *   dv = v(tau) - v0,   dx = x(tau) - x0 - v0 tau
 * with zero means and (Chandrasekhar, Rev. Mod. Phys. 15, 1 (1943), ch. I sec. 2;
 * ../shared/notes/physics-algorithms.md sec. 1.2)
 *   Var(dv) = 2 D tau / M^2,   Cov(dx, dv) = D tau^2 / M^2,   Var(dx) = 2 D tau^3 / (3 M^2).
 * Exact sampler from two independent standard normals g1, g2:
 *   dv = sqrt(2 D tau) / M g1,   dx = (tau / 2) dv + sqrt(D tau^3 / 6) / M g2
 * (Var(dx) = D tau^3/(2M^2) + D tau^3/(6M^2) = 2 D tau^3/(3M^2); Cov = (tau/2) 2 D tau/M^2).
 * The same (dv, dx) is produced by a piecewise-constant acceleration a1 on [0, tau/2) and a2
 * on [tau/2, tau), which event-driven codes can follow exactly (relative motion stays a
 * polynomial in time): gr_free_flight_accelerations. */
#ifndef GRANULE_FREE_FLIGHT_H
#define GRANULE_FREE_FLIGHT_H

/* Exact increments of one component over tau, from standard normals g1, g2. */
static inline void gr_free_flight_sample(double D, double mass, double tau, double g1, double g2,
                                         double *dv, double *dx)
{
    *dv = __builtin_sqrt(2.0 * D * tau) / mass * g1;
    *dx = 0.5 * tau * *dv + __builtin_sqrt(D * tau * tau * tau / 6.0) / mass * g2;
}

/* Accelerations a1 (first half of tau) and a2 (second half) that produce exactly the increments
 * (dv, dx) above: dv = (a1 + a2) tau / 2 and dx = (3 a1 + a2) tau^2 / 8. */
static inline void gr_free_flight_accelerations(double tau, double dv, double dx, double *a1,
                                                double *a2)
{
    /* dx - dv tau / 4 = (3 a1 + a2 - a1 - a2) tau^2 / 8 = a1 tau^2 / 4 */
    *a1 = 4.0 * (dx - 0.25 * dv * tau) / (tau * tau);
    *a2 = 2.0 * dv / tau - *a1;
}

#endif
