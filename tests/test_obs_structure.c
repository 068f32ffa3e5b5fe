/* The frame observables vcorr, clusters and pressure on configurations with a
 * known answer: clusters - a touching chain (1D ring, 2D row and square lattice
 * at spacing d) is one contact cluster; spacing 1.2 d gives N contact
 * singletons but one density cluster (cluster_distance 1.5); spacing 2 d gives
 * singletons of both kinds; two separate touching chains are two clusters;
 *   pressure - an ideal gas (no contacts) has P = n T exactly, no virial, Z =
 * 1, and the C_1 of the equation of state (5.2) follows from the mean speed;
 * two particles at rest overlapping by xi along x give P_xx = |r| k_s xi / V,
 * P_yy = 0 (1D: P = |r| k_s xi / L); vcorr    - independent random velocities
 * give C_L = C_T = 0 within errors; a pair with u_1 = -u_2 = (1, 2) at 1.5 d
 * along x gives C_L = -0.4, C_T = -1.6. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "obs_harness.h"
#include "check_main.h"

extern const gr_observable_type gr_obs_clusters, gr_obs_pressure, gr_obs_vcorr, gr_obs_profile;

static const cJSON *kind(const cJSON *j, const char *k)
{
    return cJSON_GetObjectItem(cJSON_GetObjectItem(j, "clusters"), k);
}

/* One frame of n particles on a row (1D ring or a 2D row at y = L/2) at the
 * given spacing from x0; returns the analysis summary. */
static cJSON *row_frame(int dim, int n, double L, double spacing, double x0, h_table *tab)
{
    gr_scene sc;
    const double d = 1e-3;
    h_scene(&sc, dim, n, L, 0.5 * d);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "cluster_distance", 1.5, NULL), GR_OK);
    double x[64], y[64], v[64] = {0};
    for (int i = 0; i < n; i++) {
        x[i] = x0 + i * spacing * d;
        y[i] = 0.5 * L;
    }
    void *st = h_create(&gr_obs_clusters, &sc);
    h_sample(&gr_obs_clusters, st, &sc, x, y, v, v, 0.0);
    return h_finish(&gr_obs_clusters, st, &sc, "clusters.csv", tab);
}

static void check_row(int dim)
{
    h_table tab;
    /* touching chain of 20 across the periodic boundary: one contact cluster */
    cJSON *j = row_frame(dim, 20, 0.1, 1.0, 0.095, &tab);
    ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), 1.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "largest", NULL), 20.0);
    ck_assert_int_eq(tab.rows, 1);
    ck_assert_double_eq(h_at(&tab, 0, 0), 20.0);
    ck_assert_double_eq(h_at(&tab, 0, 1), 1.0); /* one cluster of size 20 per frame */
    ck_assert_double_eq(h_at(&tab, 0, 2), 1.0); /* holding every particle */
    cJSON_Delete(j);
    free(tab.v);
    /* spacing 1.2 d: contact singletons, one density cluster */
    j = row_frame(dim, 20, 0.1, 1.2, 0.01, &tab);
    ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), 20.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "mean_size", NULL), 1.0);
    ck_assert_double_eq(h_num(kind(j, "density"), "clusters_per_frame", NULL), 1.0);
    ck_assert_double_eq(h_num(kind(j, "density"), "largest", NULL), 20.0);
    cJSON_Delete(j);
    free(tab.v);
    /* spacing 2 d: singletons of both kinds */
    j = row_frame(dim, 20, 0.1, 2.0, 0.01, &tab);
    ck_assert_double_eq(h_num(kind(j, "density"), "clusters_per_frame", NULL), 20.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "largest", NULL), 1.0);
    ck_assert_int_eq(tab.rows, 1);
    ck_assert_double_eq(h_at(&tab, 0, 0), 1.0);
    ck_assert_double_eq(h_at(&tab, 0, 1), 20.0);
    cJSON_Delete(j);
    free(tab.v);
}

START_TEST(test_clusters_row_1d) { check_row(1); }
END_TEST

START_TEST(test_clusters_row_2d) { check_row(2); }
END_TEST

/* A mixture's row: grain i of radius r[i] follows grain i-1 at f (r[i-1] + r[i]); one frame with
 * the grains' own radii (p.radii), as a run with [species] hands it over. */
static cJSON *mixture_row(const double *r, const double *x, h_table *tab)
{
    enum { N = 20 };
    gr_scene sc;
    const double L = 0.2;
    h_scene(&sc, 2, N, L, 1e-3); /* the largest radius, as a mixture's setup has it */
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "cluster_distance", 1.5, NULL), GR_OK);
    double y[N], v[N] = {0};
    for (int i = 0; i < N; i++) {
        y[i] = 0.5 * L;
    }
    void *st = h_create(&gr_obs_clusters, &sc);
    const gr_particles p = {.n = N,
                            .dim = 2,
                            .L = L,
                            .radius = 1e-3,
                            .mass = sc.mass,
                            .x = x,
                            .y = y,
                            .vx = v,
                            .vy = v,
                            .radii = r};
    gr_error err = {0};
    ck_assert_int_eq(gr_obs_clusters.sample(st, &p, 0.0, &err), GR_OK);
    return h_finish(&gr_obs_clusters, st, &sc, "clusters.csv", tab);
}

/* On a mixture grains touch at r_i + r_j, not at the largest diameter. */
START_TEST(test_clusters_mixture_pairs)
{
    enum { N = 20 };
    double r[N], x[N];
    h_table tab;
    const double gap[2] = {1.0 - 1e-12, 1.2};
    for (int k = 0; k < 2; k++) { /* alternating radii 0.5 and 1 mm, touching, then 1.2 apart */
        for (int i = 0; i < N; i++) {
            r[i] = i % 2 ? 1e-3 : 0.5e-3;
            x[i] = i ? x[i - 1] + gap[k] * (r[i - 1] + r[i]) : 0.01;
        }
        cJSON *j = mixture_row(r, x, &tab);
        ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), k ? 20.0 : 1.0);
        ck_assert_double_eq(h_num(kind(j, "density"), "clusters_per_frame", NULL), 1.0);
        h_done(&tab, j);
    }
    /* small grains 1.2 mm apart (contact at 1 mm) beside one large grain far away: contact
     * singletons, as they would not be at the largest diameter (2 mm); one density cluster of 19 */
    for (int i = 0; i < N; i++) {
        r[i] = i ? 0.5e-3 : 1e-3;
        x[i] = i ? 0.01 + 1.2e-3 * i : 0.15;
    }
    cJSON *j = mixture_row(r, x, &tab);
    ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), 20.0);
    ck_assert_double_eq(h_num(kind(j, "density"), "clusters_per_frame", NULL), 2.0);
    ck_assert_double_eq(h_num(kind(j, "density"), "largest", NULL), 19.0);
    h_done(&tab, j);
}
END_TEST

/* 2D: a touching 6 x 6 square lattice is one cluster; two touching chains of 7
 * and 5 separated by 3 d are two contact clusters (sizes 7 and 5). */
START_TEST(test_clusters_lattice_2d)
{
    gr_scene sc;
    const double d = 1e-3, L = 0.05;
    h_scene(&sc, 2, 36, L, 0.5 * d);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "cluster_distance", 1.5, NULL), GR_OK);
    double x[36], y[36], v[36] = {0};
    for (int i = 0; i < 36; i++) {
        x[i] = 0.01 + (i % 6) * d;
        y[i] = 0.02 + (i / 6) * d;
    }
    void *st = h_create(&gr_obs_clusters, &sc);
    h_sample(&gr_obs_clusters, st, &sc, x, y, v, v, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_clusters, st, &sc, "clusters.csv", &tab);
    ck_assert_double_eq(h_num(kind(j, "contact"), "largest", NULL), 36.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), 1.0);
    cJSON_Delete(j);
    free(tab.v);

    h_scene(&sc, 2, 12, L, 0.5 * d);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "cluster_distance", 1.5, NULL), GR_OK);
    for (int i = 0; i < 12; i++) {
        x[i] = i < 7 ? 0.01 + i * d : 0.01 + (i + 3) * d;
        y[i] = 0.03;
    }
    st = h_create(&gr_obs_clusters, &sc);
    for (int f = 0; f < 3; f++) {
        h_sample(&gr_obs_clusters, st, &sc, x, y, v, v, f);
    }
    j = h_finish(&gr_obs_clusters, st, &sc, "clusters.csv", &tab);
    ck_assert_double_eq(h_num(kind(j, "contact"), "clusters_per_frame", NULL), 2.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "largest", NULL), 7.0);
    ck_assert_double_eq(h_num(kind(j, "contact"), "mean_size", NULL), 6.0);
    ck_assert_int_eq(tab.rows, 2);
    ck_assert_double_eq(h_at(&tab, 0, 0), 5.0);
    ck_assert_double_eq(h_at(&tab, 1, 0), 7.0);
    ck_assert_double_eq_tol(h_at(&tab, 1, 2), 7.0 / 12.0, 1e-8);
    cJSON_Delete(j);
    free(tab.v);
}
END_TEST

/* Ideal gas: random points far apart relative to their size, Gaussian
 * velocities. */
START_TEST(test_pressure_ideal_gas)
{
    gr_scene sc;
    enum { N = 500, F = 20 };
    const double L = 1.0, M = 3.53e-5;
    h_scene(&sc, 2, N, L, 1e-6);
    sc.mass = M;
    sc.D = 1e-8;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 3);
    void *st = h_create(&gr_obs_pressure, &sc);
    double x[N], y[N], vx[N], vy[N], nT = 0.0, speed = 0.0;
    for (int f = 0; f < F; f++) {
        double m[2] = {0, 0};
        for (int i = 0; i < N; i++) {
            x[i] = L * gsl_rng_uniform(r);
            y[i] = L * gsl_rng_uniform(r);
            vx[i] = 0.3 * gsl_ran_gaussian_ziggurat(r, 1.0);
            vy[i] = 0.3 * gsl_ran_gaussian_ziggurat(r, 1.0);
            m[0] += vx[i] / N;
            m[1] += vy[i] / N;
        }
        for (int i = 0; i < N; i++) {
            double ux = vx[i] - m[0], uy = vy[i] - m[1];
            nT += M * (ux * ux + uy * uy) / 2.0 / (L * L) / F;
            speed += sqrt(ux * ux + uy * uy) / N / F;
        }
        h_sample(&gr_obs_pressure, st, &sc, x, y, vx, vy, f);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pressure");
    ck_assert_double_eq_tol(h_num(p, "P", NULL), nT, 1e-12 * nT);
    ck_assert_double_eq_tol(h_num(p, "nT", NULL), nT, 1e-12 * nT);
    ck_assert_double_eq_tol(h_num(p, "Z", NULL), 1.0, 1e-12);
    ck_assert_double_eq(h_num(p, "collisional_xx", NULL), 0.0);
    ck_assert_double_eq(h_num(p, "contacts_per_frame", NULL), 0.0);
    /* N M <u_x^2> / L^2 and the same for y: n T from each diagonal component
     * within errors */
    ck_assert_double_eq_tol(h_num(p, "kinetic_xx", NULL), nT,
                            4.0 * h_num(p, "kinetic_xx_error", NULL));
    /* (5.2): C_1 = <|v|>^3 phi M^2 (2 - eps_n^2 - eps_t^2) / (D d pi) */
    double phi = N * M_PI * sc.radius * sc.radius / (L * L),
           eps_t = sc.tangential ? sc.contact.eps_t : 1.0;
    double C1 = pow(speed, 3) * phi * M * M *
                (2.0 - sc.contact.eps_n * sc.contact.eps_n - eps_t * eps_t) /
                (sc.D * 2.0 * sc.radius * M_PI);
    ck_assert_double_eq_tol(h_num(cJSON_GetObjectItem(p, "eos_5_2"), "C1", NULL), C1, 1e-9 * C1);
    ck_assert_int_eq(tab.rows, 9);
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

/* Two particles at rest overlapping by xi: the virial of the spring (2.4), no
 * dashpot at rest. */
static void overlap_pair(int dim)
{
    gr_scene sc;
    const double d = 3e-3, xi = 1e-5, L = 0.1;
    h_scene(&sc, dim, 2, L, 0.5 * d);
    ck_assert_ptr_nonnull(sc.normal);
    double x[2] = {L - 0.4 * d, 0.6 * d - xi}, y[2] = {0.05, 0.05},
           v[2] = {0, 0}; /* across the boundary */
    void *st = h_create(&gr_obs_pressure, &sc);
    h_sample(&gr_obs_pressure, st, &sc, x, y, v, v, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pressure");
    double V = dim == 2 ? L * L : L, W = (d - xi) * sc.contact.k_s * xi / V;
    ck_assert_double_eq_tol(h_num(p, "collisional_xx", NULL), W, 1e-9 * W);
    ck_assert_double_eq_tol(h_num(p, "collisional_yy", NULL), 0.0, 1e-12 * W);
    ck_assert_double_eq_tol(h_num(p, "P", NULL), W / dim, 1e-9 * W);
    ck_assert_double_eq(h_num(p, "contacts_per_frame", NULL), 1.0);
    h_done(&tab, j);
}

/* A mixture's pressure (species lists; radii 1 and 2 mm, masses 1e-5 and 4e-5 kg, spring-dashpot):
 * the pair touches at r_1 + r_2, so overlapping by xi at rest its virial is (r_1 + r_2 - xi) k_s xi
 * / V (at the largest diameter 4 mm it would be another overlap); moving apart along x at
 * v_1, v_2 (the overlap's dashpot then acts too, so only the kinetic part is checked there) the
 * kinetic part is sum_i m_i u_i^2 / V with u relative to the centre of mass's velocity. */
START_TEST(test_pressure_mixture)
{
    gr_scene sc;
    const double r[2] = {1e-3, 2e-3}, m[2] = {1e-5, 4e-5}, xi = 1e-5, L = 0.1;
    h_scene(&sc, 2, 2, L, 2e-3); /* the largest radius, as a mixture's setup has it */
    sc.n_species = 2;
    sc.species_radius.n = 2;
    sc.species_radius.v[0] = r[0];
    sc.species_radius.v[1] = r[1];
    sc.species_masses[0] = m[0];
    sc.species_masses[1] = m[1];
    sc.species_count[0] = sc.species_count[1] = 1;
    const int species[2] = {0, 1};
    double x[2] = {0.03, 0.03 + r[0] + r[1] - xi}, y[2] = {0.05, 0.05}, v0[2] = {0.0, 0.0};
    for (int k = 0; k < 2; k++) {
        void *st = h_create(&gr_obs_pressure, &sc);
        double vx[2] = {k ? -0.4 : 0.0, k ? 0.1 : 0.0};
        const gr_particles p = {.n = 2,
                                .dim = 2,
                                .L = L,
                                .radius = 2e-3,
                                .mass = 2.5e-5,
                                .x = x,
                                .y = y,
                                .vx = vx,
                                .vy = v0,
                                .species = species,
                                .radii = r,
                                .masses = m,
                                .n_species = 2};
        gr_error err = {0};
        ck_assert_int_eq(gr_obs_pressure.sample(st, &p, 0.0, &err), GR_OK);
        h_table tab;
        cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
        const cJSON *pr = cJSON_GetObjectItem(j, "pressure");
        const double V = L * L;
        if (k == 0) {
            const double W = (r[0] + r[1] - xi) * sc.contact.k_s * xi / V;
            ck_assert_double_eq_tol(h_num(pr, "collisional_xx", NULL), W, 1e-9 * W);
            ck_assert_double_eq(h_num(pr, "contacts_per_frame", NULL), 1.0);
            ck_assert_ptr_null(cJSON_GetObjectItem(pr, "eos_5_2")); /* one species' (5.2) */
        } else {
            const double Vc = (m[0] * vx[0] + m[1] * vx[1]) / (m[0] + m[1]);
            const double K =
                (m[0] * (vx[0] - Vc) * (vx[0] - Vc) + m[1] * (vx[1] - Vc) * (vx[1] - Vc)) / V;
            ck_assert_double_eq_tol(h_num(pr, "kinetic_xx", NULL), K, 1e-12 * K);
            ck_assert_double_eq_tol(h_num(pr, "nT", NULL), K / 2.0, 1e-12 * K);
        }
        h_done(&tab, j);
    }
}
END_TEST

/* A radius distribution's pressure (uniform radii in [1, 3] mm, density 5 kg/m^2): the pair of radii
 * 1 and 2.5 mm touches at r_1 + r_2, with the coefficients the kernel scales per pair. Under hertz
 * the scene's k_h is that of two grains of radius_min, so the pair's is k_h sqrt(R / (r_min / 2))
 * with R = r_1 r_2 / (r_1 + r_2), and at rest the virial is (r_1 + r_2 - xi) k_h(R) xi^(3/2) / V.
 * Under the spring-dashpot every pair has the scene's k_s and the damping of its own reduced mass
 * M, gamma_n = 2 zeta sqrt(k_s M) with zeta = -ln eps_n / sqrt(pi^2 + ln^2 eps_n) (2.6): grain 1
 * approaching at 0.2 m/s adds gamma_n 0.2 to the force. */
static void pressure_distribution(const char *law)
{
    gr_scene sc;
    const double r[2] = {1e-3, 2.5e-3}, rho = 5.0, xi = 1e-5, L = 0.1;
    const double m[2] = {M_PI * r[0] * r[0] * rho, M_PI * r[1] * r[1] * rho};
    h_scene(&sc, 2, 2, L, 1e-3);
    sc.normal = gr_model_find(law);
    ck_assert_ptr_nonnull(sc.normal);
    sc.size_distribution = GR_SIZE_UNIFORM;
    sc.radius_min = 1e-3;
    sc.radius_max = 3e-3;
    sc.species_density.n = 1;
    sc.species_density.v[0] = rho;
    const double kh = gr_contact_get(&sc.contact, "k_h"), ks = sc.contact.k_s, e = sc.contact.eps_n;
    double x[2] = {0.03, 0.03 + r[0] + r[1] - xi}, y[2] = {0.05, 0.05}, vy[2] = {0.0, 0.0};
    double vx[2] = {0.2, 0.0};
    const bool hertz = strcmp(law, "hertz") == 0;
    if (hertz) {
        vx[0] = 0.0;
    }
    void *st = h_create(&gr_obs_pressure, &sc);
    const gr_particles p = {.n = 2,
                            .dim = 2,
                            .L = L,
                            .radius = 1e-3,
                            .mass = m[0],
                            .x = x,
                            .y = y,
                            .vx = vx,
                            .vy = vy,
                            .radii = r,
                            .masses = m};
    gr_error err = {0};
    ck_assert_int_eq(gr_obs_pressure.sample(st, &p, 0.0, &err), GR_OK);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *pr = cJSON_GetObjectItem(j, "pressure");
    const double R = r[0] * r[1] / (r[0] + r[1]), M = m[0] * m[1] / (m[0] + m[1]);
    const double zeta = -log(e) / sqrt(M_PI * M_PI + log(e) * log(e));
    const double f = hertz ? kh * sqrt(R / (0.5 * sc.radius_min)) * pow(xi, 1.5)
                           : ks * xi + 2.0 * zeta * sqrt(ks * M) * 0.2;
    const double W = (r[0] + r[1] - xi) * f / (L * L);
    ck_assert_double_eq_tol(h_num(pr, "collisional_xx", NULL), W, 1e-9 * W);
    ck_assert_double_eq(h_num(pr, "contacts_per_frame", NULL), 1.0);
    ck_assert_ptr_null(cJSON_GetObjectItem(pr, "eos_5_2")); /* one size's (5.2) */
    h_done(&tab, j);
}

START_TEST(test_pressure_distribution_hertz) { pressure_distribution("hertz"); }
END_TEST

START_TEST(test_pressure_distribution_spring) { pressure_distribution("spring_dashpot"); }
END_TEST

/* The same pair under the hertz law: the virial is the force kernel's law
 * (gr_contact_virial), whatever the law, f_n = k_h xi^(3/2) at rest (no copy of
 * a law in the observable; before, only the spring-dashpot had a virial and a
 * hertz scene reported the kinetic part alone). The pair sum is that of the old
 * spring-dashpot code in the same order, so the spring-dashpot values above
 * (and every pressure.csv) are unchanged to the last bit. */
static void overlap_pair_hertz(int dim)
{
    gr_scene sc;
    const double d = 3e-3, xi = 1e-5, L = 0.1;
    h_scene(&sc, dim, 2, L, 0.5 * d);
    sc.normal = gr_model_find("hertz");
    ck_assert_ptr_nonnull(sc.normal);
    gr_obs_setup setup;
    gr_error err = {0};
    ck_assert_msg(gr_scene_obs_setup(&sc, &setup, &err) == GR_OK, "%s", err.message);
    double x[2] = {L - 0.4 * d, 0.6 * d - xi}, y[2] = {0.05, 0.05}, v[2] = {0, 0};
    void *st = h_create(&gr_obs_pressure, &sc);
    h_sample(&gr_obs_pressure, st, &sc, x, y, v, v, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_pressure, st, &sc, "pressure.csv", &tab);
    const cJSON *p = cJSON_GetObjectItem(j, "pressure");
    double V = dim == 2 ? L * L : L, W = (d - xi) * setup.contact.k_s * pow(xi, 1.5) / V;
    ck_assert(W > 0.0);
    ck_assert_double_eq_tol(h_num(p, "collisional_xx", NULL), W, 1e-9 * W);
    ck_assert_double_eq_tol(h_num(p, "P", NULL), W / dim, 1e-9 * W);
    ck_assert_double_eq(h_num(p, "contacts_per_frame", NULL), 1.0);
    ck_assert_str_eq(cJSON_GetObjectItem(p, "virial")->valuestring,
                     "normal hertz force (models/hertz.h); tangential forces left out");
    h_done(&tab, j);
}

START_TEST(test_pressure_hertz_2d) { overlap_pair_hertz(2); }
END_TEST

START_TEST(test_pressure_hertz_1d) { overlap_pair_hertz(1); }
END_TEST

START_TEST(test_pressure_overlap_2d) { overlap_pair(2); }
END_TEST

START_TEST(test_pressure_overlap_1d) { overlap_pair(1); }
END_TEST

START_TEST(test_vcorr_random)
{
    gr_scene sc;
    enum { N = 1000, F = 40 };
    const double L = 1.0;
    h_scene(&sc, 2, N, L, 5e-3);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vcorr_bins", 10, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vcorr_rmax", 10, NULL), GR_OK);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    void *st = h_create(&gr_obs_vcorr, &sc);
    double x[N], y[N], vx[N], vy[N];
    for (int f = 0; f < F; f++) {
        for (int i = 0; i < N; i++) {
            x[i] = L * gsl_rng_uniform(r);
            y[i] = L * gsl_rng_uniform(r);
            vx[i] = gsl_ran_gaussian_ziggurat(r, 1.0);
            vy[i] = gsl_ran_gaussian_ziggurat(r, 1.0);
        }
        h_sample(&gr_obs_vcorr, st, &sc, x, y, vx, vy, f);
    }
    h_table tab;
    cJSON *j = h_finish(&gr_obs_vcorr, st, &sc, "vcorr.csv", &tab);
    ck_assert_str_eq(tab.columns, "r,r_over_d,C_L,C_L_stderr,C_T,C_T_stderr,frames\n");
    ck_assert_int_eq(tab.rows, 10);
    for (int b = 0; b < tab.rows; b++) {
        ck_assert_double_eq_tol(h_at(&tab, b, 1), (b + 0.5), 1e-9);
        ck_assert_msg(h_at(&tab, b, 3) > 0.0 && h_at(&tab, b, 3) < 0.1, "error %g",
                      h_at(&tab, b, 3));
        ck_assert_msg(fabs(h_at(&tab, b, 2)) < 4.0 * h_at(&tab, b, 3), "C_L(%g) = %g +- %g",
                      h_at(&tab, b, 0), h_at(&tab, b, 2), h_at(&tab, b, 3));
        ck_assert_msg(fabs(h_at(&tab, b, 4)) < 4.0 * h_at(&tab, b, 5), "C_T(%g) = %g +- %g",
                      h_at(&tab, b, 0), h_at(&tab, b, 4), h_at(&tab, b, 5));
    }
    gsl_rng_free(r);
    h_done(&tab, j);
}
END_TEST

START_TEST(test_vcorr_pair)
{
    gr_scene sc;
    h_scene(&sc, 2, 2, 1.0, 5e-3);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vcorr_bins", 10, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "vcorr_rmax", 10, NULL), GR_OK);
    double x[2] = {0.9925, 0.0075}, y[2] = {0.5, 0.5}, vx[2] = {1.0, -1.0},
           vy[2] = {2.0, -2.0}; /* r = 1.5 d */
    void *st = h_create(&gr_obs_vcorr, &sc);
    h_sample(&gr_obs_vcorr, st, &sc, x, y, vx, vy, 0.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_vcorr, st, &sc, "vcorr.csv", &tab);
    const cJSON *c = cJSON_GetObjectItem(j, "vcorr");
    ck_assert_int_eq(tab.rows, 1);
    ck_assert_double_eq_tol(h_num(c, "r_first", NULL), 0.015, 1e-12);
    ck_assert_double_eq_tol(h_num(c, "C_L_first", NULL), -0.4, 1e-12);
    ck_assert_double_eq_tol(h_num(c, "C_T_first", NULL), -1.6, 1e-12);
    h_done(&tab, j);
}
END_TEST

/* profile: two frames of three particles in four slabs along y, every number by hand (the CSV
 * holds 8 significant digits); and in 1D an unwrapped position counted in the slab of its image
 * in [0, L). */
START_TEST(test_profile_by_hand)
{
    gr_scene sc;
    gr_error err = {0};
    h_scene(&sc, 2, 3, 2.0, 0.01);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_bins", 4, &err), GR_OK);
    void *st = h_create(&gr_obs_profile, &sc);
    const double x[3] = {0.3, 1.1, 1.9};
    const double y1[3] = {0.1, 0.2, 1.2}, vx1[3] = {1.0, 3.0, -2.0}, vy1[3] = {0.5, 0.5, 0.0};
    const double y2[3] = {0.3, 1.1, 1.4}, vx2[3] = {2.0, 4.0, 6.0}, vy2[3] = {0.0, 1.0, -1.0};
    h_sample(&gr_obs_profile, st, &sc, x, y1, vx1, vy1, 0.0);
    h_sample(&gr_obs_profile, st, &sc, x, y2, vx2, vy2, 1.0);
    h_table tab;
    cJSON *j = h_finish(&gr_obs_profile, st, &sc, "profile.csv", &tab);
    ck_assert_int_eq(tab.rows, 4);
    ck_assert_int_eq(tab.cols, 11);
    /* slab 0 (y in [0, 0.5)): counts 2 and 1, so <c> = 1.5 and n = 1.5 / (0.5 * 2) */
    ck_assert_double_eq_tol(h_at(&tab, 0, 0), 0.25, 1e-12);
    ck_assert_double_eq_tol(h_at(&tab, 0, 1), 1.5, 1e-12);
    ck_assert_double_eq_tol(h_at(&tab, 0, 3), 1.5 * M_PI * 1e-4, 1e-10); /* %.8g */
    /* u_x = (1 + 3 + 2) / 3 = 2; T_x = (1 + 9 + 4) / 3 - 4 = 2/3; u_y = 1/3, T_y = 0.5/3 - 1/9 */
    ck_assert_double_eq_tol(h_at(&tab, 0, 5), 2.0, 1e-7);
    ck_assert_double_eq_tol(h_at(&tab, 0, 7), 2.0 / 3.0, 1e-7);
    ck_assert_double_eq_tol(h_at(&tab, 0, 6), 1.0 / 3.0, 1e-7);
    ck_assert_double_eq_tol(h_at(&tab, 0, 9), 0.5 / 3.0 - 1.0 / 9.0, 1e-7);
    /* slab 1 (y in [0.5, 1)) is empty: n = 0, no velocity */
    ck_assert_double_eq(h_at(&tab, 1, 1), 0.0);
    ck_assert(isnan(h_at(&tab, 1, 5)));
    /* slab 2 (y in [1, 1.5)): 1 and 2 particles, u_x = (-2 + 4 + 6) / 3, T_x = (4 + 16 + 36) / 3 - u^2 */
    ck_assert_double_eq_tol(h_at(&tab, 2, 1), 1.5, 1e-12);
    ck_assert_double_eq_tol(h_at(&tab, 2, 5), 8.0 / 3.0, 1e-7);
    ck_assert_double_eq_tol(h_at(&tab, 2, 7), 56.0 / 3.0 - 64.0 / 9.0, 1e-6);
    ck_assert_double_eq(h_at(&tab, 3, 1), 0.0);
    const cJSON *p = cJSON_GetObjectItem(j, "profile");
    ck_assert_str_eq(cJSON_GetObjectItem(p, "axis")->valuestring, "y");
    ck_assert_double_eq_tol(h_num(p, "mean_position", NULL), (1.5 / 3.0 + 2.8 / 3.0) / 2.0, 1e-12);
    h_done(&tab, j);

    /* 1D: positions unwrapped; -0.25 counts at 0.75 of a ring of length 1 */
    h_scene(&sc, 1, 2, 1.0, 0.01);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_bins", 2, &err), GR_OK);
    st = h_create(&gr_obs_profile, &sc);
    const double x1[2] = {-0.25, 1.2}, v1[2] = {1.0, -1.0};
    h_sample(&gr_obs_profile, st, &sc, x1, NULL, v1, NULL, 0.0);
    j = h_finish(&gr_obs_profile, st, &sc, "profile.csv", &tab);
    ck_assert_int_eq(tab.rows, 2);
    ck_assert_double_eq_tol(h_at(&tab, 0, 1), 1.0 / 0.5, 1e-12); /* 1.2 -> 0.2 */
    ck_assert_double_eq_tol(h_at(&tab, 1, 1), 1.0 / 0.5, 1e-12); /* -0.25 -> 0.75 */
    ck_assert_double_eq_tol(h_at(&tab, 1, 5), 1.0, 1e-12);
    ck_assert_double_eq_tol(h_at(&tab, 0, 3), 2.0 * 0.02, 1e-12); /* phi = n d */
    h_done(&tab, j);

    /* profile_axis = 1 (y) in 1D is refused, naming the key */
    h_scene(&sc, 1, 2, 1.0, 0.01);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_axis", 1, &err), GR_OK);
    void *bad = NULL;
    ck_assert_int_ne(gr_scene_observable(&gr_obs_profile, &sc, &bad, &err), GR_OK);
    ck_assert_ptr_nonnull(strstr(err.message, "profile_axis"));
}
END_TEST

/* profile on a mixture: one frame of three grains of two species (radii 0.1 and 0.2, masses 1
 * and 3) in two slabs along y, every number by hand: phi from each grain's own area, u the slab's
 * centre-of-mass velocity, T in J from each grain's own mass, then the same per species; in 3D
 * the z columns too (13 per group). */
static cJSON *mixture_frame(int dim, h_table *tab)
{
    gr_scene sc;
    h_scene(&sc, dim, 3, 2.0, 0.2);
    sc.n_species = 2; /* what gr_scene_obs_setup reads: a mixture of two species */
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_bins", 2, NULL), GR_OK);
    ck_assert_int_eq(gr_analysis_set(&sc.analysis, "profile_axis", 1, NULL), GR_OK);
    void *st = h_create(&gr_obs_profile, &sc);
    const double x[3] = {0.5, 1.0, 1.5}, y[3] = {0.2, 0.4, 1.5}, z[3] = {1.0, 1.0, 1.0};
    const double vx[3] = {1.0, -1.0, 2.0}, vy[3] = {0.0, 2.0, 2.0}, vz[3] = {1.0, 3.0, 0.0};
    const int species[3] = {0, 1, 0};
    const double radii[3] = {0.1, 0.2, 0.1}, masses[3] = {1.0, 3.0, 1.0};
    gr_particles p = {.n = 3,
                      .dim = dim,
                      .L = 2.0,
                      .radius = 0.2,
                      .mass = 5.0 / 3.0,
                      .x = x,
                      .y = y,
                      .z = dim == 3 ? z : NULL,
                      .vx = vx,
                      .vy = vy,
                      .vz = dim == 3 ? vz : NULL,
                      .species = species,
                      .radii = radii,
                      .masses = masses,
                      .n_species = 2};
    gr_error err = {0};
    ck_assert_int_eq(gr_obs_profile.sample(st, &p, 0.0, &err), GR_OK);
    /* a frame without species is refused */
    p.species = NULL;
    ck_assert_int_ne(gr_obs_profile.sample(st, &p, 1.0, &err), GR_OK);
    ck_assert_ptr_nonnull(strstr(err.message, "species"));
    return h_finish(&gr_obs_profile, st, &sc, "profile.csv", tab);
}

START_TEST(test_profile_mixture_by_hand)
{
    for (int dim = 2; dim <= 3; dim++) {
        h_table tab;
        cJSON *j = mixture_frame(dim, &tab);
        const int gc = dim == 3 ? 13 : 10, g1 = 1 + gc, g2 = 1 + 2 * gc; /* group offsets */
        const double slab = dim == 3 ? 1.0 * 2.0 * 2.0 : 1.0 * 2.0;
        const double a1 = dim == 3 ? 4.0 / 3.0 * M_PI * 1e-3 : M_PI * 0.01; /* grain areas */
        const double a2 = dim == 3 ? 4.0 / 3.0 * M_PI * 8e-3 : M_PI * 0.04;
        ck_assert_int_eq(tab.rows, 2);
        ck_assert_int_eq(tab.cols, 1 + 3 * gc);
        /* slab 0 (y < 1): grains 0 (species 1) and 1 (species 2); M = 4, P_x = -2, K_x = 4, so
         * u_x = -0.5, T_x = (4 - 4 / 4) / 2 = 1.5; P_y = 6, K_y = 12: u_y = 1.5, T_y = 1.5 */
        ck_assert_double_eq_tol(h_at(&tab, 0, 1), 2.0 / slab, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, 3), (a1 + a2) / slab, 1e-8);
        ck_assert_double_eq_tol(h_at(&tab, 0, 5), -0.5, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, 6), 1.5, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, 7), 1.5, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, 9), 1.5, 1e-12);
        if (dim == 3) { /* P_z = 10, K_z = 28, M = 4: u_z = 2.5, T_z = (28 - 25) / 2 */
            ck_assert_double_eq_tol(h_at(&tab, 0, 11), 2.5, 1e-12);
            ck_assert_double_eq_tol(h_at(&tab, 0, 12), 1.5, 1e-12);
        }
        /* per species in slab 0: one grain each, their own velocity, T = 0 */
        ck_assert_double_eq_tol(h_at(&tab, 0, g1), 1.0 / slab, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, g1 + 2), a1 / slab, 1e-8);
        ck_assert_double_eq_tol(h_at(&tab, 0, g1 + 4), 1.0, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, g1 + 6), 0.0, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, g2 + 2), a2 / slab, 1e-8);
        ck_assert_double_eq_tol(h_at(&tab, 0, g2 + 4), -1.0, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 0, g2 + 5), 2.0, 1e-12);
        /* slab 1: grain 2 alone (species 1); species 2 empty there: n = 0, no velocity */
        ck_assert_double_eq_tol(h_at(&tab, 1, 1), 1.0 / slab, 1e-12);
        ck_assert_double_eq_tol(h_at(&tab, 1, g1 + 4), 2.0, 1e-12);
        ck_assert_double_eq(h_at(&tab, 1, g2), 0.0);
        ck_assert(isnan(h_at(&tab, 1, g2 + 4)));
        const cJSON *pr = cJSON_GetObjectItem(j, "profile");
        ck_assert_double_eq(h_num(pr, "species", NULL), 2.0);
        const cJSON *h = cJSON_GetObjectItem(pr, "species_mean_position");
        ck_assert_double_eq_tol(cJSON_GetArrayItem(h, 0)->valuedouble, 0.85, 1e-12);
        ck_assert_double_eq_tol(cJSON_GetArrayItem(h, 1)->valuedouble, 0.4, 1e-12);
        ck_assert_ptr_nonnull(strstr(tab.columns, ",T_x_2,T_x_2_err,"));
        h_done(&tab, j);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("obs_structure");
    TCase *t = tcase_create("analysis");
    tcase_add_test(t, test_clusters_row_1d);
    tcase_add_test(t, test_clusters_row_2d);
    tcase_add_test(t, test_clusters_lattice_2d);
    tcase_add_test(t, test_clusters_mixture_pairs);
    tcase_add_test(t, test_pressure_mixture);
    tcase_add_test(t, test_pressure_distribution_hertz);
    tcase_add_test(t, test_pressure_distribution_spring);
    tcase_add_test(t, test_pressure_ideal_gas);
    tcase_add_test(t, test_pressure_overlap_2d);
    tcase_add_test(t, test_pressure_overlap_1d);
    tcase_add_test(t, test_pressure_hertz_2d);
    tcase_add_test(t, test_pressure_hertz_1d);
    tcase_add_test(t, test_profile_by_hand);
    tcase_add_test(t, test_profile_mixture_by_hand);
    tcase_add_test(t, test_vcorr_random);
    tcase_add_test(t, test_vcorr_pair);
    suite_add_tcase(s, t);
    return gr_test_run(s);
}
