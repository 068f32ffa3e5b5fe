/* The header line of a CSV table and the units of its columns (files.h): the names go to the
 * table, the units to the sidecar NAME.meta.json, so pandas and numpy read the table without
 * options and a program finds every column's unit in one JSON object. */
#include <cjson/cJSON.h>
#include <stdbool.h>
#include <string.h>

#include "io/files.h"

static void column(gr_file *out, const char *name, const char *unit, bool write)
{
    if (write) {
        fprintf(out->f, "%s%s", out->columns++ ? "," : "", name);
    }
    if (!unit) {
        return;
    }
    if (!out->units) {
        out->units = cJSON_CreateObject();
    }
    if (out->units && !cJSON_GetObjectItemCaseSensitive(out->units, name)) {
        cJSON_AddStringToObject(out->units, name, unit);
    }
}

void gr_file_column(gr_file *out, const char *name, const char *unit)
{
    column(out, name, unit, true);
}

static void columns(gr_file *out, const char *spec, bool write)
{
    for (const char *c = spec; *c;) {
        const char *end = c + strcspn(c, ",");
        const char *open = memchr(c, '[', (size_t)(end - c));
        const char *close = open ? memchr(open, ']', (size_t)(end - open)) : NULL;
        const char *name_end = open && close ? open : end;
        while (name_end > c && name_end[-1] == ' ') {
            name_end--;
        }
        char name[128], unit[64];
        snprintf(name, sizeof name, "%.*s", (int)(name_end - c), c);
        if (open && close) {
            snprintf(unit, sizeof unit, "%.*s", (int)(close - open - 1), open + 1);
        }
        column(out, name, open && close ? unit : NULL, write);
        c = *end ? end + 1 : end;
    }
}

void gr_file_columns(gr_file *out, const char *spec) { columns(out, spec, true); }

void gr_file_units(gr_file *out, const char *spec) { columns(out, spec, false); }

void gr_file_header(gr_file *out, const char *spec)
{
    gr_file_columns(out, spec);
    fputc('\n', out->f);
}

void gr_csv_text(FILE *f, const char *text, bool quote)
{
    if (quote) {
        fputc('"', f);
    }
    for (const char *p = text; *p; p++) {
        fputc(*p == ','                               ? ';'
              : *p == '#' || *p == '\n' || *p == '\r' ? ' '
              : *p == '"'                             ? '\''
                                                      : *p,
              f);
    }
    if (quote) {
        fputc('"', f);
    }
}

void gr_csv_label(char *text)
{
    for (char *p = text; (p = strstr(p, "; ")); p += 2) {
        *p = ',';
    }
}
