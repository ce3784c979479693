// stats.h — the counters one worker thread keeps during a render, on a cache line of their own.
#ifndef GLINT_STATS_H
#define GLINT_STATS_H

#include <stdint.h>

/// Per-thread counters, one cache line each so that threads never share a line.
typedef struct thread_stats {
    _Alignas(64) uint64_t rays;  ///< closest-hit queries (camera and scattered/reflected rays)
    uint64_t shadow_rays;        ///< any-hit queries
    uint64_t discarded_samples;  ///< samples dropped because they were NaN or infinite
    uint64_t samples;
} thread_stats;

#endif
