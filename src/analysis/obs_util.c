/* Helpers shared by the observables. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "analysis/obs_lag.h"
#include "analysis/obs_util.h"
#include "granule_config.h"
#include "analysis/blob_stats.h"
#include "io/plot.h"

void gr_obs_mean_velocity(const gr_particles *p, double mean[3])
{
    mean[0] = mean[1] = mean[2] = 0.0;
    for (int i = 0; i < p->n; i++) {
        mean[0] += p->vx[i];
        if (p->dim >= 2) {
            mean[1] += p->vy[i];
        }
        if (p->dim == 3) {
            mean[2] += p->vz[i];
        }
    }
    mean[0] /= p->n;
    mean[1] /= p->n;
    mean[2] /= p->n;
}

int gr_obs_csv_open(const gr_output *out, const char *name, const char *what, gr_file *f,
                    gr_error *err)
{
    int rc = gr_file_open(f, out->dir, name, err);
    if (rc) {
        return rc;
    }
    gr_file_note(f, "# granule %s: %s\n# scene %s, hash %016llx, seed %llu\n", GR_VERSION, what,
                 out->source, (unsigned long long)out->scene_hash, (unsigned long long)out->seed);
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

int gr_obs_table_write(const gr_output *out, const gr_obs_table *t, gr_error *err)
{
    gr_file f;
    int rc = gr_obs_csv_open(out, t->name, t->what, &f, err);
    if (rc) {
        return rc;
    }
    gr_file_header(&f, t->columns);
    t->rows(f.f, t->ctx);
    rc = gr_file_commit(&f, err);
    if (!rc && out->plots && t->png) {
        gr_obs_plot(out, t->png, t->plot);
    }
    return rc;
}

void gr_obs_histogram_rows(FILE *f, const void *ctx) { gr_histogram_write_rows(ctx, f); }

const char *gr_obs_column_unit(const char *table, const char *column, char *buf, size_t len)
{
    static const struct {
        const char *table, *columns;
    } tables[] = {
        {"gaps.csv", gr_obs_gaps_columns}, {"sk.csv", gr_obs_sk_columns},
        {"pair.csv", gr_obs_pair_columns}, {"freepath.csv", gr_obs_freepath_columns},
        {"pv.csv", gr_obs_pv_columns},     {"postcollision.csv", gr_obs_postcollision_columns}};
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; i++) {
        if (strcmp(table, tables[i].table)) {
            continue;
        }
        gr_file scratch = {.units =
                               NULL}; /* the units of the column line, as a table records them */
        gr_file_units(&scratch, tables[i].columns);
        const cJSON *u = cJSON_GetObjectItemCaseSensitive(scratch.units, column);
        const bool found = cJSON_IsString(u);
        if (found) {
            snprintf(buf, len, "%s", u->valuestring);
        }
        cJSON_Delete(scratch.units);
        return found ? buf : NULL;
    }
    return NULL;
}

double gr_obs_stderr(const gr_blocking *b)
{
    double e = gr_blocking_stderr(b, NULL, NULL);
    return isfinite(e) ? e : gr_blocking_stderr_at(b, 0);
}

cJSON *gr_obs_summary(const gr_output *out, const char *key, const char *file)
{
    cJSON *j = cJSON_AddObjectToObject(out->summary, key);
    cJSON_AddStringToObject(j, "file", file);
    return j;
}

int gr_obs_check_frame(const char *name, const gr_particles *p, int n, gr_error *err)
{
    if (p->n != n) {
        return GR_FAIL(err, GR_EINVAL, "%s: a frame of %d particles, the scene has %d", name, p->n,
                       n);
    }
    return GR_OK;
}

int gr_obs_frame_species(const char *name, const gr_particles *p, int ns, int n, int *species,
                         gr_error *err)
{
    bool ok = p->species && p->n_species == ns && p->n == n;
    for (int i = 0; ok && i < n; i++) {
        ok = p->species[i] >= 0 && p->species[i] < ns;
        if (species) {
            species[i] = ok ? p->species[i] : 0;
        }
    }
    return ok ? GR_OK
              : GR_FAIL(err, GR_EINVAL,
                        "%s: the frames carry %d species of %d grains, the scene %d of %d "
                        "([species]; docs/mixtures.md)",
                        name, p->species ? p->n_species : 0, p->n, ns, n);
}

void gr_obs_note_no_events(cJSON *j, const char *what)
{
    char note[200];
    snprintf(note, sizeof note,
             "no %s: none happened, or the frames came from snapshots (granule analyse has no "
             "contact events)",
             what);
    cJSON_AddStringToObject(j, "note", note);
}

void gr_obs_add_number(cJSON *o, const char *name, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, name, v);
    } else {
        cJSON_AddNullToObject(o, name);
    }
}

static void lag_rows(FILE *f, const void *ctx)
{
    const gr_lag *g = ctx;
    const double dt = gr_lag_interval(g);
    for (int l = 0; l <= g->lags; l++) {
        int64_t c;
        double e, v = gr_lag_mean(g, l, &e, &c);
        if (c > 0) {
            fprintf(f, "%.8g,%.10g,%.6g,%lld\n", l * dt, v, isfinite(e) ? e : 0.0, (long long)c);
        }
    }
}

int gr_obs_lag_csv(const gr_output *out, const gr_lag *lag, const char *name, const char *what,
                   const char *columns, cJSON *j, gr_error *err)
{
    cJSON_AddStringToObject(j, "file", name);
    gr_obs_add_number(j, "interval", gr_lag_interval(lag));
    cJSON_AddNumberToObject(j, "samples", (double)lag->frames);
    return gr_obs_table_write(
        out,
        &(gr_obs_table){
            .name = name, .what = what, .columns = columns, .rows = lag_rows, .ctx = lag},
        err);
}

static void release_histogram(void *h) { gr_histogram_free(h); }

void gr_obs_own_histogram(void *state, gr_histogram *h) { gr_obs_own(state, release_histogram, h); }

int gr_obs_histogram(void *state, gr_histogram *h, int nbins, double lo, double hi, bool log_bins,
                     gr_error *err)
{
    int rc = gr_histogram_init(h, nbins, lo, hi, log_bins, err);
    if (!rc) {
        gr_obs_own_histogram(state, h);
    }
    return rc;
}

static void release_pointer(void *field)
{
    void **p = field;
    free(*p);
    *p = NULL;
}

void gr_obs_own_pointer(void *state, void *pointer_field)
{
    gr_obs_own(state, release_pointer, pointer_field);
}

void gr_obs_io_species(gr_blob_io *io, const char *name, int *species, int n, int ns)
{
    for (int i = 0; i < n && !gr_blob_io_bad(io); i++) {
        gr_blob_io_int(io, &species[i]);
        if (species[i] < 0 || species[i] >= ns) {
            gr_blob_io_fail(io, "%s: species %d of grain %d (of %d species)", name, species[i], i,
                            ns);
        }
    }
}

void gr_obs_io_blockings(gr_blob_io *io, gr_blocking *b, int n)
{
    for (int i = 0; i < n && !gr_blob_io_bad(io); i++) {
        if (!io->in) {
            gr_blob_put_blocking(io->out, &b[i]);
        } else {
            gr_blob_get_blocking(io->in, &b[i]);
        }
    }
}

void gr_obs_io_histogram(gr_blob_io *io, gr_histogram *h)
{
    if (!io->in) {
        gr_blob_put_histogram(io->out, h);
    } else if (!io->in->bad) {
        gr_blob_get_histogram(io->in, h);
    }
}

bool gr_obs_io_histogram_new(gr_blob_io *io, gr_histogram *h)
{
    if (!io->in) {
        gr_blob_put_histogram(io->out, h);
        return true;
    }
    return !io->in->bad && gr_blob_get_histogram_new(io->in, h, false);
}

double gr_obs_collision_diameter(const gr_obs_setup *setup)
{
    const double r1 = setup->radius_mean, r2 = setup->radius_sq_mean;
    if (!setup->sizes || !(r1 > 0.0) || !(r2 > 0.0)) {
        return 2.0 * setup->radius;
    }
    return setup->dim == 3 ? sqrt(2.0 * r2 + 2.0 * r1 * r1) : 2.0 * r1;
}

_Static_assert(GR_MAX_SPECIES <= 9, "species pairs are labelled by two digits");

void gr_obs_pairs_init(gr_obs_pairs *pairs, int ns)
{
    pairs->n = 0;
    for (int a = 0; a < ns; a++) {
        for (int b = a; b < ns; b++, pairs->n++) {
            pairs->a[pairs->n] = a;
            pairs->b[pairs->n] = b;
            pairs->of[a * ns + b] = pairs->of[b * ns + a] = pairs->n;
            char *l = pairs->label[pairs->n];
            l[0] = (char)('1' + a);
            l[1] = (char)('1' + b);
            l[2] = '\0';
        }
    }
}

void gr_obs_pairs_summary(const gr_obs_pairs *pairs, cJSON *j)
{
    cJSON *arr = cJSON_AddArrayToObject(j, "species_pairs");
    for (int q = 0; q < pairs->n; q++) {
        cJSON_AddItemToArray(arr, cJSON_CreateString(pairs->label[q]));
    }
}

void gr_obs_note_diameter(cJSON *j, double d, int dim)
{
    cJSON_AddNumberToObject(j, "d", d);
    cJSON_AddStringToObject(j, "d_from",
                            dim == 3 ? "a mixture: sqrt(<(r_i + r_j)^2>) over random pairs"
                                     : "a mixture: <r_i + r_j> = 2 <r> over random pairs");
}
