/* The run driver's warm-up and sampling stages (src/app/run_internal.h): step to each sample
 * time, record T(t) and the ledger, feed the observables (sampling only), write trajectory
 * frames, checkpoints and progress; and the stop stage, where a stop request ends in a
 * checkpoint.
 *
 * Steps run in chunks of about 0.1 s so a stop request is seen quickly; how gr_sim_step calls are
 * split does not change a bit of the result (gr_sim_call_steps). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_state.h"
#include "app/run_internal.h"

/* the trajectory frame due at this step (output.trajectory); the next one snap_every steps later */
static int write_frame(gr_run_ctx *c)
{
    gr_particles p = gr_sim_particles(c->sim);
    int rc = gr_traj_writer_frame(&c->traj, &p, gr_sim_time(c->sim), gr_sim_steps(c->sim), c->err);
    c->snap_index = (int)c->traj.frames;
    c->next_snap += c->plan.snap_every;
    return rc;
}

/* 1: a signal asked to stop, 2: the wall-clock budget is about to run out, 0: go on. */
static int stop_requested(const gr_run_ctx *c)
{
    return c->opt && c->opt->stop && *c->opt->stop ? 1
           : c->scene->wall_limit > 0.0 &&
                   gr_run_now() - c->t_enter + 2.0 * c->chunk_wall + 2.0 * c->ckpt_cost + 1.0 >=
                       c->scene->wall_limit
               ? 2
               : 0;
}

/* Step to sample k (writing the trajectory frames due on the way); false when the run must not
 * go on: a failed frame, an unstable run, or a stop request before the sample. */
static bool advance(gr_run_ctx *c, int64_t k)
{
    const int64_t per_sample = c->plan.per_sample, snap_every = c->plan.snap_every;
    while (c->rc == GR_OK && gr_sim_steps(c->sim) < k * per_sample) {
        const int64_t until =
            snap_every > 0 && c->next_snap < k * per_sample ? c->next_snap : k * per_sample;
        const int64_t todo = until - gr_sim_steps(c->sim);
        double t0 = gr_run_now();
        c->rc = gr_sim_step(c->sim, gr_sim_call_steps(c->sim, c->chunk, todo), &c->step_err);
        c->chunk_wall = gr_run_now() - t0;
        c->stepping += c->chunk_wall;
        c->chunk = c->chunk_wall < 0.05 && c->chunk < c->chunk_cap
                       ? (2 * c->chunk < c->chunk_cap ? 2 * c->chunk : c->chunk_cap)
                   : c->chunk_wall > 0.2 && c->chunk > 1 ? c->chunk / 2
                                                         : c->chunk;
        if (c->rc == GR_OK && snap_every > 0 && gr_sim_steps(c->sim) == c->next_snap &&
            c->next_snap < k * per_sample) {
            c->rc = write_frame(c);
            if (c->rc) {
                break;
            }
        }
        gr_run_test_pause(c->sim, c->opt);
        c->stop = stop_requested(c);
        if (c->stop) {
            break;
        }
    }
    if (c->rc && c->err->code && !c->step_err.code) {
        return false; /* a snapshot could not be written */
    }
    if (c->rc) {
        c->status = "unstable";
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", c->step_err.message);
        return false;
    }
    if (c->stop && gr_sim_steps(c->sim) < k * per_sample) { /* stop between two samples */
        c->ckst.k_next = k;
        c->stopped_early = true;
        return false;
    }
    return true;
}

/* Sample k: T, the observables (sampling phase), one row of each table, the ledger check, the
 * frame due now; false when the run must not go on. */
static bool record(gr_run_ctx *c, int64_t k)
{
    gr_sim *sim = c->sim;
    double t = gr_sim_time(sim), T = gr_sim_temperature(sim);
    bool sampling = k > c->plan.warm_samples;
    if (!sampling) {
        gr_sim_clear_events(sim); /* events of the warm-up are not statistics */
    }
    if (c->scene->boundary[0] || c->scene->boundary[1] || c->scene->boundary[2]) {
        /* each wall's mean normal force over the sample interval, from the impulse it took */
        double J[6];
        gr_sim_wall_impulse(sim, J);
        for (int w = 0; w < (c->scene->dim == 3 ? 6 : 4); w++) {
            if (sampling) {
                gr_blocking_add(&c->wall_blk[w],
                                (J[w] - c->wall_prev[w]) / ((double)c->plan.per_sample * c->dt));
            }
            c->wall_prev[w] = J[w];
        }
    }
    if (sampling) {
        gr_blocking_add(&c->blk, T);
        if (c->haff_n < c->haff_cap) {
            c->haff_t[c->haff_n] = t;
            c->haff_T[c->haff_n++] = T;
        }
        if (gr_observer_count(c->obs) > 0) {
            gr_particles p = gr_sim_particles(sim);
            int64_t n_ev = 0;
            const gr_contact_event *ev = gr_sim_events(sim, &n_ev);
            c->rc = gr_observer_sample(c->obs, &p, t, &c->step_err);
            c->rc = c->rc  ? c->rc
                    : n_ev ? gr_observer_events(c->obs, ev, n_ev, &c->step_err)
                           : GR_OK;
            gr_sim_clear_events(sim);
            if (c->rc) {
                c->status = "failed";
                snprintf(c->diagnosis, sizeof c->diagnosis, "%s", c->step_err.message);
                return false;
            }
        }
    }
    fprintf(c->ft.f, "%.9g,%.9g,%.9g,%s", t, T, sampling ? gr_blocking_mean(&c->blk) : (double)NAN,
            sampling ? "sampling" : "warmup");
    if (c->scene->contact.rotation) {
        fprintf(c->ft.f, ",%.9g", gr_sim_rotational_temperature(sim));
    }
    fputc('\n', c->ft.f);
    gr_ledger l = gr_sim_ledger(sim);
    double moved = l.injected + fabs(l.wall_work) + gr_ledger_dissipated(&l) + l.removed_com;
    double residual = gr_ledger_residual(&l);
    bool ledger_broken = c->scene->ledger_tolerance > 0.0 && moved > 0.0 &&
                         fabs(residual) > c->scene->ledger_tolerance * fmax(moved, l.initial);
    fprintf(c->fl.f, "%.9g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.6g", t, l.kinetic, l.elastic,
            l.injected, l.dissipated_normal, l.dissipated_tangential, l.dissipated_friction,
            l.removed_com, gr_ledger_residual(&l));
    if (c->scene->contact.rotation) {
        fprintf(c->fl.f, ",%.12g", l.rotational);
    }
    if (c->scene->driving && c->scene->driving->drag) {
        fprintf(c->fl.f, ",%.12g", l.dissipated_drag);
    }
    if (c->scene->gravity[0] != 0.0 || c->scene->gravity[1] != 0.0 || c->scene->gravity[2] != 0.0) {
        fprintf(c->fl.f, ",%.12g", l.potential); /* [gravity]: -M sum g . r */
    }
    if (c->scene->vibrate) {
        fprintf(c->fl.f, ",%.12g", l.wall_work); /* the moving wall's work on the grains */
    }
    fputc('\n', c->fl.f);
    /* a full disk stops the run now, not at the end (the message names the file) */
    c->rc = gr_file_check(&c->ft, c->err);
    c->rc = c->rc ? c->rc : gr_file_check(&c->fl, c->err);
    if (c->rc) {
        return false;
    }
    if (ledger_broken) {
        c->status = "unstable";
        snprintf(c->step_err.message, sizeof c->step_err.message,
                 "energy ledger does not balance at t = %.6g s (step %lld): residual %.3g J is "
                 "%.3g of the energy moved "
                 "(tolerance %.3g, run.ledger_tolerance); dt = %g s is too coarse for these "
                 "contacts (%.1f steps per contact)",
                 t, (long long)gr_sim_steps(sim), residual, fabs(residual) / fmax(moved, l.initial),
                 c->scene->ledger_tolerance, c->dt, gr_sim_coeffs(sim)->t_c / c->dt);
        c->step_err.code = GR_EUNSTABLE;
        snprintf(c->diagnosis, sizeof c->diagnosis, "%s", c->step_err.message);
        return false;
    }
    if (c->plan.snap_every > 0 && gr_sim_steps(sim) == c->next_snap) {
        c->rc = write_frame(c);
        if (c->rc) {
            return false;
        }
    }
    return true;
}

/* After sample k (not the last): a checkpoint when one is due (every checkpoint_every of
 * simulated time or checkpoint_wall of wall clock); false on a stop request. */
static bool checkpoint_or_stop(gr_run_ctx *c, int64_t k)
{
    c->stop = c->stop ? c->stop : stop_requested(c);
    bool due = (c->plan.ckpt_samples > 0 && (k + 1) % c->plan.ckpt_samples == 0) ||
               (c->scene->checkpoint_wall > 0.0 &&
                gr_run_now() - c->last_ckpt >= c->scene->checkpoint_wall);
    if (c->can_checkpoint && due && !c->stop) {
        c->ckst.k_next = k + 1;
        double used = 0.0;
        size_t bytes = 0;
        gr_error werr = {0};
        if (gr_run_checkpoint_write(c->dir, c->scene, c->sim, c->obs, &c->ckst, &used, &bytes,
                                    &werr) == GR_OK) {
            c->res->checkpoints++;
            c->res->checkpoint_seconds += used;
            c->ckpt_cost = used;
        } else {
            if (!c->res->checkpoint_error
                     [0]) { /* reported in summary.json; the previous checkpoint is kept */
                snprintf(c->res->checkpoint_error, sizeof c->res->checkpoint_error, "%.255s",
                         werr.message);
            }
            if (c->opt && c->opt->notice) {
                char text[400];
                snprintf(text, sizeof text,
                         "checkpoint not written at t = %.6g s (the previous one is kept): %.300s",
                         gr_sim_time(c->sim), werr.message);
                c->opt->notice(text, c->opt->user);
            }
        }
        c->last_ckpt = gr_run_now();
    }
    if (c->stop) {
        c->ckst.k_next = k + 1;
        c->stopped_early = true;
        return false;
    }
    return true;
}

static void progress(gr_run_ctx *c, int64_t k, int64_t k_last)
{
    if (!(c->opt && c->opt->progress && (gr_run_now() - c->last_report > 0.5 || k == k_last))) {
        return;
    }
    c->last_report = gr_run_now();
    const double t = gr_sim_time(c->sim);
    double t_end = (double)k_last * (double)c->plan.per_sample * c->dt;
    double rate =
        c->stepping > 0.0 ? (double)c->scene->N * (double)gr_sim_steps(c->sim) / c->stepping : 0.0;
    gr_progress p = {.t = t,
                     .t_end = t_end,
                     .wall = gr_run_now() - c->start,
                     .eta = t > 0.0 ? (gr_run_now() - c->start) * (t_end - t) / t : 0.0,
                     .particle_steps_per_second = rate,
                     .event_driven = gr_sim_integrator(c->sim)->events != NULL,
                     .events_per_second =
                         c->stepping > 0.0 ? (double)gr_sim_events_processed(c->sim) / c->stepping
                                           : 0.0,
                     .warmup = k <= c->plan.warm_samples};
    c->opt->progress(&p, c->opt->user);
}

bool gr_run_samples(gr_run_ctx *c, int64_t k_from, int64_t k_to)
{
    const int64_t k_last = c->plan.warm_samples + c->plan.run_samples;
    for (int64_t k = k_from; k <= k_to; k++) {
        if (k > 0 && !advance(c, k)) {
            return false;
        }
        if (!record(c, k)) {
            return false;
        }
        if (k < k_last && !checkpoint_or_stop(c, k)) {
            return false;
        }
        progress(c, k, k_last);
    }
    return true;
}

bool gr_run_stop(gr_run_ctx *c)
{
    c->stop = c->stopped_early ? c->stop : 0; /* a request after the last sample changes nothing */
    if (c->stop && c->can_checkpoint && strcmp(c->status, "completed") == 0 && c->rc == GR_OK) {
        double used = 0.0;
        size_t bytes = 0;
        c->rc = gr_run_checkpoint_write(c->dir, c->scene, c->sim, c->obs, &c->ckst, &used, &bytes,
                                        c->err);
        if (c->rc == GR_OK) {
            /* the streamed CSVs and the trajectory stay as they are for the resume to continue */
            gr_traj_writer_close(&c->traj, &(gr_error){0});
            gr_run_stream_leave(&c->ft);
            gr_run_stream_leave(&c->fl);
            free(c->haff_t);
            free(c->haff_T);
            gr_observer_free(c->obs);
            c->res->steps = gr_sim_steps(c->sim);
            c->res->collisions = gr_sim_collisions(c->sim);
            c->res->samples = c->blk.count[0];
            c->res->wall_seconds = gr_run_now() - c->start;
            c->res->checkpoints++;
            c->res->checkpoint_seconds += used;
            c->res->stopped = c->stop;
            gr_sim_free(c->sim);
            return true;
        }
        c->status = "interrupted"; /* no checkpoint: finish the outputs instead */
        snprintf(c->diagnosis, sizeof c->diagnosis,
                 "stopped (%s) but the checkpoint could not be written: %.700s",
                 c->stop == 1 ? "signal" : "wall-clock budget", c->err->message);
        c->rc = GR_OK;
    } else if (c->stop && strcmp(c->status, "completed") == 0) {
        c->status = "interrupted";
        snprintf(c->diagnosis, sizeof c->diagnosis, "stopped (%s) at t = %.6g s; %.700s",
                 c->stop == 1 ? "signal" : "wall-clock budget", gr_sim_time(c->sim),
                 c->ck_err.message);
    }
    return false;
}
