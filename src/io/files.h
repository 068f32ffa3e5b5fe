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
