/* Plots drawn by gnuplot from the CSV tables beside them (docs/plots.md). Every plot is a
 * gnuplot body kept as NAME.gp beside the picture (so `granule plot DIR` redraws it) and run
 * under one shared preamble: terminal and fonts sized for slides, the palette as line types 1-8,
 * tick labels "%h" (10^{n} on log axes), margins so that no point sits on the frame. */
#ifndef GR_PLOT_H
#define GR_PLOT_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>

/* The picture format: pngcairo, svg or pdfcairo. */
typedef enum { GR_PLOT_PNG, GR_PLOT_SVG, GR_PLOT_PDF } gr_plot_format;

/* "png", "svg", "pdf" -> the format; -1 for anything else. */
int gr_plot_format_parse(const char *name);
const char *gr_plot_extension(gr_plot_format f);
/* The format every plot of this process is drawn in (PNG unless set; the CLI sets it once from
 * --format before anything is drawn). */
void gr_plot_set_format(gr_plot_format f);
gr_plot_format gr_plot_get_format(void);
/* The file a plot named like "NAME.png" is drawn to in the current format ("NAME.svg"). */
void gr_plot_file_name(const char *png_name, char *buf, size_t size);

/* The whole gnuplot script for `body` drawn to `output` in format f: the shared preamble,
 * "set output", the body, "set output". The caller frees it. NULL when out of memory. */
char *gr_plot_compose(const char *body, const char *output, gr_plot_format f);

/* Draw temperature and ledger of a run folder (T(t) with its running mean, Figs. 2.7-2.8; energy
 * injected, dissipated by each mechanism, kinetic + elastic and the ledger residual). Returns 0,
 * or non-zero with a one-line reason in `note` (e.g. gnuplot not installed). */
int gr_plot_run(const char *dir, int dim, char *note, size_t note_size);

/* Run a gnuplot body that draws one picture, dir/png_name with its extension changed to the
 * current format. The body is the plotting commands, run with dir as the working directory (use
 * paths relative to it); it is kept as dir/NAME.gp. The picture is drawn to a temporary file and
 * renamed, so it appears whole or not at all. Returns 0, or non-zero with a one-line reason in
 * `note` (gnuplot missing or failing). */
int gr_plot_script(const char *dir, const char *png_name, const char *body, char *note,
                   size_t note_size);

/* A legend entry "name = value ± error" (the error to two significant digits, the value to the
 * same decimal place, as in the compare table); "name = value" without a finite error. */
void gr_plot_legend_value(const char *name, double value, double error, char *buf, size_t size);

/* The shared palette of every plot: eight colours of high contrast on white (no yellow), in the
 * order overlays use them; the preamble makes them gnuplot's line types 1-8. */
#define GR_PLOT_COLOURS 8
extern const char *const gr_plot_palette[GR_PLOT_COLOURS];
/* The style of series k of an overlay (0-based): "lc rgb '<palette k>' dt <1, 2, 4, 5> lw 2", so that
 * up to eight series differ in colour and neighbours also in dash type. */
void gr_plot_series_style(int k, char *buf, size_t size);

/* Every picture (PNG, SVG or PDF) in dir and dir/analysis, sorted, as names relative to dir,
 * added to the array `list`. Returns how many. */
int gr_plot_list(const char *dir, cJSON *list);
/* Rewrite dir/summary.json's "plots" as the array of every picture in the folder (gr_plot_list);
 * a note the run left there (e.g. "skipped: gnuplot not found") moves to "plot_notes". */
int gr_plot_summary_update(const char *dir);

#endif
