/* The Single Particle Model (thesis sec. 5.2-5.3): exact free flight of the random-acceleration
 * process inside a disc or interval, Q(v, l) (sec. 5.3.1), the full SPM P(v) with l drawn from
 * P_l(l) (sec. 5.2.3, 4.25), the asymptotic prediction (5.27-5.31), and the comparison with the
 * Random Force Model's P(v) from a run folder. See include/granule/spm.h and docs/theory-spm.md.
 *
 * Units inside a walk: length l, velocity u_l = (2 D l / M^2)^(1/3), time t_l = l / u_l. Then
 * the velocity diffuses with unit strength (<dv^2> = 2 D t / M^2 becomes <dw^2> = t / t_l) and the
 * boundary is the unit circle (or +-1), whatever l, M and D are.
 *
 * Random numbers (granule/noise.h, Philox): the free-flight variates of step k of walk `key` are
 * gr_noise_normals(seed, STREAM_G1 / STREAM_G2, key, k, ...), components = spatial components; the
 * bridge midpoints use gr_noise_normal1(seed, STREAM_BRIDGE, key, 2 n + c, 0/1) for the n-th
 * midpoint of the walk; the free path of walk `key` is gr_noise_uniform(seed, STREAM_L, key, 0).
 * key = (radius index << 40) + walk index. Nothing depends on batch sizes or on the order of work. */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_gamma.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/noise.h"
#include "granule/spm.h"
#include "io/files.h"

/* Streams of their own, so the SPM never shares variates with a run of the same seed. */
enum {
    STREAM_G1 = 0x53504d01u, /* velocity increments g1 */
    STREAM_G2 = 0x53504d02u, /* position remainders g2 */
    STREAM_BRIDGE = 0x53504d03u,
    STREAM_L = 0x53504d04u
};

#define BLOCK 128    /* steps of variates drawn at once */
#define MAX_TIME 1e4 /* a walk longer than this (in t_l) is reported as an error */

void gr_spm_settings_default(gr_spm_settings *s)
{
    memset(s, 0, sizeof *s);
    s->dim = 2;
    s->mass = GR_SPM_MASS_DEFAULT;
    s->D = GR_SPM_D_DEFAULT;
    s->step = 3e-3;
    s->dt = 0.0;
    s->refine = 10;
    s->walks = 20000;
    s->batches = 20;
    s->seed = 1;
    s->tilt = 1.0;
}

int gr_spm_settings_check(const gr_spm_settings *s, gr_error *err)
{
    if (s->dim != 1 && s->dim != 2) {
        return GR_FAIL(err, GR_EINVAL, "spm: dim must be 1 or 2, got %d", s->dim);
    }
    if (!(s->mass > 0.0) || !isfinite(s->mass)) {
        return GR_FAIL(err, GR_EINVAL, "spm: mass must be > 0 (kg), got %g", s->mass);
    }
    if (!(s->D > 0.0) || !isfinite(s->D)) {
        return GR_FAIL(err, GR_EINVAL, "spm: D must be > 0 (N^2 s), got %g", s->D);
    }
    if (!(s->step > 0.0 && s->step <= 0.1)) {
        return GR_FAIL(err, GR_EINVAL, "spm: step must lie in (0, 0.1] (units of t_l), got %g",
                       s->step);
    }
    if (!(s->dt >= 0.0) || !isfinite(s->dt)) {
        return GR_FAIL(err, GR_EINVAL, "spm: dt must be >= 0 s (0: use step), got %g", s->dt);
    }
    if (s->refine < 0 || s->refine > 30) {
        return GR_FAIL(err, GR_EINVAL, "spm: refine must lie in 0..30, got %d", s->refine);
    }
    if (s->walks < 2 || s->walks > ((int64_t)1 << 40)) {
        return GR_FAIL(err, GR_EINVAL, "spm: walks must lie in 2..2^40, got %lld",
                       (long long)s->walks);
    }
    if (s->batches < 2 || s->batches > s->walks) {
        return GR_FAIL(err, GR_EINVAL, "spm: batches must lie in 2..walks (%lld), got %d",
                       (long long)s->walks, s->batches);
    }
    if (!(s->tilt >= 1.0 && s->tilt <= 100.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: tilt must lie in [1, 100], got %g", s->tilt);
    }
    return GR_OK;
}

double gr_spm_velocity_scale(const gr_spm_settings *s, double l)
{
    return cbrt(2.0 * s->D * l / (s->mass * s->mass));
}

double gr_spm_time_scale(const gr_spm_settings *s, double l)
{
    return l / gr_spm_velocity_scale(s, l);
}

double gr_spm_B(const gr_spm_settings *s, double b)
{
    return b * pow(s->mass * s->mass / (2.0 * s->D), 2.0 / 3.0);
}

void gr_spm_free_flight(double x0, double v0, double tau, double sigma, double g1, double g2,
                        double *x1, double *v1)
{
    /* physics notes sec. 1.2: dv = sqrt(2 D tau)/M g1, dx = v0 tau + tau/2 dv + sqrt(D tau^3/6)/M g2,
     * with sigma = sqrt(2 D)/M: sqrt(D tau^3 / 6)/M = sigma sqrt(tau^3 / 12) */
    double dv = sigma * sqrt(tau) * g1;
    *x1 = x0 + v0 * tau + 0.5 * tau * dv + sigma * sqrt(tau * tau * tau / 12.0) * g2;
    *v1 = v0 + dv;
}

void gr_spm_bridge_midpoint(double x0, double v0, double x1, double v1, double h, double sigma,
                            double g1, double g2, double *xm, double *vm)
{
    /* Conditioning the two half-intervals' increments (each with covariance
     * sigma^2 [[h^3/3, h^2/2], [h^2/2, h]]) on their sum gives the cubic Hermite interpolant as
     * mean and the diagonal covariance sigma^2 diag(h^3/24, h/8). */
    *xm = 0.5 * (x0 + x1) + 0.25 * h * (v0 - v1) + sigma * sqrt(h * h * h / 24.0) * g2;
    *vm = 0.75 * (x1 - x0) / h - 0.25 * (v0 + v1) + sigma * sqrt(h / 8.0) * g1;
}

/* ------------------------------------------------------------------------------------------- */

int gr_spm_dist_init(gr_spm_dist *d, int nbatches, int nbins, double vmax, gr_error *err)
{
    memset(d, 0, sizeof *d);
    if (nbatches < 2) {
        return GR_FAIL(err, GR_EINVAL, "spm: need at least 2 batches, got %d", nbatches);
    }
    if (nbins < 2 || nbins > 100000 || !(vmax > 0.0) || !isfinite(vmax)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: need 2..100000 bins and a velocity range > 0, got %d bins up to %g",
                       nbins, vmax);
    }
    int rc = gr_histogram_init(&d->all, nbins, 0.0, vmax, false, err);
    if (rc) {
        return rc;
    }
    d->batch = calloc((size_t)nbatches, sizeof *d->batch);
    if (!d->batch) {
        gr_histogram_free(&d->all);
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory for %d batches", nbatches);
    }
    d->nbatches = nbatches;
    for (int b = 0; b < nbatches; b++) {
        rc = gr_histogram_init(&d->batch[b], nbins, 0.0, vmax, false, err);
        if (rc) {
            gr_spm_dist_free(d);
            return rc;
        }
    }
    return GR_OK;
}

void gr_spm_dist_free(gr_spm_dist *d)
{
    if (d->batch) {
        for (int b = 0; b < d->nbatches; b++) {
            gr_histogram_free(&d->batch[b]);
        }
    }
    free(d->batch);
    d->batch = NULL;
    gr_histogram_free(&d->all);
}

static int dist_merge(gr_spm_dist *d, gr_error *err)
{
    int nb = d->all.nbins;
    memset(d->all.count, 0, sizeof(double) * (size_t)nb);
    d->all.below = d->all.above = d->all.total = 0.0;
    for (int b = 0; b < d->nbatches; b++) {
        int rc = gr_histogram_merge(&d->all, &d->batch[b], err);
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

double gr_spm_dist_density(const gr_spm_dist *d, int i)
{
    return 0.5 * gr_histogram_density(&d->all, i);
}

double gr_spm_dist_error(const gr_spm_dist *d, int i)
{
    /* batch b's density uses its own total; the merged density is their weighted mean, and its
     * error the spread of the batch densities over sqrt(B) (batches of similar weight) */
    int B = d->nbatches;
    double mean = 0.0, m2 = 0.0;
    int used = 0;
    for (int b = 0; b < B; b++) {
        if (d->batch[b].total > 0.0) {
            double p = 0.5 * gr_histogram_density(&d->batch[b], i);
            used++;
            double delta = p - mean;
            mean += delta / used;
            m2 += delta * (p - mean);
        }
    }
    if (used < 2) {
        return (double)NAN;
    }
    return sqrt(m2 / ((double)used * (double)(used - 1)));
}

double gr_spm_dist_poisson_error(const gr_spm_dist *d, int i)
{
    return 0.5 * gr_histogram_density_error(&d->all, i);
}

/* ------------------------------------------------------------------------------------------- *
 * One walk, in the walk's own units (boundary at radius 1, unit noise strength). */

typedef struct walker {
    int dim, refine;
    uint64_t seed;
    double tau, sq_tau, sq_tau3_12; /* sampling interval and its free-flight amplitudes */
    double five_sq_tau;
    /* output of a walk */
    double *w;  /* |w| of each component at the sample times */
    double *wt; /* trapezoid weight of each entry */
    int64_t n, cap;
    double duration; /* first-passage time */
    double exit_speed2;
    int64_t steps, bridge_points;
    bool bridge_exit;
    uint32_t bridge_counter;
    uint64_t key;
} walker;

static void walker_set_tau(walker *wk, double tau)
{
    wk->tau = tau;
    wk->sq_tau = sqrt(tau);
    wk->sq_tau3_12 = sqrt(tau * tau * tau / 12.0);
    wk->five_sq_tau = 5.0 * wk->sq_tau;
}

static int walker_push(walker *wk, const double *v, double weight, gr_error *err)
{
    if (wk->n + wk->dim > wk->cap) {
        int64_t cap = wk->cap ? 2 * wk->cap : 4096;
        double *a = realloc(wk->w, sizeof(double) * (size_t)cap),
               *b = a ? realloc(wk->wt, sizeof(double) * (size_t)cap) : NULL;
        if (a) {
            wk->w = a;
        }
        if (!a || !b) {
            return GR_FAIL(err, GR_ENOMEM, "spm: out of memory for a walk of %lld samples",
                           (long long)wk->n);
        }
        wk->wt = b;
        wk->cap = cap;
    }
    for (int c = 0; c < wk->dim; c++) {
        wk->w[wk->n] = fabs(v[c]);
        wk->wt[wk->n] = weight;
        wk->n++;
    }
    return GR_OK;
}

static double norm2(const double *x, int dim)
{
    return dim == 2 ? x[0] * x[0] + x[1] * x[1] : x[0] * x[0];
}

/* Could the path between two inside points (interval H) have reached radius 1? Positions move at
 * most (H/2) max|v| from the nearer end, and the bridge velocity exceeds the larger end speed by
 * more than 5 sqrt(H) only with probability ~ exp(-50): otherwise no refinement is needed. */
static bool may_cross(const double *x0, const double *v0, const double *x1, const double *v1,
                      double H, int dim)
{
    double r = sqrt(fmax(norm2(x0, dim), norm2(x1, dim)));
    double s = sqrt(fmax(norm2(v0, dim), norm2(v1, dim)));
    return r + 0.5 * H * (s + 5.0 * sqrt(H)) >= 1.0;
}

/* may_cross for a whole sampling interval, with one square root (the hot path). */
static inline bool near_boundary(const walker *wk, double r0sq, double r1sq, const double *v0,
                                 const double *v1)
{
    double reach =
        0.5 * wk->tau * (sqrt(fmax(norm2(v0, wk->dim), norm2(v1, wk->dim))) + wk->five_sq_tau);
    double r2 = fmax(r0sq, r1sq);
    return reach >= 1.0 || r2 >= (1.0 - reach) * (1.0 - reach);
}

/* First exit in the interval (x0, v0) -> (x1, v1) of length H (both ends inside), looked for at
 * exactly sampled bridge midpoints down to `depth` more levels. Returns the exit time offset
 * (and the velocity there) or a negative number when no exit was seen. */
static double bridge_search(walker *wk, const double *x0, const double *v0, const double *x1,
                            const double *v1, double H, int depth, double *v_exit)
{
    if (depth <= 0 || !may_cross(x0, v0, x1, v1, H, wk->dim)) {
        return -1.0;
    }
    double xm[2], vm[2], h = 0.5 * H;
    uint32_t n = wk->bridge_counter++;
    wk->bridge_points++;
    for (int c = 0; c < wk->dim; c++) {
        double g1 = gr_noise_normal1(wk->seed, STREAM_BRIDGE, wk->key, 2u * n + (uint32_t)c, 0);
        double g2 = gr_noise_normal1(wk->seed, STREAM_BRIDGE, wk->key, 2u * n + (uint32_t)c, 1);
        gr_spm_bridge_midpoint(x0[c], v0[c], x1[c], v1[c], h, 1.0, g1, g2, &xm[c], &vm[c]);
    }
    if (norm2(xm, wk->dim) >= 1.0) {
        double t = bridge_search(wk, x0, v0, xm, vm, h, depth - 1, v_exit);
        if (t >= 0.0) {
            return t;
        }
        for (int c = 0; c < wk->dim; c++) {
            v_exit[c] = vm[c];
        }
        return h;
    }
    double t = bridge_search(wk, x0, v0, xm, vm, h, depth - 1, v_exit);
    if (t >= 0.0) {
        return t;
    }
    t = bridge_search(wk, xm, vm, x1, v1, h, depth - 1, v_exit);
    return t >= 0.0 ? h + t : -1.0;
}

/* Velocities are recorded at the sample times with trapezoid weights (interval [t_k, t_k+1]
 * gives 1/2 to each end; the last, partial interval s tau gives s/2 to each end), so the walk's
 * samples weigh its duration / tau in all: sampling uniformly in time with an O(tau^2) bias. */
static int walk_run(walker *wk, uint64_t key, gr_error *err)
{
    const int dim = wk->dim;
    double x[2] = {0.0, 0.0}, v[2] = {0.0, 0.0}, x1[2] = {0.0, 0.0}, v1[2] = {0.0, 0.0};
    double g1[2 * BLOCK], g2[2 * BLOCK];
    wk->n = 0;
    wk->key = key;
    wk->steps = 0;
    wk->bridge_points = 0;
    wk->bridge_counter = 0;
    wk->bridge_exit = false;
    const int64_t max_steps = (int64_t)(MAX_TIME / wk->tau) + 1;
    double pending = 0.5; /* weight owed to the current sample point by the interval before it */
    double r0sq = 0.0;    /* |x|^2 at the current sample point */
    for (int64_t k = 0;; k++) {
        if (k >= max_steps || k > (int64_t)UINT32_MAX - BLOCK) {
            return GR_FAIL(err, GR_EINVAL,
                           "spm: a walk did not reach the boundary within %g t_l (%lld steps)",
                           MAX_TIME, (long long)k);
        }
        int j = (int)(k % BLOCK);
        if (j == 0) {
            gr_noise_normals(wk->seed, STREAM_G1, key, (uint32_t)k, BLOCK, dim, g1);
            gr_noise_normals(wk->seed, STREAM_G2, key, (uint32_t)k, BLOCK, dim, g2);
        }
        for (int c = 0; c < dim; c++) {
            /* exact free flight (physics notes sec. 1.2), unit noise strength */
            double dv = wk->sq_tau * g1[j * dim + c];
            x1[c] = x[c] + v[c] * wk->tau + 0.5 * wk->tau * dv + wk->sq_tau3_12 * g2[j * dim + c];
            v1[c] = v[c] + dv;
        }
        wk->steps++;
        double r1 = norm2(x1, dim);
        double s = -1.0, ve[2] = {v1[0], v1[1]};
        if (r1 >= 1.0) {
            /* crossed between the two looks: place the exit by linear interpolation in r */
            double r0 = sqrt(r0sq);
            r1 = sqrt(r1);
            s = r1 > r0 ? (1.0 - r0) / (r1 - r0) : 1.0;
            s = fmin(fmax(s, 0.0), 1.0);
        } else if (wk->refine > 0 && near_boundary(wk, r0sq, r1, v, v1)) {
            double t = bridge_search(wk, x, v, x1, v1, wk->tau, wk->refine, ve);
            if (t >= 0.0) {
                s = t / wk->tau;
                wk->bridge_exit = true;
            }
        }
        if (s >= 0.0) {
            int rc = walker_push(wk, v, pending + 0.5 * s - 0.5, err);
            if (!rc) {
                rc = walker_push(wk, ve, 0.5 * s, err);
            }
            if (rc) {
                return rc;
            }
            wk->duration = ((double)k + s) * wk->tau;
            wk->exit_speed2 = norm2(ve, dim);
            return GR_OK;
        }
        int rc = walker_push(wk, v, pending, err);
        if (rc) {
            return rc;
        }
        pending = 1.0;
        r0sq = r1;
        for (int c = 0; c < dim; c++) {
            x[c] = x1[c];
            v[c] = v1[c];
        }
    }
}

static int walker_init(walker *wk, const gr_spm_settings *s)
{
    memset(wk, 0, sizeof *wk);
    wk->dim = s->dim;
    wk->refine = s->refine;
    wk->seed = s->seed;
    return GR_OK;
}

static void walker_free(walker *wk)
{
    free(wk->w);
    free(wk->wt);
    wk->w = wk->wt = NULL;
}

/* running sums for gr_spm_walk_stats */
typedef struct stats_acc {
    double t_sum, t2_sum, w2_sum, weight_sum, e2_sum;
    double aa, ab,
        bb; /* per walk a = sum wt w^2, b = sum wt: for the error of <w^2> = sum a / sum b */
} stats_acc;

static void stats_add(stats_acc *a, gr_spm_walk_stats *st, const walker *wk)
{
    st->walks++;
    st->steps += wk->steps;
    st->bridge_points += wk->bridge_points;
    st->bridge_exits += wk->bridge_exit;
    a->t_sum += wk->duration;
    a->t2_sum += wk->duration * wk->duration;
    a->e2_sum += wk->exit_speed2;
    double wa = 0.0, wb = 0.0;
    for (int64_t i = 0; i < wk->n; i++) {
        double x = wk->wt[i] * wk->w[i] * wk->w[i];
        a->w2_sum += x;
        a->weight_sum += wk->wt[i];
        wa += x;
        wb += wk->wt[i];
    }
    a->aa += wa * wa;
    a->ab += wa * wb;
    a->bb += wb * wb;
}

static void stats_finish(const stats_acc *a, gr_spm_walk_stats *st)
{
    double n = (double)st->walks;
    st->exit_time_mean = a->t_sum / n;
    double var = fmax(a->t2_sum / n - st->exit_time_mean * st->exit_time_mean, 0.0);
    st->exit_time_err = n > 1 ? sqrt(var / (n - 1.0)) : (double)NAN;
    st->w2_time_mean = a->weight_sum > 0.0 ? a->w2_sum / a->weight_sum : (double)NAN;
    /* <w^2> is a ratio of sums over independent walks, R = sum a / sum b: its error by the delta
     * method, var R = sum (a - R b)^2 / (n (n - 1) b_mean^2) */
    double R = st->w2_time_mean, bm = a->weight_sum / n;
    double ss = fmax(a->aa - 2.0 * R * a->ab + R * R * a->bb, 0.0);
    st->w2_time_err = n > 1 && bm > 0.0 ? sqrt(ss / (n * (n - 1.0))) / bm : (double)NAN;
    st->exit_speed2_mean = a->e2_sum / n;
}

/* ------------------------------------------------------------------------------------------- */

int gr_spm_circle(const gr_spm_settings *s, double radius, int index, int nbins, double wmax,
                  gr_spm_q *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    int rc = gr_spm_settings_check(s, err);
    if (rc) {
        return rc;
    }
    if (!(radius > 0.0) || !isfinite(radius)) {
        return GR_FAIL(err, GR_EINVAL, "spm: radius must be > 0 (m), got %g", radius);
    }
    if (index < 0 || index > 16000000) {
        return GR_FAIL(err, GR_EINVAL, "spm: radius index must lie in 0..16000000, got %d", index);
    }
    out->radius = radius;
    out->u = gr_spm_velocity_scale(s, radius);
    out->t_scale = gr_spm_time_scale(s, radius);
    out->tau = s->dt > 0.0 ? s->dt / out->t_scale : s->step;
    if (out->tau > 10.0) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: dt = %g s is %g t_l for the radius %g m; use a dt below t_l = %g s",
                       s->dt, out->tau, radius, out->t_scale);
    }
    rc = gr_spm_dist_init(&out->q, s->batches, nbins, wmax, err);
    if (rc) {
        return rc;
    }
    walker wk;
    walker_init(&wk, s);
    walker_set_tau(&wk, out->tau);
    stats_acc acc = {0};
    for (int64_t n = 0; n < s->walks; n++) {
        uint64_t key = ((uint64_t)index << 40) + (uint64_t)n;
        rc = walk_run(&wk, key, err);
        if (rc) {
            break;
        }
        gr_histogram *h = &out->q.batch[n % s->batches];
        for (int64_t i = 0; i < wk.n; i++) {
            gr_histogram_add(h, wk.w[i], wk.wt[i]);
        }
        stats_add(&acc, &out->stats, &wk);
        if (s->progress && n % 1000 == 999) {
            s->progress((double)(n + 1) / (double)s->walks, s->user);
        }
    }
    walker_free(&wk);
    if (!rc) {
        rc = dist_merge(&out->q, err);
    }
    if (rc) {
        gr_spm_q_free(out);
        return rc;
    }
    stats_finish(&acc, &out->stats);
    return GR_OK;
}

void gr_spm_q_free(gr_spm_q *q) { gr_spm_dist_free(&q->q); }

int gr_spm_dist_jackknife(const gr_spm_dist *d, gr_spm_stat_fn fn, void *user, int nout,
                          double *value, double *jk_err, gr_error *err)
{
    const int nb = d->all.nbins, B = d->nbatches;
    if (nout < 1 || nout > 16) {
        return GR_FAIL(err, GR_EINVAL, "spm: jackknife of 1..16 numbers, got %d", nout);
    }
    double *x = malloc(sizeof(double) * (size_t)nb * 4);
    if (!x) {
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    double *p = x + nb, *e = p + nb, *c = e + nb;
    for (int i = 0; i < nb; i++) {
        x[i] = gr_histogram_center(&d->all, i);
        p[i] = gr_spm_dist_density(d, i);
        e[i] = gr_spm_dist_error(d, i);
        c[i] = d->all.count[i];
    }
    int rc = fn(x, p, e, c, nb, value, user);
    if (rc) {
        free(x);
        return GR_FAIL(err, GR_EINVAL, "spm: the statistic cannot be computed from all batches");
    }
    double t[16], sum[16] = {0}, sum2[16] = {0};
    int used = 0;
    for (int j = 0; j < B; j++) {
        const gr_histogram *h = &d->batch[j];
        double total = d->all.total - h->total;
        if (!(total > 0.0)) {
            continue;
        }
        for (int i = 0; i < nb; i++) {
            double w = gr_histogram_upper(&d->all, i) - gr_histogram_lower(&d->all, i);
            p[i] = 0.5 * (d->all.count[i] - h->count[i]) / (total * w);
        }
        if (fn(x, p, e, c, nb, t, user)) {
            free(x);
            return GR_FAIL(err, GR_EINVAL, "spm: the statistic cannot be computed without batch %d",
                           j);
        }
        for (int k = 0; k < nout; k++) {
            sum[k] += t[k];
            sum2[k] += t[k] * t[k];
        }
        used++;
    }
    free(x);
    for (int k = 0; k < nout; k++) {
        double mean = used ? sum[k] / used : 0.0;
        double var = used ? fmax(sum2[k] / used - mean * mean, 0.0) : (double)NAN;
        jk_err[k] = used > 1 ? sqrt((double)(used - 1) * var) : (double)NAN;
    }
    return GR_OK;
}

typedef struct qfit_par {
    double wfrom, min_count;
    int full;  /* also the free-exponent fit */
    int calls; /* the first call sees all batches */
    gr_spm_tail_fit *out;
} qfit_par;

/* out = (b, ln A, beta) */
static int qfit_stat(const double *xw, const double *p, const double *e, const double *count, int n,
                     double *out, void *user)
{
    qfit_par *q = user;
    double x[512], y[512], sg[512], ww[512], yy[512], ss[512];
    int m = 0;
    for (int i = 0; i < n && m < 512; i++) {
        if (xw[i] >= q->wfrom && count[i] >= q->min_count && p[i] > 0.0 && e[i] > 0.0 &&
            isfinite(e[i])) {
            ww[m] = xw[i];
            x[m] = xw[i] * xw[i];
            y[m] = log(p[i]);
            sg[m] = e[i] / p[i];
            yy[m] = p[i];
            ss[m] = e[i];
            m++;
        }
    }
    if (m < 3) {
        return 1;
    }
    gr_fit f;
    gr_error e2 = {0};
    if (gr_fit_line(x, y, sg, m, &f, &e2)) {
        return 1;
    }
    out[0] = -f.p[1];
    out[1] = f.p[0];
    out[2] = (double)NAN;
    bool first = q->calls++ == 0;
    if (first) {
        q->out->n_points = m;
        q->out->wto = ww[m - 1];
        q->out->chi2_red = f.chi2_red;
    }
    if (q->full) {
        double p0[3] = {exp(f.p[0]), 1.0 / sqrt(fmax(out[0], 1e-3)), 2.0};
        gr_fit g;
        if (gr_fit_stretched_exp(ww, yy, ss, m, p0, &g, &e2) == 0) {
            out[2] = g.p[2];
        } else if (first) {
            q->full = 0; /* no free-exponent check: it failed on all data */
        }
    }
    return 0;
}

int gr_spm_q_tail_fit(const gr_spm_q *q, double wfrom, double min_count, gr_spm_tail_fit *out,
                      gr_error *err)
{
    memset(out, 0, sizeof *out);
    out->wfrom = out->wto = wfrom;
    qfit_par par = {wfrom, min_count, 1, 0, out};
    double v[3], e[3];
    int rc = gr_spm_dist_jackknife(&q->q, qfit_stat, &par, 3, v, e, err);
    if (rc) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: Q tail fit: too few bins with w >= %g and >= %g samples; use more "
                       "walks or a lower --fit-from",
                       wfrom, min_count);
    }
    out->b = v[0];
    out->b_err = e[0];
    out->A = exp(v[1]);
    out->A_err = out->A * e[1];
    out->beta = par.full ? v[2] : (double)NAN;
    out->beta_err = par.full ? e[2] : (double)NAN;
    return GR_OK;
}

/* chi^2 of the collapse from batch densities: groups given by the index list (first B in A) */
static double split_chi2(const double *dens, int m, int B, const int *idx, double *max_abs_z)
{
    double chi2 = 0.0;
    for (int i = 0; i < m; i++) {
        double s[2] = {0.0, 0.0}, s2[2] = {0.0, 0.0};
        for (int g = 0; g < 2; g++) {
            for (int j = 0; j < B; j++) {
                double x = dens[(size_t)idx[g * B + j] * (size_t)m + (size_t)i];
                s[g] += x;
                s2[g] += x * x;
            }
        }
        double mean[2], se2[2];
        for (int g = 0; g < 2; g++) {
            mean[g] = s[g] / B;
            se2[g] = fmax(s2[g] / B - mean[g] * mean[g], 0.0) * B / (B - 1.0) / B;
        }
        double den = se2[0] + se2[1];
        if (den > 0.0) {
            double z2 = (mean[0] - mean[1]) * (mean[0] - mean[1]) / den;
            chi2 += z2;
            if (max_abs_z) {
                *max_abs_z = fmax(*max_abs_z, sqrt(z2));
            }
        }
    }
    return chi2;
}

int gr_spm_q_collapse(const gr_spm_q *a, const gr_spm_q *b, double min_count, int permutations,
                      gr_spm_collapse *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    const gr_histogram *ha = &a->q.all, *hb = &b->q.all;
    if (ha->nbins != hb->nbins || ha->lo != hb->lo || ha->hi != hb->hi ||
        a->q.nbatches != b->q.nbatches) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: collapse needs the same scaled bins and batches for both radii");
    }
    if (permutations < 0) {
        return GR_FAIL(err, GR_EINVAL, "spm: permutations must be >= 0, got %d", permutations);
    }
    const int B = a->q.nbatches, nb = ha->nbins;
    int *sel = malloc(sizeof(int) * (size_t)nb), m = 0;
    if (!sel) {
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    for (int i = 0; i < nb; i++) {
        if (ha->count[i] >= min_count && hb->count[i] >= min_count) {
            sel[m++] = i;
        }
    }
    if (m < 1) {
        free(sel);
        return GR_FAIL(err, GR_EINVAL,
                       "spm: collapse: no bins with >= %g samples in both histograms", min_count);
    }
    double *dens = malloc(sizeof(double) * (size_t)(2 * B) * (size_t)m);
    int *idx = malloc(sizeof(int) * (size_t)(2 * B));
    if (!dens || !idx) {
        free(sel);
        free(dens);
        free(idx);
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    for (int g = 0; g < 2; g++) {
        const gr_spm_dist *d = g ? &b->q : &a->q;
        for (int j = 0; j < B; j++) {
            for (int k = 0; k < m; k++) {
                dens[(size_t)(g * B + j) * (size_t)m + (size_t)k] =
                    0.5 * gr_histogram_density(&d->batch[j], sel[k]);
            }
        }
    }
    for (int j = 0; j < 2 * B; j++) {
        idx[j] = j;
    }
    out->chi2 = split_chi2(dens, m, B, idx, &out->max_abs_z);
    out->dof = m;
    out->chi2_red = out->chi2 / m;
    out->p_chi2 = gsl_cdf_chisq_Q(out->chi2, (double)m);
    out->p_value = out->p_chi2;
    if (permutations > 0) {
        int exceed = 0;
        for (int r = 0; r < permutations; r++) {
            /* Fisher-Yates with a fixed counter-based generator: reproducible */
            for (int j = 2 * B - 1; j > 0; j--) {
                int k =
                    (int)(gr_noise_uniform(0x5350u, STREAM_L, (uint64_t)r, (uint64_t)j) * (j + 1));
                int t = idx[j];
                idx[j] = idx[k];
                idx[k] = t;
            }
            exceed += split_chi2(dens, m, B, idx, NULL) >= out->chi2;
        }
        out->permutations = permutations;
        out->p_value = (exceed + 1.0) / (permutations + 1.0);
    }
    free(sel);
    free(dens);
    free(idx);
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------- *
 * P_l(l) */

int gr_spm_pl_fitted(gr_spm_pl *pl, double df, double C, gr_error *err)
{
    memset(pl, 0, sizeof *pl);
    if (!(df > 1.0 && df < 3.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: D_f must lie in (1, 3) for the free-path form 4.25, got %g", df);
    }
    if (!(C > 0.0) || !isfinite(C)) {
        return GR_FAIL(err, GR_EINVAL, "spm: C of 4.25 must be > 0 (m^-(D_f-1)), got %g", C);
    }
    pl->kind = GR_SPM_PL_FITTED;
    pl->df = df;
    pl->beta = df - 1.0;
    pl->C = C;
    snprintf(pl->source, sizeof pl->source, "fitted form 4.25 with D_f = %g, C = %g", df, C);
    return GR_OK;
}

void gr_spm_pl_free(gr_spm_pl *pl)
{
    free(pl->l);
    free(pl->p);
    free(pl->perr);
    free(pl->cdf);
    pl->l = pl->p = pl->perr = pl->cdf = NULL;
    pl->n = 0;
}

static int find_column(char **names, int n, const char *a, const char *b)
{
    for (int i = 0; i < n; i++) {
        if (!strcmp(names[i], a) || (b && !strcmp(names[i], b))) {
            return i;
        }
    }
    return -1;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) {
        s++;
    }
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1])) {
        *--e = 0;
    }
    return s;
}

int gr_spm_pl_load(gr_spm_pl *pl, const char *path, double diameter, gr_error *err)
{
    memset(pl, 0, sizeof *pl);
    int why = 0;
    FILE *f = gr_input_fopen(path, &why);
    if (!f) {
        return GR_FAIL(
            err, why < 0 || why == ENOENT ? GR_EINVAL : GR_EIO, "%s: cannot read: %s", path,
            why < 0 ? "not a regular file (a folder, FIFO, device or socket)" : strerror(why));
    }
    pl->kind = GR_SPM_PL_TABLE;
    snprintf(pl->source, sizeof pl->source, "%s", path);
    char line[4096];
    char *names[64];
    int ncol = 0, cl = -1, cp = -1, ce = -1, lineno = 0, cap = 0, rc = GR_OK;
    double unit = 1.0; /* metres per unit of the free-path column */
    char header[4096];
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *s = trim(line);
        if (!*s || *s == '#') {
            continue;
        }
        if (ncol == 0) {
            snprintf(header, sizeof header, "%s", s);
            char *save = NULL;
            for (char *tok = strtok_r(header, ",", &save); tok && ncol < 64;
                 tok = strtok_r(NULL, ",", &save)) {
                names[ncol++] = trim(tok);
            }
            cl = find_column(names, ncol, "l", NULL);
            cp = find_column(names, ncol, "P", "density");
            ce = find_column(names, ncol, "P_err", "density_error");
            if (cl < 0 && (cl = find_column(names, ncol, "l_over_d", NULL)) >= 0) {
                if (!(diameter > 0.0) || !isfinite(diameter)) {
                    rc = GR_FAIL(err, GR_EINVAL,
                                 "%s:%d: free paths in diameters (l_over_d): the particle diameter "
                                 "is needed",
                                 path, lineno);
                    break;
                }
                unit = diameter;
            }
            if (cl < 0 || cp < 0) {
                rc = GR_FAIL(err, GR_EINVAL,
                             "%s:%d: the header must name the columns l (or l_over_d) and P (or "
                             "density), got '%s'",
                             path, lineno, s);
                break;
            }
            continue;
        }
        double val[64];
        int k = 0;
        char *save = NULL;
        bool bad = false;
        for (char *tok = strtok_r(s, ",", &save); tok && k < 64; tok = strtok_r(NULL, ",", &save)) {
            char *end;
            tok = trim(tok);
            val[k] = strtod(tok, &end);
            if (end == tok || *end) {
                bad = true;
            }
            k++;
        }
        if (k != ncol || bad) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: expected %d numbers separated by commas", path,
                         lineno, ncol);
            break;
        }
        double l = val[cl] * unit, p = val[cp] / unit, e = ce >= 0 ? val[ce] / unit : 0.0;
        if (!(l > 0.0) || !isfinite(l) || !(p >= 0.0) || !isfinite(p) || (ce >= 0 && !(e >= 0.0))) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: need l > 0, P >= 0%s, got l = %g, P = %g", path,
                         lineno, ce >= 0 ? " and an error >= 0" : "", l, p);
            break;
        }
        if (pl->n > 0 && !(l > pl->l[pl->n - 1])) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: l must increase from row to row (%g after %g)",
                         path, lineno, l, pl->l[pl->n - 1]);
            break;
        }
        if (pl->n == cap) {
            cap = cap ? 2 * cap : 256;
            double *a = realloc(pl->l, sizeof(double) * (size_t)cap);
            if (a)
                pl->l = a;
            double *b = a ? realloc(pl->p, sizeof(double) * (size_t)cap) : NULL;
            if (b)
                pl->p = b;
            double *c = b ? realloc(pl->perr, sizeof(double) * (size_t)cap) : NULL;
            if (c)
                pl->perr = c;
            if (!c) {
                rc = GR_FAIL(err, GR_ENOMEM, "%s: out of memory", path);
                break;
            }
        }
        pl->l[pl->n] = l;
        pl->p[pl->n] = p;
        pl->perr[pl->n] = e;
        pl->n++;
    }
    fclose(f);
    if (!rc && ncol == 0) {
        rc = GR_FAIL(err, GR_EINVAL, "%s: no header line (expected e.g. 'l,P')", path);
    }
    if (!rc && pl->n < 3) {
        rc = GR_FAIL(err, GR_EINVAL, "%s: need at least 3 rows of l,P, got %d", path, pl->n);
    }
    if (!rc) {
        if (ce < 0) {
            free(pl->perr);
            pl->perr = NULL;
        }
        pl->cdf = malloc(sizeof(double) * (size_t)pl->n);
        if (!pl->cdf) {
            rc = GR_FAIL(err, GR_ENOMEM, "%s: out of memory", path);
        }
    }
    if (!rc) {
        /* piecewise-linear density between the points: trapezoid integral */
        pl->cdf[0] = 0.0;
        for (int i = 1; i < pl->n; i++) {
            pl->cdf[i] =
                pl->cdf[i - 1] + 0.5 * (pl->p[i] + pl->p[i - 1]) * (pl->l[i] - pl->l[i - 1]);
        }
        double total = pl->cdf[pl->n - 1];
        if (!(total > 0.0) || !isfinite(total)) {
            rc = GR_FAIL(err, GR_EINVAL, "%s: P integrates to %g over l; need a positive integral",
                         path, total);
        } else {
            for (int i = 0; i < pl->n; i++) {
                pl->cdf[i] /= total;
                pl->p[i] /= total;
                if (pl->perr) {
                    pl->perr[i] /= total;
                }
            }
        }
    }
    if (rc) {
        gr_spm_pl_free(pl);
    }
    return rc;
}

double gr_spm_pl_density(const gr_spm_pl *pl, double l)
{
    if (pl->kind == GR_SPM_PL_FITTED) {
        /* 4.25 normalised: beta C l^(beta - 1) exp(-C l^beta), beta = D_f - 1 */
        if (!(l > 0.0)) {
            return 0.0;
        }
        double lb = pow(l, pl->beta);
        return pl->beta * pl->C * lb / l * exp(-pl->C * lb);
    }
    if (!(l >= pl->l[0]) || !(l <= pl->l[pl->n - 1])) {
        return 0.0;
    }
    int lo = 0, hi = pl->n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (pl->l[mid] <= l) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    double t = (l - pl->l[lo]) / (pl->l[hi] - pl->l[lo]);
    return pl->p[lo] + t * (pl->p[hi] - pl->p[lo]);
}

double gr_spm_pl_quantile(const gr_spm_pl *pl, double u)
{
    u = fmin(fmax(u, 0.0), 1.0 - 1e-16);
    if (pl->kind == GR_SPM_PL_FITTED) {
        /* distribution function 1 - exp(-C l^beta) */
        return pow(-log1p(-u) / pl->C, 1.0 / pl->beta);
    }
    int lo = 0, hi = pl->n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (pl->cdf[mid] <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    /* inside [l_lo, l_hi] the density is p0 + (p1 - p0) x / d: solve p0 x + (p1 - p0) x^2 / 2d = r */
    double d = pl->l[hi] - pl->l[lo], p0 = pl->p[lo], p1 = pl->p[hi], r = u - pl->cdf[lo];
    double a = 0.5 * (p1 - p0) / d, x;
    if (fabs(a) * d < 1e-12 * fmax(p0, 1e-300)) {
        x = p0 > 0.0 ? r / p0 : 0.0;
    } else {
        double disc = fmax(p0 * p0 + 4.0 * a * r, 0.0);
        x = 2.0 * r / (p0 + sqrt(disc)); /* the stable root */
    }
    return pl->l[lo] + fmin(fmax(x, 0.0), d);
}

double gr_spm_pl_mean(const gr_spm_pl *pl)
{
    if (pl->kind == GR_SPM_PL_FITTED) {
        return pow(pl->C, -1.0 / pl->beta) * gsl_sf_gamma(1.0 + 1.0 / pl->beta);
    }
    double m = 0.0;
    for (int i = 1; i < pl->n; i++) {
        /* integral of l (p0 + (p1 - p0)(l - a)/d) over [a, b] */
        double a = pl->l[i - 1], b = pl->l[i], d = b - a, p0 = pl->p[i - 1], p1 = pl->p[i];
        m += d * (p0 * (2.0 * a + b) + p1 * (a + 2.0 * b)) / 6.0;
    }
    return m;
}

/* ln P = q0 + (q2 - 1) ln l - q1 l^q2 */
static double pl_tail_model(double l, const double *q, double *g, void *user)
{
    (void)user;
    double ll = log(l), lb = exp(q[2] * ll);
    if (g) {
        g[0] = 1.0;
        g[1] = -lb;
        g[2] = ll - q[1] * lb * ll;
    }
    return q[0] + (q[2] - 1.0) * ll - q[1] * lb;
}

int gr_spm_pl_fit_tail(const gr_spm_pl *pl, double lfrom, gr_spm_pl_fit *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    if (pl->kind != GR_SPM_PL_TABLE) {
        return GR_FAIL(err, GR_EINVAL, "spm: the tail fit needs a measured P_l table");
    }
    if (lfrom <= 0.0) {
        /* the longest 10% of the paths: 4.25 is a long-distance form (sec. 4.3.3 fits the lowest
         * decades of P_l) */
        lfrom = gr_spm_pl_quantile(pl, 0.9);
    }
    int n = pl->n, m = 0;
    double *x = malloc(sizeof(double) * (size_t)n * 4);
    if (!x) {
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    double *y = x + n, *s = y + n, *t = s + n;
    for (int i = 0; i < n; i++) {
        if (pl->l[i] >= lfrom && pl->p[i] > 0.0 && (!pl->perr || pl->perr[i] > 0.0)) {
            x[m] = pl->l[i];
            y[m] = log(pl->p[i]);
            s[m] = pl->perr ? pl->perr[i] / pl->p[i] : 1.0;
            m++;
        }
    }
    out->lfrom = lfrom;
    out->lto = m ? x[m - 1] : lfrom;
    out->n_points = m;
    if (m < 4) {
        free(x);
        return GR_FAIL(err, GR_EINVAL,
                       "spm: P_l tail fit: only %d usable points with l >= %g (need 4)", m, lfrom);
    }
    /* starting point: beta = 0.63 (D_f = 1.63), then C from the line ln(P l^(1 - beta)) = c - C l^beta */
    double q0[3] = {0.0, 1.0, 0.63};
    for (int i = 0; i < m; i++) {
        t[i] = pow(x[i], q0[2]);
    }
    double *yy = malloc(sizeof(double) * (size_t)m);
    if (!yy) {
        free(x);
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    for (int i = 0; i < m; i++) {
        yy[i] = y[i] + (1.0 - q0[2]) * log(x[i]);
    }
    gr_fit lf, f;
    int rc = gr_fit_line(t, yy, s, m, &lf, err);
    free(yy);
    if (!rc) {
        q0[0] = lf.p[0];
        q0[1] = lf.p[1] < 0.0 ? -lf.p[1] : 1.0;
        rc = gr_fit_nonlinear(pl_tail_model, NULL, x, y, s, m, 3, q0, &f, err);
    }
    if (!rc && !pl->perr && f.dof > 0) {
        /* no error column: estimate the scatter of ln P from the residuals and refit */
        double rms = sqrt(f.chi2 / f.dof);
        for (int i = 0; i < m; i++) {
            s[i] = rms > 0.0 ? rms : 1.0;
        }
        double q1[3] = {f.p[0], f.p[1], f.p[2]};
        rc = gr_fit_nonlinear(pl_tail_model, NULL, x, y, s, m, 3, q1, &f, err);
    }
    free(x);
    if (rc) {
        return rc;
    }
    if (!(f.p[2] > 0.0) || !(f.p[1] > 0.0)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "spm: P_l tail fit gave beta = %g, C = %g: not the form 4.25 (try another --tail-from)",
            f.p[2], f.p[1]);
    }
    out->A0 = exp(f.p[0]);
    out->C = f.p[1];
    out->C_err = f.err[1];
    out->beta = f.p[2];
    out->beta_err = f.err[2];
    out->df = out->beta + 1.0;
    out->df_err = out->beta_err;
    out->chi2_red = f.chi2_red;
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------- */

int gr_spm_full(const gr_spm_settings *s, const gr_spm_pl *pl, bool weight_time, int nbins,
                double vmax, gr_spm_full_result *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    int rc = gr_spm_settings_check(s, err);
    if (rc) {
        return rc;
    }
    rc = gr_spm_dist_init(&out->p, s->batches, nbins, vmax, err);
    if (rc) {
        return rc;
    }
    walker wk;
    walker_init(&wk, s);
    walker_set_tau(&wk, s->step);
    stats_acc acc = {0};
    const double t_ref = gr_spm_time_scale(s, gr_spm_pl_mean(pl));
    double l_sum = 0.0, iw_sum = 0.0, v2_sum = 0.0, wsum = 0.0;
    for (int64_t n = 0; n < s->walks; n++) {
        /* step two of sec. 5.2.3: the radius from P_l (by its distribution function, not by
         * rejection) */
        double U = gr_noise_uniform(s->seed, STREAM_L, (uint64_t)n, 0), F = U, iw = 1.0;
        if (s->tilt > 1.0) {
            /* importance sampling: 1 - F = (1 - U)^tilt has density (1 - F)^(1/tilt - 1) / tilt */
            double q = pow(1.0 - U, s->tilt);
            F = 1.0 - q;
            iw = s->tilt * pow(q, 1.0 - 1.0 / s->tilt);
        }
        double l = gr_spm_pl_quantile(pl, F);
        if (!(l > 0.0) || !isfinite(l)) {
            rc = GR_FAIL(err, GR_EINVAL, "spm: drew the free path %g from P_l; check the P_l table",
                         l);
            break;
        }
        double u = gr_spm_velocity_scale(s, l), tl = gr_spm_time_scale(s, l);
        if (s->dt > 0.0) {
            /* the thesis' fixed time step: coarse for short walks (refinement still applies) */
            walker_set_tau(&wk, fmin(s->dt / tl, 10.0));
        }
        rc = walk_run(&wk, (uint64_t)n, err);
        if (rc) {
            break;
        }
        /* a walk's samples weigh its duration / tau in all; uniformly in time each sample is
         * tau t_l seconds; per walk equally, 1 / (duration / tau) */
        double mult = iw * (weight_time ? wk.tau * tl / t_ref : wk.tau / wk.duration);
        gr_histogram *h = &out->p.batch[n % s->batches];
        for (int64_t i = 0; i < wk.n; i++) {
            double v = wk.w[i] * u, w = wk.wt[i] * mult;
            gr_histogram_add(h, v, w);
            v2_sum += w * v * v;
            wsum += w;
        }
        l_sum += iw * l;
        iw_sum += iw;
        stats_add(&acc, &out->stats, &wk);
        if (s->progress && n % 1000 == 999) {
            s->progress((double)(n + 1) / (double)s->walks, s->user);
        }
    }
    walker_free(&wk);
    if (!rc) {
        rc = dist_merge(&out->p, err);
    }
    if (rc) {
        gr_spm_full_result_free(out);
        return rc;
    }
    stats_finish(&acc, &out->stats);
    out->l_mean = l_sum / iw_sum;
    out->v2_mean = wsum > 0.0 ? v2_sum / wsum : (double)NAN;
    return GR_OK;
}

void gr_spm_full_result_free(gr_spm_full_result *r) { gr_spm_dist_free(&r->p); }

/* ------------------------------------------------------------------------------------------- */

double gr_spm_alpha(double df)
{
    /* 5.29: alpha = 6 beta / (3 beta + 2) = 6 (D_f - 1) / (3 D_f - 1) */
    return 6.0 * (df - 1.0) / (3.0 * df - 1.0);
}

int gr_spm_predict(double df, double B, double C, gr_spm_prediction *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    if (!(df > 1.0 && df < 3.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: D_f must lie in (1, 3), got %g", df);
    }
    if (!(B >= 0.0) || !(C >= 0.0) || !isfinite(B) || !isfinite(C)) {
        return GR_FAIL(err, GR_EINVAL, "spm: B and C must be >= 0, got B = %g, C = %g", B, C);
    }
    out->df = df;
    out->beta = df - 1.0;                               /* P_l ~ l^(beta - 1) exp(-C l^beta) */
    out->gamma = 3.0 * out->beta;                       /* below 5.15 */
    out->alpha = 2.0 * out->gamma / (out->gamma + 2.0); /* 5.27-5.28 */
    out->h = out->gamma / (out->gamma + 2.0);           /* 5.30: (2 + 2 gamma)/(2 + gamma) - 1 */
    out->B = B;
    out->C = C;
    if (B > 0.0 && C > 0.0) {
        double g = out->gamma, F = B / C;
        out->F = F;
        /* 5.27 */
        out->S = B * pow(g / (2.0 * F), 2.0 / (g + 2.0)) + C * pow(2.0 * F / g, g / (g + 2.0));
        out->v_A = pow(out->S, -1.0 / out->alpha);
    } else {
        out->F = out->S = out->v_A = (double)NAN;
    }
    return GR_OK;
}

typedef struct integrand_par {
    double a, b, C, fm; /* f(y) = -a y^(-b) - C y, fm = f(y_m) */
} integrand_par;

static double integrand(double y, void *vp)
{
    const integrand_par *p = vp;
    if (!(y > 0.0)) {
        return 0.0;
    }
    return exp(-p->a * pow(y, -p->b) - p->C * y - p->fm);
}

static double y_max(const gr_spm_prediction *p, double v)
{
    /* 5.18: y_m = (2 F v^2 / gamma)^(gamma / (gamma + 2)) */
    return pow(2.0 * p->F * v * v / p->gamma, p->gamma / (p->gamma + 2.0));
}

double gr_spm_asymptotic_log(const gr_spm_prediction *p, double v)
{
    double g = p->gamma, ym = y_max(p, v);
    double fm = -p->S * pow(fabs(v), p->alpha); /* = f(y_m), 5.27 */
    /* 5.19: f''(y_m) = -(2/gamma)((gamma + 2)/gamma) B v^2 y_m^(-(2 + 2 gamma)/gamma). The Gaussian
     * integral of exp(f''/2 x^2) is sqrt(2 pi / -f''); the thesis' 5.24-5.26 drop the 1/2, which
     * changes only the constant A_0. */
    double f2 = -(2.0 / g) * ((g + 2.0) / g) * p->B * v * v * pow(ym, -(2.0 + 2.0 * g) / g);
    return fm + 0.5 * log(2.0 * M_PI / -f2);
}

int gr_spm_integral_log(const gr_spm_prediction *p, double v, double *log_value, gr_error *err)
{
    if (!(p->B > 0.0 && p->C > 0.0) || !(v > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: the integral 5.13 needs B > 0, C > 0 and v > 0");
    }
    integrand_par par = {p->B * v * v, 2.0 / p->gamma, p->C, 0.0};
    double ym = y_max(p, v);
    par.fm = -par.a * pow(ym, -par.b) - par.C * ym;
    gsl_integration_workspace *w = gsl_integration_workspace_alloc(2000);
    if (!w) {
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    gsl_function F = {integrand, &par};
    double i1, i2, e1, e2;
    int rc1 = gsl_integration_qags(&F, 0.0, ym, 0.0, 1e-10, 2000, w, &i1, &e1);
    int rc2 = gsl_integration_qagiu(&F, ym, 0.0, 1e-10, 2000, w, &i2, &e2);
    gsl_integration_workspace_free(w);
    if ((rc1 && rc1 != GSL_EROUND) || (rc2 && rc2 != GSL_EROUND) || !(i1 + i2 > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: the integral 5.13 at v = %g failed: %s", v,
                       gsl_strerror(rc1 ? rc1 : rc2));
    }
    *log_value = par.fm + log(i1 + i2);
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------- *
 * The RFM's P(v) from snapshots */

static int name_cmp(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Parse the comment line of an extended XYZ frame: Time, pbc, and the first column of velo. */
static int xyz_comment(const char *c, double *t, int *dim, int *velo_col, int *ncols)
{
    const char *p = strstr(c, "Time=");
    *t = p ? strtod(p + 5, NULL) : (double)NAN;
    p = strstr(c, "pbc=\"");
    *dim = 0;
    if (p) {
        char a = 0, b = 0;
        if (sscanf(p + 5, "%c %c", &a, &b) == 2) {
            *dim = b == 'T' ? 2 : 1;
        }
    }
    p = strstr(c, "Properties=");
    if (!p) {
        return -1;
    }
    p += strlen("Properties=");
    int col = 0;
    *velo_col = -1;
    while (*p && !isspace((unsigned char)*p)) {
        char name[64], type[8];
        int count, used = 0;
        if (sscanf(p, "%63[^:]:%7[^:]:%d%n", name, type, &count, &used) != 3 || count < 1) {
            return -1;
        }
        if (!strcmp(name, "velo") || !strcmp(name, "vel") || !strcmp(name, "velocities")) {
            *velo_col = col;
        }
        col += count;
        p += used;
        if (*p == ':') {
            p++;
        }
    }
    *ncols = col;
    return *velo_col >= 0 ? 0 : -1;
}

int gr_spm_rfm_histogram(const char *dir, double t_from, gr_histogram *h, gr_spm_rfm_info *info,
                         gr_error *err)
{
    memset(info, 0, sizeof *info);
    char sdir[1200];
    snprintf(sdir, sizeof sdir, "%s/snapshots", dir);
    DIR *d = opendir(sdir);
    if (!d) {
        return GR_FAIL(err, GR_EINVAL, "%s: not a run folder with snapshots (%s)", dir,
                       strerror(errno));
    }
    char **names = NULL;
    int n = 0, cap = 0, rc = GR_OK;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t len = strlen(e->d_name);
        if (strncmp(e->d_name, "snap_", 5) || len < 9 || strcmp(e->d_name + len - 4, ".xyz")) {
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            char **a = realloc(names, sizeof(char *) * (size_t)cap);
            if (!a) {
                rc = GR_FAIL(err, GR_ENOMEM, "out of memory");
                break;
            }
            names = a;
        }
        names[n] = strdup(e->d_name);
        if (!names[n]) {
            rc = GR_FAIL(err, GR_ENOMEM, "out of memory");
            break;
        }
        n++;
    }
    closedir(d);
    if (!rc && n == 0) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "%s: no snapshots/snap_*.xyz (run with output.snapshot_every > 0)", dir);
    }
    if (!rc) {
        qsort(names, (size_t)n, sizeof(char *), name_cmp);
    }
    size_t lcap = 1 << 16;
    char *line = rc ? NULL : malloc(lcap);
    if (!rc && !line) {
        rc = GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    double v2 = 0.0;
    int64_t nv = 0;
    info->t_first = (double)NAN;
    for (int i = 0; i < n && !rc; i++) {
        char path[1500];
        snprintf(path, sizeof path, "%s/%s", sdir, names[i]);
        int why = 0;
        FILE *f = gr_input_fopen(path, &why);
        if (!f) {
            rc = GR_FAIL(err, why < 0 ? GR_EINVAL : GR_EIO, "%s: cannot read: %s", path,
                         why < 0 ? "not a regular file (a folder, FIFO, device or socket)"
                                 : strerror(why));
            break;
        }
        long np = 0;
        double t;
        int dim, vc, ncols;
        if (!fgets(line, (int)lcap, f) || sscanf(line, "%ld", &np) != 1 || np < 1 ||
            !fgets(line, (int)lcap, f) || xyz_comment(line, &t, &dim, &vc, &ncols) != 0 ||
            dim == 0) {
            fclose(f);
            rc = GR_FAIL(err, GR_EINVAL,
                         "%s: not an extended XYZ frame with Time, pbc and a velo column", path);
            break;
        }
        if (!(t >= t_from)) {
            fclose(f);
            info->frames_skipped++;
            continue;
        }
        if (info->frames > 0 && dim != info->dim) {
            fclose(f);
            rc = GR_FAIL(err, GR_EINVAL, "%s: dimension %d differs from the earlier frames' %d",
                         path, dim, info->dim);
            break;
        }
        info->dim = dim;
        for (long k = 0; k < np; k++) {
            if (!fgets(line, (int)lcap, f)) {
                rc = GR_FAIL(err, GR_EINVAL, "%s: frame ends after %ld of %ld particles", path, k,
                             np);
                break;
            }
            /* columns: species (1 token), then numbers; velo starts at column vc */
            char *p = line;
            double vel[3] = {0.0, 0.0, 0.0};
            int col = 0;
            while (col < vc + dim) {
                while (isspace((unsigned char)*p)) {
                    p++;
                }
                if (!*p) {
                    break;
                }
                char *end = p;
                if (col >= vc) {
                    vel[col - vc] = strtod(p, &end);
                    if (end == p) {
                        break;
                    }
                } else {
                    while (*end && !isspace((unsigned char)*end)) {
                        end++;
                    }
                }
                p = end;
                col++;
            }
            if (col < vc + dim) {
                rc = GR_FAIL(err, GR_EINVAL, "%s: particle line %ld has too few columns", path,
                             k + 1);
                break;
            }
            for (int c = 0; c < dim; c++) {
                gr_histogram_add(h, fabs(vel[c]), 1.0);
                info->v_max = fmax(info->v_max, fabs(vel[c]));
                v2 += vel[c] * vel[c];
                nv++;
            }
        }
        fclose(f);
        if (!rc) {
            if (info->frames == 0) {
                info->t_first = t;
            }
            info->t_last = t;
            info->frames++;
            info->particles = np;
        }
    }
    free(line);
    for (int i = 0; i < n; i++) {
        free(names[i]);
    }
    free(names);
    if (!rc && info->frames == 0) {
        rc = GR_FAIL(err, GR_EINVAL, "%s: all %d snapshots are before t = %g s (the warm-up)", dir,
                     info->frames_skipped, t_from);
    }
    info->v2_mean = nv ? v2 / (double)nv : (double)NAN;
    return rc;
}

/* ln P_spm and its relative error at velocity u, linear between bin centres; false outside the
 * bins or where P_spm is zero */
static bool spm_at(const double *v, const double *p, const double *e, int n, double u, double *lnp,
                   double *rel)
{
    if (!(u >= v[0]) || !(u <= v[n - 1])) {
        return false;
    }
    double dv = (v[n - 1] - v[0]) / (n - 1);
    int i = (int)((u - v[0]) / dv);
    i = i < 0 ? 0 : (i > n - 2 ? n - 2 : i);
    if (!(p[i] > 0.0) || !(p[i + 1] > 0.0)) {
        return false;
    }
    double t = (u - v[i]) / (v[i + 1] - v[i]);
    *lnp = (1.0 - t) * log(p[i]) + t * log(p[i + 1]);
    *rel = (1.0 - t) * e[i] / p[i] + t * e[i + 1] / p[i + 1];
    return isfinite(*rel);
}

/* The variance of the run's density in a bin, for sqrt(X) errors e of the density p: the Poisson
 * variance of the count the model m expects (Pearson), m e^2 / p, since the observed count's
 * sqrt(X) exaggerates low-count deficits; at least a fraction of the observed one. */
static double pearson_var(double p, double e, double m)
{
    double obs = e * e;
    return p > 0.0 && m > 0.0 ? fmax(m * obs / p, 0.25 * obs) : obs;
}

typedef struct cmp_ctx {
    const double *v, *ps, *es, *pr, *er;
    int n;
    double v_from;
} cmp_ctx;

/* best k for a given s (iterated weights) and its chi^2 */
static double cmp_chi2(const cmp_ctx *c, double s, double *k_out, double *k_err, int *m_out)
{
    double k = 1.0, den = 0.0, chi2 = 0.0;
    int m = 0;
    for (int it = 0; it < 50; it++) {
        double num = 0.0;
        den = 0.0;
        for (int i = 0; i < c->n; i++) {
            double lp, rel;
            if (c->v[i] >= c->v_from && c->pr[i] > 0.0 && c->er[i] > 0.0 &&
                spm_at(c->v, c->ps, c->es, c->n, c->v[i] / s, &lp, &rel)) {
                double q = exp(lp) / s, eq = q * rel;
                double w = 1.0 / (pearson_var(c->pr[i], c->er[i], k * q) + k * k * eq * eq);
                num += w * c->pr[i] * q;
                den += w * q * q;
            }
        }
        if (!(den > 0.0)) {
            *m_out = 0;
            return (double)INFINITY;
        }
        double knew = num / den;
        bool done = fabs(knew - k) <= 1e-12 * fabs(knew);
        k = knew;
        if (done) {
            break;
        }
    }
    for (int i = 0; i < c->n; i++) {
        double lp, rel;
        if (c->v[i] >= c->v_from && c->pr[i] > 0.0 && c->er[i] > 0.0 &&
            spm_at(c->v, c->ps, c->es, c->n, c->v[i] / s, &lp, &rel)) {
            double q = exp(lp) / s, eq = q * rel, r = c->pr[i] - k * q;
            chi2 += r * r / (pearson_var(c->pr[i], c->er[i], k * q) + k * k * eq * eq);
            m++;
        }
    }
    *k_out = k;
    *k_err = 1.0 / sqrt(den);
    *m_out = m;
    return chi2;
}

double gr_spm_compare_model(const gr_spm_compare *c, const double *v, const double *p_spm,
                            const double *e_spm, int n, int i, double *model_err)
{
    double lp, rel;
    if (!spm_at(v, p_spm, e_spm, n, v[i] / c->s, &lp, &rel)) {
        *model_err = 0.0;
        return 0.0;
    }
    double q = c->k * exp(lp) / c->s;
    *model_err = q * rel;
    return q;
}

int gr_spm_compare_tails(const double *v, const double *p_spm, const double *e_spm,
                         const double *p_rfm, const double *e_rfm, int n, double v_from,
                         double z_max, bool fit_scale, gr_spm_compare *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    out->v_from = v_from;
    out->s = 1.0;
    if (!(z_max > 0.0) || n < 3) {
        return GR_FAIL(err, GR_EINVAL, "spm: the comparison needs z_max > 0 and at least 3 bins");
    }
    cmp_ctx c = {v, p_spm, e_spm, p_rfm, e_rfm, n, v_from};
    int m;
    double k, ke, chi2 = cmp_chi2(&c, 1.0, &k, &ke, &m);
    if (m < 1) {
        return GR_FAIL(err, GR_EINVAL, "spm: no bins with v >= %g where both P(v) are positive",
                       v_from);
    }
    if (fit_scale) {
        /* a scan of ln s over [1/3, 3] by the reduced chi^2 (s changes which bins overlap; only
         * scales that keep at least half of the bins count), then golden-section refinement */
        double best = m > 2 ? chi2 / (m - 2) : (double)INFINITY, bs = 1.0;
        for (int j = 0; j <= 220; j++) {
            double sc = exp(log(3.0) * (j - 110) / 110.0), kk, kke;
            int mm;
            double x = cmp_chi2(&c, sc, &kk, &kke, &mm);
            if (mm >= 3 && 2 * mm >= m && x / (mm - 2) < best) {
                best = x / (mm - 2);
                bs = sc;
            }
        }
        double lo = log(bs) - log(3.0) / 110.0, hi = log(bs) + log(3.0) / 110.0,
               g = 0.5 * (sqrt(5.0) - 1.0);
        for (int it = 0; it < 40; it++) {
            double a = hi - g * (hi - lo), b = lo + g * (hi - lo), kk, kke;
            int ma, mb;
            double fa = cmp_chi2(&c, exp(a), &kk, &kke, &ma),
                   fb = cmp_chi2(&c, exp(b), &kk, &kke, &mb);
            fa /= ma > 2 ? ma - 2 : 1;
            fb /= mb > 2 ? mb - 2 : 1;
            if (fa < fb) {
                hi = b;
            } else {
                lo = a;
            }
        }
        double s = exp(0.5 * (lo + hi));
        chi2 = cmp_chi2(&c, s, &k, &ke, &m);
        out->s = s;
        /* error of s from chi^2 + 1 (reduced-chi^2 scaled below) by a parabola through +-1% */
        double kk, kke;
        int m1, m2;
        double cp = cmp_chi2(&c, s * 1.01, &kk, &kke, &m1),
               cm = cmp_chi2(&c, s / 1.01, &kk, &kke, &m2);
        double curv = (cp + cm - 2.0 * chi2) / (log(1.01) * log(1.01)); /* d2 chi2 / d(ln s)^2 */
        out->s_err = curv > 0.0 ? s * sqrt(2.0 / curv) : (double)NAN;
    }
    out->k = k;
    out->k_err = ke;
    out->n_points = m;
    int npar = fit_scale ? 2 : 1;
    out->chi2_red = m > npar ? chi2 / (m - npar) : (double)NAN;
    if (m > npar && out->chi2_red > 1.0) {
        out->k_err *= sqrt(out->chi2_red);
        out->s_err *= sqrt(out->chi2_red);
    }
    /* the agreeing tail: from the highest bin where both have data, downwards */
    int hi = -1, lo = -1, tail = 0, within = 0;
    bool broken = false;
    for (int i = n - 1; i >= 0; i--) {
        double me, q = gr_spm_compare_model(out, v, p_spm, e_spm, n, i, &me);
        if (!(q > 0.0) || !(p_rfm[i] > 0.0) || !(e_rfm[i] > 0.0)) {
            continue; /* an empty bin in either is no evidence either way */
        }
        double z = (p_rfm[i] - q) / sqrt(pearson_var(p_rfm[i], e_rfm[i], q) + me * me);
        if (v[i] >= v_from) {
            tail++;
            within += fabs(z) <= z_max;
        }
        if (broken) {
            continue;
        }
        if (fabs(z) > z_max) {
            broken = true;
            continue;
        }
        if (hi < 0) {
            hi = i;
        }
        lo = i;
        out->agree_bins++;
    }
    out->frac_within = tail ? (double)within / tail : (double)NAN;
    if (hi >= 0) {
        out->v_agree_lo = v[lo];
        out->v_agree_hi = v[hi];
        out->decades = log10(p_rfm[lo] / p_rfm[hi]);
    } else {
        out->v_agree_lo = out->v_agree_hi = (double)NAN;
    }
    return GR_OK;
}
