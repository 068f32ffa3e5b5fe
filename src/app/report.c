/* The application layer's one voice on the terminal (src/app/report.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/report.h"

/* Bytes a terminal would act on or mangle (control bytes, invalid UTF-8 from a binary file or
 * argument) are printed as \xNN, so a message is always one readable line. */
static size_t utf8_length(const unsigned char *p)
{
    size_t n = p[0] >= 0xf0 && p[0] <= 0xf4   ? 4
               : p[0] >= 0xe0                 ? 3
               : p[0] >= 0xc2 && p[0] <= 0xdf ? 2
                                              : 0;
    for (size_t i = 1; i < n; i++) {
        if ((p[i] & 0xc0) != 0x80) {
            return 0;
        }
    }
    return n;
}

void app_print_escaped(FILE *f, const char *text)
{
    for (const unsigned char *p = (const unsigned char *)text; *p;) {
        size_t n = *p >= 0x80 ? utf8_length(p) : 0;
        if (n) {
            fwrite(p, 1, n, f);
            p += n;
        } else if (*p < 0x20 || *p == 0x7f || *p >= 0x80) {
            fprintf(f, *p == '\n' ? "\\n" : "\\x%02x", *p);
            p++;
        } else {
            fputc(*p++, f);
        }
    }
}

void app_error(const char *fmt, ...)
{
    char text[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    fputs("granule: ", stderr);
    app_print_escaped(stderr, text);
    fputc('\n', stderr);
}

void app_note(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
}

void app_result(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
}

int app_exit_code(int status)
{
    return status == GR_OK          ? EXIT_OK
           : status == GR_EINVAL    ? EXIT_REFUSED
           : status == GR_EUNSTABLE ? EXIT_UNSTABLE
                                    : EXIT_FAILED;
}

bool app_interactive(void)
{
    const char *ci = getenv("CI");
    return isatty(STDERR_FILENO) &&
           !(ci && *ci && strcmp(ci, "0") != 0 && strcmp(ci, "false") != 0);
}
