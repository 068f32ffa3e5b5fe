/* Tests of the driving types ([driving] kind, granule/driving.h, docs/systems-driving.md):
 *
 * - langevin: an elastic gas settles at the bath temperature, T_bath / dim per component
 *   (equipartition; 3D, 2D and 1D, with collisions), within its block error;
 * - langevin: an ideal gas (no contacts) relaxes as E[T(t)] = T0 a^(2k) + T_bath (1 - 1/N)(1 - a^(2k)),
 *   a^(2k) = e^(-2t/tau), against the exact standard error of the finite sample;
 * - the ledger: injected (bath) - dissipated (contacts + drag) = change of kinetic + elastic energy,
 *   to rounding for the ideal gas and to the velocity-Verlet spring error with inelastic contacts;
 * - thread-count invariance and exact restarts of a Langevin run (2D, and 3D with walls and
 *   gravity);
 * - none: an inelastic gas cools (verlet, event, hybrid), the same run bit for bit as rfm with D = 0;
 * - rfm: a scene that names [driving] kind = rfm is bit-identical to one that does not;
 * - an integrator without the drag capability refuses langevin by name (every registered one has
 *   it: the event and hybrid integrators' bath is test_window_bath.c).
 *
 * Every random choice has a fixed seed; statistical bounds are 4-5 standard errors. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/mean_field.h"
#include "core/sim_internal.h"
#include "granule/scene.h"
#include "scene/scene_json.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

/* Per-component temperature (1/N) sum (v_c - <v_c>)^2. */
static double component_T(const gr_sim *sim, int c)
{
    gr_particles p = gr_sim_particles(sim);
    const double *v = c == 0 ? p.vx : c == 1 ? p.vy : p.vz;
    double mean = 0.0, sq = 0.0;
    for (int i = 0; i < p.n; i++) {
        mean += v[i];
    }
    mean /= p.n;
    for (int i = 0; i < p.n; i++) {
        sq += (v[i] - mean) * (v[i] - mean);
    }
    return sq / p.n;
}

/* ---- equipartition with the bath ------------------------------------------------------------ */

/* An elastic gas (eps_n = 1, soft springs) in a Langevin bath: after 10 tau every component's
 * temperature averages T_bath / dim (1 - 1/N) (the mean velocity is subtracted; with
 * momentum-conserving collisions and independent baths the stationary state is the product
 * Maxwellian). Block averages of samples one tau apart give the error. */
static void check_equipartition(int dim)
{
    const double T_bath = 0.01, tau = 0.005;
    char text[600];
    snprintf(
        text, sizeof text,
        "[system]\ndim = %d\nN = %d\n%s\n[placement]\nkind = %s\n[model]\nk_s = 5e3\neps_n = 1\n"
        "[driving]\nkind = langevin\nT_bath = %g\ntau = %g\n[run]\nseed = 3\n",
        dim, dim == 1 ? 400 : 1000, dim >= 2 ? "packing_fraction = 0.15" : "reduced_length = 0.4",
        dim >= 2 ? "random" : "uniform", T_bath, tau);
    gr_scene s;
    load(&s, text, NULL, 0);
    gr_sim *sim = create(&s);
    const int n = sim->n;
    const int64_t per_tau = (int64_t)llround(tau / gr_sim_dt(sim));
    step(sim, 10 * per_tau); /* T0 = dim v0^2 / 12 = 1.7e-3 dim: well below the bath */
    enum { BLOCKS = 20, PER_BLOCK = 4 };
    double block[3][BLOCKS];
    for (int b = 0; b < BLOCKS; b++) {
        block[0][b] = block[1][b] = block[2][b] = 0.0;
        for (int k = 0; k < PER_BLOCK; k++) {
            step(sim, per_tau);
            for (int c = 0; c < dim; c++) {
                block[c][b] += component_T(sim, c) / PER_BLOCK;
            }
        }
    }
    const double expect = T_bath / dim * (1.0 - 1.0 / n);
    for (int c = 0; c < dim; c++) {
        double se;
        const double mean = mean_se(block[c], BLOCKS, &se);
        VERBOSE("%dD component %d: T_c = %.6g +- %.2g, expected %.6g (z = %.2f)\n", dim, c, mean,
                se, expect, (mean - expect) / se);
        ck_assert_msg(se < 0.01 * mean,
                      "%dD: the block error %g is too large to test equipartition", dim, se);
        ck_assert_msg(fabs(mean - expect) < 4.0 * se,
                      "%dD component %d: <T_c> = %g +- %g, bath gives T_bath/dim (1 - 1/N) = %g",
                      dim, c, mean, se, expect);
    }
    gr_ledger l = gr_sim_ledger(sim);
    ck_assert(l.injected > 0.0 && l.dissipated_drag > 0.0);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-3 * (l.injected + gr_ledger_dissipated(&l)),
                  "residual %g of %g moved", gr_ledger_residual(&l),
                  l.injected + gr_ledger_dissipated(&l));
    gr_sim_free(sim);
}

START_TEST(equipartition_2d) { check_equipartition(2); }
END_TEST

/* the sanitizer pass runs the 3D bath's code in bath_3d_threads_restart; the statistics here */
START_TEST(equipartition_3d)
{
    if (!quick()) {
        check_equipartition(3);
    }
}
END_TEST

START_TEST(equipartition_1d) { check_equipartition(1); }
END_TEST

/* ---- the ideal gas relaxes exponentially -------------------------------------------------- */

/* Tiny elastic discs (radius 10 nm) in a large box: no contacts. Each component is an exact OU process: v(k dt) = a^k v(0) + s z, s^2 = T_bath/dim (1 - a^(2k)).
 * So T (2.19) has expectation T0 a^(2k) + T_bath (1 - 1/N)(1 - a^(2k)) (the initial mean is zero)
 * and, given v(0), variance (1/N^2) sum_i sum_c (4 a^(2k) v_ic(0)^2 s^2 + 2 s^4) (plus the mean's
 * O(1/N^2) part). A decay e^(-t/tau) instead of e^(-2t/tau) misses by hundreds of errors. */
START_TEST(ideal_gas_relaxation)
{
    const double T_bath = 0.01, tau = 0.01, dt = 1e-4;
    char text[600];
    snprintf(
        text, sizeof text,
        "[system]\ndim = 2\nN = 4000\nL = 0.2\nradius = 1e-8\n[placement]\nkind = uniform\nv0 = 1\n"
        "[model]\nk_s = 50\neps_n = 1\n[integrator]\ndt = %g\n[driving]\nkind = langevin\nT_bath = "
        "%g\ntau = %g\n",
        dt, T_bath, tau);
    gr_scene s;
    load(&s, text, NULL, 0);
    gr_sim *sim = create(&s);
    const int n = sim->n;
    double *v0 = malloc(sizeof(double) * 2 * (size_t)n);
    ck_assert_ptr_nonnull(v0);
    memcpy(v0, sim->vx, sizeof(double) * (size_t)n);
    memcpy(v0 + n, sim->vy, sizeof(double) * (size_t)n);
    const double T0 = gr_sim_temperature(sim);
    ck_assert(T0 > 10.0 * T_bath);        /* v0 = 1: T0 = 1/6 m^2/s^2 */
    const int at[] = {50, 100, 200, 500}; /* t = tau/2, tau, 2 tau, 5 tau */
    int done = 0;
    for (int q = 0; q < 4; q++) {
        step(sim, at[q] - done);
        done = at[q];
        const double a2k = exp(-2.0 * at[q] * dt / tau), s2 = T_bath / 2.0 * (1.0 - a2k);
        const double expect = T0 * a2k + T_bath * (1.0 - 1.0 / n) * (1.0 - a2k);
        double var = 0.0;
        for (int i = 0; i < 2 * n; i++) {
            var += 4.0 * a2k * v0[i] * v0[i] * s2 + 2.0 * s2 * s2;
        }
        const double se = sqrt(var) / n, T = gr_sim_temperature(sim);
        VERBOSE("t = %g tau: T = %.6g, expected %.6g +- %.2g (z = %.2f)\n", at[q] * dt / tau, T,
                expect, se, (T - expect) / se);
        ck_assert_msg(fabs(T - expect) < 5.0 * se,
                      "t = %g s: T = %g, T_bath + (T0 - T_bath) e^(-2t/tau) gives %g +- %g",
                      at[q] * dt, T, expect, se);
    }
    VERBOSE("ideal gas: %lld contacts\n", (long long)gr_sim_collisions(sim));
    ck_assert_msg(gr_sim_collisions(sim) == 0, "%lld contacts: not an ideal gas",
                  (long long)gr_sim_collisions(sim));
    /* the ledger without contacts: exact to rounding */
    gr_ledger l = gr_sim_ledger(sim);
    ck_assert(l.dissipated_drag > 0.0 && l.injected > 0.0);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    VERBOSE("ideal gas ledger: injected %g, drag %g, residual %g\n", l.injected, l.dissipated_drag,
            gr_ledger_residual(&l));
    /* no contacts, so no spring error: rounding only (2e-15 measured); a term left out of the books
     * would leave a residual of order `moved` */
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    free(v0);
    gr_sim_free(sim);
}
END_TEST

/* ---- the ledger with inelastic contacts ---------------------------------------------------- */

/* A dense inelastic gas in the bath: contacts and drag both dissipate; the balance holds to the
 * springs' velocity-Verlet error (docs/integrator.md). */
START_TEST(ledger_inelastic)
{
    const char *text =
        "[system]\ndim = 2\nN = 600\npacking_fraction = 0.3\n[placement]\nkind = random\n"
        "[model]\nk_s = 5e3\neps_n = 0.6\n[driving]\nkind = langevin\nT_bath = 0.01\ntau = 0.01\n";
    gr_scene s;
    load(&s, text, NULL, 0);
    gr_sim *sim = create(&s);
    const int64_t per_tau = (int64_t)llround(0.01 / gr_sim_dt(sim));
    step(sim, 5 * per_tau);
    gr_ledger l = gr_sim_ledger(sim);
    const double moved = l.injected + gr_ledger_dissipated(&l);
    VERBOSE("inelastic: injected %g, normal %g, drag %g, residual %g, T %g\n", l.injected,
            l.dissipated_normal, l.dissipated_drag, gr_ledger_residual(&l),
            gr_sim_temperature(sim));
    ck_assert(l.dissipated_normal > 0.01 * moved && l.dissipated_drag > 0.01 * moved);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-3 * moved, "residual %g of %g moved",
                  gr_ledger_residual(&l), moved);
    ck_assert_double_eq(gr_ledger_dissipated(&l), l.dissipated_normal + l.dissipated_tangential +
                                                      l.dissipated_friction + l.dissipated_drag);
    gr_sim_free(sim);
}
END_TEST

/* ---- reproducibility ----------------------------------------------------------------------- */

static const char *bath_2d =
    "[system]\ndim = 2\nN = 2500\npacking_fraction = 0.2\n[placement]\nkind = random\n"
    "[model]\nk_s = 5e3\neps_n = 0.8\n[driving]\nkind = langevin\nT_bath = 0.01\ntau = 0.002\n";

/* The bath's noise is the random force's counter-based stream: the same run on 1 and 2 threads
 * (several blocks of particles) is the same bit for bit. */
START_TEST(threads_invariant)
{
    gr_scene s;
    load(&s, bath_2d, NULL, 0);
    assert_threads_invariant(&s, 300);
    gr_sim *a = create(&s);
    step(a, 300);
    ck_assert(a->diss_drag > 0.0); /* the bath acted */
    gr_sim_free(a);
}
END_TEST

/* Stepping 200 steps in one go equals saving the state after 120, loading it into a fresh
 * simulation and stepping 80 more: the drag's ledger entry travels with the checkpoint. */
START_TEST(restart_exact)
{
    gr_scene s;
    load(&s, bath_2d, NULL, 0);
    assert_restart_exact(&s, 200, 120);
}
END_TEST

/* Spheres in the bath between walls under gravity (three blocks of particles): 1 and 2 threads
 * give the same run bit for bit, and a restart is exact. */
START_TEST(bath_3d_threads_restart)
{
    const char *text =
        "[system]\ndim = 3\nN = 2500\npacking_fraction = 0.1\n[placement]\nkind = random\n"
        "[model]\nk_s = 5e3\neps_n = 0.8\n[driving]\nkind = langevin\nT_bath = 0.01\ntau = "
        "0.002\n[boundary]\nz = walls\n[gravity]\ngz = -9.81\n";
    gr_scene s;
    load(&s, text, NULL, 0);
    assert_threads_invariant(&s, quick() ? 30 : 200);
    assert_restart_exact(&s, quick() ? 40 : 200, quick() ? 25 : 120);
    gr_sim *a = create(&s);
    step(a, 50);
    ck_assert(a->diss_drag > 0.0); /* the bath acted */
    gr_sim_free(a);
}
END_TEST

/* ---- none and rfm --------------------------------------------------------------------------- */

static const char *gas_1d =
    "[system]\ndim = 1\nN = 200\nreduced_length = 0.5\n[placement]\nkind = uniform\n";
static const char *gas_2d =
    "[system]\ndim = 2\nN = 1500\npacking_fraction = 0.2\n[placement]\nkind = random\n"
    "[model]\neps_n = 0.6\n";

/* Two scenes that must be the same run: equal final states after `steps`. */
static void assert_same_run(const char *text, const char *const *set_a, int na,
                            const char *const *set_b, int nb, int64_t steps)
{
    gr_scene sa, sb;
    load(&sa, text, set_a, na);
    load(&sb, text, set_b, nb);
    gr_sim *a = create(&sa), *b = create(&sb);
    step(a, steps);
    step(b, steps);
    assert_same_state(a, b);
    gr_sim_free(a);
    gr_sim_free(b);
}

START_TEST(rfm_named_is_default)
{
    const char *rfm[] = {"driving.kind=rfm"};
    assert_same_run(gas_1d, NULL, 0, rfm, 1, 2000);
    assert_same_run(gas_2d, NULL, 0, rfm, 1, 500);
    const char *com[] = {"noise.mode=com"}, *com_rfm[] = {"noise.mode=com", "driving.kind=rfm"};
    assert_same_run(gas_2d, com, 1, com_rfm, 2, 500);
    gr_scene s;
    load(&s, gas_2d, rfm, 1);
    ck_assert_ptr_eq(s.driving, gr_driving_find("rfm"));
    ck_assert_str_eq(s.warnings, "");
    ck_assert(s.D > 0.0);
}
END_TEST

START_TEST(none_is_zero_noise)
{
    const char *none[] = {"driving.kind=none"}, *d0[] = {"noise.D=0"};
    assert_same_run(gas_1d, d0, 1, none, 1, 2000);
    assert_same_run(gas_2d, d0, 1, none, 1, 500);
    /* the [noise] keys are ignored, with a warning that says why */
    const char *none_d[] = {"driving.kind=none", "noise.D=5e-8"};
    gr_scene s;
    load(&s, gas_2d, none_d, 2);
    ck_assert_double_eq(s.D, 0.0);
    ck_assert_msg(strstr(s.warnings, "[noise] D is ignored") != NULL, "warnings: %s", s.warnings);
    const char *rfm_tau[] = {"driving.tau=0.5"};
    load(&s, gas_2d, rfm_tau, 1);
    ck_assert_msg(strstr(s.warnings, "[driving] tau is ignored: it belongs to langevin") != NULL,
                  "warnings: %s", s.warnings);
}
END_TEST

/* The resolved scene.ini (what a run saves and a resume reads) of a none or langevin scene reads
 * back as the same scene (equal hash) with no new warnings: the unused [noise] keys are not
 * written; an rfm scene's has no [driving] section (it is what it was before drivings existed). */
START_TEST(saved_scene_round_trip)
{
    const char *kinds[][3] = {{"driving.kind=none", "noise.D=5e-8", NULL},
                              {"driving.kind=langevin", "driving.tau=0.02", "noise.mode=com"},
                              {"driving.kind=rfm", "noise.D=2e-8", NULL}};
    for (int k = 0; k < 3; k++) {
        gr_scene a, b;
        load(&a, gas_2d, kinds[k], kinds[k][2] ? 3 : 2);
        ck_assert_msg(k == 2 ? a.warnings[0] == 0 : strstr(a.warnings, "[noise]") != NULL, "%s",
                      a.warnings);
        char *text = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&text, &len);
        gr_scene_write(&a, f);
        fclose(f);
        ck_assert_msg((strstr(text, "\n[driving]\n") != NULL) == (k != 2), "%s", text);
        ck_assert_msg((strstr(text, "\n[noise]\n") != NULL) == (k == 2), "%s", text);
        gr_error err = {0};
        ck_assert_msg(gr_scene_load_buffer(&b, "scene.ini", text, len, NULL, 0, &err) == GR_OK,
                      "%s", err.message);
        free(text);
        ck_assert_str_eq(b.warnings, "");
        ck_assert_ptr_eq(a.driving, b.driving);
        ck_assert(gr_scene_hash(&a) == gr_scene_hash(&b));
    }
}
END_TEST

/* Free cooling: with kind = none an inelastic gas only loses energy, for verlet, event and hybrid. */
static void check_cools(const char *text, int64_t steps)
{
    const char *none[] = {"driving.kind=none"};
    gr_scene s;
    load(&s, text, none, 1);
    gr_sim *sim = create(&s);
    const double T0 = gr_sim_temperature(sim);
    step(sim, steps);
    gr_ledger l = gr_sim_ledger(sim);
    VERBOSE("%s: T %g -> %g\n", s.integrator->name, T0, gr_sim_temperature(sim));
    /* (the event integrator's exact free flight at D = 0 adds rounding-size energy, ~1e-20 J) */
    ck_assert_msg(fabs(l.injected) < 1e-12 * l.initial, "injected %g J", l.injected);
    ck_assert_double_eq(l.dissipated_drag, 0.0);
    ck_assert(gr_sim_temperature(sim) < 0.7 * T0);
    gr_sim_free(sim);
}

START_TEST(none_cools)
{
    check_cools(
        "[system]\ndim = 2\nN = 1000\npacking_fraction = 0.3\n[placement]\nkind = random\nv0 = 1\n"
        "[model]\nk_s = 5e3\neps_n = 0.5\n",
        20000);
    check_cools(
        "[system]\ndim = 2\nN = 1000\npacking_fraction = 0.3\n[placement]\nkind = random\nv0 = 1\n"
        "[model]\nnormal = hard_sphere\neps_n = 0.5\neps_t = 1\n[integrator]\nkind = event\n",
        100000);
    check_cools(
        "[system]\ndim = 2\nN = 1000\npacking_fraction = 0.3\n[placement]\nkind = random\nv0 = 1\n"
        "[model]\nk_s = 5e3\neps_n = 0.5\n[integrator]\nkind = hybrid\ndt = 4e-6\nkick_interval = "
        "4e-4\n",
        20000);
}
END_TEST

/* ---- refusals -------------------------------------------------------------------------------- */

/* Every integrator models the drag now (verlet per step; event and hybrid at each window's end:
 * test_window_bath.c); the refusal of one that does not stays, in the library (the integrator's
 * capability flag drag) and the scene (by name, tested here with the library's path). */
START_TEST(drag_refused_without_capability)
{
    gr_scene s;
    load(&s, gas_1d, NULL, 0);
    gr_sim_params p;
    gr_scene_sim_params(&s, &p);
    gr_integrator_type no_drag = *gr_integrator_find("verlet");
    no_drag.name = "no_drag";
    no_drag.drag = false;
    p.driving = gr_driving_find("langevin");
    p.integrator = &no_drag;
    gr_sim *sim = NULL;
    gr_error err = {0};
    ck_assert_int_ne(gr_sim_new(&p, &sim, &err), GR_OK);
    ck_assert_ptr_null(sim);
    ck_assert_msg(strstr(err.message, "[driving] kind = langevin") &&
                      strstr(err.message, "kind = no_drag does not model"),
                  "%s", err.message);
}
END_TEST

/* The registry: every type named once, findable, rfm the default; parameters with units and ranges. */
START_TEST(registry)
{
    int n = 0;
    for (int i = 0; gr_drivings[i]; i++, n++) {
        ck_assert_ptr_eq(gr_driving_find(gr_drivings[i]->name), gr_drivings[i]);
        ck_assert(gr_drivings[i]->summary && *gr_drivings[i]->summary);
        for (int j = 0; j < gr_drivings[i]->n_params; j++) {
            ck_assert(*gr_drivings[i]->params[j].unit && gr_drivings[i]->params[j].doc);
        }
    }
    ck_assert_int_eq(n, 3);
    ck_assert_str_eq(gr_driving_default()->name, "rfm");
    ck_assert_ptr_null(gr_driving_find("bogus"));
    ck_assert(gr_driving_find("langevin")->drag && !gr_driving_find("none")->drag &&
              !gr_driving_find("rfm")->drag);
    ck_assert(gr_integrator_find("verlet")->drag && gr_integrator_find("event")->drag &&
              gr_integrator_find("hybrid")->drag);
    /* prepare: the exact OU factors */
    gr_driving_params p = {.T_bath = 0.02, .tau = 0.5};
    gr_driving_coeffs c;
    gr_error err = {0};
    ck_assert_int_eq(gr_driving_find("langevin")->prepare(&p, 2, 1e-3, &c, &err), GR_OK);
    ck_assert_double_eq_tol(c.decay, exp(-2e-3), 1e-15);
    ck_assert_double_eq_tol(c.kick * c.kick, 0.01 * (1.0 - exp(-4e-3)), 1e-17);
}
END_TEST

/* summary.json's mean_field for a bath: its parameters, the elastic T and the Enskog estimate,
 * which solves the balance (2/tau)(T_b - T) = 2 rate sqrt(T/dim) T and is T_b at eps_n = 1. */
START_TEST(mean_field_bath)
{
    const char *eps1[] = {"model.eps_n=1"}, *eps06[] = {"model.eps_n=0.6", "driving.tau=0.2"};
    gr_scene s;
    load(&s, bath_2d, eps1, 1);
    cJSON *j = gr_mean_field_haff(&s, NULL, NULL, 0);
    ck_assert_ptr_nonnull(j);
    const double Tb = 0.01 * (1.0 - 1.0 / 2500);
    ck_assert_double_eq(cJSON_GetObjectItem(j, "T_bath")->valuedouble, 0.01);
    ck_assert_double_eq(cJSON_GetObjectItem(j, "tau")->valuedouble, 0.002);
    ck_assert_double_eq_tol(cJSON_GetObjectItem(j, "D_bath")->valuedouble,
                            3.53e-5 * 3.53e-5 * 0.01 / (2 * 0.002), 1e-25);
    ck_assert_double_eq(cJSON_GetObjectItem(j, "T_elastic")->valuedouble, Tb);
    ck_assert_double_eq(cJSON_GetObjectItem(j, "T_enskog")->valuedouble, Tb);
    cJSON_Delete(j);
    load(&s, bath_2d, eps06, 2);
    j = gr_mean_field_haff(&s, NULL, NULL, 0);
    const double T = cJSON_GetObjectItem(j, "T_enskog")->valuedouble;
    const double rate = gr_haff_rate_2d(s.packing_fraction, 0.6, 2.0 * s.radius);
    ck_assert_msg(T > 0.0 && T < 0.7 * Tb, "T_enskog = %g",
                  T); /* zeta tau ~ 2: the collisions matter */
    ck_assert_double_eq_tol((Tb - T) / 0.2, rate * T * sqrt(T / 2.0), 1e-12 * Tb / 0.2);
    cJSON_Delete(j);
}
END_TEST

static Suite *driving_suite(void)
{
    Suite *s = suite_create("driving");
    TCase *unit = tcase_create("unit");
    tcase_add_test(unit, registry);
    tcase_add_test(unit, mean_field_bath);
    tcase_add_test(unit, drag_refused_without_capability);
    tcase_add_test(unit, rfm_named_is_default);
    tcase_add_test(unit, none_is_zero_noise);
    tcase_add_test(unit, saved_scene_round_trip);
    tcase_add_test(unit, threads_invariant);
    tcase_add_test(unit, restart_exact);
    tcase_add_test(unit, bath_3d_threads_restart);
    suite_add_tcase(s, unit);
    TCase *phys = tcase_create("physics");
    tcase_set_timeout(phys, 600);
    tcase_add_test(phys, equipartition_2d);
    tcase_add_test(phys, equipartition_3d);
    tcase_add_test(phys, equipartition_1d);
    tcase_add_test(phys, ideal_gas_relaxation);
    tcase_add_test(phys, ledger_inelastic);
    tcase_add_test(phys, none_cools);
    suite_add_tcase(s, phys);
    return s;
}

int main(void) { return gr_test_run(driving_suite()); }
