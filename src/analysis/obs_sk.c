/* sk: the static structure factor of a 2D or 3D system (thesis sec. 4.1),
 * docs/analysis-structure-factor.md.
 *
 *   S(k) = |rho(k)|^2 / N,   rho(k) = sum_j exp(-i k.r_j)                       (4.2)
 *   k = 2 pi (n_x, n_y) / L, n integer, n != 0                                    (4.3)
 *
 * on every lattice vector with |k| d <= sk_kd_max, per frame, averaged over frames (streaming).
 * Positions are real, so rho(-k) = conj(rho(k)) and S(-k) = S(k): only the half plane n_x > 0, or
 * n_x = 0 and n_y > 0, is computed. Each frame's S(k) is averaged over circular bins of |n| (width
 * 1, centred on integers) and over the exact shells |n|^2 = const at small k; the time averages
 * carry block-averaging errors. finish() fits S(k) = A k^-D_f (4.4) over the shells with k < k',
 * with k' = k_D (4.5) when L > L_Eff (4.9) and 2 k_D otherwise (the thesis's choice, Tables
 * 4.1-4.3), and reports k_D, l_0 (4.7), L_min (4.6/4.8) and L_Eff (4.9).
 *
 * Method: type-1 non-uniform FFT with Gaussian gridding (Greengard & Lee, SIAM Review 46, 443
 * (2004); physics notes sec. 6.1): spread every particle onto an R-times oversampled periodic grid
 * with a separable Gaussian over 2 msp points per dimension, one real-to-complex FFTW transform,
 * deconvolve by (pi/tau) e^{tau |n|^2}. Cost O(N msp^2 + M_r^2 log M_r) per frame instead of the
 * O(N n_max^2) of the direct sum, which is kept (separable phase recurrences) as the oracle of the
 * tests and the bench, and can be selected with GRANULE_SK_METHOD=direct.
 *
 * 3D (spheres in a cube): k = 2 pi (n_x, n_y, n_z) / L on the half space, the same |n| bins
 * (spherical shells of width 1) and exact shells |n|^2 = const, the engine of src/analysis/sk_3d.c
 * (gridding on an M_r^3 grid). The dissipative scale (4.5) is carried over with the 3D mean free
 * length l_0 = 1 / (n pi d^2) = L^3 / (pi d^2 N) in place of 2D's l_0 = L^2 / (2 d N) (4.7, 1 / (n
 * 2 d)): both are 1 / (n sigma), sigma the collision cross-section (length 2 d in 2D, area pi d^2
 * in 3D); the thesis derives k_D in 2D only, so in 3D the fit window k < k' is a convention.
 *
 * A mixture of species lists (docs/mixtures.md), 2D and 3D: also the partial structure factors of
 * Ashcroft and Langreth (Phys. Rev. 156, 685 (1967)) of every species pair a <= b,
 *
 *   S_ab(k) = <rho_a(k) rho_b(-k)> / sqrt(N_a N_b),   rho_a(k) = sum_{j in a} exp(-i k.r_j),
 *
 * each rho_a by the same gridding and transform (gr_sk_compute_rho: one more FFT per species), on
 * the total's |n| bins (sk_species.csv). Their Bhatia-Thornton number-number combination
 * sum_ab sqrt(x_a x_b) S_ab, x_a = N_a / N, is S(k) (Phys. Rev. B 2, 3004 (1970)). The D_f fit
 * and the exact shells stay the total's; one species computes none of it. */
#include <cjson/cJSON.h>
#include <fftw3.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "analysis/obs_util.h"
#include "io/plot.h"
#include "granule/analysis.h"
#include "granule/sim.h"
#include "analysis/sk.h"

struct gr_sk_plan {
    double L, n_cut;
    int n_max;         /* largest |n_x| and |n_y| */
    long nsq;          /* vectors with n_x^2 + n_y^2 <= nsq */
    gr_sk_lattice lat; /* the lat.nv vectors in the half plane (lat.nz NULL); grid lat.Mr, tau */
    /* gridding */
    int msp, Mc; /* real grid Mr x Mr, r2c spectrum Mr x Mc (Mc = Mr/2 + 1) */
    double h;
    double e3[GR_SK_MSP_MAX + 1]; /* exp(-(l h)^2 / (4 tau)) */
    double *grid;
    fftw_complex *spec;
    fftw_plan rows, cols; /* r2c along x of every row, then along y of the columns n_x <= n_max */
    int *row_of, *bucket; /* particles sorted by grid row (locality), capacity cap */
    double *xs, *ys;
    int cap;
    size_t *idx;    /* spectrum index of each vector */
    double *deconv; /* (pi/tau) e^{tau |n|^2} / Mr^2 of each vector */
    /* direct sum (allocated at its first use) */
    double *rre, *rim;             /* rho on (n_max + 1) x (2 n_max + 1) */
    double *pxr, *pxi, *pyr, *pyi; /* phases of one block of particles */
};

#define DIRECT_BLOCK 8 /* particles per block of the direct sum */
#define RESEED 32      /* recompute the phase with sincos every RESEED recurrence steps */

/* Smallest even m >= target whose only prime factors are 2, 3, 5, 7 (fast FFTW sizes). */
int gr_sk_fft_size(int target)
{
    for (int m = target + (target & 1);; m += 2) {
        int r = m;
        for (int f = 2; f <= 7; f++) {
            while (r % f == 0) {
                r /= f;
            }
        }
        if (r == 1) {
            return m;
        }
    }
}

void gr_sk_plan_free(gr_sk_plan *pl)
{
    if (!pl) {
        return;
    }
    if (pl->rows) {
        fftw_destroy_plan(pl->rows);
    }
    if (pl->cols) {
        fftw_destroy_plan(pl->cols);
    }
    free(pl->row_of);
    free(pl->bucket);
    free(pl->xs);
    free(pl->ys);
    fftw_free(pl->grid);
    fftw_free(pl->spec);
    free(pl->lat.nx);
    free(pl->lat.ny);
    free(pl->idx);
    free(pl->deconv);
    free(pl->rre);
    free(pl->rim);
    free(pl->pxr);
    free(pl->pxi);
    free(pl->pyr);
    free(pl->pyi);
    free(pl);
}

/* Largest b >= 0 with b^2 <= r (r >= 0). */
static int isqrt_floor(long r)
{
    long b = (long)floor(sqrt((double)r));
    while (b * b > r) {
        b--;
    }
    while ((b + 1) * (b + 1) <= r) {
        b++;
    }
    return (int)b;
}

int gr_sk_plan_create(double L, double n_cut, int msp, gr_sk_plan **out, gr_error *err)
{
    *out = NULL;
    if (!(L > 0.0) || !isfinite(L)) {
        return GR_FAIL(err, GR_EINVAL, "sk: box side L = %g must be positive", L);
    }
    if (!(n_cut >= 1.0) || !isfinite(n_cut)) {
        return GR_FAIL(err, GR_EINVAL, "sk: no lattice vector 2 pi n / L with 0 < |n| <= %g",
                       n_cut);
    }
    if (n_cut > GR_SK_NMAX_LIMIT) {
        return GR_FAIL(err, GR_EINVAL,
                       "sk: |n| up to %.0f exceeds the limit %d (grid memory); lower sk_kd_max",
                       n_cut, GR_SK_NMAX_LIMIT);
    }
    if (msp < 1 || msp > GR_SK_MSP_MAX) {
        return GR_FAIL(err, GR_EINVAL, "sk: gridding half-width msp = %d outside 1..%d", msp,
                       GR_SK_MSP_MAX);
    }
    gr_sk_plan *pl = calloc(1, sizeof *pl);
    if (!pl) {
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory");
    }
    pl->L = L;
    pl->n_cut = n_cut;
    pl->nsq = (long)floor(n_cut * n_cut * (1.0 + 1e-12));
    pl->n_max = isqrt_floor(pl->nsq);
    const int n = pl->n_max;
    /* the half plane n_x > 0, or n_x = 0 and n_y > 0, row by row: n_y = -n_max..n_max, then
     * n_x = 0..sqrt(nsq - n_y^2) (the order of the FFT's output in memory) */
    long count = 0;
    for (int b = -n; b <= n; b++) {
        int am = isqrt_floor(pl->nsq - (long)b * b);
        count += b > 0 ? am + 1 : am;
    }
    pl->lat.nv = (int)count;
    pl->lat.nx = malloc(sizeof(int) * (size_t)count);
    pl->lat.ny = malloc(sizeof(int) * (size_t)count);
    pl->idx = malloc(sizeof(size_t) * (size_t)count);
    pl->deconv = malloc(sizeof(double) * (size_t)count);
    pl->msp = msp;
    pl->Mc = gr_sk_gridding(n, msp, &pl->lat, &pl->h, pl->e3);
    const size_t cells = (size_t)pl->lat.Mr * (size_t)pl->lat.Mr;
    pl->grid = fftw_malloc(sizeof(double) * cells);
    pl->spec = fftw_malloc(sizeof(fftw_complex) * (size_t)pl->lat.Mr * (size_t)pl->Mc);
    pl->bucket = malloc(sizeof(int) * ((size_t)pl->lat.Mr + 1));
    if (!pl->lat.nx || !pl->lat.ny || !pl->idx || !pl->deconv || !pl->grid || !pl->spec ||
        !pl->bucket) {
        gr_sk_plan_free(pl);
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory (%d vectors, %d^2 grid)", (int)count,
                       pl->lat.Mr);
    }
    /* The 2D transform, pruned: real-to-complex along x for every row, then complex along y only
     * for the n_max + 1 columns n_x = 0..n_max that are kept (0.65 of a full 2D r2c transform).
     * FFTW_ESTIMATE: the plan depends only on the size, so every run does the same arithmetic
     * (FFTW_MEASURE would be ~20% faster but picks plans by timing). The planner is not
     * thread-safe: plans are made here, once, never per frame. */
    int len = pl->lat.Mr;
    pl->rows = fftw_plan_many_dft_r2c(1, &len, pl->lat.Mr, pl->grid, NULL, 1, pl->lat.Mr, pl->spec,
                                      NULL, 1, pl->Mc, FFTW_ESTIMATE);
    pl->cols = fftw_plan_many_dft(1, &len, n + 1, pl->spec, NULL, pl->Mc, 1, pl->spec, NULL, pl->Mc,
                                  1, FFTW_FORWARD, FFTW_ESTIMATE);
    if (!pl->rows || !pl->cols) {
        gr_sk_plan_free(pl);
        return GR_FAIL(err, GR_ENOMEM, "sk: FFTW could not plan a %d x %d transform", pl->lat.Mr,
                       pl->lat.Mr);
    }
    const double norm = (M_PI / pl->lat.tau) / ((double)pl->lat.Mr * pl->lat.Mr);
    int v = 0;
    for (int b = -n; b <= n; b++) {
        int am = isqrt_floor(pl->nsq - (long)b * b);
        for (int a = b > 0 ? 0 : 1; a <= am; a++, v++) {
            pl->lat.nx[v] = a;
            pl->lat.ny[v] = b;
            /* spectrum row = k_y (negative k_y wrap to Mr + k_y), column = k_x >= 0 */
            pl->idx[v] = (size_t)(b >= 0 ? b : pl->lat.Mr + b) * (size_t)pl->Mc + (size_t)a;
            pl->deconv[v] = norm * exp(pl->lat.tau * (double)((long)a * a + (long)b * b));
        }
    }
    *out = pl;
    return GR_OK;
}

const gr_sk_lattice *gr_sk_plan_lattice(const gr_sk_plan *pl) { return &pl->lat; }

int gr_sk_vectors(const gr_sk_lattice *lat, const int **nx, const int **ny, const int **nz)
{
    if (nx) {
        *nx = lat->nx;
    }
    if (ny) {
        *ny = lat->ny;
    }
    if (nz) {
        *nz = lat->nz;
    }
    return lat->nv;
}

void gr_sk_grid(const gr_sk_lattice *lat, int *grid, double *tau)
{
    if (grid) {
        *grid = lat->Mr;
    }
    if (tau) {
        *tau = lat->tau;
    }
}

/* Greengard & Lee: M = 2 n_max + 1 modes per dimension, oversampling R = M_r / M >= 2,
 * tau = pi msp / (M^2 R (R - 1/2)) (their sec. 3, M_sp = msp; physics notes sec. 6.1). */
int gr_sk_gridding(int n_max, int msp, gr_sk_lattice *lat, double *h, double *e3)
{
    const int M = 2 * n_max + 1;
    lat->Mr = gr_sk_fft_size(2 * M > 2 * msp ? 2 * M : 2 * msp);
    const double R = (double)lat->Mr / M;
    lat->tau = M_PI * msp / ((double)M * M * R * (R - 0.5));
    *h = 2.0 * M_PI / lat->Mr;
    for (int l = 0; l <= msp; l++) {
        e3[l] = exp(-(l * *h) * (l * *h) / (4.0 * lat->tau));
    }
    return lat->Mr / 2 + 1;
}

/* Gaussian weights of one coordinate: grid index of the first of 2 msp points (unwrapped, may be
 * negative or >= Mr) and w[j] = exp(-(xi - l h)^2 / (4 tau)), l = j - msp + 1, where the particle
 * sits at (m0 + xi/h) h. Fast Gaussian gridding (Greengard & Lee sec. 3): exp(-xi^2/4tau) *
 * exp(xi h/2tau)^l * exp(-(l h)^2/4tau): two exponentials per coordinate, the last factor
 * tabulated in the plan. */
int gr_sk_gauss_weights(double L, int Mr, double h, double tau, int msp, const double *e3,
                        double coord, double *w)
{
    double u = coord / L;
    u -= floor(u);
    double g = u * Mr;
    int m0 = (int)g;
    if (m0 >= Mr) { /* u rounded up to 1 */
        m0 = Mr - 1;
    }
    const double xi = (g - m0) * h, t4 = 4.0 * tau;
    const double e1 = exp(-xi * xi / t4), e2 = exp(xi * h / (2.0 * tau)), e2i = 1.0 / e2;
    double p = e1; /* l = 0 .. msp */
    for (int l = 0; l <= msp; l++) {
        w[l + msp - 1] = p * e3[l];
        p *= e2;
    }
    p = e1 * e2i; /* l = -1 .. -msp + 1 */
    for (int l = 1; l < msp; l++) {
        w[msp - 1 - l] = p * e3[l];
        p *= e2i;
    }
    return m0 - msp + 1;
}

static int weights(const gr_sk_plan *pl, double coord, double *w)
{
    return gr_sk_gauss_weights(pl->L, pl->lat.Mr, pl->h, pl->lat.tau, pl->msp, pl->e3, coord, w);
}

/* Spread n particles onto the grid and transform it: pl->spec then holds rho(k) / deconv of every
 * vector (the deconvolution applied by the caller, S or rho). */
static int grid_transform(gr_sk_plan *pl, int n, const double *x, const double *y, gr_error *err)
{
    const int Mr = pl->lat.Mr, w2 = 2 * pl->msp;
    if (n > pl->cap) { /* the first frame (or a larger N): the only allocation after the plan */
        free(pl->row_of);
        free(pl->xs);
        free(pl->ys);
        pl->row_of = malloc(sizeof(int) * (size_t)n);
        pl->xs = malloc(sizeof(double) * (size_t)n);
        pl->ys = malloc(sizeof(double) * (size_t)n);
        pl->cap = pl->row_of && pl->xs && pl->ys ? n : 0;
        if (!pl->cap) {
            return GR_FAIL(err, GR_ENOMEM, "sk: out of memory (%d particles)", n);
        }
    }
    /* visit the particles row by row of the grid (a stable counting sort): the 2 msp rows one
     * particle touches are then still in cache for the next (~20% faster at N = 5e4-1e5) */
    int *bucket = pl->bucket;
    memset(bucket, 0, sizeof(int) * ((size_t)Mr + 1));
    for (int j = 0; j < n; j++) {
        double u = y[j] / pl->L;
        u -= floor(u);
        int r = (int)(u * Mr);
        r = r < Mr ? r : Mr - 1;
        pl->row_of[j] = r;
        bucket[r + 1]++;
    }
    for (int r = 0; r < Mr; r++) {
        bucket[r + 1] += bucket[r];
    }
    for (int j = 0; j < n; j++) { /* scatter (cheaper than gathering in the loop below) */
        int at = bucket[pl->row_of[j]]++;
        pl->xs[at] = x[j];
        pl->ys[at] = y[j];
    }
    x = pl->xs;
    y = pl->ys;
    double *grid = pl->grid;
    memset(grid, 0, sizeof(double) * (size_t)Mr * (size_t)Mr);
    /* Threads own bands of grid rows and add, in particle order, the part of every particle's
     * footprint that falls in their band: each grid value is the same sum as with one thread. */
    int T = n >= 4096 ? gr_get_threads() : 1;
    T = T < Mr / w2 ? T : (Mr / w2 > 0 ? Mr / w2 : 1);
#pragma omp parallel num_threads(T) if (T > 1)
    {
#ifdef _OPENMP
        const int tid = omp_get_thread_num(), nth = omp_get_num_threads();
#else
        const int tid = 0, nth = 1;
#endif
        const int R0 = (int)((int64_t)Mr * tid / nth), R1 = (int)((int64_t)Mr * (tid + 1) / nth);
        double wx[2 * GR_SK_MSP_MAX], wy[2 * GR_SK_MSP_MAX];
        int cols[2 * GR_SK_MSP_MAX];
        for (int j = 0; j < n; j++) {
            if (nth >
                1) { /* does the footprint (rows m0 - msp + 1 .. m0 + msp, wrapped) meet the band? */
                double u = y[j] / pl->L;
                u -= floor(u);
                int m0 = (int)(u * Mr);
                m0 = m0 < Mr ? m0 : Mr - 1;
                bool meets = false;
                for (int r = 0; r < w2 && !meets; r++) {
                    int row = m0 - pl->msp + 1 + r;
                    row = row < 0 ? row + Mr : row >= Mr ? row - Mr : row;
                    meets = row >= R0 && row < R1;
                }
                if (!meets) {
                    continue;
                }
            }
            int x0 = weights(pl, x[j], wx), y0 = weights(pl, y[j], wy);
            bool wrap_x = x0 < 0 || x0 + w2 > Mr;
            if (wrap_x) { /* Mr >= 2 msp: one wrap at most */
                for (int i = 0; i < w2; i++) {
                    int c = x0 + i;
                    cols[i] = c < 0 ? c + Mr : c >= Mr ? c - Mr : c;
                }
            }
            for (int r = 0; r < w2; r++) {
                int row = y0 + r;
                row = row < 0 ? row + Mr : row >= Mr ? row - Mr : row;
                if (row < R0 || row >= R1) {
                    continue;
                }
                double *g = grid + (size_t)row * (size_t)Mr;
                const double wr = wy[r];
                if (!wrap_x) {
                    g += x0;
                    for (int i = 0; i < w2; i++) {
                        g[i] += wr * wx[i];
                    }
                } else {
                    for (int i = 0; i < w2; i++) {
                        g[cols[i]] += wr * wx[i];
                    }
                }
            }
        }
    }
    fftw_execute(pl->rows);
    fftw_execute(pl->cols);
    return GR_OK;
}

static int compute_gridding(gr_sk_plan *pl, int n, const double *x, const double *y, double *S,
                            gr_error *err)
{
    int rc = grid_transform(pl, n, x, y, err);
    if (rc) {
        return rc;
    }
    const double inv_n = 1.0 / n;
    for (int v = 0; v < pl->lat.nv; v++) {
        const double *c = pl->spec[pl->idx[v]];
        const double f = pl->deconv[v];
        S[v] = (c[0] * c[0] + c[1] * c[1]) * f * f * inv_n;
    }
    return GR_OK;
}

static int direct_alloc(gr_sk_plan *pl, gr_error *err)
{
    const size_t W = 2 * (size_t)pl->n_max + 1, A = (size_t)pl->n_max + 1;
    pl->rre = malloc(sizeof(double) * A * W);
    pl->rim = malloc(sizeof(double) * A * W);
    pl->pxr = malloc(sizeof(double) * A * DIRECT_BLOCK);
    pl->pxi = malloc(sizeof(double) * A * DIRECT_BLOCK);
    pl->pyr = malloc(sizeof(double) * W * DIRECT_BLOCK);
    pl->pyi = malloc(sizeof(double) * W * DIRECT_BLOCK);
    if (!pl->rre || !pl->rim || !pl->pxr || !pl->pxi || !pl->pyr || !pl->pyi) {
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory (direct sum)");
    }
    return GR_OK;
}

/* exp(-i a u) for a = 0..n into (re, im), by the recurrence e^{-i a u} = e^{-i (a-1) u} e^{-i u},
 * re-seeded with sincos every RESEED steps (error ~ RESEED * machine epsilon). */
static void phases(double u, int n, double *re, double *im)
{
    const double c = cos(u), s = -sin(u);
    for (int a = 0; a <= n; a++) {
        if (a % RESEED == 0) {
            re[a] = cos(a * u);
            im[a] = -sin(a * u);
        } else {
            re[a] = re[a - 1] * c - im[a - 1] * s;
            im[a] = re[a - 1] * s + im[a - 1] * c;
        }
    }
}

/* The direct sum, separable: rho(n_x, n_y) = sum_j X_j(n_x) Y_j(n_y) with X_j(a) = e^{-2 pi i a
 * x_j / L}, Y_j(b) = e^{-2 pi i b y_j / L} (a complex matrix product), over blocks of particles so
 * that one row of rho stays in L1 while a block's phases are applied. */
static void direct_sum(gr_sk_plan *pl, int n, const double *x, const double *y)
{
    const int nm = pl->n_max, A = nm + 1, W = 2 * nm + 1;
    memset(pl->rre, 0, sizeof(double) * (size_t)A * (size_t)W);
    memset(pl->rim, 0, sizeof(double) * (size_t)A * (size_t)W);
    for (int j0 = 0; j0 < n; j0 += DIRECT_BLOCK) {
        const int bn = n - j0 < DIRECT_BLOCK ? n - j0 : DIRECT_BLOCK;
        for (int q = 0; q < bn; q++) {
            double ux = x[j0 + q] / pl->L, uy = y[j0 + q] / pl->L;
            ux = 2.0 * M_PI * (ux - floor(ux));
            uy = 2.0 * M_PI * (uy - floor(uy));
            phases(ux, nm, pl->pxr + (size_t)q * A, pl->pxi + (size_t)q * A);
            double *yr = pl->pyr + (size_t)q * W + nm, *yi = pl->pyi + (size_t)q * W + nm;
            phases(uy, nm, yr, yi);
            for (int b = 1; b <= nm; b++) { /* Y(-b) = conj Y(b) */
                yr[-b] = yr[b];
                yi[-b] = -yi[b];
            }
        }
        for (int a = 0; a <= nm; a++) {
            const int bm = isqrt_floor(pl->nsq - (long)a * a);
            double *rr = pl->rre + (size_t)a * W + nm, *ri = pl->rim + (size_t)a * W + nm;
            for (int q = 0; q < bn; q++) {
                const double xr = pl->pxr[(size_t)q * A + a], xi = pl->pxi[(size_t)q * A + a];
                const double *yr = pl->pyr + (size_t)q * W + nm, *yi = pl->pyi + (size_t)q * W + nm;
                for (int b = -bm; b <= bm; b++) {
                    rr[b] += xr * yr[b] - xi * yi[b];
                    ri[b] += xr * yi[b] + xi * yr[b];
                }
            }
        }
    }
}

/* Index of vector v in the direct sum's rho table. */
static size_t direct_index(const gr_sk_plan *pl, int v)
{
    return (size_t)pl->lat.nx[v] * (2 * (size_t)pl->n_max + 1) +
           (size_t)(pl->lat.ny[v] + pl->n_max);
}

static void compute_direct(gr_sk_plan *pl, int n, const double *x, const double *y, double *S)
{
    direct_sum(pl, n, x, y);
    const double inv_n = 1.0 / n;
    for (int v = 0; v < pl->lat.nv; v++) {
        size_t k = direct_index(pl, v);
        S[v] = (pl->rre[k] * pl->rre[k] + pl->rim[k] * pl->rim[k]) * inv_n;
    }
}

/* The checks shared by gr_sk_compute and gr_sk_compute_rho (the direct sum's tables allocated at
 * its first use). */
static int compute_check(gr_sk_plan *pl, int method, int n, int n_min, const double *x,
                         const double *y, gr_error *err)
{
    if (n < n_min || (n > 0 && (!x || !y))) {
        return GR_FAIL(err, GR_EINVAL, "sk: a frame needs at least %d particle(s) with x and y",
                       n_min);
    }
    if (method == GR_SK_DIRECT) {
        return pl->rre ? GR_OK : direct_alloc(pl, err);
    }
    if (method != GR_SK_GRIDDING) {
        return GR_FAIL(err, GR_EINVAL, "sk: unknown method %d", method);
    }
    return GR_OK;
}

int gr_sk_compute(gr_sk_plan *pl, int method, int n, const double *x, const double *y, double *S,
                  gr_error *err)
{
    int rc = compute_check(pl, method, n, 1, x, y, err);
    if (rc) {
        return rc;
    }
    if (method == GR_SK_DIRECT) {
        compute_direct(pl, n, x, y, S);
        return GR_OK;
    }
    return compute_gridding(pl, n, x, y, S, err);
}

int gr_sk_compute_rho(gr_sk_plan *pl, int method, int n, const double *x, const double *y,
                      double *re, double *im, gr_error *err)
{
    int rc = compute_check(pl, method, n, 0, x, y, err);
    if (rc) {
        return rc;
    }
    if (method == GR_SK_DIRECT) {
        direct_sum(pl, n, x, y);
        for (int v = 0; v < pl->lat.nv; v++) {
            const size_t k = direct_index(pl, v);
            re[v] = pl->rre[k];
            im[v] = pl->rim[k];
        }
        return GR_OK;
    }
    rc = grid_transform(pl, n, x, y, err);
    for (int v = 0; v < pl->lat.nv && !rc; v++) {
        const double *c = pl->spec[pl->idx[v]];
        re[v] = c[0] * pl->deconv[v];
        im[v] = c[1] * pl->deconv[v];
    }
    return rc;
}

/* ------------------------------------------------------------------------------------------
 * The observable. */

typedef struct sk_params {
    double sk_kd_max;
} sk_params;

static const gr_param params[] = {
    {"sk_kd_max", "", GR_PARAM_DOUBLE, 4.0, 0.0, 64.0, true, false,
     "S(k) on every lattice vector k = 2 pi n / L (4.3), n != 0, with k d <= sk_kd_max",
     offsetof(sk_params, sk_kd_max)},
};

#define SHELL_N_MIN 16  /* exact shells |n|^2 = const are kept at least up to |n| = 16, */
#define SHELL_N_CAP 128 /* and up to 2 k' L / 2 pi, but never beyond |n| = 128 */
#define BLOCKING_MIN_FRAMES 16

/* A set of lattice vectors averaged together: a circular bin or an exact shell. */
typedef struct sk_bin {
    int count;          /* vectors in the half plane (the full plane has twice as many) */
    double ksum;        /* sum of their |k|, 1/m */
    double frame;       /* this frame's sum of S */
    double pool, pool2; /* sums of S and S^2 over every frame and vector (one-frame errors) */
    gr_blocking acc;    /* the frame means of S */
} sk_bin;

typedef struct sk_state {
    int dim;            /* 2 or 3 */
    gr_sk_plan *plan;   /* 2D */
    gr_sk3_plan *plan3; /* 3D */
    int method, msp;
    double L, d, kd_max, n_cut;
    bool mixture; /* d is the mixture's mean collision diameter (gr_obs_collision_diameter) */
    int nv;
    double *S;     /* the current frame, one value per vector */
    int *bin_of;   /* circular bin of each vector: |n| in [s - 1/2, s + 1/2), index s - 1 */
    int *shell_of; /* exact shell of each vector (-1: beyond the shells kept) */
    int nbins, nshells;
    sk_bin *bins, *shells;
    long *shell_q;  /* |n|^2 of each shell, increasing */
    double n_shell; /* shells kept for |n| <= n_shell */
    int64_t frames;
    /* dissipative regime (4.5)-(4.9) */
    double eps_n, eps_t;
    const char *eps_t_from;
    char
        eps_t_name[80]; /* "NAME eps_t" for a law with a constant eps_t (gr_model.constant_eps_t) */
    double l0, kD, Lmin, Leff, kprime;
    /* a mixture of species lists (ns >= 2; 0 otherwise): the partial structure factors S_ab of the
     * pairs a <= b (pair p in the order 11, 12, .., 1 ns, 22, ..) on the same |n| bins */
    int ns, n;
    gr_obs_pairs pairs;
    double *pos;                       /* one species' positions: x, y, z blocks of n */
    double *rre, *rim;                 /* rho_a(k) of species a at [a nv + v] */
    sk_bin *pbins;                     /* pair p's bins at [p nbins + b] */
    int64_t pframes[GR_OBS_MAX_PAIRS]; /* frames that had both species of the pair */
    int64_t count[GR_MAX_SPECIES];     /* N_a of the last frame */
} sk_state;

static void release_plan(void *plan) { gr_sk_plan_free(plan); }
static void release_plan3(void *plan) { gr_sk3_plan_free(plan); }

/* The plan's vectors and gridding, 2D or 3D alike. */
static const gr_sk_lattice *lattice_of(const sk_state *st)
{
    return st->dim == 3 ? gr_sk3_plan_lattice(st->plan3) : gr_sk_plan_lattice(st->plan);
}

static int method_from_env(int *method, gr_error *err)
{
    const char *m = getenv("GRANULE_SK_METHOD");
    if (!m || !*m || strcmp(m, "gridding") == 0) {
        *method = GR_SK_GRIDDING;
    } else if (strcmp(m, "direct") == 0) {
        *method = GR_SK_DIRECT;
    } else {
        return GR_FAIL(err, GR_EINVAL, "sk: GRANULE_SK_METHOD = '%s': use gridding or direct", m);
    }
    return GR_OK;
}

/* A mixture's partial structure factors: the pairs, one species' positions, each species' rho
 * and the pairs' bins (one-species scenes allocate none of it). */
static int species_init(sk_state *st, const gr_obs_setup *setup, gr_error *err)
{
    st->ns = setup->n_species;
    st->n = setup->N;
    gr_obs_pairs_init(&st->pairs, st->ns);
    const size_t nv = (size_t)st->nv, ns = (size_t)st->ns;
    st->pos = gr_obs_calloc(st, (size_t)st->dim * (size_t)st->n, sizeof(double));
    st->rre = gr_obs_calloc(st, ns * nv, sizeof(double));
    st->rim = gr_obs_calloc(st, ns * nv, sizeof(double));
    st->pbins = gr_obs_calloc(st, (size_t)st->pairs.n * (size_t)st->nbins, sizeof(sk_bin));
    for (int p = 0; st->pbins && p < st->pairs.n; p++) {
        memcpy(st->pbins + (size_t)p * (size_t)st->nbins, st->bins,
               sizeof(sk_bin) * (size_t)st->nbins); /* the bins' vectors and k */
    }
    return gr_obs_alloc_ok(st, err);
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    if (setup->dim != 2 && setup->dim != 3) {
        return GR_FAIL(err, GR_EINVAL, "sk: S(k) of eqs. 4.2-4.3 needs dim = 2 or 3 (got %d)",
                       setup->dim);
    }
    const double kd_max = ((const sk_params *)params_block)->sk_kd_max;
    if (setup->N < 1 || !(setup->L > 0.0) || !isfinite(setup->L) || !(setup->radius > 0.0) ||
        !isfinite(setup->radius)) {
        return GR_FAIL(err, GR_EINVAL,
                       "sk: needs N >= 1, L > 0 and radius > 0 (got N = %d, L = %g, radius = %g)",
                       setup->N, setup->L, setup->radius);
    }
    if (!(kd_max > params[0].min) || !(kd_max <= params[0].max)) {
        return GR_FAIL(err, GR_EINVAL, "[analysis] sk_kd_max = %g outside (%g, %g]", kd_max,
                       params[0].min, params[0].max);
    }
    /* a mixture: the mean collision diameter (the mean free path's and k d's length) */
    const double d = gr_obs_collision_diameter(setup);
    const double n_cut = kd_max * setup->L / (2.0 * M_PI * d);
    if (n_cut < 1.0) {
        return GR_FAIL(err, GR_EINVAL,
                       "[analysis] sk_kd_max = %g reaches no lattice vector: the smallest |k| d is "
                       "2 pi d / L = %g",
                       kd_max, 2.0 * M_PI * d / setup->L);
    }
    sk_state *st = state;
    st->dim = setup->dim;
    int rc = method_from_env(&st->method, err);
    if (!rc && st->dim == 3) {
        rc = gr_sk3_plan_create(setup->L, n_cut, GR_SK3_MSP_DEFAULT, &st->plan3, err);
        if (!rc) {
            gr_obs_own(st, release_plan3, st->plan3);
        }
    } else if (!rc) {
        rc = gr_sk_plan_create(setup->L, n_cut, GR_SK_MSP_DEFAULT, &st->plan, err);
        if (!rc) {
            gr_obs_own(st, release_plan, st->plan);
        }
    }
    if (rc) {
        return rc;
    }
    st->msp = st->dim == 3 ? GR_SK3_MSP_DEFAULT : GR_SK_MSP_DEFAULT;
    st->L = setup->L;
    st->d = d;
    st->mixture = setup->sizes;
    st->kd_max = kd_max;
    st->n_cut = n_cut;

    /* the dissipative regime: k_D = (2 - eps_n^2 - eps_t^2) / (8 l_0) (4.5), l_0 = L^2 / (2 d N)
     * (4.7), L_min = 2 pi / k_D (4.6, 4.8), L_Eff = 2 sqrt 2 L_min (4.9); the fit window ends at
     * k' = k_D when L > L_Eff and at 2 k_D otherwise (sec. 4.1.2) */
    st->eps_n = setup->eps_n;
    if (!setup->tangential) {
        st->eps_t = 1.0;
        st->eps_t_from = "no tangential law: eps_t = 1";
    } else if (setup->tangential_constant_eps_t) {
        st->eps_t = setup->eps_t;
        snprintf(st->eps_t_name, sizeof st->eps_t_name, "%s eps_t", setup->tangential);
        st->eps_t_from = st->eps_t_name;
    } else {
        st->eps_t = 1.0;
        st->eps_t_from = "no constant eps_t for this tangential law: eps_t = 1 assumed";
    }
    st->l0 = st->dim == 3 ? setup->L * setup->L * setup->L / (M_PI * d * d * setup->N)
                          : setup->L * setup->L / (2.0 * d * setup->N);
    st->kD = (2.0 - st->eps_n * st->eps_n - st->eps_t * st->eps_t) / (8.0 * st->l0);
    if (st->kD > 0.0) {
        st->Lmin = 2.0 * M_PI / st->kD;
        st->Leff = 2.0 * sqrt(2.0) * st->Lmin;
        st->kprime = st->L > st->Leff ? st->kD : 2.0 * st->kD;
    } else {
        st->kD = st->Lmin = st->Leff = st->kprime = NAN;
    }
    double n_prime = isfinite(st->kprime) ? st->kprime * st->L / (2.0 * M_PI) : 0.0;
    st->n_shell = fmin(n_cut, fmin((double)SHELL_N_CAP, fmax((double)SHELL_N_MIN, 2.0 * n_prime)));
    const long q_shell = (long)floor(st->n_shell * st->n_shell * (1.0 + 1e-12));

    const int *nx, *ny, *nz;
    st->nv = gr_sk_vectors(lattice_of(st), &nx, &ny, &nz);
    st->S = gr_obs_calloc(st, (size_t)st->nv, sizeof(double));
    st->bin_of = gr_obs_calloc(st, (size_t)st->nv, sizeof(int));
    st->shell_of = gr_obs_calloc(st, (size_t)st->nv, sizeof(int));
    int *qmap = malloc(sizeof(int) * (size_t)(q_shell + 1));
    if (!st->S || !st->bin_of || !st->shell_of || !qmap) {
        free(qmap);
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory");
    }
    for (long q = 0; q <= q_shell; q++) {
        qmap[q] = -1;
    }
    for (int v = 0; v < st->nv; v++) {
        long q = (long)nx[v] * nx[v] + (long)ny[v] * ny[v] + (nz ? (long)nz[v] * nz[v] : 0);
        st->bin_of[v] = (int)floor(sqrt((double)q) + 0.5) - 1;
        st->nbins = st->bin_of[v] + 1 > st->nbins ? st->bin_of[v] + 1 : st->nbins;
        if (q <= q_shell) {
            qmap[q] = 0;
        }
    }
    for (long q = 1; q <= q_shell; q++) {
        st->nshells += qmap[q] == 0;
    }
    st->bins = gr_obs_calloc(st, (size_t)st->nbins, sizeof(sk_bin));
    st->shells = gr_obs_calloc(st, (size_t)(st->nshells > 0 ? st->nshells : 1), sizeof(sk_bin));
    st->shell_q = gr_obs_calloc(st, (size_t)(st->nshells > 0 ? st->nshells : 1), sizeof(long));
    if (!st->bins || !st->shells || !st->shell_q) {
        free(qmap);
        return GR_FAIL(err, GR_ENOMEM, "sk: out of memory");
    }
    for (long q = 1, i = 0; q <= q_shell; q++) {
        if (qmap[q] == 0) {
            st->shell_q[i] = q;
            qmap[q] = (int)i++;
        }
    }
    const double dk = 2.0 * M_PI / st->L;
    for (int v = 0; v < st->nv; v++) {
        long q = (long)nx[v] * nx[v] + (long)ny[v] * ny[v] + (nz ? (long)nz[v] * nz[v] : 0);
        double k = dk * sqrt((double)q);
        st->bins[st->bin_of[v]].count++;
        st->bins[st->bin_of[v]].ksum += k;
        st->shell_of[v] = q <= q_shell ? qmap[q] : -1;
        if (st->shell_of[v] >= 0) {
            st->shells[st->shell_of[v]].count++;
            st->shells[st->shell_of[v]].ksum += k;
        }
    }
    free(qmap);
    return setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES
               ? species_init(st, setup, err)
               : GR_OK;
}

/* One frame's S of every vector into a set of bins (circular bins or exact shells; of[v] < 0: in
 * none): the sums of S over each bin's vectors (pooled), then each bin's mean into its blocking. */
static void add_frame(sk_bin *set, int nset, const int *of, const double *S, int nv)
{
    for (int b = 0; b < nset; b++) {
        set[b].frame = 0.0;
    }
    for (int v = 0; v < nv; v++) {
        if (of[v] >= 0) {
            sk_bin *b = &set[of[v]];
            b->frame += S[v];
            b->pool += S[v];
            b->pool2 += S[v] * S[v];
        }
    }
    for (int b = 0; b < nset; b++) {
        if (set[b].count) {
            gr_blocking_add(&set[b].acc, set[b].frame / set[b].count);
        }
    }
}

/* A mixture's frame: rho_a(k) of each species by the same engine (one more transform per
 * species), then S_ab(k) = Re[rho_a(k) conj(rho_b(k))] / sqrt(N_a N_b) of every pair a <= b into
 * its bins (the imaginary part is odd in k: the full plane's average of it is zero). */
static int sample_species(sk_state *st, const gr_particles *p, gr_error *err)
{
    const size_t nv = (size_t)st->nv;
    double *x = st->pos, *y = st->pos + st->n, *z = st->dim == 3 ? st->pos + 2 * st->n : NULL;
    for (int a = 0; a < st->ns; a++) {
        int m = 0;
        for (int i = 0; i < p->n; i++) {
            if (p->species[i] == a) {
                x[m] = p->x[i];
                y[m] = p->y[i];
                if (z) {
                    z[m] = p->z[i];
                }
                m++;
            }
        }
        st->count[a] = m;
        double *re = st->rre + (size_t)a * nv, *im = st->rim + (size_t)a * nv;
        int rc = st->dim == 3 ? gr_sk3_compute_rho(st->plan3, st->method, m, x, y, z, re, im, err)
                              : gr_sk_compute_rho(st->plan, st->method, m, x, y, re, im, err);
        if (rc) {
            return rc;
        }
    }
    for (int q = 0; q < st->pairs.n; q++) {
        const int a = st->pairs.a[q], b = st->pairs.b[q];
        if (!st->count[a] || !st->count[b]) {
            continue; /* a species without grains in this frame */
        }
        const double norm = 1.0 / sqrt((double)st->count[a] * (double)st->count[b]);
        const double *ra = st->rre + (size_t)a * nv, *ia = st->rim + (size_t)a * nv;
        const double *rb = st->rre + (size_t)b * nv, *ib = st->rim + (size_t)b * nv;
        for (size_t v = 0; v < nv; v++) { /* st->S (the total, binned already) as scratch */
            st->S[v] = (ra[v] * rb[v] + ia[v] * ib[v]) * norm;
        }
        add_frame(st->pbins + (size_t)q * (size_t)st->nbins, st->nbins, st->bin_of, st->S, st->nv);
        st->pframes[q]++;
    }
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    sk_state *st = state;
    if (p->dim != st->dim || !p->y || (p->dim == 3 && !p->z)) {
        return GR_FAIL(err, GR_EINVAL, "sk: a %dD frame is needed (got dim = %d)", st->dim, p->dim);
    }
    if (!(fabs(p->L - st->L) <= 1e-9 * st->L)) {
        return GR_FAIL(err, GR_EINVAL,
                       "sk: the frame's box side %g differs from the scene's L = %g", p->L, st->L);
    }
    int rc = st->ns ? gr_obs_frame_species("sk", p, st->ns, st->n, NULL, err) : GR_OK;
    if (rc) {
        return rc;
    }
    rc = st->dim == 3 ? gr_sk3_compute(st->plan3, st->method, p->n, p->x, p->y, p->z, st->S, err)
                      : gr_sk_compute(st->plan, st->method, p->n, p->x, p->y, st->S, err);
    if (rc) {
        return rc;
    }
    /* circular average of this frame (sec. 4.1: the angular average of S(k)), then in time */
    add_frame(st->bins, st->nbins, st->bin_of, st->S, st->nv);
    add_frame(st->shells, st->nshells, st->shell_of, st->S, st->nv);
    st->frames++;
    return st->ns ? sample_species(st, p, err) : GR_OK;
}

/* Error of a time-averaged bin: block averaging from 16 frames on (correlated frames), the plain
 * error of the mean over 2-15 frames, and for a single frame the spread of S over the bin's
 * independent vectors divided by sqrt(count). */
static const char *error_method(int64_t frames)
{
    return frames >= BLOCKING_MIN_FRAMES ? "block averaging over frames"
           : frames >= 2 ? "error of the mean over frames (fewer than 16: uncorrelated assumed)"
                         : "spread over the independent vectors of each bin (one frame)";
}

static double bin_error(const sk_bin *b, int64_t frames)
{
    if (frames >= BLOCKING_MIN_FRAMES) {
        return gr_blocking_stderr(&b->acc, NULL, NULL);
    }
    if (frames >= 2) {
        return gr_blocking_stderr_at(&b->acc, 0);
    }
    if (frames == 1 && b->count >= 2) {
        double m = b->pool / b->count,
               var = (b->pool2 / b->count - m * m) * b->count / (b->count - 1.0);
        return sqrt(fmax(var, 0.0) / b->count);
    }
    return NAN;
}

/* The fit of S(k) = A k^-D_f (4.4) over the exact shells with k < k'. */
typedef struct sk_fit {
    bool done;
    char note[200];
    gr_fit fit;
    bool weighted, truncated;
    int shells;        /* shells inside the window */
    double k_lo, k_hi; /* the lattice points used */
} sk_fit;

static void fit_window(const sk_state *st, sk_fit *F, gr_error *err)
{
    memset(F, 0, sizeof *F);
    if (!isfinite(st->kprime)) {
        snprintf(F->note, sizeof F->note,
                 "no fit: k_D (4.5) is not positive (eps_n = %g, eps_t = %g)", st->eps_n,
                 st->eps_t);
        return;
    }
    if (st->frames == 0) {
        snprintf(F->note, sizeof F->note, "no fit: no frames");
        return;
    }
    const double dk = 2.0 * M_PI / st->L;
    F->truncated = st->kprime > dk * st->n_shell;
    double *k = malloc(sizeof(double) * (size_t)(st->nshells + 1));
    double *S = malloc(sizeof(double) * (size_t)(st->nshells + 1));
    double *e = malloc(sizeof(double) * (size_t)(st->nshells + 1));
    if (!k || !S || !e) {
        free(k);
        free(S);
        free(e);
        snprintf(F->note, sizeof F->note, "no fit: out of memory");
        return;
    }
    int n = 0;
    F->weighted = true;
    for (int b = 0; b < st->nshells; b++) {
        double kb = dk * sqrt((double)st->shell_q[b]);
        if (kb >= st->kprime) {
            break;
        }
        k[n] = kb;
        S[n] = gr_blocking_mean(&st->shells[b].acc);
        e[n] = bin_error(&st->shells[b], st->frames);
        F->weighted &= isfinite(e[n]) && e[n] > 0.0;
        n++;
    }
    F->shells = n;
    if (n >= 2) {
        F->k_lo = k[0];
        F->k_hi = k[n - 1];
    }
    gr_error ferr = {0};
    if (n < GR_FIT_MIN_POINTS) {
        snprintf(F->note, sizeof F->note,
                 "no fit: %d lattice shell(s) below k' = %g /m (2 pi / L = %g /m), a fit needs %d",
                 n, st->kprime, dk, GR_FIT_MIN_POINTS);
    } else if (gr_fit_power_law(k, S, F->weighted ? e : NULL, n, &F->fit, &ferr) != GR_OK) {
        snprintf(F->note, sizeof F->note, "no fit: %.150s", ferr.message);
    } else {
        F->done = true;
        snprintf(F->note, sizeof F->note, "ok");
    }
    (void)err;
    free(k);
    free(S);
    free(e);
}

/* sk.csv and sk_shells.csv, one row per |n| bin / exact shell */
typedef struct sk_rows_ctx {
    const sk_state *st;
    const sk_fit *fit;
} sk_rows_ctx;

const char gr_obs_sk_columns[] =
    "n [1],k [m-1],kd [1],S [1],S_err [1],vectors [1],independent_vectors [1]";

static void sk_rows(FILE *f, const void *ctx)
{
    const sk_state *st = ((const sk_rows_ctx *)ctx)->st;
    for (int b = 0; b < st->nbins; b++) {
        const sk_bin *B = &st->bins[b];
        if (!B->count || !st->frames) {
            continue;
        }
        double k = B->ksum / B->count;
        fprintf(f, "%d,%.10g,%.10g,%.10g,%.6g,%d,%d\n", b + 1, k, k * st->d,
                gr_blocking_mean(&B->acc), bin_error(B, st->frames), 2 * B->count, B->count);
    }
}

static void shell_rows(FILE *f, const void *ctx)
{
    const sk_rows_ctx *c = ctx;
    const sk_state *st = c->st;
    const double dk = 2.0 * M_PI / st->L;
    for (int b = 0; b < st->nshells && st->frames; b++) {
        const sk_bin *B = &st->shells[b];
        double k = dk * sqrt((double)st->shell_q[b]);
        fprintf(f, "%ld,%.10g,%.10g,%.10g,%.6g,%d,%d,%d\n", st->shell_q[b], k, k * st->d,
                gr_blocking_mean(&B->acc), bin_error(B, st->frames), 2 * B->count, B->count,
                c->fit->done && b < c->fit->shells ? 1 : 0);
    }
}

/* sk_species.csv: per |n| bin, S_ab and its error of every pair a <= b */
static void species_rows(FILE *f, const void *ctx)
{
    const sk_state *st = ctx;
    for (int b = 0; b < st->nbins && st->frames; b++) {
        const sk_bin *B = &st->bins[b];
        if (!B->count) {
            continue;
        }
        double k = B->ksum / B->count;
        fprintf(f, "%d,%.10g,%.10g", b + 1, k, k * st->d);
        for (int q = 0; q < st->pairs.n; q++) {
            const sk_bin *P = &st->pbins[(size_t)q * (size_t)st->nbins + (size_t)b];
            if (st->pframes[q]) { /* 15 digits: sum_ab sqrt(x_a x_b) S_ab is sk.csv's S */
                fprintf(f, ",%.15g,%.6g", gr_blocking_mean(&P->acc), bin_error(P, st->pframes[q]));
            } else {
                fputs(",nan,nan", f);
            }
        }
        fputc('\n', f);
    }
}

/* A mixture's partial structure factors (Ashcroft-Langreth): sk_species.csv, and in the summary
 * the pairs, the species' numbers and S_ab at the smallest k. */
static int finish_species(const sk_state *st, const gr_output *out, cJSON *j, gr_error *err)
{
    char columns[64 + GR_OBS_MAX_PAIRS * 40];
    const gr_obs_pairs *pairs = &st->pairs;
    size_t len = (size_t)snprintf(columns, sizeof columns, "n [1],k [m-1],kd [1]");
    for (int q = 0; q < pairs->n; q++) {
        len += (size_t)snprintf(columns + len, sizeof columns - len, ",S_%s [1],S_%s_err [1]",
                                pairs->label[q], pairs->label[q]);
    }
    gr_obs_pairs_summary(pairs, j);
    cJSON_AddStringToObject(j, "species_file", "sk_species.csv");
    cJSON *jn = cJSON_AddArrayToObject(j, "species_N");
    for (int a = 0; a < st->ns; a++) {
        cJSON_AddItemToArray(jn, cJSON_CreateNumber((double)st->count[a]));
    }
    for (int b = 0; b < st->nbins && st->frames; b++) { /* the smallest k: the S_ab(0) limit */
        if (!st->bins[b].count) {
            continue;
        }
        cJSON *o = cJSON_AddObjectToObject(j, "species_k_min");
        const double k = st->bins[b].ksum / st->bins[b].count;
        cJSON_AddNumberToObject(o, "k", k);
        cJSON_AddNumberToObject(o, "kd", k * st->d);
        cJSON *jS = cJSON_AddArrayToObject(o, "S"), *je = cJSON_AddArrayToObject(o, "S_err");
        for (int q = 0; q < st->pairs.n; q++) {
            const sk_bin *P = &st->pbins[(size_t)q * (size_t)st->nbins + (size_t)b];
            const double S = st->pframes[q] ? gr_blocking_mean(&P->acc) : (double)NAN;
            const double e = st->pframes[q] ? bin_error(P, st->pframes[q]) : (double)NAN;
            cJSON_AddItemToArray(jS, isfinite(S) ? cJSON_CreateNumber(S) : cJSON_CreateNull());
            cJSON_AddItemToArray(je, isfinite(e) ? cJSON_CreateNumber(e) : cJSON_CreateNull());
        }
        break;
    }
    char what[400], plot[600];
    snprintf(what, sizeof what,
             "partial structure factors of a mixture (Ashcroft-Langreth) S_ab(k) = <rho_a(k) "
             "rho_b(-k)> / sqrt(N_a N_b), rho_a(k) = sum_{j in a} exp(-i k.r_j), on sk.csv's |n| "
             "bins (k in 1/m, d = %g m); %lld frames; errors: %s; sum_ab sqrt(x_a x_b) S_ab = S",
             st->d, (long long)st->frames, error_method(st->frames));
    len = (size_t)snprintf(plot, sizeof plot,
                           "set logscale x\nset xlabel 'k d'\nset ylabel 'S_{ab}(k)'\n"
                           "set title 'Partial structure factors'\nplot ");
    for (int q = 0; q < st->pairs.n && len < sizeof plot; q++) {
        len += (size_t)snprintf(plot + len, sizeof plot - len,
                                "%s'sk_species.csv' skip 1 using 3:%d:%d with yerrorbars title "
                                "'S_{%s}'",
                                q ? ", " : "", 4 + 2 * q, 5 + 2 * q, pairs->label[q]);
    }
    const gr_obs_table t = {.name = "sk_species.csv",
                            .what = what,
                            .columns = columns,
                            .rows = species_rows,
                            .ctx = st,
                            .png = st->frames > 0 ? "sk_species.png" : NULL,
                            .plot = plot};
    return gr_obs_table_write(out, &t, err);
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    sk_state *st = state;
    const double dk = 2.0 * M_PI / st->L;
    sk_fit F;
    fit_window(st, &F, err);

    char what[400];
    snprintf(what, sizeof what,
             "structure factor S(k) = |rho(k)|^2/N (4.2) on k = 2 pi n/L (4.3), circular average "
             "over |n| bins "
             "of width 1 (n = bin centre), k = mean |k| of the bin in 1/m, d = %g m, %lld frames; "
             "S_err: %s; "
             "vectors = full %s (half are independent, S(-k) = S(k))",
             st->d, (long long)st->frames, error_method(st->frames),
             st->dim == 3 ? "space" : "plane");
    const sk_rows_ctx rows = {.st = st, .fit = &F};
    gr_obs_table t = {.name = "sk.csv",
                      .what = what,
                      .columns = gr_obs_sk_columns,
                      .rows = sk_rows,
                      .ctx = &rows};
    int rc = gr_obs_table_write(out, &t, err);
    if (rc) {
        return rc;
    }
    snprintf(
        what, sizeof what,
        "structure factor S(k) (4.2) averaged over each exact shell |n|^2 = n2 (k = 2 pi |n|/L in "
        "1/m) up "
        "to |n| = %g; in_fit = 1: inside the D_f fit window k < k' = %g /m; %lld frames; S_err: %s",
        st->n_shell, st->kprime, (long long)st->frames, error_method(st->frames));
    t = (gr_obs_table){
        .name = "sk_shells.csv",
        .what = what,
        .columns =
            "n2 [1],k [m-1],kd [1],S [1],S_err [1],vectors [1],independent_vectors [1],in_fit [1]",
        .rows = shell_rows,
        .ctx = &rows};
    rc = gr_obs_table_write(out, &t, err);
    if (rc) {
        return rc;
    }

    cJSON *j = cJSON_AddObjectToObject(out->summary, "sk");
    cJSON_AddStringToObject(j, "file", "sk.csv");
    cJSON_AddStringToObject(j, "shells_file", "sk_shells.csv");
    cJSON_AddNumberToObject(j, "frames", (double)st->frames);
    int grid;
    double tau;
    gr_sk_grid(lattice_of(st), &grid, &tau);
    cJSON_AddStringToObject(j, "method", st->method == GR_SK_DIRECT ? "direct" : "gridding");
    cJSON_AddNumberToObject(j, "msp", st->msp);
    cJSON_AddNumberToObject(j, "grid", grid);
    cJSON_AddNumberToObject(j, "kd_max", st->kd_max);
    cJSON_AddNumberToObject(j, "n_max", st->n_cut);
    cJSON_AddNumberToObject(j, "vectors", 2.0 * st->nv);
    cJSON_AddNumberToObject(j, "k_min", dk);
    cJSON_AddStringToObject(j, "errors", error_method(st->frames));
    cJSON_AddNumberToObject(j, "eps_n", st->eps_n);
    cJSON_AddNumberToObject(j, "eps_t", st->eps_t);
    cJSON_AddStringToObject(j, "eps_t_from", st->eps_t_from);
    cJSON_AddNumberToObject(j, "l0", st->l0);
    gr_obs_add_number(j, "k_D", st->kD);
    gr_obs_add_number(j, "k_D_d", st->kD * st->d);
    if (st->mixture) { /* one size: d = 2 radius, as before */
        gr_obs_note_diameter(j, st->d, st->dim);
    }
    gr_obs_add_number(j, "L_min", st->Lmin);
    gr_obs_add_number(j, "L_Eff", st->Leff);
    cJSON_AddNumberToObject(j, "L", st->L);
    if (isfinite(st->Leff)) {
        cJSON_AddBoolToObject(j, "L_above_L_Eff", st->L > st->Leff);
    } else {
        cJSON_AddNullToObject(j, "L_above_L_Eff");
    }
    gr_obs_add_number(j, "k_prime", st->kprime);
    gr_obs_add_number(j, "k_prime_d", st->kprime * st->d);
    cJSON *fj = cJSON_AddObjectToObject(j, "fit");
    cJSON_AddStringToObject(fj, "model", "S(k) = A k^-D_f (4.4) over the exact shells with k < k'");
    cJSON_AddStringToObject(fj, "status", F.note);
    cJSON_AddNumberToObject(fj, "shells", F.shells);
    cJSON_AddBoolToObject(fj, "window_truncated", F.truncated);
    if (F.done) {
        cJSON_AddNumberToObject(fj, "k_lo", F.k_lo);
        cJSON_AddNumberToObject(fj, "k_hi", F.k_hi);
        cJSON_AddNumberToObject(fj, "kd_lo", F.k_lo * st->d);
        cJSON_AddNumberToObject(fj, "kd_hi", F.k_hi * st->d);
        cJSON_AddNumberToObject(fj, "points", F.fit.n_points);
        gr_obs_add_number(fj, "D_f", -F.fit.p[1]);
        gr_obs_add_number(fj, "D_f_err", F.fit.err[1]);
        gr_obs_add_number(fj, "A", F.fit.p[0]);
        gr_obs_add_number(fj, "A_err", F.fit.err[0]);
        gr_obs_add_number(fj, "chi2_red", F.fit.chi2_red);
        cJSON_AddNumberToObject(fj, "dof", F.fit.dof);
        cJSON_AddBoolToObject(fj, "weighted", F.weighted);
    }

    if (st->ns) {
        rc = finish_species(st, out, j, err);
        if (rc) {
            return rc;
        }
    }
    if (out->plots && st->frames > 0) {
        char body[2400];
        int len = snprintf(body, sizeof body,
                           "set logscale xy\nset samples 1000\nset xlabel 'k d (wave number x "
                           "diameter)'\nset ylabel 'S(k)'\n"
                           "set key top right\n"
                           "set title \"Structure factor, %lld frames\\n{/*0.75 eqs. (4.2-4.3); "
                           "error bars: block averaging over frames; "
                           "fit (4.4) over its window}\"\n",
                           (long long)st->frames);
        if (isfinite(st->kD)) {
            len += snprintf(
                body + len, sizeof body - (size_t)len,
                "set arrow from %.8g, graph 0 to %.8g, graph 1 nohead dt 3 lc rgb '#888888'\n"
                "set label 'k_D d' at %.8g, graph 0.95 offset 0.5,0 tc rgb '#888888'\n",
                st->kD * st->d, st->kD * st->d, st->kD * st->d);
        }
        if (!F.done) { /* say on the plot why there is no D_f */
            len += snprintf(body + len, sizeof body - (size_t)len,
                            "set label \"%.150s\" at graph 0.03, graph 0.06 noenhanced\n", F.note);
        }
        len += snprintf(
            body + len, sizeof body - (size_t)len,
            "plot 'sk.csv' skip 1 using 3:4:5 with yerrorbars lt 1 pt 7 ps 0.6 "
            "title 'circular average (rings of width 2\u03c0/L)', "
            "'sk_shells.csv' skip 1 using 3:($4 > 0 ? $4 : 1/0):5 with yerrorbars lt 2 pt 6 ps 1.0 "
            "title 'exact shells (same |k| on the lattice)'");
        if (F.done) {
            char legend[120];
            gr_plot_legend_value("fit S = A k^{-D_f}, D_f", -F.fit.p[1], F.fit.err[1], legend,
                                 sizeof legend);
            snprintf(body + len, sizeof body - (size_t)len,
                     ", [%.8g:%.8g] %.10g * (x / %.10g)**(-%.10g) with lines lw 3 lt 5 title '%s'",
                     F.k_lo * st->d, F.k_hi * st->d, F.fit.p[0], st->d, -F.fit.p[1], legend);
        }
        gr_obs_plot(out, "sk.png", body);
    }
    return GR_OK;
}

/* Checkpoints: the pooled sums and the blocking accumulator of every bin and shell (the vector
 * tables and the NUFFT plan are re-created from the scene). */
static void io_bins(gr_blob_io *io, sk_bin *b, int n, const char *what)
{
    gr_blob_io_check(io, what, n);
    for (int i = 0; i < n; i++) {
        gr_blob_io_f64(io, &b[i].pool);
        gr_blob_io_f64(io, &b[i].pool2);
        gr_obs_io_blockings(io, &b[i].acc, 1);
    }
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    sk_state *st = state;
    gr_blob_io_i64(io, &st->frames);
    io_bins(io, st->bins, st->nbins, "circular bins");
    io_bins(io, st->shells, st->nshells, "shells");
    if (st->ns) { /* a mixture's (one species: the checkpoint as before) */
        gr_blob_io_check(io, "species pairs", st->pairs.n);
        for (int q = 0; q < st->pairs.n; q++) {
            gr_blob_io_i64(io, &st->pframes[q]);
        }
        for (int a = 0; a < st->ns; a++) {
            gr_blob_io_i64(io, &st->count[a]);
        }
        for (int q = 0; q < st->pairs.n; q++) {
            io_bins(io, st->pbins + (size_t)q * (size_t)st->nbins, st->nbins, "circular bins");
        }
    }
    return GR_OK;
}

const gr_observable_type gr_obs_sk = {
    .name = "sk",
    .summary =
        "structure factor S(k) on the k-lattice (4.2-4.3) by Gaussian-gridding NUFFT, circular "
        "average, D_f fit S ~ k^-D_f below k' (4.4) with k_D, L_min, L_Eff (4.5-4.9)",
    .dims = 6, /* 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(sk_params),
    .state_size = sizeof(sk_state),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
