// triangle.h — the watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013): float, with an exact
// double fallback where an edge function is zero.
#ifndef GLINT_TRIANGLE_H
#define GLINT_TRIANGLE_H

#include "core/vec.h"
#include "geometry/transform.h"

#include <stdbool.h>
#include <stdint.h>

/// Per-ray constants of the watertight test: the axis that becomes z, and the shear that makes the ray
/// direction (0, 0, 1). Computed once per ray and shared by every triangle it is tested against.
typedef struct tri_ray {
    vec3 o;
    int kx, ky, kz;
    float sx, sy, sz;
} tri_ray;

/// A triangle hit: ray distance t and the barycentric weights of vertices p0, p1, p2 (b0 + b1 + b2 = 1).
typedef struct tri_hit {
    float t, b0, b1, b2;
} tri_hit;

/// The per-ray constants of ray r (direction need not be unit length; a zero direction never hits).
static inline tri_ray tri_ray_make(const ray *r) {
    tri_ray tr;
    tr.o = r->o;
    const float d[3] = {r->d.x, r->d.y, r->d.z};
    float ax = fabsf(d[0]), ay = fabsf(d[1]), az = fabsf(d[2]);
    // z becomes the largest direction component so that the divisions below are by the largest value. Without
    // branches: a bounce's direction is random, so branches on it would be mispredicted about half the time.
    int x_first = (ax > ay) & (ax > az), y_first = !(ax > ay) & (ay > az);
    int kz = 2 - 2 * x_first - y_first;
    float dz = d[kz];
    // x and y follow z cyclically; swapping them when dz < 0 keeps the winding, so the sign of the edge
    // functions stays meaningful. (A table, which the compiler does not turn back into branches.)
    static const uint8_t next[3][2] = {{1, 2}, {2, 0}, {0, 1}};
    int flip = dz < 0.0f;
    int kx = next[kz][flip], ky = next[kz][1 - flip];
    tr.kx = kx;
    tr.ky = ky;
    tr.kz = kz;
    tr.sx = d[kx] / dz;
    tr.sy = d[ky] / dz;
    tr.sz = 1.0f / dz;
    return tr;
}

/// The vertices of a triangle moved to ray space (tri_ray): (x, y) sheared so that the ray is the z axis.
typedef struct tri_sheared {
    float ax, ay, az, bx, by, bz, cx, cy, cz;
} tri_sheared;

static inline tri_sheared tri_shear(const tri_ray *tr, vec3 p0, vec3 p1, vec3 p2) {
    vec3 a = v3_sub(p0, tr->o), b = v3_sub(p1, tr->o), c = v3_sub(p2, tr->o);
    tri_sheared s;
    s.az = v3_comp(a, tr->kz);
    s.bz = v3_comp(b, tr->kz);
    s.cz = v3_comp(c, tr->kz);
    s.ax = v3_comp(a, tr->kx) - tr->sx * s.az;
    s.ay = v3_comp(a, tr->ky) - tr->sy * s.az;
    s.bx = v3_comp(b, tr->kx) - tr->sx * s.bz;
    s.by = v3_comp(b, tr->ky) - tr->sy * s.bz;
    s.cx = v3_comp(c, tr->kx) - tr->sx * s.cz;
    s.cy = v3_comp(c, tr->ky) - tr->sy * s.cz;
    return s;
}

/// The test in double, for tri_intersect when an edge function rounds to zero in float: the products of two
/// floats are exact in double, so the signs are exact.
static inline bool tri_intersect_exact(const tri_ray *tr, const tri_sheared *s, float tmin, float tmax, tri_hit *h) {
    double u = (double)s->cx * s->by - (double)s->cy * s->bx;
    double v = (double)s->ax * s->cy - (double)s->ay * s->cx;
    double w = (double)s->bx * s->ay - (double)s->by * s->ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    double det = u + v + w;
    if (det == 0.0 || det != det) return false; // ray in the triangle's plane, degenerate triangle, or NaN
    double scaled_t = (u * s->az + v * s->bz + w * s->cz) * (double)tr->sz;
    double inv_det = 1.0 / det;
    float t = (float)(scaled_t * inv_det);
    if (!(t > tmin && t < tmax)) return false;
    h->t = t;
    h->b0 = (float)(u * inv_det);
    h->b1 = (float)(v * inv_det);
    h->b2 = (float)(w * inv_det);
    return true;
}

/// Watertight ray/triangle test of Woop, Benthin and Wald: the hit with tmin < t < tmax, either side of the
/// triangle. Rays through a shared edge or vertex hit at least one of the triangles around it. Vertices are
/// sheared into ray space (the same float operations for every triangle that shares a vertex); the edge
/// functions are differences of two rounded products, so the two triangles of an edge compute exactly opposite
/// values, and rounding is monotone, so a value's sign is exact unless it is zero, where the test is redone in
/// double (tri_intersect_exact). This needs multiply-adds left unfused (-ffp-contract=off, as glint builds):
/// a fused one rounds the two orders of an edge differently. The SIMD packets compute the same, lane by lane.
static inline bool tri_intersect(const tri_ray *tr, vec3 p0, vec3 p1, vec3 p2, float tmin, float tmax, tri_hit *h) {
    tri_sheared s = tri_shear(tr, p0, p1, p2);
    // Edge functions: twice the signed areas of the 2D triangles (origin, edge), in ray space.
    float u = s.cx * s.by - s.cy * s.bx;
    float v = s.ax * s.cy - s.ay * s.cx;
    float w = s.bx * s.ay - s.by * s.ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) return tri_intersect_exact(tr, &s, tmin, tmax, h);
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    float det = u + v + w;
    if (det == 0.0f || det != det) return false; // NaN (or an overflow to opposite infinities)
    float scaled_t = (u * s.az + v * s.bz + w * s.cz) * tr->sz;
    float inv_det = 1.0f / det;
    float t = scaled_t * inv_det;
    if (!(t > tmin && t < tmax)) return false;
    h->t = t;
    h->b0 = u * inv_det;
    h->b1 = v * inv_det;
    h->b2 = w * inv_det;
    return true;
}

/// Bounds of a triangle.
static inline bounds3 tri_bounds(vec3 p0, vec3 p1, vec3 p2) {
    return (bounds3){v3_min(p0, v3_min(p1, p2)), v3_max(p0, v3_max(p1, p2))};
}

#endif
