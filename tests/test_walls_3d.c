/* Tests of flat walls, gravity and the vibrating floor for spheres ([system] dim = 3 with
 * [boundary] x, y, z and [gravity] gx, gy, gz; src/core/walls.c, docs/systems-walls-gravity.md),
 * the 3D counterparts of test_walls.c:
 *
 * - a sphere dropped onto a floor: apex heights fall by eps_n^2 per bounce to the step's order,
 *   spring_dashpot and hertz, the floor at z = 0 and (gravity along x) at x = 0;
 * - eps_n = 1 on a static floor: kinetic + potential + elastic energy conserved to second order;
 * - the ledger closes with walls, gravity and the random force, with a sinusoidal and a sawtooth
 *   floor (the wall's work), and with every tangential law and rotation at the walls; restarts
 *   are exact (the walls' history vectors are part of the state), and 1 and 2 threads agree;
 * - no pair through a wall: spheres pressed into the floor and the ceiling move as each alone; a
 *   floor vibrating below 0 carries spheres below 0 without wrapping them to the ceiling;
 * - tangential laws at a wall: an oblique bounce keeps its direction along the floor and leaves
 *   with the wall's eps_t; a sphere spinning about a tilted axis ends rolling (v = r n x w ... with
 *   the pair's fixed-partner values) and keeps its spin about the normal (no twisting law);
 * - a bed at rest weighs N M g on its floor (the impulse of the wall at z = 0);
 * - event-driven smooth hard spheres: a sphere bouncing on a floor loses exactly eps_n^2 of its
 *   energy per bounce, the ledger closing to rounding; elastic spheres in a box walled all round
 *   under gravity conserve kinetic + potential energy, stay within the walls and restart exactly;
 * - refusals: z and gz outside 3D, gravity along a periodic axis (the event integrator's
 *   vibrating wall and rough spheres: test_event_vibrate.c). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "integrators/event/event.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

/* One sphere, the floor at z = 0 (gravity along z); the scene's placement is replaced by a state
 * set by hand (grain_at), dropped from 2 r above the floor. */
static const char *grain_3d =
    "[system]\ndim = 3\nN = 1\nL = 0.04\n[placement]\nkind = cubic\nv0 = 0\n"
    "[driving]\nkind = none\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n";
/* the same with the floor at x = 0 (gravity along x, y and z periodic) */
static const char *grain_3d_x =
    "[system]\ndim = 3\nN = 1\nL = 0.04\n[placement]\nkind = cubic\nv0 = 0\n"
    "[driving]\nkind = none\n[boundary]\nx = walls\n[gravity]\ngx = -9.81\n";

/* A sphere at the centre of the box with velocity v and spin w (NULL: none). */
static gr_sim *grain_at(const gr_scene *sc, const double v[3], const double w[3])
{
    gr_sim_params p;
    gr_scene_sim_params(sc, &p);
    const double c = 0.5 * sc->L, x = c, y = c, z = c, vx = v[0], vy = v[1], vz = v[2];
    const double *const r[3] = {&x, &y, &z}, *const u[3] = {&vx, &vy, &vz};
    gr_error err = {0};
    gr_sim *s = NULL;
    ck_assert_msg(gr_sim_new_with_state_3d(&p, 1, r, u, &s, &err) == GR_OK, "%s", err.message);
    if (w) {
        s->wx[0] = w[0];
        s->wy[0] = w[1];
        s->omega[0] = w[2];
        s->initial_energy += 0.5 * s->inertia * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    return s;
}

/* The coordinate and velocity along gravity's axis a. */
static double coord(const gr_sim *s, int a)
{
    return a == 0 ? s->x[0] : a == 1 ? s->y[0] : s->z[0];
}
static double veloc(const gr_sim *s, int a)
{
    return a == 0 ? s->vx[0] : a == 1 ? s->vy[0] : s->vz[0];
}

/* The first `want` apex heights above the touching point (h[0] the drop height), read off the
 * step where the velocity along the axis turns negative (y + v^2 / 2g is exact in free flight). */
static int apexes(gr_sim *s, int a, int want, double *h, int64_t max_steps)
{
    const double r = 0.5 * s->d, g = 9.81;
    h[0] = coord(s, a) - r;
    int k = 1;
    double v_prev = veloc(s, a);
    for (int64_t n = 0; n < max_steps && k <= want; n++) {
        step(s, 1);
        const double v = veloc(s, a);
        if (v_prev > 0.0 && v <= 0.0 && s->elastic == 0.0) {
            h[k++] = coord(s, a) + v * v / (2.0 * g) - r;
        }
        v_prev = v;
    }
    return k - 1;
}

/* Largest |h_k / h_(k-1) / eps^2 - 1| over 5 bounces (3 in the sanitizer pass). */
static double bounce_error(const char *text, int a, const char *const *set, int n_set, double eps)
{
    gr_scene sc;
    load(&sc, text, set, n_set);
    const double zero[3] = {0.0, 0.0, 0.0};
    gr_sim *s = grain_at(&sc, zero, NULL);
    double h[6];
    const int bounces = quick() ? 3 : 5;
    const int found = apexes(s, a, bounces, h, 4000000);
    ck_assert_msg(found == bounces, "%d apexes found", found);
    double worst = 0.0;
    for (int k = 1; k <= bounces; k++) {
        const double dev = fabs(h[k] / h[k - 1] / (eps * eps) - 1.0);
        worst = dev > worst ? dev : worst;
    }
    /* nothing moved off the axis */
    ck_assert(coord(s, (a + 1) % 3) == 0.5 * sc.L && coord(s, (a + 2) % 3) == 0.5 * sc.L);
    gr_sim_free(s);
    return worst;
}

/* The bounds of test_walls.c's bounce_case: below 0.06 (1 - eps_n) at 50 and 100 steps per
 * contact, and (the linear law at 0.9, where the step's error dominates) at least 1.6x smaller
 * at 100 (measured 1.9x). eps 0.9 and 0.8 are far apart in eps^2: the pair's reduced mass M/2
 * instead of the wall's M would fail by far. The linear law with k_s = 5e4 N/m (a 3x longer
 * step than the default's; its g t_c / v term stays below the step's error). */
static void bounce_case(const char *text, int a, const char *normal, double eps, bool converge)
{
    char e[64], n[64];
    snprintf(e, sizeof e, "model.eps_n=%g", eps);
    snprintf(n, sizeof n, "model.normal=%s", normal);
    const char *at50[] = {n, e, "integrator.steps_per_contact=50", "model.k_s=5e4"};
    const char *at100[] = {n, e, "integrator.steps_per_contact=100", "model.k_s=5e4"};
    const double d50 = bounce_error(text, a, at50, 4, eps);
    /* the sanitizer pass: the bound at 50 steps per contact only */
    const double d100 = quick() ? d50 / 2.0 : bounce_error(text, a, at100, 4, eps);
    printf("3D bounce (floor at %c = 0) %s eps_n = %g: max |h_k/h_(k-1)/eps^2 - 1| = %.2e (50 "
           "steps/contact), %.2e (100)\n",
           "xyz"[a], normal, eps, d50, d100);
    ck_assert_msg(d50 < 0.06 * (1.0 - eps), "%s eps %g: %g", normal, eps, d50);
    ck_assert_msg(d100 < 0.06 * (1.0 - eps), "%s eps %g: %g", normal, eps, d100);
    ck_assert_msg(!converge || d100 < d50 / 1.6, "%s eps %g: %g then %g", normal, eps, d50, d100);
}

/* The floor at x = 0 (gravity along x) gives the z floor's bounce bit for bit, components
 * renamed: every axis runs the same wall code (to the way up after the first bounce). */
static void same_on_x(void)
{
    gr_scene sz, sx;
    const char *set[] = {"model.k_s=5e4", "model.eps_n=0.9"};
    load(&sz, grain_3d, set, 2);
    load(&sx, grain_3d_x, set, 2);
    const double zero[3] = {0.0, 0.0, 0.0};
    gr_sim *z = grain_at(&sz, zero, NULL), *x = grain_at(&sx, zero, NULL);
    const int64_t n = (int64_t)(0.1 / gr_sim_dt(z));
    step(z, n);
    step(x, n);
    ck_assert(z->vz[0] > 0.0 && z->vz[0] < 0.6); /* bounced */
    ck_assert_double_eq(z->z[0], x->x[0]);
    ck_assert_double_eq(z->vz[0], x->vx[0]);
    ck_assert(x->y[0] == 0.5 * sx.L && x->z[0] == 0.5 * sx.L && x->vy[0] == 0.0);
    gr_sim_free(z);
    gr_sim_free(x);
}

START_TEST(bounce_apex_3d)
{
    bounce_case(grain_3d, 2, "spring_dashpot", 0.9, true);
    if (!quick()) {
        bounce_case(grain_3d, 2, "hertz", 0.8, false);
        same_on_x();
        /* the walls' own restitution: [boundary] eps_n = 0.9 against spheres of 0.5 (whose own
         * would give ratios 0.25) */
        const char *own[] = {"model.eps_n=0.5", "boundary.eps_n=0.9", "model.k_s=5e4",
                             "integrator.steps_per_contact=50"};
        const double d = bounce_error(grain_3d, 2, own, 4, 0.9);
        printf("3D bounce, the walls' eps_n 0.9 (spheres' 0.5): max deviation %.2e\n", d);
        ck_assert_msg(d < 0.06 * (1.0 - 0.9), "walls' eps_n: %g", d);
    }
}
END_TEST

/* The largest |E(t) - E(0)| / E(0) over `steps` (E = kinetic + elastic + potential). */
static double energy_drift(const char *set_spc, int64_t steps)
{
    /* the sanitizer pass: a softer spring (10x the step) */
    const char *set[] = {"model.eps_n=1", set_spc, "model.k_s=5e3"};
    gr_scene sc;
    load(&sc, grain_3d, set, quick() ? 3 : 2);
    const double zero[3] = {0.0, 0.0, 0.0};
    gr_sim *s = grain_at(&sc, zero, NULL);
    const gr_ledger l0 = gr_sim_ledger(s);
    const double e0 = l0.kinetic + l0.elastic + l0.potential;
    ck_assert(e0 > 0.0 && l0.potential == e0);
    double worst = 0.0;
    for (int64_t n = 0; n < steps; n += 10) {
        step(s, 10);
        const gr_ledger l = gr_sim_ledger(s);
        worst = fmax(worst, fabs(l.kinetic + l.elastic + l.potential - e0) / e0);
        ck_assert_double_eq(l.dissipated_normal, 0.0);
    }
    gr_sim_free(s);
    return worst;
}

/* eps_n = 1: the energy stays to the Verlet error of the contact (second order), within 1e-3 at
 * 50 steps per contact and about 4x smaller at 100; two bounces */
START_TEST(elastic_energy_3d)
{
    gr_scene sc;
    const char *set[] = {"model.eps_n=1", "integrator.steps_per_contact=50", "model.k_s=5e3"};
    load(&sc, grain_3d, set, quick() ? 3 : 2);
    gr_sim *probe = create(&sc);
    const int64_t steps = (int64_t)(0.4 / gr_sim_dt(probe));
    gr_sim_free(probe);
    const double d50 = energy_drift("integrator.steps_per_contact=50", steps);
    const double d100 = energy_drift("integrator.steps_per_contact=100", 2 * steps);
    printf("3D elastic bounce: max |dE|/E = %.3e (50 steps/contact), %.3e (100)\n", d50, d100);
    ck_assert_msg(d50 < 1e-3 && d50 > 0.0, "drift %g", d50);
    ck_assert_msg(d100 < 0.35 * d50, "not second order: %g then %g", d50, d100);
}
END_TEST

/* A bed of spheres: walls at z = 0 and L, gravity, inelastic, the random force. */
static const char *bed_3d =
    "[system]\ndim = 3\nN = 300\nL = 0.03\n[placement]\nkind = random\nv0 = 0.2\n"
    "[model]\neps_n = 0.7\n[noise]\nD = 1e-8\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n";
/* The floor vibrating at A = 1 mm, f = 50 Hz (10 g), no noise: the wall's work is the only input. */
static const char *vibrated_3d =
    "[system]\ndim = 3\nN = 100\nL = 0.03\n[placement]\nkind = random\nv0 = 0.1\n"
    "[model]\neps_n = 0.8\n[noise]\nmode = none\n[boundary]\nz = walls\nvibrate = z\n"
    "amplitude = 1e-3\nfrequency = 50\n[gravity]\ngz = -9.81\n";

/* The ledger after `steps`: injected + wall_work - dissipated = change of kinetic + elastic +
 * potential (+ rotational), to tol of the energy moved. */
static void ledger_closes(const char *text, const char *const *set, int n_set, int64_t steps,
                          double tol)
{
    gr_scene sc;
    const char *all[8] = {"model.k_s=5e3"}; /* the sanitizer pass: a softer spring, 10x the step */
    for (int k = 0; k < n_set && k < 7; k++) {
        all[k + 1] = set[k];
    }
    load(&sc, text, quick() ? all : set, quick() ? n_set + 1 : n_set);
    gr_sim *s = create(&sc);
    step(s, steps);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + fabs(l.wall_work) + gr_ledger_dissipated(&l);
    const double res = gr_ledger_residual(&l);
    printf("3D ledger (%s%s%s): injected %.4g J, wall_work %.4g J, dissipated %.4g J (tangential "
           "%.3g, friction %.3g), potential %.4g J, residual %.3g of the energy moved\n",
           sc.vibrate ? (sc.motion ? "sawtooth floor" : "vibrated floor") : "bed",
           sc.tangential ? ", " : "", sc.tangential ? sc.tangential->name : "", l.injected,
           l.wall_work, gr_ledger_dissipated(&l), l.dissipated_tangential, l.dissipated_friction,
           l.potential, res / moved);
    ck_assert(l.dissipated_normal > 0.0 && l.potential != 0.0);
    if (sc.vibrate) {
        ck_assert_msg(l.wall_work > 0.0 && l.injected == 0.0, "wall_work %g", l.wall_work);
    } else {
        ck_assert_msg(l.injected > 0.0 && l.wall_work == 0.0, "injected %g", l.injected);
    }
    if (sc.tangential) {
        ck_assert(l.dissipated_tangential + l.dissipated_friction > 0.0);
    }
    ck_assert_msg(fabs(res) < tol * moved, "residual %g of %g moved", res, moved);
    gr_sim_free(s);
}

START_TEST(ledger_walls_3d)
{
    ledger_closes(bed_3d, NULL, 0, quick() ? 2000 : 20000, 1e-3);
    ledger_closes(vibrated_3d, NULL, 0, quick() ? 4000 : 60000, 1e-3);
    if (!quick()) {
        const char *saw[] = {"boundary.motion=sawtooth"};
        ledger_closes(vibrated_3d, saw, 1, 60000, 1e-3);
    }
    gr_scene sc;
    load(&sc, bed_3d, NULL, 0);
    assert_restart_exact(&sc, 600, 350);
    load(&sc, vibrated_3d, NULL, 0);
    assert_restart_exact(&sc, 600, 350);
}
END_TEST

/* A floor vibrating 3 mm (2 r) below 0 at 20 Hz carries spheres below z = 0: they are not wrapped
 * to the ceiling (positions along a wall axis are never wrapped, the cells clamp them), nothing
 * overlaps through the image, and the ledger closes. */
START_TEST(floor_below_zero_3d)
{
    const char *set[] = {"boundary.amplitude=3e-3", "boundary.frequency=20", "model.k_s=5e3"};
    gr_scene sc;
    load(&sc, vibrated_3d, set, 3);
    gr_sim *s = create(&sc);
    const int64_t chunk = llround(1e-3 / s->dt);
    double lowest = INFINITY, highest = -INFINITY;
    for (int k = 0; k < (quick() ? 60 : 150); k++) { /* 60 ms reach the floor's lowest point */
        step(s, chunk);
        for (int i = 0; i < s->n; i++) {
            lowest = fmin(lowest, s->z[i]);
            highest = fmax(highest, s->z[i]);
        }
    }
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = fabs(l.wall_work) + gr_ledger_dissipated(&l);
    printf("3D floor below 0: lowest centre %.4g r, highest %.6g m (L - r = %.6g m); residual %.3g "
           "of the energy moved\n",
           lowest / sc.radius, highest, sc.L - sc.radius, gr_ledger_residual(&l) / moved);
    ck_assert_msg(lowest < 0.0, "no sphere went below 0: %g", lowest);
    ck_assert_msg(highest < sc.L, "a sphere at %g m: wrapped to the ceiling", highest);
    ck_assert(fabs(gr_ledger_residual(&l)) < 1e-3 * moved);
    gr_sim_free(s);
}
END_TEST

/* Every tangential law at the walls with rotation (the walls' own mu and eps_t): the ledger closes
 * and restarts are exact (the spring's history vectors per grain and wall are saved). */
START_TEST(tangential_walls_3d)
{
    static const char *const laws[] = {"tangential_dashpot", "sliding_friction",
                                       "tangential_spring"};
    for (int k = quick() ? 2 : 0; k < 3; k++) {
        char t[64];
        snprintf(t, sizeof t, "model.tangential=%s", laws[k]);
        const char *set[] = {t, "model.rotation=true", "boundary.mu=0.3", "boundary.eps_t=0.5"};
        ledger_closes(bed_3d, set, 4, quick() ? 2000 : 20000, 1e-3);
        gr_scene s;
        load(&s, bed_3d, set, 4);
        assert_restart_exact(&s, 600, 350);
    }
}
END_TEST

/* The bed of 2500 spheres (three blocks) on 1 and 2 threads: the same run bit for bit. */
START_TEST(threads_invariant_3d)
{
    const char *big[] = {"system.N=2500", "system.L=0.07"};
    gr_scene s;
    load(&s, bed_3d, big, 2);
    assert_threads_invariant(&s, quick() ? 20 : 300);
}
END_TEST

/* Two spheres driven into the floor and the ceiling at the same time move exactly as each alone:
 * the list does not wrap across the z walls (through the image they would overlap). */
START_TEST(no_contact_through_walls_3d)
{
    gr_scene sc;
    load(&sc,
         "[system]\ndim = 3\nN = 2\nL = 0.05\n[boundary]\nz = walls\n[model]\neps_n = 0.8\n"
         "[noise]\nmode = none\n",
         NULL, 0);
    gr_sim_params p;
    gr_scene_sim_params(&sc, &p);
    const double r = sc.radius, L = sc.L;
    const double x[2] = {0.02, 0.02}, y[2] = {0.03, 0.03}, z[2] = {1.05 * r, L - 1.05 * r};
    const double vx[2] = {0.0, 0.0}, vy[2] = {0.0, 0.0}, vz[2] = {-0.5, 0.5};
    const double *const r2[3] = {x, y, z}, *const v2[3] = {vx, vy, vz};
    const double *const r_lo[3] = {x, y, z}, *const v_lo[3] = {vx, vy, vz};
    const double *const r_hi[3] = {x + 1, y + 1, z + 1}, *const v_hi[3] = {vx + 1, vy + 1, vz + 1};
    gr_error err = {0};
    gr_sim *both = NULL, *lo = NULL, *hi = NULL;
    ck_assert_int_eq(gr_sim_new_with_state_3d(&p, 2, r2, v2, &both, &err), GR_OK);
    ck_assert_int_eq(gr_sim_new_with_state_3d(&p, 1, r_lo, v_lo, &lo, &err), GR_OK);
    ck_assert_int_eq(gr_sim_new_with_state_3d(&p, 1, r_hi, v_hi, &hi, &err), GR_OK);
    const int64_t steps = (int64_t)(5.0 * gr_sim_coeffs(both)->t_c / gr_sim_dt(both)) + 200;
    /* the deepest each goes: through the image they would be closer than d */
    double deepest = 0.0;
    for (int64_t k = 0; k < steps; k++) {
        step(both, 1);
        deepest = fmax(deepest, 1.05 * r - both->z[0]);
    }
    step(lo, steps);
    step(hi, steps);
    printf("3D walls: each sphere %.3g r into its wall; image distance would be %.3g d\n",
           deepest / r, (2.0 * (r - deepest)) / (2.0 * r));
    ck_assert(both->vz[0] > 0.0 && both->vz[1] < 0.0);
    ck_assert(2.0 * (1.05 * r - deepest) < 2.0 * r); /* the image pair would overlap */
    ck_assert_double_eq(both->z[0], lo->z[0]);
    ck_assert_double_eq(both->vz[0], lo->vz[0]);
    ck_assert_double_eq(both->z[1], hi->z[0]);
    ck_assert_double_eq(both->vz[1], hi->vz[0]);
    ck_assert_int_eq(gr_sim_collisions(both), 0);
    gr_sim_free(both);
    gr_sim_free(lo);
    gr_sim_free(hi);
}
END_TEST

/* A sphere thrown obliquely at the floor along (3, 4, 0) / 5, no rotation, tangential_dashpot
 * with the wall's eps_t = 0.7 (the particles' 0.2): its velocity along the floor leaves scaled by
 * 0.7 in both components (the direction kept), to the law's discretisation error. */
START_TEST(oblique_wall_eps_t_3d)
{
    const char *set[] = {"model.tangential=tangential_dashpot", "model.eps_t=0.2",
                         "boundary.eps_t=0.7", "model.eps_n=0.9"};
    gr_scene sc;
    load(&sc, grain_3d, set, 4);
    const double v0[3] = {0.18, 0.24, 0.0};
    gr_sim *s = grain_at(&sc, v0, NULL);
    double v_prev = s->vz[0];
    for (int64_t n = 0; !(v_prev < 0.0 && s->vz[0] >= 0.0) && n < 4000000; n++) {
        v_prev = s->vz[0];
        step(s, 1);
    }
    while (s->elastic > 0.0) {
        step(s, 1);
    }
    const double rx = s->vx[0] / v0[0], ry = s->vy[0] / v0[1];
    const gr_ledger l = gr_sim_ledger(s);
    const double res = gr_ledger_residual(&l) / gr_ledger_dissipated(&l);
    printf("3D oblique bounce: v_x, v_y after / before = %.5f, %.5f (wall eps_t 0.7); residual "
           "%.3g of the dissipation\n",
           rx, ry, res);
    ck_assert_msg(fabs(rx - 0.7) < 0.06 * (1.0 - 0.7), "ratio %g", rx);
    ck_assert_msg(fabs(rx - ry) < 1e-12, "direction turned: %g %g", rx, ry);
    ck_assert(l.dissipated_tangential > 0.0 && fabs(res) < 1e-3);
    gr_sim_free(s);
}
END_TEST

/* A sphere spinning at w0 = (120, -160, 50) rad/s dropped on the floor (rotation, sliding_friction,
 * the walls' mu = 0.5, the particles' 0): friction stops the contact point's slip in the first
 * bounce and the sphere leaves rolling, as a pair with one partner fixed: the spin in the floor's
 * plane becomes w0 q / (1 + q) and v = -r n x w (v_x = r w_y, v_y = -r w_x), q = 2/5; the spin
 * about the normal (w_z) is untouched (a floor's friction exerts no torque about n); the ledger
 * closes. */
START_TEST(spinning_sphere_rolls)
{
    const char *set[] = {"model.tangential=sliding_friction", "model.rotation=true", "model.mu=0",
                         "boundary.mu=0.5", "model.eps_n=0.9"};
    gr_scene sc;
    load(&sc, grain_3d, set, 5);
    const double zero[3] = {0.0, 0.0, 0.0}, w0[3] = {120.0, -160.0, 50.0};
    gr_sim *s = grain_at(&sc, zero, w0);
    const double r = sc.radius, q = sc.contact.inertia_factor, f = q / (1.0 + q);
    step(s, (int64_t)(0.12 / gr_sim_dt(s))); /* the first bounce ends at about 0.06 s */
    const double vx_th = r * w0[1] * f, vy_th = -r * w0[0] * f;
    const gr_ledger l = gr_sim_ledger(s);
    const double res = gr_ledger_residual(&l) / gr_ledger_dissipated(&l);
    printf("3D spinning sphere: v = (%.6g, %.6g) m/s (theory %.6g, %.6g), w = (%.6g, %.6g, %.6g) "
           "rad/s (theory %.6g, %.6g, 50); slip %.3g m/s; residual %.3g of the dissipation\n",
           s->vx[0], s->vy[0], vx_th, vy_th, s->wx[0], s->wy[0], s->omega[0], w0[0] * f, w0[1] * f,
           hypot(s->vx[0] - r * s->wy[0], s->vy[0] + r * s->wx[0]), res);
    ck_assert_msg(fabs(s->vx[0] / vx_th - 1.0) < 1e-3 && fabs(s->vy[0] / vy_th - 1.0) < 1e-3,
                  "v %g %g", s->vx[0], s->vy[0]);
    ck_assert_msg(fabs(s->wx[0] / (w0[0] * f) - 1.0) < 1e-3 &&
                      fabs(s->wy[0] / (w0[1] * f) - 1.0) < 1e-3,
                  "w %g %g", s->wx[0], s->wy[0]);
    ck_assert_double_eq(s->omega[0], w0[2]);
    ck_assert_msg(hypot(s->vx[0] - r * s->wy[0], s->vy[0] + r * s->wx[0]) < 1e-6 * r * 200.0,
                  "still slipping");
    ck_assert(l.dissipated_friction > 0.0 && fabs(res) < 1e-3);
    gr_sim_free(s);
}
END_TEST

/* A bed of 60 spheres settled on its floor (eps_n = 0.3, no noise, a soft spring) weighs N M g
 * on it; the ceiling and the other walls take nothing. */
START_TEST(bed_weighs_on_floor_3d)
{
    const char *bed = "[system]\ndim = 3\nN = 60\nL = 0.02\n[placement]\nkind = random\nv0 = 0\n"
                      "[model]\neps_n = 0.3\nk_s = 5e3\n[driving]\nkind = none\n[boundary]\n"
                      "z = walls\n[gravity]\ngz = -9.81\n";
    gr_scene sc;
    load(&sc, bed, NULL, 0);
    gr_sim *s = create(&sc);
    const double dt = gr_sim_dt(s), weight = 60 * sc.mass * 9.81;
    step(s, (int64_t)(0.3 / dt));
    double j0[6], j1[6];
    gr_sim_wall_impulse(s, j0);
    const int64_t n = (int64_t)(0.05 / dt);
    step(s, n);
    gr_sim_wall_impulse(s, j1);
    const double floor_f = (j1[4] - j0[4]) / (n * dt);
    printf("3D bed at rest: floor %.8g N, N M g = %.8g N (ratio - 1 = %.2e), ceiling %g N s\n",
           floor_f, weight, floor_f / weight - 1.0, j1[5]);
    ck_assert_msg(fabs(floor_f / weight - 1.0) < 1e-3, "floor %g, weight %g", floor_f, weight);
    ck_assert(j1[5] == 0.0 && j1[0] == 0.0 && j1[1] == 0.0 && j1[2] == 0.0 && j1[3] == 0.0);
    gr_sim_free(s);
}
END_TEST

/* The contact sublist (core/sublist.c) on the vibrated bed: the engine turns it on once the list
 * has lasted 100 steps (auto), GRANULE_SUBLIST=on at every build the Verlet step makes, off never;
 * the three runs end in the same state bit for bit (tests/test_sublist.sh compares their files). */
START_TEST(sublist_on_the_bed_3d)
{
    const char *modes[] = {"off", "auto", "on"};
    int64_t rebuilds[3];
    double x[3], v[3];
    for (int m = 0; m < 3; m++) {
        setenv("GRANULE_SUBLIST", modes[m], 1);
        gr_scene sc;
        load(&sc, vibrated_3d, NULL, 0);
        gr_sim *s = create(&sc);
        step(s, quick() ? 10000 : 20000);
        rebuilds[m] = gr_sim_sublist_rebuilds(s);
        x[m] = 0.0;
        v[m] = 0.0;
        for (int i = 0; i < s->n; i++) {
            x[m] += s->x[i] + s->y[i] + s->z[i];
            v[m] += s->vx[i] + s->vy[i] + s->vz[i];
        }
        gr_sim_free(s);
    }
    unsetenv("GRANULE_SUBLIST");
    printf("3D bed, sublist rebuilds: off %lld, auto %lld, on %lld\n", (long long)rebuilds[0],
           (long long)rebuilds[1], (long long)rebuilds[2]);
    ck_assert_int_eq(rebuilds[0], 0);
    ck_assert_int_gt(rebuilds[1], 0);
    ck_assert_int_ge(rebuilds[2], rebuilds[1]);
    for (int m = 1; m < 3; m++) {
        ck_assert(x[m] == x[0] && v[m] == v[0]);
    }
}
END_TEST

/* A sphere thrown at the floor faster than its soft spring can hold is stopped as unstable,
 * naming the grain and the wall. */
START_TEST(runaway_into_wall_3d)
{
    const char *soft[] = {"model.k_s=5e4"};
    gr_scene sc;
    load(&sc, grain_3d, soft, 1);
    const double v[3] = {0.0, 0.0, -60.0};
    gr_sim *s = grain_at(&sc, v, NULL);
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_step(s, 20000, &err), GR_EUNSTABLE);
    ck_assert_msg(strstr(err.message, "particle 0 and a wall"), "%s", err.message);
    gr_sim_free(s);
}
END_TEST

/* Event-driven hard spheres (smooth, constant eps_n = 0.9, no TC) under gravity: a sphere dropped
 * from the centre of a box of side 0.2 m onto the floor at z = 0. The free flight is an exact
 * parabola and each bounce keeps exactly eps_n^2 of the impact energy, so the losses of successive
 * bounces (the jumps of dissipated_normal) fall by eps_n^2 to rounding, and kinetic + potential +
 * dissipated stays the initial energy; the sphere's centre never goes below r. */
START_TEST(event_bounce_3d)
{
    const char *text = "[system]\ndim = 3\nN = 1\nL = 0.2\n[placement]\nkind = cubic\nv0 = 0\n"
                       "[model]\nnormal = hard_sphere\neps_n = 0.9\neps_t = 1\ntc = off\n[noise]\n"
                       "mode = none\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n[integrator]\n"
                       "kind = event\n";
    gr_scene sc;
    load(&sc, text, NULL, 0);
    const double zero[3] = {0.0, 0.0, 0.0};
    gr_sim *s = grain_at(&sc, zero, NULL);
    const gr_ledger l0 = gr_sim_ledger(s);
    double loss[8], last = 0.0, worst_led = 0.0, lowest = INFINITY;
    int k = 0;
    const int64_t chunk = llround(1e-4 / s->dt);   /* bounces are 0.1 s apart */
    for (int64_t m = 0; m < 12000 && k < 8; m++) { /* 1.2 s: about 6 bounces */
        step(s, chunk);
        const gr_ledger l = gr_sim_ledger(s);
        if (l.dissipated_normal > last) {
            loss[k++] = l.dissipated_normal - last;
            last = l.dissipated_normal;
        }
        worst_led =
            fmax(worst_led,
                 fabs(l.kinetic + l.potential + l.dissipated_normal - l0.potential) / l0.potential);
        lowest = fmin(lowest, s->z[0]);
    }
    double worst = 0.0;
    for (int b = 1; b < k; b++) {
        worst = fmax(worst, fabs(loss[b] / loss[b - 1] / (0.9 * 0.9) - 1.0));
    }
    printf("3D event bounce: %d bounces, max |loss_k / loss_(k-1) / eps^2 - 1| = %.2e; ledger %.2e "
           "of the initial energy; lowest centre %.9g r\n",
           k, worst, worst_led, lowest / sc.radius);
    ck_assert_int_ge(k, 5);
    ck_assert_msg(worst < 1e-9, "bounce losses %g", worst);
    ck_assert_msg(worst_led < 1e-12, "ledger %g", worst_led);
    ck_assert(lowest >= sc.radius * (1.0 - 1e-12));
    ck_assert(s->x[0] == 0.5 * sc.L && s->y[0] == 0.5 * sc.L);
    gr_sim_free(s);
}
END_TEST

/* Event-driven elastic hard spheres (eps_n = 1) in a box walled on all sides under gravity along
 * y, with the random force off: kinetic + potential is conserved to rounding, every centre stays in
 * [r, L - r] on each axis, and the run restarts exactly. */
START_TEST(event_box_3d)
{
    const char *text =
        "[system]\ndim = 3\nN = 64\nL = 0.03\n[placement]\nkind = cubic\nv0 = 1\n"
        "[model]\nnormal = hard_sphere\neps_n = 1\neps_t = 1\ntc = off\n[noise]\nmode = none\n"
        "[boundary]\nx = walls\ny = walls\nz = walls\n[gravity]\ngy = -9.81\n[integrator]\n"
        "kind = event\n";
    gr_scene sc;
    load(&sc, text, NULL, 0);
    gr_sim *s = create(&sc);
    const gr_ledger l0 = gr_sim_ledger(s);
    const double e0 = l0.kinetic + l0.potential, r = sc.radius, L = sc.L;
    double worst = 0.0, out = 0.0;
    const int64_t n = quick() ? 20 : 200, chunk = llround(1e-3 / s->dt); /* 1 ms */
    for (int64_t m = 0; m < n; m++) {
        step(s, chunk);
        const gr_ledger l = gr_sim_ledger(s);
        worst = fmax(worst, fabs(l.kinetic + l.potential - e0) / e0);
        const double *q[3] = {s->x, s->y, s->z};
        for (int i = 0; i < s->n; i++) {
            for (int a = 0; a < 3; a++) {
                out = fmax(out, fmax(r - q[a][i], q[a][i] - (L - r)));
            }
        }
    }
    gr_event_counts c;
    gr_event_stats(s, &c);
    printf("3D event box: %lld collisions, %lld wall hits over %.3g s; max |dE|/E = %.2e; "
           "deepest beyond r of a wall %.2e r\n",
           (long long)c.collisions, (long long)c.wall_hits, n * chunk * s->dt, worst, out / r);
    const int64_t least = quick() ? 10 : 100; /* 20 ms in the sanitizer pass */
    ck_assert(c.collisions > least && c.wall_hits > least);
    ck_assert_msg(worst < 1e-12, "energy drift %g", worst);
    ck_assert_msg(out < 1e-12 * r, "a centre %g r beyond a wall's reach", out / r);
    gr_sim_free(s);
    assert_restart_exact(&sc, quick() ? 20 * chunk : 100 * chunk,
                         quick() ? 11 * chunk : 57 * chunk);
}
END_TEST

static void refused(const char *text, const char *const *set, int n_set, const char *const *needles,
                    int n_needles)
{
    gr_scene s;
    gr_error err = {0};
    int rc = gr_scene_load_buffer(&s, "test.ini", text, strlen(text), set, n_set, &err);
    ck_assert_msg(rc != GR_OK, "accepted: %s", text);
    for (int i = 0; i < n_needles; i++) {
        ck_assert_msg(strstr(err.message, needles[i]), "'%s' not in: %s", needles[i], err.message);
    }
}

START_TEST(refusals_3d)
{
    const char *two = "[system]\ndim = 2\nN = 1\nL = 0.04\n[driving]\nkind = none\n";
    const char *z2[] = {"boundary.z=walls"};
    const char *n_z2[] = {"[boundary] z", "only for dim = 3", "z = periodic"};
    refused(two, z2, 1, n_z2, 3);
    const char *gz2[] = {"gravity.gz=-9.81"};
    const char *n_gz2[] = {"[gravity] gz", "only for dim = 3"};
    refused(two, gz2, 1, n_gz2, 2);
    const char *per[] = {"boundary.z=periodic"};
    const char *n_per[] = {"[gravity] gz", "[boundary] z = walls"};
    refused(grain_3d, per, 1, n_per, 2);
    const char *vib[] = {"boundary.vibrate=y"};
    const char *n_vib[] = {"[boundary] vibrate", "[boundary] y = periodic"};
    refused(grain_3d, vib, 1, n_vib, 2);
    /* the event integrator's walls (fixed or vibrating, smooth or rough spheres) run: tests of
     * test_event_vibrate.c */
    /* the library too: gz along a periodic z */
    gr_scene sc;
    gr_sim *s = NULL;
    gr_error err = {0};
    load(&sc, grain_3d, NULL, 0);
    gr_sim_params p;
    gr_scene_sim_params(&sc, &p);
    p.walls[2] = false;
    ck_assert_int_ne(gr_sim_new(&p, &s, &err), GR_OK);
    ck_assert_msg(strstr(err.message, "[gravity] gz"), "%s", err.message);
}
END_TEST

static Suite *walls_3d_suite(void)
{
    Suite *s = suite_create("walls_3d");
    TCase *unit = tcase_create("unit");
    tcase_add_test(unit, refusals_3d);
    tcase_add_test(unit, no_contact_through_walls_3d);
    tcase_add_test(unit, threads_invariant_3d);
    tcase_add_test(unit, sublist_on_the_bed_3d);
    tcase_add_test(unit, runaway_into_wall_3d);
    suite_add_tcase(s, unit);
    TCase *phys = tcase_create("physics");
    tcase_set_timeout(phys, 600);
    tcase_add_test(phys, bounce_apex_3d);
    tcase_add_test(phys, elastic_energy_3d);
    tcase_add_test(phys, ledger_walls_3d);
    tcase_add_test(phys, tangential_walls_3d);
    tcase_add_test(phys, floor_below_zero_3d);
    tcase_add_test(phys, oblique_wall_eps_t_3d);
    tcase_add_test(phys, spinning_sphere_rolls);
    tcase_add_test(phys, bed_weighs_on_floor_3d);
    tcase_add_test(phys, event_bounce_3d);
    tcase_add_test(phys, event_box_3d);
    suite_add_tcase(s, phys);
    return s;
}

int main(void) { return gr_test_run(walls_3d_suite()); }
