/* granule cascade: placeholder, being written (issue 5). */
#include <stdio.h>

#include "cli/cli.h"

int cmd_cascade(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    cli_error("cascade: not available yet");
    return EXIT_FAILED;
}
