/* granule.Sim: a simulation stepped from Python. Positions, velocities and contact forces are
 * numpy views on the simulation's own structure-of-arrays (read-only, no copy); each view holds a
 * reference to the Sim, so the arrays outlive any Python name bound to it. */
#include "pygranule.h"

typedef struct {
    PyObject_HEAD gr_sim *sim;
    PyObject *scene; /* the Scene it was created from */
} pyg_sim;

static int sim_init(pyg_sim *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"scene", NULL};
    PyObject *scene;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O!", kwlist, &pyg_scene_type, &scene)) {
        return -1;
    }
    if (self->sim) {
        PyErr_SetString(pyg_error, "Sim is already initialised");
        return -1;
    }
    gr_error err = {0};
    if (gr_sim_create(&((pyg_scene *)scene)->scene, &self->sim, &err)) {
        pyg_raise(&err);
        return -1;
    }
    Py_INCREF(scene);
    self->scene = scene;
    return 0;
}

static void sim_dealloc(pyg_sim *self)
{
    gr_sim_free(self->sim);
    Py_XDECREF(self->scene);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static bool ready(pyg_sim *self)
{
    if (!self->sim) {
        PyErr_SetString(pyg_error, "Sim was not initialised");
    }
    return self->sim != NULL;
}

static PyObject *sim_step(pyg_sim *self, PyObject *args)
{
    long long n = 1;
    if (!ready(self) || !PyArg_ParseTuple(args, "|L", &n)) {
        return NULL;
    }
    if (n < 0) {
        PyErr_SetString(pyg_scene_error, "step: the number of steps must be >= 0");
        return NULL;
    }
    gr_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS rc = gr_sim_step(self->sim, (int64_t)n, &err);
    Py_END_ALLOW_THREADS if (rc) { return pyg_raise(&err); }
    Py_RETURN_NONE;
}

static PyObject *sim_ledger(pyg_sim *self, PyObject *unused)
{
    if (!ready(self)) {
        return NULL;
    }
    gr_ledger l = gr_sim_ledger(self->sim);
    /* potential: gravity's -M sum g . r ([gravity]; 0 without), wall_work: the moving walls' work
     * ([boundary] vibrate; 0 without), both part of the balance */
    /* rotational: the spins' sum I |w|^2 / 2, part of kinetic (0 without rotation) */
    return Py_BuildValue(
        "{sdsdsdsdsdsdsdsdsdsdsdsdsdsd}", "kinetic", l.kinetic, "rotational", l.rotational,
        "elastic", l.elastic, "initial", l.initial, "injected", l.injected, "dissipated_normal",
        l.dissipated_normal, "dissipated_tangential", l.dissipated_tangential,
        "dissipated_friction", l.dissipated_friction, "dissipated_drag", l.dissipated_drag,
        "removed_com", l.removed_com, "potential", l.potential, "wall_work", l.wall_work,
        "dissipated", gr_ledger_dissipated(&l), "residual", gr_ledger_residual(&l));
}

/* The core's state as bytes (gr_sim_state_save): pickle it, keep it, restore it into a Sim of
 * the same scene to step on bit-identically. */
static PyObject *sim_state(pyg_sim *self, PyObject *unused)
{
    if (!ready(self)) {
        return NULL;
    }
    void *data = NULL;
    size_t len = 0;
    gr_error err = {0};
    if (gr_sim_state_save(self->sim, &data, &len, &err)) {
        return pyg_raise(&err);
    }
    PyObject *b = PyBytes_FromStringAndSize(data, (Py_ssize_t)len);
    free(data);
    return b;
}

static PyObject *sim_restore(pyg_sim *self, PyObject *args)
{
    Py_buffer buf;
    if (!ready(self) || !PyArg_ParseTuple(args, "y*", &buf)) {
        return NULL;
    }
    gr_error err = {0};
    int rc = gr_sim_state_load(self->sim, buf.buf, (size_t)buf.len, &err);
    PyBuffer_Release(&buf);
    if (rc) {
        /* a refused state may have been read in part: start the Sim afresh from its scene */
        gr_sim *fresh = NULL;
        gr_error e2 = {0};
        if (gr_sim_create(&((pyg_scene *)self->scene)->scene, &fresh, &e2) == GR_OK) {
            gr_sim_free(self->sim);
            self->sim = fresh;
        }
        return pyg_raise(&err);
    }
    Py_RETURN_NONE;
}

enum { F_X, F_Y, F_VX, F_VY, F_FX, F_FY, F_Z, F_VZ, F_WX, F_WY, F_WZ, F_RADII, F_MASSES };

/* species (docs/mixtures.md): each grain's species 0, 1, ... as a read-only int view; None
 * for one species */
static PyObject *sim_species(pyg_sim *self, void *unused)
{
    (void)unused;
    if (!ready(self)) {
        return NULL;
    }
    gr_particles p = gr_sim_particles(self->sim);
    if (!p.species) {
        Py_RETURN_NONE;
    }
    npy_intp dims[1] = {p.n};
    PyObject *a = PyArray_SimpleNewFromData(1, dims, NPY_INT, (void *)p.species);
    if (!a) {
        return NULL;
    }
    PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    Py_INCREF(self);
    if (PyArray_SetBaseObject((PyArrayObject *)a, (PyObject *)self) < 0) {
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

static PyObject *sim_array(pyg_sim *self, void *which)
{
    if (!ready(self)) {
        return NULL;
    }
    gr_particles p = gr_sim_particles(self->sim);
    const double *fx, *fy, *wx, *wy, *wz;
    gr_sim_forces(self->sim, &fx, &fy);
    gr_sim_spins(self->sim, &wx, &wy, &wz);
    const double *a[] = {p.x, p.y, p.vx, p.vy, fx, fy, p.z, p.vz, wx, wy, wz, p.radii, p.masses};
    const double *data = a[(int)(intptr_t)which];
    if (!data) {
        Py_RETURN_NONE; /* y, vy, fy in 1D; z, vz, wx, wy except in 3D; w without rotation; radii,
                           masses of one species */
    }
    return pyg_view((PyObject *)self, data, p.n);
}

enum { G_T, G_STEPS, G_DT, G_N, G_DIM, G_L, G_KERNEL, G_COLL, G_TEMP, G_SCENE, G_RADIUS, G_MASS };

static PyObject *sim_get(pyg_sim *self, void *which)
{
    if (!ready(self)) {
        return NULL;
    }
    const gr_sim *s = self->sim;
    gr_particles p = gr_sim_particles(s);
    switch ((int)(intptr_t)which) {
    case G_T: return PyFloat_FromDouble(gr_sim_time(s));
    case G_STEPS: return PyLong_FromLongLong(gr_sim_steps(s));
    case G_DT: return PyFloat_FromDouble(gr_sim_dt(s));
    case G_N: return PyLong_FromLong(p.n);
    case G_DIM: return PyLong_FromLong(p.dim);
    case G_L: return PyFloat_FromDouble(p.L);
    case G_KERNEL: return PyUnicode_FromString(gr_sim_kernel(s));
    case G_COLL: return PyLong_FromLongLong(gr_sim_collisions(s));
    case G_TEMP: return PyFloat_FromDouble(gr_sim_temperature(s));
    case G_RADIUS: return PyFloat_FromDouble(p.radius);
    case G_MASS: return PyFloat_FromDouble(p.mass);
    default: Py_INCREF(self->scene); return self->scene;
    }
}

#define VIEW(name, which, doc)                                                                     \
    {                                                                                              \
        name, (getter)sim_array, NULL, doc " (read-only numpy view, no copy)", (void *)(which)     \
    }
#define GET(name, which, doc)                                                                      \
    {                                                                                              \
        name, (getter)sim_get, NULL, doc, (void *)(which)                                          \
    }
static PyGetSetDef sim_getset[] = {
    VIEW("x", F_X, "x positions, m"),
    VIEW("y", F_Y, "y positions, m (None in 1D)"),
    VIEW("vx", F_VX, "x velocities, m/s"),
    VIEW("vy", F_VY, "y velocities, m/s (None in 1D)"),
    VIEW("fx", F_FX, "x contact forces of the last evaluation, N"),
    VIEW("fy", F_FY, "y contact forces of the last evaluation, N (None in 1D)"),
    VIEW("z", F_Z, "z positions, m (3D only, else None)"),
    VIEW("vz", F_VZ, "z velocities, m/s (3D only, else None)"),
    VIEW("wx", F_WX, "x angular velocities, rad/s (3D with rotation only, else None)"),
    VIEW("wy", F_WY, "y angular velocities, rad/s (3D with rotation only, else None)"),
    VIEW("wz", F_WZ,
         "z angular velocities, rad/s (2D: the discs' counterclockwise spin; None without "
         "rotation)"),
    VIEW("radii", F_RADII, "each grain's radius, m ([species]; None for one species)"),
    VIEW("masses", F_MASSES, "each grain's mass, kg ([species]; None for one species)"),
    {"species", (getter)sim_species, NULL,
     "each grain's species 0, 1, ... ([species]; None for one species; read-only numpy view, no "
     "copy)",
     NULL},
    GET("t", G_T, "simulated time, s"),
    GET("steps", G_STEPS, "steps taken"),
    GET("dt", G_DT, "time step, s"),
    GET("N", G_N, "number of particles"),
    GET("dim", G_DIM, "dimension"),
    GET("L", G_L, "box side, m"),
    GET("kernel", G_KERNEL, "the contact kernel chosen"),
    GET("collisions", G_COLL, "contacts started"),
    GET("temperature", G_TEMP, "granular temperature (2.19), m^2/s^2"),
    GET("scene", G_SCENE, "the Scene"),
    GET("radius", G_RADIUS, "particle radius, m (with species: the largest)"),
    GET("mass", G_MASS, "particle mass, kg (with species: the mean)"),
    {NULL}};

/* The walls' normal impulses since creation (gr_sim_wall_impulse) as {"x_lo", "x_hi", "y_lo",
 * "y_hi", "z_lo", "z_hi"}: N s, only the axes that have walls; {} in a periodic box. */
static PyObject *sim_wall_impulse(pyg_sim *self, PyObject *unused)
{
    if (!ready(self)) {
        return NULL;
    }
    double J[6];
    gr_sim_wall_impulse(self->sim, J);
    const gr_scene *sc = &((pyg_scene *)self->scene)->scene;
    PyObject *d = PyDict_New();
    static const char *const names[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
    for (int k = 0; d && k < 6; k++) {
        if (sc->boundary[k / 2]) {
            PyObject *v = PyFloat_FromDouble(J[k]);
            if (!v || PyDict_SetItemString(d, names[k], v)) {
                Py_XDECREF(v);
                Py_DECREF(d);
                return NULL;
            }
            Py_DECREF(v);
        }
    }
    return d;
}

static PyMethodDef sim_methods[] = {
    {"wall_impulse", (PyCFunction)sim_wall_impulse, METH_NOARGS,
     "wall_impulse(): the normal impulse each wall has taken from the grains since the start, N s, "
     "as a dict {'y_lo': ..., 'y_hi': ...} of the axes with walls; the difference of two calls "
     "over "
     "the time between them is the wall's mean force (> 0: pushed outwards)"},
    {"step", (PyCFunction)sim_step, METH_VARARGS,
     "step(n=1): advance n time steps (the GIL is released)"},
    {"ledger", (PyCFunction)sim_ledger, METH_NOARGS, "the energy ledger, J, as a dict"},
    {"state", (PyCFunction)sim_state, METH_NOARGS,
     "state(): the complete simulation state as bytes (exact restarts)"},
    {"restore", (PyCFunction)sim_restore, METH_VARARGS,
     "restore(state): continue from bytes of state() taken from a Sim of the same scene; stepping "
     "on is bit-identical"},
    {NULL}};

PyTypeObject pyg_sim_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "granule._granule.Sim",
    .tp_basicsize = sizeof(pyg_sim),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Sim(scene): a simulation of a Scene, placed as `granule run` places it",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)sim_init,
    .tp_dealloc = (destructor)sim_dealloc,
    .tp_methods = sim_methods,
    .tp_getset = sim_getset,
};

int pyg_sim_particles(PyObject *o, gr_particles *p, double *t)
{
    if (!PyObject_TypeCheck(o, &pyg_sim_type) || !((pyg_sim *)o)->sim) {
        PyErr_SetString(PyExc_TypeError, "expected an initialised granule Sim");
        return -1;
    }
    *p = gr_sim_particles(((pyg_sim *)o)->sim);
    *t = gr_sim_time(((pyg_sim *)o)->sim);
    return 0;
}
