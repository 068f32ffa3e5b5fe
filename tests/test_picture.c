/* Tests of the snapshot pictures (src/io/picture.c, issue 4; thesis Figs. 2.6 and 2.9).
 *
 * Pictures are read back with cairo_image_surface_create_from_png and probed pixel by pixel: a
 * disc centre has the colour of its speed (checked against closed-form ramp values, not only
 * against gr_picture_colour), the background is white, a disc crossing the periodic edge appears
 * on both sides, a 1D strip stacks its frames top to bottom, bad input is refused without leaving
 * any file behind, and gr_picture_run draws the picture of a real (tiny) run folder.
 *
 * Every test works in a fresh folder under one mkdtemp root, removed at the end
 * (GRANULE_KEEP_TMP=1 keeps it, e.g. to look at the pictures). */
#include <cairo.h>
#include <check.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granule/run.h"
#include "granule/scene.h"
#include "granule/status.h"
#include "app/run_picture.h"
#include "io/snapshot.h"
#include "check_main.h"

static char g_root[240];
static char g_dir[256];

static void setup(void)
{
    snprintf(g_dir, sizeof g_dir, "%s/test-XXXXXX", g_root);
    ck_assert_msg(mkdtemp(g_dir) != NULL, "mkdtemp: %s", strerror(errno));
}

static void teardown(void)
{
    if (g_dir[0] && !gr_test_keep_tmp()) {
        gr_test_rm_tree(g_dir);
    }
    g_dir[0] = 0;
}

static const char *in_dir(const char *name)
{
    static char paths[4][600];
    static int k;
    char *p = paths[k++ % 4];
    snprintf(p, sizeof paths[0], "%s/%s", g_dir, name);
    return p;
}

/* Entries of dir other than . and .. (the first is copied to first). */
static int count_entries(const char *dir, char *first, size_t n)
{
    DIR *d = opendir(dir);
    ck_assert_msg(d != NULL, "opendir %s: %s", dir, strerror(errno));
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            if (count++ == 0 && first) {
                snprintf(first, n, "%s", e->d_name);
            }
        }
    }
    closedir(d);
    return count;
}

static void assert_no_temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        ck_assert_msg(strstr(e->d_name, ".tmp") == NULL, "temporary file left in %s: %s", dir,
                      e->d_name);
    }
    closedir(d);
}

/* ---------- reading pictures back ---------- */

typedef struct image {
    cairo_surface_t *s;
    int w, h, stride;
    const unsigned char *data;
} image;

static image load_png(const char *path)
{
    image im = {0};
    im.s = cairo_image_surface_create_from_png(path);
    ck_assert_msg(cairo_surface_status(im.s) == CAIRO_STATUS_SUCCESS, "%s: %s", path,
                  cairo_status_to_string(cairo_surface_status(im.s)));
    cairo_format_t fmt = cairo_image_surface_get_format(im.s);
    ck_assert_msg(fmt == CAIRO_FORMAT_RGB24 || fmt == CAIRO_FORMAT_ARGB32,
                  "%s: unexpected format %d", path, (int)fmt);
    im.w = cairo_image_surface_get_width(im.s);
    im.h = cairo_image_surface_get_height(im.s);
    im.stride = cairo_image_surface_get_stride(im.s);
    im.data = cairo_image_surface_get_data(im.s);
    return im;
}

static void image_free(image *im)
{
    cairo_surface_destroy(im->s);
    im->s = NULL;
}

static void pixel(const image *im, int x, int y, int rgb[3])
{
    ck_assert_msg(x >= 0 && y >= 0 && x < im->w && y < im->h, "pixel (%d, %d) outside %d x %d", x,
                  y, im->w, im->h);
    uint32_t v;
    memcpy(&v, im->data + (size_t)y * (size_t)im->stride + 4 * (size_t)x, 4);
    rgb[0] = (int)((v >> 16) & 255);
    rgb[1] = (int)((v >> 8) & 255);
    rgb[2] = (int)(v & 255);
}

static void expect_pixel(const image *im, int x, int y, double r, double g, double b, int tol,
                         const char *what)
{
    int p[3];
    pixel(im, x, y, p);
    int e[3] = {(int)lround(255.0 * r), (int)lround(255.0 * g), (int)lround(255.0 * b)};
    for (int c = 0; c < 3; c++) {
        ck_assert_msg(abs(p[c] - e[c]) <= tol,
                      "%s: pixel (%d, %d) is #%02x%02x%02x, expected #%02x%02x%02x", what, x, y,
                      p[0], p[1], p[2], e[0], e[1], e[2]);
    }
}

static bool is_white(const image *im, int x, int y)
{
    int p[3];
    pixel(im, x, y, p);
    return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

/* ---------- synthetic frames ---------- */

static gr_frame frame_new(int n, int dim, double L, double t)
{
    gr_frame f = {.n = n, .dim = dim, .L = L, .t = t};
    f.x = calloc((size_t)n, sizeof(double));
    f.vx = calloc((size_t)n, sizeof(double));
    if (dim >= 2) {
        f.y = calloc((size_t)n, sizeof(double));
        f.vy = calloc((size_t)n, sizeof(double));
    }
    if (dim == 3) {
        f.z = calloc((size_t)n, sizeof(double));
        f.vz = calloc((size_t)n, sizeof(double));
    }
    ck_assert_ptr_nonnull(f.x);
    return f;
}

/* device coordinates of a physical point in a 2D picture of side `size` (y points up) */
static int dev_x(double x, double L, int size) { return (int)floor(x / L * size); }
static int dev_y(double y, double L, int size) { return (int)floor((L - y) / L * size); }

/* ---------- 2D ---------- */

/* 16 discs on a 4 x 4 grid: #0 fast (ratio 4 > vmax = 3: clipped), #1 at ratio ~1.4, the rest at
 * rest. Grey ramp: 0.88 (1 - min(ratio, 3) / 3); viridis read backwards: slow #fde725, fast #440154. */
START_TEST(test_2d_disc_colours)
{
    const double L = 0.1, r = 0.004;
    const int size = 500;
    gr_frame f = frame_new(16, 2, L, 0.25);
    for (int i = 0; i < 16; i++) {
        f.x[i] = 0.0125 + 0.025 * (i % 4);
        f.y[i] = 0.0125 + 0.025 * (i / 4);
    }
    f.vx[0] = 3.0;
    f.vy[0] = -4.0; /* |v| = 5 */
    f.vx[1] = 1.5;  /* |v| = 1.5 */
    double vrms = sqrt((25.0 + 2.25) / 16.0), ratio1 = 1.5 / vrms;
    ck_assert(5.0 / vrms > 3.0);

    for (int map = 0; map < 2; map++) {
        gr_picture_options opt = {.size = size, .colormap = map ? GR_CMAP_VIRIDIS : GR_CMAP_GREY};
        const char *png = in_dir(map ? "viridis.png" : "grey.png");
        gr_error err = {0};
        ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image im = load_png(png);
        ck_assert_int_eq(im.w, size);
        ck_assert_msg(im.h > size, "no panel under the box (height %d)", im.h);
        for (int i = 0; i < 16; i++) {
            int X = dev_x(f.x[i], L, size), Y = dev_y(f.y[i], L, size);
            double rgb[3];
            if (map == 0) {
                double g = i == 0 ? 0.0 : (i == 1 ? 0.88 * (1.0 - ratio1 / 3.0) : 0.88);
                rgb[0] = rgb[1] = rgb[2] = g;
            } else if (i == 0) {
                rgb[0] = 0x44 / 255.0, rgb[1] = 0x01 / 255.0, rgb[2] = 0x54 / 255.0;
            } else if (i > 1) {
                rgb[0] = 0xfd / 255.0, rgb[1] = 0xe7 / 255.0, rgb[2] = 0x25 / 255.0;
            } else {
                gr_picture_colour(&opt, ratio1, rgb);
            }
            expect_pixel(&im, X, Y, rgb[0], rgb[1], rgb[2], 1,
                         map ? "viridis disc centre" : "grey disc centre");
            /* inside the disc but off-centre: the same fill (the rim is at the edge only) */
            expect_pixel(&im, X + 10, Y - 10, rgb[0], rgb[1], rgb[2], 1, "inside the disc");
            /* between grid neighbours (0.011 m from this centre, 0.014 m from the next, r = 0.004):
             * background */
            double bx = f.x[i] + (i % 4 < 3 ? 0.011 : -0.011);
            ck_assert_msg(is_white(&im, dev_x(bx, L, size), Y),
                          "no white background beside disc %d", i);
        }
        /* the disc is drawn to scale: white just outside its radius, filled just inside */
        int X = dev_x(f.x[5], L, size), Y = dev_y(f.y[5], L, size);
        ck_assert(!is_white(&im, X + (int)(0.9 * r / L * size), Y));
        ck_assert(is_white(&im, X + (int)(1.3 * r / L * size) + 1, Y));
        image_free(&im);
    }
    /* a ramp quantised into 3 shades (Fig. 2.9): ratio 1.4 falls in the middle band */
    {
        gr_picture_options opt = {
            .size = size, .colormap = GR_CMAP_GREY, .levels = 3, .hide_labels = true};
        gr_error err = {0};
        const char *png = in_dir("three.png");
        ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image im = load_png(png);
        ck_assert_int_eq(im.h, size); /* no panel */
        expect_pixel(&im, dev_x(f.x[1], L, size), dev_y(f.y[1], L, size), 0.44, 0.44, 0.44, 1,
                     "middle shade");
        expect_pixel(&im, dev_x(f.x[0], L, size), dev_y(f.y[0], L, size), 0, 0, 0, 1,
                     "darkest shade");
        expect_pixel(&im, dev_x(f.x[2], L, size), dev_y(f.y[2], L, size), 0.88, 0.88, 0.88, 1,
                     "lightest shade");
        image_free(&im);
    }
    gr_frame_free(&f);
    assert_no_temporaries(g_dir);
}
END_TEST

/* A disc crossing the left edge shows on the right edge too; one in a corner shows in all four;
 * positions outside [0, L) (snapshots do not wrap y) are wrapped into the box. */
/* A mixture's frame coloured by species (by_species): each disc in its species' palette colour
 * (Okabe-Ito blue #0072b2, orange #e69f00, bluish green #009e73) whatever its speed, each at its
 * own radius (a small disc's rim pixel stays white where a large one's is filled); without
 * by_species the same frame is coloured by speed. */
START_TEST(test_2d_species_colours)
{
    const double L = 0.1;
    const int size = 500;
    gr_frame f = frame_new(3, 2, L, 0.0);
    int species[3] = {0, 1, 2};
    double radii[3] = {0.002, 0.006, 0.004}, masses[3] = {1.0, 1.0, 1.0};
    f.species = species;
    f.radii = radii;
    f.masses = masses;
    f.n_species = 3;
    for (int i = 0; i < 3; i++) {
        f.x[i] = 0.02 + 0.03 * i;
        f.y[i] = 0.05;
        f.vx[i] = i == 1 ? 3.0 : 0.0; /* the speeds would colour them otherwise */
    }
    const double want[3][3] = {{0.0, 0.447, 0.698}, {0.902, 0.624, 0.0}, {0.0, 0.620, 0.451}};
    gr_picture_options opt = {.size = size, .by_species = true};
    const char *png = in_dir("species.png");
    gr_error err = {0};
    ck_assert_msg(gr_picture_frame(&f, 0.006, png, &opt, &err) == GR_OK, "%s", err.message);
    image im = load_png(png);
    for (int i = 0; i < 3; i++) {
        expect_pixel(&im, dev_x(f.x[i], L, size), dev_y(f.y[i], L, size), want[i][0], want[i][1],
                     want[i][2], 2, "species colour");
    }
    /* disc 0 (2 mm) does not reach 4 mm from its centre; disc 1 (6 mm) does */
    ck_assert(is_white(&im, dev_x(f.x[0] + 0.004, L, size), dev_y(f.y[0], L, size)));
    ck_assert(!is_white(&im, dev_x(f.x[1] + 0.004, L, size), dev_y(f.y[1], L, size)));
    image_free(&im);
    opt.by_species = false; /* by speed: the resting discs share the ramp's slow colour */
    ck_assert_msg(gr_picture_frame(&f, 0.006, png, &opt, &err) == GR_OK, "%s", err.message);
    im = load_png(png);
    int a[3], b[3];
    pixel(&im, dev_x(f.x[0], L, size), dev_y(f.y[0], L, size), a);
    pixel(&im, dev_x(f.x[2], L, size), dev_y(f.y[2], L, size), b);
    ck_assert(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
    image_free(&im);
    f.species = NULL; /* not the test's arrays to free */
    f.radii = f.masses = NULL;
    gr_frame_free(&f);
}
END_TEST

START_TEST(test_2d_periodic_edges)
{
    const double L = 0.1, r = 0.005;
    const int size = 400;
    gr_frame f = frame_new(3, 2, L, 0.0);
    f.x[0] = 0.002, f.y[0] = 0.05;        /* crosses x = 0 */
    f.x[1] = 0.099, f.y[1] = -0.098;      /* y wraps to 0.002: crosses the corner x = L, y = 0 */
    f.x[2] = 0.05 + 3 * L, f.y[2] = 0.05; /* x wraps to 0.05 */
    gr_picture_options opt = {.size = size, .colormap = GR_CMAP_GREY, .hide_labels = true};
    gr_error err = {0};
    const char *png = in_dir("edges.png");
    ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
    image im = load_png(png);
    const double g = 0.88; /* all at rest: v_rms = 0, every disc in the slowest shade */
    int ymid = dev_y(0.05, L, size);
    expect_pixel(&im, dev_x(0.001, L, size), ymid, g, g, g, 1, "disc 0 inside the box");
    expect_pixel(&im, dev_x(L - 0.002, L, size), ymid, g, g, g, 1, "disc 0's image across x = L");
    ck_assert(is_white(&im, dev_x(L - 0.008, L, size), ymid)); /* but no wider than the disc */
    /* disc 1 at (0.099, 0.002): pieces at all four corners */
    expect_pixel(&im, dev_x(0.098, L, size), dev_y(0.003, L, size), g, g, g, 1,
                 "corner disc, bottom right");
    expect_pixel(&im, dev_x(0.001, L, size), dev_y(0.003, L, size), g, g, g, 1,
                 "corner disc, bottom left");
    expect_pixel(&im, dev_x(0.098, L, size), dev_y(L - 0.001, L, size), g, g, g, 1,
                 "corner disc, top right");
    expect_pixel(&im, dev_x(0.001, L, size), dev_y(L - 0.001, L, size), g, g, g, 1,
                 "corner disc, top left");
    expect_pixel(&im, dev_x(0.05, L, size), ymid, g, g, g, 1, "disc 2 wrapped from x = 0.35");
    ck_assert(is_white(&im, dev_x(0.05, L, size), dev_y(0.02, L, size)));
    image_free(&im);
    gr_frame_free(&f);
}
END_TEST

/* Walls along y (a bed): bars along the bottom and top edges, and no periodic image across them:
 * a disc at y = 0.002 m < r shows no piece at the top, which the periodic box draws; a centre
 * below 0 (a floor vibrating below 0) is drawn where it is, not wrapped to the top. */
START_TEST(test_2d_walls)
{
    const double L = 0.1, r = 0.005;
    const int size = 400;
    gr_frame f = frame_new(2, 2, L, 0.0);
    f.x[0] = 0.05, f.y[0] = 0.002;
    f.x[1] = 0.02, f.y[1] = -0.001;
    gr_error err = {0};
    const double g = 0.88;
    const int top = dev_y(L - 0.002, L, size), bottom = dev_y(0.001, L, size);
    for (int walls = 0; walls < 2; walls++) {
        gr_picture_options opt = {.size = size,
                                  .colormap = GR_CMAP_GREY,
                                  .hide_labels = true,
                                  .walls = {false, walls == 1}};
        const char *png = in_dir(walls ? "walls.png" : "nowalls.png");
        ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image im = load_png(png);
        if (walls) {
            ck_assert(is_white(&im, dev_x(0.05, L, size), top)); /* no image at the top */
            ck_assert(is_white(&im, dev_x(0.02, L, size), top)); /* nor the one below 0 */
            expect_pixel(&im, dev_x(0.05, L, size), bottom - 4, g, g, g, 1, "the disc itself");
            expect_pixel(&im, dev_x(0.08, L, size), size - 1, 0.15, 0.15, 0.15, 1, "the floor");
            expect_pixel(&im, dev_x(0.08, L, size), 0, 0.15, 0.15, 0.15, 1, "the ceiling");
        } else {
            expect_pixel(&im, dev_x(0.05, L, size), top, g, g, g, 1, "the periodic image");
        }
        image_free(&im);
    }
    gr_frame_free(&f);
}
END_TEST

/* ---------- 1D ---------- */

/* Three frames of a 0.2 m ring (one row each, a single segment at 1000 px): only the last frame
 * has a fast particle, and it sits across the ring's end, so its black pixels must appear in the
 * bottom row only and at both ends of that row. */
START_TEST(test_1d_strip)
{
    const double L = 0.2, r = 0.0015;
    gr_frame fr[3];
    for (int j = 0; j < 3; j++) {
        fr[j] = frame_new(20, 1, L, 0.01 * j);
        for (int i = 0; i < 20; i++) {
            fr[j].x[i] = 0.005 + 0.01 * i + 0.001 * j;
            fr[j].vx[i] = 0.1 * ((i % 3) - 1);
        }
    }
    fr[2].x[0] = 0.0005; /* crosses x = 0 */
    fr[2].vx[0] = 50.0;  /* ratio ~ 4.4: clipped black in the grey ramp */
    gr_picture_options opt = {.size = 1000, .colormap = GR_CMAP_GREY, .hide_labels = true};
    gr_error err = {0};
    const char *png = in_dir("strip.png");
    ck_assert_msg(gr_picture_strip(fr, 3, r, png, &opt, &err) == GR_OK, "%s", err.message);
    image im = load_png(png);
    ck_assert_int_eq(im.w, 1000);
    int ymin = im.h, ymax = -1, xmin = im.w, xmax = -1, first_disc_y = im.h;
    for (int y = 0; y < im.h; y++) {
        for (int x = 0; x < im.w; x++) {
            int p[3];
            pixel(&im, x, y, p);
            if (p[0] == 0 && p[1] == 0 && p[2] == 0) {
                ymin = y < ymin ? y : ymin, ymax = y > ymax ? y : ymax;
                xmin = x < xmin ? x : xmin, xmax = x > xmax ? x : xmax;
            }
            if (p[0] == 224 && y < first_disc_y) { /* 0.88 * 255: a slow disc */
                first_disc_y = y;
            }
        }
    }
    ck_assert_msg(ymax >= 0, "no black (fast) disc drawn");
    ck_assert_msg(first_disc_y < im.h / 3,
                  "the first frame's row is not at the top (first slow disc at y = %d of %d)",
                  first_disc_y, im.h);
    ck_assert_msg(ymin > im.h * 0.55,
                  "fast disc (last frame) drawn at y = %d..%d of %d: not in the bottom row", ymin,
                  ymax, im.h);
    ck_assert_msg(xmin < im.w / 20 && xmax > im.w - im.w / 20,
                  "fast disc across the ring's end spans x = %d..%d, "
                  "expected pieces at both ends of the row",
                  xmin, xmax);
    image_free(&im);

    /* one 1D frame through gr_picture_frame (y = NULL as gr_snapshot_read leaves it) */
    opt.hide_labels = false;
    const char *one = in_dir("one.png");
    ck_assert_msg(gr_picture_frame(&fr[2], r, one, &opt, &err) == GR_OK, "%s", err.message);
    im = load_png(one);
    ck_assert_int_eq(im.w, 1000);
    image_free(&im);

    /* a long ring (4 m, 1000 particles) is wrapped into several rows and stays within bounds */
    gr_frame ring = frame_new(1000, 1, 4.0, 1.0);
    for (int i = 0; i < 1000; i++) {
        ring.x[i] = 0.004 * i;
        ring.vx[i] = sin(i);
    }
    const char *longp = in_dir("long.png");
    ck_assert_msg(gr_picture_frame(&ring, r, longp, &opt, &err) == GR_OK, "%s", err.message);
    image lim = load_png(longp);
    ck_assert_int_eq(lim.w, 1000);
    ck_assert_msg(lim.h > 4 * 12 && lim.h <= GR_PICTURE_MAX_SIDE, "long ring: height %d", lim.h);
    image_free(&lim);
    gr_frame_free(&ring);
    for (int j = 0; j < 3; j++) {
        gr_frame_free(&fr[j]);
    }
    assert_no_temporaries(g_dir);
}
END_TEST

/* ---------- refusals leave nothing behind ---------- */

static char *slurp(const char *path, long *n)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot read %s", path);
    fseek(f, 0, SEEK_END);
    *n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)*n + 1);
    ck_assert_ptr_nonnull(buf);
    ck_assert_int_eq(fread(buf, 1, (size_t)*n, f), (size_t)*n);
    fclose(f);
    return buf;
}

static void expect_refusal(int rc, const gr_error *err, int code, const char *needle,
                           const char *what)
{
    ck_assert_msg(rc == code, "%s: expected %d, got %d (%s)", what, code, rc, err->message);
    ck_assert_int_eq(err->code, code);
    ck_assert_msg(strstr(err->message, needle) != NULL, "%s: message '%s' lacks '%s'", what,
                  err->message, needle);
    ck_assert_msg(strchr(err->message, '\n') == NULL, "%s: message is not one line", what);
}

START_TEST(test_refusals)
{
    const double L = 0.1, r = 0.004;
    gr_frame f = frame_new(4, 2, L, 0.0);
    for (int i = 0; i < 4; i++) {
        f.x[i] = 0.02 + 0.02 * i, f.y[i] = 0.05, f.vx[i] = i;
    }
    const char *png = in_dir("pic.png");
    gr_picture_options small = {.size = 128};
    gr_error err = {0};
    ck_assert_msg(gr_picture_frame(&f, r, png, &small, &err) == GR_OK, "%s", err.message);
    long n0;
    char *before = slurp(png, &n0);

    /* each refusal below must leave pic.png untouched and create nothing */
    f.x[2] = NAN;
    err = (gr_error){0};
    expect_refusal(gr_picture_frame(&f, r, png, &small, &err), &err, GR_EINVAL,
                   "non-finite position", "NaN x");
    f.x[2] = 0.06;
    f.y[3] = INFINITY;
    err = (gr_error){0};
    expect_refusal(gr_picture_frame(&f, r, png, &small, &err), &err, GR_EINVAL,
                   "non-finite position", "infinite y");
    f.y[3] = 0.05;
    f.vy[1] = NAN;
    err = (gr_error){0};
    expect_refusal(gr_picture_frame(&f, r, png, &small, &err), &err, GR_EINVAL,
                   "non-finite velocity", "NaN vy");
    f.vy[1] = 0.0;
    const double bad_r[] = {0.0, -1e-3, NAN, INFINITY, 0.2};
    for (size_t k = 0; k < sizeof bad_r / sizeof bad_r[0]; k++) {
        err = (gr_error){0};
        expect_refusal(gr_picture_frame(&f, bad_r[k], png, &small, &err), &err, GR_EINVAL, "radius",
                       "bad radius");
    }
    gr_picture_options huge = {.size = 100000}, neg = {.size = -5}, badv = {.vmax = NAN},
                       badl = {.levels = 1};
    const gr_picture_options *bad_opts[] = {&huge, &neg, &badv, &badl};
    for (size_t k = 0; k < 4; k++) {
        err = (gr_error){0};
        ck_assert_int_eq(gr_picture_frame(&f, r, png, bad_opts[k], &err), GR_EINVAL);
    }
    /* a strip of 1D frames refuses a 2D frame, and a NaN in a later frame */
    err = (gr_error){0};
    expect_refusal(gr_picture_strip(&f, 1, r, png, NULL, &err), &err, GR_EINVAL, "1D",
                   "2D frame in a strip");
    gr_frame s[2] = {frame_new(3, 1, L, 0.0), frame_new(3, 1, L, 0.1)};
    s[1].x[1] = NAN;
    err = (gr_error){0};
    expect_refusal(gr_picture_strip(s, 2, r, png, NULL, &err), &err, GR_EINVAL,
                   "frame 1 particle 1", "NaN in frame 1");
    err = (gr_error){0};
    ck_assert_int_eq(gr_picture_strip(s, 0, r, png, NULL, &err), GR_EINVAL);
    /* too many frames for one picture */
    gr_frame *many = calloc(3000, sizeof *many);
    ck_assert_ptr_nonnull(many);
    for (int j = 0; j < 3000; j++) {
        many[j] = s[0];
    }
    err = (gr_error){0};
    expect_refusal(gr_picture_strip(many, 3000, r, png, NULL, &err), &err, GR_EINVAL, "too large",
                   "3000 rows");
    free(many);

    long n1;
    char *after = slurp(png, &n1);
    ck_assert_msg(n0 == n1 && memcmp(before, after, (size_t)n0) == 0, "a refused call changed %s",
                  png);
    free(after);
    char name[300] = "";
    ck_assert_msg(count_entries(g_dir, name, sizeof name) == 1,
                  "refusals left files behind (e.g. %s)", name);

    /* a write failing half-way (file size limit: the PNG of 400 px is larger than 2000 bytes):
     * GR_EIO with the system's reason, the temporary removed, the earlier picture untouched */
    {
        struct rlimit old_lim, lim;
        ck_assert_int_eq(getrlimit(RLIMIT_FSIZE, &old_lim), 0);
        lim = old_lim;
        lim.rlim_cur = 2000;
        void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
        ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &lim), 0);
        gr_picture_options big = {.size = 400};
        err = (gr_error){0};
        int rc = gr_picture_frame(&f, r, png, &big, &err);
        setrlimit(RLIMIT_FSIZE, &old_lim);
        signal(SIGXFSZ, old_handler);
        expect_refusal(rc, &err, GR_EIO, "File too large", "write failure");
        after = slurp(png, &n1);
        ck_assert_msg(n0 == n1 && memcmp(before, after, (size_t)n0) == 0,
                      "a failed write changed %s", png);
        free(after);
        ck_assert_msg(count_entries(g_dir, name, sizeof name) == 1,
                      "a failed write left files behind (e.g. %s)", name);
    }
    free(before);

    /* an unwritable destination: GR_EIO, nothing created */
    err = (gr_error){0};
    expect_refusal(gr_picture_frame(&f, r, in_dir("no/such/folder/pic.png"), &small, &err), &err,
                   GR_EIO, "no/such/folder", "missing folder");
    ck_assert_int_eq(count_entries(g_dir, NULL, 0), 1);
    gr_frame_free(&s[0]);
    gr_frame_free(&s[1]);
    gr_frame_free(&f);
}
END_TEST

/* ---------- run folders ---------- */

/* The 2D steady scene of docs/scenes/steady-2d.ini shrunk to N = 200, L = 0.06 and 0.01 s with a
 * snapshot every 0.005 s: gr_picture_run draws DIR/snapshot.png from the last snapshot, and every
 * particle's centre pixel has the colour of its speed (so positions, the y flip, the radius from
 * scene.ini and v_rms are all right: a disc drawn too large would cover its neighbours' centres). */
START_TEST(test_run_folder_2d)
{
    char outset[400];
    snprintf(outset, sizeof outset, "output.dir=%s/run", g_dir);
    const char *sets[] = {"system.dim=2",
                          "system.N=200",
                          "system.L=0.06",
                          "placement.kind=hexagonal",
                          "model.normal=spring_dashpot",
                          "model.tangential=tangential_dashpot",
                          "model.eps_n=0.6",
                          "model.eps_t=0.6",
                          "noise.D=1e-8",
                          "noise.mode=symmetrised",
                          "integrator.dt=1e-6",
                          "run.warmup=0",
                          "run.duration=0.01",
                          "run.sample_every=1e-3",
                          "run.seed=1",
                          "run.progress=false",
                          "output.snapshot_every=0.005",
                          "output.plots=false",
                          outset};
    gr_scene sc;
    gr_error err = {0};
    ck_assert_msg(gr_scene_load(&sc, NULL, sets, (int)(sizeof sets / sizeof sets[0]), &err) ==
                      GR_OK,
                  "%s", err.message);
    gr_run_options ro = {.force = true};
    gr_run_result res;
    ck_assert_msg(gr_run(&sc, &ro, &res, &err) == GR_OK, "%s", err.message);
    char run[300], png[400], snap[400], last[600];
    snprintf(run, sizeof run, "%s/run", g_dir);
    snprintf(snap, sizeof snap, "%s/snapshots", run);
    ck_assert_msg(count_entries(snap, NULL, 0) >= 2, "the run wrote fewer than two snapshots");

    err = (gr_error){0};
    char written[600] = "";
    ck_assert_msg(gr_picture_run_ex(run, NULL, written, sizeof written, &err) == GR_OK, "%s",
                  err.message);
    snprintf(png, sizeof png, "%s/snapshot.png", run);
    ck_assert_str_eq(written, png);
    ck_assert_msg(gr_picture_run(run, &err) == GR_OK, "%s", err.message); /* again: replaces it */
    assert_no_temporaries(run);

    /* the last snapshot, read independently */
    int last_index = -1;
    DIR *d = opendir(snap);
    struct dirent *e;
    while ((e = readdir(d))) {
        int k;
        if (sscanf(e->d_name, "snap_%d.xyz", &k) == 1 && k > last_index) {
            last_index = k;
        }
    }
    closedir(d);
    snprintf(last, sizeof last, "%s/snap_%06d.xyz", snap, last_index);
    gr_frame f;
    ck_assert_msg(gr_snapshot_read(last, &f, &err) == GR_OK, "%s", err.message);
    ck_assert_int_eq(f.n, 200);
    image im = load_png(png);
    ck_assert_int_eq(im.w, 1000);
    double s2 = 0.0;
    for (int i = 0; i < f.n; i++) {
        s2 += f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i];
    }
    double vrms = sqrt(s2 / f.n);
    ck_assert(vrms > 0.0);
    int checked = 0;
    for (int i = 0; i < f.n; i++) {
        double x = f.x[i] - f.L * floor(f.x[i] / f.L), y = f.y[i] - f.L * floor(f.y[i] / f.L),
               rgb[3];
        gr_picture_colour(NULL, hypot(f.vx[i], f.vy[i]) / vrms, rgb);
        expect_pixel(&im, dev_x(x, f.L, 1000), dev_y(y, f.L, 1000), rgb[0], rgb[1], rgb[2], 2,
                     "particle centre");
        checked++;
    }
    ck_assert_int_eq(checked, 200);
    /* hexagonal bed of 200 discs (phi ~ 0.39) leaves background somewhere in the box */
    int white = 0;
    for (int y = 0; y < 1000; y += 7) {
        for (int x = 0; x < 1000; x += 7) {
            white += is_white(&im, x, y);
        }
    }
    ck_assert_msg(white > 1000, "hardly any background: %d white probes", white);
    image_free(&im);
    gr_frame_free(&f);
}
END_TEST

/* A 1D run folder (snapshots written by hand in the run's format, 45 of them, no scene.ini): the
 * radius comes from the XYZ column and DIR/snapshots.png stacks the last 40. A folder without
 * snapshots is refused and gets no picture. */
START_TEST(test_run_folder_1d)
{
    char snap[400];
    snprintf(snap, sizeof snap, "%s/snapshots", g_dir);
    ck_assert_int_eq(mkdir(snap, 0777), 0);
    gr_error err = {0};
    ck_assert_int_eq(gr_picture_run(g_dir, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "no trajectory") != NULL, "%s", err.message);
    for (int k = 0; k < 45; k++) {
        char p[500];
        snprintf(p, sizeof p, "%s/snap_%06d.xyz", snap, k);
        FILE *out = fopen(p, "w");
        ck_assert_ptr_nonnull(out);
        fprintf(out,
                "30\nLattice=\"0.3 0 0 0 1 0 0 0 1\" pbc=\"T F F\" Time=%g "
                "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1\n",
                0.001 * k);
        for (int i = 0; i < 30; i++) {
            fprintf(out, "G %.9g 0.5 0 %.9g 0 0 0.0015\n",
                    fmod(0.01 * i + 0.0002 * k * (i % 5), 0.3), sin(i + k));
        }
        fclose(out);
    }
    err = (gr_error){0};
    char written[600];
    ck_assert_msg(gr_picture_run_ex(g_dir, NULL, written, sizeof written, &err) == GR_OK, "%s",
                  err.message);
    ck_assert_msg(strstr(written, "/snapshots.png") != NULL, "%s", written);
    image im = load_png(written);
    ck_assert_int_eq(im.w, 1000);
    /* the space-time diagram of all 45 frames (1D runs) */
    gr_spacetime_layout l;
    ck_assert_int_eq(gr_picture_spacetime_layout(45, 0.3, 0.0015, NULL, &l, &err), GR_OK);
    ck_assert_int_eq(im.h, l.height);
    ck_assert_int_eq(l.row_h, 12); /* 900 / 45 = 20 px per frame, at most 12 */
    image_free(&im);
    assert_no_temporaries(g_dir);
}
END_TEST

/* The 1D space-time diagram: x across the ring, frame j in the j-th band of rows from the top,
 * every particle a mark at its position in the colour of its |v| / v_rms, on the dark ground; a
 * mark across the ring's end appears at both ends; the picture's size is the layout's. */
START_TEST(test_spacetime)
{
    enum { NF = 30 };
    const double L = 1.0, r = 0.002;
    gr_frame fr[NF];
    for (int j = 0; j < NF; j++) {
        fr[j] = frame_new(4, 1, L, 0.01 * j);
        fr[j].x[0] = 0.25;           /* at rest */
        fr[j].x[1] = 0.5 + 0.01 * j; /* moving right at 1 m/s */
        fr[j].vx[1] = 1.0;
        fr[j].x[2] = 0.0; /* on the ring's end, -1 m/s */
        fr[j].vx[2] = -1.0;
        fr[j].x[3] = 0.75; /* at rest */
    }
    gr_picture_options opt = {.size = 1000};
    gr_error err = {0};
    gr_spacetime_layout l;
    ck_assert_int_eq(gr_picture_spacetime_layout(NF, L, r, &opt, &l, &err), GR_OK);
    ck_assert_int_eq(l.width, 1000);
    ck_assert_int_eq(l.row_h, 12); /* 900 / 30 = 30, at most 12 */
    ck_assert_msg(l.x0 > 0 && l.y0 > 0 && l.x0 + l.w <= l.width && l.y0 + NF * l.row_h < l.height,
                  "layout %d %d %d %d", l.x0, l.y0, l.w, l.height);
    ck_assert_double_eq_tol(l.mark, fmax(1.0, 2.0 * r * l.w / L), 1e-12);
    const char *png = in_dir("spacetime.png");
    ck_assert_msg(gr_picture_spacetime(fr, NF, r, png, &opt, &err) == GR_OK, "%s", err.message);
    image im = load_png(png);
    ck_assert_int_eq(im.w, l.width);
    ck_assert_int_eq(im.h, l.height);
    const double vrms = sqrt(0.5);
    double c_still[3], c_moving[3];
    gr_picture_colour(&opt, 0.0, c_still);
    gr_picture_colour(&opt, 1.0 / vrms, c_moving);
    const double g = GR_SPACETIME_GROUND / 255.0;
    for (int j = 0; j < NF; j += 7) {
        const int y = l.y0 + j * l.row_h + l.row_h / 2;
        expect_pixel(&im, l.x0 + (int)(0.25 * l.w), y, c_still[0], c_still[1], c_still[2], 2,
                     "particle at rest");
        expect_pixel(&im, l.x0 + (int)((0.5 + 0.01 * j) * l.w), y, c_moving[0], c_moving[1],
                     c_moving[2], 2, "moving particle");
        expect_pixel(&im, l.x0, y, c_moving[0], c_moving[1], c_moving[2], 2,
                     "mark on the ring's end, left");
        expect_pixel(&im, l.x0 + l.w - 1, y, c_moving[0], c_moving[1], c_moving[2], 2,
                     "mark on the ring's end, right");
        expect_pixel(&im, l.x0 + (int)(0.4 * l.w), y, g, g, g, 0, "the ground");
        /* time runs down: the moving particle is not yet at its last position in row j < NF - 1 */
        if (j < NF - 1) {
            expect_pixel(&im, l.x0 + (int)((0.5 + 0.01 * (NF - 1)) * l.w), y, g, g, g, 0,
                         "later position, earlier row");
        }
    }
    image_free(&im);
    /* refusals: 2D frames, no frames, too many frames */
    gr_frame two = frame_new(2, 2, L, 0.0);
    ck_assert_int_eq(gr_picture_spacetime(&two, 1, r, in_dir("bad.png"), &opt, &err), GR_EINVAL);
    ck_assert_msg(strstr(err.message, "1D") != NULL, "%s", err.message);
    ck_assert_int_eq(gr_picture_spacetime(fr, 0, r, in_dir("bad.png"), &opt, &err), GR_EINVAL);
    ck_assert_int_eq(gr_picture_spacetime_layout(GR_SPACETIME_MAX_FRAMES + 1, L, r, &opt, &l, &err),
                     GR_EINVAL);
    ck_assert_int_eq(access(in_dir("bad.png"), F_OK), -1);
    gr_frame_free(&two);
    for (int j = 0; j < NF; j++) {
        gr_frame_free(&fr[j]);
    }
}
END_TEST

/* ---------- 3D ---------- */

/* Non-white pixels of the picture area (the square above the panel). */
static long inked(const image *im)
{
    long k = 0;
    for (int y = 0; y < im->w; y++) {
        for (int x = 0; x < im->w; x++) {
            k += !is_white(im, x, y);
        }
    }
    return k;
}

/* The view of src/io/picture_3d.c (yaw -30 degrees, pitch 25): the unit vector towards the viewer,
 * along which points project onto the same pixel. */
static void towards_viewer(double e[3])
{
    const double yaw = -30.0 * M_PI / 180.0, pitch = 25.0 * M_PI / 180.0;
    e[0] = -cos(pitch) * sin(yaw);
    e[1] = -cos(pitch) * cos(yaw);
    e[2] = sin(pitch);
}

/* A dense cube inks far more of the picture than a dilute one; a sphere at the centre is drawn at
 * the image's centre, lit from the upper left (its highlight brighter than its lower-right rim);
 * of two spheres on the same line of sight the nearer is drawn over the farther (painter's order),
 * whichever comes first in the frame; a non-finite z is refused. */
START_TEST(test_3d_spheres)
{
    gr_error err = {0};
    gr_picture_options opt = {.size = 400, .colormap = GR_CMAP_GREY};
    const double L = 0.05, r = 1e-3;
    uint64_t seed = 88172645463325252ull;
    long ink[2];
    const int counts[2] = {20, 3000};
    for (int k = 0; k < 2; k++) {
        gr_frame f = frame_new(counts[k], 3, L, 0.0);
        for (int i = 0; i < f.n; i++) {
            double *c[6] = {&f.x[i], &f.y[i], &f.z[i], &f.vx[i], &f.vy[i], &f.vz[i]};
            for (int q = 0; q < 6; q++) {
                seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17; /* xorshift64 */
                *c[q] = (q < 3 ? L : 1.0) * (double)(seed >> 11) / 9007199254740992.0;
            }
        }
        const char *png = in_dir(k ? "dense.png" : "dilute.png");
        ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image im = load_png(png);
        ink[k] = inked(&im);
        image_free(&im);
        gr_frame_free(&f);
    }
    ck_assert_msg(ink[1] > 10 * ink[0], "dense cube inks %ld px, dilute %ld", ink[1], ink[0]);
    /* one sphere at the centre, at rest (light grey 0.88): highlight above-left, rim below-right */
    const double pxm = 0.97 * 400 / (L * sqrt(3.0) + 2.0 * r), rp = r * pxm;
    gr_frame f = frame_new(1, 3, L, 0.0);
    f.x[0] = f.y[0] = f.z[0] = 0.5 * L;
    const char *one = in_dir("one.png");
    ck_assert_msg(gr_picture_frame(&f, r, one, &opt, &err) == GR_OK, "%s", err.message);
    image im = load_png(one);
    int hi[3], rim[3];
    pixel(&im, (int)(200 - 0.35 * rp), (int)(200 - 0.35 * rp), hi);
    pixel(&im, (int)(200 + 0.6 * rp), (int)(200 + 0.6 * rp), rim);
    ck_assert_msg(!is_white(&im, 200, 200), "no sphere at the centre");
    ck_assert_msg(hi[0] > rim[0] + 40, "highlight %d, rim %d", hi[0], rim[0]);
    image_free(&im);
    gr_frame_free(&f);
    /* two spheres on one line of sight: a fast (black) and a slow (light) one, either order */
    double e[3];
    towards_viewer(e);
    for (int order = 0; order < 2; order++) {
        gr_frame g = frame_new(2, 3, L, 0.0);
        for (int i = 0; i < 2; i++) {
            const double t = (i == order ? 0.2 : -0.2) * L; /* particle `order` is the nearer */
            g.x[i] = 0.5 * L + t * e[0];
            g.y[i] = 0.5 * L + t * e[1];
            g.z[i] = 0.5 * L + t * e[2];
        }
        g.vx[0] = 10.0; /* particle 0 fast: |v| / v_rms = sqrt(2), grey 0.88 (1 - sqrt(2) / 3) */
        const char *png = in_dir(order ? "near1.png" : "near0.png");
        ck_assert_msg(gr_picture_frame(&g, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image two = load_png(png);
        int c[3];
        pixel(&two, 200, 200, c);
        /* the nearer sphere's body colour at its centre (between highlight and rim) */
        if (order == 0) {
            ck_assert_msg(c[0] < 170, "fast sphere in front, centre pixel %d", c[0]);
        } else {
            ck_assert_msg(c[0] > 190, "slow sphere in front, centre pixel %d", c[0]);
        }
        image_free(&two);
        g.z[1] = NAN;
        expect_refusal(gr_picture_frame(&g, r, in_dir("nan.png"), &opt, &err), &err, GR_EINVAL,
                       "non-finite z", "3D frame with z = nan");
        gr_frame_free(&g);
    }
}
END_TEST

/* Walls along z (a 3D bed): the floor, the farther face from the viewer above, is shaded grey
 * behind the spheres, and a sphere below the floor (a floor vibrating below 0) is drawn where it is,
 * not wrapped to the top; without walls the floor's centre is white and the sphere is wrapped. */
START_TEST(test_3d_walls)
{
    gr_error err = {0};
    const double L = 0.05, r = 1e-3, yaw = -30.0 * M_PI / 180.0, pitch = 25.0 * M_PI / 180.0;
    const int size = 400;
    const double pxm = 0.97 * size / (L * sqrt(3.0) + 2.0 * r), o = 0.5 * size;
    /* the screen point of (x, y, z) relative to the cube's centre (src/io/picture_3d.c, view) */
    const double floor_sy = cos(pitch) * (-0.5 * L); /* the floor's centre: x = y = 0 */
    const int floor_px = (int)o, floor_py = (int)(o - floor_sy * pxm) - 3;
    const double q[3] = {0.1 * L, -0.2 * L, -0.5 * L - 0.5 * r}; /* below the floor */
    const double x1 = cos(yaw) * q[0] - sin(yaw) * q[1], y1 = sin(yaw) * q[0] + cos(yaw) * q[1];
    const int sph_px = (int)(o + x1 * pxm),
              sph_py = (int)(o - (cos(pitch) * q[2] + sin(pitch) * y1) * pxm);
    const double w[3] = {q[0], q[1], q[2] + L}; /* its periodic image at the top */
    const double wx1 = cos(yaw) * w[0] - sin(yaw) * w[1], wy1 = sin(yaw) * w[0] + cos(yaw) * w[1];
    const int img_px = (int)(o + wx1 * pxm),
              img_py = (int)(o - (cos(pitch) * w[2] + sin(pitch) * wy1) * pxm);
    for (int walls = 0; walls < 2; walls++) {
        gr_frame f = frame_new(1, 3, L, 0.0);
        f.x[0] = q[0] + 0.5 * L, f.y[0] = q[1] + 0.5 * L, f.z[0] = q[2] + 0.5 * L;
        gr_picture_options opt = {.size = size,
                                  .colormap = GR_CMAP_GREY,
                                  .hide_labels = true,
                                  .walls = {false, false, walls == 1}};
        const char *png = in_dir(walls ? "walls3d.png" : "nowalls3d.png");
        ck_assert_msg(gr_picture_frame(&f, r, png, &opt, &err) == GR_OK, "%s", err.message);
        image im = load_png(png);
        if (walls) {
            expect_pixel(&im, floor_px, floor_py, 0.82, 0.82, 0.82, 2, "the floor");
            ck_assert_msg(!is_white(&im, sph_px, sph_py), "no sphere below the floor");
            ck_assert_msg(is_white(&im, img_px, img_py), "a periodic image across the lid");
        } else {
            ck_assert_msg(is_white(&im, floor_px, floor_py), "a floor without walls");
            ck_assert_msg(!is_white(&im, img_px, img_py), "the sphere not wrapped without walls");
        }
        image_free(&im);
        gr_frame_free(&f);
    }
}
END_TEST

static Suite *picture_suite(void)
{
    Suite *s = suite_create("picture");
    TCase *tc = tcase_create("picture");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_2d_disc_colours);
    tcase_add_test(tc, test_2d_species_colours);
    tcase_add_test(tc, test_2d_periodic_edges);
    tcase_add_test(tc, test_2d_walls);
    tcase_add_test(tc, test_1d_strip);
    tcase_add_test(tc, test_refusals);
    tcase_add_test(tc, test_run_folder_2d);
    tcase_add_test(tc, test_run_folder_1d);
    tcase_add_test(tc, test_spacetime);
    tcase_add_test(tc, test_3d_spheres);
    tcase_add_test(tc, test_3d_walls);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    if (gr_test_tmp_root(g_root, sizeof g_root, "test_picture", "picture") != 0) {
        return EXIT_FAILURE;
    }
    int status = gr_test_run(picture_suite());
    gr_test_tmp_root_done(g_root, "test_picture");
    return status;
}
