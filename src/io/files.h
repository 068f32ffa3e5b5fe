/* Output files: atomic writes and output folders. */
#ifndef GR_FILES_H
#define GR_FILES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "granule/status.h"

/* An output file being written: a temporary beside the target, renamed on commit. */
typedef struct gr_file {
    FILE *f;
    char path[1100], tmp[1120];
    char *notes; /* gr_file_note text, NULL if none */
    size_t notes_len;
    struct cJSON *units; /* gr_file_columns: {"column": "unit"}, NULL if none */
    int columns;         /* columns of the header line written so far */
    bool keep_on_error; /* a streamed file a checkpoint records: a failed commit keeps the temporary */
} gr_file;

int gr_file_open(gr_file *out, const char *dir, const char *name, gr_error *err);
/* fflush + fsync + rename; closes the file either way. On failure the temporary is deleted
 * unless keep_on_error. */
int gr_file_commit(gr_file *out, gr_error *err);
void gr_file_abandon(gr_file *out);
/* Metadata of a table (what it is, units, scene, hash, seed) kept out of the table itself so that
 * pandas.read_csv(path) and numpy.genfromtxt(path, names=True, delimiter=',') read it without
 * options: printf-style text, one note per line (a leading "# " is dropped), written at commit
 * to the sidecar NAME.meta.json ({"file": "NAME.csv", "notes": [...]}) beside NAME.csv. */
void gr_file_note(gr_file *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The header line of a table with its units (src/io/csv_columns.c): spec is "name [unit],..."
 * (UDUNITS-style unit strings as in H5MD: "m s-1", "m2 s-2", "1" for a pure number, "" for a
 * text column); the names go to the file, separated by commas (continuing a line that earlier
 * calls began), and the units to the sidecar as {"units": {"name": "unit", ...}}. A column
 * without "[...]" gets no unit. gr_file_header ends the line. */
void gr_file_columns(gr_file *out, const char *spec);
void gr_file_column(gr_file *out, const char *name, const char *unit);
void gr_file_header(gr_file *out, const char *spec);
/* Only the units of spec (a streamed table continued by a resume has its header already). */
void gr_file_units(gr_file *out, const char *spec);
/* Close without committing and keep the temporary (a checkpoint records it; a resume adopts it). */
void gr_file_keep(gr_file *out);
/* GR_OK while every write to the file so far succeeded; otherwise the error (e.g. "disk full
 * while writing DIR/FILE: No space left on device"), so a long run stops at once instead of
 * finding out at commit. The file stays open: gr_file_commit/abandon still owe it a close. */
int gr_file_check(gr_file *out, gr_error *err);
/* Record the error for a failed write of `path` (errno `errnum`): ENOSPC/EDQUOT read "disk full
 * while writing PATH: ...", anything else "cannot write PATH: ...". Returns GR_EIO. */
int gr_file_fail(const char *path, int errnum, gr_error *err);

/* Refuse an output folder name with control characters (a newline would make its scene.ini
 * unreadable, so the run could never be resumed): GR_EINVAL naming the byte. */
int gr_output_path_check(const char *dir, gr_error *err);

/* Create dir (and parents); refuse a folder holding another run's summary.json unless force;
 * prove it is writable. */
int gr_output_dir_prepare(const char *dir, bool force, gr_error *err);

#endif
