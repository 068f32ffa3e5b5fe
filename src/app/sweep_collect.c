/* Collecting a sweep: every point folder is read back (whoever ran it), one row per point goes
 * into OUT/sweep.csv, and when system.N varies the velocity moments are fitted against N:
 * <|v|^m> = A N^-xi_m (3.8, 3.13) and, from the gaps observable, <R^m> = A N^-zeta_m (3.20), into
 * OUT/exponents.csv and exponents.png. Missing and failed points are named on stderr. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/report.h"
#include "app/sweep.h"
#include "granule/analysis.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

/* xi_m / m and zeta_m / m against m, one curve per combination of the other keys (Figs. 3.5, 3.11):
 * regroup exponents.csv into gnuplot index blocks and draw exponents.png. */
static void plot_exponents(const char *out)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/exponents.csv", out);
    FILE *in = gr_input_fopen(path, &(int){0});
    if (!in) {
        return;
    }
    char lines[4096][160];
    int n = 0;
    char line[512];
    while (n < 4096 && fgets(line, sizeof line, in)) {
        if (line[0] != '#' && !strstr(line, "quantity")) {
            snprintf(lines[n++], sizeof lines[0], "%.159s", line);
        }
    }
    fclose(in);
    gr_file f;
    gr_error err = {0};
    if (gr_file_open(&f, out, "exponents_blocks.dat", &err)) {
        return;
    }
    /* a block starts whenever the text before ",xi," or ",zeta," changes */
    char prev[160] = "", titles[64][160];
    int blocks = 0;
    for (int i = 0; i < n; i++) {
        char *q = strstr(lines[i], "xi,") == lines[i] || strstr(lines[i], "zeta,") == lines[i]
                      ? lines[i]
                      : strstr(lines[i], ",xi,");
        if (!q) {
            q = strstr(lines[i], ",zeta,");
        }
        if (!q) {
            continue;
        }
        char key[160];
        snprintf(key, sizeof key, "%.*s%s", (int)(q - lines[i] < 140 ? q - lines[i] : 140),
                 lines[i], strstr(q, "zeta") ? " zeta_m/m" : " xi_m/m");
        if (strcmp(key, prev) != 0) {
            if (blocks > 0) {
                fprintf(f.f, "\n\n");
            }
            if (blocks < 64) {
                snprintf(titles[blocks], sizeof titles[0], "%s", key);
            }
            blocks++;
            snprintf(prev, sizeof prev, "%s", key);
        }
        int m;
        double x, xe;
        char *fields = strchr(q + 1, ',');
        if (fields && sscanf(fields + 1, "%d,%lf,%lf", &m, &x, &xe) == 3) {
            fprintf(f.f, "%d,%.6g,%.6g\n", m, x / m, xe / m);
        }
    }
    if (gr_file_commit(&f, &err) || blocks == 0) {
        return;
    }
    char body[8192];
    size_t len = (size_t)snprintf(
        body, sizeof body,
        "set xlabel 'order m'\nset ylabel 'exponent / m'\nset key outside right top\nset xtics 1\n"
        "set title \"Scaling exponents with N, per order m, from the sweep\\n{/*0.75 \u03be_m/m of "
        "<|v|^m> ~ N^{-\u03be_m} (3.13), \u03b6_m/m of <R^m> ~ N^{-\u03b6_m} (3.20)}\"\nplot ");
    for (int b = 0; b < blocks && b < 64 && len < sizeof body; b++) {
        char style[80];
        gr_plot_series_style(b, style, sizeof style);
        len += (size_t)snprintf(body + len, sizeof body - len,
                                "%s'exponents_blocks.dat' index %d using 1:2:3 with yerrorlines %s "
                                "pt 7 title '%s' noenhanced",
                                b ? ", " : "", b, style, titles[b]);
    }
    char note[300];
    gr_plot_script(out, "exponents.png", body, note, sizeof note);
}

/* A point's summary.json, NULL when its folder holds no run of these settings */
static cJSON *point_summary(const sweep *s, long k, const char *status)
{
    char dir[1100];
    sweep_point_dir(s, k, dir, sizeof dir);
    /* a missing or stale point's folder holds nothing of these settings */
    bool has_run =
        !strcmp(status, "completed") || !strcmp(status, "unstable") || !strcmp(status, "failed");
    gr_error read_err = {0};
    return has_run ? gr_summary_read(dir, &read_err) : NULL;
}

/* Whether some point's summary has the number at `path`: the 1D separations' moments <R^m> (the
 * gaps observable), a bed's profile (the profile observable). */
static bool any_number(const sweep *s, long n_points, const char *const *status, const char *path)
{
    bool any = false;
    for (long k = 0; k < n_points && !any; k++) {
        cJSON *j = point_summary(s, k, status[k]);
        any = isfinite(gr_summary_number(j, path));
        cJSON_Delete(j);
    }
    return any;
}

static int write_tables(const sweep *s, long n_points, const char *const *status)
{
    gr_error err = {0};
    gr_file f;
    if (gr_file_open(&f, s->out, "sweep.csv", &err)) {
        app_error("sweep: %s", err.message);
        return EXIT_FAILED;
    }
    /* <R^m> columns only when some point has them (1D runs with the gaps observable) */
    const bool with_R = any_number(s, n_points, status, "analysis.gaps.moments.0");
    /* a bed's numbers when some point has the profile observable (beds, walls, gravity) */
    const bool with_profile = any_number(s, n_points, status, "analysis.profile.mean_position");
    /* a freely cooling gas's Haff time beside the Enskog one; event-driven runs' event rate */
    const bool with_haff = any_number(s, n_points, status, "mean_field.t0_fit");
    const bool with_events = any_number(s, n_points, status, "events_per_second");
    /* a binary mixture's temperature ratio and its theory (the species observable, docs/mixtures.md) */
    const bool with_species = any_number(s, n_points, status, "analysis.species.T1_over_T2");
    /* a bed of two species or more: the first two species' mean heights (the profile observable) */
    const bool with_heights =
        any_number(s, n_points, status, "analysis.profile.species_mean_position.1");
    gr_file_note(&f, "granule sweep of %s: one row per point; moments <|v|^m> in (m/s)^m%s",
                 s->scene, with_R ? ", <R^m> in m^m" : "");
    gr_file_columns(&f, "point [1],seed [1]");
    for (int i = 0; i < s->n_keys; i++) {
        gr_file_column(&f, s->key[i], gr_scene_key_unit(s->key[i]));
    }
    gr_file_columns(
        &f, "status [],T_mean [m2 s-2],T_stderr [m2 s-2],T_stderr_converged [1],collisions [1],"
            "particle_steps_per_second [s-1]");
    for (int q = 0; q < (with_R ? 2 : 1); q++) {
        for (int m = 1; m <= 12; m++) {
            char name[32], unit[32];
            snprintf(unit, sizeof unit, q ? "m%d" : "m%d s-%d", m, m);
            snprintf(name, sizeof name, q ? "R%d" : "m%d", m);
            gr_file_column(&f, name, unit);
            snprintf(name, sizeof name, q ? "R%d_stderr" : "m%d_stderr", m);
            gr_file_column(&f, name, unit);
        }
    }
    if (with_profile) {
        gr_file_columns(&f, "profile_height [m],profile_height_stderr [m],profile_max_phi [1]");
    }
    if (with_haff) {
        gr_file_columns(&f, "haff_t0 [s],haff_t0_stderr [s],haff_t0_enskog [s]");
    }
    if (with_events) {
        gr_file_columns(&f, "events_per_second [s-1]");
    }
    if (with_species) {
        gr_file_columns(&f, "T1_over_T2 [1],T1_over_T2_stderr [1],T1_over_T2_predicted [1]");
    }
    if (with_heights) {
        gr_file_columns(&f, "profile_height_1 [m],profile_height_1_stderr [m],profile_height_2 [m],"
                            "profile_height_2_stderr [m]");
    }
    fputc('\n', f.f);
    int n_col = s->n_keys;
    int n_idx = -1;
    for (int i = 0; i < s->n_keys; i++) {
        if (!strcmp(s->key[i], "system.N")) {
            n_idx = i;
        }
    }
    /* moments per point, kept for the fits */
    double(*mom)[13] = calloc((size_t)n_points, sizeof *mom);
    double(*mom_err)[13] = calloc((size_t)n_points, sizeof *mom_err);
    double(*rmom)[13] = calloc((size_t)n_points, sizeof *rmom);
    double(*rmom_err)[13] = calloc((size_t)n_points, sizeof *rmom_err);
    for (long k = 0; k < n_points; k++) {
        int idx[SWEEP_MAX_KEYS] = {0}, seed;
        sweep_decode(s, k, idx, &seed);
        cJSON *j = point_summary(s, k, status[k]);
        fprintf(f.f, "%ld,%llu", k, sweep_point_seed(s, k));
        for (int i = 0; i < n_col; i++) {
            fputc(',', f.f);
            gr_csv_text(f.f, s->value[i][idx[i]], false);
        }
        /* T_stderr_converged 0: the error bar is a lower bound (docs/analysis.md) */
        fprintf(f.f, ",%s,%.8g,%.4g,%.0f,%.0f,%.4g", status[k], gr_summary_number(j, "T_mean"),
                gr_summary_number(j, "T_stderr"), gr_summary_number(j, "T_stderr_converged"),
                gr_summary_number(j, "collisions"),
                gr_summary_number(j, "particle_steps_per_second"));
        for (int m = 1; m <= 12; m++) {
            char p1[64], p2[64];
            snprintf(p1, sizeof p1, "analysis.moments.speed.m%d", m);
            snprintf(p2, sizeof p2, "analysis.moments.speed_stderr.m%d", m);
            mom[k][m] = gr_summary_number(j, p1);
            mom_err[k][m] = gr_summary_number(j, p2);
            if (m == 2 && isnan(mom[k][m])) {
                /* without the moments observable <v^2> is known only in 1D, where it equals T */
                const cJSON *sc =
                    j ? cJSON_GetObjectItem(cJSON_GetObjectItem(j, "scene"), "system") : NULL;
                if (sc && gr_summary_number(sc, "dim") == 1.0) {
                    mom[k][m] = gr_summary_number(j, "T_mean");
                    mom_err[k][m] = gr_summary_number(j, "T_stderr");
                }
            }
            fprintf(f.f, ",%.8g,%.4g", mom[k][m], mom_err[k][m]);
            if (strcmp(status[k], "completed") !=
                0) { /* shown, but only completed runs are fitted */
                mom[k][m] = NAN;
            }
            /* 1D neighbour separations <R^m> (3.18) from the gaps observable, for zeta_m (3.20) */
            snprintf(p1, sizeof p1, "analysis.gaps.moments.%d", m - 1);
            snprintf(p2, sizeof p2, "analysis.gaps.moments_stderr.%d", m - 1);
            rmom[k][m] = gr_summary_number(j, p1);
            rmom_err[k][m] = gr_summary_number(j, p2);
        }
        for (int m = 1; m <= 12; m++) {
            if (with_R) {
                fprintf(f.f, ",%.8g,%.4g", rmom[k][m], rmom_err[k][m]);
            }
            if (strcmp(status[k], "completed") != 0) {
                rmom[k][m] = NAN;
            }
        }
        if (with_profile) {
            fprintf(f.f, ",%.8g,%.4g,%.6g", gr_summary_number(j, "analysis.profile.mean_position"),
                    gr_summary_number(j, "analysis.profile.mean_position_error"),
                    gr_summary_number(j, "analysis.profile.max_packing_fraction"));
        }
        if (with_haff) {
            fprintf(f.f, ",%.8g,%.4g,%.8g", gr_summary_number(j, "mean_field.t0_fit"),
                    gr_summary_number(j, "mean_field.t0_fit_stderr"),
                    gr_summary_number(j, "mean_field.t0_haff"));
        }
        if (with_events) {
            fprintf(f.f, ",%.4g", gr_summary_number(j, "events_per_second"));
        }
        if (with_species) {
            fprintf(f.f, ",%.8g,%.4g,%.8g", gr_summary_number(j, "analysis.species.T1_over_T2"),
                    gr_summary_number(j, "analysis.species.T1_over_T2_stderr"),
                    gr_summary_number(j, "mean_field.T1_over_T2_predicted"));
        }
        for (int a = 0; with_heights && a < 2; a++) {
            char p1[80], p2[80];
            snprintf(p1, sizeof p1, "analysis.profile.species_mean_position.%d", a);
            snprintf(p2, sizeof p2, "analysis.profile.species_mean_position_error.%d", a);
            fprintf(f.f, ",%.8g,%.4g", gr_summary_number(j, p1), gr_summary_number(j, p2));
        }
        fputc('\n', f.f);
        cJSON_Delete(j);
    }
    int rc = gr_file_commit(&f, &err);
    if (!rc && n_idx >= 0 && s->n_values[n_idx] >= 3) {
        /* xi_m: for each combination of the other keys, <|v|^m> = A N^-xi_m over the seeds
         * (gr_fit_power_law_seeds: seeds averaged at each N, the larger of their spread and the runs'
         * own errors as sigma) */
        gr_file e;
        rc = gr_file_open(&e, s->out, "exponents.csv", &err);
        if (!rc) {
            gr_file_note(&e, "# granule sweep: <|v|^m> = A N^-xi_m (3.8, 3.13) and <R^m> = A "
                             "N^-zeta_m (3.20), per combination of the other keys\n");
            for (int i = 0; i < s->n_keys; i++) {
                if (i != n_idx) {
                    gr_file_column(&e, s->key[i], gr_scene_key_unit(s->key[i]));
                }
            }
            gr_file_header(&e, "quantity [],m [1],exponent [1],exponent_error [1],A "
                               "[@A_unit],chi2_red [1],points [1],A_unit []");
            long groups = 1;
            for (int i = 0; i < s->n_keys; i++) {
                groups *= i == n_idx ? 1 : s->n_values[i];
            }
            for (long gidx = 0; gidx < groups; gidx++) {
                /* the value index of each non-N key for this group */
                int gv[SWEEP_MAX_KEYS];
                long g = gidx;
                for (int i = s->n_keys - 1; i >= 0; i--) {
                    if (i == n_idx) {
                        gv[i] = 0;
                        continue;
                    }
                    gv[i] = (int)(g % s->n_values[i]);
                    g /= s->n_values[i];
                }
                for (int q = 0; q < 2; q++)
                    for (int m = 1; m <= 12; m++) {
                        double(*val)[13] = q == 0 ? mom : rmom,
                        (*verr)[13] = q == 0 ? mom_err : rmom_err;
                        double *x = malloc(3 * sizeof(double) * (size_t)n_points),
                               *y = x + n_points, *ye = y + n_points;
                        int nr = 0, np = 0;
                        for (long k = 0; k < n_points;
                             k++) { /* this group's runs, in point order */
                            int idx[SWEEP_MAX_KEYS] = {0}, seed;
                            sweep_decode(s, k, idx, &seed);
                            bool match = true;
                            for (int i = 0; i < s->n_keys && match; i++) {
                                match = i == n_idx || idx[i] == gv[i];
                            }
                            if (match) {
                                x[nr] = atof(s->value[n_idx][idx[n_idx]]);
                                y[nr] = val[k][m];
                                ye[nr++] = verr[k][m];
                            }
                        }
                        gr_fit fit;
                        gr_error ignore = {0}; /* too few sizes: no row */
                        const int fitted =
                            gr_fit_power_law_seeds(x, y, ye, nr, &fit, &np, &ignore) == GR_OK;
                        free(x);
                        if (fitted) {
                            for (int i = 0; i < s->n_keys; i++) {
                                if (i != n_idx) {
                                    gr_csv_text(e.f, s->value[i][gv[i]], false);
                                    fputc(',', e.f);
                                }
                            }
                            /* A carries the moment's unit: (m/s)^m for xi, m^m for zeta */
                            char unit[32];
                            snprintf(unit, sizeof unit, q == 0 ? "m%d s-%d" : "m%d", m, m);
                            fprintf(e.f, "%s,%d,%.6g,%.3g,%.6g,%.4g,%d,%s\n",
                                    q == 0 ? "xi" : "zeta", m, -fit.p[1], fit.err[1], fit.p[0],
                                    fit.chi2_red, np, unit);
                        }
                    }
            }
            rc = gr_file_commit(&e, &err);
            if (!rc) {
                plot_exponents(s->out);
            }
        }
    }
    free(mom);
    free(mom_err);
    free(rmom);
    free(rmom_err);
    if (rc) {
        app_error("sweep: %s", err.message);
        return EXIT_FAILED;
    }
    return EXIT_OK;
}

/* "3, 5-9, 12" from a sorted list of point indices (shortened past len). */
static void ranges(const long *k, long n, char *out, size_t len)
{
    size_t used = 0;
    out[0] = 0;
    for (long i = 0; i < n && used + 32 < len; i++) {
        long j = i;
        while (j + 1 < n && k[j + 1] == k[j] + 1) {
            j++;
        }
        used += (size_t)(j > i ? snprintf(out + used, len - used, "%s%ld-%ld", i ? ", " : "", k[i],
                                          k[j])
                               : snprintf(out + used, len - used, "%s%ld", i ? ", " : "", k[i]));
        i = j;
    }
    if (used + 32 >= len) {
        snprintf(out + used, len - used, ", ...");
    }
}

int sweep_collect(const sweep *s, const uint64_t *hash, long *n_bad)
{
    gr_error err = {0};
    *n_bad = s->n_points;
    if (gr_output_dir_prepare(s->out, GR_OUTPUT_SWEEP, s->force, &err)) {
        app_error("sweep: %s", err.message);
        return app_exit_code(err.code);
    }
    const char **status = calloc((size_t)s->n_points, sizeof *status);
    long *missing = calloc((size_t)s->n_points, sizeof *missing),
         *failed = calloc((size_t)s->n_points, sizeof *failed);
    long n_missing = 0, n_failed = 0;
    for (long k = 0; k < s->n_points; k++) {
        char why[800];
        point_state st = sweep_point_state(s, k, hash[k], why, sizeof why);
        status[k] = sweep_state_name(st);
        if (st == POINT_COMPLETED) {
            continue;
        }
        if (st == POINT_FAILED || st == POINT_UNSTABLE) {
            failed[n_failed++] = k;
            app_note("sweep: point %ld %s: %s\n", k, status[k], why);
        } else {
            missing[n_missing++] = k;
            if (why[0]) {
                app_note("sweep: point %ld %s: %s\n", k, status[k], why);
            }
        }
    }
    char list[600];
    if (n_missing) {
        ranges(missing, n_missing, list, sizeof list);
        app_note("sweep: unfinished points (%ld; never run, stopped with a checkpoint, still "
                 "running or killed, or run with "
                 "other settings): %s\n",
                 n_missing, list);
    }
    if (n_failed) {
        ranges(failed, n_failed, list, sizeof list);
        app_note("sweep: failed points (%ld): %s (errors in OUT/pNNNN/point.json; they run again "
                 "on the next sweep or --point K)\n",
                 n_failed, list);
    }
    int rc = write_tables(s, s->n_points, status);
    *n_bad = n_missing + n_failed;
    free(status);
    free(missing);
    free(failed);
    return rc;
}
