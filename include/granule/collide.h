/* One binary collision (sec. 2.1.5, Table 2.1), time-stepped by the engine itself or integrated
 * by SUNDIALS CVODE at tight tolerance as a reference. Used by `granule collide` and by the
 * collision test suite. All velocities and energies are those of the relative motion (the
 * centre-of-mass frame), which is what "Delta T / T" of (2.13)-(2.14) refers to. */
#ifndef GRANULE_COLLIDE_H
#define GRANULE_COLLIDE_H

#include <stdbool.h>

#include "granule/model.h"
#include "granule/status.h"

/* Initial positions and velocities of the two particles (2D; 1D uses the x components). */
typedef struct gr_collision_case {
    double x1[2], v1[2], x2[2], v2[2];
} gr_collision_case;

/* Collision `number` (1-4) of Table 2.1 for particles of the given radius. */
int gr_collision_case_table21(int number, double radius, gr_collision_case *out, gr_error *err);

/* An oblique impact (2D): particle 2 at rest, particle 1 approaching with relative speed `speed`
 * (m/s, > 0) at `angle_deg` in [0, 90) degrees between -g and the line of centres at first touch,
 * which is the x axis (n = (1, 0) at impact, so the outgoing normal and tangential velocities are
 * the x and y components); the pair starts r/2 apart along the normal. Refused out of range,
 * naming the flag (--speed, --angle) and the allowed range. */
int gr_collision_case_oblique(double speed, double angle_deg, double radius, gr_collision_case *out,
                              gr_error *err);

typedef struct gr_collide_setup {
    const gr_model *normal;     /* spring_dashpot (or hard_sphere once event rules exist) */
    const gr_model *tangential; /* NULL, tangential_dashpot or sliding_friction */
    const gr_model *rolling;    /* NULL or rolling_friction (needs contact.rotation) */
    gr_contact_params contact;
    double mass;   /* of each particle, kg (Table 2.1: 1 kg) */
    double radius; /* m */
    double dt;     /* s; 0: t_c / steps_per_contact */
    double steps_per_contact;
    bool force_dt;
    int dim;               /* 1, 2 or 3 (spheres: the case's positions and velocities lie in
                              the plane z = 0, the spins are vectors w1, w2) */
    double phase;          /* in [0, 1): where in a time step the contact begins (averaging over it
                        removes the discretisation's phase noise) */
    double ref_rtol;       /* relative tolerance of the CVODE reference (default 1e-12) */
    double omega1, omega2; /* initial angular velocities, rad/s counterclockwise (default 0;
                              nonzero needs rotation: [model] rotation = true) */
    double w1[3], w2[3];   /* dim = 3: the initial angular velocity vectors, rad/s (omega1, omega2
                            unused) */
} gr_collide_setup;

void gr_collide_setup_default(gr_collide_setup *s);

typedef struct gr_collide_result {
    double energy_loss;    /* 1 - |g'|^2 / |g|^2, g = relative velocity before, g' after; with
                              rotation 1 - E'/E, E = m12 |g|^2 / 2 + I (w1^2 + w2^2) / 2 (the
                              spins before and after) */
    double expected_loss;  /* (1 - eps_n^2) cos^2(a) + (1 - eps_t,eff^2) sin^2(a), a = impact angle;
                              1 - eps^2 head-on (2.13), 1 - (eps_n^2+eps_t^2)/2 at 45 deg (2.14);
                              NaN when the discs spin before the impact (no such law) */
    double contact_time;   /* s, while the contact force acted */
    double max_overlap;    /* m */
    double eps_n_measured; /* -g'.n' / g.n with n at the start (n') and end of contact */
    double eps_t_measured; /* g'.t' / g.t (NaN for a head-on collision); with rotation that of
                              the contact point, (g'.t' + r (w1' + w2')) / (g.t + r (w1 + w2));
                              3D: the contact point's tangential velocity after (with n') along
                              its direction before, over its magnitude before */
    double omega1, omega2; /* rotation: angular velocities after the collision, rad/s
                              (counterclockwise; 0 without rotation; they start at the setup's
                              omega1, omega2; with initial spins E includes them) */
    double v1[3], v2[3];   /* the particles' velocities after the collision, m/s (z: dim = 3) */
    double w1[3], w2[3];   /* dim = 3 with rotation: the angular velocity vectors after, rad/s */
    double spin_loss;      /* rotation: I (w1^2 + w2^2) / 2 before minus after, over E (the spins'
                              share of energy_loss; rolling resistance takes it from there) */
    double impact_angle;   /* degrees between -g and the normal at impact */
    double momentum_error; /* |p' - p| / |p| */
    double normal_impulse, tangential_impulse; /* int |F_n| dt and int |F_t| dt, N s */
    bool tangential_reversed;                  /* the tangential relative velocity changed sign */
    double dt;                                 /* the time step used (0 for the reference) */
    /* the reference only (0 from the engine): where the lost energy went, as fractions of E, so
     * that energy_loss = diss_normal + diss_tangential + diss_rolling + stored_lost - work_free */
    double diss_normal, diss_tangential; /* work of the laws' non-conservative forces (dashpots,
                                            friction, the spring's slip) */
    double diss_rolling;                 /* the rolling law's torques' work on the spins */
    double stored_lost; /* elastic energy still in the contact when it ends (clamped normal
                              law: xi > 0 there; tangential_spring: k_t s^2 / 2, forgotten) */
    double work_free;   /* tangential_spring with Mindlin stiffness: energy the spring gained
                              without work, int (s^2 / 2) dk_t/dt dt (k_t changes with xi) */
} gr_collide_result;

/* A collision may resolve its contact time in at most this many steps (a smaller dt is refused). */
#define GR_COLLIDE_MAX_STEPS_PER_CONTACT 1e7
/* Largest share of eps_n_measured that the turning of the line of centres during a grazing contact
 * may explain (|g_t / g_n| sin(turn)); beyond it the impact is refused as unmeasurable. */
#define GR_COLLIDE_MAX_TURN_ERROR 0.5

/* Time-step the collision with the engine's own kernel. GR_EINVAL (naming the cause) when the
 * experiment cannot measure a collision: the discs never touch, pass through each other
 * (tunnelling: a step too long or a force too soft for the speed), or graze so that the normal
 * turns too far (GR_COLLIDE_MAX_TURN_ERROR), or dt is beyond GR_COLLIDE_MAX_STEPS_PER_CONTACT. */
int gr_collide_run(const gr_collide_setup *s, const gr_collision_case *cs, gr_collide_result *out,
                   gr_error *err);

/* Integrate the same contact with CVODE (Adams, rtol s->ref_rtol (1e-12 by default), scaled units) and root-finding for the end of the
 * contact; dt and phase are ignored. */
int gr_collide_reference(const gr_collide_setup *s, const gr_collision_case *cs,
                         gr_collide_result *out, gr_error *err);

/* The expected loss of a collision is the models' own law: gr_contact_expected_loss (model.h). */

#endif
