// transform.h — 4x4 affine matrices (translate, rotate, scale, compose, invert), their action on points,
// vectors, normals, rays and bounding boxes, and the axis-aligned bounding box type they act on.
#ifndef GLINT_TRANSFORM_H
#define GLINT_TRANSFORM_H

#include "core/vec.h"

#include <stdbool.h>

/// An axis-aligned bounding box; empty when lo > hi on some axis (bounds3_empty()).
typedef struct bounds3 {
    vec3 lo, hi;
} bounds3;

/// A row-major 4x4 matrix acting on column vectors: p' = M p. Affine matrices have last row 0 0 0 1.
typedef struct mat4 {
    float m[4][4];
} mat4;

/// A matrix together with its inverse: instances map world rays to object space with inv and
/// object-space hits back with m (normals with the inverse transpose).
typedef struct transform {
    mat4 m, inv;
} transform;

/// The empty box: +inf lower corner, -inf upper corner, so that any union with it is the other box.
static inline bounds3 bounds3_empty(void) {
    return (bounds3){v3s(INFINITY), v3s(-INFINITY)};
}
/// The smallest box holding b and point p.
static inline bounds3 bounds3_add(bounds3 b, vec3 p) { return (bounds3){v3_min(b.lo, p), v3_max(b.hi, p)}; }
/// The smallest box holding a and b.
static inline bounds3 bounds3_union(bounds3 a, bounds3 b) {
    return (bounds3){v3_min(a.lo, b.lo), v3_max(a.hi, b.hi)};
}
/// Whether the box holds no point.
static inline bool bounds3_is_empty(bounds3 b) { return !(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z); }

/// M p for a point (translation applies).
static inline vec3 mat4_apply_point(const mat4 *a, vec3 p) {
    const float (*m)[4] = a->m;
    return v3(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
              m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
              m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]);
}
/// M v for a direction (translation does not apply).
static inline vec3 mat4_apply_vector(const mat4 *a, vec3 v) {
    const float (*m)[4] = a->m;
    return v3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
              m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}
/// (M^-1)^T n for a normal, given inv = M^-1: normals stay perpendicular to transformed tangents. Not normalised.
static inline vec3 mat4_apply_normal(const mat4 *inv, vec3 n) {
    const float (*m)[4] = inv->m;
    return v3(m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
              m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
              m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z);
}
/// The ray M r: origin as a point, direction as a vector, left unnormalised so that t keeps its meaning.
static inline ray mat4_apply_ray(const mat4 *a, const ray *r) {
    ray out = *r;
    out.o = mat4_apply_point(a, r->o);
    out.d = mat4_apply_vector(a, r->d);
    return out;
}

/// The identity matrix.
mat4 mat4_identity(void);
/// Translation by t.
mat4 mat4_translate(vec3 t);
/// Scaling by s along the axes (components may be negative: a mirror).
mat4 mat4_scale(vec3 s);
/// Rotation by `degrees` about `axis` (any non-zero vector; right-handed: counter-clockwise looking down the
/// axis). Multiples of 90 degrees are exact. A zero or non-finite axis gives the identity.
mat4 mat4_rotate(vec3 axis, float degrees);
/// The product a b: the transform that applies b first, then a.
mat4 mat4_mul(const mat4 *a, const mat4 *b);
/// The transpose.
mat4 mat4_transpose(const mat4 *a);
/// Whether the last row is exactly 0 0 0 1 and every entry is finite.
bool mat4_is_affine(const mat4 *a);
/// Inverse of an affine matrix, computed in double; false (and *out untouched) when it is not affine or singular.
bool mat4_invert(const mat4 *a, mat4 *out);
/// Determinant of the linear (upper-left 3x3) part, in double: its sign says whether M mirrors.
double mat4_linear_det(const mat4 *a);
/// Whether the linear part of M is a rotation (or a mirror) times a uniform scale, up to the float rounding
/// of a composed rotation; *scale is that scale factor.
bool mat4_similarity_scale(const mat4 *a, double *scale);
/// A box holding the image under M of every point of b (Arvo 1990), computed in double and padded by the
/// rounding error of mat4_apply_point, so that float-transformed points of b are inside too.
bounds3 mat4_apply_bounds(const mat4 *a, bounds3 b);

/// A transform from a matrix and its computed inverse; false when the matrix is not affine or is singular.
bool transform_make(const mat4 *m, transform *out);
/// The identity transform.
transform transform_identity(void);
/// The transform that applies b first, then a (matrix a b, inverse b^-1 a^-1).
transform transform_compose(const transform *a, const transform *b);

#endif
