/* The CVODE reference of the Cundall-Strack tangential spring (src/collide/reference.c) on its
 * own, against what the spring must give in its limits, with and without rotation:
 *   - sticking (mu -> inf, no dashpot, eps_n = 1: the normal force vanishes only at the ends): the
 *     contact point's tangential motion is an undamped oscillator w_t = sqrt(k_t / m_t) for the
 *     contact's duration pi / w0, so eps_t = cos(w_t pi / w0); m_t = m12 without rotation,
 *     m12 q / (1 + q) with it; the energy lost is exactly the spring's k_t s^2 / 2 left at the end;
 *   - sliding (small mu, eps_n = 1: F_n = 0 at the touch, so the spring is at the limit at once):
 *     the Coulomb law eps_t = 1 - mu (1 + eps_n) v_n / v_t (m12 / m_t of it with rotation);
 *   - the energy balance: the loss equals the normal and tangential dissipation plus the elastic
 *     energy still in the contact at its end (less what a Mindlin k_t adds by changing), for the
 *     linear and Hertz laws, clamped and not, damped and not, with Mindlin;
 *   - convergence in rtol, and no dependence on the engine's time step;
 *   - the reference and the law's own fixed-normal restitution law converge as the overlap (hence
 *     the turning of the line of centres) goes to 0.
 * The impacts are slow (1e-6 m/s for 1 kg discs of radius 0.1 m with k_s = 5e5 N/m: xi / d ~ 1e-8),
 * so the line of centres turns by ~1e-8 and the limits hold to ~1e-8. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/model.h"
#include "models/tangential_spring.h"
#include "check_main.h"
#include "collide_helpers.h"
#include "test_env.h"

/* the spring acting at the contact point: rotation is wired into the engine by another change
 * (branch spinspring); the reference already handles it, so test it with the flag set here */
static gr_model spring_rot;

static gr_collide_setup setup(const char *normal, const char *settings, int rot)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s); /* 1 kg, r = 0.1 m, k_s = 5e5 N/m */
    s.normal = gr_model_find(normal);
    spring_rot = *gr_model_find("tangential_spring");
    spring_rot.contact_point = true;
    s.tangential = &spring_rot;
    s.contact.rotation = rot;
    contact_settings(&s.contact, settings);
    return s;
}

static gr_collide_result reference(const gr_collide_setup *s, double speed, double angle)
{
    gr_collision_case cs;
    gr_error err = {0};
    ck_assert(gr_collision_case_oblique(speed, angle, s->radius, &cs, &err) == GR_OK);
    gr_collide_result r;
    ck_assert_msg(gr_collide_reference(s, &cs, &r, &err) == GR_OK, "reference: %s", err.message);
    return r;
}

static gr_contact_coeffs coeffs(const gr_collide_setup *s)
{
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert_msg(gr_contact_prepare(s->normal, s->tangential, &s->contact, 0.5 * s->mass, 0.0, &k,
                                     &err) == GR_OK,
                  "%s", err.message);
    return k;
}

/* 1. sticking: eps_t = cos(w_t t_c), the loss is the spring energy left at the end */
START_TEST(test_sticking_limit)
{
    const int rot = _i;
    /* mu finite releases the spring within xi < k_t s / (mu k_s) at the end: eps_t changes by
     * ~ (k_t / k_s) v_t / (2 mu v_n), 1e-10 here */
    gr_collide_setup s = setup("spring_dashpot", "eps_n=1 mu=1e9 gamma_t=0", rot);
    const gr_contact_coeffs k = coeffs(&s);
    const double t_c = M_PI / k.w0, w_t = sqrt(k.law_t[GR_SPRING_KT] / k.m_t);
    for (int a = 0; a < 3; a++) {
        const double angle = 20.0 + 25.0 * a, sn = sin(angle * M_PI / 180.0);
        const gr_collide_result r = reference(&s, 1e-6, angle);
        const double want = cos(w_t * t_c);
        /* the energy: the contact point's tangential energy share (m_t / m12) sin^2 a, less what
         * eps_t leaves, all of it in the spring at the end */
        const double share = rot ? k.m_t / k.m12 : 1.0,
                     loss = share * sn * sn * (1.0 - want * want);
        VERBOSE("sticking%s at %g deg: eps_t %.12f, cos(w_t t_c) %.12f; loss %.12f, want %.12f, "
                "left in the spring "
                "%.12f, spins %g %g\n",
                rot ? " (rotation)" : "", angle, r.eps_t_measured, want, r.energy_loss, loss,
                r.stored_lost + r.diss_tangential, r.omega1, r.omega2);
        ck_assert_msg(fabs(r.eps_t_measured - want) <= 1e-7, "eps_t %.12f, cos(w_t t_c) = %.12f",
                      r.eps_t_measured, want);
        ck_assert_msg(fabs(r.energy_loss - loss) <= 1e-7, "loss %.12f, want %.12f", r.energy_loss,
                      loss);
        /* (the ledger's components are quadratures outside CVODE's error test) */
        ck_assert_msg(fabs(r.diss_normal) <= 1e-9, "normal dissipation %.3e with eps_n = 1",
                      r.diss_normal);
        ck_assert_msg(fabs(r.energy_loss - r.stored_lost - r.diss_tangential) <= 1e-9,
                      "loss %.12f, spring %.12f + %.12f", r.energy_loss, r.stored_lost,
                      r.diss_tangential);
        if (rot) {
            ck_assert_msg(r.omega1 != 0.0 && r.omega1 == r.omega2, "spins %g %g", r.omega1,
                          r.omega2);
        }
    }
}
END_TEST

/* 2. sliding: eps_t = 1 - mu (1 + eps_n) (m12 / m_t) v_n / v_t */
START_TEST(test_sliding_limit)
{
    const int rot = _i;
    gr_collide_setup s = setup("spring_dashpot", "eps_n=1 mu=0.01 gamma_t=0", rot);
    const gr_contact_coeffs k = coeffs(&s);
    for (int a = 0; a < 2; a++) {
        const double angle = 45.0 + 30.0 * a, an = angle * M_PI / 180.0;
        const gr_collide_result r = reference(&s, 1e-6, angle);
        const double want = 1.0 - 0.01 * 2.0 * (k.m12 / k.m_t) / tan(an);
        VERBOSE("sliding%s at %g deg: eps_t %.12f, Coulomb %.12f\n", rot ? " (rotation)" : "",
                angle, r.eps_t_measured, want);
        ck_assert_msg(fabs(r.eps_t_measured - want) <= 1e-7, "eps_t %.12f, Coulomb %.12f",
                      r.eps_t_measured, want);
        /* all the tangential loss is slip: the spring holds mu F_n / k_t -> 0 at the end */
        ck_assert_msg(fabs(r.stored_lost) <= 1e-9 && r.diss_tangential > 0.0,
                      "stored %.3e, slip %.3e", r.stored_lost, r.diss_tangential);
    }
}
END_TEST

/* 3. the energy balance over the contact, and the dissipation is >= 0 */
START_TEST(test_energy_balance)
{
    static const char *const cases[][2] = {
        {"spring_dashpot", "eps_n=0.6"},
        {"spring_dashpot", "eps_n=0.6 clamp=true gamma_t=0.1"},
        {"hertz", "eps_n=0.8"},
        {"hertz", "eps_n=1 visco_A=0"},
        {"hertz", "viscoelastic=true visco_A=1e-5 clamp=true"},
        {"hertz", "eps_n=0.8 mindlin=true"},
        {"hertz", "eps_n=1 mindlin=true mu=0.2"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        for (int rot = 0; rot < 2; rot++) {
            gr_collide_setup s = setup(cases[c][0], cases[c][1], rot);
            for (int a = 0; a < 3; a++) {
                const double angle = 15.0 + 30.0 * a;
                const gr_collide_result r = reference(&s, 0.1, angle);
                const double sum = r.diss_normal + r.diss_tangential + r.stored_lost - r.work_free;
                VERBOSE("%s %s%s at %g deg: loss %.12f = normal %.6f + tangential %.6f + left %.6f "
                        "- Mindlin %.6f "
                        "(residual %.1e)\n",
                        cases[c][0], cases[c][1], rot ? " rotation" : "", angle, r.energy_loss,
                        r.diss_normal, r.diss_tangential, r.stored_lost, r.work_free,
                        r.energy_loss - sum);
                ck_assert_msg(fabs(r.energy_loss - sum) <= 1e-8,
                              "%s %s at %g deg: loss %.12f, ledger %.12f", cases[c][0], cases[c][1],
                              angle, r.energy_loss, sum);
                ck_assert_msg(r.diss_normal >= -1e-12 && r.diss_tangential >= -1e-9 &&
                                  r.stored_lost >= 0.0,
                              "%s %s: dissipation %.3e %.3e, left %.3e", cases[c][0], cases[c][1],
                              r.diss_normal, r.diss_tangential, r.stored_lost);
                if (!strstr(cases[c][1], "mindlin")) {
                    ck_assert_msg(fabs(r.work_free) <= 1e-6, "%s %s: work without force %.3e",
                                  cases[c][0], cases[c][1], r.work_free);
                }
            }
        }
    }
}
END_TEST

/* 4. convergence in rtol (the stick/slip switches are roots, so no error stays at the kinks),
 * and no engine time step in it */
START_TEST(test_convergence)
{
    gr_collide_setup s = setup("hertz", "eps_n=0.7", 0);
    const double angle = 50.0;
    s.ref_rtol = 1e-13;
    const double best = reference(&s, 0.1, angle).energy_loss;
    double last = INFINITY;
    for (int e = 6; e <= 12; e += 2) {
        s.ref_rtol = pow(10.0, -e);
        const double err = fabs(reference(&s, 0.1, angle).energy_loss - best);
        VERBOSE("rtol 1e-%d: loss error %.3e\n", e, err);
        ck_assert_msg(err <= 300.0 * s.ref_rtol, "rtol %g: loss error %.3e", s.ref_rtol, err);
        ck_assert_msg(err <= last || err <= 1e-12, "rtol %g: loss error %.3e after %.3e",
                      s.ref_rtol, err, last);
        last = err;
    }
    s.ref_rtol = 1e-12;
    const double l0 = reference(&s, 0.1, angle).energy_loss;
    s.dt = 1e-7;
    s.phase = 0.3;
    ck_assert(reference(&s, 0.1, angle).energy_loss == l0);
}
END_TEST

/* 5. the reference approaches the fixed-normal restitution law as the line of centres stops
 * turning (the overlap over the diameter -> 0): the difference falls with the impact speed */
START_TEST(test_law_limit)
{
    const char *const normals[] = {"spring_dashpot", "hertz"};
    for (int n = 0; n < 2; n++) {
        gr_collide_setup s = setup(normals[n], n ? "mindlin=true" : "clamp=true", 0);
        double last = INFINITY;
        for (int v = 0; v < 3; v++) {
            const double speed = pow(10.0, -2.0 * v);
            const gr_collide_result r = reference(&s, speed, 60.0);
            const double diff = fabs(r.energy_loss - r.expected_loss);
            VERBOSE("%s at %g m/s: reference %.12f, law %.12f, |diff| %.2e, xi/d %.1e\n",
                    normals[n], speed, r.energy_loss, r.expected_loss, diff,
                    r.max_overlap / (2.0 * s.radius));
            ck_assert_msg(diff <= fmax(0.1 * last, 1e-8),
                          "%s at %g m/s: |reference - law| %.3e after %.3e", normals[n], speed,
                          diff, last);
            last = diff;
        }
    }
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("spring_reference");
    TCase *tc = tcase_create("reference");
    tcase_add_loop_test(tc, test_sticking_limit, 0, 2);
    tcase_add_loop_test(tc, test_sliding_limit, 0, 2);
    tcase_add_test(tc, test_energy_balance);
    tcase_add_test(tc, test_convergence);
    tcase_add_test(tc, test_law_limit);
    tcase_set_timeout(tc, 120);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
