/* Contact events: after each force evaluation, count every particle's contacts (pairs that
 * overlap) and record the particles whose count went from 0 to positive (a collision starts) or
 * from positive to 0 (the particle is free again). The free-path distribution (4.18) and the
 * post-collision velocity distribution (Fig. 5.9) are built from these, for soft-sphere runs as
 * they will be for event-driven ones. Only done when an observable asks for it. */
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"

int gr_sim_track_contacts(gr_sim *s, gr_error *err)
{
    if (s->contacts) {
        return GR_OK;
    }
    s->contacts = calloc((size_t)s->n, sizeof(uint16_t));
    s->contacts_now = calloc((size_t)s->n, sizeof(uint16_t));
    s->cap_events = 1024;
    s->events = malloc(sizeof(gr_contact_event) * (size_t)s->cap_events);
    if (!s->contacts || !s->contacts_now || !s->events) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for contact events");
    }
    /* the state at creation: particles already touching are not new collisions */
    if (s->dim == 1) {
        for (int i = 0; i < s->n && s->n > 1; i++) {
            if (s->pair_contact[i]) {
                s->contacts[i]++;
                s->contacts[(i + 1) % s->n]++;
            }
        }
    } else {
        for (int i = 0; i < s->n; i++) {
            for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
                if (s->nl_contact[p]) {
                    s->contacts[i]++;
                    s->contacts[s->nl_j[p]]++;
                }
            }
        }
    }
    return GR_OK;
}

const gr_contact_event *gr_sim_events(const gr_sim *s, int64_t *n)
{
    *n = s->n_events;
    return s->events;
}

void gr_sim_clear_events(gr_sim *s) { s->n_events = 0; }

int gr_events_append(gr_sim *s, gr_contact_event ev, gr_error *err)
{
    if (s->n_events == s->cap_events) {
        int64_t cap = 2 * s->cap_events + 1024;
        gr_contact_event *e = realloc(s->events, sizeof *e * (size_t)cap);
        if (!e) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %lld contact events", (long long)cap);
        }
        s->events = e;
        s->cap_events = cap;
    }
    s->events[s->n_events++] = ev;
    return GR_OK;
}

/* Particle i's contact begins (+1) or ends (-1) at this step: its state now. */
static int push(gr_sim *s, int i, int kind, gr_error *err)
{
    return gr_events_append(s,
                            (gr_contact_event){.i = i,
                                               .kind = kind,
                                               .t = (double)s->step * s->dt,
                                               .x = s->x[i],
                                               .y = s->dim >= 2 ? s->y[i] : 0.0,
                                               .vx = s->vx[i],
                                               .vy = s->dim >= 2 ? s->vy[i] : 0.0,
                                               .z = s->dim == 3 ? s->z[i] : 0.0,
                                               .vz = s->dim == 3 ? s->vz[i] : 0.0},
                            err);
}

int gr_events_update(gr_sim *s, gr_error *err)
{
    uint16_t *now = s->contacts_now;
    memset(now, 0, sizeof(uint16_t) * (size_t)s->n);
    if (s->dim == 1) {
        for (int i = 0; i < s->n && s->n > 1; i++) {
            if (s->pair_contact[i]) {
                now[i]++;
                now[(i + 1) % s->n]++;
            }
        }
    } else {
        for (int i = 0; i < s->n; i++) {
            for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
                if (s->nl_contact[p]) {
                    now[i]++;
                    now[s->nl_j[p]]++;
                }
            }
        }
    }
    for (int i = 0; i < s->n; i++) {
        int before = s->contacts[i] > 0, after = now[i] > 0;
        if (before != after) {
            int rc = push(s, i, after ? +1 : -1, err);
            if (rc) {
                return rc;
            }
        }
    }
    s->contacts_now = s->contacts;
    s->contacts = now;
    return GR_OK;
}
