/* Conformance suite of the collision models: every registered soft model (gr_models, generated
 * from models/list.h), in every legal combination (each normal force law alone and with each
 * tangential law, clamped and not, in 2D; each normal law on the 1D ring), must
 *   - follow its own restitution law (gr_model.restitution / duration / restitution_t, hence
 *     gr_contact_expected_loss) over impact speeds and angles, checked on the CVODE reference
 *     (gr_collide_reference): to 1e-7 head-on, to the turning of the line of centres obliquely;
 *   - be integrated by the engine's kernels (gr_collide_run) to first order: the phase-averaged
 *     energy loss within K_DT dt / t_c of the reference (docs/collision-accuracy.md derives
 *     C_N = 0.25 for the linear normal law; measured <= 0.1 here for every law);
 *   - conserve momentum (to rounding, < 1e-12 relative);
 *   - be symmetric under exchanging the two particles (the same loss to 1e-12);
 *   - conserve energy when its `elastic` settings are applied (eps = 1, no friction): reference
 *     to 1e-9, engine to (pi dt / t_c)^2 (the kink of the force at xi = 0);
 *   - give no NaN in hard cases (eps at the minimum its descriptor or prepare allows, the
 *     model's own extremes (gr_model.extremes), grazing
 *     impacts, very slow and fast impacts, contacts across the periodic boundary): either a
 *     clean refusal with a message or finite results with a loss in [0, 1];
 *   - close the energy ledger over a collision to the integrator's second order, (pi dt / t_c)^2.
 * A tangential law with modes of its own (gr_model.variants: tangential_spring's mindlin) joins
 * in each mode with every normal law whose prepare accepts it (Mindlin: hertz only).
 * The history spring (tangential_spring) is held to the same checks: its restitution law is a
 * fixed-normal integration of its stick-slip (models/tangential_spring_restitution.h), its force
 * in the CVODE reference integrates s with the stick/slip switches as roots
 * (models/tangential_spring_reference.h; every tangential law gives the reference its force,
 * gr_model.reference, and a law without one is refused, never integrated with F_t = 0); the
 * reference's own limits, energy balance and convergence are checked in
 * tests/test_spring_reference.c.
 * Rolling laws (GR_ROLLING_MODELS) join every rotating combination: the checks above (with the
 * discs not spinning a rolling law must change nothing), and their own spin_loss law on head-on
 * impacts of counter-rotating discs, rolling on and rolling arrested.
 * Event rules (hard_sphere), in every mode of gr_model.variants (smooth eps_t, viscoelastic
 * eps_n(v), rough with a constant Walton beta, Coulomb-limited beta_mu, rough viscoelastic), 1D
 * and 2D: the loss equals the rule's own restitution law to rounding over speeds and angles,
 * momentum and (applied directly) angular momentum are conserved, exchanging the particles
 * changes nothing, the elastic settings (eps_n = eps_t = 1, beta = -1) and beta = +1 conserve
 * energy, and extreme settings, grazing, slow and fast impacts give finite results.
 * A new model added to models/list.h is picked up here without editing this file.
 *
 * Particles: the RFM's discs of Table 2.2 (M = 3.53e-5 kg, r = 1.5 mm) with every model
 * parameter at its descriptor default, the scene's defaults. GRANULE_TEST_QUICK=1 uses fewer
 * speeds and phases. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "core/sim_internal.h" /* gr_kernel_force_generic, gr_kernel_instances */
#include "models/list.h"       /* the event rules, applied directly (gr_event_rule_apply) */
#include "models/reference.h"  /* gr_model.reference */
#include "check_main.h"
#include "test_env.h"

#define MASS 3.53e-5
#define RADIUS 1.5e-3
#define DIAM (2.0 * RADIUS)
#define STEPS 200.0 /* steps per contact of the engine runs */
#define K_DT 0.25   /* engine vs reference: |loss difference| <= K_DT dt / t_c */
#define MAX_COMBOS 256

typedef struct combo {
    const gr_model *normal, *tangential;
    int clamp, dim;
    int rot;                 /* [model] rotation = true (a tangential law at the contact point) */
    const char *variant;     /* the normal law's mode (gr_model.variants), NULL if it has one */
    const char *tvariant;    /* the tangential law's mode, NULL if it has none */
    const gr_model *rolling; /* a rolling law (rotation kernels only), NULL if none */
} combo;

static combo combos[MAX_COMBOS];
static int n_combos;
/* the event rules' combinations (each rule's mode, 1D and 2D), checked by their own tests below */
static combo events[MAX_COMBOS];
static int n_events;

static bool legal(const gr_model *nm, const char *var, const gr_model *tm, const char *tvar);

/* every legal combination of the registry's soft laws */
static void enumerate(void)
{
    n_combos = 0;
    for (int a = 0; gr_models[a]; a++) {
        const gr_model *nm = gr_models[a];
        if (!(nm->kind & GR_MODEL_NORMAL) || (nm->kind & GR_MODEL_EVENT)) {
            continue;
        }
        for (int v = 0; v == 0 || (nm->variants && nm->variants[v]); v++) {
            const char *var = nm->variants ? nm->variants[v] : NULL;
            for (int clamp = 0; clamp < 2 && n_combos + 2 < MAX_COMBOS; clamp++) {
                combos[n_combos++] = (combo){nm, NULL, clamp, 1, 0, var, NULL, NULL};
                combos[n_combos++] = (combo){nm, NULL, clamp, 2, 0, var, NULL, NULL};
                for (int b = 0; gr_models[b]; b++) {
                    const gr_model *tm = gr_models[b];
                    for (int tv = 0; tm->kind == GR_MODEL_TANGENTIAL &&
                                     (tv == 0 || (tm->variants && tm->variants[tv]));
                         tv++) {
                        const char *tvar = tm->variants ? tm->variants[tv] : NULL;
                        if (!legal(nm, var, tm, tvar)) {
                            continue; /* a mode this normal law refuses (mindlin without hertz) */
                        }
                        for (int rot = 0; rot <= (tm->contact_point ? 1 : 0); rot++) {
                            if (n_combos < MAX_COMBOS) {
                                combos[n_combos++] =
                                    (combo){nm, tm, clamp, 2, rot, var, tvar, NULL};
                            }
                            /* every rolling law with rotation */
                            for (int r = 0; rot && gr_models[r]; r++) {
                                if (gr_models[r]->kind == GR_MODEL_ROLLING &&
                                    n_combos < MAX_COMBOS) {
                                    combos[n_combos++] =
                                        (combo){nm, tm, clamp, 2, 1, var, tvar, gr_models[r]};
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    n_events = 0;
    for (int a = 0; gr_models[a]; a++) {
        const gr_model *em = gr_models[a];
        for (int v = 0;
             (em->kind & GR_MODEL_EVENT) && (v == 0 || (em->variants && em->variants[v])); v++) {
            const char *var = em->variants ? em->variants[v] : NULL;
            const int rot = var && strstr(var, "rotation=true") != NULL;
            for (int dim = rot ? 2 : 1; dim <= 2 && n_events < MAX_COMBOS; dim++) {
                events[n_events++] = (combo){em, NULL, 0, dim, rot, var, NULL, NULL};
            }
        }
    }
}

/* apply a model's "key=value key=value" settings (checked against the descriptors) */
static void apply_settings(gr_contact_params *p, const char *settings)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", settings ? settings : "");
    for (char *save = NULL, *tok = strtok_r(buf, " ", &save); tok;
         tok = strtok_r(NULL, " ", &save)) {
        char *eq = strchr(tok, '=');
        ck_assert_msg(eq, "settings '%s': '%s' is not key=value", settings, tok);
        *eq = '\0';
        gr_error err = {0};
        ck_assert_msg(gr_contact_set(p, tok, eq + 1, &err) == GR_OK, "settings '%s': %s", settings,
                      err.message);
    }
}

/* every descriptor's default (as a scene without [model] keys), then the combination's modes */
static gr_contact_params defaults_of(const combo *c)
{
    gr_contact_params p;
    gr_contact_defaults(&p);
    apply_settings(&p, c->variant);
    if (c->tangential) {
        apply_settings(&p, c->tvariant);
    }
    p.rotation = c->rot;
    return p;
}

/* whether the normal law in its mode accepts the tangential law's mode (at the defaults) */
static bool legal(const gr_model *nm, const char *var, const gr_model *tm, const char *tvar)
{
    gr_contact_params p;
    gr_contact_defaults(&p);
    gr_error err = {0};
    const char *modes[2] = {var, tvar};
    for (int m = 0; m < 2; m++) { /* "key=value" (no ck_assert here: this runs before the tests) */
        char buf[128];
        snprintf(buf, sizeof buf, "%s", modes[m] ? modes[m] : "");
        char *eq = strchr(buf, '=');
        if (eq) {
            *eq = '\0';
            if (gr_contact_set(&p, buf, eq + 1, &err) != GR_OK) {
                return false;
            }
        }
    }
    gr_contact_coeffs k;
    return gr_contact_prepare(nm, tm, &p, 1.0, 0.0, &k, &err) == GR_OK;
}

static const char *name_of(const combo *c, char *buf, size_t n)
{
    snprintf(buf, n, "%dd %s%s%s%s%s%s%s%s%s%s%s%s%s", c->dim, c->normal->name,
             c->variant ? "(" : "", c->variant ? c->variant : "", c->variant ? ")" : "",
             c->clamp ? "[clamped]" : "", c->tangential ? "+" : "",
             c->tangential ? c->tangential->name : "", c->tvariant ? "(" : "",
             c->tvariant ? c->tvariant : "", c->tvariant ? ")" : "", c->rot ? "(rotation)" : "",
             c->rolling ? "+" : "", c->rolling ? c->rolling->name : "");
    return buf;
}

static gr_collide_setup setup_of(const combo *c, gr_contact_params p)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    s.normal = c->normal;
    s.tangential = c->tangential;
    s.rolling = c->rolling;
    p.clamp = c->clamp;
    s.contact = p;
    s.mass = MASS;
    s.radius = RADIUS;
    s.dim = c->dim;
    return s;
}

/* particle 1 moving at `speed` along x hits particle 2 at rest at `angle` degrees */
static gr_collision_case impact(double speed, double angle)
{
    double a = angle * M_PI / 180.0;
    return (gr_collision_case){{0.0, 0.0}, {speed, 0.0}, {2.0 * DIAM, DIAM * sin(a)}, {0.0, 0.0}};
}

/* coefficients of the setup; false when its prepare refuses these parameters */
static bool coeffs_of(const gr_collide_setup *s, gr_contact_coeffs *k)
{
    gr_error err = {0};
    const gr_model *t = s->dim == 2 ? s->tangential : NULL, *r = s->dim == 2 ? s->rolling : NULL;
    return gr_contact_prepare(s->normal, t, &s->contact, 0.5 * s->mass, 0.0, k, &err) == GR_OK &&
           gr_contact_prepare_rolling(r, &s->contact, 0.5 * s->mass, 0.0, k, &err) == GR_OK;
}

/* the model's contact duration at this impact */
static double duration_of(const gr_contact_coeffs *k, double speed, double angle)
{
    const double v_n = speed * cos(angle * M_PI / 180.0);
    double t = k->normal_model->impact(k, v_n).t_c;
    return isfinite(t) ? t : M_PI / k->w0;
}

/* Engine run averaged over `nph` contact phases, dt = t_c(v) / STEPS. Returns the mean loss;
 * *mom the largest momentum error. */
static double engine_loss(gr_collide_setup s, const gr_collision_case *cs,
                          const gr_contact_coeffs *k, double speed, double angle, int nph,
                          double *mom, double *overlap, const char *what)
{
    s.dt = duration_of(k, speed, angle) / STEPS;
    double sum = 0.0;
    *mom = 0.0;
    *overlap = INFINITY;
    for (int q = 0; q < nph; q++) {
        s.phase = (q + 0.5) / nph;
        gr_collide_result r;
        gr_error err = {0};
        int rc = gr_collide_run(&s, cs, &r, &err);
        ck_assert_msg(rc == GR_OK, "%s: engine run failed: %s", what, err.message);
        ck_assert_msg(isfinite(r.energy_loss), "%s: loss %g", what, r.energy_loss);
        sum += r.energy_loss;
        *mom = fmax(*mom, r.momentum_error);
        *overlap = fmin(*overlap, r.max_overlap);
    }
    return sum / nph;
}

static const double speeds[] = {0.01, 0.1, 1.0};
static const double angles[] = {0.0, 30.0, 60.0};
static int n_speeds(void) { return quick() ? 2 : 3; }

/* 1. the CVODE reference follows the model's own restitution law */
START_TEST(test_restitution_law)
{
    const combo *c = &combos[_i];
    char what[260], name[160];
    name_of(c, name, sizeof name);
    gr_collide_setup s = setup_of(c, defaults_of(c));
    gr_contact_coeffs k;
    ck_assert_msg(coeffs_of(&s, &k), "%s: the defaults are refused", name);
    for (int a = 0; a < (c->dim == 2 ? 3 : 1); a++) {
        for (int v = 0; v < n_speeds(); v++) {
            snprintf(what, sizeof what, "%s, %g m/s at %g deg", name, speeds[v], angles[a]);
            gr_collision_case cs = impact(speeds[v], angles[a]);
            gr_collide_result r;
            gr_error err = {0};
            ck_assert_msg(gr_collide_reference(&s, &cs, &r, &err) == GR_OK, "%s: reference: %s",
                          what, err.message);
            const double want = gr_contact_expected_loss(&k, speeds[v], angles[a]);
            /* obliquely the line of centres turns by ~ v_t t_c / d during the contact, which the
             * fixed-normal law ignores */
            const double t_c = duration_of(&k, speeds[v], angles[a]);
            const double turn = speeds[v] * sin(angles[a] * M_PI / 180.0) * t_c / DIAM;
            const double tol = 1e-7 + 2.0 * turn;
            VERBOSE("%s: reference loss %.10f, law %.10f (tol %.2e)\n", what, r.energy_loss, want,
                    tol);
            ck_assert_msg(fabs(r.energy_loss - want) <= tol,
                          "%s: reference loss %.10f, the model's law %.10f (tol %.2e)", what,
                          r.energy_loss, want, tol);
            ck_assert_msg(fabs(r.impact_angle - angles[a]) <= 1e-6, "%s: impact angle %g", what,
                          r.impact_angle);
        }
    }
}
END_TEST

/* 2. the engine integrates the law to first order, conserves momentum, and is symmetric */
START_TEST(test_engine_vs_reference)
{
    const combo *c = &combos[_i];
    char what[260], name[160];
    name_of(c, name, sizeof name);
    gr_collide_setup s = setup_of(c, defaults_of(c));
    gr_contact_coeffs k;
    ck_assert(coeffs_of(&s, &k));
    const int nph = quick() ? 2 : 4;
    for (int a = 0; a < (c->dim == 2 ? 2 : 1); a++) {
        const double angle = a ? 45.0 : 0.0;
        for (int v = 0; v < n_speeds(); v += 2) {
            snprintf(what, sizeof what, "%s, %g m/s at %g deg", name, speeds[v], angle);
            gr_collision_case cs = impact(speeds[v], angle);
            gr_collide_result ref = {0};
            gr_error err = {0};
            ck_assert_msg(gr_collide_reference(&s, &cs, &ref, &err) == GR_OK, "%s: %s", what,
                          err.message);
            double mom = 0.0, ov = 0.0, ov2 = 0.0;
            const double loss = engine_loss(s, &cs, &k, speeds[v], angle, nph, &mom, &ov, what);
            const double tol = K_DT / STEPS;
            VERBOSE("%s: engine %.8f, reference %.8f, |diff| %.2e (tol %.2e), momentum %.1e\n",
                    what, loss, ref.energy_loss, fabs(loss - ref.energy_loss), tol, mom);
            ck_assert_msg(fabs(loss - ref.energy_loss) <= tol,
                          "%s: engine loss %.8f, reference %.8f (tol %.2e)", what, loss,
                          ref.energy_loss, tol);
            ck_assert_msg(loss >= -1e-6 && loss <= 1.0 + 1e-9, "%s: engine loss %.8f", what, loss);
            ck_assert_msg(mom < 1e-12, "%s: momentum error %.3e", what, mom);
            /* the same impact with the particles exchanged and the picture point-reflected (so
             * that the 1D order holds): the pair law sees i and j swapped, n and t reversed. The
             * positions differ by rounding (~ 1e-16 of the box) relative to the overlap. */
            gr_collision_case sw = {{-cs.x2[0], -cs.x2[1]},
                                    {-cs.v2[0], -cs.v2[1]},
                                    {-cs.x1[0], -cs.x1[1]},
                                    {-cs.v1[0], -cs.v1[1]}};
            double mom2 = 0.0;
            const double loss2 = engine_loss(s, &sw, &k, speeds[v], angle, nph, &mom2, &ov2, what);
            const double sym_tol = 1e-12 + 16.0 * 2.2e-16 * (64.0 * DIAM) / ov;
            ck_assert_msg(fabs(loss2 - loss) <= sym_tol,
                          "%s: loss %.17g, with the particles exchanged %.17g (tol %.2e)", what,
                          loss, loss2, sym_tol);
        }
    }
}
END_TEST

/* 3. the elastic settings conserve energy */
START_TEST(test_elastic)
{
    const combo *c = &combos[_i];
    char what[260], name[160];
    name_of(c, name, sizeof name);
    gr_contact_params p = defaults_of(c);
    apply_settings(&p, c->normal->elastic);
    if (c->tangential && c->dim == 2) {
        apply_settings(&p, c->tangential->elastic);
    }
    if (c->rolling) {
        apply_settings(&p, c->rolling->elastic);
    }
    gr_collide_setup s = setup_of(c, p);
    gr_contact_coeffs k;
    ck_assert_msg(coeffs_of(&s, &k), "%s: the elastic settings '%s' are refused", name,
                  c->normal->elastic);
    for (int a = 0; a < (c->dim == 2 ? 2 : 1); a++) {
        const double angle = a ? 45.0 : 0.0, speed = 0.1;
        snprintf(what, sizeof what, "%s elastic, %g m/s at %g deg", name, speed, angle);
        gr_collision_case cs = impact(speed, angle);
        gr_collide_result ref = {0};
        gr_error err = {0};
        ck_assert_msg(gr_collide_reference(&s, &cs, &ref, &err) == GR_OK, "%s: %s", what,
                      err.message);
        ck_assert_msg(fabs(ref.energy_loss) <= 1e-9, "%s: reference loses %.3e", what,
                      ref.energy_loss);
        /* 1e-9: a law may be a numerical integration of its own (hertz) */
        ck_assert_msg(fabs(gr_contact_expected_loss(&k, speed, angle)) <= 1e-9,
                      "%s: the law predicts a loss %.3e", what,
                      gr_contact_expected_loss(&k, speed, angle));
        double mom = 0.0, ov = 0.0;
        const double loss = engine_loss(s, &cs, &k, speed, angle, quick() ? 2 : 8, &mom, &ov, what);
        const double tol = pow(M_PI / STEPS, 2.0);
        ck_assert_msg(fabs(loss) <= tol, "%s: engine loss %.3e (tol %.2e)", what, loss, tol);
    }
}
END_TEST

/* a hard case: a clean refusal or finite results */
static void hard_case(const combo *c, const gr_contact_params *p, double speed, double angle,
                      const char *what)
{
    gr_collide_setup s = setup_of(c, *p);
    gr_contact_coeffs k;
    if (!coeffs_of(&s, &k)) {
        return; /* prepare refuses these parameters with a message (checked by the caller) */
    }
    gr_collision_case cs = impact(speed, angle);
    s.dt = duration_of(&k, speed, angle) / 50.0;
    gr_collide_result r;
    gr_error err = {0};
    int rc = gr_collide_run(&s, &cs, &r, &err);
    if (rc != GR_OK) {
        ck_assert_msg(err.message[0] != '\0', "%s: refused (%d) without a message", what, rc);
        return;
    }
    ck_assert_msg(isfinite(r.energy_loss) && isfinite(r.eps_n_measured) &&
                      isfinite(r.max_overlap) && isfinite(r.contact_time),
                  "%s: loss %g eps_n %g overlap %g", what, r.energy_loss, r.eps_n_measured,
                  r.max_overlap);
    ck_assert_msg(r.energy_loss >= -1e-6 && r.energy_loss <= 1.0 + 1e-9,
                  "%s: loss %.17g outside [0, 1]", what, r.energy_loss);
}

/* 4. hard cases: every restitution-like parameter at the minimum its descriptor allows (or just
 * above, when the minimum is open or prepare refuses it), grazing, slow and fast impacts */
START_TEST(test_hard_cases)
{
    const combo *c = &combos[_i];
    char what[260], name[160];
    name_of(c, name, sizeof name);
    const gr_model *laws[3] = {c->normal, c->dim == 2 ? c->tangential : NULL, c->rolling};
    for (int m = 0; m < 2; m++) {
        for (int i = 0; laws[m] && i < laws[m]->n_params; i++) {
            const gr_param *d = &laws[m]->params[i];
            if (d->type != GR_PARAM_DOUBLE || strncmp(d->name, "eps", 3) != 0) {
                continue;
            }
            gr_contact_params p = defaults_of(c);
            for (int lo = 0; lo < 2; lo++) {
                const double v = lo == 0 && !d->min_open ? d->min : d->min + 1e-6;
                *(double *)((char *)&p + d->offset) = v;
                gr_collide_setup s = setup_of(c, p);
                gr_contact_coeffs k;
                gr_error err = {0};
                const gr_model *t = s.dim == 2 ? s.tangential : NULL;
                if (gr_contact_prepare(s.normal, t, &s.contact, 0.5 * MASS, 0.0, &k, &err) !=
                    GR_OK) {
                    ck_assert_msg(err.message[0] != '\0', "%s: %s = %g refused without a message",
                                  name, d->name, v);
                    continue;
                }
                for (int a = 0; a < (c->dim == 2 ? 2 : 1); a++) {
                    snprintf(what, sizeof what, "%s, %s = %g, angle %g", name, d->name, v,
                             a ? 60.0 : 0.0);
                    hard_case(c, &p, 0.1, a ? 60.0 : 0.0, what);
                }
            }
        }
    }
    for (int m = 0; m < 3; m++) {
        for (int e = 0; laws[m] && laws[m]->extremes && laws[m]->extremes[e]; e++) {
            gr_contact_params x = defaults_of(c);
            apply_settings(&x, laws[m]->extremes[e]);
            for (int a = 0; a < (c->dim == 2 ? 2 : 1); a++) {
                snprintf(what, sizeof what, "%s, %s, angle %g", name, laws[m]->extremes[e],
                         a ? 60.0 : 0.0);
                hard_case(c, &x, 0.1, a ? 60.0 : 0.0, what);
            }
        }
    }
    const gr_contact_params p = defaults_of(c);
    const double hard_speeds[] = {1e-5, 10.0};
    for (int v = 0; v < 2; v++) {
        snprintf(what, sizeof what, "%s at %g m/s", name, hard_speeds[v]);
        hard_case(c, &p, hard_speeds[v], 0.0, what);
    }
    if (c->dim == 2) {
        snprintf(what, sizeof what, "%s, grazing at 89.9 deg", name);
        hard_case(c, &p, 0.1, 89.9, what);
    }
}
END_TEST

/* Two discs colliding head-on (2D: at 30 degrees) with the pair centred at (cx, cy) of a box of
 * side L; returns the final velocities and the ledger residual relative to the initial energy. */
static double pair_run(const combo *c, double cx, double cy, double out[4], double *resid,
                       double *t_over_dt)
{
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = c->dim;
    sc.N = 2;
    sc.radius = RADIUS;
    sc.mass = MASS;
    sc.normal = c->normal;
    sc.tangential = c->dim == 2 ? c->tangential : NULL;
    sc.rolling = c->rolling;
    sc.contact = defaults_of(c);
    sc.contact.clamp = c->clamp;
    sc.D = 0.0;
    sc.noise_mode = GR_NOISE_NONE;
    sc.L = 40.0 * DIAM;
    sc.skin = 0.3;
    const double speed = 0.1, a = c->dim == 2 ? 30.0 * M_PI / 180.0 : 0.0;
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert(gr_contact_prepare(sc.normal, sc.tangential, &sc.contact, 0.5 * MASS, 0.0, &k,
                                 &err) == GR_OK);
    sc.dt = duration_of(&k, speed, 0.0) / STEPS;
    /* contact begins 10.5 steps in (mid-step, so rounding cannot move it by a step); 1 moves +x, 2 moves -x, offset by d sin a in y */
    const double gap = 10.5 * sc.dt * speed, half = 0.5 * (DIAM * cos(a) + gap);
    double x[2] = {cx - half, cx + half},
           y[2] = {cy - 0.5 * DIAM * sin(a), cy + 0.5 * DIAM * sin(a)};
    for (int p = 0; p < 2; p++) {
        x[p] -= sc.L * floor(x[p] / sc.L);
        y[p] -= sc.L * floor(y[p] / sc.L);
    }
    double vx[2] = {0.5 * speed, -0.5 * speed}, vy[2] = {0.0, 0.0};
    /* the 1D ring keeps the particles in order: across the boundary particle 1 comes first */
    const int swap = c->dim == 1 && x[0] > x[1];
    if (swap) {
        double t = x[0];
        x[0] = x[1];
        x[1] = t;
        vx[0] = -0.5 * speed;
        vx[1] = 0.5 * speed;
    }
    gr_sim *s = NULL;
    int rc = gr_sim_create_with_state(&sc, 2, x, c->dim == 2 ? y : NULL, vx,
                                      c->dim == 2 ? vy : NULL, &s, &err);
    ck_assert_msg(rc == GR_OK, "create: %s", err.message);
    const int64_t steps = (int64_t)(3.0 * STEPS) + 40;
    rc = gr_sim_step(s, steps, &err);
    ck_assert_msg(rc == GR_OK, "step: %s", err.message);
    gr_particles pp = gr_sim_particles(s);
    out[0] = pp.vx[swap];
    out[1] = pp.vx[1 - swap];
    out[2] = c->dim == 2 ? pp.vy[0] : 0.0;
    out[3] = c->dim == 2 ? pp.vy[1] : 0.0;
    gr_ledger l = gr_sim_ledger(s);
    *resid = gr_ledger_residual(&l) / l.initial;
    *t_over_dt = duration_of(&k, speed, 0.0) / gr_sim_dt(s);
    const int64_t coll = gr_sim_collisions(s);
    gr_sim_free(s);
    return (double)coll;
}

/* 5. a contact across the periodic boundary equals the same contact inside the box, and the
 * ledger closes over a collision to first order */
START_TEST(test_periodic_and_ledger)
{
    const combo *c = &combos[_i];
    char name[160];
    name_of(c, name, sizeof name);
    const double L = 40.0 * DIAM;
    double mid[4], edge[4], r_mid, r_edge, steps;
    const double coll = pair_run(c, 0.5 * L, 0.5 * L, mid, &r_mid, &steps);
    pair_run(c, 0.0, c->dim == 2 ? 0.0 : 0.5 * L, edge, &r_edge, &steps);
    ck_assert_msg(coll >= 1.0, "%s: the pair did not collide", name);
    for (int q = 0; q < 4; q++) {
        ck_assert_msg(isfinite(edge[q]), "%s: velocity %d is %g across the boundary", name, q,
                      edge[q]);
        ck_assert_msg(fabs(edge[q] - mid[q]) <= 1e-9 * 0.1,
                      "%s: velocity %d %.17g across the boundary, %.17g inside", name, q, edge[q],
                      mid[q]);
    }
    /* after the collision the elastic energy is 0; the ledger's residual is the velocity-Verlet
     * energy error of the contact, second order: (w dt)^2 / 4 per collision at most for the
     * linear law (docs/collision-accuracy.md), w ~ pi / t_c */
    const double tol = pow(M_PI / steps, 2.0);
    VERBOSE("%s: ledger residual %.3e of the initial energy (tol %.2e)\n", name, r_mid, tol);
    ck_assert_msg(fabs(r_mid) <= tol && fabs(r_edge) <= tol,
                  "%s: ledger residual %.3e / %.3e of the initial energy (tol %.2e)", name, r_mid,
                  r_edge, tol);
}
END_TEST

/* the combinations with a rolling law (their index in combos) */
static int rolls[MAX_COMBOS];
static int n_rolls;

/* 7. a rolling law takes from the spins what its own law says: a head-on impact of
 * counter-rotating discs (w1 = -w2: the contact point does not slip, so the tangential law does
 * nothing and the rolling law acts alone), spinning fast (the law's torque all through the
 * contact) and slowly (the relative rolling stops). The engine's normal impulse differs from the
 * normal law's by O(dt / t_c) (docs/collision-accuracy.md): 0.5 dt / t_c relative. */
START_TEST(test_rolling_law)
{
    const combo *c = &combos[rolls[_i]];
    char what[300], name[160];
    name_of(c, name, sizeof name);
    gr_collide_setup s = setup_of(c, defaults_of(c));
    gr_contact_coeffs k;
    ck_assert_msg(coeffs_of(&s, &k), "%s: the defaults are refused", name);
    const double inertia = k.q * MASS * RADIUS * RADIUS, r_eff = 0.5 * RADIUS, m12 = 0.5 * MASS;
    for (int v = 0; v < n_speeds(); v += 2) {
        const double speed = speeds[v];
        const gr_normal_impact ni = k.normal_model->impact(&k, speed);
        const double p_n = m12 * ni.impulse_abs * speed;
        /* the relative spin the contact just stops: J_max = I dw / 2 = mu_r r_eff p_n (law-free
         * guess from the full-torque value: the law decides which regime it is) */
        const double w_stop =
            c->rolling->spin_loss(&k, p_n, r_eff, inertia, 1e30) / (1e30 * inertia);
        const double ws[2] = {20.0 * w_stop, 0.3 * w_stop};
        for (int q = 0; q < 2; q++) {
            s.omega1 = ws[q];
            s.omega2 = -ws[q];
            snprintf(what, sizeof what, "%s, %g m/s head-on, w1 = -w2 = %.4g rad/s", name, speed,
                     ws[q]);
            gr_collision_case cs = impact(speed, 0.0);
            s.dt = duration_of(&k, speed, 0.0) / STEPS;
            gr_collide_result r;
            gr_error err = {0};
            ck_assert_msg(gr_collide_run(&s, &cs, &r, &err) == GR_OK, "%s: %s", what, err.message);
            const double e0 = 0.5 * m12 * speed * speed + inertia * ws[q] * ws[q];
            const double got = r.spin_loss * e0,
                         want = c->rolling->spin_loss(&k, p_n, r_eff, inertia, 2.0 * ws[q]);
            VERBOSE("%s: spin loss %.8e J, the law %.8e J (rel %.2e)\n", what, got, want,
                    got / want - 1.0);
            ck_assert_msg(want > 0.0 && fabs(got - want) <= 0.5 / STEPS * want,
                          "%s: spin loss %.10e J, the law %.10e J", what, got, want);
            ck_assert_msg(r.omega1 + r.omega2 == 0.0,
                          "%s: the contact point slipped (w1 + w2 = %g)", what,
                          r.omega1 + r.omega2);
            ck_assert_msg(r.momentum_error < 1e-12, "%s: momentum error %.3e", what,
                          r.momentum_error);
        }
    }
}
END_TEST

/* ---------- event rules (instantaneous collisions; every mode in gr_model.variants) ---------- */

/* the event rule's collision as `granule collide` applies it; false if refused */
static bool event_collide(const combo *c, gr_contact_params p, double speed, double angle, int swap,
                          gr_collide_result *r, gr_error *err)
{
    gr_collide_setup s = setup_of(c, p);
    gr_collision_case cs = impact(speed, angle);
    if (swap) {
        gr_collision_case sw = {{-cs.x2[0], -cs.x2[1]},
                                {-cs.v2[0], -cs.v2[1]},
                                {-cs.x1[0], -cs.x1[1]},
                                {-cs.v1[0], -cs.v1[1]}};
        cs = sw;
    }
    return gr_collide_run(&s, &cs, r, err) == GR_OK;
}

/* two discs touching along the normal at angle th (rad), approaching obliquely, for the rule
 * applied directly; spins w1, w2 (NULL: none) */
static gr_event_pair oblique_pair(const gr_contact_coeffs *k, double th, double *w1, double *w2)
{
    return (gr_event_pair){.M = MASS,
                           .R = RADIUS,
                           .q = k->q,
                           .nx = cos(th),
                           .ny = sin(th),
                           .v1x = 0.3,
                           .v1y = 0.05,
                           .v2x = -0.1,
                           .v2y = 0.02,
                           .w1 = w1,
                           .w2 = w2};
}

/* 8. the rule follows its own restitution law (eps_n or eps_n(v); eps_t, or the contact point's
 * -beta, Coulomb-limited, with the spins' share m_t / m12) exactly, conserves momentum, is
 * symmetric under exchanging the particles; and, applied directly, conserves angular momentum
 * (orbital about the origin + spins) */
START_TEST(test_event_rule)
{
    const combo *c = &events[_i];
    char what[300], name[160];
    name_of(c, name, sizeof name);
    const gr_contact_params p = defaults_of(c);
    gr_collide_setup s = setup_of(c, p);
    gr_contact_coeffs k;
    ck_assert_msg(coeffs_of(&s, &k), "%s: the defaults are refused", name);
    for (int a = 0; a < (c->dim == 2 ? 3 : 1); a++) {
        for (int v = 0; v < n_speeds(); v++) {
            snprintf(what, sizeof what, "%s, %g m/s at %g deg", name, speeds[v], angles[a]);
            gr_collide_result r, rs;
            gr_error err = {0};
            ck_assert_msg(event_collide(c, p, speeds[v], angles[a], 0, &r, &err), "%s: %s", what,
                          err.message);
            const double want = gr_contact_expected_loss(&k, speeds[v], angles[a]);
            VERBOSE("%s: loss %.15f, the rule's law %.15f, spins %g %g\n", what, r.energy_loss,
                    want, r.omega1, r.omega2);
            ck_assert_msg(fabs(r.energy_loss - want) <= 1e-12,
                          "%s: loss %.17g, the rule's law %.17g", what, r.energy_loss, want);
            ck_assert_msg(r.momentum_error < 1e-12, "%s: momentum error %.3e", what,
                          r.momentum_error);
            if (c->rot && a > 0) {
                ck_assert_msg(r.omega1 != 0.0 && r.omega1 == r.omega2, "%s: spins %g %g", what,
                              r.omega1, r.omega2);
            }
            ck_assert_msg(event_collide(c, p, speeds[v], angles[a], 1, &rs, &err), "%s: %s", what,
                          err.message);
            ck_assert_msg(fabs(rs.energy_loss - r.energy_loss) <= 1e-12,
                          "%s: loss %.17g, exchanged %.17g", what, r.energy_loss, rs.energy_loss);
            ck_assert_msg(fabs(rs.omega1 - r.omega2) <= 1e-9 * fabs(r.omega2) + 1e-300 &&
                              fabs(rs.omega2 - r.omega1) <= 1e-9 * fabs(r.omega1) + 1e-300,
                          "%s: spins %g %g, exchanged %g %g", what, r.omega1, r.omega2, rs.omega2,
                          rs.omega1);
        }
    }
    if (c->rot) {
        /* angular momentum of the rough rule, discs touching at (0, 0) and d n, with spins */
        const double M = MASS, R = RADIUS, I = k.q * M * R * R;
        for (int a = 0; a < 3; a++) {
            const double th = (angles[a] + 10.0) * M_PI / 180.0, nx = cos(th), ny = sin(th);
            double w1 = 40.0, w2 = -15.0;
            gr_event_pair e = oblique_pair(&k, th, &w1, &w2);
            const double r2x = DIAM * nx, r2y = DIAM * ny;
            const double l0 = M * (r2x * e.v2y - r2y * e.v2x) + I * (w1 + w2);
            gr_event_rule_apply(gr_event_rule_of(k.normal_model), &k, &e);
            const double l1 = M * (r2x * e.v2y - r2y * e.v2x) + I * (w1 + w2);
            const double scale = M * DIAM * 0.3 + I * 55.0;
            ck_assert_msg(fabs(l1 - l0) <= 1e-13 * scale, "%s: angular momentum %.17g -> %.17g",
                          name, l0, l1);
        }
    }
}
END_TEST

/* The rule applied directly (as the event integrator applies it) to an oblique approach with spins
 * (rotation) or without: returns the kinetic energy (translation + spin) lost minus the de_n + de_t
 * the rule reports, relative to the energy before; *lost gets the loss relative to it. */
static double rule_bookkeeping(const gr_contact_coeffs *k, bool rot, bool elastic, double *lost)
{
    const double M = MASS, R = RADIUS, I = rot ? k->q * M * R * R : 0.0;
    double w1 = rot ? 30.0 : 0.0, w2 = rot ? -12.0 : 0.0;
    gr_event_pair e = oblique_pair(k, 0.4, rot ? &w1 : NULL, rot ? &w2 : NULL);
    e.elastic = elastic;
    const double e0 = 0.5 * M * (e.v1x * e.v1x + e.v1y * e.v1y + e.v2x * e.v2x + e.v2y * e.v2y) +
                      0.5 * I * (w1 * w1 + w2 * w2);
    gr_event_rule_apply(gr_event_rule_of(k->normal_model), k, &e);
    const double e1 = 0.5 * M * (e.v1x * e.v1x + e.v1y * e.v1y + e.v2x * e.v2x + e.v2y * e.v2y) +
                      0.5 * I * (w1 * w1 + w2 * w2);
    *lost = (e0 - e1) / e0;
    return (e0 - e1 - e.de_n - e.de_t) / e0;
}

/* 9. the elastic settings (eps_n = 1, eps_t = 1, beta = -1, no viscous loss) conserve energy, and
 * so do perfectly rough discs (beta = +1); the TC verdict (gr_event_pair.elastic) makes the rule
 * elastic at its default settings; the energy the rule reports (de_n + de_t, which the integrator
 * books as dissipated) is the kinetic energy it took */
START_TEST(test_event_elastic)
{
    const combo *c = &events[_i];
    char what[300], name[160];
    name_of(c, name, sizeof name);
    for (int rough = 0; rough <= c->rot; rough++) {
        gr_contact_params p = defaults_of(c);
        apply_settings(&p, c->normal->elastic);
        if (rough) {
            apply_settings(&p, "beta=1");
        }
        for (int a = 0; a < (c->dim == 2 ? 2 : 1); a++) {
            snprintf(what, sizeof what, "%s elastic%s, at %g deg", name, rough ? " (beta = 1)" : "",
                     a ? 45.0 : 0.0);
            gr_collide_result r;
            gr_error err = {0};
            ck_assert_msg(event_collide(c, p, 0.1, a ? 45.0 : 0.0, 0, &r, &err), "%s: %s", what,
                          err.message);
            ck_assert_msg(fabs(r.energy_loss) <= 1e-12, "%s: loss %.3e", what, r.energy_loss);
        }
    }
    gr_collide_setup s = setup_of(c, defaults_of(c));
    gr_contact_coeffs k;
    ck_assert_msg(coeffs_of(&s, &k), "%s: the defaults are refused", name);
    double lost;
    const double tc_miss = rule_bookkeeping(&k, c->rot, true, &lost);
    ck_assert_msg(fabs(lost) <= 1e-13 && fabs(tc_miss) <= 1e-13,
                  "%s: a TC-elastic collision lost %.3e of the energy (booked miss %.3e)", name,
                  lost, tc_miss);
    const double miss = rule_bookkeeping(&k, c->rot, false, &lost);
    ck_assert_msg(lost > 1e-3 && fabs(miss) <= 1e-13,
                  "%s: the rule took %.6g of the energy, its de_n + de_t differ by %.3e", name,
                  lost, miss);
}
END_TEST

/* 10. hard cases: the smallest eps_n and beta the descriptors allow, the strongest Coulomb limit,
 * grazing, slow and fast impacts give finite results or a clean refusal */
START_TEST(test_event_hard_cases)
{
    const combo *c = &events[_i];
    char what[300], name[160];
    name_of(c, name, sizeof name);
    static const char *const extremes[] = {
        "eps_n=1e-9", "eps_t=0", "beta=-0.999999", "beta=1 beta_mu=1e9", "beta=1 beta_mu=1e-9",
        "visco_A=1",  NULL};
    static const double hard[][2] = {{0.1, 89.9}, {1e-5, 0.0}, {10.0, 30.0}, {10.0, 89.99}};
    for (int e = -1; e < 0 || extremes[e]; e++) {
        gr_contact_params p = defaults_of(c);
        if (e >= 0) {
            apply_settings(&p, extremes[e]);
        }
        for (int h = 0; h < 4; h++) {
            if (c->dim == 1 && hard[h][1] != 0.0) {
                continue;
            }
            snprintf(what, sizeof what, "%s, %s, %g m/s at %g deg", name,
                     e >= 0 ? extremes[e] : "defaults", hard[h][0], hard[h][1]);
            gr_collide_result r;
            gr_error err = {0};
            if (!event_collide(c, p, hard[h][0], hard[h][1], 0, &r, &err)) {
                ck_assert_msg(err.message[0] != '\0', "%s: refused without a message", what);
                continue;
            }
            ck_assert_msg(isfinite(r.energy_loss) && isfinite(r.eps_n_measured) &&
                              isfinite(r.omega1) && isfinite(r.omega2),
                          "%s: loss %g eps_n %g spins %g %g", what, r.energy_loss, r.eps_n_measured,
                          r.omega1, r.omega2);
            ck_assert_msg(r.energy_loss >= -1e-12 && r.energy_loss <= 1.0 + 1e-12, "%s: loss %.17g",
                          what, r.energy_loss);
        }
    }
}
END_TEST

/* 6. the suite sees the registry: every soft normal law and every tangential law is in a combo */
START_TEST(test_registry_covered)
{
    for (int m = 0; gr_models[m]; m++) {
        const gr_model *md = gr_models[m];
        int seen = 0;
        if (md->kind & GR_MODEL_EVENT) {
            ck_assert_msg(md->impact && md->restitution_t,
                          "%s: an event rule needs its restitution law", md->name);
            for (int i = 0; i < n_events; i++) {
                seen += events[i].normal == md;
            }
            ck_assert_msg(seen > 0, "event rule %s is in no combination", md->name);
            continue;
        }
        for (int i = 0; i < n_combos; i++) {
            seen += combos[i].normal == md || combos[i].tangential == md || combos[i].rolling == md;
        }
        ck_assert_msg(seen > 0, "model %s is in no combination", md->name);
        ck_assert_msg(md->elastic && md->elastic[0], "%s: no elastic settings", md->name);
        if (md->kind & GR_MODEL_NORMAL) {
            ck_assert_msg(md->impact, "%s: a normal law needs its impact (restitution law)",
                          md->name);
        } else if (md->kind & GR_MODEL_ROLLING) {
            ck_assert_msg(md->spin_loss, "%s: a rolling law needs spin_loss", md->name);
        } else {
            ck_assert_msg(md->restitution_t, "%s: a tangential law needs restitution_t", md->name);
            ck_assert_msg(
                md->reference && md->reference->setup && md->reference->force,
                "%s: a tangential law needs its force in the CVODE reference (gr_model.reference, "
                "models/reference.h)",
                md->name);
        }
    }
}
END_TEST

/* 10. the kernel instances (src/core/kernels.c): a combination in the hot list runs its
 * specialised instance, every other one the generic instance of its dimension, and the two give
 * the same bits. 48 particles on a lattice of spacing 1.01 d (neighbours across the boundary too)
 * with random velocities and spins step 400 times twice from the same state, once as chosen and once
 * forced through the generic instance: positions, velocities, spins and the ledger must agree
 * exactly. The thesis's laws (spring_dashpot alone, 1D and 2D, and with tangential_dashpot) must be specialised, and the number
 * of instances must stay below the number of combinations (the instantiation is bounded). */
static gr_sim *packed_sim(const combo *c, int generic)
{
    enum { NP = 48 };
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = c->dim;
    sc.N = NP;
    sc.radius = RADIUS;
    sc.mass = MASS;
    sc.normal = c->normal;
    sc.tangential = c->dim == 2 ? c->tangential : NULL;
    sc.rolling = c->rolling;
    sc.contact = defaults_of(c);
    sc.contact.clamp = c->clamp;
    sc.D = 0.0;
    sc.noise_mode = GR_NOISE_NONE;
    sc.skin = 0.3;
    const int side = c->dim == 2 ? 7 : NP; /* 2D: a 7 x 7 lattice less one */
    sc.L = side * 1.01 * DIAM;
    gr_contact_coeffs k;
    gr_error err = {0};
    ck_assert(gr_contact_prepare(sc.normal, sc.tangential, &sc.contact, 0.5 * MASS, 0.0, &k,
                                 &err) == GR_OK);
    sc.dt = duration_of(&k, 0.1, 0.0) / STEPS;
    double x[NP], y[NP], vx[NP], vy[NP];
    unsigned long long r = 12345; /* a fixed LCG: the same state for both runs */
    for (int i = 0; i < NP; i++) {
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        const double u = (double)(r >> 11) / 9007199254740992.0 - 0.5;
        x[i] = ((i % side) + 0.5) * 1.01 * DIAM;
        y[i] = ((i / side) + 0.5) * 1.01 * DIAM;
        vx[i] = 2.0 * u;
        vy[i] = 4.0 * u * u - 0.3;
    }
    gr_sim *s = NULL;
    ck_assert_msg(gr_sim_create_with_state(&sc, NP, x, c->dim == 2 ? y : NULL, vx,
                                           c->dim == 2 ? vy : NULL, &s, &err) == GR_OK,
                  "create: %s", err.message);
    if (s->omega) {
        for (int i = 0; i < NP; i++) {
            s->omega[i] = 30.0 * (double)((i * 7) % 11 - 5) / DIAM * 1e-3;
        }
    }
    if (generic) {
        gr_kernel_force_generic(s);
    }
    ck_assert_msg(gr_sim_step(s, 400, &err) == GR_OK, "step: %s", err.message);
    return s;
}

static bool same_bits(const double *a, const double *b, int n)
{
    return n == 0 || (a && b && memcmp(a, b, sizeof(double) * (size_t)n) == 0);
}

START_TEST(test_generic_kernel)
{
    const combo *c = &combos[_i];
    char name[200];
    name_of(c, name, sizeof name);
    gr_sim *a = packed_sim(c, 0), *b = packed_sim(c, 1);
    const bool thesis = strcmp(c->normal->name, "spring_dashpot") == 0 && !c->variant && !c->rot &&
                        (!c->tangential ||
                         (strcmp(c->tangential->name, "tangential_dashpot") == 0 && !c->tvariant));
    ck_assert_msg(!thesis || !gr_kernel_generic(a),
                  "%s: the thesis's law runs the generic instance", name);
    ck_assert_msg(gr_kernel_generic(b), "%s: the generic instance was not used", name);
    ck_assert_str_eq(gr_sim_kernel(a), gr_sim_kernel(b));
    const int n = a->n;
    ck_assert_msg(same_bits(a->x, b->x, n) && same_bits(a->vx, b->vx, n),
                  "%s: x or vx differ (generic vs %s)", name,
                  gr_kernel_generic(a) ? "generic" : "specialised");
    if (c->dim == 2) {
        ck_assert_msg(same_bits(a->y, b->y, n) && same_bits(a->vy, b->vy, n), "%s: y or vy differ",
                      name);
    }
    ck_assert_msg(!a->omega || same_bits(a->omega, b->omega, n), "%s: spins differ", name);
    gr_ledger la = gr_sim_ledger(a), lb = gr_sim_ledger(b);
    ck_assert_msg(memcmp(&la, &lb, sizeof la) == 0, "%s: ledgers differ", name);
    ck_assert_msg(gr_sim_collisions(a) > 0, "%s: no contact in the packed state", name);
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

START_TEST(test_kernel_instances_bounded)
{
    ck_assert_msg(gr_kernel_instances() < n_combos, "%d kernel instances for %d combinations",
                  gr_kernel_instances(), n_combos);
}
END_TEST

/* 6b. a scene key several models declare (eps_n, mu, rotation, hertz's k_h in hard_sphere) is one
 * parameter: the same place in gr_contact_params (the shared keys or one model's own block), type
 * and default, so gr_contact_set, gr_contact_defaults and every model agree on it */
START_TEST(test_shared_keys_one_place)
{
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const gr_param *a = &gr_models[m]->params[i];
            ck_assert_msg(a->offset + sizeof(double) <= sizeof(gr_contact_params),
                          "%s: %s outside the parameters", gr_models[m]->name, a->name);
            for (int n = 0; gr_models[n]; n++) {
                for (int j = 0; j < gr_models[n]->n_params; j++) {
                    const gr_param *b = &gr_models[n]->params[j];
                    if (strcmp(a->name, b->name) == 0) {
                        ck_assert_msg(a->offset == b->offset && a->type == b->type &&
                                          a->def == b->def,
                                      "%s's %s and %s's differ in place, type or default",
                                      gr_models[m]->name, a->name, gr_models[n]->name);
                    } else {
                        ck_assert_msg(a->offset != b->offset, "%s's %s and %s's %s share a place",
                                      gr_models[m]->name, a->name, gr_models[n]->name, b->name);
                    }
                }
            }
        }
    }
}
END_TEST

/* 7. a tangential law without a reference force is refused by the reference, never integrated
 * with F_t = 0 (a copy of each registered tangential law with its hook removed) */
START_TEST(test_reference_needs_law)
{
    for (int i = 0; i < n_combos; i++) {
        if (!combos[i].tangential || combos[i].dim != 2) {
            continue;
        }
        gr_model lawless = *combos[i].tangential;
        lawless.reference = NULL;
        combo c = combos[i];
        c.tangential = &lawless;
        gr_collide_setup s = setup_of(&c, defaults_of(&combos[i]));
        gr_collision_case cs = impact(0.1, 30.0);
        gr_collide_result r;
        gr_error err = {0};
        ck_assert_int_eq(gr_collide_reference(&s, &cs, &r, &err), GR_EINVAL);
        ck_assert_msg(strstr(err.message, lawless.name) && strstr(err.message, "reference force"),
                      "%s", err.message);
    }
}
END_TEST

/* 3D: every 2D combination collided as spheres in the plane z = 0 (spins along z, the same q)
 * gives the discs' numbers (src/core/kernels_3d.c runs the same laws with vectors), velocities
 * and spins staying in the plane exactly (docs/three-dimensions.md) */
START_TEST(test_spheres_in_plane)
{
    const combo *c = &combos[_i];
    if (c->dim != 2 || (quick() && _i % 4 != 0)) {
        return; /* a 1D combination has no sphere counterpart; the sanitizer pass takes every
                   fourth 2D one (the release pass all) */
    }
    char name[160], what[260];
    name_of(c, name, sizeof name);
    gr_contact_params p = defaults_of(c);
    p.inertia_factor = 0.4;
    gr_collide_setup s2 = setup_of(c, p), s3 = s2;
    s3.dim = 3;
    gr_contact_coeffs k;
    ck_assert(coeffs_of(&s2, &k));
    s2.omega1 = s3.w1[2] = c->rot ? 40.0 : 0.0;
    s2.omega2 = s3.w2[2] = c->rot ? -90.0 : 0.0;
    const double speed = 0.1, angles3[] = {0.0, 40.0};
    for (int a = 0; a < 2; a++) {
        snprintf(what, sizeof what, "%s at %g deg as spheres", name, angles3[a]);
        const gr_collision_case cs = impact(speed, angles3[a]);
        s2.dt = s3.dt = duration_of(&k, speed, angles3[a]) / STEPS;
        gr_collide_result r2, r3;
        gr_error err = {0};
        ck_assert_msg(gr_collide_run(&s2, &cs, &r2, &err) == GR_OK, "%s: %s", what, err.message);
        ck_assert_msg(gr_collide_run(&s3, &cs, &r3, &err) == GR_OK, "%s: %s", what, err.message);
        double worst = fmax(fabs(r2.energy_loss - r3.energy_loss),
                            fabs(r2.eps_n_measured - r3.eps_n_measured));
        for (int q = 0; q < 2; q++) {
            worst = fmax(worst, fabs(r2.v1[q] - r3.v1[q]) / speed);
            worst = fmax(worst, fabs(r2.v2[q] - r3.v2[q]) / speed);
        }
        worst = fmax(worst, fabs(r2.omega1 - r3.w1[2]) / 90.0);
        worst = fmax(worst, fabs(r2.omega2 - r3.w2[2]) / 90.0);
        VERBOSE("%s: 3D vs 2D %.2e\n", what, worst);
        ck_assert_msg(worst <= 1e-9, "%s: the spheres differ from the discs by %.3e", what, worst);
        ck_assert_msg(r3.v1[2] == 0.0 && r3.v2[2] == 0.0 && r3.w1[0] == 0.0 && r3.w1[1] == 0.0 &&
                          r3.w2[0] == 0.0 && r3.w2[1] == 0.0,
                      "%s: left the plane", what);
    }
}
END_TEST

/* Prepare every normal law, alone, at the parameters test_hard_cases asks for (each eps-like
 * parameter at its minimum and just above, each extreme) once, here in the parent: the tests run
 * in forked children, which then find the laws' per-thread calibration caches filled (hertz's
 * Tsuji damping is a bisection over ~60 integrated contacts, sticking ones near eps = 0) instead
 * of each repeating them. Only the time changes: the cached values are the computed ones. */
static void warm_calibrations(void)
{
    for (int i = 0; i < n_combos; i++) {
        const combo *c = &combos[i];
        if (c->tangential || c->rolling || c->dim != 1) {
            continue;
        }
        gr_contact_coeffs k;
        gr_error err = {0};
        gr_contact_params p = defaults_of(c);
        p.clamp = c->clamp;
        (void)gr_contact_prepare(c->normal, NULL, &p, 0.5 * MASS, 0.0, &k, &err);
        for (int j = 0; j < c->normal->n_params; j++) {
            const gr_param *d = &c->normal->params[j];
            if (d->type != GR_PARAM_DOUBLE || strncmp(d->name, "eps", 3) != 0) {
                continue;
            }
            for (int lo = 0; lo < 2; lo++) {
                gr_contact_params q = p;
                *(double *)((char *)&q + d->offset) =
                    lo == 0 && !d->min_open ? d->min : d->min + 1e-6;
                (void)gr_contact_prepare(c->normal, NULL, &q, 0.5 * MASS, 0.0, &k, &err);
            }
        }
        for (int e = 0; c->normal->extremes && c->normal->extremes[e]; e++) {
            gr_contact_params x = p;
            apply_settings(&x, c->normal->extremes[e]);
            (void)gr_contact_prepare(c->normal, NULL, &x, 0.5 * MASS, 0.0, &k, &err);
        }
    }
}

static Suite *suite(void)
{
    enumerate();
    warm_calibrations();
    Suite *s = suite_create("models_conformance");
    TCase *tc = tcase_create("conformance");
    tcase_add_test(tc, test_registry_covered);
    tcase_add_test(tc, test_reference_needs_law);
    tcase_add_test(tc, test_shared_keys_one_place);
    tcase_add_loop_test(tc, test_restitution_law, 0, n_combos);
    tcase_add_loop_test(tc, test_engine_vs_reference, 0, n_combos);
    tcase_add_loop_test(tc, test_elastic, 0, n_combos);
    tcase_add_loop_test(tc, test_hard_cases, 0, n_combos);
    tcase_add_loop_test(tc, test_periodic_and_ledger, 0, n_combos);
    tcase_add_loop_test(tc, test_generic_kernel, 0, n_combos);
    tcase_add_loop_test(tc, test_spheres_in_plane, 0, n_combos);
    tcase_add_test(tc, test_kernel_instances_bounded);
    n_rolls = 0;
    for (int i = 0; i < n_combos; i++) {
        if (combos[i].rolling) {
            rolls[n_rolls++] = i;
        }
    }
    tcase_add_loop_test(tc, test_rolling_law, 0, n_rolls);
    tcase_add_loop_test(tc, test_event_rule, 0, n_events);
    tcase_add_loop_test(tc, test_event_elastic, 0, n_events);
    tcase_add_loop_test(tc, test_event_hard_cases, 0, n_events);
    tcase_set_timeout(tc, 300);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
