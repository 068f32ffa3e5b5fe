/* Snapshots in extended XYZ (ASE 3.22, OVITO, MDAnalysis and granule read them; the layout and
 * what each reader makes of a 2D or 1D box are in docs/trajectories.md). One frame per file
 * (written atomically) or many frames in one file (src/io/trajectory.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/files.h"
#include "io/snapshot.h"

void gr_xyz_write_frame(FILE *f, const gr_particles *p, double t, int64_t step)
{
    const double d = 2.0 * p->radius;
    if (p->dim == 3) { /* spheres in a periodic cube: the same columns, z and vz their own */
        fprintf(f,
                "%d\nLattice=\"%.17g 0 0 0 %.17g 0 0 0 %.17g\" pbc=\"T T T\" Time=%.17g "
                "Step=%lld "
                "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:masses:R:1:momenta:R:3%s%s\n",
                p->n, p->L, p->L, p->L, t, (long long)step, p->species ? ":species_index:I:1" : "",
                p->wz ? ":omega:R:3" : "");
        for (int i = 0; i < p->n; i++) {
            const double x = p->x[i] - p->L * floor(p->x[i] / p->L),
                         y = p->y[i] - p->L * floor(p->y[i] / p->L),
                         z = p->z[i] - p->L * floor(p->z[i] / p->L);
            /* species: each grain's own radius and mass, and its species 1, 2, ... (as 2D) */
            const double r = p->radii ? p->radii[i] : p->radius,
                         m = p->masses ? p->masses[i] : p->mass;
            fprintf(f, "X %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", x, y,
                    z, p->vx[i], p->vy[i], p->vz[i], r, m, m * p->vx[i], m * p->vy[i],
                    m * p->vz[i]);
            if (p->species) {
                fprintf(f, " %d", p->species[i] + 1);
            }
            if (p->wz) { /* rotation: the spin vector, rad/s */
                fprintf(f, " %.17g %.17g %.17g", p->wx[i], p->wy[i], p->wz[i]);
            }
            fputc('\n', f);
        }
        return;
    }
    const double Ly = p->dim == 2 ? p->L : d;
    fprintf(f,
            "%d\nLattice=\"%.17g 0 0 0 %.17g 0 0 0 %.17g\" pbc=\"T %s F\" Time=%.17g Step=%lld "
            "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:masses:R:1:momenta:R:3%s%s\n",
            p->n, p->L, Ly, d, p->dim == 2 ? "T" : "F", t, (long long)step,
            p->omega ? ":omega:R:3" : "", p->species ? ":species_index:I:1" : "");
    for (int i = 0; i < p->n; i++) {
        const double x = p->x[i] - p->L * floor(p->x[i] / p->L);
        const double y = p->dim == 2 ? p->y[i] : 0.5 * d;
        const double vy = p->dim == 2 ? p->vy[i] : 0.0;
        /* species (docs/mixtures.md): each grain's own radius and mass, and its species 1, 2, ... */
        const double r = p->radii ? p->radii[i] : p->radius, m = p->masses ? p->masses[i] : p->mass;
        fprintf(f, "X %.17g %.17g %.17g %.17g %.17g 0 %.17g %.17g %.17g %.17g 0", x, y, 0.5 * d,
                p->vx[i], vy, r, m, m * p->vx[i], m * vy);
        if (p->species) {
            fprintf(f, " %d", p->species[i] + 1);
        }
        if (p->omega) {
            fprintf(f, " 0 0 %.17g",
                    p->omega[i]); /* rotation: the angular velocity about z, rad/s */
        }
        fputc('\n', f);
    }
}

int gr_snapshot_write(const char *dir, int index, const gr_particles *p, double t, int64_t step,
                      gr_error *err)
{
    char name[64];
    snprintf(name, sizeof name, "snap_%06d.xyz", index);
    gr_file f;
    int rc = gr_file_open(&f, dir, name, err);
    if (rc) {
        return rc;
    }
    gr_xyz_write_frame(f.f, p, t, step);
    return gr_file_commit(&f, err);
}

void gr_frame_free(gr_frame *f)
{
    free(f->x);
    free(f->y);
    free(f->vx);
    free(f->vy);
    free(f->z);
    free(f->vz);
    free(f->species);
    free(f->radii);
    free(f->masses);
    f->x = f->y = f->vx = f->vy = f->z = f->vz = NULL;
    f->species = NULL;
    f->radii = f->masses = NULL;
}

int gr_frame_alloc(gr_frame *f, int n, int dim, gr_error *err)
{
    f->species = NULL;
    f->radii = f->masses = NULL;
    f->n_species = 0;
    f->n = n;
    f->dim = dim;
    f->x = malloc(sizeof(double) * (size_t)n);
    f->vx = malloc(sizeof(double) * (size_t)n);
    f->y = dim >= 2 ? malloc(sizeof(double) * (size_t)n) : NULL;
    f->vy = dim >= 2 ? malloc(sizeof(double) * (size_t)n) : NULL;
    f->z = dim == 3 ? malloc(sizeof(double) * (size_t)n) : NULL;
    f->vz = dim == 3 ? malloc(sizeof(double) * (size_t)n) : NULL;
    if (!f->x || !f->vx || (dim >= 2 && (!f->y || !f->vy)) || (dim == 3 && (!f->z || !f->vz))) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_ENOMEM, "out of memory for a frame of %d particles", n);
    }
    return GR_OK;
}

/* Columns of the Properties we need: first column of pos, velo, momenta, masses, radius (-1 if
 * absent) and the total number of columns. */
typedef struct xyz_columns {
    int pos, velo, momenta, masses, radius, species, total;
} xyz_columns;

static int parse_properties(const char *line, xyz_columns *c)
{
    *c = (xyz_columns){-1, -1, -1, -1, -1, -1, 0};
    const char *p = strstr(line, "Properties=");
    if (!p) {
        return -1;
    }
    p += 11;
    while (*p && *p != ' ' && *p != '\n' && *p != '\r') {
        char name[64], type[8];
        int count = 0, used = 0;
        if (sscanf(p, "%63[^:]:%7[^:]:%d%n", name, type, &count, &used) != 3 || count < 1) {
            return -1;
        }
        int *slot = !strcmp(name, "pos")             ? &c->pos
                    : !strcmp(name, "velo")          ? &c->velo
                    : !strcmp(name, "momenta")       ? &c->momenta
                    : !strcmp(name, "masses")        ? &c->masses
                    : !strcmp(name, "radius")        ? &c->radius
                    : !strcmp(name, "species_index") ? &c->species
                                                     : NULL;
        if (slot) {
            *slot = c->total;
        }
        c->total += count;
        p += used + (p[used] == ':');
    }
    return c->pos >= 0 && (c->velo >= 0 || (c->momenta >= 0 && c->masses >= 0)) && c->total <= 64
               ? 0
               : -1;
}

int gr_xyz_read_frame(FILE *in, const char *path, long *line_no, gr_frame *f, gr_error *err)
{
    memset(f, 0, sizeof *f);
    char line[4096];
    long n = 0;
    if (!fgets(line, sizeof line, in)) {
        return 1;
    }
    ++*line_no;
    if (sscanf(line, "%ld", &n) != 1 || n < 1 || n > 100000000L) {
        return GR_FAIL(err, GR_EINVAL, "%s:%ld: expected the particle count", path, *line_no);
    }
    if (!fgets(line, sizeof line, in)) {
        return GR_FAIL(err, GR_EINVAL, "%s:%ld: missing comment line", path, *line_no + 1);
    }
    ++*line_no;
    double lx = 0, dummy;
    const char *lat = strstr(line, "Lattice=\""), *tm = strstr(line, "Time="),
               *pbc = strstr(line, "pbc=\"");
    xyz_columns c;
    if (!lat || sscanf(lat + 9, "%lf %lf", &lx, &dummy) != 2 || !(lx > 0.0) ||
        parse_properties(line, &c) != 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: not a granule extended-XYZ frame (need Lattice and Properties with "
                       "pos and velo, or momenta and masses)",
                       path, *line_no);
    }
    char *tend = NULL;
    const double t = tm ? strtod(tm + 5, &tend) : 0.0;
    if (!tm || tend == tm + 5 || (*tend && !strchr(" \t\r\n", *tend)) || !isfinite(t)) {
        char word[40] = "";
        if (tm) {
            snprintf(word, sizeof word, "%.*s", (int)strcspn(tm, " \t\r\n"), tm);
        }
        return GR_FAIL(err, GR_EINVAL,
                       "%s:%ld: %s%s: every frame needs its time as Time=SECONDS, a finite number",
                       path, *line_no, tm ? word : "no Time= on the comment line",
                       tm ? " is not a finite time" : "");
    }
    const int dim = pbc && strncmp(pbc + 5, "T T T", 5) == 0 ? 3 /* granule's 3D frames (spheres) */
                    : pbc && strncmp(pbc + 5, "T F", 3) == 0 ? 1
                                                             : 2;
    int rc = gr_frame_alloc(f, (int)n, dim, err);
    if (rc) {
        return rc;
    }
    f->t = t;
    f->L = lx;
    /* a mixture: species, radii and masses of every particle (all three columns needed) */
    if (c.species >= 0 && c.radius >= 0 && c.masses >= 0) {
        f->species = malloc(sizeof(int) * (size_t)n);
        f->radii = malloc(sizeof(double) * (size_t)n);
        f->masses = malloc(sizeof(double) * (size_t)n);
        if (!f->species || !f->radii || !f->masses) {
            gr_frame_free(f);
            return GR_FAIL(err, GR_ENOMEM, "out of memory for the species of %ld particles", n);
        }
    }
    for (long i = 0; i < n; i++) {
        double v[64];
        ++*line_no;
        if (!fgets(line, sizeof line, in)) {
            gr_frame_free(f);
            return GR_FAIL(err, GR_EINVAL, "%s: truncated: %ld of %ld particles", path, i, n);
        }
        char *s = line + strspn(line, " \t");
        s += strcspn(s, " \t"); /* the species */
        int got = 0;
        for (; got < c.total - 1; got++) {
            char *end;
            v[got] = strtod(s, &end);
            if (end == s) {
                break;
            }
            s = end;
        }
        const int need = (c.velo >= 0 ? c.velo : c.momenta) + f->dim - 1;
        if (got < c.total - 1 || got <= need) {
            gr_frame_free(f);
            return GR_FAIL(err, GR_EINVAL, "%s:%ld: expected %d columns", path, *line_no, c.total);
        }
        /* v[] starts after the species column */
        const double m = c.velo >= 0 ? 1.0 : v[c.masses - 1];
        const double *vel = c.velo >= 0 ? &v[c.velo - 1] : &v[c.momenta - 1];
        f->x[i] = v[c.pos - 1];
        f->vx[i] = vel[0] / m;
        if (f->dim >= 2) {
            f->y[i] = v[c.pos];
            f->vy[i] = vel[1] / m;
        }
        if (f->dim == 3) {
            f->z[i] = v[c.pos + 1];
            f->vz[i] = vel[2] / m;
        }
        if (c.radius >= 0) {
            f->radius = v[c.radius - 1];
        }
        if (f->species) {
            const double k = v[c.species - 1];
            if (!(k >= 1.0 && k <= GR_MAX_SPECIES && k == floor(k))) {
                gr_frame_free(f);
                return GR_FAIL(err, GR_EINVAL, "%s:%ld: species_index %g; allowed: 1 to %d", path,
                               *line_no, k, GR_MAX_SPECIES);
            }
            f->species[i] = (int)k - 1;
            f->n_species = f->n_species > (int)k ? f->n_species : (int)k;
            f->radii[i] = v[c.radius - 1];
            f->masses[i] = v[c.masses - 1];
            f->radius = fmax(f->radius, f->radii[i]);
        }
        if (!isfinite(f->x[i]) || !isfinite(f->vx[i]) ||
            (f->dim >= 2 && (!isfinite(f->y[i]) || !isfinite(f->vy[i]))) ||
            (f->dim == 3 && (!isfinite(f->z[i]) || !isfinite(f->vz[i])))) {
            gr_frame_free(f);
            return GR_FAIL(err, GR_EINVAL, "%s:%ld: position or velocity not finite", path,
                           *line_no);
        }
    }
    return GR_OK;
}

int gr_snapshot_read(const char *path, gr_frame *f, gr_error *err)
{
    FILE *in;
    int rc0 = gr_input_open(path, "snapshot", &in, err);
    if (rc0) {
        memset(f, 0, sizeof *f);
        return rc0;
    }
    long line_no = 0;
    int rc = gr_xyz_read_frame(in, path, &line_no, f, err);
    fclose(in);
    return rc == 1 ? GR_FAIL(err, GR_EINVAL, "%s:1: expected the particle count", path) : rc;
}
