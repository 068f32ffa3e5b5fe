/* The run driver behind `granule run`: warm-up, sampling uniformly in time, outputs.
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

#include "granule/analysis.h"
#include "granule/observe.h"
#include "granule/run.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "io/plot.h"
#include "io/picture.h"
#include "analysis/mean_field.h"
#include "io/scene_json.h"
#include "io/trajectory.h"
#include "io/run_checkpoint.h"
#include "io/run_schedule.h"
#include "core/sim_state.h"

/* Wall clock. GRANULE_TEST_CLOCK_TICK = S replaces it by a clock that advances S seconds per
 * reading, so the tests of --wall-limit stop at the same places on any machine. */
static double now(void)
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
static void test_pause(const gr_sim *sim, const gr_run_options *opt)
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

static void csv_header(gr_file *f, const char *what, const gr_scene *s, uint64_t hash)
{
    gr_file_note(f, "# granule %s (%s)\n# scene %s, hash %016llx, seed %llu\n", what, GR_VERSION,
            s->source, (unsigned long long)hash, (unsigned long long)s->seed);
}

/* Close a streamed table without moving it into place (a resume continues it), dropping its notes. */
static void stream_leave(gr_file *f)
{
    if (f->f) {
        fclose(f->f);
        f->f = NULL;
    }
    free(f->notes);
    f->notes = NULL;
}

static int write_summary(const char *dir, const gr_scene *scene, gr_sim *sim, const gr_run_result *r,
                         const gr_blocking *blk, const char *status, const char *diagnosis,
                         const char *plots, cJSON *analysis, cJSON *mean_field, gr_error *err)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", status);
    if (diagnosis) {
        cJSON_AddStringToObject(j, "diagnosis", diagnosis);
    }
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddNumberToObject(j, "T_mean", r->T_mean);
    cJSON_AddNumberToObject(j, "T_stderr", r->T_stderr);
    cJSON_AddBoolToObject(j, "T_stderr_converged", r->T_stderr_converged);
    cJSON_AddNumberToObject(j, "samples", (double)r->samples);
    cJSON_AddNumberToObject(j, "wall_seconds", r->wall_seconds);
    cJSON_AddNumberToObject(j, "particle_steps_per_second", r->particle_steps_per_second);
    cJSON_AddNumberToObject(j, "checkpoints_written", (double)r->checkpoints); /* this session (docs/checkpoints.md) */
    cJSON_AddNumberToObject(j, "checkpoint_seconds", r->checkpoint_seconds);
    if (r->checkpoint_error[0]) {
        cJSON_AddStringToObject(j, "checkpoint_error", r->checkpoint_error);
    }
    cJSON_AddNumberToObject(j, "steps", (double)r->steps);
    cJSON_AddNumberToObject(j, "simulated_seconds", gr_sim_time(sim));
    cJSON_AddNumberToObject(j, "collisions", (double)r->collisions);
    cJSON_AddNumberToObject(j, "neighbour_rebuilds", (double)gr_sim_rebuilds(sim));
    const gr_ledger *l = &r->ledger;
    cJSON_AddNumberToObject(j, "energy_injected", l->injected);
    cJSON_AddNumberToObject(j, "energy_dissipated", gr_ledger_dissipated(l));
    cJSON *led = cJSON_AddObjectToObject(j, "ledger");
    cJSON_AddNumberToObject(led, "kinetic", l->kinetic);
    cJSON_AddNumberToObject(led, "elastic", l->elastic);
    cJSON_AddNumberToObject(led, "initial", l->initial);
    cJSON_AddNumberToObject(led, "injected", l->injected);
    cJSON_AddNumberToObject(led, "dissipated_normal", l->dissipated_normal);
    cJSON_AddNumberToObject(led, "dissipated_tangential", l->dissipated_tangential);
    cJSON_AddNumberToObject(led, "dissipated_friction", l->dissipated_friction);
    cJSON_AddNumberToObject(led, "removed_com", l->removed_com);
    double res = gr_ledger_residual(l);
    double scale = fmax(l->injected + gr_ledger_dissipated(l), l->initial);
    cJSON_AddNumberToObject(led, "residual", res);
    cJSON_AddNumberToObject(led, "relative_residual", scale > 0.0 ? res / scale : 0.0);
    cJSON_AddStringToObject(j, "kernel", r->kernel);
    cJSON_AddNumberToObject(j, "threads", gr_sim_threads(sim)); /* results do not depend on it */
    const gr_integrator_type *it = gr_sim_integrator(sim); /* its own figures, e.g. "hybrid" (docs/hybrid.md) */
    gr_integrator_figure fig[16];
    const int n_fig = it->describe ? it->describe(sim, fig, 16) : 0;
    cJSON *fj = n_fig > 0 ? cJSON_AddObjectToObject(j, it->section ? it->section : it->name) : NULL;
    for (int f = 0; f < n_fig; f++) {
        cJSON_AddNumberToObject(fj, fig[f].name, fig[f].value);
    }
    const double events = (double)gr_sim_events_processed(sim); /* event-driven runs; 0 otherwise */
    cJSON_AddNumberToObject(j, "events_processed", events);
    cJSON_AddNumberToObject(j, "events_per_second", r->wall_seconds > 0.0 ? events / r->wall_seconds : 0.0);
    const gr_contact_coeffs *c = gr_sim_coeffs(sim);
    cJSON *co = cJSON_AddObjectToObject(j, "contact");
    cJSON_AddNumberToObject(co, "dt", gr_sim_dt(sim));
    cJSON_AddNumberToObject(co, "t_c", isfinite(c->t_c) ? c->t_c : -1.0);
    cJSON_AddNumberToObject(co, "steps_per_contact", isfinite(c->t_c) ? c->t_c / gr_sim_dt(sim) : -1.0);
    cJSON_AddNumberToObject(co, "gamma_n", c->gamma_n);
    cJSON_AddNumberToObject(co, "gamma_t", c->gamma_t);
    cJSON_AddNumberToObject(co, "zeta", c->zeta);
    cJSON_AddNumberToObject(co, "eps_n_exact", c->eps_n_exact);
    cJSON_AddNumberToObject(co, "max_overlap_now", gr_sim_max_overlap(sim));
    cJSON_AddNumberToObject(j, "energy_injection_rate_expected", scene->dim * scene->D / scene->mass * scene->N *
                                                                   (scene->noise_mode == GR_NOISE_SYMMETRISED ? 1.0 - 1.0 / scene->N : 1.0));
    cJSON *bl = cJSON_AddArrayToObject(j, "T_blocking_stderr");
    for (int k = 0; k < GR_BLOCKING_LEVELS && blk->count[k] >= 2; k++) {
        cJSON_AddItemToArray(bl, cJSON_CreateNumber(gr_blocking_stderr_at(blk, k)));
    }
    cJSON_AddStringToObject(j, "plots", plots);
    if (scene->warnings[0] || r->notes[0]) {
        char all[sizeof scene->warnings + sizeof r->notes];
        snprintf(all, sizeof all, "%s%s", scene->warnings, r->notes);
        cJSON_AddStringToObject(j, "warnings", all);
    }
    if (analysis) {
        cJSON_AddItemToObject(j, "analysis", analysis);
    }
    if (mean_field) {
        cJSON_AddItemToObject(j, "mean_field", mean_field);
    }
    cJSON_AddItemToObject(j, "scene", gr_scene_to_json(scene));
    int rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}

static int write_blocks(const char *dir, const gr_scene *s, uint64_t hash, const gr_blocking *b, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "blocks.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, "block averaging of T (Flyvbjerg-Petersen); T in m^2/s^2, block length in s", s, hash);
    fprintf(f.f, "level,block_seconds,blocks,T_mean,T_stderr\n");
    for (int k = 0; k < GR_BLOCKING_LEVELS && b->count[k] >= 2; k++) {
        fprintf(f.f, "%d,%.9g,%lld,%.9g,%.9g\n", k, ldexp(s->sample_every, k), (long long)b->count[k],
                b->sum[k] / (double)b->count[k], gr_blocking_stderr_at(b, k));
    }
    return gr_file_commit(&f, err);
}

/* the trajectory frame due at this step (output.trajectory); the next one snap_every steps later */
static int write_frame(gr_sim *sim, gr_traj_writer *traj, int *index, int64_t *next, int64_t snap_every, gr_error *err)
{
    gr_particles p = gr_sim_particles(sim);
    int rc = gr_traj_writer_frame(traj, &p, gr_sim_time(sim), gr_sim_steps(sim), err);
    *index = (int)traj->frames;
    *next += snap_every;
    return rc;
}

int gr_run(const gr_scene *scene, const gr_run_options *opt, gr_run_result *res, gr_error *err)
{
    memset(res, 0, sizeof *res);
    const double t_enter = now();
    /* resuming (docs/checkpoints.md): the scene must be the checkpoint's; its source is restored */
    const bool resume = opt && opt->resume;
    gr_scene resumed;
    gr_checkpoint ck;
    void *ck_buf = NULL;
    if (resume) {
        resumed = *scene;
        int rc = gr_run_resume_open(scene->out_dir, &resumed, &ck_buf, &ck, err);
        if (rc) {
            return rc;
        }
        scene = &resumed;
    }
    const char *dir = scene->out_dir;
    /* everything that can refuse the scene (dt, placement, observables, schedule) is checked
     * before the output folder is touched: a refused run leaves it as it was */
    int rc = gr_output_path_check(dir, err);
    gr_sim *sim = NULL;
    rc = rc ? rc : gr_sim_create(scene, &sim, err);
    if (rc) {
        free(ck_buf);
        return rc;
    }
    snprintf(res->kernel, sizeof res->kernel, "%s", gr_sim_kernel(sim));
    /* an event-driven step can be long (dense or hot systems): it polls the stop flag itself and
     * returns early, with the step count unchanged, when a stop is requested */
    gr_sim_set_stop(sim, opt ? opt->stop : NULL);
    gr_observer *obs = NULL;
    rc = gr_observer_create(scene, &obs, err);
    if (!rc && gr_observer_needs_events(obs)) {
        rc = gr_sim_track_contacts(sim, err);
    }
    const double dt = gr_sim_dt(sim);
    gr_run_schedule plan;
    rc = rc ? rc : gr_run_schedule_make(scene, dt, &plan, res->notes, sizeof res->notes, err);
    rc = rc || resume ? rc : gr_run_checkpoint_guard(dir, opt && opt->force, err);
    rc = rc || resume ? rc : gr_output_dir_prepare(dir, opt && opt->force, err);
    rc = rc || resume ? rc : gr_run_clear_leftovers(dir, err); /* an old checkpoint (--force), NAME.tmpPID */
    rc = rc || resume ? rc : gr_scene_save(scene, dir, err); /* a resume reads it back */
    if (rc) {
        gr_observer_free(obs);
        gr_sim_free(sim);
        free(ck_buf);
        return rc;
    }
    const uint64_t hash = gr_scene_hash(scene);
    const int64_t per_sample = plan.per_sample, warm_samples = plan.warm_samples, run_samples = plan.run_samples;
    const int64_t snap_every = plan.snap_every;

    gr_file ft = {0}, fl = {0};
    rc = resume ? GR_OK : gr_file_open(&ft, dir, "temperature.csv", err); /* a resume continues them */
    if (!rc && !resume) {
        rc = gr_file_open(&fl, dir, "ledger.csv", err);
        if (rc) {
            gr_file_abandon(&ft);
        }
    }
    if (rc) {
        gr_sim_free(sim);
        free(ck_buf);
        return rc;
    }
    if (!resume) {
    fprintf(ft.f, "t,T,running_mean,phase\n");
    fprintf(fl.f, "t,kinetic,elastic,injected,dissipated_normal,dissipated_tangential,dissipated_friction,removed_com,residual\n");
    }

    gr_blocking blk;
    gr_blocking_init(&blk);
    /* an undriven (cooling) run keeps its T(t) for the Haff's-law fit */
    int64_t haff_n = 0, haff_cap = scene->D > 0.0 ? 0 : run_samples + 1;
    double *haff_t = haff_cap ? malloc(sizeof(double) * (size_t)haff_cap) : NULL;
    double *haff_T = haff_cap ? malloc(sizeof(double) * (size_t)haff_cap) : NULL;
    if (haff_cap && (!haff_t || !haff_T)) {
        haff_cap = 0;
    }
    double stepping = 0.0, last_report = now(), start = now();
    int64_t next_snap = 0;
    int snap_index = 0;
    gr_traj_writer traj = {0};
    /* checkpoints (docs/checkpoints.md): at sample boundaries every checkpoint_every (simulated)
     * or checkpoint_wall (wall clock); on a stop request (signal, wall budget) at the next step
     * boundary. Steps run in chunks of about 0.1 s so a request is seen quickly; splitting
     * gr_sim_step calls does not change a bit of the result. */
    gr_run_ckpt ckst = {.k_next = 0, .per_sample = per_sample, .warm_samples = warm_samples, .run_samples = run_samples,
                        .blk = &blk, .haff_n = &haff_n, .haff_cap = haff_cap, .haff_t = haff_t, .haff_T = haff_T,
                        .next_snap = &next_snap, .snap_index = &snap_index, .ft = &ft, .fl = &fl,
                        .traj = &traj};
    if (resume) {
        rc = gr_run_resume_state(&ck, dir, sim, obs, &ckst, err);
        free(ck_buf);
        while (!rc && snap_every > 0 && next_snap < gr_sim_steps(sim)) {
            next_snap += snap_every; /* a checkpoint of a version that snapshotted at samples */
        }
        if (rc) {
            free(haff_t);
            free(haff_T);
            gr_observer_free(obs);
            gr_sim_free(sim);
            return rc;
        }
    }
    /* the tables' notes (NAME.meta.json at commit) are kept in memory, so a resume writes them again */
    csv_header(&ft, "granular temperature T(t) of eq. 2.19, m^2/s^2; running_mean over the sampling phase", scene, hash);
    csv_header(&fl, "energy ledger, J (residual = kinetic + elastic - initial - injected + dissipated + removed_com)", scene, hash);
    /* the trajectory: a resume cuts the frames written after the checkpoint */
    rc = gr_traj_writer_open(&traj, scene, dir, resume ? snap_index : -1, err);
    if (rc) {
        gr_traj_writer_close(&traj, &(gr_error){0});
        stream_leave(&ft);
        stream_leave(&fl);
        free(haff_t);
        free(haff_T);
        gr_observer_free(obs);
        gr_sim_free(sim);
        return rc;
    }
    gr_error ck_err = {0};
    const bool can_checkpoint = gr_sim_checkpointable(sim, &ck_err) == GR_OK;
    const int64_t ckpt_samples = plan.ckpt_samples;
    const int64_t steps_at_start = gr_sim_steps(sim);
    double last_ckpt = now(), chunk_wall = 0.0;
    double ckpt_cost = 1e-2 + 8.0 * 14.0 * (double)scene->N / 2e8; /* until one is measured */
    int64_t chunk = per_sample < 16 ? per_sample : 16;
    /* GRANULE_CHUNK_STEPS caps the chunk (tests use it to stop between samples for certain) */
    const char *cap_env = getenv("GRANULE_CHUNK_STEPS");
    const int64_t chunk_cap = cap_env && atoll(cap_env) > 0 ? atoll(cap_env) : per_sample;
    chunk = chunk < chunk_cap ? chunk : chunk_cap;
    int stop = 0; /* 1: signal, 2: wall-clock budget */
    bool stopped_early = false;
    const char *status = "completed";
    char diagnosis[800] = "";
    gr_error step_err = {0};
    for (int64_t k = ckst.k_next; k <= warm_samples + run_samples; k++) {
        if (k > 0) {
            while (rc == GR_OK && gr_sim_steps(sim) < k * per_sample) {
                const int64_t until = snap_every > 0 && next_snap < k * per_sample ? next_snap : k * per_sample;
                const int64_t todo = until - gr_sim_steps(sim);
                double t0 = now();
                rc = gr_sim_step(sim, gr_sim_call_steps(sim, chunk, todo), &step_err);
                chunk_wall = now() - t0;
                stepping += chunk_wall;
                chunk = chunk_wall < 0.05 && chunk < chunk_cap ? (2 * chunk < chunk_cap ? 2 * chunk : chunk_cap)
                        : chunk_wall > 0.2 && chunk > 1 ? chunk / 2
                                                        : chunk;
                if (rc == GR_OK && snap_every > 0 && gr_sim_steps(sim) == next_snap && next_snap < k * per_sample) {
                    rc = write_frame(sim, &traj, &snap_index, &next_snap, snap_every, err);
                    if (rc) {
                        break;
                    }
                }
                test_pause(sim, opt);
                stop = opt && opt->stop && *opt->stop ? 1
                       : scene->wall_limit > 0.0 && now() - t_enter + 2.0 * chunk_wall + 2.0 * ckpt_cost + 1.0 >= scene->wall_limit ? 2
                                                                                                                            : 0;
                if (stop) {
                    break;
                }
            }
            if (rc && err->code && !step_err.code) {
                break; /* a snapshot could not be written */
            }
            if (rc) {
                status = "unstable";
                snprintf(diagnosis, sizeof diagnosis, "%s", step_err.message);
                break;
            }
            if (stop && gr_sim_steps(sim) < k * per_sample) { /* stop between two samples */
                ckst.k_next = k;
                stopped_early = true;
                break;
            }
        }
        double t = gr_sim_time(sim), T = gr_sim_temperature(sim);
        bool sampling = k > warm_samples;
        if (!sampling) {
            gr_sim_clear_events(sim); /* events of the warm-up are not statistics */
        }
        if (sampling) {
            gr_blocking_add(&blk, T);
            if (haff_n < haff_cap) {
                haff_t[haff_n] = t;
                haff_T[haff_n++] = T;
            }
            if (gr_observer_count(obs) > 0) {
                gr_particles p = gr_sim_particles(sim);
                int64_t n_ev = 0;
                const gr_contact_event *ev = gr_sim_events(sim, &n_ev);
                rc = gr_observer_sample(obs, &p, t, &step_err);
                rc = rc ? rc : n_ev ? gr_observer_events(obs, ev, n_ev, &step_err) : GR_OK;
                gr_sim_clear_events(sim);
                if (rc) {
                    status = "failed";
                    snprintf(diagnosis, sizeof diagnosis, "%s", step_err.message);
                    break;
                }
            }
        }
        fprintf(ft.f, "%.9g,%.9g,%.9g,%s\n", t, T, sampling ? gr_blocking_mean(&blk) : (double)NAN, sampling ? "sample" : "warmup");
        gr_ledger l = gr_sim_ledger(sim);
        double moved = l.injected + gr_ledger_dissipated(&l) + l.removed_com;
        double residual = gr_ledger_residual(&l);
        bool ledger_broken = scene->ledger_tolerance > 0.0 && moved > 0.0 &&
                             fabs(residual) > scene->ledger_tolerance * fmax(moved, l.initial);
        fprintf(fl.f, "%.9g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.6g\n", t, l.kinetic, l.elastic,
                l.injected, l.dissipated_normal, l.dissipated_tangential, l.dissipated_friction,
                l.removed_com, gr_ledger_residual(&l));
        /* a full disk stops the run now, not at the end (the message names the file) */
        rc = gr_file_check(&ft, err);
        rc = rc ? rc : gr_file_check(&fl, err);
        if (rc) {
            break;
        }
        if (ledger_broken) {
            status = "unstable";
            snprintf(step_err.message, sizeof step_err.message,
                     "energy ledger does not balance at t = %.6g s (step %lld): residual %.3g J is %.3g of the energy moved "
                     "(tolerance %.3g, run.ledger_tolerance); dt = %g s is too coarse for these contacts (%.1f steps per contact)",
                     t, (long long)gr_sim_steps(sim), residual, fabs(residual) / fmax(moved, l.initial),
                     scene->ledger_tolerance, dt, gr_sim_coeffs(sim)->t_c / dt);
            step_err.code = GR_EUNSTABLE;
            snprintf(diagnosis, sizeof diagnosis, "%s", step_err.message);
            break;
        }
        if (snap_every > 0 && gr_sim_steps(sim) == next_snap) {
            rc = write_frame(sim, &traj, &snap_index, &next_snap, snap_every, err);
            if (rc) {
                break;
            }
        }
        if (k < warm_samples + run_samples) {
            stop = stop ? stop
                   : opt && opt->stop && *opt->stop ? 1
                   : scene->wall_limit > 0.0 && now() - t_enter + 2.0 * chunk_wall + 2.0 * ckpt_cost + 1.0 >= scene->wall_limit ? 2
                                                                                                                        : 0;
            bool due = (ckpt_samples > 0 && (k + 1) % ckpt_samples == 0) ||
                       (scene->checkpoint_wall > 0.0 && now() - last_ckpt >= scene->checkpoint_wall);
            if (can_checkpoint && due && !stop) {
                ckst.k_next = k + 1;
                double used = 0.0;
                size_t bytes = 0;
                gr_error werr = {0};
                if (gr_run_checkpoint_write(dir, scene, sim, obs, &ckst, &used, &bytes, &werr) == GR_OK) {
                    res->checkpoints++;
                    res->checkpoint_seconds += used;
                    ckpt_cost = used;
                } else {
                    if (!res->checkpoint_error[0]) { /* reported in summary.json; the previous checkpoint is kept */
                        snprintf(res->checkpoint_error, sizeof res->checkpoint_error, "%.255s", werr.message);
                    }
                    if (opt && opt->notice) {
                        char text[400];
                        snprintf(text, sizeof text, "checkpoint not written at t = %.6g s (the previous one is kept): %.300s",
                                 gr_sim_time(sim), werr.message);
                        opt->notice(text, opt->user);
                    }
                }
                last_ckpt = now();
            }
            if (stop) {
                ckst.k_next = k + 1;
                stopped_early = true;
                break;
            }
        }
        if (opt && opt->progress && (now() - last_report > 0.5 || k == warm_samples + run_samples)) {
            last_report = now();
            double t_end = (double)(warm_samples + run_samples) * (double)per_sample * dt;
            double rate = stepping > 0.0 ? (double)scene->N * (double)gr_sim_steps(sim) / stepping : 0.0;
            gr_progress p = {.t = t, .t_end = t_end, .wall = now() - start,
                             .eta = t > 0.0 ? (now() - start) * (t_end - t) / t : 0.0,
                             .particle_steps_per_second = rate, .warmup = !sampling};
            opt->progress(&p, opt->user);
        }
    }
    stop = stopped_early ? stop : 0; /* a request after the last sample changes nothing */
    if (stop && can_checkpoint && strcmp(status, "completed") == 0 && rc == GR_OK) {
        double used = 0.0;
        size_t bytes = 0;
        rc = gr_run_checkpoint_write(dir, scene, sim, obs, &ckst, &used, &bytes, err);
        if (rc == GR_OK) {
            /* the streamed CSVs and the trajectory stay as they are for the resume to continue */
            gr_traj_writer_close(&traj, &(gr_error){0});
            stream_leave(&ft);
            stream_leave(&fl);
            free(haff_t);
            free(haff_T);
            gr_observer_free(obs);
            res->steps = gr_sim_steps(sim);
            res->collisions = gr_sim_collisions(sim);
            res->samples = blk.count[0];
            res->wall_seconds = now() - start;
            res->checkpoints++;
            res->checkpoint_seconds += used;
            res->stopped = stop;
            gr_sim_free(sim);
            return GR_OK;
        }
        status = "interrupted"; /* no checkpoint: finish the outputs instead */
        snprintf(diagnosis, sizeof diagnosis, "stopped (%s) but the checkpoint could not be written: %.700s",
                 stop == 1 ? "signal" : "wall-clock budget", err->message);
        rc = GR_OK;
    } else if (stop && strcmp(status, "completed") == 0) {
        status = "interrupted";
        snprintf(diagnosis, sizeof diagnosis, "stopped (%s) at t = %.6g s; %.700s", stop == 1 ? "signal" : "wall-clock budget",
                 gr_sim_time(sim), ck_err.message);
    }
    res->samples = blk.count[0];
    res->steps = gr_sim_steps(sim);
    res->collisions = gr_sim_collisions(sim);
    res->wall_seconds = now() - start;
    res->particle_steps_per_second = stepping > 0.0 ? (double)scene->N * (double)(res->steps - steps_at_start) / stepping : 0.0;
    res->ledger = gr_sim_ledger(sim);
    res->T_mean = gr_blocking_mean(&blk);
    res->T_stderr = gr_blocking_stderr(&blk, NULL, &res->T_stderr_converged);
    gr_error io_err = {0};
    int io = rc && !strcmp(status, "completed") ? rc : GR_OK; /* a snapshot write failure */
    if (io) {
        status = "failed"; /* GR_RUN_STATUS_WRITE_FAILED below when a checkpoint is kept */
        snprintf(diagnosis, sizeof diagnosis, "%s", err->message);
    }
    /* the trajectory: flushed and closed first (its frames up to the checkpoint stay readable) */
    int rc_j = gr_traj_writer_close(&traj, &io_err);
    /* a write that fails (a full disk) while a checkpoint is on disk stops the run resumably: the
     * checkpoint and the streamed temporaries are kept, and a resume redoes the rest once there
     * is space (docs/checkpoints.md, "A full disk") */
    const bool resumable = gr_run_checkpoint_present(dir);
    ft.keep_on_error = fl.keep_on_error = resumable;
    bool write_stop = (io || rc_j) && resumable;
    int rc_t = GR_OK, rc_l = GR_OK, rc_b = GR_OK, rc_o = GR_OK, rc_i = GR_OK;
    const char *plots = "not requested";
    char plot_note[300];
    cJSON *analysis = NULL;
    if (write_stop) {
        gr_file_keep(&ft);
        gr_file_keep(&fl);
    } else {
        /* io_err keeps the first failure (the message names that file), `later` the rest */
        gr_error later = {0};
        rc_t = gr_file_commit(&ft, rc_j ? &later : &io_err);
        rc_l = gr_file_commit(&fl, rc_j || rc_t ? &later : &io_err);
        rc_b = write_blocks(dir, scene, hash, &blk, rc_t || rc_l ? &later : &io_err);
        if (scene->plots) {
            plots = gr_plot_run(dir, scene->dim, plot_note, sizeof plot_note) == GR_OK ? "temperature.png, ledger.png" : plot_note;
        }
        if (gr_observer_count(obs) > 0) {
            analysis = cJSON_CreateObject();
            gr_output out = {.dir = dir, .scene = scene, .scene_hash = hash, .summary = analysis, .plots = scene->plots};
            rc_o = gr_observer_finish(obs, &out, rc_t || rc_l || rc_b ? &later : &io_err);
        }
        rc_i = gr_scene_save(scene, dir, rc_t || rc_l || rc_b || rc_o ? &later : &io_err);
    }
    gr_observer_free(obs);
    if (!write_stop && resumable && strcmp(status, "completed") == 0 && (rc_j || rc_t || rc_l || rc_b || rc_o || rc_i)) {
        write_stop = true;
        snprintf(diagnosis, sizeof diagnosis, "%s", io_err.message);
    }
    if (write_stop) {
        status = GR_RUN_STATUS_WRITE_FAILED;
    }
    char picture_note[900] = "";
    if (scene->plots && snap_index > 0 && !write_stop) {
        /* the snapshot picture coloured by speed (Figs. 2.6, 2.9), drawn with cairo */
        gr_error perr = {0};
        char png[1300];
        if (gr_picture_run_ex(dir, NULL, png, sizeof png, &perr) == 0) {
            snprintf(picture_note, sizeof picture_note, ", %.200s", strrchr(png, '/') ? strrchr(png, '/') + 1 : png);
        } else {
            snprintf(picture_note, sizeof picture_note, "; snapshot picture failed: %.800s", perr.message);
        }
    }
    char plots_text[1200];
    snprintf(plots_text, sizeof plots_text, "%s%s", plots, picture_note);
    plots = plots_text;
    cJSON *mean_field = scene->D > 0.0 ? gr_mean_field_steady(scene, res->T_mean)
                                       : gr_mean_field_haff(scene, haff_t, haff_T, (int)haff_n);
    free(haff_t);
    free(haff_T);
    int rc_s = write_summary(dir, scene, sim, res, &blk, status, diagnosis[0] ? diagnosis : NULL, plots, analysis,
                             mean_field, &io_err);
    if (rc_s && resumable && strcmp(status, "completed") == 0) {
        write_stop = true; /* no summary.json: the checkpoint is the run */
        snprintf(diagnosis, sizeof diagnosis, "%s", io_err.message);
    }
    if (rc_s == GR_OK && strcmp(status, "completed") == 0) {
        /* finished: summary.json now refuses a resume; the checkpoint and any partial file of an
         * earlier, killed attempt are no longer needed */
        rc_s = gr_run_clear_leftovers(dir, &io_err);
    }
    const double t_stop = gr_sim_time(sim);
    gr_sim_free(sim);
    if (write_stop) {
        res->stopped = GR_RUN_STOPPED_WRITE;
        return GR_FAIL(err, GR_EIO, "%.600s; the run stopped at t = %.6g s and keeps its checkpoint: free space, then "
                       "continue it with granule run --resume %s", diagnosis, t_stop, dir);
    }
    if (strcmp(status, "unstable") == 0) {
        *err = step_err;
        return GR_EUNSTABLE;
    }
    if (io) {
        return io;
    }
    if (strcmp(status, "interrupted") == 0) { /* stopped without a checkpoint */
        return GR_FAIL(err, GR_EIO, "%.600s (outputs so far written; this run cannot be resumed)", diagnosis);
    }
    if (strcmp(status, "failed") == 0 && !io) {
        *err = step_err;
        return GR_EIO;
    }
    if (rc_j || rc_t || rc_l || rc_b || rc_s || rc_o || rc_i) {
        *err = io_err;
        return GR_EIO;
    }
    return GR_OK;
}
