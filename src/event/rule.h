/* The instantaneous collision rule of two equal masses (thesis eqs. 2.1, 2.2, 2.10), shared by
 * the event-driven core and `granule collide --model hard_sphere`.
 *
 * With n the unit normal from particle 1 to particle 2 and g = v1 - v2 (so g.n > 0 when the pair
 * approaches), t the unit tangent:
 *   (v1' + v2') = (v1 + v2)                     momentum (2.1)
 *   (v2' - v1').n = eps_n (v1 - v2).n           normal restitution (2.2)
 *   (v1' - v2').t = eps_t (v1 - v2).t           tangential restitution (2.10), same sign
 * hence v1' = v1 - (1 + eps_n)/2 (g.n) n - (1 - eps_t)/2 (g.t) t and v2' = v2 + (the same).
 * The relative kinetic energy m12 |g|^2 / 2 (m12 = M/2) loses
 *   dE_n = m12/2 (1 - eps_n^2) (g.n)^2,   dE_t = m12/2 (1 - eps_t^2) (g.t)^2,
 * i.e. the fraction 1 - eps^2 head-on (2.13) and 1 - (eps_n^2 + eps_t^2)/2 at 45 degrees (2.14). */
#ifndef GR_EVENT_RULE_H
#define GR_EVENT_RULE_H

/* Apply the rule to (v1, v2) in place (2D: components x, y; 1D: pass y components of 0 and
 * n = (+-1, 0)). Returns the dissipated energies in *de_n, *de_t (J) for particles of mass M. */
static inline void gr_event_collide(double M, double eps_n, double eps_t, double nx, double ny,
                                    double *v1x, double *v1y, double *v2x, double *v2y,
                                    double *de_n, double *de_t)
{
    const double gx = *v1x - *v2x, gy = *v1y - *v2y;
    const double gn = gx * nx + gy * ny;
    const double gt = gy * nx - gx * ny; /* t = (-ny, nx) */
    const double jn = 0.5 * (1.0 + eps_n) * gn, jt = 0.5 * (1.0 - eps_t) * gt;
    const double dx = jn * nx - jt * ny, dy = jn * ny + jt * nx;
    *v1x -= dx;
    *v1y -= dy;
    *v2x += dx;
    *v2y += dy;
    *de_n = 0.25 * M * (1.0 - eps_n * eps_n) * gn * gn;
    *de_t = 0.25 * M * (1.0 - eps_t * eps_t) * gt * gt;
}

#endif
