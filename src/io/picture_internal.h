/* The drawing helpers that src/io/picture.c (snapshots, strips) and picture_spacetime.c (the 1D
 * space-time diagram) share: options, the colour ramp, the bitmap font, the canvas that is
 * written atomically, frame checks and the panel with the colour bar. */
#ifndef GR_PICTURE_INTERNAL_H
#define GR_PICTURE_INTERNAL_H

#include <cairo.h>
#include <stdbool.h>

#include "granule/status.h"
#include "io/picture.h"
#include "io/snapshot.h"

/* gr_picture_options with the defaults filled in */
typedef struct popts {
    int size, levels;
    gr_colormap cmap;
    double vmax;
    bool labels;
    bool walls[3];
    bool by_species;
} popts;

int pic_resolve_options(const gr_picture_options *o, popts *p, gr_error *err);
/* the fill colour of |v| / v_rms = ratio */
void pic_ramp(const popts *p, double ratio, double rgb[3]);
/* particle i's fill: its species' colour (by_species and a mixture's frame), else the ramp's at
 * |v_i| / vrms */
void pic_fill(const popts *p, const gr_frame *f, int i, double vrms, double rgb[3]);
/* a mixture's legend in place of the colour bar: a swatch and "species k" for each species */
void pic_draw_species_panel(cairo_t *cr, int n_species, int width, double y0, const char *left,
                            const char *right);
/* the 5x7 bitmap font at scale s: width of a text, and the text drawn with its top-left at (x, y) */
double pic_text_width(int s, const char *text);
void pic_draw_text(cairo_t *cr, double x, double y, int s, const char *text);
/* a white w x h canvas (sizes checked against the limits), saved atomically to png_path */
int pic_canvas_new(int w, int h, const char *png_path, cairo_surface_t **surf, cairo_t **cr,
                   gr_error *err);
int pic_canvas_save(cairo_surface_t *surf, cairo_t *cr, const char *png_path, gr_error *err);
int pic_check_png_path(const char *png_path, gr_error *err);
/* finite positions and velocities, a radius in (0, L/2]; index -1 for a single frame */
int pic_check_frame(const gr_frame *f, int index, double radius, gr_error *err);
double pic_speed(const gr_frame *f, int i);
double pic_rms_speed(const gr_frame *f);
/* x in [0, L) */
double pic_wrap(double x, double L);
/* the font scale for an image `width` px wide, the height of the panel at that scale */
int pic_text_scale(int width);
int pic_panel_height(int s);
/* the panel below a picture: captions left and right, the colour bar with its ticks, a caption */
void pic_draw_panel(cairo_t *cr, const popts *p, int width, double y0, const char *left,
                    const char *right, const char *caption);
/* A 3D frame (a checked one, dim = 3): the cube in orthographic view, spheres shaded by depth and
 * coloured by speed (src/io/picture_3d.c). */
int pic_picture_3d(const gr_frame *f, double radius, const char *png_path, const popts *p,
                   gr_error *err);

#endif
