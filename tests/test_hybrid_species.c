/* The hybrid integrator on a mixture (issue 36; docs/hybrid.md, "Mixtures"): grains of two
 * species with their own radii and masses (1 and 2 mm, masses 1:4) stepped by free flights and
 * soft contacts.
 *  - free flight per species: at rest and far apart, after K windows each grain's (v, x - x0) has
 *    the law of K m Verlet kicks of sqrt(2 D dt) / m_i, so <m_i^2 v^2> = 2 D t per component for
 *    both species (a single mass for all would put the heavy species 16 times off); the ledger's
 *    injected energy is the kinetic energy gained to rounding;
 *  - without noise, every grain active is the verlet integrator's mixture step to the last bit, and
 *    the normal margin (free grains leaping) the same to rounding, in 1D, 2D and 3D, with rotating
 *    grains (each with its own moment of inertia), also between walls under gravity;
 *  - with the random force (com mode), the normal margin, everybody active and a tiny margin that
 *    rolls back give the same path to rounding: which grains are stepped and which leap does not
 *    change the noise any grain sees, whatever its mass;
 *  - a driven mixture: its ledger closes, and the species' temperature ratio T_1 / T_2 agrees with
 *    the verlet integrator's from the same seeds (release pass).
 * Statistical tolerances are z-scores (|z| < 4.5); GRANULE_TEST_QUICK=1 shortens the runs. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/analysis.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "integrators/hybrid/hybrid.h"
#include "check_main.h"
#include "hybrid_test_util.h"
#include "test_env.h"

/* The mixture of these tests: radii 1 and 2 mm, masses 1:4 (both species' own pair laws). */
#define MIXTURE "species.radius=1e-3, 2e-3", "species.mass=1.5707963e-5, 6.2831853e-5"

/* ---- free flight per species ----------------------------------------------------------------- */

START_TEST(test_free_flight_per_species)
{
    const int N = quick() ? 2000 : 20000;
    char nb[64];
    snprintf(nb, sizeof nb, "system.N=%d", N);
    /* discs at rest on a lattice far apart (phi 1e-4), raw noise (com resets beyond the run),
     * windows of 100 steps */
    const char *over[] = {nb,
                          "system.packing_fraction=1e-4",
                          MIXTURE,
                          "placement.kind=uniform",
                          "placement.v0=0",
                          "driving.kind=rfm",
                          "noise.D=1e-8",
                          "noise.mode=com",
                          "noise.com_interval=1000",
                          "integrator.kind=hybrid",
                          "integrator.dt=1e-6",
                          "integrator.kick_interval=1e-4",
                          NULL};
    gr_scene sc = load("bidisperse-sizes-gas.ini", over);
    gr_sim *s = create(&sc);
    const int64_t n = 2350; /* 23 full windows of 100 steps and one of 50 (two calls) */
    step(s, 1000);
    step(s, 1350);
    gr_hybrid_stats st;
    ck_assert(gr_sim_hybrid_stats(s, &st));
    ck_assert_msg(st.active_fraction == 0.0, "active fraction %g", st.active_fraction);
    const double t = n * s->dt, D = sc.D;
    /* per species a: <m^2 v^2> over both components against 2 D t, z from Var(v^2) = 2 <v^2>^2 */
    double sum[2] = {0.0, 0.0};
    int count[2] = {0, 0};
    for (int i = 0; i < N; i++) {
        const int a = s->species[i];
        const double m = s->mass_i[i];
        sum[a] += m * m * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i]);
        count[a] += 2;
    }
    for (int a = 0; a < 2; a++) {
        const double got = sum[a] / count[a], want = 2.0 * D * t;
        const double z = (got - want) / (want * sqrt(2.0 / count[a]));
        VERBOSE("free flight, species %d: <m^2 v^2> = %.5g against 2 D t = %.5g (z %.2f)\n", a + 1,
                got, want, z);
        ck_assert_msg(fabs(z) < 4.5, "species %d: <m^2 v^2> %g against %g: z = %g", a + 1, got,
                      want, z);
    }
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-9 * l.injected,
                  "free-flight ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    gr_sim_free(s);
}
END_TEST

/* ---- without noise: verlet's mixture step ------------------------------------------------- */

/* Every grain active is the verlet integrator's step_poly.c operation for operation (the child
 * runs the same kernel on the same grains in the same order); the normal margin leaps the free
 * grains (x + v tau instead of m additions of v dt), which changes only rounding. */
static void no_noise_case(const char *scene, const char *const *scene_keys, int64_t n)
{
    const char *oh[16] = {"integrator.kind=hybrid", "integrator.kick_interval=2e-5",
                          "noise.mode=none"};
    int k = 3;
    for (int j = 0; scene_keys[j]; j++) {
        oh[k++] = scene_keys[j];
    }
    oh[k] = NULL;
    const char *const *ov = oh + 2; /* the same without the hybrid */
    gr_scene sv = load(scene, ov), sh = load(scene, oh);
    gr_sim *v = create(&sv), *all = create(&sh), *h = create(&sh);
    ck_assert_msg(strstr(h->kernel_name, "species") != NULL, "kernel %s", h->kernel_name);
    gr_hybrid_set_margin(all, 1e9);
    step(v, n);
    step(all, n - 13);
    step(all, 13);
    step(h, n);
    const double d_all = max_diff(v, all), d_h = max_diff(v, h);
    gr_hybrid_stats st;
    gr_sim_hybrid_stats(h, &st);
    VERBOSE("%s mixture, no noise: |x_verlet - x_all_active| = %.3g m, |x_verlet - x_hybrid| = "
            "%.3g m; collisions %lld / %lld / %lld; active %.3f\n",
            scene, d_all, d_h, (long long)gr_sim_collisions(v), (long long)gr_sim_collisions(all),
            (long long)gr_sim_collisions(h), st.active_fraction);
    ck_assert_msg(gr_sim_collisions(v) > 50, "only %lld collisions",
                  (long long)gr_sim_collisions(v));
    ck_assert_msg(d_all == 0.0, "all-active hybrid differs from verlet by %g m", d_all);
    if (v->omega) { /* rotation: each grain's own moment of inertia q m_i r_i^2 */
        double dw_all, dw_h, wmax;
        gr_test_spin_diff(v, all, h, &dw_all, &dw_h, &wmax);
        VERBOSE("spins: |w_verlet - w_all_active| = %.3g, |w_verlet - w_hybrid| = %.3g rad/s of "
                "%.3g rad/s\n",
                dw_all, dw_h, wmax);
        /* to the last bit: each grain's arm to the contact point does not depend on which grain
         * owns the pair in the (child's or parent's) list (kernels_poly.c, contact_arms) */
        ck_assert_msg(wmax > 0.0 && dw_all == 0.0, "all-active spins differ by %g rad/s of %g",
                      dw_all, wmax);
        ck_assert_msg(dw_h < 1e-6 * wmax, "hybrid spins differ by %g rad/s", dw_h);
    }
    ck_assert_int_eq(gr_sim_collisions(all), gr_sim_collisions(v));
    ck_assert_msg(d_h < 1e-9, "hybrid differs from verlet by %g m", d_h);
    ck_assert_int_eq(gr_sim_collisions(h), gr_sim_collisions(v));
    ck_assert_msg(st.active_fraction < 0.95, "active fraction %g: nobody leaps",
                  st.active_fraction);
    gr_sim_free(v);
    gr_sim_free(all);
    gr_sim_free(h);
}

START_TEST(test_no_noise_equals_verlet)
{
    static const char *const ring[] = {"system.dim=1",
                                       "system.N=200",
                                       "system.reduced_length=0.3",
                                       "placement.kind=uniform",
                                       "integrator.dt=1e-6",
                                       MIXTURE,
                                       NULL};
    static const char *const discs[] = {"system.N=400", "integrator.dt=1e-6", MIXTURE, NULL};
    static const char *const spheres[] = {
        "system.dim=3",       "system.N=400", "system.packing_fraction=0.05",
        "integrator.dt=1e-6", MIXTURE,        NULL};
    /* rotating grains: discs with the tangential dashpot and rolling resistance, spheres with
     * sliding friction */
    static const char *const spin2[] = {"system.N=400",
                                        "integrator.dt=1e-6",
                                        "model.tangential=tangential_dashpot",
                                        "model.eps_t=0.5",
                                        "model.rotation=true",
                                        "model.rolling=rolling_friction",
                                        "model.mu_r=0.1",
                                        MIXTURE,
                                        NULL};
    static const char *const spin3[] = {"system.dim=3",
                                        "system.N=400",
                                        "system.packing_fraction=0.05",
                                        "integrator.dt=1e-6",
                                        "model.tangential=sliding_friction",
                                        "model.mu=0.3",
                                        "model.rotation=true",
                                        MIXTURE,
                                        NULL};
    /* a lognormal distribution of radii 1-4 mm (each pair's law scaled from the reference) */
    static const char *const lognormal[] = {"integrator.dt=1e-6", NULL};
    /* a bed of two sizes shaken by its floor under gravity, grains near a wall active */
    static const char *const bed[] = {"placement.v0=1", "integrator.dt=4e-7", NULL};
    /* chaos amplifies the leaps' rounding (1e-16 m) about tenfold per few thousand steps: these
     * horizons keep it near 1e-10 m */
    const int64_t n = 6000;
    switch (_i) {
    case 0: no_noise_case("bidisperse-sizes-gas.ini", ring, 4 * n); break;
    case 1: no_noise_case("bidisperse-sizes-gas.ini", discs, n); break;
    case 2: no_noise_case("bidisperse-sizes-gas.ini", spheres, n); break;
    case 3: no_noise_case("bidisperse-sizes-gas.ini", spin2, n); break;
    case 4: no_noise_case("bidisperse-sizes-gas.ini", spin3, n); break;
    case 5: no_noise_case("vibrated-bed-mixture.ini", bed, 30000); break;
    default: no_noise_case("polydisperse-gas.ini", lognormal, n);
    }
}
END_TEST

/* ---- with noise: the active set does not change the path ------------------------------------ */

/* The normal margin, everybody active and a tiny margin (many misses, each window redone after a
 * rollback) give the same trajectory to rounding: each grain's noise path in a window is fixed by
 * the counters, scaled by its own 1 / m_i, whether it leaps or is stepped. */
static void same_path(const char *scene, const char *const *over, int64_t n, double tiny_c)
{
    gr_scene sc = load(scene, over);
    gr_sim *all = create(&sc), *h = create(&sc), *tiny = create(&sc);
    gr_hybrid_set_margin(all, 1e9);
    gr_hybrid_set_margin(tiny, tiny_c);
    step(all, n);
    step(h, n);
    step(tiny, n);
    gr_hybrid_stats sa, sh, st;
    gr_sim_hybrid_stats(all, &sa);
    gr_sim_hybrid_stats(h, &sh);
    gr_sim_hybrid_stats(tiny, &st);
    const double d_h = max_diff(all, h), d_t = max_diff(all, tiny);
    VERBOSE("mixture, %dD with noise: |all - normal| %.3g m, |all - tiny| %.3g m; active %.3f / "
            "%.3f / %.3f; rollbacks %lld / %lld; collisions %lld\n",
            all->dim, d_h, d_t, sa.active_fraction, sh.active_fraction, st.active_fraction,
            (long long)sh.rollbacks, (long long)st.rollbacks, (long long)gr_sim_collisions(all));
    ck_assert_msg(sa.active_fraction == 1.0, "huge margin: active fraction %g", sa.active_fraction);
    ck_assert_msg(gr_sim_collisions(all) > 20, "only %lld collisions",
                  (long long)gr_sim_collisions(all));
    ck_assert_msg(st.rollbacks > 0, "c = %g never rolled back", tiny_c);
    ck_assert_msg(d_h < 1e-9, "normal margin differs from all-active by %g m", d_h);
    ck_assert_msg(d_t < 1e-9, "rollbacks differ from all-active by %g m", d_t);
    ck_assert_int_eq(gr_sim_collisions(h), gr_sim_collisions(all));
    ck_assert_int_eq(gr_sim_collisions(tiny), gr_sim_collisions(all));
    gr_sim_free(all);
    gr_sim_free(h);
    gr_sim_free(tiny);
}

START_TEST(test_active_set_invariance)
{
    const char *over[] = {_i == 0 ? "system.dim=2" : "system.dim=3",
                          _i == 0 ? "system.N=300" : "system.N=216",
                          _i == 0 ? "system.packing_fraction=0.1" : "system.packing_fraction=0.25",
                          MIXTURE,
                          "placement.v0=0.5",
                          "model.eps_n=0.7",
                          "driving.kind=rfm",
                          _i == 0 ? "noise.D=1e-7" : "noise.D=1e-6",
                          "noise.mode=com",
                          "integrator.kind=hybrid",
                          "integrator.dt=1e-6",
                          _i == 0 ? "integrator.kick_interval=2e-4"
                                  : "integrator.kick_interval=1e-4",
                          NULL};
    /* chaos amplifies rounding about tenfold per few hundred steps: this horizon keeps it small */
    same_path("bidisperse-sizes-gas.ini", over, quick() ? 1500 : 2500, _i == 0 ? 0.0 : 0.5);
}
END_TEST

/* the same on the lognormal radii of docs/scenes/polydisperse-gas.ini */
START_TEST(test_active_set_invariance_distribution)
{
    const char *over[] = {"placement.v0=0.5",
                          "model.eps_n=0.7",
                          "driving.kind=rfm",
                          "noise.D=1e-7",
                          "noise.mode=com",
                          "integrator.kind=hybrid",
                          "integrator.dt=1e-6",
                          "integrator.kick_interval=2e-4",
                          NULL};
    same_path("polydisperse-gas.ini", over, quick() ? 3000 : 4000, 0.0);
}
END_TEST

/* ---- a driven mixture ------------------------------------------------------------------------ */

/* The mixture of docs/scenes/bidisperse-mixture.ini (masses 1:4, eps_n = 0.7, com mode) by the
 * hybrid: the ledger, and in the release pass T_1 / T_2 against the verlet integrator's from the
 * same seeds. */
static void species_T(gr_sim *s, double *T1, double *T2)
{
    double e[2] = {0.0, 0.0};
    int c[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        const int a = s->species[i];
        e[a] += s->mass_i[i] * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i]);
        c[a]++;
    }
    *T1 = e[0] / c[0];
    *T2 = e[1] / c[1];
}

/* the mean ratio <T_1> / <T_2> of samples every 1000 steps after the warm-up, over seeds; its
 * error from the seeds' scatter */
static void ratio_over_seeds(const char *kind, int seeds, int64_t warm, int samples, double *mean,
                             double *err, double *worst_residual)
{
    double r[16], sum = 0.0;
    *worst_residual = 0.0;
    for (int k = 0; k < seeds; k++) {
        char seed[32], kb[48];
        snprintf(seed, sizeof seed, "run.seed=%d", k + 1);
        snprintf(kb, sizeof kb, "integrator.kind=%s", kind);
        const char *over[] = {"system.N=400",
                              "noise.mode=com",
                              kb,
                              "integrator.dt=9e-6",
                              "integrator.kick_interval=9e-5",
                              seed,
                              NULL};
        gr_scene sc = load("bidisperse-mixture.ini", over);
        gr_sim *s = create(&sc);
        step(s, warm);
        double t1 = 0.0, t2 = 0.0;
        for (int j = 0; j < samples; j++) {
            step(s, 1000);
            double a, b;
            species_T(s, &a, &b);
            t1 += a;
            t2 += b;
        }
        gr_ledger l = gr_sim_ledger(s);
        *worst_residual = fmax(*worst_residual, fabs(gr_ledger_residual(&l) / l.injected));
        r[k] = t1 / t2;
        sum += r[k];
        gr_sim_free(s);
    }
    *mean = sum / seeds;
    double var = 0.0;
    for (int k = 0; k < seeds; k++) {
        var += (r[k] - *mean) * (r[k] - *mean);
    }
    *err = sqrt(var / (seeds - 1) / seeds);
    VERBOSE("%s: T_1 / T_2 = %.4f +- %.4f over %d seeds; ledger residual <= %.2g\n", kind, *mean,
            *err, seeds, *worst_residual);
}

START_TEST(test_driven_mixture)
{
    const int seeds = quick() ? 2 : 4, samples = quick() ? 20 : 150;
    const int64_t warm = quick() ? 20000 : 60000;
    double rh, eh, resid_h;
    ratio_over_seeds("hybrid", seeds, warm, samples, &rh, &eh, &resid_h);
    /* the same closure the verlet integrator reaches at 20 steps per contact (docs/mixtures.md) */
    ck_assert_msg(resid_h < 5e-3, "hybrid ledger residual %g", resid_h);
    if (quick()) {
        return;
    }
    double rv, ev, resid_v;
    ratio_over_seeds("verlet", seeds, warm, samples, &rv, &ev, &resid_v);
    const double z = (rh - rv) / sqrt(eh * eh + ev * ev);
    VERBOSE("T_1 / T_2: hybrid %.4f +- %.4f, verlet %.4f +- %.4f: z = %.2f\n", rh, eh, rv, ev, z);
    ck_assert_msg(rh > 1.03 && rv > 1.03, "no broken equipartition: %g, %g", rh, rv);
    ck_assert_msg(fabs(z) < 4.5, "T_1 / T_2 hybrid %g +- %g against verlet %g +- %g: z = %g", rh,
                  eh, rv, ev, z);
}
END_TEST

/* ---- refusals -------------------------------------------------------------------------------- */

/* A mixture's scene with the hybrid that it cannot run is refused at load, naming the key. */
static void refused(const char *const *over, const char *needle)
{
    const char *src = getenv("GRANULE_SOURCE_DIR");
    char path[2048];
    snprintf(path, sizeof path, "%s/docs/scenes/bidisperse-mixture.ini", src ? src : ".");
    int n = 0;
    while (over[n]) {
        n++;
    }
    gr_scene sc;
    gr_error err = {0};
    const int rc = gr_scene_load(&sc, path, over, n, &err);
    VERBOSE("refused: %s\n", err.message);
    ck_assert_msg(rc != GR_OK && strstr(err.message, needle), "expected a refusal naming %s: %s",
                  needle, err.message);
}

START_TEST(test_refusals)
{
    const char *sym[] = {"integrator.kind=hybrid", NULL}; /* the scene's symmetrised noise */
    refused(sym, "[noise] mode");
}
END_TEST

static Suite *hybrid_species_suite(void)
{
    Suite *s = suite_create("hybrid_species");
    TCase *t = tcase_create("hybrid_species");
    tcase_set_timeout(t, 600);
    tcase_add_test(t, test_free_flight_per_species);
    tcase_add_loop_test(t, test_no_noise_equals_verlet, 0, 7);
    tcase_add_loop_test(t, test_active_set_invariance, 0, 2);
    tcase_add_test(t, test_active_set_invariance_distribution);
    tcase_add_test(t, test_driven_mixture);
    tcase_add_test(t, test_refusals);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(hybrid_species_suite()); }
