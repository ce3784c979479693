// integrator.h — the light-transport algorithms: the paper's and the colour Whitted ray tracer, and the
// path tracer. Each computes the radiance of one pixel sample from a const scene.
#ifndef GLINT_INTEGRATOR_H
#define GLINT_INTEGRATOR_H

#include "accel/accel.h"
#include "core/rng.h"
#include "core/vec.h"
#include "scene/scene.h"

#include <stdint.h>

/// Per-thread counters, one cache line each so that threads never share a line.
typedef struct thread_stats {
    _Alignas(64) uint64_t rays;  ///< closest-hit queries (camera and scattered/reflected rays)
    uint64_t shadow_rays;        ///< any-hit queries
    uint64_t discarded_samples;  ///< samples dropped because they were NaN or infinite
    uint64_t samples;
} thread_stats;

/// Where a ray met a surface, with what shading needs.
typedef struct surface {
    vec3 p;        ///< hit point
    vec3 n;        ///< unit shading normal facing against the incoming ray
    vec3 ng;       ///< unit geometric normal on the same side as n (for offsets and emission sides)
    bool front;    ///< the ray arrived on the side the outward (geometric) normal points to
    uint32_t material;
    float u, v;    ///< texture coordinates
    float error;   ///< bound on the distance of p from the true surface, for offsetting spawned rays
    hit_kind kind; ///< what was hit, for primitive-specific refinement (sphere re-projection)
    uint32_t prim, instance;
} surface;

/// Shading data of a hit on anything but a world-space sphere (quads, triangles, instances).
surface surface_at_general(const glint_scene *s, const ray *r, const hit *h);

/// Where ray r meets sphere sp at distance t: the point re-projected onto the sphere, c + q |r| / |q| with
/// q = p - c (pbrt's refinement: its error is then a few ulps of |r| and of p, whatever the error of t;
/// spawned rays are offset by that), and the unit normal q / |q|, outward (inward for a negative radius),
/// from the same reciprocal length: one square root and one division for both.
static inline void sphere_hit_frame(const sphere *sp, const ray *r, float t, vec3 *p, vec3 *outward) {
    vec3 q = v3_sub(ray_at(r, t), sp->center);
    float len = sqrtf(v3_len2(q));
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    *p = v3_fma(sp->center, q, fabsf(sp->radius) * inv);
    *outward = v3_scale(q, copysignf(inv, sp->radius));
}

/// Shading data of a closest hit found by accel_intersect for ray r.
static inline surface surface_at(const glint_scene *s, const ray *r, const hit *h) {
    if (h->kind != HIT_SPHERE || h->instance != HIT_NO_INSTANCE) return surface_at_general(s, r, h);
    surface out;
    const sphere *sp = &s->spheres[h->prim];
    vec3 outward;
    sphere_hit_frame(sp, r, h->t, &out.p, &outward);
    out.front = v3_dot(r->d, outward) < 0.0f;
    out.n = out.front ? outward : v3_neg(outward);
    out.ng = out.n;
    out.material = sp->material;
    // Texture coordinates cost an acos and an atan2: only for materials that look them up.
    const material *m = &s->materials[sp->material];
    out.u = out.v = 0.0f;
    if (m->albedo_texture >= 0 || m->emission_texture >= 0)
        sphere_uv(sp->radius < 0.0f ? v3_neg(outward) : outward, &out.u, &out.v);
    out.error = 0.0f;
    out.kind = HIT_SPHERE;
    out.prim = h->prim;
    out.instance = HIT_NO_INSTANCE;
    return out;
}

/// Linear RGB radiance of sample `sample` of pixel (x, y); r is seeded for exactly this sample.
vec3 integrator_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts);

vec3 whitted_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts);
vec3 path_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts);
/// The rest of path_sample once its camera ray is made (integrator_camera_ray with the same r): path_sample
/// is exactly the two in sequence, so a render loop can make the next sample's camera ray ahead of time. The
/// primary ray (origin o, direction d, all t > 0) is passed by its parts, in registers: a whole ray passed by
/// value is copied with wide loads that cannot be forwarded from the stores that just made it. d need not have
/// unit length.
vec3 path_trace(const glint_scene *s, vec3 o, vec3 d, rng *r, thread_stats *ts);

/// The path tracer's index of a scene's emissive quads and mesh triangles (for next-event estimation).
typedef struct path_lights path_lights;
/// (Re)builds s->path_lights from the scene's quads, mesh instances and materials; scene_prepare calls it. False
/// when out of memory.
bool path_prepare(glint_scene *s);
/// Frees s->path_lights and sets it to NULL; glint_scene_free calls it.
void path_release(glint_scene *s);

/// Film point of a sample: the pixel centre for a single sample, else uniformly jittered in the pixel.
static inline void integrator_film_point(const glint_scene *s, int x, int y, rng *r, float *fx, float *fy) {
    if (s->settings.spp == 1 && s->settings.integrator == INTEGRATOR_WHITTED) {
        *fx = (float)x + 0.5f;
        *fy = (float)y + 0.5f;
        return;
    }
    *fx = (float)x + rng_float(r);
    *fy = (float)y + rng_float(r);
}

/// The path tracer's camera ray of a sample of pixel (x, y): its film point (integrator_film_point), then the
/// camera's ray through it, both drawing from r. Its direction is not normalised (path_trace does that when
/// it needs to).
static inline ray integrator_camera_ray(const glint_scene *s, int x, int y, rng *r) {
    float fx, fy;
    integrator_film_point(s, x, y, r, &fx, &fy);
    return camera_ray_unnormalised(&s->camera, fx, fy, r);
}

#endif
