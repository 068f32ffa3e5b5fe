/* The driving registry ([driving] kind, granule/driving.h): one line per type, each defined in its
 * own file (driving_rfm.c, driving_none.c, driving_langevin.c). Adding a driving: one file with its
 * gr_driving_type and parameter table, one line here, and the update in each integrator that can
 * represent it (or its refusal there: gr_integrator_type.drag). */
#include <stdio.h>
#include <string.h>

#include "granule/driving.h"

extern const gr_driving_type gr_driving_rfm;      /* driving_rfm.c */
extern const gr_driving_type gr_driving_none;     /* driving_none.c */
extern const gr_driving_type gr_driving_langevin; /* driving_langevin.c */

const gr_driving_type *const gr_drivings[] = {
    &gr_driving_rfm,
    &gr_driving_none,
    &gr_driving_langevin,
    NULL,
};

const gr_driving_type *gr_driving_find(const char *name)
{
    for (int i = 0; name && gr_drivings[i]; i++) {
        if (strcmp(gr_drivings[i]->name, name) == 0) {
            return gr_drivings[i];
        }
    }
    return NULL;
}

const gr_driving_type *gr_driving_default(void) { return &gr_driving_rfm; }

void gr_driving_names(char *buf, size_t cap, const char *sep)
{
    size_t len = 0;
    if (cap) {
        buf[0] = 0;
    }
    for (int i = 0; gr_drivings[i] && len < cap; i++) {
        int w = snprintf(buf + len, cap - len, "%s%s", i ? sep : "", gr_drivings[i]->name);
        len += w > 0 ? (size_t)w : 0;
    }
}

void gr_driving_defaults(gr_driving_params *p)
{
    memset(p, 0, sizeof *p);
    for (int m = 0; gr_drivings[m]; m++) {
        for (int i = 0; i < gr_drivings[m]->n_params; i++) {
            const gr_param *d = &gr_drivings[m]->params[i];
            *(double *)((char *)p + d->offset) = d->def;
        }
    }
}
