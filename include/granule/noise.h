/* Counter-based random numbers for the random force (2.15-2.18, 2.22-2.23) and initial
 * velocities.
 *
 * Every number is a pure function of (seed, stream, step, particle id, component): Philox4x32-10
 * (Salmon et al., SC'11; Debian's librandom123-dev) keyed by (seed, stream) with the counter
 * (step, id, component, retry). Noise therefore does not depend on thread count, particle storage
 * order, batch boundaries or on where a run was restarted. Gaussians come from the ziggurat method
 * (Marsaglia & Tsang 2000), which is exact; its rare rejections draw fresh bits from the same
 * counter with retry > 0. src/core/noise.c documents the exact key, counter and bit layout.
 * All functions are thread-safe and keep no state between calls. */
#ifndef GRANULE_NOISE_H
#define GRANULE_NOISE_H

#include <stdint.h>

/* Independent streams for independent uses of the same seed. */
enum {
    GR_STREAM_NOISE = 0,
    GR_STREAM_INIT_VELOCITY = 1,
    GR_STREAM_PLACEMENT = 2,
    GR_STREAM_FREE_FLIGHT = 3 /* event-driven free flight (src/integrators/event/event.c) */,
    GR_STREAM_HYBRID = 4 /* hybrid integrator: free-flight increments and bridged kicks */
};

/* Standard normal variates for particles with ids first .. first+n-1 at step `step`:
 * out[i * per + c] is component c (0 <= c < per, per = 1, 2 or 3) of particle first + i, so out
 * must hold n * per doubles. The value for (seed, stream, step, id, c) never depends on `first`,
 * `n` or `per` (per = 1 gives component 0 of per = 2, per = 2 components 0 and 1 of per = 3), and
 * equals gr_noise_normal1's. n <= 0
 * writes nothing; first + n - 1 must not exceed UINT32_MAX. The hot path: vectorised (AVX-512 /
 * AVX2 / SSE2, chosen at run time), about 2 ns per variate on a current x86 core. */
void gr_noise_normals(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n, int per,
                      double *out);

/* A uniform variate in [0, 1) (53 random bits) that is a pure function of its arguments, e.g.
 * (a, b) = (particle id, component). Independent of the normals of the same (seed, stream). */
double gr_noise_uniform(uint64_t seed, uint32_t stream, uint64_t a, uint64_t b);

/* One standard normal variate, a pure function of its arguments: the value gr_noise_normals
 * gives for (step, id, component), component 0, 1 or 2. Scalar (about 10 ns), for tests and tools. */
double gr_noise_normal1(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id, int component);

/* Single-precision normals ([noise] precision = single, docs/performance.md "Single-precision
 * noise"): the same contract as gr_noise_normals (a pure function of (seed, stream, step, id,
 * component), independent of first, n, per, thread count and batch boundaries), but each value
 * is a float widened to double into out: one 32-bit word of Philox4x32-7 per normal (four normals
 * per block, disjoint counters from gr_noise_normals'), turned into a normal by
 * gr_noise_f32_transform, no rejection. A different sequence from gr_noise_normals', the same
 * distribution up to |error| < 5e-7 in each value, with the tails cut at |z| = 6.3380 (a
 * probability of 2^-32 = 2.3e-10). About 2.5 times faster than gr_noise_normals. */
void gr_noise_normals_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n,
                          int per, double *out);

/* One single-precision normal: the value gr_noise_normals_f32 gives for (step, id, component).
 * Scalar, for tests and tools. */
double gr_noise_normal1_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id,
                            int component);

/* The single-precision path's transform of one 32-bit word w: the sign is bit 31, and with
 * q = (k + 1/2) 2^-31 (k = bits 0-30, q rounded to float) |z| approximates Phi^-1(1 - q/2), the
 * quantile of |z| for N(0, 1), within 5e-7. For tests and tools. */
float gr_noise_f32_transform(uint32_t w);

#endif
