/* Small helpers shared by the bench programs: a monotonic clock, a comparator for medians and
 * the CPU model (benchmarks always print the machine they ran on). */
#ifndef GR_BENCH_UTIL_H
#define GR_BENCH_UTIL_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "granule/granule.h"

static inline double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static inline void bench_machine(char *buf, size_t n)
{
    snprintf(buf, n, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            snprintf(buf, n, "%.200s", c ? c + 2 : line);
            buf[strcspn(buf, "\n")] = 0;
            break;
        }
    }
    if (f) {
        fclose(f);
    }
}

/* A simulation's state (gr_sim_state_save) to FILE, written to FILE.tmp and renamed into place. */
static inline int bench_save_state(const gr_sim *sim, const char *file, gr_error *err)
{
    void *data = NULL;
    size_t len = 0;
    if (gr_sim_state_save(sim, &data, &len, err)) {
        return 1;
    }
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", file);
    FILE *f = fopen(tmp, "wb");
    int ok = f && fwrite(data, 1, len, f) == len;
    ok = (f && fclose(f) == 0) && ok && rename(tmp, file) == 0;
    free(data);
    if (!ok) {
        snprintf(err->message, sizeof err->message, "cannot write the state: %s", strerror(errno));
        remove(tmp);
        return 1;
    }
    return 0;
}

/* Overwrite sim (created from the same scene) with the state in FILE (gr_sim_state_load). */
static inline int bench_load_state(gr_sim *sim, const char *file, gr_error *err)
{
    FILE *f = fopen(file, "rb");
    if (!f) {
        snprintf(err->message, sizeof err->message, "cannot open the state: %s", strerror(errno));
        return 1;
    }
    size_t cap = 1 << 20, len = 0, got;
    char *data = malloc(cap);
    while (data && (got = fread(data + len, 1, cap - len, f)) > 0) {
        len += got;
        if (len == cap) {
            char *more = realloc(data, cap *= 2);
            if (!more) {
                free(data);
            }
            data = more;
        }
    }
    fclose(f);
    if (!data) {
        snprintf(err->message, sizeof err->message, "out of memory reading the state");
        return 1;
    }
    int rc = gr_sim_state_load(sim, data, len, err);
    free(data);
    return rc;
}

#endif
