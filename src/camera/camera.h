// camera.h — the paper's viewport camera and the book's look-at thin-lens camera.
#ifndef GLINT_CAMERA_H
#define GLINT_CAMERA_H

#include "core/rng.h"
#include "core/sampling.h"
#include "core/vec.h"

#include <math.h>

typedef enum camera_kind { CAMERA_VIEWPORT, CAMERA_LOOKAT } camera_kind;

typedef struct camera {
    camera_kind kind;
    // viewport (the paper): eye at `position` looking along +z at a viewport_width x viewport_height
    // window at distance `distance`; kept in double so the paper's image is reproduced exactly.
    double position[3];
    double viewport_width, viewport_height, distance;
    // look-at (the book)
    vec3 lookfrom, lookat, vup;
    float vfov_degrees, defocus_angle_degrees, focus_distance;
    // the shutter (either camera): camera rays get times uniform in [open, close); open == close draws none
    float shutter_open, shutter_close;
    // derived by camera_prepare for the image size
    int image_width, image_height;
    vec3 pixel00, pixel_du, pixel_dv; ///< world position of film point (0,0) and per-pixel steps
    vec3 origin, defocus_u, defocus_v;
} camera;

/// Defaults: the look-at camera of the book (lookfrom (0,0,0) towards -z, vfov 90, no defocus).
camera camera_default(void);
/// Derives the per-image quantities; call once the image size is known.
void camera_prepare(camera *c, int width, int height);

/// Primary ray through film point (fx, fy) (pixel (x, y) covers [x, x+1) x [y, y+1), y down), with
/// lens samples drawn from r when the camera has defocus blur, at the shutter's opening time; its
/// direction, from the lens to the focus plane, is not normalised. Inline, as the render loop makes one per
/// sample.
static inline ray camera_ray_unnormalised(const camera *c, float fx, float fy, rng *r) {
    vec3 target = v3_add(c->pixel00, v3_add(v3_scale(c->pixel_du, fx), v3_scale(c->pixel_dv, fy)));
    ray out;
    out.tmin = 0.0f;
    out.tmax = INFINITY;
    out.time = c->shutter_open;
    if (c->kind == CAMERA_VIEWPORT) {
        // Primary rays start on the viewport plane (t >= 1 in the paper's parametrisation).
        out.o = target;
        out.d = v3_sub(target, c->origin);
        return out;
    }
    vec3 o = c->origin;
    if (c->defocus_angle_degrees > 0.0f) {
        float dx, dy;
        sample_unit_disk(r, &dx, &dy);
        o = v3_add(o, v3_add(v3_scale(c->defocus_u, dx), v3_scale(c->defocus_v, dy)));
    }
    out.o = o;
    out.d = v3_sub(target, o);
    return out;
}

/// camera_ray_unnormalised with a unit direction.
static inline ray camera_ray(const camera *c, float fx, float fy, rng *r) {
    ray out = camera_ray_unnormalised(c, fx, fy, r);
    out.d = v3_unit(out.d);
    return out;
}

/// Whether camera rays get a time drawn in the shutter (an open shutter: open < close).
static inline bool camera_has_shutter(const camera *c) { return c->shutter_open < c->shutter_close; }

/// The camera ray of a sample of pixel (x, y) as the path tracer makes it: a film point uniformly jittered in
/// the pixel (two draws from r: the Sobol' sampler's RNG_DIM_FILM), camera_ray_unnormalised through it (the lens:
/// RNG_DIM_LENS), then, with an open shutter, a time uniform in it (one draw, after the others, so that a closed
/// shutter leaves every other draw where it was; RNG_DIM_TIME; camera_batch.h makes sixteen at once).
static inline ray camera_sample_ray(const camera *c, int x, int y, rng *r) {
    float jx, jy;
    rng_float2(r, &jx, &jy);
    float fx = (float)x + jx, fy = (float)y + jy;
    ray out = camera_ray_unnormalised(c, fx, fy, r);
    if (camera_has_shutter(c)) {
        rng_decision(r, RNG_DIM_TIME);
        out.time = rng_range(r, c->shutter_open, c->shutter_close);
    }
    return out;
}

/// The paper's viewport point for film point (fx, fy), in double: V = (gx * Vw / W, gy * Vh / H, d)
/// relative to the eye, with gx = fx - W/2 and gy = H/2 - fy.
void camera_viewport_point(const camera *c, double fx, double fy, double out[3]);

#endif
