/* cost.json: the answer of `granule cost` (include/granule/cost.h), every candidate time step
 * with its errors and the calibration, written atomically. */
#include <math.h>
#include <stdlib.h>

#include <cjson/cJSON.h>

#include "granule/cost.h"
#include "io/files.h"

static void add_num(cJSON *o, const char *k, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, k, v);
    } else {
        cJSON_AddNullToObject(o, k);
    }
}

int gr_cost_write(const gr_cost_answer *a, const gr_cost_request *rq, const char *scene_path,
                  const char *dir, gr_error *err)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "scene", scene_path);
    cJSON_AddStringToObject(root, "observable", gr_cost_observable_name(rq->observable));
    add_num(root, "tolerance", rq->tolerance);
    add_num(root, "t_c", a->t_c);
    add_num(root, "simulated_seconds", a->simulated_seconds);
    cJSON *cands = cJSON_AddArrayToObject(root, "candidates");
    for (int i = 0; i < a->n; i++) {
        const gr_cost_candidate *c = &a->c[i];
        cJSON *o = cJSON_CreateObject();
        add_num(o, "dt", c->dt);
        add_num(o, "steps_per_contact", c->steps_per_contact);
        cJSON_AddBoolToObject(o, "scene_dt", c->scene_dt);
        cJSON_AddBoolToObject(o, "finite", c->finite);
        add_num(o, "loss_error_mean", c->loss_error_mean);
        add_num(o, "loss_error_worst", c->loss_error_worst);
        add_num(o, "error", c->error);
        cJSON_AddBoolToObject(o, "meets", c->meets);
        cJSON_AddItemToArray(cands, o);
    }
    if (a->best >= 0) {
        cJSON *b = cJSON_AddObjectToObject(root, "recommended");
        add_num(b, "dt", a->c[a->best].dt);
        add_num(b, "steps_per_contact", a->c[a->best].steps_per_contact);
        add_num(b, "error", a->c[a->best].error);
        add_num(b, "wall_per_simulated", a->wall_per_simulated);
        add_num(b, "wall_per_simulated_err", a->wall_per_simulated_err);
        cJSON_AddNumberToObject(b, "calibration_blocks", a->blocks);
        add_num(b, "predicted_wall", a->predicted_wall);
        add_num(b, "predicted_wall_err", a->predicted_wall_err);
        add_num(b, "particle_steps_per_second", a->particle_steps_per_second);
        const gr_cost_option *bo = a->best_option >= 0 ? &a->option[a->best_option] : NULL;
        cJSON_AddStringToObject(b, "integrator", bo ? bo->integrator : "verlet");
        add_num(b, "window", bo && bo->window > 0.0 ? bo->window : (double)NAN);
        cJSON *opts = cJSON_AddArrayToObject(root, "integrators");
        for (int k = 0; k < a->n_options; k++) {
            const gr_cost_option *o = &a->option[k];
            cJSON *j = cJSON_CreateObject();
            cJSON_AddStringToObject(j, "integrator", o->integrator);
            add_num(j, "window", o->window > 0.0 ? o->window : (double)NAN);
            cJSON_AddBoolToObject(j, "timed", o->ok);
            if (!o->ok) {
                cJSON_AddStringToObject(j, "why_not", o->note);
            }
            add_num(j, "wall_per_simulated", o->wall_per_simulated);
            add_num(j, "wall_per_simulated_err", o->wall_per_simulated_err);
            cJSON_AddNumberToObject(j, "calibration_blocks", o->blocks);
            add_num(j, "particle_steps_per_second", o->particle_steps_per_second);
            cJSON_AddItemToArray(opts, j);
        }
    } else {
        cJSON_AddNullToObject(root, "recommended");
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory writing cost.json");
    }
    gr_file f;
    int rc = gr_file_open(&f, dir, "cost.json", err);
    if (rc == GR_OK) {
        fputs(text, f.f);
        fputc('\n', f.f);
        rc = gr_file_commit(&f, err);
    }
    free(text);
    return rc;
}
