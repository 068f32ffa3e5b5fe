#ifndef GR_PLOT_H
#define GR_PLOT_H

#include <stddef.h>

/* Draw temperature.png and ledger.png from a run folder with gnuplot (pngcairo). Returns 0, or
 * non-zero with a one-line reason in `note` (e.g. gnuplot not installed). */
int gr_plot_run(const char *dir, int dim, char *note, size_t note_size);

#endif
