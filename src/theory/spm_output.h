/* Shared pieces of the SPM studies' output folders (spm_circle_study.c, spm_full_study.c,
 * spm_predict_study.c): CSV headers, summary.json fields, plots. Internal to the library. */
#ifndef GR_SPM_OUTPUT_H
#define GR_SPM_OUTPUT_H

#include <cjson/cJSON.h>
#include <stdbool.h>

#include "granule/spm.h"
#include "granule/spm_study.h"
#include "io/files.h"

/* "# granule VERSION (COMMIT) spm: what" and the settings line */
void gr_spm_csv_head(gr_file *f, const char *what, const gr_spm_settings *s);
/* {"mode", "granule_version", "commit"} */
cJSON *gr_spm_json_head(const char *mode);
void gr_spm_json_settings(cJSON *j, const gr_spm_settings *s, int bins);
/* a number, or null when not finite */
void gr_spm_json_num(cJSON *o, const char *key, double v);
/* the walk statistics, <w^2> with its error, and c, c' ("constants") */
void gr_spm_json_stats(cJSON *o, const gr_spm_walk_stats *st);
/* {"constants": {convention, c, c_err, c_prime, c_prime_err[, note]}} */
void gr_spm_json_constants(cJSON *o, const gr_spm_constants *c, const char *note);
/* the fit of 4.25 to a P_l table: l_from, l_to, D_f, C, their errors, chi2_red, points */
void gr_spm_json_pl_fit(cJSON *t, const gr_spm_pl_fit *f);
/* Draw a plot into dir when `plots`; list it in j's "plots", or note why not in "plot_notes". */
void gr_spm_plot(const char *dir, bool plots, cJSON *j, const char *png, const char *body);
/* The k-th line colour of the SPM plots, "#rrggbb" (colour-blind safe, no yellow; cycles). */
const char *gr_spm_colour(int k);
/* monotonic seconds */
double gr_spm_clock(void);

#endif
