// test_bvh.c — the wide and the binary BVH against brute force on random rays over random scenes of
// spheres, quads, meshes and instances: same hit, same primitive, bit-identical t; any-hit agrees with
// closest-hit; the SIMD path agrees with the scalar one; streams of rays traced together give the same hits.
#include "glint.h"
#include "accel/accel.h"
#include "accel/brute_force.h"
#include "accel/bvh.h"
#include "core/rng.h"
#include "render/frame.h"
#include "scene/scene.h"

#include "check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { RAYS_PER_SCENE = 4000 };

static int mismatches; // reported once per scene rather than once per ray
static int triangles_first_seen[2]; // mixed world trees that make the triangle constants up front (1) or not (0)

static float urand(rng *g, float lo, float hi) { return rng_range(g, lo, hi); }

static vec3 random_unit(rng *g) {
    for (;;) {
        vec3 p = v3(urand(g, -1, 1), urand(g, -1, 1), urand(g, -1, 1));
        float l2 = v3_len2(p);
        if (l2 > 1e-6f && l2 <= 1.0f) return v3_scale(p, 1.0f / sqrtf(l2));
    }
}

// A scene of n spheres mixing small, large, huge (the ground of rtiow), nested, coincident and
// negative-radius spheres.
static glint_scene *random_scene(rng *g, size_t n, accel_kind kind) {
    glint_scene *s = scene_new("test");
    s->settings.accel = kind;
    for (size_t i = 0; i < n; i++) {
        sphere sp = {v3(urand(g, -10, 10), urand(g, -10, 10), urand(g, -10, 10)), urand(g, 0.05f, 2.0f), 0};
        float kindr = rng_float(g);
        if (kindr < 0.05f) sp = (sphere){v3(0, -1000, 0), 1000.0f, 0};          // huge ground
        else if (kindr < 0.15f) sp.radius = -sp.radius;                          // hollow shell
        else if (kindr < 0.25f && i > 0) {                                       // nested in the previous
            sp.center = s->spheres[i - 1].center;
            sp.radius = s->spheres[i - 1].radius * urand(g, 0.2f, 1.5f);
        } else if (kindr < 0.3f && i > 0) sp = s->spheres[i - 1];              // exact duplicate (ties)
        else if (kindr < 0.35f) sp.radius = urand(g, 1e-3f, 1e-2f);             // tiny
        else if (kindr < 0.4f) sp.radius = urand(g, 5.0f, 30.0f);               // large, overlapping
        CHECK(scene_add_sphere(s, sp));
    }
    return s;
}

// Random rays: from outside and inside, towards sphere centres, grazing, unnormalised, with
// varied intervals.
static ray random_ray(rng *g, const glint_scene *s) {
    ray r;
    r.o = v3(urand(g, -15, 15), urand(g, -15, 15), urand(g, -15, 15));
    float mode = rng_float(g);
    if (s->sphere_count > 0 && mode < 0.4f) {
        const sphere *sp = &s->spheres[rng_u32(g) % s->sphere_count];
        vec3 target = sp->center;
        if (mode < 0.15f) target = v3_add(target, v3_scale(random_unit(g), fabsf(sp->radius) * 0.999f)); // near grazing
        if (mode < 0.05f) r.o = v3_add(sp->center, v3_scale(random_unit(g), fabsf(sp->radius) * 0.5f)); // inside
        r.d = v3_sub(target, r.o);
        if (v3_len2(r.d) < 1e-12f) r.d = random_unit(g);
        else if (rng_float(g) < 0.7f) r.d = v3_unit(r.d);
    } else {
        r.d = random_unit(g);
        if (mode > 0.95f) r.d = v3(0.0f, 0.0f, rng_float(g) < 0.5f ? 1.0f : -1.0f); // axis-aligned: zero components
        else if (mode > 0.9f) r.d = v3_scale(r.d, urand(g, 0.01f, 100.0f));        // not unit length
    }
    r.tmin = rng_float(g) < 0.5f ? 0.001f : 0.0f;
    r.tmax = rng_float(g) < 0.8f ? INFINITY : urand(g, 0.5f, 40.0f);
    if (rng_float(g) < 0.005f) r.d.y = NAN; // hits nothing, in every structure
    return r;
}

static bool same_hit(bool fa, const hit *a, bool fb, const hit *b) {
    if (fa != fb) return false;
    if (!fa) return true;
    return a->prim == b->prim && memcmp(&a->t, &b->t, sizeof a->t) == 0 && a->kind == b->kind &&
           a->instance == b->instance && memcmp(&a->b1, &b->b1, sizeof a->b1) == 0 &&
           memcmp(&a->b2, &b->b2, sizeof a->b2) == 0;
}

// Sphere scenes give sphere hits in world space.
/// Rays gathered for a stream query (accel_intersect_stream, bvh_intersect_stream), with what the one-ray query
/// answered for each; batches of 1 to ACCEL_STREAM rays in turn.
typedef struct stream_batch {
    int n, batches;
    ray r[ACCEL_STREAM];
    bool f[ACCEL_STREAM];
    hit h[ACCEL_STREAM];
} stream_batch;

// Adds ray r, whose one-ray answer was (f, h), to the batch; once the batch is full (or `flush`), traces it as one
// stream through a (when not NULL) and b (when not NULL). Returns the rays on which a stream's answer differs.
static int stream_add(stream_batch *sb, const accel *a, const bvh *b, const ray *r, bool f, const hit *h, bool flush) {
    if (r) {
        sb->r[sb->n] = *r;
        sb->f[sb->n] = f;
        sb->h[sb->n++] = *h;
    }
    int size = 1 + (sb->batches * 7) % ACCEL_STREAM;
    if (sb->n == 0 || (sb->n < size && !flush)) return 0;
    int bad = 0;
    for (int pass = 0; pass < 2; pass++) {
        hit hs[ACCEL_STREAM];
        bool fs[ACCEL_STREAM];
        memset(hs, 0, sizeof hs);
        if (pass == 0 && a) accel_intersect_stream(a, sb->n, sb->r, hs, fs);
        else if (pass == 1 && b) bvh_intersect_stream(b, sb->n, sb->r, hs, fs);
        else continue;
        for (int i = 0; i < sb->n; i++) bad += !same_hit(sb->f[i], &sb->h[i], fs[i], &hs[i]);
    }
    sb->n = 0;
    sb->batches++;
    return bad;
}

static bool world_sphere(bool f, const hit *h) { return !f || (h->kind == HIT_SPHERE && h->instance == HIT_NO_INSTANCE); }

// Compares every structure with brute force on RAYS_PER_SCENE rays over one scene layout.
static void check_scene(uint64_t seed, size_t n) {
    glint_error err;
    accel_kind kinds[3] = {ACCEL_NONE, ACCEL_BVH, ACCEL_BVH2};
    glint_scene *sc[3];
    accel *ac[3];
    for (int k = 0; k < 3; k++) {
        rng g = rng_for_sample(seed, n, 0); // the same spheres for every kind
        sc[k] = random_scene(&g, n, kinds[k]);
        ac[k] = frame_accel_build(sc[k], NULL, &err);
        CHECK(ac[k] != NULL);
        if (!ac[k]) return;
    }
    bvh wide;
    geometry_arrays spheres = {.spheres = sc[0]->spheres, .sphere_count = sc[0]->sphere_count};
    CHECK(bvh_build(&wide, &(bvh_input){.geometry = &spheres}, NULL, true));
    accel_stats st;
    accel_get_stats(ac[1], &st);
    CHECK(n == 0 || (st.leaves >= 1 && st.depth >= 1 && st.leaves <= n));
    accel_get_stats(ac[2], &st);
    CHECK(n == 0 || (st.leaves >= 1 && st.depth >= 1 && st.nodes + 1 == st.leaves));

    rng g = rng_for_sample(seed, n, 1);
    int bad = 0, hits = 0, stream_bad = 0;
    uint32_t occluder[3] = {ACCEL_NO_OCCLUDER, ACCEL_NO_OCCLUDER, ACCEL_NO_OCCLUDER}; // carried from ray to ray
    stream_batch sb[3] = {{0}};
    for (int i = 0; i < RAYS_PER_SCENE; i++) {
        ray r = random_ray(&g, sc[0]);
        hit h[3], hs;
        bool f[3];
        for (int k = 0; k < 3; k++) {
            memset(&h[k], 0, sizeof h[k]);
            f[k] = accel_intersect(ac[k], &r, &h[k]);
            stream_bad += stream_add(&sb[k], ac[k], k == 1 ? &wide : NULL, &r, f[k], &h[k], i + 1 == RAYS_PER_SCENE);
        }
        memset(&hs, 0, sizeof hs);
        bool fs = bvh_intersect_scalar(&wide, &r, &hs);
        hits += f[0];
        bool ok = same_hit(f[0], &h[0], f[1], &h[1]) && same_hit(f[0], &h[0], f[2], &h[2]) &&
                  same_hit(f[0], &h[0], fs, &hs) && world_sphere(f[0], &h[0]);
        for (int k = 0; k < 3; k++) ok = ok && accel_occluded(ac[k], &r) == f[0];
        for (int k = 0; k < 3; k++) ok = ok && accel_occluded_hinted(ac[k], &r, &occluder[k]) == f[0];
        ok = ok && bvh_occluded_scalar(&wide, &r) == f[0];
        if (!ok) {
            if (bad++ < 5)
                fprintf(stderr,
                        "n=%zu ray o=(%.9g %.9g %.9g) d=(%.9g %.9g %.9g) t=(%g %g): none %d %u %.9g, bvh %d %u %.9g, "
                        "bvh2 %d %u %.9g, scalar %d %u %.9g\n",
                        n, (double)r.o.x, (double)r.o.y, (double)r.o.z, (double)r.d.x, (double)r.d.y, (double)r.d.z,
                        (double)r.tmin, (double)r.tmax, f[0], h[0].prim, (double)h[0].t, f[1], h[1].prim,
                        (double)h[1].t, f[2], h[2].prim, (double)h[2].t, fs, hs.prim, (double)hs.t);
        }
    }
    CHECK(bad == 0);
    CHECK(stream_bad == 0);
    mismatches += bad + stream_bad;
    // The rays must exercise both outcomes (except in the empty scene).
    CHECK(n == 0 || (hits > 0 && hits < RAYS_PER_SCENE));
    bvh_release(&wide);
    for (int k = 0; k < 3; k++) {
        accel_free(ac[k]);
        scene_free(sc[k]);
    }
}

// Every sphere at one centre: the SAH cannot split by centroid, ties must resolve to the lowest index.
static void check_coincident(void) {
    glint_error err;
    accel_kind kinds[3] = {ACCEL_NONE, ACCEL_BVH, ACCEL_BVH2};
    glint_scene *sc[3];
    accel *ac[3];
    for (int k = 0; k < 3; k++) {
        sc[k] = scene_new("coincident");
        sc[k]->settings.accel = kinds[k];
        for (int i = 0; i < 300; i++) scene_add_sphere(sc[k], (sphere){v3(1, 2, 3), i % 3 == 0 ? 1.0f : 0.5f * (float)(1 + i % 5), 0});
        ac[k] = frame_accel_build(sc[k], NULL, &err);
        CHECK(ac[k] != NULL);
    }
    accel_stats st;
    accel_get_stats(ac[1], &st);
    CHECK(st.depth < BVH_MAX_DEPTH);
    rng g = rng_for_sample(7, 7, 7);
    int bad = 0;
    for (int i = 0; i < 2000; i++) {
        ray r = random_ray(&g, sc[0]);
        hit h[3];
        bool f[3];
        for (int k = 0; k < 3; k++) f[k] = accel_intersect(ac[k], &r, &h[k]);
        if (!same_hit(f[0], &h[0], f[1], &h[1]) || !same_hit(f[0], &h[0], f[2], &h[2])) bad++;
    }
    CHECK(bad == 0);
    // Straight at the centre from outside: the outermost shell (radius 2.5) is first, and of its many
    // copies the lowest index (4) wins the tie; from the centre, the innermost (radius 0.5, index 5).
    ray r = {v3(1, 2, -2), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
    for (int k = 0; k < 3; k++) {
        hit h;
        CHECK(accel_intersect(ac[k], &r, &h) && h.prim == 4 && h.t == 2.5f);
    }
    r.o = v3(1, 2, 3);
    for (int k = 0; k < 3; k++) {
        hit h;
        CHECK(accel_intersect(ac[k], &r, &h) && h.prim == 5 && h.t == 0.5f);
    }
    for (int k = 0; k < 3; k++) {
        accel_free(ac[k]);
        scene_free(sc[k]);
    }
}

static void check_empty(void) {
    glint_error err;
    accel_kind kinds[3] = {ACCEL_NONE, ACCEL_BVH, ACCEL_BVH2};
    for (int k = 0; k < 3; k++) {
        glint_scene *s = scene_new("empty");
        s->settings.accel = kinds[k];
        accel *a = frame_accel_build(s, NULL, &err);
        CHECK(a != NULL);
        ray r = {v3(0, 0, 0), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
        hit h;
        CHECK(!accel_intersect(a, &r, &h));
        CHECK(!accel_occluded(a, &r));
        accel_stats st;
        accel_get_stats(a, &st);
        CHECK(st.nodes == 0 && st.leaves == 0);
        accel_free(a);
        scene_free(s);
    }
}

// The exact t of a known configuration, and the ground sphere of rtiow-final seen from the camera.
static void check_known(void) {
    glint_error err;
    glint_scene *s = scene_new("known");
    scene_add_sphere(s, (sphere){v3(0, -1000, 0), 1000.0f, 0});
    scene_add_sphere(s, (sphere){v3(0, 1, 0), 1.0f, 0});
    scene_add_sphere(s, (sphere){v3(0, 1, 0), -0.9f, 0});
    accel *a = frame_accel_build(s, NULL, &err);
    CHECK(a != NULL);
    if (!a) return;
    ray r = {v3(0, 1, -5), v3(0, 0, 1), 0.001f, INFINITY, 0.0f};
    hit h;
    CHECK(accel_intersect(a, &r, &h) && h.prim == 1 && h.t == 4.0f);
    r.o = v3(0, 1, 0); // inside the shell: the negative-radius sphere first
    CHECK(accel_intersect(a, &r, &h) && h.prim == 2);
    CHECK_NEAR(h.t, 0.9, 1e-6);
    r = (ray){v3(13, 2, 3), v3_unit(v3(-13, -2.5f, -3)), 0.001f, INFINITY, 0.0f}; // down onto the ground
    CHECK(accel_intersect(a, &r, &h) && h.prim == 0);
    CHECK_NEAR(h.t, 10.8781562524, 2e-6); // the root computed in double precision
    r.tmax = h.t; // the interval is open: a hit exactly at tmax does not count
    CHECK(!accel_occluded(a, &r));
    accel_free(a);
    scene_free(s);
}

// A heightfield of g x g cells (2 g^2 triangles sharing their edges) over [-1, 1]^2, bumpy in z.
static bool make_mesh(rng *g, int cells, scene_mesh *out) {
    memset(out, 0, sizeof *out);
    mesh *m = &out->geometry;
    int side = cells + 1;
    m->position_count = (size_t)side * (size_t)side;
    m->triangle_count = 2 * (size_t)cells * (size_t)cells;
    m->positions = malloc(m->position_count * sizeof *m->positions);
    m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
    if (!m->positions || !m->triangles) return false;
    for (int y = 0; y < side; y++)
        for (int x = 0; x < side; x++)
            m->positions[y * side + x] =
                v3(-1.0f + 2.0f * (float)x / (float)cells, -1.0f + 2.0f * (float)y / (float)cells, urand(g, -0.3f, 0.3f));
    size_t t = 0;
    for (int y = 0; y < cells; y++)
        for (int x = 0; x < cells; x++) {
            int a = y * side + x, b = a + 1, c = a + side, d = c + 1;
            int tri[2][3] = {{a, b, d}, {a, d, c}};
            for (int k = 0; k < 2; k++, t++) {
                for (int j = 0; j < 3; j++) m->triangles[t].v[j] = tri[k][j];
                m->triangles[t].material = -1;
            }
        }
    mesh_compute_bounds(m);
    return true;
}

// A random similarity-or-not transform: rotation about a random axis, scale (possibly non-uniform or a
// mirror), translation.
static transform random_transform(rng *g) {
    mat4 r = mat4_rotate(random_unit(g), urand(g, 0.0f, 360.0f));
    float s = urand(g, 0.3f, 3.0f);
    vec3 sc = rng_float(g) < 0.5f ? v3(s, s, s) : v3(s, urand(g, 0.3f, 3.0f), rng_float(g) < 0.3f ? -s : s);
    mat4 k = mat4_scale(sc);
    mat4 t = mat4_translate(v3(urand(g, -8, 8), urand(g, -8, 8), urand(g, -8, 8)));
    mat4 rk = mat4_mul(&r, &k), m = mat4_mul(&t, &rk);
    transform out;
    if (!transform_make(&m, &out)) out = transform_identity();
    return out;
}

// Spheres, quads (some sharing edges in boxes), meshes placed by several instances, and transformed
// spheres: the wide BVH (SIMD and scalar paths) and the binary BVH against brute force, including the kind,
// instance and barycentrics of the hit.
static void check_mixed(uint64_t seed, size_t spheres, size_t quads, size_t meshes, size_t instances) {
    rng g = rng_for_sample(seed, 77, 0);
    glint_scene *s = random_scene(&g, spheres, ACCEL_NONE);
    for (size_t i = 0; i < quads; i++) {
        quad q[6];
        vec3 c = v3(urand(&g, -10, 10), urand(&g, -10, 10), urand(&g, -10, 10));
        if (i % 4 == 3 && quad_box(c, v3_add(c, v3(urand(&g, 0.5f, 3), urand(&g, 0.5f, 3), urand(&g, 0.5f, 3))), 0, q)) {
            for (int j = 0; j < 6; j++) CHECK(scene_add_quad(s, q[j]));
        } else if (quad_make(c, v3_scale(random_unit(&g), urand(&g, 0.2f, 4)), v3_scale(random_unit(&g), urand(&g, 0.2f, 4)),
                             0, q)) {
            CHECK(scene_add_quad(s, q[0]));
        }
    }
    for (size_t i = 0; i < meshes; i++) {
        scene_mesh m;
        CHECK(make_mesh(&g, 3 + (int)i * 4, &m));
        CHECK(scene_add_mesh(s, &m) == (long)i);
    }
    for (size_t i = 0; i < instances; i++) {
        instance in = {.kind = INSTANCE_MESH, .xf = random_transform(&g), .material = -1};
        if (meshes == 0 || rng_float(&g) < 0.3f) {
            sphere sp = {v3(urand(&g, -1, 1), urand(&g, -1, 1), urand(&g, -1, 1)), urand(&g, 0.3f, 1.5f), 0};
            in.kind = INSTANCE_SPHERE;
            in.index = (uint32_t)scene_add_instance_sphere(s, sp);
        } else {
            in.index = (uint32_t)(rng_u32(&g) % meshes);
        }
        CHECK(scene_add_instance(s, in));
    }
    // One BVH per mesh, wide and binary, then the world over spheres, quads and instances.
    bvh blas_w[4], blas_b[4], world_w, world_b;
    for (size_t i = 0; i < meshes; i++) {
        bvh_input mi = {.mesh = &s->meshes[i].geometry};
        CHECK(bvh_build(&blas_w[i], &mi, NULL, true));
        CHECK(bvh_build(&blas_b[i], &mi, NULL, false));
    }
    const mesh *mesh_list[4];
    geometry_arrays all = scene_geometry(s, mesh_list);
    bvh_input in = {.geometry = &all, .blas = blas_w};
    CHECK(bvh_build(&world_w, &in, NULL, true));
    triangles_first_seen[world_w.triangles_first]++;
    in.blas = blas_b;
    CHECK(bvh_build(&world_b, &in, NULL, false));

    // The same primitives through accel_build, which places every mesh used once in the world BVH (flattened: in
    // world space, so its hits may differ from the others' in the last bits of t; its streams are checked against
    // its own one-ray queries).
    glint_error err;
    accel *acc = accel_build(&all, ACCEL_BVH, NULL, &err);
    CHECK(acc != NULL);
    stream_batch sb_world = {0}, sb_accel = {0};
    int stream_bad = 0;

    g = rng_for_sample(seed, 78, 1);
    int bad = 0, kinds_seen[3] = {0, 0, 0}, instanced = 0;
    uint32_t occluder = BVH_EMPTY; // carried from ray to ray as a path carries it: a stale hint must not matter
    for (int i = 0; i < RAYS_PER_SCENE; i++) {
        ray r;
        float pick = rng_float(&g);
        if (pick < 0.3f && s->quad_count > 0) { // at a quad, often at its edges
            const quad *q = &s->quads[rng_u32(&g) % s->quad_count];
            float a = rng_float(&g) < 0.5f ? urand(&g, -0.01f, 1.01f) : (float)(rng_u32(&g) % 2);
            vec3 target = v3_add(q->q, v3_add(v3_scale(q->u, a), v3_scale(q->v, rng_float(&g))));
            r = (ray){v3(urand(&g, -15, 15), urand(&g, -15, 15), urand(&g, -15, 15)), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
            r.d = v3_unit(v3_sub(target, r.o));
        } else if (pick < 0.6f && s->instance_count > 0) { // at what an instance places
            const instance *ins = &s->instances[rng_u32(&g) % s->instance_count];
            vec3 target = mat4_apply_point(&ins->xf.m, v3(urand(&g, -1, 1), urand(&g, -1, 1), 0.0f));
            r = (ray){v3(urand(&g, -15, 15), urand(&g, -15, 15), urand(&g, -15, 15)), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
            r.d = v3_unit(v3_sub(target, r.o));
        } else {
            r = random_ray(&g, s);
        }
        hit h[4];
        bool f[4];
        memset(h, 0, sizeof h);
        f[0] = brute_force_intersect(&all, NULL, &r, &h[0]);
        f[1] = bvh_intersect(&world_w, &r, &h[1]);
        f[2] = bvh_intersect_scalar(&world_w, &r, &h[2]);
        f[3] = bvh2_intersect(&world_b, &r, &h[3]);
        bool last = i + 1 == RAYS_PER_SCENE;
        stream_bad += stream_add(&sb_world, NULL, &world_w, &r, f[1], &h[1], last);
        if (acc) {
            hit ha;
            memset(&ha, 0, sizeof ha);
            bool fa = accel_intersect(acc, &r, &ha);
            stream_bad += stream_add(&sb_accel, acc, NULL, &r, fa, &ha, last);
        }
        bool ok = same_hit(f[0], &h[0], f[1], &h[1]) && same_hit(f[0], &h[0], f[2], &h[2]) &&
                  same_hit(f[0], &h[0], f[3], &h[3]);
        ok = ok && brute_force_occluded(&all, NULL, &r) == f[0] && bvh_occluded(&world_w, &r, NULL) == f[0] &&
             bvh_occluded_scalar(&world_w, &r) == f[0] && bvh2_occluded(&world_b, &r) == f[0];
        // With the last ray's occluder tested first: the same answer, and a leaf kept exactly when it is blocked.
        ok = ok && bvh_occluded(&world_w, &r, &occluder) == f[0] && (occluder != BVH_EMPTY) == f[0];
        uint32_t kept = occluder; // the kept leaf answers again, and is kept again
        ok = ok && (!f[0] || (bvh_occluded(&world_w, &r, &occluder) && occluder == kept));
        if (f[0] && h[0].kind < 3) kinds_seen[h[0].kind]++;
        if (f[0] && h[0].instance != HIT_NO_INSTANCE) instanced++;
        if (!ok && bad++ < 5)
            fprintf(stderr, "mixed seed %llu: none %d kind %u inst %u prim %u t %.9g | bvh %d %u %u %u %.9g | bvh2 %d %u %u %u %.9g\n",
                    (unsigned long long)seed, f[0], h[0].kind, h[0].instance, h[0].prim, (double)h[0].t, f[1], h[1].kind,
                    h[1].instance, h[1].prim, (double)h[1].t, f[3], h[3].kind, h[3].instance, h[3].prim, (double)h[3].t);
    }
    // Streams through a tree of triangles alone (mesh 0's BVH, where bvh_stream.c keeps its rays compact), aimed at
    // its triangles and their edges, with rays that end short of most hits and NaN rays among them.
    if (meshes > 0) {
        stream_batch sb_mesh = {0};
        const mesh *m0 = &s->meshes[0].geometry;
        int mesh_hits = 0;
        for (int i = 0; i < RAYS_PER_SCENE; i++) {
            vec3 p0, p1, p2;
            mesh_triangle_positions(m0, rng_u32(&g) % m0->triangle_count, &p0, &p1, &p2);
            float a = urand(&g, -0.1f, 1.1f), b = urand(&g, -0.1f, 1.1f - a);
            vec3 target = v3_add(p0, v3_add(v3_scale(v3_sub(p1, p0), a), v3_scale(v3_sub(p2, p0), b)));
            ray r = {v3(urand(&g, -3, 3), urand(&g, -3, 3), urand(&g, -3, 3)), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
            r.d = v3_sub(target, r.o); // not of unit length
            if (i % 17 == 0) r.tmax = 0.5f;
            if (i % 101 == 0) r.d.y = NAN;
            hit h;
            memset(&h, 0, sizeof h);
            bool f = bvh_intersect(&blas_w[0], &r, &h);
            mesh_hits += f;
            stream_bad += stream_add(&sb_mesh, NULL, &blas_w[0], &r, f, &h, i + 1 == RAYS_PER_SCENE);
        }
        CHECK(blas_w[0].triangles_only);
        CHECK(mesh_hits > RAYS_PER_SCENE / 4);
    }
    CHECK(bad == 0);
    CHECK(stream_bad == 0);
    mismatches += bad + stream_bad;
    accel_free(acc);
    // Every kind of hit was exercised.
    CHECK(spheres == 0 || kinds_seen[HIT_SPHERE] > 0);
    CHECK(quads == 0 || kinds_seen[HIT_QUAD] > 0);
    CHECK(meshes == 0 || instances == 0 || kinds_seen[HIT_TRIANGLE] > 0);
    CHECK(instances == 0 || instanced > 0);
    bvh_release(&world_w);
    bvh_release(&world_b);
    for (size_t i = 0; i < meshes; i++) {
        bvh_release(&blas_w[i]);
        bvh_release(&blas_b[i]);
    }
    scene_free(s);
}

int main(void) {
    const size_t sizes[] = {1, 2, 3, 5, 17, 1000};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        for (uint64_t seed = 1; seed <= 3; seed++) check_scene(seed, sizes[i]);
    check_scene(9, 0);
    check_mixed(1, 20, 12, 1, 6);
    check_mixed(2, 0, 40, 2, 30);
    check_mixed(3, 300, 100, 3, 200);
    check_mixed(4, 0, 0, 1, 1);
    check_mixed(5, 0, 7, 0, 0);
    check_mixed(6, 5, 0, 0, 9); // sphere instances only
    check_mixed(7, 3, 80, 0, 0); // a few spheres among quads: the triangle constants made up front
    CHECK(triangles_first_seen[0] > 0 && triangles_first_seen[1] > 0);
    check_coincident();
    check_empty();
    check_known();
    if (mismatches) fprintf(stderr, "%d rays disagreed\n", mismatches);
    printf("SIMD traversal %s\n", BVH_SIMD ? "compiled in and compared with the scalar path" : "not compiled in");
    return check_summary();
}
