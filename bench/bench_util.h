/* Small helpers shared by the bench programs: a monotonic clock, a comparator for medians and
 * the CPU model (benchmarks always print the machine they ran on). */
#ifndef GR_BENCH_UTIL_H
#define GR_BENCH_UTIL_H

#include <stdio.h>
#include <string.h>
#include <time.h>

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

#endif
