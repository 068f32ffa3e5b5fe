/* Tests of species (src/core/species.c, kernels_poly.c, integrators/verlet/step_poly.c;
 * docs/mixtures.md), below the scene-level test of the driven mixture (tests/test_species.sh):
 *
 * - every pair of species has the scene's eps_n: a head-on collision of a light and a heavy rod
 *   (1D) and of two heavy ones comes out with eps_n (spring_dashpot, hertz), momentum conserved;
 * - hertz's stiffness scales with the effective radius, sqrt(R_ij / R_11), and the time step
 *   resolves the shortest contact of all pairs;
 * - the random force heats each grain by d D / m_i: an ideal gas of two species gains kinetic
 *   energy in the ratio of the inverse masses (4 for masses 1:4), not equally;
 * - the species are dealt by the seed (counts exact, the same for the same seed);
 * - a mixture's ledger closes, and a state given as arrays with species is refused;
 * - a continuous radius distribution (uniform, lognormal): radii, masses, packing fraction, every
 *   pair's eps_n and the ledger;
 * - tangential laws and rotation (2D): an oblique collision of unequal discs with the pair's eps_t,
 *   momentum and angular momentum conserved, spins in the ratio of each grain's own moment of
 *   inertia; driven gases' ledgers;
 * - the history law (tangential_spring, linear and Mindlin) with the pair's own coefficients, its
 *   springs' energy in the ledger, and an exact restart with springs held;
 * - rolling resistance with each pair's R_ij and reduced moment of inertia;
 * - the Langevin bath (equipartition of an elastic mixture) and the com mode's reset with the
 *   masses;
 * - tangential laws, rotation and rolling with a radius distribution (coefficients scaled). */
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
#include "test_env.h"

/* Two rods on a long ring, no driving. */
static const char *pair_1d =
    "[system]\ndim = 1\nN = 2\nL = 1\n[placement]\nkind = uniform\nv0 = 0\n"
    "[driving]\nkind = none\n[species]\nradius = 1e-3, 2e-3\n"
    "mass = 1e-5, 4e-5\n";

/* The restitution of a head-on collision of grains 0 and 1 approaching at 0.2 m/s. */
static double collide(gr_sim *s, double *p_before, double *p_after)
{
    const double gap = s->rad[0] + s->rad[1] + 1e-4;
    s->x[0] = 0.3;
    s->x[1] = 0.3 + gap;
    s->vx[0] = 0.1;
    s->vx[1] = -0.1;
    *p_before = s->mass_i[0] * s->vx[0] + s->mass_i[1] * s->vx[1];
    int touched = 0;
    for (int k = 0; k < 200000; k++) {
        step(s, 1);
        const double g = s->x[1] - s->x[0];
        touched |= g < s->rad[0] + s->rad[1];
        if (touched && g > s->rad[0] + s->rad[1]) {
            break;
        }
    }
    ck_assert_msg(touched, "the rods never met");
    *p_after = s->mass_i[0] * s->vx[0] + s->mass_i[1] * s->vx[1];
    return (s->vx[1] - s->vx[0]) / 0.2;
}

START_TEST(pair_restitution)
{
    static const char *const laws[][2] = {{"model.normal=spring_dashpot", "model.eps_n=0.7"},
                                          {"model.normal=hertz", "model.eps_n=0.7"}};
    static const char *const fractions[] = {"species.fraction=0.5,0.5", "species.fraction=0,1"};
    for (int l = 0; l < 2; l++) {
        for (int f = 0; f < 2; f++) {
            const char *set[] = {laws[l][0], laws[l][1], fractions[f]};
            gr_scene sc;
            load(&sc, pair_1d, set, 3);
            gr_sim *s = create(&sc);
            double p0, p1;
            const double eps = collide(s, &p0, &p1);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s, %s: eps = %.5f, want 0.7", laws[l][0],
                          fractions[f], eps);
            ck_assert_msg(fabs(p1 - p0) < 1e-18, "momentum %g -> %g", p0, p1);
            gr_sim_free(s);
        }
    }
}
END_TEST

/* Tangential laws without history with species (2D, no rotation, kernels_poly.c): an oblique
 * collision of a light and a heavy disc keeps sum m_i v_i to rounding, and its tangential
 * relative velocity comes out scaled by the law's restitution for the pair's own coefficients
 * (gr_model.restitution_t of cc_pair, prepared with the pair's reduced mass: eps_t; the
 * lightest pair's damping on this pair gives 0.58). Then a driven gas's ledger closes with
 * the law's dissipation in its own column. */
static const char *pair_2d =
    "[system]\ndim = 2\nN = 2\nL = 0.2\n[placement]\nkind = uniform\nv0 = 0\n"
    "[driving]\nkind = none\n[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n"
    "[model]\nk_s = 5e4\neps_n = 0.7\ntangential = tangential_dashpot\neps_t = 0.5\n"
    "[integrator]\nsteps_per_contact = 100\n";

/* Grains 0 and 1 of s at impact parameter d/2, approaching at (0.1, 0) and (-0.1, 0) m/s, stepped
 * until they part; the unit normal at contact (from 0 to 1; straight flight until then) in n. */
static void oblique(gr_sim *s, double n[2])
{
    const double d = s->rad[0] + s->rad[1], b = 0.5 * d;
    s->x[0] = 0.05;
    s->y[0] = 0.1;
    s->x[1] = 0.05 + sqrt(d * d - b * b) + 1e-4;
    s->y[1] = 0.1 + b;
    s->vx[0] = 0.1;
    s->vx[1] = -0.1;
    s->vy[0] = s->vy[1] = 0.0;
    n[0] = sqrt(d * d - b * b) / d;
    n[1] = b / d;
    int touched = 0;
    for (int k = 0; k < 400000; k++) {
        step(s, 1);
        const double dx = s->x[1] - s->x[0], dy = s->y[1] - s->y[0];
        const double r = sqrt(dx * dx + dy * dy);
        touched |= r < d;
        if (touched && r > d) {
            break;
        }
    }
    ck_assert_msg(touched, "the discs never met");
}

/* The scene of driven_gas: 200 grains of pair_2d's species driven by the random force (rotating:
 * spun up by omega0), law: a further setting (NULL: none). */
static void gas_scene(gr_scene *sc, bool rotating, const char *law)
{
    const char *gas[8] = {"system.N=200",       "system.L=0.1", "placement.v0=0.2",
                          "driving.kind=rfm",   "noise.D=1e-9", "model.rotation=true",
                          "placement.omega0=50"};
    const int n = rotating ? 7 : 5;
    if (law) {
        gas[n] = law;
    }
    load(sc, pair_2d, gas, n + (law != NULL));
}

/* gas_scene's gas, 20000 steps: the ledger closes to 2e-3 of the energy moved; returns it. */
static gr_ledger driven_gas(bool rotating, const char *law)
{
    gr_scene sc;
    gas_scene(&sc, rotating, law);
    gr_sim *s = create(&sc);
    step(s, 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("driven gas%s%s: dissipated normal %.4g J, tangential %.4g J, friction %.4g J, "
           "rotational energy %.4g J, residual %.3g of the energy moved\n",
           rotating ? " (rotating)" : "", law ? law : "", l.dissipated_normal,
           l.dissipated_tangential, l.dissipated_friction, l.rotational, res / moved);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    gr_sim_free(s);
    return l;
}

START_TEST(pair_tangential)
{
    gr_scene sc;
    load(&sc, pair_2d, NULL, 0);
    gr_sim *s = create(&sc);
    const double m0 = s->mass_i[0], m1 = s->mass_i[1];
    const double px0 = m0 * 0.1 - m1 * 0.1;
    double n[2];
    oblique(s, n);
    /* the normal and tangent at contact */
    const double nx = n[0], ny = n[1], tx = ny, ty = -nx;
    const double gn0 = -0.2 * nx, gt0 = -0.2 * tx; /* g = v_1 - v_0 = (-0.2, 0) */
    const double gx = s->vx[1] - s->vx[0], gy = s->vy[1] - s->vy[0];
    const double gt1 = gx * tx + gy * ty, gn1 = gx * nx + gy * ny;
    const int a = s->species[0], c1 = s->species[1];
    const gr_contact_coeffs *cp = &s->cc_pair[a * 2 + c1];
    const gr_model *tm = cp->tangential_model;
    const double want = tm->restitution_t(cp, cp->normal_model->impact(cp, -gn0), -gn0, fabs(gt0));
    printf("oblique pair (masses %g, %g kg): g_t ratio %.5f, the pair's law %.5f; g_n ratio "
           "%.5f\n",
           m0, m1, gt1 / gt0, want, -gn1 / gn0);
    ck_assert_msg(fabs(gt1 / gt0 - want) < 0.01, "g_t ratio %.5f, want %.5f", gt1 / gt0, want);
    const double px1 = m0 * s->vx[0] + m1 * s->vx[1], py1 = m0 * s->vy[0] + m1 * s->vy[1];
    ck_assert_msg(fabs(px1 - px0) < 1e-18 && fabs(py1) < 1e-18, "momentum (%g, %g) from %g", px1,
                  py1, px0);
    gr_sim_free(s);
    /* a driven gas: the ledger closes, the tangential law's dissipation in its column */
    const gr_ledger l = driven_gas(false, NULL);
    ck_assert(l.dissipated_tangential > 0.05 * l.dissipated_normal);
}
END_TEST

/* oblique() with rotating discs (I_i = s->inertia_i): the angular momentum sum
 * m_i r_i x v_i + I_i w_i before (L0) and after (L1), the contact point's tangential velocity
 * after over before (ratio, the arms a_i = |r_ij| r_i / (r_i + r_j)), the restitution the pair's
 * law gives for it (want: gr_model.restitution_t of cc_pair; a distribution: of the reference
 * pair's coefficients s->cc) and the approach (gn0, gt0). */
typedef struct spin_out {
    double L0, L1, ratio, want, gn0, gt0;
} spin_out;

static spin_out spin_collision(gr_sim *s)
{
    const double d = s->rad[0] + s->rad[1], b = 0.5 * d;
    const double m[2] = {s->mass_i[0], s->mass_i[1]}, I[2] = {s->inertia_i[0], s->inertia_i[1]};
    spin_out o;
    /* the start (oblique's positions and velocities, no spin): L = m (x v_y - y v_x), y = 0.1
     * and 0.1 + b, v_x = +-0.1 */
    o.L0 = m[0] * (-0.1 * 0.1) + m[1] * (-(0.1 + b) * -0.1);
    double n[2];
    oblique(s, n);
    const double nx = n[0], ny = n[1], tx = ny, ty = -nx;
    o.gn0 = -0.2 * nx;
    o.gt0 = -0.2 * tx;
    o.L1 = 0.0;
    for (int i = 0; i < 2; i++) {
        o.L1 += m[i] * (s->x[i] * s->vy[i] - s->y[i] * s->vx[i]) + I[i] * s->omega[i];
    }
    const double dx = s->x[1] - s->x[0], dy = s->y[1] - s->y[0], r = sqrt(dx * dx + dy * dy);
    const double a0 = r * s->rad[0] / d, a1 = r - a0;
    const double gx = s->vx[1] - s->vx[0], gy = s->vy[1] - s->vy[0];
    o.ratio = (gx * tx + gy * ty + a0 * s->omega[0] + a1 * s->omega[1]) / o.gt0;
    /* a radius distribution: the reference pair's law (prepared in full for its own M and R),
     * whose eps_t at a given speed every pair shares when its coefficients are scaled right */
    const gr_contact_coeffs *cp =
        s->cc_pair ? &s->cc_pair[s->species[0] * 2 + s->species[1]] : &s->cc;
    o.want = cp->tangential_model->restitution_t(cp, cp->normal_model->impact(cp, -o.gn0), -o.gn0,
                                                 fabs(o.gt0));
    return o;
}

/* Rotation with species (2D, kernels_poly.c, step_poly.c): the same oblique collision with
 * rotating discs. The contact point splits |r_ij| as r_0 : r_1, so the spin torques a_i f_t are
 * in the ratio of the radii at every step and the spins end in the ratio
 * w_0 / w_1 = (r_0 / I_0) / (r_1 / I_1) = m_1 r_1 / (m_0 r_0) of each grain's own moment of
 * inertia q m_i r_i^2 (to rounding; one moment for both would give r_0 / r_1 instead); the
 * angular momentum sum m_i r_i x v_i + I_i w_i is conserved to rounding; the contact point's
 * tangential velocity comes out scaled by the law's restitution with rotation; the ledger of a
 * driven rotating gas closes with the spins' energy sum I_i w_i^2 / 2. */
START_TEST(pair_rotation)
{
    const char *rot[] = {"model.rotation=true"};
    gr_scene sc;
    load(&sc, pair_2d, rot, 1);
    gr_sim *s = create(&sc);
    const double m[2] = {s->mass_i[0], s->mass_i[1]}, q = sc.contact.inertia_factor;
    const double I[2] = {q * m[0] * s->rad[0] * s->rad[0], q * m[1] * s->rad[1] * s->rad[1]};
    ck_assert(fabs(s->inertia_i[0] / I[0] - 1.0) < 1e-15 &&
              fabs(s->inertia_i[1] / I[1] - 1.0) < 1e-15);
    const spin_out o = spin_collision(s);
    const double ratio = s->omega[0] / s->omega[1],
                 ratio_want = m[1] * s->rad[1] / (m[0] * s->rad[0]);
    printf("rotating pair: w_0 / w_1 = %.15g (m_1 r_1 / (m_0 r_0) = %.15g), angular momentum "
           "%.3g -> %.3g, contact point g_t ratio %.5f (the law: %.5f)\n",
           ratio, ratio_want, o.L0, o.L1, o.ratio, o.want);
    ck_assert(s->omega[0] != 0.0);
    ck_assert_msg(fabs(ratio / ratio_want - 1.0) < 1e-9, "spin ratio %.15g, want %.15g", ratio,
                  ratio_want);
    ck_assert_msg(fabs(o.L1 - o.L0) < 1e-12 * fabs(o.L0), "angular momentum %.17g -> %.17g", o.L0,
                  o.L1);
    ck_assert_msg(fabs(o.ratio - o.want) < 0.02, "g_ct ratio %.5f, want %.5f", o.ratio, o.want);
    gr_sim_free(s);
    const gr_ledger l = driven_gas(true, NULL);
    ck_assert(l.rotational > 0.0 && l.dissipated_tangential > 0.0);
}
END_TEST

/* The history law with species (tangential_spring, 2D, kernels_poly.c): the oblique collision of
 * pair_rotation with rotating discs, linear (spring_dashpot) and Mindlin (hertz): the contact
 * point's tangential velocity comes out scaled by the law's restitution for the pair's own k_t
 * and m_t (gr_model.restitution_t of cc_pair), the angular momentum sum m_i r_i x v_i + I_i w_i is
 * conserved to rounding, and the spring is forgotten when the discs part. A driven rotating gas's
 * ledger closes with the springs' energy and the slips' losses, and a restart from the saved
 * state, springs held, is the uninterrupted run bit for bit. */
START_TEST(pair_spring)
{
    static const char *const laws[][3] = {
        {"model.normal=spring_dashpot", "model.mindlin=false", "model.kt_ratio=0.2857"},
        {"model.normal=hertz", "model.mindlin=true", "model.k_h=1e7"}};
    for (int l = 0; l < 2; l++) {
        const char *set[] = {"model.rotation=true",
                             "model.tangential=tangential_spring",
                             "model.mu=0.3",
                             laws[l][0],
                             laws[l][1],
                             laws[l][2]};
        gr_scene sc;
        load(&sc, pair_2d, set, 6);
        gr_sim *s = create(&sc);
        ck_assert_msg(s->nl_hist != NULL, "no history store");
        const spin_out o = spin_collision(s);
        const gr_contact_coeffs *cp = &s->cc_pair[s->species[0] * 2 + s->species[1]];
        /* this pair with species 0's spring (its k_t, Mindlin's km: hertz scales them with the
         * pair's effective radius), what a kernel reading the wrong pair would give */
        gr_contact_coeffs wrong = *cp;
        memcpy(wrong.law_t, s->cc_pair[0].law_t, sizeof wrong.law_t);
        const double other = wrong.tangential_model->restitution_t(
            &wrong, wrong.normal_model->impact(&wrong, -o.gn0), -o.gn0, fabs(o.gt0));
        printf("spring pair (%s): contact point g_t ratio %.5f, the pair's law %.5f (species 0's "
               "spring on it: %.5f); angular momentum %.17g -> %.17g\n",
               laws[l][0], o.ratio, o.want, other, o.L0, o.L1);
        ck_assert_msg(fabs(o.ratio - o.want) < 0.01, "g_ct ratio %.5f, want %.5f", o.ratio, o.want);
        ck_assert_msg(fabs(o.L1 - o.L0) < 1e-12 * fabs(o.L0), "angular momentum %.17g -> %.17g",
                      o.L0, o.L1);
        ck_assert_msg(s->omega[0] != 0.0 && s->omega[1] != 0.0, "no spin");
        for (int p = 0; p < s->nl_start[s->n]; p++) {
            ck_assert_msg(s->nl_hist[p] == 0.0, "a spring kept after the contact ended");
        }
        gr_sim_free(s);
    }
    /* the gas's ledger with the springs' energy and losses (the law books as friction) */
    const gr_ledger l = driven_gas(true, "model.tangential=tangential_spring");
    ck_assert(l.rotational > 0.0 && l.dissipated_friction > 0.0);
    /* an exact restart of a denser gas with springs held (the state's bytes carry the history) */
    const char *dense[] = {
        "system.N=200",     "system.L=0.06",       "placement.v0=0.2",
        "driving.kind=rfm", "noise.D=1e-9",        "model.rotation=true",
        "model.mu=0.3",     "placement.omega0=50", "model.tangential=tangential_spring"};
    gr_scene sc;
    load(&sc, pair_2d, dense, 9);
    gr_sim *a = create(&sc);
    const int64_t first = quick() ? 1000 : 5000;
    step(a, first);
    int live = 0;
    for (int p = 0; p < a->nl_start[a->n]; p++) {
        live += a->nl_hist[p] != 0.0;
    }
    printf("restart with %d live springs\n", live);
    ck_assert_msg(live > 0, "no live springs at the save: the restart tests nothing");
    step(a, first);
    gr_sim *c = restarted(&sc, 2 * first, first, 1, 1);
    assert_same_state(a, c);
    gr_sim_free(a);
    gr_sim_free(c);
}
END_TEST

/* Rolling resistance with species (rolling_friction, 2D, kernels_poly.c): a head-on collision of
 * a light and a heavy disc spinning at w_0 = 100 and w_1 = -50 rad/s, eps_t = 1 (no tangential
 * force), so only
 * the rolling couple turns them. Its angular impulse is J = min(mu_r R_ij int |F_n| dt, I_ij |dw_0|)
 * (R_ij = r_0 r_1 / (r_0 + r_1), I_ij = I_0 I_1 / (I_0 + I_1)): the spins' energy loss is
 * J |dw_0| - J^2 / (2 I_ij) (the law's spin_loss with the pair's R_ij and 2 I_ij for one
 * species' I), sum I_i w_i is conserved to rounding, and with mu_r = 1e9 the rolling is arrested:
 * both discs end with the spin (I_0 w_0 + I_1 w_1) / (I_0 + I_1). A driven gas's ledger closes. */
START_TEST(pair_rolling)
{
    for (int arrest = 0; arrest < 2; arrest++) {
        const char *set[] = {"model.rotation=true", "model.eps_t=1",
                             "model.rolling=rolling_friction",
                             arrest ? "model.mu_r=1e9" : "model.mu_r=0.02"};
        gr_scene sc;
        load(&sc, pair_2d, set, 4);
        gr_sim *s = create(&sc);
        const double d = s->rad[0] + s->rad[1];
        const double I[2] = {s->inertia_i[0], s->inertia_i[1]};
        const double w0[2] = {100.0, -50.0};
        s->x[0] = 0.05;
        s->x[1] = 0.05 + d + 1e-4;
        s->y[0] = s->y[1] = 0.1;
        s->vx[0] = 0.1;
        s->vx[1] = -0.1;
        s->vy[0] = s->vy[1] = 0.0;
        s->omega[0] = w0[0];
        s->omega[1] = w0[1];
        int touched = 0;
        for (int k = 0; k < 400000; k++) {
            step(s, 1);
            touched |= s->x[1] - s->x[0] < d;
            if (touched && s->x[1] - s->x[0] > d) {
                break;
            }
        }
        ck_assert_msg(touched, "the discs never met");
        const gr_contact_coeffs *cp = &s->cc_pair[s->species[0] * 2 + s->species[1]];
        /* int |F_n| dt of the pair's law at the approach speed 0.2 m/s (its tensile end counts) */
        const double p_n = cp->m12 * cp->normal_model->impact(cp, 0.2).impulse_abs * 0.2;
        const double R = s->rad[0] * s->rad[1] / d, Iij = I[0] * I[1] / (I[0] + I[1]);
        const double dw0 = w0[0] - w0[1];
        const double want = cp->rolling_model->spin_loss(cp, p_n, R, 2.0 * Iij, dw0);
        const double e0 = 0.5 * (I[0] * w0[0] * w0[0] + I[1] * w0[1] * w0[1]);
        const double e1 =
            0.5 * (I[0] * s->omega[0] * s->omega[0] + I[1] * s->omega[1] * s->omega[1]);
        const double L0 = I[0] * w0[0] + I[1] * w0[1], L1 = I[0] * s->omega[0] + I[1] * s->omega[1];
        printf("rolling pair (mu_r %s): spins %.6g, %.6g rad/s, spin energy lost %.6e J, the law "
               "%.6e J (R_ij, I_ij); sum I w %.17g -> %.17g\n",
               arrest ? "1e9" : "0.02", s->omega[0], s->omega[1], e0 - e1, want, L0, L1);
        ck_assert_msg(fabs((e0 - e1) / want - 1.0) < 2.5e-3, "spin loss %.8e J, the law %.8e J",
                      e0 - e1, want);
        ck_assert_msg(fabs(L1 - L0) < 1e-13 * fabs(I[0] * w0[0]), "sum I w %.17g -> %.17g", L0, L1);
        if (arrest) {
            const double w = L0 / (I[0] + I[1]);
            ck_assert_msg(fabs(s->omega[0] - w) < 1e-9 * fabs(w0[0]) &&
                              fabs(s->omega[1] - w) < 1e-9 * fabs(w0[0]),
                          "arrested rolling: spins %.17g %.17g, want %.17g", s->omega[0],
                          s->omega[1], w);
        } else {
            ck_assert_msg(s->omega[0] - s->omega[1] > 0.0, "the rolling reversed");
        }
        gr_sim_free(s);
    }
    /* a driven rotating gas with the dashpot and rolling resistance: the ledger closes, the
     * couples' work in the friction column */
    const gr_ledger l = driven_gas(true, "model.rolling=rolling_friction");
    ck_assert(l.dissipated_friction > 0.0 && l.dissipated_tangential > 0.0);
}
END_TEST

/* The Langevin bath with species (step_poly.c): every grain feels the drag -m_i v / tau and the
 * noise that holds it at the bath's energy per degree of freedom, m_1 T_bath / dim (m_1 the first
 * species' mass). An elastic mixture (eps_n = 1) of masses 1:4 then shares it equally:
 * T_s = (1 / (d N_s)) sum_{i in s} m_i |v_i - V|^2 = m_1 T_bath / 2 for both species, times
 * 1 - m_s / sum_i m_i for V's share (equipartition; one kick for all would give T_2 = 4 T_1),
 * within 5 % (the standard error of the time average is about 1.3 %; 10 times longer runs give
 * 0.996 and 0.998 of it); the ledger closes with the drag's column. A radius distribution (radii
 * uniform in 1-2 mm, masses up to 4:1) has the grains' mean mass for m_1: the grains lighter and
 * heavier than it each hold m_1 T_bath / 2 times 1 - <m>_group / sum_i m_i (measured 0.9947 and
 * 0.9954 of m_1 T_bath / 2). */
START_TEST(bath_equipartition)
{
    const int dim = _i == 1 ? 3 : 2; /* 3D: 216 spheres on a cubic lattice */
    const bool dist = _i == 2;       /* a radius distribution: the grains' mean mass for m_1 */
    static const char *bath =
        "[system]\ndim = 2\nN = 200\nL = 0.1\n[placement]\nkind = uniform\nv0 = 0.1\n"
        "[species]\nradius = 1e-3, 2e-3\nmass = 1e-5, 4e-5\n[model]\nk_s = 50\neps_n = 1\n"
        "[driving]\nkind = langevin\nT_bath = 0.01\ntau = 0.1\n"
        "[integrator]\nsteps_per_contact = 20\n";
    static const char *bath_dist =
        "[system]\ndim = 2\nN = 200\nL = 0.1\n[placement]\nkind = uniform\nv0 = 0.1\n"
        "[species]\ndistribution = uniform\nradius_min = 1e-3\nradius_max = 2e-3\n"
        "density = 2.5\n[model]\nk_s = 50\neps_n = 1\n"
        "[driving]\nkind = langevin\nT_bath = 0.01\ntau = 0.1\n"
        "[integrator]\nsteps_per_contact = 20\n";
    const char *three[] = {"system.dim=3", "system.N=216", "placement.kind=cubic"};
    gr_scene sc;
    load(&sc, dist ? bath_dist : bath, three, dim == 3 ? 3 : 0);
    gr_sim *s = create(&sc);
    /* k_B T = m_1 T_bath / dim; the two groups: species, or the grains lighter and heavier than
     * the mean mass s->mass (a distribution's m_1) */
    const double dt = gr_sim_dt(s), kT = (dist ? s->mass : 1e-5) * 0.01 / dim;
    double Mtot = 0.0, mg[2] = {0.0, 0.0};
    int ng[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        const int a = dist ? s->mass_i[i] > s->mass : s->species[i];
        Mtot += s->mass_i[i];
        mg[a] += s->mass_i[i];
        ng[a]++;
    }
    const int every = (int)(5e-3 / dt) + 1, samples = quick() ? 10 : 600;
    step(s, (int64_t)(0.5 / dt)); /* 5 tau */
    double T[2] = {0.0, 0.0};
    for (int k = 0; k < samples; k++) {
        step(s, every);
        double P[3] = {0.0, 0.0, 0.0}, M = 0.0, e[2] = {0.0, 0.0};
        int n[2] = {0, 0};
        for (int i = 0; i < s->n; i++) {
            P[0] += s->mass_i[i] * s->vx[i];
            P[1] += s->mass_i[i] * s->vy[i];
            P[2] += dim == 3 ? s->mass_i[i] * s->vz[i] : 0.0;
            M += s->mass_i[i];
        }
        for (int i = 0; i < s->n; i++) {
            const double ux = s->vx[i] - P[0] / M, uy = s->vy[i] - P[1] / M,
                         uz = dim == 3 ? s->vz[i] - P[2] / M : 0.0;
            const int a = dist ? s->mass_i[i] > s->mass : s->species[i];
            e[a] += s->mass_i[i] * (ux * ux + uy * uy + uz * uz);
            n[a]++;
        }
        for (int a = 0; a < 2; a++) {
            T[a] += e[a] / (dim * n[a]) / samples;
        }
    }
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("bath (%dD%s): T_1 = %.5g J, T_2 = %.5g J, m_1 T_bath / d = %.5g J (ratios %.4f, %.4f); "
           "drag %.4g J, residual %.3g of the energy moved\n",
           dim, dist ? ", radius distribution" : "", T[0], T[1], kT, T[0] / kT, T[1] / kT,
           l.dissipated_drag, res / moved);
    ck_assert_msg(fabs(res) < 1e-3 * moved, "ledger residual %g of %g", res, moved);
    ck_assert(l.dissipated_drag > 0.0);
    if (!quick()) { /* the statistics: the release pass */
        for (int a = 0; a < 2; a++) {
            /* V's share: E sum_{i in g} m_i |v_i - V|^2 = d kT sum_{i in g} (1 - m_i / sum_j m_j) */
            const double want = kT * (1.0 - mg[a] / ng[a] / Mtot);
            ck_assert_msg(fabs(T[a] / want - 1.0) < 0.05, "species %d: T = %g J, want %g J", a + 1,
                          T[a], want);
        }
    }
    gr_sim_free(s);
}
END_TEST

/* [noise] mode = com with species: the reset removes V = sum m_i v_i / sum m_i, so afterwards
 * sum m_i v_i = 0 (the plain mean of the velocities would leave it), and it books the kinetic
 * energy it removed, sum m_i |V|^2 / 2, exactly; a driven run in com mode closes its ledger. */
START_TEST(com_reset_masses)
{
    const char *set[] = {"system.N=200",           "system.L=0.1", "placement.v0=0.2",
                         "driving.kind=rfm",       "noise.D=1e-9", "noise.mode=com",
                         "noise.com_interval=1e-4"};
    const int dim = _i ? 3 : 2;
    const char *three[] = {"system.dim=3", "system.N=216", "placement.kind=cubic"};
    gr_scene sc;
    load(&sc, pair_2d, set, 7);
    if (dim == 3) { /* the same in 3D: 216 spheres of the two species */
        const char *both[12];
        for (int k = 0; k < 7; k++) {
            both[k] = set[k];
        }
        for (int k = 0; k < 3; k++) {
            both[7 + k] = three[k];
        }
        load(&sc,
             "[system]\ndim = 2\nN = 2\nL = 0.1\n[species]\nradius = 1e-3, 2e-3\n"
             "mass = 1e-5, 4e-5\n[placement]\nkind = uniform\nv0 = 0\n[model]\nk_s = 5e4\n"
             "eps_n = 0.7\n",
             both, 10);
    }
    gr_sim *s = create(&sc);
    double ke0 = 0.0, scale = 0.0;
    double *const v[3] = {s->vx, s->vy, s->vz};
    for (int i = 0; i < s->n; i++) {
        s->vx[i] = 0.01 * (i % 7) - 0.02;
        s->vy[i] = 0.003 * (i % 5);
        if (dim == 3) {
            s->vz[i] = 0.004 * (i % 3) - 0.001;
        }
        for (int c = 0; c < dim; c++) {
            ke0 += 0.5 * s->mass_i[i] * v[c][i] * v[c][i];
        }
        scale += s->mass_i[i] * 0.05;
    }
    const double removed = gr_remove_com(s);
    double p[3] = {0.0, 0.0, 0.0}, ke1 = 0.0;
    for (int i = 0; i < s->n; i++) {
        for (int c = 0; c < dim; c++) {
            p[c] += s->mass_i[i] * v[c][i];
            ke1 += 0.5 * s->mass_i[i] * v[c][i] * v[c][i];
        }
    }
    printf("com reset (%dD): sum m v = (%.3g, %.3g, %.3g) kg m/s, removed %.10g J, kinetic energy "
           "change %.10g J\n",
           dim, p[0], p[1], p[2], removed, ke0 - ke1);
    ck_assert_msg(fabs(p[0]) < 1e-14 * scale && fabs(p[1]) < 1e-14 * scale &&
                      fabs(p[2]) < 1e-14 * scale,
                  "sum m v = (%g, %g, %g)", p[0], p[1], p[2]);
    ck_assert_msg(fabs(removed - (ke0 - ke1)) < 1e-12 * ke0, "removed %.17g J, the change %.17g J",
                  removed, ke0 - ke1);
    gr_sim_free(s);
    s = create(&sc);
    step(s, quick() ? 2000 : 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("com mode: removed %.4g J, residual %.3g of the energy moved\n", l.removed_com,
           res / moved);
    ck_assert(l.removed_com > 0.0);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    gr_sim_free(s);
}
END_TEST

START_TEST(hertz_radius_and_dt)
{
    const char *set[] = {"model.normal=hertz", "model.k_h=1e6"};
    gr_scene sc;
    load(&sc, pair_1d, set, 2);
    gr_sim *s = create(&sc);
    ck_assert_int_eq(s->nsp, 2);
    const double r[2] = {1e-3, 2e-3}, R00 = 0.5 * r[0];
    double tmin = INFINITY;
    for (int a = 0; a < 2; a++) {
        for (int b = 0; b < 2; b++) {
            const gr_contact_coeffs *c = &s->cc_pair[2 * a + b];
            const double R = r[a] * r[b] / (r[a] + r[b]);
            ck_assert_msg(fabs(c->k_s / (1e6 * sqrt(R / R00)) - 1.0) < 1e-12, "k_h of pair %d%d", a,
                          b);
            ck_assert_msg(fabs(s->d_pair[2 * a + b] - (r[a] + r[b])) < 1e-18, "contact distance");
            tmin = fmin(tmin, c->t_c);
        }
    }
    ck_assert_msg(fabs(s->dt - tmin / sc.steps_per_contact) < 1e-12 * s->dt, "dt %g, t_c min %g",
                  s->dt, tmin);
    gr_sim_free(s);
}
END_TEST

/* An ideal gas (grains too small and too few per area to meet within the run) of two species,
 * masses 1:4: the kinetic energy each species gains is N_s d D t / m_s (times 1 - 1/N). */
START_TEST(heating_per_mass)
{
    static const char *gas =
        "[system]\ndim = 2\nN = 20000\nL = 1\n[placement]\nkind = uniform\nv0 = 0\n"
        "[species]\nradius = 1e-6, 1e-6\nmass = 1e-5, 4e-5\n[noise]\nD = 1e-10\n"
        "[integrator]\ndt = 1e-5\nforce_dt = true\n";
    gr_scene sc;
    load(&sc, gas, NULL, 0);
    gr_sim *s = create(&sc);
    const int steps = 200;
    step(s, steps);
    double ke[2] = {0.0, 0.0};
    int count[2] = {0, 0};
    for (int i = 0; i < s->n; i++) {
        ke[s->species[i]] += 0.5 * s->mass_i[i] * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i]);
        count[s->species[i]]++;
    }
    ck_assert_int_eq(count[0], 10000);
    ck_assert_int_eq(count[1], 10000);
    const double t = steps * s->dt, sym = 1.0 - 1.0 / s->n;
    for (int a = 0; a < 2; a++) {
        const double want = count[a] * 2.0 * 1e-10 * t / (a ? 4e-5 : 1e-5) * sym;
        /* relative standard deviation sqrt(2 / (N_s d)) = 1 %: 5 of them */
        ck_assert_msg(fabs(ke[a] / want - 1.0) < 0.05, "species %d gained %g J, want %g J", a,
                      ke[a], want);
    }
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-12 * l.injected, "ledger residual %g",
                  gr_ledger_residual(&l));
    gr_sim_free(s);
}
END_TEST

START_TEST(species_dealt_by_seed)
{
    static const char *mix = "[system]\ndim = 2\nN = 101\npacking_fraction = 0.2\n"
                             "[species]\nradius = 1e-3, 2e-3, 3e-3\ndensity = 10, 10, 10\n"
                             "fraction = 0.2, 0.3, 0.5\n";
    gr_scene sc;
    load(&sc, mix, NULL, 0);
    ck_assert_int_eq(sc.species_count[0], 20);
    ck_assert_int_eq(sc.species_count[1], 30);
    ck_assert_int_eq(sc.species_count[2], 51);
    /* the packing fraction counts the actual radii */
    const double area = M_PI * (20 * 1e-6 + 30 * 4e-6 + 51 * 9e-6);
    ck_assert_msg(fabs(area / (sc.L * sc.L) - 0.2) < 1e-12, "phi %g", area / (sc.L * sc.L));
    gr_sim *a = create(&sc), *b = create(&sc);
    ck_assert_msg(memcmp(a->species, b->species, sizeof(int) * 101) == 0, "same seed, same deal");
    ck_assert_msg(fabs(a->mass_i[0] - 10 * M_PI * a->rad[0] * a->rad[0]) < 1e-18, "density");
    step(a, 2000);
    gr_ledger l = gr_sim_ledger(a);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 0.01 * (l.injected + gr_ledger_dissipated(&l)),
                  "ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_params p;
    gr_scene_sim_params(&sc, &p);
    double x[1] = {0.1}, y[1] = {0.1}, v[1] = {0.0};
    gr_sim *c = NULL;
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_new_with_state(&p, 1, x, y, v, v, &c, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "carries no species") != NULL, "%s", err.message);
}
END_TEST

/* A radius distribution: radii within the bounds with the distribution's mean or median, masses
 * from the density, the packing fraction from the actual radii, and every pair of two grains of
 * different sizes keeps eps_n (the damping scaled to the pair's reduced mass, hertz's stiffness to
 * its effective radius); a 2D run's ledger closes. */
START_TEST(size_distribution)
{
    static const char *gas = "[system]\ndim = 2\nN = 4000\npacking_fraction = 0.3\n"
                             "[placement]\nkind = random\n[species]\nradius_min = 1e-3\n"
                             "radius_max = 3e-3\ndensity = 10\n";
    for (int kind = 0; kind < 2; kind++) {
        const char *set[] = {kind ? "species.distribution=lognormal"
                                  : "species.distribution=uniform",
                             "species.radius_median=2e-3", "species.radius_sigma=0.3"};
        gr_scene sc;
        load(&sc, gas, set, 3);
        gr_sim *s = create(&sc);
        double area = 0.0, mean = 0.0;
        int below = 0;
        for (int i = 0; i < s->n; i++) {
            ck_assert(s->rad[i] >= 1e-3 && s->rad[i] <= 3e-3);
            ck_assert(fabs(s->mass_i[i] / (10 * M_PI * s->rad[i] * s->rad[i]) - 1) < 1e-15);
            area += M_PI * s->rad[i] * s->rad[i];
            mean += s->rad[i] / s->n;
            below += s->rad[i] < 2e-3;
        }
        ck_assert_msg(fabs(area / (s->L * s->L) - 0.3) < 1e-12, "phi %g", area / (s->L * s->L));
        if (kind == 0) { /* uniform: mean 2 mm, standard error 9 um */
            ck_assert_msg(fabs(mean - 2e-3) < 5e-5, "mean radius %g", mean);
        } else { /* lognormal about 2 mm, truncated symmetrically in ln r: half below the median */
            ck_assert_msg(abs(below - 2000) < 200, "%d of 4000 below the median", below);
        }
        if (kind == 0) {
            step(s, 2000);
            gr_ledger l = gr_sim_ledger(s);
            ck_assert_msg(fabs(gr_ledger_residual(&l)) <
                              0.01 * (l.injected + gr_ledger_dissipated(&l)),
                          "ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
        }
        gr_sim_free(s);
    }
    static const char *pair = "[system]\ndim = 1\nN = 2\nL = 1\n[placement]\nkind = uniform\n"
                              "v0 = 0\n[driving]\nkind = none\n[species]\ndistribution = uniform\n"
                              "radius_min = 1e-3\nradius_max = 3e-3\ndensity = 10\n";
    static const char *const laws[] = {"model.normal=spring_dashpot", "model.normal=hertz"};
    for (int l = 0; l < 2; l++) {
        for (int seed = 1; seed <= 3; seed++) {
            char sd[32];
            snprintf(sd, sizeof sd, "run.seed=%d", seed);
            const char *set[] = {laws[l], "model.eps_n=0.7", sd};
            gr_scene sc;
            load(&sc, pair, set, 3);
            gr_sim *s = create(&sc);
            double p0, p1;
            const double eps = collide(s, &p0, &p1);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s, radii %g and %g m: eps = %.5f, want 0.7",
                          laws[l], s->rad[0], s->rad[1], eps);
            ck_assert_msg(fabs(p1 - p0) < 1e-13 * fabs(s->mass_i[0] * 0.1), "momentum %g -> %g", p0,
                          p1);
            gr_sim_free(s);
        }
    }
}
END_TEST

/* A radius distribution in 3D: masses 4/3 pi r^3 rho, the volume fraction from the actual radii,
 * every head-on pair of two sizes keeps eps_n and momentum (spring-dashpot and hertz), and a gas's
 * ledger closes. */
START_TEST(size_distribution_3d)
{
    static const char *gas = "[system]\ndim = 3\nN = 2000\npacking_fraction = 0.2\n"
                             "[placement]\nkind = random\n[species]\ndistribution = uniform\n"
                             "radius_min = 1e-3\nradius_max = 3e-3\ndensity = 2500\n";
    gr_scene sc;
    load(&sc, gas, NULL, 0);
    gr_sim *s = create(&sc);
    double vol = 0.0;
    for (int i = 0; i < s->n; i++) {
        const double r = s->rad[i];
        ck_assert(r >= 1e-3 && r <= 3e-3);
        ck_assert(fabs(s->mass_i[i] / (2500 * 4.0 / 3.0 * M_PI * r * r * r) - 1) < 1e-15);
        vol += 4.0 / 3.0 * M_PI * r * r * r;
    }
    ck_assert_msg(fabs(vol / (s->L * s->L * s->L) - 0.2) < 1e-12, "phi %g",
                  vol / (s->L * s->L * s->L));
    step(s, 1000);
    gr_ledger l = gr_sim_ledger(s);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) < 0.01 * (l.injected + gr_ledger_dissipated(&l)),
                  "ledger residual %g of %g", gr_ledger_residual(&l), l.injected);
    gr_sim_free(s);

    static const char *pair = "[system]\ndim = 3\nN = 2\nL = 1\n[placement]\nkind = random\n"
                              "v0 = 0\n[driving]\nkind = none\n[species]\ndistribution = uniform\n"
                              "radius_min = 1e-3\nradius_max = 3e-3\ndensity = 2500\n";
    static const char *const laws[] = {"model.normal=spring_dashpot", "model.normal=hertz"};
    for (int k = 0; k < 2; k++) {
        for (int seed = 1; seed <= 3; seed++) {
            char sd[32];
            snprintf(sd, sizeof sd, "run.seed=%d", seed);
            const char *set[] = {laws[k], "model.eps_n=0.7", sd, "model.k_s=5e3"};
            load(&sc, pair, set, k ? 3 : 4); /* hertz: its own default stiffness */
            s = create(&sc);
            for (int i = 0; i < 2; i++) { /* head-on along x at the box's middle */
                s->y[i] = s->z[i] = 0.5;
            }
            double p0, p1;
            const double eps = collide(s, &p0, &p1);
            ck_assert_msg(fabs(eps - 0.7) < 0.01, "%s, radii %g and %g m: eps = %.5f, want 0.7",
                          laws[k], s->rad[0], s->rad[1], eps);
            ck_assert_msg(fabs(p1 - p0) < 1e-13 * fabs(s->mass_i[0] * 0.1), "momentum %g -> %g", p0,
                          p1);
            ck_assert(s->vy[0] == 0.0 && s->vz[1] == 0.0); /* head-on: no sideways motion */
            gr_sim_free(s);
        }
    }
}
END_TEST

/* Tangential laws and rotation with a radius distribution (kernels_poly.c, gr_size_scaled): two
 * discs drawn with radii 2.0 and 1.1 mm (seed 11; the reference pair is that of two grains of
 * radius_min) collide obliquely, rotating, with the tangential dashpot (spring_dashpot and hertz):
 * the contact point's tangential velocity comes out scaled by the reference pair's eps_t at that
 * speed (the coefficients scaled as gamma_t ~ M^(a / (a + 1)) k^(1 / (a + 1)), m_t ~ M keep it for
 * every pair: the scene's eps_t, at v_max for hertz); the angular momentum is conserved to
 * rounding. A driven gas
 * of the distribution with sliding friction and rolling resistance closes its ledger. */
START_TEST(size_tangential)
{
    static const char *pair =
        "[system]\ndim = 2\nN = 2\nL = 0.2\n[placement]\nkind = uniform\nv0 = 0\n"
        "[driving]\nkind = none\n[species]\ndistribution = uniform\nradius_min = 1e-3\n"
        "radius_max = 3e-3\ndensity = 5\n[model]\nk_s = 5e4\neps_n = 0.7\n"
        "tangential = tangential_dashpot\neps_t = 0.5\nrotation = true\n"
        "[integrator]\nsteps_per_contact = 100\n[run]\nseed = 11\n";
    static const char *const laws[][2] = {{"model.normal=spring_dashpot", "model.k_s=5e4"},
                                          {"model.normal=hertz", "model.k_h=1e7"}};
    for (int l = 0; l < 2; l++) {
        gr_scene sc;
        load(&sc, pair, laws[l], 2);
        gr_sim *s = create(&sc);
        ck_assert(s->cc_pair == NULL && fabs(s->rad[0] - s->rad[1]) > 5e-4);
        const spin_out o = spin_collision(s);
        printf("distribution pair (%s, radii %g, %g m): contact point g_t ratio %.5f, the law "
               "%.5f; angular momentum %.17g -> %.17g\n",
               laws[l][0], s->rad[0], s->rad[1], o.ratio, o.want, o.L0, o.L1);
        /* 0.005: hertz's gamma_t scaled as sqrt(M k) (the linear law's rule) would be about 0.016
         * off (4.5 % more damping on this pair: 0.3737^1.045) */
        ck_assert_msg(fabs(o.ratio - o.want) < 0.005, "g_ct ratio %.5f, want %.5f", o.ratio,
                      o.want);
        ck_assert_msg(fabs(o.L1 - o.L0) < 1e-12 * fabs(o.L0), "angular momentum %.17g -> %.17g",
                      o.L0, o.L1);
        gr_sim_free(s);
    }
    static const char *gas =
        "[system]\ndim = 2\nN = 200\npacking_fraction = 0.3\n[placement]\nkind = random\n"
        "v0 = 0.2\nomega0 = 50\n[species]\ndistribution = uniform\nradius_min = 1e-3\n"
        "radius_max = 2e-3\ndensity = 5\n[model]\nk_s = 5e4\neps_n = 0.7\n"
        "tangential = sliding_friction\nmu = 0.3\nrotation = true\nrolling = rolling_friction\n"
        "[noise]\nD = 1e-9\n";
    gr_scene sc;
    load(&sc, gas, NULL, 0);
    gr_sim *s = create(&sc);
    step(s, quick() ? 2000 : 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("distribution gas (sliding friction, rolling): friction %.4g J, rotational %.4g J, "
           "residual %.3g of the energy moved\n",
           l.dissipated_friction, l.rotational, res / moved);
    ck_assert(l.dissipated_friction > 0.0 && l.rotational > 0.0);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    gr_sim_free(s);
}
END_TEST

/* The history spring (tangential_spring) with a radius distribution and the linear normal law:
 * its k_t = kt_ratio k_s is every pair's, so the distribution's pair (seed 11: radii 2.0 and 1.1
 * mm) collides obliquely with rotation exactly as the same two grains given as species lists (their
 * pair's coefficients prepared for it) to rounding; a driven gas of the distribution with the spring
 * closes its ledger and restarts bit for bit. Hertz's spring stays refused (its k_t follows each
 * pair's linearised contact). */
START_TEST(size_spring)
{
    static const char *pair =
        "[system]\ndim = 2\nN = 2\nL = 0.2\n[placement]\nkind = uniform\nv0 = 0\n"
        "[driving]\nkind = none\n[species]\ndistribution = uniform\nradius_min = 1e-3\n"
        "radius_max = 3e-3\ndensity = 5\n[model]\nk_s = 5e4\neps_n = 0.7\n"
        "tangential = tangential_spring\nmu = 0.5\nrotation = true\n"
        "[integrator]\ndt = 2e-7\n[run]\nseed = 11\n";
    gr_scene sc;
    load(&sc, pair, NULL, 0);
    gr_sim *a = create(&sc);
    ck_assert(a->cc_pair == NULL && a->nl_hist != NULL);
    char lists[800]; /* the same two grains as species lists, grain 0 of a's first radius */
    gr_scene sl;
    gr_sim *b = NULL;
    for (int swap = 0; swap < 2 && !(b && b->rad[0] == a->rad[0]); swap++) {
        if (b) {
            gr_sim_free(b);
        }
        snprintf(lists, sizeof lists,
                 "[system]\ndim = 2\nN = 2\nL = 0.2\n[placement]\nkind = uniform\nv0 = 0\n"
                 "[driving]\nkind = none\n[species]\nradius = %.17g, %.17g\nmass = %.17g, %.17g\n"
                 "[model]\nk_s = 5e4\neps_n = 0.7\ntangential = tangential_spring\nmu = 0.5\n"
                 "rotation = true\n[integrator]\ndt = 2e-7\n[run]\nseed = 11\n",
                 a->rad[swap], a->rad[1 - swap], a->mass_i[swap], a->mass_i[1 - swap]);
        load(&sl, lists, NULL, 0);
        b = create(&sl);
    }
    ck_assert(b->cc_pair != NULL && b->rad[0] == a->rad[0] && b->mass_i[1] == a->mass_i[1]);
    const spin_out oa = spin_collision(a), ob = spin_collision(b);
    const double dv = fabs(a->vx[0] - b->vx[0]) + fabs(a->vy[1] - b->vy[1]),
                 dw = fabs(a->omega[0] - b->omega[0]) + fabs(a->omega[1] - b->omega[1]);
    printf("distribution spring pair (radii %g, %g m): g_ct ratio %.6f against the lists' %.6f; "
           "velocities differ by %.2g m/s, spins by %.2g rad/s (of %.3g)\n",
           a->rad[0], a->rad[1], oa.ratio, ob.ratio, dv, dw, fabs(a->omega[0]));
    ck_assert(fabs(a->omega[0]) > 1.0); /* the spring turned them */
    /* to rounding: the two prepare the pair's coefficients by different paths (scaled from the
     * distribution's reference pair, or for the pair itself), equal to the last bits only */
    const double vs = fabs(a->vx[0]) + fabs(a->vy[1]);
    ck_assert_msg(vs > 0.0 && dv <= 1e-14 * vs && dw <= 1e-14 * fabs(a->omega[0]),
                  "not equal to rounding: dv %g of %g m/s, dw %g", dv, vs, dw);
    ck_assert_msg(fabs(oa.L1 - oa.L0) < 1e-12 * fabs(oa.L0), "angular momentum %.17g -> %.17g",
                  oa.L0, oa.L1);
    gr_sim_free(a);
    gr_sim_free(b);
    static const char *gas =
        "[system]\ndim = 2\nN = 200\npacking_fraction = 0.3\n[placement]\nkind = random\n"
        "v0 = 0.2\nomega0 = 50\n[species]\ndistribution = uniform\nradius_min = 1e-3\n"
        "radius_max = 2e-3\ndensity = 5\n[model]\nk_s = 5e4\neps_n = 0.7\n"
        "tangential = tangential_spring\nmu = 0.3\nrotation = true\n[noise]\nD = 1e-9\n";
    load(&sc, gas, NULL, 0);
    gr_sim *s = create(&sc);
    step(s, quick() ? 2000 : 20000);
    const gr_ledger l = gr_sim_ledger(s);
    const double moved = l.injected + gr_ledger_dissipated(&l), res = gr_ledger_residual(&l);
    printf("distribution gas (the spring): friction %.4g J, residual %.3g of the energy moved\n",
           l.dissipated_friction, res / moved);
    ck_assert(l.dissipated_friction > 0.0);
    ck_assert_msg(fabs(res) < 2e-3 * moved, "residual %g of %g", res, moved);
    gr_sim_free(s);
    assert_restart_exact(&sc, 3000, 1000);
    gr_scene h;
    gr_error err = {0};
    const char *hertz[] = {"model.normal=hertz", "model.k_h=1e7"};
    ck_assert(gr_scene_load_buffer(&h, "h.ini", gas, strlen(gas), hertz, 2, &err) != GR_OK);
    ck_assert_msg(strstr(err.message, "normal = spring_dashpot"), "%s", err.message);
}
END_TEST

static Suite *species_suite(void)
{
    Suite *s = suite_create("species");
    TCase *t = tcase_create("pairs");
    tcase_set_timeout(t, 600);
    tcase_add_test(t, pair_tangential);
    tcase_add_test(t, size_spring);
    tcase_add_test(t, pair_rotation);
    tcase_add_test(t, pair_spring);
    tcase_add_test(t, pair_rolling);
    tcase_add_loop_test(t, bath_equipartition, 0, 3);
    tcase_add_loop_test(t, com_reset_masses, 0, 2);
    tcase_add_test(t, pair_restitution);
    tcase_add_test(t, hertz_radius_and_dt);
    tcase_add_test(t, heating_per_mass);
    tcase_add_test(t, species_dealt_by_seed);
    tcase_add_test(t, size_distribution);
    tcase_add_test(t, size_distribution_3d);
    tcase_add_test(t, size_tangential);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(species_suite()); }
