/* Tests of the hybrid integrator (src/integrators/hybrid/, docs/hybrid.md): exact free flight, the energy
 * ledger and momentum, independence of the result from the active set (huge margin, rollbacks),
 * equality with Verlet without noise, agreement with Verlet on the 1D RFM scene, 2D, contact
 * events, and refusals.
 *
 * Scenes are the files of docs/scenes with overrides (GRANULE_SOURCE_DIR). Fixed seeds throughout;
 * statistical tolerances are z-scores (|z| < 4.5 for single moments, combined block-averaging
 * errors for the agreement test). GRANULE_TEST_QUICK=1 (ASan) shrinks the runs and leaves the
 * agreement statistics to the release pass; GRANULE_TEST_VERBOSE=1 prints the measured numbers. */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/sim_internal.h"
#include "granule/analysis.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "integrators/hybrid/hybrid.h"
#include "check_main.h"
#include "hybrid_test_util.h"
#include "test_env.h"

/* ---- free flight: no contact possible ------------------------------------------------------ */

/* N particles 1 m apart on a ring (1D) starting at rest, raw noise (com mode with resets far
 * beyond the run). After K windows of m steps each particle's (v, x - x0) must have exactly the
 * law of K m Verlet kicks: Var v = 2 D t / M^2, Var x = (2 D dt^3 / M^2) n(n+1)(2n+1)/6 with
 * n = K m (-> 2 D t^3 / (3 M^2)), Cov = (2 D dt^2 / M^2) n(n+1)/2. Checked by z-scores of the
 * sample moments over N particles; free_flight = kicks likewise with its own variance. */
/* at rest, raw noise (com resets far beyond the run), hybrid windows of 100 steps */
#define FREE_FLIGHT_KEYS                                                                           \
    "placement.v0=0", "noise.mode=com", "noise.com_interval=1000", "integrator.kind=hybrid",       \
        "integrator.kick_interval=1e-4"

/* 2350 steps in two calls: 23 full windows of 100 steps and one of 50, nobody active */
static void free_windows(gr_sim *s)
{
    step(s, 1000);
    step(s, 1350);
    gr_hybrid_stats st;
    ck_assert(gr_sim_hybrid_stats(s, &st));
    ck_assert_int_eq(st.windows, 10 + 14);
    ck_assert_int_eq(st.rollbacks, 0);
    ck_assert_msg(st.active_fraction == 0.0, "active fraction %g in a dilute gas",
                  st.active_fraction);
}

/* Sample means got = (<v^2>, <x^2>, <xv>) over K Gaussian samples against want, by z-scores:
 * Var(v^2) = 2 vv^2, Var(x^2) = 2 xx^2, Var(xv) = xx vv + xv^2. */
static void assert_moments(const char *label, const double got[3], const double want[3], int K)
{
    const double vv = want[0], xx = want[1], xv = want[2];
    const double zv = (got[0] - vv) / sqrt(2.0 * vv * vv / K),
                 zx = (got[1] - xx) / sqrt(2.0 * xx * xx / K),
                 zc = (got[2] - xv) / sqrt((xx * vv + xv * xv) / K);
    VERBOSE("%s: <v^2> %.5g vs %.5g (z %.2f), <x^2> %.5g vs %.5g (z %.2f), <xv> %.5g vs %.5g "
            "(z %.2f)\n",
            label, got[0], vv, zv, got[1], xx, zx, got[2], xv, zc);
    ck_assert_msg(fabs(zv) < 4.5, "%s: <v^2> %g vs %g: z = %g", label, got[0], vv, zv);
    ck_assert_msg(fabs(zx) < 4.5, "%s: <x^2> %g vs %g: z = %g", label, got[1], xx, zx);
    ck_assert_msg(fabs(zc) < 4.5, "%s: <xv> %g vs %g: z = %g", label, got[2], xv, zc);
}

static void free_moments(int kicks)
{
    const int N = quick() ? 2000 : 20000;
    char nb[64];
    snprintf(nb, sizeof nb, "system.N=%d", N);
    const char *over[] = {nb, "system.reduced_length=20000", FREE_FLIGHT_KEYS,
                          kicks ? "integrator.free_flight=kicks" : "integrator.free_flight=exact",
                          NULL};
    gr_scene sc = load("rfm-1d.ini", over);
    gr_sim *s = create(&sc);
    double *x0 = malloc(sizeof(double) * N);
    memcpy(x0, s->x, sizeof(double) * N);
    const int64_t n = 2350; /* 23 full windows of 100 steps and one of 50 */
    free_windows(s);
    const double dt = s->dt, M = s->mass, D = sc.D, t = n * dt;
    const double dn = (double)n;
    double vv = 2.0 * D * t / (M * M), xx, xv;
    if (!kicks) {
        xx = 2.0 * D * dt * dt * dt / (M * M) * dn * (dn + 1.0) * (2.0 * dn + 1.0) / 6.0;
        xv = 2.0 * D * dt * dt / (M * M) * dn * (dn + 1.0) / 2.0;
    } else { /* one kick per window at its middle step: window w of m steps kicks at step w m + m/2 */
        xx = xv = 0.0;
        const int64_t ms[2] = {100, 50};
        int64_t t0 = 0;
        for (int w = 0; w < 24; w++) {
            const int64_t m = w < 23 ? ms[0] : ms[1];
            const double var = 2.0 * D * m * dt / (M * M), lever = (double)(n - (t0 + m / 2)) * dt;
            xx += var * lever * lever;
            xv += var * lever;
            t0 += m;
        }
    }
    double mv = 0.0, mx = 0.0, mc = 0.0, m4v = 0.0, m4x = 0.0;
    for (int i = 0; i < N; i++) {
        const double v = s->vx[i], x = s->x[i] - x0[i];
        mv += v * v;
        mx += x * x;
        mc += x * v;
        m4v += v * v * v * v;
        m4x += x * x * x * x;
    }
    VERBOSE("free flight (%s): continuum 2Dt^3/3M^2 = %.5g\n", kicks ? "kicks" : "exact",
            2.0 * D * t * t * t / (3.0 * M * M));
    const double got[3] = {mv / N, mx / N, mc / N}, want[3] = {vv, xx, xv};
    assert_moments(kicks ? "free flight (kicks)" : "free flight (exact)", got, want, N);
    /* the ledger: injected energy is exactly the kinetic energy gained (no contacts) */
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-9 * l.injected,
                  "free-flight ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    free(x0);
    gr_sim_free(s);
}

START_TEST(test_free_flight_exact) { free_moments(0); }
END_TEST

START_TEST(test_free_flight_kicks) { free_moments(1); }
END_TEST

/* ---- ledger and momentum on the 1D RFM scene ----------------------------------------------- */

/* The ledger residual of a Verlet run of the scene, relative to the injected energy. */
static double verlet_residual(const char *scene, const char *const *over, int64_t steps)
{
    gr_scene sc = load(scene, over);
    gr_sim *v = create(&sc);
    step(v, steps);
    gr_ledger lv = gr_sim_ledger(v);
    const double rel_v = gr_ledger_residual(&lv) / lv.injected;
    gr_sim_free(v);
    VERBOSE("%s ledger: Verlet residual %.3g of injected %.4g J\n", scene, rel_v, lv.injected);
    return rel_v;
}

START_TEST(test_ledger_momentum_1d)
{
    const char *over[] = {quick() ? "system.N=200" : "system.N=1000",
                          quick() ? "system.reduced_length=0.2" : "system.reduced_length=1",
                          "integrator.kind=hybrid", "integrator.kick_interval=3e-5", NULL};
    gr_scene sc = load("rfm-1d.ini", over);
    gr_sim *s = create(&sc);
    const int64_t steps = quick() ? 30000 : 200000;
    step(s, steps / 2);
    step(s, steps / 2 + 7); /* a span that is not a multiple of the window */
    gr_ledger l = gr_sim_ledger(s);
    const double rel = gr_ledger_residual(&l) / l.injected;
    double p[2];
    gr_sim_momentum(s, p);
    const double pscale = s->mass * sqrt(gr_sim_temperature(s)) * s->n;
    gr_hybrid_stats st;
    gr_sim_hybrid_stats(s, &st);
    VERBOSE("1D ledger: residual %.3g of injected %.4g J; momentum %.3g (scale %.3g); "
            "active %.3f, rollbacks %lld, collisions %lld\n",
            rel, l.injected, p[0], pscale, st.active_fraction, (long long)st.rollbacks,
            (long long)gr_sim_collisions(s));
    /* the same scene with Verlet: the residual is the springs' O(dt^2) energy error, which the
     * hybrid shares (same steps for every contact); every other energy change is booked exactly */
    const char *ov[] = {over[0], over[1], NULL};
    const double rel_v = verlet_residual("rfm-1d.ini", ov, steps + 7);
    ck_assert_int_eq(gr_sim_steps(s), steps + 7);
    ck_assert_msg(gr_sim_collisions(s) > 1000, "only %lld collisions",
                  (long long)gr_sim_collisions(s));
    ck_assert_msg(fabs(rel) < 1.25 * fabs(rel_v) + 2e-4,
                  "ledger residual %g of the injected energy (Verlet %g)", rel, rel_v);
    ck_assert_msg(fabs(p[0]) < 1e-12 * pscale, "momentum %g (scale %g)", p[0], pscale);
    ck_assert_msg(st.active_fraction > 0.0 && st.active_fraction < 1.0, "active fraction %g",
                  st.active_fraction);
    gr_sim_free(s);
}
END_TEST

START_TEST(test_ledger_momentum_2d)
{
    /* _i = 1: rotating discs with sliding friction (the spins' energy in the ledger), 300 */
    const bool small = quick() || _i;
    const char *over[] = {"integrator.kind=hybrid",
                          "integrator.kick_interval=2e-5",
                          small ? "system.N=300" : "system.N=1000",
                          small ? "system.L=0.0775" : "system.L=0.1414",
                          _i ? "model.rotation=true" : NULL,
                          "model.tangential=sliding_friction",
                          "model.mu=0.3",
                          NULL};
    gr_scene sc = load("steady-2d.ini", over);
    gr_sim *s = create(&sc);
    const int64_t steps = quick() ? 3000 : (_i ? 10000 : 20000);
    step(s, steps);
    gr_ledger l = gr_sim_ledger(s);
    const double rel = gr_ledger_residual(&l) / l.injected;
    double p[2];
    gr_sim_momentum(s, p);
    const double pscale = s->mass * sqrt(gr_sim_temperature(s)) * s->n;
    gr_hybrid_stats st;
    gr_sim_hybrid_stats(s, &st);
    VERBOSE("2D ledger: residual %.3g of injected %.4g J; momentum (%.3g, %.3g) (scale %.3g); "
            "active %.3f, rollbacks %lld, "
            "collisions %lld\n",
            rel, l.injected, p[0], p[1], pscale, st.active_fraction, (long long)st.rollbacks,
            (long long)gr_sim_collisions(s));
    ck_assert_msg(gr_sim_collisions(s) > 100, "only %lld collisions",
                  (long long)gr_sim_collisions(s));
    ck_assert_msg(fabs(p[0]) < 1e-12 * pscale && fabs(p[1]) < 1e-12 * pscale, "momentum (%g, %g)",
                  p[0], p[1]);
    if (_i) { /* rotation: the residual is Verlet's time-step error; within 1.25x of Verlet's */
        gr_scene sv = load("steady-2d.ini", over + 2); /* the same scene without the hybrid */
        gr_sim *v = create(&sv);
        step(v, steps);
        gr_ledger lv = gr_sim_ledger(v);
        const double rv = gr_ledger_residual(&lv) / lv.injected;
        VERBOSE("2D ledger with rotation: Verlet's residual %.3g of injected %.4g J\n", rv,
                lv.injected);
        ck_assert_msg(fabs(rel) < 1.25 * fabs(rv) + 1e-4, "ledger residual %g, Verlet's %g", rel,
                      rv);
        gr_sim_free(v);
    } else {
        ck_assert_msg(fabs(rel) < 3e-3, "ledger residual %g of the injected energy", rel);
    }
    gr_sim_free(s);
}
END_TEST

/* ---- the active set does not change the result --------------------------------------------- */

/* Without noise a hybrid run whose every particle is active is Verlet, operation for operation:
 * same forces, same kick-drift-kick arithmetic. With the normal margin free particles leap
 * (x + v tau instead of m additions of v dt), which only changes rounding. */
static void no_noise_case(const char *scene, const char *size0, const char *size1, int64_t n,
                          const char *const *extra)
{
    /* the hybrid's keys, then the scene's own (ov: the same without the hybrid) */
    const char *oh[] = {"integrator.kind=hybrid",
                        "integrator.kick_interval=2e-5",
                        size0,
                        size1,
                        "placement.v0=1",
                        "noise.mode=none",
                        extra ? extra[0] : NULL,
                        extra ? extra[1] : NULL,
                        extra ? extra[2] : NULL,
                        NULL};
    const char *const *ov = oh + 2;
    gr_scene sv = load(scene, ov), sh = load(scene, oh);
    gr_sim *v = create(&sv), *all = create(&sh), *h = create(&sh);
    gr_hybrid_set_margin(all, 1e9);
    step(v, n);
    step(all, n - 13);
    step(all, 13);
    step(h, n);
    const double d_all = max_diff(v, all), d_h = max_diff(v, h);
    gr_ledger lv = gr_sim_ledger(v), la = gr_sim_ledger(all);
    gr_hybrid_stats st;
    gr_sim_hybrid_stats(h, &st);
    VERBOSE("%s no noise: |x_verlet - x_all_active| = %.3g m, |x_verlet - x_hybrid| = %.3g m; "
            "collisions %lld / %lld / %lld; "
            "hybrid active %.3f\n",
            scene, d_all, d_h, (long long)gr_sim_collisions(v), (long long)gr_sim_collisions(all),
            (long long)gr_sim_collisions(h), st.active_fraction);
    ck_assert_msg(gr_sim_collisions(v) > 50, "only %lld collisions",
                  (long long)gr_sim_collisions(v));
    ck_assert_msg(d_all == 0.0, "all-active hybrid differs from Verlet by %g m", d_all);
    if (v->omega) { /* rotation: the spins too, to the last bit all active, to rounding else */
        double dw_all, dw_h, wmax;
        gr_test_spin_diff(v, all, h, &dw_all, &dw_h, &wmax);
        VERBOSE("spins: |w_verlet - w_all_active| = %.3g, |w_verlet - w_hybrid| = %.3g rad/s of "
                "%.3g rad/s\n",
                dw_all, dw_h, wmax);
        ck_assert_msg(wmax > 0.0 && dw_all == 0.0, "all-active spins differ by %g rad/s", dw_all);
        ck_assert_msg(dw_h < 1e-6 * wmax, "hybrid spins differ by %g rad/s", dw_h);
    }
    ck_assert_int_eq(gr_sim_collisions(all), gr_sim_collisions(v));
    ck_assert_msg(fabs(la.dissipated_normal - lv.dissipated_normal) <= 1e-12 * lv.dissipated_normal,
                  "dissipation %.17g vs %.17g", la.dissipated_normal, lv.dissipated_normal);
    ck_assert_msg(d_h < 1e-9, "hybrid differs from Verlet by %g m", d_h);
    ck_assert_int_eq(gr_sim_collisions(h), gr_sim_collisions(v));
    ck_assert_msg(st.active_fraction < 0.9, "active fraction %g", st.active_fraction);
    gr_sim_free(v);
    gr_sim_free(all);
    gr_sim_free(h);
}

START_TEST(test_no_noise_equals_verlet)
{
    no_noise_case("rfm-1d.ini", "system.N=200", "system.reduced_length=0.2", quick() ? 3000 : 10000,
                  NULL);
}
END_TEST

/* Walls and gravity: a vibrated bed of 150 discs, then of 200 spheres (no noise), all active =
 * Verlet to the last bit, and the normal margin (grains that could reach a wall active, the others
 * leaping parabolas) differs by rounding. */
START_TEST(test_no_noise_equals_verlet_bed)
{
    static const char *const bed[] = {"boundary.amplitude=2e-3", "integrator.dt=4e-7", NULL};
    /* 3D: the bed of spheres with the tangential dashpot, without rotation */
    static const char *const bed3[] = {"integrator.dt=2e-7", "model.rotation=false",
                                       "model.tangential=tangential_dashpot"};
    if (_i == 0) {
        no_noise_case("vibrated-bed.ini", "system.N=150", "placement.kind=uniform", 60000, bed);
    } else {
        no_noise_case("vibrated-bed-3d.ini", "system.N=200", "run.seed=1", 40000, bed3);
    }
}
END_TEST

/* Rotation: discs with the scene's tangential dashpot and rolling resistance, spheres with sliding
 * friction. The child kicks the active grains' spins as step.c does (gr_verlet_spin_kicks), so all
 * active is Verlet to the last bit with the spins too, and the normal margin (free grains keep
 * their spins: no torque without a contact) differs only by rounding. */
START_TEST(test_no_noise_equals_verlet_rotation)
{
    static const char *const spin[] = {"model.rotation=true", "model.tangential=sliding_friction",
                                       "model.mu=0.3"};
    static const char *const rolling[] = {"model.rotation=true", "model.rolling=rolling_friction",
                                          "model.mu_r=0.1"};
    if (_i == 0) {
        no_noise_case("steady-2d.ini", "system.N=200", "system.L=0.06", 2000, rolling);
    } else {
        no_noise_case("rfm-3d.ini", "system.N=216", "system.packing_fraction=0.2", 4000, spin);
    }
}
END_TEST

/* With noise, each particle's noise path in a window is fixed by the counters whether it is
 * leaped or stepped (bridged kicks), so the normal margin, a huge margin (everybody active) and
 * a tiny one (c = 0.2 in 1D, 0 in 2D, 0.5 in 3D: many misses, each redone after a rollback) give the same
 * trajectory up to rounding. */
static void same_path(const char *scene, const char *const *over, int64_t n, double tol,
                      double tiny_c)
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
    VERBOSE("%s: |all - normal| %.3g m, |all - tiny| %.3g m; active %.3f / %.3f / %.3f; rollbacks "
            "%lld / %lld; "
            "collisions %lld / %lld / %lld\n",
            scene, d_h, d_t, sa.active_fraction, sh.active_fraction, st.active_fraction,
            (long long)sh.rollbacks, (long long)st.rollbacks, (long long)gr_sim_collisions(all),
            (long long)gr_sim_collisions(h), (long long)gr_sim_collisions(tiny));
    ck_assert_msg(sa.active_fraction == 1.0, "huge margin: active fraction %g", sa.active_fraction);
    ck_assert_msg(gr_sim_collisions(all) > 20, "only %lld collisions",
                  (long long)gr_sim_collisions(all));
    ck_assert_msg(st.rollbacks > 0, "c = %g never rolled back", tiny_c);
    ck_assert_msg(d_h < tol, "normal margin differs from all-active by %g m", d_h);
    ck_assert_msg(d_t < tol, "rollbacks differ from all-active by %g m", d_t);
    ck_assert_int_eq(gr_sim_collisions(h), gr_sim_collisions(all));
    ck_assert_int_eq(gr_sim_collisions(tiny), gr_sim_collisions(all));
    gr_sim_free(all);
    gr_sim_free(h);
    gr_sim_free(tiny);
}

START_TEST(test_active_set_invariance_1d)
{
    const char *over[] = {
        "system.N=200",           "system.reduced_length=0.2",     "placement.v0=0.5",
        "integrator.kind=hybrid", "integrator.kick_interval=5e-5", NULL};
    /* chaos: rounding differences (1e-13 m after the first leaps) grow by collisions to ~1e-9 m
     * after 10^4 steps here (1e-5 m after 2 10^4); 5000 steps keep them at ~1e-12 m */
    same_path("rfm-1d.ini", over, quick() ? 3000 : 5000, 1e-9, 0.2);
}
END_TEST

/* same_path on a driven gas of discs or spheres (scene, its N and size keys) with tangential law
 * k of: the tangential dashpot, sliding friction (2.7), none; strong noise and long windows, so
 * that a tiny margin misses often. */
static void invariance_case(const char *scene, const char *size0, const char *size1, int k,
                            int64_t n, double tiny_c)
{
    static const char *const tangential[][3] = {
        {"model.tangential=tangential_dashpot", "model.eps_t=0.6", NULL},
        {"model.tangential=sliding_friction", "model.mu=0.3", NULL},
        {"model.tangential=none", "model.eps_n=0.6", NULL},
        {"model.tangential=sliding_friction", "model.mu=0.3", "model.rotation=true"}};
    const char *over[] = {size0,
                          size1,
                          "placement.kind=random",
                          "placement.v0=0.5",
                          "noise.D=1e-6",
                          "integrator.kind=hybrid",
                          "integrator.kick_interval=1e-4",
                          tangential[k][0],
                          tangential[k][1],
                          tangential[k][2],
                          NULL};
    same_path(scene, over, n, 1e-9, tiny_c);
}

/* 2D with each tangential law of the scene's contact model: the tangential dashpot of
 * steady-2d.ini, sliding friction (2.7) and none */
START_TEST(test_active_set_invariance_2d)
{
    /* chaos amplifies rounding (1e-16 m after 500 steps) about tenfold per 500 steps, a bit faster
     * with friction (2e-9 m after 4000 steps, 2.5e-10 m after 3000): horizons keep it below 1e-9 m */
    invariance_case("steady-2d.ini", "system.N=200", "system.L=0.06", _i,
                    quick() || _i == 3 ? 2500 : (_i == 1 ? 3000 : 4000), 0.0);
}
END_TEST

/* Walls and gravity with noise (com mode; symmetrised is refused with walls): the bed driven by the
 * random force follows the same path all active, with the normal margin and with a tiny one that
 * rolls back (grains found at a wall or a free partner at the window's end are redone active). */
START_TEST(test_active_set_invariance_bed)
{
    const char *over[] = {"system.N=150",
                          "placement.kind=uniform",
                          "boundary.amplitude=2e-3",
                          "integrator.dt=4e-7",
                          "integrator.kind=hybrid",
                          "integrator.kick_interval=1e-4",
                          "driving.kind=rfm",
                          "noise.mode=com",
                          "noise.D=3e-7",
                          NULL};
    same_path("vibrated-bed.ini", over, 30000, 1e-9, 0.0);
}
END_TEST

/* ---- spheres (dim = 3) ---------------------------------------------------------------------- */

/* Exact free flight of spheres: a gas so dilute that nobody can touch (the active set stays
 * empty), raw noise, from rest. After 24 windows every component of (v, r - r0) has the law of
 * n = 2350 Verlet kicks (as free_moments), checked by z-scores over the 3 N components; the
 * components are independent (<vx vy>, <vy vz>, <vz vx> against 0) and the ledger closes. */
START_TEST(test_free_flight_3d)
{
    const int N = quick() ? 512 : 4096;
    char nb[64];
    snprintf(nb, sizeof nb, "system.N=%d", N);
    const char *over[] = {nb, "system.packing_fraction=1e-6", FREE_FLIGHT_KEYS, NULL};
    gr_scene sc = load("rfm-3d.ini", over);
    gr_sim *s = create(&sc);
    double *r0 = malloc(sizeof(double) * 3 * N);
    memcpy(r0, s->x, sizeof(double) * N);
    memcpy(r0 + N, s->y, sizeof(double) * N);
    memcpy(r0 + 2 * N, s->z, sizeof(double) * N);
    const int64_t n = 2350;
    free_windows(s);
    const double dt = s->dt, M = s->mass, D = sc.D, L = s->L, dn = (double)n;
    const double vv = 2.0 * D * n * dt / (M * M),
                 xx = 2.0 * D * dt * dt * dt / (M * M) * dn * (dn + 1.0) * (2.0 * dn + 1.0) / 6.0,
                 xv = 2.0 * D * dt * dt / (M * M) * dn * (dn + 1.0) / 2.0;
    const double *pos[3] = {s->x, s->y, s->z}, *vel[3] = {s->vx, s->vy, s->vz};
    double mv = 0.0, mx = 0.0, mc = 0.0, cross[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < 3; c++) {
        for (int i = 0; i < N; i++) {
            double x = pos[c][i] - r0[c * N + i];
            x = x > 0.5 * L ? x - L : (x < -0.5 * L ? x + L : x);
            const double v = vel[c][i];
            mv += v * v;
            mx += x * x;
            mc += x * v;
            cross[c] += v * vel[(c + 1) % 3][i];
        }
    }
    const int K = 3 * N;
    const double got[3] = {mv / K, mx / K, mc / K}, want[3] = {vv, xx, xv};
    assert_moments("3D free flight", got, want, K);
    for (int c = 0; c < 3; c++) { /* Var(v_a v_b) = vv^2 for independent components */
        const double z = cross[c] / N / sqrt(vv * vv / N);
        ck_assert_msg(fabs(z) < 4.5, "components %d and %d correlated: z = %g", c, (c + 1) % 3, z);
    }
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-9 * l.injected,
                  "free-flight ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    free(r0);
    gr_sim_free(s);
}
END_TEST

/* The ledger closes (the residual is the springs' O(dt^2) error, as Verlet's on the same scene)
 * and the momentum stays zero with symmetrised noise, for spheres. */
START_TEST(test_ledger_momentum_3d)
{
    const char *over[] = {quick() ? "system.N=216" : "system.N=1000",
                          "system.packing_fraction=0.2",
                          "placement.v0=1",
                          "integrator.kind=hybrid",
                          "integrator.kick_interval=3e-5",
                          NULL};
    gr_scene sc = load("rfm-3d.ini", over);
    gr_sim *s = create(&sc);
    const int64_t steps = quick() ? 5000 : 10000;
    step(s, steps / 2);
    step(s, steps / 2 + 7);
    /* momentum from the velocities (gr_sim_momentum reports x and y only) */
    double p[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < s->n; i++) {
        p[0] += s->mass * s->vx[i];
        p[1] += s->mass * s->vy[i];
        p[2] += s->mass * s->vz[i];
    }
    const double pscale = s->mass * sqrt(gr_sim_temperature(s)) * s->n;
    gr_ledger l = gr_sim_ledger(s);
    const double rel = gr_ledger_residual(&l) / l.injected;
    gr_hybrid_stats st;
    gr_sim_hybrid_stats(s, &st);
    const char *ov[] = {over[0], over[1], over[2], NULL};
    const double rel_v = verlet_residual("rfm-3d.ini", ov, steps + 7);
    VERBOSE("3D ledger: residual %.3g of injected %.4g J (Verlet %.3g); momentum (%.3g, %.3g, "
            "%.3g) (scale %.3g); active %.3f, rollbacks %lld, collisions %lld\n",
            rel, l.injected, rel_v, p[0], p[1], p[2], pscale, st.active_fraction,
            (long long)st.rollbacks, (long long)gr_sim_collisions(s));
    ck_assert_int_eq(gr_sim_steps(s), steps + 7);
    ck_assert_msg(gr_sim_collisions(s) > 100, "only %lld collisions",
                  (long long)gr_sim_collisions(s));
    ck_assert_msg(fabs(rel) < 1.25 * fabs(rel_v) + 2e-4,
                  "ledger residual %g of the injected energy (Verlet %g)", rel, rel_v);
    for (int c = 0; c < 3; c++) {
        ck_assert_msg(fabs(p[c]) < 1e-12 * pscale, "momentum[%d] %g (scale %g)", c, p[c], pscale);
    }
    ck_assert_msg(st.active_fraction > 0.0 && st.active_fraction < 1.0, "active fraction %g",
                  st.active_fraction);
    gr_sim_free(s);
}
END_TEST

/* test_no_noise_equals_verlet for spheres: all active = Verlet to the last bit (same positions,
 * collisions, dissipation); the normal margin differs by rounding only. */
START_TEST(test_no_noise_equals_verlet_3d)
{
    no_noise_case("rfm-3d.ini", "system.N=216", "system.packing_fraction=0.2",
                  quick() ? 4000 : 6000, NULL);
}
END_TEST

/* test_active_set_invariance_2d for spheres, with each tangential law the hybrid runs in 3D
 * (no rotation): tangential dashpot, sliding friction, none. The tiny margin is c = 0.5 (9-13
 * rollbacks here): at c = 0 the rule leaves the noise out altogether, and in this strongly driven
 * gas two free spheres then graze inside a window within the first 200 steps (the one miss the
 * design admits, docs/hybrid.md "What can still go wrong"; c = 0.5 and above see none). */
START_TEST(test_active_set_invariance_3d)
{
    invariance_case("rfm-3d.ini", "system.N=216", "system.packing_fraction=0.25", _i,
                    quick() || _i == 3 ? 1500 : 3000, 0.5);
}
END_TEST

/* ---- agreement with Verlet: 1D at eps = 0.1, 0.5, 0.9 and the 2D steady-state scene --------- */

/* The test: K = 16 independent runs per integrator (Verlet seeds 1001..1016, hybrid 2001..2016)
 * from the scene's start; each run gives one time average per observable over the same interval.
 * The two sets of K values are compared by the Mann-Whitney rank test (z of the U statistic,
 * normal approximation): under "same law" the runs of both integrators are i.i.d. draws of one
 * distribution, so the test is exact whatever that distribution looks like. This matters: per-run
 * gap moments are skewed (a few large voids), and a t-test on 12-16 such values was seen to give
 * |z| = 3.5-6 between equal-law ensembles (checked against 1000 seeds). Every observable must have
 * |z| < 4 (two-sided p ~ 6e-5 each). Observables (2.19, 3.11, 3.18): T; the core of P(v) as the
 * flatness <c^4>/<c^2>^2 and the fractions of velocity components with |c| / sqrt(<c^2>) below 0.5
 * and 1 (the sample's own scale: the shape, not T twice); 1D: the nearest-neighbour distribution
 * as <R^2> (R = gap / mean gap) and the fractions of gaps with R < 0.05, 0.05 <= R < 0.5 and
 * 0.5 <= R < 2. The runs are short (the approach to the steady state is part of the law being
 * compared); bench/hybrid_agreement.sh does the long steady-state comparison (docs/hybrid.md). */
enum { O_T, O_FLAT, O_CORE05, O_CORE1, O_R2, O_GAP0, O_GAP1, O_GAP2, N_OBS };
static const char *const obs_name[N_OBS] = {
    "T",     "flatness",  "P(|c|<0.5)",         "P(|c|<1)",
    "<R^2>", "P(R<0.05)", "P(R<0.5)-P(R<0.05)", "P(R<2)-P(R<0.5)"};

enum { AGREE_RUNS = 16 };

typedef struct ensemble {
    double val[N_OBS][AGREE_RUNS]; /* per-run time averages */
    int runs;
    double cpu;
} ensemble;

/* The observables of the state now into o[]. */
static void observe(const gr_sim *s, double o[N_OBS])
{
    const double *vel[3] = {s->vx, s->vy, s->vz};
    double m2 = 0.0, m4 = 0.0;
    for (int c = 0; c < s->dim; c++) {
        for (int i = 0; i < s->n; i++) {
            const double v2 = vel[c][i] * vel[c][i];
            m2 += v2;
            m4 += v2 * v2;
        }
    }
    const double nc = (double)s->n * s->dim;
    m2 /= nc;
    m4 /= nc;
    double core05 = 0.0, core1 = 0.0;
    for (int c = 0; c < s->dim; c++) {
        for (int i = 0; i < s->n; i++) {
            const double v2 = vel[c][i] * vel[c][i];
            core05 += v2 < 0.25 * m2;
            core1 += v2 < m2;
        }
    }
    o[O_T] = gr_sim_temperature(s);
    o[O_FLAT] = m4 / (m2 * m2);
    o[O_CORE05] = core05 / nc;
    o[O_CORE1] = core1 / nc;
    for (int k = O_R2; k < N_OBS; k++) {
        o[k] = 0.0;
    }
    if (s->dim == 1) {
        const double mean_gap = (s->L - s->n * s->d) / s->n;
        for (int i = 0; i < s->n; i++) {
            const double g =
                (i + 1 < s->n ? s->x[i + 1] - s->x[i] : s->x[0] + s->L - s->x[i]) - s->d;
            const double R = g / mean_gap;
            o[O_R2] += R * R / s->n;
            o[O_GAP0] += (R < 0.05) / (double)s->n;
            o[O_GAP1] += (R >= 0.05 && R < 0.5) / (double)s->n;
            o[O_GAP2] += (R >= 0.5 && R < 2.0) / (double)s->n;
        }
    }
}

/* One run: the time averages of the observables (sampled every 1000 steps) over [warm, warm + dur]
 * into the ensemble. */
static void run_into(const char *scene, const char *const *over, double warm, double dur,
                     ensemble *e)
{
    gr_scene sc = load(scene, over);
    gr_sim *s = create(&sc);
    const int64_t every = 1000, samples = (int64_t)llround(dur / s->dt) / every;
    struct timespec a, b;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &a);
    step(s, (int64_t)llround(warm / s->dt));
    double avg[N_OBS] = {0}, o[N_OBS];
    for (int64_t k = 0; k < samples; k++) {
        step(s, every);
        observe(s, o);
        for (int q = 0; q < N_OBS; q++) {
            avg[q] += o[q] / (double)samples;
        }
    }
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &b);
    e->cpu += (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
    for (int q = 0; q < N_OBS; q++) {
        e->val[q][e->runs] = avg[q];
    }
    e->runs++;
    gr_sim_free(s);
}

/* K runs of `scene` + base overrides with seeds first_seed + r (+ extra overrides). */
static ensemble run_ensemble(const char *scene, const char *const *base, const char *const *extra,
                             int first_seed, double warm, double dur)
{
    ensemble e = {0};
    for (int r = 0; r < AGREE_RUNS; r++) {
        char seed[32];
        snprintf(seed, sizeof seed, "run.seed=%d", first_seed + r);
        const char *over[24];
        int n = 0;
        for (int k = 0; base[k]; k++) {
            over[n++] = base[k];
        }
        for (int k = 0; extra && extra[k]; k++) {
            over[n++] = extra[k];
        }
        over[n++] = seed;
        over[n] = NULL;
        run_into(scene, over, warm, dur, &e);
    }
    return e;
}

static void mean_err(const double *x, int n, double *m, double *se)
{
    double s = 0.0, s2 = 0.0;
    for (int r = 0; r < n; r++) {
        s += x[r];
    }
    *m = s / n;
    for (int r = 0; r < n; r++) {
        s2 += (x[r] - *m) * (x[r] - *m);
    }
    *se = sqrt(s2 / (n - 1) / n);
}

/* Mann-Whitney: z of U = #{(i, j): b_j > a_i} (+ 1/2 per tie) against its law under "a and b
 * are draws of one distribution" (mean n m / 2, variance n m (n + m + 1) / 12); z > 0 when b
 * tends to be larger. */
static double rank_z(const double *a, int n, const double *b, int m)
{
    double u = 0.0;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < m; j++) {
            u += b[j] > a[i] ? 1.0 : (b[j] == a[i] ? 0.5 : 0.0);
        }
    }
    return (u - 0.5 * n * m) / sqrt(n * m * (n + m + 1) / 12.0);
}

/* Rank z (hybrid against Verlet) of the first n_obs observables; means +- standard errors shown. */
static void compare(const char *label, const ensemble *v, const ensemble *h, int n_obs, double *z)
{
    VERBOSE("agreement %s (%d runs each; cpu verlet %.1f s, hybrid %.1f s):\n", label, v->runs,
            v->cpu, h->cpu);
    for (int k = 0; k < n_obs; k++) {
        double mv, ev, mh, eh;
        mean_err(v->val[k], v->runs, &mv, &ev);
        mean_err(h->val[k], h->runs, &mh, &eh);
        z[k] = rank_z(v->val[k], v->runs, h->val[k], h->runs);
        VERBOSE("  %-20s verlet %.5g +- %.2g, hybrid %.5g +- %.2g, rank z %+.2f\n", obs_name[k], mv,
                ev, mh, eh, z[k]);
    }
}

static const char *const hybrid_over[] = {"integrator.kind=hybrid", "integrator.kick_interval=3e-5",
                                          NULL};

/* 1D RFM scene (N = 1000, L' = 1 m) at eps = 0.1, 0.5, 0.9. At
 * eps = 0.9 the same comparison must also fail for a hybrid whose noise is 1.5x too strong
 * (T about 30 % higher; with 16 runs each |z| > 4 needs at most 6 of the 256 pairs out of order):
 * the test can tell a wrong result. */
START_TEST(test_agreement_1d)
{
    static const char *const eps[] = {"model.eps_n=0.1", "model.eps_n=0.5", "model.eps_n=0.9"};
    const char *base[] = {"system.N=1000", "system.reduced_length=1", eps[_i], NULL};
    const double warm = 0.05, dur = 0.15;
    const ensemble v = run_ensemble("rfm-1d.ini", base, NULL, 1001, warm, dur);
    const ensemble h = run_ensemble("rfm-1d.ini", base, hybrid_over, 2001, warm, dur);
    double z[N_OBS];
    compare(eps[_i], &v, &h, N_OBS, z);
    for (int k = 0; k < N_OBS; k++) {
        ck_assert_msg(fabs(z[k]) < 4.0, "%s: %s differs by z = %.2f", eps[_i], obs_name[k], z[k]);
    }
    if (_i == 2) {
        const char *strong[] = {"integrator.kind=hybrid", "integrator.kick_interval=3e-5",
                                "noise.D=1.5e-8", NULL};
        const ensemble hd = run_ensemble("rfm-1d.ini", base, strong, 2001, warm, dur);
        compare("eps 0.9, hybrid with D x 1.5 (must differ)", &v, &hd, N_OBS, z);
        ck_assert_msg(z[O_T] > 4.0,
                      "the agreement test cannot see a 1.5x noise strength: z(T) = %.2f", z[O_T]);
    }
}
END_TEST

/* The 2D steady-state scene of sec. 2.3.3 (docs/scenes/steady-2d.ini: phi = 0.353... with eps_n =
 * eps_t = 0.6) at N = 500, L = 0.1 m (same packing fraction) from its hexagonal
 * start: T and the core of P(v). */
/* T and the core of P(v) of a 2D or 3D scene, Verlet against the hybrid (rank z < 4 each). */
static void agreement_case(const char *label, const char *scene, const char *const *base,
                           double warm, double dur)
{
    const ensemble v = run_ensemble(scene, base, NULL, 1001, warm, dur);
    const ensemble h = run_ensemble(scene, base, hybrid_over, 2001, warm, dur);
    double z[N_OBS];
    compare(label, &v, &h, O_R2, z);
    for (int k = 0; k < O_R2; k++) {
        ck_assert_msg(fabs(z[k]) < 4.0, "%s: %s differs by z = %.2f", label, obs_name[k], z[k]);
    }
}

START_TEST(test_agreement_2d)
{
    const char *base[] = {"system.N=500", "system.L=0.1", NULL};
    agreement_case("2D steady", "steady-2d.ini", base, 0.02, 0.06);
}
END_TEST

/* Spheres: docs/scenes/rfm-3d.ini (phi = 0.1, eps_n = 0.9, D = 1e-8 N^2 s) at N = 343 from its
 * cubic lattice with v0 = 1 m/s, heating towards its steady state over the compared interval. */
START_TEST(test_agreement_3d)
{
    const char *base[] = {"system.N=343", "placement.v0=1", NULL};
    agreement_case("3D driven spheres", "rfm-3d.ini", base, 0.01, 0.03);
}
END_TEST

/* ---- contact events ------------------------------------------------------------------------ */

/* With tracking on, the hybrid records the same events (particle, kind, step) as an all-active
 * run of the same seed, mapped back to parent indices. */
START_TEST(test_contact_events)
{
    const char *over[] = {
        "system.N=200",           "system.reduced_length=0.2",     "placement.v0=0.5",
        "integrator.kind=hybrid", "integrator.kick_interval=5e-5", NULL};
    gr_scene sc = load("rfm-1d.ini", over);
    gr_sim *all = create(&sc), *h = create(&sc);
    gr_hybrid_set_margin(all, 1e9);
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_track_contacts(all, &err), GR_OK);
    ck_assert_int_eq(gr_sim_track_contacts(h, &err), GR_OK);
    step(all, 5000);
    step(h, 5000);
    int64_t na, nh;
    const gr_contact_event *ea = gr_sim_events(all, &na), *eh = gr_sim_events(h, &nh);
    VERBOSE("events: %lld all-active, %lld hybrid\n", (long long)na, (long long)nh);
    ck_assert_msg(na > 20, "only %lld events", (long long)na);
    ck_assert_int_eq(na, nh);
    /* order within a step differs (child order); compare as multisets keyed by (t, i, kind) */
    int64_t matched = 0;
    for (int64_t k = 0; k < nh; k++) {
        ck_assert(eh[k].i >= 0 && eh[k].i < sc.N);
        for (int64_t q = 0; q < na; q++) {
            if (ea[q].i == eh[k].i && ea[q].kind == eh[k].kind && ea[q].t == eh[k].t) {
                matched++;
                break;
            }
        }
    }
    ck_assert_int_eq(matched, nh);
    gr_sim_free(all);
    gr_sim_free(h);
}
END_TEST

/* ---- refusals ------------------------------------------------------------------------------ */

START_TEST(test_refuse_window)
{
    const char *over[] = {"integrator.kind=hybrid", "integrator.kick_interval=2.5e-6", NULL};
    gr_scene sc = load("rfm-1d.ini", over);
    gr_sim *s = NULL;
    gr_error err = {0};
    int rc = gr_sim_create(&sc, &s, &err);
    ck_assert_int_eq(rc, GR_EINVAL);
    ck_assert_ptr_null(s);
    ck_assert_msg(strstr(err.message, "kick_interval") && strstr(err.message, "multiple") &&
                      strstr(err.message, "rfm-1d.ini"),
                  "message: %s", err.message);
    /* left at its default, the window is the nearest whole number of steps: the mixture's dt
     * (from its contact time) does not divide 1e-4 s */
    const char *def[] = {"integrator.kind=hybrid", "noise.mode=com", NULL};
    gr_scene sd = load("bidisperse-mixture.ini", def);
    ck_assert(sd.kick_interval_default);
    s = create(&sd);
    const double ratio = 1e-4 / s->dt;
    ck_assert_msg(fabs(ratio - round(ratio)) > 1e-3, "dt %g divides the window", s->dt);
    gr_hybrid_stats st;
    ck_assert(gr_sim_hybrid_stats(s, &st));
    ck_assert_msg(st.window == round(ratio) * s->dt, "window %.17g s, dt %.17g s", st.window,
                  s->dt);
    gr_sim_free(s);
}
END_TEST

static Suite *hybrid_suite(void)
{
    Suite *s = suite_create("hybrid");
    TCase *t = tcase_create("core");
    tcase_set_timeout(t, 600);
    tcase_add_test(t, test_free_flight_exact);
    tcase_add_test(t, test_free_flight_kicks);
    tcase_add_test(t, test_ledger_momentum_1d);
    tcase_add_loop_test(t, test_ledger_momentum_2d, 0, 2);
    tcase_add_test(t, test_no_noise_equals_verlet);
    tcase_add_test(t, test_active_set_invariance_1d);
    tcase_add_loop_test(t, test_active_set_invariance_2d, 0, 4);
    tcase_add_loop_test(t, test_no_noise_equals_verlet_rotation, 0, 2);
    tcase_add_loop_test(t, test_no_noise_equals_verlet_bed, 0, 2);
    tcase_add_test(t, test_active_set_invariance_bed);
    tcase_add_test(t, test_contact_events);
    tcase_add_test(t, test_free_flight_3d);
    tcase_add_test(t, test_ledger_momentum_3d);
    tcase_add_test(t, test_no_noise_equals_verlet_3d);
    tcase_add_loop_test(t, test_active_set_invariance_3d, 0, 4);
    tcase_add_test(t, test_refuse_window);
    if (!quick()) { /* statistics: the release pass's; their code runs in the tests above */
        tcase_add_loop_test(t, test_agreement_1d, 0, 3);
        tcase_add_test(t, test_agreement_2d);
        tcase_add_test(t, test_agreement_3d);
    }
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(hybrid_suite()); }
