/* The resolved scene as JSON (for summary.json) and its hash (for CSV headers). */
#include <math.h>
#include <cjson/cJSON.h>
#include <stdio.h>
#include <string.h>

#include "scene/scene_json.h"

cJSON *gr_scene_to_json(const gr_scene *s)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *sys = cJSON_AddObjectToObject(root, "system");
    cJSON_AddNumberToObject(sys, "dim", s->dim);
    cJSON_AddNumberToObject(sys, "N", s->N);
    cJSON_AddNumberToObject(sys, "L", s->L);
    if (s->dim >= 2) { /* 2D: N pi r^2 / L^2; 3D: N (4/3) pi r^3 / L^3 */
        cJSON_AddNumberToObject(sys, "packing_fraction", s->packing_fraction);
    } else {
        cJSON_AddNumberToObject(sys, "reduced_length", s->reduced_length);
    }
    cJSON_AddNumberToObject(sys, "radius", s->radius);
    cJSON_AddNumberToObject(sys, "mass", s->mass);
    cJSON *pl = cJSON_AddObjectToObject(root, "placement");
    cJSON_AddStringToObject(pl, "kind", gr_placement_name(s->placement));
    cJSON_AddNumberToObject(pl, "v0", s->v0);
    if (s->contact.rotation) {
        cJSON_AddNumberToObject(pl, "omega0",
                                s->omega0); /* only then (the hashes of other scenes stay) */
    }
    cJSON *m = cJSON_AddObjectToObject(root, "model");
    cJSON_AddStringToObject(m, "normal", s->normal ? s->normal->name : "none");
    cJSON_AddStringToObject(m, "tangential", s->tangential ? s->tangential->name : "none");
    if (s->rolling) {
        cJSON_AddStringToObject(m, "rolling",
                                s->rolling->name); /* only then (the hashes of other scenes stay) */
    }
    const gr_model *used[3] = {s->normal, s->tangential, s->rolling};
    for (int u = 0; u < 3; u++) {
        for (int i = 0; used[u] && i < used[u]->n_params; i++) {
            const gr_param *p = &used[u]->params[i];
            const char *slot = (const char *)&s->contact + p->offset;
            if (p->type == GR_PARAM_BOOL) {
                cJSON_AddBoolToObject(m, p->name, *(const bool *)slot);
            } else if (*(const double *)slot == GR_TC_OFF && strcmp(p->name, "tc") == 0) {
                cJSON_AddStringToObject(m, p->name, "off"); /* [model] tc = off */
            } else {
                cJSON_AddNumberToObject(m, p->name, *(const double *)slot);
            }
        }
    }
    if (s->driving &&
        s->driving != gr_driving_default()) { /* only then: the hashes of rfm scenes stay */
        cJSON *dr = cJSON_AddObjectToObject(root, "driving");
        cJSON_AddStringToObject(dr, "kind", s->driving->name);
        for (int i = 0; i < s->driving->n_params; i++) {
            const gr_param *p = &s->driving->params[i];
            cJSON_AddNumberToObject(
                dr, p->name, *(const double *)((const char *)&s->driving_params + p->offset));
        }
        if (s->driving->update ==
            GR_DRIVE_BATH) { /* the bath's noise strength (fluctuation-dissipation) */
            /* species: the first species' (T_bath is its temperature; species s has m_s / m_1
             * times it, docs/mixtures.md) */
            const double mb = s->n_species >= 2 ? s->species_masses[0] : s->mass;
            cJSON_AddNumberToObject(dr, "D_bath",
                                    mb * mb * s->driving_params.T_bath /
                                        (s->dim * s->driving_params.tau));
        }
    }
    if (s->boundary[0] || s->boundary[1] || s->boundary[2] || s->gravity[0] != 0.0 ||
        s->gravity[1] != 0.0 || s->gravity[2] != 0.0) {
        /* walls and gravity (docs/systems-walls-gravity.md): only then, so the periodic scenes'
         * hashes stay */
        cJSON *bd = cJSON_AddObjectToObject(root, "boundary");
        cJSON_AddStringToObject(bd, "x", s->boundary[0] ? "walls" : "periodic");
        if (s->dim >= 2) {
            cJSON_AddStringToObject(bd, "y", s->boundary[1] ? "walls" : "periodic");
        }
        if (s->dim == 3) {
            cJSON_AddStringToObject(bd, "z", s->boundary[2] ? "walls" : "periodic");
        }
        if (s->vibrate) {
            cJSON_AddStringToObject(bd, "vibrate",
                                    s->vibrate == 1   ? "x"
                                    : s->vibrate == 2 ? "y"
                                                      : "z");
            cJSON_AddNumberToObject(bd, "amplitude", s->amplitude);
            cJSON_AddNumberToObject(bd, "frequency", s->frequency);
            if (s->motion == GR_WALL_SAWTOOTH) {
                cJSON_AddStringToObject(bd, "motion", "sawtooth");
            }
        }
        /* the walls' own coefficients, where they are not the particles' (so the scenes without
         * them keep their hashes) */
        const double own[3] = {s->wall_eps_n, s->wall_eps_t, s->wall_mu},
                     model[3] = {s->contact.eps_n, s->contact.eps_t, s->contact.mu};
        static const char *const names[3] = {"eps_n", "eps_t", "mu"};
        for (int k = 0; k < 3; k++) {
            if (own[k] != model[k] && !isnan(own[k])) {
                cJSON_AddNumberToObject(bd, names[k], own[k]);
            }
        }
        cJSON *gv = cJSON_AddObjectToObject(root, "gravity");
        cJSON_AddNumberToObject(gv, "gx", s->gravity[0]);
        if (s->dim >= 2) {
            cJSON_AddNumberToObject(gv, "gy", s->gravity[1]);
        }
        if (s->dim == 3) {
            cJSON_AddNumberToObject(gv, "gz", s->gravity[2]);
        }
    }
    cJSON *nz = cJSON_AddObjectToObject(root, "noise");
    cJSON_AddNumberToObject(nz, "D", s->D);
    cJSON_AddStringToObject(nz, "mode", gr_noise_mode_name(s->noise_mode));
    cJSON_AddStringToObject(nz, "precision",
                            s->noise_precision == GR_NOISE_SINGLE ? "single" : "double");
    if (s->noise_mode == GR_NOISE_COM) {
        cJSON_AddNumberToObject(nz, "com_interval", s->com_interval);
    }
    cJSON *in = cJSON_AddObjectToObject(root, "integrator");
    cJSON_AddStringToObject(in, "kind", s->integrator->name);
    if (s->integrator->free_flight) {
        cJSON_AddStringToObject(in, "free_flight",
                                s->free_flight == GR_FREE_FLIGHT_EXACT ? "exact" : "kicks");
        cJSON_AddNumberToObject(in, "kick_interval", s->kick_interval);
    }
    if (s->dt > 0.0) {
        cJSON_AddNumberToObject(in, "dt", s->dt);
    } else {
        cJSON_AddNumberToObject(in, "steps_per_contact", s->steps_per_contact);
    }
    cJSON_AddBoolToObject(in, "force_dt", s->force_dt);
    cJSON_AddNumberToObject(in, "skin", s->skin);
    cJSON *run = cJSON_AddObjectToObject(root, "run");
    cJSON_AddNumberToObject(run, "warmup", s->warmup);
    cJSON_AddNumberToObject(run, "duration", s->duration);
    cJSON_AddNumberToObject(run, "sample_every", s->sample_every);
    char seed[32];
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)s->seed);
    cJSON_AddRawToObject(run, "seed", seed);
    cJSON *out = cJSON_AddObjectToObject(root, "output");
    cJSON_AddStringToObject(out, "dir", s->out_dir);
    cJSON_AddNumberToObject(out, "snapshot_every", s->snapshot_every);
    static const char *traj[] = {"snapshots", "xyz", "h5md"};
    cJSON_AddStringToObject(out, "trajectory", traj[s->trajectory]);
    cJSON_AddBoolToObject(out, "plots", s->plots);
    return root;
}

uint64_t gr_scene_hash(const gr_scene *s)
{
    cJSON *j = gr_scene_to_json(s);
    cJSON_DeleteItemFromObject(j, "output");     /* where results go does not change the physics */
    if (s->noise_precision == GR_NOISE_DOUBLE) { /* the default: hashes of double runs unchanged */
        cJSON_DeleteItemFromObject(cJSON_GetObjectItem(j, "noise"), "precision");
    }
    char *text = cJSON_PrintUnformatted(j);
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (const char *c = text; c && *c; c++) {
        h = (h ^ (unsigned char)*c) * 1099511628211ull;
    }
    cJSON_free(text);
    cJSON_Delete(j);
    return h;
}

/* The default of [model] key `name`, from the first registered model that has it (models share
 * a key's default), as JSON; NULL when no model has the key. */
static cJSON *model_param_default(const char *name)
{
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const gr_param *p = &gr_models[m]->params[i];
            if (!strcmp(p->name, name)) {
                return p->type == GR_PARAM_BOOL ? cJSON_CreateBool(p->def != 0.0)
                                                : cJSON_CreateNumber(p->def);
            }
        }
    }
    return NULL;
}

/* j as it reads back from a file (the seed is written raw, so it parses as a number); frees j */
static cJSON *normalised(cJSON *j)
{
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    cJSON *back = text ? cJSON_Parse(text) : NULL;
    cJSON_free(text);
    return back;
}

bool gr_scene_json_compatible(const cJSON *recorded, const gr_scene *now, char *why, size_t len)
{
    if (!cJSON_IsObject(recorded)) {
        snprintf(why, len, "no scene recorded");
        return false;
    }
    gr_scene d;
    gr_scene_default(&d);
    cJSON *cur = normalised(gr_scene_to_json(now)), *def = normalised(gr_scene_to_json(&d));
    if (!cur || !def) {
        cJSON_Delete(cur);
        cJSON_Delete(def);
        snprintf(why, len, "out of memory comparing scenes");
        return false;
    }
    bool ok = true;
    const cJSON *sec;
    cJSON_ArrayForEach(sec, cur)
    {
        if (!strcmp(sec->string, "output")) {
            continue;
        }
        const cJSON *rsec = cJSON_GetObjectItem(recorded, sec->string),
                    *dsec = cJSON_GetObjectItem(def, sec->string);
        const cJSON *item;
        cJSON_ArrayForEach(item, sec)
        {
            const cJSON *r = cJSON_GetObjectItem(rsec, item->string);
            if (r) {
                if (!cJSON_Compare(r, item, true)) {
                    char *a = cJSON_PrintUnformatted(r), *b = cJSON_PrintUnformatted(item);
                    snprintf(why, len, "[%s] %s was %s, now %s", sec->string, item->string,
                             a ? a : "?", b ? b : "?");
                    cJSON_free(a);
                    cJSON_free(b);
                    ok = false;
                }
            } else {
                cJSON *dm =
                    !strcmp(sec->string, "model") ? model_param_default(item->string) : NULL;
                const cJSON *dv = dm ? dm : cJSON_GetObjectItem(dsec, item->string);
                if (!dv || !cJSON_Compare(dv, item, true)) {
                    char *b = cJSON_PrintUnformatted(item);
                    snprintf(why, len, "[%s] %s = %s was not recorded and is not its default",
                             sec->string, item->string, b ? b : "?");
                    cJSON_free(b);
                    ok = false;
                }
                cJSON_Delete(dm);
            }
            if (!ok) {
                break;
            }
        }
        if (!ok) {
            break;
        }
    }
    /* a key the recorded run had and granule no longer knows */
    const cJSON *rsec;
    cJSON_ArrayForEach(rsec, recorded)
    {
        const cJSON *item;
        const cJSON *csec = cJSON_GetObjectItem(cur, rsec->string);
        if (!ok || !strcmp(rsec->string, "output") || !cJSON_IsObject(rsec)) {
            continue;
        }
        cJSON_ArrayForEach(item, rsec)
        {
            if (ok && !cJSON_GetObjectItem(csec, item->string)) {
                snprintf(why, len, "[%s] %s was recorded and is no longer a key of this scene",
                         rsec->string, item->string);
                ok = false;
            }
        }
    }
    cJSON_Delete(cur);
    cJSON_Delete(def);
    return ok;
}
