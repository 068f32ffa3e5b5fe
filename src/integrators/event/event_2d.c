/* The 2D event-driven core (discs in a periodic square, walls and gravity): event_cells.h
 * instantiated for GR_EV_DIM = 2 (gr_ev2d_alloc, gr_ev2d_window, gr_ev2d_process). */
#define GR_EV_DIM 2
#include "integrators/event/event_cells.h"
