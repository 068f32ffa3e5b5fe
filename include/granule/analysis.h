/* Streaming statistics shared by every run: memory does not grow with run length. */
#ifndef GRANULE_ANALYSIS_H
#define GRANULE_ANALYSIS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "granule/status.h"

#define GR_BLOCKING_LEVELS 48

/* Block averaging (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989)) of a correlated time
 * series, accumulated on the fly: level k sees the means of blocks of 2^k consecutive samples.
 * The standard error of the mean is read off where it stops growing with the block size. */
typedef struct gr_blocking {
    int64_t count[GR_BLOCKING_LEVELS]; /* completed blocks per level */
    double sum[GR_BLOCKING_LEVELS], sum2[GR_BLOCKING_LEVELS];
    double pending[GR_BLOCKING_LEVELS]; /* first half of a block waiting for its partner */
    int has_pending[GR_BLOCKING_LEVELS];
} gr_blocking;

void gr_blocking_init(gr_blocking *b);
void gr_blocking_add(gr_blocking *b, double x);
double gr_blocking_mean(const gr_blocking *b);
/* Standard error of the mean at level k (blocks of 2^k samples); NAN with fewer than 2 blocks. */
double gr_blocking_stderr_at(const gr_blocking *b, int level);
/* Conservative estimate: the largest level-k error among levels with at least 16 blocks (the
 * plateau for a series much longer than its correlation time; an underestimate otherwise, which
 * `*converged` reports as 0 when the error still grows at the last usable levels). */
double gr_blocking_stderr(const gr_blocking *b, int *level, int *converged);

/* ------------------------------------------------------------------------------------------
 * Histograms with linear or logarithmic bins, as probability densities with sqrt(X) errors
 * (App. A.1): p_i = X_i / (total w_i), sigma_i = sqrt(X_i) / (total w_i), X_i the count in bin i
 * of width w_i and `total` every sample added (including those outside [lo, hi)). */
typedef struct gr_histogram {
    int nbins;
    double lo, hi;
    bool log_bins;       /* bin edges equally spaced in ln x (lo > 0) */
    double *count;       /* nbins entries (weights, usually 1 per sample) */
    double below, above; /* weight outside [lo, hi) */
    double total;        /* all weight added */
} gr_histogram;

int gr_histogram_init(gr_histogram *h, int nbins, double lo, double hi, bool log_bins,
                      gr_error *err);
void gr_histogram_free(gr_histogram *h);
void gr_histogram_add(gr_histogram *h, double x, double weight);
/* Add another histogram with identical binning (e.g. one per thread or per repetition). */
int gr_histogram_merge(gr_histogram *into, const gr_histogram *from, gr_error *err);
double gr_histogram_lower(const gr_histogram *h, int i);
double gr_histogram_upper(const gr_histogram *h, int i);
double gr_histogram_center(const gr_histogram *h, int i); /* geometric centre for log bins */
double gr_histogram_density(const gr_histogram *h, int i);
double gr_histogram_density_error(const gr_histogram *h, int i);
/* CSV rows "x_lo,x_hi,x,count,density,density_error" (with a header line naming x). */
void gr_histogram_write_csv(const gr_histogram *h, FILE *f, const char *xname);
/* The rows alone (a caller writing the column line itself, with units). */
void gr_histogram_write_rows(const gr_histogram *h, FILE *f);

/* ------------------------------------------------------------------------------------------
 * Chi-square fits with GSL. Parameter errors are the square roots of the covariance diagonal
 * scaled by max(1, sqrt(chi2/dof)) (the GSL manual's convention). */
#define GR_FIT_MAX_PARAMS 8
typedef struct gr_fit {
    int n_params;
    double p[GR_FIT_MAX_PARAMS], err[GR_FIT_MAX_PARAMS];
    double chi2;
    int dof;
    double chi2_red; /* chi2 / dof (NAN when dof = 0) */
    int n_points;
} gr_fit;

/* The fewest frames (samples) whose statistics carry an error bar: T's block averaging needs 16
 * (`granule run` reports "n/a (< 16 samples)"); `granule analyse` warns and `granule spm full
 * --compare-run` gives no agreement verdict below it (docs/analysis.md). */
#define GR_MIN_FRAMES 16

/* The fewest points a two-parameter fit (line, power law) reports a value from: with 2 the line
 * passes through both, chi2 = 0 and the error bar means nothing (docs/analysis.md, "Fits"). */
#define GR_FIT_MIN_POINTS 3

/* Weighted straight line y = p0 + p1 x (sigma may be NULL for unit weights). */
int gr_fit_line(const double *x, const double *y, const double *sigma, int n, gr_fit *out,
                gr_error *err);
/* Weighted polynomial y = p0 + p1 x + ... + p_degree x^degree (sigma may be NULL), degree 1-7. */
int gr_fit_poly(const double *x, const double *y, const double *sigma, int n, int degree,
                gr_fit *out, gr_error *err);
/* Power law y = A x^b fitted as a line in ln x, ln y (points with y <= 0 are skipped; sigma is the
 * error of y and becomes sigma/y). p[0] = A, p[1] = b. */
int gr_fit_power_law(const double *x, const double *y, const double *sigma, int n, gr_fit *out,
                     gr_error *err);
/* The same fit over independent runs: run i measured y[i] (its own error yerr[i], NAN if none) at
 * x[i]; runs at the same x (seeds) are averaged first, each mean's sigma being the larger of the
 * seeds' standard error and the runs' own errors combined (block averaging alone is optimistic for
 * a clustering gas). Runs with a non-finite y are left out. *n_x gets the number of distinct x
 * fitted; fewer than GR_FIT_MIN_POINTS of them is GR_EINVAL. */
int gr_fit_power_law_seeds(const double *x, const double *y, const double *yerr, int n, gr_fit *out,
                           int *n_x, gr_error *err);

/* General nonlinear least squares (gsl_multifit_nlinear, trust region with geodesic
 * acceleration). `model` returns y(x; p) and, if dydp is not NULL, the n_params derivatives. */
typedef double (*gr_fit_model)(double x, const double *p, double *dydp, void *user);
int gr_fit_nonlinear(gr_fit_model model, void *user, const double *x, const double *y,
                     const double *sigma, int n, int n_params, const double *p0, gr_fit *out,
                     gr_error *err);
/* Stretched exponential y = A exp(-(x/tau)^beta): p = (A, tau, beta) (fitted with ln tau inside). */
int gr_fit_stretched_exp(const double *x, const double *y, const double *sigma, int n,
                         const double p0[3], gr_fit *out, gr_error *err);

#endif
