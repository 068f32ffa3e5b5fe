/* docs/reproduction.md, generated from the committed result sets (RESULTS_ROOT/NAME/results.json):
 * an overview of what was run and what it cost, the tallies, every disagreement with its verdict,
 * the thesis's errata and the coverage table, linking each campaign's own page (campaign_page.c:
 * RESULTS_ROOT/NAME/README.md, one table per figure or table of the thesis). */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"
#include "app/reproduce/coverage.h"

/* short names for the two readers of a result set's fields (campaign_points.h) */
#define str campaign_json_str
#define num campaign_json_num

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* How many of a result's numbers have a z against the thesis, how many of those |z| > 2, how many
 * of those also differ from the thesis's value by more than 5 %, and how many numbers are compared
 * by a rule of their own (a value without an error, about, a range, a model's value) and how many
 * of those differ (docs/campaigns/README.md, "Kinds of comparison"). */
typedef struct tallies {
    int compared, off, off5, other, differ;
} tallies;

static void count_off(const cJSON *res, tallies *t)
{
    memset(t, 0, sizeof *t);
    if (str(res, "restates")[0]) { /* another result's numbers in another form: counted there */
        return;
    }
    const cJSON *row;
    cJSON_ArrayForEach(row, cJSON_GetObjectItem(res, "rows"))
    {
        char text[160];
        const bool differs = gr_campaign_comparison_text(row, false, text, sizeof text);
        double z = num(row, "z");
        if (isfinite(z)) {
            double th = num(row, "thesis");
            t->compared++;
            t->off += fabs(z) > 2.0;
            t->off5 += fabs(z) > 2.0 && !(fabs(num(row, "value") - th) <= 0.05 * fabs(th));
        } else if (cJSON_IsBool(
                       cJSON_GetObjectItem(row, "agrees"))) { /* judged by a rule of its own */
            t->other++;
            t->differ += differs;
        }
    }
}

/* The same over a result set. */
static void tally(const cJSON *set, tallies *t)
{
    memset(t, 0, sizeof *t);
    const cJSON *res;
    cJSON_ArrayForEach(res, cJSON_GetObjectItem(set, "results"))
    {
        tallies r;
        count_off(res, &r);
        t->compared += r.compared;
        t->off += r.off;
        t->off5 += r.off5;
        t->other += r.other;
        t->differ += r.differ;
    }
}

/* Text for a Markdown table cell: '|' escaped, line breaks as spaces. */
static void cell(FILE *f, const char *text)
{
    for (const char *c = text; *c; c++) {
        if (*c == '|') {
            fputs("\\|", f);
        } else {
            fputc(*c == '\n' ? ' ' : *c, f);
        }
    }
}

/* Every result with a row at |z| > 2 and the campaign's verdict on it (campaign files, key verdict),
 * so a reader sees at a glance which disagreements are understood. */
static void disagreements(FILE *f, cJSON *const *sets, int ns, const char *base)
{
    int judged[GR_CAMPAIGN_VERDICTS + 1] = {0}, total = 0; /* the last: not investigated yet */
    const cJSON *res;
    for (int i = 0; i < ns; i++) {
        cJSON_ArrayForEach(res, cJSON_GetObjectItem(sets[i], "results"))
        {
            tallies t;
            count_off(res, &t);
            if (t.off || t.differ) {
                int k = 0;
                while (k < GR_CAMPAIGN_VERDICTS &&
                       strcmp(str(res, "verdict"), gr_campaign_verdicts[k])) {
                    k++;
                }
                judged[k]++;
                total++;
            }
        }
    }
    fprintf(f,
            "## Where granule and the thesis disagree\n\n"
            "%d results have at least one number at |z| > 2 or outside a value the thesis states "
            "without an "
            "error: %d explained, %d partly explained, %d unexplained, %d not investigated yet. "
            "The verdict is "
            "the campaign's (key `verdict` in docs/campaigns/NAME.ini); the evidence is in the "
            "result's note on its campaign's page.\n\n"
            "| result | what | \\|z\\| > 2 | differs (no z) | verdict | why "
            "|\n|---|---|---|---|---|---|\n",
            total, judged[0], judged[1], judged[2], judged[GR_CAMPAIGN_VERDICTS]);
    for (int i = 0; i < ns; i++) {
        cJSON_ArrayForEach(res, cJSON_GetObjectItem(sets[i], "results"))
        {
            tallies t;
            count_off(res, &t);
            if (!t.off && !t.differ) {
                continue;
            }
            const char *v = str(res, "verdict");
            fprintf(f, "| [%s: %s](%s/%s/README.md#%s-%s) | %s | %d of %d | %d of %d | %s | ",
                    str(sets[i], "campaign"), str(res, "id"), base, str(sets[i], "campaign"),
                    str(sets[i], "campaign"), str(res, "id"), str(res, "title"), t.off, t.compared,
                    t.differ, t.other, v[0] ? v : "**not investigated yet**");
            cell(f, str(res, "verdict_why"));
            fprintf(f, " |\n");
        }
    }
    fprintf(f, "\n");
}

/* The table of docs/thesis-errata.md (beside the results folder), so the page lists every slip
 * found in the thesis where its verdicts name them. */
static void errata(FILE *f, const char *root)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/../thesis-errata.md", root);
    FILE *in = fopen(path, "r");
    if (!in) {
        return;
    }
    fprintf(f, "## Thesis errata\n\nSlips in the thesis found while reproducing it, from "
               "[thesis-errata.md](thesis-errata.md): the "
               "thesis contradicts its own parameters, columns or derivation. Our numbers are "
               "compared with the values as "
               "printed; the notes below name the slip where it matters.\n\n");
    char line[8192];
    bool in_table = false;
    while (fgets(line, sizeof line, in)) {
        if (line[0] == '|') {
            fputs(line, f);
            in_table = true;
        } else if (in_table) {
            break;
        }
    }
    fclose(in);
    fprintf(f, "\n");
}

int gr_reproduction_page(const char *root, const char *out_path, gr_error *err)
{
    DIR *d = opendir(root);
    if (!d) {
        return GR_FAIL(err, GR_EIO,
                       "%s: no result sets (granule reproduce NAME --results %s/NAME writes one)",
                       root, root);
    }
    char *names[256];
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) && n < 256) {
        if (e->d_name[0] != '.') {
            names[n++] = strdup(e->d_name);
        }
    }
    closedir(d);
    qsort(names, (size_t)n, sizeof *names, by_name);
    cJSON *sets[256];
    int ns = 0, rc = GR_OK;
    for (int i = 0; i < n; i++) {
        char path[1300];
        snprintf(path, sizeof path, "%s/%s/results.json", root, names[i]);
        gr_error ignore = {0};
        cJSON *j = gr_json_read(path, &ignore);
        if (j) {
            sets[ns++] = j;
            gr_campaign c;
            const cJSON *name = cJSON_GetObjectItem(j, "campaign");
            if (!cJSON_IsString(name)) {
                rc = GR_FAIL(err, GR_EINVAL, "%s: no campaign name", path);
                goto done;
            }
            if ((rc =
                     gr_campaign_load(&c, name->valuestring,
                                      err))) { /* a broken campaign file never gives a stale page */
                goto done;
            }
            campaign_refresh_json(&c, j); /* today's words and judgement, the set's numbers */
        }
    }
    char dir[1100], base[256];
    snprintf(dir, sizeof dir, "%s", out_path);
    char *slash = strrchr(dir, '/');
    const char *file = slash ? slash + 1 : out_path;
    if (slash) {
        *slash = 0;
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    const char *rb = strrchr(root, '/');
    snprintf(base, sizeof base, "%s",
             rb ? rb + 1 : root); /* the page sits beside the results folder */
    char problems[2048];
    const int uncovered = gr_reproduction_coverage(NULL, root, problems, sizeof problems);
    if (uncovered) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "%s/../thesis-coverage.md disagrees with the campaigns in %d place%s: %s",
                     root, uncovered, uncovered > 1 ? "s" : "", problems);
        goto done;
    }
    for (int i = 0; i < ns; i++) { /* each campaign's own page, then the overview linking them */
        if ((rc = campaign_page_write(sets[i], root, file, err))) {
            goto done;
        }
    }
    gr_file f;
    rc = gr_file_open(&f, dir, file, err);
    if (rc) {
        goto done;
    }
    fprintf(
        f.f,
        "# Reproducing the thesis\n\n"
        "<!-- generated by `granule reproduce --page` from %s/*/results.json: do not edit; change\n"
        "     docs/campaigns/*.ini or the campaign notes and regenerate -->\n\n"
        "Every number below comes from a campaign, a file under `docs/campaigns/` that names the "
        "scene, the\n"
        "runs (sizes, run lengths, seeds) and the analysis; `granule reproduce NAME --fidelity "
        "full` runs it\n"
        "(resumable at any point, over local cores, MPI ranks or a batch array like `granule "
        "sweep`), and\n"
        "its small result set is committed under `docs/results/NAME/`, with its own page there "
        "(README.md,\n"
        "linked from the table below: every result's numbers, note and figures). Error bars come "
        "from independent\n"
        "seeds (docs/campaigns/README.md says how). The energy loss per collision of Fig. 2.5 is "
        "checked in\n"
        "[collision-accuracy.md](collision-accuracy.md) and by tests/test_collide.c.\n\n"
        "**Kinds of comparison.** Only a thesis value quoted with an error gives a z = (granule - "
        "thesis) /\n"
        "sqrt(error^2 + thesis error^2), in bold where |z| > 2. Every other thesis statement is "
        "compared by\n"
        "its own rule and never gives a z: a value quoted without an error agrees when ours +- 2 "
        "errors\n"
        "reaches it within half a unit of its last digit; \"about X\" when ours +- 2 errors "
        "reaches X to one\n"
        "significant figure; a range when ours +- 2 errors overlaps it; a model's value (the "
        "bisection model,\n"
        "the SPM: not a measurement of the thesis) by the value rule; a quantity equal by "
        "construction is\n"
        "no result. \"with z\" counts the numbers with a z, \"|z| > 2\" how many of them disagree "
        "and\n"
        "\"> 5 %%\" how many of those also differ by more than 5 %%; \"other\" counts the numbers "
        "judged by\n"
        "the other rules and \"differ\" how many of those do not agree (a number without an error "
        "of ours,\n"
        "from one run, is shown with its difference but not judged).\n\n"
        "**Verdicts.** A result that disagrees is *explained* only when a committed run isolates "
        "the\n"
        "mechanism: the quantity moves toward the thesis as the named cause is varied, with the "
        "trend\n"
        "significant in committed data. Otherwise it is *partly explained* (part of the difference "
        "is\n"
        "accounted for that way) or *unexplained* (the checks in its note did not find the cause). "
        "The\n"
        "numbers a note quotes are in committed files under docs/results/ (an investigation it "
        "names is\n"
        "linked).",
        root);
    fprintf(
        f.f,
        "\n\n| campaign | covers | fidelity | points | simulated s | CPU-h | with z | \\|z\\| > 2 "
        "| > 5 %% | other | differ |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n");
    double total = 0.0;
    tallies all = {0};
    for (int i = 0; i < ns; i++) {
        tallies t;
        tally(sets[i], &t);
        all.compared += t.compared;
        all.off += t.off;
        all.off5 += t.off5;
        all.other += t.other;
        all.differ += t.differ;
        fprintf(
            f.f,
            "| [%s](%s/%s/README.md) | %s | %s | %.0f of %.0f | %.0f | %.2f | %d | %d | %d | %d "
            "| %d |\n",
            str(sets[i], "campaign"), base, str(sets[i], "campaign"), str(sets[i], "covers"),
            str(sets[i], "fidelity"), num(sets[i], "points_finished"), num(sets[i], "points_total"),
            num(sets[i], "simulated_seconds"), num(sets[i], "cpu_seconds") / 3600.0, t.compared,
            t.off, t.off5, t.other, t.differ);
        total += num(sets[i], "cpu_seconds");
    }
    /* the built-in campaigns without a result set here */
    const char *builtin[64];
    int nb = gr_campaign_names(builtin, 64);
    for (int b = 0; b < nb; b++) {
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)(strlen(builtin[b]) - 14), builtin[b] + 10);
        bool have = false;
        for (int i = 0; i < ns; i++) {
            have |= !strcmp(str(sets[i], "campaign"), name);
        }
        gr_campaign c;
        gr_error ignore = {0};
        if (!have && gr_campaign_load(&c, name, &ignore) == GR_OK) {
            fprintf(f.f, "| %s | %s | not run yet | 0 of %ld | | | | | | | |\n", name, c.covers,
                    gr_campaign_points(&c, GR_FIDELITY_FULL));
        }
    }
    fprintf(f.f, "| total | | | | | %.2f | %d | %d | %d | %d | %d |\n\n", total / 3600.0,
            all.compared, all.off, all.off5, all.other, all.differ);
    disagreements(f.f, sets, ns, base);
    errata(f.f, root);
    gr_reproduction_coverage(f.f, root, problems, sizeof problems);
    rc = gr_file_commit(&f, err);
done:
    for (int i = 0; i < ns; i++) {
        cJSON_Delete(sets[i]);
    }
    for (int i = 0; i < n; i++) {
        free(names[i]);
    }
    return rc;
}
