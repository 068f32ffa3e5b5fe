/* A read-only view of the particle state, as the simulation and the analysis layer share it. */
#ifndef GRANULE_PARTICLES_H
#define GRANULE_PARTICLES_H

/* The most species a scene may list ([species] radius = r_1, ..., r_k; docs/mixtures.md). */
#define GR_MAX_SPECIES 8

/* Read-only view of the particle state. Arrays have n entries; y/vy are NULL in 1D, z/vz are
 * NULL except in 3D (docs/three-dimensions.md). */
typedef struct gr_particles {
    int n;
    int dim;
    double L;
    double radius, mass;
    const double *x, *y;
    const double *vx, *vy;
    const double *z, *vz; /* dim = 3 only (NULL otherwise) */
    const double *omega;  /* angular velocities, rad/s counterclockwise (2D with [model] rotation =
                            true; NULL otherwise) */
    const double *wx, *wy, *wz; /* the spin vectors' components, rad/s (3D with [model] rotation =
                                   true; NULL otherwise: omega stays NULL in 3D) */
    /* species (docs/mixtures.md): each grain's species index, radius (m) and mass (kg), and the
     * number of species; NULL and 0 for one species (radius and mass above then hold for all; with
     * species, radius is the largest and mass the mean) */
    const int *species;
    const double *radii, *masses;
    int n_species;
} gr_particles;

/* A particle's contact state changed: it touched another particle for the first time since it was
 * last free (kind = +1, "collision"), or it lost its last contact (kind = -1). Positions are as
 * the simulation stores them (1D unwrapped, 2D and 3D wrapped into [0, L)); velocities are those
 * of the step in which the change was seen (accurate to O(dt)). z, vz: 3D only (0 otherwise). */
typedef struct gr_contact_event {
    int i;
    int kind;
    double t;
    double x, y, vx, vy;
    double z, vz;
} gr_contact_event;

#endif
