/* The contact sublist: the pairs of the Verlet list that can touch soon.
 *
 * The list holds every pair closer than d (1 + skin), skin = 0.3 by default, so that it lasts
 * while no particle has moved skin d / 2 (hundreds of steps in a bed or the RFM). Most of its
 * pairs do not touch: a vibrated bed of spheres lists 4.6 pairs per sphere of which 0.013 overlap
 * (docs/systems-walls-gravity.md), and the kernels spent most of their time on the distances of
 * the others. The sublist keeps, row by row and in list order, the entries p of the list whose pair
 * is closer than d (1 + GR_SUBLIST_SKIN), or touched at the last force evaluation, or holds a
 * history vector; it is rebuilt from the list (one pass over it, no cells) when some particle has
 * moved GR_SUBLIST_SKIN d / 2 since, and after every build of the list. No pair outside it can
 * touch before then (the Verlet argument with the thinner skin), so the kernels scanning it
 * evaluate the same touching pairs in the same order as over the whole list, and every force, sum
 * and contact flag is the same bit for bit: whether it is on changes the speed only. A mixture's
 * pair is kept when closer than r_i + r_j + GR_SUBLIST_SKIN d (d the largest pair's contact
 * distance), so the same bound on the motion holds. It is on for
 * the Verlet step of a 2D or 3D simulation (identical grains or a mixture) when the list lasted at least
 * GR_SUBLIST_MIN_INTERVAL steps (then its rebuilds, about every fifteenth of the list's life, cost
 * little) and while it keeps at most GR_SUBLIST_MAX_SHARE of the list's pairs (in a clustered gas
 * most listed pairs are close, and scanning through it would only add work);
 * GRANULE_SUBLIST=off or on (environment) overrides both, for tests and benchmarks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/kernel_laws.h" /* wrap_delta */
#include "core/sim_internal.h"

#define GR_SUBLIST_SKIN 0.02 /* 0.05 gave the 3D bed 1.5-1.8x less (docs/performance.md) */
#define GR_SUBLIST_MIN_INTERVAL 100
#define GR_SUBLIST_MAX_SHARE 0.5 /* off (until the list's next build) when it keeps more */

/* Build the sublist from the list at the current positions; 0 when out of memory or when it
 * keeps more than GR_SUBLIST_MAX_SHARE of the list unless forced (then off until the list's next
 * build). */
static int build(gr_sim *s, const bool forced)
{
    const int n = s->n;
    const int64_t m = s->nl_start[n];
    if (!s->sl_start) {
        s->sl_start = malloc(sizeof(int) * (size_t)(n + 1));
        const int dz = s->dim == 3;
        s->xs_ref = malloc(sizeof(double) * (size_t)n);
        s->ys_ref = malloc(sizeof(double) * (size_t)n);
        s->zs_ref = dz ? malloc(sizeof(double) * (size_t)n) : NULL;
        if (!s->sl_start || !s->xs_ref || !s->ys_ref || (dz && !s->zs_ref)) {
            return 0;
        }
    }
    if (m > s->sl_cap) {
        int *p = realloc(s->sl_p, sizeof(int) * (size_t)(m > 0 ? m : 1));
        if (!p) {
            return 0;
        }
        s->sl_p = p;
        s->sl_cap = m;
    }
    /* identical grains: pairs closer than d (1 + skin); a mixture: closer than r_i + r_j + skin d,
     * d the largest pair's contact distance (the refresh's bound is in units of d alike) */
    const double cut = s->d * (1.0 + GR_SUBLIST_SKIN), cut2 = cut * cut;
    const double margin = GR_SUBLIST_SKIN * s->d;
    const double *rad = s->rad;
    /* the kernels' own differences: 3D wraps by the periods (INFINITY along a wall), 2D by L */
    const double P0 = s->dim == 3 ? s->period[0] : s->L, P1 = s->dim == 3 ? s->period[1] : s->L;
    const double P2 = s->dim == 3 ? s->period[2] : 0.0;
    const double *x = s->x, *y = s->y, *z = s->z, *h = s->nl_hist;
    const int hw = s->dim == 3 ? 3 : 1; /* doubles per history slot */
    int count = 0;
    for (int i = 0; i < n; i++) {
        s->sl_start[i] = count;
        for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
            const int j = s->nl_j[p];
            const double dx = wrap_delta(x[j] - x[i], P0), dy = wrap_delta(y[j] - y[i], P1);
            const double dz = s->dim == 3 ? wrap_delta(z[j] - z[i], P2) : 0.0;
            const double r2 = dx * dx + dy * dy + dz * dz,
                         cp = rad ? rad[i] + rad[j] + margin : 0.0;
            bool keep = (rad ? r2 < cp * cp : r2 < cut2) || s->nl_contact[p];
            for (int a = 0; h && a < hw && !keep; a++) {
                keep = h[(int64_t)hw * p + a] != 0.0;
            }
            if (keep) {
                s->sl_p[count++] = p;
            }
        }
    }
    s->sl_start[n] = count;
    if (!forced && count > GR_SUBLIST_MAX_SHARE * (double)m) { /* most pairs close: no gain */
        return 0;
    }
    memcpy(s->xs_ref, x, sizeof(double) * (size_t)n);
    memcpy(s->ys_ref, y, sizeof(double) * (size_t)n);
    if (s->dim == 3) {
        memcpy(s->zs_ref, z, sizeof(double) * (size_t)n);
    }
    s->sl_rebuilds++;
    return 1;
}

void gr_sublist_after_build(gr_sim *s)
{
    const char *e = getenv("GRANULE_SUBLIST"); /* once per build of the list: rare */
    const int mode = e && !strcmp(e, "off") ? -1 : e && !strcmp(e, "on") ? 1 : 0;
    const int64_t interval = s->step - s->sl_list_at; /* steps the list lasted */
    s->sl_list_at = s->step;
    const bool can = s->dim >= 2 && s->sl_verlet && s->params.skin > GR_SUBLIST_SKIN;
    s->sl_on = can && (mode == 1 || (mode == 0 && interval >= GR_SUBLIST_MIN_INTERVAL));
    s->sl_forced = mode == 1;
    if (s->sl_on && !build(s, s->sl_forced)) {
        s->sl_on = 0;
    }
}

void gr_sublist_refresh(gr_sim *s)
{
    if (!s->sl_on) {
        return;
    }
    const double lim = 0.5 * GR_SUBLIST_SKIN * s->d, lim2 = lim * lim;
    const double *x = s->x, *y = s->y, *xr = s->xs_ref, *yr = s->ys_ref;
    double worst = 0.0;
    if (s->dim == 3) {
        const double *z = s->z, *zr = s->zs_ref;
#pragma omp simd reduction(max : worst)
        for (int i = 0; i < s->n; i++) {
            const double dx = x[i] - xr[i], dy = y[i] - yr[i], dz = z[i] - zr[i];
            const double r2 = dx * dx + dy * dy + dz * dz;
            worst = r2 > worst ? r2 : worst;
        }
    } else {
#pragma omp simd reduction(max : worst)
        for (int i = 0; i < s->n; i++) {
            const double dx = x[i] - xr[i], dy = y[i] - yr[i];
            const double r2 = dx * dx + dy * dy;
            worst = r2 > worst ? r2 : worst;
        }
    }
    if (!(worst <= lim2) &&
        !build(s, s->sl_forced)) { /* a NaN rebuilds too; the step then stops on it */
        s->sl_on = 0;
    }
}

void gr_sublist_free(gr_sim *s)
{
    free(s->sl_start);
    free(s->sl_p);
    free(s->xs_ref);
    free(s->ys_ref);
    free(s->zs_ref);
}
