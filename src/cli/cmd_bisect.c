/* granule bisect: placeholder, being written (issue 5). */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

int cmd_bisect(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: granule bisect ... (being written)\n");
        return EXIT_OK;
    }
    cli_error("bisect: not available yet");
    return EXIT_FAILED;
}
