// spawn.h — where rays spawned at a surface start: the hit point pushed off the surface along the geometric
// normal, to the side the new ray goes, by a bound on the point's error (pbrt's offset ray origins), so that
// the new ray can neither start behind the surface it leaves nor re-hit it.
#ifndef GLINT_SPAWN_H
#define GLINT_SPAWN_H

#include "integrator/surface.h"

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
    float time; ///< of the ray that arrived: the rays spawned here keep it
} spawn_point;

/// The spawn point at p, re-projected onto a world sphere of radius r (sphere_hit_frame), with unit normal n,
/// for rays at `time`: offset by SPAWN_OFFSET_REL (max|p_i| + |r|).
static inline spawn_point spawn_point_sphere(vec3 p, vec3 n, float r, float time) {
    spawn_point out = {p, n, SPAWN_OFFSET_REL * (v3_max_abs(p) + fabsf(r)) + 1e-30f, time};
    return out;
}

/// Moves p, at parallelogram coordinate x along edge e (1 / |e| = inv_len), at least `margin` inside the quad's
/// two edges across e: a hit near an edge may round to beyond the neighbouring face's plane (a closed mirror
/// box's corner), and an origin offset only along the normal would start outside that face and escape through it.
static inline vec3 spawn_inside_edges(vec3 p, float x, vec3 e, float inv_len, float margin) {
    float m = margin * inv_len; // the margin in parameter units; an edge shorter than two margins keeps its point
    if (!(m < 0.5f)) return p;
    if (x < m) return v3_fma(p, e, m - x);
    if (x > 1.0f - m) return v3_fma(p, e, (1.0f - m) - x);
    return p;
}

/// Where rays leave surface sf, at its time. A world-space or moving sphere's point, re-projected onto it by
/// surface_at, is offset as spawn_point_sphere says. Any other surface (quad, triangle, instanced sphere) keeps its point
/// and is offset by its error bound sf->error (the rounding of p, from surface_at) plus SPAWN_OFFSET_REL
/// times the larger of max|p_i| and the primitive's own magnitude (surface.magnitude); a world
/// quad's point is also kept that offset inside its edges (spawn_inside_edges).
static inline spawn_point spawn_point_of(const glint_scene *s, const surface *sf) {
    if (sf->kind == HIT_SPHERE && sf->instance == HIT_NO_INSTANCE)
        return spawn_point_sphere(sf->p, sf->ng, s->spheres[sf->prim].radius, sf->time);
    if (sf->kind == HIT_MOVING_SPHERE) return spawn_point_sphere(sf->p, sf->ng, s->moving_spheres[sf->prim].radius, sf->time);
    spawn_point out;
    out.time = sf->time;
    out.n = sf->ng;
    out.p = sf->p;
    float mag = v3_max_abs(sf->p), prim = sf->magnitude;
    out.offset = sf->error + SPAWN_OFFSET_REL * (prim > mag ? prim : mag) + 1e-30f;
    if (sf->kind == HIT_QUAD && sf->instance == HIT_NO_INSTANCE) { // (u, v) are the quad's (alpha, beta)
        const quad *q = &s->quads[sf->prim];
        out.p = spawn_inside_edges(out.p, sf->u, q->u, q->inv_len_u, out.offset);
        out.p = spawn_inside_edges(out.p, sf->v, q->v, q->inv_len_v, out.offset);
    }
    return out;
}

/// The origin of a ray leaving sp along dir: offset to the side of the surface that dir points to.
static inline vec3 spawn_origin(const spawn_point *sp, vec3 dir) {
    return v3_fma(sp->p, sp->n, v3_dot(dir, sp->n) >= 0.0f ? sp->offset : -sp->offset);
}

/// A ray leaving sp along dir, hitting only at tmin < t < tmax, at sp's time.
static inline ray spawn_ray(const spawn_point *sp, vec3 dir, float tmin, float tmax) {
    ray out;
    out.o = spawn_origin(sp, dir);
    out.d = dir;
    out.tmin = tmin;
    out.tmax = tmax;
    out.time = sp->time;
    return out;
}

#endif
