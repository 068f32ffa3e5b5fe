/* How the application layer talks to the person at the terminal: the one place above the library
 * that writes to stderr (progress lines, a sweep's point reports, error lines), and the exit codes
 * of every command. The library below returns status and messages instead (docs/architecture.md). */
#ifndef GR_APP_REPORT_H
#define GR_APP_REPORT_H

#include <stdbool.h>
#include <stdio.h>

#include "granule/status.h"

/* Exit codes of every command */
enum {
    EXIT_OK = 0,
    EXIT_FAILED = 1,
    EXIT_REFUSED = 2,
    EXIT_UNSTABLE = 3,
    EXIT_WALL_LIMIT =
        4, /* stopped before run.wall_limit ran out; checkpoint written (docs/checkpoints.md) */
    EXIT_STOPPED = 5, /* stopped by SIGTERM/SIGINT; checkpoint written */
    EXIT_WRITE_FAILED = 6
}; /* an output could not be written (a full disk); checkpoint kept, resume */

/* Print "granule: <message>" on stderr, one line, control bytes and invalid UTF-8 as \xNN. */
void app_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Print a progress or report line (formatted as given, no prefix) on stderr. */
void app_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Print a result line (formatted as given) on stdout: what a command found, for the user to read or a script to parse. */
void app_result(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Print text with the same escaping. */
void app_print_escaped(FILE *f, const char *text);
/* The exit status for a library status: 0 ok, 2 refused input (GR_EINVAL), 3 unstable, 1 other. */
int app_exit_code(int status);
/* True when progress lines may be drawn (stderr is a terminal and CI is not set). */
bool app_interactive(void);

#endif
