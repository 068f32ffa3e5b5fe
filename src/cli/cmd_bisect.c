/* granule bisect: placeholder, being written (issue 5). */
#include <stdio.h>

#include "cli/cli.h"

int cmd_bisect(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    cli_error("bisect: not available yet");
    return EXIT_FAILED;
}
