/* pv on a mixture of [species] lists (obs_pv_species.c): P(v) of one velocity component for each
 * species, on the pooled distribution's bins, relative to the same frame mean (docs/mixtures.md). */
#ifndef GRANULE_OBS_PV_SPECIES_H
#define GRANULE_OBS_PV_SPECIES_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "analysis/obs_util.h"
#include "granule/sim.h"

typedef struct pv_species {
    int ns;                         /* species (0: one species, nothing here is used) */
    gr_histogram h[GR_MAX_SPECIES]; /* each species' components, the pooled binning */
    unsigned char *buf;             /* the species of each particle the pooled buffer holds */
    size_t nbuf, cap;               /* ... particles buffered, allocated */
} pv_species;

/* At init: a mixture of n_species >= 2 lists (a radius distribution has no species). */
void pv_species_init(void *state, pv_species *s, const gr_obs_setup *setup);
/* The frame carries the scene's species (GR_OK without a mixture). */
int pv_species_check(const pv_species *s, const gr_particles *p, gr_error *err);
/* Before the binning is fixed: the frame's species beside its buffered velocities. */
int pv_species_buffer(pv_species *s, const gr_particles *p, gr_error *err);
/* The binning is fixed: the species' histograms on the pooled one's bins. */
int pv_species_fix(pv_species *s, const gr_histogram *pooled, gr_error *err);
/* Components of a grain of species a (a mixture, binning fixed). */
void pv_species_add(pv_species *s, int a, int dim, double ux, double uy, double uz);
/* Checkpoint: the histograms (fixed) or the buffered species (not yet). */
void pv_species_io(pv_species *s, gr_blob_io *io, bool fixed);
/* pv_species.csv and summary pv.species (each species' T per component and flatness). */
int pv_species_finish(const pv_species *s, const gr_output *out, cJSON *pv, gr_error *err);

#endif
