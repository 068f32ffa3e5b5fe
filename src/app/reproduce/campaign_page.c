/* docs/results/NAME/README.md, one campaign's page, generated with the overview (reproduction_page.c)
 * from its committed result set: what was run and what it cost, the error bars and the warm-up check,
 * then one table per figure or table of the thesis (the thesis's value, ours +- error, the
 * comparison, seeds and CPU time) with its note and figures. */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "app/reproduce/campaign_points.h"

/* short names for the two readers of a result set's fields */
#define str campaign_json_str
#define num campaign_json_num

const char *campaign_json_str(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItem(o, name);
    return cJSON_IsString(v) ? v->valuestring : "";
}

double campaign_json_num(const cJSON *o, const char *name)
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

/* A Markdown image line if ROOT/CAMPAIGN/ID SUFFIX.png exists (the page sits beside it). */
static void figure(FILE *f, const char *root, const char *campaign, const char *id,
                   const char *suffix)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/%s/%s%s.png", root, campaign, id, suffix);
    if (access(path, R_OK) == 0) {
        fprintf(f, "![%s%s](%s%s.png)\n", id, suffix, id, suffix);
    }
}

/* TEXT with every "results/investigations/NAME" that names a committed file (ROOT/investigations/NAME)
 * written as a link to it (from the campaign's page, ../investigations/NAME), so each number a note
 * quotes from an investigation is one click away. */
static void text_with_links(FILE *f, const char *text, const char *root)
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
            fprintf(f, "[%.*s](../investigations/%.*s)", (int)(end - hit), hit, (int)(end - name),
                    name);
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
                              bool numbers)
{
    if (str(res, "restates")[0]) {
        fprintf(f,
                "\nThese numbers restate those of [%s](#%s-%s) in another form; the tallies count "
                "them there only.\n",
                str(res, "restates"), campaign, str(res, "restates"));
    }
    if (str(res, "note")[0]) {
        fputc('\n', f);
        text_with_links(f, str(res, "note"), root);
        fputc('\n', f);
    }
    if (str(res, "thesis_source")[0]) {
        fprintf(f, "\nThesis%s: %s.\n", numbers ? " values" : "", str(res, "thesis_source"));
    }
    fprintf(f, "\n");
    if (numbers) {
        figure(f, root, campaign, str(res, "id"), "");
    }
    figure(f, root, campaign, str(res, "id"), "_data");
    figure(f, root, campaign, str(res, "id"), "_slopes"); /* local slopes against x */
    fprintf(f, "\n");
}

static void result_table(FILE *f, const cJSON *res, const char *campaign, const char *root)
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
        notes_and_figures(f, res, campaign, root, false);
        return;
    }
    if (!curves) { /* a partial campaign whose runs for this result have not finished */
        fprintf(f, "No run of this result has finished yet.\n");
        notes_and_figures(f, res, campaign, root, false);
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
            snprintf(fit, sizeof fit, "local slope between %.6g and %.6g", num(row, "x_lo"),
                     num(row, "x_hi"));
        } else if (isfinite(num(row, "fit_points")) && num(row, "fit_points") < 3) {
            snprintf(fit, sizeof fit, "%.0f of the 3 points a fit needs", num(row, "fit_points"));
        } else if (isfinite(num(row, "fit_points"))) {
            snprintf(fit, sizeof fit, "%.0f points, %.6g-%.6g, chi2/dof %.2g",
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
    notes_and_figures(f, res, campaign, root, true);
}

int campaign_page_write(const cJSON *s, const char *root, const char *overview, gr_error *err)
{
    char dir[1300];
    snprintf(dir, sizeof dir, "%s/%s", root, str(s, "campaign"));
    gr_file f;
    int rc = gr_file_open(&f, dir, "README.md", err);
    if (rc) {
        return rc;
    }
    fprintf(f.f,
            "<!-- generated by `granule reproduce --page` from results.json: do not edit; change\n"
            "     docs/campaigns/%s.ini and regenerate -->\n\n"
            "<a id=\"%s\"></a>\n# %s (%s)\n\n"
            "One campaign of [the thesis's reproduction](../../%s), which says how values are "
            "compared and judged and lists every disagreement.\n\n%s\n\n",
            str(s, "campaign"), str(s, "campaign"), str(s, "title"), str(s, "covers"), overview,
            str(s, "about"));
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
                     " (%.0f more runs were restored from an archive without their T(t))", without);
        }
        fprintf(f.f,
                "Warm-up check: over %.0f runs%s, <T> in the first quarter of the sampling "
                "differs from the rest by "
                "%+.1f %% +- %.1f %% (z = %+.1f)%s\n\n",
                num(w, "runs"), missing, 100.0 * num(w, "drift"), 100.0 * num(w, "drift_error"), z,
                fabs(z) > 2.0 ? ": **the warm-up may be too short**."
                              : ": no sign of a transient left in the sampling.");
    }
    const cJSON *res;
    cJSON_ArrayForEach(res, cJSON_GetObjectItem(s, "results"))
    {
        result_table(f.f, res, str(s, "campaign"), root);
    }
    return gr_file_commit(&f, err);
}
