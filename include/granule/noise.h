/* Counter-based random numbers for the random force (2.15-2.18, 2.22-2.23) and initial
 * velocities.
 *
 * Every number is a pure function of (seed, stream, step, particle id, component): Philox4x32-10
 * (Salmon et al., SC'11; Debian's librandom123-dev) keyed by (seed, stream) with the counter
 * (step, id, retry). Noise therefore does not depend on thread count, particle storage order or
 * on where a run was restarted. Gaussians come from the ziggurat method (Marsaglia & Tsang 2000),
 * which is exact; its rare rejections draw fresh bits from the same counter with retry > 0. */
#ifndef GRANULE_NOISE_H
#define GRANULE_NOISE_H

#include <stdint.h>

/* Independent streams for independent uses of the same seed. */
enum { GR_STREAM_NOISE = 0, GR_STREAM_INIT_VELOCITY = 1, GR_STREAM_PLACEMENT = 2 };

/* Standard normal variates for particles with ids first .. first+n-1 at step `step`:
 * out[i * per + c] is component c (0 <= c < per, per = 1 or 2) of particle first + i.
 * The value for (seed, stream, step, id, c) never depends on `first` or `n`. */
void gr_noise_normals(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n, int per,
                      double *out);

/* A uniform variate in [0, 1) (53 random bits) that is a pure function of its arguments. */
double gr_noise_uniform(uint64_t seed, uint32_t stream, uint64_t a, uint64_t b);

/* One standard normal variate, a pure function of its arguments (slow path, for tests/tools). */
double gr_noise_normal1(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id, int component);

#endif
