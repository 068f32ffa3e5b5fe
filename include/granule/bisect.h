/* The multiplicative bisection process of thesis sec. 3.4 (Krapivsky & Majumdar 2000; Sibuya &
 * Itoh 1987): an interval of length 1 is bisected n times, every partition at every level, at a
 * fraction a drawn from a partition probability U_0(a) (3.26-3.27). A partition at level n has
 * length x_n = prod a_i (3.28); for the uniform U_0 its distribution is
 * P_n(x) = (-ln x)^(n-1) / (n-1)! (3.36) and its moments <x^m> = (1+m)^-n = N^-zeta_m with
 * N = 2^n and zeta_m = ln(1+m)/ln 2 (3.37-3.38). The collapse map (3.39-3.40) lays nearest
 * neighbour distributions G_1(R;N) of the 1D Random Force Model (sec. 3.3.2) over the process.
 *
 * Usage: gr_bisect_u0_parse() a partition probability, gr_bisect_settings_default() and adjust,
 * gr_bisect_run() the repetitions, read the gr_bisect_result or gr_bisect_write() it into an output
 * folder (CSV with commented headers, summary.json, PNG plots). The library never prints; errors
 * come back as a status and a gr_error. */
#ifndef GRANULE_BISECT_H
#define GRANULE_BISECT_H

#include <gsl/gsl_rng.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/analysis.h"
#include "granule/status.h"

#define GR_BISECT_MAX_LEVELS 24      /* 2^24 partitions (128 MiB of lengths) */
#define GR_BISECT_MAX_MOMENTS 12     /* <x^m>, m = 1..12 */
#define GR_BISECT_POWER_A_MIN -100.0 /* below, a^(1/(1-A)) rounds to 1 */
#define GR_BISECT_POWER_A_MAX                                                                      \
    0.95 /* above (normalisable up to 1), it underflows double precision */

/* ------------------------------------------------------------------------------------------
 * The partition probability U_0(a), 0 < a < 1 (3.29-3.30). */
typedef enum gr_bisect_u0_kind {
    GR_BISECT_U0_UNIFORM, /* U_0(a) = 1 (sec. 3.4.2) */
    GR_BISECT_U0_POWER, /* U_0(a) = (1 - A)/2 (a^-A + (1 - a)^-A), -100 <= A <= 0.95 (end of sec. 3.4.3) */
    GR_BISECT_U0_TABLE /* piecewise-linear density through user points (a, U), normalised */
} gr_bisect_u0_kind;

typedef struct gr_bisect_u0 {
    gr_bisect_u0_kind kind;
    double A;          /* POWER: the exponent */
    int n_points;      /* TABLE: nodes a[0] < ... < a[n-1] in [0, 1] */
    double *a, *U;     /* TABLE: nodes and the density there, normalised to integrate to 1 */
    double *cdf;       /* TABLE: integral of U from a[0] to each node (cdf[n-1] = 1) */
    double table_norm; /* TABLE: the integral of the file's U before normalising */
    double asymmetry;  /* TABLE: max |U(a) - U(1-a)| / max U; 3.30 asks for 0 (the statistics of
                          all partitions only see the symmetrised density (U(a) + U(1-a))/2) */
    char name[320];    /* "uniform", "power:A" or the table's path */
} gr_bisect_u0;

void gr_bisect_u0_uniform(gr_bisect_u0 *u);
int gr_bisect_u0_power(gr_bisect_u0 *u, double A, gr_error *err);
/* Copy n points (a_i, U_i): a strictly increasing within [0, 1], U_i >= 0, positive integral. */
int gr_bisect_u0_table(gr_bisect_u0 *u, const double *a, const double *U, int n, gr_error *err);
/* A CSV density table: '#' comments, an optional header naming columns a and U (else the first two
 * columns), one point a,U per line. */
int gr_bisect_u0_load(gr_bisect_u0 *u, const char *path, gr_error *err);
/* "uniform", "power:A", or a path to a table as for gr_bisect_u0_load. */
int gr_bisect_u0_parse(gr_bisect_u0 *u, const char *spec, gr_error *err);
void gr_bisect_u0_free(gr_bisect_u0 *u);

/* The normalised density U_0(a) (0 outside [0, 1] and outside a table's span). */
double gr_bisect_u0_density(const gr_bisect_u0 *u, double a);
/* One split drawn from U_0 by inversion, as the process uses it: the smaller fraction
 * f = min(a, 1 - a) in (0, 1/2] (never 0), and whether it lies on the left (a = f) or the right
 * (a = 1 - f). Keeping f rather than a preserves fractions far below 2^-53 (power:A near 1). */
double gr_bisect_u0_draw(const gr_bisect_u0 *u, gsl_rng *r, bool *small_left);
/* The same draw as the fraction a = f or 1 - f, in (0, 1] (1 only when 1 - a < 2^-53 is lost). */
double gr_bisect_u0_sample(const gr_bisect_u0 *u, gsl_rng *r);
/* mu_m = integral U_0(a) (a^m + (1-a)^m)/2 da (real m >= 0): the m-th moment of the factor a
 * partition's length is multiplied by at each level, so that <x_n^m> = mu_m^n (3.28-3.29; for
 * U_0 = 1, mu_m = 1/(1+m) and this is 3.37). Closed forms for the uniform and power U_0 (beta
 * function), adaptive quadrature for tables. */
int gr_bisect_u0_moment(const gr_bisect_u0 *u, double m, double *mu, gr_error *err);
/* Mean and variance of z = -ln(factor), the step of -ln x per level (uniform: 1 and 1; power:
 * digamma closed forms; tables: quadrature). */
int gr_bisect_u0_log_stats(const gr_bisect_u0 *u, double *mean, double *var, gr_error *err);

/* ------------------------------------------------------------------------------------------
 * The process itself. */

/* One level (3.26-3.27): partition i of length L becomes partitions 2i and 2i+1 of lengths a L and
 * (1 - a) L (left to right, as the boundaries r_{2i} and r_{2i+1}), computed as f L and L - f L with
 * f = min(a, 1 - a). x holds count lengths and room for 2 count. The two halves sum to L to within
 * one rounding. */
void gr_bisect_level(const gr_bisect_u0 *u, gsl_rng *r, double *x, size_t count);
/* A realisation to level n: x (2^levels entries) receives the partition lengths, x[0] = 1 first. */
int gr_bisect_realise(const gr_bisect_u0 *u, int levels, gsl_rng *r, double *x, gr_error *err);

/* The uniform process in closed form. */
double gr_bisect_pn_uniform(int n, double x); /* (3.36), 0 outside (0, 1) */
double gr_bisect_pn_uniform_mass(int n, double lo,
                                 double hi);      /* integral of (3.36) over [lo, hi] */
double gr_bisect_moment_uniform(int n, double m); /* (1+m)^-n (3.37) */
double gr_bisect_zeta_uniform(double m);          /* ln(1+m)/ln 2 (3.38) */

/* The Random Force Model's measured zeta_m of Table 3.1 (m = 1..5; NAN otherwise). */
double gr_bisect_zeta_rfm_table31(int m, double *error);

/* ------------------------------------------------------------------------------------------
 * Many repetitions: P_n(x), the moments at every level and the zeta_m fits. */
typedef struct gr_bisect_settings {
    int levels;              /* n: 2^n partitions (default 9, as Figs. 3.15-3.16) */
    int64_t repetitions;     /* independent realisations (default 10000) */
    uint64_t seed;           /* gsl_rng_mt19937 seed (default 1; GSL maps 0 to 4357) */
    int moments_max;         /* moments m = 1..moments_max (default 6, as Fig. 3.8) */
    int bins_per_decade;     /* logarithmic bins of P_n(x) (default 10) */
    int fit_level_min;       /* zeta_m from levels fit_level_min..levels (default 1) */
    int jackknife_groups;    /* groups of realisations for the fit errors (default 32) */
    double anchor;           /* R_0 of the collapse factor A_N (3.40; default 0.7) */
    double anchor_min_count; /* a process bin anchors the collapse if it holds this many (100) */
    /* Called every ~1/256 of the realisations and at the end (may be NULL). */
    void (*progress)(int64_t done, int64_t total, void *user);
    void *user;
} gr_bisect_settings;

void gr_bisect_settings_default(gr_bisect_settings *s);
int gr_bisect_settings_check(const gr_bisect_settings *s, gr_error *err);

typedef struct gr_bisect_zeta {
    int m;
    double zeta;    /* <x_k^m> = A N^-zeta over N = 2^k, k = fit_level_min..levels (3.20, 3.38) */
    double err_fit; /* chi-square fit error (treats the levels as independent, as the thesis) */
    double err_jackknife; /* jackknife over groups of realisations (levels of one tree correlate) */
    double prefactor, prefactor_err, chi2_red;
    int dof;
    double predicted; /* -log2 mu_m: the chosen U_0's exact exponent (3.38 for U_0 = 1) */
} gr_bisect_zeta;

typedef struct gr_bisect_result {
    int levels, moments_max, fit_level_min;
    int64_t repetitions;
    double segments;      /* partitions at level n over all realisations, R 2^n */
    gr_histogram pn;      /* x at level n, log bins over [10^-decades, 1) (App. A.1) */
    double *pn_count_var; /* per bin: variance of the count one realisation puts there */
    /* <x^m> at level k (0..levels), m = 1..moments_max, at [k * moments_max + m - 1]: the mean over
     * realisations of the mean over the 2^k partitions, its standard error from the spread over
     * realisations, and the exact mu_m^k. */
    double *moment, *moment_err, *moment_pred;
    double mu[GR_BISECT_MAX_MOMENTS + 1]; /* mu_m of U_0 (mu[0] = 1) */
    gr_bisect_zeta zeta[GR_BISECT_MAX_MOMENTS];
    double sum_error_max; /* largest |sum of the partitions - 1| at any level of any realisation */
    int64_t underflows;   /* level-n partitions whose length underflowed to 0 */
    double wall_seconds;
} gr_bisect_result;

/* Run settings->repetitions realisations with one gsl_rng_mt19937 seeded from settings->seed. */
int gr_bisect_run(const gr_bisect_settings *s, const gr_bisect_u0 *u, gr_bisect_result *res,
                  gr_error *err);
void gr_bisect_result_free(gr_bisect_result *res);
double gr_bisect_result_moment(const gr_bisect_result *res, int level, int m, double *error);

/* Goodness of fit of the simulated P_n(x) against (3.36), over the bins expecting at least
 * min_expected partitions. chi2 uses the count variance measured over realisations (partitions of
 * one realisation are correlated), chi2_poisson the sqrt(X) errors of App. A.1. p_value is the
 * chi-square(dof) tail of chi2 (approximate: neighbouring bins correlate too). */
typedef struct gr_bisect_gof {
    double chi2, chi2_poisson, p_value;
    int dof;
} gr_bisect_gof;
int gr_bisect_pn_gof(const gr_bisect_result *res, double min_expected, gr_bisect_gof *out,
                     gr_error *err);

/* ------------------------------------------------------------------------------------------
 * The collapse (3.39-3.40): G(R;N) -> A_N G^(1/(n-1)), n = log2 N, A_N = -ln(R_0) G(R_0;N)^(-1/(n-1)),
 * so that every collapsed curve passes through -ln R_0 at R_0; the uniform process collapses onto
 * -ln R exactly. */
double gr_bisect_collapse_factor(double n, double R0, double G0); /* A_N (3.40) */
double gr_bisect_collapse_map(double n, double A_N, double G);    /* (3.39) */

/* A nearest-neighbour distribution G_1(R;N) of the 1D RFM read from CSV: '#' comment lines, of which
 * one carries "N = <particles>" and may carry "reduced_length = <L'>" (R is divided by L' and G
 * multiplied by it, so the table is at L' = 1 as in the thesis); an optional header naming the
 * columns R, G (or G_1, density) and G_err (or density_error), so a gr_histogram_write_csv(h, f, "R")
 * table reads as it is; otherwise the columns are R, G[, G_err]. R strictly increasing, G >= 0.
 * A header with columns h and binning (the gaps.csv of a 1D run with the gaps observable) gives its
 * h = 1 rows, logarithmic bins if present; without an "N =" comment, N and L' come from the run's
 * summary.json ("gaps": {"N", "reduced_length"}) beside the file. path may also be the run folder. */
typedef struct gr_bisect_g1 {
    int n_points;
    double *R, *G, *G_err; /* G_err NULL when the file has none */
    double N, reduced_length;
    char name[320];
} gr_bisect_g1;
int gr_bisect_g1_load(gr_bisect_g1 *g, const char *path, gr_error *err);
void gr_bisect_g1_free(gr_bisect_g1 *g);
/* G at R, interpolated linearly in ln G against ln(-ln R) between the neighbouring rows (exact for
 * the logarithmic form G ~ (-ln R)^(n_N - 1) of 3.22; linearly in G where a G is 0); GR_EINVAL
 * outside the table. */
int gr_bisect_g1_at(const gr_bisect_g1 *g, double R, double *G, gr_error *err);

/* ------------------------------------------------------------------------------------------
 * Outputs: pn.csv, moments.csv, zeta.csv, collapse.csv, summary.json (last) and, if plots,
 * pn.png, moments.png, moments_N.png, collapse.png. The folder must exist (gr_output_dir_prepare).
 * A G_1 table whose anchor R_0 is outside its range is refused before anything is written. */
typedef struct gr_bisect_output {
    const gr_bisect_g1 *g1; /* n_g1 RFM tables to lay over the collapse (may be NULL) */
    int n_g1;
    bool plots;
    char plots_note[400]; /* out: the PNGs drawn, or why not */
} gr_bisect_output;
int gr_bisect_write(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                    const gr_bisect_result *res, gr_bisect_output *out, gr_error *err);

#endif
