/* Fig. 5.10 in numbers from the two P(v) series alone (the SPM's and the RFM run's on the same
 * bins): what a campaign keeps of `granule spm full --compare-run`, so that an archived result set
 * gives the same numbers without the run's snapshots (docs/theory-spm.md). */
#include <math.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/spm.h"

#define SERIES_MIN_POINTS 4

/* A exp(-(v/v0)^alpha) over the bins v >= v_from where P > 0 with an error: alpha, its error and
 * the number of bins (NAN with fewer than 4). */
static void tail_alpha(const double *v, const double *p, const double *e, int n, double v_from,
                       double *alpha, double *alpha_err, int *points)
{
    *alpha = *alpha_err = (double)NAN;
    *points = 0;
    double x[GR_SPM_SERIES_MAX_BINS], y[GR_SPM_SERIES_MAX_BINS], s[GR_SPM_SERIES_MAX_BINS];
    int m = 0;
    for (int i = 0; i < n && m < GR_SPM_SERIES_MAX_BINS; i++) {
        if (v[i] >= v_from && p[i] > 0.0 && e[i] > 0.0 && isfinite(e[i])) {
            x[m] = v[i];
            y[m] = p[i];
            s[m++] = e[i];
        }
    }
    if (m < SERIES_MIN_POINTS) {
        return;
    }
    /* the start: the best of lines ln P = ln A - b v^a over a grid of a (a free start at a = 1
     * can settle far from a Gaussian tail) */
    gr_fit f;
    gr_error ignore = {0};
    double p0[3] = {y[0] * exp(1.0), x[0], 1.0}, best = INFINITY, xa[GR_SPM_SERIES_MAX_BINS],
           ly[GR_SPM_SERIES_MAX_BINS], ls[GR_SPM_SERIES_MAX_BINS];
    for (double a = 0.4; a <= 3.01; a += 0.1) {
        for (int i = 0; i < m; i++) {
            xa[i] = pow(x[i], a);
            ly[i] = log(y[i]);
            ls[i] = s[i] / y[i];
        }
        if (gr_fit_line(xa, ly, ls, m, &f, &ignore) == GR_OK && f.p[1] < 0.0 && f.chi2 < best) {
            best = f.chi2;
            p0[0] = exp(f.p[0]);
            p0[1] = pow(-f.p[1], -1.0 / a);
            p0[2] = a;
        }
    }
    const int rc = gr_fit_stretched_exp(x, y, s, m, p0, &f, &ignore);
    if (rc == GR_OK && isfinite(f.p[2])) {
        *alpha = f.p[2];
        *alpha_err = f.err[2];
        *points = m;
    }
}

int gr_spm_compare_series(const double *v, const double *p_spm, const double *e_spm,
                          const double *p_rfm, const double *e_rfm, int n, double from_vrms,
                          double z_max, gr_spm_series_compare *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    out->v_rms = out->v_from = (double)NAN;
    out->alpha_spm = out->alpha_spm_err = out->alpha_rfm = out->alpha_rfm_err = (double)NAN;
    if (n < 3 || n > GR_SPM_SERIES_MAX_BINS || !(from_vrms >= 0.0) || !(z_max > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm: the series comparison needs 3 to %d bins, from_vrms >= 0 and z_max > "
                       "0 (got %d, %g, %g)",
                       GR_SPM_SERIES_MAX_BINS, n, from_vrms, z_max);
    }
    /* the run's v_rms per component from its histogram, sum P v^2 / sum P (equal bins); the
     * comparison starts at from_vrms of it, as `spm full`'s --compare-from default (2 v_rms) */
    double s0 = 0.0, s2 = 0.0;
    for (int i = 0; i < n; i++) {
        if (p_rfm[i] > 0.0) {
            s0 += p_rfm[i];
            s2 += p_rfm[i] * v[i] * v[i];
        }
    }
    if (!(s0 > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: the run's P(v) is empty");
    }
    out->v_rms = sqrt(s2 / s0);
    out->v_from = from_vrms * out->v_rms;
    gr_error ignore = {0};
    /* Fig. 5.10: the SPM scaled vertically only; then also in v (the free-path scale it implies) */
    out->have_amp = gr_spm_compare_tails(v, p_spm, e_spm, p_rfm, e_rfm, n, out->v_from, z_max,
                                         false, &out->amp, &ignore) == GR_OK;
    out->have_scaled = gr_spm_compare_tails(v, p_spm, e_spm, p_rfm, e_rfm, n, out->v_from, z_max,
                                            true, &out->scaled, &ignore) == GR_OK;
    tail_alpha(v, p_spm, e_spm, n, out->v_from, &out->alpha_spm, &out->alpha_spm_err,
               &out->points_spm);
    tail_alpha(v, p_rfm, e_rfm, n, out->v_from, &out->alpha_rfm, &out->alpha_rfm_err,
               &out->points_rfm);
    if (!out->have_amp) {
        return GR_FAIL(err, GR_EINVAL, "spm: no bins with v >= %g where both P(v) are positive",
                       out->v_from);
    }
    return GR_OK;
}
