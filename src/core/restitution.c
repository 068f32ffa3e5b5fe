/* Exact restitution formulas of the linear spring-dashpot contact; see restitution.h. */
#include "core/restitution.h"

#include <math.h>

double gr_zeta_unclamped(double eps)
{
    if (eps >= 1.0) {
        return 0.0;
    }
    if (eps <= 0.0) {
        return 1.0; /* limit of L / sqrt(1 + L^2) as L -> infinity: critical damping */
    }
    double l = -log(eps) / M_PI;
    return l / sqrt(1.0 + l * l); /* eq. 2.6: gamma_n = 2 zeta sqrt(k m12) */
}

double gr_eps_unclamped(double zeta)
{
    if (zeta >= 1.0) {
        return 0.0;
    }
    return exp(-M_PI * zeta / sqrt(1.0 - zeta * zeta));
}

double gr_duration_unclamped(double zeta)
{
    if (zeta >= 1.0) {
        return INFINITY; /* critically or over-damped: the overlap never returns to zero */
    }
    return M_PI / sqrt(1.0 - zeta * zeta);
}

double gr_eps_clamped(double zeta)
{
    if (zeta <= 0.0) {
        return 1.0;
    }
    if (zeta < 1.0) {
        double w = sqrt(1.0 - zeta * zeta);
        double r = zeta / w;
        return exp(-r * (M_PI - 2.0 * atan(r)));
    }
    if (zeta == 1.0) {
        return exp(-2.0);
    }
    double big_w = sqrt(zeta * zeta - 1.0);
    /* ln((b+W)/(b-W)) = 2 artanh(W/b), stable for large zeta */
    return exp(-(zeta / big_w) * 2.0 * atanh(big_w / zeta));
}

double gr_duration_clamped(double zeta)
{
    if (zeta <= 0.0) {
        return M_PI;
    }
    if (zeta < 1.0) {
        double w = sqrt(1.0 - zeta * zeta);
        return (M_PI - 2.0 * atan(zeta / w)) / w;
    }
    if (zeta == 1.0) {
        return 2.0 / zeta;
    }
    double big_w = sqrt(zeta * zeta - 1.0);
    return (2.0 / big_w) * atanh(big_w / zeta);
}

double gr_zeta_clamped(double eps)
{
    if (eps >= 1.0) {
        return 0.0;
    }
    /* eps(zeta) falls monotonically from 1 (zeta = 0) to 0 (zeta -> infinity); for large zeta
     * eps ~ 1/(4 zeta^2), which brackets the root. */
    double lo = 0.0, hi = 1.0;
    while (gr_eps_clamped(hi) > eps) {
        hi *= 2.0;
        if (hi > 1e12) {
            return hi;
        }
    }
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; it++) {
        double mid = 0.5 * (lo + hi);
        if (gr_eps_clamped(mid) > eps) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}
