/* Rotation ([model] rotation = true, docs/models.md "Rotation"): the physics each contact-point
 * tangential law must keep once the discs spin.
 *   - angular momentum (orbital about the origin + spin I w) and momentum are conserved to
 *     rounding through single oblique collisions, for every contact-point law, clamped or not,
 *     with and without initial spins (the lever arm |r_ij| / 2 makes the pair's torques cancel);
 *   - tangential_dashpot: the contact point's tangential restitution is the law's
 *     exp(-gamma_t t_c / m_t), m_t = m12 q / (1 + q), on the CVODE reference (which integrates the
 *     spin itself); the engine follows the reference to first order in dt / t_c; both discs end
 *     with w = -(1 - eps_t) g.t / ((1 + q) d), the impulse-momentum result;
 *   - sliding_friction: a sliding impact transfers |J_t| = mu |J_n| (Coulomb limit) and the
 *     contact point keeps the law's 1 - mu (1 + eps_n) (v_n / v_t) m12 / m_t; with a large mu the
 *     contact point sticks (eps_t = 0, w = -g.t / ((1 + q) d));
 *   - the energy ledger closes with the spin energy booked, in a driven many-particle run;
 *   - a checkpoint carries omega: 2N steps equal N + save/load + N, bit for bit;
 *   - integrators that do not rotate the discs, 1D and laws without a contact point refuse
 *     rotation = true with a message naming the key, and omega0 without rotation is refused;
 *   - [placement] omega0 gives the rotational temperature q r^2 omega0^2 / 12, in the ledger.
 * Particles: the RFM's discs (M = 3.53e-5 kg, r = 1.5 mm, k_s = 5e5 N/m). */
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

#define MASS 3.53e-5
#define RADIUS 1.5e-3
#define DIAM (2.0 * RADIUS)
#define STEPS 200.0 /* time steps per contact */

/* the scene's defaults with a tangential law, rotation on */
static gr_contact_params params_of(const char *law, const char *key, const char *value, double q)
{
    gr_contact_params p;
    gr_contact_defaults(&p);
    gr_error err = {0};
    ck_assert_msg(gr_contact_set(&p, key, value, &err) == GR_OK, "%s", err.message);
    p.rotation = true;
    p.inertia_factor = q;
    (void)law;
    return p;
}

static gr_collide_setup setup_of(const char *law, gr_contact_params p)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.normal = gr_model_find("spring_dashpot");
    s.tangential = gr_model_find(law);
    ck_assert(s.tangential);
    s.contact = p;
    s.mass = MASS;
    s.radius = RADIUS;
    s.dim = 2;
    return s;
}

/* particle 1 at `speed` along x hits particle 2 at rest at `angle` degrees */
static gr_collision_case impact(double speed, double angle)
{
    const double a = angle * M_PI / 180.0;
    return (gr_collision_case){{0.0, 0.0}, {speed, 0.0}, {2.0 * DIAM, DIAM * sin(a)}, {0.0, 0.0}};
}

static gr_contact_coeffs coeffs_of(const gr_collide_setup *s)
{
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert_msg(gr_contact_prepare(s->normal, s->tangential, &s->contact, 0.5 * s->mass, 0.0, &k,
                                     &err) == GR_OK,
                  "%s", err.message);
    return k;
}

/* the engine's collision averaged over `nph` phases, dt = t_c / STEPS */
static gr_collide_result engine(gr_collide_setup s, const gr_collision_case *cs,
                                const gr_contact_coeffs *k, int nph)
{
    s.dt = k->t_c / STEPS;
    gr_collide_result m = {0};
    for (int q = 0; q < nph; q++) {
        s.phase = (q + 0.5) / nph;
        gr_collide_result r;
        gr_error err = {0};
        ck_assert_msg(gr_collide_run(&s, cs, &r, &err) == GR_OK, "engine: %s", err.message);
        ck_assert_msg(r.omega1 == r.omega2, "equal torques, yet omega %.17g and %.17g", r.omega1,
                      r.omega2);
        m.eps_n_measured += r.eps_n_measured / nph;
        m.eps_t_measured += r.eps_t_measured / nph;
        m.omega1 += r.omega1 / nph;
        m.energy_loss += r.energy_loss / nph;
        m.normal_impulse += r.normal_impulse / nph;
        m.tangential_impulse += r.tangential_impulse / nph;
    }
    return m;
}

static gr_collide_result reference(const gr_collide_setup *s, const gr_collision_case *cs)
{
    gr_collide_result r;
    gr_error err = {0};
    ck_assert_msg(gr_collide_reference(s, cs, &r, &err) == GR_OK, "reference: %s", err.message);
    return r;
}

/* the line of centres turns by ~ v_t t_c / d during the contact, which the fixed-normal laws ignore */
static double turn_of(const gr_contact_coeffs *k, double speed, double angle)
{
    return speed * sin(angle * M_PI / 180.0) * k->t_c / DIAM;
}

/* 1. angular momentum and momentum through one oblique collision */
static const struct {
    const char *law, *key, *value;
} laws[] = {{"tangential_dashpot", "eps_t", "0.3"},
            {"sliding_friction", "mu", "0.2"},
            {"sliding_friction", "mu", "5"}};
enum { N_LAWS = sizeof laws / sizeof laws[0] };

START_TEST(test_angular_momentum)
{
    const int law = _i / 4, clamp = (_i / 2) % 2, spin = _i % 2;
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = 2;
    sc.N = 2;
    sc.radius = RADIUS;
    sc.mass = MASS;
    sc.normal = gr_model_find("spring_dashpot");
    sc.tangential = gr_model_find(laws[law].law);
    sc.contact = params_of(laws[law].law, laws[law].key, laws[law].value, 0.5);
    sc.contact.clamp = clamp;
    sc.D = 0.0;
    sc.noise_mode = GR_NOISE_NONE;
    sc.L = 40.0 * DIAM;
    sc.skin = 0.3;
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert(gr_contact_prepare(sc.normal, sc.tangential, &sc.contact, 0.5 * MASS, 0.0, &k,
                                 &err) == GR_OK);
    sc.dt = k.t_c / STEPS;
    const double speed = 0.1, a = 35.0 * M_PI / 180.0, c = 0.5 * sc.L;
    const double gap = 10.5 * sc.dt * speed, half = 0.5 * (DIAM * cos(a) + gap);
    double x[2] = {c - half, c + half}, y[2] = {c - 0.5 * DIAM * sin(a), c + 0.5 * DIAM * sin(a)};
    double vx[2] = {0.5 * speed, -0.5 * speed}, vy[2] = {0.1 * speed, 0.0};
    gr_sim *s = NULL;
    ck_assert_msg(gr_sim_create_with_state(&sc, 2, x, y, vx, vy, &s, &err) == GR_OK, "%s",
                  err.message);
    ck_assert(s->omega);
    if (spin) {
        s->omega[0] = 0.7 * speed / RADIUS; /* a spin that meets the impact (surface speeds ~ v) */
        s->omega[1] = -0.4 * speed / RADIUS;
    }
    const double I = s->inertia;
    double L0 = 0.0, P0[2], S0 = I * (s->omega[0] + s->omega[1]);
    for (int i = 0; i < 2; i++) {
        L0 += MASS * (s->x[i] * s->vy[i] - s->y[i] * s->vx[i]) + I * s->omega[i];
    }
    gr_sim_momentum(s, P0);
    ck_assert_msg(gr_sim_step(s, (int64_t)(3.0 * STEPS) + 40, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_collisions(s) == 1, "%lld collisions", (long long)gr_sim_collisions(s));
    double L1 = 0.0, P1[2], S1 = I * (s->omega[0] + s->omega[1]);
    for (int i = 0; i < 2; i++) {
        L1 += MASS * (s->x[i] * s->vy[i] - s->y[i] * s->vx[i]) + I * s->omega[i];
    }
    gr_sim_momentum(s, P1);
    const double scale = MASS * speed * c; /* the orbital part about the origin */
    VERBOSE("%s %s=%s clamp %d spin %d: dL/L %.2e, spin change %.3e of m v d\n", laws[law].law,
            laws[law].key, laws[law].value, clamp, spin, (L1 - L0) / scale,
            (S1 - S0) / (MASS * speed * DIAM));
    ck_assert_msg(fabs(S1 - S0) > 1e-2 * MASS * speed * DIAM,
                  "the collision did not change the spins (%.3e)", S1 - S0);
    ck_assert_msg(fabs(L1 - L0) <= 1e-13 * scale,
                  "%s %s=%s clamp %d spin %d: angular momentum %.17g -> %.17g (%.2e)",
                  laws[law].law, laws[law].key, laws[law].value, clamp, spin, L0, L1,
                  (L1 - L0) / scale);
    ck_assert_msg(hypot(P1[0] - P0[0], P1[1] - P0[1]) <= 1e-15 * MASS * speed, "momentum changed");
    gr_sim_free(s);
}
END_TEST

/* 2. tangential_dashpot: the contact point's restitution and the spins */
START_TEST(test_dashpot_contact_point)
{
    const double qs[] = {0.5, 0.4, 1.0}, angles[] = {30.0, 60.0}, speed = 0.1, eps_t = 0.3;
    for (int iq = 0; iq < 3; iq++) {
        gr_collide_setup s =
            setup_of("tangential_dashpot", params_of("tangential_dashpot", "eps_t", "0.3", qs[iq]));
        const gr_contact_coeffs k = coeffs_of(&s);
        ck_assert_msg(fabs(k.m_t - k.m12 * qs[iq] / (1.0 + qs[iq])) <= 1e-15 * k.m12, "m_t %g",
                      k.m_t);
        for (int ia = 0; ia < 2; ia++) {
            const gr_collision_case cs = impact(speed, angles[ia]);
            const double turn = turn_of(&k, speed, angles[ia]);
            const gr_collide_result ref = reference(&s, &cs);
            const gr_collide_result eng = engine(s, &cs, &k, quick() ? 2 : 4);
            const gr_normal_impact ni =
                k.normal_model->impact(&k, speed * cos(angles[ia] * M_PI / 180.0));
            const double law = k.tangential_model->restitution_t(&k, ni, 0.0, 0.0);
            /* w = -(1 - eps_t) g.t / ((1 + q) d), g.t = -v sin(a) in the engine's t */
            const double w_law =
                (1.0 - eps_t) * speed * sin(angles[ia] * M_PI / 180.0) / ((1.0 + qs[iq]) * DIAM);
            VERBOSE("q %.1f, %g deg: eps_t law %.8f, reference %.8f, engine %.8f; w law %.6f, ref "
                    "%.6f, engine %.6f "
                    "rad/s (turn %.1e)\n",
                    qs[iq], angles[ia], law, ref.eps_t_measured, eng.eps_t_measured, w_law,
                    ref.omega1, eng.omega1, turn);
            ck_assert_msg(fabs(law - eps_t) <= 1e-12, "the law's eps_t %.15f", law);
            ck_assert_msg(fabs(ref.eps_t_measured - law) <= 1e-7 + 2.0 * turn,
                          "q %g, %g deg: reference eps_t %.10f, law %.10f", qs[iq], angles[ia],
                          ref.eps_t_measured, law);
            ck_assert_msg(fabs(ref.omega1 - w_law) <= (1e-7 + 2.0 * turn) * w_law,
                          "q %g, %g deg: reference w %.10g, law %.10g", qs[iq], angles[ia],
                          ref.omega1, w_law);
            /* the engine to first order: the contact's start and end fall within a step */
            ck_assert_msg(fabs(eng.eps_t_measured - ref.eps_t_measured) <= 1.0 / STEPS,
                          "q %g, %g deg: engine eps_t %.8f, reference %.8f", qs[iq], angles[ia],
                          eng.eps_t_measured, ref.eps_t_measured);
            ck_assert_msg(fabs(eng.omega1 - ref.omega1) <= w_law / STEPS,
                          "q %g, %g deg: engine w %.8g, reference %.8g", qs[iq], angles[ia],
                          eng.omega1, ref.omega1);
        }
    }
}
END_TEST

/* 3. sliding_friction: the Coulomb limit while sliding, sticking for a large mu */
START_TEST(test_friction_coulomb_and_stick)
{
    const double speed = 0.1, angle = 60.0, q = 0.5;
    const gr_collision_case cs = impact(speed, angle);
    /* sliding throughout: |J_t| = mu |J_n| */
    gr_collide_setup s =
        setup_of("sliding_friction", params_of("sliding_friction", "mu", "0.1", q));
    gr_contact_coeffs k = coeffs_of(&s);
    const double v_n = speed * cos(angle * M_PI / 180.0), v_t = speed * sin(angle * M_PI / 180.0);
    const gr_normal_impact ni = k.normal_model->impact(&k, v_n);
    const double law = k.tangential_model->restitution_t(&k, ni, v_n, v_t);
    ck_assert_msg(law > 0.1, "mu = 0.1 should slide throughout (law %g)", law);
    ck_assert_msg(fabs(law - (1.0 - 0.1 * ni.impulse_abs * (v_n / v_t) * (1.0 + q) / q)) <= 1e-12,
                  "law %g, eps_n %g, |J_n| / m12 v_n %g", law, ni.eps_n, ni.impulse_abs);
    gr_collide_result ref = reference(&s, &cs), eng = engine(s, &cs, &k, quick() ? 2 : 4);
    const double turn = turn_of(&k, speed, angle);
    VERBOSE("mu 0.1: J_t / (mu J_n) engine %.12f, reference %.12f; eps_t law %.8f, reference %.8f, "
            "engine %.8f\n",
            eng.tangential_impulse / (0.1 * eng.normal_impulse),
            ref.tangential_impulse / (0.1 * ref.normal_impulse), law, ref.eps_t_measured,
            eng.eps_t_measured);
    ck_assert_msg(
        fabs(eng.tangential_impulse - 0.1 * eng.normal_impulse) <= 1e-12 * eng.normal_impulse,
        "engine: J_t %.15g, mu J_n %.15g", eng.tangential_impulse, 0.1 * eng.normal_impulse);
    ck_assert_msg(
        fabs(ref.tangential_impulse - 0.1 * ref.normal_impulse) <= 1e-9 * ref.normal_impulse,
        "reference: J_t %.15g, mu J_n %.15g", ref.tangential_impulse, 0.1 * ref.normal_impulse);
    ck_assert_msg(fabs(ref.eps_t_measured - law) <= 1e-7 + 2.0 * turn,
                  "reference eps_t %.10f, law %.10f", ref.eps_t_measured, law);
    ck_assert_msg(fabs(eng.eps_t_measured - law) <= 1e-7 + 2.0 * turn + 1.0 / STEPS,
                  "engine eps_t %.10f, law %.10f", eng.eps_t_measured, law);
    /* mu = 5: the contact point stops and stays (no spring): rolling without slip */
    s = setup_of("sliding_friction", params_of("sliding_friction", "mu", "5", q));
    k = coeffs_of(&s);
    ref = reference(&s, &cs);
    eng = engine(s, &cs, &k, quick() ? 2 : 4);
    const double w_roll = v_t / ((1.0 + q) * DIAM);
    VERBOSE(
        "mu 5: eps_t reference %.2e, engine %.2e; w roll %.6f, reference %.6f, engine %.6f rad/s\n",
        ref.eps_t_measured, eng.eps_t_measured, w_roll, ref.omega1, eng.omega1);
    ck_assert_msg(fabs(eng.eps_t_measured) <= 2.0 * turn,
                  "engine: the contact point still slides (eps_t %g)", eng.eps_t_measured);
    ck_assert_msg(fabs(ref.eps_t_measured) <= 2.0 * turn,
                  "reference: the contact point still slides (eps_t %g)", ref.eps_t_measured);
    ck_assert_msg(fabs(eng.omega1 - w_roll) <= 2.0 * turn * w_roll &&
                      fabs(ref.omega1 - w_roll) <= 2.0 * turn * w_roll,
                  "rolling spin %.8g, engine %.8g, reference %.8g", w_roll, eng.omega1, ref.omega1);
}
END_TEST

static void load_scene(gr_scene *sc, const char *file, const char **sets, int nsets)
{
    char path[4096];
    const char *root = getenv("GRANULE_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/docs/scenes/%s", root ? root : ".", file);
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(sc, path, sets, nsets, &err) == GR_OK, "%s", err.message);
}

static const char *driven[] = {"system.N=600",    "system.L=0.082",      "placement.v0=0.5",
                               "noise.D=1e-6",    "model.rotation=true", "model.eps_t=0.3",
                               "model.eps_n=0.6", "integrator.dt=2.5e-7"};
enum { N_DRIVEN = sizeof driven / sizeof driven[0] };

/* 4. the ledger closes with the spins: injected - dissipated = d(KE_trans + KE_rot) + d(elastic), to
 * velocity Verlet's spring-energy error (test_sim's bound, dt = t_c / 75 here), well below the spin energy */
START_TEST(test_ledger_closes)
{
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", driven, N_DRIVEN);
    gr_sim *s = NULL;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&sc, &s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(s, quick() ? 4000 : 16000, &err) == GR_OK, "%s", err.message);
    gr_ledger l = gr_sim_ledger(s);
    const double res = gr_ledger_residual(&l), scale = l.injected + gr_ledger_dissipated(&l);
    const double w = s->cc.w0 * gr_sim_dt(s),
                 bound = w * w / (1.0 - sc.contact.eps_n * sc.contact.eps_n);
    double rot = 0.0;
    for (int i = 0; i < s->n; i++) {
        rot += 0.5 * s->inertia * s->omega[i] * s->omega[i];
    }
    VERBOSE("driven, rotation: %lld collisions, residual %.3e of injected + dissipated (bound "
            "%.2e), %.3f of KE_rot, "
            "KE_rot %.3e J = %.3f of KE, tangential dissipation %.3e J\n",
            (long long)gr_sim_collisions(s), res / scale, bound, res / rot, rot, rot / l.kinetic,
            l.dissipated_tangential);
    ck_assert_msg(gr_sim_collisions(s) > 100, "only %lld collisions",
                  (long long)gr_sim_collisions(s));
    ck_assert_msg(fabs(l.rotational - rot) <= 1e-12 * rot && rot > 0.0,
                  "ledger's rotational KE %g, sum I w^2 / 2 %g", l.rotational, rot);
    /* the residual is velocity Verlet's spring-energy error, unrelated to the spins; a ledger that
     * forgot the spin energy (or the torques' work, which is larger) would be off by >= KE_rot */
    ck_assert_msg(fabs(res) <= 0.25 * rot,
                  "ledger residual %g J against KE_rot %g J: the spins are not booked", res, rot);
    ck_assert_msg(fabs(res) <= bound * scale, "ledger residual %g J (bound %g J), KE_rot %g J", res,
                  bound * scale, rot);
    gr_sim_free(s);
}
END_TEST

/* 5. a checkpoint carries the spins: 2N steps equal N + save + load into a new simulation + N */
START_TEST(test_checkpoint_bits)
{
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", driven, N_DRIVEN);
    const int64_t half = quick() ? 300 : 1000;
    gr_sim *a = NULL, *b = NULL;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&sc, &a, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_create(&sc, &b, &err) == GR_OK, "%s", err.message);
    ck_assert(gr_sim_step(a, 2 * half, &err) == GR_OK);
    ck_assert(gr_sim_step(b, half, &err) == GR_OK);
    void *data = NULL;
    size_t len = 0;
    ck_assert_msg(gr_sim_state_save(b, &data, &len, &err) == GR_OK, "%s", err.message);
    gr_sim_free(b);
    ck_assert_msg(gr_sim_create(&sc, &b, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_state_load(b, data, len, &err) == GR_OK, "%s", err.message);
    free(data);
    ck_assert(gr_sim_step(b, half, &err) == GR_OK);
    const size_t n = sizeof(double) * (size_t)a->n;
    double sum = 0.0;
    for (int i = 0; i < a->n; i++) {
        sum += fabs(a->omega[i]);
    }
    ck_assert_msg(sum > 0.0, "no disc spins: the test would not see omega");
    ck_assert_msg(!memcmp(a->omega, b->omega, n), "omega differs after a restart");
    ck_assert_msg(!memcmp(a->x, b->x, n) && !memcmp(a->y, b->y, n) && !memcmp(a->vx, b->vx, n) &&
                      !memcmp(a->vy, b->vy, n),
                  "positions or velocities differ after a restart");
    gr_ledger la = gr_sim_ledger(a), lb = gr_sim_ledger(b);
    ck_assert_msg(!memcmp(&la, &lb, sizeof la), "the ledger differs after a restart");
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

/* 6. refusals: rotation needs a law acting at the contact point (rough hard discs:
 * tests/test_event_rough.c) and 2D or 3D; the message names the key (every integrator rotates:
 * verlet, event and hybrid) */
START_TEST(test_refusals)
{
    static const struct {
        const char *scene, *sets[3];
    } cases[] = {
        {"rfm-2d-event.ini",
         {"model.beta=0.5", NULL, NULL}}, /* rough hard discs need rotation = true */
        {"rfm-2d.ini", {"model.rotation=true", "model.tangential=none", NULL}},
        {"rfm-1d.ini", {"model.rotation=true", NULL, NULL}},
        {"rfm-2d.ini", {"placement.omega0=10", NULL, NULL}},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        int nsets = 0;
        while (nsets < 3 && cases[c].sets[nsets]) {
            nsets++;
        }
        char path[4096];
        const char *root = getenv("GRANULE_SOURCE_DIR");
        snprintf(path, sizeof path, "%s/docs/scenes/%s", root ? root : ".", cases[c].scene);
        gr_scene sc;
        gr_error err = {0};
        int rc = gr_scene_load(&sc, path, cases[c].sets, nsets, &err);
        gr_sim *s = NULL;
        if (rc == GR_OK) {
            sc.N = sc.dim == 2 ? 200 : 100;
            rc = gr_sim_create(&sc, &s, &err);
        }
        VERBOSE("%s %s %s: %s\n", cases[c].scene, cases[c].sets[0],
                cases[c].sets[1] ? cases[c].sets[1] : "", err.message);
        ck_assert_msg(rc != GR_OK, "%s with %s: accepted", cases[c].scene,
                      cases[c].sets[1] ? cases[c].sets[1] : "");
        ck_assert_msg(strstr(err.message, "rotation"), "%s: the message does not name the key: %s",
                      cases[c].scene, err.message);
        gr_sim_free(s);
    }
}
END_TEST

/* 7. [placement] omega0: the initial spins omega0 U(-0.5, 0.5) give T_rot = I <w^2> / M =
 * q r^2 omega0^2 / 12 (to the sampling error of N discs: the relative deviation of a mean of u^2,
 * u uniform, is 0.894 / sqrt(N); 5 of them allowed), booked in the ledger's initial energy */
START_TEST(test_initial_spins)
{
    gr_scene sc;
    const char *sets[] = {"system.N=600", "system.L=0.082", "model.rotation=true",
                          "placement.omega0=300"};
    load_scene(&sc, "rfm-2d.ini", sets, 4);
    gr_sim *s = NULL;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&sc, &s, &err) == GR_OK, "%s", err.message);
    const double T_rot = gr_sim_rotational_temperature(s), q = sc.contact.inertia_factor;
    const double want = q * RADIUS * RADIUS * 300.0 * 300.0 / 12.0, tol = 5.0 * 0.894 / sqrt(600.0);
    gr_ledger l = gr_sim_ledger(s);
    VERBOSE("omega0 300 rad/s: T_rot %.5g, expected %.5g (tol %.2f relative); KE_rot %.4g J of "
            "initial %.4g J\n",
            T_rot, want, tol, l.rotational, l.initial);
    ck_assert_msg(fabs(T_rot / want - 1.0) <= tol, "T_rot %g, expected %g", T_rot, want);
    ck_assert_msg(fabs(l.rotational - 0.5 * sc.N * MASS * T_rot) <= 1e-12 * l.rotational,
                  "KE_rot %g, N M T_rot / 2 %g", l.rotational, 0.5 * sc.N * MASS * T_rot);
    ck_assert_msg(l.initial == l.kinetic + l.elastic && l.rotational > 0.0,
                  "the initial energy leaves the spins out");
    gr_sim_free(s);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("rotation");
    TCase *tc = tcase_create("rotation");
    tcase_add_loop_test(tc, test_angular_momentum, 0, 4 * N_LAWS);
    tcase_add_test(tc, test_dashpot_contact_point);
    tcase_add_test(tc, test_friction_coulomb_and_stick);
    tcase_add_test(tc, test_ledger_closes);
    tcase_add_test(tc, test_checkpoint_bits);
    tcase_add_test(tc, test_refusals);
    tcase_add_test(tc, test_initial_spins);
    tcase_set_timeout(tc, 300);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
