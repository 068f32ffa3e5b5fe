/* The run driver's last stage (src/app/run_internal.h): the results, the tables moved into place,
 * plots, the observables' outputs, summary.json, and the status gr_run returns. A write that
 * fails while a checkpoint is on disk stops the run resumably (docs/checkpoints.md, "A full
 * disk"). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/mean_field.h"
#include "app/noise_windows.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "app/run_picture.h"
#include "io/plot.h"
#include "app/run_internal.h"
#include "scene/scene_json.h"
#include "io/summary_read.h"

/* A radius distribution's sum over the grains of m_i (inverse = false: the total mass) or of 1 / m_i. */
static double distribution_mass_sum(const gr_scene *scene, bool inverse)
{
    double sum = 0.0;
    for (int i = 0; i < scene->N; i++) {
        const double r =
            gr_size_radius(scene->size_distribution, scene->radius_min, scene->radius_max,
                           scene->radius_median, scene->radius_sigma, scene->seed, i);
        const double m = gr_size_mass(scene->dim, scene->species_density.v[0], r);
        sum += inverse ? 1.0 / m : m;
    }
    return sum;
}

/* The mean energy the driving puts in per second (W). The random force: dim D / M per particle, eq.
 * 2.19 (times 1 - 1/N when symmetrised, the centre of mass takes none). The Langevin bath: its noise
 * adds M T_bath (1 - e^{-2 dt/tau}) / 2 per particle and step (step.c), N M T_bath / tau as dt -> 0;
 * the drag takes it out again in the steady state of an elastic gas (the event and hybrid
 * integrators apply it once per kick_interval, at each window's end: dt is that interval). None:
 * nothing. */
static double injection_rate_expected(const gr_scene *scene, double dt)
{
    const gr_driving_type *d = scene->driving ? scene->driving : gr_driving_default();
    if (d->update == GR_DRIVE_BATH) {
        dt = scene->integrator && scene->integrator->free_flight ? scene->kick_interval : dt;
        const gr_driving_params *p = &scene->driving_params;
        /* species: every grain at the first species' energy m_1 T_bath / dim per component; a
         * radius distribution: at the grains' mean mass's */
        const double m = scene->n_species >= 2      ? scene->species_masses[0]
                         : scene->size_distribution ? distribution_mass_sum(scene, false) / scene->N
                                                    : scene->mass;
        return scene->N * m * p->T_bath * -expm1(-2.0 * dt / p->tau) / (2.0 * dt);
    }
    if (d->update == GR_DRIVE_OFF) {
        return 0.0;
    }
    const double sym = scene->noise_mode == GR_NOISE_SYMMETRISED ? 1.0 - 1.0 / scene->N : 1.0;
    if (scene->n_species >= 2) { /* species: d D / m_i per grain (docs/mixtures.md) */
        double per_mass = 0.0;
        for (int a = 0; a < scene->n_species; a++) {
            per_mass += scene->species_count[a] / scene->species_masses[a];
        }
        return scene->dim * scene->D * per_mass * sym;
    }
    if (scene->size_distribution) { /* a radius distribution: sum over the grains of 1 / m_i */
        return scene->dim * scene->D * distribution_mass_sum(scene, true) * sym;
    }
    return scene->dim * scene->D / scene->mass * scene->N * sym;
}

/* summary.json's "walls": for each wall (x_0, x_L, y_0, y_L: the walls at 0 and L of an axis with
 * walls) the time-averaged normal force the grains exert on it, N (> 0: pushing it outwards), with
 * its standard error from block averaging of the per-sample means, and in 2D the pressure, force
 * per unit length of the wall (L), N/m. */
static void write_walls(cJSON *j, const gr_scene *scene, const gr_blocking *wb)
{
    if (!scene->boundary[0] && !scene->boundary[1] && !scene->boundary[2]) {
        return;
    }
    static const char *const names[6] = {"x_0", "x_L", "y_0", "y_L", "z_0", "z_L"};
    cJSON *wj = cJSON_AddObjectToObject(j, "walls");
    for (int w = 0; w < 6; w++) {
        if (!scene->boundary[w / 2] || wb[w].count[0] < 1) {
            continue;
        }
        int converged = 0;
        const double f = gr_blocking_mean(&wb[w]), e = gr_blocking_stderr(&wb[w], NULL, &converged);
        cJSON *o = cJSON_AddObjectToObject(wj, names[w]);
        cJSON_AddNumberToObject(o, "force", f);
        cJSON_AddNumberToObject(o, "force_stderr", isfinite(e) ? e : -1.0);
        cJSON_AddBoolToObject(o, "force_stderr_converged", converged);
        if (scene->dim >= 2) { /* force per unit length (2D) or area (3D) of the wall */
            const double len = scene->dim == 3 ? scene->L * scene->L : scene->L;
            cJSON_AddNumberToObject(o, "pressure", f / len);
            cJSON_AddNumberToObject(o, "pressure_stderr", isfinite(e) ? e / len : -1.0);
        }
    }
}

static int write_summary(const char *dir, const gr_scene *scene, gr_sim *sim,
                         const gr_run_result *r, const gr_blocking *blk,
                         const gr_blocking *wall_blk, const char *status, const char *diagnosis,
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
    if (scene->contact.rotation) {
        /* rotation: the rotational temperature I <w^2> / M at the end (the series is in temperature.csv) */
        cJSON_AddNumberToObject(j, "T_rot_final", gr_sim_rotational_temperature(sim));
    }
    cJSON_AddNumberToObject(j, "samples", (double)r->samples);
    cJSON_AddNumberToObject(j, "wall_seconds", r->wall_seconds);
    cJSON_AddNumberToObject(j, "particle_steps_per_second", r->particle_steps_per_second);
    cJSON_AddNumberToObject(j, "checkpoints_written",
                            (double)r->checkpoints); /* this session (docs/checkpoints.md) */
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
    if (scene->driving && scene->driving->drag) {
        cJSON_AddNumberToObject(led, "dissipated_drag", l->dissipated_drag);
    }
    if (scene->gravity[0] != 0.0 || scene->gravity[1] != 0.0 || scene->gravity[2] != 0.0) {
        cJSON_AddNumberToObject(led, "potential", l->potential); /* [gravity]: -M sum g . r */
    }
    if (scene->vibrate) {
        cJSON_AddNumberToObject(led, "wall_work", l->wall_work); /* the moving wall's work */
    }
    double res = gr_ledger_residual(l);
    double scale = fmax(l->injected + fabs(l->wall_work) + gr_ledger_dissipated(l), l->initial);
    cJSON_AddNumberToObject(led, "residual", res);
    cJSON_AddNumberToObject(led, "relative_residual", scale > 0.0 ? res / scale : 0.0);
    cJSON_AddStringToObject(j, "kernel", r->kernel);
    cJSON_AddNumberToObject(j, "threads", gr_sim_threads(sim)); /* results do not depend on it */
    const gr_integrator_type *it =
        gr_sim_integrator(sim); /* its own figures, e.g. "hybrid" (docs/hybrid.md) */
    gr_integrator_figure fig[16];
    const int n_fig = it->describe ? it->describe(sim, fig, 16) : 0;
    cJSON *fj = n_fig > 0 ? cJSON_AddObjectToObject(j, it->section ? it->section : it->name) : NULL;
    for (int f = 0; f < n_fig; f++) {
        cJSON_AddNumberToObject(fj, fig[f].name, fig[f].value);
    }
    cJSON_AddNumberToObject(j, "events_processed", (double)r->events);
    cJSON_AddNumberToObject(j, "events_per_second", r->events_per_second);
    const gr_contact_coeffs *c = gr_sim_coeffs(sim);
    cJSON *co = cJSON_AddObjectToObject(j, "contact");
    cJSON_AddNumberToObject(co, "dt", gr_sim_dt(sim));
    cJSON_AddNumberToObject(co, "t_c", isfinite(c->t_c) ? c->t_c : -1.0);
    cJSON_AddNumberToObject(co, "steps_per_contact",
                            isfinite(c->t_c) ? c->t_c / gr_sim_dt(sim) : -1.0);
    cJSON_AddNumberToObject(co, "gamma_n", c->gamma_n);
    cJSON_AddNumberToObject(co, "gamma_t", c->gamma_t);
    cJSON_AddNumberToObject(co, "zeta", c->zeta);
    cJSON_AddNumberToObject(co, "eps_n_exact", c->eps_n_exact);
    cJSON_AddNumberToObject(co, "max_overlap_now", gr_sim_max_overlap(sim));
    cJSON_AddNumberToObject(j, "energy_injection_rate_expected",
                            injection_rate_expected(scene, gr_sim_dt(sim)));
    write_walls(j, scene, wall_blk);
    cJSON *bl = cJSON_AddArrayToObject(j, "T_blocking_stderr");
    for (int k = 0; k < GR_BLOCKING_LEVELS && blk->count[k] >= 2; k++) {
        cJSON_AddItemToArray(bl, cJSON_CreateNumber(gr_blocking_stderr_at(blk, k)));
    }
    const gr_noise_windows w = gr_noise_windows_of(scene, sim, r);
    gr_noise_windows_json(&w, scene, j);
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

static int write_blocks(const char *dir, const gr_scene *s, uint64_t hash, const gr_blocking *b,
                        gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "blocks.csv", err);
    if (rc) {
        return rc;
    }
    gr_run_csv_header(
        &f, "block averaging of T (Flyvbjerg-Petersen); T in m^2/s^2, block length in s", s, hash);
    gr_file_header(&f, "level [1],block_seconds [s],blocks [1],T_mean [m2 s-2],T_stderr [m2 s-2]");
    for (int k = 0; k < GR_BLOCKING_LEVELS && b->count[k] >= 2; k++) {
        fprintf(f.f, "%d,%.9g,%lld,%.9g,%.9g\n", k, ldexp(s->sample_every, k),
                (long long)b->count[k], b->sum[k] / (double)b->count[k],
                gr_blocking_stderr_at(b, k));
    }
    return gr_file_commit(&f, err);
}

/* walls.csv (a scene with walls only): summary.json's "walls" as a table, one row per wall (x_0,
 * x_L, y_0, y_L of the axes with walls): the mean normal force on it over the sampling phase, its
 * standard error (block averaging; nan with fewer than 16 samples), and in 2D the pressure. */
static int write_walls_csv(const char *dir, const gr_scene *s, uint64_t hash, const gr_blocking *wb,
                           gr_error *err)
{
    if (!s->boundary[0] && !s->boundary[1] && !s->boundary[2]) {
        return GR_OK;
    }
    gr_file f;
    int rc = gr_file_open(&f, dir, "walls.csv", err);
    if (rc) {
        return rc;
    }
    const bool spheres = s->dim == 3;
    gr_run_csv_header(&f,
                      spheres ? "mean normal force of the grains on each wall over the sampling "
                                "phase, N (> 0: outwards), block-averaged per sample interval; "
                                "pressure = force / L^2 (3D), N/m^2"
                              : "mean normal force of the grains on each wall over the sampling "
                                "phase, N "
                                "(> 0: outwards), block-averaged per sample interval; pressure = "
                                "force / L (2D), N/m",
                      s, hash);
    gr_file_header(&f, spheres ? "wall [],force [N],force_stderr [N],pressure [N m-2],"
                                 "pressure_stderr [N m-2]"
                               : "wall [],force [N],force_stderr [N],pressure [N m-1],"
                                 "pressure_stderr [N m-1]");
    static const char *const names[6] = {"x_0", "x_L", "y_0", "y_L", "z_0", "z_L"};
    for (int w = 0; w < 6; w++) {
        if (!s->boundary[w / 2]) {
            continue;
        }
        const double m = gr_blocking_mean(&wb[w]), e = gr_blocking_stderr(&wb[w], NULL, NULL);
        /* 1D: the force is the pressure; 2D per unit length, 3D per unit area */
        const double len = s->dim == 3 ? s->L * s->L : s->dim == 2 ? s->L : 1.0;
        fprintf(f.f, "%s,%.9g,%.9g,%.9g,%.9g\n", names[w], m, e, m / len, e / len);
    }
    return gr_file_commit(&f, err);
}

/* What the final writes returned: the trajectory, temperature.csv, ledger.csv, blocks.csv, the
 * observables, scene.ini, summary.json. */
typedef struct finish_rcs {
    int j, t, l, b, o, i, s;
} finish_rcs;

static void results(gr_run_ctx *c)
{
    c->res->samples = c->blk.count[0];
    c->res->steps = gr_sim_steps(c->sim);
    c->res->collisions = gr_sim_collisions(c->sim);
    c->res->wall_seconds = gr_run_now() - c->start;
    c->res->particle_steps_per_second =
        c->stepping > 0.0
            ? (double)c->scene->N * (double)(c->res->steps - c->steps_at_start) / c->stepping
            : 0.0;
    c->res->event_driven = gr_sim_integrator(c->sim)->events != NULL;
    c->res->events = gr_sim_events_processed(c->sim); /* event-driven runs; 0 otherwise */
    c->res->events_per_second =
        c->res->wall_seconds > 0.0 ? (double)c->res->events / c->res->wall_seconds : 0.0;
    c->res->ledger = gr_sim_ledger(c->sim);
    c->res->T_mean = gr_blocking_mean(&c->blk);
    c->res->T_stderr = gr_blocking_stderr(&c->blk, NULL, &c->res->T_stderr_converged);
    const gr_noise_windows w = gr_noise_windows_of(c->scene, c->sim, c->res);
    gr_noise_windows_warn(&w, c->scene, c->res->notes, sizeof c->res->notes);
}

/* The tables, plots, the observables' outputs and scene.ini (unless the run stops for a write
 * failure: then the tables are kept as temporaries for the resume). *plots names the plots. */
static void write_outputs(gr_run_ctx *c, bool write_stop, finish_rcs *r, cJSON **analysis,
                          const char **plots, char *plot_note, size_t note_cap, gr_error *io_err)
{
    if (write_stop) {
        gr_file_keep(&c->ft);
        gr_file_keep(&c->fl);
        return;
    }
    /* io_err keeps the first failure (the message names that file), `later` the rest */
    gr_error later = {0};
    r->t = gr_file_commit(&c->ft, r->j ? &later : io_err);
    r->l = gr_file_commit(&c->fl, r->j || r->t ? &later : io_err);
    r->b = write_blocks(c->dir, c->scene, c->hash, &c->blk, r->t || r->l ? &later : io_err);
    if (!r->b) {
        r->b =
            write_walls_csv(c->dir, c->scene, c->hash, c->wall_blk, r->t || r->l ? &later : io_err);
    }
    if (c->scene->plots) {
        *plots = gr_plot_run(c->dir, c->scene->dim, plot_note, note_cap) == GR_OK
                     ? "temperature.png, ledger.png"
                     : plot_note;
    }
    if (gr_observer_count(c->obs) > 0) {
        *analysis = cJSON_CreateObject();
        gr_output out = {.dir = c->dir,
                         .source = c->scene->source,
                         .seed = c->scene->seed,
                         .scene_hash = c->hash,
                         .summary = *analysis,
                         .plots = c->scene->plots};
        r->o = gr_observer_finish(c->obs, &out, r->t || r->l || r->b ? &later : io_err);
    }
    r->i = gr_scene_save(c->scene, c->dir, r->t || r->l || r->b || r->o ? &later : io_err);
}

/* The snapshot picture coloured by speed (Figs. 2.6, 2.9), drawn with cairo: ", NAME.png" or why not. */
static void picture(const gr_run_ctx *c, char *note, size_t cap)
{
    gr_error perr = {0};
    char png[1300];
    if (gr_picture_run_ex(c->dir, NULL, png, sizeof png, &perr) == 0) {
        snprintf(note, cap, ", %.200s", strrchr(png, '/') ? strrchr(png, '/') + 1 : png);
    } else {
        snprintf(note, cap, "; snapshot picture failed: %.800s", perr.message);
    }
}

/* gr_run's return status and message, from the run's status and the final writes. */
static int exit_status(gr_run_ctx *c, bool write_stop, double t_stop, int io, const finish_rcs *r,
                       const gr_error *io_err)
{
    if (write_stop) {
        c->res->stopped = GR_RUN_STOPPED_WRITE;
        return GR_FAIL(
            c->err, GR_EIO,
            "%.600s; the run stopped at t = %.6g s and keeps its checkpoint: free space, then "
            "continue it with granule run --resume %s",
            c->diagnosis, t_stop, c->dir);
    }
    if (strcmp(c->status, "unstable") == 0) {
        *c->err = c->step_err;
        return GR_EUNSTABLE;
    }
    if (io) {
        return io;
    }
    if (strcmp(c->status, "interrupted") == 0) { /* stopped without a checkpoint */
        return GR_FAIL(c->err, GR_EIO,
                       "%.600s (outputs so far written; this run cannot be resumed)", c->diagnosis);
    }
    if (strcmp(c->status, "failed") == 0) {
        *c->err =
            c->step_err.code ? c->step_err : *io_err; /* an observer's sample, or a final write */
        return GR_EIO;
    }
    if (r->j || r->t || r->l || r->b || r->s || r->o || r->i) {
        *c->err = *io_err;
        return GR_EIO;
    }
    return GR_OK;
}

int gr_run_finish(gr_run_ctx *c)
{
    results(c);
    gr_error io_err = {0};
    int io =
        c->rc && !strcmp(c->status, "completed") ? c->rc : GR_OK; /* a snapshot write failure */
    if (io) {
        c->status = "failed"; /* GR_RUN_STATUS_WRITE_FAILED below when a checkpoint is kept */
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", c->err->message);
    }
    finish_rcs r = {0};
    /* the trajectory: flushed and closed first (its frames up to the checkpoint stay readable) */
    r.j = gr_traj_writer_close(&c->traj, &io_err);
    /* a write that fails (a full disk) while a checkpoint is on disk stops the run resumably: the
     * checkpoint and the streamed temporaries are kept, and a resume redoes the rest once there
     * is space (docs/checkpoints.md, "A full disk") */
    const bool resumable = gr_run_checkpoint_present(c->dir);
    c->ft.keep_on_error = c->fl.keep_on_error = resumable;
    bool write_stop = (io || r.j) && resumable;
    const char *plots = "not requested";
    char plot_note[300];
    cJSON *analysis = NULL;
    write_outputs(c, write_stop, &r, &analysis, &plots, plot_note, sizeof plot_note, &io_err);
    gr_observer_free(c->obs);
    if (!write_stop && resumable && strcmp(c->status, "completed") == 0 &&
        (r.j || r.t || r.l || r.b || r.o || r.i)) {
        write_stop = true;
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", io_err.message);
    }
    if (write_stop) {
        c->status = GR_RUN_STATUS_WRITE_FAILED;
    } else if (strcmp(c->status, "completed") == 0 && (r.j || r.t || r.l || r.b || r.o || r.i)) {
        /* no checkpoint to keep: the run failed (exit 1), and --force starts it again; never
         * "completed" with outputs missing */
        c->status = "failed";
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", io_err.message);
    }
    char picture_note[900] = "";
    if (c->scene->plots && c->snap_index > 0 && !write_stop) {
        picture(c, picture_note, sizeof picture_note);
    }
    char plots_text[1200];
    snprintf(plots_text, sizeof plots_text, "%s%s", plots, picture_note);
    plots = plots_text;
    cJSON *mean_field = c->scene->D > 0.0
                            ? gr_mean_field_steady(c->scene, c->res->T_mean)
                            : gr_mean_field_haff(c->scene, c->haff_t, c->haff_T, (int)c->haff_n);
    free(c->haff_t);
    free(c->haff_T);
    r.s =
        write_summary(c->dir, c->scene, c->sim, c->res, &c->blk, c->wall_blk, c->status,
                      c->diagnosis[0] ? c->diagnosis : NULL, plots, analysis, mean_field, &io_err);
    if (r.s == GR_OK && c->scene->plots) {
        gr_plot_summary_update(
            c->dir); /* "plots": every picture in the folder, as run/compare/sweep list them */
    }
    if (r.s && resumable && strcmp(c->status, "completed") == 0) {
        write_stop = true; /* no summary.json: the checkpoint is the run */
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", io_err.message);
    }
    if (r.s == GR_OK && strcmp(c->status, "completed") == 0) {
        /* finished: summary.json now refuses a resume; the checkpoint and any partial file of an
         * earlier, killed attempt are no longer needed */
        r.s = gr_run_clear_leftovers(c->dir, &io_err);
    }
    const double t_stop = gr_sim_time(c->sim);
    gr_sim_free(c->sim);
    return exit_status(c, write_stop, t_stop, io, &r, &io_err);
}
