/* granule bench [core|scaling|noise|sk|all]: regenerate the throughput tables of
 * docs/performance.md on this machine (the bench programs live in bench/; this runs them). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule_config.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: granule bench [core|scaling|noise|sk|all] [--quick]\n\n"
               "  core     particle-steps/s of the 2D and 1D RFM scenes, Verlet list vs cell list every step\n"
               "  scaling  particle-steps/s against N (2D, 1D) and the cost of each effect\n"
               "  noise    ns per normal variate of the random force\n"
               "  sk       S(k) per frame: gridding vs direct sum, accuracy\n"
               "  all      every one of them (default)\n"
               "Each prints the machine, compiler flags and commit beside the numbers; --quick runs tiny sizes.\n"
               "Runs the programs of %s/bench built in %s.\n", GR_SOURCE_DIR, GR_BUILD_DIR);
}

static int run(const char *cmd)
{
    fprintf(stderr, "granule bench: %s\n", cmd);
    fflush(NULL);
    int rc = system(cmd);
    return rc == 0 ? 0 : 1;
}

int cmd_bench(int argc, char **argv)
{
    const char *what = "all";
    bool quick = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--quick")) {
            quick = true;
        } else if (argv[i][0] != '-') {
            what = argv[i];
        } else {
            cli_error("bench: unknown option %s", argv[i]);
            return EXIT_REFUSED;
        }
    }
    const char *names[] = {"core", "scaling", "noise", "sk"};
    bool all = !strcmp(what, "all"), known = all;
    for (int k = 0; k < 4; k++) {
        known |= !strcmp(what, names[k]);
    }
    if (!known) {
        usage(stderr);
        return EXIT_REFUSED;
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/bench/bench_throughput", GR_BUILD_DIR);
    if (access(path, X_OK) != 0) {
        cli_error("bench: %s not found: build the project (ninja -C %s) first", path, GR_BUILD_DIR);
        return EXIT_FAILED;
    }
    char cmd[4096];
    int failures = 0;
    if (all || !strcmp(what, "core")) {
        snprintf(cmd, sizeof cmd, "cd '%s' && bash bench/core_throughput.sh '%s' %s", GR_SOURCE_DIR, GR_BUILD_DIR, quick ? "--quick" : "");
        failures += run(cmd);
    }
    if (all || !strcmp(what, "scaling")) {
        snprintf(cmd, sizeof cmd, "cd '%s' && bash bench/scaling.sh '%s' %s", GR_SOURCE_DIR, GR_BUILD_DIR, quick ? "--quick" : "");
        failures += run(cmd);
    }
    if (all || !strcmp(what, "noise")) {
        snprintf(cmd, sizeof cmd, "'%s/bench/bench_noise'%s", GR_BUILD_DIR, quick ? " --repeats 3" : "");
        failures += run(cmd);
    }
    if (all || !strcmp(what, "sk")) {
        snprintf(cmd, sizeof cmd, "'%s/bench/bench_sk'%s", GR_BUILD_DIR, quick ? " --quick" : "");
        failures += run(cmd);
    }
    return failures ? EXIT_FAILED : EXIT_OK;
}
