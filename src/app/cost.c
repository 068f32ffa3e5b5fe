/* The error of a time step in a scene's observables and the recommendation of `granule cost`
 * (include/granule/cost.h explains the method). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/collide.h"
#include "granule/cost.h"

const char *gr_cost_observable_name(gr_cost_observable o)
{
    return o == GR_COST_LOSS ? "loss" : "T";
}

int gr_cost_observable_parse(const char *name)
{
    if (!strcmp(name, "loss")) {
        return GR_COST_LOSS;
    }
    if (!strcmp(name, "T")) {
        return GR_COST_T;
    }
    return -1;
}

void gr_cost_request_default(gr_cost_request *r)
{
    r->observable = GR_COST_T;
    r->tolerance = 0.01;
    r->calibrate_seconds = 10.0;
    r->phases = 16;
}

/* The candidate time steps, as steps per contact: from well resolved to past velocity Verlet's
 * stability limit for an undamped spring (w0 dt = 2, i.e. pi / 2 = 1.6 steps per contact). */
static const double ladder[] = {64, 45, 32, 23, 16, 11, 8, 6, 4.5, 3.5, 2.5};
#define LADDER_N ((int)(sizeof ladder / sizeof ladder[0]))

static int cmp_dt(const void *a, const void *b)
{
    const gr_cost_candidate *x = a, *y = b;
    return (x->dt > y->dt) - (x->dt < y->dt);
}

/* The loss of the collision of case `number` at time step dt against the CVODE reference, relative
 * to the reference loss (or, for a contact that loses almost nothing, eps -> 1, to the collision's
 * energy: the loss is a fraction of it): the mean and the worst (largest in magnitude) over the
 * contact phases; false when the contact blew up in some phase (non-finite, or off by more than
 * half the collision's energy: past the stability limit). */
static bool loss_errors(gr_collide_setup su, const gr_collision_case *cs, double ref, int phases,
                        double *mean, double *worst)
{
    const double scale = ref > 1e-3 ? ref : 1.0;
    double sum = 0.0, w = 0.0;
    *mean = *worst = (double)NAN;
    for (int k = 0; k < phases; k++) {
        su.phase = (k + 0.5) / phases;
        gr_collide_result r;
        gr_error e = {0};
        if (gr_collide_run(&su, cs, &r, &e) || !isfinite(r.energy_loss) ||
            !(fabs(r.energy_loss - ref) < 0.5)) {
            return false;
        }
        double d = (r.energy_loss - ref) / scale;
        sum += d;
        if (fabs(d) > fabs(w)) {
            w = d;
        }
    }
    *mean = sum / phases;
    *worst = w;
    return true;
}

/* Many-body contacts: a particle pressed between neighbours vibrates faster than a pair. The
 * stiffest mode of a 1D chain of contacts has 2x the squared frequency of a binary contact, that of
 * a close-packed (triangular) 2D cluster 3x, that of a close-packed (FCC) 3D cluster 4x (largest
 * eigenvalue of the lattice's dynamical matrix with nearest-neighbour springs, 4 k/m, 6 k/m and
 * 8 k/m (the longitudinal mode at the X point), against 2 k/m for the pair's relative motion);
 * with the dashpots scaled alike it is a binary contact with the mass divided by that factor, i.e.
 * the same collision stepped at dt sqrt(factor). A time step is usable only if that collision is
 * still stable, and the cluster modes dissipate with its error. */
static double cluster_factor(int dim) { return dim == 1 ? 2.0 : dim == 2 ? 3.0 : 4.0; }

gr_collide_setup gr_cost_pair(const gr_scene *sc)
{
    gr_collide_setup su;
    gr_collide_setup_default(&su);
    su.normal = sc->normal;
    su.tangential = sc->tangential;
    su.contact = sc->contact;
    su.mass = sc->mass;
    su.radius = sc->radius;
    su.dim = sc->dim;
    su.force_dt = true;
    return su;
}

int gr_cost_errors(const gr_scene *sc, const gr_cost_request *rq, gr_cost_answer *out,
                   gr_error *err)
{
    memset(out, 0, sizeof *out);
    out->best = out->scene = -1;
    out->wall_per_simulated = out->wall_per_simulated_err = NAN;
    out->predicted_wall = out->predicted_wall_err = out->particle_steps_per_second = NAN;
    out->best_option = -1;
    out->simulated_seconds = sc->warmup + sc->duration;
    if (sc->normal->kind & GR_MODEL_EVENT) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] normal = %s: its collisions are instantaneous rules, exact at any "
                       "kick interval; "
                       "there is no time step to choose (granule cost answers for force laws)",
                       sc->normal->name);
    }
    if (!(rq->tolerance > 0.0 && rq->tolerance < 1.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "tolerance %g: give a relative tolerance in (0, 1), e.g. 1%%",
                       rq->tolerance);
    }
    gr_contact_coeffs cc;
    const double probe_dt = sc->dt > 0.0 ? sc->dt : 1e-6;
    if (gr_contact_prepare(sc->normal, sc->tangential, &sc->contact, gr_scene_m12(sc), probe_dt,
                           &cc, err)) {
        return err->code;
    }
    if (!(cc.t_c > 0.0 && isfinite(cc.t_c))) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the contact of this scene has no finite duration (t_c = %g s): nothing to resolve",
            cc.t_c);
    }
    out->t_c = cc.t_c;
    const double scene_dt = sc->dt > 0.0 ? sc->dt : cc.t_c / sc->steps_per_contact;
    for (int i = 0; i < LADDER_N; i++) {
        const double dt = cc.t_c / ladder[i];
        if (fabs(dt / scene_dt - 1.0) >
            0.02) { /* the scene's own dt stands for a ladder step next to it */
            out->c[out->n++] = (gr_cost_candidate){.dt = dt};
        }
    }
    out->c[out->n++] = (gr_cost_candidate){.dt = scene_dt, .scene_dt = true};
    qsort(out->c, (size_t)out->n, sizeof out->c[0], cmp_dt);

    gr_collide_setup su = gr_cost_pair(sc);
    /* head-on, and oblique (2D and 3D: a collision without initial spins stays in the plane of
     * the normal and the relative velocity, so 3D takes the same two cases) */
    const int cases[2] = {1, 3}, n_cases = sc->dim >= 2 ? 2 : 1;
    double ref[2];
    gr_collision_case cs[2];
    for (int k = 0; k < n_cases; k++) {
        gr_collide_result r;
        if (gr_collision_case_table21(cases[k], sc->radius, &cs[k], err) ||
            gr_collide_reference(&su, &cs[k], &r, err)) {
            return err->code;
        }
        ref[k] = r.energy_loss;
    }
    const int phases = rq->phases > 0 ? rq->phases : 16;
    for (int i = 0; i < out->n; i++) {
        gr_cost_candidate *c = &out->c[i];
        if (c->scene_dt) {
            out->scene = i;
        }
        c->steps_per_contact = cc.t_c / c->dt;
        double mean_sum = 0.0, worst = 0.0, cluster_sum = 0.0;
        c->finite = true;
        for (int k = 0; k < n_cases && c->finite; k++) {
            double m = NAN, w = NAN, mc = NAN, wc = NAN;
            su.dt = c->dt;
            c->finite = loss_errors(su, &cs[k], ref[k], phases, &m, &w);
            su.dt = c->dt * sqrt(cluster_factor(sc->dim));
            c->finite = c->finite && loss_errors(su, &cs[k], ref[k], phases, &mc, &wc);
            mean_sum += m;
            cluster_sum += mc;
            worst = fabs(w) > fabs(worst) ? w : worst;
        }
        c->loss_error_mean = c->finite ? mean_sum / n_cases : (double)NAN;
        c->loss_error_worst = c->finite ? worst : (double)NAN;
        c->cluster_loss_error = c->finite ? cluster_sum / n_cases : (double)NAN;
        /* T ~ (1 - eps^2)^(-2/3) in the homogeneous driven gas (cost.h), with the larger of the
         * binary and the cluster-mode loss errors */
        const double dl = fabs(c->cluster_loss_error) > fabs(c->loss_error_mean)
                              ? c->cluster_loss_error
                              : c->loss_error_mean;
        c->error = rq->observable == GR_COST_LOSS ? c->loss_error_worst : -2.0 / 3.0 * dl;
    }
    /* a candidate meets the tolerance only if every finer one does too: an error that changes
     * sign between two time steps is small there by accident, not by resolution */
    bool all_so_far = true;
    for (int i = 0; i < out->n; i++) {
        gr_cost_candidate *c = &out->c[i];
        all_so_far = all_so_far && c->finite && fabs(c->error) <= rq->tolerance;
        c->meets = all_so_far;
        if (c->meets) {
            out->best = i;
        }
    }
    return GR_OK;
}

int gr_cost_advise(const gr_scene *sc, const gr_cost_request *rq, gr_cost_answer *out,
                   gr_error *err)
{
    if (gr_cost_errors(sc, rq, out, err)) {
        return err->code;
    }
    if (out->best >= 0 && rq->calibrate_seconds > 0.0) {
        return gr_cost_calibrate(sc, out->c[out->best].dt, rq->calibrate_seconds, out, err);
    }
    return GR_OK;
}
