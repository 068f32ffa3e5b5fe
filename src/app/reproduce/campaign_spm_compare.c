/* kind = spm_compare (docs/campaigns/README.md): Fig. 5.10, the full Single Particle Model (thesis
 * sec. 5.2.3: every walk draws its free path l from P_l) with P_l the run's own free paths
 * (freepath.csv), beside the run's P(v) per component from its snapshots, the SPM curve scaled
 * vertically as the thesis's figure does. Per run, with the library calls behind `granule spm full
 * --compare-run` (gr_spm_full_prepare/run, walks by fidelity, seeded by the run's seed), the two
 * P(v) series on the same bins are kept as RUN/spm_compare.csv (a first line "# walks W seed S"
 * names what made them; another W reruns the walks); the archive keeps them (series.json), so a
 * result set restored without the run folders gives the same rows. The numbers come from the
 * series alone (gr_spm_compare_series): the fraction of bins beyond 2 v_rms within z_max = 3 of
 * the scaled SPM curve, the decades of P_rfm over which they agree contiguously from the top,
 * the vertical scale k, the velocity scale s of a fit with both scales, and the tail exponents of
 * A exp(-(v/v0)^alpha) of both curves over the same bins. The row of a group is the seed mean. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "granule/spm.h"
#include "granule/spm_study.h"
#include "io/files.h"
#include "app/reproduce/campaign_points.h"

#define CMP_TABLE "spm_compare.csv"
#define CMP_FROM_VRMS                                                                              \
    2.0 /* `spm full`'s --compare-from default: beyond the crossover (Table 5.3) */
#define CMP_Z_MAX 3.0

static const char *const quantities[] = {"frac_within", "decades",   "k",
                                         "s",           "alpha_spm", "alpha_rfm"};
enum { Q_FRAC, Q_DECADES, Q_K, Q_S, Q_ALPHA_SPM, Q_ALPHA_RFM, Q_COUNT };

static int quantity_index(const char *y) { return campaign_name_index(quantities, Q_COUNT, y); }

bool campaign_spm_compare_quantity_known(const char *y) { return quantity_index(y) >= 0; }

void campaign_spm_compare_series(int which, gr_campaign_result *out)
{
    memset(out, 0, sizeof *out);
    out->kind = GR_RESULT_CURVE;
    snprintf(out->table, sizeof out->table, CMP_TABLE);
    snprintf(out->x, sizeof out->x, "v");
    snprintf(out->y, sizeof out->y, "%s", which ? "p_rfm" : "p_spm");
    snprintf(out->y_err, sizeof out->y_err, "%s", which ? "e_rfm" : "e_spm");
}

/* Is RUN/spm_compare.csv there and made by these walks? */
static bool table_current(const char *dir, long walks, int seed)
{
    char path[1300], line[128], want[128];
    snprintf(path, sizeof path, "%s/" CMP_TABLE, dir);
    FILE *f = gr_input_fopen(path, &(int){0});
    if (!f) {
        return false;
    }
    const bool ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    snprintf(want, sizeof want, "# walks %ld seed %d\n", walks, seed);
    return ok && !strcmp(line, want);
}

/* The SPM walks from the run's free paths against its snapshots: RUN/spm_compare.csv. A run
 * without snapshots (or restored from a result set) is left alone. */
static void make_table(const campaign_point *pt, long walks, int seed)
{
    char snaps[1200];
    snprintf(snaps, sizeof snaps, "%.1100s/snapshots", pt->dir);
    struct stat st;
    if (stat(snaps, &st) != 0 || !S_ISDIR(st.st_mode) || table_current(pt->dir, walks, seed)) {
        return;
    }
    gr_spm_full_params p;
    gr_spm_full_params_default(&p);
    p.run_dir = pt->dir;
    p.s.walks = walks;
    p.s.seed = (uint64_t)seed;
    gr_spm_full_report r;
    gr_error err = {0};
    int rc = gr_spm_full_prepare(&p, &r, &err);
    if (!rc) {
        rc = gr_spm_full_run(&p, &r, &err);
    }
    char path[1300];
    snprintf(path, sizeof path, "%s/" CMP_TABLE, pt->dir);
    FILE *f = rc ? NULL : fopen(path, "w");
    if (f) {
        fprintf(f, "# walks %ld seed %d\nv,p_spm,e_spm,p_rfm,e_rfm\n", walks, seed);
        for (int i = 0; i < r.nb; i++) {
            fprintf(f, "%.9g,%.9g,%.9g,%.9g,%.9g\n", r.v[i], r.p_spm[i], r.e_spm[i], r.p_rfm[i],
                    r.e_rfm[i]);
        }
        if (fclose(f)) {
            remove(path);
        }
    } else {
        campaign_note("%s: spm full not run: %s", pt->dir,
                      rc ? err.message : "cannot write " CMP_TABLE);
    }
    gr_spm_full_report_free(&r);
}

typedef struct cmp_run {
    int n;
    double *v, *ps, *es, *pr, *er; /* one allocation */
    gr_spm_series_compare c;
    bool ok;
    double q[Q_COUNT], q_err[Q_COUNT];
} cmp_run;

static void analyse_run(const campaign_point *pt, long walks, cmp_run *o)
{
    memset(o, 0, sizeof *o);
    for (int k = 0; k < Q_COUNT; k++) {
        o->q[k] = o->q_err[k] = (double)NAN;
    }
    make_table(pt, walks, campaign_seed_of(pt));
    o->v = malloc(6 * GR_SPM_SERIES_MAX_BINS * sizeof(double));
    if (!o->v) {
        return;
    }
    o->ps = o->v + GR_SPM_SERIES_MAX_BINS;
    o->es = o->ps + GR_SPM_SERIES_MAX_BINS;
    o->pr = o->es + GR_SPM_SERIES_MAX_BINS;
    o->er = o->pr + GR_SPM_SERIES_MAX_BINS;
    double *v2 = o->er + GR_SPM_SERIES_MAX_BINS;
    gr_campaign_result s;
    campaign_spm_compare_series(0, &s);
    const int n = campaign_curve_series(pt, &s, o->v, o->ps, o->es);
    campaign_spm_compare_series(1, &s);
    const int n2 = campaign_curve_series(pt, &s, v2, o->pr, o->er);
    if (n < 3 || n2 != n) {
        return;
    }
    o->n = n; /* both series at the archive's 6 digits (campaign_curve_series): live = restored */
    gr_error ignore = {0};
    o->ok = gr_spm_compare_series(o->v, o->ps, o->es, o->pr, o->er, n, CMP_FROM_VRMS, CMP_Z_MAX,
                                  &o->c, &ignore) == GR_OK;
    if (!o->ok) {
        return;
    }
    o->q[Q_FRAC] = o->c.amp.frac_within;
    o->q[Q_DECADES] = o->c.amp.decades;
    o->q[Q_K] = o->c.amp.k;
    o->q_err[Q_K] = o->c.amp.k_err;
    if (o->c.have_scaled) {
        o->q[Q_S] = o->c.scaled.s;
        o->q_err[Q_S] = o->c.scaled.s_err;
    }
    o->q[Q_ALPHA_SPM] = o->c.alpha_spm;
    o->q_err[Q_ALPHA_SPM] = o->c.alpha_spm_err;
    o->q[Q_ALPHA_RFM] = o->c.alpha_rfm;
    o->q_err[Q_ALPHA_RFM] = o->c.alpha_rfm_err;
}

/* One gnuplot block per run: the run's P(v) and the SPM's scaled by k (Fig. 5.10's dashed lines). */
static void write_block(FILE *f, const char *group, int seed, const cmp_run *o, bool first)
{
    char label[200];
    campaign_pretty_group(group, label, sizeof label); /* N = 3000, L = 0.2 m */
    fprintf(f, "%s\"%s, seed %d\"\n# v P_rfm P_rfm_err k_P_spm k_P_spm_err compared\n",
            first ? "" : "\n\n", label, seed);
    for (int i = 0; i < o->n; i++) {
        double me = 0.0;
        const double m = o->ps[i] > 0.0
                             ? gr_spm_compare_model(&o->c.amp, o->v, o->ps, o->es, o->n, i, &me)
                             : (double)NAN;
        if (o->pr[i] > 0.0 || m > 0.0) {
            fprintf(f, "%.6g %.6g %.6g %.6g %.6g %d\n", o->v[i],
                    o->pr[i] > 0.0 ? o->pr[i] : (double)NAN, o->er[i], m > 0.0 ? m : (double)NAN,
                    me, o->v[i] >= o->c.v_from);
        }
    }
}

static void draw(const char *results, const gr_campaign_result *r, int blocks)
{
    char body[2048];
    snprintf(
        body, sizeof body,
        "set datafile separator whitespace\nset datafile missing 'nan'\nset logscale y\nset format "
        "y '10^{%%L}'\n"
        "set key below height 1.5 noenhanced\nset xlabel '|v| (m/s)'\nset ylabel 'P(v) (s/m)'\n"
        "set title \"P(v) of each run (points) and the SPM from its free paths, times k "
        "(lines)\" noenhanced\n"
        "plot for [i=0:%d] '%s_pv.dat' index i using 1:2 with points pt 7 ps 0.4 lc i+1 title "
        "columnheader(1), "
        "for [i=0:%d] '' index i using 1:4 with lines lw 2 lc i+1 notitle\n",
        blocks - 1, r->id, blocks - 1);
    campaign_draw(results, r->id, "_data", body);
}

int campaign_spm_compare(const gr_campaign_result *r, gr_fidelity fid, const campaign_points *pts,
                         campaign_rows *rows, const char *results, gr_file *data, gr_error *err)
{
    const int q = quantity_index(r->y);
    if (q < 0) {
        return GR_FAIL(err, GR_EINVAL, "[result %s] kind = spm_compare: y = %s: allowed %s", r->id,
                       r->y, GR_CAMPAIGN_SPM_COMPARE_QUANTITIES);
    }
    const long walks = fid == GR_FIDELITY_FULL
                           ? (r->walks > 0 ? r->walks : GR_CAMPAIGN_SPM_WALKS)
                           : (r->walks_quick > 0 ? r->walks_quick : GR_CAMPAIGN_SPM_WALKS_QUICK);
    char path[1200];
    snprintf(path, sizeof path, "%s/%s_pv.dat", results, r->id);
    FILE *blocks_file = fopen(path, "w");
    if (!blocks_file) {
        return GR_FAIL(err, GR_EIO, "cannot write %s", path);
    }
    gr_file_columns(data, "group [],seed [1]");
    for (int k = 0; k < Q_COUNT; k++) { /* fractions, decades, scale factors, exponents */
        char name[64];
        snprintf(name, sizeof name, "%s_error", quantities[k]);
        gr_file_column(data, quantities[k], "1");
        gr_file_column(data, name, "1");
    }
    gr_file_header(data, "v_rms [m s-1],v_from [m s-1],v_agree_lo [m s-1],v_agree_hi [m s-1],"
                         "agree_bins [1],compared_bins [1],chi2_red_k [1],chi2_red_ks [1],k_with_s "
                         "[1],points_alpha_spm [1],points_alpha_rfm [1]");
    static char g[MAX_GROUPS][160];
    const int ng = campaign_groups(pts, NULL, NULL, g);
    int blocks = 0;
    for (int gi = 0; gi < ng; gi++) {
        campaign_row *row = campaign_group_row(rows, g[gi]);
        const campaign_point *m[MAX_SEEDS];
        const int nm = campaign_members(pts, g[gi], m, MAX_SEEDS);
        double v[MAX_SEEDS], e2 = 0.0, chi2 = 0.0;
        int n = 0, n_err = 0;
        for (int i = 0; i < nm; i++) {
            cmp_run o;
            analyse_run(m[i], walks, &o);
            const gr_spm_series_compare *c = &o.c;
            gr_csv_text(data->f, g[gi], true);
            fprintf(data->f, ",%d", campaign_seed_of(m[i]));
            for (int k = 0; k < Q_COUNT; k++) {
                fprintf(data->f, ",%.9g,%.9g", o.q[k], o.q_err[k]);
            }
            fprintf(data->f, ",%.6g,%.6g,%.6g,%.6g,%d,%d,%.4g,%.4g,%.6g,%d,%d\n", c->v_rms,
                    c->v_from, c->amp.v_agree_lo, c->amp.v_agree_hi, c->amp.agree_bins,
                    c->amp.n_points, c->amp.chi2_red, c->scaled.chi2_red, c->scaled.k,
                    c->points_spm, c->points_rfm);
            if (o.ok) {
                write_block(blocks_file, g[gi], campaign_seed_of(m[i]), &o, blocks == 0);
                blocks++;
            }
            if (isfinite(o.q[q])) {
                v[n++] = o.q[q];
                if (isfinite(o.q_err[q])) {
                    e2 += o.q_err[q] * o.q_err[q];
                    n_err++;
                }
                if (n == 1) { /* the first run's compared window, for the page: |v| in m/s */
                    row->n_x = c->amp.n_points;
                    row->x_lo = c->v_from;
                    snprintf(row->x_unit, sizeof row->x_unit, "m s-1");
                    row->x_hi = c->amp.v_agree_hi;
                }
                chi2 += q == Q_S ? c->scaled.chi2_red : c->amp.chi2_red;
                campaign_add_cost(row, m[i]);
            }
            free(o.v);
        }
        campaign_row_of_runs(r, row, v, n, e2, n_err);
        row->chi2_red = n ? chi2 / n : (double)NAN;
    }
    if (fclose(blocks_file)) {
        return GR_FAIL(err, GR_EIO, "cannot write %s", path);
    }
    if (blocks) {
        draw(results, r, blocks);
    }
    return GR_OK;
}
