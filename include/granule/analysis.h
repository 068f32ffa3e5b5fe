/* Streaming statistics shared by every run: memory does not grow with run length. */
#ifndef GRANULE_ANALYSIS_H
#define GRANULE_ANALYSIS_H

#include <stdint.h>

#define GR_BLOCKING_LEVELS 48

/* Block averaging (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989)) of a correlated time
 * series, accumulated on the fly: level k sees the means of blocks of 2^k consecutive samples.
 * The standard error of the mean is read off where it stops growing with the block size. */
typedef struct gr_blocking {
    int64_t count[GR_BLOCKING_LEVELS];  /* completed blocks per level */
    double sum[GR_BLOCKING_LEVELS], sum2[GR_BLOCKING_LEVELS];
    double pending[GR_BLOCKING_LEVELS]; /* first half of a block waiting for its partner */
    int has_pending[GR_BLOCKING_LEVELS];
} gr_blocking;

void gr_blocking_init(gr_blocking *b);
void gr_blocking_add(gr_blocking *b, double x);
double gr_blocking_mean(const gr_blocking *b);
/* Standard error of the mean at level k (blocks of 2^k samples); NAN with fewer than 2 blocks. */
double gr_blocking_stderr_at(const gr_blocking *b, int level);
/* Conservative estimate: the largest level-k error among levels with at least 16 blocks (the
 * plateau for a series much longer than its correlation time; an underestimate otherwise, which
 * `*converged` reports as 0 when the error still grows at the last usable levels). */
double gr_blocking_stderr(const gr_blocking *b, int *level, int *converged);

#endif
