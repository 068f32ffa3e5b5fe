/* Mean-field references. Each is printed with the measured value and the compensation constant
 * the measurement implies, so a user sees at once how far the mean-field picture holds. */
#include <math.h>
#include <stdlib.h>

#include "app/mean_field.h"
#include "granule/analysis.h"

/* The energy each grain of species i loses per second in collisions over the number density,
 * at temperatures T (J) of a binary mixture of smooth inelastic discs (dim 2) or spheres (dim 3),
 * Enskog-Maxwellian (docs/validation.md, "Driven binary mixtures": the prefactor
 * 2^(3/2) pi^((d-1)/2) / Gamma(d/2) sigma_ij^(d-1) is 2^(3/2) sqrt(pi) sigma_ij in 2D and
 * 2^(5/2) sqrt(pi) sigma_ij^2 in 3D; scripts/mixture_theory.py is the same). */
static double mixture_loss(int dim, int i, const double T[2], const double m[2], const double r[2],
                           const double x[2], double eps, double chi)
{
    double tot = 0.0;
    for (int j = 0; j < 2; j++) {
        const double M = m[i] + m[j], mu_ji = m[j] / M, mij = m[i] * m[j] / M;
        const double s2 = T[i] / m[i] + T[j] / m[j];
        /* sigma_ij = r_i + r_j; 3D: 2 sigma_ij^2 (times the 2D prefactor 4 sqrt(pi/2)) */
        const double sig = dim == 3 ? 2.0 * (r[i] + r[j]) * (r[i] + r[j]) : r[i] + r[j];
        tot += x[j] * chi * sig * 4.0 * sqrt(M_PI / 2.0) * pow(s2, 1.5) * mij * (1.0 + eps) *
               (mu_ji * (1.0 - eps) / 2.0 + (T[i] - T[j]) / (M * s2));
    }
    return tot;
}

double gr_mixture_ratio(int dim, const double m[2], const double r[2], const double x[2],
                        double eps)
{
    if (eps >= 1.0) {
        return 1.0;
    }
    double lo = -20.0, hi = 20.0; /* log T_1 at T_2 = 1: m_1 loss_1 - m_2 loss_2 rises with it */
    for (int k = 0; k < 200; k++) {
        const double mid = 0.5 * (lo + hi), T[2] = {exp(mid), 1.0};
        const double g = m[0] * mixture_loss(dim, 0, T, m, r, x, eps, 1.0) -
                         m[1] * mixture_loss(dim, 1, T, m, r, x, eps, 1.0);
        if (g > 0.0) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return exp(0.5 * (lo + hi));
}

/* A driven binary mixture of discs or spheres ([species], docs/mixtures.md): T_1 / T_2 and each
 * species' T from the two energy balances, chi of one-size discs (Henderson) or spheres
 * (Carnahan-Starling) at the actual packing fraction for every pair (exact for equal radii, where
 * it drops out of the ratio). */
static cJSON *mean_field_mixture(const gr_scene *s)
{
    if (s->dim == 1 || s->n_species != 2 || s->D <= 0.0 || s->contact.eps_n >= 1.0) {
        return NULL;
    }
    const double m[2] = {s->species_masses[0], s->species_masses[1]},
                 r[2] = {s->species_radius.v[0], s->species_radius.v[1]},
                 x[2] = {(double)s->species_count[0] / s->N, (double)s->species_count[1] / s->N};
    const double eps = s->contact.eps_n, phi = s->packing_fraction;
    const int dim = s->dim;
    const double chi = dim == 3 ? (1.0 - 0.5 * phi) / ((1.0 - phi) * (1.0 - phi) * (1.0 - phi))
                                : (1.0 - 7.0 * phi / 16.0) / ((1.0 - phi) * (1.0 - phi));
    const double R = gr_mixture_ratio(dim, m, r, x, eps), T[2] = {R, 1.0};
    const double n = dim == 3 ? s->N / (s->L * s->L * s->L) : s->N / (s->L * s->L);
    const double sym = s->noise_mode == GR_NOISE_SYMMETRISED ? 1.0 - 1.0 / s->N : 1.0;
    /* the losses scale as T^(3/2): d D / m_1 (1 - 1/N) = n loss_1(T_1, T_2) fixes the scale */
    const double lam =
        pow(dim * s->D * sym / (m[0] * n * mixture_loss(dim, 0, T, m, r, x, eps, chi)), 2.0 / 3.0);
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "reference",
                            dim == 3 ? "driven binary mixture of smooth inelastic spheres: each "
                                       "species' energy balance, Enskog-Maxwellian, "
                                       "Carnahan-Starling chi(phi) of one-size spheres for every "
                                       "pair (docs/validation.md, Driven binary mixtures)"
                                     : "driven binary mixture of smooth inelastic discs: each "
                                       "species' energy balance, Enskog-Maxwellian, chi(phi) of "
                                       "one-size discs for every pair (docs/validation.md, Driven "
                                       "binary mixtures)");
    cJSON_AddNumberToObject(j, "T1_over_T2_predicted", R);
    cJSON *t = cJSON_AddArrayToObject(j, "T_predicted");
    cJSON_AddItemToArray(t, cJSON_CreateNumber(R * lam));
    cJSON_AddItemToArray(t, cJSON_CreateNumber(lam));
    return j;
}

cJSON *gr_mean_field_steady(const gr_scene *s, double T_mean)
{
    if (s->D <= 0.0 || !(T_mean > 0.0)) {
        return NULL;
    }
    if (s->n_species >= 2 ||
        s->size_distribution) { /* the references below have one radius and mass */
        return mean_field_mixture(s);
    }
    const double M = s->mass, D = s->D, d = 2.0 * s->radius;
    if (s->dim == 3) {
        const double pred =
            gr_steady_T_enskog_3d(D, M, d, s->packing_fraction, s->contact.eps_n, s->N);
        if (!isfinite(pred) || s->tangential) {
            return NULL;
        }
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(
            j, "reference",
            "Enskog energy balance of smooth hard spheres: 3 D (1 - 1/N) / M = (M/2) zeta T, "
            "Carnahan-Starling chi(phi), first Sonine correction with the stochastic "
            "thermostat's a2 (van Noije & Ernst 1998); docs/validation.md, \"Hard spheres in "
            "3D\"");
        cJSON_AddNumberToObject(j, "a2_driven", gr_driven_a2(s->contact.eps_n, 3));
        cJSON_AddNumberToObject(j, "T_predicted", pred);
        cJSON_AddNumberToObject(j, "T_measured", T_mean);
        cJSON_AddNumberToObject(j, "ratio", T_mean / pred);
        return j;
    }
    cJSON *j = cJSON_CreateObject();
    if (s->dim == 1) {
        /* Williams-MacKintosh (3.7): <v^2>^(3/2) = (4C/N) D L' / (M^2 (1 - eps^2)); in 1D T = <v^2> */
        double e = s->contact.eps_n, lp = s->L - s->N * d;
        if (e >= 1.0 || lp <= 0.0) {
            cJSON_Delete(j);
            return NULL;
        }
        double pred = pow(4.0 / s->N * D * lp / (M * M * (1.0 - e * e)), 2.0 / 3.0);
        cJSON_AddStringToObject(j, "reference", "Williams-MacKintosh (3.7) with C = 1");
        cJSON_AddNumberToObject(j, "v2_predicted", pred);
        cJSON_AddNumberToObject(j, "v2_measured", T_mean);
        cJSON_AddNumberToObject(j, "C_implied", pow(T_mean / pred, 1.5));
    } else {
        /* 2D equation of state (5.2): <|v|>^3 = (C1/phi) D d pi / (M^2 (2 - eps_n^2 - eps_t^2)),
         * with <|v|> estimated from T as for a Gaussian, <|v|> = sqrt(pi T / 4) (T of eq. 2.19) */
        double en = s->contact.eps_n,
               et = s->tangential && s->tangential->params ? s->contact.eps_t : 1.0;
        double loss = 2.0 - en * en - et * et;
        if (loss <= 0.0) {
            cJSON_Delete(j);
            return NULL;
        }
        double pred = cbrt(D * d * M_PI / (s->packing_fraction * M * M * loss));
        double meas = sqrt(M_PI * T_mean / 4.0);
        cJSON_AddStringToObject(
            j, "reference",
            "2D equation of state (5.2) with C1 = 1; <|v|> = sqrt(pi T/4) (Gaussian estimate)");
        cJSON_AddNumberToObject(j, "mean_speed_predicted", pred);
        cJSON_AddNumberToObject(j, "mean_speed_measured", meas);
        cJSON_AddNumberToObject(j, "C1_implied", pow(meas / pred, 3.0));
    }
    return j;
}

/* The fourth cumulant of the homogeneous cooling state of smooth inelastic hard spheres in d
 * dimensions, first Sonine approximation: van Noije & Ernst, Granular Matter 1, 57 (1998), eq. 4.3
 * (docs/validation.md). */
double gr_hcs_a2(double eps, int dim)
{
    const double e = eps, d = dim;
    return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) /
           (9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * (1.0 - e) * e * e);
}

/* Haff's law for smooth hard discs: d(T^-1/2)/dt = zeta / (2 sqrt T) with the Enskog cooling rate
 * zeta = (4/sqrt(pi)) phi chi(phi) (1 - eps^2) (1 + 3 a2/16) sqrt(T) / sigma (T per degree of
 * freedom, velocity^2; chi = (1 - 7 phi/16) / (1 - phi)^2, Henderson). Returns zeta / (2 sqrt T),
 * i.e. 1 / (t0 sqrt(T0)) of T = T0 / (1 + t/t0)^2. The thesis's eq. 1.2 is the quasi-elastic limit
 * (1 - eps^2 -> 2 (1 - eps), a2 -> 0), 33 % off at eps = 0.5. */
double gr_chi_henderson(double phi)
{
    return (1.0 - 7.0 * phi / 16.0) / ((1.0 - phi) * (1.0 - phi));
}

double gr_haff_rate_2d(double phi, double eps, double sigma)
{
    return gr_enskog_rate_2d(phi, eps, sigma, gr_hcs_a2(eps, 2));
}

double gr_enskog_rate_2d(double phi, double eps, double sigma, double a2)
{
    const double chi = gr_chi_henderson(phi);
    return 2.0 / sqrt(M_PI) * phi * chi * (1.0 - eps * eps) * (1.0 + 3.0 * a2 / 16.0) / sigma;
}

/* Smooth hard discs driven by the random force (symmetrised): T_1 = T / 2 rises by
 * 2 D (1 - 1/N) / M^2 per second and falls at zeta T_1, zeta = 2 gr_enskog_rate_2d sqrt(T_1) with
 * the stochastic thermostat's a2 in d = 2, so T_1^(3/2) = 2 D (1 - 1/N) / (M^2 2 rate); returns
 * T = 2 T_1 (eq. 2.19, both components). */
double gr_steady_T_enskog_2d(double D, double M, double sigma, double phi, double eps, int N)
{
    const double k = 2.0 * gr_enskog_rate_2d(phi, eps, sigma, gr_driven_a2(eps, 2));
    const double input = 2.0 * D * (1.0 - 1.0 / N) / (M * M);
    return k > 0.0 ? 2.0 * pow(input / k, 2.0 / 3.0) : (double)INFINITY;
}

/* The fourth cumulant of the steady state of smooth inelastic hard spheres driven by a white-noise
 * force (the stochastic thermostat), first Sonine approximation: van Noije & Ernst, Granular
 * Matter 1, 57 (1998) (docs/validation.md, "Hard spheres in 3D"). */
double gr_driven_a2(double eps, int dim)
{
    const double e = eps, d = dim;
    return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) /
           (73.0 + 56.0 * d - 3.0 * e * (35.0 + 8.0 * d) + 30.0 * (1.0 - e) * e * e);
}

/* Carnahan-Starling's contact value of the pair correlation of hard spheres. */
double gr_chi_cs(double phi)
{
    return (1.0 - 0.5 * phi) / ((1.0 - phi) * (1.0 - phi) * (1.0 - phi));
}

/* Smooth hard spheres (d = 3): the Enskog cooling rate of the temperature per degree of freedom
 * T_1 = T / 3 is zeta = (8 / sqrt(pi)) phi chi (1 - eps^2) (1 + 3 a2 / 16) sqrt(T_1) / sigma
 * (docs/validation.md, "Hard spheres in 3D"); returns zeta / (2 sqrt(T_1)), i.e. 1 / (t0 sqrt(T_1
 * at 0)) of Haff's law, for the given a2 (the HCS's: gr_hcs_a2(eps, 3)). */
double gr_haff_rate_3d(double phi, double eps, double sigma, double a2)
{
    return 4.0 / sqrt(M_PI) * phi * gr_chi_cs(phi) * (1.0 - eps * eps) * (1.0 + 3.0 * a2 / 16.0) /
           sigma;
}

/* The random force raises T_1 = T / 3 by 2 D (1 - 1/N) / M^2 per second (symmetrised: N - 1
 * degrees of freedom per component); the balance 2 D (1 - 1/N) / M^2 = zeta T_1 with the Enskog
 * rate above and the stochastic thermostat's a2 (gr_driven_a2) gives T_1^(3/2) =
 * 2 D (1 - 1/N) / (M^2 2 gr_haff_rate_3d). */
double gr_steady_T_enskog_3d(double D, double M, double sigma, double phi, double eps, int N)
{
    const double k = 2.0 * gr_haff_rate_3d(phi, eps, sigma, gr_driven_a2(eps, 3));
    const double input = 2.0 * D * (1.0 - 1.0 / N) / (M * M);
    return k > 0.0 ? 3.0 * pow(input / k, 2.0 / 3.0) : (double)INFINITY;
}

double gr_bath_T_enskog(double T_bath, double tau, double rate, int dim, int N)
{
    /* (2/tau)(T_b - T) = 2 rate sqrt(T/dim) T, T_b = T_bath (1 - 1/N): the left side falls and the
     * right rises with T, so the root in [0, T_b] is unique; bisection on x = sqrt(T) */
    const double Tb = T_bath * (1.0 - 1.0 / N);
    double lo = 0.0, hi = sqrt(Tb);
    for (int it = 0; it < 200 && rate > 0.0; it++) {
        const double x = 0.5 * (lo + hi),
                     f = (Tb - x * x) / tau - rate * x * x * x / sqrt((double)dim);
        if (f > 0.0) {
            lo = x;
        } else {
            hi = x;
        }
    }
    return rate > 0.0 ? 0.25 * (lo + hi) * (lo + hi) : Tb;
}

/* The Langevin bath's references (docs/systems-driving.md): its parameters, the elastic gas's
 * T = T_bath (1 - 1/N) and, in 2D, the Enskog estimate of an inelastic gas's steady T. */
static cJSON *mean_field_bath(const gr_scene *s)
{
    const gr_driving_params *p = &s->driving_params;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(
        j, "reference",
        "Langevin bath: dT/dt = (2/tau) (T_bath - T) - zeta(T) T (docs/systems-driving.md)");
    cJSON_AddNumberToObject(j, "T_bath", p->T_bath);
    cJSON_AddNumberToObject(j, "tau", p->tau);
    cJSON_AddNumberToObject(j, "D_bath", s->mass * s->mass * p->T_bath / (s->dim * p->tau));
    cJSON_AddNumberToObject(j, "T_elastic", p->T_bath * (1.0 - 1.0 / s->N));
    if (s->dim == 2 && s->packing_fraction > 0.0) {
        const double rate = gr_haff_rate_2d(s->packing_fraction, s->contact.eps_n, 2.0 * s->radius);
        cJSON_AddNumberToObject(j, "T_enskog",
                                gr_bath_T_enskog(p->T_bath, p->tau, rate, s->dim, s->N));
        cJSON_AddStringToObject(
            j, "note",
            "T of eq. 2.19. T_elastic: equipartition, exact for eps_n = 1 (the mean velocity "
            "excluded). T_enskog: the bath's heating against the Enskog cooling rate of smooth "
            "hard discs (eps_n, Henderson's chi, the HCS Sonine a2; docs/validation.md, \"Haff's "
            "law\"), a mean-field estimate for binary collisions without tangential dissipation");
    }
    return j;
}

cJSON *gr_mean_field_haff(const gr_scene *s, const double *t, const double *T, int n)
{
    if (s->n_species >= 2 || s->size_distribution) { /* Haff's rate of one radius and mass */
        return NULL;
    }
    if (s->driving &&
        s->driving->update == GR_DRIVE_BATH) { /* driven, not cooling: the bath's references */
        return mean_field_bath(s);
    }
    /* T^(-1/2) = T0^(-1/2) (1 + t/t0) is a straight line in t: intercept a, slope b, t0 = a/b */
    double *y = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (T[i] > 0.0) {
            y[m] = 1.0 / sqrt(T[i]);
            m++;
        }
    }
    gr_fit f;
    gr_error err = {0};
    cJSON *j = NULL;
    if (m >= 3 && m == n && gr_fit_line(t, y, NULL, m, &f, &err) == GR_OK && f.p[1] > 0.0) {
        double T0 = 1.0 / (f.p[0] * f.p[0]), t0 = f.p[0] / f.p[1];
        double phi = s->dim >= 2 ? s->packing_fraction : 0.0;
        j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "reference", "Haff's law (1.2): T = T0 / (1 + t/t0)^2");
        cJSON_AddNumberToObject(j, "T0_fit", T0);
        cJSON_AddNumberToObject(j, "t0_fit", t0);
        cJSON_AddNumberToObject(j, "t0_fit_stderr",
                                t0 * hypot(f.err[0] / f.p[0], f.err[1] / f.p[1]));
        if (s->dim == 2 && phi > 0.0) {
            const double rate = gr_haff_rate_2d(phi, s->contact.eps_n, 2.0 * s->radius);
            cJSON_AddNumberToObject(j, "t0_haff", 1.0 / (rate * sqrt(T0 / s->dim)));
            cJSON_AddNumberToObject(j, "t0_haff_T_eq_2_19", 1.0 / (rate * sqrt(T0)));
            cJSON_AddNumberToObject(j, "a2_hcs", gr_hcs_a2(s->contact.eps_n, s->dim));
            cJSON_AddStringToObject(
                j, "note",
                "Enskog cooling rate of smooth hard discs (docs/validation.md, \"Haff's law\"): "
                "(1 - eps_n^2), Henderson's chi(phi), first Sonine correction (1 + 3 a2/16); "
                "T0 per degree of freedom (T of eq. 2.19 / dim); t0_haff_T_eq_2_19 uses T0 of eq. "
                "2.19. "
                "The thesis's eq. 1.2 is its quasi-elastic limit, 2 (1 - eps) for 1 - eps^2, a2 = "
                "0");
        } else if (s->dim == 3 && phi > 0.0 && !s->tangential) {
            const double a2 = gr_hcs_a2(s->contact.eps_n, 3);
            const double rate = gr_haff_rate_3d(phi, s->contact.eps_n, 2.0 * s->radius, a2);
            cJSON_AddNumberToObject(j, "t0_haff", 1.0 / (rate * sqrt(T0 / 3.0)));
            cJSON_AddNumberToObject(j, "a2_hcs", a2);
            cJSON_AddStringToObject(
                j, "note",
                "Enskog cooling rate of smooth hard spheres (docs/validation.md, \"Hard spheres "
                "in 3D\"): (1 - eps_n^2), Carnahan-Starling chi(phi), first Sonine correction "
                "(1 + 3 a2/16); T0 per degree of freedom (T of eq. 2.19 / 3)");
        }
    }
    free(y);
    return j;
}
