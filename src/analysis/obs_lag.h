/* Time correlations over a window of recent frames, shared by msd and vacf: a
 * ring of the last `lags` frames (2 components per particle, 3 in 3D), so memory is N *
 * lags and does not grow with the run. Each new frame s is paired with the
 * frames s - l, l = 0 .. min(lags, s), and the particle average of f(frame s,
 * frame s - l) is added to a block-averaging accumulator of lag l: every sample
 * is a time origin (origins at s - l). */
#ifndef GR_OBS_LAG_H
#define GR_OBS_LAG_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/analysis.h"
#include "granule/sim.h"
#include "granule/status.h"

#define GR_LAG_MAX 2000 /* most lags an observable may keep */

typedef enum { GR_LAG_DISPLACEMENT2, GR_LAG_DOT } gr_lag_kind;

typedef struct gr_lag {
    int n, dim, lags;
    gr_lag_kind kind; /* |a(s) - a(s-l)|^2 (msd) or a(s) . a(s-l) (vacf) */
    double *ring;     /* (lags + 1) frames of stride n values, slot s % (lags + 1) */
    int64_t frames;
    double t_first, t_last;
    gr_blocking *acc; /* lags + 1 accumulators */
    /* a mixture (gr_lag_species; ns = 0 without): the particle average of each species, acc_s[(lags
     * + 1) a + l], over its count[a] particles (the first frame's) */
    int ns;
    int count[GR_MAX_SPECIES];
    gr_blocking *acc_s;
} gr_lag;

int gr_lag_init(gr_lag *g, int n, int dim, int lags, gr_lag_kind kind, gr_error *err);
void gr_lag_free(gr_lag *g);
/* Values per particle in the ring: 3 in 3D, else 2 (1D keeps a zero second component). */
static inline int gr_lag_stride(const gr_lag *g) { return g->dim == 3 ? 3 : 2; }
/* One frame of n values per component (b is NULL in 1D, c is read in 3D only) at time t. */
int gr_lag_add(gr_lag *g, const double *a, const double *b, const double *c, double t,
               gr_error *err);
/* A mixture of ns species (2 .. GR_MAX_SPECIES): also average each species' particles; frames then
 * come with gr_lag_add_species. */
int gr_lag_species(gr_lag *g, int ns, gr_error *err);
/* gr_lag_add with each particle's species (0 .. ns - 1; `what` names the observable for the
 * message when the frame's species do not fit): the total is gr_lag_add's, bit for bit. */
int gr_lag_add_species(gr_lag *g, const char *what, const gr_particles *p, const double *a,
                       const double *b, const double *c, double t, gr_error *err);
/* Species a's lags as a gr_lag to read (gr_lag_mean, gr_lag_fit_line; not to add to). */
gr_lag gr_lag_species_view(const gr_lag *g, int a);
/* Mean interval between frames (0 before the second frame). */
double gr_lag_interval(const gr_lag *g);
/* Mean and block-averaging error at lag l; samples = origins seen. */
double gr_lag_mean(const gr_lag *g, int l, double *stderr_out, int64_t *samples);
/* A weighted straight-line fit y = p0 + p1 tau over lags lo .. hi (those with
 * >= 2 origins); 0 on success. */
int gr_lag_fit_line(const gr_lag *g, int lo, int hi, gr_fit *fit, gr_error *err);

/* gr_lag_init for a gr_lag inside an observable's state, freed with the state (gr_obs_own). */
int gr_lag_init_owned(void *state, gr_lag *g, int n, int dim, int lags, gr_lag_kind kind,
                      gr_error *err);

struct gr_blob_io;
/* Checkpoints: the ring, the times and the accumulators (obs_util.h, gr_blob_io); `what` names the
 * scene key fixing the number of lags, for the message when a checkpoint disagrees. */
void gr_lag_io(struct gr_blob_io *io, gr_lag *g, const char *what);

#endif
