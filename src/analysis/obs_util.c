/* Helpers shared by the observables. */
#include <cjson/cJSON.h>
#include <stdio.h>

#include "analysis/obs_util.h"
#include "granule/scene.h"
#include "granule_config.h"
#include "io/plot.h"

void gr_obs_mean_velocity(const gr_particles *p, double mean[2])
{
    mean[0] = mean[1] = 0.0;
    for (int i = 0; i < p->n; i++) {
        mean[0] += p->vx[i];
        if (p->dim == 2) {
            mean[1] += p->vy[i];
        }
    }
    mean[0] /= p->n;
    mean[1] /= p->n;
}

int gr_obs_csv_open(const gr_output *out, const char *name, const char *what, gr_file *f, gr_error *err)
{
    int rc = gr_file_open(f, out->dir, name, err);
    if (rc) {
        return rc;
    }
    gr_file_note(f, "# granule %s: %s\n# scene %s, hash %016llx, seed %llu\n", GR_VERSION, what,
            out->scene->source, (unsigned long long)out->scene_hash, (unsigned long long)out->scene->seed);
    return GR_OK;
}

void gr_obs_plot(const gr_output *out, const char *png, const char *body)
{
    char note[300];
    if (gr_plot_script(out->dir, png, body, note, sizeof note) != 0) {
        cJSON *notes = cJSON_GetObjectItem(out->summary, "plot_notes");
        if (!notes) {
            notes = cJSON_AddArrayToObject(out->summary, "plot_notes");
        }
        cJSON_AddItemToArray(notes, cJSON_CreateString(note));
    }
}
