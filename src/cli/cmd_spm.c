/* granule spm: placeholder, being written (issue 5). */
#include <stdio.h>

#include "cli/cli.h"

int cmd_spm(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    cli_error("spm: not available yet");
    return EXIT_FAILED;
}
