/* The reproduction page's coverage table (docs/thesis-coverage.md, beside the results folder) and
 * its check against the campaigns: every figure or table a campaign's `covers` line claims must
 * be marked covered or partly there with that campaign named, and a covered or partly item that
 * names campaigns must be claimed by each of them. A coverage file that disagrees with the
 * campaigns refuses the page, so the page never states a coverage the campaigns do not back. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granule/campaign.h"
#include "app/reproduce/coverage.h"

typedef struct {
    char item[32], status[32], where[256];
} coverage_row;

enum { MAX_ROWS = 128, MAX_CAMPAIGNS = 64 };

/* Cell k (0-based) of a markdown table line "| a | b | c |", trimmed. */
static void cell_of(const char *line, int k, char *out, size_t len)
{
    const char *p = strchr(line, '|');
    for (int i = 0; p && i < k; i++) {
        p = strchr(p + 1, '|');
    }
    const char *end = p ? strchr(p + 1, '|') : NULL;
    if (!p || !end) {
        out[0] = 0;
        return;
    }
    p++;
    while (p < end && *p == ' ') {
        p++;
    }
    while (end > p && end[-1] == ' ') {
        end--;
    }
    snprintf(out, len, "%.*s", (int)(end - p), p);
}

/* Whether the comma-separated list holds `word` as one of its entries. */
static bool listed(const char *list, const char *word)
{
    const size_t n = strlen(word);
    for (const char *p = list; (p = strstr(p, word)); p += n) {
        const bool start = p == list || p[-1] == ' ' || p[-1] == ',';
        const bool end = p[n] == 0 || p[n] == ',' || p[n] == ' ';
        if (start && end) {
            return true;
        }
    }
    return false;
}

int gr_reproduction_coverage(FILE *out, const char *root, char *problems, size_t len)
{
    problems[0] = 0;
    char path[1300];
    snprintf(path, sizeof path, "%s/../thesis-coverage.md", root);
    FILE *in = fopen(path, "r");
    if (!in) {
        return 0; /* a results folder without the coverage file beside it: no section */
    }
    coverage_row *rows = calloc(MAX_ROWS, sizeof *rows);
    char(*lines)[1024] = calloc(MAX_ROWS + 2, sizeof *lines);
    int n = 0, nl = 0;
    char line[1024];
    bool in_table = false;
    while (rows && lines && fgets(line, sizeof line, in)) {
        if (line[0] != '|') {
            if (in_table) {
                break;
            }
            continue;
        }
        in_table = true;
        if (nl < MAX_ROWS + 2) {
            snprintf(lines[nl++], sizeof lines[0], "%s", line);
        }
        if (nl > 2 && n < MAX_ROWS) { /* past the header and its rule */
            cell_of(line, 0, rows[n].item, sizeof rows[n].item);
            cell_of(line, 1, rows[n].status, sizeof rows[n].status);
            cell_of(line, 2, rows[n].where, sizeof rows[n].where);
            n++;
        }
    }
    fclose(in);
    const char *names[MAX_CAMPAIGNS];
    const int nc = gr_campaign_names(names, MAX_CAMPAIGNS);
    gr_campaign *c = malloc(sizeof *c);
    int bad = 0;
    size_t used = 0;
#define PROBLEM(...)                                                                               \
    do {                                                                                           \
        bad++;                                                                                     \
        if (used < len) {                                                                          \
            used += (size_t)snprintf(problems + used, len - used, "%s", used ? "; " : "");         \
        }                                                                                          \
        if (used < len) {                                                                          \
            used += (size_t)snprintf(problems + used, len - used, __VA_ARGS__);                    \
        }                                                                                          \
    } while (0)
    for (int k = 0; c && rows && k < nc; k++) {
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)(strlen(names[k]) - 14), names[k] + 10);
        gr_error ignore = {0};
        if (gr_campaign_load(c, name, &ignore) != GR_OK) {
            continue;
        }
        /* what this campaign claims: each entry must be covered or partly, naming it */
        char covers[256];
        snprintf(covers, sizeof covers, "%s", c->covers);
        char *save = NULL;
        for (char *it = strtok_r(covers, ",", &save); it; it = strtok_r(NULL, ",", &save)) {
            while (*it == ' ') {
                it++;
            }
            if (strncmp(it, "Fig. ", 5) && strncmp(it, "Table ", 6)) {
                continue; /* "contact models": not a thesis item */
            }
            int r = 0;
            while (r < n && strcmp(rows[r].item, it)) {
                r++;
            }
            if (r == n) {
                PROBLEM("%s claims %s, which the coverage table does not list", name, it);
            } else if (strcmp(rows[r].status, "covered") && strcmp(rows[r].status, "partly")) {
                PROBLEM("%s claims %s, marked \"%s\"", name, it, rows[r].status);
            } else if (!listed(rows[r].where, name)) {
                PROBLEM("%s claims %s, whose row does not name it", name, it);
            }
        }
        /* each row naming this campaign must be one it claims */
        for (int r = 0; r < n; r++) {
            if (listed(rows[r].where, name) && !listed(c->covers, rows[r].item)) {
                PROBLEM("%s names %s, whose covers line does not claim it", rows[r].item, name);
            }
        }
    }
    int tally[4] = {0};
    static const char *const kinds[4] = {"covered", "partly", "not", "not a result"};
    for (int r = 0; r < n; r++) {
        int k = 0;
        while (k < 4 && strcmp(rows[r].status, kinds[k])) {
            k++;
        }
        if (k == 4) {
            PROBLEM("%s: status \"%s\" (allowed: covered, partly, not, not a result)", rows[r].item,
                    rows[r].status);
        } else {
            tally[k]++;
        }
    }
#undef PROBLEM
    if (!bad && out) {
        fprintf(out,
                "## Coverage of the thesis\n\nEvery table and figure of chapters 2-6 and the "
                "appendices with a quantitative result, from\n[thesis-coverage.md]"
                "(thesis-coverage.md) (checked against the campaigns' `covers` lines when this "
                "page was made):\n%d covered, %d partly, %d not (and %d items that are no "
                "result).\n\n",
                tally[0], tally[1], tally[2], tally[3]);
        for (int i = 0; i < nl; i++) {
            fputs(lines[i], out);
        }
        fprintf(out, "\n");
    }
    free(c);
    free(rows);
    free(lines);
    return bad;
}
