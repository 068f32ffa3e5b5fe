/* H5MD trajectories (https://www.nongnu.org/h5md/, version 1.1) through the HDF5 C library:
 * positions, velocities, optional angular velocities, the box, time and step of every frame,
 * appended one frame at a time to chunked, deflate-compressed datasets. Layout and what readers
 * make of it: docs/trajectories.md. */
#ifndef GR_H5MD_H
#define GR_H5MD_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/particles.h"
#include "granule/status.h"
#include "io/snapshot.h"

typedef struct gr_h5md gr_h5md;

/* What a file holds; fixed when it is created. */
typedef struct gr_h5md_desc {
    int n, dim;
    double L, radius, mass; /* m, m, kg */
    bool angular_velocity;  /* an angular_velocity element (rad/s, 3 components per particle) */
    int deflate;            /* deflate level 0-9 */
    /* a mixture (docs/mixtures.md): each particle's species 0, 1, ..., radius (m) and mass (kg),
     * written as /particles/all/species (1, 2, ...), radius and mass; NULL for one species */
    const int *species;
    const double *radii, *masses;
    int n_species;
} gr_h5md_desc;

/* Create path (replacing it) with no frames. */
int gr_h5md_create(const char *path, const gr_h5md_desc *d, gr_h5md **out, gr_error *err);
/* Reopen path to append after its first `keep` frames (frames after them are cut: a resume
 * from a checkpoint taken when `keep` frames were written). Refuses a file with fewer frames
 * or another particle count. */
int gr_h5md_reopen(const char *path, int64_t keep, int n, gr_h5md **out, gr_error *err);
/* Append one frame; omega (n values, rad/s about z) only when the file has angular velocities,
 * else NULL. The file is flushed after the frame: a killed run leaves every frame appended
 * before the last flush readable. */
int gr_h5md_append(gr_h5md *h, const gr_particles *p, const double *omega, double t, int64_t step,
                   gr_error *err);
/* Close; GR_OK if every write reached the file. */
int gr_h5md_close(gr_h5md *h, gr_error *err);

/* Reading: open, count frames, read frame k into f (arrays allocated), close. */
int gr_h5md_open_read(const char *path, gr_h5md **out, int64_t *frames, gr_error *err);
int gr_h5md_read_frame(gr_h5md *h, int64_t k, gr_frame *f, gr_error *err);

#endif
