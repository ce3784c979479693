// surface.c — shading data of hits on quads, triangles and instances (world spheres are inline in surface.h).
#include "integrator/surface.h"

#include <math.h>

// Bound on the rounding error of a point computed as o + t d in float, relative to its magnitude: a few
// ulps of the largest coordinate involved (pbrt's gamma(n) bounds, rounded up generously).
static float point_error(vec3 o, vec3 p) {
    vec3 ao = v3(fabsf(o.x), fabsf(o.y), fabsf(o.z)), ap = v3(fabsf(p.x), fabsf(p.y), fabsf(p.z));
    return (v3_max_comp(ao) + v3_max_comp(ap)) * 0x1p-20f;
}

// Orients the shading record: `outward` is the geometric normal the surface was defined with, `ns` the
// shading normal on the same side; both end up facing against the ray.
static void orient(surface *out, const ray *r, vec3 outward, vec3 ns) {
    out->front = v3_dot(r->d, outward) < 0.0f;
    out->ng = out->front ? outward : v3_neg(outward);
    out->n = out->front ? ns : v3_neg(ns);
}

surface surface_at_general(const glint_scene *s, const ray *r, const hit *h) {
    surface out;
    out.p = ray_at(r, h->t);
    out.error = point_error(r->o, out.p);
    out.kind = (hit_kind)h->kind;
    out.prim = h->prim;
    out.instance = h->instance;
    out.u = h->b1;
    out.v = h->b2;
    out.time = r->time;
    if (h->kind == HIT_MOVING_SPHERE) { // the sphere where it was at the ray's time, then as a world sphere
        sphere sp = moving_sphere_at(&s->moving_spheres[h->prim], r->time);
        vec3 outward;
        sphere_hit_frame(&sp, r, h->t, &out.p, &outward);
        orient(&out, r, outward, outward);
        out.material = sp.material;
        out.u = out.v = 0.0f;
        const material *m = &s->materials[sp.material];
        if (m->albedo_texture >= 0 || m->emission_texture >= 0)
            sphere_uv(sp.radius < 0.0f ? v3_neg(outward) : outward, &out.u, &out.v);
        out.error = 0.0f;
        return out;
    }
    if (h->instance == HIT_NO_INSTANCE) { // world-space quad (world spheres take the inline path)
        const quad *q = &s->quads[h->prim];
        orient(&out, r, q->normal, q->normal);
        out.material = q->material;
        return out;
    }
    const instance *in = &s->instances[h->instance];
    transform moved; // a moving instance's transform at the ray's time (the one the hit was found with)
    if (in->motion) motion_at(&s->motions[in->motion - 1], r->time, &moved);
    const transform *xf = in->motion ? &moved : &in->xf;
    // Object-space quantities go to world space: normals by the inverse transpose.
    if (in->kind == INSTANCE_SPHERE) {
        const sphere *sp = &s->instance_spheres[in->index];
        ray ro = mat4_apply_ray(&xf->inv, r);
        vec3 po = ray_at(&ro, h->t);
        vec3 no = sphere_normal(sp, po);
        vec3 nw = v3_unit(mat4_apply_normal(&xf->inv, no));
        orient(&out, r, nw, nw);
        out.material = in->material >= 0 ? (uint32_t)in->material : sp->material;
        sphere_uv(sp->radius < 0.0f ? v3_neg(no) : no, &out.u, &out.v);
        return out;
    }
    const scene_mesh *sm = &s->meshes[in->index];
    tri_hit th = {h->t, 1.0f - h->b1 - h->b2, h->b1, h->b2};
    mesh_shading sh = mesh_shade(&sm->geometry, h->prim, &th);
    vec3 ng = sh.ng, ns = sh.ns;
    if (!(in->motion ? mat4_keeps_directions(&xf->m) : in->keeps_directions)) {
        ng = v3_unit(mat4_apply_normal(&xf->inv, sh.ng));
        ns = v3_unit(mat4_apply_normal(&xf->inv, sh.ns));
    }
    orient(&out, r, ng, ns);
    out.u = sh.u;
    out.v = sh.v;
    int32_t slot = sm->geometry.triangles[h->prim].material;
    if (in->material >= 0) out.material = (uint32_t)in->material;
    else if (slot >= 0 && (size_t)slot < sm->slot_count) out.material = sm->slot_material[slot];
    else out.material = sm->default_material;
    return out;
}
