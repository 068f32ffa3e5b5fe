/* The event-driven integrator's registration: its hooks for the core and the run driver. */
#include "integrators/event/event.h"

/* A call interrupted by a stop owes the steps up to its target: events up to an instant inside
 * them are done, so the next call must reach at least that far (if the caller may go there). */
static int64_t event_call_steps(const gr_sim *s, int64_t n, int64_t todo)
{
    const int64_t owed = gr_event_owed_steps(s);
    return owed > n && owed <= todo ? owed : n;
}

/* summary.json "event": the collision count split by what the model did (issue 37). In exact free
 * flight a pair pressed together by the window's constant accelerations bounces on the contact
 * floor (docs/event-driven.md): those collisions are the ED stand-in for one sustained contact,
 * not impacts of the continuous RFM, so the rate a user compares is collisions - collisions_floor. */
static int event_describe(const gr_sim *s, gr_integrator_figure *out, int cap)
{
    gr_event_counts c;
    gr_event_stats(s, &c);
    if (cap < 4) {
        return 0;
    }
    out[0] = (gr_integrator_figure){"collisions_floor", (double)c.floors};
    out[1] = (gr_integrator_figure){"collisions_impact", (double)(c.collisions - c.floors)};
    out[2] = (gr_integrator_figure){"collisions_tc_elastic", (double)c.tc_elastic};
    out[3] = (gr_integrator_figure){"floor_energy", c.floor_energy};
    if (c.walls && cap >= 5) {
        out[4] = (gr_integrator_figure){"wall_hits", (double)c.wall_hits};
        return 5;
    }
    return 4;
}

const gr_integrator_type gr_integrator_event = {
    .name = "event",
    .summary = "event-driven hard spheres (needs an event rule as [model] normal, e.g. "
               "hard_sphere; docs/event-driven.md)",
    .instantaneous = true,
    .free_flight = true,
    .rotation = true, /* rough discs and spheres: spins change only at collisions */
    .walls = true,    /* fixed and vibrating walls, gravity (event_cells.h wall_hit, event.c 1D) */
    .spheres = true,  /* smooth and rough hard spheres in a periodic cube (event_3d.c) */
    .species = true,  /* [species] lists of smooth and rough discs and of rods (gr_ev_rule) */
    .drag = true,     /* the Langevin bath at each window's end (event.c, bath_window) */
    .create = gr_event_init,
    .step = gr_event_step,
    .free = gr_event_free,
    .call_steps = event_call_steps,
    .state_io = gr_event_state_io,
    .set_stop = gr_event_set_stop,
    .events = gr_event_processed,
    .describe = event_describe,
    .section = "event",
};
