/* Looking models up, and the combination of a normal law with a tangential law. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/model.h"

/* gr_models, the list itself, is generated from models/list.h in models/registry.c. */

const gr_model *gr_model_find(const char *name)
{
    for (int i = 0; gr_models[i]; i++) {
        if (strcmp(gr_models[i]->name, name) == 0) {
            return gr_models[i];
        }
    }
    return NULL;
}

int gr_contact_prepare(const gr_model *normal, const gr_model *tangential,
                       const gr_contact_params *p, double m12, double dt, gr_contact_coeffs *c,
                       gr_error *err)
{
    memset(c, 0, sizeof *c);
    if (!normal || !(normal->kind & (GR_MODEL_NORMAL | GR_MODEL_EVENT))) {
        return GR_FAIL(err, GR_EINVAL, "no normal collision model given");
    }
    if (tangential && tangential->kind != GR_MODEL_TANGENTIAL) {
        return GR_FAIL(err, GR_EINVAL, "'%s' is not a tangential model", tangential->name);
    }
    c->normal_model = normal;
    c->tangential_model = tangential;
    /* an event rule (hard_sphere) carries its own contact-point rule (beta) */
    if (p->rotation && !(tangential && tangential->contact_point) &&
        !(normal->kind & GR_MODEL_EVENT)) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] rotation = true needs a tangential law that acts at the contact "
                       "point (%s)%s%s",
                       "tangential_dashpot, sliding_friction, tangential_spring",
                       tangential ? "; given " : ", none given",
                       tangential ? tangential->name : "");
    }
    int rc = normal->prepare(p, m12, dt, c, err);
    /* Rotation: two equal discs (mass m, radius R, I = q m R^2). An impulse J along t on j (-J on
     * i) changes g.t by J / m12 and, through the torques R J on both discs (same sign),
     * R (w_i + w_j) by 2 R^2 J / I = J / (q m12): the contact point's tangential velocity changes
     * by J (1 + 1/q) / m12, so m_t = m12 / (1 + 1/q) = m12 q / (1 + q) (m12 / 3 for a disc; for
     * spheres, q = 2/5, the familiar 2/7 m12, e.g. Luding, Granular Matter 10, 235 (2008)). */
    c->rotation = p->rotation;
    c->q = p->inertia_factor;
    c->m_t = p->rotation ? m12 * p->inertia_factor / (1.0 + p->inertia_factor) : m12;
    if (rc == GR_OK && tangential) {
        rc = tangential->prepare(p, m12, dt, c, err);
    }
    return rc;
}

int gr_contact_prepare_rolling(const gr_model *rolling, const gr_contact_params *p, double m12,
                               double dt, gr_contact_coeffs *c, gr_error *err)
{
    c->rolling_model = NULL;
    memset(c->law_r, 0, sizeof c->law_r);
    if (!rolling) {
        return GR_OK;
    }
    if (rolling->kind != GR_MODEL_ROLLING) {
        return GR_FAIL(err, GR_EINVAL, "[model] rolling = %s: not a rolling law", rolling->name);
    }
    c->rolling_model = rolling;
    return rolling->prepare(p, m12, dt, c, err);
}

void gr_contact_defaults(gr_contact_params *p)
{
    memset(p, 0, sizeof *p);
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const gr_param *d = &gr_models[m]->params[i];
            char *slot = (char *)p + d->offset;
            if (d->type == GR_PARAM_BOOL) {
                *(bool *)slot = d->def != 0.0;
            } else {
                *(double *)slot = d->def;
            }
        }
    }
}

int gr_contact_set(gr_contact_params *p, const char *name, const char *value, gr_error *err)
{
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const gr_param *d = &gr_models[m]->params[i];
            if (strcmp(d->name, name) != 0) {
                continue;
            }
            char *slot = (char *)p + d->offset;
            if (d->type == GR_PARAM_BOOL) {
                if (strcmp(value, "true") != 0 && strcmp(value, "false") != 0) {
                    return GR_FAIL(err, GR_EINVAL, "[model] %s = %s: allowed true or false", name,
                                   value);
                }
                *(bool *)slot = strcmp(value, "true") == 0;
                return GR_OK;
            }
            char *end = NULL;
            double x = strtod(value, &end);
            bool ok = end != value && *end == '\0' && isfinite(x) &&
                      (d->min_open ? x > d->min : x >= d->min) &&
                      (d->max_open ? x < d->max : x <= d->max);
            if (!ok) {
                return GR_FAIL(err, GR_EINVAL, "[model] %s = %s: allowed range %c%g, %g%c %s", name,
                               value, d->min_open ? '(' : '[', d->min, d->max,
                               d->max_open ? ')' : ']', d->unit);
            }
            *(double *)slot = x;
            return GR_OK;
        }
    }
    return GR_FAIL(err, GR_EINVAL,
                   "[model] %s: no model has this parameter (granule models lists them)", name);
}

/* the descriptor of the model parameter `name` (the first model declaring it: a key several
 * models declare has one place, checked by the conformance suite) */
static const gr_param *param_of(const char *name)
{
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            if (strcmp(gr_models[m]->params[i].name, name) == 0) {
                return &gr_models[m]->params[i];
            }
        }
    }
    return NULL;
}

int gr_contact_set_value(gr_contact_params *p, const char *name, double v, gr_error *err)
{
    const gr_param *d = param_of(name);
    if (!d) {
        return GR_FAIL(err, GR_EINVAL,
                       "[model] %s: no model has this parameter (granule models lists them)", name);
    }
    char *slot = (char *)p + d->offset;
    if (d->type == GR_PARAM_BOOL) {
        *(bool *)slot = v != 0.0;
        return GR_OK;
    }
    if (!(isfinite(v) && (d->min_open ? v > d->min : v >= d->min) &&
          (d->max_open ? v < d->max : v <= d->max))) {
        return GR_FAIL(err, GR_EINVAL, "[model] %s = %g: allowed range %c%g, %g%c %s", name, v,
                       d->min_open ? '(' : '[', d->min, d->max, d->max_open ? ')' : ']', d->unit);
    }
    *(double *)slot = v;
    return GR_OK;
}

double gr_contact_get(const gr_contact_params *p, const char *name)
{
    const gr_param *d = param_of(name);
    if (!d) {
        return NAN;
    }
    const char *slot = (const char *)p + d->offset;
    return d->type == GR_PARAM_BOOL ? (*(const bool *)slot ? 1.0 : 0.0) : *(const double *)slot;
}

double gr_contact_expected_loss(const gr_contact_coeffs *c, double speed, double angle_deg)
{
    const gr_model *nm = c->normal_model, *tm = c->tangential_model;
    double a = angle_deg * M_PI / 180.0, cos2 = cos(a) * cos(a), sin2 = 1.0 - cos2;
    double v_n = speed * sqrt(cos2), v_t = speed * sqrt(sin2);
    gr_normal_impact ni = {c->eps_n_exact, c->t_c, 1.0 + c->eps_n_exact};
    if (nm && nm->impact) {
        ni = nm->impact(c, v_n);
    }
    double et = 1.0;
    if (sin2 > 0.0) {
        const gr_model *law = tm ? tm : nm; /* an event rule carries its own tangential rule */
        if (law && law->restitution_t) {
            et = law->restitution_t(c, ni, v_n, v_t);
        } else if (tm && !(tm->inert && tm->inert(c))) {
            et = NAN; /* a law without a closed restitution law (tangential_spring): unknown */
        }
    }
    /* With rotation (discs not spinning before) the tangential impulse that brings the contact
     * point's velocity from v_t to et v_t leaves the fraction 1 - (1 - et^2) m_t / m12 of the
     * tangential energy in translation + rotation (docs/models.md, "Rotation"). */
    const double share = c->rotation ? c->m_t / c->m12 : 1.0;
    return (1.0 - ni.eps_n * ni.eps_n) * cos2 + share * (1.0 - et * et) * sin2;
}
