/* The sweep file ([sweep], [vary], [set]) and its points: point k is one combination of the
 * varied values and one seed, numbered from 0 with the seed fastest, then the last [vary] key. */
#include <dirent.h>
#include <errno.h>
#include <ini.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/report.h"
#include "app/sweep.h"
#include "io/files.h"
#include "scene/scene_lines.h"

/* Split a comma/blank separated list into out[0..max); -1 when a value is longer than
 * SWEEP_VALUE_LEN - 1 characters or there are more than max values (nothing is cut silently). */
static int split_list(const char *text, char out[][SWEEP_VALUE_LEN], int max)
{
    char buf[4096];
    if (strlen(text) >= sizeof buf) {
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", text);
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        if (n == max || strlen(tok) >= SWEEP_VALUE_LEN) {
            return -1;
        }
        snprintf(out[n++], SWEEP_VALUE_LEN, "%s", tok);
    }
    return n;
}

/* A seed: decimal digits only (no sign, hex, exponent or blanks), within 64 bits. */
static bool parse_seed(const char *text, unsigned long long *seed)
{
    if (!*text || strspn(text, "0123456789") != strlen(text) || strlen(text) > 20) {
        return false;
    }
    errno = 0;
    *seed = strtoull(text, NULL, 10);
    return errno == 0;
}

/* Index of [vary] or [set] key `name` so far, or -1. */
static int find_key(const sweep *s, const char *name)
{
    for (int i = 0; i < s->n_keys; i++) {
        if (!strcmp(s->key[i], name)) {
            return i;
        }
    }
    return -1;
}

static int find_set(const sweep *s, const char *name)
{
    const size_t n = strlen(name);
    for (int i = 0; i < s->n_sets; i++) {
        if (!strncmp(s->set[i], name, n) && s->set[i][n] == '=') {
            return i;
        }
    }
    return -1;
}

static int on_line(void *user, const char *section, const char *name, const char *value)
{
    sweep *s = user;
    if (s->error
            [0]) { /* inih goes on after an error and reports the first one's line: keep its message */
        return 0;
    }
    if (strlen(name) >= sizeof s->key[0]) {
        snprintf(s->error, sizeof s->error, "[%s] %.60s...: a key name of at most %zu characters",
                 section, name, sizeof s->key[0] - 1);
        return 0;
    }
    if (!strcmp(section, "sweep")) {
        if (!strcmp(name, "scene")) {
            snprintf(s->scene, sizeof s->scene, "%s", value);
        } else if (!strcmp(name, "out")) {
            snprintf(s->out, sizeof s->out, "%s", value);
        } else if (!strcmp(name, "jobs")) {
            char *end;
            long j = strtol(value, &end, 10);
            if (*end || j < 1 || j > 4096) {
                snprintf(s->error, sizeof s->error,
                         "[sweep] jobs = %s: expected an integer in 1..4096", value);
                return 0;
            }
            s->jobs = (int)j;
        } else if (!strcmp(name, "seeds")) {
            char v[SWEEP_MAX_VALUES][SWEEP_VALUE_LEN];
            s->n_seeds = split_list(value, v, SWEEP_MAX_VALUES);
            if (s->n_seeds < 0) {
                snprintf(s->error, sizeof s->error,
                         "[sweep] seeds: at most %d seeds of at most %d characters",
                         SWEEP_MAX_VALUES, SWEEP_VALUE_LEN - 1);
                return 0;
            }
            if (s->seeds_given) {
                snprintf(s->error, sizeof s->error,
                         "[sweep] seeds: given twice; list every seed on one line");
                return 0;
            }
            s->seeds_given = true;
            for (int i = 0; i < s->n_seeds; i++) {
                if (!parse_seed(v[i], &s->seeds[i])) {
                    snprintf(s->error, sizeof s->error,
                             "[sweep] seeds: '%.64s' is not an integer written in decimal digits "
                             "(0 .. 2^64 - 1)",
                             v[i]);
                    return 0;
                }
                for (int j = 0; j < i; j++) {
                    if (s->seeds[j] == s->seeds[i]) {
                        snprintf(
                            s->error, sizeof s->error,
                            "[sweep] seeds: %llu is listed twice (two points would be one run)",
                            s->seeds[i]);
                        return 0;
                    }
                }
            }
        } else {
            snprintf(s->error, sizeof s->error,
                     "[sweep] %s: unknown key; keys: scene, out, seeds, jobs", name);
            return 0;
        }
    } else if (!strcmp(section, "vary")) {
        /* a list longer than a line continues on a line that repeats the key */
        const bool more = s->n_keys > 0 && !strcmp(s->key[s->n_keys - 1], name);
        if (!more && find_key(s, name) >= 0) {
            snprintf(
                s->error, sizeof s->error,
                "[vary] %s: given twice; a list longer than a line continues on the very next line",
                name);
            return 0;
        }
        if (!more && strchr(name, '+') && gr_linked_key_names(name, "run.seed")) {
            snprintf(
                s->error, sizeof s->error,
                "[vary] %s: run.seed cannot be linked to other keys; vary it on a line of its own",
                name);
            return 0;
        }
        if (find_set(s, name) >= 0) {
            snprintf(s->error, sizeof s->error,
                     "[vary] %s: also in [set]; a key is either set or varied", name);
            return 0;
        }
        if (more) {
            s->n_keys--;
        } else if (s->n_keys == SWEEP_MAX_KEYS) {
            snprintf(s->error, sizeof s->error, "[vary]: at most %d keys", SWEEP_MAX_KEYS);
            return 0;
        }
        const int had = more ? s->n_values[s->n_keys] : 0;
        snprintf(s->key[s->n_keys], 128, "%s", name);
        const int got = split_list(value, s->value[s->n_keys] + had, SWEEP_MAX_VALUES - had);
        if (got <= 0 || !strchr(name, '.')) {
            snprintf(s->error, sizeof s->error,
                     "[vary] %s: expected section.key = v1, v2, ... (at most %d values in all, "
                     "each at most %d characters)",
                     name, SWEEP_MAX_VALUES, SWEEP_VALUE_LEN - 1);
            return 0;
        }
        s->n_values[s->n_keys] = had + got;
        for (int v = had; v < had + got;
             v++) { /* a varied value listed twice would be one point twice */
            for (int u = 0; u < v; u++) {
                if (!strcmp(s->value[s->n_keys][u], s->value[s->n_keys][v])) {
                    snprintf(s->error, sizeof s->error, "[vary] %s: value '%s' is listed twice",
                             name, s->value[s->n_keys][v]);
                    return 0;
                }
            }
        }
        if (!strcmp(name, "run.seed")) {
            unsigned long long seed;
            for (int v = had; v < had + got; v++) {
                if (!parse_seed(s->value[s->n_keys][v], &seed)) {
                    snprintf(s->error, sizeof s->error,
                             "[vary] run.seed: '%.64s' is not an integer written in decimal digits "
                             "(0 .. 2^64 - 1)",
                             s->value[s->n_keys][v]);
                    return 0;
                }
            }
        }
        /* linked keys, varied together: system.N+system.packing_fraction = 1000/0.177, 2000/0.353 */
        int parts = 1;
        for (const char *c = name; *c; c++) {
            parts += *c == '+';
        }
        for (int v = had; v < s->n_values[s->n_keys]; v++) {
            int n_parts = 1;
            for (const char *c = s->value[s->n_keys][v]; *c; c++) {
                n_parts += *c == '/';
            }
            if (n_parts != parts || parts > SWEEP_MAX_LINKED) {
                snprintf(s->error, sizeof s->error,
                         "[vary] %s: value '%s' has %d part%s for %d linked key%s (at most %d, "
                         "written a+b = 1/2, 3/4)",
                         name, s->value[s->n_keys][v], n_parts, n_parts == 1 ? "" : "s", parts,
                         parts == 1 ? "" : "s", SWEEP_MAX_LINKED);
                return 0;
            }
        }
        s->n_keys++;
    } else if (!strcmp(section, "set")) {
        if (s->n_sets == SWEEP_MAX_SETS || !strchr(name, '.')) {
            snprintf(s->error, sizeof s->error,
                     "[set] %s: expected section.key = value (at most %d lines)", name,
                     SWEEP_MAX_SETS);
            return 0;
        }
        if (find_set(s, name) >= 0) {
            snprintf(s->error, sizeof s->error, "[set] %s: given twice", name);
            return 0;
        }
        for (int i = 0; i < s->n_keys; i++) {
            if (gr_linked_key_names(s->key[i], name)) {
                snprintf(s->error, sizeof s->error,
                         "[set] %s: also varied in [vary] %s; a key is either set or varied", name,
                         s->key[i]);
                return 0;
            }
        }
        if (!strcmp(name, "run.seed")) {
            snprintf(s->error, sizeof s->error,
                     "[set] run.seed: the seeds are [sweep] seeds (or [vary] run.seed), not [set]");
            return 0;
        }
        if (strlen(name) + strlen(value) + 2 > sizeof s->set[0]) {
            snprintf(s->error, sizeof s->error,
                     "[set] %s: name and value of at most %zu characters", name,
                     sizeof s->set[0] - 2);
            return 0;
        }
        snprintf(s->set[s->n_sets++], sizeof s->set[0], "%s=%s", name, value);
    } else {
        snprintf(s->error, sizeof s->error, "[%s]: unknown section; sections: sweep, vary, set",
                 section);
        return 0;
    }
    return 1;
}

int sweep_load(sweep *s, const char *file)
{
    snprintf(s->file, sizeof s->file, "%s", file);
    snprintf(s->out, sizeof s->out, "out/sweep");
    int why = 0;
    FILE *in = gr_input_fopen(file, &why);
    if (!in) {
        if (why < 0) {
            app_error("sweep: %s: not a regular file (a sweep file is an INI file; a folder, FIFO, "
                      "device or socket is refused)",
                      file);
        } else {
            app_error("sweep: %s: cannot open: %s", file, strerror(why));
        }
        return EXIT_REFUSED;
    }
    /* the scene reader's lines: control bytes (NUL included), long lines and headers checked alike */
    gr_line_reader lines = {.f = in, .what = "sweep file", .sections = "sweep, vary, set"};
    int bad = gr_line_parse(&lines, on_line, s);
    fclose(in);
    if (bad != 0 || s->error[0]) {
        if (bad < 0) {
            app_error("sweep: %s: cannot read", file);
        } else {
            app_error("sweep: %s:%d: %s", file, bad,
                      lines.problem[0] ? lines.problem
                      : s->error[0]    ? s->error
                                       : "not an INI line");
        }
        gr_line_reader_free(&lines);
        return EXIT_REFUSED;
    }
    gr_line_reader_free(&lines);
    s->seed_key = find_key(s, "run.seed");
    if (s->seed_key >= 0 && s->seeds_given) {
        app_error(
            "sweep: %s: seeds are given twice, by [sweep] seeds and by [vary] run.seed; keep one",
            file);
        return EXIT_REFUSED;
    }
    if (!s->scene[0]) {
        app_error("sweep: %s: [sweep] scene is missing", file);
        return EXIT_REFUSED;
    }
    if (s->scene[0] != '/') { /* relative to the sweep file's folder */
        char copy[1024], joined[1100];
        snprintf(copy, sizeof copy, "%s", file);
        snprintf(joined, sizeof joined, "%.500s/%.500s", dirname(copy), s->scene);
        snprintf(s->scene, sizeof s->scene, "%.1010s", joined);
    }
    if (s->n_seeds == 0) { /* one seed per point: 1, or the point's [vary] run.seed */
        s->n_seeds = 1;
        s->seeds[0] = 1;
    }
    s->n_points = s->n_seeds;
    for (int i = 0; i < s->n_keys; i++) {
        s->n_points *= s->n_values[i];
        if (s->n_points > SWEEP_MAX_POINTS) {
            break;
        }
    }
    if (s->n_points < 1 || s->n_points > SWEEP_MAX_POINTS) {
        app_error("sweep: %s: more than %ld points (keys x seeds); between 1 and %ld allowed", file,
                  SWEEP_MAX_POINTS, SWEEP_MAX_POINTS);
        return EXIT_REFUSED;
    }
    return EXIT_OK;
}

void sweep_decode(const sweep *s, long k, int idx[SWEEP_MAX_KEYS], int *seed)
{
    *seed = (int)(k % s->n_seeds);
    k /= s->n_seeds;
    for (int i = s->n_keys - 1; i >= 0; i--) {
        idx[i] = (int)(k % s->n_values[i]);
        k /= s->n_values[i];
    }
}

unsigned long long sweep_point_seed(const sweep *s, long k)
{
    int idx[SWEEP_MAX_KEYS] = {0}, seed;
    sweep_decode(s, k, idx, &seed);
    if (s->seed_key >= 0) {
        return strtoull(s->value[s->seed_key][idx[s->seed_key]], NULL,
                        10); /* checked by parse_seed */
    }
    return s->seeds[seed];
}

int sweep_overrides(const sweep *s, long k, char store[][256], const char **ptrs)
{
    int idx[SWEEP_MAX_KEYS] = {0}, seed, m = 0;
    sweep_decode(s, k, idx, &seed);
    for (int i = 0; i < s->n_sets; i++) {
        snprintf(store[m], 256, "%s", s->set[i]);
        ptrs[m] = store[m];
        m++;
    }
    for (int i = 0; i < s->n_keys; i++) { /* a+b = x/y gives a=x and b=y */
        char keys[128], values[SWEEP_VALUE_LEN], *ks = NULL, *vs = NULL;
        snprintf(keys, sizeof keys, "%s", s->key[i]);
        snprintf(values, sizeof values, "%s", s->value[i][idx[i]]);
        char *key = strtok_r(keys, "+", &ks), *value = strtok_r(values, "/", &vs);
        for (; key && value; key = strtok_r(NULL, "+", &ks), value = strtok_r(NULL, "/", &vs)) {
            snprintf(store[m], 256, "%s=%s", key, value);
            ptrs[m] = store[m];
            m++;
        }
    }
    if (s->seed_key >= 0) { /* run.seed is one of the varied keys above */
        return m;
    }
    snprintf(store[m], 256, "run.seed=%llu", s->seeds[seed]);
    ptrs[m] = store[m];
    return m + 1;
}

int sweep_point_scene(const sweep *s, long k, gr_scene *sc, gr_error *err)
{
    char store[SWEEP_MAX_OVERRIDES][256];
    const char *ptrs[SWEEP_MAX_OVERRIDES];
    int m = sweep_overrides(s, k, store, ptrs);
    return gr_scene_load_whole(sc, s->scene, ptrs, m,
                               err); /* an empty or sectionless scene is refused */
}

void sweep_point_dir(const sweep *s, long k, char *dir, size_t len)
{
    snprintf(dir, len, "%.1000s/p%04ld", s->out, k);
}

void sweep_list(const sweep *s, FILE *f)
{
    fprintf(f,
            "# %s: %ld points (0 .. %ld), into %s/pNNNN; a batch array of them: --array=0-%ld "
            "(SLURM)\n",
            s->file, s->n_points, s->n_points - 1, s->out, s->n_points - 1);
    fprintf(f, "# point");
    for (int i = 0; i < s->n_keys; i++) {
        fprintf(f, " %s", s->key[i]);
    }
    fprintf(f, s->seed_key < 0 ? " run.seed\n" : "\n");
    for (long k = 0; k < s->n_points; k++) {
        int idx[SWEEP_MAX_KEYS] = {0}, seed;
        sweep_decode(s, k, idx, &seed);
        fprintf(f, "%ld", k);
        for (int i = 0; i < s->n_keys; i++) {
            fprintf(f, " %s=%s", s->key[i], s->value[i][idx[i]]);
        }
        if (s->seed_key < 0) {
            fprintf(f, " run.seed=%llu", s->seeds[seed]);
        }
        fprintf(f, "\n");
    }
}

int sweep_foreign_points(const sweep *s, bool force, char *why, size_t len)
{
    why[0] = 0;
    DIR *d = opendir(s->out);
    if (!d) {
        return 0; /* a new folder */
    }
    long lo = -1, hi = -1, n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *name = e->d_name;
        if (name[0] != 'p' || strlen(name) < 5 ||
            strspn(name + 1, "0123456789") != strlen(name + 1)) {
            continue;
        }
        const long k = atol(name + 1);
        if (k < s->n_points) {
            continue;
        }
        char path[1400];
        snprintf(path, sizeof path, "%s/%s", s->out, name);
        gr_error err = {0};
        if (force && gr_output_dir_remove(path, &err)) {
            snprintf(why, len, "%.700s (a point of another sweep)", err.message);
            closedir(d);
            return -1;
        }
        lo = lo < 0 || k < lo ? k : lo;
        hi = k > hi ? k : hi;
        n++;
    }
    closedir(d);
    if (n && !force) {
        snprintf(why, len,
                 "%.600s holds %ld point folder%s (p%04ld..p%04ld) beyond this sweep's %ld points: "
                 "they come from "
                 "another sweep file; choose another folder, or pass --force to delete them",
                 s->out, n, n == 1 ? "" : "s", lo, hi, s->n_points);
        return -1;
    }
    return (int)n;
}
