/* [species] of a scene (scene_species.h, docs/mixtures.md). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "models/list.h"
#include "scene/scene_species.h"

/* What a mixture cannot run yet (src/core/species.c refuses the same without the line). */
static int refused(const gr_scene *s, const char **section, const char **key, char *detail,
                   size_t cap)
{
    /* tangential laws and rolling laws: the verlet integrator (kernels_poly.c); the history law:
     * species lists; the bath and com mode: verlet; walls and gravity: both integrators */
    const bool event = s->integrator->instantaneous;
    /* the hybrid (soft contacts between free flights): species lists, com or no noise
     * (docs/hybrid.md, "Mixtures") */
    const bool leaps = s->integrator->free_flight && !event;

    struct {
        bool on;
        const char *section, *key, *allowed;
    } const no[] = {
        {!s->integrator->species, "integrator", "kind", "verlet | event | hybrid"},
        {leaps && s->noise_mode == GR_NOISE_SYMMETRISED && s->D > 0.0 &&
             !(s->driving && s->driving->update != GR_DRIVE_FORCE),
         "noise", "mode",
         "com | none with the hybrid integrator (subtracting the mean force accelerates grains of "
         "unequal mass unequally, which its centre-of-mass frame cannot represent)"},
        {s->normal && !(s->normal->kind & GR_MODEL_NORMAL), "model", "normal",
         "a normal force law (spring_dashpot, hertz, ...) or event rule (hard_sphere)"},
        {s->tangential &&
             (event || (s->size_distribution && gr_model_keeps_history(s->tangential) &&
                        s->normal != &gr_model_spring_dashpot)),
         "model", "tangential",
         "none, or with verlet tangential_dashpot | sliding_friction (and tangential_spring with "
         "[species] lists, or with a radius distribution and normal = spring_dashpot)"},
        {s->rolling && event, "model", "rolling", "none, or with verlet rolling_friction"},
        {s->noise_mode == GR_NOISE_COM && event, "noise", "mode",
         "symmetrised | none (com: with the verlet integrator)"},
        {s->noise_precision == GR_NOISE_SINGLE, "noise", "precision", "double"},
    };
    for (size_t k = 0; k < sizeof no / sizeof no[0]; k++) {
        if (no[k].on) {
            *section = no[k].section;
            *key = no[k].key;
            snprintf(detail, cap,
                     "not available with [species] yet; allowed with a mixture: %s "
                     "(docs/mixtures.md lists what a mixture runs with)",
                     no[k].allowed);
            return GR_EINVAL;
        }
    }
    if (s->size_distribution &&
        (s->normal == &gr_model_hertz || s->normal == &gr_model_hard_sphere) &&
        GR_OWN(&s->contact, hertz)->viscoelastic) {
        *section = "model";
        *key = "viscoelastic";
        snprintf(detail, cap,
                 "true is not available with a radius distribution yet: its damping is not "
                 "calibrated to eps_n, so it cannot be scaled per pair; allowed: false");
        return GR_EINVAL;
    }
    /* observables: every one but species (which needs lists) measures a distribution
     * (docs/mixtures.md, "Observables on a mixture") */
    char buf[sizeof s->observables], *save = NULL;
    snprintf(buf, sizeof buf, "%s", s->observables);
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        if (strcmp(tok, "species") == 0 && s->size_distribution) {
            *section = "analysis";
            *key = "observables";
            snprintf(detail, cap,
                     "species needs [species] lists: a radius distribution has no species; "
                     "allowed with a radius distribution: moments, pv, msd, vacf, postcollision, "
                     "collisions, profile, clusters, sk, pair, vcorr, freepath, gaps, pressure "
                     "(docs/mixtures.md)");
            return GR_EINVAL;
        }
    }
    return GR_OK;
}

int gr_scene_species_resolve(gr_scene *s, const char **section, const char **key, char *detail,
                             size_t cap)
{
    const gr_number_list *r = &s->species_radius, *m = &s->species_mass, *rho = &s->species_density,
                         *f = &s->species_fraction;
    s->n_species = 0;
    *section = "species";
    if (s->size_distribution) { /* a continuous distribution: bounds, density, no lists */
        const bool logn = s->size_distribution == GR_SIZE_LOGNORMAL;
        *key = r->n || m->n || f->n ? (r->n   ? "radius"
                                       : m->n ? "mass"
                                              : "fraction")
               : rho->n != 1        ? "density"
               : !(s->radius_min > 0.0 && s->radius_max > s->radius_min)
                   ? (s->radius_min > 0.0 ? "radius_max" : "radius_min")
               : logn && !(s->radius_median > 0.0) ? "radius_median"
               : logn && !(s->radius_sigma > 0.0)  ? "radius_sigma"
                                                   : NULL;
        if (*key) {
            snprintf(detail, cap,
                     "a radius distribution needs 0 < radius_min < radius_max, one density "
                     "(kg/m^3 in 3D, kg/m^2 in 2D, kg/m in 1D), lognormal radius_median and "
                     "radius_sigma > 0, "
                     "and no radius, mass or fraction lists");
            return GR_EINVAL;
        }
        return refused(s, section, key, detail, cap);
    }
    if (r->n == 0 && m->n == 0 && rho->n == 0 && f->n == 0) {
        return GR_OK; /* one species: [system] radius and mass */
    }
    const int ns = r->n;
    if (ns < 2) {
        *key = "radius";
        snprintf(detail, cap,
                 "give the radii of 2 to %d species (one species: [system] radius and mass, "
                 "without [species])",
                 GR_MAX_SPECIES);
        return GR_EINVAL;
    }
    if ((m->n > 0) == (rho->n > 0)) {
        *key = m->n > 0 ? "density" : "mass";
        snprintf(detail, cap, "give either mass or density, one value per radius (%d)", ns);
        return GR_EINVAL;
    }
    const gr_number_list *given = m->n > 0 ? m : rho;
    if (given->n != ns || (f->n != 0 && f->n != ns)) {
        *key = given->n != ns ? (m->n > 0 ? "mass" : "density") : "fraction";
        snprintf(detail, cap, "%d values given, one per radius needed (%d)",
                 given->n != ns ? given->n : f->n, ns);
        return GR_EINVAL;
    }
    double frac[GR_MAX_SPECIES], sum = 0.0;
    for (int a = 0; a < ns; a++) {
        frac[a] = f->n ? f->v[a] : 1.0 / ns;
        sum += frac[a];
        s->species_masses[a] = m->n > 0      ? m->v[a]
                               : s->dim == 1 ? rho->v[a] * 2.0 * r->v[a]
                               : s->dim == 3
                                   ? rho->v[a] * 4.0 / 3.0 * M_PI * r->v[a] * r->v[a] * r->v[a]
                                   : rho->v[a] * M_PI * r->v[a] * r->v[a];
    }
    if (fabs(sum - 1.0) > 1e-9 || gr_species_counts(s->N, ns, frac, s->species_count)) {
        *key = "fraction";
        snprintf(detail, cap,
                 "the number fractions sum to %.12g; allowed: fractions in [0, 1] summing to 1",
                 sum);
        return GR_EINVAL;
    }
    s->n_species = ns;
    return refused(s, section, key, detail, cap);
}

/* The radius of grain i of a scene's distribution. */
static double size_radius(const gr_scene *s, int i)
{
    return gr_size_radius(s->size_distribution, s->radius_min, s->radius_max, s->radius_median,
                          s->radius_sigma, s->seed, i);
}

double gr_scene_grain_area(const gr_scene *s)
{
    if (s->size_distribution) {
        double a = 0.0;
        for (int i = 0; i < s->N; i++) {
            a += M_PI * size_radius(s, i) * size_radius(s, i);
        }
        return a;
    }
    if (s->n_species < 2) {
        return s->N * M_PI * s->radius * s->radius;
    }
    double a = 0.0;
    for (int k = 0; k < s->n_species; k++) {
        a += s->species_count[k] * M_PI * s->species_radius.v[k] * s->species_radius.v[k];
    }
    return a;
}

double gr_scene_grain_volume(const gr_scene *s)
{
    if (s->size_distribution) {
        double v = 0.0;
        for (int i = 0; i < s->N; i++) {
            const double r = size_radius(s, i);
            v += 4.0 / 3.0 * M_PI * r * r * r;
        }
        return v;
    }
    if (s->n_species < 2) {
        return s->N * (4.0 / 3.0 * M_PI * s->radius * s->radius * s->radius);
    }
    double v = 0.0;
    for (int k = 0; k < s->n_species; k++) {
        const double r = s->species_radius.v[k];
        v += s->species_count[k] * (4.0 / 3.0 * M_PI * r * r * r);
    }
    return v;
}

double gr_scene_grain_length(const gr_scene *s)
{
    if (s->size_distribution) {
        double l = 0.0;
        for (int i = 0; i < s->N; i++) {
            l += 2.0 * size_radius(s, i);
        }
        return l;
    }
    if (s->n_species < 2) {
        return s->N * (2.0 * s->radius);
    }
    double l = 0.0;
    for (int k = 0; k < s->n_species; k++) {
        l += s->species_count[k] * 2.0 * s->species_radius.v[k];
    }
    return l;
}

void gr_scene_radius_moments(const gr_scene *s, double *mean, double *sq_mean)
{
    double m1 = 0.0, m2 = 0.0;
    if (s->size_distribution) {
        for (int i = 0; i < s->N; i++) {
            const double r = size_radius(s, i);
            m1 += r;
            m2 += r * r;
        }
    } else if (s->n_species >= 2) {
        for (int k = 0; k < s->n_species; k++) {
            const double r = s->species_radius.v[k];
            m1 += s->species_count[k] * r;
            m2 += s->species_count[k] * r * r;
        }
    } else {
        m1 = s->N * s->radius;
        m2 = s->N * s->radius * s->radius;
    }
    *mean = s->N > 0 ? m1 / s->N : s->radius;
    *sq_mean = s->N > 0 ? m2 / s->N : s->radius * s->radius;
}
