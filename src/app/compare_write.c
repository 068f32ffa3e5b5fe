/* A comparison's table written out (include/granule/compare.h): compare.csv and compare.json
 * (the headline numbers and every scalar of every summary), compare.md and the terminal table
 * (the headline with its footnotes). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/compare.h"
#include "io/files.h"
#include "io/summary_read.h"

/* Every number under `node` as "prefix.key" (arrays of up to 16 numbers as prefix.key.i). */
static void flatten(cJSON *row, const char *prefix, const cJSON *node)
{
    char key[256];
    for (const cJSON *c = node ? node->child : NULL; c; c = c->next) {
        snprintf(key, sizeof key, "%s%s%s", prefix, prefix[0] ? "." : "",
                 c->string ? c->string : "");
        if (cJSON_IsNumber(c)) {
            cJSON_AddNumberToObject(row, key, c->valuedouble);
        } else if (cJSON_IsBool(c)) {
            cJSON_AddNumberToObject(row, key, cJSON_IsTrue(c) ? 1.0 : 0.0);
        } else if (cJSON_IsObject(c) && strcmp(c->string ? c->string : "", "scene")) {
            flatten(row, key, c);
        } else if (cJSON_IsArray(c) && cJSON_GetArraySize(c) <= 16) {
            int k = 0;
            for (const cJSON *a = c->child; a; a = a->next, k++) {
                if (cJSON_IsNumber(a)) {
                    char ak[300];
                    snprintf(ak, sizeof ak, "%s.%d", key, k);
                    cJSON_AddNumberToObject(row, ak, a->valuedouble);
                }
            }
        }
    }
}

static void add_value(cJSON *o, const char *name, double v)
{
    if (isfinite(v)) {
        cJSON_AddNumberToObject(o, name, v);
    } else {
        cJSON_AddNullToObject(o, name);
    }
}

/* One object per model: identity, the headline (value, error, text) and the flattened summary. */
static cJSON *model_rows(const gr_compare_table *t)
{
    cJSON *models = cJSON_CreateArray();
    for (int k = 0; k < t->n_models; k++) {
        cJSON *m = cJSON_CreateObject();
        cJSON_AddStringToObject(m, "model", t->spec[k].text);
        cJSON_AddStringToObject(m, "folder", t->spec[k].label);
        cJSON_AddStringToObject(m, "integrator", t->integrator[k]);
        cJSON_AddStringToObject(m, "kernel", t->kernel[k]);
        cJSON_AddStringToObject(m, "status", t->status[k]);
        cJSON *h = cJSON_AddObjectToObject(m, "headline");
        for (int i = 0; i < t->n_rows; i++) {
            const gr_compare_cell *c = &t->row[i].cell[k];
            cJSON *q = cJSON_AddObjectToObject(h, t->row[i].key);
            cJSON_AddStringToObject(q, "quantity", t->row[i].quantity);
            add_value(q, "value", c->value);
            add_value(q, "error", c->error);
            cJSON_AddStringToObject(q, "text", c->text);
        }
        cJSON *all = cJSON_AddObjectToObject(m, "summary");
        flatten(all, "", t->summaries[k]);
        cJSON_AddItemToArray(models, m);
    }
    return models;
}

/* A cell carrying a footnote mark (" *" or " #" at its end). */
static bool marked(const char *text)
{
    size_t n = strlen(text);
    return n >= 2 && text[n - 2] == ' ' && (text[n - 1] == '*' || text[n - 1] == '#');
}

/* Which of a headline row's columns the CSV carries: [0] an error, [1] a note (a reason or a mark). */
static void row_columns(const gr_compare_table *t, int i, bool has[2])
{
    has[0] = has[1] = false;
    for (int k = 0; k < t->n_models; k++) {
        const gr_compare_cell *c = &t->row[i].cell[k];
        has[0] |= isfinite(c->error);
        has[1] |= !isfinite(c->value) || marked(c->text);
    }
}

static bool headline_key(const gr_compare_table *t, const char *name)
{
    for (int i = 0; i < t->n_rows; i++) {
        if (!strcmp(t->row[i].key, name)) {
            return true;
        }
    }
    return false;
}

/* The CSV: identity columns, then per headline quantity its value, error and note (the reason
 * when there is no value; only the columns some model fills), then the union of the summaries'
 * other scalars in first-seen order. */
static int write_csv(const gr_compare_table *t, const cJSON *models, const char *out, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, out, "compare.csv", err);
    if (rc) {
        return rc;
    }
    gr_file_note(&f,
                 "granule compare of %s: one row per model, same initial state and noise seed\n",
                 t->scene);
    gr_file_note(&f,
                 "headline columns: <key> (value), <key>_err (its error, empty if none; %s), "
                 "<key>_note (why "
                 "there is no value, or its footnote in words); then every scalar of the model's "
                 "summary.json "
                 "(empty where a model has none)",
                 GR_COMPARE_ERRORS);
    const char *cols[512];
    int nc = 0;
    for (const cJSON *m = models->child; m; m = m->next) {
        for (const cJSON *c = cJSON_GetObjectItem(m, "summary")->child; c && nc < 512;
             c = c->next) {
            bool have = headline_key(t, c->string);
            for (int i = 0; i < nc && !have; i++) {
                have = !strcmp(cols[i], c->string);
            }
            if (!have) {
                cols[nc++] = c->string;
            }
        }
    }
    gr_file_columns(&f, "model [],integrator [],kernel [],status []");
    for (int i = 0; i < t->n_rows; i++) {
        bool has[2];
        row_columns(t, i, has);
        char name[64];
        gr_file_column(&f, t->row[i].key, t->row[i].unit);
        if (has[0]) {
            snprintf(name, sizeof name, "%s_err", t->row[i].key);
            gr_file_column(&f, name, t->row[i].unit);
        }
        if (has[1]) {
            snprintf(name, sizeof name, "%s_note", t->row[i].key);
            gr_file_column(&f, name, "");
        }
    }
    for (int i = 0; i < nc; i++) {
        char buf[32];
        gr_file_column(&f, cols[i], gr_summary_unit(cols[i], buf, sizeof buf));
    }
    fputc('\n', f.f);
    int k = 0;
    for (const cJSON *m = models->child; m; m = m->next, k++) {
        const char *text[] = {t->spec[k].text, t->integrator[k], t->kernel[k], t->status[k]};
        for (int i = 0; i < 4; i++) { /* text cells: no comma, no '#' (gr_csv_text) */
            if (i) {
                fputc(',', f.f);
            }
            gr_csv_text(f.f, text[i], false);
        }
        for (int i = 0; i < t->n_rows; i++) {
            const gr_compare_cell *c = &t->row[i].cell[k];
            bool has[2];
            row_columns(t, i, has);
            fputc(',', f.f);
            if (isfinite(c->value)) {
                fprintf(f.f, "%.8g", c->value);
            }
            if (has[0]) {
                fputc(',', f.f);
            }
            if (has[0] && isfinite(c->error)) {
                fprintf(f.f, "%.8g", c->error);
            }
            if (!has[1]) {
                continue;
            }
            /* the note: the reason, or the footnote in words (a '#' would start a comment for
             * numpy.genfromtxt); commas would split the cell */
            fputc(',', f.f);
            if (!isfinite(c->value)) {
                gr_csv_text(f.f, c->text, false);
            } else if (marked(c->text)) {
                fputs(gr_compare_mark_words(c->text[strlen(c->text) - 1]), f.f);
            }
        }
        const cJSON *all = cJSON_GetObjectItem(m, "summary");
        for (int i = 0; i < nc; i++) {
            const cJSON *c = cJSON_GetObjectItem(all, cols[i]);
            fputc(',', f.f);
            if (c) {
                fprintf(f.f, "%.8g", c->valuedouble);
            }
        }
        fputc('\n', f.f);
    }
    return gr_file_commit(&f, err);
}

static int write_md(const gr_compare_table *t, const char *out, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, out, "compare.md", err);
    if (rc) {
        return rc;
    }
    fprintf(f.f,
            "# granule compare: %s\n\nSame scene, initial state and noise seed for every model. "
            "The full table "
            "(every scalar of every run) is compare.csv / compare.json.\n\n| quantity |",
            t->scene);
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f.f, " %s |", t->spec[k].text);
    }
    fprintf(f.f, "\n|---|");
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f.f, "---|");
    }
    fprintf(f.f, "\n| integrator |");
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f.f, " %s |", t->integrator[k]);
    }
    fputc('\n', f.f);
    for (int i = 0; i < t->n_rows; i++) {
        fprintf(f.f, "| %s |", t->row[i].quantity);
        for (int k = 0; k < t->n_models; k++) {
            fprintf(f.f, " %s |", t->row[i].cell[k].text);
        }
        fputc('\n', f.f);
    }
    if (t->footnotes[0]) {
        fprintf(f.f, "\n%s", t->footnotes);
    }
    fprintf(f.f, "\nKernels:\n\n");
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f.f, "- %s: `%s` (%s)\n", t->spec[k].text, t->kernel[k], t->status[k]);
    }
    return gr_file_commit(&f, err);
}

int gr_compare_table_write(const gr_compare_table *t, const char *out, gr_error *err)
{
    cJSON *models = model_rows(t);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "scene", t->scene);
    cJSON_AddNumberToObject(root, "dim", t->dim);
    cJSON *rows = cJSON_AddArrayToObject(root, "headline");
    for (int i = 0; i < t->n_rows; i++) {
        cJSON *r = cJSON_CreateObject();
        cJSON_AddStringToObject(r, "key", t->row[i].key);
        cJSON_AddStringToObject(r, "quantity", t->row[i].quantity);
        cJSON_AddItemToArray(rows, r);
    }
    cJSON_AddStringToObject(root, "footnotes", t->footnotes);
    cJSON_AddItemToObject(root, "models", models);
    int rc = write_csv(t, models, out, err);
    rc = rc ? rc : gr_json_write(out, "compare.json", root, err);
    rc = rc ? rc : write_md(t, out, err);
    cJSON_Delete(root);
    return rc;
}

void gr_compare_table_print(const gr_compare_table *t, FILE *f)
{
    int w0 = (int)strlen("integrator"), w[GR_COMPARE_MAX];
    for (int i = 0; i < t->n_rows; i++) {
        w0 = (int)strlen(t->row[i].quantity) > w0 ? (int)strlen(t->row[i].quantity) : w0;
    }
    for (int k = 0; k < t->n_models; k++) {
        w[k] = (int)strlen(t->spec[k].text);
        for (int i = 0; i < t->n_rows; i++) {
            w[k] = (int)strlen(t->row[i].cell[k].text) > w[k] ? (int)strlen(t->row[i].cell[k].text)
                                                              : w[k];
        }
    }
    fprintf(f, "%-*s", w0, "");
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f, "  %-*s", w[k], t->spec[k].text);
    }
    fprintf(f, "\n%-*s", w0, "integrator");
    for (int k = 0; k < t->n_models; k++) {
        fprintf(f, "  %-*s", w[k], t->integrator[k]);
    }
    fputc('\n', f);
    for (int i = 0; i < t->n_rows; i++) {
        fprintf(f, "%-*s", w0, t->row[i].quantity);
        for (int k = 0; k < t->n_models; k++) {
            fprintf(f, "  %-*s", w[k], t->row[i].cell[k].text);
        }
        fputc('\n', f);
    }
    fputs(t->footnotes, f);
    for (int k = 0; k < t->n_models; k++) {
        if (strcmp(t->status[k], "completed")) {
            fprintf(f, "%s: run %s\n", t->spec[k].text, t->status[k]);
        }
    }
}
