/* The trajectory formats a run can write (output.trajectory, docs/trajectories.md). */
#ifndef GR_TRAJECTORY_FORMAT_H
#define GR_TRAJECTORY_FORMAT_H

/* Where the frames of output.snapshot_every go: one extended-XYZ file per frame, one multi-frame
 * extended-XYZ file, or one H5MD file. */
typedef enum { GR_TRAJ_SNAPSHOTS, GR_TRAJ_XYZ, GR_TRAJ_H5MD } gr_trajectory_format;

#endif
