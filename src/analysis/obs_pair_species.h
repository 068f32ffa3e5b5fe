/* pair on a mixture of [species] lists (obs_pair_species.c): the partial pair correlation
 * functions g_ab(R) of every species pair a <= b on the pooled g(R)'s bins, their contact values
 * g_ab(sigma_ab+) and the check that they add up to the pooled g (docs/mixtures.md). */
#ifndef GRANULE_OBS_PAIR_SPECIES_H
#define GRANULE_OBS_PAIR_SPECIES_H

#include <cjson/cJSON.h>
#include <stdint.h>

#include "analysis/obs_util.h"
#include "granule/sim.h"

#define PAIR_KINDS_MAX (GR_MAX_SPECIES * (GR_MAX_SPECIES + 1) / 2)

typedef struct pair_species {
    int ns;    /* species (0: one species, nothing here is used) */
    int nk;    /* species pairs a <= b: ns (ns + 1) / 2 */
    int nbins; /* the pooled g's bins, of width `width` from R = 0 */
    double width, volume;
    int kind_of[GR_MAX_SPECIES * GR_MAX_SPECIES]; /* (a, b) -> kind, symmetric */
    int N_s[GR_MAX_SPECIES];                      /* grains per species (the first frame's) */
    double r_s[GR_MAX_SPECIES];                   /* each species' radius (m) */
    int *species;                                 /* the current frame's, per grain */
    int64_t *frame_count;                         /* nk x nbins pairs of the current frame */
    double *total;                                /* nk x nbins pairs, all frames */
    gr_blocking *g_blk;                           /* nk x nbins per-frame g_ab */
    int64_t frames;
} pair_species;

/* At init: a mixture of n_species >= 2 lists (a radius distribution has no species); the pooled
 * g's bins (nbins of width `width`) in a box of `volume` (L^2 or L^3). */
int pair_species_init(void *state, pair_species *s, const gr_obs_setup *setup, int nbins,
                      double width, double volume, gr_error *err);
/* A frame: its grains' species into s->species, the frame's counts zeroed (GR_OK without a
 * mixture). */
int pair_species_begin(pair_species *s, const gr_particles *p, gr_error *err);
/* The kind of the pair of species a and b. */
static inline int pair_species_kind(const pair_species *s, int a, int b)
{
    return s->kind_of[a * s->ns + b];
}
/* The frame's counts (s->frame_count, filled by the caller) into per-frame g_ab; area[b] is bin
 * b's shell area (volume in 3D). */
void pair_species_end(pair_species *s, const double *area);
/* Checkpoint: the accumulators and the species' sizes. */
void pair_species_io(pair_species *s, gr_blob_io *io);
/* pair_species.csv and summary pair.species (each kind's contact distance, contact value, first
 * peak); d is the pooled g's length unit and area[b] bin b's shell area (volume in 3D). */
int pair_species_finish(const pair_species *s, const gr_output *out, cJSON *pair, double d,
                        const double *area, gr_error *err);

#endif
