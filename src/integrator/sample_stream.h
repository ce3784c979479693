// sample_stream.h — the sample scheduler's stream loop: a tile pass with many paths in flight, their rays traced
// together before any is shaded. The integrator that includes it (path.c) defines its paths' state and steps
// (scheduler_paths and its functions) in its own translation unit, and the loop calls them directly, so that they
// are inlined into it as early as the rest of the loop (a call through a pointer is resolved too late for that).
#ifndef GLINT_SAMPLE_STREAM_H
#define GLINT_SAMPLE_STREAM_H

#include "integrator/sample_scheduler.h"
#include "integrator/surface.h"

#include <stdbool.h>
#include <string.h>

/// Paths in flight in the stream loop, and samples started and not yet added to the film (a power of two). Many
/// more paths than one traversal takes at once (ACCEL_STREAM), and a window that a long path rarely fills: on
/// bunny1m 64 paths and a window of 256 ran 0.93 times as fast as 256 and 1,024, and those 0.98 times as fast as
/// 1,024 and 4,096; the bunny and the 278k bunny, traced one by one, run as fast with any (docs/benchmarks.md).
enum { SCHEDULER_STREAM = 1024, SCHEDULER_WINDOW = 4096 };

/// The stream loop's paths in flight (lanes: their rays, generators, hits and AOVs; the integrator keeps the rest
/// of each path's state in its scheduler_paths, by lane) and its window of finished samples: about 300 kB,
/// on the heap rather than on the stack of a library caller's thread.
typedef struct scheduler_stream {
    rng_position gen[SCHEDULER_STREAM]; ///< the lanes' generators (positions alone: 16 bytes a lane)
    int item[SCHEDULER_STREAM];
    ray rays[SCHEDULER_STREAM];
    hit hits[SCHEDULER_STREAM];
    bool found[SCHEDULER_STREAM], has_hit[SCHEDULER_STREAM];
    film_aov_sample aov[SCHEDULER_STREAM];
    vec3 finished[SCHEDULER_WINDOW];
    film_aov_sample finished_aov[SCHEDULER_WINDOW];
    bool is_finished[SCHEDULER_WINDOW];
} scheduler_stream;

/// The per-path state of the stream loop's paths, by lane: defined by the integrator whose translation unit runs
/// scheduler_tile_stream, with the four functions below. They are static and called directly (not through
/// pointers), so that the compiler inlines them into the loop before it weighs anything else there.
typedef struct scheduler_paths scheduler_paths;
/// A new path in lane `lane`; aov (not NULL when the film takes AOVs) is its AOVs.
static inline void scheduler_paths_start(scheduler_paths *p, int lane, film_aov_sample *aov);
/// What lane `lane`'s path does where its ray *cur ends (at *h when found): true while the path goes on, with its
/// next ray in *cur; its generator stands at *at (updated).
static inline bool scheduler_paths_step(scheduler_paths *p, int lane, ray *cur, bool found, hit *h, rng_position *at,
                                        thread_stats *ts, film_aov_sample *aov);
/// The radiance lane `lane`'s path (ended) gathered.
static inline vec3 scheduler_paths_radiance(const scheduler_paths *p, int lane);
/// Lane `from`'s path state moves to lane `to`.
static inline void scheduler_paths_move(scheduler_paths *p, int to, int from);

/// The hits of the rays among rays[0, n) whose lanes have none yet (has_hit false), traversed together, ACCEL_STREAM
/// at a time, when `together` (accel_interleaves), else one by one in place; the other lanes keep the hits they came
/// with. Clears has_hit: the next round's rays are new.
static inline void scheduler_stream_trace(const accel *a, bool together, int n, const ray *rays, bool *has_hit,
                                          hit *hits, bool *found) {
    if (!together) {
        for (int l = 0; l < n; l++)
            if (!has_hit[l]) found[l] = accel_intersect(a, &rays[l], &hits[l]);
    } else {
        int lane[SCHEDULER_STREAM], m = 0;
        for (int l = 0; l < n; l++)
            if (!has_hit[l]) lane[m++] = l;
        for (int c = 0; c < m; c += ACCEL_STREAM) {
            int k = m - c < ACCEL_STREAM ? m - c : ACCEL_STREAM;
            if (m == n) { // no camera packets: the rays as they are, no copy
                accel_intersect_stream(a, k, rays + c, hits + c, found + c);
                continue;
            }
            ray todo[ACCEL_STREAM];
            hit th[ACCEL_STREAM];
            bool tf[ACCEL_STREAM];
            for (int j = 0; j < k; j++) todo[j] = rays[lane[c + j]];
            accel_intersect_stream(a, k, todo, th, tf);
            for (int j = 0; j < k; j++) hits[lane[c + j]] = th[j], found[lane[c + j]] = tf[j];
        }
    }
    for (int l = 0; l < n; l++) has_hit[l] = false; // the next round's rays are new
}

/// A tile pass with many paths in flight (accel_streams): SCHEDULER_STREAM of them, the rays of each round traced
/// before any is shaded (scheduler_stream_trace; shadow rays, one at a time, stay in the integrator's step), so that
/// the corners of the hits a few paths ahead come from memory while one is shaded (SHADE_AHEAD), the paths that go
/// on closing up in their order, and the next samples filling the lanes behind them. The samples (and their AOVs
/// when `aovs`) are added to the film in their order, from a window of finished ones: the same sums as
/// scheduler_tile_batched, so the same bytes. The integrator's per-path state is `paths`, worked on by the
/// scheduler_paths_* functions it defines.
static inline __attribute__((always_inline)) bool scheduler_tile_stream(const integrator *it, const tile_pass *tp,
                                                                       film_tile *ft, thread_stats *ts,
                                                                       scheduler_stream *sp, bool aovs,
                                                                       scheduler_paths *paths) {
    int w = tp->x1 - tp->x0, spp = tp->k1 - tp->k0;
    int items = w * (tp->y1 - tp->y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    enum { WINDOW = SCHEDULER_WINDOW };
    enum { SHADE_AHEAD = 4 }; // paths between a hit whose corners are fetched and its shading
    vec3 *finished = sp->finished;
    film_aov_sample *finished_aov = sp->finished_aov, *aov = sp->aov;
    bool *is_finished = sp->is_finished;
    memset(is_finished, 0, sizeof sp->is_finished);
    rng_position *gen = sp->gen;
    int *item = sp->item;
    ray *rays = sp->rays; // each path's next ray
    hit *hits = sp->hits;
    bool *found = sp->found, *has_hit = sp->has_hit;
    int lanes = 0, started = 0, added = 0; // paths in flight are lanes [0, lanes)
    scheduler_cursor cursor = scheduler_cursor_start(it, tp);
    camera_batch cb;
    int batch_start = 0, batch_end = 0; // cb holds items [batch_start, batch_end)
    film_tile t = *ft;
    // Each batch of camera rays traced as a packet when it is made (scheduler_stream_packets); a path that starts
    // from it comes with its first hit, and the stream traces the other paths' rays.
    bool packets = scheduler_stream_packets(it, spp), together = accel_interleaves(it->accel);
    hit first[CAMERA_BATCH];
    bool first_found[CAMERA_BATCH];
    for (;;) {
        while (lanes < SCHEDULER_STREAM && started < items && started < added + WINDOW) {
            if (started == batch_end) {
                int n = items - started < CAMERA_BATCH ? items - started : CAMERA_BATCH;
                scheduler_cursor_batch(it, tp, &cursor, n, &cb);
                batch_start = started;
                batch_end = started + n;
                if (packets) {
                    ray cam[CAMERA_BATCH];
                    for (int k = 0; k < n; k++) cam[k] = scheduler_batch_ray(&cb, k);
                    accel_intersect_coherent(it->accel, n, cam, first, first_found);
                }
            }
            int i = started - batch_start;
            scheduler_paths_start(paths, lanes, aovs ? &aov[lanes] : NULL);
            rays[lanes] = scheduler_batch_ray(&cb, i);
            gen[lanes] = rng_position_of(&cb.r[i]);
            has_hit[lanes] = packets;
            if (packets) hits[lanes] = first[i], found[lanes] = first_found[i];
            item[lanes++] = started++;
        }
        if (lanes == 0) break;
        scheduler_stream_trace(it->accel, together, lanes, rays, has_hit, hits, found);
        int kept = 0; // the paths that go on close up in their order: lanes [0, kept) after lane l
        for (int l = 0; l < lanes; l++) {
            ts->rays++;
            // The corners of a hit a few paths ahead start coming from memory while this one is shaded.
            if (l + SHADE_AHEAD < lanes && found[l + SHADE_AHEAD]) surface_prefetch(it->scene, &hits[l + SHADE_AHEAD]);
            if (scheduler_paths_step(paths, l, &rays[l], found[l], &hits[l], &gen[l], ts, aovs ? &aov[l] : NULL)) {
                // Kept in item order, a pixel's paths stay side by side: their next rays leave nearby points and
                // find the same nodes in the cache (the last path moved into each ended one's place scattered them
                // over the rounds: the engine and the dragon 1.11, the bunny 1.02, engine-2m 1.007 at 16 spp).
                if (kept != l) {
                    scheduler_paths_move(paths, kept, l);
                    rays[kept] = rays[l];
                    gen[kept] = gen[l], item[kept] = item[l];
                    if (aovs) aov[kept] = aov[l];
                }
                kept++;
                continue;
            }
            finished[item[l] % WINDOW] = scheduler_paths_radiance(paths, l);
            if (aovs) finished_aov[item[l] % WINDOW] = aov[l];
            is_finished[item[l] % WINDOW] = true;
        }
        lanes = kept;
        for (; added < items && is_finished[added % WINDOW]; added++) {
            if (tile_pass_stopping(tp)) {
                film_tile_stop(&t);
                *ft = t;
                return false;
            }
            int k = added % WINDOW;
            is_finished[k] = false;
            if (!(aovs ? film_tile_add_aov(&t, finished[k], &finished_aov[k]) : film_tile_add(&t, finished[k]))) {
                *ft = t;
                return true;
            }
        }
    }
    *ft = t;
    return true;
}

#endif
