// common.c — what the module's files share, at the bottom of their calls (module.c -> scene.c -> render.c ->
// here): glint.Error and raising it with the library's message, the busy check of a scene, NumPy float arrays.
#include "glintpy.h"

PyObject *glintpy_error;

PyObject *glintpy_raise(const glint_error *err) {
    PyErr_SetString(glintpy_error, err->message);
    return NULL;
}

int glintpy_scene_check_idle(glintpy_scene *self, const char *what) {
    if (!self->busy) return 0;
    PyErr_Format(glintpy_error, "%s: the scene is being rendered on another thread", what);
    return -1;
}

PyArrayObject *glintpy_float_array(PyObject *value, const char *what, const char *name, int ndim) {
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(value);
    if (!a) return NULL;
    char kind = PyArray_DESCR(a)->kind;
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        PyErr_Format(PyExc_TypeError, "%s: %s: expected an array of numbers (float32 or float64), got dtype %s", what,
                     name, PyArray_DESCR(a)->typeobj->tp_name);
        Py_DECREF(a);
        return NULL;
    }
    if (PyArray_NDIM(a) != ndim) {
        PyErr_Format(PyExc_ValueError, "%s: %s: expected a %d-dimensional array, got %d dimensions", what, name, ndim,
                     PyArray_NDIM(a));
        Py_DECREF(a);
        return NULL;
    }
    // float32, C order: float64 values round to the nearest float, as the scene reader rounds decimal text
    PyArrayObject *f = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)a, NPY_FLOAT32, NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(a);
    return f;
}
