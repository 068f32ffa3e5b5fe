/* The RFM's measured P(v) against the SPM's asymptotic tail (thesis sec. 5.3.3, Figs. 5.12-5.13):
 * the fold of a P(v) table, the fit of 5.31 with alpha and h fixed, the tail plot
 * -ln(-ln(P/P')) of Fig. 5.13 for P' = P(0) and P' = A0, and C of 4.25 at a fixed D_f.
 * Declared in granule/spm.h; the campaign kind `spm` (src/app/reproduce/campaign_spm.c) applies them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/spm.h"

int gr_spm_fold_pv(const double *v, const double *p, const double *e, int n, double *vf, double *pf,
                   double *ef, double *counts)
{
    int m = 0;
    for (int i = n / 2; i < n; i++) {
        const int j = n - 1 - i; /* the mirror bin of i */
        const double width = n > 1 ? fabs(v[1] - v[0]) : 0.0;
        if (!(v[i] > 0.0) || fabs(v[i] + v[j]) > 0.01 * width) {
            if (v[i] > 0.0) {
                return 0; /* not symmetric about 0 */
            }
            continue;
        }
        vf[m] = v[i];
        pf[m] = 0.5 * (p[i] + p[j]);
        ef[m] = 0.5 * sqrt(e[i] * e[i] + e[j] * e[j]);
        /* sqrt(X) errors (A.5): e = sqrt(X) / (N dv), so X = (P / e)^2 */
        counts[m] = (e[i] > 0.0 ? (p[i] / e[i]) * (p[i] / e[i]) : 0.0) +
                    (e[j] > 0.0 ? (p[j] / e[j]) * (p[j] / e[j]) : 0.0);
        m++;
    }
    return m;
}

double gr_spm_tail531_log(double lnA0, double h, double S, double alpha, double v)
{
    return lnA0 + h * log(v) - S * pow(v, alpha); /* 5.31 with S = v_A^-alpha */
}

/* Every line fit below takes its errors from gr_fit_line, already scaled by sqrt(chi2/dof) where that
 * exceeds 1 (src/analysis/fit.c); they are not scaled again. */

/* The Fig. 5.13 slope of -ln(-ln(P/P')) against ln(v/v_rms) over the chosen bins (P < P' only). */
static void tail_plot_slope(const double *v, const double *p, const double *e, const int *use,
                            int n, double v_rms, double Pp, double *icpt, double *slope,
                            double *slope_err)
{
    double *x = malloc(3 * sizeof(double) * (size_t)(n > 0 ? n : 1)), *y = x + n, *s = y + n;
    int m = 0;
    for (int i = 0; x && i < n; i++) {
        const double r = p[i] / Pp;
        if (use[i] && r > 0.0 && r < 1.0) {
            x[m] = log(v[i] / v_rms);
            y[m] = -log(-log(r));
            s[m++] = e[i] / (p[i] * fabs(log(r))); /* d/dP of -ln(-ln(P/P')) */
        }
    }
    gr_fit f;
    gr_error ignore = {0};
    *icpt = *slope = *slope_err = (double)NAN;
    if (m >= GR_FIT_MIN_POINTS && gr_fit_line(x, y, s, m, &f, &ignore) == GR_OK) {
        *icpt = f.p[0];
        *slope = f.p[1];
        *slope_err = f.err[1];
    }
    free(x);
}

int gr_spm_tail531_fit(const double *v, const double *p, const double *e, const double *counts,
                       int n, double P0, double v_rms, double alpha, double h, double x_lo,
                       double x_hi, double counts_min, double S_pred, gr_spm_tail531 *out,
                       gr_error *err)
{
    memset(out, 0, sizeof *out);
    out->alpha = alpha;
    out->h = h;
    out->P0 = P0;
    if (!(alpha > 0.0) || !isfinite(h) || !(P0 > 0.0) || !(v_rms > 0.0) || !(x_hi > x_lo)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm tail: need alpha > 0, P(0) > 0, v_rms > 0 and a window, got alpha = "
                       "%g, P(0) = %g, "
                       "v_rms = %g, window %g-%g",
                       alpha, P0, v_rms, x_lo, x_hi);
    }
    int *use = calloc((size_t)(n > 0 ? n : 1), sizeof *use);
    double *x = malloc(3 * sizeof(double) * (size_t)(n > 0 ? n : 1)), *y = x ? x + n : NULL,
           *s = y ? y + n : NULL;
    if (!use || !x) {
        free(use);
        free(x);
        return GR_FAIL(err, GR_ENOMEM, "spm tail: out of memory");
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double xr = v[i] / v_rms;
        if (xr >= x_lo && xr <= x_hi && counts[i] >= counts_min && p[i] > 0.0 && e[i] > 0.0) {
            use[i] = 1;
            x[m] = pow(v[i], alpha);
            y[m] = log(p[i]) - h * log(v[i]);
            s[m++] = e[i] / p[i];
            out->v_lo = m == 1 ? v[i] : out->v_lo;
            out->v_hi = v[i];
        }
    }
    out->n_points = m;
    gr_fit f;
    int rc = m >= GR_FIT_MIN_POINTS
                 ? gr_fit_line(x, y, s, m, &f, err)
                 : GR_FAIL(err, GR_EINVAL,
                           "spm tail: %d bins in the window (v/v_rms %g-%g, >= %g counts), need %d",
                           m, x_lo, x_hi, counts_min, GR_FIT_MIN_POINTS);
    if (rc == GR_OK) {
        out->lnA0 = f.p[0];
        out->lnA0_err = f.err[0];
        out->S = -f.p[1];
        out->S_err = f.err[1];
        out->chi2_red = f.chi2_red;
        out->A0 = exp(out->lnA0);
        out->A0_over_P0 = out->A0 / P0;
        double plo = NAN, phi = NAN;
        for (int i = 0; i < n; i++) {
            if (use[i]) {
                plo = isfinite(plo) ? plo : p[i];
                phi = p[i];
            }
        }
        out->decades = log10(plo / phi);
        /* Fig. 5.12's line: 5.31 with S = S_pred, only the amplitude fitted (weighted mean) */
        double sw = 0.0, swy = 0.0;
        for (int k = 0; k < m && S_pred > 0.0; k++) {
            sw += 1.0 / (s[k] * s[k]);
            swy += (y[k] + S_pred * x[k]) / (s[k] * s[k]);
        }
        out->lnA0_at_S_pred = sw > 0.0 ? swy / sw : (double)NAN;
        tail_plot_slope(v, p, e, use, n, v_rms, P0, &out->icpt_P0, &out->slope_P0,
                        &out->slope_P0_err);
        tail_plot_slope(v, p, e, use, n, v_rms, out->A0, &out->icpt_A0, &out->slope_A0,
                        &out->slope_A0_err);
    }
    free(use);
    free(x);
    return rc;
}

int gr_spm_pl_fit_C(const double *l, const double *p, const double *e, int n, double beta,
                    double l_lo, double l_hi, double *C, double *C_err, double *chi2_red,
                    gr_error *err)
{
    *C = *C_err = *chi2_red = (double)NAN;
    if (!(beta > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "spm: 4.25 needs beta = D_f - 1 > 0, got %g", beta);
    }
    double *x = malloc(3 * sizeof(double) * (size_t)(n > 0 ? n : 1)), *y = x ? x + n : NULL,
           *s = y ? y + n : NULL;
    if (!x) {
        return GR_FAIL(err, GR_ENOMEM, "spm: out of memory");
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (l[i] >= l_lo && l[i] <= l_hi && l[i] > 0.0 && p[i] > 0.0 && e[i] > 0.0) {
            x[m] = pow(l[i], beta);
            y[m] = log(p[i]) - (beta - 1.0) * log(l[i]); /* 4.25: ln A0 - C l^beta */
            s[m++] = e[i] / p[i];
        }
    }
    gr_fit f;
    int rc = m >= GR_FIT_MIN_POINTS
                 ? gr_fit_line(x, y, s, m, &f, err)
                 : GR_FAIL(err, GR_EINVAL, "spm: %d free-path bins in %g-%g, need %d", m, l_lo,
                           l_hi, GR_FIT_MIN_POINTS);
    if (rc == GR_OK) {
        *C = -f.p[1];
        *C_err = f.err[1];
        *chi2_red = f.chi2_red;
    }
    free(x);
    return rc;
}
