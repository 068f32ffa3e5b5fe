/* The output folder of granule cascade (gr_cascade_study_write); see docs/theory-cascade.md. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/cascade_study.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "analysis/obs_util.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/snapshot.h"
#include "io/summary_read.h"

typedef struct run_info {
    const gr_cascade_settings *s;
    const gr_cascade_variant_info *vi;
    const char *dir;
} run_info;

static void csv_header(gr_file *f, const run_info *ri, const char *what)
{
    const gr_cascade_settings *s = ri->s;
    gr_file_note(f, "# granule cascade (%s, %s): %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f,
                 "# variant %s (%s), levels %d (%d x %d squares), L = %.9g m, %d configurations, "
                 "seed %lu (gsl mt19937)\n",
                 ri->vi->name, ri->vi->label, s->levels, 1 << s->levels, 1 << s->levels, s->L,
                 s->configurations, s->seed);
}

static int write_sk(const run_info *ri, const gr_cascade_study *st, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "sk.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, ri, "structure factor S(k) of eq. 6.5, circular average (sec. 4.1)");
    gr_file_note(&f, "# q: bin q-1/2 <= |k| L/(2 pi) < q+1/2; k: mean |k| of its lattice vectors, "
                     "1/m; vectors: how many;\n"
                     "# S, S_err: configuration average and its standard error; S_expected: exact "
                     "average (second moments);\n"
                     "# in_fit: 1 for the bins of the D_f fit\n");
    gr_file_header(&f, "q [1],k [m-1],vectors [1],S [1],S_err [1],S_expected [1],in_fit [1]");
    for (int i = 0; i < st->nbins; i++) {
        const gr_cascade_sk_bin *b = &st->bins[i];
        fprintf(f.f, "%d,%.9g,%d,%.9g,%.6g,%.9g,%d\n", b->q, b->k, b->vectors, b->S, b->S_err,
                b->S_expected, b->q >= st->q_min && b->q <= st->q_max);
    }
    return gr_file_commit(&f, err);
}

static int write_levels(const run_info *ri, const gr_cascade_study *st, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "levels.csv", err);
    if (rc) {
        return rc;
    }
    const int C = ri->s->configurations;
    double mu[4], second[4][4];
    gr_cascade_moments(ri->s, mu, second);
    const double growth = mu[0] + mu[1] + mu[2] + mu[3];
    csv_header(&f, ri, "total probability sum m_{i,j}(l) at each level l over the configurations");
    gr_file_note(&f, "# expected: (sum_c E[w_c])^l; sd: standard deviation over configurations (0 "
                     "for a conserving variant)\n");
    gr_file_header(
        &f,
        "level [1],side [1],total_mean [1],total_sd [1],total_min [1],total_max [1],expected [1]");
    for (int l = 0; l <= ri->s->levels; l++) {
        fprintf(f.f, "%d,%d,%.17g,%.6g,%.17g,%.17g,%.17g\n", l, 1 << l, st->t_mean[l],
                C > 1 ? sqrt(st->t_m2[l] / (C - 1)) : 0.0, st->t_lo[l], st->t_hi[l],
                pow(growth, l));
    }
    return gr_file_commit(&f, err);
}

static int write_field(const run_info *ri, const gr_cascade_study *st, gr_error *err)
{
    const int l = st->field_level, n = 1 << l, block = 1 << (ri->s->levels - l);
    gr_file f;
    int rc = gr_file_open(&f, ri->dir, "field.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, ri, "the first configuration's field");
    gr_file_note(&f,
                 "# %d x %d squares (blocks of %d x %d finest squares summed); x, y: square centre "
                 "(6.1), m;\n"
                 "# density = 4^%d m, the probability relative to a uniform field\n",
                 n, n, block, block, l);
    gr_file_header(&f, "x [m],y [m],density [1]");
    const double h = ri->s->L / n;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            fprintf(f.f, "%.9g,%.9g,%.9g\n", (i + 0.5) * h, (j + 0.5) * h, st->coarse[j * n + i]);
        }
    }
    return gr_file_commit(&f, err);
}

/* the discs as a snapshot, and the system, so that `granule analyse DIR` can read them */
static int write_placement(const run_info *ri, const gr_cascade_study_params *p,
                           const gr_cascade_study *st, gr_error *err)
{
    char snapdir[1000];
    snprintf(snapdir, sizeof snapdir, "%s/snapshots", ri->dir);
    if (mkdir(snapdir, 0777) != 0 && access(snapdir, W_OK) != 0) {
        return GR_FAIL(err, GR_EIO, "cannot create %s", snapdir);
    }
    const int n = p->placement.n;
    double *pv = calloc((size_t)n, sizeof(double));
    if (!pv) {
        return GR_FAIL(err, GR_ENOMEM, "cascade: out of memory for %d discs", n);
    }
    gr_particles parts = {.n = n,
                          .dim = 2,
                          .L = ri->s->L,
                          .radius = p->placement.radius,
                          .mass = 3.53e-5,
                          .x = st->px,
                          .y = st->py,
                          .vx = pv,
                          .vy = pv};
    int rc = gr_snapshot_write(snapdir, 0, &parts, 0.0, 0, err);
    free(pv);
    if (rc) {
        return rc;
    }
    gr_scene scene;
    gr_scene_default(&scene);
    scene.dim = 2;
    scene.N = n;
    scene.L = ri->s->L;
    scene.radius = p->placement.radius;
    snprintf(scene.out_dir, sizeof scene.out_dir, "%s", ri->dir);
    snprintf(scene.source, sizeof scene.source,
             "granule cascade --variant %s --levels %d --seed %lu --place %d", ri->vi->name,
             ri->s->levels, ri->s->seed, n);
    return gr_scene_save(&scene, ri->dir, err);
}

static void add_plot(const char *dir, const char *png, const char *body, char *plots, size_t size)
{
    char note[300];
    size_t used = strlen(plots);
    snprintf(plots + used, size - used, "%s%s", used ? ", " : "",
             gr_plot_script(dir, png, body, note, sizeof note) ? note : png);
}

static void plots(const run_info *ri, const gr_cascade_study_params *p, const gr_cascade_study *st,
                  char *list, size_t size)
{
    const gr_cascade_settings *s = ri->s;
    const gr_cascade_variant_info *vi = ri->vi;
    char body[3000];
    const int skip_sk = 1; /* sk.csv: the column names (notes are in sk.meta.json) */
    char thesis[64] = "none";
    if (isfinite(vi->thesis_D_f)) {
        snprintf(thesis, sizeof thesis, "%.3f +- %.3f", vi->thesis_D_f, vi->thesis_D_f_err);
    }
    list[0] = 0;
    if (st->have_fit) {
        const gr_cascade_fit *h = gr_cascade_study_headline(st);
        int k = snprintf(
            body, sizeof body,
            "set logscale xy\nset format y '10^{%%L}'\nset key bottom left\n"
            "set xlabel 'k (1/m)'\nset ylabel 'S(k)'\n"
            "set title \"Multiplicative cascade %s, n = %d, %d configurations: D_f = %.3f +- %.3f "
            "(Table 6.2: %s)\"\n"
            "A = %.17g\nD = %.17g\n"
            "plot 'sk.csv' skip %d using 2:4:5 with yerrorbars pt 7 ps 0.5 lc rgb '#224466' title "
            "'S(k), eq. 6.5', "
            "'' skip %d using 2:6 with lines lc rgb '#cc6600' dt 2 title 'exact configuration "
            "average', "
            "[%.9g:%.9g] A * x**(-D) with lines lw 2 lc rgb '#cc2222' title '%s'",
            vi->label, s->levels, s->configurations, h->D_f, h->D_f_err, thesis, h->A, h->D_f,
            skip_sk, skip_sk, h->k_min, h->k_max,
            st->headline_unweighted ? "fit A k^{-D_f}, equal weights per shell" : "fit A k^{-D_f}");
        if (st->headline_unweighted) {
            k += snprintf(body + k, sizeof body - (size_t)k,
                          ", [%.9g:%.9g] %.17g * x**(-%.17g) with lines lw 1 dt 3 lc rgb '#555555' "
                          "title 'weighted by S_{err}: D_f = %.3f (chi^2/dof %.3g)'",
                          st->fit.k_min, st->fit.k_max, st->fit.A, st->fit.D_f, st->fit.D_f,
                          st->fit.chi2_red);
        }
        snprintf(body + k, sizeof body - (size_t)k, "\n");
    } else {
        snprintf(body, sizeof body,
                 "set logscale x\nset xlabel 'k (1/m)'\nset ylabel 'S(k)'\n"
                 "set title \"Multiplicative cascade %s, n = %d, %d configurations (%s)\"\n"
                 "plot 'sk.csv' skip %d using 2:4 with points pt 7 ps 0.5 title 'S(k), eq. 6.5'\n",
                 vi->label, s->levels, s->configurations, st->fit_note, skip_sk);
    }
    add_plot(ri->dir, "sk.png", body, list, size);
    snprintf(body, sizeof body,
             "set size ratio -1\nset xrange [0:%.9g]\nset yrange [0:%.9g]\nset xlabel 'x (m)'\nset "
             "ylabel 'y (m)'\n"
             "set palette defined (0 'white', 1 '#99aabb', 2 '#224466', 3 'black')\nset cblabel "
             "'log_{10}(4^{%d} m_{i,j})'\nset cbrange [-4:4]\n"
             "set title \"Cascade field %s, configuration 1 (%d x %d)\"\n"
             "plot 'field.csv' skip 1 using 1:2:($3 > 0 ? log10($3) : 1/0) with image notitle\n",
             s->L, s->L, st->field_level, vi->label, 1 << st->field_level, 1 << st->field_level);
    add_plot(ri->dir, "field.png", body, list, size);
    if (p->place) {
        snprintf(
            body, sizeof body,
            "set datafile separator whitespace\nset size ratio -1\nset xrange [0:%.9g]\nset yrange "
            "[0:%.9g]\n"
            "set xlabel 'x (m)'\nset ylabel 'y (m)'\nunset grid\n"
            "set title \"%d discs (r = %g m, phi = %.3f) placed from the %s field (Fig. 6.3)\"\n"
            "plot 'snapshots/snap_000000.xyz' skip 2 using 2:3:8 with circles fill solid 0.6 "
            "noborder "
            "lc rgb '#224466' notitle\n",
            s->L, s->L, p->placement.n, p->placement.radius, st->pres.phi, vi->label);
        add_plot(ri->dir, "placement.png", body, list, size);
    }
}

static void json_fit(cJSON *j, const gr_cascade_study *st)
{
    cJSON *fo = cJSON_AddObjectToObject(j, "fit");
    cJSON_AddStringToObject(
        fo, "model", "S(k) = A k^-D_f (eq. 4.4), chi-square line in ln k, ln S weighted by S_err");
    cJSON_AddNumberToObject(fo, "q_min", st->q_min);
    cJSON_AddNumberToObject(fo, "q_max", st->q_max);
    if (!st->have_fit) {
        cJSON_AddStringToObject(fo, "note", st->fit_note);
        return;
    }
    cJSON_AddNumberToObject(fo, "k_min", st->fit.k_min);
    cJSON_AddNumberToObject(fo, "k_max", st->fit.k_max);
    cJSON_AddNumberToObject(fo, "points", st->fit.points);
    cJSON_AddNumberToObject(fo, "A", st->fit.A);
    cJSON_AddNumberToObject(fo, "A_err", st->fit.A_err);
    gr_obs_add_number(fo, "chi2_red", st->fit.chi2_red);
    cJSON_AddNumberToObject(fo, "exact_average_D_f_err", st->fit_exp.D_f_err);
    if (st->have_unweighted) {
        cJSON *u = cJSON_AddObjectToObject(fo, "unweighted");
        cJSON_AddStringToObject(
            u, "model", "the same line with equal weights per k shell, errors from the scatter");
        gr_obs_add_number(u, "D_f", st->fit_unweighted.D_f);
        gr_obs_add_number(u, "D_f_err", st->fit_unweighted.D_f_err);
        gr_obs_add_number(u, "A", st->fit_unweighted.A);
        gr_obs_add_number(u, "residual_variance_ln_S", st->fit_unweighted.chi2_red);
    }
    const gr_cascade_fit *h = gr_cascade_study_headline(st);
    cJSON *hj = cJSON_AddObjectToObject(j, "headline");
    cJSON_AddStringToObject(hj, "fit", st->headline_unweighted ? "unweighted" : "weighted");
    gr_obs_add_number(hj, "D_f", h->D_f);
    gr_obs_add_number(hj, "D_f_err", h->D_f_err);
    cJSON_AddStringToObject(hj, "why", st->headline_why);
}

static cJSON *summary(const gr_cascade_study_params *p, const gr_cascade_study *st,
                      const char *plot_list)
{
    const gr_cascade_settings *s = &p->s;
    const gr_cascade_variant_info *vi = gr_cascade_variant_get(s->variant);
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "completed");
    cJSON_AddStringToObject(j, "command", "cascade");
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddStringToObject(j, "variant", vi->name);
    cJSON_AddStringToObject(j, "variant_label", vi->label);
    if (s->variant == GR_CASCADE_MEAKIN ||
        (s->variant >= GR_CASCADE_MEAKIN1 && s->variant <= GR_CASCADE_MEAKIN4)) {
        cJSON_AddItemToObject(
            j, "p", cJSON_CreateDoubleArray(s->variant == GR_CASCADE_MEAKIN ? s->p : vi->p, 4));
    }
    cJSON_AddNumberToObject(j, "levels", s->levels);
    cJSON_AddNumberToObject(j, "grid", 1 << s->levels);
    cJSON_AddNumberToObject(j, "L", s->L);
    cJSON_AddNumberToObject(j, "configurations", s->configurations);
    cJSON_AddNumberToObject(j, "seed", (double)s->seed);
    cJSON_AddStringToObject(j, "rng", "gsl_rng_mt19937");
    gr_obs_add_number(j, "D_f", st->have_fit ? st->fit.D_f : (double)NAN);
    gr_obs_add_number(j, "D_f_err", st->have_fit ? st->fit.D_f_err : (double)NAN);
    gr_obs_add_number(j, "D_f_exact_average", st->have_fit ? st->fit_exp.D_f : (double)NAN);
    gr_obs_add_number(j, "D_2", s->variant == GR_CASCADE_UNIFORM ? (double)NAN : gr_cascade_d2(s));
    gr_obs_add_number(j, "thesis_D_f", vi->thesis_D_f);
    gr_obs_add_number(j, "thesis_D_f_err", vi->thesis_D_f_err);
    json_fit(j, st);
    cJSON *to = cJSON_AddObjectToObject(j, "total_probability");
    const int C = s->configurations;
    cJSON_AddNumberToObject(to, "mean", st->t_mean[s->levels]);
    cJSON_AddNumberToObject(to, "sd", C > 1 ? sqrt(st->t_m2[s->levels] / (C - 1)) : 0.0);
    cJSON_AddNumberToObject(to, "min", st->t_lo[s->levels]);
    cJSON_AddNumberToObject(to, "max", st->t_hi[s->levels]);
    cJSON_AddBoolToObject(to, "conserving", vi->conserving);
    cJSON_AddNumberToObject(j, "wall_seconds", st->wall_seconds);
    cJSON_AddNumberToObject(j, "seconds_per_configuration",
                            (st->wall_seconds - st->place_seconds) / C);
    if (p->place) {
        cJSON *po = cJSON_AddObjectToObject(j, "placement");
        cJSON_AddNumberToObject(po, "N", p->placement.n);
        cJSON_AddNumberToObject(po, "radius", p->placement.radius);
        cJSON_AddNumberToObject(po, "L", s->L);
        cJSON_AddNumberToObject(po, "phi", st->pres.phi);
        cJSON_AddNumberToObject(po, "attempts", (double)st->pres.attempts);
        cJSON_AddNumberToObject(po, "rejected_overlaps", (double)st->pres.rejected);
        cJSON_AddNumberToObject(po, "seed", (double)st->place_seed);
        cJSON_AddStringToObject(po, "snapshot", "snapshots/snap_000000.xyz");
        cJSON_AddNumberToObject(po, "wall_seconds", st->place_seconds);
    }
    cJSON_AddStringToObject(j, "plots", plot_list);
    return j;
}

int gr_cascade_study_write(const char *dir, const gr_cascade_study_params *p,
                           const gr_cascade_study *st, char *list, size_t size, gr_error *err)
{
    run_info ri = {&p->s, gr_cascade_variant_get(p->s.variant), dir};
    int rc = write_sk(&ri, st, err);
    if (!rc) {
        rc = write_levels(&ri, st, err);
    }
    if (!rc) {
        rc = write_field(&ri, st, err);
    }
    if (!rc && p->place) {
        rc = write_placement(&ri, p, st, err);
    }
    if (rc) {
        return rc;
    }
    if (p->no_plots) {
        snprintf(list, size, "not requested");
    } else {
        plots(&ri, p, st, list, size);
    }
    cJSON *j = summary(p, st, list);
    rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}
