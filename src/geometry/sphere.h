// sphere.h — spheres: a centre and a radius; a negative radius turns the normal inward (a hollow shell).
#ifndef GLINT_SPHERE_H
#define GLINT_SPHERE_H

#include "core/vec.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct sphere {
    vec3 center;
    float radius;       ///< may be negative: same surface, normal pointing inward
    uint32_t material;  ///< index into scene materials
} sphere;

/// Nearest root t of |o + t d - c| = |r| with tmin < t < tmax, in the form of Haines et al. (Ray Tracing
/// Gems, ch. 7) that keeps precision for large spheres and distant rays. Returns false when there is none.
static inline bool sphere_intersect(vec3 center, float radius, const ray *r, float tmin, float tmax, float *t_out) {
    vec3 f = v3_sub(r->o, center);
    float a = v3_dot(r->d, r->d), inv_a = 1.0f / a; // one division per ray, shared by a packet's spheres
    float b = -v3_dot(f, r->d); // half of -b of the textbook quadratic
    // |f - (f.d/a) d|^2 is the squared distance from the centre to the line: no cancellation in b^2 - ac.
    vec3 l = v3_fma(f, r->d, b * inv_a);
    float disc = radius * radius - v3_len2(l);
    if (disc < 0.0f) return false;
    float c = v3_len2(f) - radius * radius;
    float q = b + copysignf(sqrtf(a * disc), b);
    float t0 = c / q, t1 = q * inv_a; // the two roots, neither computed by subtracting near-equal numbers
    if (q == 0.0f) t0 = t1;
    if (t0 > t1) { float tmp = t0; t0 = t1; t1 = tmp; }
    if (t0 > tmin && t0 < tmax) { *t_out = t0; return true; }
    if (t1 > tmin && t1 < tmax) { *t_out = t1; return true; }
    return false;
}

/// Outward normal (for a negative radius, inward) at a point p on the sphere.
static inline vec3 sphere_normal(const sphere *s, vec3 p) { return v3_scale(v3_sub(p, s->center), 1.0f / s->radius); }

/// (u, v) texture coordinates of a unit normal: u from the angle around +y, v from bottom to top.
static inline void sphere_uv(vec3 n, float *u, float *v) {
    const float pi = 3.14159265358979f;
    float theta = acosf(fmaxf(-1.0f, fminf(1.0f, -n.y)));
    float phi = atan2f(-n.z, n.x) + pi;
    *u = phi / (2.0f * pi);
    *v = theta / pi;
}

#endif
