/* Helpers of the Check tests that build simulations from scene text (test_driving.c,
 * test_walls.c): load a scene, create and step its simulation, failing the test with the
 * library's message, and compare two simulations' states bit for bit. */
#ifndef GR_TEST_SIM_HELPERS_H
#define GR_TEST_SIM_HELPERS_H

#include <check.h>
#include <math.h>

#include "check_main.h" /* its ck_assert_msg: a passed assertion writes nothing */
#include <stdlib.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/scene.h"

/* The mean of x[0..n) and its standard error, the n block averages taken as independent. */
static inline double mean_se(const double *x, int n, double *se)
{
    double mean = 0.0, var = 0.0;
    for (int b = 0; b < n; b++) {
        mean += x[b];
    }
    mean /= n;
    for (int b = 0; b < n; b++) {
        var += (x[b] - mean) * (x[b] - mean);
    }
    *se = sqrt(var / (n - 1) / n);
    return mean;
}

static inline void load(gr_scene *s, const char *text, const char *const *set, int n_set)
{
    gr_error err = {0};
    int rc = gr_scene_load_buffer(s, "test.ini", text, strlen(text), set, n_set, &err);
    ck_assert_msg(rc == GR_OK, "scene refused: %s", err.message);
}

static inline gr_sim *create(const gr_scene *s)
{
    gr_error err = {0};
    gr_sim *sim = NULL;
    int rc = gr_sim_create(s, &sim, &err);
    ck_assert_msg(rc == GR_OK, "simulation refused: %s", err.message);
    return sim;
}

static inline void step(gr_sim *sim, int64_t n)
{
    gr_error err = {0};
    int rc = gr_sim_step(sim, n, &err);
    ck_assert_msg(rc == GR_OK, "step failed: %s", err.message);
}

/* Positions, velocities and the ledger's accumulated entries the same bit for bit. */
static inline void assert_same_state(const gr_sim *a, const gr_sim *b)
{
    ck_assert_int_eq(a->n, b->n);
    ck_assert(memcmp(a->x, b->x, sizeof(double) * (size_t)a->n) == 0);
    ck_assert(memcmp(a->vx, b->vx, sizeof(double) * (size_t)a->n) == 0);
    if (a->dim >= 2) {
        ck_assert(memcmp(a->y, b->y, sizeof(double) * (size_t)a->n) == 0);
        ck_assert(memcmp(a->vy, b->vy, sizeof(double) * (size_t)a->n) == 0);
    }
    if (a->dim == 3) {
        ck_assert(memcmp(a->z, b->z, sizeof(double) * (size_t)a->n) == 0);
        ck_assert(memcmp(a->vz, b->vz, sizeof(double) * (size_t)a->n) == 0);
    }
    ck_assert(memcmp(&a->injected, &b->injected, sizeof a->injected) == 0);
    ck_assert(memcmp(&a->diss_drag, &b->diss_drag, sizeof a->diss_drag) == 0);
    ck_assert(memcmp(&a->diss_n, &b->diss_n, sizeof a->diss_n) == 0);
    ck_assert(memcmp(&a->elastic, &b->elastic, sizeof a->elastic) == 0);
    ck_assert(memcmp(&a->initial_energy, &b->initial_energy, sizeof a->initial_energy) == 0);
    ck_assert(memcmp(&a->diss_t, &b->diss_t, sizeof a->diss_t) == 0);
    ck_assert(memcmp(&a->diss_f, &b->diss_f, sizeof a->diss_f) == 0);
    if (a->omega) {
        ck_assert(memcmp(a->omega, b->omega, sizeof(double) * (size_t)a->n) == 0);
    }
    if (a->wx) { /* 3D: the other components of the spins */
        ck_assert(memcmp(a->wx, b->wx, sizeof(double) * (size_t)a->n) == 0);
        ck_assert(memcmp(a->wy, b->wy, sizeof(double) * (size_t)a->n) == 0);
    }
    /* walls: the moving wall's work and the impulse each wall took */
    ck_assert(memcmp(&a->wall_work, &b->wall_work, sizeof a->wall_work) == 0);
    ck_assert(memcmp(a->wall_impulse, b->wall_impulse, sizeof a->wall_impulse) == 0);
}

/* The scene's simulation stepped `first` steps on `t0` threads, saved, restored into a new one
 * and continued to `total` on `t1` threads (then back to 1 thread). */
static inline gr_sim *restarted(const gr_scene *s, int64_t total, int64_t first, int t0, int t1)
{
    gr_set_threads(t0);
    gr_sim *b = create(s);
    step(b, first);
    void *data = NULL;
    size_t len = 0;
    gr_error err = {0};
    ck_assert_int_eq(gr_sim_state_save(b, &data, &len, &err), GR_OK);
    gr_sim_free(b);
    gr_set_threads(t1);
    gr_sim *c = create(s);
    ck_assert_msg(gr_sim_state_load(c, data, len, &err) == GR_OK, "%s", err.message);
    free(data);
    step(c, total - first);
    gr_set_threads(1);
    return c;
}

/* Stepping `total` steps of the scene's simulation in one go equals stepping `first`, saving the
 * state into bytes, loading them into a fresh simulation and stepping the rest: bit for bit. */
static inline void assert_restart_exact(const gr_scene *s, int64_t total, int64_t first)
{
    gr_sim *a = create(s);
    step(a, total);
    gr_sim *c = restarted(s, total, first, 1, 1);
    assert_same_state(a, c);
    gr_sim_free(a);
    gr_sim_free(c);
}

/* The scene's simulation stepped `steps` on 1 and on 2 threads: the same run bit for bit. */
static inline void assert_threads_invariant(const gr_scene *s, int64_t steps)
{
    gr_set_threads(1);
    gr_sim *a = create(s);
    step(a, steps);
    gr_set_threads(2);
    gr_sim *b = create(s);
    step(b, steps);
#ifdef _OPENMP
    ck_assert_int_eq(gr_sim_threads(b), 2); /* really on two */
#endif
    gr_set_threads(1);
    assert_same_state(a, b);
    gr_sim_free(a);
    gr_sim_free(b);
}

/* The forces, torques and contact state of the last force evaluation the same bit for bit (the
 * list of a must be b's: same run). */
static inline void assert_same_forces(const gr_sim *a, const gr_sim *b)
{
    const size_t bytes = sizeof(double) * (size_t)a->n;
    const double *fa[] = {a->fx, a->fy,  a->fz,  a->gx, a->gy,  a->gz,
                          a->tq, a->tqx, a->tqy, a->tg, a->tgx, a->tgy};
    const double *fb[] = {b->fx, b->fy,  b->fz,  b->gx, b->gy,  b->gz,
                          b->tq, b->tqx, b->tqy, b->tg, b->tgx, b->tgy};
    for (size_t k = 0; k < sizeof fa / sizeof fa[0]; k++) {
        ck_assert(!fa[k] == !fb[k]);
        ck_assert_msg(!fa[k] || memcmp(fa[k], fb[k], bytes) == 0, "force/torque array %zu differs",
                      k);
    }
    ck_assert_int_eq(a->nl_start[a->n], b->nl_start[b->n]);
    const size_t entries = (size_t)a->nl_start[a->n];
    ck_assert(memcmp(a->nl_contact, b->nl_contact, entries) == 0);
    ck_assert(!a->nl_hist == !b->nl_hist);
    ck_assert(!a->nl_hist || memcmp(a->nl_hist, b->nl_hist,
                                    sizeof(double) * (size_t)(a->dim == 3 ? 3 : 1) * entries) == 0);
    ck_assert(memcmp(&a->last, &b->last, sizeof a->last) == 0);
}

/* The scene stepped `total` steps on 1 thread, on 2 and on 3 (each really on that many, with
 * cross pairs between the threads' particles, across list rebuilds), and restarted at `first`
 * from the bytes saved on 3 threads and continued on 2: the same run bit for bit, forces,
 * torques, history and ledger included. */
static inline void assert_threads_exact(const gr_scene *s, int64_t total, int64_t first)
{
    gr_set_threads(1);
    gr_sim *a = create(s);
    step(a, total);
    ck_assert_msg(a->rebuilds >= 2, "%lld list builds: the test crosses no rebuild",
                  (long long)a->rebuilds);
    ck_assert_msg(a->collisions > 100, "%lld contacts: the test tests nothing",
                  (long long)a->collisions);
    for (int T = 2; T <= 3; T++) {
        gr_set_threads(T);
        gr_sim *b = create(s);
        step(b, total);
#ifdef _OPENMP
        ck_assert_int_eq(gr_sim_threads(b), T); /* really on T */
        ck_assert_int_eq(b->par_threads, T);    /* the threaded kernel ran */
        ck_assert_msg(b->cross_start[T] > 0, "no cross pair between the threads on %d", T);
#endif
        gr_set_threads(1);
        assert_same_state(a, b);
        assert_same_forces(a, b);
        gr_sim_free(b);
    }
    gr_sim *c = restarted(s, total, first, 3, 2);
    assert_same_state(a, c);
    assert_same_forces(a, c);
    gr_sim_free(a);
    gr_sim_free(c);
}

/* A bed left to settle for `settle` s, then the mean normal force on each wall over `window` s
 * (N: walls at 0 and L of x, then of y, then of z; gr_sim_wall_impulse's differences over the window). */
static inline void settled_wall_forces(gr_sim *s, double settle, double window, double f[6])
{
    const double dt = gr_sim_dt(s);
    step(s, (int64_t)(settle / dt));
    double j0[6], j1[6];
    gr_sim_wall_impulse(s, j0);
    const int64_t n = (int64_t)(window / dt);
    step(s, n);
    gr_sim_wall_impulse(s, j1);
    for (int k = 0; k < 6; k++) {
        f[k] = (j1[k] - j0[k]) / (n * dt);
    }
}
#endif
