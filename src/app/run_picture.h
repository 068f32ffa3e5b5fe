/* The picture of a run folder, drawn from its scene and trajectory (src/app/run_picture.c). */
#ifndef GR_APP_RUN_PICTURE_H
#define GR_APP_RUN_PICTURE_H

#include <stddef.h>

#include "granule/status.h"
#include "io/picture.h"

/* The picture of a run folder: DIR/snapshot.png from the last snapshot in DIR/snapshots (2D) or
 * DIR/snapshots.png, the space-time diagram of the last (up to) 800 snapshots (1D). The radius comes from
 * DIR/scene.ini when it loads, else from the snapshots' radius column. No snapshots: GR_EINVAL. */
int gr_picture_run(const char *run_dir, gr_error *err);

/* As gr_picture_run with options (NULL = defaults); the path written is copied to png_path
 * (may be NULL). */
int gr_picture_run_ex(const char *run_dir, const gr_picture_options *opt, char *png_path,
                      size_t png_path_size, gr_error *err);

#endif
