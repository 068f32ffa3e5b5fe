/* The normal laws as the force kernels call them: their compile-time ids from models/list.h
 * (NL_NAME) and normal_law, always inlined, so a kernel with the law as a constant compiles to
 * one inlined call and one with the law read at run time branches per pair, never an indirect
 * call. Shared by the 1D and 2D kernels (kernels.c) and the 3D one (kernels_3d.c), with the
 * tangential and rolling laws' ids (TL_NAME, RL_NAME) and their always-inline dispatch. */
#ifndef GR_KERNEL_LAWS_H
#define GR_KERNEL_LAWS_H

#include "core/sim_internal.h"
#include "models/list.h"

/* What every pair of the 2D and 3D kernels needs besides positions and velocities, loaded once
 * per loop: the contact distance d and d^2, m_t / dt (tangential laws), I / (2 dt) (rotation: a
 * rolling law) and a local copy of the laws' coefficients. Each kernel's context (pair_ctx in
 * kernels.c, ctx3 in kernels_3d.c) declares these fields with GR_PAIR_CONSTS and sets them with
 * GR_PAIR_CONSTS_OF(s) among its initialisers, beside its own (the box, the arrays). Flat fields,
 * not a nested struct: the pair loops compile to the code they had before the two contexts
 * shared them (a nested copy changed their register allocation). */
#define GR_PAIR_CONSTS                                                                             \
    double d, d2, m12_dt, i_2dt;                                                                   \
    gr_contact_coeffs cc
#define GR_PAIR_CONSTS_OF(s)                                                                       \
    .d = (s)->d, .d2 = (s)->d * (s)->d, .m12_dt = (s)->cc.m_t / (s)->dt,                           \
    .i_2dt = 0.5 * (s)->inertia / (s)->dt, .cc = (s)->cc

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

/* Compile-time ids of the tangential laws, from the list (TL_none = no tangential law). */
#define GR_TL_ID(A, NAME) TL_##NAME,
enum { TL_none = 0, GR_TANGENTIAL_MODELS(GR_TL_ID, ) TL_COUNT };
/* rolling laws (RL_none = none): instantiated with rotation only */
#define GR_RL_ID(A, NAME) RL_##NAME,
enum { RL_none = 0, GR_ROLLING_MODELS(GR_RL_ID, ) RL_COUNT };
#undef GR_TL_ID
#undef GR_RL_ID

static inline __attribute__((always_inline)) gr_tangential_force tangential_law(
    const int tl, const gr_contact_coeffs *c, const gr_tangential_in in)
{
    switch (tl) {
#define GR_TL_CASE(A, NAME)                                                                        \
    case TL_##NAME: return gr_tangential_##NAME(c, in);
        GR_TANGENTIAL_MODELS(GR_TL_CASE, )
#undef GR_TL_CASE
    }
    return (gr_tangential_force){.f = 0.0, .p = 0.0};
}

/* 1 when tangential law tl keeps a per-contact history (GR_HISTORY_MODELS of models/list.h). */
static inline __attribute__((always_inline)) int history_of(const int tl)
{
    switch (tl) {
#define GR_TL_HIST(A, NAME)                                                                        \
    case TL_##NAME: return 1;
        GR_HISTORY_MODELS(GR_TL_HIST, )
#undef GR_TL_HIST
    }
    return 0;
}

static inline __attribute__((always_inline)) gr_rolling_torque rolling_law(
    const int rl, const gr_contact_coeffs *c, const gr_rolling_in in)
{
    switch (rl) {
#define GR_RL_CASE(A, NAME)                                                                        \
    case RL_##NAME: return gr_rolling_##NAME(c, in);
        GR_ROLLING_MODELS(GR_RL_CASE, )
#undef GR_RL_CASE
    }
    return (gr_rolling_torque){.m = 0.0, .p = 0.0};
}

/* The ledger column of tangential law tl: GR_BOOK_TANGENTIAL or GR_BOOK_FRICTION (0: none). */
static inline __attribute__((always_inline)) int book_of(const int tl)
{
    switch (tl) {
#define GR_TL_BOOK(A, NAME)                                                                        \
    case TL_##NAME: return GR_BOOK_##NAME;
        GR_TANGENTIAL_MODELS(GR_TL_BOOK, )
#undef GR_TL_BOOK
    }
    return 0;
}

/* 3D: the vector step of history law tl (GR_HISTORY_MODELS; models/law.h, gr_tangential_in3). */
static inline __attribute__((always_inline)) gr_tangential_force3 tangential3_law(
    const int tl, const gr_contact_coeffs *c, const gr_tangential_in3 in)
{
    switch (tl) {
#define GR_TL3_CASE(A, NAME)                                                                       \
    case TL_##NAME: return gr_tangential3_##NAME(c, in);
        GR_HISTORY_MODELS(GR_TL3_CASE, )
#undef GR_TL3_CASE
    }
    return (gr_tangential_force3){.p = 0.0};
}

/* 3D: a history vector turned into the tangent plane of n, its length kept (LAMMPS pair granular:
 * s <- (s - (s.n) n) |s| / |s - (s.n) n|; 0 when s lies along n). */
static inline void gr_to_plane(double h[3], const double n[3])
{
    const double hn = h[0] * n[0] + h[1] * n[1] + h[2] * n[2];
    if (hn == 0.0) {
        return;
    }
    const double len2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    for (int a = 0; a < 3; a++) {
        h[a] -= hn * n[a];
    }
    const double p2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    const double scale = p2 > 0.0 ? sqrt(len2 / p2) : 0.0;
    for (int a = 0; a < 3; a++) {
        h[a] *= scale;
    }
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
