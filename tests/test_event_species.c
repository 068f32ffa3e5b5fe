/* The event-driven integrator with species (issue 36, docs/mixtures.md): hard discs and rods of
 * their own radii and masses.
 *  - two-body collisions of unequal grains (2D head-on and oblique, 1D): they touch at r_i + r_j,
 *    at the instant of the analytic flight; momentum sum m_i v_i is conserved, the normal relative
 *    velocity is reversed times eps_n (the tangential one kept with eps_t = 1), and the energy lost
 *    is (1 - eps_n^2) M_ij g_n^2 / 2 with the reduced mass M_ij, booked as dissipated;
 *  - each species pair's TC time is its own contact time (t_c ~ sqrt(M_ij));
 *  - the random force's kicks per species: free flight without collisions gives
 *    <m_i^2 v^2> = 2 D t per component for every species (kicks sqrt(2 D tau) / m_i);
 *  - a driven gas of two species: symmetrised kicks and collisions keep sum m_i v_i = 0, the
 *    ledger closes to rounding, no two grains overlap (checked after every collision);
 *  - a checkpoint continues bit for bit (1D, 2D);
 *  - rough discs (Walton's rule with each grain's arm and moment of inertia): the contact point's
 *    g_ct times -beta or at the Coulomb limit, angular momentum about the contact point conserved,
 *    the loss; a driven rough gas.s ledger and restart;
 *  - a radius distribution: each pair's TC time is the matching contact's at its reduced mass
 *    (t_c ~ sqrt(M_ij)), or the [model] tc given for all; a driven gas of lognormal radii (discs,
 *    and spheres) keeps its momentum, closes its ledger, never overlaps and restarts bit for bit; the viscoelastic
 *    eps_n(v) is refused there (it would need each pair's own calibration).
 * Deterministic tolerances come from rounding; the statistical one is 5 sigma (fixed seed). */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "integrators/event/event.h"
#include "integrators/event/event_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "test_env.h"
#include "sim_helpers.h"
#include "test_scenes.h"

#define EPS_N 0.6

/* Two grains (radii 1 and 2 mm, masses 1e-5 and 4e-5 kg) without driving in a box of L = 0.1 m
 * (2D, 3D) or a ring of L = 0.506 m (1D). */
static gr_sim *grains_with(int dim, const char *const *more, int n_more)
{
    const char *ov[16] = {dim == 1   ? "system.dim=1"
                          : dim == 2 ? "system.dim=2"
                                     : "system.dim=3",
                          "system.N=2",
                          dim == 1   ? "system.reduced_length=0.5"
                          : dim == 2 ? "system.packing_fraction=0.0015707963267948967"
                                     : "system.L=0.1",
                          "species.radius=1e-3, 2e-3",
                          "species.mass=1e-5, 4e-5",
                          dim == 3 ? "placement.kind=cubic" : "placement.kind=uniform",
                          "model.normal=hard_sphere",
                          "model.eps_n=0.6",
                          "noise.mode=none",
                          "integrator.kind=event"};
    for (int k = 0; k < n_more; k++) {
        ov[10 + k] = more[k];
    }
    gr_scene sc = scene_of(ov, 10 + n_more);
    return sim_of(&sc);
}

/* Smooth grains with eps_t = 1. */
static gr_sim *two_grains(int dim)
{
    const char *smooth[] = {"model.eps_t=1"};
    return grains_with(dim, smooth, 1);
}

/* Set grain k's state at the current (window start) time and predict again. */
static void place(gr_sim *s, const double *x, const double *y, const double *vx, const double *vy)
{
    struct gr_event_state *e = gr_ev(s);
    for (int k = 0; k < 2; k++) {
        e->bx[k] = x[k];
        e->bv[k] = vx[k];
        if (s->dim == 2) {
            e->by[k] = y[k];
            e->bw[k] = vy[k];
        }
    }
    gr_event_set_debug(s, true, false); /* overlap checks after every collision */
}

/* Grain a at (x_a, y0) moving (+0.1, 0) m/s towards grain b at (x_a + 0.02, y0 + b) moving
 * (-0.05, 0): one collision at the analytic instant, then free flight to T. */
static void collide_pair(int dim, double b)
{
    gr_sim *s = two_grains(dim);
    ck_assert_ptr_nonnull(s->mass_i);
    const double ma = s->mass_i[0], mb = s->mass_i[1], d = s->rad[0] + s->rad[1];
    ck_assert(ma != mb && fabs(d - 3e-3) < 1e-18);
    const double m12 = ma * mb / (ma + mb);
    const double x[2] = {0.03, 0.05}, y[2] = {0.05, 0.05 + b}, vx[2] = {0.1, -0.05},
                 vy[2] = {0.0, 0.0};
    place(s, x, y, vx, vy);
    /* contact: (0.02 - 0.15 t)^2 + b^2 = d^2 */
    const double tcol = (0.02 - sqrt(d * d - b * b)) / 0.15;
    const double nx = (0.02 - 0.15 * tcol) / d, ny = b / d; /* unit normal from a to b */
    const double gn = 0.15 * nx;                            /* (v_a - v_b).n > 0 */
    const double P = (1.0 + EPS_N) * m12 * gn;              /* the impulse on b, -P on a */
    const double ua[2] = {vx[0] - P / ma * nx, -P / ma * ny},
                 ub[2] = {vx[1] + P / mb * nx, P / mb * ny};
    const double T = tcol + 0.02;
    const int64_t steps = (int64_t)ceil(T / s->dt);
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    const double t = gr_sim_time(s);
    gr_event_counts c;
    gr_event_stats(s, &c);
    ck_assert_int_eq(c.collisions, 1);
    /* velocities and positions of the analytic collision (touching at r_a + r_b, not at the
     * largest pair's distance) */
    const double vxa = s->vx[0], vxb = s->vx[1], vya = dim == 2 ? s->vy[0] : 0.0,
                 vyb = dim == 2 ? s->vy[1] : 0.0;
    ck_assert_msg(fabs(vxa - ua[0]) < 1e-14 && fabs(vxb - ub[0]) < 1e-14 &&
                      fabs(vya - ua[1]) < 1e-14 && fabs(vyb - ub[1]) < 1e-14,
                  "velocities (%.17g, %.17g), (%.17g, %.17g); expected (%.17g, %.17g), (%.17g, "
                  "%.17g)",
                  vxa, vya, vxb, vyb, ua[0], ua[1], ub[0], ub[1]);
    const double xa = x[0] + 0.1 * tcol + ua[0] * (t - tcol),
                 xb = x[1] - 0.05 * tcol + ub[0] * (t - tcol);
    ck_assert_msg(fabs(s->x[0] - xa) < 1e-13 && fabs(s->x[1] - xb) < 1e-13,
                  "positions %.17g, %.17g; expected %.17g, %.17g (contact at r_a + r_b)", s->x[0],
                  s->x[1], xa, xb);
    if (dim == 2) {
        ck_assert(fabs(s->y[0] - (y[0] + ua[1] * (t - tcol))) < 1e-13);
        ck_assert(fabs(s->y[1] - (y[1] + ub[1] * (t - tcol))) < 1e-13);
    }
    /* momentum, restitution of the normal relative velocity, the tangential one kept */
    const double p0x = ma * vx[0] + mb * vx[1], p1x = ma * vxa + mb * vxb,
                 p1y = ma * vya + mb * vyb;
    ck_assert_msg(fabs(p1x - p0x) < 1e-16 * ma && fabs(p1y) < 1e-16 * ma, "momentum %g, %g from %g",
                  p1x, p1y, p0x);
    const double gn1 = (vxa - vxb) * nx + (vya - vyb) * ny, gt0 = -0.15 * ny,
                 gt1 = -(vxa - vxb) * ny + (vya - vyb) * nx;
    ck_assert_msg(fabs(gn1 + EPS_N * gn) < 1e-14, "g_n after %.17g, want -%g * %.17g", gn1, EPS_N,
                  gn);
    ck_assert(fabs(gt1 - gt0) < 1e-14);
    /* the loss: (1 - eps^2) of the reduced-mass kinetic energy of the normal motion, booked */
    const double k0 = 0.5 * (ma * (vx[0] * vx[0]) + mb * (vx[1] * vx[1]));
    const double k1 = 0.5 * (ma * (vxa * vxa + vya * vya) + mb * (vxb * vxb + vyb * vyb));
    const double want = 0.5 * (1.0 - EPS_N * EPS_N) * m12 * gn * gn;
    ck_assert_msg(fabs((k0 - k1) / want - 1.0) < 1e-10, "lost %.12g J, want %.12g J", k0 - k1,
                  want);
    ck_assert(fabs(s->diss_n / want - 1.0) < 1e-12);
    ck_assert(t >= T);
    gr_sim_free(s);
}

START_TEST(test_two_body_2d_headon) { collide_pair(2, 0.0); }
END_TEST

START_TEST(test_two_body_2d_oblique) { collide_pair(2, 1.9e-3); }
END_TEST

START_TEST(test_two_body_1d) { collide_pair(1, 0.0); }
END_TEST

/* Two spheres at x0 with velocities v0 (the event state's flights from now), every event checked
 * (debug). */
static void place_3d(gr_sim *s, const double x0[2][3], const double v0[2][3])
{
    struct gr_event_state *e = gr_ev(s);
    for (int k = 0; k < 2; k++) {
        e->bx[k] = x0[k][0];
        e->by[k] = x0[k][1];
        e->bz[k] = x0[k][2];
        e->bv[k] = v0[k][0];
        e->bw[k] = v0[k][1];
        e->bu[k] = v0[k][2];
    }
    gr_event_set_debug(s, true, false);
}

/* 3D (smooth spheres): grain 0 at (0.03, 0.05, 0.05) moving (+0.1, 0, 0) m/s, grain 1 at
 * (0.05, 0.05 + b_y, 0.05 + b_z) moving (-0.05, 0, 0), the impact parameter out of every
 * coordinate plane: one collision at the analytic instant and normal, r_i + r_j apart; momentum,
 * eps_n of the normal relative velocity, the tangential one kept, the loss
 * (1 - eps^2) M_ij g_n^2 / 2 booked. */
START_TEST(test_two_body_3d)
{
    gr_sim *s = two_grains(3);
    const double ma = s->mass_i[0], mb = s->mass_i[1], d = s->rad[0] + s->rad[1];
    ck_assert(ma != mb && fabs(d - 3e-3) < 1e-18);
    const double m12 = ma * mb / (ma + mb), by = 1.2e-3, bz = -0.9e-3;
    const double x0[2][3] = {{0.03, 0.05, 0.05}, {0.05, 0.05 + by, 0.05 + bz}};
    const double v0[2][3] = {{0.1, 0.0, 0.0}, {-0.05, 0.0, 0.0}};
    place_3d(s, x0, v0);
    const double b = sqrt(by * by + bz * bz);
    const double tcol = (0.02 - sqrt(d * d - b * b)) / 0.15;
    const double n[3] = {(0.02 - 0.15 * tcol) / d, by / d, bz / d};
    const double gn = 0.15 * n[0], P = (1.0 + EPS_N) * m12 * gn;
    double ua[3], ub[3];
    for (int a = 0; a < 3; a++) {
        ua[a] = v0[0][a] - P / ma * n[a];
        ub[a] = v0[1][a] + P / mb * n[a];
    }
    const double T = tcol + 0.02;
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, (int64_t)ceil(T / s->dt), &err) == GR_OK, "%s", err.message);
    const double t = gr_sim_time(s);
    gr_event_counts c;
    gr_event_stats(s, &c);
    ck_assert_int_eq(c.collisions, 1);
    const double va[3] = {s->vx[0], s->vy[0], s->vz[0]}, vb[3] = {s->vx[1], s->vy[1], s->vz[1]};
    const double qa[3] = {s->x[0], s->y[0], s->z[0]}, qb[3] = {s->x[1], s->y[1], s->z[1]};
    double k0 = 0.0, k1 = 0.0, gn1 = 0.0;
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(va[a] - ua[a]) < 1e-14 && fabs(vb[a] - ub[a]) < 1e-14,
                      "component %d: velocities %.17g, %.17g; expected %.17g, %.17g", a, va[a],
                      vb[a], ua[a], ub[a]);
        ck_assert_msg(fabs(qa[a] - (x0[0][a] + v0[0][a] * tcol + ua[a] * (t - tcol))) < 1e-13 &&
                          fabs(qb[a] - (x0[1][a] + v0[1][a] * tcol + ub[a] * (t - tcol))) < 1e-13,
                      "component %d: positions (contact at r_a + r_b)", a);
        const double p0 = ma * v0[0][a] + mb * v0[1][a], p1 = ma * va[a] + mb * vb[a];
        ck_assert_msg(fabs(p1 - p0) < 1e-16 * ma, "momentum %d: %g from %g", a, p1, p0);
        k0 += 0.5 * (ma * v0[0][a] * v0[0][a] + mb * v0[1][a] * v0[1][a]);
        k1 += 0.5 * (ma * va[a] * va[a] + mb * vb[a] * vb[a]);
        gn1 += (va[a] - vb[a]) * n[a];
    }
    ck_assert_msg(fabs(gn1 + EPS_N * gn) < 1e-14, "g_n after %.17g, want -%g * %.17g", gn1, EPS_N,
                  gn);
    /* the tangential relative velocity kept (eps_t = 1): (g - g_n n) before and after */
    for (int a = 0; a < 3; a++) {
        const double g0 = v0[0][a] - v0[1][a] - gn * n[a], g1 = va[a] - vb[a] - gn1 * n[a];
        ck_assert_msg(fabs(g1 - g0) < 1e-14, "tangential %d: %.17g -> %.17g", a, g0, g1);
    }
    const double want = 0.5 * (1.0 - EPS_N * EPS_N) * m12 * gn * gn;
    ck_assert_msg(fabs((k0 - k1) / want - 1.0) < 1e-10, "lost %.12g J, want %.12g J", k0 - k1,
                  want);
    ck_assert(fabs(s->diss_n / want - 1.0) < 1e-12);
    ck_assert(strncmp(gr_sim_kernel(s), "event-3d", 8) == 0);
    gr_sim_free(s);
}
END_TEST

/* Each species pair's TC time is the contact time of its own reduced mass. */
START_TEST(test_pair_tc)
{
    gr_sim *s = two_grains(2);
    struct gr_event_state *e = gr_ev(s);
    const int a = s->species[0], b = s->species[1];
    const double taa = s->cc_pair[a * 2 + a].tc, tbb = s->cc_pair[b * 2 + b].tc,
                 tab = s->cc_pair[a * 2 + b].tc;
    const double ma = s->mass_i[0], mb = s->mass_i[1];
    ck_assert(fabs(tbb / taa - sqrt(mb / ma)) < 1e-12);
    ck_assert(fabs(tab / taa - sqrt(2.0 * mb / (ma + mb))) < 1e-12);
    ck_assert(gr_ev_tc(e, 0, 1) == tab && gr_ev_tc(e, 0, 0) == taa);
    gr_sim_free(s);
}
END_TEST

/* Free flight without collisions: every species gets kicks of sqrt(2 D tau) / m_i, so
 * m_i^2 <v^2> = 2 D t per component whatever the mass (5 sigma; 2D, exact or kicks). */
START_TEST(test_kicks_per_species)
{
    const bool exact = _i == 0;
    const char *ov[] = {"system.dim=2",
                        "system.N=4000",
                        "system.L=10",
                        "species.radius=1e-3, 2e-3",
                        "species.mass=1e-5, 4e-5",
                        "placement.kind=uniform",
                        "placement.v0=0",
                        "model.normal=hard_sphere",
                        "noise.D=1e-8",
                        "integrator.kind=event",
                        "integrator.dt=1e-6",
                        "integrator.kick_interval=4e-5",
                        exact ? "integrator.free_flight=exact" : "integrator.free_flight=kicks",
                        "run.seed=3"};
    gr_scene sc = scene_of(ov, 14);
    gr_sim *s = sim_of(&sc);
    gr_event_set_debug(s, false, true);
    gr_error err = {0};
    ck_assert(gr_sim_step(s, 400, &err) == GR_OK);
    const double t = gr_sim_time(s), D = 1e-8;
    double sum[2] = {0, 0}, p[2] = {0, 0};
    int cnt[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        const int a = s->species[i];
        const double m = s->mass_i[i];
        sum[a] += m * m * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i]) / 2.0;
        cnt[a]++;
        p[0] += m * s->vx[i];
        p[1] += m * s->vy[i];
    }
    for (int a = 0; a < 2; a++) {
        const double r = sum[a] / cnt[a] / (2.0 * D * t), sigma = sqrt(1.0 / cnt[a]);
        if (verbose()) {
            printf("species %d: m^2 <v^2> / (2 D t) = %.4f +- %.4f\n", a + 1, r, sigma);
        }
        ck_assert_msg(fabs(r - 1.0) < 5.0 * sigma, "species %d: %.4f (sigma %.4f)", a + 1, r,
                      sigma);
    }
    /* symmetrised: the kicks carry no momentum (sum m_i v_i = 0 to rounding) */
    const double scale = sqrt(2.0 * D * t) * s->n;
    ck_assert_msg(fabs(p[0]) < 1e-12 * scale && fabs(p[1]) < 1e-12 * scale, "momentum %g, %g", p[0],
                  p[1]);
    gr_sim_free(s);
}
END_TEST

/* A gas of two species (radii 1 and 2 mm, equal density) of n grains (key=value) driven by the
 * random force, hard discs (2D, packing fraction 0.1) or rods (1D, L' = 5 cm), eps_n = 0.5;
 * variant 2: rough discs (2D, beta = 0.3); variant 3: smooth spheres (3D); variant 4: discs of a
 * lognormal radius distribution in [1, 3] mm (median 1.5 mm) instead of the two species; variant 5:
 * spheres of that distribution (3D). */
static gr_scene species_gas(int variant, const char *n, const char *seed)
{
    const int dim = variant == 0 ? 1 : variant == 3 || variant == 5 ? 3 : 2;
    const char *ov[16] = {dim == 1   ? "system.dim=1"
                          : dim == 2 ? "system.dim=2"
                                     : "system.dim=3",
                          n,
                          dim == 1 ? "system.reduced_length=0.05" : "system.packing_fraction=0.1",
                          "species.radius=1e-3, 2e-3",
                          "species.density=10, 10",
                          "species.fraction=0.5, 0.5",
                          "placement.kind=random",
                          "placement.v0=0.05",
                          "model.normal=hard_sphere",
                          "model.eps_n=0.5",
                          "noise.D=1e-9",
                          "integrator.kind=event",
                          seed,
                          "model.rotation=true",
                          "model.beta=0.3"};
    if (variant >= 4) { /* the distribution's keys in place of the lists (and of rotation) */
        ov[3] = "species.distribution=lognormal";
        ov[4] = "species.radius_min=1e-3";
        ov[5] = "species.radius_max=3e-3";
        ov[13] = "species.radius_median=1.5e-3";
        ov[14] = "species.radius_sigma=0.3";
        ov[15] = "species.density=10";
        return scene_of(ov, 16);
    }
    return scene_of(ov, variant == 2 ? 15 : 13);
}

/* A driven inelastic gas of two species (1D ring, 2D box, 2D rough discs): momentum stays 0, the
 * ledger (rough: with the spins' energy sum I_i w_i^2 / 2 and the tangential losses) closes to
 * rounding, no overlaps (checked after every collision), collisions of all three pair kinds. */
START_TEST(test_driven_gas)
{
    const int dim = _i == 0 ? 1 : _i == 3 || _i == 5 ? 3 : 2; /* 4, 5: a radius distribution */
    /* 3D: 100 spheres (the overlap check after every collision is O(N^2)) */
    gr_scene sc = species_gas(_i,
                              quick()    ? "system.N=60"
                              : dim == 3 ? "system.N=100"
                                         : "system.N=200",
                              "run.seed=5");
    gr_sim *s = sim_of(&sc);
    gr_event_set_debug(s, true, false);
    gr_error err = {0};
    const int64_t steps = (int64_t)((quick() ? 0.02 : 0.1) / s->dt);
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    gr_event_counts c;
    gr_event_stats(s, &c);
    ck_assert_msg(c.collisions > (quick() ? 5 : 200), "%lld collisions", (long long)c.collisions);
    double p[3] = {0, 0, 0}, scale = 0.0;
    for (int i = 0; i < s->n; i++) {
        const double vy = dim >= 2 ? s->vy[i] : 0.0, vz = dim == 3 ? s->vz[i] : 0.0;
        p[0] += s->mass_i[i] * s->vx[i];
        p[1] += s->mass_i[i] * vy;
        p[2] += s->mass_i[i] * vz;
        scale += s->mass_i[i] * sqrt(s->vx[i] * s->vx[i] + vy * vy + vz * vz);
    }
    ck_assert_msg(fabs(p[0]) < 1e-12 * scale && fabs(p[1]) < 1e-12 * scale &&
                      fabs(p[2]) < 1e-12 * scale,
                  "momentum %g, %g, %g of %g", p[0], p[1], p[2], scale);
    gr_ledger l = gr_sim_ledger(s);
    const double rel =
        gr_ledger_residual(&l) / fmax(l.injected + gr_ledger_dissipated(&l), l.initial);
    if (verbose()) {
        printf("%dD: %lld collisions, ledger residual %.3g\n", dim, (long long)c.collisions, rel);
    }
    ck_assert_msg(fabs(rel) < 1e-10, "ledger residual %g", rel);
    ck_assert(strncmp(gr_sim_kernel(s), "event-", 6) == 0);
    ck_assert(_i != 2 || (l.rotational > 0.0 && l.dissipated_tangential > 0.0));
    gr_sim_free(s);
}
END_TEST

/* A checkpoint of an event-driven mixture (mid-window state, each grain's mass and radius from the
 * scene again; rough: the spins) continues bit for bit, in 1D, 2D and 2D rough. */
START_TEST(test_restart_exact)
{
    gr_scene sc = species_gas(_i, "system.N=60", "run.seed=9");
    gr_sim *probe = sim_of(&sc);
    const int64_t total = (int64_t)(0.02 / probe->dt);
    gr_sim_free(probe);
    assert_restart_exact(&sc, total, total / 3);
}
END_TEST

/* Rough discs of two species (gr_ev_rule, event_internal.h): grain a (r 1 mm, 1e-5 kg) spinning
 * at 300 rad/s meets grain b (r 2 mm, 4e-5 kg) spinning at -100 rad/s obliquely. Walton's rule with
 * each grain's own arm r_i and moment of inertia I_i = q m_i r_i^2: the contact point's relative
 * tangential velocity g.t + r_a w_a + r_b w_b comes out times -beta (beta_mu = 0), or with the
 * Coulomb limit (beta_mu = 0.05) the tangential impulse is beta_mu times the normal one; the
 * normal one times -eps_n; momentum and the angular momentum about the contact point,
 * sum_i m_i (x_i - c) x v_i + I_i w_i, are conserved; the energy lost is
 * M_ij (1 - eps_n^2) g_n^2 / 2 + m_t (1 - beta^2) g_ct^2 / 2 with m_t = M_ij q / (1 + q), booked
 * as normal and tangential dissipation. One moment of inertia or arm for both grains breaks the
 * angular momentum and the -beta. */
static void rough_pair(double beta_mu)
{
    char mu[32];
    snprintf(mu, sizeof mu, "model.beta_mu=%g", beta_mu);
    const char *rough[] = {"model.rotation=true", "model.beta=0.4", mu};
    gr_sim *s = grains_with(2, rough, 3);
    const double ma = s->mass_i[0], mb = s->mass_i[1], ra = s->rad[0], rb = s->rad[1], d = ra + rb,
                 q = s->cc.q;
    const double Ia = q * ma * ra * ra, Ib = q * mb * rb * rb, m12 = ma * mb / (ma + mb),
                 m_t = m12 * q / (1.0 + q);
    ck_assert(fabs(s->inertia_i[0] / Ia - 1.0) < 1e-15 && fabs(s->inertia_i[1] / Ib - 1.0) < 1e-15);
    const double b = 1.2e-3, x[2] = {0.03, 0.05}, y[2] = {0.05, 0.05 + b}, vx[2] = {0.1, -0.05},
                 vy[2] = {0.0, 0.0}, w0[2] = {300.0, -100.0};
    place(s, x, y, vx, vy);
    s->omega[0] = w0[0];
    s->omega[1] = w0[1];
    const double tcol = (0.02 - sqrt(d * d - b * b)) / 0.15;
    const double nx = (0.02 - 0.15 * tcol) / d, ny = b / d, tx = -ny, ty = nx;
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, (int64_t)ceil((tcol + 0.01) / s->dt), &err) == GR_OK, "%s",
                  err.message);
    gr_event_counts c;
    gr_event_stats(s, &c);
    ck_assert_int_eq(c.collisions, 1);
    const double va[2] = {s->vx[0], s->vy[0]}, vb[2] = {s->vx[1], s->vy[1]};
    const double wa = s->omega[0], wb = s->omega[1];
    /* before and after: g = v_a - v_b, the contact point's g_ct = g.t + r_a w_a + r_b w_b */
    const double gn0 = 0.15 * nx, gct0 = 0.15 * tx + ra * w0[0] + rb * w0[1];
    const double gn1 = (va[0] - vb[0]) * nx + (va[1] - vb[1]) * ny,
                 gct1 = (va[0] - vb[0]) * tx + (va[1] - vb[1]) * ty + ra * wa + rb * wb;
    /* the impulse on b: P = m_b dv_b; its normal and tangential parts */
    const double Pn = mb * ((vb[0] - vx[1]) * nx + vb[1] * ny),
                 Pt = mb * ((vb[0] - vx[1]) * tx + vb[1] * ty);
    /* angular momentum about the contact point c = x_a + r_a n: x_a - c = -r_a n, x_b - c = r_b n */
    const double dLa =
        ma * (-ra) * (nx * (va[1] - vy[0]) - ny * (va[0] - vx[0])) + Ia * (wa - w0[0]);
    const double dLb = mb * rb * (nx * (vb[1] - vy[1]) - ny * (vb[0] - vx[1])) + Ib * (wb - w0[1]);
    const double L_scale = Ia * fabs(w0[0]);
    const double k0 =
        0.5 * (ma * vx[0] * vx[0] + mb * vx[1] * vx[1] + Ia * w0[0] * w0[0] + Ib * w0[1] * w0[1]);
    const double k1 = 0.5 * (ma * (va[0] * va[0] + va[1] * va[1]) +
                             mb * (vb[0] * vb[0] + vb[1] * vb[1]) + Ia * wa * wa + Ib * wb * wb);
    const double beta = -gct1 / gct0;
    const double want = 0.5 * m12 * (1.0 - EPS_N * EPS_N) * gn0 * gn0 +
                        0.5 * m_t * (1.0 - beta * beta) * gct0 * gct0;
    printf("rough pair (beta_mu %g): g_n ratio %.15f, g_ct ratio %.15f, |P_t| / |P_n| = %.15f, dL "
           "about the contact %.3g (of %.3g), energy lost %.12g J (Walton %.12g J)\n",
           beta_mu, gn1 / gn0, gct1 / gct0, fabs(Pt / Pn), dLa + dLb, L_scale, k0 - k1, want);
    ck_assert_msg(fabs(gn1 / gn0 + EPS_N) < 1e-12, "g_n ratio %.17g", gn1 / gn0);
    if (beta_mu == 0.0) {
        ck_assert_msg(fabs(beta - 0.4) < 1e-12, "g_ct ratio %.17g, want -0.4", gct1 / gct0);
    } else {
        ck_assert_msg(beta < 0.4 && fabs(fabs(Pt / Pn) - beta_mu) < 1e-12,
                      "sliding: beta %.17g, |P_t / P_n| %.17g, want %g", beta, fabs(Pt / Pn),
                      beta_mu);
    }
    ck_assert_msg(fabs(dLa + dLb) < 1e-12 * L_scale, "angular momentum about the contact: %g",
                  dLa + dLb);
    ck_assert_msg(fabs(ma * (va[0] - vx[0]) + Pn * nx + Pt * tx) < 1e-16 * ma &&
                      fabs(ma * va[1] + Pn * ny + Pt * ty) < 1e-16 * ma,
                  "momentum");
    ck_assert_msg(fabs((k0 - k1) / want - 1.0) < 1e-10, "lost %.12g J, Walton %.12g J", k0 - k1,
                  want);
    ck_assert(fabs((s->diss_n + s->diss_t) / want - 1.0) < 1e-10);
    gr_sim_free(s);
}

/* 3D: the same rule on unequal spheres spinning about axes out of every plane (Walton on
 * 3-vectors): g_n' = -eps_n g_n; the contact point's tangential relative velocity g_ct = (g +
 * (r_a w_a + r_b w_b) x n)_t turned into -beta g_ct (or, sliding, |P_t| = beta_mu |P_n| along
 * g_ct); momentum; each sphere's angular momentum about the contact point (the impulse acts
 * there); Walton's energy loss with m_t = M_ab q / (1 + q). */
static void rough_pair_3d(double beta_mu)
{
    char mu[32];
    snprintf(mu, sizeof mu, "model.beta_mu=%g", beta_mu);
    const char *rough[] = {"model.rotation=true", "model.beta=0.4", mu};
    gr_sim *s = grains_with(3, rough, 3);
    const double ma = s->mass_i[0], mb = s->mass_i[1], ra = s->rad[0], rb = s->rad[1], d = ra + rb,
                 q = s->cc.q;
    const double Ia = q * ma * ra * ra, Ib = q * mb * rb * rb, m12 = ma * mb / (ma + mb),
                 m_t = m12 * q / (1.0 + q);
    const double by = 1.2e-3, bz = -0.9e-3;
    const double x0[2][3] = {{0.03, 0.05, 0.05}, {0.05, 0.05 + by, 0.05 + bz}};
    const double v0[2][3] = {{0.1, 0.0, 0.0}, {-0.05, 0.0, 0.0}};
    const double w0[2][3] = {{300.0, -200.0, 150.0}, {-100.0, 250.0, -50.0}};
    double *w[3] = {s->wx, s->wy, s->omega};
    for (int k = 0; k < 2; k++) {
        for (int a = 0; a < 3; a++) {
            w[a][k] = w0[k][a];
        }
    }
    place_3d(s, x0, v0);
    const double b = sqrt(by * by + bz * bz), tcol = (0.02 - sqrt(d * d - b * b)) / 0.15;
    const double n[3] = {(0.02 - 0.15 * tcol) / d, by / d, bz / d}; /* from a to b */
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, (int64_t)ceil((tcol + 0.01) / s->dt), &err) == GR_OK, "%s",
                  err.message);
    gr_event_counts c;
    gr_event_stats(s, &c);
    ck_assert_int_eq(c.collisions, 1);
    const double v1[2][3] = {{s->vx[0], s->vy[0], s->vz[0]}, {s->vx[1], s->vy[1], s->vz[1]}};
    const double w1[2][3] = {{s->wx[0], s->wy[0], s->omega[0]}, {s->wx[1], s->wy[1], s->omega[1]}};
    /* g_ct before and after; the impulse on b, P = m_b dv_b */
    double gct[2][3], gn[2] = {0.0, 0.0}, P[3], Pn = 0.0;
    for (int k = 0; k < 2; k++) {
        const double(*v)[3] = k ? v1 : v0, (*ww)[3] = k ? w1 : w0;
        double g[3], W[3];
        for (int a = 0; a < 3; a++) {
            g[a] = v[0][a] - v[1][a];
            W[a] = ra * ww[0][a] + rb * ww[1][a];
            gn[k] += g[a] * n[a];
        }
        const double Wn[3] = {W[1] * n[2] - W[2] * n[1], W[2] * n[0] - W[0] * n[2],
                              W[0] * n[1] - W[1] * n[0]};
        for (int a = 0; a < 3; a++) {
            gct[k][a] = g[a] - gn[k] * n[a] + Wn[a];
        }
    }
    for (int a = 0; a < 3; a++) {
        P[a] = mb * (v1[1][a] - v0[1][a]);
        Pn += P[a] * n[a];
    }
    double Pt2 = 0.0, g0 = 0.0, g1 = 0.0, dot = 0.0;
    for (int a = 0; a < 3; a++) {
        Pt2 += (P[a] - Pn * n[a]) * (P[a] - Pn * n[a]);
        g0 += gct[0][a] * gct[0][a];
        g1 += gct[1][a] * gct[1][a];
        dot += gct[0][a] * gct[1][a];
    }
    const double beta = -dot / g0; /* g_ct' = -beta g_ct */
    /* angular momentum about the contact point c: x_a - c = -r_a n, x_b - c = r_b n */
    double dL[2][3];
    for (int k = 0; k < 2; k++) {
        const double arm = k ? rb : -ra, m = k ? mb : ma, I = k ? Ib : Ia;
        double dv[3];
        for (int a = 0; a < 3; a++) {
            dv[a] = v1[k][a] - v0[k][a];
        }
        const double nxdv[3] = {n[1] * dv[2] - n[2] * dv[1], n[2] * dv[0] - n[0] * dv[2],
                                n[0] * dv[1] - n[1] * dv[0]};
        for (int a = 0; a < 3; a++) {
            dL[k][a] = m * arm * nxdv[a] + I * (w1[k][a] - w0[k][a]);
        }
    }
    double k0 = 0.0, k1 = 0.0, worst_L = 0.0, mom = 0.0, par = 0.0;
    for (int k = 0; k < 2; k++) {
        const double m = k ? mb : ma, I = k ? Ib : Ia;
        for (int a = 0; a < 3; a++) {
            k0 += 0.5 * (m * v0[k][a] * v0[k][a] + I * w0[k][a] * w0[k][a]);
            k1 += 0.5 * (m * v1[k][a] * v1[k][a] + I * w1[k][a] * w1[k][a]);
            worst_L = fmax(worst_L, fabs(dL[k][a]));
        }
    }
    for (int a = 0; a < 3; a++) {
        mom = fmax(mom, fabs(ma * (v1[0][a] - v0[0][a]) + P[a]));
        /* g_ct' parallel to g_ct: the cross product vanishes */
        const int a1 = (a + 1) % 3, a2 = (a + 2) % 3;
        par = fmax(par, fabs(gct[0][a1] * gct[1][a2] - gct[0][a2] * gct[1][a1]) / g0);
    }
    const double L_scale = Ia * 300.0;
    const double want =
        0.5 * m12 * (1.0 - EPS_N * EPS_N) * gn[0] * gn[0] + 0.5 * m_t * (1.0 - beta * beta) * g0;
    printf("3D rough pair (beta_mu %g): g_n ratio %.15f, beta %.15f, |P_t| / |P_n| = %.15f, "
           "parallel %.2g, dL about the contact %.3g (of %.3g), lost %.12g J (Walton %.12g J)\n",
           beta_mu, gn[1] / gn[0], beta, sqrt(Pt2) / fabs(Pn), par, worst_L, L_scale, k0 - k1,
           want);
    ck_assert_msg(fabs(gn[1] / gn[0] + EPS_N) < 1e-12, "g_n ratio %.17g", gn[1] / gn[0]);
    ck_assert_msg(par < 1e-12, "g_ct turned out of its direction: %g", par);
    if (beta_mu == 0.0) {
        ck_assert_msg(fabs(beta - 0.4) < 1e-12 && fabs(g1 / g0 - 0.16) < 1e-12,
                      "g_ct ratio %.17g, want -0.4", beta);
    } else {
        ck_assert_msg(beta < 0.4 && fabs(sqrt(Pt2) / fabs(Pn) - beta_mu) < 1e-12,
                      "sliding: beta %.17g, |P_t / P_n| %.17g, want %g", beta, sqrt(Pt2) / fabs(Pn),
                      beta_mu);
    }
    ck_assert_msg(worst_L < 1e-12 * L_scale, "angular momentum about the contact: %g", worst_L);
    ck_assert_msg(mom < 1e-16 * ma, "momentum %g", mom);
    ck_assert_msg(fabs((k0 - k1) / want - 1.0) < 1e-10, "lost %.12g J, Walton %.12g J", k0 - k1,
                  want);
    ck_assert(fabs((s->diss_n + s->diss_t) / want - 1.0) < 1e-10);
    gr_sim_free(s);
}

START_TEST(test_rough_pair_3d) { rough_pair_3d(0.0); }
END_TEST

START_TEST(test_rough_pair_3d_sliding) { rough_pair_3d(0.05); }
END_TEST

START_TEST(test_rough_pair) { rough_pair(0.0); }
END_TEST

START_TEST(test_rough_pair_sliding) { rough_pair(0.05); }
END_TEST

/* What the event integrator does not run with species yet is refused by name. */
/* Two grains of two sizes dropped from rest onto a floor (2D, walls along y, g = 9.81, the walls'
 * eps_n 0.8): each is exactly a ball bouncing at its own radius, y = r_k when it touches, its
 * speed eps times the impact's after; the floor's impulse is sum_k m_k (1 + eps) v_k. */
START_TEST(test_bounce_two_sizes)
{
    const char *walls[] = {"model.eps_t=1", "boundary.y=walls", "gravity.gy=-9.81",
                           "boundary.eps_n=0.8"};
    gr_sim *s = grains_with(2, walls, 4);
    const double g = 9.81, eps = 0.8, y0 = 0.03, x[2] = {0.02, 0.07}, y[2] = {y0, y0},
                 zero[2] = {0.0, 0.0};
    place(s, x, y, zero, zero);
    const double T = 0.12; /* after each grain's first bounce (t = 0.077, 0.076 s), before its
                              second (0.2 s) */
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, (int64_t)ceil(T / s->dt), &err) == GR_OK, "%s", err.message);
    const double t = gr_sim_time(s);
    double impulse = 0.0;
    for (int k = 0; k < 2; k++) {
        const double r = s->rad[k], th = sqrt(2.0 * (y0 - r) / g), vh = g * th, up = eps * vh;
        const double dt = t - th, want_y = r + up * dt - 0.5 * g * dt * dt, want_v = up - g * dt;
        ck_assert_msg(fabs(s->y[k] - want_y) < 1e-12 && fabs(s->vy[k] - want_v) < 1e-12,
                      "grain %d (r = %g m): y %.15g, v %.15g; bouncing at its own radius: %.15g, "
                      "%.15g",
                      k, r, s->y[k], s->vy[k], want_y, want_v);
        ck_assert(s->vx[k] == 0.0 && s->x[k] == x[k]);
        impulse += s->mass_i[k] * (1.0 + eps) * vh;
    }
    ck_assert_msg(fabs(s->wall_impulse[2] - impulse) < 1e-12 * impulse,
                  "floor impulse %.15g, want sum m (1 + eps) v = %.15g", s->wall_impulse[2],
                  impulse);
    gr_sim_free(s);
}
END_TEST

/* A driven gas of two species between walls under gravity (2D, 3D; _i = 2: a uniform radius
 * distribution in 2D): the ledger closes with the gravity's work (its potential sum_i m_i g h_i)
 * and the walls' hits, no overlaps (checked after every collision), the walls hit. */
START_TEST(test_gas_walls_gravity)
{
    const int dim = _i == 1 ? 3 : 2;
    const char *ov[] = {dim == 2 ? "system.dim=2" : "system.dim=3",
                        dim == 2 ? "system.N=300" : "system.N=200",
                        "system.packing_fraction=0.1",
                        _i == 2 ? "species.distribution=uniform" : "species.radius=1e-3, 2e-3",
                        _i == 2 ? "species.radius_min=1e-3" : "species.density=10, 10",
                        "placement.kind=random",
                        "placement.v0=0.05",
                        "model.normal=hard_sphere",
                        "model.eps_n=0.5",
                        "noise.D=1e-9",
                        "integrator.kind=event",
                        "run.seed=5",
                        dim == 2 ? "boundary.y=walls" : "boundary.z=walls",
                        dim == 2 ? "gravity.gy=-9.81" : "gravity.gz=-9.81",
                        "boundary.eps_n=0.9",
                        "species.radius_max=2e-3",
                        "species.density=10"};
    gr_error err = {0};
    gr_scene w = scene_of(ov, _i == 2 ? 17 : 15);
    gr_sim *s = sim_of(&w);
    gr_event_set_debug(s, true, false);
    ck_assert_msg(gr_sim_step(s, 200000, &err) == GR_OK, "%s", err.message);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    gr_event_counts c;
    gr_event_stats(s, &c);
    if (verbose()) {
        printf(
            "%dD mixture between walls: %lld collisions, %lld wall hits, residual %.3g of %.3g J\n",
            dim, (long long)c.collisions, (long long)c.wall_hits, gr_ledger_residual(&l), moved);
    }
    ck_assert(c.collisions > 0 && c.wall_hits > 0);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-9 * moved, "residual %g of %g J",
                  gr_ledger_residual(&l), moved);
    gr_sim_free(s);
}
END_TEST

/* A radius distribution: the TC time of the pair i, j is the reference pair's (the sim's tc, at
 * its reduced mass cont_m12) times sqrt(M_ij / cont_m12), the matching linear contact's duration
 * at one k_s; a tc given in the scene holds for every pair; eps_n(v) is refused. */
START_TEST(test_distribution_tc)
{
    gr_scene sc = species_gas(4, "system.N=100", "run.seed=2");
    gr_sim *s = sim_of(&sc);
    struct gr_event_state *e = gr_ev(s);
    ck_assert(s->cc.tc > 0.0 && s->cont_m12 > 0.0 && s->cc_pair == NULL);
    int checked = 0;
    for (int i = 0; i < 20; i++) {
        const int j = 99 - i;
        const double M = s->mass_i[i] * s->mass_i[j] / (s->mass_i[i] + s->mass_i[j]);
        const double want = s->cc.tc * sqrt(M / s->cont_m12);
        ck_assert_msg(fabs(gr_ev_tc(e, i, j) / want - 1.0) < 1e-14, "pair %d, %d: %g s, want %g s",
                      i, j, gr_ev_tc(e, i, j), want);
        checked += s->mass_i[i] != s->mass_i[j];
    }
    ck_assert(checked > 10); /* pairs of unequal grains */
    gr_sim_free(s);
    const char *ov[] = {"system.dim=2",
                        "system.N=100",
                        "system.packing_fraction=0.1",
                        "species.distribution=uniform",
                        "species.radius_min=1e-3",
                        "species.radius_max=2e-3",
                        "species.density=5",
                        "placement.kind=random",
                        "model.normal=hard_sphere",
                        "integrator.kind=event",
                        "model.tc=1e-5"};
    sc = scene_of(ov, 11);
    s = sim_of(&sc);
    ck_assert(gr_ev_tc(gr_ev(s), 0, 1) == 1e-5 && gr_ev_tc(gr_ev(s), 2, 7) == 1e-5);
    gr_sim_free(s);
    ov[10] = "model.viscoelastic=true";
    refused(ov, 11, "viscoelastic");
}
END_TEST

static Suite *event_species_suite(void)
{
    Suite *s = suite_create("event_species");
    TCase *t = tcase_create("two_body");
    tcase_add_test(t, test_two_body_2d_headon);
    tcase_add_test(t, test_two_body_2d_oblique);
    tcase_add_test(t, test_two_body_1d);
    tcase_add_test(t, test_two_body_3d);
    tcase_add_test(t, test_pair_tc);
    tcase_add_test(t, test_distribution_tc);
    tcase_add_test(t, test_bounce_two_sizes);
    tcase_add_test(t, test_rough_pair);
    tcase_add_test(t, test_rough_pair_sliding);
    tcase_add_test(t, test_rough_pair_3d);
    tcase_add_test(t, test_rough_pair_3d_sliding);
    suite_add_tcase(s, t);
    TCase *g = tcase_create("gas");
    tcase_set_timeout(g, 600);
    tcase_add_loop_test(g, test_kicks_per_species, 0, 2);
    tcase_add_loop_test(g, test_driven_gas, 0, 6);
    tcase_add_loop_test(g, test_restart_exact, 0, 5);
    tcase_add_loop_test(g, test_gas_walls_gravity, 0, 3);
    suite_add_tcase(s, g);
    return s;
}

int main(void) { return gr_test_run(event_species_suite()); }
