/* Placeholder until the event-driven core lands: refuse instead of silently running Verlet. */
#include "event/event.h"

int gr_event_init(gr_sim *s, gr_error *err)
{
    return GR_FAIL(err, GR_EINVAL, "%s: [integrator] kind = event is not available in this build", s->scene.source);
}

int gr_event_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    (void)nsteps;
    return GR_FAIL(err, GR_EINVAL, "%s: [integrator] kind = event is not available in this build", s->scene.source);
}

void gr_event_free(gr_sim *s) { (void)s; }
