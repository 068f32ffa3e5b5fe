/* Snapshots in extended XYZ (readable by OVITO and ASE): one frame per file, written atomically. */
#include <math.h>
#include <stdio.h>

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
