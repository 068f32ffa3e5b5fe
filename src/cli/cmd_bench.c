/* granule bench [PART|all]: regenerate the tables and plots of docs/performance.md (and the
 * benchmark tables of docs/event-driven.md, docs/hybrid.md, docs/checkpoints.md) on this machine.
 * The bench programs and scripts live in bench/; this runs them, one part or all in order.
 * Tables and plots go to --out (default out/bench in the current folder); only --update-docs
 * writes them into the source tree's out/bench and docs/img, the files the docs show. --quick is a
 * smoke test (tiny sizes, the test suite's) and says so. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule_config.h"

/* One part: a script of bench/ taking [BUILD_DIR] [--quick], or a bench program of the build. */
typedef struct {
    const char *name;
    const char *script;  /* bench/NAME.sh, or NULL for a program */
    const char *program; /* bench/NAME in the build folder, or NULL */
    const char *quick;   /* its quick-mode arguments */
    const char *doc;
} bench_part;

static const bench_part parts[] = {
    {"core", "core_throughput.sh", NULL, "--quick",
     "particle-steps/s of the 2D and 1D RFM scenes, Verlet list vs cell list every step"},
    {"scaling", "scaling.sh", NULL, "--quick",
     "particle-steps/s against N (2D, 1D) and the cost of each effect"},
    {"throughput", "throughput_all.sh", NULL, "--quick",
     "every model and integrator against N (2D 1e3-1e5, 1D 1e2-1e4), threads;\n"
     "                   out/bench/throughput.md, docs/img/scaling.png"},
    {"threads", "threads.sh", NULL, "--quick",
     "OpenMP speed-up of the soft-sphere core (docs/performance.md, Threads)"},
    {"noise", NULL, "bench_noise", "--repeats 3", "ns per normal variate of the random force"},
    {"sk", NULL, "bench_sk", "--quick", "S(k) per frame: gridding vs direct sum, accuracy"},
    {"accuracy", "accuracy_cost.sh", NULL, "--quick",
     "error (collision energy loss, steady temperature) against wall seconds per\n"
     "                   simulated second as dt grows; out/bench/accuracy-*.md, "
     "docs/img/accuracy-*.png"},
    {"cost", "cost_check.sh", NULL, "--quick",
     "granule cost's recommended dt and predicted wall time against real runs"},
    {"event", "event_throughput.sh", NULL, "--quick",
     "event-driven collisions/s and events/s (docs/event-driven.md)"},
    {"hybrid", "hybrid_speedup.sh", NULL, "--quick",
     "hybrid against soft-sphere: speed-up at equal accuracy (docs/hybrid.md)"},
    {"hybrid-agreement", "hybrid_agreement.sh", NULL, "--quick",
     "hybrid against soft-sphere over several seeds (long)"},
    {"lammps", "lammps.sh", NULL, "--quick",
     "the 2D RFM scene and single collisions side by side with LAMMPS (skipped\n"
     "                   without lmp; --install installs the Debian package lammps, as root)"},
};
enum { N_PARTS = sizeof parts / sizeof parts[0] };

/* the parts and this build's paths, after the generated help */
static void parts_help(FILE *f)
{
    fprintf(f, "\nparts:\n");
    for (int k = 0; k < N_PARTS; k++) {
        fprintf(f, "  %-16s %s\n", parts[k].name, parts[k].doc);
    }
    fprintf(f,
            "  %-16s every one of them, in this order (default)\n\n"
            "--update-docs writes %s/out/bench and %s/docs/img.\n"
            "Runs the programs and scripts of %s/bench built in %s.\n",
            "all", GR_SOURCE_DIR, GR_SOURCE_DIR, GR_SOURCE_DIR, GR_BUILD_DIR);
}

typedef struct bench_args {
    const char *out;
    bool quick, update_docs, install;
} bench_args;

static const cli_opt bench_opts[] = {
    {"--quick", CLI_FLAG, NULL, offsetof(bench_args, quick), 0, 0, 0, NULL,
     "a smoke test: tiny sizes (what the test suite runs), every part once; the numbers are not "
     "benchmarks and nothing "
     "is kept",
     NULL},
    {"--out", CLI_STRING, "DIR", offsetof(bench_args, out), 0, 0, 0, "out/bench",
     "tables (CSV, Markdown) in DIR, plots in DIR/img", NULL},
    {"--update-docs", CLI_FLAG, NULL, offsetof(bench_args, update_docs), 0, 0, 0, NULL,
     "write into the source tree instead: out/bench and docs/img, the files docs/performance.md "
     "shows",
     NULL},
    {"--install", CLI_FLAG, NULL, offsetof(bench_args, install), 0, 0, 0, NULL,
     "lammps part: install the Debian package lammps first (as root)", NULL},
};

const cli_command cli_cmd_bench = {
    .name = "bench",
    .usage = "granule bench [PART|all] [--quick] [--out DIR | --update-docs] [--install]",
    .about = "Regenerates the throughput tables of docs/performance.md on this machine (granule "
             "bench --help\n"
             "lists the parts). Each prints the machine, compiler flags and commit beside the "
             "numbers.\n",
    .epilog = "A part whose script is not in this source tree is skipped with a note.\n",
    .pos_name = "part",
    .max_pos = 1,
    CLI_OPTS(bench_opts),
    .more_help = parts_help,
};

static int run(const char *cmd)
{
    fprintf(stderr, "granule bench: %s\n", cmd);
    fflush(NULL);
    int rc = system(cmd);
    return rc == 0 ? 0 : 1;
}

static int run_part(const bench_part *p, bool quick, bool install)
{
    char cmd[4096], path[1200];
    if (p->script) {
        snprintf(path, sizeof path, "%s/bench/%s", GR_SOURCE_DIR, p->script);
        if (access(path, R_OK) != 0) {
            printf("bench %s: skipped: %s is not in this source tree\n", p->name, path);
            return 0;
        }
        snprintf(cmd, sizeof cmd, "cd '%s' && bash 'bench/%s' '%s' %s%s", GR_SOURCE_DIR, p->script,
                 GR_BUILD_DIR, quick ? p->quick : "",
                 install && !strcmp(p->name, "lammps") ? " --install" : "");
    } else {
        snprintf(path, sizeof path, "%s/bench/%s", GR_BUILD_DIR, p->program);
        if (access(path, X_OK) != 0) {
            printf("bench %s: skipped: %s is not built\n", p->name, path);
            return 0;
        }
        snprintf(cmd, sizeof cmd, "'%s' %s", path, quick ? p->quick : "");
    }
    return run(cmd);
}

/* Where a full run writes: GRANULE_BENCH_OUT and GRANULE_BENCH_IMG for bench/lib.sh (absolute,
 * since the scripts run in the source tree). */
static int set_outputs(const char *out, bool update_docs)
{
    char dir[PATH_MAX + 1000], img[PATH_MAX + 1010], cwd[PATH_MAX];
    if (update_docs) {
        snprintf(dir, sizeof dir, "%s/out/bench", GR_SOURCE_DIR);
        snprintf(img, sizeof img, "%s/docs/img", GR_SOURCE_DIR);
    } else {
        if (out[0] != '/' && getcwd(cwd, sizeof cwd)) {
            snprintf(dir, sizeof dir, "%s/%s", cwd, out);
        } else {
            snprintf(dir, sizeof dir, "%s", out);
        }
        snprintf(img, sizeof img, "%s/img", dir);
    }
    if (setenv("GRANULE_BENCH_OUT", dir, 1) || setenv("GRANULE_BENCH_IMG", img, 1)) {
        app_error("bench: cannot set the output folder %s", dir);
        return EXIT_FAILED;
    }
    printf("granule bench: tables in %s, plots in %s%s\n", dir, img,
           update_docs ? " (--update-docs: the source tree's files)" : "");
    return EXIT_OK;
}

int cmd_bench(int argc, char **argv)
{
    bench_args args = {0};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_bench, argc, argv, &args, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    const char *what = pos.n ? pos.v[0] : "all", *out = args.out ? args.out : "out/bench";
    const bool quick = args.quick, install = args.install, update_docs = args.update_docs,
               out_given = args.out != NULL;
    if (strlen(out) > 900) {
        app_error("bench: --out needs a folder (at most 900 characters)");
        return EXIT_REFUSED;
    }
    bool all = !strcmp(what, "all"), known = all;
    for (int k = 0; k < N_PARTS; k++) {
        known |= !strcmp(what, parts[k].name);
    }
    if (!known) {
        app_error("bench: unknown part '%s'", what);
        cli_help(&cli_cmd_bench, stderr);
        return EXIT_REFUSED;
    }
    if (update_docs && (out_given || quick)) {
        app_error("bench: --update-docs writes the source tree's files; it takes neither --out nor "
                  "--quick");
        return EXIT_REFUSED;
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/bench/bench_throughput", GR_BUILD_DIR);
    if (access(path, X_OK) != 0) {
        app_error("bench: %s not found: build the project (ninja -C %s) first", path, GR_BUILD_DIR);
        return EXIT_FAILED;
    }
    if (quick) {
        printf("granule bench --quick: SMOKE TEST: tiny sizes, every part once, nothing kept; the "
               "numbers below are not "
               "benchmarks (run without --quick for those)\n");
    } else if (set_outputs(out, update_docs)) {
        return EXIT_FAILED;
    }
    fflush(stdout);
    int failures = 0;
    for (int k = 0; k < N_PARTS; k++) {
        if (all || !strcmp(what, parts[k].name)) {
            failures += run_part(&parts[k], quick, install);
        }
    }
    if (failures) {
        fprintf(stderr, "granule bench: %d part%s failed\n", failures, failures == 1 ? "" : "s");
    }
    if (quick) {
        printf("granule bench --quick: smoke test %s (%d part%s failed); not benchmark numbers\n",
               failures ? "FAILED" : "passed", failures, failures == 1 ? "" : "s");
    }
    return failures ? EXIT_FAILED : EXIT_OK;
}
