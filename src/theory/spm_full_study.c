/* granule spm full as a library call: the SPM P(v) with l drawn from P_l (thesis sec. 5.2.3), its
 * tail fits (a free stretched exponential; 5.31 with the predicted alpha) and the comparison with
 * a Random Force Model run (Fig. 5.10); see granule/spm_study.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/spm_study.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "theory/spm_output.h"

void gr_spm_full_params_default(gr_spm_full_params *p)
{
    memset(p, 0, sizeof *p);
    gr_spm_settings_default(&p->s);
    p->s.walks = 200000;
    p->bins = 100;
    p->df = p->C = p->vmax = p->fit_from = p->t_from = p->compare_from = p->diameter = (double)NAN;
    p->tail_from = 0.0;
    p->z_max = 3.0;
    p->weight_time = true;
}

/* Mass, D, dim, warm-up and particle diameter from a run folder's summary.json (any may stay
 * unknown: NAN or 0). */
static void run_scene(const char *dir, double *mass, double *D, int *dim, double *warmup,
                      double *diameter)
{
    *mass = *D = *warmup = *diameter = (double)NAN;
    *dim = 0;
    gr_error err = {0};
    cJSON *j = gr_summary_read(dir, &err);
    if (!j) {
        return;
    }
    cJSON *sc = cJSON_GetObjectItem(j, "scene");
    cJSON *x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "mass");
    if (cJSON_IsNumber(x)) {
        *mass = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "dim");
    if (cJSON_IsNumber(x)) {
        *dim = x->valueint;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "noise"), "D");
    if (cJSON_IsNumber(x)) {
        *D = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "run"), "warmup");
    if (cJSON_IsNumber(x)) {
        *warmup = x->valuedouble;
    }
    x = cJSON_GetObjectItem(cJSON_GetObjectItem(sc, "system"), "radius");
    if (cJSON_IsNumber(x)) {
        *diameter = 2.0 * x->valuedouble;
    }
    cJSON_Delete(j);
}

double gr_spm_pl_diameter(const char *pl_path, double given)
{
    if (given > 0.0) {
        return given;
    }
    char dir[1300];
    snprintf(dir, sizeof dir, "%.1200s", pl_path);
    char *slash = strrchr(dir, '/');
    if (slash) {
        *slash = 0;
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    double m, D, w, d;
    int dim;
    run_scene(dir, &m, &D, &dim, &w, &d);
    return d > 0.0 ? d : 0.0;
}

int gr_spm_pl_load_for(gr_spm_pl *pl, const char *path, double diameter, gr_error *err)
{
    int rc = gr_spm_pl_load(pl, path, gr_spm_pl_diameter(path, diameter), err);
    if (rc && strstr(err->message, "diameter")) {
        size_t n = strlen(err->message);
        snprintf(err->message + n, sizeof err->message - n, " (give --diameter D in m)");
    }
    return rc;
}

static int refuse(gr_error *err)
{
    err->code = GR_EINVAL;
    return GR_EINVAL;
}

int gr_spm_full_prepare(gr_spm_full_params *p, gr_spm_full_report *r, gr_error *err)
{
    memset(r, 0, sizeof *r);
    r->run_mass = r->run_D = (double)NAN;
    r->implied_C = (double)NAN;
    if (!p->pl_path && isnan(p->df) && p->run_dir) {
        /* Fig. 5.10: the run's own free paths (the freepath observable) */
        snprintf(r->auto_pl, sizeof r->auto_pl, "%s/freepath.csv", p->run_dir);
        FILE *probe = gr_input_fopen(r->auto_pl, &(int){0});
        if (!probe) {
            return GR_FAIL(err, GR_EINVAL,
                           "spm full: %s has no freepath.csv (run it with [analysis] observables = "
                           "freepath); give --pl "
                           "FILE or --df D_f",
                           p->run_dir);
        }
        fclose(probe);
        p->pl_path = r->auto_pl;
    }
    if (!p->pl_path && isnan(p->df)) {
        /* neither a P_l table nor D_f: the thesis' D_f = 1.63 +- 0.03 (sec. 4.2, Table 4.1) */
        p->df = GR_SPM_THESIS_DF;
        r->df_defaulted = true;
    }
    if ((p->pl_path != NULL) == !isnan(p->df)) {
        return GR_FAIL(err, GR_EINVAL, "spm full: give either --pl FILE or --df D_f, not both");
    }
    if (!isnan(p->diameter) && !(p->diameter > 0.0 && isfinite(p->diameter))) {
        return GR_FAIL(err, GR_EINVAL, "spm full: --diameter must be > 0 m, got %g", p->diameter);
    }
    if (p->pl_path && !isnan(p->C)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm full: --C belongs to --df (the fitted form 4.25), not to --pl");
    }
    if (!isnan(p->vmax) && !(p->vmax > 0.0 && isfinite(p->vmax))) {
        return GR_FAIL(err, GR_EINVAL, "spm full: --vmax must be > 0 m/s, got %g", p->vmax);
    }
    if ((!isnan(p->fit_from) && !(p->fit_from >= 0.0)) ||
        (!isnan(p->t_from) && !isfinite(p->t_from)) ||
        (!isnan(p->compare_from) && !(p->compare_from >= 0.0)) || !(p->z_max > 0.0)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "spm full: --fit-from and --compare-from must be >= 0, --t-from finite, --z-max > 0");
    }
    if ((!isnan(p->t_from) || !isnan(p->compare_from)) && !p->run_dir) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm full: --t-from and --compare-from need --compare-run DIR");
    }
    if (p->run_dir) {
        double warmup, run_d;
        int run_dim;
        run_scene(p->run_dir, &r->run_mass, &r->run_D, &run_dim, &warmup, &run_d);
        if (!p->mass_set && r->run_mass > 0.0) {
            p->s.mass = r->run_mass;
        }
        if (!p->D_set && r->run_D > 0.0) {
            p->s.D = r->run_D;
        }
        if (!p->dim_set && (run_dim == 1 || run_dim == 2)) {
            p->s.dim = run_dim;
        }
        if (isnan(p->t_from)) {
            p->t_from = warmup >= 0.0 ? warmup : 0.0;
        }
    }
    if (gr_spm_settings_check(&p->s, err)) {
        return refuse(err);
    }
    if (p->pl_path) {
        int rc =
            gr_spm_pl_load_for(&r->pl, p->pl_path, isnan(p->diameter) ? 0.0 : p->diameter, err);
        if (rc) {
            return rc;
        }
        r->pl_loaded = true;
        gr_error e2 = {0};
        r->have_plfit = gr_spm_pl_fit_tail(&r->pl, p->tail_from, &r->plfit, &e2) == 0;
        if (!r->have_plfit) {
            snprintf(r->plfit_note, sizeof r->plfit_note, "%s", e2.message);
        }
    } else {
        if (isnan(p->C)) {
            p->C = GR_SPM_THESIS_C;
        }
        if (gr_spm_pl_fitted(&r->pl, p->df, p->C, err)) {
            return refuse(err);
        }
        r->pl_loaded = true;
    }
    double pred_df = p->pl_path ? (r->have_plfit ? r->plfit.df : (double)NAN) : p->df;
    double pred_C = p->pl_path ? (r->have_plfit ? r->plfit.C : (double)NAN) : p->C;
    r->have_pred =
        isfinite(pred_df) &&
        gr_spm_predict(pred_df, gr_spm_B(&p->s, GR_SPM_THESIS_B_COEF), pred_C, &r->pred, err) == 0;

    /* the RFM's snapshots: checked before any work, and their largest |v| for the range */
    if (p->run_dir) {
        gr_histogram probe;
        int rc = gr_histogram_init(&probe, 1, 0.0, 1e-300, false, err);
        if (!rc) {
            rc = gr_spm_rfm_histogram(p->run_dir, p->t_from, &probe, &r->info, err);
        }
        gr_histogram_free(&probe);
        if (rc) {
            return rc;
        }
        if (r->info.dim != p->s.dim) {
            return GR_FAIL(err, GR_EINVAL, "spm full: the run is %dD but --dim %d was asked for",
                           r->info.dim, p->s.dim);
        }
    }
    if (isnan(p->vmax)) {
        /* 3 u_l at the largest free path expected among the walks (tilted: quantile 1 - N^-tilt) */
        double lbig = gr_spm_pl_quantile(&r->pl, 1.0 - pow((double)p->s.walks, -p->s.tilt));
        p->vmax = 3.0 * gr_spm_velocity_scale(&p->s, lbig);
        if (p->run_dir) {
            p->vmax =
                fmax(p->vmax, 1.02 * r->info.v_max); /* the run's fastest component fits too */
        }
    }
    return GR_OK;
}

/* A0 v^h exp(-S v^alpha) with the predicted alpha fixed: ln P - ... linear in (1, ln v, v^alpha);
 * q = (ln A0, h, S) */
static double tail_531(double v, const double *q, double *g, void *user)
{
    double alpha = *(const double *)user, va = pow(v, alpha), lv = log(v);
    if (g) {
        g[0] = 1.0;
        g[1] = lv;
        g[2] = -va;
    }
    return q[0] + q[1] * lv - q[2] * va;
}

typedef struct pv_fit_par {
    double from, alpha, S, h;
    double chi2_red; /* of the fit to all batches (the first call) */
    int points;
    int calls;
} pv_fit_par;

static int pv_select(const pv_fit_par *q, const double *x, const double *p, const double *e,
                     const double *count, int n, double *vx, double *vy, double *vs)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (x[i] >= q->from && p[i] > 0.0 && e[i] > 0.0 && isfinite(e[i]) && count[i] > 0.0) {
            vx[m] = x[i];
            vy[m] = p[i];
            vs[m] = e[i];
            m++;
        }
    }
    return m;
}

/* The tail bins of a jackknife sample for a fit: x, y, sigma in one allocation (free vx). */
static double *pv_points(const pv_fit_par *q, const double *x, const double *p, const double *e,
                         const double *count, int n, int *m)
{
    double *vx = malloc(sizeof(double) * (size_t)n * 3);
    if (vx) {
        *m = pv_select(q, x, p, e, count, n, vx, vx + n, vx + 2 * n);
    }
    return vx;
}

/* copy a fit's parameters out; the first call (all batches) also keeps chi2 and the points */
static int pv_done(pv_fit_par *q, const gr_fit *f, int m, double *out)
{
    for (int k = 0; k < 3; k++) {
        out[k] = f->p[k];
    }
    if (q->calls++ == 0) {
        q->chi2_red = f->chi2_red;
        q->points = m;
    }
    return 0;
}

/* A exp(-(v/v_A)^alpha): out = (A, v_A, alpha) */
static int pv_stretched(const double *x, const double *p, const double *e, const double *count,
                        int n, double *out, void *user)
{
    pv_fit_par *q = user;
    int m = 0;
    double *vx = pv_points(q, x, p, e, count, n, &m);
    if (!vx) {
        return 1;
    }
    double *vy = vx + n, *vs = vy + n;
    gr_fit f;
    gr_error e2 = {0};
    double p0[3] = {m ? vy[0] * exp(1.0) : 1.0, m ? vx[0] : 1.0, 1.0};
    int rc = m >= 4 ? gr_fit_stretched_exp(vx, vy, vs, m, p0, &f, &e2) : 1;
    free(vx);
    return rc ? 1 : pv_done(q, &f, m, out);
}

/* ln P = ln A0 + h ln v - S v^alpha with alpha fixed: out = (ln A0, h, S) */
static int pv_531(const double *x, const double *p, const double *e, const double *count, int n,
                  double *out, void *user)
{
    pv_fit_par *q = user;
    int m = 0;
    double *vx = pv_points(q, x, p, e, count, n, &m);
    if (!vx) {
        return 1;
    }
    double *vy = vx + n, *vs = vy + n;
    for (int i = 0; i < m; i++) {
        vs[i] /= vy[i];
        vy[i] = log(vy[i]);
    }
    gr_fit f;
    gr_error e2 = {0};
    double q0[3] = {m ? vy[0] + q->S * pow(vx[0], q->alpha) - q->h * log(vx[0]) : 0.0, q->h, q->S};
    int rc = m >= 4 ? gr_fit_nonlinear(tail_531, &q->alpha, vx, vy, vs, m, 3, q0, &f, &e2) : 1;
    free(vx);
    return rc ? 1 : pv_done(q, &f, m, out);
}

/* the RFM run's P(v) per component on the SPM's bins, and the two comparisons */
static int compare_run(gr_spm_full_params *p, gr_spm_full_report *r, gr_error *err)
{
    gr_histogram rh = {0};
    int nb = r->nb;
    int rc = gr_histogram_init(&rh, nb, 0.0, p->vmax, false, err);
    if (!rc) {
        rc = gr_spm_rfm_histogram(p->run_dir, p->t_from, &rh, &r->info, err);
    }
    if (!rc && r->info.dim != p->s.dim) {
        rc = GR_FAIL(err, GR_EINVAL, "spm full: the run is %dD but --dim %d was asked for",
                     r->info.dim, p->s.dim);
    }
    if (!rc) {
        for (int i = 0; i < nb; i++) {
            r->p_rfm[i] = 0.5 * gr_histogram_density(&rh, i);
            r->e_rfm[i] = 0.5 * gr_histogram_density_error(&rh, i);
        }
        if (isnan(p->compare_from)) {
            p->compare_from = 2.0 * sqrt(r->info.v2_mean);
        }
        gr_error e2 = {0};
        r->have_cmp = gr_spm_compare_tails(r->v, r->p_spm, r->e_spm, r->p_rfm, r->e_rfm, nb,
                                           p->compare_from, p->z_max, false, &r->cmp, &e2) == 0;
        r->have_cmp2 = gr_spm_compare_tails(r->v, r->p_spm, r->e_spm, r->p_rfm, r->e_rfm, nb,
                                            p->compare_from, p->z_max, true, &r->cmp2, &e2) == 0;
    }
    gr_histogram_free(&rh);
    return rc;
}

int gr_spm_full_run(gr_spm_full_params *p, gr_spm_full_report *r, gr_error *err)
{
    double t0 = gr_spm_clock();
    int rc = gr_spm_full(&p->s, &r->pl, p->weight_time, p->bins, p->vmax, &r->res, err);
    if (rc) {
        return rc;
    }
    r->have_res = true;
    r->wall_seconds = gr_spm_clock() - t0;
    const int nb = r->nb = p->bins;
    r->v = calloc((size_t)nb * 8, sizeof(double));
    if (!r->v) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    r->p_spm = r->v + nb;
    r->e_spm = r->p_spm + nb;
    r->p_rfm = r->e_spm + nb;
    r->e_rfm = r->p_rfm + nb;
    for (int i = 0; i < nb; i++) {
        r->v[i] = gr_histogram_center(&r->res.p.all, i);
        r->p_spm[i] = gr_spm_dist_density(&r->res.p, i);
        r->e_spm[i] = gr_spm_dist_error(&r->res.p, i);
    }
    r->v_rms = sqrt(r->res.v2_mean);
    gr_spm_constants_of(&r->res.stats, &r->constants);
    if (isnan(p->fit_from)) {
        p->fit_from = 3.0 * r->v_rms;
    }
    /* tail fits of the SPM P(v), jackknife errors: a free stretched exponential, and 5.31 with
     * alpha fixed at the prediction */
    const gr_spm_prediction *pred = &r->pred;
    pv_fit_par fp = {p->fit_from,
                     r->have_pred ? pred->alpha : 1.0,
                     r->have_pred ? pred->S : 10.0,
                     r->have_pred ? pred->h : 0.5,
                     0.0,
                     0,
                     0};
    gr_error e2 = {0};
    r->have_sfit =
        gr_spm_dist_jackknife(&r->res.p, pv_stretched, &fp, 3, r->sfit, r->sfit_err, &e2) == 0;
    r->sfit_chi2 = fp.chi2_red;
    r->sfit_points = fp.points;
    fp.calls = 0;
    r->have_531 = r->have_pred &&
                  gr_spm_dist_jackknife(&r->res.p, pv_531, &fp, 3, r->f531, r->f531_err, &e2) == 0;
    r->f531_chi2 = fp.chi2_red;
    r->v_data = 0.0;
    for (int i = 0; i < nb; i++) {
        if (r->p_spm[i] > 0.0) {
            r->v_data = gr_histogram_upper(&r->res.p.all, i);
        }
    }
    if (p->run_dir) {
        rc = compare_run(p, r, err);
    }
    /* the free-path scale the fitted velocity scale s stands for: l -> s^3 l */
    r->implied_C = r->pl.kind == GR_SPM_PL_FITTED && r->have_cmp2
                       ? r->pl.C * pow(r->cmp2.s, -3.0 * r->pl.beta)
                       : (double)NAN;
    return rc;
}

void gr_spm_full_report_free(gr_spm_full_report *r)
{
    free(r->v);
    r->v = NULL;
    if (r->have_res) {
        gr_spm_full_result_free(&r->res);
        r->have_res = false;
    }
    if (r->pl_loaded) {
        gr_spm_pl_free(&r->pl);
        r->pl_loaded = false;
    }
}

double gr_spm_full_531(const gr_spm_full_report *r, double v)
{
    double alpha = r->pred.alpha;
    return exp(tail_531(v, r->f531, NULL, &alpha));
}
