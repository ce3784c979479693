// crew.h — one rank's render threads: they take units (one pass of one tile) from an inbox, render them with
// tiles_render_pass and post them, done, to an outbox that the rank's main thread (the only one that calls
// MPI) empties. No thread but the main one ever touches MPI.
#ifndef GLINT_MPI_CREW_H
#define GLINT_MPI_CREW_H

#include "core/stats.h"
#include "core/thread_pool.h"
#include "integrator/integrator.h"
#include "render/tiles.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

enum { UNIT_MAX_PIXELS = TILES_SIZE * TILES_SIZE };

/// One pass of one tile, in and out: the tile's running sums before the pass (after it once rendered), and the
/// means after it; the counters of its samples.
typedef struct unit {
    int tile, pass;
    bool complete;       ///< rendered to its end (false: cut short by a stop, to be dropped)
    thread_stats stats;  ///< of this unit's samples
    struct unit *next;
    double sums[UNIT_MAX_PIXELS * 3];
    float means[UNIT_MAX_PIXELS * 3];
} unit;

/// A render thread's state, on cache lines of its own.
typedef struct crew_thread {
    _Alignas(64) _Atomic uint64_t samples; ///< film_tile_add's progress counter (nobody reads it here)
} crew_thread;

typedef struct crew {
    const tiles *grid;
    const integrator *integrator;
    const atomic_int *stop;  ///< nonzero: units in progress end at their next sample, none starts
    pthread_mutex_t lock;
    pthread_cond_t work;     ///< the inbox has a unit, or the crew is closing
    pthread_cond_t finished; ///< the outbox has a unit
    unit *inbox, *inbox_tail, *outbox;
    int queued;              ///< units given and not yet taken back (inbox, rendering, outbox)
    bool closing;
    crew_thread *threads;
    thread_pool *pool;       ///< the crew's threads: one long item each (core/thread_pool)
    int thread_count;
} crew;

/// A new unit (its counters are on a cache line of their own: it is allocated aligned); NULL when out of memory.
unit *crew_unit_new(void);

/// Starts `threads` render threads over the grid with the integrator; *stop is polled before every sample.
/// False (nothing started) when no thread could be.
bool crew_start(crew *c, const tiles *grid, const integrator *it, const atomic_int *stop, int threads);
/// Queues a unit; the crew owns it until crew_take hands it back.
void crew_give(crew *c, unit *u);
/// The units finished since the last call (a list through ->next, complete or cut short), waiting up to
/// `seconds` for one when there are none; NULL when none finished in time.
unit *crew_take(crew *c, double seconds);
/// Units given and not yet taken back.
int crew_queued(crew *c);
/// Lets the threads finish (or drop, if *stop is set) what they hold, joins them and frees every unit left.
void crew_close(crew *c);

#endif
