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
    bool
        keep_on_error; /* a streamed file a checkpoint records: a failed commit keeps the temporary */
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
/* A text cell of a table, written so that numpy.genfromtxt (which knows no quoting and takes '#'
 * for a comment) reads it as one cell, as pandas.read_csv does: a ',' becomes ';' (so a label's
 * "k1=v1, k2=v2" reads "k1=v1; k2=v2"), a '#' a blank, a '"' a "'", a line break a blank;
 * between double quotes when quote. */
void gr_csv_text(FILE *f, const char *text, bool quote);
/* A label read back from such a cell, in place: "; " becomes ", " again (the inverse of
 * gr_csv_text for labels whose only commas are ", " separators). */
void gr_csv_label(char *text);
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

/* What granule wrote into an output folder, told by the files at its top (docs/architecture.md,
 * "Output folders"). */
typedef enum gr_output_kind {
    GR_OUTPUT_ANY =
        -1, /* gr_output_dir_prepare only: a sub-folder a command manages itself (no check) */
    GR_OUTPUT_NONE,     /* absent, empty, or nothing granule wrote */
    GR_OUTPUT_RUN,      /* granule run: summary.json with scene.ini, scene.ini, checkpoint */
    GR_OUTPUT_COMPARE,  /* granule compare: compare.json, compare.md, compare.csv */
    GR_OUTPUT_SWEEP,    /* granule sweep: sweep.csv, pNNNN/point.json */
    GR_OUTPUT_CAMPAIGN, /* granule reproduce: sweep.ini (with scene.ini, runs/, results/) */
    GR_OUTPUT_LAMMPS,   /* granule export lammps: in.granule, data.granule */
    GR_OUTPUT_RESULT,   /* another command's results: summary.json without scene.ini, cost.json */
} gr_output_kind;

/* The kind of output dir holds; what (len bytes) gets the file that tells it ("" for NONE). */
gr_output_kind gr_output_dir_kind(const char *dir, char *what, size_t len);
/* "a run", "a comparison", ... */
const char *gr_output_kind_name(gr_output_kind kind);

/* Remove dir and everything under it (symlinks removed, never followed). */
int gr_output_dir_remove(const char *dir, gr_error *err);

/* Create dir (and parents) for a result of `kind` and prove it is writable. A folder holding a
 * result (gr_output_dir_kind) is refused (GR_EINVAL, naming the folder, what it holds and
 * --force) unless force; with force it is emptied as a whole first (its lock files kept), but
 * only when everything in it is granule's own output (names granule writes: *.csv, *.json,
 * *.ini, *.png, ...; symbolic links are removed, never followed) and no run in it is still
 * going: otherwise it is refused even with force. Not refused, and not emptied: a folder of the same kind that a
 * command continues (a sweep or campaign rerun into its own folder, a run that left no
 * summary.json and no checkpoint: emptied), a folder holding nothing granule wrote. kind
 * GR_OUTPUT_ANY only creates and probes (sub-folders a command manages itself). */
int gr_output_dir_prepare(const char *dir, gr_output_kind kind, bool force, gr_error *err);

/* Input files (scenes, sweep and campaign files, checkpoints, snapshots, trajectories, dumps):
 * opened for reading without blocking on a FIFO (open with O_NONBLOCK, fstat, anything but a
 * regular file refused, then O_NONBLOCK cleared), so no input can hang a command.
 * gr_input_fopen: the stream, or NULL with *why = errno, or *why = -1 for a folder, FIFO, device
 * or socket (the caller words the message). gr_input_open: the same with the messages "PATH: not
 * a regular file (a WHAT must be ...)" (GR_EINVAL) and "PATH: cannot open WHAT: REASON" (GR_EINVAL
 * when it does not exist, GR_EIO otherwise). gr_input_check: open and close (for readers that open
 * the path themselves, such as HDF5). */
/* Before long work whose results go to dir: refuse a bad name or a path that exists and is not a
 * folder (GR_EINVAL), without creating anything (gr_output_dir_prepare does that afterwards). */
int gr_output_dir_precheck(const char *dir, gr_error *err);

FILE *gr_input_fopen(const char *path, int *why);
int gr_input_open(const char *path, const char *what, FILE **out, gr_error *err);
int gr_input_check(const char *path, const char *what, gr_error *err);

#endif
