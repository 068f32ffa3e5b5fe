/* granule reproduce: run a reproduction campaign (docs/campaigns/NAME.ini, built in) as a sweep,
 * analyse its finished points into a result set, and generate docs/reproduction.md from the
 * committed result sets. Parsing and printing only: the campaign, its analysis and the page live
 * in the library (include/granule/campaign.h). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/cli.h"
#include "app/sweep.h"
#include "granule/campaign.h"
#include "io/files.h"
#include "io/summary_read.h"

typedef struct reproduce_args {
    const char *fidelity, *out, *results, *root, *page_out, *point, *base;
    int jobs;
    bool list, page, collect;
} reproduce_args;

static const cli_opt reproduce_opts[] = {
    {"--fidelity", CLI_CHOICE, "quick|full", offsetof(reproduce_args, fidelity), 0, 0, 0, "quick",
     "quick: minutes, checks the pipeline; full: the sizes and run lengths of docs/reproduction.md",
     NULL},
    {"--out", CLI_STRING, "DIR", offsetof(reproduce_args, out), 0, 0, 0, "out/reproduce",
     "the runs go to DIR/NAME/FIDELITY/runs", NULL},
    {"--results", CLI_STRING, "DIR", offsetof(reproduce_args, results), 0, 0, 0,
     "DIR/NAME/FIDELITY/results", "where the result set is written", NULL},
    {"--jobs", CLI_INT, "J", offsetof(reproduce_args, jobs), 1, SWEEP_MAX_JOBS, 0,
     "the number of cores", "parallel runs", NULL},
    CLI_OPT_THREADS,
    {"--point", CLI_STRING, "K", offsetof(reproduce_args, point), 0, 0, 0, NULL,
     "run point K only (a batch-array task)", NULL},
    {"--array-base", CLI_STRING, "B", offsetof(reproduce_args, base), 0, 0, 0, "0",
     "in a batch-array task, run point = array index - B", NULL},
    {"--collect", CLI_FLAG, NULL, offsetof(reproduce_args, collect), 0, 0, 0, NULL,
     "analyse the finished points only", NULL},
    {"--list", CLI_FLAG, NULL, offsetof(reproduce_args, list), 0, 0, 0, NULL,
     "list the built-in campaigns", NULL},
    {"--page", CLI_FLAG, NULL, offsetof(reproduce_args, page), 0, 0, 0, NULL,
     "regenerate docs/reproduction.md and each campaign's page (RESULTS_ROOT/NAME/README.md) from "
     "the committed result sets",
     NULL},
    {"--results-root", CLI_STRING, "DIR", offsetof(reproduce_args, root), 0, 0, 0, "docs/results",
     "with --page: the result sets to read", NULL},
    {"--output", CLI_STRING, "FILE", offsetof(reproduce_args, page_out), 0, 0, 0,
     "docs/reproduction.md", "with --page: the page to write", NULL},
};

const cli_command cli_cmd_reproduce = {
    .name = "reproduce",
    .usage =
        "granule reproduce NAME [--fidelity quick|full] [--out DIR] [--results DIR] [--jobs J] "
        "[--threads N]\n"
        "       granule reproduce NAME ... --point K | --array-base B      one point (batch-array "
        "task)\n"
        "       mpirun -n P granule reproduce NAME ...                     over MPI ranks\n"
        "       granule reproduce NAME [--fidelity F] [--out DIR] --collect  analyse the finished "
        "points only\n"
        "       granule reproduce --list                                   the built-in campaigns\n"
        "       granule reproduce --page [--results-root DIR] [--output FILE]  regenerate "
        "docs/reproduction.md",
    .about = "NAME is a campaign (granule reproduce --list), a figure or table it covers (fig3.2, "
             "table4.1), or a\n"
             "campaign file. Its runs go to DIR/NAME/FIDELITY/runs (default DIR: out/reproduce) as "
             "a granule sweep:\n"
             "finished points are never rerun and an interrupted one continues from its "
             "checkpoint, so the\n"
             "command can be stopped at any time and run again. Progress lines give the CPU-hours "
             "spent and left.\n"
             "When every point is finished the result set (results.csv, results.json, a data CSV "
             "and figures per\n"
             "figure/table, the thesis's values overlaid) is written to --results (default "
             "DIR/NAME/FIDELITY/results;\n"
             "docs/results/NAME for the committed ones) and the numbers are printed. The campaigns "
             "and scenes are\n"
             "built into granule, so this works from any folder. quick: minutes, checks the "
             "pipeline; full: the\n"
             "sizes and run lengths of docs/reproduction.md, which gives each campaign's CPU-hours "
             "(hours to days).\n",
    .pos_name = "campaign",
    .max_pos = 1,
    CLI_OPTS(reproduce_opts),
};

static void print_pm(double v, double e)
{
    if (!isfinite(v)) {
        printf("%-22s", "no value");
    } else if (isfinite(e)) {
        char buf[64];
        snprintf(buf, sizeof buf, "%.4g +- %.2g", v, e);
        printf("%-22s", buf);
    } else {
        printf("%-22.4g", v);
    }
}

/* The numbers of a result set, as a table on stdout. */
static void print_results(const char *results)
{
    char path[4300];
    snprintf(path, sizeof path, "%s/results.json", results);
    gr_error err = {0};
    cJSON *j = gr_json_read(path, &err);
    const cJSON *res, *row;
    cJSON_ArrayForEach(res, cJSON_GetObjectItem(j, "results"))
    {
        const cJSON *id = cJSON_GetObjectItem(res, "id"), *q = cJSON_GetObjectItem(res, "quantity");
        printf("\n%s (%s)\n  %-34s %-22s %-22s %s\n", id->valuestring, q->valuestring, "",
               "granule", "thesis", "comparison");
        cJSON_ArrayForEach(row, cJSON_GetObjectItem(res, "rows"))
        {
            char group[200];
            double m = gr_summary_number(row, "m");
            snprintf(group, sizeof group, "%s%s%.0f",
                     cJSON_GetObjectItem(row, "group")->valuestring, isfinite(m) ? " m=" : "",
                     isfinite(m) ? m : 0.0);
            if (!isfinite(m)) {
                group[strlen(group) - 1] = 0;
            }
            printf("  %-34s ", group);
            print_pm(gr_summary_number(row, "value"), gr_summary_number(row, "error"));
            print_pm(gr_summary_number(row, "thesis"), gr_summary_number(row, "thesis_error"));
            double bad = gr_summary_number(row, "runs_not_converged");
            char how[160];
            gr_campaign_comparison_text(row, false, how, sizeof how);
            printf("%s", how);
            printf(bad > 0 ? "  (%.0f run%s: T's block error not converged)\n" : "\n", bad,
                   bad == 1 ? "" : "s");
        }
    }
    printf("\n%s/results.json: %.0f of %.0f points, %.3g CPU-hours\n", results,
           gr_summary_number(j, "points_finished"), gr_summary_number(j, "points_total"),
           gr_summary_number(j, "cpu_seconds") / 3600.0);
    cJSON_Delete(j);
}

static int list_campaigns(void)
{
    const char *names[64];
    int n = gr_campaign_names(names, 64), width = (int)strlen("campaign");
    for (int i = 0; i < n; i++) { /* names[i] is "campaigns/NAME.ini" */
        const int w = (int)strlen(names[i]) - 14;
        width = w > width ? w : width;
    }
    printf("%-*s %-6s %-6s %s\n", width, "campaign", "quick", "full",
           "covers (points per fidelity)");
    for (int i = 0; i < n; i++) {
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)(strlen(names[i]) - 14), names[i] + 10);
        gr_campaign c;
        gr_error err = {0};
        if (gr_campaign_load(&c, name, &err)) {
            app_error("reproduce: %s", err.message);
            return EXIT_FAILED;
        }
        printf("%-*s %-6ld %-6ld %s\n", width, name, gr_campaign_points(&c, GR_FIDELITY_QUICK),
               gr_campaign_points(&c, GR_FIDELITY_FULL), c.covers);
    }
    return EXIT_OK;
}

/* A refused campaign leaves the output folder as it was: remove the sweep file and scene written
 * into dir and every folder of out/NAME/FIDELITY that did not exist before (existed[0..2]). */
static void undo_materialise(const char *dir, const bool existed[3])
{
    char path[4300], parent[4300];
    snprintf(path, sizeof path, "%s/sweep.ini", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/scene.ini", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s", dir);
    for (int level = 2; level >= 0; level--) {
        if (!existed[level]) {
            rmdir(path); /* only if empty: anything of the user's stays */
        }
        snprintf(parent, sizeof parent, "%s", path);
        char *slash = strrchr(parent, '/');
        if (!slash) {
            break;
        }
        *slash = 0;
        snprintf(path, sizeof path, "%s", parent);
    }
}

static bool is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* Under an MPI launcher only rank 0 analyses (every rank runs the sweep). */
static bool mpi_worker(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK",
                                       "SLURM_PROCID"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++) {
        const char *v = getenv(vars[i]);
        if (v && atoi(v) > 0) {
            return true;
        }
    }
    return false;
}

int cmd_reproduce(int argc, char **argv)
{
    reproduce_args args = {.fidelity = "quick",
                           .out = "out/reproduce",
                           .root = "docs/results",
                           .page_out = "docs/reproduction.md"};
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_reproduce, argc, argv, &args, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    if (args.list) {
        return list_campaigns();
    }
    const char *name = pos.n ? pos.v[0] : NULL, *out = args.out, *results = args.results,
               *root = args.root, *page_out = args.page_out;
    const gr_fidelity fid = !strcmp(args.fidelity, "full") ? GR_FIDELITY_FULL : GR_FIDELITY_QUICK;
    const bool collect = args.collect, page = args.page, one_point = args.point || args.base;
    long point =
        -2; /* --point K (-1: not a number); checked against the campaign before anything is written */
    const char *point_text = args.point;
    if (point_text) {
        char *end;
        point = strtol(point_text, &end, 10);
        point = *end || end == point_text ? -1 : point;
    }
    /* passed on to the sweep */
    char jobs_text[32];
    char *pass[8];
    int n_pass = 0;
    if (args.jobs) {
        snprintf(jobs_text, sizeof jobs_text, "%d", args.jobs);
        pass[n_pass++] = "--jobs";
        pass[n_pass++] = jobs_text;
    }
    if (args.point) {
        pass[n_pass++] = "--point";
        pass[n_pass++] = (char *)args.point;
    }
    if (args.base) {
        pass[n_pass++] = "--array-base";
        pass[n_pass++] = (char *)args.base;
    }
    if (page) {
        gr_error err = {0};
        if (gr_reproduction_page(root, page_out, &err)) {
            app_error("reproduce: %s", err.message);
            return EXIT_FAILED;
        }
        printf("%s: generated from %s/*/results.json\n", page_out, root);
        return EXIT_OK;
    }
    if (!name) {
        cli_help(&cli_cmd_reproduce, stderr);
        return EXIT_REFUSED;
    }
    gr_campaign *c = calloc(1, sizeof *c);
    gr_error err = {0};
    int rc = EXIT_OK;
    char dir[1200], abs_dir[4096], sweep_path[4200], res_dir[4200];
    if (gr_campaign_load(c, name, &err)) {
        app_error("reproduce: %s", err.message);
        free(c);
        return EXIT_REFUSED;
    }
    long total = gr_campaign_points(c, fid);
    if (point != -2 && (point < 0 || point >= total)) {
        app_error("reproduce: --point %s: %s has points 0..%ld at %s fidelity", point_text, c->name,
                  total - 1, fid == GR_FIDELITY_FULL ? "full" : "quick");
        free(c);
        return EXIT_REFUSED;
    }
    snprintf(dir, sizeof dir, "%.1000s/%s/%s", out, c->name,
             fid == GR_FIDELITY_FULL ? "full" : "quick");
    char level[1200];
    bool existed[3] = {is_dir(out), false, is_dir(dir)};
    snprintf(level, sizeof level, "%.1000s/%s", out, c->name);
    existed[1] = is_dir(level);
    if (gr_output_dir_prepare(dir, GR_OUTPUT_CAMPAIGN, false, &err) || !realpath(dir, abs_dir)) {
        app_error("reproduce: %s: %s", dir,
                  err.message[0] ? err.message : "cannot resolve the folder");
        free(c);
        return err.code ? app_exit_code(err.code) : EXIT_FAILED;
    }
    snprintf(res_dir, sizeof res_dir, "%s", results ? results : "");
    if (!results) {
        snprintf(res_dir, sizeof res_dir, "%s/results", abs_dir);
    }
    fprintf(stderr, "reproduce: campaign %s (%s), %s fidelity, %ld points, into %s\n", c->name,
            c->covers, fid == GR_FIDELITY_FULL ? "full" : "quick", total, abs_dir);
    if (gr_campaign_materialise(c, fid, abs_dir, sweep_path, sizeof sweep_path, &err)) {
        app_error("reproduce: %s", err.message);
        free(c);
        return EXIT_FAILED;
    }
    long restored = 0;
    if (gr_campaign_restore(abs_dir, res_dir, &restored, &err)) {
        app_error("reproduce: %s", err.message);
        free(c);
        return EXIT_FAILED;
    }
    if (restored) {
        fprintf(stderr, "reproduce: %ld finished points restored from %s/points\n", restored,
                res_dir);
    }
    if (!collect) {
        char *sargv[20] = {"sweep", sweep_path};
        int sargc = 2;
        for (int i = 0; i < n_pass; i++) {
            sargv[sargc++] = pass[i];
        }
        if (!one_point) {
            sargv[sargc++] =
                "--all"; /* every point here, even inside a batch-array task's environment */
        }
        rc = cmd_sweep(sargc, sargv);
        if (rc == EXIT_REFUSED) { /* the sweep said why: a key or value of the campaign */
            if (!mpi_worker()) {
                undo_materialise(abs_dir, existed);
                app_error("reproduce: %s refused: the sweep above was written from its [sweep.F], "
                          "[vary.F] and [set] "
                          "sections; nothing was run or kept",
                          c->source);
            }
            free(c);
            return rc;
        }
        if (one_point || mpi_worker()) {
            free(c);
            return rc; /* the other points run elsewhere: analyse with --collect when all are done */
        }
    }
    long finished = 0;
    static char notes[8192];
    const int arc =
        gr_campaign_analyse(c, fid, abs_dir, res_dir, &finished, notes, sizeof notes, &err);
    for (char *line = notes, *nl; *line;
         line = nl + 1) { /* the analysis's notes, one "reproduce: " line each */
        nl = strchr(line, '\n');
        fprintf(stderr, "reproduce: %.*s\n", nl ? (int)(nl - line) : (int)strlen(line), line);
        if (!nl) {
            break;
        }
    }
    if (arc) {
        app_error("reproduce: %s", err.message);
        free(c);
        return EXIT_FAILED;
    }
    print_results(res_dir);
    fflush(stdout); /* the tables before the warning below, also when both streams go to one pipe */
    if (finished < total) {
        fprintf(stderr,
                "reproduce: %s: only %ld of %ld points are finished; the numbers above use those "
                "(run the campaign "
                "again to continue)\n",
                c->name, finished, total);
        rc = rc ? rc : EXIT_FAILED;
    }
    free(c);
    return rc;
}
