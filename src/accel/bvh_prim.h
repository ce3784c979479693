// bvh_prim.h — the test of one primitive outside the SIMD packets, shared by the wide and the binary traversal
// (private to bvh_wide.c and bvh2_traverse.c): quads, triangles and spheres one at a time, moving spheres at
// the ray's time, and instances, whose ray is taken to object space and traced through their mesh's BVH.
//
// That last step recurses into a traversal: each file that includes this header defines `blas_traverse` (declared
// below) with its own traversal, the binary one for the binary BVH's instances and the wide one (bvh_wide.c, with
// bvh_wide.h's wide_run) for the wide BVH's. The recursion through instances thus stays within one module, and
// neither traversal calls the other. Include
// it only where prim_hit is used: its out-of-line helpers are plain static functions, as they were in one file.
#ifndef GLINT_BVH_PRIM_H
#define GLINT_BVH_PRIM_H

#include "accel/bvh_kernel.h"

/// Traces an instance's ray (in object space) through the BVH of its mesh, blas, improving *best; true when
/// anything was hit. Defined by every file that includes this header, with the traversal `mode` names.
static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode);

/// An instance: the ray taken to object space by world_to_object (direction not normalised, so t keeps its
/// meaning), then the mesh's BVH or the object-space sphere. True when it hit (any-hit queries stop there).
static bool instance_hit(const bvh *b, uint32_t index, const mat4 *world_to_object, const ray *r, hit *best, bool any,
                         trav_mode mode) {
    const instance *in = &b->input.geometry->instances[index];
    ray o = mat4_apply_ray(world_to_object, r);
    if (in->kind == INSTANCE_SPHERE) {
        const sphere *sp = &b->input.geometry->instance_spheres[in->index];
        float t;
        if (!sphere_intersect(sp->center, sp->radius, &o, o.tmin, o.tmax, &t)) return false;
        offer(best, (hit){t, in->index, HIT_SPHERE, index, 0.0f, 0.0f});
        return true;
    }
    return blas_traverse(&b->input.blas[in->index], &o, best, index, any, mode);
}

/// A moving instance: its transform at the ray's time, then as any instance. Out of line: only scenes with
/// motion reach it.
static __attribute__((noinline)) bool moving_instance_hit(const bvh *b, uint32_t index, const ray *r, hit *best,
                                                          bool any, trav_mode mode) {
    transform xf;
    motion_at(&b->input.geometry->motions[b->input.geometry->instances[index].motion - 1], r->time, &xf);
    return instance_hit(b, index, &xf.inv, r, best, any, mode);
}

/// A moving sphere: the sphere where it is at the ray's time.
static __attribute__((noinline)) bool moving_sphere_hit(const bvh *b, uint32_t index, const ray *r, hit *best,
                                                        uint32_t inst_id) {
    vec3 c = moving_sphere_center(&b->input.geometry->moving_spheres[index], r->time);
    float t;
    if (!sphere_intersect(c, b->input.geometry->moving_spheres[index].radius, r, r->tmin, r->tmax, &t)) return false;
    offer(best, (hit){t, index, HIT_MOVING_SPHERE, inst_id, 0.0f, 0.0f});
    return true;
}

/// One primitive that is not tested in SIMD: a quad, a triangle of b's mesh or of the flattened instance
/// `owner` (else HIT_NO_INSTANCE), an instance (or a sphere in the binary BVH). `inst_id` is the instance whose
/// mesh b is, or HIT_NO_INSTANCE. True when it hit.
static inline bool prim_hit(const bvh *b, uint32_t kind, uint32_t index, uint32_t owner, const ray *r, tri_cache *tc,
                            hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch ((prim_kind)kind) {
    case PRIM_SPHERE: {
        const sphere *s = &b->input.geometry->spheres[index];
        float t;
        if (!sphere_intersect(s->center, s->radius, r, r->tmin, r->tmax, &t)) return false;
        offer(best, (hit){t, index, HIT_SPHERE, inst_id, 0.0f, 0.0f});
        return true;
    }
    case PRIM_QUAD: {
        quad_hit qh;
        if (!quad_intersect(&b->input.geometry->quads[index], tri_for(tc, r), r->tmin, r->tmax, &qh)) return false;
        offer(best, (hit){qh.t, index, HIT_QUAD, inst_id, qh.alpha, qh.beta});
        return true;
    }
    case PRIM_TRIANGLE: {
        const mesh *m = owner == HIT_NO_INSTANCE ? b->input.mesh : b->input.flat[owner];
        tri_hit th;
        if (!mesh_intersect_triangle(m, index, tri_for(tc, r), r->tmin, r->tmax, &th)) return false;
        offer(best, (hit){th.t, index, HIT_TRIANGLE, owner == HIT_NO_INSTANCE ? inst_id : owner, th.b1, th.b2});
        return true;
    }
    case PRIM_INSTANCE: return instance_hit(b, index, &b->input.geometry->instances[index].xf.inv, r, best, any, mode);
    case PRIM_MOVING_SPHERE: return moving_sphere_hit(b, index, r, best, inst_id);
    case PRIM_MOVING_INSTANCE: return moving_instance_hit(b, index, r, best, any, mode);
    }
    return false;
}


#endif
