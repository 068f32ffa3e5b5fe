/* granule fokker-planck as library calls (thesis App. B): the quadrature of (B.32)-(B.34) with its
 * moments and tail fits, the simulation of the same walkers, their comparison (Figs. B.1-B.2),
 * and the output folder (docs/theory-fokker-planck.md). The pieces are in granule/fokker_planck.h.
 * Order: gr_fp_study_quadrature, gr_fp_study_simulate, gr_fp_study_compare, gr_fp_study_summary,
 * gr_fp_study_free (the caller prepares the folder first; each step writes its own files). */
#ifndef GRANULE_FOKKER_PLANCK_STUDY_H
#define GRANULE_FOKKER_PLANCK_STUDY_H

#include <stdbool.h>

#include "granule/analysis.h"
#include "granule/fokker_planck.h"
#include "granule/status.h"

#define GR_FP_STUDY_NOTES 8

typedef struct gr_fp_study_params {
    gr_fp_settings s;
    bool sim;         /* simulate too (else quadrature only) */
    int points;       /* points of the quadrature curves */
    double min_walks; /* bins of Q compared need this many walks */
    gr_fp_progress progress;
    void *user;
} gr_fp_study_params;

typedef struct gr_fp_study {
    double V, T0; /* (D L/M^2)^(1/3), L/V */
    bool uniform; /* uniform start (the quadrature's) */
    gr_fp_quad *q;
    /* quadrature (uniform start) */
    double T_quad, v2, vabs, v4, e1, e2, Q0, PL_half, quad_seconds;
    gr_fit quad_tail[3]; /* effective tail exponents over the ranges below (in V) */
    bool quad_tail_ok[3];
    /* simulation and comparison */
    bool have_sim;
    gr_fp_sim_result r;
    double *qm, *em; /* quadrature bin means on the simulation's bins */
    gr_fp_chi2 cq, ce;
    double q0fit, q0fit_err;
    bool have_tail_fit;
    gr_fit sim_tail, quad_tail_on_bins; /* |v| in [1.5 V, 3.5 V] */
    double compare_seconds;
    char notes[GR_FP_STUDY_NOTES][768];
    int n_notes;
} gr_fp_study;

/* the ranges of the quadrature's tail fits, in units of V */
extern const double gr_fp_study_tail_ranges[3][2];

/* The quadrature and its curves (q_curve.csv, exit_curve.csv). */
int gr_fp_study_quadrature(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                           gr_error *err);
/* The simulation (with p->sim); without it, removes an earlier run's q.csv and exit.csv. */
int gr_fp_study_simulate(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                         gr_error *err);
/* The comparison and the tables q.csv, exit.csv (after a simulation). */
int gr_fp_study_compare(const char *dir, const gr_fp_study_params *p, gr_fp_study *st,
                        gr_error *err);
/* The plots and summary.json. */
int gr_fp_study_summary(const char *dir, const gr_fp_study_params *p, gr_fp_study *st, bool plots,
                        gr_error *err);
void gr_fp_study_free(gr_fp_study *st);

#endif
