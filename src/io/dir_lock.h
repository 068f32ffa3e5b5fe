/* Folder locks: an exclusive flock on a file in an output folder, so that two processes never
 * write one folder at once (two `granule run` into one --out, a --resume of a run still going,
 * two sweeps over one point). The lock ends with the process (or its last inherited descriptor),
 * so a killed run never leaves a stale one. */
#ifndef GR_DIR_LOCK_H
#define GR_DIR_LOCK_H

#include <stdbool.h>
#include <stddef.h>

#include "granule/status.h"

/* gr_dir_lock's answer when a live process holds the lock (nothing taken) */
#define GR_LOCK_HELD 1

/* Lock dir/name (dir exists; name is created): GR_OK with *fd holding it and the file noting
 * "pid P on HOST since T"; GR_LOCK_HELD with holder (len bytes) getting the holder's note; or
 * GR_EIO. Where the file system refuses flock (some network mounts) GR_OK with *fd = -1: nothing
 * is locked and the caller decides whether to say so. O_CLOEXEC, but inherited by fork. */
int gr_dir_lock(const char *dir, const char *name, int *fd, char *holder, size_t len,
                gr_error *err);
/* Release a lock taken by gr_dir_lock on dir/name: the file is deleted while still locked, so a
 * finished folder holds no lock file; *fd = -1. A no-op for -1. (gr_dir_lock checks, once it
 * holds the lock, that dir/name is still the file it locked, so a process that opened the file
 * just before the delete cannot hold a lock nobody else sees.) */
void gr_dir_unlock(const char *dir, const char *name, int *fd);
/* Whether a live process holds dir/name; holder gets its note. Read only: the probe takes a
 * shared lock for an instant, which gr_dir_lock rides out by retrying. */
bool gr_dir_lock_held(const char *dir, const char *name, char *holder, size_t len);

#endif
