/* kind = spm (docs/campaigns/README.md): the Single Particle Model's asymptotic P(v) (thesis sec.
 * 5.3.2, 5.27-5.31) predicted from every run's own free paths and set against the run's own P(v),
 * as the thesis's Figs. 5.12 and 5.13 do for its L = 0.6 m runs. Per run:
 *   - D_f and C of 4.25 from the free paths' tail as the thesis fits it (sec. 4.3.3, "the lowest
 *     decades, where P < 1"): the bins beyond the most probable free path where P_l < 1 per metre,
 *     l in m (the freepath observable's table is in diameters: l d, P / d), at least 10 counts;
 *     with `df` the D_f given (the thesis's 1.63) and only C fitted, else both;
 *   - alpha, h and S of 5.27-5.31 from D_f, C and B = 0.98 (M^2/2D)^(2/3) (gr_spm_predict, the
 *     library call behind `granule spm predict`);
 *   - the run's P(v) (pv.csv, folded about 0) fitted with 5.31 at that alpha and h: S measured,
 *     A0 and A0/P(0), and the slopes of the tail plot of Fig. 5.13 for P' = P(0) and P' = A0, over
 *     v >= x_min v_rms (default 2, beyond the crossover v_c ~ 1.5 v_r of Table 5.3) in bins with at
 *     least 50 counts (the low end of Table 5.1's window); with `tail = exponential` the fit is
 *     A0 exp(-S |v|) instead (alpha = 1, h = 0), the thesis's A0 of Fig. 5.13.
 * The row of a group is the seed mean of the quantity `y` names, its error the seeds' standard
 * error (with fewer than 3 seeds the larger of that and the runs' fit errors). The tables come from
 * the run folder or, for a point restored from a result set, from the series the archive keeps
 * (the keys of the CURVE results fig5.4 and fig4.10, campaign_spm_series); without them the run
 * gives no value. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/spm.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

#define SPM_COUNTS_MIN 50.0
#define SPM_X_MIN 2.0
#define SPM_MAX_BINS 4096
#define SPM_PL_TAIL_MAX 1.0 /* per metre: the thesis fits P_l "where P < 1" (sec. 4.3.3) */
#define SPM_PL_COUNTS_MIN 10.0

static const char *const quantities[] = {"D_f",         "C",        "alpha",
                                         "S_predicted", "S",        "S_over_predicted",
                                         "A0_over_P0",  "slope_P0", "slope_A0"};
/* Their units (ID_data.meta.json), with the row's exponents (docs/trajectories.md): C of 4.25 in
 * m^-(D_f - 1); 5.31 is ln P = ln A0 + h ln v - S v^alpha with the fit's alpha_fit and h_fit, so S
 * is in (m/s)^-alpha_fit and A0 / P(0) in (m/s)^-h_fit; S_predicted has the predicted alpha; the
 * slopes of Fig. 5.13 are of ln-ln lines. */
static const char *const quantity_units[] = {"1",
                                             "m m^-D_f",
                                             "1",
                                             "(m s-1)^-alpha",
                                             "(m s-1)^-alpha_fit",
                                             "(m s-1)^-alpha_fit (m s-1)^alpha",
                                             "(m s-1)^-h_fit",
                                             "1",
                                             "1"};
enum { Q_DF, Q_C, Q_ALPHA, Q_SPRED, Q_S, Q_SRATIO, Q_A0P0, Q_SLOPE_P0, Q_SLOPE_A0, Q_COUNT };

static int quantity_index(const char *y) { return campaign_name_index(quantities, Q_COUNT, y); }

bool campaign_spm_quantity_known(const char *y) { return quantity_index(y) >= 0; }

void campaign_spm_series(int which, gr_campaign_result *out)
{
    memset(out, 0, sizeof *out);
    out->kind = GR_RESULT_CURVE;
    snprintf(out->table, sizeof out->table, "%s", which ? "freepath.csv" : "pv.csv");
    snprintf(out->x, sizeof out->x, "%s", which ? "l_over_d" : "v");
    snprintf(out->y, sizeof out->y, "density");
    snprintf(out->y_err, sizeof out->y_err, "density_error");
}

/* Everything the kind measures in one run (NAN where it could not). */
typedef struct spm_run {
    double q[Q_COUNT], q_err[Q_COUNT];
    double v_rms, C_fit_chi2;
    int pl_points; /* the free-path tail fitted, l in m */
    double pl_lo, pl_hi;
    gr_spm_tail531 t;
    bool have_tail;
    /* the folded P(v) for the figure */
    int n;
    double *v, *p, *e, *counts;
} spm_run;

/* The free paths' tail as the thesis fits it (sec. 4.3.3: "the lowest decades, where P < 1"): the
 * bins beyond the most probable free path where P_l < p_max per metre (l in m; p_max 1 unless the
 * result's pl_max says otherwise), with at least 10 counts. The series is in diameters (the
 * freepath observable), converted to SI here: l d, P / d. Returns how many bins, written to l, p, e. */
static int pl_tail_si(const campaign_point *pt, double d, double p_max, double *l, double *p,
                      double *e)
{
    gr_campaign_result series;
    campaign_spm_series(1, &series);
    const int n = campaign_curve_series(pt, &series, l, p, e);
    int mode = 0;
    for (int i = 1; i < n; i++) {
        mode = p[i] > p[mode] ? i : mode;
    }
    int m = 0;
    for (int i = mode; i < n; i++) {
        const double ps = p[i] / d, es = e[i] / d,
                     counts = e[i] > 0.0 ? (p[i] / e[i]) * (p[i] / e[i]) : 0.0;
        if (ps > 0.0 && ps < p_max && counts >= SPM_PL_COUNTS_MIN) {
            l[m] = l[i] * d;
            p[m] = ps;
            e[m++] = es;
        }
    }
    return m;
}

/* D_f and C (SI) of 4.25 over that tail: both free, or C at the fixed D_f `df`. */
static void free_paths(const gr_campaign_result *r, const campaign_point *pt, double d, spm_run *o,
                       double *buf)
{
    double *l = buf, *p = buf + SPM_MAX_BINS, *e = buf + 2 * SPM_MAX_BINS;
    const int m = pl_tail_si(pt, d, r->pl_max > 0.0 ? r->pl_max : SPM_PL_TAIL_MAX, l, p, e);
    gr_error ignore = {0};
    o->pl_points = m;
    o->pl_lo = m ? l[0] : (double)NAN;
    o->pl_hi = m ? l[m - 1] : (double)NAN;
    if (r->df > 0.0) {
        o->q[Q_DF] = r->df;
        o->q_err[Q_DF] = 0.0;
        if (gr_spm_pl_fit_C(l, p, e, m, r->df - 1.0, 0.0, INFINITY, &o->q[Q_C], &o->q_err[Q_C],
                            &o->C_fit_chi2, &ignore) != GR_OK) {
            o->q[Q_C] = o->q_err[Q_C] = (double)NAN;
        }
        return;
    }
    gr_spm_pl pl = {.kind = GR_SPM_PL_TABLE, .n = m, .l = l, .p = p, .perr = e};
    gr_spm_pl_fit f;
    if (m > 0 && gr_spm_pl_fit_tail(&pl, l[0], &f, &ignore) == GR_OK) {
        const double scale = f.chi2_red > 1.0 ? sqrt(f.chi2_red) : 1.0; /* correlated counts */
        o->q[Q_DF] = f.df;
        o->q_err[Q_DF] = f.df_err * scale;
        o->q[Q_C] = f.C;
        o->q_err[Q_C] = f.C_err * scale;
        o->C_fit_chi2 = f.chi2_red;
    }
}

static void spm_run_free(spm_run *o) { free(o->v); }

static void analyse_run(const gr_campaign_result *r, const campaign_point *pt, spm_run *o,
                        double *buf)
{
    memset(o, 0, sizeof *o);
    for (int i = 0; i < Q_COUNT; i++) {
        o->q[i] = o->q_err[i] = (double)NAN;
    }
    const cJSON *s = pt->summary;
    const double d = 2.0 * gr_summary_number(s, "scene.system.radius");
    if (gr_summary_number(s, "scene.system.dim") != 2.0 || !(d > 0.0)) {
        return; /* 5.12's B and 4.25 are 2D statements */
    }
    free_paths(r, pt, d, o, buf);
    gr_spm_settings st;
    gr_spm_settings_default(&st);
    st.mass = gr_summary_number(s, "scene.system.mass");
    st.D = gr_summary_number(s, "scene.noise.D");
    gr_spm_prediction pred;
    gr_error ignore = {0};
    if (!(st.mass > 0.0 && st.D > 0.0) || !(o->q[Q_C] > 0.0) ||
        gr_spm_predict(o->q[Q_DF], gr_spm_B(&st, GR_SPM_THESIS_B_COEF), o->q[Q_C], &pred,
                       &ignore) != GR_OK) {
        return;
    }
    o->q[Q_ALPHA] = pred.alpha;
    o->q[Q_SPRED] = pred.S;
    /* the run's P(v), folded */
    gr_campaign_result series;
    campaign_spm_series(0, &series);
    double *v = buf, *p = buf + SPM_MAX_BINS, *e = buf + 2 * SPM_MAX_BINS;
    const int n = campaign_curve_series(pt, &series, v, p, e);
    o->v = malloc(4 * sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (!o->v) {
        return;
    }
    o->p = o->v + n;
    o->e = o->p + n;
    o->counts = o->e + n;
    o->n = gr_spm_fold_pv(v, p, e, n, o->v, o->p, o->e, o->counts);
    o->v_rms = gr_summary_number(s, "analysis.pv.v_rms");
    const double x_lo = r->x_min > 0.0 ? r->x_min : SPM_X_MIN;
    /* tail = exponential: A0 exp(-S |v|), the thesis's "exponential fitted asymptotically" of Fig. 5.13 */
    const double alpha = r->tail_exponential ? 1.0 : pred.alpha,
                 h = r->tail_exponential ? 0.0 : pred.h;
    o->have_tail =
        o->n > 0 && gr_spm_tail531_fit(o->v, o->p, o->e, o->counts, o->n,
                                       gr_summary_number(s, "analysis.pv.P0"), o->v_rms, alpha, h,
                                       x_lo, r->x_max, SPM_COUNTS_MIN,
                                       r->tail_exponential ? 0.0 : pred.S, &o->t, &ignore) == GR_OK;
    if (o->have_tail) {
        o->q[Q_S] = o->t.S;
        o->q_err[Q_S] = o->t.S_err;
        o->q[Q_SRATIO] = o->t.S / pred.S;
        o->q_err[Q_SRATIO] = o->t.S_err / pred.S;
        o->q[Q_A0P0] = o->t.A0_over_P0;
        o->q_err[Q_A0P0] = o->t.A0_over_P0 * o->t.lnA0_err;
        o->q[Q_SLOPE_P0] = o->t.slope_P0;
        o->q_err[Q_SLOPE_P0] = o->t.slope_P0_err;
        o->q[Q_SLOPE_A0] = o->t.slope_A0;
        o->q_err[Q_SLOPE_A0] = o->t.slope_A0_err;
    }
}

/* One gnuplot block per group (its first run with a tail fit): the folded P(v), 5.31 fitted and
 * predicted, and the tail plot's two series with their lines. */
static void write_block(FILE *f, const char *group, const spm_run *o, bool first)
{
    const gr_spm_tail531 *t = &o->t;
    fprintf(f, "%s\"%s\"\n", first ? "" : "\n\n", group);
    fprintf(f, "# v v_over_vrms P P_err in_window P_531_fit P_531_predicted moon_P0 moon_A0 "
               "line_P0 line_A0\n");
    for (int i = 0; i < o->n; i++) {
        if (!(o->p[i] > 0.0)) {
            continue;
        }
        const double v = o->v[i], lx = log(v / o->v_rms);
        const bool in = v >= t->v_lo && v <= t->v_hi && o->counts[i] >= SPM_COUNTS_MIN;
        const double r0 = o->p[i] / t->P0, ra = o->p[i] / t->A0;
        fprintf(f, "%.6g %.6g %.6g %.6g %d %.6g %.6g %.6g %.6g %.6g %.6g\n", v, v / o->v_rms,
                o->p[i], o->e[i], in,
                v >= t->v_lo ? exp(gr_spm_tail531_log(t->lnA0, t->h, t->S, t->alpha, v))
                             : (double)NAN,
                v >= t->v_lo && isfinite(t->lnA0_at_S_pred)
                    ? exp(gr_spm_tail531_log(t->lnA0_at_S_pred, t->h, o->q[Q_SPRED], t->alpha, v))
                    : (double)NAN,
                r0 > 0.0 && r0 < 1.0 ? -log(-log(r0)) : (double)NAN,
                ra > 0.0 && ra < 1.0 ? -log(-log(ra)) : (double)NAN,
                in ? t->icpt_P0 + t->slope_P0 * lx : (double)NAN,
                in ? t->icpt_A0 + t->slope_A0 * lx : (double)NAN);
    }
}

/* titles: the blocks' groups in physical labels (N = 3000, L = 0.2 m), a gnuplot array's items;
 * labels too long for a row of the key (contact-models' model names) go one per line in a smaller
 * font: gnuplot drops a key wider than the picture */
static void draw(const char *results, const gr_campaign_result *r, int blocks, const char *titles,
                 bool long_labels)
{
    char body[16384];
    const char *key = long_labels ? "set key below height 1.5 noenhanced maxcols 1 font ',11'\n"
                                  : "set key below height 1.5 noenhanced\n";
    const int q = quantity_index(r->y);
    if (q == Q_A0P0 || q == Q_SLOPE_P0 || q == Q_SLOPE_A0) { /* Fig. 5.13 */
        snprintf(
            body, sizeof body,
            "array T[%d] = [%s]\n"
            "set datafile separator whitespace\nset datafile missing 'nan'\n%s"
            "set xlabel 'ln(v / v_{rms})'\nset ylabel '-ln(-ln(P / P^{/Symbol \\242}))'\n"
            "set title \"%s: P' = P(0) (filled) and A_0 (open), lines fitted over the window\" "
            "noenhanced\n"
            "plot for [i=0:%d] '%s_tail.dat' index i using (log($2)):8 with points pt 7 ps 0.5 lc "
            "i+1 title T[i+1], "
            "for [i=0:%d] '' index i using (log($2)):9 with points pt 6 ps 0.5 lc i+1 notitle, "
            "for [i=0:%d] '' index i using (log($2)):10 with lines lw 2 lc i+1 notitle, "
            "for [i=0:%d] '' index i using (log($2)):11 with lines lw 2 dt 2 lc i+1 notitle\n",
            blocks, titles, key, r->id, blocks - 1, r->id, blocks - 1, blocks - 1, blocks - 1);
    } else { /* Fig. 5.12 */
        snprintf(
            body, sizeof body,
            "array T[%d] = [%s]\n"
            "set datafile separator whitespace\nset datafile missing 'nan'\nset logscale y\nset "
            "format y '10^{%%L}'\n"
            "%sset xlabel '|v| (m/s)'\nset ylabel 'P(v) (s/m)'\n"
            "set title \"%s: the runs' P(v), 5.31 with the predicted S (solid) and fitted "
            "(dashed)\" noenhanced\n"
            "plot for [i=0:%d] '%s_tail.dat' index i using 1:3 with points pt 7 ps 0.4 lc i+1 "
            "title T[i+1], "
            "for [i=0:%d] '' index i using 1:7 with lines lw 2 lc i+1 notitle, "
            "for [i=0:%d] '' index i using 1:6 with lines lw 1 dt 2 lc i+1 notitle\n",
            blocks, titles, key, r->id, blocks - 1, r->id, blocks - 1, blocks - 1);
    }
    campaign_draw(results, r->id, "_data", body);
}

int campaign_spm(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                 campaign_rows *rows, const char *results, gr_file *data, gr_error *err)
{
    (void)c;
    const int q = quantity_index(r->y);
    if (q < 0) {
        return GR_FAIL(err, GR_EINVAL, "[result %s] kind = spm: y = %s: allowed %s", r->id, r->y,
                       GR_CAMPAIGN_SPM_QUANTITIES);
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/%s_tail.dat", results, r->id);
    FILE *tail = fopen(path, "w");
    double *buf = malloc(3 * SPM_MAX_BINS * sizeof *buf);
    if (!tail || !buf) {
        if (tail) {
            fclose(tail);
        }
        free(buf);
        return GR_FAIL(err, GR_EIO, "cannot write %s", path);
    }
    gr_file_columns(data, "group [],seed [1]");
    for (int k = 0; k < Q_COUNT; k++) {
        char name[64];
        snprintf(name, sizeof name, "%s_error", quantities[k]);
        gr_file_column(data, quantities[k], quantity_units[k]);
        gr_file_column(data, name, quantity_units[k]);
    }
    gr_file_header(data, "v_lo [m s-1],v_hi [m s-1],fit_points [1],decades [1],chi2_red_531 [1],A0 "
                         "[s m-1 (m s-1)^-h_fit],P0 [s m-1],alpha_fit [1],h_fit [1],pl_l_lo [m],"
                         "pl_l_hi [m],pl_points [1],pl_chi2_red [1]");
    static char g[MAX_GROUPS][160];
    const int ng = campaign_groups(pts, NULL, NULL, g);
    int blocks = 0;
    char titles[MAX_GROUPS * 48] = "";
    bool long_labels = false;
    for (int gi = 0; gi < ng; gi++) {
        campaign_row *row = campaign_group_row(rows, g[gi]);
        const campaign_point *m[MAX_SEEDS];
        const int nm = campaign_members(pts, g[gi], m, MAX_SEEDS);
        double v[MAX_SEEDS], e2 = 0.0, chi2 = 0.0;
        int n = 0, n_err = 0;
        bool drawn = false;
        for (int i = 0; i < nm; i++) {
            spm_run o;
            analyse_run(r, m[i], &o, buf);
            gr_csv_text(data->f, g[gi], true);
            fprintf(data->f, ",%d", campaign_seed_of(m[i]));
            for (int k = 0; k < Q_COUNT; k++) {
                fprintf(data->f, ",%.9g,%.9g", o.q[k], o.q_err[k]);
            }
            fprintf(data->f, ",%.6g,%.6g,%d,%.4g,%.4g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.4g\n",
                    o.t.v_lo, o.t.v_hi, o.t.n_points, o.t.decades, o.t.chi2_red, o.t.A0, o.t.P0,
                    o.t.alpha, o.t.h, o.pl_lo, o.pl_hi, o.pl_points, o.C_fit_chi2);
            if (o.have_tail && !drawn) {
                write_block(tail, g[gi], &o, blocks == 0);
                char label[160];
                campaign_pretty_group(g[gi], label, sizeof label);
                long_labels |= strlen(label) > 40;
                const size_t used = strlen(titles);
                snprintf(titles + used, sizeof titles - used, "%s\"%s\"", blocks ? ", " : "",
                         label);
                drawn = true;
                blocks++;
            }
            if (isfinite(o.q[q])) {
                v[n++] = o.q[q];
                if (isfinite(o.q_err[q])) {
                    e2 += o.q_err[q] * o.q_err[q];
                    n_err++;
                }
                if (n == 1 &&
                    q <= Q_C) { /* the first run's window, for the page: free paths in m */
                    row->n_x = o.pl_points;
                    row->x_lo = o.pl_lo;
                    row->x_hi = o.pl_hi;
                    snprintf(row->x_unit, sizeof row->x_unit, "m");
                } else if (n == 1 && o.have_tail && q >= Q_S) { /* ... or |v| in m/s */
                    row->n_x = o.t.n_points;
                    row->x_lo = o.t.v_lo;
                    row->x_hi = o.t.v_hi;
                    snprintf(row->x_unit, sizeof row->x_unit, "m s-1");
                }
                chi2 += q <= Q_C ? o.C_fit_chi2 : o.t.chi2_red;
                campaign_add_cost(row, m[i]);
            }
            spm_run_free(&o);
        }
        campaign_row_of_runs(r, row, v, n, e2, n_err);
        row->chi2_red =
            n && row->n_x ? chi2 / n : (double)NAN; /* of the fits behind the quantity */
    }
    free(buf);
    if (fclose(tail)) {
        return GR_FAIL(err, GR_EIO, "cannot write %s", path);
    }
    if (blocks) {
        draw(results, r, blocks, titles, long_labels);
    }
    return GR_OK;
}
