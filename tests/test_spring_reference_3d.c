/* The CVODE reference of the Cundall-Strack spring between spheres, out of the impact's plane
 * (src/collide/reference.c, ref3; models/tangential_spring_reference.h, the vector form: s in the
 * tangent plane, sticking with ds/dt = g_c - (s.g / |r|) n, slipping along the direction of
 * k_t s + gamma_t g_c at mu |F_n|), linear and Mindlin, clamped and not, with and without the
 * dashpot beside the spring, sticking through and slipping at once:
 *   - a spin about x of 1e-7 rad/s takes the contact into the 3D integration with the vector
 *     state; its numbers must be the plane's (the 2D integration with the scalar s) to 1e-8;
 *   - spins about every axis: the energy balance closes (the loss is the normal and tangential
 *     dissipation plus the elastic energy left in the contact, less what a Mindlin k_t adds by
 *     changing), the dissipation is >= 0, the friction impulse stays within mu times the normal
 *     one, momentum is conserved;
 *   - the engine (its 3D step, models/tangential_spring.h) converges to the reference at first
 *     order in dt / t_c: at 400 steps per contact the loss, spins and velocities are closer than
 *     at 100, by at least half the factor 4 a first-order error gives, and within 1e-3 of it.
 * The spheres are the thesis's (Table 2.2: r = 1.5 mm, 3.53e-5 kg, k_s = 5e5 N/m), the impact
 * 0.5 m/s at 30 degrees; spins of a few hundred rad/s give the contact point a velocity out of
 * the plane comparable to the impact's. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/model.h"
#include "check_main.h"
#include "collide_helpers.h"
#include "test_env.h"

typedef struct spring_case {
    const char *normal;
    const char *settings; /* key=value pairs of the contact parameters */
} spring_case;

static const spring_case cases[] = {
    {"spring_dashpot", "eps_n=0.6"}, /* unclamped: F_n changes sign at the end */
    {"spring_dashpot", "eps_n=0.6 clamp=true gamma_t=0.002"},
    {"spring_dashpot", "eps_n=0.9 mu=0.05"}, /* slips from the touch */
    {"hertz", "eps_n=0.8"},
    {"hertz", "eps_n=0.8 mindlin=true"},
    {"hertz", "eps_n=1 visco_A=0 mindlin=true mu=0.2"},
};
enum { N_CASES = sizeof cases / sizeof cases[0] };

static gr_collide_setup setup(const spring_case *c)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.dim = 3;
    s.normal = gr_model_find(c->normal);
    s.tangential = gr_model_find("tangential_spring");
    s.mass = 3.53e-5;
    s.radius = 1.5e-3;
    s.contact.rotation = true;
    s.contact.inertia_factor = 0.4;
    contact_settings(&s.contact, c->settings);
    return s;
}

static void set_spins(gr_collide_setup *s, const double w1[3], const double w2[3])
{
    memcpy(s->w1, w1, sizeof s->w1);
    memcpy(s->w2, w2, sizeof s->w2);
}

/* the largest difference of two results: the loss, the velocities over the impact speed, the
 * spins over 400 rad/s */
static double distance(const gr_collide_result *a, const gr_collide_result *b)
{
    double d = fabs(a->energy_loss - b->energy_loss);
    for (int k = 0; k < 3; k++) {
        d = fmax(d, fabs(a->v1[k] - b->v1[k]) / 0.5);
        d = fmax(d, fabs(a->v2[k] - b->v2[k]) / 0.5);
        d = fmax(d, fabs(a->w1[k] - b->w1[k]) / 400.0);
        d = fmax(d, fabs(a->w2[k] - b->w2[k]) / 400.0);
    }
    return d;
}

static const double W1[3] = {400.0, 100.0, 150.0}, W2[3] = {-100.0, 0.0, -300.0};

START_TEST(test_tilt_is_the_plane)
{
    const spring_case *c = &cases[_i];
    gr_collide_setup s = setup(c);
    const double w1[3] = {0.0, 0.0, 150.0}, w2[3] = {0.0, 0.0, -300.0};
    set_spins(&s, w1, w2);
    const gr_collide_result plane = collide_impact_run(&s, true);
    s.w1[0] = 1e-7;
    gr_collide_result tilted = collide_impact_run(&s, true);
    tilted.w1[0] -= 1e-7; /* the spin about x the plane's run did not have */
    const double d = distance(&plane, &tilted);
    VERBOSE("%s %s: 3D reference vs the plane's %.2e (loss %.10f, eps_t %.6f)\n", c->normal,
            c->settings, d, plane.energy_loss, plane.eps_t_measured);
    ck_assert_msg(d < 1e-8, "%s %s: the 3D reference differs from the plane's by %.3e", c->normal,
                  c->settings, d);
    ck_assert_msg(fabs(tilted.v2[2]) < 1e-9, "%s: v_z %g", c->normal, tilted.v2[2]);
}
END_TEST

START_TEST(test_balance_out_of_plane)
{
    const spring_case *c = &cases[_i];
    gr_collide_setup s = setup(c);
    set_spins(&s, W1, W2);
    const gr_collide_result r = collide_impact_run(&s, true);
    const double sum = r.diss_normal + r.diss_tangential + r.stored_lost - r.work_free;
    VERBOSE("%s %s: loss %.12f = normal %.6f + tangential %.6f + left %.6f - Mindlin %.6f "
            "(residual %.1e), v_z %.4f, w1_y %.3f\n",
            c->normal, c->settings, r.energy_loss, r.diss_normal, r.diss_tangential, r.stored_lost,
            r.work_free, r.energy_loss - sum, r.v2[2], r.w1[1]);
    ck_assert_msg(fabs(r.v2[2]) > 1e-3 && fabs(r.w1[1] - W1[1]) > 0.5,
                  "%s: the contact stayed in the plane: the test tests nothing", c->normal);
    ck_assert_msg(fabs(r.energy_loss - sum) <= 1e-8, "%s %s: loss %.12f, ledger %.12f", c->normal,
                  c->settings, r.energy_loss, sum);
    ck_assert_msg(r.diss_normal >= -1e-12 && r.diss_tangential >= -1e-9 && r.stored_lost >= 0.0,
                  "%s %s: dissipation %.3e %.3e, left %.3e", c->normal, c->settings, r.diss_normal,
                  r.diss_tangential, r.stored_lost);
    if (!strstr(c->settings, "mindlin")) {
        ck_assert_msg(fabs(r.work_free) <= 1e-9, "%s %s: work without force %.3e", c->normal,
                      c->settings, r.work_free);
    }
    /* the Coulomb bound: the friction impulse <= mu x the normal one (J_n = int |F_n| dt) */
    VERBOSE("  impulses: tangential %.12e, mu x normal %.12e\n", r.tangential_impulse,
            s.contact.mu * r.normal_impulse);
    ck_assert_msg(r.tangential_impulse <= s.contact.mu * r.normal_impulse * (1.0 + 1e-9),
                  "%s %s: friction impulse %.12e > mu x normal %.12e", c->normal, c->settings,
                  r.tangential_impulse, s.contact.mu * r.normal_impulse);
    /* momentum: the velocities' sum is unchanged (the impact lies in the plane z = 0) */
    const gr_collision_case cs = collide_impact(&s);
    for (int k = 0; k < 3; k++) {
        const double before = k < 2 ? cs.v1[k] + cs.v2[k] : 0.0;
        ck_assert_double_le(fabs(r.v1[k] + r.v2[k] - before), 1e-15);
    }
}
END_TEST

START_TEST(test_engine_converges)
{
    const spring_case *c = &cases[_i];
    gr_collide_setup s = setup(c);
    set_spins(&s, W1, W2);
    const gr_collide_result ref = collide_impact_run(&s, true);
    double d[2];
    const int steps[2] = {100, 400};
    for (int k = 0; k < 2; k++) {
        s.steps_per_contact = steps[k];
        const gr_collide_result e = collide_impact_run(&s, false);
        d[k] = distance(&e, &ref);
        VERBOSE("%s %s: engine at %d steps per contact vs the 3D reference: %.3e (loss %.8f / "
                "%.8f)\n",
                c->normal, c->settings, steps[k], d[k], e.energy_loss, ref.energy_loss);
    }
    ck_assert_msg(d[1] <= 1e-3, "%s %s: engine and 3D reference differ by %.3e", c->normal,
                  c->settings, d[1]);
    ck_assert_msg(d[1] <= d[0] / 2.0, "%s %s: no convergence: %.3e at 100 steps, %.3e at 400",
                  c->normal, c->settings, d[0], d[1]);
}
END_TEST

static Suite *spring3_suite(void)
{
    Suite *s = suite_create("spring-reference-3d");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 600);
    tcase_add_loop_test(tc, test_tilt_is_the_plane, 0, N_CASES);
    tcase_add_loop_test(tc, test_balance_out_of_plane, 0, N_CASES);
    tcase_add_loop_test(tc, test_engine_converges, 0, N_CASES);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(spring3_suite()); }
