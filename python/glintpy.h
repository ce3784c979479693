// glintpy.h — private to the Python module `glint` (docs/python.md): the Scene object, glint.Error, and the parts
// that module.c, scene.c, params.c and render.c share. The module uses glint.h alone, as any client would.
#ifndef GLINTPY_H
#define GLINTPY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
// One NumPy C-API table for the module's files: module.c imports it (GLINTPY_IMPORT_ARRAY), the others use it.
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL glintpy_ARRAY_API
#ifndef GLINTPY_IMPORT_ARRAY
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "glint.h"

/// glint.Error: every failure the C library reports, with its message.
extern PyObject *glintpy_error;

/// glint.Scene: owns one glint_scene. `busy` is set (under the GIL) while a render of it runs with the GIL
/// released: the library renders a scene from one thread at a time and nothing may change it meanwhile.
typedef struct glintpy_scene {
    PyObject_HEAD
    glint_scene *scene;
    int busy;
} glintpy_scene;

extern PyTypeObject glintpy_scene_type;

/// Raises glint.Error with the library's message; returns NULL (for `return glintpy_raise(&err);`).
PyObject *glintpy_raise(const glint_error *err);
/// A new Scene object owning `scene` (freed on failure).
PyObject *glintpy_scene_wrap(glint_scene *scene);
/// Raises glint.Error (and returns -1) when the scene is being rendered on another thread; 0 otherwise.
int glintpy_scene_check_idle(glintpy_scene *self, const char *what);

/// `value` as a C-ordered float32 array of `ndim` dimensions (float64 values rounded to float; integers taken as
/// numbers), or NULL with TypeError (not numbers) or ValueError (dimensions) naming `what` and `name`.
PyArrayObject *glintpy_float_array(PyObject *value, const char *what, const char *name, int ndim);

/// Scene.render(**overrides): the image as a float32 (H, W, 3) array, with a dict of AOV arrays when asked.
PyObject *glintpy_scene_render(glintpy_scene *self, PyObject *args, PyObject *kwargs);

/// The JSON text of a Python value for the scene API: dicts with str keys, lists and tuples, str, bool, int,
/// finite float, NumPy scalars and arrays of bool/int/float. Anything else raises TypeError (ValueError for a
/// non-finite number or nesting too deep) naming `what` (the method) and the key path. The text is
/// PyMem_Malloc'ed, NUL-terminated; NULL on error.
char *glintpy_json(PyObject *value, const char *what);

/// The dict a set_*/add_* method takes: its one positional dict, or its keywords (not both); a new reference
/// or NULL with TypeError. `what` names the method in messages.
PyObject *glintpy_dict_argument(PyObject *positional, PyObject *kwargs, const char *what);

#endif
