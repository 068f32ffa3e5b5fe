/* The space-time diagram of a 1D run (src/io/picture.h): x across the ring, t down, particles
 * coloured by |v| / v_rms. Particles of a cluster move slowly (they have collided, eps < 1) and are
 * packed: a cluster is a band of light marks; its world lines show it forming and dissolving. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/picture.h"
#include "io/picture_internal.h"

enum { MAX_PLOT_ROWS = 900, MAX_ROW_H = 12 };

/* a "nice" tick step (1, 2 or 5 times a power of ten) giving about `target` intervals over span */
static double nice_step(double span, double target)
{
    const double raw = span / target, p = pow(10.0, floor(log10(raw))), f = raw / p;
    return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * p;
}

int gr_picture_spacetime_layout(int n, double L, double radius, const gr_picture_options *opt,
                                gr_spacetime_layout *l, gr_error *err)
{
    popts p;
    int rc = pic_resolve_options(opt, &p, err);
    if (rc) {
        return rc;
    }
    if (n < 1 || n > GR_SPACETIME_MAX_FRAMES) {
        return GR_FAIL(err, GR_EINVAL, "a space-time diagram takes 1 to %d frames (got %d)",
                       GR_SPACETIME_MAX_FRAMES, n);
    }
    if (!(L > 0.0) || !(radius > 0.0) || !isfinite(L)) {
        return GR_FAIL(err, GR_EINVAL,
                       "space-time diagram: ring length %g m and radius %g m must be positive", L,
                       radius);
    }
    const int s = pic_text_scale(p.size);
    memset(l, 0, sizeof *l);
    l->width = p.size;
    l->row_h =
        MAX_PLOT_ROWS / n < 1 ? 1 : (MAX_PLOT_ROWS / n > MAX_ROW_H ? MAX_ROW_H : MAX_PLOT_ROWS / n);
    /* left: the t tick labels ("0.0125"); top: the axis titles, then the x tick labels */
    l->x0 = p.labels ? (int)pic_text_width(s, "0.00000") + 6 * s : 2 * s;
    l->y0 = p.labels ? 22 * s : 2 * s;
    l->w = l->width - l->x0 - 4 * s;
    l->mark = fmax(1.0, 2.0 * radius * l->w / L);
    l->height = l->y0 + n * l->row_h + 4 * s + (p.labels ? pic_panel_height(s) : 0);
    if (l->w < 16) {
        return GR_FAIL(err, GR_EINVAL, "space-time diagram: %d px is too narrow", p.size);
    }
    return GR_OK;
}

/* The row (fractional, 0 = the middle of frame 0's band) of time t, interpolated between the
 * frames' times; -1 outside them. */
static double row_of(const gr_frame *frames, int n, double t)
{
    for (int j = 0; j + 1 < n; j++) {
        if (t >= frames[j].t && t <= frames[j + 1].t && frames[j + 1].t > frames[j].t) {
            return j + (t - frames[j].t) / (frames[j + 1].t - frames[j].t);
        }
    }
    return n == 1 || t == frames[n - 1].t ? n - 1.0 : -1.0;
}

/* ticks and titles: x (m) along the top edge, t (s) at round times down the left edge */
static void draw_axes(cairo_t *cr, const gr_spacetime_layout *l, const gr_frame *frames, int n,
                      double L, int s)
{
    char label[48];
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    pic_draw_text(cr, 2 * s, 2 * s, s, "t (s)");
    pic_draw_text(cr, l->x0 + 0.5 * l->w - 0.5 * pic_text_width(s, "x (m)"), 2 * s, s, "x (m)");
    const double step = nice_step(L, 5.0);
    for (int k = 0; k * step <= L * (1.0 + 1e-9); k++) {
        const double x = l->x0 + k * step / L * l->w;
        cairo_rectangle(cr, floor(fmin(x, l->x0 + l->w - 1)), l->y0 - 3 * s, 1.0, 3 * s);
        cairo_fill(cr);
        snprintf(label, sizeof label, "%g", k * step);
        const double tw = pic_text_width(s, label);
        double lx = x - 0.5 * tw;
        lx = lx + tw > l->width ? l->width - tw : lx;
        pic_draw_text(cr, lx, l->y0 - 12 * s, s, label);
    }
    /* about one tick per 40 px of picture, at multiples of a round step */
    const double t0 = frames[0].t, t1 = frames[n - 1].t;
    const double tstep = t1 > t0 ? nice_step(t1 - t0, fmax(1.0, n * l->row_h / (20.0 * s))) : 1.0;
    for (double T = ceil(t0 / tstep - 1e-9) * tstep; n > 0 && T <= t1 + 1e-9 * tstep; T += tstep) {
        const double r = row_of(frames, n, T);
        if (r < 0.0) {
            continue;
        }
        const double y = l->y0 + (r + 0.5) * l->row_h;
        cairo_rectangle(cr, l->x0 - 3 * s, floor(y), 3 * s, 1.0);
        cairo_fill(cr);
        snprintf(label, sizeof label, "%g", fabs(T) < 1e-12 * tstep ? 0.0 : T);
        pic_draw_text(cr, l->x0 - 4 * s - pic_text_width(s, label), y - 3.5 * s, s, label);
    }
}

int gr_picture_spacetime(const gr_frame *frames, int n, double radius, const char *png_path,
                         const gr_picture_options *opt, gr_error *err)
{
    popts p;
    int rc = pic_check_png_path(png_path, err);
    rc = rc ? rc : pic_resolve_options(opt, &p, err);
    if (!rc && (!frames || n < 1)) {
        rc = GR_FAIL(err, GR_EINVAL, "%s: a space-time diagram needs at least one frame (got %d)",
                     png_path, n);
    }
    for (int j = 0; j < n && !rc; j++) {
        rc = pic_check_frame(&frames[j], j, radius, err);
        if (!rc && frames[j].dim != 1) {
            rc =
                GR_FAIL(err, GR_EINVAL, "%s: frame %d is %dD; a space-time diagram is of 1D frames",
                        png_path, j, frames[j].dim);
        }
        if (!rc && fabs(frames[j].L - frames[0].L) > 1e-9 * frames[0].L) {
            rc = GR_FAIL(err, GR_EINVAL, "%s: frame %d has ring length %g m, frame 0 has %g m",
                         png_path, j, frames[j].L, frames[0].L);
        }
    }
    const double L = rc ? 0.0 : frames[0].L;
    gr_spacetime_layout l;
    rc = rc ? rc : gr_picture_spacetime_layout(n, L, radius, opt, &l, err);
    cairo_surface_t *surf;
    cairo_t *cr;
    rc = rc ? rc : pic_canvas_new(l.width, l.height, png_path, &surf, &cr, err);
    if (rc) {
        return rc;
    }
    const double ground = GR_SPACETIME_GROUND / 255.0;
    cairo_set_source_rgb(cr, ground, ground, ground);
    cairo_rectangle(cr, l.x0, l.y0, l.w, (double)n * l.row_h);
    cairo_fill(cr);
    cairo_save(cr);
    cairo_rectangle(cr, l.x0, l.y0, l.w, (double)n * l.row_h);
    cairo_clip(cr);
    double rgb[3];
    for (int j = 0; j < n; j++) {
        const gr_frame *f = &frames[j];
        const double vrms = pic_rms_speed(f), y = l.y0 + (double)j * l.row_h;
        for (int i = 0; i < f->n; i++) {
            pic_ramp(&p, vrms > 0.0 ? pic_speed(f, i) / vrms : 0.0, rgb);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            const double x = l.x0 + pic_wrap(f->x[i], L) / L * l.w;
            for (int m = -1; m <= 1; m++) { /* a mark across the ring's end is drawn at both ends */
                const double xm = x + m * l.w;
                if (xm + 0.5 * l.mark >= l.x0 && xm - 0.5 * l.mark <= l.x0 + l.w) {
                    cairo_rectangle(cr, xm - 0.5 * l.mark, y, l.mark, l.row_h);
                    cairo_fill(cr);
                }
            }
        }
    }
    cairo_restore(cr);
    if (p.labels) {
        const int s = pic_text_scale(l.width);
        draw_axes(cr, &l, frames, n, L, s);
        char left[96], right[64], caption[128];
        snprintf(left, sizeof left, "t = %.5g .. %.5g s, down", frames[0].t, frames[n - 1].t);
        snprintf(right, sizeof right, "N = %d  L = %.4g m", frames[0].n, L);
        snprintf(caption, sizeof caption, "speed |v| / v_rms (v_rms of each frame)");
        if (pic_text_width(s, caption) > l.width) {
            snprintf(caption, sizeof caption, "|v| / v_rms");
        }
        pic_draw_panel(cr, &p, l.width, l.height - pic_panel_height(s), left, right, caption);
    }
    return pic_canvas_save(surf, cr, png_path, err);
}
