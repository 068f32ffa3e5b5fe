/* Contacts with friction and rotation between spheres ([system] dim = 3, docs/three-dimensions.md,
 * src/core/kernels_3d.c): the tangential laws (tangential_dashpot, sliding_friction,
 * tangential_spring linear and Mindlin), rotation with angular velocity vectors and the rolling
 * law, on two spheres and in a gas.
 *   - a collision in the plane z = 0 with spins along z gives the 2D engine's numbers (the same
 *     laws on discs with the same q), to rounding, and leaves v_z, w_x, w_y at exactly 0;
 *   - an impact parameter along z gives the impact along y turned by 90 degrees about x
 *     (velocities and spins), to rounding;
 *   - with spins about arbitrary axes: momentum and angular momentum about the origin (orbital +
 *     I w) conserved to rounding, the energy never rises, nothing is NaN;
 *   - exchanging the two spheres (indices) gives the mirrored result;
 *   - the energy loss of head-on and oblique impacts (y and z) follows the law's restitution
 *     (gr_contact_expected_loss) to first order in dt / t_c;
 *   - hard cases: grazing, zero relative velocity with spin, huge spin: finite results;
 *   - a driven gas with rotation (and the history law, the rolling law) closes the ledger, with
 *     the rotational energy in the kinetic one; the history vectors survive a forced list rebuild
 *     bit for bit, a checkpoint restart continues bit for bit, 1, 2 and 3 threads agree;
 *   - the moment of inertia's factor defaults to 2/5 in 3D and stays 1/2 in 2D.
 * Particles: the thesis's spheres (Table 2.2 size and mass, k_s = 5e5 N/m). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/granule.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

static const char *pair_scene =
    "[system]\ndim = 3\nN = 2\nL = 0.05\n[placement]\nkind = cubic\nv0 = 0\n"
    "[model]\nnormal = spring_dashpot\nk_s = 5e5\neps_n = 0.8\n[noise]\nD = 0\n"
    "[integrator]\nsteps_per_contact = 200\n";

/* The laws under test, as --set lists (rotation on, q = 2/5 given so 2D uses it too). */
typedef struct law {
    const char *name;
    const char *set[8];
    int nset;
} law;

static const law laws[] = {
    {"tangential_dashpot",
     {"model.tangential=tangential_dashpot", "model.eps_t=0.5", "model.rotation=true",
      "model.inertia_factor=0.4"},
     4},
    {"sliding_friction",
     {"model.tangential=sliding_friction", "model.mu=0.3", "model.rotation=true",
      "model.inertia_factor=0.4"},
     4},
    {"tangential_spring",
     {"model.tangential=tangential_spring", "model.mu=0.3", "model.rotation=true",
      "model.inertia_factor=0.4"},
     4},
    {"tangential_spring+gamma_t",
     {"model.tangential=tangential_spring", "model.mu=0.3", "model.gamma_t=0.05",
      "model.rotation=true", "model.inertia_factor=0.4"},
     5},
    {"hertz+mindlin",
     {"model.normal=hertz", "model.tangential=tangential_spring", "model.mindlin=true",
      "model.mu=0.3", "model.rotation=true", "model.inertia_factor=0.4"},
     6},
    {"tangential_dashpot+rolling",
     {"model.tangential=tangential_dashpot", "model.eps_t=0.5", "model.rotation=true",
      "model.inertia_factor=0.4", "model.rolling=rolling_friction", "model.mu_r=0.2"},
     6},
    {"tangential_spring+rolling",
     {"model.tangential=tangential_spring", "model.mu=0.3", "model.rotation=true",
      "model.inertia_factor=0.4", "model.rolling=rolling_friction", "model.mu_r=0.2"},
     6},
};
enum { N_LAWS = sizeof laws / sizeof laws[0] };

/* Two particles: positions, velocities, spins. */
typedef struct pair_state {
    double r[2][3], v[2][3], w[2][3];
} pair_state;

static gr_sim *pair_sim(const law *l, int dim, const char *extra)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[12];
    int n = 0;
    char dims[32];
    snprintf(dims, sizeof dims, "system.dim=%d", dim);
    set[n++] = dims;
    if (dim == 2) {
        set[n++] = "placement.kind=square";
    }
    for (int k = 0; k < l->nset; k++) {
        set[n++] = l->set[k];
    }
    if (extra) {
        set[n++] = extra;
    }
    load(sc, pair_scene, set, n);
    gr_sim *s = create(sc);
    free(sc);
    return s;
}

/* Put the state into s and evaluate the forces there (a fresh list, no history). */
static void put(gr_sim *s, const pair_state *st)
{
    double *r[3] = {s->x, s->y, s->z}, *v[3] = {s->vx, s->vy, s->vz};
    double *w[3] = {s->wx, s->wy, s->omega};
    for (int i = 0; i < 2; i++) {
        for (int a = 0; a < s->dim; a++) {
            r[a][i] = st->r[i][a];
            v[a][i] = st->v[i][a];
        }
        for (int a = s->dim == 3 ? 0 : 2; a < 3 && s->omega; a++) {
            w[a][i] = st->w[i][a];
        }
    }
    gr_error err = {0};
    ck_assert_int_eq(gr_neighbours_build(s, &err), GR_OK);
    if (s->nl_hist) {
        memset(s->nl_hist, 0, sizeof(double) * (size_t)gr_history_width(s) * (size_t)s->nl_cap);
    }
    gr_force_report rep;
    gr_forces(s, &rep);
    ck_assert_double_eq(rep.elastic, 0.0);
}

static void get(const gr_sim *s, pair_state *st)
{
    memset(st, 0, sizeof *st);
    const double *r[3] = {s->x, s->y, s->z}, *v[3] = {s->vx, s->vy, s->vz};
    const double *w[3] = {s->wx, s->wy, s->omega};
    for (int i = 0; i < 2; i++) {
        for (int a = 0; a < s->dim; a++) {
            st->r[i][a] = r[a][i];
            st->v[i][a] = v[a][i];
        }
        for (int a = s->dim == 3 ? 0 : 2; a < 3 && s->omega; a++) {
            st->w[i][a] = w[a][i];
        }
    }
}

static double dist_of(const gr_sim *s)
{
    double d2 = 0.0;
    const double *r[3] = {s->x, s->y, s->z};
    for (int a = 0; a < s->dim; a++) {
        const double dd = r[a][1] - r[a][0];
        d2 += dd * dd;
    }
    return sqrt(d2);
}

/* Step from st through one collision until the spheres are apart again; the state after. */
static void collide(gr_sim *s, const pair_state *st, pair_state *out)
{
    put(s, st);
    int touched = 0;
    int64_t k = 0;
    for (; k < 2000000 && !(touched && dist_of(s) > s->d); k++) {
        step(s, 1);
        touched |= dist_of(s) < s->d;
    }
    ck_assert_msg(touched && k < 2000000, "no collision, or it never ended (%lld steps)",
                  (long long)k);
    get(s, out);
}

/* The energy of the pair (translation + I |w|^2 / 2), with inertia I. */
static double energy(const pair_state *st, double M, double I)
{
    double e = 0.0;
    for (int i = 0; i < 2; i++) {
        for (int a = 0; a < 3; a++) {
            e += 0.5 * M * st->v[i][a] * st->v[i][a] + 0.5 * I * st->w[i][a] * st->w[i][a];
        }
    }
    return e;
}

/* The relative motion's energy: energy() minus the centre of mass's kinetic energy. */
static double energy_rel(const pair_state *st, double M, double I)
{
    double com = 0.0;
    for (int a = 0; a < 3; a++) {
        const double p = st->v[0][a] + st->v[1][a];
        com += 0.25 * M * p * p;
    }
    return energy(st, M, I) - com;
}

/* Sphere 0 at rest at the box's centre c, sphere 1 approaching along -x at `speed` with impact
 * parameter (0, by, bz) in diameters; spins w0, w1. */
static pair_state impact(const gr_sim *s, double speed, double by, double bz, const double w0[3],
                         const double w1[3])
{
    const double d = s->d, c = 0.5 * s->L;
    pair_state st = {{{c, c, s->dim == 3 ? c : 0.0}, {c + 1.1 * d, c + by * d, c + bz * d}},
                     {{0.0, 0.0, 0.0}, {-speed, 0.0, 0.0}},
                     {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}};
    if (s->dim == 2) {
        st.r[1][2] = 0.0;
    }
    for (int a = 0; a < 3; a++) {
        st.w[0][a] = w0 ? w0[a] : 0.0;
        st.w[1][a] = w1 ? w1[a] : 0.0;
    }
    return st;
}

static double rel_diff(double a, double b, double scale) { return fabs(a - b) / scale; }

static const double zero3[3] = {0.0, 0.0, 0.0};

/* ---- a collision in the plane z = 0 is the 2D collision ----------------------------------- */

START_TEST(test_plane_is_2d)
{
    const law *l = &laws[_i];
    gr_sim *s3 = pair_sim(l, 3, NULL), *s2 = pair_sim(l, 2, NULL);
    ck_assert_double_eq(s3->dt, s2->dt);
    ck_assert_double_eq(s3->inertia, s2->inertia);
    const double speed = 0.5, wz0[3] = {0.0, 0.0, 150.0}, wz1[3] = {0.0, 0.0, -400.0};
    const double bys[] = {0.0, 0.3, 0.7};
    for (int b = 0; b < 3; b++) {
        for (int spin = 0; spin < 2; spin++) {
            pair_state in3 = impact(s3, speed, bys[b], 0.0, spin ? wz0 : NULL, spin ? wz1 : NULL);
            pair_state in2 = in3, out3, out2;
            in2.r[0][2] = in2.r[1][2] = 0.0;
            collide(s3, &in3, &out3);
            collide(s2, &in2, &out2);
            const double ws = speed / (0.5 * s3->d);
            double worst = 0.0;
            for (int i = 0; i < 2; i++) {
                for (int a = 0; a < 2; a++) {
                    worst = fmax(worst, rel_diff(out3.v[i][a], out2.v[i][a], speed));
                }
                worst = fmax(worst, rel_diff(out3.w[i][2], out2.w[i][2], ws));
                ck_assert_msg(out3.v[i][2] == 0.0 && out3.w[i][0] == 0.0 && out3.w[i][1] == 0.0,
                              "%s: left the plane: v_z %g, w_x %g, w_y %g", l->name, out3.v[i][2],
                              out3.w[i][0], out3.w[i][1]);
            }
            VERBOSE("%s, b = %g, spin %d: 3D vs 2D %.2e (v1 %g %g, w1 %g)\n", l->name, bys[b], spin,
                    worst, out3.v[1][0], out3.v[1][1], out3.w[1][2]);
            ck_assert_msg(worst < 1e-9, "%s, b = %g, spin %d: 3D differs from 2D by %.3e", l->name,
                          bys[b], spin, worst);
            /* the test can fail: the collision did something tangential */
            if (b > 0 || spin) {
                ck_assert_msg(fabs(out3.w[1][2] - in3.w[1][2]) > 1e-3 * ws,
                              "%s: the spins did not change", l->name);
            }
        }
    }
    gr_sim_free(s3);
    gr_sim_free(s2);
}
END_TEST

/* ---- the impact along z is the impact along y turned about x -------------------------------- */

/* (a, b, c) -> (a, -c, b): +90 degrees about x (y -> z) */
static void turn(const double u[3], double out[3])
{
    out[0] = u[0];
    out[1] = -u[2];
    out[2] = u[1];
}

START_TEST(test_turned_impact)
{
    const law *l = &laws[_i];
    gr_sim *s = pair_sim(l, 3, NULL);
    const double speed = 0.5, ws = speed / (0.5 * s->d);
    const double w0[3] = {120.0, -300.0, 80.0}, w1[3] = {-50.0, 210.0, 400.0};
    pair_state a = impact(s, speed, 0.4, 0.0, w0, w1), b = a, oa, ob;
    const double c = 0.5 * s->L;
    for (int i = 0; i < 2; i++) {
        const double rel[3] = {a.r[i][0] - c, a.r[i][1] - c, a.r[i][2] - c};
        double t[3];
        turn(rel, t);
        for (int k = 0; k < 3; k++) {
            b.r[i][k] = c + t[k];
        }
        turn(a.v[i], b.v[i]);
        turn(a.w[i], b.w[i]);
    }
    ck_assert_double_eq(b.r[1][1], c);
    collide(s, &a, &oa);
    collide(s, &b, &ob);
    double worst = 0.0;
    for (int i = 0; i < 2; i++) {
        double tv[3], tw[3];
        turn(oa.v[i], tv);
        turn(oa.w[i], tw);
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, rel_diff(ob.v[i][k], tv[k], speed));
            worst = fmax(worst, rel_diff(ob.w[i][k], tw[k], ws));
        }
    }
    VERBOSE("%s: impact along z vs along y turned: %.2e\n", l->name, worst);
    ck_assert_msg(worst < 1e-9, "%s: the impact along z differs from the turned one by %.3e",
                  l->name, worst);
    gr_sim_free(s);
}
END_TEST

/* ---- conservation with spins about any axis, exchange symmetry ------------------------------ */

static void angular_momentum(const pair_state *st, double M, double I, double Lout[3])
{
    for (int a = 0; a < 3; a++) {
        Lout[a] = 0.0;
    }
    for (int i = 0; i < 2; i++) {
        const double *r = st->r[i], *v = st->v[i];
        Lout[0] += M * (r[1] * v[2] - r[2] * v[1]) + I * st->w[i][0];
        Lout[1] += M * (r[2] * v[0] - r[0] * v[2]) + I * st->w[i][1];
        Lout[2] += M * (r[0] * v[1] - r[1] * v[0]) + I * st->w[i][2];
    }
}

START_TEST(test_conservation_any_axis)
{
    const law *l = &laws[_i];
    gr_sim *s = pair_sim(l, 3, NULL);
    const double M = s->mass, I = s->inertia, speed = 0.5, c = 0.5 * s->L;
    const double w0[3] = {310.0, -170.0, 520.0}, w1[3] = {-90.0, 240.0, 60.0};
    const double b[][2] = {{0.0, 0.0}, {0.3, 0.2}, {-0.1, 0.6}};
    for (int k = 0; k < 3; k++) {
        pair_state in = impact(s, speed, b[k][0], b[k][1], w0, w1), out;
        collide(s, &in, &out);
        double L0[3], L1[3];
        angular_momentum(&in, M, I, L0);
        angular_momentum(&out, M, I, L1);
        const double lscale = M * speed * c;
        double dp = 0.0, dl = 0.0;
        for (int a = 0; a < 3; a++) {
            dp = fmax(dp, fabs((out.v[0][a] + out.v[1][a]) - (in.v[0][a] + in.v[1][a])) / speed);
            dl = fmax(dl, fabs(L1[a] - L0[a]) / lscale);
            for (int i = 0; i < 2; i++) {
                ck_assert_msg(isfinite(out.v[i][a]) && isfinite(out.w[i][a]), "%s: NaN", l->name);
            }
        }
        const double e0 = energy(&in, M, I), e1 = energy(&out, M, I);
        VERBOSE("%s, b = (%g, %g): momentum %.1e, angular momentum %.1e, energy %g -> %g\n",
                l->name, b[k][0], b[k][1], dp, dl, e0, e1);
        ck_assert_msg(dp < 1e-14, "%s: momentum changed by %.3e", l->name, dp);
        ck_assert_msg(dl < 1e-13, "%s: angular momentum changed by %.3e", l->name, dl);
        ck_assert_msg(e1 < e0 && e1 > 0.0, "%s: energy %g -> %g", l->name, e0, e1);
        /* the spins changed: the tangential law acted (the test can fail) */
        ck_assert_msg(fabs(out.w[1][0] - w1[0]) + fabs(out.w[1][1] - w1[1]) > 1.0,
                      "%s: the spins did not change", l->name);
    }
    gr_sim_free(s);
}
END_TEST

START_TEST(test_exchange_symmetry)
{
    const law *l = &laws[_i];
    gr_sim *s = pair_sim(l, 3, NULL);
    const double speed = 0.5, ws = speed / (0.5 * s->d);
    const double w0[3] = {310.0, -170.0, 520.0}, w1[3] = {-90.0, 240.0, 60.0};
    pair_state a = impact(s, speed, 0.3, -0.25, w0, w1), b, oa, ob;
    for (int a3 = 0; a3 < 3; a3++) {
        b.r[0][a3] = a.r[1][a3];
        b.r[1][a3] = a.r[0][a3];
        b.v[0][a3] = a.v[1][a3];
        b.v[1][a3] = a.v[0][a3];
        b.w[0][a3] = a.w[1][a3];
        b.w[1][a3] = a.w[0][a3];
    }
    collide(s, &a, &oa);
    collide(s, &b, &ob);
    double worst = 0.0;
    for (int i = 0; i < 2; i++) {
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, rel_diff(ob.v[1 - i][k], oa.v[i][k], speed));
            worst = fmax(worst, rel_diff(ob.w[1 - i][k], oa.w[i][k], ws));
        }
    }
    VERBOSE("%s: exchanged %.2e\n", l->name, worst);
    ck_assert_msg(worst < 1e-10, "%s: exchanging the spheres changes the result by %.3e", l->name,
                  worst);
    gr_sim_free(s);
}
END_TEST

/* ---- energy loss against the restitution law -------------------------------------------------- */

START_TEST(test_restitution_law)
{
    const law *l = &laws[_i];
    if (strstr(l->name, "rolling")) {
        return; /* the rolling torque acts on spins only: covered by the conservation checks */
    }
    gr_sim *s = pair_sim(l, 3, NULL);
    const double M = s->mass, I = s->inertia, speed = 0.5;
    /* impact parameter b (diameters) along y or z: the angle between -g and n is asin(b) */
    const double bs[] = {0.0, 0.3, 0.6};
    for (int k = 0; k < 3; k++) {
        for (int axis = 0; axis < (bs[k] > 0.0 ? 2 : 1); axis++) {
            pair_state in = impact(s, speed, axis ? 0.0 : bs[k], axis ? bs[k] : 0.0, zero3, zero3),
                       out;
            collide(s, &in, &out);
            const double loss = 1.0 - energy_rel(&out, M, I) / energy_rel(&in, M, I);
            const double angle = asin(bs[k]) * 180.0 / M_PI;
            const double want = gr_contact_expected_loss(&s->cc, speed, angle);
            /* the engine follows the law to first order in dt / t_c (200 steps per contact);
             * the line of centres turns while the spheres touch: 2 turn (tests/test_rotation.c) */
            const double tol = 0.25 / 200.0 + 0.01 * bs[k];
            VERBOSE("%s, b = %g along %s: loss %.6f, law %.6f\n", l->name, bs[k], axis ? "z" : "y",
                    loss, want);
            ck_assert_msg(isfinite(want) && fabs(loss - want) <= tol,
                          "%s, b = %g along %s: loss %.6f, the law's %.6f (tol %.2e)", l->name,
                          bs[k], axis ? "z" : "y", loss, want, tol);
        }
    }
    gr_sim_free(s);
}
END_TEST

/* ---- hard cases --------------------------------------------------------------------------- */

START_TEST(test_hard_cases)
{
    const law *l = &laws[_i];
    gr_sim *s = pair_sim(l, 3, NULL);
    const double M = s->mass, I = s->inertia;
    const double big[3] = {3e5, -2e5, 4e5}, spin[3] = {0.0, 800.0, 0.0};
    /* grazing; head-on with only spin (zero tangential relative velocity of the centres, the
     * spins equal and opposite so the contact point does not slide: zero g_c); huge spin */
    const double neg[3] = {0.0, -800.0, 0.0};
    struct {
        const char *what;
        double speed, by, bz;
        const double *w0, *w1;
    } const cases[] = {{"grazing", 0.5, 0.0, 0.99, NULL, NULL},
                       {"zero sliding", 0.5, 0.0, 0.0, spin, neg},
                       {"zero g_c with spin about n", 0.5, 0.0, 0.0, (const double[3]){900, 0, 0},
                        (const double[3]){900, 0, 0}},
                       {"huge spin", 0.5, 0.2, 0.1, big, NULL}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        pair_state in = impact(s, cases[k].speed, cases[k].by, cases[k].bz, cases[k].w0,
                               cases[k].w1),
                   out;
        collide(s, &in, &out);
        const double e0 = energy(&in, M, I), e1 = energy(&out, M, I);
        for (int i = 0; i < 2; i++) {
            for (int a = 0; a < 3; a++) {
                ck_assert_msg(isfinite(out.v[i][a]) && isfinite(out.w[i][a]), "%s, %s: NaN",
                              l->name, cases[k].what);
            }
        }
        VERBOSE("%s, %s: energy %g -> %g\n", l->name, cases[k].what, e0, e1);
        ck_assert_msg(e1 <= e0 * (1.0 + 1e-12), "%s, %s: energy rose %g -> %g", l->name,
                      cases[k].what, e0, e1);
    }
    gr_sim_free(s);
}
END_TEST

/* ---- granule collide --dim 3 and its CVODE reference ------------------------------------------ */

static gr_collide_setup collide_setup(const char *normal, const char *tangential)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.dim = 3;
    s.normal = gr_model_find(normal);
    s.tangential = gr_model_find(tangential);
    s.contact.rotation = true;
    s.contact.inertia_factor = 0.4;
    s.contact.eps_t = 0.4;
    s.mass = 3.53e-5;
    s.radius = 1.5e-3;
    s.steps_per_contact = 200;
    return s;
}

/* Out of the impact's plane the reference integrates the contact in 3D (tangential_dashpot,
 * sliding_friction; the history spring's vector form: tests/test_spring_reference_3d.c); a
 * spin about x of 1e-7 rad/s must give the plane's reference (the 2D integration) to its
 * tolerance, and the engine must follow the 3D reference to first order in dt / t_c with spins
 * about every axis. */
START_TEST(test_collide_reference_3d)
{
    const char *const normals[] = {"spring_dashpot", "hertz", "spring_dashpot", "hertz"};
    const char *const tangentials[] = {"tangential_dashpot", "tangential_dashpot",
                                       "sliding_friction", "sliding_friction"};
    gr_collision_case cs;
    gr_error err = {0};
    ck_assert_int_eq(gr_collision_case_oblique(0.5, 30.0, 1.5e-3, &cs, &err), GR_OK);
    for (int k = 0; k < 4; k++) {
        gr_collide_setup s = collide_setup(normals[k], tangentials[k]);
        s.w1[2] = 150.0;
        s.w2[2] = -300.0;
        gr_collide_result plane, tilted, engine, ref;
        ck_assert_msg(gr_collide_reference(&s, &cs, &plane, &err) == GR_OK, "%s", err.message);
        s.w1[0] = 1e-7;
        ck_assert_msg(gr_collide_reference(&s, &cs, &tilted, &err) == GR_OK, "%s", err.message);
        double worst = fabs(plane.energy_loss - tilted.energy_loss);
        for (int a = 0; a < 3; a++) {
            worst = fmax(worst, fabs(plane.v1[a] - tilted.v1[a]) / 0.5);
            worst = fmax(worst, fabs(plane.w2[a] - tilted.w2[a]) / 300.0);
        }
        VERBOSE("%s + %s: 3D reference vs the plane's: %.2e (loss %.10f)\n", normals[k],
                tangentials[k], worst, plane.energy_loss);
        ck_assert_msg(worst < 1e-8, "%s: the 3D reference differs from the plane's by %.3e",
                      normals[k], worst);
        const double w1[3] = {400.0, 100.0, 150.0}, w2[3] = {-100.0, 0.0, -300.0};
        memcpy(s.w1, w1, sizeof w1);
        memcpy(s.w2, w2, sizeof w2);
        ck_assert_msg(gr_collide_reference(&s, &cs, &ref, &err) == GR_OK, "%s", err.message);
        ck_assert_msg(gr_collide_run(&s, &cs, &engine, &err) == GR_OK, "%s", err.message);
        const double dl = fabs(engine.energy_loss - ref.energy_loss);
        double dw = 0.0, dv = 0.0;
        for (int a = 0; a < 3; a++) {
            dw = fmax(dw, fabs(engine.w1[a] - ref.w1[a]) / 400.0);
            dv = fmax(dv, fabs(engine.v2[a] - ref.v2[a]) / 0.5);
        }
        VERBOSE("%s + %s: engine vs 3D reference: loss %.8f / %.8f, spins %.2e, velocities %.2e, "
                "v_z %g\n",
                normals[k], tangentials[k], engine.energy_loss, ref.energy_loss, dw, dv, ref.v2[2]);
        ck_assert_msg(fabs(ref.v2[2]) > 1e-3 && fabs(ref.w1[1] - 100.0) > 1.0,
                      "%s: the contact stayed in the plane: the test tests nothing", normals[k]);
        ck_assert_msg(dl <= 0.25 / 200.0 && dw <= 2e-3 && dv <= 2e-3,
                      "%s: engine and 3D reference differ: loss %.3e, spins %.3e, velocities %.3e",
                      normals[k], dl, dw, dv);
        ck_assert_double_le(engine.momentum_error, 1e-13);
    }
}
END_TEST

/* `granule collide --dim 3 --model hard_sphere` (rough: rotation = true, beta, beta_mu): in the
 * plane without spins the 2D rule's numbers to rounding (v_z and the spins' x, y exactly 0); with spins
 * about every axis Walton's rule on 3-vectors: eps_n and -beta (the Coulomb value when sliding) as
 * the measured restitutions, the loss (1 - eps_n^2) g_n^2 + q / (1 + q) (1 - beta^2) |g_c|^2 of
 * the energy, momentum, and both spins turned by the same R n x P / I (angular momentum). */
static void hard_3d(double beta, double mu, const double w1[3], const double w2[3])
{
    gr_collision_case cs;
    gr_error err = {0};
    ck_assert_int_eq(gr_collision_case_oblique(0.5, 35.0, 1.5e-3, &cs, &err), GR_OK);
    gr_collide_setup s = collide_setup("hard_sphere", "tangential_dashpot");
    s.tangential = NULL;
    s.tangential = NULL;
    s.contact.eps_n = 0.7;
    ck_assert_int_eq(gr_contact_set_value(&s.contact, "beta", beta, &err), GR_OK);
    ck_assert_int_eq(gr_contact_set_value(&s.contact, "beta_mu", mu, &err), GR_OK);
    memcpy(s.w1, w1, sizeof s.w1);
    memcpy(s.w2, w2, sizeof s.w2);
    gr_collide_result r;
    ck_assert_msg(gr_collide_run(&s, &cs, &r, &err) == GR_OK, "%s", err.message);
    const double M = s.mass, R = s.radius, q = 0.4, I = q * M * R * R;
    const double spun = w1[0] != 0.0 || w1[1] != 0.0 || w1[2] != 0.0 || w2[0] != 0.0 ||
                        w2[1] != 0.0 || w2[2] != 0.0;
    if (!spun) { /* the plane: the 2D rule (discs with the same q) */
        gr_collide_setup s2 = s;
        s2.dim = 2;
        gr_collide_result r2;
        ck_assert_msg(gr_collide_run(&s2, &cs, &r2, &err) == GR_OK, "%s", err.message);
        double dv = 0.0;
        for (int a = 0; a < 2; a++) {
            dv = fmax(dv, fmax(fabs(r.v1[a] - r2.v1[a]), fabs(r.v2[a] - r2.v2[a])) / 0.5);
        }
        const double dw =
            fmax(fabs(r.w1[2] - r2.omega1), fabs(r.w2[2] - r2.omega2)) / fabs(r2.omega1);
        VERBOSE("collide --dim 3 hard_sphere in the plane vs 2D: velocities %.2e, spins %.2e, "
                "loss %.2e\n",
                dv, dw, fabs(r.energy_loss - r2.energy_loss));
        ck_assert_msg(dv < 1e-15 && dw < 1e-15 && r2.omega1 != 0.0, "velocities %g, spins %g", dv,
                      dw);
        ck_assert(r.v1[2] == 0.0 && r.v2[2] == 0.0 && r.w1[0] == 0.0 && r.w1[1] == 0.0 &&
                  r.w2[0] == 0.0 && r.w2[1] == 0.0);
        ck_assert(fabs(r.energy_loss - r2.energy_loss) < 1e-15 &&
                  fabs(r.expected_loss - r2.expected_loss) < 1e-15);
    }
    /* the geometry at contact, from the case (collide: n from 1 to 2, g = v2 - v1) */
    const double x1[3] = {cs.x1[0], cs.x1[1], 0.0}, x2[3] = {cs.x2[0], cs.x2[1], 0.0};
    const double v1[3] = {cs.v1[0], cs.v1[1], 0.0}, v2[3] = {cs.v2[0], cs.v2[1], 0.0};
    double g[3], dx[3], n[3], gc[3];
    for (int a = 0; a < 3; a++) {
        g[a] = v2[a] - v1[a];
        dx[a] = x2[a] - x1[a];
    }
    const double gg = g[0] * g[0] + g[1] * g[1], gd = g[0] * dx[0] + g[1] * dx[1];
    const double dd = dx[0] * dx[0] + dx[1] * dx[1];
    const double th = (-gd - sqrt(gd * gd - gg * (dd - 4.0 * R * R))) / gg;
    for (int a = 0; a < 3; a++) {
        n[a] = (dx[a] + g[a] * th) / (2.0 * R);
    }
    const double gn = g[0] * n[0] + g[1] * n[1];
    const double W[3] = {w1[0] + w2[0], w1[1] + w2[1], w1[2] + w2[2]};
    const double nW[3] = {n[1] * W[2] - n[2] * W[1], n[2] * W[0] - n[0] * W[2],
                          n[0] * W[1] - n[1] * W[0]};
    double gc2 = 0.0;
    for (int a = 0; a < 3; a++) {
        gc[a] = g[a] - gn * n[a] + R * nW[a];
        gc2 += gc[a] * gc[a];
    }
    double bt = beta;
    if (mu > 0.0 && (1.0 + beta) * q / (1.0 + q) * sqrt(gc2) > mu * 1.7 * fabs(gn)) {
        bt = -1.0 + mu * 1.7 * (1.0 + 1.0 / q) * fabs(gn) / sqrt(gc2);
    }
    const double e0 = gg + I *
                               (w1[0] * w1[0] + w1[1] * w1[1] + w1[2] * w1[2] + w2[0] * w2[0] +
                                w2[1] * w2[1] + w2[2] * w2[2]) /
                               (0.5 * M);
    const double loss = ((1.0 - 0.49) * gn * gn + q / (1.0 + q) * (1.0 - bt * bt) * gc2) / e0;
    VERBOSE("collide --dim 3 hard_sphere beta %g mu %g: loss %.15f (Walton %.15f), eps_n %.15f, "
            "eps_t %.15f (-beta %g)\n",
            beta, mu, r.energy_loss, loss, r.eps_n_measured, r.eps_t_measured, -bt);
    ck_assert_msg(fabs(r.energy_loss - loss) < 1e-12, "loss %.15f, Walton %.15f", r.energy_loss,
                  loss);
    ck_assert(fabs(r.eps_n_measured - 0.7) < 1e-12 && fabs(r.eps_t_measured + bt) < 1e-12);
    ck_assert_double_le(r.momentum_error, 1e-15);
    for (int a = 0; a < 3; a++) { /* I dw = R n x P, P = M (v1' - v1), the same for both */
        const double P[3] = {M * (r.v1[0] - v1[0]), M * (r.v1[1] - v1[1]), M * (r.v1[2] - v1[2])};
        const double nP[3] = {n[1] * P[2] - n[2] * P[1], n[2] * P[0] - n[0] * P[2],
                              n[0] * P[1] - n[1] * P[0]};
        const double wscale = 1.0 + fabs(r.w1[0]) + fabs(r.w1[1]) + fabs(r.w1[2]);
        ck_assert_msg(fabs(I * (r.w1[a] - w1[a]) - R * nP[a]) < 1e-12 * I * wscale &&
                          fabs(I * (r.w2[a] - w2[a]) - R * nP[a]) < 1e-12 * I * wscale,
                      "spin %d: %.15g -> %.15g, R n x P / I = %.15g", a, w1[a], r.w1[a],
                      R * nP[a] / I);
    }
}

START_TEST(test_collide_hard_3d)
{
    const double zero[3] = {0.0, 0.0, 0.0}, wa[3] = {400.0, -200.0, 150.0},
                 wb[3] = {-100.0, 300.0, -300.0};
    hard_3d(0.5, 0.0, zero, zero);
    hard_3d(0.5, 0.0, wa, wb);
    hard_3d(1.0, 0.1, wa, zero); /* Coulomb-limited: slides */
    hard_3d(-0.2, 0.0, zero, wb);
    /* initial spins without rotation are refused, naming the keys */
    gr_collision_case cs;
    gr_error err = {0};
    ck_assert_int_eq(gr_collision_case_oblique(0.5, 35.0, 1.5e-3, &cs, &err), GR_OK);
    gr_collide_setup s = collide_setup("hard_sphere", "tangential_dashpot");
    s.tangential = NULL;
    s.contact.rotation = false;
    s.w1[0] = 10.0;
    gr_collide_result r;
    ck_assert_int_eq(gr_collide_run(&s, &cs, &r, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "rotation = true") && strstr(err.message, "0,0,0"), "%s",
                  err.message);
}
END_TEST

/* ---- a gas: ledger, list rebuilds, restarts, threads ------------------------------------------ */

static const char *gas =
    "[system]\ndim = 3\nN = 343\npacking_fraction = 0.2\n[placement]\nkind = cubic\nv0 = 0.1\n"
    "omega0 = 300\n[model]\nnormal = spring_dashpot\nk_s = 5e5\neps_n = 0.9\nrotation = true\n"
    "[noise]\nD = 1e-8\n[integrator]\ndt = 1e-6\n";

static const char *const gas_laws[][3] = {
    {"model.tangential=tangential_spring", "model.mu=0.5", "model.rolling=rolling_friction"},
    {"model.tangential=sliding_friction", "model.mu=0.5", "model.rolling=none"},
    {"model.tangential=tangential_dashpot", "model.eps_t=0.5", "model.rolling=none"},
    /* threads only: rolling without a history law (the cross pairs' torques evaluated twice) */
    {"model.tangential=sliding_friction", "model.mu=0.5", "model.rolling=rolling_friction"},
};

START_TEST(test_ledger_closes)
{
    gr_scene *sc = malloc(sizeof *sc);
    load(sc, gas, gas_laws[_i], 3);
    gr_sim *s = create(sc);
    ck_assert_ptr_nonnull(s->wx);
    const double rot0 = gr_sim_ledger(s).rotational;
    ck_assert_msg(rot0 > 0.0, "omega0 gave no spin energy");
    step(s, 10000); /* the sanitizer pass too: 3000 steps hold only ~20 collisions */
    const gr_ledger l = gr_sim_ledger(s);
    const double scale = l.injected + gr_ledger_dissipated(&l);
    const double res = gr_ledger_residual(&l) / scale;
    VERBOSE("%s: ledger residual %.2e of %g J, rotational %g -> %g J, friction %g J, %lld "
            "collisions\n",
            gas_laws[_i][0], res, scale, rot0, l.rotational, l.dissipated_friction,
            (long long)s->collisions);
    ck_assert_msg(s->collisions > 200, "%lld collisions", (long long)s->collisions);
    ck_assert_msg(l.dissipated_friction + l.dissipated_tangential > 0.01 * scale,
                  "the tangential law dissipated nothing: %g", l.dissipated_friction);
    ck_assert_msg(fabs(res) < 5e-3, "ledger residual %.3e of injected + dissipated", res);
    gr_sim_free(s);
    free(sc);
}
END_TEST

static int64_t live_springs(const gr_sim *s)
{
    int64_t k = 0;
    for (int64_t p = 0; p < s->nl_start[s->n]; p++) {
        k += s->nl_hist[3 * p] != 0.0 || s->nl_hist[3 * p + 1] != 0.0 ||
             s->nl_hist[3 * p + 2] != 0.0;
    }
    return k;
}

/* The history vector of the listed pair (i, j), i < j (zero if not listed). */
static void slot_of(const gr_sim *s, int i, int j, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
        if (s->nl_j[p] == j) {
            memcpy(out, s->nl_hist + 3 * (int64_t)p, 3 * sizeof(double));
        }
    }
}

/* A forced list rebuild carries every contact's vector over bit for bit (compared pair by pair
 * with the twin run that did not rebuild), and the runs then continue identically; forgetting the
 * vectors at the rebuilds (the control) changes the run. Then a restart (threads: below). */
START_TEST(test_history_rebuild_restart_threads)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"model.tangential=tangential_spring", "model.mu=0.5",
                         "model.rolling=rolling_friction", "system.packing_fraction=0.45",
                         "placement.v0=2"};
    load(sc, gas, set, 5);
    gr_sim *a = create(sc), *b = create(sc), *c = create(sc);
    gr_error err = {0};
    int64_t alive = 0;
    for (int k = 0; k < 20; k++) {
        step(a, 50);
        step(b, 50);
        step(c, 50);
        ck_assert_int_eq(gr_neighbours_build(b, &err), GR_OK); /* keeps them */
        int64_t carried = 0;
        for (int i = 0; i < a->n; i++) {
            for (int p = a->nl_start[i]; p < a->nl_start[i + 1]; p++) {
                double va[3], vb[3];
                memcpy(va, a->nl_hist + 3 * (int64_t)p, sizeof va);
                slot_of(b, i, a->nl_j[p], vb);
                ck_assert_msg(memcmp(va, vb, sizeof va) == 0,
                              "pair (%d, %d): history (%g, %g, %g) became (%g, %g, %g) at a "
                              "rebuild",
                              i, a->nl_j[p], va[0], va[1], va[2], vb[0], vb[1], vb[2]);
                carried += va[0] != 0.0 || va[1] != 0.0 || va[2] != 0.0;
            }
        }
        ck_assert_int_eq(carried, live_springs(b));
        alive += carried;
        ck_assert_int_eq(gr_neighbours_build(a, &err), GR_OK); /* the same list again */
        ck_assert_int_eq(gr_neighbours_build(c, &err), GR_OK);
        memset(c->nl_hist, 0, sizeof(double) * 3 * (size_t)c->nl_start[c->n]); /* forgets */
    }
    step(a, 50);
    step(b, 50);
    step(c, 50);
    ck_assert_msg(alive > 20, "only %lld live springs at the rebuilds: the test tests nothing",
                  (long long)alive);
    assert_same_state(a, b);
    ck_assert_msg(memcmp(a->vx, c->vx, sizeof(double) * (size_t)a->n) != 0,
                  "forgetting the springs changed nothing: the test tests nothing");
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_free(c);
    assert_restart_exact(sc, 1200, 517);
    free(sc);
}
END_TEST

/* Every law at once (the history spring, rotation, rolling) on 1, 2 and 3 threads: 2197 spheres
 * (three blocks), the same bits for forces, torques, history vectors and the ledger, across list
 * rebuilds and a restart saved on 3 threads and continued on 2. */
START_TEST(test_threads_every_law)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {
        "model.tangential=tangential_spring", "model.mu=0.5",   "model.rolling=rolling_friction",
        "system.packing_fraction=0.45",       "placement.v0=2", "system.N=2197"};
    load(sc, gas, set, 6);
    assert_threads_exact(sc, 500, 211);
    gr_sim *a = create(sc);
    step(a, 500);
    ck_assert_msg(live_springs(a) > 100, "%lld live springs: the test tests nothing",
                  (long long)live_springs(a));
    gr_sim_free(a);
    free(sc);
}
END_TEST

/* The laws without history (sliding friction, the tangential dashpot, sliding friction with
 * rolling; rotation) on 1, 2 and 3 threads, as above: each thread evaluates the cross pairs it
 * receives itself (kernels_3d.c, add_direct_3d). */
START_TEST(test_threads_laws)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {gas_laws[_i][0],  gas_laws[_i][1],
                         gas_laws[_i][2],  "system.packing_fraction=0.45",
                         "placement.v0=4", "system.N=2197"};
    load(sc, gas, set, 6);
    assert_threads_exact(sc, 800, 333);
    free(sc);
}
END_TEST

/* A restart where contacts hold springs carries the spin vectors and the history vectors. */
START_TEST(test_restart_spins)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"model.tangential=tangential_spring", "model.mu=0.5",
                         "system.packing_fraction=0.45", "placement.v0=2"};
    load(sc, gas, set, 4);
    gr_sim *b = create(sc);
    int64_t first = 400;
    step(b, first);
    for (; live_springs(b) == 0 && first < 2000; first++) {
        step(b, 1); /* stop where a contact holds a spring */
    }
    ck_assert_msg(live_springs(b) > 0, "no live spring at the restart: the test tests nothing");
    gr_sim_free(b);
    assert_restart_exact(sc, first + 500, first); /* sim_helpers.h: the spin vectors too */
    free(sc);
}
END_TEST

/* eps_n = 1 without friction (eps_t = 1: the dashpot does nothing, the normal law's instance
 * runs): spinning spheres keep their spins exactly and the energy is conserved as in test_3d.c;
 * and the instance with every law read at run time gives the normal-only instance's bits. */
START_TEST(test_elastic_without_friction)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"model.tangential=tangential_dashpot",
                         "model.eps_t=1",
                         "model.eps_n=1",
                         "noise.D=0",
                         "placement.v0=2",
                         "system.packing_fraction=0.3",
                         "integrator.steps_per_contact=50"};
    load(sc, gas, set, 7);
    sc->dt = 0.0;
    gr_sim *s = create(sc), *g = create(sc);
    ck_assert_msg(strstr(gr_sim_kernel(s), "+rotation") == NULL, "%s", gr_sim_kernel(s));
    ck_assert_int_eq(gr_kernel_force_generic(g), GR_OK);
    ck_assert(g->kernel.run != s->kernel.run);
    const size_t bytes = sizeof(double) * (size_t)s->n;
    double *w0 = malloc(3 * bytes);
    memcpy(w0, s->wx, bytes);
    memcpy(w0 + s->n, s->wy, bytes);
    memcpy(w0 + 2 * s->n, s->omega, bytes);
    gr_ledger l0 = gr_sim_ledger(s);
    const double e0 = l0.kinetic + l0.elastic;
    step(s, 3000);
    step(g, 3000);
    const gr_ledger l = gr_sim_ledger(s);
    const double err = fabs(l.kinetic + l.elastic - e0) / e0;
    VERBOSE("elastic spheres with spins: energy error %.2e, %lld collisions\n", err,
            (long long)s->collisions);
    ck_assert_msg(s->collisions > 100, "%lld collisions", (long long)s->collisions);
    ck_assert_msg(err < 1e-3, "energy error %.3e", err);
    ck_assert(memcmp(w0, s->wx, bytes) == 0 && memcmp(w0 + s->n, s->wy, bytes) == 0 &&
              memcmp(w0 + 2 * s->n, s->omega, bytes) == 0);
    assert_same_state(s, g);
    free(w0);
    gr_sim_free(s);
    gr_sim_free(g);
    free(sc);
}
END_TEST

/* The instance compiled with the issue-35 scene's laws as constants (spring-dashpot and tangential
 * dashpot, unclamped, no rotation) gives the bits of the instance reading every law at run time,
 * over contacts and list rebuilds. */
START_TEST(test_dashpots_instance)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"model.tangential=tangential_dashpot",
                         "model.eps_t=0.1",
                         "model.clamp=false",
                         "model.rotation=false",
                         "placement.omega0=0",
                         "placement.v0=4",
                         "system.packing_fraction=0.3"};
    load(sc, gas, set, 7);
    gr_sim *s = create(sc), *g = create(sc);
    ck_assert_msg(s->kernel.run == gr_kernel_run_3d_dashpots, "%s: not the dashpots' instance",
                  gr_sim_kernel(s));
    ck_assert_int_eq(gr_kernel_force_generic(g), GR_OK);
    ck_assert(g->kernel.run == gr_kernel_run_3d_full);
    step(s, 800);
    step(g, 800);
    ck_assert_msg(s->collisions > 100 && s->rebuilds > 1, "%lld collisions, %lld rebuilds",
                  (long long)s->collisions, (long long)s->rebuilds);
    assert_same_state(s, g);
    gr_sim_free(s);
    gr_sim_free(g);
    free(sc);
}
END_TEST

/* ---- defaults and initial spins --------------------------------------------------------------- */

START_TEST(test_defaults_follow_dim)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set3[] = {"model.tangential=tangential_dashpot"};
    load(sc, gas, set3, 1);
    gr_sim *s = create(sc);
    ck_assert_double_eq_tol(s->cc.q, 0.4, 1e-15);
    ck_assert_double_eq_tol(s->inertia, 0.4 * s->mass * 0.25 * s->d * s->d, 1e-30);
    /* omega0: each component omega0 U(-0.5, 0.5): <|w|^2> = 3 omega0^2 / 12 */
    double w2 = 0.0;
    for (int i = 0; i < s->n; i++) {
        w2 += s->wx[i] * s->wx[i] + s->wy[i] * s->wy[i] + s->omega[i] * s->omega[i];
    }
    w2 /= s->n;
    const double want = 3.0 * 300.0 * 300.0 / 12.0;
    ck_assert_msg(fabs(w2 / want - 1.0) < 0.15, "<|w|^2> = %g, want %g", w2, want);
    ck_assert_double_eq_tol(gr_sim_rotational_temperature(s), s->inertia * w2 / s->mass,
                            1e-12 * s->inertia * w2 / s->mass);
    gr_sim_free(s);
    const char *set2[] = {"model.tangential=tangential_dashpot", "system.dim=2",
                          "placement.kind=hexagonal", "system.packing_fraction=0.3"};
    load(sc, gas, set2, 4);
    s = create(sc);
    ck_assert_double_eq_tol(s->cc.q, 0.5, 1e-15);
    gr_sim_free(s);
    const char *set3q[] = {"model.tangential=tangential_dashpot", "model.inertia_factor=0.7"};
    load(sc, gas, set3q, 2);
    s = create(sc);
    ck_assert_double_eq_tol(s->cc.q, 0.7, 1e-15);
    gr_sim_free(s);
    free(sc);
}
END_TEST

static Suite *contacts_suite(void)
{
    Suite *s = suite_create("3d-contacts");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 600);
    tcase_add_loop_test(tc, test_plane_is_2d, 0, N_LAWS);
    tcase_add_loop_test(tc, test_turned_impact, 0, N_LAWS);
    tcase_add_loop_test(tc, test_conservation_any_axis, 0, N_LAWS);
    tcase_add_loop_test(tc, test_exchange_symmetry, 0, N_LAWS);
    tcase_add_loop_test(tc, test_restitution_law, 0, N_LAWS);
    tcase_add_loop_test(tc, test_hard_cases, 0, N_LAWS);
    tcase_add_loop_test(tc, test_ledger_closes, 0, 3);
    tcase_add_test(tc, test_history_rebuild_restart_threads);
    tcase_add_test(tc, test_threads_every_law);
    if (!quick()) { /* thread invariance of the other laws: the release pass's (the sanitizer pass
                       runs the threaded kernel in test_threads_every_law) */
        tcase_add_loop_test(tc, test_threads_laws, 1, 4);
    }
    tcase_add_test(tc, test_restart_spins);
    tcase_add_test(tc, test_elastic_without_friction);
    tcase_add_test(tc, test_dashpots_instance);
    tcase_add_test(tc, test_collide_reference_3d);
    tcase_add_test(tc, test_collide_hard_3d);
    tcase_add_test(tc, test_defaults_follow_dim);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(contacts_suite()); }
