/* summary.json and the plots of granule fokker-planck (gr_fp_study_summary); see
 * docs/theory-fokker-planck.md. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "analysis/obs_util.h"
#include "granule/fokker_planck_study.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/plot.h"
#include "io/summary_read.h"

static double z_score(double x, double err, double expect)
{
    return err > 0.0 ? (x - expect) / err : (double)NAN;
}

static void plot(const char *dir, cJSON *plots, cJSON *notes, const char *png, const char *body)
{
    char note[300];
    if (gr_plot_script(dir, png, body, note, sizeof note) == 0) {
        cJSON_AddItemToArray(plots, cJSON_CreateString(png));
    } else {
        cJSON_AddItemToArray(notes, cJSON_CreateString(note));
    }
}

static cJSON *fit_json(const gr_fit *f, double V, double a, double b)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "from_over_V", a / V);
    cJSON_AddNumberToObject(j, "to_over_V", b / V);
    gr_obs_add_number(j, "A", f->p[0]);
    gr_obs_add_number(j, "v0_over_V", f->p[1] / V);
    gr_obs_add_number(j, "v0_over_V_err", f->err[1] / V);
    gr_obs_add_number(j, "beta", f->p[2]);
    gr_obs_add_number(j, "beta_err", f->err[2]);
    gr_obs_add_number(j, "chi2_red", f->chi2_red);
    return j;
}

/* the simulation, the exact identities and the comparison */
static void json_simulation(cJSON *j, const gr_fp_study_params *p, const gr_fp_study *st)
{
    const double V = st->V;
    const double Gamma = p->s.D / (p->s.M * p->s.M);
    cJSON *sj = cJSON_AddObjectToObject(j, "simulation");
    cJSON_AddNumberToObject(sj, "walkers", (double)st->r.walkers);
    cJSON_AddNumberToObject(sj, "right_exits", (double)st->r.right_exits);
    cJSON_AddNumberToObject(sj, "left_exits", (double)st->r.left_exits);
    cJSON_AddNumberToObject(sj, "truncated", (double)st->r.truncated);
    cJSON_AddNumberToObject(sj, "steps", (double)st->r.steps);
    cJSON_AddNumberToObject(sj, "tau", st->r.tau);
    gr_obs_add_number(sj, "mean_exit_time", st->r.mean_exit_time);
    gr_obs_add_number(sj, "mean_exit_time_err", st->r.mean_exit_time_err);
    gr_obs_add_number(sj, "v_mean", st->r.v_moment[1]);
    gr_obs_add_number(sj, "v_mean_err", st->r.v_moment_err[1]);
    gr_obs_add_number(sj, "v2_mean", st->r.v_moment[2]);
    gr_obs_add_number(sj, "v2_mean_err", st->r.v_moment_err[2]);
    gr_obs_add_number(sj, "v3_mean", st->r.v_moment[3]);
    gr_obs_add_number(sj, "v3_mean_err", st->r.v_moment_err[3]);
    gr_obs_add_number(sj, "v4_mean", st->r.v_moment[4]);
    gr_obs_add_number(sj, "v4_mean_err", st->r.v_moment_err[4]);
    gr_obs_add_number(sj, "abs_v_mean", st->r.abs_v_mean);
    gr_obs_add_number(sj, "abs_v_mean_err", st->r.abs_v_mean_err);
    gr_obs_add_number(sj, "exit_speed_mean", st->r.exit_speed_mean);
    gr_obs_add_number(sj, "exit_speed_err", st->r.exit_speed_err);
    gr_obs_add_number(sj, "exit_speed2_mean", st->r.exit_speed2_mean);
    gr_obs_add_number(sj, "exit_speed2_err", st->r.exit_speed2_err);
    gr_obs_add_number(sj, "Q_pdf_at_0_fit", st->q0fit);
    gr_obs_add_number(sj, "Q_pdf_at_0_fit_err", st->q0fit_err);
    cJSON_AddNumberToObject(sj, "seconds", st->r.wall_seconds);
    cJSON_AddNumberToObject(sj, "cpu_seconds", st->r.cpu_seconds);
    cJSON_AddNumberToObject(sj, "steps_per_cpu_second",
                            st->r.cpu_seconds > 0.0 ? (double)st->r.steps / st->r.cpu_seconds
                                                    : 0.0);
    /* exact identities of the process, any symmetric start (docs): Q(0) = <|v_exit|>/(2 Gamma <T>),
         * <v^2> = Gamma L Q(0) */
    cJSON *id = cJSON_AddObjectToObject(j, "identities");
    double q0_id = st->r.exit_speed_mean / (2.0 * Gamma * st->r.mean_exit_time);
    double q0_id_err = q0_id * hypot(st->r.exit_speed_err / st->r.exit_speed_mean,
                                     st->r.mean_exit_time_err / st->r.mean_exit_time);
    gr_obs_add_number(id, "Q_pdf_at_0_from_exits", q0_id);
    gr_obs_add_number(id, "Q_pdf_at_0_from_exits_err", q0_id_err);
    gr_obs_add_number(id, "Q_pdf_at_0_fit", st->q0fit);
    gr_obs_add_number(id, "z_Q0_fit_vs_exits",
                      z_score(st->q0fit, hypot(st->q0fit_err, q0_id_err), q0_id));
    gr_obs_add_number(id, "v2_over_Gamma_L", st->r.v_moment[2] / (Gamma * p->s.L));
    gr_obs_add_number(id, "z_v2_over_Gamma_L_vs_Q0_fit",
                      z_score(st->r.v_moment[2] / (Gamma * p->s.L),
                              hypot(st->r.v_moment_err[2] / (Gamma * p->s.L), st->q0fit_err),
                              st->q0fit));
    cJSON *cj = cJSON_AddObjectToObject(j, "comparison");
    if (st->uniform) {
        cJSON_AddStringToObject(
            cj, "note", "simulation of the uniform start against the quadrature of the same model");
        gr_obs_add_number(cj, "z_mean_exit_time",
                          z_score(st->r.mean_exit_time, st->r.mean_exit_time_err, st->T_quad));
        gr_obs_add_number(cj, "z_v2_mean",
                          z_score(st->r.v_moment[2], st->r.v_moment_err[2], st->v2));
        gr_obs_add_number(cj, "z_abs_v_mean",
                          z_score(st->r.abs_v_mean, st->r.abs_v_mean_err, st->vabs));
        gr_obs_add_number(cj, "z_v4_mean",
                          z_score(st->r.v_moment[4], st->r.v_moment_err[4], st->v4));
        gr_obs_add_number(cj, "z_exit_speed_mean",
                          z_score(st->r.exit_speed_mean, st->r.exit_speed_err, st->e1));
        gr_obs_add_number(cj, "z_exit_speed2_mean",
                          z_score(st->r.exit_speed2_mean, st->r.exit_speed2_err, st->e2));
        gr_obs_add_number(cj, "z_Q_pdf_at_0", z_score(st->q0fit, st->q0fit_err, st->Q0));
    } else {
        cJSON_AddStringToObject(
            cj, "note",
            "centre start: (B.32)-(B.34) describe the uniform start, so the chi-squares below "
            "measure the difference between the two models, not an error");
    }
    gr_obs_add_number(cj, "z_v_mean_zero", z_score(st->r.v_moment[1], st->r.v_moment_err[1], 0.0));
    gr_obs_add_number(cj, "z_v3_mean_zero", z_score(st->r.v_moment[3], st->r.v_moment_err[3], 0.0));
    double nexit = (double)(st->r.right_exits + st->r.left_exits);
    gr_obs_add_number(cj, "z_right_left",
                      nexit > 0 ? ((double)st->r.right_exits - 0.5 * nexit) / (0.5 * sqrt(nexit))
                                : (double)NAN);
    cJSON *cqj = cJSON_AddObjectToObject(cj, "Q");
    gr_obs_add_number(cqj, "chi2", st->cq.chi2);
    cJSON_AddNumberToObject(cqj, "bins", st->cq.dof);
    gr_obs_add_number(cqj, "dof_eff", st->cq.dof_eff);
    gr_obs_add_number(cqj, "p_value", st->cq.p_value);
    gr_obs_add_number(cqj, "max_abs_pull", st->cq.max_abs_z);
    gr_obs_add_number(cqj, "chi2_full_covariance", st->cq.chi2_full);
    gr_obs_add_number(cqj, "p_full_covariance", st->cq.p_full);
    cJSON *cej = cJSON_AddObjectToObject(cj, "exit");
    gr_obs_add_number(cej, "chi2", st->ce.chi2);
    cJSON_AddNumberToObject(cej, "bins", st->ce.dof);
    gr_obs_add_number(cej, "p_value", st->ce.p_value);
    gr_obs_add_number(cej, "max_abs_pull", st->ce.max_abs_z);
    if (st->have_tail_fit) {
        cJSON_AddItemToObject(cj, "tail_fit_simulation",
                              fit_json(&st->sim_tail, V, 1.5 * V, fmin(3.5, p->s.vmax_V) * V));
        cJSON_AddItemToObject(
            cj, "tail_fit_quadrature",
            fit_json(&st->quad_tail_on_bins, V, 1.5 * V, fmin(3.5, p->s.vmax_V) * V));
    }
    cJSON_AddNumberToObject(cj, "seconds", st->compare_seconds);
}

int gr_fp_study_summary(const char *dir, const gr_fp_study_params *p, gr_fp_study *st, bool on,
                        gr_error *err)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "completed");
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON *sj0 = cJSON_AddObjectToObject(j, "settings");
    cJSON_AddNumberToObject(sj0, "L", p->s.L);
    cJSON_AddNumberToObject(sj0, "D", p->s.D);
    cJSON_AddNumberToObject(sj0, "M", p->s.M);
    cJSON_AddStringToObject(sj0, "start", st->uniform ? "uniform" : "centre");
    cJSON_AddNumberToObject(sj0, "walkers", p->sim ? (double)p->s.walkers : 0.0);
    cJSON_AddNumberToObject(sj0, "seed", (double)p->s.seed);
    cJSON_AddStringToObject(sj0, "rng", "gsl_rng_mt19937");
    cJSON_AddNumberToObject(sj0, "steps_per_T0", p->s.steps_per_T0);
    cJSON_AddNumberToObject(sj0, "refine", p->s.refine);
    cJSON_AddNumberToObject(sj0, "bins", p->s.bins);
    cJSON_AddNumberToObject(sj0, "exit_bins", p->s.exit_bins);
    cJSON_AddNumberToObject(sj0, "vmax_over_V", p->s.vmax_V);
    cJSON_AddNumberToObject(sj0, "epsrel", p->s.epsrel);
    cJSON_AddBoolToObject(sj0, "inner_quadrature", p->s.inner_quadrature);
    cJSON_AddNumberToObject(sj0, "min_walks", p->min_walks);
    cJSON *sc = cJSON_AddObjectToObject(j, "scales");
    cJSON_AddNumberToObject(sc, "Gamma", p->s.D / (p->s.M * p->s.M));
    cJSON_AddNumberToObject(sc, "V", st->V);
    cJSON_AddNumberToObject(sc, "T0", st->T0);
    cJSON *qj = cJSON_AddObjectToObject(j, "quadrature");
    cJSON_AddStringToObject(qj, "applies_to", "uniform start (B.1 with R delta(v), App. B)");
    gr_obs_add_number(qj, "mean_exit_time", st->T_quad);
    gr_obs_add_number(qj, "mean_exit_time_over_T0", st->T_quad / st->T0);
    gr_obs_add_number(qj, "v2_mean", st->v2);
    gr_obs_add_number(qj, "abs_v_mean", st->vabs);
    gr_obs_add_number(qj, "v4_mean", st->v4);
    gr_obs_add_number(qj, "Q_pdf_at_0", st->Q0);
    gr_obs_add_number(qj, "exit_speed_mean", st->e1);
    gr_obs_add_number(qj, "exit_speed2_mean", st->e2);
    gr_obs_add_number(qj, "P_L_over_RL_at_half_V", st->PL_half);
    cJSON_AddNumberToObject(qj, "thesis_prefactor_ratio", gr_fp_thesis_prefactor_ratio());
    cJSON_AddNumberToObject(qj, "kappa", gr_fp_kappa());
    cJSON_AddNumberToObject(qj, "seconds", st->quad_seconds);
    cJSON *tf = cJSON_AddArrayToObject(qj, "tail_fits");
    for (int k = 0; k < 3; k++) {
        if (st->quad_tail_ok[k]) {
            cJSON_AddItemToArray(tf, fit_json(&st->quad_tail[k], st->V,
                                              gr_fp_study_tail_ranges[k][0] * st->V,
                                              gr_fp_study_tail_ranges[k][1] * st->V));
        }
    }
    cJSON *plots = cJSON_AddArrayToObject(j, "plots");
    cJSON *notes = cJSON_CreateArray();
    for (int k = 0; k < st->n_notes; k++) {
        cJSON_AddItemToArray(notes, cJSON_CreateString(st->notes[k]));
    }
    if (st->have_sim) {
        json_simulation(j, p, st);
    }
    if (on) {
        char body[4096];
        const char *simlabel =
            st->uniform ? "simulation (uniform start)" : "simulation (centre start)";
        const char *qlabel =
            st->uniform ? "quadrature B.34" : "quadrature B.34 (uniform start, reference)";
        char simpart[512] = "";
        if (p->sim) {
            snprintf(simpart, sizeof simpart,
                     ", 'q.csv' skip 1 using 3:6:7 with yerrorbars pt 7 ps 0.6 lc rgb '#1f5fbf' "
                     "title '%s (walk-scatter errors)'",
                     simlabel);
        }
        snprintf(
            body, sizeof body,
            "set title 'Q(v, L): velocity sampled uniformly in time until the first exit (Fig. "
            "B.2)'\n"
            "set xlabel 'v (m/s)'\nset ylabel 'Q(v, L) (s/m, normalised)'\nset key top right\n"
            "plot 'q_curve.csv' skip 1 using 1:3 with lines lw 2 lc rgb '#cc3333' title '%s'%s\n",
            qlabel, simpart);
        plot(dir, plots, notes, "q.png", body);
        snprintf(
            body, sizeof body,
            "set title 'Q(v, L), logarithmic (tail: exp(-|v|^3 M^2/(9 D L)) times a power of v)'\n"
            "set xlabel 'v (m/s)'\nset ylabel 'Q(v, L) (s/m, normalised)'\nset logscale y\nset key "
            "bottom center\n"
            "plot 'q_curve.csv' skip 1 using 1:($3 > 0 ? $3 : 1/0) with lines lw 2 lc rgb "
            "'#cc3333' title '%s'%s\n",
            qlabel,
            p->sim ? ", 'q.csv' skip 1 using 3:($6 > 0 ? $6 : 1/0):7 with yerrorbars pt 7 ps 0.5 "
                     "lc rgb '#1f5fbf' title 'simulation'"
                   : "");
        plot(dir, plots, notes, "q_log.png", body);
        snprintf(
            body, sizeof body,
            "set title 'Arrivals at x = L: P(L, v) / (R L) (Fig. B.1)'\n"
            "set xlabel 'v (m/s)'\nset ylabel 'P(L, v) / (R L)  (s^2/m^2)'\nset key top right\n"
            "plot 'exit_curve.csv' skip 1 using 1:3 with lines lw 2 lc rgb '#cc3333' title "
            "'%s'%s\n",
            st->uniform ? "quadrature B.32" : "quadrature B.32 (uniform start, reference)",
            p->sim ? ", 'exit.csv' skip 1 using 3:8:9 with yerrorbars pt 7 ps 0.6 lc rgb '#1f5fbf' "
                     "title 'simulation, both ends pooled (sqrt(X) errors)', "
                     "'' skip 1 using 3:($10 / (2 * $3)) with points pt 6 ps 1.1 lc rgb '#cc3333' "
                     "title 'quadrature, bin means treated alike'"
                   : "");
        plot(dir, plots, notes, "exit.png", body);
    }
    if (cJSON_GetArraySize(notes) > 0) {
        cJSON_AddItemToObject(j, "notes", notes);
    } else {
        cJSON_Delete(notes);
    }
    int rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}
