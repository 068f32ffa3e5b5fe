/* granule compare SCENE --models a,b,...: the same scene, initial state and noise seed under each
 * collision model; one side-by-side table (compare.csv, compare.md) and overlaid plots. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/run.h"
#include "io/checkpoint.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: granule compare SCENE --models SPEC[,SPEC...] [--set section.key=value ...] [--out DIR] [--force]\n\n"
               "Runs SCENE once per model SPEC with the same initial state and the same noise (same seed):\n"
               "SPEC = NORMAL[+TANGENTIAL][@clamp], e.g.\n"
               "  --models spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@clamp,spring_dashpot+sliding_friction\n"
               "Writes DIR/<label>/ (a full run folder each), DIR/compare.csv and compare.md (T, collisions, energy\n"
               "dissipated by mechanism, wall time, particle-steps/s and every scalar the enabled observables report)\n"
               "and DIR/temperature.png with the T(t) of all runs overlaid. With the pv observable enabled\n"
               "(--set analysis.observables=pv) also the collapse P'(v) = P(v) P_0(1)/P(1) of (5.4) in\n"
               "pv_collapse.csv/.png. Default DIR: out/compare.\n");
}

typedef struct entry {
    char spec[128], label[128];
    cJSON *summary;
} entry;

static void flatten(cJSON *row, const char *prefix, const cJSON *node)
{
    char key[256];
    for (const cJSON *c = node ? node->child : NULL; c; c = c->next) {
        snprintf(key, sizeof key, "%s.%s", prefix, c->string ? c->string : "");
        if (cJSON_IsNumber(c)) {
            cJSON_AddNumberToObject(row, key, c->valuedouble);
        } else if (cJSON_IsObject(c)) {
            flatten(row, key, c);
        } else if (cJSON_IsArray(c) && cJSON_GetArraySize(c) <= 16) {
            int k = 0;
            for (const cJSON *a = c->child; a; a = a->next, k++) {
                if (cJSON_IsNumber(a)) {
                    char ak[300];
                    snprintf(ak, sizeof ak, "%s.%d", key, k);
                    cJSON_AddNumberToObject(row, ak, a->valuedouble);
                }
            }
        }
    }
}

/* Read columns `xcol` and `ycol` of a CSV with '#' comments and one header line. */
static int read_columns(const char *path, const char *xcol, const char *ycol, double **x, double **y)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        return 0;
    }
    char line[4096];
    int ix = -1, iy = -1, n = 0, cap = 0;
    *x = *y = NULL;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            continue;
        }
        line[strcspn(line, "\n")] = 0;
        if (ix < 0 && iy < 0) { /* header */
            int c = 0;
            char *save = NULL;
            for (char *tok = strtok_r(line, ",", &save); tok; tok = strtok_r(NULL, ",", &save), c++) {
                ix = !strcmp(tok, xcol) ? c : ix;
                iy = !strcmp(tok, ycol) ? c : iy;
            }
            if (ix < 0 || iy < 0) {
                break;
            }
            continue;
        }
        double vx = NAN, vy = NAN;
        int c = 0;
        char *save = NULL;
        for (char *tok = strtok_r(line, ",", &save); tok; tok = strtok_r(NULL, ",", &save), c++) {
            vx = c == ix ? atof(tok) : vx;
            vy = c == iy ? atof(tok) : vy;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            *x = realloc(*x, sizeof(double) * (size_t)cap);
            *y = realloc(*y, sizeof(double) * (size_t)cap);
        }
        (*x)[n] = vx;
        (*y)[n] = vy;
        n++;
    }
    fclose(f);
    return n;
}

/* P at |v| = 1 (scaled units): mean of the two bins nearest +1 and -1 */
static double at_one(const double *x, const double *y, int n)
{
    double best_p = INFINITY, best_m = INFINITY, yp = NAN, ym = NAN;
    for (int i = 0; i < n; i++) {
        if (fabs(x[i] - 1.0) < best_p) {
            best_p = fabs(x[i] - 1.0);
            yp = y[i];
        }
        if (fabs(x[i] + 1.0) < best_m) {
            best_m = fabs(x[i] + 1.0);
            ym = y[i];
        }
    }
    return 0.5 * (yp + ym);
}

/* The data collapse of (5.4): P'(v) = P(v) P_0(1) / P(1) in units of v_rms, P_0 = the first model,
 * so the tails of all models can be compared in shape (pv observable needed). */
static void pv_collapse(const char *out, const entry *list, int n)
{
    double *xs[16] = {0}, *ys[16] = {0}, scale[16];
    int len[16] = {0};
    char path[1400];
    for (int k = 0; k < n; k++) {
        snprintf(path, sizeof path, "%s/%s/pv.csv", out, list[k].label);
        len[k] = read_columns(path, "v_over_vrms", "density_scaled", &xs[k], &ys[k]);
        if (len[k] == 0) {
            for (int j = 0; j <= k; j++) {
                free(xs[j]);
                free(ys[j]);
            }
            return; /* no pv in these runs */
        }
    }
    double p0 = at_one(xs[0], ys[0], len[0]);
    for (int k = 0; k < n; k++) {
        double pk = at_one(xs[k], ys[k], len[k]);
        scale[k] = pk > 0.0 ? p0 / pk : (double)NAN;
    }
    gr_file f;
    gr_error err = {0};
    if (gr_file_open(&f, out, "pv_collapse.csv", &err) == GR_OK) {
        gr_file_note(&f, "granule compare: P'(v) = P(v) P_0(1)/P(1) (5.4), v in units of v_rms, P_0 = %s; one row per "
                         "model and bin with P > 0 (a long table: filter on model)", list[0].spec);
        fprintf(f.f, "model,v_over_vrms,P_scaled\n");
        for (int k = 0; k < n; k++) {
            for (int i = 0; i < len[k]; i++) {
                if (ys[k][i] > 0.0) {
                    fprintf(f.f, "%s,%.6g,%.6g\n", list[k].spec, xs[k][i], ys[k][i] * scale[k]);
                }
            }
        }
        if (gr_file_commit(&f, &err) == GR_OK) {
            char body[4096];
            size_t blen = (size_t)snprintf(body, sizeof body,
                                           "set logscale y\nset xlabel 'v / v_{rms}'\nset ylabel \"P'(v) (5.4)\"\n"
                                           "set title 'Velocity distributions rescaled at v = v_{rms} (5.4)'\nplot ");
            for (int k = 0; k < n && blen < sizeof body; k++) {
                blen += (size_t)snprintf(body + blen, sizeof body - blen, "%s'pv_collapse.csv' skip 1 using 2:(strcol(1) eq '%s' ? $3 : 1/0) with lines title '%s' noenhanced",
                                         k ? ", " : "", list[k].spec, list[k].spec);
            }
            char note[300];
            gr_plot_script(out, "pv_collapse.png", body, note, sizeof note);
        }
    }
    for (int k = 0; k < n; k++) {
        free(xs[k]);
        free(ys[k]);
    }
}

/* The first result of an earlier comparison in `out` (its tables, or a model's finished or
 * interrupted run), named in `what`; false when there is none. */
static bool earlier_comparison(const char *out, const entry *list, int n, char *what, size_t len)
{
    const char *tables[] = {"compare.md", "compare.csv"};
    for (int i = 0; i < 2; i++) {
        snprintf(what, len, "%s/%s", out, tables[i]);
        if (access(what, F_OK) == 0) {
            return true;
        }
    }
    for (int k = 0; k < n; k++) {
        const char *runs[] = {"summary.json", GR_CHECKPOINT_NAME};
        for (int i = 0; i < 2; i++) {
            snprintf(what, len, "%s/%s/%s", out, list[k].label, runs[i]);
            if (access(what, F_OK) == 0) {
                return true;
            }
        }
    }
    return false;
}

int cmd_compare(int argc, char **argv)
{
    const char *scene_path = NULL, *models = NULL, *out = "out/compare";
    const char **sets = calloc((size_t)argc + 4, sizeof(char *));
    int n_sets = 0;
    bool force = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            free(sets);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--models") && i + 1 < argc) {
            models = argv[++i];
        } else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            sets[n_sets++] = argv[++i];
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--force")) {
            force = true;
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            cli_error("compare: unexpected argument %s", argv[i]);
            free(sets);
            return EXIT_REFUSED;
        }
    }
    if (!scene_path || !models) {
        usage(stderr);
        free(sets);
        return EXIT_REFUSED;
    }
    gr_error err = {0};
    entry list[16];
    int n = 0;
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", models);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok && n < 16; tok = strtok_r(NULL, ",", &save)) {
        entry *e = &list[n++];
        memset(e, 0, sizeof *e);
        snprintf(e->spec, sizeof e->spec, "%.120s", tok);
        snprintf(e->label, sizeof e->label, "%.120s", tok);
        for (char *c = e->label; *c; c++) {
            *c = (*c == '+' || *c == '@') ? '_' : *c;
        }
    }
    /* first pass: every spec must load before anything runs */
    static char assign[16][3][160];
    gr_scene scenes[16];
    for (int k = 0; k < n; k++) {
        char spec[128];
        snprintf(spec, sizeof spec, "%.127s", list[k].spec);
        bool clamp = false;
        char *at = strchr(spec, '@');
        if (at) {
            clamp = !strcmp(at + 1, "clamp");
            if (!clamp) {
                cli_error("compare: '%s': the only modifier is @clamp", list[k].spec);
                free(sets);
                return EXIT_REFUSED;
            }
            *at = 0;
        }
        char *plus = strchr(spec, '+');
        if (plus) {
            *plus = 0;
        }
        snprintf(assign[k][0], 160, "model.normal=%s", spec);
        snprintf(assign[k][1], 160, "model.tangential=%s", plus ? plus + 1 : "none");
        snprintf(assign[k][2], 160, "model.clamp=%s", clamp ? "true" : "false");
        const char *all[64];
        int m = 0;
        for (int i = 0; i < n_sets && m < 60; i++) {
            all[m++] = sets[i];
        }
        for (int i = 0; i < 3; i++) {
            all[m++] = assign[k][i];
        }
        if (gr_scene_load_whole(&scenes[k], scene_path, all, m, &err)) {
            cli_error("compare: %s: %s", list[k].spec, err.message);
            free(sets);
            return EXIT_REFUSED;
        }
        snprintf(scenes[k].out_dir, sizeof scenes[k].out_dir, "%s/%s", out, list[k].label);
    }
    free(sets);
    /* only now, with every model's scene accepted, is the folder touched; an earlier comparison
     * (its table or any model's run) is kept unless --force */
    if (!force && earlier_comparison(out, list, n, buf, sizeof buf)) {
        cli_error("compare: %s already holds a comparison (%s); choose another folder or pass --force to overwrite it", out, buf);
        return EXIT_REFUSED;
    }
    if (gr_output_dir_prepare(out, force, &err)) {
        cli_error("compare: %s", err.message);
        return cli_exit_code(err.code);
    }
    int failures = 0;
    for (int k = 0; k < n; k++) {
        fprintf(stderr, "compare: %s (%d/%d)\n", list[k].spec, k + 1, n);
        gr_run_options opt = {.force = force};
        gr_run_result res;
        int rc = gr_run(&scenes[k], &opt, &res, &err);
        if (rc) {
            cli_error("compare: %s: %s", list[k].spec, err.message);
            failures++;
        }
        list[k].summary = gr_summary_read(scenes[k].out_dir, &err);
    }
    /* the table: fixed columns first, then every scalar of the analysis members */
    cJSON *rows = cJSON_CreateArray();
    for (int k = 0; k < n; k++) {
        cJSON *row = cJSON_CreateObject();
        const cJSON *s = list[k].summary;
        const char *fixed[] = {"T_mean", "T_stderr", "T_stderr_converged", "collisions", "ledger.injected", "ledger.dissipated_normal",
                               "ledger.dissipated_tangential", "ledger.dissipated_friction", "wall_seconds",
                               "particle_steps_per_second"};
        for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
            cJSON_AddNumberToObject(row, fixed[i], s ? gr_summary_number(s, fixed[i]) : (double)NAN);
        }
        if (s) {
            flatten(row, "analysis", cJSON_GetObjectItem(s, "analysis"));
            flatten(row, "mean_field", cJSON_GetObjectItem(s, "mean_field"));
        }
        cJSON_AddItemToArray(rows, row);
    }
    /* union of columns in first-seen order */
    const char *cols[256];
    int nc = 0;
    for (const cJSON *row = rows->child; row; row = row->next) {
        for (const cJSON *c = row->child; c && nc < 256; c = c->next) {
            bool have = false;
            for (int i = 0; i < nc; i++) {
                have |= !strcmp(cols[i], c->string);
            }
            if (!have) {
                cols[nc++] = c->string;
            }
        }
    }
    gr_file csv, md;
    int rc = gr_file_open(&csv, out, "compare.csv", &err);
    if (!rc) {
        rc = gr_file_open(&md, out, "compare.md", &err);
    }
    if (rc) {
        cli_error("compare: %s", err.message);
        return EXIT_FAILED;
    }
    gr_file_note(&csv, "granule compare of %s: one row per model, same initial state and noise seed", scene_path);
    fprintf(csv.f, "model,kernel");
    for (int i = 0; i < nc; i++) {
        fprintf(csv.f, ",%s", cols[i]);
    }
    fputc('\n', csv.f);
    fprintf(md.f, "# granule compare: %s\n\n| quantity |", scene_path);
    for (int k = 0; k < n; k++) {
        fprintf(md.f, " %s |", list[k].spec);
    }
    fprintf(md.f, "\n|---|");
    for (int k = 0; k < n; k++) {
        fprintf(md.f, "---|");
    }
    fprintf(md.f, "\n| kernel |");
    int k = 0;
    for (const cJSON *row = rows->child; row; row = row->next, k++) {
        const cJSON *kern = list[k].summary ? cJSON_GetObjectItem(list[k].summary, "kernel") : NULL;
        const char *kname = cJSON_IsString(kern) ? kern->valuestring : "failed";
        fprintf(csv.f, "%s,%s", list[k].spec, kname);
        fprintf(md.f, " %s |", kname);
        for (int i = 0; i < nc; i++) {
            const cJSON *c = cJSON_GetObjectItem(row, cols[i]);
            fprintf(csv.f, ",%.8g", c ? c->valuedouble : (double)NAN);
        }
        fputc('\n', csv.f);
    }
    fputc('\n', md.f);
    for (int i = 0; i < nc; i++) {
        fprintf(md.f, "| %s |", cols[i]);
        for (const cJSON *row = rows->child; row; row = row->next) {
            const cJSON *c = cJSON_GetObjectItem(row, cols[i]);
            fprintf(md.f, " %.6g |", c ? c->valuedouble : (double)NAN);
        }
        fputc('\n', md.f);
    }
    /* an error bar whose blocking never reached a plateau is a lower bound: say so under the table */
    for (int j = 0; j < n; j++) {
        if (list[j].summary && gr_summary_number(list[j].summary, "T_stderr_converged") == 0.0) {
            fprintf(md.f, "\n**Warning**: %s: the error bar of T is not converged (T_stderr_converged = 0): it is a "
                          "lower bound; run longer.\n", list[j].spec);
            fprintf(stderr, "compare: warning: %s: the error bar of T is not converged (T_stderr_converged = false): run longer\n",
                    list[j].spec);
        }
    }
    rc = gr_file_commit(&csv, &err);
    rc = rc ? rc : gr_file_commit(&md, &err);
    /* overlaid temperatures */
    char body[4096];
    size_t len = (size_t)snprintf(body, sizeof body, "set title 'T(t) under each model'\nset xlabel 't (s)'\nset ylabel 'T (m^2/s^2)'\nplot ");
    for (int j = 0; j < n && len < sizeof body; j++) {
        len += (size_t)snprintf(body + len, sizeof body - len, "%s'%s/temperature.csv' skip 1 using 1:2 with lines title '%s' noenhanced",
                                j ? ", " : "", list[j].label, list[j].spec);
    }
    char note[300];
    gr_plot_script(out, "temperature.png", body, note, sizeof note);
    pv_collapse(out, list, n);
    cJSON_Delete(rows);
    for (int j = 0; j < n; j++) {
        cJSON_Delete(list[j].summary);
    }
    if (rc) {
        cli_error("compare: %s", err.message);
        return EXIT_FAILED;
    }
    printf("%s/compare.md\n", out);
    return failures ? EXIT_FAILED : EXIT_OK;
}
