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

/* Single-precision normals ([noise] precision = single, docs/noise.md): the same contract as
 * gr_noise_normals (a pure function of (seed, stream, step, id, component), independent of
 * first, n, per, thread count and batch boundaries), but each value is a float (23-bit uniform,
 * 32-bit Philox4x32-10 words: four normals per block instead of two) widened to double into
 * out. A different sequence from gr_noise_normals' (disjoint Philox counters), same
 * distribution up to single-precision rounding; half the Philox work per normal, about 1.3x
 * faster in all (docs/performance.md, "Single-precision noise"). */
void gr_noise_normals_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n,
                          int per, double *out);

/* One single-precision normal: the value gr_noise_normals_f32 gives for (step, id, component).
 * Scalar, for tests and tools. */
double gr_noise_normal1_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id,
                            int component);

#endif
