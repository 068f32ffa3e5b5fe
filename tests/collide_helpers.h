/* The collision tests' helpers: contact parameters from a short "key=value key=value" list, and
 * the oblique impact they share (0.5 m/s at 30 degrees) run by the engine or the CVODE
 * reference. */
#ifndef GR_TEST_COLLIDE_HELPERS_H
#define GR_TEST_COLLIDE_HELPERS_H

#include <check.h>
#include <stdio.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/model.h"

static inline void contact_settings(gr_contact_params *p, const char *settings)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", settings);
    for (char *save = NULL, *tok = strtok_r(buf, " ", &save); tok;
         tok = strtok_r(NULL, " ", &save)) {
        char *eq = strchr(tok, '=');
        ck_assert(eq);
        *eq = '\0';
        gr_error err = {0};
        ck_assert_msg(gr_contact_set(p, tok, eq + 1, &err) == GR_OK, "%s", err.message);
    }
}

/* the impact: 0.5 m/s at 30 degrees in the plane z = 0, particle 2 at rest */
static inline gr_collision_case collide_impact(const gr_collide_setup *s)
{
    gr_collision_case cs;
    gr_error err = {0};
    ck_assert(gr_collision_case_oblique(0.5, 30.0, s->radius, &cs, &err) == GR_OK);
    return cs;
}

/* that impact run by the engine or by the CVODE reference, which must succeed */
static inline gr_collide_result collide_impact_run(const gr_collide_setup *s, bool reference)
{
    gr_collision_case cs = collide_impact(s);
    gr_error err = {0};
    gr_collide_result r;
    const int rc =
        reference ? gr_collide_reference(s, &cs, &r, &err) : gr_collide_run(s, &cs, &r, &err);
    ck_assert_msg(rc == GR_OK, "%s", err.message);
    return r;
}

#endif
