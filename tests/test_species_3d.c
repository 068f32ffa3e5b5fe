/* Species in 3D (issue 35/36; src/core/kernels_poly.c poly_3d, integrators/verlet/step_poly.c;
 * docs/mixtures.md), with the verlet integrator:
 *
 * - a head-on collision of a light and a heavy sphere (and of two heavy ones) along a diagonal of
 *   the cube comes out with the scene's eps_n for every pair, momentum conserved to rounding;
 * - an oblique collision of unequal rotating spheres, out of every coordinate plane: momentum and
 *   angular momentum sum m_i r_i x v_i + I_i w_i conserved to rounding, the spin vectors parallel
 *   and in the ratio m_1 r_1 / (m_0 r_0) of each grain's own moment of inertia (2/5) m_i r_i^2,
 *   the contact point's tangential velocity scaled by the pair's law;
 * - the scene: masses from the density (4/3) pi r^3, the packing fraction from the actual radii,
 *   random placement keeping r_i + r_j apart; a driven rotating 3D gas's ledger closes with the
 *   tangential law's dissipation and the spins' energy sum I_i |w_i|^2 / 2;
 * - a checkpoint of a rotating 3D mixture continues bit for bit. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check_main.h"
#include "core/sim_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "sim_helpers.h"

/* Two spheres in a large periodic cube, no driving. */
static const char *pair_3d =
    "[system]\ndim = 3\nN = 2\nL = 0.2\n[placement]\nkind = cubic\nv0 = 0\n"
    "[driving]\nkind = none\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n"
    "[model]\nk_s = 5e4\neps_n = 0.7\n[integrator]\nsteps_per_contact = 100\n";

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Grain 0 at c, grain 1 at c + (d + 1e-4) u + b w (u, w orthonormal), velocities +-0.1 u; stepped
 * until they part. */
static void approach(gr_sim *s, const double u[3], const double w[3], double b)
{
    const double d = s->rad[0] + s->rad[1], along = sqrt(d * d - b * b) + 1e-4;
    double *q[3] = {s->x, s->y, s->z}, *v[3] = {s->vx, s->vy, s->vz};
    for (int a = 0; a < 3; a++) {
        q[a][0] = 0.1;
        q[a][1] = 0.1 + along * u[a] + b * w[a];
        v[a][0] = 0.1 * u[a];
        v[a][1] = -0.1 * u[a];
    }
    int touched = 0;
    for (int k = 0; k < 400000; k++) {
        step(s, 1);
        const double r[3] = {s->x[1] - s->x[0], s->y[1] - s->y[0], s->z[1] - s->z[0]};
        const double dist = sqrt(dot(r, r));
        touched |= dist < d;
        if (touched && dist > d) {
            break;
        }
    }
    ck_assert_msg(touched, "the spheres never met");
}

static void momentum(const gr_sim *s, double p[3])
{
    for (int a = 0; a < 3; a++) {
        const double *v = a == 0 ? s->vx : a == 1 ? s->vy : s->vz;
        p[a] = s->mass_i[0] * v[0] + s->mass_i[1] * v[1];
    }
}

/* The angular momentum about the origin, sum m r x v (+ I w when spinning), of the pair as it
 * starts (approach's positions and velocities for offset d / 2) or as it is now. */
static void start_angular_momentum(const double m[2], const double u[3], const double w[3],
                                   double d, double L[3])
{
    const double along = sqrt(d * d - 0.25 * d * d) + 1e-4;
    L[0] = L[1] = L[2] = 0.0;
    for (int i = 0; i < 2; i++) {
        double r[3], v[3];
        for (int a = 0; a < 3; a++) {
            r[a] = 0.1 + (i ? along * u[a] + 0.5 * d * w[a] : 0.0);
            v[a] = (i ? -0.1 : 0.1) * u[a];
        }
        L[0] += m[i] * (r[1] * v[2] - r[2] * v[1]);
        L[1] += m[i] * (r[2] * v[0] - r[0] * v[2]);
        L[2] += m[i] * (r[0] * v[1] - r[1] * v[0]);
    }
}

static void angular_momentum(const gr_sim *s, const double m[2], const double I[2], double L[3])
{
    L[0] = L[1] = L[2] = 0.0;
    for (int i = 0; i < 2; i++) {
        const double r[3] = {s->x[i], s->y[i], s->z[i]}, v[3] = {s->vx[i], s->vy[i], s->vz[i]};
        L[0] += m[i] * (r[1] * v[2] - r[2] * v[1]) + I[i] * s->wx[i];
        L[1] += m[i] * (r[2] * v[0] - r[0] * v[2]) + I[i] * s->wy[i];
        L[2] += m[i] * (r[0] * v[1] - r[1] * v[0]) + I[i] * s->omega[i];
    }
}

START_TEST(pair_restitution_3d)
{
    static const char *const fractions[] = {"species.fraction=0.5,0.5", "species.fraction=0,1"};
    static const char *const laws[] = {"model.normal=spring_dashpot", "model.normal=hertz"};
    const double u[3] = {1.0 / sqrt(3.0), 1.0 / sqrt(3.0), 1.0 / sqrt(3.0)},
                 w[3] = {1.0 / sqrt(2.0), -1.0 / sqrt(2.0), 0.0};
    for (int l = 0; l < 2; l++) {
        for (int f = 0; f < 2; f++) {
            const char *set[] = {fractions[f], laws[l]};
            gr_scene sc;
            load(&sc, pair_3d, set, 2);
            gr_sim *s = create(&sc);
            ck_assert_str_eq(gr_sim_kernel(s),
                             l ? "3d-verlet-list-species/hertz/no-noise"
                               : "3d-verlet-list-species/spring_dashpot/no-noise");
            double p0[3], p1[3];
            approach(s, u, w, 0.0);
            momentum(s, p1);
            p0[0] = p0[1] = p0[2] = (s->mass_i[0] - s->mass_i[1]) * 0.1 / sqrt(3.0);
            const double g[3] = {s->vx[1] - s->vx[0], s->vy[1] - s->vy[0], s->vz[1] - s->vz[0]};
            const double eps = dot(g, u) / 0.2;
            printf("3D head-on (%s, masses %g, %g kg): eps = %.5f\n", laws[l], s->mass_i[0],
                   s->mass_i[1], eps);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s: eps = %.5f, want 0.7", fractions[f], eps);
            for (int a = 0; a < 3; a++) {
                ck_assert_msg(fabs(p1[a] - p0[a]) < 1e-18, "momentum %d: %g -> %g", a, p0[a],
                              p1[a]);
            }
            gr_sim_free(s);
        }
    }
}
END_TEST

START_TEST(pair_rotation_3d)
{
    const char *set[] = {"model.tangential=tangential_dashpot", "model.eps_t=0.5",
                         "model.rotation=true"};
    gr_scene sc;
    load(&sc, pair_3d, set, 3);
    gr_sim *s = create(&sc);
    ck_assert(s->wx != NULL && s->inertia_i != NULL);
    const double q = sc.contact.inertia_factor;
    ck_assert(fabs(q - 0.4) < 1e-15);
    const double m[2] = {s->mass_i[0], s->mass_i[1]};
    const double I[2] = {q * m[0] * s->rad[0] * s->rad[0], q * m[1] * s->rad[1] * s->rad[1]};
    ck_assert(s->inertia_i[0] == I[0] && s->inertia_i[1] == I[1]);
    /* an approach along u = (2, 1, 2) / 3, offset along w = (1, -2, 0) / sqrt(5) by half d */
    const double u[3] = {2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0},
                 w[3] = {1.0 / sqrt(5.0), -2.0 / sqrt(5.0), 0.0};
    const double d = s->rad[0] + s->rad[1];
    double *q3[3] = {s->x, s->y, s->z}, *v3[3] = {s->vx, s->vy, s->vz};
    double *w3[3] = {s->wx, s->wy, s->omega};
    /* the angular momentum about the origin: sum m r x v + I w */
    double L0[3], L1[3], P0[3];
    start_angular_momentum(m, u, w, d, L0);
    for (int a = 0; a < 3; a++) {
        P0[a] = (m[0] - m[1]) * 0.1 * u[a];
    }
    approach(s, u, w, 0.5 * d);
    double P1[3];
    momentum(s, P1);
    angular_momentum(s, m, I, L1);
    const double Lmag = sqrt(dot(L0, L0));
    /* the spins: both torques are -a_i n x F_t, parallel, in the ratio a_0 / I_0 : a_1 / I_1 */
    const double want = m[1] * s->rad[1] / (m[0] * s->rad[0]);
    const double w0[3] = {s->wx[0], s->wy[0], s->omega[0]},
                 w1[3] = {s->wx[1], s->wy[1], s->omega[1]};
    const double ratio = sqrt(dot(w0, w0) / dot(w1, w1)),
                 cosine = dot(w0, w1) / sqrt(dot(w0, w0) * dot(w1, w1));
    /* the contact point's tangential velocity against the law's restitution with rotation */
    double rv[3], gv[3];
    for (int a = 0; a < 3; a++) {
        rv[a] = q3[a][1] - q3[a][0];
        gv[a] = v3[a][1] - v3[a][0];
    }
    const double dist = sqrt(dot(rv, rv)), a0 = dist * s->rad[0] / d, a1 = dist - a0;
    double n[3], W[3], gc[3];
    for (int a = 0; a < 3; a++) {
        n[a] = rv[a] / dist;
        W[a] = a0 * w3[a][0] + a1 * w3[a][1];
    }
    const double gn = dot(gv, n);
    gc[0] = gv[0] - gn * n[0] + n[1] * W[2] - n[2] * W[1];
    gc[1] = gv[1] - gn * n[1] + n[2] * W[0] - n[0] * W[2];
    gc[2] = gv[2] - gn * n[2] + n[0] * W[1] - n[1] * W[0];
    /* before: g = -0.2 u, normal at contact n0 = (along u + b w) / |.|, straight flight */
    const double n0u = sqrt(0.75), gn0 = -0.2 * n0u, gt0 = 0.2 * 0.5; /* |g_t| = 0.2 sin */
    const gr_contact_coeffs *cp = &s->cc_pair[s->species[0] * 2 + s->species[1]];
    const double law =
        cp->tangential_model->restitution_t(cp, cp->normal_model->impact(cp, -gn0), -gn0, gt0);
    const double gct = sqrt(dot(gc, gc));
    printf("3D rotating pair: |w_0| / |w_1| = %.15g (m_1 r_1 / (m_0 r_0) = %.15g, cos %.15f), "
           "angular momentum |%.3g| changed by (%.2g, %.2g, %.2g), |g_ct| ratio %.5f (the law: "
           "%.5f)\n",
           ratio, want, cosine, Lmag, L1[0] - L0[0], L1[1] - L0[1], L1[2] - L0[2], gct / gt0,
           fabs(law));
    ck_assert(dot(w0, w0) > 0.0);
    ck_assert_msg(fabs(ratio / want - 1.0) < 1e-9, "spin ratio %.15g, want %.15g", ratio, want);
    ck_assert_msg(cosine > 1.0 - 1e-12, "spins not parallel: cos %.17g", cosine);
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(L1[a] - L0[a]) < 1e-12 * Lmag, "angular momentum %d: %.17g -> %.17g", a,
                      L0[a], L1[a]);
        ck_assert_msg(fabs(P1[a] - P0[a]) < 1e-18, "momentum %d: %g -> %g", a, P0[a], P1[a]);
    }
    ck_assert_msg(fabs(gct / gt0 - fabs(law)) < 0.02, "|g_ct| ratio %.5f, want %.5f", gct / gt0,
                  fabs(law));
    gr_sim_free(s);
}
END_TEST

/* The history law (tangential_spring, Cundall-Strack with Coulomb limit mu) on the same oblique
 * rotating pair of unequal spheres: the vector spring in the tangent plane, the pair's k_t, each
 * grain's arm; momentum and angular momentum are kept, the spins come out parallel in the ratio
 * of a_i / I_i, and the ledger closes (the spring's energy and its losses booked). */
START_TEST(pair_history_3d)
{
    const char *set[] = {"model.tangential=tangential_spring", "model.mu=0.5",
                         "model.rotation=true"};
    gr_scene sc;
    load(&sc, pair_3d, set, 3);
    gr_sim *s = create(&sc);
    ck_assert(s->nl_hist != NULL && s->tgx != NULL);
    const double m[2] = {s->mass_i[0], s->mass_i[1]};
    const double I[2] = {s->inertia_i[0], s->inertia_i[1]};
    const double u[3] = {2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0},
                 w[3] = {1.0 / sqrt(5.0), -2.0 / sqrt(5.0), 0.0};
    const double d = s->rad[0] + s->rad[1];
    double L0[3], L1[3];
    start_angular_momentum(m, u, w, d, L0);
    approach(s, u, w, 0.5 * d);
    double P1[3];
    momentum(s, P1);
    angular_momentum(s, m, I, L1);
    const double w0[3] = {s->wx[0], s->wy[0], s->omega[0]},
                 w1[3] = {s->wx[1], s->wy[1], s->omega[1]};
    const double ratio = sqrt(dot(w0, w0) / dot(w1, w1)),
                 cosine = dot(w0, w1) / sqrt(dot(w0, w0) * dot(w1, w1));
    const double want = m[1] * s->rad[1] / (m[0] * s->rad[0]), Lmag = sqrt(dot(L0, L0));
    const gr_ledger l = gr_sim_ledger(s);
    printf("3D history pair: |w_0| / |w_1| = %.15g (want %.15g, cos %.15f), angular momentum "
           "changed by (%.2g, %.2g, %.2g) of %.3g, friction %.4g J, ledger residual %.3g J of %.3g "
           "J\n",
           ratio, want, cosine, L1[0] - L0[0], L1[1] - L0[1], L1[2] - L0[2], Lmag,
           l.dissipated_friction + l.dissipated_tangential,
           gr_ledger_residual(&l) - 0.5 * (m[0] + m[1]) * 0.01, 0.5 * (m[0] + m[1]) * 0.01);
    ck_assert(dot(w0, w0) > 0.0);
    ck_assert_msg(fabs(ratio / want - 1.0) < 1e-9 && cosine > 1.0 - 1e-12, "spins %.15g, cos %.17g",
                  ratio, cosine);
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(L1[a] - L0[a]) < 1e-12 * Lmag, "angular momentum %d: %.17g -> %.17g", a,
                      L0[a], L1[a]);
        ck_assert_msg(fabs(P1[a] - (m[0] - m[1]) * 0.1 * u[a]) < 1e-18, "momentum %d", a);
    }
    /* the ledger's initial energy is the creation's (at rest); the approach set K0 after */
    const double K0 = 0.5 * (m[0] + m[1]) * 0.01, res = gr_ledger_residual(&l) - K0;
    ck_assert_msg(fabs(res) < 1e-3 * K0, "ledger residual %g of %g J", res, K0);
    ck_assert(l.dissipated_friction + l.dissipated_tangential > 0.0);
    gr_sim_free(s);
}
END_TEST

/* Two species of one radius and one mass are one species: with the history law and rotation (and,
 * variant 1, rolling resistance) the mixture kernel (kernels_poly.c) follows the one-species 3D
 * kernel (kernels_3d.c) to rounding over a short stretch of a driven gas (summation orders differ,
 * so not bit for bit). */
START_TEST(history_equal_species_3d)
{
    static const char *gas =
        "[system]\ndim = 3\nN = 343\nL = 0.0253\nradius = 1.5e-3\nmass = 3.5e-5\n"
        "[placement]\nkind = cubic\nv0 = 0.1\n[model]\nk_s = 5e3\neps_n = 0.7\n"
        "tangential = tangential_spring\nmu = 0.5\nrotation = true\n[noise]\nD = 1e-8\n"
        "[integrator]\nsteps_per_contact = 20\n";
    const char *mix[] = {"model.rolling=rolling_friction", "model.mu_r=0.05",
                         "species.radius=1.5e-3, 1.5e-3", "species.mass=3.5e-5, 3.5e-5"};
    const int k = _i ? 0 : 2; /* variant 1: from the rolling law on */
    gr_scene one, two;
    load(&one, gas, mix + k, 2 - k);
    load(&two, gas, mix + k, 4 - k);
    gr_sim *a = create(&one), *b = create(&two);
    ck_assert(b->nl_hist != NULL && b->cc_pair != NULL && a->cc_pair == NULL);
    for (int i = 0; i < a->n; i++) { /* the same start: the lattice, and a's velocities (the
                                        * mixture's mass-weighted mean differs in the last bits) */
        ck_assert(a->x[i] == b->x[i] && a->y[i] == b->y[i] && a->z[i] == b->z[i]);
        b->vx[i] = a->vx[i];
        b->vy[i] = a->vy[i];
        b->vz[i] = a->vz[i];
    }
    /* a chaotic gas: rounding differences grow about threefold per 100 steps (1e-16 at 100,
     * 4e-13 at 600, 1e-7 m/s at 2000), so the comparison is early, after the first contacts */
    step(a, 600);
    step(b, 600);
    double worst = 0.0, held = 0.0;
    for (int i = 0; i < a->n; i++) {
        worst = fmax(worst, fabs(a->vx[i] - b->vx[i]) + fabs(a->vy[i] - b->vy[i]) +
                                fabs(a->vz[i] - b->vz[i]));
        worst = fmax(worst, 1.5e-3 * (fabs(a->wx[i] - b->wx[i]) + fabs(a->omega[i] - b->omega[i])));
    }
    const gr_ledger la = gr_sim_ledger(a), lb = gr_sim_ledger(b);
    held = lb.dissipated_friction;
    printf("3D history, two equal species against one: largest velocity difference %.3g m/s after "
           "600 steps; friction %.6g J against %.6g J\n",
           worst, lb.dissipated_friction, la.dissipated_friction);
    ck_assert(held > 0.0);
    ck_assert_msg(worst < 1e-11, "the mixture kernel departs from the one-species one by %g m/s",
                  worst);
    ck_assert_msg(fabs(lb.dissipated_friction / la.dissipated_friction - 1.0) < 1e-9,
                  "friction %.17g against %.17g J", lb.dissipated_friction, la.dissipated_friction);
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

/* The scene of a 3D mixture: density in kg/m^3, the packing fraction of the actual radii, random
 * placement with each pair r_i + r_j apart; a driven rotating gas's ledger closes. */
START_TEST(driven_gas_3d)
{
    const int quick =
        getenv("GRANULE_TEST_QUICK") && strcmp(getenv("GRANULE_TEST_QUICK"), "1") == 0;
    static const char *gas =
        "[system]\ndim = 3\nN = 300\npacking_fraction = 0.1\n[placement]\nkind = random\n"
        "v0 = 0.2\nomega0 = 50\n[species]\nradius = 1e-3, 2e-3\ndensity = 2500, 2500\n"
        "fraction = 0.6, 0.4\n[model]\nk_s = 5e4\neps_n = 0.7\ntangential = "
        "tangential_dashpot\neps_t = 0.5\nrotation = true\n[noise]\nD = 1e-9\n"
        "[integrator]\nsteps_per_contact = 20\n";
    gr_scene sc;
    load(&sc, gas, NULL, 0);
    ck_assert_int_eq(sc.species_count[0], 180);
    ck_assert_int_eq(sc.species_count[1], 120);
    const double vol = 4.0 / 3.0 * M_PI * (180 * 1e-9 + 120 * 8e-9);
    ck_assert_msg(fabs(vol / (sc.L * sc.L * sc.L) - 0.1) < 1e-12, "phi %g",
                  vol / (sc.L * sc.L * sc.L));
    gr_sim *s = create(&sc);
    int count[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        ck_assert(fabs(s->mass_i[i] / (2500 * 4.0 / 3.0 * M_PI * pow(s->rad[i], 3)) - 1) < 1e-15);
        count[s->species[i]]++;
    }
    ck_assert_int_eq(count[0], 180);
    ck_assert_int_eq(count[1], 120);
    /* random placement: every pair at least r_i + r_j apart (creation checks overlaps), and some
     * pair of small grains closer than the largest diameter */
    double closest = INFINITY;
    for (int i = 0; i < s->n; i++) {
        for (int j = i + 1; j < s->n; j++) {
            double r2 = 0.0;
            const double *q[3] = {s->x, s->y, s->z};
            for (int a = 0; a < 3; a++) {
                double dx = q[a][j] - q[a][i];
                dx -= s->L * rint(dx / s->L);
                r2 += dx * dx;
            }
            ck_assert(sqrt(r2) >= s->rad[i] + s->rad[j]);
            closest = fmin(closest, sqrt(r2) / (s->rad[i] + s->rad[j]));
        }
    }
    ck_assert_msg(closest < 2.0, "closest pair %g contact distances apart", closest);
    step(s, quick ? 2000 : 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("driven 3D gas: injected %.4g J, dissipated normal %.4g J, tangential %.4g J, "
           "rotational energy %.4g J, residual %.3g of the energy moved\n",
           l.injected, l.dissipated_normal, l.dissipated_tangential, l.rotational, res / moved);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    ck_assert(l.rotational > 0.0 && l.dissipated_tangential > 0.0 && l.dissipated_normal > 0.0);
    gr_sim_free(s);
}
END_TEST

/* A checkpoint of a rotating 3D mixture with friction (and with the history law) continues bit
 * for bit. */
START_TEST(restart_exact_3d)
{
    static const char *gas =
        "[system]\ndim = 3\nN = 100\npacking_fraction = 0.1\n[placement]\nkind = random\n"
        "v0 = 0.2\nomega0 = 50\n[species]\nradius = 1e-3, 2e-3\ndensity = 2500, 2500\n"
        "[model]\nk_s = 5e4\neps_n = 0.7\ntangential = sliding_friction\nmu = 0.3\n"
        "rotation = true\n[noise]\nD = 1e-9\n";
    /* and with the history law: each contact's spring vector is in the checkpoint */
    const char *spring[] = {"model.tangential=tangential_spring"};
    gr_scene sc;
    load(&sc, gas, spring, _i);
    assert_restart_exact(&sc, 3000, 1000);
}
END_TEST

static Suite *species_3d_suite(void)
{
    Suite *s = suite_create("species_3d");
    TCase *t = tcase_create("spheres");
    tcase_set_timeout(t, 300);
    tcase_add_test(t, pair_restitution_3d);
    tcase_add_test(t, pair_rotation_3d);
    tcase_add_test(t, pair_history_3d);
    tcase_add_loop_test(t, history_equal_species_3d, 0, 2);
    tcase_add_test(t, driven_gas_3d);
    tcase_add_loop_test(t, restart_exact_3d, 0, 2);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(species_3d_suite()); }
