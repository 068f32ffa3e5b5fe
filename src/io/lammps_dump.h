/* Reader of LAMMPS text dump files (dump custom) for `granule analyse --lammps-dump`. */
#ifndef GR_LAMMPS_DUMP_H
#define GR_LAMMPS_DUMP_H

#include "io/snapshot.h"

typedef struct gr_lammps_dump gr_lammps_dump;

/* dim: the scene's dimension; 3 reads z and vz too (and needs a cube), 1 and 2 take the dimension
 * from the columns. */
int gr_lammps_dump_open(const char *path, int dim, gr_lammps_dump **out, gr_error *err);
/* Read the next frame into f (arrays allocated here, free with gr_frame_free), particles in the
 * order of their atom ids 1..n. Columns are found by name: id, x (or xu, xs), vx, and in 2D y and
 * vy; z and vz (a LAMMPS 2D run still writes them) are ignored except for a 3D scene, which needs
 * them (z, zu or zs; vz). Positions are shifted by the box's
 * lower bounds and wrapped into [0, L); f->t = timestep * dt. The box must be orthogonal and, in
 * 2D, square, or a square box one of whose axes reaches below 0 (a wall axis with a floor
 * vibrating below 0, as `granule export lammps` writes it): that axis is read unshifted and
 * unwrapped. Returns 1 with a frame, 0 at the end of the file, a negative status on an error
 * that names the file and line. */
int gr_lammps_dump_next(gr_lammps_dump *d, double dt, gr_frame *f, gr_error *err);
void gr_lammps_dump_close(gr_lammps_dump *d);

#endif
