/* Streaming block averaging for the time-averaged temperature and its error bar (2.20, Fig. 2.8). */
#include <math.h>
#include <string.h>

#include "granule/analysis.h"

void gr_blocking_init(gr_blocking *b) { memset(b, 0, sizeof *b); }

void gr_blocking_add(gr_blocking *b, double x)
{
    for (int k = 0; k < GR_BLOCKING_LEVELS; k++) {
        b->count[k]++;
        b->sum[k] += x;
        b->sum2[k] += x * x;
        if (!b->has_pending[k]) {
            b->pending[k] = x;
            b->has_pending[k] = 1;
            return;
        }
        x = 0.5 * (x + b->pending[k]);
        b->has_pending[k] = 0;
    }
}

double gr_blocking_mean(const gr_blocking *b)
{
    return b->count[0] ? b->sum[0] / (double)b->count[0] : (double)NAN;
}

double gr_blocking_stderr_at(const gr_blocking *b, int level)
{
    int64_t n = b->count[level];
    if (n < 2) {
        return NAN;
    }
    double mean = b->sum[level] / (double)n;
    double var = (b->sum2[level] / (double)n - mean * mean) * (double)n / (double)(n - 1);
    return sqrt(fmax(var, 0.0) / (double)n);
}

double gr_blocking_stderr(const gr_blocking *b, int *level, int *converged)
{
    double best = NAN;
    int best_level = 0, last = -1;
    for (int k = 0; k < GR_BLOCKING_LEVELS && b->count[k] >= 16; k++) {
        double e = gr_blocking_stderr_at(b, k);
        if (isnan(best) || e > best) {
            best = e;
            best_level = k;
        }
        last = k;
    }
    if (level) {
        *level = best_level;
    }
    if (converged) {
        /* converged when the maximum is not at the last usable level */
        *converged = last >= 2 && best_level < last;
    }
    return best;
}
