// motion.h — what moves while the shutter is open: spheres along a straight line, and transforms between two
// poses (translation linear, rotation by quaternion slerp, scale linear). Time 0 is the first pose, time 1 the
// second; the camera's shutter picks times in [0, 1].
#ifndef GLINT_MOTION_H
#define GLINT_MOTION_H

#include "core/vec.h"
#include "geometry/sphere.h"
#include "geometry/transform.h"

#include <stdbool.h>
#include <stdint.h>

/// A sphere whose centre moves linearly: center at time 0, center + motion at time 1 (book 2's convention,
/// center(t) = center + t (center2 - center)). Kept apart from the static spheres so that their tests stay as
/// they are.
typedef struct moving_sphere {
    vec3 center;       ///< centre at time 0
    vec3 motion;       ///< centre at time 1 minus centre at time 0
    float radius;      ///< may be negative: same surface, normal pointing inward
    uint32_t material; ///< index into scene materials
} moving_sphere;

/// The centre at time t: one fused multiply-add per axis, the same bits wherever it is computed.
static inline vec3 moving_sphere_center(const moving_sphere *s, float t) { return v3_fma(s->center, s->motion, t); }

/// The sphere at time t.
static inline sphere moving_sphere_at(const moving_sphere *s, float t) {
    sphere out = {moving_sphere_center(s, t), s->radius, s->material};
    return out;
}

/// A pose decomposed for interpolation: M = T R S, with T a translation, R a rotation (unit quaternion
/// w + xi + yj + zk) and S the symmetric stretch of the polar decomposition (scale, and shear; a mirror is
/// folded into S so that R stays a proper rotation).
typedef struct motion_pose {
    double t[3];
    double q[4]; ///< x, y, z, w
    double s[3][3];
} motion_pose;

/// A transform that moves from pose 0 (time 0) to pose 1 (time 1). The quaternions are on the same
/// hemisphere, so that the slerp takes the shorter arc.
typedef struct motion {
    motion_pose p0, p1;
    double theta;         ///< angle between the two quaternions (half the rotation between the poses)
} motion;

/// Decomposes the start and end matrices; false (with *out untouched) when a matrix is not affine or
/// singular, or when one mirrors and the other does not (every pose between would have to pass through a
/// flat one).
bool motion_make(const mat4 *m0, const mat4 *m1, motion *out);
/// The transform (matrix and inverse) at time t: T and S interpolated linearly, R by slerp. Computed in
/// double, the same bits for the same t wherever it is called.
void motion_at(const motion *m, float t, transform *out);
/// A box holding every point of object-space box b under the transform at every time in [t0, t1]: the boxes
/// at 65 evenly spread times, each padded by how far any point of b can travel in half the time between them
/// (a bound from the poses' translation, rotation angle and stretch), so the union holds the whole sweep.
bounds3 motion_bounds(const motion *m, bounds3 b, float t0, float t1);

#endif
