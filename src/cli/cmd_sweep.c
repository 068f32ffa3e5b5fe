/* granule sweep FILE: one scene over lists of keys (e.g. N x eps as in sec. 3.1.2) and seeds, in
 * parallel over local cores, resumable (a point whose folder holds a completed summary.json is
 * not rerun), with one table of results and the fitted exponents of the velocity moments in N
 * (xi_m of eqs. 3.8 and 3.13). */
#include <cjson/cJSON.h>
#include <errno.h>
#include <ini.h>
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/analysis.h"
#include "granule/run.h"
#include "io/files.h"
#include "io/plot.h"
#include "io/summary_read.h"

#define MAX_KEYS 8
#define MAX_VALUES 64
#define MAX_SETS 64

typedef struct sweep {
    char scene[1024], out[1024];
    int jobs;
    int n_seeds;
    unsigned long long seeds[MAX_VALUES];
    int n_keys;
    char key[MAX_KEYS][128];
    int n_values[MAX_KEYS];
    char value[MAX_KEYS][MAX_VALUES][64];
    int n_sets;
    char set[MAX_SETS][256];
    int line;
    char error[600];
} sweep;

static void usage(FILE *f)
{
    fprintf(f, "usage: granule sweep FILE [--jobs J] [--force]\n\n"
               "FILE (INI):\n"
               "  [sweep]\n  scene = rfm-1d.ini        ; relative to FILE's folder\n  out = out/sweep           ; relative to the working folder\n"
               "  seeds = 1, 2, 3\n  jobs = 2                  ; parallel runs (default: number of cores)\n"
               "  [vary]                    ; every combination is run, for every seed\n"
               "  system.N = 100, 158, 251\n  model.eps_n = 0.1, 0.5\n"
               "  [set]                     ; fixed overrides for every point\n  run.duration = 20\n  analysis.observables = moments\n\n"
               "Each point runs into OUT/pNNNN (point.json names its keys); finished points are not rerun;\n"
               "a failed point is reported and the others go on. Writes OUT/sweep.csv (one row per point)\n"
               "and, when system.N varies, OUT/exponents.csv: <|v|^m> ~ N^-xi_m fitted per combination of\n"
               "the other keys (3.8, 3.13), averaging seeds, with errors and reduced chi-square.\n");
}

static int split_list(const char *text, char out[][64], int max)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", text);
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", \t", &save); tok && n < max; tok = strtok_r(NULL, ", \t", &save)) {
        snprintf(out[n++], 64, "%s", tok);
    }
    return n;
}

static int on_line(void *user, const char *section, const char *name, const char *value)
{
    sweep *s = user;
    if (!strcmp(section, "sweep")) {
        if (!strcmp(name, "scene")) {
            snprintf(s->scene, sizeof s->scene, "%s", value);
        } else if (!strcmp(name, "out")) {
            snprintf(s->out, sizeof s->out, "%s", value);
        } else if (!strcmp(name, "jobs")) {
            s->jobs = atoi(value);
        } else if (!strcmp(name, "seeds")) {
            char v[MAX_VALUES][64];
            s->n_seeds = split_list(value, v, MAX_VALUES);
            for (int i = 0; i < s->n_seeds; i++) {
                char *end;
                s->seeds[i] = strtoull(v[i], &end, 10);
                if (*end) {
                    snprintf(s->error, sizeof s->error, "[sweep] seeds: '%s' is not an integer", v[i]);
                    return 0;
                }
            }
        } else {
            snprintf(s->error, sizeof s->error, "[sweep] %s: unknown key; keys: scene, out, seeds, jobs", name);
            return 0;
        }
    } else if (!strcmp(section, "vary")) {
        if (s->n_keys == MAX_KEYS) {
            snprintf(s->error, sizeof s->error, "[vary]: at most %d keys", MAX_KEYS);
            return 0;
        }
        snprintf(s->key[s->n_keys], 128, "%s", name);
        s->n_values[s->n_keys] = split_list(value, s->value[s->n_keys], MAX_VALUES);
        if (s->n_values[s->n_keys] == 0 || !strchr(name, '.')) {
            snprintf(s->error, sizeof s->error, "[vary] %s: expected section.key = v1, v2, ...", name);
            return 0;
        }
        s->n_keys++;
    } else if (!strcmp(section, "set")) {
        if (s->n_sets == MAX_SETS || !strchr(name, '.')) {
            snprintf(s->error, sizeof s->error, "[set] %s: expected section.key = value", name);
            return 0;
        }
        snprintf(s->set[s->n_sets++], 256, "%s=%s", name, value);
    } else {
        snprintf(s->error, sizeof s->error, "[%s]: unknown section; sections: sweep, vary, set", section);
        return 0;
    }
    return 1;
}

/* Point k: the value index of each varied key (last key fastest) and the seed index. */
static void decode(const sweep *s, long k, int idx[MAX_KEYS], int *seed)
{
    *seed = (int)(k % s->n_seeds);
    k /= s->n_seeds;
    for (int i = s->n_keys - 1; i >= 0; i--) {
        idx[i] = (int)(k % s->n_values[i]);
        k /= s->n_values[i];
    }
}

static int point_overrides(const sweep *s, long k, char store[][256], const char **ptrs)
{
    int idx[MAX_KEYS] = {0}, seed, m = 0;
    decode(s, k, idx, &seed);
    for (int i = 0; i < s->n_sets; i++) {
        snprintf(store[m], 256, "%s", s->set[i]);
        ptrs[m] = store[m];
        m++;
    }
    for (int i = 0; i < s->n_keys; i++) {
        snprintf(store[m], 256, "%s=%s", s->key[i], s->value[i][idx[i]]);
        ptrs[m] = store[m];
        m++;
    }
    snprintf(store[m], 256, "run.seed=%llu", s->seeds[seed]);
    ptrs[m] = store[m];
    return m + 1;
}

static bool point_done(const char *dir)
{
    gr_error err = {0};
    cJSON *j = gr_summary_read(dir, &err);
    const cJSON *st = j ? cJSON_GetObjectItem(j, "status") : NULL;
    bool done = cJSON_IsString(st) && !strcmp(st->valuestring, "completed");
    cJSON_Delete(j);
    return done;
}

/* Child process: run one point; exit status 0 ok, 2 refused, 3 unstable, 1 other. */
static int run_point(const sweep *s, long k, const char *dir)
{
    char store[MAX_SETS + MAX_KEYS + 2][256];
    const char *ptrs[MAX_SETS + MAX_KEYS + 2];
    int m = point_overrides(s, k, store, ptrs);
    gr_scene sc;
    gr_error err = {0};
    if (gr_scene_load(&sc, s->scene, ptrs, m, &err)) {
        fprintf(stderr, "granule sweep: point %ld: %s\n", k, err.message);
        return EXIT_REFUSED;
    }
    snprintf(sc.out_dir, sizeof sc.out_dir, "%.1000s", dir);
    sc.progress = false;
    gr_run_options opt = {.force = true}; /* an unfinished point's folder is ours to redo */
    gr_run_result res;
    int rc = gr_run(&sc, &opt, &res, &err);
    if (rc) {
        fprintf(stderr, "granule sweep: point %ld: %s\n", k, err.message);
    }
    return rc == GR_OK ? EXIT_OK : rc == GR_EUNSTABLE ? EXIT_UNSTABLE : rc == GR_EINVAL ? EXIT_REFUSED : EXIT_FAILED;
}

static void write_manifest(const sweep *s, long k, const char *dir)
{
    int idx[MAX_KEYS] = {0}, seed;
    decode(s, k, idx, &seed);
    cJSON *j = cJSON_CreateObject();
    cJSON_AddNumberToObject(j, "point", (double)k);
    cJSON_AddStringToObject(j, "scene", s->scene);
    cJSON *keys = cJSON_AddObjectToObject(j, "keys");
    for (int i = 0; i < s->n_keys; i++) {
        cJSON_AddStringToObject(keys, s->key[i], s->value[i][idx[i]]);
    }
    cJSON_AddNumberToObject(j, "seed", (double)s->seeds[seed]);
    char *text = cJSON_Print(j);
    gr_file f;
    gr_error err = {0};
    if (!gr_file_open(&f, dir, "point.json", &err)) {
        fputs(text, f.f);
        gr_file_commit(&f, &err);
    }
    cJSON_free(text);
    cJSON_Delete(j);
}

/* xi_m / m and zeta_m / m against m, one curve per combination of the other keys (Figs. 3.5, 3.11):
 * regroup exponents.csv into gnuplot index blocks and draw exponents.png. */
static void plot_exponents(const char *out)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/exponents.csv", out);
    FILE *in = fopen(path, "r");
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
        char *q = strstr(lines[i], "xi,") == lines[i] || strstr(lines[i], "zeta,") == lines[i] ? lines[i] : strstr(lines[i], ",xi,");
        if (!q) {
            q = strstr(lines[i], ",zeta,");
        }
        if (!q) {
            continue;
        }
        char key[160];
        snprintf(key, sizeof key, "%.*s%s", (int)(q - lines[i] < 140 ? q - lines[i] : 140), lines[i], strstr(q, "zeta") ? " zeta_m/m" : " xi_m/m");
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
    size_t len = (size_t)snprintf(body, sizeof body, "set xlabel 'm'\nset ylabel 'exponent / m'\nset key outside\n"
                                                      "set title 'xi_m/m (3.13) and zeta_m/m (3.20) from the sweep' noenhanced\nplot ");
    for (int b = 0; b < blocks && b < 64 && len < sizeof body; b++) {
        len += (size_t)snprintf(body + len, sizeof body - len, "%s'exponents_blocks.dat' index %d using 1:2:3 with yerrorlines title '%s' noenhanced",
                                b ? ", " : "", b, titles[b]);
    }
    char note[300];
    gr_plot_script(out, "exponents.png", body, note, sizeof note);
}

static int write_tables(const sweep *s, long n_points, const char *const *status)
{
    gr_error err = {0};
    gr_file f;
    if (gr_file_open(&f, s->out, "sweep.csv", &err)) {
        cli_error("sweep: %s", err.message);
        return EXIT_FAILED;
    }
    fprintf(f.f, "# granule sweep of %s: one row per point; moments <|v|^m> in (m/s)^m\npoint,seed", s->scene);
    for (int i = 0; i < s->n_keys; i++) {
        fprintf(f.f, ",%s", s->key[i]);
    }
    fprintf(f.f, ",status,T_mean,T_stderr,collisions,particle_steps_per_second");
    for (int m = 1; m <= 12; m++) {
        fprintf(f.f, ",m%d,m%d_stderr", m, m);
    }
    for (int m = 1; m <= 12; m++) {
        fprintf(f.f, ",R%d,R%d_stderr", m, m);
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
    double (*mom)[13] = calloc((size_t)n_points, sizeof *mom);
    double (*mom_err)[13] = calloc((size_t)n_points, sizeof *mom_err);
    double (*rmom)[13] = calloc((size_t)n_points, sizeof *rmom);
    double (*rmom_err)[13] = calloc((size_t)n_points, sizeof *rmom_err);
    for (long k = 0; k < n_points; k++) {
        int idx[MAX_KEYS] = {0}, seed;
        decode(s, k, idx, &seed);
        char dir[1200];
        snprintf(dir, sizeof dir, "%s/p%04ld", s->out, k);
        cJSON *j = gr_summary_read(dir, &err);
        fprintf(f.f, "%ld,%llu", k, s->seeds[seed]);
        for (int i = 0; i < n_col; i++) {
            fprintf(f.f, ",%s", s->value[i][idx[i]]);
        }
        fprintf(f.f, ",%s,%.8g,%.4g,%.0f,%.4g", status[k], gr_summary_number(j, "T_mean"), gr_summary_number(j, "T_stderr"),
                gr_summary_number(j, "collisions"), gr_summary_number(j, "particle_steps_per_second"));
        for (int m = 1; m <= 12; m++) {
            char p1[64], p2[64];
            snprintf(p1, sizeof p1, "analysis.moments.speed.m%d", m);
            snprintf(p2, sizeof p2, "analysis.moments.speed_stderr.m%d", m);
            mom[k][m] = gr_summary_number(j, p1);
            mom_err[k][m] = gr_summary_number(j, p2);
            if (m == 2 && isnan(mom[k][m]) && s->n_keys >= 0) {
                /* without the moments observable <v^2> is known only in 1D, where it equals T */
                const cJSON *sc = j ? cJSON_GetObjectItem(cJSON_GetObjectItem(j, "scene"), "system") : NULL;
                if (sc && gr_summary_number(sc, "dim") == 1.0) {
                    mom[k][m] = gr_summary_number(j, "T_mean");
                    mom_err[k][m] = gr_summary_number(j, "T_stderr");
                }
            }
            fprintf(f.f, ",%.8g,%.4g", mom[k][m], mom_err[k][m]);
            /* 1D neighbour separations <R^m> (3.18) from the gaps observable, for zeta_m (3.20) */
            snprintf(p1, sizeof p1, "analysis.gaps.moments.%d", m - 1);
            snprintf(p2, sizeof p2, "analysis.gaps.moments_stderr.%d", m - 1);
            rmom[k][m] = gr_summary_number(j, p1);
            rmom_err[k][m] = gr_summary_number(j, p2);
        }
        for (int m = 1; m <= 12; m++) {
            fprintf(f.f, ",%.8g,%.4g", rmom[k][m], rmom_err[k][m]);
        }
        fputc('\n', f.f);
        cJSON_Delete(j);
    }
    int rc = gr_file_commit(&f, &err);
    if (!rc && n_idx >= 0 && s->n_values[n_idx] >= 3) {
        /* xi_m: for each combination of the other keys, average the seeds at each N and fit
         * <|v|^m> = A N^-xi_m with the spread of the seeds (or the runs' own errors) as sigma */
        gr_file e;
        rc = gr_file_open(&e, s->out, "exponents.csv", &err);
        if (!rc) {
            fprintf(e.f, "# granule sweep: <|v|^m> = A N^-xi_m (3.8, 3.13) and <R^m> = A N^-zeta_m (3.20), per combination of the other keys\n");
            for (int i = 0; i < s->n_keys; i++) {
                if (i != n_idx) {
                    fprintf(e.f, "%s,", s->key[i]);
                }
            }
            fprintf(e.f, "quantity,m,exponent,exponent_error,A,chi2_red,points\n");
            long groups = 1;
            for (int i = 0; i < s->n_keys; i++) {
                groups *= i == n_idx ? 1 : s->n_values[i];
            }
            for (long gidx = 0; gidx < groups; gidx++) {
                /* the value index of each non-N key for this group */
                int gv[MAX_KEYS];
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
                    double(*val)[13] = q == 0 ? mom : rmom, (*verr)[13] = q == 0 ? mom_err : rmom_err;
                    double x[MAX_VALUES], y[MAX_VALUES], sig[MAX_VALUES];
                    int np = 0;
                    for (int v = 0; v < s->n_values[n_idx]; v++) {
                        double sum = 0.0, sum2 = 0.0, esum = 0.0;
                        int cnt = 0;
                        for (long k = 0; k < n_points; k++) {
                            int idx[MAX_KEYS] = {0}, seed;
                            decode(s, k, idx, &seed);
                            bool match = idx[n_idx] == v;
                            for (int i = 0; i < s->n_keys && match; i++) {
                                match = i == n_idx || idx[i] == gv[i];
                            }
                            if (match && isfinite(val[k][m])) {
                                sum += val[k][m];
                                sum2 += val[k][m] * val[k][m];
                                esum += isfinite(verr[k][m]) ? verr[k][m] * verr[k][m] : 0.0;
                                cnt++;
                            }
                        }
                        if (cnt > 0) {
                            double mean = sum / cnt;
                            double spread = cnt > 1 ? sqrt(fmax(sum2 / cnt - mean * mean, 0.0) / (cnt - 1)) : 0.0;
                            double own = sqrt(esum) / cnt;
                            x[np] = atof(s->value[n_idx][v]);
                            y[np] = mean;
                            sig[np] = fmax(spread, own);
                            np += sig[np] > 0.0;
                        }
                    }
                    gr_fit fit;
                    if (np >= 3 && gr_fit_power_law(x, y, sig, np, &fit, &err) == GR_OK) {
                        for (int i = 0; i < s->n_keys; i++) {
                            if (i != n_idx) {
                                fprintf(e.f, "%s,", s->value[i][gv[i]]);
                            }
                        }
                        fprintf(e.f, "%s,%d,%.6g,%.3g,%.6g,%.4g,%d\n", q == 0 ? "xi" : "zeta", m, -fit.p[1], fit.err[1],
                                fit.p[0], fit.chi2_red, np);
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
        cli_error("sweep: %s", err.message);
        return EXIT_FAILED;
    }
    return EXIT_OK;
}

int cmd_sweep(int argc, char **argv)
{
    const char *file = NULL;
    int jobs = 0;
    bool force = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--jobs") && i + 1 < argc) {
            jobs = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--force")) {
            force = true;
        } else if (argv[i][0] != '-' && !file) {
            file = argv[i];
        } else {
            cli_error("sweep: unexpected argument %s", argv[i]);
            return EXIT_REFUSED;
        }
    }
    if (!file) {
        usage(stderr);
        return EXIT_REFUSED;
    }
    sweep *s = calloc(1, sizeof *s);
    snprintf(s->out, sizeof s->out, "out/sweep");
    int bad = ini_parse(file, on_line, s);
    if (bad != 0 || s->error[0]) {
        if (bad < 0) {
            cli_error("sweep: %s: cannot open", file);
        } else {
            cli_error("sweep: %s:%d: %s", file, bad, s->error[0] ? s->error : "not an INI line");
        }
        free(s);
        return EXIT_REFUSED;
    }
    if (!s->scene[0]) {
        cli_error("sweep: %s: [sweep] scene is missing", file);
        free(s);
        return EXIT_REFUSED;
    }
    if (s->scene[0] != '/') { /* relative to the sweep file's folder */
        char copy[1024], joined[1100];
        snprintf(copy, sizeof copy, "%s", file);
        snprintf(joined, sizeof joined, "%.500s/%.500s", dirname(copy), s->scene);
        snprintf(s->scene, sizeof s->scene, "%.1010s", joined);
    }
    if (s->n_seeds == 0) {
        s->n_seeds = 1;
        s->seeds[0] = 1;
    }
    if (jobs > 0) {
        s->jobs = jobs;
    }
    if (s->jobs <= 0) {
        s->jobs = (int)sysconf(_SC_NPROCESSORS_ONLN);
    }
    long n_points = s->n_seeds;
    for (int i = 0; i < s->n_keys; i++) {
        n_points *= s->n_values[i];
    }
    if (n_points < 1 || n_points > 100000) {
        cli_error("sweep: %s: %ld points; between 1 and 100000 allowed", file, n_points);
        free(s);
        return EXIT_REFUSED;
    }
    /* validate every point's scene before running anything */
    for (long k = 0; k < n_points; k++) {
        char store[MAX_SETS + MAX_KEYS + 2][256];
        const char *ptrs[MAX_SETS + MAX_KEYS + 2];
        int m = point_overrides(s, k, store, ptrs);
        gr_scene sc;
        gr_error err = {0};
        if (gr_scene_load(&sc, s->scene, ptrs, m, &err)) {
            cli_error("sweep: point %ld: %s", k, err.message);
            free(s);
            return EXIT_REFUSED;
        }
    }
    gr_error err = {0};
    if (gr_output_dir_prepare(s->out, true, &err)) {
        cli_error("sweep: %s", err.message);
        free(s);
        return EXIT_FAILED;
    }
    const char **status = calloc((size_t)n_points, sizeof(char *));
    pid_t *pid_of = calloc((size_t)n_points, sizeof(pid_t));
    long next = 0, running = 0, done = 0, skipped = 0, failed = 0;
    fprintf(stderr, "sweep: %ld points (%d keys x %d seeds), %d parallel runs, into %s\n", n_points, s->n_keys, s->n_seeds, s->jobs, s->out);
    while (next < n_points || running > 0) {
        while (next < n_points && running < s->jobs) {
            long k = next++;
            char dir[1200];
            snprintf(dir, sizeof dir, "%s/p%04ld", s->out, k);
            if (!force && point_done(dir)) {
                status[k] = "completed";
                skipped++;
                continue;
            }
            if (gr_output_dir_prepare(dir, true, &err) == GR_OK) {
                write_manifest(s, k, dir);
            }
            fflush(NULL);
            pid_t pid = fork();
            if (pid == 0) {
                _exit(run_point(s, k, dir));
            }
            if (pid < 0) {
                status[k] = "failed";
                failed++;
                continue;
            }
            pid_of[k] = pid;
            running++;
        }
        if (running == 0) {
            break;
        }
        int ws;
        pid_t pid = wait(&ws);
        if (pid < 0) {
            break;
        }
        for (long k = 0; k < n_points; k++) {
            if (pid_of[k] == pid) {
                int code = WIFEXITED(ws) ? WEXITSTATUS(ws) : 1;
                status[k] = code == 0 ? "completed" : code == EXIT_UNSTABLE ? "unstable" : "failed";
                failed += code != 0;
                done++;
                pid_of[k] = 0;
                fprintf(stderr, "sweep: point %ld %s (%ld/%ld)\n", k, status[k], done + skipped, n_points);
            }
        }
        running--;
    }
    for (long k = 0; k < n_points; k++) {
        status[k] = status[k] ? status[k] : "failed";
    }
    int rc = write_tables(s, n_points, status);
    printf("%s/sweep.csv: %ld points, %ld run now, %ld already finished, %ld failed\n", s->out, n_points, done, skipped, failed);
    free(status);
    free(pid_of);
    free(s);
    return rc ? rc : (failed ? EXIT_FAILED : EXIT_OK);
}
