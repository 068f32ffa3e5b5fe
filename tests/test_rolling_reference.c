/* The CVODE reference of the rolling law (rolling_friction: a torque pair mu_r |F_n| R_eff against
 * the relative spin w1 - w2 across n; src/collide/reference.c, models/reference.h
 * gr_reference_rolling), on discs and on spheres spinning about any axis:
 *   - discs: the torque changes w1 - w2 only, at a rate proportional to |F_n|, so over the contact
 *     it delivers J = min(mu_r R_eff int |F_n| dt, I |w1 - w2| / 2) whatever the geometry does:
 *     the reference's rolling loss must be the law's own J |dw_0| - J^2 / I
 *     (gr_model.spin_loss) with its own normal impulse, to 1e-9, rolling throughout (small mu_r)
 *     and arrested (large mu_r, where w1 - w2 ends at 0);
 *   - the energy balance closes with the rolling term, for linear and Hertz normal laws, with the
 *     history spring beside it;
 *   - spheres: a spin of 1e-7 rad/s about x takes the contact into the 3D integration; its numbers
 *     must be the plane's to 1e-8; a pure twist (w1 - w2 along the normal at the touch) is left to
 *     the turning normal, which drags it across n, where the arrested law holds it (the engine
 *     agrees); with spins about every axis the balance closes and the engine (its cap, the torque
 *     that stops the rolling in one step) converges to the reference: from 100 to 1600 steps per
 *     contact its difference falls at least 4 times (16 at first order) and ends within dt / t_c.
 * The particles are the thesis's (Table 2.2: r = 1.5 mm, 3.53e-5 kg, k_s = 5e5 N/m), the impact
 * 0.5 m/s at 30 degrees. */
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

typedef struct roll_case {
    const char *normal, *tangential;
    const char *settings;
} roll_case;

static const roll_case cases[] = {
    {"spring_dashpot", "tangential_dashpot", "eps_n=0.6 eps_t=0.5 mu_r=0.02"}, /* rolls on */
    {"spring_dashpot", "tangential_spring", "eps_n=0.6 mu_r=0.5"},             /* arrested */
    {"hertz", "tangential_spring", "eps_n=0.8 mu_r=0.05"},
    {"hertz", "sliding_friction", "eps_n=0.8 mu=0.3 mu_r=0.3"},
};
enum { N_CASES = sizeof cases / sizeof cases[0] };

static gr_collide_setup setup(const roll_case *c, int dim)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.dim = dim;
    s.normal = gr_model_find(c->normal);
    s.tangential = gr_model_find(c->tangential);
    s.rolling = gr_model_find("rolling_friction");
    s.mass = 3.53e-5;
    s.radius = 1.5e-3;
    s.contact.rotation = true;
    s.contact.inertia_factor = 0.4;
    contact_settings(&s.contact, c->settings);
    return s;
}

/* E before the impact: the relative motion's m12 |g|^2 / 2 and both spins' I |w|^2 / 2 */
static double energy_before(const gr_collide_setup *s, const double w1[3], const double w2[3])
{
    const gr_collision_case cs = collide_impact(s);
    const double g0 = cs.v2[0] - cs.v1[0], g1 = cs.v2[1] - cs.v1[1];
    const double I = s->contact.inertia_factor * s->mass * s->radius * s->radius;
    double ww = 0.0;
    for (int k = 0; k < 3; k++) {
        ww += w1[k] * w1[k] + w2[k] * w2[k];
    }
    return 0.25 * s->mass * (g0 * g0 + g1 * g1) + 0.5 * I * ww;
}

static void check_balance(const roll_case *c, const gr_collide_result *r, const char *what)
{
    const double sum =
        r->diss_normal + r->diss_tangential + r->diss_rolling + r->stored_lost - r->work_free;
    VERBOSE("%s + %s %s, %s: loss %.12f = normal %.6f + tangential %.6f + rolling %.6f + left "
            "%.6f (residual %.1e)\n",
            c->normal, c->tangential, c->settings, what, r->energy_loss, r->diss_normal,
            r->diss_tangential, r->diss_rolling, r->stored_lost, r->energy_loss - sum);
    ck_assert_msg(fabs(r->energy_loss - sum) <= 1e-8, "%s %s, %s: loss %.12f, ledger %.12f",
                  c->normal, c->settings, what, r->energy_loss, sum);
    ck_assert_msg(r->diss_rolling > 0.0, "%s %s, %s: the rolling law did nothing", c->normal,
                  c->settings, what);
}

START_TEST(test_discs_follow_the_law)
{
    const roll_case *c = &cases[_i];
    gr_collide_setup s = setup(c, 2);
    s.omega1 = 300.0;
    s.omega2 = -100.0;
    const gr_collide_result r = collide_impact_run(&s, true);
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert(gr_contact_prepare(s.normal, s.tangential, &s.contact, 0.5 * s.mass, 0.0, &k, &err) ==
              GR_OK);
    ck_assert(gr_contact_prepare_rolling(s.rolling, &s.contact, 0.5 * s.mass, 0.0, &k, &err) ==
              GR_OK);
    const double I = s.contact.inertia_factor * s.mass * s.radius * s.radius;
    const double w1[3] = {0.0, 0.0, s.omega1}, w2[3] = {0.0, 0.0, s.omega2};
    const double e0 = energy_before(&s, w1, w2);
    const double law =
        s.rolling->spin_loss(&k, r.normal_impulse, 0.5 * s.radius, I, s.omega1 - s.omega2) / e0;
    const double dw = r.omega1 - r.omega2;
    VERBOSE("%s + %s %s: rolling loss %.12f, the law %.12f; w1 - w2 400 -> %.6f rad/s\n", c->normal,
            c->tangential, c->settings, r.diss_rolling, law, dw);
    ck_assert_msg(fabs(r.diss_rolling - law) <= 1e-9 * law, "%s: rolling loss %.12f, law %.12f",
                  c->settings, r.diss_rolling, law);
    check_balance(c, &r, "discs");
    /* the engine converges to it at first order */
    double d[2];
    const int steps[2] = {100, 1600};
    for (int j = 0; j < 2; j++) {
        s.steps_per_contact = steps[j];
        const gr_collide_result e = collide_impact_run(&s, false);
        d[j] = fmax(fabs(e.energy_loss - r.energy_loss),
                    fmax(fabs(e.omega1 - r.omega1), fabs(e.omega2 - r.omega2)) / 400.0);
        VERBOSE("  engine at %d steps per contact: %.3e (w1 - w2 %.6f)\n", steps[j], d[j],
                e.omega1 - e.omega2);
    }
    ck_assert_msg(d[1] <= 1.0 / 1600.0 && d[1] <= d[0] / 4.0,
                  "%s: engine %.3e at 100, %.3e at 1600", c->settings, d[0], d[1]);
}
END_TEST

/* the largest difference of two 3D results: the loss, velocities over 0.5 m/s, spins over 400 */
static double distance(const gr_collide_result *a, const gr_collide_result *b)
{
    double d = fabs(a->energy_loss - b->energy_loss);
    for (int k = 0; k < 3; k++) {
        d = fmax(d, fabs(a->v2[k] - b->v2[k]) / 0.5);
        d = fmax(d, fabs(a->w1[k] - b->w1[k]) / 400.0);
        d = fmax(d, fabs(a->w2[k] - b->w2[k]) / 400.0);
    }
    return d;
}

START_TEST(test_spheres)
{
    const roll_case *c = &cases[_i];
    gr_collide_setup s = setup(c, 3);
    /* in the plane (w along z), then tilted by 1e-7 rad/s about x: the 3D integration */
    s.w1[2] = 300.0;
    s.w2[2] = -100.0;
    const gr_collide_result plane = collide_impact_run(&s, true);
    s.w1[0] = 1e-7;
    gr_collide_result tilted = collide_impact_run(&s, true);
    tilted.w1[0] -= 1e-7;
    const double dp = distance(&plane, &tilted);
    VERBOSE("%s + %s %s: 3D reference vs the plane's %.2e\n", c->normal, c->tangential, c->settings,
            dp);
    ck_assert_msg(dp < 1e-8, "%s: the 3D reference differs from the plane's by %.3e", c->settings,
                  dp);
    /* spins about every axis, and a pure twist (w1 - w2 along x, the normal at the touch) */
    static const double spins[2][2][3] = {{{300.0, 100.0, 150.0}, {-100.0, 0.0, -300.0}},
                                          {{300.0, 0.0, 0.0}, {-100.0, 0.0, 0.0}}};
    for (int k = 0; k < 2; k++) {
        memcpy(s.w1, spins[k][0], sizeof s.w1);
        memcpy(s.w2, spins[k][1], sizeof s.w2);
        s.steps_per_contact = 200;
        const gr_collide_result r = collide_impact_run(&s, true);
        if (k == 0) {
            check_balance(c, &r, "spheres");
        } else { /* the twist keeps its size about the normal, which turns by < 7e-3 rad */
            VERBOSE("  twist: w1 (%.6f, %.6f, %.6f), rolling loss %.3e\n", r.w1[0], r.w1[1],
                    r.w1[2], r.diss_rolling);
            ck_assert_msg(fabs(r.w1[0] - r.w2[0] - 400.0) < 1e-2, "twist %.6f", r.w1[0] - r.w2[0]);
        }
        double d[2];
        const int steps[2] = {100, 1600};
        for (int j = 0; j < 2; j++) {
            s.steps_per_contact = steps[j];
            const gr_collide_result e = collide_impact_run(&s, false);
            d[j] = distance(&e, &r);
            VERBOSE("  spins %d, engine at %d steps per contact: %.3e (loss %.8f / %.8f)\n", k,
                    steps[j], d[j], e.energy_loss, r.energy_loss);
        }
        ck_assert_msg(d[1] <= 1.0 / 1600.0 && d[1] <= d[0] / 4.0,
                      "%s, spins %d: engine %.3e at 100, %.3e at 1600", c->settings, k, d[0], d[1]);
    }
}
END_TEST

static Suite *rolling_ref_suite(void)
{
    Suite *s = suite_create("rolling-reference");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 600);
    tcase_add_loop_test(tc, test_discs_follow_the_law, 0, N_CASES);
    tcase_add_loop_test(tc, test_spheres, 0, N_CASES);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(rolling_ref_suite()); }
