/* Shared declarations of the granule Python extension (granule._granule): the exception, the
 * Scene type every other type is built from, and the numpy C API import. */
#ifndef PYGRANULE_H
#define PYGRANULE_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL granule_ARRAY_API
#ifndef PYGRANULE_MAIN
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "granule/granule.h"

/* granule.Error (a RuntimeError); granule.SceneError (also a ValueError) for GR_EINVAL. */
extern PyObject *pyg_error, *pyg_scene_error;
/* Raise the exception matching err->code with granule's message; returns NULL. */
PyObject *pyg_raise(const gr_error *err);

typedef struct {
    PyObject_HEAD gr_scene scene;
} pyg_scene;

extern PyTypeObject pyg_scene_type;
extern PyTypeObject pyg_sim_type;
extern PyTypeObject pyg_observer_type;

/* A read-only 1-D float64 numpy view of n doubles owned by `owner` (kept alive by the view). */
PyObject *pyg_view(PyObject *owner, const double *data, int n);
/* The particles and time of a granule.Sim (-1 with a TypeError for anything else). */
int pyg_sim_particles(PyObject *o, gr_particles *p, double *t);
/* granule.run(scene, out, force=False) -> dict */
PyObject *pyg_run(PyObject *self, PyObject *args, PyObject *kw);

#endif
