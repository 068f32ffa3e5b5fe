/* Helpers shared by the observables: mean velocity of a frame, CSV files with the standard
 * commented header, plots. */
#ifndef GR_OBS_UTIL_H
#define GR_OBS_UTIL_H

#include <stdio.h>

#include <cjson/cJSON.h>

#include "granule/analysis.h"
#include "granule/observe.h"
#include "io/files.h"

struct gr_lag;

void gr_obs_mean_velocity(const gr_particles *p, double mean[2]);
/* Open out->dir/name atomically and write the header "# granule <what>\n# scene ..., hash, seed". */
int gr_obs_csv_open(const gr_output *out, const char *name, const char *what, gr_file *f, gr_error *err);
/* Draw out->dir/png with a gnuplot body run inside out->dir; failures only add a note to the
 * summary (plots are a convenience, the CSV is the result). */
void gr_obs_plot(const gr_output *out, const char *png, const char *body);

/* The rows of one CSV table, written to f. */
typedef void (*gr_obs_rows)(FILE *f, const void *ctx);

/* One result table of an observable: a CSV file and, optionally, its plot. */
typedef struct gr_obs_table {
    const char *name;    /* CSV file in out->dir */
    const char *what;    /* the header's description (gr_obs_csv_open) */
    const char *columns; /* the column line with units, "name [unit],..." (gr_file_header) */
    gr_obs_rows rows;
    const void *ctx;
    const char *png;     /* NULL: no plot */
    const char *plot;    /* gnuplot body, drawn when the CSV was written and out->plots is set */
} gr_obs_table;

/* Rows of a histogram (gr_histogram_write_rows): ctx is the gr_histogram. */
void gr_obs_histogram_rows(FILE *f, const void *ctx);

/* gr_obs_csv_open, the column line, the rows, commit; then the plot (gr_obs_plot). */
int gr_obs_table_write(const gr_output *out, const gr_obs_table *t, gr_error *err);
/* The error of a time average: the blocking plateau, or with fewer than 16 samples the naive
 * standard error of the samples (NAN with fewer than 2). */
double gr_obs_stderr(const gr_blocking *b);
/* The observable's member of the summary: an object `key` holding "file": file first. */
cJSON *gr_obs_summary(const gr_output *out, const char *key, const char *file);
/* GR_EINVAL unless the frame has the scene's n particles (observables keeping per-particle state). */
int gr_obs_check_frame(const char *name, const gr_particles *p, int n, gr_error *err);
struct gr_blob;
struct gr_blob_reader;
/* Checkpoints: n blocking accumulators in a row. */
void gr_obs_put_blockings(struct gr_blob *out, const gr_blocking *b, int n);
void gr_obs_get_blockings(struct gr_blob_reader *in, gr_blocking *b, int n);
/* A number, or null when it is not finite (JSON has no nan). */
void gr_obs_add_number(cJSON *o, const char *name, double v);
/* A lag table (obs_lag.h) as CSV: tau (s), mean, block-averaging error, origins; and into `j`
 * "file", "interval" (s) and "samples". */
int gr_obs_lag_csv(const gr_output *out, const struct gr_lag *lag, const char *name, const char *what,
                   const char *columns, cJSON *j, gr_error *err);

#endif
