/* The picture of a 3D frame (spheres in a periodic cube): an orthographic view of the whole cube,
 * turned by VIEW_YAW about the vertical and tilted by VIEW_PITCH towards the viewer so that three
 * of its faces show, its 12 edges drawn thin behind the spheres. Every sphere is drawn at its true
 * radius, back to front (painter's order by depth), filled with the speed colour of the 2D
 * pictures (|v| / v_rms, src/io/picture.h) and shaded as a lit ball: a radial gradient from a
 * highlight up and to the left to a darker rim; and by depth: the farther a sphere, the more its
 * colour is mixed with the white background (the front sphere at the full colour, the back ones at
 * DEPTH_FADE), so the layers of a dense cube read apart. Positions are wrapped into the cube; no
 * periodic images are drawn (a sphere crossing a face sticks out of it). Along an axis with walls
 * (a bed) positions are not wrapped, and the walls are the box's faces there: the farther one
 * shaded grey behind everything, the nearer one outlined dark in front (a floor seen from above,
 * its lid as a frame). */
#include <cairo.h>
#include <math.h>
#include <stdlib.h>

#include "io/picture_internal.h"

#define VIEW_YAW (-30.0 * M_PI / 180.0)
#define VIEW_PITCH (25.0 * M_PI / 180.0)
#define DEPTH_FADE 0.55 /* the farthest sphere's colour: 55 % ramp colour, 45 % background */

typedef struct sphere {
    double sx, sy, depth, speed; /* screen coordinates (m, centred), depth (m, larger = nearer) */
    int i;                       /* the particle (its species, radius) */
} sphere;

/* The view of a point (m, relative to the cube's centre): screen x right, y up, depth towards the
 * viewer. */
static void view(const double c[3], double *sx, double *sy, double *depth)
{
    const double cy = cos(VIEW_YAW), sy_ = sin(VIEW_YAW), cp = cos(VIEW_PITCH),
                 sp = sin(VIEW_PITCH);
    /* yaw about the vertical axis (z, up in the picture), then pitch about the screen's x */
    const double x1 = cy * c[0] - sy_ * c[1], y1 = sy_ * c[0] + cy * c[1], z1 = c[2];
    *sx = x1;
    *sy = cp * z1 + sp * y1; /* up */
    *depth = -(cp * y1) + sp * z1;
}

static int by_depth(const void *a, const void *b)
{
    const double da = ((const sphere *)a)->depth, db = ((const sphere *)b)->depth;
    return (da > db) - (da < db);
}

static void draw_ball(cairo_t *cr, double cx, double cy, double rp, const double rgb[3],
                      double fade)
{
    double c[3], hi[3], rim[3];
    for (int k = 0; k < 3; k++) {
        c[k] = fade * rgb[k] + (1.0 - fade);
        hi[k] = 0.45 * c[k] + 0.55;
        rim[k] = 0.5 * c[k];
    }
    const double r = rp > 0.5 ? rp : 0.5;
    cairo_new_path(cr);
    cairo_arc(cr, cx, cy, r, 0.0, 2.0 * M_PI);
    if (r < 2.0) {
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_fill(cr);
        return;
    }
    cairo_pattern_t *g = cairo_pattern_create_radial(cx - 0.35 * r, cy - 0.35 * r, 0.0, cx, cy, r);
    cairo_pattern_add_color_stop_rgb(g, 0.0, hi[0], hi[1], hi[2]);
    cairo_pattern_add_color_stop_rgb(g, 0.55, c[0], c[1], c[2]);
    cairo_pattern_add_color_stop_rgb(g, 1.0, rim[0], rim[1], rim[2]);
    cairo_set_source(cr, g);
    cairo_fill(cr);
    cairo_pattern_destroy(g);
}

/* The faces of the walled axes: of the two faces normal to a walled axis, the farther (its
 * centre's depth) is filled light grey with dark edges (`front` false: before the spheres), the
 * nearer outlined dark (`front` true: after them). */
static void draw_walls(cairo_t *cr, const popts *p, double L, double o, double pxm, bool front)
{
    for (int a = 0; a < 3; a++) {
        if (!p->walls[a]) {
            continue;
        }
        for (int side = 0; side < 2; side++) {
            double centre[3] = {0.0, 0.0, 0.0}, sx, sy, depth, other;
            centre[a] = (side ? 0.5 : -0.5) * L;
            view(centre, &sx, &sy, &depth);
            centre[a] = -centre[a];
            view(centre, &sx, &sy, &other);
            if ((depth > other) != front) {
                continue; /* this face is drawn in the other pass */
            }
            /* the face's corners in order: the two other axes b, c around the square */
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            static const double us[4] = {-0.5, 0.5, 0.5, -0.5}, vs[4] = {-0.5, -0.5, 0.5, 0.5};
            cairo_new_path(cr);
            for (int k = 0; k < 4; k++) {
                double corner[3];
                corner[a] = (side ? 0.5 : -0.5) * L;
                corner[b] = us[k] * L;
                corner[c] = vs[k] * L;
                view(corner, &sx, &sy, &depth);
                if (k == 0) {
                    cairo_move_to(cr, o + sx * pxm, o - sy * pxm);
                } else {
                    cairo_line_to(cr, o + sx * pxm, o - sy * pxm);
                }
            }
            cairo_close_path(cr);
            if (!front) {
                cairo_set_source_rgb(cr, 0.82, 0.82, 0.82);
                cairo_fill_preserve(cr);
            }
            cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
            cairo_set_line_width(cr, 2.0);
            cairo_stroke(cr);
        }
    }
}

int pic_picture_3d(const gr_frame *f, double radius, const char *png_path, const popts *p,
                   gr_error *err)
{
    sphere *s = malloc(sizeof *s * (size_t)(f->n > 0 ? f->n : 1));
    if (!s) {
        return GR_FAIL(err, GR_ENOMEM, "picture: out of memory for %d spheres", f->n);
    }
    const double L = f->L, vrms = pic_rms_speed(f);
    double dmin = INFINITY, dmax = -INFINITY;
    for (int i = 0; i < f->n; i++) {
        const double q[3] = {f->x[i], f->y[i], f->z[i]};
        double c[3];
        for (int a = 0; a < 3; a++) { /* a walled axis is not periodic */
            c[a] = (p->walls[a] ? q[a] : pic_wrap(q[a], L)) - 0.5 * L;
        }
        view(c, &s[i].sx, &s[i].sy, &s[i].depth);
        s[i].speed = pic_speed(f, i);
        s[i].i = i;
        dmin = fmin(dmin, s[i].depth);
        dmax = fmax(dmax, s[i].depth);
    }
    qsort(s, (size_t)f->n, sizeof *s, by_depth); /* farthest first */
    const int size = p->size, ts = pic_text_scale(size);
    const int height = size + (p->labels ? pic_panel_height(ts) : 0);
    cairo_surface_t *surf;
    cairo_t *cr;
    int rc = pic_canvas_new(size, height, png_path, &surf, &cr, err);
    if (rc) {
        free(s);
        return rc;
    }
    /* the cube's projection spans at most L sqrt(3): that and a sphere's diameter fit the square */
    const double pxm = 0.97 * size / (L * sqrt(3.0) + 2.0 * radius), o = 0.5 * size,
                 rp = radius * pxm;
    /* the cube's edges, behind everything */
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, 1.0);
    for (int a = 0; a < 8; a++) {
        for (int k = 0; k < 3; k++) {
            const int b = a | (1 << k);
            if (b == a) {
                continue;
            }
            double ca[3], cb[3], x0, y0, x1, y1, d;
            for (int q = 0; q < 3; q++) {
                ca[q] = ((a >> q) & 1 ? 0.5 : -0.5) * L;
                cb[q] = ((b >> q) & 1 ? 0.5 : -0.5) * L;
            }
            view(ca, &x0, &y0, &d);
            view(cb, &x1, &y1, &d);
            cairo_move_to(cr, o + x0 * pxm, o - y0 * pxm);
            cairo_line_to(cr, o + x1 * pxm, o - y1 * pxm);
        }
    }
    cairo_stroke(cr);
    draw_walls(cr, p, L, o, pxm, false); /* the farther faces, behind the spheres */
    const double span = dmax > dmin ? dmax - dmin : 1.0;
    double rgb[3];
    for (int i = 0; i < f->n; i++) {
        pic_fill(p, f, s[i].i, vrms, rgb);
        const double fade = DEPTH_FADE + (1.0 - DEPTH_FADE) * (s[i].depth - dmin) / span;
        /* a mixture's frame: every sphere to its own scale */
        const double rpi = f->radii ? f->radii[s[i].i] * pxm : rp;
        draw_ball(cr, o + s[i].sx * pxm, o - s[i].sy * pxm, rpi, rgb, fade);
    }
    free(s);
    draw_walls(cr, p, L, o, pxm, true); /* the nearer faces' outlines, in front */
    if (p->labels) {
        char left[96], right[64], caption[128];
        snprintf(left, sizeof left, "t = %.6g s", f->t);
        snprintf(right, sizeof right, "N = %d  L = %.4g m  (3D)", f->n, L);
        snprintf(caption, sizeof caption, "speed |v| / v_rms,  v_rms = %.4g m/s, far ones faded",
                 vrms);
        if (pic_text_width(ts, caption) > size) {
            snprintf(caption, sizeof caption, "|v| / v_rms");
        }
        if (p->by_species && f->species) {
            pic_draw_species_panel(cr, f->n_species, size, size, left, right);
        } else {
            pic_draw_panel(cr, p, size, size, left, right, caption);
        }
    }
    return pic_canvas_save(surf, cr, png_path, err);
}
