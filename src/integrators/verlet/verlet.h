/* The soft-sphere integrator ([integrator] kind = verlet, docs/integrator.md): velocity Verlet in
 * kick-drift-kick form with the random force as a mid-step kick (step.c). It keeps no state of
 * its own beyond the core's, so its checkpoint is the core's. The hybrid integrator steps its
 * child simulation of active particles with the same scheme. */
#ifndef GR_VERLET_H
#define GR_VERLET_H

#include <stdint.h>
#include <stdio.h>

#include "core/sim_internal.h"

extern const gr_integrator_type gr_integrator_verlet;

/* Sums in the step loops are kept in LANES independent partial sums (particle i goes to lane
 * i % LANES) combined in a fixed order at the end: the compiler can then vectorise the loop while
 * the result stays the same on every machine and for every vector width. */
#define LANES 8

static inline double lanes_total(const double *acc)
{
    double t = 0.0;
    for (int l = 0; l < LANES; l++) {
        t += acc[l];
    }
    return t;
}

/* This step's normals of the random force or the bath (s->noise, a pure function of seed, step,
 * particle and component) drawn per block of GR_BLOCK particles on T threads, and the means the
 * symmetrised mode subtracts (2.18) from the block sums in block order (mean[2]: 3D only). */
void gr_verlet_draw_noise(gr_sim *s, double mean[3], int T);

/* Advance by nsteps time steps (gr_integrator_type.step). */
int gr_verlet_step(gr_sim *s, int64_t nsteps, gr_error *err);
/* The same for a simulation with species (step_poly.c; docs/mixtures.md): each grain kicked with
 * its own mass. gr_verlet_step calls it when s->nsp. */
int gr_verlet_step_poly(gr_sim *s, int64_t nsteps, gr_error *err);
/* Rotation ([model] rotation = true): the half kicks of the angular velocities, w += tau dt / 2I,
 * of all s->n grains from the torques of the last force evaluation: the previous step's closing
 * kick when `closing`, this step's opening kick when `opening` (step.c's rhythm; the hybrid's child
 * runs it too). Adds the work of the non-conservative torques, dt/2 included, to *wc and *wo;
 * false when a spin or a work is not finite. */
bool gr_verlet_spin_kicks(gr_sim *s, int closing, int opening, double *wc, double *wo);

/* GR_EUNSTABLE naming the first particle with a non-finite position or velocity; 0 if none. */
int gr_verlet_check_finite(gr_sim *s, gr_error *err);

/* Overlap beyond this fraction of d means the springs cannot hold the particles apart. */
#define GR_VERLET_RUNAWAY 0.5

/* Book energy dissipated (= minus the work of the non-conservative forces), split between the
 * mechanisms in proportion to their dissipation rates at the force evaluation. */
static inline void gr_verlet_book(gr_sim *s, double work)
{
    s->diss_n -= work * s->share[0];
    s->diss_t -= work * s->share[1];
    s->diss_f -= work * s->share[2];
}

static inline void gr_verlet_shares(gr_sim *s, const gr_force_report *r)
{
    double total = r->power_normal + r->power_tangential + r->power_friction;
    if (total > 0.0) {
        s->share[0] = r->power_normal / total;
        s->share[1] = r->power_tangential / total;
        s->share[2] = r->power_friction / total;
    } else {
        s->share[0] = 1.0;
        s->share[1] = s->share[2] = 0.0;
    }
}

/* The force evaluation of a step, after the drift and the list check: forces, the ledger's
 * shares, contact events, and the runaway-overlap guard. */
static inline int gr_verlet_forces(gr_sim *s, gr_error *err)
{
    gr_force_report r;
    gr_forces(s, &r);
    gr_verlet_shares(s, &r);
    s->diss_f += r.lost; /* a history law's slip and ended contacts: no work, booked directly */
    if (s->contacts) {
        int rc = gr_events_update(s, err);
        if (rc) {
            return rc;
        }
    }
    s->elastic = r.elastic;
    s->collisions += r.new_contacts;
    s->last = r;
    if (r.max_overlap > GR_VERLET_RUNAWAY) {
        /* worst_j = -1: a grain pressed into a wall, its overlap reported as xi / r (walls.c) */
        const int wall = s->walls_on && r.worst_i >= 0 && r.worst_j < 0;
        char who[80];
        if (wall) {
            snprintf(who, sizeof who, "particle %d and a wall", r.worst_i);
        } else {
            snprintf(who, sizeof who, "particles %d and %d", r.worst_i, r.worst_j);
        }
        return GR_FAIL(err, GR_EUNSTABLE,
                       "unstable run: %s overlap by %.3g d at step %lld (t = "
                       "%.6g s), beyond the %.2g d limit; "
                       "the springs (k_s = %g N/m) cannot hold them apart at this speed or "
                       "packing; use a stiffer k_s or a smaller dt",
                       who, wall ? 0.5 * r.max_overlap : r.max_overlap, (long long)s->step,
                       gr_sim_time(s), wall ? 0.5 * GR_VERLET_RUNAWAY : GR_VERLET_RUNAWAY,
                       s->cc.k_s);
    }
    return GR_OK;
}

#endif
