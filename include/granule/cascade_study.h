/* granule cascade as library calls (thesis sec. 6.2): C configurations of the cascade field, the
 * configuration-averaged structure factor (6.5), the D_f fits (4.4: weighted, unweighted, the exact
 * average), the total probability per level, the first field and (Fig. 6.3) discs placed from it;
 * then the output folder (docs/theory-cascade.md). The pieces are in granule/cascade.h. */
#ifndef GRANULE_CASCADE_STUDY_H
#define GRANULE_CASCADE_STUDY_H

#include <stdbool.h>

#include "granule/cascade.h"
#include "granule/status.h"

#define GR_CASCADE_FIELD_CSV_MAX_LEVELS 8 /* field.csv: at most 256 x 256 values */

typedef struct gr_cascade_study_params {
    gr_cascade_settings s;
    bool place;    /* Fig. 6.3: place discs from the first field */
    bool no_plots; /* skip the PNGs (granule cascade --no-plots) */
    gr_cascade_placement placement;
    /* called now and then: configurations done, of total, seconds spent on them */
    void (*progress)(int done, int total, double seconds, void *user);
    void *user;
} gr_cascade_study_params;

typedef struct gr_cascade_study {
    int levels;
    double *t_mean, *t_m2, *t_lo, *t_hi; /* total probability per level over the configurations */
    double *coarse;                      /* the first field, 4^l m, coarse-grained to field_level */
    int field_level;
    gr_cascade_sk_bin *bins;
    int nbins;
    double q_min, q_max; /* the fit's bins */
    bool have_fit;       /* weighted and exact-average fits */
    gr_cascade_fit fit, fit_exp;
    bool have_unweighted;
    gr_cascade_fit fit_unweighted; /* equal weights per shell; see gr_cascade_fit_df_unweighted */
    bool headline_unweighted;      /* chi2/dof of the weighted fit > GR_CASCADE_CHI2_LARGE */
    char headline_why[300];
    char fit_note[800]; /* why there is no fit */
    double *px, *py;    /* placed discs */
    gr_cascade_placement_result pres;
    unsigned long place_seed;
    double place_seconds, wall_seconds;
} gr_cascade_study;

/* The seed of the placement's generator, derived from the field's (splitmix64). */
unsigned long gr_cascade_place_seed(unsigned long seed);
/* The fit a reader should quote: the unweighted one when headline_unweighted, else the weighted. */
const gr_cascade_fit *gr_cascade_study_headline(const gr_cascade_study *st);
/* Checks the settings and the placement (GR_EINVAL before any work), then runs. */
int gr_cascade_study_run(const gr_cascade_study_params *p, gr_cascade_study *st, gr_error *err);
/* sk.csv, levels.csv, field.csv, summary.json, sk.png, field.png and with a placement
 * snapshots/snap_000000.xyz, scene.ini, placement.png. `plots` receives the plots drawn or why not. */
int gr_cascade_study_write(const char *dir, const gr_cascade_study_params *p,
                           const gr_cascade_study *st, char *plots, size_t plots_size,
                           gr_error *err);
void gr_cascade_study_free(gr_cascade_study *st);

#endif
