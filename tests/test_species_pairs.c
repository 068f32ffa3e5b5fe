/* Tests of species (src/core/species.c, kernels_poly.c, integrators/verlet/step_poly.c;
 * docs/mixtures.md), below the scene-level test of the driven mixture (tests/test_species.sh):
 *
 * - every pair of species has the scene's eps_n: a head-on collision of a light and a heavy rod
 *   (1D) and of two heavy ones comes out with eps_n (spring_dashpot, hertz), momentum conserved;
 * - hertz's stiffness scales with the effective radius, sqrt(R_ij / R_11), and the time step
 *   resolves the shortest contact of all pairs;
 * - the random force heats each grain by d D / m_i: an ideal gas of two species gains kinetic
 *   energy in the ratio of the inverse masses (4 for masses 1:4), not equally;
 * - the species are dealt by the seed (counts exact, the same for the same seed);
 * - a mixture's ledger closes, and a state given as arrays with species is refused;
 * - a continuous radius distribution (uniform, lognormal): radii, masses, packing fraction, every
 *   pair's eps_n and the ledger;
 * - tangential laws and rotation (2D): an oblique collision of unequal discs with the pair's eps_t,
 *   momentum and angular momentum conserved, spins in the ratio of each grain's own moment of
 *   inertia; driven gases' ledgers. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "core/sim_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "sim_helpers.h"

/* Two rods on a long ring, no driving. */
static const char *pair_1d =
    "[system]\ndim = 1\nN = 2\nL = 1\n[placement]\nkind = uniform\nv0 = 0\n"
    "[driving]\nkind = none\n[species]\nradius = 1e-3, 2e-3\n"
    "mass = 1e-5, 4e-5\n";

/* The restitution of a head-on collision of grains 0 and 1 approaching at 0.2 m/s. */
static double collide(gr_sim *s, double *p_before, double *p_after)
{
    const double gap = s->rad[0] + s->rad[1] + 1e-4;
    s->x[0] = 0.3;
    s->x[1] = 0.3 + gap;
    s->vx[0] = 0.1;
    s->vx[1] = -0.1;
    *p_before = s->mass_i[0] * s->vx[0] + s->mass_i[1] * s->vx[1];
    int touched = 0;
    for (int k = 0; k < 200000; k++) {
        step(s, 1);
        const double g = s->x[1] - s->x[0];
        touched |= g < s->rad[0] + s->rad[1];
        if (touched && g > s->rad[0] + s->rad[1]) {
            break;
        }
    }
    ck_assert_msg(touched, "the rods never met");
    *p_after = s->mass_i[0] * s->vx[0] + s->mass_i[1] * s->vx[1];
    return (s->vx[1] - s->vx[0]) / 0.2;
}

START_TEST(pair_restitution)
{
    static const char *const laws[][2] = {{"model.normal=spring_dashpot", "model.eps_n=0.7"},
                                          {"model.normal=hertz", "model.eps_n=0.7"}};
    static const char *const fractions[] = {"species.fraction=0.5,0.5", "species.fraction=0,1"};
    for (int l = 0; l < 2; l++) {
        for (int f = 0; f < 2; f++) {
            const char *set[] = {laws[l][0], laws[l][1], fractions[f]};
            gr_scene sc;
            load(&sc, pair_1d, set, 3);
            gr_sim *s = create(&sc);
            double p0, p1;
            const double eps = collide(s, &p0, &p1);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s, %s: eps = %.5f, want 0.7", laws[l][0],
                          fractions[f], eps);
            ck_assert_msg(fabs(p1 - p0) < 1e-18, "momentum %g -> %g", p0, p1);
            gr_sim_free(s);
        }
    }
}
END_TEST

/* Tangential laws without history with species (2D, no rotation, kernels_poly.c): an oblique
 * collision of a light and a heavy disc keeps sum m_i v_i to rounding, and its tangential
 * relative velocity comes out scaled by the law's restitution for the pair's own coefficients
 * (gr_model.restitution_t of cc_pair, prepared with the pair's reduced mass: eps_t; the
 * lightest pair's damping on this pair gives 0.58). Then a driven gas's ledger closes with
 * the law's dissipation in its own column. */
static const char *pair_2d =
    "[system]\ndim = 2\nN = 2\nL = 0.2\n[placement]\nkind = uniform\nv0 = 0\n"
    "[driving]\nkind = none\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n"
    "[model]\nk_s = 5e4\neps_n = 0.7\ntangential = tangential_dashpot\neps_t = 0.5\n"
    "[integrator]\nsteps_per_contact = 100\n";

/* Grains 0 and 1 of s at impact parameter d/2, approaching at (0.1, 0) and (-0.1, 0) m/s, stepped
 * until they part; the unit normal at contact (from 0 to 1; straight flight until then) in n. */
static void oblique(gr_sim *s, double n[2])
{
    const double d = s->rad[0] + s->rad[1], b = 0.5 * d;
    s->x[0] = 0.05;
    s->y[0] = 0.1;
    s->x[1] = 0.05 + sqrt(d * d - b * b) + 1e-4;
    s->y[1] = 0.1 + b;
    s->vx[0] = 0.1;
    s->vx[1] = -0.1;
    s->vy[0] = s->vy[1] = 0.0;
    n[0] = sqrt(d * d - b * b) / d;
    n[1] = b / d;
    int touched = 0;
    for (int k = 0; k < 400000; k++) {
        step(s, 1);
        const double dx = s->x[1] - s->x[0], dy = s->y[1] - s->y[0];
        const double r = sqrt(dx * dx + dy * dy);
        touched |= r < d;
        if (touched && r > d) {
            break;
        }
    }
    ck_assert_msg(touched, "the discs never met");
}

/* 200 grains of pair_2d's species driven by the random force (rotating: spun up by omega0), 20000
 * steps: the ledger closes to 2e-3 of the energy moved; returns it. */
static gr_ledger driven_gas(bool rotating)
{
    const char *gas[] = {"system.N=200",       "system.L=0.1", "placement.v0=0.2",
                         "driving.kind=rfm",   "noise.D=1e-9", "model.rotation=true",
                         "placement.omega0=50"};
    gr_scene sc;
    load(&sc, pair_2d, gas, rotating ? 7 : 5);
    gr_sim *s = create(&sc);
    step(s, 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("driven gas%s: dissipated normal %.4g J, tangential %.4g J, rotational energy %.4g J, "
           "residual %.3g of the energy moved\n",
           rotating ? " (rotating)" : "", l.dissipated_normal, l.dissipated_tangential,
           l.rotational, res / moved);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    gr_sim_free(s);
    return l;
}

START_TEST(pair_tangential)
{
    gr_scene sc;
    load(&sc, pair_2d, NULL, 0);
    gr_sim *s = create(&sc);
    const double m0 = s->mass_i[0], m1 = s->mass_i[1];
    const double px0 = m0 * 0.1 - m1 * 0.1;
    double n[2];
    oblique(s, n);
    /* the normal and tangent at contact */
    const double nx = n[0], ny = n[1], tx = ny, ty = -nx;
    const double gn0 = -0.2 * nx, gt0 = -0.2 * tx; /* g = v_1 - v_0 = (-0.2, 0) */
    const double gx = s->vx[1] - s->vx[0], gy = s->vy[1] - s->vy[0];
    const double gt1 = gx * tx + gy * ty, gn1 = gx * nx + gy * ny;
    const int a = s->species[0], c1 = s->species[1];
    const gr_contact_coeffs *cp = &s->cc_pair[a * 2 + c1];
    const gr_model *tm = cp->tangential_model;
    const double want = tm->restitution_t(cp, cp->normal_model->impact(cp, -gn0), -gn0, fabs(gt0));
    printf("oblique pair (masses %g, %g kg): g_t ratio %.5f, the pair's law %.5f; g_n ratio "
           "%.5f\n",
           m0, m1, gt1 / gt0, want, -gn1 / gn0);
    ck_assert_msg(fabs(gt1 / gt0 - want) < 0.01, "g_t ratio %.5f, want %.5f", gt1 / gt0, want);
    const double px1 = m0 * s->vx[0] + m1 * s->vx[1], py1 = m0 * s->vy[0] + m1 * s->vy[1];
    ck_assert_msg(fabs(px1 - px0) < 1e-18 && fabs(py1) < 1e-18, "momentum (%g, %g) from %g", px1,
                  py1, px0);
    gr_sim_free(s);
    /* a driven gas: the ledger closes, the tangential law's dissipation in its column */
    const gr_ledger l = driven_gas(false);
    ck_assert(l.dissipated_tangential > 0.05 * l.dissipated_normal);
}
END_TEST

/* Rotation with species (2D, kernels_poly.c, step_poly.c): the same oblique collision with
 * rotating discs. The contact point splits |r_ij| as r_0 : r_1, so the spin torques a_i f_t are
 * in the ratio of the radii at every step and the spins end in the ratio
 * w_0 / w_1 = (r_0 / I_0) / (r_1 / I_1) = m_1 r_1 / (m_0 r_0) of each grain's own moment of
 * inertia q m_i r_i^2 (to rounding; one moment for both would give r_0 / r_1 instead); the
 * angular momentum sum m_i r_i x v_i + I_i w_i is conserved to rounding; the contact point's
 * tangential velocity comes out scaled by the law's restitution with rotation; the ledger of a
 * driven rotating gas closes with the spins' energy sum I_i w_i^2 / 2. */
START_TEST(pair_rotation)
{
    const char *rot[] = {"model.rotation=true"};
    gr_scene sc;
    load(&sc, pair_2d, rot, 1);
    gr_sim *s = create(&sc);
    const double d = s->rad[0] + s->rad[1];
    const double m[2] = {s->mass_i[0], s->mass_i[1]}, q = sc.contact.inertia_factor;
    const double I[2] = {q * m[0] * s->rad[0] * s->rad[0], q * m[1] * s->rad[1] * s->rad[1]};
    ck_assert(fabs(s->inertia_i[0] / I[0] - 1.0) < 1e-15 &&
              fabs(s->inertia_i[1] / I[1] - 1.0) < 1e-15);
    /* the angular momentum of the start (oblique's positions and velocities, no spin) */
    const double b = 0.5 * d; /* L = m (x v_y - y v_x): y = 0.1 and 0.1 + b, v_x = +-0.1 */
    const double L0 = m[0] * (-0.1 * 0.1) + m[1] * (-(0.1 + b) * -0.1);
    double n[2];
    oblique(s, n);
    const double nx = n[0], ny = n[1], tx = ny, ty = -nx;
    const double gn0 = -0.2 * nx, gt0 = -0.2 * tx;
    double L1 = 0.0;
    for (int i = 0; i < 2; i++) {
        L1 += m[i] * (s->x[i] * s->vy[i] - s->y[i] * s->vx[i]) + I[i] * s->omega[i];
    }
    const double dx = s->x[1] - s->x[0], dy = s->y[1] - s->y[0], r = sqrt(dx * dx + dy * dy);
    const double a0 = r * s->rad[0] / d, a1 = r - a0;
    const double gx = s->vx[1] - s->vx[0], gy = s->vy[1] - s->vy[0];
    const double gct = gx * tx + gy * ty + a0 * s->omega[0] + a1 * s->omega[1];
    const gr_contact_coeffs *cp = &s->cc_pair[s->species[0] * 2 + s->species[1]];
    const double want = cp->tangential_model->restitution_t(cp, cp->normal_model->impact(cp, -gn0),
                                                            -gn0, fabs(gt0));
    const double ratio = s->omega[0] / s->omega[1],
                 ratio_want = m[1] * s->rad[1] / (m[0] * s->rad[0]);
    printf("rotating pair: w_0 / w_1 = %.15g (m_1 r_1 / (m_0 r_0) = %.15g), angular momentum "
           "%.3g -> %.3g, contact point g_t ratio %.5f (the law: %.5f)\n",
           ratio, ratio_want, L0, L1, gct / gt0, want);
    ck_assert(s->omega[0] != 0.0);
    ck_assert_msg(fabs(ratio / ratio_want - 1.0) < 1e-9, "spin ratio %.15g, want %.15g", ratio,
                  ratio_want);
    ck_assert_msg(fabs(L1 - L0) < 1e-12 * fabs(L0), "angular momentum %.17g -> %.17g", L0, L1);
    ck_assert_msg(fabs(gct / gt0 - want) < 0.02, "g_ct ratio %.5f, want %.5f", gct / gt0, want);
    gr_sim_free(s);
    const gr_ledger l = driven_gas(true);
    ck_assert(l.rotational > 0.0 && l.dissipated_tangential > 0.0);
}
END_TEST

START_TEST(hertz_radius_and_dt)
{
    const char *set[] = {"model.normal=hertz", "model.k_h=1e6"};
    gr_scene sc;
    load(&sc, pair_1d, set, 2);
    gr_sim *s = create(&sc);
    ck_assert_int_eq(s->nsp, 2);
    const double r[2] = {1e-3, 2e-3}, R00 = 0.5 * r[0];
    double tmin = INFINITY;
    for (int a = 0; a < 2; a++) {
        for (int b = 0; b < 2; b++) {
            const gr_contact_coeffs *c = &s->cc_pair[2 * a + b];
            const double R = r[a] * r[b] / (r[a] + r[b]);
            ck_assert_msg(fabs(c->k_s / (1e6 * sqrt(R / R00)) - 1.0) < 1e-12, "k_h of pair %d%d", a,
                          b);
            ck_assert_msg(fabs(s->d_pair[2 * a + b] - (r[a] + r[b])) < 1e-18, "contact distance");
            tmin = fmin(tmin, c->t_c);
        }
    }
    ck_assert_msg(fabs(s->dt - tmin / sc.steps_per_contact) < 1e-12 * s->dt, "dt %g, t_c min %g",
                  s->dt, tmin);
    gr_sim_free(s);
}
END_TEST

/* An ideal gas (grains too small and too few per area to meet within the run) of two species,
 * masses 1:4: the kinetic energy each species gains is N_s d D t / m_s (times 1 - 1/N). */
START_TEST(heating_per_mass)
{
    static const char *gas =
        "[system]\ndim = 2\nN = 20000\nL = 1\n[placement]\nkind = uniform\nv0 = 0\n"
        "[species]\nradius = 1e-6, 1e-6\nmass = 1e-5, 4e-5\n[noise]\nD = 1e-10\n"
        "[integrator]\ndt = 1e-5\nforce_dt = true\n";
    gr_scene sc;
    load(&sc, gas, NULL, 0);
    gr_sim *s = create(&sc);
    const int steps = 200;
    step(s, steps);
    double ke[2] = {0.0, 0.0};
    int count[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        ke[s->species[i]] += 0.5 * s->mass_i[i] * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i]);
        count[s->species[i]]++;
    }
    ck_assert_int_eq(count[0], 10000);
    ck_assert_int_eq(count[1], 10000);
    const double t = steps * s->dt, sym = 1.0 - 1.0 / s->n;
    for (int a = 0; a < 2; a++) {
        const double want = count[a] * 2.0 * 1e-10 * t / (a ? 4e-5 : 1e-5) * sym;
        /* relative standard deviation sqrt(2 / (N_s d)) = 1 %: 5 of them */
        ck_assert_msg(fabs(ke[a] / want - 1.0) < 0.05, "species %d gained %g J, want %g J", a,
                      ke[a], want);
    }
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * l.injected, "ledger residual %g",
                  gr_ledger_residual(&l));
    gr_sim_free(s);
}
END_TEST

START_TEST(species_dealt_by_seed)
{
    static const char *mix = "[system]\ndim = 2\nN = 101\npacking_fraction = 0.2\n"
                             "[species]\nradius = 1e-3, 2e-3, 3e-3\ndensity = 10, 10, 10\n"
                             "fraction = 0.2, 0.3, 0.5\n";
    gr_scene sc;
    load(&sc, mix, NULL, 0);
    ck_assert_int_eq(sc.species_count[0], 20);
    ck_assert_int_eq(sc.species_count[1], 30);
    ck_assert_int_eq(sc.species_count[2], 51);
    /* the packing fraction counts the actual radii */
    const double area = M_PI * (20 * 1e-6 + 30 * 4e-6 + 51 * 9e-6);
    ck_assert_msg(fabs(area / (sc.L * sc.L) - 0.2) < 1e-12, "phi %g", area / (sc.L * sc.L));
    gr_sim *a = create(&sc), *b = create(&sc);
    ck_assert_msg(memcmp(a->species, b->species, sizeof(int) * 101) == 0, "same seed, same deal");
    ck_assert_msg(fabs(a->mass_i[0] - 10 * M_PI * a->rad[0] * a->rad[0]) < 1e-18, "density");
    step(a, 2000);
    gr_ledger l = gr_sim_ledger(a);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 0.01 * (l.injected + gr_ledger_dissipated(&l)),
                  "ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_params p;
    gr_scene_sim_params(&sc, &p);
    double x[1] = {0.1}, y[1] = {0.1}, v[1] = {0.0};
    gr_sim *c = NULL;
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_new_with_state(&p, 1, x, y, v, v, &c, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "carries no species") != NULL, "%s", err.message);
}
END_TEST

/* A radius distribution: radii within the bounds with the distribution's mean or median, masses
 * from the density, the packing fraction from the actual radii, and every pair of two grains of
 * different sizes keeps eps_n (the damping scaled to the pair's reduced mass, hertz's stiffness to
 * its effective radius); a 2D run's ledger closes. */
START_TEST(size_distribution)
{
    static const char *gas = "[system]\ndim = 2\nN = 4000\npacking_fraction = 0.3\n"
                             "[placement]\nkind = random\n[species]\nradius_min = 1e-3\n"
                             "radius_max = 3e-3\ndensity = 10\n";
    for (int kind = 0; kind < 2; kind++) {
        const char *set[] = {kind ? "species.distribution=lognormal"
                                  : "species.distribution=uniform",
                             "species.radius_median=2e-3", "species.radius_sigma=0.3"};
        gr_scene sc;
        load(&sc, gas, set, 3);
        gr_sim *s = create(&sc);
        double area = 0.0, mean = 0.0;
        int below = 0;
        for (int i = 0; i < s->n; i++) {
            ck_assert(s->rad[i] >= 1e-3 && s->rad[i] <= 3e-3);
            ck_assert(fabs(s->mass_i[i] / (10 * M_PI * s->rad[i] * s->rad[i]) - 1) < 1e-15);
            area += M_PI * s->rad[i] * s->rad[i];
            mean += s->rad[i] / s->n;
            below += s->rad[i] < 2e-3;
        }
        ck_assert_msg(fabs(area / (s->L * s->L) - 0.3) < 1e-12, "phi %g", area / (s->L * s->L));
        if (kind == 0) { /* uniform: mean 2 mm, standard error 9 um */
            ck_assert_msg(fabs(mean - 2e-3) < 5e-5, "mean radius %g", mean);
        } else { /* lognormal about 2 mm, truncated symmetrically in ln r: half below the median */
            ck_assert_msg(abs(below - 2000) < 200, "%d of 4000 below the median", below);
        }
        if (kind == 0) {
            step(s, 2000);
            gr_ledger l = gr_sim_ledger(s);
            ck_assert_msg(fabs(gr_ledger_residual(&l)) <
                              0.01 * (l.injected + gr_ledger_dissipated(&l)),
                          "ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
        }
        gr_sim_free(s);
    }
    static const char *pair = "[system]\ndim = 1\nN = 2\nL = 1\n[placement]\nkind = uniform\n"
                              "v0 = 0\n[driving]\nkind = none\n[species]\ndistribution = uniform\n"
                              "radius_min = 1e-3\nradius_max = 3e-3\ndensity = 10\n";
    static const char *const laws[] = {"model.normal=spring_dashpot", "model.normal=hertz"};
    for (int l = 0; l < 2; l++) {
        for (int seed = 1; seed <= 3; seed++) {
            char sd[32];
            snprintf(sd, sizeof sd, "run.seed=%d", seed);
            const char *set[] = {laws[l], "model.eps_n=0.7", sd};
            gr_scene sc;
            load(&sc, pair, set, 3);
            gr_sim *s = create(&sc);
            double p0, p1;
            const double eps = collide(s, &p0, &p1);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s, radii %g and %g m: eps = %.5f, want 0.7",
                          laws[l], s->rad[0], s->rad[1], eps);
            ck_assert_msg(fabs(p1 - p0) < 1e-13 * fabs(s->mass_i[0] * 0.1), "momentum %g -> %g", p0,
                          p1);
            gr_sim_free(s);
        }
    }
}
END_TEST

static Suite *species_suite(void)
{
    Suite *s = suite_create("species");
    TCase *t = tcase_create("pairs");
    tcase_set_timeout(t, 600);
    tcase_add_test(t, pair_tangential);
    tcase_add_test(t, pair_rotation);
    tcase_add_test(t, pair_restitution);
    tcase_add_test(t, hertz_radius_and_dt);
    tcase_add_test(t, heating_per_mass);
    tcase_add_test(t, species_dealt_by_seed);
    tcase_add_test(t, size_distribution);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(species_suite()); }
