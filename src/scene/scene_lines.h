/* Whole lines for inih: a reader of scene files that never splits a line.
 *
 * inih reads into a fixed buffer of INI_MAX_LINE (200) bytes and reads the tail of a longer
 * line as a new line. This reader reads each physical line whole (any length), counts it, and
 * refuses control bytes (NUL included) with the line number. A long comment line is handed to
 * inih as an empty line; a long `key = value` line as `key = <GR_LONG_VALUE>`, the value itself
 * (inline comment and surrounding blanks removed, as inih does) kept in `long_value` for the
 * handler. Anything else that does not fit is refused with its line number, and so is a section
 * header that is not `[name]` alone on its line (unterminated, or followed by anything but a
 * comment): inih would read `[system]x` as [system] and `[run` as more of the previous section.
 * Every text input (scenes, sweep and campaign files) is read through it. */
#ifndef GR_IO_SCENE_LINES_H
#define GR_IO_SCENE_LINES_H

#include <stdbool.h>
#include <stdio.h>

/* The value inih sees for a long line; files cannot contain it (control bytes are refused). */
#define GR_LONG_VALUE "\x01"

typedef struct gr_line_reader {
    FILE *f;
    char *buf; /* the current physical line */
    size_t cap;
    int line;             /* its number, from 1 */
    size_t length;        /* its length, line end excluded */
    bool content;         /* a line other than blanks and comments was read */
    char *long_value;     /* the value of the current long line, or NULL */
    const char *what;     /* the kind of file, for messages ("scene", "sweep file"; NULL: "file") */
    const char *sections; /* the sections allowed, for messages ("system, run, ..."), or NULL */
    char problem[300];    /* why reading stopped early ("" when it did not) */
} gr_line_reader;

/* fgets-shaped reader for ini_parse_stream; NULL at the end or on a problem. */
char *gr_line_read(char *str, int num, gr_line_reader *r);
void gr_line_reader_free(gr_line_reader *r);

/* Does the (possibly linked, "a+b") sweep key `linked` name `key`? */
bool gr_linked_key_names(const char *linked, const char *key);

/* ini_parse_stream through whole lines: `handler` sees each long value itself (not
 * GR_LONG_VALUE). Returns 0, the number of the first line refused (by the reader: r->problem says
 * why; by the handler; or not an INI line), or -1 when the file could not be read. */
int gr_line_parse(gr_line_reader *r,
                  int (*handler)(void *user, const char *section, const char *name,
                                 const char *value),
                  void *user);

#endif
