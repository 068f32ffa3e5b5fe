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
cJSON *gr_mean_field_haff(const gr_scene *s, const double *t, const double *T, int n);

#endif
