/* The integrator registry: one line per integrator (each defined in its own folder). Adding an
 * integrator: docs/architecture.md, "How to add an integrator". */
#include <stdio.h>
#include <string.h>

#include "granule/integrator.h"

extern const gr_integrator_type gr_integrator_verlet; /* verlet/verlet.c */
extern const gr_integrator_type gr_integrator_event;  /* event/event_type.c */
extern const gr_integrator_type gr_integrator_hybrid; /* hybrid/hybrid_type.c */

const gr_integrator_type *const gr_integrators[] = {
    &gr_integrator_verlet,
    &gr_integrator_event,
    &gr_integrator_hybrid,
    NULL,
};

const gr_integrator_type *gr_integrator_find(const char *name)
{
    for (int i = 0; name && gr_integrators[i]; i++) {
        if (strcmp(gr_integrators[i]->name, name) == 0) {
            return gr_integrators[i];
        }
    }
    return NULL;
}

void gr_integrator_names(char *buf, size_t cap, const char *sep)
{
    size_t len = 0;
    if (cap) {
        buf[0] = 0;
    }
    for (int i = 0; gr_integrators[i] && len < cap; i++) {
        int w = snprintf(buf + len, cap - len, "%s%s", i ? sep : "", gr_integrators[i]->name);
        len += w > 0 ? (size_t)w : 0;
    }
}
