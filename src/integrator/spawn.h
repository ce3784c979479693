// spawn.h — where rays spawned at a surface start: the hit point pushed off the surface along the geometric
// normal, to the side the new ray goes, by a bound on the point's error (pbrt's offset ray origins), so that
// the new ray can neither start behind the surface it leaves nor re-hit it.
#ifndef GLINT_SPAWN_H
#define GLINT_SPAWN_H

#include "integrator/integrator.h"

#include <math.h>

/// Offset relative to the coordinate magnitudes that set a hit point's float error. For a sphere those are
/// the point's coordinates (rounding of the re-projected point) and the radius (sphere_intersect rounds
/// o - c and |o - c|^2 - r^2, misplacing a nearby origin by about 3 * 2^-24 r); 2^-21 is 2.7 times that
/// bound, and 8 times the smallest factor with which no ray re-hit its own sphere on the book's final scene.
#define SPAWN_OFFSET_REL 0x1p-21f

/// A surface point ready to spawn rays from: the refined point, the unit normal to offset along, and the
/// distance to offset by.
typedef struct spawn_point {
    vec3 p;
    vec3 n;
    float offset;
} spawn_point;

/// max(|x|, |y|, |z|), with plain comparisons (fmaxf is a libm call at -O3 without -ffinite-math-only).
static inline float spawn_max_abs(vec3 p) {
    float ax = fabsf(p.x), ay = fabsf(p.y), az = fabsf(p.z);
    return ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
}

/// The point p moved onto sphere sp in double precision, so that its only error is the final rounding to
/// float: c + (p - c) |r| / |p - c| (pbrt's re-projection).
static inline vec3 spawn_sphere_reproject(const sphere *sp, vec3 p) {
    double q[3] = {(double)p.x - sp->center.x, (double)p.y - sp->center.y, (double)p.z - sp->center.z};
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(len > 0.0)) return p;
    double k = fabs((double)sp->radius) / len;
    return v3((float)(sp->center.x + q[0] * k), (float)(sp->center.y + q[1] * k), (float)(sp->center.z + q[2] * k));
}

/// Where rays leave surface sf. A world-space sphere's point is re-projected onto it in double and offset by
/// SPAWN_OFFSET_REL (max|p_i| + |r|). Any other surface (quad, triangle, instanced sphere) keeps its point
/// and is offset by its own error bound sf->error (which scales with its vertices' magnitudes and its
/// instance's transform), and at least by SPAWN_OFFSET_REL max|p_i| for the rounding of p itself.
static inline spawn_point spawn_point_of(const glint_scene *s, const surface *sf) {
    spawn_point out;
    out.n = sf->ng;
    if (sf->kind == HIT_SPHERE && sf->instance == HIT_NO_INSTANCE) {
        const sphere *sp = &s->spheres[sf->prim];
        out.p = spawn_sphere_reproject(sp, sf->p);
        out.offset = SPAWN_OFFSET_REL * (spawn_max_abs(out.p) + fabsf(sp->radius)) + 1e-30f;
        return out;
    }
    out.p = sf->p;
    float own = SPAWN_OFFSET_REL * spawn_max_abs(sf->p);
    out.offset = (sf->error > own ? sf->error : own) + 1e-30f;
    return out;
}

/// The origin of a ray leaving sp along dir: offset to the side of the surface that dir points to.
static inline vec3 spawn_origin(const spawn_point *sp, vec3 dir) {
    return v3_fma(sp->p, sp->n, v3_dot(dir, sp->n) >= 0.0f ? sp->offset : -sp->offset);
}

/// A ray leaving sp along dir, hitting only at tmin < t < tmax.
static inline ray spawn_ray(const spawn_point *sp, vec3 dir, float tmin, float tmax) {
    ray out;
    out.o = spawn_origin(sp, dir);
    out.d = dir;
    out.tmin = tmin;
    out.tmax = tmax;
    return out;
}

#endif
