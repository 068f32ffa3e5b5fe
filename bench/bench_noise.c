/* Cost of the random force: nanoseconds per standard normal variate of gr_noise_normals, the
 * call made over all N particles every time step, for per = 1 (1D) and per = 2 (2D) and a few N.
 *
 *   bench_noise [--repeats R] [--normals M]
 *
 * Each repeat times enough consecutive steps to draw at least M normals (default 4e6); the line
 * shows the median and the minimum over R repeats (default 9). For scale it also times the
 * single-variate gr_noise_normal1, gr_noise_uniform, and the thesis's Box-Muller transform (eq.
 * 2.16) on the same Philox bits. GRANULE_NOISE_ISA = avx512 | avx2 | sse2 | scalar caps the
 * vector kernel, to compare them. Machine, compiler flags and commit are printed so numbers from
 * different machines are never compared by accident. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <Random123/philox.h>

#include "granule/noise.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "bench_util.h"

static volatile double sink; /* keeps the results alive */

/* What one timed call does: draw `n` particles x `per` components at step `step` into out. */
typedef void draw_fn(uint64_t step, int n, int per, double *out);

static void draw_batch(uint64_t step, int n, int per, double *out)
{
    gr_noise_normals(12345, GR_STREAM_NOISE, step, 0, n, per, out);
}

static void draw_batch_f32(uint64_t step, int n, int per, double *out)
{
    gr_noise_normals_f32(12345, GR_STREAM_NOISE, step, 0, n, per, out);
}

static void draw_single(uint64_t step, int n, int per, double *out)
{
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < per; c++) {
            out[i * per + c] = gr_noise_normal1(12345, GR_STREAM_NOISE, step, (uint32_t)i, c);
        }
    }
}

static void draw_uniform(uint64_t step, int n, int per, double *out)
{
    for (int i = 0; i < n * per; i++) {
        out[i] = gr_noise_uniform(12345, GR_STREAM_NOISE, step, (uint64_t)i);
    }
}

/* Box-Muller as in the thesis (2.16, 2.23): one Philox block per particle, both components from
 * the same pair of uniforms. */
static void draw_box_muller(uint64_t step, int n, int per, double *out)
{
    philox4x32_key_t key = {{12345, 0}};
    for (int i = 0; i < n; i++) {
        philox4x32_ctr_t ctr = {{(uint32_t)step, (uint32_t)(step >> 32), (uint32_t)i, 0}};
        philox4x32_ctr_t r = philox4x32(ctr, key);
        double a1 = ((double)((uint64_t)r.v[1] << 21 ^ r.v[0]) + 0.5) * 0x1p-53;
        double a2 = (double)((uint64_t)r.v[3] << 21 ^ r.v[2]) * 0x1p-53;
        double rho = sqrt(-2.0 * log(a1)), phi = 6.283185307179586 * a2;
        out[i * per] = rho * cos(phi);
        if (per == 2) {
            out[i * per + 1] = rho * sin(phi);
        }
    }
}

/* Median and minimum ns per normal over `repeats` repeats of >= `normals` variates each. */
static void measure(const char *name, draw_fn *f, int n, int per, int repeats, double normals)
{
    double *out = malloc((size_t)n * (size_t)per * sizeof *out);
    double *ns = malloc((size_t)repeats * sizeof *ns);
    if (!out || !ns) {
        fprintf(stderr, "bench_noise: out of memory\n");
        exit(1);
    }
    long calls = (long)ceil(normals / ((double)n * per));
    uint64_t step = 0;
    f(step++, n, per, out); /* warm caches and the kernel choice */
    for (int r = 0; r < repeats; r++) {
        double t0 = bench_now(), sum = 0;
        for (long k = 0; k < calls; k++) {
            f(step++, n, per, out);
            sum += out[k % n];
        }
        ns[r] = 1e9 * (bench_now() - t0) / ((double)calls * n * per);
        sink = sum;
    }
    qsort(ns, (size_t)repeats, sizeof *ns, bench_cmp_double);
    printf("%-30s per=%d  n=%-7d  median %6.3f  min %6.3f ns/normal\n", name, per, n,
           ns[repeats / 2], ns[0]);
    free(out);
    free(ns);
}

int main(int argc, char **argv)
{
    int repeats = 9;
    double normals = 4e6;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            repeats = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--normals") && i + 1 < argc) {
            normals = atof(argv[++i]);
        } else {
            fprintf(stderr, "usage: bench_noise [--repeats R] [--normals M]\n");
            return 2;
        }
    }
    if (repeats < 1 || repeats > 1000 || !(normals >= 1)) {
        fprintf(stderr, "bench_noise: need 1 <= --repeats <= 1000 and --normals >= 1\n");
        return 2;
    }
    char cpu[256];
    bench_machine(cpu, sizeof cpu);
    const char *isa = getenv("GRANULE_NOISE_ISA");
    printf("bench_noise: %d repeats of >= %.3g normals [%s | %s | %s | GRANULE_NOISE_ISA=%s]\n",
           repeats, normals, cpu, GR_CFLAGS, GR_COMMIT, isa ? isa : "(auto)");
    static const int sizes[] = {1000, 12000, 100000};
    for (int per = 1; per <= 2; per++) {
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            measure("gr_noise_normals", draw_batch, sizes[s], per, repeats, normals);
            measure("gr_noise_normals_f32", draw_batch_f32, sizes[s], per, repeats, normals);
        }
    }
    double few = normals / 8;
    measure("gr_noise_normal1 (one by one)", draw_single, 12000, 2, repeats, few);
    measure("gr_noise_uniform", draw_uniform, 12000, 2, repeats, few);
    measure("Box-Muller, scalar (2.16)", draw_box_muller, 12000, 2, repeats, few);
    return 0;
}
