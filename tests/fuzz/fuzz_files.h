/* What the fuzz targets of files read by path share: the app_error of cli/main.c (not linked into
 * a harness: messages are kept to be checked, not printed) and writing each input to its path. */
#ifndef GR_FUZZ_FILES_H
#define GR_FUZZ_FILES_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "cli/cli.h"

static char last_error[1024];

void app_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(last_error, sizeof last_error, fmt, ap);
    va_end(ap);
}

/* The harness's private folder, /tmp/granule-fuzz-TAG-XXXXXX */
static char fuzz_dir[64];
static void (*fuzz_cleanup_files)(void);

static void fuzz_cleanup(void)
{
    if (fuzz_cleanup_files) {
        fuzz_cleanup_files();
    }
    rmdir(fuzz_dir);
}

/* True on the first call only, having made fuzz_dir; at exit, cleanup (which removes the files
 * the harness put there) runs and the folder is removed. */
static bool fuzz_first(const char *tag, void (*cleanup)(void))
{
    if (fuzz_dir[0]) {
        return false;
    }
    snprintf(fuzz_dir, sizeof fuzz_dir, "/tmp/granule-fuzz-%.20s-XXXXXX", tag);
    if (!mkdtemp(fuzz_dir)) {
        abort();
    }
    fuzz_cleanup_files = cleanup;
    atexit(fuzz_cleanup);
    return true;
}

/* The input as the file at path (a harness failure aborts: it is not a finding of the parser). */
static void fuzz_write_input(const char *path, const uint8_t *data, size_t size)
{
    FILE *f = fopen(path, "w");
    if (!f || fwrite(data, 1, size, f) != size || fclose(f)) {
        abort();
    }
}

#endif
