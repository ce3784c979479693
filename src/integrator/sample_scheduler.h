// sample_scheduler.h — the tile loops every integrator's render_tile is made of, owned once above the
// per-sample and per-path functions (as pbrt-v4's ImageTileIntegrator owns the tile loop above `Li`): sample by
// sample, or in batches of sixteen camera rays; with many paths in flight in sample_stream.h. Each loop takes the
// integrator's functions as parameters; the loops are always inlined, so those functions (constants in the
// caller) are called directly and inlined where they are static inline: an integrator's tile functions are
// its loops instantiated with its own per-sample or per-path steps, in its own translation unit.
#ifndef GLINT_SAMPLE_SCHEDULER_H
#define GLINT_SAMPLE_SCHEDULER_H

#include "integrator/integrator_common.h"

#include "camera/camera_batch.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

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
            // The generator of (seed, pixel, k), its per-render and per-pixel parts computed once.
            uint64_t key = rng_pixel_key(rs->seed, (uint64_t)y * (uint64_t)rs->width + (uint64_t)x);
            for (int k = tp->k0; k < tp->k1; k++) {
                if (tile_pass_stopping(tp)) {
                    film_tile_stop(&t);
                    *ft = t;
                    return false;
                }
                rng r = rng_for_stream(it->stream, key, (uint64_t)k);
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
    // A tree of triangles traces each batch's camera rays (a pixel's samples, or neighbours) as one packet; not
    // with alpha masks, which the packet query (accel_intersect_coherent) knows nothing of: the path steps past cuts.
    bool coherent = accel_coherent(it->accel) && it->scene->settings.max_depth > 0 && !it->alpha_masks;
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

/// A tile pass of at least this many samples a pixel traces its camera rays as packets whatever the tree: a batch
/// of CAMERA_BATCH rays then spans at most two pixels.
enum { SCHEDULER_PACKET_SAMPLES = CAMERA_BATCH / 2 };
/// Whether the stream loop traces its camera rays as packets (accel_intersect_coherent) in a tile pass of
/// `samples` samples a pixel.
bool scheduler_stream_packets(const integrator *it, int samples);

#endif
