/* Snapshot pictures with cairo: particles to scale, coloured by |v| / v_rms (thesis Figs. 2.6 and
 * 2.9). See picture.h for the conventions. Every cairo call's status is checked (a failure is
 * GR_EIO with cairo's message) and PNGs are written through gr_file (temporary + fsync + rename). */
#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/files.h"
#include "io/picture.h"
#include "io/picture_internal.h"
#include "io/snapshot.h"
#include "io/trajectory.h"

enum { DEFAULT_SIZE = 1000, MIN_SIZE = 64 };
/* the space-time diagram of a run reads at most this many particle positions (memory) */
#define DEFAULT_VMAX 3.0
#define GREY_LIGHT 0.88 /* the slowest shade of the grey ramp */

/* ---------- options and colours ---------- */

int pic_resolve_options(const gr_picture_options *o, popts *p, gr_error *err)
{
    *p = (popts){.size = DEFAULT_SIZE,
                 .levels = 0,
                 .cmap = GR_CMAP_VIRIDIS,
                 .vmax = DEFAULT_VMAX,
                 .labels = true};
    if (!o) {
        return GR_OK;
    }
    if (o->size != 0 && (o->size < MIN_SIZE || o->size > GR_PICTURE_MAX_SIDE)) {
        return GR_FAIL(err, GR_EINVAL, "picture size %d px is outside [%d, %d]", o->size, MIN_SIZE,
                       GR_PICTURE_MAX_SIDE);
    }
    if (o->colormap != GR_CMAP_VIRIDIS && o->colormap != GR_CMAP_GREY) {
        return GR_FAIL(err, GR_EINVAL, "unknown colormap %d (viridis = 0, grey = 1)",
                       (int)o->colormap);
    }
    if (!(o->vmax >= 0.0 && o->vmax <= 1000.0)) { /* also refuses NaN */
        return GR_FAIL(err, GR_EINVAL, "picture vmax %g is outside (0, 1000] (0 = default %g)",
                       o->vmax, DEFAULT_VMAX);
    }
    if (o->levels != 0 && (o->levels < 2 || o->levels > 64)) {
        return GR_FAIL(err, GR_EINVAL, "picture levels %d: 0 (continuous) or [2, 64] shades",
                       o->levels);
    }
    p->size = o->size ? o->size : DEFAULT_SIZE;
    p->cmap = o->colormap;
    p->vmax = o->vmax > 0.0 ? o->vmax : DEFAULT_VMAX;
    p->levels = o->levels;
    p->labels = !o->hide_labels;
    for (int a = 0; a < 3; a++) {
        p->walls[a] = o->walls[a];
    }
    p->by_species = o->by_species;
    return GR_OK;
}

/* viridis at k/7, k = 0..7 (van der Walt & Smith's matplotlib colormap, as R's viridis(8)) */
static const unsigned char viridis8[8][3] = {
    {0x44, 0x01, 0x54}, {0x46, 0x33, 0x7e}, {0x36, 0x5c, 0x8d}, {0x27, 0x7f, 0x8e},
    {0x1f, 0xa1, 0x87}, {0x4a, 0xc1, 0x6d}, {0x9f, 0xda, 0x3a}, {0xfd, 0xe7, 0x25},
};

/* ratio = |v| / v_rms -> colour; u = 0 slow (light) .. 1 fast (dark) */
void pic_ramp(const popts *p, double ratio, double rgb[3])
{
    double u = ratio / p->vmax;
    u = u > 0.0 ? (u < 1.0 ? u : 1.0) : 0.0; /* NaN -> 0 */
    if (p->levels >= 2) {
        int k = (int)floor(u * p->levels);
        u = (double)(k < p->levels - 1 ? k : p->levels - 1) / (p->levels - 1);
    }
    if (p->cmap == GR_CMAP_GREY) {
        rgb[0] = rgb[1] = rgb[2] = GREY_LIGHT * (1.0 - u);
        return;
    }
    double w = (1.0 - u) * 7.0;
    int i = (int)floor(w);
    i = i < 0 ? 0 : (i > 6 ? 6 : i);
    double a = w - i;
    for (int c = 0; c < 3; c++) {
        rgb[c] = ((1.0 - a) * viridis8[i][c] + a * viridis8[i + 1][c]) / 255.0;
    }
}

void gr_picture_colour(const gr_picture_options *opt, double ratio, double rgb[3])
{
    popts p;
    gr_error ignored;
    if (pic_resolve_options(opt, &p, &ignored) != GR_OK) {
        pic_resolve_options(NULL, &p, &ignored);
    }
    pic_ramp(&p, ratio, rgb);
}

/* ---------- a 5x7 bitmap font (no fontconfig: identical on every machine, clean under ASan) ---------- */

typedef struct glyph {
    char c;
    const char *rows[7];
} glyph;

static const glyph font[] = {
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
    {' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
    {'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
    {',', {".....", ".....", ".....", ".....", ".##..", "..#..", ".#..."}},
    {':', {".....", ".##..", ".##..", ".....", ".##..", ".##..", "....."}},
    {'-', {".....", ".....", ".....", "#####", ".....", ".....", "....."}},
    {'+', {".....", "..#..", "..#..", "#####", "..#..", "..#..", "....."}},
    {'=', {".....", ".....", "#####", ".....", "#####", ".....", "....."}},
    {'/', {".....", "....#", "...#.", "..#..", ".#...", "#....", "....."}},
    {'|', {"..#..", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'_', {".....", ".....", ".....", ".....", ".....", ".....", "#####"}},
    {'(', {"...#.", "..#..", ".#...", ".#...", ".#...", "..#..", "...#."}},
    {')', {".#...", "..#..", "...#.", "...#.", "...#.", "..#..", ".#..."}},
    {'<', {"...#.", "..#..", ".#...", "#....", ".#...", "..#..", "...#."}},
    {'>', {".#...", "..#..", "...#.", "....#", "...#.", "..#..", ".#..."}},
    {'a', {".....", ".....", ".###.", "....#", ".####", "#...#", ".####"}},
    {'b', {"#....", "#....", "#.##.", "##..#", "#...#", "#...#", "####."}},
    {'c', {".....", ".....", ".###.", "#....", "#....", "#...#", ".###."}},
    {'d', {"....#", "....#", ".##.#", "#..##", "#...#", "#...#", ".####"}},
    {'e', {".....", ".....", ".###.", "#...#", "#####", "#....", ".###."}},
    {'f', {"..##.", ".#..#", ".#...", "###..", ".#...", ".#...", ".#..."}},
    {'g', {".....", ".####", "#...#", "#...#", ".####", "....#", ".###."}},
    {'h', {"#....", "#....", "#.##.", "##..#", "#...#", "#...#", "#...#"}},
    {'i', {"..#..", ".....", ".##..", "..#..", "..#..", "..#..", ".###."}},
    {'j', {"...#.", ".....", "..##.", "...#.", "...#.", "#..#.", ".##.."}},
    {'k', {"#....", "#....", "#..#.", "#.#..", "##...", "#.#..", "#..#."}},
    {'l', {".##..", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'m', {".....", ".....", "##.#.", "#.#.#", "#.#.#", "#...#", "#...#"}},
    {'n', {".....", ".....", "#.##.", "##..#", "#...#", "#...#", "#...#"}},
    {'o', {".....", ".....", ".###.", "#...#", "#...#", "#...#", ".###."}},
    {'p', {".....", ".....", "####.", "#...#", "####.", "#....", "#...."}},
    {'q', {".....", ".....", ".##.#", "#..##", ".####", "....#", "....#"}},
    {'r', {".....", ".....", "#.##.", "##..#", "#....", "#....", "#...."}},
    {'s', {".....", ".....", ".###.", "#....", ".###.", "....#", "####."}},
    {'t', {".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##."}},
    {'u', {".....", ".....", "#...#", "#...#", "#...#", "#..##", ".##.#"}},
    {'v', {".....", ".....", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
    {'w', {".....", ".....", "#...#", "#...#", "#.#.#", "#.#.#", ".#.#."}},
    {'x', {".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#"}},
    {'y', {".....", ".....", "#...#", "#...#", ".####", "....#", ".###."}},
    {'z', {".....", ".....", "#####", "...#.", "..#..", ".#...", "#####"}},
    {'D', {"####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####."}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'N', {"#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#"}},
    {'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
};
static const glyph unknown_glyph = {
    '?', {"#####", "#...#", "#...#", "#...#", "#...#", "#...#", "#####"}};

static const glyph *find_glyph(char c)
{
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++) {
        if (font[i].c == c) {
            return &font[i];
        }
    }
    if (c >= 'A' && c <= 'Z') {
        return find_glyph((char)(c - 'A' + 'a'));
    }
    return &unknown_glyph;
}

double pic_text_width(int s, const char *text)
{
    size_t n = strlen(text);
    return n ? (double)(6 * (int)n - 1) * s : 0.0;
}

/* Draw text with its top-left corner at (x, y), each font pixel s x s device pixels, in the
 * current source colour. */
void pic_draw_text(cairo_t *cr, double x, double y, int s, const char *text)
{
    cairo_new_path(cr);
    for (const char *c = text; *c; c++, x += 6.0 * s) {
        const glyph *g = find_glyph(*c);
        for (int r = 0; r < 7; r++) {
            for (int col = 0; col < 5; col++) {
                if (g->rows[r][col] == '#') {
                    cairo_rectangle(cr, x + col * s, y + r * s, s, s);
                }
            }
        }
    }
    cairo_fill(cr);
}

/* ---------- canvas and PNG output ---------- */

static int cairo_fail(gr_error *err, const char *png_path, const char *what, cairo_status_t st)
{
    return GR_FAIL(err, GR_EIO, "%s: cairo could not %s: %s", png_path, what,
                   cairo_status_to_string(st));
}

int pic_canvas_new(int w, int h, const char *png_path, cairo_surface_t **surf, cairo_t **cr,
                   gr_error *err)
{
    *surf = NULL;
    *cr = NULL;
    if (w < 1 || h < 1 || w > GR_PICTURE_MAX_SIDE || h > GR_PICTURE_MAX_SIDE ||
        (long)w * (long)h > GR_PICTURE_MAX_PIXELS) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: a %d x %d px picture is too large (at most %d px a side, %ld pixels)",
                       png_path, w, h, GR_PICTURE_MAX_SIDE, (long)GR_PICTURE_MAX_PIXELS);
    }
    *surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_status_t st = cairo_surface_status(*surf);
    if (st != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(*surf);
        *surf = NULL;
        return cairo_fail(err, png_path, "create the image", st);
    }
    *cr = cairo_create(*surf);
    st = cairo_status(*cr);
    if (st != CAIRO_STATUS_SUCCESS) {
        cairo_destroy(*cr);
        cairo_surface_destroy(*surf);
        *cr = NULL;
        *surf = NULL;
        return cairo_fail(err, png_path, "start drawing", st);
    }
    cairo_set_source_rgb(*cr, 1.0, 1.0, 1.0);
    cairo_paint(*cr);
    return GR_OK;
}

typedef struct png_sink {
    FILE *f;
    int errnum;
} png_sink;

static cairo_status_t sink_write(void *closure, const unsigned char *data, unsigned int length)
{
    png_sink *k = closure;
    errno = 0;
    if (fwrite(data, 1, length, k->f) != length) {
        k->errnum = errno ? errno : EIO;
        return CAIRO_STATUS_WRITE_ERROR;
    }
    return CAIRO_STATUS_SUCCESS;
}

/* Check the drawing, write the PNG atomically, free the canvas. */
int pic_canvas_save(cairo_surface_t *surf, cairo_t *cr, const char *png_path, gr_error *err)
{
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (st != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(surf);
        return cairo_fail(err, png_path, "draw the picture", st);
    }
    cairo_surface_flush(surf);
    st = cairo_surface_status(surf);
    if (st != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(surf);
        return cairo_fail(err, png_path, "finish the image", st);
    }
    char dir[1024];
    const char *slash = strrchr(png_path, '/'), *name = slash ? slash + 1 : png_path;
    if (!slash) {
        snprintf(dir, sizeof dir, ".");
    } else if (slash == png_path) {
        snprintf(dir, sizeof dir, "/");
    } else {
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - png_path), png_path);
    }
    gr_file out;
    int rc = gr_file_open(&out, dir, name, err);
    if (rc) {
        cairo_surface_destroy(surf);
        return rc;
    }
    png_sink k = {.f = out.f, .errnum = 0};
    st = cairo_surface_write_to_png_stream(surf, sink_write, &k);
    cairo_surface_destroy(surf);
    if (st != CAIRO_STATUS_SUCCESS) {
        gr_file_abandon(&out);
        return GR_FAIL(err, GR_EIO, "cannot write %s: cairo: %s%s%s", png_path,
                       cairo_status_to_string(st), k.errnum ? ": " : "",
                       k.errnum ? strerror(k.errnum) : "");
    }
    return gr_file_commit(&out, err);
}

int pic_check_png_path(const char *png_path, gr_error *err)
{
    if (!png_path || !png_path[0]) {
        return GR_FAIL(err, GR_EINVAL, "picture: no PNG path given");
    }
    size_t n = strlen(png_path);
    if (n >= 1000) {
        return GR_FAIL(err, GR_EINVAL, "picture: PNG path too long (%zu characters, at most 999)",
                       n);
    }
    if (png_path[n - 1] == '/') {
        return GR_FAIL(err, GR_EINVAL, "picture: %s names a folder, not a PNG file", png_path);
    }
    return GR_OK;
}

/* ---------- frames ---------- */

int pic_check_frame(const gr_frame *f, int index, double radius, gr_error *err)
{
    char which[32] = "";
    if (index >= 0) {
        snprintf(which, sizeof which, " %d", index);
    }
    if (!f) {
        return GR_FAIL(err, GR_EINVAL, "picture: frame%s is NULL", which);
    }
    if (f->dim < 1 || f->dim > 3) {
        return GR_FAIL(err, GR_EINVAL, "picture: frame%s has dim = %d (1, 2 or 3)", which, f->dim);
    }
    if (!(isfinite(f->L) && f->L > 0.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "picture: frame%s has box length L = %g (need a finite L > 0)", which, f->L);
    }
    if (!(isfinite(radius) && radius > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "picture: particle radius %g m (need a finite radius > 0)",
                       radius);
    }
    if (2.0 * radius > f->L) {
        return GR_FAIL(
            err, GR_EINVAL,
            "picture: particle radius %g m: the diameter exceeds the box length L = %g m", radius,
            f->L);
    }
    if (f->n < 0 || f->n > 100000000) {
        return GR_FAIL(err, GR_EINVAL, "picture: frame%s has %d particles", which, f->n);
    }
    if (f->n > 0 && (!f->x || !f->vx || (f->dim >= 2 && (!f->y || !f->vy)) ||
                     (f->dim == 3 && (!f->z || !f->vz)))) {
        return GR_FAIL(err, GR_EINVAL, "picture: frame%s lacks its position or velocity arrays",
                       which);
    }
    for (int i = 0; i < f->n; i++) {
        double y = f->dim >= 2 ? f->y[i] : 0.0, vy = f->dim >= 2 ? f->vy[i] : 0.0;
        if (f->dim == 3 && (!isfinite(f->z[i]) || !isfinite(f->vz[i]))) {
            return GR_FAIL(err, GR_EINVAL,
                           "picture: frame%s particle %d has a non-finite z = %g or vz = %g; "
                           "nothing drawn",
                           which, i, f->z[i], f->vz[i]);
        }
        if (!isfinite(f->x[i]) || !isfinite(y)) {
            return GR_FAIL(err, GR_EINVAL,
                           "picture: frame%s particle %d has a non-finite position (x = %g, y = "
                           "%g); nothing drawn",
                           which, i, f->x[i], y);
        }
        if (!isfinite(f->vx[i]) || !isfinite(vy)) {
            return GR_FAIL(err, GR_EINVAL,
                           "picture: frame%s particle %d has a non-finite velocity (vx = %g, vy = "
                           "%g); nothing drawn",
                           which, i, f->vx[i], vy);
        }
    }
    return GR_OK;
}

double pic_speed(const gr_frame *f, int i)
{
    return f->dim == 3   ? hypot(hypot(f->vx[i], f->vy[i]), f->vz[i])
           : f->dim == 2 ? hypot(f->vx[i], f->vy[i])
                         : fabs(f->vx[i]);
}

/* sqrt(<|v|^2>) without overflow */
double pic_rms_speed(const gr_frame *f)
{
    double m = 0.0, s = 0.0;
    for (int i = 0; i < f->n; i++) {
        double v = pic_speed(f, i);
        m = v > m ? v : m;
    }
    if (!(m > 0.0) || !isfinite(m)) {
        return isfinite(m) ? 0.0 : m;
    }
    for (int i = 0; i < f->n; i++) {
        double v = pic_speed(f, i) / m;
        s += v * v;
    }
    return m * sqrt(s / f->n);
}

double pic_wrap(double x, double L)
{
    double w = x - L * floor(x / L);
    return w >= L || w < 0.0 ? 0.0 : w;
}

/* One disc at device (cx, cy) of device radius rp. */
static void draw_disc(cairo_t *cr, double cx, double cy, double rp, const double rgb[3])
{
    cairo_new_path(cr);
    cairo_arc(cr, cx, cy, rp > 0.5 ? rp : 0.5, 0.0, 2.0 * M_PI);
    cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
    if (rp >= 3.0) { /* a thin darker rim separates touching discs of the same shade */
        cairo_fill_preserve(cr);
        cairo_set_source_rgba(cr, 0.0, 0.0, 0.0, 0.45);
        cairo_set_line_width(cr, rp >= 8.0 ? 1.0 : 0.6);
        cairo_stroke(cr);
    } else {
        cairo_fill(cr);
    }
}

/* Okabe and Ito (2008): blue, orange, bluish green, vermillion, reddish purple, sky blue, yellow,
 * black, distinguishable in every common colour-vision deficiency */
static const double species_rgb[GR_PICTURE_SPECIES_COLOURS][3] = {
    {0.000, 0.447, 0.698}, {0.902, 0.624, 0.000}, {0.000, 0.620, 0.451}, {0.835, 0.369, 0.000},
    {0.800, 0.475, 0.655}, {0.337, 0.706, 0.914}, {0.941, 0.894, 0.259}, {0.000, 0.000, 0.000}};

void pic_fill(const popts *p, const gr_frame *f, int i, double vrms, double rgb[3])
{
    if (p->by_species && f->species) {
        const double *c = species_rgb[f->species[i] % GR_PICTURE_SPECIES_COLOURS];
        rgb[0] = c[0], rgb[1] = c[1], rgb[2] = c[2];
        return;
    }
    pic_ramp(p, vrms > 0.0 ? pic_speed(f, i) / vrms : 0.0, rgb);
}

/* ---------- the panel: captions and colour bar ---------- */

int pic_text_scale(int width)
{
    int s = width / 450;
    return s < 1 ? 1 : (s > 8 ? 8 : s);
}

int pic_panel_height(int s)
{
    return 6 * s + 10 * s + 3 * s + 8 * s + 2 * s + 10 * s + 10 * s + 3 * s;
}

/* The panel's top line: the left and right captions; returns the y below them. */
static double panel_captions(cairo_t *cr, int width, double y0, const char *left, const char *right)
{
    int s = pic_text_scale(width);
    double y = y0 + 6 * s;
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    pic_draw_text(cr, 4 * s, y, s, left);
    double wr = pic_text_width(s, right);
    if (4 * s + pic_text_width(s, left) + 6 * s + wr <= width - 4 * s) {
        pic_draw_text(cr, width - 4 * s - wr, y, s, right);
    }
    return y + 13 * s;
}

/* The panel occupying [0, width) x [y0, y0 + panel_height): left/right captions, the colour bar with
 * its ticks and a caption under it. */
void pic_draw_panel(cairo_t *cr, const popts *p, int width, double y0, const char *left,
                    const char *right, const char *caption)
{
    int s = pic_text_scale(width);
    double y = panel_captions(cr, width, y0, left, right);
    /* the bar, one device column at a time in the ramp's own colours */
    double bx0 = 8 * s, bx1 = width - 14 * s, bh = 8 * s;
    double rgb[3];
    for (int px = (int)bx0; px < (int)bx1; px++) {
        pic_ramp(p, (px + 0.5 - bx0) / (bx1 - bx0) * p->vmax, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_rectangle(cr, px, y, 1.0, bh);
        cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, bx0 - 0.5, y - 0.5, (double)((int)bx1 - (int)bx0) + 1.0, bh + 1.0);
    cairo_stroke(cr);
    /* ticks at whole multiples of v_rms (at most ~10) and the clipping end marked "+" */
    double step = ceil(p->vmax / 10.0);
    char label[32];
    for (int k = 0;; k++) {
        double r = k * step;
        bool end = r >= p->vmax - 1e-9 * p->vmax;
        if (end) {
            r = p->vmax;
        }
        double tx = bx0 + (bx1 - bx0) * r / p->vmax;
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        cairo_rectangle(cr, floor(tx), y + bh, 1.0, 2 * s);
        cairo_fill(cr);
        snprintf(label, sizeof label, end ? "%g+" : "%g", r);
        double lw = pic_text_width(s, label),
               lx = tx - (end ? 0.5 * pic_text_width(s, label) - 3 * s : 0.5 * lw);
        lx = lx < 0 ? 0 : (lx + lw > width ? width - lw : lx);
        pic_draw_text(cr, lx, y + bh + 3 * s, s, label);
        if (end) {
            break;
        }
    }
    y += bh + 2 * s + 10 * s;
    double wc = pic_text_width(s, caption);
    pic_draw_text(cr, wc < width ? 0.5 * (width - wc) : 0.0, y, s, caption);
}

void pic_draw_species_panel(cairo_t *cr, int n_species, int width, double y0, const char *left,
                            const char *right)
{
    int s = pic_text_scale(width);
    double y = panel_captions(cr, width, y0, left, right);
    double x = 8 * s;
    char label[32];
    for (int k = 0; k < n_species; k++) { /* a swatch and its name, left to right */
        const double *c = species_rgb[k % GR_PICTURE_SPECIES_COLOURS];
        snprintf(label, sizeof label, "species %d", k + 1);
        const double need = 8 * s + 3 * s + pic_text_width(s, label) + 8 * s;
        if (x + need > width && k > 0) {
            break; /* more species than fit: the rest share the palette by k mod 8 */
        }
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_rectangle(cr, x, y, 8 * s, 8 * s);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        pic_draw_text(cr, x + 11 * s, y + 0.5 * s, s, label);
        x += need;
    }
    y += 8 * s + 2 * s + 10 * s;
    const char *caption = "colour: species";
    double wc = pic_text_width(s, caption);
    pic_draw_text(cr, wc < width ? 0.5 * (width - wc) : 0.0, y, s, caption);
}

/* ---------- 2D ---------- */

static int picture_2d(const gr_frame *f, double radius, const char *png_path, const popts *p,
                      gr_error *err)
{
    int size = p->size, s = pic_text_scale(size);
    int height = size + (p->labels ? pic_panel_height(s) : 0);
    cairo_surface_t *surf;
    cairo_t *cr;
    int rc = pic_canvas_new(size, height, png_path, &surf, &cr, err);
    if (rc) {
        return rc;
    }
    const double L = f->L, pxm = size / L, rp = radius * pxm, vrms = pic_rms_speed(f);
    /* the box outline first: discs at the edge are drawn over it, so every centre shows its colour */
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, 0.5, 0.5, size - 1.0, size - 1.0);
    cairo_stroke(cr);
    cairo_save(cr);
    cairo_rectangle(cr, 0, 0, size, size);
    cairo_clip(cr);
    double rgb[3];
    /* a wall axis has no periodic images, and its positions stay where they are */
    const int ax = p->walls[0] ? 0 : 1, ay = p->walls[1] ? 0 : 1;
    for (int i = 0; i < f->n; i++) {
        double x = p->walls[0] ? f->x[i] : pic_wrap(f->x[i], L);
        double y = p->walls[1] ? f->y[i] : pic_wrap(f->y[i], L);
        pic_fill(p, f, i, vrms, rgb);
        /* a mixture's frame (docs/mixtures.md): every disc to its own scale */
        const double ri = f->radii ? f->radii[i] : radius, rpi = f->radii ? ri * pxm : rp;
        for (int a = -ax; a <= ax; a++) {
            double X = x + a * L;
            if (X + ri < 0.0 || X - ri > L) {
                continue;
            }
            for (int b = -ay; b <= ay; b++) {
                double Y = y + b * L;
                if (Y + ri < 0.0 || Y - ri > L) {
                    continue;
                }
                draw_disc(cr, X * pxm, (L - Y) * pxm, rpi, rgb); /* y points up */
            }
        }
    }
    cairo_restore(cr);
    /* the walls: dark bars along the box's edges, drawn over the discs that touch them */
    const double bar = fmax(3.0, 0.004 * size);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    if (p->walls[0]) {
        cairo_rectangle(cr, 0.0, 0.0, bar, size);
        cairo_rectangle(cr, size - bar, 0.0, bar, size);
    }
    if (p->walls[1]) {
        cairo_rectangle(cr, 0.0, size - bar, size, bar);
        cairo_rectangle(cr, 0.0, 0.0, size, bar);
    }
    cairo_fill(cr);
    if (p->labels) {
        char left[96], right[64], caption[128];
        snprintf(left, sizeof left, "t = %.6g s", f->t);
        snprintf(right, sizeof right, "N = %d  L = %.4g m", f->n, L);
        snprintf(caption, sizeof caption, "speed |v| / v_rms,  v_rms = %.4g m/s", vrms);
        if (pic_text_width(s, caption) > size) {
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

/* ---------- 1D strips ---------- */

typedef struct strip_layout {
    int nseg, row_h, caption_h, gap, top, gutter, width, height, s;
    double seg_len, pxm, rp;
} strip_layout;

static void strip_measure(strip_layout *l, int nframes, int nseg, double L, double radius,
                          const popts *p)
{
    l->nseg = nseg;
    l->seg_len = L / nseg;
    l->pxm = (l->width - l->gutter - 2 * l->s) / l->seg_len;
    l->rp = radius * l->pxm;
    int d = (int)ceil(2.0 * l->rp) + 2;
    l->row_h = d < 3 ? 3 : (d > 200 ? 200 : d);
    l->caption_h = p->labels && nseg > 1 ? 10 * l->s : 0;
    long h = l->top + (long)nseg * (l->caption_h + (long)nframes * l->row_h + l->gap) +
             (p->labels ? pic_panel_height(l->s) : 0);
    l->height = h > INT32_MAX ? INT32_MAX : (int)h;
}

static int picture_strip(const gr_frame *frames, int n, double radius, const char *png_path,
                         const popts *p, gr_error *err)
{
    const double L = frames[0].L;
    strip_layout l = {.width = p->size, .s = pic_text_scale(p->size)};
    const bool row_labels = p->labels && n > 1; /* each row's time, in the small (scale 1) font */
    l.gutter = row_labels ? 6 * 11 + 6 : 2 * l.s;
    l.top = 3 * l.s;
    l.gap = 5 * l.s;
    /* cut the ring into segments so a disc is ~10 px wide, as long as the picture stays in bounds */
    double plot_w = l.width - l.gutter - 2 * l.s;
    double want = ceil(L * 10.0 / (plot_w * 2.0 * radius));
    int nseg = want < 1.0 ? 1 : (want > 256.0 ? 256 : (int)want);
    for (;;) {
        strip_measure(&l, n, nseg, L, radius, p);
        if ((l.height <= GR_PICTURE_MAX_SIDE &&
             (long)l.width * l.height <= GR_PICTURE_MAX_PIXELS) ||
            nseg == 1) {
            break;
        }
        nseg = nseg > 8 ? nseg * 3 / 4 : nseg - 1;
    }
    cairo_surface_t *surf;
    cairo_t *cr;
    int rc = pic_canvas_new(l.width, l.height, png_path, &surf, &cr, err);
    if (rc) {
        if (rc == GR_EINVAL && err) {
            snprintf(err->message + strlen(err->message),
                     sizeof err->message - strlen(err->message),
                     " (%d frames: draw fewer or choose a smaller width)", n);
        }
        return rc;
    }
    const double x0 = l.gutter;
    int row_label_every = (int)ceil(9.0 / l.row_h);
    double y = l.top, rgb[3];
    char label[96];
    for (int g = 0; g < l.nseg; g++) {
        const double a = g * l.seg_len, b = a + l.seg_len;
        if (l.caption_h) {
            snprintf(label, sizeof label, "x = %.4g .. %.4g m", a, b);
            cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
            pic_draw_text(cr, x0, y + 1.5 * l.s, l.s, label);
            if (row_labels) {
                pic_draw_text(cr, 2, y + l.caption_h - 9, 1, "t (s)");
            }
            y += l.caption_h;
        }
        for (int j = 0; j < n; j++, y += l.row_h) {
            const gr_frame *f = &frames[j];
            const double vrms = pic_rms_speed(f), ymid = y + 0.5 * l.row_h;
            if (row_labels && j % row_label_every == 0) {
                snprintf(label, sizeof label, "%.4g", f->t);
                cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
                pic_draw_text(cr, 2, floor(ymid - 3.5), 1, label);
            }
            cairo_save(cr);
            cairo_rectangle(cr, x0, y, l.seg_len * l.pxm, l.row_h);
            cairo_clip(cr);
            cairo_set_source_rgb(cr, 0.8, 0.8, 0.8); /* the line the particles live on */
            cairo_rectangle(cr, x0, floor(ymid), l.seg_len * l.pxm, 1.0);
            cairo_fill(cr);
            for (int i = 0; i < f->n; i++) {
                double x = pic_wrap(f->x[i], L);
                bool coloured = false;
                for (int m = -1; m <= 1; m++) {
                    double X = x + m * L;
                    if (X + radius < a || X - radius > b) {
                        continue;
                    }
                    if (!coloured) {
                        pic_ramp(p, vrms > 0.0 ? pic_speed(f, i) / vrms : 0.0, rgb);
                        coloured = true;
                    }
                    draw_disc(cr, x0 + (X - a) * l.pxm, ymid, l.rp, rgb);
                }
            }
            cairo_restore(cr);
        }
        y += l.gap;
    }
    if (p->labels) {
        char left[96], right[64], caption[128];
        if (n == 1) {
            snprintf(left, sizeof left, "t = %.6g s", frames[0].t);
            snprintf(caption, sizeof caption, "speed |v| / v_rms,  v_rms = %.4g m/s",
                     pic_rms_speed(&frames[0]));
        } else {
            snprintf(left, sizeof left, "t = %.5g .. %.5g s, down", frames[0].t, frames[n - 1].t);
            snprintf(caption, sizeof caption, "speed |v| / v_rms (v_rms of each row)");
        }
        snprintf(right, sizeof right, "N = %d  L = %.4g m", frames[0].n, L);
        if (pic_text_width(l.s, caption) > l.width) {
            snprintf(caption, sizeof caption, "|v| / v_rms");
        }
        pic_draw_panel(cr, p, l.width, l.height - pic_panel_height(l.s), left, right, caption);
    }
    return pic_canvas_save(surf, cr, png_path, err);
}

int gr_picture_strip(const gr_frame *frames, int n, double radius, const char *png_path,
                     const gr_picture_options *opt, gr_error *err)
{
    popts p;
    int rc = pic_check_png_path(png_path, err);
    rc = rc ? rc : pic_resolve_options(opt, &p, err);
    if (rc) {
        return rc;
    }
    if (!frames || n < 1) {
        return GR_FAIL(err, GR_EINVAL, "%s: a strip needs at least one frame (got %d)", png_path,
                       n);
    }
    for (int j = 0; j < n; j++) {
        rc = pic_check_frame(&frames[j], j, radius, err);
        if (rc) {
            return rc;
        }
        if (frames[j].dim != 1) {
            return GR_FAIL(err, GR_EINVAL, "%s: frame %d is %dD; a strip stacks 1D frames",
                           png_path, j, frames[j].dim);
        }
        if (fabs(frames[j].L - frames[0].L) > 1e-9 * frames[0].L) {
            return GR_FAIL(err, GR_EINVAL, "%s: frame %d has ring length %g m, frame 0 has %g m",
                           png_path, j, frames[j].L, frames[0].L);
        }
    }
    return picture_strip(frames, n, radius, png_path, &p, err);
}

int gr_picture_frame(const gr_frame *f, double radius, const char *png_path,
                     const gr_picture_options *opt, gr_error *err)
{
    popts p;
    int rc = pic_check_png_path(png_path, err);
    rc = rc ? rc : pic_resolve_options(opt, &p, err);
    rc = rc ? rc : pic_check_frame(f, -1, radius, err);
    if (rc) {
        return rc;
    }
    return f->dim == 3   ? pic_picture_3d(f, radius, png_path, &p, err)
           : f->dim == 2 ? picture_2d(f, radius, png_path, &p, err)
                         : picture_strip(f, 1, radius, png_path, &p, err);
}
