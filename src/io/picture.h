/* Snapshot pictures drawn with cairo (issue 4; thesis Figs. 2.6 and 2.9).
 *
 * Particles are drawn to scale and filled with a colour from a ramp by their speed relative to the
 * frame's rms speed, s = |v| / v_rms with v_rms = sqrt(<|v|^2>) over the frame, clipped at
 * opt->vmax (default 3). Both ramps follow the thesis convention: slow = light, fast = dark
 * (Fig. 2.9: "the fastest particles are black-shaded whereas the majority slow moving particles
 * are lightly-shaded"; Fig. 2.6: "darker shaded particles are faster"):
 *   GR_CMAP_VIRIDIS  viridis read backwards: slow = yellow (#fde725), fast = dark violet (#440154)
 *   GR_CMAP_GREY     light grey (0.88) to black, as the thesis figures
 * opt->levels = k > 1 quantises the ramp into k shades (Fig. 2.9 uses 3).
 *
 * 2D (Fig. 2.9): the periodic box as a square of opt->size pixels (default 1000), y pointing up,
 * every disc at its true radius; a disc crossing an edge is drawn on both (all) sides. Below the box
 * a panel holds the time, N, v_rms and the colour bar with its labels.
 * 1D, a run folder: the space-time diagram (gr_picture_spacetime) of its snapshots.
 * 1D (Fig. 2.6), gr_picture_strip: the ring is cut into segments drawn as rows (the line wrapped like text, so discs
 * stay a readable size); gr_picture_strip stacks several frames: within each segment block one row
 * per frame, time running downwards, so a cluster's history reads down the block. A disc crossing a
 * segment boundary (or the ring's end) is drawn at both ends.
 *
 * Labels are drawn with a built-in 5x7 bitmap font: no fontconfig, identical pictures on every
 * machine. PNGs are written to a temporary file beside the target and renamed (src/io/files.h), so
 * a PNG appears whole or not at all; an error leaves no file behind and an earlier PNG untouched. */
#ifndef GR_PICTURE_H
#define GR_PICTURE_H

#include <stdbool.h>
#include <stddef.h>

#include "granule/status.h"
#include "io/snapshot.h"

typedef enum { GR_CMAP_VIRIDIS = 0, GR_CMAP_GREY = 1 } gr_colormap;

/* Zero-initialise; a zero field takes its default. */
typedef struct gr_picture_options {
    int size;             /* 2D: box side in px; 1D: image width in px. 0 = 1000; [64, 8192] */
    gr_colormap colormap; /* default GR_CMAP_VIRIDIS */
    double vmax;          /* |v|/v_rms at which the ramp saturates; 0 = 3; (0, 1000] */
    int levels;           /* 0 = continuous ramp, k in [2, 64]: k shades */
    bool hide_labels;     /* true: no panel (box or rows only) */
    bool walls[3]; /* flat walls along x, y (and z in 3D) ([boundary]): in 2D drawn as bars at 0 and
                      L, in 3D as the box's faces (the farther one shaded behind the spheres, the
                      nearer one outlined in front); positions there neither wrapped nor imaged
                      across the box (a grain below a floor vibrating below 0 is drawn where it
                      is) */
    bool by_species; /* 2D and 3D, a mixture's frame: each grain in its species' colour (a fixed
                        palette, GR_PICTURE_SPECIES_COLOURS), the panel a legend of them */
} gr_picture_options;

/* The species palette (Okabe and Ito's colour-blind-safe set): species k in colour k mod 8. */
#define GR_PICTURE_SPECIES_COLOURS 8

/* Largest image side and pixel count accepted (a larger picture is refused with GR_EINVAL). */
#define GR_PICTURE_MAX_SIDE 8192
#define GR_PICTURE_MAX_PIXELS (40L * 1000L * 1000L)

/* One frame: 2D as the box picture, 1D as a one-frame strip. radius in m (> 0, 2 radius <= L).
 * Errors: GR_EINVAL for bad input (non-finite positions or velocities, radius, options, sizes),
 * GR_EIO for a cairo or file failure (message includes cairo's or the system's reason). */
int gr_picture_frame(const gr_frame *f, double radius, const char *png_path,
                     const gr_picture_options *opt, gr_error *err);

/* 1D frames (all with the same N and L) stacked as rows, first frame on top (Fig. 2.6). */
int gr_picture_strip(const gr_frame *frames, int n, double radius, const char *png_path,
                     const gr_picture_options *opt, gr_error *err);

/* Where a space-time diagram puts its data: the plot area [x0, x0 + w) x [y0, y0 + n row_h) in
 * pixels, frame j in the rows [y0 + j row_h, y0 + (j + 1) row_h), x = 0 at x0 and x = L at x0 + w;
 * a particle is a mark `mark` px wide centred on its position; the image is width x height. */
typedef struct gr_spacetime_layout {
    int width, height;
    int x0, y0, w, row_h;
    double mark;
} gr_spacetime_layout;

/* The space-time diagram of 1D frames (all with the same N and L, in time order): x across the
 * whole ring, t down, one band of row_h px per frame (row_h = 900 / n, within [1, 12]); every
 * particle a mark of its diameter (at least 1 px) coloured by |v| / v_rms of its frame, on a dark
 * ground (GR_SPACETIME_GROUND) so that the slow, light particles of a cluster stand out; a cluster
 * forming is a band of light marks narrowing down the picture, dissolving one fanning out. Ticks
 * and labels: x (m) above, t (s) on the left; the colour bar below. At most GR_SPACETIME_MAX_FRAMES
 * frames. */
#define GR_SPACETIME_MAX_FRAMES 2000
#define GR_SPACETIME_GROUND 0x1e /* grey level of the ground, 0x1e1e1e */
int gr_picture_spacetime(const gr_frame *frames, int n, double radius, const char *png_path,
                         const gr_picture_options *opt, gr_error *err);
/* The layout gr_picture_spacetime uses for n frames of a ring of length L (GR_EINVAL for bad
 * options or n outside [1, GR_SPACETIME_MAX_FRAMES]). */
int gr_picture_spacetime_layout(int n, double L, double radius, const gr_picture_options *opt,
                                gr_spacetime_layout *l, gr_error *err);

/* The fill colour (sRGB components in [0, 1]) of a particle with |v|/v_rms = ratio. */
void gr_picture_colour(const gr_picture_options *opt, double ratio, double rgb[3]);

#endif
