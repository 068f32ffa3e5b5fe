/* Placeholder until the hybrid integrator lands: refuse instead of silently running Verlet. */
#include "hybrid/hybrid.h"

int gr_hybrid_init(gr_sim *s, gr_error *err)
{
    return GR_FAIL(err, GR_EINVAL, "%s: [integrator] kind = hybrid is not available in this build", s->scene.source);
}

int gr_hybrid_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    (void)nsteps;
    return GR_FAIL(err, GR_EINVAL, "%s: [integrator] kind = hybrid is not available in this build", s->scene.source);
}

void gr_hybrid_free(gr_sim *s) { (void)s; }
