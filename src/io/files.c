/* Atomic output files and output-folder checks: a reader never sees a half-written file, and a
 * full disk or unwritable folder is reported with the path and the system's reason. */
#include <errno.h>
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
    out->f = fopen(out->tmp, "w");
    if (!out->f) {
        return GR_FAIL(err, GR_EIO, "cannot write %s: %s", out->tmp, strerror(errno));
    }
    return GR_OK;
}

int gr_file_commit(gr_file *out, gr_error *err)
{
    int bad = ferror(out->f) || fflush(out->f) != 0 || fsync(fileno(out->f)) != 0;
    int saved = errno;
    bad |= fclose(out->f) != 0;
    out->f = NULL;
    if (bad) {
        unlink(out->tmp);
        return GR_FAIL(err, GR_EIO, "cannot write %s: %s", out->path, strerror(saved ? saved : errno));
    }
    if (rename(out->tmp, out->path) != 0) {
        int e = errno;
        unlink(out->tmp);
        return GR_FAIL(err, GR_EIO, "cannot move %s into place: %s", out->path, strerror(e));
    }
    return GR_OK;
}

void gr_file_abandon(gr_file *out)
{
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

int gr_output_dir_prepare(const char *dir, bool force, gr_error *err)
{
    int rc = mkdir_p(dir, err);
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
    close(fd);
    unlink(probe);
    return GR_OK;
}
