/* kind = spm_circle (docs/campaigns/README.md): Fig. 5.11 and eq. 5.12 (thesis sec. 5.3.1), the
 * velocity distribution Q(v,l) of a particle that starts at rest in the centre of a disc of fixed
 * radius l and is driven by the random force until it reaches the rim. The walks use the runs' M
 * and D (the first point's scene) and `granule spm circle`'s library calls (gr_spm_circle_run,
 * seed 1, `walks` per radius or `walks_quick` at quick fidelity) at the radii of the thesis's
 * figure and three larger ones (3.6, 10, 20, 40 mm). Per radius, and pooled over the radii in the
 * collapsed variable w = v / u_l, u_l = (2 D l / M^2)^(1/3), the Gaussian tail of 5.12,
 * u_l Q = A exp(-b w^2), is fitted over w >= 2.5 (where one Gaussian fits: docs/theory-spm.md):
 *   b            the coefficient of 5.12 (thesis 0.98), the same for every l if Q collapses;
 *   coefficient  b (M^2 / 2 D l)^(2/3), the tail of Q in s^2/m^2 (thesis Fig. 5.11: 6.56 at 3.6 mm).
 * The error is the fit's with the errors of 20 batches of independent walks (every walk starts
 * afresh: the batches are independent samples, not blocks of one correlated run), scaled by
 * sqrt(chi2/dof) when that exceeds 1. The walks take seconds, so they are rerun at every collect
 * rather than archived. ID_q.dat holds u_l Q(w) per radius; ID_data.png draws it with the fitted
 * tail and the thesis's b = 0.98 through the same amplitude. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/spm_study.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

#define CIRCLE_WALKS 400000
#define CIRCLE_WALKS_QUICK 5000
#define POOLED_GROUP "pooled"

static const char *const quantities[] = {"b", "coefficient"};
enum { Q_B, Q_COEFFICIENT, Q_COUNT };

bool campaign_spm_circle_quantity_known(const char *y)
{
    return campaign_name_index(quantities, Q_COUNT, y) >= 0;
}

/* (M^2 / 2 D l)^(2/3): b in the collapsed variable w times this is the coefficient of v^2 in s^2/m^2 */
static double v2_scale(double mass, double D, double l)
{
    return pow(mass * mass / (2.0 * D * l), 2.0 / 3.0);
}

/* The fit error of b, inflated by sqrt(chi2/dof) where the fit is worse than its errors say. */
static double b_error(const gr_spm_tail_fit *f)
{
    return f->b_err * (f->chi2_red > 1.0 ? sqrt(f->chi2_red) : 1.0);
}

static void fill_row(const gr_campaign_result *r, campaign_row *row, const gr_spm_tail_fit *f,
                     double scale)
{
    row->value = f->b * scale;
    row->error = row->error_fit = b_error(f) * scale;
    row->error_seeds = NAN;
    row->n_seeds = 1;
    row->n_x = f->n_points;
    row->chi2_red = f->chi2_red;
    row->x_lo = f->wfrom;
    row->x_hi = f->wto;
    snprintf(row->x_unit, sizeof row->x_unit, "1"); /* w = v / u_l */
    campaign_row_thesis(r, row);
}

/* u_l Q(w) of every radius, one gnuplot index block each, and the figure. */
static int write_q(const char *results, const gr_campaign_result *r,
                   const gr_spm_circle_report *rep, gr_error *err)
{
    char name[96];
    snprintf(name, sizeof name, "%s_q.dat", r->id);
    gr_file f;
    int rc = gr_file_open(&f, results, name, err);
    if (rc) {
        return rc;
    }
    for (int k = 0; k < rep->n_radii; k++) {
        const gr_histogram *h = &rep->q[k].q.all;
        fprintf(f.f, "%s\"l = %g mm\"\n", k ? "\n\n" : "", 1e3 * rep->q[k].radius);
        for (int i = 0; i < h->nbins; i++) {
            const double p = gr_spm_dist_density(&rep->q[k].q, i);
            if (p > 0.0) {
                fprintf(f.f, "%.6g %.6g %.6g\n", h->lo + (i + 0.5) * (h->hi - h->lo) / h->nbins, p,
                        gr_spm_dist_error(&rep->q[k].q, i));
            }
        }
    }
    if ((rc = gr_file_commit(&f, err))) {
        return rc;
    }
    const gr_spm_tail_fit *pf = &rep->pooled_fit;
    char body[2048];
    snprintf(body, sizeof body,
             "set datafile separator whitespace\nset logscale y\nset format y '10^{%%L}'\nset key "
             "below height 1.5 noenhanced\n"
             "set xlabel 'w = v / u_l,  u_l = (2 D l / M^2)^{1/3}'\nset ylabel 'u_l Q(v, l)'\n"
             "set title \"Q(v,l) of a particle in a disc of fixed radius (Fig. 5.11), collapsed "
             "(sec. 5.3.1)\" noenhanced\n"
             "plot for [i=0:%d] '%s' index i using 1:2 with points pt 7 ps 0.5 lc i+1 title "
             "columnheader(1), "
             "(x >= %g ? %.9g * exp(-%.9g * x**2) : 1/0) with lines lw 2 lc rgb 'black' title "
             "'pooled fit, b = %.3f', "
             "(x >= %g ? %.9g * exp(-%.9g * x**2 + %.9g * %.9g**2) : 1/0) with lines dt 2 lw 2 lc "
             "rgb '#c0392b' "
             "title 'thesis 5.12: b = 0.98'\n",
             rep->n_radii - 1, name, pf->wfrom, pf->A, pf->b, pf->b, pf->wfrom,
             pf->A * exp(-pf->b * pf->wfrom * pf->wfrom), 0.98, 0.98, pf->wfrom);
    campaign_draw(results, r->id, "_data", body);
    return GR_OK;
}

int campaign_spm_circle(const gr_campaign_result *r, gr_fidelity fid, const campaign_points *pts,
                        campaign_rows *rows, const char *results, gr_file *data, gr_error *err)
{
    const int q = campaign_name_index(quantities, Q_COUNT, r->y);
    gr_file_header(data, "group [],l [m],u_l [m s-1],b [1],b_err [1],chi2_red [1],w_from [1],w_to "
                         "[1],bins [1],beta [1],beta_err [1],coefficient [s2 m-2],coefficient_err "
                         "[s2 m-2]");
    if (pts->n == 0) {
        return GR_OK;
    }
    gr_spm_circle_params p;
    gr_spm_circle_params_default(&p);
    p.s.mass = gr_summary_number(pts->p[0].summary, "scene.system.mass");
    p.s.D = gr_summary_number(pts->p[0].summary, "scene.noise.D");
    p.s.dim = 2;
    const long walks = fid == GR_FIDELITY_FULL
                           ? (r->walks ? r->walks : CIRCLE_WALKS)
                           : (r->walks_quick ? r->walks_quick : CIRCLE_WALKS_QUICK);
    p.s.walks = walks;
    if (!(p.s.mass > 0.0 && p.s.D > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "spm_circle: the runs' summaries lack scene.system.mass or scene.noise.D");
    }
    gr_spm_circle_report rep;
    int rc = gr_spm_circle_run(&p, &rep, err);
    if (rc) {
        return rc;
    }
    for (int k = 0; k <= rep.n_radii; k++) {
        const bool pooled = k == rep.n_radii;
        const gr_spm_tail_fit *f = pooled ? &rep.pooled_fit : &rep.fit[k];
        const double l = pooled ? (double)NAN : rep.q[k].radius,
                     scale = pooled ? (double)NAN : v2_scale(p.s.mass, p.s.D, l);
        char group[64];
        snprintf(group, sizeof group, pooled ? POOLED_GROUP : "l=%g", l);
        gr_csv_text(data->f, group, true);
        fprintf(data->f, ",%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.4g,%d,%.6g,%.6g,%.6g,%.6g\n", l,
                pooled ? (double)NAN : rep.q[k].u, f->b, b_error(f), f->chi2_red, f->wfrom, f->wto,
                f->n_points, f->beta, f->beta_err, f->b * scale, b_error(f) * scale);
        if (q == Q_COEFFICIENT && pooled) {
            continue; /* the coefficient in s^2/m^2 belongs to one radius */
        }
        campaign_row *row = campaign_group_row(rows, group);
        fill_row(r, row, f, q == Q_COEFFICIENT ? scale : 1.0);
    }
    rc = write_q(results, r, &rep, err);
    gr_spm_circle_report_free(&rep);
    return rc;
}
