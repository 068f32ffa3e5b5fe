/* Mean-field references printed beside measurements (summary.json "mean_field"). */
#ifndef GR_MEAN_FIELD_H
#define GR_MEAN_FIELD_H

#include <cjson/cJSON.h>

#include "granule/scene.h"

/* The driven steady state: Williams-MacKintosh (3.7) in 1D, the 2D equation of state (5.2).
 * T_mean is eq. 2.20. Returns a new JSON object (NULL when no reference applies). */
cJSON *gr_mean_field_steady(const gr_scene *s, double T_mean);

/* Haff's law (1.2) for an undriven gas: fits T(t) = T0 / (1 + t/t0)^2 to the samples and prints
 * the prediction of eq. 1.2 for t0. */
/* HCS fourth cumulant a2(eps) of smooth hard spheres in dim dimensions (first Sonine). */
double gr_hcs_a2(double eps, int dim);
/* 1/(t0 sqrt(T0)) of Haff's law for smooth hard discs at packing fraction phi, diameter sigma. */
double gr_haff_rate_2d(double phi, double eps, double sigma);
cJSON *gr_mean_field_haff(const gr_scene *s, const double *t, const double *T, int n);

#endif
