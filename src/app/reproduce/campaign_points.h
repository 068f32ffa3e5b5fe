/* The finished points of a campaign's sweep, read back from DIR/runs/pNNNN (point.json +
 * summary.json), and the per-result analyses that turn them into rows. */
#ifndef GR_REPRODUCE_CAMPAIGN_POINTS_H
#define GR_REPRODUCE_CAMPAIGN_POINTS_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stdio.h>

#include "granule/campaign.h"
#include "io/files.h"

typedef struct campaign_point {
    char dir[1100];
    cJSON *manifest; /* point.json: keys, seed, cpu_seconds, scene_hash, commit */
    cJSON *summary;  /* summary.json */
    double cpu_seconds, sim_seconds;
} campaign_point;

typedef struct campaign_points {
    int n;
    campaign_point *p;
} campaign_points;

/* Every completed point under dir/runs (unfinished and failed ones are left out). */
int campaign_points_read(const char *dir, campaign_points *pts, gr_error *err);
void campaign_points_free(campaign_points *pts);
/* The value of varied key `key` of a point ("" if not varied). */
const char *campaign_point_key(const campaign_point *p, const char *key);

/* The unit of a group's key as the page writes it ("m" for L, "" for a number). */
const char *campaign_key_unit(const char *key);
/* A group label as a physicist writes it: "N+L=3000/0.2, eps_n=0.1" -> "N = 3000, L = 0.2 m,
 * eps_n = 0.1" (linked keys split, units of the lengths, masses and times added). */
void campaign_pretty_group(const char *group, char *out, size_t len);

/* A field of a result set (results.json): its text ("" if absent) or number (NAN if absent). */
const char *campaign_json_str(const cJSON *o, const char *name);
double campaign_json_num(const cJSON *o, const char *name);
/* Write one campaign's page, RESULTS_ROOT/NAME/README.md, from its result set s (refreshed by
 * today's campaign file); OVERVIEW is the file name of the page beside RESULTS_ROOT that links it. */
int campaign_page_write(const cJSON *s, const char *results_root, const char *overview,
                        gr_error *err);

/* Keep every point's manifest, summary and curve series in RESULTS/points (campaign_archive.c). */
int campaign_archive(const gr_campaign *c, const campaign_points *pts, const char *results,
                     gr_error *err);
/* v to the 6 significant digits the archive keeps a series at: an analysis that rounds its run's
 * series with it gives the same numbers on archived points (%.6g round trips). */
double campaign_archive_digits(double v);

/* One row of results.csv: a number of ours beside the thesis's. */
typedef struct campaign_row {
    char group[160]; /* the varied values it belongs to, e.g. "model.eps_n=0.1" */
    int m;           /* moment order, 0 if none */
    double value, error;
    double error_fit, error_seeds; /* the two estimates behind `error` (NAN if not applicable) */
    int n_seeds, n_x;              /* seeds averaged; abscissa points in a fit */
    double chi2_red, x_lo, x_hi;
    char x_unit[24]; /* the unit of x_lo, x_hi; "" for a power law's: its abscissa key's */
    double thesis, thesis_error; /* NAN if the thesis gives none */
    char thesis_note[128];
    /* How ours is compared with the thesis's (docs/campaigns/README.md, "Kinds of comparison"):
     * "z" (a value with an error), "stated" (a value without one: within its stated digits),
     * "about", "range" (thesis .. thesis_hi), "model" (a model's value, not a measurement),
     * "construction" (equal by construction: not a result); "" when there is no thesis value. */
    char comparison[16];
    double thesis_hi; /* range: the upper end */
    double tolerance; /* stated, about, model: how far ours may lie from the thesis's value */
    int agrees;       /* 1 or 0 for the kinds without a z, -1 where it does not apply */
    double z;         /* kind "z" only: (ours - thesis) / sqrt(error^2 + thesis_error^2) */
    double sim_seconds, cpu_seconds;
    int unconverged;  /* runs whose own (block-averaging) error of T had not converged */
    char hashes[160]; /* scene hashes of the points used (first few) */
    /* A power law's rows of local slopes (role 'l': the exponent between x_lo and x_hi) and of
     * their trend (role 't': d exponent / d ln x over the fit, from a quadratic in ln x, whose
     * local exponent at centre_x is centre_value); 0 for every other row. */
    char role;
    double centre_x, centre_value;
} campaign_row;

typedef struct campaign_rows {
    int n, cap;
    campaign_row *r;
} campaign_rows;

/* Notes of the analysis for its caller (a figure not drawn, a point's SPM not run): the library
 * does not print; gr_campaign_analyse hands them over. */
void campaign_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void campaign_notes_take(char *out, size_t len);

campaign_row *campaign_rows_add(campaign_rows *rows);
void campaign_rows_free(campaign_rows *rows);

/* The analyses (campaign_analyse.c): rows from points, the data behind the figure into `data`
 * (a CSV with a header line whose units go to ID_data.meta.json, campaign_header) and the gnuplot
 * body of the figure into `plot`. */
int campaign_mean(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                  campaign_rows *rows, gr_file *data, gr_error *err);
int campaign_power_law(const gr_campaign *c, const gr_campaign_result *r,
                       const campaign_points *pts, campaign_rows *rows, gr_file *data,
                       gr_error *err);
int campaign_running(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                     campaign_rows *rows, gr_file *data, gr_error *err);
int campaign_rise(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                  campaign_rows *rows, gr_file *data, gr_error *err);
/* CASCADE (Fig. 6.3): also writes RESULTS/ID_positions.csv (campaign_cascade.c). */
int campaign_cascade(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                     campaign_rows *rows, const char *results, gr_file *data, gr_error *err);
/* SPM (Figs. 5.12-5.13, campaign_spm.c): also writes RESULTS/ID_tail.dat and draws ID_data.png. */
int campaign_spm(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                 campaign_rows *rows, const char *results, gr_file *data, gr_error *err);
/* Is y one of GR_CAMPAIGN_SPM_QUANTITIES? */
bool campaign_spm_quantity_known(const char *y);
/* The run tables the SPM kind reads, as CURVE results (which = 0: pv.csv's P(v); 1: freepath.csv's
 * P_l), so that the archive keeps their series under the keys of fig5.4 and fig4.10. */
void campaign_spm_series(int which, gr_campaign_result *out);
/* SPM_COMPARE (Fig. 5.10, campaign_spm_compare.c): per run the full SPM from its free paths against
 * its snapshots' P(v) (gr_spm_full_*, walks by fidelity), kept as RUN/spm_compare.csv; writes
 * RESULTS/ID_pv.dat and draws ID_data.png. */
int campaign_spm_compare(const gr_campaign_result *r, gr_fidelity fid, const campaign_points *pts,
                         campaign_rows *rows, const char *results, gr_file *data, gr_error *err);
bool campaign_spm_compare_quantity_known(const char *y);
/* The two series it reads from spm_compare.csv as CURVE results (which = 0: the SPM's P(v); 1: the
 * run's), so that the archive keeps them. */
void campaign_spm_compare_series(int which, gr_campaign_result *out);
/* SPM_CIRCLE (Fig. 5.11, campaign_spm_circle.c): Q(v,l) of walks in discs of fixed radius with the
 * runs' M and D, the Gaussian tail of 5.12 per radius and pooled; writes RESULTS/ID_q.dat and draws
 * ID_data.png. */
int campaign_spm_circle(const gr_campaign_result *r, gr_fidelity fid, const campaign_points *pts,
                        campaign_rows *rows, const char *results, gr_file *data, gr_error *err);
bool campaign_spm_circle_quantity_known(const char *y);
/* CASCADE_FIELD (Table 6.2, campaign_cascade_field.c): D_f of every cascade variant's own S(k). */
int campaign_cascade_field(const gr_campaign_result *r, gr_fidelity fid, campaign_rows *rows,
                           const char *results, gr_file *data, gr_error *err);
/* COLLAPSE (Fig. 3.3, campaign_collapse.c): the points of the power_law result `compensate`, each
 * times x^(its group's fitted exponent), against the group's value b or 1 - b^2; a row per point;
 * writes RESULTS/ID_series.dat and draws ID.png. */
int campaign_collapse(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                      campaign_rows *rows, const char *results, gr_file *data, gr_error *err);
int campaign_curve(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                   campaign_rows *rows, gr_file *data, gr_error *err);
/* A CURVE result's series of one run (from its table, or from the archive's series.json): x, y, e
 * (at most 4096 rows each), rows with a finite y only, at the archive's 6 digits either way (a
 * restored point gives what the live run gave); returns the number of rows. */
int campaign_curve_series(const campaign_point *p, const gr_campaign_result *r, double *x,
                          double *y, double *e);
/* The name a CURVE result's series is archived under (results sharing table and columns share it). */
void campaign_curve_key(const gr_campaign_result *r, char *out, size_t len);
/* The bisection collapse (thesis 3.39-3.40) of G(x) in place: x -> -ln x, G -> A_N G^(1/(n-1)) with
 * n = log2 N and A_N such that the mapped G(x0) (interpolated log-log between the bins around x0,
 * x ascending) is -ln x0; errors propagated. False (nothing changed) when G there is not positive
 * or N <= 2. */
bool campaign_bisection_collapse(double N, double x0, double *x, double *y, double *e, int n);
/* The result's `transform` of one point's series in place; returns its new length (0: cannot). */
int campaign_curve_transform(const gr_campaign_result *r, const campaign_point *p, double *x,
                             double *y, double *e, int n);
/* Is a group label among `select`'s (values of one key are alternatives, keys must all hold)? */
bool campaign_curve_selected(const char *select, const char *label);
/* overlay = power_law: A of A x^E over the window [x_min, x_max] (ln A the mean of ln y - E ln x);
 * NAN when no point is in it. */
double campaign_curve_overlay_amplitude(const gr_campaign_result *r, const double *x,
                                        const double *y, int n);

/* Is the warm-up long enough? The mean of T over the first quarter of a run's sampling relative to
 * the mean over the rest, minus 1, from temperature.csv, or for a point restored from the archive
 * the value archived with it (warmup.json); NAN without either. */
double campaign_warmup_drift(const campaign_point *p, double *error);

/* Shared by the analyses (campaign_analyse.c). */
/* The header line of a data table: pairs of column name and unit (NULL: none known), ending with
 * NULL; the units go to the table's NAME.meta.json (docs/trajectories.md's unit forms). */
void campaign_header(gr_file *f, ...);
/* The unit of a result's quantity as the campaign file gives it ("1" for a pure number), as
 * results.csv's unit column writes it. */
const char *campaign_unit(const gr_campaign_result *r);
/* The unit of the summary value y a power law fits: "(m s-1)^m" / "m^m" for the speed and gap
 * moments with the power in the row's column m, else the summary's table (NULL if it has none). */
const char *campaign_y_unit(const gr_campaign_result *r, char *buf, size_t len);
/* Draw DIR/ID SUFFIX.png (SUFFIX "" for the result's figure, "_data" for its data figure) from a
 * gnuplot script body (io/plot.h); a figure that cannot be drawn is reported on stderr and skipped,
 * the numbers stand without it. */
void campaign_draw(const char *dir, const char *id, const char *suffix, const char *body);
/* ID.png, ours beside the thesis's, against m or a varied number with a handful of series where
 * the rows' keys allow it (campaign_compare_series.c); false (nothing drawn) otherwise. */
bool campaign_compare_series(const char *dir, const gr_campaign_result *r,
                             const campaign_rows *rows, const char *ylabel);
/* A power law with local_slopes: ID_slopes.dat and ID_slopes.png, the local slopes against x with
 * their trend, the whole fit's exponent and the thesis's value (campaign_slopes.c). */
void campaign_slopes_plot(const char *dir, const gr_campaign_result *r, const campaign_rows *rows);
#define MAX_GROUPS 256
#define MAX_SEEDS 64
/* "k=v, k=v" of a point's varied keys (sections dropped): those in `only` (all if NULL), minus `except`. */
void campaign_group_of(const campaign_point *p, const char *only, const char *except, char *out,
                       size_t len);
/* The distinct groups of the points in order of first appearance; returns how many. */
int campaign_groups(const campaign_points *pts, const char *only, const char *except,
                    char g[][160]);
/* Mean and standard error of the mean (NAN with fewer than 2 values). */
void campaign_mean_sd(const double *v, int n, double *mean, double *se);
/* The error a row reports: the seeds' when there are 3 or more, else the larger estimate. */
double campaign_headline_error(double seeds, double other, int n_seeds);
/* Book a point's CPU and simulated seconds, scene hash and convergence flag into a row. */
void campaign_add_cost(campaign_row *row, const campaign_point *p);
int campaign_seed_of(const campaign_point *p);
/* The points of a group of all varied keys (as campaign_groups(pts, NULL, NULL, ...) names it);
 * returns how many (at most max). */
int campaign_members(const campaign_points *pts, const char *group, const campaign_point **members,
                     int max);
/* A new row for a group. */
campaign_row *campaign_group_row(campaign_rows *rows, const char *group);

/* The index of y among names[0..n), or -1. */
int campaign_name_index(const char *const *names, int n, const char *y);
/* A row from the runs' values v[0..n) of a group: their mean, the seeds' standard error, the runs'
 * own errors combined (sqrt(err2_sum) / n when all n_err == n runs had one, else NAN), the headline
 * error, n_seeds and the thesis columns. */
void campaign_row_of_runs(const gr_campaign_result *r, campaign_row *row, const double *v, int n,
                          double err2_sum, int n_err);

/* How many of a result's thesis entries name a group (with " m=K") that no row has; the first
 * such group goes to `first`. A complete campaign must have none: a misspelt group would drop its
 * comparison without a word (gr_campaign_analyse refuses it). */
int campaign_thesis_unmatched(const gr_campaign_result *r, const campaign_rows *rows, char *first,
                              size_t len);
/* Fill thesis, thesis_error and z of a row from the result's thesis list. */
void campaign_row_thesis(const gr_campaign_result *r, campaign_row *row);
/* Re-judge a committed result set (results.json) by today's campaign file: its words, verdicts,
 * thesis values and comparisons replace the set's; the numbers stay (campaign_refresh.c). */
struct cJSON;
void campaign_refresh_json(const gr_campaign *c, struct cJSON *set);

#endif
