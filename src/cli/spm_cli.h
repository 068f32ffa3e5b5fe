/* Pieces shared by the granule spm modes (cmd_spm.c, cmd_spm_full.c): the option rows every mode
 * takes, the progress line. The science is in the library (granule/spm_study.h). */
#ifndef GR_SPM_CLI_H
#define GR_SPM_CLI_H

#include <stdbool.h>

#include "cli/options.h"
#include "granule/spm.h"
#include "granule/spm_study.h"

/* The options circle and full take alike; the mode's argument struct T holds them as `spm` and
 * its study parameters as `p` (with p.s the gr_spm_settings and p.bins). */
typedef struct spm_options {
    int dim;        /* 0: not given */
    double mass, D; /* NAN: not given */
    cli_theory th;
    gr_spm_settings *s; /* filled by spm_parse */
    bool mass_set, D_set, dim_set;
} spm_options;

#define SPM_COMMON_OPTS(T, walks_default, bins_default, out_default)                               \
    {"--dim", CLI_INT, "1|2", offsetof(T, spm.dim), 1, 2, 0, "2", "interval or disc", NULL},       \
        {"--mass",                                                                                 \
         CLI_DOUBLE,                                                                               \
         "M",                                                                                      \
         offsetof(T, spm.mass),                                                                    \
         0,                                                                                        \
         0,                                                                                        \
         0,                                                                                        \
         "3.53e-5, Table 2.2",                                                                     \
         "particle mass, kg",                                                                      \
         NULL},                                                                                    \
        {"--D",                                                                                    \
         CLI_DOUBLE,                                                                               \
         "D",                                                                                      \
         offsetof(T, spm.D),                                                                       \
         0,                                                                                        \
         0,                                                                                        \
         0,                                                                                        \
         "1e-8, Table 2.2",                                                                        \
         "noise strength, N^2 s",                                                                  \
         NULL},                                                                                    \
        {"--walks",                                                                                \
         CLI_INT64,                                                                                \
         "N",                                                                                      \
         offsetof(T, p.s.walks),                                                                   \
         2,                                                                                        \
         1e12,                                                                                     \
         0,                                                                                        \
         walks_default,                                                                            \
         "walks (repetitions of the walk)",                                                        \
         NULL},                                                                                    \
        {"--step",                                                                                 \
         CLI_DOUBLE,                                                                               \
         "S",                                                                                      \
         offsetof(T, p.s.step),                                                                    \
         0,                                                                                        \
         0,                                                                                        \
         0,                                                                                        \
         "3e-3",                                                                                   \
         "sampling interval in units of t_l = (M^2 l^2 / 2D)^(1/3)",                               \
         NULL},                                                                                    \
        {"--dt",                                                                                   \
         CLI_DOUBLE,                                                                               \
         "DT",                                                                                     \
         offsetof(T, p.s.dt),                                                                      \
         0,                                                                                        \
         0,                                                                                        \
         0,                                                                                        \
         NULL,                                                                                     \
         "a fixed sampling interval in seconds instead of --step (the thesis' way)",               \
         NULL},                                                                                    \
        {"--refine",                                                                               \
         CLI_INT,                                                                                  \
         "K",                                                                                      \
         offsetof(T, p.s.refine),                                                                  \
         0,                                                                                        \
         30,                                                                                       \
         0,                                                                                        \
         "10",                                                                                     \
         "exact bridge points looked at between samples near the boundary: K levels of bisection " \
         "(0: look at the samples "                                                                \
         "only)",                                                                                  \
         NULL},                                                                                    \
        {"--batches",                                                                              \
         CLI_INT,                                                                                  \
         "B",                                                                                      \
         offsetof(T, p.s.batches),                                                                 \
         2,                                                                                        \
         10000,                                                                                    \
         0,                                                                                        \
         "20",                                                                                     \
         "independent batches of walks for the error bars",                                        \
         NULL},                                                                                    \
        {"--seed",                                                                                 \
         CLI_UINT64,                                                                               \
         "S",                                                                                      \
         offsetof(T, p.s.seed),                                                                    \
         0,                                                                                        \
         9007199254740992.0,                                                                       \
         0,                                                                                        \
         "1",                                                                                      \
         "random seed; results are reproducible from it",                                          \
         NULL},                                                                                    \
        {"--bins", CLI_INT, "N",          offsetof(T, p.bins), 4,                                  \
         100000,   0,       bins_default, "histogram bins",    NULL},                              \
        CLI_THEORY_OPTS(T, spm.th, out_default)

/* Parse a mode's options (args: its argument struct, whose `spm` is o and whose p.s is s) and
 * apply --dim, --mass, --D to s. -1 to go on, else the exit status. */
int spm_parse(const cli_command *cmd, int argc, char **argv, void *args, spm_options *o,
              gr_spm_settings *s);
/* Turn on the progress line on stderr (when interactive and not --quiet). */
void spm_progress_on(spm_options *o, const char *label);
void spm_progress_off(spm_options *o);
/* "  SPM constants (thesis convention): c = .. +- .., c' = .. +- .. (how)" */
void spm_print_constants(const gr_spm_constants *c, const char *how);
/* exit status for a library error */
int spm_exit_code(const gr_error *err);

#endif
