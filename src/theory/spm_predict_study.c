/* granule spm predict as a library call: the asymptotic tail of P(v) from D_f (thesis sec. 5.3.2,
 * 5.27-5.31) and the SPM integral 5.13 integrated numerically against its steepest-descent form
 * 5.26; see granule/spm_study.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/spm_study.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "theory/spm_output.h"

void gr_spm_predict_params_default(gr_spm_predict_params *p)
{
    memset(p, 0, sizeof *p);
    gr_spm_settings_default(&p->s);
    p->df = p->C = p->vmax = (double)NAN;
    p->b = GR_SPM_THESIS_B_COEF;
    p->tail_from = 0.0;
    p->diameter = 0.0;
}

int gr_spm_predict_prepare(gr_spm_predict_params *p, gr_spm_predict_report *r, gr_error *err)
{
    memset(r, 0, sizeof *r);
    r->alpha_err = (double)NAN;
    if (!p->pl_path && isnan(p->df)) {
        /* the thesis' D_f = 1.63 +- 0.03 (sec. 4.2, Table 4.1) */
        p->df = GR_SPM_THESIS_DF;
        r->df_defaulted = true;
    }
    if ((p->pl_path != NULL) == !isnan(p->df)) {
        return GR_FAIL(err, GR_EINVAL, "spm predict: give either --df D_f or --pl FILE, not both");
    }
    if (!(p->b > 0.0) || !isfinite(p->b)) {
        return GR_FAIL(err, GR_EINVAL, "spm predict: --b must be > 0, got %g", p->b);
    }
    if (!isnan(p->vmax) && !(p->vmax > 0.0 && isfinite(p->vmax))) {
        return GR_FAIL(err, GR_EINVAL, "spm predict: --vmax must be > 0 m/s, got %g", p->vmax);
    }
    if (gr_spm_settings_check(&p->s, err)) {
        err->code = GR_EINVAL;
        return GR_EINVAL;
    }
    if (p->pl_path) {
        gr_spm_pl pl;
        int rc = gr_spm_pl_load_for(&pl, p->pl_path, p->diameter, err);
        if (rc) {
            return rc;
        }
        rc = gr_spm_pl_fit_tail(&pl, p->tail_from, &r->plfit, err);
        gr_spm_pl_free(&pl);
        if (rc) {
            err->code = GR_EINVAL;
            return GR_EINVAL;
        }
        p->df = r->plfit.df;
        if (isnan(p->C)) {
            p->C = r->plfit.C;
        }
        /* d alpha / d D_f = 12 / (3 D_f - 1)^2 */
        r->alpha_err = 12.0 / ((3.0 * p->df - 1.0) * (3.0 * p->df - 1.0)) * r->plfit.df_err;
    } else if (isnan(p->C)) {
        p->C = GR_SPM_THESIS_C;
    }
    if (!(p->C > 0.0) || !isfinite(p->C)) {
        return GR_FAIL(err, GR_EINVAL, "spm predict: --C must be > 0, got %g", p->C);
    }
    if (gr_spm_predict(p->df, gr_spm_B(&p->s, p->b), p->C, &r->p, err)) {
        err->code = GR_EINVAL;
        return GR_EINVAL;
    }
    if (isnan(p->vmax)) {
        p->vmax = 20.0 * r->p.v_A;
    }
    return GR_OK;
}

/* the numerical integral 5.13 against the steepest-descent form 5.26 */
static int write_table(const char *dir, const gr_spm_predict_params *in, const gr_spm_prediction *p,
                       double *last_delta, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "prediction.csv", err);
    if (rc) {
        return rc;
    }
    gr_file_note(&f, "# granule %s (%s) spm: the SPM integral identity's tail (sec. 5.3.2)\n",
                 GR_VERSION, GR_COMMIT);
    gr_file_note(&f,
                 "# D_f = %g, alpha = %g, h = %g, B = %g (b = %g, M = %g kg, D = %g N^2 s), C = "
                 "%g, S = %g, v_A = %g m/s\n",
                 p->df, p->alpha, p->h, p->B, in->b, in->s.mass, in->s.D, p->C, p->S, p->v_A);
    gr_file_note(&f, "# ln_I: ln of 5.13 (A_2 = 1) integrated numerically; ln_asym: 5.26 = -S "
                     "v^alpha + ln sqrt(2 pi / -f''(y_m));\n"
                     "# P_531 = v^h exp(-S v^alpha) (5.31 with A_0 = 1); v in m/s\n");
    gr_file_header(&f, "v [m s-1],ln_I [1],ln_asym [1],delta [1],P_531 [1]");
    for (int i = 1; i <= 200 && !rc; i++) {
        double v = in->vmax * i / 200.0, li;
        rc = gr_spm_integral_log(p, v, &li, err);
        if (!rc) {
            double la = gr_spm_asymptotic_log(p, v);
            *last_delta = li - la;
            fprintf(f.f, "%.6g,%.10g,%.10g,%.6g,%.6g\n", v, li, la, li - la,
                    pow(v, p->h) * exp(-p->S * pow(v, p->alpha)));
        }
    }
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    return gr_file_commit(&f, err);
}

static cJSON *summary(const gr_spm_predict_params *in, const gr_spm_predict_report *r,
                      double last_delta)
{
    const gr_spm_prediction *p = &r->p;
    cJSON *j = gr_spm_json_head("predict");
    cJSON *ij = cJSON_AddObjectToObject(j, "input");
    gr_spm_json_num(ij, "D_f", in->df);
    cJSON_AddStringToObject(ij, "D_f_source",
                            in->pl_path       ? "fitted to the P_l table"
                            : r->df_defaulted ? "default: the thesis' 1.63 (sec. 4.2)"
                                              : "--df");
    gr_spm_json_num(ij, "C", in->C);
    gr_spm_json_num(ij, "b", in->b);
    gr_spm_json_num(ij, "mass", in->s.mass);
    gr_spm_json_num(ij, "D", in->s.D);
    if (in->pl_path) {
        cJSON *t = cJSON_AddObjectToObject(ij, "tail_fit_4_25");
        cJSON_AddStringToObject(t, "file", in->pl_path);
        gr_spm_json_pl_fit(t, &r->plfit);
    }
    cJSON *rj = cJSON_AddObjectToObject(j, "prediction");
    gr_spm_json_num(rj, "beta", p->beta);
    gr_spm_json_num(rj, "gamma", p->gamma);
    gr_spm_json_num(rj, "alpha", p->alpha);
    if (in->pl_path) {
        gr_spm_json_num(rj, "alpha_err", r->alpha_err);
    }
    gr_spm_json_num(rj, "h", p->h);
    gr_spm_json_num(rj, "B", p->B);
    gr_spm_json_num(rj, "F", p->F);
    gr_spm_json_num(rj, "S", p->S);
    gr_spm_json_num(rj, "v_A", p->v_A);
    gr_spm_json_num(rj, "integral_minus_asymptotic_at_vmax", last_delta);
    cJSON_AddArrayToObject(j, "plots");
    return j;
}

int gr_spm_predict_write(const char *dir, const gr_spm_predict_params *in,
                         const gr_spm_predict_report *r, bool plots, gr_error *err)
{
    double last_delta = (double)NAN;
    int rc = write_table(dir, in, &r->p, &last_delta, err);
    if (rc) {
        return rc;
    }
    cJSON *j = summary(in, r, last_delta);
    char body[2048];
    snprintf(body, sizeof body,
             "set title 'SPM integral 5.13 (numerical) and its steepest-descent form 5.26'\n"
             "set xlabel 'v (m/s)'\nset ylabel 'ln I(v)'\nset format x '%%g'\nset format y "
             "'%%g'\nset key top right\n"
             "plot 'prediction.csv' using 1:2 with lines lw 2 lc rgb '%s' title 'ln I, numerical', "
             "'' using 1:3 with lines dt 2 lw 2 lc rgb '%s' title 'steepest descent 5.26: -S "
             "v^{%.3f} + ln (2 pi / |f_{yy}|)^{1/2}'\n",
             gr_spm_colour(0), gr_spm_colour(1), r->p.alpha);
    gr_spm_plot(dir, plots, j, "prediction.png", body);
    rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}
