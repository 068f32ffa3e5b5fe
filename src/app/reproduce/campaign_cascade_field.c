/* kind = cascade_field (docs/campaigns/README.md): Table 6.2 (thesis sec. 6.2.2), the fractal
 * dimension D_f of the structure factor (6.5) of the multiplicative cascade fields themselves, for
 * every variant of sec. 6.2.1: UCP, UnonCP, the symmetrised cascade and Meakin 1-4 (Table 6.1), on
 * the thesis's grid (8 levels, 256 x 256 squares over L = 1 m). Per variant, `granule cascade` as
 * library calls (gr_cascade_study_run) for CASCADE_FIELD_SEEDS independent seeds of
 * `configurations` fields each (2 seeds of at most 10 at quick fidelity); every seed's
 * configuration-averaged S(k) is fitted with A k^-D_f over the default range (the fit a reader
 * should quote, gr_cascade_study_headline), and the row is the seeds' mean; its error the larger of
 * the seeds' standard error and one seed's fit error (the misfit to the lattice wiggles of S(k) is
 * systematic and does not average down over seeds). ID_sk.dat and ID_data.png hold seed 1's S(k) of every
 * variant with its fit, shifted apart as in Fig. 6.2. The fields need no run: the campaign's runs only
 * carry the rest of its results. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/cascade_study.h"
#include "io/files.h"
#include "app/reproduce/campaign_points.h"

#define CASCADE_FIELD_SEEDS 5
#define CASCADE_FIELD_SEEDS_QUICK 2
#define CASCADE_FIELD_CONFIGURATIONS_QUICK 10

static const gr_cascade_variant variants[] = {
    GR_CASCADE_UCP,     GR_CASCADE_UNONCP,  GR_CASCADE_SYMMETRISED, GR_CASCADE_MEAKIN1,
    GR_CASCADE_MEAKIN2, GR_CASCADE_MEAKIN3, GR_CASCADE_MEAKIN4};

/* Fig. 6.2: seed 1's S(k) of every variant over its first bin, one gnuplot block each, shifted by
 * 10^-i for clarity as the thesis's figure does, with the fitted A k^-D_f over the fit's bins. */
static void write_sk(FILE *f, const char *label, int i, const gr_cascade_study *st,
                     const gr_cascade_fit *fit)
{
    double first = NAN; /* UnonCP's total drifts as 2^n: every curve starts at 1, then shifted */
    for (int b = 0; b < st->nbins && !isfinite(first); b++) {
        first = st->bins[b].S > 0.0 ? st->bins[b].S : (double)NAN;
    }
    const double shift = pow(10.0, -i) / first;
    fprintf(f, "%s\"%s (x 1e-%d)\"\n", i ? "\n\n" : "", label, i);
    for (int b = 0; b < st->nbins; b++) {
        const gr_cascade_sk_bin *k = &st->bins[b];
        const bool in_fit = fit && k->q >= fit->q_min && k->q <= fit->q_max;
        if (k->S > 0.0) {
            fprintf(f, "%.6g %.6g %.6g\n", k->k, k->S * shift,
                    in_fit ? fit->A * pow(k->k, -fit->D_f) * shift : (double)NAN);
        }
    }
}

static void plot_sk(const char *results, const gr_campaign_result *r, int blocks)
{
    char body[1024];
    snprintf(body, sizeof body,
             "set datafile separator whitespace\nset logscale xy\nset format y '10^{%%L}'\nset key "
             "below height 1.5 noenhanced\n"
             "set xlabel 'k (1/m)'\nset ylabel 'S(k) / S(k_1) x 10^{-i}'\n"
             "set title \"Cascade fields' S(k) (6.5), 256 x 256 over 1 m (Fig. 6.2), fits of %s\" "
             "noenhanced\n"
             "plot for [i=0:%d] '%s_sk.dat' index i using 1:2 with points pt 7 ps 0.5 lc i+1 title "
             "columnheader(1), "
             "for [i=0:%d] '' index i using 1:3 with lines lw 2 lc i+1 notitle\n",
             r->id, blocks - 1, r->id, blocks - 1);
    campaign_draw(results, r->id, "_data", body);
}

int campaign_cascade_field(const gr_campaign_result *r, gr_fidelity fid, campaign_rows *rows,
                           const char *results, gr_file *data, gr_error *err)
{
    char name[96];
    snprintf(name, sizeof name, "%s_sk.dat", r->id);
    gr_file sk;
    int rc = gr_file_open(&sk, results, name, err);
    if (rc) {
        return rc;
    }
    const bool full = fid == GR_FIDELITY_FULL;
    const int seeds = full ? CASCADE_FIELD_SEEDS : CASCADE_FIELD_SEEDS_QUICK;
    const int configurations = full ? r->configurations
                                    : (r->configurations < CASCADE_FIELD_CONFIGURATIONS_QUICK
                                           ? r->configurations
                                           : CASCADE_FIELD_CONFIGURATIONS_QUICK);
    gr_file_header(data,
                   "group [],seed [1],configurations [1],D_f [1],D_f_err [1],chi2_red [1],fit "
                   "[],q_min [1],q_max [1],wall_seconds [s]");
    for (size_t i = 0; i < sizeof variants / sizeof variants[0]; i++) {
        const gr_cascade_variant_info *info = gr_cascade_variant_get(variants[i]);
        double v[CASCADE_FIELD_SEEDS], err2 = 0.0;
        int n = 0;
        for (int s = 1; s <= seeds; s++) {
            gr_cascade_study_params sp = {0};
            gr_cascade_settings_default(&sp.s);
            sp.s.variant = variants[i];
            sp.s.configurations = configurations;
            sp.s.seed = (unsigned long)s;
            gr_cascade_study st = {0};
            if ((rc = gr_cascade_study_run(&sp, &st, err))) {
                gr_file_abandon(&sk);
                return rc;
            }
            const gr_cascade_fit *f = st.have_fit ? gr_cascade_study_headline(&st) : NULL;
            if (s == 1) {
                write_sk(sk.f, info->label, (int)i, &st, f && isfinite(f->D_f) ? f : NULL);
            }
            if (f && isfinite(f->D_f)) {
                v[n++] = f->D_f;
                err2 += f->D_f_err * f->D_f_err;
                gr_csv_text(data->f, info->label, true);
                fprintf(data->f, ",%d,%d,%.6g,%.6g,%.4g,%s,%g,%g,%.3g\n", s, configurations, f->D_f,
                        f->D_f_err, f->chi2_red, st.headline_unweighted ? "unweighted" : "weighted",
                        f->q_min, f->q_max, st.wall_seconds);
            } else {
                gr_csv_text(data->f, info->label, true);
                fprintf(data->f, ",%d,%d,,,,none,,,%.3g\n", s, configurations, st.wall_seconds);
            }
            gr_cascade_study_free(&st);
        }
        campaign_row *row = campaign_group_row(rows, info->label);
        campaign_row_of_runs(r, row, v, n, err2, n);
        /* A seed's fit error is the power law's misfit to the lattice wiggles of S(k) (Fig. 6.2), the
         * same in every seed: it does not average down, so it is a floor under the seeds' error. */
        row->error_fit = n > 0 ? sqrt(err2 / n) : (double)NAN;
        if (isfinite(row->error_fit) && !(row->error >= row->error_fit)) {
            row->error = row->error_fit;
            campaign_row_thesis(r, row); /* z with this error */
        }
    }
    if ((rc = gr_file_commit(&sk, err))) {
        return rc;
    }
    plot_sk(results, r, (int)(sizeof variants / sizeof variants[0]));
    return GR_OK;
}
