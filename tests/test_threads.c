/* Threads (docs/performance.md, "Threads"): a trajectory is bit-identical for any thread count
 * and any input order of the particles.
 *
 * Thread count: the same scene is stepped with 1, 2 and 3 OpenMP threads and the complete state
 * (positions, velocities, energy ledger, collision count, contact events) is hashed; the hashes
 * must be equal bit for bit. The 2D scenes have 1500 particles (2500 for three threads), i.e. two
 * (three) blocks of GR_BLOCK, so the threads really split the particles, the pair list has
 * "cross" pairs (checked), and the noise and the reductions are drawn and summed in pieces. Laws: spring-dashpot with
 * tangential dashpot and symmetrised noise (the 2D RFM), and clamped sliding friction with com
 * noise; and the 1D ring (which runs on one thread; its hash must not change either).
 *
 * Neighbour list: rebuilt on 1, 2 and 3 threads, the same entries.
 *
 * Observables: S(k) (gridding) and g(R) give the same numbers for 1 and 2 threads.
 *
 * Particle order: the placed state (random velocities) is given to gr_sim_create_canonical as it
 * is and shuffled; both runs must have the same hash after the steps (1 and 2 threads).
 *
 * GRANULE_TEST_QUICK=1 (ASan builds) cuts the steps to 1000. */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "core/sim_internal.h"
#include "granule/granule.h"
#include "granule_config.h"
#include "analysis/sk.h"
#include "granule/observe.h"
#include "check_main.h"
#include "test_env.h"

extern const gr_observable_type gr_obs_pair; /* src/analysis/obs_pair.c */

static int64_t steps_full(void) { return env_flag("GRANULE_TEST_QUICK") ? 1000 : 10000; }

static void set_threads(int t) { gr_set_threads(t); }

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* Hash of everything a run produces: state, ledger, counters, contact events. */
static uint64_t state_hash(gr_sim *s)
{
    gr_particles p = gr_sim_particles(s);
    uint64_t h = 1469598103934665603ull;
    h = fnv(h, p.x, sizeof(double) * (size_t)p.n);
    h = fnv(h, p.vx, sizeof(double) * (size_t)p.n);
    if (p.dim >= 2) {
        h = fnv(h, p.y, sizeof(double) * (size_t)p.n);
        h = fnv(h, p.vy, sizeof(double) * (size_t)p.n);
    }
    if (p.dim == 3) {
        h = fnv(h, p.z, sizeof(double) * (size_t)p.n);
        h = fnv(h, p.vz, sizeof(double) * (size_t)p.n);
    }
    if (s->omega) {
        h = fnv(h, s->omega, sizeof(double) * (size_t)s->n);
    }
    gr_ledger l = gr_sim_ledger(s);
    double led[8] = {l.kinetic,
                     l.elastic,
                     l.initial,
                     l.injected,
                     l.dissipated_normal,
                     l.dissipated_tangential,
                     l.dissipated_friction,
                     l.removed_com};
    h = fnv(h, led, sizeof led);
    int64_t cnt[3] = {gr_sim_collisions(s), gr_sim_rebuilds(s), gr_sim_steps(s)};
    h = fnv(h, cnt, sizeof cnt);
    int64_t ne = 0;
    const gr_contact_event *ev = gr_sim_events(s, &ne);
    h = fnv(h, &ne, sizeof ne);
    if (ne > 0) {
        h = fnv(h, ev, sizeof *ev * (size_t)ne);
    }
    return h;
}

static void load_scene(gr_scene *sc, const char *file, const char **sets, int nsets)
{
    char path[4096];
    const char *root = getenv("GRANULE_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/docs/scenes/%s", root ? root : GR_SOURCE_DIR, file);
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(sc, path, sets, nsets, &err) == GR_OK, "%s", err.message);
}

/* Create from the scene's placement, track contacts, step with t threads; returns the hash. */
static uint64_t run_placed(const gr_scene *sc, int threads, int64_t steps, int *cross)
{
    gr_sim *s;
    gr_error err = {0};
    set_threads(threads);
    ck_assert_msg(gr_sim_create(sc, &s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_track_contacts(s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    if (cross) {
        *cross = s->par_threads > 1 ? s->cross_start[s->par_threads] : 0;
    }
    uint64_t h = state_hash(s);
    if (env_flag("GRANULE_TEST_VERBOSE")) {
        fprintf(stderr,
                "threads %d: %lld steps, %lld collisions, %lld events, hash %016llx, cross pairs "
                "%d of %d\n",
                threads, (long long)steps, (long long)gr_sim_collisions(s), (long long)s->n_events,
                (unsigned long long)h, s->par_threads > 1 ? s->cross_start[s->par_threads] : 0,
                s->dim == 2 ? s->nl_start[s->n] : 0);
    }
    ck_assert_msg(gr_sim_collisions(s) > 100, "too few collisions (%lld) for a meaningful test",
                  (long long)gr_sim_collisions(s));
    gr_sim_free(s);
    set_threads(1);
    return h;
}

static const char *rfm2d_sets[] = {"system.N=1500", "system.L=0.13", "placement.v0=0.5",
                                   "noise.D=1e-6"};
static const char *rfm2d_sets3[] = {"system.N=2500", "system.L=0.17", "placement.v0=0.5",
                                    "noise.D=1e-6"};

START_TEST(test_threads_rfm2d)
{
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", rfm2d_sets, 4);
    int cross2 = 0, cross3 = 0;
    uint64_t h1 = run_placed(&sc, 1, steps_full(), NULL);
    uint64_t h2 = run_placed(&sc, 2, steps_full(), &cross2);
#ifdef _OPENMP
    ck_assert_msg(cross2 > 0, "two threads did not split the pair list (no cross pairs)");
#endif
    ck_assert_msg(h1 == h2, "1 and 2 threads differ after %lld steps: %016llx vs %016llx",
                  (long long)steps_full(), (unsigned long long)h1, (unsigned long long)h2);
    /* three threads and three blocks: another partition (short: 2 cores may be busy) */
    load_scene(&sc, "rfm-2d.ini", rfm2d_sets3, 4);
    uint64_t s1 = run_placed(&sc, 1, 500, NULL), s3 = run_placed(&sc, 3, 500, &cross3);
#ifdef _OPENMP
    ck_assert_msg(cross3 > 0, "three threads did not split the pair list (no cross pairs)");
#endif
    ck_assert_msg(s1 == s3, "1 and 3 threads differ: %016llx vs %016llx", (unsigned long long)s1,
                  (unsigned long long)s3);
}
END_TEST

/* The neighbour list rebuilt on 1, 2 and 3 threads (rows built in pieces, then joined): the same
 * offsets, pairs and contact flags, entry by entry. */
START_TEST(test_threads_list)
{
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", rfm2d_sets3, 4);
    gr_sim *s;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&sc, &s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(s, 300, &err) == GR_OK, "%s", err.message); /* moved, some contacts */
    int64_t pairs[4] = {0};
    int *start[4] = {NULL}, *js[4] = {NULL};
    uint8_t *touch[4] = {NULL};
    for (int t = 1; t <= 3; t++) {
        set_threads(t);
        ck_assert_msg(gr_neighbours_build(s, &err) == GR_OK, "%s", err.message);
        pairs[t] = s->nl_start[s->n];
        start[t] = malloc(sizeof(int) * ((size_t)s->n + 1));
        js[t] = malloc(sizeof(int) * (size_t)pairs[t]);
        touch[t] = malloc((size_t)pairs[t]);
        memcpy(start[t], s->nl_start, sizeof(int) * ((size_t)s->n + 1));
        memcpy(js[t], s->nl_j, sizeof(int) * (size_t)pairs[t]);
        memcpy(touch[t], s->nl_contact, (size_t)pairs[t]);
    }
    set_threads(1);
    ck_assert_msg(pairs[1] > 2 * s->n, "too few pairs (%lld) for a meaningful test",
                  (long long)pairs[1]);
    int touching = 0;
    for (int64_t p = 0; p < pairs[1]; p++) {
        touching += touch[1][p];
    }
    ck_assert_msg(touching > 0, "no pair in contact: the contact flags are not tested");
    for (int t = 2; t <= 3; t++) {
        ck_assert_msg(pairs[t] == pairs[1], "%d threads: %lld pairs, 1 thread: %lld", t,
                      (long long)pairs[t], (long long)pairs[1]);
        ck_assert_msg(memcmp(start[t], start[1], sizeof(int) * ((size_t)s->n + 1)) == 0,
                      "%d threads: row offsets differ", t);
        ck_assert_msg(memcmp(js[t], js[1], sizeof(int) * (size_t)pairs[1]) == 0,
                      "%d threads: pairs differ", t);
        ck_assert_msg(memcmp(touch[t], touch[1], (size_t)pairs[1]) == 0,
                      "%d threads: contact flags differ", t);
    }
    for (int t = 1; t <= 3; t++) {
        free(start[t]);
        free(js[t]);
        free(touch[t]);
    }
    gr_sim_free(s);
}
END_TEST

START_TEST(test_threads_friction_com)
{
    const char *sets[] = {"system.N=1500", "system.L=0.13",   "placement.v0=0.5",
                          "noise.D=1e-6",  "noise.mode=com",  "model.tangential=sliding_friction",
                          "model.mu=0.5",  "model.clamp=true"};
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", sets, 8);
    const int64_t n = steps_full() / 4;
    uint64_t h1 = run_placed(&sc, 1, n, NULL), h2 = run_placed(&sc, 2, n, NULL);
    ck_assert_msg(h1 == h2, "friction/com: 1 and 2 threads differ: %016llx vs %016llx",
                  (unsigned long long)h1, (unsigned long long)h2);
}
END_TEST

START_TEST(test_threads_1d)
{
    const char *sets[] = {"system.N=2000", "system.reduced_length=0.1", "placement.v0=1"};
    gr_scene sc;
    load_scene(&sc, "rfm-1d.ini", sets, 3);
    uint64_t h1 = run_placed(&sc, 1, steps_full(), NULL),
             h2 = run_placed(&sc, 2, steps_full(), NULL);
    ck_assert_msg(h1 == h2, "1D: 1 and 2 threads differ: %016llx vs %016llx",
                  (unsigned long long)h1, (unsigned long long)h2);
}
END_TEST

/* The state (positions, velocities) of the scene after `steps`, in the simulation's order. */
static void melted_state(const gr_scene *sc, int64_t steps, double **st, int *n)
{
    gr_sim *s;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(sc, &s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    gr_particles p = gr_sim_particles(s);
    *n = p.n;
    *st = malloc(sizeof(double) * 4 * (size_t)p.n);
    for (int i = 0; i < p.n; i++) {
        (*st)[i] = p.x[i];
        (*st)[p.n + i] = p.dim == 2 ? p.y[i] : 0.0;
        (*st)[2 * p.n + i] = p.vx[i];
        (*st)[3 * p.n + i] = p.dim == 2 ? p.vy[i] : 0.0;
    }
    gr_sim_free(s);
}

static uint64_t run_state(const gr_scene *sc, const double *st, int n, const int *perm, int threads,
                          int64_t steps)
{
    double *b = malloc(sizeof(double) * 4 * (size_t)n);
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++) {
            b[c * n + i] = st[c * n + perm[i]];
        }
    }
    gr_sim *s;
    gr_error err = {0};
    set_threads(threads);
    ck_assert_msg(gr_sim_create_canonical(sc, n, b, b + n, b + 2 * n, b + 3 * n, &s, &err) == GR_OK,
                  "%s", err.message);
    ck_assert_msg(gr_sim_step(s, steps, &err) == GR_OK, "%s", err.message);
    uint64_t h = state_hash(s);
    gr_sim_free(s);
    free(b);
    set_threads(1);
    return h;
}

static void check_order(const char *file, const char **sets, int nsets, int64_t steps)
{
    gr_scene sc;
    load_scene(&sc, file, sets, nsets);
    double *st;
    int n;
    melted_state(&sc, 0, &st, &n); /* the placement: an accepted state must not overlap */
    int *id = malloc(sizeof(int) * (size_t)n), *sh = malloc(sizeof(int) * (size_t)n);
    uint64_t r = 12345;
    for (int i = 0; i < n; i++) {
        id[i] = sh[i] = i;
    }
    for (int i = n - 1; i > 0; i--) { /* Fisher-Yates with a fixed LCG */
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        int j = (int)((r >> 33) % (uint64_t)(i + 1));
        int t = sh[i];
        sh[i] = sh[j];
        sh[j] = t;
    }
    uint64_t a = run_state(&sc, st, n, id, 1, steps), b = run_state(&sc, st, n, sh, 1, steps);
    ck_assert_msg(a == b, "%s: shuffled input gives another trajectory: %016llx vs %016llx", file,
                  (unsigned long long)a, (unsigned long long)b);
    uint64_t c = run_state(&sc, st, n, sh, 2, steps);
    ck_assert_msg(a == c, "%s: shuffled input on 2 threads differs: %016llx vs %016llx", file,
                  (unsigned long long)a, (unsigned long long)c);
    free(id);
    free(sh);
    free(st);
}

START_TEST(test_order_2d) { check_order("rfm-2d.ini", rfm2d_sets, 4, steps_full() / 2); }
END_TEST

START_TEST(test_order_1d)
{
    const char *sets[] = {"system.N=1000"};
    check_order("rfm-1d.ini", sets, 1, steps_full());
}
END_TEST

/* [noise] precision = single: the float normals are the same pure function of (step, id) on 1,
 * 2 and 3 threads (blocks of 1024 ids = one group of the f32 generator, or three partial ones),
 * and in any particle order; and they are not the double path's. */
START_TEST(test_threads_single)
{
    const char *sets[] = {"system.N=1500", "system.L=0.13", "placement.v0=0.5", "noise.D=1e-6",
                          "noise.precision=single"};
    gr_scene sc;
    load_scene(&sc, "rfm-2d.ini", sets, 5);
    const int64_t n = steps_full() / 4;
    uint64_t h1 = run_placed(&sc, 1, n, NULL), h2 = run_placed(&sc, 2, n, NULL),
             h3 = run_placed(&sc, 3, n, NULL);
    ck_assert_msg(h1 == h2 && h1 == h3, "single: 1, 2, 3 threads differ: %016llx %016llx %016llx",
                  (unsigned long long)h1, (unsigned long long)h2, (unsigned long long)h3);
    load_scene(&sc, "rfm-2d.ini", sets, 4);
    ck_assert_msg(run_placed(&sc, 1, n, NULL) != h1, "single gives the double path's trajectory");
    check_order("rfm-2d.ini", sets, 5, n);
    const char *sets1[] = {"system.N=1000", "noise.precision=single"};
    check_order("rfm-1d.ini", sets1, 2, steps_full());
}
END_TEST

/* The same in 3D (spheres): the third component is drawn from ids of its own (step.c,
 * normals_f32_3d), so the run is the same on 1, 2 and 3 threads (two blocks of 1024 ids), and not
 * the double path's. And the three components are independent unit normals: free spheres (no
 * contacts) kicked for 200 steps have velocity components of equal variance and no correlation
 * between them (a z drawn from x's counters would give corr(v_x, v_z) = 1). */
START_TEST(test_threads_single_3d)
{
    const char *sets[] = {"system.N=1500", "system.packing_fraction=0.3", "placement.v0=2",
                          "noise.D=1e-6", "noise.precision=single"};
    gr_scene sc;
    load_scene(&sc, "rfm-3d.ini", sets, 5);
    const int64_t n = 1000; /* the sanitizer pass too: 100 steps hold no collision */
    uint64_t h1 = run_placed(&sc, 1, n, NULL), h2 = run_placed(&sc, 2, n, NULL),
             h3 = run_placed(&sc, 3, n, NULL);
    ck_assert_msg(h1 == h2 && h1 == h3,
                  "single 3D: 1, 2, 3 threads differ: %016llx %016llx %016llx",
                  (unsigned long long)h1, (unsigned long long)h2, (unsigned long long)h3);
    load_scene(&sc, "rfm-3d.ini", sets, 4);
    ck_assert_msg(run_placed(&sc, 1, n, NULL) != h1, "single gives the double path's trajectory");
    const char *free_sets[] = {"system.N=4000",  "system.radius=1e-8", "system.L=1",
                               "placement.v0=0", "noise.D=1e-8",       "noise.precision=single"};
    load_scene(&sc, "rfm-3d.ini", free_sets, 6);
    gr_sim *s;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&sc, &s, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(gr_sim_step(s, 200, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(gr_sim_collisions(s), 0);
    gr_particles p = gr_sim_particles(s);
    const double *v[3] = {p.vx, p.vy, p.vz};
    double m2[3][3] = {{0}};
    for (int i = 0; i < p.n; i++) {
        for (int a = 0; a < 3; a++) {
            for (int b = 0; b < 3; b++) {
                m2[a][b] += v[a][i] * v[b][i] / p.n;
            }
        }
    }
    /* each v_c is a sum of 200 kicks (symmetrised: their mean over the spheres subtracted):
     * variance 200 (sqrt(2 D dt) / M)^2 (1 - 1/N) (1 +- sqrt(2 / N)) */
    const double amp = sqrt(2.0 * 1e-8 * gr_sim_dt(s)) / s->mass,
                 var = 200.0 * amp * amp * (1.0 - 1.0 / p.n);
    for (int a = 0; a < 3; a++) {
        ck_assert_msg(fabs(m2[a][a] / var - 1.0) < 5.0 * sqrt(2.0 / p.n), "var %d: %g of %g", a,
                      m2[a][a], var);
        for (int b = a + 1; b < 3; b++) {
            const double r = m2[a][b] / sqrt(m2[a][a] * m2[b][b]);
            ck_assert_msg(fabs(r) < 5.0 / sqrt((double)p.n), "corr(%d, %d) = %g", a, b, r);
        }
    }
    gr_sim_free(s);
}
END_TEST

/* S(k) by gridding (the default) and g(R): the same numbers for 1 and 2 threads, bit for bit, for
 * 20000 random points (above the 4096 the observables need before they use threads). */
static double *random_points(int n, uint64_t seed)
{
    double *p = malloc(sizeof(double) * 2 * (size_t)n);
    for (int i = 0; i < 2 * n; i++) {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        p[i] = (double)(seed >> 11) * 0x1.0p-53;
    }
    return p;
}

START_TEST(test_threads_sk)
{
    const int n = 20000;
    double *p = random_points(n, 7);
    gr_sk_plan *pl;
    gr_error err = {0};
    ck_assert_msg(gr_sk_plan_create(1.0, 60.0, GR_SK_MSP_DEFAULT, &pl, &err) == GR_OK, "%s",
                  err.message);
    const int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), NULL, NULL, NULL);
    double *s1 = malloc(sizeof(double) * (size_t)nv), *s2 = malloc(sizeof(double) * (size_t)nv);
    set_threads(1);
    ck_assert_msg(gr_sk_compute(pl, GR_SK_GRIDDING, n, p, p + n, s1, &err) == GR_OK, "%s",
                  err.message);
    set_threads(2);
    ck_assert_msg(gr_sk_compute(pl, GR_SK_GRIDDING, n, p, p + n, s2, &err) == GR_OK, "%s",
                  err.message);
    set_threads(1);
    for (int v = 0; v < nv; v++) {
        ck_assert_msg(memcmp(&s1[v], &s2[v], sizeof(double)) == 0,
                      "S(k) vector %d: %.17g (1 thread) vs %.17g (2)", v, s1[v], s2[v]);
    }
    free(s1);
    free(s2);
    free(p);
    gr_sk_plan_free(pl);
}
END_TEST

/* pair.csv of the g(R) observable after three frames with t threads, as one string */
static char *pair_csv(int t, const double *const *frames, int n, double L)
{
    gr_scene sc;
    gr_scene_default(&sc);
    sc.dim = 2;
    sc.N = n;
    sc.L = L;
    sc.radius = 0.002;
    snprintf(sc.source, sizeof sc.source, "test_threads");
    void *st = NULL;
    gr_error err = {0};
    set_threads(t);
    ck_assert_msg(gr_scene_observable(&gr_obs_pair, &sc, &st, &err) == GR_OK, "%s", err.message);
    for (int f = 0; f < 3; f++) {
        gr_particles p = {.n = n,
                          .dim = 2,
                          .L = L,
                          .radius = sc.radius,
                          .mass = 1.0,
                          .x = frames[f],
                          .y = frames[f] + n};
        ck_assert_msg(gr_obs_pair.sample(st, &p, 0.0, &err) == GR_OK, "%s", err.message);
    }
    set_threads(1);
    char dir[] = "/tmp/test_threads_XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    cJSON *summary = cJSON_CreateObject();
    gr_output out = {.dir = dir,
                     .source = sc.source,
                     .seed = sc.seed,
                     .scene_hash = 1,
                     .summary = summary,
                     .plots = false};
    ck_assert_msg(gr_obs_pair.finish(st, &out, &err) == GR_OK, "%s", err.message);
    gr_observable_free(st);
    cJSON_Delete(summary);
    char path[256];
    snprintf(path, sizeof path, "%s/pair.csv", dir);
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    rewind(f);
    char *text = calloc((size_t)len + 1, 1);
    ck_assert_int_eq((long)fread(text, 1, (size_t)len, f), len);
    fclose(f);
    remove(path);
    rmdir(dir);
    return text;
}

START_TEST(test_threads_pair)
{
    const int n = 20000;
    double *fr[3];
    for (int f = 0; f < 3; f++) {
        fr[f] = random_points(n, 11 + (uint64_t)f);
    }
    const double *frames[3] = {fr[0], fr[1], fr[2]};
    char *a = pair_csv(1, frames, n, 1.0), *b = pair_csv(2, frames, n, 1.0);
    ck_assert_msg(strlen(a) > 100 && strcmp(a, b) == 0, "pair.csv differs between 1 and 2 threads");
    free(a);
    free(b);
    for (int f = 0; f < 3; f++) {
        free(fr[f]);
    }
}
END_TEST

/* rotation (the torques of cross pairs, evaluated by the thread that receives them): 1 and 2
 * threads, bit for bit, for both contact-point tangential laws and the rolling law */
START_TEST(test_threads_rotation)
{
    static const char *laws[][3] = {
        {"model.tangential=tangential_dashpot", "model.eps_t=0.3", "model.rolling=none"},
        {"model.tangential=sliding_friction", "model.mu=0.4", "model.rolling=none"},
        {"model.tangential=sliding_friction", "model.mu=0.4", "model.rolling=rolling_friction"}};
    for (int k = 0; k < 3; k++) {
        const char *sets[] = {
            "system.N=1500",       "system.L=0.13", "placement.v0=0.5", "noise.D=1e-6",
            "model.rotation=true", laws[k][0],      laws[k][1],         laws[k][2]};
        gr_scene sc;
        load_scene(&sc, "rfm-2d.ini", sets, 8);
        int cross2 = 0;
        const int64_t steps = steps_full() / 2;
        uint64_t h1 = run_placed(&sc, 1, steps, NULL);
        uint64_t h2 = run_placed(&sc, 2, steps, &cross2);
#ifdef _OPENMP
        ck_assert_msg(cross2 > 0, "two threads did not split the pair list (no cross pairs)");
#endif
        ck_assert_msg(h1 == h2, "%s with rotation: 1 and 2 threads differ: %016llx vs %016llx",
                      laws[k][0], (unsigned long long)h1, (unsigned long long)h2);
    }
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("threads");
    TCase *tc = tcase_create("threads");
    tcase_set_timeout(tc, 600);
    tcase_add_test(tc, test_threads_rfm2d);
    tcase_add_test(tc, test_threads_list);
    tcase_add_test(tc, test_threads_friction_com);
    tcase_add_test(tc, test_threads_rotation);
    tcase_add_test(tc, test_threads_1d);
    tcase_add_test(tc, test_threads_single);
    tcase_add_test(tc, test_threads_single_3d);
    tcase_add_test(tc, test_order_2d);
    tcase_add_test(tc, test_order_1d);
    tcase_add_test(tc, test_threads_sk);
    tcase_add_test(tc, test_threads_pair);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
