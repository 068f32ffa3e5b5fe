/* JSON files read back (summary.json, sweep manifests): whole file into cJSON, numbers by dotted path. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/files.h"
#include "io/summary_read.h"

int gr_json_write(const char *dir, const char *name, const cJSON *j, gr_error *err)
{
    char *text = cJSON_Print(j);
    if (!text) {
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory", name);
    }
    gr_file f;
    int rc = gr_file_open(&f, dir, name, err);
    if (!rc) {
        fputs(text, f.f);
        fputc('\n', f.f);
        rc = gr_file_commit(&f, err);
    }
    cJSON_free(text);
    return rc;
}

cJSON *gr_json_read(const char *path, gr_error *err)
{
    int why = 0;
    FILE *f = gr_input_fopen(path, &why);
    if (!f) {
        GR_FAIL(err, GR_EIO, "%s: %s", path, why < 0 ? "not a regular file" : "missing");
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = n > 0 ? malloc((size_t)n + 1) : NULL;
    if (!text || fread(text, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        free(text);
        GR_FAIL(err, GR_EIO, "%s: cannot read", path);
        return NULL;
    }
    fclose(f);
    text[n] = 0;
    cJSON *j = cJSON_Parse(text);
    free(text);
    if (!j) {
        GR_FAIL(err, GR_EINVAL, "%s: not valid JSON", path);
    }
    return j;
}

cJSON *gr_summary_read(const char *dir, gr_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    return gr_json_read(path, err);
}

double gr_summary_number(const cJSON *root, const char *path)
{
    const cJSON *node = gr_summary_node(root, path);
    return node && cJSON_IsNumber(node) ? node->valuedouble
           : cJSON_IsBool(node)         ? (double)cJSON_IsTrue(node)
                                        : (double)NAN;
}

const cJSON *gr_summary_node(const cJSON *root, const char *path)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", path);
    const cJSON *node = root;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ".", &save); tok && node; tok = strtok_r(NULL, ".", &save)) {
        if (cJSON_IsArray(node)) {
            char *end;
            long i = strtol(tok, &end, 10);
            node = *end ? NULL : cJSON_GetArrayItem(node, (int)i);
        } else {
            node = cJSON_GetObjectItemCaseSensitive(node, tok);
        }
    }
    return node;
}
