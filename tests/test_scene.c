/* Tests of scene loading (src/scene/scene.c), the time-step check of gr_sim_create and the run
 * driver's output-folder contract (src/app/run.c, src/io/files.c), through the public API.
 *
 * Every test writes its small INI files into a fresh folder made with mkdtemp and removes it at
 * the end. Refusals must return GR_EINVAL with a one-line message that names where the value came
 * from ("path:LINE:" or "--set section.key=value"), the [section] and key, and the allowed range
 * or choices (SPEC sec. 3 and 7, include/granule/scene.h). */
#include <check.h>
#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <glob.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/run.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "granule/status.h"
#include "scene/scene_json.h"
#include "check_main.h"

/* ---------- a fresh temporary folder per test ---------- */

static char g_root[240]; /* made by main before Check forks; removed at the end */
static char g_dir[256];
static int g_files;

static void setup(void)
{
    snprintf(g_dir, sizeof g_dir, "%s/test-XXXXXX", g_root);
    ck_assert_msg(mkdtemp(g_dir) != NULL, "mkdtemp: %s", strerror(errno));
    g_files = 0;
}

static void teardown(void)
{
    if (g_dir[0]) {
        gr_test_rm_tree(g_dir);
        g_dir[0] = 0;
    }
}

/* Write text to a new file in the test folder; returns its path (static storage, 8 slots). */
static const char *write_scene(const char *text)
{
    static char paths[8][512];
    char *p = paths[g_files % 8];
    snprintf(p, sizeof paths[0], "%s/scene%d.ini", g_dir, g_files++);
    FILE *f = fopen(p, "w");
    ck_assert_msg(f != NULL, "cannot write %s", p);
    fputs(text, f);
    fclose(f);
    return p;
}

static bool exists(const char *dir, const char *name)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return access(p, F_OK) == 0;
}

/* Names in dir containing `needle` (e.g. ".tmp"), or 0; the first one is copied to `first`. */
static int count_names(const char *dir, const char *needle, char *first, size_t n)
{
    DIR *d = opendir(dir);
    if (!d) {
        return 0;
    }
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (strstr(e->d_name, needle)) {
            if (count++ == 0 && first) {
                snprintf(first, n, "%s", e->d_name);
            }
        }
    }
    closedir(d);
    return count;
}

static void assert_no_temporaries(const char *dir)
{
    char name[300] = "";
    ck_assert_msg(count_names(dir, ".tmp", name, sizeof name) == 0, "temporary file left in %s: %s",
                  dir, name);
    ck_assert_msg(count_names(dir, ".granule-write-test", name, sizeof name) == 0,
                  "write probe left in %s: %s", dir, name);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    ck_assert_ptr_nonnull(buf);
    ck_assert_int_eq(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = 0;
    fclose(f);
    return buf;
}

/* A run recorded by an older granule (its scene JSON lacks keys added since, at their defaults)
 * ran the same physics; a changed value, a new key away from its default or a key granule no
 * longer has did not (sweeps and campaigns resume across versions, src/app/sweep_point.c). */
START_TEST(recorded_scene_compatibility)
{
    const char *path = write_scene(
        "[system]\ndim = 2\nN = 50\nL = 0.05\n[model]\ntangential = tangential_dashpot\n");
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, path, NULL, 0, &err) == GR_OK, "%s", err.message);
    char why[400] = "";
    cJSON *j = gr_scene_to_json(&s);
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    cJSON *rec = cJSON_Parse(text);
    ck_assert_msg(gr_scene_json_compatible(rec, &s, why, sizeof why), "%s", why);
    /* an older run: no rotation keys yet (they are at their defaults now), another output folder */
    cJSON *m = cJSON_GetObjectItem(rec, "model");
    cJSON_DeleteItemFromObject(m, "rotation");
    cJSON_DeleteItemFromObject(m, "inertia_factor");
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(rec, "output"), "dir",
                              cJSON_CreateString("elsewhere"));
    ck_assert_msg(gr_scene_json_compatible(rec, &s, why, sizeof why), "%s", why);
    /* the same older run against a scene that rotates: not the same physics */
    s.contact.rotation = true;
    ck_assert(!gr_scene_json_compatible(rec, &s, why, sizeof why));
    ck_assert_msg(strstr(why, "not its default"), "%s",
                  why); /* [placement] omega0 or [model] rotation */
    s.contact.rotation = false;
    /* a changed value */
    cJSON_ReplaceItemInObject(m, "eps_n", cJSON_CreateNumber(0.3));
    ck_assert(!gr_scene_json_compatible(rec, &s, why, sizeof why));
    ck_assert_msg(strstr(why, "[model] eps_n was 0.3"), "%s", why);
    /* a key granule no longer has */
    cJSON_ReplaceItemInObject(m, "eps_n", cJSON_CreateNumber(s.contact.eps_n));
    cJSON_AddNumberToObject(m, "warp", 9);
    ck_assert(!gr_scene_json_compatible(rec, &s, why, sizeof why));
    ck_assert_msg(strstr(why, "warp") && strstr(why, "no longer"), "%s", why);
    ck_assert(!gr_scene_json_compatible(NULL, &s, why, sizeof why));
    cJSON_Delete(rec);
    cJSON_free(text);
}
END_TEST

/* ---------- refusals ---------- */

/* Load `text` and require GR_EINVAL with "path:LINE:" for one of the given lines (line_b = 0:
 * only line_a) and every substring in the NULL-terminated list. */
static void expect_refused_at(const char *text, int line_a, int line_b, ...)
{
    const char *path = write_scene(text);
    gr_scene s;
    gr_error err = {0};
    int rc = gr_scene_load(&s, path, NULL, 0, &err);
    ck_assert_msg(rc == GR_EINVAL, "expected GR_EINVAL for\n%s\ngot %d (%s)", text, rc,
                  err.message);
    ck_assert_int_eq(err.code, GR_EINVAL);
    ck_assert_msg(strchr(err.message, '\n') == NULL, "message is not one line: '%s'", err.message);
    char loc_a[600], loc_b[600];
    snprintf(loc_a, sizeof loc_a, "%s:%d:", path, line_a);
    snprintf(loc_b, sizeof loc_b, "%s:%d:", path, line_b);
    bool at = strstr(err.message, loc_a) || (line_b > 0 && strstr(err.message, loc_b));
    if (line_b > 0) {
        ck_assert_msg(at, "message '%s' names neither '%s' nor '%s'", err.message, loc_a, loc_b);
    } else {
        ck_assert_msg(at, "message '%s' does not name '%s'", err.message, loc_a);
    }
    va_list ap;
    va_start(ap, line_b);
    for (const char *sub; (sub = va_arg(ap, const char *));) {
        ck_assert_msg(strstr(err.message, sub) != NULL, "message '%s' lacks '%s'", err.message,
                      sub);
    }
    va_end(ap);
}

START_TEST(refuse_unknown_key)
{
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "radious = 1e-3\n",
                      3, 0, "[system] radious", "unknown key", "radius", "packing_fraction",
                      (char *)NULL);
    /* a [model] key no model knows lists the models' parameters too */
    expect_refused_at("[model]\n"
                      "eps = 0.5\n",
                      2, 0, "[model] eps", "eps_n", "eps_t", "mu", (char *)NULL);
}
END_TEST

START_TEST(refuse_unknown_section)
{
    expect_refused_at("[system]\n"
                      "N = 10\n"
                      "\n"
                      "[modle]\n"
                      "eps_n = 0.5\n",
                      4, 0, "[modle]", "unknown section", "system", "placement", "model", "noise",
                      "integrator", "run", "output", (char *)NULL);
}
END_TEST

/* a misspelt section is refused even when no key follows it (inih reports keys only) */
START_TEST(refuse_empty_unknown_section)
{
    expect_refused_at("[system]\n"
                      "N = 10\n"
                      "[bogus]\n",
                      3, 0, "[bogus]", "unknown section", (char *)NULL);
}
END_TEST

/* a path the saved scene.ini would read back as a comment (fuzz finding: "dir =; text") */
START_TEST(refuse_path_read_back_as_comment)
{
    expect_refused_at("[output]\n"
                      "dir =; not a path\n",
                      2, 0, "[output] dir", "may not begin with ';'", (char *)NULL);
}
END_TEST

START_TEST(refuse_bad_number)
{
    expect_refused_at("[system]\n"
                      "radius = 1.5mm\n",
                      2, 0, "[system] radius", "1.5mm", "[1e-100, 1e+100]", (char *)NULL);
    expect_refused_at("[system]\n"
                      "N = 12.5\n",
                      2, 0, "[system] N", "[1, ", (char *)NULL);
    expect_refused_at("[run]\n"
                      "duration = nan\n",
                      2, 0, "[run] duration", "[0, inf)", (char *)NULL);
}
END_TEST

START_TEST(refuse_bad_boolean)
{
    expect_refused_at("[output]\n"
                      "plots = maybe\n",
                      2, 0, "[output] plots", "maybe", "true", "false", (char *)NULL);
    expect_refused_at("[model]\n"
                      "clamp = 2\n",
                      2, 0, "[model] clamp", "true", "false", (char *)NULL);
}
END_TEST

START_TEST(refuse_bad_choice)
{
    expect_refused_at("[placement]\n"
                      "kind = hexagon\n",
                      2, 0, "[placement] kind", "hexagon", "hexagonal", "square", "uniform",
                      "cluster", (char *)NULL);
    expect_refused_at("[noise]\n"
                      "D = 1e-8\n"
                      "mode = symmetric\n",
                      3, 0, "[noise] mode", "symmetric", "symmetrised", "com", "none",
                      (char *)NULL);
    expect_refused_at("[model]\n"
                      "normal = spring\n",
                      2, 0, "[model] normal", "spring_dashpot", (char *)NULL);
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "[model]\n"
                      "tangential = friction\n",
                      4, 0, "[model] tangential", "none", "tangential_dashpot", "sliding_friction",
                      (char *)NULL);
    /* a tangential law is not a normal law */
    expect_refused_at("[model]\n"
                      "normal = tangential_dashpot\n",
                      2, 0, "[model] normal", "spring_dashpot", (char *)NULL);
}
END_TEST

START_TEST(refuse_eps_n_out_of_range)
{
    expect_refused_at("[model]\n"
                      "k_s = 5e5\n"
                      "eps_n = 1.5\n",
                      3, 0, "[model] eps_n", "1.5", "[0, 1]", (char *)NULL);
    expect_refused_at("[model]\n"
                      "eps_n = -0.1\n",
                      2, 0, "[model] eps_n", "-0.1", "[0, 1]", (char *)NULL);
    /* the limits themselves are legal (SPEC sec. 2) */
    gr_scene s;
    gr_error err = {0};
    const char *p = write_scene("[model]\neps_n = 0\neps_t = 1\n");
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    p = write_scene("[model]\neps_n = 1\n");
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert(s.contact.eps_n == 1.0);
}
END_TEST

START_TEST(refuse_zero_particles)
{
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "N = 0\n",
                      3, 0, "[system] N", "[1, ", (char *)NULL);
}
END_TEST

START_TEST(refuse_duplicate_key)
{
    expect_refused_at("[system]\n"
                      "N = 10\n"
                      "L = 0.2\n"
                      "N = 20\n",
                      4, 0, "[system] N", "twice", (char *)NULL);
    /* the same key repeated in a second [system] block is still one file */
    expect_refused_at("[system]\n"
                      "N = 10\n"
                      "[run]\n"
                      "seed = 3\n"
                      "[system]\n"
                      "N = 20\n",
                      6, 0, "[system] N", "twice", (char *)NULL);
}
END_TEST

START_TEST(refuse_L_with_packing_fraction)
{
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "L = 0.2\n"
                      "packing_fraction = 0.3\n",
                      3, 4, "[system]", "packing_fraction", "L", (char *)NULL);
}
END_TEST

START_TEST(refuse_packing_fraction_in_1d)
{
    expect_refused_at("[system]\n"
                      "dim = 1\n"
                      "N = 10\n"
                      "packing_fraction = 0.3\n"
                      "[placement]\n"
                      "kind = uniform\n",
                      4, 0, "[system] packing_fraction", "dim = 2", (char *)NULL);
}
END_TEST

START_TEST(refuse_reduced_length_in_2d)
{
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "N = 10\n"
                      "reduced_length = 1.0\n",
                      4, 0, "[system] reduced_length", "dim = 1", (char *)NULL);
}
END_TEST

START_TEST(refuse_dt_with_steps_per_contact)
{
    expect_refused_at("[integrator]\n"
                      "dt = 1e-7\n"
                      "steps_per_contact = 40\n",
                      2, 3, "[integrator]", "dt", "steps_per_contact", (char *)NULL);
}
END_TEST

START_TEST(refuse_steps_per_contact_5)
{
    expect_refused_at("[integrator]\n"
                      "steps_per_contact = 5\n",
                      2, 0, "[integrator] steps_per_contact", "[10, ", (char *)NULL);
}
END_TEST

START_TEST(refuse_tangential_in_1d)
{
    expect_refused_at("[system]\n"
                      "dim = 1\n"
                      "N = 10\n"
                      "L = 1.0\n"
                      "[placement]\n"
                      "kind = uniform\n"
                      "[model]\n"
                      "tangential = tangential_dashpot\n",
                      8, 0, "[model] tangential", "none", (char *)NULL);
}
END_TEST

START_TEST(refuse_hexagonal_in_1d)
{
    expect_refused_at("[system]\n"
                      "dim = 1\n"
                      "N = 10\n"
                      "L = 1.0\n"
                      "[placement]\n"
                      "kind = hexagonal\n",
                      6, 0, "[placement] kind", "uniform", "cluster", (char *)NULL);
}
END_TEST

START_TEST(refuse_short_ring_1d)
{
    /* N d = 100 * 3e-3 = 0.3 m > L */
    expect_refused_at("[system]\n"
                      "dim = 1\n"
                      "N = 100\n"
                      "L = 0.2\n"
                      "[placement]\n"
                      "kind = uniform\n",
                      4, 3, "[system] L", "N d", (char *)NULL);
    /* a negative reduced length is out of the key's range */
    expect_refused_at("[system]\n"
                      "dim = 1\n"
                      "N = 100\n"
                      "reduced_length = -0.1\n"
                      "[placement]\n"
                      "kind = uniform\n",
                      4, 0, "[system] reduced_length", "[0, inf)", (char *)NULL);
}
END_TEST

START_TEST(refuse_packing_fraction_above_hexagonal)
{
    /* given directly: out of the key's range */
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "N = 100\n"
                      "packing_fraction = 0.95\n",
                      4, 0, "[system] packing_fraction", "0.9069", (char *)NULL);
    /* implied by N and L: 2000 pi (1.5e-3)^2 / 0.07^2 = 2.885 */
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "N = 2000\n"
                      "L = 0.07\n",
                      4, 3, "[system]", "0.9069", (char *)NULL);
}
END_TEST

/* ---------- --set overrides ---------- */

START_TEST(override_wins_over_file)
{
    const char *p = write_scene("[model]\n"
                                "eps_n = 0.3\n"
                                "[system]\n"
                                "N = 500\n");
    const char *sets[] = {"model.eps_n=0.8", "system.N=64", "run.seed=42"};
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, sets, 3, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.contact.eps_n, 0.8, 1e-15);
    ck_assert_int_eq(s.N, 64);
    ck_assert_uint_eq(s.seed, 42);
    /* and without the override the file's value holds */
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.contact.eps_n, 0.3, 1e-15);
    ck_assert_int_eq(s.N, 500);
}
END_TEST

/* Defaults that depend on dim follow it (issue 38): dim = 1 alone gets a uniform placement and a
 * 1 m reduced length; a hexagonal placement given in 1D is still refused, naming the key; 2D keeps
 * the hexagonal bed and the 0.2 m box. */
START_TEST(defaults_follow_dim)
{
    const char *p = write_scene("[system]\ndim = 1\n");
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(s.placement, GR_PLACE_UNIFORM);
    ck_assert_double_eq_tol(s.reduced_length, 1.0, 1e-12);
    ck_assert_double_eq_tol(s.L, 1.0 + s.N * 2.0 * s.radius, 1e-12);
    const char *dim1[] = {"system.dim=1"};
    ck_assert_msg(gr_scene_load(&s, NULL, dim1, 1, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(s.placement, GR_PLACE_UNIFORM);
    const char *dim1_L[] = {"system.dim=1", "system.N=10", "system.L=0.5"};
    ck_assert_msg(gr_scene_load(&s, NULL, dim1_L, 3, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.L, 0.5, 1e-15);
    const char *hex[] = {"system.dim=1", "placement.kind=hexagonal"};
    ck_assert_int_eq(gr_scene_load(&s, NULL, hex, 2, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "--set placement.kind=hexagonal") &&
                      strstr(err.message, "2D packing"),
                  "%s", err.message);
    const char *dim2[] = {"system.dim=2"};
    ck_assert_msg(gr_scene_load(&s, NULL, dim2, 1, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(s.placement, GR_PLACE_HEXAGONAL);
    ck_assert_double_eq_tol(s.L, 0.2, 1e-15);
}
END_TEST

START_TEST(override_bad_value_named)
{
    const char *p = write_scene("[model]\neps_n = 0.3\n");
    const char *sets[] = {"model.eps_n=2"};
    gr_scene s;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_load(&s, p, sets, 1, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "--set model.eps_n=2"),
                  "message '%s' lacks the --set argument", err.message);
    ck_assert_msg(strstr(err.message, "[0, 1]"), "message '%s' lacks the range", err.message);
    ck_assert_msg(strstr(err.message, "eps_n"), "message '%s' lacks the key", err.message);

    const char *unknown[] = {"system.radious=1e-3"};
    ck_assert_int_eq(gr_scene_load(&s, p, unknown, 1, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "--set system.radious=1e-3"), "message '%s'", err.message);
    ck_assert_msg(strstr(err.message, "radius"), "message '%s' lacks the known keys", err.message);

    /* overrides work without a file too */
    ck_assert_int_eq(gr_scene_load(&s, NULL, sets, 1, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "--set model.eps_n=2"), "message '%s'", err.message);
}
END_TEST

START_TEST(override_malformed_refused)
{
    const char *bad[] = {"modeleps_n=0.5", "model.eps_n", "model.eps_n 0.5",
                         "=0.5",           ".eps_n=0.5",  "model.=0.5"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        gr_scene s;
        gr_error err = {0};
        const char *one[] = {bad[i]};
        int rc = gr_scene_load(&s, NULL, one, 1, &err);
        ck_assert_msg(rc == GR_EINVAL, "--set '%s' accepted (rc %d)", bad[i], rc);
        ck_assert_msg(strstr(err.message, bad[i]), "message '%s' does not quote '%s'", err.message,
                      bad[i]);
        ck_assert_msg(strstr(err.message, "section.key=value"),
                      "message '%s' lacks the expected form", err.message);
    }
}
END_TEST

/* ---------- defaults and derived lengths ---------- */

START_TEST(defaults_table_2_2)
{
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, NULL, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.radius, 1.5e-3, 1e-18);
    ck_assert_double_eq_tol(s.mass, 3.53e-5, 1e-20);
    ck_assert_double_eq_tol(s.contact.k_s, 5e5, 1e-9);
    ck_assert_double_eq_tol(s.D, 1e-8, 1e-22);
    ck_assert_double_eq_tol(s.steps_per_contact, 50.0, 1e-12);
    ck_assert(s.dt == 0.0); /* derived from steps_per_contact by gr_sim_create */
    ck_assert_int_eq(s.noise_mode, GR_NOISE_SYMMETRISED);
    ck_assert_ptr_nonnull(s.normal);
    ck_assert_str_eq(s.normal->name, "spring_dashpot");
    ck_assert_str_eq(s.warnings, "");
    /* a file that names none of them leaves them at the defaults */
    const char *p = write_scene("; only a comment\n[run]\nseed = 7\n");
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.radius, 1.5e-3, 1e-18);
    ck_assert_double_eq_tol(s.mass, 3.53e-5, 1e-20);
    ck_assert_double_eq_tol(s.contact.k_s, 5e5, 1e-9);
    ck_assert_double_eq_tol(s.D, 1e-8, 1e-22);
    ck_assert_double_eq_tol(s.steps_per_contact, 50.0, 1e-12);
    ck_assert_uint_eq(s.seed, 7);
    ck_assert_str_eq(s.source, p);
}
END_TEST

START_TEST(packing_fraction_sets_L)
{
    const char *p = write_scene("[system]\n"
                                "dim = 2\n"
                                "N = 2000\n"
                                "radius = 1.5e-3\n"
                                "packing_fraction = 0.353\n");
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    double want = sqrt(2000.0 * M_PI * 1.5e-3 * 1.5e-3 / 0.353);
    ck_assert_double_eq_tol(s.L, want, 1e-12 * want);
    ck_assert_double_eq_tol(s.L, 0.2, 1e-3); /* the thesis's sec. 2.3.3 box */
    ck_assert_double_eq_tol(s.packing_fraction, 0.353, 1e-12);
}
END_TEST

START_TEST(reduced_length_sets_L)
{
    const char *p = write_scene("[system]\n"
                                "dim = 1\n"
                                "N = 100\n"
                                "reduced_length = 1.0\n"
                                "[placement]\n"
                                "kind = uniform\n");
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.L, 1.0 + 100 * 3e-3, 1e-12);
    ck_assert_double_eq_tol(s.reduced_length, 1.0, 1e-12);
    /* the reverse: L given, reduced length derived */
    p = write_scene("[system]\ndim = 1\nN = 100\nL = 2.0\n[placement]\nkind = cluster\n");
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_double_eq_tol(s.reduced_length, 2.0 - 0.3, 1e-12);
}
END_TEST

/* ---------- warnings ---------- */

START_TEST(unused_model_key_warns)
{
    const char *p = write_scene("[system]\n"
                                "dim = 2\n"
                                "[model]\n"
                                "tangential = tangential_dashpot\n"
                                "eps_t = 0.5\n"
                                "mu = 0.3\n");
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(strstr(s.warnings, "mu"), "warnings '%s' do not name mu", s.warnings);
    ck_assert_msg(strstr(s.warnings, "sliding_friction"),
                  "warnings '%s' do not name the owning model", s.warnings);
    ck_assert_msg(!strstr(s.warnings, "eps_t"),
                  "eps_t is used by tangential_dashpot, yet warned: '%s'", s.warnings);
    ck_assert_double_eq_tol(s.contact.mu, 0.3, 1e-15); /* accepted, just unused */
    /* a used key gives no warning */
    p = write_scene("[model]\ntangential = sliding_friction\nmu = 0.3\n");
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    ck_assert_str_eq(s.warnings, "");
    /* the same through --set */
    const char *sets[] = {"model.mu=0.2"};
    ck_assert_msg(gr_scene_load(&s, NULL, sets, 1, &err) == GR_OK, "%s", err.message);
    ck_assert_msg(strstr(s.warnings, "mu"), "warnings '%s' do not name mu (--set)", s.warnings);
}
END_TEST

/* ---------- time step check in gr_sim_create ---------- */

static void thesis_scene(gr_scene *s, const char *dt_line)
{
    char text[512];
    snprintf(text, sizeof text,
             "[system]\ndim = 2\nN = 100\nL = 0.2\n"
             "[model]\nk_s = 5e5\neps_n = 0.6\n"
             "[integrator]\n%s\n"
             "[run]\nprogress = false\n",
             dt_line);
    const char *p = write_scene(text);
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
}

START_TEST(sim_dt_1e6_accepted)
{
    gr_scene s;
    thesis_scene(&s, "dt = 1e-6");
    gr_sim *sim = NULL;
    gr_error err = {0};
    ck_assert_msg(gr_sim_create(&s, &sim, &err) == GR_OK, "dt = 1e-6 refused: %s", err.message);
    ck_assert_double_eq_tol(gr_sim_dt(sim), 1e-6, 1e-20);
    const gr_contact_coeffs *c = gr_sim_coeffs(sim);
    double steps = c->t_c / gr_sim_dt(sim);
    ck_assert_msg(steps > 17.0 && steps < 21.0, "t_c / dt = %g, expected ~19", steps);
    gr_sim_free(sim);
}
END_TEST

START_TEST(sim_dt_5e6_refused_unless_forced)
{
    gr_scene s;
    thesis_scene(&s, "dt = 5e-6");
    gr_sim *sim = NULL;
    gr_error err = {0};
    int rc = gr_sim_create(&s, &sim, &err);
    ck_assert_msg(rc == GR_EINVAL, "dt = 5e-6 (~4 steps per contact) accepted (rc %d)", rc);
    ck_assert_msg(strstr(err.message, "steps"), "message '%s' lacks 'steps'", err.message);
    ck_assert_msg(strstr(err.message, "force_dt"), "message '%s' does not say how to force it",
                  err.message);

    thesis_scene(&s, "dt = 5e-6\nforce_dt = true");
    ck_assert(s.force_dt);
    sim = NULL;
    ck_assert_msg(gr_sim_create(&s, &sim, &err) == GR_OK, "force_dt = true still refused: %s",
                  err.message);
    ck_assert_double_eq_tol(gr_sim_dt(sim), 5e-6, 1e-20);
    gr_sim_free(sim);
}
END_TEST

/* ---------- gr_run and the output folder ---------- */

/* A tiny 2D scene: N = 50 in a 5 cm box (phi ~ 0.14), 0.01 s, 11 samples, no plots. */
static void tiny_scene(gr_scene *s, const char *out_dir)
{
    char text[1600];
    snprintf(text, sizeof text,
             "[system]\ndim = 2\nN = 50\nL = 0.05\n"
             "[placement]\nkind = hexagonal\n"
             "[model]\neps_n = 0.6\n"
             "[run]\nwarmup = 0\nduration = 0.01\nsample_every = 1e-3\nseed = 3\nprogress = false\n"
             "[output]\ndir = %s\nplots = false\n",
             out_dir);
    const char *p = write_scene(text);
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
}

START_TEST(run_unwritable_folder)
{
    char file[400], out[500];
    snprintf(file, sizeof file, "%s/a_regular_file", g_dir);
    FILE *f = fopen(file, "w");
    ck_assert_ptr_nonnull(f);
    fputs("not a folder\n", f);
    fclose(f);
    snprintf(out, sizeof out, "%s/out", file);
    gr_scene s;
    tiny_scene(&s, out);
    gr_run_result res;
    gr_error err = {0};
    int rc = gr_run(&s, NULL, &res, &err);
    ck_assert_msg(rc == GR_EIO, "run into %s: rc %d (%s), expected GR_EIO", out, rc, err.message);
    ck_assert_msg(strstr(err.message, file), "message '%s' does not name the folder", err.message);
    ck_assert(!exists(out, "summary.json"));
    ck_assert(!exists(g_dir, "summary.json"));

    /* the output folder is itself a regular file */
    s = (gr_scene){0};
    tiny_scene(&s, file);
    rc = gr_run(&s, NULL, &res, &err);
    ck_assert_msg(rc == GR_EIO, "run into a regular file: rc %d (%s)", rc, err.message);
    ck_assert_msg(strstr(err.message, file), "message '%s' does not name the folder", err.message);
}
END_TEST

START_TEST(run_refused_scene_writes_nothing)
{
    /* L = 10.9 d: hexagonal rows hold 10 x 11 = 110 particles, yet phi(130) = 0.86 < 0.9069
     * passes the scene check: gr_sim_create must refuse the placement */
    char out[400];
    snprintf(out, sizeof out, "%s/refused", g_dir);
    char text[1200];
    snprintf(text, sizeof text,
             "[system]\ndim = 2\nN = 130\nL = 0.0327\n"
             "[placement]\nkind = hexagonal\n"
             "[run]\nwarmup = 0\nduration = 0.01\nprogress = false\n"
             "[output]\ndir = %s\nplots = false\n",
             out);
    const char *p = write_scene(text);
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&s, p, NULL, 0, &err) == GR_OK, "%s", err.message);
    gr_run_result res;
    int rc = gr_run(&s, NULL, &res, &err);
    ck_assert_msg(rc == GR_EINVAL, "over-full hexagonal placement: rc %d (%s)", rc, err.message);
    ck_assert_msg(strstr(err.message, "hexagonal"), "message '%s' does not name the placement",
                  err.message);
    ck_assert(!exists(out, "summary.json"));
    ck_assert(!exists(out, "temperature.csv"));
    ck_assert(!exists(out, "ledger.csv"));
    assert_no_temporaries(out);
    assert_no_temporaries(g_dir);

    /* an overlapping 1D cluster is refused at the scene level or by gr_sim_create */
    snprintf(out, sizeof out, "%s/refused1d", g_dir);
    snprintf(text, sizeof text,
             "[system]\ndim = 1\nN = 100\nL = 0.29\n[placement]\nkind = cluster\n"
             "[run]\nprogress = false\n[output]\ndir = %s\nplots = false\n",
             out);
    p = write_scene(text);
    rc = gr_scene_load(&s, p, NULL, 0, &err);
    if (rc == GR_OK) {
        rc = gr_run(&s, NULL, &res, &err);
    }
    ck_assert_int_eq(rc, GR_EINVAL);
    ck_assert(!exists(out, "summary.json"));
    assert_no_temporaries(out);
}
END_TEST

START_TEST(run_refuses_existing_summary_unless_forced)
{
    char out[400], summary[500];
    snprintf(out, sizeof out, "%s/done", g_dir);
    ck_assert_int_eq(mkdir(out, 0777), 0);
    snprintf(summary, sizeof summary, "%s/summary.json", out);
    FILE *f = fopen(summary, "w");
    ck_assert_ptr_nonnull(f);
    fputs("{\"marker\": \"earlier run\"}\n", f);
    fclose(f);

    gr_scene s;
    tiny_scene(&s, out);
    gr_run_result res;
    gr_error err = {0};
    gr_run_options opt = {.force = false};
    int rc = gr_run(&s, &opt, &res, &err);
    ck_assert_msg(rc != GR_OK, "run into a folder holding summary.json was not refused");
    ck_assert_msg(strstr(err.message, "summary.json") && strstr(err.message, "force"),
                  "message '%s' should name summary.json and --force", err.message);
    ck_assert_msg(strstr(err.message, out), "message '%s' does not name the folder", err.message);
    char *text = slurp(summary);
    ck_assert_msg(strstr(text, "earlier run"), "summary.json was touched: %s", text);
    free(text);
    ck_assert(!exists(out, "temperature.csv"));
    /* NULL options mean no force either */
    ck_assert_int_ne(gr_run(&s, NULL, &res, &err), GR_OK);

    opt.force = true;
    rc = gr_run(&s, &opt, &res, &err);
    ck_assert_msg(rc == GR_OK, "forced run failed: %s", err.message);
    text = slurp(summary);
    ck_assert_msg(!strstr(text, "earlier run"), "forced run did not replace summary.json");
    free(text);
    assert_no_temporaries(out);
}
END_TEST

/* A CSV that plain readers load: the column row starting `first` on the first line (no comments),
 * its notes in NAME.meta.json beside it. */
static int check_csv(const char *dir, const char *name, const char *first)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    char *text = slurp(path);
    ck_assert_msg(text[0] != '#', "%s starts with a '#' comment (pandas.read_csv would fail)",
                  name);
    char *line = text;
    char meta[600];
    snprintf(meta, sizeof meta, "%s/%.*s.meta.json", dir, (int)(strlen(name) - 4), name);
    char *notes = slurp(meta);
    ck_assert_msg(strstr(notes, "\"notes\"") && strstr(notes, "hash"), "%s lacks the notes: %s",
                  meta, notes);
    free(notes);
    ck_assert_msg(strncmp(line, first, strlen(first)) == 0,
                  "%s: column row '%.40s' should start '%s'", name, line, first);
    int rows = 0;
    for (char *q = strchr(line, '\n'); q && q[1]; q = strchr(q + 1, '\n')) {
        rows++;
    }
    free(text);
    return rows;
}

START_TEST(run_tiny_writes_outputs)
{
    char out[400];
    snprintf(out, sizeof out, "%s/tiny", g_dir);
    gr_scene s;
    tiny_scene(&s, out);
    gr_run_result res;
    gr_error err = {0};
    int rc = gr_run(&s, NULL, &res, &err);
    ck_assert_msg(rc == GR_OK, "tiny run failed (%d): %s", rc, err.message);
    ck_assert_int_eq(res.samples, 10);
    ck_assert(res.T_mean > 0.0 && isfinite(res.T_mean));

    char path[600];
    snprintf(path, sizeof path, "%s/summary.json", out);
    char *text = slurp(path);
    cJSON *j = cJSON_Parse(text);
    ck_assert_msg(j != NULL, "summary.json does not parse:\n%s", text);
    /* T_stderr needs >= 16 samples for block averaging (src/analysis/blocking.c); with fewer it is
     * JSON null (not available), never absent */
    cJSON *se = cJSON_GetObjectItemCaseSensitive(j, "T_stderr");
    ck_assert_msg(se != NULL, "summary.json: T_stderr missing");
    if (res.samples < 16) {
        ck_assert_msg(cJSON_IsNull(se) || cJSON_IsNumber(se),
                      "summary.json: T_stderr neither number nor null");
    } else {
        ck_assert_msg(cJSON_IsNumber(se),
                      "summary.json: T_stderr is not a number with %lld samples",
                      (long long)res.samples);
    }
    const char *numbers[] = {"T_mean",     "wall_seconds",    "particle_steps_per_second",
                             "collisions", "energy_injected", "energy_dissipated"};
    for (size_t i = 0; i < sizeof numbers / sizeof numbers[0]; i++) {
        cJSON *v = cJSON_GetObjectItemCaseSensitive(j, numbers[i]);
        ck_assert_msg(cJSON_IsNumber(v), "summary.json: %s missing or not a number", numbers[i]);
        ck_assert_msg(isfinite(v->valuedouble) && v->valuedouble >= 0.0, "summary.json: %s = %g",
                      numbers[i], v->valuedouble);
    }
    ck_assert_double_eq_tol(cJSON_GetObjectItemCaseSensitive(j, "T_mean")->valuedouble, res.T_mean,
                            1e-12 * res.T_mean);
    ck_assert(cJSON_GetObjectItemCaseSensitive(j, "particle_steps_per_second")->valuedouble > 0.0);
    ck_assert(cJSON_GetObjectItemCaseSensitive(j, "energy_injected")->valuedouble > 0.0);
    cJSON *kernel = cJSON_GetObjectItemCaseSensitive(j, "kernel");
    ck_assert_msg(cJSON_IsString(kernel) && kernel->valuestring[0],
                  "summary.json: kernel missing or empty");
    cJSON *scene = cJSON_GetObjectItemCaseSensitive(j, "scene");
    ck_assert_msg(cJSON_IsObject(scene), "summary.json: scene missing or not an object");
    ck_assert_msg(cJSON_GetArraySize(scene) > 0, "summary.json: scene is empty");
    cJSON *status = cJSON_GetObjectItemCaseSensitive(j, "status");
    ck_assert_msg(cJSON_IsString(status) && !strcmp(status->valuestring, "completed"),
                  "status is not 'completed'");
    cJSON_Delete(j);
    free(text);

    int rows_t = check_csv(out, "temperature.csv", "t,");
    int rows_l = check_csv(out, "ledger.csv", "t,");
    ck_assert_msg(rows_t == 11, "temperature.csv: %d rows, expected 11 (t = 0 .. 0.01 every 1e-3)",
                  rows_t);
    ck_assert_int_eq(rows_l, rows_t);
    assert_no_temporaries(out);
    ck_assert(!exists(out, "temperature.png")); /* plots = false */
}
END_TEST

START_TEST(run_stderr_with_enough_samples)
{
    /* 20 samples: enough for block averaging, so T_stderr must be a finite number */
    char out[400];
    snprintf(out, sizeof out, "%s/twenty", g_dir);
    gr_scene s;
    tiny_scene(&s, out);
    s.sample_every = 5e-4;
    gr_run_result res;
    gr_error err = {0};
    ck_assert_msg(gr_run(&s, NULL, &res, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(res.samples, 20);
    ck_assert_msg(isfinite(res.T_stderr) && res.T_stderr > 0.0, "T_stderr = %g with 20 samples",
                  res.T_stderr);
    char path[600];
    snprintf(path, sizeof path, "%s/summary.json", out);
    char *text = slurp(path);
    cJSON *j = cJSON_Parse(text);
    ck_assert_ptr_nonnull(j);
    cJSON *se = cJSON_GetObjectItemCaseSensitive(j, "T_stderr");
    ck_assert_msg(cJSON_IsNumber(se), "summary.json: T_stderr is not a number with 20 samples");
    ck_assert_double_eq_tol(se->valuedouble, res.T_stderr, 1e-9 * res.T_stderr);
    cJSON_Delete(j);
    free(text);
}
END_TEST

/* ---------- shipped scenes ---------- */

START_TEST(docs_scenes_load)
{
    const char *src = getenv("GRANULE_SOURCE_DIR");
    if (!src || !*src) {
        src = "/work/main";
    }
    char pattern[1200];
    snprintf(pattern, sizeof pattern, "%s/docs/scenes/*.ini", src);
    glob_t g;
    int rc = glob(pattern, 0, NULL, &g);
    if (rc == GLOB_NOMATCH || g.gl_pathc == 0) {
        fprintf(stderr,
                "test_scene: note: no scene files match %s; docs_scenes_load checked nothing\n",
                pattern);
        if (rc == 0) {
            globfree(&g);
        }
        return;
    }
    ck_assert_int_eq(rc, 0);
    for (size_t i = 0; i < g.gl_pathc; i++) {
        gr_scene s;
        gr_error err = {0};
        int r = gr_scene_load(&s, g.gl_pathv[i], NULL, 0, &err);
        ck_assert_msg(r == GR_OK, "%s does not load: %s", g.gl_pathv[i], err.message);
    }
    fprintf(stderr, "test_scene: %zu scene files under %s/docs/scenes load\n", g.gl_pathc, src);
    globfree(&g);
}
END_TEST

/* gr_scene_load_buffer (the fuzz targets' entry point) is gr_scene_load on text in memory: the
 * same scene, and refusals name the given name and line. */
START_TEST(load_buffer_matches_file)
{
    const char *text = "[system]\ndim = 1\nN = 10\nreduced_length = 0.5\n[placement]\nkind = "
                       "uniform\n[model]\neps_n = 0.3\n";
    const char *set[] = {"run.seed=7"};
    gr_scene a, b;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_load(&a, write_scene(text), set, 1, &err), GR_OK);
    ck_assert_int_eq(gr_scene_load_buffer(&b, "mem.ini", text, strlen(text), set, 1, &err), GR_OK);
    ck_assert_int_eq(b.N, 10);
    ck_assert(b.L == a.L && b.contact.eps_n == a.contact.eps_n && b.seed == 7 && a.seed == 7);
    ck_assert_str_eq(b.source, "mem.ini");
    /* not NUL-terminated: only len bytes are read (the cut leaves "N = 1") */
    ck_assert_int_eq(gr_scene_load_buffer(&b, "mem.ini", "[system]\nN = 12", 14, NULL, 0, &err),
                     GR_OK);
    ck_assert_int_eq(b.N, 1);
    ck_assert_int_eq(gr_scene_load_buffer(&b, "mem.ini", "", 0, NULL, 0, &err), GR_OK);
    const char *bad = "[system]\n\nN = many\n";
    ck_assert_int_eq(gr_scene_load_buffer(&b, "mem.ini", bad, strlen(bad), NULL, 0, &err),
                     GR_EINVAL);
    ck_assert_msg(strstr(err.message, "mem.ini:3:") && strstr(err.message, "[system] N"), "%s",
                  err.message);
}
END_TEST

/* Issue 14: inih split lines longer than 197 characters and read the tail as a new line; a NUL
 * cut a value short; a comments-only scene ran the defaults. */
START_TEST(lines_read_whole)
{
    char text[1200], dir[600];
    memset(dir, 'd', sizeof dir);
    dir[sizeof dir - 1] = 0;
    /* a long comment whose tail looks like a key is a comment */
    snprintf(text, sizeof text, "[system]\ndim = 2\n; %0197d seed = 42\n", 0);
    gr_scene s;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load_whole(&s, write_scene(text), NULL, 0, &err) == GR_OK, "%s",
                  err.message);
    ck_assert(s.seed == 1);
    /* a long value is read whole (inline comment removed), and the next line keeps its number */
    snprintf(text, sizeof text, "[system]\ndim = 2\n[output]\ndir = %s ; a comment\nplots = 1x\n",
             dir);
    char p[700];
    snprintf(p, sizeof p, "%s", write_scene(text));
    snprintf(text, sizeof text, "[system]\ndim = 2\n[output]\ndir = %s ; a comment\n", dir);
    ck_assert_msg(gr_scene_load_whole(&s, write_scene(text), NULL, 0, &err) == GR_OK, "%s",
                  err.message);
    ck_assert_str_eq(s.out_dir, dir);
    char at[800];
    snprintf(at, sizeof at, "%s:5:", p);
    ck_assert_int_eq(gr_scene_load_whole(&s, p, NULL, 0, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, at) && strstr(err.message, "plots"), "%s", err.message);
    /* a NUL byte or another control byte is refused at its line */
    const char nul[] = "[system]\ndim = 2\nN = 5\0000\n";
    ck_assert_int_eq(gr_scene_load_buffer(&s, "nul.ini", nul, sizeof nul - 1, NULL, 0, &err),
                     GR_EINVAL);
    ck_assert_msg(strstr(err.message, "nul.ini:3:") && strstr(err.message, "control byte 0x00"),
                  "%s", err.message);
    /* a whole scene needs content and a [system] section; a folder is not a scene */
    ck_assert_int_eq(gr_scene_load_whole(&s, write_scene("; only a comment\n"), NULL, 0, &err),
                     GR_EINVAL);
    ck_assert_msg(strstr(err.message, "empty"), "%s", err.message);
    ck_assert_int_eq(gr_scene_load_whole(&s, write_scene("[run]\nseed = 3\n"), NULL, 0, &err),
                     GR_EINVAL);
    ck_assert_msg(strstr(err.message, "[system]"), "%s", err.message);
    ck_assert_int_eq(gr_scene_load_whole(&s, g_dir, NULL, 0, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "not a regular file"), "%s", err.message);
}
END_TEST

/* Found while fuzzing: seeds were read with strtoull after a strtod range check, so "1e3" ran
 * with seed 1, "0x10" with seed 0 and 2^64 with 2^64 - 1, silently. */
START_TEST(refuse_seed_not_digits)
{
    expect_refused_at("[run]\nseed = 1e3\n", 2, 0, "[run] seed", "decimal digits", (char *)NULL);
    expect_refused_at("[run]\nseed = 0x10\n", 2, 0, "[run] seed", "decimal digits", (char *)NULL);
    expect_refused_at("[run]\n\nseed = 18446744073709551616\n", 3, 0, "[run] seed", (char *)NULL);
    const char *ok = "[run]\nseed = 18446744073709551615\n";
    gr_scene sc;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_load_buffer(&sc, "seed.ini", ok, strlen(ok), NULL, 0, &err), GR_OK);
    ck_assert(sc.seed == UINT64_MAX);
}
END_TEST

/* Found by tests/fuzz: a box of more than 1e9 diameters overflowed int lattice indices (UB; the
 * release build then claimed the box was "narrower than a particle"). Refused by name now. */
START_TEST(refuse_box_beyond_1e9_diameters)
{
    expect_refused_at("[system]\n"
                      "dim = 2\n"
                      "N = 12\n"
                      "L = 9103232\n",
                      4, 0, "[system] L", "particle diameters", "1e9", (char *)NULL);
}
END_TEST

/* Found by tests/fuzz: random placement in a dilute box allocated (L/d)^2 grid cells (L = 200 m:
 * 4e9 cells, an int overflow and a crash); the grid is now O(N). */
START_TEST(sim_random_placement_dilute_box)
{
    const char *text = "[system]\ndim = 2\nN = 32\nL = 200\n[placement]\nkind = random\n";
    gr_scene sc;
    gr_error err = {0};
    ck_assert_int_eq(gr_scene_load_buffer(&sc, "dilute.ini", text, strlen(text), NULL, 0, &err),
                     GR_OK);
    gr_sim *sim = NULL;
    ck_assert_msg(gr_sim_create(&sc, &sim, &err) == GR_OK, "%s", err.message);
    gr_particles p = gr_sim_particles(sim);
    for (int i = 0; i < p.n; i++) {
        ck_assert(p.x[i] >= 0.0 && p.x[i] < sc.L && p.y[i] >= 0.0 && p.y[i] < sc.L);
        for (int j = 0; j < i; j++) {
            double dx = fabs(p.x[i] - p.x[j]), dy = fabs(p.y[i] - p.y[j]);
            dx = fmin(dx, sc.L - dx);
            dy = fmin(dy, sc.L - dy);
            ck_assert(dx * dx + dy * dy >= 4.0 * sc.radius * sc.radius);
        }
    }
    gr_sim_free(sim);
}
END_TEST

static Suite *scene_suite(void)
{
    Suite *s = suite_create("scene");
    TCase *refuse = tcase_create("refuse");
    tcase_add_checked_fixture(refuse, setup, teardown);
    tcase_add_test(refuse, refuse_unknown_key);
    tcase_add_test(refuse, refuse_unknown_section);
    tcase_add_test(refuse, refuse_empty_unknown_section);
    tcase_add_test(refuse, refuse_path_read_back_as_comment);
    tcase_add_test(refuse, refuse_bad_number);
    tcase_add_test(refuse, refuse_bad_boolean);
    tcase_add_test(refuse, refuse_bad_choice);
    tcase_add_test(refuse, refuse_eps_n_out_of_range);
    tcase_add_test(refuse, refuse_zero_particles);
    tcase_add_test(refuse, refuse_duplicate_key);
    tcase_add_test(refuse, refuse_L_with_packing_fraction);
    tcase_add_test(refuse, refuse_packing_fraction_in_1d);
    tcase_add_test(refuse, refuse_reduced_length_in_2d);
    tcase_add_test(refuse, refuse_dt_with_steps_per_contact);
    tcase_add_test(refuse, refuse_steps_per_contact_5);
    tcase_add_test(refuse, refuse_tangential_in_1d);
    tcase_add_test(refuse, refuse_hexagonal_in_1d);
    tcase_add_test(refuse, refuse_short_ring_1d);
    tcase_add_test(refuse, refuse_packing_fraction_above_hexagonal);
    tcase_add_test(refuse, refuse_box_beyond_1e9_diameters);
    tcase_add_test(refuse, refuse_seed_not_digits);
    tcase_add_test(refuse, lines_read_whole);
    suite_add_tcase(s, refuse);

    TCase *load = tcase_create("load");
    tcase_add_checked_fixture(load, setup, teardown);
    tcase_add_test(load, override_wins_over_file);
    tcase_add_test(load, override_bad_value_named);
    tcase_add_test(load, defaults_follow_dim);
    tcase_add_test(load, override_malformed_refused);
    tcase_add_test(load, defaults_table_2_2);
    tcase_add_test(load, packing_fraction_sets_L);
    tcase_add_test(load, reduced_length_sets_L);
    tcase_add_test(load, unused_model_key_warns);
    tcase_add_test(load, docs_scenes_load);
    tcase_add_test(load, load_buffer_matches_file);
    tcase_add_test(load, recorded_scene_compatibility);
    suite_add_tcase(s, load);

    TCase *sim = tcase_create("sim");
    tcase_add_checked_fixture(sim, setup, teardown);
    tcase_add_test(sim, sim_dt_1e6_accepted);
    tcase_add_test(sim, sim_dt_5e6_refused_unless_forced);
    tcase_add_test(sim, sim_random_placement_dilute_box);
    suite_add_tcase(s, sim);

    TCase *run = tcase_create("run");
    tcase_add_checked_fixture(run, setup, teardown);
    tcase_set_timeout(run, 120);
    tcase_add_test(run, run_unwritable_folder);
    tcase_add_test(run, run_refused_scene_writes_nothing);
    tcase_add_test(run, run_refuses_existing_summary_unless_forced);
    tcase_add_test(run, run_tiny_writes_outputs);
    tcase_add_test(run, run_stderr_with_enough_samples);
    suite_add_tcase(s, run);
    return s;
}

int main(void)
{
    /* one root for every test's folder, so a failing test (whose teardown Check skips) leaves
     * nothing behind either; GRANULE_KEEP_TMP=1 keeps it for inspection */
    if (gr_test_tmp_root(g_root, sizeof g_root, "test_scene", "scene") != 0) {
        return EXIT_FAILURE;
    }
    int status = gr_test_run(scene_suite());
    gr_test_tmp_root_done(g_root, "test_scene");
    return status;
}
