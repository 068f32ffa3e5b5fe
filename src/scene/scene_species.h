/* [species] of a scene (docs/mixtures.md): from the lists of keys to the grains of each species. */
#ifndef GR_SCENE_SPECIES_H
#define GR_SCENE_SPECIES_H

#include <stddef.h>

#include "granule/scene.h"

/* Resolve s->n_species, species_count and species_masses from the [species] lists, and refuse
 * what a mixture cannot run yet. Returns 0, or GR_EINVAL with the section and key to blame and
 * the reason (with the allowed values) in detail. */
int gr_scene_species_resolve(gr_scene *s, const char **section, const char **key, char *detail,
                             size_t cap);
/* The grains' total area N pi r^2 (2D; with species or a radius distribution the sum over the
 * grains), and total length N 2 r (1D). */
double gr_scene_grain_area(const gr_scene *s);
double gr_scene_grain_length(const gr_scene *s);
/* The grains' number means <r> (m) and <r^2> (m^2), for one size radius and radius^2. */
void gr_scene_radius_moments(const gr_scene *s, double *mean, double *sq_mean);
/* The grains' volume sum (4/3) pi r_i^3 (3D), m^3. */
double gr_scene_grain_volume(const gr_scene *s);

#endif
