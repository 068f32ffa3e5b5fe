/* Rolling resistance ([model] rolling = rolling_friction, models/rolling_friction.h): the torque
 * pair -+ min(mu_r |F_n| R_eff, I |w_i - w_j| / (2 dt)) sign(w_i - w_j), R_eff = r / 2.
 *   - a head-on impact of counter-rotating discs (w1 = -w2 = w: the contact point does not slip,
 *     so only the rolling law acts) takes from the spins exactly J |dw_0| - J^2 / I with
 *     J = min(mu_r R_eff P_n, I |dw_0| / 2), P_n = int |F_n| dt = m12 (1 + eps_n) v_n: the rate
 *     mu_r |F_n| R_eff |dw| integrated; both the rolling regime (J = mu_r R_eff P_n) and the
 *     arrested one (the spins stop: all spin energy lost) for every normal and contact-point
 *     tangential law, clamped or not; the translation is bit-identical to rolling = none;
 *   - angular momentum (orbital + spins) and momentum conserved to rounding in oblique
 *     collisions of spinning discs with friction;
 *   - exchanging the two particles gives the same loss and swapped spins;
 *   - mu_r = 0 is bit-identical to rolling = none in a driven many-particle run (and mu_r > 0 is
 *     not: the test would see a law that does nothing);
 *   - the energy ledger closes in a driven run with rolling, the rolling dissipation booked;
 *   - threads 1 vs 2 and a restart (N + save/load + N vs 2N) are bit-identical;
 *   - hard cases (eps_n -> 0, huge mu_r, huge spins, grazing, the densest packing) stay finite;
 *   - rolling without rotation, in 1D or with the event integrator is refused naming the key.
 * Particles: the RFM's discs (M = 3.53e-5 kg, r = 1.5 mm). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/collide.h"
#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "test_env.h"
#include "test_scenes.h"

#define MASS 3.53e-5
#define RADIUS 1.5e-3
#define DIAM (2.0 * RADIUS)
#define Q 0.5
#define INERTIA (Q * MASS * RADIUS * RADIUS)
#define R_EFF (0.5 * RADIUS)

static gr_collide_setup setup_of(const char *normal, const char *tangential, int clamp, double mu_r)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    gr_contact_defaults(&s.contact);
    s.normal = gr_model_find(normal);
    s.tangential = gr_model_find(tangential);
    s.rolling = gr_model_find("rolling_friction");
    ck_assert(s.normal && s.tangential && s.rolling);
    s.contact.rotation = true;
    s.contact.inertia_factor = Q;
    s.contact.clamp = clamp;
    ck_assert_int_eq(gr_contact_set_value(&s.contact, "mu_r", mu_r, NULL), GR_OK);
    s.mass = MASS;
    s.radius = RADIUS;
    s.dim = 2;
    s.steps_per_contact = 200.0;
    return s;
}

/* particle 1 at speed v along x hits particle 2 at rest, the line of centres at `angle` degrees */
static gr_collision_case impact(double v, double angle)
{
    const double a = angle * M_PI / 180.0;
    return (gr_collision_case){{0.0, 0.0}, {v, 0.0}, {2.0 * DIAM, DIAM * sin(a)}, {0.0, 0.0}};
}

static gr_collide_result run(const gr_collide_setup *s, const gr_collision_case *cs)
{
    gr_collide_result r;
    gr_error err = {0};
    ck_assert_msg(gr_collide_run(s, cs, &r, &err) == GR_OK, "%s", err.message);
    return r;
}

/* 1. the spins lose what the law's torque dissipates: J dw_0 - J^2 / I */
START_TEST(test_spin_loss_law)
{
    const char *normals[] = {"spring_dashpot", "hertz"},
               *tangentials[] = {"sliding_friction", "tangential_dashpot"};
    const double v = 0.1, mu_r = 0.2;
    for (int a = 0; a < 2; a++) {
        for (int b = 0; b < 2; b++) {
            for (int clamp = 0; clamp < 2; clamp++) {
                gr_collide_setup s = setup_of(normals[a], tangentials[b], clamp, mu_r);
                gr_contact_coeffs k;
                gr_error err = {0};
                ck_assert(gr_contact_prepare(s.normal, s.tangential, &s.contact, 0.5 * MASS, 0.0,
                                             &k, &err) == GR_OK);
                const gr_normal_impact ni = k.normal_model->impact(&k, v);
                const double p_n = 0.5 * MASS * ni.impulse_abs * v; /* int |F_n| dt of the law */
                const double j_roll = mu_r * R_EFF * p_n;
                /* w_roll: the relative spin the contact exactly stops; well above it the pair rolls on */
                const double w_stop =
                    j_roll / INERTIA; /* w1 = -w2 = w_stop: dw_0 = 2 w_stop = 2 J / I */
                const double ws[2] = {20.0 * w_stop, 0.3 * w_stop};
                for (int q = 0; q < 2; q++) {
                    const double w = ws[q], dw0 = 2.0 * w;
                    const double J = fmin(j_roll, 0.5 * INERTIA * dw0);
                    const double want = J * dw0 - J * J / INERTIA; /* J */
                    gr_collision_case cs = impact(v, 0.0);
                    s.omega1 = w;
                    s.omega2 = -w;
                    gr_collide_result r = run(&s, &cs);
                    const double e0 =
                        0.25 * MASS * v * v + INERTIA * w * w; /* m12 v^2 / 2 + 2 I w^2 / 2 */
                    const double got = r.spin_loss * e0;
                    /* the engine's normal impulse differs from the law's by its restitution error,
                     * O(dt / t_c) = 1/200 (docs/collision-accuracy.md); measured <= 7.3e-4 */
                    const double tol = 2.5e-3 * want;
                    VERBOSE("%s+%s%s, w = %.3g rad/s: spin loss %.6e J, law %.6e J (rel %.2e), w "
                            "after %g %g\n",
                            normals[a], tangentials[b], clamp ? "[clamped]" : "", w, got, want,
                            got / want - 1.0, r.omega1, r.omega2);
                    ck_assert_msg(fabs(got - want) <= tol,
                                  "%s+%s clamp %d w %g: spin loss %.8e J, the law %.8e J",
                                  normals[a], tangentials[b], clamp, w, got, want);
                    ck_assert_msg(r.omega1 + r.omega2 == 0.0,
                                  "the contact point slipped: w1 + w2 = %g", r.omega1 + r.omega2);
                    if (q == 1) {
                        /* stopped to rounding: the limit stops dw within a step, up to the last bits */
                        ck_assert_msg(fabs(r.omega1) <= 1e-9 * w && fabs(r.omega2) <= 1e-9 * w,
                                      "arrested rolling: spins %g %g, expected 0", r.omega1,
                                      r.omega2);
                    } else {
                        ck_assert_msg(r.omega1 > 0.0 && r.omega2 < 0.0, "the spins reversed: %g %g",
                                      r.omega1, r.omega2);
                    }
                    /* the translation does not see the torques: the same as without the law, bit for bit */
                    gr_collide_setup none = s;
                    none.rolling = NULL;
                    gr_collide_result r0 = run(&none, &cs);
                    ck_assert_msg(r0.eps_n_measured == r.eps_n_measured && r0.spin_loss == 0.0,
                                  "translation changed by the rolling law: eps_n %.17g vs %.17g",
                                  r.eps_n_measured, r0.eps_n_measured);
                }
            }
        }
    }
}
END_TEST

/* a 2-disc simulation of an oblique impact with spins */
static gr_sim *pair_sim(double mu_r, int swap, double angle, double w1, double w2)
{
    gr_scene sc;
    gr_scene_default(&sc);
    sc.N = 2;
    sc.radius = RADIUS;
    sc.mass = MASS;
    sc.normal = gr_model_find("spring_dashpot");
    sc.tangential = gr_model_find("sliding_friction");
    sc.rolling = gr_model_find("rolling_friction");
    sc.contact.rotation = true;
    ck_assert_int_eq(gr_contact_set_value(&sc.contact, "mu_r", mu_r, NULL), GR_OK);
    sc.D = 0.0;
    sc.noise_mode = GR_NOISE_NONE;
    sc.L = 40.0 * DIAM;
    sc.steps_per_contact = 200.0;
    /* impact parameter d sin a, 0.002 d apart along x: contact after ~ 300 steps */
    const double a = angle * M_PI / 180.0, c = 0.5 * sc.L, v = 0.1,
                 hx = 0.5 * DIAM * (cos(a) + 0.002);
    double x[2] = {c - hx, c + hx};
    double y[2] = {c - 0.5 * DIAM * sin(a), c + 0.5 * DIAM * sin(a)};
    double vx[2] = {0.5 * v, -0.5 * v}, vy[2] = {0.0, 0.0};
    double ws[2] = {w1, w2};
    if (swap) {
        /* the same picture with the indices exchanged */
        double t = x[0];
        x[0] = x[1];
        x[1] = t;
        t = y[0];
        y[0] = y[1];
        y[1] = t;
        t = vx[0];
        vx[0] = vx[1];
        vx[1] = t;
        ws[0] = w2;
        ws[1] = w1;
    }
    gr_sim *s = NULL;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create_with_state(&sc, 2, x, y, vx, vy, &s, &err) == GR_OK, "%s",
                  err.message);
    s->omega[0] = ws[0];
    s->omega[1] = ws[1];
    return s;
}

static double ang_mom(const gr_sim *s)
{
    double l = 0.0;
    for (int i = 0; i < s->n; i++) {
        l += s->mass * (s->x[i] * s->vy[i] - s->y[i] * s->vx[i]) + s->inertia * s->omega[i];
    }
    return l;
}

/* 2. angular and linear momentum conserved; 3. symmetric under exchanging the particles */
START_TEST(test_conservation_and_symmetry)
{
    const double angles[] = {0.0, 30.0, 70.0};
    for (int a = 0; a < 3; a++) {
        gr_sim *s = pair_sim(0.3, 0, angles[a], 300.0, -40.0),
               *t = pair_sim(0.3, 1, angles[a], 300.0, -40.0);
        const double l0 = ang_mom(s), scale = fabs(s->mass * s->x[0] * 0.1) + s->inertia * 300.0;
        gr_error err = {0};
        ck_assert(gr_sim_step(s, 1200, &err) == GR_OK);
        ck_assert(gr_sim_step(t, 1200, &err) == GR_OK);
        ck_assert_msg(gr_sim_collisions(s) >= 1, "no collision");
        const double l1 = ang_mom(s);
        double p[2];
        gr_sim_momentum(s, p);
        VERBOSE("angle %g: angular momentum %.3e relative change, momentum %.2e %.2e, spins %g %g "
                "/ swapped %g %g\n",
                angles[a], (l1 - l0) / scale, p[0], p[1], s->omega[0], s->omega[1], t->omega[1],
                t->omega[0]);
        ck_assert_msg(fabs(l1 - l0) <= 1e-12 * scale, "angular momentum %.17g -> %.17g", l0, l1);
        ck_assert_msg(fabs(p[0]) <= 1e-15 && fabs(p[1]) <= 1e-15, "momentum %g %g", p[0], p[1]);
        /* the rolling law acted: the spins' difference shrank */
        ck_assert_msg(fabs(s->omega[0] - s->omega[1]) < 340.0 - 1.0,
                      "spins %g %g: no rolling resistance", s->omega[0], s->omega[1]);
        const double tol = 1e-9 * 300.0;
        ck_assert_msg(fabs(s->omega[0] - t->omega[1]) <= tol &&
                          fabs(s->omega[1] - t->omega[0]) <= tol,
                      "exchanged: spins %.17g %.17g vs %.17g %.17g", s->omega[0], s->omega[1],
                      t->omega[1], t->omega[0]);
        ck_assert_msg(fabs(s->vx[0] - t->vx[1]) <= 1e-12 && fabs(s->vy[0] - t->vy[1]) <= 1e-12,
                      "exchanged: velocities differ");
        gr_sim_free(s);
        gr_sim_free(t);
    }
}
END_TEST

static const char *driven[] = {"system.N=400",
                               "system.packing_fraction=0.5",
                               "placement.v0=0.5",
                               "noise.D=1e-6",
                               "model.tangential=sliding_friction",
                               "model.rotation=true",
                               "model.eps_n=0.6",
                               "model.mu=0.3",
                               "placement.omega0=2000",
                               "integrator.steps_per_contact=75",
                               "model.rolling=rolling_friction",
                               "model.mu_r=0.2"};
enum { N_DRIVEN = sizeof driven / sizeof driven[0] };

/* the driven scene with up to two more overrides (NULL: none) */
static gr_sim *driven_sim2(const char *extra, const char *extra2)
{
    const char *ov[N_DRIVEN + 2];
    memcpy(ov, driven, sizeof driven);
    ov[N_DRIVEN] = extra ? extra : "model.mu_r=0.2";
    ov[N_DRIVEN + 1] = extra2 ? extra2 : "model.mu_r=0.2";
    gr_scene sc = scene_of(ov, extra2 ? N_DRIVEN + 2 : N_DRIVEN + 1);
    return sim_of(&sc);
}

static gr_sim *driven_sim(const char *extra) { return driven_sim2(extra, NULL); }

static int same_state(const gr_sim *a, const gr_sim *b)
{
    const size_t n = sizeof(double) * (size_t)a->n;
    return !memcmp(a->x, b->x, n) && !memcmp(a->y, b->y, n) && !memcmp(a->vx, b->vx, n) &&
           !memcmp(a->vy, b->vy, n) && !memcmp(a->omega, b->omega, n);
}

/* 4. mu_r = 0 is rolling = none, bit for bit; mu_r > 0 is not */
START_TEST(test_zero_is_none)
{
    const int64_t steps = quick() ? 500 : 2000;
    gr_sim *a = driven_sim("model.mu_r=0"), *b = driven_sim("model.rolling=none"),
           *c = driven_sim(NULL);
    gr_error err = {0};
    ck_assert(gr_sim_step(a, steps, &err) == GR_OK && gr_sim_step(b, steps, &err) == GR_OK &&
              gr_sim_step(c, steps, &err) == GR_OK);
    ck_assert_msg(strstr(gr_sim_kernel(c), "+rolling_friction"), "kernel %s", gr_sim_kernel(c));
    ck_assert_msg(!strstr(gr_sim_kernel(a), "rolling"), "mu_r = 0 runs %s", gr_sim_kernel(a));
    ck_assert_msg(same_state(a, b), "mu_r = 0 differs from rolling = none");
    ck_assert_msg(!same_state(a, c), "mu_r = 0.2 equals rolling = none: the law does nothing");
    gr_ledger la = gr_sim_ledger(a), lb = gr_sim_ledger(b);
    ck_assert(!memcmp(&la, &lb, sizeof la));
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_free(c);
}
END_TEST

/* 5. the ledger closes with the rolling dissipation booked (in diss_f) */
START_TEST(test_ledger_closes)
{
    const int64_t steps = quick() ? 3000 : 12000;
    gr_sim *s = driven_sim(NULL), *f = driven_sim("model.mu_r=0");
    gr_error err = {0};
    ck_assert(gr_sim_step(s, steps, &err) == GR_OK && gr_sim_step(f, steps, &err) == GR_OK);
    gr_ledger l = gr_sim_ledger(s), lf = gr_sim_ledger(f);
    const double res = gr_ledger_residual(&l), scale = l.injected + gr_ledger_dissipated(&l);
    const double res_f = gr_ledger_residual(&lf), scale_f = lf.injected + gr_ledger_dissipated(&lf);
    VERBOSE("driven with rolling: %lld collisions, residual %.3e of injected + dissipated (without "
            "rolling %.3e); "
            "friction column %.3e J (without %.3e J), KE_rot %.3e J (without %.3e J)\n",
            (long long)gr_sim_collisions(s), res / scale, res_f / scale_f, l.dissipated_friction,
            lf.dissipated_friction, l.rotational, lf.rotational);
    ck_assert_msg(gr_sim_collisions(s) > 100, "only %lld collisions",
                  (long long)gr_sim_collisions(s));
    /* the rolling law's work is of the order of the friction's; forgetting it would leave a
     * residual of that size. Velocity Verlet's spring-energy error (as without rolling) remains. */
    const double extra = l.dissipated_friction - lf.dissipated_friction;
    ck_assert_msg(extra > 0.0, "rolling booked nothing: friction %g vs %g J", l.dissipated_friction,
                  lf.dissipated_friction);
    const double w = s->cc.w0 * gr_sim_dt(s), bound = w * w / (1.0 - 0.36);
    ck_assert_msg(fabs(res) <= bound * scale, "ledger residual %g J (bound %g J)", res,
                  bound * scale);
    ck_assert_msg(fabs(res) <= 0.1 * extra,
                  "ledger residual %g J against the rolling dissipation %g J", res, extra);
    gr_sim_free(s);
    gr_sim_free(f);
}
END_TEST

/* 6. threads 1 and 2, and a restart, bit-identical */
START_TEST(test_threads_and_restart)
{
    const int64_t half = quick() ? 100 : 400;
    gr_error err = {0};
    /* 1500 discs: two blocks of GR_BLOCK rows, so two threads really split the pairs */
    const char *big = "system.N=1500";
    gr_set_threads(1);
    gr_sim *a = driven_sim2(big, "model.mu_r=0.2");
    ck_assert(gr_sim_step(a, 2 * half, &err) == GR_OK);
    gr_set_threads(2);
    gr_sim *b = driven_sim2(big, "model.mu_r=0.2");
    ck_assert_msg(gr_sim_threads(b) == 2, "2 threads requested, %d used", gr_sim_threads(b));
    ck_assert(gr_sim_step(b, 2 * half, &err) == GR_OK);
    ck_assert_msg(same_state(a, b), "1 and 2 threads differ");
    gr_set_threads(1);
    gr_sim *c = driven_sim2(big, "model.mu_r=0.2");
    ck_assert(gr_sim_step(c, half, &err) == GR_OK);
    void *data = NULL;
    size_t len = 0;
    ck_assert_msg(gr_sim_state_save(c, &data, &len, &err) == GR_OK, "%s", err.message);
    gr_sim_free(c);
    c = driven_sim2(big, "model.mu_r=0.2");
    ck_assert_msg(gr_sim_state_load(c, data, len, &err) == GR_OK, "%s", err.message);
    free(data);
    ck_assert(gr_sim_step(c, half, &err) == GR_OK);
    ck_assert_msg(same_state(a, c), "a restart differs");
    gr_ledger la = gr_sim_ledger(a), lc = gr_sim_ledger(c);
    ck_assert_msg(!memcmp(&la, &lc, sizeof la), "the ledger differs after a restart");
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_free(c);
}
END_TEST

/* 7. hard cases stay finite */
START_TEST(test_hard_cases)
{
    static const struct {
        double eps_n, mu_r, w, angle;
    } cases[] = {{0.0, 0.2, 500.0, 0.0},
                 {0.6, 1e6, 500.0, 30.0},
                 {0.6, 0.2, 1e8, 45.0},
                 {0.6, 50.0, 1e-12, 89.9}};
    for (int c = 0; c < 4; c++) {
        for (int clamp = 0; clamp < 2; clamp++) {
            gr_collide_setup s =
                setup_of("spring_dashpot", "sliding_friction", clamp, cases[c].mu_r);
            s.contact.eps_n = cases[c].eps_n;
            s.omega1 = cases[c].w;
            s.omega2 = -0.5 * cases[c].w;
            gr_collision_case cs = impact(0.1, cases[c].angle);
            gr_collide_result r;
            gr_error err = {0};
            int rc = gr_collide_run(&s, &cs, &r, &err);
            if (rc != GR_OK) {
                ck_assert_msg(err.message[0], "case %d refused without a message", c);
                continue;
            }
            ck_assert_msg(isfinite(r.energy_loss) && isfinite(r.omega1) && isfinite(r.omega2) &&
                              isfinite(r.spin_loss),
                          "case %d: loss %g spins %g %g", c, r.energy_loss, r.omega1, r.omega2);
            ck_assert_msg(r.energy_loss >= -1e-9 && r.energy_loss <= 1.0 + 1e-9, "case %d: loss %g",
                          c, r.energy_loss);
        }
    }
    /* the densest legal packing, spinning, with a huge mu_r */
    gr_sim *s = driven_sim2("system.packing_fraction=0.85", "model.mu_r=1e3");
    gr_error err = {0};
    ck_assert_msg(gr_sim_step(s, 200, &err) == GR_OK, "%s", err.message);
    for (int i = 0; i < s->n; i++) {
        ck_assert_msg(isfinite(s->omega[i]) && isfinite(s->vx[i]), "disc %d: w %g v %g", i,
                      s->omega[i], s->vx[i]);
    }
    gr_sim_free(s);
}
END_TEST

/* 8. refusals name the key */
START_TEST(test_refusals)
{
    const char *no_rot[] = {"model.tangential=sliding_friction", "model.rolling=rolling_friction"};
    refused(no_rot, 2, "[model] rolling");
    const char *one_d[] = {"system.dim=1", "system.N=20", "placement.kind=uniform",
                           "model.rolling=rolling_friction"};
    refused(one_d, 4, "rolling");
    const char *unknown[] = {"model.rolling=sliding_friction"};
    refused(unknown, 1, "not a rolling model");
    const char *neg[] = {"model.tangential=sliding_friction", "model.rotation=true",
                         "model.rolling=rolling_friction", "model.mu_r=-1"};
    refused(neg, 4, "mu_r");
    /* the library path (no scene parser) refuses too */
    gr_contact_params p;
    gr_contact_defaults(&p);
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert(gr_contact_prepare(gr_model_find("spring_dashpot"), NULL, &p, 0.5 * MASS, 0.0, &k,
                                 &err) == GR_OK);
    ck_assert(gr_contact_prepare_rolling(gr_model_find("rolling_friction"), &p, 0.5 * MASS, 0.0, &k,
                                         &err) == GR_EINVAL);
    ck_assert_msg(strstr(err.message, "rotation = true"), "%s", err.message);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("rolling");
    TCase *tc = tcase_create("rolling");
    tcase_add_test(tc, test_spin_loss_law);
    tcase_add_test(tc, test_conservation_and_symmetry);
    tcase_add_test(tc, test_zero_is_none);
    tcase_add_test(tc, test_ledger_closes);
    tcase_add_test(tc, test_threads_and_restart);
    tcase_add_test(tc, test_hard_cases);
    tcase_add_test(tc, test_refusals);
    tcase_set_timeout(tc, 300);
    suite_add_tcase(s, tc);
    return gr_test_run(s);
}
