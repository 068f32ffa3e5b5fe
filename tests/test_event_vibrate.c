/* The event-driven integrator's vibrating wall and rough grains at walls (issue 36;
 * docs/systems-walls-gravity.md, "Event-driven"):
 *  - the moving wall's contact time (gr_ev_moving_wall_first) against a brute-force root of the
 *    gap h(t) = q(t) - r - q_w(t) in long double (a fine scan, then bisection): sine and sawtooth,
 *    with and without gravity, agree within 1e-12 s and no earlier contact is missed;
 *  - a ball dropped on a vibrating floor under gravity: the time of its first hit (the TC clock,
 *    e->last) is the brute-force root within 1e-12 s, its rebound speed 2 v_w - v;
 *  - one elastic grain between a sinusoidal (and a sawtooth) floor and a fixed ceiling without
 *    gravity, 2D and 3D: its kinetic energy changes by exactly the wall's work (ledger to 1e-12);
 *  - a vibrated bed of inelastic grains under gravity, 2D and 3D: the ledger closes to 1e-12 and
 *    no grain ever lies inside the moving floor (overlap checks after every event);
 *  - a spinning rough disc (and sphere) dropped on a floor: Walton's rule at an infinite mass, the
 *    contact point's tangential velocity -beta times itself, the angular momentum about the contact
 *    point conserved, the normal velocity -eps_n times itself;
 *  - viscoelastic grains (eps_n(v)) at a floor: hertz's eps_n(v) of the grain's mass and speed;
 *  - 1D: a rod of grains between two walls (energy, the first bounce's loss, a vibrating floor).
 * GRANULE_TEST_QUICK=1 shortens the runs. */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "integrators/event/event_internal.h"
#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "test_env.h"
#include "test_scenes.h"

#define RADIUS 1.5e-3

static double uniform(uint64_t *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*st >> 11) / 9007199254740992.0;
}

/* the wall's position in long double (the same formulas as gr_walls_motion) */
static long double wall_q(const gr_sim_params *p, long double t)
{
    if (p->motion == GR_WALL_SAWTOOTH) {
        const long double ph = p->frequency * t + 0.5L;
        return p->amplitude * (2.0L * (ph - floorl(ph)) - 1.0L);
    }
    return p->amplitude * sinl(2.0L * 3.14159265358979323846264338327950288L * p->frequency * t);
}

static long double gap(const gr_sim_params *p, long double tw, double q0, double v0, double a,
                       long double u)
{
    return q0 + u * (v0 + 0.5L * a * u) - RADIUS - wall_q(p, tw + u);
}

/* brute force: the first grid point with h <= 0 after a positive one, then bisection */
static long double brute_first(const gr_sim_params *p, long double tw, double q0, double v0,
                               double a, double T)
{
    const int n = 20000;
    long double lo = 0.0L;
    if (gap(p, tw, q0, v0, a, 0.0L) <= 0.0L) {
        return -1.0L; /* starts inside: not used */
    }
    for (int k = 1; k <= n; k++) {
        const long double u = (long double)T * k / n;
        if (gap(p, tw, q0, v0, a, u) <= 0.0L) {
            long double hi = u;
            for (int it = 0; it < 200 && hi - lo > 1e-18L; it++) {
                const long double m = 0.5L * (lo + hi);
                if (gap(p, tw, q0, v0, a, m) > 0.0L) {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            return lo;
        }
        lo = u;
    }
    return INFINITY;
}

START_TEST(test_root_brute)
{
    uint64_t st = 36;
    int found = 0, none = 0;
    const int cases = quick() ? 60 : 400;
    for (int k = 0; k < cases; k++) {
        gr_sim_params p = {0};
        p.motion = k % 3 == 2 ? GR_WALL_SAWTOOTH : GR_WALL_SINE;
        p.amplitude = 1e-3 + 4e-3 * uniform(&st);
        p.frequency = 5.0 + 45.0 * uniform(&st);
        const double tw = 10.0 * uniform(&st);
        const double q0 = RADIUS + 6e-3 + 0.02 * uniform(&st);
        const double v0 = 0.6 * (uniform(&st) - 0.7);
        const double a = k % 2 ? -9.81 : 0.0;
        const double T = 0.1;
        const double w = 2.0 * M_PI * p.frequency;
        const double C = fabs(a) + (p.motion == GR_WALL_SINE ? p.amplitude * w * w : 0.0);
        /* as the integrator calls it: a checkpoint (h > 0) is followed by a new call there */
        double u = 0.0, t = GR_EV_INF;
        for (int calls = 0; calls < 1000; calls++) {
            const double q = q0 + u * (v0 + 0.5 * a * u), v = v0 + a * u;
            const double x = gr_ev_moving_wall_first(&p, tw + u, q, v, a, RADIUS, C, T - u);
            if (x == GR_EV_INF) {
                break;
            }
            if (gap(&p, tw, q0, v0, a, u + x) > 1e-9 * 2.0 * RADIUS) {
                u += x;
                continue;
            }
            t = u + x;
            break;
        }
        const long double tb = brute_first(&p, tw, q0, v0, a, T);
        if (t == GR_EV_INF) {
            ck_assert_msg(tb == INFINITY, "case %d: no contact found, brute force has %.15Lg s", k,
                          tb);
            none++;
            continue;
        }
        found++;
        ck_assert_msg(tb != INFINITY, "case %d: contact at %.15g s, brute force has none", k, t);
        ck_assert_msg(fabsl((long double)t - tb) <= 1e-12L,
                      "case %d: contact at %.17g s, brute "
                      "force %.17Lg s (%s)",
                      k, t, tb, p.motion ? "sawtooth" : "sine");
    }
    ck_assert_msg(found > cases / 4 && none > cases / 20, "found %d, none %d", found, none);
}
END_TEST

/* One grain in a box with y walls (3D: z walls), the floor vibrating; no noise. */
static gr_sim *box(int dim, int n, const char *motion, const char *g, const char *eps,
                   const char *rough)
{
    char nbuf[32], gbuf[40], ebuf[40], mbuf[48];
    snprintf(nbuf, sizeof nbuf, "system.N=%d", n);
    snprintf(gbuf, sizeof gbuf, dim == 3 ? "gravity.gz=%s" : "gravity.gy=%s", g);
    snprintf(ebuf, sizeof ebuf, "model.eps_n=%s", eps);
    snprintf(mbuf, sizeof mbuf, "boundary.motion=%s", motion);
    const char *ov[26] = {dim == 3 ? "system.dim=3" : "system.dim=2",
                          nbuf,
                          "system.L=0.06",
                          "system.radius=1.5e-3",
                          "system.mass=3.53e-5",
                          dim == 3 ? "placement.kind=random" : "placement.kind=uniform",
                          "placement.v0=0.3",
                          "model.normal=hard_sphere",
                          ebuf,
                          "model.eps_t=1",
                          "noise.mode=none",
                          dim == 3 ? "boundary.z=walls" : "boundary.y=walls",
                          dim == 3 ? "boundary.vibrate=z" : "boundary.vibrate=y",
                          "boundary.amplitude=0.004",
                          "boundary.frequency=25",
                          mbuf,
                          gbuf,
                          "integrator.kind=event",
                          "run.seed=5"};
    int k = 19;
    if (dim == 3) {
        ov[k++] = "boundary.x=walls"; /* a small box: walls all round */
        ov[k++] = "boundary.y=walls";
    }
    if (rough) { /* rough grains, beta = 0.4, and one more key */
        ov[k++] = "model.rotation=true";
        ov[k++] = "model.beta=0.4";
        ov[k++] = rough;
    }
    gr_scene sc = scene_of(ov, k);
    return sim_of(&sc);
}

static double kinetic(const gr_sim *s) { return gr_sim_ledger((gr_sim *)s).kinetic; }

/* an elastic grain, no gravity: the kinetic energy changes by the wall's work, exactly */
static void elastic_work(int dim, const char *motion)
{
    gr_sim *s = box(dim, 1, motion, "0", "1", NULL);
    gr_error err = {0};
    const double k0 = kinetic(s);
    gr_event_set_debug(s, true, false);
    const int64_t steps = (int64_t)llround((quick() ? 0.5 : 2.0) / s->dt);
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    gr_ledger l = gr_sim_ledger(s);
    gr_event_counts c;
    gr_event_stats(s, &c);
    const double dk = l.kinetic - k0;
    VERBOSE("%dD %s: %lld wall hits, kinetic %.6g -> %.6g J, wall work %.6g J, injected %.3g J "
            "(floors %lld: %.3g J)\n",
            dim, motion, (long long)c.wall_hits, k0, l.kinetic, l.wall_work, l.injected,
            (long long)c.floors, c.floor_energy);
    ck_assert_msg(c.wall_hits >= (quick() ? 3 : 10), "%lld wall hits", (long long)c.wall_hits);
    ck_assert_msg(fabs(l.wall_work) > 1e-3 * k0, "wall work %g J", l.wall_work);
    ck_assert_msg(fabs(dk - l.wall_work) <= 1e-12 * (k0 + fabs(l.wall_work)),
                  "%dD %s: kinetic energy changed by %.17g J, the wall's work %.17g J", dim, motion,
                  dk, l.wall_work);
    /* nothing else: no losses, and the free flights' booked work is rounding */
    ck_assert_msg(l.dissipated_normal == 0.0 &&
                      fabs(l.injected) <= 1e-12 * (k0 + fabs(l.wall_work)),
                  "dissipated %g J, injected %g J", l.dissipated_normal, l.injected);
    gr_sim_free(s);
}

START_TEST(test_elastic_work_2d)
{
    elastic_work(2, "sine");
    elastic_work(2, "sawtooth");
}
END_TEST

START_TEST(test_elastic_work_3d)
{
    elastic_work(3, "sine");
    elastic_work(3, "sawtooth");
}
END_TEST

/* A ball dropped from rest under gravity onto the sinusoidal floor: the first hit at the
 * brute-force root, the rebound 2 v_w - v (eps_n = 1). */
START_TEST(test_drop_time)
{
    for (int dim = 2; dim <= 3; dim++) {
        gr_sim *s = box(dim, 1, "sine", "-9.81", "1", NULL);
        struct gr_event_state *e = gr_ev(s);
        const double h0 = 0.02;
        e->bv[0] = 0.0;
        e->bw[0] = 0.0;
        if (dim == 3) {
            e->bu[0] = 0.0;
            e->bz[0] = h0;
        } else {
            e->by[0] = h0;
        }
        gr_event_set_debug(s, true, false);
        const long double tb = brute_first(&s->params, 0.0L, h0, 0.0, -9.81, 0.2);
        ck_assert(tb > 0.0L && tb < 0.2L);
        gr_error err = {0};
        const int64_t steps = (int64_t)ceil((double)tb / s->dt) + 2;
        ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
        gr_event_counts c;
        gr_event_stats(s, &c);
        ck_assert_msg(c.wall_hits == 1, "%lld wall hits", (long long)c.wall_hits);
        VERBOSE("%dD: hit at %.17g s, brute force %.17Lg s\n", dim, e->last[0], tb);
        ck_assert_msg(fabsl((long double)e->last[0] - tb) <= 1e-12L,
                      "%dD: hit at %.17g s, brute force %.17Lg s", dim, e->last[0], tb);
        double qw, vw;
        gr_walls_motion(&s->params, e->last[0], &qw, &vw);
        const double v_in = -9.81 * e->last[0]; /* and after the hit, back to that instant: */
        const double v_out =
            (dim == 3 ? s->vz[0] : s->vy[0]) + 9.81 * (gr_sim_time(s) - e->last[0]);
        ck_assert_msg(fabs(v_out - (2.0 * vw - v_in)) <= 1e-13,
                      "rebound %.17g m/s, expected 2 v_w - v = %.17g", v_out, 2.0 * vw - v_in);
        gr_sim_free(s);
    }
}
END_TEST

/* a vibrated bed of inelastic grains: the ledger closes, no grain enters the moving floor */
static void bed(int dim, const char *motion, const char *rough)
{
    gr_sim *s = box(dim, dim == 3 ? 60 : 40, motion, "-9.81", "0.8", rough);
    gr_event_set_debug(s, true, false);
    gr_error err = {0};
    const int chunks = quick() ? 10 : 40;
    const int64_t steps = (int64_t)llround(0.02 / s->dt);
    const double r = 0.5 * s->d;
    const double *q = dim == 3 ? s->z : s->y;
    double worst = 0.0;
    for (int c = 0; c < chunks; c++) {
        ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
        double qw, vw;
        gr_walls_motion(&s->params, gr_sim_time(s), &qw, &vw);
        for (int i = 0; i < s->n; i++) {
            worst = fmax(worst, qw + r - q[i]);
        }
    }
    gr_ledger l = gr_sim_ledger(s);
    gr_event_counts c;
    gr_event_stats(s, &c);
    const double scale = l.initial + fabs(l.wall_work) + gr_ledger_dissipated(&l);
    VERBOSE("%dD bed %s: %lld wall hits, %lld collisions, wall work %.6g J, dissipated %.6g J, "
            "residual %.3g J, deepest %.3g m\n",
            dim, motion, (long long)c.wall_hits, (long long)c.collisions, l.wall_work,
            gr_ledger_dissipated(&l), gr_ledger_residual(&l), worst);
    ck_assert_msg(c.wall_hits > 20 && c.collisions > 20, "%lld wall hits, %lld collisions",
                  (long long)c.wall_hits, (long long)c.collisions);
    ck_assert_msg(l.wall_work > 0.0, "wall work %g J", l.wall_work);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) <= 1e-12 * scale, "%dD %s: residual %.3g of %.3g J",
                  dim, motion, gr_ledger_residual(&l), scale);
    ck_assert_msg(worst <= 1e-9 * s->d, "a grain %.3g m inside the floor", worst);
    gr_sim_free(s);
}

START_TEST(test_bed_ledger)
{
    bed(2, "sine", NULL);
    bed(2, "sawtooth", NULL);
    bed(3, "sine", NULL);
    /* rough grains (Walton, sliding at the Coulomb limit too): the spins' energy in the ledger */
    bed(2, "sine", "model.beta_mu=0.3");
    bed(3, "sawtooth", "model.beta_mu=0.3");
}
END_TEST

/* A spinning rough grain dropped on the floor (fixed: amplitude 0) without gravity: Walton's rule
 * against an infinite mass. Contact point c = v_x + w R (2D; floor normal -y), after the hit
 * -beta c; L = I w - M R v_x about the contact point conserved; v_y -> -eps_n v_y. */
START_TEST(test_rough_drop)
{
    for (int dim = 2; dim <= 3; dim++) {
        gr_sim *s = box(dim, 1, "sine", "0", "0.7", "model.beta_mu=0"); /* sticking */
        struct gr_event_state *e = gr_ev(s);
        ck_assert(e->rough);
        s->params.amplitude = 0.0; /* a fixed floor (the vibrating path, its wall at rest) */
        const double vx = 0.2, vn = -0.5, w = 80.0, R = e->R, M = e->M, I = s->inertia;
        e->bv[0] = vx;
        if (dim == 3) {
            e->bw[0] = 0.0;
            e->bu[0] = vn;
            e->bz[0] = 0.01;
            s->wx[0] = 0.0;
            s->wy[0] = -w; /* about -y: the contact point (0, 0, -R) moves at v_x + w R along x */
            s->omega[0] = 0.0;
        } else {
            e->bw[0] = vn;
            e->by[0] = 0.01;
            s->omega[0] = w; /* z: the contact point (0, -R) moves at v_x + w R along x */
        }
        gr_event_set_debug(s, true, false);
        gr_error err = {0};
        const int64_t steps = (int64_t)llround(0.03 / s->dt);
        ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
        gr_event_counts c;
        gr_event_stats(s, &c);
        ck_assert_msg(c.wall_hits == 1, "%lld wall hits", (long long)c.wall_hits);
        const double spin = dim == 3 ? -s->wy[0] : s->omega[0];
        const double ux = e->bv[0], un = dim == 3 ? e->bu[0] : e->bw[0];
        const double c0 = vx + w * R, c1 = ux + spin * R;
        const double L0 = I * w - M * R * vx, L1 = I * spin - M * R * ux;
        VERBOSE("%dD rough: c %.6g -> %.6g, L %.6g -> %.6g, v_n %.3g -> %.3g\n", dim, c0, c1, L0,
                L1, vn, un);
        ck_assert_msg(fabs(c1 + 0.4 * c0) <= 1e-13 * fabs(c0), "contact point %.17g -> %.17g", c0,
                      c1);
        ck_assert_msg(fabs(L1 - L0) <= 1e-13 * fabs(L0), "angular momentum %.17g -> %.17g", L0, L1);
        ck_assert_msg(fabs(un + 0.7 * vn) <= 1e-14, "normal velocity %.17g -> %.17g", vn, un);
        if (dim == 3) {
            ck_assert(e->bw[0] == 0.0 && s->wx[0] == 0.0 && s->omega[0] == 0.0);
        }
        /* the loss booked is Walton's at the wall: m_t = M q / (1 + q) */
        const double q = e->q, m_t = M * q / (1.0 + q);
        const double lost = 0.5 * M * (1.0 - 0.49) * vn * vn + 0.5 * m_t * (1.0 - 0.16) * c0 * c0;
        gr_ledger l = gr_sim_ledger(s);
        ck_assert_msg(fabs(gr_ledger_dissipated(&l) - lost) <= 1e-13 * lost,
                      "dissipated %.17g J, Walton %.17g J", gr_ledger_dissipated(&l), lost);
        gr_sim_free(s);
    }
}
END_TEST

/* viscoelastic hard grains (eps_n(v)) at a fixed floor, 2D and 3D, no gravity: the rebound speed
 * over the impact speed is hertz's eps_n(v) for the grain's own mass against the infinite wall
 * (reduced mass M, impact speed v; not the mirror pair's M / 2 at 2 v), and the Schwager-Poeschel
 * series 1 - C1 b + C2 b^2, b = (3/2) A (k_h / M)^(2/5) v^(1/5), to its truncation O(b^3) */
START_TEST(test_wall_viscoelastic)
{
    const double speeds[] = {0.05, 0.5, 2.0};
    const double k_h = 1e9, A = 2e-7, M = 3.53e-5;
    for (int dim = 2; dim <= 3; dim++) {
        const char *ov[] = {dim == 3 ? "system.dim=3" : "system.dim=2",
                            "system.N=1",
                            "system.L=0.06",
                            "system.radius=1.5e-3",
                            "system.mass=3.53e-5",
                            dim == 3 ? "placement.kind=random" : "placement.kind=uniform",
                            "model.normal=hard_sphere",
                            "model.viscoelastic=true",
                            "model.k_h=1e9",
                            "model.visco_A=2e-7",
                            "noise.mode=none",
                            dim == 3 ? "boundary.z=walls" : "boundary.y=walls",
                            "integrator.kind=event"};
        gr_scene sc = scene_of(ov, 13);
        const gr_contact_coeffs hc = hertz_of(&sc, M);
        gr_error err = {0};
        for (int k = 0; k < 3; k++) {
            const double v = speeds[k];
            gr_sim *s = sim_of(&sc);
            struct gr_event_state *e = gr_ev(s);
            e->bv[0] = 0.0;
            e->bw[0] = dim == 3 ? 0.0 : -v;
            if (dim == 3) {
                e->bu[0] = -v;
                e->bz[0] = 0.03;
            } else {
                e->by[0] = 0.03;
            }
            gr_event_set_debug(s, true, false);
            ck_assert(gr_sim_step(s, (int64_t)ceil(0.03 / v / s->dt), &err) == GR_OK);
            gr_event_counts c;
            gr_event_stats(s, &c);
            ck_assert_int_eq(c.wall_hits, 1);
            const double eps = (dim == 3 ? s->vz[0] : s->vy[0]) / v;
            const double hertz = hc.normal_model->impact(&hc, v).eps_n;
            const double b = 1.5 * A * pow(k_h / M, 0.4) * pow(v, 0.2);
            const double series = 1.0 - 1.15344 * b + 0.79826 * b * b;
            VERBOSE("%dD wall, v = %g: eps %.12f, hertz %.12f, series %.12f\n", dim, v, eps, hertz,
                    series);
            ck_assert_msg(fabs(eps - hertz) <= 1e-12, "%dD v = %g: eps %.15g, hertz %.15g", dim, v,
                          eps, hertz);
            ck_assert_msg(fabs(eps - series) <= 2.0 * b * b * b, "v = %g: eps %.15g, series %.15g",
                          v, eps, series);
            gr_ledger l = gr_sim_ledger(s);
            const double e0 = 0.5 * M * v * v; /* the state set here: kinetic + lost = e0 */
            ck_assert_msg(fabs(l.kinetic + gr_ledger_dissipated(&l) - e0) <= 1e-13 * e0,
                          "kinetic %.17g + dissipated %.17g J, before %.17g J", l.kinetic,
                          gr_ledger_dissipated(&l), e0);
            gr_sim_free(s);
        }
    }
}
END_TEST

/* A rod of hard grains between two walls (1D, [boundary] x = walls): ten elastic grains without
 * gravity keep their energy and stay within [r, L - r]; a grain dropped from rest onto the floor
 * under gx (eps_n = 0.9, no TC) first loses (1 - eps_n^2) M g (h - r); ten inelastic grains
 * on a vibrating floor under gx: the ledger closes and the wall works. */
static gr_sim *rod(int n, const char *g, const char *eps, const char *tc, bool vibrate)
{
    char nbuf[32], gbuf[40], ebuf[40], tbuf[40];
    snprintf(nbuf, sizeof nbuf, "system.N=%d", n);
    snprintf(gbuf, sizeof gbuf, "gravity.gx=%s", g);
    snprintf(ebuf, sizeof ebuf, "model.eps_n=%s", eps);
    snprintf(tbuf, sizeof tbuf, "model.tc=%s", tc);
    const char *ov[20] = {"system.dim=1",
                          nbuf,
                          "system.L=0.1",
                          "system.radius=1.5e-3",
                          "system.mass=3.53e-5",
                          "placement.kind=uniform",
                          n == 1 ? "placement.v0=0" : "placement.v0=0.3",
                          "model.normal=hard_sphere",
                          ebuf,
                          tbuf,
                          "noise.mode=none",
                          "boundary.x=walls",
                          gbuf,
                          "integrator.kind=event",
                          "run.seed=7"};
    int k = 15;
    if (vibrate) {
        ov[k++] = "boundary.vibrate=x";
        ov[k++] = "boundary.amplitude=0.003";
        ov[k++] = "boundary.frequency=20";
    }
    gr_scene sc = scene_of(ov, k);
    gr_sim *s = sim_of(&sc);
    gr_event_set_debug(s, true, false); /* overlap checks after every event */
    return s;
}

START_TEST(test_rod_1d)
{
    gr_error err = {0};
    /* elastic, no gravity */
    gr_sim *s = rod(10, "0", "1", "0", false);
    const double r = 0.5 * s->d, e0 = kinetic(s);
    double worst = 0.0;
    for (int c = 0; c < (quick() ? 5 : 20); c++) {
        ck_assert_msg(gr_sim_step(s, (int64_t)llround(0.05 / s->dt), &err) == GR_OK, "%s",
                      err.message);
        for (int i = 0; i < s->n; i++) {
            worst = fmax(worst, fmax(r - s->x[i], s->x[i] - (s->L - r)));
        }
    }
    gr_event_counts c;
    gr_event_stats(s, &c);
    VERBOSE("1D rod: %lld wall hits, %lld collisions, energy %.17g -> %.17g J\n",
            (long long)c.wall_hits, (long long)c.collisions, e0, kinetic(s));
    ck_assert_msg(c.wall_hits >= (quick() ? 2 : 8) && c.collisions >= (quick() ? 5 : 40),
                  "%lld wall hits, %lld collisions", (long long)c.wall_hits,
                  (long long)c.collisions);
    ck_assert_msg(fabs(kinetic(s) - e0) <= 1e-13 * e0, "energy %.17g -> %.17g J", e0, kinetic(s));
    ck_assert_msg(worst <= 1e-12, "a centre %.3g m beyond [r, L - r]", worst);
    gr_sim_free(s);
    /* one grain dropped from L / 2 under gx: the first bounce's loss */
    s = rod(1, "-9.81", "0.9", "off", false);
    const double h = s->x[0], M = s->mass, g = 9.81, t1 = sqrt(2.0 * (h - r) / g);
    ck_assert_msg(gr_sim_step(s, (int64_t)llround(1.5 * t1 / s->dt), &err) == GR_OK, "%s",
                  err.message);
    gr_event_stats(s, &c);
    gr_ledger l = gr_sim_ledger(s);
    const double lost = (1.0 - 0.81) * M * g * (h - r);
    ck_assert_msg(c.wall_hits == 1, "%lld wall hits", (long long)c.wall_hits);
    ck_assert_msg(fabs(l.dissipated_normal - lost) <= 1e-12 * lost, "lost %.17g J, expected %.17g",
                  l.dissipated_normal, lost);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) <= 1e-12 * l.initial, "residual %.3g of %.3g J",
                  gr_ledger_residual(&l), l.initial);
    gr_sim_free(s);
    /* a vibrating floor under gravity: the ledger closes */
    s = rod(10, "-9.81", "0.8", "0", true);
    ck_assert_msg(gr_sim_step(s, (int64_t)llround((quick() ? 0.2 : 1.0) / s->dt), &err) == GR_OK,
                  "%s", err.message);
    gr_event_stats(s, &c);
    l = gr_sim_ledger(s);
    const double scale = l.initial + fabs(l.wall_work) + gr_ledger_dissipated(&l);
    VERBOSE("1D vibrated rod: %lld wall hits, wall work %.6g J, residual %.3g J\n",
            (long long)c.wall_hits, l.wall_work, gr_ledger_residual(&l));
    ck_assert_msg(c.wall_hits > 20 && l.wall_work > 0.0, "%lld wall hits, wall work %g J",
                  (long long)c.wall_hits, l.wall_work);
    ck_assert_msg(fabs(gr_ledger_residual(&l)) <= 1e-12 * scale, "residual %.3g of %.3g J",
                  gr_ledger_residual(&l), scale);
    gr_sim_free(s);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("event_vibrate");
    TCase *tc = tcase_create("core");
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_root_brute);
    tcase_add_test(tc, test_elastic_work_2d);
    tcase_add_test(tc, test_elastic_work_3d);
    tcase_add_test(tc, test_drop_time);
    tcase_add_test(tc, test_bed_ledger);
    tcase_add_test(tc, test_rough_drop);
    tcase_add_test(tc, test_wall_viscoelastic);
    tcase_add_test(tc, test_rod_1d);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
