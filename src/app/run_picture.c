/* The picture of a run folder (src/app/run_picture.h): reads the run's scene and trajectory and
 * draws them with the io layer's pictures. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/run_picture.h"
#include "granule/scene.h"
#include "io/picture_internal.h"
#include "io/snapshot.h"
#include "io/trajectory.h"

/* a 1D run draws up to this many frames, and up to this many particles in all */
enum { RUN_SPACETIME_FRAMES = 800 };
#define RUN_SPACETIME_PARTICLES 2e6

/* Frames first..last (inclusive) of a run folder's trajectory (any output.trajectory format). */
static int read_frames(const char *run_dir, int64_t first, int64_t last, gr_frame *frames,
                       gr_error *err)
{
    gr_traj_reader *r;
    int64_t count;
    int rc = gr_traj_reader_open(run_dir, -1, &r, &count, err);
    for (int64_t k = first; !rc && k <= last; k++) {
        rc = gr_traj_reader_frame(r, k, &frames[k - first], err);
    }
    gr_traj_reader_close(r);
    return rc;
}

int gr_picture_run_ex(const char *run_dir, const gr_picture_options *opt, char *png_path,
                      size_t png_path_size, gr_error *err)
{
    if (!run_dir || !run_dir[0] || strlen(run_dir) > 900) {
        return GR_FAIL(err, GR_EINVAL, "picture: run folder name missing or too long");
    }
    popts p;
    int rc = pic_resolve_options(opt, &p, err);
    if (rc) {
        return rc;
    }
    char path[1200], out[1100];
    gr_traj_reader *r;
    int64_t count = 0;
    rc = gr_traj_reader_open(run_dir, -1, &r, &count, err);
    gr_traj_reader_close(r);
    if (!rc && count == 0) {
        rc = GR_FAIL(err, GR_EINVAL,
                     "%s: no snapshots (an empty trajectory); set output.snapshot_every", run_dir);
    }
    if (rc) {
        return rc;
    }
    /* the last frame decides the kind of picture; a 1D run draws up to 800 successive frames */
    gr_frame last;
    rc = read_frames(run_dir, count - 1, count - 1, &last, err);
    if (rc) {
        return rc;
    }
    int nf = 1;
    if (last.dim == 1) {
        const double fit = fmax(2.0, floor(RUN_SPACETIME_PARTICLES / fmax(1.0, (double)last.n)));
        nf = (int)fmin((double)count, fmin((double)RUN_SPACETIME_FRAMES, fit));
    }
    gr_frame *frames = calloc((size_t)nf, sizeof *frames);
    if (!frames) {
        gr_frame_free(&last);
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory", run_dir);
    }
    frames[nf - 1] = last;
    if (nf > 1) {
        rc = read_frames(run_dir, count - nf, count - 2, frames, err);
    }
    for (int j = 0; j < nf - 1 && !rc; j++) {
        if (frames[j].dim != last.dim) {
            rc = GR_FAIL(err, GR_EINVAL, "%s: frame %lld is %dD but the last one is %dD", run_dir,
                         (long long)(count - nf + j), frames[j].dim, last.dim);
        }
    }
    /* the radius: the run's scene.ini, else the snapshots' radius column */
    double radius = last.radius;
    gr_picture_options o = opt ? *opt : (gr_picture_options){0};
    gr_error scene_err = {0};
    snprintf(path, sizeof path, "%s/scene.ini", run_dir);
    if (!rc && access(path, R_OK) == 0) {
        gr_scene *scene = malloc(sizeof *scene);
        if (scene && gr_scene_load(scene, path, NULL, 0, &scene_err) == GR_OK) {
            radius = scene->radius;
            for (int a = 0; a < 3; a++) { /* a bed is drawn between its walls */
                o.walls[a] = scene->boundary[a] != 0;
            }
        }
        free(scene);
    }
    if (!rc && !(radius > 0.0)) {
        rc = GR_FAIL(
            err, GR_EINVAL,
            "%s: no particle radius (no loadable scene.ini%s%s, no radius column in the snapshots)",
            run_dir, scene_err.code ? ": " : "", scene_err.code ? scene_err.message : "");
    }
    if (!rc) {
        snprintf(out, sizeof out, "%s/%s", run_dir,
                 last.dim >= 2 ? "snapshot.png" : "snapshots.png");
        rc = last.dim >= 2 ? gr_picture_frame(&frames[0], radius, out, &o, err)
                           : gr_picture_spacetime(frames, nf, radius, out, &o, err);
        if (!rc && last.dim >= 2 && last.species && last.n_species >= 2) {
            /* a mixture: also the same frame coloured by species (docs/mixtures.md) */
            gr_picture_options os = o;
            os.by_species = true;
            char sp[1200];
            snprintf(sp, sizeof sp, "%s/snapshot_species.png", run_dir);
            rc = gr_picture_frame(&frames[0], radius, sp, &os, err);
        }
        if (!rc && png_path && png_path_size) {
            snprintf(png_path, png_path_size, "%s", out);
        }
    }
    for (int j = 0; j < nf; j++) {
        gr_frame_free(&frames[j]);
    }
    free(frames);
    return rc;
}

int gr_picture_run(const char *run_dir, gr_error *err)
{
    return gr_picture_run_ex(run_dir, NULL, NULL, 0, err);
}
