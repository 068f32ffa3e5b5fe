/* granule plot DIR: redraw the plots of a run folder. */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "io/plot.h"

int cmd_plot(int argc, char **argv)
{
    if (argc != 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        printf("usage: granule plot DIR\nDraws DIR/temperature.png and DIR/ledger.png from the run's CSV files (needs gnuplot).\n");
        return argc == 2 ? EXIT_OK : EXIT_REFUSED;
    }
    char note[300];
    if (gr_plot_run(argv[1], 0, note, sizeof note)) {
        cli_error("plot %s: %s", argv[1], note);
        return EXIT_FAILED;
    }
    printf("%s/temperature.png\n%s/ledger.png\n", argv[1], argv[1]);
    return EXIT_OK;
}
