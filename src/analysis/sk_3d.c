/* S(k) of a 3D frame (src/analysis/sk.h): every lattice vector k = 2 pi n / L of the half space
 * with |n| <= n_cut, S(k) = |rho(k)|^2 / N, by Gaussian gridding (Greengard & Lee, SIAM Review 46,
 * 443 (2004), as the 2D engine in obs_sk.c: spread each particle onto an R-times oversampled M_r^3
 * periodic grid with a separable Gaussian over 2 msp points per axis, one r2c FFTW transform,
 * deconvolve by (pi / tau)^(3/2) e^{tau |n|^2}) or by the direct sum; rho(k) itself for a
 * mixture's species (gr_sk3_compute_rho). */
#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/sk.h"

struct gr_sk3_plan {
    gr_sk_lattice lat; /* the lat.nv vectors, grid lat.Mr, Gaussian width lat.tau */
    double L, h;
    int n_max, msp, Mc;
    size_t *idx;    /* spectrum index of each vector */
    double *deconv; /* (pi / tau)^(3/2) e^{tau |n|^2} / Mr^3 */
    double e3[GR_SK_MSP_MAX + 1];
    double *grid;
    fftw_complex *spec;
    fftw_plan plan;
};

void gr_sk3_plan_free(gr_sk3_plan *pl)
{
    if (!pl) {
        return;
    }
    if (pl->plan) {
        fftw_destroy_plan(pl->plan);
    }
    fftw_free(pl->grid);
    fftw_free(pl->spec);
    free(pl->lat.nx);
    free(pl->lat.ny);
    free(pl->lat.nz);
    free(pl->idx);
    free(pl->deconv);
    free(pl);
}

/* n in the half space: n_z > 0, or n_z = 0 and n_y > 0, or n_z = n_y = 0 and n_x > 0 */
static int half_space(int a, int b, int c)
{
    return c > 0 || (c == 0 && (b > 0 || (b == 0 && a > 0)));
}

int gr_sk3_plan_create(double L, double n_cut, int msp, gr_sk3_plan **out, gr_error *err)
{
    *out = NULL;
    if (!(L > 0.0) || !isfinite(L)) {
        return GR_FAIL(err, GR_EINVAL, "sk: box side L = %g must be positive", L);
    }
    if (!(n_cut >= 1.0) || !isfinite(n_cut)) {
        return GR_FAIL(err, GR_EINVAL, "sk: no lattice vector 2 pi n / L with 0 < |n| <= %g",
                       n_cut);
    }
    if (n_cut > GR_SK3_NMAX_LIMIT) {
        return GR_FAIL(err, GR_EINVAL,
                       "sk: in 3D |n| up to %.0f exceeds the limit %d (grid memory, M_r^3); lower "
                       "[analysis] sk_kd_max",
                       n_cut, GR_SK3_NMAX_LIMIT);
    }
    if (msp < 1 || msp > GR_SK_MSP_MAX) {
        return GR_FAIL(err, GR_EINVAL, "sk: gridding half-width msp = %d outside 1..%d", msp,
                       GR_SK_MSP_MAX);
    }
    gr_sk3_plan *pl = calloc(1, sizeof *pl);
    if (!pl) {
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory");
    }
    const long nsq = (long)floor(n_cut * n_cut * (1.0 + 1e-12));
    const int n = (int)floor(sqrt((double)nsq) + 1e-9);
    pl->L = L;
    pl->n_max = n;
    pl->msp = msp;
    long count = 0;
    for (int c = -n; c <= n; c++) {
        for (int b = -n; b <= n; b++) {
            for (int a = -n; a <= n; a++) {
                count += half_space(a, b, c) && (long)a * a + (long)b * b + (long)c * c <= nsq;
            }
        }
    }
    pl->Mc = gr_sk_gridding(n, msp, &pl->lat, &pl->h, pl->e3);
    const size_t Mr = (size_t)pl->lat.Mr;
    pl->lat.nv = (int)count;
    pl->lat.nx = malloc(sizeof(int) * (size_t)count);
    pl->lat.ny = malloc(sizeof(int) * (size_t)count);
    pl->lat.nz = malloc(sizeof(int) * (size_t)count);
    pl->idx = malloc(sizeof(size_t) * (size_t)count);
    pl->deconv = malloc(sizeof(double) * (size_t)count);
    pl->grid = fftw_malloc(sizeof(double) * Mr * Mr * Mr);
    pl->spec = fftw_malloc(sizeof(fftw_complex) * Mr * Mr * (size_t)pl->Mc);
    if (!pl->lat.nx || !pl->lat.ny || !pl->lat.nz || !pl->idx || !pl->deconv || !pl->grid ||
        !pl->spec) {
        gr_sk3_plan_free(pl);
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory (%ld vectors, %d^3 grid)", count,
                       (int)Mr);
    }
    /* grid[(ix Mr + iy) Mr + iz]: z is the halved axis of the r2c output, spec[(kx Mr + ky) Mc +
     * kz], kz = 0..Mr/2; FFTW_ESTIMATE (the same arithmetic on every run), planned once here */
    pl->plan =
        fftw_plan_dft_r2c_3d(pl->lat.Mr, pl->lat.Mr, pl->lat.Mr, pl->grid, pl->spec, FFTW_ESTIMATE);
    if (!pl->plan) {
        gr_sk3_plan_free(pl);
        return GR_FAIL(err, GR_ENOMEM, "sk: FFTW could not plan a %d^3 transform", (int)Mr);
    }
    const double norm = pow(M_PI / pl->lat.tau, 1.5) / ((double)Mr * Mr * Mr);
    int v = 0;
    for (int c = -n; c <= n; c++) {
        for (int b = -n; b <= n; b++) {
            for (int a = -n; a <= n; a++) {
                const long q = (long)a * a + (long)b * b + (long)c * c;
                if (!half_space(a, b, c) || q > nsq) {
                    continue;
                }
                pl->lat.nx[v] = a;
                pl->lat.ny[v] = b;
                pl->lat.nz[v] = c;
                pl->idx[v] = ((size_t)(a >= 0 ? a : pl->lat.Mr + a) * Mr +
                              (size_t)(b >= 0 ? b : pl->lat.Mr + b)) *
                                 (size_t)pl->Mc +
                             (size_t)c;
                pl->deconv[v] = norm * exp(pl->lat.tau * (double)q);
                v++;
            }
        }
    }
    *out = pl;
    return GR_OK;
}

const gr_sk_lattice *gr_sk3_plan_lattice(const gr_sk3_plan *pl) { return &pl->lat; }

static int wrap_index(int i, int Mr) { return i < 0 ? i + Mr : i >= Mr ? i - Mr : i; }

/* Spread n particles onto the grid and transform it: pl->spec then holds rho(k) / deconv. */
static void grid_transform(gr_sk3_plan *pl, int n, const double *x, const double *y,
                           const double *z)
{
    const int Mr = pl->lat.Mr, w2 = 2 * pl->msp;
    const size_t M = (size_t)Mr;
    memset(pl->grid, 0, sizeof(double) * M * M * M);
    double wx[2 * GR_SK_MSP_MAX], wy[2 * GR_SK_MSP_MAX], wz[2 * GR_SK_MSP_MAX];
    int iy[2 * GR_SK_MSP_MAX], iz[2 * GR_SK_MSP_MAX];
    for (int j = 0; j < n; j++) {
        const int x0 =
            gr_sk_gauss_weights(pl->L, Mr, pl->h, pl->lat.tau, pl->msp, pl->e3, x[j], wx);
        const int y0 =
            gr_sk_gauss_weights(pl->L, Mr, pl->h, pl->lat.tau, pl->msp, pl->e3, y[j], wy);
        const int z0 =
            gr_sk_gauss_weights(pl->L, Mr, pl->h, pl->lat.tau, pl->msp, pl->e3, z[j], wz);
        for (int k = 0; k < w2; k++) {
            iy[k] = wrap_index(y0 + k, Mr);
            iz[k] = wrap_index(z0 + k, Mr);
        }
        for (int a = 0; a < w2; a++) {
            double *plane = pl->grid + (size_t)wrap_index(x0 + a, Mr) * M * M;
            for (int b = 0; b < w2; b++) {
                double *row = plane + (size_t)iy[b] * M;
                const double wab = wx[a] * wy[b];
                for (int c = 0; c < w2; c++) {
                    row[iz[c]] += wab * wz[c];
                }
            }
        }
    }
    fftw_execute(pl->plan);
}

static void compute_gridding(gr_sk3_plan *pl, int n, const double *x, const double *y,
                             const double *z, double *S)
{
    grid_transform(pl, n, x, y, z);
    const double inv_n = 1.0 / n;
    for (int v = 0; v < pl->lat.nv; v++) {
        const double *c = pl->spec[pl->idx[v]];
        const double f = pl->deconv[v];
        S[v] = (c[0] * c[0] + c[1] * c[1]) * f * f * inv_n;
    }
}

/* The direct sum of one vector: rho(k) = sum_j exp(-i k.r_j), O(N). */
static void direct_rho(const gr_sk3_plan *pl, int v, int n, const double *x, const double *y,
                       const double *z, double *re, double *im)
{
    const double k0 = 2.0 * M_PI / pl->L;
    *re = *im = 0.0;
    for (int j = 0; j < n; j++) {
        const double ph = k0 * (pl->lat.nx[v] * x[j] + pl->lat.ny[v] * y[j] + pl->lat.nz[v] * z[j]);
        *re += cos(ph);
        *im -= sin(ph);
    }
}

/* The direct sum, vector by vector: O(N n_vectors), the oracle of the tests. */
static void compute_direct(const gr_sk3_plan *pl, int n, const double *x, const double *y,
                           const double *z, double *S)
{
    for (int v = 0; v < pl->lat.nv; v++) {
        double re, im;
        direct_rho(pl, v, n, x, y, z, &re, &im);
        S[v] = (re * re + im * im) / n;
    }
}

int gr_sk3_compute(gr_sk3_plan *pl, int method, int n, const double *x, const double *y,
                   const double *z, double *S, gr_error *err)
{
    if (n < 1 || !x || !y || !z) {
        return GR_FAIL(err, GR_EINVAL, "sk: a 3D frame needs at least one particle with x, y, z");
    }
    if (method == GR_SK_DIRECT) {
        compute_direct(pl, n, x, y, z, S);
        return GR_OK;
    }
    if (method != GR_SK_GRIDDING) {
        return GR_FAIL(err, GR_EINVAL, "sk: unknown method %d", method);
    }
    compute_gridding(pl, n, x, y, z, S);
    return GR_OK;
}

int gr_sk3_compute_rho(gr_sk3_plan *pl, int method, int n, const double *x, const double *y,
                       const double *z, double *re, double *im, gr_error *err)
{
    if (n < 0 || (n > 0 && (!x || !y || !z))) {
        return GR_FAIL(err, GR_EINVAL, "sk: a 3D frame needs particles with x, y, z");
    }
    if (method == GR_SK_DIRECT) {
        for (int v = 0; v < pl->lat.nv; v++) {
            direct_rho(pl, v, n, x, y, z, &re[v], &im[v]);
        }
        return GR_OK;
    }
    if (method != GR_SK_GRIDDING) {
        return GR_FAIL(err, GR_EINVAL, "sk: unknown method %d", method);
    }
    grid_transform(pl, n, x, y, z);
    for (int v = 0; v < pl->lat.nv; v++) {
        const double *c = pl->spec[pl->idx[v]];
        re[v] = c[0] * pl->deconv[v];
        im[v] = c[1] * pl->deconv[v];
    }
    return GR_OK;
}
