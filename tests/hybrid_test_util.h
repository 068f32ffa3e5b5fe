/* Helpers of the hybrid integrator's tests (test_hybrid.c, test_hybrid_species.c): a scene of
 * docs/scenes with --set style overrides, its simulation created and stepped (failing the test
 * with the library's message), and the largest differences of positions and spins between runs. */
#ifndef GR_TEST_HYBRID_UTIL_H
#define GR_TEST_HYBRID_UTIL_H

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/sim_internal.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"

/* docs/scenes/NAME with --set style overrides (NULL-terminated). */
static inline gr_scene load(const char *name, const char *const *over)
{
    const char *src = getenv("GRANULE_SOURCE_DIR");
    char path[2048];
    snprintf(path, sizeof path, "%s/docs/scenes/%s", src ? src : ".", name);
    int n = 0;
    while (over[n]) {
        n++;
    }
    gr_scene sc;
    gr_error err = {0};
    int rc = gr_scene_load(&sc, path, over, n, &err);
    ck_assert_msg(rc == GR_OK, "scene %s: %s", path, err.message);
    return sc;
}

static inline gr_sim *create(const gr_scene *sc)
{
    gr_sim *s = NULL;
    gr_error err = {0};
    int rc = gr_sim_create(sc, &s, &err);
    ck_assert_msg(rc == GR_OK, "gr_sim_create: %s", err.message);
    return s;
}

static inline void step(gr_sim *s, int64_t n)
{
    gr_error err = {0};
    int rc = gr_sim_step(s, n, &err);
    ck_assert_msg(rc == GR_OK, "gr_sim_step: %s", err.message);
}

/* The largest |x_a - x_b| over grains and components (minimum image along periodic axes). */
static inline double max_diff(const gr_sim *a, const gr_sim *b)
{
    const double *pa[3] = {a->x, a->y, a->z}, *pb[3] = {b->x, b->y, b->z};
    double w = 0.0;
    for (int c = 0; c < a->dim; c++) {
        for (int i = 0; i < a->n; i++) {
            double d = fabs(pa[c][i] - pb[c][i]);
            if (a->dim >= 2 && isfinite(a->period[c])) {
                d = fmin(d, a->L - d);
            }
            w = fmax(w, d);
        }
    }
    return w;
}

/* The largest spin differences of runs a, b from a reference run (each component of the
 * angular velocity: omega in 2D, wx, wy, omega in 3D) and the largest spin of the reference. */
static inline void gr_test_spin_diff(const gr_sim *ref, const gr_sim *a, const gr_sim *b,
                                     double *da, double *db, double *wmax)
{
    const double *wr[3] = {ref->omega, ref->wx, ref->wy}, *wa[3] = {a->omega, a->wx, a->wy},
                 *wb[3] = {b->omega, b->wx, b->wy};
    *da = *db = *wmax = 0.0;
    for (int c = 0; c < (ref->dim == 3 ? 3 : 1); c++) {
        for (int i = 0; i < ref->n; i++) {
            *da = fmax(*da, fabs(wa[c][i] - wr[c][i]));
            *db = fmax(*db, fabs(wb[c][i] - wr[c][i]));
            *wmax = fmax(*wmax, fabs(wr[c][i]));
        }
    }
}

#endif
