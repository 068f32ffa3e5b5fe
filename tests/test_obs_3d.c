/* The observables in 3D (issue 35) on frames with a known answer (fixed seeds):
 *   pair     - uniform random points in a cube: g(R) = 1 at large R (shells 4 pi R^2 dR);
 *   pressure - an ideal gas: P = n T per component (kinetic_xx, yy, zz each n M <u_a^2>), no
 *              virial; two spheres overlapping along a 3D direction: the virial |r| f_n n_a n_b;
 *   pv       - a 3D Maxwellian: the speed distribution 3 sqrt(6/pi) c^2 exp(-3 c^2/2) in
 *              c = |v| / sqrt(<|v|^2>) and a Gaussian component;
 *   msd      - ballistic motion across the periodic cube: MSD = <|v|^2> tau^2 = 3 T_1 tau^2;
 *   vacf     - constant velocities: C(tau) = <|v|^2> / 3 at every lag;
 *   vcorr    - two spheres with u_2 = -u_1: C_L = -3 u_par^2 / |u|^2 and C_T = -3 (|u|^2 -
 *              u_par^2) / (2 |u|^2);
 *   clusters - a touching chain along a body diagonal is one contact cluster, spread out N;
 *              (the chain spans 0.6-0.7 L per axis, crossing all three periodic boundaries)
 *   profile  - along z: the density of a slab-filled frame and T_z of each slab;
 *   sk       - the 3D gridding engine equals the direct sum; a simple cubic lattice has S = N on
 *              its reciprocal lattice and 0 elsewhere; random points have S(k) = 1 in every
 *              spherical bin and D_f = 0 within errors;
 * and the registry: every frame observable takes dim = 3, gaps (1D) is refused. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "analysis/sk.h"
#include "obs_harness.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_pair, gr_obs_pressure, gr_obs_pv, gr_obs_msd, gr_obs_vacf,
    gr_obs_vcorr, gr_obs_clusters, gr_obs_profile, gr_obs_gaps, gr_obs_sk;

static void sample3(const gr_observable_type *t, void *st, const gr_scene *sc, const double *x,
                    const double *y, const double *z, const double *vx, const double *vy,
                    const double *vz, double time)
{
    gr_particles p = {.n = sc->N,
                      .dim = 3,
                      .L = sc->L,
                      .radius = sc->radius,
                      .mass = sc->mass,
                      .x = x,
                      .y = y,
                      .z = z,
                      .vx = vx,
                      .vy = vy,
                      .vz = vz};
    gr_error err = {0};
    int rc = t->sample(st, &p, time, &err);
    ck_assert_msg(rc == GR_OK, "%s sample: %s", t->name, err.message);
}

typedef struct frame3 {
    int n;
    double *x, *y, *z, *vx, *vy, *vz;
} frame3;

static frame3 frame_new(int n)
{
    frame3 f = {.n = n};
    double **a[6] = {&f.x, &f.y, &f.z, &f.vx, &f.vy, &f.vz};
    for (int k = 0; k < 6; k++) {
        *a[k] = calloc((size_t)n, sizeof(double));
    }
    return f;
}

static void frame_free(frame3 *f)
{
    double *a[6] = {f->x, f->y, f->z, f->vx, f->vy, f->vz};
    for (int k = 0; k < 6; k++) {
        free(a[k]);
    }
}

static void frame_random(frame3 *f, double L, double sigma_v, gsl_rng *r)
{
    for (int i = 0; i < f->n; i++) {
        f->x[i] = L * gsl_rng_uniform(r);
        f->y[i] = L * gsl_rng_uniform(r);
        f->z[i] = L * gsl_rng_uniform(r);
        f->vx[i] = sigma_v * gsl_ran_gaussian_ziggurat(r, 1.0);
        f->vy[i] = sigma_v * gsl_ran_gaussian_ziggurat(r, 1.0);
        f->vz[i] = sigma_v * gsl_ran_gaussian_ziggurat(r, 1.0);
    }
}

static void sample_frame(const gr_observable_type *t, void *st, const gr_scene *sc, const frame3 *f,
                         double time)
{
    sample3(t, st, sc, f->x, f->y, f->z, f->vx, f->vy, f->vz, time);
}

/* Uniform random points: g(R) -> 1 in the tail (the 3D shell volume; a 2D shell area would give
 * g ~ R), and C(R_hi) = n (4/3) pi R_hi^3 within errors, so n(R) ~ 0. */
START_TEST(test_pair_ideal_gas)
{
    gr_scene sc;
    enum { N = 2000, F = 20 };
    const double L = 1.0;
    h_scene(&sc, 3, N, L, 1e-3);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "gr_bins", 50, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "gr_rmax", 100, NULL), GR_OK); /* L/2 */
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    frame3 f = frame_new(N);
    void *st = h_create(&gr_obs_pair, &sc);
    for (int k = 0; k < F; k++) {
        frame_random(&f, L, 1.0, r);
        sample_frame(&gr_obs_pair, st, &sc, &f, k);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pair, st, &sc, "pair.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pair");
    ck_assert_int_eq(tab.rows, 50);
    double tail = h_num(p, "g_tail", "value"), tail_err = h_num(p, "g_tail", "error");
    ck_assert_msg(fabs(tail - 1.0) < 4.0 * tail_err && tail_err < 0.01, "g_tail = %g +- %g", tail,
                  tail_err);
    /* every bin from R = 0.2 L on: g = 1 within 5 errors */
    for (int b = 20; b < tab.rows; b++) {
        ck_assert_msg(fabs(h_at(&tab, b, 2) - 1.0) < 5.0 * h_at(&tab, b, 3), "g(%g) = %g +- %g",
                      h_at(&tab, b, 0), h_at(&tab, b, 2), h_at(&tab, b, 3));
    }
    /* C at the last edge R_max = 0.2 L: n (4/3) pi R_max^3 */
    const double R_hi = h_at(&tab, tab.rows - 1, 8);
    ck_assert_double_eq_tol(R_hi, 0.2 * L, 1e-9);
    double C = h_at(&tab, tab.rows - 1, 4), C0 = (N - 1) * 4.0 / 3.0 * M_PI * pow(R_hi, 3);
    ck_assert_msg(fabs(C - C0) < 0.01 * C0, "C(L/2) = %g, expected %g", C, C0);
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* Ideal gas: P = n T per component exactly (T = M <|u|^2> / 3), each diagonal kinetic component
 * n M <u_a^2> within errors, the off-diagonal ones 0, no virial; 15 rows. */
START_TEST(test_pressure_ideal_gas)
{
    gr_scene sc;
    enum { N = 1000, F = 20 };
    const double L = 1.0, M = 3.53e-5;
    h_scene(&sc, 3, N, L, 1e-6);
    sc.mass = M;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    frame3 f = frame_new(N);
    void *st = h_create(&gr_obs_pressure, &sc);
    double nT = 0.0;
    for (int k = 0; k < F; k++) {
        frame_random(&f, L, 0.3, r);
        double m[3] = {0, 0, 0};
        for (int i = 0; i < N; i++) {
            m[0] += f.vx[i] / N;
            m[1] += f.vy[i] / N;
            m[2] += f.vz[i] / N;
        }
        for (int i = 0; i < N; i++) {
            double ux = f.vx[i] - m[0], uy = f.vy[i] - m[1], uz = f.vz[i] - m[2];
            nT += M * (ux * ux + uy * uy + uz * uz) / 3.0 / (L * L * L) / F;
        }
        sample_frame(&gr_obs_pressure, st, &sc, &f, k);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pressure");
    ck_assert_int_eq(tab.rows, 15);
    ck_assert_double_eq_tol(h_num(p, "P", NULL), nT, 1e-12 * nT);
    ck_assert_double_eq_tol(h_num(p, "nT", NULL), nT, 1e-12 * nT);
    ck_assert_double_eq_tol(h_num(p, "Z", NULL), 1.0, 1e-12);
    static const char *const diag[3] = {"kinetic_xx", "kinetic_yy", "kinetic_zz"};
    for (int a = 0; a < 3; a++) {
        char e[64];
        snprintf(e, sizeof e, "%s_error", diag[a]);
        double v = h_num(p, diag[a], NULL), err = h_num(p, e, NULL);
        ck_assert_msg(fabs(v - nT) < 4.0 * err && err < 0.02 * nT, "%s = %g +- %g, nT = %g",
                      diag[a], v, err, nT);
    }
    static const char *const off[3] = {"kinetic_xy", "kinetic_xz", "kinetic_yz"};
    for (int a = 0; a < 3; a++) {
        char e[64];
        snprintf(e, sizeof e, "%s_error", off[a]);
        ck_assert_msg(fabs(h_num(p, off[a], NULL)) < 4.0 * h_num(p, e, NULL), "%s = %g", off[a],
                      h_num(p, off[a], NULL));
    }
    ck_assert_double_eq(h_num(p, "collisional_zz", NULL), 0.0);
    ck_assert_double_eq(h_num(p, "contacts_per_frame", NULL), 0.0);
    ck_assert_ptr_null(cJSON_GetObjectItem(p, "eos_5_2")); /* the 2D equation of state */
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* Two spheres at rest overlapping by xi along n = (1, 2, 2)/3, across the periodic boundary: the
 * spring's virial (d - xi) k_s xi n_a n_b / L^3 in every component (no dashpot at rest). */
START_TEST(test_pressure_overlap)
{
    gr_scene sc;
    const double d = 3e-3, xi = 1e-5, L = 0.1, n[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
    h_scene(&sc, 3, 2, L, 0.5 * d);
    ck_assert_ptr_nonnull(sc.normal);
    double x[2], y[2], z[2], v[2] = {0, 0};
    const double c[3] = {L - 0.2 * d, 0.05, L - 0.1 * d};
    double *pos[3] = {x, y, z};
    for (int a = 0; a < 3; a++) {
        pos[a][0] = c[a];
        pos[a][1] = fmod(c[a] + (d - xi) * n[a], L);
    }
    void *st = h_create(&gr_obs_pressure, &sc);
    sample3(&gr_obs_pressure, st, &sc, x, y, z, v, v, v, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pressure");
    const double W = (d - xi) * sc.contact.k_s * xi / (L * L * L);
    static const char *const key[6] = {"collisional_xx", "collisional_yy", "collisional_zz",
                                       "collisional_xy", "collisional_xz", "collisional_yz"};
    static const int ia[6] = {0, 1, 2, 0, 0, 1}, ib[6] = {0, 1, 2, 1, 2, 2};
    for (int q = 0; q < 6; q++) {
        double want = W * n[ia[q]] * n[ib[q]];
        ck_assert_msg(fabs(h_num(p, key[q], NULL) - want) < 1e-6 * W, "%s = %.10g, expected %.10g",
                      key[q], h_num(p, key[q], NULL), want);
    }
    ck_assert_double_eq_tol(h_num(p, "P", NULL), W / 3.0, 1e-6 * W);
    ck_assert_double_eq(h_num(p, "contacts_per_frame", NULL), 1.0);
    ck_assert_str_eq(cJSON_GetObjectItem(p, "unit")->valuestring, "Pa (N/m^2)");
    h_done(&tab, j);
}
END_TEST

/* A 3D Maxwellian: the scaled speed distribution against 3 sqrt(6/pi) c^2 exp(-3 c^2 / 2) (the 2D
 * form 2 c exp(-c^2) differs by 30 % near its peak), and one component against a Gaussian. */
START_TEST(test_pv_maxwellian)
{
    gr_scene sc;
    enum { N = 2000, F = 50 };
    const double L = 1.0;
    h_scene(&sc, 3, N, L, 1e-6);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "pv_bins", 60, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "pv_range", 6, NULL), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 9);
    frame3 f = frame_new(N);
    void *st = h_create(&gr_obs_pv, &sc);
    for (int k = 0; k < F; k++) {
        frame_random(&f, L, 0.5, r);
        sample_frame(&gr_obs_pv, st, &sc, &f, k);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pv, st, &sc, "pv_speed.csv", &tab);
    int checked = 0;
    for (int b = 0; b < tab.rows; b++) {
        double c = h_at(&tab, b, 0), dens = h_at(&tab, b, 1), err = h_at(&tab, b, 2);
        if (!(c > 0.3 && c < 1.8)) {
            continue;
        }
        /* the bin average of the density, c at the centre: curvature error below 1e-3 */
        double want = 3.0 * sqrt(6.0 / M_PI) * c * c * exp(-1.5 * c * c);
        ck_assert_msg(fabs(dens - want) < 5.0 * err + 0.01 * want, "P(c = %g) = %g +- %g, want %g",
                      c, dens, err, want);
        checked++;
    }
    ck_assert_int_ge(checked, 10);
    const cJSON *pv = cJSON_GetObjectItem(j, "pv");
    ck_assert_ptr_nonnull(pv);
    h_done(&tab, j);
    /* P(v) of a component pools x, y and z: N_s = 3 N F */
    gsl_rng_set(r, 9);
    st = h_create(&gr_obs_pv, &sc);
    for (int k = 0; k < F; k++) {
        frame_random(&f, L, 0.5, r);
        sample_frame(&gr_obs_pv, st, &sc, &f, k);
    }
    j = h_finish(&gr_obs_pv, st, &sc, "pv.csv", &tab);
    double total = 0.0;
    for (int b = 0; b < tab.rows; b++) {
        total += h_at(&tab, b, 3); /* counts */
    }
    ck_assert_double_eq(total, 3.0 * N * F);
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* Ballistic motion through the periodic cube (each particle crosses it several times): MSD(tau) =
 * <|v|^2> tau^2 = 3 T_1 tau^2 exactly at every lag; and the VACF of the same frames is <|v|^2>/3
 * at every lag. */
START_TEST(test_msd_vacf_ballistic)
{
    gr_scene sc;
    enum { N = 500, S = 60, LAGS = 20 };
    const double L = 0.05, h = 1e-3;
    h_scene(&sc, 3, N, L, 1e-5);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "msd_lags", LAGS, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vacf_lags", LAGS, NULL), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 2);
    frame3 f = frame_new(N);
    frame_random(&f, L, 1.0, r); /* |v| h ~ 1.7 mm per sample < L/4 */
    double v2 = 0.0;
    for (int i = 0; i < N; i++) {
        v2 += (f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i] + f.vz[i] * f.vz[i]) / N;
    }
    void *msd = h_create(&gr_obs_msd, &sc), *vacf = h_create(&gr_obs_vacf, &sc);
    for (int s = 0; s < S; s++) {
        sample_frame(&gr_obs_msd, msd, &sc, &f, s * h);
        sample_frame(&gr_obs_vacf, vacf, &sc, &f, s * h);
        for (int i = 0; i < N; i++) {
            f.x[i] = fmod(f.x[i] + f.vx[i] * h + L, L);
            f.y[i] = fmod(f.y[i] + f.vy[i] * h + L, L);
            f.z[i] = fmod(f.z[i] + f.vz[i] * h + L, L);
        }
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_msd, msd, &sc, "msd.csv", &tab);
    ck_assert_int_ge(tab.rows, LAGS);
    for (int row = 0; row < tab.rows; row++) {
        double tau = h_at(&tab, row, 0), want = v2 * tau * tau;
        ck_assert_msg(fabs(h_at(&tab, row, 1) - want) <= 1e-9 * want + 1e-18,
                      "MSD(%g) = %.12g, expected %.12g", tau, h_at(&tab, row, 1), want);
    }
    ck_assert_double_eq(h_num(cJSON_GetObjectItem(j, "msd"), "suspect_jumps", NULL), 0.0);
    h_done(&tab, j);
    j = h_finish(&gr_obs_vacf, vacf, &sc, "vacf.csv", &tab);
    for (int row = 0; row < tab.rows; row++) {
        ck_assert_msg(fabs(h_at(&tab, row, 1) - v2) <= 1e-9 * v2,
                      "VACF row %d = %.12g, <v^2> %.12g", row, h_at(&tab, row, 1), v2);
    }
    ck_assert_double_eq_tol(h_num(cJSON_GetObjectItem(j, "vacf"), "C0_per_component", NULL),
                            v2 / 3.0, 1e-12 * v2);
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* Two spheres with opposite velocities, separated along x: u_par = u_x. */
START_TEST(test_vcorr_pair)
{
    gr_scene sc;
    const double L = 0.1, d = 1e-3;
    h_scene(&sc, 3, 2, L, 0.5 * d);
    double x[2] = {0.05, 0.05 + 2.5 * d}, y[2] = {0.02, 0.02}, z[2] = {0.07, 0.07};
    double vx[2] = {0.3, -0.3}, vy[2] = {-0.4, 0.4}, vz[2] = {1.2, -1.2};
    void *st = h_create(&gr_obs_vcorr, &sc);
    sample3(&gr_obs_vcorr, st, &sc, x, y, z, vx, vy, vz, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_vcorr, st, &sc, "vcorr.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "vcorr");
    const double u2 = 0.09 + 0.16 + 1.44, par2 = 0.09;
    ck_assert_double_eq_tol(h_num(p, "C_L_first", NULL), -3.0 * par2 / u2, 1e-12);
    ck_assert_double_eq_tol(h_num(p, "C_T_first", NULL), -1.5 * (u2 - par2) / u2, 1e-12);
    h_done(&tab, j);
}
END_TEST

/* A touching chain along the body diagonal (spacing d) is one contact cluster, wrapped across all
 * three boundaries; at spacing 1.2 d it is N contact singletons and one density cluster. */
static cJSON *chain(double spacing, h_table *tab)
{
    gr_scene sc;
    enum { N = 30 };
    const double d = 1e-3, L = 0.03, e = spacing * d / sqrt(3.0);
    h_scene(&sc, 3, N, L, 0.5 * d);
    double x[N], y[N], z[N], v[N] = {0};
    for (int i = 0; i < N; i++) {
        x[i] = fmod(0.025 + i * e, L);
        y[i] = fmod(0.027 + i * e, L);
        z[i] = fmod(0.029 + i * e, L);
    }
    void *st = h_create(&gr_obs_clusters, &sc);
    sample3(&gr_obs_clusters, st, &sc, x, y, z, v, v, v, 0.0);
    return h_finish(&gr_obs_clusters, st, &sc, "clusters.csv", tab);
}

START_TEST(test_clusters_chain)
{
    h_table tab;
    cJSON *j = chain(1.0 - 1e-12, &tab);
    const cJSON *c = cJSON_GetObjectItem(j, "clusters");
    ck_assert_double_eq(h_num(cJSON_GetObjectItem(c, "contact"), "largest", NULL), 30.0);
    ck_assert_double_eq(h_num(cJSON_GetObjectItem(c, "contact"), "clusters_per_frame", NULL), 1.0);
    h_done(&tab, j);
    j = chain(1.2, &tab);
    c = cJSON_GetObjectItem(j, "clusters");
    ck_assert_double_eq(h_num(cJSON_GetObjectItem(c, "contact"), "clusters_per_frame", NULL), 30.0);
    ck_assert_double_eq(h_num(cJSON_GetObjectItem(c, "density"), "largest", NULL), 30.0);
    h_done(&tab, j);
}
END_TEST

/* Along z: particles only in the lower half (z < L/2) with T_z = 4 T_x; 4 slabs. */
START_TEST(test_profile_z)
{
    gr_scene sc;
    enum { N = 4000 };
    const double L = 0.1, r0 = 1e-4;
    h_scene(&sc, 3, N, L, r0);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_axis", 2, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_bins", 4, NULL), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 4);
    frame3 f = frame_new(N);
    frame_random(&f, L, 1.0, r);
    for (int i = 0; i < N; i++) {
        f.z[i] = 0.5 * f.z[i];
        f.vz[i] *= 2.0;
    }
    void *st = h_create(&gr_obs_profile, &sc);
    sample_frame(&gr_obs_profile, st, &sc, &f, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_profile, st, &sc, "profile.csv", &tab);
    ck_assert_int_eq(tab.rows, 4);
    ck_assert_int_eq(tab.cols, 14);
    ck_assert_str_eq(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "profile"), "axis")->valuestring,
                     "z");
    const double slab = 0.25 * L * L * L;
    double n_lower = h_at(&tab, 0, 1) + h_at(&tab, 1, 1);
    ck_assert_double_eq_tol(n_lower * slab, N, 1e-9 * N);
    ck_assert_double_eq(h_at(&tab, 2, 1), 0.0);
    ck_assert_double_eq(h_at(&tab, 3, 1), 0.0);
    for (int k = 0; k < 2; k++) {
        double phi = h_at(&tab, k, 1) * 4.0 / 3.0 * M_PI * r0 * r0 * r0;
        ck_assert_double_eq_tol(h_at(&tab, k, 3), phi, 1e-7 * phi);
        double Tx = h_at(&tab, k, 7), Tz = h_at(&tab, k, 12);
        ck_assert_msg(Tz > 3.3 * Tx && Tz < 4.8 * Tx, "slab %d: T_x = %g, T_z = %g", k, Tx, Tz);
    }
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* The 3D engine: gridding against the direct sum on random points (every vector, absolute 1e-5 at
 * a mean S of 1); the half space holds each +-n pair once and never n = 0; a simple cubic lattice
 * of 4^3 sites has S = N on its reciprocal lattice (n = 4 m) and 0 elsewhere. */
START_TEST(test_sk_engine)
{
    enum { N = 400 };
    const double L = 0.3;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 21);
    frame3 f = frame_new(N);
    frame_random(&f, L, 1.0, r);
    f.x[0] = -0.7 * L; /* any real coordinate: periodic */
    f.z[1] = 2.3 * L;
    gr_sk3_plan *pl = NULL;
    gr_error err = {0};
    ck_assert_int_eq(gr_sk3_plan_create(L, 6.5, GR_SK3_MSP_DEFAULT, &pl, &err), GR_OK);
    const int *nx, *ny, *nz;
    const int nv = gr_sk_vectors(gr_sk3_plan_lattice(pl), &nx, &ny, &nz);
    int count = 0; /* lattice points with 0 < |n|^2 <= 42 (6.5^2 = 42.25), halved */
    for (int a = -6; a <= 6; a++) {
        for (int b = -6; b <= 6; b++) {
            for (int c = -6; c <= 6; c++) {
                const int q = a * a + b * b + c * c;
                count += q > 0 && q <= 42;
            }
        }
    }
    ck_assert_int_eq(2 * nv, count);
    for (int v = 0; v < nv; v++) {
        ck_assert(nz[v] > 0 || (nz[v] == 0 && (ny[v] > 0 || (ny[v] == 0 && nx[v] > 0))));
    }
    double *Sg = malloc(sizeof(double) * (size_t)nv), *Sd = malloc(sizeof(double) * (size_t)nv);
    ck_assert_int_eq(gr_sk3_compute(pl, GR_SK_GRIDDING, N, f.x, f.y, f.z, Sg, &err), GR_OK);
    ck_assert_int_eq(gr_sk3_compute(pl, GR_SK_DIRECT, N, f.x, f.y, f.z, Sd, &err), GR_OK);
    double worst = 0.0;
    for (int v = 0; v < nv; v++) {
        worst = fmax(worst, fabs(Sg[v] - Sd[v]));
    }
    ck_assert_msg(worst < 1e-5, "gridding - direct: %g", worst); /* measured 3.9e-6, msp = 6 */
    ck_assert_int_eq(gr_sk3_compute(pl, 7, N, f.x, f.y, f.z, Sg, &err), GR_EINVAL);
    gr_sk3_plan_free(pl);
    ck_assert_int_eq(gr_sk3_plan_create(L, 65.0, 6, &pl, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "sk_kd_max"), "%s", err.message);
    enum { M = 4, NL = M * M * M };
    double x[NL], y[NL], z[NL];
    for (int i = 0; i < NL; i++) {
        x[i] = (i % M + 0.25) * L / M;
        y[i] = (i / M % M + 0.5) * L / M;
        z[i] = (i / (M * M) + 0.75) * L / M;
    }
    ck_assert_int_eq(gr_sk3_plan_create(L, 8.0, GR_SK3_MSP_DEFAULT, &pl, &err), GR_OK);
    const int nv2 = gr_sk_vectors(gr_sk3_plan_lattice(pl), &nx, &ny, &nz);
    double *S = malloc(sizeof(double) * (size_t)nv2);
    ck_assert_int_eq(gr_sk3_compute(pl, GR_SK_GRIDDING, NL, x, y, z, S, &err), GR_OK);
    int peaks = 0;
    for (int v = 0; v < nv2; v++) {
        const bool bragg = nx[v] % M == 0 && ny[v] % M == 0 && nz[v] % M == 0;
        peaks += bragg;
        ck_assert_msg(fabs(S[v] - (bragg ? NL : 0.0)) < 1e-5 * NL, "S(%d, %d, %d) = %g", nx[v],
                      ny[v], nz[v], S[v]);
    }
    /* in the half space with |n| <= 8: (4,0,0) and (8,0,0) 3 each, (4,4,0) 6, (4,4,4) 4 */
    ck_assert_int_eq(peaks, 16);
    gr_sk3_plan_free(pl);
    free(S);
    free(Sg);
    free(Sd);
    frame_free(&f);
    gsl_rng_free(r);
}
END_TEST

/* Random points through the observable: S = 1 in every spherical bin within 4 errors, and the fit
 * (4.4) S ~ k^-D_f flat, D_f = 0 within 4 errors; l_0 = L^3 / (pi d^2 N). Large spheres (d = L/5)
 * and eps_n = 0.5 put k' = 2 k_D = 2 (1 - eps_n^2) / (8 l_0) at 11 2 pi / L: shells to fit. */
START_TEST(test_sk_ideal_gas)
{
    gr_scene sc;
    enum { N = 3000, F = 20 };
    const double L = 0.1, r0 = 0.01;
    h_scene(&sc, 3, N, L, r0);
    sc.contact.eps_n = 0.5;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "sk_kd_max", 20.0, NULL), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 17);
    frame3 f = frame_new(N);
    void *st = h_create(&gr_obs_sk, &sc);
    for (int k = 0; k < F; k++) {
        frame_random(&f, L, 1.0, r);
        sample_frame(&gr_obs_sk, st, &sc, &f, k);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_sk, st, &sc, "sk.csv", &tab);
    const cJSON *sk = cJSON_GetObjectItem(j, "sk");
    ck_assert_int_eq(tab.rows, 16); /* |n| up to 20 L / (2 pi d) = 15.9: bins centred 1 .. 16 */
    int outliers = 0;
    for (int b = 0; b < tab.rows; b++) {
        const double S = h_at(&tab, b, 3), e = h_at(&tab, b, 4);
        outliers += !(fabs(S - 1.0) < 4.0 * e);
    }
    ck_assert_msg(outliers == 0, "%d bins more than 4 errors from S = 1", outliers);
    const cJSON *fit = cJSON_GetObjectItem(sk, "fit");
    const double Df = h_num(fit, "D_f", NULL), Df_err = h_num(fit, "D_f_err", NULL);
    ck_assert_msg(fabs(Df) < 4.0 * Df_err && Df_err < 0.2, "D_f = %g +- %g", Df, Df_err);
    ck_assert_double_eq_tol(h_num(sk, "l0", NULL), L * L * L / (M_PI * 4 * r0 * r0 * N), 1e-15);
    frame_free(&f);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* The registry: the frame observables take dim = 3 (gaps is 1D and refused, with the scene file);
 * a frame whose z is beyond the wrappable range is refused before any observable sees it; a
 * profile axis beyond z is refused naming the allowed axes. */
START_TEST(test_registry)
{
    static const char *const ok3[] = {"moments", "pv",    "pair",      "msd",
                                      "vacf",    "vcorr", "clusters",  "pressure",
                                      "profile", "sk",    "collisions"};
    for (size_t k = 0; k < sizeof ok3 / sizeof ok3[0]; k++) {
        const gr_observable_type *t = gr_observable_find(ok3[k]);
        ck_assert_ptr_nonnull(t);
        ck_assert_msg(t->dims & 4u, "%s: no 3D", ok3[k]);
    }
    gr_scene sc;
    h_scene(&sc, 3, 8, 0.1, 1e-3);
    snprintf(sc.observables, sizeof sc.observables, "gaps");
    gr_observer *o = NULL;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_observer(&sc, &o, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "gaps is not defined for dim = 3"), "%s", err.message);
    snprintf(sc.observables, sizeof sc.observables, "msd");
    ck_assert_int_eq(gr_scene_observer(&sc, &o, &err), GR_OK);
    frame3 f = frame_new(8);
    f.z[5] = 1e300;
    gr_particles p = {.n = 8,
                      .dim = 3,
                      .L = 0.1,
                      .radius = 1e-3,
                      .mass = 1.0,
                      .x = f.x,
                      .y = f.y,
                      .z = f.z,
                      .vx = f.vx,
                      .vy = f.vy,
                      .vz = f.vz};
    ck_assert_int_eq(gr_observer_sample(o, &p, 0.0, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "particle 5 has z = "), "%s", err.message);
    gr_observer_free(o);
    frame_free(&f);
    /* profile_axis beyond z (the scene parser's range is -1..2; gr_analysis_set skips it) */
    void *st = NULL;
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_axis", 3, NULL), GR_OK);
    ck_assert_int_eq(gr_scene_observable(&gr_obs_profile, &sc, &st, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "profile_axis: 3 (no axis) in a 3D system; allowed in 3D: 0 "
                                      "(x), 1 (y), 2 (z)"),
                  "%s", err.message);
    ck_assert_ptr_null(st);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_3d");
    TCase *t = tcase_create("obs_3d");
    tcase_set_timeout(t, 300);
    tcase_add_test(t, test_pair_ideal_gas);
    tcase_add_test(t, test_pressure_ideal_gas);
    tcase_add_test(t, test_pressure_overlap);
    tcase_add_test(t, test_pv_maxwellian);
    tcase_add_test(t, test_msd_vacf_ballistic);
    tcase_add_test(t, test_vcorr_pair);
    tcase_add_test(t, test_clusters_chain);
    tcase_add_test(t, test_profile_z);
    tcase_add_test(t, test_sk_engine);
    tcase_add_test(t, test_sk_ideal_gas);
    tcase_add_test(t, test_registry);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
