/* Checkpoint blobs of the analysis layer's accumulators (block averages, histograms), on top of
 * the core's byte buffer (src/core/blob.c). */
#include <string.h>

#include "analysis/blob_stats.h"

void gr_blob_put_blocking(gr_blob *b, const gr_blocking *k)
{
    gr_blob_put(b, k->count, sizeof k->count);
    gr_blob_put(b, k->sum, sizeof k->sum);
    gr_blob_put(b, k->sum2, sizeof k->sum2);
    gr_blob_put(b, k->pending, sizeof k->pending);
    for (int i = 0; i < GR_BLOCKING_LEVELS; i++) {
        unsigned char c = (unsigned char)(k->has_pending[i] != 0);
        gr_blob_put(b, &c, 1);
    }
}

void gr_blob_put_histogram(gr_blob *b, const gr_histogram *h)
{
    gr_blob_put_u64(b, (uint64_t)h->nbins);
    gr_blob_put_f64(b, h->lo);
    gr_blob_put_f64(b, h->hi);
    gr_blob_put(b, h->count, sizeof(double) * (size_t)h->nbins);
    gr_blob_put_f64(b, h->below);
    gr_blob_put_f64(b, h->above);
    gr_blob_put_f64(b, h->total);
}

bool gr_blob_get_blocking(gr_blob_reader *r, gr_blocking *k)
{
    gr_blob_get(r, k->count, sizeof k->count);
    gr_blob_get(r, k->sum, sizeof k->sum);
    gr_blob_get(r, k->sum2, sizeof k->sum2);
    gr_blob_get(r, k->pending, sizeof k->pending);
    for (int i = 0; i < GR_BLOCKING_LEVELS; i++) {
        unsigned char c = 0;
        gr_blob_get(r, &c, 1);
        k->has_pending[i] = c != 0;
    }
    return !r->bad;
}

bool gr_blob_get_histogram(gr_blob_reader *r, gr_histogram *h)
{
    uint64_t nb = gr_blob_get_u64(r);
    double lo = gr_blob_get_f64(r), hi = gr_blob_get_f64(r);
    if (!r->bad && (nb != (uint64_t)h->nbins || lo != h->lo || hi != h->hi)) {
        gr_blob_fail(r,
                     "histogram of %llu bins on [%g, %g) where the scene gives %d bins on [%g, %g)",
                     (unsigned long long)nb, lo, hi, h->nbins, h->lo, h->hi);
    }
    if (r->bad) {
        return false;
    }
    gr_blob_get(r, h->count, sizeof(double) * (size_t)h->nbins);
    h->below = gr_blob_get_f64(r);
    h->above = gr_blob_get_f64(r);
    h->total = gr_blob_get_f64(r);
    return !r->bad;
}

bool gr_blob_get_histogram_new(gr_blob_reader *r, gr_histogram *h, bool log_bins)
{
    memset(h, 0, sizeof *h);
    uint64_t nb = gr_blob_get_u64(r);
    double lo = gr_blob_get_f64(r), hi = gr_blob_get_f64(r);
    if (r->bad) {
        return false;
    }
    if (nb < 1 || nb > (r->len - r->pos) / sizeof(double)) {
        gr_blob_fail(r, "histogram of %llu bins does not fit in the section",
                     (unsigned long long)nb);
        return false;
    }
    gr_error e = {0};
    if (gr_histogram_init(h, (int)nb, lo, hi, log_bins, &e) != GR_OK) {
        gr_blob_fail(r, "%s", e.message);
        return false;
    }
    r->pos -= 8 + 8 + 8; /* read it again through the checked path */
    return gr_blob_get_histogram(r, h);
}
