/* granule cost SCENE --observable T|loss --tolerance 1%: the largest time step that keeps the
 * observable within the tolerance and the wall time of the scene's run with it on this machine
 * (include/granule/cost.h, docs/performance.md "What accuracy costs"). */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/cost.h"
#include "io/files.h"

typedef struct cost_args {
    const char *observable, *tolerance, *out;
    double calibrate;
    int phases;
    cli_list sets;
    bool force;
} cost_args;

static const cli_opt cost_opts[] = {
    {"--observable", CLI_CHOICE, "T|loss", offsetof(cost_args, observable), 0, 0, 0, "T",
     "T: the steady temperature (2.19); loss: the energy lost in one collision, worst contact "
     "phase",
     NULL},
    {"--tolerance", CLI_STRING, "TOL[%]", offsetof(cost_args, tolerance), 0, 0, 0, "1%",
     "relative tolerance in (0, 1), or a percentage", NULL},
    {"--calibrate", CLI_DOUBLE, "SECONDS", offsetof(cost_args, calibrate), 0, 86400, 0, "10",
     "wall seconds of the calibration run (0: no calibration)", NULL},
    {"--phases", CLI_INT, "K", offsetof(cost_args, phases), 1, 1000, 0, "16",
     "contact phases per collision", NULL},
    CLI_OPT_THREADS,
    CLI_OPT_SET(cost_args, sets),
    CLI_OPT_OUT(cost_args, out, "out/cost"),
    {"--force", CLI_FLAG, NULL, offsetof(cost_args, force), 0, 0, 0, NULL,
     "replace a result already in DIR (refused before anything is computed otherwise)", NULL},
};

const cli_command cli_cmd_cost = {
    .name = "cost",
    .usage = "granule cost SCENE [--observable T|loss] [--tolerance TOL[%]] [--calibrate SECONDS]\n"
             "                   [--phases K] [--threads N] [--set section.key=value ...] [--out "
             "DIR] [--force]",
    .about =
        "Which time step keeps the observable within TOL (relative; '1%' or 0.01; default 1%), and "
        "how long\n"
        "the scene's run (warm-up + duration) takes with it on this machine:\n"
        "  T     the steady temperature (2.19): the contact's energy-loss error at each dt, "
        "computed against\n"
        "        the CVODE reference, through the energy balance of the driven gas (T ~ "
        "(1-eps^2)^(-2/3))\n"
        "  loss  the energy lost in one collision, worst contact phase (head-on and, in 2D, "
        "oblique)\n"
        "Candidate time steps run from 64 down to 2.5 steps per contact, plus the scene's own dt; "
        "the\n"
        "recommendation is the largest dt whose error, and that of every smaller dt, is within "
        "TOL. Its\n"
        "wall time is measured by a calibration run of SECONDS (default 10) of the scene at that "
        "dt,\n"
        "in blocks, shared between Verlet and the hybrid integrator at windows of 10, 30 and 100 "
        "dt (same\n"
        "contact steps, free flights exact: the same error); the cheapest is recommended, and the\n"
        "prediction's +- is the spread of its blocks.\n",
    .epilog = "Writes DIR/cost.json (default out/cost); a DIR holding a result (an earlier "
              "cost.json, a run, ...)\n"
              "is refused before anything is computed unless --force, which replaces its contents "
              "as a whole.\n"
              "Ctrl-C stops it at once (exit 5) with nothing written.\n",
    .pos_name = "scene",
    .max_pos = 1,
    CLI_OPTS(cost_opts),
};

static bool parse_tolerance(const char *text, double *tol)
{
    char *end;
    double v = strtod(text, &end);
    if (end != text && *end == '%' && end[1] == '\0') {
        v /= 100.0;
    } else if (end == text || *end != '\0') {
        return false;
    }
    *tol = v;
    return v > 0.0 && v < 1.0;
}

/* The hybrid window as the scene check wants it: a whole number of the dt as printed (%.4g) */
static double hybrid_window(double dt, double window)
{
    char text[32];
    snprintf(text, sizeof text, "%.4g", dt);
    const double dt_printed = strtod(text, NULL);
    return round(window / dt) * dt_printed;
}

/* The recommendation as the --set arguments one pastes after granule run SCENE (force_dt only
 * when dt is above t_c/10, where the scene check needs it). */
static void print_set_form(const char *integrator, double dt, double window,
                           double steps_per_contact)
{
    printf("  as --set: ");
    if (integrator) {
        printf("--set integrator.kind=%s ", integrator);
    }
    printf("--set integrator.dt=%.4g", dt);
    if (window > 0.0) {
        printf(" --set integrator.kick_interval=%.10g", hybrid_window(dt, window));
    }
    printf("%s\n", steps_per_contact < 10.0 ? " --set integrator.force_dt=true" : "");
}

static void print_answer(const gr_cost_answer *a, const gr_cost_request *rq)
{
    printf("contact duration t_c = %.4g s; observable %s, tolerance %.3g%%\n\n", a->t_c,
           rq->observable == GR_COST_T ? "T (steady temperature)"
                                       : "loss (energy lost per collision)",
           100.0 * rq->tolerance);
    printf("  %-11s %9s %14s %14s %12s  %s\n", "dt (s)", "t_c/dt", "loss err mean",
           "loss err worst", rq->observable == GR_COST_T ? "T error" : "error", "");
    for (int i = 0; i < a->n; i++) {
        const gr_cost_candidate *c = &a->c[i];
        char mark[64] = "";
        snprintf(mark, sizeof mark, "%s%s%s",
                 c->meets    ? "ok"
                 : c->finite ? ""
                             : "unstable (clusters)",
                 c->scene_dt ? (c->meets || !c->finite ? ", the scene's dt" : "the scene's dt")
                             : "",
                 i == a->best ? "  <- recommended" : "");
        if (c->finite) {
            printf("  %-11.4g %9.3g %+14.2e %+14.2e %+12.2e  %s\n", c->dt, c->steps_per_contact,
                   c->loss_error_mean, c->loss_error_worst, c->error, mark);
        } else {
            printf("  %-11.4g %9.3g %14s %14s %12s  %s\n", c->dt, c->steps_per_contact, "-", "-",
                   "-", mark);
        }
    }
    printf("\n");
    if (a->best < 0) {
        printf("no candidate time step keeps the error within %.3g%%: the finest (t_c/dt = %.3g) "
               "has %+.2e\n",
               100.0 * rq->tolerance, a->n ? a->c[0].steps_per_contact : 0.0,
               a->n ? a->c[0].error : (double)NAN);
        return;
    }
    const gr_cost_candidate *b = &a->c[a->best];
    if (a->best_option >= 0) {
        printf("integrators timed at that dt:\n");
        for (int k = 0; k < a->n_options; k++) {
            const gr_cost_option *o = &a->option[k];
            char name[48];
            snprintf(name, sizeof name, o->window > 0.0 ? "%s, window %.3g s" : "%s", o->integrator,
                     o->window);
            if (o->ok) {
                printf("  %-26s %10.4g +- %-8.2g wall s per simulated s%s\n", name,
                       o->wall_per_simulated, o->wall_per_simulated_err,
                       k == a->best_option ? "  <- recommended" : "");
            } else {
                printf("  %-26s not timed: %s\n", name, o->note);
            }
        }
        const gr_cost_option *o = &a->option[a->best_option];
        if (o->window > 0.0) {
            printf("use the hybrid integrator, dt = %.4g s (%.3g steps per contact), window %.4g s "
                   "([integrator] kind = "
                   "hybrid, dt = %.4g, kick_interval = %.10g, force_dt = true if above t_c/10)\n",
                   b->dt, b->steps_per_contact, o->window, b->dt, hybrid_window(b->dt, o->window));
        } else {
            printf("use verlet, dt = %.4g s (%.3g steps per contact; [integrator] kind = verlet, "
                   "dt = %.4g, force_dt = "
                   "true if above t_c/10)\n",
                   b->dt, b->steps_per_contact, b->dt);
        }
        print_set_form(o->window > 0.0 ? "hybrid" : "verlet", b->dt, o->window,
                       b->steps_per_contact);
    } else {
        printf("use dt = %.4g s (%.3g steps per contact; [integrator] dt = %.4g, force_dt = true "
               "if above t_c/10)\n",
               b->dt, b->steps_per_contact, b->dt);
        print_set_form(NULL, b->dt, 0.0, b->steps_per_contact);
    }
    if (isfinite(a->predicted_wall)) {
        printf("predicted wall time for %.4g simulated s: %.4g +- %.2g s (%.4g +- %.2g wall s per "
               "simulated s, %d "
               "calibration blocks, %.3g particle-steps/s)\n",
               a->simulated_seconds, a->predicted_wall, a->predicted_wall_err,
               a->wall_per_simulated, a->wall_per_simulated_err, a->blocks,
               a->particle_steps_per_second);
        if (a->scene >= 0 && a->scene != a->best) {
            printf("the scene's own dt = %.4g s would take about %.3gx as long\n",
                   a->c[a->scene].dt, b->dt / a->c[a->scene].dt);
        }
    }
}

static void on_cost_stop(int sig)
{
    (void)sig;
    static const char msg[] =
        "\ncost: stopped by a signal before anything was written; it has no checkpoint to continue "
        "(a shorter --calibrate SECONDS makes it quicker): run it again\n";
    ssize_t unused =
        write(STDERR_FILENO, msg, sizeof msg - 1); /* async-signal-safe, unlike stdio */
    (void)unused;
    _exit(EXIT_STOPPED);
}

int cmd_cost(int argc, char **argv)
{
    gr_cost_request rq;
    gr_cost_request_default(&rq);
    cost_args args = {.out = "out/cost", .calibrate = rq.calibrate_seconds, .phases = rq.phases};
    cli_pos pos;
    int rc = cli_parse(&cli_cmd_cost, argc, argv, &args, &pos);
    if (rc >= 0) {
        cli_list_free(&args.sets);
        return rc;
    }
    rc = EXIT_OK;
    const char *scene_path = pos.n ? pos.v[0] : NULL, *out = args.out;
    const char **sets = args.sets.items;
    const int n_sets = args.sets.n;
    const bool force = args.force;
    rq.calibrate_seconds = args.calibrate;
    rq.phases = args.phases;
    if (args.observable) {
        rq.observable = (gr_cost_observable)gr_cost_observable_parse(args.observable);
    }
    if (args.tolerance && !parse_tolerance(args.tolerance, &rq.tolerance)) {
        app_error("cost: --tolerance %s: expected a relative tolerance in (0, 1) or a percentage, "
                  "e.g. 0.01 or 1%%",
                  args.tolerance);
        rc = EXIT_REFUSED;
    }
    if (rc == EXIT_OK && !scene_path) {
        cli_help(&cli_cmd_cost, stderr);
        rc = EXIT_REFUSED;
    }
    gr_scene sc;
    gr_error err = {0};
    if (rc == EXIT_OK && gr_output_dir_precheck(out, &err)) { /* before the calibration runs */
        app_error("cost: %s", err.message);
        rc = EXIT_REFUSED;
    }
    if (rc == EXIT_OK && gr_scene_load_whole(&sc, scene_path, sets, n_sets, &err)) {
        app_error("cost: %s", err.message);
        rc = EXIT_REFUSED;
    }
    free(sets);
    if (rc != EXIT_OK) {
        return rc;
    }
    /* Ctrl-C or SIGTERM while it computes: nothing is half written (the files are written last,
     * with the signals held off), so stop at once and say so */
    struct sigaction sa = {.sa_handler = on_cost_stop, .sa_flags = SA_RESETHAND};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    gr_cost_answer ans;
    if (gr_cost_errors(&sc, &rq, &ans, &err)) {
        app_error("cost: %s: %s", scene_path, err.message);
        return err.code == GR_EINVAL ? EXIT_REFUSED : app_exit_code(err.code);
    }
    if (gr_output_dir_prepare(out, GR_OUTPUT_RESULT, force,
                              &err)) { /* before the calibration run */
        app_error("cost: %s", err.message);
        return app_exit_code(err.code);
    }
    if (ans.best >= 0 && rq.calibrate_seconds > 0.0) {
        fprintf(stderr, "cost: calibrating dt = %.4g s for %g s of wall time\n", ans.c[ans.best].dt,
                rq.calibrate_seconds);
        if (gr_cost_calibrate(&sc, ans.c[ans.best].dt, rq.calibrate_seconds, &ans, &err)) {
            app_error("cost: calibration run: %s", err.message);
            return app_exit_code(err.code);
        }
    }
    sigset_t hold, before;
    sigemptyset(&hold);
    sigaddset(&hold, SIGINT);
    sigaddset(&hold, SIGTERM);
    sigprocmask(SIG_BLOCK, &hold, &before); /* a signal now waits until the files are complete */
    print_answer(&ans, &rq);
    const int wrc = gr_cost_write(&ans, &rq, scene_path, out, &err);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    sigprocmask(SIG_SETMASK, &before, NULL);
    if (wrc) {
        app_error("cost: %s", err.message);
        return app_exit_code(err.code);
    }
    printf("wrote %s/cost.json\n", out);
    return ans.best >= 0 ? EXIT_OK : EXIT_FAILED;
}
