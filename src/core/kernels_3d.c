/* Spheres in a periodic cube ([system] dim = 3, docs/three-dimensions.md): the neighbour list and
 * the generic 3D force kernel.
 *
 * Neighbours. A cell list with cells of side >= cutoff = d (1 + skin) (at most about 2 cells per
 * particle) feeds a half Verlet list in the CSR arrays the 2D list uses (nl_start, nl_j,
 * nl_contact): row i lists every j > i closer than the cutoff, found in the 27 cells around i's
 * (so each pair once, from its lower index; the rows are in particle order and each row in a
 * fixed cell order, so the list is a pure function of the positions). Fewer than 3 cells per
 * edge would alias neighbour cells: then every pair is checked. The list is rebuilt when some
 * particle has moved skin/2 since the last build (verlet/step.c), as in 2D.
 *
 * Kernel. For a listed pair i < j at overlap xi = d - |r_ij| > 0, n = r_ij / |r_ij| (from i to
 * j), g = v_j - v_i, g_n = g.n: the normal law (the same always-inline normal_law as in 1D and
 * 2D, core/kernel_laws.h) gives f_n and its non-conservative part f_d; the force on j is f_n n, on
 * i its opposite, and G = f_d n is kept apart for the ledger (it dissipates -f_d g_n). No
 * tangential law, rotation or rolling yet: the scene and gr_sim_new refuse them in 3D. One
 * instance, the laws read from the simulation (a branch per pair on the law, no indirect call);
 * one thread, forces summed in list order, so a run is the same for every thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/kernel_laws.h"

int gr_neighbours_alloc_3d(gr_sim *s, gr_error *err)
{
    const int n = s->n;
    s->cutoff = s->d * (1.0 + s->params.skin);
    const double side = floor(s->L / s->cutoff);
    const int max_side = (int)ceil(cbrt(2.0 * n)) + 1; /* more cells only cost memory and time */
    const int nc = side >= 3.0 ? (side < max_side ? (int)side : (max_side >= 3 ? max_side : 3)) : 0;
    s->ncell = nc;
    const size_t ncells = nc ? (size_t)nc * nc * nc : 1;
    s->cell_start = calloc(2 * (ncells + 1), sizeof(int)); /* second half: fill pointers */
    s->cell_of = malloc(sizeof(int) * (size_t)(n + 1));
    s->cell_order = malloc(sizeof(int) * (size_t)(n + 1));
    s->nl_start = calloc((size_t)n + 1, sizeof(int));
    s->x_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->y_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->z_ref = malloc(sizeof(double) * (size_t)(n + 1));
    s->nl_cap = 16 * (int64_t)n + 64;
    s->nl_j = malloc(sizeof(int) * (size_t)s->nl_cap);
    s->nl_contact = calloc((size_t)s->nl_cap, 1);
    if (!s->cell_start || !s->cell_of || !s->cell_order || !s->nl_start || !s->x_ref || !s->y_ref ||
        !s->z_ref || !s->nl_j || !s->nl_contact) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the neighbour list of %d spheres", n);
    }
    return GR_OK;
}

/* Room for `need` entries of the list. */
static int reserve(gr_sim *s, int64_t need, gr_error *err)
{
    if (need <= s->nl_cap) {
        return GR_OK;
    }
    const int64_t cap = need + need / 2;
    int *j = realloc(s->nl_j, sizeof(int) * (size_t)cap);
    uint8_t *c = j ? realloc(s->nl_contact, (size_t)cap) : NULL;
    if (j) {
        s->nl_j = j;
    }
    if (!c) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory growing the neighbour list to %lld pairs",
                       (long long)cap);
    }
    s->nl_contact = c;
    s->nl_cap = cap;
    return GR_OK;
}

/* Append pair (i, j) if closer than the cutoff, with its contact flag: whether it overlapped at
 * the last force evaluation, one drift ago (r - g dt), so a contact that begins in the step of a
 * rebuild is still counted as new. */
static inline int consider(gr_sim *s, const int i, const int j, int64_t *count, gr_error *err)
{
    const double L = s->L, rc2 = s->cutoff * s->cutoff, d2 = s->d * s->d;
    const double dx = wrap_delta(s->x[j] - s->x[i], L), dy = wrap_delta(s->y[j] - s->y[i], L),
                 dz = wrap_delta(s->z[j] - s->z[i], L);
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= rc2) {
        return GR_OK;
    }
    int rc = reserve(s, *count + 1, err);
    if (rc) {
        return rc;
    }
    int touching = r2 < d2;
    if (s->step > 0) {
        const double dt = s->dt, px = dx - (s->vx[j] - s->vx[i]) * dt,
                     py = dy - (s->vy[j] - s->vy[i]) * dt, pz = dz - (s->vz[j] - s->vz[i]) * dt;
        touching = px * px + py * py + pz * pz < d2;
    }
    s->nl_contact[*count] = (uint8_t)touching;
    s->nl_j[(*count)++] = j;
    return GR_OK;
}

/* Put every coordinate into [0, L) (a particle that moved out of the box in one step) and refuse
 * non-finite ones. */
static int wrap_positions(gr_sim *s, gr_error *err)
{
    const double L = s->L;
    double *r[3] = {s->x, s->y, s->z};
    for (int i = 0; i < s->n; i++) {
        for (int a = 0; a < 3; a++) {
            double *q = &r[a][i];
            if (*q >= 0.0 && *q < L) {
                continue;
            }
            if (!isfinite(*q)) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "unstable run: particle %d has a non-finite position (%g, %g, %g) "
                               "at step %lld",
                               i, s->x[i], s->y[i], s->z[i], (long long)s->step);
            }
            const double q0 = *q;
            *q -= L * floor(*q / L);
            *q = *q >= L ? 0.0 : *q;
            if (!(*q >= 0.0)) {
                return GR_FAIL(err, GR_EUNSTABLE,
                               "unstable run: particle %d moved %g box lengths in one step, at "
                               "step %lld",
                               i, fabs(q0) / L, (long long)s->step);
            }
        }
    }
    return GR_OK;
}

int gr_neighbours_build_3d(gr_sim *s, gr_error *err)
{
    const int n = s->n, nc = s->ncell;
    int64_t count = 0;
    int rc = wrap_positions(s, err);
    if (rc) {
        return rc;
    }
    if (nc == 0) {
        for (int i = 0; i < n; i++) {
            s->nl_start[i] = (int)count;
            for (int j = i + 1; j < n && !rc; j++) {
                rc = consider(s, i, j, &count, err);
            }
        }
    } else {
        /* counting sort of the particles by cell (x fastest, then y, then z) */
        const double inv = nc / s->L;
        const size_t ncells = (size_t)nc * nc * nc;
        int *start = s->cell_start, *fill = s->cell_start + ncells + 1;
        memset(start, 0, sizeof(int) * (ncells + 1));
        for (int i = 0; i < n; i++) {
            int c[3] = {(int)(s->x[i] * inv), (int)(s->y[i] * inv), (int)(s->z[i] * inv)};
            for (int a = 0; a < 3; a++) {
                c[a] = c[a] >= nc ? nc - 1 : c[a];
            }
            s->cell_of[i] = c[0] + nc * (c[1] + nc * c[2]);
            start[s->cell_of[i] + 1]++;
        }
        for (size_t c = 0; c < ncells; c++) {
            start[c + 1] += start[c];
        }
        memcpy(fill, start, sizeof(int) * ncells);
        for (int i = 0; i < n; i++) {
            s->cell_order[fill[s->cell_of[i]]++] = i;
        }
        for (int i = 0; i < n && !rc; i++) {
            s->nl_start[i] = (int)count;
            const int ci = s->cell_of[i], cx = ci % nc, cy = ci / nc % nc, cz = ci / nc / nc;
            for (int oz = -1; oz <= 1 && !rc; oz++) {
                for (int oy = -1; oy <= 1 && !rc; oy++) {
                    for (int ox = -1; ox <= 1 && !rc; ox++) {
                        const int c = (cx + ox + nc) % nc +
                                      nc * ((cy + oy + nc) % nc + nc * ((cz + oz + nc) % nc));
                        for (int k = start[c]; k < start[c + 1] && !rc; k++) {
                            const int j = s->cell_order[k];
                            if (j > i) {
                                rc = consider(s, i, j, &count, err);
                            }
                        }
                    }
                }
            }
        }
    }
    if (rc) {
        return rc;
    }
    s->nl_start[n] = (int)count;
    memcpy(s->x_ref, s->x, sizeof(double) * (size_t)n);
    memcpy(s->y_ref, s->y, sizeof(double) * (size_t)n);
    memcpy(s->z_ref, s->z, sizeof(double) * (size_t)n);
    s->rebuilds++;
    return GR_OK;
}

void gr_kernel_run_3d(gr_sim *s, gr_force_report *r)
{
    const int n = s->n, nl = s->kernel.nl, clamp = s->kernel.clamp;
    const double L = s->L, d = s->d, d2 = d * d;
    const gr_contact_coeffs cc = s->cc;
    const double *restrict x = s->x, *restrict y = s->y, *restrict z = s->z;
    const double *restrict vx = s->vx, *restrict vy = s->vy, *restrict vz = s->vz;
    double *restrict fx = s->fx, *restrict fy = s->fy, *restrict fz = s->fz;
    double *restrict gx = s->gx, *restrict gy = s->gy, *restrict gz = s->gz;
    const int *restrict start = s->nl_start, *restrict list = s->nl_j;
    uint8_t *restrict touching = s->nl_contact;
    const size_t bytes = sizeof(double) * (size_t)n;
    memset(fx, 0, bytes);
    memset(fy, 0, bytes);
    memset(fz, 0, bytes);
    memset(gx, 0, bytes);
    memset(gy, 0, bytes);
    memset(gz, 0, bytes);
    double elastic = 0.0, pn = 0.0, worst = 0.0;
    int64_t fresh = 0;
    int wi = -1, wj = -1;
    for (int i = 0; i < n; i++) {
        double fxi = 0.0, fyi = 0.0, fzi = 0.0, gxi = 0.0, gyi = 0.0, gzi = 0.0;
        for (int p = start[i]; p < start[i + 1]; p++) {
            const int j = list[p];
            const double dx = wrap_delta(x[j] - x[i], L), dy = wrap_delta(y[j] - y[i], L),
                         dz = wrap_delta(z[j] - z[i], L);
            const double r2 = dx * dx + dy * dy + dz * dz;
            if (r2 >= d2) {
                touching[p] = 0;
                continue;
            }
            const double dist = sqrt(r2), inv = 1.0 / dist;
            const double nx = dx * inv, ny = dy * inv, nz = dz * inv, ov = d - dist;
            const double g_n = (vx[j] - vx[i]) * nx + (vy[j] - vy[i]) * ny + (vz[j] - vz[i]) * nz;
            const gr_normal_force fn = normal_law(nl, &cc, ov, g_n, clamp);
            fresh += !touching[p];
            touching[p] = 1;
            elastic += fn.e;
            pn -= fn.f_d * g_n;
            if (ov > worst) {
                worst = ov;
                wi = i;
                wj = j;
            }
            const double Fx = fn.f * nx, Fy = fn.f * ny, Fz = fn.f * nz;
            const double Gx = fn.f_d * nx, Gy = fn.f_d * ny, Gz = fn.f_d * nz;
            fxi -= Fx;
            fyi -= Fy;
            fzi -= Fz;
            gxi -= Gx;
            gyi -= Gy;
            gzi -= Gz;
            fx[j] += Fx;
            fy[j] += Fy;
            fz[j] += Fz;
            gx[j] += Gx;
            gy[j] += Gy;
            gz[j] += Gz;
        }
        fx[i] += fxi;
        fy[i] += fyi;
        fz[i] += fzi;
        gx[i] += gxi;
        gy[i] += gyi;
        gz[i] += gzi;
    }
    *r = (gr_force_report){.elastic = cc.e_scale * elastic,
                           .power_normal = pn,
                           .new_contacts = fresh,
                           .max_overlap = worst / d,
                           .worst_i = wi,
                           .worst_j = wj};
}
