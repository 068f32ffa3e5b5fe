/* The options every theory command (spm, bisect, cascade, fokker-planck) takes alike; see cli.h. */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

int cli_theory_option(const char *cmd, int argc, char **argv, int *i, bool *force, bool *quiet, bool *plots)
{
    const char *a = argv[*i];
    if (!strcmp(a, "--force") || !strcmp(a, "--quiet") || !strcmp(a, "--no-plots")) {
        *force |= !strcmp(a, "--force");
        *quiet |= !strcmp(a, "--quiet");
        *plots &= !!strcmp(a, "--no-plots");
        return 1;
    }
    if (!strcmp(a, "--format") || !strcmp(a, "--set")) {
        if (*i + 1 >= argc) {
            cli_error("%s: %s needs a value (granule %s --help)", cmd, a, cmd);
            return -1;
        }
        const char *v = argv[++*i];
        if (!strcmp(a, "--format")) {
            return cli_plot_format(v) ? 1 : -1;
        }
        cli_error("%s: --set %s: %s has no scene, so no scene keys to set; its settings are options (granule %s --help)",
                  cmd, v, cmd, cmd);
        return -1;
    }
    return 0;
}
