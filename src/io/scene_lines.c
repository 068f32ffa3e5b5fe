/* Whole lines for inih (see scene_lines.h). */
#include "io/scene_lines.h"

#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

static char *trim(char *s)
{
    s += strspn(s, " \t");
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n')) {
        s[--n] = '\0';
    }
    return s;
}

/* A long `name = value ; comment` line: name handed to inih, value kept (inih's rules: the
 * first '=' or ':' separates, an inline ';' comment needs a blank before it). */
static char *long_line(char *str, int num, gr_line_reader *r, char *line)
{
    char *sep = line + strcspn(line, "=:");
    if (*line == ' ' || *line == '\t' || *line == '[' || !*sep) {
        snprintf(r->problem, sizeof r->problem, "line of %zu characters is not a key = value line (at most %d are read "
                 "otherwise)", strlen(line), num - 3);
        return NULL;
    }
    *sep = '\0';
    char *value = sep + 1;
    for (char *c = value; *c; c++) {
        if (*c == ';' && c > value && (c[-1] == ' ' || c[-1] == '\t')) {
            *c = '\0';
            break;
        }
    }
    const char *name = trim(line);
    if (strlen(name) + sizeof " = " GR_LONG_VALUE "\n" > (size_t)num) {
        snprintf(r->problem, sizeof r->problem, "key name of %zu characters is too long", strlen(name));
        return NULL;
    }
    free(r->long_value);
    r->long_value = strdup(trim(value));
    if (!r->long_value) {
        snprintf(r->problem, sizeof r->problem, "out of memory");
        return NULL;
    }
    snprintf(str, (size_t)num, "%s = " GR_LONG_VALUE "\n", name);
    return str;
}

char *gr_line_read(char *str, int num, gr_line_reader *r)
{
    ssize_t n = getline(&r->buf, &r->cap, r->f);
    if (n < 0 || r->problem[0]) {
        return NULL;
    }
    r->line++;
    char *line = r->buf;
    for (ssize_t i = 0; i < n; i++) {
        const unsigned char c = (unsigned char)line[i];
        if ((c < 0x20 && c != '\t' && c != '\r' && c != '\n') || c == 0x7f) {
            snprintf(r->problem, sizeof r->problem, "control byte 0x%02x at column %zd (a scene is text)", c, i + 1);
            return NULL;
        }
    }
    if (r->line == 1 && n >= 3 && memcmp(line, "\xef\xbb\xbf", 3) == 0) {
        line += 3; /* the UTF-8 byte-order mark inih skips */
        n -= 3;
    }
    const char *start = line + strspn(line, " \t\r\n");
    const bool comment = *start == ';' || *start == '#';
    r->content |= *start && !comment;
    free(r->long_value);
    r->long_value = NULL;
    if (n + 3 <= num) {
        memcpy(str, line, (size_t)n + 1);
        return str;
    }
    if (comment) {
        snprintf(str, (size_t)num, "\n");
        return str;
    }
    return long_line(str, num, r, line);
}

void gr_line_reader_free(gr_line_reader *r)
{
    free(r->buf);
    free(r->long_value);
    r->buf = r->long_value = NULL;
}
