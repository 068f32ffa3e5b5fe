/* Flat walls and gravity ([boundary] x, y and [gravity] gx, gy; docs/systems-walls-gravity.md).
 *
 * Walls on axis a stand at q = 0 and q = L (q the coordinate along a). A wall is a particle of
 * infinite mass and radius: a grain of radius r at q overlaps the wall at 0 by xi = r - q and the
 * wall at L by xi = q + r - L, and feels the scene's normal law (spring_dashpot, hertz; the law of
 * the pair kernel, gr_kernel_normal) with the wall's coefficients: those of the same model
 * prepared for the reduced mass M of a grain against an infinite mass (a pair of grains has M/2),
 * so eps_n is the scene's eps_n for a wall contact too; the stiffness (k_s, k_h) is the scene's.
 * The wall's normal points into the box and the wall does not move, so g_n = +v_a at the wall at 0
 * and -v_a at the wall at L (< 0 approaching), and the force on the grain is f_n along the normal.
 *
 * Gravity is a constant force M g on every grain. It enters the forces but not their
 * non-conservative part (gx, gy), so the step books no dissipation for it: its work shows up as the
 * change of the potential energy -M sum g . r_i, which the ledger carries (gr_sim_ledger). The wall
 * springs' energy is part of the elastic energy, their dashpots' work is normal dissipation, booked
 * by the step like a pair's. So injected - dissipated = change of kinetic + elastic + potential
 * still closes, to the velocity-Verlet error of the contacts.
 *
 * A vibrating wall ([boundary] vibrate, amplitude, frequency) is the wall at 0 of one axis at
 * q_w = A sin(2 pi f t): the overlap is r - (q - q_w), g_n = v - q_w'. Its force's power on the
 * grains, f_n q_w', is the work it injects (booked as injected, per step); the dissipation is that
 * of the relative motion, -f_d g_n.
 *
 * This pass runs after the pair kernel, once per force evaluation, only when walls or gravity are
 * on (gr_sim.walls_on, chosen once): the pair kernels are untouched. The 2D neighbour list does
 * not wrap across a wall axis (gr_sim.period, neighbours.c), so no pair is seen through a wall. The
 * 1D ring's kernel always closes the ring with the pair (n-1, 0) at gap x_0 + L - x_{n-1}; with
 * walls that pair does not exist, and the rare times both end grains press into their walls so
 * hard that the kernel finds it overlapping, this pass takes its force back out. */
#include <math.h>

#include "core/sim_internal.h"

static const char axis_name[2] = {'x', 'y'};

int gr_walls_prepare(gr_sim *s, gr_error *err)
{
    const gr_sim_params *p = &s->params;
    s->period[0] = s->period[1] = s->L;
    s->walls_on = p->walls[0] || p->walls[1] || p->gravity[0] != 0.0 || p->gravity[1] != 0.0 ||
                  p->vibrate != 0;
    if (!s->walls_on) {
        return GR_OK; /* the periodic box: nothing here ever runs */
    }
    if (!s->integrator->walls) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] walls and [gravity] need an integrator that models them "
                       "(gr_integrator_type.walls: verlet); given [integrator] kind = %s",
                       p->source, s->integrator->name);
    }
    if (s->dim == 1 && (p->walls[1] || p->gravity[1] != 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] y and [gravity] gy need dim = 2; in 1D only x and gx "
                       "(allowed in 1D: y = periodic, gy = 0)",
                       p->source);
    }
    for (int a = 0; a < s->dim; a++) {
        if (p->gravity[a] != 0.0 && !p->walls[a]) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [gravity] g%c = %g m/s^2 needs walls along %c ([boundary] %c = "
                           "walls): a periodic axis under gravity accelerates for ever; allowed "
                           "with %c = periodic: g%c = 0",
                           p->source, axis_name[a], p->gravity[a], axis_name[a], axis_name[a],
                           axis_name[a], axis_name[a]);
        }
    }
    if (p->tangential) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [model] tangential = %s has no wall contact yet: with [boundary] walls "
                       "allowed: tangential = none",
                       p->source, p->tangential->name);
    }
    if (p->vibrate &&
        !(p->vibrate <= s->dim && p->walls[p->vibrate - 1] && p->amplitude >= 0.0 &&
          p->amplitude < 0.25 * s->L && p->frequency >= 0.0 && isfinite(p->frequency))) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] vibrate = %d needs walls along that axis (1 = x, 2 = y), "
                       "amplitude in [0, L / 4) = [0, %g) m and frequency in [0, inf) Hz; given "
                       "amplitude = %g m, frequency = %g Hz",
                       p->source, p->vibrate, 0.25 * s->L, p->amplitude, p->frequency);
    }
    if (s->integrator->instantaneous) {
        /* collisions with the walls are the integrator's own events (event_2d.c), placed as
         * below; no force law and no neighbour list */
    } else if (!p->normal || !(p->normal->kind & GR_MODEL_NORMAL)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] walls need a normal force law (spring_dashpot, hertz, ...); "
                       "given [model] normal = %s",
                       p->source, p->normal ? p->normal->name : "none");
    }
    const double r = 0.5 * s->d;
    for (int a = 0; a < s->dim; a++) {
        if (!p->walls[a]) {
            continue;
        }
        /* a listed pair must never be nearer through the periodic image than directly (the pair
         * kernel takes the minimum image), so the box spans at least twice the list's reach */
        const double reach = s->dim == 2 ? 2.0 * s->d * (1.0 + 2.0 * p->skin) : 2.0 * s->d;
        if (!(s->L > reach)) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [system] L = %g m is too short for walls along %c: allowed L > %g "
                           "m (2 d (1 + 2 skin))",
                           p->source, s->L, axis_name[a], reach);
        }
        const double *q = a == 0 ? s->x : s->y;
        for (int i = 0; i < s->n; i++) {
            if (!(q[i] >= r && q[i] <= s->L - r)) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: particle %d at %c = %g m overlaps a wall: with [boundary] %c "
                               "= walls every centre must lie in [r, L - r] = [%g, %g] m; choose "
                               "another [placement] kind or a larger L",
                               p->source, i, axis_name[a], q[i], axis_name[a], r, s->L - r);
            }
        }
        s->period[a] = INFINITY; /* the neighbour list does not wrap across the walls */
    }
    if (s->integrator->instantaneous) {
        return GR_OK;
    }
    /* the same law against an infinite mass: reduced mass M instead of M / 2 */
    return gr_contact_prepare(p->normal, NULL, &p->contact, s->mass, s->dt, &s->wall_cc, err);
}

/* The contacts of every grain with the two walls of axis a (coordinates q, velocities v, forces
 * f and their non-conservative part g), the wall at 0 at qw moving with vw (0 and 0 unless it
 * vibrates); adds the walls' energy / e_scale to *e and their dissipation rate to *pn, and for a
 * moving wall the power it does on the grains, sum f_n vw, to *pw and the part of the step's
 * booking (the work of g on the grains, -f_d v) that is the wall's work, not dissipation, sum
 * f_d vw, to *pd. */
static void axis_walls(const gr_sim *s, const double *restrict q, const double *restrict v,
                       double *restrict f, double *restrict g, const double qw, const double vw,
                       double *e, double *pn, double *pw, double *pd, gr_force_report *r_out)
{
    const double r = 0.5 * s->d, L = s->L;
    for (int i = 0; i < s->n; i++) {
        const double lo = r - (q[i] - qw), hi = q[i] + r - L;
        /* the step's runaway guard (overlap > RUNAWAY_OVERLAP = 0.5 d, step.c) sees a wall's
         * overlap doubled, xi / r, with worst_j = -1: a grain deeper than r has crossed the wall
         * (and in 2D the drift has wrapped it to the other side), so it must stop at half a
         * radius. Only then: max_overlap otherwise stays the pairs' (gr_sim_max_overlap). */
        const double deepest = (lo > hi ? lo : hi) / r;
        if (deepest > 0.5 && deepest > r_out->max_overlap) {
            r_out->max_overlap = deepest;
            r_out->worst_i = i;
            r_out->worst_j = -1;
        }
        if (lo > 0.0) { /* the wall at 0: normal +e_a, g_n = v - vw */
            double f_d, ei;
            const double g_n = v[i] - vw;
            const double f_n = gr_kernel_normal(s, &s->wall_cc, lo, g_n, &f_d, &ei);
            f[i] += f_n;
            g[i] += f_d;
            *e += ei;
            *pn -= f_d * g_n;
            *pw += f_n * vw;
            *pd += f_d * vw;
        }
        if (hi > 0.0) { /* the wall at L: normal -e_a, g_n = -v */
            double f_d, ei;
            f[i] -= gr_kernel_normal(s, &s->wall_cc, hi, -v[i], &f_d, &ei);
            g[i] -= f_d;
            *e += ei;
            *pn += f_d * v[i];
        }
    }
}

/* 1D with walls: take the ring's closing pair (n-1, 0) back out if the kernel found it touching. */
static void unwrap_ring(gr_sim *s, gr_force_report *r)
{
    const int n = s->n;
    if (n < 2 || !s->pair_contact[n - 1]) {
        return;
    }
    const double ov = s->d - (s->x[0] + s->L - s->x[n - 1]), g_n = s->vx[0] - s->vx[n - 1];
    double f_d, e;
    const double f_n = gr_kernel_normal(s, &s->cc, ov, g_n, &f_d, &e);
    s->fx[n - 1] += f_n;
    s->fx[0] -= f_n;
    s->gx[n - 1] += f_d;
    s->gx[0] -= f_d;
    r->elastic -= s->cc.e_scale * e;
    r->power_normal += f_d * g_n;
    r->new_contacts -= 1; /* the flag is cleared below every time, so the kernel counted it new */
    s->pair_contact[n - 1] = 0;
}

void gr_walls_forces(gr_sim *s, gr_force_report *r)
{
    const gr_sim_params *p = &s->params;
    double e = 0.0, pn = 0.0, pw = 0.0, pd = 0.0;
    /* a vibrating wall at 0 of axis vibrate - 1: A sin(w t), velocity A w cos(w t), at the time of
     * this evaluation (the positions' time, step dt) */
    double qw[2] = {0.0, 0.0}, vw[2] = {0.0, 0.0};
    if (p->vibrate) {
        const double w = 2.0 * M_PI * p->frequency, t = gr_sim_time(s);
        qw[p->vibrate - 1] = p->amplitude * sin(w * t);
        vw[p->vibrate - 1] = p->amplitude * w * cos(w * t);
    }
    if (p->walls[0]) {
        if (s->dim == 1) {
            unwrap_ring(s, r);
        }
        axis_walls(s, s->x, s->vx, s->fx, s->gx, qw[0], vw[0], &e, &pn, &pw, &pd, r);
    }
    if (p->walls[1]) {
        axis_walls(s, s->y, s->vy, s->fy, s->gy, qw[1], vw[1], &e, &pn, &pw, &pd, r);
    }
    r->elastic += s->wall_cc.e_scale * e;
    r->power_normal += pn;
    /* the moving wall's work: these forces kick the grains for one step (two half kicks), so its
     * work is its power times dt (injected); the step books the work of g, -f_d v, as dissipation,
     * of which f_d vw is the wall's, not lost: given back here, so dissipated is -f_d (v - vw) */
    s->injected += pw * s->dt;
    s->diss_n += pd * s->dt;
    /* gravity: conservative, so into f only (its work is the change of the potential energy) */
    for (int a = 0; a < s->dim; a++) {
        const double mg = s->mass * p->gravity[a];
        double *restrict f = a == 0 ? s->fx : s->fy;
        for (int i = 0; mg != 0.0 && i < s->n; i++) {
            f[i] += mg;
        }
    }
}

double gr_walls_potential(const gr_sim *s)
{
    double u = 0.0;
    for (int a = 0; a < s->dim; a++) {
        const double ga = s->params.gravity[a];
        const double *q = a == 0 ? s->x : s->y;
        double sum = 0.0;
        for (int i = 0; ga != 0.0 && i < s->n; i++) {
            sum += q[i];
        }
        u -= s->mass * ga * sum;
    }
    return u;
}
