/* The analyses of T(t) (docs/campaigns/README.md): the running average and period means of Fig.
 * 2.8, and the rise of T to its steady value of Fig. 2.7, from each run's temperature.csv. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "io/files.h"
#include "io/summary_read.h"
#include "app/reproduce/campaign_points.h"

/* T(t) of one run from its temperature.csv (comment lines skipped, columns found by name); with
 * sample_only, the sampling phase only. Returns the number of samples (t and T malloc'ed). */
static int read_series(const campaign_point *p, bool sample_only, double **t_out, double **T_out)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/temperature.csv", p->dir);
    FILE *f = gr_input_fopen(path, &(int){0});
    *t_out = *T_out = NULL;
    if (!f) {
        return 0;
    }
    char line[512];
    int col_t = -1, col_T = -1, col_phase = -1, n = 0, cap = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            continue;
        }
        char *fields[8];
        int nfields = 0;
        char *save = NULL;
        for (char *tok = strtok_r(line, ",\n", &save); tok && nfields < 8;
             tok = strtok_r(NULL, ",\n", &save)) {
            fields[nfields++] = tok;
        }
        if (col_t < 0) {
            for (int i = 0; i < nfields; i++) {
                col_t = !strcmp(fields[i], "t") ? i : col_t;
                col_T = !strcmp(fields[i], "T") ? i : col_T;
                col_phase = !strcmp(fields[i], "phase") ? i : col_phase;
            }
            if (col_t < 0 || col_T < 0 || col_phase < 0) {
                break;
            }
            continue;
        }
        /* "sampling"; "sample" in the folders of versions before issue 38 */
        if (nfields <= col_phase || (sample_only && strcmp(fields[col_phase], "sampling") &&
                                     strcmp(fields[col_phase], "sample"))) {
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 4096;
            *t_out = realloc(*t_out, (size_t)cap * sizeof **t_out);
            *T_out = realloc(*T_out, (size_t)cap * sizeof **T_out);
        }
        (*t_out)[n] = atof(fields[col_t]);
        (*T_out)[n++] = atof(fields[col_T]);
    }
    fclose(f);
    return n;
}

/* Means of T over periods of the sampling phase, appended to data with the running average;
 * returns the number of periods. */
static int run_periods(const campaign_point *p, double period, const char *group, FILE *data,
                       double *means, int max)
{
    double *t, *T;
    int ns = read_series(p, true, &t, &T), n = 0, count = 0;
    double sum = 0.0, total = 0.0;
    /* the first sample stands for the interval that ends at it, so sample i closes a sampling
     * time of t[i] - t[0] + dt_sample (else the last period of a run falls one sample short) */
    const double dt_sample = ns > 1 ? t[1] - t[0] : 0.0;
    for (int i = 0; i < ns; i++) {
        sum += T[i];
        total += T[i];
        count++;
        const double elapsed = t[i] - t[0] + dt_sample;
        if (elapsed >= period * (n + 1) - 1e-6 * period && n < max) {
            means[n] = sum / count;
            gr_csv_text(data, group, true);
            fprintf(data, ",%d,%.6g,%.9g,%.9g\n", campaign_seed_of(p), elapsed, means[n],
                    total / (i + 1));
            n++;
            sum = 0.0;
            count = 0;
        }
    }
    fprintf(data, "\n"); /* a blank line ends this run's curve in the plot */
    free(t);
    free(T);
    return n;
}

int campaign_running(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                     campaign_rows *rows, gr_file *data, gr_error *err)
{
    (void)c;
    (void)err;
    static char g[MAX_GROUPS][160];
    int ng = campaign_groups(pts, NULL, NULL, g);
    campaign_header(data, "group", "", "seed", "1", "t", "s", "period_mean", campaign_unit(r),
                    "running_mean", campaign_unit(r), NULL);
    for (int gi = 0; gi < ng; gi++) {
        campaign_row *row = campaign_group_row(rows, g[gi]);
        double all[4096], seed_means[MAX_SEEDS];
        int n_all = 0, n_seed = 0;
        const campaign_point *mem[MAX_SEEDS];
        int nm = campaign_members(pts, g[gi], mem, MAX_SEEDS);
        for (int i = 0; i < nm; i++) {
            /* a period of at most a tenth of the sampling, so that short (quick) runs still have ten */
            double period =
                fmin(r->period, 0.1 * gr_summary_number(mem[i]->summary, "scene.run.duration"));
            double means[1024], m, se;
            int n = run_periods(mem[i], period, g[gi], data->f, means, 1024);
            if (n == 0) {
                continue;
            }
            campaign_mean_sd(means, n, &m, &se);
            seed_means[n_seed++] = m;
            for (int k = 0; k < n && n_all < 4096; k++) {
                all[n_all++] = means[k];
            }
            campaign_add_cost(row, mem[i]);
        }
        double m_all;
        campaign_mean_sd(seed_means, n_seed, &row->value, &row->error_seeds);
        campaign_mean_sd(all, n_all, &m_all,
                         &row->error_fit); /* period means treated as independent */
        row->error = campaign_headline_error(row->error_seeds, row->error_fit, n_seed);
        row->n_seeds = n_seed;
        row->n_x = n_all;
        campaign_row_thesis(r, row);
    }
    return GR_OK;
}

/* Fig. 2.7: how long T(t) takes to reach its steady value (the mean over the second half of the
 * run), two ways:
 *  - rise: the first time T's mean over the preceding 50 ms reaches 90 % of the steady value;
 *  - settle: the time after which T's means over consecutive 100 ms windows stay inside the steady
 *    value +- 3 sd of those window means over the second half (the steady state's own scatter):
 *    the end of the last window of the first half outside that band. From a touching cluster T
 *    overshoots (the cluster's stored spread turns into speed) before it settles, so the two differ.
 * Writes every 10th sample of the first half of T(t) to `data`. */
static double rise_or_settle_time(const campaign_point *p, const char *group, bool settle,
                                  FILE *data)
{
    double *t, *T;
    int n = read_series(p, false, &t, &T);
    double rise = NAN, steady = 0.0;
    for (int i = n / 2; i < n; i++) {
        steady += T[i] / (n - n / 2);
    }
    int w = 0;
    while (w < n && t[w] - t[0] < 0.05) {
        w++; /* samples per 50 ms */
    }
    for (int i = 0; i < n / 2; i += 10) {
        gr_csv_text(data, group, true);
        fprintf(data, ",%d,%.6g,%.9g,%.9g\n", campaign_seed_of(p), t[i], T[i], steady);
    }
    fprintf(data, "\n"); /* a blank line ends this run's curve in the plot */
    if (settle) {
        const int ws = 2 * w; /* samples per 100 ms */
        double sd = 0.0;
        int nw = 0;
        for (int a = n / 2; ws > 0 && a + ws <= n; a += ws, nw++) {
            double m = 0.0;
            for (int i = a; i < a + ws; i++) {
                m += T[i] / ws;
            }
            sd += (m - steady) * (m - steady);
        }
        sd = nw > 1 ? sqrt(sd / (nw - 1)) : (double)NAN;
        double last_out = NAN;
        for (int a = 0; isfinite(sd) && a + ws <= n / 2; a += ws) {
            double m = 0.0;
            for (int i = a; i < a + ws; i++) {
                m += T[i] / ws;
            }
            if (fabs(m - steady) > 3.0 * sd) {
                last_out = t[a + ws - 1];
            }
        }
        free(t);
        free(T);
        return !isfinite(sd) ? (double)NAN : isfinite(last_out) ? last_out : 0.0;
    }
    double sum = 0.0;
    for (int i = 0; i < n / 2 && w > 0; i++) {
        sum += T[i] - (i >= w ? T[i - w] : 0.0);
        if (i >= w - 1 && !(rise >= 0.0) && sum / w >= 0.9 * steady) {
            rise = t[i];
        }
    }
    free(t);
    free(T);
    return rise;
}

int campaign_rise(const gr_campaign *c, const gr_campaign_result *r, const campaign_points *pts,
                  campaign_rows *rows, gr_file *data, gr_error *err)
{
    (void)c;
    (void)err;
    static char g[MAX_GROUPS][160];
    int ng = campaign_groups(pts, NULL, NULL, g);
    const bool settle = r->kind == GR_RESULT_SETTLE;
    campaign_header(data, "group", "", "seed", "1", "t", "s", "T", "m2 s-2", "steady_T", "m2 s-2",
                    NULL);
    for (int gi = 0; gi < ng; gi++) {
        campaign_row *row = campaign_group_row(rows, g[gi]);
        double v[MAX_SEEDS];
        int n = 0;
        const campaign_point *mem[MAX_SEEDS];
        int nm = campaign_members(pts, g[gi], mem, MAX_SEEDS);
        for (int i = 0; i < nm; i++) {
            double rt = rise_or_settle_time(mem[i], g[gi], settle, data->f);
            if (isfinite(rt)) {
                v[n++] = rt;
                campaign_add_cost(row, mem[i]);
            }
        }
        campaign_mean_sd(v, n, &row->value, &row->error_seeds);
        row->error = row->error_seeds;
        row->n_seeds = n;
        campaign_row_thesis(r, row);
    }
    return GR_OK;
}

/* The warm-up check of one run: <T> over the first quarter of the sampling against the rest, minus
 * 1, and its error from the run's own fluctuations: the sampling cut into 8 blocks (the first
 * quarter is 2 of them), the scatter of the block means giving var = s_b^2 (1/2 + 1/6) / <T>^2.
 * With two or three runs the seed-to-seed scatter alone is a poor error (Fig. 2.8's runs drift by
 * +1.0 % and +1.8 %, within their 20 s block means' +-2 %, yet gave z = 3.5). */
/* The drift a restored point kept (warmup.json, written by gr_campaign_restore from the archive):
 * NAN when there is none. */
static double archived_drift(const campaign_point *p, double *error)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/warmup.json", p->dir);
    FILE *probe = gr_input_fopen(path, &(int){0});
    if (!probe) {
        return NAN;
    }
    fclose(probe);
    gr_error ignore = {0};
    cJSON *j = gr_json_read(path, &ignore);
    const cJSON *d = cJSON_GetObjectItem(j, "drift"), *e = cJSON_GetObjectItem(j, "error");
    const double drift = cJSON_IsNumber(d) ? d->valuedouble : (double)NAN;
    *error = cJSON_IsNumber(e) ? e->valuedouble : (double)NAN;
    cJSON_Delete(j);
    return drift;
}

double campaign_warmup_drift(const campaign_point *p, double *error)
{
    double *t, *T;
    int n = read_series(p, true, &t, &T);
    if (n == 0) { /* a point restored from the archive: its T(t) stayed on the machine it ran on */
        free(t);
        free(T);
        *error = NAN;
        return archived_drift(p, error);
    }
    double first = 0.0, rest = 0.0, block[8] = {0};
    int q = n / 4;
    for (int i = 0; i < n; i++) {
        if (i < q) {
            first += T[i];
        } else {
            rest += T[i];
        }
        block[(int)((int64_t)i * 8 / (n > 0 ? n : 1))] += T[i];
    }
    free(t);
    free(T);
    *error = NAN;
    if (!(q > 0 && rest > 0.0)) {
        return NAN;
    }
    const double mean = (first + rest) / n;
    if (n >= 64) {
        double s2 = 0.0;
        for (int b = 0; b < 8; b++) {
            const int lo = (int)(((int64_t)b * n + 7) / 8),
                      hi = (int)(((int64_t)(b + 1) * n + 7) / 8);
            const double m = block[b] / (hi - lo);
            s2 += (m - mean) * (m - mean) / 7.0;
        }
        *error = sqrt(s2 * (1.0 / 2.0 + 1.0 / 6.0)) / mean;
    }
    return (first / q) / (rest / (n - q)) - 1.0;
}
