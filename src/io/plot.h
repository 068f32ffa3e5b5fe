#ifndef GR_PLOT_H
#define GR_PLOT_H

#include <stddef.h>

/* Draw temperature.png and ledger.png from a run folder with gnuplot (pngcairo). Returns 0, or
 * non-zero with a one-line reason in `note` (e.g. gnuplot not installed). */
int gr_plot_run(const char *dir, int dim, char *note, size_t note_size);

/* Run a gnuplot script that draws one PNG into dir/png_name. `body` is the plotting commands
 * (terminal and output are set here; write "plot ..." lines with absolute paths, or use the
 * placeholder-free form relative to dir: gnuplot is run with dir as its working directory).
 * The PNG is drawn to a temporary file and renamed, so it appears whole or not at all. Returns 0,
 * or non-zero with a one-line reason in `note` (gnuplot missing or failing). */
int gr_plot_script(const char *dir, const char *png_name, const char *body, char *note, size_t note_size);

#endif
