/* The granule command: dispatch to one file per subcommand. */
#include <gsl/gsl_errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule_commit.h"
#include "granule_config.h"

typedef struct command {
    const char *name, *args, *summary;
    int (*fn)(int, char **);
    const cli_command
        *table; /* NULL: its options are not in a table yet (see its --help), or in its modes' */
} command;

/* the tables of spm's modes */
static const cli_command *const spm_modes[] = {&cli_cmd_spm_circle, &cli_cmd_spm_full,
                                               &cli_cmd_spm_predict};

static const command commands[] = {
    {"run", "SCENE", "run a scene: summary.json, temperature.csv, ledger.csv, snapshots, plots",
     cmd_run, &cli_cmd_run},
    {"collide", "", "one binary collision of Table 2.1: energy loss against 1 - eps^2", cmd_collide,
     &cli_cmd_collide},
    {"models", "", "list the collision models and their parameters", cmd_models, &cli_cmd_models},
    {"keys", "", "list every scene key (Markdown)", cmd_keys, &cli_cmd_keys},
    {"plot", "DIR", "(re)draw the plots of a run folder", cmd_plot, &cli_cmd_plot},
    {"analyse", "DIR",
     "feed a run's snapshots (or a LAMMPS dump) to the analysis layer's observables", cmd_analyse,
     &cli_cmd_analyse},
    {"compare", "SCENE", "the same scene under several collision models, side by side", cmd_compare,
     &cli_cmd_compare},
    {"cost", "SCENE", "the time step a tolerance needs and the wall time it costs here", cmd_cost,
     &cli_cmd_cost},
    {"sweep", "FILE", "a scene over lists of keys and seeds, in parallel, resumable, with fits",
     cmd_sweep, &cli_cmd_sweep},
    {"reproduce", "NAME", "run a thesis-reproduction campaign (--list) and write its result set",
     cmd_reproduce, &cli_cmd_reproduce},
    {"bench", "", "regenerate the throughput tables of docs/performance.md on this machine",
     cmd_bench, &cli_cmd_bench},
    {"observables", "", "list the observables (statistics) a scene can ask for", cmd_observables,
     &cli_cmd_observables},
    {"export", "lammps SCENE", "a LAMMPS deck + data file of the scene (docs/lammps.md)",
     cmd_export, &cli_cmd_export},
    {"spm", "", "Single Particle Model: Q(v,l), P(v), the predicted tail exponent", cmd_spm, NULL},
    {"bisect", "", "multiplicative bisection process (sec. 3.4)", cmd_bisect, &cli_cmd_bisect},
    {"cascade", "", "multiplicative cascade on a 2^n grid, its S(k) and D_f (sec. 6.2)",
     cmd_cascade, &cli_cmd_cascade},
    {"fokker-planck", "", "the 1D absorbing-interval Fokker-Planck solution (App. B)",
     cmd_fokker_planck, &cli_cmd_fokker_planck},
};
enum { N_COMMANDS = sizeof commands / sizeof commands[0], FIRST_THEORY = 13 };

static void usage(FILE *f)
{
    fprintf(f,
            "granule %s (%s): granular dynamics and the Random Force Model\n\n"
            "usage: granule <command> [options]\n"
            "       granule help <command>    the same as granule <command> --help\n"
            "       granule -V | --version\n\n"
            "commands:\n",
            GR_VERSION, GR_COMMIT);
    for (int k = 0; k < N_COMMANDS; k++) {
        char head[40];
        snprintf(head, sizeof head, "%s%s%s", commands[k].name, commands[k].args[0] ? " " : "",
                 commands[k].args);
        if (k == FIRST_THEORY) {
            fprintf(f, "theory models (no N-body run; thesis ch. 3, 5, 6, App. B):\n");
        }
        fprintf(f, "  %-*s%s\n", strlen(head) >= 15 ? (int)strlen(head) + 1 : 15, head,
                commands[k].summary);
    }
    fprintf(f,
            "  help           this text\n\n"
            "`granule <command> --help` describes each command; docs/cli.md lists every option.\n"
            "Docs: docs/ in the source tree.\n");
}

/* docs/cli.md: the reference of every command's options, from their tables */
static void markdown(FILE *f)
{
    fprintf(
        f, "# The granule command line\n\n"
           "Generated from the option tables in src/cli by `granule help --markdown`; do not edit "
           "(the `docs`\n"
           "test compares). Every command takes `--help` (`-h`), and `granule help COMMAND` prints "
           "the same;\n"
           "`granule -V` (`--version`) prints the version. Options take their value as `--name "
           "VALUE` or\n"
           "`--name=VALUE`; a value out of its allowed range is refused naming the option and the "
           "range\n"
           "(exit 2), and an unknown option is refused with the nearest known one. The commands "
           "that write\n"
           "files spell the shared options alike: `--out DIR`, `--force`, `--format png|svg|pdf`,\n"
           "`--no-plots`, `--set section.key=value` (where a scene is read). An option is one row "
           "of its\n"
           "command's table (src/cli/cmd_NAME.c: name, type, range, default, help); after adding "
           "one,\n"
           "regenerate this page with `granule help --markdown > docs/cli.md`.\n\n");
    for (int k = 0; k < N_COMMANDS; k++) {
        if (commands[k].table) {
            cli_markdown(commands[k].table, f);
        } else if (commands[k].fn == cmd_spm) {
            for (size_t m = 0; m < sizeof spm_modes / sizeof spm_modes[0]; m++) {
                cli_markdown(spm_modes[m], f);
            }
        } else {
            fprintf(f, "## granule %s\n\n%s; `granule %s --help` lists its options.\n\n",
                    commands[k].name, commands[k].summary, commands[k].name);
        }
    }
}

static const command *find_command(const char *name)
{
    for (int k = 0; k < N_COMMANDS; k++) {
        if (!strcmp(name, commands[k].name)) {
            return &commands[k];
        }
    }
    return !strcmp(name, "analyze") ? find_command("analyse") : NULL;
}

/* "unknown command 'x'" with the nearest command's name, when one is near */
static void unknown_command(const char *name)
{
    cli_opt names[N_COMMANDS];
    for (int k = 0; k < N_COMMANDS; k++) {
        names[k] = (cli_opt){.name = commands[k].name};
    }
    const cli_command all = {.name = "granule", .opts = names, .n_opts = N_COMMANDS};
    const char *near = cli_nearest(&all, name);
    app_error("unknown command '%s'%s%s%s (granule help lists them)", name,
              near ? "; did you mean '" : "", near ? near : "", near ? "'?" : "");
}

/* granule help [COMMAND [MODE]] | help --markdown */
static int help(int argc, char **argv)
{
    if (argc < 2) {
        usage(stdout);
        return EXIT_OK;
    }
    if (!strcmp(argv[1], "--markdown")) {
        markdown(stdout);
        return EXIT_OK;
    }
    const command *c = find_command(argv[1]);
    if (!c) {
        unknown_command(argv[1]);
        return EXIT_REFUSED;
    }
    char *args[4] = {argv[1], argc > 2 ? argv[2] : "--help", "--help", NULL};
    return c->fn(argc > 2 ? 3 : 2, args);
}

int main(int argc, char **argv)
{
    if (argc >= 2 && !strcmp(argv[1], "run")) {
        cmd_run_catch_stop(); /* first: a stop signal from here on is a checkpoint and exit 5 */
    }
    gsl_set_error_handler_off(); /* the library reports GSL errors through return values */
    if (argc < 2) {
        usage(stderr);
        return EXIT_REFUSED;
    }
    const char *cmd = argv[1];
    const command *c = find_command(cmd);
    if (c) {
        return c->fn(argc - 1, argv + 1);
    }
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) {
        return help(argc - 1, argv + 1);
    }
    if (!strcmp(cmd, "--version") || !strcmp(cmd, "version") || !strcmp(cmd, "-V")) {
        printf("granule %s (%s)\n", GR_VERSION, GR_COMMIT);
        return EXIT_OK;
    }
    unknown_command(cmd);
    return EXIT_REFUSED;
}
