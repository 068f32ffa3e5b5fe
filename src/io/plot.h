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

/* The shared palette of every plot: eight colours of high contrast on white (no yellow), in the
 * order overlays use them; gr_plot_script makes them gnuplot's line types 1-8. */
#define GR_PLOT_COLOURS 8
extern const char *const gr_plot_palette[GR_PLOT_COLOURS];
/* The style of series k of an overlay (0-based): "lc rgb '<palette k>' dt <1-4> lw 2", so that
 * up to eight series differ in colour and neighbours also in dash type. */
void gr_plot_series_style(int k, char *buf, size_t size);

#endif
