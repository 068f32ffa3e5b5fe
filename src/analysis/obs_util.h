/* Helpers shared by the observables: mean velocity of a frame, CSV files with the standard
 * commented header, plots. */
#ifndef GR_OBS_UTIL_H
#define GR_OBS_UTIL_H

#include "granule/observe.h"
#include "io/files.h"

void gr_obs_mean_velocity(const gr_particles *p, double mean[2]);
/* Open out->dir/name atomically and write the header "# granule <what>\n# scene ..., hash, seed". */
int gr_obs_csv_open(const gr_output *out, const char *name, const char *what, gr_file *f, gr_error *err);
/* Draw out->dir/png with a gnuplot body run inside out->dir; failures only add a note to the
 * summary (plots are a convenience, the CSV is the result). */
void gr_obs_plot(const gr_output *out, const char *png, const char *body);

#endif
