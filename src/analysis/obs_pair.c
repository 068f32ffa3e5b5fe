/* pair: real-space structure of the 2D and 3D systems (thesis sec. 4.2).
 *
 *   g(R)  the angularly averaged pair correlation function (4.10),
 *   C(R)  the mean number of other particles within a distance R of a particle (4.15),
 *   n(R)  = C(R) - n_bar(R), its excess over a homogeneous (ideal-gas) system (4.17),
 *
 * and a power-law fit n(R) ~ A'' R^D_f (4.16-4.17) over a fixed window, giving the fractal
 * dimension D_f of the large-scale structure (the D_f of S(k) ~ k^-D_f, 4.4, via 4.12-4.14).
 *
 * Per frame every pair closer than R_max = min(gr_rmax d, L/2) (minimum image; d = 2 r) is found
 * with a cell list (O(N) for fixed R_max) and binned into gr_bins equal bins of width
 * w = R_max / gr_bins. Frames are fed uniformly in time and each has weight 1.
 *
 * Normalisation. With P_b the mean number of (unordered) pairs per frame in bin b, of area
 * A_b = pi (R_hi^2 - R_lo^2) (the exact shell, 2 pi R dR of 4.10 integrated over the bin),
 *
 *   g_b = P_b / (N (N-1) / (2 L^2) A_b)                                   (4.10)
 *
 * i.e. 4.10 with the ideal-gas pair count N(N-1)/2 instead of N^2/2, so that N uniform random
 * points give g = 1 exactly on average (4.10 as printed gives 1 - 1/N). With n = (N-1)/L^2 the
 * density of the other particles seen from one,
 *
 *   C(R_hi) = (2/N) sum_{b' <= b} P_b' = n sum_{b' <= b} g_b' A_b'         (4.15, exact at R_hi)
 *   n(R_hi) = C(R_hi) - n pi R_hi^2                                      (4.17)
 *
 * C and n are cumulative counts and are exact at the bins' upper edges R_hi (no binning error).
 *
 * Errors. g, C and n of every bin are time averages of per-frame values, and their errors come
 * from block averaging over frames (gr_blocking_stderr, the plateau estimate). With fewer than 16
 * frames blocking has no usable level and the ideal-gas counting error is used instead:
 * sigma(P_b) = sqrt(total count in b) / frames (and likewise for the cumulative count of C).
 * n(R) differs from C(R) by a constant, so they share their error.
 *
 * D_f fit. n(R_hi) is fitted as A'' R^D_f (gr_fit_power_law, weighted by the errors of n) over
 * bins with max(2 d, R_max / 4) <= R_hi <= R_max / 2: beyond the contact shells, whose integrated
 * exclusion hole and peaks add a constant to n(R) (4.15 integrated from 0), and inside R_max / 2,
 * away from the box scale where the sum rule n sum_box (g - 1) dA = 0 bends n(R) back to 0. The
 * window moves with gr_rmax (default 20 d: 5 d .. 10 d). Bins with n <= 0 are left out (a log-log
 * fit). The values of n at neighbouring R are strongly correlated (cumulative counts), so the
 * chi-square error of D_f is optimistic; the reported error is the larger of it and a jackknife
 * error over 16-32 equal batches of consecutive frames (streaming batch means, the batch length
 * doubling as the run grows; frames of an unfinished batch count in the value, not the jackknife).
 *
 * In 3D the same definitions hold with volumes: shells of volume A_b = (4/3) pi (R_hi^3 - R_lo^3)
 * (4 pi R^2 dR integrated over the bin), the box volume L^3 in place of L^2, and n(R) = C(R) -
 * n (4/3) pi R^3; the pairs come from the shared cell list (obs_cells.h).
 *
 * Positions may lie anywhere (snapshots hold [0, L), a running simulation may be slightly
 * outside): they are wrapped into [0, L) here. N and L must stay those of the first frame. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_cells.h"
#include "analysis/obs_pair_species.h"
#include "analysis/obs_util.h"
#include "io/plot.h"
#include "granule/analysis.h"
#include "granule/sim.h"

#define PAIR_MAX_BINS 8192
#define CELL_DIV 2   /* cells of side >= R_max / CELL_DIV: a (2 CELL_DIV + 1)^2 stencil */
#define N_BATCH 32   /* batches of consecutive frames for the jackknife error of D_f */
#define FIT_LO_D 2.0 /* D_f fit window: R_hi >= max(FIT_LO_D d, FIT_LO_FRAC R_max) ... */
#define FIT_LO_FRAC 0.25
#define FIT_HI_FRAC 0.5    /* ... and R_hi <= FIT_HI_FRAC R_max */
#define PEAK_MAX_D 1.5     /* first peak: maximum of g over bins centred below 1.5 d */
#define TAIL_FROM_FRAC 0.5 /* g_tail: mean g over R_max / 2 <= R < R_max (cf. Fig. 4.7) */

typedef struct pair_params {
    int gr_bins;
    double gr_rmax;
} pair_params;

static const gr_param params[] = {
    {"gr_bins", "", GR_PARAM_INT, 400, 1, PAIR_MAX_BINS, false, false,
     "bins of g(R), C(R), n(R) over 0 <= R < R_max (4.10, 4.15-4.17)",
     offsetof(pair_params, gr_bins)},
    {"gr_rmax", "d", GR_PARAM_DOUBLE, 20, 0, 1e4, true, false,
     "largest pair distance R_max in diameters (clamped to L/2)", offsetof(pair_params, gr_rmax)},
};

typedef struct pair {
    /* fixed at init */
    int dim; /* 2 or 3 */
    int nbins;
    double d, L, R_max, width, inv_width;
    int N;
    bool clamped;
    bool mixture;       /* d is the mixture's mean collision diameter (gr_obs_collision_diameter) */
    double *area;       /* A_b = pi (R_hi^2 - R_lo^2) */
    gr_blocking *g_blk; /* per-frame g_b */
    gr_blocking *c_blk; /* per-frame C(R_hi of b) */
    gr_blocking tail_blk; /* per-frame mean g over the tail window */
    int tail_from;        /* first bin of the tail window */
    int64_t *frame_count; /* pairs per bin in the current frame */
    double *c_frame;      /* C(R_hi) of the current frame */
    double *total;        /* pairs per bin, all frames (exact up to 2^53) */
    int64_t frames;
    /* batch means of C for the jackknife of D_f */
    double *batch;                 /* N_BATCH x nbins sums of per-frame C */
    int64_t batch_len, batch_fill; /* frames per full batch; frames in the current batch */
    int n_full;                    /* completed batches */
    /* cell list, allocated at the first frame */
    int M;        /* cells per side */
    int nox, noy; /* distinct cell offsets per axis */
    int off[2 * CELL_DIV + 1];
    double *xs, *ys; /* wrapped positions sorted by cell */
    int *sps;        /* a mixture's species in the same order (NULL for one species) */
    int *cell_of, *cell_start, *cell_fill;
    gr_cells cells3; /* 3D: the shared cell list */
    pair_species sp; /* a mixture of species lists: g_ab(R) (obs_pair_species.c) */
} pair;

/* L^2 in 2D, L^3 in 3D */
static double box_volume(const pair *s) { return s->dim == 3 ? s->L * s->L * s->L : s->L * s->L; }

/* dens times the volume within R: the ideal-gas count of others within R (4.17) */
static double ideal_within(const pair *s, double dens, double R)
{
    return s->dim == 3 ? dens * (4.0 / 3.0) * M_PI * R * R * R : dens * M_PI * R * R;
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    const pair_params *a = params_block;
    if (setup->dim != 2 && setup->dim != 3) {
        return GR_FAIL(err, GR_EINVAL,
                       "pair: g(R) is defined for dim = 2 and 3 only (scene has dim = %d)",
                       setup->dim);
    }
    if (a->gr_bins < 1 || a->gr_bins > PAIR_MAX_BINS) {
        return GR_FAIL(err, GR_EINVAL, "pair: [analysis] gr_bins = %d outside [1, %d]", a->gr_bins,
                       PAIR_MAX_BINS);
    }
    if (!(a->gr_rmax > 0.0) || !isfinite(a->gr_rmax)) {
        return GR_FAIL(err, GR_EINVAL,
                       "pair: [analysis] gr_rmax = %g must be a finite number > 0 (diameters)",
                       a->gr_rmax);
    }
    if (!(setup->radius > 0.0) || !isfinite(setup->radius) || !(setup->L > 0.0) ||
        !isfinite(setup->L)) {
        return GR_FAIL(err, GR_EINVAL, "pair: needs radius > 0 and L > 0 (radius = %g, L = %g)",
                       setup->radius, setup->L);
    }
    if (setup->N < 2) {
        return GR_FAIL(err, GR_EINVAL, "pair: needs N >= 2 particles (N = %d)", setup->N);
    }
    pair *s = state;
    s->dim = setup->dim;
    gr_cells_own(s, &s->cells3);
    s->nbins = a->gr_bins;
    s->d = gr_obs_collision_diameter(setup); /* 2 radius; a mixture's mean over random pairs */
    s->mixture = setup->sizes;
    s->L = setup->L;
    s->N = setup->N;
    s->R_max = a->gr_rmax * s->d;
    if (s->R_max > 0.5 * s->L) {
        s->R_max = 0.5 * s->L; /* beyond L/2 a minimum-image shell is cut by the box */
        s->clamped = true;
    }
    s->width = s->R_max / s->nbins;
    s->inv_width = s->nbins / s->R_max;
    size_t nb = (size_t)s->nbins;
    s->area = gr_obs_calloc(s, nb, sizeof(double));
    s->g_blk = gr_obs_calloc(s, nb, sizeof(gr_blocking));
    s->c_blk = gr_obs_calloc(s, nb, sizeof(gr_blocking));
    s->frame_count = gr_obs_calloc(s, nb, sizeof(int64_t));
    s->c_frame = gr_obs_calloc(s, nb, sizeof(double));
    s->total = gr_obs_calloc(s, nb, sizeof(double));
    s->batch = gr_obs_calloc(s, nb * N_BATCH, sizeof(double));
    /* the cell list, allocated at the first frame */
    void *cells[] = {&s->xs, &s->ys, &s->sps, &s->cell_of, &s->cell_start, &s->cell_fill};
    for (size_t k = 0; k < sizeof cells / sizeof cells[0]; k++) {
        gr_obs_own_pointer(s, cells[k]);
    }
    if (!s->area || !s->g_blk || !s->c_blk || !s->frame_count || !s->c_frame || !s->total ||
        !s->batch) {
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory for %d bins", s->nbins);
    }
    for (int b = 0; b < s->nbins; b++) {
        double lo = b * s->width, hi = (b + 1) * s->width;
        s->area[b] = s->dim == 3 ? (4.0 / 3.0) * M_PI * (hi * hi * hi - lo * lo * lo)
                                 : M_PI * (hi * hi - lo * lo);
    }
    s->tail_from = (int)floor(TAIL_FROM_FRAC * s->nbins);
    s->batch_len = 1;
    return pair_species_init(s, &s->sp, setup, s->nbins, s->width, box_volume(s), err);
}

/* Cells of side L/M >= R_max / CELL_DIV (with a margin against rounding in the cell index), at
 * most about one per particle. Along an axis with fewer than 2 CELL_DIV + 1 cells the stencil
 * would alias: then every cell of that axis is a neighbour, each once. */
static int build_cells(pair *s, gr_error *err)
{
    double side_min = (s->R_max + 1e-10 * s->L) / CELL_DIV;
    double m = floor(s->L / side_min);
    int cap = (int)ceil(sqrt((double)s->N)) + 1;
    s->M = m < 1.0 ? 1 : (m > cap ? cap : (int)m);
    if (s->M >= 2 * CELL_DIV + 1) {
        s->nox = 2 * CELL_DIV + 1;
        for (int k = 0; k < s->nox; k++) {
            s->off[k] = k - CELL_DIV;
        }
    } else {
        s->nox = s->M;
        for (int k = 0; k < s->nox; k++) {
            s->off[k] = k;
        }
    }
    s->noy = s->nox;
    size_t n = (size_t)s->N, nc = (size_t)s->M * (size_t)s->M;
    s->xs = malloc(sizeof(double) * n);
    s->ys = malloc(sizeof(double) * n);
    s->cell_of = malloc(sizeof(int) * n);
    s->cell_start = malloc(sizeof(int) * (nc + 1));
    s->cell_fill = malloc(sizeof(int) * nc);
    s->sps = s->sp.ns ? malloc(sizeof(int) * n) : NULL;
    if (!s->xs || !s->ys || !s->cell_of || !s->cell_start || !s->cell_fill ||
        (s->sp.ns && !s->sps)) {
        free(s->xs);
        free(s->ys);
        free(s->sps);
        free(s->cell_of);
        free(s->cell_start);
        free(s->cell_fill);
        s->xs = s->ys = NULL;
        s->sps = s->cell_of = s->cell_start = s->cell_fill = NULL;
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory for the cell list of %d particles",
                       s->N);
    }
    return GR_OK;
}

static inline double wrap(double x, double L)
{
    if (x >= 0.0 && x < L) {
        return x;
    }
    x = fmod(x, L);
    if (x < 0.0) {
        x += L;
    }
    return x < L ? x : 0.0; /* x + L may round up to L */
}

static inline double min_image(double dx, double L)
{
    if (dx > 0.5 * L) {
        return dx - L;
    }
    if (dx < -0.5 * L) {
        return dx + L;
    }
    return dx;
}

/* All pairs of cell a (particles [a0, a1)) with cell b (particles [b0, b1)), or within a when
 * same. Unaliased stencil: cell b's image next to a is b shifted by (sx, sy) (0 or +-L), which is
 * the minimum image for every pair closer than R_max; aliased: minimum image per pair. A mixture
 * (s->sps) counts each pair into its kind's histogram, count[kind * nbins + bin]. */
static void count_cells(const pair *s, int64_t *count, int a0, int a1, int b0, int b1, bool same,
                        double sx, double sy, bool aliased)
{
    const double L = s->L, r2max = s->R_max * s->R_max, inv = s->inv_width;
    const int last = s->nbins - 1;
    const double *xs = s->xs, *ys = s->ys;
    const int *sps = s->sps;
    for (int i = a0; i < a1; i++) {
        double xi = xs[i] - sx, yi = ys[i] - sy;
        for (int j = same ? i + 1 : b0; j < b1; j++) {
            double dx = xs[j] - xi, dy = ys[j] - yi;
            if (aliased) {
                dx = min_image(dx, L);
                dy = min_image(dy, L);
            }
            double r2 = dx * dx + dy * dy;
            if (r2 < r2max) {
                int b = (int)(sqrt(r2) * inv);
                b = b < last ? b : last;
                count[sps ? pair_species_kind(&s->sp, sps[i], sps[j]) * s->nbins + b : b]++;
            }
        }
    }
}

static void batch_add(pair *s, const double *c)
{
    /* streaming batch means: at most N_BATCH batches; when all are full, merge neighbours */
    if (s->n_full == N_BATCH) {
        size_t nb = (size_t)s->nbins;
        for (int k = 0; k < N_BATCH / 2; k++) {
            double *to = s->batch + (size_t)k * nb, *a = s->batch + (size_t)(2 * k) * nb,
                   *b = a + nb;
            for (size_t q = 0; q < nb; q++) {
                to[q] = a[q] + b[q];
            }
        }
        memset(s->batch + (size_t)(N_BATCH / 2) * nb, 0, sizeof(double) * nb * (N_BATCH / 2));
        s->n_full = N_BATCH / 2;
        s->batch_len *= 2;
    }
    double *cur = s->batch + (size_t)s->n_full * (size_t)s->nbins;
    for (int b = 0; b < s->nbins; b++) {
        cur[b] += c[b];
    }
    if (++s->batch_fill == s->batch_len) {
        s->n_full++;
        s->batch_fill = 0;
    }
}

static void count_3d(int i, int j, const double dr[3], double r2, void *user)
{
    (void)dr;
    pair *s = user;
    int b = (int)(sqrt(r2) * s->inv_width);
    b = b < s->nbins - 1 ? b : s->nbins - 1;
    s->frame_count[b]++;
    if (s->sp.ns) {
        int k = pair_species_kind(&s->sp, s->sp.species[i], s->sp.species[j]);
        s->sp.frame_count[(size_t)k * (size_t)s->nbins + (size_t)b]++;
    }
}

static void frame_done(pair *s);

static int sample_3d(pair *s, const gr_particles *p, gr_error *err)
{
    for (int i = 0; i < p->n; i++) {
        if (!isfinite(p->x[i]) || !isfinite(p->y[i]) || !isfinite(p->z[i])) {
            return GR_FAIL(err, GR_EINVAL, "pair: particle %d has a non-finite position", i);
        }
    }
    memset(s->frame_count, 0, sizeof(int64_t) * (size_t)s->nbins);
    int rc = gr_cells_pairs(&s->cells3, p, s->R_max, count_3d, s, err);
    if (rc) {
        return rc;
    }
    frame_done(s);
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    pair *s = state;
    if (p->dim != s->dim || !p->y || (p->dim == 3 && !p->z)) {
        return GR_FAIL(err, GR_EINVAL, "pair: frame is %dD, the scene %dD", p->dim, s->dim);
    }
    if (p->n != s->N || !(fabs(p->L - s->L) <= 1e-9 * s->L)) {
        return GR_FAIL(err, GR_EINVAL,
                       "pair: frame has N = %d, L = %.10g but the scene has N = %d, L = %.10g",
                       p->n, p->L, s->N, s->L);
    }
    int rc = pair_species_begin(&s->sp, p, err);
    if (rc) {
        return rc;
    }
    if (s->dim == 3) {
        return sample_3d(s, p, err);
    }
    if (!s->xs) {
        rc = build_cells(s, err);
        if (rc) {
            return rc;
        }
    }
    const int n = s->N, M = s->M, nc = M * M;
    const double L = s->L, cell_scale = M / L;
    /* wrap, assign cells, counting sort */
    memset(s->cell_fill, 0, sizeof(int) * (size_t)nc);
    for (int i = 0; i < n; i++) {
        if (!isfinite(p->x[i]) || !isfinite(p->y[i])) {
            return GR_FAIL(err, GR_EINVAL, "pair: particle %d has a non-finite position", i);
        }
        double x = wrap(p->x[i], L), y = wrap(p->y[i], L);
        int cx = (int)(x * cell_scale), cy = (int)(y * cell_scale);
        cx = cx < M ? cx : M - 1;
        cy = cy < M ? cy : M - 1;
        s->cell_of[i] = cy * M + cx;
        s->cell_fill[cy * M + cx]++;
    }
    s->cell_start[0] = 0;
    for (int c = 0; c < nc; c++) {
        s->cell_start[c + 1] = s->cell_start[c] + s->cell_fill[c];
        s->cell_fill[c] = s->cell_start[c];
    }
    for (int i = 0; i < n; i++) {
        int k = s->cell_fill[s->cell_of[i]]++;
        s->xs[k] = wrap(p->x[i], L);
        s->ys[k] = wrap(p->y[i], L);
        if (s->sps) {
            s->sps[k] = s->sp.species[i];
        }
    }
    /* every unordered pair of neighbouring cells once (cell b > cell a), and each cell with itself;
     * rows of cells shared by the threads, each counting into its own histogram (integer counts:
     * the sum does not depend on the thread count) */
    memset(s->frame_count, 0, sizeof(int64_t) * (size_t)s->nbins);
    const bool aliased = M < 2 * CELL_DIV + 1;
    bool oom = false;
    const int T = n >= 4096 ? gr_get_threads() : 1;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        const size_t kinds = s->sps ? (size_t)s->sp.nk : 1; /* a mixture: per kind */
        int64_t *count = calloc(kinds * (size_t)s->nbins, sizeof(int64_t));
#pragma omp for schedule(dynamic, 1)
        for (int cy = 0; cy < M; cy++) {
            if (!count) {
                continue;
            }
            for (int cx = 0; cx < M; cx++) {
                int a = cy * M + cx;
                int a0 = s->cell_start[a], a1 = s->cell_start[a + 1];
                if (a0 == a1) {
                    continue;
                }
                for (int oy = 0; oy < s->noy; oy++) {
                    int yr = cy + s->off[oy], by = (yr % M + M) % M;
                    double sy = aliased ? 0.0 : (yr < 0 ? -L : (yr >= M ? L : 0.0));
                    for (int ox = 0; ox < s->nox; ox++) {
                        int xr = cx + s->off[ox], bx = (xr % M + M) % M;
                        double sx = aliased ? 0.0 : (xr < 0 ? -L : (xr >= M ? L : 0.0));
                        int b = by * M + bx;
                        if (b < a) {
                            continue;
                        }
                        count_cells(s, count, a0, a1, s->cell_start[b], s->cell_start[b + 1],
                                    b == a, sx, sy, aliased);
                    }
                }
            }
        }
#pragma omp critical(gr_pair_count)
        {
            if (count) {
                for (size_t q = 0; q < kinds * (size_t)s->nbins; q++) {
                    s->frame_count[q % (size_t)s->nbins] += count[q];
                    if (s->sps) {
                        s->sp.frame_count[q] += count[q];
                    }
                }
            } else {
                oom = true;
            }
        }
        free(count);
    }
    if (oom) {
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory for the g(R) histogram");
    }
    frame_done(s);
    return GR_OK;
}

/* The frame's counts s->frame_count into per-frame g_b (4.10), C(R_hi) (4.15) and the tail mean of
 * g. */
static void frame_done(pair *s)
{
    const int n = s->N;
    /* ideal-gas pairs per area (volume in 3D) */
    const double norm = 0.5 * (double)n * (double)(n - 1) / box_volume(s);
    double cum = 0.0, tail_pairs = 0.0, tail_area = 0.0;
    for (int b = 0; b < s->nbins; b++) {
        double cnt = (double)s->frame_count[b];
        s->total[b] += cnt;
        cum += cnt;
        s->c_frame[b] = 2.0 * cum / n;
        gr_blocking_add(&s->g_blk[b], cnt / (norm * s->area[b]));
        gr_blocking_add(&s->c_blk[b], s->c_frame[b]);
        if (b >= s->tail_from) {
            tail_pairs += cnt;
            tail_area += s->area[b];
        }
    }
    gr_blocking_add(&s->tail_blk, tail_pairs / (norm * tail_area));
    pair_species_end(&s->sp, s->area);
    batch_add(s, s->c_frame);
    s->frames++;
}

/* Error of a per-frame average: blocking plateau, or (fewer than 16 frames) sqrt(count). */
static double frame_error(const pair *s, const gr_blocking *blk, double count, double scale,
                          bool *ok)
{
    double e = gr_blocking_stderr(blk, NULL, NULL);
    if (isfinite(e)) {
        return e;
    }
    *ok = false;
    return sqrt(count) * scale / (double)s->frames;
}

/* Power-law fit of n(R_hi) = A'' R^D_f (4.17) over the window [lo, hi); returns points used. */
static int fit_window(const pair *s, const double *n_of, const double *sigma, int lo, int hi,
                      gr_fit *fit, double *x, double *y, double *e, gr_error *err)
{
    int m = 0;
    for (int b = lo; b < hi; b++) {
        if (n_of[b] > 0.0 && sigma[b] > 0.0) {
            x[m] = (b + 1) * s->width;
            y[m] = n_of[b];
            e[m] = sigma[b];
            m++;
        }
    }
    if (m < 3) {
        return m;
    }
    return gr_fit_power_law(x, y, e, m, fit, err) == GR_OK ? m : -1;
}

/* ------------------------------------------------------------------------------------------
 * Fitting: everything finish reports, computed from the accumulators, with no output. */

typedef struct pair_result {
    double *g, *ge, *c, *n, *ne; /* per bin: g(R) and its error, C(R_hi), n(R_hi) and its error */
    bool blocking;               /* errors from block averaging (else sqrt(counts)) */
    int unconverged;             /* bins whose g blocking has not converged */
    int peak;                    /* bin of the first peak */
    double tail, tail_error;     /* g_tail over bins tail_from .. nbins - 1 */
    int lo, hi;                  /* the D_f window: bins lo .. hi - 1 */
    int used;                    /* points of the D_f fit (< 3: no fit; < 0: the fit failed) */
    char fit_failure[sizeof((gr_error *)0)->message];
    gr_fit fit;       /* n(R) = A R^D_f (4.17) */
    double jackknife; /* jackknife error of D_f over batches of frames (NAN: none) */
} pair_result;

static void result_free(pair_result *r)
{
    free(r->g);
    r->g = NULL;
}

/* The error of D_f: leave one full batch of frames out and refit, B >= 8 batches (NAN otherwise). */
static double jackknife(const pair *s, const pair_result *r, double *fx, double *fy, double *fe)
{
    const int nb = s->nbins, B = s->n_full;
    const double dens = (s->N - 1) / box_volume(s);
    if (B < 8) {
        return NAN;
    }
    double jk = NAN;
    double *nj = malloc(sizeof(double) * (size_t)nb), *dj = malloc(sizeof(double) * (size_t)B);
    bool ok = nj && dj;
    for (int k = 0; ok && k < B; k++) {
        double frames_k = (double)(B - 1) * (double)s->batch_len;
        for (int b = 0; b < nb; b++) {
            double sum = 0.0;
            for (int q = 0; q < B; q++) {
                sum += q == k ? 0.0 : s->batch[(size_t)q * (size_t)nb + (size_t)b];
            }
            double hr = (b + 1) * s->width;
            nj[b] = sum / frames_k - ideal_within(s, dens, hr);
        }
        gr_fit fk;
        gr_error kerr = {0};
        ok = fit_window(s, nj, r->ne, r->lo, r->hi, &fk, fx, fy, fe, &kerr) >= 3;
        dj[k] = ok ? fk.p[1] : 0.0;
    }
    if (ok) {
        double mean = 0.0, var = 0.0;
        for (int k = 0; k < B; k++) {
            mean += dj[k] / B;
        }
        for (int k = 0; k < B; k++) {
            var += (dj[k] - mean) * (dj[k] - mean);
        }
        jk = sqrt(var * (B - 1) / B);
    }
    free(nj);
    free(dj);
    return jk;
}

/* g, C, n with errors per bin, the first peak, g_tail and the D_f fit (s->frames > 0). */
static int compute(const pair *s, pair_result *r, gr_error *err)
{
    const int nb = s->nbins, N = s->N;
    const double dens = (N - 1) / box_volume(s); /* density of the others, n of 4.15-4.17 */
    const double norm = 0.5 * (double)N * (double)(N - 1) / box_volume(s);
    memset(r, 0, sizeof *r);
    r->g = malloc(sizeof(double) * (size_t)nb * 8);
    if (!r->g) {
        return GR_FAIL(err, GR_ENOMEM, "pair: out of memory");
    }
    r->ge = r->g + nb;
    r->n = r->g + 2 * nb;
    r->ne = r->g + 3 * nb;
    r->c = r->g + 4 * nb;
    double *fx = r->g + 5 * nb, *fy = r->g + 6 * nb, *fe = r->g + 7 * nb; /* fit workspace */
    r->blocking = true;
    double cum = 0.0;
    for (int b = 0; b < nb; b++) {
        double hi = (b + 1) * s->width;
        cum += s->total[b];
        r->g[b] = gr_blocking_mean(&s->g_blk[b]);
        r->ge[b] =
            frame_error(s, &s->g_blk[b], s->total[b], 1.0 / (norm * s->area[b]), &r->blocking);
        r->c[b] = gr_blocking_mean(&s->c_blk[b]);
        r->ne[b] = frame_error(s, &s->c_blk[b], cum, 2.0 / N, &r->blocking);
        r->n[b] = r->c[b] - ideal_within(s, dens, hi);
        int conv = 1;
        if (s->frames >= 16) {
            gr_blocking_stderr(&s->g_blk[b], NULL, &conv);
            r->unconverged += !conv && s->total[b] > 0.0;
        }
    }

    /* first peak: the largest g among bins centred below PEAK_MAX_D d (the contact shell) */
    int peak_end = (int)ceil(PEAK_MAX_D * s->d / s->width - 0.5);   /* bins centred below 1.5 d */
    peak_end = peak_end < 1 ? nb : (peak_end < nb ? peak_end : nb); /* none: all bins */
    for (int b = 1; b < peak_end; b++) {
        r->peak = r->g[b] > r->g[r->peak] ? b : r->peak;
    }

    /* g_tail: mean g over R_max/2 <= R < R_max (Fig. 4.7's constant fit) */
    double tail_total = 0.0, tail_area = 0.0;
    for (int b = s->tail_from; b < nb; b++) {
        tail_total += s->total[b];
        tail_area += s->area[b];
    }
    bool tail_blocking = r->blocking;
    r->tail = gr_blocking_mean(&s->tail_blk);
    r->tail_error =
        frame_error(s, &s->tail_blk, tail_total, 1.0 / (norm * tail_area), &tail_blocking);

    /* D_f from n(R) ~ A'' R^D_f (4.17) over max(2 d, R_max / 4) <= R_hi <= R_max / 2; bin b's
     * upper edge is (b + 1) w, so the window is the bins lo .. hi - 1 */
    double fit_from = fmax(FIT_LO_D * s->d, FIT_LO_FRAC * s->R_max);
    r->lo = (int)ceil(fit_from / s->width - 1.0 - 1e-9);
    r->hi = (int)floor(FIT_HI_FRAC * nb + 1e-9);
    r->lo = r->lo < 0 ? 0 : r->lo;
    gr_error ferr = {0};
    r->used = r->hi - r->lo >= 3
                  ? fit_window(s, r->n, r->ne, r->lo, r->hi, &r->fit, fx, fy, fe, &ferr)
                  : 0;
    snprintf(r->fit_failure, sizeof r->fit_failure, "%s", ferr.message);
    r->jackknife = r->used >= 3 ? jackknife(s, r, fx, fy, fe) : (double)NAN;
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * Writing: the summary member, pair.csv and the plots, from a pair_result. */

static double d_f_error(const pair_result *r)
{
    return isfinite(r->jackknife) ? fmax(r->fit.err[1], r->jackknife) : r->fit.err[1];
}

static void write_summary(const pair *s, const pair_result *r, cJSON *j)
{
    cJSON_AddStringToObject(j, "errors",
                            r->blocking
                                ? "block averaging over frames"
                                : "sqrt(counts) (fewer than 16 frames for block averaging)");
    if (r->blocking) {
        cJSON_AddNumberToObject(j, "g_bins_blocking_unconverged", r->unconverged);
    }
    const int pk = r->peak;
    cJSON *jp = cJSON_AddObjectToObject(j, "first_peak");
    gr_obs_add_number(jp, "R", (pk + 0.5) * s->width);
    gr_obs_add_number(jp, "R_over_d", (pk + 0.5) * s->width / s->d);
    gr_obs_add_number(jp, "g", r->g[pk]);
    gr_obs_add_number(jp, "g_error", r->ge[pk]);
    cJSON_AddStringToObject(jp, "definition", "largest g(R) over bins centred below 1.5 d");

    cJSON *jt = cJSON_AddObjectToObject(j, "g_tail");
    gr_obs_add_number(jt, "value", r->tail);
    gr_obs_add_number(jt, "error", r->tail_error);
    gr_obs_add_number(jt, "R_from_over_d", s->tail_from * s->width / s->d);
    gr_obs_add_number(jt, "R_to_over_d", s->R_max / s->d);

    cJSON *jd = cJSON_AddObjectToObject(j, "D_f");
    gr_obs_add_number(jd, "R_from_over_d", (r->lo + 1) * s->width / s->d);
    gr_obs_add_number(jd, "R_to_over_d", r->hi * s->width / s->d);
    if (r->used >= 3) {
        const gr_fit *fit = &r->fit;
        gr_obs_add_number(jd, "value", fit->p[1]);
        gr_obs_add_number(jd, "error", d_f_error(r));
        gr_obs_add_number(jd, "fit_error", fit->err[1]);
        gr_obs_add_number(jd, "jackknife_error", r->jackknife);
        cJSON_AddNumberToObject(jd, "jackknife_batches", isfinite(r->jackknife) ? s->n_full : 0);
        gr_obs_add_number(jd, "A", fit->p[0]);
        gr_obs_add_number(jd, "A_error", fit->err[0]);
        gr_obs_add_number(jd, "A_over_d",
                          fit->p[0] * pow(s->d, fit->p[1])); /* n = A_over_d (R/d)^D_f */
        gr_obs_add_number(jd, "chi2_red", fit->chi2_red);
        cJSON_AddNumberToObject(jd, "points", r->used);
        cJSON_AddNumberToObject(jd, "points_left_out", r->hi - r->lo - r->used);
    } else {
        cJSON_AddNullToObject(jd, "value");
        cJSON_AddNullToObject(jd, "error");
        char note[900];
        snprintf(note, sizeof note,
                 "no fit: %d bins of the window have n(R) > 0 with an error (3 needed)%s%s",
                 r->used < 0 ? 0 : r->used, r->used < 0 ? "; " : "",
                 r->used < 0 ? r->fit_failure : "");
        cJSON_AddStringToObject(jd, "note", note);
    }
    cJSON_AddStringToObject(
        jd, "definition",
        "n(R) = C(R) - n pi R^2 ~ A R^D_f (4.17), weighted log-log fit at bin upper edges R_hi "
        "in [max(2 d, R_max/4), R_max/2], bins with n <= 0 left out; error = max(fit, jackknife "
        "over batches of frames)");
}

static void write_plots(const pair *s, const pair_result *r, const gr_output *out)
{
    char body[1600];
    snprintf(body, sizeof body,
             "set xlabel 'R / d'\nset ylabel 'g(R)'\n"
             "set title \"Pair correlation function, %lld frames\\n{/*0.75 eq. (4.10)}\"\n"
             "set key top right\n"
             "set bars 0\n"
             "plot 'pair.csv' skip 1 using 2:3:4 with yerrorlines lt 1 pt 7 ps 0.3 title 'g(R)', "
             "1 with lines dt 2 lt 5 title 'ideal gas'",
             (long long)s->frames);
    gr_obs_plot(out, "pair_g.png", body);
    const int nb = s->nbins, every = nb > 50 ? nb / 50 : 1; /* error bars on about 50 points */
    const double from = (r->lo + 1) * s->width / s->d, to = r->hi * s->width / s->d;
    if (r->used >= 3) {
        char legend[120];
        gr_plot_legend_value("fit A R^{D_f}, D_f", r->fit.p[1], d_f_error(r), legend,
                             sizeof legend);
        snprintf(body, sizeof body,
                 "set logscale xy\nset bars 0\nset xrange [1:%.10g]\nset xlabel 'R / d'\n"
                 "set ylabel 'n(R) = C(R) - n pi R^2'\n"
                 "set title \"Excess neighbours within R\\n{/*0.75 eq. (4.17); fit over %.3g d <= "
                 "R <= %.3g d}\"\n"
                 "set key top left\n"
                 "plot 'pair.csv' skip 1 using ($9/%.10g):($6 > 0 ? $6 : 1/0) with lines lt 1 "
                 "title 'n(R)', '' skip 1 every %d using ($9/%.10g):($6 > 0 ? $6 : 1/0):7 with "
                 "yerrorbars lt 1 pt 7 "
                 "ps 0.4 notitle, [%.10g:%.10g] %.10g * x**%.10g with lines lw 3 lt 2 title '%s'",
                 s->R_max / s->d, from, to, s->d, every, s->d, from, to,
                 r->fit.p[0] * pow(s->d, r->fit.p[1]), r->fit.p[1], legend);
    } else {
        snprintf(body, sizeof body,
                 "set logscale xy\nset bars 0\nset xrange [1:%.10g]\nset xlabel 'R / d'\n"
                 "set ylabel 'n(R) = C(R) - n pi R^2'\n"
                 "set title \"Excess neighbours within R\\n{/*0.75 eq. (4.17); too few bins for "
                 "the power-law fit}\"\n"
                 "plot 'pair.csv' skip 1 using ($9/%.10g):($6 > 0 ? $6 : 1/0) with lines lt 1 "
                 "title 'n(R)', '' skip 1 every %d using ($9/%.10g):($6 > 0 ? $6 : 1/0):7 with "
                 "yerrorbars lt 1 pt 7 "
                 "ps 0.4 notitle",
                 s->R_max / s->d, s->d, every, s->d);
    }
    gr_obs_plot(out, "pair_n.png", body);
}

/* pair.csv: one row per bin from the result (none before the first frame) */
typedef struct pair_rows_ctx {
    const pair *s;
    const pair_result *r;
} pair_rows_ctx;

static const char pair_csv_what[] =
    "pair correlation g(R) (4.10, normalised by the ideal-gas pair count N(N-1)/2 per area "
    "2 pi R dR/L^2, shell area exact per bin) at the bin centre R; C = mean number of others "
    "within R_hi (4.15) and n = C - (N-1)/L^2 pi R_hi^2 (4.17), cumulative up to the bin's "
    "upper edge R_hi; pairs = total pair count in the bin over all frames; errors from block "
    "averaging over frames (sqrt(count) with fewer than 16 frames); R in m, d = 2 radius";
static const char pair_csv_what_3d[] =
    "pair correlation g(R) (3D: normalised by the ideal-gas pair count N(N-1)/2 per volume "
    "4 pi R^2 dR/L^3, shell volume (4/3) pi (R_hi^3 - R_lo^3) exact per bin) at the bin centre R; "
    "C = mean number of others within R_hi (4.15) and n = C - (N-1)/L^3 (4/3) pi R_hi^3 (4.17), "
    "cumulative up to the bin's upper edge R_hi; pairs = total pair count in the bin over all "
    "frames; errors from block averaging over frames (sqrt(count) with fewer than 16 frames); R in "
    "m, d = 2 radius";

const char gr_obs_pair_columns[] = "R [m],R_over_d [1],g [1],g_error [1],C [1],n [1],n_error "
                                   "[1],R_lo [m],R_hi [m],pairs [1]";

static void pair_rows(FILE *f, const void *ctx)
{
    const pair_rows_ctx *c = ctx;
    const pair *s = c->s;
    const pair_result *r = c->r;
    for (int b = 0; b < s->nbins && s->frames > 0; b++) {
        double lo = b * s->width, hi = (b + 1) * s->width, R = 0.5 * (lo + hi);
        fprintf(f, "%.10g,%.10g,%.10g,%.6g,%.10g,%.10g,%.6g,%.10g,%.10g,%.0f\n", R, R / s->d,
                r->g[b], r->ge[b], r->c[b], r->n[b], r->ne[b], lo, hi, s->total[b]);
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    pair *s = state;
    cJSON *j = cJSON_AddObjectToObject(out->summary, "pair");
    cJSON_AddStringToObject(j, "file", "pair.csv");
    cJSON_AddNumberToObject(j, "frames", (double)s->frames);
    cJSON_AddNumberToObject(j, "bins", s->nbins);
    if (s->mixture) {
        gr_obs_note_diameter(j, s->d, s->dim);
    } else {
        cJSON_AddNumberToObject(j, "d", s->d);
    }
    cJSON_AddNumberToObject(j, "R_max", s->R_max);
    cJSON_AddNumberToObject(j, "R_max_over_d", s->R_max / s->d);
    cJSON_AddBoolToObject(j, "R_max_clamped_to_half_box", s->clamped);
    cJSON_AddNumberToObject(j, "bin_width_over_d", s->width / s->d);
    pair_result r = {0};
    pair_rows_ctx rows = {.s = s, .r = &r};
    gr_obs_table t = {.name = "pair.csv",
                      .what = s->dim == 3 ? pair_csv_what_3d : pair_csv_what,
                      .columns = gr_obs_pair_columns,
                      .rows = pair_rows,
                      .ctx = &rows};
    if (s->frames == 0) {
        cJSON_AddStringToObject(j, "note", "no frames sampled");
        return gr_obs_table_write(out, &t, err);
    }
    int rc = compute(s, &r, err);
    if (rc) {
        return rc;
    }
    write_summary(s, &r, j);
    rc = gr_obs_table_write(out, &t, err);
    if (!rc) {
        rc = pair_species_finish(&s->sp, out, j, s->d, s->area, err);
    }
    if (!rc && out->plots) {
        write_plots(s, &r, out);
    }
    result_free(&r);
    return rc;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    pair *s = state;
    const size_t nb = (size_t)s->nbins;
    gr_blob_io_check(io, "gr_bins", s->nbins);
    for (size_t b = 0; b < nb; b++) {
        gr_obs_io_blockings(io, &s->g_blk[b], 1);
        gr_obs_io_blockings(io, &s->c_blk[b], 1);
    }
    gr_obs_io_blockings(io, &s->tail_blk, 1);
    gr_blob_io_f64s(io, s->total, (int64_t)nb);
    gr_blob_io_i64(io, &s->frames);
    gr_blob_io_f64s(io, s->batch, (int64_t)(nb * N_BATCH));
    gr_blob_io_i64(io, &s->batch_len);
    gr_blob_io_i64(io, &s->batch_fill);
    int64_t n_full = s->n_full;
    gr_blob_io_i64(io, &n_full);
    if (gr_blob_io_loading(io) &&
        (n_full < 0 || n_full > N_BATCH || s->batch_len < 1 || s->batch_fill < 0 ||
         s->batch_fill >= s->batch_len || (n_full == N_BATCH && s->batch_fill != 0))) {
        gr_blob_io_fail(io, "batch counters (%lld full, %lld of %lld) are inconsistent",
                        (long long)n_full, (long long)s->batch_fill, (long long)s->batch_len);
    }
    s->n_full = (int)n_full;
    pair_species_io(&s->sp, io);
    return GR_OK;
}

const gr_observable_type gr_obs_pair = {
    .name = "pair",
    .summary = "pair correlation g(R) (4.10), neighbours within R, C(R) (4.15), excess n(R) = C - "
               "n pi R^2 and "
               "D_f from n ~ R^D_f (4.17); 2D and 3D",
    .dims = 6, /* 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(pair_params),
    .state_size = sizeof(pair),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
