/* Export a scene to another engine: today LAMMPS (docs/lammps.md), for systems larger than one
 * machine on LAMMPS's MPI domain decomposition. The exported run starts from the very state
 * granule would start from (same placement, same seed), with the same contact law, random force
 * and schedule; its dump is read back by `granule analyse --lammps-dump`. */
#ifndef GRANULE_EXPORT_H
#define GRANULE_EXPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "granule/scene.h"
#include "granule/status.h"

/* What an export wrote, for the caller to report. */
typedef struct gr_lammps_export {
    char deck[1100]; /* DIR/in.granule */
    char data[1100]; /* DIR/data.granule */
    char dump[64];   /* the dump file the deck writes, relative to where LAMMPS runs */
    int64_t warmup_steps, run_steps, sample_steps;
    double kn, gamman, gammat;       /* pair_style gran/hooke coefficients (N/m, 1/s, 1/s) */
    double gamman_wall, gammat_wall; /* fix wall/gran hooke damping (1/s; 0 without walls) */
    double noise_sigma;              /* random force per component per step, N */
} gr_lammps_export;

/* Write DIR/in.granule (the LAMMPS input deck), DIR/data.granule (the initial particles) and
 * DIR/scene.ini (the resolved scene, which `granule analyse` reads next to the dump). Refuses,
 * with the reason, what LAMMPS's GRANULAR package cannot express: 1D, the event-driven and hybrid
 * integrators, hard spheres and sliding friction. A folder holding a result (an earlier export,
 * a run, a comparison, ...) is refused unless force, which replaces its contents as a whole
 * (docs/output.md, "Output folders"); nothing is written before the scene is accepted. */
int gr_export_lammps(const gr_scene *scene, const char *dir, bool force, gr_lammps_export *info,
                     gr_error *err);

#endif
