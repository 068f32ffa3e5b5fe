/* Histograms as probability densities with sqrt(X) errors (thesis App. A.1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"

int gr_histogram_init(gr_histogram *h, int nbins, double lo, double hi, bool log_bins,
                      gr_error *err)
{
    memset(h, 0, sizeof *h);
    if (nbins < 1 || !(hi > lo) || (log_bins && !(lo > 0.0)) || !isfinite(lo) || !isfinite(hi)) {
        return GR_FAIL(err, GR_EINVAL,
                       "histogram: need nbins >= 1 and lo < hi (lo > 0 for log bins); got %d bins "
                       "on [%g, %g)%s",
                       nbins, lo, hi, log_bins ? " log" : "");
    }
    h->count = calloc((size_t)nbins, sizeof(double));
    if (!h->count) {
        return GR_FAIL(err, GR_ENOMEM, "histogram: out of memory for %d bins", nbins);
    }
    h->nbins = nbins;
    h->lo = lo;
    h->hi = hi;
    h->log_bins = log_bins;
    return GR_OK;
}

void gr_histogram_free(gr_histogram *h)
{
    free(h->count);
    h->count = NULL;
}

void gr_histogram_add(gr_histogram *h, double x, double weight)
{
    h->total += weight;
    if (!(x >= h->lo)) {
        h->below += weight;
        return;
    }
    if (!(x < h->hi)) {
        h->above += weight;
        return;
    }
    double u = h->log_bins ? log(x / h->lo) / log(h->hi / h->lo) : (x - h->lo) / (h->hi - h->lo);
    int i = (int)(u * h->nbins);
    i = i < 0 ? 0 : (i >= h->nbins ? h->nbins - 1 : i);
    h->count[i] += weight;
}

int gr_histogram_merge(gr_histogram *into, const gr_histogram *from, gr_error *err)
{
    if (into->nbins != from->nbins || into->lo != from->lo || into->hi != from->hi ||
        into->log_bins != from->log_bins) {
        return GR_FAIL(err, GR_EINVAL, "histogram merge: binnings differ");
    }
    for (int i = 0; i < into->nbins; i++) {
        into->count[i] += from->count[i];
    }
    into->below += from->below;
    into->above += from->above;
    into->total += from->total;
    return GR_OK;
}

double gr_histogram_lower(const gr_histogram *h, int i)
{
    double u = (double)i / h->nbins;
    return h->log_bins ? h->lo * pow(h->hi / h->lo, u) : h->lo + u * (h->hi - h->lo);
}

double gr_histogram_upper(const gr_histogram *h, int i) { return gr_histogram_lower(h, i + 1); }

double gr_histogram_center(const gr_histogram *h, int i)
{
    double a = gr_histogram_lower(h, i), b = gr_histogram_upper(h, i);
    return h->log_bins ? sqrt(a * b) : 0.5 * (a + b);
}

double gr_histogram_density(const gr_histogram *h, int i)
{
    double w = gr_histogram_upper(h, i) - gr_histogram_lower(h, i);
    return h->total > 0.0 ? h->count[i] / (h->total * w) : 0.0;
}

double gr_histogram_density_error(const gr_histogram *h, int i)
{
    double w = gr_histogram_upper(h, i) - gr_histogram_lower(h, i);
    return h->total > 0.0 ? sqrt(h->count[i]) / (h->total * w) : 0.0;
}

void gr_histogram_write_csv(const gr_histogram *h, FILE *f, const char *xname)
{
    fprintf(f, "%s_lo,%s_hi,%s,count,density,density_error\n", xname, xname, xname);
    gr_histogram_write_rows(h, f);
}

void gr_histogram_write_rows(const gr_histogram *h, FILE *f)
{
    for (int i = 0; i < h->nbins; i++) {
        fprintf(f, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", gr_histogram_lower(h, i),
                gr_histogram_upper(h, i), gr_histogram_center(h, i), h->count[i],
                gr_histogram_density(h, i), gr_histogram_density_error(h, i));
    }
}
