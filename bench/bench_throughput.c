/* Step throughput of a scene: particle-steps per second of gr_sim_step, median of repeats.
 *
 *   bench_throughput SCENE [--set section.key=value ...] [--warmup-steps W] [--steps S]
 *                    [--repeats R] [--label TEXT] [--threads T] [--csv]
 *                    [--save-state FILE | --state FILE] [--generic]
 *
 * The scene is first advanced W steps (so a lattice start has melted), then R timed blocks of S
 * steps each. Prints one line per scene: label, N, kernel, median / min / max particle-steps/s,
 * neighbour rebuilds, contacts started, plus the machine, compiler flags and commit, so numbers
 * from different machines are never compared by accident. Timing excludes set-up and I/O.
 * --threads T asks OpenMP for T threads (default: OMP_NUM_THREADS, else 1, so a bare run measures
 * one core). --csv prints one CSV row instead (header: --csv-header), with the wall seconds per
 * simulated second and the collisions per wall second, which is what the event-driven and hybrid
 * integrators are compared by.
 * A steady state takes far longer to reach than a benchmark should spend warming up (the 2D RFM
 * scene about 1 s, 1e6 steps): --save-state FILE writes the state after the warm-up
 * (gr_sim_state_save) and --state FILE starts from such a file instead of warming up, so every
 * build and repeat times the same steady state (bench/steady_state.sh). --generic runs the laws
 * through the generic kernel instance even when they are in the hot list (src/core/kernels.c), to
 * measure what specialising them buys (bench/kernel_instances.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "granule/granule.h"
#include "core/sim_internal.h" /* gr_kernel_force_generic */
#include "granule_commit.h"
#include "granule_config.h"
#include "bench_util.h"

#define CSV_HEADER                                                                                 \
    "label,dim,N,kernel,threads,median,min,max,rebuilds_per_step,contacts_per_step,wall_per_"      \
    "simulated_s,collisions_per_s,cpu,cflags,commit"

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *label = NULL, *save_state = NULL, *state = NULL;
    const char *sets[64];
    int n_sets = 0;
    long warm = 2000, steps = 2000, repeats = 5, threads = 0;
    bool csv = false, generic = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--set") && i + 1 < argc && n_sets < 64) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--warmup-steps") && i + 1 < argc) {
            warm = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--steps") && i + 1 < argc) {
            steps = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            repeats = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--label") && i + 1 < argc) {
            label = argv[++i];
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            threads = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--save-state") && i + 1 < argc) {
            save_state = argv[++i];
        } else if (!strcmp(argv[i], "--state") && i + 1 < argc) {
            state = argv[++i];
        } else if (!strcmp(argv[i], "--csv")) {
            csv = true;
        } else if (!strcmp(argv[i], "--generic")) {
            generic = true;
        } else if (!strcmp(argv[i], "--csv-header")) {
            puts(CSV_HEADER);
            return 0;
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            fprintf(stderr, "usage: bench_throughput SCENE [--set k=v ...] [--warmup-steps W] "
                            "[--steps S] [--repeats R] [--label TEXT] [--threads T] [--csv] "
                            "[--save-state FILE | --state FILE] [--generic]\n");
            return 2;
        }
    }
    if (!scene_path || steps < 1 || repeats < 1 || repeats > 1000 || threads < 0 ||
        threads > 1024 || (save_state && state)) {
        fprintf(stderr, "bench_throughput: need a scene, --steps >= 1, 1 <= --repeats <= 1000, 0 "
                        "<= --threads <= 1024 and at "
                        "most one of --save-state and --state\n");
        return 2;
    }
    if (threads == 0) {
        const char *env = getenv("OMP_NUM_THREADS");
        threads = env && atol(env) > 0 ? atol(env) : 1;
    }
    gr_set_threads((int)threads);
    threads = gr_get_threads(); /* 1 when built without OpenMP */
    gr_scene sc;
    gr_error err = {0};
    if (gr_scene_load(&sc, scene_path, sets, n_sets, &err)) {
        fprintf(stderr, "bench_throughput: %s\n", err.message);
        return 2;
    }
    gr_sim *sim;
    if (gr_sim_create(&sc, &sim, &err)) {
        fprintf(stderr, "bench_throughput: %s\n", err.message);
        return 2;
    }
    if (generic) {
        gr_kernel_force_generic(sim);
    }
    if (state) {
        if (bench_load_state(sim, state, &err)) {
            fprintf(stderr, "bench_throughput: %s: %s\n", state, err.message);
            return 2;
        }
    } else if (warm > 0 && gr_sim_step(sim, warm, &err)) {
        fprintf(stderr, "bench_throughput: %s\n", err.message);
        return 1;
    }
    if (save_state && bench_save_state(sim, save_state, &err)) {
        fprintf(stderr, "bench_throughput: %s: %s\n", save_state, err.message);
        return 1;
    }
    double *rate = malloc(sizeof(double) * (size_t)repeats);
    double wall = 0.0;
    int64_t reb0 = gr_sim_rebuilds(sim), col0 = gr_sim_collisions(sim),
            sub0 = gr_sim_sublist_rebuilds(sim);
    for (long r = 0; r < repeats; r++) {
        double t0 = bench_now();
        if (gr_sim_step(sim, steps, &err)) {
            fprintf(stderr, "bench_throughput: %s\n", err.message);
            return 1;
        }
        double t1 = bench_now();
        wall += t1 - t0;
        rate[r] = (double)sc.N * (double)steps / (t1 - t0);
    }
    qsort(rate, (size_t)repeats, sizeof(double), bench_cmp_double);
    char cpu[256];
    bench_machine(cpu, sizeof cpu);
    double simulated = (double)(steps * repeats) * gr_sim_dt(sim);
    double collisions = (double)(gr_sim_collisions(sim) - col0);
    if (csv) {
        printf("\"%s\",%d,%d,%s,%ld,%.4e,%.4e,%.4e,%.5f,%.3f,%.4e,%.4e,\"%s\",\"%s\",%s\n",
               label ? label : scene_path, sc.dim, sc.N, gr_sim_kernel(sim), threads,
               rate[repeats / 2], rate[0], rate[repeats - 1],
               (double)(gr_sim_rebuilds(sim) - reb0) / (double)(steps * repeats),
               collisions / (double)(steps * repeats), wall / simulated, collisions / wall, cpu,
               GR_CFLAGS, GR_COMMIT);
        free(rate);
        gr_sim_free(sim);
        return 0;
    }
    printf("%-28s N=%-7d %-70s median %.3e  min %.3e  max %.3e particle-steps/s  rebuilds/step "
           "%.4f  sublist builds/step %.4f  contacts/step %.2f  [%s | %s | %s]\n",
           label ? label : scene_path, sc.N, gr_sim_kernel(sim), rate[repeats / 2], rate[0],
           rate[repeats - 1], (double)(gr_sim_rebuilds(sim) - reb0) / (double)(steps * repeats),
           (double)(gr_sim_sublist_rebuilds(sim) - sub0) / (double)(steps * repeats),
           (double)(gr_sim_collisions(sim) - col0) / (double)(steps * repeats), cpu, GR_CFLAGS,
           GR_COMMIT);
    free(rate);
    gr_sim_free(sim);
    return 0;
}
