/* A run's trajectory (output.trajectory, docs/trajectories.md): the frames taken every
 * output.snapshot_every, as one extended-XYZ file per frame (snapshots/snap_NNNNNN.xyz), one
 * multi-frame extended-XYZ file (snapshots/trajectory.xyz) or one H5MD file (trajectory.h5).
 * The writer appends frames and is synced at checkpoints; a resume cuts the frames written after
 * the checkpoint. The reader finds whichever a run folder holds. */
#ifndef GR_TRAJECTORY_H
#define GR_TRAJECTORY_H

#include <stdint.h>

#include "granule/sim.h"
#include "granule/trajectory.h"
#include "io/h5md.h"
#include "io/snapshot.h"

typedef struct gr_traj_writer {
    gr_trajectory_format format;
    char dir[1100]; /* the run folder */
    FILE *xyz;      /* GR_TRAJ_XYZ */
    gr_h5md *h5;    /* GR_TRAJ_H5MD */
    int64_t frames; /* written so far */
} gr_traj_writer;

/* What a run's trajectory holds: its format, whether frames are taken at all
 * (output.snapshot_every > 0), and the particles' description (H5MD writes it into the file). */
typedef struct gr_traj_setup {
    gr_trajectory_format format;
    bool frames;
    gr_h5md_desc particles;
} gr_traj_setup;

/* Start the trajectory of a run in dir (creating snapshots/ if needed): a fresh one, or, when
 * resume_frames >= 0, the existing one cut after its first resume_frames frames. */
int gr_traj_writer_open(gr_traj_writer *w, const gr_traj_setup *s, const char *dir,
                        int64_t resume_frames, gr_error *err);
int gr_traj_writer_frame(gr_traj_writer *w, const gr_particles *p, double t, int64_t step,
                         gr_error *err);
/* Everything appended so far is on disk (called at checkpoints). */
int gr_traj_writer_sync(gr_traj_writer *w, gr_error *err);
int gr_traj_writer_close(gr_traj_writer *w, gr_error *err);

/* Reading a run folder's frames in order. */
typedef struct gr_traj_reader gr_traj_reader;
/* Open the trajectory of run folder dir in format `want` (the run's output.trajectory), or, with
 * want < 0, whichever it holds: trajectory.h5, else snapshots/trajectory.xyz, else the per-frame
 * snapshots. */
int gr_traj_reader_open(const char *dir, int want, gr_traj_reader **r, int64_t *frames,
                        gr_error *err);
/* Frame k (0-based, in increasing k order for the multi-frame XYZ file). */
int gr_traj_reader_frame(gr_traj_reader *r, int64_t k, gr_frame *f, gr_error *err);
/* Name of what was read (for messages), e.g. "DIR/trajectory.h5". */
const char *gr_traj_reader_source(const gr_traj_reader *r);
void gr_traj_reader_close(gr_traj_reader *r);

#endif
