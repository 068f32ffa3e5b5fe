/* A tight single-file kernel of the 1D RFM scene (docs/scenes/rfm-1d.ini), the reference the
 * 1D throughput is measured against (issue 38 item 8, docs/performance.md, "Single-precision
 * noise"). Same physics and parameters: N = 1000 particles of radius 1.5e-3 m and mass 3.53e-5 kg
 * on a ring of reduced length L' = 1 m, linear spring-dashpot contacts (k_s = 5e5 N/m, eps = 0.1,
 * no clamp), random force of strength D = 1e-8 N^2 s symmetrised every step (2.18), velocity
 * Verlet with dt = 1e-6 s, uniform start with v0 = 0.1 m/s. What it gives up for speed, and granule
 * does not: the normals are floats from a sequential generator (xorshift64*, one 64-bit word per
 * normal, LANES interleaved streams so the loop vectorises: the sum of four 16-bit uniforms, the Irwin-Hall approximation, tails cut at
 * |x| = 2 sqrt(3)), so the noise depends on the order particles are visited and is neither
 * counter-based nor exact in the tails; no energy ledger, no diagnostics, no checks.
 *
 *   tight_1d [--warmup-steps W] [--steps S] [--repeats R]
 *
 * Prints the median, minimum and maximum particle-steps/s over R timed blocks of S steps after W
 * warm-up steps (defaults 200000, 50000, 5), and the granular temperature m <v^2> at the end as a
 * sanity check against granule's run of the same scene. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { N = 1000, LANES = 8 }; /* N a multiple of LANES */

static double x[N], v[N], f[N], fc[N];
static float g[N];

static inline uint64_t xs64(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545f4914f6cdd1dull;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double p = *(const double *)a, q = *(const double *)b;
    return (p > q) - (p < q);
}

int main(int argc, char **argv)
{
    long warm = 200000, steps = 50000;
    int repeats = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--warmup-steps")) {
            warm = atol(argv[i + 1]);
        } else if (!strcmp(argv[i], "--steps")) {
            steps = atol(argv[i + 1]);
        } else if (!strcmp(argv[i], "--repeats")) {
            repeats = atoi(argv[i + 1]);
        } else {
            fprintf(stderr, "tight_1d: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (repeats < 1 || repeats > 100 || steps < 1 || warm < 0) {
        fprintf(stderr, "tight_1d: --repeats in [1, 100], --steps >= 1, --warmup-steps >= 0\n");
        return 2;
    }
    const double r = 1.5e-3, d = 2 * r, m = 3.53e-5, k = 5e5, eps = 0.1, D = 1e-8, dt = 1e-6;
    const double L = 1.0 + N * d;
    /* dashpot for restitution eps at reduced mass m/2: eps = exp(-pi zeta / sqrt(1 - zeta^2)) */
    const double le = log(eps), zeta = -le / sqrt(M_PI * M_PI + le * le);
    const double c = 2 * zeta * sqrt(k * m / 2);
    const double half = 0.5 * dt / m;
    /* kick of the random force sqrt(2 D / dt) g over dt; the Irwin-Hall sum of four 16-bit
     * uniforms has variance 4 (2^32 - 1) / 12 / 2^32 ~ 1/3 in units of 2^16 */
    const float amp = (float)(sqrt(2 * D / dt) * dt / m * sqrt(3.0) / 65536.0);
    uint64_t s = 0x9e3779b97f4a7c15ull, st[LANES];
    float lsum[LANES] = {0};
    for (int i = 0; i < N; i++) {
        x[i] = (i + 0.5) * (L / N);
        v[i] = 0.1 * ((double)(xs64(&s) >> 11) * 0x1p-53 - 0.5);
    }
    for (int l = 0; l < LANES; l++) {
        st[l] = xs64(&s) | 1u;
    }
    double rate[100];
    for (int rep = -1; rep < repeats; rep++) {
        const long n = rep < 0 ? warm : steps;
        const double t0 = now();
        for (long t = 0; t < n; t++) {
            for (int i = 0; i < N; i++) {
                v[i] += half * f[i]; /* f: the forces of the last step */
                x[i] += dt * v[i];
            }
            /* contact forces: fc[i] between i and i + 1 (fc[N - 1] across the seam), then
             * f[i] = fc[i - 1] - fc[i]; both loops vectorise */
            for (int i = 0; i < N - 1; i++) {
                double ov = d - (x[i + 1] - x[i]);
                fc[i] = ov > 0 ? k * ov + c * (v[i] - v[i + 1]) : 0.0;
            }
            {
                double ov = d - (x[0] + L - x[N - 1]);
                fc[N - 1] = ov > 0 ? k * ov + c * (v[N - 1] - v[0]) : 0.0;
            }
            f[0] = fc[N - 1] - fc[0];
            for (int i = 1; i < N; i++) {
                f[i] = fc[i - 1] - fc[i];
            }
            /* normals: LANES independent xorshift64* streams, particle i from stream i % LANES */
            float sum = 0.0f;
            for (int i0 = 0; i0 < N; i0 += LANES) {
                for (int l = 0; l < LANES; l++) {
                    uint64_t w = st[l];
                    w ^= w >> 12;
                    w ^= w << 25;
                    w ^= w >> 27;
                    st[l] = w;
                    w *= 0x2545f4914f6cdd1dull;
                    float u = (float)((w & 0xffff) + (w >> 16 & 0xffff) + (w >> 32 & 0xffff) +
                                      (w >> 48)) -
                              131070.0f;
                    g[i0 + l] = u;
                    lsum[l] += u;
                }
            }
            for (int l = 0; l < LANES; l++) {
                sum += lsum[l];
                lsum[l] = 0.0f;
            }
            const float mean = sum / N;
            for (int i = 0; i < N; i++) {
                v[i] += half * f[i] + (double)(amp * (g[i] - mean));
            }
        }
        if (rep >= 0) {
            rate[rep] = (double)N * (double)n / (now() - t0);
        }
    }
    double v2 = 0.0;
    for (int i = 0; i < N; i++) {
        v2 += v[i] * v[i];
    }
    double sorted[100];
    memcpy(sorted, rate, sizeof(double) * (size_t)repeats);
    qsort(sorted, (size_t)repeats, sizeof(double), cmp);
    printf("tight_1d N %d: median %.4g min %.4g max %.4g particle-steps/s; T = m<v^2> = %.4g J "
           "after %ld steps\n",
           N, sorted[repeats / 2], sorted[0], sorted[repeats - 1], m * v2 / N,
           warm + steps * repeats);
    return 0;
}
