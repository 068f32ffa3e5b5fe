/* Chi-square fits with GSL: weighted lines and power laws (gsl_fit_wlinear), polynomials
 * (gsl_multifit_wlinear) and general nonlinear least squares (gsl_multifit_nlinear) with parameter
 * errors and reduced chi-square (physics notes sec. 6.2). */
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_fit.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"

static void finish(gr_fit *out, int n, int np)
{
    out->n_points = n;
    out->n_params = np;
    out->dof = n - np;
    out->chi2_red = out->dof > 0 ? out->chi2 / out->dof : (double)NAN;
    double scale = out->dof > 0 ? fmax(1.0, sqrt(out->chi2_red)) : 1.0;
    for (int i = 0; i < np; i++) {
        out->err[i] *= scale;
    }
}

int gr_fit_line(const double *x, const double *y, const double *sigma, int n, gr_fit *out,
                gr_error *err)
{
    memset(out, 0, sizeof *out);
    if (n < 2) {
        return GR_FAIL(err, GR_EINVAL, "line fit: need at least 2 points, got %d", n);
    }
    double *w = malloc(sizeof(double) * (size_t)n);
    if (!w) {
        return GR_FAIL(err, GR_ENOMEM, "line fit: out of memory");
    }
    for (int i = 0; i < n; i++) {
        w[i] = sigma ? 1.0 / (sigma[i] * sigma[i]) : 1.0;
    }
    double c0, c1, cov00, cov01, cov11, chi2;
    int rc = gsl_fit_wlinear(x, 1, w, 1, y, 1, (size_t)n, &c0, &c1, &cov00, &cov01, &cov11, &chi2);
    free(w);
    if (rc != GSL_SUCCESS || !isfinite(c0) || !isfinite(c1)) {
        return GR_FAIL(err, GR_EINVAL, "line fit failed: %s", gsl_strerror(rc));
    }
    out->p[0] = c0;
    out->p[1] = c1;
    out->err[0] = sqrt(cov00);
    out->err[1] = sqrt(cov11);
    out->chi2 = chi2;
    finish(out, n, 2);
    if (!sigma && out->dof > 0 && out->chi2_red < 1.0) {
        /* no errors given: the scatter itself estimates them (errors scale with sqrt(chi2/dof)) */
        out->err[0] *= sqrt(out->chi2_red);
        out->err[1] *= sqrt(out->chi2_red);
    }
    return GR_OK;
}

int gr_fit_poly(const double *x, const double *y, const double *sigma, int n, int degree,
                gr_fit *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    const int np = degree + 1;
    if (degree < 1 || np > GR_FIT_MAX_PARAMS || n < np) {
        return GR_FAIL(err, GR_EINVAL,
                       "polynomial fit of degree %d: need at least %d points, got %d", degree, np,
                       n);
    }
    gsl_matrix *X = gsl_matrix_alloc((size_t)n, (size_t)np), *cov = gsl_matrix_alloc(np, np);
    gsl_vector *yv = gsl_vector_alloc((size_t)n), *w = gsl_vector_alloc((size_t)n),
               *c = gsl_vector_alloc(np);
    gsl_multifit_linear_workspace *ws = gsl_multifit_linear_alloc((size_t)n, (size_t)np);
    int rc = GR_OK;
    if (!X || !cov || !yv || !w || !c || !ws) {
        rc = GR_FAIL(err, GR_ENOMEM, "polynomial fit: out of memory");
    } else {
        for (int i = 0; i < n; i++) {
            double xk = 1.0;
            for (int k = 0; k < np; k++, xk *= x[i]) {
                gsl_matrix_set(X, (size_t)i, (size_t)k, xk);
            }
            gsl_vector_set(yv, (size_t)i, y[i]);
            gsl_vector_set(w, (size_t)i, sigma ? 1.0 / (sigma[i] * sigma[i]) : 1.0);
        }
        double chi2;
        int g = gsl_multifit_wlinear(X, w, yv, c, cov, &chi2, ws);
        if (g != GSL_SUCCESS || !isfinite(chi2)) {
            rc = GR_FAIL(err, GR_EINVAL, "polynomial fit failed: %s", gsl_strerror(g));
        } else {
            for (int k = 0; k < np; k++) {
                out->p[k] = gsl_vector_get(c, (size_t)k);
                out->err[k] = sqrt(gsl_matrix_get(cov, (size_t)k, (size_t)k));
            }
            out->chi2 = chi2;
            finish(out, n, np);
            if (!sigma && out->dof > 0 && out->chi2_red < 1.0) { /* as gr_fit_line */
                for (int k = 0; k < np; k++) {
                    out->err[k] *= sqrt(out->chi2_red);
                }
            }
        }
    }
    gsl_multifit_linear_free(ws);
    gsl_matrix_free(X);
    gsl_matrix_free(cov);
    gsl_vector_free(yv);
    gsl_vector_free(w);
    gsl_vector_free(c);
    return rc;
}

int gr_fit_power_law(const double *x, const double *y, const double *sigma, int n, gr_fit *out,
                     gr_error *err)
{
    double *lx = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1)),
           *ly = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    double *ls = sigma ? malloc(sizeof(double) * (size_t)(n > 0 ? n : 1)) : NULL;
    if (!lx || !ly || (sigma && !ls)) {
        free(lx);
        free(ly);
        free(ls);
        return GR_FAIL(err, GR_ENOMEM, "power-law fit: out of memory");
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (x[i] > 0.0 && y[i] > 0.0 && (!sigma || sigma[i] > 0.0)) {
            lx[m] = log(x[i]);
            ly[m] = log(y[i]);
            if (ls) {
                ls[m] = sigma[i] / y[i];
            }
            m++;
        }
    }
    int rc = gr_fit_line(lx, ly, ls, m, out, err);
    free(lx);
    free(ly);
    free(ls);
    if (rc) {
        return rc;
    }
    /* p0 = ln A -> A, with error A * err(ln A) */
    out->p[0] = exp(out->p[0]);
    out->err[0] *= out->p[0];
    return GR_OK;
}

int gr_fit_power_law_seeds(const double *x, const double *y, const double *yerr, int n, gr_fit *out,
                           int *n_x, gr_error *err)
{
    double *mx = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1) * 3), *my = mx + (n > 0 ? n : 1),
           *ms = my + (n > 0 ? n : 1);
    if (!mx) {
        return GR_FAIL(err, GR_ENOMEM, "power-law fit: out of memory");
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        bool first = isfinite(y[i]);
        for (int k = 0; k < i && first; k++) {
            first = !(x[k] == x[i] && isfinite(y[k]));
        }
        if (!first) {
            continue; /* its x was averaged with an earlier run's */
        }
        double sum = 0.0, sum2 = 0.0, own2 = 0.0;
        int cnt = 0;
        for (int k = i; k < n; k++) {
            if (x[k] == x[i] && isfinite(y[k])) {
                sum += y[k];
                sum2 += y[k] * y[k];
                own2 += isfinite(yerr[k]) ? yerr[k] * yerr[k] : 0.0;
                cnt++;
            }
        }
        const double mean = sum / cnt;
        const double spread = cnt > 1 ? sqrt(fmax(sum2 / cnt - mean * mean, 0.0) / (cnt - 1)) : 0.0;
        mx[m] = x[i];
        my[m] = mean;
        ms[m] = fmax(spread, sqrt(own2) / cnt);
        m += ms[m] > 0.0;
    }
    *n_x = m;
    int rc = m >= GR_FIT_MIN_POINTS
                 ? gr_fit_power_law(mx, my, ms, m, out, err)
                 : GR_FAIL(err, GR_EINVAL, "power-law fit: %d distinct x with errors, %d needed", m,
                           GR_FIT_MIN_POINTS);
    free(mx);
    return rc;
}

typedef struct nl_data {
    gr_fit_model model;
    void *user;
    const double *x, *y, *sigma;
    int n, np;
} nl_data;

static int nl_f(const gsl_vector *p, void *data, gsl_vector *f)
{
    nl_data *d = data;
    for (int i = 0; i < d->n; i++) {
        double yi = d->model(d->x[i], p->data, NULL, d->user);
        if (!isfinite(yi)) {
            return GSL_EDOM;
        }
        gsl_vector_set(f, (size_t)i, (yi - d->y[i]) / (d->sigma ? d->sigma[i] : 1.0));
    }
    return GSL_SUCCESS;
}

static int nl_df(const gsl_vector *p, void *data, gsl_matrix *J)
{
    nl_data *d = data;
    double g[GR_FIT_MAX_PARAMS];
    for (int i = 0; i < d->n; i++) {
        d->model(d->x[i], p->data, g, d->user);
        double s = d->sigma ? d->sigma[i] : 1.0;
        for (int k = 0; k < d->np; k++) {
            gsl_matrix_set(J, (size_t)i, (size_t)k, g[k] / s);
        }
    }
    return GSL_SUCCESS;
}

int gr_fit_nonlinear(gr_fit_model model, void *user, const double *x, const double *y,
                     const double *sigma, int n, int n_params, const double *p0, gr_fit *out,
                     gr_error *err)
{
    memset(out, 0, sizeof *out);
    if (n_params < 1 || n_params > GR_FIT_MAX_PARAMS || n < n_params) {
        return GR_FAIL(err, GR_EINVAL, "nonlinear fit: %d points for %d parameters", n, n_params);
    }
    nl_data d = {model, user, x, y, sigma, n, n_params};
    gsl_multifit_nlinear_fdf fdf = {
        .f = nl_f, .df = nl_df, .fvv = NULL, .n = (size_t)n, .p = (size_t)n_params, .params = &d};
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    par.trs = gsl_multifit_nlinear_trs_lmaccel;
    gsl_multifit_nlinear_workspace *w =
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, (size_t)n, (size_t)n_params);
    gsl_vector *pv = gsl_vector_alloc((size_t)n_params);
    gsl_matrix *cov = gsl_matrix_alloc((size_t)n_params, (size_t)n_params);
    if (!w || !pv || !cov) {
        if (w)
            gsl_multifit_nlinear_free(w);
        if (pv)
            gsl_vector_free(pv);
        if (cov)
            gsl_matrix_free(cov);
        return GR_FAIL(err, GR_ENOMEM, "nonlinear fit: out of memory");
    }
    for (int k = 0; k < n_params; k++) {
        gsl_vector_set(pv, (size_t)k, p0[k]);
    }
    int info = 0, rc = gsl_multifit_nlinear_init(pv, &fdf, w);
    if (rc == GSL_SUCCESS) {
        rc = gsl_multifit_nlinear_driver(500, 1e-10, 1e-12, 1e-12, NULL, NULL, &info, w);
    }
    int status = GR_OK;
    if (rc == GSL_EMAXITER || rc == GSL_ENOPROG) {
        /* exact (zero-residual) data never meets the relative convergence tests: accept a fit
         * whose residual vanished */
        double chi = gsl_blas_dnrm2(gsl_multifit_nlinear_residual(w));
        if (chi * chi <= 1e-24 * n) {
            rc = GSL_SUCCESS;
        }
    }
    if (rc != GSL_SUCCESS) {
        status = GR_FAIL(err, GR_EINVAL, "nonlinear fit did not converge: %s", gsl_strerror(rc));
    } else {
        gsl_matrix *J = gsl_multifit_nlinear_jac(w);
        gsl_multifit_nlinear_covar(J, 0.0, cov);
        gsl_vector *f = gsl_multifit_nlinear_residual(w);
        double chi = gsl_blas_dnrm2(f);
        out->chi2 = chi * chi;
        for (int k = 0; k < n_params; k++) {
            out->p[k] = gsl_vector_get(w->x, (size_t)k);
            out->err[k] = sqrt(gsl_matrix_get(cov, (size_t)k, (size_t)k));
        }
        finish(out, n, n_params);
    }
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(pv);
    gsl_matrix_free(cov);
    return status;
}

/* y = A exp(-u), u = (x/tau)^beta, with q = (A, ln tau, beta) */
static double stretched(double x, const double *q, double *g, void *user)
{
    (void)user;
    double A = q[0], beta = q[2];
    double r = x > 0.0 ? log(x) - q[1] : -(double)INFINITY;
    double u = x > 0.0 ? exp(beta * r) : 0.0;
    double e = exp(-u);
    if (g) {
        g[0] = e;
        g[1] = x > 0.0 ? A * e * u * beta : 0.0;
        g[2] = x > 0.0 ? -A * e * u * r : 0.0;
    }
    return A * e;
}

int gr_fit_stretched_exp(const double *x, const double *y, const double *sigma, int n,
                         const double p0[3], gr_fit *out, gr_error *err)
{
    double q0[3] = {p0[0], log(p0[1]), p0[2]};
    int rc = gr_fit_nonlinear(stretched, NULL, x, y, sigma, n, 3, q0, out, err);
    if (rc) {
        return rc;
    }
    double tau = exp(out->p[1]);
    out->err[1] *= tau; /* d tau = tau d(ln tau) */
    out->p[1] = tau;
    return GR_OK;
}
