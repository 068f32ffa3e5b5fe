#ifndef GR_SNAPSHOT_H
#define GR_SNAPSHOT_H

#include <stdint.h>
#include <stdio.h>

#include "granule/sim.h"

/* Extended-XYZ frames (docs/trajectories.md): the layout ASE 3.22, OVITO and granule read.
 * Species X (ASE's dummy element), SI units; Lattice with the box side(s) and the particle
 * diameter d for each unused direction (2D: z; 1D: y and z) with pbc F there; unused
 * coordinates sit in the middle of that slab (d/2);
 * Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:masses:R:1:momenta:R:3 (velo for OVITO and
 * granule, masses and momenta = masses * velo so ASE's get_velocities() is right). A frame with
 * species (docs/mixtures.md) has each grain's own radius and masses and a last column
 * species_index:I:1 (1, 2, ...: ASE's atoms.arrays["species_index"]). */

/* Write one frame (time t, step count `step`) to f; 2D positions wrapped into [0, L). */
void gr_xyz_write_frame(FILE *f, const gr_particles *p, double t, int64_t step);

/* Write dir/snap_<index>.xyz (one frame, atomically). */
int gr_snapshot_write(const char *dir, int index, const gr_particles *p, double t, int64_t step,
                      gr_error *err);

/* A frame read back from an extended-XYZ snapshot (or an H5MD trajectory). */
typedef struct gr_frame {
    int n, dim;
    double L, t, radius;
    double *x, *y, *vx, *vy;
    double *z, *vz; /* dim = 3 only (NULL otherwise) */
    /* a mixture's frame (a species_index column, docs/mixtures.md): each particle's species 0, 1,
     * ..., radius and mass, and the number of species (the largest index); NULL and 0 without */
    int *species;
    double *radii, *masses;
    int n_species;
} gr_frame;

/* Read the next frame of `in` into f (arrays allocated here; dim 1 when pbc = "T F F", 3 when
 * pbc = "T T T"). Accepts
 * any Properties with pos and velo (or momenta and masses); radius optional. *line_no counts the
 * lines read so far (for messages naming path:line). Returns GR_OK, GR_EINVAL/GR_ENOMEM with a
 * message, or 1 at a clean end of file. */
int gr_xyz_read_frame(FILE *in, const char *path, long *line_no, gr_frame *f, gr_error *err);
/* Read the single-frame file path into f. */
int gr_snapshot_read(const char *path, gr_frame *f, gr_error *err);
int gr_frame_alloc(gr_frame *f, int n, int dim, gr_error *err);
void gr_frame_free(gr_frame *f);

#endif
