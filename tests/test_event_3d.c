/* Event-driven hard spheres in a periodic cube ([system] dim = 3, [integrator] kind = event;
 * src/integrators/event/event_cells.h, docs/three-dimensions.md):
 *
 * - an elastic gas (eps_n = eps_t = 1, no noise) conserves energy and momentum to rounding, never
 *   overlaps (every pair checked after every event) and crosses cells; so does a box too small
 *   for cells (all pairs);
 * - a single oblique collision (impact parameter in y and z) gives the velocities of the rule
 *   (2.1, 2.2, 2.10) on 3-vectors: eps_n on the normal, eps_t on the whole tangential relative
 *   velocity, the losses booked as dE_n and dE_t; with viscoelastic = true eps_n(v) is the
 *   model's impact at the normal approach speed;
 * - free flight under the random force injects 3 D (N - 1) / M per second (all three
 *   components), in both free_flight modes;
 * - with noise and dissipation (TC rule, both free_flight modes) the ledger closes to rounding;
 * - a restart from saved bytes continues bit for bit, and split calls equal one call;
 * - rough spheres are refused. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "integrators/event/event.h"
#include "integrators/event/event_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "sim_helpers.h"
#include "test_env.h"

/* The thesis's spheres (Table 2.2) at phi = 0.1, smooth and elastic, no noise. */
static const char *gas = "[system]\ndim = 3\nN = 343\npacking_fraction = 0.1\n"
                         "[placement]\nkind = random\nv0 = 1\n"
                         "[model]\nnormal = hard_sphere\neps_n = 1\neps_t = 1\n"
                         "[noise]\nmode = none\n[integrator]\nkind = event\n";

static double kinetic(const gr_sim *s, double p[3])
{
    double k = 0.0;
    p[0] = p[1] = p[2] = 0.0;
    for (int i = 0; i < s->n; i++) {
        k += 0.5 * s->mass * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i] + s->vz[i] * s->vz[i]);
        p[0] += s->mass * s->vx[i];
        p[1] += s->mass * s->vy[i];
        p[2] += s->mass * s->vz[i];
    }
    return k;
}

static int64_t steps_of(const gr_sim *s, double t) { return (int64_t)llround(t / s->dt); }

/* 343 spheres at phi = 0.1 (9 cells per side); 27 at phi = 0.2 in a box of 4.8 d (4 cells per
 * side, the fewest allowed: the nearest image of a pair in adjacent cells is the one they touch). */
static void elastic_gas(const char *n, const char *phi, const char *kernel, double t)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {n, phi};
    load(sc, gas, set, 2);
    gr_sim *s = create(sc);
    gr_event_set_debug(s, true, false); /* every pair checked after every collision */
    double p0[3], p1[3];
    const double k0 = kinetic(s, p0);
    step(s, steps_of(s, t));
    const double k1 = kinetic(s, p1);
    gr_event_counts c;
    gr_event_stats(s, &c);
    VERBOSE("elastic gas: %lld collisions, %lld crossings, energy %.17g -> %.17g (%.3g)\n",
            (long long)c.collisions, (long long)c.crossings, k0, k1, k1 / k0 - 1.0);
    ck_assert_msg(c.collisions > 300 && c.crossings > 3 * s->n, "%lld collisions, %lld crossings",
                  (long long)c.collisions, (long long)c.crossings);
    ck_assert_msg(fabs(k1 / k0 - 1.0) < 1e-12, "energy %.17g -> %.17g", k0, k1);
    const double pscale = s->mass * s->n * sqrt(2.0 * k0 / (s->mass * s->n));
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(p1[a] - p0[a]) < 1e-13 * pscale, "momentum %d: %g -> %g", a, p0[a],
                      p1[a]);
    }
    /* the reported positions are in the box */
    for (int i = 0; i < s->n; i++) {
        ck_assert(s->x[i] >= 0.0 && s->x[i] < s->L && s->y[i] >= 0.0 && s->y[i] < s->L &&
                  s->z[i] >= 0.0 && s->z[i] < s->L);
    }
    ck_assert_str_eq(s->kernel_name, kernel);
    gr_sim_free(s);
    free(sc);
}

START_TEST(test_elastic_gas)
{
    elastic_gas("system.N=343", "system.packing_fraction=0.1", "event-3d-cells-nonoise-tc",
                quick() ? 0.01 : 0.03);
    elastic_gas("system.N=27", "system.packing_fraction=0.2", "event-3d-cells-nonoise-tc", 0.1);
    /* 8 spheres at phi = 0.3: a box of 2.4 d, refused */
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.N=8", "system.packing_fraction=0.3", "placement.kind=cubic"};
    load(sc, gas, set, 3);
    gr_sim *s = NULL;
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_create(sc, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "2.41 sphere diameters") && strstr(err.message, "at least 4"),
                  "%s", err.message);
    free(sc);
}
END_TEST

/* Sphere 0 at rest at the centre, sphere 1 at (1.5, by, bz) d from it moving with (-speed, 0, 0):
 * one collision, then compared with the rule on 3-vectors. */
static void oblique(const char *eps_n, const char *eps_t, const char *visco, double by, double bz)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.N=2", "system.L=0.05", eps_n, eps_t, visco, "model.tc=off"};
    load(sc, gas, set, 6);
    gr_sim *s = create(sc);
    struct gr_event_state *e = gr_ev(s);
    const double d = s->d, c = 0.5 * s->L, speed = 0.7;
    const double r0[3] = {c, c, c}, r1[3] = {c + 1.5 * d, c + by * d, c + bz * d};
    const double v1[3] = {-speed, 0.0, 0.0};
    double *b[3] = {e->bx, e->by, e->bz}, *bv[3] = {e->bv, e->bw, e->bu};
    for (int a = 0; a < 3; a++) {
        b[a][0] = r0[a];
        b[a][1] = r1[a];
        bv[a][0] = 0.0;
        bv[a][1] = v1[a];
    }
    gr_event_set_debug(s, true, false); /* predict again from these bases */
    step(s, steps_of(s, 2.0 * d / speed));
    ck_assert_int_eq(s->collisions, 1);
    /* contact: |r1 - speed t x - r0| = d */
    const double bb = (by * by + bz * bz) * d * d, tc = (1.5 * d - sqrt(d * d - bb)) / speed;
    double n[3] = {r0[0] - (r1[0] - speed * tc), r0[1] - r1[1], r0[2] - r1[2]}; /* 1 -> 0 */
    const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    ck_assert(fabs(nn - d) < 1e-12 * d);
    double g[3], gt[3], gn = 0.0;
    for (int a = 0; a < 3; a++) {
        n[a] /= nn;
        g[a] = v1[a]; /* g = v_1 - v_0: sphere 1 is the rule's particle 1 along n */
        gn += g[a] * n[a];
    }
    const gr_contact_coeffs *cc = &s->cc;
    const double en = cc->normal_model->impact(cc, gn).eps_n, et = atof(eps_t + 12);
    double gt2 = 0.0;
    for (int a = 0; a < 3; a++) {
        gt[a] = g[a] - gn * n[a];
        gt2 += gt[a] * gt[a];
    }
    const double vout[2][3] = {
        {0.5 * (1.0 + en) * gn * n[0] + 0.5 * (1.0 - et) * gt[0],
         0.5 * (1.0 + en) * gn * n[1] + 0.5 * (1.0 - et) * gt[1],
         0.5 * (1.0 + en) * gn * n[2] + 0.5 * (1.0 - et) * gt[2]},
        {v1[0] - 0.5 * (1.0 + en) * gn * n[0] - 0.5 * (1.0 - et) * gt[0],
         -0.5 * (1.0 + en) * gn * n[1] - 0.5 * (1.0 - et) * gt[1],
         -0.5 * (1.0 + en) * gn * n[2] - 0.5 * (1.0 - et) * gt[2]}};
    const double *got[3] = {s->vx, s->vy, s->vz};
    for (int i = 0; i < 2; i++) {
        for (int a = 0; a < 3; a++) {
            ck_assert_msg(fabs(got[a][i] - vout[i][a]) < 1e-12 * speed,
                          "%s %s %s b = (%g, %g): v[%d][%d] = %.15g, rule %.15g", eps_n, eps_t,
                          visco, by, bz, i, a, got[a][i], vout[i][a]);
        }
    }
    const double m12 = 0.5 * s->mass;
    const double de_n = 0.5 * m12 * (1.0 - en * en) * gn * gn,
                 de_t = 0.5 * m12 * (1.0 - et * et) * gt2;
    ck_assert_msg(fabs(s->diss_n - de_n) <= 1e-12 * m12 * speed * speed &&
                      fabs(s->diss_t - de_t) <= 1e-12 * m12 * speed * speed,
                  "losses %g %g, rule %g %g", s->diss_n, s->diss_t, de_n, de_t);
    VERBOSE("oblique %s %s %s b = (%g, %g): eps_n %.6f, dE_n %g, dE_t %g J\n", eps_n, eps_t, visco,
            by, bz, en, de_n, de_t);
    gr_sim_free(s);
    free(sc);
}

START_TEST(test_oblique_collisions)
{
    oblique("model.eps_n=0.7", "model.eps_t=0.5", "model.viscoelastic=false", 0.3, 0.5);
    oblique("model.eps_n=0.7", "model.eps_t=0.5", "model.viscoelastic=false", 0.0, 0.0);
    oblique("model.eps_n=0.9", "model.eps_t=1", "model.viscoelastic=false", -0.6, 0.2);
    /* eps_n(v) of the hertz viscoelastic contact: visibly below 1 at this speed */
    oblique("model.eps_n=0.5", "model.eps_t=0.8", "model.viscoelastic=true", 0.1, -0.7);
}
END_TEST

/* Free flight only: the random force injects 3 D (N - 1) / M t (symmetrised), within 5 standard
 * errors of the chi-square spread of sum v^2 (2/3 of it would be 2D's injection). */
static void injection(const char *free_flight)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"system.N=1000", "placement.v0=0", "noise.mode=symmetrised",
                         "noise.D=1e-8", free_flight};
    load(sc, gas, set, 5);
    gr_sim *s = create(sc);
    gr_event_set_debug(s, false, true);
    const double t = 0.01;
    step(s, steps_of(s, t));
    double p[3];
    const double k = kinetic(s, p), want = 3.0 * sc->D * (s->n - 1) / s->mass * gr_sim_time(s);
    const double se = want * sqrt(2.0 / (3.0 * (s->n - 1)));
    VERBOSE("%s: injected %g J, 3 D (N - 1) t / M = %g J (se %g), booked %g\n", free_flight, k,
            want, se, s->injected);
    ck_assert_msg(fabs(k - want) < 5.0 * se, "%s: kinetic energy %g J, expected %g +- %g",
                  free_flight, k, want, se);
    ck_assert_msg(fabs(s->injected - k) < 1e-12 * k, "booked %g, kinetic %g", s->injected, k);
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(p[a]) < 1e-12 * s->mass * s->n * sqrt(k / (s->mass * s->n)),
                      "momentum %d: %g", a, p[a]);
    }
    gr_sim_free(s);
    free(sc);
}

START_TEST(test_injection)
{
    injection("integrator.free_flight=exact");
    injection("integrator.free_flight=kicks");
}
END_TEST

/* Noise, dissipation, the TC rule: the ledger closes to rounding in both free-flight modes. */
START_TEST(test_ledger)
{
    static const char *const modes[] = {"integrator.free_flight=exact",
                                        "integrator.free_flight=kicks"};
    for (int m = 0; m < 2; m++) {
        gr_scene *sc = malloc(sizeof *sc);
        const char *set[] = {"noise.mode=symmetrised", "noise.D=1e-8", "model.eps_n=0.8",
                             "model.eps_t=0.6", "placement.v0=1", modes[m]};
        load(sc, gas, set, 6);
        gr_sim *s = create(sc);
        step(s, steps_of(s, quick() ? 0.02 : 0.05));
        gr_ledger l = gr_sim_ledger(s);
        const double scale = fmax(l.injected + gr_ledger_dissipated(&l), l.initial);
        gr_event_counts c;
        gr_event_stats(s, &c);
        VERBOSE("%s: %lld collisions (%lld TC-elastic), injected %g, dissipated %g + %g, residual "
                "%g\n",
                modes[m], (long long)c.collisions, (long long)c.tc_elastic, l.injected,
                l.dissipated_normal, l.dissipated_tangential, gr_ledger_residual(&l) / scale);
        ck_assert(c.collisions > 1000 && l.dissipated_tangential > 0.0);
        ck_assert_msg(fabs(gr_ledger_residual(&l)) < 1e-10 * scale, "%s: residual %g of %g",
                      modes[m], gr_ledger_residual(&l), scale);
        gr_sim_free(s);
        free(sc);
    }
}
END_TEST

/* A restart from saved bytes continues bit for bit; so does a run in split calls. */
START_TEST(test_restart)
{
    gr_scene *sc = malloc(sizeof *sc);
    const char *set[] = {"noise.mode=symmetrised", "noise.D=1e-8", "model.eps_n=0.8",
                         "integrator.free_flight=exact", "placement.v0=1"};
    load(sc, gas, set, 5);
    gr_sim *a = create(sc);
    const int64_t total = steps_of(a, 0.01), first = total / 3 + 7;
    step(a, total);
    gr_sim *b = create(sc);
    step(b, first);
    step(b, total - first);
    assert_same_state(a, b);
    gr_event_counts ca, cb;
    gr_event_stats(a, &ca);
    gr_event_stats(b, &cb);
    ck_assert(ca.collisions > 100 && ca.collisions == cb.collisions &&
              ca.crossings == cb.crossings);
    gr_sim_free(a);
    gr_sim_free(b);
    assert_restart_exact(sc, total, first);
    free(sc);
}
END_TEST

/* Rough spheres need spin vectors: refused (by the scene at its key, and by the library). */
START_TEST(test_refusals)
{
    gr_scene *sc = malloc(sizeof *sc);
    gr_error err = {0};
    const char *rough[] = {"model.rotation=true", "model.beta=0.5"};
    ck_assert_int_eq(gr_scene_load_buffer(sc, "test.ini", gas, strlen(gas), rough, 2, &err),
                     GR_EINVAL);
    ck_assert_msg(strstr(err.message, "rotation") && strstr(err.message, "dim = 3"), "%s",
                  err.message);
    load(sc, gas, NULL, 0);
    gr_sim_params p;
    gr_scene_sim_params(sc, &p);
    p.contact.rotation = true;
    gr_sim *s = NULL;
    ck_assert_int_eq(gr_sim_new(&p, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "rotation"), "%s", err.message);
    free(sc);
}
END_TEST

static Suite *event_3d_suite(void)
{
    Suite *s = suite_create("event-3d");
    TCase *tc = tcase_create("spheres");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, test_elastic_gas);
    tcase_add_test(tc, test_oblique_collisions);
    tcase_add_test(tc, test_injection);
    tcase_add_test(tc, test_ledger);
    tcase_add_test(tc, test_restart);
    tcase_add_test(tc, test_refusals);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(event_3d_suite()); }
