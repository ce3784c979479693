// integrator.h — the light-transport algorithms (the paper's and the colour Whitted ray tracer, the path
// tracer) behind one interface: built per render from a const scene and the acceleration structure, each
// renders "these samples of this tile" into the film. The render loop (render/) knows nothing more of them.
#ifndef GLINT_INTEGRATOR_H
#define GLINT_INTEGRATOR_H

#include "glint.h"
#include "accel/accel.h"
#include "camera/camera.h"
#include "core/rng.h"
#include "core/stats.h"
#include "core/vec.h"
#include "film/film.h"
#include "scene/scene.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

/// One tile pass: samples [k0, k1) of every pixel of [x0, x1) x [y0, y1), pixels in row order.
typedef struct tile_pass {
    int x0, y0, x1, y1, k0, k1;
    const atomic_int *stop; ///< nonzero once a stop is requested: the pass ends before its next sample
} tile_pass;

/// Choices of a render that are not part of the scene.
typedef struct integrator_options {
    bool no_light_sampling; ///< path tracer: no next-event estimation towards area lights (tests compare both)
} integrator_options;

typedef struct integrator integrator;

/// Radiance of sample `sample` of pixel (x, y); r is seeded for exactly this sample (rng_for_key).
typedef vec3 (*integrator_sample_fn)(const integrator *it, int x, int y, uint32_t sample, rng *r, thread_stats *ts);
/// Renders a tile pass into ft, in ft's order; false when a stop request cut it short (after film_tile_stop).
typedef bool (*integrator_tile_fn)(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts);

/// What every integrator holds; an integrator's own state follows it (the struct is its first member).
struct integrator {
    const glint_scene *scene; ///< plain data, read by every thread
    const accel *accel;       ///< built from the scene's geometry by the render frame
    camera camera;            ///< the scene's camera prepared for the image size
    uint64_t stream;          ///< rng_seed_stream(seed): shared by every sample's generator
    integrator_sample_fn sample;
    integrator_tile_fn render_tile;
    void (*release)(integrator *it); ///< frees the integrator's own state, or NULL
};

/// The integrator the scene's settings choose, reading s and a (both must outlive it). NULL, with a message
/// in *err, when out of memory.
integrator *integrator_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err);
/// Frees an integrator (NULL is allowed).
void integrator_free(integrator *it);

/// Fills the common part: scene, accel, camera prepared for the scene's image size, random stream.
void integrator_init(integrator *it, const glint_scene *s, const accel *a);

/// The Whitted integrator (paper or colour mode, as the scene says).
integrator *whitted_create(const glint_scene *s, const accel *a, glint_error *err);
/// The path tracer; `sample_area_lights` false turns off next-event estimation towards emissive surfaces.
integrator *path_create(const glint_scene *s, const accel *a, bool sample_area_lights, glint_error *err);

/// Whether a stop was requested (polled before every sample).
static inline bool tile_pass_stopping(const tile_pass *tp) {
    return atomic_load_explicit(tp->stop, memory_order_relaxed) != 0;
}

/// A tile pass sample by sample, each with the generator of (seed, pixel, sample): the tile loop of an
/// integrator that renders one sample at a time. Inline, so that `sample` (a constant in the caller) is called
/// directly.
static inline bool integrator_tile_by_samples(const integrator *it, const tile_pass *tp, film_tile *ft,
                                              thread_stats *ts, integrator_sample_fn sample) {
    const render_settings *rs = &it->scene->settings;
    film_tile t = *ft; // a local copy whose address does not escape: its fields can live in registers
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
                film_tile_add(&t, sample(it, x, y, (uint32_t)k, &r, ts));
            }
        }
    *ft = t;
    return true;
}

#endif
