/* Driving: what feeds energy into the gas between collisions ([driving] kind, docs/systems-driving.md).
 * Each type is a registered gr_driving_type in its own file (src/core/driving_NAME.c, the list in
 * src/core/driving.c), with its parameter descriptors, the way collision models are:
 *
 *   rfm       the thesis's random force (2.15-2.18), [noise] D and mode (today's default)
 *   none      no driving: the gas cools freely (Haff's law)
 *   langevin  a thermostat: white noise plus a viscous drag -M v / tau, with the noise set by the
 *             fluctuation-dissipation relation so the steady temperature is the bath's T_bath
 *
 * The driving is chosen once per run: an integrator steps one specialised loop for it, so a
 * driving that is off costs nothing. A driving whose update an integrator cannot represent (a
 * drag that exact free flight does not model) is refused by name when the simulation is built. */
#ifndef GRANULE_DRIVING_H
#define GRANULE_DRIVING_H

#include <stdbool.h>
#include <stddef.h>

#include "granule/model.h"
#include "granule/status.h"

/* How a driving changes the velocities each step (what an integrator must be able to do). */
typedef enum {
    GR_DRIVE_OFF,   /* nothing: free flight between collisions */
    GR_DRIVE_FORCE, /* the random force of [noise] (white noise, no drag): the thesis's RFM */
    GR_DRIVE_BATH, /* Ornstein-Uhlenbeck: v <- v e^{-dt/tau} + sqrt(T_bath/dim (1 - e^{-2dt/tau})) xi */
} gr_drive_update;

/* A driving's inputs, as given in a scene's [driving] section. */
typedef struct gr_driving_params {
    double
        T_bath; /* langevin: bath temperature, m^2/s^2, in the units of T (2.19): sum over components */
    double tau; /* langevin: drag time constant M / gamma, s */
} gr_driving_params;

/* What the integrator applies per step (from prepare, once per run). */
typedef struct gr_driving_coeffs {
    double decay; /* bath: e^{-dt/tau}, the drag's factor on each velocity component per step */
    double
        kick; /* bath: sqrt(T_bath / dim (1 - e^{-2 dt/tau})), m/s, the noise's standard deviation */
} gr_driving_coeffs;

typedef struct gr_driving_type {
    const char *name;    /* [driving] kind */
    const char *summary; /* one line for the scene-key documentation */
    gr_drive_update update;
    /* Has a viscous drag: needs an integrator that models it (gr_integrator_type.drag). */
    bool drag;
    const gr_param *params; /* offsets into gr_driving_params */
    int n_params;
    /* The per-step coefficients for time step dt in dim dimensions (NULL: none needed). */
    int (*prepare)(const gr_driving_params *p, int dim, double dt, gr_driving_coeffs *c,
                   gr_error *err);
} gr_driving_type;

/* The registry: every driving type, NULL-terminated, in documentation order (rfm first). */
extern const gr_driving_type *const gr_drivings[];
/* The driving called name, or NULL. */
const gr_driving_type *gr_driving_find(const char *name);
/* The default, today's random force (rfm); a NULL gr_sim_params.driving means it too. */
const gr_driving_type *gr_driving_default(void);
/* The registered names joined by sep ("rfm|none|langevin"), for messages and docs. */
void gr_driving_names(char *buf, size_t cap, const char *sep);
/* Every driving type's parameter defaults. */
void gr_driving_defaults(gr_driving_params *p);

/* The bath's exact Ornstein-Uhlenbeck step with coefficients c (prepare's, for the interval it
 * covers) on the velocities v[0..dim)[0..n): v <- c.decay v + k_i g, k_i = c.kick sqrt(m1 / m_i)
 * (mass_i NULL: every grain of mass M, k_i = c.kick), g the n x dim standard normals (grain i's
 * component a at g[i dim + a]). Adds the noise's work to *added and the drag's loss to *dragged
 * (J). The event and hybrid integrators' window-end step (driving_langevin.c). */
void gr_bath_ou_step(const gr_driving_coeffs *c, double m1, int n, int dim, double *const v[3],
                     const double *mass_i, double M, const double *g, double *added,
                     double *dragged);

#endif
