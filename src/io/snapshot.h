#ifndef GR_SNAPSHOT_H
#define GR_SNAPSHOT_H

#include "granule/sim.h"

/* Write dir/snap_<index>.xyz (extended XYZ; 1D particles lie on the line y = 0.5). */
int gr_snapshot_write(const char *dir, int index, const gr_particles *p, double t, gr_error *err);

#endif
