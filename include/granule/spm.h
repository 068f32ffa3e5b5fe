/* The Single Particle Model (SPM) of the thesis, sec. 5.2-5.3.
 *
 * One particle starts at rest at the centre of a disc (2D) or interval (1D) of radius l and is
 * driven by the random force (<eta eta> = 2 D delta, 2.15) until it first reaches the boundary;
 * its velocity, sampled uniformly in time, has the distribution Q(v, l) (sec. 5.3.1). Drawing l
 * from the free-path distribution P_l(l) (sec. 4.3) for every walk gives the SPM velocity
 * distribution P(v) (sec. 5.2.3, the integral identity 5.10). The steepest-descent solution of
 * 5.10 gives the asymptotic tail P(v) ~ v^h exp(-|v/v_A|^alpha) (5.27-5.31).
 *
 * Free flight is integrated exactly: over an interval tau each component advances by the
 * bivariate Gaussian of the random-acceleration process (physics notes sec. 1.2),
 *   dv = sqrt(2 D tau)/M g1,   dx = v0 tau + (tau/2) dv + sqrt(D tau^3 / 6)/M g2,
 * so positions and velocities at the sample times are exact. The only approximation is that the
 * boundary is looked for at the sample times (and, with `refine` > 0, at exactly sampled
 * bridge points between them near the boundary): a walk that leaves and re-enters between two
 * looks is continued. `step` (or `dt`) and `refine` are the knobs (docs/theory-spm.md).
 *
 * Internally every walk runs in units of its radius: length l, velocity u_l = (2 D l / M^2)^(1/3),
 * time t_l = l / u_l, in which the noise has unit strength. The process is self-similar, so Q(v, l)
 * collapses under v -> v / l^(1/3) (sec. 5.3.1): u_l Q(w u_l, l) is one function of w = v / u_l.
 *
 * Random numbers: granule's counter-based generator (granule/noise.h), keyed by the seed and by
 * (walk, step), so every run is reproducible from its seed and independent of batch sizes.
 * The library never prints: functions return 0 or a negative GR_E* code with a gr_error. */
#ifndef GRANULE_SPM_H
#define GRANULE_SPM_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/analysis.h"
#include "granule/status.h"

/* Table 2.2 */
#define GR_SPM_MASS_DEFAULT 3.53e-5 /* kg */
#define GR_SPM_D_DEFAULT 1e-8       /* N^2 s */
/* The Gaussian tail of Q (5.12): Q ~ exp(-b (M^2 / (2 D l))^(2/3) v^2) = exp(-b w^2), b = 0.98 */
#define GR_SPM_THESIS_B_COEF 0.98

typedef struct gr_spm_settings {
    int dim;       /* 1: interval [-l, l]; 2: disc of radius l (default 2) */
    double mass;   /* M, kg (default 3.53e-5, Table 2.2) */
    double D;      /* noise strength, N^2 s (default 1e-8, Table 2.2) */
    double step;   /* sampling interval in units of t_l of each walk (default 3e-3) */
    double dt;     /* > 0: a fixed sampling interval in seconds for every walk instead (the
                       * thesis' fixed time step); 0 (default) uses `step` */
    int refine;    /* bridge-refinement levels near the boundary, 0..30 (default 10) */
    int64_t walks; /* walks per radius (circle) or in all (full) (default 20000) */
    int batches;   /* independent batches of walks for the error bars, >= 2 (default 20) */
    uint64_t seed; /* default 1 */
    double tilt;   /* full SPM: importance sampling of long free paths, >= 1 (default 1:
                       * none). The distribution-function value u of each free path is drawn as
                       * 1 - (1 - U)^tilt, U uniform, and the walk weighed by
                       * tilt (1 - u)^(1 - 1/tilt); for 4.25 this draws l with C / tilt. It
                       * reaches further into the tail of P(v) for the same number of walks. */
    /* Optional progress report: fraction done in [0, 1]. Called from the sampling loop about
     * every 1000 walks; never by the library's own choice of output. */
    void (*progress)(double fraction, void *user);
    void *user;
} gr_spm_settings;

void gr_spm_settings_default(gr_spm_settings *s);
/* GR_EINVAL with a one-line reason when a setting is out of range. */
int gr_spm_settings_check(const gr_spm_settings *s, gr_error *err);

/* Natural scales of a walk of radius l: u_l = (2 D l / M^2)^(1/3) (m/s), t_l = l / u_l (s). */
double gr_spm_velocity_scale(const gr_spm_settings *s, double l);
double gr_spm_time_scale(const gr_spm_settings *s, double l);
/* B of 5.12-5.13 from the dimensionless tail coefficient b: B = b (M^2 / 2D)^(2/3) (s^2 m^-4/3),
 * so that Q ~ exp(-B v^2 / l^(2/3)). With Table 2.2 and b = 0.98: B = 0.154 (thesis sec. 5.3.3). */
double gr_spm_B(const gr_spm_settings *s, double b);

/* One exact free-flight interval of one component (physics notes sec. 1.2): from (x0, v0) over
 * tau with the noise amplitude sigma = sqrt(2 D)/M and two independent N(0,1) variates g1, g2.
 * Var(dv) = sigma^2 tau, Cov(dx, dv) = sigma^2 tau^2 / 2, Var(dx) = sigma^2 tau^3 / 3. */
void gr_spm_free_flight(double x0, double v0, double tau, double sigma, double g1, double g2,
                        double *x1, double *v1);
/* The exact midpoint of a free flight of length 2h given both ends (the random-acceleration
 * bridge): (x_m, v_m) is Gaussian with the cubic Hermite interpolant as mean and the
 * independent variances sigma^2 h^3 / 24 and sigma^2 h / 8. Used for `refine`. */
void gr_spm_bridge_midpoint(double x0, double v0, double x1, double v1, double h, double sigma,
                            double g1, double g2, double *xm, double *vm);

/* ---------------------------------------------------------------------------------------------
 * A velocity distribution of one component with error bars from the spread between batches of
 * walks (samples within a walk are strongly correlated, so sqrt(X) would be far too small). The
 * histograms are of |v|; densities are of the signed component (half the |v| density). */
typedef struct gr_spm_dist {
    gr_histogram all;    /* every batch merged; the counts are (fractional) sample weights */
    gr_histogram *batch; /* nbatches histograms with the same bins */
    int nbatches;
} gr_spm_dist;

int gr_spm_dist_init(gr_spm_dist *d, int nbatches, int nbins, double vmax, gr_error *err);
void gr_spm_dist_free(gr_spm_dist *d);
/* Density of the signed component in bin i (bins of |v|), and its standard error:
 * sqrt(sum_b (p_b - p)^2 / (B (B - 1))) over the B batch densities p_b. */
double gr_spm_dist_density(const gr_spm_dist *d, int i);
double gr_spm_dist_error(const gr_spm_dist *d, int i);
/* The sqrt(X) error of App. A.1 (gr_histogram_density_error / 2): for comparison only. */
double gr_spm_dist_poisson_error(const gr_spm_dist *d, int i);

/* Statistics of a set of walks (all in the walks' own units: lengths / l, velocities / u_l,
 * times / t_l) and the work done. */
typedef struct gr_spm_walk_stats {
    int64_t walks;
    int64_t steps;                        /* sampling intervals integrated */
    int64_t bridge_points;                /* refinement midpoints drawn */
    int64_t bridge_exits;                 /* walks whose exit was found only by the refinement */
    double exit_time_mean, exit_time_err; /* first-passage time / t_l */
    double w2_time_mean;                  /* <w^2> per component, uniformly in time */
    double w2_time_err;      /* its standard error (walks independent; ratio estimator) */
    double exit_speed2_mean; /* <|w|^2> at the exit; = dim * exit_time_mean (Ito) */
} gr_spm_walk_stats;

/* ---------------------------------------------------------------------------------------------
 * (a) Q(v, l) for a fixed radius (sec. 5.3.1). The histogram is of the scaled component
 * |w| = |v| / u_l on [0, wmax) with nbins bins, so curves of different radii are compared bin by
 * bin (the collapse). `index` separates the random streams of different radii of one run. */
typedef struct gr_spm_q {
    double radius;  /* l, m */
    double u;       /* u_l, m/s */
    double t_scale; /* t_l, s */
    double tau;     /* sampling interval / t_l actually used */
    gr_spm_dist q;  /* of w: density of v is density(w) / u */
    gr_spm_walk_stats stats;
} gr_spm_q;

int gr_spm_circle(const gr_spm_settings *s, double radius, int index, int nbins, double wmax,
                  gr_spm_q *out, gr_error *err);
void gr_spm_q_free(gr_spm_q *q);

/* A statistic of a distribution with a leave-one-batch-out jackknife error (the bins are
 * correlated, since one walk fills many of them, so a fit's own chi-square errors are too small).
 * fn gets, per bin, the centre x, the density p, its batch error e and the merged sample count;
 * it writes nout numbers to out and returns 0, or non-zero when it cannot (then the jackknife
 * fails with GR_EINVAL). value = fn on all batches; jk_err[k] = sqrt((B-1)/B sum_j (t_j - t)^2)
 * over the B leave-one-out estimates t_j (the error bars stay those of all batches). */
typedef int (*gr_spm_stat_fn)(const double *x, const double *p, const double *e,
                              const double *count, int n, double *out, void *user);
int gr_spm_dist_jackknife(const gr_spm_dist *d, gr_spm_stat_fn fn, void *user, int nout,
                          double *value, double *jk_err, gr_error *err);

/* The Gaussian tail 5.12 fitted to Q: ln Q(w) = ln A - b w^2 over the bins with w >= wfrom and at
 * least min_count samples (a weighted straight line in w^2 with gr_fit_line), and a free-exponent
 * check Q = A exp(-(w/tau)^beta) over the same bins (gr_fit_stretched_exp; beta = 2 for a Gaussian
 * tail). Errors are jackknife errors over the batches. */
typedef struct gr_spm_tail_fit {
    double wfrom, wto;
    double b, b_err; /* the coefficient of 5.12 (thesis 0.98) */
    double A, A_err; /* amplitude of the scaled density */
    double chi2_red; /* of the line fit with the batch errors (bins correlated) */
    int n_points;
    double beta, beta_err; /* free-exponent fit (NAN if it failed) */
} gr_spm_tail_fit;
int gr_spm_q_tail_fit(const gr_spm_q *q, double wfrom, double min_count, gr_spm_tail_fit *out,
                      gr_error *err);

/* Collapse of two scaled Q histograms (same bins and number of batches): over the bins where
 * both hold at least min_count samples, chi^2 = sum (Q_a - Q_b)^2 / (s_a^2 + s_b^2) with Q the
 * mean and s the standard error of the batch densities. Neighbouring bins are correlated, so the
 * chi-square law's p-value (p_chi2) is only indicative; p_value comes from a permutation test:
 * the 2B batches are exchangeable when the curves collapse, and p_value is the fraction of
 * `permutations` random re-splits (a fixed generator: reproducible) with a chi^2 at least as
 * large as the observed one. permutations = 0 skips it (p_value = p_chi2). */
typedef struct gr_spm_collapse {
    double chi2;
    int dof;
    double chi2_red, p_chi2, p_value;
    int permutations;
    double max_abs_z;
} gr_spm_collapse;
int gr_spm_q_collapse(const gr_spm_q *a, const gr_spm_q *b, double min_count, int permutations,
                      gr_spm_collapse *out, gr_error *err);

/* ---------------------------------------------------------------------------------------------
 * The free-path distribution P_l(l) (sec. 4.3): either the fitted form 4.25,
 *   P_l(l) = A0 l^(D_f - 2) exp(-C l^(D_f - 1)) = Weibull with shape beta = D_f - 1,
 * sampled exactly through its distribution function 1 - exp(-C l^beta), or a table (a CSV file
 * with columns l and P, see gr_spm_pl_load) sampled as a piecewise-linear density. */
enum { GR_SPM_PL_FITTED = 0, GR_SPM_PL_TABLE = 1 };
typedef struct gr_spm_pl {
    int kind;
    double df, beta, C;   /* fitted form: beta = D_f - 1, C in m^-beta */
    int n;                /* table: points (l ascending, P >= 0) */
    double *l, *p, *perr; /* perr NULL when the file has no error column */
    double *cdf;          /* cumulative integral at each point, normalised to 1 */
    char source[512];     /* file name or "fitted form 4.25" */
} gr_spm_pl;

int gr_spm_pl_fitted(gr_spm_pl *pl, double df, double C, gr_error *err);
/* Read a CSV file: '#' lines are comments; the first other line names the columns; the free path
 * is the column "l" (m) and the density the column "P" (or "density", as gr_histogram_write_csv
 * writes); an optional error column "P_err" (or "density_error"). Other columns are ignored. A
 * run's freepath.csv (the freepath observable) has "l_over_d" instead of "l": then `diameter`
 * (m, the particle diameter) converts it, and must be > 0. At least 3 rows with l > 0 ascending,
 * P >= 0 and a positive integral. */
int gr_spm_pl_load(gr_spm_pl *pl, const char *path, double diameter, gr_error *err);
void gr_spm_pl_free(gr_spm_pl *pl);
/* The normalised density at l, and the free path with distribution function value u in [0, 1). */
double gr_spm_pl_density(const gr_spm_pl *pl, double l);
double gr_spm_pl_quantile(const gr_spm_pl *pl, double u);
double gr_spm_pl_mean(const gr_spm_pl *pl);

/* Fit the tail of a tabulated P_l with 4.25, ln P = ln A0 + (beta - 1) ln l - C l^beta, over the
 * points with l >= lfrom (lfrom <= 0: the longest 10% of the paths, l >= the 0.9 quantile),
 * weighted by the relative errors when the file has them (else by their scatter). D_f = beta + 1. */
typedef struct gr_spm_pl_fit {
    double lfrom, lto;
    double A0, C, C_err, beta, beta_err, df, df_err;
    double chi2_red;
    int n_points;
} gr_spm_pl_fit;
int gr_spm_pl_fit_tail(const gr_spm_pl *pl, double lfrom, gr_spm_pl_fit *out, gr_error *err);

/* ---------------------------------------------------------------------------------------------
 * (b) The full SPM (sec. 5.2.3): every walk draws its own l from P_l. weight_time = true samples
 * every walk uniformly in time (the thesis' simulation: long walks weigh more); false weighs every
 * walk equally (5.10 taken literally with Q normalised per walk). P(v) is histogrammed in m/s on
 * [0, vmax). */
typedef struct gr_spm_full_result {
    gr_spm_dist p; /* P(v) of one component, m/s */
    gr_spm_walk_stats stats;
    double l_mean;  /* mean drawn free path, m */
    double v2_mean; /* <v^2> per component of P(v), m^2/s^2 */
} gr_spm_full_result;

int gr_spm_full(const gr_spm_settings *s, const gr_spm_pl *pl, bool weight_time, int nbins,
                double vmax, gr_spm_full_result *out, gr_error *err);
void gr_spm_full_result_free(gr_spm_full_result *r);

/* ---------------------------------------------------------------------------------------------
 * (c) The asymptotic prediction (sec. 5.3.2) from D_f (beta = D_f - 1, gamma = 3 beta):
 *   alpha = 2 gamma / (gamma + 2) = 6 (D_f - 1) / (3 D_f - 1)                     (5.28-5.29)
 *   |v / v_A|^alpha = [B (gamma / 2F)^(2/(gamma+2)) + C (2F / gamma)^(gamma/(gamma+2))] |v|^alpha,
 *   F = B / C                                                                      (5.27)
 *   H(v) ~ v^h, h = (2 + 2 gamma)/(2 + gamma) - 1 = 3 (D_f - 1) / (3 D_f - 1)      (5.30-5.31)
 * S is the bracket of 5.27 (the numbers the thesis quotes as "v_A" in sec. 5.3.3, e.g. 9.48 for
 * C = 121, B = 0.154); v_A = S^(-1/alpha). B and C may be 0 (unknown): then S and v_A are NAN. */
typedef struct gr_spm_prediction {
    double df, beta, gamma, alpha, h;
    double B, C, F;
    double S, v_A;
} gr_spm_prediction;

double gr_spm_alpha(double df);
int gr_spm_predict(double df, double B, double C, gr_spm_prediction *out, gr_error *err);
/* The right-hand side of 5.13 with A_2 = 1, integrated numerically (GSL QAG in y = l^beta):
 * I(v) = int_0^inf exp(-B v^2 / y^(2/gamma) - C y) dy, returned as ln I(v). For v -> inf,
 * ln I - [ln sqrt(pi / -f''(y_m)) - S v^alpha] -> 0 (the steepest-descent result 5.26). */
int gr_spm_integral_log(const gr_spm_prediction *p, double v, double *log_value, gr_error *err);
/* ln of the steepest-descent form 5.26: f(y_m) + ln sqrt(pi / -f''(y_m)). */
double gr_spm_asymptotic_log(const gr_spm_prediction *p, double v);

/* ---------------------------------------------------------------------------------------------
 * The Random Force Model's P(v) per component from a run folder: every DIR/snapshots/snap_*.xyz
 * (extended XYZ, columns species pos(3) velo(3) radius) with Time >= t_from is added to h (bins
 * of |v|, prepared by the caller), every component of every particle once (dim from the pbc
 * field). Counts in h are samples, so gr_histogram's sqrt(X) errors apply (frames far apart). */
typedef struct gr_spm_rfm_info {
    int frames, frames_skipped, dim;
    int64_t particles; /* per frame (the last one read) */
    double t_first, t_last;
    double v2_mean; /* <v^2> per component over the frames read */
    double v_max;   /* largest |v| component seen */
} gr_spm_rfm_info;
int gr_spm_rfm_histogram(const char *dir, double t_from, gr_histogram *h, gr_spm_rfm_info *info,
                         gr_error *err);

/* Compare two P(v) tails given on the same bins (v centres ascending, equal widths). The SPM
 * curve is scaled vertically by k (the thesis' Fig. 5.10 does the same), fitted over the bins
 * v >= v_from where both are positive; with fit_scale also horizontally, k P_spm(v / s) / s (ln P_spm
 * interpolated linearly between bin centres), which is the SPM P(v) for free paths scaled by s^3
 * (the SPM is self-similar; for 4.25 that is C -> C s^(-3 (D_f - 1))). Then, going down from the
 * highest bin where both have data, bins agree when |P_rfm - model| <= z_max sqrt(s_rfm^2 +
 * e_model^2); `decades` is log10(P_rfm(v_lo) / P_rfm(v_hi)) over that contiguous range, and
 * frac_within the fraction of all bins v >= v_from within z_max. e_rfm must be sqrt(X) errors:
 * s_rfm^2 = model e_rfm^2 / P_rfm is then the Poisson variance of the count the model expects
 * (Pearson; the fits use it too), which the observed sqrt(X) underestimates for low-count
 * deficits. */
typedef struct gr_spm_compare {
    double v_from, k, k_err, s, s_err; /* s = 1 unless fit_scale */
    double chi2_red;                   /* over the bins v >= v_from */
    int n_points;
    double v_agree_lo, v_agree_hi, decades;
    int agree_bins;
    double frac_within;
} gr_spm_compare;
int gr_spm_compare_tails(const double *v, const double *p_spm, const double *e_spm,
                         const double *p_rfm, const double *e_rfm, int n, double v_from,
                         double z_max, bool fit_scale, gr_spm_compare *out, gr_error *err);
/* The compared model at bin i: k P_spm(v_i / s) / s and its error (0 where P_spm is unknown). */
double gr_spm_compare_model(const gr_spm_compare *c, const double *v, const double *p_spm,
                            const double *e_spm, int n, int i, double *model_err);

/* Fig. 5.10 in numbers from the two series alone (src/theory/spm_compare_series.c; a campaign's
 * kind spm_compare archives them): v_rms of the run's P(v) from its bins (sum P v^2 / sum P), both
 * comparisons above from v_from = from_vrms v_rms (amp: k only, as the thesis's vertically scaled
 * SPM curves; scaled: k and s), and the tail exponent alpha of A exp(-(v/v0)^alpha) fitted to each
 * series over v >= v_from (bins with P > 0 and an error; NAN with fewer than 4). GR_EINVAL when the
 * run's series is empty or no bin beyond v_from has both. */
#define GR_SPM_SERIES_MAX_BINS 4096
typedef struct gr_spm_series_compare {
    double v_rms, v_from;
    gr_spm_compare amp, scaled;
    bool have_amp, have_scaled;
    double alpha_spm, alpha_spm_err, alpha_rfm, alpha_rfm_err;
    int points_spm, points_rfm;
} gr_spm_series_compare;
int gr_spm_compare_series(const double *v, const double *p_spm, const double *e_spm,
                          const double *p_rfm, const double *e_rfm, int n, double from_vrms,
                          double z_max, gr_spm_series_compare *out, gr_error *err);

/* ---------------------------------------------------------------------------------------------
 * The RFM's P(v) against the SPM's asymptotic form, as measured from a run's tables (Figs.
 * 5.12-5.13; src/theory/spm_rfm_tail.c, docs/theory-spm.md).
 *
 * Fold a P(v) given on bins symmetric about 0 (v ascending, as the pv observable's pv.csv):
 * P_sym(|v|) = (P(v) + P(-v)) / 2 with error sqrt(e(v)^2 + e(-v)^2) / 2, and the counts behind
 * it, (P/e)^2 summed over both sides (the errors are sqrt(X) ones, A.5). Writes the bins with
 * v > 0 ascending and returns how many; 0 when the bins are not symmetric about 0. */
int gr_spm_fold_pv(const double *v, const double *p, const double *e, int n, double *vf, double *pf,
                   double *ef, double *counts);

/* 5.31 with alpha and h fixed, ln P = ln A0 + h ln v - S |v|^alpha (v in m/s), fitted to the
 * folded P(v) as a weighted line in v^alpha over the window x_lo <= v / v_rms <= x_hi where the
 * bin has at least counts_min counts; errors scaled by sqrt(chi2/dof) when that exceeds 1
 * (counts sampled every ms are correlated). Then the tail plot of Fig. 5.13 over the same bins,
 * -ln(-ln(P / P')) against ln(v / v_rms), a weighted line for P' = P(0) and for P' = A0: for P
 * exactly A0 exp(-S v^alpha) its slope with P' = A0 is -alpha. With S_pred > 0 also the amplitude
 * of 5.31 with S fixed at S_pred (the line of Fig. 5.12). */
typedef struct gr_spm_tail531 {
    double alpha, h;            /* fixed */
    double v_lo, v_hi, decades; /* the bins fitted (m/s) and log10 P(v_lo) / P(v_hi) */
    int n_points;
    double S, S_err, lnA0, lnA0_err, chi2_red;
    double A0, P0, A0_over_P0;
    double lnA0_at_S_pred; /* NAN without S_pred */
    double slope_P0, slope_P0_err, slope_A0, slope_A0_err;
    double icpt_P0, icpt_A0; /* the lines' intercepts, at ln(v / v_rms) = 0 */
} gr_spm_tail531;
int gr_spm_tail531_fit(const double *v, const double *p, const double *e, const double *counts,
                       int n, double P0, double v_rms, double alpha, double h, double x_lo,
                       double x_hi, double counts_min, double S_pred, gr_spm_tail531 *out,
                       gr_error *err);
/* ln of 5.31 at v: ln A0 + h ln v - S v^alpha. */
double gr_spm_tail531_log(double lnA0, double h, double S, double alpha, double v);

/* C of 4.25 with beta = D_f - 1 fixed, ln P - (beta - 1) ln l = ln A0 - C l^beta, a weighted line
 * in l^beta over the points l_lo <= l <= l_hi with P > 0 and e > 0 (C in the units of l^-beta; a
 * table in diameters gives C per d^beta: C_SI = C d^-beta). Errors scaled by sqrt(chi2/dof) > 1. */
int gr_spm_pl_fit_C(const double *l, const double *p, const double *e, int n, double beta,
                    double l_lo, double l_hi, double *C, double *C_err, double *chi2_red,
                    gr_error *err);

#endif
