/* LAMMPS text dumps (dump custom) as granule frames: the ITEM: blocks TIMESTEP, NUMBER OF ATOMS,
 * BOX BOUNDS and ATOMS <columns>, repeated once per frame (docs/lammps.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/files.h"
#include "io/lammps_dump.h"

struct gr_lammps_dump {
    FILE *in;
    char path[1024];
    long line;
    char buf[4096];
    long long last_step; /* the timestep of the last frame read (frames > 0) */
    int wall_axis;       /* the frame's axis read unwrapped (a floor below 0), or -1 */
    long frames;
    int dim3; /* the scene is 3D: z and vz are read too */
};

enum { C_ID, C_X, C_Y, C_Z, C_VX, C_VY, C_VZ, C_N };

int gr_lammps_dump_open(const char *path, int dim, gr_lammps_dump **out, gr_error *err)
{
    gr_lammps_dump *d = calloc(1, sizeof *d);
    if (!d) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    int rc = gr_input_open(path, "LAMMPS dump", &d->in, err);
    if (rc) {
        free(d);
        return rc;
    }
    snprintf(d->path, sizeof d->path, "%s", path);
    d->dim3 = dim == 3;
    *out = d;
    return GR_OK;
}

void gr_lammps_dump_close(gr_lammps_dump *d)
{
    if (d) {
        fclose(d->in);
        free(d);
    }
}

static bool next_line(gr_lammps_dump *d)
{
    d->line++;
    return fgets(d->buf, sizeof d->buf, d->in) != NULL;
}

/* The next line must start with `item`; then the line after it is read. */
static int expect(gr_lammps_dump *d, const char *item, gr_error *err)
{
    if (!next_line(d) || strncmp(d->buf, item, strlen(item)) != 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: expected \"%s\" (a LAMMPS text dump of dump custom)", d->path,
                       d->line, item);
    }
    return GR_OK;
}

/* Column index of each field in the ATOMS header (-1 when absent); scaled[k] for xs/ys. */
static int columns(gr_lammps_dump *d, int col[C_N], bool scaled[C_N], int *ncol, gr_error *err)
{
    static const char *const names[C_N][3] = {
        {"id", NULL, NULL}, {"x", "xu", "xs"},  {"y", "yu", "ys"}, {"z", "zu", "zs"},
        {"vx", NULL, NULL}, {"vy", NULL, NULL}, {"vz", NULL, NULL}};
    for (int k = 0; k < C_N; k++) {
        col[k] = -1;
        scaled[k] = false;
    }
    char *save = NULL;
    int c = 0;
    for (char *tok = strtok_r(d->buf + strlen("ITEM: ATOMS"), " \t\r\n", &save); tok;
         tok = strtok_r(NULL, " \t\r\n", &save), c++) {
        for (int k = 0; k < C_N; k++) {
            for (int a = 0; a < 3; a++) {
                if (names[k][a] && !strcmp(tok, names[k][a]) && col[k] < 0) {
                    col[k] = c;
                    scaled[k] = a == 2;
                }
            }
        }
    }
    *ncol = c;
    if (d->dim3 && (col[C_ID] < 0 || col[C_X] < 0 || col[C_Y] < 0 || col[C_Z] < 0 ||
                    col[C_VX] < 0 || col[C_VY] < 0 || col[C_VZ] < 0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: the ATOMS columns of a 3D scene need id, x, y, z, vx, vy, vz; dump "
                       "custom ... id x y z vx vy vz",
                       d->path, d->line);
    }
    if (col[C_ID] < 0 || col[C_X] < 0 || col[C_VX] < 0 || (col[C_Y] < 0) != (col[C_VY] < 0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: the ATOMS columns need id, x, vx (and y, vy in 2D); dump custom "
                       "... id x y vx vy",
                       d->path, d->line);
    }
    return GR_OK;
}

static int frame_alloc(gr_frame *f, long n, int dim, const char *path, gr_error *err)
{
    f->n = (int)n;
    f->dim = dim;
    f->x = calloc((size_t)n, sizeof(double));
    f->vx = calloc((size_t)n, sizeof(double));
    f->y = dim >= 2 ? calloc((size_t)n, sizeof(double)) : NULL;
    f->vy = dim >= 2 ? calloc((size_t)n, sizeof(double)) : NULL;
    f->z = dim == 3 ? calloc((size_t)n, sizeof(double)) : NULL;
    f->vz = dim == 3 ? calloc((size_t)n, sizeof(double)) : NULL;
    if (!f->x || !f->vx || (dim >= 2 && (!f->y || !f->vy)) || (dim == 3 && (!f->z || !f->vz))) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory for %ld particles", path, n);
    }
    return GR_OK;
}

static int read_atoms(gr_lammps_dump *d, gr_frame *f, const double lo[3], const double len[3],
                      gr_error *err)
{
    int col[C_N], ncol;
    bool scaled[C_N];
    int rc = columns(d, col, scaled, &ncol, err);
    if (rc) {
        return rc;
    }
    const int dim = d->dim3 ? 3 : col[C_Y] >= 0 ? 2 : 1;
    long n = f->n;
    rc = frame_alloc(f, n, dim, d->path, err);
    if (rc) {
        return rc;
    }
    char *seen = calloc((size_t)n, 1);
    if (!seen) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    double v[64];
    for (long a = 0; a < n && !rc; a++) {
        if (!next_line(d)) {
            rc = GR_FAIL(err, GR_EINVAL, "%s: truncated frame: %ld of %ld atoms", d->path, a, n);
            break;
        }
        char *p = d->buf, *end;
        int got = 0;
        for (; got < ncol && got < 64; got++, p = end) {
            v[got] = strtod(p, &end);
            if (end == p) {
                break;
            }
        }
        long id = got > col[C_ID] ? (long)v[col[C_ID]] : 0;
        if (got < ncol || id < 1 || id > n || seen[id - 1]) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%ld: expected %d numbers with a new atom id in 1..%ld",
                         d->path, d->line, ncol, n);
            break;
        }
        seen[id - 1] = 1;
        double *pos[3] = {f->x, f->y, f->z}, *vel[3] = {f->vx, f->vy, f->vz};
        for (int k = 0; k < dim; k++) {
            double x = v[col[C_X + k]];
            if (k == d->wall_axis) { /* a wall axis reaching below 0: absolute, not wrapped */
                x = scaled[C_X + k] ? lo[k] + x * len[k] : x;
                pos[k][id - 1] = x;
            } else {
                x = scaled[C_X + k] ? x * len[k] : x - lo[k];
                x -= len[k] * floor(x / len[k]);
                pos[k][id - 1] = x >= len[k] ? 0.0 : x;
            }
            vel[k][id - 1] = v[col[C_VX + k]];
            if (!isfinite(x) || !isfinite(vel[k][id - 1])) {
                rc = GR_FAIL(err, GR_EINVAL, "%s:%ld: non-finite position or velocity", d->path,
                             d->line);
            }
        }
    }
    free(seen);
    if (rc) {
        gr_frame_free(f);
    }
    return rc;
}

int gr_lammps_dump_next(gr_lammps_dump *d, double dt, gr_frame *f, gr_error *err)
{
    memset(f, 0, sizeof *f);
    if (!next_line(d)) {
        return 0;
    }
    long long step;
    long n;
    if (strncmp(d->buf, "ITEM: TIMESTEP", 14) != 0 || !next_line(d) ||
        sscanf(d->buf, "%lld", &step) != 1) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s:%ld: expected \"ITEM: TIMESTEP\" and the step (a LAMMPS text dump of dump custom)",
            d->path, d->line);
    }
    if (step < 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: timestep %lld is negative (LAMMPS counts steps from 0)", d->path,
                       d->line, step);
    }
    if (d->frames > 0 && step <= d->last_step) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s:%ld: timestep %lld does not follow the previous frame's %lld: frames must be in "
            "increasing time order",
            d->path, d->line, step, d->last_step);
    }
    int rc = expect(d, "ITEM: NUMBER OF ATOMS", err);
    if (rc) {
        return rc;
    }
    if (!next_line(d) || sscanf(d->buf, "%ld", &n) != 1 || n < 1 || n > 100000000L) {
        return GR_FAIL(err, GR_EINVAL, "%s:%ld: expected the number of atoms", d->path, d->line);
    }
    rc = expect(d, "ITEM: BOX BOUNDS", err);
    if (rc) {
        return rc;
    }
    if (strstr(d->buf, "xy")) {
        return GR_FAIL(err, GR_EINVAL, "%s:%ld: a triclinic box; granule's boxes are square",
                       d->path, d->line);
    }
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        if (!next_line(d) || sscanf(d->buf, "%lf %lf", &lo[k], &hi[k]) != 2 || !(hi[k] > lo[k])) {
            return GR_FAIL(err, GR_EINVAL, "%s:%ld: expected the box bounds lo hi", d->path,
                           d->line);
        }
    }
    const double len[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    /* `granule export lammps` of a floor vibrating below 0 by more than a radius writes that
     * wall axis as [-(A + d), L] and the other as [0, L]: read it as the square box of side L */
    d->wall_axis = -1;
    for (int k = 0; k < 2 && !d->dim3; k++) {
        const double side = hi[1 - k] - lo[1 - k];
        if (lo[k] < 0.0 && lo[1 - k] == 0.0 && fabs(hi[k] - side) <= 1e-9 * side) {
            d->wall_axis = k;
        }
    }
    rc = expect(d, "ITEM: ATOMS", err);
    if (rc) {
        return rc;
    }
    f->n = (int)n;
    rc = read_atoms(d, f, lo, len, err);
    if (rc) {
        return rc;
    }
    if (f->dim == 3 &&
        (fabs(len[0] - len[1]) > 1e-9 * len[0] || fabs(len[0] - len[2]) > 1e-9 * len[0])) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_EINVAL, "%s: box %g x %g x %g is not a cube (a 3D scene's box)",
                       d->path, len[0], len[1], len[2]);
    }
    if (f->dim == 2 && d->wall_axis < 0 && fabs(len[0] - len[1]) > 1e-9 * len[0]) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_EINVAL,
                       "%s: box %g x %g is not square (nor a square box whose wall axis reaches "
                       "below 0, as granule export lammps writes for a vibrating floor)",
                       d->path, len[0], len[1]);
    }
    f->L = d->wall_axis == 0 ? len[1] : len[0];
    f->t = (double)step * dt;
    d->last_step = step;
    d->frames++;
    return 1;
}
