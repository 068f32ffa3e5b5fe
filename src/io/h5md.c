/* H5MD trajectories through the HDF5 C library (docs/trajectories.md).
 *
 * Layout (H5MD 1.1; MDAnalysis needs dimension 3 and time-dependent box edges):
 *   /h5md                      version = [1, 1]; author/name, creator/name, creator/version
 *   /particles/all/box         dimension = 3, boundary = periodic x (y) and none for the unused
 *                              directions; edges/{step,time,value[F][3][3]}: the box matrix
 *   /particles/all/position    value[F][N][3] (m), step[F], time[F] (s)
 *   /particles/all/velocity    value[F][N][3] (m s-1), step and time hard links to position's
 *   /particles/all/angular_velocity  value[F][N][3] (rad s-1), when the file has them
 *   /particles/all/mass        [N] kg
 *   /particles/all/species     [N] 1, 2, ... (a mixture only: H5MD's species element)
 *   /particles/all/radius      [N] m (a mixture only; granule's own element)
 *   /parameters/granule        dim, N, L, radius, mass, length_unit = "m"; a mixture's
 *                              n_species (radius the largest, mass the mean)
 * A 3D system has its three coordinates and a cube of edges L, periodic in x, y and z; a 2D
 * system has z = d/2 and a z edge of one diameter d, a 1D system y = z = d/2 and y, z edges
 * of d, as in the extended-XYZ snapshots. Position values carry no unit attribute: MDAnalysis
 * 2.4 refuses the unit "m" (it knows only Angstrom, nm, pm, fm); lengths are metres.
 * Per-particle datasets are chunked one frame by up to 32768 particles, shuffled and deflated;
 * the file is flushed after every frame. HDF5's own error printing is switched off: errors come
 * back as gr_error messages naming the file. */
#include <hdf5.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granule_config.h"
#include "io/h5md.h"

enum { EL_POS, EL_VEL, EL_OMEGA, EL_EDGES, N_EL };
static const char *el_path[N_EL] = {"/particles/all/position", "/particles/all/velocity",
                                    "/particles/all/angular_velocity", "/particles/all/box/edges"};

struct gr_h5md {
    hid_t file;
    hid_t value[N_EL]; /* H5I_INVALID_HID when absent */
    hid_t step, time;  /* position's; the other elements link to them */
    int n, dim;
    double L, d, radius;
    int64_t frames;
    int writable;
    double *buf; /* 3 n */
    /* a mixture's per-particle constants (read back; NULL without) */
    int *species, n_species;
    double *radii, *masses;
    char path[1024];
};

static gr_h5md *h5md_new(const char *path, int n)
{
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* the library never prints */
    gr_h5md *h = calloc(1, sizeof *h);
    if (!h) {
        return NULL;
    }
    h->buf = malloc(sizeof(double) * 3 * (size_t)(n > 0 ? n : 1));
    if (!h->buf) {
        free(h);
        return NULL;
    }
    h->file = h->step = h->time = H5I_INVALID_HID;
    for (int e = 0; e < N_EL; e++) {
        h->value[e] = H5I_INVALID_HID;
    }
    h->n = n;
    snprintf(h->path, sizeof h->path, "%s", path);
    return h;
}

static void h5md_release(gr_h5md *h)
{
    for (int e = 0; e < N_EL; e++) {
        if (h->value[e] >= 0) {
            H5Dclose(h->value[e]);
        }
    }
    if (h->step >= 0) {
        H5Dclose(h->step);
    }
    if (h->time >= 0) {
        H5Dclose(h->time);
    }
    if (h->file >= 0) {
        H5Fclose(h->file);
    }
    free(h->buf);
    free(h->species);
    free(h->radii);
    free(h->masses);
    free(h);
}

static int attr_write(hid_t obj, const char *name, hid_t type, int rank, const hsize_t *dims,
                      const void *data)
{
    hid_t space = rank ? H5Screate_simple(rank, dims, NULL) : H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    herr_t st = a < 0 ? -1 : H5Awrite(a, type, data);
    if (a >= 0) {
        H5Aclose(a);
    }
    H5Sclose(space);
    return st < 0 ? -1 : 0;
}

/* Variable-length strings: h5py (and so MDAnalysis) reads them as str, fixed-length ones as bytes. */
static int attr_strings(hid_t obj, const char *name, int count, const char **values)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    const hsize_t n = (hsize_t)count;
    int st = attr_write(obj, name, type, count > 1 ? 1 : 0, &n, values);
    H5Tclose(type);
    return st;
}

static int attr_string(hid_t obj, const char *name, const char *value)
{
    return attr_strings(obj, name, 1, &value);
}

static int attr_double(hid_t obj, const char *name, double v)
{
    return attr_write(obj, name, H5T_NATIVE_DOUBLE, 0, NULL, &v);
}

static hid_t group_make(hid_t parent, const char *path)
{
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    hid_t g = H5Gcreate2(parent, path, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Pclose(lcpl);
    return g;
}

/* An extendible dataset [0][inner...] of `type`, chunked as [chunk0][inner...] (inner dims
 * capped at 32768 in the first one), shuffled and deflated when level > 0. */
static hid_t dataset_make(hid_t parent, const char *path, hid_t type, int rank,
                          const hsize_t *inner, hsize_t chunk0, int level)
{
    hsize_t dims[3] = {0, 0, 0}, maxd[3] = {H5S_UNLIMITED, 0, 0}, chunk[3] = {chunk0, 1, 1};
    for (int r = 1; r < rank; r++) {
        dims[r] = maxd[r] = chunk[r] = inner[r - 1];
    }
    if (rank > 1 && chunk[1] > 32768) {
        chunk[1] = 32768;
    }
    hid_t space = H5Screate_simple(rank, dims, maxd);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, rank, chunk);
    if (level > 0) {
        H5Pset_shuffle(dcpl);
        H5Pset_deflate(dcpl, (unsigned)level);
    }
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    hid_t d = H5Dcreate2(parent, path, type, space, lcpl, dcpl, H5P_DEFAULT);
    H5Pclose(lcpl);
    H5Pclose(dcpl);
    H5Sclose(space);
    return d;
}

/* step and time of one element: position's own datasets, hard links from the others */
static int element_make(gr_h5md *h, int e, int rank, const hsize_t *inner, const char *unit,
                        int level)
{
    char p[128];
    snprintf(p, sizeof p, "%s/value", el_path[e]);
    h->value[e] =
        dataset_make(h->file, p, H5T_NATIVE_DOUBLE, rank, inner, rank == 3 ? 1 : 64, level);
    if (h->value[e] < 0 || (unit && attr_string(h->value[e], "unit", unit))) {
        return -1;
    }
    if (e == EL_POS) {
        h->step = dataset_make(h->file, "/particles/all/position/step", H5T_NATIVE_INT64, 1, NULL,
                               1024, 0);
        h->time = dataset_make(h->file, "/particles/all/position/time", H5T_NATIVE_DOUBLE, 1, NULL,
                               1024, 0);
        return h->step < 0 || h->time < 0 || attr_string(h->time, "unit", "s") ? -1 : 0;
    }
    char s[128], t[128];
    snprintf(s, sizeof s, "%s/step", el_path[e]);
    snprintf(t, sizeof t, "%s/time", el_path[e]);
    return H5Lcreate_hard(h->file, "/particles/all/position/step", h->file, s, H5P_DEFAULT,
                          H5P_DEFAULT) < 0 ||
                   H5Lcreate_hard(h->file, "/particles/all/position/time", h->file, t, H5P_DEFAULT,
                                  H5P_DEFAULT) < 0
               ? -1
               : 0;
}

/* A time-independent per-particle dataset [N] (mass, species, radius), chunked and deflated. */
static int constant_write(gr_h5md *h, const char *path, hid_t type, const void *data,
                          const char *unit)
{
    hsize_t n = (hsize_t)h->n, chunk = n < 32768 ? n : 32768;
    chunk = chunk > 0 ? chunk : 1;
    hid_t space = H5Screate_simple(1, &n, NULL), dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, &chunk);
    H5Pset_deflate(dcpl, 1);
    hid_t m = H5Dcreate2(h->file, path, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int st = m < 0 || H5Dwrite(m, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0 ||
             (unit && attr_string(m, "unit", unit));
    if (m >= 0) {
        H5Dclose(m);
    }
    H5Pclose(dcpl);
    H5Sclose(space);
    return st ? -1 : 0;
}

/* Read the time-independent dataset path [N] into a new array (NULL if absent or unreadable). */
static void *constant_read(gr_h5md *h, const char *path, hid_t type, size_t size)
{
    if (H5Lexists(h->file, path, H5P_DEFAULT) <= 0) {
        return NULL;
    }
    void *out = malloc(size * (size_t)(h->n > 0 ? h->n : 1));
    hid_t d = H5Dopen2(h->file, path, H5P_DEFAULT);
    if (!out || d < 0 || H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0) {
        free(out);
        out = NULL;
    }
    if (d >= 0) {
        H5Dclose(d);
    }
    return out;
}

static int metadata_write(gr_h5md *h, const gr_h5md_desc *d)
{
    int st = 0;
    hid_t g = group_make(h->file, "/h5md");
    const int version[2] = {1, 1};
    const hsize_t two = 2;
    st |= g < 0 || attr_write(g, "version", H5T_NATIVE_INT, 1, &two, version);
    H5Gclose(g);
    g = group_make(h->file, "/h5md/author");
    st |= g < 0 || attr_string(g, "name", "granule");
    H5Gclose(g);
    g = group_make(h->file, "/h5md/creator");
    st |= g < 0 || attr_string(g, "name", "granule") || attr_string(g, "version", GR_VERSION);
    H5Gclose(g);
    g = group_make(h->file, "/particles/all/box");
    const int dimension = 3;
    const char *boundary[3] = {"periodic", d->dim >= 2 ? "periodic" : "none",
                               d->dim == 3 ? "periodic" : "none"};
    st |= g < 0 || attr_write(g, "dimension", H5T_NATIVE_INT, 0, NULL, &dimension) ||
          attr_strings(g, "boundary", 3, boundary);
    H5Gclose(g);
    g = group_make(h->file, "/parameters/granule");
    st |= g < 0 || attr_write(g, "dim", H5T_NATIVE_INT, 0, NULL, &d->dim) ||
          attr_write(g, "N", H5T_NATIVE_INT, 0, NULL, &d->n) || attr_double(g, "L", d->L) ||
          attr_double(g, "radius", d->radius) || attr_double(g, "mass", d->mass) ||
          attr_string(g, "length_unit", "m");
    H5Gclose(g);
    if (d->species) {
        g = H5Gopen2(h->file, "/parameters/granule", H5P_DEFAULT);
        st |= g < 0 || attr_write(g, "n_species", H5T_NATIVE_INT, 0, NULL, &d->n_species);
        H5Gclose(g);
    }
    /* the masses: one value per particle, constant, so they compress to almost nothing */
    for (int i = 0; i < d->n; i++) {
        h->buf[i] = d->masses ? d->masses[i] : d->mass; /* buf holds 3 n values */
    }
    st |= constant_write(h, "/particles/all/mass", H5T_NATIVE_DOUBLE, h->buf, "kg");
    if (d->species) { /* a mixture: H5MD's species (1, 2, ...) and each grain's radius */
        int *sp = malloc(sizeof(int) * (size_t)(d->n > 0 ? d->n : 1));
        for (int i = 0; sp && i < d->n; i++) {
            sp[i] = d->species[i] + 1;
        }
        st |= !sp || constant_write(h, "/particles/all/species", H5T_NATIVE_INT, sp, NULL);
        free(sp);
        st |= constant_write(h, "/particles/all/radius", H5T_NATIVE_DOUBLE, d->radii, "m");
    }
    return st ? -1 : 0;
}

int gr_h5md_create(const char *path, const gr_h5md_desc *d, gr_h5md **out, gr_error *err)
{
    *out = NULL;
    gr_h5md *h = h5md_new(path, d->n);
    if (!h) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for an H5MD writer of %d particles", d->n);
    }
    h->dim = d->dim;
    h->L = d->L;
    h->radius = d->radius;
    h->d = 2.0 * d->radius;
    h->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (h->file < 0) {
        h5md_release(h);
        return GR_FAIL(err, GR_EIO, "cannot create %s (HDF5)", path);
    }
    const hsize_t per_particle[2] = {(hsize_t)d->n, 3}, matrix[2] = {3, 3};
    const int level = d->deflate < 0 ? 0 : d->deflate > 9 ? 9 : d->deflate;
    int st = metadata_write(h, d);
    st = st ? st : element_make(h, EL_POS, 3, per_particle, NULL, level);
    st = st ? st : element_make(h, EL_VEL, 3, per_particle, "m s-1", level);
    st = st                    ? st
         : d->angular_velocity ? element_make(h, EL_OMEGA, 3, per_particle, "rad s-1", level)
                               : 0;
    st = st ? st : element_make(h, EL_EDGES, 3, matrix, NULL, 0);
    if (st || H5Fflush(h->file, H5F_SCOPE_GLOBAL) < 0) {
        h5md_release(h);
        return GR_FAIL(err, GR_EIO, "cannot write the H5MD layout of %s (HDF5)", path);
    }
    h->writable = 1;
    *out = h;
    return GR_OK;
}

static int64_t frames_of(hid_t d)
{
    hsize_t dims[3] = {0, 0, 0};
    hid_t s = H5Dget_space(d);
    int rank = s < 0 ? -1 : H5Sget_simple_extent_dims(s, dims, NULL);
    if (s >= 0) {
        H5Sclose(s);
    }
    return rank < 1 ? -1 : (int64_t)dims[0];
}

/* Open an existing file's datasets and parameters. */
static int h5md_attach(gr_h5md *h, unsigned mode, gr_error *err)
{
    h->file = H5Fopen(h->path, mode, H5P_DEFAULT);
    if (h->file < 0) {
        return GR_FAIL(err, GR_EIO, "%s: cannot open as HDF5 (missing, or not an HDF5 file)",
                       h->path);
    }
    for (int e = 0; e < N_EL; e++) {
        char p[128];
        snprintf(p, sizeof p, "%s/value", el_path[e]);
        h->value[e] = H5Lexists(h->file, el_path[e], H5P_DEFAULT) > 0
                          ? H5Dopen2(h->file, p, H5P_DEFAULT)
                          : H5I_INVALID_HID;
    }
    h->step = H5Dopen2(h->file, "/particles/all/position/step", H5P_DEFAULT);
    h->time = H5Dopen2(h->file, "/particles/all/position/time", H5P_DEFAULT);
    hid_t g = H5Gopen2(h->file, "/parameters/granule", H5P_DEFAULT);
    int n = -1, dim = 0;
    double radius = 0.0;
    if (g >= 0) {
        hid_t a = H5Aopen(g, "N", H5P_DEFAULT);
        (void)(a >= 0 && H5Aread(a, H5T_NATIVE_INT, &n) >= 0 && H5Aclose(a) >= 0);
        a = H5Aopen(g, "dim", H5P_DEFAULT);
        (void)(a >= 0 && H5Aread(a, H5T_NATIVE_INT, &dim) >= 0 && H5Aclose(a) >= 0);
        a = H5Aopen(g, "radius", H5P_DEFAULT);
        (void)(a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &radius) >= 0 && H5Aclose(a) >= 0);
        H5Gclose(g);
    }
    if (h->value[EL_POS] < 0 || h->value[EL_VEL] < 0 || h->value[EL_EDGES] < 0 || h->step < 0 ||
        h->time < 0 || n != h->n || dim < 1 || dim > 3) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: not a granule H5MD trajectory of %d particles (needs position, velocity, "
            "box/edges and /parameters/granule)",
            h->path, h->n);
    }
    h->dim = dim;
    h->radius = radius;
    h->d = 2.0 * radius;
    /* a mixture: each particle's species (1, 2, ... in the file), radius and mass */
    h->species = constant_read(h, "/particles/all/species", H5T_NATIVE_INT, sizeof(int));
    if (h->species) {
        h->radii = constant_read(h, "/particles/all/radius", H5T_NATIVE_DOUBLE, sizeof(double));
        h->masses = constant_read(h, "/particles/all/mass", H5T_NATIVE_DOUBLE, sizeof(double));
        for (int i = 0; i < h->n; i++) {
            h->species[i]--;
            h->n_species = h->species[i] + 1 > h->n_species ? h->species[i] + 1 : h->n_species;
            if (h->species[i] < 0) {
                return GR_FAIL(err, GR_EINVAL,
                               "%s: /particles/all/species[%d] = %d; allowed: 1, 2, ... (the "
                               "species of a granule mixture)",
                               h->path, i, h->species[i] + 1);
            }
        }
        if (!h->radii || !h->masses) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: a mixture's trajectory needs /particles/all/radius and mass "
                           "beside species",
                           h->path);
        }
    }
    h->frames = frames_of(h->value[EL_POS]);
    for (int e = 0; e < N_EL; e++) {
        if (h->value[e] >= 0 && frames_of(h->value[e]) < h->frames) {
            h->frames = frames_of(h->value[e]);
        }
    }
    int64_t ft = frames_of(h->time), fs = frames_of(h->step);
    h->frames = ft < h->frames ? ft : fs < h->frames ? fs : h->frames;
    return h->frames < 0 ? GR_FAIL(err, GR_EINVAL, "%s: unreadable dataset extents", h->path)
                         : GR_OK;
}

static int parameter_n(const char *path, int *n)
{
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t g = f >= 0 ? H5Gopen2(f, "/parameters/granule", H5P_DEFAULT) : H5I_INVALID_HID;
    hid_t a = g >= 0 ? H5Aopen(g, "N", H5P_DEFAULT) : H5I_INVALID_HID;
    int ok = a >= 0 && H5Aread(a, H5T_NATIVE_INT, n) >= 0;
    if (a >= 0) {
        H5Aclose(a);
    }
    if (g >= 0) {
        H5Gclose(g);
    }
    if (f >= 0) {
        H5Fclose(f);
    }
    return ok && *n > 0 ? 0 : -1;
}

static int extent_set(hid_t d, int64_t frames)
{
    hsize_t dims[3];
    hid_t s = H5Dget_space(d);
    int rank = H5Sget_simple_extent_dims(s, dims, NULL);
    H5Sclose(s);
    dims[0] = (hsize_t)frames;
    return rank < 1 || H5Dset_extent(d, dims) < 0 ? -1 : 0;
}

int gr_h5md_reopen(const char *path, int64_t keep, int n, gr_h5md **out, gr_error *err)
{
    *out = NULL;
    gr_h5md *h = h5md_new(path, n);
    if (!h) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for an H5MD writer of %d particles", n);
    }
    int rc = h5md_attach(h, H5F_ACC_RDWR, err);
    if (!rc && h->frames < keep) {
        rc = GR_FAIL(err, GR_EINVAL, "%s: %lld frames, but the checkpoint was taken after %lld",
                     path, (long long)h->frames, (long long)keep);
    }
    if (!rc) { /* frames written after the checkpoint are cut */
        int st = extent_set(h->step, keep) | extent_set(h->time, keep);
        for (int e = 0; e < N_EL; e++) {
            st |= h->value[e] >= 0 ? extent_set(h->value[e], keep) : 0;
        }
        rc = st || H5Fflush(h->file, H5F_SCOPE_GLOBAL) < 0
                 ? GR_FAIL(err, GR_EIO, "%s: cannot cut to %lld frames (HDF5)", path,
                           (long long)keep)
                 : GR_OK;
        h->frames = keep;
    }
    if (rc) {
        h5md_release(h);
        return rc;
    }
    /* the box is taken back from the file's parameters */
    hid_t g = H5Gopen2(h->file, "/parameters/granule", H5P_DEFAULT);
    hid_t a = H5Aopen(g, "L", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &h->L);
    H5Aclose(a);
    H5Gclose(g);
    h->writable = 1;
    *out = h;
    return GR_OK;
}

/* Transfer one frame (index `frame`, all inner dims) of dataset d from/to data; a write first
 * grows the dataset to frame + 1 frames. */
static int frame_io(hid_t d, int64_t frame, hid_t type, void *data, bool write)
{
    hsize_t dims[3], start[3] = {(hsize_t)frame, 0, 0};
    if (write && extent_set(d, frame + 1)) {
        return -1;
    }
    hid_t fs = H5Dget_space(d);
    int rank = H5Sget_simple_extent_dims(fs, dims, NULL);
    dims[0] = 1;
    H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, dims, NULL);
    hid_t ms = H5Screate_simple(rank, dims, NULL);
    herr_t st = write ? H5Dwrite(d, type, ms, fs, H5P_DEFAULT, data)
                      : H5Dread(d, type, ms, fs, H5P_DEFAULT, data);
    H5Sclose(ms);
    H5Sclose(fs);
    return st < 0 ? -1 : 0;
}

static int frame_write(hid_t d, int64_t frame, hid_t type, const void *data)
{
    return frame_io(d, frame, type, (void *)data, true);
}

static int frame_read(hid_t d, int64_t frame, hid_t type, void *data)
{
    return frame_io(d, frame, type, data, false);
}

int gr_h5md_append(gr_h5md *h, const gr_particles *p, const double *omega, double t, int64_t step,
                   gr_error *err)
{
    if (p->n != h->n) {
        return GR_FAIL(err, GR_EINVAL, "%s: a frame of %d particles in a file of %d", h->path, p->n,
                       h->n);
    }
    const int64_t k = h->frames;
    double *b = h->buf;
    const double half = 0.5 * h->d;
    for (int i = 0; i < p->n; i++) {
        b[3 * i] = p->x[i] - p->L * floor(p->x[i] / p->L);
        b[3 * i + 1] = p->dim == 3   ? p->y[i] - p->L * floor(p->y[i] / p->L)
                       : p->dim == 2 ? p->y[i]
                                     : half;
        b[3 * i + 2] = p->dim == 3 ? p->z[i] - p->L * floor(p->z[i] / p->L) : half;
    }
    int st = frame_write(h->value[EL_POS], k, H5T_NATIVE_DOUBLE, b);
    for (int i = 0; i < p->n; i++) {
        b[3 * i] = p->vx[i];
        b[3 * i + 1] = p->dim >= 2 ? p->vy[i] : 0.0;
        b[3 * i + 2] = p->dim == 3 ? p->vz[i] : 0.0;
    }
    st |= frame_write(h->value[EL_VEL], k, H5T_NATIVE_DOUBLE, b);
    if (h->value[EL_OMEGA] >= 0) {
        for (int i = 0; i < p->n; i++) { /* 2D: about z; 3D: the spin vector */
            b[3 * i] = p->wz ? p->wx[i] : 0.0;
            b[3 * i + 1] = p->wz ? p->wy[i] : 0.0;
            b[3 * i + 2] = p->wz ? p->wz[i] : omega ? omega[i] : 0.0;
        }
        st |= frame_write(h->value[EL_OMEGA], k, H5T_NATIVE_DOUBLE, b);
    }
    const double edges[9] = {
        p->L, 0, 0, 0, p->dim >= 2 ? p->L : h->d, 0, 0, 0, p->dim == 3 ? p->L : h->d};
    st |= frame_write(h->value[EL_EDGES], k, H5T_NATIVE_DOUBLE, edges);
    st |= frame_write(h->step, k, H5T_NATIVE_INT64, &step);
    st |= frame_write(h->time, k, H5T_NATIVE_DOUBLE, &t);
    if (st || H5Fflush(h->file, H5F_SCOPE_GLOBAL) < 0) {
        return GR_FAIL(err, GR_EIO, "cannot write frame %lld of %s (HDF5; disk full?)",
                       (long long)k, h->path);
    }
    h->frames = k + 1;
    return GR_OK;
}

int gr_h5md_close(gr_h5md *h, gr_error *err)
{
    if (!h) {
        return GR_OK;
    }
    int bad = h->writable && h->file >= 0 && H5Fflush(h->file, H5F_SCOPE_GLOBAL) < 0;
    char path[1024];
    snprintf(path, sizeof path, "%s", h->path);
    h5md_release(h);
    return bad ? GR_FAIL(err, GR_EIO, "cannot finish %s (HDF5)", path) : GR_OK;
}

int gr_h5md_open_read(const char *path, gr_h5md **out, int64_t *frames, gr_error *err)
{
    *out = NULL;
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    int n = 0;
    if (parameter_n(path, &n)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: not a granule H5MD trajectory (no /parameters/granule N)", path);
    }
    gr_h5md *h = h5md_new(path, n);
    if (!h) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for an H5MD reader of %d particles", n);
    }
    int rc = h5md_attach(h, H5F_ACC_RDONLY, err);
    if (rc) {
        h5md_release(h);
        return rc;
    }
    *frames = h->frames;
    *out = h;
    return GR_OK;
}

int gr_h5md_read_frame(gr_h5md *h, int64_t k, gr_frame *f, gr_error *err)
{
    memset(f, 0, sizeof *f);
    if (k < 0 || k >= h->frames) {
        return GR_FAIL(err, GR_EINVAL, "%s: no frame %lld (%lld frames)", h->path, (long long)k,
                       (long long)h->frames);
    }
    int rc = gr_frame_alloc(f, h->n, h->dim, err);
    if (rc) {
        return rc;
    }
    double edges[9];
    int st = frame_read(h->value[EL_EDGES], k, H5T_NATIVE_DOUBLE, edges) |
             frame_read(h->time, k, H5T_NATIVE_DOUBLE, &f->t) |
             frame_read(h->value[EL_POS], k, H5T_NATIVE_DOUBLE, h->buf);
    for (int i = 0; i < h->n && !st; i++) {
        f->x[i] = h->buf[3 * i];
        if (h->dim >= 2) {
            f->y[i] = h->buf[3 * i + 1];
        }
        if (h->dim == 3) {
            f->z[i] = h->buf[3 * i + 2];
        }
    }
    st |= frame_read(h->value[EL_VEL], k, H5T_NATIVE_DOUBLE, h->buf);
    for (int i = 0; i < h->n && !st; i++) {
        f->vx[i] = h->buf[3 * i];
        if (h->dim >= 2) {
            f->vy[i] = h->buf[3 * i + 1];
        }
        if (h->dim == 3) {
            f->vz[i] = h->buf[3 * i + 2];
        }
    }
    if (st) {
        gr_frame_free(f);
        return GR_FAIL(err, GR_EIO, "%s: cannot read frame %lld (HDF5)", h->path, (long long)k);
    }
    f->L = edges[0];
    f->radius = h->radius;
    if (h->species) { /* a mixture: the frame's own copies (gr_frame_free frees them) */
        const size_t n = (size_t)(h->n > 0 ? h->n : 1);
        f->species = malloc(sizeof(int) * n);
        f->radii = malloc(sizeof(double) * n);
        f->masses = malloc(sizeof(double) * n);
        if (!f->species || !f->radii || !f->masses) {
            gr_frame_free(f);
            return GR_FAIL(err, GR_ENOMEM, "out of memory for the species of %d particles", h->n);
        }
        memcpy(f->species, h->species, sizeof(int) * (size_t)h->n);
        memcpy(f->radii, h->radii, sizeof(double) * (size_t)h->n);
        memcpy(f->masses, h->masses, sizeof(double) * (size_t)h->n);
        f->n_species = h->n_species;
    }
    return GR_OK;
}
