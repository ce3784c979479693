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

#include <math.h>
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

/// Radiance of sample `sample` of pixel (x, y); r is seeded for exactly this sample (rng_for_key). When aov is not
/// NULL it receives the sample's AOVs (film_aov_sample); the radiance and the random numbers drawn are the same
/// either way.
typedef vec3 (*integrator_sample_fn)(const integrator *it, int x, int y, uint32_t sample, rng *r, thread_stats *ts,
                                     film_aov_sample *aov);
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

/// The albedo an AOV records: each channel clamped to [0, 1], as denoisers expect (NaN becomes 0).
static inline vec3 integrator_aov_albedo(vec3 a) {
    return v3(a.x > 0.0f ? (a.x < 1.0f ? a.x : 1.0f) : 0.0f, a.y > 0.0f ? (a.y < 1.0f ? a.y : 1.0f) : 0.0f,
              a.z > 0.0f ? (a.z < 1.0f ? a.z : 1.0f) : 0.0f);
}

/// The albedo an emitter records: its emission scaled so that the largest channel is 1 (0 when it is black), so
/// that a light's pixels tell a denoiser its colour and its edges.
static inline vec3 integrator_aov_emitter(vec3 le) {
    float peak = v3_max_comp(le);
    return peak > 0.0f && isfinite(peak) ? integrator_aov_albedo(v3_scale(le, 1.0f / peak)) : v3s(0.0f);
}

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

#endif
