#ifndef GR_SNAPSHOT_H
#define GR_SNAPSHOT_H

#include "granule/sim.h"

/* Write dir/snap_<index>.xyz (extended XYZ; 1D particles lie on the line y = 0.5). */
int gr_snapshot_write(const char *dir, int index, const gr_particles *p, double t, gr_error *err);

/* A frame read back from an extended-XYZ snapshot written by gr_snapshot_write (or any file with
 * the same Lattice/Time/Properties=species:S:1:pos:R:3:velo:R:3[:radius:R:1] layout). */
typedef struct gr_frame {
    int n, dim;
    double L, t, radius;
    double *x, *y, *vx, *vy;
} gr_frame;

/* Read path into f (arrays allocated here; dim taken from pbc "T F F" = 1D). Errors name the file
 * and line. */
int gr_snapshot_read(const char *path, gr_frame *f, gr_error *err);
void gr_frame_free(gr_frame *f);

#endif
