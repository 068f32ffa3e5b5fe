/* Tests of rough and viscoelastic hard discs in the event-driven integrator (models/hard_sphere.h:
 * gr_event_collide_rough, Walton's rule; src/integrators/event/: eps_n(v) of the hertz viscoelastic
 * contact). Per collision: the energy loss against Walton's analytic value, linear and angular
 * momentum, the Coulomb limit; in runs: beta = -1 reproduces the smooth integrator bit for bit,
 * beta = +1 with eps_n = 1 conserves energy, a noisy driven run's ledger closes; viscoelastic
 * collisions give hertz's eps_n(v); rough scenes with the hybrid integrator are refused.
 *
 * Particles: r = 1.5 mm, M = 3.53e-5 kg (Table 2.2). Expected values are computed here from the
 * formulas (Luding, Huthmann, McNamara & Zippelius, PRE 58, 3416 (1998), eqs. 2-7), not by the
 * library. GRANULE_TEST_QUICK=1 shortens the runs. */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/blob.h"
#include "core/sim_internal.h"
#include "core/sim_state.h"
#include "models/hard_sphere.h"
#include "granule/collide.h"
#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "integrators/event/event_internal.h"
#include "check_main.h"
#include "test_env.h"
#include "test_scenes.h"

#define MASS 3.53e-5
#define RADIUS 1.5e-3
#define DIAM (2.0 * RADIUS)

static double uniform(uint64_t *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*st >> 11) / 9007199254740992.0;
}

/* ---------- the rule, one collision at a time ---------- */

/* Random geometries, spins and coefficients (a third of them Coulomb-limited): the kinetic energy
 * (translational + rotational) lost equals Walton's value m12/2 (1 - eps^2) g_n^2 + m_t/2
 * (1 - beta^2) g_ct^2 with beta from the Coulomb formula computed here; g_n' = -eps g_n and
 * g_ct' = -beta g_ct; linear momentum and the angular momentum about the origin (orbital + spin)
 * are conserved; when the pair slides |P_t| = mu |P_n| and otherwise |P_t| <= mu |P_n|. */
START_TEST(test_walton_rule)
{
    const double M = 2.0, R = 0.5;
    uint64_t st = 2718281828ULL;
    int slid = 0, stuck = 0;
    for (int k = 0; k < 20000; k++) {
        const double eps = 0.05 + 0.95 * uniform(&st), beta0 = -1.0 + 2.0 * uniform(&st);
        const double q = 0.2 + 0.8 * uniform(&st), mu = k % 3 == 0 ? 0.0 : 0.05 + uniform(&st);
        const double a = 2.0 * M_PI * uniform(&st), nx = cos(a), ny = sin(a);
        double v1x = uniform(&st) - 0.5, v1y = uniform(&st) - 0.5, v2x = uniform(&st) - 0.5,
               v2y = uniform(&st) - 0.5;
        double w1 = 4.0 * (uniform(&st) - 0.5), w2 = 4.0 * (uniform(&st) - 0.5);
        const double x1 = uniform(&st), y1 = uniform(&st), x2 = x1 + 2.0 * R * nx,
                     y2 = y1 + 2.0 * R * ny;
        const double I = q * M * R * R, m12 = 0.5 * M, m_t = m12 * q / (1.0 + q);
        const double gn = (v1x - v2x) * nx + (v1y - v2y) * ny;
        if (gn <= 0.0) { /* receding: reverse so the pair approaches */
            v1x = -v1x, v1y = -v1y, v2x = -v2x, v2y = -v2y;
            k--;
            continue;
        }
        const double gct = -(v1x - v2x) * ny + (v1y - v2y) * nx + R * (w1 + w2);
        double beta = beta0;
        if (mu > 0.0) {
            beta = fmin(beta0, -1.0 + mu * (1.0 + eps) * (1.0 + 1.0 / q) * fabs(gn) / fabs(gct));
        }
        const double e0 = 0.5 * M * (v1x * v1x + v1y * v1y + v2x * v2x + v2y * v2y) +
                          0.5 * I * (w1 * w1 + w2 * w2);
        const double px = v1x + v2x, py = v1y + v2y;
        const double L0 = M * (x1 * v1y - y1 * v1x + x2 * v2y - y2 * v2x) + I * (w1 + w2);
        const double u1x = v1x, u1y = v1y;
        double de_n, de_t;
        const double used = gr_event_collide_rough(M, q, R, eps, beta0, mu, nx, ny, &v1x, &v1y,
                                                   &v2x, &v2y, &w1, &w2, &de_n, &de_t);
        const double e1 = 0.5 * M * (v1x * v1x + v1y * v1y + v2x * v2x + v2y * v2y) +
                          0.5 * I * (w1 * w1 + w2 * w2);
        const double walton =
            0.5 * m12 * (1.0 - eps * eps) * gn * gn + 0.5 * m_t * (1.0 - beta * beta) * gct * gct;
        ck_assert_msg(fabs(used - beta) <= 1e-12, "beta %.17g, expected %.17g", used, beta);
        ck_assert_msg(fabs((e0 - e1) - walton) <= 1e-13 * e0, "lost %.17g, Walton %.17g", e0 - e1,
                      walton);
        ck_assert_msg(fabs(de_n + de_t - walton) <= 1e-13 * e0, "booked %.17g, Walton %.17g",
                      de_n + de_t, walton);
        ck_assert(fabs(v1x + v2x - px) <= 1e-15 && fabs(v1y + v2y - py) <= 1e-15);
        const double L1 = M * (x1 * v1y - y1 * v1x + x2 * v2y - y2 * v2x) + I * (w1 + w2);
        ck_assert_msg(fabs(L1 - L0) <= 1e-14 * (1.0 + fabs(L0)), "angular momentum %.17g -> %.17g",
                      L0, L1);
        const double gn1 = (v1x - v2x) * nx + (v1y - v2y) * ny;
        const double gct1 = -(v1x - v2x) * ny + (v1y - v2y) * nx + R * (w1 + w2);
        ck_assert(fabs(gn1 + eps * gn) <= 1e-13);
        ck_assert_msg(fabs(gct1 + beta * gct) <= 1e-13, "g_ct' %.17g, expected %.17g", gct1,
                      -beta * gct);
        /* impulses on 1 from its velocity change */
        const double Pn = M * ((v1x - u1x) * nx + (v1y - u1y) * ny),
                     Pt = M * (-(v1x - u1x) * ny + (v1y - u1y) * nx);
        if (mu > 0.0) {
            ck_assert(fabs(Pt) <= mu * fabs(Pn) * (1.0 + 1e-12) + 1e-15);
            if (beta < beta0) {
                slid++;
                ck_assert_msg(fabs(fabs(Pt) - mu * fabs(Pn)) <= 1e-12 * fabs(Pn) + 1e-15 * M,
                              "sliding: |P_t| %.17g, mu |P_n| %.17g", fabs(Pt), mu * fabs(Pn));
            } else {
                stuck++;
            }
        }
    }
    /* both regimes were exercised */
    ck_assert_msg(slid > 1000 && stuck > 1000, "slid %d, stuck %d", slid, stuck);
}
END_TEST

/* ---------- runs ---------- */

/* A 2D gas under the random force, N = 200, phi = 0.3 (overrides appended by the caller). */
static gr_sim *gas(const char *const *extra, int n_extra)
{
    const char *ov[16] = {"system.dim=2",
                          "system.N=200",
                          "system.packing_fraction=0.3",
                          "placement.kind=uniform",
                          "placement.v0=0.05",
                          "model.normal=hard_sphere",
                          "model.eps_n=0.7",
                          "noise.D=1e-8",
                          "integrator.kind=event",
                          "run.seed=11"};
    int n = 10;
    for (int k = 0; k < n_extra; k++) {
        ov[n++] = extra[k];
    }
    gr_scene sc = scene_of(ov, n);
    return sim_of(&sc);
}

/* simulated time of the runs: about 20 (quick 5) collisions per particle at v0 = 0.5 m/s */
static int64_t run_steps(const gr_sim *s)
{
    return (int64_t)llround((quick() ? 0.05 : 0.2) / s->dt);
}

/* beta = -1 (rotation on, no tangential impulse) is the smooth integrator with eps_t = 1, bit for
 * bit, and the spins stay zero. */
START_TEST(test_smooth_bitwise)
{
    const char *rough[] = {"model.rotation=true", "model.beta=-1", "model.eps_t=1"};
    const char *smooth[] = {"model.eps_t=1"};
    gr_sim *a = gas(rough, 3), *b = gas(smooth, 1);
    ck_assert(a->omega != NULL && b->omega == NULL);
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(a, run_steps(a), &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(b, run_steps(a), &err) == GR_OK, "%s", err.message);
    ck_assert(gr_sim_collisions(a) > 100);
    ck_assert_int_eq(gr_sim_collisions(a), gr_sim_collisions(b));
    const size_t bytes = (size_t)a->n * sizeof(double);
    ck_assert(memcmp(a->x, b->x, bytes) == 0 && memcmp(a->y, b->y, bytes) == 0);
    ck_assert(memcmp(a->vx, b->vx, bytes) == 0 && memcmp(a->vy, b->vy, bytes) == 0);
    for (int i = 0; i < a->n; i++) {
        ck_assert(a->omega[i] == 0.0);
    }
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

/* beta = +1, eps_n = 1, no noise: collisions trade translational for rotational energy and the
 * total is conserved to rounding. */
START_TEST(test_perfectly_rough_elastic)
{
    const char *ov[] = {"model.rotation=true", "model.beta=1", "model.eps_n=1", "noise.D=0",
                        "placement.v0=0.5"};
    gr_sim *s = gas(ov, 5);
    const double e0 = gr_sim_ledger(s).kinetic;
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, run_steps(s), &err) == GR_OK, "%s", err.message);
    gr_ledger l = gr_sim_ledger(s);
    if (verbose()) {
        printf("rough elastic: %lld collisions, E %.17g -> %.17g, rotational %.3g\n",
               (long long)gr_sim_collisions(s), e0, l.kinetic, l.rotational);
    }
    ck_assert(gr_sim_collisions(s) > 300);
    ck_assert_msg(l.rotational > 0.05 * l.kinetic, "spins got %.3g of %.3g", l.rotational,
                  l.kinetic);
    ck_assert_msg(fabs(l.kinetic - e0) <= 1e-12 * e0, "energy %.17g -> %.17g", e0, l.kinetic);
    gr_sim_free(s);
}
END_TEST

/* A noisy driven run with Coulomb-limited rough collisions: the ledger (rotational energy in the
 * kinetic total, dissipation booked normal + tangential) closes to rounding, both mechanisms
 * dissipate; the total angular momentum about the origin changes only by the noise (checked
 * without noise: exactly conserved up to rounding is covered by test_walton_rule). */
START_TEST(test_driven_ledger)
{
    const char *ov[] = {"model.rotation=true", "model.beta=0.4", "model.beta_mu=0.2",
                        "model.inertia_factor=0.5"};
    gr_sim *s = gas(ov, 4);
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, 2 * run_steps(s), &err) == GR_OK, "%s", err.message);
    gr_ledger l = gr_sim_ledger(s);
    const double scale = fmax(l.injected + gr_ledger_dissipated(&l), l.initial);
    if (verbose()) {
        printf("driven rough: %lld collisions, diss_n %.4g diss_t %.4g, rot %.4g of %.4g, residual "
               "%.3g\n",
               (long long)gr_sim_collisions(s), s->diss_n, s->diss_t, l.rotational, l.kinetic,
               gr_ledger_residual(&l) / scale);
    }
    ck_assert(gr_sim_collisions(s) > 1000);
    ck_assert(s->diss_n > 0.0 && s->diss_t > 0.0 && l.rotational > 0.0);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) <= 1e-12 * scale, "ledger residual %.3g",
                  gr_ledger_residual(&l) / scale);
    gr_sim_free(s);
}
END_TEST

/* Checkpoint restart of a rough, Coulomb-limited, noisy run: the continuation from the saved state
 * equals the uninterrupted run bit for bit, spins included; a truncated state is refused. */
START_TEST(test_restart_bitwise)
{
    const char *ov[] = {"model.rotation=true", "model.beta=0.4", "model.beta_mu=0.2"};
    gr_sim *a = gas(ov, 3), *b = gas(ov, 3);
    const int64_t T = run_steps(a) / 2;
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(a, T, &err) == GR_OK, "%s", err.message);
    gr_blob blob = {0};
    ck_assert_msg(gr_sim_save_state(a, &blob, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(a, T, &err) == GR_OK, "%s", err.message);
    gr_blob_reader r;
    gr_blob_reader_init(&r, blob.data, blob.len, "SIM");
    ck_assert_msg(gr_sim_load_state(b, &r, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(b, T, &err) == GR_OK, "%s", err.message);
    ck_assert(gr_sim_collisions(a) > 100);
    ck_assert_int_eq(gr_sim_collisions(a), gr_sim_collisions(b));
    const size_t bytes = (size_t)a->n * sizeof(double);
    ck_assert(memcmp(a->x, b->x, bytes) == 0 && memcmp(a->y, b->y, bytes) == 0);
    ck_assert(memcmp(a->vx, b->vx, bytes) == 0 && memcmp(a->vy, b->vy, bytes) == 0);
    ck_assert_msg(memcmp(a->omega, b->omega, bytes) == 0, "spins differ after the restart");
    ck_assert(a->diss_n == b->diss_n && a->diss_t == b->diss_t);
    /* the spins are the last thing saved: a state cut inside them is refused */
    gr_sim *c = gas(ov, 3);
    gr_blob_reader_init(&r, blob.data, blob.len - 8, "SIM");
    ck_assert_int_eq(gr_sim_load_state(c, &r, &err), GR_EINVAL);
    gr_sim_free(c);
    gr_blob_free(&blob);
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

/* ---------- viscoelastic hard discs ---------- */

/* Head-on collisions of two discs at several speeds through the engine: the measured eps_n equals
 * hertz's own eps_n(v) (the same keys prepared as the hertz normal law) and, for this weak damping,
 * the Schwager-Poeschel series 1 - C1 b + C2 b^2 (b = (3/2) A (k_h/m12)^(2/5) v^(1/5),
 * C1 = 1.15344, C2 = 0.79826; models/hertz.h) to its truncation O(b^3). */
START_TEST(test_viscoelastic_eps)
{
    const double speeds[] = {0.01, 0.1, 1.0, 3.0};
    const double k_h = 1e9, A = 2e-7, m12 = 0.5 * MASS;
    const char *ov[] = {"system.dim=2",
                        "system.N=2",
                        "system.L=0.1",
                        "placement.kind=uniform",
                        "model.normal=hard_sphere",
                        "model.viscoelastic=true",
                        "model.k_h=1e9",
                        "model.visco_A=2e-7",
                        "noise.D=0",
                        "integrator.kind=event"};
    gr_scene sc = scene_of(ov, 10);
    const gr_contact_coeffs hc = hertz_of(&sc, m12);
    gr_error err = {0};
    double last = 1.0;
    for (int k = 0; k < 4; k++) {
        const double v = speeds[k];
        double x[2] = {0.04, 0.04 + DIAM + 1e-4}, y[2] = {0.05, 0.05}, vx[2] = {0.5 * v, -0.5 * v},
               vy[2] = {0.0, 0.0};
        gr_sim *s;
        ck_assert_msg(gr_sim_create_with_state(&sc, 2, x, y, vx, vy, &s, &err) == GR_OK, "%s",
                      err.message);
        while (gr_sim_collisions(s) == 0) {
            ck_assert(gr_sim_step(s, 1, &err) == GR_OK);
        }
        ck_assert_int_eq(gr_sim_collisions(s), 1);
        const double eps = (s->vx[1] - s->vx[0]) / v;
        const double hertz = hc.normal_model->impact(&hc, v).eps_n;
        const double b = 1.5 * A * pow(k_h / m12, 0.4) * pow(v, 0.2);
        const double series = 1.0 - 1.15344 * b + 0.79826 * b * b;
        if (verbose()) {
            printf("viscoelastic v = %g: eps %.12f, hertz %.12f, series %.12f (b = %.3g)\n", v, eps,
                   hertz, series, b);
        }
        ck_assert_msg(fabs(eps - hertz) <= 1e-12, "v = %g: eps %.15g, hertz %.15g", v, eps, hertz);
        ck_assert_msg(fabs(eps - series) <= 2.0 * b * b * b, "v = %g: eps %.15g, series %.15g", v,
                      eps, series);
        ck_assert_msg(eps < last && eps > 0.0, "eps(v) must fall with v: %.6g after %.6g", eps,
                      last);
        last = eps;
        gr_ledger l = gr_sim_ledger(s);
        ck_assert(fabs(gr_ledger_residual(&l)) <= 1e-12 * l.initial);
        gr_sim_free(s);
    }
}
END_TEST

/* hard_sphere's eps_n(v) is a Chebyshev series of hertz's integrated contact (models/hard_sphere.h):
 * it equals hertz's own eps_n(v) to 1e-12 from nearly elastic to nearly sticking impacts (scaled
 * damping c from 1e-5 to past the series' end at c = 4.9, where it integrates directly), and
 * never leaves [GR_HARD_SPHERE_MIN_EPS, 1]. */
START_TEST(test_viscoelastic_series)
{
    const double m12 = 0.5 * MASS, A[] = {1e-8, 2e-7, 3e-6, 5e-5};
    int compared = 0;
    for (int a = 0; a < 4; a++) {
        gr_contact_params p;
        gr_contact_defaults(&p);
        gr_error err = {0};
        ck_assert(gr_contact_set(&p, "viscoelastic", "true", &err) == GR_OK);
        ck_assert(gr_contact_set_value(&p, "visco_A", A[a], &err) == GR_OK);
        gr_contact_coeffs hs, hz;
        ck_assert_msg(gr_contact_prepare(gr_model_find("hard_sphere"), NULL, &p, m12, 0.0, &hs,
                                         &err) == GR_OK,
                      "%s", err.message);
        ck_assert_msg(gr_contact_prepare(gr_model_find("hertz"), NULL, &p, m12, 0.0, &hz, &err) ==
                          GR_OK,
                      "%s", err.message);
        for (double v = 1e-4; v <= 1e2; v *= 1.37) {
            const double eps = hs.normal_model->impact(&hs, v).eps_n;
            const double want = hz.normal_model->impact(&hz, v).eps_n;
            ck_assert_msg(eps >= GR_HARD_SPHERE_MIN_EPS && eps <= 1.0, "A %g, v %g: eps %.17g",
                          A[a], v, eps);
            if (want >= GR_HARD_SPHERE_MIN_EPS) {
                ck_assert_msg(fabs(eps - want) <= 1e-12, "A %g, v %g: series %.17g, hertz %.17g",
                              A[a], v, eps, want);
                compared++;
            } else {
                ck_assert_msg(eps == GR_HARD_SPHERE_MIN_EPS, "A %g, v %g: eps %.17g, hertz %.3g",
                              A[a], v, eps, want);
            }
        }
    }
    ck_assert_int_ge(compared, 100);
}
END_TEST

/* `granule collide --model hard_sphere` with rotation: an impact at 45 degrees (discs not spinning
 * before) gives the contact point's eps_t = -beta (constant, and the Coulomb value when it
 * slides), equal spins of the size Walton's impulse gives, and the loss (1 - eps_n^2) cos^2 +
 * (m_t / m12) (1 - beta^2) sin^2 with the spin energy counted, which is also the model's own
 * expected loss. Viscoelastic collide runs are checked in test_viscoelastic_collide. */
START_TEST(test_collide_rough)
{
    const double beta0 = 0.5, eps = 0.8, q = 0.5;
    for (int coulomb = 0; coulomb < 2; coulomb++) {
        gr_collide_setup cs;
        gr_collide_setup_default(&cs);
        cs.normal = gr_model_find("hard_sphere");
        cs.contact.eps_n = eps;
        cs.contact.rotation = true;
        cs.contact.inertia_factor = q;
        ck_assert_int_eq(gr_contact_set_value(&cs.contact, "beta", beta0, NULL), GR_OK);
        ck_assert_int_eq(gr_contact_set_value(&cs.contact, "beta_mu", coulomb ? 0.1 : 0.0, NULL),
                         GR_OK);
        /* disc 1 moves along x at 1 m/s towards disc 2 (at rest) with impact parameter d / sqrt 2 */
        gr_collision_case c = {
            {0.0, 0.0}, {1.0, 0.0}, {1.0, 2.0 * cs.radius * M_SQRT1_2}, {0.0, 0.0}};
        gr_error err = {0};
        gr_collide_result r;
        ck_assert_msg(gr_collide_run(&cs, &c, &r, &err) == GR_OK, "%s", err.message);
        const double gn = M_SQRT1_2, gt = M_SQRT1_2; /* |g| = 1 at 45 degrees */
        double beta = beta0;
        if (coulomb) {
            beta = fmin(beta0, -1.0 + 0.1 * (1.0 + eps) * (1.0 + 1.0 / q) * gn / gt);
            ck_assert(beta < beta0); /* this case slides */
        }
        const double m12 = 0.5 * cs.mass, m_t = m12 * q / (1.0 + q),
                     I = q * cs.mass * cs.radius * cs.radius;
        const double spin = (1.0 + beta) * m_t * gt * cs.radius / I;
        const double loss = (1.0 - eps * eps) * 0.5 + (m_t / m12) * (1.0 - beta * beta) * 0.5;
        if (verbose()) {
            printf("collide rough (Coulomb %d): eps_t %.15g (expected %.15g), omega %.15g %.15g "
                   "(|%.15g|), loss %.15g (%.15g)\n",
                   coulomb, r.eps_t_measured, -beta, r.omega1, r.omega2, spin, r.energy_loss, loss);
        }
        ck_assert_msg(fabs(r.eps_t_measured + beta) <= 1e-12, "eps_t %.17g, expected %.17g",
                      r.eps_t_measured, -beta);
        ck_assert_msg(fabs(r.eps_n_measured - eps) <= 1e-12, "eps_n %.17g", r.eps_n_measured);
        ck_assert(r.omega1 == r.omega2);
        ck_assert_msg(fabs(fabs(r.omega1) - spin) <= 1e-12 * spin, "omega %.17g, expected |%.17g|",
                      r.omega1, spin);
        ck_assert_msg(fabs(r.energy_loss - loss) <= 1e-12, "loss %.17g, expected %.17g",
                      r.energy_loss, loss);
        /* the model's own law (gr_contact_expected_loss: restitution_t with the Coulomb limit) */
        ck_assert_msg(fabs(r.expected_loss - loss) <= 1e-12, "law's loss %.17g, expected %.17g",
                      r.expected_loss, loss);
        ck_assert(r.momentum_error <= 1e-15);
    }
}
END_TEST

/* `granule collide --model hard_sphere --set viscoelastic=true`: head-on, the measured eps_n and
 * the model's law eps_n(v) equal the engine's (test_viscoelastic_eps's hertz values, computed
 * there through the event integrator) at the same speeds. */
START_TEST(test_viscoelastic_collide)
{
    const double speeds[] = {0.01, 1.0};
    for (int k = 0; k < 2; k++) {
        gr_collide_setup cs;
        gr_collide_setup_default(&cs);
        cs.normal = gr_model_find("hard_sphere");
        cs.mass = MASS;
        cs.radius = RADIUS;
        ck_assert_int_eq(gr_contact_set_value(&cs.contact, "viscoelastic", true, NULL), GR_OK);
        ck_assert_int_eq(gr_contact_set_value(&cs.contact, "k_h", 1e9, NULL), GR_OK);
        ck_assert_int_eq(gr_contact_set_value(&cs.contact, "visco_A", 2e-7, NULL), GR_OK);
        gr_collision_case c = {{0.0, 0.0}, {speeds[k], 0.0}, {2.0 * DIAM, 0.0}, {0.0, 0.0}};
        gr_collide_result r;
        gr_error err = {0};
        ck_assert_msg(gr_collide_run(&cs, &c, &r, &err) == GR_OK, "%s", err.message);
        gr_contact_params hp = cs.contact;
        gr_contact_coeffs hc;
        ck_assert(gr_contact_prepare(gr_model_find("hertz"), NULL, &hp, 0.5 * MASS, 0.0, &hc,
                                     &err) == GR_OK);
        const double eps = hc.normal_model->impact(&hc, speeds[k]).eps_n;
        ck_assert_msg(fabs(r.eps_n_measured - eps) <= 1e-12,
                      "v = %g: collide eps_n %.15g, hertz %.15g", speeds[k], r.eps_n_measured, eps);
        ck_assert_msg(fabs(r.expected_loss - (1.0 - eps * eps)) <= 1e-12, "law's loss %.15g",
                      r.expected_loss);
    }
}
END_TEST

/* ---------- validation ---------- */

START_TEST(test_validation)
{
    const char *a[] = {"model.normal=hard_sphere", "integrator.kind=event", "model.beta=0.5"};
    refused(a, 3, "rotation = true");
    const char *b[] = {"model.normal=hard_sphere", "integrator.kind=event", "model.rotation=true",
                       "model.beta=1.5"};
    refused(b, 4, "beta");
    const char *c[] = {"model.normal=hard_sphere", "integrator.kind=event", "model.rotation=true",
                       "model.beta_mu=0.3"};
    refused(c, 4, "beta = -1");
    const char *d[] = {"model.normal=hard_sphere",
                       "integrator.kind=event",
                       "system.dim=1",
                       "system.N=3",
                       "system.L=1",
                       "placement.kind=uniform",
                       "model.rotation=true",
                       "model.beta=0.5"};
    refused(d, 8, "dim = 2");
    /* the hybrid integrator runs soft contacts: rough hard discs are refused */
    const char *e[] = {"model.normal=hard_sphere", "integrator.kind=hybrid", "model.rotation=true",
                       "model.beta=0.5"};
    refused(e, 4, "kind = event");
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("event_rough");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_walton_rule);
    tcase_add_test(tc, test_smooth_bitwise);
    tcase_add_test(tc, test_perfectly_rough_elastic);
    tcase_add_test(tc, test_driven_ledger);
    tcase_add_test(tc, test_restart_bitwise);
    tcase_add_test(tc, test_viscoelastic_eps);
    tcase_add_test(tc, test_viscoelastic_series);
    tcase_add_test(tc, test_collide_rough);
    tcase_add_test(tc, test_viscoelastic_collide);
    tcase_add_test(tc, test_validation);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
