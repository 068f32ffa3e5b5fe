/* granule.Observer: the analysis layer's observables fed from Python (frames of a Sim or any
 * arrays), finished into a folder whose summary member comes back as JSON text; and granule.run.
 * The Python package (granule/__init__.py) turns both into dicts and numpy arrays. */
#include "pygranule.h"

#include <cjson/cJSON.h>

#include "io/files.h"
#include "scene/scene_json.h"

typedef struct {
    PyObject_HEAD gr_observer *obs;
    PyObject *scene;
    long frames;
} pyg_observer;

static int observer_init(pyg_observer *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"scene", NULL};
    PyObject *scene;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O!", kwlist, &pyg_scene_type, &scene)) {
        return -1;
    }
    gr_error err = {0};
    gr_observer_free(self->obs);
    self->obs = NULL;
    if (gr_scene_observer(&((pyg_scene *)scene)->scene, &self->obs, &err)) {
        pyg_raise(&err);
        return -1;
    }
    Py_XDECREF(self->scene);
    Py_INCREF(scene);
    self->scene = scene;
    return 0;
}

static void observer_dealloc(pyg_observer *self)
{
    gr_observer_free(self->obs);
    Py_XDECREF(self->scene);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject *feed(pyg_observer *self, const gr_particles *p, double t)
{
    if (!self->obs) {
        PyErr_SetString(pyg_error, "Observer was not initialised");
        return NULL;
    }
    gr_error err = {0};
    if (gr_observer_sample(self->obs, p, t, &err)) {
        return pyg_raise(&err);
    }
    self->frames++;
    Py_RETURN_NONE;
}

static PyObject *observer_sample(pyg_observer *self, PyObject *args)
{
    PyObject *sim;
    if (!PyArg_ParseTuple(args, "O", &sim)) {
        return NULL;
    }
    gr_particles p;
    double t;
    if (pyg_sim_particles(sim, &p, &t) < 0) {
        return NULL;
    }
    return feed(self, &p, t);
}

/* A contiguous float64 copy (or the array itself) of n entries, NULL with an exception. */
static PyArrayObject *as_doubles(PyObject *o, npy_intp n, const char *name)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(o, NPY_FLOAT64, 1, 1, NPY_ARRAY_IN_ARRAY);
    if (a && PyArray_DIM(a, 0) != n) {
        PyErr_Format(pyg_scene_error, "sample_frame: %s has %zd entries, expected %zd", name,
                     (Py_ssize_t)PyArray_DIM(a, 0), (Py_ssize_t)n);
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

static PyObject *observer_sample_frame(pyg_observer *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"t", "x", "vx", "y", "vy", "L", "z", "vz", NULL};
    double t, L = 0.0;
    PyObject *ox, *ovx, *oy = Py_None, *ovy = Py_None, *oz = Py_None, *ovz = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "dOO|OOdOO", kwlist, &t, &ox, &ovx, &oy, &ovy, &L,
                                     &oz, &ovz)) {
        return NULL;
    }
    const gr_scene *s = &((pyg_scene *)self->scene)->scene;
    if (s->dim == 3 && (oz == Py_None || ovz == Py_None || oy == Py_None || ovy == Py_None)) {
        PyErr_SetString(pyg_scene_error, "sample_frame: a 3D scene needs y, vy, z and vz "
                                         "(docs/three-dimensions.md)");
        return NULL;
    }
    const npy_intp n = s->N;
    PyArrayObject *a[6] = {
        as_doubles(ox, n, "x"), as_doubles(ovx, n, "vx"), NULL, NULL, NULL, NULL};
    if (s->dim >= 2) {
        a[2] = as_doubles(oy, n, "y");
        a[3] = as_doubles(ovy, n, "vy");
    }
    if (s->dim == 3) {
        a[4] = as_doubles(oz, n, "z");
        a[5] = as_doubles(ovz, n, "vz");
    }
    PyObject *res = NULL;
    if (a[0] && a[1] && (s->dim == 1 || (a[2] && a[3])) && (s->dim != 3 || (a[4] && a[5]))) {
        gr_particles p = {.n = s->N,
                          .dim = s->dim,
                          .L = L > 0.0 ? L : s->L,
                          .radius = s->radius,
                          .mass = s->mass,
                          .x = PyArray_DATA(a[0]),
                          .vx = PyArray_DATA(a[1]),
                          .y = a[2] ? PyArray_DATA(a[2]) : NULL,
                          .vy = a[3] ? PyArray_DATA(a[3]) : NULL,
                          .z = a[4] ? PyArray_DATA(a[4]) : NULL,
                          .vz = a[5] ? PyArray_DATA(a[5]) : NULL};
        res = feed(self, &p, t);
    }
    for (int k = 0; k < 6; k++) {
        Py_XDECREF(a[k]);
    }
    return res;
}

static PyObject *observer_finish(pyg_observer *self, PyObject *args, PyObject *kwargs)
{
    static char *kwlist[] = {"dir", "plots", "force", NULL};
    const char *dir;
    int plots = 0, force = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "s|pp", kwlist, &dir, &plots, &force)) {
        return NULL;
    }
    if (!self->obs) {
        PyErr_SetString(pyg_error, "Observer was not initialised");
        return NULL;
    }
    const gr_scene *s = &((pyg_scene *)self->scene)->scene;
    gr_error err = {0};
    /* a folder holding a run, a comparison, ... is refused unless force, as on the command line */
    if (gr_output_dir_prepare(dir, GR_OUTPUT_RESULT, force, &err)) {
        return pyg_raise(&err);
    }
    cJSON *analysis = cJSON_CreateObject();
    gr_output out = {.dir = dir,
                     .source = s->source,
                     .seed = s->seed,
                     .scene_hash = gr_scene_hash(s),
                     .summary = analysis,
                     .plots = plots};
    int rc = gr_observer_finish(self->obs, &out, &err);
    gr_observer_free(self->obs); /* finished: accumulators are spent */
    self->obs = NULL;
    char *text = rc ? NULL : cJSON_PrintUnformatted(analysis);
    cJSON_Delete(analysis);
    if (rc) {
        return pyg_raise(&err);
    }
    PyObject *r = text ? PyUnicode_FromString(text) : PyErr_NoMemory();
    cJSON_free(text);
    return r;
}

static PyObject *observer_frames(pyg_observer *self, void *unused)
{
    return PyLong_FromLong(self->frames);
}

static PyGetSetDef observer_getset[] = {
    {"frames", (getter)observer_frames, NULL, "frames sampled", NULL}, {NULL}};

static PyMethodDef observer_methods[] = {
    {"sample", (PyCFunction)observer_sample, METH_VARARGS,
     "sample(sim): one frame of a Sim at its time"},
    {"sample_frame", (PyCFunction)(void (*)(void))observer_sample_frame,
     METH_VARARGS | METH_KEYWORDS,
     "sample_frame(t, x, vx, y=None, vy=None, L=scene L, z=None, vz=None): one frame from arrays "
     "(y, vy in 2D and 3D; z, vz in 3D)"},
    {"finish", (PyCFunction)(void (*)(void))observer_finish, METH_VARARGS | METH_KEYWORDS,
     "finish(dir, plots=False, force=False) -> str: write the observables' CSVs into dir, return "
     "their summary as JSON "
     "text; a dir holding another result (a run, a comparison, ...) is refused unless force, which "
     "empties it first"},
    {NULL}};

PyTypeObject pyg_observer_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "granule._granule.Observer",
    .tp_basicsize = sizeof(pyg_observer),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Observer(scene): the observables named in the scene's [analysis] observables",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)observer_init,
    .tp_dealloc = (destructor)observer_dealloc,
    .tp_methods = observer_methods,
    .tp_getset = observer_getset,
};

PyObject *pyg_run(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"scene", "out", "force", NULL};
    PyObject *scene;
    const char *out = NULL;
    int force = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O!|zp", kwlist, &pyg_scene_type, &scene, &out,
                                     &force)) {
        return NULL;
    }
    gr_scene s = ((pyg_scene *)scene)->scene;
    if (out) {
        snprintf(s.out_dir, sizeof s.out_dir, "%s", out);
    }
    gr_run_options opt = {.force = force};
    gr_run_result res;
    gr_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = gr_run(&s, &opt, &res, &err);
    Py_END_ALLOW_THREADS if (rc) { return pyg_raise(&err); }
    return Py_BuildValue("{sssdsdsLsLsLsdsdss}", "dir", s.out_dir, "T_mean", res.T_mean, "T_stderr",
                         res.T_stderr, "samples", (long long)res.samples, "steps",
                         (long long)res.steps, "collisions", (long long)res.collisions,
                         "wall_seconds", res.wall_seconds, "particle_steps_per_second",
                         res.particle_steps_per_second, "kernel", res.kernel);
}
