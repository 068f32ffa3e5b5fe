/* The multiplicative cascade of thesis sec. 6.2 (src/theory/cascade.c): probability conservation
 * per variant (6.2)-(6.4), the FFT structure factor against the direct sum (6.5), the uniform
 * control, the Monte Carlo average against the exact second-moment average, D_f for UCP against
 * Table 6.2, overlap-free placement (Fig. 6.3) and the refusals. Fixed seeds throughout.
 *
 * Environment: GRANULE_TEST_QUICK=1 (ASan/UBSan builds) uses fewer configurations where the
 * tolerances are statistical and scale with them. */
#include <check.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/cascade.h"
#include "check_main.h"

static int quick(void)
{
    const char *v = getenv("GRANULE_TEST_QUICK");
    return v && *v && strcmp(v, "0") != 0;
}

static gsl_rng *rng_new(unsigned long seed)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    return r;
}

static gr_cascade_settings settings(gr_cascade_variant v, int levels)
{
    gr_cascade_settings s;
    gr_cascade_settings_default(&s);
    s.variant = v;
    s.levels = levels;
    return s;
}

/* sum of the level-(l+1) children of every level-l square, compared with the saved parents */
static double max_parent_mismatch(const gr_cascade_field *f, const double *parents, int l)
{
    const int n = 1 << l, side = f->side;
    double worst = 0.0;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            double sum = 0.0;
            for (int h = 0; h < 2; h++) {
                for (int g = 0; g < 2; g++) {
                    sum += f->m[(2 * j + h) * side + 2 * i + g];
                }
            }
            double p = parents[j * n + i];
            worst = fmax(worst, fabs(sum - p) / p);
        }
    }
    return worst;
}

/* ---------------------------------------------------------------------------------------------
 * Conservation */

static const gr_cascade_variant conserving[] = {
    GR_CASCADE_UCP,     GR_CASCADE_SYMMETRISED, GR_CASCADE_MEAKIN1, GR_CASCADE_MEAKIN2,
    GR_CASCADE_MEAKIN3, GR_CASCADE_MEAKIN4,     GR_CASCADE_UNIFORM};

START_TEST(test_unweighted_fit)
{
    /* S = A k^-D exactly: both fits give D. With a shell-to-shell scatter of +-10% (what the
     * lattice does) and tiny error bars, the weighted chi2/dof is huge; the unweighted fit still
     * finds D within its error from the scatter, and that error is the scatter's, not S_err's. */
    gr_cascade_sk_bin b[40];
    const double A = 3.0, D = 1.6;
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < 40; i++) {
            const double k = 2.0 * M_PI * (i + 1),
                         wiggle = pass ? 1.0 + 0.1 * ((i % 3) - 1.0) : 1.0;
            b[i] = (gr_cascade_sk_bin){.q = i + 1,
                                       .k = k,
                                       .vectors = 4 * (i + 1),
                                       .S = A * pow(k, -D) * wiggle,
                                       .S_err = 1e-3 * A * pow(k, -D),
                                       .S_expected = A * pow(k, -D)};
        }
        gr_cascade_fit w, u;
        gr_error err = {0};
        ck_assert(gr_cascade_fit_df(b, 40, 1, 40, false, &w, &err) == 0);
        ck_assert(gr_cascade_fit_df_unweighted(b, 40, 1, 40, &u, &err) == 0);
        ck_assert_int_eq(u.points, 40);
        if (!pass) {
            ck_assert(fabs(u.D_f - D) < 1e-10 && fabs(w.D_f - D) < 1e-10 &&
                      fabs(u.A / A - 1.0) < 1e-9);
        } else {
            ck_assert_msg(w.chi2_red > 100.0, "weighted chi2/dof %g", w.chi2_red);
            ck_assert_msg(fabs(u.D_f - D) < 3.0 * u.D_f_err, "unweighted D_f %g +- %g", u.D_f,
                          u.D_f_err);
            /* the residual variance of ln S is that of ln(1 + 0.1 {-1, 0, 1}): about 0.0067 */
            ck_assert_msg(fabs(u.chi2_red / 0.0067 - 1.0) < 0.2, "residual variance %g",
                          u.chi2_red);
            ck_assert(u.D_f_err > 0.005 && u.D_f_err < 0.1);
        }
    }
}
END_TEST

START_TEST(test_conserving_variants)
{
    /* (6.2)-(6.3): the four children share their parent's probability exactly (to rounding), so the
     * total is 1 at every level, and each parent equals the sum of its children */
    const gr_cascade_variant v = conserving[_i];
    gr_cascade_settings s = settings(v, 8);
    gr_error err = {0};
    gr_cascade_field *f;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    double *parents = malloc(sizeof(double) * (size_t)f->side * (size_t)f->side);
    gsl_rng *r = rng_new(11 + (unsigned long)_i);
    gr_cascade_field_reset(f);
    ck_assert_double_eq(gr_cascade_field_total(f), 1.0);
    for (int l = 0; l < s.levels; l++) {
        const int n = 1 << l;
        for (int j = 0; j < n; j++) {
            for (int i = 0; i < n; i++) {
                parents[j * n + i] = f->m[j * f->side + i];
            }
        }
        ck_assert_int_eq(gr_cascade_refine(&s, r, f, &err), 0);
        ck_assert_int_eq(f->level, l + 1);
        double mis = max_parent_mismatch(f, parents, l), total = gr_cascade_field_total(f);
        ck_assert_msg(mis < 1e-15,
                      "%s level %d: a parent differs from its children's sum by %g (relative)",
                      gr_cascade_variant_get(v)->name, l + 1, mis);
        ck_assert_msg(fabs(total - 1.0) < 1e-13, "%s level %d: total %.17g",
                      gr_cascade_variant_get(v)->name, l + 1, total);
    }
    /* the finished field refuses to be refined further */
    ck_assert_int_eq(gr_cascade_refine(&s, r, f, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "finest level"));
    free(parents);
    gsl_rng_free(r);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_unoncp_not_conserving)
{
    /* UnonCP (A = 1): children get m a_c with a_c ~ U(0,1), so the total is a random variable with mean
     * 2^l and a spread; it differs from configuration to configuration and from 1 */
    gr_cascade_settings s = settings(GR_CASCADE_UNONCP, 6);
    gr_error err = {0};
    gr_cascade_field *f;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    gsl_rng *r = rng_new(5);
    const int C = 400;
    double totals[7], sum[7] = {0}, sum2[7] = {0}, lo = (double)INFINITY, hi = -(double)INFINITY;
    for (int c = 0; c < C; c++) {
        ck_assert_int_eq(gr_cascade_generate(&s, r, f, totals, &err), 0);
        for (int l = 0; l <= s.levels; l++) {
            sum[l] += totals[l];
            sum2[l] += totals[l] * totals[l];
        }
        lo = fmin(lo, totals[s.levels] / 64.0);
        hi = fmax(hi, totals[s.levels] / 64.0);
        ck_assert_double_eq_tol(totals[s.levels], gr_cascade_field_total(f),
                                1e-12 * totals[s.levels]);
    }
    for (int l = 1; l <= s.levels; l++) {
        double mean = sum[l] / C, sd = sqrt(fmax(sum2[l] / C - mean * mean, 0.0));
        double expect = ldexp(1.0, l); /* (sum_c E a_c)^l = 2^l */
        ck_assert_msg(sd > 0.05 * mean,
                      "level %d: total spread %g around %g is too small for UnonCP", l, sd, mean);
        ck_assert_msg(fabs(mean - expect) < 5.0 * sd / sqrt(C),
                      "level %d: mean total %g, expected 2^l = %g", l, mean, expect);
    }
    ck_assert_msg(hi - lo > 0.2, "final totals / 2^6 span only [%g, %g]", lo, hi);
    gsl_rng_free(r);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_reproducible)
{
    gr_cascade_settings s = settings(GR_CASCADE_UCP, 5);
    gr_error err = {0};
    gr_cascade_field *a, *b;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &a, &err), 0);
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &b, &err), 0);
    gsl_rng *r1 = rng_new(42), *r2 = rng_new(42), *r3 = rng_new(43);
    gr_cascade_generate(&s, r1, a, NULL, &err);
    gr_cascade_generate(&s, r2, b, NULL, &err);
    ck_assert_int_eq(memcmp(a->m, b->m, sizeof(double) * 32 * 32), 0);
    gr_cascade_generate(&s, r3, b, NULL, &err);
    ck_assert_int_ne(memcmp(a->m, b->m, sizeof(double) * 32 * 32), 0);
    gsl_rng_free(r1);
    gsl_rng_free(r2);
    gsl_rng_free(r3);
    gr_cascade_field_free(a);
    gr_cascade_field_free(b);
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Structure factor */

START_TEST(test_fft_equals_direct_sum)
{
    /* (6.5) by FFTW against the literal double sum over cell centres r_{i,j} = L/2^n (i+1/2, j+1/2) */
    const gr_cascade_variant vs[] = {GR_CASCADE_UCP, GR_CASCADE_MEAKIN1, GR_CASCADE_UNONCP};
    const int q[][2] = {{1, 0}, {0, 1},  {1, 1},   {3, 5},    {-2, 7},
                        {8, 8}, {16, 0}, {-5, -3}, {13, -11}, {31, 2}};
    gr_error err = {0};
    for (size_t iv = 0; iv < sizeof vs / sizeof vs[0]; iv++) {
        for (int levels = 4; levels <= 5; levels++) {
            gr_cascade_settings s = settings(vs[iv], levels);
            gr_cascade_field *f;
            gr_cascade_sk *sk;
            ck_assert_int_eq(gr_cascade_field_alloc(levels, 1.0, &f, &err), 0);
            ck_assert_int_eq(gr_cascade_sk_alloc(&s, &sk, &err), 0);
            gsl_rng *r = rng_new(3 + iv);
            ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
            ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
            const double S0 = gr_cascade_sk_direct(f, 0, 0), total = gr_cascade_field_total(f);
            ck_assert_double_eq_tol(S0, total * total, 1e-12 * S0);
            ck_assert_double_eq_tol(gr_cascade_sk_last(sk, 0, 0), S0, 1e-12 * S0);
            for (size_t k = 0; k < sizeof q / sizeof q[0]; k++) {
                double fft = gr_cascade_sk_last(sk, q[k][0], q[k][1]),
                       direct = gr_cascade_sk_direct(f, q[k][0], q[k][1]);
                ck_assert_msg(fabs(fft - direct) < 1e-12 * S0 + 1e-9 * direct,
                              "%s n=%d q=(%d,%d): FFT %.15g, direct %.15g",
                              gr_cascade_variant_get(vs[iv])->name, levels, q[k][0], q[k][1], fft,
                              direct);
                /* S(-q) = S(q) */
                ck_assert_double_eq_tol(gr_cascade_sk_last(sk, -q[k][0], -q[k][1]), fft,
                                        1e-12 * S0);
            }
            gsl_rng_free(r);
            gr_cascade_sk_free(sk);
            gr_cascade_field_free(f);
        }
    }
}
END_TEST

START_TEST(test_uniform_field_has_no_structure)
{
    /* unit multipliers (a = 1, A = 4): m = 4^-n everywhere, so S(k) = |sum m e^{ik.r}|^2 = 0 for k != 0 */
    gr_cascade_settings s = settings(GR_CASCADE_UNIFORM, 6);
    s.configurations = 1;
    gr_error err = {0};
    gr_cascade_field *f;
    gr_cascade_sk *sk;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    ck_assert_int_eq(gr_cascade_sk_alloc(&s, &sk, &err), 0);
    gsl_rng *r = rng_new(1);
    ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
    for (int c = 0; c < f->side * f->side; c++) {
        ck_assert_double_eq(f->m[c], 1.0 / 4096.0);
    }
    ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
    ck_assert_double_eq_tol(gr_cascade_sk_last(sk, 0, 0), 1.0, 1e-14);
    double worst = 0.0;
    for (int qy = -32; qy < 32; qy++) {
        for (int qx = -32; qx < 32; qx++) {
            if (qx || qy) {
                worst = fmax(worst, gr_cascade_sk_last(sk, qx, qy));
                /* the exact average is a recursion of cancelling terms: zero to rounding of S(0) = 1 */
                ck_assert_double_eq_tol(gr_cascade_sk_expected(&s, qx, qy), 0.0, 1e-15);
            }
        }
    }
    ck_assert_msg(worst < 1e-28, "uniform field: S(k != 0) up to %g", worst);
    const int nb = gr_cascade_sk_nbins(sk);
    gr_cascade_sk_bin *b = malloc(sizeof *b * (size_t)nb);
    gr_cascade_sk_bins(sk, b);
    for (int i = 0; i < nb; i++) {
        ck_assert_msg(b[i].S < 1e-28, "bin %d: S = %g", b[i].q, b[i].S);
    }
    free(b);
    gsl_rng_free(r);
    gr_cascade_sk_free(sk);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_circular_bins)
{
    /* every lattice vector with 0 < |q| < 2^n/2 + 1/2 falls in exactly one bin, and a bin's S (and exact
     * average) is the mean of the configuration-averaged S (exact average) over its vectors */
    gr_cascade_settings s = settings(GR_CASCADE_MEAKIN2, 5);
    gr_error err = {0};
    gr_cascade_field *f;
    gr_cascade_sk *sk;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 2.0, &f, &err), 0);
    s.L = 2.0;
    ck_assert_int_eq(gr_cascade_sk_alloc(&s, &sk, &err), 0);
    gsl_rng *r = rng_new(9);
    for (int c = 0; c < 20; c++) {
        gr_cascade_generate(&s, r, f, NULL, &err);
        ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
    }
    ck_assert_int_eq(gr_cascade_sk_configurations(sk), 20);
    const int nb = gr_cascade_sk_nbins(sk);
    ck_assert_int_eq(nb, 16);
    gr_cascade_sk_bin *b = malloc(sizeof *b * (size_t)nb);
    gr_cascade_sk_bins(sk, b);
    double sumS[16] = {0}, sumE[16] = {0}, sumq[16] = {0};
    int count[16] = {0}, total = 0;
    for (int qy = -16; qy <= 16; qy++) {
        for (int qx = -16; qx <= 16; qx++) {
            double q = sqrt((double)(qx * qx + qy * qy));
            if (q == 0.0 || q >= 16.5) {
                continue;
            }
            int bin = (int)floor(q + 0.5) - 1;
            count[bin]++;
            sumS[bin] += gr_cascade_sk_mean(sk, qx, qy);
            sumE[bin] += gr_cascade_sk_expected(&s, qx, qy);
            sumq[bin] += q;
            total++;
        }
    }
    int counted = 0;
    for (int i = 0; i < nb; i++) {
        ck_assert_int_eq(b[i].q, i + 1);
        ck_assert_int_eq(b[i].vectors, count[i]);
        ck_assert_double_eq_tol(b[i].q_mean, sumq[i] / count[i], 1e-12);
        ck_assert_double_eq_tol(b[i].k, 2.0 * M_PI * b[i].q_mean / 2.0, 1e-12);
        ck_assert_msg(fabs(b[i].S - sumS[i] / count[i]) < 1e-12 * b[i].S, "bin %d: %g vs %g", i + 1,
                      b[i].S, sumS[i] / count[i]);
        ck_assert(b[i].S_err > 0.0);
        /* the bins' exact average (phases from a table) equals the per-vector one (phases from sin/cos) */
        ck_assert_msg(fabs(b[i].S_expected - sumE[i] / count[i]) < 1e-12 * b[i].S_expected,
                      "bin %d: %.15g vs %.15g", i + 1, b[i].S_expected, sumE[i] / count[i]);
        counted += b[i].vectors;
    }
    ck_assert_int_eq(counted, total);
    ck_assert_int_eq(b[0].vectors, 8); /* (+-1, 0), (0, +-1), (+-1, +-1) */
    free(b);
    gsl_rng_free(r);
    gr_cascade_sk_free(sk);
    gr_cascade_field_free(f);
}
END_TEST

static const gr_cascade_variant all_random[] = {
    GR_CASCADE_UCP,     GR_CASCADE_UNONCP,  GR_CASCADE_SYMMETRISED, GR_CASCADE_MEAKIN1,
    GR_CASCADE_MEAKIN2, GR_CASCADE_MEAKIN3, GR_CASCADE_MEAKIN4};

START_TEST(test_average_matches_exact_expectation)
{
    /* The four sub-cascades of a square are independent, so the configuration average of (6.5) follows
     * exactly from E[w_c] and E[w_c w_c'] (gr_cascade_sk_expected). The Monte Carlo mean must agree
     * within its statistical error at every k: this checks each variant's multipliers (6.2)-(6.4) and
     * Table 6.1 down to their second moments. */
    const gr_cascade_variant v = all_random[_i];
    gr_cascade_settings s = settings(v, 4);
    const int C = quick() ? 1500 : 6000;
    gr_error err = {0};
    gr_cascade_field *f;
    gr_cascade_sk *sk;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    ck_assert_int_eq(gr_cascade_sk_alloc(&s, &sk, &err), 0);
    enum { NQ = 8 };
    const int q[NQ][2] = {{1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 1}, {4, 4}, {5, 2}, {-7, 3}};
    double sum[NQ] = {0}, sum2[NQ] = {0};
    gsl_rng *r = rng_new(100 + (unsigned long)_i);
    for (int c = 0; c < C; c++) {
        gr_cascade_generate(&s, r, f, NULL, &err);
        ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
        for (int k = 0; k < NQ; k++) {
            double x = gr_cascade_sk_last(sk, q[k][0], q[k][1]);
            sum[k] += x;
            sum2[k] += x * x;
        }
    }
    const char *name = gr_cascade_variant_get(v)->name;
    for (int k = 0; k < NQ; k++) {
        double mean = sum[k] / C, se = sqrt(fmax(sum2[k] / C - mean * mean, 0.0) / (C - 1));
        double exact = gr_cascade_sk_expected(&s, q[k][0], q[k][1]);
        ck_assert_double_eq_tol(gr_cascade_sk_mean(sk, q[k][0], q[k][1]), mean, 1e-9 * mean);
        ck_assert_msg(fabs(mean - exact) < 5.0 * se + 1e-12,
                      "%s q=(%d,%d): Monte Carlo %g +- %g, exact %g", name, q[k][0], q[k][1], mean,
                      se, exact);
    }
    const int nb = gr_cascade_sk_nbins(sk);
    gr_cascade_sk_bin *b = malloc(sizeof *b * (size_t)nb);
    gr_cascade_sk_bins(sk, b);
    for (int i = 0; i < nb; i++) {
        ck_assert_msg(fabs(b[i].S - b[i].S_expected) < 5.0 * b[i].S_err,
                      "%s bin %d: %g +- %g, exact %g", name, b[i].q, b[i].S, b[i].S_err,
                      b[i].S_expected);
    }
    /* With a uniform mean field (all but Symmetrised) the cross terms vanish at integer q, so
     * S_n(2q) = sum_c E[w_c^2] S_(n-1)(q) exactly: the octave law behind D_2 */
    if (v != GR_CASCADE_SYMMETRISED) {
        gr_cascade_settings s8 = settings(v, 8), s7 = settings(v, 7);
        double mean[4], second[4][4], diag = 0.0;
        gr_cascade_moments(&s8, mean, second);
        for (int c = 0; c < 4; c++) {
            diag += second[c][c];
        }
        const int qq[][2] = {{1, 0}, {2, 1}, {3, 3}, {5, -2}, {17, 4}};
        for (size_t k = 0; k < sizeof qq / sizeof qq[0]; k++) {
            double ratio = gr_cascade_sk_expected(&s8, 2 * qq[k][0], 2 * qq[k][1]) /
                           gr_cascade_sk_expected(&s7, qq[k][0], qq[k][1]);
            ck_assert_msg(fabs(ratio / diag - 1.0) < 1e-9,
                          "%s q=(%d,%d): S_8(2q)/S_7(q) = %.15g, sum E w^2 = %.15g", name, qq[k][0],
                          qq[k][1], ratio, diag);
        }
    }
    free(b);
    gsl_rng_free(r);
    gr_cascade_sk_free(sk);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_d2_values)
{
    /* D_2 = -log2(sum E w^2 / (sum E w)^2): UCP from the exact E w^2 = 1/2 + 27/2 ln 3 - 22 ln 2 of normalised
     * uniforms; UnonCP and Symmetrised log2 3; Meakin -log2(sum p^2 / (sum p)^2) */
    gr_cascade_settings s = settings(GR_CASCADE_UCP, 8);
    ck_assert_double_eq_tol(gr_cascade_d2(&s), 1.6077410609097263, 1e-12);
    s.variant = GR_CASCADE_UNONCP;
    ck_assert_double_eq_tol(gr_cascade_d2(&s), log2(3.0), 1e-12);
    s.variant = GR_CASCADE_SYMMETRISED;
    ck_assert_double_eq_tol(gr_cascade_d2(&s), log2(3.0), 1e-12);
    s.variant = GR_CASCADE_MEAKIN2;
    ck_assert_double_eq_tol(
        gr_cascade_d2(&s), -log2(0.02 * 0.02 + 3 * 0.32 * 0.32 - 0.32 * 0.32 + 0.34 * 0.34), 1e-12);
    s.variant = GR_CASCADE_MEAKIN;
    s.p[0] = 2.0, s.p[1] = 2.0, s.p[2] = 2.0, s.p[3] = 2.0;
    ck_assert_double_eq_tol(gr_cascade_d2(&s), 2.0, 1e-12);
    /* the second moments of a conserving variant sum to (sum E w)^2 = 1 (sum w = 1 exactly); for UnonCP to
     * E (sum a)^2 = 4 + 4 Var a = 4 + 1/3 */
    for (int v = 0; v < GR_CASCADE_NVARIANTS; v++) {
        s.variant = (gr_cascade_variant)v;
        double mean[4], second[4][4], m = 0.0, m2 = 0.0;
        gr_cascade_moments(&s, mean, second);
        for (int c = 0; c < 4; c++) {
            m += mean[c];
            for (int d = 0; d < 4; d++) {
                m2 += second[c][d];
            }
        }
        const bool cons = gr_cascade_variant_get(s.variant)->conserving;
        ck_assert_int_eq(cons, v != GR_CASCADE_UNONCP);
        ck_assert_msg(fabs(m2 - (cons ? 1.0 : 4.0 + 1.0 / 3.0)) < 1e-14 &&
                          fabs(m - (cons ? 1.0 : 2.0)) < 1e-15,
                      "%s: sum E w = %.17g, sum E w w' = %.17g",
                      gr_cascade_variant_get(s.variant)->name, m, m2);
    }
}
END_TEST

START_TEST(test_ucp_fractal_dimension)
{
    /* Table 6.2 / SPEC sec. 6: UCP gives D_f = 1.602 +- 0.066. At the thesis's 8 levels the default fit
     * (bins 1..32) must agree with it within the combined errors, agree with the fit of the exact average
     * (1.585) within 3 of its own errors, and separate UCP from Meakin 1 (1.29 in Table 6.2). */
    const int C = quick() ? 100 : 300;
    double df[2], err_df[2];
    const gr_cascade_variant vs[2] = {GR_CASCADE_UCP, GR_CASCADE_MEAKIN1};
    for (int iv = 0; iv < 2; iv++) {
        gr_cascade_settings s = settings(vs[iv], 8);
        s.configurations = C;
        gr_error err = {0};
        gr_cascade_field *f;
        gr_cascade_sk *sk;
        ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
        ck_assert_int_eq(gr_cascade_sk_alloc(&s, &sk, &err), 0);
        gsl_rng *r = rng_new(2009);
        for (int c = 0; c < C; c++) {
            ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
            ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
        }
        const int nb = gr_cascade_sk_nbins(sk);
        gr_cascade_sk_bin *b = malloc(sizeof *b * (size_t)nb);
        gr_cascade_sk_bins(sk, b);
        double q_min, q_max;
        gr_cascade_fit_range(&s, &q_min, &q_max);
        ck_assert_double_eq(q_min, 1.0);
        ck_assert_double_eq(q_max, 32.0);
        gr_cascade_fit fit, exact;
        ck_assert_int_eq(gr_cascade_fit_df(b, nb, q_min, q_max, false, &fit, &err), 0);
        ck_assert_int_eq(gr_cascade_fit_df(b, nb, q_min, q_max, true, &exact, &err), 0);
        ck_assert_int_eq(fit.points, 32);
        ck_assert(fit.D_f_err > 0.0 && fit.D_f_err < 0.05);
        ck_assert_msg(fabs(fit.D_f - exact.D_f) < 3.0 * fit.D_f_err,
                      "%s: D_f %.3f +- %.3f, exact average %.3f",
                      gr_cascade_variant_get(vs[iv])->name, fit.D_f, fit.D_f_err, exact.D_f);
        df[iv] = fit.D_f;
        err_df[iv] = fit.D_f_err;
        free(b);
        gsl_rng_free(r);
        gr_cascade_sk_free(sk);
        gr_cascade_field_free(f);
    }
    const gr_cascade_variant_info *ucp = gr_cascade_variant_get(GR_CASCADE_UCP);
    ck_assert_double_eq(ucp->thesis_D_f, 1.602);
    ck_assert_msg(fabs(df[0] - ucp->thesis_D_f) < hypot(err_df[0], ucp->thesis_D_f_err),
                  "UCP D_f = %.3f +- %.3f, Table 6.2: 1.602 +- 0.066", df[0], err_df[0]);
    ck_assert_msg(df[0] - df[1] > 5.0 * hypot(err_df[0], err_df[1]), "UCP %.3f vs Meakin 1 %.3f",
                  df[0], df[1]);
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Placement (Fig. 6.3) */

START_TEST(test_placement_no_overlap)
{
    gr_cascade_settings s = settings(GR_CASCADE_UCP, 7);
    gr_error err = {0};
    gr_cascade_field *f;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 0.2, &f, &err), 0);
    gsl_rng *r = rng_new(17);
    ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
    gr_cascade_placement p;
    gr_cascade_placement_default(&p);
    ck_assert_int_eq(p.n, 2500);
    ck_assert_double_eq(p.radius, 1.5e-3);
    p.n = quick() ? 1000 : 2500; /* Fig. 6.3: phi = 0.442 at 2500 */
    double *x = malloc(sizeof(double) * (size_t)p.n), *y = malloc(sizeof(double) * (size_t)p.n);
    gr_cascade_placement_result res;
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), 0);
    ck_assert_int_eq(res.attempts, p.n + res.rejected);
    ck_assert(res.rejected > 0);
    const double L = 0.2, d = 2.0 * p.radius;
    ck_assert_double_eq_tol(res.phi, p.n * M_PI * p.radius * p.radius / (L * L), 1e-15);
    double closest = (double)INFINITY;
    for (int i = 0; i < p.n; i++) {
        ck_assert(x[i] >= 0.0 && x[i] < L && y[i] >= 0.0 && y[i] < L);
        for (int j = 0; j < i; j++) { /* brute force, periodic minimum image */
            double dx = x[i] - x[j], dy = y[i] - y[j];
            dx -= L * nearbyint(dx / L);
            dy -= L * nearbyint(dy / L);
            closest = fmin(closest, sqrt(dx * dx + dy * dy));
        }
    }
    ck_assert_msg(closest >= d * (1.0 - 1e-12), "closest pair %g m apart, diameter %g m", closest,
                  d);
    free(x);
    free(y);
    gsl_rng_free(r);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_placement_follows_field)
{
    /* dilute discs land in the 16 level-2 squares in proportion to their probability (binomial, 5 sigma) */
    gr_cascade_settings s = settings(GR_CASCADE_UCP, 6);
    gr_error err = {0};
    gr_cascade_field *f;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    gsl_rng *r = rng_new(23);
    ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
    double prob[16] = {0};
    for (int j = 0; j < 64; j++) {
        for (int i = 0; i < 64; i++) {
            prob[(j / 16) * 4 + i / 16] += f->m[j * 64 + i];
        }
    }
    gr_cascade_placement p = {.n = 20000, .radius = 1e-5, .max_attempts = 0};
    double *x = malloc(sizeof(double) * (size_t)p.n), *y = malloc(sizeof(double) * (size_t)p.n);
    gr_cascade_placement_result res;
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), 0);
    int count[16] = {0};
    for (int i = 0; i < p.n; i++) {
        count[(int)(y[i] * 4.0) * 4 + (int)(x[i] * 4.0)]++;
    }
    for (int c = 0; c < 16; c++) {
        double expect = p.n * prob[c], sd = sqrt(p.n * prob[c] * (1.0 - prob[c]));
        ck_assert_msg(fabs(count[c] - expect) < 5.0 * sd + 1.0,
                      "square %d: %d discs, expected %g +- %g", c, count[c], expect, sd);
    }
    free(x);
    free(y);
    gsl_rng_free(r);
    gr_cascade_field_free(f);
}
END_TEST

START_TEST(test_placement_refusals)
{
    gr_cascade_settings s = settings(GR_CASCADE_UCP, 4);
    gr_error err = {0};
    gr_cascade_field *f;
    ck_assert_int_eq(gr_cascade_field_alloc(s.levels, 1.0, &f, &err), 0);
    gsl_rng *r = rng_new(1);
    double x[400], y[400];
    gr_cascade_placement_result res;
    /* unfinished field */
    gr_cascade_placement p = {.n = 10, .radius = 0.01, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
    /* above the random-sequential-addition jamming limit: phi = 400 pi 0.025^2 = 0.785 */
    p = (gr_cascade_placement){.n = 400, .radius = 0.025, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "packing fraction 0.785"));
    ck_assert_int_eq(gr_cascade_placement_check(&p, 1.0, &err), GR_EINVAL);
    /* box smaller than two diameters, no discs, no radius */
    p = (gr_cascade_placement){.n = 1, .radius = 0.3, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "two diameters"));
    p = (gr_cascade_placement){.n = 0, .radius = 0.01, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    p = (gr_cascade_placement){.n = 5, .radius = -1.0, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    /* a field whose probability sits in one square of side 1/16: at most ~9 discs of radius 0.02 fit */
    s.variant = GR_CASCADE_MEAKIN;
    s.p[0] = 1.0, s.p[1] = s.p[2] = s.p[3] = 0.0;
    ck_assert_int_eq(gr_cascade_settings_check(&s, &err), 0);
    ck_assert_int_eq(gr_cascade_generate(&s, r, f, NULL, &err), 0);
    p = (gr_cascade_placement){.n = 50, .radius = 0.02, .max_attempts = 200000};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "placed only"));
    ck_assert_int_eq(res.attempts, 200000);
    /* a field of zero probability */
    s.p[0] = 0.0;
    memset(f->m, 0, sizeof(double) * 256);
    p = (gr_cascade_placement){.n = 5, .radius = 0.01, .max_attempts = 0};
    ck_assert_int_eq(gr_cascade_place(f, &p, r, x, y, &res, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "total probability"));
    gsl_rng_free(r);
    gr_cascade_field_free(f);
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Bad inputs */

START_TEST(test_bad_inputs)
{
    gr_error err = {0};
    gr_cascade_settings s;
    gr_cascade_settings_default(&s);
    ck_assert_int_eq(s.levels, 8);
    ck_assert_int_eq(s.variant, GR_CASCADE_UCP);
    ck_assert_int_eq(gr_cascade_settings_check(&s, &err), 0);
    gr_cascade_settings b = s;
    b.levels = 0;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "levels"));
    b.levels = GR_CASCADE_MAX_LEVELS + 1;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b = s;
    b.L = 0.0;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b.L = (double)NAN;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b = s;
    b.configurations = 0;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b = s;
    b.variant = GR_CASCADE_NVARIANTS;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b = s;
    b.variant = GR_CASCADE_MEAKIN;
    b.p[1] = -0.1;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "p2"));
    b.p[0] = b.p[1] = b.p[2] = b.p[3] = 0.0;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b = s;
    b.fit_q_min = 10.0, b.fit_q_max = 11.0; /* two bins */
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b.fit_q_min = 1.0, b.fit_q_max = 129.0; /* beyond 2^7 */
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    b.fit_q_min = 0.0, b.fit_q_max = 0.0;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), GR_EINVAL);
    /* small grids: the automatic range is capped, and with fewer than 3 bins there is simply no fit */
    b = s;
    b.levels = 2;
    ck_assert_int_eq(gr_cascade_settings_check(&b, &err), 0);
    double lo, hi;
    gr_cascade_fit_range(&b, &lo, &hi);
    ck_assert_double_eq(hi, 2.0);
    b.levels = 12;
    gr_cascade_fit_range(&b, &lo, &hi);
    ck_assert_double_eq(hi, 512.0);
    /* names */
    gr_cascade_variant v;
    ck_assert_int_eq(gr_cascade_variant_parse("Meakin3", &v, &err), 0);
    ck_assert_int_eq(v, GR_CASCADE_MEAKIN3);
    ck_assert_int_eq(gr_cascade_variant_parse("symmetrized", &v, &err), 0);
    ck_assert_int_eq(v, GR_CASCADE_SYMMETRISED);
    ck_assert_int_eq(gr_cascade_variant_parse("meakin5", &v, &err), GR_EINVAL);
    ck_assert_ptr_nonnull(strstr(err.message, "meakin5"));
    ck_assert_ptr_null(gr_cascade_variant_get(GR_CASCADE_NVARIANTS));
    /* fields and accumulators */
    gr_cascade_field *f = NULL;
    ck_assert_int_eq(gr_cascade_field_alloc(GR_CASCADE_MAX_LEVELS + 1, 1.0, &f, &err), GR_EINVAL);
    ck_assert_ptr_null(f);
    gr_cascade_sk *sk = NULL;
    b = s;
    b.levels = 0;
    ck_assert_int_eq(gr_cascade_sk_alloc(&b, &sk, &err), GR_EINVAL);
    ck_assert_ptr_null(sk);
    b.levels = 3;
    ck_assert_int_eq(gr_cascade_sk_alloc(&b, &sk, &err), 0);
    ck_assert(isnan(gr_cascade_sk_last(sk, 1, 0)));
    ck_assert_int_eq(gr_cascade_field_alloc(3, 1.0, &f, &err), 0);
    ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), GR_EINVAL); /* level 0 of 3 */
    gr_cascade_field *g;
    ck_assert_int_eq(gr_cascade_field_alloc(4, 1.0, &g, &err), 0);
    gsl_rng *r = rng_new(1);
    gr_cascade_generate(&b, r, g, NULL, &err);
    ck_assert_int_eq(gr_cascade_sk_add(sk, g, &err),
                     GR_EINVAL); /* 4 levels into a 3-level accumulator */
    gr_cascade_generate(&b, r, f, NULL, &err);
    ck_assert_int_eq(gr_cascade_sk_add(sk, f, &err), 0);
    gr_cascade_sk_bin bins[4];
    ck_assert_int_eq(gr_cascade_sk_nbins(sk), 4);
    gr_cascade_sk_bins(sk, bins);
    ck_assert(isnan(bins[0].S_err)); /* one configuration: no error bar */
    gr_cascade_fit fit;
    ck_assert_int_eq(gr_cascade_fit_df(bins, 4, 1.0, 2.0, false, &fit, &err), GR_EINVAL);
    ck_assert_int_eq(gr_cascade_fit_df(bins, 4, 1.0, 4.0, false, &fit, &err), 0); /* unweighted */
    ck_assert(isfinite(fit.D_f));
    gsl_rng_free(r);
    gr_cascade_field_free(f);
    gr_cascade_field_free(g);
    gr_cascade_sk_free(sk);
}
END_TEST

int main(void)
{
    gsl_set_error_handler_off();
    Suite *s = suite_create("cascade");
    TCase *unit = tcase_create("unit");
    tcase_add_loop_test(unit, test_conserving_variants, 0,
                        (int)(sizeof conserving / sizeof conserving[0]));
    tcase_add_test(unit, test_unoncp_not_conserving);
    tcase_add_test(unit, test_unweighted_fit);
    tcase_add_test(unit, test_reproducible);
    tcase_add_test(unit, test_fft_equals_direct_sum);
    tcase_add_test(unit, test_uniform_field_has_no_structure);
    tcase_add_test(unit, test_circular_bins);
    tcase_add_test(unit, test_d2_values);
    tcase_add_test(unit, test_placement_refusals);
    tcase_add_test(unit, test_bad_inputs);
    suite_add_tcase(s, unit);
    TCase *physics = tcase_create("physics");
    tcase_set_timeout(physics, 300);
    tcase_add_loop_test(physics, test_average_matches_exact_expectation, 0,
                        (int)(sizeof all_random / sizeof all_random[0]));
    tcase_add_test(physics, test_ucp_fractal_dimension);
    tcase_add_test(physics, test_placement_no_overlap);
    tcase_add_test(physics, test_placement_follows_field);
    suite_add_tcase(s, physics);
    return gr_test_run(s);
}
