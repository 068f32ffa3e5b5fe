/* Flat walls and gravity ([boundary] x, y and [gravity] gx, gy; docs/systems-walls-gravity.md).
 *
 * Walls on axis a stand at q = 0 and q = L (q the coordinate along a). A wall is a particle of
 * infinite mass and radius: a grain of radius r at q overlaps the wall at 0 by xi = r - q and the
 * wall at L by xi = q + r - L, and feels the scene's normal law (spring_dashpot, hertz; the law of
 * the pair kernel, gr_kernel_normal) with the wall's coefficients: those of the same model
 * prepared for the reduced mass M of a grain against an infinite mass (a pair of grains has M/2)
 * from [model]'s parameters with the walls' own eps_n, eps_t, mu ([boundary]; the particles' by
 * default), so a wall contact has the restitution [boundary] eps_n; the stiffness (k_s, k_h) is
 * the scene's. The wall's normal n points into the box and the wall does not move, so g_n = +v_a
 * at the wall at 0 and -v_a at the wall at L (< 0 approaching), and the force on the grain is f_n
 * along the normal.
 *
 * Tangential laws (2D): the wall is the pair's partner i (n from the wall to the grain, t = n
 * rotated by -90 degrees as in models/law.h), not rotating, its contact point on the grain's
 * surface at distance r from its centre: g_t = v.t + r w (the wall's surface does not move along
 * t), the force f_t t acts on the grain and its torque r f_t on the grain only; the law's mass is
 * the contact point's, m_t = M q / (1 + q) with rotation (M without), prepared with m12 = M. A
 * history law keeps one slot per grain and wall (s->wall_hist), forgotten when the contact ends
 * as in the pair kernel, its spring energy in the elastic energy and its torque's spring part out
 * of s->tg.
 *
 * Gravity is a constant force M g on every grain. It enters the forces but not their
 * non-conservative part (gx, gy), so the step books no dissipation for it: its work shows up as the
 * change of the potential energy -M sum g . r_i, which the ledger carries (gr_sim_ledger). The wall
 * springs' energy is part of the elastic energy, their dashpots' work is normal dissipation, booked
 * by the step like a pair's. So injected - dissipated = change of kinetic + elastic + potential
 * still closes, to the velocity-Verlet error of the contacts.
 *
 * A vibrating wall ([boundary] vibrate, amplitude, frequency, motion) is the wall at 0 of one axis
 * at q_w = A sin(2 pi f t), or for a sawtooth q_w = A (2 frac(f t + 1/2) - 1) (rising at 2 A f,
 * dropping by 2 A at t = (k + 1/2) / f): the overlap is r - (q - q_w), g_n = v - q_w'. Its force's
 * power on the grains, f_n q_w', is its work (gr_ledger.wall_work, per step); the dissipation is
 * that of the relative motion, -f_d g_n. A sawtooth's drop between two evaluations releases the
 * springs of the grains pressed into it without any force doing work: the wall's work then is
 * the change of their energy, evaluated at the grains' positions with the wall before and after
 * the drop. The normal force of each evaluation on each wall, times dt, adds to its impulse
 * (gr_sim_wall_impulse), whose differences give the mean force on the wall.
 *
 * This pass runs after the pair kernel, once per force evaluation, only when walls or gravity are
 * on (gr_sim.walls_on, chosen once): the pair kernels are untouched. The 2D neighbour list does
 * not wrap across a wall axis (gr_sim.period, neighbours.c), so no pair is seen through a wall. The
 * 1D ring's kernel always closes the ring with the pair (n-1, 0) at gap x_0 + L - x_{n-1}; with
 * walls that pair does not exist, and the rare times both end grains press into their walls so
 * hard that the kernel finds it overlapping, this pass takes its force back out.
 *
 * Species lists (docs/mixtures.md): a grain touches a wall at its own radius r_i and feels the
 * wall's law prepared for its own mass (reduced mass m_i against the infinite wall; hertz's k_h
 * scaled as for its own pair: s->wall_cc_sp, gr_species_wall_coeffs), gravity is m_i g. Without
 * species every grain has r = d / 2 and the coefficients s->wall_cc, as before. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"

static const char axis_name[3] = {'x', 'y', 'z'};

int gr_walls_prepare(gr_sim *s, gr_error *err)
{
    const gr_sim_params *p = &s->params;
    s->period[0] = s->period[1] = s->period[2] = s->L;
    s->walls_on = p->walls[0] || p->walls[1] || p->walls[2] || p->gravity[0] != 0.0 ||
                  p->gravity[1] != 0.0 || p->gravity[2] != 0.0 || p->vibrate != 0;
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
    if (s->dim < 3 && (p->walls[2] || p->gravity[2] != 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] z and [gravity] gz need dim = 3 (allowed in %dD: z = "
                       "periodic, gz = 0)",
                       p->source, s->dim);
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
    if (p->vibrate && p->motion != GR_WALL_SINE && p->motion != GR_WALL_SAWTOOTH) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [boundary] motion = %d: allowed %d (sine) or %d (sawtooth)", p->source,
                       p->motion, GR_WALL_SINE, GR_WALL_SAWTOOTH);
    }
    if (p->vibrate &&
        !(p->vibrate <= s->dim && p->walls[p->vibrate - 1] && p->amplitude >= 0.0 &&
          p->amplitude < 0.25 * s->L && p->frequency >= 0.0 && isfinite(p->frequency))) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [boundary] vibrate = %d needs walls along that axis (1 = x, 2 = y, 3 = z), "
            "amplitude in [0, L / 4) = [0, %g) m and frequency in [0, inf) Hz; given "
            "amplitude = %g m, frequency = %g Hz",
            p->source, p->vibrate, 0.25 * s->L, p->amplitude, p->frequency);
    }
    if (s->integrator->instantaneous) {
        /* collisions with the walls are the integrator's own events (event_cells.h), placed as
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
        const double *q = a == 0 ? s->x : a == 1 ? s->y : s->z;
        for (int i = 0; i < s->n; i++) {
            const double ri = s->rad ? s->rad[i] : r; /* species: its own radius */
            if (!(q[i] >= ri && q[i] <= s->L - ri)) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: particle %d at %c = %g m overlaps a wall: with [boundary] %c "
                               "= walls every centre must lie in [r, L - r] = [%g, %g] m; choose "
                               "another [placement] kind or a larger L",
                               p->source, i, axis_name[a], q[i], axis_name[a], ri, s->L - ri);
            }
        }
        s->period[a] = INFINITY; /* the neighbour list does not wrap across the walls */
    }
    /* the event integrator's wall hits use the same coefficients through its rule (event_cells.h) */
    /* the same laws against an infinite mass: reduced mass M instead of M / 2, with the walls' own
     * restitution and friction */
    gr_contact_params wp = p->contact;
    if (p->wall_coeffs) {
        if (!(p->wall_eps_n >= 0.0 && p->wall_eps_n <= 1.0 && p->wall_eps_t >= 0.0 &&
              p->wall_eps_t <= 1.0 && p->wall_mu >= 0.0 && isfinite(p->wall_mu))) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [boundary] eps_n = %g, eps_t = %g, mu = %g: allowed eps_n, eps_t "
                           "in [0, 1] and mu in [0, inf)",
                           p->source, p->wall_eps_n, p->wall_eps_t, p->wall_mu);
        }
        wp.eps_n = p->wall_eps_n;
        wp.eps_t = p->wall_eps_t;
        wp.mu = p->wall_mu;
    }
    const gr_model *tang = s->dim >= 2 ? p->tangential : NULL;
    int rc = gr_contact_prepare(p->normal, tang, &wp, s->mass, s->dt, &s->wall_cc, err);
    if (rc) {
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message); /* GR_FAIL rewrites err->message */
        return GR_FAIL(err, rc,
                       "%s: the walls' contact ([boundary] eps_n = %g, eps_t = %g, mu = %g): %s",
                       p->source, wp.eps_n, wp.eps_t, wp.mu, why);
    }
    if (s->cc_pair && !s->integrator->instantaneous) { /* species lists: each its own contact */
        rc = gr_species_wall_coeffs(s, &wp, s->dt, err);
        if (rc) {
            return rc;
        }
    }
    s->wall_tl =
        tang && !(tang->inert && tang->inert(&s->wall_cc)) ? gr_kernel_tangential_id(tang) : 0;
    if (s->wall_tl && gr_kernel_tangential_history(s->wall_tl)) {
        if (s->dim == 3 && tang->inert && tang->inert(&s->cc)) {
            /* the non-conservative torques (tgx, tgy, tg) are zeroed by the pair kernel, which
             * runs the history law only when the particles' coefficients switch it on */
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [boundary] eps_t = %g, mu = %g switch the walls' %s on while the "
                           "particles' [model] eps_t = %g, mu = %g leave it off; allowed in 3D: "
                           "the particles' law on too, or the walls' off",
                           p->source, wp.eps_t, wp.mu, tang->name, p->contact.eps_t, p->contact.mu);
        }
        /* 2D: one slot per grain and wall (4); 3D: a vector per grain and wall (3 x 6) */
        s->wall_hist = calloc((s->dim == 3 ? 18 : 4) * (size_t)s->n + 1, sizeof(double));
        /* rotation: the springs' torques are conservative, the rest goes into s->tg (as the pair
         * kernel's; allocated here when the particles' law does nothing) */
        if (!s->wall_hist ||
            (s->omega && !s->tg && !(s->tg = calloc((size_t)s->n + 1, sizeof(double)))) ||
            (s->wx && !s->tgx && !(s->tgx = calloc((size_t)s->n + 1, sizeof(double)))) ||
            (s->wx && !s->tgy && !(s->tgy = calloc((size_t)s->n + 1, sizeof(double))))) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %d grains' wall contacts", s->n);
        }
    }
    return GR_OK;
}

/* What one evaluation's wall contacts add up to: the normal springs' energy / e_scale (e) and
 * the tangential springs' (et, J), dissipation rates (pn, pt, pf), energy a history law dropped
 * (lost), for a moving wall its power on the grains (pw) and the share of the step's booking that
 * is its work (pd), and the normal force on each wall (fw: 0 and L of x, then of y, then of z). */
typedef struct wall_sums {
    double e, et, pn, pt, pf, lost, pw, pd;
    double fw[6];
    double ej; /* species: the normal springs' energy, J (each species' own e_scale) */
} wall_sums;

/* Grain i's contact with a wall: its species' (s->wall_cc_sp), a radius distribution's scaled to
 * the grain (into *tmp: the walls' coefficients s->wall_cc, prepared for the mean mass and the
 * scene's k_h of two grains of radius_min, scaled to M = m_i and R = r_i / 2 as for its own pair,
 * gr_size_scaled), or s->wall_cc. */
static inline const gr_contact_coeffs *wall_coeffs(const gr_sim *s, int i, gr_contact_coeffs *tmp)
{
    if (s->wall_cc_sp) {
        return &s->wall_cc_sp[s->species[i]];
    }
    if (s->rad && !s->cc_pair) {
        gr_size_scaled(&s->wall_cc, s->mass, 0.5 * s->params.size_min, s->mass_i[i],
                       0.5 * s->rad[i], tmp);
        return tmp;
    }
    return &s->wall_cc;
}

/* Whether each grain's wall contact has its own e_scale (species lists, a radius distribution). */
static inline bool own_walls(const gr_sim *s) { return s->wall_cc_sp || (s->rad && !s->cc_pair); }

/* The vibrating wall at time t (sim_internal.h). */
void gr_walls_motion(const gr_sim_params *p, double t, double *q, double *v)
{
    if (p->motion == GR_WALL_SAWTOOTH) {
        const double ph = p->frequency * t + 0.5;
        *q = p->amplitude * (2.0 * (ph - floor(ph)) - 1.0);
        *v = 2.0 * p->amplitude * p->frequency;
        return;
    }
    const double w = 2.0 * M_PI * p->frequency;
    *q = p->amplitude * sin(w * t);
    *v = p->amplitude * w * cos(w * t);
}

/* The tangential law at the contact of grain i with a wall whose t is st times the other axis's
 * unit vector (v_o, f_o, g_o that axis's velocities, forces and their non-conservative part), its
 * history in slot k of s->wall_hist; acts = 0 for a contact that ended (a history law forgets). */
static void wall_tangential(gr_sim *s, int i, int k, double st, const double *v_o, double *f_o,
                            double *g_o, double f_n, double xi, double g_n, int acts, wall_sums *w)
{
    const double r = gr_grain_r(s, i); /* species: its own radius and contact */
    gr_contact_coeffs tmp;
    const gr_contact_coeffs *wc = wall_coeffs(s, i, &tmp);
    double g_t = st * v_o[i];
    if (s->omega) {
        g_t +=
            r * s->omega[i]; /* the grain's surface at the contact point; the wall's is at rest */
    }
    double slot = s->wall_hist ? s->wall_hist[k] : 0.0;
    const gr_tangential_in in = {.g_t = g_t,
                                 .f_n = f_n,
                                 .xi = xi,
                                 .g_n = g_n,
                                 .acts = acts,
                                 .m12_dt = wc->m_t / s->dt,
                                 .hist = s->wall_hist ? &slot : NULL};
    int book, hist;
    const gr_tangential_force ft = gr_kernel_tangential(s->wall_tl, wc, in, &book, &hist);
    const double nc = hist ? ft.f - ft.fc : ft.f; /* the non-conservative part */
    if (acts) {
        f_o[i] += st * ft.f;
        g_o[i] += st * nc;
        if (s->omega) {
            s->tq[i] += r * ft.f;
            if (s->tg) {
                s->tg[i] += r * nc;
            }
        }
    }
    const double p = hist ? -nc * g_t : ft.p;
    if (book == GR_BOOK_TANGENTIAL) {
        w->pt += p;
    } else {
        w->pf += p;
    }
    if (hist) {
        s->wall_hist[k] = slot;
        w->et += ft.e;
        w->lost += ft.lost;
    }
}

/* The contacts of every grain with the two walls of axis a (coordinates q, velocities v, forces
 * f and their non-conservative part g; v_o, f_o, g_o those of the other axis in 2D, NULL in 1D),
 * the wall at 0 at qw moving with vw (0 and 0 unless it vibrates); adds to *w (wall_sums). */
static void axis_wall_grain(gr_sim *s, const int a, const int i, const double *restrict q,
                            const double *restrict v, double *restrict f, double *restrict g,
                            const double *v_o, double *f_o, double *g_o, const double qw,
                            const double vw, wall_sums *w, gr_force_report *r_out, const double r,
                            const double L, const double st0, const int tang);

/* The walls' pass scans the grains in blocks of WALL_BLOCK (a multiple of 8). */
enum { WALL_BLOCK = 256 };

/* Whether each grain of [i0, i0 + m) touches a wall of the axis whose coordinates are q: branch
 * free, so that it vectorises (species: each grain's own radius, else r). */
static void wall_touch_flags(const gr_sim *s, const double *restrict q, const int i0, const int m,
                             const double r, const double qw, const double L,
                             uint8_t *restrict touch)
{
    const double *restrict qb = q + i0;
    if (s->rad) {
        const double *restrict rb = s->rad + i0;
        for (int k = 0; k < m; k++) {
            touch[k] = (uint8_t)((rb[k] - (qb[k] - qw) > 0.0) | (qb[k] + rb[k] - L > 0.0));
        }
    } else {
        for (int k = 0; k < m; k++) { /* vectorises */
            touch[k] = (uint8_t)((r - (qb[k] - qw) > 0.0) | (qb[k] + r - L > 0.0));
        }
    }
}

/* The grains i0 + k whose flag touch[k] (k < m) is set, in increasing order, into idx; returns
 * how many. The flags are read eight at a time: most words are zero (no grain of the eight
 * touches). Clears the flags. */
static int touching(uint8_t *restrict touch, const int m, const int i0, int *restrict idx)
{
    const int m8 = (m + 7) / 8 * 8;
    memset(touch + m, 0, (size_t)(m8 - m));
    int nt = 0;
    for (int k8 = 0; k8 < m8; k8 += 8) {
        uint64_t word;
        memcpy(&word, touch + k8, sizeof word);
        while (word) { /* the set bytes in increasing order (little or big endian alike) */
            int k = k8;
            while (!touch[k]) {
                k++;
            }
            touch[k] = 0;
            memcpy(&word, touch + k8, sizeof word);
            idx[nt++] = i0 + k;
        }
    }
    return nt;
}

static void axis_walls(gr_sim *s, const int a, const double *restrict q, const double *restrict v,
                       double *restrict f, double *restrict g, const double *v_o, double *f_o,
                       double *g_o, const double qw, const double vw, wall_sums *w,
                       gr_force_report *r_out)
{
    const double r = 0.5 * s->d, L = s->L;
    /* t = n rotated by -90 degrees: along +x at the floor (y = 0), -y at the wall x = 0 */
    const double st0 = a == 1 ? 1.0 : -1.0;
    const int tang = s->wall_tl != 0 && v_o;
    const bool hist = tang && s->wall_hist;
    /* Grains away from both walls do nothing here, and most grains are: a branch-free scan of a
     * block lists those that touch a wall (or still hold a wall spring), then only they are
     * visited, in order, so the sums are those of visiting every grain. */
    uint8_t touch[WALL_BLOCK];
    int idx[WALL_BLOCK];
    for (int i0 = 0; i0 < s->n; i0 += WALL_BLOCK) {
        const int m = i0 + WALL_BLOCK < s->n ? WALL_BLOCK : s->n - i0;
        wall_touch_flags(s, q, i0, m, r, qw, L, touch);
        if (hist) {
            for (int k = 0; k < m; k++) {
                const int i = i0 + k;
                touch[k] |=
                    s->wall_hist[4 * i + 2 * a] != 0.0 || s->wall_hist[4 * i + 2 * a + 1] != 0.0;
            }
        }
        const int nt = touching(touch, m, i0, idx);
        for (int t = 0; t < nt; t++) {
            const int i = idx[t];
            axis_wall_grain(s, a, i, q, v, f, g, v_o, f_o, g_o, qw, vw, w, r_out,
                            s->rad ? s->rad[i] : r, L, st0, tang);
        }
    }
}

/* One grain's contacts with the two walls of axis a (axis_walls). */
static void axis_wall_grain(gr_sim *s, const int a, const int i, const double *restrict q,
                            const double *restrict v, double *restrict f, double *restrict g,
                            const double *v_o, double *f_o, double *g_o, const double qw,
                            const double vw, wall_sums *w, gr_force_report *r_out, const double r,
                            const double L, const double st0, const int tang)
{
    {
        /* species: the grain's own contact with the walls (its mass, radius r) */
        gr_contact_coeffs tmp;
        const gr_contact_coeffs *wc = wall_coeffs(s, i, &tmp);
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
        const int k0 = 4 * i + 2 * a;
        if (lo > 0.0) { /* the wall at 0: normal +e_a, g_n = v - vw */
            double f_d, ei;
            const double g_n = v[i] - vw;
            const double f_n = gr_kernel_normal(s, wc, lo, g_n, &f_d, &ei);
            f[i] += f_n;
            g[i] += f_d;
            if (own_walls(s)) {
                w->ej += wc->e_scale * ei;
            } else {
                w->e += ei;
            }
            w->pn -= f_d * g_n;
            w->pw += f_n * vw;
            w->pd += f_d * vw;
            w->fw[2 * a] += f_n;
            if (tang) {
                wall_tangential(s, i, k0, st0, v_o, f_o, g_o, f_n, lo, g_n,
                                !s->wall_cc.clamp || f_n > 0.0, w);
            }
        } else if (tang && s->wall_hist && s->wall_hist[k0] != 0.0) {
            wall_tangential(s, i, k0, st0, v_o, f_o, g_o, 0.0, lo, v[i] - vw, 0, w); /* ended */
        }
        if (hi > 0.0) { /* the wall at L: normal -e_a, g_n = -v */
            double f_d, ei;
            const double f_n = gr_kernel_normal(s, wc, hi, -v[i], &f_d, &ei);
            f[i] -= f_n;
            g[i] -= f_d;
            if (own_walls(s)) {
                w->ej += wc->e_scale * ei;
            } else {
                w->e += ei;
            }
            w->pn += f_d * v[i];
            w->fw[2 * a + 1] += f_n;
            if (tang) {
                wall_tangential(s, i, k0 + 1, -st0, v_o, f_o, g_o, f_n, hi, -v[i],
                                !s->wall_cc.clamp || f_n > 0.0, w);
            }
        } else if (tang && s->wall_hist && s->wall_hist[k0 + 1] != 0.0) {
            wall_tangential(s, i, k0 + 1, -st0, v_o, f_o, g_o, 0.0, hi, -v[i], 0, w);
        }
    }
}

/* A sawtooth wall that dropped (by 2 A) since the last evaluation: the energy of the springs of
 * the grains pressed into it before the drop (the wall 2 A higher) that the drop released, at the
 * grains' present positions, minus what they keep, J; its negative is the wall's work. */
static double dropped_energy(const gr_sim *s, const double *q, double qw)
{
    const double up = qw + 2.0 * s->params.amplitude;
    double before = 0.0, after = 0.0;
    for (int i = 0; i < s->n; i++) {
        double f_d, e;
        const double r = gr_grain_r(s, i); /* species: its own radius and contact */
        gr_contact_coeffs tmp;
        const gr_contact_coeffs *wc = wall_coeffs(s, i, &tmp);
        const double w = own_walls(s) ? wc->e_scale / s->wall_cc.e_scale : 1.0;
        if (r - (q[i] - up) > 0.0) {
            gr_kernel_normal(s, wc, r - (q[i] - up), 0.0, &f_d, &e);
            before += w * e;
        }
        if (r - (q[i] - qw) > 0.0) {
            gr_kernel_normal(s, wc, r - (q[i] - qw), 0.0, &f_d, &e);
            after += w * e;
        }
    }
    return s->wall_cc.e_scale * (before - after);
}

/* 1D with walls: take the ring's closing pair (n-1, 0) back out if the kernel found it touching. */
static void unwrap_ring(gr_sim *s, gr_force_report *r)
{
    const int n = s->n;
    if (n < 2 || !s->pair_contact[n - 1]) {
        return;
    }
    /* species: the pair's own distance and coefficients, as the kernel took them (a distribution:
     * the reference's scaled to the pair) */
    gr_contact_coeffs tmp = s->cc;
    if (s->rad && !s->cc_pair) {
        const double mi = s->mass_i[n - 1], mj = s->mass_i[0], d = s->rad[n - 1] + s->rad[0];
        gr_size_scaled(&s->cc, s->cont_m12, s->cont_r, mi * mj / (mi + mj),
                       s->rad[n - 1] * s->rad[0] / d, &tmp);
    }
    const gr_contact_coeffs *c =
        s->cc_pair ? &s->cc_pair[s->species[n - 1] * s->nsp + s->species[0]] : &tmp;
    const double ov = gr_pair_d(s, n - 1, 0) - (s->x[0] + s->L - s->x[n - 1]),
                 g_n = s->vx[0] - s->vx[n - 1];
    double f_d, e;
    const double f_n = gr_kernel_normal(s, c, ov, g_n, &f_d, &e);
    s->fx[n - 1] += f_n;
    s->fx[0] -= f_n;
    s->gx[n - 1] += f_d;
    s->gx[0] -= f_d;
    r->elastic -= c->e_scale * e;
    r->power_normal += f_d * g_n;
    r->new_contacts -= 1; /* the flag is cleared below every time, so the kernel counted it new */
    s->pair_contact[n - 1] = 0;
}

/* 3D (spheres): the tangential law at the contact of grain i with the wall (a, side) of normal
 * n = +-e_a (into the box), as the pair kernel's (kernels_3d.c) with the wall as the partner i,
 * resting and not rotating, at the arm r: g_c = v - (v.n) n + r n x w; a law without history acts
 * along g_c with its scalar code at |g_c|, a history law keeps its vector in the wall's plane (slot
 * 3 (2 a + side) of the grain's 18 in s->wall_hist); the force F_t acts on the grain, its torque
 * -r n x F_t on the grain only. acts = 0 for a contact that ended. */
static void wall_tangential_3d(gr_sim *s, const int i, const int a, const int side,
                               const double f_n, const double xi, const double g_n, const int acts,
                               wall_sums *w)
{
    const double r = gr_grain_r(s, i); /* species: its own radius and contact */
    const gr_contact_coeffs *wc = s->wall_cc_sp ? &s->wall_cc_sp[s->species[i]] : &s->wall_cc;
    double *const v[3] = {s->vx, s->vy, s->vz}, *const f[3] = {s->fx, s->fy, s->fz},
                  *const g[3] = {s->gx, s->gy, s->gz};
    double n[3] = {0.0, 0.0, 0.0};
    n[a] = side ? -1.0 : 1.0;
    double gc[3];
    for (int c = 0; c < 3; c++) {
        gc[c] = c == a ? 0.0 : v[c][i];
    }
    if (s->omega) {
        const double W[3] = {s->wx[i], s->wy[i], s->omega[i]};
        const double nw[3] = {n[1] * W[2] - n[2] * W[1], n[2] * W[0] - n[0] * W[2],
                              n[0] * W[1] - n[1] * W[0]};
        for (int c = 0; c < 3; c++) {
            gc[c] += r * nw[c];
        }
    }
    double Ft[3], Fn[3], p;
    int book;
    if (s->wall_hist) {
        double *slot = s->wall_hist + 18 * (size_t)i + 3 * (size_t)(2 * a + side);
        const gr_tangential_in3 in = {.g = {gc[0], gc[1], gc[2]},
                                      .f_n = f_n,
                                      .xi = xi,
                                      .g_n = g_n,
                                      .acts = acts,
                                      .hist = slot};
        const gr_tangential_force3 ft = gr_kernel_tangential3(s->wall_tl, wc, in, &book);
        for (int c = 0; c < 3; c++) {
            Ft[c] = ft.f[c];
            Fn[c] = ft.f[c] - ft.fc[c];
        }
        p = -(Fn[0] * gc[0] + Fn[1] * gc[1] + Fn[2] * gc[2]);
        w->et += ft.e;
        w->lost += ft.lost;
    } else {
        const double gm = sqrt(gc[0] * gc[0] + gc[1] * gc[1] + gc[2] * gc[2]);
        const gr_tangential_in in = {.g_t = gm,
                                     .f_n = f_n,
                                     .xi = xi,
                                     .g_n = g_n,
                                     .acts = acts,
                                     .m12_dt = wc->m_t / s->dt,
                                     .hist = NULL};
        int hist;
        const gr_tangential_force ft = gr_kernel_tangential(s->wall_tl, wc, in, &book, &hist);
        const double along = gm > 0.0 ? ft.f / gm : 0.0;
        for (int c = 0; c < 3; c++) {
            Ft[c] = Fn[c] = along * gc[c];
        }
        p = ft.p;
    }
    if (book == GR_BOOK_TANGENTIAL) {
        w->pt += p;
    } else {
        w->pf += p;
    }
    if (!acts) {
        return;
    }
    for (int c = 0; c < 3; c++) {
        f[c][i] += Ft[c];
        g[c][i] += Fn[c];
    }
    if (s->omega) {
        double *const tq[3] = {s->tqx, s->tqy, s->tq}, *const tg[3] = {s->tgx, s->tgy, s->tg};
        for (int c = 0, c1 = 1, c2 = 2; c < 3; c++, c1 = (c1 + 1) % 3, c2 = (c2 + 1) % 3) {
            /* -r (n x F)_c */
            tq[c][i] -= r * (n[c1] * Ft[c2] - n[c2] * Ft[c1]);
            if (s->tg) {
                tg[c][i] -= r * (n[c1] * Fn[c2] - n[c2] * Fn[c1]);
            }
        }
    }
}

/* 3D: grain i against the two walls of axis a, the wall at 0 at qw moving with vw; the same
 * arithmetic as axis_wall_grain's normal part, the tangential law by wall_tangential_3d. */
static void wall_grain_3d(gr_sim *s, const int a, const int i, const double qw, const double vw,
                          const int tang, wall_sums *w, gr_force_report *r_out)
{
    const double r = gr_grain_r(s, i), L = s->L; /* species: its own radius and contact */
    const gr_contact_coeffs *wc = s->wall_cc_sp ? &s->wall_cc_sp[s->species[i]] : &s->wall_cc;
    double *const q[3] = {s->x, s->y, s->z}, *const v[3] = {s->vx, s->vy, s->vz},
                  *const f[3] = {s->fx, s->fy, s->fz}, *const g[3] = {s->gx, s->gy, s->gz};
    const double lo = r - (q[a][i] - qw), hi = q[a][i] + r - L;
    const double deepest = (lo > hi ? lo : hi) / r; /* the runaway guard, as axis_wall_grain */
    if (deepest > 0.5 && deepest > r_out->max_overlap) {
        r_out->max_overlap = deepest;
        r_out->worst_i = i;
        r_out->worst_j = -1;
    }
    for (int side = 0; side < 2; side++) {
        const double xi = side ? hi : lo, sign = side ? -1.0 : 1.0;
        const double g_n = side ? -v[a][i] : v[a][i] - vw; /* along n = sign e_a */
        const double *slot = s->wall_hist ? s->wall_hist + 18 * (size_t)i + 6 * a + 3 * side : 0;
        if (xi > 0.0) {
            double f_d, ei;
            const double f_n = gr_kernel_normal(s, wc, xi, g_n, &f_d, &ei);
            f[a][i] += sign * f_n;
            g[a][i] += sign * f_d;
            if (s->wall_cc_sp) {
                w->ej += wc->e_scale * ei;
            } else {
                w->e += ei;
            }
            w->pn -= f_d * g_n;
            if (!side) {
                w->pw += f_n * vw;
                w->pd += f_d * vw;
            }
            w->fw[2 * a + side] += f_n;
            if (tang) {
                wall_tangential_3d(s, i, a, side, f_n, xi, g_n, !s->wall_cc.clamp || f_n > 0.0, w);
            }
        } else if (tang && slot && (slot[0] != 0.0 || slot[1] != 0.0 || slot[2] != 0.0)) {
            wall_tangential_3d(s, i, a, side, 0.0, xi, g_n, 0, w); /* ended: the law forgets */
        }
    }
}

/* 3D: every grain against the walls of axis a (those touching or holding a wall spring). */
static void axis_walls_3d(gr_sim *s, const int a, const double qw, const double vw, wall_sums *w,
                          gr_force_report *r_out)
{
    const double L = s->L;
    const double *q = a == 0 ? s->x : a == 1 ? s->y : s->z;
    const int tang = s->wall_tl != 0;
    /* as in 2D (axis_walls): a branch-free scan of a block, then the grains that touch a wall or
     * hold a wall spring, in order */
    uint8_t touch[WALL_BLOCK];
    int idx[WALL_BLOCK];
    for (int i0 = 0; i0 < s->n; i0 += WALL_BLOCK) {
        const int m = i0 + WALL_BLOCK < s->n ? WALL_BLOCK : s->n - i0;
        wall_touch_flags(s, q, i0, m, 0.5 * s->d, qw, L, touch);
        for (int k = 0; s->wall_hist && k < m; k++) {
            const double *h = s->wall_hist + 18 * (size_t)(i0 + k) + 6 * a;
            touch[k] |= (h[0] != 0.0) | (h[1] != 0.0) | (h[2] != 0.0) | (h[3] != 0.0) |
                        (h[4] != 0.0) | (h[5] != 0.0);
        }
        const int nt = touching(touch, m, i0, idx);
        for (int t = 0; t < nt; t++) {
            wall_grain_3d(s, a, idx[t], qw, vw, tang, w, r_out);
        }
    }
}

void gr_walls_forces(gr_sim *s, gr_force_report *r)
{
    const gr_sim_params *p = &s->params;
    wall_sums w = {0};
    /* a vibrating wall at 0 of axis vibrate - 1, at the time of this evaluation (the positions'
     * time, step dt) */
    double qw[3] = {0.0, 0.0, 0.0}, vw[3] = {0.0, 0.0, 0.0};
    double *const pos[3] = {s->x, s->y, s->z};
    double released = 0.0;
    if (p->vibrate) {
        const int a = p->vibrate - 1;
        const double t = gr_sim_time(s);
        gr_walls_motion(p, t, &qw[a], &vw[a]);
        if (p->motion == GR_WALL_SAWTOOTH && s->step > 0 &&
            floor(p->frequency * t + 0.5) != floor(p->frequency * (t - s->dt) + 0.5)) {
            released = dropped_energy(s, pos[a], qw[a]);
        }
    }
    if (s->dim == 3) {
        if (s->omega && s->wall_tl && !s->kernel.rot) {
            /* the pair kernel without rotation (the particles' laws do nothing) leaves the
             * torques alone: the walls' are the only ones */
            const size_t bytes = sizeof(double) * (size_t)s->n;
            memset(s->tqx, 0, bytes);
            memset(s->tqy, 0, bytes);
            memset(s->tq, 0, bytes);
        }
        for (int a = 0; a < 3; a++) {
            if (p->walls[a]) {
                axis_walls_3d(s, a, qw[a], vw[a], &w, r);
            }
        }
    } else if (p->walls[0]) {
        if (s->dim == 1) {
            unwrap_ring(s, r);
        }
        axis_walls(s, 0, s->x, s->vx, s->fx, s->gx, s->dim == 2 ? s->vy : NULL, s->fy, s->gy, qw[0],
                   vw[0], &w, r);
    }
    if (s->dim == 2 && p->walls[1]) {
        axis_walls(s, 1, s->y, s->vy, s->fy, s->gy, s->vx, s->fx, s->gx, qw[1], vw[1], &w, r);
    }
    r->elastic += s->wall_cc.e_scale * w.e;
    if (own_walls(s)) {
        r->elastic += w.ej; /* species, a distribution: each grain's own springs */
    }
    r->power_normal += w.pn;
    if (s->wall_tl) {
        r->elastic += w.et;
        r->power_tangential += w.pt;
        r->power_friction += w.pf;
        r->lost += w.lost;
    }
    /* the moving wall's work: these forces kick the grains for one step (two half kicks), so its
     * work is its power times dt (gr_ledger.wall_work); the step books the work of g, -f_d v, as
     * dissipation, of which f_d vw is the wall's, not lost: given back here, so dissipated is
     * -f_d (v - vw) */
    if (p->vibrate) {
        s->wall_work += w.pw * s->dt - released;
        s->diss_n += w.pd * s->dt;
    }
    for (int k = 0; k < 2 * s->dim; k++) {
        s->wall_impulse[k] += w.fw[k] * s->dt;
    }
    /* gravity: conservative, so into f only (its work is the change of the potential energy) */
    for (int a = 0; a < s->dim; a++) {
        const double ga = p->gravity[a], mg = s->mass * ga;
        double *restrict f = a == 0 ? s->fx : a == 1 ? s->fy : s->fz;
        const double *restrict m_i = s->mass_i;
        const int n = s->n;
        if (mg == 0.0) {
            continue;
        }
        if (m_i) {
            for (int i = 0; i < n; i++) {
                f[i] += m_i[i] * ga; /* species: its own weight */
            }
        } else {
            for (int i = 0; i < n; i++) { /* vectorises: the loop's bounds are constants */
                f[i] += mg;
            }
        }
    }
}

void gr_sim_wall_impulse(const gr_sim *s, double J[6])
{
    for (int k = 0; k < 6; k++) {
        J[k] = s->wall_impulse[k];
    }
}

double gr_walls_potential(const gr_sim *s)
{
    double u = 0.0;
    for (int a = 0; a < s->dim; a++) {
        const double ga = s->params.gravity[a];
        const double *q = a == 0 ? s->x : a == 1 ? s->y : s->z;
        double sum = 0.0;
        for (int i = 0; ga != 0.0 && i < s->n; i++) {
            sum += s->mass_i ? s->mass_i[i] / s->mass * q[i] : q[i]; /* species: own masses */
        }
        u -= s->mass * ga * sum;
    }
    return u;
}
