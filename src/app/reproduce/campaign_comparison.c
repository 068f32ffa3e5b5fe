/* A row of a result set against the thesis, in words (docs/campaigns/README.md, "Kinds of
 * comparison"): only a thesis value with an error gives a z; a value without one, an "about", a
 * range or a model's value says whether ours agrees within its own +- 2 errors; a quantity equal
 * by construction is no result. The page and `granule reproduce` print the same words. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/campaign.h"
#include "io/summary_read.h"

/* The kind of a row; result sets collected before the kinds existed: z with an error, else stated. */
static const char *kind_of(const cJSON *row)
{
    const cJSON *k = cJSON_GetObjectItem(row, "comparison");
    if (cJSON_IsString(k)) {
        return k->valuestring;
    }
    const double t = gr_summary_number(row, "thesis"), e = gr_summary_number(row, "thesis_error");
    return !isfinite(t) ? "" : e > 0.0 ? "z" : "stated";
}

bool gr_campaign_comparison_text(const void *json_row, bool bold, char *out, size_t len)
{
    const cJSON *row = json_row;
    const char *kind = kind_of(row);
    const double v = gr_summary_number(row, "value"), t = gr_summary_number(row, "thesis");
    out[0] = 0;
    if (!kind[0] || !isfinite(t)) {
        return false;
    }
    if (!strcmp(kind, "construction")) {
        snprintf(out, len, "equal by construction (not a result)");
        return false;
    }
    if (!isfinite(v)) {
        return false;
    }
    const char *b = bold ? "**" : "";
    if (!strcmp(kind, "z")) {
        const double z = gr_summary_number(row, "z");
        if (!isfinite(z)) {
            return false;
        }
        const bool off = fabs(z) > 2.0;
        snprintf(out, len, "%sz = %+.1f%s", off ? b : "", z, off ? b : "");
        return off;
    }
    const cJSON *a = cJSON_GetObjectItem(row, "agrees");
    const double e = gr_summary_number(row, "error");
    const double rel = t != 0.0 ? 100.0 * (v - t) / fabs(t) : (double)NAN;
    bool agrees;
    if (cJSON_IsBool(a)) {
        agrees = cJSON_IsTrue(a);
    } else if (!(e >= 0.0)) { /* one run, no error of ours: a difference, no judgement */
        snprintf(out, len, "%+.1f %% (no error of ours to judge by)", rel);
        return false;
    } else { /* an old result set: within 2 errors or to 1e-4 */
        agrees = fabs(v - t) <= 2.0 * e + 1e-4 * fabs(t);
    }
    const char *o = agrees ? "" : b;
    if (!strcmp(kind, "range")) {
        snprintf(out, len, "%s%s %g .. %g%s", o, agrees ? "inside" : "outside", t,
                 gr_summary_number(row, "thesis_high"), o);
    } else if (!strcmp(kind, "about")) {
        snprintf(out, len, "%s%+.0f %%: %s about %g%s", o, rel,
                 agrees ? "agrees with" : "differs from", t, o);
    } else if (!strcmp(kind, "model")) {
        snprintf(out, len, "%s%+.1f %%: %s the model's %g%s", o, rel,
                 agrees ? "agrees with" : "differs from", t, o);
    } else {
        snprintf(out, len, "%s%+.1f %%: %s the stated %g%s", o, rel,
                 agrees ? "agrees with" : "differs from", t, o);
    }
    return !agrees;
}
