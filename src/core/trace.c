// trace.c — the timeline recorder: per-thread lanes of complete events, written as Chrome trace-event JSON.
#include "core/trace.h"
#include "core/array.h"

#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

struct trace_lane {
    trace *owner;
    char *name;
    int tid;             ///< 1, 2, ... in the order lanes were opened
    trace_event *events; ///< owned; text arguments point to copies the lane owns
    size_t count, capacity;
};

struct glint_trace {
    int64_t origin;         ///< trace_clock() when the trace was made: time 0 of the file
    pthread_mutex_t lock;   ///< guards the list of lanes, never a lane's events
    trace_lane **lanes;
    size_t lane_count, lane_capacity;
    atomic_bool incomplete; ///< an event or a lane could not be stored
};

// Each thread's lane: set by whoever starts the thread's recording, read once per piece of work.
static _Thread_local trace_lane *current_lane;

int64_t trace_clock(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + (int64_t)ts.tv_nsec;
}

trace *trace_new(void) {
    trace *t = calloc(1, sizeof *t);
    if (!t) return NULL;
    if (pthread_mutex_init(&t->lock, NULL) != 0) {
        free(t);
        return NULL;
    }
    atomic_init(&t->incomplete, false);
    t->origin = trace_clock();
    return t;
}

// Frees memory held through a pointer to const (an event's text, which the lane owns but shows as const).
static void free_owned(const char *p) {
    void *q;
    memcpy(&q, &p, sizeof q);
    free(q);
}

static void free_event_texts(trace_event *e) {
    for (int i = 0; i < e->arg_count; i++) free_owned(e->args[i].text);
}

void trace_free(trace *t) {
    if (!t) return;
    if (current_lane && current_lane->owner == t) current_lane = NULL;
    for (size_t i = 0; i < t->lane_count; i++) {
        trace_lane *l = t->lanes[i];
        for (size_t k = 0; k < l->count; k++) free_event_texts(&l->events[k]);
        free(l->events);
        free(l->name);
        free(l);
    }
    free(t->lanes);
    pthread_mutex_destroy(&t->lock);
    free(t);
}

static void mark_incomplete(trace *t) { atomic_store_explicit(&t->incomplete, true, memory_order_relaxed); }

trace_lane *trace_lane_open(trace *t, const char *name) {
    trace_lane *l = calloc(1, sizeof *l);
    char *copy = l ? strdup(name) : NULL;
    bool stored = false;
    if (copy) {
        pthread_mutex_lock(&t->lock);
        stored = array_reserve((void **)&t->lanes, &t->lane_capacity, t->lane_count + 1, sizeof *t->lanes);
        if (stored) {
            *l = (trace_lane){.owner = t, .name = copy, .tid = (int)t->lane_count + 1};
            t->lanes[t->lane_count++] = l;
        }
        pthread_mutex_unlock(&t->lock);
    }
    if (stored) return l;
    free(copy);
    free(l);
    mark_incomplete(t);
    return NULL;
}

trace *trace_lane_owner(const trace_lane *lane) { return lane->owner; }

trace_lane *trace_current(void) { return current_lane; }

void trace_set_current(trace_lane *lane) { current_lane = lane; }

void trace_add(trace_lane *lane, const trace_event *e) {
    if (!array_reserve((void **)&lane->events, &lane->capacity, lane->count + 1, sizeof *lane->events)) {
        mark_incomplete(lane->owner);
        return;
    }
    trace_event copy = *e;
    if (copy.arg_count > TRACE_MAX_ARGS) copy.arg_count = TRACE_MAX_ARGS;
    if (copy.arg_count < 0) copy.arg_count = 0;
    for (int i = 0; i < copy.arg_count; i++) {
        if (!e->args[i].text) continue;
        copy.args[i].text = strdup(e->args[i].text);
        if (!copy.args[i].text) { // drop the event whole: keep no half of its arguments
            copy.arg_count = i;
            free_event_texts(&copy);
            mark_incomplete(lane->owner);
            return;
        }
    }
    lane->events[lane->count++] = copy;
}

bool trace_complete(trace *t) { return !atomic_load_explicit(&t->incomplete, memory_order_relaxed); }

size_t trace_event_count(trace *t) {
    pthread_mutex_lock(&t->lock);
    size_t n = 0;
    for (size_t i = 0; i < t->lane_count; i++) n += t->lanes[i]->count;
    pthread_mutex_unlock(&t->lock);
    return n;
}

// Bytes of the well-formed UTF-8 sequence at p (RFC 3629: no overlong forms, no surrogates, nothing past
// U+10FFFF), or 0 when the bytes there are not one.
static size_t utf8_length(const unsigned char *p) {
    unsigned c = p[0];
    size_t n;
    unsigned lo = 0x80, hi = 0xBF; // the range of the second byte; later ones are always 80..BF
    if (c >= 0xC2 && c <= 0xDF) n = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
    } else return 0;
    if (p[1] < lo || p[1] > hi) return 0;
    for (size_t i = 2; i < n; i++)
        if (p[i] < 0x80 || p[i] > 0xBF) return 0; // a NUL ends the string here too
    return n;
}

void trace_json_string(FILE *f, const char *s) {
    const unsigned char *p = (const unsigned char *)s;
    putc('"', f);
    while (*p) {
        unsigned c = *p;
        if (c == '"' || c == '\\') {
            putc('\\', f);
            putc((int)c, f);
            p++;
        } else if (c < 0x20) {
            fprintf(f, "\\u%04x", c);
            p++;
        } else if (c < 0x80) {
            putc((int)c, f);
            p++;
        } else {
            size_t n = utf8_length(p);
            if (n) fwrite(p, 1, n, f);
            else fputs("\\ufffd", f); // a file name need not be UTF-8; JSON text must be
            p += n ? n : 1;
        }
    }
    putc('"', f);
}

// Microseconds with three decimals, from nanoseconds, without floating point (exact, and no locale).
static void put_microseconds(FILE *f, int64_t ns) {
    if (ns < 0) ns = 0;
    fprintf(f, "%lld.%03lld", (long long)(ns / 1000), (long long)(ns % 1000));
}

static void put_metadata(FILE *f, long pid, int tid, const char *what, const char *key, const char *text, int number) {
    fprintf(f, ",\n{\"name\":\"%s\",\"ph\":\"M\",\"pid\":%ld,\"tid\":%d,\"args\":{\"%s\":", what, pid, tid, key);
    if (text) trace_json_string(f, text);
    else fprintf(f, "%d", number);
    fputs("}}", f);
}

static void put_event(FILE *f, long pid, int tid, int64_t origin, const trace_event *e) {
    fputs(",\n{\"name\":", f);
    trace_json_string(f, e->name);
    fputs(",\"cat\":", f);
    trace_json_string(f, e->category);
    fputs(",\"ph\":\"X\",\"ts\":", f);
    put_microseconds(f, e->start - origin);
    fputs(",\"dur\":", f);
    put_microseconds(f, e->end > e->start ? e->end - e->start : 0);
    fprintf(f, ",\"pid\":%ld,\"tid\":%d,\"args\":{", pid, tid);
    for (int i = 0; i < e->arg_count; i++) {
        if (i) putc(',', f);
        trace_json_string(f, e->args[i].name);
        putc(':', f);
        if (e->args[i].text) trace_json_string(f, e->args[i].text);
        else fprintf(f, "%lld", (long long)e->args[i].value);
    }
    fputs("}}", f);
}

int trace_write_json(const trace *t, FILE *f) {
    long pid = (long)getpid();
    errno = 0;
    // The process's name first: every later element starts with ",\n", so no element needs to know it is last.
    fprintf(f, "{\"traceEvents\":[\n{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":%ld,\"tid\":0,"
               "\"args\":{\"name\":\"glint\"}}", pid);
    for (size_t i = 0; i < t->lane_count; i++) {
        const trace_lane *l = t->lanes[i];
        put_metadata(f, pid, l->tid, "thread_name", "name", l->name, 0);
        put_metadata(f, pid, l->tid, "thread_sort_index", "sort_index", NULL, l->tid);
    }
    for (size_t i = 0; i < t->lane_count; i++) {
        const trace_lane *l = t->lanes[i];
        for (size_t k = 0; k < l->count; k++) put_event(f, pid, l->tid, t->origin, &l->events[k]);
    }
    fputs("\n],\n\"displayTimeUnit\":\"ms\"}\n", f);
    if (ferror(f)) return errno ? errno : EIO;
    return 0;
}
