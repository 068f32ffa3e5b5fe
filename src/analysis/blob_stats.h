/* Checkpoint blobs with the analysis layer's accumulators: the core's byte buffer
 * (src/core/blob.h) plus block averages and histograms (src/analysis/blob_stats.c). */
#ifndef GR_BLOB_H
#define GR_BLOB_H

#include "core/blob.h"
#include "granule/analysis.h"

void gr_blob_put_blocking(gr_blob *b, const gr_blocking *k);
/* Counts only (the binning is checked against the one re-created from the scene on load). */
void gr_blob_put_histogram(gr_blob *b, const gr_histogram *h);
bool gr_blob_get_blocking(gr_blob_reader *r, gr_blocking *k);
/* Into a histogram already initialised with the same number of bins. */
bool gr_blob_get_histogram(gr_blob_reader *r, gr_histogram *h);
/* Into an uninitialised histogram: the stored binning (linear or log as given) is re-created
 * (for accumulators whose range is fixed from the first frames). */
bool gr_blob_get_histogram_new(gr_blob_reader *r, gr_histogram *h, bool log_bins);

#endif
