/* Comparisons (include/granule/compare.h): the model SPECs, the scene of each, and an earlier
 * comparison in the output folder. The table is in compare_table.c, the plots in compare_plots.c. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "granule/compare.h"
#include "granule/integrator.h"
#include "granule/model.h"
#include "io/checkpoint.h"

/* "a | b | c": the registered models of the given kinds */
static void model_names(int kinds, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = 0;
    for (int i = 0; gr_models[i] && len < size; i++) {
        if (gr_models[i]->kind & kinds) {
            len += (size_t)snprintf(buf + len, size - len, "%s%s", len ? " | " : "",
                                    gr_models[i]->name);
        }
    }
}

/* whether the model (NULL: none) has the scene key `name` among its parameters */
static bool model_has_param(const gr_model *m, const char *name)
{
    for (int i = 0; m && i < m->n_params; i++) {
        if (!strcmp(m->params[i].name, name)) {
            return true;
        }
    }
    return false;
}

/* the integrator's index in the registry (granule/integrator.h), -1 if none has that name */
static int integrator_find(const char *name)
{
    for (int i = 0; gr_integrators[i]; i++) {
        if (!strcmp(name, gr_integrators[i]->name)) {
            return i;
        }
    }
    return -1;
}

int gr_compare_spec_parse(const char *text, gr_compare_spec *spec, gr_error *err)
{
    memset(spec, 0, sizeof *spec);
    spec->integrator = -1;
    if (strlen(text) >= sizeof spec->text - 8) {
        return GR_FAIL(err, GR_EINVAL, "model spec '%.40s...' is too long (at most %zu characters)",
                       text, sizeof spec->text - 8);
    }
    snprintf(spec->text, sizeof spec->text, "%s", text);
    snprintf(spec->label, sizeof spec->label, "%s", text);
    for (char *c = spec->label; *c; c++) {
        *c = (*c == '+' || *c == '@') ? '_' : *c;
    }
    char buf[128], names[512];
    snprintf(buf, sizeof buf, "%s", text);
    char *at = strchr(buf, '@');
    if (at) {
        *at++ = 0;
    }
    /* the modifiers: clamp, rotation and at most one integrator */
    for (char *mod = at; mod;) {
        char *next = strchr(mod, '@');
        if (next) {
            *next++ = 0;
        }
        int kind = integrator_find(mod);
        if (!strcmp(mod, "clamp") && !spec->clamp) {
            spec->clamp = true;
        } else if (!strcmp(mod, "rotation") && !spec->rotation) {
            spec->rotation = true;
        } else if (kind >= 0 && spec->integrator < 0) {
            spec->integrator = kind;
        } else if (kind >= 0 || !strcmp(mod, "clamp") || !strcmp(mod, "rotation")) {
            return GR_FAIL(err, GR_EINVAL,
                           "'%s': @%s is given twice (or two integrators); one integrator, @clamp "
                           "and @rotation at most",
                           text, mod);
        } else {
            return GR_FAIL(err, GR_EINVAL,
                           "'%s': unknown modifier @%s; allowed: @clamp, @rotation and an "
                           "integrator @verlet | @event | @hybrid",
                           text, mod);
        }
        mod = next;
    }
    char *plus = strchr(buf, '+'), *plus2 = NULL;
    if (plus) {
        *plus++ = 0;
        plus2 = strchr(plus, '+');
        if (plus2) {
            *plus2++ = 0;
        }
    }
    const gr_model *normal = gr_model_find(buf);
    if (!normal || !(normal->kind & (GR_MODEL_NORMAL | GR_MODEL_EVENT))) {
        model_names(GR_MODEL_NORMAL | GR_MODEL_EVENT, names, sizeof names);
        return GR_FAIL(err, GR_EINVAL,
                       "'%s': unknown normal model '%s'; allowed: %s (granule models lists them)",
                       text, buf, names);
    }
    snprintf(spec->normal, sizeof spec->normal, "%.63s", buf);
    if (plus) {
        const gr_model *tan = gr_model_find(plus);
        if (!tan || !(tan->kind & GR_MODEL_TANGENTIAL)) {
            model_names(GR_MODEL_TANGENTIAL, names, sizeof names);
            return GR_FAIL(err, GR_EINVAL, "'%s': unknown tangential model '%s'; allowed: %s", text,
                           plus, names);
        }
        snprintf(spec->tangential, sizeof spec->tangential, "%.63s", plus);
    }
    if (plus2) {
        const gr_model *roll = gr_model_find(plus2);
        if (!roll || !(roll->kind & GR_MODEL_ROLLING)) {
            model_names(GR_MODEL_ROLLING, names, sizeof names);
            return GR_FAIL(err, GR_EINVAL, "'%s': unknown rolling model '%s'; allowed: %s", text,
                           plus2, names);
        }
        if (!spec->rotation) {
            return GR_FAIL(err, GR_EINVAL,
                           "'%s': a rolling law acts on spinning discs: add @rotation", text);
        }
        snprintf(spec->rolling, sizeof spec->rolling, "%.63s", plus2);
    }
    if (spec->rotation && !model_has_param(normal, "rotation") &&
        !model_has_param(plus ? gr_model_find(plus) : NULL, "rotation")) {
        return GR_FAIL(err, GR_EINVAL,
                       "'%s': @rotation needs a law that acts at the contact point: a tangential "
                       "law with the key "
                       "rotation (granule models) or an event rule that has it (hard_sphere)",
                       text);
    }
    return GR_OK;
}

int gr_compare_specs_parse(const char *list, gr_compare_spec *specs, int max, int *n, gr_error *err)
{
    *n = 0;
    char buf[2048];
    if (strlen(list) >= sizeof buf) {
        return GR_FAIL(err, GR_EINVAL, "--models: the list is too long (at most %zu characters)",
                       sizeof buf - 1);
    }
    snprintf(buf, sizeof buf, "%s", list);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (*n == max) {
            return GR_FAIL(err, GR_EINVAL, "--models: at most %d models in one comparison", max);
        }
        int rc = gr_compare_spec_parse(tok, &specs[*n], err);
        if (rc) {
            return rc;
        }
        for (int k = 0; k < *n; k++) {
            if (!strcmp(specs[k].label, specs[*n].label)) {
                return GR_FAIL(
                    err, GR_EINVAL,
                    "--models: '%s' and '%s' would share the folder %s; give each model once",
                    specs[k].text, specs[*n].text, specs[k].label);
            }
        }
        (*n)++;
    }
    if (*n == 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "--models: no model given (e.g. --models spring_dashpot,hard_sphere@event)");
    }
    return GR_OK;
}

int gr_compare_scene_load(const gr_compare_spec *spec, const char *scene_path,
                          const char *const *sets, int n_sets, const char *out, gr_scene *scene,
                          gr_error *err)
{
    /* the integrator: the spec's, else event for an event rule, else the scene's (verlet when the
     * scene is event-driven: a force law cannot run there) */
    const char *kind = spec->integrator >= 0 ? gr_integrators[spec->integrator]->name : NULL;
    const gr_model *normal = gr_model_find(spec->normal);
    if (!kind && normal && (normal->kind & GR_MODEL_EVENT)) {
        kind = "event";
    }
    if (!kind) {
        gr_scene base;
        gr_error ignored = {
            0}; /* a scene that does not load is refused below, with the spec's models */
        if (gr_scene_load_whole(&base, scene_path, sets, n_sets, &ignored) == GR_OK &&
            base.integrator) {
            kind = base.integrator->instantaneous ? "verlet" : base.integrator->name;
        }
    }
    /* rotation is decided by the spec where its models have the key (elsewhere the key would be
     * "ignored" and the scene's value cannot matter) */
    const bool has_rotation =
        model_has_param(normal, "rotation") ||
        (spec->tangential[0] && model_has_param(gr_model_find(spec->tangential), "rotation"));
    char assign[6][160];
    snprintf(assign[0], sizeof assign[0], "model.normal=%s", spec->normal);
    snprintf(assign[1], sizeof assign[1], "model.tangential=%s",
             spec->tangential[0] ? spec->tangential : "none");
    snprintf(assign[2], sizeof assign[2], "model.clamp=%s", spec->clamp ? "true" : "false");
    snprintf(assign[3], sizeof assign[3], "model.rotation=%s", spec->rotation ? "true" : "false");
    snprintf(assign[4], sizeof assign[4], "integrator.kind=%s", kind ? kind : "verlet");
    snprintf(assign[5], sizeof assign[5], "model.rolling=%s",
             spec->rolling[0] ? spec->rolling : "none");
    const char *all[80];
    int m = 0;
    for (int i = 0; i < n_sets && m < 74; i++) {
        all[m++] = sets[i];
    }
    for (int i = 0; i < 6; i++) {
        if ((i == 3 && !has_rotation) || (i == 4 && !kind)) {
            continue;
        }
        all[m++] = assign[i];
    }
    if (gr_scene_load_whole(scene, scene_path, all, m, err)) {
        gr_error inner = *err;
        return GR_FAIL(err, inner.code, "%s: %s", spec->text, inner.message);
    }
    snprintf(scene->out_dir, sizeof scene->out_dir, "%s/%s", out, spec->label);
    return GR_OK;
}

bool gr_compare_earlier(const char *out, const gr_compare_spec *specs, int n, char *what,
                        size_t what_size)
{
    const char *tables[] = {"compare.md", "compare.csv", "compare.json"};
    for (int i = 0; i < 3; i++) {
        snprintf(what, what_size, "%s/%s", out, tables[i]);
        if (access(what, F_OK) == 0) {
            return true;
        }
    }
    for (int k = 0; k < n; k++) {
        const char *runs[] = {"summary.json", GR_CHECKPOINT_NAME};
        for (int i = 0; i < 2; i++) {
            snprintf(what, what_size, "%s/%s/%s", out, specs[k].label, runs[i]);
            if (access(what, F_OK) == 0) {
                return true;
            }
        }
    }
    return false;
}
