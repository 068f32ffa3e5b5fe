/* Tests of the counter-based Gaussian noise (src/core/noise.c).
 *
 * Two kinds of checks. Exact ones: gr_noise_normals agrees bit for bit with gr_noise_normal1
 * whatever the batch (first, n), per and vector kernel, and both agree with an independent,
 * slow implementation written here from the documented scheme (Random123's philox4x32 for the
 * bits, ziggurat tables re-derived from the recursion in long double). Statistical ones, all with
 * fixed seeds so each outcome is deterministic yet would fail for a wrong distribution: moments,
 * Kolmogorov-Smirnov and chi-square against the normal CDF (GSL), tail frequencies, correlations
 * between neighbouring ids, components and steps, and the uniforms. Sizes are kept modest so the
 * suite also runs quickly under AddressSanitizer. */
#include "granule/noise.h"

#include <check.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Random123/philox.h>

#include "check_main.h"

static const uint64_t SEED = UINT64_C(0x243f6a8885a308d3); /* fixed, arbitrary */

/* ck_assert_msg for loops: Check records a checkpoint on every passing assertion, which costs a
 * write per call, so inside loops only the failure goes through Check. */
#define REQUIRE(cond, ...)                                                                         \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            ck_abort_msg(__VA_ARGS__);                                                             \
        }                                                                                          \
    } while (0)

/* z within k standard errors of its expectation? */
static int within(double z, double expect, double sigma, double k)
{
    return fabs(z - expect) <= k * sigma;
}

/* ---- An independent reference implementation ----------------------------------------------------
 * Written from the description at the top of noise.c, sharing no code with it. */

static long double ref_x[257], ref_f[257];
static const long double ref_r = 3.6541528853610088L;

static void ref_tables(void)
{
    long double v =
        ref_r * expl(-ref_r * ref_r / 2) + sqrtl(acosl(-1.0L) / 2) * erfcl(ref_r / sqrtl(2.0L));
    ref_x[0] = v / expl(-ref_r * ref_r / 2);
    ref_x[1] = ref_r;
    for (int i = 2; i < 256; i++) {
        ref_x[i] = sqrtl(-2 * logl(v / ref_x[i - 1] + expl(-ref_x[i - 1] * ref_x[i - 1] / 2)));
    }
    ref_x[256] = 0;
    for (int i = 0; i < 257; i++) {
        ref_f[i] = expl(-ref_x[i] * ref_x[i] / 2);
    }
}

static uint32_t ref_mix(uint32_t h)
{
    h = (h ^ (h >> 16)) * 0x85ebca6bu;
    h = (h ^ (h >> 13)) * 0xc2b2ae35u;
    return h ^ (h >> 16);
}

static void ref_block(uint64_t seed, uint32_t stream, uint32_t kind, uint32_t w0, uint32_t w1,
                      uint32_t w2, uint32_t w3, uint64_t out[2])
{
    philox4x32_key_t key = {{(uint32_t)seed, (uint32_t)(seed >> 32) ^ ref_mix(2 * stream + kind)}};
    philox4x32_ctr_t ctr = {{w0, w1, w2, w3}};
    philox4x32_ctr_t r = philox4x32(ctr, key);
    out[0] = (uint64_t)r.v[1] << 32 | r.v[0];
    out[1] = (uint64_t)r.v[3] << 32 | r.v[2];
}

/* Which way the reference variate went, for coverage counts. */
enum { PATH_FAST, PATH_WEDGE, PATH_TAIL };

static double ref_normal(uint64_t seed, uint32_t stream, uint64_t step, uint32_t id, uint32_t c,
                         int *path, int *layer)
{
    uint32_t s0 = (uint32_t)step, s1 = (uint32_t)(step >> 32), pair = id / 2, lane = id % 2;
    uint64_t blk[2];
    ref_block(seed, stream, 0, s0, s1, pair, c, blk);
    uint64_t w = blk[lane];
    *path = PATH_FAST;
    *layer = (int)(w % 256);
    for (uint32_t r = 1;; r++) {
        int i = (int)(w % 256);
        double sign = (w >> 63) ? -1.0 : 1.0;
        long double x = (long double)((w >> 11) % (UINT64_C(1) << 52)) * 0x1p-52L * ref_x[i];
        if (x < ref_x[i + 1]) {
            return sign * (double)x;
        }
        ref_block(seed, stream, 0, s0, s1, pair, c + 2 * lane + 4 * r, blk);
        if (i == 0) {
            *path = PATH_TAIL;
            for (;;) {
                long double t = -logl((long double)((blk[0] >> 11) + 1) * 0x1p-53L) / ref_r;
                long double e = -logl((long double)((blk[1] >> 11) + 1) * 0x1p-53L);
                if (2 * e > t * t) {
                    return sign * (double)(ref_r + t);
                }
                r++;
                ref_block(seed, stream, 0, s0, s1, pair, c + 2 * lane + 4 * r, blk);
            }
        }
        *path = PATH_WEDGE;
        long double y =
            ref_f[i] + (long double)(blk[0] >> 11) * 0x1p-53L * (ref_f[i + 1] - ref_f[i]);
        if (y < expl(-x * x / 2)) {
            return sign * (double)x;
        }
        w = blk[1];
    }
}

static int close_to(double a, double b) { return fabs(a - b) <= 1e-12 * fmax(1.0, fabs(b)); }

START_TEST(test_reference)
{
    /* Every layer, the wedges and the tail, against the independent implementation. */
    ref_tables();
    enum { N = 100000 };
    double *v = malloc(2 * N * sizeof *v);
    ck_assert_ptr_nonnull(v);
    const uint64_t step = UINT64_C(0x100000007); /* both step words non-zero */
    gr_noise_normals(SEED, GR_STREAM_NOISE, step, 0, N, 2, v);
    int paths[3] = {0, 0, 0}, layers[256] = {0};
    for (uint32_t id = 0; id < N; id++) {
        for (uint32_t c = 0; c < 2; c++) {
            int path, layer;
            double ref = ref_normal(SEED, GR_STREAM_NOISE, step, id, c, &path, &layer);
            REQUIRE(close_to(v[2 * id + c], ref), "id %u c %u: %.17g, reference %.17g (path %d)",
                    id, c, v[2 * id + c], ref, path);
            paths[path]++;
            layers[layer]++;
        }
    }
    for (int i = 0; i < 256; i++) {
        ck_assert_msg(layers[i] > 0, "layer %d never sampled", i);
    }
    /* expected: wedges 1.5%, tail 0.013% of 2e5 */
    ck_assert_msg(paths[PATH_WEDGE] > 2000 && paths[PATH_TAIL] > 5, "wedges %d, tails %d",
                  paths[PATH_WEDGE], paths[PATH_TAIL]);
    free(v);
}
END_TEST

START_TEST(test_reference_uniform)
{
    const uint64_t a = UINT64_C(0x123456789abcdef0), b = UINT64_C(0xfedcba9876543210);
    uint64_t blk[2];
    ref_block(SEED, 5, 1, (uint32_t)a, (uint32_t)(a >> 32), (uint32_t)b, (uint32_t)(b >> 32), blk);
    ck_assert(gr_noise_uniform(SEED, 5, a, b) == (double)(blk[0] >> 11) * 0x1p-53);
}
END_TEST

/* ---- Exact identities ------------------------------------------------------------------------ */

START_TEST(test_batch_independence)
{
    /* The value of an id never depends on the batch it is drawn in. */
    enum { N = 3000 };
    const uint32_t base = 1000001; /* odd: pairs straddle the batch start */
    for (int per = 1; per <= 2; per++) {
        double *all = malloc((size_t)N * 2 * sizeof *all),
               *part = malloc((size_t)N * 2 * sizeof *part);
        ck_assert_ptr_nonnull(all);
        ck_assert_ptr_nonnull(part);
        gr_noise_normals(SEED, GR_STREAM_NOISE, 42, base, N, per, all);
        static const int windows[][2] = {{0, 1},   {1, 1},     {0, 2},  {1, 2},     {3, 7},
                                         {2, 8},   {5, 17},    {0, 16}, {1, 511},   {7, 512},
                                         {6, 513}, {10, 1025}, {0, N},  {1, N - 1}, {N - 1, 1}};
        for (size_t w = 0; w < sizeof windows / sizeof windows[0]; w++) {
            int off = windows[w][0], n = windows[w][1];
            memset(part, 0, (size_t)N * 2 * sizeof *part);
            gr_noise_normals(SEED, GR_STREAM_NOISE, 42, base + (uint32_t)off, n, per, part);
            for (int i = 0; i < n * per; i++) {
                REQUIRE(part[i] == all[off * per + i],
                        "per %d, window (%d, %d), element %d: %.17g != %.17g", per, off, n, i,
                        part[i], all[off * per + i]);
            }
            for (int i = n * per; i < N * 2; i++) {
                REQUIRE(part[i] == 0.0, "per %d, window (%d, %d) wrote past its end", per, off, n);
            }
        }
        /* one particle at a time, through both entry points */
        for (int i = 0; i < N; i += 7) {
            double one[2];
            gr_noise_normals(SEED, GR_STREAM_NOISE, 42, base + (uint32_t)i, 1, per, one);
            for (int c = 0; c < per; c++) {
                REQUIRE(one[c] == all[i * per + c], "per %d, id offset %d alone", per, i);
                REQUIRE(gr_noise_normal1(SEED, GR_STREAM_NOISE, 42, base + (uint32_t)i, c) ==
                            all[i * per + c],
                        "per %d, id offset %d: gr_noise_normal1", per, i);
            }
        }
        free(all);
        free(part);
    }
}
END_TEST

START_TEST(test_per_consistency)
{
    /* per = 1 gives component 0 of per = 2; gr_noise_normal1 matches both. */
    enum { N = 5000 };
    double *one = malloc(N * sizeof *one), *two = malloc(2 * N * sizeof *two);
    ck_assert_ptr_nonnull(one);
    ck_assert_ptr_nonnull(two);
    gr_noise_normals(SEED, GR_STREAM_INIT_VELOCITY, 9, 0, N, 1, one);
    gr_noise_normals(SEED, GR_STREAM_INIT_VELOCITY, 9, 0, N, 2, two);
    int differ = 0;
    for (int i = 0; i < N; i++) {
        REQUIRE(one[i] == two[2 * i], "id %d: per 1 %.17g, per 2 %.17g", i, one[i], two[2 * i]);
        REQUIRE(gr_noise_normal1(SEED, GR_STREAM_INIT_VELOCITY, 9, (uint32_t)i, 0) == one[i],
                "id %d, component 0: gr_noise_normal1", i);
        REQUIRE(gr_noise_normal1(SEED, GR_STREAM_INIT_VELOCITY, 9, (uint32_t)i, 1) ==
                    two[2 * i + 1],
                "id %d, component 1: gr_noise_normal1", i);
        differ += two[2 * i] != two[2 * i + 1];
    }
    ck_assert_int_eq(differ, N);
    /* repeated calls give the same numbers */
    double again[16];
    gr_noise_normals(SEED, GR_STREAM_INIT_VELOCITY, 9, 100, 8, 2, again);
    ck_assert(memcmp(again, two + 200, sizeof again) == 0);
    free(one);
    free(two);
}
END_TEST

START_TEST(test_id_range_ends)
{
    /* ids up to UINT32_MAX; n = 0 writes nothing */
    double v[2 * 21], sentinel = -12345.0;
    gr_noise_normals(SEED, GR_STREAM_NOISE, 3, UINT32_MAX - 20, 21, 2, v);
    for (uint32_t i = 0; i < 21; i++) {
        for (int c = 0; c < 2; c++) {
            REQUIRE(v[2 * i + (uint32_t)c] ==
                        gr_noise_normal1(SEED, GR_STREAM_NOISE, 3, UINT32_MAX - 20 + i, c),
                    "id UINT32_MAX - %u, component %d", 20 - i, c);
        }
    }
    v[0] = sentinel;
    gr_noise_normals(SEED, GR_STREAM_NOISE, 3, 0, 0, 1, v);
    ck_assert(v[0] == sentinel);
}
END_TEST

/* How many of a batch's normals differ from the one-by-one function's */
static int isa_diff(void (*all)(uint64_t, uint32_t, uint64_t, uint32_t, int, int, double *),
                    double (*one)(uint64_t, uint32_t, uint64_t, uint32_t, int))
{
    enum { N = 4099 };
    static double v[2 * N];
    int bad = 0;
    for (int per = 1; per <= 2; per++) {
        all(SEED, GR_STREAM_NOISE, 77, 11, N, per, v);
        for (int i = 0; i < N; i++) {
            for (int c = 0; c < per; c++) {
                bad += v[i * per + c] != one(SEED, GR_STREAM_NOISE, 77, 11 + (uint32_t)i, c);
            }
        }
    }
    return bad;
}

/* Run this test binary again as `--isa-check NAME` with GRANULE_NOISE_ISA = NAME: a fresh process,
 * because the kernel is chosen once per process. */
static int isa_check(void)
{
    /* the double path, and the single-precision one (its AVX-512 kernel or the portable loop) */
    const int bad = isa_diff(gr_noise_normals, gr_noise_normal1),
              bad32 = isa_diff(gr_noise_normals_f32, gr_noise_normal1_f32);
    if (bad || bad32) {
        fprintf(stderr,
                "GRANULE_NOISE_ISA=%s: %d values differ from gr_noise_normal1, %d from "
                "gr_noise_normal1_f32\n",
                getenv("GRANULE_NOISE_ISA"), bad, bad32);
    }
    return bad != 0 || bad32 != 0;
}

START_TEST(test_kernels_agree)
{
    /* Every vector kernel (this CPU permitting) gives the scalar reference values bit for bit. */
    static const char *const isas[] = {"scalar", "sse2", "avx2", "avx512"};
    const char *isa = isas[_i];
    fflush(NULL);
    pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) {
        setenv("GRANULE_NOISE_ISA", isa, 1);
        execl("/proc/self/exe", "test_noise", "--isa-check", (char *)NULL);
        _exit(127);
    }
    int status;
    ck_assert_int_eq(waitpid(pid, &status, 0), pid);
    ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 0, "kernel %s: exit status %d", isa,
                  WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}
END_TEST

START_TEST(test_golden)
{
    /* Recorded values: a change here changes the noise of every run (and invalidates restarts
     * and comparisons across versions), so it must be deliberate. */
    static const struct {
        uint64_t seed;
        uint32_t stream;
        uint64_t step;
        uint32_t id;
        int c;
        double x;
    } golden[] = {
        {UINT64_C(0x0), 0, UINT64_C(0x0), 0u, 0, -0x1.697c2247595d3p-1},
        {UINT64_C(0x0), 0, UINT64_C(0x0), 1u, 0, -0x1.9ead07bdd767ep-2},
        {UINT64_C(0x243f6a8885a308d3), 0, UINT64_C(0x1), 2u, 1, 0x1.bad888238cdccp-5},
        {UINT64_C(0x243f6a8885a308d3), 1, UINT64_C(0x0), 12345u, 0, 0x1.07221ca67b45ap+0},
        {UINT64_C(0x1), 2, UINT64_C(0x100000000), 4000000000u, 1, -0x1.7f481b826a9bap-2},
        {UINT64_C(0x2a), 0, UINT64_C(0xf4240), 99999u, 1, 0x1.b5629ede895e4p-7},
    };
    for (size_t i = 0; i < sizeof golden / sizeof golden[0]; i++) {
        double x = gr_noise_normal1(golden[i].seed, golden[i].stream, golden[i].step, golden[i].id,
                                    golden[i].c);
        ck_assert_msg(x == golden[i].x, "golden %zu: %a, recorded %a", i, x, golden[i].x);
    }
}
END_TEST

/* ---- Statistics ------------------------------------------------------------------------------ */

/* Draw `steps` steps of n particles x per components, calling f on each batch. */
/* The generator the statistical tests draw from: the double path, or the single-precision one. */
typedef void normals_fn(uint64_t seed, uint32_t stream, uint64_t step, uint32_t first, int n,
                        int per, double *out);
static normals_fn *draw_normals = gr_noise_normals;

static void draw(uint64_t seed, uint32_t stream, int steps, int n, int per,
                 void (*f)(const double *v, int cnt, void *ctx), void *ctx)
{
    double *v = malloc((size_t)n * (size_t)per * sizeof *v);
    ck_assert_ptr_nonnull(v);
    for (int s = 0; s < steps; s++) {
        draw_normals(seed, stream, (uint64_t)s, 0, n, per, v);
        f(v, n * per, ctx);
    }
    free(v);
}

struct moments {
    double s1, s2, s3, s4;
    long cnt;
};

static void add_moments(const double *v, int cnt, void *ctx)
{
    struct moments *m = ctx;
    for (int i = 0; i < cnt; i++) {
        double x = v[i], x2 = x * x;
        m->s1 += x;
        m->s2 += x2;
        m->s3 += x2 * x;
        m->s4 += x2 * x2;
    }
    m->cnt += cnt;
}

/* n draws (steps x count x per) from draw_normals: mean 0, variance 1, skewness 0, kurtosis 3,
 * each within 5 standard errors (standard errors of the raw moments: sqrt(1/n), sqrt(2/n),
 * sqrt(15/n), sqrt(96/n)). */
static void check_moments(uint64_t seed, int steps, int count, int per, const char *what)
{
    struct moments m = {0, 0, 0, 0, 0};
    draw(seed, GR_STREAM_NOISE, steps, count, per, add_moments, &m);
    double n = (double)m.cnt;
    ck_assert(m.cnt == (long)steps * count * per);
    ck_assert_msg(within(m.s1 / n, 0, sqrt(1 / n), 5), "%s per %d mean %g", what, per, m.s1 / n);
    ck_assert_msg(within(m.s2 / n, 1, sqrt(2 / n), 5), "%s per %d variance %g", what, per,
                  m.s2 / n);
    ck_assert_msg(within(m.s3 / n, 0, sqrt(15 / n), 5), "%s per %d third moment %g", what, per,
                  m.s3 / n);
    ck_assert_msg(within(m.s4 / n, 3, sqrt(96 / n), 5), "%s per %d fourth moment %g", what, per,
                  m.s4 / n);
}

START_TEST(test_moments)
{
    /* 2e6 draws */
    for (int per = 1; per <= 2; per++) {
        check_moments(SEED + (uint64_t)per, 100, 20000 / per, per, "double");
    }
}
END_TEST

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Kolmogorov's limiting distribution: P(sqrt(n) D > lambda). */
static double ks_q(double lambda)
{
    double q = 0;
    for (int k = 1; k <= 100; k++) {
        q += 2 * ((k % 2) ? 1 : -1) * exp(-2.0 * k * k * lambda * lambda);
    }
    return fmin(1.0, fmax(0.0, q));
}

START_TEST(test_kolmogorov_smirnov)
{
    enum { N = 200000 };
    double *v = malloc(N * sizeof *v);
    ck_assert_ptr_nonnull(v);
    gr_noise_normals(SEED, GR_STREAM_NOISE, 1, 0, N / 2, 2, v);
    qsort(v, N, sizeof *v, cmp_double);
    double d = 0;
    for (int i = 0; i < N; i++) {
        double p = gsl_cdf_ugaussian_P(v[i]);
        d = fmax(d, fmax((i + 1.0) / N - p, p - (double)i / N));
    }
    double sn = sqrt((double)N), p = ks_q((sn + 0.12 + 0.11 / sn) * d);
    ck_assert_msg(p > 1e-3, "KS: D = %g, p = %g", d, p);
    free(v);
}
END_TEST

enum { BINS = 1000 };
struct chi {
    double edge[BINS - 1]; /* equiprobable bins of the normal */
    long count[BINS];
};

static void add_chi(const double *v, int cnt, void *ctx)
{
    struct chi *h = ctx;
    for (int i = 0; i < cnt; i++) {
        int lo = 0, hi = BINS - 1; /* the bin: number of edges <= v[i] */
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (h->edge[mid] <= v[i]) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        h->count[lo]++;
    }
}

START_TEST(test_chi_square)
{
    /* 1e6 draws in 1000 equiprobable bins: chi^2 with 999 degrees of freedom, p > 1e-4. */
    static struct chi h;
    memset(&h, 0, sizeof h);
    for (int b = 0; b < BINS - 1; b++) {
        h.edge[b] = gsl_cdf_ugaussian_Pinv((b + 1.0) / BINS);
    }
    draw(SEED, GR_STREAM_PLACEMENT, 100, 10000, 1, add_chi, &h);
    double expect = 1e6 / BINS, chi2 = 0;
    for (int b = 0; b < BINS; b++) {
        chi2 += ((double)h.count[b] - expect) * ((double)h.count[b] - expect) / expect;
    }
    double p = gsl_cdf_chisq_Q(chi2, BINS - 1);
    ck_assert_msg(p > 1e-4, "chi^2 = %g for %d dof, p = %g", chi2, BINS - 1, p);
}
END_TEST

struct tails {
    double limit[4];
    long beyond[4], cnt;
};

static void add_tails(const double *v, int cnt, void *ctx)
{
    struct tails *t = ctx;
    for (int i = 0; i < cnt; i++) {
        double a = fabs(v[i]);
        for (int k = 0; k < 4; k++) {
            t->beyond[k] += a > t->limit[k];
        }
    }
    t->cnt += cnt;
}

/* 1e7 draws from draw_normals: the frequency of |x| > 3, > R (where the exact tail sampler takes
 * over), > 4 and > 4.5 matches 2 (1 - Phi) within 5 binomial standard errors. */
static void check_tails(const char *what)
{
    struct tails t = {{3.0, 3.6541528853610088, 4.0, 4.5}, {0, 0, 0, 0}, 0};
    draw(SEED, GR_STREAM_NOISE, 100, 50000, 2, add_tails, &t);
    ck_assert(t.cnt == 10000000);
    for (int k = 0; k < 4; k++) {
        double p = 2 * gsl_cdf_ugaussian_Q(t.limit[k]), n = (double)t.cnt;
        ck_assert_msg(within((double)t.beyond[k], n * p, sqrt(n * p * (1 - p)), 5),
                      "%s: |x| > %g: %ld times, expected %g", what, t.limit[k], t.beyond[k], n * p);
    }
}

START_TEST(test_tails) { check_tails("double"); }
END_TEST

static double correlation(const double *a, const double *b, int n, int stride_a, int stride_b)
{
    double sab = 0, saa = 0, sbb = 0;
    for (int i = 0; i < n; i++) {
        double x = a[i * stride_a], y = b[i * stride_b];
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    return sab / sqrt(saa * sbb);
}

/* (seed, stream, step) next to (SEED, GR_STREAM_NOISE, 0), for the correlation tests */
static const struct {
    uint64_t seed;
    uint32_t stream;
    uint64_t step;
    const char *what;
} other[] = {{SEED, GR_STREAM_NOISE, 1, "next step"},
             {SEED, GR_STREAM_INIT_VELOCITY, 0, "stream 1"},
             {SEED + 1, GR_STREAM_NOISE, 0, "seed + 1"},
             {SEED ^ (UINT64_C(1) << 32), GR_STREAM_NOISE, 0, "seed, high word"},
             {SEED, GR_STREAM_NOISE, UINT64_C(1) << 32, "step, high word"}};

START_TEST(test_correlations)
{
    /* Values that share a Philox block or a counter neighbourhood are uncorrelated, also in
     * their squares: ids 2k and 2k+1, components 0 and 1, consecutive steps, streams, seeds. */
    enum { N = 200000 };
    double *a = malloc(2 * N * sizeof *a), *b = malloc(2 * N * sizeof *b);
    double *a2 = malloc(2 * N * sizeof *a2), *b2 = malloc(2 * N * sizeof *b2);
    ck_assert(a && b && a2 && b2);
    const double lim = 5 / sqrt(N / 2.0), lim_all = 5 / sqrt(2.0 * N); /* 5 sigma */
    gr_noise_normals(SEED, GR_STREAM_NOISE, 0, 0, N, 2, a);
    for (int i = 0; i < 2 * N; i++) {
        a2[i] = a[i] * a[i] - 1;
    }
    double r;
    r = correlation(a, a + 2, N / 2, 4, 4); /* ids 2k, 2k+1, component 0: same block */
    ck_assert_msg(fabs(r) < lim, "ids 2k, 2k+1: r = %g", r);
    r = correlation(a2, a2 + 2, N / 2, 4, 4);
    ck_assert_msg(fabs(r) < lim, "ids 2k, 2k+1, squares: r = %g", r);
    r = correlation(a, a + 1, N / 2, 4, 4); /* components 0, 1 of one id */
    ck_assert_msg(fabs(r) < lim, "components: r = %g", r);
    r = correlation(a2, a2 + 1, N / 2, 4, 4);
    ck_assert_msg(fabs(r) < lim, "components, squares: r = %g", r);
    r = correlation(a + 2, a + 4, N / 2 - 1, 4, 4); /* ids 2k+1, 2k+2: neighbouring blocks */
    ck_assert_msg(fabs(r) < lim, "ids 2k+1, 2k+2: r = %g", r);
    for (size_t o = 0; o < sizeof other / sizeof other[0]; o++) {
        gr_noise_normals(other[o].seed, other[o].stream, other[o].step, 0, N, 2, b);
        int equal = 0;
        for (int i = 0; i < 2 * N; i++) {
            equal += a[i] == b[i];
            b2[i] = b[i] * b[i] - 1;
        }
        ck_assert_msg(equal == 0, "%s: %d values equal", other[o].what, equal);
        r = correlation(a, b, 2 * N, 1, 1);
        ck_assert_msg(fabs(r) < lim_all, "%s: r = %g", other[o].what, r);
        r = correlation(a2, b2, 2 * N, 1, 1);
        ck_assert_msg(fabs(r) < lim_all, "%s, squares: r = %g", other[o].what, r);
    }
    free(a);
    free(b);
    free(a2);
    free(b2);
}
END_TEST

START_TEST(test_uniform)
{
    /* In [0, 1), mean 1/2 and variance 1/12 within 5 sigma, flat in 100 bins (chi^2), a pure
     * function of its arguments, and different for different arguments. */
    enum { N = 1000000, B = 100 };
    static long bins[B];
    memset(bins, 0, sizeof bins);
    double s1 = 0, s2 = 0;
    for (uint64_t i = 0; i < N; i++) {
        double u = gr_noise_uniform(SEED, GR_STREAM_PLACEMENT, i / 1000, i % 1000);
        REQUIRE(u >= 0.0 && u < 1.0, "u = %.17g", u);
        s1 += u;
        s2 += (u - 0.5) * (u - 0.5);
        bins[(int)(u * B)]++;
    }
    ck_assert_msg(within(s1 / N, 0.5, sqrt(1.0 / 12 / N), 5), "mean %g", s1 / N);
    ck_assert_msg(within(s2 / N, 1.0 / 12, sqrt(1.0 / 180 / N), 5), "variance %g", s2 / N);
    double chi2 = 0, e = (double)N / B;
    for (int b = 0; b < B; b++) {
        chi2 += ((double)bins[b] - e) * ((double)bins[b] - e) / e;
    }
    ck_assert_msg(gsl_cdf_chisq_Q(chi2, B - 1) > 1e-4, "chi^2 %g", chi2);

    double u = gr_noise_uniform(SEED, 1, 2, 3);
    ck_assert(u == gr_noise_uniform(SEED, 1, 2, 3));
    ck_assert(u != gr_noise_uniform(SEED + 1, 1, 2, 3));
    ck_assert(u != gr_noise_uniform(SEED ^ (UINT64_C(1) << 63), 1, 2, 3));
    ck_assert(u != gr_noise_uniform(SEED, 2, 2, 3));
    ck_assert(u != gr_noise_uniform(SEED, 1, 3, 2));
    ck_assert(u != gr_noise_uniform(SEED, 1, 2 + (UINT64_C(1) << 40), 3));
    ck_assert(u != gr_noise_uniform(SEED, 1, 2, 3 + (UINT64_C(1) << 40)));
}
END_TEST

/* ---- Single-precision normals ([noise] precision = single) ---------------------------------- */

START_TEST(test_f32_exact)
{
    /* A pure function of (step, id, component): the same value whatever the window it is drawn
     * in, with per = 1 or 2, and through gr_noise_normal1_f32 (Random123's philox4x32_R(7) and
     * the scalar transform); every value is a float; a different sequence from the double
     * path's. */
    enum { N = 5000 };
    const uint32_t base = 1000001; /* straddles the groups of 1024 ids */
    double all[2 * N], part[2 * N], dbl[2 * N];
    int rounded = 0, equal_dbl = 0;
    for (int per = 1; per <= 2; per++) {
        gr_noise_normals_f32(SEED, GR_STREAM_NOISE, 42, base, N, per, all);
        gr_noise_normals(SEED, GR_STREAM_NOISE, 42, base, N, per, dbl);
        static const int windows[][2] = {{0, 1},     {1, 1},    {3, 7},    {5, 1023},
                                         {0, 1024},  {7, 1025}, {1023, 2}, {1500, 2049},
                                         {1, N - 1}, {N - 1, 1}};
        for (size_t w = 0; w < sizeof windows / sizeof windows[0]; w++) {
            int off = windows[w][0], n = windows[w][1];
            memset(part, 0, sizeof part);
            gr_noise_normals_f32(SEED, GR_STREAM_NOISE, 42, base + (uint32_t)off, n, per, part);
            for (int i = 0; i < n * per; i++) {
                REQUIRE(part[i] == all[off * per + i], "f32 per %d, window (%d, %d), element %d",
                        per, off, n, i);
            }
            for (int i = n * per; i < 2 * N; i++) {
                REQUIRE(part[i] == 0.0, "f32 per %d, window (%d, %d) wrote past its end", per, off,
                        n);
            }
        }
        for (int i = 0; i < N; i++) {
            for (int c = 0; c < per; c++) {
                double x = all[i * per + c];
                REQUIRE(gr_noise_normal1_f32(SEED, GR_STREAM_NOISE, 42, base + (uint32_t)i, c) == x,
                        "f32 per %d, id offset %d, component %d: gr_noise_normal1_f32", per, i, c);
                rounded += (double)(float)x != x;
                equal_dbl += x == dbl[i * per + c];
            }
        }
    }
    ck_assert_msg(rounded == 0, "%d f32 normals are not floats", rounded);
    ck_assert_msg(equal_dbl == 0, "%d f32 normals equal the double path's", equal_dbl);
}
END_TEST

START_TEST(test_f32_reference)
{
    /* The documented counter layout, written here from noise.c's description: id = 1024 g +
     * 256 l + j takes word l of the Philox4x32-7 block with counter (step low, step high,
     * 256 g + j, 2^31 | c), turned into a normal by gr_noise_f32_transform. */
    enum { N = 3000 };
    const uint32_t base = 2047; /* straddles three groups of 1024 ids */
    const uint64_t step = UINT64_C(0x100000005);
    static double v[2 * N];
    const uint32_t hi = (uint32_t)(SEED >> 32) ^ ref_mix(2u * GR_STREAM_NOISE);
    const philox4x32_key_t key = {{(uint32_t)SEED, hi}};
    for (int per = 1; per <= 2; per++) {
        gr_noise_normals_f32(SEED, GR_STREAM_NOISE, step, base, N, per, v);
        for (int i = 0; i < N; i++) {
            const uint32_t id = base + (uint32_t)i, k = id % 1024;
            for (int c = 0; c < per; c++) {
                philox4x32_ctr_t ctr = {{(uint32_t)step, (uint32_t)(step >> 32),
                                         id / 1024 * 256 + k % 256, 0x80000000u | (uint32_t)c}};
                philox4x32_ctr_t r = philox4x32_R(7, ctr, key);
                const double x = gr_noise_f32_transform(r.v[k / 256]);
                REQUIRE(v[i * per + c] == x, "f32 per %d, id %u, component %d: %a, reference %a",
                        per, id, c, v[i * per + c], x);
            }
        }
    }
}
END_TEST

/* |gr_noise_f32_transform(k) - the exact quantile| for k (bits 0-30), the quantile from GSL */
static double f32_error(uint32_t k)
{
    const float q = fminf((float)((double)k * 0x1p-31 + 0x1p-32), 0x1.fffffep-1f);
    return fabs((double)gr_noise_f32_transform(k) - gsl_cdf_ugaussian_Qinv((double)q / 2));
}

/* f32 transform on the words lo .. hi - 1: |z| never rises with k, bit 31 flips the sign only;
 * returns the largest error */
static double f32_run(uint32_t lo, uint32_t hi)
{
    double worst = 0;
    float prev = gr_noise_f32_transform(lo);
    for (uint32_t k = lo; k < hi; k++) {
        const float z = gr_noise_f32_transform(k);
        REQUIRE(z <= prev, "f32 transform rises from k = %u to %u: %a > %a", k - 1, k, (double)z,
                (double)prev);
        REQUIRE(gr_noise_f32_transform(k | 0x80000000u) == -z, "f32 transform k = %u: sign", k);
        prev = z;
        worst = fmax(worst, f32_error(k));
    }
    return worst;
}

START_TEST(test_f32_transform)
{
    /* The transform of one word (noise.c, "Single-precision normals"): |z| = Phi^-1(1 - q/2),
     * q = (k + 1/2) 2^-31, within 5e-7 (the polynomials' fit plus float rounding; 4.9e-7 is the
     * largest over all 2^31 words); bit 31 flips the sign only; |z| falls as k grows, also
     * across the octaves' ends (where the polynomial changes); the largest |z| is the documented
     * truncation point, 6.3380 = Phi^-1(1 - 2^-33), at k = 0. Checked on the 2^16 words at
     * each end, 2^12 around every other octave's end, and every 4099th word in between. */
    double worst = fmax(f32_run(0, 1u << 16), f32_run((1u << 31) - (1u << 16), 1u << 31));
    for (int b = 16; b < 31; b++) { /* around 2^b: q = 2^(b - 31), the end of an octave */
        worst = fmax(worst, f32_run((1u << b) - 2048, (1u << b) + 2048));
    }
    for (uint32_t k = 1u << 16; k < (1u << 31) - (1u << 16); k += 4099) {
        worst = fmax(worst, f32_error(k));
    }
    ck_assert_msg(worst < 5e-7, "f32 transform: largest error %g", worst);
    const double top = gr_noise_f32_transform(0);
    ck_assert_msg(fabs(top - 6.3379577545537895) < 5e-7,
                  "f32 transform: largest |z| %a, expected "
                  "6.3379578",
                  top);
}
END_TEST

/* |r| of x and y, and of their squares minus 1, below lim (5 standard errors) */
static void f32_uncorrelated(const double *x, const double *y, int n, int stride, double lim,
                             const char *what)
{
    double *x2 = malloc((size_t)n * sizeof *x2), *y2 = malloc((size_t)n * sizeof *y2);
    ck_assert(x2 && y2);
    for (int i = 0; i < n; i++) {
        x2[i] = x[(size_t)i * (size_t)stride] * x[(size_t)i * (size_t)stride] - 1;
        y2[i] = y[(size_t)i * (size_t)stride] * y[(size_t)i * (size_t)stride] - 1;
    }
    const double r = correlation(x, y, n, stride, stride), r2 = correlation(x2, y2, n, 1, 1);
    free(x2);
    free(y2);
    ck_assert_msg(fabs(r) < lim && fabs(r2) < lim, "f32 %s: r = %g, squares %g (limit %g)", what, r,
                  r2, lim);
}

START_TEST(test_f32_correlations)
{
    /* The single path on Philox4x32-7: the four words of one block (ids 256 apart in a group of
     * 1024), the two components of one id, neighbouring counters, and the keys and steps of
     * other[] give uncorrelated values and squares (5 standard errors). */
    enum { N = 262144 }; /* 256 groups */
    double *a = malloc(2 * N * sizeof *a), *b = malloc(2 * N * sizeof *b);
    ck_assert(a && b);
    gr_noise_normals_f32(SEED, GR_STREAM_NOISE, 0, 0, N, 2, a);
    /* word l and word l2 of the blocks of group g: ids 1024 g + 256 l + j, component 0 */
    static const int words[][2] = {{0, 1}, {1, 2}, {2, 3}, {0, 3}};
    double *x = malloc(N / 4 * sizeof *x), *y = malloc(N / 4 * sizeof *y);
    ck_assert(x && y);
    for (size_t w = 0; w < sizeof words / sizeof words[0]; w++) {
        for (int i = 0; i < N / 4; i++) {
            const int g = i / 256, j = i % 256;
            x[i] = a[2 * (1024 * g + 256 * words[w][0] + j)];
            y[i] = a[2 * (1024 * g + 256 * words[w][1] + j)];
        }
        char what[64];
        snprintf(what, sizeof what, "words %d and %d of a block", words[w][0], words[w][1]);
        f32_uncorrelated(x, y, N / 4, 1, 5 / sqrt(N / 4.0), what);
    }
    free(x);
    free(y);
    f32_uncorrelated(a, a + 1, N, 2, 5 / sqrt((double)N), "components 0 and 1");
    f32_uncorrelated(a, a + 2, N - 1, 2, 5 / sqrt(N - 1.0), "ids k, k + 1");
    for (size_t o = 0; o < sizeof other / sizeof other[0]; o++) {
        gr_noise_normals_f32(other[o].seed, other[o].stream, other[o].step, 0, N, 2, b);
        f32_uncorrelated(a, b, 2 * N, 1, 5 / sqrt(2.0 * N), other[o].what);
    }
    free(a);
    free(b);
}
END_TEST

START_TEST(test_f32_statistics)
{
    /* The single-precision normals against N(0, 1): the four raw moments of 4e6 draws within 5
     * standard errors (per = 1 and 2), the frequencies of |x| > 3, > R, > 4, > 4.5 in 1e7 draws
     * within 5 binomial standard errors (as test_moments and test_tails for the double path). */
    draw_normals = gr_noise_normals_f32;
    check_moments(SEED + 3, 200, 20000, 1, "f32");
    check_moments(SEED + 4, 100, 20000, 2, "f32");
    check_tails("f32");
    draw_normals = gr_noise_normals;
}
END_TEST

static Suite *noise_suite(void)
{
    Suite *s = suite_create("noise");
    TCase *exact = tcase_create("exact");
    tcase_add_test(exact, test_reference);
    tcase_add_test(exact, test_reference_uniform);
    tcase_add_test(exact, test_batch_independence);
    tcase_add_test(exact, test_per_consistency);
    tcase_add_test(exact, test_id_range_ends);
    tcase_add_loop_test(exact, test_kernels_agree, 0, 4);
    tcase_add_test(exact, test_golden);
    tcase_add_test(exact, test_f32_exact);
    tcase_add_test(exact, test_f32_reference);
    tcase_add_test(exact, test_f32_transform);
    tcase_set_timeout(exact, 120);
    suite_add_tcase(s, exact);
    TCase *stats = tcase_create("statistics");
    tcase_add_test(stats, test_moments);
    tcase_add_test(stats, test_kolmogorov_smirnov);
    tcase_add_test(stats, test_chi_square);
    tcase_add_test(stats, test_tails);
    tcase_add_test(stats, test_correlations);
    tcase_add_test(stats, test_uniform);
    tcase_add_test(stats, test_f32_statistics);
    tcase_add_test(stats, test_f32_correlations);
    tcase_set_timeout(stats, 300);
    suite_add_tcase(s, stats);
    return s;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--isa-check") == 0) {
        return isa_check();
    }
    gsl_set_error_handler_off();
    return gr_test_run(noise_suite());
}
