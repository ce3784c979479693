// scene.c — glint.Scene: a glint_scene built from dicts and NumPy arrays through the scene API, its size and
// warnings; rendering is in render.c.
#include "glintpy.h"

#include <stdint.h>
#include <string.h>

PyObject *glintpy_scene_wrap(glint_scene *scene) {
    glintpy_scene *self = PyObject_New(glintpy_scene, &glintpy_scene_type);
    if (!self) {
        glint_scene_free(scene);
        return NULL;
    }
    self->scene = scene;
    self->busy = 0;
    return (PyObject *)self;
}

static PyObject *scene_new(PyTypeObject *type, PyObject *args, PyObject *kwargs) {
    (void)type;
    static char *keywords[] = {"name", NULL};
    const char *name = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|z:Scene", keywords, &name)) return NULL;
    glint_scene *scene = NULL;
    glint_error err;
    if (glint_scene_new(name, &scene, &err) != GLINT_OK) return glintpy_raise(&err);
    return glintpy_scene_wrap(scene);
}

static void scene_dealloc(glintpy_scene *self) {
    glint_scene_free(self->scene);
    PyObject_Free(self);
}

static PyObject *scene_repr(glintpy_scene *self) {
    int w, h;
    glint_scene_size(self->scene, &w, &h);
    return PyUnicode_FromFormat("<glint.Scene %dx%d>", w, h);
}

static PyObject *scene_size(glintpy_scene *self, void *closure) {
    (void)closure;
    int w, h;
    glint_scene_size(self->scene, &w, &h);
    return Py_BuildValue("(ii)", w, h);
}

static PyObject *scene_warnings(glintpy_scene *self, void *closure) {
    (void)closure;
    size_t n = glint_scene_warning_count(self->scene);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; i++) {
        PyObject *s = PyUnicode_DecodeUTF8(glint_scene_warning(self->scene, i),
                                           (Py_ssize_t)strlen(glint_scene_warning(self->scene, i)), "replace");
        if (!s) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, s);
    }
    return list;
}

static PyObject *scene_render(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return glintpy_scene_render(self, args, kwargs);
}

// The parameters of a dict, through its JSON text; NULL with the error raised.
static glint_params *params_of(PyObject *dict, const char *what) {
    char *json = glintpy_json(dict, what);
    if (!json) return NULL;
    glint_params *params = NULL;
    glint_error err;
    glint_status st = glint_params_parse(json, &params, &err);
    PyMem_Free(json);
    if (st != GLINT_OK) {
        glintpy_raise(&err);
        return NULL;
    }
    return params;
}

typedef glint_status (*set_fn)(glint_scene *, const glint_params *, glint_error *);
typedef glint_status (*add_named_fn)(glint_scene *, const char *, const glint_params *, glint_error *);

// The shape of set_render, set_camera, add_object, add_light (named: NULL) and add_texture, add_material
// (unnamed: NULL): an optional name, then a dict or keywords.
static PyObject *scene_call(glintpy_scene *self, PyObject *args, PyObject *kwargs, const char *what, set_fn set,
                            add_named_fn add_named) {
    const char *name = NULL;
    PyObject *positional = NULL;
    char format[64];
    snprintf(format, sizeof format, "%s|O:%s", add_named ? "s" : "", what);
    if (add_named ? !PyArg_ParseTuple(args, format, &name, &positional) : !PyArg_ParseTuple(args, format, &positional))
        return NULL;
    if (glintpy_scene_check_idle(self, what) < 0) return NULL;
    PyObject *dict = glintpy_dict_argument(positional, kwargs, what);
    if (!dict) return NULL;
    glint_params *params = params_of(dict, what);
    Py_DECREF(dict);
    if (!params) return NULL;
    glint_error err;
    glint_status st = add_named ? add_named(self->scene, name, params, &err) : set(self->scene, params, &err);
    glint_params_free(params);
    if (st != GLINT_OK) return glintpy_raise(&err);
    Py_RETURN_NONE;
}

static PyObject *scene_set_render(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "set_render", glint_scene_set_render, NULL);
}
static PyObject *scene_set_camera(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "set_camera", glint_scene_set_camera, NULL);
}
static PyObject *scene_add_object(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "add_object", glint_scene_add_object, NULL);
}
static PyObject *scene_add_light(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "add_light", glint_scene_add_light, NULL);
}
static PyObject *scene_add_texture(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "add_texture", NULL, glint_scene_add_texture);
}
static PyObject *scene_add_material(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    return scene_call(self, args, kwargs, "add_material", NULL, glint_scene_add_material);
}

// An integer array of `columns` columns (0: one dimension) whose values lie in [0, limit), as uint32 (a copy
// the caller PyMem_Free's); NULL with TypeError (not integers), ValueError (shape, a value out of range).
static uint32_t *index_array(PyObject *value, const char *name, int columns, Py_ssize_t rows, size_t limit,
                             const char *limit_what, Py_ssize_t *count) {
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(value);
    if (!a) return NULL;
    uint32_t *out = NULL;
    char kind = PyArray_DESCR(a)->kind;
    int ndim = columns ? 2 : 1;
    if (kind != 'i' && kind != 'u') {
        PyErr_Format(PyExc_TypeError, "add_mesh: %s: expected an array of integers, got dtype %s", name,
                     PyArray_DESCR(a)->typeobj->tp_name);
    } else if (PyArray_NDIM(a) != ndim || (columns && PyArray_DIM(a, 1) != columns) ||
               (rows >= 0 && PyArray_DIM(a, 0) != rows)) {
        if (columns)
            PyErr_Format(PyExc_ValueError, "add_mesh: %s: expected shape (M, %d), got %d dimensions%s", name, columns,
                         PyArray_NDIM(a), PyArray_NDIM(a) == 2 ? " of another shape" : "");
        else
            PyErr_Format(PyExc_ValueError, "add_mesh: %s: expected shape (%zd,): one value a triangle", name, rows);
    } else {
        // int64 holds every index a mesh can have; a uint64 beyond it reads as negative: out of range either way
        PyArrayObject *wide = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)a, NPY_INT64, NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
        if (wide) {
            Py_ssize_t n = (Py_ssize_t)PyArray_SIZE(wide);
            const int64_t *v = PyArray_DATA(wide);
            out = PyMem_Malloc(n > 0 ? (size_t)n * sizeof *out : 1);
            if (!out) PyErr_NoMemory();
            for (Py_ssize_t i = 0; out && i < n; i++) {
                if (v[i] < 0 || (uint64_t)v[i] >= limit) {
                    if (columns)
                        PyErr_Format(PyExc_ValueError, "add_mesh: %s[%zd, %zd] = %lld is out of range [0, %zu): %s", name,
                                     i / columns, i % columns, (long long)v[i], limit, limit_what);
                    else
                        PyErr_Format(PyExc_ValueError, "add_mesh: %s[%zd] = %lld is out of range [0, %zu): %s", name, i,
                                     (long long)v[i], limit, limit_what);
                    PyMem_Free(out);
                    out = NULL;
                    break;
                }
                out[i] = (uint32_t)v[i];
            }
            *count = columns ? n / columns : n;
            Py_DECREF(wide);
        }
    }
    Py_DECREF(a);
    return out;
}

// A float array of shape (rows, columns) (rows < 0: any), or NULL with the error raised.
static PyArrayObject *float_rows(PyObject *value, const char *name, int columns, Py_ssize_t rows) {
    PyArrayObject *a = glintpy_float_array(value, "add_mesh", name, 2);
    if (a && (PyArray_DIM(a, 1) != columns || (rows >= 0 && PyArray_DIM(a, 0) != rows))) {
        if (rows >= 0)
            PyErr_Format(PyExc_ValueError, "add_mesh: %s: expected shape (%zd, %d): one row a vertex, got (%zd, %zd)",
                         name, rows, columns, (Py_ssize_t)PyArray_DIM(a, 0), (Py_ssize_t)PyArray_DIM(a, 1));
        else
            PyErr_Format(PyExc_ValueError, "add_mesh: %s: expected shape (N, %d), got (%zd, %zd)", name, columns,
                         (Py_ssize_t)PyArray_DIM(a, 0), (Py_ssize_t)PyArray_DIM(a, 1));
        Py_CLEAR(a);
    }
    return a;
}

static PyObject *scene_add_mesh(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    static char *keywords[] = {"name", "positions", "indices", "normals", "uvs", "face_materials", "materials", "flat",
                               NULL};
    const char *name;
    PyObject *positions_in, *indices_in, *normals_in = Py_None, *uvs_in = Py_None, *faces_in = Py_None,
                                         *materials_in = Py_None;
    int flat = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "sOO|OOOOp:add_mesh", keywords, &name, &positions_in, &indices_in,
                                     &normals_in, &uvs_in, &faces_in, &materials_in, &flat))
        return NULL;
    if (glintpy_scene_check_idle(self, "add_mesh") < 0) return NULL;
    PyObject *result = NULL;
    PyArrayObject *positions = NULL, *normals = NULL, *uvs = NULL;
    uint32_t *indices = NULL, *faces = NULL;
    PyObject *materials = NULL;
    const char **material_names = NULL;
    Py_ssize_t material_count = 0, triangles = 0, face_count = 0;

    positions = float_rows(positions_in, "positions", 3, -1);
    if (!positions) goto done;
    Py_ssize_t vertices = (Py_ssize_t)PyArray_DIM(positions, 0);
    if (normals_in != Py_None && !(normals = float_rows(normals_in, "normals", 3, vertices))) goto done;
    if (uvs_in != Py_None && !(uvs = float_rows(uvs_in, "uvs", 2, vertices))) goto done;
    indices = index_array(indices_in, "indices", 3, -1, (size_t)vertices, "an index of positions", &triangles);
    if (!indices) goto done;
    if (materials_in != Py_None) {
        materials = PySequence_Tuple(materials_in);
        if (!materials) goto done;
        material_count = PyTuple_GET_SIZE(materials);
        material_names = PyMem_Calloc(material_count > 0 ? (size_t)material_count : 1, sizeof *material_names);
        if (!material_names) {
            PyErr_NoMemory();
            goto done;
        }
        for (Py_ssize_t i = 0; i < material_count; i++) {
            PyObject *m = PyTuple_GET_ITEM(materials, i);
            if (!PyUnicode_Check(m)) {
                PyErr_Format(PyExc_TypeError, "add_mesh: materials[%zd]: expected a material name (str), got %.100s", i,
                             Py_TYPE(m)->tp_name);
                goto done;
            }
            if (!(material_names[i] = PyUnicode_AsUTF8(m))) goto done;
        }
    }
    if (faces_in != Py_None) {
        if (!materials) {
            PyErr_SetString(PyExc_TypeError, "add_mesh: face_materials needs materials, the names its values index");
            goto done;
        }
        faces = index_array(faces_in, "face_materials", 0, triangles, (size_t)material_count, "an index of materials",
                            &face_count);
        if (!faces) goto done;
    }
    glint_mesh_data mesh = {
        .vertex_count = (size_t)vertices,
        .positions = PyArray_DATA(positions),
        .normals = normals ? PyArray_DATA(normals) : NULL,
        .uvs = uvs ? PyArray_DATA(uvs) : NULL,
        .triangle_count = (size_t)triangles,
        .indices = indices,
        .face_materials = faces,
        .materials = material_names,
        .material_count = (size_t)material_count,
        .flat = flat != 0,
    };
    glint_error err;
    if (glint_scene_add_mesh(self->scene, name, &mesh, &err) != GLINT_OK) {
        glintpy_raise(&err);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    Py_XDECREF(positions);
    Py_XDECREF(normals);
    Py_XDECREF(uvs);
    Py_XDECREF(materials);
    PyMem_Free(indices);
    PyMem_Free(faces);
    PyMem_Free(material_names);
    return result;
}

static PyObject *scene_add_image(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    static char *keywords[] = {"name", "pixels", "encoding", "filter", NULL};
    const char *name;
    PyObject *pixels_in, *encoding = Py_None, *filter = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "sO|$OO:add_image", keywords, &name, &pixels_in, &encoding, &filter))
        return NULL;
    if (glintpy_scene_check_idle(self, "add_image") < 0) return NULL;
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(pixels_in);
    if (!a) return NULL;
    PyObject *result = NULL;
    PyArrayObject *pixels = NULL;
    glint_params *options = NULL;
    int ndim = PyArray_NDIM(a);
    npy_intp channels = ndim == 3 ? PyArray_DIM(a, 2) : 1;
    bool bytes = PyArray_TYPE(a) == NPY_UINT8;
    if (!bytes && PyArray_DESCR(a)->kind != 'f') {
        PyErr_Format(PyExc_TypeError, "add_image: pixels: expected uint8 (8-bit) or float32 (linear) values, got dtype %s",
                     PyArray_DESCR(a)->typeobj->tp_name);
        goto done;
    }
    if ((ndim != 2 && ndim != 3) || (channels != 1 && channels != 3 && channels != 4) || PyArray_DIM(a, 0) > INT32_MAX ||
        PyArray_DIM(a, 1) > INT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "add_image: pixels: expected shape (H, W) or (H, W, C) with C = 1, 3 or 4");
        goto done;
    }
    pixels = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)a, bytes ? NPY_UINT8 : NPY_FLOAT32,
                                               NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    if (!pixels) goto done;
    if (encoding != Py_None || filter != Py_None) {
        PyObject *d = PyDict_New();
        if (!d || (encoding != Py_None && PyDict_SetItemString(d, "encoding", encoding) < 0) ||
            (filter != Py_None && PyDict_SetItemString(d, "filter", filter) < 0)) {
            Py_XDECREF(d);
            goto done;
        }
        options = params_of(d, "add_image");
        Py_DECREF(d);
        if (!options) goto done;
    }
    glint_pixels px = {.width = (int)PyArray_DIM(pixels, 1), .height = (int)PyArray_DIM(pixels, 0),
                       .channels = (int)channels, .values = bytes ? NULL : PyArray_DATA(pixels),
                       .bytes = bytes ? PyArray_DATA(pixels) : NULL};
    glint_error err;
    if (glint_scene_add_image(self->scene, name, &px, options, &err) != GLINT_OK) {
        glintpy_raise(&err);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    glint_params_free(options);
    Py_XDECREF(pixels);
    Py_DECREF(a);
    return result;
}

#define METHOD(name, doc) {#name, (PyCFunction)(void (*)(void))scene_##name, METH_VARARGS | METH_KEYWORDS, doc}
static PyMethodDef SCENE_METHODS[] = {
    METHOD(render, "render(*, spp, threads, seed, width, height, max_depth, region, accel, output_encoding, "
                   "time_limit, aov, progress, checkpoint, resume, trace) -> float32 (H, W, 3) array, or (array, dict "
                   "of AOV arrays) when aov is given. Overrides apply to this render only."),
    METHOD(set_render, "set_render(dict or **keys): the scene file's \"render\" object"),
    METHOD(set_camera, "set_camera(dict or **keys): the scene file's \"camera\" object"),
    METHOD(add_texture, "add_texture(name, dict or **keys): a named texture, as in \"textures\""),
    METHOD(add_material, "add_material(name, dict or **keys): a named material, as in \"materials\""),
    METHOD(add_object, "add_object(dict or **keys): one element of \"objects\""),
    METHOD(add_light, "add_light(dict or **keys): one element of \"lights\""),
    METHOD(add_mesh, "add_mesh(name, positions, indices, normals=None, uvs=None, face_materials=None, "
                     "materials=None, flat=False): a named mesh from arrays (copied), placed by add_object({'type': 'mesh', "
                     "'mesh': name, ...})"),
    METHOD(add_image, "add_image(name, pixels, *, encoding=None, filter=None): a named image texture from an "
                      "(H, W[, C]) array of uint8 or float32, row 0 at the top"),
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef SCENE_GETSET[] = {
    {"size", (getter)scene_size, NULL, "(width, height) the scene renders at", NULL},
    {"warnings", (getter)scene_warnings, NULL, "the warnings collected while the scene was read or built", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject glintpy_scene_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "glint.Scene",
    .tp_basicsize = sizeof(glintpy_scene),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Scene(name=None): an empty scene, built with set_*/add_* calls; glint.load and glint.parse read one",
    .tp_new = scene_new,
    .tp_dealloc = (destructor)scene_dealloc,
    .tp_repr = (reprfunc)scene_repr,
    .tp_methods = SCENE_METHODS,
    .tp_getset = SCENE_GETSET,
};
