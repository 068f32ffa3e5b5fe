/* Tests of granule compare's library part (include/granule/compare.h, src/app/compare*.c):
 * the model SPECs and their refusals, "value +- error" formatting, the headline table's cells and
 * the reason that replaces every missing number (from hand-written summaries with a known
 * answer), real tiny runs of one scene under the verlet, hybrid and event-driven integrators in
 * one table, and the overlaid plot bodies (palette colours, dash types, legend outside). */
#include <check.h>
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/compare.h"
#include "granule/integrator.h"
#include "granule/run.h"
#include "io/plot.h"
#include "io/summary_read.h"
#include "check_main.h"

static char g_dir[256];

static void setup(void)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(g_dir, sizeof g_dir, "%s/granule-test-compare-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    ck_assert_msg(mkdtemp(g_dir) != NULL, "mkdtemp: %s", strerror(errno));
}

static void teardown(void)
{
    if (!gr_test_keep_tmp()) {
        gr_test_rm_tree(g_dir);
    }
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "%s: %s", path, strerror(errno));
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    return buf;
}

START_TEST(test_spec_parse)
{
    gr_compare_spec s;
    gr_error err = {0};
    ck_assert_int_eq(
        gr_compare_spec_parse("spring_dashpot+tangential_dashpot@clamp@hybrid", &s, &err), GR_OK);
    ck_assert_str_eq(s.normal, "spring_dashpot");
    ck_assert_str_eq(s.tangential, "tangential_dashpot");
    ck_assert(s.clamp);
    ck_assert_str_eq(gr_integrators[s.integrator]->name, "hybrid");
    ck_assert_str_eq(s.label, "spring_dashpot_tangential_dashpot_clamp_hybrid");
    ck_assert_int_eq(gr_compare_spec_parse("hard_sphere@event", &s, &err), GR_OK);
    ck_assert_str_eq(gr_integrators[s.integrator]->name, "event");
    ck_assert_str_eq(s.tangential, "");
    ck_assert_int_eq(gr_compare_spec_parse("spring_dashpot", &s, &err), GR_OK);
    ck_assert_int_eq(s.integrator, -1);
    ck_assert(!s.clamp);
    /* refusals name the culprit and list what is allowed */
    struct {
        const char *spec, *words[3];
    } bad[] = {
        {"nosuch", {"nosuch", "spring_dashpot", "hard_sphere"}},
        {"tangential_dashpot", {"unknown normal model", "spring_dashpot", NULL}},
        {"spring_dashpot+nosuch", {"nosuch", "tangential_dashpot", "sliding_friction"}},
        {"spring_dashpot@warp", {"@warp", "@clamp", "@verlet | @event | @hybrid"}},
        {"spring_dashpot@event@hybrid", {"twice", NULL, NULL}},
        {"spring_dashpot@clamp@clamp", {"twice", NULL, NULL}},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        memset(&err, 0, sizeof err);
        ck_assert_int_eq(gr_compare_spec_parse(bad[i].spec, &s, &err), GR_EINVAL);
        for (int w = 0; w < 3 && bad[i].words[w]; w++) {
            ck_assert_msg(strstr(err.message, bad[i].words[w]), "%s: '%s' lacks '%s'", bad[i].spec,
                          err.message, bad[i].words[w]);
        }
    }
    gr_compare_spec list[GR_COMPARE_MAX];
    int n = 0;
    ck_assert_int_eq(
        gr_compare_specs_parse("spring_dashpot,spring_dashpot@hybrid,hard_sphere@event", list,
                               GR_COMPARE_MAX, &n, &err),
        GR_OK);
    ck_assert_int_eq(n, 3);
    ck_assert_int_eq(
        gr_compare_specs_parse("spring_dashpot,spring_dashpot", list, GR_COMPARE_MAX, &n, &err),
        GR_EINVAL);
    ck_assert(strstr(err.message, "share the folder"));
    ck_assert_int_eq(gr_compare_specs_parse(",", list, GR_COMPARE_MAX, &n, &err), GR_EINVAL);
    ck_assert(strstr(err.message, "no model"));
    char many[2000] = "";
    for (int k = 0; k <= GR_COMPARE_MAX; k++) {
        snprintf(many + strlen(many), sizeof many - strlen(many), "%sspring_dashpot@hybrid%s",
                 k ? "," : "", k % 2 ? "@clamp" : "");
    }
    ck_assert_int_eq(gr_compare_specs_parse(many, list, GR_COMPARE_MAX, &n, &err), GR_EINVAL);
}
END_TEST

START_TEST(test_format)
{
    char buf[96];
    struct {
        double v, e;
        const char *want;
    } cases[] = {
        {0.22630251, 0.0085026, "0.2263 +- 0.0085"},
        {9.8743855, 0.7856377, "9.87 +- 0.79"},
        {2.03, NAN, "2.03"},
        {1.32e-5, 1.1e-6, "(1.32 +- 0.11)e-05"},
        {123456.0, 789.0, "(1.2346 +- 0.0079)e+05"},
        {-0.5, 0.25, "-0.50 +- 0.25"},
        {3.0, 0.0, "3"},
        {NAN, 0.1, "n/a"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        gr_compare_format(cases[i].v, cases[i].e, buf, sizeof buf);
        ck_assert_msg(!strcmp(buf, cases[i].want), "%g +- %g: '%s', want '%s'", cases[i].v,
                      cases[i].e, buf, cases[i].want);
    }
}
END_TEST

/* A hand-written summary.json in g_dir/label. */
static void write_summary(const char *label, const char *json)
{
    char dir[400];
    snprintf(dir, sizeof dir, "%s/%s", g_dir, label);
    ck_assert_int_eq(mkdir(dir, 0755), 0);
    cJSON *j = cJSON_Parse(json);
    ck_assert_msg(j != NULL, "bad test JSON for %s", label);
    gr_error err = {0};
    ck_assert_int_eq(gr_json_write(dir, "summary.json", j, &err), GR_OK);
    cJSON_Delete(j);
}

static const char *cell(const gr_compare_table *t, const char *key, int k)
{
    for (int i = 0; i < t->n_rows; i++) {
        if (!strcmp(t->row[i].key, key)) {
            return t->row[i].cell[k].text;
        }
    }
    ck_abort_msg("no headline row %s", key);
    return NULL;
}

START_TEST(test_headline_reasons)
{
    /* 1D, verlet, no observables, no collisions, error bar not converged */
    write_summary(
        "a",
        "{\"status\":\"completed\",\"T_mean\":0.25,\"T_stderr\":0.01,\"T_stderr_converged\":false,"
        "\"collisions\":0,\"simulated_seconds\":1,\"wall_seconds\":2,\"particle_steps_per_second\":"
        "5e6,"
        "\"ledger\":{\"injected\":1e-3,\"dissipated_normal\":0,\"relative_residual\":1e-4},"
        "\"kernel\":\"k\",\"scene\":{\"system\":{\"dim\":1,\"N\":10},\"model\":{\"tangential\":"
        "\"none\"},"
        "\"integrator\":{\"kind\":\"verlet\"}}}");
    /* 2D, event-driven, tail fit failed, S(k) fit failed, 400 collisions of 10 particles in 2 s */
    write_summary(
        "b",
        "{\"status\":\"completed\",\"T_mean\":0.5,\"T_stderr\":0.02,\"T_stderr_converged\":true,"
        "\"collisions\":400,\"simulated_seconds\":2,\"wall_seconds\":4,\"events_per_second\":1e6,"
        "\"ledger\":{\"injected\":2e-3,\"dissipated_normal\":1.5e-3,\"dissipated_tangential\":5e-4,"
        "\"relative_residual\":0},"
        "\"kernel\":\"e\",\"analysis\":{\"pv\":{\"tail\":{\"accepted\":false,\"n_points\":3,"
        "\"free\":{\"converged\":false}}},"
        "\"sk\":{\"fit\":{\"status\":\"fewer than 3 shells below k'\"}}},"
        "\"scene\":{\"system\":{\"dim\":2,\"N\":10},\"model\":{\"tangential\":\"none\"},"
        "\"integrator\":{\"kind\":\"event\"}}}");
    /* 2D, verlet with sliding friction, the tail accepted, D_f fitted */
    write_summary(
        "c",
        "{\"status\":\"completed\",\"T_mean\":0.4,\"T_stderr\":0.02,\"T_stderr_converged\":true,"
        "\"collisions\":10,\"simulated_seconds\":1,\"wall_seconds\":1,\"particle_steps_per_"
        "second\":2e7,"
        "\"ledger\":{\"injected\":1e-3,\"dissipated_normal\":5e-4,\"dissipated_friction\":2.5e-4,"
        "\"relative_residual\":0},"
        "\"kernel\":\"s\",\"analysis\":{\"pv\":{\"tail\":{\"accepted\":true,\"alpha\":1.5,\"alpha_"
        "halfwidth\":0.1}},"
        "\"sk\":{\"fit\":{\"D_f\":1.63,\"D_f_err\":0.04}}},"
        "\"scene\":{\"system\":{\"dim\":2,\"N\":10},\"model\":{\"tangential\":\"sliding_friction\"}"
        ",\"integrator\":{\"kind\":\"verlet\"}}}");
    gr_compare_spec specs[4];
    gr_error err = {0};
    int n;
    ck_assert_int_eq(
        gr_compare_specs_parse(
            "spring_dashpot,hard_sphere,spring_dashpot+sliding_friction,spring_dashpot@hybrid",
            specs, 4, &n, &err),
        GR_OK);
    /* the folders of this test are a, b, c and (missing) d */
    snprintf(specs[0].label, sizeof specs[0].label, "a");
    snprintf(specs[1].label, sizeof specs[1].label, "b");
    snprintf(specs[2].label, sizeof specs[2].label, "c");
    snprintf(specs[3].label, sizeof specs[3].label, "d");
    gr_compare_table *t = gr_compare_table_build(g_dir, "scene.ini", 2, specs, 4);
    ck_assert_ptr_nonnull(t);
    ck_assert_str_eq(cell(t, "T", 0), "0.250 +- 0.010 *");
    ck_assert(strstr(t->footnotes, "*: the error bar of T is not converged"));
    ck_assert_str_eq(cell(t, "T", 1), "0.500 +- 0.020");
    ck_assert_str_eq(cell(t, "tail_alpha", 0), "n/a: pv not enabled");
    ck_assert_str_eq(cell(t, "tail_alpha", 1), "fit failed: 3 points in the window");
    ck_assert_str_eq(cell(t, "tail_alpha", 2), "1.50 +- 0.10");
    ck_assert_str_eq(cell(t, "D_f", 0), "n/a: 1D");
    ck_assert_str_eq(cell(t, "D_f", 1), "fit failed: fewer than 3 shells below k'");
    ck_assert_str_eq(cell(t, "D_f", 2), "1.630 +- 0.040");
    ck_assert_str_eq(cell(t, "n_N", 0), "n/a: gaps not enabled");
    ck_assert_str_eq(cell(t, "n_N", 1), "n/a: 2D");
    ck_assert_str_eq(cell(t, "collision_rate", 0), "no collisions");
    ck_assert_str_eq(cell(t, "collision_rate", 1), "20"); /* 400 / (10 particles x 2 s) */
    ck_assert_str_eq(cell(t, "dissipated_normal", 0), "no collisions");
    ck_assert_str_eq(cell(t, "dissipated_normal", 1), "0.0015 (75%)");
    ck_assert_str_eq(cell(t, "dissipated_tangential", 0), "n/a: 1D");
    ck_assert_str_eq(cell(t, "dissipated_tangential", 1), "0.0005 (25%)"); /* hard_sphere's eps_t */
    ck_assert_str_eq(cell(t, "dissipated_tangential", 2), "n/a: no tangential dashpot");
    ck_assert_str_eq(cell(t, "dissipated_friction", 1), "n/a: no sliding friction");
    ck_assert_str_eq(cell(t, "dissipated_friction", 2), "0.00025 (25%)");
    ck_assert_str_eq(cell(t, "throughput", 0), "5e+06 particle-steps/s");
    ck_assert_str_eq(cell(t, "throughput", 1), "1e+06 events/s");
    ck_assert_str_eq(cell(t, "collisions_per_wall_second", 0), "no collisions");
    ck_assert_str_eq(cell(t, "collisions_per_wall_second", 1), "100");
    ck_assert_str_eq(t->integrator[1], "event");
    ck_assert_str_eq(cell(t, "T", 3), "run failed: no summary.json");
    /* never a nan or inf in the headline, the terminal table, compare.md or compare.csv */
    for (int i = 0; i < t->n_rows; i++) {
        for (int k = 0; k < 4; k++) {
            ck_assert_msg(!strstr(t->row[i].cell[k].text, "nan") &&
                              !strstr(t->row[i].cell[k].text, "inf") && t->row[i].cell[k].text[0],
                          "%s / %d: '%s'", t->row[i].key, k, t->row[i].cell[k].text);
        }
    }
    ck_assert_int_eq(gr_compare_table_write(t, g_dir, &err), GR_OK);
    char path[400];
    snprintf(path, sizeof path, "%s/compare.md", g_dir);
    const char *md = slurp(path);
    ck_assert(strstr(md, "| T (m^2/s^2) | 0.250 +- 0.010 * | 0.500 +- 0.020 |"));
    ck_assert(strstr(md, "| fractal dimension D_f of S(k) (4.4) | n/a: 1D |"));
    ck_assert(!strstr(md, "nan"));
    snprintf(path, sizeof path, "%s/compare.csv", g_dir);
    const char *csv = slurp(path);
    ck_assert(!strstr(csv, "nan"));
    ck_assert(strstr(csv, "model,integrator,kernel,status,T,T_err,T_note,T_rot,T_rot_note,tail_"
                          "alpha,tail_alpha_err,tail_alpha_note,D_f,"
                          "D_f_err,D_f_note"));
    ck_assert(strstr(csv, "fit failed: fewer than 3 shells below k'"));
    snprintf(path, sizeof path, "%s/compare.json", g_dir);
    cJSON *j = gr_json_read(path, &err);
    ck_assert_ptr_nonnull(j);
    const cJSON *d = cJSON_GetObjectItem(
        cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(j, "models"), 2), "headline"),
        "D_f");
    ck_assert_double_eq_tol(cJSON_GetObjectItem(d, "value")->valuedouble, 1.63, 1e-12);
    ck_assert_double_eq_tol(cJSON_GetObjectItem(d, "error")->valuedouble, 0.04, 1e-12);
    cJSON_Delete(j);
    /* the terminal table: the spec names, the integrators and the same cells */
    snprintf(path, sizeof path, "%s/table.txt", g_dir);
    FILE *f = fopen(path, "w");
    gr_compare_table_print(t, f);
    fclose(f);
    const char *txt = slurp(path);
    ck_assert(strstr(txt, "spring_dashpot+sliding_friction") && strstr(txt, "event") &&
              strstr(txt, "1e+06 events/s"));
    ck_assert(!strstr(txt, "nan"));
    gr_compare_table_free(t);
}
END_TEST

/* compare.csv is plain for numpy.genfromtxt (no '#', which starts a comment there, in any cell:
 * the footnote marks are words in <key>_note), compare.meta.json gives every column's unit and
 * its notes one per line, and the footer says what "+-" is (issue 38). */
/* The system's own rows (issue 36): a free-cooling gas's Haff time, a Langevin gas's T / T_bath and
 * a bed's profile and its walls' work, present only when the scene has them. */
START_TEST(test_system_rows)
{
    write_summary(
        "cool",
        "{\"status\":\"completed\",\"T_mean\":0.1,\"T_stderr\":0.01,\"T_stderr_converged\":true,"
        "\"collisions\":5,\"simulated_seconds\":1,\"wall_seconds\":1,"
        "\"mean_field\":{\"t0_fit\":1.2,\"t0_fit_stderr\":0.03,\"t0_haff\":1.0},"
        "\"ledger\":{\"injected\":0},\"scene\":{\"system\":{\"dim\":2,\"N\":10},"
        "\"integrator\":{\"kind\":\"event\"}}}");
    write_summary(
        "bed",
        "{\"status\":\"completed\",\"T_mean\":0.2,\"T_stderr\":0.01,\"T_stderr_converged\":true,"
        "\"collisions\":5,\"simulated_seconds\":1,\"wall_seconds\":1,"
        "\"mean_field\":{\"t0_fit\":9,\"t0_fit_stderr\":1,\"T_bath\":0.4},"
        "\"analysis\":{\"profile\":{\"mean_position\":0.05,\"mean_position_error\":0.001,"
        "\"max_packing_fraction\":0.3}},"
        "\"ledger\":{\"injected\":0,\"wall_work\":0.004,\"dissipated_normal\":0.003,"
        "\"dissipated_drag\":0.001},"
        "\"scene\":{\"system\":{\"dim\":2,\"N\":10},"
        "\"gravity\":{\"gy\":-9.81},\"integrator\":{\"kind\":\"verlet\"}}}");
    gr_compare_spec specs[1];
    gr_error err = {0};
    int n;
    ck_assert_int_eq(gr_compare_specs_parse("hard_sphere", specs, 1, &n, &err), GR_OK);
    snprintf(specs[0].label, sizeof specs[0].label, "cool");
    gr_compare_table *t = gr_compare_table_build(g_dir, "scene.ini", 2, specs, 1);
    ck_assert_str_eq(cell(t, "haff_t0", 0), "1.200 +- 0.030");
    ck_assert_str_eq(cell(t, "haff_t0_ratio", 0), "1.200 +- 0.030");
    for (int i = 0; i < t->n_rows; i++) { /* no bath, walls or profile rows for a free gas */
        ck_assert(strcmp(t->row[i].key, "T_over_bath") && strcmp(t->row[i].key, "profile_height") &&
                  strcmp(t->row[i].key, "wall_work"));
    }
    gr_compare_table_free(t);
    snprintf(specs[0].label, sizeof specs[0].label, "bed");
    t = gr_compare_table_build(g_dir, "scene.ini", 2, specs, 1);
    ck_assert_str_eq(cell(t, "T_over_bath", 0), "0.500 +- 0.025");
    ck_assert_str_eq(cell(t, "profile_height", 0), "0.0500 +- 0.0010");
    ck_assert_str_eq(cell(t, "profile_max_phi", 0), "0.3");
    /* a bed's energy comes from its walls: their work has a row and is the dissipation's base */
    ck_assert_str_eq(cell(t, "wall_work", 0), "0.004");
    ck_assert_str_eq(cell(t, "dissipated_normal", 0), "0.003 (75%)");
    ck_assert_str_eq(cell(t, "dissipated_drag", 0), "0.001 (25%)"); /* a bath's drag */
    for (int i = 0; i < t->n_rows; i++) { /* under gravity Haff's law is not the reference */
        ck_assert(strcmp(t->row[i].key, "haff_t0"));
    }
    gr_compare_table_free(t);
}
END_TEST

START_TEST(test_csv_plain_with_units)
{
    write_summary(
        "f",
        "{\"status\":\"completed\",\"T_mean\":0.25,\"T_stderr\":0.01,\"T_stderr_converged\":false,"
        "\"collisions\":10,\"simulated_seconds\":1,\"wall_seconds\":2,\"particle_steps_per_"
        "second\":5e6,"
        "\"ledger\":{\"injected\":1e-3,\"dissipated_normal\":1e-3,\"relative_residual\":1e-4},"
        "\"kernel\":\"k\",\"analysis\":{\"pv\":{\"v_rms\":0.3,\"tail\":{\"accepted\":false,\"n_"
        "points\":9,"
        "\"free\":{\"converged\":true,\"alpha\":1.349,\"alpha_err\":0.011}}},"
        "\"moments\":{\"speed\":{\"m3\":0.1}}},"
        "\"scene\":{\"system\":{\"dim\":2,\"N\":10},\"model\":{\"tangential\":\"none\"},"
        "\"integrator\":{\"kind\":\"verlet\"}}}");
    gr_compare_spec specs[1];
    gr_error err = {0};
    int n;
    ck_assert_int_eq(gr_compare_specs_parse("spring_dashpot", specs, 1, &n, &err), GR_OK);
    snprintf(specs[0].label, sizeof specs[0].label, "f");
    gr_compare_table *t = gr_compare_table_build(g_dir, "scene.ini", 2, specs, 1);
    ck_assert_ptr_nonnull(t);
    ck_assert_str_eq(cell(t, "tail_alpha", 0), "1.349 +- 0.011 #");
    ck_assert_msg(strstr(t->footnotes, "+-: T: one standard error") &&
                      strstr(t->footnotes, "half-width"),
                  "%s", t->footnotes);
    ck_assert_int_eq(gr_compare_table_write(t, g_dir, &err), GR_OK);
    char path[400];
    snprintf(path, sizeof path, "%s/compare.csv", g_dir);
    const char *csv = slurp(path);
    ck_assert_msg(!strchr(csv, '#'), "%s", csv);
    ck_assert(
        strstr(csv, ",free fit of (5.5): no alpha has chi2/dof < 1.2 in the Table 5.1 window"));
    ck_assert(strstr(csv, ",error bar not converged (a lower bound): run longer"));
    char header[8192];
    snprintf(header, sizeof header, "%.*s", (int)strcspn(csv, "\n"), csv);
    snprintf(path, sizeof path, "%s/compare.md", g_dir);
    ck_assert(strstr(slurp(path), "+-: T: one standard error"));
    snprintf(path, sizeof path, "%s/compare.meta.json", g_dir);
    cJSON *j = gr_json_read(path, &err);
    ck_assert_ptr_nonnull(j);
    ck_assert_int_eq(cJSON_GetArraySize(cJSON_GetObjectItem(j, "notes")),
                     2); /* not "noise seedheadline" */
    const cJSON *units = cJSON_GetObjectItem(j, "units");
    ck_assert_ptr_nonnull(units);
    /* every column of the header line has a unit */
    int columns = 0;
    for (char *save = NULL, *c = strtok_r(header, ",", &save); c;
         c = strtok_r(NULL, ",", &save), columns++) {
        ck_assert_msg(cJSON_IsString(cJSON_GetObjectItem(units, c)), "column %s has no unit", c);
    }
    ck_assert_int_eq(cJSON_GetArraySize(units), columns);
    ck_assert_str_eq(cJSON_GetObjectItem(units, "T")->valuestring, "m2 s-2");
    ck_assert_str_eq(cJSON_GetObjectItem(units, "tail_alpha_note")->valuestring, "");
    ck_assert_str_eq(cJSON_GetObjectItem(units, "analysis.pv.v_rms")->valuestring, "m s-1");
    ck_assert_str_eq(cJSON_GetObjectItem(units, "analysis.moments.speed.m3")->valuestring,
                     "m3 s-3");
    cJSON_Delete(j);
    gr_compare_table_free(t);
}
END_TEST

static void write_scene(const char *name, const char *extra)
{
    char path[400];
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fprintf(
        f,
        "[system]\ndim = 1\nN = 20\nreduced_length = 0.1\n[placement]\nkind = uniform\nv0 = 0.1\n"
        "[noise]\nD = 1e-8\n[run]\nwarmup = 0\nduration = 0.01\nsample_every = 1e-3\n"
        "[output]\nplots = false\nsnapshot_every = 0\n%s",
        extra);
    fclose(f);
}

/* One scene under the three integrators: each run's summary names its integrator, the table
 * gives each the throughput of its kind, and the overlaid plot gives each its palette style. */
START_TEST(test_mixed_integrators)
{
    write_scene("ring.ini",
                "[model]\nnormal = spring_dashpot\neps_n = 0.5\n[integrator]\ndt = 1e-6\n");
    char scene[400];
    snprintf(scene, sizeof scene, "%s/ring.ini", g_dir);
    gr_compare_spec specs[3];
    int n;
    gr_error err = {0};
    ck_assert_int_eq(gr_compare_specs_parse("spring_dashpot,spring_dashpot@hybrid,hard_sphere",
                                            specs, 3, &n, &err),
                     GR_OK);
    const char *kinds[] = {"verlet", "hybrid", "event"};
    for (int k = 0; k < 3; k++) {
        gr_scene s;
        ck_assert_msg(gr_compare_scene_load(&specs[k], scene, NULL, 0, g_dir, &s, &err) == GR_OK,
                      "%s", err.message);
        ck_assert_str_eq(s.integrator->name, kinds[k]);
        gr_run_options opt = {0};
        gr_run_result res;
        ck_assert_msg(gr_run(&s, &opt, &res, &err) == GR_OK, "%s: %s", specs[k].text, err.message);
    }
    gr_compare_table *t = gr_compare_table_build(g_dir, scene, 1, specs, 3);
    for (int k = 0; k < 3; k++) {
        ck_assert_str_eq(t->integrator[k], kinds[k]);
        ck_assert_str_eq(t->status[k], "completed");
        ck_assert_msg(isfinite(t->row[0].cell[k].value) && t->row[0].cell[k].value > 0.0, "T of %s",
                      specs[k].text);
        ck_assert(strstr(cell(t, "throughput", k), k == 2 ? " events/s" : " particle-steps/s"));
        ck_assert_str_eq(cell(t, "D_f", k), "n/a: 1D");
    }
    /* an event rule in a soft scene was told apart; a force law in an event scene runs verlet */
    write_scene("ring-event.ini",
                "[model]\nnormal = hard_sphere\neps_n = 0.5\n[integrator]\nkind = event\n");
    snprintf(scene, sizeof scene, "%s/ring-event.ini", g_dir);
    gr_scene s;
    ck_assert_msg(gr_compare_scene_load(&specs[0], scene, NULL, 0, g_dir, &s, &err) == GR_OK, "%s",
                  err.message);
    ck_assert_str_eq(s.integrator->name, "verlet");
    /* a force law forced onto the event-driven integrator is refused by the scene, naming the spec */
    gr_compare_spec bad;
    ck_assert_int_eq(gr_compare_spec_parse("spring_dashpot@event", &bad, &err), GR_OK);
    ck_assert_int_eq(gr_compare_scene_load(&bad, scene, NULL, 0, g_dir, &s, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "spring_dashpot@event: ") &&
                      strstr(err.message, "hard_sphere"),
                  "%s", err.message);
    /* the overlaid T(t): one palette colour and dash type per model, legend outside the data */
    char note[300];
    gr_compare_plots(g_dir, specs, 3, note, sizeof note);
    char path[400];
    snprintf(path, sizeof path, "%s/temperature.gp", g_dir);
    if (access(path, R_OK) == 0) { /* written by gr_plot_script, which needs gnuplot */
        const char *gp = slurp(path);
        ck_assert(strstr(gp, "set key below"));
        for (int k = 0; k < 3; k++) {
            char style[80];
            gr_plot_series_style(k, style, sizeof style);
            ck_assert_msg(strstr(gp, style), "%s lacks %s", gp, style);
            ck_assert(strstr(gp, specs[k].label));
        }
    } else {
        ck_assert_msg(strstr(note, "gnuplot"), "no temperature.gp and no reason: %s", note);
    }
    gr_compare_table_free(t);
}
END_TEST

/* @rotation sets model.rotation = true (false without it, whatever the scene says); the table
 * gives the spin's temperature of a rotating run and says "no rotation" for the others; a spec
 * whose laws do not act at the contact point cannot rotate, and is refused before anything runs. */
START_TEST(test_rotation_modifier)
{
    gr_compare_spec specs[2], bad;
    gr_error err = {0};
    int n;
    ck_assert_int_eq(
        gr_compare_specs_parse(
            "spring_dashpot+tangential_dashpot,spring_dashpot+tangential_dashpot@rotation", specs,
            2, &n, &err),
        GR_OK);
    ck_assert(!specs[0].rotation && specs[1].rotation);
    ck_assert_str_eq(specs[1].label, "spring_dashpot_tangential_dashpot_rotation");
    ck_assert_int_eq(
        gr_compare_spec_parse("spring_dashpot+tangential_dashpot@rotation@rotation", &bad, &err),
        GR_EINVAL);
    ck_assert(strstr(err.message, "twice") && strstr(err.message, "@rotation"));
    char path[400];
    snprintf(path, sizeof path, "%s/discs.ini", g_dir);
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fprintf(f, "[system]\ndim = 2\nN = 60\nL = 0.03\n[placement]\nkind = uniform\nv0 = 0.3\n"
               "[model]\nrotation = true\neps_n = 0.5\neps_t = 0.5\n[noise]\nD = "
               "1e-8\n[integrator]\ndt = 1e-6\n"
               "[run]\nwarmup = 0\nduration = 0.004\nsample_every = 1e-3\n[output]\nplots = "
               "false\nsnapshot_every = 0\n");
    fclose(f);
    for (int k = 0; k < 2; k++) {
        gr_scene s;
        ck_assert_msg(gr_compare_scene_load(&specs[k], path, NULL, 0, g_dir, &s, &err) == GR_OK,
                      "%s", err.message);
        ck_assert_int_eq(s.contact.rotation,
                         k == 1); /* the scene's rotation = true is the spec's to decide */
        gr_run_options opt = {0};
        gr_run_result res;
        ck_assert_msg(gr_run(&s, &opt, &res, &err) == GR_OK, "%s: %s", specs[k].text, err.message);
    }
    gr_compare_table *t = gr_compare_table_build(g_dir, path, 2, specs, 2);
    ck_assert_str_eq(cell(t, "T_rot", 0), "n/a: no rotation");
    ck_assert_msg(t->row[1].cell[1].value > 0.0 && isfinite(t->row[1].cell[1].value), "T_rot %s",
                  cell(t, "T_rot", 1));
    gr_compare_table_free(t);
    ck_assert_int_eq(gr_compare_spec_parse("spring_dashpot@rotation", &bad, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "'spring_dashpot@rotation'") &&
                      strstr(err.message, "contact point"),
                  "%s", err.message);
    /* hard discs have the key themselves (rough discs, docs/event-driven.md) */
    ck_assert_int_eq(gr_compare_spec_parse("hard_sphere@rotation", &bad, &err), GR_OK);
    /* a rolling law is the third part, on spinning discs only */
    ck_assert_int_eq(gr_compare_spec_parse(
                         "spring_dashpot+tangential_dashpot+rolling_friction@rotation", &bad, &err),
                     GR_OK);
    ck_assert_str_eq(bad.rolling, "rolling_friction");
    ck_assert_int_eq(
        gr_compare_spec_parse("spring_dashpot+tangential_dashpot+rolling_friction", &bad, &err),
        GR_EINVAL);
    ck_assert_msg(strstr(err.message, "@rotation"), "%s", err.message);
    ck_assert_int_eq(
        gr_compare_spec_parse("spring_dashpot+tangential_dashpot+nosuch@rotation", &bad, &err),
        GR_EINVAL);
    ck_assert_msg(strstr(err.message, "nosuch") && strstr(err.message, "rolling_friction"), "%s",
                  err.message);
    gr_compare_spec roll;
    ck_assert_int_eq(
        gr_compare_spec_parse("spring_dashpot+tangential_dashpot+rolling_friction@rotation", &roll,
                              &err),
        GR_OK);
    gr_scene rs;
    ck_assert_msg(gr_compare_scene_load(&roll, path, NULL, 0, g_dir, &rs, &err) == GR_OK, "%s",
                  err.message);
    ck_assert_ptr_nonnull(rs.rolling);
    ck_assert_str_eq(rs.rolling->name, "rolling_friction");
}
END_TEST

/* The shared palette: eight distinct colours, each with a contrast of at least 3:1 on white
 * (WCAG relative luminance); neighbouring overlay styles differ in colour and dash type. */
START_TEST(test_palette)
{
    for (int k = 0; k < GR_PLOT_COLOURS; k++) {
        unsigned r, g, b;
        ck_assert_int_eq(sscanf(gr_plot_palette[k], "#%2x%2x%2x", &r, &g, &b), 3);
        double c[3] = {r / 255.0, g / 255.0, b / 255.0};
        for (int i = 0; i < 3; i++) {
            c[i] = c[i] <= 0.03928 ? c[i] / 12.92 : pow((c[i] + 0.055) / 1.055, 2.4);
        }
        const double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        ck_assert_msg(1.05 / (lum + 0.05) >= 3.0, "%s: contrast %.2f on white", gr_plot_palette[k],
                      1.05 / (lum + 0.05));
        for (int j = 0; j < k; j++) {
            ck_assert_str_ne(gr_plot_palette[j], gr_plot_palette[k]);
        }
    }
    char a[80], b[80];
    for (int k = 0; k + 1 < 8; k++) {
        gr_plot_series_style(k, a, sizeof a);
        gr_plot_series_style(k + 1, b, sizeof b);
        ck_assert(strncmp(a, b, 20) != 0); /* the colour */
        ck_assert(strstr(a, "dt ") &&
                  strcmp(strstr(a, "dt "), strstr(b, "dt ")) != 0); /* the dash */
    }
}
END_TEST

static Suite *compare_suite(void)
{
    Suite *s = suite_create("compare");
    TCase *tc = tcase_create("compare");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, test_spec_parse);
    tcase_add_test(tc, test_format);
    tcase_add_test(tc, test_headline_reasons);
    tcase_add_test(tc, test_system_rows);
    tcase_add_test(tc, test_csv_plain_with_units);
    tcase_add_test(tc, test_mixed_integrators);
    tcase_add_test(tc, test_rotation_modifier);
    tcase_add_test(tc, test_palette);
    suite_add_tcase(s, tc);
    return s;
}

int main(void) { return gr_test_run(compare_suite()); }
