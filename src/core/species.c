/* Species: grains of several radii and masses (gr_sim_params.n_species >= 2, docs/mixtures.md).
 *
 * Each grain gets the radius and mass of its species; the counts (gr_species_counts) are handed
 * out in an order shuffled by the seed (Fisher-Yates on the placement stream, word 2, which the
 * placements never draw), so a lattice holds the species mixed. The contact of grains i and j is
 * the scene's law with the pair's own coefficients, prepared once per species pair: the reduced
 * mass M_ij = m_i m_j / (m_i + m_j), so a law calibrated to a restitution (the spring-dashpot's
 * damping from eps_n) gives every pair that eps_n; hertz with the effective radius R_ij = r_i r_j /
 * (r_i + r_j): k_h,ij = k_h sqrt(R_ij / R_00), the scene's k_h being that of two grains of the first
 * species. The contact distance is r_i + r_j. The time step resolves the shortest contact of all
 * pairs. What runs with species so far: 1D, 2D and 3D, the verlet and the event integrator
 * (smooth hard rods, discs and spheres of species lists: src/integrators/event), a normal force
 * law or event rule, tangential laws without history and rotation with verlet, walls and gravity
 * with verlet, the random force (the same D on every
 * grain, so the kicks are sqrt(2 D dt) / m_i) or no driving; the rest is refused here (and, with
 * the file and line, by the scene). The Fisher-Yates deal draws word 2 of the placement stream
 * in 1D and 2D and word 4 in 3D, whose random placement draws words 0 to 2. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/noise.h"
#include "models/list.h"

int gr_species_counts(int N, int ns, const double *fraction, int *count)
{
    int used = 0;
    for (int a = 0; a < ns; a++) {
        count[a] = a + 1 < ns ? (int)lround(fraction[a] * N) : N - used;
        used += count[a];
        if (count[a] < 0) {
            return GR_EINVAL;
        }
    }
    return GR_OK;
}

/* What a run with species does not cover yet: the first such setting, or NULL. */
static const char *not_covered(const gr_sim *s)
{
    const gr_sim_params *p = &s->params;
    /* the history law: species lists, or a distribution with the linear normal law (its k_t =
     * kt_ratio k_s is every pair's; hertz's k_t follows each pair's linearised contact); rolling:
     * the verlet integrator; com mode: the verlet integrator */
    return !p->integrator->species ? "[integrator] kind"
           : p->tangential && ((p->size_distribution && gr_model_keeps_history(p->tangential) &&
                                p->normal != &gr_model_spring_dashpot) ||
                               p->integrator->instantaneous)
               ? "[model] tangential"
           : p->rolling && p->integrator->instantaneous                    ? "[model] rolling"
           : p->noise_mode == GR_NOISE_COM && p->integrator->instantaneous ? "[noise] mode = com"
           : p->noise_precision == GR_NOISE_SINGLE               ? "[noise] precision = single"
           : !(p->normal && (p->normal->kind & GR_MODEL_NORMAL)) ? "[model] normal"
                                                                 : NULL;
}

/* The standard normal distribution function. */
static double normal_cdf(double z) { return 0.5 * erfc(-z / sqrt(2.0)); }

double gr_size_radius(int kind, double rmin, double rmax, double median, double sigma,
                      uint64_t seed, int i)
{
    /* the placement stream's word 3 (placements draw words 0 and 1, the species' deal 2) */
    const double u = gr_noise_uniform(seed, GR_STREAM_PLACEMENT, (uint64_t)i, 3);
    if (kind != GR_SIZE_LOGNORMAL) {
        return rmin + (rmax - rmin) * u;
    }
    /* lognormal truncated to [rmin, rmax]: the normal quantile between the bounds' by bisection */
    const double za = (log(rmin) - log(median)) / sigma, zb = (log(rmax) - log(median)) / sigma;
    const double q = normal_cdf(za) + u * (normal_cdf(zb) - normal_cdf(za));
    double lo = za, hi = zb;
    for (int k = 0; k < 100; k++) {
        const double mid = 0.5 * (lo + hi);
        if (normal_cdf(mid) < q) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return fmin(rmax, fmax(rmin, median * exp(sigma * 0.5 * (lo + hi))));
}

double gr_size_mass(int dim, double density, double r)
{
    return dim == 1   ? density * 2.0 * r
           : dim == 3 ? density * 4.0 / 3.0 * M_PI * r * r * r
                      : density * M_PI * r * r;
}

/* A continuous radius distribution: each grain its own radius and mass (density), one "species"
 * with the pairs' coefficients scaled in the kernel (cc_pair NULL). */
static int size_setup(gr_sim *s, gr_error *err)
{
    const gr_sim_params *p = &s->params;
    const int n = s->n;
    const char *what = not_covered(s); /* walls and gravity run (walls.c: each grain's contact
                                          * scaled from the walls' reference, wall_coeffs) */
    if (!what && p->normal == &gr_model_hertz &&
        ((const hertz_own *)(const void *)(p->contact.own + offsetof(gr_own_layout, hertz)))
            ->viscoelastic) {
        what = "[model] viscoelastic = true"; /* its damping is not calibrated per pair */
    }
    if (what) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: %s: not available with a radius distribution yet; it runs in 1D, "
            "2D and 3D with the verlet integrator, spring_dashpot or hertz (viscoelastic = "
            "false) alone, periodic or between walls under gravity, and the random "
            "force or no driving (docs/mixtures.md)",
            p->source, what);
    }
    const bool logn = p->size_distribution == GR_SIZE_LOGNORMAL;
    if (p->n_species >= 2 || !(p->size_min > 0.0 && p->size_max > p->size_min) ||
        !isfinite(p->size_max) || !(p->size_density > 0.0 && isfinite(p->size_density)) ||
        (logn && !(p->size_median > 0.0 && p->size_sigma > 0.0 && isfinite(p->size_sigma)))) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [species] distribution: radius_min = %g m, radius_max = %g m, density "
                       "= %g, median %g m, sigma %g, %d species; allowed: 0 < radius_min < "
                       "radius_max, density > 0, lognormal median and sigma > 0, no species list",
                       p->source, p->size_min, p->size_max, p->size_density, p->size_median,
                       p->size_sigma, p->n_species);
    }
    s->nsp = 1;
    s->species = calloc((size_t)n + 1, sizeof(int)); /* all 0: one species, radii of their own */
    s->rad = calloc((size_t)n + 1, sizeof(double));
    s->mass_i = calloc((size_t)n + 1, sizeof(double));
    s->inv_m = calloc((size_t)n + 1, sizeof(double));
    if (!s->species || !s->rad || !s->mass_i || !s->inv_m) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the radii of %d grains", n);
    }
    double msum = 0.0, rmax = 0.0;
    for (int i = 0; i < n; i++) {
        const double r = gr_size_radius(p->size_distribution, p->size_min, p->size_max,
                                        p->size_median, p->size_sigma, p->seed, i);
        s->rad[i] = r;
        s->mass_i[i] = gr_size_mass(p->dim, p->size_density, r);
        s->inv_m[i] = 1.0 / s->mass_i[i];
        msum += s->mass_i[i];
        rmax = fmax(rmax, r);
    }
    s->d = 2.0 * rmax;
    s->mass = n > 0 ? msum / n : 1.0;
    return GR_OK;
}

int gr_species_setup(gr_sim *s, gr_error *err)
{
    const gr_sim_params *p = &s->params;
    const int ns = p->n_species, n = s->n;
    if (p->size_distribution != GR_SIZE_NONE) {
        return size_setup(s, err);
    }
    if (ns < 2) {
        return GR_OK;
    }
    if (ns > GR_MAX_SPECIES) {
        return GR_FAIL(err, GR_EINVAL, "%s: [species] %d species; allowed: 2 to %d", p->source, ns,
                       GR_MAX_SPECIES);
    }
    const char *what = not_covered(s);
    if (what) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: %s: not available with [species] yet; a mixture runs in 1D, 2D and 3D "
            "with the verlet, event or hybrid integrator, a normal force law, tangential laws "
            "(with verlet the history law with species lists, and rolling "
            "resistance), walls and gravity, and the random force, no driving or "
            "(verlet) the Langevin bath (docs/mixtures.md)",
            p->source, what);
    }
    int total = 0;
    double dmax = 0.0;
    for (int a = 0; a < ns; a++) {
        if (!(p->species_radius[a] > 0.0) || !(p->species_mass[a] > 0.0) ||
            !isfinite(p->species_radius[a]) || !isfinite(p->species_mass[a]) ||
            p->species_count[a] < 0) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [species] species %d has radius %g m, mass %g kg, %d grains; "
                           "allowed: radius and mass finite and > 0, count >= 0",
                           p->source, a + 1, p->species_radius[a], p->species_mass[a],
                           p->species_count[a]);
        }
        total += p->species_count[a];
        dmax = fmax(dmax, 2.0 * p->species_radius[a]);
    }
    if (total != n) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [species] the species' counts sum to %d grains, [system] N = %d",
                       p->source, total, n);
    }
    s->nsp = ns;
    s->species = calloc((size_t)n + 1, sizeof(int));
    s->rad = calloc((size_t)n + 1, sizeof(double));
    s->mass_i = calloc((size_t)n + 1, sizeof(double));
    s->inv_m = calloc((size_t)n + 1, sizeof(double));
    s->cc_pair = calloc((size_t)ns * ns, sizeof(gr_contact_coeffs));
    if (!s->species || !s->rad || !s->mass_i || !s->inv_m || !s->cc_pair) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the species of %d grains", n);
    }
    for (int a = 0, i = 0; a < ns; a++) {
        for (int k = 0; k < p->species_count[a]; k++) {
            s->species[i++] = a;
        }
    }
    /* 3D placements draw word 2 (z) too: the deal takes word 4 there, which nothing else draws */
    const uint64_t word = p->dim == 3 ? 4 : 2;
    for (int i = n - 1; i > 0; i--) { /* Fisher-Yates, a pure function of the seed */
        const int j =
            (int)(gr_noise_uniform(p->seed, GR_STREAM_PLACEMENT, (uint64_t)i, word) * (i + 1));
        const int t = s->species[i];
        s->species[i] = s->species[j < i ? j : i];
        s->species[j < i ? j : i] = t;
    }
    double msum = 0.0;
    for (int i = 0; i < n; i++) {
        const int a = s->species[i];
        s->rad[i] = p->species_radius[a];
        s->mass_i[i] = p->species_mass[a];
        s->inv_m[i] = 1.0 / p->species_mass[a];
        msum += s->mass_i[i];
    }
    for (int a = 0; a < ns; a++) {
        for (int b = 0; b < ns; b++) {
            s->d_pair[a * ns + b] = p->species_radius[a] + p->species_radius[b];
        }
    }
    s->d = dmax;
    s->mass = n > 0 ? msum / n : p->species_mass[0];
    return GR_OK;
}

/* The contact parameters and reduced mass of grains of radii ra, rb and masses ma, mb; r0 the
 * radius of the grains the scene's k_h is for (hertz: k_h ~ sqrt(R_eff)). */
static void radii_params(const gr_sim_params *p, double ra, double rb, double ma, double mb,
                         double r0, gr_contact_params *cp, double *m12)
{
    *cp = p->contact;
    *m12 = ma * mb / (ma + mb);
    /* hard_sphere's eps_n(v) (viscoelastic = true) is hertz's, with hertz's k_h */
    if (p->normal == &gr_model_hertz || p->normal == &gr_model_hard_sphere) {
        hertz_own *o = (hertz_own *)(void *)(cp->own + offsetof(gr_own_layout, hertz));
        o->k_h *= sqrt(ra * rb / (ra + rb) / (0.5 * r0));
    }
}

/* The same for species pair (a, b); the scene's k_h is that of two grains of species 0. */
static void pair_params(const gr_sim_params *p, int a, int b, gr_contact_params *cp, double *m12)
{
    radii_params(p, p->species_radius[a], p->species_radius[b], p->species_mass[a],
                 p->species_mass[b], p->species_radius[0], cp, m12);
}

int gr_species_pair_coeffs(const gr_sim_params *p, int a, int b, gr_contact_coeffs *out,
                           gr_error *err)
{
    gr_contact_params cp;
    double m;
    pair_params(p, a, b, &cp, &m);
    return gr_contact_prepare(p->normal, p->tangential, &cp, m, 0.0, out, err);
}

/* A distribution's reference: the shortest contact among the pairs of its extreme grains (the
 * scene's k_h is that of two grains of radius_min); its reduced mass m12 and effective radius r12
 * are what every pair's coefficients are scaled from (gr_size_scaled). */
static void size_reference_params(const gr_sim_params *q, gr_contact_params *p, double *m12,
                                  double *r12)
{
    const double r[2] = {q->size_min, q->size_max};
    double best = INFINITY;
    for (int a = 0; a < 2; a++) {
        for (int b = a; b < 2; b++) {
            const double ma = gr_size_mass(q->dim, q->size_density, r[a]),
                         mb = gr_size_mass(q->dim, q->size_density, r[b]);
            gr_contact_params cp;
            double m;
            gr_contact_coeffs c;
            gr_error e;
            radii_params(q, r[a], r[b], ma, mb, q->size_min, &cp, &m);
            const double tc = gr_contact_prepare(q->normal, NULL, &cp, m, 0.0, &c, &e) == GR_OK
                                  ? c.t_c
                                  : (double)INFINITY;
            if (tc < best || (a == 0 && b == 0)) { /* the first pair stands in if all fail */
                best = fmin(best, tc);
                *p = cp;
                *m12 = m;
                *r12 = r[a] * r[b] / (r[a] + r[b]);
            }
        }
    }
}

static void size_reference(gr_sim *s, gr_contact_params *p, double *m12)
{
    size_reference_params(&s->params, p, m12, &s->cont_r);
    s->cont_m12 = *m12;
}

int gr_size_reference_coeffs(const gr_sim_params *p, gr_contact_coeffs *out, double *m_ref,
                             double *r_ref, gr_error *err)
{
    gr_contact_params cp;
    size_reference_params(p, &cp, m_ref, r_ref);
    return gr_contact_prepare(p->normal, p->tangential, &cp, *m_ref, 0.0, out, err);
}

void gr_contact_size_scaled(const gr_contact_coeffs *ref, double m_ref, double r_ref, double M,
                            double R, gr_contact_coeffs *c)
{
    gr_size_scaled(ref, m_ref, r_ref, M, R, c);
}

void gr_species_reference(gr_sim *s, gr_contact_params *p, double *m12)
{
    if (!s->cc_pair) { /* a radius distribution */
        size_reference(s, p, m12);
        return;
    }
    const int ns = s->nsp;
    double best = INFINITY;
    for (int a = 0; a < ns; a++) {
        for (int b = a; b < ns; b++) {
            gr_contact_params cp;
            double m;
            gr_contact_coeffs c;
            gr_error e;
            pair_params(&s->params, a, b, &cp, &m);
            if (gr_contact_prepare(s->params.normal, NULL, &cp, m, 0.0, &c, &e) == GR_OK &&
                c.t_c < best) {
                best = c.t_c;
                *p = cp;
                *m12 = m;
            }
        }
    }
    if (!isfinite(best)) { /* every pair failed: the reference's own prepare reports why */
        pair_params(&s->params, 0, 0, p, m12);
    }
}

int gr_species_wall_coeffs(gr_sim *s, const gr_contact_params *wp, double dt, gr_error *err)
{
    const gr_sim_params *p = &s->params;
    s->wall_cc_sp = calloc((size_t)s->nsp, sizeof(gr_contact_coeffs));
    if (!s->wall_cc_sp) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the walls' contacts of %d species",
                       s->nsp);
    }
    for (int a = 0; a < s->nsp; a++) {
        /* the grain against an infinite mass: reduced mass m_a; hertz's k_h as for its own pair */
        gr_contact_params cp;
        double m12;
        radii_params(p, p->species_radius[a], p->species_radius[a], p->species_mass[a],
                     p->species_mass[a], p->species_radius[0], &cp, &m12);
        gr_contact_params w = *wp;
        memcpy(w.own, cp.own, sizeof w.own);
        int rc = gr_contact_prepare(p->normal, s->dim >= 2 ? p->tangential : NULL, &w,
                                    p->species_mass[a], dt, &s->wall_cc_sp[a], err);
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

int gr_species_coeffs(gr_sim *s, double dt, gr_error *err)
{
    if (!s->cc_pair) { /* a radius distribution: the kernel scales the reference (cc) per pair */
        return GR_OK;
    }
    const int ns = s->nsp;
    for (int a = 0; a < ns; a++) {
        for (int b = 0; b < ns; b++) {
            gr_contact_params cp;
            double m;
            pair_params(&s->params, a, b, &cp, &m);
            /* the tangential law too, k_t and gamma_t of a history law with the pair's M_ij */
            int rc = gr_contact_prepare(s->params.normal, s->params.tangential, &cp, m, dt,
                                        &s->cc_pair[a * ns + b], err);
            if (!rc) { /* the rolling law's (kernels_poly.c gives it the pair's R_ij) */
                rc = gr_contact_prepare_rolling(s->params.rolling, &cp, m, dt,
                                                &s->cc_pair[a * ns + b], err);
            }
            if (rc) {
                return rc;
            }
        }
    }
    return GR_OK;
}
