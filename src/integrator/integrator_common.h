// integrator_common.h — what every integrator shares and the render loop sees of one: the tile pass, the
// common state and its function pointers, and the small helpers the Whitted and path integrators both use. The
// integrators (whitted.c, path.c) build on this file, and the chooser (integrator.c) on them: nothing here calls up.
#ifndef GLINT_INTEGRATOR_COMMON_H
#define GLINT_INTEGRATOR_COMMON_H

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

typedef struct integrator integrator;

/// Radiance of sample `sample` of pixel (x, y); r is seeded for exactly this sample (rng_for_stream). When aov is not
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
    uint64_t stream;          ///< rng_seed_stream(seed), shared by every sample's PCG32 generator, or
                              ///< RNG_SOBOL_STREAM: the samples draw from the Sobol' sampler (rng_for_stream)
    integrator_sample_fn sample;
    integrator_tile_fn render_tile;
    void (*release)(integrator *it); ///< frees the integrator's own state, or NULL
    bool alpha_masks;         ///< some material has an alpha mask: closest-hit and shadow queries go through
                              ///< integrator/alpha_mask.h, one ray at a time (no streams, no camera packets)
};

/// The stream of a render's generators (rng_for_stream): the Sobol' sampler's for the path tracer when the scene
/// asks for it, else PCG32's stream of the seed (the Whitted integrators always).
uint64_t integrator_stream(const render_settings *rs);
/// Fills the common part: scene, accel, camera prepared for the scene's image size, random stream, alpha_masks.
void integrator_init(integrator *it, const glint_scene *s, const accel *a);

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

/// Choices of a render that are not part of the scene.
typedef struct integrator_options {
    bool no_light_sampling; ///< path tracer: no next-event estimation towards area lights (tests compare both)
    bool no_light_tree;     ///< path tracer: lights chosen by power alone however many there are (tests compare both)
    bool light_sampling_only; ///< path tracer (tests of MIS): next-event estimation unweighted, and BSDF samples that
                              ///< hit a light it samples add nothing (the estimator of light sampling alone)
} integrator_options;

#endif
