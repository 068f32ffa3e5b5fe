/* Pictures of snapshots drawn with cairo (being written; see picture.c). */
#ifndef GR_PICTURE_H
#define GR_PICTURE_H

#include "granule/status.h"

int gr_picture_run(const char *run_dir, gr_error *err);

#endif
