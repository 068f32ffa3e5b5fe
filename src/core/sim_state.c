/* Saving and restoring a simulation's state for exact restarts (docs/checkpoints.md): the core's
 * part below, then the integrator's own (its save / load hooks, e.g.
 * src/integrators/event/event_state.c, src/integrators/hybrid/hy_state.c). The state goes into a
 * byte buffer (src/core/blob.h); the io layer writes it to a file (src/io/checkpoint.c).
 *
 * Between two gr_sim_step calls the velocities are synchronised, and the next step depends on:
 * positions and velocities; the forces of the last evaluation (fx, fy), their non-conservative
 * part (gx, gy) and the dissipation shares the opening half kick books them with; the step
 * counter (the noise is a pure function of seed, step and particle, and com resets fall on
 * multiples of com_every); the ledger totals; the contact flags (pair_contact in 1D, nl_contact
 * in 2D: they decide which contacts are new); in 2D the Verlet list itself (nl_start, nl_j) and
 * the reference positions x_ref, y_ref that schedule its next rebuild (3D: z, vz, fz, gz and
 * z_ref too, and the same list). The list is stored rather
 * than rebuilt: its order fixes the summation order of the forces, and a build also wraps
 * positions and derives contact flags from the velocities, so storing it is the only way that
 * is exact by construction. With contact tracking, each particle's contact count and the
 * events not yet handed to the observables are stored too; with rotation, the angular
 * velocities and torques; with a Langevin bath, the energy its drag removed. The noise buffer is scratch (redrawn
 * every step); cell arrays are rebuilt from positions at the next list build. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "core/sim_state.h"

#define SIM_STATE_TAG 0x53494d31u /* "SIM1": bump when the layout below changes */

int gr_sim_checkpointable(const gr_sim *s, gr_error *err)
{
    /* an integrator with state of its own must save it */
    if (s->integrator_state && !s->integrator->state_io) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kind = %s cannot save its state (no checkpoints)",
                       s->params.source, s->integrator->name);
    }
    return GR_OK;
}

int64_t gr_sim_call_steps(const gr_sim *s, int64_t want, int64_t todo)
{
    const int64_t n = want < todo ? want : todo;
    return s->integrator->call_steps ? s->integrator->call_steps(s, n, todo) : n;
}

static void report_io(gr_blob_io *io, gr_force_report *r)
{
    gr_blob_io_f64(io, &r->elastic);
    gr_blob_io_f64(io, &r->power_normal);
    gr_blob_io_f64(io, &r->power_tangential);
    gr_blob_io_f64(io, &r->power_friction);
    gr_blob_io_i64(io, &r->new_contacts);
    gr_blob_io_f64(io, &r->max_overlap);
    gr_blob_io_int(io, &r->worst_i);
    gr_blob_io_int(io, &r->worst_j);
}

/* Loading: room for a neighbour list of `pairs` pairs (the growth a list build would do). */
static int list_room(gr_sim *s, int64_t pairs, gr_error *err)
{
    if (pairs <= s->nl_cap) {
        return GR_OK;
    }
    int *j = realloc(s->nl_j, sizeof(int) * (size_t)pairs);
    if (j) {
        s->nl_j = j;
    }
    uint8_t *c = j ? realloc(s->nl_contact, (size_t)pairs) : NULL;
    if (c) {
        s->nl_contact = c;
    }
    double *h =
        c && s->nl_hist
            ? realloc(s->nl_hist, sizeof(double) * (size_t)gr_history_width(s) * (size_t)pairs)
            : NULL;
    if (h) {
        s->nl_hist = h;
    }
    if (!j || !c || (s->nl_hist && !h)) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for a neighbour list of %lld pairs",
                       (long long)pairs);
    }
    s->nl_cap = pairs;
    return GR_OK;
}

/* Loading: the kernels index with the list, so refuse anything that is not a valid half list. */
static void check_list(const gr_sim *s, gr_blob_reader *b, int64_t pairs)
{
    const int n = s->n;
    for (int i = 0; i < n && !b->bad; i++) {
        if (s->nl_start[i] < 0 || s->nl_start[i] > s->nl_start[i + 1]) {
            gr_blob_fail(b, "neighbour list offsets are not increasing at particle %d", i);
        }
    }
    if (!b->bad && (s->nl_start[0] != 0 || s->nl_start[n] != pairs)) {
        gr_blob_fail(b, "neighbour list offsets do not span its %lld pairs", (long long)pairs);
    }
    for (int64_t p = 0; p < pairs && !b->bad; p++) {
        if (s->nl_j[p] < 0 || s->nl_j[p] >= n) {
            gr_blob_fail(b, "neighbour list entry %lld names particle %d of %d", (long long)p,
                         s->nl_j[p], n);
        }
    }
    for (int i = 0; i < n && !b->bad; i++) {
        if (!(s->x[i] >= 0.0 && s->x[i] < s->L && s->y[i] >= 0.0 && s->y[i] < s->L) ||
            (s->dim == 3 && !(s->z[i] >= 0.0 && s->z[i] < s->L))) {
            gr_blob_fail(b, "particle %d lies outside the box [0, L)", i);
        }
    }
}

/* 2D: the neighbour list, stored as it is (its order fixes the summation order). */
static int list_io(gr_sim *s, gr_blob_io *io, gr_error *err)
{
    const int n = s->n;
    int64_t pairs = io->in ? 0 : s->nl_start[n];
    gr_blob_io_i64(io, &pairs);
    if (io->in) {
        if (!io->in->bad && (pairs < 0 || pairs > (int64_t)n * (int64_t)(n - 1) / 2 ||
                             pairs > (int64_t)INT32_MAX)) {
            gr_blob_fail(io->in, "neighbour list of %lld pairs is impossible for %d particles",
                         (long long)pairs, n);
        }
        if (io->in->bad) {
            return gr_blob_done(io->in, err);
        }
        int rc = list_room(s, pairs, err);
        if (rc) {
            return rc;
        }
        s->par_threads =
            0; /* the threaded kernel's cross-pair tables belong to the list just replaced */
    }
    gr_blob_io_bytes(io, s->nl_start, sizeof(int) * ((size_t)n + 1));
    gr_blob_io_bytes(io, s->nl_j, sizeof(int) * (size_t)pairs);
    gr_blob_io_bytes(io, s->nl_contact, (size_t)pairs);
    if (s->nl_hist) { /* the contact history (contact_history.c), when the law keeps one */
        gr_blob_io_f64s(io, s->nl_hist, pairs * gr_history_width(s)); /* 3D: vectors */
    }
    if (io->in) {
        check_list(s, io->in, pairs);
    }
    return GR_OK;
}

/* The contact events not yet handed to the observables (contact tracking only). */
static int events_io(gr_sim *s, gr_blob_io *io, gr_error *err)
{
    const int n = s->n;
    uint32_t tracked = s->contacts != NULL;
    gr_blob_io_u32(io, &tracked);
    if (io->in && !io->in->bad && (tracked != 0) != (s->contacts != NULL)) {
        gr_blob_fail(io->in,
                     "contact events were %s in the checkpoint but %s for this scene's observables",
                     tracked ? "tracked" : "not tracked", s->contacts ? "are needed" : "are not");
    }
    if (!tracked || gr_blob_io_bad(io)) {
        return GR_OK;
    }
    gr_blob_io_bytes(io, s->contacts, sizeof(uint16_t) * (size_t)n);
    int64_t n_events = s->n_events;
    gr_blob_io_i64(io, &n_events);
    const int nv = s->dim == 3 ? 7 : 5; /* t, x, y, vx, vy (3D: z, vz too) */
    const int64_t each = 2 * 8 + nv * 8;
    if (io->in && !io->in->bad &&
        (n_events < 0 || (uint64_t)n_events > gr_blob_io_left(io) / each)) {
        gr_blob_fail(io->in, "%lld contact events do not fit in the section", (long long)n_events);
    }
    if (io->in) {
        s->n_events = 0;
    }
    for (int64_t k = 0; k < n_events && !gr_blob_io_bad(io); k++) {
        if (io->in && s->n_events == s->cap_events) {
            gr_contact_event *e = realloc(s->events, sizeof *e * (size_t)(2 * s->cap_events));
            if (!e) {
                return GR_FAIL(err, GR_ENOMEM, "out of memory for %lld contact events",
                               (long long)n_events);
            }
            s->events = e;
            s->cap_events *= 2;
        }
        gr_contact_event *e = &s->events[io->in ? s->n_events++ : k];
        int64_t i = e->i, kind = e->kind;
        double v[7] = {e->t, e->x, e->y, e->vx, e->vy, e->z, e->vz};
        gr_blob_io_i64(io, &i);
        gr_blob_io_i64(io, &kind);
        gr_blob_io_bytes(io, v, sizeof v[0] * (size_t)nv);
        if (io->in && !io->in->bad && (i < 0 || i >= n || (kind != 1 && kind != -1))) {
            gr_blob_fail(io->in, "contact event %lld is malformed (particle %lld, kind %lld)",
                         (long long)k, (long long)i, (long long)kind);
        }
        if (io->in) {
            *e = (gr_contact_event){.i = (int)i,
                                    .kind = (int)kind,
                                    .t = v[0],
                                    .x = v[1],
                                    .y = v[2],
                                    .vx = v[3],
                                    .vy = v[4],
                                    .z = nv == 7 ? v[5] : 0.0,
                                    .vz = nv == 7 ? v[6] : 0.0};
        }
    }
    return GR_OK;
}

/* The core's state, listed once: gr_sim_save_state appends it, gr_sim_load_state reads it back
 * in the same order (core/blob.h, gr_blob_io). */
static int sim_io(gr_sim *s, gr_blob_io *io, gr_error *err)
{
    const int n = s->n;
    gr_blob_io_tag(io, "simulation state", SIM_STATE_TAG);
    int64_t n_saved = n, dim = s->dim;
    gr_blob_io_i64(io, &n_saved);
    gr_blob_io_i64(io, &dim);
    if (io->in && !io->in->bad && (n_saved != n || dim != s->dim)) {
        gr_blob_fail(io->in, "%lld particles in %lld D, the scene has %d in %d D",
                     (long long)n_saved, (long long)dim, n, s->dim);
    }
    gr_blob_io_expect_f64(io, "dt", s->dt);
    gr_blob_io_expect_f64(io, "L", s->L);
    gr_blob_io_expect_f64(io, "d", s->d);
    gr_blob_io_expect_f64(io, "mass", s->mass);
    if (!io->in) {
        gr_blob_put_str(io->out, s->kernel_name);
    } else {
        char kernel[sizeof s->kernel_name];
        if (gr_blob_get_str(io->in, kernel, sizeof kernel) && strcmp(kernel, s->kernel_name) != 0) {
            gr_blob_fail(io->in, "kernel %s in the checkpoint, %s for this scene", kernel,
                         s->kernel_name);
        }
    }
    gr_blob_io_i64(io, &s->step);
    gr_blob_io_i64(io, &s->collisions);
    gr_blob_io_i64(io, &s->rebuilds);
    int64_t com_every = s->com_every;
    gr_blob_io_i64(io, &com_every);
    if (io->in && !io->in->bad && (s->step < 0 || com_every != s->com_every)) {
        gr_blob_fail(io->in, "step %lld / com_every %lld do not fit this scene (com_every %lld)",
                     (long long)s->step, (long long)com_every, (long long)s->com_every);
    }
    double totals[] = {s->elastic, s->initial_energy, s->injected, s->diss_n,   s->diss_t,
                       s->diss_f,  s->removed_com,    s->share[0], s->share[1], s->share[2]};
    gr_blob_io_f64s(io, totals, (int64_t)(sizeof totals / sizeof totals[0]));
    if (io->in) {
        s->elastic = totals[0];
        s->initial_energy = totals[1];
        s->injected = totals[2];
        s->diss_n = totals[3];
        s->diss_t = totals[4];
        s->diss_f = totals[5];
        s->removed_com = totals[6];
        memcpy(s->share, totals + 7, sizeof s->share);
    }
    report_io(io, &s->last);
    double *const per_particle[] = {s->x, s->vx, s->fx, s->gx};
    for (size_t k = 0; k < sizeof per_particle / sizeof per_particle[0]; k++) {
        gr_blob_io_f64s(io, per_particle[k], n);
    }
    int rc = GR_OK;
    if (s->dim >= 2) {
        double *const per_particle_2d[] = {s->y, s->vy, s->fy, s->gy, s->x_ref, s->y_ref};
        for (size_t k = 0; k < sizeof per_particle_2d / sizeof per_particle_2d[0]; k++) {
            gr_blob_io_f64s(io, per_particle_2d[k], n);
        }
        if (s->dim == 3) { /* spheres: the third component, then the same list (kernels_3d.c) */
            double *const per_particle_3d[] = {s->z, s->vz, s->fz, s->gz, s->z_ref};
            for (size_t k = 0; k < sizeof per_particle_3d / sizeof per_particle_3d[0]; k++) {
                gr_blob_io_f64s(io, per_particle_3d[k], n);
            }
        }
        rc = list_io(s, io, err);
    } else {
        gr_blob_io_bytes(io, s->pair_contact, (size_t)n + 1);
    }
    rc = rc ? rc : events_io(s, io, err);
    if (!rc && !gr_blob_io_bad(io) && s->omega) {
        /* rotation: the angular velocities and the torques the next opening half kick uses */
        gr_blob_io_f64s(io, s->omega, n);
        gr_blob_io_f64s(io, s->tq, n);
        if (s->tg) { /* a history law's: their non-conservative part, which that kick books */
            gr_blob_io_f64s(io, s->tg, n);
        }
        if (s->wx) { /* 3D: the x and y components of the spins and torques (the above are z) */
            double *const spin_3d[] = {s->wx, s->wy, s->tqx, s->tqy, s->tgx, s->tgy};
            for (size_t k = 0; k < sizeof spin_3d / sizeof spin_3d[0]; k++) {
                if (spin_3d[k]) {
                    gr_blob_io_f64s(io, spin_3d[k], n);
                }
            }
        }
    }
    if (!rc && !gr_blob_io_bad(io) && s->walls_on) {
        /* walls (walls.c): the impulse each took, the moving wall's work, a history law's slots */
        gr_blob_io_f64s(io, s->wall_impulse, s->dim == 3 ? 6 : 4);
        if (s->params.vibrate) {
            gr_blob_io_f64(io, &s->wall_work);
        }
        if (s->wall_hist) {
            gr_blob_io_f64s(io, s->wall_hist, (s->dim == 3 ? 18 : 4) * (int64_t)n);
        }
    }
    if (!rc && !gr_blob_io_bad(io) && s->drive == GR_DRIVE_BATH) {
        gr_blob_io_f64(
            io,
            &s->diss_drag); /* the bath's drag in the ledger (only then: other layouts unchanged) */
    }
    return rc;
}

int gr_sim_save_state(const gr_sim *s, gr_blob *b, gr_error *err)
{
    int rc = gr_sim_checkpointable(s, err);
    if (rc) {
        return rc;
    }
    gr_blob_io io = {.out = b};
    rc = sim_io((gr_sim *)s, &io, err); /* saving reads the state only */
    rc = rc ? rc : gr_blob_ok(b, err);
    if (!rc && s->integrator->state_io) {
        rc = s->integrator->state_io((gr_sim *)s, &io, err);
    }
    return rc;
}

int gr_sim_load_state(gr_sim *s, gr_blob_reader *b, gr_error *err)
{
    int rc = gr_sim_checkpointable(s, err);
    if (rc) {
        return rc;
    }
    gr_blob_io io = {.in = b};
    rc = sim_io(s, &io, err);
    if (!rc && !b->bad && s->integrator->state_io) {
        rc = s->integrator->state_io(s, &io, err);
    }
    return rc ? rc : gr_blob_done(b, err);
}

static const char STATE_MAGIC[4] = {'G', 'R', 'S', 'C'};
#define STATE_TRAILER 8

int gr_sim_state_save(const gr_sim *s, void **data, size_t *len, gr_error *err)
{
    gr_blob b = {0};
    *data = NULL;
    *len = 0;
    int rc = gr_sim_save_state(s, &b, err);
    rc = rc ? rc : gr_blob_ok(&b, err);
    if (rc) {
        gr_blob_free(&b);
        return rc;
    }
    /* a trailer: magic and the CRC-32 of the bytes before it, checked by gr_sim_state_load (a
     * checkpoint file has its own, src/io/checkpoint.c) */
    const uint32_t crc = gr_blob_crc32(b.data, b.len);
    gr_blob_put(&b, STATE_MAGIC, 4);
    gr_blob_put_u32(&b, crc);
    if ((rc = gr_blob_ok(&b, err))) {
        gr_blob_free(&b);
        return rc;
    }
    *data = b.data;
    *len = b.len;
    return GR_OK;
}

int gr_sim_state_load(gr_sim *s, const void *data, size_t len, gr_error *err)
{
    const unsigned char *p = data;
    if (len < STATE_TRAILER || memcmp(p + len - STATE_TRAILER, STATE_MAGIC, 4)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "state: %zu bytes without the checksum trailer of gr_sim_state_save (Sim.state()): "
            "not a saved state, cut short, or from a granule before the checksum",
            len);
    }
    uint32_t stored;
    memcpy(&stored, p + len - 4, 4);
    const uint32_t computed = gr_blob_crc32(p, len - STATE_TRAILER);
    if (stored != computed) {
        return GR_FAIL(
            err, GR_EINVAL,
            "state: checksum mismatch (CRC-32 stored %08x, computed %08x): the bytes were changed "
            "after they were saved",
            stored, computed);
    }
    gr_blob_reader r;
    gr_blob_reader_init(&r, data, len - STATE_TRAILER, "SIM");
    return gr_sim_load_state(s, &r, err);
}
