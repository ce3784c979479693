// module.c — the Python module `glint` (docs/python.md): load, parse, write, version, glint.Error and glint.Scene.
#define GLINTPY_IMPORT_ARRAY
#include "glintpy.h"

#include <string.h>

// The load options' thread count: 0 (all CPUs) to 256, as --threads.
static int thread_count(long threads, const char *what) {
    if (threads < 0 || threads > 256) {
        PyErr_Format(PyExc_ValueError, "%s: threads=%ld is out of range, expected an integer in [0, 256]", what,
                     threads);
        return -1;
    }
    return 0;
}

static PyObject *py_load(PyObject *module, PyObject *args, PyObject *kwargs) {
    (void)module;
    static char *keywords[] = {"path", "threads", NULL};
    PyObject *path = NULL;
    long threads = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O&|$l:load", keywords, PyUnicode_FSConverter, &path, &threads))
        return NULL;
    if (thread_count(threads, "load") < 0) {
        Py_DECREF(path);
        return NULL;
    }
    glint_load_options opt = {.threads = (int)threads};
    glint_scene *scene = NULL;
    glint_error err;
    glint_status st;
    // Reading a large mesh takes a while: other Python threads run meanwhile
    Py_BEGIN_ALLOW_THREADS
    st = glint_scene_load_with(PyBytes_AS_STRING(path), &opt, &scene, &err);
    Py_END_ALLOW_THREADS
    Py_DECREF(path);
    if (st != GLINT_OK) return glintpy_raise(&err);
    return glintpy_scene_wrap(scene);
}

static PyObject *py_parse(PyObject *module, PyObject *args, PyObject *kwargs) {
    (void)module;
    static char *keywords[] = {"text", "name", "threads", NULL};
    const char *text;
    Py_ssize_t length;
    const char *name = "<scene>";
    long threads = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "s#|s$l:parse", keywords, &text, &length, &name, &threads))
        return NULL;
    if (thread_count(threads, "parse") < 0) return NULL;
    glint_load_options opt = {.threads = (int)threads};
    glint_scene *scene = NULL;
    glint_error err;
    if (glint_scene_parse_with(name, text, (size_t)length, &opt, &scene, &err) != GLINT_OK) return glintpy_raise(&err);
    return glintpy_scene_wrap(scene);
}

// The formats glint.write names (None: the file name's extension chooses).
static const struct {
    const char *name;
    glint_format format;
} FORMATS[] = {
    {"png", GLINT_FORMAT_PNG}, {"ppm", GLINT_FORMAT_PPM}, {"ppm-ascii", GLINT_FORMAT_PPM_ASCII},
    {"pfm", GLINT_FORMAT_PFM}, {"exr", GLINT_FORMAT_EXR}, {"exr-half", GLINT_FORMAT_EXR_HALF},
    {"hdr", GLINT_FORMAT_HDR},
};

static PyObject *py_write(PyObject *module, PyObject *args, PyObject *kwargs) {
    (void)module;
    static char *keywords[] = {"path", "image", "encoding", "format", NULL};
    PyObject *path = NULL, *image = NULL;
    const char *encoding = NULL, *format_name = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O&O|z$z:write", keywords, PyUnicode_FSConverter, &path, &image,
                                     &encoding, &format_name))
        return NULL;
    PyObject *result = NULL;
    PyArrayObject *rgb = NULL;
    glint_format format = GLINT_FORMAT_AUTO;
    if (format_name) {
        size_t i = 0;
        while (i < sizeof FORMATS / sizeof FORMATS[0] && strcmp(FORMATS[i].name, format_name) != 0) i++;
        if (i == sizeof FORMATS / sizeof FORMATS[0]) {
            PyErr_Format(PyExc_ValueError,
                         "write: unknown format '%s', expected png, ppm, ppm-ascii, pfm, exr, exr-half or hdr",
                         format_name);
            goto done;
        }
        format = FORMATS[i].format;
    }
    rgb = glintpy_float_array(image, "write", "image", 3);
    if (!rgb) goto done;
    if (PyArray_DIM(rgb, 2) != 3 || PyArray_DIM(rgb, 0) < 1 || PyArray_DIM(rgb, 1) < 1 ||
        PyArray_DIM(rgb, 0) > 16384 || PyArray_DIM(rgb, 1) > 16384) {
        PyErr_Format(PyExc_ValueError, "write: image: expected shape (H, W, 3) with 1 <= H, W <= 16384, got (%zd, %zd, %zd)",
                     (Py_ssize_t)PyArray_DIM(rgb, 0), (Py_ssize_t)PyArray_DIM(rgb, 1), (Py_ssize_t)PyArray_DIM(rgb, 2));
        goto done;
    }
    glint_error err;
    glint_image *img = NULL;
    if (glint_image_from_rgb((int)PyArray_DIM(rgb, 1), (int)PyArray_DIM(rgb, 0), PyArray_DATA(rgb), encoding, &img,
                             &err) != GLINT_OK) {
        glintpy_raise(&err);
        goto done;
    }
    glint_status st;
    Py_BEGIN_ALLOW_THREADS
    st = glint_image_write(img, PyBytes_AS_STRING(path), format, &err);
    Py_END_ALLOW_THREADS
    glint_image_free(img);
    if (st != GLINT_OK) {
        glintpy_raise(&err);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    Py_XDECREF(rgb);
    Py_DECREF(path);
    return result;
}

static PyMethodDef MODULE_METHODS[] = {
    {"load", (PyCFunction)(void (*)(void))py_load, METH_VARARGS | METH_KEYWORDS,
     "load(path, *, threads=0) -> Scene\n\nReads a JSON scene file (docs/scene-format.md); raises glint.Error with "
     "the reader's message (file:line:col) when it is bad."},
    {"parse", (PyCFunction)(void (*)(void))py_parse, METH_VARARGS | METH_KEYWORDS,
     "parse(text, name='<scene>', *, threads=0) -> Scene\n\nReads a JSON scene from a str; name appears in "
     "messages and is the base of relative paths."},
    {"write", (PyCFunction)(void (*)(void))py_write, METH_VARARGS | METH_KEYWORDS,
     "write(path, image, encoding=None, *, format=None)\n\nWrites a float (H, W, 3) array of linear values as "
     "glint writes images: .png .ppm .pfm .exr .hdr by the extension, or format= png, ppm, ppm-ascii, pfm, exr, "
     "exr-half, hdr; encoding (linear, gamma2, srgb; None: srgb) is how 8-bit formats encode the values."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef MODULE = {
    PyModuleDef_HEAD_INIT, "glint",
    "glint, a ray tracer: build or load a scene, render it to NumPy arrays, write images (docs/python.md).", -1,
    MODULE_METHODS, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit_glint(void);
PyMODINIT_FUNC PyInit_glint(void) {
    import_array();
    if (PyType_Ready(&glintpy_scene_type) < 0) return NULL;
    PyObject *m = PyModule_Create(&MODULE);
    if (!m) return NULL;
    glintpy_error = PyErr_NewExceptionWithDoc("glint.Error", "A failure the glint library reports, with its message.",
                                              PyExc_Exception, NULL);
    if (!glintpy_error || PyModule_AddObjectRef(m, "Error", glintpy_error) < 0 ||
        PyModule_AddObjectRef(m, "Scene", (PyObject *)&glintpy_scene_type) < 0 ||
        PyModule_AddStringConstant(m, "version", glint_version()) < 0 ||
        PyModule_AddStringConstant(m, "__version__", glint_version()) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
