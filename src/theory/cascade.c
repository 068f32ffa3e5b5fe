/* The multiplicative cascade process of thesis sec. 6.2: generation of the field m_{i,j} (6.1)-(6.4)
 * for the variants of Table 6.1, its structure factor (6.5) by FFTW with the circular average of
 * sec. 4.1 (4.2-4.3), the exact configuration average from the multipliers' moments, the D_f fit
 * (4.4) and the overlap-free placement of discs of Fig. 6.3. See include/granule/cascade.h and
 * docs/theory-cascade.md. */
#include <complex.h>
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "granule/analysis.h"
#include "granule/cascade.h"

static const gr_cascade_variant_info variants[GR_CASCADE_NVARIANTS] = {
    [GR_CASCADE_UCP] = {"ucp", "UCP", {0, 0, 0, 0}, 1.602, 0.066, true},
    [GR_CASCADE_UNONCP] = {"unoncp", "UnonCP", {0, 0, 0, 0}, 1.595, 0.064, false},
    [GR_CASCADE_SYMMETRISED] =
        {"symmetrised", "Symmetrised Cascade", {0, 0, 0, 0}, (double)NAN, (double)NAN, true},
    [GR_CASCADE_MEAKIN1] = {"meakin1", "Meakin 1", {0.001, 0.15, 0.32, 0.53}, 1.287, 0.084, true},
    [GR_CASCADE_MEAKIN2] = {"meakin2", "Meakin 2", {0.02, 0.32, 0.32, 0.34}, 1.596, 0.147, true},
    [GR_CASCADE_MEAKIN3] = {"meakin3", "Meakin 3", {0.18, 0.21, 0.29, 0.31}, 1.828, 0.233, true},
    [GR_CASCADE_MEAKIN4] = {"meakin4", "Meakin 4", {0.07, 0.26, 0.32, 0.36}, 1.689, 0.178, true},
    [GR_CASCADE_MEAKIN] =
        {"meakin", "Meakin (custom p)", {0, 0, 0, 0}, (double)NAN, (double)NAN, true},
    [GR_CASCADE_UNIFORM] =
        {"uniform", "uniform (control)", {0, 0, 0, 0}, (double)NAN, (double)NAN, true},
};

const gr_cascade_variant_info *gr_cascade_variant_get(gr_cascade_variant v)
{
    return (int)v >= 0 && v < GR_CASCADE_NVARIANTS ? &variants[v] : NULL;
}

int gr_cascade_variant_parse(const char *name, gr_cascade_variant *out, gr_error *err)
{
    for (int v = 0; v < GR_CASCADE_NVARIANTS; v++) {
        if (name && strcasecmp(name, variants[v].name) == 0) {
            *out = (gr_cascade_variant)v;
            return GR_OK;
        }
    }
    if (name && strcasecmp(name, "symmetrized") == 0) {
        *out = GR_CASCADE_SYMMETRISED;
        return GR_OK;
    }
    return GR_FAIL(
        err, GR_EINVAL,
        "unknown cascade variant '%s': expected ucp, unoncp, symmetrised, meakin1, meakin2, "
        "meakin3, meakin4, meakin (with p) or uniform",
        name ? name : "");
}

void gr_cascade_settings_default(gr_cascade_settings *s)
{
    memset(s, 0, sizeof *s);
    s->levels = 8;
    s->variant = GR_CASCADE_UCP;
    s->p[0] = s->p[1] = s->p[2] = s->p[3] = 0.25;
    s->L = 1.0;
    s->configurations = 200;
    s->seed = 1;
    s->fit_q_min = 1.0;
    s->fit_q_max = 0.0; /* automatic */
}

void gr_cascade_fit_range(const gr_cascade_settings *s, double *q_min, double *q_max)
{
    const double top = ldexp(1.0, s->levels - 1); /* the last bin, |q| = 2^n / 2 */
    *q_min = s->fit_q_min;
    *q_max = s->fit_q_max > 0.0 ? s->fit_q_max : fmin(fmax(ldexp(1.0, s->levels - 3), 4.0), top);
}

/* the four numbers a_c the variant shares a square by (Meakin: the table's or the caller's) */
static const double *meakin_p(const gr_cascade_settings *s)
{
    return s->variant == GR_CASCADE_MEAKIN ? s->p : variants[s->variant].p;
}

int gr_cascade_settings_check(const gr_cascade_settings *s, gr_error *err)
{
    if ((int)s->variant < 0 || s->variant >= GR_CASCADE_NVARIANTS) {
        return GR_FAIL(err, GR_EINVAL, "cascade: unknown variant %d", (int)s->variant);
    }
    if (s->levels < 1 || s->levels > GR_CASCADE_MAX_LEVELS) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade: levels must lie in [1, %d] (a 2^n x 2^n grid), got %d",
                       GR_CASCADE_MAX_LEVELS, s->levels);
    }
    if (!(s->L > 0.0) || !isfinite(s->L)) {
        return GR_FAIL(err, GR_EINVAL, "cascade: box side L must be > 0 m, got %g", s->L);
    }
    if (s->configurations < 1) {
        return GR_FAIL(err, GR_EINVAL, "cascade: configurations must be >= 1, got %d",
                       s->configurations);
    }
    if (s->variant == GR_CASCADE_MEAKIN) {
        double sum = 0.0;
        for (int c = 0; c < 4; c++) {
            if (!(s->p[c] >= 0.0) || !isfinite(s->p[c])) {
                return GR_FAIL(err, GR_EINVAL,
                               "cascade: Meakin numbers p must be finite and >= 0, got p%d = %g",
                               c + 1, s->p[c]);
            }
            sum += s->p[c];
        }
        if (!(sum > 0.0)) {
            return GR_FAIL(err, GR_EINVAL, "cascade: Meakin numbers p must not all be 0");
        }
    }
    const double top = ldexp(1.0, s->levels - 1);
    double q_min, q_max;
    gr_cascade_fit_range(s, &q_min, &q_max);
    /* an explicit range must hold 3 bins; the automatic one may not (levels < 3: no fit, not an error) */
    if (!(q_min >= 1.0) || !(s->fit_q_max >= 0.0) ||
        (s->fit_q_max > 0.0 && (!(q_max <= top) || !(q_max >= q_min + 2.0)))) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade: the fit range must hold at least 3 bins within 1..2^(levels-1) = "
                       "%g, got %g..%g",
                       top, q_min, q_max);
    }
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * The field */

int gr_cascade_field_alloc(int levels, double L, gr_cascade_field **out, gr_error *err)
{
    *out = NULL;
    if (levels < 0 || levels > GR_CASCADE_MAX_LEVELS || !(L > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade field: levels must lie in [0, %d] and L > 0, got %d and %g",
                       GR_CASCADE_MAX_LEVELS, levels, L);
    }
    gr_cascade_field *f = calloc(1, sizeof *f);
    if (!f) {
        return GR_FAIL(err, GR_ENOMEM, "cascade field: out of memory");
    }
    f->levels = levels;
    f->side = 1 << levels;
    f->L = L;
    f->m = fftw_alloc_real((size_t)f->side * (size_t)f->side);
    if (!f->m) {
        free(f);
        return GR_FAIL(err, GR_ENOMEM, "cascade field: out of memory for %d x %d squares",
                       1 << levels, 1 << levels);
    }
    gr_cascade_field_reset(f);
    *out = f;
    return GR_OK;
}

void gr_cascade_field_free(gr_cascade_field *f)
{
    if (f) {
        fftw_free(f->m);
        free(f);
    }
}

void gr_cascade_field_reset(gr_cascade_field *f)
{
    memset(f->m, 0, sizeof(double) * (size_t)f->side * (size_t)f->side);
    f->m[0] = 1.0; /* level 0: the whole box, m_{0,0}(0) = 1 at r = L/2 (1, 1) */
    f->level = 0;
}

double gr_cascade_field_total(const gr_cascade_field *f)
{
    /* Neumaier's compensated sum: the result reflects the field, not 4^n roundings of the sum */
    const int s = 1 << f->level;
    double total = 0.0, comp = 0.0;
    for (int j = 0; j < s; j++) {
        for (int i = 0; i < s; i++) {
            const double x = f->m[(size_t)j * (size_t)f->side + (size_t)i], t = total + x;
            comp += fabs(total) >= fabs(x) ? (total - t) + x : (x - t) + total;
            total = t;
        }
    }
    return total + comp;
}

/* The 24 orders in which Meakin's four numbers can be dealt to the four children. */
static const unsigned char perms[24][4] = {
    {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {0, 3, 2, 1},
    {1, 0, 2, 3}, {1, 0, 3, 2}, {1, 2, 0, 3}, {1, 2, 3, 0}, {1, 3, 0, 2}, {1, 3, 2, 0},
    {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 1, 0, 3}, {2, 1, 3, 0}, {2, 3, 0, 1}, {2, 3, 1, 0},
    {3, 0, 1, 2}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 1, 2, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

int gr_cascade_refine(const gr_cascade_settings *s, gsl_rng *rng, gr_cascade_field *f,
                      gr_error *err)
{
    if (f->level >= f->levels) {
        return GR_FAIL(err, GR_EINVAL, "cascade: the field is already at its finest level %d",
                       f->levels);
    }
    if ((int)s->variant < 0 || s->variant >= GR_CASCADE_NVARIANTS) {
        return GR_FAIL(err, GR_EINVAL, "cascade: unknown variant %d", (int)s->variant);
    }
    const size_t side = (size_t)f->side;
    const long n = 1L << f->level;
    const gr_cascade_variant v = s->variant;
    const double *p = meakin_p(s);
    double *m = f->m;
    /* In place: parents are visited from the last to the first (row-major), and a parent's children
     * (2i+g, 2j+h) never sit before it, so no parent is overwritten before it is read. */
    for (long idx = n * n - 1; idx >= 0; idx--) {
        const size_t i = (size_t)(idx % n), j = (size_t)(idx / n);
        const double parent = m[j * side + i];
        double a[4]; /* a_{2i+g, 2j+h}, c = g + 2h */
        switch (v) {
        case GR_CASCADE_UCP:
        case GR_CASCADE_UNONCP:
            for (int c = 0; c < 4; c++) {
                a[c] = gsl_rng_uniform_pos(rng); /* 0 < a < 1 */
            }
            break;
        case GR_CASCADE_SYMMETRISED: {
            /* (6.4): a_{i,j} = a_{i+1,j+1} in (0, 1/2), a_{i+1,j} = a_{i,j+1} = 1 - a_{i,j} */
            double x = 0.5 * gsl_rng_uniform_pos(rng);
            a[0] = a[3] = x;
            a[1] = a[2] = 1.0 - x;
            break;
        }
        case GR_CASCADE_UNIFORM: a[0] = a[1] = a[2] = a[3] = 1.0; break;
        default: { /* Meakin: p1..p4 dealt to the four children in a random order */
            const unsigned char *o = perms[gsl_rng_uniform_int(rng, 24)];
            for (int c = 0; c < 4; c++) {
                a[c] = p[o[c]];
            }
            break;
        }
        }
        /* (6.3): A = a_{2i,2j} + a_{2i+1,2j} + a_{2i,2j+1} + a_{2i+1,2j+1}; UnonCP replaces it by 1 */
        const double A = v == GR_CASCADE_UNONCP ? 1.0 : (a[0] + a[1]) + (a[2] + a[3]);
        for (size_t h = 0; h < 2; h++) {
            for (size_t g = 0; g < 2; g++) {
                m[(2 * j + h) * side + 2 * i + g] = parent * (a[g + 2 * h] / A); /* (6.2) */
            }
        }
    }
    f->level++;
    return GR_OK;
}

int gr_cascade_generate(const gr_cascade_settings *s, gsl_rng *rng, gr_cascade_field *f,
                        double *totals, gr_error *err)
{
    gr_cascade_field_reset(f);
    if (totals) {
        totals[0] = 1.0;
    }
    while (f->level < f->levels) {
        int rc = gr_cascade_refine(s, rng, f, err);
        if (rc) {
            return rc;
        }
        if (totals) {
            totals[f->level] = gr_cascade_field_total(f);
        }
    }
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * Moments of the multipliers w_c = a_c / A and the exact configuration average of (6.5) */

void gr_cascade_moments(const gr_cascade_settings *s, double mean[4], double second[4][4])
{
    double mu = 0.25, diag = 0.0, off = 0.0;
    switch (s->variant) {
    case GR_CASCADE_UCP:
        /* w = a_1 / (a_1 + T), T the sum of three U(0,1) (Irwin-Hall density): integrating a^2/(a+T)^2
         * exactly gives E w^2 = 1/2 + (27/2) ln 3 - 22 ln 2 = 0.0820279247...; sum_c w_c = 1 gives
         * E w w' = (1/4 - E w^2) / 3. (Uniforms normalised by their sum are not Dirichlet(1,1,1,1),
         * whose E w^2 would be 1/10.) */
        diag = 0.5 + 13.5 * log(3.0) - 22.0 * log(2.0);
        off = (0.25 - diag) / 3.0;
        break;
    case GR_CASCADE_UNONCP: /* independent U(0,1) */
        mu = 0.5;
        diag = 1.0 / 3.0;
        off = 0.25;
        break;
    case GR_CASCADE_SYMMETRISED: {
        /* w_0 = w_3 = a/2, w_1 = w_2 = (1-a)/2, a ~ U(0,1/2): E a = 1/4, E a^2 = 1/12 */
        const double small = 1.0 / 8.0, big = 3.0 / 8.0;
        const double ss = 1.0 / 48.0, bb = 7.0 / 48.0, sb = 1.0 / 24.0;
        const bool is_small[4] = {true, false, false, true};
        for (int c = 0; c < 4; c++) {
            mean[c] = is_small[c] ? small : big;
            for (int d = 0; d < 4; d++) {
                second[c][d] =
                    is_small[c] && is_small[d] ? ss : (!is_small[c] && !is_small[d] ? bb : sb);
            }
        }
        return;
    }
    case GR_CASCADE_UNIFORM: diag = off = 1.0 / 16.0; break;
    default: { /* Meakin: a random order of p/P, P = sum p */
        const double *p = meakin_p(s);
        double P = 0.0, P2 = 0.0;
        for (int c = 0; c < 4; c++) {
            P += p[c];
            P2 += p[c] * p[c];
        }
        diag = P2 / (4.0 * P * P);
        off = (P * P - P2) / (12.0 * P * P);
        break;
    }
    }
    for (int c = 0; c < 4; c++) {
        mean[c] = mu;
        for (int d = 0; d < 4; d++) {
            second[c][d] = c == d ? diag : off;
        }
    }
}

double gr_cascade_d2(const gr_cascade_settings *s)
{
    double mean[4], second[4][4], sum = 0.0, sum2 = 0.0;
    gr_cascade_moments(s, mean, second);
    for (int c = 0; c < 4; c++) {
        sum += mean[c];
        sum2 += second[c][c];
    }
    return -log2(sum2 / (sum * sum));
}

/* e^{i pi x} with x reduced modulo 2 first, so large q keep full precision */
static double complex expipi(double x)
{
    x = fmod(x, 2.0);
    return cos(M_PI * x) + (double complex)I * sin(M_PI * x);
}

typedef struct moments {
    double mean[4], second[4][4];
} moments;

/* The recursion of gr_cascade_sk_expected. `table` (NULL or 2^(levels+1) entries e^{i pi j / 2^levels})
 * turns every phase of an integer q into a lookup: e^{i pi q 2^l / 2^n} = table[q 2^l mod 2^(n+1)]. */
static double expected_with(const moments *mo, int levels, const double complex *table, double qx,
                            double qy)
{
    const double *mean = mo->mean;
    const double(*second)[4] = mo->second;
    double diag = 0.0;
    for (int c = 0; c < 4; c++) {
        diag += second[c][c];
    }
    const long period = 2L << levels;
    const long iqx = table ? (((long)qx % period) + period) % period : 0;
    const long iqy = table ? (((long)qy % period) + period) % period : 0;
    const double kx0 = ldexp(qx, -levels), ky0 = ldexp(qy, -levels);
    double S = 1.0;
    double complex M = table ? table[(iqx + iqy) % period] : expipi(kx0 + ky0);
    for (int l = 1; l <= levels; l++) {
        const double complex ex = table ? table[(iqx << l) % period] : expipi(ldexp(kx0, l));
        const double complex ey = table ? table[(iqy << l) % period] : expipi(ldexp(ky0, l));
        const double complex ph[4] = {1.0, ex, ey,
                                      ex * ey}; /* e^{2 pi i kappa . o_c}, o_c = (g, h)/2 */
        double cross = 0.0;
        double complex Mn = 0.0;
        for (int c = 0; c < 4; c++) {
            Mn += mean[c] * ph[c];
            for (int d = 0; d < 4; d++) {
                if (d != c) {
                    cross += second[c][d] * creal(ph[c] * conj(ph[d]));
                }
            }
        }
        const double M2 = creal(M) * creal(M) + cimag(M) * cimag(M);
        S = diag * S + cross * M2;
        M = Mn * M;
    }
    return S;
}

double gr_cascade_sk_expected(const gr_cascade_settings *s, double qx, double qy)
{
    moments mo;
    gr_cascade_moments(s, mo.mean, mo.second);
    return expected_with(&mo, s->levels, NULL, qx, qy);
}

/* ------------------------------------------------------------------------------------------
 * Structure factor */

struct gr_cascade_sk {
    gr_cascade_settings s;
    int side, nh, nbins, configs;
    fftw_plan plan;
    double *in;                 /* planning array, freed once planned */
    fftw_complex *out;          /* side x (side/2 + 1) */
    double *sum;                /* sum over configurations of S on the half plane */
    gr_histogram h_S, h_n, h_q; /* per configuration: sum of S, vectors, sum of |q| per bin */
    double *bin_mean, *bin_m2;  /* Welford over configurations of the circular average */
    double *bin_expected;
};

void gr_cascade_sk_free(gr_cascade_sk *sk)
{
    if (!sk) {
        return;
    }
    if (sk->plan) {
        fftw_destroy_plan(sk->plan);
    }
    fftw_free(sk->in);
    fftw_free(sk->out);
    free(sk->sum);
    gr_histogram_free(&sk->h_S);
    gr_histogram_free(&sk->h_n);
    gr_histogram_free(&sk->h_q);
    free(sk->bin_mean);
    free(sk->bin_m2);
    free(sk->bin_expected);
    free(sk);
}

/* The lattice vectors of the disc |q| < side/2 + 1/2, one of each pair (q, -q): the half plane
 * q_x > 0, or q_x = 0 and q_y > 0. Each stands for two vectors of the circular average (S(-q) = S(q)). */
static bool in_half_disc(int side, int qx, int qy, double *qabs)
{
    if (qx < 0 || (qx == 0 && qy <= 0)) {
        return false;
    }
    *qabs = sqrt((double)qx * qx + (double)qy * qy);
    return *qabs < side / 2 + 0.5;
}

int gr_cascade_sk_alloc(const gr_cascade_settings *s, gr_cascade_sk **out, gr_error *err)
{
    *out = NULL;
    int rc = gr_cascade_settings_check(s, err);
    if (rc) {
        return rc;
    }
    gr_cascade_sk *sk = calloc(1, sizeof *sk);
    if (!sk) {
        return GR_FAIL(err, GR_ENOMEM, "cascade S(k): out of memory");
    }
    sk->s = *s;
    sk->side = 1 << s->levels;
    sk->nh = sk->side / 2 + 1;
    sk->nbins = sk->side / 2;
    const size_t n = (size_t)sk->side * (size_t)sk->side, nc = (size_t)sk->side * (size_t)sk->nh;
    sk->in = fftw_alloc_real(n);
    sk->out = fftw_alloc_complex(nc);
    sk->sum = calloc(nc, sizeof(double));
    sk->bin_mean = calloc((size_t)sk->nbins, sizeof(double));
    sk->bin_m2 = calloc((size_t)sk->nbins, sizeof(double));
    sk->bin_expected = calloc((size_t)sk->nbins, sizeof(double));
    if (!sk->in || !sk->out || !sk->sum || !sk->bin_mean || !sk->bin_m2 || !sk->bin_expected) {
        gr_cascade_sk_free(sk);
        return GR_FAIL(err, GR_ENOMEM, "cascade S(k): out of memory for a %d x %d grid", sk->side,
                       sk->side);
    }
    /* Integer |q| bins [q - 1/2, q + 1/2), q = 1 .. side/2: histograms with weights */
    const double lo = 0.5, hi = sk->nbins + 0.5;
    if ((rc = gr_histogram_init(&sk->h_S, sk->nbins, lo, hi, false, err)) ||
        (rc = gr_histogram_init(&sk->h_n, sk->nbins, lo, hi, false, err)) ||
        (rc = gr_histogram_init(&sk->h_q, sk->nbins, lo, hi, false, err))) {
        gr_cascade_sk_free(sk);
        return rc;
    }
    /* FFTW_ESTIMATE: the same plan (and so bit-identical sums) on every run */
    sk->plan = fftw_plan_dft_r2c_2d(sk->side, sk->side, sk->in, sk->out, FFTW_ESTIMATE);
    fftw_free(
        sk->in); /* fields are transformed with the new-array interface; same FFTW alignment */
    sk->in = NULL;
    if (!sk->plan) {
        gr_cascade_sk_free(sk);
        return GR_FAIL(err, GR_ENOMEM, "cascade S(k): FFTW could not plan a %d x %d transform",
                       sk->side, sk->side);
    }
    /* the vectors per bin, their mean |q| and the exact expected S, once */
    moments mo;
    gr_cascade_moments(s, mo.mean, mo.second);
    const long period = 2L << s->levels;
    double complex *table = malloc(sizeof(double complex) * (size_t)period);
    if (!table) {
        gr_cascade_sk_free(sk);
        return GR_FAIL(err, GR_ENOMEM, "cascade S(k): out of memory");
    }
    for (long j = 0; j < period; j++) {
        table[j] = expipi(ldexp((double)j, -s->levels));
    }
    const int h = sk->side / 2;
    for (int qy = -h; qy <= h; qy++) {
        for (int qx = 0; qx <= h; qx++) {
            double q;
            if (in_half_disc(sk->side, qx, qy, &q)) {
                gr_histogram_add(&sk->h_n, q, 2.0);
                gr_histogram_add(&sk->h_q, q, 2.0 * q);
                gr_histogram_add(&sk->h_S, q, 2.0 * expected_with(&mo, s->levels, table, qx, qy));
            }
        }
    }
    free(table);
    for (int b = 0; b < sk->nbins; b++) {
        sk->bin_expected[b] =
            sk->h_n.count[b] > 0.0 ? sk->h_S.count[b] / sk->h_n.count[b] : (double)NAN;
    }
    *out = sk;
    return GR_OK;
}

/* fftw_complex is the C99 double complex here (<complex.h> comes first) */
static double cabs2(fftw_complex z) { return creal(z) * creal(z) + cimag(z) * cimag(z); }

/* index of q on the stored half plane (FFTW's r2c layout), using S(-q) = S(q) and the period side */
static size_t half_index(const gr_cascade_sk *sk, int qx, int qy)
{
    const int n = sk->side;
    int ix = ((qx % n) + n) % n, jy = ((qy % n) + n) % n;
    if (ix > n / 2) {
        ix = n - ix;
        jy = (n - jy) % n;
    }
    return (size_t)jy * (size_t)sk->nh + (size_t)ix;
}

int gr_cascade_sk_add(gr_cascade_sk *sk, const gr_cascade_field *f, gr_error *err)
{
    if (f->levels != sk->s.levels || f->level != f->levels) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade S(k): need a finished field of %d levels (got level %d of %d)",
                       sk->s.levels, f->level, f->levels);
    }
    /* (6.5): sum_{i,j} m_{i,j} e^{-2 pi i (q_x i + q_y j)/2^n}; the centre offset (i + 1/2) of (6.1) is a
     * phase, and the sign of the exponent does not matter for a real field: |.|^2 is S(k). */
    fftw_execute_dft_r2c(sk->plan, f->m, sk->out);
    const size_t nc = (size_t)sk->side * (size_t)sk->nh;
    for (size_t i = 0; i < nc; i++) {
        sk->sum[i] += cabs2(sk->out[i]);
    }
    memset(sk->h_S.count, 0, sizeof(double) * (size_t)sk->nbins);
    sk->h_S.below = sk->h_S.above = sk->h_S.total = 0.0;
    const int h = sk->side / 2;
    for (int qy = -h; qy <= h; qy++) {
        for (int qx = 0; qx <= h; qx++) {
            double q;
            if (in_half_disc(sk->side, qx, qy, &q)) {
                gr_histogram_add(&sk->h_S, q, 2.0 * cabs2(sk->out[half_index(sk, qx, qy)]));
            }
        }
    }
    sk->configs++;
    for (int b = 0; b < sk->nbins; b++) {
        const double x =
            sk->h_S.count[b] / sk->h_n.count[b]; /* circular average of this configuration */
        const double d = x - sk->bin_mean[b];
        sk->bin_mean[b] += d / sk->configs;
        sk->bin_m2[b] += d * (x - sk->bin_mean[b]);
    }
    return GR_OK;
}

int gr_cascade_sk_configurations(const gr_cascade_sk *sk) { return sk->configs; }

double gr_cascade_sk_last(const gr_cascade_sk *sk, int qx, int qy)
{
    return sk->configs > 0 ? cabs2(sk->out[half_index(sk, qx, qy)]) : (double)NAN;
}

double gr_cascade_sk_mean(const gr_cascade_sk *sk, int qx, int qy)
{
    return sk->configs > 0 ? sk->sum[half_index(sk, qx, qy)] / sk->configs : (double)NAN;
}

int gr_cascade_sk_nbins(const gr_cascade_sk *sk) { return sk->nbins; }

void gr_cascade_sk_bins(const gr_cascade_sk *sk, gr_cascade_sk_bin *bins)
{
    for (int b = 0; b < sk->nbins; b++) {
        gr_cascade_sk_bin *o = &bins[b];
        o->q = b + 1;
        o->vectors = (int)sk->h_n.count[b];
        o->q_mean = sk->h_q.count[b] / sk->h_n.count[b];
        o->k = 2.0 * M_PI * o->q_mean / sk->s.L; /* (4.3) */
        o->S = sk->configs > 0 ? sk->bin_mean[b] : (double)NAN;
        o->S_err =
            sk->configs > 1 ? sqrt(sk->bin_m2[b] / (sk->configs - 1) / sk->configs) : (double)NAN;
        o->S_expected = sk->bin_expected[b];
    }
}

double gr_cascade_sk_direct(const gr_cascade_field *f, int qx, int qy)
{
    /* k . r_{i,j} = 2 pi (q_x (i + 1/2) + q_y (j + 1/2)) / 2^n = pi (q_x (2i+1) + q_y (2j+1)) / 2^n, the
     * integer numerator reduced modulo 2^(n+1) so the angle is exact */
    const long n = f->side, period = 2 * n;
    double re = 0.0, im = 0.0;
    for (long j = 0; j < n; j++) {
        for (long i = 0; i < n; i++) {
            long t = ((long)qx * (2 * i + 1) + (long)qy * (2 * j + 1)) % period;
            double ang = M_PI * (double)t / (double)n, m = f->m[j * n + i];
            re += m * cos(ang);
            im += m * sin(ang);
        }
    }
    return re * re + im * im;
}

static int fit_df(const gr_cascade_sk_bin *bins, int nbins, double q_min, double q_max,
                  bool expected, bool unweighted, gr_cascade_fit *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    double *x = malloc(sizeof(double) * (size_t)(nbins > 0 ? nbins : 1));
    double *y = malloc(sizeof(double) * (size_t)(nbins > 0 ? nbins : 1));
    double *sg = malloc(sizeof(double) * (size_t)(nbins > 0 ? nbins : 1));
    if (!x || !y || !sg) {
        free(x);
        free(y);
        free(sg);
        return GR_FAIL(err, GR_ENOMEM, "cascade fit: out of memory");
    }
    int n = 0;
    bool weighted = !expected && !unweighted;
    out->q_min = (double)INFINITY;
    out->q_max = -(double)INFINITY;
    for (int b = 0; b < nbins; b++) {
        const gr_cascade_sk_bin *o = &bins[b];
        const double S = expected ? o->S_expected : o->S;
        if (o->q < q_min || o->q > q_max || !(S > 0.0) || o->vectors == 0) {
            continue;
        }
        x[n] = o->k;
        y[n] = S;
        sg[n] = o->S_err;
        weighted = weighted && isfinite(o->S_err) && o->S_err > 0.0;
        out->q_min = fmin(out->q_min, o->q);
        out->q_max = fmax(out->q_max, o->q);
        if (n == 0) {
            out->k_min = o->k;
        }
        out->k_max = o->k;
        n++;
    }
    gr_fit fit;
    int rc = n >= GR_FIT_MIN_POINTS
                 ? gr_fit_power_law(x, y, weighted ? sg : NULL, n, &fit, err)
                 : GR_FAIL(err, GR_EINVAL,
                           "cascade fit: need at least 3 bins with S > 0 in q = %g..%g, got %d",
                           q_min, q_max, n);
    free(x);
    free(y);
    free(sg);
    if (rc) {
        return rc;
    }
    out->D_f = -fit.p[1]; /* (4.4): S = A k^-D_f */
    out->D_f_err = fit.err[1];
    out->A = fit.p[0];
    out->A_err = fit.err[0];
    out->chi2_red = fit.chi2_red;
    out->points = n;
    return GR_OK;
}

int gr_cascade_fit_df(const gr_cascade_sk_bin *bins, int nbins, double q_min, double q_max,
                      bool expected, gr_cascade_fit *out, gr_error *err)
{
    return fit_df(bins, nbins, q_min, q_max, expected, false, out, err);
}

int gr_cascade_fit_df_unweighted(const gr_cascade_sk_bin *bins, int nbins, double q_min,
                                 double q_max, gr_cascade_fit *out, gr_error *err)
{
    return fit_df(bins, nbins, q_min, q_max, false, true, out, err);
}

/* ------------------------------------------------------------------------------------------
 * Placement (Fig. 6.3) */

void gr_cascade_placement_default(gr_cascade_placement *p)
{
    p->n = 2500;
    p->radius = 1.5e-3;
    p->max_attempts = 0;
}

/* first index with cdf[index] > u (cdf non-decreasing, u < cdf[n-1]) */
static size_t cdf_search(const double *cdf, size_t n, double u)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cdf[mid] > u) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

int gr_cascade_placement_check(const gr_cascade_placement *p, double L, gr_error *err)
{
    const double r = p->radius;
    if (p->n < 1) {
        return GR_FAIL(err, GR_EINVAL, "cascade placement: need at least 1 disc, got %d", p->n);
    }
    if (!(r > 0.0) || !isfinite(r)) {
        return GR_FAIL(err, GR_EINVAL, "cascade placement: radius must be > 0 m, got %g", r);
    }
    if (!(L >= 4.0 * r)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "cascade placement: the box (L = %g m) must be at least two diameters (%g m)", L,
            4.0 * r);
    }
    const double phi = p->n * M_PI * r * r / (L * L); /* (2.24) */
    if (phi > GR_CASCADE_RSA_JAMMING) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade placement: %d discs of radius %g m in a %g m box have packing "
                       "fraction %.3f, above "
                       "the %.3f that random sequential placement can reach; place fewer or "
                       "smaller discs or enlarge the box",
                       p->n, r, L, phi, GR_CASCADE_RSA_JAMMING);
    }
    return GR_OK;
}

int gr_cascade_place(const gr_cascade_field *f, const gr_cascade_placement *p, gsl_rng *rng,
                     double *x, double *y, gr_cascade_placement_result *res, gr_error *err)
{
    memset(res, 0, sizeof *res);
    const double L = f->L, r = p->radius, d = 2.0 * r;
    int rc = gr_cascade_placement_check(p, L, err);
    if (rc) {
        return rc;
    }
    res->phi = p->n * M_PI * r * r / (L * L); /* (2.24) */
    if (f->level != f->levels) {
        return GR_FAIL(err, GR_EINVAL,
                       "cascade placement: the field is unfinished (level %d of %d)", f->level,
                       f->levels);
    }
    const size_t ncell = (size_t)f->side * (size_t)f->side;
    const double lc = L / f->side; /* l_n = L / 2^n */
    const int64_t budget = p->max_attempts > 0 ? p->max_attempts : 1000000 + 10000 * (int64_t)p->n;
    /* neighbour grid of cells at least one diameter wide (brute force below 3 per side) */
    int ng = (int)floor(L / d);
    ng = ng > 1024 ? 1024 : ng;
    const bool grid = ng >= 3;
    if (!grid) {
        ng = 1;
    }
    double *cdf = malloc(sizeof(double) * ncell);
    int *head = malloc(sizeof(int) * (size_t)ng * (size_t)ng),
        *next = malloc(sizeof(int) * (size_t)p->n);
    if (!cdf || !head || !next) {
        free(cdf);
        free(head);
        free(next);
        return GR_FAIL(err, GR_ENOMEM, "cascade placement: out of memory");
    }
    double total = 0.0;
    for (size_t c = 0; c < ncell; c++) {
        total += f->m[c] > 0.0 ? f->m[c] : 0.0;
        cdf[c] = total;
    }
    if (!(total > 0.0) || !isfinite(total)) {
        rc = GR_FAIL(
            err, GR_EINVAL,
            "cascade placement: the field's total probability is %g: nowhere to place discs",
            total);
    }
    for (int c = 0; c < ng * ng; c++) {
        head[c] = -1;
    }
    const double gw = L / ng;
    int placed = 0;
    while (!rc && placed < p->n) {
        if (res->attempts >= budget) {
            rc = GR_FAIL(
                err, GR_EINVAL,
                "cascade placement: placed only %d of %d discs (radius %g m) in %lld attempts: the "
                "field's "
                "likely squares are full; place fewer or smaller discs, or use fewer levels",
                placed, p->n, r, (long long)res->attempts);
            break;
        }
        res->attempts++;
        /* a square with probability m_{i,j} / sum m, then a uniform point inside it */
        const size_t c = cdf_search(cdf, ncell, gsl_rng_uniform(rng) * total);
        const double px = ((double)(c % (size_t)f->side) + gsl_rng_uniform(rng)) * lc;
        const double py = ((double)(c / (size_t)f->side) + gsl_rng_uniform(rng)) * lc;
        const int gx = grid ? (int)(px / gw) % ng : 0, gy = grid ? (int)(py / gw) % ng : 0;
        bool overlap = false;
        const int span = grid ? 1 : 0;
        for (int oy = -span; oy <= span && !overlap; oy++) {
            for (int ox = -span; ox <= span && !overlap; ox++) {
                const int cell = ((gy + oy + ng) % ng) * ng + (gx + ox + ng) % ng;
                for (int k = head[cell]; k >= 0; k = next[k]) {
                    double dx = px - x[k], dy = py - y[k];
                    dx -= L * nearbyint(dx / L);
                    dy -= L * nearbyint(dy / L);
                    if (dx * dx + dy * dy < d * d) {
                        overlap = true;
                        break;
                    }
                }
            }
        }
        if (overlap) {
            res->rejected++;
            continue;
        }
        x[placed] = px;
        y[placed] = py;
        const int cell = gy * ng + gx;
        next[placed] = head[cell];
        head[cell] = placed;
        placed++;
    }
    free(cdf);
    free(head);
    free(next);
    return rc;
}
