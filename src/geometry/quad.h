// quad.h — parallelogram quads (corner Q, edges u, v), tested as two watertight triangles, and boxes of
// six quads ("Ray Tracing: The Next Week", ch. 6-7).
#ifndef GLINT_QUAD_H
#define GLINT_QUAD_H

#include "core/vec.h"
#include "geometry/transform.h"
#include "geometry/triangle.h"

#include <stdbool.h>
#include <stdint.h>

/// A parallelogram: the points q + a u + b v for a, b in [0, 1]. Its front side is where u x v points.
typedef struct quad {
    vec3 q, u, v;
    vec3 p[4];         ///< corners q, q+u, q+u+v, q+v: the two triangles (p0,p1,p2), (p0,p2,p3) are tested
    vec3 normal;       ///< unit u x v
    float area;        ///< |u x v|
    float inv_len_u, inv_len_v; ///< 1 / |u| and 1 / |v|: distances along an edge in parameter units (spawn.h)
    float magnitude;   ///< the largest |coordinate| of its corners: what intersection errors scale with (spawn.h)
    uint32_t material; ///< index into the scene's materials
} quad;

/// A quad hit: distance and the parallelogram coordinates (alpha along u, beta along v), both in [0, 1].
typedef struct quad_hit {
    float t, alpha, beta;
} quad_hit;

/// A quad from corner q and edges u, v; false when u x v is zero or anything is not finite.
bool quad_make(vec3 q, vec3 u, vec3 v, uint32_t material, quad *out);
/// The six quads of the axis-aligned box with opposite corners a and b, normals outwards (the book's box()),
/// with corners snapped to exactly the box's coordinates so that the box is watertight.
/// False when the box is flat along some axis or not finite.
bool quad_box(vec3 a, vec3 b, uint32_t material, quad out[6]);
/// The quad q under affine m: its corners transformed as points (so corners shared by quads stay shared,
/// and a box stays watertight), u and v swapped under a mirror so that the front stays the front.
/// False when the result has no area or is not finite.
bool quad_transform(const quad *q, const mat4 *m, quad *out);
/// Bounds of a quad.
bounds3 quad_bounds(const quad *q);

/// The quad coordinates of a hit on triangle `half` (0: p0 p1 p2, 1: p0 p2 p3) with barycentrics th.
static inline quad_hit quad_hit_of(const tri_hit *th, int half) {
    // Half 0: b1 (q+u) + b2 (q+u+v) - q, so alpha = b1 + b2, beta = b2; half 1: b1 (q+u+v) + b2 (q+v) - q.
    if (half == 0) return (quad_hit){th->t, th->b1 + th->b2, th->b2};
    return (quad_hit){th->t, th->b1, th->b1 + th->b2};
}

/// Ray/quad test with tmin < t < tmax: the watertight triangle test on the quad's two triangles, the nearer
/// hit kept (the first triangle's on a tie), which is what the BVH's SIMD packets find when they test both.
static inline bool quad_intersect(const quad *qd, const tri_ray *tr, float tmin, float tmax, quad_hit *h) {
    tri_hit th0 = {0}, th1 = {0};
    bool hit0 = tri_intersect(tr, qd->p[0], qd->p[1], qd->p[2], tmin, tmax, &th0);
    bool hit1 = tri_intersect(tr, qd->p[0], qd->p[2], qd->p[3], tmin, hit0 ? th0.t : tmax, &th1);
    if (hit1) *h = quad_hit_of(&th1, 1);
    else if (hit0) *h = quad_hit_of(&th0, 0);
    return hit0 || hit1;
}

#endif
