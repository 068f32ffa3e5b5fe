/* granule analyse DIR: feed a run's snapshots to the observables of the analysis layer (the same
 * code that samples during a run) and write the results into DIR/analysis (or --out). */
#include <cjson/cJSON.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/analysis.h"
#include "granule/compare.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "scene/scene_json.h"
#include "io/lammps_dump.h"
#include "io/snapshot.h"
#include "io/summary_read.h"
#include "io/trajectory.h"

typedef struct analyse_args {
    const char *out, *dump;
    cli_list sets;
    bool force, no_plots;
} analyse_args;

static const cli_opt analyse_opts[] = {
    CLI_OPT_SET(analyse_args, sets),
    CLI_OPT_OUT(analyse_args, out, "DIR/analysis"),
    CLI_OPT_FORCE(analyse_args, force),
    CLI_OPT_FORMAT,
    {"--no-plots", CLI_FLAG, NULL, offsetof(analyse_args, no_plots), 0, 0, 0, NULL,
     "draw no plots (same as --set output.plots=false)", NULL},
    {"--lammps-dump", CLI_STRING, "FILE", offsetof(analyse_args, dump), 0, 0, 0, NULL,
     "read the frames from a LAMMPS text dump instead of DIR's trajectory", NULL},
};

const cli_command cli_cmd_analyse = {
    .name = "analyse",
    .usage =
        "granule analyse DIR [--set analysis.observables=a,b ...] [--set section.key=value ...]\n"
        "                       [--out OUT] [--force] [--lammps-dump FILE]",
    .about =
        "Reads DIR/scene.ini and the trajectory of a finished run (DIR/trajectory.h5, "
        "DIR/snapshots/trajectory.xyz\n"
        "or DIR/snapshots/snap_*.xyz, as output.trajectory wrote it) and feeds\n"
        "every frame to the observables named in [analysis] observables (granule observables "
        "lists\n"
        "them; --set changes them or their parameters); frames of the warm-up (t <= run.warmup) "
        "are\n"
        "skipped, as in a run. Writes OUT (default DIR/analysis):\n"
        "summary.json and one CSV (and PNG) per observable, exactly as a run that sampled them.\n"
        "--lammps-dump FILE reads the frames from a LAMMPS text dump (dump custom with id x y vx "
        "vy,\n"
        "e.g. of a deck from `granule export lammps`) instead of the snapshots; DIR (default: the\n"
        "dump's folder) holds the scene.ini; frame times are timestep * integrator.dt "
        "(docs/lammps.md).\n",
    .pos_name = "run folder",
    .max_pos = 1,
    CLI_OPTS(analyse_opts),
};

/* Frames of a run folder's trajectory (any output.trajectory format) or of a LAMMPS dump, one at
 * a time. */
typedef struct frame_source {
    gr_traj_reader *traj;
    int64_t next, total;
    gr_lammps_dump *dump;
    double dt;
} frame_source;

static int source_open(frame_source *src, const char *dir, const char *dump, const gr_scene *scene,
                       gr_error *err)
{
    memset(src, 0, sizeof *src);
    src->dt = scene->dt;
    if (dump && !(scene->dt > 0.0)) { /* frame times are timestep * dt */
        return GR_FAIL(
            err, GR_EINVAL,
            "--lammps-dump %s: its frame times are timestep * integrator.dt, but %s leaves "
            "integrator.dt unset (it follows from steps_per_contact); analyse the folder `granule "
            "export lammps` "
            "wrote (its scene.ini holds the resolved dt) or give --set integrator.dt=DT",
            dump, scene->source);
    }
    if (dump) {
        return gr_lammps_dump_open(dump, scene->dim, &src->dump, err);
    }
    return gr_traj_reader_open(dir, (int)scene->trajectory, &src->traj, &src->total, err);
}

/* 1 with a frame in f, 0 after the last, an error code otherwise. */
static int source_next(frame_source *src, gr_frame *f, gr_error *err)
{
    if (src->dump) {
        return gr_lammps_dump_next(src->dump, src->dt, f, err);
    }
    if (src->next >= src->total) {
        return 0;
    }
    int rc = gr_traj_reader_frame(src->traj, src->next++, f, err);
    return rc ? rc : 1;
}

static void source_close(frame_source *src)
{
    if (src->dump) {
        gr_lammps_dump_close(src->dump);
    } else {
        gr_traj_reader_close(src->traj);
    }
}

/* A frame the observables may take: the scene's N, dim and box, a finite time after the previous
 * frame's. GR_EINVAL naming the source, the frame and the cause otherwise. */
static int frame_check(const gr_frame *fr, size_t k, double t_prev, const gr_scene *scene,
                       const char *source, const char *scene_path, gr_error *err)
{
    if (fr->n != scene->N || fr->dim != scene->dim) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s, frame %zu: %d particles in %dD, but the scene has N = %d in %dD",
                       source, k, fr->n, fr->dim, scene->N, scene->dim);
    }
    if (!isfinite(fr->t)) {
        return GR_FAIL(err, GR_EINVAL, "%s, frame %zu: time t = %g s is not a finite number",
                       source, k, fr->t);
    }
    if (!(fr->t > t_prev)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s, frame %zu: t = %.17g s is not after frame %zu's t = %.17g s: frames must be "
            "in increasing time order",
            source, k, fr->t, k - 1, t_prev);
    }
    if (!(fabs(fr->L - scene->L) <= 1e-9 * scene->L)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s, frame %zu: box length %.17g m disagrees with system.L = %.17g m of %s: the "
            "trajectory belongs to another scene",
            source, k, fr->L, scene->L, scene_path);
    }
    return GR_OK;
}

/* Exit status for an error while reading the input: bad input (2) unless memory ran out. */
static int input_exit(int rc) { return rc == GR_ENOMEM ? EXIT_FAILED : EXIT_REFUSED; }

/* T of eq. 2.19: (1/N) sum |v_i - <v>|^2 over all components, as gr_sim_temperature */
static double frame_temperature(const gr_particles *p)
{
    double mx = 0.0, my = 0.0, mz = 0.0, sum = 0.0;
    for (int i = 0; i < p->n; i++) {
        mx += p->vx[i];
        my += p->dim >= 2 ? p->vy[i] : 0.0;
        mz += p->dim == 3 ? p->vz[i] : 0.0;
    }
    mx /= p->n;
    my /= p->n;
    mz /= p->n;
    for (int i = 0; i < p->n; i++) {
        const double ux = p->vx[i] - mx, uy = p->dim >= 2 ? p->vy[i] - my : 0.0;
        if (p->dim == 3) {
            const double uz = p->vz[i] - mz;
            sum += ux * ux + uy * uy + uz * uz;
            continue;
        }
        sum += ux * ux + uy * uy;
    }
    return sum / p->n;
}

static void add_number(cJSON *o, const char *name, double v)
{
    if (v == v) {
        cJSON_AddNumberToObject(o, name, v);
    } else {
        cJSON_AddNullToObject(o, name);
    }
}

/* The fitted headline numbers of the observables that ran, as the compare table reads them:
 * "; alpha = 1.52 +- 0.10 (5.5); D_f = ...; n_N = ..." (empty when none ran). */
static void headline_fits(const cJSON *analysis, char *buf, size_t size)
{
    buf[0] = 0;
    static const struct {
        const char *label, *value, *error, *flag;
    } fits[] = {
        {"tail alpha (5.5)", "pv.tail.alpha", "pv.tail.alpha_halfwidth", "pv.tail.accepted"},
        {"tail alpha (5.5, free fit)", "pv.tail.free.alpha", "pv.tail.free.alpha_err",
         "pv.tail.free.converged"},
        {"D_f (4.4)", "sk.fit.D_f", "sk.fit.D_f_err", NULL},
        {"n_N (3.22)", "gaps.fit_3_22.n_N", "gaps.fit_3_22.n_N_stderr", NULL},
    };
    bool alpha = false;
    for (size_t k = 0; k < sizeof fits / sizeof fits[0]; k++) {
        const bool is_alpha = fits[k].value[0] == 'p';
        const double v = gr_summary_number(analysis, fits[k].value);
        if ((is_alpha && alpha) || !(v == v) ||
            (fits[k].flag && gr_summary_number(analysis, fits[k].flag) != 1.0)) {
            continue;
        }
        alpha |= is_alpha;
        char num[80];
        gr_compare_format(v, gr_summary_number(analysis, fits[k].error), num, sizeof num);
        size_t len = strlen(buf);
        snprintf(buf + len, size - len, "; %s = %s", fits[k].label, num);
    }
}

int cmd_analyse(int argc, char **argv)
{
    analyse_args args = {0};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_analyse, argc, argv, &args, &pos);
    if (parsed >= 0) {
        cli_list_free(&args.sets);
        return parsed;
    }
    const char *dir = pos.n ? pos.v[0] : NULL, *out_dir = args.out, *dump = args.dump;
    if (args.no_plots && !cli_list_add(&args.sets, "output.plots=false")) {
        cli_list_free(&args.sets);
        return EXIT_FAILED;
    }
    const char **sets = args.sets.items;
    const int n_sets = args.sets.n;
    const bool force = args.force;
    char path[1200], outbuf[1200], dumpdir[1200];
    if (!dir && dump) { /* the folder of the dump */
        snprintf(dumpdir, sizeof dumpdir, "%s", dump);
        char *slash = strrchr(dumpdir, '/');
        if (slash) {
            *slash = '\0';
        } else {
            snprintf(dumpdir, sizeof dumpdir, ".");
        }
        dir = dumpdir;
    }
    if (!dir) {
        cli_help(&cli_cmd_analyse, stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    snprintf(path, sizeof path, "%.1150s/scene.ini", dir);
    gr_scene scene;
    gr_error err = {0};
    int rc = gr_scene_load(&scene, path, sets, n_sets, &err);
    free(sets);
    if (rc) {
        app_error("analyse: %s", err.message);
        return EXIT_REFUSED;
    }
    if (!scene.observables[0]) {
        app_error("analyse: no observables chosen; add --set analysis.observables=NAME[,NAME] "
                  "(granule observables lists them)");
        return EXIT_REFUSED;
    }
    if (!out_dir) {
        snprintf(outbuf, sizeof outbuf, "%.1150s/analysis", dir);
        out_dir = outbuf;
    }
    rc = gr_output_dir_precheck(out_dir, &err);
    if (rc) {
        app_error("analyse: %s", err.message);
        return EXIT_REFUSED;
    }
    char real_in[PATH_MAX], real_out[PATH_MAX];
    const size_t n_out =
        realpath(dir, real_in) && realpath(out_dir, real_out) ? strlen(real_out) : 0;
    if (n_out && !strncmp(real_in, real_out, n_out) &&
        (real_in[n_out] == '/' || !real_in[n_out] || n_out == 1)) {
        app_error("analyse: --out %s is the folder analysed (%s) or holds it; its results would "
                  "replace their own input: "
                  "choose another folder (the default is %s/analysis)",
                  out_dir, dir, dir);
        return EXIT_REFUSED;
    }
    gr_observer *obs = NULL;
    rc = gr_scene_observer(&scene, &obs, &err);
    if (rc) {
        app_error("analyse: %s", err.message);
        return app_exit_code(rc);
    }
    frame_source src;
    rc = source_open(&src, dir, dump, &scene, &err);
    if (rc) {
        gr_observer_free(obs);
        app_error("analyse: %s", err.message);
        return input_exit(rc);
    }
    /* every frame is read and checked before the output folder is touched: a refused input
     * leaves it as it was (absent, or the earlier analysis) */
    char source[1200]; /* the reader's name outlives the reader for the messages below */
    snprintf(source, sizeof source, "%s", dump ? dump : gr_traj_reader_source(src.traj));
    size_t frames = 0, read = 0;
    double t_prev = -INFINITY, t_last = NAN;
    gr_blocking T_blk; /* T of eq. 2.19 per frame, block-averaged as a run's samples are */
    gr_blocking_init(&T_blk);
    gr_frame fr;
    while ((rc = source_next(&src, &fr, &err)) == 1) {
        read++;
        rc = frame_check(&fr, read, t_prev, &scene, source, path, &err);
        if (!rc) {
            t_prev = t_last = fr.t;
        }
        if (!rc &&
            fr.t > scene.warmup * (1.0 + 1e-12)) { /* the warm-up is not sampled, as in a run */
            gr_particles p = {.n = fr.n,
                              .dim = fr.dim,
                              .L = fr.L,
                              .radius = scene.radius,
                              .mass = scene.mass,
                              .x = fr.x,
                              .y = fr.y,
                              .vx = fr.vx,
                              .vy = fr.vy,
                              .z = fr.z,
                              .vz = fr.vz,
                              .species = fr.species, /* a mixture's frames (docs/mixtures.md) */
                              .radii = fr.radii,
                              .masses = fr.masses,
                              .n_species = fr.n_species};
            rc = gr_observer_sample(obs, &p, fr.t, &err);
            if (rc) {
                char why[sizeof err.message];
                snprintf(why, sizeof why, "%s", err.message);
                GR_FAIL(&err, rc, "%s, frame %zu: %s", source, read, why);
            }
            if (!rc) {
                gr_blocking_add(&T_blk, frame_temperature(&p));
            }
            frames++;
        }
        gr_frame_free(&fr);
        if (rc) {
            break;
        }
        if (app_interactive()) {
            fprintf(stderr, "\ranalyse: %zu frames", read);
        }
    }
    if (app_interactive()) {
        fputc('\n', stderr);
    }
    source_close(&src);
    if (!rc && read == 0) {
        rc = GR_FAIL(&err, GR_EINVAL, "%s holds no frames: nothing to analyse", source);
    } else if (!rc && frames == 0) {
        rc = GR_FAIL(&err, GR_EINVAL,
                     "%s: none of its %zu frames (the last at t = %.17g s) is after the warm-up "
                     "(run.warmup = %g s): nothing to analyse",
                     source, read, t_last, scene.warmup);
    }
    if (rc) {
        gr_observer_free(obs);
        app_error("analyse: %s", err.message);
        return input_exit(rc);
    }
    rc = gr_output_dir_prepare(out_dir, GR_OUTPUT_RESULT, force, &err);
    if (rc) {
        gr_observer_free(obs);
        app_error("analyse: %s", err.message);
        return rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
    }
    cJSON *sum = cJSON_CreateObject(), *analysis = cJSON_AddObjectToObject(sum, "analysis");
    gr_output out = {.dir = out_dir,
                     .source = scene.source,
                     .seed = scene.seed,
                     .scene_hash = gr_scene_hash(&scene),
                     .summary = analysis,
                     .plots = scene.plots};
    rc = gr_observer_finish(obs, &out, &err);
    gr_observer_free(obs);
    cJSON_AddStringToObject(sum, "source", dump ? dump : dir);
    cJSON_AddNumberToObject(sum, "frames", (double)frames);
    /* the run's headline: T over the frames after the warm-up (summary.json as a run writes it) */
    int T_converged = 0;
    const double T_mean = gr_blocking_mean(&T_blk),
                 T_stderr = gr_blocking_stderr(&T_blk, NULL, &T_converged);
    add_number(sum, "T_mean", T_mean);
    add_number(sum, "T_stderr", T_stderr);
    cJSON_AddBoolToObject(sum, "T_stderr_converged", T_converged);
    cJSON_AddNumberToObject(sum, "samples", (double)frames);
    char few[200] = "";
    if (frames < GR_MIN_FRAMES) {
        snprintf(few, sizeof few,
                 "only %zu frames after the warm-up, fewer than the %d that statistics with error "
                 "bars need",
                 frames, GR_MIN_FRAMES);
        cJSON_AddStringToObject(sum, "warnings", few);
    }
    cJSON_AddStringToObject(sum, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(sum, "commit", GR_COMMIT);
    cJSON_AddItemToObject(sum, "scene", gr_scene_to_json(&scene));
    char fits[400];
    headline_fits(analysis, fits, sizeof fits);
    char *text = cJSON_Print(sum);
    cJSON_Delete(sum);
    gr_file f;
    gr_error ferr = {0};
    int rc_s = gr_file_open(&f, out_dir, "summary.json", &ferr);
    if (!rc_s) {
        fputs(text, f.f);
        fputc('\n', f.f);
        rc_s = gr_file_commit(&f, &ferr);
    }
    cJSON_free(text);
    if (rc || rc_s) {
        app_error("analyse: %s", rc ? err.message : ferr.message);
        return EXIT_FAILED;
    }
    if (few[0]) {
        fprintf(stderr, "analyse: warning: %s\n", few);
    }
    char T_text[200];
    cli_T_text(T_text, sizeof T_text, T_mean, T_stderr, T_converged);
    printf("%s: %s over %zu frames%s\n", out_dir, T_text, frames, fits);
    return EXIT_OK;
}

int cmd_observables(int argc, char **argv)
{
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_observables, argc, argv, NULL, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    for (int i = 0; gr_observables[i]; i++) {
        const gr_observable_type *t = gr_observables[i];
        char dims[16] = ""; /* "1D, 2D, 3D": the bits of t->dims */
        for (int d = 1, len = 0; d <= 3; d++) {
            if (t->dims & (1u << (d - 1))) {
                len += snprintf(dims + len, sizeof dims - (size_t)len, "%s%dD", len ? ", " : "", d);
            }
        }
        printf("%s  [%s]\n  %s\n", t->name, dims, t->summary);
        if (t->events) {
            printf("  takes contact events: computed in a run only (granule analyse has none)\n");
        }
        for (int k = 0; k < t->n_params; k++) {
            printf("    %-14s default %-8g %s\n", t->params[k].name, t->params[k].def,
                   t->params[k].doc);
        }
    }
    return EXIT_OK;
}
