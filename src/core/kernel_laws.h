/* The normal laws as the force kernels call them: their compile-time ids from models/list.h
 * (NL_NAME) and normal_law, always inlined, so a kernel with the law as a constant compiles to
 * one inlined call and one with the law read at run time branches per pair, never an indirect
 * call. Shared by the 1D and 2D kernels (kernels.c) and the 3D one (kernels_3d.c). */
#ifndef GR_KERNEL_LAWS_H
#define GR_KERNEL_LAWS_H

#include "core/sim_internal.h"
#include "models/list.h"

#define GR_NL_ID(A, NAME) NL_##NAME,
enum { GR_NORMAL_MODELS(GR_NL_ID, ) NL_COUNT };
#undef GR_NL_ID

/* The law `nl` (a constant after inlining, so the switch folds to one inlined call). */
static inline __attribute__((always_inline)) gr_normal_force normal_law(
    const int nl, const gr_contact_coeffs *c, const double xi, const double g_n, const int clamp)
{
    switch (nl) {
#define GR_NL_CASE(A, NAME)                                                                        \
    case NL_##NAME: return gr_normal_##NAME(c, xi, g_n, clamp);
        GR_NORMAL_MODELS(GR_NL_CASE, )
#undef GR_NL_CASE
    }
    __builtin_unreachable();
}

/* The minimum image of a coordinate difference in a periodic box of side L. */
static inline double wrap_delta(double dx, double L)
{
    if (dx > 0.5 * L) {
        dx -= L;
    } else if (dx < -0.5 * L) {
        dx += L;
    }
    return dx;
}

#endif
