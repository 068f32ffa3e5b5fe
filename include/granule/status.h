/* Status codes and the error record every fallible granule call fills in.
 *
 * The library never prints, exits or aborts: a call returns an int status (0 ok, negative
 * error) and, on error, describes what went wrong in a gr_error the caller owns. The CLI
 * decides what to print and which exit code to use. */
#ifndef GRANULE_STATUS_H
#define GRANULE_STATUS_H

enum {
    GR_OK = 0,
    GR_EINVAL = -1,   /* invalid argument or scene value */
    GR_ENOMEM = -2,   /* allocation failed */
    GR_EIO = -3,      /* file could not be read or written */
    GR_EUNSTABLE = -4 /* the run became unstable (non-finite value, runaway overlap) */
};

typedef struct gr_error {
    int code;             /* one of the GR_E* codes, 0 when no error was recorded */
    char message[768];    /* one line, no trailing newline */
    const char *src_file; /* where in granule's source the error was raised */
    int src_line;
} gr_error;

/* Record an error (printf-style message) and return its code. */
int gr_error_set(gr_error *err, int code, const char *src_file, int src_line, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

#define GR_FAIL(err, code, ...) gr_error_set((err), (code), __FILE__, __LINE__, __VA_ARGS__)

#endif
