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
 * the reference positions x_ref, y_ref that schedule its next rebuild. The list is stored rather
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
    if (s->integrator_state && (!s->integrator->save || !s->integrator->load)) {
        return GR_FAIL(err, GR_EINVAL, "%s: [integrator] kind = %s cannot save its state (no checkpoints)",
                       s->params.source, s->integrator->name);
    }
    return GR_OK;
}

int64_t gr_sim_call_steps(const gr_sim *s, int64_t want, int64_t todo)
{
    const int64_t n = want < todo ? want : todo;
    return s->integrator->call_steps ? s->integrator->call_steps(s, n, todo) : n;
}

static void put_report(gr_blob *b, const gr_force_report *r)
{
    gr_blob_put_f64(b, r->elastic);
    gr_blob_put_f64(b, r->power_normal);
    gr_blob_put_f64(b, r->power_tangential);
    gr_blob_put_f64(b, r->power_friction);
    gr_blob_put_i64(b, r->new_contacts);
    gr_blob_put_f64(b, r->max_overlap);
    gr_blob_put_i64(b, r->worst_i);
    gr_blob_put_i64(b, r->worst_j);
}

static void get_report(gr_blob_reader *b, gr_force_report *r)
{
    r->elastic = gr_blob_get_f64(b);
    r->power_normal = gr_blob_get_f64(b);
    r->power_tangential = gr_blob_get_f64(b);
    r->power_friction = gr_blob_get_f64(b);
    r->new_contacts = gr_blob_get_i64(b);
    r->max_overlap = gr_blob_get_f64(b);
    r->worst_i = (int)gr_blob_get_i64(b);
    r->worst_j = (int)gr_blob_get_i64(b);
}

int gr_sim_save_state(const gr_sim *s, gr_blob *b, gr_error *err)
{
    int rc = gr_sim_checkpointable(s, err);
    if (rc) {
        return rc;
    }
    const int n = s->n;
    gr_blob_put_u32(b, SIM_STATE_TAG);
    gr_blob_put_i64(b, n);
    gr_blob_put_i64(b, s->dim);
    gr_blob_put_f64(b, s->dt);
    gr_blob_put_f64(b, s->L);
    gr_blob_put_f64(b, s->d);
    gr_blob_put_f64(b, s->mass);
    gr_blob_put_str(b, s->kernel_name);
    gr_blob_put_i64(b, s->step);
    gr_blob_put_i64(b, s->collisions);
    gr_blob_put_i64(b, s->rebuilds);
    gr_blob_put_i64(b, s->com_every);
    const double totals[] = {s->elastic, s->initial_energy, s->injected, s->diss_n, s->diss_t, s->diss_f,
                             s->removed_com, s->share[0], s->share[1], s->share[2]};
    gr_blob_put_f64s(b, totals, (int64_t)(sizeof totals / sizeof totals[0]));
    put_report(b, &s->last);
    gr_blob_put_f64s(b, s->x, n);
    gr_blob_put_f64s(b, s->vx, n);
    gr_blob_put_f64s(b, s->fx, n);
    gr_blob_put_f64s(b, s->gx, n);
    if (s->dim == 2) {
        gr_blob_put_f64s(b, s->y, n);
        gr_blob_put_f64s(b, s->vy, n);
        gr_blob_put_f64s(b, s->fy, n);
        gr_blob_put_f64s(b, s->gy, n);
        gr_blob_put_f64s(b, s->x_ref, n);
        gr_blob_put_f64s(b, s->y_ref, n);
        const int64_t pairs = s->nl_start[n];
        gr_blob_put_i64(b, pairs);
        gr_blob_put(b, s->nl_start, sizeof(int) * ((size_t)n + 1));
        gr_blob_put(b, s->nl_j, sizeof(int) * (size_t)pairs);
        gr_blob_put(b, s->nl_contact, (size_t)pairs);
        if (s->nl_hist) { /* the contact history (contact_history.c), when the law keeps one */
            gr_blob_put_f64s(b, s->nl_hist, pairs);
        }
    } else {
        gr_blob_put(b, s->pair_contact, (size_t)n + 1);
    }
    gr_blob_put_u32(b, s->contacts != NULL);
    if (s->contacts) {
        gr_blob_put(b, s->contacts, sizeof(uint16_t) * (size_t)n);
        gr_blob_put_i64(b, s->n_events);
        for (int64_t k = 0; k < s->n_events; k++) {
            const gr_contact_event *e = &s->events[k];
            gr_blob_put_i64(b, e->i);
            gr_blob_put_i64(b, e->kind);
            const double v[] = {e->t, e->x, e->y, e->vx, e->vy};
            gr_blob_put(b, v, sizeof v);
        }
    }
    if (s->omega) {
        /* rotation: the angular velocities and the torques the next opening half kick uses */
        gr_blob_put_f64s(b, s->omega, n);
        gr_blob_put_f64s(b, s->tq, n);
        if (s->tg) { /* a history law's: their non-conservative part, which that kick books */
            gr_blob_put_f64s(b, s->tg, n);
        }
    }
    if (s->drive == GR_DRIVE_BATH) { /* the bath's drag in the ledger (only then: other layouts unchanged) */
        gr_blob_put_f64(b, s->diss_drag);
    }
    rc = gr_blob_ok(b, err);
    if (!rc && s->integrator->save) {
        rc = s->integrator->save(s, b, err);
    }
    return rc;
}

/* Compare a stored scalar with the one the scene gives, bit for bit. */
static void expect_f64(gr_blob_reader *b, const char *what, double have)
{
    double v = gr_blob_get_f64(b);
    if (!b->bad && memcmp(&v, &have, sizeof v) != 0) {
        gr_blob_fail(b, "%s is %.17g in the checkpoint but %.17g for this scene", what, v, have);
    }
}

int gr_sim_load_state(gr_sim *s, gr_blob_reader *b, gr_error *err)
{
    int rc = gr_sim_checkpointable(s, err);
    if (rc) {
        return rc;
    }
    const int n = s->n;
    uint32_t tag = gr_blob_get_u32(b);
    if (!b->bad && tag != SIM_STATE_TAG) {
        gr_blob_fail(b, "simulation state layout %08x, this build reads %08x", tag, SIM_STATE_TAG);
    }
    int64_t n_saved = gr_blob_get_i64(b), dim = gr_blob_get_i64(b);
    if (!b->bad && (n_saved != n || dim != s->dim)) {
        gr_blob_fail(b, "%lld particles in %lld D, the scene has %d in %d D", (long long)n_saved, (long long)dim, n, s->dim);
    }
    expect_f64(b, "dt", s->dt);
    expect_f64(b, "L", s->L);
    expect_f64(b, "d", s->d);
    expect_f64(b, "mass", s->mass);
    char kernel[sizeof s->kernel_name];
    if (gr_blob_get_str(b, kernel, sizeof kernel) && strcmp(kernel, s->kernel_name) != 0) {
        gr_blob_fail(b, "kernel %s in the checkpoint, %s for this scene", kernel, s->kernel_name);
    }
    s->step = gr_blob_get_i64(b);
    s->collisions = gr_blob_get_i64(b);
    s->rebuilds = gr_blob_get_i64(b);
    int64_t com_every = gr_blob_get_i64(b);
    if (!b->bad && (s->step < 0 || com_every != s->com_every)) {
        gr_blob_fail(b, "step %lld / com_every %lld do not fit this scene (com_every %lld)", (long long)s->step,
                     (long long)com_every, (long long)s->com_every);
    }
    double totals[10];
    gr_blob_get_f64s(b, totals, 10);
    s->elastic = totals[0];
    s->initial_energy = totals[1];
    s->injected = totals[2];
    s->diss_n = totals[3];
    s->diss_t = totals[4];
    s->diss_f = totals[5];
    s->removed_com = totals[6];
    memcpy(s->share, totals + 7, sizeof s->share);
    get_report(b, &s->last);
    gr_blob_get_f64s(b, s->x, n);
    gr_blob_get_f64s(b, s->vx, n);
    gr_blob_get_f64s(b, s->fx, n);
    gr_blob_get_f64s(b, s->gx, n);
    if (s->dim == 2) {
        gr_blob_get_f64s(b, s->y, n);
        gr_blob_get_f64s(b, s->vy, n);
        gr_blob_get_f64s(b, s->fy, n);
        gr_blob_get_f64s(b, s->gy, n);
        gr_blob_get_f64s(b, s->x_ref, n);
        gr_blob_get_f64s(b, s->y_ref, n);
        int64_t pairs = gr_blob_get_i64(b);
        if (!b->bad && (pairs < 0 || pairs > (int64_t)n * (int64_t)(n - 1) / 2 || pairs > (int64_t)INT32_MAX)) {
            gr_blob_fail(b, "neighbour list of %lld pairs is impossible for %d particles", (long long)pairs, n);
        }
        if (b->bad) {
            return gr_blob_done(b, err);
        }
        if (pairs > s->nl_cap) { /* same growth the list build would have done */
            int *j = realloc(s->nl_j, sizeof(int) * (size_t)pairs);
            if (j) {
                s->nl_j = j;
            }
            uint8_t *c = j ? realloc(s->nl_contact, (size_t)pairs) : NULL;
            if (c) {
                s->nl_contact = c;
            }
            double *h = c && s->nl_hist ? realloc(s->nl_hist, sizeof(double) * (size_t)pairs) : NULL;
            if (h) {
                s->nl_hist = h;
            }
            if (!j || !c || (s->nl_hist && !h)) {
                return GR_FAIL(err, GR_ENOMEM, "out of memory for a neighbour list of %lld pairs", (long long)pairs);
            }
            s->nl_cap = pairs;
        }
        /* the threaded kernel's cross-pair tables belong to the list just replaced: rebuild them */
        s->par_threads = 0;
        gr_blob_get(b, s->nl_start, sizeof(int) * ((size_t)n + 1));
        gr_blob_get(b, s->nl_j, sizeof(int) * (size_t)pairs);
        gr_blob_get(b, s->nl_contact, (size_t)pairs);
        if (s->nl_hist) {
            gr_blob_get_f64s(b, s->nl_hist, pairs);
        }
        /* the kernels index with these: refuse anything that is not a valid half list */
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
                gr_blob_fail(b, "neighbour list entry %lld names particle %d of %d", (long long)p, s->nl_j[p], n);
            }
        }
        for (int i = 0; i < n && !b->bad; i++) {
            if (!(s->x[i] >= 0.0 && s->x[i] < s->L && s->y[i] >= 0.0 && s->y[i] < s->L)) {
                gr_blob_fail(b, "particle %d lies outside the box [0, L)", i);
            }
        }
    } else {
        gr_blob_get(b, s->pair_contact, (size_t)n + 1);
    }
    uint32_t tracked = gr_blob_get_u32(b);
    if (!b->bad && (tracked != 0) != (s->contacts != NULL)) {
        gr_blob_fail(b, "contact events were %s in the checkpoint but %s for this scene's observables",
                     tracked ? "tracked" : "not tracked", s->contacts ? "are needed" : "are not");
    }
    if (!b->bad && tracked) {
        gr_blob_get(b, s->contacts, sizeof(uint16_t) * (size_t)n);
        int64_t n_events = gr_blob_get_i64(b);
        const int64_t each = 2 * 8 + 5 * 8;
        if (!b->bad && (n_events < 0 || (uint64_t)n_events > (b->len - b->pos) / each)) {
            gr_blob_fail(b, "%lld contact events do not fit in the section", (long long)n_events);
        }
        s->n_events = 0;
        for (int64_t k = 0; k < n_events && !b->bad; k++) {
            if (s->n_events == s->cap_events) {
                gr_contact_event *e = realloc(s->events, sizeof *e * (size_t)(2 * s->cap_events));
                if (!e) {
                    return GR_FAIL(err, GR_ENOMEM, "out of memory for %lld contact events", (long long)n_events);
                }
                s->events = e;
                s->cap_events *= 2;
            }
            gr_contact_event *e = &s->events[s->n_events++];
            int64_t i = gr_blob_get_i64(b), kind = gr_blob_get_i64(b);
            double v[5] = {0};
            gr_blob_get(b, v, sizeof v);
            if (!b->bad && (i < 0 || i >= n || (kind != 1 && kind != -1))) {
                gr_blob_fail(b, "contact event %lld is malformed (particle %lld, kind %lld)", (long long)k, (long long)i,
                             (long long)kind);
            }
            *e = (gr_contact_event){.i = (int)i, .kind = (int)kind, .t = v[0], .x = v[1], .y = v[2], .vx = v[3], .vy = v[4]};
        }
    }
    if (!b->bad && s->omega) {
        gr_blob_get_f64s(b, s->omega, n);
        gr_blob_get_f64s(b, s->tq, n);
        if (s->tg) {
            gr_blob_get_f64s(b, s->tg, n);
        }
    }
    if (!b->bad && s->drive == GR_DRIVE_BATH) {
        s->diss_drag = gr_blob_get_f64(b);
    }
    if (!b->bad && s->integrator->load) {
        rc = s->integrator->load(s, b, err);
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
        return GR_FAIL(err, GR_EINVAL, "state: %zu bytes without the checksum trailer of gr_sim_state_save (Sim.state()): "
                       "not a saved state, cut short, or from a granule before the checksum", len);
    }
    uint32_t stored;
    memcpy(&stored, p + len - 4, 4);
    const uint32_t computed = gr_blob_crc32(p, len - STATE_TRAILER);
    if (stored != computed) {
        return GR_FAIL(err, GR_EINVAL, "state: checksum mismatch (CRC-32 stored %08x, computed %08x): the bytes were changed "
                       "after they were saved", stored, computed);
    }
    gr_blob_reader r;
    gr_blob_reader_init(&r, data, len - STATE_TRAILER, "SIM");
    return gr_sim_load_state(s, &r, err);
}
