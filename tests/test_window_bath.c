/* The Langevin bath with the event-driven and hybrid integrators ([driving] kind = langevin,
 * [integrator] kind = event or hybrid; event.c and hybrid.c, bath_window; docs/event-driven.md,
 * "Langevin bath", docs/hybrid.md): free flight is ballistic, collisions are exact events (event)
 * or soft contacts stepped by the child (hybrid), and every window's end applies the exact
 * Ornstein-Uhlenbeck step of the window to each velocity.
 *
 * - an ideal gas (no collisions): T after k windows has the OU expectation T0 a^(2k) + T_bath
 *   (1 - a^(2k)), a = e^(-kick_interval/tau), against the exact standard error of the sample (a
 *   decay per window of a instead of a^2, or the bath applied at the middle of a window as well
 *   as at its end, misses by many errors);
 * - an elastic gas of hard discs and spheres (1D, 2D, 3D), at about 5 collisions per grain per
 *   drag time, settles at T_bath / dim per component;
 *   a binary mixture (masses 1:4) at m_1 T_bath / dim per component for every grain's m v^2;
 *   perfectly rough elastic discs (beta = 1), which the bath does not spin, at q r^2 <w^2> =
 *   T_bath / dim through their collisions;
 * - the hybrid: the ideal gas's OU law, equipartition of elastic soft discs, its ledger to the
 *   springs' velocity-Verlet error;
 * - the ledger: injected (bath) - dissipated (collisions + drag) = change of kinetic energy, to
 *   rounding (the event integrator's books are exact);
 * - a restart is exact (event: 3D, walls and gravity; hybrid: 2D);
 * - free_flight (the random force's) is ignored under the bath with a warning: exact and kicks
 *   give the same run.
 *
 * Every random choice has a fixed seed; statistical bounds are 4-5 standard errors. The quick mode
 * (GRANULE_TEST_QUICK, the sanitizer pass) runs the equipartition scenes for one tau and checks
 * their ledgers only. */
#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "integrators/hybrid/hybrid.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

/* hard discs (spheres, rods), elastic unless a --set says otherwise, in the bath */
#define BATH "[driving]\nkind = langevin\nT_bath = 0.01\ntau = 0.01\n"
#define BATH_EVENT                                                                                 \
    "[model]\nnormal = hard_sphere\neps_n = 1\neps_t = 1\n[integrator]\nkind = event\n"            \
    "kick_interval = 1e-3\n" BATH
/* soft elastic discs (the hybrid's default window, 1e-4 s rounded to whole steps) */
#define BATH_HYBRID "[model]\nk_s = 5e3\neps_n = 1\n[integrator]\nkind = hybrid\n" BATH

/* (1/N) sum_i m_i v_ic^2 / m_ref over component c (m_ref <= 0: the scene's M; one species: the
 * mean of v_c^2) */
static double component_mv2(const gr_sim *sim, int c, double m_ref)
{
    gr_particles p = gr_sim_particles(sim);
    m_ref = m_ref > 0.0 ? m_ref : sim->mass;
    const double *v = c == 0 ? p.vx : c == 1 ? p.vy : p.vz;
    double sq = 0.0;
    for (int i = 0; i < p.n; i++) {
        const double m = sim->mass_i ? sim->mass_i[i] : sim->mass;
        sq += m / m_ref * v[i] * v[i];
    }
    return sq / p.n;
}

static int64_t steps_for(const gr_sim *sim, double t)
{
    return (int64_t)llround(t / gr_sim_dt(sim));
}

/* ---- the ideal gas: the OU process sampled once per window ---------------------------------- */

static void check_ideal_gas(const char *integrator)
{
    const double T_bath = 0.01, tau = 0.01, w = 1e-3;
    const char *event = "[system]\ndim = 2\nN = 4000\nL = 0.2\nradius = 1e-8\n[placement]\nkind = "
                        "uniform\nv0 = 1\n[run]\nseed = 5\n" BATH_EVENT;
    /* windows of 1 ms = 10 steps of 0.1 ms */
    const char *hybrid = "[system]\ndim = 2\nN = 4000\nL = 0.2\nradius = 1e-8\n[placement]\nkind = "
                         "uniform\nv0 = 1\n[run]\nseed = 5\n" BATH_HYBRID;
    const char *window[] = {"integrator.dt=1e-4", "integrator.kick_interval=1e-3", "model.k_s=50"};
    gr_scene s;
    const bool ev = !strcmp(integrator, "event");
    load(&s, ev ? event : hybrid, ev ? NULL : window, ev ? 0 : 3);
    gr_sim *sim = create(&s);
    const int n = sim->n;
    double *v0 = malloc(sizeof(double) * 2 * (size_t)n);
    ck_assert_ptr_nonnull(v0);
    memcpy(v0, sim->vx, sizeof(double) * (size_t)n);
    memcpy(v0 + n, sim->vy, sizeof(double) * (size_t)n);
    double T0 = 0.0;
    for (int i = 0; i < 2 * n; i++) {
        T0 += v0[i] * v0[i] / n; /* the raw <|v|^2>: the bath does not conserve momentum */
    }
    const int windows[] = {5, 10, 20, 50}; /* t = tau/2 ... 5 tau */
    int64_t done = 0;
    for (int q = 0; q < 4; q++) {
        /* half a window past the k-th window end: exactly k bath steps, whatever the rounding */
        const int64_t at = steps_for(sim, (windows[q] + 0.5) * w);
        step(sim, at - done);
        done = at;
        /* the event integrator's windows run to their ends, k of them; the hybrid's last one is
         * cut at the call's end, and that partial window gets the OU step of its own length */
        const double t_ou = ev ? windows[q] * w : (double)at * gr_sim_dt(sim);
        const double a2k = exp(-2.0 * t_ou / tau), s2 = T_bath / 2.0 * (1.0 - a2k);
        const double expect = T0 * a2k + T_bath * (1.0 - a2k);
        double var = 0.0;
        for (int i = 0; i < 2 * n; i++) {
            var += 4.0 * a2k * v0[i] * v0[i] * s2 + 2.0 * s2 * s2;
        }
        const double se = sqrt(var) / n,
                     T = component_mv2(sim, 0, sim->mass) + component_mv2(sim, 1, sim->mass);
        VERBOSE("%s, %d windows: T = %.6g, expected %.6g +- %.2g (z = %.2f)\n", integrator,
                windows[q], T, expect, se, (T - expect) / se);
        ck_assert_msg(fabs(T - expect) < 5.0 * se,
                      "after %d windows: <|v|^2> = %g, the OU process gives %g +- %g", windows[q],
                      T, expect, se);
    }
    ck_assert_msg(gr_sim_collisions(sim) == 0, "%lld collisions: not an ideal gas",
                  (long long)gr_sim_collisions(sim));
    gr_ledger l = gr_sim_ledger(sim);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    ck_assert(l.dissipated_drag > 0.0 && l.injected > 0.0);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    free(v0);
    gr_sim_free(sim);
}

START_TEST(ideal_gas_windows)
{
    check_ideal_gas("event");
    check_ideal_gas("hybrid");
}
END_TEST

/* ---- equipartition ------------------------------------------------------------------------- */

/* After 10 tau, 40 blocks of 2 samples one tau apart; every component's raw <m v^2> / m_ref
 * against expect (per component; the mean velocity is not subtracted: the bath does not conserve
 * momentum, and the stationary state is the product Maxwellian). */
static void check_bath_level(const char *text, double m_ref, double expect, const char *what,
                             double ledger_tol)
{
    /* a hot bath (T_bath = 1 m^2/s^2) with a slow drag: about 5 collisions per grain per tau, so
     * the collisions, not the bath alone, mix the components */
    const double tau = 0.05;
    const char *set[] = {"driving.T_bath=1", "driving.tau=0.05"};
    gr_scene s;
    load(&s, text, set, 2);
    gr_sim *sim = create(&s);
    const int dim = sim->dim;
    const int64_t per_tau = steps_for(sim, tau);
    if (quick()) { /* the sanitizer pass: the code paths and the ledger, not the statistics */
        step(sim, per_tau);
        gr_ledger l = gr_sim_ledger(sim);
        const double moved = l.injected + gr_ledger_dissipated(&l);
        ck_assert(l.dissipated_drag > 0.0 && gr_sim_collisions(sim) > 0);
        ck_assert_msg(fabs(gr_ledger_residual(&l)) < ledger_tol * moved,
                      "%s: residual %g of %g moved", what, gr_ledger_residual(&l), moved);
        gr_sim_free(sim);
        return;
    }
    step(sim, 10 * per_tau);
    enum { BLOCKS = 40, PER_BLOCK = 2 };
    double block[3][BLOCKS];
    for (int b = 0; b < BLOCKS; b++) {
        block[0][b] = block[1][b] = block[2][b] = 0.0;
        for (int k = 0; k < PER_BLOCK; k++) {
            step(sim, per_tau);
            for (int c = 0; c < dim; c++) {
                block[c][b] += component_mv2(sim, c, m_ref) / PER_BLOCK;
            }
        }
    }
    for (int c = 0; c < dim; c++) {
        double se;
        const double mean = mean_se(block[c], BLOCKS, &se);
        VERBOSE("%s, component %d: %.6g +- %.2g, expected %.6g (z = %.2f)\n", what, c, mean, se,
                expect, (mean - expect) / se);
        ck_assert_msg(se < 0.01 * mean, "%s: the block error %g is too large for the test", what,
                      se);
        ck_assert_msg(fabs(mean - expect) < 4.0 * se, "%s, component %d: %g +- %g, expected %g",
                      what, c, mean, se, expect);
    }
    VERBOSE("%s: %.1f collisions per grain and tau\n", what,
            (double)gr_sim_collisions(sim) / sim->n / (10 + BLOCKS * PER_BLOCK));
    ck_assert_msg(gr_sim_collisions(sim) > 2 * sim->n * (10 + BLOCKS * PER_BLOCK),
                  "%s: %lld collisions: fewer than 2 per grain and tau", what,
                  (long long)gr_sim_collisions(sim));
    gr_ledger l = gr_sim_ledger(sim);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < ledger_tol * moved, "%s: residual %g of %g moved",
                  what, gr_ledger_residual(&l), moved);
    gr_sim_free(sim);
}

static void check_equipartition(int dim)
{
    char text[800];
    snprintf(text, sizeof text,
             "[system]\ndim = %d\nN = %d\n%s\n[placement]\nkind = %s\n[run]\nseed = 3\n" BATH_EVENT,
             dim,
             dim == 1   ? 400
             : dim == 2 ? 1000
                        : 512,
             dim >= 2 ? "packing_fraction = 0.15" : "reduced_length = 0.4",
             dim >= 2 ? "random" : "uniform");
    char what[32];
    snprintf(what, sizeof what, "%dD elastic gas", dim);
    check_bath_level(text, 0.0 /* one species: m / M = 1 */, 1.0 / dim, what, 1e-12);
}

START_TEST(equipartition_1d) { check_equipartition(1); }
END_TEST

START_TEST(equipartition_2d) { check_equipartition(2); }
END_TEST

START_TEST(equipartition_3d) { check_equipartition(3); }
END_TEST

/* The hybrid: elastic soft discs (k_s = 5e3 N/m; the ledger to the springs' velocity-Verlet
 * error, docs/integrator.md) */
START_TEST(equipartition_hybrid)
{
    const char *text = "[system]\ndim = 2\nN = 1000\npacking_fraction = 0.15\n[placement]\nkind = "
                       "random\n[run]\nseed = 3\n" BATH_HYBRID;
    check_bath_level(text, 0.0, 1.0 / 2.0, "2D elastic soft discs, hybrid", 1e-3);
}
END_TEST

/* Two species of discs, masses 1:4 (the same radius): every grain at the first species' energy per
 * degree of freedom, m_i <v_ic^2> = m_1 T_bath / dim (docs/mixtures.md); one kick for both masses
 * would leave the heavy ones at a quarter of it. */
START_TEST(mixture_equipartition)
{
    const char *text =
        "[system]\ndim = 2\nN = 800\npacking_fraction = 0.15\n[placement]\nkind = random\n"
        "[species]\nradius = 1.5e-3, 1.5e-3\nmass = 1e-5, 4e-5\nfraction = 0.5, 0.5\n[run]\n"
        "seed = 4\n" BATH_EVENT;
    check_bath_level(text, 1e-5, 1.0 / 2.0, "2D mixture 1:4", 1e-12);
}
END_TEST

/* Perfectly rough elastic discs (eps_n = 1, beta = 1: Walton's rule conserves energy) in the bath:
 * the bath acts on the translations only, the collisions share the energy with the spins, and the
 * stationary state is the Gibbs one, k_B T per degree of freedom for the spins too: q M r^2
 * <w^2> = M T_bath / dim (q = 1/2). */
START_TEST(rough_spins_equipartition)
{
    const char *text =
        "[system]\ndim = 2\nN = 1000\npacking_fraction = 0.15\n[placement]\nkind = random\n"
        "[run]\nseed = 6\n" BATH_EVENT;
    const char *set[] = {"model.rotation=true", "model.beta=1", "driving.T_bath=1",
                         "driving.tau=0.05"};
    gr_scene s;
    load(&s, text, set, 4);
    gr_sim *sim = create(&s);
    ck_assert_ptr_nonnull(sim->omega);
    const double tau = 0.05, r = 0.5 * sim->d, q = sim->cc.q;
    const int64_t per_tau = steps_for(sim, tau);
    if (quick()) { /* the sanitizer pass: the code path, not the statistics */
        step(sim, per_tau);
        ck_assert(sim->diss_drag > 0.0 && gr_sim_collisions(sim) > 0);
        gr_sim_free(sim);
        return;
    }
    step(sim, 10 * per_tau);
    enum { BLOCKS = 40, PER_BLOCK = 2 };
    double block[BLOCKS];
    for (int b = 0; b < BLOCKS; b++) {
        block[b] = 0.0;
        for (int k = 0; k < PER_BLOCK; k++) {
            step(sim, per_tau);
            double w2 = 0.0;
            for (int i = 0; i < sim->n; i++) {
                w2 += sim->omega[i] * sim->omega[i];
            }
            block[b] += q * r * r * w2 / sim->n / PER_BLOCK;
        }
    }
    double se;
    const double mean = mean_se(block, BLOCKS, &se), expect = 1.0 / 2.0;
    VERBOSE("rough discs: q r^2 <w^2> = %.6g +- %.2g, expected %.6g (z = %.2f)\n", mean, se, expect,
            (mean - expect) / se);
    ck_assert_msg(se < 0.01 * mean, "the block error %g is too large for the test", se);
    ck_assert_msg(fabs(mean - expect) < 4.0 * se,
                  "rough discs: q r^2 <w^2> = %g +- %g, the bath's T_bath / dim is %g", mean, se,
                  expect);
    gr_ledger l = gr_sim_ledger(sim);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    gr_sim_free(sim);
}
END_TEST

/* ---- the ledger with inelastic collisions --------------------------------------------------- */

START_TEST(ledger_inelastic)
{
    const char *text = "[system]\ndim = 2\nN = 600\npacking_fraction = 0.3\n[placement]\nkind = "
                       "random\n" BATH_EVENT;
    const char *eps[] = {"model.eps_n=0.6"};
    gr_scene s;
    load(&s, text, eps, 1);
    gr_sim *sim = create(&s);
    step(sim, steps_for(sim, 0.05));
    gr_ledger l = gr_sim_ledger(sim);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    VERBOSE("inelastic: injected %g, normal %g, drag %g, residual %g, T %g\n", l.injected,
            l.dissipated_normal, l.dissipated_drag, gr_ledger_residual(&l),
            gr_sim_temperature(sim));
    ck_assert(l.dissipated_normal > 0.01 * moved && l.dissipated_drag > 0.01 * moved);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    gr_sim_free(sim);
}
END_TEST

/* ---- reproducibility ------------------------------------------------------------------------ */

START_TEST(restart_3d_walls)
{
    const char *text = "[system]\ndim = 3\nN = 300\npacking_fraction = 0.1\n[placement]\nkind = "
                       "random\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n" BATH_EVENT;
    const char *eps[] = {"model.eps_n=0.8"};
    gr_scene s;
    load(&s, text, eps, 1);
    gr_sim *a = create(&s);
    const int64_t total = steps_for(a, 0.02);
    gr_sim_free(a);
    assert_restart_exact(&s, total, total / 3 + 7); /* (the event integrator runs on one thread) */
    a = create(&s);
    step(a, total);
    ck_assert(a->diss_drag > 0.0 && a->injected > 0.0); /* the bath acted */
    gr_sim_free(a);
}
END_TEST

START_TEST(restart_hybrid)
{
    const char *text = "[system]\ndim = 2\nN = 600\npacking_fraction = 0.3\n[placement]\nkind = "
                       "random\n[run]\nseed = 2\n" BATH_HYBRID;
    const char *eps[] = {"model.eps_n=0.7"};
    gr_scene s;
    load(&s, text, eps, 1);
    gr_sim *a = create(&s);
    /* saved at a window's end (a call that ends inside one cuts it, as the run driver never does:
     * gr_integrator_type.call_steps) */
    const int64_t q = gr_hybrid_window_steps(a), total = steps_for(a, 0.01) / q * q;
    gr_sim_free(a);
    assert_restart_exact(&s, total, total / 3 / q * q);
    a = create(&s);
    step(a, total);
    ck_assert(a->diss_drag > 0.0 && a->injected > 0.0 && a->diss_n > 0.0);
    gr_ledger l = gr_sim_ledger(a);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-3 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    gr_sim_free(a);
}
END_TEST

/* ---- refusals -------------------------------------------------------------------------------- */

/* free_flight belongs to the random force: under the bath it is ignored with a warning, and a
 * scene that gives exact runs as one that gives kicks, bit for bit */
START_TEST(free_flight_ignored)
{
    const char *ev = "[system]\ndim = 2\nN = 200\npacking_fraction = 0.2\n[placement]\nkind = "
                     "random\n[model]\nnormal = hard_sphere\neps_n = 0.8\n[integrator]\nkind = "
                     "event\nfree_flight = exact\n[driving]\nkind = langevin\n";
    const char *kicks[] = {"integrator.free_flight=kicks"};
    gr_scene a, b;
    load(&a, ev, NULL, 0);
    load(&b, ev, kicks, 1);
    ck_assert_msg(strstr(a.warnings, "[integrator] free_flight is ignored") &&
                      strstr(b.warnings, "[integrator] free_flight is ignored"),
                  "%s", a.warnings);
    gr_sim *sa = create(&a), *sb = create(&b);
    step(sa, 2000);
    step(sb, 2000);
    assert_same_state(sa, sb);
    ck_assert(sa->diss_drag > 0.0);
    gr_sim_free(sa);
    gr_sim_free(sb);
}
END_TEST

static Suite *window_bath_suite(void)
{
    Suite *s = suite_create("window_bath");
    TCase *unit = tcase_create("unit");
    tcase_add_test(unit, free_flight_ignored);
    tcase_add_test(unit, restart_3d_walls);
    tcase_add_test(unit, restart_hybrid);
    tcase_add_test(unit, ledger_inelastic);
    suite_add_tcase(s, unit);
    TCase *phys = tcase_create("physics");
    tcase_set_timeout(phys, 600);
    tcase_add_test(phys, ideal_gas_windows);
    tcase_add_test(phys, equipartition_1d);
    tcase_add_test(phys, equipartition_2d);
    tcase_add_test(phys, equipartition_3d);
    tcase_add_test(phys, equipartition_hybrid);
    tcase_add_test(phys, mixture_equipartition);
    tcase_add_test(phys, rough_spins_equipartition);
    suite_add_tcase(s, phys);
    return s;
}

int main(void) { return gr_test_run(window_bath_suite()); }
