/* docs/reproduction.md, generated from the committed result sets (RESULTS_ROOT/NAME/results.json):
 * an overview of what was run and what it cost, then one section per campaign and one table per
 * figure or table of the thesis: the thesis's value, ours +- error, z, seeds and CPU time. */
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

static const char *str(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(o, name);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static double num(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(o, name);
    return cJSON_IsNumber(v) ? v->valuedouble : (double)NAN;
}

/* value +- error with the error to two significant figures and the value to the same place */
static void pm(char *out, size_t len, double v, double e)
{
    if (!isfinite(v)) {
        snprintf(out, len, "no value");
        return;
    }
    if (!isfinite(e) || e <= 0.0) {
        snprintf(out, len, "%.4g", v);
        return;
    }
    int digits = 1 - (int)floor(log10(e));
    digits = digits < 0 ? 0 : digits > 8 ? 8 : digits;
    snprintf(out, len, "%.*f +- %.*f", digits, v, digits, e);
}

/* A thesis value as the thesis printed it (rounding it to its error's digits would change it). */
static void quoted(char *out, size_t len, double v, double e)
{
    if (isfinite(e) && e > 0.0) {
        snprintf(out, len, "%g +- %g", v, e);
    } else {
        snprintf(out, len, "%g", v);
    }
}

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

/* A Markdown image line if ROOT/CAMPAIGN/NAME exists. */
static void figure(FILE *f, const char *root, const char *link_root, const char *campaign,
                   const char *id, const char *suffix)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/%s/%s%s.png", root, campaign, id, suffix);
    if (access(path, R_OK) == 0) {
        fprintf(f, "![%s%s](%s/%s/%s%s.png)\n", id, suffix, link_root, campaign, id, suffix);
    }
}

/* TEXT with every "results/investigations/NAME" that names a committed file (ROOT/investigations/NAME)
 * written as a link to it, so each number a note quotes from an investigation is one click away. */
static void text_with_links(FILE *f, const char *text, const char *root, const char *link_root)
{
    static const char key[] = "results/investigations/";
    const char *c = text;
    for (const char *hit; (hit = strstr(c, key)); c = hit) {
        const char *name = hit + strlen(key), *end = name;
        while (isalnum((unsigned char)*end) || *end == '.' || *end == '-' || *end == '_') {
            end++;
        }
        while (end > name && end[-1] == '.') { /* a sentence's full stop is not part of the name */
            end--;
        }
        char path[1400];
        snprintf(path, sizeof path, "%s/investigations/%.*s", root, (int)(end - name), name);
        fwrite(c, 1, (size_t)(hit - c), f);
        if (end > name && access(path, R_OK) == 0) {
            fprintf(f, "[%.*s](%s/investigations/%.*s)", (int)(end - hit), hit, link_root,
                    (int)(end - name), name);
        } else {
            fwrite(hit, 1, (size_t)(end - hit), f);
        }
        hit = end;
    }
    fputs(c, f);
}

/* A result's note, where the thesis's values come from, and its figures (the comparison only when
 * there are numbers to compare). */
static void notes_and_figures(FILE *f, const cJSON *res, const char *campaign, const char *root,
                              const char *link_root, bool numbers)
{
    if (str(res, "restates")[0]) {
        fprintf(f,
                "\nThese numbers restate those of [%s](#%s-%s) in another form; the tallies count "
                "them there only.\n",
                str(res, "restates"), campaign, str(res, "restates"));
    }
    if (str(res, "note")[0]) {
        fputc('\n', f);
        text_with_links(f, str(res, "note"), root, link_root);
        fputc('\n', f);
    }
    if (str(res, "thesis_source")[0]) {
        fprintf(f, "\nThesis%s: %s.\n", numbers ? " values" : "", str(res, "thesis_source"));
    }
    fprintf(f, "\n");
    if (numbers) {
        figure(f, root, link_root, campaign, str(res, "id"), "");
    }
    figure(f, root, link_root, campaign, str(res, "id"), "_data");
    figure(f, root, link_root, campaign, str(res, "id"), "_slopes"); /* local slopes against x */
    fprintf(f, "\n");
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
static void disagreements(FILE *f, cJSON *const *sets, int ns)
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
            "result's note below.\n\n"
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
            fprintf(f, "| [%s: %s](#%s-%s) | %s | %d of %d | %d of %d | %s | ",
                    str(sets[i], "campaign"), str(res, "id"), str(sets[i], "campaign"),
                    str(res, "id"), str(res, "title"), t.off, t.compared, t.differ, t.other,
                    v[0] ? v : "**not investigated yet**");
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

static void result_table(FILE *f, const cJSON *res, const char *campaign, const char *root,
                         const char *link_root)
{
    fprintf(f, "<a id=\"%s-%s\"></a>\n### %s: %s\n\n", campaign, str(res, "id"), str(res, "id"),
            str(res, "title"));
    const cJSON *row;
    bool values = false;
    double runs = 0.0, cpu = 0.0;
    int curves = 0;
    cJSON_ArrayForEach(row, cJSON_GetObjectItem(res, "rows"))
    {
        values |= isfinite(num(row, "value"));
        runs += num(row, "seeds");
        cpu += num(row, "cpu_seconds");
        curves++;
    }
    if (!values &&
        !strcmp(str(res, "kind"), "curve")) { /* a figure to compare by eye: no table of blanks */
        fprintf(f,
                "A figure only (the thesis gives no number): %d curves from %.0f runs, %.2f "
                "CPU-hours.\n",
                curves, runs, cpu / 3600.0);
        notes_and_figures(f, res, campaign, root, link_root, false);
        return;
    }
    if (!curves) { /* a partial campaign whose runs for this result have not finished */
        fprintf(f, "No run of this result has finished yet.\n");
        notes_and_figures(f, res, campaign, root, link_root, false);
        return;
    }
    const char *unit = str(res, "unit");
    fprintf(f,
            "| %s | thesis%s%s%s | granule | comparison | seeds | fit / runs | CPU-h "
            "|\n|---|---|---|---|---|---|---|\n",
            !strcmp(str(res, "kind"), "power_law") ? "fit of" : "run", unit[0] ? " (" : "", unit,
            unit[0] ? ")" : "");
    cJSON_ArrayForEach(row, cJSON_GetObjectItem(res, "rows"))
    {
        char ours[64], theirs[96], group[200], fit[96] = "";
        pm(ours, sizeof ours, num(row, "value"), num(row, "error"));
        double tv = num(row, "thesis");
        if (isfinite(tv)) {
            quoted(theirs, sizeof theirs, tv, num(row, "thesis_error"));
            const char *kind = str(row, "comparison");
            if (!strcmp(kind, "range")) {
                snprintf(theirs, sizeof theirs, "%g .. %g", tv, num(row, "thesis_high"));
            } else if (!strcmp(kind, "about") || !strcmp(kind, "model")) {
                snprintf(theirs, sizeof theirs, "%s %g", kind[0] == 'a' ? "about" : "model:", tv);
            }
            if (str(row, "thesis_note")[0]) {
                snprintf(theirs + strlen(theirs), sizeof theirs - strlen(theirs), " %s",
                         str(row, "thesis_note"));
            }
        } else {
            snprintf(theirs, sizeof theirs, "not quoted");
        }
        campaign_pretty_group(str(row, "group"), group, sizeof group);
        if (isfinite(num(row, "m"))) {
            snprintf(group + strlen(group), sizeof group - strlen(group), ", m = %.0f",
                     num(row, "m"));
        }
        if (!strcmp(str(row, "role"), "trend")) {
            snprintf(fit, sizeof fit,
                     "local slope's change per unit ln x (quadratic in ln x, %.0f "
                     "points, chi2/dof %.2g)",
                     num(row, "fit_points"), num(row, "chi2_red"));
        } else if (num(row, "fit_points") == 2 && isfinite(num(row, "value"))) {
            snprintf(fit, sizeof fit, "local slope between %.4g and %.4g", num(row, "x_lo"),
                     num(row, "x_hi"));
        } else if (isfinite(num(row, "fit_points")) && num(row, "fit_points") < 3) {
            snprintf(fit, sizeof fit, "%.0f of the 3 points a fit needs", num(row, "fit_points"));
        } else if (isfinite(num(row, "fit_points"))) {
            snprintf(fit, sizeof fit, "%.0f points, %.4g-%.4g, chi2/dof %.2g",
                     num(row, "fit_points"), num(row, "x_lo"), num(row, "x_hi"),
                     num(row, "chi2_red"));
        } else {
            snprintf(fit, sizeof fit, "%.0f s simulated", num(row, "simulated_seconds"));
        }
        char zs[160];
        gr_campaign_comparison_text(row, true, zs, sizeof zs);
        char seeds[64]; /* T's block-error convergence is summarised once per campaign */
        snprintf(seeds, sizeof seeds, "%.0f", num(row, "seeds"));
        fprintf(f, "| %s | %s | %s | %s | %s | %s | %.2f |\n", group, theirs, ours, zs, seeds, fit,
                num(row, "cpu_seconds") / 3600.0);
    }
    notes_and_figures(f, res, campaign, root, link_root, true);
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
        "its small result set is committed under `docs/results/NAME/`. Error bars come from "
        "independent\n"
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
        fprintf(f.f,
                "| [%s](#%s) | %s | %s | %.0f of %.0f | %.0f | %.2f | %d | %d | %d | %d | %d |\n",
                str(sets[i], "campaign"), str(sets[i], "campaign"), str(sets[i], "covers"),
                str(sets[i], "fidelity"), num(sets[i], "points_finished"),
                num(sets[i], "points_total"), num(sets[i], "simulated_seconds"),
                num(sets[i], "cpu_seconds") / 3600.0, t.compared, t.off, t.off5, t.other, t.differ);
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
    disagreements(f.f, sets, ns);
    errata(f.f, root);
    gr_reproduction_coverage(f.f, root, problems, sizeof problems);
    for (int i = 0; i < ns; i++) {
        const cJSON *s = sets[i];
        fprintf(f.f, "<a id=\"%s\"></a>\n## %s (%s)\n\n%s\n\n", str(s, "campaign"), str(s, "title"),
                str(s, "covers"), str(s, "about"));
        fprintf(f.f,
                "Run: `granule reproduce %s --fidelity %s` (scene `docs/scenes/%s`); %.0f of %.0f "
                "points finished, "
                "%.0f s simulated, %.2f CPU-hours; analysed at commit %s.\n\n",
                str(s, "campaign"), str(s, "fidelity"), str(s, "scene"), num(s, "points_finished"),
                num(s, "points_total"), num(s, "simulated_seconds"), num(s, "cpu_seconds") / 3600.0,
                str(s, "commit"));
        int bad = 0, rows_seen = 0, few = 0;
        const cJSON *rs, *rw;
        cJSON_ArrayForEach(rs, cJSON_GetObjectItem(s, "results"))
        {
            cJSON_ArrayForEach(rw, cJSON_GetObjectItem(rs, "rows"))
            {
                rows_seen++;
                bad += num(rw, "runs_not_converged") > 0;
                few += isfinite(num(rw, "value")) && num(rw, "seeds") < 3;
            }
        }
        if (bad) {
            fprintf(f.f,
                    "Error bars: %d of the %d numbers below rest on runs whose block-averaging "
                    "error of T did not converge "
                    "(the blocking never reached a plateau, so a run's own error bar is a lower "
                    "bound). Where a number "
                    "averages three or more independent seeds its error is the seeds' spread, "
                    "which does not depend on that; "
                    "%d number%s from fewer seeds use%s the larger of the spread and the runs' own "
                    "errors and may be "
                    "too small.\n\n",
                    bad, rows_seen, few, few == 1 ? "" : "s", few == 1 ? "s" : "");
        }
        const cJSON *w = cJSON_GetObjectItem(s, "warmup_check");
        const cJSON *na = cJSON_GetObjectItem(w, "not_applicable");
        const cJSON *unavailable = cJSON_GetObjectItem(w, "not_available");
        if (cJSON_IsString(na)) {
            fprintf(f.f, "Warm-up check: not applicable (%s).\n\n", na->valuestring);
        } else if (cJSON_IsString(unavailable)) {
            fprintf(f.f, "Warm-up check: not available (%s).\n\n", unavailable->valuestring);
        } else if (w) {
            double z = num(w, "z"), without = num(w, "runs_without_series");
            char missing[160] = "";
            if (without > 0.0) {
                snprintf(missing, sizeof missing,
                         " (%.0f more runs were restored from an archive without their T(t))",
                         without);
            }
            fprintf(f.f,
                    "Warm-up check: over %.0f runs%s, <T> in the first quarter of the sampling "
                    "differs from the rest by "
                    "%+.1f %% +- %.1f %% (z = %+.1f)%s\n\n",
                    num(w, "runs"), missing, 100.0 * num(w, "drift"), 100.0 * num(w, "drift_error"),
                    z,
                    fabs(z) > 2.0 ? ": **the warm-up may be too short**."
                                  : ": no sign of a transient left in the sampling.");
        }
        const cJSON *res;
        cJSON_ArrayForEach(res, cJSON_GetObjectItem(s, "results"))
        {
            result_table(f.f, res, str(s, "campaign"), root, base);
        }
    }
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
