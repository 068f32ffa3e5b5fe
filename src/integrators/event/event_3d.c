/* The 3D event-driven core (hard spheres in a periodic cube, with walls and gravity for smooth
 * ones, docs/three-dimensions.md):
 * event_cells.h instantiated for GR_EV_DIM = 3 (gr_ev3d_alloc, gr_ev3d_window, gr_ev3d_process). */
#define GR_EV_DIM 3
#include "integrators/event/event_cells.h"
