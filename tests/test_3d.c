/* Spheres in a periodic cube ([system] dim = 3; docs/three-dimensions.md):
 *
 * - the three-component noise: components 0 and 1 are the 2D normals bit for bit, component 2
 *   new ones, the same whatever the batch (first, n) and equal to gr_noise_normal1 (retries
 *   included), uncorrelated with the others, standard normal;
 * - placements: cubic, fcc (at phi = 0.7) and random give the packing fraction asked for, without overlaps;
 * - the kernel against every pair by brute force with the same normal law;
 * - eps_n = 1 without noise conserves energy (a gas of spheres, and a pair collision, whose
 *   error falls about 4x when dt halves) and momentum;
 * - a head-on and an oblique pair collision lose 1 - eps_n^2 of the normal relative kinetic
 *   energy and conserve momentum, for spring_dashpot (clamped and not) and hertz;
 * - the ledger closes with the random force and dissipation;
 * - the random force injects dim D / M per particle per second (3 D / M, not the 2 D / M of 2D);
 * - the driven steady state's T agrees with the Enskog energy balance of smooth hard spheres
 *   (gr_steady_T_enskog_3d) within 5 %;
 * - the same run on 1, 2 and 3 threads (forces, ledger), and an exact restart from saved bytes;
 * - the library refuses what 3D cannot run (the scene's refusals: test_bad_inputs.sh). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/mean_field.h"
#include "core/sim_internal.h"
#include "granule/noise.h"
#include "granule/scene.h"
#include "granule/model.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

/* The thesis's spheres (Table 2.2) at phi = 0.1, noise on: the docs/scenes/rfm-3d.ini system. */
static const char *gas =
    "[system]\ndim = 3\nN = 343\npacking_fraction = 0.1\n[placement]\nkind = cubic\nv0 = 0.1\n"
    "[model]\nnormal = spring_dashpot\nk_s = 5e5\neps_n = 0.9\n[noise]\nD = 1e-8\n"
    "[integrator]\ndt = 1e-6\n";

/* ---- noise ---------------------------------------------------------------------------------- */

START_TEST(test_noise_three_components)
{
    const int n = 20001; /* odd: the last pair is half used */
    const uint64_t seed = 12345, step = 77;
    double *a3 = malloc(sizeof(double) * 3 * (size_t)n),
           *a2 = malloc(sizeof(double) * 2 * (size_t)n);
    double *part = malloc(sizeof(double) * 3 * (size_t)n);
    gr_noise_normals(seed, GR_STREAM_NOISE, step, 0, n, 3, a3);
    gr_noise_normals(seed, GR_STREAM_NOISE, step, 0, n, 2, a2);
    /* components 0, 1: the 2D normals (so the x, y noise of a 3D run is a 2D run's) */
    for (int i = 0; i < n; i++) {
        ck_assert(memcmp(&a3[3 * i], &a2[2 * i], 2 * sizeof(double)) == 0);
    }
    /* any batch: three pieces with odd boundaries give the same bits */
    const int cut[4] = {0, 333, 10007, n};
    for (int k = 0; k < 3; k++) {
        gr_noise_normals(seed, GR_STREAM_NOISE, step, (uint32_t)cut[k], cut[k + 1] - cut[k], 3,
                         part + 3 * cut[k]);
    }
    ck_assert(memcmp(part, a3, sizeof(double) * 3 * (size_t)n) == 0);
    /* the scalar reference, rejected variates (about 1.5%) included */
    for (int i = 0; i < n; i += 1) {
        for (int c = 0; c < 3; c++) {
            const double z = gr_noise_normal1(seed, GR_STREAM_NOISE, step, (uint32_t)i, c);
            ck_assert_msg(memcmp(&z, &a3[3 * i + c], sizeof z) == 0, "id %d c %d: %g vs %g", i, c,
                          z, a3[3 * i + c]);
        }
    }
    /* component 2: standard normal, uncorrelated with 0 and 1 and with the same ids' normals of
     * other steps (independent counters), never equal to them */
    double m = 0.0, v = 0.0, c0 = 0.0, c1 = 0.0;
    int equal = 0;
    for (int i = 0; i < n; i++) {
        const double z = a3[3 * i + 2];
        m += z;
        v += z * z;
        c0 += z * a3[3 * i];
        c1 += z * a3[3 * i + 1];
        equal += z == a3[3 * i] || z == a3[3 * i + 1];
    }
    m /= n;
    v = v / n - m * m;
    const double se = 1.0 / sqrt((double)n);
    VERBOSE("z: mean %g var %g corr %g %g (se %g)\n", m, v, c0 / n, c1 / n, se);
    ck_assert_msg(fabs(m) < 5 * se, "mean %g", m);
    ck_assert_msg(fabs(v - 1.0) < 5 * sqrt(2.0) * se, "variance %g", v);
    ck_assert_msg(fabs(c0 / n) < 5 * se && fabs(c1 / n) < 5 * se, "correlations %g %g", c0 / n,
                  c1 / n);
    ck_assert_int_eq(equal, 0);
    free(a3);
    free(a2);
    free(part);
}
END_TEST

/* Recorded values of the third component (as test_noise.c's test_golden for the first two): a
 * change here changes the noise of every 3D run, so it must be deliberate. The last one lies in
 * the tail (|x| > R = 3.654), drawn on the retry counters (bit 30 of word 3). */
START_TEST(test_noise_golden_z)
{
    static const struct {
        uint64_t seed;
        uint32_t stream;
        uint64_t step;
        uint32_t id;
        double x;
    } golden[] = {
        {UINT64_C(0x0), 0, UINT64_C(0x0), 0u, -0x1.dffc02e56e0cap-1},
        {UINT64_C(0x0), 0, UINT64_C(0x0), 1u, -0x1.8c2332ada77a5p+0},
        {UINT64_C(0x243f6a8885a308d3), 0, UINT64_C(0x1), 2u, 0x1.2941636a66ecbp+0},
        {UINT64_C(0x1), 2, UINT64_C(0x100000000), 4000000000u, -0x1.5eb88b00dc125p+0},
        {UINT64_C(0x7), 0, UINT64_C(0x3), 2695u, -0x1.19026e03a4c6ep+2},
    };
    for (size_t i = 0; i < sizeof golden / sizeof golden[0]; i++) {
        const double x =
            gr_noise_normal1(golden[i].seed, golden[i].stream, golden[i].step, golden[i].id, 2);
        double v[3 * 3];
        gr_noise_normals(golden[i].seed, golden[i].stream, golden[i].step,
                         golden[i].id > 0 ? golden[i].id - 1 : 0, 3, 3, v);
        const double y = v[3 * (golden[i].id > 0 ? 1 : 0) + 2];
        ck_assert_msg(x == golden[i].x && y == golden[i].x, "golden %zu: %a, %a, recorded %a", i, x,
                      y, golden[i].x);
    }
}
END_TEST

/* ---- placement and kernel -------------------------------------------------------------------- */

static double sphere_phi(const gr_sim *s)
{
    return s->n * M_PI * s->d * s->d * s->d / 6.0 / (s->L * s->L * s->L);
}

START_TEST(test_placements)
{
    static const char *const kinds[] = {"placement.kind=cubic", "placement.kind=random",
                                        "placement.kind=fcc"};
    static const char *const phis[] = {"system.packing_fraction=0.25",
                                       "system.packing_fraction=0.25",
                                       "system.packing_fraction=0.7"};
    for (int k = 0; k < 3; k++) {
        gr_scene *sc = malloc(sizeof *sc);
        const char *set[] = {kinds[k], phis[k], "system.N=500"};
        load(sc, gas, set, 3);
        gr_sim *s = create(sc); /* gr_sim_new refuses overlaps (gr_check_overlaps) */
        ck_assert_double_eq_tol(sphere_phi(s), k == 2 ? 0.7 : 0.25, 1e-12);
        for (int i = 0; i < s->n; i++) {
            ck_assert(s->z[i] >= 0.0 && s->z[i] < s->L && s->x[i] >= 0.0 && s->y[i] < s->L);
        }
        /* the default follows dim: cubic */
        load(sc, "[system]\ndim = 3\nN = 27\npacking_fraction = 0.1\n", NULL, 0);
        ck_assert_int_eq(sc->placement, GR_PLACE_CUBIC);
        gr_sim_free(s);
        free(sc);
    }
}
END_TEST

/* The conservative forces (the springs: F - G) and the elastic energy of every pair by brute
 * force with the kernel's own normal law. (The dashpots saw the half-step velocities, which the
 * closing half kick has moved on since.) */
static void brute_force(const gr_sim *s, double *f, double *elastic)
{
    const double L = s->L;
    *elastic = 0.0;
    memset(f, 0, sizeof(double) * 3 * (size_t)s->n);
    for (int i = 0; i < s->n; i++) {
        for (int j = i + 1; j < s->n; j++) {
            double r[3] = {s->x[j] - s->x[i], s->y[j] - s->y[i], s->z[j] - s->z[i]};
            const double g[3] = {s->vx[j] - s->vx[i], s->vy[j] - s->vy[i], s->vz[j] - s->vz[i]};
            for (int a = 0; a < 3; a++) {
                r[a] -= L * rint(r[a] / L);
            }
            const double dist = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            if (dist >= s->d) {
                continue;
            }
            const double g_n = (g[0] * r[0] + g[1] * r[1] + g[2] * r[2]) / dist;
            double f_d, e;
            const double fn = gr_kernel_normal(s, &s->cc, s->d - dist, g_n, &f_d, &e);
            *elastic += s->cc.e_scale * e;
            for (int a = 0; a < 3; a++) {
                f[3 * j + a] += (fn - f_d) * r[a] / dist;
                f[3 * i + a] -= (fn - f_d) * r[a] / dist;
            }
        }
    }
}

START_TEST(test_kernel_brute_force)
{
    static const char *const laws[] = {"model.normal=spring_dashpot", "model.normal=hertz"};
    for (int k = 0; k < 2; k++) {
        gr_scene *sc = malloc(sizeof *sc);
        const char *set[] = {"placement.kind=random", "system.packing_fraction=0.3",
                             "placement.v0=2", laws[k]};
        load(sc, gas, set, 4);
        gr_sim *s = create(sc);
        step(s, 200); /* contacts form */
        double *f = malloc(sizeof(double) * 3 * (size_t)s->n), el;
        brute_force(s, f, &el);
        double fmax = 0.0;
        for (int i = 0; i < 3 * s->n; i++) {
            fmax = fmax > fabs(f[i]) ? fmax : fabs(f[i]);
        }
        ck_assert_msg(fmax > 0.0 && s->last.new_contacts >= 0, "no contacts to compare");
        const double *mine[3] = {s->fx, s->fy, s->fz}, *nc[3] = {s->gx, s->gy, s->gz};
        for (int i = 0; i < s->n; i++) {
            for (int a = 0; a < 3; a++) {
                ck_assert_msg(fabs(mine[a][i] - nc[a][i] - f[3 * i + a]) <= 1e-12 * fmax,
                              "%s: particle %d axis %d: %g vs %g", laws[k], i, a,
                              mine[a][i] - nc[a][i], f[3 * i + a]);
            }
        }
        ck_assert_double_eq_tol(s->elastic, el, 1e-12 * el);
        free(f);
        gr_sim_free(s);
        free(sc);
    }
}
END_TEST

/* ---- energy ---------------------------------------------------------------------------------- */

static double mechanical(gr_sim *s)
{
    gr_ledger l = gr_sim_ledger(s);
    return l.kinetic + l.elastic;
}

static void momentum3(const gr_sim *s, double p[3])
{
    p[0] = p[1] = p[2] = 0.0;
    for (int i = 0; i < s->n; i++) {
        p[0] += s->mass * s->vx[i];
        p[1] += s->mass * s->vy[i];
        p[2] += s->mass * s->vz[i];
    }
}

/* The largest relative energy error of an elastic gas over `t` seconds at steps_per_contact spc. */
static double elastic_gas_error(double spc, double t, int64_t *collisions)
{
    gr_scene *sc = malloc(sizeof *sc);
    char spc_set[64];
    snprintf(spc_set, sizeof spc_set, "integrator.steps_per_contact=%g", spc);
    const char *set[] = {"model.eps_n=1", "noise.D=0", "placement.v0=2",
                         "system.packing_fraction=0.3", spc_set};
    load(sc, gas, set, 5);
    sc->dt = 0.0; /* steps_per_contact sets it */
    gr_sim *s = create(sc);
    const double e0 = mechanical(s);
    double p0[3], p1[3], worst = 0.0;
    momentum3(s, p0);
    const int64_t steps = (int64_t)llround(t / s->dt), every = steps / 50;
    for (int64_t k = 0; k < steps; k += every) {
        step(s, every);
        const double e = fabs(mechanical(s) - e0) / e0;
        worst = e > worst ? e : worst;
    }
    momentum3(s, p1);
    const double scale = s->mass * s->n * 2.0; /* |p| of the particles' speeds */
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(p1[a] - p0[a]) < 1e-12 * scale, "momentum %d: %g -> %g", a, p0[a],
                      p1[a]);
    }
    *collisions = s->collisions;
    gr_sim_free(s);
    free(sc);
    return worst;
}

START_TEST(test_elastic_energy_conserved)
{
    int64_t c1, c2;
    const double t = quick() ? 2e-3 : 5e-3;
    const double e1 = elastic_gas_error(25, t, &c1), e2 = elastic_gas_error(50, t, &c2);
    VERBOSE("elastic gas: error %g (%lld collisions) at 25 steps per contact, %g (%lld) at 50\n",
            e1, (long long)c1, e2, (long long)c2);
    ck_assert_msg(c1 > 100 && c2 > 100, "too few collisions: %lld, %lld", (long long)c1,
                  (long long)c2);
    ck_assert_msg(e1 < 1e-3 && e2 < 1e-3, "energy error %g, %g at 25, 50 steps per contact", e1,
                  e2);
}
END_TEST

/* Two spheres in a large box, 1 moving at `speed` along x towards 0 with the impact parameter
 * (0, by, bz) (in diameters). Returns the kinetic energy lost over the normal relative kinetic
 * energy at impact; checks momentum. */
static double pair_loss(const char *law, const char *clamp, const char *eps, double spc,
                        double speed, double by, double bz)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {law, clamp, "system.N=2", "system.L=0.05", "noise.D=0", eps};
    load(sc, gas, set, 6);
    sc->dt = 0.0;
    sc->steps_per_contact = spc;
    gr_sim *s = create(sc);
    const double d = s->d, c = 0.5 * s->L;
    const double r[2][3] = {{c - 0.6 * d, c, c}, {c + 0.6 * d, c + by * d, c + bz * d}};
    double *pos[3] = {s->x, s->y, s->z}, *vel[3] = {s->vx, s->vy, s->vz};
    for (int i = 0; i < 2; i++) {
        for (int a = 0; a < 3; a++) {
            pos[a][i] = r[i][a];
            vel[a][i] = 0.0;
        }
    }
    s->vx[1] = -speed;
    gr_error err = {0};
    ck_assert_int_eq(gr_neighbours_build(s, &err), GR_OK);
    gr_force_report rep;
    gr_forces(s, &rep);
    ck_assert_double_eq(rep.elastic, 0.0);
    /* the normal relative velocity at impact: the line of centres when they touch */
    const double b2 = (by * by + bz * bz) * d * d, dx = sqrt(d * d - b2);
    const double g_n = speed * dx / d, m12 = 0.5 * s->mass;
    const double e0 = 0.5 * s->mass * speed * speed, en = 0.5 * m12 * g_n * g_n;
    double p0[3], p1[3];
    momentum3(s, p0);
    int touched = 0;
    for (int k = 0; k < 1000000 && !(touched && s->elastic == 0.0); k++) {
        step(s, 1);
        touched |= s->elastic > 0.0;
    }
    ck_assert_msg(touched && s->collisions == 1, "%s: no single collision", law);
    momentum3(s, p1);
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(p1[a] - p0[a]) < 1e-14 * s->mass * speed, "momentum %d: %g -> %g", a,
                      p0[a], p1[a]);
    }
    const double lost = e0 - mechanical(s);
    gr_sim_free(s);
    free(sc);
    return lost / en;
}

START_TEST(test_pair_collisions)
{
    static const char *const laws[][2] = {{"model.normal=spring_dashpot", "model.clamp=false"},
                                          {"model.normal=spring_dashpot", "model.clamp=true"},
                                          {"model.normal=hertz", "model.clamp=false"}};
    static const double impact[][2] = {{0.0, 0.0}, {0.3, 0.4}, {0.0, -0.6}};
    for (int l = 0; l < 3; l++) {
        for (int k = 0; k < 3; k++) {
            const double f = pair_loss(laws[l][0], laws[l][1], "model.eps_n=0.8", 100, 0.5,
                                       impact[k][0], impact[k][1]);
            VERBOSE("%s %s, impact (%g, %g) d: loss / normal energy %.6f (1 - eps^2 = %.6f)\n",
                    laws[l][0], laws[l][1], impact[k][0], impact[k][1], f, 1.0 - 0.8 * 0.8);
            ck_assert_msg(fabs(f - (1.0 - 0.8 * 0.8)) < 0.01 * (1.0 - 0.8 * 0.8),
                          "%s %s impact (%g, %g): lost %g of the normal energy, want %g",
                          laws[l][0], laws[l][1], impact[k][0], impact[k][1], f, 1.0 - 0.8 * 0.8);
        }
    }
    /* eps_n = 1: the energy comes back, to second order in dt */
    const double e1 = pair_loss(laws[0][0], laws[0][1], "model.eps_n=1", 25, 0.5, 0.3, 0.4),
                 e2 = pair_loss(laws[0][0], laws[0][1], "model.eps_n=1", 50, 0.5, 0.3, 0.4);
    VERBOSE("eps_n = 1: relative energy error %g at 25 steps per contact, %g at 50\n", e1, e2);
    ck_assert_msg(fabs(e1) < 1e-2 && fabs(e2) < fabs(e1) / 3.0, "eps_n = 1: errors %g, %g", e1, e2);
}
END_TEST

/* The ledger closes: symmetrised noise with the linear law, centre-of-mass resets (their energy
 * booked as removed_com) with hertz. The residual is velocity Verlet's energy error, second order
 * in dt: hertz (t_c = 1.03e-5 s at the reference speed) gives 3.6e-3, 9.0e-4, 2.3e-4 of the
 * energy turned over at dt = 1e-6, 5e-7, 2.5e-7 s, so it runs at 5e-7 s (20 steps per contact). */
START_TEST(test_ledger_closes)
{
    static const char *const variants[][3] = {
        {"noise.mode=symmetrised", "model.normal=spring_dashpot", "integrator.dt=1e-6"},
        {"noise.mode=com", "model.normal=hertz", "integrator.dt=5e-7"}};
    for (int k = 0; k < 2; k++) {
        gr_scene *sc = malloc(sizeof *sc);
        const char *set[] = {"placement.v0=1", variants[k][0], variants[k][1], variants[k][2],
                             "noise.com_interval=1e-4"};
        load(sc, gas, set, 5);
        gr_sim *s = create(sc);
        step(s, quick() ? 10000 : 20000); /* at least 100 collisions at dt = 5e-7 s too */
        gr_ledger l = gr_sim_ledger(s);
        const double res = gr_ledger_residual(&l), scale = l.injected + gr_ledger_dissipated(&l);
        VERBOSE("ledger (%s, %s): injected %g dissipated %g removed_com %g kinetic %g elastic %g "
                "residual %g (%g)\n",
                variants[k][0], variants[k][1], l.injected, gr_ledger_dissipated(&l), l.removed_com,
                l.kinetic, l.elastic, res, res / scale);
        ck_assert_msg(l.injected > 0.0 && l.dissipated_normal > 0.0 && s->collisions > 100,
                      "%s: injected %g, dissipated %g, %lld collisions", variants[k][0], l.injected,
                      l.dissipated_normal, (long long)s->collisions);
        ck_assert(k == 0 ? l.removed_com == 0.0 : l.removed_com > 0.0);
        ck_assert_msg(fabs(res) < 5e-3 * scale, "%s: residual %g of %g", variants[k][0], res,
                      scale);
        gr_sim_free(s);
        free(sc);
    }
}
END_TEST

/* The random force's mean injection, dim D / M per particle per second (N - 1 degrees of freedom
 * per component with the symmetrised mode), within 5 standard errors, which exclude 2 D / M. */
START_TEST(test_injection_rate)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.packing_fraction=0.01", "system.N=1000", "noise.D=1e-7"};
    load(sc, gas, set, 3);
    gr_sim *s = create(sc);
    const int64_t steps = quick() ? 1000 : 4000;
    const double M = s->mass, dt = s->dt, D = s->params.D, amp2 = 2.0 * D * dt / (M * M);
    double var = 0.0; /* of the injected energy: M^2 amp^2 sum |v|^2 + (M/2)^2 2 amp^4 3 (N - 1) */
    for (int64_t k = 0; k < steps; k++) {
        double v2 = 0.0;
        for (int i = 0; i < s->n; i++) {
            v2 += s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i] + s->vz[i] * s->vz[i];
        }
        var += M * M * amp2 * v2 + 0.25 * M * M * 2.0 * amp2 * amp2 * 3.0 * (s->n - 1);
        step(s, 1);
    }
    const double t = steps * dt, want = 3.0 * D / M * (s->n - 1) * t, se = sqrt(var);
    const double want_2d = 2.0 * D / M * (s->n - 1) * t;
    VERBOSE("injected %g J, expected %g +- %g (2D's %g)\n", s->injected, want, se, want_2d);
    ck_assert_msg(fabs(want - want_2d) > 10.0 * se, "the test cannot tell 3 D / M from 2 D / M");
    ck_assert_msg(fabs(s->injected - want) < 5.0 * se, "injected %g, expected %g +- %g",
                  s->injected, want, se);
    gr_sim_free(s);
    free(sc);
}
END_TEST

/* The driven steady state against kinetic theory: T (2.19) averaged over 0.2 s after 0.1 s of
 * warm-up (about 3 relaxation times 1/zeta), N = 500 at phi = 0.1, eps_n = 0.9: measured 0.98-1.01
 * of the Enskog balance (soft contacts, a2, finite N and time); 2D's injection 2 D / M would give
 * 0.76 of it, a wrong chi 0.7. */
START_TEST(test_steady_state_enskog)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.N=500", "placement.v0=1"};
    load(sc, gas, set, 2);
    gr_sim *s = create(sc);
    const int64_t warm = 100000, run = 200000, every = 1000;
    step(s, warm);
    double T = 0.0;
    int n = 0;
    for (int64_t k = 0; k < run; k += every, n++) {
        step(s, every);
        T += gr_sim_temperature(s);
    }
    T /= n;
    const double pred = gr_steady_T_enskog_3d(sc->D, sc->mass, 2.0 * sc->radius,
                                              sc->packing_fraction, sc->contact.eps_n, sc->N);
    VERBOSE("steady state: T = %g, Enskog %g (ratio %g), %lld collisions\n", T, pred, T / pred,
            (long long)s->collisions);
    ck_assert_msg(fabs(T / pred - 1.0) < 0.05, "T = %g, Enskog balance %g", T, pred);
    gr_sim_free(s);
    free(sc);
}
END_TEST

START_TEST(test_threads_and_restart)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.N=2197", "placement.v0=1"}; /* three blocks of particles */
    load(sc, gas, set, 2);
    /* the normal law alone on 1, 2, 3 threads, a restart: dense and fast enough for contacts and
     * list rebuilds */
    const char *dense[] = {"system.N=2197", "placement.v0=5", "system.packing_fraction=0.35"};
    gr_scene *sd = malloc(sizeof *sd);
    load(sd, gas, dense, 3);
    assert_threads_exact(sd, 400, 170);
    free(sd);
    assert_restart_exact(sc, 400, 170);
    free(sc);
}
END_TEST

/* The library (gr_sim_new) refuses what 3D cannot run, for callers without a scene. */
START_TEST(test_library_refusals)
{
    gr_scene *sc = malloc(sizeof *sc);
    load(sc, gas, NULL, 0);
    gr_sim_params p;
    gr_scene_sim_params(sc, &p);
    const gr_sim_params ok = p;
    gr_sim *s = NULL;
    gr_error err = {0};
    p.gravity[1] = -9.81; /* along a periodic axis (walls and gravity: test_walls_3d.c) */
    ck_assert_int_eq(gr_sim_new(&p, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "[gravity] gy") &&
                      strstr(err.message, "[boundary] y = walls"),
                  "%s", err.message);
    p = ok;
    p.integrator = gr_integrator_find("hybrid"); /* steps spheres; not with a history spring */
    p.contact.rotation = true;
    p.tangential = gr_model_find("tangential_spring");
    ck_assert_ptr_nonnull(p.tangential);
    ck_assert_int_eq(gr_sim_new(&p, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "history") && strstr(err.message, "hybrid"), "%s",
                  err.message);
    p = ok;
    p.dim = 4;
    ck_assert_int_eq(gr_sim_new(&p, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "allowed: 1, 2 or 3"), "%s", err.message);
    p = ok;
    ck_assert_int_eq(gr_sim_new(&p, &s, &err), GR_OK);
    gr_sim_free(s);
    free(sc);
}
END_TEST

static Suite *three_d_suite(void)
{
    Suite *s = suite_create("3d");
    TCase *tc = tcase_create("spheres");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, test_noise_three_components);
    tcase_add_test(tc, test_noise_golden_z);
    tcase_add_test(tc, test_placements);
    tcase_add_test(tc, test_kernel_brute_force);
    tcase_add_test(tc, test_elastic_energy_conserved);
    tcase_add_test(tc, test_pair_collisions);
    tcase_add_test(tc, test_ledger_closes);
    tcase_add_test(tc, test_injection_rate);
    if (!quick()) { /* statistics: the release pass's; its code runs in the tests around it */
        tcase_add_test(tc, test_steady_state_enskog);
    }
    tcase_add_test(tc, test_threads_and_restart);
    tcase_add_test(tc, test_library_refusals);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(three_d_suite()); }
