// trace.h — a timeline of what the library's threads do (scene loading, BVH build, tiles, sample passes, file
// writes), kept in memory and written as Chrome trace-event JSON, which Perfetto and chrome://tracing open.
//
// Every thread records into a lane of its own (one "thread" of the timeline): appending to a lane takes no lock,
// because only its thread writes it; opening a lane takes the trace's mutex. A thread finds its lane through
// trace_current (a thread-local pointer, NULL when nothing is traced), so that code deep in a file reader needs no
// extra parameter. Code that records checks that pointer once per piece of work (per tile, never per ray): with
// tracing off, the cost is that branch. A lane's events are read only once its thread has stopped recording
// (after the render's threads have joined), when the trace is written.
#ifndef GLINT_TRACE_H
#define GLINT_TRACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/// Arguments an event holds at most (a tile has x, y, w, h, pass, samples and, when stopped, stopped).
#define TRACE_MAX_ARGS 8

/// The trace: its lanes, its time origin. The same struct as the public glint_trace.
typedef struct glint_trace trace;
/// One thread's events, owned by the trace.
typedef struct trace_lane trace_lane;

/// One argument of an event: a name (a string literal) and an integer, or a string when `text` is not NULL.
typedef struct trace_arg {
    const char *name;
    int64_t value;
    const char *text; ///< copied when the event is added; the lane owns the copy
} trace_arg;

/// A complete event ("ph":"X"): what happened on one thread from `start` to `end` (trace_clock values).
typedef struct trace_event {
    const char *name;     ///< a string literal: what was done ("tile", "BVH build")
    const char *category; ///< a string literal: the stage ("load", "render", "io")
    int64_t start, end;
    int arg_count;
    trace_arg args[TRACE_MAX_ARGS];
} trace_event;

/// A new, empty trace whose time origin is now; NULL when out of memory.
trace *trace_new(void);
/// Frees the trace and its lanes, and detaches the calling thread if its lane is one of them (NULL is allowed).
void trace_free(trace *t);
/// Opens a new lane named `name` (a thread's name: "main", "worker 3"); NULL (and the trace marked incomplete)
/// when out of memory. Lanes are numbered in the order they are opened: that is their thread id in the file.
trace_lane *trace_lane_open(trace *t, const char *name);
/// The trace a lane belongs to.
trace *trace_lane_owner(const trace_lane *lane);
/// The calling thread's lane, or NULL when the thread records nothing.
trace_lane *trace_current(void);
/// Makes `lane` the calling thread's lane (NULL: record nothing).
void trace_set_current(trace_lane *lane);
/// Nanoseconds on the monotonic clock: the time base of events.
int64_t trace_clock(void);
/// Appends a copy of *e to the lane; when memory runs out the event is dropped and the trace marked incomplete.
void trace_add(trace_lane *lane, const trace_event *e);
/// Whether every event offered to the trace was kept (false: memory ran out, the timeline has holes).
bool trace_complete(trace *t);
/// Events the trace holds, on every lane.
size_t trace_event_count(trace *t);
/// Writes the trace as Chrome trace-event JSON: {"traceEvents":[...],"displayTimeUnit":"ms"}, with a
/// thread_name and a thread_sort_index metadata event for each lane, then its complete events (ts and dur in
/// microseconds since the trace began). Returns 0, or an errno value when the stream fails.
int trace_write_json(const trace *t, FILE *f);
/// Writes s as a JSON string, quotes included: quotes, backslashes and control characters escaped, invalid
/// UTF-8 bytes replaced by U+FFFD, so that any file name gives valid JSON.
void trace_json_string(FILE *f, const char *s);

#endif
