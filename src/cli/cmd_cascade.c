/* granule cascade: placeholder, being written (issue 5). */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

int cmd_cascade(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: granule cascade ... (being written)\n");
        return EXIT_OK;
    }
    cli_error("cascade: not available yet");
    return EXIT_FAILED;
}
