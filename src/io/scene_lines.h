/* Whole lines for inih: a reader of scene files that never splits a line.
 *
 * inih reads into a fixed buffer of INI_MAX_LINE (200) bytes and reads the tail of a longer
 * line as a new line. This reader reads each physical line whole (any length), counts it, and
 * refuses control bytes (NUL included) with the line number. A long comment line is handed to
 * inih as an empty line; a long `key = value` line as `key = <GR_LONG_VALUE>`, the value itself
 * (inline comment and surrounding blanks removed, as inih does) kept in `long_value` for the
 * handler. Anything else that does not fit is refused with its line number. */
#ifndef GR_IO_SCENE_LINES_H
#define GR_IO_SCENE_LINES_H

#include <stdbool.h>
#include <stdio.h>

/* The value inih sees for a long line; files cannot contain it (control bytes are refused). */
#define GR_LONG_VALUE "\x01"

typedef struct gr_line_reader {
    FILE *f;
    char *buf;          /* the current physical line */
    size_t cap;
    int line;           /* its number, from 1 */
    bool content;       /* a line other than blanks and comments was read */
    char *long_value;   /* the value of the current long line, or NULL */
    char problem[200];  /* why reading stopped early ("" when it did not) */
} gr_line_reader;

/* fgets-shaped reader for ini_parse_stream; NULL at the end or on a problem. */
char *gr_line_read(char *str, int num, gr_line_reader *r);
void gr_line_reader_free(gr_line_reader *r);

#endif
