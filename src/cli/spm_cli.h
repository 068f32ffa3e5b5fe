/* Pieces shared by the granule spm modes (cmd_spm.c, cmd_spm_full.c): the options every mode
 * takes, the progress line. The science is in the library (granule/spm_study.h). */
#ifndef GR_SPM_CLI_H
#define GR_SPM_CLI_H

#include <stdbool.h>

#include "granule/spm.h"
#include "granule/spm_study.h"

#define SPM_COMMON_HELP                                                                                      \
    "  --dim 1|2         interval or disc (default 2)\n"                                                      \
    "  --mass M          particle mass, kg (default 3.53e-5, Table 2.2)\n"                                    \
    "  --D D             noise strength, N^2 s (default 1e-8, Table 2.2)\n"                                   \
    "  --walks N         walks (repetitions of the walk) (default %s)\n"                                       \
    "  --step S          sampling interval in units of t_l = (M^2 l^2 / 2D)^(1/3) (default 3e-3)\n"           \
    "  --dt DT           a fixed sampling interval in seconds instead of --step (the thesis' way)\n"          \
    "  --refine K        exact bridge points looked at between samples near the boundary: K levels\n"       \
    "                    of bisection (default 10; 0: look at the samples only)\n"                          \
    "  --batches B       independent batches of walks for the error bars (default 20)\n"                   \
    "  --seed S          random seed (default 1); results are reproducible from it\n"                      \
    "  --bins N          histogram bins (default %d)\n"                                                       \
    "  --out DIR         output folder (default %s)\n"                                                        \
    CLI_THEORY_OPTIONS_HELP

typedef struct spm_options {
    gr_spm_settings *s;
    const char *out;
    bool force, quiet, plots;
    bool mass_set, D_set, dim_set;
    int *bins;
} spm_options;

/* Options shared by the modes. Returns 1 if argv[*i] was one (consuming its value), 0 if not,
 * -1 after printing an error. */
int spm_common_option(int argc, char **argv, int *i, spm_options *o);
/* The value of a mode option as a number (the option is argv[*i]). */
bool spm_value_number(int argc, char **argv, int *i, double *x);
void spm_unknown(const char *mode, const char *a);
/* Turn on the progress line on stderr (when interactive and not --quiet). */
void spm_progress_on(spm_options *o, const char *label);
void spm_progress_off(spm_options *o);
/* "  SPM constants (thesis convention): c = .. +- .., c' = .. +- .. (how)" */
void spm_print_constants(const gr_spm_constants *c, const char *how);
/* exit status for a library error */
int spm_exit_code(const gr_error *err);

#endif
