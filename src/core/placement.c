/* Initial placements (sec. 2.1.4, Fig. 2.4) and the overlap check every initial state passes.
 *
 * 2D: hexagonal and square packings are beds of touching-or-nearly-touching particles filled
 * row by row from the bottom of the box (Fig. 2.4 a, b); `uniform` gives every particle an equal
 * square of the box (Fig. 2.4 c); `cluster` is one hexagonal cluster of touching particles at the
 * centre; `random` is random sequential addition, which jams near phi = 0.547, so it is refused
 * above phi = 0.5 (use a lattice for dense scenes). 1D: uniform spacing L/N, one touching
 * cluster, or random gaps. 3D (spheres in a periodic cube, docs/three-dimensions.md): `cubic`, a
 * simple cubic lattice of m = ceil(N^(1/3)) sites per edge filled x fastest, then y, then z;
 * `fcc`, the face-centred cubic lattice of m = ceil((N/4)^(1/3)) cells per edge (4 sites each,
 * nearest neighbours a / sqrt 2 apart, a = L / m), filled cell by cell in the same order; and
 * `random`, random sequential addition, which jams near phi = 0.38 in 3D, so it is refused above
 * phi = 0.3. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "core/sim_internal.h"
#include "granule/noise.h"

const char *gr_placement_name(gr_placement_kind k)
{
    static const char *names[] = {"hexagonal", "square", "uniform", "cluster",
                                  "random",    "cubic",  "fcc"};
    return names[k];
}

/* 1D with species or a radius distribution: the grains in index order, each its own diameter,
 * separated by gaps: equal (uniform), none (cluster, centred), or L' cut at sorted uniform points
 * (random); L' = L - sum of the diameters. */
static int place_1d_sizes(gr_sim *s, gr_error *err)
{
    const int n = s->n;
    double free_len = s->L;
    for (int i = 0; i < n; i++) {
        free_len -= 2.0 * s->rad[i];
    }
    double *gap = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (!gap) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory placing %d particles", n);
    }
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        gap[i] =
            s->params.placement == GR_PLACE_UNIFORM ? 1.0
            : s->params.placement == GR_PLACE_CLUSTER
                ? 0.0
                : -log(1.0 - gr_noise_uniform(s->params.seed, GR_STREAM_PLACEMENT, (uint64_t)i, 0));
        sum += gap[i];
    }
    /* uniform: the first grain half a gap from 0; cluster: the touching row centred */
    double pos = s->params.placement == GR_PLACE_UNIFORM   ? 0.5 * free_len / n
                 : s->params.placement == GR_PLACE_CLUSTER ? 0.5 * free_len
                                                           : 0.0;
    for (int i = 0; i < n; i++) {
        s->x[i] = pos + s->rad[i];
        pos += 2.0 * s->rad[i] + (sum > 0.0 ? free_len * gap[i] / sum : 0.0);
    }
    free(gap);
    return GR_OK;
}

static int place_1d(gr_sim *s, gr_error *err)
{
    int n = s->n;
    double L = s->L, d = s->d;
    if (s->rad &&
        (s->params.placement == GR_PLACE_UNIFORM || s->params.placement == GR_PLACE_CLUSTER ||
         s->params.placement == GR_PLACE_RANDOM)) {
        return place_1d_sizes(s, err);
    }
    switch (s->params.placement) {
    case GR_PLACE_UNIFORM:
        for (int i = 0; i < n; i++) {
            s->x[i] = (i + 0.5) * L / n;
        }
        return GR_OK;
    case GR_PLACE_CLUSTER:
        for (int i = 0; i < n; i++) {
            s->x[i] = 0.5 * L - 0.5 * n * d + (i + 0.5) * d;
        }
        return GR_OK;
    case GR_PLACE_RANDOM: {
        /* free length L' split at n sorted uniform points: gaps are d + spacings */
        double free_len = L - n * d;
        double *u = malloc(sizeof(double) * (size_t)n);
        if (!u) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory placing %d particles", n);
        }
        double sum = 0.0;
        for (int i = 0; i < n; i++) {
            u[i] =
                -log(1.0 - gr_noise_uniform(s->params.seed, GR_STREAM_PLACEMENT, (uint64_t)i, 0));
            sum += u[i];
        }
        double pos = 0.0;
        for (int i = 0; i < n; i++) {
            s->x[i] = pos + 0.5 * d;
            pos += d + free_len * u[i] / sum;
        }
        free(u);
        return GR_OK;
    }
    default:
        return GR_FAIL(err, GR_EINVAL, "placement %s is not available in 1D",
                       gr_placement_name(s->params.placement));
    }
}

static int capacity_error(gr_sim *s, gr_error *err, long cap, const char *what)
{
    return GR_FAIL(
        err, GR_EINVAL,
        "%s: [placement] kind = %s holds at most %ld particles in L = %g m with d = %g m (%s); N = "
        "%d. "
        "Use a larger L or a smaller N%s",
        s->params.source, gr_placement_name(s->params.placement), cap, s->L, s->d, what, s->n,
        s->params.placement == GR_PLACE_HEXAGONAL ? "" : ", or kind = hexagonal (densest)");
}

/* Hexagonal packing. A bed of touching rows (spacing a = L / floor(L/d) >= d, row height
 * a sqrt(3)/2) filled from the bottom when it fits; otherwise a triangular lattice stretched over
 * the whole periodic box (an even number of rows so the stagger wraps), with as many columns as
 * keep every neighbour distance >= d. The densest legal packing of the box is the largest
 * nx * ny over those lattices. */
static int place_hexagonal(gr_sim *s, gr_error *err)
{
    const double L = s->L, d = s->d;
    int nx = (int)floor(L / d);
    if (nx < 1) {
        return capacity_error(s, err, 0, "box narrower than a particle");
    }
    double a = L / nx, h = a * sqrt(3.0) / 2.0;
    int rows = (s->n + nx - 1) / nx;
    /* the bed fits if its rows do not reach their own periodic image: the top row must stay a
     * row height (staggered) or a full spacing (aligned, odd row count) below the bottom one */
    bool full = rows * h > L - (rows % 2 ? a - h : 0.0) + 1e-12 * L;
    if (!full) {
        for (int k = 0; k < s->n; k++) {
            int row = k / nx, col = k % nx;
            s->x[k] = (col + 0.25 + 0.5 * (row % 2)) * a;
            s->y[k] = (row + 0.5) * h;
        }
        return GR_OK;
    }
    long best_cap = 0;
    int best_nx = 0, best_ny = 0;
    for (int cx = (int)floor(L / d); cx >= 1; cx--) {
        double ax = L / cx;
        /* rows r and r+1 are a diagonal apart, rows r and r+2 a vertical 2h apart */
        double hmin2 = d * d - 0.25 * ax * ax;
        double hmin = fmax(hmin2 > 0.0 ? sqrt(hmin2) : 0.0, 0.5 * d);
        int cy = (int)floor(L / hmin * (1.0 + 1e-12));
        cy -= cy % 2;
        if (cy < 2) {
            continue;
        }
        long cap = (long)cx * cy;
        if (cap > best_cap) {
            best_cap = cap;
        }
        if (cap >= s->n && (best_nx == 0)) {
            /* fewest rows that hold N with this many columns */
            int ny = (s->n + cx - 1) / cx;
            ny += ny % 2;
            best_nx = cx;
            best_ny = ny;
        }
    }
    if (best_nx == 0) {
        /* the bed's own capacity: the most rows that still clear their periodic image */
        int rows_max = 0;
        for (int r = 1; r * h <= L + 1e-12 * L; r++) {
            if (!(r * h > L - (r % 2 ? a - h : 0.0) + 1e-12 * L)) {
                rows_max = r;
            }
        }
        long bed_cap = (long)nx * rows_max;
        return capacity_error(
            s, err, bed_cap > best_cap ? bed_cap : best_cap,
            "a hexagonal bed or a triangular lattice with neighbour distances >= d");
    }
    a = L / best_nx;
    h = L / best_ny;
    /* spread the N particles over the sites evenly, row by row */
    long sites = (long)best_nx * best_ny;
    for (int k = 0; k < s->n; k++) {
        long site = (long)((double)k * (double)sites / (double)s->n);
        int row = (int)(site / best_nx), col = (int)(site % best_nx);
        s->x[k] = (col + 0.25 + 0.5 * (row % 2)) * a;
        s->y[k] = (row + 0.5) * h;
    }
    return GR_OK;
}

static int place_square(gr_sim *s, gr_error *err)
{
    int nx = (int)floor(s->L / s->d);
    long cap = (long)nx * nx;
    if (s->n > cap) {
        return capacity_error(s, err, cap, "square lattice of spacing >= d");
    }
    double a = s->L / nx;
    for (int k = 0; k < s->n; k++) {
        s->x[k] = (k % nx + 0.5) * a;
        s->y[k] = (k / nx + 0.5) * a;
    }
    return GR_OK;
}

static int place_uniform(gr_sim *s, gr_error *err)
{
    int side = (int)ceil(sqrt((double)s->n));
    double a = s->L / side;
    if (a < s->d) {
        return capacity_error(s, err, (long)floor(s->L / s->d) * (long)floor(s->L / s->d),
                              "one particle per square of side L / ceil(sqrt N) >= d");
    }
    for (int k = 0; k < s->n; k++) {
        s->x[k] = (k % side + 0.5) * a;
        s->y[k] = (k / side + 0.5) * a;
    }
    return GR_OK;
}

typedef struct site {
    double x, y, r2;
} site;

static int by_distance(const void *a, const void *b)
{
    double da = ((const site *)a)->r2, db = ((const site *)b)->r2;
    return (da > db) - (da < db);
}

static int place_cluster(gr_sim *s, gr_error *err)
{
    /* the N sites of a touching hexagonal lattice nearest the centre: a roughly round cluster */
    double d = s->d, h = d * sqrt(3.0) / 2.0, c = 0.5 * s->L;
    int rings = (int)ceil(sqrt((double)s->n)) + 2;
    int m = (2 * rings + 1) * (2 * rings + 1);
    site *sites = malloc(sizeof(site) * (size_t)m);
    if (!sites) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory placing a cluster of %d particles", s->n);
    }
    int k = 0;
    for (int row = -rings; row <= rings; row++) {
        for (int col = -rings; col <= rings; col++) {
            double x = (col + 0.5 * (abs(row) % 2)) * d, y = row * h;
            sites[k++] = (site){x, y, x * x + y * y};
        }
    }
    qsort(sites, (size_t)m, sizeof(site), by_distance);
    double reach = sqrt(sites[s->n - 1].r2) + d;
    if (2.0 * reach > s->L) {
        free(sites);
        return capacity_error(s, err, 0, "a cluster wider than the box would touch its own image");
    }
    for (int i = 0; i < s->n; i++) {
        s->x[i] = c + sites[i].x;
        s->y[i] = c + sites[i].y;
    }
    free(sites);
    return GR_OK;
}

/* Random sequential addition gave up on particle i: free the grid, say which lattice to use. */
static int no_free_spot(const gr_sim *s, int i, uint64_t attempt, const char *lattice, int *head,
                        int *next, gr_error *err)
{
    free(head);
    free(next);
    return GR_FAIL(err, GR_EINVAL,
                   "%s: [placement] kind = random: no free spot found for particle %d after %llu "
                   "attempts; use %s",
                   s->params.source, i, (unsigned long long)attempt, lattice);
}

static int place_random(gr_sim *s, gr_error *err)
{
    double phi = s->n * M_PI * 0.25 * s->d * s->d / (s->L * s->L);
    if (s->rad) { /* species or a radius distribution: the actual radii */
        phi = 0.0;
        for (int i = 0; i < s->n; i++) {
            phi += M_PI * s->rad[i] * s->rad[i] / (s->L * s->L);
        }
    }
    if (phi > 0.5) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [placement] kind = random cannot reach phi = %.3f: random sequential "
                       "addition jams near 0.547; use hexagonal (any phi <= 0.9069)",
                       s->params.source, phi);
    }
    /* brute-force rejection against a coarse grid of already placed particles; cells of side
     * >= d, at most about 2N of them, so a dilute box costs O(N) memory (found by tests/fuzz) */
    int side = (int)floor(s->L / s->d);
    const int max_side = (int)ceil(sqrt(2.0 * s->n)) + 1;
    side = side < max_side ? side : max_side;
    if (side < 3) {
        side = 1; /* one cell holding everyone (the neighbour scan below assumes 3 or more) */
    }
    double cell = s->L / side;
    int *head = malloc(sizeof(int) * (size_t)side * (size_t)side),
        *next = malloc(sizeof(int) * (size_t)s->n);
    if (!head || !next) {
        free(head);
        free(next);
        return GR_FAIL(err, GR_ENOMEM, "out of memory placing %d particles", s->n);
    }
    for (int c = 0; c < side * side; c++) {
        head[c] = -1;
    }
    uint64_t attempt = 0;
    const uint64_t max_attempts = 1000ull * (uint64_t)s->n + 100000ull;
    for (int i = 0; i < s->n; i++) {
        for (;;) {
            if (attempt++ > max_attempts) {
                return no_free_spot(s, i, attempt, "hexagonal", head, next, err);
            }
            /* along a wall axis ([boundary], walls.c) every centre lies in [r_i, L - r_i] */
            const double ri = s->rad ? s->rad[i] : 0.5 * s->d;
            const double ux = gr_noise_uniform(s->params.seed, GR_STREAM_PLACEMENT, attempt, 0),
                         uy = gr_noise_uniform(s->params.seed, GR_STREAM_PLACEMENT, attempt, 1);
            double x = s->params.walls[0] ? ri + (s->L - 2.0 * ri) * ux : s->L * ux;
            double y = s->params.walls[1] ? ri + (s->L - 2.0 * ri) * uy : s->L * uy;
            int cx = (int)(x / cell) % side, cy = (int)(y / cell) % side;
            int ok = 1;
            for (int ox = -1; ox <= 1 && ok; ox++) {
                for (int oy = -1; oy <= 1 && ok; oy++) {
                    int c = ((cx + ox + side) % side) + side * ((cy + oy + side) % side);
                    for (int j = head[c]; j >= 0 && ok; j = next[j]) {
                        double dx = s->x[j] - x, dy = s->y[j] - y; /* no image across walls */
                        dx -= s->params.walls[0] ? 0.0 : s->L * rint(dx / s->L);
                        dy -= s->params.walls[1] ? 0.0 : s->L * rint(dy / s->L);
                        /* each pair its own contact distance (r_i + r_j <= d, the cells' side) */
                        const double dd = s->rad ? (s->rad[i] + s->rad[j]) * (s->rad[i] + s->rad[j])
                                                 : s->d * s->d;
                        ok = dx * dx + dy * dy >= dd;
                    }
                    if (side < 3) {
                        break;
                    }
                }
            }
            if (ok) {
                s->x[i] = x;
                s->y[i] = y;
                int c = cx + side * cy;
                next[i] = head[c];
                head[c] = i;
                break;
            }
        }
    }
    free(head);
    free(next);
    return GR_OK;
}

/* Sites per edge of the simple cubic lattice for n particles: the least m with m^3 >= n. */
static int cubic_side(int n)
{
    int m = (int)cbrt((double)n);
    while ((int64_t)m * m * m < n) {
        m++;
    }
    while (m > 1 && (int64_t)(m - 1) * (m - 1) * (m - 1) >= n) {
        m--;
    }
    return m < 1 ? 1 : m;
}

/* Random sequential addition in 3D: the maximum, and the grid of cells of side >= d it uses. */
#define RANDOM_MAX_PHI_3D 0.3

static int place_random_3d(gr_sim *s, gr_error *err)
{
    const double L = s->L, d = s->d;
    double phi = s->n * M_PI * d * d * d / 6.0 / (L * L * L);
    if (s->rad) { /* species: the actual radii (d the largest diameter, the cells' side) */
        phi = 0.0;
        for (int i = 0; i < s->n; i++) {
            phi += 4.0 / 3.0 * M_PI * s->rad[i] * s->rad[i] * s->rad[i] / (L * L * L);
        }
    }
    if (phi > RANDOM_MAX_PHI_3D * (1.0 + 1e-12)) { /* phi = 0.3 given may come back rounded up */
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [placement] kind = random cannot reach phi = %.3f in 3D: random "
                       "sequential addition jams near 0.38; allowed range (0, %.1f], or kind = "
                       "cubic (phi <= pi/6 = 0.5236)",
                       s->params.source, phi, RANDOM_MAX_PHI_3D);
    }
    int side = (int)floor(L / d);
    const int max_side = (int)ceil(cbrt(2.0 * s->n)) + 1; /* O(N) cells however dilute */
    side = side < max_side ? side : max_side;
    side = side < 3 ? 1 : side; /* fewer than 3 would alias neighbours: one cell, all pairs */
    const double cell = L / side;
    const size_t ncells = (size_t)side * (size_t)side * (size_t)side;
    int *head = malloc(sizeof(int) * ncells), *next = malloc(sizeof(int) * (size_t)(s->n + 1));
    if (!head || !next) {
        free(head);
        free(next);
        return GR_FAIL(err, GR_ENOMEM, "out of memory placing %d particles", s->n);
    }
    for (size_t c = 0; c < ncells; c++) {
        head[c] = -1;
    }
    const int reach = side < 3 ? 0 : 1;
    uint64_t attempt = 0;
    const uint64_t max_attempts = 1000ull * (uint64_t)s->n + 100000ull;
    for (int i = 0; i < s->n; i++) {
        for (;;) {
            if (attempt++ > max_attempts) {
                return no_free_spot(s, i, attempt, "cubic", head, next, err);
            }
            double r[3];
            int cc[3];
            for (int a = 0; a < 3; a++) { /* the placement stream, words 0, 1, 2 */
                const double u =
                    gr_noise_uniform(s->params.seed, GR_STREAM_PLACEMENT, attempt, (uint64_t)a);
                /* along a wall axis ([boundary], walls.c) every centre lies in [r, L - r] */
                r[a] = s->params.walls[a] ? 0.5 * d + (L - d) * u : L * u;
                cc[a] = (int)(r[a] / cell) % side;
            }
            int ok = 1;
            for (int ox = -reach; ox <= reach && ok; ox++) {
                for (int oy = -reach; oy <= reach && ok; oy++) {
                    for (int oz = -reach; oz <= reach && ok; oz++) {
                        const size_t c =
                            (size_t)((cc[0] + ox + side) % side) +
                            (size_t)side * ((size_t)((cc[1] + oy + side) % side) +
                                            (size_t)side * (size_t)((cc[2] + oz + side) % side));
                        for (int j = head[c]; j >= 0 && ok; j = next[j]) {
                            double dx = s->x[j] - r[0], dy = s->y[j] - r[1], dz = s->z[j] - r[2];
                            /* no image across walls */
                            dx -= s->params.walls[0] ? 0.0 : L * rint(dx / L);
                            dy -= s->params.walls[1] ? 0.0 : L * rint(dy / L);
                            dz -= s->params.walls[2] ? 0.0 : L * rint(dz / L);
                            /* species: each pair its own contact distance r_i + r_j <= d */
                            const double dd = s->rad ? s->rad[i] + s->rad[j] : d;
                            ok = dx * dx + dy * dy + dz * dz >= dd * dd;
                        }
                    }
                }
            }
            if (ok) {
                s->x[i] = r[0];
                s->y[i] = r[1];
                s->z[i] = r[2];
                const size_t c =
                    (size_t)cc[0] + (size_t)side * ((size_t)cc[1] + (size_t)side * (size_t)cc[2]);
                next[i] = head[c];
                head[c] = (int)i;
                break;
            }
        }
    }
    free(head);
    free(next);
    return GR_OK;
}

static int place_3d(gr_sim *s, gr_error *err)
{
    switch (s->params.placement) {
    case GR_PLACE_CUBIC: {
        const int m = cubic_side(s->n);
        const double a = s->L / m;
        if (a < s->d) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [placement] kind = cubic: %d particles need %d sites per edge, "
                           "spaced L/%d = %g m, closer than d = %g m (the packing fraction must "
                           "stay below pi/6 N/%d^3 = %.4f; allowed: a larger L or a smaller "
                           "packing_fraction)",
                           s->params.source, s->n, m, m, a, s->d, m,
                           M_PI / 6.0 * s->n / ((double)m * m * m));
        }
        for (int i = 0; i < s->n; i++) {
            s->x[i] = (i % m + 0.5) * a;
            s->y[i] = (i / m % m + 0.5) * a;
            s->z[i] = (i / m / m + 0.5) * a;
        }
        return GR_OK;
    }
    case GR_PLACE_FCC: {
        int m = cubic_side((s->n + 3) / 4);
        const double a = s->L / m;
        if (a / sqrt(2.0) < s->d) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: [placement] kind = fcc: %d particles need %d cells per edge (4 "
                           "sites each), nearest neighbours L/%d/sqrt(2) = %g m apart, closer than "
                           "d = %g m (the packing fraction must stay below 2 pi/3 / sqrt(2) "
                           "N/(4 %d^3) = %.4f; allowed: a larger L or a smaller packing_fraction)",
                           s->params.source, s->n, m, m, a / sqrt(2.0), s->d, m,
                           M_PI / (3.0 * sqrt(2.0)) * s->n / (4.0 * m * m * m));
        }
        static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
        for (int i = 0; i < s->n; i++) {
            const int c = i / 4, b = i % 4;
            s->x[i] = (c % m + basis[b][0] + 0.25) * a;
            s->y[i] = (c / m % m + basis[b][1] + 0.25) * a;
            s->z[i] = (c / m / m + basis[b][2] + 0.25) * a;
        }
        return GR_OK;
    }
    case GR_PLACE_RANDOM: return place_random_3d(s, err);
    default:
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [placement] kind = %s is not available in 3D; allowed: cubic | fcc | "
                       "random",
                       s->params.source, gr_placement_name(s->params.placement));
    }
}

int gr_place(gr_sim *s, gr_error *err)
{
    if (s->dim == 1) {
        return place_1d(s, err);
    }
    if (s->dim == 3) {
        return place_3d(s, err);
    }
    switch (s->params.placement) {
    case GR_PLACE_CUBIC:
    case GR_PLACE_FCC:
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [placement] kind = %s is a 3D lattice; allowed in 2D: "
                       "hexagonal | square | uniform | cluster | random",
                       s->params.source, gr_placement_name(s->params.placement));
    case GR_PLACE_HEXAGONAL: return place_hexagonal(s, err);
    case GR_PLACE_SQUARE: return place_square(s, err);
    case GR_PLACE_UNIFORM: return place_uniform(s, err);
    case GR_PLACE_CLUSTER: return place_cluster(s, err);
    case GR_PLACE_RANDOM: return place_random(s, err);
    }
    return GR_FAIL(err, GR_EINVAL, "unknown placement");
}

/* Track the largest relative overlap (d - r) / d of pair (i, j) under minimum image (2D). */
static inline void consider_pair(const gr_sim *s, int i, int j, double *worst, int *wi, int *wj)
{
    const double L = s->L;
    double dx = s->x[j] - s->x[i], dy = s->y[j] - s->y[i];
    dx -= L * rint(dx / L);
    dy -= L * rint(dy / L);
    const double d = gr_pair_d(s, i, j); /* r_i + r_j with species */
    double ov = (d - sqrt(dx * dx + dy * dy)) / d;
    if (ov > *worst) {
        *worst = ov;
        *wi = i;
        *wj = j;
    }
}

/* 3D: the largest relative overlap, every pair within reach of a cell grid (all pairs below 3
 * cells per edge). */
static int worst_overlap_3d(const gr_sim *s, double *worst, int *wi, int *wj, gr_error *err)
{
    const double L = s->L, d = s->d;
    int side = (int)floor(L / d);
    const int max_side = (int)ceil(cbrt(2.0 * s->n)) + 1;
    side = side < max_side ? side : max_side;
    side = side < 3 ? 1 : side;
    const double cell = L / side;
    const size_t ncells = (size_t)side * side * side;
    int *head = malloc(sizeof(int) * ncells), *next = malloc(sizeof(int) * (size_t)(s->n + 1)),
        *home = malloc(sizeof(int) * 3 * (size_t)(s->n + 1));
    if (!head || !next || !home) {
        free(head);
        free(next);
        free(home);
        return GR_FAIL(err, GR_ENOMEM, "out of memory checking overlaps");
    }
    for (size_t c = 0; c < ncells; c++) {
        head[c] = -1;
    }
    const double *r[3] = {s->x, s->y, s->z};
    for (int i = 0; i < s->n; i++) {
        for (int a = 0; a < 3; a++) {
            const double w = r[a][i] - L * floor(r[a][i] / L);
            int c = (int)(w / cell);
            home[3 * i + a] = c >= side ? side - 1 : (c < 0 ? 0 : c);
        }
        const size_t c = (size_t)home[3 * i] +
                         (size_t)side * ((size_t)home[3 * i + 1] + (size_t)side * home[3 * i + 2]);
        next[i] = head[c];
        head[c] = i;
    }
    const int reach = side < 3 ? 0 : 1;
    for (int i = 0; i < s->n; i++) {
        for (int ox = -reach; ox <= reach; ox++) {
            for (int oy = -reach; oy <= reach; oy++) {
                for (int oz = -reach; oz <= reach; oz++) {
                    const size_t c =
                        (size_t)((home[3 * i] + ox + side) % side) +
                        (size_t)side * ((size_t)((home[3 * i + 1] + oy + side) % side) +
                                        (size_t)side * ((home[3 * i + 2] + oz + side) % side));
                    for (int j = head[c]; j >= 0; j = next[j]) {
                        if (j <= i) {
                            continue;
                        }
                        double dx = s->x[j] - s->x[i], dy = s->y[j] - s->y[i],
                               dz = s->z[j] - s->z[i];
                        dx -= L * rint(dx / L);
                        dy -= L * rint(dy / L);
                        dz -= L * rint(dz / L);
                        const double dij = s->rad ? s->rad[i] + s->rad[j] : d; /* species */
                        const double ov = (dij - sqrt(dx * dx + dy * dy + dz * dz)) / dij;
                        if (ov > *worst) {
                            *worst = ov;
                            *wi = i;
                            *wj = j;
                        }
                    }
                }
            }
        }
    }
    free(head);
    free(next);
    free(home);
    return GR_OK;
}

/* Closest pair by brute force for small N, else via a temporary cell grid. */
int gr_check_overlaps(const gr_sim *s, gr_error *err)
{
    const double tol = 1e-9, d = s->d, L = s->L;
    double worst = 0.0;
    int wi = -1, wj = -1;
    if (s->dim == 3) {
        int rc = worst_overlap_3d(s, &worst, &wi, &wj, err);
        if (rc) {
            return rc;
        }
    } else if (s->dim == 1) {
        for (int i = 0; i < s->n; i++) {
            int j = (i + 1) % s->n;
            double gap = s->x[j] - s->x[i] + (j == 0 ? L : 0.0);
            if (s->n == 1) {
                gap = L;
            }
            if (gap < 0.0) {
                return GR_FAIL(err, GR_EINVAL,
                               "initial state: particles %d and %d are not in order along the line",
                               i, j);
            }
            double ov = (gr_pair_d(s, i, j) - gap) / gr_pair_d(s, i, j);
            if (ov > worst) {
                worst = ov;
                wi = i;
                wj = j;
            }
        }
    } else {
        int side = (int)floor(L / d);
        const int max_side = (int)ceil(sqrt(2.0 * s->n)) + 1; /* O(N) cells however dilute */
        side = side < max_side ? side : max_side;
        if (side < 3 || (long)s->n * s->n < 4000000L) {
            for (int i = 0; i < s->n; i++) {
                for (int j = i + 1; j < s->n; j++) {
                    consider_pair(s, i, j, &worst, &wi, &wj);
                }
            }
        } else {
            double cell = L / side;
            int *head = malloc(sizeof(int) * (size_t)side * (size_t)side),
                *next = malloc(sizeof(int) * (size_t)s->n);
            if (!head || !next) {
                free(head);
                free(next);
                return GR_FAIL(err, GR_ENOMEM, "out of memory checking overlaps");
            }
            for (int c = 0; c < side * side; c++) {
                head[c] = -1;
            }
            for (int i = 0; i < s->n; i++) {
                int cx = (int)(s->x[i] / cell) % side, cy = (int)(s->y[i] / cell) % side;
                int c = cx + side * cy;
                next[i] = head[c];
                head[c] = i;
            }
            for (int i = 0; i < s->n; i++) {
                int cx = (int)(s->x[i] / cell) % side, cy = (int)(s->y[i] / cell) % side;
                for (int ox = -1; ox <= 1; ox++) {
                    for (int oy = -1; oy <= 1; oy++) {
                        int c = ((cx + ox + side) % side) + side * ((cy + oy + side) % side);
                        for (int j = head[c]; j >= 0; j = next[j]) {
                            if (j > i) {
                                consider_pair(s, i, j, &worst, &wi, &wj);
                            }
                        }
                    }
                }
            }
            free(head);
            free(next);
        }
    }
    if (worst > tol) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: initial state overlaps: particles %d and %d overlap by %.3g d (tolerance %g d); "
            "refusing to start (the spring energy would explode the packing)",
            s->params.source, wi, wj, worst, tol);
    }
    return GR_OK;
}
