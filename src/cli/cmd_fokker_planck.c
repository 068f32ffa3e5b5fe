/* granule fokker-planck: placeholder, being written (issue 5). */
#include <stdio.h>

#include "cli/cli.h"

int cmd_fokker_planck(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    cli_error("fokker-planck: not available yet");
    return EXIT_FAILED;
}
