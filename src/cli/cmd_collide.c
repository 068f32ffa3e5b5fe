/* granule collide: one binary collision of Table 2.1, printed as one JSON object. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/collide.h"

/* --phases: each phase is one whole collision (as `granule cost --phases`) */
#define COLLIDE_MAX_PHASES 1000

typedef struct collide_args {
    gr_collide_setup s;
    int number, phases;
    const char *model, *speeds;
    double speed, angle; /* oblique impact: --speed V [--angle DEG] */
    bool reference;
    const char *omega1, *omega2; /* W (2D) or WX,WY,WZ (3D) */
    bool inertia_given;          /* --set inertia_factor=Q (else 2/5 with --dim 3) */
} collide_args;

/* --set KEY=VALUE: a model parameter, in the order given among the other options */
static bool apply_set(void *args, const char *v, double number)
{
    (void)number;
    collide_args *c = args;
    char key[64];
    const char *eq = strchr(v, '=');
    gr_error e = {0};
    snprintf(key, sizeof key, "%.*s", eq ? (int)(eq - v) : 0, v);
    if (!eq || gr_contact_set(&c->s.contact, key, eq + 1, &e) != GR_OK) {
        app_error("collide: --set %s: %s", v, eq ? e.message : "expected KEY=VALUE");
        return false;
    }
    c->inertia_given = c->inertia_given || strcmp(key, "inertia_factor") == 0;
    return true;
}

static const cli_opt collide_opts[] = {
    {"--case", CLI_INT, "N", offsetof(collide_args, number), 1, 4, 0, "1",
     "collision N of Table 2.1", NULL},
    {"--model", CLI_STRING, "NORMAL[+TANGENTIAL[+ROLLING]]", offsetof(collide_args, model), 0, 0, 0,
     "spring_dashpot", "the collision model (granule models lists them)", NULL},
    {"--eps-n", CLI_DOUBLE, "E", offsetof(collide_args, s.contact.eps_n), 0, 0, 0, "0.6",
     "normal restitution, allowed (0, 1] (eps_n = 0 is a sticking pair that never separates, so "
     "there is no collision "
     "to measure; a scene may use it with spring_dashpot)",
     NULL},
    {"--eps-t", CLI_DOUBLE, "E", offsetof(collide_args, s.contact.eps_t), 0, 0, 0, "0.6",
     "tangential restitution, allowed [0, 1] (a tangential model)", NULL},
    {"--mu", CLI_DOUBLE, "MU", offsetof(collide_args, s.contact.mu), 0, 0, 0, "0.5",
     "sliding friction, >= 0 (a sliding_friction model)", NULL},
    {"--k", CLI_DOUBLE, "K", offsetof(collide_args, s.contact.k_s), 0, 0, 0, "5e5",
     "spring constant, N/m (a soft model)", NULL},
    {"--dt", CLI_DOUBLE, "DT", offsetof(collide_args, s.dt), 0, 0, 0, "t_c/50", "time step, s",
     NULL},
    {"--steps-per-contact", CLI_DOUBLE, "S", offsetof(collide_args, s.steps_per_contact), 0, 0, 0,
     "50", "time steps per contact time (instead of --dt)", NULL},
    {"--mass", CLI_DOUBLE, "M", offsetof(collide_args, s.mass), 0, 0, 0, "1",
     "mass of each particle, kg", NULL},
    {"--radius", CLI_DOUBLE, "R", offsetof(collide_args, s.radius), 0, 0, 0, "0.1",
     "radius, m (so the overlap v/w0 = 1 mm stays small; the RFM's particles: --mass 3.53e-5 "
     "--radius 1.5e-3)",
     NULL},
    {"--clamp", CLI_FLAG, NULL, offsetof(collide_args, s.contact.clamp), 0, 0, 0, NULL,
     "the normal force never attracts (gamma_n from the clamped restitution)", NULL},
    {"--dim", CLI_INT, "1|2|3", offsetof(collide_args, s.dim), 1, 3, 0, "2",
     "dimension (3: spheres, the impact in the plane z = 0; rotation's inertia_factor defaults to "
     "2/5)",
     NULL},
    {"--phases", CLI_INT, "P", offsetof(collide_args, phases), 1, COLLIDE_MAX_PHASES, 0, "1",
     "average P contact phases (start offsets within a time step)", NULL},
    {"--force-dt", CLI_FLAG, NULL, offsetof(collide_args, s.force_dt), 0, 0, 0, NULL,
     "take --dt even above t_c/10", NULL},
    {"--reference", CLI_FLAG, NULL, offsetof(collide_args, reference), 0, 0, 0, NULL,
     "also integrate the contact with SUNDIALS CVODE and add reference_energy_loss", NULL},
    {"--rtol", CLI_DOUBLE, "TOL", offsetof(collide_args, s.ref_rtol), 1e-14, 1e-2, 0, "1e-12",
     "relative tolerance of the CVODE reference", NULL},
    {"--set", CLI_LIST, "KEY=VALUE", CLI_NOWHERE, 0, 0, 0, NULL,
     "any model parameter of `granule models`, e.g. --model hertz --set viscoelastic=true --set "
     "visco_A=1e-6 "
     "(repeatable)",
     apply_set},
    {"--speeds", CLI_STRING, "V1,V2,...", offsetof(collide_args, speeds), 0, 0, 0, NULL,
     "add restitution_vs_speed: head-on impacts at these relative speeds (m/s)", NULL},
    {"--speed", CLI_DOUBLE, "V", offsetof(collide_args, speed), 0, INFINITY, CLI_MIN_OPEN, NULL,
     "an oblique impact (2D) at this relative speed, m/s, instead of --case", NULL},
    {"--angle", CLI_DOUBLE, "DEG", offsetof(collide_args, angle), 0, 90, CLI_MAX_OPEN, "0",
     "with --speed: the angle between -g and the line of centres at first touch", NULL},
    {"--omega1", CLI_STRING, "W1|WX,WY,WZ", offsetof(collide_args, omega1), 0, 0, 0, "0",
     "initial angular velocity of particle 1, rad/s: counterclockwise in 2D, the vector wx,wy,wz "
     "with --dim 3 (needs rotation)",
     NULL},
    {"--omega2", CLI_STRING, "W2|WX,WY,WZ", offsetof(collide_args, omega2), 0, 0, 0, "0",
     "initial angular velocity of particle 2, as --omega1", NULL},
};

const cli_command cli_cmd_collide = {
    .name = "collide",
    .usage =
        "granule collide [--case N] [--model NORMAL[+TANGENTIAL[+ROLLING]]] [--eps-n E] [--eps-t "
        "E]\n"
        "                       [--mu MU] [--k K] [--dt DT | --steps-per-contact S] [--mass M]\n"
        "                       [--radius R] [--clamp] [--dim 1|2|3] [--phases P] [--force-dt] "
        "[--reference [--rtol TOL]]\n"
        "                       [--set KEY=VALUE ...] [--speeds V1,V2,...]\n"
        "                       [--speed V --angle DEG] [--omega1 W1] [--omega2 W2]",
    .about =
        "Runs collision N (1-4) of Table 2.1 (particle 2 at rest; 1 kg masses unless --mass) and\n"
        "prints one JSON object: energy_loss (fraction of the relative kinetic energy lost),\n"
        "expected_loss (1 - eps^2 head-on, 1 - (eps_n^2 + eps_t^2)/2 at 45 degrees; in general\n"
        "(1 - eps_n^2) cos^2 a + (1 - eps_t^2) sin^2 a), contact_time, max_overlap, "
        "eps_n_measured,\n"
        "eps_t_measured, impact_angle. --phases P averages P contact phases. --reference also "
        "integrates\n"
        "the contact with SUNDIALS CVODE and adds reference_energy_loss. --model hard_sphere "
        "applies the\n"
        "instantaneous rule of the event-driven integrator (exact loss; contact_time 0); with "
        "--dim 3 and\n"
        "--set rotation=true --set beta=B (rough spheres) it takes --omega1/--omega2 vectors and "
        "reports\n"
        "omega1, omega2 after.\n"
        "--speeds V1,V2,... adds restitution_vs_speed: head-on impacts at these relative speeds "
        "(m/s),\n"
        "each with the engine's eps_n and contact time (steps with a force x dt), the model's own "
        "law\n"
        "eps_n(v) and contact time t_c(v) (and the CVODE reference's with --reference); for hertz "
        "the\n"
        "time step then follows each impact (dt = t_c(v) / steps-per-contact).\n"
        "The JSON lists only the parameters the chosen model uses (granule models; --eps-t and "
        "--mu\n"
        "need a tangential model, --k and --dt a soft one) and gives every unit in \"units\".\n",
    .epilog =
        "Rotation (--set rotation=true [--set inertia_factor=Q] with tangential_dashpot, "
        "sliding_friction or\n"
        "tangential_spring): energy_loss then includes the spin energy I w^2 / 2 of both discs,\n"
        "eps_t_measured is the contact point's tangential restitution (g.t + r (w1 + w2) after "
        "over\n"
        "before; the discs start without spin), and omega1, omega2 give the angular velocities "
        "after\n"
        "the collision (rad/s, counterclockwise).\n"
        "Oblique impact (instead of --case; 2D): --speed V --angle DEG, particle 2 at rest; the "
        "normal at\n"
        "impact is the x axis, so v1_after, v2_after (velocities after the collision) give the "
        "normal (x)\n"
        "and tangential (y) components. With --omega1, --omega2 expected_loss is null (the "
        "restitution\n"
        "laws assume discs without spin); energy_loss counts the spins' energy too, and spin_loss "
        "gives\n"
        "their share of it. Rolling resistance: --model NORMAL+TANGENTIAL+rolling_friction --set\n"
        "rotation=true [--set mu_r=M]; spin_loss_rolling_law is its law (J |w1 - w2| - J^2 / I,\n"
        "J = min(mu_r r/2 normal_impulse, I |w1 - w2| / 2), over the initial energy), which "
        "spin_loss\n"
        "equals when the contact point does not slip (head-on, --omega2 = -omega1).\n",
    CLI_OPTS(collide_opts),
};

/* the unit of every key collide prints besides the models' parameters (1: a pure number); those
 * take theirs from the models' descriptors */
static const struct {
    const char *key, *unit;
} units[] = {{"mass", "kg"},
             {"radius", "m"},
             {"dt", "s"},
             {"energy_loss", "1 (fraction of the relative kinetic energy)"},
             {"expected_loss", "1"},
             {"contact_time", "s"},
             {"max_overlap", "m"},
             {"eps_n_measured", "1"},
             {"eps_t_measured", "1"},
             {"impact_angle", "degrees"},
             {"momentum_error", "1 (|p' - p| / |p|)"},
             {"normal_impulse", "N s"},
             {"tangential_impulse", "N s"},
             {"relative_error", "1"},
             {"energy_loss_min", "1"},
             {"energy_loss_max", "1"},
             {"omega1", "rad/s (counterclockwise)"},
             {"omega2", "rad/s (counterclockwise)"},
             {"v1_after", "m/s"},
             {"v2_after", "m/s"},
             {"speed", "m/s"},
             {"angle", "degrees"},
             {"omega1_before", "rad/s (counterclockwise)"},
             {"omega2_before", "rad/s (counterclockwise)"},
             {"spin_loss", "1 (fraction of the initial energy)"},
             {"spin_loss_rolling_law", "1 (fraction of the initial energy)"}};

/* does the normal or the tangential model take the scene key `name`? */
static bool model_uses(const gr_collide_setup *s, const char *name)
{
    const gr_model *m[3] = {s->normal, s->tangential, s->rolling};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; m[k] && i < m[k]->n_params; i++) {
            if (!strcmp(m[k]->params[i].name, name)) {
                return true;
            }
        }
    }
    return false;
}

/* the chosen models' parameters (their [model] keys, from their descriptors), each once, with its
 * value: the keys a model declares are exactly the keys printed */
static void add_model_params(cJSON *o, const gr_collide_setup *s)
{
    const gr_model *m[3] = {s->normal, s->tangential, s->rolling};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; m[k] && i < m[k]->n_params; i++) {
            const gr_param *d = &m[k]->params[i];
            if (cJSON_GetObjectItem(o, d->name)) {
                continue; /* shared by two of the models (the rotation keys) */
            }
            const char *slot = (const char *)&s->contact + d->offset;
            if (d->type == GR_PARAM_BOOL) {
                cJSON_AddBoolToObject(o, d->name, *(const bool *)slot);
            } else {
                cJSON_AddNumberToObject(o, d->name, *(const double *)slot);
            }
        }
    }
}

/* "units": the unit of every number in o (a model parameter's from its descriptor) */
static void add_units(cJSON *o, const gr_collide_setup *s)
{
    cJSON *u = cJSON_CreateObject();
    const gr_model *m[3] = {s->normal, s->tangential, s->rolling};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; m[k] && i < m[k]->n_params; i++) {
            const gr_param *d = &m[k]->params[i];
            if (d->type != GR_PARAM_BOOL && cJSON_GetObjectItem(o, d->name) &&
                !cJSON_GetObjectItem(u, d->name)) {
                cJSON_AddStringToObject(u, d->name, d->unit[0] ? d->unit : "1");
            }
        }
    }
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++) {
        char ref[64];
        snprintf(ref, sizeof ref, "reference_%s", units[i].key);
        if (cJSON_GetObjectItem(o, units[i].key)) {
            cJSON_AddStringToObject(u, units[i].key, units[i].unit);
        }
        if (cJSON_GetObjectItem(o, ref)) {
            cJSON_AddStringToObject(u, ref, units[i].unit);
        }
    }
    cJSON_AddItemToObject(o, "units", u);
}

static void add_result(cJSON *o, const char *prefix, const gr_collide_result *r, bool instantaneous,
                       bool rotation, int dim)
{
    char key[64];
    struct {
        const char *name;
        double v;
    } f[] = {{"energy_loss", r->energy_loss},
             {"expected_loss", r->expected_loss},
             {"contact_time", r->contact_time},
             {"max_overlap", r->max_overlap},
             {"eps_n_measured", r->eps_n_measured},
             {"eps_t_measured", r->eps_t_measured},
             {"impact_angle", r->impact_angle},
             {"momentum_error", r->momentum_error},
             {"normal_impulse", r->normal_impulse},
             {"tangential_impulse", r->tangential_impulse},
             {"omega1", r->omega1},
             {"omega2", r->omega2}};
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
        if ((!rotation || dim == 3) && !strncmp(f[i].name, "omega", 5)) {
            continue; /* angular velocities only with [model] rotation = true (3D: vectors) */
        }
        if (instantaneous &&
            (!strcmp(f[i].name, "contact_time") || !strcmp(f[i].name, "max_overlap"))) {
            continue; /* an instantaneous collision has neither */
        }
        snprintf(key, sizeof key, "%s%s", prefix, f[i].name);
        if (isfinite(f[i].v)) {
            cJSON_AddNumberToObject(o, key, f[i].v);
        } else {
            cJSON_AddNullToObject(o, key);
        }
    }
    const double *v[2] = {r->v1, r->v2}, *w[2] = {r->w1, r->w2};
    for (int p = 0; p < 2; p++) {
        snprintf(key, sizeof key, "%sv%d_after", prefix, p + 1);
        cJSON_AddItemToObject(o, key, cJSON_CreateDoubleArray(v[p], dim == 3 ? 3 : 2));
        if (rotation && dim == 3) { /* the angular velocity vectors after the collision */
            snprintf(key, sizeof key, "%somega%d", prefix, p + 1);
            cJSON_AddItemToObject(o, key, cJSON_CreateDoubleArray(w[p], 3));
        }
    }
}

/* --omega1/--omega2: one number (1D, 2D: counterclockwise) or, with --dim 3, the vector
 * WX,WY,WZ; 0 means no spin in any dimension. Nonzero on error (printed). */
static int parse_spin(const char *opt, const char *text, int dim, double *scalar, double vec[3])
{
    double v[3] = {0.0, 0.0, 0.0};
    int n = 0;
    const char *p = text;
    char *end = NULL;
    while (n < 3) {
        v[n] = strtod(p, &end);
        if (end == p || !isfinite(v[n])) {
            end = NULL;
            break;
        }
        n++;
        p = end;
        if (*p != ',') {
            break;
        }
        p++;
    }
    const bool whole = end && *end == '\0';
    if (whole && n == 1 && v[0] == 0.0) {
        return 0; /* the default: no spin */
    }
    if (!whole || n != (dim == 3 ? 3 : 1)) {
        app_error("collide: %s %s: %s (rad/s)", opt, text,
                  dim == 3 ? "with --dim 3 give the angular velocity vector WX,WY,WZ, three "
                             "finite numbers, e.g. 0,0,150"
                           : "give one finite number, counterclockwise (WX,WY,WZ needs --dim 3)");
        return 1;
    }
    if (dim == 3) {
        memcpy(vec, v, sizeof v);
    } else {
        *scalar = v[0];
    }
    return 0;
}

/* restitution_vs_speed: head-on impacts at each speed of the comma-separated list */
static int add_speeds(cJSON *o, const gr_collide_setup *s0, const char *list, int phases,
                      bool reference)
{
    cJSON *arr = cJSON_AddArrayToObject(o, "restitution_vs_speed");
    char buf[512];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        char *end = NULL;
        const double v = strtod(tok, &end);
        if (end == tok || *end || !(v > 0.0) || !isfinite(v)) {
            app_error("collide: --speeds: '%s' is not a speed > 0 (m/s)", tok);
            return EXIT_REFUSED;
        }
        gr_collide_setup s = *s0;
        gr_contact_coeffs k;
        gr_error err = {0};
        if (gr_contact_prepare(s.normal, s.dim >= 2 ? s.tangential : NULL, &s.contact, 0.5 * s.mass,
                               0.0, &k, &err)) {
            app_error("collide: %s", err.message);
            return EXIT_REFUSED;
        }
        const gr_normal_impact law =
            s.normal->impact ? s.normal->impact(&k, v)
                             : (gr_normal_impact){k.eps_n_exact, k.t_c, 1.0 + k.eps_n_exact};
        if (s.dt == 0.0 && law.t_c > 0.0 && isfinite(law.t_c)) {
            s.dt = law.t_c / s.steps_per_contact; /* resolve this impact */
        }
        const double gap = 0.5 * s.radius; /* head-on, particle 2 at rest */
        gr_collision_case cs = {{0.0, 0.0}, {v, 0.0}, {2.0 * s.radius + gap, 0.0}, {0.0, 0.0}};
        double eps = 0.0, t_contact = 0.0;
        for (int p = 0; p < phases; p++) {
            gr_collide_result r;
            s.phase = phases == 1 ? 0.0 : (p + 0.5) / phases;
            if (gr_collide_run(&s, &cs, &r, &err)) {
                app_error("collide: %g m/s: %s", v, err.message);
                return EXIT_REFUSED;
            }
            eps += r.eps_n_measured / phases;
            t_contact += r.contact_time / phases;
        }
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "speed", v);
        cJSON_AddNumberToObject(e, "eps_n_measured", eps);
        cJSON_AddNumberToObject(e, "eps_n_law", law.eps_n);
        if (isfinite(law.t_c)) {
            cJSON_AddNumberToObject(e, "contact_time_law", law.t_c);
        } else {
            cJSON_AddNullToObject(e, "contact_time_law");
        }
        cJSON_AddNumberToObject(e, "contact_time_measured",
                                t_contact); /* steps with a force x dt */
        cJSON_AddNumberToObject(e, "dt", s.dt);
        if (reference) {
            gr_collide_result ref;
            if (gr_collide_reference(&s, &cs, &ref, &err)) {
                app_error("collide --reference: %g m/s: %s", v, err.message);
                return EXIT_REFUSED;
            }
            cJSON_AddNumberToObject(e, "eps_n_reference", ref.eps_n_measured);
            cJSON_AddNumberToObject(e, "contact_time_reference", ref.contact_time);
        }
        cJSON_AddItemToArray(arr, e);
    }
    return EXIT_OK;
}

int cmd_collide(int argc, char **argv)
{
    gr_collide_setup s;
    gr_collide_setup_default(&s);
    collide_args args = {.s = s,
                         .number = 1,
                         .phases = 1,
                         .model = "spring_dashpot",
                         .angle = NAN,
                         .omega1 = "0",
                         .omega2 = "0"};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_collide, argc, argv, &args, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    s = args.s;
    const int number = args.number, phases = args.phases;
    const bool reference = args.reference;
    const char *model = args.model, *speeds = args.speeds;
    struct {
        const char *opt, *key;
        bool set;
    } given[] = {{"--eps-t", "eps_t", false},
                 {"--mu", "mu", false},
                 {"--k", "k_s", false},
                 {"--clamp", "clamp", false}};
    for (size_t k = 0; k < sizeof given / sizeof given[0]; k++) {
        given[k].set = cli_given(&cli_cmd_collide, &pos, given[k].opt);
    }
    const bool oblique = args.speed > 0.0, angle_given = !isnan(args.angle);
    const double speed = args.speed, angle = angle_given ? args.angle : 0.0;
    /* validate like a scene would */
    if (!(s.contact.eps_n >= 0.0 && s.contact.eps_n <= 1.0) ||
        !(s.contact.eps_t >= 0.0 && s.contact.eps_t <= 1.0)) {
        app_error("collide: --eps-n %g, --eps-t %g: allowed ranges (0, 1] for --eps-n, [0, 1] for "
                  "--eps-t",
                  s.contact.eps_n, s.contact.eps_t);
        return EXIT_REFUSED;
    }
    if (!(s.contact.k_s > 0.0) || !(s.mass > 0.0) || !(s.radius > 0.0) || s.dt < 0.0 ||
        !(s.contact.mu >= 0.0) || s.dim < 1 || s.dim > 3 || phases < 1 ||
        (s.dt == 0.0 && !(s.steps_per_contact >= 1.0))) {
        app_error("collide: --k, --mass and --radius must be > 0, --dt >= 0, --mu >= 0, --dim 1, 2 "
                  "or 3, --phases >= 1");
        return EXIT_REFUSED;
    }
    char normal[64], tangential[64] = "", rolling[64] = "";
    const char *plus = strchr(model, '+'), *plus2 = plus ? strchr(plus + 1, '+') : NULL;
    snprintf(normal, sizeof normal, "%.*s", plus ? (int)(plus - model) : (int)strlen(model), model);
    if (plus) {
        snprintf(tangential, sizeof tangential, "%.*s",
                 plus2 ? (int)(plus2 - plus - 1) : (int)strlen(plus + 1), plus + 1);
    }
    if (plus2) {
        snprintf(rolling, sizeof rolling, "%s", plus2 + 1);
    }
    s.normal = gr_model_find(normal);
    s.tangential = tangential[0] ? gr_model_find(tangential) : NULL;
    s.rolling = rolling[0] ? gr_model_find(rolling) : NULL;
    if (!s.normal || !(s.normal->kind & (GR_MODEL_NORMAL | GR_MODEL_EVENT)) ||
        (tangential[0] && (!s.tangential || s.tangential->kind != GR_MODEL_TANGENTIAL)) ||
        (rolling[0] && (!s.rolling || s.rolling->kind != GR_MODEL_ROLLING))) {
        app_error("collide: --model %s: expected NORMAL[+TANGENTIAL[+ROLLING]], e.g. "
                  "spring_dashpot+tangential_dashpot or "
                  "spring_dashpot+sliding_friction+rolling_friction (granule models lists them)",
                  model);
        return EXIT_REFUSED;
    }
    if ((s.normal->kind & GR_MODEL_EVENT) && s.tangential) {
        app_error("collide: --model %s: hard_sphere carries its own tangential restitution "
                  "(--eps-t); give it without +TANGENTIAL",
                  model);
        return EXIT_REFUSED;
    }
    if (s.contact.eps_n == 0.0) {
        /* spring_dashpot documents [0, 1] with 0 = sticking (a scene may use it), hard_sphere and
         * the clamped law (0, 1]: either way no collision ends, so collide has nothing to measure */
        app_error("collide: --eps-n 0 is a sticking pair that never separates, so there is no "
                  "collision to measure; "
                  "collide needs eps_n in (0, 1] (allowed range), e.g. 0.001");
        return EXIT_REFUSED;
    }
    for (size_t k = 0; k < sizeof given / sizeof given[0]; k++) {
        if (given[k].set && !model_uses(&s, given[k].key)) {
            fprintf(stderr,
                    "granule: collide: warning: %s does not apply to --model %s (ignored)\n",
                    given[k].opt, model);
        }
    }
    if (angle_given && !oblique) {
        app_error("collide: --angle needs --speed V (an oblique impact; --case N gives Table 2.1's "
                  "geometries)");
        return EXIT_REFUSED;
    }
    if (oblique && s.dim == 1) {
        app_error("collide: --speed/--angle: an oblique impact needs --dim 2 or 3");
        return EXIT_REFUSED;
    }
    if (parse_spin("--omega1", args.omega1, s.dim, &s.omega1, s.w1) ||
        parse_spin("--omega2", args.omega2, s.dim, &s.omega2, s.w2)) {
        return EXIT_REFUSED;
    }
    if (s.dim == 3 && !args.inertia_given) {
        s.contact.inertia_factor = 0.4; /* solid spheres (2D: 1/2, discs), as a 3D scene */
    }
    gr_collision_case cs;
    gr_error err = {0};
    if (oblique ? gr_collision_case_oblique(speed, angle, s.radius, &cs, &err)
                : gr_collision_case_table21(number, s.radius, &cs, &err)) {
        app_error("collide: %s", err.message);
        return EXIT_REFUSED;
    }
    gr_collide_result r, sum = {0};
    double lo = INFINITY, hi = -INFINITY;
    for (int p = 0; p < phases; p++) {
        s.phase = (p + 0.5) / phases;
        if (phases == 1) {
            s.phase = 0.0;
        }
        if (gr_collide_run(&s, &cs, &r, &err)) {
            app_error("collide: %s", err.message);
            return app_exit_code(err.code);
        }
        lo = fmin(lo, r.energy_loss);
        hi = fmax(hi, r.energy_loss);
        sum.energy_loss += r.energy_loss / phases;
        sum.contact_time += r.contact_time / phases;
        sum.max_overlap = fmax(sum.max_overlap, r.max_overlap);
        sum.eps_n_measured += r.eps_n_measured / phases;
        sum.eps_t_measured += r.eps_t_measured / phases;
        sum.momentum_error = fmax(sum.momentum_error, r.momentum_error);
        sum.normal_impulse += r.normal_impulse / phases;
        sum.tangential_impulse += r.tangential_impulse / phases;
        sum.tangential_reversed |= r.tangential_reversed;
        sum.omega1 += r.omega1 / phases;
        sum.omega2 += r.omega2 / phases;
        for (int k = 0; k < 3; k++) {
            sum.v1[k] += r.v1[k] / phases;
            sum.v2[k] += r.v2[k] / phases;
            sum.w1[k] += r.w1[k] / phases;
            sum.w2[k] += r.w2[k] / phases;
        }
        sum.spin_loss += r.spin_loss / phases;
    }
    sum.expected_loss = r.expected_loss;
    sum.impact_angle = r.impact_angle;
    cJSON *o = cJSON_CreateObject();
    if (oblique) {
        cJSON_AddNumberToObject(o, "speed", speed);
        cJSON_AddNumberToObject(o, "angle", angle);
    } else {
        cJSON_AddNumberToObject(o, "case", number);
    }
    cJSON_AddStringToObject(o, "model", model);
    const bool instantaneous = (s.normal->kind & GR_MODEL_EVENT) != 0;
    /* only the parameters the chosen models take (their [model] keys) */
    add_model_params(o, &s);
    /* 3D: rough hard spheres report their spin vectors too (2D's rule output is unchanged) */
    const bool rotation =
        s.dim >= 2 && s.contact.rotation &&
        ((s.tangential && s.tangential->contact_point) || (s.dim == 3 && instantaneous));
    if (rotation && s.dim == 3) {
        cJSON_AddItemToObject(o, "omega1_before", cJSON_CreateDoubleArray(s.w1, 3));
        cJSON_AddItemToObject(o, "omega2_before", cJSON_CreateDoubleArray(s.w2, 3));
    } else if (rotation) {
        cJSON_AddNumberToObject(o, "omega1_before", s.omega1);
        cJSON_AddNumberToObject(o, "omega2_before", s.omega2);
    }
    if (rotation) {
        cJSON_AddNumberToObject(o, "spin_loss", sum.spin_loss);
    }
    if (rotation && s.rolling && s.dim == 2) {
        /* the rolling law's spin loss with the measured normal impulse, over the initial energy */
        gr_contact_coeffs k;
        gr_error e2 = {0};
        if (gr_contact_prepare(s.normal, s.tangential, &s.contact, 0.5 * s.mass, 0.0, &k, &e2) ==
                GR_OK &&
            gr_contact_prepare_rolling(s.rolling, &s.contact, 0.5 * s.mass, 0.0, &k, &e2) ==
                GR_OK) {
            const double inertia = s.contact.inertia_factor * s.mass * s.radius * s.radius;
            const double g2 = (cs.v2[0] - cs.v1[0]) * (cs.v2[0] - cs.v1[0]) +
                              (cs.v2[1] - cs.v1[1]) * (cs.v2[1] - cs.v1[1]);
            const double e0 =
                0.25 * s.mass * g2 + 0.5 * inertia * (s.omega1 * s.omega1 + s.omega2 * s.omega2);
            cJSON_AddStringToObject(o, "rolling", s.rolling->name);
            cJSON_AddNumberToObject(o, "spin_loss_rolling_law",
                                    s.rolling->spin_loss(&k, sum.normal_impulse, 0.5 * s.radius,
                                                         inertia, s.omega1 - s.omega2) /
                                        e0);
        }
    }
    cJSON_AddNumberToObject(o, "mass", s.mass);
    cJSON_AddNumberToObject(o, "radius", s.radius);
    if (!instantaneous) {
        cJSON_AddNumberToObject(o, "dt", r.dt);
    }
    cJSON_AddNumberToObject(o, "phases", phases);
    if (s.dim == 3) {
        cJSON_AddNumberToObject(o, "dim", 3);
    }
    add_result(o, "", &sum, instantaneous, rotation, s.dim);
    cJSON_AddNumberToObject(o, "relative_error",
                            (sum.energy_loss - sum.expected_loss) /
                                fmax(sum.expected_loss, 1e-300));
    if (phases > 1) {
        cJSON_AddNumberToObject(o, "energy_loss_min", lo);
        cJSON_AddNumberToObject(o, "energy_loss_max", hi);
    }
    cJSON_AddBoolToObject(o, "tangential_reversed", sum.tangential_reversed);
    if (reference) {
        gr_collide_result ref;
        if (gr_collide_reference(&s, &cs, &ref, &err)) {
            cJSON_Delete(o);
            app_error("collide --reference: %s", err.message);
            return app_exit_code(err.code);
        }
        add_result(o, "reference_", &ref, instantaneous, rotation, s.dim);
    }
    if (speeds && add_speeds(o, &s, speeds, phases, reference) != EXIT_OK) {
        cJSON_Delete(o);
        return EXIT_REFUSED;
    }
    add_units(o, &s);
    char *text = cJSON_Print(o);
    puts(text);
    cJSON_free(text);
    cJSON_Delete(o);
    return EXIT_OK;
}
