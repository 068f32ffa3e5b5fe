/* pressure: the pressure tensor (stress with the sign of a pressure) of the
 * periodic system, P_ab = (1/V) [ sum_i M u_ia u_ib  +  sum_{pairs i<j} r_ij,a
 * F_ij,b ], kinetic part plus the collisional virial (Irving-Kirkwood /
 * Clausius), with V = L^3 (3D: the full symmetric 3x3 tensor, xx yy zz xy xz yz),
 * L^2 (2D) or the ring length L (1D, where P is a force), u
 * = v - <v>_frame (T of 2.19), r_ij = r_j - r_i under the minimum image and
 * F_ij the force of i on j. P = trace / dim. In 1D and 2D the ideal-gas limit
 * is P = n T with n = N / V and T = M <u_x^2> (per component: n M <|u|^2> / dim, in 3D
 * too; nT reports it).
 *
 * The contact force is the normal force F_ij = f_n n of the run's contact law,
 * computed by the force kernel's own law (gr_contact_virial, src/core/kernels.c:
 * the inlined law of models/list.h, e.g. the spring-dashpot F_n = k_s xi -
 * gamma_n g_n of 2.4-2.5, clamped to F_n >= 0 if the scene clamps) at the
 * frame's positions and velocities, so frames from snapshots are measured
 * alike; src/analysis holds no copy of any force law, only the pair search.
 * Tangential forces are left out (their laws need the contact history and
 * spins, which a frame does not hold; their virial is antisymmetric at first
 * order and small; the summary says so). Event-driven (hard-sphere) runs have
 * no force law: only the kinetic part is reported there.
 *
 * On a mixture of species lists each grain's kinetic term has its own mass, and a pair of species
 * (a, b) touches at r_i + r_j with that pair's coefficients (the setup's contact_pair, as the force
 * kernel has them); on a radius distribution each pair's coefficients are the reference pair's
 * scaled to its reduced mass and effective radius as the kernel scales them (gr_contact_size_scaled).
 * The equation of state (5.2) is one species' and is not compared.
 *
 * In 2D the summary compares with the mean-field equation of state (5.2),
 *     <|v|>^3 = (C_1 / phi) D d pi / (M^2 (2 - eps_n^2 - eps_t^2)),
 * by reporting the C_1 the measured mean speed implies (eps_t = 1 without a
 * tangential law), and the compressibility factor Z = P / (n T). Per-frame
 * values are time-averaged with block-averaging errors. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_cells.h"
#include "analysis/obs_util.h"
#include "granule/analysis.h"

/* 1D and 2D keep the first N_SERIES_2D series (their CSV, summary and checkpoint bytes as before
 * the 3D ones); 3D has all of them, written in the order `order_3d`. */
enum {
    KXX,
    KYY,
    KXY,
    CXX,
    CYY,
    CXY,
    P_TOTAL,
    NT,
    SPEED,
    N_SERIES_2D,
    KZZ = N_SERIES_2D,
    KXZ,
    KYZ,
    CZZ,
    CXZ,
    CYZ,
    N_SERIES
};
static const char *const series_name[N_SERIES] = {"kinetic_xx",
                                                  "kinetic_yy",
                                                  "kinetic_xy",
                                                  "collisional_xx",
                                                  "collisional_yy",
                                                  "collisional_xy",
                                                  "P",
                                                  "nT",
                                                  "mean_speed",
                                                  "kinetic_zz",
                                                  "kinetic_xz",
                                                  "kinetic_yz",
                                                  "collisional_zz",
                                                  "collisional_xz",
                                                  "collisional_yz"};
static const int order_2d[N_SERIES_2D] = {KXX, KYY, KXY, CXX, CYY, CXY, P_TOTAL, NT, SPEED};
static const int order_3d[N_SERIES] = {KXX, KYY, KZZ, KXY, KXZ,     KYZ, CXX,  CYY,
                                       CZZ, CXY, CXZ, CYZ, P_TOTAL, NT,  SPEED};

typedef struct pressure {
    int n, dim;
    double L, V, mass, d, phi, D, eps_n, eps_t;
    const char *law; /* the normal force law (NULL: none, kinetic part only) */
    gr_contact_coeffs cc;
    int ns;                     /* species of a mixture (0: one species) */
    gr_contact_coeffs *cc_pair; /* a mixture: pair (a, b)'s coefficients at [a * ns + b] */
    bool sizes;                 /* grains of their own radius and mass (lists or a distribution) */
    bool dist;                  /* a radius distribution: the reference pair's coefficients below */
    gr_contact_coeffs size_cc;
    double size_m_ref, size_r_ref;
    const gr_particles *p; /* the frame being visited */
    double mean[3], w[6];  /* mean velocity; the frame's virial xx, yy, xy (3D: zz, xz, yz too) */
    int queued;            /* contacts waiting in `pairs` for gr_contact_virial */
    gr_contact_pair pairs[256];
    int64_t contacts, frames;
    gr_blocking b[N_SERIES];
    gr_cells cells;
} pressure;

static int series_count(const pressure *s) { return s->dim == 3 ? N_SERIES : N_SERIES_2D; }

static const int *series_order(const pressure *s) { return s->dim == 3 ? order_3d : order_2d; }

static const char *pressure_unit(const pressure *s)
{
    return s->dim == 3 ? "N m-2" : s->dim == 2 ? "N m-1" : "N";
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)params_block;
    pressure *s = state;
    gr_cells_own(s, &s->cells);
    s->n = setup->N;
    s->dim = setup->dim;
    s->L = setup->L;
    s->V = setup->dim == 3   ? setup->L * setup->L * setup->L
           : setup->dim == 2 ? setup->L * setup->L
                             : setup->L;
    s->mass = setup->mass;
    s->d = 2.0 * setup->radius;
    s->phi = setup->N * M_PI * setup->radius * setup->radius / (setup->L * setup->L); /* (2.24) */
    s->D = setup->D;
    s->eps_n = setup->eps_n;
    s->eps_t = setup->tangential ? setup->eps_t : 1.0;
    s->cc = setup->contact;
    s->law = gr_contact_virial(&s->cc, s->d, NULL, 0, s->w);
    s->sizes = setup->sizes;
    if (setup->sizes && setup->n_species < 2) {
        s->dist = true;
        s->size_cc = setup->size_contact;
        s->size_m_ref = setup->size_m_ref;
        s->size_r_ref = setup->size_r_ref;
    }
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        s->ns = setup->n_species;
        s->cc_pair = gr_obs_calloc(s, (size_t)(s->ns * s->ns), sizeof *s->cc_pair);
        int rc = gr_obs_alloc_ok(s, err);
        if (rc) {
            return rc;
        }
        memcpy(s->cc_pair, setup->contact_pair, (size_t)(s->ns * s->ns) * sizeof *s->cc_pair);
    }
    return GR_OK;
}

/* One contact of the frame: queued for the kernel's law, which adds r_ij F_ij to the virial in
 * the order the pairs are visited. */
static void flush(pressure *s)
{
    gr_contact_virial(&s->cc, s->d, s->pairs, s->queued, s->w);
    s->queued = 0;
}

/* A 3D contact: the kernel's law on the pair seen along its normal (r_ij = (|r_ij|, 0), g = (g .
 * n, 0)) gives |r_ij| f_n in its xx slot; the tensor is |r_ij| f_n n_a n_b. */
static void contact_3d(pressure *s, const gr_contact_coeffs *cc, double d, int i, int j,
                       const double dr[3], double r2)
{
    const gr_particles *p = s->p;
    const double dist = sqrt(r2), n[3] = {dr[0] / dist, dr[1] / dist, dr[2] / dist};
    const double g[3] = {p->vx[j] - p->vx[i], p->vy[j] - p->vy[i], p->vz[j] - p->vz[i]};
    const gr_contact_pair along = {.dx = dist, .gx = g[0] * n[0] + g[1] * n[1] + g[2] * n[2]};
    double rf[3] = {0.0, 0.0, 0.0};
    gr_contact_virial(cc, d, &along, 1, rf);
    s->w[0] += rf[0] * n[0] * n[0];
    s->w[1] += rf[0] * n[1] * n[1];
    s->w[2] += rf[0] * n[0] * n[1];
    s->w[3] += rf[0] * n[2] * n[2];
    s->w[4] += rf[0] * n[0] * n[2];
    s->w[5] += rf[0] * n[1] * n[2];
}

static void contact(int i, int j, const double dr[3], double r2, void *user)
{
    pressure *s = user;
    const gr_particles *p = s->p;
    if (r2 == 0.0) {
        return;
    }
    if (s->sizes) { /* a mixture: the pair's own contact distance and coefficients */
        const double d = p->radii[i] + p->radii[j];
        if (r2 >= d * d) {
            return;
        }
        gr_contact_coeffs scaled;
        const gr_contact_coeffs *cc = &scaled;
        if (s->dist) {
            const double mi = p->masses[i], mj = p->masses[j];
            gr_contact_size_scaled(&s->size_cc, s->size_m_ref, s->size_r_ref, mi * mj / (mi + mj),
                                   p->radii[i] * p->radii[j] / d, &scaled);
        } else {
            cc = &s->cc_pair[p->species[i] * s->ns + p->species[j]];
        }
        if (p->dim == 3) {
            contact_3d(s, cc, d, i, j, dr, r2);
        } else {
            const gr_contact_pair one = {.dx = dr[0],
                                         .dy = dr[1],
                                         .gx = p->vx[j] - p->vx[i],
                                         .gy = p->dim == 2 ? p->vy[j] - p->vy[i] : 0.0};
            gr_contact_virial(cc, d, &one, 1, s->w);
        }
        s->contacts++;
        return;
    }
    if (p->dim == 3) {
        contact_3d(s, &s->cc, s->d, i, j, dr, r2);
        s->contacts++;
        return;
    }
    s->pairs[s->queued++] = (gr_contact_pair){.dx = dr[0],
                                              .dy = dr[1],
                                              .gx = p->vx[j] - p->vx[i],
                                              .gy = p->dim == 2 ? p->vy[j] - p->vy[i] : 0.0};
    if (s->queued == (int)(sizeof s->pairs / sizeof s->pairs[0])) {
        flush(s);
    }
    s->contacts++;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    pressure *s = state;
    int bad = gr_obs_check_frame("pressure", p, s->n, err);
    if (!bad && s->ns) {
        bad = gr_obs_frame_species("pressure", p, s->ns, s->n, NULL, err);
    }
    if (!bad && s->sizes && !(p->radii && p->masses)) {
        bad = GR_FAIL(err, GR_EINVAL,
                      "pressure: a mixture's frame without the grains' radii and "
                      "masses");
    }
    if (bad) {
        return bad;
    }
    double k[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, speed = 0.0;
    gr_obs_mean_velocity(p, s->mean);
    if (s->sizes) { /* a mixture: relative to the centre of mass's velocity */
        double M = 0.0, P[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < p->n; i++) {
            M += p->masses[i];
            P[0] += p->masses[i] * p->vx[i];
            P[1] += p->dim >= 2 ? p->masses[i] * p->vy[i] : 0.0;
            P[2] += p->dim == 3 ? p->masses[i] * p->vz[i] : 0.0;
        }
        for (int c = 0; c < 3; c++) {
            s->mean[c] = P[c] / M;
        }
    }
    for (int i = 0; i < p->n; i++) {
        double ux = p->vx[i] - s->mean[0], uy = p->dim >= 2 ? p->vy[i] - s->mean[1] : 0.0;
        const double m = s->sizes ? p->masses[i] : s->mass; /* a mixture: each grain's own */
        k[0] += m * ux * ux;
        k[1] += m * uy * uy;
        k[2] += m * ux * uy;
        if (p->dim == 3) {
            double uz = p->vz[i] - s->mean[2];
            k[3] += m * uz * uz;
            k[4] += m * ux * uz;
            k[5] += m * uy * uz;
            speed += sqrt(ux * ux + uy * uy + uz * uz);
            continue;
        }
        speed += sqrt(ux * ux + uy * uy);
    }
    for (int q = 0; q < 6; q++) {
        s->w[q] = 0.0;
    }
    if (s->law) {
        s->p = p;
        s->queued = 0;
        double cut = s->d;
        if (s->sizes) { /* grains of their own sizes: the frame's largest contact distance */
            cut = 0.0;
            for (int i = 0; i < p->n; i++) {
                cut = fmax(cut, 2.0 * p->radii[i]);
            }
        }
        int rc = gr_cells_pairs(&s->cells, p, fmin(cut, 0.5 * s->L), contact, s, err);
        if (rc) {
            return rc;
        }
        flush(s);
    }
    double v[N_SERIES] = {k[0] / s->V,    k[1] / s->V,    k[2] / s->V,
                          s->w[0] / s->V, s->w[1] / s->V, s->w[2] / s->V};
    v[P_TOTAL] = (v[KXX] + v[KYY] + v[CXX] + v[CYY]) / s->dim;
    v[NT] = (k[0] + k[1]) / s->dim / s->V; /* n T, T = M <u^2> / dim (2.19) */
    v[SPEED] = speed / p->n;
    if (p->dim == 3) {
        v[KZZ] = k[3] / s->V;
        v[KXZ] = k[4] / s->V;
        v[KYZ] = k[5] / s->V;
        v[CZZ] = s->w[3] / s->V;
        v[CXZ] = s->w[4] / s->V;
        v[CYZ] = s->w[5] / s->V;
        v[P_TOTAL] = (v[KXX] + v[KYY] + v[KZZ] + v[CXX] + v[CYY] + v[CZZ]) / 3.0;
        v[NT] = (k[0] + k[1] + k[3]) / 3.0 / s->V;
    }
    for (int q = 0; q < series_count(s); q++) {
        gr_blocking_add(&s->b[q], v[q]);
    }
    s->frames++;
    return GR_OK;
}

static void rows(FILE *f, const void *ctx)
{
    const pressure *s = ctx;
    for (int o = 0; o < series_count(s); o++) {
        const int q = series_order(s)[o];
        fprintf(f, "%s,%.10g,%.6g,%s\n", series_name[q], gr_blocking_mean(&s->b[q]),
                gr_obs_stderr(&s->b[q]), q == SPEED ? "m s-1" : pressure_unit(s));
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    pressure *s = state;
    cJSON *j = gr_obs_summary(out, "pressure", "pressure.csv");
    cJSON_AddNumberToObject(j, "frames", (double)s->frames);
    cJSON_AddStringToObject(j, "unit",
                            s->dim == 3   ? "Pa (N/m^2)"
                            : s->dim == 2 ? "N/m (force per unit length, 2D pressure)"
                                          : "N (1D pressure)");
    for (int o = 0; o < series_count(s); o++) {
        const int q = series_order(s)[o];
        char key[64];
        gr_obs_add_number(j, series_name[q], gr_blocking_mean(&s->b[q]));
        snprintf(key, sizeof key, "%s_error", series_name[q]);
        gr_obs_add_number(j, key, gr_obs_stderr(&s->b[q]));
    }
    double P = gr_blocking_mean(&s->b[P_TOTAL]), nT = gr_blocking_mean(&s->b[NT]);
    gr_obs_add_number(j, "Z", nT > 0.0 ? P / nT : (double)NAN);
    gr_obs_add_number(j, "contacts_per_frame",
                      s->frames ? (double)s->contacts / s->frames : (double)NAN);
    char law[160];
    const bool sd = s->law && strcmp(s->law, "spring_dashpot") == 0;
    snprintf(law, sizeof law, "normal %s force (%s%s%s); tangential forces left out",
             sd ? "spring-dashpot" : s->law, sd ? "2.4-2.5" : "models/", sd ? "" : s->law,
             sd ? "" : ".h");
    cJSON_AddStringToObject(
        j, "virial", s->law ? law : "none: the scene has no contact force law (kinetic part only)");
    if (s->dim == 2 && !s->sizes) { /* (5.2) is one species' */
        double v = gr_blocking_mean(&s->b[SPEED]);
        double rhs =
            s->D * s->d * M_PI /
            (s->phi * s->mass * s->mass * (2.0 - s->eps_n * s->eps_n - s->eps_t * s->eps_t));
        cJSON *e = cJSON_AddObjectToObject(j, "eos_5_2");
        gr_obs_add_number(e, "mean_speed_cubed", v * v * v);
        gr_obs_add_number(e, "rhs_over_C1", rhs);
        gr_obs_add_number(e, "C1", rhs > 0.0 && isfinite(rhs) ? v * v * v / rhs : (double)NAN);
        gr_obs_add_number(e, "C1_error",
                          rhs > 0.0 && isfinite(rhs)
                              ? 3.0 * v * v * gr_obs_stderr(&s->b[SPEED]) / rhs
                              : (double)NAN);
        cJSON_AddStringToObject(e, "equation",
                                "<|v|>^3 = (C_1/phi) D d pi / (M^2 (2 - eps_n^2 - eps_t^2)) (5.2)");
    }
    const gr_obs_table t = {
        .name = "pressure.csv",
        .what = s->dim == 3 ? "pressure tensor P_ab = (sum_i M u_a u_b + sum_pairs r_a F_b) / "
                              "V (3D: V = L^3, the symmetric 3x3 tensor), "
                              "kinetic and collisional parts, total P = trace / 3, n T, and "
                              "the mean speed (m/s); "
                              "block-averaging errors over frames"
                            : "pressure tensor P_ab = (sum_i M u_a u_b + sum_pairs r_a F_b) / "
                              "V (V = L^2 in 2D, L in 1D), "
                              "kinetic and collisional parts, total P = trace / dim, n T, and "
                              "the mean speed (m/s); "
                              "block-averaging errors over frames",
        .columns = "quantity [],value [@unit],stderr [@unit],unit []",
        .rows = rows,
        .ctx = s,
        .png = s->frames > 0 ? "pressure.png" : NULL,
        .plot = s->dim == 3 /* the 12 tensor components, P and nT */
                    ? "set style data histograms\nset style histogram errorbars gap "
                      "1\nset style fill solid 0.5\n"
                      "set ylabel 'pressure (Pa)'\nset title 'Pressure: kinetic and "
                      "collisional parts (3D)'\n"
                      "set xtics rotate by -30 noenhanced\nplot 'pressure.csv' skip 1 every "
                      "::0::13 using 2:3:xtic(1) title 'P_{ab}'"
                    : "set style data histograms\nset style histogram errorbars gap "
                      "1\nset style fill solid 0.5\n"
                      "set ylabel 'pressure (N/m in 2D, N in 1D)'\nset title 'Pressure: kinetic "
                      "and collisional parts'\n"
                      "set xtics rotate by -30 noenhanced\nplot 'pressure.csv' skip 1 every "
                      "::0::7 using 2:3:xtic(1) title 'P_{ab}'",
    };
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    pressure *s = state;
    gr_blob_io_i64(io, &s->frames);
    gr_blob_io_i64(io, &s->contacts);
    gr_obs_io_blockings(io, s->b, series_count(s));
    return GR_OK;
}

const gr_observable_type gr_obs_pressure = {
    .name = "pressure",
    .summary = "pressure and stress tensor (3x3 in 3D), kinetic + collisional virial; 2D: "
               "C_1 of the equation of state (5.2)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = NULL,
    .n_params = 0,
    .state_size = sizeof(pressure),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
