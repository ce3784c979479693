// test_surface.c — the shading record of a hit (integrator/surface.h). surface_at takes world quads and the
// triangles of meshes placed without turning inline (surface_at_flat), and the lean path tracer uses that record
// directly: for random rays into a scene of every kind of placement, each field is checked against what it is
// defined to be — the point o + t d and its error bound, the geometric and shading normals turned against the
// ray, the material of the triangle's slot or of its instance, and the primitive's largest coordinate in world
// units, which the spawn offset scales with — and the other hits (a turning instance, spheres) are left to
// surface_at_general.
#include "glint.h"
#include "check.h"
#include "test_util.h"
#include "core/rng.h"
#include "integrator/spawn.h"
#include "integrator/surface.h"
#include "render/frame.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

// A tetrahedron with two MTL materials (two faces each), corners of magnitude up to 1.5, and no normals (smooth
// ones are computed).
static void write_files(void) {
    const char *mtl = "newmtl warm\nKd 0.7 0.35 0.2\nnewmtl cold\nKd 0.2 0.35 0.7\n";
    const char *obj = "mtllib tet.mtl\nv -1 0 -1\nv 1.5 0 -1\nv 0 0 1\nv 0 1.25 0\n"
                      "usemtl warm\nf 1 3 2\nf 1 2 4\nusemtl cold\nf 2 3 4\nf 3 1 4\n";
    CHECK(tmp_write(tmp_path("tet.mtl"), mtl, strlen(mtl)));
    CHECK(tmp_write(tmp_path("tet.obj"), obj, strlen(obj)));
}

// The scene: a ground quad; the tetrahedron placed once (flattened into the world BVH, with its MTL materials);
// placed twice more, scaled and moved (one BVH shared by two instances that turn no direction), each with a
// material of its own; once rotated (a turning instance); and a sphere.
static glint_scene *make_scene(void) {
    char text[4096];
    int n = snprintf(
        text, sizeof text,
        "{\"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"integrator\": \"path\", \"background\": \"sky\"},\n"
        " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 3, 8], \"lookat\": [0, 0, 0], \"vfov\": 40},\n"
        " \"materials\": {\"ground\": {\"type\": \"lambertian\", \"albedo\": 0.5},\n"
        "               \"clay\": {\"type\": \"lambertian\", \"albedo\": [0.7, 0.6, 0.5]},\n"
        "               \"steel\": {\"type\": \"metal\", \"albedo\": 0.8}},\n"
        " \"objects\": [\n"
        "  {\"type\": \"quad\", \"q\": [-20, -0.5, 20], \"u\": [40, 0, 0], \"v\": [0, 0, -40], \"material\": \"ground\"},\n"
        "  {\"type\": \"mesh\", \"file\": \"%s\"},\n"
        "  {\"type\": \"mesh\", \"file\": \"%s\", \"material\": \"clay\",\n"
        "   \"transform\": [{\"scale\": 0.5}, {\"translate\": [-3, 0, 0]}]},\n"
        "  {\"type\": \"mesh\", \"file\": \"%s\", \"material\": \"steel\",\n"
        "   \"transform\": [{\"scale\": 2}, {\"translate\": [3.5, 0, -1]}]},\n"
        "  {\"type\": \"mesh\", \"file\": \"%s\", \"material\": \"clay\",\n"
        "   \"transform\": [{\"rotate\": {\"axis\": [0, 1, 0], \"degrees\": 30}}, {\"translate\": [0, 0, -4]}]},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 0.5, 3], \"radius\": 0.5, \"material\": \"clay\"}]}\n",
        tmp_path("tet.obj"), tmp_path("tet.obj"), tmp_path("tet.obj"), tmp_path("tet.obj"));
    CHECK(n > 0 && (size_t)n < sizeof text);
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_parse(tmp_path("scene.json"), text, strlen(text), &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "  %s\n", err.message);
    return st == GLINT_OK ? s : NULL;
}

static bool same_vec(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// What each kind of hit was found, to check that the rays reached them all.
enum { SEEN_QUAD, SEEN_FLAT_MESH, SEEN_SHARED_MESH, SEEN_TURNED_MESH, SEEN_SPHERE, SEEN_KINDS };

// The fields of the record of hit h of ray r, on a quad or a triangle of a mesh placed without turning.
static void check_flat(const glint_scene *s, const ray *r, const hit *h, const surface *sf, int *bad) {
    vec3 p = ray_at(r, h->t);
    bool ok = same_vec(sf->p, p) && sf->error == surface_point_error(r->o, p) && sf->kind == (hit_kind)h->kind &&
              sf->prim == h->prim && sf->instance == h->instance && sf->time == r->time;
    vec3 outward, ns;
    uint32_t want_material;
    float magnitude;
    if (h->kind == HIT_QUAD) {
        const quad *q = &s->quads[h->prim];
        outward = ns = q->normal;
        want_material = q->material;
        magnitude = q->magnitude;
        ok = ok && sf->u == h->b1 && sf->v == h->b2;
    } else {
        const instance *in = &s->instances[h->instance];
        const scene_mesh *sm = &s->meshes[in->index];
        tri_hit th = {h->t, 1.0f - h->b1 - h->b2, h->b1, h->b2};
        mesh_shading sh = mesh_shade(&sm->geometry, h->prim, &th);
        outward = sh.ng;
        ns = sh.ns;
        int32_t slot = sm->geometry.triangles[h->prim].material;
        want_material = in->material >= 0 ? (uint32_t)in->material
                   : slot >= 0       ? sm->slot_material[slot]
                                     : sm->default_material;
        vec3 c[3];
        mesh_triangle_positions(&sm->geometry, h->prim, &c[0], &c[1], &c[2]);
        float largest = 0.0f;
        for (int k = 0; k < 3; k++) largest = fmaxf(largest, fmaxf(fabsf(c[k].x), fmaxf(fabsf(c[k].y), fabsf(c[k].z))));
        magnitude = largest * in->stretch;
        ok = ok && sf->u == sh.u && sf->v == sh.v;
    }
    bool front = v3_dot(r->d, outward) < 0.0f;
    ok = ok && sf->front == front && same_vec(sf->ng, front ? outward : v3_neg(outward)) &&
         same_vec(sf->n, front ? ns : v3_neg(ns)) && sf->material == want_material && sf->magnitude == magnitude;
    // The spawn offset covers the primitive's own magnitude (a small hit point on a large primitive).
    spawn_point sp = spawn_point_of(s, sf);
    ok = ok && sp.offset >= SPAWN_OFFSET_REL * magnitude && same_vec(sp.n, sf->ng);
    if (!ok && (*bad)++ < 3)
        fprintf(stderr, "surface of kind %u prim %u instance %u at t %.9g: a field differs\n", h->kind, h->prim,
                h->instance, (double)h->t);
}

static void test_records(void) {
    glint_scene *s = make_scene();
    if (!s) return;
    glint_error err;
    accel *a = frame_accel_build(s, &(accel_build_options){.threads = 1}, &err);
    CHECK(a != NULL);
    if (!a) {
        glint_scene_free(s);
        return;
    }
    // The instances in the scene's order: the flattened one, the two that share a BVH, the turned one.
    CHECK(s->instance_count == 4);
    if (s->instance_count != 4) {
        accel_free(a);
        glint_scene_free(s);
        return;
    }
    CHECK(s->instances[0].keeps_directions && s->instances[1].keeps_directions && s->instances[2].keeps_directions &&
          !s->instances[3].keeps_directions && s->instances[0].material < 0 && s->instances[2].material >= 0);
    int seen[SEEN_KINDS] = {0}, bad = 0;
    rng g = rng_for_key(7, 0, 0);
    for (int i = 0; i < 20000; i++) {
        vec3 o = v3(rng_range(&g, -6, 6), rng_range(&g, -0.25f, 4), rng_range(&g, -7, 5));
        vec3 target = v3(rng_range(&g, -4, 5), rng_range(&g, -0.6f, 1.5f), rng_range(&g, -5, 3));
        ray r = {o, v3_sub(target, o), 0.0f, INFINITY, 0.0f};
        hit h;
        if (!accel_intersect(a, &r, &h)) continue;
        surface flat = {0};
        bool inline_taken = surface_at_flat(s, &r, &h, &flat);
        surface sf = surface_at(s, &r, &h);
        if (h.kind == HIT_SPHERE) {
            seen[SEEN_SPHERE]++;
            CHECK(!inline_taken && sf.magnitude == 0.0f);
            continue;
        }
        if (h.kind == HIT_QUAD) {
            seen[SEEN_QUAD]++;
            // surface_at_general, called directly, takes a world quad too (surface_at never asks it)
            surface general = surface_at_general(s, &r, &h);
            CHECK(same_vec(general.p, sf.p) && same_vec(general.ng, sf.ng) && general.material == sf.material &&
                  general.magnitude == sf.magnitude);
        } else if (h.instance == 3) {
            seen[SEEN_TURNED_MESH]++;
            // surface_at_general: the turned normals are unit and face the ray; the magnitude is the world's.
            CHECK(!inline_taken && fabsf(v3_len(sf.ng) - 1.0f) < 1e-6f && v3_dot(r.d, sf.ng) <= 0.0f &&
                  sf.magnitude > 0.0f);
            continue;
        } else {
            seen[h.instance == 0 ? SEEN_FLAT_MESH : SEEN_SHARED_MESH]++;
        }
        CHECK(inline_taken);
        if (!inline_taken) continue;
        // surface_at returns that record
        CHECK(same_vec(flat.p, sf.p) && same_vec(flat.n, sf.n) && same_vec(flat.ng, sf.ng) &&
              flat.material == sf.material && flat.magnitude == sf.magnitude);
        check_flat(s, &r, &h, &flat, &bad);
    }
    CHECK(bad == 0);
    for (int k = 0; k < SEEN_KINDS; k++) CHECK(seen[k] > 20);
    fprintf(stderr, "hits: quad %d, flattened mesh %d, shared mesh %d, turned mesh %d, sphere %d\n", seen[SEEN_QUAD],
            seen[SEEN_FLAT_MESH], seen[SEEN_SHARED_MESH], seen[SEEN_TURNED_MESH], seen[SEEN_SPHERE]);
    accel_free(a);
    glint_scene_free(s);
}

int main(void) {
    if (!tmpdir_make("glint-test-surface")) return 1;
    write_files();
    test_records();
    tmpdir_remove();
    return check_summary();
}
