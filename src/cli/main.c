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

bool cli_missing_value(const char *cmd, const char *a, const char *with_value, bool last)
{
    const size_t n = strlen(a);
    for (const char *p = strstr(with_value, a); last && n && p; p = strstr(p + 1, a)) {
        if ((p == with_value || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) {
            cli_error("%s: %s needs a value", cmd, a);
            return true;
        }
    }
    return false;
}

bool cli_number(const char *opt, const char *text, double *out)
{
    char *end;
    double x = text ? strtod(text, &end) : 0.0;
    if (!text || end == text || *end) {
        cli_error("%s needs a number, got '%s'", opt, text ? text : "");
        return false;
    }
    *out = x;
    return true;
}

static void usage(FILE *f)
{
    fprintf(f,
            "granule %s (%s): granular dynamics and the Random Force Model\n\n"
            "usage: granule <command> [options]\n\n"
            "commands:\n"
            "  run SCENE      run a scene: summary.json, temperature.csv, ledger.csv, snapshots, plots\n"
            "  collide        one binary collision of Table 2.1: energy loss against 1 - eps^2\n"
            "  models         list the collision models and their parameters\n"
            "  keys           list every scene key (Markdown)\n"
            "  plot DIR       (re)draw the plots of a run folder\n"
            "  analyse DIR    feed a run's snapshots (or a LAMMPS dump) to the analysis layer's observables\n"
            "  compare SCENE  the same scene under several collision models, side by side\n"
            "  cost SCENE     the time step a tolerance needs and the wall time it costs here\n"
            "  sweep FILE     a scene over lists of keys and seeds, in parallel, resumable, with fits\n"
            "  reproduce NAME run a thesis-reproduction campaign (--list) and write its result set\n"
            "  bench          regenerate the throughput tables of docs/performance.md on this machine\n"
            "  observables    list the observables (statistics) a scene can ask for\n"
            "  export lammps SCENE  a LAMMPS deck + data file of the scene (docs/lammps.md)\n"
            "theory models (no N-body run; thesis ch. 3, 5, 6, App. B):\n"
            "  spm            Single Particle Model: Q(v,l), P(v), the predicted tail exponent\n"
            "  bisect         multiplicative bisection process (sec. 3.4)\n"
            "  cascade        multiplicative cascade on a 2^n grid, its S(k) and D_f (sec. 6.2)\n"
            "  fokker-planck  the 1D absorbing-interval Fokker-Planck solution (App. B)\n"
            "  help           this text\n\n"
            "`granule <command> --help` describes each command. Docs: docs/ in the source tree.\n",
            GR_VERSION, GR_COMMIT);
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
    struct {
        const char *name;
        int (*fn)(int, char **);
    } table[] = {{"run", cmd_run}, {"collide", cmd_collide}, {"models", cmd_models},
                 {"keys", cmd_keys}, {"plot", cmd_plot}, {"analyse", cmd_analyse}, {"compare", cmd_compare}, {"cost", cmd_cost}, {"sweep", cmd_sweep}, {"reproduce", cmd_reproduce}, {"bench", cmd_bench},
                 {"analyze", cmd_analyse}, {"observables", cmd_observables}, {"spm", cmd_spm}, {"bisect", cmd_bisect},
                 {"cascade", cmd_cascade}, {"fokker-planck", cmd_fokker_planck}, {"export", cmd_export}};
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        if (strcmp(cmd, table[i].name) == 0) {
            return table[i].fn(argc - 1, argv + 1);
        }
    }
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) {
        usage(stdout);
        return EXIT_OK;
    }
    if (!strcmp(cmd, "--version") || !strcmp(cmd, "version")) {
        printf("granule %s (%s)\n", GR_VERSION, GR_COMMIT);
        return EXIT_OK;
    }
    cli_error("unknown command '%s'; try granule help", cmd);
    return EXIT_REFUSED;
}
