/* Shared pieces of the SPM studies' output folders; see spm_output.h. */
#include "theory/spm_output.h"

#include <math.h>
#include <time.h>

#include "analysis/obs_util.h"
#include "granule/spm_study.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/plot.h"

void gr_spm_csv_head(gr_file *f, const char *what, const gr_spm_settings *s)
{
    gr_file_note(f, "# granule %s (%s) spm: %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f,
                 "# dim %d, M = %g kg, D = %g N^2 s, %s = %g, refine %d, walks %lld, batches %d, "
                 "seed %llu\n",
                 s->dim, s->mass, s->D, s->dt > 0.0 ? "dt (s)" : "step (t_l)",
                 s->dt > 0.0 ? s->dt : s->step, s->refine, (long long)s->walks, s->batches,
                 (unsigned long long)s->seed);
}

void gr_spm_json_settings(cJSON *j, const gr_spm_settings *s, int bins)
{
    cJSON *st = cJSON_AddObjectToObject(j, "settings");
    cJSON_AddNumberToObject(st, "dim", s->dim);
    cJSON_AddNumberToObject(st, "mass", s->mass);
    cJSON_AddNumberToObject(st, "D", s->D);
    cJSON_AddNumberToObject(st, "step", s->step);
    cJSON_AddNumberToObject(st, "dt", s->dt);
    cJSON_AddNumberToObject(st, "refine", s->refine);
    cJSON_AddNumberToObject(st, "walks", (double)s->walks);
    cJSON_AddNumberToObject(st, "batches", s->batches);
    cJSON_AddNumberToObject(st, "seed", (double)s->seed);
    cJSON_AddNumberToObject(st, "bins", bins);
}

void gr_spm_json_num(cJSON *o, const char *key, double v) { gr_obs_add_number(o, key, v); }

cJSON *gr_spm_json_head(const char *mode)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "mode", mode);
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    return j;
}

void gr_spm_json_stats(cJSON *o, const gr_spm_walk_stats *st)
{
    cJSON_AddNumberToObject(o, "walks", (double)st->walks);
    cJSON_AddNumberToObject(o, "samples", (double)st->steps);
    gr_spm_json_num(o, "exit_time_mean_t_l", st->exit_time_mean);
    gr_spm_json_num(o, "exit_time_err_t_l", st->exit_time_err);
    gr_spm_json_num(o, "w2_time_mean", st->w2_time_mean);
    gr_spm_json_num(o, "w2_time_err", st->w2_time_err);
    gr_spm_json_num(o, "exit_speed2_over_exit_time", st->exit_speed2_mean / st->exit_time_mean);
    cJSON_AddNumberToObject(o, "bridge_points", (double)st->bridge_points);
    cJSON_AddNumberToObject(o, "exits_found_by_refinement", (double)st->bridge_exits);
    gr_spm_constants c;
    gr_spm_constants_of(st, &c);
    gr_spm_json_constants(o, &c, NULL);
}

void gr_spm_json_constants(cJSON *o, const gr_spm_constants *c, const char *note)
{
    cJSON *t = cJSON_AddObjectToObject(o, "constants");
    cJSON_AddStringToObject(t, "convention",
                            "<v_x^2> = c (D l/M^2)^(2/3), <T_fp> = c' (l^2 M^2/D)^(1/3)");
    gr_spm_json_num(t, "c", c->c);
    gr_spm_json_num(t, "c_err", c->c_err);
    gr_spm_json_num(t, "c_prime", c->c_prime);
    gr_spm_json_num(t, "c_prime_err", c->c_prime_err);
    if (note) {
        cJSON_AddStringToObject(t, "note", note);
    }
}

void gr_spm_plot(const char *dir, bool plots, cJSON *j, const char *png, const char *body)
{
    cJSON *list = cJSON_GetObjectItem(j, "plots");
    if (!plots) {
        return;
    }
    char note[300];
    if (gr_plot_script(dir, png, body, note, sizeof note) == 0) {
        cJSON_AddItemToArray(list, cJSON_CreateString(png));
    } else {
        cJSON *notes = cJSON_GetObjectItem(j, "plot_notes");
        if (!notes) {
            notes = cJSON_AddArrayToObject(j, "plot_notes");
        }
        cJSON_AddItemToArray(notes, cJSON_CreateString(note));
    }
}

double gr_spm_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void gr_spm_json_pl_fit(cJSON *t, const gr_spm_pl_fit *f)
{
    gr_spm_json_num(t, "l_from", f->lfrom);
    gr_spm_json_num(t, "l_to", f->lto);
    gr_spm_json_num(t, "D_f", f->df);
    gr_spm_json_num(t, "D_f_err", f->df_err);
    gr_spm_json_num(t, "C", f->C);
    gr_spm_json_num(t, "C_err", f->C_err);
    gr_spm_json_num(t, "chi2_red", f->chi2_red);
    cJSON_AddNumberToObject(t, "points", f->n_points);
}

/* Okabe-Ito colours without the yellow (too faint on white), then black and grey */
static const char *const colours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                      "#56b4e9", "#e69f00", "#000000", "#7f7f7f"};

const char *gr_spm_colour(int k) { return colours[k % (int)(sizeof colours / sizeof colours[0])]; }
