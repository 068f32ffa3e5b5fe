/* Options and the progress line shared by the granule spm modes; see spm_cli.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli/cli.h"
#include "cli/spm_cli.h"

int spm_parse(const cli_command *cmd, int argc, char **argv, void *args, spm_options *o,
              gr_spm_settings *s)
{
    cli_pos pos;
    const int parsed = cli_parse(cmd, argc, argv, args, &pos);
    if (parsed >= 0 || cli_theory_set_refused(cmd, &o->th)) {
        cli_list_free(&o->th.sets);
        return parsed >= 0 ? parsed : EXIT_REFUSED;
    }
    if (strlen(o->th.out) >= 1000) {
        app_error("%s: --out %s: path too long", cmd->name, o->th.out);
        return EXIT_REFUSED;
    }
    o->s = s;
    o->dim_set = o->dim != 0;
    o->mass_set = !isnan(o->mass);
    o->D_set = !isnan(o->D);
    s->dim = o->dim_set ? o->dim : s->dim;
    s->mass = o->mass_set ? o->mass : s->mass;
    s->D = o->D_set ? o->D : s->D;
    return -1;
}

int spm_exit_code(const gr_error *err)
{
    return err->code == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
}

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
    fprintf(stderr, "\r%s %3.0f%%  ETA %d:%02d:%02d   ", progress_state.label, 100.0 * done,
            eta / 3600, eta / 60 % 60, eta % 60);
    fflush(stderr);
}

void spm_progress_on(spm_options *o, const char *label)
{
    if (!o->th.quiet && app_interactive()) {
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
