/* hard_sphere: the instantaneous collision rule of the event-driven integrator (thesis 2.1, 2.2,
 * 2.10): momentum conserved, the normal relative velocity reversed and scaled by eps_n, the
 * tangential relative velocity scaled by eps_t (same sign, eq. 2.10), so a collision at impact
 * angle a loses (1 - eps_n^2) cos^2 a + (1 - eps_t^2) sin^2 a of the relative kinetic energy
 * (2.13, 2.14). The rule is gr_event_collide below.
 *
 * Inelastic collapse is cured by the TC model (Luding & McNamara, Granular Matter 1, 113 (1998);
 * ../shared/notes/physics-algorithms.md sec. 2): a collision is elastic if either particle
 * collided less than t_c ago. t_c defaults to the contact duration of the matching linear
 * spring-dashpot (k_s, eps_n; eq. 2.6, unclamped), so event-driven and soft-sphere runs stop
 * dissipating in the same multi-contact situations; `tc` overrides it. The matching contact also
 * sets the nominal clock tick dt = t_c / steps_per_contact (the step of gr_sim_step). */
#ifndef GR_MODELS_HARD_SPHERE_H
#define GR_MODELS_HARD_SPHERE_H

#include <math.h>

#include "models/hertz.h"
#include "models/law.h"

extern const gr_model gr_model_hard_sphere;

/* its own parameters (gr_contact_params.own); viscoelastic = true uses hertz's (k_h, visco_A) */
typedef struct hard_sphere_own {
    double tc;   /* TC-model time, s; 0 = the k_s contact's duration t_c; GR_TC_OFF = no TC rule */
    double beta; /* rotation: tangential restitution at the contact point, [-1, 1] */
    double beta_mu; /* rotation: Coulomb limit of the tangential impulse (0: none) */
} hard_sphere_own;

/* The rule itself: the instantaneous collision of two equal masses (thesis eqs. 2.1, 2.2, 2.10),
 * called by the event-driven integrator (src/integrators/event/) and by
 * `granule collide --model hard_sphere`.
 *
 * With n the unit normal from particle 1 to particle 2 and g = v1 - v2 (so g.n > 0 when the pair
 * approaches), t the unit tangent:
 *   (v1' + v2') = (v1 + v2)                     momentum (2.1)
 *   (v2' - v1').n = eps_n (v1 - v2).n           normal restitution (2.2)
 *   (v1' - v2').t = eps_t (v1 - v2).t           tangential restitution (2.10), same sign
 * hence v1' = v1 - (1 + eps_n)/2 (g.n) n - (1 - eps_t)/2 (g.t) t and v2' = v2 + (the same).
 * The relative kinetic energy m12 |g|^2 / 2 (m12 = M/2) loses
 *   dE_n = m12/2 (1 - eps_n^2) (g.n)^2,   dE_t = m12/2 (1 - eps_t^2) (g.t)^2,
 * i.e. the fraction 1 - eps^2 head-on (2.13) and 1 - (eps_n^2 + eps_t^2)/2 at 45 degrees (2.14). */
/* Apply the rule to (v1, v2) in place (2D: components x, y; 1D: pass y components of 0 and
 * n = (+-1, 0)). Returns the dissipated energies in *de_n, *de_t (J) for particles of mass M. */
static inline void gr_event_collide(double M, double eps_n, double eps_t, double nx, double ny,
                                    double *v1x, double *v1y, double *v2x, double *v2y,
                                    double *de_n, double *de_t)
{
    const double gx = *v1x - *v2x, gy = *v1y - *v2y;
    const double gn = gx * nx + gy * ny;
    const double gt = gy * nx - gx * ny; /* t = (-ny, nx) */
    const double jn = 0.5 * (1.0 + eps_n) * gn, jt = 0.5 * (1.0 - eps_t) * gt;
    const double dx = jn * nx - jt * ny, dy = jn * ny + jt * nx;
    *v1x -= dx;
    *v1y -= dy;
    *v2x += dx;
    *v2y += dy;
    *de_n = 0.25 * M * (1.0 - eps_n * eps_n) * gn * gn;
    *de_t = 0.25 * M * (1.0 - eps_t * eps_t) * gt * gt;
}

/* Rough discs (rotation = true): Walton's rule (O. R. Walton, in Particulate Two-Phase Flow,
 * ed. Roco, 1993; S. Luding, M. Huthmann, S. McNamara, A. Zippelius, PRE 58, 3416 (1998),
 * eqs. 2-7). Discs of mass M, radius R, moment of inertia I = q M R^2, spins w (counterclockwise).
 * The contact point's relative tangential velocity (surface of 1 minus surface of 2) is
 *   g_ct = g.t + R (w1 + w2)                     (t = (-ny, nx), as above)
 * and the impulse P = P_n n + P_t t on 1 (-P on 2; torque R P_t on both discs) gives
 *   g.n' = -eps_n g.n,  g_ct' = -beta g_ct,
 *   P_n = -(1 + eps_n) m12 g.n,  P_t = -(1 + beta) m_t g_ct,  m12 = M / 2,  m_t = m12 q / (1 + q).
 * beta = -1: smooth (no tangential impulse, spins untouched); beta = +1: perfectly rough (g_ct
 * reversed, energy conserved). Coulomb limit mu > 0 (Walton; Luding et al. 1998 eq. 7): the
 * pair slides when the sticking impulse exceeds mu |P_n|, i.e. beta is replaced by
 *   beta(g) = min(beta0, -1 + mu (1 + eps_n) (1 + 1/q) |g.n| / |g_ct|),
 * so |P_t| = mu |P_n| when sliding. The loss of translational + rotational kinetic energy:
 *   dE_n = m12/2 (1 - eps_n^2) (g.n)^2,   dE_t = m_t/2 (1 - beta^2) g_ct^2   (beta after the limit).
 * Returns the beta used (beta0, or the Coulomb value when the pair slid). Rough spheres (3D): the
 * event core applies this rule in the plane of n and the contact point's relative tangential
 * velocity g_c = g_t + R (w1 + w2) x n, with the spin vectors' components along n x t as w1, w2
 * (gr_event_rule_3d, models/list.h). */
static inline double gr_event_collide_rough(double M, double q, double R, double eps_n,
                                            double beta0, double mu, double nx, double ny,
                                            double *v1x, double *v1y, double *v2x, double *v2y,
                                            double *w1, double *w2, double *de_n, double *de_t)
{
    const double gx = *v1x - *v2x, gy = *v1y - *v2y;
    const double gn = gx * nx + gy * ny;
    const double gct = gy * nx - gx * ny + R * (*w1 + *w2);
    const double m12 = 0.5 * M, m_t = m12 * q / (1.0 + q);
    double beta = beta0;
    if (mu > 0.0 && (1.0 + beta0) * m_t * fabs(gct) > mu * (1.0 + eps_n) * m12 * fabs(gn)) {
        beta = -1.0 + mu * (1.0 + eps_n) * (1.0 + 1.0 / q) * fabs(gn) / fabs(gct); /* sliding */
    }
    /* velocity changes of 1 (2 gets the opposite): P / M */
    const double jn = 0.5 * (1.0 + eps_n) * gn, jt = (1.0 + beta) * m_t * gct / M;
    const double dx = jn * nx - jt * ny, dy = jn * ny + jt * nx;
    *v1x -= dx;
    *v1y -= dy;
    *v2x += dx;
    *v2y += dy;
    const double dw = -(1.0 + beta) * m_t * gct * R / (q * M * R * R); /* R P_t / I, both discs */
    *w1 += dw;
    *w2 += dw;
    *de_n = 0.25 * M * (1.0 - eps_n * eps_n) * gn * gn;
    *de_t = 0.5 * m_t * (1.0 - beta * beta) * gct * gct;
    return beta;
}

/* The rule's constants, which its prepare sets and the event integrator and `granule collide`
 * read (never the parameters themselves): in gr_contact_coeffs.law_n, 1 with viscoelastic = true
 * and the hertz contact's damping and stiffness that set eps_n(v); in law_t, eps_t, Walton's
 * beta and its Coulomb limit beta_mu (rotation = true). */
enum { GR_HARD_SPHERE_VISCO = 0, GR_HARD_SPHERE_GAMMA = 1, GR_HARD_SPHERE_KH = 2 };
enum { GR_HARD_SPHERE_EPS_T = 0, GR_HARD_SPHERE_BETA = 1, GR_HARD_SPHERE_BETA_MU = 2 };

/* viscoelastic hard discs: the smallest eps_n used (an impact that would stick, eps_n(v) = 0,
 * would leave the pair touching at zero normal speed and stall the event calendar) */
#define GR_HARD_SPHERE_MIN_EPS 1e-3

/* The rule as the event-driven integrator and `granule collide` call it (models/law.h,
 * gr_event_pair): smooth discs get gr_event_collide with eps_n and eps_t, rough ones
 * (p->w1 != NULL) Walton's gr_event_collide_rough with beta and its Coulomb limit. eps_n is the
 * constant eps_n, or with viscoelastic = true the hertz contact's eps_n(v) at the normal approach
 * speed (the model's impact: one call per collision). A TC-elastic collision has eps_n = 1 and no
 * tangential loss (eps_t = 1; rough discs: smooth, beta = -1). */
GR_LAW void gr_event_rule_hard_sphere(const gr_contact_coeffs *c, gr_event_pair *p)
{
    double eps_n = 1.0;
    if (!p->elastic) {
        const double gn = (p->v1x - p->v2x) * p->nx + (p->v1y - p->v2y) * p->ny;
        eps_n = c->law_n[GR_HARD_SPHERE_VISCO] != 0.0 ? c->normal_model->impact(c, gn).eps_n
                                                      : c->eps_n_exact;
    }
    if (p->w1) {
        gr_event_collide_rough(
            p->M, p->q, p->R, eps_n, p->elastic ? -1.0 : c->law_t[GR_HARD_SPHERE_BETA],
            p->elastic ? 0.0 : c->law_t[GR_HARD_SPHERE_BETA_MU], p->nx, p->ny, &p->v1x, &p->v1y,
            &p->v2x, &p->v2y, p->w1, p->w2, &p->de_n, &p->de_t);
    } else {
        gr_event_collide(p->M, eps_n, p->elastic ? 1.0 : c->law_t[GR_HARD_SPHERE_EPS_T], p->nx,
                         p->ny, &p->v1x, &p->v1y, &p->v2x, &p->v2y, &p->de_n, &p->de_t);
    }
}

#endif /* GR_MODELS_HARD_SPHERE_H */

#if defined(GR_MODEL_IMPL) && !defined(GR_MODELS_HARD_SPHERE_IMPL)
#define GR_MODELS_HARD_SPHERE_IMPL
/* the descriptor and prepare: compiled once, in models/registry.c */
#include <math.h>
#include <stddef.h>

#include "models/spring_dashpot_restitution.h"

static const gr_param hard_sphere_params[] = {
    {"k_s", "N/m", GR_PARAM_DOUBLE, 5e5, 0.0, INFINITY, true, true,
     "spring constant of the matching soft contact; sets the TC contact time t_c (2.6)",
     offsetof(gr_contact_params, k_s)},
    {"eps_n", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, true, false,
     "normal coefficient of restitution (2.2); 1 = elastic", offsetof(gr_contact_params, eps_n)},
    {"eps_t", "", GR_PARAM_DOUBLE, 0.6, 0.0, 1.0, false, false,
     "tangential coefficient of restitution (2.10) of smooth discs and spheres (rotation = "
     "false); 1 = no tangential dissipation (default shared with tangential_dashpot)",
     offsetof(gr_contact_params, eps_t)},
    {"tc", "s", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "TC-model time: a collision is elastic if either particle collided less than tc ago; default "
     "(or 0): the contact duration of the matching spring-dashpot (k_s, eps_n); off = no TC rule "
     "(an inelastic collapse is then stopped by the event-rate guard)",
     GR_OWN_KEY(hard_sphere, tc)},
    GR_ROTATION_PARAMS,
    {"beta", "", GR_PARAM_DOUBLE, -1.0, -1.0, 1.0, false, false,
     "rotation = true: tangential restitution of the contact point (Walton): -1 smooth (no spin "
     "change), +1 perfectly rough; replaces eps_t",
     GR_OWN_KEY(hard_sphere, beta)},
    {"beta_mu", "", GR_PARAM_DOUBLE, 0.0, 0.0, INFINITY, false, true,
     "rotation = true: Coulomb friction, the tangential impulse at most beta_mu times the normal "
     "one (the pair "
     "slides, Walton 1993); 0 = constant beta (always sticking)",
     GR_OWN_KEY(hard_sphere, beta_mu)},
    {"viscoelastic", "", GR_PARAM_BOOL, 0.0, 0.0, 1.0, false, false,
     "true: eps_n depends on the impact speed as for the hertz viscoelastic contact (k_h, "
     "visco_A; eps_n ignored); false = constant eps_n",
     GR_OWN_KEY(hertz, viscoelastic)},
    {"k_h", "N/m^1.5", GR_PARAM_DOUBLE, 1e9, 0.0, INFINITY, true, true,
     "viscoelastic = true: the hertz stiffness that sets eps_n(v)", GR_OWN_KEY(hertz, k_h)},
    {"visco_A", "s", GR_PARAM_DOUBLE, 1e-6, 0.0, INFINITY, false, true,
     "viscoelastic = true: the hertz viscoelastic time A that sets eps_n(v); 0 = elastic",
     GR_OWN_KEY(hertz, visco_A)},
};

static int hard_sphere_prepare(const gr_contact_params *p, double m12, double dt,
                               gr_contact_coeffs *c, gr_error *err)
{
    const hard_sphere_own *o = GR_OWN(p, hard_sphere);
    (void)dt;
    if (!(p->eps_n > 0.0)) {
        /* eps_n = 0 leaves a touching pair at zero normal velocity: the next event is at the same
         * instant and the calendar never advances */
        return GR_FAIL(
            err, GR_EINVAL,
            "[model] eps_n = %g: hard_sphere needs eps_n in (0, 1] (a perfectly sticking "
            "instantaneous collision leaves the pair touching at zero normal speed); use e.g. "
            "0.001",
            p->eps_n);
    }
    if (!p->rotation && (o->beta != -1.0 || o->beta_mu != 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] beta = %g, beta_mu = %g: hard_sphere's rough collisions (beta in "
                       "[-1, 1], beta_mu >= 0) "
                       "need rotation = true; without rotation the tangential restitution is eps_t",
                       o->beta, o->beta_mu);
    }
    if (p->rotation && o->beta_mu > 0.0 && o->beta == -1.0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "[model] beta_mu = %g with beta = -1: smooth discs and spheres get no tangential "
            "impulse, so a Coulomb limit does nothing; set beta in (-1, 1] (the sticking value, "
            "e.g. 1) or beta_mu = 0",
            o->beta_mu);
    }
    if (!(o->tc >= 0.0 || o->tc == GR_TC_OFF) || !isfinite(o->tc)) {
        return GR_FAIL(err, GR_EINVAL, "[model] tc = %g: allowed range [0, inf) s, or off", o->tc);
    }
    c->m12 = m12;
    c->clamp = false;
    c->zeta = spring_dashpot_zeta_unclamped(p->eps_n); /* the matching spring-dashpot, eq. 2.6 */
    /* t_c, the k_s contact's duration, sets only the clock tick dt = t_c / steps_per_contact; a given
     * tc is the TC time alone (c->tc, which the event integrator reads), so a tiny tc cannot make
     * the tick crawl (issue 37) */
    c->w0 = sqrt(p->k_s / m12);
    c->k_s = m12 * c->w0 * c->w0;
    c->t_c = spring_dashpot_duration_unclamped(c->zeta) / c->w0;
    c->tc = o->tc == GR_TC_OFF ? 0.0 : o->tc > 0.0 ? o->tc : c->t_c; /* the TC time */
    c->eps_n_exact = p->eps_n;
    c->gamma_n = 0.0; /* no force law: kernels see a hard sphere as force-free */
    c->e_scale = 0.5 * c->k_s;
    c->pow_a = 1.0;
    c->pow_p = 0.0;
    if (GR_OWN(p, hertz)->viscoelastic) {
        /* eps_n(v) of the hertz viscoelastic contact with the same keys: its damping and stiffness
         * feed hertz's own impact (hard_sphere_impact) */
        gr_contact_params hp = *p;
        hp.clamp = false;
        gr_contact_coeffs hc = {0};
        int rc = gr_model_hertz.prepare(&hp, m12, 0.0, &hc, err);
        if (rc) {
            return rc;
        }
        c->law_n[GR_HARD_SPHERE_VISCO] = 1.0;
        c->law_n[GR_HARD_SPHERE_GAMMA] = hc.gamma_n;
        c->law_n[GR_HARD_SPHERE_KH] = hc.k_s;
    }
    c->law_t[GR_HARD_SPHERE_EPS_T] = p->eps_t; /* the rule's tangential restitution */
    c->law_t[GR_HARD_SPHERE_BETA] =
        o->beta; /* rotation = true: Walton's beta and its Coulomb limit */
    c->law_t[GR_HARD_SPHERE_BETA_MU] = o->beta_mu;
    c->gamma_t = 0.0;
    return GR_OK;
}

/* eps_n(v) of the viscoelastic hertz contact depends on the impact only through the scaled
 * damping c = (3/2) A / t0 (models/hertz.h), and is smooth in sqrt(c) (the Schwager-Poeschel
 * series runs in powers of v^(1/10), i.e. of sqrt(c)). Integrating the scaled contact takes
 * ~0.6 ms, once per collision an event-driven run could not afford, so the rule evaluates a
 * Chebyshev series of eps(sqrt(c)) (GSL, order 60 on c in [0, 4.9], built once per process from
 * hertz_scaled_impact itself in ~0.1 s): it agrees with the integration to 3e-14 (tested in
 * tests/test_event_rough.c). Beyond it eps < 0.002: impacts up to the damping c_stick where the
 * integration first reports a sticking pair (eps = 0; found once by bisection) are integrated
 * directly, harder ones get GR_HARD_SPHERE_MIN_EPS at once, as the integration would give them
 * after ~3 ms each. */
#include <gsl/gsl_chebyshev.h>
#include <threads.h>

#define HARD_SPHERE_CHEB_ORDER 60
#define HARD_SPHERE_CHEB_C_MAX 4.9

static gsl_cheb_series *hard_sphere_cheb;
static double hard_sphere_c_stick = INFINITY;
static once_flag hard_sphere_cheb_once = ONCE_FLAG_INIT;

static double hard_sphere_eps_of_root_c(double s, void *unused)
{
    (void)unused;
    return hertz_scaled_impact(s * s, 0, 0).eps_n;
}

static void hard_sphere_cheb_build(void)
{
    gsl_cheb_series *cs = gsl_cheb_alloc(HARD_SPHERE_CHEB_ORDER);
    if (cs) {
        gsl_function f = {hard_sphere_eps_of_root_c, NULL};
        gsl_cheb_init(cs, &f, 0.0, sqrt(HARD_SPHERE_CHEB_C_MAX));
    }
    hard_sphere_cheb = cs; /* NULL (out of memory): every impact is integrated */
    double lo = HARD_SPHERE_CHEB_C_MAX, hi = 2.0 * lo;
    if (hertz_scaled_impact(hi, 0, 0).eps_n == 0.0) {
        for (int it = 0; it < 40; it++) {
            const double mid = 0.5 * (lo + hi);
            *(hertz_scaled_impact(mid, 0, 0).eps_n > 0.0 ? &lo : &hi) = mid;
        }
        hard_sphere_c_stick = hi; /* the first damping found sticking */
    }
}

/* Its restitution law: eps_n and eps_t exactly, at any speed, in no time; viscoelastic = true:
 * eps_n(v_n) of the hertz viscoelastic contact with the same keys (the Chebyshev series above
 * of hertz's own scaled contact, so both models agree), at least GR_HARD_SPHERE_MIN_EPS. */
static gr_normal_impact hard_sphere_impact(const gr_contact_coeffs *c, double v_n)
{
    if (c->law_n[GR_HARD_SPHERE_VISCO] == 0.0) {
        return (gr_normal_impact){c->eps_n_exact, 0.0, 1.0 + c->eps_n_exact};
    }
    gr_contact_coeffs hc = {0};
    hc.m12 = c->m12;
    hc.gamma_n = c->law_n[GR_HARD_SPHERE_GAMMA];
    hc.k_s = c->law_n[GR_HARD_SPHERE_KH];
    hc.pow_a = 1.5;
    hc.pow_p = 0.5; /* law_n[0] = 0: hertz's viscoelastic mode */
    const double damping = hertz_scaled_damping(&hc, v_n);
    call_once(&hard_sphere_cheb_once, hard_sphere_cheb_build);
    double eps = hard_sphere_cheb && damping <= HARD_SPHERE_CHEB_C_MAX
                     ? gsl_cheb_eval(hard_sphere_cheb, sqrt(damping))
                 : damping >= hard_sphere_c_stick ? 0.0
                                                  : hertz_scaled_impact(damping, 0, 0).eps_n;
    eps = eps >= GR_HARD_SPHERE_MIN_EPS ? (eps <= 1.0 ? eps : 1.0) : GR_HARD_SPHERE_MIN_EPS;
    return (gr_normal_impact){eps, 0.0, 1.0 + eps};
}

static double hard_sphere_restitution_t(const gr_contact_coeffs *c, gr_normal_impact n, double v_n,
                                        double v_t)
{
    if (c->rotation) {
        /* the contact point's eps_t = -beta (g_ct' = -beta g_ct), for discs at rest before: g_ct = v_t */
        double beta = c->law_t[GR_HARD_SPHERE_BETA];
        const double beta_mu = c->law_t[GR_HARD_SPHERE_BETA_MU];
        if (beta_mu > 0.0 && v_t > 0.0) {
            beta = fmin(beta, -1.0 + beta_mu * (1.0 + n.eps_n) * (1.0 + 1.0 / c->q) * v_n / v_t);
        }
        return -beta;
    }
    return c->law_t[GR_HARD_SPHERE_EPS_T];
}

/* the modes the conformance suite checks as combinations of their own: smooth discs with eps_t,
 * eps_n(v), rough discs with a constant beta (Walton) and Coulomb-limited (beta_mu), and rough
 * viscoelastic discs */
static const char *const hard_sphere_variants[] = {
    "rotation=false",
    "viscoelastic=true",
    "rotation=true beta=0.5",
    "rotation=true beta=1 beta_mu=0.2",
    "rotation=true beta=0.5 beta_mu=0.1 viscoelastic=true",
    NULL};

const gr_model gr_model_hard_sphere = {
    .name = "hard_sphere",
    .summary = "instantaneous collisions (2.1, 2.2, 2.10) with the TC model against collapse; "
               "needs [integrator] kind = event",
    .kind = GR_MODEL_NORMAL | GR_MODEL_EVENT,
    .params = hard_sphere_params,
    .n_params = sizeof hard_sphere_params / sizeof hard_sphere_params[0],
    .prepare = hard_sphere_prepare,
    .force_law = "spring_dashpot",
    .impact = hard_sphere_impact,
    .restitution_t = hard_sphere_restitution_t,
    .elastic = "eps_n=1 eps_t=1 beta=-1 beta_mu=0 visco_A=0",
    .variants = hard_sphere_variants,
};
#endif /* GR_MODEL_IMPL */
