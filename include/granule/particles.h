/* A read-only view of the particle state, as the simulation and the analysis layer share it. */
#ifndef GRANULE_PARTICLES_H
#define GRANULE_PARTICLES_H

/* Read-only view of the particle state. Arrays have n entries; y/vy are NULL in 1D. */
typedef struct gr_particles {
    int n;
    int dim;
    double L;
    double radius, mass;
    const double *x, *y;
    const double *vx, *vy;
} gr_particles;

#endif
