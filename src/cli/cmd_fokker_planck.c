/* granule fokker-planck: placeholder, being written (issue 5). */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

int cmd_fokker_planck(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: granule fokker-planck ... (being written)\n");
        return EXIT_OK;
    }
    cli_error("fokker-planck: not available yet");
    return EXIT_FAILED;
}
