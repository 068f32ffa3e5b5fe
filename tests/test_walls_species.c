/* Walls and gravity with species (issue 36; src/core/walls.c, docs/mixtures.md): every grain
 * touches a wall at its own radius, feels the wall's law prepared for its own mass and weighs
 * its own m_i g.
 *
 * - two grains of radii 1 and 2 mm, masses 1:4, dropped side by side onto a floor: each one's
 *   apex heights above its own touching point r_i fall by eps_n^2 per bounce (within
 *   0.06 (1 - eps_n), the one-species test's bound in tests/test_walls.c); the wall's damping for
 *   the mean mass or the largest radius would miss by far;
 * - a bed of two species at rest weighs sum_i m_i g on its floor;
 * - the ledger closes with walls, gravity, the random force and species (a 2D bed, a 1D column
 *   whose ring pair the walls take out with the pair's own distance);
 * - rotation: spinning grains of two species dropped on a floor with sliding friction end
 *   rolling with their own radius and moment of inertia;
 * - a checkpoint of a rotating bed continues bit for bit;
 * - the contact sublist, on for a bed of two sizes, changes no bit (2D and 3D);
 * - a radius distribution: each grain's wall contact scaled from the walls' reference to its own
 *   mass and radius (the bounces, the bed's weight, the ledgers); the event integrator's
 *   distribution between walls: tests/test_event_species.c. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"
#include "test_scenes.h"

#define EPS 0.7
#define G 9.81

static const char *pair_2d =
    "[system]\ndim = 2\nN = 2\nL = 0.04\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n"
    "[placement]\nkind = uniform\nv0 = 0\n[model]\nk_s = 5e4\neps_n = 0.7\n"
    "[driving]\nkind = none\n[boundary]\ny = walls\n[gravity]\ngy = -9.81\n"
    "[integrator]\nsteps_per_contact = 50\n";

/* The same pair from a radius distribution (seed 11: radii 2.0 and 1.1 mm, masses 6.3e-5 and
 * 1.9e-5 kg at 5 kg/m^2; with the walls' damping of the mean mass the light grain's apex ratio
 * misses eps_n^2 by 15 %). */
static const char *pair_dist =
    "[system]\ndim = 2\nN = 2\nL = 0.04\n[species]\ndistribution = uniform\nradius_min = 1e-3\n"
    "radius_max = 3e-3\ndensity = 5\n[placement]\nkind = uniform\nv0 = 0\n[model]\nk_s = 5e4\n"
    "eps_n = 0.7\n[driving]\nkind = none\n[boundary]\ny = walls\n[gravity]\ngy = -9.81\n"
    "[integrator]\nsteps_per_contact = 50\n[run]\nseed = 11\n";

/* The same pair of spheres (3D) on the floor z = 0 (issue 35). */
static const char *pair_3d =
    "[system]\ndim = 3\nN = 2\nL = 0.04\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n"
    "[placement]\nkind = cubic\nv0 = 0\n[model]\nk_s = 5e4\neps_n = 0.7\n"
    "[driving]\nkind = none\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n"
    "[integrator]\nsteps_per_contact = 50\n";

/* Both grains' apex heights above their own touching points, `want` bounces each (3D: spheres on
 * the floor z = 0). */
static void bounce_each(const char *text, const char *const *set, int n_set)
{
    gr_scene sc;
    load(&sc, text, set, n_set);
    gr_sim *s = create(&sc);
    ck_assert_ptr_nonnull(s->rad);
    ck_assert_msg(fabs(s->x[0] - s->x[1]) > s->rad[0] + s->rad[1] + 1e-3,
                  "the grains fall side by side (x %g, %g)", s->x[0], s->x[1]);
    const int want = quick() ? 3 : 5;
    const double *q = s->dim == 3 ? s->z : s->y, *vq = s->dim == 3 ? s->vz : s->vy;
    double h[2][6], v_prev[2] = {0.0, 0.0};
    int k[2] = {1, 1};
    for (int i = 0; i < 2; i++) {
        h[i][0] = q[i] - s->rad[i];
    }
    for (int64_t n = 0; n < 20000000 && (k[0] <= want || k[1] <= want); n++) {
        step(s, 1);
        for (int i = 0; i < 2; i++) {
            const double v = vq[i];
            if (v_prev[i] > 0.0 && v <= 0.0 && q[i] > s->rad[i] && k[i] <= want) {
                h[i][k[i]++] = q[i] + v * v / (2.0 * G) - s->rad[i];
            }
            v_prev[i] = v;
        }
    }
    ck_assert_msg(k[0] > want && k[1] > want, "apexes found: %d, %d", k[0] - 1, k[1] - 1);
    for (int i = 0; i < 2; i++) {
        double worst = 0.0;
        for (int b = 1; b <= want; b++) {
            worst = fmax(worst, fabs(h[i][b] / h[i][b - 1] / (EPS * EPS) - 1.0));
        }
        printf("%dD species %d (r = %g m, m = %g kg): max |h_k/h_(k-1)/eps^2 - 1| = %.2e over %d "
               "bounces\n",
               s->dim, s->species[i] + 1, s->rad[i], s->mass_i[i], worst, want);
        ck_assert_msg(worst < 0.06 * (1.0 - EPS), "grain %d: %g", i, worst);
    }
    gr_sim_free(s);
}

START_TEST(bounce_each_species) { bounce_each(_i ? pair_3d : pair_2d, NULL, 0); }
END_TEST

/* A radius distribution (walls.c, wall_coeffs: each grain's wall contact scaled from the walls'
 * reference to its own mass and radius), spring_dashpot and hertz: the same bounces. */
START_TEST(bounce_each_size)
{
    const char *hertz[] = {"model.normal=hertz", "model.k_h=1e7"};
    bounce_each(pair_dist, NULL, 0);
    bounce_each(pair_dist, hertz, 2);
}
END_TEST

/* A bed of two species (or of a radius distribution) settled on its floor weighs sum_i m_i g (the
 * floor's mean normal force); 3D: 60 spheres from a cubic lattice between walls at z = 0 and L. */
static void bed_weighs(int dim, const char *sizes)
{
    char bed[512];
    snprintf(bed, sizeof bed,
             "[system]\ndim = %d\nN = 60\nL = %s\n[species]\n%s[placement]\nkind = %s\n"
             "v0 = 0\n[model]\nk_s = 5e3\neps_n = 0.3\n[driving]\nkind = none\n[boundary]\n"
             "%s = walls\n[gravity]\n%s = -9.81\n",
             dim, dim == 3 ? "0.03" : "0.04", sizes, dim == 3 ? "cubic" : "uniform",
             dim == 3 ? "z" : "y", dim == 3 ? "gz" : "gy");
    gr_scene sc;
    load(&sc, bed, NULL, 0);
    gr_sim *s = create(&sc);
    double weight = 0.0;
    for (int i = 0; i < s->n; i++) {
        weight += s->mass_i[i] * G;
    }
    double fw[6];
    settled_wall_forces(s, 0.3, 0.05, fw); /* fallen and settled, then 0.05 s */
    const double floor_f = fw[dim == 3 ? 4 : 2];
    printf("%dD bed (%s) at rest: floor %.8g N, sum m_i g = %.8g N (ratio - 1 = %.2e)\n", dim,
           s->cc_pair ? "two species" : "a radius distribution", floor_f, weight,
           floor_f / weight - 1.0);
    ck_assert_msg(fabs(floor_f / weight - 1.0) < 1e-3, "floor %g, weight %g", floor_f, weight);
    gr_sim_free(s);
}

START_TEST(bed_weighs_each_mass)
{
    const char *two = "radius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\nfraction = 0.5, 0.5\n";
    bed_weighs(2, two);
    bed_weighs(2, "distribution = uniform\nradius_min = 1e-3\nradius_max = 2e-3\ndensity = 5\n");
    bed_weighs(3, two);
}
END_TEST

/* The ledger: injected - dissipated = change of kinetic + elastic + potential (sum m_i g q_i). */
static void ledger_closes(const char *text, const char *const *set, int n_set, int64_t steps)
{
    gr_scene sc;
    load(&sc, text, set, n_set);
    gr_sim *s = create(&sc);
    step(s, steps);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("ledger (%dD, species, walls, gravity, noise): injected %.4g J, dissipated %.4g J, "
           "potential %.4g J, residual %.3g of the energy moved\n",
           s->dim, l.injected, gr_ledger_dissipated(&l), l.potential, res / moved);
    ck_assert(l.dissipated_normal > 0.0 && l.potential != 0.0 && l.injected > 0.0);
    ck_assert_msg(fabs(res) < 1e-3 * moved, "residual %g of %g moved", res, moved);
    gr_sim_free(s);
}

START_TEST(ledger_species_walls)
{
    const char *bed =
        "[system]\ndim = 2\nN = 200\nL = 0.1\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, "
        "4e-5\n[placement]\nkind = uniform\nv0 = 0.2\n[model]\nk_s = 5e4\neps_n = 0.7\n"
        "[noise]\nD = 1e-9\n[boundary]\ny = walls\n[gravity]\ngy = -9.81\n";
    const char *column =
        "[system]\ndim = 1\nN = 30\nL = 0.15\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, "
        "4e-5\n[placement]\nkind = uniform\nv0 = 0.3\n[model]\nk_s = 5e4\neps_n = 0.8\n"
        "[noise]\nD = 1e-9\n[boundary]\nx = walls\n[gravity]\ngx = -9.81\n";
    ledger_closes(bed, NULL, 0, quick() ? 15000 : 40000);
    ledger_closes(column, NULL, 0, quick() ? 15000 : 40000);
    /* the history law (tangential_spring) at the pairs and the walls, rotating: the springs'
     * energy in the elastic total, the slips' and ended contacts' losses booked */
    const char *spring[] = {"model.tangential=tangential_spring", "model.mu=0.3",
                            "model.rotation=true", "placement.omega0=100"};
    ledger_closes(bed, spring, 4, quick() ? 15000 : 40000);
    /* a radius distribution (2D bed, 1D column) */
    const char *dist[] = {
        "species.radius=",         "species.mass=",           "species.distribution=uniform",
        "species.radius_min=1e-3", "species.radius_max=2e-3", "species.density=5"};
    ledger_closes(bed, dist, 6, quick() ? 15000 : 40000);
    dist[5] = "species.density=0.007"; /* kg/m in 1D: masses near the lists' */
    ledger_closes(column, dist, 6, quick() ? 15000 : 40000);
    /* 3D: spheres between walls at z = 0 and L (and x) under gravity, with sliding friction at the
     * walls and between the grains, rotating */
    const char *box3 =
        "[system]\ndim = 3\nN = 150\nL = 0.04\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, "
        "4e-5\n[placement]\nkind = cubic\nv0 = 0.2\nomega0 = 100\n[model]\nk_s = 5e4\n"
        "eps_n = 0.7\ntangential = sliding_friction\nmu = 0.3\nrotation = true\n"
        "[noise]\nD = 1e-9\n[boundary]\nz = walls\nx = walls\n[gravity]\ngz = -9.81\n";
    ledger_closes(box3, NULL, 0, quick() ? 12000 : 20000);
}
END_TEST

/* Rotation at a wall (sliding friction): two spinning grains of radii 1 and 2 mm dropped side
 * by side on a floor end rolling, v_x = -w r_i with each grain's own radius, at the velocities of
 * a disc whose moment of inertia is q m_i r_i^2 (v_x = -r_i w0 q / (1 + q), w = w0 q / (1 + q));
 * the ledger closes with the spins' energy. */
START_TEST(spinning_grains_roll)
{
    const char *set[] = {"model.tangential=sliding_friction", "model.rotation=true", "model.mu=0",
                         "boundary.mu=0.5", "model.eps_n=0.9"};
    gr_scene sc;
    load(&sc, pair_2d, set, 5);
    gr_sim *s = create(&sc);
    const double w0 = 200.0, q = sc.contact.inertia_factor;
    for (int i = 0; i < 2; i++) {
        s->omega[i] = w0;
        s->initial_energy += 0.5 * s->inertia_i[i] * w0 * w0;
    }
    step(s, (int64_t)(0.2 / gr_sim_dt(s)));
    const gr_ledger l = gr_sim_ledger(s);
    const double res = gr_ledger_residual(&l) / gr_ledger_dissipated(&l);
    for (int i = 0; i < 2; i++) {
        const double r = s->rad[i], vx_th = -r * w0 * q / (1.0 + q), w_th = w0 * q / (1.0 + q);
        printf("spinning grain r = %g m: v_x = %.6g m/s (theory %.6g), w = %.6g rad/s (theory "
               "%.6g), v_x + w r = %.3g m/s\n",
               r, s->vx[i], vx_th, s->omega[i], w_th, s->vx[i] + s->omega[i] * r);
        ck_assert_msg(fabs(s->vx[i] / vx_th - 1.0) < 1e-3 && fabs(s->omega[i] / w_th - 1.0) < 1e-3,
                      "grain %d: vx %g w %g", i, s->vx[i], s->omega[i]);
        ck_assert_msg(fabs(s->vx[i] + s->omega[i] * r) < 1e-6 * r * w0, "still slipping");
    }
    printf("ledger: dissipated friction %.4g J, residual %.3g of the dissipation\n",
           l.dissipated_friction, res);
    ck_assert(l.dissipated_friction > 0.0 && fabs(res) < 1e-3);
    gr_sim_free(s);
}
END_TEST

/* A checkpoint of a rotating two-species bed under gravity with sliding friction, or with the
 * history law (the pairs' and the walls' springs carried in the state), continues bit for bit. */
START_TEST(restart_exact)
{
    static const char *const laws[] = {"model.tangential=sliding_friction",
                                       "model.tangential=tangential_spring"};
    for (int k = 0; k < 2; k++) {
        const char *set[] = {
            "system.N=40",  "system.L=0.05",       "placement.v0=0.2",     laws[k],
            "model.mu=0.3", "model.rotation=true", "placement.omega0=100", "driving.kind=rfm",
            "noise.D=1e-9"};
        gr_scene sc;
        load(&sc, pair_2d, set, 9);
        assert_restart_exact(&sc, 6000, 2000);
    }
}
END_TEST

/* The contact sublist (core/sublist.c) on a bed of two sizes, discs (_i = 0, a history spring with
 * rotation) and spheres (_i = 1): a mixture's pair is kept within r_i + r_j + 0.02 d. The engine
 * turns it on once the list has lasted 100 steps (auto), GRANULE_SUBLIST=on at every build, off
 * never; the three runs end in the same state bit for bit (tests/test_sublist.sh: the files). */
START_TEST(sublist_on_a_mixture_bed)
{
    static const char *bed[2] = {
        "[system]\ndim = 2\nN = 100\nL = 0.05\n[species]\nradius = 1.5e-3, 2.5e-3\n"
        "density = 5, 5\nfraction = 0.7, 0.3\n[placement]\nkind = uniform\nv0 = 0.05\n"
        "[model]\nk_s = 5e4\neps_n = 0.8\ntangential = tangential_spring\nrotation = true\n"
        "[driving]\nkind = none\n[boundary]\ny = walls\nvibrate = y\namplitude = 5e-4\n"
        "frequency = 50\n[gravity]\ngy = -9.81\n",
        "[system]\ndim = 3\nN = 200\nL = 0.02\n[species]\nradius = 1e-3, 1.5e-3\n"
        "density = 2500, 2500\nfraction = 0.7, 0.3\n[placement]\nkind = cubic\nv0 = 0.05\n"
        "[model]\nk_s = 5e4\neps_n = 0.8\n[driving]\nkind = none\n[boundary]\nz = walls\n"
        "vibrate = z\namplitude = 5e-4\nfrequency = 50\n[gravity]\ngz = -9.81\n"};
    const char *modes[] = {"off", "auto", "on"};
    gr_sim *sims[3];
    int64_t rebuilds[3];
    for (int m = 0; m < 3; m++) {
        setenv("GRANULE_SUBLIST", modes[m], 1);
        gr_scene sc;
        load(&sc, bed[_i], NULL, 0);
        sims[m] = create(&sc);
        step(sims[m], quick() ? 10000 : 20000);
        rebuilds[m] = gr_sim_sublist_rebuilds(sims[m]);
    }
    unsetenv("GRANULE_SUBLIST");
    printf("%dD mixture bed, sublist rebuilds: off %lld, auto %lld, on %lld\n", _i + 2,
           (long long)rebuilds[0], (long long)rebuilds[1], (long long)rebuilds[2]);
    ck_assert_int_eq(rebuilds[0], 0);
    ck_assert_int_gt(rebuilds[1], 0);
    ck_assert_int_ge(rebuilds[2], rebuilds[1]);
    for (int m = 1; m < 3; m++) {
        assert_same_state(sims[0], sims[m]);
    }
    for (int m = 0; m < 3; m++) {
        gr_sim_free(sims[m]);
    }
}
END_TEST

static Suite *walls_species_suite(void)
{
    Suite *s = suite_create("walls_species");
    TCase *t = tcase_create("walls");
    tcase_set_timeout(t, 600);
    tcase_add_loop_test(t, bounce_each_species, 0, 2);
    tcase_add_test(t, bounce_each_size);
    tcase_add_test(t, bed_weighs_each_mass);
    tcase_add_test(t, ledger_species_walls);
    tcase_add_test(t, spinning_grains_roll);
    tcase_add_test(t, restart_exact);
    tcase_add_loop_test(t, sublist_on_a_mixture_bed, 0, 2);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(walls_species_suite()); }
