/* The largest spin differences of two runs a, b from a reference run (each component of the
 * angular velocity: omega in 2D, wx, wy, omega in 3D) and the largest spin of the reference:
 * the hybrid tests' comparison with the verlet integrator (test_hybrid.c, test_hybrid_species.c). */
#ifndef GR_TEST_SPIN_DIFF_H
#define GR_TEST_SPIN_DIFF_H

#include <math.h>

#include "core/sim_internal.h"

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
