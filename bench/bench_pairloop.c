/* The 2D pair loop on its own, and what the particle order costs (issue 17; docs/performance.md,
 * "The 2D pair loop").
 *
 *   bench_pairloop SCENE [--set section.key=value ...] [--warmup-steps W] [--evals E]
 *                  [--segments S] [--seg-steps K] [--orders]
 *
 * Advances a 2D scene W steps, then reports the neighbour list it has (listed pairs and
 * overlapping pairs per particle, the share of listed pairs that overlap, row lengths) and two
 * timings in CPU time of this process (CLOCK_PROCESS_CPUTIME_ID: time the process waited for a
 * core is not counted, which is what makes numbers taken on a loaded machine usable):
 *   forces  gr_forces alone, the minimum over 7 repeats of E evaluations of the same state
 *           (ns per particle);
 *   step    whole steps, the minimum over S segments of K steps (ns per particle-step).
 * Minima, not medians: on a shared machine the least disturbed segment is the best estimate of
 * the code's own cost. --orders times the same state in three particle orders, interleaved: as
 * the run has them, randomly shuffled (seed 7) and sorted by cell (row-major cells of side d),
 * each copy with a freshly built neighbour list, to measure what locality is worth (a reordered
 * copy is a timing object only: its noise and contact flags are not those of the run). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/sim_internal.h"
#include "granule/granule.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "bench_util.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Minimum ns per particle of one gr_forces call (7 repeats of evals calls). */
static double time_forces(gr_sim *s, long evals)
{
    gr_force_report r;
    double best = 1e300;
    for (int rep = 0; rep < 7; rep++) {
        const double t0 = cpu_now();
        for (long k = 0; k < evals; k++) {
            gr_forces(s, &r);
        }
        const double t = (cpu_now() - t0) / (double)evals;
        best = t < best ? t : best;
    }
    return best * 1e9 / s->n;
}

/* Minimum ns per particle-step over segments of seg_steps steps; -1 on a failed step. */
static double time_steps(gr_sim *s, long segments, long seg_steps)
{
    gr_error err = {0};
    double best = 1e300;
    for (long k = 0; k < segments; k++) {
        const double t0 = cpu_now();
        if (gr_sim_step(s, seg_steps, &err)) {
            fprintf(stderr, "bench_pairloop: %s\n", err.message);
            return -1.0;
        }
        const double t = (cpu_now() - t0) / (double)seg_steps;
        best = t < best ? t : best;
    }
    return best * 1e9 / s->n;
}

/* The overlapping pairs of the list at s's state (sets the contact flags). */
static int64_t overlapping(gr_sim *s)
{
    gr_force_report r;
    gr_forces(s, &r);
    int64_t touching = 0;
    for (int64_t p = 0; p < s->nl_start[s->n]; p++) {
        touching += s->nl_contact[p];
    }
    return touching;
}

static void list_stats(gr_sim *s)
{
    const int n = s->n;
    const int64_t listed = s->nl_start[n];
    const int64_t touching = overlapping(s);
    int longest = 0;
    for (int i = 0; i < n; i++) {
        const int l = s->nl_start[i + 1] - s->nl_start[i];
        longest = l > longest ? l : longest;
    }
    printf("list: %.3f listed and %.3f overlapping pairs per particle (%.1f %% of the listed "
           "overlap), longest row %d\n",
           (double)listed / n, (double)touching / n,
           listed ? 100.0 * (double)touching / (double)listed : 0.0, longest);
}

/* Copies of s's state in three orders, each a sim of its own with a fresh list. */
static int orders(const gr_scene *sc, gr_sim *s, long evals, long segments, long seg_steps)
{
    const int n = s->n;
    int *perm = malloc(sizeof(int) * (size_t)n), *key = malloc(sizeof(int) * (size_t)n);
    int *sorted = malloc(sizeof(int) * (size_t)n), *count = NULL;
    gr_sim *copy[3] = {NULL, NULL, NULL};
    const char *names[3] = {"as run", "shuffled", "cell order"};
    gr_error err = {0};
    int rc = 1;
    if (!perm || !key || !sorted) {
        goto done;
    }
    /* shuffle (Fisher-Yates, a fixed LCG so the bench is repeatable) */
    uint64_t st = 7;
    for (int i = 0; i < n; i++) {
        perm[i] = i;
    }
    for (int i = n - 1; i > 0; i--) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        const int k = (int)((st >> 33) % (uint64_t)(i + 1));
        const int t = perm[i];
        perm[i] = perm[k];
        perm[k] = t;
    }
    /* cell order of the shuffled particles: counting sort by row-major cell of side >= d */
    const int side = (int)(s->L / s->d) > 0 ? (int)(s->L / s->d) : 1;
    count = calloc((size_t)side * (size_t)side + 1, sizeof(int));
    if (!count) {
        goto done;
    }
    for (int i = 0; i < n; i++) {
        const int cx = (int)(s->x[perm[i]] / s->L * side) % side,
                  cy = (int)(s->y[perm[i]] / s->L * side) % side;
        key[i] = cx + side * cy;
        count[key[i] + 1]++;
    }
    for (int c = 0; c < side * side; c++) {
        count[c + 1] += count[c];
    }
    for (int i = 0; i < n; i++) {
        sorted[count[key[i]]++] = perm[i];
    }
    for (int k = 0; k < 3; k++) {
        if (gr_sim_create(sc, &copy[k], &err)) {
            fprintf(stderr, "bench_pairloop: %s\n", err.message);
            goto done;
        }
        gr_sim *t = copy[k];
        for (int i = 0; i < n; i++) {
            const int from = k == 0 ? i : k == 1 ? perm[i] : sorted[i];
            t->x[i] = s->x[from];
            t->y[i] = s->y[from];
            t->vx[i] = s->vx[from];
            t->vy[i] = s->vy[from];
        }
        if (gr_neighbours_build(t, &err)) {
            fprintf(stderr, "bench_pairloop: %s\n", err.message);
            goto done;
        }
        /* the same configuration in another order: the same contacts, or the copy is wrong */
        if (overlapping(t) != overlapping(s)) {
            fprintf(stderr,
                    "bench_pairloop: the %s copy has %lld overlapping pairs, the run %lld\n",
                    names[k], (long long)overlapping(t), (long long)overlapping(s));
            goto done;
        }
    }
    double bf[3] = {1e300, 1e300, 1e300}, bs[3] = {1e300, 1e300, 1e300};
    for (int round = 0; round < 3; round++) { /* interleaved: a load change hits all three */
        for (int k = 0; k < 3; k++) {
            const double f = time_forces(copy[k], evals),
                         t = time_steps(copy[k], segments, seg_steps);
            if (t < 0.0) {
                goto done;
            }
            bf[k] = f < bf[k] ? f : bf[k];
            bs[k] = t < bs[k] ? t : bs[k];
        }
    }
    for (int k = 0; k < 3; k++) {
        printf("order %-10s forces %6.2f ns/particle  step %6.2f ns/particle-step  (%.3g "
               "particle-steps per CPU s)\n",
               names[k], bf[k], bs[k], 1e9 / bs[k]);
    }
    rc = 0;
done:
    for (int k = 0; k < 3; k++) {
        if (copy[k]) {
            gr_sim_free(copy[k]);
        }
    }
    free(perm);
    free(key);
    free(sorted);
    free(count);
    return rc;
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL;
    const char *sets[64];
    int n_sets = 0;
    long warm = 3000, evals = 200, segments = 40, seg_steps = 50;
    bool all_orders = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--set") && i + 1 < argc && n_sets < 64) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--warmup-steps") && i + 1 < argc) {
            warm = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--evals") && i + 1 < argc) {
            evals = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--segments") && i + 1 < argc) {
            segments = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--seg-steps") && i + 1 < argc) {
            seg_steps = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--orders")) {
            all_orders = true;
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            scene_path = NULL;
            break;
        }
    }
    if (!scene_path || warm < 0 || evals < 1 || segments < 1 || seg_steps < 1) {
        fprintf(stderr,
                "usage: bench_pairloop SCENE [--set section.key=value ...] [--warmup-steps W >= 0] "
                "[--evals E >= 1] [--segments S >= 1] [--seg-steps K >= 1] [--orders]\n");
        return 2;
    }
    gr_set_threads(1);
    gr_scene sc;
    gr_error err = {0};
    if (gr_scene_load(&sc, scene_path, sets, n_sets, &err)) {
        fprintf(stderr, "bench_pairloop: %s\n", err.message);
        return 2;
    }
    if (sc.dim != 2) {
        fprintf(
            stderr,
            "bench_pairloop: %s: system.dim = %d; this bench times the 2D pair loop (dim = 2)\n",
            scene_path, sc.dim);
        return 2;
    }
    gr_sim *s;
    if (gr_sim_create(&sc, &s, &err)) {
        fprintf(stderr, "bench_pairloop: %s\n", err.message);
        return 2;
    }
    if (warm > 0 && gr_sim_step(s, warm, &err)) {
        fprintf(stderr, "bench_pairloop: %s\n", err.message);
        gr_sim_free(s);
        return 1;
    }
    char cpu[256];
    bench_machine(cpu, sizeof cpu);
    printf("# bench_pairloop %s N=%d after %ld steps, %s, one thread, CPU time, minima [%s | %s | "
           "%s]\n",
           scene_path, s->n, warm, gr_sim_kernel(s), cpu, GR_CFLAGS, GR_COMMIT);
    list_stats(s);
    int rc = 0;
    if (all_orders) {
        rc = orders(&sc, s, evals, segments, seg_steps);
    } else {
        const double f = time_forces(s, evals), t = time_steps(s, segments, seg_steps);
        rc = t < 0.0;
        if (!rc) {
            printf("forces %.2f ns/particle  step %.2f ns/particle-step  (%.3g particle-steps per "
                   "CPU s; forces %.0f %% of a step)\n",
                   f, t, 1e9 / t, 100.0 * f / t);
        }
    }
    gr_sim_free(s);
    return rc;
}
