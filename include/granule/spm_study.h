/* The three studies of `granule spm` (thesis sec. 5.2-5.3) as library calls: what a command, the
 * Python module or a campaign needs to run the Single Particle Model end to end, write its output
 * folder and read the numbers back. The building blocks (walks, fits, P_l, prediction, RFM
 * comparison) are in granule/spm.h; docs/theory-spm.md describes the outputs.
 *
 * Every study has the same life cycle:
 *   1. fill the params (gr_spm_*_params_default, then the fields asked for),
 *   2. gr_spm_*_prepare: checks the params, reads the input files (refusals are GR_EINVAL with a
 *      message naming the option and its allowed range) and resolves the defaults,
 *   3. (the caller prepares the output folder, gr_output_dir_prepare in io/files.h),
 *   4. gr_spm_*_run: the computation (walks, fits, comparison),
 *   5. gr_spm_*_write: the CSV files, summary.json and plots into a folder,
 *   6. gr_spm_*_report_free. */
#ifndef GRANULE_SPM_STUDY_H
#define GRANULE_SPM_STUDY_H

#include <stdbool.h>

#include "granule/spm.h"
#include "granule/status.h"

#define GR_SPM_MAX_RADII 32
/* C of 4.25 measured for phi = 0.530, L = 0.6 m, eps = 0.1 (thesis sec. 5.3.3) */
#define GR_SPM_THESIS_C 121.0
/* D_f the thesis measures for the same system (sec. 4.3, used throughout sec. 5.3.3) */
#define GR_SPM_THESIS_DF 1.63
#define GR_SPM_NOTE 768

/* The thesis' constants of the SPM (sec. 5.2.2, eqs. 5.6-5.7): for a walk in a disc (interval)
 * of radius l,
 *   <v_x^2> = c  (D l / M^2)^(2/3)        (5.6; velocities sampled uniformly in time)
 *   <T_fp>  = c' (l^2 M^2 / D)^(1/3)      (5.7; mean first-passage time)
 * The walks are in units u_l = (2 D l / M^2)^(1/3), t_l = (M^2 l^2 / 2D)^(1/3), so
 *   c = 2^(2/3) <w^2>,  c' = 2^(-1/3) <T / t_l>. */
double gr_spm_c_from_w2(double w2);
double gr_spm_cprime_from_exit_time(double exit_time);
/* c and c' with their errors from a set of walks (errors scale by the same factors) */
typedef struct gr_spm_constants {
    double c, c_err, c_prime, c_prime_err;
} gr_spm_constants;
void gr_spm_constants_of(const gr_spm_walk_stats *st, gr_spm_constants *out);
/* The inverse-variance mean of c and c' over radii (they do not depend on l). */
void gr_spm_constants_pool(const gr_spm_constants *per, int n, gr_spm_constants *out);

/* ------------------------------------------------------------------------------------------- *
 * circle: Q(v, l) for fixed radii (sec. 5.3.1) */
typedef struct gr_spm_circle_params {
    gr_spm_settings s;
    int bins;
    int n_radii;
    double radii[GR_SPM_MAX_RADII]; /* m */
    double wmax;                    /* histogram range of |w| = |v| / u_l */
    double fit_from;                /* Gaussian tail fit (5.12) over w >= fit_from */
} gr_spm_circle_params;

typedef struct gr_spm_circle_report {
    int n_radii;
    gr_spm_q q[GR_SPM_MAX_RADII];
    gr_spm_q pooled;                       /* batch b of every radius in batch b */
    gr_spm_tail_fit fit[GR_SPM_MAX_RADII]; /* NAN and a note where the fit failed */
    char fit_note[GR_SPM_MAX_RADII][GR_SPM_NOTE];
    gr_spm_collapse collapse[GR_SPM_MAX_RADII]; /* [r] against radius 0; [0] unused */
    gr_spm_tail_fit pooled_fit;
    char pooled_note[GR_SPM_NOTE];
    gr_spm_constants constants[GR_SPM_MAX_RADII]; /* c, c' per radius */
    gr_spm_constants pooled_constants;
    double wall_seconds;
} gr_spm_circle_report;

void gr_spm_circle_params_default(gr_spm_circle_params *p);
int gr_spm_circle_prepare(const gr_spm_circle_params *p, gr_error *err);
int gr_spm_circle_run(const gr_spm_circle_params *p, gr_spm_circle_report *r, gr_error *err);
int gr_spm_circle_write(const char *dir, const gr_spm_circle_params *p,
                        const gr_spm_circle_report *r, bool plots, gr_error *err);
void gr_spm_circle_report_free(gr_spm_circle_report *r);

/* ------------------------------------------------------------------------------------------- *
 * full: P(v) with l drawn from P_l (sec. 5.2.3), optionally against an RFM run (Fig. 5.10) */
typedef struct gr_spm_full_params {
    gr_spm_settings s;
    bool mass_set, D_set, dim_set; /* else M, D and dim default to the run's (with run_dir) */
    int bins;
    const char *pl_path; /* a P_l table, or NULL */
    const char *run_dir; /* an RFM run to compare with, or NULL */
    double df, C;        /* the fitted form 4.25 (NAN: not given; df defaults to 1.63 (the
                             thesis' D_f, sec. 4.2) when neither pl_path nor run_dir is given,
                             C to 121) */
    double tail_from;    /* fit 4.25 to the table over l >= tail_from, m (0: the longest 10%) */
    double vmax;         /* NAN: from P_l and the walks */
    double fit_from;     /* NAN: 3 v_rms */
    double t_from;       /* NAN: the run's warm-up */
    double compare_from; /* NAN: 2 v_rms of the run */
    double z_max;
    double diameter; /* NAN: the run folder's */
    bool weight_time;
} gr_spm_full_params;

typedef struct gr_spm_full_report {
    /* resolved by prepare */
    char auto_pl[1200];
    bool df_defaulted; /* D_f = 1.63 was taken because no P_l was given */
    gr_spm_pl pl;
    bool pl_loaded;
    gr_spm_pl_fit plfit;
    bool have_plfit;
    char plfit_note[GR_SPM_NOTE];
    gr_spm_prediction pred;
    bool have_pred;
    gr_spm_rfm_info info;
    double run_mass, run_D;
    /* computed by run */
    gr_spm_constants constants; /* c, c' over walks of all l (each in units of its own l) */
    gr_spm_full_result res;
    bool have_res;
    int nb;
    double *v, *p_spm, *e_spm, *p_rfm, *e_rfm; /* per bin */
    double v_rms, v_data;                      /* v_data: the largest v with SPM data */
    double sfit[3], sfit_err[3], sfit_chi2;    /* A exp(-(v/v_A)^alpha): (A, v_A, alpha) */
    int sfit_points;
    bool have_sfit;
    double f531[3], f531_err[3], f531_chi2; /* 5.31 with alpha fixed: (ln A0, h, S) */
    bool have_531;
    gr_spm_compare cmp, cmp2; /* amplitude only; amplitude and velocity scale */
    bool have_cmp, have_cmp2;
    double implied_C;
    double wall_seconds;
} gr_spm_full_report;

void gr_spm_full_params_default(gr_spm_full_params *p);
/* Resolves the run's defaults into p (M, D, dim, t_from, the run's freepath.csv as P_l, D_f). */
int gr_spm_full_prepare(gr_spm_full_params *p, gr_spm_full_report *r, gr_error *err);
int gr_spm_full_run(gr_spm_full_params *p, gr_spm_full_report *r, gr_error *err);
int gr_spm_full_write(const char *dir, const gr_spm_full_params *p, const gr_spm_full_report *r,
                      bool plots, gr_error *err);
void gr_spm_full_report_free(gr_spm_full_report *r);
/* The fit of 5.31 with alpha fixed (have_531), A0 v^h exp(-S v^alpha), at v. */
double gr_spm_full_531(const gr_spm_full_report *r, double v);

/* A P_l table (gr_spm_pl_load) whose l_over_d column is converted with `diameter` (m), or when
 * diameter <= 0 with the particle diameter of the run folder the file is in; the message of a
 * missing diameter says to give --diameter. */
int gr_spm_pl_load_for(gr_spm_pl *pl, const char *path, double diameter, gr_error *err);
double gr_spm_pl_diameter(const char *pl_path, double given);

/* ------------------------------------------------------------------------------------------- *
 * predict: alpha, h, S, v_A from D_f (sec. 5.3.2) and the integral 5.13 against 5.26 */
typedef struct gr_spm_predict_params {
    gr_spm_settings s;   /* mass and D only */
    const char *pl_path; /* fit D_f and C to this P_l table, or NULL */
    double df, C, b;     /* df NAN without pl_path: 1.63; C NAN: 121 (or the fit's) */
    double tail_from, vmax, diameter;
} gr_spm_predict_params;

typedef struct gr_spm_predict_report {
    bool df_defaulted; /* D_f = 1.63 was taken because neither --df nor --pl was given */
    gr_spm_pl_fit plfit;
    gr_spm_prediction p;
    double alpha_err; /* from the error of the fitted D_f; NAN with --df */
} gr_spm_predict_report;

void gr_spm_predict_params_default(gr_spm_predict_params *p);
int gr_spm_predict_prepare(gr_spm_predict_params *p, gr_spm_predict_report *r, gr_error *err);
/* prediction.csv (5.13 integrated numerically on 200 points up to vmax), summary.json, the plot */
int gr_spm_predict_write(const char *dir, const gr_spm_predict_params *p,
                         const gr_spm_predict_report *r, bool plots, gr_error *err);

#endif
