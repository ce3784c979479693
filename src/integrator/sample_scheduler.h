// sample_scheduler.h — the tile loops every integrator's render_tile is made of, owned once above the
// per-sample and per-path functions (as pbrt-v4's ImageTileIntegrator owns the tile loop above `Li`): sample by
// sample, in batches of sixteen camera rays, or with many paths in flight (streams). Each loop takes the
// integrator's functions as parameters; the loops are always inlined, so those functions (constants in the
// caller) are called directly and inlined where they are static inline: an integrator's tile functions are
// its loops instantiated with its own per-sample or per-path steps, in its own translation unit.
#ifndef GLINT_SAMPLE_SCHEDULER_H
#define GLINT_SAMPLE_SCHEDULER_H

#include "integrator/integrator_common.h"
#include "integrator/surface.h"

#include "camera/camera_batch.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/// A tile pass sample by sample, each with the generator of (seed, pixel, sample): the tile loop of an
/// integrator that renders one sample at a time. Inline, so that `sample` (a constant in the caller) is called
/// directly.
static inline bool scheduler_tile_by_samples(const integrator *it, const tile_pass *tp, film_tile *ft,
                                             thread_stats *ts, integrator_sample_fn sample) {
    const render_settings *rs = &it->scene->settings;
    film_tile t = *ft; // a local copy whose address does not escape: its fields can live in registers
    bool aovs = t.film->aovs != 0;
    for (int y = tp->y0; y < tp->y1; y++)
        for (int x = tp->x0; x < tp->x1; x++) {
            // rng_for_sample(seed, pixel, k), its per-render and per-pixel parts computed once.
            uint64_t key = rng_pixel_key(rs->seed, (uint64_t)y * (uint64_t)rs->width + (uint64_t)x);
            for (int k = tp->k0; k < tp->k1; k++) {
                if (tile_pass_stopping(tp)) {
                    film_tile_stop(&t);
                    *ft = t;
                    return false;
                }
                rng r = rng_for_key(it->stream, key, (uint64_t)k);
                if (aovs) {
                    film_aov_sample a;
                    vec3 c = sample(it, x, y, (uint32_t)k, &r, ts, &a);
                    film_tile_add_aov(&t, c, &a);
                } else {
                    film_tile_add(&t, sample(it, x, y, (uint32_t)k, &r, ts, NULL));
                }
            }
        }
    *ft = t;
    return true;
}

/// The radiance of a path starting with the primary ray (origin o, direction d, all t > 0, at `time`; d need not
/// have unit length) and its AOVs when aov is not NULL. The ray comes by its parts, in registers. `first`, when
/// not NULL, is the primary ray's hit (found: `first_found`), traced with its batch as a packet.
typedef vec3 (*scheduler_trace_fn)(const integrator *it, vec3 o, vec3 d, float time, rng *r, thread_stats *ts,
                                   film_aov_sample *aov, const hit *first, bool first_found);

/// The next sample of a tile pass to make a camera ray for: pixel (x, y), its rng_pixel_key, sample k.
typedef struct scheduler_cursor {
    int x, y, k;
    uint64_t key;
} scheduler_cursor;

/// The cursor at the tile pass's first sample.
static inline scheduler_cursor scheduler_cursor_start(const integrator *it, const tile_pass *tp) {
    const render_settings *rs = &it->scene->settings;
    return (scheduler_cursor){tp->x0, tp->y0, tp->k0,
                              rng_pixel_key(rs->seed, (uint64_t)tp->y0 * (uint64_t)rs->width + (uint64_t)tp->x0)};
}

/// The camera rays (and generators) of the next n <= CAMERA_BATCH samples, in vector instructions
/// (camera_batch.h); lanes past n repeat the first.
static inline __attribute__((always_inline)) void scheduler_cursor_batch(const integrator *it, const tile_pass *tp,
                                                                        scheduler_cursor *c, int n,
                                                                        camera_batch *cb) {
    const render_settings *rs = &it->scene->settings;
    for (int i = 0; i < CAMERA_BATCH; i++) {
        if (i >= n) {
            cb->x[i] = cb->x[0], cb->y[i] = cb->y[0], cb->key[i] = cb->key[0], cb->sample[i] = cb->sample[0];
            continue;
        }
        cb->x[i] = c->x, cb->y[i] = c->y, cb->key[i] = c->key, cb->sample[i] = (uint64_t)c->k;
        if (++c->k == tp->k1) {
            c->k = tp->k0;
            if (++c->x == tp->x1) {
                c->x = tp->x0;
                c->y++;
            }
            if (c->y < tp->y1) c->key = rng_pixel_key(rs->seed, (uint64_t)c->y * (uint64_t)rs->width + (uint64_t)c->x);
        }
    }
    camera_batch_make(&it->camera, it->stream, cb);
}

/// Camera ray i of batch cb, open-ended.
static inline ray scheduler_batch_ray(const camera_batch *cb, int i) {
    return (ray){cb->o[i], cb->d[i], 0.0f, INFINITY, cb->time[i]};
}

/// One tile pass: the samples' camera rays are made CAMERA_BATCH at a time before their paths are traced one by
/// one (`trace`). Same samples, same order, same sums as one sample at a time: the same bytes. `aovs` (a constant
/// in the caller): the film takes AOVs.
static inline __attribute__((always_inline)) bool scheduler_tile_batched(const integrator *it, const tile_pass *tp,
                                                                        film_tile *ft, thread_stats *ts, bool aovs,
                                                                        scheduler_trace_fn trace) {
    int w = tp->x1 - tp->x0, spp = tp->k1 - tp->k0;
    int items = w * (tp->y1 - tp->y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    scheduler_cursor cursor = scheduler_cursor_start(it, tp); // runs ahead of the film tile's by up to CAMERA_BATCH
    camera_batch cb;
    film_tile t = *ft; // a local copy whose address does not escape: its fields can live in registers
    // A tree of triangles traces each batch's camera rays (a pixel's samples, or neighbours) as one packet.
    bool coherent = accel_coherent(it->accel) && it->scene->settings.max_depth > 0;
    _Static_assert((int)CAMERA_BATCH <= (int)ACCEL_COHERENT, "a batch of camera rays fits in one packet");
    hit first[CAMERA_BATCH];
    bool first_found[CAMERA_BATCH] = {false};
    for (int j = 0; j < items; j += CAMERA_BATCH) {
        int n = items - j < CAMERA_BATCH ? items - j : CAMERA_BATCH;
        scheduler_cursor_batch(it, tp, &cursor, n, &cb);
        if (coherent) {
            ray rays[CAMERA_BATCH];
            for (int i = 0; i < n; i++) rays[i] = scheduler_batch_ray(&cb, i);
            accel_intersect_coherent(it->accel, n, rays, first, first_found);
        }
        for (int i = 0; i < n; i++) {
            if (tile_pass_stopping(tp)) {
                film_tile_stop(&t);
                *ft = t;
                return false;
            }
            rng r = cb.r[i];
            bool more;
            if (aovs) {
                film_aov_sample a;
                vec3 c = trace(it, cb.o[i], cb.d[i], cb.time[i], &r, ts, &a, coherent ? &first[i] : NULL,
                               first_found[i]);
                more = film_tile_add_aov(&t, c, &a);
            } else {
                more = film_tile_add(&t, trace(it, cb.o[i], cb.d[i], cb.time[i], &r, ts, NULL,
                                               coherent ? &first[i] : NULL, first_found[i]));
            }
            if (!more) {
                *ft = t;
                return true;
            }
        }
    }
    *ft = t;
    return true;
}

/// Paths in flight in the stream loop, and samples started and not yet added to the film (a power of two). Many
/// more paths than one traversal takes at once (ACCEL_STREAM), and a window that a long path rarely fills: on
/// bunny1m 64 paths and a window of 256 ran 0.93 times as fast as 256 and 1,024, and those 0.98 times as fast as
/// 1,024 and 4,096; the bunny and the 278k bunny, traced one by one, run as fast with any (docs/benchmarks.md).
enum { SCHEDULER_STREAM = 1024, SCHEDULER_WINDOW = 4096 };

/// The stream loop's paths in flight (lanes: their rays, generators, hits and AOVs; the integrator keeps the rest
/// of each path's state in arrays of its own, indexed by lane) and its window of finished samples: about 300 kB,
/// on the heap rather than on the stack of a library caller's thread.
typedef struct scheduler_stream {
    rng gen[SCHEDULER_STREAM];
    int item[SCHEDULER_STREAM];
    ray rays[SCHEDULER_STREAM];
    hit hits[SCHEDULER_STREAM];
    bool found[SCHEDULER_STREAM], has_hit[SCHEDULER_STREAM];
    film_aov_sample aov[SCHEDULER_STREAM];
    vec3 finished[SCHEDULER_WINDOW];
    film_aov_sample finished_aov[SCHEDULER_WINDOW];
    bool is_finished[SCHEDULER_WINDOW];
} scheduler_stream;

/// A new path in lane `lane` of the integrator's state `ctx`; aov (not NULL when the film takes AOVs) is its AOVs.
typedef void (*scheduler_start_fn)(void *ctx, int lane, film_aov_sample *aov);
/// What lane `lane`'s path does where its ray *cur ends (at *h when found): true while the path goes on, with
/// its next ray in *cur.
typedef bool (*scheduler_step_fn)(void *ctx, int lane, ray *cur, bool found, hit *h, rng *r, thread_stats *ts,
                                  film_aov_sample *aov);
/// The radiance lane `lane`'s path (ended) gathered.
typedef vec3 (*scheduler_radiance_fn)(void *ctx, int lane);
/// Lane `from`'s path state moves to lane `to`.
typedef void (*scheduler_move_fn)(void *ctx, int to, int from);

/// Whether the stream loop traces its camera rays as packets (accel_intersect_coherent).
bool scheduler_stream_packets(const integrator *it);

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
/// the corners of the hits a few paths ahead come from memory while one is shaded (SHADE_AHEAD), and a path that
/// ends giving its place to the next sample. The samples (and their AOVs when `aovs`) are added to the film in
/// their order, from a window of finished ones: the same sums as scheduler_tile_batched, so the same bytes. The
/// integrator's per-path state is `ctx`, worked on by start, step, radiance and move (constants in the caller).
static inline __attribute__((always_inline)) bool
scheduler_tile_stream(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts,
                      scheduler_stream *sp, bool aovs, void *ctx, scheduler_start_fn start, scheduler_step_fn step,
                      scheduler_radiance_fn radiance, scheduler_move_fn move) {
    int w = tp->x1 - tp->x0, spp = tp->k1 - tp->k0;
    int items = w * (tp->y1 - tp->y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    enum { WINDOW = SCHEDULER_WINDOW };
    enum { SHADE_AHEAD = 4 }; // paths between a hit whose corners are fetched and its shading
    vec3 *finished = sp->finished;
    film_aov_sample *finished_aov = sp->finished_aov, *aov = sp->aov;
    bool *is_finished = sp->is_finished;
    memset(is_finished, 0, sizeof sp->is_finished);
    rng *gen = sp->gen;
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
    bool packets = scheduler_stream_packets(it), together = accel_interleaves(it->accel);
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
            start(ctx, lanes, aovs ? &aov[lanes] : NULL);
            rays[lanes] = scheduler_batch_ray(&cb, i);
            gen[lanes] = cb.r[i];
            has_hit[lanes] = packets;
            if (packets) hits[lanes] = first[i], found[lanes] = first_found[i];
            item[lanes++] = started++;
        }
        if (lanes == 0) break;
        scheduler_stream_trace(it->accel, together, lanes, rays, has_hit, hits, found);
        for (int l = 0; l < lanes;) {
            ts->rays++;
            // The corners of a hit a few paths ahead start coming from memory while this one is shaded.
            if (l + SHADE_AHEAD < lanes && found[l + SHADE_AHEAD]) surface_prefetch(it->scene, &hits[l + SHADE_AHEAD]);
            if (step(ctx, l, &rays[l], found[l], &hits[l], &gen[l], ts, aovs ? &aov[l] : NULL)) {
                l++;
                continue;
            }
            finished[item[l] % WINDOW] = radiance(ctx, l);
            if (aovs) finished_aov[item[l] % WINDOW] = aov[l];
            is_finished[item[l] % WINDOW] = true;
            // The last path in flight takes this place, with its hit still to be shaded.
            lanes--;
            move(ctx, l, lanes);
            rays[l] = rays[lanes];
            gen[l] = gen[lanes], item[l] = item[lanes];
            hits[l] = hits[lanes], found[l] = found[lanes];
            if (aovs) aov[l] = aov[lanes];
        }
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
