/* The structure-factor engine behind the `sk` observable (src/analysis/obs_sk.c): S(k) on the
 * integer k-lattice by Gaussian gridding + FFTW, with the direct sum as the exact reference.
 * Used by the observable, tests/test_obs_sk.c and bench/bench_sk.c. */
#ifndef GR_SK_H
#define GR_SK_H

#include "granule/status.h"

/* ------------------------------------------------------------------------------------------
 * The S(k) engine. */
typedef struct gr_sk_plan gr_sk_plan;
typedef struct gr_sk3_plan gr_sk3_plan;
enum { GR_SK_GRIDDING = 0, GR_SK_DIRECT = 1 };
#define GR_SK_MSP_DEFAULT 8 /* Gaussian half-width in grid points; chosen with bench/bench_sk.c */
#define GR_SK_MSP_MAX 16
#define GR_SK_NMAX_LIMIT 1024 /* largest |n_x|, |n_y|: a ~4100^2 grid, 270 MB */
/* All vectors with n_x^2 + n_y^2 <= n_cut^2 in the half plane, for a box of side L; gridding with
 * half-width msp (1..GR_SK_MSP_MAX). */
int gr_sk_plan_create(double L, double n_cut, int msp, gr_sk_plan **out, gr_error *err);
void gr_sk_plan_free(gr_sk_plan *pl);
/* What a plan, 2D or 3D, hands out: its nv vectors' integer components (nz: NULL in 2D) and its
 * gridding (grid side M_r, Gaussian width tau). Read it with the getters below. */
typedef struct gr_sk_lattice {
    int nv;
    int *nx, *ny, *nz;
    int Mr;
    double tau;
} gr_sk_lattice;
const gr_sk_lattice *gr_sk_plan_lattice(const gr_sk_plan *pl);
const gr_sk_lattice *gr_sk3_plan_lattice(const gr_sk3_plan *pl);
/* Number of vectors; *nx, *ny, *nz (each if not NULL) point at their integer components (*nz at
 * NULL in 2D). */
int gr_sk_vectors(const gr_sk_lattice *lat, const int **nx, const int **ny, const int **nz);
/* Grid side M_r and Gaussian width tau of the gridding (each if not NULL). */
void gr_sk_grid(const gr_sk_lattice *lat, int *grid, double *tau);
/* S of every vector for n particles at (x, y) (any real coordinates; periodic in L). */
int gr_sk_compute(gr_sk_plan *pl, int method, int n, const double *x, const double *y, double *S,
                  gr_error *err);
/* rho(k) = sum_j exp(-i k.r_j) of every vector, not normalised, into (re[v], im[v]), for n >= 0
 * particles: a mixture's species one at a time (S_ab(k) = Re rho_a(k) conj rho_b(k) / sqrt(N_a
 * N_b), obs_sk.c). |rho|^2 / n is gr_sk_compute's S to rounding, not bit for bit. */
int gr_sk_compute_rho(gr_sk_plan *pl, int method, int n, const double *x, const double *y,
                      double *re, double *im, gr_error *err);

/* Shared by the 2D and 3D engines: the smallest even FFT size >= target with prime factors 2, 3,
 * 5, 7; and the Gaussian gridding weights of one coordinate (2 msp of them into w, for a grid of
 * Mr points of spacing h = 2 pi / Mr on a period L, width tau, e3[l] = exp(-(l h)^2 / (4 tau)));
 * returns the (unwrapped) grid index of the first weight. */
int gr_sk_fft_size(int target);
/* The gridding of M = 2 n_max + 1 modes per axis with half-width msp (Greengard & Lee: oversampling
 * R = M_r / M >= 2, tau = pi msp / (M^2 R (R - 1/2))): sets lat->Mr and lat->tau, the grid
 * spacing *h = 2 pi / M_r and e3[l] = exp(-(l h)^2 / (4 tau)), l = 0..msp; returns the r2c
 * spectrum's last dimension M_r / 2 + 1. */
int gr_sk_gridding(int n_max, int msp, gr_sk_lattice *lat, double *h, double *e3);
int gr_sk_gauss_weights(double L, int Mr, double h, double tau, int msp, const double *e3,
                        double coord, double *w);

/* ------------------------------------------------------------------------------------------
 * The 3D engine (src/analysis/sk_3d.c): S(k) on the integer lattice k = 2 pi (n_x, n_y, n_z) / L
 * of a periodic cube, every vector with |n| <= n_cut in the half space (n_z > 0, or n_z = 0 and
 * n_y > 0, or n_z = n_y = 0 and n_x > 0; S(-k) = S(k)), by the same Gaussian gridding on an
 * M_r^3 grid and one real-to-complex FFTW transform, or by the direct sum (the tests' oracle). */
#define GR_SK3_MSP_DEFAULT 6 /* (2 msp)^3 grid points per sphere */
#define GR_SK3_NMAX_LIMIT 64 /* largest |n|: a ~260^3 grid, 140 MB */
int gr_sk3_plan_create(double L, double n_cut, int msp, gr_sk3_plan **out, gr_error *err);
void gr_sk3_plan_free(gr_sk3_plan *pl);
int gr_sk3_compute(gr_sk3_plan *pl, int method, int n, const double *x, const double *y,
                   const double *z, double *S, gr_error *err);
/* rho(k) of every vector in 3D (as gr_sk_compute_rho). */
int gr_sk3_compute_rho(gr_sk3_plan *pl, int method, int n, const double *x, const double *y,
                       const double *z, double *re, double *im, gr_error *err);

#endif
