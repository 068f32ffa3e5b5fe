/* Comparisons: one scene, the same initial state and noise seed, run under several collision
 * models and integrators, and one table a physicist reads like a paper's (docs/compare.md).
 *
 * A model SPEC is NORMAL[+TANGENTIAL[+ROLLING]][@MODIFIER...], a modifier being `clamp`, `rotation` (the
 * discs rotate: model.rotation = true; without it false) or an integrator (`verlet`, `event`, `hybrid`): "spring_dashpot+tangential_dashpot@clamp", "spring_dashpot@hybrid",
 * "hard_sphere@event". Without an integrator, an event rule (hard_sphere) runs event-driven and a
 * force law runs with the scene's integrator (verlet if the scene is event-driven).
 *
 * The table (gr_compare_table_build) has a headline — T, the P(v) tail exponent, D_f (2D) or the
 * G_1 exponent (1D), collisions, energy by mechanism, wall time, throughput in the integrator's
 * unit — with units in the row names, "value +- error" in one cell and, where there is no number,
 * the reason ("n/a: 1D", "no collisions", "fit failed: ...") instead of nan. The full table
 * (every scalar of every summary.json) is written as compare.csv and compare.json. */
#ifndef GRANULE_COMPARE_H
#define GRANULE_COMPARE_H

#include <stdbool.h>
#include <stdio.h>

#include "granule/scene.h"
#include "granule/status.h"

#define GR_COMPARE_MAX 16   /* models in one comparison */
#define GR_COMPARE_ROWS 24  /* headline rows: 15 common, up to 5 of the system */
#define GR_COMPARE_CELL 112 /* characters of one headline cell */

typedef struct gr_compare_spec {
    char text[128];      /* as given */
    char label[128];     /* its folder under the comparison: '+' and '@' become '_' */
    char normal[64];     /* a normal law or an event rule */
    char tangential[64]; /* "" = none */
    char rolling[64];    /* "" = none; NORMAL+TANGENTIAL+ROLLING (needs @rotation) */
    bool clamp;
    bool
        rotation; /* @rotation: model.rotation = true (false without it, whatever the scene says) */
    int integrator; /* index into gr_integrators (granule/integrator.h), or -1 when the spec names none */
} gr_compare_spec;

/* Parse one SPEC. GR_EINVAL naming the spec and listing the valid names when the normal or
 * tangential model, a modifier or the integrator is unknown or given twice. */
int gr_compare_spec_parse(const char *text, gr_compare_spec *spec, gr_error *err);
/* Parse a comma-separated list into specs[0..*n); refuses more than `max`, an empty list and two
 * specs with the same folder label. */
int gr_compare_specs_parse(const char *list, gr_compare_spec *specs, int max, int *n,
                           gr_error *err);

/* Load scene_path with the --set assignments `sets`, then the spec's model and integrator, into
 * `scene` with out_dir = out/<label>. Errors are those of the scene loader, prefixed with the spec. */
int gr_compare_scene_load(const gr_compare_spec *spec, const char *scene_path,
                          const char *const *sets, int n_sets, const char *out, gr_scene *scene,
                          gr_error *err);

/* The first result of an earlier comparison in `out` (its tables or a model's run or checkpoint),
 * written to `what`; false when there is none. */
bool gr_compare_earlier(const char *out, const gr_compare_spec *specs, int n, char *what,
                        size_t what_size);

/* One headline cell: a number with its error (NAN when it has none), and the text shown — the
 * number formatted "value +- error", or the reason there is none. */
typedef struct gr_compare_cell {
    double value, error;
    char text[GR_COMPARE_CELL];
} gr_compare_cell;

/* What "+-" means in the headline (the table's footer, compare.csv's notes, docs/compare.md). */
#define GR_COMPARE_ERRORS                                                                          \
    "+-: T: one standard error of the time average (block averaging, Flyvbjerg-Petersen); alpha: " \
    "the "                                                                                         \
    "half-width of the accepted range (chi2/dof < 1.2 in the Table 5.1 window), or the free "      \
    "fit's one-sigma "                                                                             \
    "error (#); D_f, n_N: the fit's one-sigma error"

/* A cell's footnote mark ('*', '#') in words, as compare.csv's <key>_note carries it. */
const char *gr_compare_mark_words(char mark);

typedef struct gr_compare_row {
    char quantity[64]; /* words, with the unit: "T (m^2/s^2)" */
    char key[32];      /* its column in compare.csv */
    char unit[16]; /* the column's unit in compare.meta.json (UDUNITS-style, "1": a pure number) */
    gr_compare_cell cell[GR_COMPARE_MAX];
} gr_compare_row;

typedef struct gr_compare_table {
    char scene[1024];
    int dim;
    int n_models, n_rows;
    gr_compare_spec spec[GR_COMPARE_MAX];
    char integrator[GR_COMPARE_MAX][16];
    char kernel[GR_COMPARE_MAX][160];
    char status[GR_COMPARE_MAX][32]; /* summary.json's status, or "failed" without one */
    gr_compare_row row[GR_COMPARE_ROWS];
    char footnotes
        [1024]; /* one per line: the marks used in cells ("*: error bar not converged ...") */
    void *summaries
        [GR_COMPARE_MAX]; /* the parsed summary.json of each model (cJSON *), NULL if none */
} gr_compare_table;

/* Read out/<label>/summary.json of every spec and build the headline. `dim` is the scene's.
 * Returns NULL only when out of memory; free with gr_compare_table_free. */
gr_compare_table *gr_compare_table_build(const char *out, const char *scene_path, int dim,
                                         const gr_compare_spec *specs, int n);
void gr_compare_table_free(gr_compare_table *t);

/* Write out/compare.csv (one row per model: the headline numbers, their errors and reasons, then
 * every scalar of the summary, empty where a model has none), compare.json (the same, and the
 * headline as shown) and compare.md (the headline table and its footnotes). */
int gr_compare_table_write(const gr_compare_table *t, const char *out, gr_error *err);
/* The headline as an aligned text table (for a terminal). */
void gr_compare_table_print(const gr_compare_table *t, FILE *f);

/* The overlaid plots of a comparison: temperature.png (T(t) of every model) and, when the runs
 * have the pv observable, pv_collapse.csv/.png (the collapse (5.4)). Distinct colours and dash
 * types for up to 8 models, the legend below the data. Failures only fill `note`. */
void gr_compare_plots(const char *out, const gr_compare_spec *specs, int n, char *note,
                      size_t note_size);

/* "value +- error" with the error to two significant digits and the value to the same decimal
 * place ("0.2263 +- 0.0085", "(1.32 +- 0.11)e-03"); the value alone to 4 significant digits
 * when the error is not finite. */
void gr_compare_format(double value, double error, char *buf, size_t size);

#endif
