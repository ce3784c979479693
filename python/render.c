// render.c — Scene.render: the command line's overrides as keywords, the render on a thread of its own while the
// calling thread, GIL released, waits; Ctrl-C, progress callbacks and their exceptions handled on the calling thread.
//
// Why a thread of its own: Python's SIGINT handler only sets a flag that the main thread acts on when it runs
// Python code (PyErr_CheckSignals). The calling thread therefore waits for the render in short slices, and
// between them takes the GIL back, checks signals and calls the progress callable. A signal handler raising
// KeyboardInterrupt (or any exception of a handler the program installed, or of the progress callable) requests
// the render's own cancel token: it stops before its next sample, and the exception is raised once it has
// returned. No signal disposition is changed, no Python code ever runs on a thread of the library's, and a
// render started on another Python thread works the same way (only the main thread sees signals).
#include "glintpy.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>

enum { WAIT_SLICE_MS = 50 }; // how often the waiting thread checks signals: Ctrl-C is acted on within this

typedef struct render_call {
    const glint_scene *scene;
    glint_render_options options;
    glint_trace *trace; ///< NULL: no trace= asked
    // what the render thread leaves
    glint_image *image;
    glint_render_stats stats;
    glint_error err;
    glint_status status;
    // the handshake: the render thread reports progress and its end; the calling thread waits on `changed`
    pthread_mutex_t lock;
    pthread_cond_t changed;
    bool done;
    bool progress_pending;
    double fraction;
} render_call;

// Called by the library on its progress thread (and once at the end on the render thread): never Python.
static void on_progress(double fraction, void *user) {
    render_call *c = user;
    pthread_mutex_lock(&c->lock);
    c->fraction = fraction;
    c->progress_pending = true;
    pthread_cond_signal(&c->changed);
    pthread_mutex_unlock(&c->lock);
}

static void run_render(render_call *c, bool with_progress) {
    glint_error scratch;
    if (c->trace && glint_trace_attach(c->trace, "python", &scratch) != GLINT_OK) c->trace = NULL;
    c->status = glint_render(c->scene, &c->options, with_progress ? on_progress : NULL, c, &c->image, &c->stats,
                             &c->err);
    if (c->trace) glint_trace_attach(NULL, NULL, &scratch);
}

static void *render_main(void *arg) {
    render_call *c = arg;
    run_render(c, true);
    pthread_mutex_lock(&c->lock);
    c->done = true;
    pthread_cond_signal(&c->changed);
    pthread_mutex_unlock(&c->lock);
    return NULL;
}

// The calling thread's wait, GIL released: until the render ends or reports progress, or a slice passes.
static void wait_slice(render_call *c, bool *done, bool *progress, double *fraction) {
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    until.tv_nsec += WAIT_SLICE_MS * 1000000L;
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&c->lock);
    while (!c->done && !c->progress_pending)
        if (pthread_cond_timedwait(&c->changed, &c->lock, &until) == ETIMEDOUT) break;
    *done = c->done;
    *progress = c->progress_pending;
    *fraction = c->fraction;
    c->progress_pending = false;
    pthread_mutex_unlock(&c->lock);
}

// Runs the render and waits for it as the comment at the top says. Returns -1 with a Python exception set when a
// signal handler or the progress callable raised (the render was cancelled); 0 otherwise (c->status says how it went).
static int render_and_wait(render_call *c, PyObject *progress_fn) {
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    pthread_cond_init(&c->changed, &attr);
    pthread_condattr_destroy(&attr);
    pthread_mutex_init(&c->lock, NULL);
    pthread_t thread;
    bool started;
    Py_BEGIN_ALLOW_THREADS
    started = pthread_create(&thread, NULL, render_main, c) == 0;
    if (!started) run_render(c, false); // no thread to spare: render here, without Ctrl-C or progress
    Py_END_ALLOW_THREADS
    bool raised = false;
    while (started) {
        bool done, progress;
        double fraction;
        Py_BEGIN_ALLOW_THREADS
        wait_slice(c, &done, &progress, &fraction);
        Py_END_ALLOW_THREADS
        if (!raised && PyErr_CheckSignals() < 0) raised = true;
        if (!raised && progress && progress_fn) {
            PyObject *r = PyObject_CallFunction(progress_fn, "d", fraction);
            if (r)
                Py_DECREF(r);
            else
                raised = true;
        }
        if (raised) glint_cancel_request(c->options.cancel); // then wait on for the render to stop
        if (done) break;
    }
    if (started) {
        Py_BEGIN_ALLOW_THREADS
        pthread_join(thread, NULL);
        Py_END_ALLOW_THREADS
    }
    pthread_mutex_destroy(&c->lock);
    pthread_cond_destroy(&c->changed);
    return raised ? -1 : 0;
}

// --- Keywords

// An integer keyword (an int or a NumPy integer; not a bool or a float) in [0, max]; -1 when absent (None).
static int integer_keyword(PyObject *value, const char *name, long long max, long long *out) {
    *out = -1;
    if (!value || value == Py_None) return 0;
    if (PyBool_Check(value) || !PyIndex_Check(value)) {
        PyErr_Format(PyExc_TypeError, "render: %s must be an int, got %.100s", name, Py_TYPE(value)->tp_name);
        return -1;
    }
    PyObject *index = PyNumber_Index(value);
    if (!index) return -1;
    int overflow;
    long long v = PyLong_AsLongLongAndOverflow(index, &overflow);
    Py_DECREF(index);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (overflow || v < 0 || v > max) {
        PyErr_Format(PyExc_ValueError, "render: %s is out of range, expected an integer in [0, %lld]", name, max);
        return -1;
    }
    *out = v;
    return 0;
}

// A str keyword; NULL (and no error) when absent. The text lives as long as `value`.
static int string_keyword(PyObject *value, const char *name, const char **out) {
    *out = NULL;
    if (!value || value == Py_None) return 0;
    if (!PyUnicode_Check(value)) {
        PyErr_Format(PyExc_TypeError, "render: %s must be a str, got %.100s", name, Py_TYPE(value)->tp_name);
        return -1;
    }
    *out = PyUnicode_AsUTF8(value);
    return *out ? 0 : -1;
}

// A path keyword (str, bytes or os.PathLike), as a new bytes object in *out; NULL when absent.
static int path_keyword(PyObject *value, const char *name, PyObject **out) {
    *out = NULL;
    if (!value || value == Py_None) return 0;
    if (!PyUnicode_FSConverter(value, out)) {
        if (PyErr_ExceptionMatches(PyExc_TypeError)) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "render: %s must be a path (str or os.PathLike), got %.100s", name,
                         Py_TYPE(value)->tp_name);
        }
        return -1;
    }
    return 0;
}

static int region_keyword(PyObject *value, int region[4]) {
    if (!value || value == Py_None) return 0;
    PyObject *items = PySequence_Check(value) && !PyUnicode_Check(value) ? PySequence_Tuple(value) : NULL;
    if (!items || PyTuple_GET_SIZE(items) != 4) {
        Py_XDECREF(items);
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "render: region must be a sequence of four ints (x0, y0, x1, y1), got %.100s",
                     Py_TYPE(value)->tp_name);
        return -1;
    }
    static const char *const names[4] = {"region x0", "region y0", "region x1", "region y1"};
    for (int i = 0; i < 4; i++) {
        long long v;
        if (integer_keyword(PyTuple_GET_ITEM(items, i), names[i], INT_MAX, &v) < 0) {
            Py_DECREF(items);
            return -1;
        }
        region[i] = (int)v;
    }
    Py_DECREF(items);
    return 0;
}

static const struct {
    const char *name;
    glint_aov bit;
} AOVS[] = {{"albedo", GLINT_AOV_ALBEDO}, {"normal", GLINT_AOV_NORMAL}, {"depth", GLINT_AOV_DEPTH}};
enum { AOV_COUNT = sizeof AOVS / sizeof AOVS[0] };

// aov=: a list of names (or one str, comma-separated as --aov takes it) as glint_aov bits.
static int aov_keyword(PyObject *value, unsigned *mask) {
    *mask = 0;
    PyObject *items;
    if (PyUnicode_Check(value)) {
        PyObject *comma = PyUnicode_FromString(",");
        items = comma ? PyUnicode_Split(value, comma, -1) : NULL;
        Py_XDECREF(comma);
    } else if (PySequence_Check(value)) {
        items = PySequence_Tuple(value);
    } else {
        PyErr_Format(PyExc_TypeError, "render: aov must be a list of 'albedo', 'normal', 'depth', got %.100s",
                     Py_TYPE(value)->tp_name);
        return -1;
    }
    if (!items) return -1;
    PyObject *fast = PySequence_Fast(items, "aov");
    Py_DECREF(items);
    if (!fast) return -1;
    int r = 0;
    for (Py_ssize_t i = 0; r == 0 && i < PySequence_Fast_GET_SIZE(fast); i++) {
        PyObject *item = PySequence_Fast_GET_ITEM(fast, i);
        const char *s = PyUnicode_Check(item) ? PyUnicode_AsUTF8(item) : NULL;
        if (!s) {
            if (!PyErr_Occurred())
                PyErr_Format(PyExc_TypeError, "render: aov[%zd] must be a str, got %.100s", i, Py_TYPE(item)->tp_name);
            r = -1;
            break;
        }
        int k = 0;
        while (k < AOV_COUNT && strcmp(AOVS[k].name, s) != 0) k++;
        if (k == AOV_COUNT) {
            PyErr_Format(PyExc_ValueError, "render: unknown AOV '%s', expected albedo, normal or depth", s);
            r = -1;
        } else {
            *mask |= (unsigned)AOVS[k].bit;
        }
    }
    Py_DECREF(fast);
    return r;
}

// --- Results

// An (h, w, channels) float32 array (channels 1: (h, w)) holding a copy of values.
static PyObject *float_image(int w, int h, int channels, const float *values) {
    npy_intp dims[3] = {h, w, channels};
    PyObject *a = PyArray_SimpleNew(channels == 1 ? 2 : 3, dims, NPY_FLOAT32);
    if (a) memcpy(PyArray_DATA((PyArrayObject *)a), values, (size_t)w * (size_t)h * (size_t)channels * sizeof(float));
    return a;
}

// The image, or (image, {aov name: array}) when aov= was given.
static PyObject *render_result(const glint_image *img, bool aov_given, unsigned aovs) {
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    PyObject *image = float_image(w, h, 3, rgb);
    if (!image || !aov_given) return image;
    PyObject *planes = PyDict_New();
    for (int k = 0; planes && k < AOV_COUNT; k++) {
        if (!(aovs & (unsigned)AOVS[k].bit)) continue;
        int channels;
        const float *plane = glint_image_aov(img, AOVS[k].bit, &channels);
        PyObject *a = plane ? float_image(w, h, channels, plane) : NULL;
        if (!a || PyDict_SetItemString(planes, AOVS[k].name, a) < 0) Py_CLEAR(planes);
        Py_XDECREF(a);
    }
    if (!planes) {
        Py_DECREF(image);
        return NULL;
    }
    PyObject *pair = PyTuple_Pack(2, image, planes);
    Py_DECREF(image);
    Py_DECREF(planes);
    return pair;
}

PyObject *glintpy_scene_render(glintpy_scene *self, PyObject *args, PyObject *kwargs) {
    static char *keywords[] = {"spp", "threads", "seed", "width", "height", "max_depth", "region", "accel",
                               "output_encoding", "time_limit", "aov", "progress", "checkpoint", "resume", "trace",
                               NULL};
    PyObject *spp = NULL, *threads = NULL, *seed = NULL, *width = NULL, *height = NULL, *max_depth = NULL,
             *region = NULL, *accel = NULL, *encoding = NULL, *time_limit = NULL, *aov = NULL, *progress = NULL,
             *checkpoint = NULL, *resume = NULL, *trace_path = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|$OOOOOOOOOOOOOOO:render", keywords, &spp, &threads, &seed, &width,
                                     &height, &max_depth, &region, &accel, &encoding, &time_limit, &aov, &progress,
                                     &checkpoint, &resume, &trace_path))
        return NULL;
    if (glintpy_scene_check_idle(self, "render") < 0) return NULL;

    PyObject *result = NULL, *checkpoint_bytes = NULL, *resume_bytes = NULL, *trace_bytes = NULL;
    render_call call = {.scene = self->scene};
    glint_overrides ov;
    glint_overrides_init(&ov);
    long long v, n_threads;
    // The ranges of --width, --spp, ... are the library's to check (glint.Error naming the flag); these are
    // only what glint_overrides can carry (a negative value there means "not overridden").
    if (integer_keyword(spp, "spp", LONG_MAX, &v) < 0) goto done;
    ov.spp = (long)v;
    if (integer_keyword(width, "width", LONG_MAX, &v) < 0) goto done;
    ov.width = (long)v;
    if (integer_keyword(height, "height", LONG_MAX, &v) < 0) goto done;
    ov.height = (long)v;
    if (integer_keyword(max_depth, "max_depth", LONG_MAX, &v) < 0) goto done;
    ov.max_depth = (long)v;
    // The command line's ranges, which only it checks
    if (integer_keyword(seed, "seed", 9007199254740992LL, &ov.seed) < 0) goto done;
    if (integer_keyword(threads, "threads", 256, &n_threads) < 0) goto done;
    if (string_keyword(accel, "accel", &ov.accel) < 0 || string_keyword(encoding, "output_encoding", &ov.output_encoding) < 0)
        goto done;
    call.options.threads = n_threads < 0 ? 0 : (int)n_threads;
    if (region_keyword(region, call.options.region) < 0) goto done;
    if (time_limit && time_limit != Py_None) {
        double t = PyBool_Check(time_limit) ? -1.0 : PyFloat_AsDouble(time_limit);
        if (t == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "render: time_limit must be a number of seconds, got %.100s",
                         Py_TYPE(time_limit)->tp_name);
            goto done;
        }
        if (!(t > 0 && t <= 1e8)) {
            PyErr_SetString(PyExc_ValueError, "render: time_limit is out of range, expected seconds in (0, 1e8]");
            goto done;
        }
        call.options.time_limit = t;
    }
    if (aov && aov != Py_None && aov_keyword(aov, &call.options.aovs) < 0) goto done;
    if (progress == Py_None) progress = NULL;
    if (progress && !PyCallable_Check(progress)) {
        PyErr_Format(PyExc_TypeError, "render: progress must be callable (it is given the fraction done), got %.100s",
                     Py_TYPE(progress)->tp_name);
        goto done;
    }
    if (path_keyword(checkpoint, "checkpoint", &checkpoint_bytes) < 0 || path_keyword(resume, "resume", &resume_bytes) < 0 ||
        path_keyword(trace_path, "trace", &trace_bytes) < 0)
        goto done;
    call.options.checkpoint = checkpoint_bytes ? PyBytes_AS_STRING(checkpoint_bytes) : NULL;
    call.options.resume = resume_bytes ? PyBytes_AS_STRING(resume_bytes) : NULL;
    glint_error err;
    if (trace_bytes) {
        if (glint_trace_check_path(PyBytes_AS_STRING(trace_bytes), &err) != GLINT_OK) {
            glintpy_raise(&err);
            goto done;
        }
        if (!(call.trace = glint_trace_new())) {
            PyErr_NoMemory();
            goto done;
        }
    }
    call.options.overrides = &ov; // this render only
    if (!(call.options.cancel = glint_cancel_new())) {
        PyErr_NoMemory();
        goto done;
    }

    self->busy = 1;
    int raised = render_and_wait(&call, progress);
    self->busy = 0;
    if (raised) {
        // KeyboardInterrupt, or what the progress callable or a signal handler raised: the render stopped for it
    } else if (call.status == GLINT_OK) {
        result = render_result(call.image, aov && aov != Py_None, call.options.aovs);
    } else {
        glintpy_raise(&call.err);
    }
    if (call.trace && call.status != GLINT_ERR_INPUT) {
        // the trace of any render that ran, as the command line writes it; an exception already set wins
        if (glint_trace_write(call.trace, PyBytes_AS_STRING(trace_bytes), &err) != GLINT_OK && result) {
            Py_CLEAR(result);
            glintpy_raise(&err);
        }
    }
done:
    glint_image_free(call.image);
    glint_cancel_free(call.options.cancel);
    glint_trace_free(call.trace);
    Py_XDECREF(checkpoint_bytes);
    Py_XDECREF(resume_bytes);
    Py_XDECREF(trace_bytes);
    return result;
}
