/* Whole lines for inih (see scene_lines.h). */
#include "scene/scene_lines.h"

#include <ini.h>
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
        snprintf(r->problem, sizeof r->problem,
                 "line of %zu characters is not a key = value line (at most %d are read "
                 "otherwise)",
                 strlen(line), num - 3);
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
        snprintf(r->problem, sizeof r->problem, "key name of %zu characters is too long",
                 strlen(name));
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

/* `[name]` alone on its line (a comment may follow); anything else is a problem. */
static bool section_header(gr_line_reader *r, const char *p)
{
    const size_t len = strcspn(p + 1, "]\r\n");
    const int shown = (int)strcspn(p, "\r\n") < 60 ? (int)strcspn(p, "\r\n") : 60;
    char hint[200] = "";
    if (r->sections) {
        snprintf(hint, sizeof hint, " (sections: %.180s)", r->sections);
    }
    if (p[1 + len] != ']') {
        snprintf(r->problem, sizeof r->problem,
                 "unterminated section header '%.*s': expected [section] on one line%s", shown, p,
                 hint);
        return false;
    }
    const char *after = p + 2 + len;
    after += strspn(after, " \t\r\n");
    if (*after && *after != ';' && *after != '#') {
        snprintf(r->problem, sizeof r->problem,
                 "'%.*s': characters after the section header [%.*s]; a header is [section] alone "
                 "on its line%s",
                 shown, p, (int)(len < 60 ? len : 60), p + 1, hint);
        return false;
    }
    return true;
}

char *gr_line_read(char *str, int num, gr_line_reader *r)
{
    ssize_t n = getline(&r->buf, &r->cap, r->f);
    if (n < 0 || r->problem[0]) {
        return NULL;
    }
    r->line++;
    char *line = r->buf;
    r->length = strcspn(line, "\r\n");
    for (ssize_t i = 0; i < n; i++) {
        const unsigned char c = (unsigned char)line[i];
        if ((c < 0x20 && c != '\t' && c != '\r' && c != '\n') || c == 0x7f) {
            snprintf(r->problem, sizeof r->problem,
                     "control byte 0x%02x at column %zd (a %s is text)", c, i + 1,
                     r->what ? r->what : "file");
            return NULL;
        }
    }
    if (r->line == 1 && n >= 3 && memcmp(line, "\xef\xbb\xbf", 3) == 0) {
        line += 3; /* the UTF-8 byte-order mark inih skips */
        n -= 3;
    }
    const char *start = line + strspn(line, " \t\r\n");
    const bool comment = *start == ';' || *start == '#';
    if (*start == '[' && !section_header(r, start)) {
        return NULL;
    }
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

typedef struct parse_ctx {
    gr_line_reader *r;
    int (*handler)(void *, const char *, const char *, const char *);
    void *user;
} parse_ctx;

static char *parse_read(char *str, int num, void *stream)
{
    return gr_line_read(str, num, ((parse_ctx *)stream)->r);
}

static int parse_line(void *user, const char *section, const char *name, const char *value)
{
    const parse_ctx *p = user;
    if (p->r->long_value && !strcmp(value, GR_LONG_VALUE)) {
        value = p->r->long_value;
    }
    return p->handler(p->user, section, name, value);
}

int gr_line_parse(gr_line_reader *r,
                  int (*handler)(void *user, const char *section, const char *name,
                                 const char *value),
                  void *user)
{
    parse_ctx p = {r, handler, user};
    int bad = ini_parse_stream(parse_read, &p, parse_line, &p);
    if (r->problem[0] && bad > 0 && bad < r->line) {
        r->problem[0] = '\0'; /* the handler refused an earlier line: that one is reported */
    }
    if (r->problem[0]) {
        return r->line;
    }
    if (bad == 0 && ferror(r->f)) {
        return -1;
    }
    return bad;
}

bool gr_linked_key_names(const char *linked, const char *key)
{
    const size_t n = strlen(key);
    if (n == 0) {
        return false; /* an empty name is no key (strstr would find it everywhere, forever) */
    }
    for (const char *p = linked; (p = strstr(p, key)) != NULL; p += n) {
        if ((p == linked || p[-1] == '+') && (p[n] == '\0' || p[n] == '+')) {
            return true;
        }
    }
    return false;
}
