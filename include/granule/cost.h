/* What accuracy costs (`granule cost`, docs/performance.md "What accuracy costs"): for a scene
 * with a soft contact law, the largest time step whose error in a chosen observable stays within
 * a tolerance, and the wall time a run of the scene will take with it on this machine.
 *
 * The error of the time step is the contact's: velocity Verlet integrates each contact in
 * t_c / dt steps, and the energy a collision removes comes out wrong by a relative amount that
 * grows with dt (docs/performance.md, "Accuracy against cost"). It is computed, not looked up:
 * the scene's own pair collides head-on (and, in 2D, obliquely: Table 2.1 cases 1 and 3) at each
 * candidate dt over several contact phases and is compared with the SUNDIALS CVODE integration of
 * the same contact (gr_collide_reference). A particle pressed inside a cluster vibrates faster
 * than a pair (sqrt(2) in a 1D chain, sqrt(3) in a close-packed 2D cluster), so each dt is also
 * checked at dt times that factor: past it the clusters blow up although a pair would not. The steady temperature follows from the energy
 * balance of the driven gas: with injection fixed by D, the dissipation rate
 * ~ (1 - eps^2) n T^(3/2) (homogeneous gas) must stay equal to it, so a relative error delta of
 * the energy lost per collision shifts T by -(2/3) delta (T ~ (1 - eps^2)^(-2/3); the same
 * homogeneous argument that gives xi_2 = 2/3 in sec. 3.2). The wall time is measured: a short
 * calibration run of the scene at the chosen dt on this machine, in blocks, whose spread is the
 * prediction's uncertainty. The calibration also times the hybrid integrator at the same dt over a
 * few windows (docs/hybrid.md): its contacts are the same Verlet steps and its free flights exact
 * in law, so its error is the time step's, and only the cost differs; the cheapest is recommended. */
#ifndef GRANULE_COST_H
#define GRANULE_COST_H

#include <stdbool.h>

#include "granule/collide.h"
#include "granule/scene.h"
#include "granule/status.h"

typedef enum {
    GR_COST_LOSS, /* the energy lost in one collision, worst contact phase (per-collision accuracy) */
    GR_COST_T,    /* the steady temperature (2.19), through the energy balance above */
} gr_cost_observable;

const char *gr_cost_observable_name(gr_cost_observable o);
/* "loss" or "T"; returns -1 for anything else */
int gr_cost_observable_parse(const char *name);

#define GR_COST_MAX_CANDIDATES 16

typedef struct gr_cost_candidate {
    double dt;                /* s */
    double steps_per_contact; /* t_c / dt */
    bool scene_dt;            /* the scene's own time step */
    double loss_error_mean;  /* relative error of the loss per collision, mean over phases (signed);
                                 relative to the collision's energy when the contact loses < 0.1 % */
    double loss_error_worst; /* the same, worst phase and case (signed) */
    double cluster_loss_error; /* mean loss error of the stiffest many-body mode (cost.c) */
    double error;              /* the observable's relative error (signed) */
    bool finite; /* stable: the collision, and the stiffest cluster mode, lose energy and end */
    bool meets;  /* |error| <= tolerance here and at every smaller candidate dt */
} gr_cost_candidate;

typedef struct gr_cost_request {
    gr_cost_observable observable;
    double tolerance;         /* relative, e.g. 0.01 */
    double calibrate_seconds; /* wall seconds of the calibration run; 0: no calibration */
    int phases;               /* contact phases per collision (default 16) */
} gr_cost_request;

/* One integrator timed by the calibration, at the recommended dt. */
#define GR_COST_MAX_OPTIONS 4
typedef struct gr_cost_option {
    char integrator[16]; /* "verlet" or "hybrid" */
    double window;       /* hybrid: kick_interval (s), a whole number of dt; verlet: 0 */
    bool ok;             /* timed; else note says why (the scene refuses this integrator) */
    char note[800];
    double wall_per_simulated;     /* median over blocks, wall s per simulated s */
    double wall_per_simulated_err; /* half the 16-84 % spread of the blocks */
    int blocks;
    double
        particle_steps_per_second; /* N / dt particle-steps per simulated second, per wall second */
} gr_cost_option;

typedef struct gr_cost_answer {
    int n;
    gr_cost_candidate c[GR_COST_MAX_CANDIDATES]; /* ordered by increasing dt */
    double t_c;                                  /* s, the scene's contact duration */
    int best;                 /* index of the recommended dt (the largest that meets), or -1 */
    int scene;                /* index of the scene's own dt */
    double simulated_seconds; /* warm-up + duration of the scene */
    /* calibration at c[best]: every integrator timed, and the recommended one (best_option) */
    int n_options, best_option; /* best_option -1 when not calibrated */
    gr_cost_option option[GR_COST_MAX_OPTIONS];
    /* the recommended option's numbers (NAN when not calibrated) */
    double wall_per_simulated;     /* median over blocks, wall s per simulated s */
    double wall_per_simulated_err; /* half the 16-84 % spread of the blocks */
    int blocks;
    double predicted_wall, predicted_wall_err; /* s, for simulated_seconds */
    double particle_steps_per_second;
} gr_cost_answer;

void gr_cost_request_default(gr_cost_request *r);

/* The scene's pair as gr_cost_errors collides it (its laws, mass, radius and dimension; the time
 * step forced, set per candidate). */
gr_collide_setup gr_cost_pair(const gr_scene *scene);

/* The candidate time steps and their errors (no run of the scene). Refuses scenes whose
 * contacts are instantaneous (event-driven hard spheres: nothing to step). */
int gr_cost_errors(const gr_scene *scene, const gr_cost_request *rq, gr_cost_answer *out,
                   gr_error *err);

/* Time the scene at time step dt on this machine in blocks, from the scene's start: Verlet and
 * the hybrid at windows of 10, 30 and 100 dt (a hybrid scene: its own window first), `seconds` of
 * wall time shared among them; fills the options, the recommended (cheapest) one and the
 * calibration fields of out (simulated_seconds must be set). */
int gr_cost_calibrate(const gr_scene *scene, double dt, double seconds, gr_cost_answer *out,
                      gr_error *err);

/* Both: the errors, the recommendation and, when rq->calibrate_seconds > 0 and a candidate
 * meets the tolerance, its calibrated wall time. */
int gr_cost_advise(const gr_scene *scene, const gr_cost_request *rq, gr_cost_answer *out,
                   gr_error *err);

/* DIR/cost.json: every candidate, the recommendation and its calibration (atomic write). */
int gr_cost_write(const gr_cost_answer *a, const gr_cost_request *rq, const char *scene_path,
                  const char *dir, gr_error *err);

#endif
