/* Golden trajectories of every force-kernel instance the thesis's scenes use (issue 13: the
 * collision models moved into models/NAME.h and the kernels are instantiated from
 * models/list.h; the results had to stay bit for bit what the hand-written kernels gave).
 *
 * Each case loads a scene of docs/scenes/ with overrides, steps it and hashes (FNV-1a, 64 bit)
 * the bytes of the final positions, velocities and energy ledger. The recorded hashes were
 * produced by the kernels before the refactor (commit 3001715, the same test built there) and
 * must not change: a change alters every run's trajectory, so it must be deliberate. Then
 * re-record with GRANULE_GOLDEN_PRINT=1 and say why in the commit. The arithmetic is
 * deterministic (-ffp-contract=off, no fast-math); libm differences between machines could in
 * principle change a hash, which the message then shows.
 *
 * Every case also asserts that contacts happened (the laws were exercised), so a hash cannot
 * pass on a run where nothing collided. */
#include <check.h>
#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/model.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "check_main.h"
#include "test_env.h"

/* a dense, fast 3D gas of 2197 spheres: contacts from the first steps */
#define SPHERES "system.N=2197", "placement.v0=5", "system.packing_fraction=0.35"

typedef struct golden_case {
    const char *scene;        /* file in docs/scenes */
    const char *overrides[8]; /* NULL-terminated */
    int steps;
    uint64_t hash;
} golden_case;

static const golden_case cases[] = {
    {"rfm-2d.ini", {NULL}, 600, UINT64_C(0x3a6820c86bac931d)},
    {"rfm-2d.ini", {"model.clamp=true", NULL}, 600, UINT64_C(0xc0734f240e2c1d7c)},
    /* rotation = false (the default) is the trajectory of the thesis, bit for bit */
    {"rfm-2d.ini", {"model.rotation=false", NULL}, 600, UINT64_C(0x3a6820c86bac931d)},
    {"rfm-2d.ini",
     {"model.tangential=sliding_friction", "model.mu=0.3", "model.rotation=false"},
     600,
     UINT64_C(0x47687f6efa0f884f)},
    {"rfm-2d.ini", {"model.tangential=none", NULL}, 600, UINT64_C(0xf271d1070c2be18e)},
    {"rfm-2d.ini",
     {"model.tangential=none", "model.clamp=true", NULL},
     600,
     UINT64_C(0x751615ea7305399e)},
    {"rfm-2d.ini",
     {"model.tangential=sliding_friction", "model.mu=0.3", NULL},
     600,
     UINT64_C(0x47687f6efa0f884f)},
    {"rfm-2d.ini",
     {"model.tangential=sliding_friction", "model.mu=0.3", "model.clamp=true"},
     600,
     UINT64_C(0xf621db12a9b492be)},
    {"rfm-1d.ini", {NULL}, 4000, UINT64_C(0x51891d9534706687)},
    {"rfm-1d.ini", {"model.clamp=true", NULL}, 4000, UINT64_C(0x84136eb5693cd97f)},
    {"cooling-2d.ini", {NULL}, 6000, UINT64_C(0x29bad14aa1f79508)},
    {"rfm-1d-event.ini", {NULL}, 40000, UINT64_C(0x8fa124c064adec2f)},
    {"rfm-2d-event.ini", {NULL}, 300, UINT64_C(0x76d74f24262589c8)},
    /* spheres (recorded at 977d3c7, after the 3D step's blocks): the normal law's instance, the
     * dashpots' instance, every law with rotation and the history spring, and a bed on a
     * vibrating floor; three blocks of particles, so the blocked sums count */
    {"rfm-3d.ini", {SPHERES, NULL}, 300, UINT64_C(0x931b325076ea20ff)},
    {"rfm-3d.ini",
     {SPHERES, "model.tangential=tangential_dashpot", "model.eps_t=0.5", NULL},
     300,
     UINT64_C(0x5745ce89bd45d5a3)},
    {"rfm-3d.ini",
     {SPHERES, "model.normal=hertz", "model.tangential=tangential_spring", "model.rotation=true",
      "model.rolling=rolling_friction", NULL},
     300,
     UINT64_C(0x23dc7886ece44c69)},
    {"vibrated-bed-3d.ini", {NULL}, 3000, UINT64_C(0xa3deefd85b29c73e)},
};
enum { N_CASES = sizeof cases / sizeof cases[0] };

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= UINT64_C(0x100000001b3);
    }
    return h;
}

static uint64_t run_case(const golden_case *c, int64_t *collisions, char *kernel, size_t kn)
{
    char path[1024];
    const char *root = getenv("GRANULE_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/docs/scenes/%s", root ? root : ".", c->scene);
    int n_over = 0;
    while (n_over < 8 && c->overrides[n_over]) {
        n_over++;
    }
    gr_scene sc;
    gr_error err = {0};
    int rc = gr_scene_load(&sc, path, c->overrides, n_over, &err);
    ck_assert_msg(rc == GR_OK, "%s: %s", path, err.message);
    gr_sim *sim = NULL;
    rc = gr_sim_create(&sc, &sim, &err);
    ck_assert_msg(rc == GR_OK, "%s: %s", path, err.message);
    rc = gr_sim_step(sim, c->steps, &err);
    ck_assert_msg(rc == GR_OK, "%s: %s", path, err.message);
    gr_particles p = gr_sim_particles(sim);
    const size_t n = (size_t)p.n * sizeof(double);
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    h = fnv(h, p.x, n);
    h = fnv(h, p.vx, n);
    if (p.dim >= 2) {
        h = fnv(h, p.y, n);
        h = fnv(h, p.vy, n);
    }
    if (p.dim == 3) {
        h = fnv(h, p.z, n);
        h = fnv(h, p.vz, n);
        for (int k = 0; k < 3 && p.wx; k++) { /* spin vectors */
            h = fnv(h, (const double *[]){p.wx, p.wy, p.wz}[k], n);
        }
    }
    gr_ledger l = gr_sim_ledger(sim);
    const double led[] = {l.kinetic,
                          l.elastic,
                          l.injected,
                          l.dissipated_normal,
                          l.dissipated_tangential,
                          l.dissipated_friction,
                          l.removed_com};
    h = fnv(h, led, sizeof led);
    *collisions = gr_sim_collisions(sim);
    snprintf(kernel, kn, "%s", gr_sim_kernel(sim));
    gr_sim_free(sim);
    return h;
}

START_TEST(test_golden_trajectory)
{
    const golden_case *c = &cases[_i];
    int64_t collisions = 0;
    char kernel[200];
    uint64_t h = run_case(c, &collisions, kernel, sizeof kernel);
    if (env_flag("GRANULE_GOLDEN_PRINT")) {
        printf("case %d %s: UINT64_C(0x%016" PRIx64 ") %s, %" PRId64 " collisions\n", _i, c->scene,
               h, kernel, collisions);
        return;
    }
    VERBOSE("case %d %s (%s): %" PRId64 " collisions, hash %016" PRIx64 "\n", _i, c->scene, kernel,
            collisions, h);
    ck_assert_msg(collisions > 0,
                  "case %d %s: no collision in %d steps, the laws were not exercised", _i, c->scene,
                  c->steps);
    ck_assert_msg(h == c->hash,
                  "case %d %s (%s): trajectory hash %016" PRIx64 ", recorded %016" PRIx64, _i,
                  c->scene, kernel, h, c->hash);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("kernels_golden");
    TCase *tc = tcase_create("golden");
    tcase_add_loop_test(tc, test_golden_trajectory, 0, N_CASES);
    tcase_set_timeout(tc, 300);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(suite()); }
