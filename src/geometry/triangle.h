// triangle.h — the watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013).
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
    float ax = fabsf(r->d.x), ay = fabsf(r->d.y), az = fabsf(r->d.z);
    // z becomes the largest direction component so that the divisions below are by the largest value.
    int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    float dz = v3_comp(r->d, kz);
    // Swapping x and y when dz < 0 keeps the winding, so the sign of the edge functions stays meaningful.
    if (dz < 0.0f) { int tmp = kx; kx = ky; ky = tmp; }
    tr.kx = kx;
    tr.ky = ky;
    tr.kz = kz;
    tr.sx = v3_comp(r->d, kx) / dz;
    tr.sy = v3_comp(r->d, ky) / dz;
    tr.sz = 1.0f / dz;
    return tr;
}

/// Watertight ray/triangle test: the hit with tmin < t < tmax, either side of the triangle. Rays through a
/// shared edge or vertex hit at least one of the triangles around it. Vertices are sheared into ray space
/// in float (the same operations for every triangle that shares a vertex), and the edge functions are
/// evaluated in double, where the products of two floats are exact: their signs are exact and opposite for
/// the two triangles of an edge whether or not the compiler fuses multiply-adds. This replaces the paper's
/// float path with a double fallback at zero, at about the same cost in scalar code.
static inline bool tri_intersect(const tri_ray *tr, vec3 p0, vec3 p1, vec3 p2, float tmin, float tmax, tri_hit *h) {
    vec3 a = v3_sub(p0, tr->o), b = v3_sub(p1, tr->o), c = v3_sub(p2, tr->o);
    float az = v3_comp(a, tr->kz), bz = v3_comp(b, tr->kz), cz = v3_comp(c, tr->kz);
    float ax = v3_comp(a, tr->kx) - tr->sx * az, ay = v3_comp(a, tr->ky) - tr->sy * az;
    float bx = v3_comp(b, tr->kx) - tr->sx * bz, by = v3_comp(b, tr->ky) - tr->sy * bz;
    float cx = v3_comp(c, tr->kx) - tr->sx * cz, cy = v3_comp(c, tr->ky) - tr->sy * cz;
    // Edge functions: twice the signed areas of the 2D triangles (origin, edge), in ray space.
    double u = (double)cx * by - (double)cy * bx;
    double v = (double)ax * cy - (double)ay * cx;
    double w = (double)bx * ay - (double)by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    double det = u + v + w;
    if (det == 0.0 || det != det) return false; // ray in the triangle's plane, degenerate triangle, or NaN
    // Distance: the barycentric mix of the vertices' z in ray space, scaled by 1/dz.
    double scaled_t = (u * az + v * bz + w * cz) * (double)tr->sz;
    double inv_det = 1.0 / det;
    float t = (float)(scaled_t * inv_det);
    if (!(t > tmin && t < tmax)) return false;
    h->t = t;
    h->b0 = (float)(u * inv_det);
    h->b1 = (float)(v * inv_det);
    h->b2 = (float)(w * inv_det);
    return true;
}

/// Bounds of a triangle.
static inline bounds3 tri_bounds(vec3 p0, vec3 p1, vec3 p2) {
    return (bounds3){v3_min(p0, v3_min(p1, p2)), v3_max(p0, v3_max(p1, p2))};
}

#endif
