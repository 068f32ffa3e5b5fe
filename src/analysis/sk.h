/* The structure-factor engine behind the `sk` observable (src/analysis/obs_sk.c): S(k) on the
 * integer k-lattice by Gaussian gridding + FFTW, with the direct sum as the exact reference.
 * Used by the observable, tests/test_obs_sk.c and bench/bench_sk.c. */
#ifndef GR_SK_H
#define GR_SK_H

#include "granule/status.h"

/* ------------------------------------------------------------------------------------------
 * The S(k) engine. */
typedef struct gr_sk_plan gr_sk_plan;
enum { GR_SK_GRIDDING = 0, GR_SK_DIRECT = 1 };
#define GR_SK_MSP_DEFAULT 8 /* Gaussian half-width in grid points; chosen with bench/bench_sk.c */
#define GR_SK_MSP_MAX 16
#define GR_SK_NMAX_LIMIT 1024 /* largest |n_x|, |n_y|: a ~4100^2 grid, 270 MB */
/* All vectors with n_x^2 + n_y^2 <= n_cut^2 in the half plane, for a box of side L; gridding with
 * half-width msp (1..GR_SK_MSP_MAX). */
int gr_sk_plan_create(double L, double n_cut, int msp, gr_sk_plan **out, gr_error *err);
void gr_sk_plan_free(gr_sk_plan *pl);
/* Number of vectors; *nx, *ny (if not NULL) point at their integer components. */
int gr_sk_plan_vectors(const gr_sk_plan *pl, const int **nx, const int **ny);
/* Grid side M_r and Gaussian width tau of the gridding. */
void gr_sk_plan_grid(const gr_sk_plan *pl, int *grid, double *tau);
/* S of every vector for n particles at (x, y) (any real coordinates; periodic in L). */
int gr_sk_compute(gr_sk_plan *pl, int method, int n, const double *x, const double *y, double *S,
                  gr_error *err);

#endif
