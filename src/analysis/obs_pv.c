/* pv: the velocity distribution P(v) of one velocity component (thesis ch. 5, sec. 5.1-5.1.1;
 * the method of App. A.1), its stretched-exponential tails and the crossover function P_0(v).
 *
 * Sampling (App. A.1): every sampled frame (uniform in time) adds each particle's velocity
 * components, taken relative to the frame's mean velocity (as T of eq. 2.19), to one histogram
 * (x and y pooled in 2D, x, y and z in 3D: "v denotes a component of velocity", sec. 5.1), and
 * each particle's |v| (the speed in 2D and 3D, |v_x| in 1D) to a second histogram. The speed's
 * Maxwell-Boltzmann reference in c = |v| / sqrt(<|v|^2>) is sqrt(2/pi) exp(-c^2/2) in 1D,
 * 2 c exp(-c^2) in 2D and 3 sqrt(6/pi) c^2 exp(-3 c^2 / 2) in 3D (4 pi v^2 of the shell). Densities are X_i / (N_s dv) with
 * errors sqrt(X_i) / (N_s dv) (A.4-A.5), N_s counting every sampled component, so the in-range
 * integral is the in-range fraction.
 *
 * The binning is fixed once, from T_ref: the mean granular temperature T (2.19, all components,
 * so T = dim <v_x^2>) of the first REF_FRAMES sampled frames, whose velocities are buffered
 * (at most REF_MAX_VALUES numbers) and then histogrammed. P(v) covers
 * [-pv_range sqrt(T_ref), pv_range sqrt(T_ref)) in pv_bins bins; |v| covers [0, pv_range sqrt(T_ref)).
 * Memory is the two histograms (plus that bounded buffer at the start): independent of the run
 * length.
 *
 * finish() fits (eq. numbers of the thesis):
 *  - tails, (5.5)/(A.8): the frequency distribution X_i against A_0 exp(-(|v|/v0)^alpha) with errors
 *    sqrt(X_i), on the bins whose count lies in the window [50, 50 000] (Table 5.1; Table A.1 uses
 *    [50, 5 000], reported too). alpha is scanned on a grid (A_0 and v0 fitted for each value) and
 *    accepted when the reduced chi-square is below 1.2 — the accepted range is the thesis's
 *    "alpha +- halfwidth"; a free three-parameter fit gives the best alpha with its error, and free
 *    fits over single decades of counts show how the local exponent changes along the tail. Not in
 *    the thesis: the over-dispersion of the counts, measured from the symmetry X(v) ~ X(-v), and the
 *    acceptance repeated with errors sqrt(dispersion X_i) (correlated frames make sqrt(X) too small);
 *  - the crossover function (5.32) P_0(v) = D exp(-(v/v_r)^2 / (1 + |v/v_c|^(2-alpha))) with
 *    alpha = 1 (as in Tables 5.3-5.4), on every bin with at least 50 counts, giving v_r, v_c,
 *    v_A = v_r^2/v_c and P(v_c)/P(0) = exp(-(v_c/v_r)^2/2);
 *  - the tail plot of Moon, Swift and Swinney (5.6): -ln(-ln(P(v)/P(0))) against ln(v/v_rms), with
 *    lines of slope -alpha_T for alpha_T = 2, 1.5 and 1.16.
 * Outputs: pv.csv, pv_tail.csv, pv_speed.csv, plots pv.png, pv_tail.png, pv_speed.png and the
 * summary member "pv" (docs/analysis-velocity.md). */
#include <cjson/cJSON.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_pv_species.h"
#include "analysis/obs_util.h"
#include "io/plot.h"
#include "granule/analysis.h"

enum {
    REF_FRAMES = 8,
    REF_MAX_VALUES = 1 << 20,
    MIN_FIT_POINTS = 5,
    MIN_DECADE_POINTS = 6,
    MIN_PAIRS = 5,
    MAX_SCAN = 512
};

#define COUNT_MIN 50.0        /* Tables 5.1 and A.1: bins with fewer counts are ignored */
#define COUNT_MAX_5_1 50000.0 /* Table 5.1: "the lowest three decades" */
#define COUNT_MAX_A_1 5000.0  /* Table A.1: "the lowest two decades" */
#define CHI2_RED_MAX 1.2      /* alpha accepted when chi2/dof < 1.2 */
#define ALPHA_SCAN_MIN 0.20
#define ALPHA_SCAN_MAX 3.00
#define ALPHA_SCAN_STEP 0.01
#define CROSSOVER_ALPHA 1.0 /* (5.32): "alpha is taken to be 1.00" */
#define NOVALUE ((double)NAN)
#define HUGE_D ((double)INFINITY)

typedef struct pv_params {
    int pv_bins;
    double pv_range;
} pv_params;

static const gr_param params[] = {
    {"pv_bins", "", GR_PARAM_INT, 400, 10, 1000000, false, false,
     "bins of P(v) per component and of the speed (App. A.1)", offsetof(pv_params, pv_bins)},
    {"pv_range", "", GR_PARAM_DOUBLE, 12, 1, 1000, false, false,
     "P(v) spans +-pv_range sqrt(T_ref), T_ref the mean T (2.19) of the first 8 sampled frames",
     offsetof(pv_params, pv_range)},
};

typedef struct pv {
    int dim, bins;
    double range;
    /* reference frames, before the binning is fixed */
    bool fixed;
    int ref_frames;
    double ref_T_sum, T_ref;
    double *buf; /* velocity components relative to the frame mean, dim per particle */
    size_t nbuf, capbuf;
    /* the distributions */
    gr_histogram comp;         /* P(v), one component (x and y pooled in 2D, x y z in 3D) */
    gr_histogram speed;        /* |v| */
    int64_t frames, particles; /* frames sampled; particles summed over frames */
    double sum_u2;             /* sum of |v - <v>|^2 over particles and frames */
    pv_species sp;             /* a mixture's P(v) per species (obs_pv_species.c) */
} pv;

static int check_params(const gr_obs_setup *setup, const pv_params *a, gr_error *err)
{
    if (setup->dim < 1 || setup->dim > 3) {
        return GR_FAIL(err, GR_EINVAL, "pv: dim = %d, expected 1, 2 or 3", setup->dim);
    }
    if (a->pv_bins < (int)params[0].min || a->pv_bins > (int)params[0].max) {
        return GR_FAIL(err, GR_EINVAL, "pv: [analysis] pv_bins = %d is outside [%g, %g]",
                       a->pv_bins, params[0].min, params[0].max);
    }
    if (!(a->pv_range >= params[1].min && a->pv_range <= params[1].max)) {
        return GR_FAIL(err, GR_EINVAL, "pv: [analysis] pv_range = %g is outside [%g, %g]",
                       a->pv_range, params[1].min, params[1].max);
    }
    return GR_OK;
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    const pv_params *a = params_block;
    int rc = check_params(setup, a, err);
    if (rc) {
        return rc;
    }
    pv *s = state;
    s->dim = setup->dim;
    s->bins = a->pv_bins;
    s->range = a->pv_range;
    gr_obs_own_pointer(s, &s->buf);
    gr_obs_own_histogram(s, &s->comp); /* binned once the reference frames are in */
    gr_obs_own_histogram(s, &s->speed);
    pv_species_init(s, &s->sp, setup);
    return GR_OK;
}

/* One particle's components (relative to the frame mean); a >= 0: its species in a mixture. */
static void add_particle(pv *s, int a, double ux, double uy, double uz)
{
    if (a >= 0) {
        pv_species_add(&s->sp, a, s->dim, ux, uy, uz);
    }
    gr_histogram_add(&s->comp, ux, 1.0);
    if (s->dim >= 2) {
        gr_histogram_add(&s->comp, uy, 1.0);
    }
    if (s->dim == 3) {
        gr_histogram_add(&s->comp, uz, 1.0);
        gr_histogram_add(&s->speed, sqrt(ux * ux + uy * uy + uz * uz), 1.0);
        return;
    }
    gr_histogram_add(&s->speed, s->dim == 2 ? sqrt(ux * ux + uy * uy) : fabs(ux), 1.0);
}

/* Fix the binning from the reference frames and histogram the buffered velocities. */
static int fix_binning(pv *s, gr_error *err)
{
    s->T_ref = s->ref_frames > 0 ? s->ref_T_sum / s->ref_frames : 0.0;
    if (!(s->T_ref > 0.0) || !isfinite(s->T_ref)) {
        return GR_FAIL(err, GR_EINVAL,
                       "pv: the reference temperature T_ref = %g of the first %d sampled frames is "
                       "not positive "
                       "(all velocities equal): P(v) needs moving particles",
                       s->T_ref, s->ref_frames);
    }
    double vmax = s->range * sqrt(s->T_ref);
    int rc = gr_histogram_init(&s->comp, s->bins, -vmax, vmax, false, err);
    if (!rc) {
        rc = gr_histogram_init(&s->speed, s->bins, 0.0, vmax, false, err);
        if (rc) {
            gr_histogram_free(&s->comp);
        }
    }
    if (!rc) {
        rc = pv_species_fix(&s->sp, &s->comp, err);
    }
    if (rc) {
        return rc;
    }
    s->fixed = true;
    for (size_t k = 0; k < s->nbuf; k += (size_t)s->dim) {
        const size_t i = k / (size_t)s->dim; /* the buffered particle */
        add_particle(s, s->sp.ns && i < s->sp.nbuf ? s->sp.buf[i] : -1, s->buf[k],
                     s->dim >= 2 ? s->buf[k + 1] : 0.0, s->dim == 3 ? s->buf[k + 2] : 0.0);
    }
    free(s->buf);
    s->buf = NULL;
    s->nbuf = s->capbuf = 0;
    free(s->sp.buf);
    s->sp.buf = NULL;
    s->sp.nbuf = s->sp.cap = 0;
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    pv *s = state;
    if (p->n < 1 || p->dim != s->dim || !p->vx || (p->dim >= 2 && !p->vy) ||
        (p->dim == 3 && !p->vz)) {
        return GR_FAIL(err, GR_EINVAL,
                       "pv: frame with %d particles in %d dimensions, expected dim = %d", p->n,
                       p->dim, s->dim);
    }
    int bad = pv_species_check(&s->sp, p, err);
    if (bad) {
        return bad;
    }
    double mean[3];
    gr_obs_mean_velocity(p, mean);
    double u2 = 0.0;
    for (int i = 0; i < p->n; i++) {
        double ux = p->vx[i] - mean[0], uy = s->dim >= 2 ? p->vy[i] - mean[1] : 0.0;
        if (s->dim == 3) {
            double uz = p->vz[i] - mean[2];
            u2 += ux * ux + uy * uy + uz * uz;
            continue;
        }
        u2 += ux * ux + uy * uy;
    }
    if (!isfinite(u2)) {
        return GR_FAIL(err, GR_EINVAL, "pv: non-finite velocity in the frame at t = %g", t);
    }
    s->frames++;
    s->particles += p->n;
    s->sum_u2 += u2;
    if (!s->fixed) {
        size_t need = (size_t)p->n * (size_t)s->dim;
        if (s->nbuf + need <= REF_MAX_VALUES) {
            if (s->nbuf + need > s->capbuf) {
                size_t cap = s->capbuf ? 2 * s->capbuf : need * REF_FRAMES;
                cap = cap < s->nbuf + need ? s->nbuf + need : cap;
                cap = cap > REF_MAX_VALUES ? REF_MAX_VALUES : cap;
                double *nb = realloc(s->buf, cap * sizeof(double));
                if (!nb) {
                    return GR_FAIL(err, GR_ENOMEM, "pv: out of memory for the reference frames");
                }
                s->buf = nb;
                s->capbuf = cap;
            }
            int rs = pv_species_buffer(&s->sp, p, err);
            if (rs) {
                return rs;
            }
            for (int i = 0; i < p->n; i++) {
                s->buf[s->nbuf++] = p->vx[i] - mean[0];
                if (s->dim >= 2) {
                    s->buf[s->nbuf++] = p->vy[i] - mean[1];
                }
                if (s->dim == 3) {
                    s->buf[s->nbuf++] = p->vz[i] - mean[2];
                }
            }
            s->ref_T_sum += u2 / p->n; /* T of this frame (2.19) */
            s->ref_frames++;
            return s->ref_frames >= REF_FRAMES ? fix_binning(s, err) : GR_OK;
        }
        if (s->ref_frames == 0) { /* one frame larger than the buffer: it alone sets T_ref */
            s->ref_T_sum = u2 / p->n;
            s->ref_frames = 1;
        }
        int rc = fix_binning(s, err);
        if (rc) {
            return rc;
        }
    }
    for (int i = 0; i < p->n; i++) {
        add_particle(s, s->sp.ns ? p->species[i] : -1, p->vx[i] - mean[0],
                     s->dim >= 2 ? p->vy[i] - mean[1] : 0.0,
                     s->dim == 3 ? p->vz[i] - mean[2] : 0.0);
    }
    return GR_OK;
}

/* ------------------------------------------------------------------------------------------
 * Fits. Velocities inside the fits are in units of sqrt(T_ref) (u = v / sqrt(T_ref)) to keep the
 * problems well scaled; the data are the counts X_i with errors sqrt(X_i) (A.4), as in the thesis. */

static double clamp_exp(double a) { return exp(a > 700.0 ? 700.0 : a); }

/* (5.5) with alpha fixed: X(u) = exp(q0 - (u / exp(q1))^alpha), q = (ln A_0, ln v0). */
static double model_fixed_alpha(double x, const double *q, double *g, void *user)
{
    double alpha = *(const double *)user;
    double z = x > 0.0 ? pow(x * exp(-q[1]), alpha) : 0.0;
    if (!isfinite(z)) {
        if (g) {
            g[0] = g[1] = 0.0;
        }
        return 0.0;
    }
    double y = clamp_exp(q[0] - z);
    if (g) {
        g[0] = y;
        g[1] = y * alpha * z;
    }
    return y;
}

/* The exponent of (5.32), E(u) = (u/v_r)^2 / (1 + |u/v_c|^(2 - alpha)) with q = (ln D, ln v_r, ln v_c),
 * and its derivatives dE/dq (dE/dq0 = 0). */
static double crossover_exponent(double x, const double *q, double beta, double dE[3])
{
    double ax = fabs(x);
    double r = ax * exp(-q[1]), gg = r * r;
    double hm1 = ax > 0.0 ? pow(ax * exp(-q[2]), beta) : 0.0, h = 1.0 + hm1;
    double E = isfinite(hm1) ? gg / h : 0.0;
    dE[0] = 0.0;
    dE[1] = -2.0 * E;
    dE[2] = isfinite(hm1) ? gg * beta * hm1 / (h * h) : 0.0;
    return E;
}

/* (5.32): X(u) = exp(q0 - E(u)), fitted to the counts. */
static double model_crossover(double x, const double *q, double *g, void *user)
{
    double dE[3], E = crossover_exponent(x, q, 2.0 - *(const double *)user, dE);
    double y = clamp_exp(q[0] - E);
    if (g) {
        g[0] = y;
        g[1] = -y * dE[1];
        g[2] = -y * dE[2];
    }
    return y;
}

/* ln of (5.32): ln X(u) = q0 - E(u), fitted to ln(counts) with equal weights (a fit on log axes). */
static double model_crossover_ln(double x, const double *q, double *g, void *user)
{
    double dE[3], E = crossover_exponent(x, q, 2.0 - *(const double *)user, dE);
    if (g) {
        g[0] = 1.0;
        g[1] = -dE[1];
        g[2] = -dE[2];
    }
    return q[0] - E;
}

static bool fit_finite(const gr_fit *f)
{
    if (!isfinite(f->chi2)) {
        return false;
    }
    for (int k = 0; k < f->n_params; k++) {
        if (!isfinite(f->p[k])) {
            return false;
        }
    }
    return true;
}

typedef struct points {
    int n;
    double *x, *y, *sig;  /* u, counts, sqrt(counts) */
    double *wx, *wy, *ws; /* scratch for the linearised starting fits */
} points;

static int points_alloc(points *pt, int cap)
{
    memset(pt, 0, sizeof *pt);
    size_t c = (size_t)(cap > 0 ? cap : 1);
    pt->x = malloc(c * sizeof(double));
    pt->y = malloc(c * sizeof(double));
    pt->sig = malloc(c * sizeof(double));
    pt->wx = malloc(c * sizeof(double));
    pt->wy = malloc(c * sizeof(double));
    pt->ws = malloc(c * sizeof(double));
    return pt->x && pt->y && pt->sig && pt->wx && pt->wy && pt->ws ? 0 : -1;
}

static void points_free(points *pt)
{
    free(pt->x);
    free(pt->y);
    free(pt->sig);
    free(pt->wx);
    free(pt->wy);
    free(pt->ws);
}

/* Bins of h with count in [cmin, cmax]; x = |centre| / scale (or the signed centre). */
static void points_select(points *pt, const gr_histogram *h, double scale, double cmin, double cmax,
                          bool absolute)
{
    pt->n = 0;
    for (int i = 0; i < h->nbins; i++) {
        double c = h->count[i];
        if (c >= cmin && c <= cmax && c > 0.0) {
            double x = gr_histogram_center(h, i) / scale;
            pt->x[pt->n] = absolute ? fabs(x) : x;
            pt->y[pt->n] = c;
            pt->sig[pt->n] = sqrt(c);
            pt->n++;
        }
    }
}

/* (5.5) with alpha fixed: start from the weighted line ln X = ln A_0 - B u^alpha (sigma_ln = 1/sqrt(X)),
 * then the chi-square fit on the counts. */
static bool fit_fixed_alpha(points *pt, double alpha, gr_fit *f)
{
    double xmax = 0.0, ymax = 0.0;
    for (int i = 0; i < pt->n; i++) {
        pt->wx[i] = pt->x[i] > 0.0 ? pow(pt->x[i], alpha) : 0.0;
        pt->wy[i] = log(pt->y[i]);
        pt->ws[i] = 1.0 / pt->sig[i];
        xmax = fmax(xmax, pt->x[i]);
        ymax = fmax(ymax, pt->y[i]);
    }
    gr_error e = {0};
    gr_fit lin;
    double q0[2] = {log(ymax), log(xmax > 0.0 ? xmax : 1.0)};
    if (gr_fit_line(pt->wx, pt->wy, pt->ws, pt->n, &lin, &e) == GR_OK && lin.p[1] < 0.0 &&
        isfinite(lin.p[0])) {
        q0[0] = lin.p[0];
        q0[1] = -log(-lin.p[1]) / alpha; /* v0 = B^(-1/alpha) */
    }
    if (gr_fit_nonlinear(model_fixed_alpha, &alpha, pt->x, pt->y, pt->sig, pt->n, 2, q0, f, &e) !=
        GR_OK) {
        return false;
    }
    return fit_finite(f);
}

typedef struct tail_result {
    double cmin, cmax;
    const char *reference;
    int n;
    double u_lo, u_hi, decades;
    bool any; /* at least one alpha of the scan fitted */
    bool accepted,
        contiguous; /* some alpha with chi2_red < CHI2_RED_MAX; accepted set in one piece */
    double alpha_lo, alpha_hi; /* accepted range */
    double alpha_best, chi2_best, lnA_best, lnv0_best,
        lnv0_err_best; /* smallest chi2_red of the scan */
    int nscan;
    double chi2_scan[MAX_SCAN]; /* chi2_red per alpha of the scan (NAN where the fit failed) */
    int pairs;                  /* mirrored bin pairs v, -v both inside the window */
    double
        dispersion; /* <(X(v) - X(-v))^2 / (X(v) + X(-v))> over those pairs: 1 for Poisson counts */
    bool free_ok;
    gr_fit free_fit; /* p = (A_0 counts, v0 in units of sqrt(T_ref), alpha) */
} tail_result;

static void fit_tail(points *pt, const gr_histogram *h, double scale, double cmin, double cmax,
                     const char *ref, tail_result *r)
{
    memset(r, 0, sizeof *r);
    r->cmin = cmin;
    r->cmax = cmax;
    r->reference = ref;
    r->chi2_best = HUGE_D;
    r->alpha_lo = r->alpha_hi = r->alpha_best = NOVALUE;
    points_select(pt, h, scale, cmin, cmax, true);
    r->n = pt->n;
    if (pt->n < MIN_FIT_POINTS) {
        return;
    }
    double ylo = HUGE_D, yhi = 0.0;
    r->u_lo = HUGE_D;
    for (int i = 0; i < pt->n; i++) {
        r->u_lo = fmin(r->u_lo, pt->x[i]);
        r->u_hi = fmax(r->u_hi, pt->x[i]);
        ylo = fmin(ylo, pt->y[i]);
        yhi = fmax(yhi, pt->y[i]);
    }
    r->decades = log10(yhi / ylo);
    /* Over-dispersion of the counts, from the symmetry P(v) = P(-v) of a steady state: for
     * independent (Poisson) counts X(v) - X(-v) has variance X(v) + X(-v). Correlated samples
     * (frames close in time, particles of one cluster) make it larger: sqrt(X) errors are then too
     * small by sqrt(dispersion). Not in the thesis; reported beside its acceptance rule. */
    double dsum = 0.0;
    for (int i = 0; i < h->nbins; i++) {
        int j = h->nbins - 1 - i;
        double a = h->count[i], b = h->count[j];
        if (gr_histogram_center(h, i) > 0.0 && a >= cmin && a <= cmax && b >= cmin && b <= cmax) {
            dsum += (a - b) * (a - b) / (a + b);
            r->pairs++;
        }
    }
    r->dispersion = r->pairs >= MIN_PAIRS ? dsum / r->pairs : NOVALUE;
    int nscan = (int)lround((ALPHA_SCAN_MAX - ALPHA_SCAN_MIN) / ALPHA_SCAN_STEP) + 1, last = -2,
        pieces = 0;
    nscan = nscan > MAX_SCAN ? MAX_SCAN : nscan;
    r->nscan = nscan;
    for (int k = 0; k < nscan; k++) {
        double alpha = ALPHA_SCAN_MIN + k * ALPHA_SCAN_STEP;
        gr_fit f;
        r->chi2_scan[k] = NOVALUE;
        if (!fit_fixed_alpha(pt, alpha, &f) || !isfinite(f.chi2_red)) {
            continue;
        }
        r->chi2_scan[k] = f.chi2_red;
        r->any = true;
        if (f.chi2_red < r->chi2_best) {
            r->chi2_best = f.chi2_red;
            r->alpha_best = alpha;
            r->lnA_best = f.p[0];
            r->lnv0_best = f.p[1];
            r->lnv0_err_best = f.err[1];
        }
        if (f.chi2_red < CHI2_RED_MAX) {
            if (!r->accepted) {
                r->alpha_lo = alpha;
            }
            r->accepted = true;
            r->alpha_hi = alpha;
            pieces += last != k - 1;
            last = k;
        }
    }
    r->contiguous = pieces == 1;
    if (!r->any) {
        return;
    }
    /* free fit of (5.5), started from the best alpha of the scan */
    gr_error e = {0};
    double p0[3] = {exp(r->lnA_best), exp(r->lnv0_best), r->alpha_best};
    r->free_ok =
        gr_fit_stretched_exp(pt->x, pt->y, pt->sig, pt->n, p0, &r->free_fit, &e) == GR_OK &&
        fit_finite(&r->free_fit) && r->free_fit.p[1] > 0.0 && r->free_fit.p[2] > 0.0 &&
        isfinite(r->free_fit.err[2]);
}

typedef struct crossover_result {
    bool ok;
    int n;
    gr_fit fit;        /* q = (ln D, ln v_r, ln v_c), v in units of sqrt(T_ref) */
    double u_data_max; /* largest |u| among the fitted points */
} crossover_result;

/* Two fits of (5.32) to the same bins (count >= cmin, COUNT_MIN in the summary's own):
 *  - `poisson`: the counts with sqrt(X) errors, the maximum-likelihood fit; the peak's bins, which
 *    hold most counts, decide it;
 *  - `log`: ln X with equal weights, the least-squares fit of the curve drawn on log axes (Fig. 5.14),
 *    where every bin counts the same and the tail pulls v_c in. The thesis says only "best fitting";
 *    docs/analysis-velocity.md compares the two with its Tables 5.3-5.4. */
static void fit_crossover(points *pt, const gr_histogram *h, double scale, double v_rms,
                          double cmin, bool log_axes, crossover_result *r)
{
    memset(r, 0, sizeof *r);
    points_select(pt, h, scale, cmin, HUGE_D, false);
    r->n = pt->n;
    if (pt->n < MIN_FIT_POINTS) {
        return;
    }
    double ymax = 0.0;
    for (int i = 0; i < pt->n; i++) {
        ymax = fmax(ymax, pt->y[i]);
        r->u_data_max = fmax(r->u_data_max, fabs(pt->x[i]));
        if (log_axes) {
            pt->y[i] = log(pt->y[i]); /* the selected counts are >= cmin > 0 */
        }
    }
    /* Gaussian start v_r = sqrt(2) v_rms; several crossover velocities, keep the best fit */
    double alpha = CROSSOVER_ALPHA, vr0 = sqrt(2.0) * v_rms / scale;
    const double vc_start[] = {0.5, 1.0, 2.0, 4.0, 8.0};
    for (size_t k = 0; k < sizeof vc_start / sizeof vc_start[0]; k++) {
        double q0[3] = {log(ymax), log(vr0), log(vc_start[k] * vr0)};
        gr_fit f;
        gr_error e = {0};
        int rc = log_axes ? gr_fit_nonlinear(model_crossover_ln, &alpha, pt->x, pt->y, NULL, pt->n,
                                             3, q0, &f, &e)
                          : gr_fit_nonlinear(model_crossover, &alpha, pt->x, pt->y, pt->sig, pt->n,
                                             3, q0, &f, &e);
        if (rc == GR_OK && fit_finite(&f) && (!r->ok || f.chi2 < r->fit.chi2)) {
            r->fit = f;
            r->ok = true;
        }
    }
    if (r->ok && log_axes && r->fit.dof > 0 && r->fit.chi2_red < 1.0) {
        /* unit weights: the scatter about the curve is the error of ln X, so the parameter errors
         * scale with sqrt(chi2/dof) both ways (gr_fit_nonlinear only scales them up) */
        for (int k = 0; k < 3; k++) {
            r->fit.err[k] *= sqrt(r->fit.chi2_red);
        }
    }
}

/* ------------------------------------------------------------------------------------------
 * Output. */

static void add_crossover_summary(cJSON *jx, const crossover_result *xo, const char *weighting,
                                  double scale, double v_rms, double norm)
{
    cJSON_AddStringToObject(
        jx, "equation", "P_0(v) = D exp(-(v/v_r)^2 / (1 + |v/v_c|^(2-alpha))) (5.32), alpha = 1");
    cJSON_AddStringToObject(jx, "weighting", weighting);
    cJSON_AddBoolToObject(jx, "converged", xo->ok);
    cJSON_AddNumberToObject(jx, "n_points", xo->n);
    gr_obs_add_number(jx, "counts_min", COUNT_MIN);
    gr_obs_add_number(jx, "alpha", CROSSOVER_ALPHA);
    if (xo->ok) {
        double vr = exp(xo->fit.p[1]) * scale, vc = exp(xo->fit.p[2]) * scale;
        gr_obs_add_number(jx, "D", exp(xo->fit.p[0]) / norm);
        gr_obs_add_number(jx, "v_r", vr);
        gr_obs_add_number(jx, "v_r_err", vr * xo->fit.err[1]);
        gr_obs_add_number(jx, "v_c", vc);
        gr_obs_add_number(jx, "v_c_err", vc * xo->fit.err[2]);
        gr_obs_add_number(jx, "v_c_over_v_r", vc / vr);
        gr_obs_add_number(jx, "v_A", vr * vr / vc);
        /* P_0(v_c)/P_0(0): at v = v_c the denominator of (5.32) is 2 (the thesis's column) */
        gr_obs_add_number(jx, "P_vc_over_P0", exp(-0.5 * (vc / vr) * (vc / vr)));
        gr_obs_add_number(jx, "v_r_over_vrms", vr / v_rms);
        gr_obs_add_number(jx, "chi2_red", xo->fit.chi2_red);
        cJSON_AddBoolToObject(jx, "v_c_beyond_data", vc > xo->u_data_max * scale);
    }
}

static void add_tail_summary(cJSON *j, const tail_result *r, double scale, double v_rms,
                             double total, double w)
{
    cJSON *win = cJSON_AddObjectToObject(j, "window");
    gr_obs_add_number(win, "counts_min", r->cmin);
    gr_obs_add_number(win, "counts_max", r->cmax);
    gr_obs_add_number(win, "chi2_red_max", CHI2_RED_MAX);
    cJSON_AddStringToObject(win, "reference", r->reference);
    cJSON_AddNumberToObject(j, "n_points", r->n);
    gr_obs_add_number(j, "v_min", r->n >= MIN_FIT_POINTS ? r->u_lo * scale : NOVALUE);
    gr_obs_add_number(j, "v_max", r->n >= MIN_FIT_POINTS ? r->u_hi * scale : NOVALUE);
    gr_obs_add_number(j, "decades", r->n >= MIN_FIT_POINTS ? r->decades : NOVALUE);
    cJSON_AddBoolToObject(j, "accepted", r->accepted);
    cJSON *range = cJSON_AddArrayToObject(j, "alpha_range");
    if (r->accepted) {
        cJSON_AddItemToArray(range, cJSON_CreateNumber(r->alpha_lo));
        cJSON_AddItemToArray(range, cJSON_CreateNumber(r->alpha_hi));
    }
    gr_obs_add_number(j, "alpha", r->accepted ? 0.5 * (r->alpha_lo + r->alpha_hi) : NOVALUE);
    gr_obs_add_number(j, "alpha_halfwidth",
                      r->accepted ? 0.5 * (r->alpha_hi - r->alpha_lo) : NOVALUE);
    cJSON_AddBoolToObject(j, "contiguous", r->contiguous);
    gr_obs_add_number(j, "alpha_step", ALPHA_SCAN_STEP);
    gr_obs_add_number(j, "alpha_best", r->any ? r->alpha_best : NOVALUE);
    gr_obs_add_number(j, "chi2_red", r->any ? r->chi2_best : NOVALUE);
    gr_obs_add_number(j, "v0", r->any ? exp(r->lnv0_best) * scale : NOVALUE);
    gr_obs_add_number(j, "v0_err", r->any ? exp(r->lnv0_best) * r->lnv0_err_best * scale : NOVALUE);
    gr_obs_add_number(j, "v0_over_vrms", r->any ? exp(r->lnv0_best) * scale / v_rms : NOVALUE);
    gr_obs_add_number(j, "A", r->any ? exp(r->lnA_best) / (total * w) : NOVALUE);
    /* the same acceptance with errors sqrt(dispersion X_i) (chi2_red / dispersion < 1.2) */
    cJSON *jd = cJSON_AddObjectToObject(j, "dispersion_corrected");
    gr_obs_add_number(jd, "dispersion", r->dispersion);
    cJSON_AddNumberToObject(jd, "pairs", r->pairs);
    double phi = isfinite(r->dispersion) ? fmax(1.0, r->dispersion) : NOVALUE, lo = NOVALUE,
           hi = NOVALUE;
    for (int k = 0; k < r->nscan && isfinite(phi); k++) {
        if (isfinite(r->chi2_scan[k]) && r->chi2_scan[k] / phi < CHI2_RED_MAX) {
            double alpha = ALPHA_SCAN_MIN + k * ALPHA_SCAN_STEP;
            lo = isfinite(lo) ? lo : alpha;
            hi = alpha;
        }
    }
    cJSON_AddBoolToObject(jd, "accepted", isfinite(lo));
    cJSON *drange = cJSON_AddArrayToObject(jd, "alpha_range");
    if (isfinite(lo)) {
        cJSON_AddItemToArray(drange, cJSON_CreateNumber(lo));
        cJSON_AddItemToArray(drange, cJSON_CreateNumber(hi));
    }
    gr_obs_add_number(jd, "alpha", 0.5 * (lo + hi));
    gr_obs_add_number(jd, "alpha_halfwidth", 0.5 * (hi - lo));
    gr_obs_add_number(jd, "chi2_red", r->any && isfinite(phi) ? r->chi2_best / phi : NOVALUE);
    cJSON *fr = cJSON_AddObjectToObject(j, "free");
    cJSON_AddBoolToObject(fr, "converged", r->free_ok);
    const gr_fit *f = &r->free_fit;
    gr_obs_add_number(fr, "alpha", r->free_ok ? f->p[2] : NOVALUE);
    gr_obs_add_number(fr, "alpha_err", r->free_ok ? f->err[2] : NOVALUE);
    gr_obs_add_number(fr, "v0", r->free_ok ? f->p[1] * scale : NOVALUE);
    gr_obs_add_number(fr, "v0_err", r->free_ok ? f->err[1] * scale : NOVALUE);
    gr_obs_add_number(fr, "A", r->free_ok ? f->p[0] / (total * w) : NOVALUE);
    gr_obs_add_number(fr, "chi2_red", r->free_ok ? f->chi2_red : NOVALUE);
    cJSON_AddNumberToObject(fr, "dof", r->free_ok ? f->dof : 0);
}

/* Density of the tail fit at v (free fit when it converged, else the best alpha of the scan). */
static double tail_density(const tail_result *r, double u, double total, double w)
{
    if (r->free_ok) {
        return r->free_fit.p[0] * exp(-pow(fabs(u) / r->free_fit.p[1], r->free_fit.p[2])) /
               (total * w);
    }
    if (r->any) {
        return exp(r->lnA_best - pow(fabs(u) / exp(r->lnv0_best), r->alpha_best)) / (total * w);
    }
    return NOVALUE;
}

typedef struct pv_rows_ctx {
    const pv *s;
    const tail_result *tail;
    const crossover_result *xo, *xo_log;
    double v_rms, P0, speed_rms;
} pv_rows_ctx;

const char gr_obs_pv_columns[] =
    "v [m s-1],density [s m-1],density_error [s m-1],counts [1],v_lo [m s-1],v_hi [m s-1],"
    "v_over_vrms [1],density_scaled [1],fit_stretched [s m-1],fit_crossover [s m-1],"
    "fit_crossover_log [s m-1]";

static void pv_rows(FILE *f, const void *ctx)
{
    const pv_rows_ctx *c = ctx;
    const gr_histogram *h = &c->s->comp;
    double scale = sqrt(c->s->T_ref), w = (h->hi - h->lo) / h->nbins, alpha = CROSSOVER_ALPHA,
           v_rms = c->v_rms;
    for (int i = 0; i < h->nbins; i++) {
        double v = gr_histogram_center(h, i), d = gr_histogram_density(h, i);
        double fx = c->xo->ok
                        ? model_crossover(v / scale, c->xo->fit.p, NULL, &alpha) / (h->total * w)
                        : NOVALUE;
        double fl = c->xo_log->ok ? model_crossover(v / scale, c->xo_log->fit.p, NULL, &alpha) /
                                        (h->total * w)
                                  : NOVALUE;
        fprintf(f, "%.10g,%.10g,%.6g,%.0f,%.10g,%.10g,%.8g,%.10g,%.6g,%.6g,%.6g\n", v, d,
                gr_histogram_density_error(h, i), h->count[i], gr_histogram_lower(h, i),
                gr_histogram_upper(h, i), v / v_rms, d * v_rms,
                tail_density(c->tail, v / scale, h->total, w), fx, fl);
    }
}

static int write_pv_csv(const gr_output *out, const pv_rows_ctx *c, gr_error *err)
{
    const gr_histogram *h = &c->s->comp;
    char what[1100];
    snprintf(what, sizeof what,
             "velocity distribution P(v) of one component (App. A.1; %s), relative to the frame's "
             "mean velocity, "
             "sampled uniformly in time; v in m/s on [-%g, %g) = pv_range sqrt(T_ref), T_ref = "
             "%.6g m^2/s^2; "
             "density in s/m normalised to all %.0f sampled components, density_error = "
             "sqrt(counts)/(N_s dv) (A.5); "
             "v_over_vrms = v/sqrt(<v_x^2>), density_scaled = density sqrt(<v_x^2>); fit_stretched "
             "= tail fit (5.5), "
             "fit_crossover = P_0(v) (5.32), alpha = 1, fitted to the counts, fit_crossover_log = "
             "the same fitted on "
             "log axes (summary members crossover and crossover_log)",
             c->s->dim == 3   ? "x, y and z pooled"
             : c->s->dim == 2 ? "x and y pooled"
                              : "1D",
             h->hi, h->hi, c->s->T_ref, h->total);
    const gr_obs_table t = {
        .name = "pv.csv",
        .what = what,
        .columns = gr_obs_pv_columns,
        .rows = pv_rows,
        .ctx = c,
    };
    return gr_obs_table_write(out, &t, err);
}

/* Positive half folded with the negative one: P(v) = (P(v) + P(-v))/2 (the bins are symmetric about
 * 0), and the variable of the tail plot (5.6). */
static void tail_rows(FILE *f, const void *ctx)
{
    const pv_rows_ctx *c = ctx;
    const gr_histogram *h = &c->s->comp;
    double w = (h->hi - h->lo) / h->nbins, v_rms = c->v_rms, P0 = c->P0;
    for (int i = 0; i < h->nbins; i++) {
        double v = gr_histogram_center(h, i);
        if (!(v > 0.0)) {
            continue;
        }
        double n = h->count[i] + h->count[h->nbins - 1 - i];
        if (n <= 0.0) {
            continue;
        }
        double d = n / (2.0 * h->total * w), de = sqrt(n) / (2.0 * h->total * w), ratio = d / P0;
        double moon = ratio > 0.0 && ratio < 1.0 ? -log(-log(ratio)) : NOVALUE;
        fprintf(f, "%.8g,%.8g,%.10g,%.6g,%.0f,%.8g,%.8g\n", v / v_rms, log(v / v_rms), d, de, n,
                ratio, moon);
    }
}

static int write_tail_csv(const gr_output *out, const pv_rows_ctx *c, gr_error *err)
{
    char what[600];
    snprintf(what, sizeof what,
             "tail of P(v) folded about 0, P_sym(v) = (P(v) + P(-v))/2 for v > 0, in s/m; v_rms = "
             "sqrt(<v_x^2>) = %.6g m/s, "
             "P(0) = %.6g s/m (the largest P(v)); moon = -ln(-ln(P_sym/P(0))) of the tail plot "
             "(5.6), nan where undefined",
             c->v_rms, c->P0);
    const gr_obs_table t = {
        .name = "pv_tail.csv",
        .what = what,
        .columns = "v_over_vrms [1],ln_v_over_vrms [1],density_sym [s m-1],density_sym_error [s "
                   "m-1],counts [1],"
                   "P_over_P0 [1],moon [1]",
        .rows = tail_rows,
        .ctx = c,
    };
    return gr_obs_table_write(out, &t, err);
}

static void speed_rows(FILE *f, const void *ctx)
{
    const pv_rows_ctx *c = ctx;
    const gr_histogram *h = &c->s->speed;
    double speed_rms = c->speed_rms;
    for (int i = 0; i < h->nbins; i++) {
        double v = gr_histogram_center(h, i);
        fprintf(f, "%.10g,%.10g,%.6g,%.0f,%.10g,%.10g,%.10g\n", v / speed_rms,
                gr_histogram_density(h, i) * speed_rms,
                gr_histogram_density_error(h, i) * speed_rms, h->count[i],
                gr_histogram_lower(h, i) / speed_rms, gr_histogram_upper(h, i) / speed_rms, v);
    }
}

static int write_speed_csv(const gr_output *out, const pv_rows_ctx *c, gr_error *err)
{
    char what[600];
    snprintf(what, sizeof what,
             "scaled speed distribution: c = |v|/sqrt(<|v|^2>) (|v| the %s relative to the frame's "
             "mean velocity), "
             "sqrt(<|v|^2>) = %.6g m/s over the run; density per unit c normalised to all %.0f "
             "sampled particles, "
             "sqrt(counts) errors (A.5); speed in m/s",
             c->s->dim >= 2 ? "speed" : "absolute velocity", c->speed_rms, c->s->speed.total);
    const gr_obs_table t = {
        .name = "pv_speed.csv",
        .what = what,
        .columns = "c [1],density [1],density_error [1],counts [1],c_lo [1],c_hi [1],speed [m s-1]",
        .rows = speed_rows,
        .ctx = c,
    };
    return gr_obs_table_write(out, &t, err);
}

/* C of the line -alpha_T ln(v/v_rms) + C (5.6) closest (least squares) to the tail-plot points with
 * at least COUNT_MIN counts, on the core (v < v_rms, for alpha_T = 2) or on the tail (v > v_rms). */
static double moon_constant(const pv *s, double v_rms, double P0, double alpha_T, bool core)
{
    const gr_histogram *h = &s->comp;
    double w = (h->hi - h->lo) / h->nbins, sum = 0.0;
    int n = 0;
    for (int i = 0; i < h->nbins; i++) {
        double v = gr_histogram_center(h, i);
        double c = v > 0.0 ? h->count[i] + h->count[h->nbins - 1 - i] : 0.0;
        if (c < COUNT_MIN || (core ? v >= v_rms : v <= v_rms)) {
            continue;
        }
        double ratio = c / (2.0 * h->total * w) / P0;
        if (ratio > 0.0 && ratio < 1.0) {
            sum += -log(-log(ratio)) + alpha_T * log(v / v_rms);
            n++;
        }
    }
    return n ? sum / n : NOVALUE;
}

static void draw_plots(const gr_output *out, const pv *s, const tail_result *tail, double v_rms,
                       double P0, double ymin, const double C[3])
{
    /* x ranges: where there are counts, plus a margin */
    double vlim = 0.0, slim = 0.0;
    for (int i = 0; i < s->comp.nbins; i++) {
        if (s->comp.count[i] > 0.0) {
            vlim = fmax(vlim, fabs(gr_histogram_upper(&s->comp, i)));
            vlim = fmax(vlim, fabs(gr_histogram_lower(&s->comp, i)));
        }
        if (s->speed.count[i] > 0.0) {
            slim = fmax(slim, gr_histogram_upper(&s->speed, i));
        }
    }
    vlim = vlim > 0.0 ? 1.05 * vlim : s->comp.hi;
    slim = (slim > 0.0 ? 1.05 * slim : s->speed.hi) / sqrt(s->sum_u2 / (double)s->particles);
    char body[4096], label[160];
    /* the tail fit is drawn over its window only (|v| in [v_lo, v_hi]), its alpha with the error */
    const double scale = sqrt(s->T_ref), v_lo = tail->n > 0 ? tail->u_lo * scale : 0.0,
                 v_hi = tail->n > 0 ? tail->u_hi * scale : 0.0;
    if (tail->accepted) {
        gr_plot_legend_value("fit (5.5), accepted \u03b1", 0.5 * (tail->alpha_lo + tail->alpha_hi),
                             0.5 * (tail->alpha_hi - tail->alpha_lo), label, sizeof label);
    } else if (tail->free_ok) {
        gr_plot_legend_value("free fit (5.5), \u03b1", tail->free_fit.p[2], tail->free_fit.err[2],
                             label, sizeof label);
    } else {
        snprintf(label, sizeof label, "fit (5.5), best \u03b1 of the scan = %.2f",
                 tail->alpha_best);
    }
    snprintf(body, sizeof body,
             "set logscale y\nset format y '10^{%%L}'\nset yrange [%g:*]\nset xrange [%g:%g]\n"
             "set xlabel 'v (m/s), one component'\nset ylabel 'P(v) (s/m)'\nset key top right\n"
             "set title \"Velocity distribution\\n{/*0.75 App. A.1; tail fit (5.5) over its "
             "window, crossover P_0 (5.32)}\"\n"
             "s = %.10g\ngauss(x) = exp(-x*x/(2*s*s))/sqrt(2*pi*s*s)\n"
             "plot 'pv.csv' skip 1 using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars lt 1 pt 7 ps 0.5 "
             "title 'P(v)', "
             "'' skip 1 using 1:((abs($1) >= %.10g && abs($1) <= %.10g) ? $9 : 1/0) with lines lw "
             "3 lt 2 title '%s', "
             "'' skip 1 using 1:10 with lines lw 2 dt 2 lt 3 title 'crossover P_0(v) (5.32)', "
             "gauss(x) with lines dt 3 lt 5 title 'Gaussian of the same <v^2>'",
             ymin, -vlim, vlim, v_rms, v_lo, v_hi, label);
    gr_obs_plot(out, "pv.png", body);

    snprintf(body, sizeof body,
             "set xlabel 'ln(v/v_{rms})'\nset ylabel '-ln(-ln(P(v)/P(0)))'\nset key top right\n"
             "set title \"Tail plot of Moon et al.: straight lines are stretched "
             "exponentials\\n{/*0.75 eq. (5.6), P(0) = %.4g s/m; "
             "lines of slope -\u03b1_T}\"\n"
             "plot 'pv_tail.csv' skip 1 using 2:7 with points lt 1 pt 7 ps 0.5 title 'data, "
             "(P(v)+P(-v))/2', "
             "-2*x + (%.10g) with lines lw 2 lt 5 title '\u03b1_T = 2 (Gaussian)', "
             "-1.5*x + (%.10g) with lines lw 2 dt 2 lt 2 title '\u03b1_T = 1.5', "
             "-1.16*x + (%.10g) with lines lw 2 dt 4 lt 3 title '\u03b1_T = 1.16'",
             P0, isfinite(C[0]) ? C[0] : 0.0, isfinite(C[1]) ? C[1] : 0.0,
             isfinite(C[2]) ? C[2] : 0.0);
    gr_obs_plot(out, "pv_tail.png", body);

    snprintf(body, sizeof body,
             "set logscale y\nset format y '10^{%%L}'\nset yrange [%g:*]\nset xrange [0:%g]\n"
             "set xlabel 'c = |v| / sqrt(<|v|^2>)'\nset ylabel 'P(c)'\n"
             "set title 'Distribution of the scaled %s'\n"
             "mb(c) = %s\n"
             "plot 'pv_speed.csv' skip 1 using 1:($4 > 0 ? $2 : 1/0):3 with yerrorbars lt 1 pt 7 "
             "ps 0.5 title 'data', "
             "mb(x) with lines lw 2 dt 2 lt 5 title 'Maxwell-Boltzmann, same <|v|^2>'",
             ymin * v_rms, slim, s->dim >= 2 ? "speed" : "|v|",
             s->dim == 3   ? "c > 0 ? 3*sqrt(6/pi)*c*c*exp(-1.5*c*c) : 1/0"
             : s->dim == 2 ? "c > 0 ? 2*c*exp(-c*c) : 1/0"
                           : "c > 0 ? sqrt(2/pi)*exp(-c*c/2) : 1/0");
    gr_obs_plot(out, "pv_speed.png", body);
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    pv *s = state;
    cJSON *j = cJSON_AddObjectToObject(out->summary, "pv");
    if (s->frames == 0) {
        cJSON_AddNumberToObject(j, "frames", 0);
        cJSON_AddStringToObject(j, "note", "no frames were sampled: no P(v), no files");
        return GR_OK;
    }
    cJSON_AddStringToObject(j, "file", "pv.csv");
    cJSON_AddNumberToObject(j, "frames", (double)s->frames);
    cJSON_AddNumberToObject(j, "bins", s->bins);
    cJSON_AddNumberToObject(j, "range", s->range);
    if (!s->fixed) {
        int rc = fix_binning(s, err);
        if (rc) {
            return rc;
        }
    }
    const gr_histogram *h = &s->comp;
    const double scale = sqrt(s->T_ref), w = (h->hi - h->lo) / h->nbins;
    const double T_mean = s->sum_u2 / (double)s->particles;
    const double v_rms = sqrt(T_mean / s->dim), speed_rms = sqrt(T_mean);
    double P0 = 0.0, ymin = HUGE_D;
    for (int i = 0; i < h->nbins; i++) {
        double d = gr_histogram_density(h, i);
        P0 = fmax(P0, d);
        if (d > 0.0) {
            ymin = fmin(ymin, d);
        }
    }
    ymin = isfinite(ymin) ? 0.3 * ymin : 1e-12;

    /* GSL reports through return values here: never abort the caller's process */
    gsl_error_handler_t *old_handler = gsl_set_error_handler_off();
    points pt;
    tail_result tail, tail_a1;
    crossover_result xo, xo_log;
    if (points_alloc(&pt, h->nbins)) {
        points_free(&pt);
        gsl_set_error_handler(old_handler);
        return GR_FAIL(err, GR_ENOMEM, "pv: out of memory for the fits");
    }
    fit_tail(&pt, h, scale, COUNT_MIN, COUNT_MAX_5_1, "Table 5.1", &tail);
    fit_tail(&pt, h, scale, COUNT_MIN, COUNT_MAX_A_1, "Table A.1", &tail_a1);
    fit_crossover(&pt, h, scale, v_rms, COUNT_MIN, false, &xo);
    fit_crossover(&pt, h, scale, v_rms, COUNT_MIN, true, &xo_log);

    /* free fits of (5.5) over single decades of counts: the local exponent along the tail */
    cJSON *local = cJSON_CreateArray();
    double cmax = 0.0;
    for (int i = 0; i < h->nbins; i++) {
        cmax = fmax(cmax, h->count[i]);
    }
    for (double lo = COUNT_MIN; lo < cmax && tail.any; lo *= 10.0) {
        points_select(&pt, h, scale, lo, 10.0 * lo, true);
        cJSON *d = cJSON_CreateObject();
        gr_obs_add_number(d, "counts_min", lo);
        gr_obs_add_number(d, "counts_max", 10.0 * lo);
        cJSON_AddNumberToObject(d, "n_points", pt.n);
        gr_fit f;
        gr_error e = {0};
        double p0[3] = {exp(tail.lnA_best), exp(tail.lnv0_best), tail.alpha_best};
        bool ok = pt.n >= MIN_DECADE_POINTS &&
                  gr_fit_stretched_exp(pt.x, pt.y, pt.sig, pt.n, p0, &f, &e) == GR_OK &&
                  fit_finite(&f) && f.p[1] > 0.0 && f.p[2] > 0.0 && isfinite(f.err[2]);
        cJSON_AddBoolToObject(d, "converged", ok);
        gr_obs_add_number(d, "alpha", ok ? f.p[2] : NOVALUE);
        gr_obs_add_number(d, "alpha_err", ok ? f.err[2] : NOVALUE);
        gr_obs_add_number(d, "v0", ok ? f.p[1] * scale : NOVALUE);
        gr_obs_add_number(d, "chi2_red", ok ? f.chi2_red : NOVALUE);
        cJSON_AddItemToArray(local, d);
    }
    /* the log-axes crossover fit over fewer decades below the peak (bins with >= 50, 500, 5000 and
     * 50 000 counts): how the fit's depth moves v_r and v_c (Tables 5.3-5.4; the thesis sampled 6-8
     * decades, sec. 5.3.4) */
    cJSON *by_depth = cJSON_CreateArray();
    for (double lo = COUNT_MIN; lo < cmax; lo *= 10.0) {
        crossover_result d = xo_log; /* counts >= COUNT_MIN: the fit above */
        if (lo > COUNT_MIN) {
            fit_crossover(&pt, h, scale, v_rms, lo, true, &d);
        }
        cJSON *o = cJSON_CreateObject();
        gr_obs_add_number(o, "counts_min", lo);
        gr_obs_add_number(o, "decades", log10(cmax / lo));
        cJSON_AddNumberToObject(o, "n_points", d.n);
        cJSON_AddBoolToObject(o, "converged", d.ok);
        const double vr = d.ok ? exp(d.fit.p[1]) * scale : NOVALUE,
                     vc = d.ok ? exp(d.fit.p[2]) * scale : NOVALUE;
        gr_obs_add_number(o, "v_r", vr);
        gr_obs_add_number(o, "v_r_err", d.ok ? vr * d.fit.err[1] : NOVALUE);
        gr_obs_add_number(o, "v_c_over_v_r", d.ok ? vc / vr : NOVALUE);
        gr_obs_add_number(o, "chi2_red", d.ok ? d.fit.chi2_red : NOVALUE);
        cJSON_AddItemToArray(by_depth, o);
    }
    points_free(&pt);
    gsl_set_error_handler(old_handler);

    /* summary */
    cJSON *files = cJSON_AddArrayToObject(j, "files");
    cJSON_AddItemToArray(files, cJSON_CreateString("pv.csv"));
    cJSON_AddItemToArray(files, cJSON_CreateString("pv_tail.csv"));
    cJSON_AddItemToArray(files, cJSON_CreateString("pv_speed.csv"));
    cJSON_AddNumberToObject(j, "components", h->total);
    gr_obs_add_number(j, "v_max", h->hi);
    gr_obs_add_number(j, "bin_width", w);
    gr_obs_add_number(j, "T_ref", s->T_ref);
    cJSON_AddNumberToObject(j, "T_ref_frames", s->ref_frames);
    gr_obs_add_number(j, "T_mean", T_mean);
    gr_obs_add_number(j, "v_rms", v_rms);
    gr_obs_add_number(j, "out_of_range_fraction",
                      h->total > 0.0 ? (h->below + h->above) / h->total : NOVALUE);
    gr_obs_add_number(j, "P0", P0);
    cJSON *jt = cJSON_AddObjectToObject(j, "tail");
    cJSON_AddStringToObject(
        jt, "equation",
        "P(v) = A exp(-(|v|/v0)^alpha) (5.5), fitted to counts with sqrt(X) errors");
    add_tail_summary(jt, &tail, scale, v_rms, h->total, w);
    cJSON_AddItemToObject(jt, "decades_local", local);
    cJSON *ja = cJSON_AddObjectToObject(j, "tail_a1");
    add_tail_summary(ja, &tail_a1, scale, v_rms, h->total, w);

    add_crossover_summary(cJSON_AddObjectToObject(j, "crossover"), &xo,
                          "Poisson: the counts with sqrt(X) errors", scale, v_rms, h->total * w);
    cJSON *jxl = cJSON_AddObjectToObject(j, "crossover_log");
    add_crossover_summary(jxl, &xo_log, "log axes: ln X with equal weights", scale, v_rms,
                          h->total * w);
    cJSON_AddItemToObject(jxl, "by_depth", by_depth);

    double C[3] = {moon_constant(s, v_rms, P0, 2.0, true), moon_constant(s, v_rms, P0, 1.5, false),
                   moon_constant(s, v_rms, P0, 1.16, false)};
    cJSON *jm = cJSON_AddObjectToObject(j, "moon");
    cJSON_AddStringToObject(jm, "equation", "-ln(-ln(P(v)/P(0))) = -alpha_T ln(v/v_rms) + C (5.6)");
    cJSON_AddStringToObject(jm, "file", "pv_tail.csv");
    gr_obs_add_number(jm, "C_alpha_2", C[0]);
    gr_obs_add_number(jm, "C_alpha_1_5", C[1]);
    gr_obs_add_number(jm, "C_alpha_1_16", C[2]);

    cJSON *jsp = cJSON_AddObjectToObject(j, "speed");
    cJSON_AddStringToObject(jsp, "file", "pv_speed.csv");
    gr_obs_add_number(jsp, "rms", speed_rms);
    gr_obs_add_number(jsp, "out_of_range_fraction",
                      s->speed.total > 0.0 ? (s->speed.below + s->speed.above) / s->speed.total
                                           : NOVALUE);

    const pv_rows_ctx rows = {.s = s,
                              .tail = &tail,
                              .xo = &xo,
                              .xo_log = &xo_log,
                              .v_rms = v_rms,
                              .P0 = P0,
                              .speed_rms = speed_rms};
    int rc = write_pv_csv(out, &rows, err);
    if (!rc) {
        rc = write_tail_csv(out, &rows, err);
    }
    if (!rc) {
        rc = write_speed_csv(out, &rows, err);
    }
    if (!rc) {
        rc = pv_species_finish(&s->sp, out, j, err);
    }
    if (!rc && out->plots) {
        draw_plots(out, s, &tail, v_rms, P0, ymin, C);
    }
    return rc;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    pv *s = state;
    uint32_t fixed = s->fixed;
    int64_t ref_frames = s->ref_frames;
    gr_blob_io_u32(io, &fixed);
    gr_blob_io_i64(io, &ref_frames);
    if (gr_blob_io_loading(io) && (ref_frames < 0 || ref_frames > REF_FRAMES)) {
        gr_blob_io_fail(io, "%lld reference frames (at most %d)", (long long)ref_frames,
                        REF_FRAMES);
    }
    s->ref_frames = (int)ref_frames;
    gr_blob_io_f64(io, &s->ref_T_sum);
    gr_blob_io_f64(io, &s->T_ref);
    if (gr_blob_io_bad(io)) {
        return GR_OK;
    }
    if (fixed) {
        bool ok = gr_obs_io_histogram_new(io, &s->comp) && gr_obs_io_histogram_new(io, &s->speed);
        s->fixed = ok;
        if (ok && (s->comp.nbins != s->bins || s->speed.nbins != s->bins)) {
            gr_blob_io_fail(io, "%d bins in the checkpoint, pv_bins = %d in the scene",
                            s->comp.nbins, s->bins);
        }
    } else {
        int64_t nbuf = (int64_t)s->nbuf;
        gr_blob_io_i64(io, &nbuf);
        if (gr_blob_io_loading(io) && (nbuf < 0 || (uint64_t)nbuf > REF_MAX_VALUES ||
                                       (uint64_t)nbuf > gr_blob_io_left(io) / sizeof(double))) {
            gr_blob_io_fail(io, "%lld buffered reference values do not fit", (long long)nbuf);
        }
        if (gr_blob_io_bad(io)) {
            return GR_OK;
        }
        if (gr_blob_io_loading(io)) {
            s->buf = malloc(sizeof(double) * (size_t)(nbuf > 0 ? nbuf : 1));
            if (!s->buf) {
                return GR_FAIL(err, GR_ENOMEM, "pv: out of memory for the reference frames");
            }
            s->nbuf = s->capbuf = (size_t)nbuf;
        }
        gr_blob_io_bytes(io, s->buf, sizeof(double) * (size_t)nbuf);
    }
    pv_species_io(&s->sp, io, s->fixed); /* nothing for one species: its bytes as before */
    gr_blob_io_i64(io, &s->frames);
    gr_blob_io_i64(io, &s->particles);
    gr_blob_io_f64(io, &s->sum_u2);
    return GR_OK;
}

const gr_observable_type gr_obs_pv = {
    .name = "pv",
    .summary = "velocity distribution P(v) per component (App. A.1), stretched-exponential tails "
               "(5.5) with the "
               "chi2_red < 1.2 acceptance of Table 5.1, crossover P_0(v) (5.32), tail plot (5.6), "
               "scaled |v|",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(pv_params),
    .state_size = sizeof(pv),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
