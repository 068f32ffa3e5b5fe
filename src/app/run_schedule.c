/* The schedule of a run in whole steps (see run_schedule.h). */
#include "app/run_schedule.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* An interval of `x` seconds as a whole number of steps of dt (at least one). */
static int steps_of(const char *key, double x, double dt, int64_t *n, char *note, size_t note_len,
                    gr_error *err)
{
    const double r = x / dt;
    if (!(r <= GR_SCHEDULE_MAX_STEPS)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s = %g s is %.3g time steps of integrator.dt = %g s; at most %.3g steps are run: "
            "allowed range [dt, %.3g s] (or a larger integrator.dt)",
            key, x, r, dt, GR_SCHEDULE_MAX_STEPS, GR_SCHEDULE_MAX_STEPS * dt);
    }
    if (r < 1.0 - 1e-9) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s = %g s is shorter than the time step dt = %g s (integrator.dt): nothing would "
            "happen between two of them; allowed range [%g, inf) s",
            key, x, dt, dt);
    }
    *n = llround(r);
    const double moved = fabs((double)*n * dt - x) / x;
    if (moved > GR_SCHEDULE_NOTE) {
        size_t len = strlen(note);
        snprintf(note + len, note_len - len,
                 "%s = %g s is not a whole number of steps of dt = %g s: rounded to %lld steps "
                 "= %g s (%.1f %% off)\n",
                 key, x, dt, (long long)*n, (double)*n * dt, 100.0 * moved);
    }
    return GR_OK;
}

/* `x` seconds as a whole number of sample intervals. */
static int samples_of(const char *key, double x, double every, int64_t *n, gr_error *err)
{
    const double r = x / every;
    const double whole = nearbyint(r);
    if (!(fabs(r - whole) <= 1e-6 * fmax(1.0, r))) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s = %g s is not a whole number of run.sample_every = %g s (%.6g samples); "
                       "allowed: a multiple of run.sample_every, e.g. %g s or %g s",
                       key, x, every, r, floor(r) * every, ceil(r) * every);
    }
    *n = (int64_t)whole;
    return GR_OK;
}

int gr_run_schedule_make(const gr_scene *s, double dt, gr_run_schedule *out, char *note,
                         size_t note_len, gr_error *err)
{
    memset(out, 0, sizeof *out);
    note[0] = '\0';
    int rc =
        steps_of("run.sample_every", s->sample_every, dt, &out->per_sample, note, note_len, err);
    if (!rc && s->sample_every > s->duration && s->duration > 0.0) {
        rc = GR_FAIL(
            err, GR_EINVAL,
            "run.sample_every = %g s is longer than run.duration = %g s: no sample would be taken; "
            "allowed range (0, %g] s",
            s->sample_every, s->duration, s->duration);
    }
    rc = rc ? rc : samples_of("run.warmup", s->warmup, s->sample_every, &out->warm_samples, err);
    rc = rc ? rc : samples_of("run.duration", s->duration, s->sample_every, &out->run_samples, err);
    if (!rc && out->run_samples < 1) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "run.duration = %g s takes no sample: allowed range [%g, inf) s (at least one "
                     "run.sample_every)",
                     s->duration, s->sample_every);
    }
    if (!rc && (double)(out->warm_samples + out->run_samples) * (double)out->per_sample >
                   GR_SCHEDULE_MAX_STEPS) {
        rc = GR_FAIL(
            err, GR_EINVAL,
            "run.warmup + run.duration = %g s is %.3g time steps of dt = %g s; at most %.3g steps "
            "are run: shorten the run or use a larger integrator.dt",
            s->warmup + s->duration, (s->warmup + s->duration) / dt, dt, GR_SCHEDULE_MAX_STEPS);
    }
    if (!rc && s->snapshot_every > 0.0) {
        rc = steps_of("output.snapshot_every", s->snapshot_every, dt, &out->snap_every, note,
                      note_len, err);
    }
    if (!rc && s->checkpoint_every > 0.0) {
        const double c = ceil(s->checkpoint_every / s->sample_every - 1e-9);
        out->ckpt_samples =
            c < (double)(out->warm_samples + out->run_samples) ? (c < 1.0 ? 1 : (int64_t)c) : 0;
    }
    return rc;
}
