/* Folder locks (dir_lock.h): flock on a small file whose text names the holder. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "io/dir_lock.h"

static void read_note(int fd, char *holder, size_t len)
{
    ssize_t n = pread(fd, holder, len - 1, 0);
    holder[n > 0 ? n : 0] = 0;
    holder[strcspn(holder, "\n")] = 0;
}

bool gr_dir_lock_held(const char *dir, const char *name, char *holder, size_t len)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    holder[0] = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return false;
    }
    bool held = flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    if (held) {
        read_note(fd, holder, len);
    }
    close(fd); /* also drops the shared lock, if we got it */
    return held;
}

int gr_dir_lock(const char *dir, const char *name, int *fd, char *holder, size_t len, gr_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    holder[0] = 0;
    int e = 0;
    for (int opened = 1;; opened++) {
        *fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (*fd < 0) {
            return GR_FAIL(err, GR_EIO, "cannot open the lock %s: %s", path, strerror(errno));
        }
        /* a few tries: a gr_dir_lock_held probe (another process reading the state) holds a shared
         * lock for a moment, which must not pass for a live holder */
        for (int tries = 1;; tries++) {
            e = flock(*fd, LOCK_EX | LOCK_NB) != 0 ? errno : 0;
            if (e != EWOULDBLOCK || tries == 5) {
                break;
            }
            nanosleep(&(struct timespec){.tv_nsec = 20000000}, NULL);
        }
        /* the holder deletes the file before it lets go (gr_dir_unlock): a lock on a file no
         * longer at `path` is no lock at all; open the new one */
        struct stat mine, now;
        if (e || opened == 100 || fstat(*fd, &mine) != 0 ||
            (stat(path, &now) == 0 && now.st_ino == mine.st_ino && now.st_dev == mine.st_dev)) {
            break;
        }
        close(*fd);
    }
    if (e) {
        if (e == EWOULDBLOCK) {
            read_note(*fd, holder, len);
        }
        close(*fd); /* not ours: its note stays */
        *fd = -1;
        /* no flock here (some network mounts): run unlocked, as before locks existed */
        return e == EWOULDBLOCK ? GR_LOCK_HELD : GR_OK;
    }
    char host[256] = "unknown", note[400];
    gethostname(host, sizeof host - 1);
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    char when[32];
    strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tm);
    int n = snprintf(note, sizeof note, "pid %ld on %.200s since %s\n", (long)getpid(), host, when);
    if (ftruncate(*fd, 0) != 0 || pwrite(*fd, note, (size_t)n, 0) != n) {
        /* the note only names the holder to whoever finds the folder locked */
    }
    return GR_OK;
}

void gr_dir_unlock(const char *dir, const char *name, int *fd)
{
    if (*fd >= 0) {
        /* deleted while still held: whoever opened it meanwhile finds, once it gets the lock, that
         * the path is gone (gr_dir_lock) and takes a new file */
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, name);
        if (unlink(path) != 0 && ftruncate(*fd, 0) != 0) {
            /* a read-only folder: only the note is left behind */
        }
        close(*fd);
        *fd = -1;
    }
}
