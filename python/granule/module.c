/* granule._granule: the Python binding of libgranule (docs/python.md). Scenes are parsed by the
 * library (file or text, --set overrides), and every error is raised with granule's message. */
#define PYGRANULE_MAIN
#include "pygranule.h"

#include "granule_config.h"
#include "scene/scene_json.h"
#include <cjson/cJSON.h>

PyObject *pyg_error, *pyg_scene_error;

PyObject *pyg_raise(const gr_error *err)
{
    PyErr_SetString(err->code == GR_EINVAL ? pyg_scene_error : pyg_error, err->message);
    return NULL;
}

PyObject *pyg_view(PyObject *owner, const double *data, int n)
{
    npy_intp dims[1] = {n};
    PyObject *a = PyArray_SimpleNewFromData(1, dims, NPY_FLOAT64, (void *)data);
    if (!a) {
        return NULL;
    }
    PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    Py_INCREF(owner);
    if (PyArray_SetBaseObject((PyArrayObject *)a, owner) < 0) {
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

/* Scene(path=None, overrides=(), text=None, name="<text>") */
static int scene_init(pyg_scene *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"path", "overrides", "text", "name", NULL};
    const char *path = NULL, *text = NULL, *name = "<text>";
    Py_ssize_t text_len = 0;
    PyObject *overrides = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|zOz#s", kwlist, &path, &overrides, &text,
                                     &text_len, &name)) {
        return -1;
    }
    PyObject *empty = NULL;
    if (!overrides || overrides == Py_None) {
        overrides = empty = PyTuple_New(0);
    }
    PyObject *seq =
        overrides ? PySequence_Fast(overrides,
                                    "overrides must be a sequence of 'section.key=value' strings")
                  : NULL;
    Py_XDECREF(empty);
    if (!seq) {
        return -1;
    }
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    const char **sets = PyMem_Calloc((size_t)n + 1, sizeof(char *));
    int rc = sets ? 0 : -1;
    for (Py_ssize_t i = 0; i < n && !rc; i++) {
        Py_ssize_t len = 0;
        sets[i] = PyUnicode_AsUTF8AndSize(PySequence_Fast_GET_ITEM(seq, i), &len);
        rc = sets[i] ? 0 : -1;
        if (sets[i] && strlen(sets[i]) != (size_t)len) { /* a NUL byte would cut the value short */
            PyErr_Format(pyg_scene_error,
                         "--set %s...: control byte 0x00 at column %zu (an assignment is text)",
                         sets[i], strlen(sets[i]) + 1);
            rc = -1;
        }
    }
    if (rc) {
        PyMem_Free(sets);
        Py_DECREF(seq);
        return -1;
    }
    gr_error err = {0};
    rc = text ? gr_scene_load_buffer(&self->scene, name, text, (size_t)text_len, sets, (int)n, &err)
              : gr_scene_load(&self->scene, path, sets, (int)n, &err);
    PyMem_Free(sets);
    Py_DECREF(seq);
    if (rc) {
        pyg_raise(&err);
        return -1;
    }
    return 0;
}

static PyObject *scene_json(pyg_scene *self, PyObject *unused)
{
    cJSON *j = gr_scene_to_json(&self->scene);
    char *text = j ? cJSON_PrintUnformatted(j) : NULL;
    cJSON_Delete(j);
    if (!text) {
        return PyErr_NoMemory();
    }
    PyObject *s = PyUnicode_FromString(text);
    cJSON_free(text);
    return s;
}

static PyObject *scene_save(pyg_scene *self, PyObject *args)
{
    const char *dir;
    if (!PyArg_ParseTuple(args, "s", &dir)) {
        return NULL;
    }
    gr_error err = {0};
    if (gr_scene_save(&self->scene, dir, &err)) {
        return pyg_raise(&err);
    }
    Py_RETURN_NONE;
}

static PyObject *scene_get(pyg_scene *self, void *what)
{
    const gr_scene *s = &self->scene;
    switch ((int)(intptr_t)what) {
    case 0: return PyLong_FromLong(s->dim);
    case 1: return PyLong_FromLong(s->N);
    case 2: return PyFloat_FromDouble(s->L);
    case 3: return PyFloat_FromDouble(s->dt);
    case 4: return PyUnicode_FromString(s->source);
    case 5: return PyUnicode_FromString(s->out_dir);
    default: return PyUnicode_FromString(s->warnings);
    }
}

static PyGetSetDef scene_getset[] = {
    {"dim", (getter)scene_get, NULL, "dimension, 1 or 2", (void *)0},
    {"N", (getter)scene_get, NULL, "number of particles", (void *)1},
    {"L", (getter)scene_get, NULL, "box side or ring length, m (resolved)", (void *)2},
    {"dt", (getter)scene_get, NULL, "time step, s (0: derived from steps_per_contact by Sim)",
     (void *)3},
    {"source", (getter)scene_get, NULL, "where the scene came from", (void *)4},
    {"out_dir", (getter)scene_get, NULL, "output.dir", (void *)5},
    {"warnings", (getter)scene_get, NULL, "keys accepted without effect, one per line", (void *)6},
    {NULL}};

static PyMethodDef scene_methods[] = {
    {"to_json", (PyCFunction)scene_json, METH_NOARGS,
     "the resolved scene as JSON text (as summary.json holds it)"},
    {"save", (PyCFunction)scene_save, METH_VARARGS,
     "save(dir): write dir/scene.ini, every key as resolved"},
    {NULL}};

PyTypeObject pyg_scene_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "granule._granule.Scene",
    .tp_basicsize = sizeof(pyg_scene),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Scene(path=None, overrides=(), text=None, name='<text>'): a resolved granule scene",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)scene_init,
    .tp_methods = scene_methods,
    .tp_getset = scene_getset,
};

static PyMethodDef module_methods[] = {
    {"run", (PyCFunction)(void (*)(void))pyg_run, METH_VARARGS | METH_KEYWORDS,
     "run(scene, out=None, force=False) -> dict: `granule run` into out (default scene.out_dir)"},
    {NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "granule._granule",
                                        "Binding of libgranule (docs/python.md).", -1,
                                        module_methods};

PyMODINIT_FUNC PyInit__granule(void);
PyMODINIT_FUNC PyInit__granule(void)
{
    import_array();
    PyTypeObject *types[] = {&pyg_scene_type, &pyg_sim_type, &pyg_observer_type};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        if (PyType_Ready(types[i]) < 0) {
            return NULL;
        }
    }
    PyObject *m = PyModule_Create(&module_def);
    if (!m) {
        return NULL;
    }
    pyg_error = PyErr_NewExceptionWithDoc("granule.Error",
                                          "a granule library call failed (message from granule)",
                                          PyExc_RuntimeError, NULL);
    PyObject *bases = PyTuple_Pack(2, pyg_error, PyExc_ValueError);
    pyg_scene_error = bases ? PyErr_NewExceptionWithDoc("granule.SceneError",
                                                        "an invalid scene or argument", bases, NULL)
                            : NULL;
    Py_XDECREF(bases);
    if (!pyg_scene_error || PyModule_AddObjectRef(m, "Error", pyg_error) < 0 ||
        PyModule_AddObjectRef(m, "SceneError", pyg_scene_error) < 0 ||
        PyModule_AddObjectRef(m, "Scene", (PyObject *)&pyg_scene_type) < 0 ||
        PyModule_AddObjectRef(m, "Sim", (PyObject *)&pyg_sim_type) < 0 ||
        PyModule_AddObjectRef(m, "Observer", (PyObject *)&pyg_observer_type) < 0 ||
        PyModule_AddStringConstant(m, "version", GR_VERSION) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
