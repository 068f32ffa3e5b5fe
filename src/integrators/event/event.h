/* The event-driven integrator ([integrator] kind = event, [model] normal = hard_sphere):
 * instantaneous collisions (2.1, 2.2, 2.10) between free flights driven by the random force.
 * A registered integrator (gr_integrator_event, event_type.c); its state lives behind
 * gr_sim.integrator_state. docs/event-driven.md describes the algorithm. */
#ifndef GR_EVENT_H
#define GR_EVENT_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/blob.h"
#include "core/sim_internal.h"

extern const gr_integrator_type gr_integrator_event;

/* The event state of s, or NULL when s is not event-driven. */
static inline struct gr_event_state *gr_ev(const gr_sim *s)
{
    return s->integrator == &gr_integrator_event ? (struct gr_event_state *)s->integrator_state
                                                 : NULL;
}

/* Build the event state after positions, velocities and coefficients are set. */
int gr_event_init(gr_sim *s, gr_error *err);
/* Advance by nsteps * s->dt of simulated time; on return s->x, vx (y, vy) hold the state at that
 * time and s->step has advanced by nsteps. Exception: when the flag given to gr_event_set_stop
 * becomes non-zero, the call returns GR_OK early with s->step and s->x unchanged (the events
 * done so far are kept; calling again continues bit-identically). An unstable run (diverging
 * event rate, runaway speeds, a contact floor that outgrows the random force) returns
 * GR_EUNSTABLE with a diagnosis. */
int gr_event_step(gr_sim *s, int64_t nsteps, gr_error *err);
void gr_event_free(gr_sim *s);
/* Poll *stop (e.g. set by a SIGTERM handler) every few thousand events; NULL for none. */
void gr_event_set_stop(gr_sim *s, volatile sig_atomic_t *stop);
/* After a call that returned early on a stop request: the steps it still owes (its target minus
 * s->step), else 0. Events up to an instant inside those steps are already done, so the next
 * call must go at least that far (a shorter one could not report its end state). */
int64_t gr_event_owed_steps(const gr_sim *s);
/* Events processed (collisions, cell crossings, noise updates) since creation. */
int64_t gr_event_processed(const gr_sim *s);

/* Exact restarts (event_state.c, docs/checkpoints.md): append / read back everything the next
 * gr_event_step depends on (the save / load hooks: src/core/sim_state.c calls them after the
 * soft-sphere part). Load
 * into a simulation freshly created from the same scene; the calendar is rebuilt from the
 * stored keys. */
int gr_event_state_io(gr_sim *s, gr_blob_io *io, gr_error *err);

/* Counts since creation (all zero for other integrators). kicks = particle updates at window
 * ends; invalid = calendar entries found stale when they came due; tc_elastic = collisions made
 * elastic by the TC rule; floors = separations raised by the contact floor. */
typedef struct gr_event_counts {
    int64_t collisions, crossings, kicks, invalid, tc_elastic, floors;
    double floor_energy; /* J added by the contact floor (part of the injected energy) */
    bool walls;          /* the run has walls: wall_hits counts the grains' hits on them */
    int64_t wall_hits;
} gr_event_counts;
void gr_event_stats(const gr_sim *s, gr_event_counts *c);
/* The event calendar in use: "bucket", "sparse" or "full" (src/integrators/event/calendar.c). */
const char *gr_event_calendar(const gr_sim *s);

/* Test hooks: check every pair for overlap after every collision (also GRANULE_EVENT_CHECK=1),
 * and free flight without collisions. Predictions are redone at the current time. */
void gr_event_set_debug(gr_sim *s, bool check_overlaps, bool no_collisions);

#endif
