/* The Cundall-Strack tangential spring's pair law (models/tangential_spring.h) on its own: one
 * step of the law against its formula, the Coulomb limit (|F_t| = mu |F_n|, no NaN), the energy
 * it books, and a tangential oscillator driven through a Hertz-free linear normal contact: a
 * sticking contact reverses the contact point's tangential velocity (Walton's beta > 0,
 * eps_t = -cos(w_t t_c) for an undamped spring), a sliding one loses 2 mu v_n. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/tangential_spring.h"
#include "check_main.h"

static gr_contact_coeffs coeffs(double k_t, double gamma_t, double mu, double dt)
{
    gr_contact_coeffs c = {0};
    c.law_t[GR_SPRING_KT] = k_t;
    c.law_t[GR_SPRING_GAMMA] = gamma_t;
    c.law_t[GR_SPRING_DT] = dt;
    c.mu = mu;
    return c;
}

static gr_tangential_force step(const gr_contact_coeffs *c, double *s, double g_t, double f_n,
                                int acts)
{
    gr_tangential_in in = {.g_t = g_t, .f_n = f_n, .acts = acts, .m12_dt = 0.0, .hist = s};
    return gr_tangential_tangential_spring(c, in);
}

START_TEST(test_stick_step)
{
    const gr_contact_coeffs c = coeffs(200.0, 0.3, 0.5, 1e-4);
    double s = 2e-4;
    const gr_tangential_force o = step(&c, &s, 0.7, 10.0, 1);
    const double s_want = 2e-4 + 0.7 * 1e-4;
    ck_assert_double_eq_tol(s, s_want, 1e-18);
    ck_assert_double_eq_tol(o.f, -200.0 * s_want - 0.3 * 0.7, 1e-15);
    ck_assert_double_eq_tol(o.e, 0.5 * 200.0 * s_want * s_want, 1e-18);
    /* dissipation = dashpot + the explicit step's k g^2 dt / 2 */
    ck_assert_double_eq_tol(o.p, 0.3 * 0.7 * 0.7 + 0.5 * 200.0 * 0.7 * 0.7 * 1e-4, 1e-12);
}
END_TEST

START_TEST(test_coulomb_limit)
{
    const double k = 200.0, gamma = 0.3, mu = 0.5, f_n = 10.0, dt = 1e-4;
    const gr_contact_coeffs c = coeffs(k, gamma, mu, dt);
    for (int sign = -1; sign <= 1; sign += 2) {
        double s = sign * 1.0; /* k s = 200 >> mu f_n = 5 */
        const double g = 0.2 * sign;
        const gr_tangential_force o = step(&c, &s, g, f_n, 1);
        ck_assert_double_eq_tol(fabs(o.f), mu * f_n, 1e-14);
        ck_assert(o.f * sign < 0.0);                             /* opposes the displacement */
        ck_assert_double_eq_tol(-k * s - gamma * g, o.f, 1e-13); /* spring rescaled (LAMMPS) */
        ck_assert(o.fc == -k * s);                               /* the conservative part */
        const double s_old = sign * 1.0,
                     s_trial = s_old + g * dt; /* dropped beyond the trapezoid's work */
        ck_assert_double_eq_tol(o.lost, 0.5 * k * (s_old + s) * (s_trial - s), 1e-12);
        ck_assert(o.lost > 0.0);
        ck_assert(isfinite(o.p) && o.p > 0.0);
    }
    /* F_n = 0 while the contact acts (unclamped law at the edge): no force, no NaN */
    double s = 1e-3;
    gr_tangential_force o = step(&c, &s, 0.1, 0.0, 1);
    ck_assert(o.f == 0.0 && isfinite(s) && isfinite(o.p) && isfinite(o.e));
    /* nothing stored, nothing moving: no force even at mu = 0 */
    const gr_contact_coeffs c0 = coeffs(k, gamma, 0.0, dt);
    s = 0.0;
    o = step(&c0, &s, 0.0, f_n, 1);
    ck_assert(o.f == 0.0 && s == 0.0 && o.p == 0.0);
    /* the contact breaks: history dropped, its energy booked as lost (dissipated) together with
     * the work its last force did over the step, k s_old g dt / 2 (the kernel's trapezoid) */
    s = 0.01;
    o = step(&c, &s, 0.1, 0.0, 0);
    ck_assert(s == 0.0 && o.f == 0.0 && o.e == 0.0);
    ck_assert_double_eq_tol(o.lost, 0.5 * k * 0.01 * (0.01 + 0.1 * dt), 1e-18);
    ck_assert_double_eq_tol(o.p * dt, o.lost, 1e-18);
}
END_TEST

/* One binary contact: a linear normal spring (k_n, m) with impact speed v_n gives
 * F_n = m v_n w_n sin(w_n t) for t < t_c = pi / w_n; the contact point's tangential velocity
 * obeys m dg/dt = F_t (no rotation: m_t = m12 = m). Symplectic Euler, the law first. Returns
 * g after the contact; *ledger: |KE_t + U_t + dissipated - KE_t(0)| at the end. */
static double contact(double k_t, double gamma_t, double mu, double v_n, double g0, int steps,
                      double *ledger)
{
    const double m = 1.0, k_n = 1e4, w_n = sqrt(k_n / m), t_c = M_PI / w_n, dt = t_c / steps;
    const gr_contact_coeffs c = coeffs(k_t, gamma_t, mu, dt);
    double s = 0.0, g = g0, lost = 0.0, e = 0.0;
    for (int n = 0; n < steps; n++) {
        const double f_n = m * v_n * w_n * sin(w_n * (n + 0.5) * dt);
        const gr_tangential_force o = step(&c, &s, g, f_n, 1);
        lost += o.p * dt;
        e = o.e;
        g += o.f * dt / m;
    }
    /* the contact ends: the law drops the history (its energy joins the dissipation) */
    const gr_tangential_force o = step(&c, &s, g, 0.0, 0);
    lost += o.p * dt;
    e = o.e;
    *ledger = fabs(0.5 * m * g * g + e + lost - 0.5 * m * g0 * g0);
    return g;
}

START_TEST(test_stick_reverses)
{
    /* k_t = 2/7 k_n: w_t t_c = pi sqrt(2/7), eps_t = -g'/g = -cos(w_t t_c) = 0.0989 > 0 */
    /* mu = 1e6: a finite mu releases the spring where mu F_n falls below k_t s at the end of the
     * contact, which moves eps_t by about (k_t / k_n) g_0 / (2 mu v_n), 1.4e-4 at mu = 10 */
    const double k_t = 2.0 / 7.0 * 1e4, want = -cos(M_PI * sqrt(2.0 / 7.0));
    double led1 = 0.0, led2 = 0.0;
    const double g1 = contact(k_t, 0.0, 1e6, 1.0, 0.01, 4000, &led1);
    const double g2 = contact(k_t, 0.0, 1e6, 1.0, 0.01, 8000, &led2);
    ck_assert_msg(want > 0.09, "want %g", want);
    ck_assert_msg(fabs(-g1 / 0.01 - want) < 2e-3, "eps_t %g, want %g", -g1 / 0.01, want);
    ck_assert_msg(fabs(-g2 / 0.01 - want) < fabs(-g1 / 0.01 - want) + 1e-6, "no convergence");
    /* the ledger closes to the step's accuracy: first order, halves with dt */
    const double ke0 = 0.5 * 0.01 * 0.01;
    ck_assert_msg(led1 < 1e-2 * ke0 && led2 < 0.6 * led1 + 1e-15 * ke0, "ledger %g, %g of %g", led1,
                  led2, ke0);
}
END_TEST

START_TEST(test_slide)
{
    /* mu = 0.01 and g0 = 1 >> 2 mu v_n: the contact slides throughout and loses the Coulomb
     * impulse mu int F_n dt = 2 mu m v_n */
    double led = 0.0;
    const double g = contact(2.0 / 7.0 * 1e4, 0.0, 0.01, 1.0, 1.0, 4000, &led);
    ck_assert_msg(fabs(g - (1.0 - 2.0 * 0.01)) < 1e-4, "g' %g, want %g", g, 1.0 - 0.02);
    ck_assert_msg(led < 1e-3 * 0.5, "ledger %g", led);
}
END_TEST

/* Mindlin (mindlin = true): k_t = km sqrt(xi) now, km sqrt(xi + g_n dt) at the previous step;
 * the energy the stiffness change adds to k_t s^2 / 2 without work is booked in `lost` (negative
 * while loading) so that the kernel's trapezoid work closes the ledger */
START_TEST(test_mindlin_step)
{
    const double km = 4e6, xi = 2.5e-5, g_n = -0.1, g_t = 0.7, dt = 1e-4, gamma = 0.3;
    gr_contact_coeffs c = coeffs(0.0, gamma, 0.5, dt);
    c.law_t[GR_SPRING_KM] = km;
    double s = 2e-4;
    const gr_tangential_in in = {
        .g_t = g_t, .f_n = 100.0, .xi = xi, .g_n = g_n, .acts = 1, .hist = &s};
    const gr_tangential_force o = gr_tangential_tangential_spring(&c, in);
    const double k = km * sqrt(xi), k_old = km * sqrt(xi + g_n * dt), s_new = 2e-4 + g_t * dt;
    ck_assert_double_eq_tol(s, s_new, 1e-18);
    ck_assert_double_eq_tol(o.f, -k * s_new - gamma * g_t, 1e-12);
    ck_assert_double_eq_tol(o.fc, -k * s_new, 1e-12);
    ck_assert_double_eq_tol(o.e, 0.5 * k * s_new * s_new, 1e-18);
    const double work =
        0.5 * (k_old * 2e-4 + k * s_new) * g_t * dt; /* the trapezoid, on the motion */
    const double lost = work - (o.e - 0.5 * k_old * 2e-4 * 2e-4);
    ck_assert_double_eq_tol(o.lost, lost, 1e-15);
    ck_assert_msg(o.lost < 0.0, "loading stiffens the spring: energy gained, lost %g", o.lost);
    /* at the Coulomb limit the spring is shortened with the new stiffness */
    double s2 = 2e-4;
    gr_tangential_in in2 = in;
    in2.f_n = 1.0;
    in2.hist = &s2;
    const gr_tangential_force o2 = gr_tangential_tangential_spring(&c, in2);
    ck_assert_double_eq_tol(fabs(o2.f), 0.5, 1e-14);
    ck_assert_double_eq_tol(-k * s2 - gamma * g_t, o2.f, 1e-12);
}
END_TEST

/* Mindlin's prepare: km = kt_ratio (3/2) k_h (the Hertz law's own stiffness dF_n/dxi times
 * kt_ratio), or k_t sqrt(xi / x0) with an explicit k_t; refused with a linear normal law */
START_TEST(test_mindlin_prepare)
{
    gr_contact_params p;
    gr_contact_defaults(&p);
    ck_assert_int_eq(gr_contact_set_value(&p, "mindlin", true, NULL), GR_OK);
    ck_assert_int_eq(gr_contact_set_value(&p, "kt_ratio", 0.8, NULL), GR_OK);
    gr_contact_coeffs c;
    gr_error err = {0};
    const gr_model *hz = gr_model_find("hertz"), *ts = gr_model_find("tangential_spring");
    const double m12 = 1.765e-5;
    ck_assert_msg(gr_contact_prepare(hz, ts, &p, m12, 0.0, &c, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(c.law_t[GR_SPRING_KM], 0.8 * 1.5 * gr_contact_get(&p, "k_h"),
                            1e-9 * gr_contact_get(&p, "k_h"));
    ck_assert(c.law_t[GR_SPRING_KT] == 0.0);
    ck_assert_int_eq(gr_contact_set_value(&p, "k_t", 500.0, NULL), GR_OK);
    ck_assert(gr_contact_prepare(hz, ts, &p, m12, 0.0, &c, &err) == GR_OK);
    const double x0 = pow(m12 * gr_contact_get(&p, "v_max") * gr_contact_get(&p, "v_max") /
                              gr_contact_get(&p, "k_h"),
                          0.4);
    ck_assert_double_eq_tol(c.law_t[GR_SPRING_KM] * sqrt(x0), 500.0, 1e-9);
    ck_assert(gr_contact_prepare(gr_model_find("spring_dashpot"), ts, &p, m12, 0.0, &c, &err) ==
              GR_EINVAL);
    ck_assert_msg(strstr(err.message, "mindlin") && strstr(err.message, "hertz") &&
                      strstr(err.message, "spring_dashpot"),
                  "message: %s", err.message);
}
END_TEST

int main(void)
{
    Suite *su = suite_create("tangential_spring");
    TCase *tc = tcase_create("law");
    tcase_add_test(tc, test_stick_step);
    tcase_add_test(tc, test_coulomb_limit);
    tcase_add_test(tc, test_stick_reverses);
    tcase_add_test(tc, test_slide);
    tcase_add_test(tc, test_mindlin_step);
    tcase_add_test(tc, test_mindlin_prepare);
    suite_add_tcase(su, tc);
    return gr_test_run(su);
}
