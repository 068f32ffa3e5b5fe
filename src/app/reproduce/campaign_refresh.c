/* A committed result set judged by today's campaign file: the numbers (value, error, seeds, fit)
 * are the set's, measured once; the words and the judgement (title, note, where the thesis's values
 * come from, the verdict, the thesis's values and how ours is compared with them) are the campaign
 * file's, so a corrected thesis value, a new kind of comparison or a revised verdict reaches the page
 * without rerunning anything (some analyses need run tables a result set does not archive). */
#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

static void set_string(cJSON *o, const char *name, const char *value)
{
    cJSON_DeleteItemFromObject(o, name);
    cJSON_AddStringToObject(o, name, value);
}

static void set_number(cJSON *o, const char *name, double value)
{
    cJSON_DeleteItemFromObject(o, name);
    if (isfinite(value)) {
        cJSON_AddNumberToObject(o, name, value);
    } else {
        cJSON_AddNullToObject(o, name);
    }
}

void campaign_refresh_json(const gr_campaign *c, cJSON *set)
{
    set_string(set, "title", c->title);
    set_string(set, "covers", c->covers);
    set_string(set, "about", c->about);
    cJSON *res;
    cJSON_ArrayForEach(res, cJSON_GetObjectItem(set, "results"))
    {
        const cJSON *id = cJSON_GetObjectItem(res, "id");
        const gr_campaign_result *r = NULL;
        for (int i = 0; i < c->n_results && cJSON_IsString(id); i++) {
            if (!strcmp(c->results[i].id, id->valuestring)) {
                r = &c->results[i];
            }
        }
        if (!r) { /* a result the campaign no longer has keeps its own words */
            continue;
        }
        set_string(res, "title", r->title);
        set_string(res, "thesis_source", r->thesis_source);
        set_string(res, "note", r->note);
        set_string(res, "verdict", r->verdict);
        set_string(res, "verdict_why", r->verdict_why);
        set_string(res, "restates", r->restates);
        cJSON *row;
        cJSON_ArrayForEach(row, cJSON_GetObjectItem(res, "rows"))
        {
            campaign_rows one = {0};
            campaign_row *w = campaign_rows_add(&one);
            const cJSON *g = cJSON_GetObjectItem(row, "group");
            snprintf(w->group, sizeof w->group, "%s", cJSON_IsString(g) ? g->valuestring : "");
            const double m = gr_summary_number(row, "m");
            w->m = isfinite(m) ? (int)m : 0;
            w->value = gr_summary_number(row, "value");
            w->error = gr_summary_number(row, "error");
            campaign_row_thesis(r, w);
            set_number(row, "thesis", w->thesis);
            set_number(row, "thesis_error", w->thesis_error);
            set_string(row, "thesis_note", w->thesis_note);
            set_string(row, "comparison", w->comparison);
            set_number(row, "thesis_high", w->thesis_hi);
            set_number(row, "tolerance", w->tolerance);
            cJSON_DeleteItemFromObject(row, "agrees");
            if (w->agrees >= 0) {
                cJSON_AddBoolToObject(row, "agrees", w->agrees);
            } else {
                cJSON_AddNullToObject(row, "agrees");
            }
            set_number(row, "z", w->z);
            campaign_rows_free(&one);
        }
    }
}
