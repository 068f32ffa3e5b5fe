/* The run driver behind `granule run`: set-up, warm-up, sampling uniformly in time, outputs.
 * gr_run calls the stages of src/app/run_internal.h in order; this file holds the set-up.
 *
 * Time series are streamed into temporary files and moved into place at the end (or when the run
 * stops unstable), so a reader never sees half a file and memory does not grow with run length.
 * The temperature average and its error bar come from streaming block averaging (2.20). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/sim_state.h"
#include "granule_config.h"
#include "io/dir_lock.h"
#include "app/run_internal.h"
#include "scene/scene_json.h"

#define RUN_LOCK ".run.lock" /* held by the run writing the folder */

/* Wall clock. GRANULE_TEST_CLOCK_TICK = S replaces it by a clock that advances S seconds per
 * reading, so the tests of --wall-limit stop at the same places on any machine. */
double gr_run_now(void)
{
    static double tick = -1.0, fake = 0.0;
    if (tick < 0.0) {
        const char *e = getenv("GRANULE_TEST_CLOCK_TICK");
        tick = e && atof(e) > 0.0 ? atof(e) : 0.0;
    }
    if (tick > 0.0) {
        return fake += tick;
    }
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* GRANULE_TEST_PAUSE_AT_STEP = K: once step K is passed, wait (up to 60 s) for a stop request
 * or a kill, so the tests of SIGTERM and kill -9 hit a running process on any machine. */
void gr_run_test_pause(const gr_sim *sim, const gr_run_options *opt)
{
    static int64_t at = -1;
    if (at < 0) {
        const char *e = getenv("GRANULE_TEST_PAUSE_AT_STEP");
        at = e && atoll(e) > 0 ? atoll(e) : 0;
    }
    if (at > 0 && gr_sim_steps(sim) >= at) {
        at = 0; /* once */
        const struct timespec slice = {0, 10000000};
        for (int i = 0; i < 6000 && !(opt && opt->stop && *opt->stop); i++) {
            nanosleep(&slice, NULL);
        }
    }
}

void gr_run_csv_header(gr_file *f, const char *what, const gr_scene *s, uint64_t hash)
{
    gr_file_note(f, "# granule %s (%s)\n# scene %s, hash %016llx, seed %llu\n", what, GR_VERSION,
                 s->source, (unsigned long long)hash, (unsigned long long)s->seed);
}

/* Close a streamed table without moving it into place (a resume continues it), dropping its notes. */
void gr_run_stream_leave(gr_file *f)
{
    if (f->f) {
        fclose(f->f);
        f->f = NULL;
    }
    free(f->notes);
    f->notes = NULL;
    cJSON_Delete(f->units);
    f->units = NULL;
    f->columns = 0;
}

/* A folder with a run still going (its RUN_LOCK held) is refused: a second run would delete the
 * first one's partial files, and a resume would continue a checkpoint the first one still moves. */
static int refuse_busy(const gr_run_ctx *c, const char *holder)
{
    return GR_FAIL(c->err, GR_EINVAL, "output folder %s is in use by a run still going (%s): %s",
                   c->scene->out_dir, holder[0] ? holder : "another process",
                   c->resume ? "it is not interrupted, so there is nothing to resume until it stops"
                             : "wait for it to finish, or choose another folder");
}

/* A note when the threads asked for (--threads, OMP_NUM_THREADS) exceed those the step uses. */
static void note_threads(const gr_sim *sim, char *notes, size_t len)
{
    const int asked = gr_get_threads(), used = gr_sim_threads(sim);
    const char *why = gr_sim_one_thread_reason(sim);
    const size_t at = strlen(notes);
    if (asked > used && why && at < len) {
        snprintf(notes + at, len - at,
                 "%d threads were asked for, but %s; the results are the same for every count\n",
                 asked, why);
    }
}

/* Set-up, part 1: the checkpoint of a resume, the simulation, the observables, the schedule and
 * (fresh runs) the output folder. Everything that can refuse the scene (dt, placement,
 * observables, schedule) is checked before the output folder is touched: a refused run leaves it
 * as it was. */
static int open_run(gr_run_ctx *c)
{
    const gr_scene *scene = c->scene;
    const gr_run_options *opt = c->opt;
    gr_error *err = c->err;
    char holder[400];
    if (gr_dir_lock_held(scene->out_dir, RUN_LOCK, holder,
                         sizeof holder)) { /* before any word about its files */
        return refuse_busy(c, holder);
    }
    /* resuming (docs/checkpoints.md): the scene must be the checkpoint's; its source is restored */
    if (c->resume) {
        c->resumed = *scene;
        int rc = gr_run_resume_open(scene->out_dir, &c->resumed, &c->ck_buf, &c->ck, err);
        if (rc) {
            return rc;
        }
        c->scene = scene = &c->resumed;
    }
    c->dir = scene->out_dir;
    int rc = gr_output_path_check(c->dir, err);
    rc = rc ? rc : gr_sim_create(scene, &c->sim, err);
    if (rc) {
        return rc;
    }
    snprintf(c->res->kernel, sizeof c->res->kernel, "%s", gr_sim_kernel(c->sim));
    /* an event-driven step can be long (dense or hot systems): it polls the stop flag itself and
     * returns early, with the step count unchanged, when a stop is requested */
    gr_sim_set_stop(c->sim, opt ? opt->stop : NULL);
    rc = gr_scene_observer(scene, &c->obs, err);
    if (!rc && gr_observer_needs_events(c->obs)) {
        rc = gr_sim_track_contacts(c->sim, err);
    }
    c->dt = gr_sim_dt(c->sim);
    rc =
        rc ? rc
           : gr_run_schedule_make(scene, c->dt, &c->plan, c->res->notes, sizeof c->res->notes, err);
    note_threads(c->sim, c->res->notes, sizeof c->res->notes);
    const bool resume = c->resume;
    rc = rc || resume ? rc : gr_run_checkpoint_guard(c->dir, opt && opt->force, err);
    rc = rc || resume ? rc : gr_output_dir_prepare(c->dir, GR_OUTPUT_RUN, opt && opt->force, err);
    if (!rc) {
        rc = gr_dir_lock(c->dir, RUN_LOCK, &c->lock_fd, holder, sizeof holder, err);
        if (rc == GR_LOCK_HELD) {
            return refuse_busy(c, holder); /* started since the check above */
        }
    }
    rc = rc || resume
             ? rc
             : gr_run_clear_leftovers(c->dir, err); /* an old checkpoint (--force), NAME.tmpPID */
    rc = rc || resume ? rc : gr_scene_save(scene, c->dir, err); /* a resume reads it back */
    c->hash = gr_scene_hash(scene);
    return rc;
}

/* Set-up, part 2 (fresh runs): temperature.csv and ledger.csv, streamed; a resume continues them. */
/* The columns of the streamed tables with their units (gr_file_header) */
static const char *temperature_columns(const gr_scene *s)
{
    return s->contact.rotation ? "t [s],T [m2 s-2],running_mean [m2 s-2],phase [],T_rot [m2 s-2]"
                               : "t [s],T [m2 s-2],running_mean [m2 s-2],phase []";
}

static const char *ledger_columns(const gr_scene *s)
{
#define GR_LEDGER_BASE                                                                             \
    "t [s],kinetic [J],elastic [J],injected [J],dissipated_normal [J],dissipated_tangential [J],"  \
    "dissipated_friction [J],removed_com [J],residual [J]"
    /* optional columns at the end, so the others keep their places: the spins' energy with
     * rotation, the bath's drag with a Langevin driving */
    static const char *const columns[2][2][2] = {
        {{GR_LEDGER_BASE, GR_LEDGER_BASE ",potential [J]"},
         {GR_LEDGER_BASE ",dissipated_drag [J]",
          GR_LEDGER_BASE ",dissipated_drag [J],potential [J]"}},
        {{GR_LEDGER_BASE ",rotational [J]", GR_LEDGER_BASE ",rotational [J],potential [J]"},
         {GR_LEDGER_BASE ",rotational [J],dissipated_drag [J]",
          GR_LEDGER_BASE ",rotational [J],dissipated_drag [J],potential [J]"}}};
#undef GR_LEDGER_BASE
    /* and gravity's potential energy last, with [gravity] (docs/systems-walls-gravity.md); after
     * it the moving walls' work, with [boundary] vibrate */
    const char *cols =
        columns[s->contact.rotation ? 1 : 0][s->driving && s->driving->drag ? 1 : 0]
               [s->gravity[0] != 0.0 || s->gravity[1] != 0.0 || s->gravity[2] != 0.0];
    if (!s->vibrate) {
        return cols;
    }
    static _Thread_local char with_walls[400];
    snprintf(with_walls, sizeof with_walls, "%s,wall_work [J]", cols);
    return with_walls;
}

static int open_tables(gr_run_ctx *c)
{
    if (c->resume) {
        return GR_OK;
    }
    int rc = gr_file_open(&c->ft, c->dir, "temperature.csv", c->err);
    if (!rc) {
        rc = gr_file_open(&c->fl, c->dir, "ledger.csv", c->err);
        if (rc) {
            gr_file_abandon(&c->ft);
        }
    }
    if (!rc) {
        /* rotation: T_rot = I <w^2> / M (gr_sim_rotational_temperature) as a last column of T(t),
         * and the rotational part of the kinetic energy (sum I w^2 / 2) as a last column of the ledger */
        gr_file_header(&c->ft, temperature_columns(c->scene));
        gr_file_header(&c->fl, ledger_columns(c->scene));
    }
    return rc;
}

/* Set-up, part 3: the accumulators, the driver state a checkpoint keeps (restored on a resume),
 * the tables' notes and the trajectory. */
static int start_outputs(gr_run_ctx *c)
{
    const gr_run_schedule *plan = &c->plan;
    gr_blocking_init(&c->blk);
    for (int w = 0; w < 6; w++) {
        gr_blocking_init(&c->wall_blk[w]);
    }
    gr_sim_wall_impulse(c->sim, c->wall_prev); /* a resume restores the checkpoint's */
    /* an undriven (cooling) run keeps its T(t) for the Haff's-law fit */
    c->haff_cap = c->scene->D > 0.0 ? 0 : plan->run_samples + 1;
    c->haff_t = c->haff_cap ? malloc(sizeof(double) * (size_t)c->haff_cap) : NULL;
    c->haff_T = c->haff_cap ? malloc(sizeof(double) * (size_t)c->haff_cap) : NULL;
    if (c->haff_cap && (!c->haff_t || !c->haff_T)) {
        c->haff_cap = 0;
    }
    c->last_report = gr_run_now();
    c->start = gr_run_now();
    /* checkpoints (docs/checkpoints.md): at sample boundaries every checkpoint_every (simulated)
     * or checkpoint_wall (wall clock); on a stop request (signal, wall budget) at the next step
     * boundary */
    c->ckst = (gr_run_ckpt){.k_next = 0,
                            .per_sample = plan->per_sample,
                            .warm_samples = plan->warm_samples,
                            .run_samples = plan->run_samples,
                            .blk = &c->blk,
                            .haff_n = &c->haff_n,
                            .haff_cap = c->haff_cap,
                            .haff_t = c->haff_t,
                            .haff_T = c->haff_T,
                            .next_snap = &c->next_snap,
                            .snap_index = &c->snap_index,
                            .ft = &c->ft,
                            .fl = &c->fl,
                            .traj = &c->traj,
                            .walls = c->scene->boundary[0] || c->scene->boundary[1] ||
                                             c->scene->boundary[2]
                                         ? (c->scene->dim == 3 ? 6 : 4)
                                         : 0,
                            .wall_blk = c->wall_blk,
                            .wall_prev = c->wall_prev};
    if (c->resume) {
        int rc = gr_run_resume_state(&c->ck, c->dir, c->sim, c->obs, &c->ckst, c->err);
        free(c->ck_buf);
        c->ck_buf = NULL;
        while (!rc && plan->snap_every > 0 && c->next_snap < gr_sim_steps(c->sim)) {
            c->next_snap +=
                plan->snap_every; /* a checkpoint of a version that snapshotted at samples */
        }
        if (rc) {
            return rc;
        }
    }
    /* the tables' notes (NAME.meta.json at commit) are kept in memory, so a resume writes them again */
    gr_run_csv_header(
        &c->ft,
        "granular temperature T(t) of eq. 2.19, m^2/s^2; running_mean over the sampling phase",
        c->scene, c->hash);
    gr_run_csv_header(&c->fl,
                      c->scene->vibrate ? "energy ledger, J (residual = kinetic + elastic + "
                                          "potential - initial - injected - wall_work + "
                                          "dissipated + removed_com)"
                                        : "energy ledger, J (residual = kinetic + elastic - "
                                          "initial - injected + dissipated + removed_com)",
                      c->scene, c->hash);
    if (c->resume) { /* the header is in the file already; the units go to the sidecar again */
        gr_file_units(&c->ft, temperature_columns(c->scene));
        gr_file_units(&c->fl, ledger_columns(c->scene));
    }
    /* the trajectory: a resume cuts the frames written after the checkpoint */
    const gr_scene *s = c->scene;
    const gr_particles parts = gr_sim_particles(c->sim); /* a mixture's species, radii, masses */
    const gr_traj_setup setup = {
        .format = s->trajectory,
        .frames = s->snapshot_every > 0.0,
        .particles = {.n = s->N,
                      .dim = s->dim,
                      .L = s->L,
                      .radius = parts.species ? parts.radius : s->radius, /* mixture: largest */
                      .mass = parts.species ? parts.mass : s->mass,       /* and the mean mass */
                      .angular_velocity = s->dim >= 2 && s->contact.rotation,
                      .deflate = 1,
                      .species = parts.species,
                      .radii = parts.radii,
                      .masses = parts.masses,
                      .n_species = parts.n_species}};
    int rc = gr_traj_writer_open(&c->traj, &setup, c->dir, c->resume ? c->snap_index : -1, c->err);
    if (rc) {
        gr_traj_writer_close(&c->traj, &(gr_error){0});
        gr_run_stream_leave(&c->ft);
        gr_run_stream_leave(&c->fl);
        return rc;
    }
    c->can_checkpoint = gr_sim_checkpointable(c->sim, &c->ck_err) == GR_OK;
    c->steps_at_start = gr_sim_steps(c->sim);
    c->last_ckpt = gr_run_now();
    c->ckpt_cost = 1e-2 + 8.0 * 14.0 * (double)c->scene->N / 2e8; /* until one is measured */
    c->chunk = plan->per_sample < 16 ? plan->per_sample : 16;
    /* GRANULE_CHUNK_STEPS caps the chunk (tests use it to stop between samples for certain) */
    const char *cap_env = getenv("GRANULE_CHUNK_STEPS");
    c->chunk_cap = cap_env && atoll(cap_env) > 0 ? atoll(cap_env) : plan->per_sample;
    c->chunk = c->chunk < c->chunk_cap ? c->chunk : c->chunk_cap;
    return GR_OK;
}

/* What a run that stops during set-up has taken. */
static void release(gr_run_ctx *c)
{
    free(c->haff_t);
    free(c->haff_T);
    gr_observer_free(c->obs);
    gr_sim_free(c->sim);
    free(c->ck_buf);
    gr_dir_unlock(c->dir, RUN_LOCK, &c->lock_fd);
}

int gr_run(const gr_scene *scene, const gr_run_options *opt, gr_run_result *res, gr_error *err)
{
    memset(res, 0, sizeof *res);
    gr_run_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    *c = (gr_run_ctx){.scene = scene,
                      .opt = opt,
                      .res = res,
                      .err = err,
                      .resume = opt && opt->resume,
                      .t_enter = gr_run_now(),
                      .status = "completed",
                      .lock_fd = -1};
    /* set-up */
    int rc = open_run(c);
    rc = rc ? rc : open_tables(c);
    rc = rc ? rc : start_outputs(c);
    if (rc) {
        release(c);
        free(c);
        return rc;
    }
    /* warm-up (samples 0..warm_samples), then sampling; a resume starts where it stopped */
    const int64_t k0 = c->ckst.k_next, warm = c->plan.warm_samples;
    if (gr_run_samples(c, k0, warm)) {
        gr_run_samples(c, k0 > warm + 1 ? k0 : warm + 1, warm + c->plan.run_samples);
    }
    /* a stop request ends in a checkpoint; otherwise the outputs are finished */
    rc = gr_run_stop(c) ? c->rc : gr_run_finish(c);
    gr_dir_unlock(c->dir, RUN_LOCK, &c->lock_fd);
    free(c);
    return rc;
}
