/* granule plot DIR [--format png|svg|pdf]: redraw every plot of a run folder (or of an analyse,
 * compare, sweep or theory folder, and of the run folders inside it): the pictures an observable
 * or command drew, from the gnuplot bodies (*.gp) kept beside them, and the snapshot picture. */
#include <dirent.h>
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/cli.h"
#include "io/files.h"
#include "app/run_picture.h"
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
        FILE *f = gr_input_fopen(g.gl_pathv[k], &(int){0});
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
        if (len > 0 && body[len - 1] == '\n') {
            body[len - 1] =
                0; /* the newline gr_plot_script wrote after the body: once, not again */
        }
        char *first = strchr(body, '\n'); /* skip the header comment */
        const char *base = strrchr(g.gl_pathv[k], '/') + 1;
        char png[512], picture[600], note[300];
        snprintf(png, sizeof png, "%.*s.png", (int)(strlen(base) - 3), base);
        gr_plot_file_name(png, picture, sizeof picture);
        char *copy = strdup(first ? first + 1 : body);
        if (gr_plot_script(dir, png, copy, note, sizeof note) == 0) {
            printf("%s/%s\n", dir, picture);
            (*drawn)++;
        } else {
            app_error("plot %s/%s: %s", dir, picture, note);
            failures++;
        }
        free(copy);
        free(body);
    }
    globfree(&g);
    return failures;
}

static bool exists(const char *dir, const char *name)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, R_OK) == 0;
}

/* One folder: its scripts (and its analysis/ folder's), a run's snapshot picture, the run's
 * summary.json list of pictures; then every sub-folder that is a run or holds scripts (the
 * models of a comparison, the points of a sweep), `depth` levels down. */
static int redraw_folder(const char *dir, int depth, int *drawn)
{
    int failures = 0;
    char note[300], path[1200];
    /* a run folder written before the temperature and ledger bodies were kept */
    if (exists(dir, "temperature.csv") && exists(dir, "ledger.csv") &&
        !exists(dir, "temperature.gp")) {
        if (gr_plot_run(dir, 0, note, sizeof note)) {
            app_error("plot %s: %s", dir, note);
            failures++;
        } else {
            printf("%s/temperature.%s\n%s/ledger.%s\n", dir,
                   gr_plot_extension(gr_plot_get_format()), dir,
                   gr_plot_extension(gr_plot_get_format()));
            *drawn += 2;
        }
    }
    failures += redraw_scripts(dir, drawn);
    snprintf(path, sizeof path, "%s/analysis", dir);
    if (access(path, R_OK) == 0) {
        failures += redraw_scripts(path, drawn);
    }
    if (exists(dir, "snapshots")) {
        gr_error err = {0};
        char png[1300];
        if (gr_picture_run_ex(dir, NULL, png, sizeof png, &err) == 0) {
            printf("%s\n", png);
            (*drawn)++;
        } else {
            app_error("plot %s: %s", dir, err.message);
            failures++;
        }
    }
    if (exists(dir, "summary.json")) {
        gr_plot_summary_update(dir);
    }
    DIR *d = depth > 0 ? opendir(dir) : NULL;
    for (struct dirent *e; d && (e = readdir(d));) {
        if (e->d_name[0] == '.' || !strcmp(e->d_name, "analysis") ||
            !strcmp(e->d_name, "snapshots")) {
            continue;
        }
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
            continue;
        }
        bool wanted = exists(path, "summary.json");
        if (!wanted) {
            char pattern[1300];
            snprintf(pattern, sizeof pattern, "%s/*.gp", path);
            glob_t g;
            wanted = glob(pattern, 0, NULL, &g) == 0;
            globfree(&g);
        }
        if (wanted) {
            failures += redraw_folder(path, depth - 1, drawn);
        }
    }
    if (d) {
        closedir(d);
    }
    return failures;
}

static const cli_opt plot_opts[] = {
    CLI_OPT_FORMAT,
};

const cli_command cli_cmd_plot = {
    .name = "plot",
    .usage = "granule plot DIR [--format png|svg|pdf]",
    .about = "Redraws every plot in DIR (and DIR/analysis, and the run folders inside a compare or "
             "sweep\n"
             "folder): every observable's and command's pictures from the gnuplot bodies (*.gp) "
             "kept beside\n"
             "them and the snapshot picture coloured by speed (cairo, PNG); a run's summary.json "
             "then lists\n"
             "every picture. Needs gnuplot.\n",
    .pos_name = "folder",
    .max_pos = 1,
    CLI_OPTS(plot_opts),
};

int cmd_plot(int argc, char **argv)
{
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_plot, argc, argv, &(char){0}, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    const char *dir = pos.n ? pos.v[0] : NULL;
    if (!dir) {
        app_error("plot: usage: granule plot DIR [--format png|svg|pdf]");
        return EXIT_REFUSED;
    }
    if (access(dir, R_OK) != 0) {
        app_error("plot %s: no such folder", dir);
        return EXIT_REFUSED;
    }
    int drawn = 0;
    const int failures = redraw_folder(dir, 2, &drawn);
    if (drawn == 0 && failures == 0) {
        app_error("plot %s: nothing to draw (no run outputs found)", dir);
        return EXIT_REFUSED;
    }
    /* each picture's path above; then what was drawn in all */
    printf("plot: drew %d picture%s under %s (graphs as %s)%s\n", drawn, drawn == 1 ? "" : "s", dir,
           gr_plot_extension(gr_plot_get_format()), failures ? "; some failed: see above" : "");
    return failures ? EXIT_FAILED : EXIT_OK;
}
