/* Counter-based Gaussian noise: the random force of the Random Force Model and the random
 * initial velocities.
 *
 * The random force is white noise held constant over a time step, so every particle and every
 * component gets eta = sqrt(2D/dt) xi per step with xi a standard normal variate (thesis eq. 2.16
 * in 1D, eq. 2.23 in 2D). The thesis drew xi with the Box-Muller transform; we use the ziggurat
 * method of Marsaglia & Tsang (J. Stat. Softw. 5(8), 2000) instead, which is exact as well (it
 * samples the normal density itself, tail included) and much faster: 98.5% of the variates cost
 * two table look-ups, a multiplication and a comparison, with no log, sqrt or cos. The bits
 * come from the counter-based generator Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel
 * random numbers: as easy as 1, 2, 3", SC'11; Random123, Debian's librandom123-dev), so a variate
 * is a pure function of (seed, stream, step, particle id, component): the noise does not depend
 * on the thread count, the storage order of the particles, the batch a particle is drawn in or
 * where a run was restarted, and a checkpoint needs no generator state.
 *
 * Key. The 64-bit Philox key is
 *   k0 = seed & 0xffffffff,   k1 = (seed >> 32) ^ fmix32(2 stream + kind),
 * kind = 0 for normals and 1 for uniforms, fmix32 = MurmurHash3's bijective 32-bit finaliser. So
 * for a fixed stream every seed has its own key, and for a fixed seed every (stream, kind) does;
 * as (seed, stream) has 96 bits, two pairs whose seeds differ in the high word can share a key
 * (never for seeds below 2^32).
 *
 * Counter. The normal for particle `id`, component c (0 or 1), takes its first 64 bits from the
 * Philox block with counter
 *   (step & 0xffffffff, step >> 32, id >> 1, c)
 * namely word (id & 1) of it, the 128-bit block being read as the words v0 | v1 << 32 and
 * v2 | v3 << 32. Two consecutive ids share a block, which gives two normals per Philox call for
 * per = 1, 2 and 3 alike, and the value never depends on `first`, `n` or `per`. A variate the
 * fast path rejects continues with fresh blocks private to it, r = 1, 2, ...:
 *   (step & 0xffffffff, step >> 32, id >> 1, c | (id & 1) << 1 | r << 2)   for c = 0, 1.
 * The third component of 3D (c = 2, per = 3) was added later and must not touch a block the 1D
 * and 2D normals use, so that they stay bit-identical: its first draw takes word 3 = 2, which no
 * other first draw (0 or 1) or retry (r >= 1: word 3 >= 4) takes, and its retries take
 *   (step & 0xffffffff, step >> 32, id >> 1, 1 << 30 | (id & 1) << 1 | r << 2),
 * i.e. bit 30 set where the other components' retries have it clear (their r stays below 2^28:
 * a retry is needed with probability < 2%, so 2^28 of them in a row never happen). Bit 31 belongs
 * to the single-precision path below. per = 3 draws the components 0 and 1 exactly as per = 2
 * and the component 2 as a per = 1 draw under its own counter word, so the x and y normals of a
 * 3D run are those of a 2D run with the same seed, and the z normals are new ones.
 * gr_noise_uniform(seed, stream, a, b) is the top 53 bits of word 0 of the block with counter
 * (a & 0xffffffff, a >> 32, b & 0xffffffff, b >> 32) under the kind = 1 key.
 *
 * Ziggurat. 256 layers of equal area V under f(x) = exp(-x^2/2), x >= 0: Marsaglia & Tsang's
 * R = 3.6541528853610088 and V = R f(R) + int_R^inf f dx = 4.92867323397465e-3 computed from R
 * (their rounded 4.92867323399e-3 agrees to 11 digits). Layer 0 is the base strip [0, x_0] x
 * [0, f(R)], x_0 = V/f(R): the rectangle up to R plus, in area, the tail beyond R. Layer
 * i = 1..255 is [0, x_i] x [f(x_i), f(x_{i+1})] with x_1 = R, x_{i+1} = f^-1(V/x_i + f(x_i)),
 * x_256 = 0. One 64-bit word w gives the layer i = bits 0-7, a 52-bit uniform u = bits 11-62 and
 * the sign = bit 63: separate bits, since taking the layer from the low bits of the uniform makes
 * them correlated (Doornik, "An improved ziggurat method to generate normal random samples",
 * 2005). x = u x_i is accepted at once when x < x_{i+1}; the test is u < t_i with t_i rounded up
 * to the 2^-52 grid, which is exact. Otherwise a fresh block (retry r) decides: in layer 0 the
 * tail is sampled exactly by Marsaglia's method (x = R + e1/R with e1, e2 standard exponentials,
 * accepted when 2 e2 > (e1/R)^2, a new block per attempt); in layers 1..255 the wedge test
 * f(x_i) + u' (f(x_{i+1}) - f(x_i)) < f(x) accepts x, and when it fails the block's second word
 * starts the ziggurat over. The tables were computed once with 80-digit arithmetic (mpmath) and
 * are written as hex literals, so they do not depend on the build machine's libm; test_noise.c
 * re-derives them from the recursion and checks the values against an independent scalar
 * implementation of everything described here.
 *
 * Speed. Philox and the ziggurat's fast path run on whole vectors of counters in 64-bit lanes
 * (AVX-512, AVX2 or SSE2, picked at run time from the CPU, whatever -march says), in three passes
 * over a batch: Philox words, the two table look-ups per word (scalar loads, cheaper than vector
 * gathers), the fast test; the rejected variates are then finished in scalar code, their first
 * retry blocks again computed in vectors.
 * Every kernel gives bit-identical results: Philox is integer arithmetic, and the fast path is one
 * correctly rounded subtraction and multiplication. The environment variable GRANULE_NOISE_ISA
 * (avx512, avx2, sse2 or scalar) caps the choice, for tests and benchmarks. */
#include "granule/noise.h"

#include <assert.h>
#include <stdbool.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include <Random123/philox.h>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define NOISE_X86 1
#else
#define NOISE_X86 0
#endif

enum { KIND_NORMAL = 0, KIND_UNIFORM = 1 };

/* ---- Ziggurat tables ------------------------------------------------------------------------- */

/* Layer edges x_i, i = 0..256 (x_0 = V/f(R), x_1 = R, x_256 = 0), rounded to nearest. */
static const double zig_x[257] = {
    0x1.f493b7815d982p+1,
    0x1.d3bb48209ad33p+1,
    0x1.b981f3878fdb0p+1,
    0x1.a8fdc78947759p+1,
    0x1.9cbee014057abp+1,
    0x1.92ee0946f4496p+1,
    0x1.8ab0fbfaa7c14p+1,
    0x1.839030529f234p+1,
    0x1.7d42df4d6ce8bp+1,
    0x1.7799556090672p+1,
    0x1.72728f05f7a33p+1,
    0x1.6db6b8d09e231p+1,
    0x1.69540be9fe5c2p+1,
    0x1.653ce7b006aeap+1,
    0x1.61669cf861e4bp+1,
    0x1.5dc8a243ad0fep+1,
    0x1.5a5c08b718ddap+1,
    0x1.571b1a94ae41cp+1,
    0x1.54011523a7e43p+1,
    0x1.5109f53e9ac42p+1,
    0x1.4e3250dcd8903p+1,
    0x1.4b7739d6b5a28p+1,
    0x1.48d62759c43bdp+1,
    0x1.464ce44a73a16p+1,
    0x1.43d9815545e94p+1,
    0x1.417a49cb9e5dbp+1,
    0x1.3f2dbaa60f475p+1,
    0x1.3cf27b31704a6p+1,
    0x1.3ac7570ae88fbp+1,
    0x1.38ab39256410ap+1,
    0x1.369d27a33a840p+1,
    0x1.349c405ae12a3p+1,
    0x1.32a7b5e68a4a3p+1,
    0x1.30becd256aeeep+1,
    0x1.2ee0db1a978f5p+1,
    0x1.2d0d43196db98p+1,
    0x1.2b437532a0a53p+1,
    0x1.2982ecd770e78p+1,
    0x1.27cb2faa8592ep+1,
    0x1.261bcc77658e0p+1,
    0x1.24745a4ac9c25p+1,
    0x1.22d477a6fd3efp+1,
    0x1.213bc9d04cc82p+1,
    0x1.1fa9fc2e2d901p+1,
    0x1.1e1ebfbe4ae3ap+1,
    0x1.1c99ca971a695p+1,
    0x1.1b1ad777f2f8fp+1,
    0x1.19a1a564eebadp+1,
    0x1.182df74d21262p+1,
    0x1.16bf93b9deef5p+1,
    0x1.1556448602e3dp+1,
    0x1.13f1d69c4096fp+1,
    0x1.129219bbb5d37p+1,
    0x1.1136e04207043p+1,
    0x1.0fdffefa69fb8p+1,
    0x1.0e8d4cf116594p+1,
    0x1.0d3ea34aa3d32p+1,
    0x1.0bf3dd1eed449p+1,
    0x1.0aacd7571c0c5p+1,
    0x1.0969708e8a255p+1,
    0x1.082988f632e18p+1,
    0x1.06ed023a72669p+1,
    0x1.05b3bf6adb37ep+1,
    0x1.047da4e3ef5c7p+1,
    0x1.034a983a902abp+1,
    0x1.021a8028fc947p+1,
    0x1.00ed447d3a075p+1,
    0x1.ff859c118f60bp+0,
    0x1.fd360d22fe786p+0,
    0x1.faebb187122bfp+0,
    0x1.f8a6604899783p+0,
    0x1.f665f20c90168p+0,
    0x1.f42a40fb74d6dp+0,
    0x1.f1f328ac25321p+0,
    0x1.efc086101eca9p+0,
    0x1.ed9237610a73ap+0,
    0x1.eb681c0f76f08p+0,
    0x1.e94214b2abf09p+0,
    0x1.e72002f97fe23p+0,
    0x1.e501c99c1d186p+0,
    0x1.e2e74c4ea46f3p+0,
    0x1.e0d06fb49d219p+0,
    0x1.debd195522e34p+0,
    0x1.dcad2f8fc490cp+0,
    0x1.daa0999206e6fp+0,
    0x1.d8973f4d7fba5p+0,
    0x1.d691096e7f123p+0,
    0x1.d48de1533c647p+0,
    0x1.d28db1037ef21p+0,
    0x1.d0906328b8f6fp+0,
    0x1.ce95e3068e038p+0,
    0x1.cc9e1c73bd690p+0,
    0x1.caa8fbd36a2acp+0,
    0x1.c8b66e0eba617p+0,
    0x1.c6c6608ec8706p+0,
    0x1.c4d8c136e0d1dp+0,
    0x1.c2ed7e5f07a2ep+0,
    0x1.c10486cec16a0p+0,
    0x1.bf1dc9b81ae83p+0,
    0x1.bd3936b2ec0a2p+0,
    0x1.bb56bdb85256ep+0,
    0x1.b9764f1e5f73dp+0,
    0x1.b797db93f8928p+0,
    0x1.b5bb541ce3d04p+0,
    0x1.b3e0aa0e00c01p+0,
    0x1.b207cf09a985cp+0,
    0x1.b030b4fc3a11cp+0,
    0x1.ae5b4e18bb338p+0,
    0x1.ac878cd5af5d0p+0,
    0x1.aab563e9ff10bp+0,
    0x1.a8e4c64a03140p+0,
    0x1.a715a724aa9a7p+0,
    0x1.a547f9e0bbb8bp+0,
    0x1.a37bb21a2c85fp+0,
    0x1.a1b0c39f93696p+0,
    0x1.9fe7226fad24ep+0,
    0x1.9e1ec2b6f7414p+0,
    0x1.9c5798cd5d92ep+0,
    0x1.9a919933f99c1p+0,
    0x1.98ccb892e2a33p+0,
    0x1.9708ebb70d5f0p+0,
    0x1.954627903a28cp+0,
    0x1.9384612ef0afep+0,
    0x1.91c38dc288349p+0,
    0x1.9003a2973b591p+0,
    0x1.8e44951446a28p+0,
    0x1.8c865aba10c9dp+0,
    0x1.8ac8e9205c045p+0,
    0x1.890c35f47f72fp+0,
    0x1.875036f7a7ec7p+0,
    0x1.8594e1fd1f5bep+0,
    0x1.83da2ce899f16p+0,
    0x1.82200dac88677p+0,
    0x1.80667a486ea20p+0,
    0x1.7ead68c73dee8p+0,
    0x1.7cf4cf3db22fdp+0,
    0x1.7b3ca3c8b140bp+0,
    0x1.7984dc8babd95p+0,
    0x1.77cd6faeff44bp+0,
    0x1.7616535e57321p+0,
    0x1.745f7dc70eeddp+0,
    0x1.72a8e516914c8p+0,
    0x1.70f27f78b68edp+0,
    0x1.6f3c43161f856p+0,
    0x1.6d8626128d355p+0,
    0x1.6bd01e8b343bep+0,
    0x1.6a1a22950b2b4p+0,
    0x1.6864283b13139p+0,
    0x1.66ae257c99674p+0,
    0x1.64f8104b7260dp+0,
    0x1.6341de8a2b0a4p+0,
    0x1.618b860a31fc5p+0,
    0x1.5fd4fc89f5e3ap+0,
    0x1.5e1e37b2f8cd5p+0,
    0x1.5c672d17d733fp+0,
    0x1.5aafd23241b5bp+0,
    0x1.58f81c60e8516p+0,
    0x1.574000e555f7ap+0,
    0x1.558774e1bb2c9p+0,
    0x1.53ce6d56a6651p+0,
    0x1.5214df20a8b5cp+0,
    0x1.505abef5e5563p+0,
    0x1.4ea001638a606p+0,
    0x1.4ce49acb311ddp+0,
    0x1.4b287f602415ep+0,
    0x1.496ba32488f30p+0,
    0x1.47adf9e66c338p+0,
    0x1.45ef773cac75fp+0,
    0x1.44300e83c30a6p+0,
    0x1.426fb2da6745fp+0,
    0x1.40ae571e09e76p+0,
    0x1.3eebede725a86p+0,
    0x1.3d28698561de4p+0,
    0x1.3b63bbfb83d06p+0,
    0x1.399dd6fb2b267p+0,
    0x1.37d6abe05586dp+0,
    0x1.360e2baca52d8p+0,
    0x1.3444470265ea4p+0,
    0x1.3278ee1f4b934p+0,
    0x1.30ac10d6e48dap+0,
    0x1.2edd9e8cba991p+0,
    0x1.2d0d862e1b856p+0,
    0x1.2b3bb62b82edcp+0,
    0x1.29681c719d71ep+0,
    0x1.2792a661dd382p+0,
    0x1.25bb40ca96bffp+0,
    0x1.23e1d7de9c322p+0,
    0x1.2206572c4c6ecp+0,
    0x1.2028a9940a0a3p+0,
    0x1.1e48b93e0d431p+0,
    0x1.1c666f8f82acfp+0,
    0x1.1a81b51ee6d8bp+0,
    0x1.189a71a78da37p+0,
    0x1.16b08bfc42021p+0,
    0x1.14c3e9f8e9144p+0,
    0x1.12d4707310fc2p+0,
    0x1.10e20329515f2p+0,
    0x1.0eec84b16086fp+0,
    0x1.0cf3d664bcc83p+0,
    0x1.0af7d84bc6117p+0,
    0x1.08f869071f40fp+0,
    0x1.06f565b72a014p+0,
    0x1.04eea9e16a600p+0,
    0x1.02e40f5398f9ep+0,
    0x1.00d56e04234efp+0,
    0x1.fd8537dfa2eb2p-1,
    0x1.f956d9e87d7b4p-1,
    0x1.f51f654d8f68dp-1,
    0x1.f0de784f0622cp-1,
    0x1.ec93abdf982d4p-1,
    0x1.e83e9337a6f06p-1,
    0x1.e3debb5d2ee04p-1,
    0x1.df73aa9f17658p-1,
    0x1.dafce0023b8c9p-1,
    0x1.d679d29e41f15p-1,
    0x1.d1e9f0e80b74dp-1,
    0x1.cd4c9fe722691p-1,
    0x1.c8a13a5323b68p-1,
    0x1.c3e70f9594efap-1,
    0x1.bf1d62abf823ap-1,
    0x1.ba4368e529f42p-1,
    0x1.b558487427a31p-1,
    0x1.b05b16d136ca4p-1,
    0x1.ab4ad6e101638p-1,
    0x1.a62676d77cd61p-1,
    0x1.a0eccdca4a733p-1,
    0x1.9b9c98e38c54fp-1,
    0x1.96347822c1ef2p-1,
    0x1.90b2ea94ecfa0p-1,
    0x1.8b1649e7b76a1p-1,
    0x1.855cc53430a7fp-1,
    0x1.7f845ad46f54bp-1,
    0x1.798ad10b32a80p-1,
    0x1.736dad346f8b0p-1,
    0x1.6d2a292000579p-1,
    0x1.66bd261a37c47p-1,
    0x1.60231cfd97ef4p-1,
    0x1.59580a707ce9fp-1,
    0x1.52575621ad37cp-1,
    0x1.4b1bb363dfeb0p-1,
    0x1.439ef8dff9b5dp-1,
    0x1.3bd9ec1a2b137p-1,
    0x1.33c3fc05791fdp-1,
    0x1.2b52e3863d888p-1,
    0x1.227a28f7a1afdp-1,
    0x1.192a697413681p-1,
    0x1.0f5053b025d4ep-1,
    0x1.04d32278ebbb9p-1,
    0x1.f32482d4cd5dap-2,
    0x1.dac2f5a74728cp-2,
    0x1.c004d2f386213p-2,
    0x1.a230c2e4cd0d8p-2,
    0x1.801fce82fa72ap-2,
    0x1.57cb938443b84p-2,
    0x1.250af3c2c5bdfp-2,
    0x1.b8d0be3fdf753p-3,
    0x0.0p+0,
};
/* Fast-path thresholds t_i = ceil(2^52 x_{i+1} / zig_x[i]) 2^-52, with the exact x_{i+1}: for u on
 * the 2^-52 grid, u < t_i exactly when u zig_x[i] < x_{i+1}. */
static const double zig_t[256] = {
    0x1.de67b004bdeccp-1, 0x1.e34b496663894p-1, 0x1.ecd8befe0605ap-1, 0x1.f13f491483bf8p-1,
    0x1.f3d2e3c028b30p-1, 0x1.f5880b05450e8p-1, 0x1.f6c0d8800a868p-1, 0x1.f7acb03817074p-1,
    0x1.f86565e3c45dap-1, 0x1.f8fa4dd9a5a46p-1, 0x1.f9751b0bc2364p-1, 0x1.f9dc408ec3f3ep-1,
    0x1.fa3434f698f5ap-1, 0x1.fa80293c5e024p-1, 0x1.fac275b7aca18p-1, 0x1.fafcdde919e0ap-1,
    0x1.fb30bc36574eap-1, 0x1.fb5f1f05c0506p-1, 0x1.fb88dca537e28p-1, 0x1.fbaea138c77fcp-1,
    0x1.fbd0f8afdfd56p-1, 0x1.fbf056056e356p-1, 0x1.fc0d189dccf60p-1, 0x1.fc27904f1062ap-1,
    0x1.fc4000732aab0p-1, 0x1.fc56a245fc9fap-1, 0x1.fc6ba6bdd6338p-1, 0x1.fc7f37ffa3c70p-1,
    0x1.fc917a86de8b0p-1, 0x1.fca28e12ee502p-1, 0x1.fcb28e671ee86p-1, 0x1.fcc193e7060fcp-1,
    0x1.fccfb416d57b2p-1, 0x1.fcdd020554404p-1, 0x1.fce98ea3ed54cp-1, 0x1.fcf569104677ep-1,
    0x1.fd009ed215280p-1, 0x1.fd0b3c0f563d6p-1, 0x1.fd154bb89d1cep-1, 0x1.fd1ed7aed8baep-1,
    0x1.fd27e8e3a8e52p-1, 0x1.fd30877528f48p-1, 0x1.fd38bac5eac76p-1, 0x1.fd408991bb3eep-1,
    0x1.fd47f9ffae7ccp-1, 0x1.fd4f11b1dc64ep-1, 0x1.fd55d5d3244b0p-1, 0x1.fd5c4b23405d4p-1,
    0x1.fd62760165a98p-1, 0x1.fd685a75a3f3cp-1, 0x1.fd6dfc3930a86p-1, 0x1.fd735ebdc19bap-1,
    0x1.fd78853416d24p-1, 0x1.fd7d7291cdfa2p-1, 0x1.fd8229969666ap-1, 0x1.fd86acd0d92c6p-1,
    0x1.fd8afea1e63fcp-1, 0x1.fd8f2141b52f2p-1, 0x1.fd9316c246182p-1, 0x1.fd96e112add68p-1,
    0x1.fd9a8201d6f70p-1, 0x1.fd9dfb40ffc68p-1, 0x1.fda14e65fcc88p-1, 0x1.fda47ced45fb0p-1,
    0x1.fda7883bd4846p-1, 0x1.fdaa71a0d5c00p-1, 0x1.fdad3a5738058p-1, 0x1.fdafe3871506ep-1,
    0x1.fdb26e46fd31ap-1, 0x1.fdb4db9d27194p-1, 0x1.fdb72c80859e8p-1, 0x1.fdb961d9c73a8p-1,
    0x1.fdbb7c84408fcp-1, 0x1.fdbd7d4ec42dap-1, 0x1.fdbf64fc69398p-1, 0x1.fdc134454288ep-1,
    0x1.fdc2ebd7078b4p-1, 0x1.fdc48c55b040ap-1, 0x1.fdc6165c055b0p-1, 0x1.fdc78a7c258a0p-1,
    0x1.fdc8e94000d9ep-1, 0x1.fdca3329caf6ep-1, 0x1.fdcb68b465112p-1, 0x1.fdcc8a53c0100p-1,
    0x1.fdcd987537abep-1, 0x1.fdce937fe6ffep-1, 0x1.fdcf7bd4f7110p-1, 0x1.fdd051cfe7bfcp-1,
    0x1.fdd115c6d38f4p-1, 0x1.fdd1c80aaea2cp-1, 0x1.fdd268e781472p-1, 0x1.fdd2f8a49e5c8p-1,
    0x1.fdd37784d5e5ep-1, 0x1.fdd3e5c6a404ap-1, 0x1.fdd443a45c9b4p-1, 0x1.fdd4915453d06p-1,
    0x1.fdd4cf0903a4ap-1, 0x1.fdd4fcf12eca8p-1, 0x1.fdd51b3800ebcp-1, 0x1.fdd52a052c820p-1,
    0x1.fdd5297d06678p-1, 0x1.fdd519c09f416p-1, 0x1.fdd4faeddadf4p-1, 0x1.fdd4cd1f85ae4p-1,
    0x1.fdd4906d68558p-1, 0x1.fdd444ec5995ep-1, 0x1.fdd3eaae4e7e8p-1, 0x1.fdd381c2690b8p-1,
    0x1.fdd30a35053d6p-1, 0x1.fdd2840fc4bb6p-1, 0x1.fdd1ef59990a4p-1, 0x1.fdd14c16cc688p-1,
    0x1.fdd09a4909566p-1, 0x1.fdcfd9ef60d74p-1, 0x1.fdcf0b064f704p-1, 0x1.fdce2d87c0ef6p-1,
    0x1.fdcd416b12fe2p-1, 0x1.fdcc46a51685cp-1, 0x1.fdcb3d280fe84p-1, 0x1.fdca24e3b610ep-1,
    0x1.fdc8fdc5305e8p-1, 0x1.fdc7c7b71367ap-1, 0x1.fdc682a15c978p-1, 0x1.fdc52e696ca4ap-1,
    0x1.fdc3caf200dc0p-1, 0x1.fdc2581b2b40ep-1, 0x1.fdc0d5c24978cp-1, 0x1.fdbf43c1fa828p-1,
    0x1.fdbda1f213300p-1, 0x1.fdbbf027915a6p-1, 0x1.fdba2e348dca6p-1, 0x1.fdb85be82cca6p-1,
    0x1.fdb6790e8d568p-1, 0x1.fdb48570b6e08p-1, 0x1.fdb280d485992p-1, 0x1.fdb06afc95304p-1,
    0x1.fdae43a829fd0p-1, 0x1.fdac0a93187bap-1, 0x1.fda9bf75ab0dcp-1, 0x1.fda7620485e9ap-1,
    0x1.fda4f1f089208p-1, 0x1.fda26ee6b0a52p-1, 0x1.fd9fd88ff2370p-1, 0x1.fd9d2e9119168p-1,
    0x1.fd9a708a9f62cp-1, 0x1.fd979e1884ffep-1, 0x1.fd94b6d223e22p-1, 0x1.fd91ba4a0196ap-1,
    0x1.fd8ea80d9ddeap-1, 0x1.fd8b7fa53e32ep-1, 0x1.fd884093b5fa8p-1, 0x1.fd84ea562b42ap-1,
    0x1.fd817c63d7bd2p-1, 0x1.fd7df62dc5c7cp-1, 0x1.fd7a571e893a0p-1, 0x1.fd769e99f3af8p-1,
    0x1.fd72cbfcc4028p-1, 0x1.fd6ede9c509f4p-1, 0x1.fd6ad5c62c56ap-1, 0x1.fd66b0bfc5496p-1,
    0x1.fd626ec5fd826p-1, 0x1.fd5e0f0cbcc7ap-1, 0x1.fd5990be7b240p-1, 0x1.fd54f2fbc39e0p-1,
    0x1.fd5034daae834p-1, 0x1.fd4b556652a5cp-1, 0x1.fd46539e2cd4ap-1, 0x1.fd412e757ccf8p-1,
    0x1.fd3be4d296dacp-1, 0x1.fd36758e290ccp-1, 0x1.fd30df7273546p-1, 0x1.fd2b213a711d6p-1,
    0x1.fd253990f363ap-1, 0x1.fd1f270fa9deep-1, 0x1.fd18e83e19d7ap-1, 0x1.fd127b90810cap-1,
    0x1.fd0bdf66a2e78p-1, 0x1.fd05120a7e11ap-1, 0x1.fcfe11aee8486p-1, 0x1.fcf6dc6e0e146p-1,
    0x1.fcef7047d3c74p-1, 0x1.fce7cb2014e04p-1, 0x1.fcdfeabcbe9e6p-1, 0x1.fcd7ccc3c2356p-1,
    0x1.fccf6eb8daaf2p-1, 0x1.fcc6cdfb220f0p-1, 0x1.fcbde7c270d14p-1, 0x1.fcb4b91c82426p-1,
    0x1.fcab3ee9d78f0p-1, 0x1.fca175da52a4ap-1, 0x1.fc975a69812bap-1, 0x1.fc8ce8da8ee6ap-1,
    0x1.fc821d33d5afep-1, 0x1.fc76f33a00056p-1, 0x1.fc6b666ab1a96p-1, 0x1.fc5f71f6a830cp-1,
    0x1.fc5310bb43724p-1, 0x1.fc463d3b63954p-1, 0x1.fc38f19787f34p-1, 0x1.fc2b278517098p-1,
    0x1.fc1cd844b44b2p-1, 0x1.fc0dfc97849e6p-1, 0x1.fbfe8cb33da7ep-1, 0x1.fbee8034d685cp-1,
    0x1.fbddce11aa29ep-1, 0x1.fbcc6c86d3ec8p-1, 0x1.fbba510685f20p-1, 0x1.fba770230e53cp-1,
    0x1.fb93bd77334fap-1, 0x1.fb7f2b8b7f9a2p-1, 0x1.fb69abb805c40p-1, 0x1.fb532e020bd18p-1,
    0x1.fb3ba0f4f5ba6p-1, 0x1.fb22f175a5918p-1, 0x1.fb090a8f611d2p-1, 0x1.faedd5391d066p-1,
    0x1.fad13811d33dap-1, 0x1.fab3171241ea6p-1, 0x1.fa935332168f4p-1, 0x1.fa71c9fe1923ep-1,
    0x1.fa4e551c5e8a2p-1, 0x1.fa28c9bad89ccp-1, 0x1.fa00f7e3b9262p-1, 0x1.f9d6a9b1fd934p-1,
    0x1.f9a9a25f0738ap-1, 0x1.f9799d2044636p-1, 0x1.f9464bc97bd0cp-1, 0x1.f90f552512d4cp-1,
    0x1.f8d452ef5dc62p-1, 0x1.f894cf5c4b7a4p-1, 0x1.f8504206f4492p-1, 0x1.f8060c1fed8b0p-1,
    0x1.f7b573a0817dcp-1, 0x1.f75d9d343ca1ap-1, 0x1.f6fd846cdfcf0p-1, 0x1.f693f1aa6e98cp-1,
    0x1.f61f6ce31721ep-1, 0x1.f59e2c1a6a9b8p-1, 0x1.f50dfbcb697f2p-1, 0x1.f46c1eb03f4e8p-1,
    0x1.f3b520fb7ea14p-1, 0x1.f2e498e9ba1b6p-1, 0x1.f1f4caf064bbcp-1, 0x1.f0de218c6afa8p-1,
    0x1.ef965d8508938p-1, 0x1.ee0f4eaa72d4ap-1, 0x1.ec34bc837472ep-1, 0x1.e9e8d2ac24ab8p-1,
    0x1.e6fdac3ff9632p-1, 0x1.e328e15f4895ap-1, 0x1.dde9702fd9576p-1, 0x1.d64abd3a7ef02p-1,
    0x1.ca3ecfd83dde0p-1, 0x1.b46a9f57b029ap-1, 0x1.8117d31f78d94p-1, 0x0.0p+0,
};
/* f(x_i) = exp(-x_i^2/2), i = 0..256, rounded to nearest. */
static const double zig_f[257] = {
    0x1.f4a946f13842ep-12, 0x1.4a605b6b9f70dp-10, 0x1.55f9f43c1b06fp-9, 0x1.08a1f03b0b205p-8,
    0x1.69ea8d90cb863p-8,  0x1.ce160f8ec683bp-8,  0x1.1a59229952f95p-7, 0x1.4eb96421acfe7p-7,
    0x1.841040d8da47dp-7,  0x1.ba48d274f8fb3p-7,  0x1.f152a4f72dd52p-7, 0x1.1490334603019p-6,
    0x1.30d388dab5e19p-6,  0x1.4d6eaf2fbb066p-6,  0x1.6a5daf40bbf86p-6, 0x1.879d1b600c10ap-6,
    0x1.a529f4e22ebf4p-6,  0x1.c301983cd0911p-6,  0x1.e121adb828c68p-6, 0x1.ff881d718a5b4p-6,
    0x1.0f1982e968008p-5,  0x1.1e9059f1f6ab6p-5,  0x1.2e27ce83df494p-5, 0x1.3ddf2ce98eec6p-5,
    0x1.4db5d0e11275bp-5,  0x1.5dab23cf2add0p-5,  0x1.6dbe9b398d061p-5, 0x1.7defb77af271cp-5,
    0x1.8e3e02a68b5a8p-5,  0x1.9ea90f9295560p-5,  0x1.af30790385f6ep-5, 0x1.bfd3e0f282a2bp-5,
    0x1.d092efeadf161p-5,  0x1.e16d547b25184p-5,  0x1.f262c2b6c6e33p-5, 0x1.01b979e30e495p-4,
    0x1.0a4ed2c159621p-4,  0x1.12f14d0f2179cp-4,  0x1.1ba0cbe97897ep-4, 0x1.245d344dd0d8fp-4,
    0x1.2d266cf9b310dp-4,  0x1.35fc5e4d93e68p-4,  0x1.3edef23269a80p-4, 0x1.47ce1401b2212p-4,
    0x1.50c9b06fa2babp-4,  0x1.59d1b5774669cp-4,  0x1.62e6124854d10p-4, 0x1.6c06b73694a45p-4,
    0x1.753395aaa116dp-4,  0x1.7e6ca013eefcbp-4,  0x1.87b1c9dbf2845p-4, 0x1.9103075a4a09ep-4,
    0x1.9a604dc9d5b0ap-4,  0x1.a3c9933ea627ap-4,  0x1.ad3ece9caf626p-4, 0x1.b6bff78f2e227p-4,
    0x1.c04d0680b1009p-4,  0x1.c9e5f493b7403p-4,  0x1.d38abb9bd91dbp-4, 0x1.dd3b56176e88ap-4,
    0x1.e6f7bf29aa545p-4,  0x1.f0bff29520e15p-4,  0x1.fa93ecb6b222ap-4, 0x1.0239d54067d29p-3,
    0x1.072f94bb8bf83p-3,  0x1.0c2b33d5209b8p-3,  0x1.112cb1da26eb8p-3, 0x1.16340e5a82d62p-3,
    0x1.1b41492757d41p-3,  0x1.2054625183c34p-3,  0x1.256d5a2835eb5p-3, 0x1.2a8c3137a071ap-3,
    0x1.2fb0e847c2a64p-3,  0x1.34db805b4ab88p-3,  0x1.3a0bfaae8d7edp-3, 0x1.3f4258b6931aep-3,
    0x1.447e9c20375d6p-3,  0x1.49c0c6cf5ce2fp-3,  0x1.4f08dade31fc5p-3, 0x1.5456da9c8683ap-3,
    0x1.59aac88f31d74p-3,  0x1.5f04a76f88400p-3,  0x1.64647a2adf1a3p-3, 0x1.69ca43e21f261p-3,
    0x1.6f3607e964718p-3,  0x1.74a7c9c7ab5a7p-3,  0x1.7a1f8d368a323p-3, 0x1.7f9d5621f7173p-3,
    0x1.852128a819a37p-3,  0x1.8aab091928159p-3,  0x1.903afbf74fa68p-3, 0x1.95d105f6a7c26p-3,
    0x1.9b6d2bfd2fe59p-3,  0x1.a10f7322d7e3bp-3,  0x1.a6b7e0b19267bp-3, 0x1.ac667a2571804p-3,
    0x1.b21b452ccd139p-3,  0x1.b7d647a8731aap-3,  0x1.bd9787abe18a1p-3, 0x1.c35f0b7d89d45p-3,
    0x1.c92cd9971df51p-3,  0x1.cf00f8a5e6fc9p-3,  0x1.d4db6f8b2514bp-3, 0x1.dabc455c79005p-3,
    0x1.e0a381645717fp-3,  0x1.e6912b2283cd8p-3,  0x1.ec854a4c99c3dp-3, 0x1.f27fe6ce998cbp-3,
    0x1.f88108cb8322ep-3,  0x1.fe88b89df93bbp-3,  0x1.024b7f6c77479p-2, 0x1.0555f2242e9d4p-2,
    0x1.0863b8f904330p-2,  0x1.0b74d88b242d3p-2,  0x1.0e895598709bdp-2, 0x1.11a134fcf241dp-2,
    0x1.14bc7bb34ee62p-2,  0x1.17db2ed5454e5p-2,  0x1.1afd539c2f04cp-2, 0x1.1e22ef6188112p-2,
    0x1.214c079f7cc9bp-2,  0x1.2478a1f17de86p-2,  0x1.27a8c414db11ap-2, 0x1.2adc73e963fd9p-2,
    0x1.2e13b77210763p-2,  0x1.314e94d5af62cp-2,  0x1.348d125f9d19bp-2, 0x1.37cf368081376p-2,
    0x1.3b1507cf143abp-2,  0x1.3e5e8d08ed2d8p-2,  0x1.41abcd1357a17p-2, 0x1.44fccefc324fbp-2,
    0x1.485199fad6ad3p-2,  0x1.4baa357109ca1p-2,  0x1.4f06a8ebf6d90p-2, 0x1.5266fc2533beap-2,
    0x1.55cb3703d00fcp-2,  0x1.5933619d6eebbp-2,  0x1.5c9f84376c240p-2, 0x1.600fa7480d2c5p-2,
    0x1.6383d377be512p-2,  0x1.66fc11a25cbdep-2,  0x1.6a786ad88de1dp-2, 0x1.6df8e86124ca5p-2,
    0x1.717d93ba96147p-2,  0x1.7506769c7b1e7p-2,  0x1.78939af9252e5p-2, 0x1.7c250aff414abp-2,
    0x1.7fbad11b8d90cp-2,  0x1.8354f7faa0dd4p-2,  0x1.86f38a8ac5ab2p-2, 0x1.8a9693fde9184p-2,
    0x1.8e3e1fcb9f112p-2,  0x1.91ea39b33cb12p-2,  0x1.959aedbe09f8ep-2, 0x1.995048418c0c2p-2,
    0x1.9d0a55e1e93dbp-2,  0x1.a0c923946843ap-2,  0x1.a48cbea20c04ap-2, 0x1.a85534aa4d87cp-2,
    0x1.ac2293a5f5a99p-2,  0x1.aff4e9ea1854fp-2,  0x1.b3cc462b331c6p-2, 0x1.b7a8b78071318p-2,
    0x1.bb8a4d6716d8ep-2,  0x1.bf7117c616a13p-2,  0x1.c35d26f1d2cb4p-2, 0x1.c74e8bb00d7c2p-2,
    0x1.cb45573c0a842p-2,  0x1.cf419b4ae5b68p-2,  0x1.d3436a102107ap-2, 0x1.d74ad6426de2cp-2,
    0x1.db57f320b56a9p-2,  0x1.df6ad47763a02p-2,  0x1.e3838ea5f9b7dp-2, 0x1.e7a236a4ec3bep-2,
    0x1.ebc6e20bd1f4dp-2,  0x1.eff1a717e8f8dp-2,  0x1.f4229cb2f7aebp-2, 0x1.f859da7a900c3p-2,
    0x1.fc9778c7bbd9ap-2,  0x1.006dc85b8cac1p-1,  0x1.02931e18b8227p-1, 0x1.04bbcafa63f2bp-1,
    0x1.06e7dccf03c32p-1,  0x1.091761d995d7dp-1,  0x1.0b4a68d70d9aap-1, 0x1.0d8101041429bp-1,
    0x1.0fbb3a232590ep-1,  0x1.11f9248311f34p-1,  0x1.143ad105ea997p-1, 0x1.16805128639d6p-1,
    0x1.18c9b709b3c4cp-1,  0x1.1b171573fd10dp-1,  0x1.1d687fe549965p-1, 0x1.1fbe0a992961cp-1,
    0x1.2217ca92ff7edp-1,  0x1.2475d5a90db7fp-1,  0x1.26d84290504e8p-1, 0x1.293f28e93cd10p-1,
    0x1.2baaa14d79544p-1,  0x1.2e1ac55ea3be9p-1,  0x1.308fafd6438eap-1, 0x1.33097c9703a31p-1,
    0x1.358848bf550e5p-1,  0x1.380c32bda00d2p-1,  0x1.3a955a662cd0ap-1, 0x1.3d23e10af31a0p-1,
    0x1.3fb7e99585b7ep-1,  0x1.425198a355fdfp-1,  0x1.44f114a493675p-1, 0x1.479685fdf500ep-1,
    0x1.4a42172dc5275p-1,  0x1.4cf3f4f494ebdp-1,  0x1.4fac4e820b664p-1, 0x1.526b55a656cd2p-1,
    0x1.55313f08d9e43p-1,  0x1.57fe4264c8d8bp-1,  0x1.5ad29acc85c84p-1, 0x1.5dae86f4aff65p-1,
    0x1.6092498802660p-1,  0x1.637e298550c14p-1,  0x1.667272a92e31ep-1, 0x1.696f75e513b25p-1,
    0x1.6c7589e635a84p-1,  0x1.6f850baea7ae9p-1,  0x1.729e5f43f6d0dp-1, 0x1.75c1f0770d851p-1,
    0x1.78f033ca0b0d0p-1,  0x1.7c29a779c6854p-1,  0x1.7f6ed4b20e2c7p-1, 0x1.82c050f56cf69p-1,
    0x1.861ebfc37bca6p-1,  0x1.898ad48badefdp-1,  0x1.8d0554fe60aa3p-1, 0x1.908f1bd31714ap-1,
    0x1.94291c21b7a42p-1,  0x1.97d4657617abcp-1,  0x1.9b9228d24067dp-1, 0x1.9f63bee651fd3p-1,
    0x1.a34aafdf5af0ap-1,  0x1.a748bd550c9ddp-1,  0x1.ab5fef17a2500p-1, 0x1.af92a3f6ce89ep-1,
    0x1.b3e3a8234dd0cp-1,  0x1.b85653a8ff54dp-1,  0x1.bceeb4ee1dc7dp-1, 0x1.c1b1cd9eebae5p-1,
    0x1.c6a5ecea9787ap-1,  0x1.cbd33a8a72de6p-1,  0x1.d144978a119d7p-1, 0x1.d70920657bcedp-1,
    0x1.dd36fa704de90p-1,  0x1.e3f11e027f071p-1,  0x1.eb7545b6ca90fp-1, 0x1.f446ac979f080p-1,
    0x1.0000000000000p+0,
};

/* ---- Philox key, counter and the scalar reference -------------------------------------------- */

/* MurmurHash3's 32-bit finaliser: a bijection that spreads small stream numbers over the word. */
static uint32_t fmix32(uint32_t h)
{
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

static philox4x32_key_t make_key(uint64_t seed, uint32_t stream, uint32_t kind)
{
    philox4x32_key_t k = {{(uint32_t)seed, (uint32_t)(seed >> 32) ^ fmix32(2u * stream + kind)}};
    return k;
}

/* Everything a normal variate depends on besides (id, component). */
struct gen {
    philox4x32_key_t key;
    uint32_t s0, s1; /* step, low and high word */
};

static struct gen make_gen(uint64_t seed, uint32_t stream, uint64_t step)
{
    struct gen g = {make_key(seed, stream, KIND_NORMAL), (uint32_t)step, (uint32_t)(step >> 32)};
    return g;
}

/* One block of Random123's philox4x32 (10 rounds) with counter (step, pair, w3), as two words. */
static void block(const struct gen *g, uint32_t pair, uint32_t w3, uint64_t *a, uint64_t *b)
{
    philox4x32_ctr_t ctr = {{g->s0, g->s1, pair, w3}};
    philox4x32_ctr_t r = philox4x32(ctr, g->key);
    *a = r.v[0] | (uint64_t)r.v[1] << 32;
    *b = r.v[2] | (uint64_t)r.v[3] << 32;
}

/* Counter word 3 of retry r of the variate (lane, c) of a pair: c | lane << 1 | r << 2 for the
 * components 0 and 1 of 1D and 2D; the third component of 3D (c = 2) sets bit 30 instead of bit 0
 * (see "Counter" at the top). */
static inline uint32_t retry_w3(uint32_t lane, uint32_t c, uint32_t r)
{
    return (c & 1u) | lane << 1 | r << 2 | (c >> 1) << 30;
}

/* ---- Ziggurat, scalar ------------------------------------------------------------------------ */

#define ZIG_MANT UINT64_C(0x000fffffffffffff)
#define ZIG_ONE UINT64_C(0x3ff0000000000000) /* 1.0 */
#define ZIG_SIGN UINT64_C(0x8000000000000000)

static const double zig_r = 0x1.d3bb48209ad33p+1; /* R = 3.6541528853610088 = zig_x[1] */

static inline double from_bits(uint64_t b)
{
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

static inline uint64_t to_bits(double d)
{
    uint64_t b;
    memcpy(&b, &d, sizeof b);
    return b;
}

/* Bits 11-62 of w as a uniform on the 2^-52 grid in [0, 1) (1 + u is exact, and so is - 1). */
static inline double u52(uint64_t w) { return from_bits((w >> 11 & ZIG_MANT) | ZIG_ONE) - 1.0; }
/* The top 53 bits as a uniform on [0, 1), and on (0, 1] for logarithms. */
static inline double u53(uint64_t w) { return (double)(w >> 11) * 0x1p-53; }
static inline double u53_open0(uint64_t w) { return (double)((w >> 11) + 1) * 0x1p-53; }
/* x with the sign bit of w (bit 63). */
static inline double with_sign(double x, uint64_t w)
{
    return from_bits(to_bits(x) ^ (w & ZIG_SIGN));
}

/* The fast path for the word w: the signed candidate, and whether it is accepted. */
static inline double zig_fast(uint64_t w, int *ok)
{
    unsigned i = (unsigned)(w & 0xffu);
    double u = u52(w);
    *ok = u < zig_t[i];
    return with_sign(u * zig_x[i], w);
}

/* The rest of the ziggurat for the variate (pair, lane, c) whose word w failed the fast test;
 * (a, b) is its retry block r = 1, further retries are drawn here. */
static double zig_slow(const struct gen *g, uint32_t pair, uint32_t lane, uint32_t c, uint64_t w,
                       uint64_t a, uint64_t b)
{
    uint32_t r = 1;
    for (;;) {
        unsigned i = (unsigned)(w & 0xffu);
        if (i == 0) {
            /* Beyond R (Marsaglia 1964): x = R + e1/R is accepted with probability
             * exp(-(e1/R)^2/2), i.e. when 2 e2 > (e1/R)^2 for a second exponential e2. */
            for (;;) {
                double t = -log(u53_open0(a)) / zig_r;
                double e = -log(u53_open0(b));
                if (e + e > t * t) {
                    return with_sign(zig_r + t, w);
                }
                block(g, pair, retry_w3(lane, c, ++r), &a, &b);
            }
        }
        /* The wedge of layer i: a uniform height between f(x_i) and f(x_{i+1}) against f(x). */
        double x = u52(w) * zig_x[i];
        if (zig_f[i] + u53(a) * (zig_f[i + 1] - zig_f[i]) < exp(-0.5 * x * x)) {
            return with_sign(x, w);
        }
        w = b; /* start over with the block's second word */
        int ok;
        x = zig_fast(w, &ok);
        if (ok) {
            return x;
        }
        block(g, pair, retry_w3(lane, c, ++r), &a, &b);
    }
}

enum {
    CHUNK = 256, /* pairs per batch: up to 4 CHUNK variates; a multiple of every vector width */
    RETRIES = 64 /* rejected variates finished together */
};

/* ---- Philox and the fast path on vectors ----------------------------------------------------- */

/* The counters of one batch differ only in words 2 (pair) and, for retries, 3; the step (words
 * 0, 1) is shared, and so is word 3 for first draws. The parts of the first rounds that involve
 * only shared words are done once here. Random123's round is
 *   (c0, c1, c2, c3) -> (hi(M1 c2) ^ c1 ^ ka, lo(M1 c2), hi(M0 c0) ^ c3 ^ kb, lo(M0 c0))
 * with the key (ka, kb) bumped by the Weyl constants (W0, W1) after each round. */
struct prep {
    struct gen g;
    uint32_t c;              /* component: counter word 3 of first draws */
    uint32_t ka[10], kb[10]; /* round keys */
    uint32_t x0;             /* round 0: c0 = hi(M1 c2) ^ x0 */
    uint32_t y0;             /* round 0: c2 = w3 ^ y0; c3 = lo(M0 s0) */
    uint32_t x1;             /* round 1, w3 = c: c0 = c1 ^ x1 */
    uint32_t x2;             /* round 1: c2 = hi(M0 c0) ^ x2, c3 = lo(M0 c0) */
    uint32_t x3;             /* round 2, w3 = c: c0 = hi(M1 c2) ^ x3 */
};

static void prepare(const struct gen *g, uint32_t c, struct prep *p)
{
    p->g = *g;
    p->c = c;
    uint32_t a = g->key.v[0], b = g->key.v[1];
    for (int r = 0; r < 10; r++) {
        p->ka[r] = a;
        p->kb[r] = b;
        a += PHILOX_W32_0;
        b += PHILOX_W32_1;
    }
    uint64_t q0 = (uint64_t)PHILOX_M4x32_0 * g->s0; /* round 0 */
    p->x0 = g->s1 ^ p->ka[0];
    p->y0 = (uint32_t)(q0 >> 32) ^ p->kb[0];
    uint64_t q1 = (uint64_t)PHILOX_M4x32_1 * (c ^ p->y0); /* round 1 when w3 = c */
    p->x1 = (uint32_t)(q1 >> 32) ^ p->ka[1];
    p->x2 = (uint32_t)q0 ^ p->kb[1];
    p->x3 = (uint32_t)q1 ^ p->ka[2];
}

/* In the vector code each 64-bit lane holds one 32-bit counter word in its low half. The high
 * halves carry garbage that never reaches a low half: the multiplication (pmuludq) reads only the
 * low halves, and hi(q) is taken by swapping the halves of q rather than shifting. Per width:
 * MUL = 32x32->64 multiplication, SWAP = swap the halves of each lane, WORD(a, b) = the low half
 * of a with the low half of b above it, GE = u >= t as a bit mask. */
#define PHILOX_ROUND(MUL, SWAP, c0, c1, c2, c3, ka, kb)                                            \
    do {                                                                                           \
        __typeof__(c0) q0_ = MUL(c0, m0v), q1_ = MUL(c2, m1v);                                     \
        c0 = SWAP(q1_) ^ c1 ^ (ka);                                                                \
        c1 = q1_;                                                                                  \
        c2 = SWAP(q0_) ^ c3 ^ (kb);                                                                \
        c3 = q0_;                                                                                  \
    } while (0)

/* Blocks (step, pair, p->c) for a vector of pairs: w0, w1 = their words 0 and 1. */
#define PHILOX_FIRST(VT, MUL, SWAP, WORD, p, pair, w0, w1)                                         \
    do {                                                                                           \
        VT q_ = MUL(pair, m1v);                                                                    \
        VT c0_ = SWAP(q_) ^ (p)->x0, c1_ = q_, c2_, c3_;                                           \
        q_ = MUL(c0_, m0v); /* round 1: the c2 half is shared */                                   \
        c0_ = c1_ ^ (p)->x1;                                                                       \
        c2_ = SWAP(q_) ^ (p)->x2;                                                                  \
        c3_ = q_;                                                                                  \
        c1_ = (VT){0}; /* round 2 reads it only through x3 */                                      \
        PHILOX_ROUND(MUL, SWAP, c0_, c1_, c2_, c3_, (p)->x3, (p)->kb[2]);                          \
        for (int r_ = 3; r_ < 10; r_++) {                                                          \
            PHILOX_ROUND(MUL, SWAP, c0_, c1_, c2_, c3_, (p)->ka[r_], (p)->kb[r_]);                 \
        }                                                                                          \
        (w0) = WORD(c0_, c1_);                                                                     \
        (w1) = WORD(c2_, c3_);                                                                     \
    } while (0)

/* zig_x[i] and zig_t[i] side by side, so one 16-byte load and store moves both (filled once, in
 * pick_kernels). */
static _Alignas(64) double zig_xt[2 * 256];

/* The ziggurat's table look-ups for the words w[0..nk): xt[2k] = zig_x[i], xt[2k+1] = zig_t[i]
 * with i = w[k] & 0xff. Scalar loads on purpose: on AMD Zen 4 a vector gather of 8 doubles costs
 * more than 8 loads, and the gathers were the largest single cost of the fast path
 * (docs/performance.md, "Random force generator"). Kept out of line and unvectorised so the
 * compiler does not turn the loop back into gathers. */
__attribute__((noinline, optimize("no-tree-vectorize"))) static void zig_lookup(
    const uint64_t *restrict w, int nk, double *restrict xt)
{
    for (int k = 0; k < nk; k++) {
        const unsigned i = (unsigned)(w[k] & 0xffu);
        memcpy(xt + 2 * k, zig_xt + 2 * i, 2 * sizeof *xt);
    }
}

/* The fast path on the words w[0..nk) (nk a multiple of the vector width L) with their looked-up
 * pairs xt: the candidates go to z, and bit k of bad[] is set where the fast test failed. EVEN and
 * ODD pick the x and t halves out of two vectors of pairs. */
#define ZIG_PASS(VT, VD, GE, EVEN, ODD, nk, w, xt, z, bad)                                         \
    do {                                                                                           \
        enum { L_ = sizeof(VT) / 8 };                                                              \
        for (int k_ = 0; k_ < (nk); k_ += L_) {                                                    \
            VT wv_, p0_, p1_;                                                                      \
            memcpy(&wv_, (w) + k_, sizeof wv_);                                                    \
            memcpy(&p0_, (xt) + 2 * k_, sizeof p0_);                                               \
            memcpy(&p1_, (xt) + 2 * k_ + L_, sizeof p1_);                                          \
            VD xv_ = (VD)SHUF(p0_, p1_, EVEN), tv_ = (VD)SHUF(p0_, p1_, ODD);                      \
            VD u_ = (VD)((wv_ >> 11 & ZIG_MANT) | ZIG_ONE) - 1.0;                                  \
            VT s_ = (VT)(u_ * xv_) ^ (wv_ & ZIG_SIGN);                                             \
            memcpy((z) + k_, &s_, sizeof s_);                                                      \
            (bad)[k_ >> 6] |= GE(u_, tv_) << (k_ & 63);                                            \
        }                                                                                          \
    } while (0)

/* One batch: pairs pair0 .. pair0+m-1 (m rounded up to the vector width L), components
 * 0 .. per-1, in output order k = 2 per j + per lane + c (j = pair - pair0): z[k] the fast-path
 * candidate, w[k] its word, bit k of bad[] (zeroed by the caller) set if zig_slow must finish it.
 * ILV_LO/HI interleave two vectors one element at a time, PAIR_LO/HI two elements at a time. */
#define BATCH_KERNEL(NAME, TARGET, VT, VD, MUL, SWAP, WORD, GE, IOTA, ILV_LO, ILV_HI, PAIR_LO,     \
                     PAIR_HI, EVEN, ODD)                                                           \
    TARGET static void NAME(const struct prep *p, int per, uint32_t pair0, int m,                  \
                            uint64_t *restrict w, double *restrict z, uint64_t *restrict bad)      \
    {                                                                                              \
        enum { L = sizeof(VT) / 8 };                                                               \
        const VT m0v = (VT){0} + PHILOX_M4x32_0, m1v = (VT){0} + PHILOX_M4x32_1;                   \
        for (int j = 0; j < m; j += L) {                                                           \
            VT pair = IOTA + (pair0 + (uint32_t)j), a0, a1;                                        \
            PHILOX_FIRST(VT, MUL, SWAP, WORD, &p[0], pair, a0, a1);                                \
            int k = 2 * per * j;                                                                   \
            if (per == 1) {                                                                        \
                VT o0 = SHUF(a0, a1, ILV_LO), o1 = SHUF(a0, a1, ILV_HI);                           \
                memcpy(w + k, &o0, sizeof o0);                                                     \
                memcpy(w + k + L, &o1, sizeof o1);                                                 \
            } else {                                                                               \
                VT b0, b1;                                                                         \
                PHILOX_FIRST(VT, MUL, SWAP, WORD, &p[1], pair, b0, b1);                            \
                VT pl = SHUF(a0, b0, ILV_LO), ph = SHUF(a0, b0, ILV_HI);                           \
                VT ql = SHUF(a1, b1, ILV_LO), qh = SHUF(a1, b1, ILV_HI);                           \
                VT o0 = SHUF(pl, ql, PAIR_LO), o1 = SHUF(pl, ql, PAIR_HI);                         \
                VT o2 = SHUF(ph, qh, PAIR_LO), o3 = SHUF(ph, qh, PAIR_HI);                         \
                memcpy(w + k, &o0, sizeof o0);                                                     \
                memcpy(w + k + L, &o1, sizeof o1);                                                 \
                memcpy(w + k + 2 * L, &o2, sizeof o2);                                             \
                memcpy(w + k + 3 * L, &o3, sizeof o3);                                             \
            }                                                                                      \
        }                                                                                          \
        const int nk = 2 * per * ((m + L - 1) / L * L);                                            \
        _Alignas(64) double xt[8 * CHUNK];                                                         \
        zig_lookup(w, nk, xt);                                                                     \
        ZIG_PASS(VT, VD, GE, EVEN, ODD, nk, w, xt, z, bad);                                        \
    }

/* First retry blocks (step, pair[i], w3[i]) for i < cnt (rounded up to L): words a[i], b[i]. */
#define RETRY_KERNEL(NAME, TARGET, VT, MUL, SWAP, WORD)                                            \
    TARGET static void NAME(const struct prep *p, int cnt, const uint64_t *pair,                   \
                            const uint64_t *w3, uint64_t *restrict a, uint64_t *restrict b)        \
    {                                                                                              \
        const VT m0v = (VT){0} + PHILOX_M4x32_0, m1v = (VT){0} + PHILOX_M4x32_1;                   \
        for (int i = 0; i < cnt; i += (int)(sizeof(VT) / 8)) {                                     \
            VT c0, c1, c2, c3, q;                                                                  \
            memcpy(&c2, pair + i, sizeof c2);                                                      \
            memcpy(&c3, w3 + i, sizeof c3);                                                        \
            q = MUL(c2, m1v); /* round 0: the c0 half is shared */                                 \
            c0 = SWAP(q) ^ p->x0;                                                                  \
            c1 = q;                                                                                \
            c2 = c3 ^ p->y0;                                                                       \
            c3 = (VT){0} + (p->x2 ^ p->kb[1]); /* lo(M0 s0): round 1 xors kb[1] back in */         \
            for (int r = 1; r < 10; r++) {                                                         \
                PHILOX_ROUND(MUL, SWAP, c0, c1, c2, c3, p->ka[r], p->kb[r]);                       \
            }                                                                                      \
            VT wa = WORD(c0, c1), wb = WORD(c2, c3);                                               \
            memcpy(a + i, &wa, sizeof wa);                                                         \
            memcpy(b + i, &wb, sizeof wb);                                                         \
        }                                                                                          \
    }

#define UNPAREN(...) __VA_ARGS__
#if defined(__clang__)
#define SHUF(a, b, idx) __builtin_shufflevector(a, b, UNPAREN idx)
#else
#define SHUF(a, b, idx) __builtin_shuffle(a, b, (__typeof__(a)){UNPAREN idx})
#endif

typedef void batch_fn(const struct prep *p, int per, uint32_t pair0, int m, uint64_t *restrict w,
                      double *restrict z, uint64_t *restrict bad);
typedef void retry_fn(const struct prep *p, int cnt, const uint64_t *pair, const uint64_t *w3,
                      uint64_t *restrict a, uint64_t *restrict b);

#if NOISE_X86
typedef uint64_t v2u __attribute__((vector_size(16)));
typedef uint64_t v4u __attribute__((vector_size(32)));
typedef uint64_t v8u __attribute__((vector_size(64)));
typedef double v2d __attribute__((vector_size(16)));
typedef double v4d __attribute__((vector_size(32)));
typedef double v8d __attribute__((vector_size(64)));

#define MUL2(a, b) ((v2u)_mm_mul_epu32((__m128i)(a), (__m128i)(b)))
#define SWAP2(a) ((v2u)_mm_shuffle_epi32((__m128i)(a), 0xb1))
#define WORD2(a, b) (((a)&0xffffffffu) | (b) << 32)
#define GE2(u, t) ((uint64_t)_mm_movemask_pd(_mm_cmpge_pd((__m128d)(u), (__m128d)(t))))

#define MUL4(a, b) ((v4u)_mm256_mul_epu32((__m256i)(a), (__m256i)(b)))
#define SWAP4(a) ((v4u)_mm256_shuffle_epi32((__m256i)(a), 0xb1))
#define WORD4(a, b) ((v4u)_mm256_blend_epi32((__m256i)(a), (__m256i)SWAP4(b), 0xaa))
#define GE4(u, t)                                                                                  \
    ((uint64_t)_mm256_movemask_pd(_mm256_cmp_pd((__m256d)(u), (__m256d)(t), _CMP_GE_OQ)))

#define MUL8(a, b) ((v8u)_mm512_mul_epu32((__m512i)(a), (__m512i)(b)))
#define SWAP8(a) ((v8u)_mm512_shuffle_epi32((__m512i)(a), _MM_PERM_CDAB))
#define WORD8(a, b) ((v8u)_mm512_mask_blend_epi32(0xaaaa, (__m512i)(a), (__m512i)SWAP8(b)))
#define GE8(u, t) ((uint64_t)_mm512_cmp_pd_mask((__m512d)(u), (__m512d)(t), _CMP_GE_OQ))

#define SSE2 __attribute__((target("sse2")))
#define AVX2 __attribute__((target("avx2")))
#define AVX512 __attribute__((target("avx512f")))
BATCH_KERNEL(batch_sse2, SSE2, v2u, v2d, MUL2, SWAP2, WORD2, GE2, ((v2u){0, 1}), (0, 2), (1, 3),
             (0, 1), (2, 3), (0, 2), (1, 3))
BATCH_KERNEL(batch_avx2, AVX2, v4u, v4d, MUL4, SWAP4, WORD4, GE4, ((v4u){0, 1, 2, 3}), (0, 4, 1, 5),
             (2, 6, 3, 7), (0, 1, 4, 5), (2, 3, 6, 7), (0, 2, 4, 6), (1, 3, 5, 7))
BATCH_KERNEL(batch_avx512, AVX512, v8u, v8d, MUL8, SWAP8, WORD8, GE8,
             ((v8u){0, 1, 2, 3, 4, 5, 6, 7}), (0, 8, 1, 9, 2, 10, 3, 11),
             (4, 12, 5, 13, 6, 14, 7, 15), (0, 1, 8, 9, 2, 3, 10, 11), (4, 5, 12, 13, 6, 7, 14, 15),
             (0, 2, 4, 6, 8, 10, 12, 14), (1, 3, 5, 7, 9, 11, 13, 15))
RETRY_KERNEL(retry_sse2, SSE2, v2u, MUL2, SWAP2, WORD2)
RETRY_KERNEL(retry_avx2, AVX2, v4u, MUL4, SWAP4, WORD4)
RETRY_KERNEL(retry_avx512, AVX512, v8u, MUL8, SWAP8, WORD8)
#endif

/* Portable fallback with the same output: Random123's philox4x32, one block at a time. */
static inline void zig_store(uint64_t wk, int k, uint64_t *restrict w, double *restrict z,
                             uint64_t *restrict bad)
{
    int ok;
    z[k] = zig_fast(wk, &ok);
    w[k] = wk;
    bad[k >> 6] |= (uint64_t)!ok << (k & 63);
}

static void batch_scalar(const struct prep *p, int per, uint32_t pair0, int m, uint64_t *restrict w,
                         double *restrict z, uint64_t *restrict bad)
{
    for (int j = 0; j < m; j++) {
        for (int c = 0; c < per; c++) {
            uint64_t a, b;
            block(&p[c].g, pair0 + (uint32_t)j, p[c].c, &a, &b);
            zig_store(a, 2 * per * j + c, w, z, bad);
            zig_store(b, 2 * per * j + per + c, w, z, bad);
        }
    }
}

static void retry_scalar(const struct prep *p, int cnt, const uint64_t *pair, const uint64_t *w3,
                         uint64_t *restrict a, uint64_t *restrict b)
{
    for (int i = 0; i < cnt; i++) {
        block(&p->g, (uint32_t)pair[i], (uint32_t)w3[i], a + i, b + i);
    }
}

/* ---- Dispatch -------------------------------------------------------------------------------- */

static struct {
    batch_fn *batch;
    retry_fn *retry;
} kern;
static once_flag kern_once = ONCE_FLAG_INIT;

static void pick_kernels(void)
{
    enum { ISA_SCALAR, ISA_SSE2, ISA_AVX2, ISA_AVX512 };
    int best = ISA_SCALAR;
#if NOISE_X86
    __builtin_cpu_init();
    best = ISA_SSE2; /* part of x86-64 */
    if (__builtin_cpu_supports("avx2")) {
        best = ISA_AVX2;
    }
    if (__builtin_cpu_supports("avx512f")) {
        best = ISA_AVX512;
    }
#endif
    const char *cap = getenv("GRANULE_NOISE_ISA");
    if (cap != NULL) {
        static const char *const names[] = {"scalar", "sse2", "avx2", "avx512"};
        for (int i = 0; i < 4; i++) {
            if (strcmp(cap, names[i]) == 0 && i < best) {
                best = i;
            }
        }
    }
    for (int i = 0; i < 256; i++) {
        zig_xt[2 * i] = zig_x[i];
        zig_xt[2 * i + 1] = zig_t[i];
    }
    kern.batch = batch_scalar;
    kern.retry = retry_scalar;
#if NOISE_X86
    if (best == ISA_SSE2) {
        kern.batch = batch_sse2;
        kern.retry = retry_sse2;
    } else if (best == ISA_AVX2) {
        kern.batch = batch_avx2;
        kern.retry = retry_avx2;
    } else if (best == ISA_AVX512) {
        kern.batch = batch_avx512;
        kern.retry = retry_avx512;
    }
#endif
}

/* ---- Public functions ------------------------------------------------------------------------ */

/* Finish the rejected variates k of a batch (pairs from p): rk[i] their output positions. */
static void finish(const struct prep *prep, int per, uint32_t p, int cnt, const int *rk,
                   const uint64_t *w, double *z)
{
    _Alignas(64) uint64_t pair[RETRIES], w3[RETRIES], a[RETRIES], b[RETRIES];
    for (int i = 0; i < cnt; i++) {
        int v = rk[i] / per; /* 2 (pair - p) + lane */
        pair[i] = p + (uint32_t)(v >> 1);
        w3[i] = retry_w3((uint32_t)v & 1u, prep[rk[i] % per].c, 1);
    }
    for (int i = cnt; i < RETRIES; i++) { /* the vector kernels run over whole vectors */
        pair[i] = w3[i] = 0;
    }
    kern.retry(prep, cnt, pair, w3, a, b);
    for (int i = 0; i < cnt; i++) {
        int v = rk[i] / per;
        z[rk[i]] = zig_slow(&prep->g, (uint32_t)pair[i], (uint32_t)v & 1u, prep[rk[i] % per].c,
                            w[rk[i]], a[i], b[i]);
    }
}

/* The normals of ids first .. first+n-1 for the per = 1 or 2 components prep[0 .. per-1]
 * (prep[c].c: which component; gr_noise_normals). */
static void normals(const struct prep *prep, uint32_t first, int n, int per, double *out);

/* per = 3 (spheres): components 0 and 1 as per = 2, component 2 as per = 1 under prep[2] (its
 * own counter words), interleaved in pieces. */
static void normals3(const struct prep *prep, uint32_t first, int n, double *out)
{
    enum { PIECE = 512 };
    double xy[2 * PIECE], zs[PIECE];
    for (int k = 0; k < n; k += PIECE) {
        const int m = n - k < PIECE ? n - k : PIECE;
        normals(prep, first + (uint32_t)k, m, 2, xy);
        normals(prep + 2, first + (uint32_t)k, m, 1, zs);
        for (int i = 0; i < m; i++) {
            out[3 * (size_t)(k + i)] = xy[2 * i];
            out[3 * (size_t)(k + i) + 1] = xy[2 * i + 1];
            out[3 * (size_t)(k + i) + 2] = zs[i];
        }
    }
}

void gr_noise_normals(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n, int per,
                      double *out)
{
    assert(per >= 1 && per <= 3);
    assert(n <= 0 || (uint64_t)first + (uint64_t)n - 1 <= UINT32_MAX);
    if (n <= 0 || per < 1 || per > 3) {
        return;
    }
    call_once(&kern_once, pick_kernels);
    struct gen g = make_gen(seed, stream, step);
    struct prep prep[3];
    for (int c = 0; c < per; c++) {
        prepare(&g, (uint32_t)c, &prep[c]);
    }
    if (per == 3) {
        normals3(prep, first, n, out);
    } else {
        normals(prep, first, n, per, out);
    }
}

static void normals(const struct prep *prep, uint32_t first, int n, int per, double *out)
{
    _Alignas(64) uint64_t w[4 * CHUNK];
    _Alignas(64) double z[4 * CHUNK];
    uint64_t bad[4 * CHUNK / 64];
    int rk[RETRIES];
    const uint64_t end = (uint64_t)first + (uint64_t)n; /* one past the last id */
    for (uint64_t id = first; id < end;) {
        /* the batch: ids 2p .. id_end-1, of which id .. id_end-1 are wanted */
        uint32_t p = (uint32_t)(id >> 1);
        uint64_t id_end = 2 * ((uint64_t)p + CHUNK);
        if (id_end > end) {
            id_end = end;
        }
        int m = (int)((id_end - 2 * (uint64_t)p + 1) >> 1);
        int k_lo = (int)(id - 2 * (uint64_t)p) * per, k_hi = (int)(id_end - 2 * (uint64_t)p) * per;
        /* a whole batch that starts at an even id is written straight into out */
        int whole = k_lo == 0 && k_hi == 2 * per * CHUNK;
        double *zb = whole ? out + (id - first) * (uint64_t)per : z;
        memset(bad, 0, sizeof bad);
        kern.batch(prep, per, p, m, w, zb, bad);
        /* the retries in increasing order, RETRIES at a time (the hot path: a plain bit loop) */
        int cnt = 0;
        for (int i = k_lo >> 6; i <= (k_hi - 1) >> 6; i++) {
            for (uint64_t bits = bad[i]; bits != 0; bits &= bits - 1) {
                const int k = 64 * i + __builtin_ctzll(bits);
                if (k >= k_lo && k < k_hi) {
                    rk[cnt++] = k;
                    if (cnt == RETRIES) {
                        finish(prep, per, p, cnt, rk, w, zb);
                        cnt = 0;
                    }
                }
            }
        }
        if (cnt > 0) {
            finish(prep, per, p, cnt, rk, w, zb);
        }
        if (zb == z) {
            memcpy(out + (id - first) * (uint64_t)per, z + k_lo, (size_t)(k_hi - k_lo) * sizeof *z);
        }
        id = id_end;
    }
}

double gr_noise_normal1(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id, int component)
{
    assert(component >= 0 && component <= 2);
    struct gen g = make_gen(seed, stream, step);
    uint32_t pair = id >> 1, lane = id & 1u, c = (uint32_t)component % 3u;
    uint64_t a, b;
    block(&g, pair, c, &a, &b);
    uint64_t w = lane ? b : a;
    int ok;
    double x = zig_fast(w, &ok);
    if (ok) {
        return x;
    }
    block(&g, pair, retry_w3(lane, c, 1), &a, &b);
    return zig_slow(&g, pair, lane, c, w, a, b);
}

double gr_noise_uniform(uint64_t seed, uint32_t stream, uint64_t a, uint64_t b)
{
    philox4x32_ctr_t ctr = {{(uint32_t)a, (uint32_t)(a >> 32), (uint32_t)b, (uint32_t)(b >> 32)}};
    philox4x32_ctr_t r = philox4x32(ctr, make_key(seed, stream, KIND_UNIFORM));
    return u53(r.v[0] | (uint64_t)r.v[1] << 32);
}

/* ---- Single-precision normals ([noise] precision = single) ----------------------------------- *
 *
 * Same key as the double normals (make_key(seed, stream, KIND_NORMAL)); counter (step low, step
 * high, quad, F32_FLAG | c) for component c. Bit 31 of word 3 is never set by the double path (its
 * word 3 is c | lane << 1 | r << 2 with r < 2^29), so the two paths never share a block. The
 * generator is Philox4x32-7 (F32_ROUNDS = 7; Random123's philox4x32_R(7, ...)), which passes
 * TestU01's BigCrush as Philox4x32-10 does (Salmon et al., SC'11; ten is their default,
 * for a safety margin): three rounds fewer cut the path's cost per normal by about a fifth.
 * Each block gives four 32-bit words, one normal each: ids are taken in groups of 4 F32_QUADS,
 * and id = F32_GROUP g + F32_QUADS l + j uses word l of quad F32_QUADS g + j.
 *
 * Transform: one word, one normal, no rejection, no table look-up in memory. Bit 31 is the sign;
 * k = bits 0-30 give q = (k + 1/2) 2^-31 in (0, 1) (rounded to float, at most 1 - 2^-24), and
 * |z| = g(q) = Phi^-1(1 - q/2), the inverse CDF of the half-normal, so P(|z| > g(q)) = q up to the
 * 2^-31 grid. g is a degree-F32_DEG polynomial in t = m - 3/2 on each octave q = m 2^e, m in
 * [1, 2), e = -32 .. -1 (32 octaves: the coefficients f32_icdf_c[j][e & 31], fitted by
 * bench/f32_icdf_fit.py, Chebyshev least squares against scipy's ndtri, rounded to float); the
 * AVX-512 kernel picks them with two-register permutes (vpermt2ps), so it has no gathers and no
 * branch. |z - exact| < 5e-7 for every word, and |z| never rises with k (checked over all 2^31
 * words; tests/test_noise.c checks samples against GSL's quantile). Truncation: the largest |z|
 * is g(2^-32) = 6.3380 (k = 0), and N(0, 1) exceeds it with probability 2^-32 = 2.3e-10, so a
 * run of 1e12 normals misses some 230 of them. The portable loop (f32_group_c)
 * computes the same thing with frexpf and fmaf, so both give the same bits. */

enum { F32_QUADS = 256, F32_GROUP = 4 * F32_QUADS, F32_DEG = 7, F32_ROUNDS = 7 };
#define F32_FLAG 0x80000000u

static _Alignas(64) const float f32_icdf_c[F32_DEG + 1][32] = {
    {
        /* t^0 */
        0x1.919c6ep+2f, 0x1.8aa6c8p+2f, 0x1.8392aap+2f, 0x1.7c5e7cp+2f, 0x1.750884p+2f,
        0x1.6d8ed8p+2f, 0x1.65ef68p+2f, 0x1.5e27e8p+2f, 0x1.5635dp+2f,  0x1.4e1654p+2f,
        0x1.45c658p+2f, 0x1.3d425ap+2f, 0x1.348672p+2f, 0x1.2b8e2ep+2f, 0x1.225482p+2f,
        0x1.18d3a6p+2f, 0x1.0f04ecp+2f, 0x1.04e092p+2f, 0x1.f4baep+1f,  0x1.dee15cp+1f,
        0x1.c81a78p+1f, 0x1.b0465p+1f,  0x1.973d58p+1f, 0x1.7ccd7ap+1f, 0x1.60b5d2p+1f,
        0x1.429fdp+1f,  0x1.2213b8p+1f, 0x1.fcc812p+0f, 0x1.ad0a62p+0f, 0x1.516928p+0f,
        0x1.c6381p-1f,  0x1.46496p-2f,
    },
    {
        /* t^1 */
        -0x1.a8da82p-4f, -0x1.afff76p-4f, -0x1.b78276p-4f, -0x1.bf6bc6p-4f, -0x1.c7c4bap-4f,
        -0x1.d097dcp-4f, -0x1.d9f12cp-4f, -0x1.e3de58p-4f, -0x1.ee6f18p-4f, -0x1.f9b59p-4f,
        -0x1.02e368p-3f, -0x1.095dbap-3f, -0x1.10583ep-3f, -0x1.17e424p-3f, -0x1.2015fep-3f,
        -0x1.2906a8p-3f, -0x1.32d478p-3f, -0x1.3da4e8p-3f, -0x1.49a6e4p-3f, -0x1.571608p-3f,
        -0x1.663f68p-3f, -0x1.77889ap-3f, -0x1.8b7abap-3f, -0x1.a2d3dap-3f, -0x1.bea452p-3f,
        -0x1.e08236p-3f, -0x1.05751ap-2f, -0x1.210294p-2f, -0x1.46b4c2p-2f, -0x1.7e5f94p-2f,
        -0x1.db8e2p-2f,  -0x1.518e9p-1f,
    },
    {
        /* t^2 */
        0x1.148f3ap-5f, 0x1.18fbdcp-5f, 0x1.1d9fb2p-5f, 0x1.227f5p-5f,  0x1.279fd6p-5f,
        0x1.2d0706p-5f, 0x1.32bb5ep-5f, 0x1.38c434p-5f, 0x1.3f29e6p-5f, 0x1.45f5fap-5f,
        0x1.4d3366p-5f, 0x1.54eeccp-5f, 0x1.5d36dap-5f, 0x1.661caep-5f, 0x1.6fb472p-5f,
        0x1.7a16p-5f,   0x1.855dd2p-5f, 0x1.91ae3p-5f,  0x1.9f30c2p-5f, 0x1.ae189cp-5f,
        0x1.bea50ap-5f, 0x1.d1255ep-5f, 0x1.e5fe02p-5f, 0x1.fdaf4ep-5f, 0x1.0c6f24p-4f,
        0x1.1c2f22p-4f, 0x1.2e9ab4p-4f, 0x1.44413ep-4f, 0x1.5d6a34p-4f, 0x1.78694p-4f,
        0x1.87e468p-4f, 0x1.1bb02cp-4f,
    },
    {
        /* t^3 */
        -0x1.e63222p-7f, -0x1.edcbf2p-7f, -0x1.f5c258p-7f, -0x1.fe1cd4p-7f, -0x1.0371ep-6f,
        -0x1.08104p-6f,  -0x1.0ceecap-6f, -0x1.12137p-6f,  -0x1.1784eap-6f, -0x1.1d4aep-6f,
        -0x1.236e1p-6f,  -0x1.29f88ap-6f, -0x1.30f5e6p-6f, -0x1.3873a6p-6f, -0x1.40818cp-6f,
        -0x1.49322cp-6f, -0x1.529b86p-6f, -0x1.5cd7eap-6f, -0x1.680708p-6f, -0x1.744f72p-6f,
        -0x1.81e07ep-6f, -0x1.90f4f4p-6f, -0x1.a1d692p-6f, -0x1.b4e2ecp-6f, -0x1.ca9212p-6f,
        -0x1.e37f86p-6f, -0x1.003b0ep-5f, -0x1.113fcap-5f, -0x1.258054p-5f, -0x1.3e25b2p-5f,
        -0x1.6017e2p-5f, -0x1.d6cd28p-5f,
    },
    {
        /* t^4 */
        0x1.de241cp-8f, 0x1.e58202p-8f, 0x1.ed384ep-8f, 0x1.f54e0ep-8f, 0x1.fdcb1cp-8f,
        0x1.035c1ep-7f, 0x1.080fa4p-7f, 0x1.0d05a8p-7f, 0x1.12447p-7f,  0x1.17d318p-7f,
        0x1.1db9bcp-7f, 0x1.2401a4p-7f, 0x1.2ab588p-7f, 0x1.31e1ccp-7f, 0x1.3994e2p-7f,
        0x1.41dfbcp-7f, 0x1.4ad65cp-7f, 0x1.549096p-7f, 0x1.5f2af8p-7f, 0x1.6ac818p-7f,
        0x1.77923p-7f,  0x1.85bd62p-7f, 0x1.958ab4p-7f, 0x1.a74c2ap-7f, 0x1.bb6a68p-7f,
        0x1.d26c5ap-7f, 0x1.ed017ap-7f, 0x1.060774p-6f, 0x1.185ebep-6f, 0x1.2e39a8p-6f,
        0x1.47785ap-6f, 0x1.35c5a6p-6f,
    },
    {
        /* t^5 */
        -0x1.f8c762p-9f, -0x1.003c68p-8f, -0x1.0442c6p-8f, -0x1.087a62p-8f, -0x1.0ce74p-8f,
        -0x1.118dd4p-8f, -0x1.16732p-8f,  -0x1.1b9cc8p-8f, -0x1.211122p-8f, -0x1.26d764p-8f,
        -0x1.2cf7bep-8f, -0x1.337b9p-8f,  -0x1.3a6dap-8f,  -0x1.41da62p-8f, -0x1.49d052p-8f,
        -0x1.52606p-8f,  -0x1.5b9e7cp-8f, -0x1.65a254p-8f, -0x1.708832p-8f, -0x1.7c723cp-8f,
        -0x1.8989fap-8f, -0x1.98027ap-8f, -0x1.a81b2ap-8f, -0x1.ba23aep-8f, -0x1.ce812ep-8f,
        -0x1.e5b59ap-8f, -0x1.0034bcp-7f, -0x1.0fbc6cp-7f, -0x1.22019p-7f,  -0x1.37be8p-7f,
        -0x1.521b68p-7f, -0x1.90833ep-7f,
    },
    {
        /* t^6 */
        0x1.509956p-9f, 0x1.55abc8p-9f, 0x1.5af9bap-9f, 0x1.6087cep-9f, 0x1.665b2ep-9f,
        0x1.6c7994p-9f, 0x1.72e96ep-9f, 0x1.79b1f2p-9f, 0x1.80db4p-9f,  0x1.886e8ap-9f,
        0x1.907644p-9f, 0x1.98fe5cp-9f, 0x1.a2148p-9f,  0x1.abc87ap-9f, 0x1.b62c96p-9f,
        0x1.c15632p-9f, 0x1.cd5e68p-9f, 0x1.da62e2p-9f, 0x1.e88706p-9f, 0x1.f7f556p-9f,
        0x1.0470b2p-8f, 0x1.0dc52ap-8f, 0x1.181f18p-8f, 0x1.23af4ep-8f, 0x1.30b386p-8f,
        0x1.3f7aaap-8f, 0x1.506abep-8f, 0x1.6408b8p-8f, 0x1.7b0274p-8f, 0x1.9639b6p-8f,
        0x1.b6bb8cp-8f, 0x1.c8a0e2p-8f,
    },
    {
        /* t^7 */
        -0x1.8a99acp-10f, -0x1.908104p-10f, -0x1.96ad1cp-10f, -0x1.9d2346p-10f, -0x1.a3e96cp-10f,
        -0x1.ab061cp-10f, -0x1.b280b4p-10f, -0x1.ba617p-10f,  -0x1.c2b196p-10f, -0x1.cb7ba8p-10f,
        -0x1.d4cb8cp-10f, -0x1.deaed4p-10f, -0x1.e93512p-10f, -0x1.f4703p-10f,  -0x1.003a76p-9f,
        -0x1.06adbcp-9f,  -0x1.0da014p-9f,  -0x1.15223cp-9f,  -0x1.1d481cp-9f,  -0x1.262996p-9f,
        -0x1.2fe38ap-9f,  -0x1.3a9944p-9f,  -0x1.467642p-9f,  -0x1.53b0c4p-9f,  -0x1.628d32p-9f,
        -0x1.7362c4p-9f,  -0x1.86a1ecp-9f,  -0x1.9cdcf6p-9f,  -0x1.b6d34p-9f,   -0x1.d57e54p-9f,
        -0x1.fa21f4p-9f,  -0x1.1a5bc4p-8f,
    },
};

static once_flag f32_once = ONCE_FLAG_INIT;

/* The normal of one 32-bit Philox word (scalar; f32_icdf16 gives the same bits). */
static inline float f32_icdf(uint32_t w)
{
    const float q =
        fminf(fmaf((float)(int32_t)(w & 0x7fffffffu), 0x1p-31f, 0x1p-32f), 0x1.fffffep-1f);
    int e;
    const float t = 2.0f * frexpf(q, &e) - 1.5f; /* q = (t + 3/2) 2^(e - 1); both steps exact */
    const unsigned i = (unsigned)(e - 1) & 31u;
    float p = f32_icdf_c[F32_DEG][i];
    for (int j = F32_DEG - 1; j >= 0; j--) {
        p = fmaf(p, t, f32_icdf_c[j][i]);
    }
    uint32_t b;
    memcpy(&b, &p, sizeof b);
    b ^= w & 0x80000000u;
    memcpy(&p, &b, sizeof p);
    return p;
}

#define F32_ROUND(r)                                                                               \
    do {                                                                                           \
        uint64_t q0_ = (uint64_t)PHILOX_M4x32_0 * c0, q1_ = (uint64_t)PHILOX_M4x32_1 * c2;         \
        c0 = (uint32_t)(q1_ >> 32) ^ c1 ^ ka[r];                                                   \
        c1 = (uint32_t)q1_;                                                                        \
        c2 = (uint32_t)(q0_ >> 32) ^ c3 ^ kb[r];                                                   \
        c3 = (uint32_t)q0_;                                                                        \
    } while (0)

/* One group, component word w3: the normals of its candidates k = 0 .. k_hi - 1 (id order) into
 * z[k], as doubles. Portable version; f32_group_avx512 gives the same bits. */
static void f32_group_c(const uint32_t *restrict ka, const uint32_t *restrict kb, uint32_t s0,
                        uint32_t s1, uint32_t quad0, uint32_t w3, double *restrict z, int k_hi)
{
    for (int j = 0; j < F32_QUADS; j++) {
        uint32_t c0 = s0, c1 = s1, c2 = quad0 + (uint32_t)j, c3 = w3;
        for (int r = 0; r < F32_ROUNDS; r++) {
            F32_ROUND(r);
        }
        const uint32_t v[4] = {c0, c1, c2, c3};
        for (int l = 0; l < 4; l++) {
            if (l * F32_QUADS + j < k_hi) {
                z[l * F32_QUADS + j] = f32_icdf(v[l]);
            }
        }
    }
}

typedef void f32_group_fn(const uint32_t *restrict ka, const uint32_t *restrict kb, uint32_t s0,
                          uint32_t s1, uint32_t quad0, uint32_t w3, double *restrict z, int k_hi);
static f32_group_fn *f32_group = f32_group_c;

#if NOISE_X86
/* hi and lo halves of the 32x32-bit products a m, lane by lane, for 16 lanes */
#define F32_MULHILO(a, m, hi, lo)                                                                  \
    do {                                                                                           \
        __m512i pe_ = _mm512_mul_epu32(a, m), po_ = _mm512_mul_epu32(_mm512_srli_epi64(a, 32), m); \
        lo = _mm512_mask_blend_epi32(0xaaaa, pe_, _mm512_slli_epi64(po_, 32));                     \
        hi = _mm512_mask_blend_epi32(0xaaaa, _mm512_srli_epi64(pe_, 32), po_);                     \
    } while (0)

/* f32_icdf on 16 words; lo[j], hi[j] = f32_icdf_c[j][0..15], [16..31] */
AVX512 static inline __m512 f32_icdf16(__m512i w, const __m512 *lo, const __m512 *hi)
{
    const __m512 q = _mm512_min_ps(
        _mm512_fmadd_ps(_mm512_cvtepi32_ps(_mm512_and_si512(w, _mm512_set1_epi32(INT32_MAX))),
                        _mm512_set1_ps(0x1p-31f), _mm512_set1_ps(0x1p-32f)),
        _mm512_set1_ps(0x1.fffffep-1f));
    const __m512i i = _mm512_cvtps_epi32(_mm512_getexp_ps(q)); /* e - 1 = -32 .. -1, exact */
    const __m512 t = _mm512_sub_ps(_mm512_getmant_ps(q, _MM_MANT_NORM_1_2, _MM_MANT_SIGN_src),
                                   _mm512_set1_ps(1.5f));
    __m512 p = _mm512_permutex2var_ps(lo[F32_DEG], i, hi[F32_DEG]);
    for (int j = F32_DEG - 1; j >= 0; j--) {
        p = _mm512_fmadd_ps(p, t, _mm512_permutex2var_ps(lo[j], i, hi[j]));
    }
    return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(p),
                                                _mm512_and_si512(w, _mm512_set1_epi32(INT32_MIN))));
}

/* 16 floats widened into z[0..left) (left < 16: the last, partial vector of a group) */
AVX512 static inline void f32_store16(__m512 x, double *z, int left)
{
    const __m512d x0 = _mm512_cvtps_pd(_mm512_castps512_ps256(x)),
                  x1 = _mm512_cvtps_pd(
                      _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1)));
    if (left >= 16) {
        _mm512_storeu_pd(z, x0);
        _mm512_storeu_pd(z + 8, x1);
    } else if (left > 0) {
        _mm512_mask_storeu_pd(z, (__mmask8)(left >= 8 ? 0xff : (1u << left) - 1), x0);
        _mm512_mask_storeu_pd(z + 8, (__mmask8)(left <= 8 ? 0 : (1u << (left - 8)) - 1), x1);
    }
}

AVX512 static void f32_group_avx512(const uint32_t *restrict ka, const uint32_t *restrict kb,
                                    uint32_t s0, uint32_t s1, uint32_t quad0, uint32_t w3,
                                    double *restrict z, int k_hi)
{
    const __m512i m0 = _mm512_set1_epi32((int)PHILOX_M4x32_0),
                  m1 = _mm512_set1_epi32((int)PHILOX_M4x32_1),
                  iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    __m512 lo[F32_DEG + 1], hi[F32_DEG + 1];
    for (int j = 0; j <= F32_DEG; j++) {
        lo[j] = _mm512_load_ps(f32_icdf_c[j]);
        hi[j] = _mm512_load_ps(f32_icdf_c[j] + 16);
    }
    /* quads whose four words all lie at k >= k_hi are not drawn */
    const int j_hi = k_hi >= F32_QUADS ? F32_QUADS : k_hi;
    for (int j = 0; j < j_hi; j += 16) {
        __m512i c0 = _mm512_set1_epi32((int)s0), c1 = _mm512_set1_epi32((int)s1),
                c2 = _mm512_add_epi32(_mm512_set1_epi32((int)(quad0 + (uint32_t)j)), iota),
                c3 = _mm512_set1_epi32((int)w3);
        for (int r = 0; r < F32_ROUNDS; r++) {
            __m512i h0, l0, h1, l1;
            F32_MULHILO(c0, m0, h0, l0);
            F32_MULHILO(c2, m1, h1, l1);
            c0 = _mm512_xor_si512(_mm512_xor_si512(h1, c1), _mm512_set1_epi32((int)ka[r]));
            c1 = l1;
            c2 = _mm512_xor_si512(_mm512_xor_si512(h0, c3), _mm512_set1_epi32((int)kb[r]));
            c3 = l0;
        }
        f32_store16(f32_icdf16(c0, lo, hi), z + j, k_hi - j);
        f32_store16(f32_icdf16(c1, lo, hi), z + F32_QUADS + j, k_hi - F32_QUADS - j);
        f32_store16(f32_icdf16(c2, lo, hi), z + 2 * F32_QUADS + j, k_hi - 2 * F32_QUADS - j);
        f32_store16(f32_icdf16(c3, lo, hi), z + 3 * F32_QUADS + j, k_hi - 3 * F32_QUADS - j);
    }
}
#endif

static void f32_init(void)
{
#if NOISE_X86
    __builtin_cpu_init();
    /* a cap below avx512 (scalar, sse2, avx2; as for the double path) selects the portable loop */
    const char *cap = getenv("GRANULE_NOISE_ISA");
    const bool capped = cap != NULL && (strcmp(cap, "scalar") == 0 || strcmp(cap, "sse2") == 0 ||
                                        strcmp(cap, "avx2") == 0);
    if (__builtin_cpu_supports("avx512f") && !capped) {
        f32_group = f32_group_avx512;
    }
#endif
}

static void f32_keys(const struct gen *g, uint32_t *ka, uint32_t *kb)
{
    uint32_t a = g->key.v[0], b = g->key.v[1];
    for (int r = 0; r < F32_ROUNDS; r++) {
        ka[r] = a;
        kb[r] = b;
        a += PHILOX_W32_0;
        b += PHILOX_W32_1;
    }
}

void gr_noise_normals_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n,
                          int per, double *out)
{
    assert(per == 1 || per == 2);
    assert(n <= 0 || (uint64_t)first + (uint64_t)n - 1 <= UINT32_MAX);
    if (n <= 0 || (per != 1 && per != 2)) {
        return;
    }
    call_once(&f32_once, f32_init);
    const struct gen g = make_gen(seed, stream, step);
    uint32_t ka[F32_ROUNDS], kb[F32_ROUNDS];
    f32_keys(&g, ka, kb);
    _Alignas(64) double z[2][F32_GROUP];
    const uint64_t end = (uint64_t)first + (uint64_t)n;
    for (uint64_t g0 = (uint64_t)first / F32_GROUP * F32_GROUP; g0 < end; g0 += F32_GROUP) {
        const uint64_t lo = g0 > first ? g0 : first,
                       hi = g0 + F32_GROUP < end ? g0 + F32_GROUP : end;
        const uint32_t quad0 = (uint32_t)(g0 / F32_GROUP * F32_QUADS);
        const int k_lo = (int)(lo - g0), k_hi = (int)(hi - g0);
        double *o = out + (lo - first) * (uint64_t)per;
        if (per == 1 && k_lo == 0) { /* from the start of the group: straight into out */
            f32_group(ka, kb, g.s0, g.s1, quad0, F32_FLAG, o, k_hi);
        } else if (per == 1) {
            f32_group(ka, kb, g.s0, g.s1, quad0, F32_FLAG, z[0], k_hi);
            memcpy(o, z[0] + k_lo, (size_t)(k_hi - k_lo) * sizeof *o);
        } else { /* the two components' groups, interleaved */
            f32_group(ka, kb, g.s0, g.s1, quad0, F32_FLAG, z[0], k_hi);
            f32_group(ka, kb, g.s0, g.s1, quad0, F32_FLAG | 1u, z[1], k_hi);
            for (int k = k_lo; k < k_hi; k++) {
                o[2 * (k - k_lo)] = z[0][k];
                o[2 * (k - k_lo) + 1] = z[1][k];
            }
        }
    }
}

float gr_noise_f32_transform(uint32_t w) { return f32_icdf(w); }

double gr_noise_normal1_f32(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id,
                            int component)
{
    assert(component == 0 || component == 1);
    const struct gen g = make_gen(seed, stream, step);
    const uint32_t k = id % F32_GROUP, quad = id / F32_GROUP * F32_QUADS + k % F32_QUADS,
                   lane = k / F32_QUADS, c = (uint32_t)component & 1u;
    philox4x32_ctr_t ctr = {{g.s0, g.s1, quad, F32_FLAG | c}};
    philox4x32_ctr_t r = philox4x32_R(F32_ROUNDS, ctr, g.key);
    return f32_icdf(r.v[lane]);
}
