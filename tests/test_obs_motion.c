/* The time-correlation observables on trajectories with a known answer (fixed
 * seeds): msd  - free RFM particles (noise only, no collisions; 2.15, 2.22):
 * the velocity is a Wiener process with <dv^2> = 2 (D/M^2) t per component,
 * sampled exactly together with its integral, in a periodic box (2D) and ring
 * (1D) small enough that particles cross the boundary many times: MSD(tau) = 2
 * B dim (<t0> tau^2 + tau^3/3), B = D/M^2, <t0> the mean time origin of lag
 * tau;
 *        - Langevin particles (friction gamma, temperature T): D_self = T / (M
 * gamma); vacf - the same free particles give a flat C(tau) = 2 B <t0> per
 * component; the Langevin ones C(tau)/C(0) = exp(-gamma tau) and a Green-Kubo
 * integral T / (M gamma); collisions - synthetic contact events: a collision
 * every 12.5 ms per particle gives a rate of 80 /s, 12.5 ms between collisions,
 * and no events reports a note and null rates. OBS_TEST_VERBOSE=1 prints the
 * measured numbers. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "obs_harness.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_msd, gr_obs_vacf, gr_obs_collisions;

static bool verbose(void) { return getenv("OBS_TEST_VERBOSE") != NULL; }

typedef struct traj {
    int n, dim;
    double *x, *y, *vx, *vy;
} traj;

static traj traj_new(int n, int dim)
{
    traj t = {.n = n, .dim = dim};
    t.x = calloc((size_t)n, sizeof(double));
    t.y = calloc((size_t)n, sizeof(double));
    t.vx = calloc((size_t)n, sizeof(double));
    t.vy = calloc((size_t)n, sizeof(double));
    return t;
}

static void traj_free(traj *t)
{
    free(t->x);
    free(t->y);
    free(t->vx);
    free(t->vy);
}

/* Exact step h of a free particle whose velocity is a Wiener process of
 * diffusion B per component: dv ~ N(0, 2Bh), dx - v h | dv ~ N(h dv / 2, B h^3
 * / 6). */
static void free_step(double *x, double *v, double B, double h, gsl_rng *r)
{
    double dv = sqrt(2.0 * B * h) * gsl_ran_gaussian_ziggurat(r, 1.0);
    *x += *v * h + 0.5 * h * dv + sqrt(B * h * h * h / 6.0) * gsl_ran_gaussian_ziggurat(r, 1.0);
    *v += dv;
}

static void wrap_all(traj *t, double L)
{
    for (int i = 0; i < t->n; i++) {
        t->x[i] -= L * floor(t->x[i] / L);
        t->y[i] -= L * floor(t->y[i] / L);
    }
}

/* Free particles from rest: msd and vacf against the exact moments, in 1D and
 * 2D. */
static void free_particles(int dim)
{
    gr_scene sc;
    const int N = 20000, S = 100, lags = 40;
    const double D = 1e-8, M = 3.53e-5, B = D / (M * M), h = 1e-3; /* B = 8.0 m^2/s^3 */
    /* rms displacement at the end ~ sqrt(2 B t^3 / 3) = 0.07 m = 1.8 L; steps per
     * sample < L/4 */
    const double L = 0.04;
    h_scene(&sc, dim, N, L, 1e-5);
    sc.mass = M;
    sc.D = D;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "msd_lags", lags, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vacf_lags", lags, NULL), GR_OK);
    void *ms = h_create(&gr_obs_msd, &sc), *va = h_create(&gr_obs_vacf, &sc);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7 + (unsigned long)dim);
    traj t = traj_new(N, dim);
    double max_step = 0.0;
    for (int s = 0; s < S; s++) {
        if (s > 0) {
            for (int i = 0; i < N; i++) {
                double x0 = t.x[i];
                free_step(&t.x[i], &t.vx[i], B, h, r);
                max_step = fmax(max_step, fabs(t.x[i] - x0));
                if (dim == 2) {
                    free_step(&t.y[i], &t.vy[i], B, h, r);
                }
            }
            wrap_all(&t, L);
        }
        h_sample(&gr_obs_msd, ms, &sc, t.x, t.y, t.vx, t.vy, s * h);
        h_sample(&gr_obs_vacf, va, &sc, t.x, t.y, t.vx, t.vy, s * h);
    }
    ck_assert_msg(max_step < 0.25 * L, "the test's steps %g must stay below L/4", max_step);
    h_table tm, tv;
    cJSON *jm = h_finish(&gr_obs_msd, ms, &sc, "msd.csv", &tm),
          *jv = h_finish(&gr_obs_vacf, va, &sc, "vacf.csv", &tv);
    ck_assert_str_eq(tm.columns, "tau,msd,msd_stderr,origins\n");
    ck_assert_int_eq(tm.rows, lags + 1);
    ck_assert_double_eq(h_num(jm, "msd", "suspect_jumps"), 0.0);
    ck_assert_double_eq_tol(h_num(jm, "msd", "interval"), h, 1e-15);
    for (int l = 1; l <= lags; l++) {
        double tau = h_at(&tm, l, 0), t0 = 0.5 * (S - 1 - l) * h;
        ck_assert_double_eq_tol(tau, l * h, 1e-12);
        ck_assert_int_eq((int)h_at(&tm, l, 3), S - l);
        double expect = 2.0 * B * dim * (t0 * tau * tau + tau * tau * tau / 3.0);
        double got = h_at(&tm, l, 1);
        if (verbose() && l % 10 == 0) {
            printf("free %dD msd lag %d: %.6g expected %.6g (ratio %.4f)\n", dim, l, got, expect,
                   got / expect);
        }
        /* N = 20000 particles: the relative spread of a mean of v^2 is sqrt(2 /
         * (dim N)), 1 % in 1D, 0.7 % in 2D (less after averaging over origins): 4 %
         * is 4-6 sigma; a wrong unwrap or factor is off by far more */
        ck_assert_msg(fabs(got / expect - 1.0) < 0.04, "%dD msd lag %d: %g, expected %g", dim, l,
                      got, expect);
    }
    /* vacf: flat, C(tau) = 2 B <t0> per component for origins t0 */
    for (int l = 0; l <= lags; l += 10) {
        double t0 = 0.5 * (S - 1 - l) * h, expect = 2.0 * B * t0 * dim, got = h_at(&tv, l, 1);
        if (verbose()) {
            printf("free %dD vacf lag %d: %.6g expected %.6g (ratio %.4f)\n", dim, l, got, expect,
                   got / expect);
        }
        ck_assert_msg(fabs(got / expect - 1.0) < 0.04, "%dD vacf lag %d: %g, expected %g", dim, l,
                      got, expect);
    }
    traj_free(&t);
    gsl_rng_free(r);
    free(tm.v);
    free(tv.v);
    cJSON_Delete(jm);
    cJSON_Delete(jv);
}

START_TEST(test_free_2d) { free_particles(2); }
END_TEST

START_TEST(test_free_1d) { free_particles(1); }
END_TEST

/* Langevin particles: exact Ornstein-Uhlenbeck velocities, positions integrated
 * in fine steps. */
START_TEST(test_langevin)
{
    gr_scene sc;
    const int N = 200, sub = 10, S = 3000, lags = 100;
    const double M = 2.0, T = 3.0, gamma = 5.0, h = 0.02 / gamma,
                 L = 1.0; /* sample every 0.2 / gamma */
    const double D_true = T / (M * gamma), a = exp(-gamma * h), s_v = sqrt(T / M * (1.0 - a * a));
    h_scene(&sc, 2, N, L, 1e-4);
    sc.mass = M;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "msd_lags", lags, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vacf_lags", lags, NULL), GR_OK);
    void *ms = h_create(&gr_obs_msd, &sc), *va = h_create(&gr_obs_vacf, &sc);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    traj t = traj_new(N, 2);
    for (int i = 0; i < N; i++) {
        t.x[i] = L * gsl_rng_uniform(r);
        t.y[i] = L * gsl_rng_uniform(r);
        t.vx[i] = sqrt(T / M) * gsl_ran_gaussian_ziggurat(r, 1.0);
        t.vy[i] = sqrt(T / M) * gsl_ran_gaussian_ziggurat(r, 1.0);
    }
    for (int s = 0; s < S; s++) {
        for (int k = 0; k < sub && s > 0; k++) {
            for (int i = 0; i < N; i++) {
                double vx = t.vx[i] * a + s_v * gsl_ran_gaussian_ziggurat(r, 1.0);
                double vy = t.vy[i] * a + s_v * gsl_ran_gaussian_ziggurat(r, 1.0);
                t.x[i] += 0.5 * (t.vx[i] + vx) * h;
                t.y[i] += 0.5 * (t.vy[i] + vy) * h;
                t.vx[i] = vx;
                t.vy[i] = vy;
            }
        }
        wrap_all(&t, L);
        h_sample(&gr_obs_msd, ms, &sc, t.x, t.y, t.vx, t.vy, s * sub * h);
        h_sample(&gr_obs_vacf, va, &sc, t.x, t.y, t.vx, t.vy, s * sub * h);
    }
    h_table tm, tv;
    cJSON *jm = h_finish(&gr_obs_msd, ms, &sc, "msd.csv", &tm),
          *jv = h_finish(&gr_obs_vacf, va, &sc, "vacf.csv", &tv);
    double D = h_num(jm, "msd", "D_self"), De = 0.0;
    D = h_num(cJSON_GetObjectItem(jm, "msd"), "D_self", "value");
    De = h_num(cJSON_GetObjectItem(jm, "msd"), "D_self", "error");
    double Dg = h_num(cJSON_GetObjectItem(jv, "vacf"), "D_green_kubo", "value");
    double Dge = h_num(cJSON_GetObjectItem(jv, "vacf"), "D_green_kubo", "error");
    /* the slope window tau = 10/gamma .. 20/gamma: MSD slope 4 D (1 - e^{-gamma
     * tau}), 5e-5 low */
    if (verbose()) {
        printf("langevin: D_self = %.5g +- %.2g, D_GK = %.5g +- %.2g, T/(M gamma) "
               "= %.5g\n",
               D, De, Dg, Dge, D_true);
    }
    ck_assert_msg(De > 0.0 && De < 0.05 * D_true, "D_self error %g", De);
    ck_assert_msg(fabs(D - D_true) < 4.0 * De, "D_self = %g +- %g, expected %g", D, De, D_true);
    ck_assert_msg(Dge > 0.0 && Dge < 0.05 * D_true, "D_GK error %g", Dge);
    /* trapezoid over lags 0.2/gamma: (x/2) coth(x/2) = 1.0033 */
    ck_assert_msg(fabs(Dg - D_true * 1.0033) < 4.0 * Dge, "D_GK = %g +- %g, expected %g", Dg, Dge,
                  D_true);
    /* C(tau)/C(0) = exp(-gamma tau) */
    double c0 = h_at(&tv, 0, 1);
    ck_assert_double_eq_tol(c0 / 2.0, T / M, 0.03 * T / M);
    for (int l = 1; l <= 15; l += 2) {
        double tau = h_at(&tv, l, 0), got = h_at(&tv, l, 1) / c0, e = h_at(&tv, l, 2) / c0;
        ck_assert_msg(fabs(got - exp(-gamma * tau)) < 4.0 * e + 0.01,
                      "C(%g)/C(0) = %g +- %g, exp = %g", tau, got, e, exp(-gamma * tau));
    }
    traj_free(&t);
    gsl_rng_free(r);
    free(tm.v);
    free(tv.v);
    cJSON_Delete(jm);
    cJSON_Delete(jv);
}
END_TEST

static void event(const gr_observable_type *ty, void *st, int i, int kind, double t)
{
    gr_contact_event ev = {.i = i, .kind = kind, .t = t};
    gr_error err = {0};
    ck_assert_int_eq(ty->events(st, &ev, 1, &err), GR_OK);
}

/* Collisions every 12.5 ms per particle (contacts of 1 ms), samples every 0.1
 * s; the events of each interval arrive after its closing sample, as in
 * src/app/run.c. */
START_TEST(test_collisions_periodic)
{
    gr_scene sc;
    enum { N = 10, S = 21 };
    h_scene(&sc, 1, N, 1.0, 1e-3);
    void *st = h_create(&gr_obs_collisions, &sc);
    double x[N], v[N];
    memset(x, 0, sizeof x);
    memset(v, 0, sizeof v);
    for (int s = 0; s < S; s++) {
        h_sample(&gr_obs_collisions, st, &sc, x, NULL, v, NULL, 0.1 * s);
        for (int k = 0; s > 0 && k < 8; k++) {
            for (int i = 0; i < N; i++) {
                double tc = 0.1 * (s - 1) + 0.0125 * k + 0.001 * i / N + 0.0005;
                event(&gr_obs_collisions, st, i, +1, tc);
                event(&gr_obs_collisions, st, i, -1, tc + 0.001);
            }
        }
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_collisions, st, &sc, "collisions.csv", &tab);
    const cJSON *c = cJSON_GetObjectItem(j, "collisions");
    if (verbose()) {
        printf("collisions: rate %.6g +- %.3g, mean tau %.6g, %g collisions\n",
               h_num(c, "rate_per_particle", NULL), h_num(c, "rate_per_particle_error", NULL),
               h_num(c, "mean_time_between", NULL), h_num(c, "collisions", NULL));
    }
    ck_assert_double_eq(h_num(c, "collisions", NULL), (S - 1) * 8 * N);
    ck_assert_double_eq_tol(h_num(c, "rate_per_particle", NULL), 80.0, 1e-9);
    ck_assert_double_eq_tol(h_num(c, "rate_per_particle_error", NULL), 0.0, 1e-9);
    ck_assert_double_eq_tol(h_num(c, "mean_time_between", NULL), 0.0125, 1e-12);
    ck_assert_double_eq(h_num(c, "intervals", NULL), ((S - 1) * 8 - 1) * N);
    /* every interval in the one bin holding 12.5 ms */
    int hit = -1;
    for (int r = 0; r < tab.rows; r++) {
        if (h_at(&tab, r, 3) > 0) {
            ck_assert_msg(hit < 0, "intervals in more than one bin");
            hit = r;
        }
    }
    ck_assert_int_ge(hit, 0);
    ck_assert(h_at(&tab, hit, 0) <= 0.0125 && 0.0125 < h_at(&tab, hit, 1));
    h_done(&tab, j);
}
END_TEST

/* Frames without events (snapshots, or no contacts): null rates and a note. */
START_TEST(test_collisions_none)
{
    gr_scene sc;
    h_scene(&sc, 2, 3, 1.0, 1e-3);
    void *st = h_create(&gr_obs_collisions, &sc);
    double z[3] = {0.1, 0.5, 0.9};
    for (int s = 0; s < 5; s++) {
        h_sample(&gr_obs_collisions, st, &sc, z, z, z, z, s);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_collisions, st, &sc, "collisions.csv", &tab);
    const cJSON *c = cJSON_GetObjectItem(j, "collisions");
    ck_assert(isnan(h_num(c, "rate_per_particle", NULL)));
    ck_assert_ptr_nonnull(cJSON_GetObjectItem(c, "note"));
    ck_assert_double_eq(h_num(c, "collisions", NULL), 0.0);
    h_done(&tab, j);
}
END_TEST

/* A frame of the wrong size is refused. */
START_TEST(test_bad_frame)
{
    gr_scene sc;
    h_scene(&sc, 1, 4, 1.0, 1e-3);
    void *st = h_create(&gr_obs_msd, &sc);
    double x[3] = {0}, v[3] = {0};
    gr_particles p = {.n = 3, .dim = 1, .L = 1.0, .x = x, .vx = v};
    gr_error err = {0};
    ck_assert_int_eq(gr_obs_msd.sample(st, &p, 0.0, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "3 particles"));
    gr_observable_free(st);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_motion");
    TCase *t = tcase_create("analysis");
    tcase_add_test(t, test_free_2d);
    tcase_add_test(t, test_free_1d);
    tcase_add_test(t, test_langevin);
    tcase_add_test(t, test_collisions_periodic);
    tcase_add_test(t, test_collisions_none);
    tcase_add_test(t, test_bad_frame);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
