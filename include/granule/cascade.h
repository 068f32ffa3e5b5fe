/* The multiplicative cascade process of thesis sec. 6.2: a square of side L is broken level by
 * level into 2^n x 2^n squares, the probability m_{i,j} of each square being shared among its
 * four children by random multipliers (6.2)-(6.4) (variants UCP, UnonCP, Symmetrised, Meakin 1-4
 * of Table 6.1). Its configuration-averaged structure factor S(k) (6.5) is computed with FFTW on
 * the integer lattice k = 2 pi (q_x, q_y) / L (4.3), circularly averaged in integer |q| bins and
 * fitted by A k^-D_f (4.4) to compare with Table 6.2. Discs can be placed without overlap in
 * proportion to one field (Fig. 6.3).
 *
 * Besides Monte Carlo, the exact configuration average of S(k) follows from the first and second
 * moments of the four multipliers (the four sub-cascades of a square are independent), so every
 * variant also has an exact expected S(k) and a correlation dimension
 * D_2 = -log2( sum_c E[w_c^2] / (sum_c E[w_c])^2 ) (docs/theory-cascade.md).
 *
 * Errors: every fallible call returns 0 or a negative GR_E* code and fills a gr_error; nothing
 * here prints. Random numbers come from a caller-owned GSL generator (mt19937 in the CLI). */
#ifndef GRANULE_CASCADE_H
#define GRANULE_CASCADE_H

#include <gsl/gsl_rng.h>
#include <stdbool.h>
#include <stdint.h>

#include "granule/status.h"

#define GR_CASCADE_MAX_LEVELS 12 /* 4096 x 4096 squares: about 0.35 GB with the FFT buffers */

typedef enum gr_cascade_variant {
    GR_CASCADE_UCP = 0, /* a ~ U(0,1), A = a1 + a2 + a3 + a4 (6.2)-(6.3): conserves probability */
    GR_CASCADE_UNONCP,  /* a ~ U(0,1), A = 1: does not conserve (the total drifts as 2^n) */
    GR_CASCADE_SYMMETRISED, /* a_{i,j} = a_{i+1,j+1} = a ~ U(0,1/2), the other two 1 - a (6.4) */
    GR_CASCADE_MEAKIN1,     /* Table 6.1: (p1..p4) assigned to the four children in random order */
    GR_CASCADE_MEAKIN2,
    GR_CASCADE_MEAKIN3,
    GR_CASCADE_MEAKIN4,
    GR_CASCADE_MEAKIN,  /* Meakin with the caller's p[4] (settings.p) */
    GR_CASCADE_UNIFORM, /* control: a = 1, so every child gets m/4 (a uniform field) */
    GR_CASCADE_NVARIANTS
} gr_cascade_variant;

typedef struct gr_cascade_variant_info {
    const char *name;  /* CLI name: ucp, unoncp, symmetrised, meakin1..4, meakin, uniform */
    const char *label; /* the thesis's name: "UCP", "Meakin 1", ... */
    double p[4];       /* Table 6.1 numbers (Meakin 1-4 only; zeros otherwise) */
    double thesis_D_f, thesis_D_f_err; /* Table 6.2 (NAN where the thesis gives none) */
    bool conserving; /* children's probabilities sum to the parent's (to rounding) */
} gr_cascade_variant_info;

const gr_cascade_variant_info *gr_cascade_variant_get(gr_cascade_variant v);
/* Look a variant up by CLI name (case-insensitive; "symmetrized" accepted). */
int gr_cascade_variant_parse(const char *name, gr_cascade_variant *out, gr_error *err);

typedef struct gr_cascade_settings {
    int levels; /* n: grid of 2^n x 2^n squares (6.1), 1..GR_CASCADE_MAX_LEVELS */
    gr_cascade_variant variant;
    double p[4];                 /* GR_CASCADE_MEAKIN only: each >= 0, sum > 0 (normalised by A) */
    double L;                    /* box side, m (sec. 6.2.2 uses 1 m; Fig. 6.3 uses 0.2 m) */
    int configurations;          /* configurations averaged in S(k) (6.5) */
    unsigned long seed;          /* of the caller's gsl_rng_mt19937 (GSL uses the low 32 bits) */
    double fit_q_min, fit_q_max; /* D_f fit over the integer |q| bins q_min..q_max, k = 2 pi q / L;
                                    fit_q_max = 0: automatic (gr_cascade_fit_range) */
} gr_cascade_settings;

/* levels 8 (the thesis's 256 x 256), UCP, L = 1 m, 200 configurations, seed 1, automatic fit range. */
void gr_cascade_settings_default(gr_cascade_settings *s);
/* The fit range in bins: q_min = fit_q_min, q_max = fit_q_max or, when 0, 2^(levels-3) (structure at
 * least 8 squares wide; S is periodic in q with period 2^n and bends over towards the last bin
 * 2^(n-1), where its mirror image at 2^n - q is as large as itself), but at least 4 and at most
 * 2^(levels-1) (docs/theory-cascade.md). */
void gr_cascade_fit_range(const gr_cascade_settings *s, double *q_min, double *q_max);
/* Refuse out-of-range values with a one-line message naming the setting. */
int gr_cascade_settings_check(const gr_cascade_settings *s, gr_error *err);

/* ------------------------------------------------------------------------------------------
 * One cascade field. While refining, the level-l field occupies the top-left 2^l x 2^l block of
 * the side x side array: m_{i,j}(l) = m[j * side + i], i across (x), j down (y), the square
 * centred at r_{i,j}(l) = L / 2^l (i + 1/2, j + 1/2) (6.1). */
typedef struct gr_cascade_field {
    int levels; /* n: the finest level */
    int level;  /* current level, 0..levels */
    int side;   /* 2^levels */
    double L;   /* box side, m */
    double *m;  /* side * side probabilities (FFTW-aligned) */
} gr_cascade_field;

int gr_cascade_field_alloc(int levels, double L, gr_cascade_field **out, gr_error *err);
void gr_cascade_field_free(gr_cascade_field *f);
/* Level 0: one square of probability 1. */
void gr_cascade_field_reset(gr_cascade_field *f);
/* One level more (6.2): every square of the current level is broken into four with the
 * variant's multipliers, drawn from rng. Refuses when already at f->levels. The settings are
 * expected to have passed gr_cascade_settings_check (only the variant and p are used). */
int gr_cascade_refine(const gr_cascade_settings *s, gsl_rng *rng, gr_cascade_field *f,
                      gr_error *err);
/* Reset and refine to f->levels. totals (NULL or levels + 1 entries) receives the total
 * probability sum_{i,j} m_{i,j}(l) at every level l. */
int gr_cascade_generate(const gr_cascade_settings *s, gsl_rng *rng, gr_cascade_field *f,
                        double *totals, gr_error *err);
/* sum of m over the current level */
double gr_cascade_field_total(const gr_cascade_field *f);

/* ------------------------------------------------------------------------------------------
 * Structure factor (6.5): S(q) = |sum_{i,j} m_{i,j} exp(i k . r_{i,j})|^2 with k = 2 pi q / L,
 * averaged over configurations. The sum is one FFTW 2D real-to-complex transform of the finest
 * field (the cell-centre offset of (6.1) is a phase and drops out of |.|^2). */
typedef struct gr_cascade_sk gr_cascade_sk;

typedef struct gr_cascade_sk_bin {
    int q;         /* the bin holds the lattice vectors with q - 1/2 <= |q| < q + 1/2 */
    int vectors;   /* how many (the whole k plane, -q and q both counted) */
    double q_mean; /* mean |q| of those vectors */
    double k;      /* 2 pi q_mean / L, 1/m */
    double S;      /* configuration average of the circular average of S */
    double S_err;  /* its standard error over configurations (NAN for one configuration) */
    double
        S_expected; /* the exact configuration average (gr_cascade_sk_expected), circularly averaged */
} gr_cascade_sk_bin;

/* An accumulator for fields of s->levels levels (bins q = 1 .. 2^(levels-1)). */
int gr_cascade_sk_alloc(const gr_cascade_settings *s, gr_cascade_sk **out, gr_error *err);
void gr_cascade_sk_free(gr_cascade_sk *sk);
/* Transform one finished field (f->level == f->levels) and add it to the averages. */
int gr_cascade_sk_add(gr_cascade_sk *sk, const gr_cascade_field *f, gr_error *err);
int gr_cascade_sk_configurations(const gr_cascade_sk *sk);
/* S(q) of the field added last, and averaged over all added, at any integer q (taken modulo
 * the grid: q and q + 2^n q' are the same lattice vector of the sampled field). */
double gr_cascade_sk_last(const gr_cascade_sk *sk, int qx, int qy);
double gr_cascade_sk_mean(const gr_cascade_sk *sk, int qx, int qy);
/* The circular averages: 2^(levels-1) bins, q = 1, 2, ... */
int gr_cascade_sk_nbins(const gr_cascade_sk *sk);
void gr_cascade_sk_bins(const gr_cascade_sk *sk, gr_cascade_sk_bin *bins);

/* Direct sum of (6.5) for one field at one k (the test oracle; O(4^n) per k). */
double gr_cascade_sk_direct(const gr_cascade_field *f, int qx, int qy);

/* The exact configuration average of (6.5) for the settings' variant and levels at k = 2 pi q / L:
 * with F_l(kappa) the sum over a level-l cascade on the unit square and o_c = (g, h) / 2 the
 * corner of child c = (g, h),
 *   F_l(kappa) = sum_c w_c exp(2 pi i kappa . o_c) F^(c)_{l-1}(kappa / 2),
 * so with the children independent
 *   S_l(kappa) = sum_c E[w_c^2] S_{l-1}(kappa/2)
 *              + sum_{c != c'} E[w_c w_c'] cos(2 pi kappa . (o_c - o_c')) |M_{l-1}(kappa/2)|^2,
 *   M_l(kappa) = sum_c E[w_c] exp(2 pi i kappa . o_c) M_{l-1}(kappa/2),
 * from S_0 = 1, M_0 = exp(i pi (kappa_x + kappa_y)) at kappa = q / 2^n. */
double gr_cascade_sk_expected(const gr_cascade_settings *s, double qx, double qy);
/* E[w_c] and E[w_c w_c'] of the variant's multipliers (c = g + 2 h, child (2i+g, 2j+h)). */
void gr_cascade_moments(const gr_cascade_settings *s, double mean[4], double second[4][4]);
/* Correlation dimension of the configuration-averaged measure:
 * D_2 = -log2(sum_c E[w_c^2] / (sum_c E[w_c])^2); along every doubling of an even q,
 * S(2q) = 2^-D_2 S(q) holds exactly up to the finest level. */
double gr_cascade_d2(const gr_cascade_settings *s);

/* Fit S(k) = A k^-D_f (4.4) over the bins with q_min <= q <= q_max: a chi-square straight line in
 * ln k, ln S (gr_fit_power_law) weighted by S_err (unweighted with one configuration, or for
 * `expected`, which fits S_expected instead). Errors scaled by max(1, sqrt(chi2/dof)). */
typedef struct gr_cascade_fit {
    double D_f, D_f_err;
    double A, A_err;
    double chi2_red;
    int points;
    double q_min, q_max, k_min, k_max; /* the bins actually used */
} gr_cascade_fit;

int gr_cascade_fit_df(const gr_cascade_sk_bin *bins, int nbins, double q_min, double q_max,
                      bool expected, gr_cascade_fit *out, gr_error *err);
/* The same line with equal weights per k shell; its errors come from the scatter about the line.
 * Where the weighted fit's chi2/dof is large the scatter is the lattice's shell structure (how
 * many vectors a shell has, which directions), not noise in S: the error bars S_err do not
 * describe it, and this fit is the one to quote (gr_cascade_study headlines it then). */
int gr_cascade_fit_df_unweighted(const gr_cascade_sk_bin *bins, int nbins, double q_min,
                                 double q_max, gr_cascade_fit *out, gr_error *err);
/* chi2/dof of the weighted fit above which the unweighted fit is reported and headlined */
#define GR_CASCADE_CHI2_LARGE 3.0

/* ------------------------------------------------------------------------------------------
 * Placement of Fig. 6.3: n discs of radius r in the periodic box of side f->L, one at a time,
 * each at a point drawn with probability density proportional to the field (a square chosen
 * with probability m_{i,j} / sum m, then a uniform point in it: the same law as the thesis's
 * "accept (x, y) if p < m_{i,j}" rejection) and kept only if it overlaps no disc already placed
 * (periodic minimum-image distance >= 2r). Refused (GR_EINVAL) when impossible: 2r >= L, packing
 * fraction n pi r^2 / L^2 above the random-sequential-addition jamming limit 0.547, a field of
 * zero total, or max_attempts drawn without placing all n. */
#define GR_CASCADE_RSA_JAMMING 0.547 /* Feder, J. Theor. Biol. 87, 237 (1980) */

typedef struct gr_cascade_placement {
    int n;                /* discs */
    double radius;        /* m (Table 2.2: 1.5e-3) */
    int64_t max_attempts; /* draws allowed in total; 0: 10^6 + 10^4 n */
} gr_cascade_placement;

void gr_cascade_placement_default(gr_cascade_placement *p); /* Fig. 6.3: 2500 discs, r = 1.5 mm */

typedef struct gr_cascade_placement_result {
    int64_t attempts; /* points drawn */
    int64_t rejected; /* of which overlapped a disc already placed */
    double phi;       /* n pi r^2 / L^2 (2.24) */
} gr_cascade_placement_result;

/* The checks that need no field: n >= 1, r > 0, L >= 4r, packing fraction <= the jamming limit. */
int gr_cascade_placement_check(const gr_cascade_placement *p, double L, gr_error *err);
/* x, y: n entries each, in [0, L). The field must be finished (level == levels). */
int gr_cascade_place(const gr_cascade_field *f, const gr_cascade_placement *p, gsl_rng *rng,
                     double *x, double *y, gr_cascade_placement_result *res, gr_error *err);

#endif
