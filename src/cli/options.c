/* The table-driven option parser of the granule command; see options.h. */
#include "cli/options.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/sim.h"
#include "io/plot.h"

bool cli_apply_format(void *args, const char *text, double number)
{
    (void)args;
    (void)number;
    gr_plot_set_format((gr_plot_format)gr_plot_format_parse(text));
    return true;
}

bool cli_apply_threads(void *args, const char *text, double number)
{
    (void)args;
    (void)text;
    gr_set_threads((int)number);
    return true;
}

bool cli_given(const cli_command *cmd, const cli_pos *pos, const char *name)
{
    for (int k = 0; k < cmd->n_opts && k < 64; k++) {
        if (!strcmp(cmd->opts[k].name, name)) {
            return pos->seen >> k & 1;
        }
    }
    return false;
}

void cli_list_free(cli_list *l)
{
    free(l->items);
    l->items = NULL;
    l->n = 0;
}

bool cli_list_add(cli_list *l, const char *text)
{
    const char **items = realloc(l->items, (size_t)(l->n + 1) * sizeof *items);
    if (!items) {
        return false;
    }
    l->items = items;
    l->items[l->n++] = text;
    return true;
}

bool cli_theory_set_refused(const cli_command *cmd, cli_theory *th)
{
    cli_list *sets = &th->sets;
    const bool refused = sets->n > 0;
    if (refused) {
        app_error("%s: --set %s: %s has no scene, so no scene keys to set; its settings are "
                  "options (granule %s --help)",
                  cmd->name, sets->items[0], cmd->name, cmd->name);
    }
    cli_list_free(sets);
    return refused;
}

/* Levenshtein distance of a and b (each at most 63 characters; longer ones are far anyway). */
static size_t edit_distance(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    if (na > 63 || nb > 63) {
        return 64;
    }
    size_t row[64];
    for (size_t j = 0; j <= nb; j++) {
        row[j] = j;
    }
    for (size_t i = 1; i <= na; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= nb; j++) {
            const size_t up = row[j];
            const size_t sub = diag + (a[i - 1] != b[j - 1]);
            row[j] = sub < up + 1 ? sub : up + 1;
            row[j] = row[j] < row[j - 1] + 1 ? row[j] : row[j - 1] + 1;
            diag = up;
        }
    }
    return row[nb];
}

const char *cli_nearest(const cli_command *cmd, const char *given)
{
    char name[64];
    snprintf(name, sizeof name, "%.*s", (int)strcspn(given, "="), given);
    const size_t len = strlen(name);
    const char *best = NULL, *prefix = NULL;
    size_t best_d = (size_t)-1;
    int n_prefix = 0;
    for (int k = 0; k < cmd->n_opts; k++) {
        const char *o = cmd->opts[k].name;
        const size_t d = edit_distance(name, o);
        if (d < best_d) {
            best_d = d;
            best = o;
        }
        if (len > 2 && !strncmp(o, name, len)) {
            prefix = o;
            n_prefix++;
        }
    }
    if (n_prefix == 1) {
        return prefix;
    }
    /* near: one or two edits, or a third of the name's letters */
    return best && (best_d <= 2 || 3 * best_d <= len) ? best : NULL;
}

static const cli_opt *find(const cli_command *cmd, const char *name, size_t len)
{
    for (int k = 0; k < cmd->n_opts; k++) {
        if (strlen(cmd->opts[k].name) == len && !strncmp(cmd->opts[k].name, name, len)) {
            return &cmd->opts[k];
        }
    }
    return NULL;
}

/* "from 1 to 1024", ">= 0", "in (0, 1]", "> 0": the allowed range of o in words */
static void range_text(const cli_opt *o, char *buf, size_t size)
{
    const bool integer = o->type != CLI_DOUBLE;
    const bool lo = isfinite(o->min), hi = isfinite(o->max);
    if (integer && lo && hi) {
        snprintf(buf, size, "from %.15g to %.15g", o->min, o->max);
    } else if (lo && hi) {
        snprintf(buf, size, "in %c%.15g, %.15g%c", o->range & CLI_MIN_OPEN ? '(' : '[', o->min,
                 o->max, o->range & CLI_MAX_OPEN ? ')' : ']');
    } else if (lo) {
        snprintf(buf, size, "%s %.15g", !integer && o->range & CLI_MIN_OPEN ? ">" : ">=", o->min);
    } else {
        snprintf(buf, size, "%s %.15g", !integer && o->range & CLI_MAX_OPEN ? "<" : "<=", o->max);
    }
}

static bool has_range(const cli_opt *o)
{
    return o->type != CLI_FLAG && o->type < CLI_STRING && o->min < o->max;
}

static bool in_range(const cli_opt *o, double x)
{
    if (!has_range(o)) {
        return true;
    }
    const bool lo = o->range & CLI_MIN_OPEN ? x > o->min : x >= o->min;
    const bool hi = o->range & CLI_MAX_OPEN ? x < o->max : x <= o->max;
    return lo && hi;
}

/* the words of a CLI_CHOICE as "png, svg or pdf" */
static void choice_text(const char *words, char *buf, size_t size)
{
    buf[0] = '\0';
    for (const char *p = words; *p;) {
        const size_t n = strcspn(p, "|");
        const size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%.*s",
                 used == 0 ? ""
                 : p[n]    ? ", "
                           : " or ",
                 (int)n, p);
        p += n + (p[n] == '|');
    }
}

static bool is_choice(const char *words, const char *v)
{
    const size_t len = strlen(v);
    for (const char *p = words; *p;) {
        const size_t n = strcspn(p, "|");
        if (n == len && !strncmp(p, v, n)) {
            return true;
        }
        p += n + (p[n] == '|');
    }
    return false;
}

/* Check the value v of o and store it; false after an error naming the option. */
static bool take(const cli_command *cmd, const cli_opt *o, const char *v, void *args)
{
    char *field = o->at == CLI_NOWHERE ? NULL : (char *)args + o->at;
    double x = 0.0;
    char allowed[160];
    long long iv = 0;
    unsigned long long uv = 0;
    if (o->type == CLI_INT || o->type == CLI_INT64 || o->type == CLI_UINT64 ||
        o->type == CLI_DOUBLE) {
        char *end;
        bool exact = false; /* an integer in decimal digits, read without rounding */
        errno = 0;
        if (o->type == CLI_UINT64 && v[0] != '-') {
            uv = strtoull(v, &end, 10);
            exact = end != v && *end == '\0' && errno == 0;
            x = (double)uv;
        } else if (o->type != CLI_DOUBLE) {
            iv = strtoll(v, &end, 10);
            exact = end != v && *end == '\0' && errno == 0;
            x = (double)iv;
        }
        if (!exact) { /* 1e6 is an integer too */
            errno = 0;
            x = strtod(v, &end);
            iv = (long long)fmax(fmin(x, 9e18), -9e18);
            uv = x > 0.0 ? (unsigned long long)fmin(x, 1.8e19) : 0;
        }
        const bool number =
            end != v && *end == '\0' && isfinite(x) && !strchr(v, 'x') && !strchr(v, 'X');
        const bool integer = number && (o->type == CLI_DOUBLE || x == floor(x)) &&
                             (o->type != CLI_UINT64 || x >= 0.0);
        if (!integer || !in_range(o, x)) {
            if (has_range(o)) {
                range_text(o, allowed, sizeof allowed);
                app_error("%s: %s %s: expected %s %s (allowed range)", cmd->name, o->name, v,
                          o->type == CLI_DOUBLE ? "a number" : "an integer", allowed);
            } else {
                app_error("%s: %s %s: expected %s", cmd->name, o->name, v,
                          o->type == CLI_DOUBLE   ? "a number"
                          : o->type == CLI_UINT64 ? "a non-negative integer"
                                                  : "an integer");
            }
            return false;
        }
    } else if (o->type == CLI_CHOICE && !is_choice(o->value, v)) {
        choice_text(o->value, allowed, sizeof allowed);
        app_error("%s: %s %s: expected %s", cmd->name, o->name, v, allowed);
        return false;
    }
    if (field) {
        switch (o->type) {
        case CLI_FLAG: *(bool *)field = true; break;
        case CLI_INT: *(int *)field = (int)x; break;
        case CLI_INT64: *(int64_t *)field = (int64_t)iv; break;
        case CLI_UINT64: *(uint64_t *)field = (uint64_t)uv; break;
        case CLI_DOUBLE: *(double *)field = x; break;
        case CLI_STRING:
        case CLI_CHOICE: *(const char **)field = v; break;
        case CLI_LIST:
            if (!cli_list_add((cli_list *)field, v)) {
                app_error("%s: out of memory", cmd->name);
                return false;
            }
            break;
        }
    }
    return !o->apply || o->apply(args, v, x);
}

int cli_parse(const cli_command *cmd, int argc, char **argv, void *args, cli_pos *pos)
{
    pos->n = 0;
    pos->seen = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            cli_help(cmd, stdout);
            return EXIT_OK;
        }
        if (a[0] != '-' || !a[1]) {
            if (pos->n >= cmd->max_pos || pos->n >= CLI_MAX_POS) {
                if (cmd->max_pos == 1) {
                    app_error("%s: one %s at a time (got %s and %s)", cmd->name, cmd->pos_name,
                              pos->v[0], a);
                } else {
                    app_error("%s: unexpected argument %s (granule %s --help)", cmd->name, a,
                              cmd->name);
                }
                return EXIT_REFUSED;
            }
            pos->v[pos->n++] = a;
            continue;
        }
        const char *eq = strchr(a, '=');
        const size_t len = eq ? (size_t)(eq - a) : strlen(a);
        const cli_opt *o = find(cmd, a, len);
        if (!o) {
            const char *near = cli_nearest(cmd, a);
            app_error("%s: unknown option %s%s%s%s (granule %s --help lists them)", cmd->name, a,
                      near ? "; did you mean " : "", near ? near : "", near ? "?" : "", cmd->name);
            return EXIT_REFUSED;
        }
        const char *v = NULL;
        if (o->type == CLI_FLAG) {
            if (eq) {
                app_error("%s: %s takes no value (got %s)", cmd->name, o->name, a);
                return EXIT_REFUSED;
            }
        } else if (eq) {
            v = eq + 1;
        } else if (i + 1 < argc) {
            v = argv[++i];
        } else {
            app_error("%s: %s needs a value (granule %s --help)", cmd->name, o->name, cmd->name);
            return EXIT_REFUSED;
        }
        if (!take(cmd, o, v ? v : "", args)) {
            return EXIT_REFUSED;
        }
        pos->seen |= o - cmd->opts < 64 ? 1ULL << (o - cmd->opts) : 0;
    }
    return -1;
}

/* "--out DIR", "--force", "--format png|svg|pdf" */
static void option_head(const cli_opt *o, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s", o->name, o->value ? " " : "", o->value ? o->value : "");
}

/* the default and the range of o, as help prints them after its text ("" when neither) */
static void option_tail(const cli_opt *o, char *buf, size_t size)
{
    char allowed[160] = "";
    if (has_range(o)) {
        range_text(o, allowed, sizeof allowed);
    }
    snprintf(buf, size, "%s%s%s%s%s%s", o->def || allowed[0] ? " (" : "", o->def ? "default " : "",
             o->def ? o->def : "", o->def && allowed[0] ? "; " : "", allowed,
             o->def || allowed[0] ? ")" : "");
}

/* text wrapped to 100 columns, every line after the first indented by `indent` */
static void wrapped(FILE *f, const char *text, size_t indent, size_t column)
{
    const size_t width = 100;
    for (const char *p = text; *p;) {
        while (*p == ' ') {
            p++;
        }
        size_t n = strlen(p);
        if (column + n > width) {
            size_t cut = 0;
            for (size_t k = 0; k < n && column + k <= width; k++) {
                cut = p[k] == ' ' ? k : cut;
            }
            n = cut ? cut : strcspn(p, " ");
        }
        fprintf(f, "%.*s", (int)n, p);
        p += n;
        if (*p) {
            fprintf(f, "\n%*s", (int)indent, "");
            column = indent;
        }
    }
    fputc('\n', f);
}

void cli_help(const cli_command *cmd, FILE *f)
{
    fprintf(f, "usage: %s\n", cmd->usage);
    if (cmd->about) {
        fprintf(f, "\n%s", cmd->about);
    }
    fprintf(f, "\noptions:\n");
    const size_t col = 24;
    for (int k = 0; k <= cmd->n_opts; k++) {
        static const cli_opt help = {"--help", CLI_FLAG, NULL, CLI_NOWHERE,      0,
                                     0,        0,        NULL, "this text (-h)", NULL};
        const cli_opt *o = k < cmd->n_opts ? &cmd->opts[k] : &help;
        char head[160], tail[240], text[1400];
        option_head(o, head, sizeof head);
        option_tail(o, tail, sizeof tail);
        snprintf(text, sizeof text, "%s%s", o->help, tail);
        if (strlen(head) + 4 > col) {
            fprintf(f, "  %s\n%*s", head, (int)col, "");
        } else {
            fprintf(f, "  %-*s", (int)col - 2, head);
        }
        wrapped(f, text, col, col);
    }
    if (cmd->epilog) {
        fprintf(f, "\n%s", cmd->epilog);
    }
    if (cmd->more_help) {
        cmd->more_help(f);
    }
}

/* text with the characters Markdown tables and inline text would act on escaped */
static void md_text(FILE *f, const char *text)
{
    for (const char *p = text; *p; p++) {
        if (*p == '|' || *p == '*' || *p == '_' || *p == '<' || *p == '>' || *p == '`' ||
            *p == '[') {
            fputc('\\', f);
        }
        fputc(*p == '\n' ? ' ' : *p, f);
    }
}

void cli_markdown(const cli_command *cmd, FILE *f)
{
    fprintf(f, "## granule %s\n\n```\nusage: %s\n```\n\n", cmd->name, cmd->usage);
    if (cmd->about) {
        fprintf(f, "```\n%s```\n\n", cmd->about);
    }
    fprintf(f, cmd->n_opts ? "| option | default | allowed | meaning |\n|---|---|---|---|\n"
                           : "No options but `--help`.\n");
    for (int k = 0; k < cmd->n_opts; k++) {
        const cli_opt *o = &cmd->opts[k];
        char head[160], allowed[160] = "";
        option_head(o, head, sizeof head);
        if (has_range(o)) {
            range_text(o, allowed, sizeof allowed);
        } else if (o->type == CLI_CHOICE) {
            choice_text(o->value, allowed, sizeof allowed);
        } else if (o->type == CLI_LIST) {
            snprintf(allowed, sizeof allowed, "repeatable");
        }
        fprintf(f, "| `");
        for (const char *p = head; *p; p++) {
            fprintf(f, *p == '|' ? "\\|" : "%c", *p); /* a pipe in a table cell, code span or not */
        }
        fprintf(f, "` | ");
        md_text(f, o->def ? o->def : "");
        fprintf(f, " | ");
        md_text(f, allowed);
        fprintf(f, " | ");
        md_text(f, o->help);
        fprintf(f, " |\n");
    }
    if (cmd->epilog) {
        fprintf(f, "\n```\n%s```\n", cmd->epilog);
    }
    fputc('\n', f);
}
