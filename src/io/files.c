/* Atomic output files and output-folder checks: a reader never sees a half-written file, and a
 * full disk or unwritable folder is reported with the path and the system's reason. */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/checkpoint.h"
#include "io/dir_lock.h"
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
    snprintf(name, sizeof name, "%.*s.meta.json", dot ? (int)(dot - base) : (int)strlen(base),
             base);
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
    int rc = json ? gr_file_open(&f, dir, name, err)
                  : GR_FAIL(err, GR_ENOMEM, "out of memory for %s", name);
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
                return GR_FAIL(err, GR_EIO, "cannot create output folder %s: %s", buf,
                               strerror(errno));
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
            return GR_FAIL(
                err, GR_EINVAL,
                "output folder %s: the name holds a %s (byte 0x%02x); the run's scene.ini could "
                "not name it and the run could never be resumed: choose a name without control "
                "characters",
                dir, *c == '\n' ? "newline" : "control character", *c);
        }
    }
    return *dir ? GR_OK : GR_FAIL(err, GR_EINVAL, "output folder: empty name");
}

static bool has(const char *dir, const char *name)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat st;
    return lstat(path, &st) == 0;
}

/* a sweep point's folder name: p and four or more digits */
static bool point_name(const char *name)
{
    size_t n = strlen(name);
    return name[0] == 'p' && n >= 5 && strspn(name + 1, "0123456789") == n - 1;
}

gr_output_kind gr_output_dir_kind(const char *dir, char *what, size_t len)
{
    static const struct {
        const char *name;
        gr_output_kind kind;
    } marks[] = {{"compare.json", GR_OUTPUT_COMPARE}, {"compare.md", GR_OUTPUT_COMPARE},
                 {"compare.csv", GR_OUTPUT_COMPARE},  {"sweep.ini", GR_OUTPUT_CAMPAIGN},
                 {"sweep.csv", GR_OUTPUT_SWEEP},      {"in.granule", GR_OUTPUT_LAMMPS},
                 {"data.granule", GR_OUTPUT_LAMMPS},  {"cost.json", GR_OUTPUT_RESULT}};
    snprintf(what, len, "%s", "");
    for (size_t i = 0; i < sizeof marks / sizeof marks[0]; i++) {
        if (has(dir, marks[i].name)) {
            snprintf(what, len, "%s", marks[i].name);
            return marks[i].kind;
        }
    }
    DIR *d = opendir(dir);
    for (struct dirent *de; d && (de = readdir(d));) {
        char sub[600];
        snprintf(sub, sizeof sub, "%.300s/point.json", de->d_name);
        if (point_name(de->d_name) && has(dir, sub)) {
            snprintf(what, len, "%s", sub);
            closedir(d);
            return GR_OUTPUT_SWEEP;
        }
    }
    if (d) {
        closedir(d);
    }
    const bool summary = has(dir, "summary.json"), scene = has(dir, "scene.ini");
    const char *run = summary && scene               ? "summary.json"
                      : scene                        ? "scene.ini"
                      : has(dir, GR_CHECKPOINT_NAME) ? GR_CHECKPOINT_NAME
                                                     : NULL;
    if (run || summary) {
        snprintf(what, len, "%s", run ? run : "summary.json");
        return run ? GR_OUTPUT_RUN : GR_OUTPUT_RESULT;
    }
    return GR_OUTPUT_NONE;
}

const char *gr_output_kind_name(gr_output_kind kind)
{
    switch (kind) {
    case GR_OUTPUT_RUN: return "a run";
    case GR_OUTPUT_COMPARE: return "a comparison";
    case GR_OUTPUT_SWEEP: return "a sweep";
    case GR_OUTPUT_CAMPAIGN: return "a campaign of granule reproduce";
    case GR_OUTPUT_LAMMPS: return "a LAMMPS export";
    case GR_OUTPUT_RESULT: return "the results of a granule command";
    default: return "nothing of granule's";
    }
}

/* the folders' lock files (src/io/dir_lock.h): kept when a folder is emptied */
static bool lock_name(const char *name)
{
    return !strcmp(name, ".run.lock") || !strcmp(name, ".point.lock");
}

/* A name granule writes into an output folder: its tables, notes, scenes, plots, trajectories,
 * checkpoints, LAMMPS files, lock files and partial files NAME.tmpPID. */
static bool own_name(const char *name)
{
    static const char *const ext[] = {".csv", ".json", ".png", ".svg",     ".pdf",       ".gp",
                                      ".dat", ".xyz",  ".h5",  ".granule", ".lammpstrj", ".lammps"};
    const char *tmp = strstr(name, ".tmp");
    if (tmp && tmp > name && (!tmp[4] || strspn(tmp + 4, "0123456789") == strlen(tmp + 4))) {
        return true; /* NAME.tmpPID, checkpoint.tmp */
    }
    if (lock_name(name) || !strcmp(name, GR_CHECKPOINT_NAME) ||
        !strncmp(name, ".granule-write-test.", 20) || !strcmp(name, "scene.ini") ||
        !strcmp(name, "sweep.ini") || !strcmp(name, "compare.md")) {
        return true; /* not any *.ini or *.md: a user's scene file or notes may sit beside the results */
    }
    const char *dot = strrchr(name, '.');
    for (size_t i = 0; dot && dot > name && i < sizeof ext / sizeof ext[0]; i++) {
        if (!strcmp(dot, ext[i])) {
            return true;
        }
    }
    return false;
}

/* Everything under dir granule's own (sub-folders too, to `depth` levels)? If not, *bad names the
 * first entry that is not (a foreign file, or a folder where a run is still going: *busy). */
static bool all_own(const char *dir, int depth, char *bad, size_t len, bool *busy)
{
    DIR *d = opendir(dir);
    if (!d) {
        snprintf(bad, len, "%s (unreadable: %s)", dir, strerror(errno));
        return false;
    }
    bool ok = true;
    char holder[400];
    for (struct dirent *de; ok && (de = readdir(d));) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..")) {
            continue;
        }
        char path[1400];
        snprintf(path, sizeof path, "%.1100s/%.290s", dir, de->d_name);
        struct stat st;
        if (lstat(path, &st) != 0) {
            continue; /* gone meanwhile */
        }
        if (S_ISDIR(st.st_mode)) {
            ok = depth > 0 && all_own(path, depth - 1, bad, len, busy);
            if (!ok && !bad[0]) {
                snprintf(bad, len, "%s", path);
            }
        } else if (!strcmp(de->d_name, ".run.lock") &&
                   gr_dir_lock_held(dir, de->d_name, holder, sizeof holder)) {
            ok = false;
            *busy = true;
            snprintf(bad, len, "%s", dir);
        } else if (!own_name(de->d_name) || !(S_ISREG(st.st_mode) || S_ISLNK(st.st_mode))) {
            ok = false;
            snprintf(bad, len, "%s", path);
        }
    }
    closedir(d);
    return ok;
}

/* Remove everything under dir (checked by all_own), but the lock files at its top and a sweep
 * point's manifest point.json, which the sweep holding the point rewrites. */
static int empty_dir(const char *dir, bool top, gr_error *err)
{
    DIR *d = opendir(dir);
    if (!d) {
        return GR_FAIL(err, GR_EIO, "cannot empty output folder %s: %s", dir, strerror(errno));
    }
    int rc = GR_OK;
    for (struct dirent *de; !rc && (de = readdir(d));) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..") ||
            (top && (lock_name(de->d_name) ||
                     (!strcmp(de->d_name, "point.json") && has(dir, ".point.lock"))))) {
            continue;
        }
        char path[1400];
        snprintf(path, sizeof path, "%.1100s/%.290s", dir, de->d_name);
        struct stat st;
        if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            rc = empty_dir(path, false, err);
            if (!rc && rmdir(path) != 0 && errno != ENOENT) {
                rc = GR_FAIL(err, GR_EIO, "cannot remove %s: %s", path, strerror(errno));
            }
        } else if (unlink(path) != 0 && errno != ENOENT) {
            rc = GR_FAIL(err, GR_EIO, "cannot remove %s: %s", path, strerror(errno));
        }
    }
    closedir(d);
    return rc;
}

int gr_output_dir_remove(const char *dir, gr_error *err)
{
    int rc = empty_dir(dir, false, err);
    if (!rc && rmdir(dir) != 0 && errno != ENOENT) {
        rc = GR_FAIL(err, GR_EIO, "cannot remove %s: %s", dir, strerror(errno));
    }
    return rc;
}

/* The folder check of gr_output_dir_prepare: refuse, empty or leave dir as it is. */
static int claim_dir(const char *dir, gr_output_kind kind, bool force, gr_error *err)
{
    char what[400];
    const gr_output_kind held = gr_output_dir_kind(dir, what, sizeof what);
    if (held == GR_OUTPUT_NONE) {
        return GR_OK; /* nothing of granule's is replaced (a user's own files stay) */
    }
    /* continued in place: a sweep or campaign rerun (finished points are kept; --force reruns
     * them), a run that left no result (emptied below: nothing can continue it) */
    const bool again =
        held == kind &&
        (kind == GR_OUTPUT_SWEEP || kind == GR_OUTPUT_CAMPAIGN ||
         (kind == GR_OUTPUT_RUN && !has(dir, "summary.json") && !has(dir, GR_CHECKPOINT_NAME)));
    if (again && kind != GR_OUTPUT_RUN) {
        return GR_OK;
    }
    if (!again && !force) {
        return GR_FAIL(
            err, GR_EINVAL, "output folder %s already holds %s (%s); choose another folder%s", dir,
            gr_output_kind_name(held), what,
            kind == GR_OUTPUT_CAMPAIGN ? ""
                                       : " or pass --force to replace it (it is emptied first)");
    }
    char bad[1500] = "";
    bool busy = false;
    if (again && !force && !has(dir, ".run.lock")) {
        return GR_OK; /* a scene.ini no run of granule's wrote beside (a user's folder): left as it is */
    }
    if (!all_own(dir, 6, bad, sizeof bad, &busy)) {
        if (again) {
            return GR_OK; /* a killed run's folder with files of the user's: kept, as it is */
        }
        if (busy) {
            return GR_FAIL(
                err, GR_EINVAL,
                "output folder %s holds %s with a run still going in %s (.run.lock): "
                "--force does not replace it; wait for it to finish, or choose another folder",
                dir, gr_output_kind_name(held), bad);
        }
        return GR_FAIL(
            err, GR_EINVAL,
            "output folder %s holds %s (%s) and also %s, which granule did not write: --force "
            "replaces only a folder of granule's own outputs; move that away or choose another "
            "folder",
            dir, gr_output_kind_name(held), what, bad);
    }
    return empty_dir(dir, true, err);
}

int gr_output_dir_prepare(const char *dir, gr_output_kind kind, bool force, gr_error *err)
{
    int rc = gr_output_path_check(dir, err);
    rc = rc || kind == GR_OUTPUT_ANY ? rc : claim_dir(dir, kind, force, err);
    rc = rc ? rc : mkdir_p(dir, err);
    if (rc) {
        return rc;
    }
    char probe[1200];
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
        return GR_FAIL(err, GR_EIO, "disk full: output folder %s has no space left: %s", dir,
                       strerror(e));
    }
    if (e) {
        return GR_FAIL(err, GR_EIO, "output folder %s is not writable: %s", dir, strerror(e));
    }
    return GR_OK;
}

/* ---- input files ---------------------------------------------------------------------------- */

FILE *gr_input_fopen(const char *path, int *why)
{
    /* O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        *why = errno;
        return NULL;
    }
    struct stat st;
    int e = fstat(fd, &st) != 0 ? errno : !S_ISREG(st.st_mode) ? -1 : 0;
    const int fl = e ? 0 : fcntl(fd, F_GETFL);
    if (!e && (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0)) {
        e = errno;
    }
    FILE *f = e ? NULL : fdopen(fd, "r");
    if (!f) {
        e = e ? e : errno;
        close(fd);
    }
    *why = e;
    return f;
}

int gr_input_open(const char *path, const char *what, FILE **out, gr_error *err)
{
    int why = 0;
    *out = gr_input_fopen(path, &why);
    if (*out) {
        return GR_OK;
    }
    if (why < 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: not a regular file (a %s must be a regular file; a folder, FIFO, "
                       "device or socket is refused)",
                       path, what);
    }
    return GR_FAIL(err, why == ENOENT || why == ENOTDIR ? GR_EINVAL : GR_EIO,
                   "%s: cannot open %s: %s", path, what, strerror(why));
}

int gr_input_check(const char *path, const char *what, gr_error *err)
{
    FILE *f;
    int rc = gr_input_open(path, what, &f, err);
    if (!rc) {
        fclose(f);
    }
    return rc;
}

int gr_output_dir_precheck(const char *dir, gr_error *err)
{
    int rc = gr_output_path_check(dir, err);
    struct stat st;
    if (!rc && stat(dir, &st) == 0 && !S_ISDIR(st.st_mode)) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "output folder %s exists but is not a folder; choose another --out", dir);
    }
    return rc;
}
