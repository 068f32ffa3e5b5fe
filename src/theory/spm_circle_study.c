/* granule spm circle as a library call: Q(v, l) for fixed radii, its collapse under v / l^(1/3)
 * and the Gaussian tail 5.12 (thesis sec. 5.3.1); see granule/spm_study.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/analysis.h"
#include "granule/spm_study.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "theory/spm_output.h"

/* bins compared or fitted need at least this many samples */
#define MIN_COUNT 20.0

double gr_spm_c_from_w2(double w2) { return pow(2.0, 2.0 / 3.0) * w2; }
double gr_spm_cprime_from_exit_time(double exit_time) { return pow(2.0, -1.0 / 3.0) * exit_time; }

void gr_spm_constants_of(const gr_spm_walk_stats *st, gr_spm_constants *out)
{
    out->c = gr_spm_c_from_w2(st->w2_time_mean);
    out->c_err = gr_spm_c_from_w2(st->w2_time_err);
    out->c_prime = gr_spm_cprime_from_exit_time(st->exit_time_mean);
    out->c_prime_err = gr_spm_cprime_from_exit_time(st->exit_time_err);
}

/* one term of an inverse-variance mean */
static void pool_add(double *w, double *wx, double x, double e)
{
    if (isfinite(x) && e > 0.0 && isfinite(e)) {
        *w += 1.0 / (e * e);
        *wx += x / (e * e);
    }
}

void gr_spm_constants_pool(const gr_spm_constants *per, int n, gr_spm_constants *out)
{
    double w1 = 0.0, s1 = 0.0, w2 = 0.0, s2 = 0.0;
    for (int k = 0; k < n; k++) {
        pool_add(&w1, &s1, per[k].c, per[k].c_err);
        pool_add(&w2, &s2, per[k].c_prime, per[k].c_prime_err);
    }
    out->c = w1 > 0.0 ? s1 / w1 : (double)NAN;
    out->c_err = w1 > 0.0 ? 1.0 / sqrt(w1) : (double)NAN;
    out->c_prime = w2 > 0.0 ? s2 / w2 : (double)NAN;
    out->c_prime_err = w2 > 0.0 ? 1.0 / sqrt(w2) : (double)NAN;
}

void gr_spm_circle_params_default(gr_spm_circle_params *p)
{
    memset(p, 0, sizeof *p);
    gr_spm_settings_default(&p->s);
    p->bins = 90;
    p->n_radii = 4;
    p->radii[0] = 0.0036;
    p->radii[1] = 0.01;
    p->radii[2] = 0.02;
    p->radii[3] = 0.04;
    p->wmax = 4.5;
    p->fit_from = 2.5;
}

int gr_spm_circle_prepare(const gr_spm_circle_params *p, gr_error *err)
{
    int rc = gr_spm_settings_check(&p->s, err);
    if (rc) {
        return rc;
    }
    if (p->n_radii < 1 || p->n_radii > GR_SPM_MAX_RADII) {
        return GR_FAIL(err, GR_EINVAL, "spm circle: 1 to %d radii, got %d", GR_SPM_MAX_RADII,
                       p->n_radii);
    }
    if (!(p->wmax > 0.0 && p->wmax <= 100.0) || !(p->fit_from >= 0.0 && p->fit_from < p->wmax)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "spm circle: need 0 < --wmax <= 100 and 0 <= --fit-from < --wmax, got %g and %g",
            p->wmax, p->fit_from);
    }
    for (int r = 0; r < p->n_radii; r++) {
        if (!(p->radii[r] > 0.0) || !isfinite(p->radii[r])) {
            return GR_FAIL(err, GR_EINVAL, "spm circle: radii must be > 0 m, got %g", p->radii[r]);
        }
        double tl = gr_spm_time_scale(&p->s, p->radii[r]);
        if (p->s.dt > 0.0 && p->s.dt > 10.0 * tl) {
            return GR_FAIL(err, GR_EINVAL,
                           "spm circle: --dt %g s is %g t_l for the radius %g m (t_l = %g s); use "
                           "a smaller --dt",
                           p->s.dt, p->s.dt / tl, p->radii[r], tl);
        }
    }
    return GR_OK;
}

/* the caller's progress over all radii: radius r of n covers [r/n, (r+1)/n) */
typedef struct radius_progress {
    void (*fn)(double, void *);
    void *user;
    int r, n;
} radius_progress;

static void progress_of_radius(double fraction, void *user)
{
    radius_progress *rp = user;
    rp->fn(((double)rp->r + fraction) / (double)rp->n, rp->user);
}

static void fit_failed(gr_spm_tail_fit *f, char *note, const gr_error *e)
{
    snprintf(note, GR_SPM_NOTE, "%s", e->message);
    f->b = f->b_err = f->A = f->chi2_red = f->beta = f->beta_err = f->wto = (double)NAN;
}

int gr_spm_circle_run(const gr_spm_circle_params *p, gr_spm_circle_report *r, gr_error *err)
{
    memset(r, 0, sizeof *r);
    int rc = gr_spm_circle_prepare(p, err);
    if (rc) {
        return rc;
    }
    double t0 = gr_spm_clock();
    gr_spm_settings s = p->s;
    radius_progress rp = {p->s.progress, p->s.user, 0, p->n_radii};
    if (s.progress) {
        s.progress = progress_of_radius;
        s.user = &rp;
    }
    for (int k = 0; k < p->n_radii && !rc; k++) {
        rp.r = k;
        rc = gr_spm_circle(&s, p->radii[k], k, p->bins, p->wmax, &r->q[k], err);
        if (!rc) {
            r->n_radii++;
        }
    }
    if (rc) {
        gr_spm_circle_report_free(r);
        return rc;
    }
    r->wall_seconds = gr_spm_clock() - t0;

    /* pooled: batch b of every radius into batch b (same scaled bins) */
    rc = gr_spm_dist_init(&r->pooled.q, p->s.batches, p->bins, p->wmax, err);
    for (int k = 0; k < p->n_radii && !rc; k++) {
        for (int b = 0; b < p->s.batches && !rc; b++) {
            rc = gr_histogram_merge(&r->pooled.q.batch[b], &r->q[k].q.batch[b], err);
        }
        if (!rc) {
            rc = gr_histogram_merge(&r->pooled.q.all, &r->q[k].q.all, err);
        }
    }
    for (int k = 0; k < p->n_radii && !rc; k++) {
        r->fit_note[k][0] = 0;
        gr_error e2 = {0};
        if (gr_spm_q_tail_fit(&r->q[k], p->fit_from, MIN_COUNT, &r->fit[k], &e2)) {
            fit_failed(&r->fit[k], r->fit_note[k], &e2);
        }
        memset(&r->collapse[k], 0, sizeof r->collapse[k]);
        if (k > 0 && gr_spm_q_collapse(&r->q[0], &r->q[k], MIN_COUNT, 2000, &r->collapse[k], &e2)) {
            r->collapse[k].chi2_red = r->collapse[k].p_value = r->collapse[k].p_chi2 = (double)NAN;
        }
    }
    for (int k = 0; k < r->n_radii; k++) {
        gr_spm_constants_of(&r->q[k].stats, &r->constants[k]);
    }
    gr_spm_constants_pool(r->constants, r->n_radii, &r->pooled_constants);
    if (!rc) {
        gr_error e2 = {0};
        if (gr_spm_q_tail_fit(&r->pooled, p->fit_from, MIN_COUNT, &r->pooled_fit, &e2)) {
            fit_failed(&r->pooled_fit, r->pooled_note, &e2);
        }
    }
    if (rc) {
        gr_spm_circle_report_free(r);
    }
    return rc;
}

void gr_spm_circle_report_free(gr_spm_circle_report *r)
{
    for (int k = 0; k < r->n_radii; k++) {
        gr_spm_q_free(&r->q[k]);
    }
    gr_spm_q_free(&r->pooled);
    r->n_radii = 0;
}

static int write_q(const char *dir, const gr_spm_circle_params *p, const gr_spm_circle_report *r,
                   gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "q.csv", err);
    if (rc) {
        return rc;
    }
    gr_spm_csv_head(&f, "Q(v,l) of sec. 5.3.1, one velocity component, sampled uniformly in time",
                    &p->s);
    gr_file_note(&f, "# w = |v| / u_l, u_l = (2 D l / M^2)^(1/3); Q_scaled = u_l Q(v,l) (density "
                     "of the signed scaled\n"
                     "# component: collapses under v / l^(1/3)); Q in s/m; errors from the spread "
                     "between batches\n"
                     "# (_poisson: the sqrt(X) error of App. A.1, too small because samples of one "
                     "walk correlate)\n");
    gr_file_header(
        &f, "radius_index [1],radius [m],w_lo [1],w_hi [1],w [1],v [m s-1],samples [1],Q_scaled "
            "[1],Q_scaled_err [1],Q_scaled_err_poisson [1],Q [s m-1],Q_err [s m-1]");
    for (int k = 0; k < r->n_radii; k++) {
        const gr_spm_q *q = &r->q[k];
        const gr_histogram *h = &q->q.all;
        for (int i = 0; i < h->nbins; i++) {
            double w = gr_histogram_center(h, i), d = gr_spm_dist_density(&q->q, i),
                   e = gr_spm_dist_error(&q->q, i);
            fprintf(f.f, "%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.6g,%.4g\n", k,
                    p->radii[k], gr_histogram_lower(h, i), gr_histogram_upper(h, i), w, w * q->u,
                    h->count[i], d, e, gr_spm_dist_poisson_error(&q->q, i), d / q->u, e / q->u);
        }
    }
    rc = gr_file_commit(&f, err);
    if (rc) {
        return rc;
    }
    rc = gr_file_open(&f, dir, "q_radii.csv", err);
    if (rc) {
        return rc;
    }
    gr_spm_csv_head(&f,
                    "per radius: scales, first-passage time, Gaussian tail fit (5.12), collapse "
                    "against the first radius",
                    &p->s);
    gr_file_note(&f,
                 "# u_l in m/s, t_l in s, tau = sampling interval / t_l; exit_time and w2 (<w^2> "
                 "per component in\n"
                 "# time) in the walk's units; b of Q ~ A exp(-b w^2) over w >= %g (thesis: 0.98); "
                 "beta: free-exponent fit;\n"
                 "# chi2 between the scaled Q of this radius and of the first one over bins with "
                 ">= %g samples in both;\n"
                 "# c, c_prime: the thesis' constants of <v_x^2> = c (D l/M^2)^(2/3), <T_fp> = c' "
                 "(l^2 M^2/D)^(1/3)\n",
                 p->fit_from, MIN_COUNT);
    gr_file_header(
        &f,
        "radius [m],u_l [m s-1],t_l [s],tau [1],walks [1],exit_time [1],exit_time_err [1],w2 [1],b "
        "[1],"
        "b_err [1],A [1],fit_chi2_red [1],beta [1],beta_err [1],collapse_chi2 [1],collapse_dof [1],"
        "collapse_p [1],w2_err [1],c [1],c_err [1],c_prime [1],c_prime_err [1]");
    for (int k = 0; k < r->n_radii; k++) {
        const gr_spm_walk_stats *st = &r->q[k].stats;
        const gr_spm_tail_fit *ft = &r->fit[k];
        const gr_spm_collapse *c = &r->collapse[k];
        const gr_spm_constants *cc = &r->constants[k];
        fprintf(f.f,
                "%.6g,%.6g,%.6g,%.6g,%lld,%.6g,%.3g,%.6g,%.5g,%.3g,%.5g,%.3g,%.4g,%.3g,%.5g,%d,%."
                "4g,%.3g,%.6g,%.3g,%.6g,%.3g\n",
                p->radii[k], r->q[k].u, r->q[k].t_scale, r->q[k].tau, (long long)st->walks,
                st->exit_time_mean, st->exit_time_err, st->w2_time_mean, ft->b, ft->b_err, ft->A,
                ft->chi2_red, ft->beta, ft->beta_err, k ? c->chi2 : 0.0, k ? c->dof : 0,
                k ? c->p_value : 1.0, st->w2_time_err, cc->c, cc->c_err, cc->c_prime,
                cc->c_prime_err);
    }
    return gr_file_commit(&f, err);
}

static void json_tail_fit(cJSON *tf, const gr_spm_tail_fit *f)
{
    gr_spm_json_num(tf, "b", f->b);
    gr_spm_json_num(tf, "b_err", f->b_err);
    gr_spm_json_num(tf, "A", f->A);
    gr_spm_json_num(tf, "chi2_red", f->chi2_red);
}

static cJSON *summary(const gr_spm_circle_params *p, const gr_spm_circle_report *r)
{
    cJSON *j = gr_spm_json_head("circle");
    gr_spm_json_settings(j, &p->s, p->bins);
    cJSON_AddNumberToObject(j, "wmax", p->wmax);
    cJSON_AddNumberToObject(j, "fit_from", p->fit_from);
    cJSON *ra = cJSON_AddArrayToObject(j, "radii");
    for (int k = 0; k < r->n_radii; k++) {
        const gr_spm_tail_fit *ft = &r->fit[k];
        cJSON *x = cJSON_CreateObject();
        cJSON_AddNumberToObject(x, "radius", p->radii[k]);
        cJSON_AddNumberToObject(x, "u_l", r->q[k].u);
        cJSON_AddNumberToObject(x, "t_l", r->q[k].t_scale);
        cJSON_AddNumberToObject(x, "tau_over_t_l", r->q[k].tau);
        gr_spm_json_stats(x, &r->q[k].stats);
        cJSON *tf = cJSON_AddObjectToObject(x, "tail_fit");
        json_tail_fit(tf, ft);
        gr_spm_json_num(tf, "w_to", ft->wto);
        gr_spm_json_num(tf, "free_exponent", ft->beta);
        gr_spm_json_num(tf, "free_exponent_err", ft->beta_err);
        if (r->fit_note[k][0]) {
            cJSON_AddStringToObject(tf, "note", r->fit_note[k]);
        }
        /* B of 5.12-5.13 in SI units for this b */
        gr_spm_json_num(tf, "B", gr_spm_B(&p->s, ft->b));
        if (k > 0) {
            const gr_spm_collapse *cl = &r->collapse[k];
            cJSON *c = cJSON_AddObjectToObject(x, "collapse_vs_first");
            gr_spm_json_num(c, "chi2", cl->chi2);
            cJSON_AddNumberToObject(c, "dof", cl->dof);
            gr_spm_json_num(c, "chi2_red", cl->chi2_red);
            gr_spm_json_num(c, "p_value_permutation", cl->p_value);
            cJSON_AddNumberToObject(c, "permutations", cl->permutations);
            gr_spm_json_num(c, "p_value_chi2_law", cl->p_chi2);
            gr_spm_json_num(c, "max_abs_z", cl->max_abs_z);
        }
        cJSON_AddItemToArray(ra, x);
    }
    const gr_spm_tail_fit *pf = &r->pooled_fit;
    cJSON *pj = cJSON_AddObjectToObject(j, "pooled_tail_fit");
    json_tail_fit(pj, pf);
    gr_spm_json_num(pj, "w_from", p->fit_from);
    gr_spm_json_num(pj, "w_to", pf->wto);
    gr_spm_json_num(pj, "free_exponent", pf->beta);
    gr_spm_json_num(pj, "free_exponent_err", pf->beta_err);
    gr_spm_json_num(pj, "B", gr_spm_B(&p->s, pf->b));
    cJSON_AddNumberToObject(pj, "thesis_b", GR_SPM_THESIS_B_COEF);
    if (r->pooled_note[0]) {
        cJSON_AddStringToObject(pj, "note", r->pooled_note);
    }
    gr_spm_json_constants(j, &r->pooled_constants, "inverse-variance mean over the radii");
    cJSON_AddNumberToObject(j, "wall_seconds", r->wall_seconds);
    cJSON_AddArrayToObject(j, "plots");
    return j;
}

/* the collapse and the raw Q(v, l) */
static void plots(const char *dir, bool on, cJSON *j, const gr_spm_circle_params *p,
                  const gr_spm_circle_report *r)
{
    const gr_spm_tail_fit *pf = &r->pooled_fit;
    char body[8192], *b = body;
    size_t left = sizeof body;
    int k =
        snprintf(b, left,
                 "set title 'Q(v,l) rescaled: collapse under v / l^{1/3} (sec. 5.3.1), %dD'\n"
                 "set xlabel 'w = |v| / u_l,  u_l = (2Dl/M^2)^{1/3}'\nset ylabel 'u_l Q(v,l)'\n"
                 "set logscale y\nset format y '10^{%%L}'\nset format x '%%g'\nset key top right\n"
                 "A = %.10g\nb = %.10g\nbt = %.10g\n"
                 "plot ",
                 p->s.dim, isfinite(pf->A) ? pf->A : 1.0, isfinite(pf->b) ? pf->b : 1.0,
                 GR_SPM_THESIS_B_COEF);
    b += k;
    left -= (size_t)k;
    for (int i = 0; i < r->n_radii; i++) {
        k = snprintf(b, left,
                     "'q.csv' using 5:(($1==%d && $8>0) ? $8 : 1/0):9 with yerrorbars pt %d ps 0.5 "
                     "lc rgb '%s' title 'l = %g m', ",
                     i, 5 + 2 * (i / 6 % 4), gr_spm_colour(i % 6), p->radii[i]);
        b += k;
        left -= (size_t)k;
    }
    snprintf(b, left,
             "[x=%g:%g] A*exp(-b*x**2) lw 2 lc rgb 'black' title sprintf('pooled fit A exp(-%%.3f "
             "w^2)', b), "
             "[x=%g:%g] A*exp(-bt*x**2) dt 2 lc rgb 'black' title 'b = 0.98 (5.12)'\n",
             p->fit_from, p->wmax, p->fit_from, p->wmax);
    gr_spm_plot(dir, on, j, "q_collapse.png", body);
    b = body;
    left = sizeof body;
    k = snprintf(
        b, left,
        "set title 'Q(v,l) for fixed radii (sec. 5.3.1), %dD'\nset xlabel '|v| (m/s)'\nset ylabel "
        "'Q(v,l) (s/m)'\n"
        "set logscale y\nset format y '10^{%%L}'\nset format x '%%g'\nset key top right\nplot ",
        p->s.dim);
    b += k;
    left -= (size_t)k;
    for (int i = 0; i < r->n_radii; i++) {
        k = snprintf(b, left,
                     "'q.csv' using 6:(($1==%d && $11>0) ? $11 : 1/0) with linespoints pt %d ps "
                     "0.4 lc rgb '%s' title 'l = %g m'%s",
                     i, 5 + 2 * (i / 6 % 4), gr_spm_colour(i % 6), p->radii[i],
                     i + 1 < r->n_radii ? ", " : "\n");
        b += k;
        left -= (size_t)k;
    }
    gr_spm_plot(dir, on, j, "q_raw.png", body);
}

int gr_spm_circle_write(const char *dir, const gr_spm_circle_params *p,
                        const gr_spm_circle_report *r, bool on, gr_error *err)
{
    int rc = write_q(dir, p, r, err);
    if (rc) {
        return rc;
    }
    cJSON *j = summary(p, r);
    plots(dir, on, j, p, r);
    rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}
