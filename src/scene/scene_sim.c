/* From a scene to a simulation: the scene's engine keys copied into the core's plain parameter
 * struct (the core never sees gr_scene), and the scene-level gr_sim_create* conveniences; and to
 * the observables' plain setup (the analysis layer never sees gr_scene either). */
#include <math.h>
#include <stdio.h>

#include "granule/scene.h"
#include "scene/scene_species.h"

void gr_scene_sim_params(const gr_scene *s, gr_sim_params *p)
{
    *p = (gr_sim_params){.dim = s->dim,
                         .N = s->N,
                         .L = s->L,
                         .radius = s->radius,
                         .mass = s->mass,
                         .placement = s->placement,
                         .v0 = s->v0,
                         .omega0 = s->omega0,
                         .normal = s->normal,
                         .tangential = s->tangential,
                         .rolling = s->rolling,
                         .contact = s->contact,
                         .D = s->D,
                         .noise_mode = s->noise_mode,
                         .com_interval = s->com_interval,
                         .noise_precision = s->noise_precision,
                         .driving = s->driving,
                         .driving_params = s->driving_params,
                         .walls = {s->boundary[0] != 0, s->boundary[1] != 0, s->boundary[2] != 0},
                         .gravity = {s->gravity[0], s->gravity[1], s->gravity[2]},
                         .vibrate = s->vibrate,
                         .amplitude = s->amplitude,
                         .frequency = s->frequency,
                         .motion = s->motion,
                         .wall_coeffs = isfinite(s->wall_eps_n) && isfinite(s->wall_eps_t) &&
                                        isfinite(s->wall_mu),
                         .wall_eps_n = s->wall_eps_n,
                         .wall_eps_t = s->wall_eps_t,
                         .wall_mu = s->wall_mu,
                         .integrator = s->integrator,
                         .dt = s->dt,
                         .steps_per_contact = s->steps_per_contact,
                         .force_dt = s->force_dt,
                         .skin = s->skin,
                         .free_flight = s->free_flight,
                         .kick_interval = s->kick_interval,
                         .kick_interval_default = s->kick_interval_default,
                         .seed = s->seed};
    snprintf(p->source, sizeof p->source, "%s", s->source);
    p->n_species = s->n_species; /* [species] (docs/mixtures.md); 0: one species */
    p->size_distribution = s->size_distribution;
    p->size_min = s->radius_min;
    p->size_max = s->radius_max;
    p->size_median = s->radius_median;
    p->size_sigma = s->radius_sigma;
    p->size_density = s->size_distribution ? s->species_density.v[0] : 0.0;
    for (int a = 0; a < s->n_species; a++) {
        p->species_radius[a] = s->species_radius.v[a];
        p->species_mass[a] = s->species_masses[a];
        p->species_count[a] = s->species_count[a];
    }
}

int gr_scene_obs_setup(const gr_scene *s, gr_obs_setup *out, gr_error *err)
{
    *out =
        (gr_obs_setup){.source = s->source,
                       .observables = s->observables,
                       .analysis = &s->analysis,
                       .dim = s->dim,
                       .N = s->N,
                       .L = s->L,
                       .radius = s->radius,
                       .mass = s->mass,
                       .D = s->D,
                       .eps_n = s->contact.eps_n,
                       .eps_t = s->contact.eps_t,
                       .tangential = s->tangential ? s->tangential->name : NULL,
                       .tangential_constant_eps_t = s->tangential && s->tangential->constant_eps_t,
                       .walls = {s->boundary[0] != 0, s->boundary[1] != 0, s->boundary[2] != 0},
                       .n_species = s->n_species,
                       .sizes = s->n_species >= 2 || s->size_distribution};
    gr_scene_radius_moments(s, &out->radius_mean, &out->radius_sq_mean);
    if (s->normal && s->n_species >= 2) { /* the pressure's virial per species pair */
        gr_sim_params p;
        gr_scene_sim_params(s, &p);
        for (int a = 0; a < s->n_species; a++) {
            for (int b = 0; b < s->n_species; b++) {
                int rc =
                    gr_species_pair_coeffs(&p, a, b, &out->contact_pair[a * s->n_species + b], err);
                if (rc) {
                    return rc;
                }
            }
        }
    }
    if (s->normal && s->size_distribution) { /* the pressure's virial, scaled per pair */
        gr_sim_params p;
        gr_scene_sim_params(s, &p);
        int rc = gr_size_reference_coeffs(&p, &out->size_contact, &out->size_m_ref,
                                          &out->size_r_ref, err);
        if (rc) {
            return rc;
        }
    }
    if (s->normal) {
        int rc = gr_contact_prepare(s->normal, s->tangential, &s->contact, gr_scene_m12(s), 0.0,
                                    &out->contact, err);
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

int gr_scene_observer(const gr_scene *s, gr_observer **out, gr_error *err)
{
    gr_obs_setup setup;
    int rc = gr_scene_obs_setup(s, &setup, err);
    return rc ? rc : gr_observer_create(&setup, out, err);
}

int gr_scene_observable(const gr_observable_type *t, const gr_scene *s, void **state, gr_error *err)
{
    gr_obs_setup setup;
    *state = NULL;
    int rc = gr_scene_obs_setup(s, &setup, err);
    return rc ? rc : gr_observable_create(t, &setup, state, err);
}

int gr_sim_create(const gr_scene *scene, gr_sim **out, gr_error *err)
{
    gr_sim_params p;
    gr_scene_sim_params(scene, &p);
    return gr_sim_new(&p, out, err);
}

int gr_sim_create_with_state(const gr_scene *scene, int n, const double *x, const double *y,
                             const double *vx, const double *vy, gr_sim **out, gr_error *err)
{
    gr_sim_params p;
    gr_scene_sim_params(scene, &p);
    return gr_sim_new_with_state(&p, n, x, y, vx, vy, out, err);
}

int gr_sim_create_canonical(const gr_scene *scene, int n, const double *x, const double *y,
                            const double *vx, const double *vy, gr_sim **out, gr_error *err)
{
    gr_sim_params p;
    gr_scene_sim_params(scene, &p);
    return gr_sim_new_canonical(&p, n, x, y, vx, vy, out, err);
}
