/* Shared pieces of the granule command: subcommand entry points and option helpers. */
#ifndef GR_CLI_H
#define GR_CLI_H

#include <stdbool.h>
#include <stdio.h>

#include "app/report.h"
#include "cli/options.h"
#include "granule/status.h"

int cmd_run(int argc, char **argv);
/* The option tables of the commands (granule help --markdown writes docs/cli.md from them). */
extern const cli_command cli_cmd_run;
extern const cli_command cli_cmd_sweep;
extern const cli_command cli_cmd_compare;
extern const cli_command cli_cmd_analyse;
extern const cli_command cli_cmd_reproduce;
extern const cli_command cli_cmd_bisect;
extern const cli_command cli_cmd_cascade;
extern const cli_command cli_cmd_fokker_planck;
extern const cli_command cli_cmd_cost;
extern const cli_command cli_cmd_plot;
extern const cli_command cli_cmd_export;
extern const cli_command cli_cmd_bench;
extern const cli_command cli_cmd_collide;
extern const cli_command cli_cmd_models, cli_cmd_keys, cli_cmd_observables;
extern const cli_command cli_cmd_spm_circle, cli_cmd_spm_full, cli_cmd_spm_predict;
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

/* Error lines, exit codes and the terminal test: the application layer's (src/app/report.h). */
/* "T = <mean> +- <error> m^2/s^2" with the warning of an unconverged error bar, as run and
 * analyse print it (defined in cmd_run.c). */
void cli_T_text(char *buf, size_t size, double T_mean, double T_stderr, int converged);

#endif
