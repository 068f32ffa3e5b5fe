/* A campaign file (docs/campaigns/README.md): [campaign] (title, covers, scene, about), the sweep of
 * each fidelity ([sweep.quick] / [sweep.full] seeds, [vary.quick] / [vary.full] lists, [set] for
 * both and [set.quick] / [set.full]) and one [result ID] section per figure or table. Loading
 * checks every key; materialising writes a plain sweep file beside the embedded scene. */
#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "granule/campaign.h"
#include "io/files.h"
#include "scene/scene_lines.h"
#include "app/reproduce/campaign_points.h"
#include "app/reproduce/embedded.h"

const char *gr_embedded_find(const char *name)
{
    for (int i = 0; i < gr_embedded_count; i++) {
        if (!strcmp(gr_embedded_files[i].name, name)) {
            return gr_embedded_files[i].text;
        }
    }
    return NULL;
}

#define SEEN_MAX 1024

typedef struct parse_ctx {
    gr_campaign *c;
    const gr_line_reader *lines;
    char (*seen)[176]; /* "section\x1fkey" of every line so far, to refuse a key given twice */
    int n_seen;
    char last[176]; /* the line before: a [vary.F] list continues on a line that repeats its key */
    char error[512];
} parse_ctx;

/* May `name` appear on several lines of `section` (text that continues, a [vary.F] list that goes
 * on on the very next line)? */
static bool may_repeat(const char *section, const char *name)
{
    if (!strcmp(section, "campaign")) {
        return !strcmp(name, "about");
    }
    if (!strncmp(section, "result ", 7)) {
        return !strcmp(name, "thesis") || !strcmp(name, "note") || !strcmp(name, "verdict");
    }
    return false;
}

/* A key given twice in one section is refused as in scenes; a repeated section is one section. */
static int check_repeat(parse_ctx *p, const char *section, const char *name)
{
    char id[176];
    snprintf(id, sizeof id, "%.80s\x1f%.90s", section, name);
    const bool continues = !strncmp(section, "vary.", 5) && !strcmp(id, p->last);
    snprintf(p->last, sizeof p->last, "%s", id);
    if (continues || may_repeat(section, name)) {
        return 1;
    }
    for (int i = 0; i < p->n_seen; i++) {
        if (!strcmp(p->seen[i], id)) {
            snprintf(p->error, sizeof p->error, "[%s] %s: given twice%s", section, name,
                     !strncmp(section, "vary.", 5)
                         ? "; a list longer than a line continues on the very next line"
                         : "");
            return 0;
        }
    }
    if (p->n_seen == SEEN_MAX) {
        snprintf(p->error, sizeof p->error, "[%s] %s: more than %d lines in the campaign file",
                 section, name, SEEN_MAX);
        return 0;
    }
    snprintf(p->seen[p->n_seen++], sizeof p->seen[0], "%s", id);
    return 1;
}

static bool parse_double(const char *v, double *out)
{
    char *end;
    double x = strtod(v, &end);
    while (isspace((unsigned char)*end)) {
        end++;
    }
    if (end == v || *end || !isfinite(x)) {
        return false;
    }
    *out = x;
    return true;
}

/* Appends a key that may continue over several lines (about, thesis, note) to dst; refuses when
 * the whole would not fit instead of cutting it short on the page. */
static int append_text(parse_ctx *p, const char *section, const char *name, char *dst, size_t size,
                       const char *sep, const char *value)
{
    const size_t len = strlen(dst), add = (len ? strlen(sep) : 0) + strlen(value);
    if (len + add >= size) {
        snprintf(p->error, sizeof p->error,
                 "[%s] %s: %zu characters in all, at most %zu (shorten it)", section, name,
                 len + add, size - 1);
        return 0;
    }
    snprintf(dst + len, size - len, "%s%s", len ? sep : "", value);
    return 1;
}

/* [sweep.F] seeds: decimal integers, none twice (two points would be one run) */
static int check_seeds(parse_ctx *p, const char *section, const char *value)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", value);
    unsigned long long seen[64];
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        errno = 0;
        const unsigned long long seed = strtoull(tok, NULL, 10);
        if (strspn(tok, "0123456789") != strlen(tok) || strlen(tok) > 20 || errno) {
            snprintf(
                p->error, sizeof p->error,
                "[%s] seeds: '%.64s' is not an integer written in decimal digits (0 .. 2^64 - 1)",
                section, tok);
            return 0;
        }
        for (int i = 0; i < n; i++) {
            if (seen[i] == seed) {
                snprintf(p->error, sizeof p->error,
                         "[%s] seeds: %llu is listed twice (two points would be one run)", section,
                         seed);
                return 0;
            }
        }
        if (n == 64) {
            snprintf(p->error, sizeof p->error, "[%s] seeds: at most 64 seeds", section);
            return 0;
        }
        seen[n++] = seed;
    }
    return 1;
}

static int campaign_key(parse_ctx *p, const char *name, const char *value)
{
    gr_campaign *c = p->c;
    struct {
        const char *key;
        char *dst;
        size_t size;
    } keys[] = {{"title", c->title, sizeof c->title},
                {"covers", c->covers, sizeof c->covers},
                {"scene", c->scene, sizeof c->scene},
                {"about", c->about, sizeof c->about}};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        if (!strcmp(name, keys[i].key)) {
            if (!strcmp(name, "about")) { /* may continue over several lines */
                return append_text(p, "campaign", name, keys[i].dst, keys[i].size, " ", value);
            } else {
                snprintf(keys[i].dst, keys[i].size, "%s", value);
            }
            return 1;
        }
    }
    snprintf(p->error, sizeof p->error,
             "[campaign] %s: unknown key; keys: title, covers, scene, about", name);
    return 0;
}

static int result_key(parse_ctx *p, gr_campaign_result *r, const char *name, const char *value)
{
    struct {
        const char *key;
        char *dst;
        size_t size;
    } text[] = {{"title", r->title, sizeof r->title},
                {"quantity", r->quantity, sizeof r->quantity},
                {"unit", r->unit, sizeof r->unit},
                {"y", r->y, sizeof r->y},
                {"y_err", r->y_err, sizeof r->y_err},
                {"x", r->x, sizeof r->x},
                {"by", r->by, sizeof r->by},
                {"thesis_source", r->thesis_source, sizeof r->thesis_source},
                {"table", r->table, sizeof r->table},
                {"where", r->where, sizeof r->where},
                {"select", r->select, sizeof r->select},
                {"axes", r->axes, sizeof r->axes},
                {"overlay", r->overlay, sizeof r->overlay},
                {"overlay_y", r->overlay_y, sizeof r->overlay_y},
                {"overlay_title", r->overlay_title, sizeof r->overlay_title},
                {"x_label", r->x_label, sizeof r->x_label},
                {"restates", r->restates, sizeof r->restates},
                {"compensate", r->compensate, sizeof r->compensate},
                {"against", r->against, sizeof r->against}};
    for (size_t i = 0; i < sizeof text / sizeof text[0]; i++) {
        if (!strcmp(name, text[i].key)) {
            if (strlen(value) >= text[i].size) { /* never cut a value short in silence */
                snprintf(p->error, sizeof p->error,
                         "[result %s] %s: %zu characters, at most %zu allowed", r->id, name,
                         strlen(value), text[i].size - 1);
                return 0;
            }
            snprintf(text[i].dst, text[i].size, "%s", value);
            return 1;
        }
    }
    if (!strcmp(name, "thesis") || !strcmp(name, "note")) { /* may continue over several lines */
        char section[48];
        snprintf(section, sizeof section, "result %s", r->id);
        return name[0] == 't'
                   ? append_text(p, section, name, r->thesis, sizeof r->thesis, "; ", value)
                   : append_text(p, section, name, r->note, sizeof r->note, " ", value);
    }
    if (!strcmp(name, "verdict")) { /* "CATEGORY: why", the why may continue over several lines */
        char section[48];
        snprintf(section, sizeof section, "result %s", r->id);
        if (r->verdict[0]) {
            return append_text(p, section, name, r->verdict_why, sizeof r->verdict_why, " ", value);
        }
        for (int i = 0; i < GR_CAMPAIGN_VERDICTS; i++) {
            const size_t len = strlen(gr_campaign_verdicts[i]);
            if (!strncmp(value, gr_campaign_verdicts[i], len) && value[len] == ':') {
                const char *why = value + len + 1;
                while (*why == ' ') {
                    why++;
                }
                if (!*why) {
                    break;
                }
                snprintf(r->verdict, sizeof r->verdict, "%s", gr_campaign_verdicts[i]);
                return append_text(p, section, name, r->verdict_why, sizeof r->verdict_why, " ",
                                   why);
            }
        }
        snprintf(p->error, sizeof p->error,
                 "[result %s] verdict = %.60s: expected \"explained: WHY\", \"partly explained: "
                 "WHY\" or \"unexplained: WHY\"",
                 r->id, value);
        return 0;
    }
    if (!strcmp(name, "kind")) {
        if (!strcmp(value, "mean")) {
            r->kind = GR_RESULT_MEAN;
        } else if (!strcmp(value, "power_law")) {
            r->kind = GR_RESULT_POWER_LAW;
        } else if (!strcmp(value, "running_mean")) {
            r->kind = GR_RESULT_RUNNING;
        } else if (!strcmp(value, "rise_time")) {
            r->kind = GR_RESULT_RISE;
        } else if (!strcmp(value, "settle_time")) {
            r->kind = GR_RESULT_SETTLE;
        } else if (!strcmp(value, "curve")) {
            r->kind = GR_RESULT_CURVE;
        } else if (!strcmp(value, "cascade")) {
            r->kind = GR_RESULT_CASCADE;
        } else if (!strcmp(value, "spm")) {
            r->kind = GR_RESULT_SPM;
        } else if (!strcmp(value, "spm_compare")) {
            r->kind = GR_RESULT_SPM_COMPARE;
        } else if (!strcmp(value, "spm_circle")) {
            r->kind = GR_RESULT_SPM_CIRCLE;
        } else if (!strcmp(value, "cascade_field")) {
            r->kind = GR_RESULT_CASCADE_FIELD;
        } else if (!strcmp(value, "collapse")) {
            r->kind = GR_RESULT_COLLAPSE;
        } else {
            snprintf(p->error, sizeof p->error,
                     "[result %s] kind = %s: allowed mean, power_law, running_mean, rise_time, "
                     "settle_time, curve, cascade, cascade_field, spm, spm_compare, spm_circle, "
                     "collapse",
                     r->id, value);
            return 0;
        }
        return 1;
    }
    if (!strcmp(name, "m")) {
        int used = 0;
        r->m_step = 1;
        const int got = sscanf(value, "%d-%d%n/%d%n", &r->m_lo, &r->m_hi, &used, &r->m_step, &used);
        if (got < 2 || value[used] || r->m_lo < 1 || r->m_hi < r->m_lo || r->m_hi > 12 ||
            r->m_step < 1) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] m = %s: expected a range LO-HI within 1-12, optionally with a "
                     "step (3-12/3: 3, 6, 9, 12)",
                     r->id, value);
            return 0;
        }
        return 1;
    }
    int *count = !strcmp(name, "configurations") ? &r->configurations
                 : !strcmp(name, "slope_span")   ? &r->slope_span
                                                 : NULL;
    if (count) { /* configurations: cascade placements or fields; slope_span: sizes apart */
        const long lo = count == &r->slope_span ? 2 : 1, hi = count == &r->slope_span ? 8 : 1000;
        char *end;
        long k = strtol(value, &end, 10);
        if (end == value || *end || k < lo || k > hi) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] %s = %s: expected an integer from %ld to %ld", r->id, name, value,
                     lo, hi);
            return 0;
        }
        *count = (int)k;
        return 1;
    }
    if (!strcmp(name, "per_m") || !strcmp(name, "local_slopes")) {
        bool *flag = name[0] == 'p' ? &r->per_m : &r->local_slopes;
        *flag = !strcmp(value, "true");
        if (!*flag && strcmp(value, "false")) {
            snprintf(p->error, sizeof p->error, "[result %s] %s = %s: true or false", r->id, name,
                     value);
            return 0;
        }
        return 1;
    }
    if (!strcmp(name, "transform")) {
        if (strcmp(value, "none") && strcmp(value, "bisection_collapse") &&
            strcmp(value, "scale_at") && strcmp(value, "log_ratio") &&
            strcmp(value, "moment_scale")) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] transform = %s: allowed none, bisection_collapse, scale_at, "
                     "log_ratio, moment_scale",
                     r->id, value);
            return 0;
        }
        snprintf(r->transform, sizeof r->transform, "%s", strcmp(value, "none") ? value : "");
        return 1;
    }
    if (!strcmp(name, "tail")) {
        r->tail_exponential = !strcmp(value, "exponential");
        if (!r->tail_exponential && strcmp(value, "5.31")) {
            snprintf(p->error, sizeof p->error, "[result %s] tail = %s: allowed 5.31, exponential",
                     r->id, value);
            return 0;
        }
        return 1;
    }
    if (!strcmp(name, "walks") || !strcmp(name, "walks_quick")) {
        char *end;
        long k = strtol(value, &end, 10);
        if (end == value || *end || k < 100 || k > 100000000) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] %s = %s: expected an integer from 100 to 100000000 (SPM walks "
                     "per run)",
                     r->id, name, value);
            return 0;
        }
        *(name[5] ? &r->walks_quick : &r->walks) = k;
        return 1;
    }
    if (!strcmp(name, "overlay_exponent")) {
        if (!parse_double(value, &r->overlay_exponent) || r->overlay_exponent == 0.0 ||
            fabs(r->overlay_exponent) > 100.0) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] overlay_exponent = %s: expected a number from -100 to 100, not 0",
                     r->id, value);
            return 0;
        }
        return 1;
    }
    if (!strcmp(name, "df")) {
        if (!parse_double(value, &r->df) || !(r->df > 1.0 && r->df < 2.0)) {
            snprintf(p->error, sizeof p->error,
                     "[result %s] df = %s: expected D_f in (1, 2) (2D free paths, 4.25)", r->id,
                     value);
            return 0;
        }
        return 1;
    }
    double *num = !strcmp(name, "x_min")          ? &r->x_min
                  : !strcmp(name, "x_max")        ? &r->x_max
                  : !strcmp(name, "period")       ? &r->period
                  : !strcmp(name, "collapse_at")  ? &r->collapse_at
                  : !strcmp(name, "scale_moment") ? &r->scale_moment
                  : !strcmp(name, "pl_max")       ? &r->pl_max
                                                  : NULL;
    if (num) {
        if (!parse_double(value, num) || *num <= 0.0) {
            snprintf(p->error, sizeof p->error, "[result %s] %s = %s: expected a positive number",
                     r->id, name, value);
            return 0;
        }
        return 1;
    }
    snprintf(p->error, sizeof p->error,
             "[result %s] %s: unknown key; keys: title, kind, quantity, unit, y, y_err, x, x_min, "
             "x_max, by, m, per_m, local_slopes, slope_span, period, "
             "table, where, select, transform, collapse_at, scale_moment, axes, overlay, "
             "overlay_exponent, "
             "overlay_y, overlay_title, x_label, restates, compensate, against, "
             "configurations, df, pl_max, tail, walks, walks_quick, thesis, thesis_source, note, "
             "verdict",
             r->id, name);
    return 0;
}

static int on_line(void *user, const char *section, const char *name, const char *value)
{
    parse_ctx *p = user;
    gr_campaign *c = p->c;
    if (p->error
            [0]) { /* inih goes on after an error and reports the first one's line: keep its message */
        return 0;
    }
    if (p->lines && p->lines->length > INI_MAX_LINE - 2) { /* the limit campaign files always had */
        snprintf(
            p->error, sizeof p->error,
            "line longer than %d characters (split it: about, note, thesis and verdict may repeat)",
            INI_MAX_LINE - 2);
        return 0;
    }
    if (!check_repeat(p, section, name)) {
        return 0;
    }
    if (!strcmp(section, "campaign")) {
        return campaign_key(p, name, value);
    }
    if (!strncmp(section, "result ", 7)) {
        const char *id = section + 7;
        gr_campaign_result *r = c->n_results ? &c->results[c->n_results - 1] : NULL;
        if (!r || strcmp(r->id, id)) {
            for (int i = 0; i < c->n_results; i++) {
                if (!strcmp(c->results[i].id, id)) {
                    snprintf(p->error, sizeof p->error,
                             "[%s]: given twice; each result is one section", section);
                    return 0;
                }
            }
            if (c->n_results == GR_CAMPAIGN_MAX_RESULTS) {
                snprintf(p->error, sizeof p->error, "[%s]: at most %d results per campaign",
                         section, GR_CAMPAIGN_MAX_RESULTS);
                return 0;
            }
            r = &c->results[c->n_results++];
            snprintf(r->id, sizeof r->id, "%s", id);
            r->x_max = INFINITY;
            r->period = 20.0;
            r->configurations = 20;
        }
        return result_key(p, r, name, value);
    }
    /* sweep sections: [set] for both fidelities, [sweep.F] [vary.F] [set.F] for one */
    char base[16] = "";
    int fid = -1;
    const char *dot = strchr(section, '.');
    if (!strcmp(section, "set")) {
        snprintf(base, sizeof base, "set");
    } else if (dot && (size_t)(dot - section) < sizeof base) {
        snprintf(base, sizeof base, "%.*s", (int)(dot - section), section);
        fid = !strcmp(dot + 1, "quick")  ? GR_FIDELITY_QUICK
              : !strcmp(dot + 1, "full") ? GR_FIDELITY_FULL
                                         : -1;
    }
    if ((strcmp(base, "sweep") && strcmp(base, "vary") && strcmp(base, "set")) ||
        (fid < 0 && strcmp(section, "set"))) {
        snprintf(p->error, sizeof p->error,
                 "[%s]: unknown section; sections: campaign, set, sweep.quick, vary.quick, "
                 "set.quick, sweep.full, vary.full, "
                 "set.full, result ID",
                 section);
        return 0;
    }
    for (int f = 0; f < 2; f++) {
        if (fid >= 0 && f != fid) {
            continue;
        }
        if (c->n_lines[f] == GR_CAMPAIGN_MAX_LINES) {
            snprintf(p->error, sizeof p->error, "[%s]: at most %d sweep lines per fidelity",
                     section, GR_CAMPAIGN_MAX_LINES);
            return 0;
        }
        gr_campaign_line *last = c->n_lines[f] ? &c->lines[f][c->n_lines[f] - 1] : NULL;
        if (!strcmp(base, "vary") && last && !strcmp(last->section, "vary") &&
            !strcmp(last->key, name)) {
            /* a list longer than a line continues on a line that repeats the key */
            size_t used = strlen(last->value);
            if (used + 2 + strlen(value) >= sizeof last->value) {
                snprintf(p->error, sizeof p->error,
                         "[%s] %s: the list is longer than %zu characters", section, name,
                         sizeof last->value - 1);
                return 0;
            }
            snprintf(last->value + used, sizeof last->value - used, ", %s", value);
            continue;
        }
        for (int i = 0; i < c->n_lines[f]; i++) { /* a [set] or [set.F] key is not varied too */
            const gr_campaign_line *o = &c->lines[f][i];
            const bool set_vary = !strcmp(base, "set") && !strcmp(o->section, "vary") &&
                                  gr_linked_key_names(o->key, name);
            if (set_vary || (!strcmp(base, "vary") && !strcmp(o->section, "set") &&
                             gr_linked_key_names(name, o->key))) {
                snprintf(p->error, sizeof p->error,
                         "[%s] %s: also in [%s%s] %s; a key is either set or varied", section, name,
                         o->section, strcmp(o->section, "set") ? (f ? ".full" : ".quick") : "",
                         o->key);
                return 0;
            }
        }
        if (!strcmp(base, "sweep") && !strcmp(name, "seeds") && !check_seeds(p, section, value)) {
            return 0;
        }
        gr_campaign_line *l = &c->lines[f][c->n_lines[f]++];
        snprintf(l->section, sizeof l->section, "%s", base);
        snprintf(l->key, sizeof l->key, "%s", name);
        snprintf(l->value, sizeof l->value, "%s", value);
    }
    return 1;
}

/* Each entry of a thesis list (docs/campaigns/README.md) is "GROUP: [about|model|exact|range]
 * VALUE ..." with a finite VALUE; anything else would be skipped silently when the rows are made.
 * On a bad entry, `why` says which. */
static bool thesis_ok(const char *thesis, char *why, size_t len)
{
    char buf[sizeof((gr_campaign_result *)0)->thesis];
    snprintf(buf, sizeof buf, "%s", thesis);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
        const char *colon = strchr(tok, ':'), *group = tok + strspn(tok, " \t");
        const char *text = colon ? colon + 1 + strspn(colon + 1, " \t") : NULL;
        static const char *const words[] = {"about ", "model ", "exact ", "range "};
        for (int k = 0; k < 4 && text; k++) {
            text += strncmp(text, words[k], strlen(words[k])) ? 0 : strlen(words[k]);
        }
        char *end = NULL;
        const double v = text ? strtod(text, &end) : (double)NAN;
        if (!colon || group == colon || end == text || !isfinite(v) ||
            !strchr("-+0123456789.", text[0])) {
            snprintf(why, len,
                     "'%.80s' is not GROUP: [about|model|exact|range] VALUE [+- ERROR | .. HIGH] "
                     "with a finite VALUE",
                     tok + strspn(tok, " \t"));
            return false;
        }
    }
    return true;
}

/* "fig3.2" matches covers = "Fig. 3.1, Fig. 3.2": compare with spaces, dots after words and case
 * ignored ("Fig. 3.2" -> "fig3.2"). */
static void normalise(const char *in, char *out, size_t len)
{
    size_t n = 0;
    for (const char *s = in; *s && n + 1 < len; s++) {
        if (isspace((unsigned char)*s) || (*s == '.' && s > in && isalpha((unsigned char)s[-1]))) {
            continue;
        }
        out[n++] = (char)tolower((unsigned char)*s);
    }
    out[n] = 0;
}

static bool covers(const char *list, const char *want)
{
    char buf[256], w[64];
    snprintf(buf, sizeof buf, "%s", list);
    normalise(want, w, sizeof w);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        char t[64];
        normalise(tok, t, sizeof t);
        if (!strcmp(t, w)) {
            return true;
        }
    }
    return false;
}

/* Parse `len` bytes of campaign text (NUL bytes included: they are refused, not an end). */
static int parse_text(gr_campaign *c, const char *text, size_t len, const char *where,
                      gr_error *err)
{
    /* the scene reader's lines: control bytes (NUL included), long lines and headers checked alike */
    static char newline[] = "\n"; /* fmemopen refuses a size of 0 */
    FILE *in = len ? fmemopen((void *)text, len, "r") : fmemopen(newline, 1, "r");
    parse_ctx p = {.c = c, .seen = calloc(SEEN_MAX, sizeof *p.seen)};
    if (!in || !p.seen) {
        if (in) {
            fclose(in);
        }
        free(p.seen);
        return GR_FAIL(err, GR_ENOMEM, "%s: cannot read: out of memory", where);
    }
    gr_line_reader lines = {.f = in,
                            .what = "campaign file",
                            .sections = "campaign, set, sweep.quick, vary.quick, set.quick, "
                                        "sweep.full, vary.full, set.full, result ID"};
    p.lines = &lines;
    int bad = gr_line_parse(&lines, on_line, &p);
    fclose(in);
    free(p.seen);
    if (bad) {
        int rc = GR_FAIL(err, GR_EINVAL, "%s:%d: %s", where, bad,
                         lines.problem[0] ? lines.problem
                         : p.error[0]     ? p.error
                                          : "not an INI line");
        gr_line_reader_free(&lines);
        return rc;
    }
    gr_line_reader_free(&lines);
    if (!c->title[0] || !c->scene[0]) {
        return GR_FAIL(err, GR_EINVAL, "%s: [campaign] needs title and scene", where);
    }
    char scene[200];
    snprintf(scene, sizeof scene, "scenes/%s", c->scene);
    if (!gr_embedded_find(scene)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [campaign] scene = %s: not a scene of docs/scenes (granule reproduce --list)",
            where, c->scene);
    }
    for (int f = 0; f < 2; f++) {
        if (gr_campaign_points(c, (gr_fidelity)f) <= 0) {
            return GR_FAIL(err, GR_EINVAL, "%s: no [vary.%s] lists", where, f ? "full" : "quick");
        }
    }
    for (int i = 0; i < c->n_results; i++) {
        const gr_campaign_result *r = &c->results[i];
        if (r->kind == GR_RESULT_COLLAPSE) { /* its y, x and groups are the power law's */
            int k = 0;
            while (k < c->n_results && (k == i || strcmp(c->results[k].id, r->compensate))) {
                k++;
            }
            const gr_campaign_result *fit = k < c->n_results ? &c->results[k] : NULL;
            if (!fit || fit->kind != GR_RESULT_POWER_LAW || fit->m_lo || fit->per_m ||
                !fit->by[0] || strchr(fit->by, ',')) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: [result %s] kind = collapse needs compensate = the id of a "
                               "power_law result of this campaign with one key in by and no m",
                               where, r->id);
            }
            if (r->against[0] && strcmp(r->against, "by") && strcmp(r->against, "1-by^2")) {
                return GR_FAIL(err, GR_EINVAL, "%s: [result %s] against = %s: allowed by, 1-by^2",
                               where, r->id, r->against);
            }
        }
        if (r->kind != GR_RESULT_RUNNING && r->kind != GR_RESULT_RISE &&
            r->kind != GR_RESULT_SETTLE && r->kind != GR_RESULT_CASCADE_FIELD &&
            r->kind != GR_RESULT_COLLAPSE && !r->y[0]) {
            return GR_FAIL(err, GR_EINVAL, "%s: [result %s] needs y (a summary.json path)", where,
                           r->id);
        }
        if (r->restates
                [0]) { /* counted once: where its numbers are, which must exist and be another result */
            int k = 0;
            while (k < c->n_results && (k == i || strcmp(c->results[k].id, r->restates))) {
                k++;
            }
            if (k == c->n_results) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: [result %s] restates = %s: not another result of this campaign",
                               where, r->id, r->restates);
            }
        }
        if (r->slope_span && (r->kind != GR_RESULT_POWER_LAW || !r->local_slopes)) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] slope_span needs kind = power_law and local_slopes = "
                           "true",
                           where, r->id);
        }
        if (r->kind == GR_RESULT_POWER_LAW && !r->x[0]) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] kind = power_law needs x (the varied key)", where,
                           r->id);
        }
        if (r->kind == GR_RESULT_CURVE && (!r->table[0] || !r->x[0])) {
            return GR_FAIL(
                err, GR_EINVAL,
                "%s: [result %s] kind = curve needs table (a run's CSV) and x, y (its columns)",
                where, r->id);
        }
        if (r->kind == GR_RESULT_SPM && !campaign_spm_quantity_known(r->y)) {
            return GR_FAIL(err, GR_EINVAL, "%s: [result %s] kind = spm: y = %s: allowed %s", where,
                           r->id, r->y, GR_CAMPAIGN_SPM_QUANTITIES);
        }
        if (r->kind == GR_RESULT_SPM_COMPARE && !campaign_spm_compare_quantity_known(r->y)) {
            return GR_FAIL(err, GR_EINVAL, "%s: [result %s] kind = spm_compare: y = %s: allowed %s",
                           where, r->id, r->y, GR_CAMPAIGN_SPM_COMPARE_QUANTITIES);
        }
        if (r->kind == GR_RESULT_SPM_CIRCLE && !campaign_spm_circle_quantity_known(r->y)) {
            return GR_FAIL(err, GR_EINVAL, "%s: [result %s] kind = spm_circle: y = %s: allowed %s",
                           where, r->id, r->y, GR_CAMPAIGN_SPM_CIRCLE_QUANTITIES);
        }
        char why[200];
        if (r->thesis[0] && !thesis_ok(r->thesis, why, sizeof why)) {
            return GR_FAIL(err, GR_EINVAL, "%s: [result %s] thesis: %s", where, r->id, why);
        }
        if (r->axes[0] && strcmp(r->axes, "loglog") && strcmp(r->axes, "linlog") &&
            strcmp(r->axes, "linear")) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] axes = %s: allowed loglog, linlog, linear", where,
                           r->id, r->axes);
        }
        if (r->overlay[0] && strcmp(r->overlay, "bisection") && strcmp(r->overlay, "power_law") &&
            strcmp(r->overlay, "column")) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] overlay = %s: allowed bisection, power_law, column",
                           where, r->id, r->overlay);
        }
        if (!strcmp(r->overlay, "power_law") &&
            (r->overlay_exponent == 0.0 || !(r->x_min > 0.0 || isfinite(r->x_max)))) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] overlay = power_law needs overlay_exponent and a "
                           "window (x_min, x_max) to fit its amplitude over",
                           where, r->id);
        }
        if (!strcmp(r->overlay, "column") && (!r->overlay_y[0] || r->transform[0])) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] overlay = column needs overlay_y and no transform",
                           where, r->id);
        }
        if (!strcmp(r->transform, "bisection_collapse") &&
            !(r->collapse_at > 0.0 && r->collapse_at < 1.0)) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] transform = %s needs collapse_at in (0, 1)", where,
                           r->id, r->transform);
        }
        if (!strcmp(r->transform, "moment_scale") &&
            !(r->scale_moment >= 1.0 && r->scale_moment <= 12.0 &&
              r->scale_moment == floor(r->scale_moment))) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] transform = moment_scale needs scale_moment, the "
                           "order m of <|v|^m> (a whole number 1-12, the moments observable's)",
                           where, r->id);
        }
        if (!strcmp(r->transform, "scale_at") && !(r->collapse_at > 0.0)) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [result %s] transform = scale_at needs collapse_at (the x_0 where "
                           "every curve is 1)",
                           where, r->id);
        }
    }
    return GR_OK;
}

int gr_campaign_load(gr_campaign *c, const char *name, gr_error *err)
{
    memset(c, 0, sizeof *c);
    struct stat st;
    if (strchr(name, '/') || (strlen(name) > 4 && !strcmp(name + strlen(name) - 4, ".ini"))) {
        int why = 0;
        FILE *f = gr_input_fopen(name, &why);
        if (!f || fstat(fileno(f), &st) != 0) {
            if (f) {
                fclose(f);
            }
            return GR_FAIL(err, GR_EINVAL, "%s: not a campaign file (%s)", name,
                           why < 0 ? "not a regular file: a folder, FIFO, device or socket"
                                   : strerror(why ? why : errno));
        }
        char *text = calloc(1, (size_t)st.st_size + 1);
        size_t got = f && text ? fread(text, 1, (size_t)st.st_size, f) : 0;
        if (f) {
            fclose(f);
        }
        int rc = got == (size_t)st.st_size ? parse_text(c, text, got, name, err)
                                           : GR_FAIL(err, GR_EIO, "%s: cannot read", name);
        free(text);
        const char *base = strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
        snprintf(c->name, sizeof c->name, "%.*s",
                 (int)(strlen(base) > 4 ? strlen(base) - 4 : strlen(base)), base);
        snprintf(c->source, sizeof c->source, "%s", name);
        return rc;
    }
    for (int i = 0; i < gr_embedded_count; i++) {
        const char *n = gr_embedded_files[i].name;
        if (strncmp(n, "campaigns/", 10)) {
            continue;
        }
        char own[64];
        snprintf(own, sizeof own, "%.*s", (int)(strlen(n) - 14), n + 10); /* campaigns/NAME.ini */
        gr_campaign probe;
        memset(&probe, 0, sizeof probe);
        gr_error perr = {0};
        if (parse_text(&probe, gr_embedded_files[i].text, strlen(gr_embedded_files[i].text), n,
                       &perr)) {
            return GR_FAIL(err, GR_EINVAL, "%s",
                           perr.message); /* a broken built-in campaign is a bug: say so */
        }
        if (!strcmp(own, name) || covers(probe.covers, name)) {
            *c = probe;
            snprintf(c->name, sizeof c->name, "%s", own);
            snprintf(c->source, sizeof c->source, "docs/%s (built in)", n);
            return GR_OK;
        }
    }
    return GR_FAIL(err, GR_EINVAL, "no campaign or figure named '%s' (granule reproduce --list)",
                   name);
}

int gr_campaign_names(const char **names, int max)
{
    int n = 0;
    for (int i = 0; i < gr_embedded_count && n < max; i++) {
        if (!strncmp(gr_embedded_files[i].name, "campaigns/", 10) &&
            strstr(gr_embedded_files[i].name, ".ini")) {
            names[n++] = gr_embedded_files[i].name;
        }
    }
    return n;
}

static long count_list(const char *value)
{
    long n = 0;
    bool in = false;
    for (const char *s = value; *s; s++) {
        bool sep = *s == ',' || isspace((unsigned char)*s);
        n += !sep && !in;
        in = !sep;
    }
    return n;
}

long gr_campaign_points(const gr_campaign *c, gr_fidelity fid)
{
    long points = 1, vary = 0;
    for (int i = 0; i < c->n_lines[fid]; i++) {
        const gr_campaign_line *l = &c->lines[fid][i];
        if (!strcmp(l->section, "vary")) {
            points *= count_list(l->value);
            vary++;
        } else if (!strcmp(l->section, "sweep") && !strcmp(l->key, "seeds")) {
            points *= count_list(l->value);
        }
    }
    return vary ? points : 0;
}

int gr_campaign_materialise(const gr_campaign *c, gr_fidelity fid, const char *dir,
                            char *sweep_path, size_t len, gr_error *err)
{
    int rc = gr_output_dir_prepare(dir, GR_OUTPUT_ANY, true, err);
    if (rc) {
        return rc;
    }
    char scene_name[200];
    snprintf(scene_name, sizeof scene_name, "scenes/%s", c->scene);
    gr_file f;
    if ((rc = gr_file_open(&f, dir, "scene.ini", err))) {
        return rc;
    }
    fputs(gr_embedded_find(scene_name), f.f);
    if ((rc = gr_file_commit(&f, err)) || (rc = gr_file_open(&f, dir, "sweep.ini", err))) {
        return rc;
    }
    fprintf(f.f, "; campaign %s (%s fidelity), written by granule reproduce from %s\n", c->name,
            fid == GR_FIDELITY_FULL ? "full" : "quick", c->source);
    static const char *const order[] = {"sweep", "vary", "set"};
    for (int s = 0; s < 3; s++) {
        fprintf(f.f, "[%s]\n", order[s]);
        if (s == 0) {
            fprintf(f.f, "scene = scene.ini\nout = %s/runs\n", dir);
        }
        for (int i = 0; i < c->n_lines[fid]; i++) {
            const gr_campaign_line *l = &c->lines[fid][i];
            if (strcmp(l->section, order[s])) {
                continue;
            }
            bool overridden =
                false; /* a [set.F] line overrides the same key's [set] line before it */
            for (int j = i + 1; j < c->n_lines[fid] && s == 2; j++) {
                overridden |= !strcmp(c->lines[fid][j].section, "set") &&
                              !strcmp(c->lines[fid][j].key, l->key);
            }
            if (overridden) {
                continue;
            }
            /* a long list goes on several lines that repeat the key (INI lines hold INI_MAX_LINE
             * characters; inih cuts the names it hands over for indented continuation lines) */
            fprintf(f.f, "%s =", l->key);
            int col = (int)strlen(l->key) + 2;
            const char *v = l->value;
            while (*v) {
                size_t n = strcspn(v, ",");
                if (col > (int)strlen(l->key) + 2 && col + (int)n > 190) {
                    fprintf(f.f, "\n%s =", l->key);
                    col = (int)strlen(l->key) + 2;
                }
                fprintf(f.f, " %.*s%s", (int)n, v,
                        v[n + (v[n] != 0) + strspn(v + n + (v[n] != 0), " \t")] ? "," : "");
                col += (int)n + 2;
                v += n + (v[n] != 0);
                v += strspn(v, " \t");
            }
            fputc('\n', f.f);
        }
    }
    if ((rc = gr_file_commit(&f, err))) {
        return rc;
    }
    snprintf(sweep_path, len, "%s/sweep.ini", dir);
    return GR_OK;
}
