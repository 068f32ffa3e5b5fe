/* Cost and accuracy of the structure factor S(k) of the sk observable (docs/analysis-structure-
 * factor.md): time per frame of the Gaussian-gridding NUFFT and of the direct sum (the oracle) for
 * every lattice vector with |k| d <= 4, at the thesis density phi = 0.53 (r = 1.5 mm; N = 3000,
 * 12000, 48000 are its L = 0.2, 0.4, 0.8 m systems), and the largest difference |dS| between them.
 *
 *   bench_sk [--repeats R] [--quick] [--no-direct] [--scan-n N]
 *
 * Two point sets per N: uniform random positions (S ~ 1 everywhere: the typical error) and a
 * square lattice with Gaussian jitter of 0.3 lattice spacings (S(k) ~ k^2 sigma^2, down to ~1e-4 at
 * the smallest k: the hardest case for the absolute error, see the accuracy requirement
 * eps << sqrt(S_min / N) of the physics notes sec. 6.1). Timings are medians of R repeats (default
 * 7; the direct sum is timed once above N = 1e4). The msp scan (gridding half-width 2..10 at N =
 * 48000, or --scan-n) is what GR_SK_MSP_DEFAULT was chosen from. Machine, compiler flags and commit
 * are printed so numbers from different machines are never compared by accident. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "granule/status.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "bench_util.h"

#include "analysis/sk.h"

#define RADIUS 1.5e-3
#define PHI 0.53
#define KD_MAX 4.0
#define DEFAULT_MSP 8 /* GR_SK_MSP_DEFAULT */

static volatile double sink;

typedef struct points {
    int n;
    double L, *x, *y;
} points;

static void make_points(points *p, int n, int jitter, unsigned long seed)
{
    p->n = n;
    p->L = sqrt(n * M_PI * RADIUS * RADIUS / PHI);
    p->x = malloc(sizeof(double) * (size_t)n);
    p->y = malloc(sizeof(double) * (size_t)n);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    if (!jitter) {
        for (int i = 0; i < n; i++) {
            p->x[i] = p->L * gsl_rng_uniform(r);
            p->y[i] = p->L * gsl_rng_uniform(r);
        }
    } else {
        int m = (int)ceil(sqrt((double)n));
        double a = p->L / m;
        for (int i = 0; i < n; i++) {
            p->x[i] = a * (i % m + 0.5) + gsl_ran_gaussian(r, 0.3 * a);
            p->y[i] = a * (i / m + 0.5) + gsl_ran_gaussian(r, 0.3 * a);
        }
    }
    gsl_rng_free(r);
}

static double n_cut_of(double L) { return KD_MAX * L / (2.0 * M_PI * 2.0 * RADIUS); }

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Median CPU time (and median wall time in *wall) of `repeats` frames. CPU time is the figure to
 * quote on a shared machine; the two agree on an idle one. */
static double time_frames(gr_sk_plan *pl, int method, const points *p, double *S, int repeats,
                          double *wall)
{
    double t[64], w[64];
    gr_error err = {0};
    if (repeats > 64) {
        repeats = 64;
    }
    for (int r = 0; r < repeats; r++) {
        double w0 = bench_now(), t0 = cpu_now();
        if (gr_sk_compute(pl, method, p->n, p->x, p->y, S, &err)) {
            fprintf(stderr, "bench_sk: %s\n", err.message);
            exit(1);
        }
        t[r] = cpu_now() - t0;
        w[r] = bench_now() - w0;
        sink += S[0];
    }
    qsort(t, (size_t)repeats, sizeof t[0], bench_cmp_double);
    qsort(w, (size_t)repeats, sizeof w[0], bench_cmp_double);
    if (wall) {
        *wall = w[repeats / 2];
    }
    return t[repeats / 2];
}

typedef struct accuracy {
    double max_abs, max_rel, S_min;
} accuracy;

static accuracy compare(const double *Sg, const double *Sd, int nv)
{
    accuracy a = {0.0, 0.0, INFINITY};
    for (int v = 0; v < nv; v++) {
        double d = fabs(Sg[v] - Sd[v]);
        a.max_abs = fmax(a.max_abs, d);
        a.max_rel = fmax(a.max_rel, d / fmax(Sd[v], 1e-300));
        a.S_min = fmin(a.S_min, Sd[v]);
    }
    return a;
}

int main(int argc, char **argv)
{
    int repeats = 7, quick = 0, direct = 1, scan_n = 48000;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            repeats = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--quick")) {
            quick = 1;
        } else if (!strcmp(argv[i], "--no-direct")) {
            direct = 0;
        } else if (!strcmp(argv[i], "--scan-n") && i + 1 < argc) {
            scan_n = atoi(argv[++i]);
        } else {
            fprintf(stderr, "usage: bench_sk [--repeats R] [--quick] [--no-direct] [--scan-n N]\n");
            return 2;
        }
    }
    if (repeats < 1 || repeats > 64 || scan_n < 100) {
        fprintf(stderr, "bench_sk: need 1 <= --repeats <= 64 and --scan-n >= 100\n");
        return 2;
    }
    char cpu[256];
    bench_machine(cpu, sizeof cpu);
    printf("bench_sk: S(k) for |k| d <= %g at phi = %g, r = %g m; median of %d frames [%s | %s | "
           "%s]\n",
           KD_MAX, PHI, RADIUS, repeats, cpu, GR_CFLAGS, GR_COMMIT);
    const int sizes[] = {1000, 12000, 48000, 100000};
    const int n_sizes = quick ? 1 : 4;
    printf("\nCPU seconds per frame (wall seconds in brackets); vectors = full plane, half "
           "computed\n");
    printf("%7s %7s %6s %8s %5s %22s %22s %12s %12s %12s\n", "N", "L/m", "n_max", "vectors", "grid",
           "gridding/s", "direct/s", "max|dS|unif", "max|dS|jit", "min S jit");
    for (int s = 0; s < n_sizes; s++) {
        const int n = quick ? 1000 : sizes[s];
        points pu, pj;
        make_points(&pu, n, 0, 1000u + (unsigned)s);
        make_points(&pj, n, 1, 2000u + (unsigned)s);
        gr_sk_plan *pl;
        gr_error err = {0};
        if (gr_sk_plan_create(pu.L, n_cut_of(pu.L), DEFAULT_MSP, &pl, &err)) {
            fprintf(stderr, "bench_sk: %s\n", err.message);
            return 1;
        }
        int nv = gr_sk_vectors(gr_sk_plan_lattice(pl), NULL, NULL, NULL), grid;
        gr_sk_grid(gr_sk_plan_lattice(pl), &grid, NULL);
        double *Sg = malloc(sizeof(double) * (size_t)nv), *Sd = malloc(sizeof(double) * (size_t)nv);
        double wg, wd = NAN;
        double tg = time_frames(pl, GR_SK_GRIDDING, &pu, Sg, repeats, &wg);
        double td = NAN;
        accuracy au = {NAN, NAN, NAN}, aj = {NAN, NAN, NAN};
        if (direct) {
            td = time_frames(pl, GR_SK_DIRECT, &pu, Sd, n > 10000 ? 1 : repeats, &wd);
            au = compare(Sg, Sd, nv);
            time_frames(pl, GR_SK_GRIDDING, &pj, Sg, 1, NULL);
            time_frames(pl, GR_SK_DIRECT, &pj, Sd, 1, NULL);
            aj = compare(Sg, Sd, nv);
        }
        printf("%7d %7.4f %6.1f %8d %5d %10.4g (%9.4g) %10.4g (%9.4g) %12.3g %12.3g %12.3g\n", n,
               pu.L, n_cut_of(pu.L), 2 * nv, grid, tg, wg, td, wd, au.max_abs, aj.max_abs,
               aj.S_min);
        fflush(stdout);
        free(Sg);
        free(Sd);
        gr_sk_plan_free(pl);
        free(pu.x);
        free(pu.y);
        free(pj.x);
        free(pj.y);
    }
    if (quick || !direct) {
        return 0;
    }
    /* msp scan at one N: accuracy against the direct sum and time per frame */
    points pu, pj;
    make_points(&pu, scan_n, 0, 3001u);
    make_points(&pj, scan_n, 1, 3002u);
    gr_sk_plan *ref;
    gr_error err = {0};
    if (gr_sk_plan_create(pu.L, n_cut_of(pu.L), DEFAULT_MSP, &ref, &err)) {
        fprintf(stderr, "bench_sk: %s\n", err.message);
        return 1;
    }
    int nv = gr_sk_vectors(gr_sk_plan_lattice(ref), NULL, NULL, NULL);
    double *Su = malloc(sizeof(double) * (size_t)nv), *Sj = malloc(sizeof(double) * (size_t)nv);
    double *Sg = malloc(sizeof(double) * (size_t)nv);
    time_frames(ref, GR_SK_DIRECT, &pu, Su, 1, NULL);
    time_frames(ref, GR_SK_DIRECT, &pj, Sj, 1, NULL);
    printf("\nmsp scan at N = %d (direct sums as reference; max |dS|/S over the jittered set's "
           "vectors)\n",
           scan_n);
    printf("%4s %6s %12s %12s %12s %12s %12s\n", "msp", "grid", "cpu/s", "max|dS|unif",
           "mean|dS|unif", "max|dS|jit", "max|dS|/S jit");
    for (int msp = 2; msp <= 10; msp++) {
        gr_sk_plan *pl;
        if (gr_sk_plan_create(pu.L, n_cut_of(pu.L), msp, &pl, &err)) {
            fprintf(stderr, "bench_sk: %s\n", err.message);
            return 1;
        }
        int grid;
        gr_sk_grid(gr_sk_plan_lattice(pl), &grid, NULL);
        double t = time_frames(pl, GR_SK_GRIDDING, &pu, Sg, repeats, NULL);
        accuracy au = compare(Sg, Su, nv);
        double mean = 0.0;
        for (int v = 0; v < nv; v++) {
            mean += fabs(Sg[v] - Su[v]) / nv;
        }
        time_frames(pl, GR_SK_GRIDDING, &pj, Sg, 1, NULL);
        accuracy aj = compare(Sg, Sj, nv);
        printf("%4d %6d %12.4g %12.3g %12.3g %12.3g %12.3g\n", msp, grid, t, au.max_abs, mean,
               aj.max_abs, aj.max_rel);
        fflush(stdout);
        gr_sk_plan_free(pl);
    }
    free(Su);
    free(Sj);
    free(Sg);
    gr_sk_plan_free(ref);
    free(pu.x);
    free(pu.y);
    free(pj.x);
    free(pj.y);
    return 0;
}
