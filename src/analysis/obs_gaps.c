/* gaps (1D only): the structure of the ring in reduced coordinates (thesis sec. 3.3).
 *
 * Reduced coordinates (3.16): the particle diameters are removed, r'_i = r_i - r_1 - (i - 1) d
 * (plus L when the ring was crossed), so N point particles live on a free ring of length
 * L' = L - N d, with r'_{i+N} = r'_i + L'. Contacting particles sit at the same reduced position.
 *
 * Per frame (sampled uniformly in time) this observable computes
 *   - the signed reduced gaps  s_i = ((x_{i+1} - x_i) mod L) - d,  i = 1..N (ring order, i + 1
 *     taken modulo N), i.e. s_i = r'_{i+1} - r'_i. Taking the centre distance modulo L makes
 *     unwrapped positions (during a run) and positions wrapped into [0, L) (snapshots) give the
 *     same gaps; the array order must be the ring order, which is checked: the centre distances
 *     must wind exactly once around the ring (sum = L), so sum_i s_i = L' exactly (3.19);
 *   - the h-th neighbour separations R_{i,i+h} = |r'_{i+h} - r'_i| = |s_i + ... + s_{i+h-1}|
 *     (3.17 for h = 1, 3.23), h = 1..gaps_h_max, in O(N h_max) per frame;
 * and accumulates
 *   - G_h(R;N) = (1/N) < sum_i delta(R - R_{i,i+h}) > (3.21, 3.24) as probability densities with
 *     sqrt(X) errors (App. A.1), in gaps_bins linear bins on [0, L') and, with gaps_log, in
 *     gaps_bins logarithmic bins on [1e-8 L', L') (Fig. 3.12). The binning depends on L' only,
 *     not on N, so runs with different N at the same L' share bins (renormalisation, 3.25);
 *   - the moments <R_{i,i+h}^m>, m = 1..12 ((3.18) for h = 1), averaged over i per frame and then
 *     over frames with block-averaging errors.
 * finish() also fits the logarithmic form (3.22), G_1 L' = A (-ln(R/L'))^(n_N - 1), to the bins
 * beyond the mean separation (R >= L'/N), and plots G_h on log-log axes against R and against
 * -ln(R/L') (Fig. 3.12).
 *
 * On a mixture (rods of their own lengths 2 r_i) the reduced coordinates remove each rod's own
 * length: s_i = ((x_{i+1} - x_i) mod L) - (r_i + r_{i+1}) and L' = L - sum_i 2 r_i, so (3.19) holds
 * as before; G_h is then that of the free ring of the mixture. With species lists the nearest-
 * neighbour separations R_{i,i+1} are also split by the kind of the pair (species a <= b of grains
 * i and i+1): per frame the number of such neighbour pairs and their mean R and R^2, time-averaged
 * with block-averaging errors (summary gaps.species_*). Weighted by the pair counts they are the
 * pooled <R> and <R^2> of h = 1; rods do not pass each other, so the counts are the placement's.
 *
 * Overlaps: soft particles in contact overlap by delta > 0, giving s_i = -delta < 0. Following
 * (3.17) literally the separation is |s_i| = delta (tiny against L'/N for stiff springs); then
 * <R> = L'/N + (2/N) sum(overlaps), while the signed mean <s> = L'/N holds exactly (3.19) and is
 * reported as a check together with the fraction of overlapping neighbour pairs.
 *
 * Renormalisation (3.25): G_h(R; hN) = G_1(R; N) at fixed L'. From one run of N particles,
 * G_h(R; N) is the distribution that the hypothesis compares with G_1(R; N/h) of a run with N/h
 * particles at the same L' (same R axis and same bins, no rescaling, since
 * <R_{i,i+h}>(N) = h L'/N = <R_{i,i+1}>(N/h)); likewise G_{2h}(R;N) against G_h(R;N/2)
 * (Fig. 3.13). gaps.csv also gives every G_h in mean-scaled form, x = R / (h L'/N) with density
 * (h L'/N) G_h, for overlays at different L'. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_util.h"
#include "io/plot.h"
#include "granule/analysis.h"

#define M_MAX 12    /* moments <R^m>, m = 1..12 (3.18) */
#define H_LIMIT 256 /* largest allowed gaps_h_max */
#define BINS_MIN 2
#define BINS_MAX 10000
#define LOG_DECADES 8.0   /* logarithmic bins cover [1e-8 L', L') */
#define FIT_MIN_COUNT 5.0 /* (3.22) is fitted to bins holding at least this many separations */

typedef struct gaps_params {
    int gaps_h_max, gaps_bins;
    bool gaps_log;
} gaps_params;

static const gr_param params[] = {
    {"gaps_h_max", "", GR_PARAM_INT, 8, 1, H_LIMIT, false, false,
     "1D: highest neighbour order h of G_h(R;N) and <R^m> (3.21, 3.24); at most N - 1",
     offsetof(gaps_params, gaps_h_max)},
    {"gaps_bins", "", GR_PARAM_INT, 200, BINS_MIN, BINS_MAX, false, false,
     "1D: bins of each G_h, linear on [0, L') and (gaps_log) logarithmic on [1e-8 L', L')",
     offsetof(gaps_params, gaps_bins)},
    {"gaps_log", "", GR_PARAM_BOOL, 1, 0, 1, false, false,
     "1D: also bin G_h logarithmically, for log-log and -ln R plots (Fig. 3.12)",
     offsetof(gaps_params, gaps_log)},
};

typedef struct gaps {
    int n, h_max, bins;
    bool log_bins;
    double L, d, Lr; /* ring length, diameter, reduced length L' = L - N d (3.16) */
    double mean;     /* L'/N (3.19) */
    int64_t frames;
    double *s;              /* the current frame's signed reduced gaps s_i = r'_{i+1} - r'_i */
    double *acc;            /* running sums s_i + ... + s_{i+h-1} = r'_{i+h} - r'_i */
    gr_histogram *lin, *lg; /* h_max each; lg only with gaps_log */
    gr_blocking (*mom)[M_MAX + 1]; /* [h-1][m]: per-frame <R_{i,i+h}^m> */
    gr_blocking signed_mean;       /* per-frame (1/N) sum s_i = L'/N (3.19) */
    double overlaps;               /* neighbour pairs with s_i < 0, summed over frames */
    double r1_min, r1_max;         /* extremes of R_{i,i+1} */
    /* species lists (ns >= 2; 0 otherwise): grain species, and per neighbour kind a <= b (index
     * a * ns + b) the per-frame pair count, mean R and mean R^2 of h = 1 */
    int ns;
    int *species;
    gr_blocking kind_count[GR_MAX_SPECIES * GR_MAX_SPECIES],
        kind_R[GR_MAX_SPECIES * GR_MAX_SPECIES], kind_R2[GR_MAX_SPECIES * GR_MAX_SPECIES];
} gaps;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    const gaps_params *a = params_block;
    if (setup->dim != 1) {
        return GR_FAIL(err, GR_EINVAL,
                       "gaps: defined for dim = 1 only (reduced coordinates 3.16), not dim = %d",
                       setup->dim);
    }
    if (setup->N < 2) {
        return GR_FAIL(err, GR_EINVAL, "gaps: need N >= 2 particles on the ring, got %d", setup->N);
    }
    /* a mixture: the rods' total length N 2 <r> (each gap is then the centre distance less
     * r_i + r_{i+1}) */
    double d = 2.0 * setup->radius,
           Lr =
               setup->L -
               setup->N * (setup->sizes && setup->radius_mean > 0.0 ? 2.0 * setup->radius_mean : d);
    if (!(setup->radius > 0.0) || !isfinite(setup->L) || !(Lr > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "gaps: need radius > 0 and a free length L' = L - N d > 0 (3.16); got L = "
                       "%g m, N = %d, d = %g m",
                       setup->L, setup->N, d);
    }
    if (a->gaps_h_max < 1 || a->gaps_h_max > H_LIMIT || a->gaps_h_max > setup->N - 1) {
        return GR_FAIL(err, GR_EINVAL,
                       "gaps: [analysis] gaps_h_max = %d must be in [1, %d] and at most N - 1 = %d",
                       a->gaps_h_max, H_LIMIT, setup->N - 1);
    }
    if (a->gaps_bins < BINS_MIN || a->gaps_bins > BINS_MAX) {
        return GR_FAIL(err, GR_EINVAL, "gaps: [analysis] gaps_bins = %d must be in [%d, %d]",
                       a->gaps_bins, BINS_MIN, BINS_MAX);
    }
    gaps *g = state;
    g->n = setup->N;
    g->h_max = a->gaps_h_max;
    g->bins = a->gaps_bins;
    g->log_bins = a->gaps_log;
    g->L = setup->L;
    g->d = d;
    g->Lr = Lr;
    g->mean = Lr / setup->N;
    g->r1_min = INFINITY;
    g->r1_max = -INFINITY;
    g->s = gr_obs_calloc(g, (size_t)g->n, sizeof(double));
    g->acc = gr_obs_calloc(g, (size_t)g->n, sizeof(double));
    g->lin = gr_obs_calloc(g, (size_t)g->h_max, sizeof *g->lin);
    g->lg = g->log_bins ? gr_obs_calloc(g, (size_t)g->h_max, sizeof *g->lg) : NULL;
    g->mom = gr_obs_calloc(g, (size_t)g->h_max, sizeof *g->mom);
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        g->ns = setup->n_species;
        g->species = gr_obs_calloc(g, (size_t)g->n, sizeof(int));
    }
    if (!g->s || !g->acc || !g->lin || (g->log_bins && !g->lg) || !g->mom) {
        return GR_FAIL(err, GR_ENOMEM, "gaps: out of memory for N = %d, h_max = %d", setup->N,
                       a->gaps_h_max);
    }
    for (int h = 0; h < g->h_max; h++) {
        int rc = gr_obs_histogram(g, &g->lin[h], g->bins, 0.0, Lr, false, err);
        if (!rc && g->log_bins) {
            rc = gr_obs_histogram(g, &g->lg[h], g->bins, Lr * pow(10.0, -LOG_DECADES), Lr, true,
                                  err);
        }
        if (rc) {
            return rc;
        }
    }
    return GR_OK;
}

/* A mixture's frame: the nearest-neighbour separations |s_i| by the kind of the pair (i, i + 1). */
static void species_frame(gaps *g)
{
    const int n = g->n, ns = g->ns;
    double cnt[GR_MAX_SPECIES * GR_MAX_SPECIES] = {0}, r1[GR_MAX_SPECIES * GR_MAX_SPECIES] = {0},
                                r2[GR_MAX_SPECIES * GR_MAX_SPECIES] = {0};
    for (int i = 0; i < n; i++) {
        int a = g->species[i], b = g->species[i + 1 < n ? i + 1 : 0];
        const int k = a < b ? a * ns + b : b * ns + a;
        const double R = fabs(g->s[i]);
        cnt[k] += 1.0;
        r1[k] += R;
        r2[k] += R * R;
    }
    for (int a = 0; a < ns; a++) {
        for (int b = a; b < ns; b++) {
            const int k = a * ns + b;
            gr_blocking_add(&g->kind_count[k], cnt[k]);
            if (cnt[k] > 0.0) { /* a kind absent from the ring has no mean */
                gr_blocking_add(&g->kind_R[k], r1[k] / cnt[k]);
                gr_blocking_add(&g->kind_R2[k], r2[k] / cnt[k]);
            }
        }
    }
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    gaps *g = state;
    if (p->dim != 1 || p->n != g->n || !p->x) {
        return GR_FAIL(err, GR_EINVAL,
                       "gaps: frame at t = %g s has %d particles in %dD, expected N = %d in 1D", t,
                       p->n, p->dim, g->n);
    }
    const double L = p->L, d = 2.0 * p->radius;
    double Lr = L - p->n * d;
    if (p->radii) { /* a mixture: L' = L - sum_i 2 r_i */
        Lr = L;
        for (int i = 0; i < p->n; i++) {
            Lr -= 2.0 * p->radii[i];
        }
    }
    if (!(fabs(Lr - g->Lr) <= 1e-9 * g->Lr + 1e-12 * L)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "gaps: frame at t = %g s has L' = L - N d = %.10g m, but the scene's L' is %.10g m", t,
            Lr, g->Lr);
    }
    const int n = p->n;
    const double *x = p->x;
    if (g->ns) {
        int rc = gr_obs_frame_species("gaps", p, g->ns, n, g->species, err);
        if (rc) {
            return rc;
        }
    }
    /* centre distances modulo L (unwrapped or wrapped positions alike); s_i = r'_{i+1} - r'_i */
    double wound = 0.0, signed_sum = 0.0;
    int overlaps = 0;
    for (int i = 0; i < n; i++) {
        double c = fmod(x[i + 1 < n ? i + 1 : 0] - x[i], L);
        if (c < 0.0) {
            c += L;
        }
        if (c >= L) {
            c -= L;
        }
        if (!isfinite(c)) {
            return GR_FAIL(err, GR_EINVAL,
                           "gaps: non-finite position of particle %d or %d at t = %g s", i,
                           i + 1 < n ? i + 1 : 0, t);
        }
        wound += c;
        g->s[i] = c - (p->radii ? p->radii[i] + p->radii[i + 1 < n ? i + 1 : 0] : d);
        signed_sum += g->s[i];
        overlaps += g->s[i] < 0.0;
    }
    /* ring order: the centre distances go exactly once around the ring */
    if (!(fabs(wound - L) <= 1e-6 * L)) {
        return GR_FAIL(err, GR_EINVAL,
                       "gaps: the particles at t = %g s are not in ring order (neighbour distances "
                       "add up to %.6g L, not L)",
                       t, wound / L);
    }
    for (int i = 0; i < n; i++) {
        g->acc[i] = 0.0;
    }
    for (int h = 1; h <= g->h_max; h++) {
        double sm[M_MAX + 1] = {0};
        gr_histogram *lin = &g->lin[h - 1], *lg = g->lg ? &g->lg[h - 1] : NULL;
        for (int i = 0; i < n; i++) {
            int k = i + h - 1;
            k = k >= n ? k - n : k; /* h <= n - 1, so one wrap at most */
            g->acc[i] += g->s[k];
            double R = fabs(g->acc[i]); /* R_{i,i+h} = |r'_{i+h} - r'_i| (3.17, 3.23) */
            gr_histogram_add(lin, R, 1.0);
            if (lg) {
                gr_histogram_add(lg, R, 1.0);
            }
            double pw = 1.0;
            for (int m = 1; m <= M_MAX; m++) {
                pw *= R;
                sm[m] += pw;
            }
            if (h == 1) {
                g->r1_min = fmin(g->r1_min, R);
                g->r1_max = fmax(g->r1_max, R);
            }
        }
        for (int m = 1; m <= M_MAX; m++) {
            gr_blocking_add(&g->mom[h - 1][m], sm[m] / n); /* (3.18), one term per sample time */
        }
    }
    gr_blocking_add(&g->signed_mean, signed_sum / n);
    if (g->ns) {
        species_frame(g);
    }
    g->overlaps += overlaps;
    g->frames++;
    return GR_OK;
}

/* A number, or null when it is not finite (e.g. an error bar from too few samples). */
static cJSON *num(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }

/* summary gaps.species_*: each neighbour kind's pairs per frame, <R> and <R^2> with errors */
static void species_summary(const gaps *g, cJSON *j)
{
    cJSON *kinds = cJSON_AddArrayToObject(j, "species_pairs");
    const char *name[6] = {"species_neighbours", "species_mean_R",        "species_mean_R_error",
                           "species_mean_R2",    "species_mean_R2_error", "species_R_over_mean"};
    cJSON *arr[6];
    for (int q = 0; q < 6; q++) {
        arr[q] = cJSON_AddArrayToObject(j, name[q]);
    }
    for (int a = 0; a < g->ns; a++) {
        for (int b = a; b < g->ns; b++) {
            const int k = a * g->ns + b;
            char label[32];
            snprintf(label, sizeof label, "%d-%d", a + 1, b + 1);
            cJSON_AddItemToArray(kinds, cJSON_CreateString(label));
            const double R = gr_blocking_mean(&g->kind_R[k]);
            cJSON_AddItemToArray(arr[0], num(gr_blocking_mean(&g->kind_count[k])));
            cJSON_AddItemToArray(arr[1], num(R));
            cJSON_AddItemToArray(arr[2], num(gr_obs_stderr(&g->kind_R[k])));
            cJSON_AddItemToArray(arr[3], num(gr_blocking_mean(&g->kind_R2[k])));
            cJSON_AddItemToArray(arr[4], num(gr_obs_stderr(&g->kind_R2[k])));
            cJSON_AddItemToArray(arr[5], num(R / g->mean));
        }
    }
    cJSON_AddStringToObject(j, "species_definition",
                            "nearest neighbours (h = 1) split by the species a <= b of the pair: "
                            "pairs per frame, and per frame the mean R and R^2 over them (m, m^2), "
                            "time-averaged with block-averaging errors; R_over_mean = <R>_ab / "
                            "(L'/N)");
}

/* The neighbour orders drawn in the plots: 1..4, then powers of two, and h_max. */
static int plot_orders(int h_max, int *hs)
{
    int k = 0;
    for (int h = 1; h <= h_max; h = h < 4 ? h + 1 : 2 * h) {
        hs[k++] = h;
    }
    if (hs[k - 1] != h_max) {
        hs[k++] = h_max;
    }
    return k;
}

static void write_plots(const gaps *g, const gr_output *out, const gr_fit *fit, bool fit_ok,
                        double u_lo, double u_hi)
{
    int hs[32], nh = plot_orders(g->h_max, hs);
    const char *bin = g->log_bins ? "log" : "lin";
    char body[8192];
    size_t len;

    /* G_h(R;N) on log-log axes; lines join the bins with 2 counts or more, and the bins of a
     * single count (a tail of lone events, all at one level) are open circles, not a flat line */
    len = (size_t)snprintf(
        body, sizeof body,
        "set logscale xy\nset format y '10^{%%L}'\nset format x '10^{%%L}'\nset key bottom left\n"
        "set xlabel \"R (m, reduced coordinates 3.16)\"\nset ylabel 'G_h(R;N) (1/m)'\n"
        "set title \"Distances to the h-th neighbour, N = %d, L' = %g m\\n{/*0.75 G_h(R;N), eqs. "
        "(3.21, 3.24); %s bins}\"\nplot ",
        g->n, g->Lr, bin);
    for (int k = 0; k < nh && len < sizeof body; k++) {
        len += (size_t)snprintf(
            body + len, sizeof body - len,
            "%s'gaps.csv' skip 1 using (($1 == %d && strcol(2) eq '%s' && $6 > 1) ? $5 : 1/0):7 "
            "with linespoints lt %d pt 7 ps 0.5 title 'h = %d', "
            "'gaps.csv' skip 1 using (($1 == %d && strcol(2) eq '%s' && $6 == 1) ? $5 : 1/0):7 "
            "with points lt %d pt 6 ps 0.5 notitle",
            k ? ", " : "", hs[k], bin, k + 1, hs[k], hs[k], bin, k + 1);
    }
    if (len < sizeof body) {
        gr_obs_plot(out, "gaps.png", body);
    }

    /* Fig. 3.12: G_h L' against -ln(R/L') on log-log axes, with the fit (3.22) for h = 1 */
    len =
        (size_t)snprintf(body, sizeof body,
                         "set logscale xy\nset format y '10^{%%L}'\nset key top left\n"
                         "set xlabel \"-ln(R/L')\"\nset ylabel \"G_h(R;N) L'\"\n"
                         "set title \"Neighbour distributions against -ln(R/L'), N = %d\\n{/*0.75 "
                         "Fig. 3.12; fit of (3.22) to h = 1 over its window; %s bins}\"\nplot ",
                         g->n, bin);
    for (int k = 0; k < nh && len < sizeof body; k++) {
        len += (size_t)snprintf(body + len, sizeof body - len,
                                "%s'gaps.csv' skip 1 using (($1 == %d && strcol(2) eq '%s' && $6 > "
                                "1 && $9 > 0) ? $9 : 1/0):($7 * %.10g) "
                                "with linespoints lt %d pt 7 ps 0.5 title 'h = %d', "
                                "'gaps.csv' skip 1 using (($1 == %d && strcol(2) eq '%s' && $6 == "
                                "1 && $9 > 0) ? $9 : 1/0):($7 * %.10g) "
                                "with points lt %d pt 6 ps 0.5 notitle",
                                k ? ", " : "", hs[k], bin, g->Lr, k + 1, hs[k], hs[k], bin, g->Lr,
                                k + 1);
    }
    if (fit_ok && len < sizeof body) {
        char legend[120];
        gr_plot_legend_value("fit (3.22), n_N", fit->p[1] + 1.0, fit->err[1], legend,
                             sizeof legend);
        len += (size_t)snprintf(
            body + len, sizeof body - len,
            ", [%.10g:%.10g] %.10g * x**%.10g with lines lw 4 dt 2 lc rgb '#707070' title '%s'",
            u_lo, u_hi, fit->p[0], fit->p[1], legend);
    }
    if (len < sizeof body) {
        gr_obs_plot(out, "gaps_lnR.png", body);
    }

    /* reduced moments <(R_h / <R_h>)^m> against m, with the Poisson (Gamma(h)) values */
    len = (size_t)snprintf(
        body, sizeof body,
        "set logscale y\nset format y '10^{%%L}'\nset key top left\nset xlabel 'm'\n"
        "set ylabel \"<(R_{i,i+h} N / (h L'))^m>\"\n"
        "set title \"Moments of the neighbour separations, N = %d\\n{/*0.75 eq. (3.18); dashed: "
        "Poisson points (Gamma(h))}\"\n"
        "set xrange [0.5:%d.5]\nplot ",
        g->n, M_MAX);
    for (int k = 0; k < nh && len < sizeof body; k++) {
        len += (size_t)snprintf(
            body + len, sizeof body - len,
            "%s'gaps_moments.csv' skip 1 using ($1 == %d ? $2 : 1/0):5:6 with yerrorlines pt 7 ps "
            "0.6 lc %d title 'h = %d', "
            "[1:%d] exp(lgamma(%d + x) - lgamma(%d) - x * log(%d)) with lines dt 2 lc %d notitle",
            k ? ", " : "", hs[k], k + 1, hs[k], M_MAX, hs[k], hs[k], hs[k], k + 1);
    }
    if (len < sizeof body) {
        gr_obs_plot(out, "gaps_moments.png", body);
    }
}

const char gr_obs_gaps_columns[] =
    "h [1],binning [],R_lo [m],R_hi [m],R [m],count [1],density [m-1],density_error [m-1],neg_ln_R "
    "[1],x [1],density_x [1],density_x_error [1]";

static void gaps_rows(FILE *f, const void *ctx)
{
    const gaps *g = ctx;
    for (int h = 1; h <= g->h_max; h++) {
        double scale = h * g->mean;
        for (int b = 0; b < (g->log_bins ? 2 : 1); b++) {
            const gr_histogram *hist = b ? &g->lg[h - 1] : &g->lin[h - 1];
            for (int i = 0; i < hist->nbins; i++) {
                double R = gr_histogram_center(hist, i), den = gr_histogram_density(hist, i),
                       de = gr_histogram_density_error(hist, i);
                fprintf(f, "%d,%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.6g,%.10g,%.10g,%.10g,%.6g\n", h,
                        b ? "log" : "lin", gr_histogram_lower(hist, i), gr_histogram_upper(hist, i),
                        R, hist->count[i], den, de, -log(R / g->Lr), R / scale, den * scale,
                        de * scale);
            }
        }
    }
}

/* gaps_moments.csv rows; the summary's moment arrays are filled on the way */
typedef struct moment_rows_ctx {
    const gaps *g;
    cJSON *jm, *je, *jr, *jh;
} moment_rows_ctx;

static void moment_rows(FILE *f, const void *ctx)
{
    const moment_rows_ctx *c = ctx;
    const gaps *g = c->g;
    for (int h = 1; h <= g->h_max; h++) {
        double scale = h * g->mean;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "h", h);
        cJSON *jo = cJSON_AddArrayToObject(o, "moments_reduced");
        for (int m = 1; m <= M_MAX; m++) {
            const gr_blocking *bl = &g->mom[h - 1][m];
            int conv = 0;
            double mk = gr_blocking_mean(bl), ek = gr_blocking_stderr(bl, NULL, &conv),
                   sc = pow(scale, m);
            fprintf(f, "%d,%d,%.15g,%.6g,%.15g,%.6g,%d,%lld\n", h, m, mk, ek, mk / sc, ek / sc,
                    conv, (long long)bl->count[0]);
            cJSON_AddItemToArray(jo, num(mk / sc));
            if (m == 1) {
                cJSON_AddItemToObject(o, "mean", num(mk));
                cJSON_AddItemToObject(o, "mean_stderr", num(ek));
            }
            if (h == 1) {
                cJSON_AddItemToArray(c->jm, num(mk));
                cJSON_AddItemToArray(c->je, num(ek));
                cJSON_AddItemToArray(c->jr, num(mk / sc));
            }
        }
        const gr_histogram *lin = &g->lin[h - 1];
        cJSON_AddItemToObject(o, "beyond_reduced_length",
                              num(lin->total > 0 ? lin->above / lin->total : (double)NAN));
        if (g->log_bins) {
            const gr_histogram *lg = &g->lg[h - 1];
            cJSON_AddItemToObject(o, "below_log_range",
                                  num(lg->total > 0 ? lg->below / lg->total : (double)NAN));
        }
        cJSON_AddItemToArray(c->jh, o);
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    gaps *g = state;
    cJSON *j = cJSON_AddObjectToObject(out->summary, "gaps");
    cJSON_AddNumberToObject(j, "N", g->n);
    cJSON_AddNumberToObject(j, "reduced_length", g->Lr);
    cJSON_AddNumberToObject(j, "mean_separation", g->mean);
    cJSON_AddNumberToObject(j, "h_max", g->h_max);
    cJSON_AddNumberToObject(j, "bins", g->bins);
    cJSON_AddBoolToObject(j, "log_bins", g->log_bins);
    cJSON_AddNumberToObject(j, "samples", (double)g->frames);
    cJSON_AddStringToObject(j, "file", "gaps.csv");
    cJSON_AddStringToObject(j, "moments_file", "gaps_moments.csv");
    if (g->frames == 0) {
        cJSON_AddStringToObject(j, "note", "no samples");
    } else if (g->ns) {
        species_summary(g, j);
    }

    /* ---- gaps.csv: every G_h in every binning ---- */
    gr_obs_table t = {
        .name = "gaps.csv",
        .what =
            "h-th neighbour separation distributions G_h(R;N) (3.21, 3.24) in reduced coordinates "
            "(3.16), R = |r'_{i+h} - r'_i| in m; density in 1/m with sqrt(X) errors (App. A.1), "
            "normalised by all separations sampled; neg_ln_R = -ln(R/L') (Fig. 3.12); "
            "x = R N / (h L') and density_x = density h L' / N (mean-scaled, for 3.25 overlays)",
        .columns = gr_obs_gaps_columns,
        .rows = gaps_rows,
        .ctx = g,
    };
    int rc = gr_obs_table_write(out, &t, err);
    if (rc) {
        return rc;
    }

    /* ---- gaps_moments.csv: <R_{i,i+h}^m> (3.18 for h = 1), and the same into the summary ---- */
    const moment_rows_ctx mrows = {
        .g = g,
        .jm = cJSON_AddArrayToObject(j, "moments"),
        .je = cJSON_AddArrayToObject(j, "moments_stderr"),
        .jr = cJSON_AddArrayToObject(j, "moments_reduced"),
        .jh = cJSON_AddArrayToObject(j, "neighbours"),
    };
    t = (gr_obs_table){
        .name = "gaps_moments.csv",
        .what = "moments <R^m> of the h-th neighbour separations R_{i,i+h} (3.18 for h = 1) in "
                "m^m, averaged "
                "over particles and uniformly in time, block-averaging errors; reduced = <(R N / "
                "(h L'))^m> "
                "(Poisson points: Gamma(h + m) / (Gamma(h) h^m) for large N)",
        .columns = "h [1],m [1],moment [m^m],stderr [m^m],reduced_moment [1],reduced_stderr "
                   "[1],converged [1],samples [1]",
        .rows = moment_rows,
        .ctx = &mrows,
    };
    rc = gr_obs_table_write(out, &t, err);
    if (rc) {
        return rc;
    }

    /* ---- checks and the (3.22) fit ---- */
    double nsep = (double)g->frames * g->n;
    cJSON_AddItemToObject(j, "mean_signed_separation", num(gr_blocking_mean(&g->signed_mean)));
    cJSON_AddItemToObject(j, "overlap_fraction", num(nsep > 0 ? g->overlaps / nsep : (double)NAN));
    cJSON_AddItemToObject(j, "R1_min", num(g->r1_min));
    cJSON_AddItemToObject(j, "R1_max", num(g->r1_max));
    if (g->log_bins) {
        cJSON *lr = cJSON_AddArrayToObject(j, "log_range");
        cJSON_AddItemToArray(lr, cJSON_CreateNumber(g->lg[0].lo));
        cJSON_AddItemToArray(lr, cJSON_CreateNumber(g->lg[0].hi));
    }

    /* (3.22): G_1(R;N) L' = A (-ln(R/L'))^(n_N - 1) at large R, here every bin beyond the mean
     * separation, L'/N <= R < L' (Fig. 3.12: the form holds at large R and bends away at small R,
     * where collisions dominate) */
    const gr_histogram *h1 = g->log_bins ? &g->lg[0] : &g->lin[0];
    double *fx = malloc(sizeof(double) * (size_t)h1->nbins),
           *fy = malloc(sizeof(double) * (size_t)h1->nbins),
           *fs = malloc(sizeof(double) * (size_t)h1->nbins);
    int np = 0;
    double u_lo = INFINITY, u_hi = -INFINITY;
    gr_fit fit = {0};
    bool fit_ok = false;
    if (fx && fy && fs) {
        for (int i = 0; i < h1->nbins; i++) {
            double R = gr_histogram_center(h1, i), G = gr_histogram_density(h1, i) * g->Lr;
            if (h1->count[i] >= FIT_MIN_COUNT && gr_histogram_lower(h1, i) >= g->mean &&
                R < g->Lr) {
                fx[np] = -log(R / g->Lr);
                u_lo = fmin(u_lo, fx[np]);
                u_hi = fmax(u_hi, fx[np]);
                fy[np] = G;
                fs[np] = gr_histogram_density_error(h1, i) * g->Lr;
                np++;
            }
        }
        gr_error fit_err = {0};
        fit_ok =
            np >= GR_FIT_MIN_POINTS && gr_fit_power_law(fx, fy, fs, np, &fit, &fit_err) == GR_OK;
    }
    free(fx);
    free(fy);
    free(fs);
    cJSON *jf = cJSON_AddObjectToObject(j, "fit_3_22");
    cJSON_AddStringToObject(
        jf, "form",
        "G_1(R;N) L' = A (-ln(R/L'))^(n_N - 1), bins with L'/N <= R < L' and >= 5 counts");
    cJSON_AddNumberToObject(jf, "points", np);
    if (np > 0) {
        cJSON_AddNumberToObject(jf, "neg_ln_R_min", u_lo);
        cJSON_AddNumberToObject(jf, "neg_ln_R_max", u_hi);
    }
    if (fit_ok) {
        cJSON_AddItemToObject(jf, "n_N", num(fit.p[1] + 1.0));
        cJSON_AddItemToObject(jf, "n_N_stderr", num(fit.err[1]));
        cJSON_AddItemToObject(jf, "A", num(fit.p[0]));
        cJSON_AddItemToObject(jf, "chi2_red", num(fit.chi2_red));
    } else {
        cJSON_AddStringToObject(jf, "note", "fewer than 3 usable bins in the tail: no fit");
    }

    if (out->plots && g->frames > 0) {
        write_plots(g, out, &fit, fit_ok, u_lo, u_hi);
    }
    return GR_OK;
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    gaps *g = state;
    gr_blob_io_check(io, "gaps_h_max", g->h_max);
    gr_blob_io_i64(io, &g->frames);
    for (int h = 0; h < g->h_max; h++) {
        gr_obs_io_histogram(io, &g->lin[h]);
        if (g->log_bins) {
            gr_obs_io_histogram(io, &g->lg[h]);
        }
        gr_obs_io_blockings(io, g->mom[h], M_MAX + 1);
    }
    gr_obs_io_blockings(io, &g->signed_mean, 1);
    gr_blob_io_f64(io, &g->overlaps);
    gr_blob_io_f64(io, &g->r1_min);
    gr_blob_io_f64(io, &g->r1_max);
    if (g->ns) { /* a mixture's (one species: the checkpoint as before) */
        const int kinds = g->ns * g->ns;
        gr_obs_io_blockings(io, g->kind_count, kinds);
        gr_obs_io_blockings(io, g->kind_R, kinds);
        gr_obs_io_blockings(io, g->kind_R2, kinds);
    }
    return GR_OK;
}

const gr_observable_type gr_obs_gaps = {
    .name = "gaps",
    .summary =
        "1D neighbour separations in reduced coordinates (3.16-3.17): G_h(R;N), h = 1..gaps_h_max "
        "(3.21, 3.24, Figs. 3.10-3.13), moments <R^m>, m = 1..12 (3.18), block-averaging errors",
    .dims = 1,
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(gaps_params),
    .state_size = sizeof(gaps),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
