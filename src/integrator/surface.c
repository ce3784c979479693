// surface.c — shading data of hits on moving spheres, instanced spheres and meshes placed by moving or turning
// instances (world spheres, world quads and the other meshes' triangles are inline in surface.h).
#include "integrator/surface.h"

#include <math.h>

surface surface_at_general(const glint_scene *s, const ray *r, const hit *h) {
    surface out;
    surface_start(&out, r, h);
    if (h->kind == HIT_MOVING_SPHERE) { // the sphere where it was at the ray's time, then as a world sphere
        sphere sp = moving_sphere_at(&s->moving_spheres[h->prim], r->time);
        vec3 outward;
        sphere_hit_frame(&sp, r, h->t, &out.p, &outward);
        surface_orient(&out, r, outward, outward);
        out.material = sp.material;
        out.u = out.v = 0.0f;
        const material *m = &s->materials[sp.material];
        if (m->albedo_texture >= 0 || m->emission_texture >= 0 || m->alpha_texture >= 0)
            sphere_uv(sp.radius < 0.0f ? v3_neg(outward) : outward, &out.u, &out.v);
        out.error = out.magnitude = 0.0f;
        return out;
    }
    // A world quad: surface_at takes it inline, but this stays whole for any other caller (no instance to read).
    if (h->instance == HIT_NO_INSTANCE && surface_at_flat(s, r, h, &out)) return out;
    const instance *in = &s->instances[h->instance];
    transform moved; // a moving instance's transform at the ray's time (the one the hit was found with)
    if (in->motion) motion_at(&s->motions[in->motion - 1], r->time, &moved);
    const transform *xf = in->motion ? &moved : &in->xf;
    // Instanced primitives are intersected in object space: their object-space magnitude times the transform's
    // largest row sum (its infinity norm, bounding how it stretches lengths) is the world's.
    float stretch = in->motion ? mat4_stretch(&xf->m) : in->stretch;
    // Object-space quantities go to world space: normals by the inverse transpose.
    if (in->kind == INSTANCE_SPHERE) {
        const sphere *sp = &s->instance_spheres[in->index];
        ray ro = mat4_apply_ray(&xf->inv, r);
        vec3 po = ray_at(&ro, h->t);
        vec3 no = sphere_normal(sp, po);
        vec3 nw = v3_unit(mat4_apply_normal(&xf->inv, no));
        surface_orient(&out, r, nw, nw);
        out.material = in->material >= 0 ? (uint32_t)in->material : sp->material;
        sphere_uv(sp->radius < 0.0f ? v3_neg(no) : no, &out.u, &out.v);
        out.magnitude = (v3_max_abs(sp->center) + fabsf(sp->radius)) * stretch;
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
    surface_orient(&out, r, ng, ns);
    out.u = sh.u;
    out.v = sh.v;
    out.material = surface_mesh_material(sm, in, h->prim);
    out.magnitude = sh.magnitude * stretch;
    return out;
}
