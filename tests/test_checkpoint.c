/* Tests of checkpoints (docs/checkpoints.md): the file format (src/io/checkpoint.c), the blob
 * reader's bounds checks (src/io/blob.c), the simulation state (src/core/sim_state.c) and the
 * observables' save/load hooks.
 *
 *   - a checkpoint image round-trips; every truncation and every single-byte change of it is
 *     refused with a message (never a crash, never a silent success)
 *   - a simulation saved after T steps and loaded into a fresh one continues bit for bit like
 *     the original (2D with contact tracking and com noise, 1D), and gr_sim_step split into
 *     uneven calls equals one call (what chunked stepping in the run driver relies on)
 *   - a state saved for another N is refused naming both
 *   - observers (every 1D and 2D observable) saved after some frames and loaded into fresh ones
 *     accumulate exactly like the originals: their saves after further frames are byte-equal
 *   - the event-driven (1D ring; 2D with cells, kicks, com) and hybrid (1D; 2D com; 3D) integrators:
 *     saved, loaded and continued in uneven calls (gr_sim_call_steps) equal the original bit for
 *     bit, counters included; every truncation of their state is refused; an event-driven call
 *     stopped by the stop flag, saved and resumed, equals an uninterrupted run
 *
 * GRANULE_TEST_QUICK=1 shortens the runs. */
#include <check.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim_state.h"
#include "integrators/event/event.h"
#include "integrators/hybrid/hybrid.h"
#include "granule/observe.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "analysis/blob_stats.h"
#include "io/checkpoint.h"
#include "app/run_checkpoint.h"
#include "check_main.h"

static int quick(void)
{
    const char *v = getenv("GRANULE_TEST_QUICK");
    return v && *v && strcmp(v, "0") != 0;
}

static void scene_of(gr_scene *s, const char *const *sets, int n)
{
    gr_error err = {0};
    int rc = gr_scene_load(s, NULL, sets, n, &err);
    ck_assert_msg(rc == GR_OK, "%s", err.message);
}

/* ---------- format ---------- */

static void *image_of(size_t *len)
{
    static const char a[] = "first section", c[] = "third";
    double b[4] = {1.0, -2.5, 3.25e-300, 1e300};
    const gr_checkpoint_section sec[] = {
        {"AAAA", a, sizeof a}, {"BBBB", b, sizeof b}, {"CCCC", c, 0}, {"DDDD", c, sizeof c}};
    void *img;
    gr_error err = {0};
    ck_assert_int_eq(gr_checkpoint_build(0x1234abcdULL, sec, 4, &img, len, &err), GR_OK);
    return img;
}

/* A checkpoint written by an older granule lacks the keys added since: each is compared with its
 * default (what that granule ran with), so such a checkpoint resumes when the scene leaves the
 * new key at its default and is refused, naming the key, when it does not. */
START_TEST(test_scene_text_older_checkpoint)
{
    const char *ck = "[run]\nseed = 1\n[analysis]\nobservables = moments\n";
    const char *same = "[run]\nseed = 1\n[analysis]\nobservables = moments\nprofile_axis = -1\n";
    const char *other = "[run]\nseed = 1\n[analysis]\nobservables = moments\nprofile_axis = 1\n";
    gr_error err = {0};
    bool defaulted = false;
    ck_assert_int_eq(gr_scene_text_compare(ck, strlen(ck), same, &defaulted, &err), GR_OK);
    ck_assert(defaulted);
    ck_assert_int_eq(gr_scene_text_compare(ck, strlen(ck), other, &defaulted, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "[analysis] profile_axis = -1 in the checkpoint, 1 now"),
                  "%s", err.message);
    defaulted = true;
    ck_assert_int_eq(gr_scene_text_compare(same, strlen(same), same, &defaulted, &err), GR_OK);
    ck_assert(!defaulted);
    /* a key no granule knows is still a difference */
    const char *odd = "[run]\nseed = 1\nfoo = 2\n[analysis]\nobservables = moments\n";
    ck_assert_int_eq(gr_scene_text_compare(odd, strlen(odd), same, NULL, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "[run] foo = 2 in the checkpoint, (unset) now"), "%s",
                  err.message);
}
END_TEST

START_TEST(test_format_round_trip)
{
    size_t len;
    unsigned char *img = image_of(&len);
    gr_checkpoint ck;
    gr_error err = {0};
    ck_assert_msg(gr_checkpoint_read_buffer(img, len, &ck, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(ck.n_sections, 4);
    ck_assert_uint_eq(ck.scene_hash, 0x1234abcdULL);
    ck_assert_uint_eq(ck.version, GR_CHECKPOINT_VERSION);
    const gr_checkpoint_section *s = gr_checkpoint_find(&ck, "BBBB");
    ck_assert_ptr_nonnull(s);
    ck_assert_uint_eq(s->len, 4 * sizeof(double));
    double b[4];
    memcpy(b, s->data, sizeof b);
    ck_assert(b[2] == 3.25e-300 && b[3] == 1e300);
    ck_assert_uint_eq(gr_checkpoint_find(&ck, "CCCC")->len, 0);
    ck_assert_str_eq(gr_checkpoint_find(&ck, "AAAA")->data, "first section");
    ck_assert_ptr_null(gr_checkpoint_find(&ck, "EEEE"));
    free(img);
}
END_TEST

START_TEST(test_format_truncation_and_corruption)
{
    size_t len;
    unsigned char *img = image_of(&len);
    unsigned char *copy = malloc(len);
    gr_checkpoint ck;
    for (size_t cut = 0; cut < len;
         cut++) { /* every truncation, each in a buffer of exactly that size */
        unsigned char *t = malloc(cut ? cut : 1);
        memcpy(t, img, cut);
        gr_error err = {0};
        ck_assert_int_eq(gr_checkpoint_read_buffer(t, cut, &ck, &err), GR_EINVAL);
        ck_assert_msg(cut < 8 ? strstr(err.message, "not a granule checkpoint") != NULL
                              : strstr(err.message, "truncated at byte") != NULL,
                      "cut at %zu: %s", cut, err.message);
        free(t);
    }
    for (size_t i = 0; i < len; i++) { /* every byte changed, two ways */
        for (int flip = 0; flip < 2; flip++) {
            memcpy(copy, img, len);
            copy[i] ^= flip ? 0xff : 0x01;
            gr_error err = {0};
            ck_assert_msg(gr_checkpoint_read_buffer(copy, len, &ck, &err) == GR_EINVAL &&
                              err.message[0],
                          "byte %zu ^ %d accepted", i, flip ? 0xff : 1);
        }
    }
    /* a wrong version is named as such (before the checksum) */
    memcpy(copy, img, len);
    copy[8] = 7;
    gr_error err = {0};
    gr_checkpoint_read_buffer(copy, len, &ck, &err);
    ck_assert_msg(strstr(err.message, "format version 7") != NULL, "%s", err.message);
    /* trailing garbage */
    unsigned char *longer = malloc(len + 3);
    memcpy(longer, img, len);
    memset(longer + len, 0, 3);
    ck_assert_int_eq(gr_checkpoint_read_buffer(longer, len + 3, &ck, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "trailing") != NULL, "%s", err.message);
    free(longer);
    free(copy);
    free(img);
}
END_TEST

START_TEST(test_blob_reader_bounds)
{
    gr_blob b = {0};
    gr_blob_put_u64(&b, 3);
    gr_blob_put_f64(&b, 1.5);
    gr_blob_reader r;
    gr_blob_reader_init(&r, b.data, b.len, "TEST");
    ck_assert_uint_eq(gr_blob_get_u64(&r), 3);
    ck_assert(gr_blob_get_f64(&r) == 1.5);
    gr_error err = {0};
    ck_assert_int_eq(gr_blob_done(&r, &err), GR_OK);
    /* an array that claims 3 doubles where 1 is stored */
    gr_blob_reader_init(&r, b.data, b.len, "TEST");
    double v[3];
    ck_assert(!gr_blob_get_f64s(&r, v, 3));
    ck_assert_int_eq(gr_blob_done(&r, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "checkpoint section TEST") != NULL, "%s", err.message);
    /* reading past the end, and leftover bytes */
    gr_blob_reader_init(&r, b.data, 4, "TEST");
    gr_blob_get_u64(&r);
    ck_assert_int_eq(gr_blob_done(&r, &err), GR_EINVAL);
    gr_blob_reader_init(&r, b.data, b.len, "TEST");
    gr_blob_get_u64(&r);
    ck_assert_int_eq(gr_blob_done(&r, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "unexpected bytes") != NULL, "%s", err.message);
    /* strings longer than the destination */
    gr_blob s = {0};
    gr_blob_put_str(&s, "abcdefgh");
    char small[4];
    gr_blob_reader_init(&r, s.data, s.len, "TEST");
    ck_assert(!gr_blob_get_str(&r, small, sizeof small));
    ck_assert_str_eq(small, "");
    gr_blob_free(&s);
    gr_blob_free(&b);
}
END_TEST

/* ---------- simulation state ---------- */

static void assert_same_sim(gr_sim *a, gr_sim *b)
{
    gr_particles pa = gr_sim_particles(a), pb = gr_sim_particles(b);
    ck_assert_int_eq(pa.n, pb.n);
    size_t bytes = sizeof(double) * (size_t)pa.n;
    ck_assert(memcmp(pa.x, pb.x, bytes) == 0);
    ck_assert(memcmp(pa.vx, pb.vx, bytes) == 0);
    if (pa.dim == 2) {
        ck_assert(memcmp(pa.y, pb.y, bytes) == 0);
        ck_assert(memcmp(pa.vy, pb.vy, bytes) == 0);
    }
    gr_ledger la = gr_sim_ledger(a), lb = gr_sim_ledger(b);
    ck_assert(memcmp(&la, &lb, sizeof la) == 0);
    ck_assert_int_eq(gr_sim_steps(a), gr_sim_steps(b));
    ck_assert_int_eq(gr_sim_collisions(a), gr_sim_collisions(b));
    ck_assert_int_eq(gr_sim_rebuilds(a), gr_sim_rebuilds(b));
    int64_t na, nb;
    const gr_contact_event *ea = gr_sim_events(a, &na), *eb = gr_sim_events(b, &nb);
    ck_assert_int_eq(na, nb);
    for (int64_t k = 0; k < na; k++) {
        ck_assert(ea[k].i == eb[k].i && ea[k].kind == eb[k].kind && ea[k].t == eb[k].t &&
                  ea[k].x == eb[k].x && ea[k].vx == eb[k].vx && ea[k].y == eb[k].y &&
                  ea[k].vy == eb[k].vy);
    }
}

/* Step T, save, step T2 more; a fresh simulation loaded from the save and stepped T2 must agree
 * bit for bit. */
static void resume_case(const char *const *sets, int n_sets, bool track, int64_t T, int64_t T2)
{
    gr_scene sc;
    scene_of(&sc, sets, n_sets);
    gr_error err = {0};
    gr_sim *a, *b;
    ck_assert_msg(gr_sim_create(&sc, &a, &err) == GR_OK, "%s", err.message);
    if (track) {
        ck_assert_int_eq(gr_sim_track_contacts(a, &err), GR_OK);
    }
    ck_assert_msg(gr_sim_step(a, T, &err) == GR_OK, "%s", err.message);
    gr_blob blob = {0};
    ck_assert_msg(gr_sim_save_state(a, &blob, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(a, T2, &err) == GR_OK, "%s", err.message);

    ck_assert_msg(gr_sim_create(&sc, &b, &err) == GR_OK, "%s", err.message);
    if (track) {
        ck_assert_int_eq(gr_sim_track_contacts(b, &err), GR_OK);
    }
    gr_blob_reader r;
    gr_blob_reader_init(&r, blob.data, blob.len, "SIM");
    ck_assert_msg(gr_sim_load_state(b, &r, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(b, T2, &err) == GR_OK, "%s", err.message);
    assert_same_sim(a, b);
    if (track) {
        ck_assert_msg(gr_sim_collisions(a) > 0, "the case should have collisions");
    }
    gr_sim_free(a);
    gr_sim_free(b);
    gr_blob_free(&blob);
}

START_TEST(test_sim_state_2d)
{
    /* dense and hot enough for contacts, list rebuilds and events; com mode resets on a step
     * schedule that the split must respect */
    static const char *const sets[] = {"system.dim=2",
                                       "system.N=400",
                                       "system.packing_fraction=0.45",
                                       "model.tangential=tangential_dashpot",
                                       "model.eps_n=0.6",
                                       "model.eps_t=0.6",
                                       "noise.D=1e-7",
                                       "noise.mode=com",
                                       "noise.com_interval=1e-4",
                                       "integrator.dt=1e-6",
                                       "placement.v0=1"};
    int64_t T = quick() ? 300 : 1500;
    resume_case(sets, 11, true, T, T + 37);
    resume_case(sets, 7, false, T, T); /* symmetrised noise, steps_per_contact, no tracking */
}
END_TEST

START_TEST(test_sim_state_1d)
{
    static const char *const sets[] = {
        "system.dim=1",    "system.N=300", "system.reduced_length=0.05", "placement.kind=uniform",
        "model.eps_n=0.5", "noise.D=1e-7", "integrator.dt=1e-6",         "placement.v0=1"};
    int64_t T = quick() ? 300 : 2000;
    resume_case(sets, 8, true, T, T + 11);
}
END_TEST

START_TEST(test_split_steps_equal_one_call)
{
    static const char *const sets[] = {"system.dim=2",
                                       "system.N=300",
                                       "system.packing_fraction=0.45",
                                       "model.tangential=tangential_dashpot",
                                       "noise.D=1e-7",
                                       "noise.mode=com",
                                       "noise.com_interval=5e-5",
                                       "integrator.dt=1e-6",
                                       "placement.v0=1"};
    gr_scene sc;
    scene_of(&sc, sets, 9);
    gr_error err = {0};
    gr_sim *a, *b;
    ck_assert_int_eq(gr_sim_create(&sc, &a, &err), GR_OK);
    ck_assert_int_eq(gr_sim_create(&sc, &b, &err), GR_OK);
    ck_assert_int_eq(gr_sim_step(a, 1000, &err), GR_OK);
    static const int64_t parts[] = {1,   49,  50, 7,
                                    393, 100, 400}; /* sums to 1000; crosses com resets */
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; i++) {
        ck_assert_int_eq(gr_sim_step(b, parts[i], &err), GR_OK);
    }
    assert_same_sim(a, b);
    gr_sim_free(a);
    gr_sim_free(b);
}
END_TEST

START_TEST(test_sim_state_mismatch_refused)
{
    static const char *const s1[] = {"system.dim=2", "system.N=100", "system.packing_fraction=0.3"};
    static const char *const s2[] = {"system.dim=2", "system.N=120", "system.packing_fraction=0.3"};
    gr_scene a_sc, b_sc;
    scene_of(&a_sc, s1, 3);
    scene_of(&b_sc, s2, 3);
    gr_error err = {0};
    gr_sim *a, *b;
    ck_assert_int_eq(gr_sim_create(&a_sc, &a, &err), GR_OK);
    ck_assert_int_eq(gr_sim_create(&b_sc, &b, &err), GR_OK);
    gr_blob blob = {0};
    ck_assert_int_eq(gr_sim_save_state(a, &blob, &err), GR_OK);
    gr_blob_reader r;
    gr_blob_reader_init(&r, blob.data, blob.len, "SIM");
    ck_assert_int_eq(gr_sim_load_state(b, &r, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "100 particles") && strstr(err.message, "120"), "%s",
                  err.message);
    /* every truncation of the state is refused, never read past */
    for (size_t cut = 0; cut < blob.len; cut += 1 + blob.len / 200) {
        gr_sim *c;
        ck_assert_int_eq(gr_sim_create(&a_sc, &c, &err), GR_OK);
        gr_blob_reader_init(&r, blob.data, cut, "SIM");
        ck_assert_int_eq(gr_sim_load_state(c, &r, &err), GR_EINVAL);
        gr_sim_free(c);
    }
    gr_sim_free(a);
    gr_sim_free(b);
    gr_blob_free(&blob);
}
END_TEST

/* ---------- observables ---------- */

/* Sample F frames of a simulation into observer A, save, load into B; F more frames into both:
 * their saves must be byte-equal. */
static void observer_case(const char *const *sets, int n_sets, int F)
{
    gr_scene sc;
    scene_of(&sc, sets, n_sets);
    gr_error err = {0};
    gr_sim *sim;
    gr_observer *a, *b;
    ck_assert_msg(gr_sim_create(&sc, &sim, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_scene_observer(&sc, &a, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_scene_observer(&sc, &b, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_track_contacts(sim, &err), GR_OK);
    gr_blob mid = {0};
    for (int f = 0; f < 2 * F; f++) {
        ck_assert_msg(gr_sim_step(sim, 100, &err) == GR_OK, "%s", err.message);
        gr_particles p = gr_sim_particles(sim);
        int64_t n_ev;
        const gr_contact_event *ev = gr_sim_events(sim, &n_ev);
        for (int k = 0; k < (f < F ? 1 : 2); k++) {
            gr_observer *o = k == 0 ? a : b;
            ck_assert_msg(gr_observer_sample(o, &p, gr_sim_time(sim), &err) == GR_OK, "%s",
                          err.message);
            ck_assert_msg(!n_ev || gr_observer_events(o, ev, n_ev, &err) == GR_OK, "%s",
                          err.message);
        }
        gr_sim_clear_events(sim);
        if (f == F - 1) {
            ck_assert_msg(gr_observer_save(a, &mid, &err) == GR_OK, "%s", err.message);
            ck_assert_msg(gr_observer_load(b, mid.data, mid.len, &err) == GR_OK, "%s", err.message);
            /* a truncated save is refused */
            gr_observer *c;
            ck_assert_int_eq(gr_scene_observer(&sc, &c, &err), GR_OK);
            ck_assert_int_eq(gr_observer_load(c, mid.data, mid.len - 1, &err), GR_EINVAL);
            gr_observer_free(c);
        }
    }
    gr_blob sa = {0}, sb = {0};
    ck_assert_int_eq(gr_observer_save(a, &sa, &err), GR_OK);
    ck_assert_int_eq(gr_observer_save(b, &sb, &err), GR_OK);
    ck_assert_uint_eq(sa.len, sb.len);
    ck_assert_msg(memcmp(sa.data, sb.data, sa.len) == 0, "observer state differs after resume");
    ck_assert_msg(sa.len != mid.len || memcmp(sa.data, mid.data, mid.len) != 0,
                  "the frames after the save changed nothing");
    gr_blob_free(&mid);
    gr_blob_free(&sa);
    gr_blob_free(&sb);
    gr_observer_free(a);
    gr_observer_free(b);
    gr_sim_free(sim);
}

START_TEST(test_observers_2d)
{
    /* F = 4 < pv's 8 reference frames: the save happens while pv still buffers */
    static const char *const sets[] = {
        "system.dim=2",
        "system.N=300",
        "system.packing_fraction=0.45",
        "noise.D=1e-7",
        "integrator.dt=1e-6",
        "placement.v0=1",
        "analysis.observables=moments,freepath,postcollision,sk,pair,pv"};
    observer_case(sets, 7, 4);
    observer_case(sets, 7, quick() ? 9 : 12);
}
END_TEST

START_TEST(test_observers_1d)
{
    static const char *const sets[] = {
        "system.dim=1",
        "system.N=200",
        "system.reduced_length=0.05",
        "placement.kind=uniform",
        "noise.D=1e-7",
        "integrator.dt=1e-6",
        "placement.v0=1",
        "analysis.observables=moments,freepath,postcollision,gaps,pv",
        "analysis.gaps_log=true"};
    observer_case(sets, 9, quick() ? 9 : 12);
}
END_TEST

/* the transport, structure and pressure observables (lag rings, unwrapped positions, cluster
 * counts, per-particle collision times) continue bit for bit */
START_TEST(test_observers_new_2d)
{
    static const char *const sets[] = {
        "system.dim=2",
        "system.N=300",
        "system.packing_fraction=0.45",
        "noise.D=1e-7",
        "integrator.dt=1e-6",
        "placement.v0=1",
        "analysis.observables=msd,vacf,vcorr,clusters,pressure,collisions",
        "analysis.msd_lags=5",
        "analysis.vacf_lags=5"};
    observer_case(sets, 9, quick() ? 9 : 12);
}
END_TEST

START_TEST(test_observers_new_1d)
{
    static const char *const sets[] = {"system.dim=1",
                                       "system.N=200",
                                       "system.reduced_length=0.05",
                                       "placement.kind=uniform",
                                       "noise.D=1e-7",
                                       "integrator.dt=1e-6",
                                       "placement.v0=1",
                                       "analysis.observables=msd,vacf,clusters,pressure,collisions",
                                       "analysis.msd_lags=5"};
    observer_case(sets, 9, quick() ? 9 : 12);
}
END_TEST

/* ---------- the event-driven and hybrid integrators ---------- */

static void assert_same_integrator(gr_sim *a, gr_sim *b)
{
    assert_same_sim(a, b);
    gr_event_counts ea, eb;
    gr_event_stats(a, &ea);
    gr_event_stats(b, &eb);
    ck_assert(memcmp(&ea, &eb, sizeof ea) == 0);
    gr_hybrid_stats ha, hb;
    ck_assert_int_eq(gr_sim_hybrid_stats(a, &ha), gr_sim_hybrid_stats(b, &hb));
    ck_assert(memcmp(&ha, &hb, sizeof ha) == 0);
}

/* resume_case, but the continuation of the loaded copy is cut into uneven calls the way the run
 * driver cuts it (gr_sim_call_steps); every truncation of the saved state is refused. */
static void integrator_case(const char *const *sets, int n_sets, int64_t T, int64_t T2)
{
    gr_scene sc;
    scene_of(&sc, sets, n_sets);
    gr_error err = {0};
    gr_sim *a, *b;
    ck_assert_msg(gr_sim_create(&sc, &a, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_track_contacts(a, &err), GR_OK);
    ck_assert_msg(gr_sim_step(a, T, &err) == GR_OK, "%s", err.message);
    gr_blob blob = {0};
    ck_assert_msg(gr_sim_save_state(a, &blob, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(a, T2, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_collisions(a) > 0, "the case should have collisions");

    ck_assert_msg(gr_sim_create(&sc, &b, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_track_contacts(b, &err), GR_OK);
    gr_blob_reader r;
    gr_blob_reader_init(&r, blob.data, blob.len, "SIM");
    ck_assert_msg(gr_sim_load_state(b, &r, &err) == GR_OK, "%s", err.message);
    static const int64_t wants[] = {1, 49, 50, 7, 393, 100, 17};
    for (int k = 0; gr_sim_steps(b) < T + T2; k++) {
        int64_t n = gr_sim_call_steps(b, wants[k % 7], T + T2 - gr_sim_steps(b));
        ck_assert(n >= 1 && n <= T + T2 - gr_sim_steps(b));
        ck_assert_msg(gr_sim_step(b, n, &err) == GR_OK, "%s", err.message);
    }
    assert_same_integrator(a, b);
    for (size_t cut = 0; cut < blob.len; cut += 1 + blob.len / 300) {
        gr_sim *c;
        ck_assert_int_eq(gr_sim_create(&sc, &c, &err), GR_OK);
        ck_assert_int_eq(gr_sim_track_contacts(c, &err), GR_OK);
        gr_blob_reader_init(&r, blob.data, cut, "SIM");
        ck_assert_int_eq(gr_sim_load_state(c, &r, &err), GR_EINVAL);
        gr_sim_free(c);
    }
    gr_sim_free(a);
    gr_sim_free(b);
    gr_blob_free(&blob);
}

START_TEST(test_event_state)
{
    static const char *const s1[] = {"system.dim=1",
                                     "system.N=100",
                                     "system.reduced_length=0.2",
                                     "placement.kind=uniform",
                                     "model.normal=hard_sphere",
                                     "model.eps_n=0.5",
                                     "noise.D=1e-7",
                                     "integrator.kind=event",
                                     "integrator.kick_interval=1e-4",
                                     "placement.v0=1"};
    integrator_case(s1, 10, quick() ? 3001 : 20001, quick() ? 3000 : 20000);
    /* 2D with cells (crossings), kicks instead of exact free flight, com resets */
    static const char *const s2[] = {"system.dim=2",
                                     "system.N=200",
                                     "system.packing_fraction=0.3",
                                     "model.normal=hard_sphere",
                                     "model.eps_n=0.6",
                                     "model.eps_t=0.8",
                                     "noise.D=1e-7",
                                     "noise.mode=com",
                                     "noise.com_interval=3e-4",
                                     "integrator.kind=event",
                                     "integrator.kick_interval=1e-4",
                                     "integrator.free_flight=kicks",
                                     "placement.v0=1"};
    integrator_case(s2, 13, quick() ? 1001 : 5001, quick() ? 1000 : 5000);
}
END_TEST

/* A call interrupted by a stop request keeps the events it did; a checkpoint taken then and
 * resumed with gr_sim_call_steps (which widens the next call to what is owed) continues exactly. */
START_TEST(test_event_stop_then_resume)
{
    static const char *const sets[] = {"system.dim=2",
                                       "system.N=200",
                                       "system.packing_fraction=0.35",
                                       "model.normal=hard_sphere",
                                       "model.eps_n=0.6",
                                       "noise.D=1e-7",
                                       "integrator.kind=event",
                                       "integrator.kick_interval=1e-4",
                                       "placement.v0=1"};
    gr_scene sc;
    scene_of(&sc, sets, 9);
    gr_error err = {0};
    gr_sim *a, *b, *c;
    ck_assert_int_eq(gr_sim_create(&sc, &c, &err), GR_OK);
    int64_t big = 0; /* the reference: steps until more than 6000 events */
    for (gr_event_counts k = {0}; k.collisions + k.invalid < 6000; gr_event_stats(c, &k)) {
        ck_assert_msg(gr_sim_step(c, 500, &err) == GR_OK, "%s", err.message);
        big += 500;
    }
    ck_assert_int_eq(gr_sim_create(&sc, &a, &err), GR_OK);
    volatile sig_atomic_t stop = 1;
    gr_event_set_stop(a, &stop);
    ck_assert_int_eq(gr_sim_step(a, big, &err), GR_OK);
    ck_assert_int_eq(gr_sim_steps(a), 0); /* stopped after GR_EV_POLL events */
    ck_assert_int_eq(gr_event_owed_steps(a), big);
    gr_blob blob = {0};
    ck_assert_msg(gr_sim_save_state(a, &blob, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_create(&sc, &b, &err), GR_OK);
    gr_blob_reader r;
    gr_blob_reader_init(&r, blob.data, blob.len, "SIM");
    ck_assert_msg(gr_sim_load_state(b, &r, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_call_steps(b, 7, big), big); /* not 7: the events are past step 7 */
    ck_assert_msg(gr_sim_step(b, gr_sim_call_steps(b, 7, big), &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_event_owed_steps(b), 0);
    assert_same_integrator(b, c);
    gr_sim_free(a);
    gr_sim_free(b);
    gr_sim_free(c);
    gr_blob_free(&blob);
}
END_TEST

START_TEST(test_hybrid_state)
{
    static const char *const s1[] = {
        "system.dim=1",           "system.N=200",       "system.reduced_length=0.2",
        "placement.kind=uniform", "model.eps_n=0.5",    "noise.D=1e-7",
        "integrator.kind=hybrid", "integrator.dt=1e-6", "integrator.kick_interval=3e-5",
        "placement.v0=1"};
    integrator_case(s1, 10, quick() ? 1013 : 5013, quick() ? 1000 : 5000);
    static const char *const s2[] = {"system.dim=2",
                                     "system.N=200",
                                     "system.packing_fraction=0.35",
                                     "model.eps_n=0.6",
                                     "noise.D=1e-7",
                                     "noise.mode=com",
                                     "noise.com_interval=1e-4",
                                     "integrator.kind=hybrid",
                                     "integrator.dt=1e-6",
                                     "integrator.kick_interval=2e-5",
                                     "placement.v0=1"};
    integrator_case(s2, 11, quick() ? 507 : 2007, quick() ? 500 : 2000);
    static const char *const s3[] = {"system.dim=3",
                                     "system.N=216",
                                     "system.packing_fraction=0.25",
                                     "model.eps_n=0.6",
                                     "noise.D=1e-7",
                                     "integrator.kind=hybrid",
                                     "integrator.dt=1e-6",
                                     "integrator.kick_interval=2e-5",
                                     "placement.v0=1"};
    integrator_case(s3, 9, quick() ? 507 : 2007, quick() ? 500 : 2000);
    /* rotating discs with sliding friction: the spins restart exactly too */
    static const char *const s4[] = {"system.dim=2",
                                     "system.N=200",
                                     "system.packing_fraction=0.35",
                                     "model.eps_n=0.6",
                                     "model.rotation=true",
                                     "model.tangential=sliding_friction",
                                     "model.mu=0.3",
                                     "noise.D=1e-7",
                                     "integrator.kind=hybrid",
                                     "integrator.dt=1e-6",
                                     "integrator.kick_interval=2e-5",
                                     "placement.v0=1"};
    integrator_case(s4, 12, quick() ? 507 : 2007, quick() ? 500 : 2000);
    /* s2 with a mixture of two sizes and masses (docs/hybrid.md, "Mixtures"), rotating with
     * sliding friction: the restart rebuilds the lists, so the pairs' owners may change */
    const char *s5[16];
    memcpy(s5, s2, sizeof s2);
    s5[11] = "species.radius=1e-3, 2e-3";
    s5[12] = "species.mass=1.5707963e-5, 6.2831853e-5";
    s5[13] = "model.rotation=true";
    s5[14] = "model.tangential=sliding_friction";
    s5[15] = "model.mu=0.3";
    integrator_case(s5, 16, quick() ? 507 : 2007, quick() ? 500 : 2000);
}
END_TEST

/* Every registered integrator (granule/integrator.h), picked up from the registry without editing
 * this test: it is documented, it saves and restores its state exactly, a run split into the calls
 * gr_sim_call_steps allows equals one call, truncated states are refused, and the events hook
 * reports events where there is one. A scene per integrator: instantaneous ones get the
 * hard_sphere rule, the others the spring-dashpot; 2D, contacts and noise. */
START_TEST(test_every_registered_integrator)
{
    int n = 0;
    for (int i = 0; gr_integrators[i]; i++, n++) {
        const gr_integrator_type *t = gr_integrators[i];
        ck_assert_msg(t->name && *t->name && t->summary && *t->summary && t->step,
                      "integrator %d is incomplete", i);
        ck_assert_ptr_eq(gr_integrator_find(t->name), t);
        char kind[64];
        snprintf(kind, sizeof kind, "integrator.kind=%s", t->name);
        const char *sets[] = {"system.dim=2",
                              "system.N=200",
                              "system.packing_fraction=0.3",
                              "model.eps_n=0.6",
                              "noise.D=1e-7",
                              "placement.v0=1",
                              "integrator.kick_interval=2e-5",
                              kind,
                              t->instantaneous ? "model.normal=hard_sphere" : "integrator.dt=1e-6"};
        integrator_case(sets, 9, quick() ? 1001 : 3001, quick() ? 1000 : 3000);
        gr_scene sc;
        scene_of(&sc, sets, 9);
        gr_sim *sim;
        gr_error err = {0};
        ck_assert_msg(gr_sim_create(&sc, &sim, &err) == GR_OK, "%s", err.message);
        ck_assert_ptr_eq(gr_sim_integrator(sim), t);
        ck_assert_int_eq(gr_sim_checkpointable(sim, &err), GR_OK);
        ck_assert_msg(gr_sim_step(sim, 200, &err) == GR_OK, "%s", err.message);
        ck_assert_int_eq(gr_sim_steps(sim), 200);
        ck_assert_msg((gr_sim_events_processed(sim) > 0) == (t->events != NULL), "%s: events %lld",
                      t->name, (long long)gr_sim_events_processed(sim));
        gr_sim_free(sim);
    }
    ck_assert_int_ge(n, 3); /* verlet, event, hybrid at least */
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("checkpoint");
    TCase *t = tcase_create("checkpoint");
    tcase_set_timeout(t, 600);
    tcase_add_test(t, test_format_round_trip);
    tcase_add_test(t, test_scene_text_older_checkpoint);
    tcase_add_test(t, test_format_truncation_and_corruption);
    tcase_add_test(t, test_blob_reader_bounds);
    tcase_add_test(t, test_sim_state_2d);
    tcase_add_test(t, test_sim_state_1d);
    tcase_add_test(t, test_split_steps_equal_one_call);
    tcase_add_test(t, test_sim_state_mismatch_refused);
    tcase_add_test(t, test_every_registered_integrator);
    tcase_add_test(t, test_observers_2d);
    tcase_add_test(t, test_observers_1d);
    tcase_add_test(t, test_observers_new_2d);
    tcase_add_test(t, test_observers_new_1d);
    tcase_add_test(t, test_event_state);
    tcase_add_test(t, test_event_stop_then_resume);
    tcase_add_test(t, test_hybrid_state);
    suite_add_tcase(s, t);
    return s;
}

int main(void) { return gr_test_run(suite()); }
