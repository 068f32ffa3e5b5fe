/* The contact sublist: the pairs of the Verlet list that can touch soon.
 *
 * The list holds every pair closer than d (1 + skin), skin = 0.3 by default, so that it lasts
 * while no particle has moved skin d / 2 (hundreds of steps in a bed or the RFM). Most of its
 * pairs do not touch: a vibrated bed of spheres lists 4.6 pairs per sphere of which 0.013 overlap
 * (docs/systems-walls-gravity.md), and the kernels spent most of their time on the distances of
 * the others. The sublist keeps, row by row and in list order, the entries p of the list whose pair
 * is closer than d (1 + w), or touched at the last force evaluation, or holds a history vector; it
 * is rebuilt from the list (one pass over it, no cells) when some particle has moved w d / 2
 * since, and after every build of the list. No pair outside it can touch before then (the Verlet
 * argument with the thinner skin), so the kernels scanning it evaluate the same touching pairs in
 * the same order as over the whole list, and every force, sum and contact flag is the same bit for
 * bit: whether it is on, and its width, change the speed only. A mixture's pair is kept when closer
 * than r_i + r_j + w d (d the largest pair's contact distance), so the same bound on the motion
 * holds. The width w (s->sl_width) adapts at each build of the list, by counts, never by clocks
 * (`adapt_width`).
 *
 * It is on for the Verlet step of a 2D or 3D simulation (identical grains or a mixture) when the
 * list lasted at least GR_SUBLIST_MIN_INTERVAL steps (then the list's own builds are rare enough
 * for the sublist's rebuilds between them to pay) and while it keeps at most GR_SUBLIST_MAX_SHARE
 * of the list's pairs (in a clustered gas most listed pairs are close, and scanning through it
 * would only add work) or the kernels screen it (few of its pairs touch); GRANULE_SUBLIST=off or
 * on (environment) overrides both, for tests and benchmarks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/kernel_laws.h" /* wrap_delta */
#include "core/sim_internal.h"

/* The sublist's width w in units of d: its start and its bounds. Thinner keeps fewer pairs to scan
 * at each step but is rebuilt more often; the best w is the system's (docs/performance.md, "The
 * sublist's width"): 0.002 on the settled 2D bed, 0.005 on the 3D bed, 0.02 or more on a
 * fluidised bed of 150 grains. */
#define GR_SUBLIST_WIDTH 0.02
#define GR_SUBLIST_WIDTH_MIN 0.001
#define GR_SUBLIST_WIDTH_MAX 0.05
#define GR_SUBLIST_WIDTH_STEP 1.25
/* A rebuild's cost in screened entries: one per listed pair plus this many per particle (the
 * pass walks every row; a row's loop exit is mispredicted about once per row). Calibrated on the
 * three beds at w = 0.02, 0.005, 0.002: the w where the two costs balance was the fastest on each. */
#define GR_SUBLIST_ROW_COST 4
#define GR_SUBLIST_MIN_INTERVAL 100
#define GR_SUBLIST_MAX_SHARE 0.5 /* off (until the list's next build) when it keeps more */

/* What deciding an entry reads, copied once per build (the flags the build writes as bytes could
 * otherwise alias every field of the simulation). */
typedef struct keep_ctx {
    const double *x, *y, *z, *h, *rad;
    const uint8_t *contact;
    const int *list;
    double P0, P1, P2, d, margin;
    int three;
} keep_ctx;

static keep_ctx keep_ctx_of(const gr_sim *s, const double margin)
{
    /* the kernels' own differences: 3D wraps by the periods (INFINITY along a wall), 2D by L */
    const int three = s->dim == 3;
    return (keep_ctx){.x = s->x,
                      .y = s->y,
                      .z = s->z,
                      .h = s->nl_hist,
                      .rad = s->rad,
                      .contact = s->nl_contact,
                      .list = s->nl_j,
                      .P0 = three ? s->period[0] : s->L,
                      .P1 = three ? s->period[1] : s->L,
                      .P2 = three ? s->period[2] : 0.0,
                      .d = s->d,
                      .margin = margin,
                      .three = three};
}

/* Whether list entry p of row i stays in the sublist: its pair is closer than its contact
 * distance (d, or r_i + r_j with species) plus margin, touched at the last evaluation, or holds a
 * history vector. */
static inline bool keeps(const keep_ctx *c, const int i, const int p)
{
    const int j = c->list[p];
    const double dx = wrap_delta(c->x[j] - c->x[i], c->P0),
                 dy = wrap_delta(c->y[j] - c->y[i], c->P1);
    const double dz = c->three ? wrap_delta(c->z[j] - c->z[i], c->P2) : 0.0;
    const double r2 = dx * dx + dy * dy + dz * dz;
    const double cut = (c->rad ? c->rad[i] + c->rad[j] : c->d) + c->margin;
    bool keep = (r2 < cut * cut) | c->contact[p]; /* no branch: most entries are apart */
    const int hw = c->three ? 3 : 1;              /* doubles per history slot */
    for (int a = 0; c->h && a < hw && !keep; a++) {
        keep = c->h[(int64_t)hw * p + a] != 0.0;
    }
    return keep;
}

/* The largest squared displacement of particles [lo, hi) since the list's build, by the Verlet
 * step's own expression (its opening pass, step.c: the minimum image by L along every axis, the
 * squares summed x, y, z in order), so that its comparison with the list's skin gives the same
 * answer bit for bit. */
static double list_moved2(const gr_sim *s, const int lo, const int hi)
{
    const double L = s->L, half = 0.5 * s->L;
    const double *x = s->x, *y = s->y, *z = s->z, *xr = s->x_ref, *yr = s->y_ref, *zr = s->z_ref;
    double worst = 0.0;
    for (int i = lo; i < hi; i++) {
        double dx = x[i] - xr[i], dy = y[i] - yr[i];
        dx += dx > half ? -L : (dx < -half ? L : 0.0);
        dy += dy > half ? -L : (dy < -half ? L : 0.0);
        double d2;
        if (s->dim == 3) {
            double dz = z[i] - zr[i];
            dz += dz > half ? -L : (dz < -half ? L : 0.0);
            d2 = 0.0;
            d2 += dx * dx;
            d2 += dy * dy;
            d2 += dz * dz;
        } else {
            d2 = dx * dx + dy * dy;
        }
        worst = d2 > worst ? d2 : worst;
    }
    return worst;
}

/* Each list entry's row (sl_row) for rows [lo, hi): once per build of the list. */
static void fill_rows(gr_sim *restrict s, const int lo, const int hi)
{
    int *restrict row = s->sl_row;
    for (int i = lo; i < hi; i++) {
        for (int p = s->nl_start[i]; p < s->nl_start[i + 1]; p++) {
            row[p] = i;
        }
    }
}

/* The keep decisions of entries [p0, p1) into sl_flag, without a loop per row (whose exit,
 * mispredicted once per row of two to five entries, was most of a bed's rebuild): each entry's
 * row from sl_row. Returns how many entries touched at the last evaluation (all of them kept). */
static int64_t decide(gr_sim *restrict s, const keep_ctx *c, const int p0, const int p1)
{
    const int *restrict row = s->sl_row;
    uint8_t *restrict flag = s->sl_flag;
    const uint8_t *restrict contact = c->contact;
    if (!c->h && !c->rad) {
        /* identical grains without a history law: the decisions in vector lanes (keeps'
         * arithmetic, wrap_delta as selects, as the kernels' screen_3d) */
        const double *restrict x = c->x, *restrict y = c->y, *restrict z = c->z;
        const int *restrict list = c->list;
        const double P0 = c->P0, P1 = c->P1, P2 = c->P2, h0 = 0.5 * P0, h1 = 0.5 * P1,
                     h2 = 0.5 * P2, cut = c->d + c->margin, cut2 = cut * cut;
        if (c->three) {
#pragma omp simd
            for (int p = p0; p < p1; p++) {
                const int i = row[p], j = list[p];
                double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
                dx += dx > h0 ? -P0 : (dx < -h0 ? P0 : 0.0);
                dy += dy > h1 ? -P1 : (dy < -h1 ? P1 : 0.0);
                dz += dz > h2 ? -P2 : (dz < -h2 ? P2 : 0.0);
                flag[p] = (uint8_t)((dx * dx + dy * dy + dz * dz < cut2) | contact[p]);
            }
        } else {
#pragma omp simd
            for (int p = p0; p < p1; p++) {
                const int i = row[p], j = list[p];
                double dx = x[j] - x[i], dy = y[j] - y[i];
                dx += dx > h0 ? -P0 : (dx < -h0 ? P0 : 0.0);
                dy += dy > h1 ? -P1 : (dy < -h1 ? P1 : 0.0);
                flag[p] = (uint8_t)((dx * dx + dy * dy < cut2) | contact[p]);
            }
        }
    } else {
        for (int p = p0; p < p1; p++) {
            flag[p] = keeps(c, row[p], p);
        }
    }
    int64_t touching = 0;
    for (int p = p0; p < p1; p++) {
        touching += contact[p];
    }
    return touching;
}

/* The kept entries of [p0, p1), appended branch-free from slot `count` on, and each entry's count
 * of kept entries before it (sl_pref); returns the count after them. An entry not kept writes the
 * slot the next kept one overwrites, so the entries after the range's last kept one write none:
 * that slot is the next thread's. */
static int compact(gr_sim *restrict s, const int p0, const int p1, int count)
{
    const int *restrict row = s->sl_row;
    const uint8_t *restrict flag = s->sl_flag;
    int *restrict pref = s->sl_pref, *restrict row_of = s->sl_i, *restrict sub = s->sl_p;
    int last = p1;
    while (last > p0 && !flag[last - 1]) {
        last--;
    }
    for (int p = p0; p < last; p++) {
        pref[p] = count;
        row_of[count] = row[p]; /* count <= p < m, so the slot exists */
        sub[count] = p;
        count += flag[p];
    }
    for (int p = last; p < p1; p++) {
        pref[p] = count;
    }
    return count;
}

/* What the build leaves besides the sublist, for particles [lo, hi): the rows' starts
 * (sl_start[i], from sl_pref), the reference positions, and the largest squared displacement
 * since the list's build (returned). */
static double finish_rows(gr_sim *restrict s, const int lo, const int hi)
{
    const int *restrict start = s->nl_start, *restrict pref = s->sl_pref;
    for (int i = lo; i < hi; i++) {
        s->sl_start[i] = pref[start[i]];
    }
    const size_t bytes = sizeof(double) * (size_t)(hi - lo);
    memcpy(s->xs_ref + lo, s->x + lo, bytes);
    memcpy(s->ys_ref + lo, s->y + lo, bytes);
    if (s->dim == 3) {
        memcpy(s->zs_ref + lo, s->z + lo, bytes);
    }
    return list_moved2(s, lo, hi);
}

/* The sublist of the entries of the list, its rows' starts, the reference positions and sl_gap, on
 * T threads (the entries and the rows split evenly; each thread's kept entries go after those of
 * the threads before it, so the sublist is the same on any T). Returns the touching entries. */
static int64_t build_flat(gr_sim *restrict s, const keep_ctx *c, const int T)
{
    const int n = s->n, m = s->nl_start[n];
    int64_t touching = 0;
    double worst = 0.0;
    int *kept = T > 1 ? malloc(sizeof(int) * (size_t)(T + 1)) : NULL; /* per thread */
    if (!kept) { /* one thread (or out of memory: the same sublist) */
        if (!s->sl_rows_ok) {
            fill_rows(s, 0, n);
        }
        touching = decide(s, c, 0, m);
        s->sl_pref[m] = compact(s, 0, m, 0);
        s->sl_start[n] = s->sl_pref[m];
        worst = finish_rows(s, 0, n);
    } else {
        const int rows_ok = s->sl_rows_ok;
#pragma omp parallel num_threads(T) reduction(+ : touching) reduction(max : worst)
        {
            const int t = GR_THREAD_ID, nth = GR_THREAD_COUNT;
            const int i0 = (int)((int64_t)n * t / nth), i1 = (int)((int64_t)n * (t + 1) / nth);
            const int p0 = (int)((int64_t)m * t / nth), p1 = (int)((int64_t)m * (t + 1) / nth);
            if (!rows_ok) {
                fill_rows(s, i0, i1);
#pragma omp barrier
            }
            touching += decide(s, c, p0, p1);
            int here = 0;
            for (int p = p0; p < p1; p++) {
                here += s->sl_flag[p];
            }
            kept[t + 1] = here;
#pragma omp barrier
            int before = 0;
            for (int u = 0; u < t; u++) {
                before += kept[u + 1];
            }
            const int after = compact(s, p0, p1, before);
            if (t == nth - 1) {
                s->sl_pref[m] = after;
                s->sl_start[n] = after;
            }
#pragma omp barrier
            const double w = finish_rows(s, i0, i1);
            worst = w > worst ? w : worst;
        }
        free(kept);
    }
    s->sl_rows_ok = 1;
    s->sl_gap = sqrt(worst);
    return touching;
}

/* Build the sublist from the list at the current positions; 0 when out of memory or when it
 * keeps more than GR_SUBLIST_MAX_SHARE of the list without being screened, unless forced (then
 * off until the list's next build). */
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
    if (m > s->sl_cap || !s->sl_pref) { /* sl_pref: m + 1 entries, also for an empty list */
        const size_t cap = (size_t)(m > 0 ? m : 1);
        int *p = realloc(s->sl_p, sizeof(int) * cap);
        if (p) {
            s->sl_p = p;
        }
        int *ri = p ? realloc(s->sl_i, sizeof(int) * cap) : NULL;
        if (ri) {
            s->sl_i = ri;
        }
        int *hits = ri ? realloc(s->sl_hits, sizeof(int) * cap) : NULL;
        if (hits) {
            s->sl_hits = hits;
        }
        uint8_t *f = hits ? realloc(s->sl_flag, cap) : NULL;
        if (f) {
            s->sl_flag = f;
        }
        int *rw = f ? realloc(s->sl_row, sizeof(int) * cap) : NULL;
        if (rw) {
            s->sl_row = rw;
        }
        int *pf = rw ? realloc(s->sl_pref, sizeof(int) * (cap + 1)) : NULL;
        if (!pf) {
            return 0;
        }
        s->sl_pref = pf;
        s->sl_cap = m;
        s->sl_rows_ok = 0;
    }
    /* pairs closer than their contact distance + skin d, d the largest pair's (the refresh's
     * bound is in units of d alike) */
    const keep_ctx c = keep_ctx_of(s, s->sl_width * s->d);
    const int64_t touching = build_flat(s, &c, gr_team(s));
    /* screen the entries first (the kernels' sl_screen) while fewer than half touch: where most
     * do (a clustered gas, a bed pressed into contact), the screen is a second look at every
     * touching pair */
    s->sl_screen = 2 * touching < s->sl_start[n];
    /* Most listed pairs close: without the screen, scanning through the sublist only adds work.
     * With it the sublist stays: a settled bed lists its nearest neighbours a hair apart, about
     * half of them within the sublist's width, and the kernel walking rows of two or three
     * entries spends its time leaving them (a mispredicted loop exit per row) where the screen's
     * one branch-free pass finds the few that touch (docs/performance.md, "The crystal's
     * kernel"). Species kernels and history laws do not screen. */
    const bool screened = s->sl_screen && !s->nl_hist && !s->rad;
    if (!forced && !screened && s->sl_start[n] > GR_SUBLIST_MAX_SHARE * (double)m) {
        return 0;
    }
    s->sl_rebuilds++;
    /* the work of the list's life so far: the kept entries scanned since the last build, and
     * this build's pass */
    s->sl_scan_work += (int64_t)s->sl_kept * (s->step - s->sl_built_at);
    s->sl_kept = s->sl_start[n];
    s->sl_built_at = s->step;
    s->sl_build_work += m + GR_SUBLIST_ROW_COST * (int64_t)n;
    return 1;
}

/* At a build of the list: the width that balances, over the list's life that ended, the entries
 * the kernels scanned at every step against the sublist's rebuilds. Scanning grows with w (more
 * kept pairs), rebuilding falls as 1 / w (a particle moves w d / 2 less often), so their sum is
 * least about where they are equal; one step of GR_SUBLIST_WIDTH_STEP per list towards it. Only
 * counts enter, so it is the same on every thread count and machine. */
static void adapt_width(gr_sim *s)
{
    const double hi = fmin(GR_SUBLIST_WIDTH_MAX, 0.5 * s->params.skin);
    if (s->sl_width == 0.0) {
        s->sl_width = fmin(GR_SUBLIST_WIDTH, hi);
    } else if (s->sl_on) {
        const int64_t scan = s->sl_scan_work + (int64_t)s->sl_kept * (s->step - s->sl_built_at);
        const double w = scan > s->sl_build_work ? s->sl_width / GR_SUBLIST_WIDTH_STEP
                                                 : s->sl_width * GR_SUBLIST_WIDTH_STEP;
        s->sl_width = fmax(GR_SUBLIST_WIDTH_MIN, fmin(w, hi));
    }
    s->sl_scan_work = 0;
    s->sl_build_work = 0;
    s->sl_kept = 0;
    s->sl_built_at = s->step;
}

void gr_sublist_after_build(gr_sim *s)
{
    const char *e = getenv("GRANULE_SUBLIST"); /* once per build of the list: rare */
    const int mode = e && !strcmp(e, "off") ? -1 : e && !strcmp(e, "on") ? 1 : 0;
    const int64_t interval = s->step - s->sl_list_at; /* steps the list lasted */
    s->sl_rows_ok = 0; /* a new list: build_flat fills its rows again */
    s->sl_list_at = s->step;
    adapt_width(s);
    const bool can = s->dim >= 2 && s->sl_verlet && s->params.skin > 2.0 * GR_SUBLIST_WIDTH_MIN;
    s->sl_on = can && (mode == 1 || (mode == 0 && interval >= GR_SUBLIST_MIN_INTERVAL));
    s->sl_forced = mode == 1;
    if (s->sl_on && !build(s, s->sl_forced)) {
        s->sl_on = 0;
    }
}

double gr_sublist_list_moved2(const gr_sim *s, const double moved2, const double lim2)
{
    /* a particle is at most sl_gap from the list's reference at the sublist's build plus its
     * move since (the triangle inequality, which the minimum image keeps); the margin covers the
     * rounding of the three square roots and the sum */
    const double bound = s->sl_gap + sqrt(moved2);
    if (bound * (1.0 + 1e-12) < sqrt(lim2)) {
        return 0.0; /* below the skin's half: the list stays, as the exact value would say */
    }
    return list_moved2(s, 0, s->n);
}

/* The largest squared displacement of the particles [lo, hi) since the sublist's build (the raw
 * difference: a particle wrapped across a periodic face counts as a long move, which only
 * rebuilds early; the Verlet step measures the minimum image in its opening pass instead). */
static double moved2(const gr_sim *s, const int lo, const int hi)
{
    const double *x = s->x, *y = s->y, *xr = s->xs_ref, *yr = s->ys_ref;
    double worst = 0.0;
    if (s->dim == 3) {
        const double *z = s->z, *zr = s->zs_ref;
#pragma omp simd reduction(max : worst)
        for (int i = lo; i < hi; i++) {
            const double dx = x[i] - xr[i], dy = y[i] - yr[i], dz = z[i] - zr[i];
            const double r2 = dx * dx + dy * dy + dz * dz;
            worst = r2 > worst ? r2 : worst;
        }
    } else {
#pragma omp simd reduction(max : worst)
        for (int i = lo; i < hi; i++) {
            const double dx = x[i] - xr[i], dy = y[i] - yr[i];
            const double r2 = dx * dx + dy * dy;
            worst = r2 > worst ? r2 : worst;
        }
    }
    return worst;
}

void gr_sublist_refresh(gr_sim *s)
{
    if (!s->sl_on) {
        return;
    }
    /* the largest displacement is the same on any number of threads; one thread enters no
     * parallel region (its call alone would cost a small bed's step a fifth, measured) */
    const int T = gr_team(s), n = s->n;
    double worst = 0.0;
    if (T > 1) {
#pragma omp parallel for num_threads(T) reduction(max : worst) schedule(static)
        for (int t = 0; t < T; t++) {
            const double w = moved2(s, (int)((int64_t)n * t / T), (int)((int64_t)n * (t + 1) / T));
            worst = w > worst ? w : worst;
        }
    } else {
        worst = moved2(s, 0, n);
    }
    gr_sublist_refresh_moved(s, worst);
}

void gr_sublist_refresh_moved(gr_sim *s, const double worst2)
{
    const double lim = 0.5 * s->sl_width * s->d;
    if (s->sl_on && !(worst2 <= lim * lim) &&
        !build(s, s->sl_forced)) { /* a NaN rebuilds too; the step then stops on it */
        s->sl_on = 0;
    }
}

void gr_sublist_free(gr_sim *s)
{
    free(s->sl_start);
    free(s->sl_p);
    free(s->sl_i);
    free(s->sl_hits);
    free(s->sl_flag);
    free(s->sl_row);
    free(s->sl_pref);
    free(s->xs_ref);
    free(s->ys_ref);
    free(s->zs_ref);
}
