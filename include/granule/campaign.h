/* Reproduction campaigns: one file per set of runs behind thesis figures and tables
 * (docs/campaigns/NAME.ini, compiled into the library), run as a `granule sweep`, analysed into a
 * small result set (CSV + JSON + figures) and a generated page, docs/reproduction.md.
 * The format and the analysis kinds are documented in docs/campaigns/README.md. */
#ifndef GRANULE_CAMPAIGN_H
#define GRANULE_CAMPAIGN_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "granule/status.h"

#define GR_CAMPAIGN_MAX_LINES 64
#define GR_CAMPAIGN_MAX_RESULTS 20
#define GR_CAMPAIGN_MAX_VARY 8

/* A thesis value quoted without an error that ours equals to 1e-4 relative is exact by
 * construction (Table 3.1's zeta_1 = 1: the fit reproduces it to rounding, ~1e-6): a z of our
 * rounding against no error would mean nothing, so there is none and the page says "exact". */
#define GR_CAMPAIGN_EXACT_REL 1e-4
static inline bool gr_campaign_exact_match(double value, double thesis, double thesis_error)
{
    return !(thesis_error > 0.0) && isfinite(value) && isfinite(thesis) &&
           fabs(value - thesis) <= GR_CAMPAIGN_EXACT_REL * fabs(thesis);
}

/* The verdicts a campaign may give a result whose numbers disagree with the thesis (key verdict,
 * docs/campaigns/README.md), in the order the reproduction page counts them. */
#define GR_CAMPAIGN_VERDICTS 3
static const char *const gr_campaign_verdicts[GR_CAMPAIGN_VERDICTS] = {
    "explained", "partly explained", "unexplained"};

typedef enum { GR_FIDELITY_QUICK = 0, GR_FIDELITY_FULL = 1 } gr_fidelity;

/* How a [result ID] section turns the runs into numbers (docs/campaigns/README.md):
 * MEAN       y averaged over seeds for every combination of the varied keys;
 * POWER_LAW  y = A x^-exponent fitted over x (usually system.N) in [x_min, x_max] per
 *            combination of the `by` keys, and per m when y names {m};
 * RUNNING    the running average of T(t) and its means over `period` seconds (Fig. 2.8);
 * RISE       the time T(t) takes to reach 90 % of its steady value (Fig. 2.7);
 * CURVE      a table column y(x) of every run (e.g. G_1(R) of gaps.csv) averaged over seeds bin by
 *            bin, one curve per combination of the varied keys, optionally mapped (`transform`) and
 *            summarised by the slope of a power law over [x_min, x_max];
 * CASCADE    y averaged over seeds as MEAN (the RFM's D_f of S(k)), beside the same S(k) analysis of
 *            discs placed from `configurations` multiplicative-cascade fields (UCP, 256 x 256, the
 *            runs' N, L and radius; Fig. 6.3), and both configurations side by side;
 * SPM        the Single Particle Model's prediction of the P(v) tail (5.27-5.31) from each run's free
 *            paths against the run's P(v) (Figs. 5.12-5.13): y names the quantity reported, one of
 *            GR_CAMPAIGN_SPM_QUANTITIES; `df` fixes D_f (0: the free 4.25 fit of the run).
 * SPM_COMPARE the full SPM (walks with l drawn from each run's own free paths) against the run's P(v)
 *            from its snapshots (Fig. 5.10): y names one of GR_CAMPAIGN_SPM_COMPARE_QUANTITIES;
 *            `walks` and `walks_quick` the walks per run at each fidelity.
 * SPM_CIRCLE Q(v,l) of the SPM in discs of fixed radius with the runs' M and D (Fig. 5.11): the
 *            Gaussian tail of 5.12 per radius and pooled; y names one of
 *            GR_CAMPAIGN_SPM_CIRCLE_QUANTITIES; `walks` and `walks_quick` the walks per radius.
 * CASCADE_FIELD D_f of S(k) (6.5) of the cascade fields themselves, every variant of sec. 6.2.1 on the
 *            thesis's 256 x 256 grid (Table 6.2), from independent seeds of `configurations` fields
 *            each; needs no run and no y. */
typedef enum {
    GR_RESULT_MEAN,
    GR_RESULT_POWER_LAW,
    GR_RESULT_RUNNING,
    GR_RESULT_RISE,
    GR_RESULT_SETTLE,
    GR_RESULT_CURVE,
    GR_RESULT_CASCADE,
    GR_RESULT_SPM,
    GR_RESULT_SPM_COMPARE,
    GR_RESULT_SPM_CIRCLE,
    GR_RESULT_CASCADE_FIELD,
    GR_RESULT_COLLAPSE
} gr_result_kind;
#define GR_CAMPAIGN_SPM_QUANTITIES                                                                 \
    "D_f, C, alpha, S_predicted, S, S_over_predicted, A0_over_P0, slope_P0, slope_A0"
#define GR_CAMPAIGN_SPM_COMPARE_QUANTITIES "frac_within, decades, k, s, alpha_spm, alpha_rfm"
#define GR_CAMPAIGN_SPM_CIRCLE_QUANTITIES "b, coefficient"
#define GR_CAMPAIGN_SPM_WALKS 200000     /* SPM_COMPARE's default walks per run, full fidelity */
#define GR_CAMPAIGN_SPM_WALKS_QUICK 5000 /* ... and quick */

typedef struct gr_campaign_result {
    char id[32]; /* e.g. "fig3.2", "table3.1" */
    char title[256];
    gr_result_kind kind;
    char quantity[64]; /* e.g. "xi_2", "zeta_m", "D_f" */
    char unit[32];
    char y[128]; /* dotted summary.json path; {m} and {m-1} are replaced by m (CURVE: a column) */
    char y_err
        [128];  /* the run's own error of y (used when a group has one seed) (CURVE: a column) */
    char x[64]; /* POWER_LAW: the varied key on the abscissa (CURVE: a column) */
    char table[64];  /* CURVE: the run's CSV, e.g. "gaps.csv" */
    char where[128]; /* CURVE: the rows used, "column=value, ..." */
    char
        select[256]; /* CURVE, MEAN: only the groups (curves, rows) with every "key=value" listed */
    char transform[32];  /* CURVE: "", "bisection_collapse" (thesis 3.39-3.40), "scale_at" (each
                           curve divided by its value at x_0 = collapse_at, Fig. 5.3's 5.4) or
                           "log_ratio" (y -> -ln(y / y(0)) for x > 0: the axes of Moon, Swift and
                           Swinney, Figs. 5.6-5.7, where y = exp(-c x^alpha) is a line of slope alpha)
                           or "moment_scale" (x -> x / M, y -> y M with M = <|v|^m>^(1/m) of the
                           run's moments, m = scale_moment: the collapse of Figs. 3.6-3.7) */
    double scale_moment; /* CURVE, moment_scale: the order m of the moment that scales v */
    double collapse_at;  /* CURVE: x_0 of the transform (bisection_collapse: every mapped curve
                           equals -ln x_0 there; scale_at: every curve is 1 there) */
    char axes[16]; /* CURVE: the figure's axes, "loglog" (default), "linlog" (log y) or "linear" */
    char
        overlay[32]; /* CURVE: "" or "bisection": beside every curve the uniform bisection process's
                             P_n(x) = (-ln x)^(n-1)/(n-1)! (3.36), n = log2 N, no parameter fitted;
                             "power_law": A x^overlay_exponent, A fitted to each curve over the window;
                             "column": the seed mean of the table's column overlay_y (a fit the
                             run wrote beside its curve), each drawn dashed in its curve's colour */
    double overlay_exponent; /* CURVE, overlay = power_law: the fixed exponent (-1.63 for S(k)) */
    char overlay_y[64];      /* CURVE, overlay = column: the column */
    char overlay_title[96];  /* CURVE: the key's words for the dashed lines */
    char x_label[96];        /* CURVE: the abscissa's label (default: the column's name) */
    double x_min, x_max;     /* POWER_LAW: fit window; SPM: the P(v) tail window in v / v_rms */
    char by[256];            /* POWER_LAW: comma-separated keys that label a fit */
    int m_lo, m_hi;          /* moments: m = m_lo..m_hi (0 = no {m}) */
    int m_step;              /* ... in steps of m_step (m = 3-12/3: 3, 6, 9, 12; 0 means 1) */
    bool per_m;              /* report exponent / m (Fig. 3.5) */
    bool
        local_slopes; /* POWER_LAW: also the exponent between every pair of neighbouring x (one row each) */
    int slope_span; /* POWER_LAW with local_slopes: also the exponent between x_i and x_i+span (0: none) */
    double period; /* RUNNING: seconds per period mean */
    int configurations; /* CASCADE: cascade placements averaged (default 20); CASCADE_FIELD: fields per seed */
    double df; /* SPM: D_f fixed for C, alpha and h (0: the run's free 4.25 fit) */
    double
        pl_max; /* SPM: the free-path tail is where P_l < pl_max per metre (0: 1, the thesis's) */
    bool
        tail_exponential; /* SPM: fit P(v)'s tail with A0 exp(-S |v|) (alpha = 1, h = 0: the thesis's
                              A0 of Fig. 5.13) instead of 5.31 at the predicted alpha and h */
    long walks,
        walks_quick; /* SPM_COMPARE: SPM walks per run, SPM_CIRCLE per radius, at full and quick fidelity (0: default) */
    char thesis[4096]; /* "GROUP: value +- error; ..." (GROUP as in results.csv) */
    char thesis_source[256];
    char note[2048];        /* what a reader should know (shown on the page) */
    char verdict[24];       /* where rows disagree (|z| > 2): "explained", "partly explained" or
                             "unexplained" ("" = not judged yet); the page's table of disagreements */
    char verdict_why[1024]; /* the verdict's one-paragraph reason */
    char compensate[32]; /* COLLAPSE: the power_law result of this campaign whose points, each times
                            x^(its group's exponent), are drawn against the group's value (Fig. 3.3) */
    char against[16]; /* COLLAPSE: the abscissa, "by" (the group's value b, default) or "1-by^2" */
    char restates
        [32]; /* the id of the result whose numbers this one restates in another form (S from C,
                             c from b): shown, but not counted again in the page's tallies */
} gr_campaign_result;

typedef struct gr_campaign_line {
    char section[16]; /* sweep, vary, set */
    char key[96];
    char value[512];
} gr_campaign_line;

typedef struct gr_campaign {
    char name[64];
    char source[1024]; /* where it was read from: "embedded docs/campaigns/NAME.ini" or a path */
    char title[256];
    char covers[256]; /* the figures and tables it serves, e.g. "Fig. 3.1, Fig. 3.2, Table 3.1" */
    char scene[128];  /* a scene of docs/scenes, e.g. "rfm-1d.ini" */
    char about[2048]; /* what is run and why (warm-up, run length, seeds), for the page */
    int n_lines[2];   /* the sweep body of each fidelity ([sweep.F], [vary.F], [set] + [set.F]) */
    gr_campaign_line lines[2][GR_CAMPAIGN_MAX_LINES];
    int n_results;
    gr_campaign_result results[GR_CAMPAIGN_MAX_RESULTS];
} gr_campaign;

/* Load a campaign by name (the compiled-in docs/campaigns/NAME.ini), by a figure or table it
 * covers ("fig3.2", "table3.1"), or from a file path. */
int gr_campaign_load(gr_campaign *c, const char *name_or_path, gr_error *err);
/* The names of the compiled-in campaigns, in order; returns how many (at most max). */
int gr_campaign_names(const char **names, int max);

/* Write DIR/scene.ini (the embedded scene) and DIR/sweep.ini (points into DIR/runs) for the
 * fidelity; sweep_path gets DIR/sweep.ini. Existing runs are kept: rerunning continues. */
int gr_campaign_materialise(const gr_campaign *c, gr_fidelity fid, const char *dir,
                            char *sweep_path, size_t len, gr_error *err);
/* Number of points of the fidelity's sweep (seeds x every [vary] list). */
long gr_campaign_points(const gr_campaign *c, gr_fidelity fid);

/* Read the finished points of DIR/runs and write RESULTS/results.csv, results.json, one data CSV
 * and one figure per result (the thesis's values overlaid), and archive every finished point in
 * RESULTS/points. *finished gets the finished points; notes (one per line, "" if none) what the
 * caller should tell the user (a figure not drawn, a point's SPM not run). */
int gr_campaign_analyse(const gr_campaign *c, gr_fidelity fid, const char *dir, const char *results,
                        long *finished, char *notes, size_t notes_len, gr_error *err);

/* Put the points archived in RESULTS/points back into DIR/runs where DIR has no finished run of
 * its own, so that the sweep runs only what is missing; *restored gets how many. */
int gr_campaign_restore(const char *dir, const char *results, long *restored, gr_error *err);

/* Generate the reproduction page (Markdown) at OUT_PATH, the overview, and one page per campaign,
 * RESULTS_ROOT/NAME/README.md, from every RESULTS_ROOT/NAME/results.json. */
int gr_reproduction_page(const char *results_root, const char *out_path, gr_error *err);

/* How one row of a result set (a results.json row: value, error, thesis, comparison, agrees, z)
 * compares with the thesis, as the page and `granule reproduce` print it: "z = -3.1", "-5.6 %:
 * differs from the stated 0.528", "inside 0.53 .. 0.667", "by construction", ... (`bold` marks
 * |z| > 2 and disagreements for Markdown). Returns true when the row counts as a disagreement. */
bool gr_campaign_comparison_text(const void *json_row, bool bold, char *out, size_t len);

#endif
