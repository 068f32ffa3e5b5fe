/* Shared pieces of the granule command: subcommand entry points and option helpers. */
#ifndef GR_CLI_H
#define GR_CLI_H

#include <stdbool.h>
#include <stdio.h>

#include "app/report.h"
#include "granule/status.h"

int cmd_run(int argc, char **argv);
/* SIGTERM/SIGINT ask `granule run` to checkpoint and stop (exit 5; a second signal kills): main
 * installs this before anything else, so a signal during option parsing or scene loading is a
 * stop at step 0 as well. Defined in cmd_run.c. */
void cmd_run_catch_stop(void);
int cmd_collide(int argc, char **argv);
int cmd_models(int argc, char **argv);
int cmd_keys(int argc, char **argv);
int cmd_plot(int argc, char **argv);
int cmd_analyse(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_cost(int argc, char **argv);
int cmd_sweep(int argc, char **argv);
int cmd_reproduce(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_observables(int argc, char **argv);
int cmd_spm(int argc, char **argv);
int cmd_bisect(int argc, char **argv);
int cmd_cascade(int argc, char **argv);
int cmd_fokker_planck(int argc, char **argv);
int cmd_export(int argc, char **argv);

/* Error lines, exit codes and the terminal test are the application layer's (src/app/report.h);
 * the command files use them under their CLI names. */
#define cli_error app_error
#define cli_print_escaped app_print_escaped
#define cli_exit_code app_exit_code
#define cli_interactive app_interactive
/* For the branch of an option loop that met an argument it does not take: when `a` is one of the
 * space-separated options of `with_value` and is the last argument (`last`), print "CMD: A needs
 * a value" and return true (the caller then refuses, exit 2); false otherwise (the caller reports
 * the argument as unknown). */
bool cli_missing_value(const char *cmd, const char *a, const char *with_value, bool last);
/* Parse a number option value or print an error naming the option. */
bool cli_number(const char *opt, const char *text, double *out);
/* --threads N: use N OpenMP threads (1 to 1024; results do not depend on N). False (after an
 * error naming the allowed range) for anything else. Defined in cmd_run.c. */
bool cli_threads(const char *text);
/* --format png|svg|pdf: draw every plot of this command in that format (gr_plot_set_format).
 * False (after an error naming the allowed values) for anything else. Defined in cmd_run.c. */
bool cli_plot_format(const char *text);
/* The options every theory command takes alike (src/cli/theory_options.c): --force, --quiet,
 * --no-plots, --format png|svg|pdf; --set is refused with a message (no scene). Returns 1 if
 * argv[*i] was one (its value consumed), 0 if not, -1 after printing an error naming cmd. */
int cli_theory_option(const char *cmd, int argc, char **argv, int *i, bool *force, bool *quiet, bool *plots);
#define CLI_THEORY_OPTIONS_HELP                                                                              \
    "  --force           overwrite the results of an earlier run in DIR\n"                                   \
    "  --no-plots        no plots\n"                                                                         \
    "  --format F        plots as png (default), svg or pdf\n"                                              \
    "  --quiet           no progress line\n"
/* "T = <mean> +- <error> m^2/s^2" with the warning of an unconverged error bar, as run and
 * analyse print it (defined in cmd_run.c). */
void cli_T_text(char *buf, size_t size, double T_mean, double T_stderr, int converged);

#endif
