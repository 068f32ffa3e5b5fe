/* Snapshots in extended XYZ (readable by OVITO and ASE): one frame per file, written atomically. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/files.h"
#include "io/snapshot.h"

int gr_snapshot_write(const char *dir, int index, const gr_particles *p, double t, gr_error *err)
{
    char name[64];
    snprintf(name, sizeof name, "snap_%06d.xyz", index);
    gr_file f;
    int rc = gr_file_open(&f, dir, name, err);
    if (rc) {
        return rc;
    }
    double Ly = p->dim == 2 ? p->L : 1.0;
    fprintf(f.f, "%d\nLattice=\"%.17g 0 0 0 %.17g 0 0 0 1\" pbc=\"T %s F\" Time=%.17g "
                 "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1\n",
            p->n, p->L, Ly, p->dim == 2 ? "T" : "F", t);
    for (int i = 0; i < p->n; i++) {
        double x = p->x[i] - p->L * floor(p->x[i] / p->L);
        double y = p->dim == 2 ? p->y[i] : 0.5;
        double vy = p->dim == 2 ? p->vy[i] : 0.0;
        fprintf(f.f, "G %.17g %.17g 0 %.17g %.17g 0 %.17g\n", x, y, p->vx[i], vy, p->radius);
    }
    return gr_file_commit(&f, err);
}

void gr_frame_free(gr_frame *f)
{
    free(f->x);
    free(f->y);
    free(f->vx);
    free(f->vy);
    f->x = f->y = f->vx = f->vy = NULL;
}

int gr_snapshot_read(const char *path, gr_frame *f, gr_error *err)
{
    memset(f, 0, sizeof *f);
    FILE *in = fopen(path, "r");
    if (!in) {
        return GR_FAIL(err, GR_EIO, "%s: cannot open snapshot", path);
    }
    char line[1024];
    long n = 0;
    if (!fgets(line, sizeof line, in) || sscanf(line, "%ld", &n) != 1 || n < 1 || n > 100000000L) {
        fclose(in);
        return GR_FAIL(err, GR_EINVAL, "%s:1: expected the particle count", path);
    }
    if (!fgets(line, sizeof line, in)) {
        fclose(in);
        return GR_FAIL(err, GR_EINVAL, "%s:2: missing comment line", path);
    }
    double lx = 0, ly = 0;
    const char *lat = strstr(line, "Lattice=\""), *tm = strstr(line, "Time="), *pbc = strstr(line, "pbc=\"");
    double dummy;
    if (!lat || sscanf(lat + 9, "%lf %lf %lf %lf %lf", &lx, &dummy, &dummy, &dummy, &ly) != 5 || !(lx > 0.0) ||
        !strstr(line, "Properties=species:S:1:pos:R:3:velo:R:3")) {
        fclose(in);
        return GR_FAIL(err, GR_EINVAL, "%s:2: not a granule extended-XYZ frame (need Lattice, Properties=species:S:1:pos:R:3:velo:R:3)", path);
    }
    f->dim = pbc && strncmp(pbc + 5, "T F", 3) == 0 ? 1 : 2;
    f->t = tm ? strtod(tm + 5, NULL) : 0.0;
    f->L = lx;
    f->n = (int)n;
    f->x = malloc(sizeof(double) * (size_t)n);
    f->vx = malloc(sizeof(double) * (size_t)n);
    f->y = malloc(sizeof(double) * (size_t)n);
    f->vy = malloc(sizeof(double) * (size_t)n);
    if (!f->x || !f->vx || !f->y || !f->vy) {
        fclose(in);
        gr_frame_free(f);
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory for %ld particles", path, n);
    }
    for (long i = 0; i < n; i++) {
        char sp[16];
        double z, vz, r = 0.0;
        if (!fgets(line, sizeof line, in)) {
            fclose(in);
            gr_frame_free(f);
            return GR_FAIL(err, GR_EINVAL, "%s: truncated: %ld of %ld particles", path, i, n);
        }
        int got = sscanf(line, "%15s %lf %lf %lf %lf %lf %lf %lf", sp, &f->x[i], &f->y[i], &z, &f->vx[i], &f->vy[i], &vz, &r);
        if (got < 7 || !isfinite(f->x[i]) || !isfinite(f->vx[i])) {
            fclose(in);
            gr_frame_free(f);
            return GR_FAIL(err, GR_EINVAL, "%s:%ld: expected species x y z vx vy vz [radius]", path, i + 3);
        }
        if (got == 8) {
            f->radius = r;
        }
    }
    fclose(in);
    if (f->dim == 1) {
        free(f->y);
        free(f->vy);
        f->y = f->vy = NULL;
        /* 1D frames are written wrapped into [0, L): restore the ring order for the analysis */
    }
    return GR_OK;
}
