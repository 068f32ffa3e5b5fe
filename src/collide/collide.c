/* One binary collision time-stepped by the engine itself (the same kernels as a full run), for
 * `granule collide` and the collision test suite (sec. 2.1.5, Table 2.1, Fig. 2.5).
 *
 * The particles are moved along their free flight to just before contact, (1 + phase) steps
 * ahead of it, so the contact starts at a chosen point inside a time step; averaging over phases
 * removes the discretisation's phase noise from the measured energy loss. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/sim_internal.h"
#include "models/list.h"
#include "granule/collide.h"
#include "granule/integrator.h"
#include "granule/sim.h"

int gr_collision_case_table21(int number, double radius, gr_collision_case *out, gr_error *err)
{
    /* Table 2.1: (x1, v1, x2, v2); particle 2 starts at rest */
    double r = radius;
    switch (number) {
    case 1: *out = (gr_collision_case){{0, 0}, {1, 0}, {1, 0}, {0, 0}}; break;
    case 2: *out = (gr_collision_case){{0, 0}, {1, 1}, {1, 1}, {0, 0}}; break;
    case 3: *out = (gr_collision_case){{0, 0}, {0, 1}, {r, 1}, {0, 0}}; break;
    case 4: *out = (gr_collision_case){{0, 0}, {1 + r, 1}, {1, 1}, {0, 0}}; break;
    default: return GR_FAIL(err, GR_EINVAL, "--case %d: Table 2.1 has collisions 1 to 4", number);
    }
    return GR_OK;
}

int gr_collision_case_oblique(double speed, double angle_deg, double radius, gr_collision_case *out,
                              gr_error *err)
{
    if (!(speed > 0.0) || !isfinite(speed)) {
        return GR_FAIL(err, GR_EINVAL, "--speed %g: the impact speed must be > 0 and finite (m/s)",
                       speed);
    }
    if (!(angle_deg >= 0.0 && angle_deg < 90.0)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "--angle %g: the impact angle must lie in [0, 90) degrees (90: the discs only graze)",
            angle_deg);
    }
    if (!(radius > 0.0) || !isfinite(radius)) {
        return GR_FAIL(err, GR_EINVAL, "--radius %g: must be > 0 (m)", radius);
    }
    /* at first touch x1 = 0, x2 = (d, 0): n = (1, 0); -g = v1 makes the angle a with n. Start
     * r/2 back along v1 (the pair is then at least d apart: |x2 - x1|^2 = d^2 + d r cos a + r^2/4) */
    const double a = angle_deg * M_PI / 180.0, c = cos(a), sn = sin(a);
    *out = (gr_collision_case){{-0.5 * radius * c, -0.5 * radius * sn},
                               {speed * c, speed * sn},
                               {2.0 * radius, 0.0},
                               {0.0, 0.0}};
    return GR_OK;
}

void gr_collide_setup_default(gr_collide_setup *s)
{
    memset(s, 0, sizeof *s);
    s->normal = gr_model_find("spring_dashpot");
    gr_contact_defaults(&s->contact); /* every model's defaults (hertz: k_h, v_max, ...) */
    s->contact.k_s = 5e5;
    s->contact.eps_n = 0.6;
    s->contact.eps_t = 0.6;
    s->contact.mu = 0.5;
    s->contact.clamp = false;
    s->mass = 1.0;
    s->radius = 0.1; /* Table 2.1 gives no radius; with 1 kg masses and k_s = 5e5 the overlap is
                        v / w0 = 1 mm, so r = 0.1 m keeps it below 1% of d */
    s->steps_per_contact = 50.0;
    s->dim = 2;
    s->ref_rtol = 1e-12;
}

/* Time at which |r + g t| first equals d (r, g relative position and velocity), or -1. */
static double contact_time_of(const double r[2], const double g[2], double d)
{
    double b = r[0] * g[0] + r[1] * g[1], gg = g[0] * g[0] + g[1] * g[1];
    double c = r[0] * r[0] + r[1] * r[1] - d * d;
    double disc = b * b - gg * c;
    if (c <= 0.0) {
        return 0.0;
    }
    if (b >= 0.0 || disc < 0.0 || gg == 0.0) {
        return -1.0;
    }
    return c / (-b + sqrt(disc)); /* cancellation-free root (physics notes sec. 3.3) */
}

/* An event rule (hard_sphere, ...): the model's instantaneous rule (gr_event_rule_apply, models/list.h)
 * applied at the exact contact instant */
static int collide_hard(const gr_collide_setup *cs, const gr_collision_case *cc, double t_hit,
                        gr_collide_result *out, gr_error *err)
{
    const int dim = cs->dim;
    gr_contact_params p = cs->contact;
    if (dim == 1) {
        p.eps_t = 1.0;
    }
    gr_contact_coeffs coeffs;
    int rc = gr_contact_prepare(cs->normal, NULL, &p, 0.5 * cs->mass, 0.0, &coeffs, err);
    if (rc) {
        return rc;
    }
    double v1[2] = {cc->v1[0], dim == 2 ? cc->v1[1] : 0.0},
           v2[2] = {cc->v2[0], dim == 2 ? cc->v2[1] : 0.0};
    double r[2] = {cc->x2[0] - cc->x1[0] + (v2[0] - v1[0]) * t_hit,
                   dim == 2 ? cc->x2[1] - cc->x1[1] + (v2[1] - v1[1]) * t_hit : 0.0};
    double rn = hypot(r[0], r[1]), n[2] = {r[0] / rn, r[1] / rn};
    double g0[2] = {v2[0] - v1[0], v2[1] - v1[1]};
    double gg0 = g0[0] * g0[0] + g0[1] * g0[1];
    double gn0 = g0[0] * n[0] + g0[1] * n[1], gt0 = g0[0] * n[1] - g0[1] * n[0];
    double p0[2] = {v1[0] + v2[0], v1[1] + v2[1]};
    /* rough discs (rotation = true, 2D): the rule with both discs at rest before; the spin energy
     * counts in the loss and the contact point's velocity in eps_t (models/hard_sphere.h) */
    double w1 = 0.0, w2 = 0.0, spin_t = 0.0, spin_e = 0.0;
    gr_event_pair pair = {.M = cs->mass,
                          .R = cs->radius,
                          .q = p.inertia_factor,
                          .nx = n[0],
                          .ny = n[1],
                          .v1x = v1[0],
                          .v1y = v1[1],
                          .v2x = v2[0],
                          .v2y = v2[1]};
    if (p.rotation && dim == 2) {
        pair.w1 = &w1;
        pair.w2 = &w2;
    }
    gr_event_rule_apply(gr_event_rule_of(coeffs.normal_model), &coeffs, &pair);
    const double u1[2] = {pair.v1x, pair.v1y}, u2[2] = {pair.v2x, pair.v2y};
    if (pair.w1) {
        out->omega1 = w1;
        out->omega2 = w2;
        /* the rule's g = v1 - v2 and t = n rotated by +90 degrees are both reversed here (g = v2 - v1,
         * t = n rotated by -90 degrees), so g.t is the same and the surface term +r (w1 + w2);
         * the spin energy I (w1^2 + w2^2) / 2 in units of m12 / 2 (the |g|^2 of energy_loss) */
        spin_t = cs->radius * (w1 + w2);
        spin_e = 2.0 * p.inertia_factor * cs->radius * cs->radius * (w1 * w1 + w2 * w2);
    }
    double g1[2] = {u2[0] - u1[0], u2[1] - u1[1]};
    out->energy_loss = 1.0 - (g1[0] * g1[0] + g1[1] * g1[1] + spin_e) / gg0;
    out->impact_angle = acos(fmin(1.0, fabs(gn0) / sqrt(gg0))) * 180.0 / M_PI;
    out->expected_loss = gr_contact_expected_loss(&coeffs, sqrt(gg0), out->impact_angle);
    out->contact_time = 0.0;
    out->max_overlap = 0.0;
    out->eps_n_measured = -(g1[0] * n[0] + g1[1] * n[1]) / gn0;
    out->eps_t_measured =
        fabs(gt0) > 1e-12 * sqrt(gg0) ? (g1[0] * n[1] - g1[1] * n[0] + spin_t) / gt0 : (double)NAN;
    out->momentum_error = hypot(u1[0] + u2[0] - p0[0], u1[1] + u2[1] - p0[1]) / hypot(p0[0], p0[1]);
    out->normal_impulse = cs->mass * fabs((u1[0] - v1[0]) * n[0] + (u1[1] - v1[1]) * n[1]);
    out->tangential_impulse = cs->mass * fabs((u1[0] - v1[0]) * n[1] - (u1[1] - v1[1]) * n[0]);
    out->tangential_reversed = gt0 * (g1[0] * n[1] - g1[1] * n[0]) < 0.0;
    out->dt = 0.0;
    for (int k = 0; k < 2; k++) {
        out->v1[k] = u1[k];
        out->v2[k] = u2[k];
    }
    return GR_OK;
}

/* A collision the engine resolved, or GR_EINVAL naming why its numbers would mean nothing: the
 * discs passed through each other (tunnelled: a step carried them past the overlap the force can
 * stop, so after "the contact" they are on the wrong sides and still approach), or the line of
 * centres turned so far during a grazing contact that the normal velocity after it is mostly the
 * tangential one projected on the turned normal: its share of eps_n_measured, |g_t / g_n| sin(theta)
 * for a turn by theta, exceeds GR_COLLIDE_MAX_TURN_ERROR. */
static int check_contact(const gr_collide_setup *cs, const gr_sim *s, double L, const double n0[3],
                         const double n_end[3], double gn0, double gt0, const double g1[3],
                         const gr_collide_result *out, gr_error *err)
{
    double dx = s->x[1] - s->x[0], dy = cs->dim >= 2 ? s->y[1] - s->y[0] : 0.0,
           dz = cs->dim == 3 ? s->z[1] - s->z[0] : 0.0;
    dx -= L * rint(dx / L);
    dy -= L * rint(dy / L);
    dz -= L * rint(dz / L);
    const double speed = hypot(gn0, gt0), d = 2.0 * cs->radius;
    if (dx * n0[0] + dy * n0[1] + dz * n0[2] < 0.0 ||
        g1[0] * n_end[0] + g1[1] * n_end[1] + g1[2] * n_end[2] < 0.0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the discs passed through each other (tunnelled) instead of colliding: at %g m/s "
            "they move %g m per step of dt = %g s against d = %g m, and the contact force stopped "
            "them "
            "only %.3g m into the overlap; no collision happened to measure: use a smaller --dt "
            "(or "
            "--steps-per-contact larger), a stiffer --k or a lower speed",
            speed, speed * s->dt, s->dt, d, out->max_overlap);
    }
    const double cx = n0[1] * n_end[2] - n0[2] * n_end[1], cy = n0[2] * n_end[0] - n0[0] * n_end[2],
                 cz = n0[0] * n_end[1] - n0[1] * n_end[0];
    const double turn = cs->dim == 3 ? sqrt(cx * cx + cy * cy + cz * cz) : fabs(cz); /* sin */
    const double share = fabs(gt0 / gn0) * turn;
    if (share > GR_COLLIDE_MAX_TURN_ERROR) {
        return GR_FAIL(
            err, GR_EINVAL,
            "a grazing impact (%.6g degrees): the line of centres turned by %.3g degrees "
            "while the discs touched, which moves eps_n_measured by up to |g_t / g_n| sin(turn) = "
            "%.3g, more "
            "than %g; the normal restitution of this contact cannot be measured: use a smaller "
            "--angle or "
            "speed",
            out->impact_angle, asin(fmin(1.0, turn)) * 180.0 / M_PI, share,
            GR_COLLIDE_MAX_TURN_ERROR);
    }
    return GR_OK;
}

/* The two particles' run: a box large enough that they meet only once, no driving, velocity
 * Verlet, the core's plain parameters (granule/sim.h), no scene; and the contact's coefficients
 * (its time step first: it sets how far before contact to start). r0: x2 - x1 at the start. */
static int pair_params(const gr_collide_setup *cs, const double r0[2], gr_sim_params *sc,
                       gr_contact_coeffs *coeffs, gr_error *err)
{
    const int dim = cs->dim;
    const double d = 2.0 * cs->radius;
    *sc = (gr_sim_params){.dim = dim,
                          .N = 2,
                          .radius = cs->radius,
                          .mass = cs->mass,
                          .normal = cs->normal,
                          .tangential = dim >= 2 ? cs->tangential : NULL,
                          .rolling = dim >= 2 ? cs->rolling : NULL,
                          .contact = cs->contact,
                          .D = 0.0,
                          .noise_mode = GR_NOISE_NONE,
                          .integrator = gr_integrator_find("verlet"),
                          .dt = cs->dt,
                          .steps_per_contact =
                              cs->steps_per_contact > 0.0 ? cs->steps_per_contact : 50.0,
                          .force_dt = cs->force_dt,
                          .skin = 0.3,
                          .seed = 1};
    snprintf(sc->source, sizeof sc->source,
             "options"); /* messages read "collide: options: [..] key ..." */
    sc->L = fmax(64.0 * d, 8.0 * (fabs(r0[0]) + fabs(r0[1]) + d));
    int rc = gr_contact_prepare(sc->normal, sc->tangential, &sc->contact, 0.5 * sc->mass, 0.0,
                                coeffs, err);
    return rc ? rc
              : gr_contact_prepare_rolling(sc->rolling, &sc->contact, 0.5 * sc->mass, 0.0, coeffs,
                                           err);
}

/* GR_EINVAL (s freed) when dt resolves the contact in more steps than a collision may take. */
static int too_fine(gr_sim *s, double t_c, gr_error *err)
{
    if (t_c / s->dt <= GR_COLLIDE_MAX_STEPS_PER_CONTACT) {
        return GR_OK;
    }
    const double dt = s->dt;
    gr_sim_free(s);
    return GR_FAIL(err, GR_EINVAL,
                   "dt = %g s resolves the contact time t_c = %g s in %.3g steps, more than the %g "
                   "a collision may take; use dt >= t_c / %g = %g s (--dt)",
                   dt, t_c, t_c / dt, GR_COLLIDE_MAX_STEPS_PER_CONTACT,
                   GR_COLLIDE_MAX_STEPS_PER_CONTACT, t_c / GR_COLLIDE_MAX_STEPS_PER_CONTACT);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The contact point's tangential relative velocity of spheres at unit normal n (from 1 to 2):
 * g - (g.n) n + a n x (w1 + w2), a the lever arm (src/core/kernels_3d.c). */
static void contact_velocity(const double g[3], const double n[3], const double w1[3],
                             const double w2[3], double a, double gc[3])
{
    const double gn = dot3(g, n), W[3] = {w1[0] + w2[0], w1[1] + w2[1], w1[2] + w2[2]};
    const double nw[3] = {n[1] * W[2] - n[2] * W[1], n[2] * W[0] - n[0] * W[2],
                          n[0] * W[1] - n[1] * W[0]};
    for (int k = 0; k < 3; k++) {
        gc[k] = g[k] - gn * n[k] + a * nw[k];
    }
}

/* An event rule on spheres (dim = 3): the rule on 3-vectors (gr_event_rule_3d of models/list.h, the event core's)
 * at the exact contact instant, the centres in the plane z = 0; with rotation = true (rough
 * spheres) the spins are the setup's vectors w1, w2, which enter the contact point's velocity. */
static int collide_hard_3d(const gr_collide_setup *cs, const gr_collision_case *cc, double t_hit,
                           bool spun, gr_collide_result *out, gr_error *err)
{
    gr_contact_params p = cs->contact;
    if (spun && !p.rotation) {
        return GR_FAIL(err, GR_EINVAL,
                       "--omega1/--omega2: initial spins need rotation = true (rough spheres: "
                       "--set rotation=true --set beta=B; allowed without: 0,0,0)");
    }
    if (cs->rolling) {
        return GR_FAIL(err, GR_EINVAL, "%s: the rule has no rolling law (allowed: rolling = none)",
                       cs->normal->name);
    }
    gr_contact_coeffs coeffs;
    int rc = gr_contact_prepare(cs->normal, NULL, &p, 0.5 * cs->mass, 0.0, &coeffs, err);
    if (rc) {
        return rc;
    }
    const double M = cs->mass, R = cs->radius, I = p.inertia_factor * M * R * R;
    const double v1[3] = {cc->v1[0], cc->v1[1], 0.0}, v2[3] = {cc->v2[0], cc->v2[1], 0.0};
    const double r[3] = {cc->x2[0] - cc->x1[0] + (v2[0] - v1[0]) * t_hit,
                         cc->x2[1] - cc->x1[1] + (v2[1] - v1[1]) * t_hit, 0.0};
    const double rn = sqrt(dot3(r, r)), n[3] = {r[0] / rn, r[1] / rn, 0.0};
    const double g0[3] = {v2[0] - v1[0], v2[1] - v1[1], 0.0}, zero[3] = {0.0, 0.0, 0.0};
    const double gg0 = dot3(g0, g0), gn0 = dot3(g0, n);
    double u1[3], u2[3], w1[3], w2[3], gc0[3], gc1[3], de_n, de_t;
    for (int a = 0; a < 3; a++) {
        u1[a] = v1[a];
        u2[a] = v2[a];
        w1[a] = p.rotation ? cs->w1[a] : 0.0;
        w2[a] = p.rotation ? cs->w2[a] : 0.0;
    }
    contact_velocity(g0, n, w1, w2, R, gc0);
    const double spin_e0 = I * (dot3(w1, w1) + dot3(w2, w2)) / (0.5 * M);
    gr_event_rule_3d(gr_event_rule_of(coeffs.normal_model), &coeffs, M, R, p.inertia_factor, n, u1,
                     u2, p.rotation ? w1 : NULL, p.rotation ? w2 : NULL, false, &de_n, &de_t);
    const double g1[3] = {u2[0] - u1[0], u2[1] - u1[1], u2[2] - u1[2]};
    contact_velocity(g1, n, p.rotation ? w1 : zero, p.rotation ? w2 : zero, R, gc1);
    const double spin_e = I * (dot3(w1, w1) + dot3(w2, w2)) / (0.5 * M);
    out->energy_loss = 1.0 - (dot3(g1, g1) + spin_e) / (gg0 + spin_e0);
    out->spin_loss = (spin_e0 - spin_e) / (gg0 + spin_e0);
    out->impact_angle = acos(fmin(1.0, fabs(gn0) / sqrt(gg0))) * 180.0 / M_PI;
    out->expected_loss =
        spun ? (double)NAN : gr_contact_expected_loss(&coeffs, sqrt(gg0), out->impact_angle);
    out->eps_n_measured = -dot3(g1, n) / gn0;
    const double gc0m2 = dot3(gc0, gc0);
    out->eps_t_measured = gc0m2 > 1e-24 * gg0 ? dot3(gc1, gc0) / gc0m2 : (double)NAN;
    double dv[3], dp[3];
    const double p0[3] = {M * (v1[0] + v2[0]), M * (v1[1] + v2[1]), 0.0};
    for (int a = 0; a < 3; a++) {
        dv[a] = u1[a] - v1[a];
        dp[a] = M * (u1[a] + u2[a]) - p0[a];
        out->v1[a] = u1[a];
        out->v2[a] = u2[a];
        out->w1[a] = w1[a];
        out->w2[a] = w2[a];
    }
    const double jn = dot3(dv, n),
                 jt[3] = {dv[0] - jn * n[0], dv[1] - jn * n[1], dv[2] - jn * n[2]};
    out->momentum_error = sqrt(dot3(dp, dp)) / sqrt(dot3(p0, p0));
    out->normal_impulse = M * fabs(jn);
    out->tangential_impulse = M * sqrt(dot3(jt, jt));
    out->tangential_reversed = dot3(gc0, gc1) < 0.0;
    out->omega1 = w1[2];
    out->omega2 = w2[2];
    return GR_OK;
}

/* Spheres (dim = 3): the case's positions and velocities in the plane z = 0 (the centres at
 * z = L/2), the spins the setup's vectors w1, w2; everything else as the 2D run below. */
static int collide_run_3d(const gr_collide_setup *cs, const gr_collision_case *cc,
                          gr_collide_result *out, gr_error *err)
{
    const double d = 2.0 * cs->radius;
    double r0[2] = {cc->x2[0] - cc->x1[0], cc->x2[1] - cc->x1[1]};
    double g0[3] = {cc->v2[0] - cc->v1[0], cc->v2[1] - cc->v1[1], 0.0};
    const double t_hit = contact_time_of(r0, g0, d);
    if (t_hit < 0.0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the two particles never touch: their relative motion misses by more than d = %g m", d);
    }
    bool spun = false;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(cs->w1[k]) || !isfinite(cs->w2[k])) {
            return GR_FAIL(err, GR_EINVAL,
                           "--omega1 %g,%g,%g, --omega2 %g,%g,%g: the initial angular velocities "
                           "must be finite (rad/s)",
                           cs->w1[0], cs->w1[1], cs->w1[2], cs->w2[0], cs->w2[1], cs->w2[2]);
        }
        spun = spun || cs->w1[k] != 0.0 || cs->w2[k] != 0.0;
    }
    if (cs->normal && (cs->normal->kind & GR_MODEL_EVENT)) {
        return collide_hard_3d(cs, cc, t_hit, spun, out, err);
    }
    gr_sim_params sc;
    gr_contact_coeffs coeffs;
    int rc = pair_params(cs, r0, &sc, &coeffs, err);
    if (rc) {
        return rc;
    }
    const double t_c = isfinite(coeffs.t_c) ? coeffs.t_c : M_PI / coeffs.w0;
    const double dt_guess = sc.dt > 0.0 ? sc.dt : t_c / sc.steps_per_contact;
    const double t0 = t_hit - fmin(t_hit, (1.0 + cs->phase) * dt_guess);
    double x[2], y[2], z[2] = {0.5 * sc.L, 0.5 * sc.L}, vx[2], vy[2], vz[2] = {0.0, 0.0};
    const double *xs[2] = {cc->x1, cc->x2}, *vs[2] = {cc->v1, cc->v2};
    for (int p = 0; p < 2; p++) {
        x[p] = 0.5 * sc.L + xs[p][0] + vs[p][0] * t0 - 0.5 * r0[0];
        y[p] = 0.5 * sc.L + xs[p][1] + vs[p][1] * t0 - 0.5 * r0[1];
        vx[p] = vs[p][0];
        vy[p] = vs[p][1];
    }
    const double *const rr[3] = {x, y, z}, *const vv[3] = {vx, vy, vz};
    gr_sim *s;
    rc = gr_sim_new_with_state_3d(&sc, 2, rr, vv, &s, err);
    if (rc) {
        return rc;
    }
    out->dt = s->dt;
    if (spun && !s->omega) {
        gr_sim_free(s);
        return GR_FAIL(err, GR_EINVAL,
                       "--omega1/--omega2: initial spins need rotation: [model] rotation = true "
                       "with a tangential law at the contact point (tangential_dashpot, "
                       "sliding_friction, tangential_spring; allowed without: 0,0,0)");
    }
    double *w[2][3] = {{NULL}};
    double spin_e0 = 0.0;
    if (s->omega) {
        double *wc[3] = {s->wx, s->wy, s->omega};
        for (int k = 0; k < 3; k++) {
            w[0][k] = &wc[k][0];
            w[1][k] = &wc[k][1];
            wc[k][0] = cs->w1[k];
            wc[k][1] = cs->w2[k];
        }
        spin_e0 = s->inertia * (dot3(cs->w1, cs->w1) + dot3(cs->w2, cs->w2)) / (0.5 * cs->mass);
    }
    const double rh[3] = {r0[0] + g0[0] * t_hit, r0[1] + g0[1] * t_hit, 0.0};
    const double nh = sqrt(dot3(rh, rh));
    const double n0[3] = {rh[0] / nh, rh[1] / nh, 0.0};
    const double gg0 = dot3(g0, g0), gn0 = dot3(g0, n0);
    double gc0[3];
    contact_velocity(g0, n0, s->omega ? cs->w1 : (const double[3]){0},
                     s->omega ? cs->w2 : (const double[3]){0}, cs->radius, gc0);
    const double gc0m = sqrt(dot3(gc0, gc0));
    const double gt0 = sqrt(fmax(gg0 - gn0 * gn0, 0.0)); /* |g_t| of the centres, for the checks */
    const double p_before[3] = {cs->mass * (cc->v1[0] + cc->v2[0]),
                                cs->mass * (cc->v1[1] + cc->v2[1]), 0.0};
    out->impact_angle = acos(fmin(1.0, fabs(gn0) / sqrt(gg0))) * 180.0 / M_PI;
    if ((rc = too_fine(s, t_c, err))) {
        return rc;
    }
    bool touched = false;
    double n_end[3] = {n0[0], n0[1], n0[2]}, jn = 0.0, jt = 0.0;
    int64_t active = 0;
    const int64_t max_steps = (int64_t)(2000.0 * t_c / s->dt) + 1000;
    int64_t k = 0;
    for (; k < max_steps; k++) {
        if ((rc = gr_sim_step(s, 1, err))) {
            gr_sim_free(s);
            return rc;
        }
        double r[3] = {s->x[1] - s->x[0], s->y[1] - s->y[0], s->z[1] - s->z[0]};
        for (int a = 0; a < 3; a++) {
            r[a] -= sc.L * rint(r[a] / sc.L);
        }
        const double dist = sqrt(dot3(r, r));
        const double g[3] = {s->vx[1] - s->vx[0], s->vy[1] - s->vy[0], s->vz[1] - s->vz[0]};
        const double F[3] = {s->fx[1], s->fy[1], s->fz[1]}; /* the force on particle 2 */
        const bool force_free = F[0] == 0.0 && F[1] == 0.0 && F[2] == 0.0;
        if (dist < d && touched && force_free && dot3(g, r) > 0.0 && s->cc.clamp) {
            break; /* clamped: the force vanished while the pair separates (as in 2D) */
        }
        if (dist < d) {
            touched = true;
            out->max_overlap = fmax(out->max_overlap, d - dist);
            const double n[3] = {r[0] / dist, r[1] / dist, r[2] / dist};
            if (!force_free) {
                active++;
                memcpy(n_end, n, sizeof n_end);
            }
            const double fn = dot3(F, n);
            const double ft[3] = {F[0] - fn * n[0], F[1] - fn * n[1], F[2] - fn * n[2]};
            jn += fabs(fn) * s->dt;
            jt += sqrt(dot3(ft, ft)) * s->dt;
            double gc[3];
            const double wa[3] = {s->omega ? *w[0][0] : 0.0, s->omega ? *w[0][1] : 0.0,
                                  s->omega ? *w[0][2] : 0.0},
                         wb[3] = {s->omega ? *w[1][0] : 0.0, s->omega ? *w[1][1] : 0.0,
                                  s->omega ? *w[1][2] : 0.0};
            contact_velocity(g, n, wa, wb, cs->radius, gc);
            if (dot3(gc0, gc) < -1e-12 * gg0) {
                out->tangential_reversed = true;
            }
        } else if (touched) {
            break;
        }
    }
    if (k == max_steps) {
        gr_sim_free(s);
        return GR_FAIL(err, GR_EINVAL,
                       touched ? "the contact did not end within %lld steps (2000 contact times): "
                                 "the pair sticks (eps_n = %g)"
                               : "the spheres never came into contact within %lld steps (eps_n = "
                                 "%g): there is no collision to measure; use a smaller --angle",
                       (long long)max_steps, sc.contact.eps_n);
    }
    const double g1[3] = {s->vx[1] - s->vx[0], s->vy[1] - s->vy[0], s->vz[1] - s->vz[0]};
    rc = check_contact(cs, s, sc.L, n0, n_end, gn0, gt0, g1, out, err);
    if (rc) {
        gr_sim_free(s);
        return rc;
    }
    double spin_e = 0.0, gc1[3];
    for (int a = 0; a < 3; a++) {
        out->w1[a] = s->omega ? *w[0][a] : 0.0;
        out->w2[a] = s->omega ? *w[1][a] : 0.0;
    }
    if (s->omega) {
        out->omega1 = out->w1[2];
        out->omega2 = out->w2[2];
        spin_e = s->inertia * (dot3(out->w1, out->w1) + dot3(out->w2, out->w2)) / (0.5 * cs->mass);
    }
    contact_velocity(g1, n_end, out->w1, out->w2, cs->radius, gc1);
    out->energy_loss = 1.0 - (dot3(g1, g1) + spin_e) / (gg0 + spin_e0);
    out->spin_loss = (spin_e0 - spin_e) / (gg0 + spin_e0);
    out->expected_loss =
        spun ? (double)NAN : gr_contact_expected_loss(&s->cc, sqrt(gg0), out->impact_angle);
    out->contact_time = (double)active * s->dt;
    out->eps_n_measured = -dot3(g1, n_end) / gn0;
    /* along the direction g_c had, carried into the tangent plane at the end (as 2D's t') */
    double u[3] = {gc0[0], gc0[1], gc0[2]};
    const double un = dot3(u, n_end);
    for (int a = 0; a < 3; a++) {
        u[a] -= un * n_end[a];
    }
    const double um = sqrt(dot3(u, u));
    out->eps_t_measured =
        gc0m > 1e-12 * sqrt(gg0) && um > 0.0 ? dot3(gc1, u) / (um * gc0m) : (double)NAN;
    const double *v[3] = {s->vx, s->vy, s->vz};
    double dp[3];
    for (int a = 0; a < 3; a++) {
        out->v1[a] = v[a][0];
        out->v2[a] = v[a][1];
        dp[a] = cs->mass * (v[a][0] + v[a][1]) - p_before[a];
    }
    out->momentum_error = sqrt(dot3(dp, dp)) / sqrt(dot3(p_before, p_before));
    out->normal_impulse = jn;
    out->tangential_impulse = jt;
    gr_sim_free(s);
    return GR_OK;
}

int gr_collide_run(const gr_collide_setup *cs, const gr_collision_case *cc, gr_collide_result *out,
                   gr_error *err)
{
    memset(out, 0, sizeof *out);
    if (cs->dim == 3) {
        return collide_run_3d(cs, cc, out, err);
    }
    const int dim = cs->dim;
    const double d = 2.0 * cs->radius;
    double r0[2] = {cc->x2[0] - cc->x1[0], dim == 2 ? cc->x2[1] - cc->x1[1] : 0.0};
    double g0[2] = {cc->v2[0] - cc->v1[0], dim == 2 ? cc->v2[1] - cc->v1[1] : 0.0};
    double t_hit = contact_time_of(r0, g0, d);
    if (t_hit < 0.0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the two particles never touch: their relative motion misses by more than d = %g m", d);
    }
    const bool spun = cs->omega1 != 0.0 || cs->omega2 != 0.0;
    if (!isfinite(cs->omega1) || !isfinite(cs->omega2)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "--omega1 %g, --omega2 %g: the initial angular velocities must be finite (rad/s)",
            cs->omega1, cs->omega2);
    }
    if (cs->normal && (cs->normal->kind & GR_MODEL_EVENT)) {
        if (spun) {
            return GR_FAIL(err, GR_EINVAL,
                           "--omega1/--omega2: %s's rule starts the discs without spin; initial "
                           "spins need a soft normal law (allowed with %s: 0)",
                           cs->normal->name, cs->normal->name);
        }
        if (cs->rolling) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: the rule has no rolling law (allowed: rolling = none)",
                           cs->normal->name);
        }
        return collide_hard(cs, cc, t_hit, out, err);
    }
    gr_sim_params sc;
    gr_contact_coeffs coeffs;
    int rc = pair_params(cs, r0, &sc, &coeffs, err);
    if (rc) {
        return rc;
    }
    double t_c = isfinite(coeffs.t_c) ? coeffs.t_c : M_PI / coeffs.w0;
    double dt_guess = sc.dt > 0.0 ? sc.dt : t_c / sc.steps_per_contact;
    /* place the pair (1 + phase) steps before contact, centred in the box */
    double lead = fmin(t_hit, (1.0 + cs->phase) * dt_guess);
    double t0 = t_hit - lead;
    double x[2], y[2], vx[2], vy[2];
    const double *xs[2] = {cc->x1, cc->x2}, *vs[2] = {cc->v1, cc->v2};
    for (int p = 0; p < 2; p++) {
        x[p] = 0.5 * sc.L + xs[p][0] + vs[p][0] * t0 - 0.5 * r0[0];
        y[p] = 0.5 * sc.L + (dim == 2 ? xs[p][1] + vs[p][1] * t0 - 0.5 * r0[1] : 0.0);
        vx[p] = vs[p][0];
        vy[p] = dim == 2 ? vs[p][1] : 0.0;
    }
    gr_sim *s;
    rc = gr_sim_new_with_state(&sc, 2, x, y, vx, vy, &s, err);
    if (rc) {
        return rc;
    }
    out->dt = s->dt;
    if (spun && !s->omega) {
        gr_sim_free(s);
        return GR_FAIL(
            err, GR_EINVAL,
            "--omega1/--omega2: initial spins need rotation: [model] rotation = true with a "
            "tangential law at the contact point (tangential_dashpot, sliding_friction; allowed "
            "without: 0)");
    }
    /* initial spins: free flight does not change them, so they hold at the start too */
    double spin_t0 = 0.0, spin_e0 = 0.0;
    if (s->omega) {
        s->omega[0] = cs->omega1;
        s->omega[1] = cs->omega2;
        spin_t0 = cs->radius * (cs->omega1 + cs->omega2);
        spin_e0 =
            s->inertia * (cs->omega1 * cs->omega1 + cs->omega2 * cs->omega2) / (0.5 * cs->mass);
    }
    /* the normal at impact, from the exact free flight */
    double rh[2] = {r0[0] + g0[0] * t_hit, r0[1] + g0[1] * t_hit};
    double nh = hypot(rh[0], rh[1]);
    double n0[3] = {rh[0] / nh, rh[1] / nh, 0.0}, t0v[2] = {n0[1], -n0[0]};
    double gg0 = g0[0] * g0[0] + g0[1] * g0[1];
    double gn0 = g0[0] * n0[0] + g0[1] * n0[1], gt0 = g0[0] * t0v[0] + g0[1] * t0v[1];
    double p_before[2] = {cs->mass * (cc->v1[0] + cc->v2[0]),
                          cs->mass * (dim == 2 ? cc->v1[1] + cc->v2[1] : 0.0)};
    out->impact_angle = acos(fmin(1.0, fabs(gn0) / sqrt(gg0))) * 180.0 / M_PI;

    bool touched = false;
    double n_end[3] = {n0[0], n0[1], 0.0};
    double jn = 0.0, jt = 0.0;
    int64_t active = 0;
    if ((rc = too_fine(s, t_c, err))) {
        return rc;
    }
    const int64_t max_steps = (int64_t)(2000.0 * t_c / s->dt) + 1000;
    for (int64_t k = 0; k < max_steps; k++) {
        rc = gr_sim_step(s, 1, err);
        if (rc) {
            gr_sim_free(s);
            return rc;
        }
        double dx = s->x[1] - s->x[0], dy = dim == 2 ? s->y[1] - s->y[0] : 0.0;
        dx -= sc.L * rint(dx / sc.L);
        dy -= sc.L * rint(dy / sc.L);
        double dist = hypot(dx, dy);
        double gx = s->vx[1] - s->vx[0], gy = dim == 2 ? s->vy[1] - s->vy[0] : 0.0;
        bool force_free = s->fx[1] == 0.0 && (dim == 1 || s->fy[1] == 0.0);
        if (dist < d && touched && force_free && (gx * dx + gy * dy) > 0.0 && s->cc.clamp) {
            /* clamped law: the force has vanished while the pair separates; from here the motion
             * is force-free, so the outgoing velocities are final (Schwager & Poeschel 2007) */
            break;
        }
        if (dist < d) {
            touched = true;
            out->max_overlap = fmax(out->max_overlap, d - dist);
            double nx = dx / dist, ny = dy / dist;
            double Fx = s->fx[1], Fy = dim == 2 ? s->fy[1] : 0.0; /* force on particle 2 */
            if (Fx != 0.0 || Fy != 0.0) {
                active++;
                n_end[0] = nx;
                n_end[1] = ny;
            }
            jn += fabs(Fx * nx + Fy * ny) * s->dt; /* int |F_n| dt: the bound of friction */
            jt += fabs(Fx * ny - Fy * nx) * s->dt;
            double g_t =
                gx * ny - gy * nx + (s->omega ? cs->radius * (s->omega[0] + s->omega[1]) : 0.0);
            if ((gt0 + spin_t0) * g_t < -1e-12 * sqrt(gg0)) {
                out->tangential_reversed = true;
            }
        } else if (touched) {
            break;
        }
        if (k == max_steps - 1 && !touched) {
            gr_sim_free(s);
            return GR_FAIL(
                err, GR_EINVAL,
                "the discs never came into contact within %lld steps of dt = %g s (their "
                "closest approach, %.3g degrees from grazing, stays outside d = %g m once "
                "rounded): there "
                "is no collision to measure; use a smaller --angle",
                (long long)max_steps, out->dt, 90.0 - out->impact_angle, d);
        }
        if (k == max_steps - 1) {
            const gr_contact_coeffs *c = &s->cc;
            bool critical = !c->clamp && c->zeta >= 1.0;
            char why[200];
            snprintf(why, sizeof why,
                     critical ? "eps_n = %g unclamped is critically damped (zeta = %.3g): the "
                                "overlap decays without returning to zero"
                              : "numerically (eps_n = %g, zeta = %.3g): the time step is too "
                                "coarse for this dashpot",
                     sc.contact.eps_n, c->zeta);
            gr_sim_free(s);
            return GR_FAIL(err, GR_EINVAL,
                           "the contact did not end within %lld steps (2000 contact times): the "
                           "pair sticks %s",
                           (long long)max_steps, why);
        }
    }
    double g1[3] = {s->vx[1] - s->vx[0], dim == 2 ? s->vy[1] - s->vy[0] : 0.0, 0.0};
    double t_end[2] = {n_end[1], -n_end[0]};
    rc = check_contact(cs, s, sc.L, n0, n_end, gn0, gt0, g1, out, err);
    if (rc) {
        gr_sim_free(s);
        return rc;
    }
    /* rotation: the surface velocities at the contact point (models/law.h) and the spin energy
     * in units of m12 (I w^2 / 2 over m12 / 2) */
    double spin_t = 0.0, spin_e = 0.0;
    if (s->omega) {
        out->omega1 = s->omega[0];
        out->omega2 = s->omega[1];
        spin_t = cs->radius * (s->omega[0] + s->omega[1]);
        spin_e =
            s->inertia * (s->omega[0] * s->omega[0] + s->omega[1] * s->omega[1]) / (0.5 * cs->mass);
    }
    out->energy_loss = 1.0 - (g1[0] * g1[0] + g1[1] * g1[1] + spin_e) / (gg0 + spin_e0);
    out->spin_loss = (spin_e0 - spin_e) / (gg0 + spin_e0);
    /* the models' restitution laws assume discs without spin before the impact */
    out->expected_loss =
        spun ? (double)NAN : gr_contact_expected_loss(&s->cc, sqrt(gg0), out->impact_angle);
    out->contact_time = (double)active * s->dt;
    out->eps_n_measured = -(g1[0] * n_end[0] + g1[1] * n_end[1]) / gn0;
    const double gc0 = gt0 + spin_t0; /* the contact point's tangential velocity before */
    out->eps_t_measured = fabs(gc0) > 1e-12 * sqrt(gg0)
                              ? (g1[0] * t_end[0] + g1[1] * t_end[1] + spin_t) / gc0
                              : (double)NAN;
    out->v1[0] = s->vx[0];
    out->v1[1] = dim == 2 ? s->vy[0] : 0.0;
    out->v2[0] = s->vx[1];
    out->v2[1] = dim == 2 ? s->vy[1] : 0.0;
    double p_after[2];
    gr_sim_momentum(s, p_after);
    out->momentum_error =
        hypot(p_after[0] - p_before[0], p_after[1] - p_before[1]) / hypot(p_before[0], p_before[1]);
    out->normal_impulse = fabs(jn);
    out->tangential_impulse = fabs(jt);
    gr_sim_free(s);
    return GR_OK;
}
