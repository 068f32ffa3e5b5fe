/* A run's trajectory in one of three formats (docs/trajectories.md). The per-frame snapshots are
 * written atomically; the multi-frame XYZ and the H5MD file grow in place: both are flushed after
 * every frame and fsync'ed at checkpoints, and a resume cuts them back to the frames the
 * checkpoint counted (the XYZ file by counting frames, the H5MD datasets by their extent). */
#include <errno.h>
#include <glob.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/files.h"
#include "io/trajectory.h"

/* Byte offset just after the first `frames` frames of an extended-XYZ file, or -1. */
static long xyz_offset_after(FILE *f, int64_t frames)
{
    char line[4096];
    for (int64_t k = 0; k < frames; k++) {
        long n = 0;
        if (!fgets(line, sizeof line, f) || sscanf(line, "%ld", &n) != 1 || n < 1) {
            return -1;
        }
        for (long i = 0; i <= n; i++) { /* the comment line and n particles */
            if (!fgets(line, sizeof line, f)) {
                return -1;
            }
        }
    }
    return ftell(f);
}

static int xyz_open(gr_traj_writer *w, int64_t resume_frames, gr_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/snapshots/trajectory.xyz", w->dir);
    w->xyz = fopen(path, resume_frames >= 0 ? "r+" : "w");
    if (!w->xyz) {
        return GR_FAIL(err, GR_EIO, "cannot open %s: %s", path, strerror(errno));
    }
    if (resume_frames >= 0) {
        long at = xyz_offset_after(w->xyz, resume_frames);
        if (at < 0 || fseek(w->xyz, at, SEEK_SET) != 0 || ftruncate(fileno(w->xyz), at) != 0) {
            fclose(w->xyz);
            w->xyz = NULL;
            return GR_FAIL(err, GR_EIO, "%s: cannot cut to the %lld frames of the checkpoint", path,
                           (long long)resume_frames);
        }
    }
    return GR_OK;
}

int gr_traj_writer_open(gr_traj_writer *w, const gr_traj_setup *s, const char *dir,
                        int64_t resume_frames, gr_error *err)
{
    memset(w, 0, sizeof *w);
    w->format = s->format;
    w->frames = resume_frames > 0 ? resume_frames : 0;
    snprintf(w->dir, sizeof w->dir, "%s", dir);
    if (!s->frames) {
        return GR_OK;
    }
    char path[1200];
    if (w->format != GR_TRAJ_H5MD) {
        snprintf(path, sizeof path, "%s/snapshots", dir);
        if (mkdir(path, 0777) != 0 && access(path, W_OK) != 0) {
            return GR_FAIL(err, GR_EIO, "cannot create %s", path);
        }
    }
    if (w->format == GR_TRAJ_XYZ) {
        return xyz_open(w, resume_frames, err);
    }
    if (w->format == GR_TRAJ_H5MD) {
        snprintf(path, sizeof path, "%s/trajectory.h5", dir);
        if (resume_frames >= 0) {
            return gr_h5md_reopen(path, resume_frames, s->particles.n, &w->h5, err);
        }
        return gr_h5md_create(path, &s->particles, &w->h5, err);
    }
    return GR_OK;
}

int gr_traj_writer_frame(gr_traj_writer *w, const gr_particles *p, double t, int64_t step,
                         gr_error *err)
{
    int rc = GR_OK;
    if (w->format == GR_TRAJ_SNAPSHOTS) {
        char snapdir[1200];
        snprintf(snapdir, sizeof snapdir, "%s/snapshots", w->dir);
        rc = gr_snapshot_write(snapdir, (int)w->frames, p, t, step, err);
    } else if (w->format == GR_TRAJ_XYZ) {
        gr_xyz_write_frame(w->xyz, p, t, step);
        if (fflush(w->xyz) != 0 || ferror(w->xyz)) {
            char path[1200];
            snprintf(path, sizeof path, "%s/snapshots/trajectory.xyz", w->dir);
            rc = gr_file_fail(path, errno, err);
        }
    } else {
        rc = gr_h5md_append(w->h5, p, p->omega, t, step, err);
    }
    w->frames += rc == GR_OK;
    return rc;
}

int gr_traj_writer_sync(gr_traj_writer *w, gr_error *err)
{
    if (w->xyz && (fflush(w->xyz) != 0 || fsync(fileno(w->xyz)) != 0)) {
        return GR_FAIL(err, GR_EIO, "cannot sync %s/snapshots/trajectory.xyz: %s", w->dir,
                       strerror(errno));
    }
    return GR_OK; /* the H5MD file is flushed after every frame */
}

int gr_traj_writer_close(gr_traj_writer *w, gr_error *err)
{
    int rc = GR_OK;
    if (w->xyz) {
        rc = fclose(w->xyz) != 0
                 ? GR_FAIL(err, GR_EIO, "cannot finish %s/snapshots/trajectory.xyz: %s", w->dir,
                           strerror(errno))
                 : GR_OK;
        w->xyz = NULL;
    }
    if (w->h5) {
        rc = gr_h5md_close(w->h5, err) ? GR_EIO : rc;
        w->h5 = NULL;
    }
    return rc;
}

struct gr_traj_reader {
    gr_trajectory_format format;
    char source[1200];
    glob_t files; /* snapshots */
    FILE *xyz;    /* xyz: read in order */
    long line_no;
    int64_t next;
    gr_h5md *h5;
};

static int64_t xyz_count(FILE *f)
{
    int64_t k = 0;
    while (xyz_offset_after(f, 1) >= 0) {
        k++;
    }
    rewind(f);
    return k;
}

int gr_traj_reader_open(const char *dir, int want, gr_traj_reader **out, int64_t *frames,
                        gr_error *err)
{
    *out = NULL;
    gr_traj_reader *r = calloc(1, sizeof *r);
    if (!r) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    struct stat st;
    snprintf(r->source, sizeof r->source, "%.1100s/trajectory.h5", dir);
    if ((want < 0 && stat(r->source, &st) == 0) || want == GR_TRAJ_H5MD) {
        r->format = GR_TRAJ_H5MD;
        int rc = gr_input_check(r->source, "trajectory", err);
        rc = rc ? rc : gr_h5md_open_read(r->source, &r->h5, frames, err);
        if (rc) {
            free(r);
            return rc;
        }
        *out = r;
        return GR_OK;
    }
    snprintf(r->source, sizeof r->source, "%.1100s/snapshots/trajectory.xyz", dir);
    if ((want < 0 && stat(r->source, &st) == 0) || want == GR_TRAJ_XYZ) {
        r->format = GR_TRAJ_XYZ;
        int e = 0;
        r->xyz = gr_input_fopen(r->source, &e);
        if (!r->xyz) {
            free(r);
            if (e < 0) {
                return GR_FAIL(
                    err, GR_EINVAL,
                    "%s/snapshots/trajectory.xyz: not a regular file (a trajectory is a file "
                    "granule wrote; a folder, FIFO, device or socket is refused)",
                    dir);
            }
            return GR_FAIL(err, e == ENOENT ? GR_EINVAL : GR_EIO,
                           "cannot open %s/snapshots/trajectory.xyz (output.trajectory = xyz): %s",
                           dir, strerror(e));
        }
        *frames = xyz_count(r->xyz);
        *out = r;
        return GR_OK;
    }
    r->format = GR_TRAJ_SNAPSHOTS;
    snprintf(r->source, sizeof r->source, "%.1100s/snapshots/snap_*.xyz", dir);
    if (glob(r->source, 0, NULL, &r->files) != 0 || r->files.gl_pathc == 0) {
        globfree(&r->files);
        free(r);
        return GR_FAIL(err, GR_EINVAL,
                       "no trajectory in %s (no trajectory.h5, snapshots/trajectory.xyz or "
                       "snapshots/snap_*.xyz; run with output.snapshot_every > 0)",
                       dir);
    }
    *frames = (int64_t)r->files.gl_pathc;
    *out = r;
    return GR_OK;
}

int gr_traj_reader_frame(gr_traj_reader *r, int64_t k, gr_frame *f, gr_error *err)
{
    if (r->format == GR_TRAJ_H5MD) {
        return gr_h5md_read_frame(r->h5, k, f, err);
    }
    if (r->format == GR_TRAJ_SNAPSHOTS) {
        if (k < 0 || (size_t)k >= r->files.gl_pathc) {
            return GR_FAIL(err, GR_EINVAL, "%s: no frame %lld", r->source, (long long)k);
        }
        return gr_snapshot_read(r->files.gl_pathv[k], f, err);
    }
    if (k > r->next) { /* skip to frame k */
        if (xyz_offset_after(r->xyz, k - r->next) < 0) {
            return GR_FAIL(err, GR_EINVAL, "%s: no frame %lld", r->source, (long long)k);
        }
        r->next = k;
        r->line_no = -1; /* no longer counted */
    }
    if (k != r->next) {
        return GR_FAIL(err, GR_EINVAL, "%s: frames are read in order (asked %lld, next %lld)",
                       r->source, (long long)k, (long long)r->next);
    }
    int rc = gr_xyz_read_frame(r->xyz, r->source, &r->line_no, f, err);
    if (rc == 1) {
        return GR_FAIL(err, GR_EINVAL, "%s: no frame %lld", r->source, (long long)k);
    }
    r->next += rc == GR_OK;
    return rc;
}

const char *gr_traj_reader_source(const gr_traj_reader *r) { return r->source; }

void gr_traj_reader_close(gr_traj_reader *r)
{
    if (!r) {
        return;
    }
    if (r->format == GR_TRAJ_SNAPSHOTS) {
        globfree(&r->files);
    }
    if (r->xyz) {
        fclose(r->xyz);
    }
    gr_h5md_close(r->h5, &(gr_error){0});
    free(r);
}
