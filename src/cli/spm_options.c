/* Options and the progress line shared by the granule spm modes; see spm_cli.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "cli/spm_cli.h"

static bool integer_option(const char *opt, double x, double lo, double hi)
{
    if (!(x >= lo && x <= hi) || x != floor(x)) {
        cli_error("spm: %s must be an integer in [%.0f, %.0f], got %g", opt, lo, hi, x);
        return false;
    }
    return true;
}

/* an integer option's range, or lo > hi for a plain number */
static const struct {
    const char *name;
    double lo, hi;
} with_value[] = {{"--out", 1, 0},      {"--dim", 1, 0},     {"--mass", 1, 0},      {"--D", 1, 0},
                  {"--walks", 2, 1e12}, {"--step", 1, 0},    {"--dt", 1, 0},        {"--refine", 0, 30},
                  {"--batches", 2, 10000}, {"--seed", 0, 9007199254740992.0}, {"--bins", 4, 100000}};

int spm_common_option(int argc, char **argv, int *i, spm_options *o)
{
    const char *a = argv[*i];
    const int common = cli_theory_option("spm", argc, argv, i, &o->force, &o->quiet, &o->plots);
    if (common) {
        return common;
    }
    int k = -1;
    for (int j = 0; j < (int)(sizeof with_value / sizeof with_value[0]); j++) {
        if (!strcmp(a, with_value[j].name)) {
            k = j;
        }
    }
    if (k < 0) {
        return 0;
    }
    if (*i + 1 >= argc) {
        cli_error("spm: %s needs a value", a);
        return -1;
    }
    const char *v = argv[++*i];
    if (!strcmp(a, "--out")) {
        if (strlen(v) >= 1000) {
            cli_error("spm: --out %s: path too long", v);
            return -1;
        }
        o->out = v;
        return 1;
    }
    double x;
    if (!cli_number(a, v, &x)) {
        return -1;
    }
    if (with_value[k].lo <= with_value[k].hi && !integer_option(a, x, with_value[k].lo, with_value[k].hi)) {
        return -1;
    }
    gr_spm_settings *s = o->s;
    if (!strcmp(a, "--dim")) {
        if (x != 1.0 && x != 2.0) {
            cli_error("spm: --dim must be 1 or 2, got %s", v);
            return -1;
        }
        s->dim = (int)x;
        o->dim_set = true;
    } else if (!strcmp(a, "--mass")) {
        s->mass = x;
        o->mass_set = true;
    } else if (!strcmp(a, "--D")) {
        s->D = x;
        o->D_set = true;
    } else if (!strcmp(a, "--walks")) {
        s->walks = (int64_t)x;
    } else if (!strcmp(a, "--step")) {
        s->step = x;
    } else if (!strcmp(a, "--dt")) {
        s->dt = x;
    } else if (!strcmp(a, "--refine")) {
        s->refine = (int)x;
    } else if (!strcmp(a, "--batches")) {
        s->batches = (int)x;
    } else if (!strcmp(a, "--seed")) {
        s->seed = (uint64_t)x;
    } else {
        *o->bins = (int)x;
    }
    return 1;
}

bool spm_value_number(int argc, char **argv, int *i, double *x)
{
    if (*i + 1 >= argc) {
        cli_error("spm: %s needs a value", argv[*i]);
        return false;
    }
    const char *opt = argv[*i];
    return cli_number(opt, argv[++*i], x);
}

void spm_unknown(const char *mode, const char *a)
{
    cli_error("spm %s: unknown option %s (granule spm %s --help lists them)", mode, a, mode);
}

int spm_exit_code(const gr_error *err) { return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED; }

static struct {
    const char *label;
    double t0;
} progress_state;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress(double done, void *user)
{
    (void)user;
    double wall = now() - progress_state.t0;
    int eta = done > 0.0 ? (int)(wall * (1.0 - done) / done + 0.5) : 0;
    fprintf(stderr, "\r%s %3.0f%%  ETA %d:%02d:%02d   ", progress_state.label, 100.0 * done, eta / 3600, eta / 60 % 60,
            eta % 60);
    fflush(stderr);
}

void spm_progress_on(spm_options *o, const char *label)
{
    if (!o->quiet && cli_interactive()) {
        progress_state.label = label;
        progress_state.t0 = now();
        o->s->progress = progress;
        o->s->user = NULL;
    }
}

void spm_progress_off(spm_options *o)
{
    if (o->s->progress) {
        fprintf(stderr, "\r%*s\r", 60, "");
        fflush(stderr);
        o->s->progress = NULL;
    }
}

void spm_print_constants(const gr_spm_constants *c, const char *how)
{
    printf("  constants (thesis convention): <v_x^2> = c (D l/M^2)^(2/3), c = %.4f +- %.4f; "
           "<T_fp> = c' (l^2 M^2/D)^(1/3), c' = %.4f +- %.4f (%s)\n",
           c->c, c->c_err, c->c_prime, c->c_prime_err, how);
}
