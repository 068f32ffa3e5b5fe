/* Contact times under piecewise-constant accelerations (exact free flight, 2D): the first time
 * in [0, T] at which f(t) = |r + w t + A t^2 / 2|^2 - d^2, a quartic, is <= 0 while decreasing.
 * Robust root isolation instead of a closed-form quartic: the real roots of f' split [0, T] into
 * pieces on which f is monotone (the roots of f' are found the same way from f''), a sign change
 * on a decreasing piece brackets the contact, bisection finishes it. Returns the bracket end with
 * f > 0 (just before contact), or 0 when the pair already overlaps and approaches.
 *
 * Work is bounded for any input: every root search stops when its bracket is narrower than
 * tol = 4 DBL_EPSILON T (T the window piece; event times are local times in [0, tau], whose
 * rounding is of that order anyway) or after ITER_CAP steps, whichever comes first, so a root
 * near 0 is not chased through the subnormal range; non-finite coefficients give no event (the
 * step's finiteness check reports the state). */
#include <float.h>

#include "integrators/event/event_internal.h"

#define ITER_CAP 120 /* Newton/bisection steps per phase: 2^-120 of any bracket is below tol */

static double peval(const double *c, int deg, double t)
{
    double y = c[deg];
    for (int k = deg - 1; k >= 0; k--) {
        y = y * t + c[k];
    }
    return y;
}

/* Safeguarded Newton on the bracket [lo, hi] whose end lo has the sign of flo: Newton steps
 * that stay strictly inside the bracket, bisection otherwise; returns the end with lo's sign
 * once |hi - lo| <= tol (or after ITER_CAP steps of each phase). */
static double bisect(const double *c, int deg, double lo, double hi, double flo, double tol)
{
    double dc[4];
    for (int k = 0; k < deg; k++) {
        dc[k] = (k + 1) * c[k + 1];
    }
    double t = 0.5 * (lo + hi);
    for (int it = 0; it < ITER_CAP && fabs(hi - lo) > tol; it++) {
        double ft = peval(c, deg, t);
        if ((ft > 0.0) == (flo > 0.0)) {
            lo = t;
        } else {
            hi = t;
        }
        if (ft == 0.0) {
            return t; /* an exact root */
        }
        double df = peval(dc, deg - 1, t);
        double next = df != 0.0 ? t - ft / df : 0.5 * (lo + hi);
        if (!(next > (lo < hi ? lo : hi) && next < (lo < hi ? hi : lo)) ||
            fabs(next - t) > 0.5 * fabs(hi - lo)) {
            next = 0.5 * (lo + hi);
        }
        if (next == lo || next == hi || next == t) {
            break;
        }
        t = next;
    }
    /* Newton may have approached from one side only: probe across the root, then finish the
     * bracket by bisection so the returned end really lies next to the root */
    double probe = t - 2.0 * (peval(c, deg, t) / peval(dc, deg - 1, t));
    if (probe > (lo < hi ? lo : hi) && probe < (lo < hi ? hi : lo)) { /* inside the bracket */
        double fp = peval(c, deg, probe);
        if ((fp > 0.0) == (flo > 0.0)) {
            lo = probe;
        } else {
            hi = probe;
        }
    }
    for (int it = 0; it < ITER_CAP && fabs(hi - lo) > tol; it++) {
        double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) {
            break;
        }
        double fm = peval(c, deg, mid);
        if ((fm > 0.0) == (flo > 0.0)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* All real roots of the polynomial in (a, b), ascending (to within tol); returns their number (<= deg). */
static int roots_in(const double *c, int deg, double a, double b, double tol, double *out)
{
    while (deg > 0 && c[deg] == 0.0) {
        deg--;
    }
    int n = 0;
    if (deg == 1) {
        double t = -c[0] / c[1];
        if (t > a && t < b) {
            out[n++] = t;
        }
        return n;
    }
    if (deg == 2) {
        double disc = c[1] * c[1] - 4.0 * c[2] * c[0];
        if (disc < 0.0) {
            return 0;
        }
        double q = -0.5 * (c[1] + (c[1] >= 0.0 ? sqrt(disc) : -sqrt(disc)));
        double r1 = q / c[2], r2 = q != 0.0 ? c[0] / q : r1;
        if (r1 > r2) {
            double tmp = r1;
            r1 = r2;
            r2 = tmp;
        }
        if (r1 > a && r1 < b) {
            out[n++] = r1;
        }
        if (r2 > a && r2 < b && r2 != r1) {
            out[n++] = r2;
        }
        return n;
    }
    if (deg < 1) {
        return 0;
    }
    double dc[4], crit[4], pts[6];
    for (int k = 0; k < deg; k++) {
        dc[k] = (k + 1) * c[k + 1];
    }
    int m = roots_in(dc, deg - 1, a, b, tol, crit);
    pts[0] = a;
    for (int k = 0; k < m; k++) {
        pts[k + 1] = crit[k];
    }
    pts[m + 1] = b;
    for (int k = 0; k <= m; k++) {
        double fp = peval(c, deg, pts[k]), fq = peval(c, deg, pts[k + 1]);
        if (fq == 0.0 && k < m) {
            out[n++] = pts[k + 1];
        } else if ((fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0)) {
            out[n++] = bisect(c, deg, pts[k], pts[k + 1], fp, tol);
        }
    }
    return n;
}

double gr_ev_first_quartic(const double c[5], double T)
{
    if (!(isfinite(c[0]) && isfinite(c[1]) && isfinite(c[2]) && isfinite(c[3]) && isfinite(c[4]) &&
          T > 0.0 && isfinite(T))) {
        return GR_EV_INF;
    }
    const double tol = 4.0 * DBL_EPSILON * T;
    int deg = 4;
    while (deg > 0 && c[deg] == 0.0) {
        deg--;
    }
    double dc[4], crit[4], pts[6];
    for (int k = 0; k < deg; k++) {
        dc[k] = (k + 1) * c[k + 1];
    }
    int m = deg > 0 ? roots_in(dc, deg - 1, 0.0, T, tol, crit) : 0;
    pts[0] = 0.0;
    for (int k = 0; k < m; k++) {
        pts[k + 1] = crit[k];
    }
    pts[m + 1] = T;
    for (int k = 0; k <= m; k++) {
        double p = pts[k], q = pts[k + 1];
        double fp = peval(c, deg, p), fq = peval(c, deg, q);
        bool decreasing =
            fq < fp || (fq == fp && deg > 0 && peval(dc, deg - 1, 0.5 * (p + q)) < 0.0);
        if (!decreasing) {
            continue;
        }
        if (fp <= 0.0) {
            return p;
        }
        if (fq <= 0.0) {
            return bisect(c, deg, p, q, fp, tol);
        }
    }
    return GR_EV_INF;
}

/* Conservative advancement: at u the gap h and its rate h' bound h from below by
 * h + h' x - C x^2 / 2 for x >= 0 (|h''| <= C; a sawtooth's drops only raise h), so h has no zero
 * before that bound's first one, and the step to it skips no contact. Near a crossing of h this is
 * a Newton step from the safe side (the distance to the root squares per step); it ends when a
 * step no longer moves u, just before the root, h > 0 by rounding. A grain touching the wall and
 * separating (h <= 0, h' > 0, after a bounce) steps to the bound's second zero: h' stays
 * positive until then. */
double gr_ev_moving_wall_first(const gr_sim_params *p, double tw, double q0, double v0, double acc,
                               double r, double C, double T)
{
    double u = 0.0;
    for (int it = 0; it < GR_EV_WALL_STEPS; it++) {
        double qw, vw;
        gr_walls_motion(p, tw + u, &qw, &vw);
        const double h = q0 + u * (v0 + 0.5 * acc * u) - r - qw, hd = v0 + acc * u - vw;
        if (!(isfinite(h) && isfinite(hd))) {
            return GR_EV_INF; /* the step's finiteness check reports the state */
        }
        if (h <= 0.0 && hd <= 0.0) {
            return u; /* touching and approaching (or pressed): now */
        }
        double x;
        if (C == 0.0) {
            x = h > 0.0 && hd < 0.0 ? -h / hd : GR_EV_INF; /* straight lines: exact */
        } else if (h <= 0.0) {
            const double disc = hd * hd + 2.0 * C * h;
            x = disc > 0.0 ? (hd + sqrt(disc)) / C : hd / C;
        } else {
            const double root = sqrt(hd * hd + 2.0 * C * h);
            x = hd < 0.0 ? 2.0 * h / (root - hd) : (hd + root) / C;
        }
        if (!(u + x <= T)) {
            return GR_EV_INF;
        }
        if (u + x == u) {
            return u;
        }
        u += x;
    }
    return u; /* a checkpoint: h > 0 here */
}
