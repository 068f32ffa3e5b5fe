#include <math.h>
#include <Random123/philox.h>
#include "granule/noise.h"
static void bits(uint64_t seed, uint32_t stream, uint64_t a, uint64_t b, uint64_t out[2]) {
    philox4x32_key_t k = {{(uint32_t)seed, (uint32_t)(seed >> 32) ^ (stream * 0x9E3779B9u)}};
    philox4x32_ctr_t c = {{(uint32_t)a, (uint32_t)(a >> 32), (uint32_t)b, (uint32_t)(b >> 32)}};
    philox4x32_ctr_t r = philox4x32(c, k);
    out[0] = ((uint64_t)r.v[0] << 32) | r.v[1]; out[1] = ((uint64_t)r.v[2] << 32) | r.v[3];
}
double gr_noise_uniform(uint64_t seed, uint32_t stream, uint64_t a, uint64_t b) {
    uint64_t o[2]; bits(seed, stream, a, b, o); return (double)(o[0] >> 11) * 0x1.0p-53;
}
double gr_noise_normal1(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id, int c) {
    uint64_t o[2]; bits(seed, stream, step, ((uint64_t)id << 1) | (uint64_t)c, o);
    double u1 = ((double)(o[0] >> 11) + 0.5) * 0x1.0p-53, u2 = (double)(o[1] >> 11) * 0x1.0p-53;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}
void gr_noise_normals(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n, int per, double *out) {
    for (int i = 0; i < n; i++) for (int c = 0; c < per; c++) out[i * per + c] = gr_noise_normal1(seed, stream, step, first + (uint32_t)i, c);
}
