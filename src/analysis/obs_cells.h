/* Pairs of particles closer than a cut-off in one frame, for the observables
 * that need them (vcorr, clusters, pressure): a cell list over the periodic cube
 * (3D), box (2D) or ring (1D) with cells of side >= r_cut, minimum image; a brute-force
 * double loop when fewer than 3 cells fit per side. Each unordered pair is
 * visited once with the separation r_j - r_i (minimum image). */
#ifndef GR_OBS_CELLS_H
#define GR_OBS_CELLS_H

#include "granule/particles.h"
#include "granule/status.h"

/* dr: the separation r_j - r_i (minimum image), dr[1] = 0 in 1D, dr[2] = 0 except in 3D. */
typedef void (*gr_pair_visit)(int i, int j, const double dr[3], double r2, void *user);

typedef struct gr_cells {
    int cap_n, cap_cells;
    int *head, *next; /* linked lists per cell */
} gr_cells;

/* Visit every pair with |r_ij| < r_cut (r_cut <= L/2). `cells` is a reusable
 * workspace, zero-initialised before the first call and released with
 * gr_cells_free. */
int gr_cells_pairs(gr_cells *cells, const gr_particles *p, double r_cut, gr_pair_visit visit,
                   void *user, gr_error *err);
void gr_cells_free(gr_cells *cells);
/* Free the cells (grown by gr_cells_pairs) with an observable's state (obs_util.h, gr_obs_own). */
void gr_cells_own(void *state, gr_cells *cells);

#endif
