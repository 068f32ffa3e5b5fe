/* Event-driven throughput of a scene ([integrator] kind = event): collisions, cell crossings and
 * per-particle noise updates (kicks) per second of CPU time of this process, one core.
 *
 *   bench_event SCENE [--set section.key=value ...] [--warmup T] [--time T] [--repeats R]
 *               [--label TEXT]
 *
 * The scene is advanced `--warmup` simulated seconds, then R timed blocks of `--time` simulated
 * seconds; the median block is reported. CPU time (CLOCK_PROCESS_CPUTIME_ID) is used beside wall
 * time because the machines we share are busy. The calendar is picked with the environment
 * variable GRANULE_EVENT_CALENDAR = bucket (default) | sparse | full (docs/event-driven.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "integrators/event/event.h"
#include "granule/granule.h"
#include "granule_commit.h"
#include "bench_util.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct block {
    double cpu, wall;
    gr_event_counts c;
} block;

static int cmp_block(const void *a, const void *b)
{
    double x = ((const block *)a)->cpu, y = ((const block *)b)->cpu;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *label = "";
    const char *sets[64];
    int n_sets = 0;
    double warm = 0.05, span = 0.05;
    long repeats = 3;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--set") && i + 1 < argc && n_sets < 64) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--warmup") && i + 1 < argc) {
            warm = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--time") && i + 1 < argc) {
            span = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            repeats = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--label") && i + 1 < argc) {
            label = argv[++i];
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            fprintf(stderr, "usage: bench_event SCENE [--set k=v ...] [--warmup T] [--time T] "
                            "[--repeats R] [--label TEXT]\n");
            return 2;
        }
    }
    if (!scene_path || repeats < 1 || repeats > 100 || !(span > 0.0) || !(warm >= 0.0)) {
        fprintf(stderr,
                "bench_event: need a scene, --time > 0, --warmup >= 0, 1 <= --repeats <= 100\n");
        return 2;
    }
    gr_scene sc;
    gr_error err = {0};
    gr_sim *s = NULL;
    if (gr_scene_load(&sc, scene_path, sets, n_sets, &err) || gr_sim_create(&sc, &s, &err)) {
        fprintf(stderr, "bench_event: %s\n", err.message);
        return 1;
    }
    if (!sc.integrator->instantaneous) {
        fprintf(stderr,
                "bench_event: %s is not an event-driven scene (set integrator.kind=event, "
                "model.normal=hard_sphere)\n",
                scene_path);
        gr_sim_free(s);
        return 2;
    }
    const double dt = gr_sim_dt(s);
    if (gr_sim_step(s, (int64_t)(warm / dt + 0.5), &err)) {
        fprintf(stderr, "bench_event: warm-up: %s\n", err.message);
        gr_sim_free(s);
        return 1;
    }
    block b[100];
    const int64_t steps = (int64_t)(span / dt + 0.5);
    for (long r = 0; r < repeats; r++) {
        gr_event_counts c0, c1;
        gr_event_stats(s, &c0);
        double w0 = bench_now(), p0 = cpu_now();
        if (gr_sim_step(s, steps, &err)) {
            fprintf(stderr, "bench_event: %s\n", err.message);
            gr_sim_free(s);
            return 1;
        }
        b[r].cpu = cpu_now() - p0;
        b[r].wall = bench_now() - w0;
        gr_event_stats(s, &c1);
        b[r].c = (gr_event_counts){.collisions = c1.collisions - c0.collisions,
                                   .crossings = c1.crossings - c0.crossings,
                                   .kicks = c1.kicks - c0.kicks,
                                   .tc_elastic = c1.tc_elastic - c0.tc_elastic,
                                   .floors = c1.floors - c0.floors,
                                   .invalid = c1.invalid - c0.invalid};
    }
    qsort(b, (size_t)repeats, sizeof b[0], cmp_block);
    const block *m = &b[repeats / 2];
    const double events = (double)(m->c.collisions + m->c.crossings + m->c.kicks);
    char cpu[256];
    bench_machine(cpu, sizeof cpu);
    printf("%-28s N=%-6d %-28s calendar=%-6s collisions/s=%.3g crossings/s=%.3g kicks/s=%.3g "
           "events/s=%.3g "
           "cpu_per_simulated_s=%.3g wall_per_simulated_s=%.3g tc_elastic=%.2f floors=%.2f "
           "invalid=%.2f T=%.4g | %s | %s\n",
           label, sc.N, gr_sim_kernel(s), gr_event_calendar(s), (double)m->c.collisions / m->cpu,
           (double)m->c.crossings / m->cpu, (double)m->c.kicks / m->cpu, events / m->cpu,
           m->cpu / span, m->wall / span,
           m->c.collisions ? (double)m->c.tc_elastic / (double)m->c.collisions : 0.0,
           m->c.collisions ? (double)m->c.floors / (double)m->c.collisions : 0.0,
           m->c.collisions ? (double)m->c.invalid / (double)m->c.collisions : 0.0,
           gr_sim_temperature(s), cpu, GR_COMMIT);
    gr_sim_free(s);
    return 0;
}
