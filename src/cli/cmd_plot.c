/* granule plot DIR: redraw every plot of a run folder (or of an analyse/compare/theory folder):
 * the temperature and ledger plots of a run, and every picture an observable or command drew,
 * from the gnuplot bodies (*.gp) kept beside them; also the snapshot picture. */
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "io/picture.h"
#include "io/plot.h"

static int redraw_scripts(const char *dir, int *drawn)
{
    char pattern[1200];
    snprintf(pattern, sizeof pattern, "%s/*.gp", dir);
    glob_t g;
    int failures = 0;
    if (glob(pattern, 0, NULL, &g) != 0) {
        return 0;
    }
    for (size_t k = 0; k < g.gl_pathc; k++) {
        FILE *f = fopen(g.gl_pathv[k], "r");
        if (!f) {
            failures++;
            continue;
        }
        char *body = calloc(1, 65536);
        size_t len = body ? fread(body, 1, 65535, f) : 0;
        fclose(f);
        if (!body) {
            failures++;
            continue;
        }
        body[len] = 0;
        char *first = strchr(body, '\n'); /* skip the header comment */
        const char *base = strrchr(g.gl_pathv[k], '/') + 1;
        char png[512], note[300];
        snprintf(png, sizeof png, "%.*s.png", (int)(strlen(base) - 3), base);
        char *copy = strdup(first ? first + 1 : body);
        if (gr_plot_script(dir, png, copy, note, sizeof note) == 0) {
            printf("%s/%s\n", dir, png);
            (*drawn)++;
        } else {
            cli_error("plot %s/%s: %s", dir, png, note);
            failures++;
        }
        free(copy);
        free(body);
    }
    globfree(&g);
    return failures;
}

int cmd_plot(int argc, char **argv)
{
    if (argc != 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        printf("usage: granule plot DIR\nRedraws every plot in DIR (and DIR/analysis): T(t) and the energy ledger of a run, every\n"
               "observable's and command's pictures from the gnuplot bodies (*.gp) kept beside them, and the\n"
               "snapshot picture coloured by speed (cairo). Needs gnuplot for the graphs.\n");
        return argc == 2 ? EXIT_OK : EXIT_REFUSED;
    }
    const char *dir = argv[1];
    if (access(dir, R_OK) != 0) {
        cli_error("plot %s: no such folder", dir);
        return EXIT_REFUSED;
    }
    int drawn = 0, failures = 0;
    char note[300], path[1200];
    snprintf(path, sizeof path, "%s/temperature.csv", dir);
    if (access(path, R_OK) == 0) {
        if (gr_plot_run(dir, 0, note, sizeof note)) {
            cli_error("plot %s: %s", dir, note);
            failures++;
        } else {
            printf("%s/temperature.png\n%s/ledger.png\n", dir, dir);
            drawn += 2;
        }
    }
    failures += redraw_scripts(dir, &drawn);
    snprintf(path, sizeof path, "%s/analysis", dir);
    if (access(path, R_OK) == 0) {
        failures += redraw_scripts(path, &drawn);
    }
    snprintf(path, sizeof path, "%s/snapshots", dir);
    if (access(path, R_OK) == 0) {
        gr_error err = {0};
        char png[1300];
        if (gr_picture_run_ex(dir, NULL, png, sizeof png, &err) == 0) {
            printf("%s\n", png);
            drawn++;
        } else {
            cli_error("plot %s: %s", dir, err.message);
            failures++;
        }
    }
    if (drawn == 0 && failures == 0) {
        cli_error("plot %s: nothing to draw (no run outputs found)", dir);
        return EXIT_REFUSED;
    }
    return failures ? EXIT_FAILED : EXIT_OK;
}
