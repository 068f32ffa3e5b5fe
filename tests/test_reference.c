/* Tests of gr_collide_reference, the CVODE integration of one binary contact, against the exact
 * results of the linear spring-dashpot law (thesis 2.4-2.13, Schwager & Poeschel 2007):
 * head-on energy loss 1 - eps^2 (unclamped), the closed-form clamped restitution, the tangential
 * dashpot's exp(-gamma_t t_c / m12), and the sliding-friction invariants (g.t never reverses,
 * |J_t| <= mu |J_n|). Uses the public API only.
 *
 * Parameters are the thesis's (Table 2.2: M = 3.53e-5 kg, r = 1.5 mm, k_s = 5e5 N/m). Oblique
 * impacts use a slow impact (1e-3 m/s, max overlap ~1e-6 d) so the rotation of the normal during
 * the contact, a real effect of order xi/d the reference resolves, stays below the tolerances. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/model.h"
#include "check_main.h"

#define MASS 3.53e-5
#define RADIUS 1.5e-3
#define K_S 5e5
#define SLOW 1e-3 /* m/s, oblique impacts */

static gr_collide_setup make_setup(const char *tangential, double eps_n, double eps_t, double mu,
                                   bool clamp, int dim)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.normal = gr_model_find("spring_dashpot");
    s.tangential = tangential ? gr_model_find(tangential) : NULL;
    ck_assert_ptr_nonnull(s.normal);
    if (tangential) {
        ck_assert_ptr_nonnull(s.tangential);
    }
    s.contact.k_s = K_S;
    s.contact.eps_n = eps_n;
    s.contact.eps_t = eps_t;
    s.contact.mu = mu;
    s.contact.clamp = clamp;
    s.mass = MASS;
    s.radius = RADIUS;
    s.dim = dim;
    return s;
}

/* Particle 1 flies along +x at speed v into particle 2 at rest; at the touch the line of centres
 * makes angle_deg with the relative velocity. The whole case is rotated by rot_deg. */
static gr_collision_case make_case(double v, double angle_deg, double rot_deg)
{
    const double d = 2.0 * RADIUS, a = angle_deg * M_PI / 180.0, q = rot_deg * M_PI / 180.0;
    const double gap = 0.7 * d;
    double x1[2] = {-gap, 0.0}, v1[2] = {v, 0.0}, x2[2] = {d * cos(a), d * sin(a)};
    gr_collision_case c;
    memset(&c, 0, sizeof c);
    c.x1[0] = cos(q) * x1[0] - sin(q) * x1[1];
    c.x1[1] = sin(q) * x1[0] + cos(q) * x1[1];
    c.v1[0] = cos(q) * v1[0] - sin(q) * v1[1];
    c.v1[1] = sin(q) * v1[0] + cos(q) * v1[1];
    c.x2[0] = cos(q) * x2[0] - sin(q) * x2[1];
    c.x2[1] = sin(q) * x2[0] + cos(q) * x2[1];
    return c;
}

static gr_contact_coeffs coeffs_of(const gr_collide_setup *s)
{
    gr_contact_coeffs c;
    gr_error err = {0};
    int rc =
        gr_contact_prepare(s->normal, s->tangential, &s->contact, 0.5 * s->mass, 0.0, &c, &err);
    ck_assert_msg(rc == GR_OK, "gr_contact_prepare: %s", err.message);
    return c;
}

static gr_collide_result run_ok(const gr_collide_setup *s, const gr_collision_case *c)
{
    gr_collide_result r;
    gr_error err = {0};
    int rc = gr_collide_reference(s, c, &r, &err);
    ck_assert_msg(rc == GR_OK, "gr_collide_reference failed (%d): %s", rc, err.message);
    ck_assert_int_eq(err.code, 0);
    return r;
}

static void assert_rel(double got, double want, double tol, const char *what)
{
    double rel = fabs(got - want) / fabs(want);
    ck_assert_msg(rel <= tol, "%s: got %.15g, want %.15g (relative error %.3g > %.3g)", what, got,
                  want, rel, tol);
}

/* Maximum overlap of m12 xi'' + gamma xi' + k xi = 0, xi(0) = 0, xi'(0) = v (the force is
 * repulsive up to the maximum, so clamping does not matter yet). */
static double xi_max_exact(double v, double w0, double beta)
{
    if (beta < w0) {
        double w = sqrt(w0 * w0 - beta * beta);
        double tm = atan2(w, beta) / w;
        return v / w * exp(-beta * tm) * sin(w * tm);
    }
    double big_w = sqrt(beta * beta - w0 * w0);
    double tm = atanh(big_w / beta) / big_w;
    return v / big_w * exp(-beta * tm) * sinh(big_w * tm);
}

/* ---- unclamped, head-on: Delta T / T = 1 - eps^2 (2.13) ------------------------------------ */

static const double unclamped_eps[] = {0.1, 0.5, 0.9, 1.0};

START_TEST(test_unclamped_head_on)
{
    const double eps = unclamped_eps[_i];
    gr_collide_setup s = make_setup(NULL, eps, 1.0, 0.0, false, 1);
    gr_collision_case c = make_case(1.0, 0.0, 0.0);
    gr_contact_coeffs k = coeffs_of(&s);
    gr_collide_result r = run_ok(&s, &c);

    const double want = 1.0 - eps * eps;
    if (want > 0.0) {
        assert_rel(r.energy_loss, want, 1e-7, "energy loss vs 1 - eps^2");
    } else {
        ck_assert_double_eq_tol(r.energy_loss, 0.0, 1e-9);
    }
    assert_rel(r.eps_n_measured, eps, 1e-7, "eps_n");
    const double m12 = 0.5 * MASS, w0 = sqrt(K_S / m12), beta = k.gamma_n / (2.0 * m12);
    const double w = sqrt(w0 * w0 - beta * beta);
    assert_rel(r.contact_time, M_PI / w, 1e-7, "contact time pi/w");
    assert_rel(r.max_overlap, xi_max_exact(1.0, w0, beta), 1e-7, "max overlap");
    /* int |F_n| dt exceeds the net impulse m12 (1+eps) v by twice the attractive tail's impulse */
    ck_assert_msg(r.normal_impulse >= m12 * (1.0 + eps) * (1.0 - 1e-9),
                  "int |F_n| dt = %.15g below the net impulse %.15g", r.normal_impulse,
                  m12 * (1.0 + eps));
    if (eps == 1.0) {
        assert_rel(r.normal_impulse, 2.0 * m12, 1e-7, "elastic normal impulse 2 m12 v");
    }
    ck_assert_double_eq_tol(r.tangential_impulse, 0.0, 1e-20);
    ck_assert_double_eq_tol(r.impact_angle, 0.0, 1e-12);
    ck_assert(isnan(r.eps_t_measured));
    ck_assert(!r.tangential_reversed);
    ck_assert_double_le_tol(r.momentum_error, 0.0, 1e-15);
    ck_assert(r.dt == 0.0);
    ck_assert_double_eq_tol(r.expected_loss, want, 1e-12);
}
END_TEST

/* ---- clamped, head-on: Schwager & Poeschel's restitution ----------------------------------- */

/* eps 0.1 is overdamped (zeta > 1), the others underdamped. */
static const double clamped_eps[] = {0.1, 0.3, 0.5, 0.9};

START_TEST(test_clamped_head_on)
{
    const double eps = clamped_eps[_i];
    gr_collide_setup s = make_setup(NULL, eps, 1.0, 0.0, true, 1);
    gr_collision_case c = make_case(1.0, 0.0, 0.0);
    gr_contact_coeffs k = coeffs_of(&s);
    gr_collide_result r = run_ok(&s, &c);

    /* Closed form for the coefficient prepare chose (independent of how it chose it). */
    const double m12 = 0.5 * MASS, w0 = sqrt(K_S / m12), beta = k.gamma_n / (2.0 * m12);
    double eps_exact, t_end;
    if (beta < w0) {
        double w = sqrt(w0 * w0 - beta * beta);
        double phase = M_PI - 2.0 * atan(beta / w);
        eps_exact = exp(-(beta / w) * phase);
        t_end = phase / w;
    } else {
        double big_w = sqrt(beta * beta - w0 * w0);
        eps_exact = exp(-(beta / big_w) * log((beta + big_w) / (beta - big_w)));
        t_end = 2.0 / big_w * atanh(big_w / beta);
    }
    assert_rel(r.eps_n_measured, eps_exact, 1e-7, "clamped eps_n vs closed form");
    assert_rel(sqrt(1.0 - r.energy_loss), eps_exact, 1e-7, "sqrt(1 - loss) vs closed form");
    assert_rel(r.contact_time, t_end, 1e-7, "clamped contact time");
    assert_rel(r.max_overlap, xi_max_exact(1.0, w0, beta), 1e-7, "max overlap");
    /* prepare inverts the closed form, so the requested eps_n must come out */
    assert_rel(r.eps_n_measured, eps, 1e-7, "clamped eps_n vs requested");
    ck_assert_double_le_tol(r.momentum_error, 0.0, 1e-15);
}
END_TEST

/* The clamped law at eps_n = 1 has no dashpot: the force k xi starts at zero (a root at t = 0
 * that must not end the contact). */
START_TEST(test_clamped_elastic)
{
    gr_collide_setup s = make_setup(NULL, 1.0, 1.0, 0.0, true, 1);
    gr_collision_case c = make_case(1.0, 0.0, 0.0);
    gr_collide_result r = run_ok(&s, &c);
    ck_assert_double_eq_tol(r.energy_loss, 0.0, 1e-9);
    assert_rel(r.contact_time, M_PI / sqrt(K_S / (0.5 * MASS)), 1e-7, "elastic contact time");
}
END_TEST

/* ---- tangential dashpot, 45 degrees -------------------------------------------------------- */

START_TEST(test_tangential_dashpot_45)
{
    const bool clamp = _i / 2;
    const double eps_t = (_i % 2) ? 0.7 : 0.3, eps_n = 0.5;
    gr_collide_setup s = make_setup("tangential_dashpot", eps_n, eps_t, 0.0, clamp, 2);
    gr_collision_case c = make_case(SLOW, 45.0, 0.0);
    gr_contact_coeffs k = coeffs_of(&s);
    gr_collide_result r = run_ok(&s, &c);

    ck_assert_double_eq_tol(r.impact_angle, 45.0, 1e-9);
    /* m12 dg_t/dt = -gamma_t g_t during the contact. Unclamped, |r| = d at both ends and
     * |r| g.t decays exactly so; clamped, the contact ends at |r| = d - xi_end (~1e-6 d here). */
    const double want = exp(-k.gamma_t * r.contact_time / (0.5 * MASS));
    assert_rel(r.eps_t_measured, want, clamp ? 1e-6 : 1e-9, "eps_t vs exp(-gamma_t t_c / m12)");
    assert_rel(r.eps_t_measured, eps_t, 1e-6, "eps_t vs requested");
    assert_rel(r.eps_n_measured, eps_n, 1e-5, "eps_n at 45 degrees");
    assert_rel(r.energy_loss, 1.0 - (eps_n * eps_n + eps_t * eps_t) / 2.0, 1e-5, "loss vs (2.14)");
    ck_assert(!r.tangential_reversed);
    ck_assert_double_le_tol(r.momentum_error, 0.0, 1e-15);
}
END_TEST

/* ---- sliding friction ---------------------------------------------------------------------- */

typedef struct friction_case {
    double angle, mu;
} friction_case;

/* sliding through the whole contact, and sticking part-way (eps_t = 0) */
static const friction_case friction_cases[] = {
    {45.0, 0.1}, {30.0, 0.2}, {80.0, 0.8}, {45.0, 1.0}, {10.0, 0.05}, {60.0, 2.0},
};

START_TEST(test_sliding_friction_clamped)
{
    const friction_case fc = friction_cases[_i];
    const double eps_n = 0.5;
    gr_collide_setup s = make_setup("sliding_friction", eps_n, 1.0, fc.mu, true, 2);
    gr_collision_case c = make_case(SLOW, fc.angle, 0.0);
    gr_collide_result r = run_ok(&s, &c);

    ck_assert_msg(!r.tangential_reversed, "g.t reversed (angle %g, mu %g)", fc.angle, fc.mu);
    ck_assert_msg(r.eps_t_measured >= -1e-12, "eps_t = %g < 0", r.eps_t_measured);
    ck_assert_msg(r.tangential_impulse <= fc.mu * r.normal_impulse * (1.0 + 1e-9),
                  "|J_t| = %.15g > mu |J_n| = %.15g", r.tangential_impulse,
                  fc.mu * r.normal_impulse);
    /* eps_t = max(0, 1 - mu (1 + eps_n) |g_n| / |g_t|) without rotation */
    const double a = fc.angle * M_PI / 180.0;
    const double want = fmax(0.0, 1.0 - fc.mu * (1.0 + eps_n) / tan(a));
    ck_assert_msg(fabs(r.eps_t_measured - want) <= 1e-5, "eps_t %.12g, want %.12g",
                  r.eps_t_measured, want);
    if (want == 0.0) {
        /* stuck: the tangential impulse took out all tangential momentum, m12 |g_t| */
        assert_rel(r.tangential_impulse, 0.5 * MASS * SLOW * sin(a), 1e-6, "stuck J_t");
        ck_assert_double_eq_tol(r.eps_t_measured, 0.0, 1e-9);
    }
    ck_assert_double_le_tol(r.momentum_error, 0.0, 1e-15);
}
END_TEST

/* Unclamped, the friction mu |F_n| also acts in the attractive tail, so |J_t| may exceed
 * mu |J_n| (J_n is the net normal impulse); the velocity still never reverses. */
START_TEST(test_sliding_friction_unclamped)
{
    const friction_case fc = friction_cases[_i];
    gr_collide_setup s = make_setup("sliding_friction", 0.5, 1.0, fc.mu, false, 2);
    gr_collision_case c = make_case(SLOW, fc.angle, 0.0);
    gr_collide_result r = run_ok(&s, &c);
    ck_assert(!r.tangential_reversed);
    ck_assert_msg(r.eps_t_measured >= -1e-12, "eps_t = %g < 0", r.eps_t_measured);
    ck_assert(r.eps_t_measured <= 1.0);
}
END_TEST

/* ---- invariances --------------------------------------------------------------------------- */

/* Rotating the whole case or swapping the particles changes nothing. */
START_TEST(test_frame_invariance)
{
    gr_collide_setup s = make_setup("tangential_dashpot", 0.6, 0.4, 0.0, true, 2);
    gr_collision_case c0 = make_case(0.5, 35.0, 0.0);
    gr_collide_result r0 = run_ok(&s, &c0);
    gr_collision_case c1 = make_case(0.5, 35.0, 123.0);
    gr_collide_result r1 = run_ok(&s, &c1);
    gr_collision_case c2;
    memcpy(c2.x1, c1.x2, sizeof c2.x1);
    memcpy(c2.v1, c1.v2, sizeof c2.v1);
    memcpy(c2.x2, c1.x1, sizeof c2.x2);
    memcpy(c2.v2, c1.v1, sizeof c2.v2);
    gr_collide_result r2 = run_ok(&s, &c2);
    const gr_collide_result *rs[2] = {&r1, &r2};
    for (int i = 0; i < 2; i++) {
        assert_rel(rs[i]->energy_loss, r0.energy_loss, 1e-9, "loss");
        assert_rel(rs[i]->eps_n_measured, r0.eps_n_measured, 1e-9, "eps_n");
        assert_rel(rs[i]->eps_t_measured, r0.eps_t_measured, 1e-9, "eps_t");
        assert_rel(rs[i]->contact_time, r0.contact_time, 1e-9, "contact time");
        assert_rel(rs[i]->max_overlap, r0.max_overlap, 1e-9, "max overlap");
        assert_rel(rs[i]->impact_angle, r0.impact_angle, 1e-9, "impact angle");
    }
}
END_TEST

/* Table 2.1 through the public case table: case 2 is head-on along the diagonal. */
START_TEST(test_table21)
{
    gr_collide_setup s = make_setup("tangential_dashpot", 0.6, 0.6, 0.0, false, 2);
    s.mass = 1.0;
    for (int n = 1; n <= 4; n++) {
        gr_collision_case c;
        gr_error err = {0};
        ck_assert_int_eq(gr_collision_case_table21(n, s.radius, &c, &err), GR_OK);
        s.dim = n == 1 ? 1 : 2;
        gr_collide_result r = run_ok(&s, &c);
        ck_assert_msg(r.energy_loss > 0.0 && r.energy_loss < 1.0, "case %d loss %g", n,
                      r.energy_loss);
        ck_assert_double_le_tol(r.momentum_error, 0.0, 1e-15);
        if (n <= 2) {
            ck_assert_double_eq_tol(r.impact_angle, 0.0, 1e-9);
            assert_rel(r.energy_loss, 1.0 - 0.36, 1e-7, "head-on loss");
        }
    }
}
END_TEST

/* ---- errors -------------------------------------------------------------------------------- */

static void expect_error(const gr_collide_setup *s, const gr_collision_case *c, int code,
                         const char *needle)
{
    gr_collide_result r;
    gr_error err = {0};
    int rc = gr_collide_reference(s, c, &r, &err);
    ck_assert_int_eq(rc, code);
    ck_assert_int_eq(err.code, code);
    ck_assert_msg(strstr(err.message, needle) != NULL, "message '%s' lacks '%s'", err.message,
                  needle);
    ck_assert_ptr_null(strchr(err.message, '\n'));
}

START_TEST(test_errors)
{
    gr_collide_setup s = make_setup(NULL, 0.0, 1.0, 0.0, false, 1);
    gr_collision_case c = make_case(1.0, 0.0, 0.0);
    expect_error(&s, &c, GR_EINVAL, "sticks");

    s = make_setup(NULL, 0.5, 1.0, 0.0, false, 2);
    gr_collision_case apart = c;
    apart.v1[0] = -1.0;
    expect_error(&s, &apart, GR_EINVAL, "never touch");
    gr_collision_case miss = make_case(1.0, 0.0, 0.0);
    miss.x2[1] = 3.0 * RADIUS;
    expect_error(&s, &miss, GR_EINVAL, "never touch");
    gr_collision_case still = c;
    still.v1[0] = 0.0;
    expect_error(&s, &still, GR_EINVAL, "never touch");
    gr_collision_case overlap = c;
    overlap.x1[0] = RADIUS;
    overlap.x2[0] = 2.0 * RADIUS;
    expect_error(&s, &overlap, GR_EINVAL, "overlap");

    gr_collide_setup bad = s;
    bad.dim = 4;
    expect_error(&bad, &c, GR_EINVAL, "dim must be 1, 2 or 3");
    /* 3D: spins without rotation are refused */
    bad = s;
    bad.dim = 3;
    bad.w1[0] = 10.0;
    expect_error(&bad, &c, GR_EINVAL, "initial spins need rotation");
    bad = s;
    bad.normal = NULL;
    expect_error(&bad, &c, GR_EINVAL, "model");
    bad = s;
    bad.mass = 0.0;
    expect_error(&bad, &c, GR_EINVAL, "mass");

    /* so soft that the centres would meet: refused, not integrated through */
    bad = s;
    bad.contact.k_s = 1e-3;
    bad.contact.eps_n = 1.0;
    expect_error(&bad, &c, GR_EUNSTABLE, "centres nearly met");
}
END_TEST

static Suite *reference_suite(void)
{
    Suite *s = suite_create("reference");
    TCase *tc = tcase_create("physics");
    tcase_add_loop_test(tc, test_unclamped_head_on, 0,
                        (int)(sizeof unclamped_eps / sizeof unclamped_eps[0]));
    tcase_add_loop_test(tc, test_clamped_head_on, 0,
                        (int)(sizeof clamped_eps / sizeof clamped_eps[0]));
    tcase_add_test(tc, test_clamped_elastic);
    tcase_add_loop_test(tc, test_tangential_dashpot_45, 0, 4);
    tcase_add_loop_test(tc, test_sliding_friction_clamped, 0,
                        (int)(sizeof friction_cases / sizeof friction_cases[0]));
    tcase_add_loop_test(tc, test_sliding_friction_unclamped, 0,
                        (int)(sizeof friction_cases / sizeof friction_cases[0]));
    tcase_add_test(tc, test_frame_invariance);
    tcase_add_test(tc, test_table21);
    suite_add_tcase(s, tc);
    TCase *te = tcase_create("errors");
    tcase_add_test(te, test_errors);
    suite_add_tcase(s, te);
    return s;
}

int main(void) { return gr_test_run(reference_suite()); }
