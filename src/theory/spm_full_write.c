/* The output folder of granule spm full (gr_spm_full_write): p_v.csv, pl.csv, compare.csv,
 * summary.json, p_v.png, pl.png; see docs/theory-spm.md. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/spm_study.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "theory/spm_output.h"

static int write_pv(const char *dir, const gr_spm_full_params *p, const gr_spm_full_report *r,
                    gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "p_v.csv", err);
    if (rc) {
        return rc;
    }
    gr_spm_csv_head(&f, "P(v) of the full SPM (sec. 5.2.3), one velocity component", &p->s);
    gr_file_note(&f, "# P_l: %s; weight %s; tilt %g\n", r->pl.source,
                 p->weight_time ? "uniform in time" : "per walk", p->s.tilt);
    gr_file_note(&f,
                 "# v in m/s, P in s/m (density of the signed component); errors from the spread "
                 "between batches;\n"
                 "# P_531: A0 v^h exp(-S v^alpha) of 5.31 with alpha = %g and S, h, A0 fitted over "
                 "%g <= v <= %g m/s\n",
                 r->have_pred ? r->pred.alpha : (double)NAN, p->fit_from, r->v_data);
    gr_file_header(&f, "v_lo [m s-1],v_hi [m s-1],v [m s-1],samples [1],P [s m-1],P_err [s "
                       "m-1],P_err_poisson [s m-1],P_531 [s m-1]");
    for (int i = 0; i < r->nb; i++) {
        double v = r->v[i];
        double p531 =
            r->have_531 && v >= p->fit_from && v <= r->v_data ? gr_spm_full_531(r, v) : (double)NAN;
        fprintf(f.f, "%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.6g\n",
                gr_histogram_lower(&r->res.p.all, i), gr_histogram_upper(&r->res.p.all, i), v,
                r->res.p.all.count[i], r->p_spm[i], r->e_spm[i],
                gr_spm_dist_poisson_error(&r->res.p, i), p531);
    }
    return gr_file_commit(&f, err);
}

/* the free-path density used */
static int write_pl(const char *dir, const gr_spm_full_params *p, const gr_spm_full_report *r,
                    gr_error *err)
{
    const gr_spm_pl *pl = &r->pl;
    const gr_spm_pl_fit *fit = &r->plfit;
    gr_file f;
    int rc = gr_file_open(&f, dir, "pl.csv", err);
    if (rc) {
        return rc;
    }
    gr_spm_csv_head(&f, "the free-path distribution P_l(l) the walks drew from (sec. 4.3)", &p->s);
    gr_file_note(
        &f,
        "# %s; l in m, P in 1/m (normalised); P_fit: 4.25 fitted to the table's tail (if any)\n",
        pl->source);
    gr_file_header(&f, "l [m],P [m-1],P_fit [m-1]");
    if (pl->kind == GR_SPM_PL_TABLE) {
        for (int i = 0; i < pl->n; i++) {
            double l = pl->l[i];
            double y = r->have_plfit && l >= fit->lfrom && l <= fit->lto
                           ? fit->A0 * pow(l, fit->beta - 1.0) * exp(-fit->C * pow(l, fit->beta))
                           : (double)NAN;
            fprintf(f.f, "%.6g,%.6g,%.6g\n", l, pl->p[i], y);
        }
    } else {
        double lo = gr_spm_pl_quantile(pl, 1e-6), hi = gr_spm_pl_quantile(pl, 1.0 - 1e-12);
        for (int i = 0; i <= 200; i++) {
            double l = lo * pow(hi / lo, i / 200.0);
            fprintf(f.f, "%.6g,%.6g,%.6g\n", l, gr_spm_pl_density(pl, l), gr_spm_pl_density(pl, l));
        }
    }
    return gr_file_commit(&f, err);
}

static int write_compare(const char *dir, const gr_spm_full_params *p, const gr_spm_full_report *r,
                         gr_error *err)
{
    const gr_spm_compare *c1 = &r->cmp, *c2 = &r->cmp2;
    gr_file f;
    int rc = gr_file_open(&f, dir, "compare.csv", err);
    if (rc) {
        return rc;
    }
    gr_spm_csv_head(&f, "SPM P(v) against the Random Force Model's P(v) per component (Fig. 5.10)",
                    &p->s);
    gr_file_note(&f,
                 "# run %s: %d frames with Time >= %g s (%d skipped), %lld particles, %dD; P_rfm "
                 "errors sqrt(X)\n",
                 p->run_dir, r->info.frames, p->t_from, r->info.frames_skipped,
                 (long long)r->info.particles, r->info.dim);
    gr_file_note(
        &f,
        "# P_spm_scaled = k P_spm, k = %g +- %g fitted over v >= %g m/s; P_spm_fit = k2 "
        "P_spm(v/s)/s, k2 = %g,\n"
        "# s = %g +- %g (velocity scale fitted too); agree: |z| <= %g in the contiguous tail\n",
        c1->k, c1->k_err, p->compare_from, c2->k, c2->s, c2->s_err, p->z_max);
    gr_file_header(
        &f, "v [m s-1],P_spm [s m-1],P_spm_err [s m-1],P_spm_scaled [s m-1],P_rfm [s "
            "m-1],P_rfm_err [s m-1],z [1],agree [1],P_spm_fit [s m-1],z_fit [1],agree_fit [1]");
    const double *v = r->v, *pr = r->p_rfm, *er = r->e_rfm;
    for (int i = 0; i < r->nb; i++) {
        double m1e, m1 = gr_spm_compare_model(c1, v, r->p_spm, r->e_spm, r->nb, i, &m1e);
        double m2e, m2 = gr_spm_compare_model(c2, v, r->p_spm, r->e_spm, r->nb, i, &m2e);
        double z1 =
            m1 > 0.0 && pr[i] > 0.0 ? (pr[i] - m1) / sqrt(er[i] * er[i] + m1e * m1e) : (double)NAN;
        double z2 =
            m2 > 0.0 && pr[i] > 0.0 ? (pr[i] - m2) / sqrt(er[i] * er[i] + m2e * m2e) : (double)NAN;
        int a1 =
            r->have_cmp && c1->agree_bins > 0 && v[i] >= c1->v_agree_lo && v[i] <= c1->v_agree_hi;
        int a2 =
            r->have_cmp2 && c2->agree_bins > 0 && v[i] >= c2->v_agree_lo && v[i] <= c2->v_agree_hi;
        fprintf(f.f, "%.6g,%.6g,%.4g,%.6g,%.6g,%.4g,%.4g,%d,%.6g,%.4g,%d\n", v[i], r->p_spm[i],
                r->e_spm[i], m1, pr[i], er[i], z1, a1, m2, z2, a2);
    }
    return gr_file_commit(&f, err);
}

static void json_free_paths(cJSON *j, const gr_spm_full_params *p, const gr_spm_full_report *r)
{
    cJSON *pj = cJSON_AddObjectToObject(j, "free_paths");
    cJSON_AddStringToObject(pj, "source", r->pl.source);
    gr_spm_json_num(pj, "mean", gr_spm_pl_mean(&r->pl));
    gr_spm_json_num(pj, "mean_drawn", r->res.l_mean);
    if (p->pl_path) {
        cJSON *t = cJSON_AddObjectToObject(pj, "tail_fit_4_25");
        if (r->have_plfit) {
            gr_spm_json_pl_fit(t, &r->plfit);
        } else {
            cJSON_AddStringToObject(t, "note", r->plfit_note);
        }
    } else {
        cJSON_AddNumberToObject(pj, "D_f", p->df);
        cJSON_AddStringToObject(pj, "D_f_source",
                                r->df_defaulted ? "default: the thesis' 1.63 (sec. 4.2)" : "--df");
        cJSON_AddNumberToObject(pj, "C", p->C);
    }
}

static void json_spm(cJSON *j, const gr_spm_full_params *p, const gr_spm_full_report *r)
{
    cJSON *rj = cJSON_AddObjectToObject(j, "spm");
    gr_spm_json_stats(rj, &r->res.stats);
    gr_spm_json_num(rj, "vmax", p->vmax);
    gr_spm_json_num(rj, "v_max_with_data", r->v_data);
    gr_spm_json_num(rj, "v_rms", r->v_rms);
    gr_spm_json_num(rj, "fit_from", p->fit_from);
    if (r->have_sfit) {
        cJSON *t = cJSON_AddObjectToObject(rj, "stretched_exp_fit");
        gr_spm_json_num(t, "alpha", r->sfit[2]);
        gr_spm_json_num(t, "alpha_err", r->sfit_err[2]);
        gr_spm_json_num(t, "v_A", r->sfit[1]);
        gr_spm_json_num(t, "v_A_err", r->sfit_err[1]);
        gr_spm_json_num(t, "chi2_red", r->sfit_chi2);
        cJSON_AddNumberToObject(t, "points", r->sfit_points);
    }
    if (r->have_pred) {
        const gr_spm_prediction *pred = &r->pred;
        cJSON *t = cJSON_AddObjectToObject(rj, "prediction_5_27_5_31");
        gr_spm_json_num(t, "D_f", pred->df);
        gr_spm_json_num(t, "alpha", pred->alpha);
        gr_spm_json_num(t, "h", pred->h);
        gr_spm_json_num(t, "B_b_0_98", pred->B);
        gr_spm_json_num(t, "C", pred->C);
        gr_spm_json_num(t, "S", pred->S);
        gr_spm_json_num(t, "v_A", pred->v_A);
        if (r->have_531) {
            gr_spm_json_num(t, "fit_S", r->f531[2]);
            gr_spm_json_num(t, "fit_S_err", r->f531_err[2]);
            gr_spm_json_num(t, "fit_h", r->f531[1]);
            gr_spm_json_num(t, "fit_h_err", r->f531_err[1]);
            gr_spm_json_num(t, "fit_chi2_red", r->f531_chi2);
        }
    }
}

static void json_rfm(cJSON *j, const gr_spm_full_params *p, const gr_spm_full_report *r)
{
    cJSON *t = cJSON_AddObjectToObject(j, "rfm");
    cJSON_AddStringToObject(t, "run", p->run_dir);
    cJSON_AddNumberToObject(t, "frames", r->info.frames);
    cJSON_AddNumberToObject(t, "frames_skipped", r->info.frames_skipped);
    gr_spm_json_num(t, "t_from", p->t_from);
    cJSON_AddNumberToObject(t, "particles", (double)r->info.particles);
    gr_spm_json_num(t, "v_rms", sqrt(r->info.v2_mean));
    gr_spm_json_num(t, "v_max", r->info.v_max);
    gr_spm_json_num(t, "mass_of_run", r->run_mass);
    gr_spm_json_num(t, "D_of_run", r->run_D);
    gr_spm_json_num(t, "compare_from", p->compare_from);
    gr_spm_json_num(t, "z_max", p->z_max);
    if (r->info.frames < GR_MIN_FRAMES) {
        cJSON_AddStringToObject(
            t, "warning", "fewer frames than the 16 a comparison needs: no agreement verdict");
    }
    for (int w = 0; w < 2; w++) {
        const gr_spm_compare *c = w ? &r->cmp2 : &r->cmp;
        if (!(w ? r->have_cmp2 : r->have_cmp)) {
            continue;
        }
        cJSON *x =
            cJSON_AddObjectToObject(t, w ? "amplitude_and_velocity_scale" : "amplitude_only");
        gr_spm_json_num(x, "k", c->k);
        gr_spm_json_num(x, "k_err", c->k_err);
        gr_spm_json_num(x, "s", c->s);
        gr_spm_json_num(x, "s_err", c->s_err);
        if (w) {
            gr_spm_json_num(x, "implied_C", r->implied_C);
        }
        gr_spm_json_num(x, "chi2_red", c->chi2_red);
        cJSON_AddNumberToObject(x, "points", c->n_points);
        gr_spm_json_num(x, "agree_v_lo", c->v_agree_lo);
        gr_spm_json_num(x, "agree_v_hi", c->v_agree_hi);
        cJSON_AddNumberToObject(x, "agree_bins", c->agree_bins);
        gr_spm_json_num(x, "agree_decades", c->decades);
        gr_spm_json_num(x, "fraction_of_tail_bins_within_z_max", c->frac_within);
    }
}

static void plots(const char *dir, bool on, cJSON *j, const gr_spm_full_params *p,
                  const gr_spm_full_report *r)
{
    char body[4096];
    int k = snprintf(
        body, sizeof body,
        "set title 'P(v) of the Single Particle Model (sec. 5.2.3), %dD'\n"
        "set xlabel '|v| (m/s)'\nset ylabel 'P(v) (s/m)'\nset logscale y\nset format y '10^{%%L}'\n"
        "set format x '%%g'\nset key top right\nset xrange [0:%g]\n"
        "plot 'p_v.csv' using 3:($5>0 ? $5 : 1/0):($5-$6 > 0 ? $5-$6 : $5/10):($5+$6) with "
        "yerrorbars "
        "pt 7 ps 0.4 lc rgb '%s' title 'SPM'",
        p->s.dim, p->run_dir ? fmax(r->v_data, 1.02 * r->info.v_max) : r->v_data, gr_spm_colour(0));
    if (r->have_531) {
        k += snprintf(body + k, sizeof body - (size_t)k,
                      ", '' using 3:8 with lines lw 2 lc rgb 'black' "
                      "title 'fit of 5.31, alpha = %.3f fixed'",
                      r->pred.alpha);
    }
    if (p->run_dir) {
        /* the SPM's amplitude k (and velocity scale s) are fitted to the run's tail: say so in the
         * legend instead of an unexplained factor */
        k += snprintf(
            body + k, sizeof body - (size_t)k,
            ", 'compare.csv' using 1:($5>0 ? $5 : 1/0):($5-$6 > 0 ? $5-$6 : $5/10):($5+$6) with "
            "yerrorbars "
            "pt 6 ps 0.6 lc rgb '%s' title 'RFM run', "
            "'' using 1:($4>0 ? $4 : 1/0) with lines dt 2 lw 2 lc rgb '%s' "
            "title 'k P_{SPM}(v), amplitude k = %.3g fitted to the run for v >= %.3g m/s', "
            "'' using 1:($9>0 ? $9 : 1/0) with lines dt 3 lw 2 lc rgb '%s' "
            "title 'k P_{SPM}(v/s)/s, k = %.3g and velocity scale s = %.3g fitted'",
            gr_spm_colour(1), gr_spm_colour(2), r->cmp.k, p->compare_from, gr_spm_colour(3),
            r->cmp2.k, r->cmp2.s);
    }
    snprintf(body + k, sizeof body - (size_t)k, "\n");
    gr_spm_plot(dir, on, j, "p_v.png", body);
    snprintf(
        body, sizeof body,
        "set title 'Free-path distribution P_l(l) used (sec. 4.3)'\nset xlabel 'l (m)'\nset ylabel "
        "'P_l(l) (1/m)'\n"
        "set logscale xy\nset format y '10^{%%L}'\nset format x '10^{%%L}'\nset key top right\n"
        "plot 'pl.csv' using 1:($2>0 ? $2 : 1/0) with linespoints pt 7 ps 0.4 lc rgb '%s' title "
        "'P_l', "
        "'' using 1:($3>0 ? $3 : 1/0) with lines lw 2 dt 2 lc rgb 'black' title '4.25'\n",
        gr_spm_colour(0));
    gr_spm_plot(dir, on, j, "pl.png", body);
}

int gr_spm_full_write(const char *dir, const gr_spm_full_params *p, const gr_spm_full_report *r,
                      bool on, gr_error *err)
{
    int rc = write_pv(dir, p, r, err);
    if (!rc) {
        rc = write_pl(dir, p, r, err);
    }
    if (!rc && p->run_dir) {
        rc = write_compare(dir, p, r, err);
    }
    if (rc) {
        return rc;
    }
    cJSON *j = gr_spm_json_head("full");
    gr_spm_json_settings(j, &p->s, p->bins);
    cJSON_AddNumberToObject(cJSON_GetObjectItem(j, "settings"), "tilt", p->s.tilt);
    cJSON_AddStringToObject(j, "weight", p->weight_time ? "time" : "walk");
    json_free_paths(j, p, r);
    json_spm(j, p, r);
    if (p->run_dir) {
        json_rfm(j, p, r);
    }
    cJSON_AddNumberToObject(j, "wall_seconds", r->wall_seconds);
    cJSON_AddArrayToObject(j, "plots");
    plots(dir, on, j, p, r);
    rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}
