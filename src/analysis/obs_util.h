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

/* The frame's mean velocity per component (mean[1] = 0 in 1D, mean[2] = 0 except in 3D). */
void gr_obs_mean_velocity(const gr_particles *p, double mean[3]);
/* Open out->dir/name atomically and write the header "# granule <what>\n# scene ..., hash, seed". */
int gr_obs_csv_open(const gr_output *out, const char *name, const char *what, gr_file *f,
                    gr_error *err);
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
    const char *png;  /* NULL: no plot */
    const char *plot; /* gnuplot body, drawn when the CSV was written and out->plots is set */
} gr_obs_table;

/* The column lines of the tables a campaign's curve result reads (docs/campaigns/README.md), and
 * the unit a column has in its table: copied to buf (size len), or NULL for a table or column not
 * listed. `granule reproduce` gives its data tables' x and y these units (ID_data.meta.json). */
extern const char gr_obs_gaps_columns[], gr_obs_sk_columns[], gr_obs_pair_columns[],
    gr_obs_freepath_columns[], gr_obs_pv_columns[], gr_obs_postcollision_columns[];
const char *gr_obs_column_unit(const char *table, const char *column, char *buf, size_t len);

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
/* A mixture's frame (docs/mixtures.md): its grains' species copied into species[0..n) (unless NULL), GR_EINVAL
 * naming the observable unless the frame carries ns species (each in [0, ns)) of n grains. */
int gr_obs_frame_species(const char *name, const gr_particles *p, int ns, int n, int *species,
                         gr_error *err);
/* The note of an observable that takes contact events and saw none: "no <what>: none happened,
 * or the frames came from snapshots (granule analyse has no contact events)". */
void gr_obs_note_no_events(cJSON *j, const char *what);
/* A number, or null when it is not finite (JSON has no nan). */
void gr_obs_add_number(cJSON *o, const char *name, double v);
/* A lag table (obs_lag.h) as CSV: tau (s), mean, block-averaging error, origins; and into `j`
 * "file", "interval" (s) and "samples". */
int gr_obs_lag_csv(const gr_output *out, const struct gr_lag *lag, const char *name,
                   const char *what, const char *columns, cJSON *j, gr_error *err);

/* ------------------------------------------------------------------------------------------
 * The skeleton (src/analysis/observe.c): what an observable's init allocates through these is
 * freed by gr_observable_free, in reverse order, so observables have no destroy of their own. */

/* Zeroed memory for n elements of `size` bytes, owned by the state (NULL when out of memory;
 * gr_obs_alloc_ok then reports it, so init may check once after all its allocations). */
void *gr_obs_calloc(void *state, size_t n, size_t size);
/* Hand `obj` to the state: release(obj) runs when the state is freed (at once if this fails). */
bool gr_obs_own(void *state, void (*release)(void *obj), void *obj);
/* GR_ENOMEM naming the observable if any allocation above failed, else GR_OK. */
int gr_obs_alloc_ok(const void *state, gr_error *err);
/* gr_histogram_init of a histogram inside the state, freed with it. A histogram filled later
 * (gr_histogram_init or gr_blob_get_histogram_new from sample or io) is registered with
 * gr_obs_own_histogram while still zeroed, at init. */
int gr_obs_histogram(void *state, gr_histogram *h, int nbins, double lo, double hi, bool log_bins,
                     gr_error *err);
void gr_obs_own_histogram(void *state, gr_histogram *h);
/* A pointer field of the state that sample may grow with realloc: freed with the state. */
void gr_obs_own_pointer(void *state, void *pointer_field);

/* ------------------------------------------------------------------------------------------
 * Checkpoints: an observable's `io` lists its accumulators once; the same calls append them to
 * the blob (saving) or read them back (loading). A failed read marks the reader bad (the whole
 * load then fails with its message), and every later call does nothing. */
#include "core/blob.h" /* gr_blob_io: the primitives */

/* n species indices (gr_obs_frame_species), each checked in [0, ns) on load. */
void gr_obs_io_species(gr_blob_io *io, const char *name, int *species, int n, int ns);
/* n blocking accumulators in a row. */
void gr_obs_io_blockings(gr_blob_io *io, gr_blocking *b, int n);
/* The counts of a histogram initialised alike (its binning comes from the scene). */
void gr_obs_io_histogram(gr_blob_io *io, gr_histogram *h);
/* A histogram whose binning is fixed from the first frames (pv, postcollision): saved with its
 * binning, loaded into an uninitialised histogram re-created with the stored binning (false if
 * that failed). */
bool gr_obs_io_histogram_new(gr_blob_io *io, gr_histogram *h);
/* A size fixed by the scene (a number of bins, lags, particles): stored, and on load it must
 * equal `value` ("<what> = <stored> in the checkpoint, <value> in the scene"). */
void gr_blob_io_check(gr_blob_io *io, const char *what, int64_t value);

/* A mixture's species pairs a <= b (sk's partial structure factors, vcorr's pair kinds), in the
 * order 11, 12, .., 1 ns, 22, .., ns ns. */
#define GR_OBS_MAX_PAIRS (GR_MAX_SPECIES * (GR_MAX_SPECIES + 1) / 2)
typedef struct gr_obs_pairs {
    int n; /* ns (ns + 1) / 2 */
    int a[GR_OBS_MAX_PAIRS], b[GR_OBS_MAX_PAIRS];
    int of[GR_MAX_SPECIES *
           GR_MAX_SPECIES];          /* the pair of species (a, b), and (b, a), at [a ns + b] */
    char label[GR_OBS_MAX_PAIRS][4]; /* "11", "12", ..: the species numbered from 1 */
} gr_obs_pairs;
void gr_obs_pairs_init(gr_obs_pairs *pairs, int ns);
/* The summary's array "species_pairs" of the labels. */
void gr_obs_pairs_summary(const gr_obs_pairs *pairs, cJSON *j);

/* A mixture's summary: the length its lengths are in units of (gr_obs_collision_diameter) and why. */
void gr_obs_note_diameter(cJSON *j, double d, int dim);

#endif
