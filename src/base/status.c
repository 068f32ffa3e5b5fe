/* gr_error_set: record an error on a caller-owned gr_error. */
#include <stdarg.h>
#include <stdio.h>

#include "granule/status.h"

int gr_error_set(gr_error *err, int code, const char *src_file, int src_line, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->code = code;
        err->src_file = src_file;
        err->src_line = src_line;
    }
    return code;
}
