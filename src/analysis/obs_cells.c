/* Pairs closer than a cut-off in one frame (see obs_cells.h). */
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_cells.h"
#include "analysis/obs_util.h"

static double wrap(double x, double L)
{
    double w = x - L * floor(x / L);
    return w >= L ? 0.0 : w;
}

static double min_image(double dx, double L) { return dx - L * rint(dx / L); }

static void visit_pair(const gr_particles *p, int i, int j, double r_cut, gr_pair_visit visit,
                       void *user)
{
    double dx = min_image(p->x[j] - p->x[i], p->L);
    double dy = p->dim >= 2 ? min_image(p->y[j] - p->y[i], p->L) : 0.0;
    double dz = p->dim == 3 ? min_image(p->z[j] - p->z[i], p->L) : 0.0;
    double r2 = p->dim == 3 ? dx * dx + dy * dy + dz * dz : dx * dx + dy * dy;
    if (r2 < r_cut * r_cut) {
        const double dr[3] = {dx, dy, dz};
        visit(i, j, dr, r2, user);
    }
}

int gr_cells_pairs(gr_cells *c, const gr_particles *p, double r_cut, gr_pair_visit visit,
                   void *user, gr_error *err)
{
    const int n = p->n;
    /* cells of side L/s >= r_cut, at most about 2 n of them (larger cells are
     * still correct) */
    const int cap = p->dim == 3   ? (int)cbrt(2.0 * n) + 1
                    : p->dim == 2 ? (int)sqrt(2.0 * n) + 1
                                  : 2 * n + 1;
    const double fit = floor(p->L / r_cut);
    const int s = fit < cap ? (int)fit : cap;
    if (s < 3) {
        for (int i = 0; i < n; i++) {
            for (int j = i + 1; j < n; j++) {
                visit_pair(p, i, j, r_cut, visit, user);
            }
        }
        return GR_OK;
    }
    const int ncell = p->dim == 3 ? s * s * s : p->dim == 2 ? s * s : s;
    if (c->cap_n < n || c->cap_cells < ncell) {
        free(c->head);
        free(c->next);
        c->head = malloc(sizeof(int) * (size_t)ncell);
        c->next = malloc(sizeof(int) * (size_t)n);
        c->cap_n = c->next ? n : 0;
        c->cap_cells = c->head ? ncell : 0;
        if (!c->head || !c->next) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %d cells", ncell);
        }
    }
    for (int k = 0; k < ncell; k++) {
        c->head[k] = -1;
    }
    int *cx = malloc(sizeof(int) * 3 * (size_t)n);
    if (!cx) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d particles", n);
    }
    for (int i = 0; i < n; i++) {
        int a = (int)(wrap(p->x[i], p->L) / p->L * s),
            b = p->dim >= 2 ? (int)(wrap(p->y[i], p->L) / p->L * s) : 0,
            e = p->dim == 3 ? (int)(wrap(p->z[i], p->L) / p->L * s) : 0;
        a = a >= s ? s - 1 : a;
        b = b >= s ? s - 1 : b;
        e = e >= s ? s - 1 : e;
        cx[3 * i] = a;
        cx[3 * i + 1] = b;
        cx[3 * i + 2] = e;
        int k = (e * s + b) * s + a;
        c->next[i] = c->head[k];
        c->head[k] = i;
    }
    /* half stencil: the cell itself (j > i) and the forward neighbours (in 3D the 13 of the 26
     * that come after the cell in z, y, x order) */
    static const int st3[14][3] = {{0, 0, 0},   {1, 0, 0},  {-1, 1, 0}, {0, 1, 0},  {1, 1, 0},
                                   {-1, -1, 1}, {0, -1, 1}, {1, -1, 1}, {-1, 0, 1}, {0, 0, 1},
                                   {1, 0, 1},   {-1, 1, 1}, {0, 1, 1},  {1, 1, 1}};
    const int nst = p->dim == 3 ? 14 : p->dim == 2 ? 5 : 2; /* st3's first 5 (2) are 2D's (1D's) */
    for (int i = 0; i < n; i++) {
        for (int q = 0; q < nst; q++) {
            const int *o = st3[q];
            int a = (cx[3 * i] + o[0] + s) % s, b = (cx[3 * i + 1] + o[1] + s) % s,
                e = (cx[3 * i + 2] + o[2] + s) % s;
            for (int j = c->head[(e * s + b) * s + a]; j >= 0; j = c->next[j]) {
                if (q > 0 || j > i) {
                    visit_pair(p, i, j, r_cut, visit, user);
                }
            }
        }
    }
    free(cx);
    return GR_OK;
}

void gr_cells_free(gr_cells *c)
{
    free(c->head);
    free(c->next);
    c->head = c->next = NULL;
    c->cap_n = c->cap_cells = 0;
}

static void release(void *c) { gr_cells_free(c); }

void gr_cells_own(void *state, gr_cells *c) { gr_obs_own(state, release, c); }
