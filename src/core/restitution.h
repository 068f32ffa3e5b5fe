/* Exact restitution of the linear spring-dashpot contact, m12 xi'' + gamma xi' + k xi = 0,
 * with beta = gamma / (2 m12), w0 = sqrt(k / m12), zeta = beta / w0.
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
#ifndef GR_RESTITUTION_H
#define GR_RESTITUTION_H

/* Damping ratio the thesis's eq. 2.6 assigns to eps: zeta = L / sqrt(1 + L^2), L = -ln(eps)/pi.
 * eps = 0 gives critical damping (zeta = 1) without evaluating ln(0). */
double gr_zeta_unclamped(double eps);
/* Restitution and contact duration (in units of 1/w0) of the unclamped law at damping zeta < 1. */
double gr_eps_unclamped(double zeta);
double gr_duration_unclamped(double zeta);
/* Restitution and contact duration (units of 1/w0) of the clamped law, any zeta >= 0. */
double gr_eps_clamped(double zeta);
double gr_duration_clamped(double zeta);
/* Inverse of gr_eps_clamped for eps in (0, 1]: bisection on zeta (eps is monotone). */
double gr_zeta_clamped(double eps);

#endif
