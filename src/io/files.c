/* Atomic output files and output-folder checks: a reader never sees a half-written file, and a
 * full disk or unwritable folder is reported with the path and the system's reason. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/files.h"

int gr_file_open(gr_file *out, const char *dir, const char *name, gr_error *err)
{
    snprintf(out->path, sizeof out->path, "%s/%s", dir, name);
    snprintf(out->tmp, sizeof out->tmp, "%s.tmp%ld", out->path, (long)getpid());
    out->notes = NULL;
    out->notes_len = 0;
    out->units = NULL;
    out->columns = 0;
    out->keep_on_error = false;
    out->f = fopen(out->tmp, "w");
    if (!out->f) {
        return gr_file_fail(out->path, errno, err);
    }
    return GR_OK;
}

/* Why an earlier buffered write of this stream failed. stdio may drop the buffer it could not
 * write, so a later fflush can succeed and errno may have moved on: ask the file system again
 * by appending to the (already lost) temporary file until it refuses. */
static int lost_write_reason(FILE *f)
{
    int fd = fileno(f);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        return EIO;
    }
    static const char zeros[65536];
    off_t at = st.st_size;
    for (int i = 0; i < 4; i++) {
        ssize_t w = pwrite(fd, zeros, sizeof zeros, at);
        if (w < 0) {
            return errno;
        }
        at += w;
    }
    return EIO; /* there is room again: the failure was not (or no longer) a full disk */
}

void gr_file_note(gr_file *out, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *grown = len > 0 ? realloc(out->notes, out->notes_len + (size_t)len + 1) : NULL;
    if (!grown) {
        return; /* notes are a convenience; the table is the result */
    }
    va_start(ap, fmt);
    vsnprintf(grown + out->notes_len, (size_t)len + 1, fmt, ap);
    va_end(ap);
    out->notes = grown;
    out->notes_len += (size_t)len;
}

/* NAME.meta.json beside NAME.csv (see gr_file_note) */
static int notes_commit(const gr_file *t, gr_error *err)
{
    const char *slash = strrchr(t->path, '/'), *base = slash ? slash + 1 : t->path;
    char dir[1100], name[300];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - t->path) : 1, slash ? t->path : ".");
    const char *dot = strrchr(base, '.');
    snprintf(name, sizeof name, "%.*s.meta.json", dot ? (int)(dot - base) : (int)strlen(base), base);
    cJSON *j = cJSON_CreateObject(), *notes = cJSON_AddArrayToObject(j, "notes");
    cJSON_AddStringToObject(j, "file", base);
    if (t->units) {
        cJSON_AddItemReferenceToObject(j, "units", t->units);
    }
    char *text = t->notes;
    for (char *line = text ? strtok(text, "\n") : NULL; line; line = strtok(NULL, "\n")) {
        line += line[0] == '#' ? 1 + (line[1] == ' ') : 0;
        if (line[0]) {
            cJSON_AddItemToArray(notes, cJSON_CreateString(line));
        }
    }
    char *json = cJSON_Print(j);
    cJSON_Delete(j);
    gr_file f;
    int rc = json ? gr_file_open(&f, dir, name, err) : GR_FAIL(err, GR_ENOMEM, "out of memory for %s", name);
    if (!rc) {
        fprintf(f.f, "%s\n", json);
        rc = gr_file_commit(&f, err);
    }
    cJSON_free(json);
    return rc;
}

int gr_file_commit(gr_file *out, gr_error *err)
{
    if (out->notes || out->units) {
        int rc = notes_commit(out, err);
        free(out->notes);
        out->notes = NULL;
        cJSON_Delete(out->units);
        out->units = NULL;
        if (rc) { /* a streamed table a checkpoint records keeps its temporary, as for its own write */
            if (out->keep_on_error) {
                gr_file_keep(out);
            } else {
                gr_file_abandon(out);
            }
            return rc;
        }
    }
    int e = fflush(out->f) != 0 ? errno : 0;
    if (!e && ferror(out->f)) {
        e = lost_write_reason(out->f); /* an earlier write failed and its data are gone */
    }
    if (!e && fsync(fileno(out->f)) != 0 && errno != EINVAL) {
        e = errno; /* EINVAL: a file system without fsync (e.g. a pipe); nothing to sync */
    }
    if (fclose(out->f) != 0 && !e) {
        e = errno;
    }
    out->f = NULL;
    if (e) {
        if (!out->keep_on_error) {
            unlink(out->tmp); /* never leave a half-written file behind */
        }
        return gr_file_fail(out->path, e, err);
    }
    if (rename(out->tmp, out->path) != 0) {
        int r = errno;
        unlink(out->tmp);
        return GR_FAIL(err, GR_EIO, "cannot move %s into place: %s", out->path, strerror(r));
    }
    return GR_OK;
}

int gr_file_check(gr_file *out, gr_error *err)
{
    if (!out->f || !ferror(out->f)) {
        return GR_OK;
    }
    int e = fflush(out->f) != 0 ? errno : lost_write_reason(out->f);
    return gr_file_fail(out->path, e, err);
}

int gr_file_fail(const char *path, int errnum, gr_error *err)
{
    if (errnum == ENOSPC || errnum == EDQUOT) {
        return GR_FAIL(err, GR_EIO, "disk full while writing %s: %s", path, strerror(errnum));
    }
    return GR_FAIL(err, GR_EIO, "cannot write %s: %s", path, strerror(errnum));
}

void gr_file_keep(gr_file *out)
{
    free(out->notes); /* a resume writes the notes and units again */
    out->notes = NULL;
    cJSON_Delete(out->units);
    out->units = NULL;
    if (out->f) {
        fclose(out->f); /* may fail on a full disk: the checkpoint's length is on disk already */
        out->f = NULL;
    }
}

void gr_file_abandon(gr_file *out)
{
    free(out->notes);
    out->notes = NULL;
    cJSON_Delete(out->units);
    out->units = NULL;
    if (out->f) {
        fclose(out->f);
        out->f = NULL;
        unlink(out->tmp);
    }
}

static int mkdir_p(const char *dir, gr_error *err)
{
    char buf[1100];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *p = buf + 1; *p; p++) {
        if (*p == '/') {
            *p = 0;
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                return GR_FAIL(err, GR_EIO, "cannot create output folder %s: %s", buf, strerror(errno));
            }
            *p = '/';
        }
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
        return GR_FAIL(err, GR_EIO, "cannot create output folder %s: %s", buf, strerror(errno));
    }
    struct stat st;
    if (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode)) {
        return GR_FAIL(err, GR_EIO, "output folder %s exists but is not a folder", buf);
    }
    return GR_OK;
}

int gr_output_path_check(const char *dir, gr_error *err)
{
    for (const unsigned char *c = (const unsigned char *)dir; *c; c++) {
        if (*c < 0x20 || *c == 0x7f) {
            return GR_FAIL(err, GR_EINVAL, "output folder %s: the name holds a %s (byte 0x%02x); the run's scene.ini could "
                           "not name it and the run could never be resumed: choose a name without control characters",
                           dir, *c == '\n' ? "newline" : "control character", *c);
        }
    }
    return *dir ? GR_OK : GR_FAIL(err, GR_EINVAL, "output folder: empty name");
}

int gr_output_dir_prepare(const char *dir, bool force, gr_error *err)
{
    int rc = gr_output_path_check(dir, err);
    rc = rc ? rc : mkdir_p(dir, err);
    if (rc) {
        return rc;
    }
    char probe[1200];
    snprintf(probe, sizeof probe, "%s/summary.json", dir);
    if (!force && access(probe, F_OK) == 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "output folder %s already holds a run (summary.json); choose another folder or pass --force to overwrite it",
                       dir);
    }
    snprintf(probe, sizeof probe, "%s/.granule-write-test.%ld", dir, (long)getpid());
    int fd = open(probe, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        return GR_FAIL(err, GR_EIO, "output folder %s is not writable: %s", dir, strerror(errno));
    }
    /* one byte, so a disk that is already full is refused before the run starts */
    int e = write(fd, "\n", 1) == 1 ? 0 : errno ? errno : ENOSPC;
    e = close(fd) != 0 && !e ? errno : e;
    unlink(probe);
    if (e == ENOSPC || e == EDQUOT) {
        return GR_FAIL(err, GR_EIO, "disk full: output folder %s has no space left: %s", dir, strerror(e));
    }
    if (e) {
        return GR_FAIL(err, GR_EIO, "output folder %s is not writable: %s", dir, strerror(e));
    }
    return GR_OK;
}
