/* spring_dashpot's restitution law (and that of hard_sphere's matching soft contact), included
 * by models/spring_dashpot.h and models/hard_sphere.h inside GR_MODEL_IMPL (compiled once, in
 * models/registry.c): the exact restitution of the linear spring-dashpot contact,
 * m12 xi'' + gamma xi' + k xi = 0, with beta = gamma / (2 m12), w0 = sqrt(k / m12),
 * zeta = beta / w0.
 *
 * Unclamped (the thesis, eq. 2.6): the contact ends when the overlap returns to zero,
 *   eps = exp(-pi beta / w), w = sqrt(w0^2 - beta^2), duration pi / w.
 * Clamped (F_n = max(0, k xi + gamma xi'), Schwager & Poeschel, Granular Matter 9, 465 (2007)):
 * the contact ends when the force vanishes,
 *   zeta < 1: eps = exp(-(beta/w)(pi - 2 arctan(beta/w))), t_e = (pi - 2 arctan(beta/w)) / w
 *   zeta = 1: eps = exp(-2), t_e = 2 / beta
 *   zeta > 1: W = sqrt(beta^2 - w0^2), eps = exp(-(beta/W) ln((beta+W)/(beta-W))),
 *             t_e = (2/W) artanh(W/beta).
 * (../shared/notes/physics-algorithms.md sec. 4.1 derives and checks these.) */
#ifndef GR_MODELS_SPRING_DASHPOT_RESTITUTION_H
#define GR_MODELS_SPRING_DASHPOT_RESTITUTION_H

#include <math.h>

/* Damping ratio the thesis's eq. 2.6 assigns to eps: zeta = L / sqrt(1 + L^2), L = -ln(eps)/pi.
 * eps = 0 gives critical damping (zeta = 1) without evaluating ln(0). */
static inline double spring_dashpot_zeta_unclamped(double eps)
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

/* Restitution and contact duration (in units of 1/w0) of the unclamped law at damping zeta < 1. */
static inline double spring_dashpot_eps_unclamped(double zeta)
{
    if (zeta >= 1.0) {
        return 0.0;
    }
    return exp(-M_PI * zeta / sqrt(1.0 - zeta * zeta));
}

static inline double spring_dashpot_duration_unclamped(double zeta)
{
    if (zeta >= 1.0) {
        return INFINITY; /* critically or over-damped: the overlap never returns to zero */
    }
    return M_PI / sqrt(1.0 - zeta * zeta);
}

/* Restitution and contact duration (units of 1/w0) of the clamped law, any zeta >= 0. */
static inline double spring_dashpot_eps_clamped(double zeta)
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

static inline double spring_dashpot_duration_clamped(double zeta)
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

/* Inverse of spring_dashpot_eps_clamped for eps in (0, 1]: bisection on zeta (eps is monotone). */
static inline double spring_dashpot_zeta_clamped(double eps)
{
    if (eps >= 1.0) {
        return 0.0;
    }
    /* eps(zeta) falls monotonically from 1 (zeta = 0) to 0 (zeta -> infinity); for large zeta
     * eps ~ 1/(4 zeta^2), which brackets the root. */
    double lo = 0.0, hi = 1.0;
    while (spring_dashpot_eps_clamped(hi) > eps) {
        hi *= 2.0;
        if (hi > 1e12) {
            return hi;
        }
    }
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; it++) {
        double mid = 0.5 * (lo + hi);
        if (spring_dashpot_eps_clamped(mid) > eps) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

#endif
