// params.c — Python values as the JSON text of the scene API's parameters: a strict writer that accepts only
// what a scene file can hold and names the key of anything else.
#include "glintpy.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

enum {
    MAX_DEPTH = 32,   // deeper than any scene value (a transform inside an object inside a list): a cycle, or a mistake
    PATH_BYTES = 256, // the key path kept for messages ("material.albedo[2]"), cut beyond
};

typedef struct json_writer {
    char *text;
    size_t length, capacity;
    const char *what;      ///< the method, for messages
    char path[PATH_BYTES]; ///< where in the value the writer is
} json_writer;

static int put(json_writer *w, const char *s, size_t n) {
    if (w->length + n + 1 > w->capacity) {
        size_t cap = w->capacity ? w->capacity : 256;
        while (w->length + n + 1 > cap) cap *= 2;
        char *grown = PyMem_Realloc(w->text, cap);
        if (!grown) {
            PyErr_NoMemory();
            return -1;
        }
        w->text = grown;
        w->capacity = cap;
    }
    memcpy(w->text + w->length, s, n);
    w->length += n;
    w->text[w->length] = '\0';
    return 0;
}

static int put_str(json_writer *w, const char *s) { return put(w, s, strlen(s)); }

// The key path as messages show it: "key 'material.albedo[2]'", or "the value" at the top.
static void raise_at(json_writer *w, PyObject *type, const char *problem, PyObject *value) {
    if (w->path[0])
        PyErr_Format(type, "%s: key '%s': %s, got %.100s", w->what, w->path, problem, Py_TYPE(value)->tp_name);
    else
        PyErr_Format(type, "%s: %s, got %.100s", w->what, problem, Py_TYPE(value)->tp_name);
}

// A JSON string: UTF-8 as is, with '"', '\\' and control characters escaped.
static int put_string(json_writer *w, PyObject *s) {
    Py_ssize_t n;
    const char *utf8 = PyUnicode_AsUTF8AndSize(s, &n);
    if (!utf8) return -1;
    if (put(w, "\"", 1) < 0) return -1;
    for (Py_ssize_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)utf8[i];
        char esc[8];
        if (c == '"' || c == '\\') {
            esc[0] = '\\';
            esc[1] = (char)c;
            if (put(w, esc, 2) < 0) return -1;
        } else if (c < 0x20) {
            snprintf(esc, sizeof esc, "\\u%04x", c);
            if (put(w, esc, 6) < 0) return -1;
        } else if (put(w, utf8 + i, 1) < 0) {
            return -1;
        }
    }
    return put(w, "\"", 1);
}

// Appends ".key" or "[i]" to the path; returns the old length to restore.
static size_t path_push(json_writer *w, const char *key, Py_ssize_t index) {
    size_t old = strlen(w->path);
    if (key)
        snprintf(w->path + old, sizeof w->path - old, "%s%s", old ? "." : "", key);
    else
        snprintf(w->path + old, sizeof w->path - old, "[%zd]", index);
    return old;
}

static int put_value(json_writer *w, PyObject *v, int depth);

static int put_number(json_writer *w, PyObject *v) {
    double d = PyFloat_AsDouble(v);
    if (d == -1.0 && PyErr_Occurred()) return -1;
    if (!isfinite(d)) {
        raise_at(w, PyExc_ValueError, "expected a finite number", v);
        return -1;
    }
    // repr's shortest text that reads back as the same double
    char *text = PyOS_double_to_string(d, 'r', 0, 0, NULL);
    if (!text) return -1;
    int r = put_str(w, text);
    PyMem_Free(text);
    return r;
}

static int put_integer(json_writer *w, PyObject *v) {
    PyObject *index = PyNumber_Index(v); // an exact int, whatever subclass (IntEnum) or NumPy integer it was
    if (!index) return -1;
    PyObject *text = PyObject_Repr(index);
    Py_DECREF(index);
    if (!text) return -1;
    Py_ssize_t n;
    const char *s = PyUnicode_AsUTF8AndSize(text, &n);
    int r = s ? put(w, s, (size_t)n) : -1;
    Py_DECREF(text);
    return r;
}

static int put_sequence(json_writer *w, PyObject *v, int depth) {
    PyObject *items = PySequence_Tuple(v); // a snapshot: nothing the writer calls can change what it walks
    if (!items) return -1;
    int r = put(w, "[", 1);
    for (Py_ssize_t i = 0; r == 0 && i < PyTuple_GET_SIZE(items); i++) {
        if (i > 0 && put(w, ",", 1) < 0) {
            r = -1;
            break;
        }
        size_t old = path_push(w, NULL, i);
        r = put_value(w, PyTuple_GET_ITEM(items, i), depth + 1);
        if (r == 0) w->path[old] = '\0';
    }
    Py_DECREF(items);
    return r < 0 ? -1 : put(w, "]", 1);
}

static int put_dict(json_writer *w, PyObject *v, int depth) {
    PyObject *items = PyDict_Items(v);
    if (!items) return -1;
    int r = put(w, "{", 1);
    for (Py_ssize_t i = 0; r == 0 && i < PyList_GET_SIZE(items); i++) {
        PyObject *pair = PyList_GET_ITEM(items, i);
        PyObject *key = PyTuple_GET_ITEM(pair, 0);
        if (!PyUnicode_Check(key)) {
            raise_at(w, PyExc_TypeError, "keys must be str", key);
            r = -1;
            break;
        }
        const char *k = PyUnicode_AsUTF8(key);
        if (!k || (i > 0 && put(w, ",", 1) < 0) || put_string(w, key) < 0 || put(w, ":", 1) < 0) {
            r = -1;
            break;
        }
        size_t old = path_push(w, k, 0);
        r = put_value(w, PyTuple_GET_ITEM(pair, 1), depth + 1);
        if (r == 0) w->path[old] = '\0';
    }
    Py_DECREF(items);
    return r < 0 ? -1 : put(w, "}", 1);
}

// A NumPy array: its elements as numbers (bool, integer and floating dtypes only), nested as its shape.
static int put_array(json_writer *w, PyObject *v, int depth) {
    PyArrayObject *a = (PyArrayObject *)v;
    char kind = PyArray_DESCR(a)->kind;
    if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f') {
        PyErr_Format(PyExc_TypeError, "%s: key '%s': expected numbers, got an array of dtype %c%d", w->what,
                     w->path[0] ? w->path : "(the value)", kind, (int)PyArray_ITEMSIZE(a));
        return -1;
    }
    PyObject *list = PyArray_ToList(a); // Python numbers (a 0-d array: one number)
    if (!list) return -1;
    int r = put_value(w, list, depth);
    Py_DECREF(list);
    return r;
}

static int put_value(json_writer *w, PyObject *v, int depth) {
    if (depth > MAX_DEPTH) {
        raise_at(w, PyExc_ValueError, "nested deeper than 32 levels (a list that holds itself?)", v);
        return -1;
    }
    if (PyBool_Check(v) || PyArray_IsScalar(v, Bool)) {
        int truth = PyObject_IsTrue(v);
        return truth < 0 ? -1 : put_str(w, truth ? "true" : "false");
    }
    if (PyLong_Check(v) || PyArray_IsScalar(v, Integer)) return put_integer(w, v);
    if (PyFloat_Check(v) || PyArray_IsScalar(v, Floating)) return put_number(w, v);
    if (PyUnicode_Check(v)) return put_string(w, v);
    if (PyDict_Check(v)) return put_dict(w, v, depth);
    if (PyList_Check(v) || PyTuple_Check(v)) return put_sequence(w, v, depth);
    if (PyArray_Check(v)) return put_array(w, v, depth);
    raise_at(w, PyExc_TypeError, "expected a number, str, bool, list, tuple, dict or NumPy array", v);
    return -1;
}

char *glintpy_json(PyObject *value, const char *what) {
    json_writer w = {.what = what};
    if (put_value(&w, value, 0) < 0) {
        PyMem_Free(w.text);
        return NULL;
    }
    return w.text;
}

PyObject *glintpy_dict_argument(PyObject *positional, PyObject *kwargs, const char *what) {
    bool has_keywords = kwargs && PyDict_GET_SIZE(kwargs) > 0;
    if (positional && has_keywords) {
        PyErr_Format(PyExc_TypeError, "%s: give a dict or keywords, not both", what);
        return NULL;
    }
    if (positional) {
        if (!PyDict_Check(positional)) {
            PyErr_Format(PyExc_TypeError, "%s: expected a dict, got %.100s", what, Py_TYPE(positional)->tp_name);
            return NULL;
        }
        Py_INCREF(positional);
        return positional;
    }
    return kwargs ? PyDict_Copy(kwargs) : PyDict_New();
}
