/* The option tables of the granule command (issue 34 item 7): one table per command, each row
 * an option's name, type, range, default and help, and where its value goes. One parser reads
 * argv against the table, checks types and ranges (the message names the option and the allowed
 * range), suggests the nearest option for an unknown one, and the same table prints `--help` and
 * the Markdown of docs/cli.md (`granule help --markdown`). */
#ifndef GR_CLI_OPTIONS_H
#define GR_CLI_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef enum cli_type {
    CLI_FLAG,   /* bool: present or not */
    CLI_INT,    /* int: an integer in [min, max] */
    CLI_INT64,  /* int64_t: an integer in [min, max] */
    CLI_UINT64, /* uint64_t: an integer in [min, max] (a seed) */
    CLI_DOUBLE, /* double: a finite number in min..max (ends open or closed, see range) */
    CLI_STRING, /* const char *: any text */
    CLI_CHOICE, /* const char *: one of the words of `value` ("png|svg|pdf") */
    CLI_LIST,   /* cli_list: a repeatable text option (--set K=V ...) */
} cli_type;

/* range of a CLI_DOUBLE: the ends that are excluded ("(0, 1]" is CLI_MIN_OPEN) */
enum { CLI_MIN_OPEN = 1, CLI_MAX_OPEN = 2 };

/* the values of a repeatable option, in the order given (items freed by cli_list_free) */
typedef struct cli_list {
    const char **items;
    int n;
} cli_list;

/* where a row stores nothing (its apply hook does the work) */
#define CLI_NOWHERE ((size_t)-1)

typedef struct cli_opt {
    const char *name; /* "--out" */
    cli_type type;
    const char
        *value; /* the value's name in help ("DIR"); the words of a CLI_CHOICE ("png|svg|pdf") */
    size_t at;  /* offsetof(the command's argument struct, field), or CLI_NOWHERE */
    double min, max; /* range of the integer types and CLI_DOUBLE; unchecked when min >= max;
                        * +-INFINITY for an open-ended one */
    int range;       /* CLI_MIN_OPEN | CLI_MAX_OPEN for a CLI_DOUBLE */
    const char *def; /* the default, as help and docs/cli.md print it (NULL: none shown) */
    const char *help;
    /* optional: called with the parsed arguments, the checked value and its number as soon as it
     * is read, in the order given (--threads sets the thread count, --format the plot format);
     * false after an error message refuses the command line */
    bool (*apply)(void *args, const char *text, double number);
} cli_opt;

typedef struct cli_command {
    const char *name;   /* "run", "spm circle" */
    const char *usage;  /* the synopsis lines after "usage: " (several forms on several lines) */
    const char *about;  /* what the command does, before the options */
    const char *epilog; /* after the options: outputs, exit status (may be NULL) */
    const char
        *pos_name; /* the positional argument's name in messages ("scene"); NULL: none taken */
    int max_pos;   /* how many positional arguments at most */
    const cli_opt *opts;
    int n_opts;
    /* optional: more help after the epilog, for --help only (what depends on this build, such as
     * its paths, stays out of docs/cli.md) */
    void (*more_help)(FILE *f);
} cli_command;

/* .opts and .n_opts of a cli_command from a table */
#define CLI_OPTS(table) .opts = table, .n_opts = (int)(sizeof table / sizeof table[0])

/* a numeric macro's value as text, for help strings */
#define CLI_STR_(x) #x
#define CLI_STR(x) CLI_STR_(x)

#define CLI_MAX_POS 4

/* the positional arguments (not options nor their values), in order */
typedef struct cli_pos {
    const char *v[CLI_MAX_POS];
    int n;
    unsigned long long seen; /* bit k: row k of the table was given */
} cli_pos;

/* Was the option `name` of cmd given (after cli_parse filled pos)? */
bool cli_given(const cli_command *cmd, const cli_pos *pos, const char *name);

/* Read argv[1..argc-1] against cmd's table into args (the struct the rows' `at` offsets point
 * into, set to its defaults by the caller) and pos. --NAME VALUE and --NAME=VALUE both work;
 * -h/--help prints the help on stdout. Returns -1 to go on, else the exit status to return now:
 * 0 after --help, 2 after an error on stderr ("CMD: ..." naming the option, and the allowed range
 * or the nearest option's name). */
int cli_parse(const cli_command *cmd, int argc, char **argv, void *args, cli_pos *pos);
void cli_list_free(cli_list *l);
/* Append text to l (false when out of memory). */
bool cli_list_add(cli_list *l, const char *text);
/* The help of cmd, generated from its table ("usage: ..." first). */
void cli_help(const cli_command *cmd, FILE *f);
/* cmd's section of docs/cli.md. */
void cli_markdown(const cli_command *cmd, FILE *f);
/* The option of cmd's table nearest to `given` (edit distance, or a unique prefix), or NULL when
 * none is near. */
const char *cli_nearest(const cli_command *cmd, const char *given);

/* Rows that every command writing files spells alike (issue 34 item 7); T is the argument struct. */
#define CLI_OPT_OUT(T, field, def_text)                                                            \
    {                                                                                              \
        "--out", CLI_STRING, "DIR", offsetof(T, field), 0, 0, 0, def_text, "output folder", NULL   \
    }
#define CLI_OPT_FORCE(T, field)                                                                    \
    {                                                                                              \
        "--force", CLI_FLAG, NULL, offsetof(T, field), 0, 0, 0, NULL,                              \
            "overwrite the results of an earlier run in the output folder", NULL                   \
    }
#define CLI_OPT_QUIET(T, field)                                                                    \
    {                                                                                              \
        "--quiet", CLI_FLAG, NULL, offsetof(T, field), 0, 0, 0, NULL, "no progress line", NULL     \
    }
#define CLI_OPT_NO_PLOTS(T, field)                                                                 \
    {                                                                                              \
        "--no-plots", CLI_FLAG, NULL, offsetof(T, field), 0, 0, 0, NULL, "draw no plots", NULL     \
    }
#define CLI_OPT_SET(T, field)                                                                      \
    {                                                                                              \
        "--set", CLI_LIST, "K=V", offsetof(T, field), 0, 0, 0, NULL,                               \
            "override a scene key, e.g. --set model.eps_n=0.5 (repeatable; docs/scene-keys.md)",   \
            NULL                                                                                   \
    }
/* The options every theory command (spm, bisect, cascade, fokker-planck) takes alike; its
 * argument struct T holds them as the member th (a member path: th, spm.th). --set is refused after parsing
 * (cli_theory_set_refused). */
typedef struct cli_theory {
    const char *out;
    cli_list sets;
    bool force, quiet, no_plots;
} cli_theory;
#define CLI_THEORY_OPTS(T, th, out_default)                                                        \
    CLI_OPT_OUT(T, th.out, out_default), CLI_OPT_FORCE(T, th.force),                               \
        CLI_OPT_NO_PLOTS(T, th.no_plots), CLI_OPT_FORMAT, CLI_OPT_QUIET(T, th.quiet),              \
    {                                                                                              \
        "--set", CLI_LIST, "K=V", offsetof(T, th.sets), 0, 0, 0, NULL,                             \
            "refused: a theory command reads no scene; its settings are options", NULL             \
    }
/* After parsing a theory command: true (after the message) when --set was given; frees the list. */
bool cli_theory_set_refused(const cli_command *cmd, cli_theory *th);

#define CLI_OPT_FORMAT                                                                             \
    {                                                                                              \
        "--format", CLI_CHOICE, "png|svg|pdf", CLI_NOWHERE, 0, 0, 0, "png",                        \
            "the format of every plot", cli_apply_format                                           \
    }
#define CLI_OPT_THREADS                                                                            \
    {                                                                                              \
        "--threads", CLI_INT, "N", CLI_NOWHERE, 1, 1024, 0, "1, or OMP_NUM_THREADS",               \
            "threads; the results are bit-identical for every N (docs/performance.md)",            \
            cli_apply_threads                                                                      \
    }

bool cli_apply_format(void *args, const char *text, double number);
bool cli_apply_threads(void *args, const char *text, double number);

#endif
