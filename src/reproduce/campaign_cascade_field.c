/* kind = cascade_field (docs/campaigns/README.md): Table 6.2 (thesis sec. 6.2.2), the fractal
 * dimension D_f of the structure factor (6.5) of the multiplicative cascade fields themselves, for
 * every variant of sec. 6.2.1: UCP, UnonCP, the symmetrised cascade and Meakin 1-4 (Table 6.1), on
 * the thesis's grid (8 levels, 256 x 256 squares over L = 1 m). Per variant, `granule cascade` as
 * library calls (gr_cascade_study_run) for CASCADE_FIELD_SEEDS independent seeds of
 * `configurations` fields each (2 seeds of at most 10 at quick fidelity); every seed's
 * configuration-averaged S(k) is fitted with A k^-D_f over the default range (the fit a reader
 * should quote, gr_cascade_study_headline), and the row is the seeds' mean; its error the larger of
 * the seeds' standard error and one seed's fit error (the misfit to the lattice wiggles of S(k) is
 * systematic and does not average down over seeds). The fields need no run: the campaign's runs only carry the rest of its results. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/cascade_study.h"
#include "reproduce/campaign_points.h"

#define CASCADE_FIELD_SEEDS 5
#define CASCADE_FIELD_SEEDS_QUICK 2
#define CASCADE_FIELD_CONFIGURATIONS_QUICK 10

static const gr_cascade_variant variants[] = {GR_CASCADE_UCP,     GR_CASCADE_UNONCP,  GR_CASCADE_SYMMETRISED, GR_CASCADE_MEAKIN1,
                                              GR_CASCADE_MEAKIN2, GR_CASCADE_MEAKIN3, GR_CASCADE_MEAKIN4};

int campaign_cascade_field(const gr_campaign_result *r, gr_fidelity fid, campaign_rows *rows, FILE *data, gr_error *err)
{
    const bool full = fid == GR_FIDELITY_FULL;
    const int seeds = full ? CASCADE_FIELD_SEEDS : CASCADE_FIELD_SEEDS_QUICK;
    const int configurations = full ? r->configurations : (r->configurations < CASCADE_FIELD_CONFIGURATIONS_QUICK ? r->configurations : CASCADE_FIELD_CONFIGURATIONS_QUICK);
    fprintf(data, "group,seed,configurations,D_f,D_f_err,chi2_red,fit,q_min,q_max,wall_seconds\n");
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
            int rc = gr_cascade_study_run(&sp, &st, err);
            if (rc) {
                return rc;
            }
            const gr_cascade_fit *f = st.have_fit ? gr_cascade_study_headline(&st) : NULL;
            if (f && isfinite(f->D_f)) {
                v[n++] = f->D_f;
                err2 += f->D_f_err * f->D_f_err;
                fprintf(data, "\"%s\",%d,%d,%.6g,%.6g,%.4g,%s,%g,%g,%.3g\n", info->label, s, configurations, f->D_f, f->D_f_err,
                        f->chi2_red, st.headline_unweighted ? "unweighted" : "weighted", f->q_min, f->q_max, st.wall_seconds);
            } else {
                fprintf(data, "\"%s\",%d,%d,,,,none,,,%.3g\n", info->label, s, configurations, st.wall_seconds);
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
    return GR_OK;
}
