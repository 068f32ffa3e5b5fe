/* The table of a comparison (include/granule/compare.h): the headline a physicist reads first,
 * built from each model's summary.json, with units, "value +- error" cells and the reason where
 * there is no number; and the full table of every scalar as compare.csv / compare.json. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/compare.h"
#include "io/files.h"
#include "io/summary_read.h"

static const cJSON *member(const cJSON *j, const char *path)
{
    char buf[160];
    snprintf(buf, sizeof buf, "%s", path);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ".", &save); tok && j; tok = strtok_r(NULL, ".", &save)) {
        j = cJSON_GetObjectItemCaseSensitive(j, tok);
    }
    return j;
}

static const char *string_at(const cJSON *j, const char *path, const char *fallback)
{
    const cJSON *m = member(j, path);
    return cJSON_IsString(m) ? m->valuestring : fallback;
}

static gr_compare_row *add_row(gr_compare_table *t, const char *quantity, const char *key,
                               const char *unit)
{
    gr_compare_row *r = &t->row[t->n_rows++];
    snprintf(r->quantity, sizeof r->quantity, "%s", quantity);
    snprintf(r->key, sizeof r->key, "%s", key);
    snprintf(r->unit, sizeof r->unit, "%s", unit);
    for (int k = 0; k < GR_COMPARE_MAX; k++) {
        r->cell[k].value = r->cell[k].error = NAN;
    }
    return r;
}

static void set_number(gr_compare_cell *c, double value, double error, const char *suffix)
{
    c->value = value;
    c->error = error;
    char num[80];
    gr_compare_format(value, error, num, sizeof num);
    snprintf(c->text, sizeof c->text, "%.70s%.40s", num, suffix ? suffix : "");
}

static void set_reason(gr_compare_cell *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static void set_reason(gr_compare_cell *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->text, sizeof c->text, fmt, ap);
    va_end(ap);
}

const char *gr_compare_mark_words(char mark)
{
    return mark == '*' ? "error bar not converged (a lower bound): run longer"
                       : "free fit of (5.5): no alpha has chi2/dof < 1.2 in the Table 5.1 window";
}

static void footnote(gr_compare_table *t, const char *line)
{
    if (!strstr(t->footnotes, line)) {
        size_t len = strlen(t->footnotes);
        snprintf(t->footnotes + len, sizeof t->footnotes - len, "%s\n", line);
    }
}

/* P(v) tail exponent of (5.5): the thesis's accepted range (chi2/dof < 1.2 in the Table 5.1
 * window), else the free fit marked with a footnote, else why there is none. */
static void tail_cell(gr_compare_table *t, gr_compare_cell *c, const cJSON *s)
{
    const cJSON *pv = member(s, "analysis.pv"), *tail = member(pv, "tail");
    if (!pv) {
        set_reason(c, "n/a: pv not enabled");
    } else if (!tail) {
        set_reason(c, "no samples");
    } else if (cJSON_IsTrue(member(tail, "accepted"))) {
        set_number(c, gr_summary_number(tail, "alpha"), gr_summary_number(tail, "alpha_halfwidth"),
                   NULL);
    } else if (cJSON_IsTrue(member(tail, "free.converged"))) {
        set_number(c, gr_summary_number(tail, "free.alpha"),
                   gr_summary_number(tail, "free.alpha_err"), " #");
        footnote(t, "#: free fit of (5.5); no alpha has chi2/dof < 1.2 in the Table 5.1 window");
    } else {
        set_reason(c, "fit failed: %.0f points in the window", gr_summary_number(tail, "n_points"));
    }
}

static void df_cell(gr_compare_cell *c, const cJSON *s, int dim)
{
    const cJSON *sk = member(s, "analysis.sk");
    if (dim == 1) { /* S(k) is computed in 2D and 3D */
        set_reason(c, "n/a: 1D");
    } else if (!sk) {
        set_reason(c, "n/a: sk not enabled");
    } else if (isfinite(gr_summary_number(sk, "fit.D_f"))) {
        set_number(c, gr_summary_number(sk, "fit.D_f"), gr_summary_number(sk, "fit.D_f_err"), NULL);
    } else {
        set_reason(c, "fit failed: %.80s", string_at(sk, "fit.status", "no fit"));
    }
}

static void g1_cell(gr_compare_cell *c, const cJSON *s, int dim)
{
    const cJSON *gaps = member(s, "analysis.gaps");
    if (dim >= 2) { /* G_h is 1D */
        set_reason(c, dim == 2 ? "n/a: 2D" : "n/a: 3D");
    } else if (!gaps) {
        set_reason(c, "n/a: gaps not enabled");
    } else if (isfinite(gr_summary_number(gaps, "fit_3_22.n_N"))) {
        set_number(c, gr_summary_number(gaps, "fit_3_22.n_N"),
                   gr_summary_number(gaps, "fit_3_22.n_N_stderr"), NULL);
    } else {
        set_reason(c, "fit failed: %.80s", string_at(gaps, "fit_3_22.note", "no fit"));
    }
}

/* The energy put in: the driving's (noise, bath) and the moving walls' work (a vibrated bed's
 * only source; ledger.wall_work is absent without walls). */
static double energy_in(const cJSON *s)
{
    const double w = gr_summary_number(s, "ledger.wall_work");
    return gr_summary_number(s, "ledger.injected") + (isfinite(w) ? w : 0.0);
}

/* Energy dissipated by one mechanism, with its share of the energy put in; the reason when the
 * model has no such mechanism or nothing collided. */
static void dissipated_cell(gr_compare_cell *c, const cJSON *s, const char *path,
                            const char *absent)
{
    const double v = gr_summary_number(s, path), injected = energy_in(s);
    if (absent) {
        set_reason(c, "%s", absent);
    } else if (gr_summary_number(s, "collisions") == 0.0) {
        set_reason(c, "no collisions");
    } else if (injected > 0.0) {
        char suffix[40];
        snprintf(suffix, sizeof suffix, " (%.0f%%)", 100.0 * v / injected);
        set_number(c, v, NAN, suffix);
    } else {
        set_number(c, v, NAN, NULL);
    }
}

static void throughput_cells(gr_compare_row *tp, gr_compare_row *cps, int k, const cJSON *s)
{
    const double wall = gr_summary_number(s, "wall_seconds"),
                 coll = gr_summary_number(s, "collisions");
    const bool event = !strcmp(string_at(s, "scene.integrator.kind", ""), "event");
    const double rate = event ? gr_summary_number(s, "events_per_second")
                              : gr_summary_number(s, "particle_steps_per_second");
    tp->cell[k].value = rate;
    snprintf(tp->cell[k].text, sizeof tp->cell[k].text, "%.3g %s", rate,
             event ? "events/s" : "particle-steps/s");
    if (!(wall > 0.0)) {
        set_reason(&cps->cell[k], "n/a: no wall time");
    } else if (coll == 0.0) {
        set_reason(&cps->cell[k], "no collisions");
    } else {
        cps->cell[k].value = coll / wall;
        snprintf(cps->cell[k].text, sizeof cps->cell[k].text, "%.3g", coll / wall);
    }
}

/* Every row of one model k whose run left no summary says so. */
static void failed_column(gr_compare_table *t, int k)
{
    snprintf(t->status[k], sizeof t->status[k], "failed");
    snprintf(t->integrator[k], sizeof t->integrator[k], "?");
    snprintf(t->kernel[k], sizeof t->kernel[k], "failed");
    for (int i = 0; i < t->n_rows; i++) {
        set_reason(&t->row[i].cell[k], "run failed: no summary.json");
    }
}

static void fill_column(gr_compare_table *t, int k, const cJSON *s)
{
    snprintf(t->status[k], sizeof t->status[k], "%s", string_at(s, "status", "?"));
    snprintf(t->integrator[k], sizeof t->integrator[k], "%s",
             string_at(s, "scene.integrator.kind", "?"));
    snprintf(t->kernel[k], sizeof t->kernel[k], "%s", string_at(s, "kernel", "?"));
    const int sdim = (int)gr_summary_number(s, "scene.system.dim");
    const int dim = sdim >= 1 && sdim <= 3 ? sdim : t->dim;
    gr_compare_row *r = t->row;
    int i = 0;
    if (isfinite(gr_summary_number(s, "T_mean"))) {
        const bool converged = gr_summary_number(s, "T_stderr_converged") != 0.0;
        set_number(&r[i].cell[k], gr_summary_number(s, "T_mean"), gr_summary_number(s, "T_stderr"),
                   converged ? NULL : " *");
        if (!converged) {
            footnote(t, "*: the error bar of T is not converged (a lower bound): run longer");
        }
    } else {
        set_reason(&r[i].cell[k], "no samples");
    }
    /* rotating discs: the spin's temperature I <w^2> / M (one degree of freedom), the last sample (T_rot_final) */
    const double T_rot = gr_summary_number(s, "T_rot_final");
    if (isfinite(T_rot)) {
        set_number(&r[++i].cell[k], T_rot, NAN, NULL);
    } else {
        set_reason(&r[++i].cell[k], "n/a: no rotation");
    }
    tail_cell(t, &r[++i].cell[k], s);
    df_cell(&r[++i].cell[k], s, dim);
    g1_cell(&r[++i].cell[k], s, dim);
    const double coll = gr_summary_number(s, "collisions"),
                 n = gr_summary_number(s, "scene.system.N"),
                 simulated = gr_summary_number(s, "simulated_seconds");
    set_number(&r[++i].cell[k], coll, NAN, NULL);
    snprintf(r[i].cell[k].text, sizeof r[i].cell[k].text, "%.0f", coll);
    if (coll > 0.0 && n > 0.0 && simulated > 0.0) {
        r[++i].cell[k].value = coll / (n * simulated);
        snprintf(r[i].cell[k].text, sizeof r[i].cell[k].text, "%.4g", coll / (n * simulated));
    } else {
        set_reason(&r[++i].cell[k], coll == 0.0 ? "no collisions" : "n/a: no simulated time");
    }
    set_number(&r[++i].cell[k], gr_summary_number(s, "ledger.injected"), NAN, NULL);
    const char *tangential = string_at(s, "scene.model.tangential", "none");
    const bool event = !strcmp(t->integrator[k], "event");
    dissipated_cell(&r[++i].cell[k], s, "ledger.dissipated_normal", NULL);
    dissipated_cell(&r[++i].cell[k], s, "ledger.dissipated_tangential",
                    dim == 1 ? "n/a: 1D"
                    : !event && strcmp(tangential, "tangential_dashpot")
                        ? "n/a: no tangential dashpot"
                        : NULL);
    dissipated_cell(&r[++i].cell[k], s, "ledger.dissipated_friction",
                    dim == 1                                 ? "n/a: 1D"
                    : strcmp(tangential, "sliding_friction") ? "n/a: no sliding friction"
                                                             : NULL);
    const double residual = gr_summary_number(s, "ledger.relative_residual");
    r[++i].cell[k].value = residual;
    snprintf(r[i].cell[k].text, sizeof r[i].cell[k].text, "%.2g", residual);
    set_number(&r[++i].cell[k], gr_summary_number(s, "wall_seconds"), NAN, NULL);
    throughput_cells(&r[i + 1], &r[i + 2], k, s);
}

/* The system's own numbers (issue 36), as rows after the common ones, present when the compared
 * scene has them: a freely cooling gas's Haff time (mean_field.t0_fit beside the Enskog t0_haff;
 * not with walls or gravity),
 * a Langevin gas's T over the bath's, a bed's centre-of-mass height and densest slab (the profile
 * observable). Which rows: from the first model that left a summary (all share the scene). */
enum { SYS_HAFF = 1, SYS_BATH = 2, SYS_PROFILE = 4, SYS_WALLS = 8, SYS_SPECIES = 16 };

static int system_rows(gr_compare_table *t)
{
    const cJSON *s = NULL;
    for (int k = 0; k < t->n_models && !s; k++) {
        s = t->summaries[k];
    }
    int sys = 0;
    /* Haff's law is the homogeneous gas's: not under gravity or between walls */
    const bool open = !member(s, "scene.gravity") && !member(s, "scene.boundary");
    sys |= member(s, "mean_field.t0_fit") && open ? SYS_HAFF : 0;
    sys |= member(s, "mean_field.T_bath") ? SYS_BATH : 0;
    sys |= member(s, "analysis.profile") ? SYS_PROFILE : 0;
    sys |= member(s, "ledger.wall_work") ? SYS_WALLS : 0;
    sys |= member(s, "analysis.species.T1_over_T2") ? SYS_SPECIES : 0;
    if (sys & SYS_HAFF) {
        add_row(t, "Haff time t0, fitted (s)", "haff_t0", "s");
        add_row(t, "t0 fitted / Enskog t0 (docs/validation.md)", "haff_t0_ratio", "1");
    }
    if (sys & SYS_BATH) {
        add_row(t, "T / T_bath (Langevin bath)", "T_over_bath", "1");
        add_row(t, "dissipated by the bath's drag (J, %)", "dissipated_drag", "J");
    }
    if (sys & SYS_WALLS) {
        add_row(t, "work done by the walls (J)", "wall_work", "J");
    }
    if (sys & SYS_PROFILE) {
        add_row(t, "centre-of-mass position along the profile axis (m)", "profile_height", "m");
        add_row(t, "densest slab's packing fraction", "profile_max_phi", "1");
    }
    if (sys & SYS_SPECIES) { /* a binary mixture (docs/mixtures.md) */
        add_row(t, "T_1 / T_2 of the two species", "species_ratio", "1");
        add_row(t, "T_1 / T_2, Enskog-Maxwellian (docs/validation.md)", "species_ratio_theory",
                "1");
    }
    return sys;
}

static gr_compare_cell *cell_of(gr_compare_table *t, const char *key, int k)
{
    for (int i = 0; i < t->n_rows; i++) {
        if (!strcmp(t->row[i].key, key)) {
            return &t->row[i].cell[k];
        }
    }
    return NULL; /* not reached: system_rows added it */
}

static void fill_system(gr_compare_table *t, int k, const cJSON *s, int sys)
{
    if (sys & SYS_HAFF) {
        const double t0 = gr_summary_number(s, "mean_field.t0_fit"),
                     e = gr_summary_number(s, "mean_field.t0_fit_stderr"),
                     ref = gr_summary_number(s, "mean_field.t0_haff");
        if (isfinite(t0)) {
            set_number(cell_of(t, "haff_t0", k), t0, e, NULL);
        } else {
            set_reason(cell_of(t, "haff_t0", k), "no fit");
        }
        if (isfinite(t0) && ref > 0.0) {
            set_number(cell_of(t, "haff_t0_ratio", k), t0 / ref, e / ref, NULL);
        } else {
            set_reason(cell_of(t, "haff_t0_ratio", k), "n/a: no Enskog t0 (2D hard discs only)");
        }
    }
    if (sys & SYS_BATH) {
        const double bath = gr_summary_number(s, "mean_field.T_bath");
        if (bath > 0.0 && isfinite(gr_summary_number(s, "T_mean"))) {
            set_number(cell_of(t, "T_over_bath", k), gr_summary_number(s, "T_mean") / bath,
                       gr_summary_number(s, "T_stderr") / bath, NULL);
        } else {
            set_reason(cell_of(t, "T_over_bath", k), bath > 0.0 ? "no samples" : "n/a: T_bath = 0");
        }
        dissipated_cell(cell_of(t, "dissipated_drag", k), s, "ledger.dissipated_drag", NULL);
    }
    if (sys & SYS_WALLS) {
        set_number(cell_of(t, "wall_work", k), gr_summary_number(s, "ledger.wall_work"), NAN, NULL);
    }
    if (sys & SYS_PROFILE) {
        const cJSON *p = member(s, "analysis.profile");
        if (p && isfinite(gr_summary_number(p, "mean_position"))) {
            set_number(cell_of(t, "profile_height", k), gr_summary_number(p, "mean_position"),
                       gr_summary_number(p, "mean_position_error"), NULL);
            set_number(cell_of(t, "profile_max_phi", k),
                       gr_summary_number(p, "max_packing_fraction"), NAN, NULL);
        } else {
            set_reason(cell_of(t, "profile_height", k),
                       p ? "no samples" : "n/a: profile not enabled");
            set_reason(cell_of(t, "profile_max_phi", k),
                       p ? "no samples" : "n/a: profile not enabled");
        }
    }
    if (sys & SYS_SPECIES) {
        const double r = gr_summary_number(s, "analysis.species.T1_over_T2"),
                     th = gr_summary_number(s, "mean_field.T1_over_T2_predicted");
        if (isfinite(r)) {
            set_number(cell_of(t, "species_ratio", k), r,
                       gr_summary_number(s, "analysis.species.T1_over_T2_stderr"), NULL);
        } else {
            set_reason(cell_of(t, "species_ratio", k), "n/a: species not enabled");
        }
        if (isfinite(th)) {
            set_number(cell_of(t, "species_ratio_theory", k), th, NAN, NULL);
        } else {
            set_reason(cell_of(t, "species_ratio_theory", k), "n/a: 2D, driven, eps_n < 1 only");
        }
    }
}

gr_compare_table *gr_compare_table_build(const char *out, const char *scene_path, int dim,
                                         const gr_compare_spec *specs, int n)
{
    gr_compare_table *t = calloc(1, sizeof *t);
    if (!t) {
        return NULL;
    }
    snprintf(t->scene, sizeof t->scene, "%s", scene_path);
    t->dim = dim;
    t->n_models = n > GR_COMPARE_MAX ? GR_COMPARE_MAX : n;
    /* the order a physicist reads them: state, structure, collisions, energy, cost */
    add_row(t, "T (m^2/s^2)", "T", "m2 s-2");
    add_row(t, "rotational T at the end (m^2/s^2)", "T_rot", "m2 s-2");
    add_row(t, "P(v) tail exponent alpha (5.5)", "tail_alpha", "1");
    add_row(t, "fractal dimension D_f of S(k) (4.4)", "D_f", "1");
    add_row(t, "G_1 tail exponent n_N (3.22)", "n_N", "1");
    add_row(t, "collisions", "collisions", "1");
    add_row(t, "collisions per particle per s (1/s)", "collision_rate", "s-1");
    add_row(t, "energy injected by noise (J)", "injected", "J");
    add_row(t, "dissipated, normal (J, % of energy in)", "dissipated_normal", "J");
    add_row(t, "dissipated, tangential (J, %)", "dissipated_tangential", "J");
    add_row(t, "dissipated, friction (J, %)", "dissipated_friction", "J");
    add_row(t, "energy ledger residual (relative)", "ledger_residual", "1");
    add_row(t, "wall time (s)", "wall_seconds", "s");
    add_row(t, "throughput", "throughput", "s-1");
    add_row(t, "collisions per wall-clock s (1/s)", "collisions_per_wall_second", "s-1");
    footnote(t, GR_COMPARE_ERRORS);
    for (int k = 0; k < t->n_models; k++) {
        t->spec[k] = specs[k];
        char dir[1200];
        snprintf(dir, sizeof dir, "%s/%s", out, specs[k].label);
        gr_error err = {0};
        t->summaries[k] = gr_summary_read(dir, &err);
    }
    const int sys = system_rows(t);
    for (int k = 0; k < t->n_models; k++) {
        if (t->summaries[k]) {
            fill_column(t, k, t->summaries[k]);
            fill_system(t, k, t->summaries[k], sys);
        } else {
            failed_column(t, k);
        }
    }
    return t;
}

void gr_compare_table_free(gr_compare_table *t)
{
    if (!t) {
        return;
    }
    for (int k = 0; k < t->n_models; k++) {
        cJSON_Delete(t->summaries[k]);
    }
    free(t);
}
