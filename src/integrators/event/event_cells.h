/* The event-driven core of discs and spheres, a template instantiated once per dimension:
 * event_2d.c (GR_EV_DIM 2: periodic square box, walls and gravity) and event_3d.c (GR_EV_DIM 3:
 * periodic cube, walls and gravity). Cell list with cell-crossing events, one calendar entry per particle (its
 * earliest predicted event: a collision with a partner, checked lazily against the partner's
 * collision counter, or the crossing into a neighbouring cell; "Single" scheduling,
 * ../shared/notes/physics-algorithms.md sec. 3.1-3.2).
 *
 * Cells have side >= d, so a particle can only touch particles of its own and the 8 (3D: 26)
 * adjacent cells; a particle's membership is kept exact by crossing events, and after every change
 * of its trajectory (collision) or cell (crossing) it is predicted again against those 9 (27)
 * cells. At least 4 cells per side (see alloc); all pairs, no crossings, only in a box walled
 * all round. Positions stay in [0, L): a
 * crossing out of the box wraps the particle's base. Pair geometry uses the minimum image.
 *
 * The 3D instance adds the z terms (EV_Z) after the 2D expressions, so the 2D instance is the 2D
 * code as it was, bit for bit. A 3D collision applies the model's rule (written for a plane,
 * models/law.h) in the plane of the normal n and the relative tangential velocity of the contact
 * point (g_t for smooth spheres, g_c of rule_3d for rough ones): the impulse lies in that plane,
 * so the rule's eps_n, eps_t, eps_n(v) and Walton's beta act on the 3-vectors exactly. */
#include <stdlib.h>

#include "integrators/event/event_internal.h"
#include "models/list.h"

#if GR_EV_DIM == 3
#define EV_Z(...) __VA_ARGS__
#define EV_FN(name) gr_ev3d_##name
#define EV_CELLS(nc) ((nc) * (nc) * (nc))
#elif GR_EV_DIM == 2
#define EV_Z(...)
#define EV_FN(name) gr_ev2d_##name
#define EV_CELLS(nc) ((nc) * (nc))
#else
#error "GR_EV_DIM must be 2 or 3"
#endif

int EV_FN(alloc)(gr_sim *s, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    const size_t n = (size_t)(e->n > 0 ? e->n : 1);
    e->ncell = (int)floor(e->L / e->d);
    /* A pair is predicted with the nearest periodic image of its relative position. With at
     * least 4 cells per side, particles in adjacent cells are less than L/2 apart on every axis,
     * so that image is the one they can touch until one of them changes cell or trajectory (and
     * is predicted again); with fewer (3 cells, or all pairs) a pair could meet through another
     * image unseen, and did (overlaps). Only walls on every axis (no images) allow all pairs. */
    const bool pairs = e->n >= 2 && !(e->wall[0] && e->wall[1] && GR_EV_DIM == 2);
    if (e->ncell < 4 && pairs) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: the periodic box is %.3g particle diameters wide (L = %g m, d = %g m): "
                       "the event-driven integrator needs at least 4 (a cell grid of 4 cells per "
                       "side keeps each pair's nearest periodic image exact); raise [system] N or "
                       "L, or lower packing_fraction",
                       s->params.source, e->L / e->d, e->L, e->d);
    }
    /* without pairs that could meet through an image (walls all round, or fewer than 2
     * particles), 3 cells per side or all pairs as before */
    const int least = pairs ? 4 : 3;
    if (e->ncell < least) {
        e->ncell = 1;
    }
    /* no more cells than about 2 per particle: bigger cells only cost a few more pair checks */
#if GR_EV_DIM == 3
    const int most = (int)ceil(cbrt(2.0 * e->n)) + 1;
#else
    const int most = (int)ceil(sqrt(2.0 * e->n)) + 1;
#endif
    if (e->ncell > most) {
        e->ncell = most >= least ? most : pairs ? 4 : 1;
    }
    e->cell = e->L / e->ncell;
    e->partner = malloc(n * sizeof(int));
    e->count = calloc(n, sizeof(int64_t));
    e->ev_count = calloc(n, sizeof(int64_t));
    e->cell_of = malloc(n * sizeof(int));
    e->next = malloc(n * sizeof(int));
    e->prev = malloc(n * sizeof(int));
    e->head = malloc(sizeof(int) * (size_t)EV_CELLS(e->ncell));
    if (!e->partner || !e->count || !e->ev_count || !e->cell_of || !e->next || !e->prev ||
        !e->head) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the event-driven cell list");
    }
    return GR_OK;
}

static inline void cell_insert(struct gr_event_state *e, int i, int c)
{
    e->cell_of[i] = c;
    e->prev[i] = -1;
    e->next[i] = e->head[c];
    if (e->head[c] >= 0) {
        e->prev[e->head[c]] = i;
    }
    e->head[c] = i;
}

static inline void cell_remove(struct gr_event_state *e, int i)
{
    const int c = e->cell_of[i];
    if (e->prev[i] >= 0) {
        e->next[e->prev[i]] = e->next[i];
    } else {
        e->head[c] = e->next[i];
    }
    if (e->next[i] >= 0) {
        e->prev[e->next[i]] = e->prev[i];
    }
}

/* Relative state of j seen from i at local time t (minimum image). */
static inline void rel(const struct gr_event_state *e, int i, int j, double t, int phase,
                       double *rx, double *ry, EV_Z(double *rz, ) double *wx,
                       double *wy EV_Z(, double *wz))
{
    double xi, vi, yi, ui, xj, vj, yj, uj;
    gr_ev_state_x(e, i, t, phase, &xi, &vi);
    gr_ev_state_y(e, i, t, phase, &yi, &ui);
    gr_ev_state_x(e, j, t, phase, &xj, &vj);
    gr_ev_state_y(e, j, t, phase, &yj, &uj);
    *rx = xj - xi;
    *ry = yj - yi;
    *rx -= e->wall[0] ? 0.0 : e->L * rint(*rx / e->L); /* no image across walls */
    *ry -= e->wall[1] ? 0.0 : e->L * rint(*ry / e->L);
    *wx = vj - vi;
    *wy = uj - ui;
#if GR_EV_DIM == 3
    double zi, si, zj, sj;
    gr_ev_state_z(e, i, t, phase, &zi, &si);
    gr_ev_state_z(e, j, t, phase, &zj, &sj);
    *rz = zj - zi;
    *rz -= e->wall[2] ? 0.0 : e->L * rint(*rz / e->L);
    *wz = sj - si;
#endif
}

/* First contact of the pair within one piece of constant relative acceleration A. */
static inline double piece_contact(double d, double rx, double ry, EV_Z(double rz, ) double wx,
                                   double wy, EV_Z(double wz, ) double Ax, double Ay,
                                   EV_Z(double Az, ) double T)
{
    const double r2 = rx * rx + ry * ry EV_Z(+rz * rz), w2 = wx * wx + wy * wy EV_Z(+wz * wz),
                 A2 = Ax * Ax + Ay * Ay EV_Z(+Az * Az);
    const double reach = sqrt(w2) * T + 0.5 * sqrt(A2) * T * T;
    if (r2 > (d + reach) * (d + reach)) {
        return GR_EV_INF; /* cannot get within d during this piece */
    }
    const double f0 = r2 - d * d, f1 = 2.0 * (rx * wx + ry * wy EV_Z(+rz * wz));
    if (A2 == 0.0) {
        return gr_ev_first_quadratic(f0, f1, w2, T);
    }
    const double c[5] = {f0, f1, w2 + rx * Ax + ry * Ay EV_Z(+rz * Az),
                         wx * Ax + wy * Ay EV_Z(+wz * Az), 0.25 * A2};
    /* f(t) >= c0 + min(c1, 0) T + min(c2, 0) T^2 + min(c3, 0) T^3 on [0, T] (c4 >= 0) */
    if (f0 > 0.0 &&
        f0 + T * (gr_ev_min0(c[1]) + T * (gr_ev_min0(c[2]) + T * gr_ev_min0(c[3]))) > 0.0) {
        return GR_EV_INF;
    }
    return gr_ev_first_quartic(c, T);
}

static double pair_time(const struct gr_event_state *e, int i, int j, int *phase)
{
    double rx, ry, wx, wy EV_Z(, rz, wz);
    rel(e, i, j, e->now, e->phase, &rx, &ry, EV_Z(&rz, ) & wx, &wy EV_Z(, &wz));
    *phase = e->phase;
    const double d = gr_ev_d(e, i, j); /* the pair's contact distance */
    if (e->phase == 0) {
        double t =
            piece_contact(d, rx, ry, EV_Z(rz, ) wx, wy, EV_Z(wz, ) e->a1x[j] - e->a1x[i],
                          e->a1y[j] - e->a1y[i], EV_Z(e->a1z[j] - e->a1z[i], ) e->h - e->now);
        if (t < GR_EV_INF) {
            return e->now + t;
        }
        rel(e, i, j, e->h, 1, &rx, &ry, EV_Z(&rz, ) & wx, &wy EV_Z(, &wz));
        *phase = 1;
        t = piece_contact(d, rx, ry, EV_Z(rz, ) wx, wy, EV_Z(wz, ) e->a2x[j] - e->a2x[i],
                          e->a2y[j] - e->a2y[i], EV_Z(e->a2z[j] - e->a2z[i], ) e->tau - e->h);
        return t < GR_EV_INF ? e->h + t : GR_EV_INF;
    }
    double t = piece_contact(d, rx, ry, EV_Z(rz, ) wx, wy, EV_Z(wz, ) e->a2x[j] - e->a2x[i],
                             e->a2y[j] - e->a2y[i], EV_Z(e->a2z[j] - e->a2z[i], ) e->tau - e->now);
    return t < GR_EV_INF ? e->now + t : GR_EV_INF;
}

/* Earliest exit through the cell walls lo/hi of one coordinate within one piece. */
static inline double piece_exit(double x, double v, double a, double lo, double hi, double T,
                                int *face, int f_lo)
{
    double t_hi = gr_ev_first_quadratic(hi - x, -v, -0.5 * a, T);
    double t_lo = gr_ev_first_quadratic(x - lo, v, 0.5 * a, T);
    *face = t_lo < t_hi ? f_lo : f_lo + 1;
    return t_lo < t_hi ? t_lo : t_hi;
}

/* Cell c's coordinates (x fastest, then y, then z). */
static inline void cell_xyz(int nc, int c, int *cx, int *cy, int *cz)
{
#if GR_EV_DIM == 3
    *cx = c % nc;
    *cy = (c / nc) % nc;
    *cz = c / (nc * nc);
#else
    *cx = c % nc;
    *cy = c / nc;
    *cz = 0;
#endif
}

static inline int cell_index(int nc, int cx, int cy, int cz)
{
#if GR_EV_DIM == 3
    return (cz * nc + cy) * nc + cx;
#else
    (void)cz;
    return cy * nc + cx;
#endif
}

static double crossing_time(const struct gr_event_state *e, int i, int *face, int *phase)
{
    int cx, cy, cz;
    cell_xyz(e->ncell, e->cell_of[i], &cx, &cy, &cz);
    /* the first cell along a vibrating wall's axis reaches below 0 (grains on the wall there) */
    const double xlo = e->vib == 0 && cx == 0 ? -GR_EV_INF : cx * e->cell,
                 xhi = cx + 1 == e->ncell ? e->L : (cx + 1) * e->cell;
    const double ylo = e->vib == 1 && cy == 0 ? -GR_EV_INF : cy * e->cell,
                 yhi = cy + 1 == e->ncell ? e->L : (cy + 1) * e->cell;
#if GR_EV_DIM == 3
    const double zlo = e->vib == 2 && cz == 0 ? -GR_EV_INF : cz * e->cell,
                 zhi = cz + 1 == e->ncell ? e->L : (cz + 1) * e->cell;
#endif
    double x, v, y, w;
    int fx, fy;
    *phase = e->phase;
    double t0 = e->now;
    for (int piece = e->phase; piece < 2; piece++) {
        gr_ev_state_x(e, i, t0, piece, &x, &v);
        gr_ev_state_y(e, i, t0, piece, &y, &w);
        const double T = (piece == 0 ? e->h : e->tau) - t0;
        const double ax = piece == 0 ? e->a1x[i] : e->a2x[i],
                     ay = piece == 0 ? e->a1y[i] : e->a2y[i];
        double tx = piece_exit(x, v, ax, xlo, xhi, T, &fx, 0);
        double ty = piece_exit(y, w, ay, ylo, yhi, T, &fy, 2);
        double t = tx < ty ? tx : ty;
        int f = tx < ty ? fx : fy;
#if GR_EV_DIM == 3
        double z, u;
        int fz;
        gr_ev_state_z(e, i, t0, piece, &z, &u);
        const double tz = piece_exit(z, u, piece == 0 ? e->a1z[i] : e->a2z[i], zlo, zhi, T, &fz, 4);
        if (tz < t) {
            t = tz;
            f = fz;
        }
#endif
        if (t < GR_EV_INF) {
            *face = f;
            *phase = piece;
            return t0 + t;
        }
        t0 = e->h;
    }
    return GR_EV_INF;
}

/* Walls: event "faces" WALL_FACE + k, k = 2 a + side (side 0: the wall at 0, 1: at L). */
enum { WALL_FACE = 2 * GR_EV_DIM };

/* The coordinate and velocity of particle i along axis a (gr_ev_state_x, _y, _z), and its
 * acceleration there in piece `piece`. */
static inline double axis_state(const struct gr_event_state *e, int a, int i, double t, int piece,
                                double *q, double *v)
{
#if GR_EV_DIM == 3
    if (a == 2) {
        gr_ev_state_z(e, i, t, piece, q, v);
        return piece == 0 ? e->a1z[i] : e->a2z[i];
    }
#endif
    (a == 0 ? gr_ev_state_x : gr_ev_state_y)(e, i, t, piece, q, v);
    return a == 0 ? (piece == 0 ? e->a1x[i] : e->a2x[i]) : (piece == 0 ? e->a1y[i] : e->a2y[i]);
}

/* Earliest hit of a wall: the centre reaching r from it while moving towards it, per piece of
 * constant acceleration (a parabola under gravity: gr_ev_first_quadratic). */
static double wall_time(const struct gr_event_state *e, int i, int *face, int *phase)
{
    double t0 = e->now;
    *phase = e->phase;
    for (int piece = e->phase; piece < 2; piece++) {
        const double T = (piece == 0 ? e->h : e->tau) - t0;
        double best = GR_EV_INF;
        for (int a = 0; a < GR_EV_DIM; a++) {
            if (!e->wall[a]) {
                continue;
            }
            double q, v;
            const double acc = axis_state(e, a, i, t0, piece, &q, &v);
            const double lo = gr_ev_wall_piece(e, a, 0, t0, q, v, acc, T, gr_ev_radius(e, i));
            const double hi = gr_ev_wall_piece(e, a, 1, t0, q, v, acc, T, gr_ev_radius(e, i));
            if (lo < best) {
                best = lo;
                *face = WALL_FACE + 2 * a;
            }
            if (hi < best) {
                best = hi;
                *face = WALL_FACE + 2 * a + 1;
            }
        }
        if (best < GR_EV_INF) {
            *phase = piece;
            return t0 + best;
        }
        t0 = e->h;
    }
    return GR_EV_INF;
}

/* The particle's own next event, a cell crossing or a wall, into best/who/phase. */
static void own_event(const struct gr_event_state *e, int i, double *best, int *who, int *phase)
{
    int face = 0, ph;
    if (e->ncell > 1) {
        double t = crossing_time(e, i, &face, &ph);
        if (t < *best) {
            *best = t;
            *who = -1 - face;
            *phase = ph;
        }
    }
    if (e->wall[0] || e->wall[1] EV_Z(|| e->wall[2])) {
        double t = wall_time(e, i, &face, &ph);
        if (t < *best || (t == *best && ph < *phase)) {
            *best = t;
            *who = -1 - face;
            *phase = ph;
        }
    }
}

/* The particle's crossing or wall hit as its provisional event. */
static void predict_crossing(struct gr_event_state *e, int i)
{
    double best = GR_EV_INF;
    int who = -1, best_phase = e->phase;
    own_event(e, i, &best, &who, &best_phase);
    e->heap.t[i] = best;
    e->heap.ph[i] = (uint8_t)best_phase;
    e->partner[i] = who;
    e->ev_count[i] = 0;
}

static inline void offer(struct gr_event_state *e, int i, int j, double t, int ph)
{
    if (t < e->heap.t[i] || (t == e->heap.t[i] && ph < e->heap.ph[i])) {
        e->heap.t[i] = t;
        e->heap.ph[i] = (uint8_t)ph;
        e->partner[i] = j;
        e->ev_count[i] = e->count[j];
    }
}

/* Runs the statements after J for every particle J (an int the macro declares) in particle I's
 * cell and the cells around it: z, then y, then x from below, each cell's list in order, I itself
 * included (`continue` skips to the next partner). One walk for predict_all and predict, a macro
 * so that both compile to the loops they had when each wrote its own: this is the event loop's
 * hot path. */
#define EV_EACH_PARTNER(E, I, J, ...)                                                              \
    do {                                                                                           \
        const int nc_ = (E)->ncell, span_ = nc_ > 1 ? 1 : 0;                                       \
        int cx_, cy_, cz_;                                                                         \
        cell_xyz(nc_, (E)->cell_of[I], &cx_, &cy_, &cz_);                                          \
        for (int dz_ = EV_Z(-span_) + 0; dz_ <= EV_Z(span_) + 0; dz_++) {                          \
            const int zz_ = (cz_ + dz_ + nc_) % nc_;                                               \
            for (int dy_ = -span_; dy_ <= span_; dy_++) {                                          \
                const int yy_ = (cy_ + dy_ + nc_) % nc_;                                           \
                for (int dx_ = -span_; dx_ <= span_; dx_++) {                                      \
                    const int xx_ = (cx_ + dx_ + nc_) % nc_;                                       \
                    for (int J = (E)->head[cell_index(nc_, xx_, yy_, zz_)]; J >= 0;                \
                         J = (E)->next[J]) {                                                       \
                        __VA_ARGS__                                                                \
                    }                                                                              \
                }                                                                                  \
            }                                                                                      \
        }                                                                                          \
    } while (0)

/* All particles at a window start: every pair is solved once and offered to both. */
static void predict_all(struct gr_event_state *e)
{
    for (int i = 0; i < e->n; i++) {
        predict_crossing(e, i);
    }
    if (e->no_collisions) {
        return;
    }
    for (int i = 0; i < e->n; i++) {
        EV_EACH_PARTNER(e, i, j, {
            if (j <= i) {
                continue;
            }
            int ph;
            double t = pair_time(e, i, j, &ph);
            if (t < GR_EV_INF) {
                offer(e, i, j, t, ph);
                offer(e, j, i, t, ph);
            }
        });
    }
}

/* The particle's earliest event in the rest of the window. */
static void predict(struct gr_event_state *e, int i)
{
    double best = GR_EV_INF;
    int who = -1, best_phase = e->phase;
    own_event(e, i, &best, &who, &best_phase);
    if (!e->no_collisions) {
        EV_EACH_PARTNER(e, i, j, {
            if (j == i) {
                continue;
            }
            int ph;
            double t = pair_time(e, i, j, &ph);
            if (t < best || (t == best && ph < best_phase)) {
                best = t;
                who = j;
                best_phase = ph;
            }
        });
    }
    e->heap.t[i] = best;
    e->heap.ph[i] = (uint8_t)best_phase;
    e->partner[i] = who;
    e->ev_count[i] = who >= 0 ? e->count[who] : 0;
}

void EV_FN(window)(gr_sim *s)
{
    struct gr_event_state *e = gr_ev(s);
    const int nc = e->ncell;
    for (int c = 0; c < EV_CELLS(nc); c++) {
        e->head[c] = -1;
    }
    for (int i = 0; i < e->n; i++) {
        /* bases are at the window start here: wrap them into the box */
        /* (not along a vibrating wall's axis: grains on it may be below 0) */
        e->bx[i] -= e->vib == 0 ? 0.0 : e->L * floor(e->bx[i] / e->L);
        e->by[i] -= e->vib == 1 ? 0.0 : e->L * floor(e->by[i] / e->L);
        int cx = (int)(e->bx[i] / e->cell), cy = (int)(e->by[i] / e->cell), cz = 0;
        cx = cx < 0 ? 0 : cx >= nc ? nc - 1 : cx;
        cy = cy < 0 ? 0 : cy >= nc ? nc - 1 : cy;
#if GR_EV_DIM == 3
        e->bz[i] -= e->vib == 2 ? 0.0 : e->L * floor(e->bz[i] / e->L);
        cz = (int)(e->bz[i] / e->cell);
        cz = cz < 0 ? 0 : cz >= nc ? nc - 1 : cz;
#endif
        cell_insert(e, i, cell_index(nc, cx, cy, cz));
    }
    predict_all(e);
    gr_heap_build(&e->heap);
}

/* Rebase particle i now at (x, y, z) with velocity (vx, vy, vz), booking the free-flight work
 * since its old base (its velocity just before: (vx0, vy0, vz0)). */
static inline void rebase(struct gr_event_state *e, int i, double x, double y,
                          EV_Z(double z, ) double vx0, double vy0, EV_Z(double vz0, ) double vx,
                          double vy EV_Z(, double vz))
{
#if GR_EV_DIM == 3
    e->injected +=
        0.5 * gr_ev_mass(e, i) *
        (vx0 * vx0 + vy0 * vy0 + vz0 * vz0 - e->bv[i] * e->bv[i] - e->bw[i] * e->bw[i] -
         e->bu[i] * e->bu[i] - gr_ev_gravity_work_3d(e, x - e->bx[i], y - e->by[i], z - e->bz[i]));
    e->bz[i] = z;
    e->bu[i] = vz;
#else
    e->injected += 0.5 * gr_ev_mass(e, i) *
                   (vx0 * vx0 + vy0 * vy0 - e->bv[i] * e->bv[i] - e->bw[i] * e->bw[i] -
                    gr_ev_gravity_work(e, x - e->bx[i], y - e->by[i]));
#endif
    e->t0[i] = e->now;
    e->bx[i] = x;
    e->by[i] = y;
    e->bv[i] = vx;
    e->bw[i] = vy;
    e->past[i] = (uint8_t)e->phase;
}

static int check_overlaps(gr_sim *s, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    for (int i = 0; i < e->n; i++) {
        for (int j = i + 1; j < e->n; j++) {
            double rx, ry, wx, wy EV_Z(, rz, wz);
            rel(e, i, j, e->now, e->phase, &rx, &ry, EV_Z(&rz, ) & wx, &wy EV_Z(, &wz));
            double r = sqrt(rx * rx + ry * ry EV_Z(+rz * rz)), d = gr_ev_d(e, i, j);
            if (r < d * (1.0 - 1e-9)) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "event check: particles %d and %d overlap by %.3g d at t = %.9g s",
                               i, j, 1.0 - r / d, (double)e->win * e->tau + e->now);
            }
        }
    }
    return GR_OK;
}

/* A collision's losses (a pair's or a wall hit's), unless the TC rule made it elastic. */
static inline void book_losses(gr_sim *s, struct gr_event_state *e, bool elastic, double de_n,
                               double de_t)
{
    if (elastic) {
        e->tc_elastic++;
    } else {
        s->diss_n += de_n;
        s->diss_t += de_t;
    }
}

/* After a pair collision (rebased): its losses (unless TC-elastic), the TC clocks, the counts. */
static inline void booked(gr_sim *s, int i, int j, double t_abs, bool elastic, double de_n,
                          double de_t)
{
    struct gr_event_state *e = gr_ev(s);
    book_losses(s, e, elastic, de_n, de_t);
    e->last[i] = e->last[j] = t_abs;
    e->count[i]++;
    e->count[j]++;
    e->collisions++;
    s->collisions++;
}

#if GR_EV_DIM == 3
/* The model's rule on spheres i and j (gr_event_rule_3d, models/list.h): smooth (w1 = NULL) or
 * rough (the spin vectors, changed in place). With species as gr_ev_rule in 2D: the pair's
 * coefficients on two grains of mass 2 M_ij, the velocity changes rebuilt with the real masses
 * (2 m_j / (m_i + m_j) and 2 m_i / (m_i + m_j) of them), so sum m_i v_i is conserved; rough
 * spheres enter with their surface speeds r_i w_i, r_j w_j at unit arm, whose changes are rebuilt
 * the same way (so grain i's spin changes by -r_i n x P_t / I_i with its own I_i = q m_i r_i^2:
 * the equal pair's tangential mass q M_ij / (1 + q) is the unequal pair's, 1/m_t = 1/m_i + 1/m_j +
 * r_i^2/I_i + r_j^2/I_j). */
static inline void rule_3d(const struct gr_event_state *e, int i, int j, double n[3], double v1[3],
                           double v2[3], double *w1, double *w2, bool elastic, double *de_n,
                           double *de_t)
{
    if (!e->m) {
        gr_event_rule_3d(e->rule, e->cc, e->M, e->R, e->q, n, v1, v2, w1, w2, elastic, de_n, de_t);
        return;
    }
    const double mi = e->m[i], mj = e->m[j];
    const double u1[3] = {v1[0], v1[1], v1[2]}, u2[3] = {v2[0], v2[1], v2[2]};
    double s1[3] = {0.0, 0.0, 0.0}, s2[3] = {0.0, 0.0, 0.0}; /* rough: the surface speeds */
    for (int a = 0; w1 && a < 3; a++) {
        s1[a] = e->r[i] * w1[a];
        s2[a] = e->r[j] * w2[a];
    }
    const double s10[3] = {s1[0], s1[1], s1[2]}, s20[3] = {s2[0], s2[1], s2[2]};
    gr_event_rule_3d(e->rule, gr_ev_pair_cc(e, i, j), 2.0 * mi * mj / (mi + mj), w1 ? 1.0 : e->R,
                     e->q, n, v1, v2, w1 ? s1 : NULL, w1 ? s2 : NULL, elastic, de_n, de_t);
    const double wi = 2.0 * mj / (mi + mj), wj = 2.0 * mi / (mi + mj);
    for (int a = 0; a < 3; a++) {
        v1[a] = u1[a] + wi * (v1[a] - u1[a]);
        v2[a] = u2[a] + wj * (v2[a] - u2[a]);
        if (w1) {
            w1[a] += wi * (s1[a] - s10[a]) / e->r[i];
            w2[a] += wj * (s2[a] - s20[a]) / e->r[j];
        }
    }
}

/* Returns 0 after the collision, 1 when it is none after all (predict again), < 0 an error code
 * (the 3D twin of the 2D collide below: the same steps on 3-vectors). */
static int collide(gr_sim *s, int i, int j, double t_abs, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    double ri[3], vi[3], rj[3], vj[3];
    gr_ev_state_x(e, i, e->now, e->phase, &ri[0], &vi[0]);
    gr_ev_state_y(e, i, e->now, e->phase, &ri[1], &vi[1]);
    gr_ev_state_z(e, i, e->now, e->phase, &ri[2], &vi[2]);
    gr_ev_state_x(e, j, e->now, e->phase, &rj[0], &vj[0]);
    gr_ev_state_y(e, j, e->now, e->phase, &rj[1], &vj[1]);
    gr_ev_state_z(e, j, e->now, e->phase, &rj[2], &vj[2]);
    const double *const a_of[2][3] = {{e->a1x, e->a1y, e->a1z}, {e->a2x, e->a2y, e->a2z}};
    double n[3], A[3], r2 = 0.0, gn = 0.0, push = 0.0, A2 = 0.0;
    for (int a = 0; a < 3; a++) {
        n[a] = rj[a] - ri[a];
        n[a] -= e->wall[a] ? 0.0 : e->L * rint(n[a] / e->L); /* no image across walls */
        r2 += n[a] * n[a];
    }
    const double r = sqrt(r2);
    for (int a = 0; a < 3; a++) {
        n[a] /= r;
        A[a] = a_of[e->phase][a][j] - a_of[e->phase][a][i];
        gn += (vi[a] - vj[a]) * n[a]; /* > 0: approaching */
        push -= A[a] * n[a];          /* > 0: the noise presses the pair together */
        A2 += A[a] * A[a];
    }
    if (gn <= 0.0) {
        if (r > gr_ev_d(e, i, j) * (1.0 + 1e-9) || A2 == 0.0) {
            return 1; /* not a collision after all, or touching without approaching: predict again */
        }
        push = fmax(push, sqrt(A2)); /* about to approach: a pressed contact (2D collide) */
    }
    const bool elastic = gr_ev_tc_elastic(e, i, j, t_abs);
    double ui[3] = {vi[0], vi[1], vi[2]}, uj[3] = {vj[0], vj[1], vj[2]}, de_n = 0.0, de_t = 0.0;
    if (gn > 0.0 && e->rough) { /* [model] rotation = true: the spin vectors (wx, wy, omega) */
        double wi[3] = {s->wx[i], s->wy[i], s->omega[i]}, wj[3] = {s->wx[j], s->wy[j], s->omega[j]};
        rule_3d(e, i, j, n, ui, uj, wi, wj, elastic, &de_n, &de_t);
        s->wx[i] = wi[0], s->wy[i] = wi[1], s->omega[i] = wi[2];
        s->wx[j] = wj[0], s->wy[j] = wj[1], s->omega[j] = wj[2];
    } else if (gn > 0.0) {
        rule_3d(e, i, j, n, ui, uj, NULL, NULL, elastic, &de_n, &de_t);
    }
    const double floor_speed = 0.5 * push * gr_ev_tc(e, i, j); /* the contact floor, as in 2D */
    const double sep = (uj[0] - ui[0]) * n[0] + (uj[1] - ui[1]) * n[1] + (uj[2] - ui[2]) * n[2];
    if (push > 0.0 && sep < floor_speed) {
        double k0 = 0.0, k1 = 0.0, fi, fj; /* 1/2 each, or by the masses with species */
        gr_ev_floor_shares(e, i, j, &fi, &fj);
        for (int a = 0; a < 3; a++) {
            k0 += e->m ? e->m[i] * ui[a] * ui[a] + e->m[j] * uj[a] * uj[a]
                       : ui[a] * ui[a] + uj[a] * uj[a];
            ui[a] -= fi * (floor_speed - sep) * n[a];
            uj[a] += fj * (floor_speed - sep) * n[a];
            k1 += e->m ? e->m[i] * ui[a] * ui[a] + e->m[j] * uj[a] * uj[a]
                       : ui[a] * ui[a] + uj[a] * uj[a];
        }
        const double mk = e->m ? 1.0 : e->M; /* species: the masses are in k0, k1 */
        e->injected += 0.5 * mk * (k1 - k0);
        e->floor_energy += 0.5 * mk * (k1 - k0);
        e->floors++;
        if (gr_ev_floor_check(s, i, j, t_abs, floor_speed, err)) {
            return GR_EUNSTABLE;
        }
    }
    /* s->contacts: no observable that reads contact events is defined in 3D (the scene refuses
     * them), and gr_contact_event has no z: nothing is recorded */
    rebase(e, i, ri[0], ri[1], ri[2], vi[0], vi[1], vi[2], ui[0], ui[1], ui[2]);
    rebase(e, j, rj[0], rj[1], rj[2], vj[0], vj[1], vj[2], uj[0], uj[1], uj[2]);
    booked(s, i, j, t_abs, elastic, de_n, de_t);
    return 0;
}
#else
/* Returns 0 after the collision, 1 when it is none after all (predict again), < 0 an error code. */
static int collide(gr_sim *s, int i, int j, double t_abs, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    double xi, vi, yi, ui, xj, vj, yj, uj;
    gr_ev_state_x(e, i, e->now, e->phase, &xi, &vi);
    gr_ev_state_y(e, i, e->now, e->phase, &yi, &ui);
    gr_ev_state_x(e, j, e->now, e->phase, &xj, &vj);
    gr_ev_state_y(e, j, e->now, e->phase, &yj, &uj);
    double rx = xj - xi, ry = yj - yi;
    rx -= e->wall[0] ? 0.0 : e->L * rint(rx / e->L);
    ry -= e->wall[1] ? 0.0 : e->L * rint(ry / e->L);
    const double r = sqrt(rx * rx + ry * ry), nx = rx / r, ny = ry / r;
    const double gn = (vi - vj) * nx + (ui - uj) * ny; /* > 0: approaching */
    const double Ax = (e->phase ? e->a2x[j] - e->a2x[i] : e->a1x[j] - e->a1x[i]);
    const double Ay = (e->phase ? e->a2y[j] - e->a2y[i] : e->a1y[j] - e->a1y[i]);
    double push = -(Ax * nx + Ay * ny); /* > 0: the noise presses the pair together */
    if (gn <= 0.0) {
        if (r > gr_ev_d(e, i, j) * (1.0 + 1e-9)) {
            return 1; /* not a collision after all: predict again */
        }
        /* touching without approaching: the quartic saw the pair about to approach (a critical
         * point at rounding distance); separate it as a pressed contact so time moves on */
        if (Ax == 0.0 && Ay == 0.0) {
            return 1; /* no acceleration: a touching pair that does not approach stays apart */
        }
        push = fmax(push, sqrt(Ax * Ax + Ay * Ay));
    }
    const bool elastic = gr_ev_tc_elastic(e, i, j, t_abs);
    double pi_x = vi, pi_y = ui, pj_x = vj, pj_y = uj, de_n = 0.0, de_t = 0.0;
    if (gn > 0.0) { /* a pressed pair that is not approaching only gets the floor */
        gr_event_pair p = {.R = e->R,
                           .q = e->q,
                           .nx = nx,
                           .ny = ny,
                           .v1x = vi,
                           .v1y = ui,
                           .v2x = vj,
                           .v2y = uj,
                           .elastic = elastic};
        if (e->rough) {
            p.w1 = &s->omega[i];
            p.w2 = &s->omega[j];
        }
        gr_ev_rule(e, i, j, &p); /* with species: the pair's masses and coefficients */
        pi_x = p.v1x;
        pi_y = p.v1y;
        pj_x = p.v2x;
        pj_y = p.v2y;
        de_n = p.de_n;
        de_t = p.de_t;
    }
    if (push > 0.0) {
        /* contact floor (docs/event-driven.md): separate at least fast enough that the pressing
         * noise brings the pair back no sooner than tc, so a pressed pair cannot stall time */
        const double floor_speed = 0.5 * push * gr_ev_tc(e, i, j);
        const double sep = (pj_x - pi_x) * nx + (pj_y - pi_y) * ny;
        if (sep < floor_speed) {
            const double k0 = pi_x * pi_x + pi_y * pi_y + pj_x * pj_x + pj_y * pj_y;
            const double ki = pi_x * pi_x + pi_y * pi_y, kj = pj_x * pj_x + pj_y * pj_y;
            double fi, fj; /* 1/2 each, or by the masses with species */
            gr_ev_floor_shares(e, i, j, &fi, &fj);
            const double dvi = fi * (floor_speed - sep), dvj = fj * (floor_speed - sep);
            pi_x -= dvi * nx;
            pi_y -= dvi * ny;
            pj_x += dvj * nx;
            pj_y += dvj * ny;
            const double added =
                e->m ? 0.5 * (e->m[i] * (pi_x * pi_x + pi_y * pi_y - ki) +
                              e->m[j] * (pj_x * pj_x + pj_y * pj_y - kj))
                     : 0.5 * e->M * (pi_x * pi_x + pi_y * pi_y + pj_x * pj_x + pj_y * pj_y - k0);
            e->injected += added;
            e->floor_energy += added;
            e->floors++;
            if (gr_ev_floor_check(s, i, j, t_abs, floor_speed, err)) {
                return GR_EUNSTABLE; /* before the rebase: the state stays that of the last event */
            }
        }
    }
    if (s->contacts) {
        const double L = e->L;
        double wxi = xi - L * floor(xi / L), wyi = yi - L * floor(yi / L);
        double wxj = xj - L * floor(xj / L), wyj = yj - L * floor(yj / L);
        if (e->vib >= 0) { /* not along a vibrating wall's axis (grains below 0 stay there) */
            wxi = e->vib == 0 ? xi : wxi, wxj = e->vib == 0 ? xj : wxj;
            wyi = e->vib == 1 ? yi : wyi, wyj = e->vib == 1 ? yj : wyj;
        }
        int rc = gr_ev_record(s, i, +1, t_abs, wxi, wyi, vi, ui, err);
        rc = rc ? rc : gr_ev_record(s, j, +1, t_abs, wxj, wyj, vj, uj, err);
        rc = rc ? rc : gr_ev_record(s, i, -1, t_abs, wxi, wyi, pi_x, pi_y, err);
        rc = rc ? rc : gr_ev_record(s, j, -1, t_abs, wxj, wyj, pj_x, pj_y, err);
        if (rc) {
            return rc; /* negative: an error code */
        }
    }
    rebase(e, i, xi, yi, vi, ui, pi_x, pi_y);
    rebase(e, j, xj, yj, vj, uj, pj_x, pj_y);
    booked(s, i, j, t_abs, elastic, de_n, de_t);
    return 0;
}

#endif

/* After a wall hit (rebased): its losses (unless TC-elastic), the TC clock, the counts. */
static inline void wall_booked(gr_sim *s, int i, double t_abs, bool elastic, double de_n,
                               double de_t)
{
    struct gr_event_state *e = gr_ev(s);
    book_losses(s, e, elastic, de_n, de_t);
    e->last[i] = t_abs;
    e->count[i]++;
    e->wall_hits++;
}

#if GR_EV_DIM == 2
/* Particle i hits the wall `k` (WALL_FACE + 2 a + side) now. The wall is a grain of infinite mass:
 * its collision is the model's event rule with the grain's point mirror image as partner
 * (velocity -v, normal along the axis; rough discs: the same spin, so the contact points' relative
 * velocity is twice the grain's), which for equal masses and a relative velocity 2 v gives
 * v' = v - (1 + eps_n) v_n n - (1 - eps_t) v_t exactly (an eps_n(v) rule gets the eps_n of the
 * grain's own speed against the wall as a constant: gr_ev_wall_cc), and for rough discs Walton's
 * rule at a fixed rough wall (the contact point's tangential velocity v_t + R w becomes -beta
 * times itself, or slides at the Coulomb limit beta_mu).
 * The pair's losses are both grains'; the wall's share is half. The TC rule
 * applies as for a pair (elastic within tc of the grain's last collision), and a grain that
 * gravity holds on the wall leaves it at least at the contact floor's speed g tc / 2 (as a pressed
 * pair does), so a resting grain bounces every ~tc instead of stalling time. A vibrating wall
 * (the wall at 0 of axis vib) does all this in its own frame (v_n' = v_w - eps_n (v_n - v_w)); the
 * grain's energy change plus the losses is the wall's work (gr_ledger.wall_work). */
static int wall_hit(gr_sim *s, int i, int k, double t_abs, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    const int a = (k - WALL_FACE) / 2, side = (k - WALL_FACE) % 2;
    double x, v, y, w;
    gr_ev_state_x(e, i, e->now, e->phase, &x, &v);
    gr_ev_state_y(e, i, e->now, e->phase, &y, &w);
    const double nx = a == 0 ? (side ? 1.0 : -1.0) : 0.0, ny = a == 1 ? (side ? 1.0 : -1.0) : 0.0;
    const double m = gr_ev_mass(e, i), R = gr_ev_radius(e, i); /* species: the grain's own */
    const bool moving = a == e->vib && side == 0;
    double vr = v, wr = w, vw = 0.0, aw = 0.0; /* the velocity in the wall's frame */
    if (moving) {
        if (gr_ev_vib_wall(e, t_abs, a == 0 ? x : y, R, &vw, &aw) > 1e-9 * e->d) {
            return 1; /* a checkpoint of gr_ev_moving_wall_first, not a hit: predict again */
        }
        vr -= a == 0 ? vw : 0.0;
        wr -= a == 1 ? vw : 0.0;
    }
    const double vn = vr * nx + wr * ny; /* > 0: towards the wall */
    const double acc =
        a == 0 ? (e->phase ? e->a2x[i] : e->a1x[i]) : (e->phase ? e->a2y[i] : e->a1y[i]);
    const double push = (a == 0 ? nx : ny) * (moving ? acc - aw : acc); /* > 0: pressed in */
    if (vn <= 0.0 && push <= 0.0) {
        return 1; /* leaving and not pressed: predict again */
    }
    const bool elastic = t_abs - e->last[i] < e->tc;
    double ux = vr, uy = wr, de_n = 0.0, de_t = 0.0;
    const double spin0 = e->rough ? s->omega[i] : 0.0;
    if (vn > 0.0) {
        double image_spin = spin0;
        gr_event_pair p = {.M = m,
                           .R = R,
                           .q = e->q,
                           .nx = nx,
                           .ny = ny,
                           .v1x = vr,
                           .v1y = wr,
                           .v2x = -vr,
                           .v2y = -wr,
                           .elastic = elastic};
        if (e->rough) {
            p.w1 = &s->omega[i];
            p.w2 = &image_spin;
        }
        gr_event_rule_apply(e->rule, gr_ev_wall_cc(s, e, vn), &p); /* the walls' own eps_n, eps_t */
        ux = p.v1x;
        uy = p.v1y;
        de_n = 0.5 * p.de_n;
        de_t = 0.5 * p.de_t;
    }
    double out = -(ux * nx + uy * ny); /* speed away from the wall (in its frame) */
    if (moving) {                      /* back in the lab frame */
        ux += a == 0 ? vw : 0.0;
        uy += a == 1 ? vw : 0.0;
        const double v0[2] = {v, w}, u1[2] = {ux, uy};
        const double spin1 = e->rough ? s->omega[i] : 0.0;
        s->wall_work += gr_ev_wall_work(m, gr_ev_inertia(s, e, i), 2, v0, u1, &spin0, &spin1, 1,
                                        elastic, de_n, de_t);
    }
    const double floor_speed = push > 0.0 ? 0.5 * push * e->tc : 0.0;
    if (out < floor_speed) {
        const double k0 = ux * ux + uy * uy;
        ux -= (floor_speed - out) * nx;
        uy -= (floor_speed - out) * ny;
        const double added = 0.5 * m * (ux * ux + uy * uy - k0);
        e->injected += added;
        e->floor_energy += added;
        e->floors++; /* ~M (g tc)^2 / 8 per resting grain and tc: booked as injected */
    }
    if (s->contacts) {
        const double wx = e->vib == 0 ? x : x - e->L * floor(x / e->L);
        const double wy = e->vib == 1 ? y : y - e->L * floor(y / e->L);
        int rc = gr_ev_record(s, i, +1, t_abs, wx, wy, v, w, err);
        rc = rc ? rc : gr_ev_record(s, i, -1, t_abs, wx, wy, ux, uy, err);
        if (rc) {
            return rc;
        }
    }
    /* the impulse the wall took (walls.csv: the mean force is its rate), the grain's momentum
     * change along the axis with the wall's sign (+: pushed outwards) */
    s->wall_impulse[2 * a + side] += m * (a == 0 ? ux - v : uy - w) * -(a == 0 ? nx : ny);
    rebase(e, i, x, y, v, w, ux, uy);
    wall_booked(s, i, t_abs, elastic, de_n, de_t);
    return 0;
}

#else
/* Sphere i hits the wall `k` (WALL_FACE + 2 a + side) now: the 2D wall_hit on 3-vectors, the
 * model's rule (gr_event_rule_3d) with the sphere's mirror image, velocity -v and the same spin
 * vector (rough spheres), as partner along the normal n = +-e_a towards the wall; a vibrating wall
 * in its own frame. */
static int wall_hit(gr_sim *s, int i, int k, double t_abs, gr_error *err)
{
    (void)err; /* no contact events in 3D (collide) */
    struct gr_event_state *e = gr_ev(s);
    const int a = (k - WALL_FACE) / 2, side = (k - WALL_FACE) % 2;
    double r[3], v[3];
    gr_ev_state_x(e, i, e->now, e->phase, &r[0], &v[0]);
    gr_ev_state_y(e, i, e->now, e->phase, &r[1], &v[1]);
    gr_ev_state_z(e, i, e->now, e->phase, &r[2], &v[2]);
    double n[3] = {0.0, 0.0, 0.0};
    n[a] = side ? 1.0 : -1.0;
    const double m = gr_ev_mass(e, i), R = gr_ev_radius(e, i); /* species: the grain's own */
    const bool moving = a == e->vib && side == 0;
    double u[3] = {v[0], v[1], v[2]}, vw = 0.0, aw = 0.0; /* u: in the wall's frame */
    if (moving) {
        if (gr_ev_vib_wall(e, t_abs, r[a], R, &vw, &aw) > 1e-9 * e->d) {
            return 1; /* a checkpoint of gr_ev_moving_wall_first, not a hit: predict again */
        }
        u[a] -= vw;
    }
    const double vn = u[a] * n[a]; /* > 0: towards the wall */
    double q, vq;
    const double acc = axis_state(e, a, i, e->now, e->phase, &q, &vq);
    const double push = n[a] * (moving ? acc - aw : acc); /* > 0: pressed */
    if (vn <= 0.0 && push <= 0.0) {
        return 1; /* leaving and not pressed: predict again */
    }
    const bool elastic = t_abs - e->last[i] < e->tc;
    double de_n = 0.0, de_t = 0.0;
    double spin0[3] = {0.0, 0.0, 0.0};
    if (e->rough) {
        spin0[0] = s->wx[i], spin0[1] = s->wy[i], spin0[2] = s->omega[i];
    }
    if (vn > 0.0) {
        double image[3] = {-u[0], -u[1], -u[2]};
        double wi[3] = {spin0[0], spin0[1], spin0[2]}, wj[3] = {spin0[0], spin0[1], spin0[2]};
        gr_event_rule_3d(e->rule, gr_ev_wall_cc(s, e, vn), m, R, e->q, n, u, image,
                         e->rough ? wi : NULL, e->rough ? wj : NULL, elastic, &de_n,
                         &de_t); /* the walls' own eps_n */
        if (e->rough) {
            s->wx[i] = wi[0], s->wy[i] = wi[1], s->omega[i] = wi[2];
        }
        de_n *= 0.5;
        de_t *= 0.5;
    }
    const double out = -u[a] * n[a]; /* speed away from the wall (in its frame) */
    if (moving) {                    /* back in the lab frame */
        u[a] += vw;
        const double spin1[3] = {e->rough ? s->wx[i] : 0.0, e->rough ? s->wy[i] : 0.0,
                                 e->rough ? s->omega[i] : 0.0};
        s->wall_work += gr_ev_wall_work(m, gr_ev_inertia(s, e, i), 3, v, u, spin0, spin1, 3,
                                        elastic, de_n, de_t);
    }
    const double floor_speed = push > 0.0 ? 0.5 * push * e->tc : 0.0;
    if (out < floor_speed) {
        const double k0 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        u[a] -= (floor_speed - out) * n[a];
        const double added = 0.5 * m * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2] - k0);
        e->injected += added;
        e->floor_energy += added;
        e->floors++;
    }
    s->wall_impulse[2 * a + side] += m * (u[a] - v[a]) * -n[a]; /* as in 2D */
    rebase(e, i, r[0], r[1], r[2], v[0], v[1], v[2], u[0], u[1], u[2]);
    wall_booked(s, i, t_abs, elastic, de_n, de_t);
    return 0;
}
#endif

int EV_FN(process)(gr_sim *s, double t_limit, gr_error *err)
{
    struct gr_event_state *e = gr_ev(s);
    gr_heap *hp = &e->heap;
    const double t_win = (double)e->win * e->tau;
    for (int i; (i = gr_heap_min(hp)) >= 0;) {
        const double t = hp->t[i];
        if (!(t <= t_limit)) {
            break;
        }
        const int p = e->partner[i];
        const double t_abs = t_win + t;
        int grc = gr_ev_guard(s, e, t_abs, i, p, err);
        if (grc) {
            return grc;
        }
        e->now = t;
        e->phase = hp->ph[i];
        if (p >= 0) {
            if (e->count[p] != e->ev_count[i]) {
                e->invalid++;
                predict(e, i);
                gr_heap_update(hp, i);
                continue;
            }
            int rc = collide(s, i, p, t_abs, err);
            if (rc < 0) {
                return rc;
            }
            if (rc > 0) {
                e->invalid++;
            } else if (e->check) {
                rc = check_overlaps(s, err);
                if (rc) {
                    return rc;
                }
            }
            predict(e, i);
            gr_heap_update(hp, i);
            if (rc == 0) {
                predict(e, p);
                gr_heap_update(hp, p);
            }
            continue;
        }
        const int face = -1 - p, nc = e->ncell;
        if (face >= WALL_FACE) {
            int rc = wall_hit(s, i, face, t_abs, err);
            if (rc < 0) {
                return rc;
            }
            e->invalid += rc;
            predict(e, i);
            gr_heap_update(hp, i);
            continue;
        }
        /* cell crossing: rebase at the cell wall, move to the neighbouring cell, wrap at the box
         * edge */
        double x, v, y, w;
        gr_ev_state_x(e, i, t, e->phase, &x, &v);
        gr_ev_state_y(e, i, t, e->phase, &y, &w);
#if GR_EV_DIM == 3
        double z, u;
        gr_ev_state_z(e, i, t, e->phase, &z, &u);
#endif
        rebase(e, i, x, y, EV_Z(z, ) v, w, EV_Z(u, ) v, w EV_Z(, u));
        int cx, cy, cz;
        cell_xyz(nc, e->cell_of[i], &cx, &cy, &cz);
        switch (face) {
        case 0: cx--; break;
        case 1: cx++; break;
        case 2: cy--; break;
        case 3: cy++; break;
        case 4: cz--; break;
        default: cz++; break;
        }
        if (cx < 0) {
            cx = nc - 1;
            e->bx[i] += e->L;
        } else if (cx >= nc) {
            cx = 0;
            e->bx[i] -= e->L;
        }
        if (cy < 0) {
            cy = nc - 1;
            e->by[i] += e->L;
        } else if (cy >= nc) {
            cy = 0;
            e->by[i] -= e->L;
        }
#if GR_EV_DIM == 3
        if (cz < 0) {
            cz = nc - 1;
            e->bz[i] += e->L;
        } else if (cz >= nc) {
            cz = 0;
            e->bz[i] -= e->L;
        }
#endif
        cell_remove(e, i);
        cell_insert(e, i, cell_index(nc, cx, cy, cz));
        e->crossings++;
        predict(e, i);
        gr_heap_update(hp, i);
    }
    return GR_OK;
}

#undef EV_Z
#undef EV_FN
#undef EV_EACH_PARTNER
#undef EV_CELLS
