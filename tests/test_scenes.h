/* Scene helpers shared by the event-driven tests (test_event.c, test_event_rough.c): a scene from
 * key=value overrides through the real parser, a simulation from it, and a refusal check. */
#ifndef GR_TEST_SCENES_H
#define GR_TEST_SCENES_H

#include <check.h>

#include "check_main.h" /* its ck_assert_msg: a passed assertion writes nothing */
#include <string.h>

#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"

/* The scene's [model] keys prepared as the hertz normal law for the reduced mass m12: the
 * reference eps_n(v) of viscoelastic hard grains (test_event_rough.c, test_event_vibrate.c). */
static inline gr_contact_coeffs hertz_of(const gr_scene *sc, double m12)
{
    gr_contact_params hp = sc->contact;
    gr_contact_coeffs hc;
    gr_error err = {0};
    ck_assert_msg(gr_contact_prepare(gr_model_find("hertz"), NULL, &hp, m12, 0.0, &hc, &err) ==
                      GR_OK,
                  "%s", err.message);
    return hc;
}

/* A resolved scene from overrides (every test scene goes through the real parser). */
static inline gr_scene scene_of(const char *const *ov, int n)
{
    gr_scene sc;
    gr_error err = {0};
    int rc = gr_scene_load(&sc, NULL, ov, n, &err);
    ck_assert_msg(rc == GR_OK, "scene: %s", err.message);
    return sc;
}

static inline gr_sim *sim_of(const gr_scene *sc)
{
    gr_sim *s;
    gr_error err = {0};
    int rc = gr_sim_create(sc, &s, &err);
    ck_assert_msg(rc == GR_OK, "create: %s", err.message);
    return s;
}

/* The scene (or the simulation made from it) is refused with a message containing `needle`. */
static inline void refused(const char *const *ov, int n, const char *needle)
{
    gr_scene sc;
    gr_error err = {0};
    int rc = gr_scene_load(&sc, NULL, ov, n, &err);
    if (rc == GR_OK) {
        gr_sim *s;
        rc = gr_sim_create(&sc, &s, &err);
        if (rc == GR_OK) {
            gr_sim_free(s);
        }
    }
    ck_assert_msg(rc != GR_OK, "accepted: %s", ov[n - 1]);
    ck_assert_msg(strstr(err.message, needle), "message '%s' lacks '%s'", err.message, needle);
}

#endif
