/* Collision-model plugins: each model is one file, models/NAME.h, holding its parameter
 * descriptors, its `prepare` and its pair law (a static inline function); models/list.h lists
 * every model once, and the registry `gr_models`, the force kernels and the conformance suite
 * are generated from that list (docs/architecture.md, "How to add a collision model").
 *
 * A model declares its parameters (name, unit, default, allowed range, one-line doc); the scene
 * parser validates scene keys against them and `granule models` lists them. Its `prepare`
 * turns physical inputs (k_s, restitution coefficients, masses, time step) into solver
 * coefficients once per run. The core never calls a model per pair: the coefficients feed
 * specialised pair loops, instantiated from the models' laws and chosen once per run
 * (src/core/kernels.c, models/law.h). */
#ifndef GRANULE_MODEL_H
#define GRANULE_MODEL_H

#include <stdbool.h>
#include <stddef.h>

#include "granule/status.h"

/* [model] tc = off: the TC rule switched off (hard_sphere; docs/event-driven.md) */
#define GR_TC_OFF (-1.0)

typedef enum { GR_PARAM_DOUBLE, GR_PARAM_BOOL, GR_PARAM_INT } gr_param_type;

/* One scene key. `offset` locates the value inside the struct the descriptor table belongs to
 * (gr_contact_params for model parameters). Ranges are inclusive unless *_open is set. */
typedef struct gr_param {
    const char *name;
    const char *unit;
    gr_param_type type;
    double def;
    double min, max;
    bool min_open, max_open;
    const char *doc;
    size_t offset;
} gr_param;

/* room for the models' own parameters in gr_contact_params.own (96 bytes used; the size keeps
 * gr_contact_params at its size before the blocks, 152 bytes: raise it when the build asks) */
#define GR_CONTACT_OWN_BYTES 104

/* Inputs of the contact laws, as given in a scene's [model] section: the keys several laws share,
 * and each model's own keys in a block of its own. */
typedef struct gr_contact_params {
    double k_s;    /* normal spring constant, N/m (2.4) */
    double eps_n;  /* normal coefficient of restitution (2.2) */
    double eps_t;  /* tangential coefficient of restitution (2.10) */
    double mu;     /* sliding-friction coefficient (2.7) */
    bool clamp;    /* true: normal force never attractive, gamma_n from the clamped restitution */
    bool rotation; /* a tangential law at the contact point: discs rotate (omega, torque) */
    double inertia_factor; /* rotation: moment of inertia I = q M r^2, q (1/2: uniform disc) */
    /* The models' own parameters (hertz's k_h, hard_sphere's beta, ...): one block per model,
     * declared in its own file as a struct NAME_own (models/NAME.h) and laid out by models/list.h;
     * only the model (and a law built on it) reads its block. Set and read them by name
     * (gr_contact_set, gr_contact_set_value, gr_contact_get). */
    _Alignas(8) unsigned char own[GR_CONTACT_OWN_BYTES];
} gr_contact_params;

struct gr_model;

/* A normal law's binary head-on impact at normal speed v_n, in continuous time (two equal discs,
 * no rotation): what the tangential laws' restitution needs. */
typedef struct gr_normal_impact {
    double eps_n;       /* normal restitution */
    double t_c;         /* contact duration, s (0: instantaneous; infinite: the pair sticks) */
    double impulse_abs; /* int |F_n| dt / (m12 v_n): 1 + eps_n unless the force turns attractive */
} gr_normal_impact;

/* Solver coefficients derived once per run by the models' prepare functions; `normal_model` /
 * `tangential_model` are the models themselves (set by gr_contact_prepare). A law with constants of its own keeps them in law_n / law_t (the model's
 * file names the slots). */
typedef struct gr_contact_coeffs {
    const struct gr_model *normal_model, *tangential_model;
    double m12;         /* reduced mass of a colliding pair, kg */
    double k_s;         /* N/m */
    double gamma_n;     /* normal dashpot, kg/s (2.5) */
    bool clamp;         /* clamp F_n >= 0 */
    double w0;          /* undamped contact frequency sqrt(k_s/m12), rad/s */
    double zeta;        /* damping ratio gamma_n / (2 sqrt(k_s m12)) */
    double t_c;         /* duration of a binary contact, s (infinite when the pair sticks) */
    double eps_n_exact; /* restitution the continuous-time law really gives */
    double gamma_t;     /* tangential dashpot, kg/s (2.9) */
    double mu;          /* sliding friction (2.7) */
    /* Rotation (gr_contact_params.rotation with a tangential law that acts at the contact point):
     * q = inertia_factor; m_t is the mass that resists the contact point's tangential relative
     * motion, m12 without rotation and m12 q / (1 + q) with it (docs/models.md, "Rotation"). */
    bool rotation;
    double q;
    double m_t;
    double e_scale; /* elastic energy of a contact = e_scale * (the law's e), J per unit of e */
    /* The normal law as F = k_s xi^pow_a - gamma_n xi^pow_p g_n (before the clamp): pow_a = 1,
     * pow_p = 0 for the linear law; hertz has 3/2 and 1/2 or 1/4 (k_s, gamma_n then in the units
     * these powers need). The CVODE reference (src/collide/reference.c) integrates this form. */
    double pow_a, pow_p;
    /* Event rules: the TC-model time, s (docs/event-driven.md): the integrator makes a collision
     * elastic when either disc collided less than tc ago, and separates a noise-pressed pair fast
     * enough to stay apart that long; 0 = no TC rule. Set by the rule's prepare. */
    double tc;
    double law_n[4]; /* constants private to the normal law */
    double law_t[4]; /* constants private to the tangential law */
    /* Rolling resistance (gr_contact_prepare_rolling; NULL / 0 without): the law and its constants
     * (private to it, as law_n / law_t; the model's file names the slots). */
    const struct gr_model *rolling_model;
    double law_r[4];
} gr_contact_coeffs;

typedef enum {
    GR_MODEL_NORMAL = 1,     /* a normal contact force law */
    GR_MODEL_TANGENTIAL = 2, /* a tangential contact force law */
    GR_MODEL_EVENT = 4,      /* an instantaneous event rule (event-driven integrator) */
    GR_MODEL_ROLLING = 8     /* a rolling-resistance torque law (needs rotation) */
} gr_model_kind;

typedef struct gr_model {
    const char *name;
    const char *summary; /* one line */
    gr_model_kind kind;
    const gr_param *params;
    int n_params;
    /* Derive this model's coefficients. Normal models run first and set t_c; tangential models
     * may read it. `dt` is the time step (0 when the caller only wants the continuous law). */
    int (*prepare)(const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                   gr_error *err);
    /* Tangential and rolling laws (optional): true when the prepared coefficients make the law do nothing
     * (eps_t = 1, mu = 0); the kernel without it then runs. Called once per run. */
    bool (*inert)(const gr_contact_coeffs *c);
    /* Tangential laws: the force acts at the contact point, so the discs may rotate (the scene
     * key rotation = true is then legal; the law then sees the contact point's velocity). */
    bool contact_point;
    /* Tangential laws: the law's tangential restitution is the parameter eps_t itself, the same at
     * every impact (tangential_dashpot). Code that needs a constant eps_t (the S(k) observable's
     * dissipative window, thesis eq. 4.5) asks this flag, never the model's name. */
    bool constant_eps_t;
    /* The LAMMPS pair style this law is the same force as (granule export lammps, docs/lammps.md;
     * NULL: none). A normal and a tangential law export together when they name the same style
     * (spring_dashpot and tangential_dashpot: gran/hooke, whose gamma_t is the dashpot's). */
    const char *lammps_pair;
    /* Event rules: the normal force law whose kernel evaluates forces when the engine asks for
     * them (the initial state, which has no overlaps), with the coefficients prepare set. */
    const char *force_law;
    /* The model's own restitution law, in continuous time, for a binary impact of two equal
     * discs without rotation (the conformance suite and `granule collide` check the engine
     * against it). Normal laws and event rules: the impact at normal speed v_n > 0 (the same at
     * every speed for the linear law). Tangential laws (and event rules): the tangential
     * restitution given that normal impact and the impact speeds v_n, v_t > 0. */
    gr_normal_impact (*impact)(const gr_contact_coeffs *c, double v_n);
    double (*restitution_t)(const gr_contact_coeffs *c, gr_normal_impact n, double v_n, double v_t);
    /* Tangential laws (required): the force the CVODE reference (src/collide/reference.c)
     * integrates for this law, in continuous time (models/reference.h). */
    const struct gr_reference_law *reference;
    /* Rolling laws: the spin energy (J) one contact takes from two discs of moment of inertia
     * `inertia` whose spins differ by dw0 (w_i - w_j, the contact point not slipping) while it
     * transmits the normal impulse p_n = int |F_n| dt; r_eff = r / 2 for equal discs. */
    double (*spin_loss)(const gr_contact_coeffs *c, double p_n, double r_eff, double inertia,
                        double dw0);
    /* Rolling laws (required): the torque the CVODE reference integrates (models/reference.h) */
    const struct gr_reference_rolling *reference_rolling;
    /* Parameter settings that make the model conserve energy ("eps_n=1", space-separated
     * key=value); the conformance suite applies them to test elastic impacts. */
    const char *elastic;
    /* Optional, NULL-terminated: settings selecting each mode of the law ("viscoelastic=true";
     * tangential_spring's "mindlin=true", tested with the normal laws that accept it);
     * the conformance suite tests every mode as a combination of its own. */
    const char *const *variants;
    /* Optional, NULL-terminated: extreme settings beyond the eps minima (which the suite tries by
     * itself), e.g. an overdamped viscoelastic time; each must give finite results or a clean
     * refusal. */
    const char *const *extremes;
} gr_model;

/* The registry: every built-in model, NULL-terminated. */
extern const gr_model *const gr_models[];

/* Look a model up by name; NULL if unknown. */
const gr_model *gr_model_find(const char *name);

/* Derive coefficients for a normal model combined with an optional tangential model
 * (tangential may be NULL). */
/* Every model parameter at its descriptor's default (as a scene without [model] keys has them). */
void gr_contact_defaults(gr_contact_params *p);

/* Set the model parameter `name` from text, checked against its descriptor's type and range;
 * GR_EINVAL (naming the key and the allowed range) if unknown or out of range. */
int gr_contact_set(gr_contact_params *p, const char *name, const char *value, gr_error *err);

/* Set the double or bool model parameter `name` to v (a bool: v != 0), checked against its
 * descriptor's range as gr_contact_set; GR_EINVAL (naming the key) if unknown or out of range. */
int gr_contact_set_value(gr_contact_params *p, const char *name, double v, gr_error *err);

/* The model parameter `name` as a double (a bool: 0 or 1); NAN if no model declares it. */
double gr_contact_get(const gr_contact_params *p, const char *name);

/* Expected fraction of the relative kinetic energy a binary impact loses, from the models' own
 * restitution laws (gr_model.restitution etc.): (1 - eps_n^2) cos^2 a + (1 - eps_t^2) sin^2 a for
 * impact speed `speed` (m/s) at angle `angle_deg` between -g and the normal. */
double gr_contact_expected_loss(const gr_contact_coeffs *c, double speed, double angle_deg);

/* One overlapping pair of a frame: r_ij = r_j - r_i (minimum image, |r_ij| < d) and the relative
 * velocity g = v_j - v_i (dy, gy zero in 1D). */
typedef struct gr_contact_pair {
    double dx, dy, gx, gy;
} gr_contact_pair;

/* The contact virial of a frame's overlapping pairs, from the force kernel's own normal law
 * (src/core/kernels.c: the law of models/list.h that gr_kernel_choose runs for c, inlined the
 * same way, clamped if c->clamp; an event rule's stand-in law is not a force of the frame): adds
 * |r_ij| f_n n_a n_b, the virial r_ij,a F_ij,b of the normal force F_ij = f_n n of i on j
 * (n = r_ij / |r_ij|), to w[0] (xx), w[1] (yy), w[2] (xy), pair by pair in the order given
 * (pairs at r_ij = 0 are skipped); d is the diameter. Returns the law's name, or NULL (nothing
 * added) when c has no normal force law (an event rule, or no model). Tangential forces are not
 * included: their laws need the contact's history and spins, which a frame does not hold. */
const char *gr_contact_virial(const gr_contact_coeffs *c, double d, const gr_contact_pair *pairs,
                              int n, double w[3]);

/* A radius distribution's pair (reduced mass M, effective radius R = r_i r_j / (r_i + r_j)): the
 * reference pair's coefficients ref (reduced mass m_ref, effective radius r_ref;
 * gr_size_reference_coeffs) scaled as the force kernel scales them, the stiffness as
 * (R / r_ref)^(a - 1) for a force k xi^a and the damping as sqrt(M k), so every pair keeps the
 * scene's eps_n (src/core/sim_internal.h, gr_size_scaled). */
void gr_contact_size_scaled(const gr_contact_coeffs *ref, double m_ref, double r_ref, double M,
                            double R, gr_contact_coeffs *c);

int gr_contact_prepare(const gr_model *normal, const gr_model *tangential,
                       const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                       gr_error *err);

/* Add a rolling law (NULL: none) to coefficients gr_contact_prepare has made; it needs
 * c->rotation (GR_EINVAL naming the keys otherwise). */
int gr_contact_prepare_rolling(const gr_model *rolling, const gr_contact_params *p, double m12,
                               double dt, gr_contact_coeffs *c, gr_error *err);

#endif
