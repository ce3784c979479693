// surface.h — what shading needs to know of a closest hit: the point, the normals facing the ray, the
// material and texture coordinates, and a bound on the point's error for offsetting spawned rays.
#ifndef GLINT_SURFACE_H
#define GLINT_SURFACE_H

#include "accel/accel.h"
#include "core/vec.h"
#include "scene/scene.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/// Where a ray met a surface, with what shading needs.
typedef struct surface {
    vec3 p;        ///< hit point
    vec3 n;        ///< unit shading normal facing against the incoming ray
    vec3 ng;       ///< unit geometric normal on the same side as n (for offsets and emission sides)
    bool front;    ///< the ray arrived on the side the outward (geometric) normal points to
    uint32_t material;
    float u, v;    ///< texture coordinates
    float error;   ///< bound on the distance of p from the true surface, for offsetting spawned rays
    float magnitude; ///< largest |coordinate| of the primitive in world units, what the error of intersecting it
                     ///< again scales with (spawn.h; 0 for spheres, whose points are re-projected onto them)
    hit_kind kind; ///< what was hit, for primitive-specific refinement (sphere re-projection)
    uint32_t prim, instance;
    float time;    ///< the ray's time: rays leaving the surface keep it
} surface;

/// Shading data of a hit on anything but a world-space sphere; surface_at_into calls it only for moving spheres,
/// instanced spheres and the triangles of instances that move or turn directions (it takes the others inline).
surface surface_at_general(const glint_scene *s, const ray *r, const hit *h);

/// Bound on the rounding error of a point computed as o + t d in float, relative to its magnitude: a few
/// ulps of the largest coordinate involved (pbrt's gamma(n) bounds, rounded up generously).
static inline float surface_point_error(vec3 o, vec3 p) {
    vec3 ao = v3(fabsf(o.x), fabsf(o.y), fabsf(o.z)), ap = v3(fabsf(p.x), fabsf(p.y), fabsf(p.z));
    return (v3_max_comp(ao) + v3_max_comp(ap)) * 0x1p-20f;
}

/// Orients the shading record: `outward` is the geometric normal the surface was defined with, `ns` the
/// shading normal on the same side; both end up facing against the ray.
static inline void surface_orient(surface *out, const ray *r, vec3 outward, vec3 ns) {
    out->front = v3_dot(r->d, outward) < 0.0f;
    out->ng = out->front ? outward : v3_neg(outward);
    out->n = out->front ? ns : v3_neg(ns);
}

/// The fields of every hit but a world sphere's: the point o + t d, its error bound, and what was hit.
static inline void surface_start(surface *out, const ray *r, const hit *h) {
    out->p = ray_at(r, h->t);
    out->error = surface_point_error(r->o, out->p);
    out->kind = (hit_kind)h->kind;
    out->prim = h->prim;
    out->instance = h->instance;
    out->u = h->b1;
    out->v = h->b2;
    out->time = r->time;
}

/// The scene material of triangle `tri` of mesh sm placed by instance in: the instance's, else the triangle's
/// slot's, else the mesh's default.
static inline uint32_t surface_mesh_material(const scene_mesh *sm, const instance *in, size_t tri) {
    int32_t slot = sm->geometry.triangles[tri].material;
    if (in->material >= 0) return (uint32_t)in->material;
    if (slot >= 0 && (size_t)slot < sm->slot_count) return sm->slot_material[slot];
    return sm->default_material;
}

/// Shading data of a hit on a world quad, or on a triangle of a mesh instance that neither moves nor turns
/// directions (every flattened mesh): inline, without the other kinds' code; false (*out unset) for other hits.
static inline __attribute__((always_inline)) bool surface_at_flat(const glint_scene *s, const ray *r, const hit *h,
                                                                  surface *out) {
    if (h->instance == HIT_NO_INSTANCE) {
        if (h->kind != HIT_QUAD) return false;
        const quad *q = &s->quads[h->prim];
        surface_start(out, r, h);
        surface_orient(out, r, q->normal, q->normal);
        out->material = q->material;
        out->magnitude = q->magnitude;
        return true;
    }
    const instance *in = &s->instances[h->instance];
    if (h->kind != HIT_TRIANGLE || in->motion || !in->keeps_directions) return false;
    const scene_mesh *sm = &s->meshes[in->index];
    tri_hit th = {h->t, 1.0f - h->b1 - h->b2, h->b1, h->b2};
    mesh_shading sh = mesh_shade(&sm->geometry, h->prim, &th);
    surface_start(out, r, h);
    surface_orient(out, r, sh.ng, sh.ns);
    out->u = sh.u;
    out->v = sh.v;
    out->material = surface_mesh_material(sm, in, h->prim);
    out->magnitude = sh.magnitude * in->stretch;
    return true;
}

/// Starts fetching what surface_at will read of a hit on a mesh's triangle (mesh_prefetch_shade), for a loop that
/// shades many hits in turn and can call this a few hits ahead; the traversal fetched the triangle's record when it
/// found the hit.
static inline __attribute__((always_inline)) void surface_prefetch(const glint_scene *s, const hit *h) {
    if (h->kind != HIT_TRIANGLE || h->instance == HIT_NO_INSTANCE) return;
    const instance *in = &s->instances[h->instance];
    if (in->kind != INSTANCE_MESH) return;
    mesh_prefetch_shade(&s->meshes[in->index].geometry, h->prim);
}

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

/// Shading data of a closest hit found by accel_intersect for ray r, written into *out: a caller's own record,
/// where a returned one was copied, and the copy's wide loads waited for the record's narrow stores to retire
/// (8 % of path_trace's samples in book 2's final scene).
static inline void surface_at_into(const glint_scene *s, const ray *r, const hit *h, surface *out) {
    if (h->kind != HIT_SPHERE || h->instance != HIT_NO_INSTANCE) {
        if (!surface_at_flat(s, r, h, out)) *out = surface_at_general(s, r, h);
        return;
    }
    const sphere *sp = &s->spheres[h->prim];
    vec3 outward;
    sphere_hit_frame(sp, r, h->t, &out->p, &outward);
    out->front = v3_dot(r->d, outward) < 0.0f;
    out->n = out->front ? outward : v3_neg(outward);
    out->ng = out->n;
    out->material = sp->material;
    // Texture coordinates cost an acos and an atan2: only for materials that look them up.
    const material *m = &s->materials[sp->material];
    out->u = out->v = 0.0f;
    if (m->albedo_texture >= 0 || m->emission_texture >= 0 || m->alpha_texture >= 0)
        sphere_uv(sp->radius < 0.0f ? v3_neg(outward) : outward, &out->u, &out->v);
    out->error = out->magnitude = 0.0f;
    out->kind = HIT_SPHERE;
    out->prim = h->prim;
    out->instance = HIT_NO_INSTANCE;
    out->time = r->time;
}

/// surface_at_into's record, returned.
static inline surface surface_at(const glint_scene *s, const ray *r, const hit *h) {
    surface out;
    surface_at_into(s, r, h, &out);
    return out;
}

/// Where solid (3D) textures are evaluated for sf: on a world quad the point q + alpha u + beta v, exactly in
/// the quad's plane for an axis-aligned quad (u and v are 0 across it), so that a checker on a floor at
/// exactly a cell boundary (y = 0) does not turn to noise as o + t d rounds to either side; elsewhere, and
/// for a material slot with no texture (`texture_index` < 0, where the point is not looked at), sf->p.
static inline vec3 surface_texture_point(const glint_scene *s, const surface *sf, int32_t texture_index) {
    if (texture_index < 0 || sf->kind != HIT_QUAD || sf->instance != HIT_NO_INSTANCE) return sf->p;
    const quad *q = &s->quads[sf->prim];
    return v3_add(q->q, v3_add(v3_scale(q->u, sf->u), v3_scale(q->v, sf->v)));
}

#endif
