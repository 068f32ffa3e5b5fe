/* Mean-field references printed beside measurements (summary.json "mean_field"). */
#ifndef GR_MEAN_FIELD_H
#define GR_MEAN_FIELD_H

#include <cjson/cJSON.h>

#include "granule/scene.h"

/* The driven steady state: Williams-MacKintosh (3.7) in 1D, the 2D equation of state (5.2), in 3D
 * the Enskog energy balance of smooth hard spheres (gr_steady_T_enskog_3d). T_mean is eq. 2.20.
 * Returns a new JSON object (NULL when no reference applies). */
cJSON *gr_mean_field_steady(const gr_scene *s, double T_mean);
/* T_1 / T_2 of a binary mixture of smooth inelastic discs (dim 2) or spheres (dim 3) (masses m,
 * radii r, number fractions x, restitution eps) driven by the random force of the same D on every
 * grain, Enskog-Maxwellian with the same chi for every pair (docs/validation.md, "Driven binary
 * mixtures"); 1 at eps = 1. A mixture's summary.json gives it in mean_field
 * (gr_mean_field_steady), with each T_s. */
double gr_mixture_ratio(int dim, const double m[2], const double r[2], const double x[2],
                        double eps);
/* The steady T (2.19, three components) of smooth inelastic hard spheres (diameter sigma, mass M,
 * packing fraction phi, restitution eps) driven by the random force of strength D, symmetrised:
 * the injection 3 D (1 - 1/N) / M per particle balances the Enskog dissipation with the first
 * Sonine correction of the stochastic thermostat (docs/validation.md, "Hard spheres in 3D").
 * Infinite when eps = 1. */
double gr_steady_T_enskog_3d(double D, double M, double sigma, double phi, double eps, int N);

/* Haff's law (1.2) for an undriven gas: fits T(t) = T0 / (1 + t/t0)^2 to the samples and prints
 * the prediction of eq. 1.2 for t0. */
/* HCS fourth cumulant a2(eps) of smooth hard spheres in dim dimensions (first Sonine). */
double gr_hcs_a2(double eps, int dim);
/* 1/(t0 sqrt(T0)) of Haff's law for smooth hard discs at packing fraction phi, diameter sigma. */
double gr_haff_rate_2d(double phi, double eps, double sigma);
/* The same with a given fourth cumulant a2 (Henderson's chi, gr_chi_henderson) */
double gr_enskog_rate_2d(double phi, double eps, double sigma, double a2);
/* The steady T (2.19, two components) of smooth inelastic hard discs driven by the random force of
 * strength D, symmetrised: the Enskog balance with the stochastic thermostat's a2 in 2D
 * (docs/validation.md, "Hard spheres in 3D", its 2D rows). Infinite when eps = 1. */
double gr_steady_T_enskog_2d(double D, double M, double sigma, double phi, double eps, int N);
/* The same for smooth hard spheres (T0 per degree of freedom), with the fourth cumulant a2 of the
 * velocity distribution (the HCS's: gr_hcs_a2(eps, 3); Carnahan-Starling's chi, gr_chi_cs). */
double gr_haff_rate_3d(double phi, double eps, double sigma, double a2);
double gr_chi_cs(double phi);
/* Henderson's contact value of the pair correlation of hard discs (2D). */
double gr_chi_henderson(double phi);
/* a2 of the steady state driven by a white-noise force (van Noije & Ernst's stochastic
 * thermostat), first Sonine, d dimensions. */
double gr_driven_a2(double eps, int dim);
cJSON *gr_mean_field_haff(const gr_scene *s, const double *t, const double *T, int n);
/* The steady T (2.19) of a gas in a Langevin bath (T_bath, tau) that cools at the Enskog rate:
 * (2/tau) (T_bath (1 - 1/N) - T) = zeta(T) T with zeta(T) = 2 rate sqrt(T / dim), rate =
 * gr_haff_rate_2d (the unique root; T_bath (1 - 1/N) when rate = 0, eps_n = 1). For a bath
 * scene gr_mean_field_haff returns these references instead of a Haff fit. */
double gr_bath_T_enskog(double T_bath, double tau, double rate, int dim, int N);

#endif
