// test_triangle.c — ray/triangle and ray/quad hits against analytic answers, and watertightness: rays from
// inside closed meshes aimed exactly at shared vertices and along shared edges never escape.
#include "check.h"
#include "accel/bvh.h"
#include "core/rng.h"
#include "geometry/mesh.h"
#include "geometry/transform.h"
#include "geometry/quad.h"
#include "geometry/triangle.h"

#include <stdlib.h>
#include <string.h>

static ray mkray(vec3 o, vec3 d) { return (ray){o, d, 0.0f, INFINITY, 0.0f}; }

static bool hit_tri(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, float tmin, float tmax, tri_hit *h) {
    ray r = mkray(o, d);
    tri_ray tr = tri_ray_make(&r);
    return tri_intersect(&tr, p0, p1, p2, tmin, tmax, h);
}

static void test_analytic(void) {
    vec3 a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(0, 1, 0);
    tri_hit h;
    CHECK(hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, 1), a, b, c, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 1.0, 1e-7);
    CHECK_NEAR(h.b0, 0.5, 1e-7);
    CHECK_NEAR(h.b1, 0.2, 1e-7);
    CHECK_NEAR(h.b2, 0.3, 1e-7);
    // t is measured in units of the (unnormalised) direction.
    CHECK(hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, 2), a, b, c, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 0.5, 1e-7);
    // No back-face culling: from the other side too.
    CHECK(hit_tri(v3(0.25f, 0.25f, 3), v3(0, 0, -1), a, b, c, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 3.0, 1e-6);
    CHECK_NEAR(h.b0, 0.5, 1e-7);
    // Oblique ray from (-0.5, -0.5, -1) along (1, 1, 1): meets z = 0 at t = 1 in (0.5, 0.5), exactly on the
    // hypotenuse, which counts as a hit with b0 = 0.
    CHECK(hit_tri(v3(-0.5f, -0.5f, -1), v3(1, 1, 1), a, b, c, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 1.0, 1e-6);
    CHECK_NEAR(h.b0, 0.0, 1e-6);
    // Misses: outside, beyond tmax, before tmin, in the plane, degenerate triangle, zero or NaN direction.
    CHECK(!hit_tri(v3(0.6f, 0.6f, -1), v3(0, 0, 1), a, b, c, 0, INFINITY, &h));
    CHECK(!hit_tri(v3(-0.1f, 0.5f, -1), v3(0, 0, 1), a, b, c, 0, INFINITY, &h));
    CHECK(!hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, 1), a, b, c, 0, 0.999f, &h));
    CHECK(!hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, 1), a, b, c, 1.001f, INFINITY, &h));
    CHECK(!hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, -1), a, b, c, 0, INFINITY, &h)); // pointing away
    CHECK(!hit_tri(v3(-1, 0.1f, 0), v3(1, 0, 0), a, b, c, 0, INFINITY, &h));     // in the plane
    CHECK(!hit_tri(v3(0.5f, 0, -1), v3(0, 0, 1), a, b, v3(2, 0, 0), 0, INFINITY, &h));
    CHECK(!hit_tri(v3(0.2f, 0.3f, -1), v3(0, 0, 0), a, b, c, 0, INFINITY, &h));
    CHECK(!hit_tri(v3(0.2f, 0.3f, -1), v3(NAN, 0, 1), a, b, c, 0, INFINITY, &h));
    CHECK(!hit_tri(v3(NAN, 0.3f, -1), v3(0, 0, 1), a, b, c, 0, INFINITY, &h));
}

// Reference intersection in double (Cramer's rule on o + t d = p0 + b1 e1 + b2 e2).
static bool reference_hit(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, double *t, double *b1, double *b2) {
    double e1[3] = {(double)p1.x - p0.x, (double)p1.y - p0.y, (double)p1.z - p0.z};
    double e2[3] = {(double)p2.x - p0.x, (double)p2.y - p0.y, (double)p2.z - p0.z};
    double s[3] = {(double)o.x - p0.x, (double)o.y - p0.y, (double)o.z - p0.z};
    double dd[3] = {d.x, d.y, d.z};
    double p[3] = {dd[1] * e2[2] - dd[2] * e2[1], dd[2] * e2[0] - dd[0] * e2[2], dd[0] * e2[1] - dd[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-12) return false;
    double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    *b1 = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    *b2 = (dd[0] * q[0] + dd[1] * q[1] + dd[2] * q[2]) / det;
    *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return true;
}

static vec3 rand_point(rng *r, float lo, float hi) {
    return v3(rng_range(r, lo, hi), rng_range(r, lo, hi), rng_range(r, lo, hi));
}

static void test_random_against_reference(void) {
    rng r = rng_for_sample(7, 1, 2);
    int hits = 0, misses = 0, bad = 0;
    for (int i = 0; i < 20000; i++) {
        vec3 p0 = rand_point(&r, -2, 2), p1 = rand_point(&r, -2, 2), p2 = rand_point(&r, -2, 2);
        vec3 o = rand_point(&r, -4, 4), target = rand_point(&r, -1, 1);
        vec3 d = v3_sub(target, o);
        double t, b1, b2;
        if (!reference_hit(o, d, p0, p1, p2, &t, &b1, &b2)) continue;
        double b0 = 1.0 - b1 - b2, margin = 1e-4;
        bool clear_hit = b0 > margin && b1 > margin && b2 > margin && t > margin;
        bool clear_miss = b0 < -margin || b1 < -margin || b2 < -margin || t < -margin;
        tri_hit h;
        bool got = hit_tri(o, d, p0, p1, p2, 0, INFINITY, &h);
        if (clear_hit) {
            hits++;
            if (!got || fabs(h.t - t) > 1e-4 * fmax(1.0, t) || fabs(h.b1 - b1) > 1e-4 || fabs(h.b2 - b2) > 1e-4 ||
                fabs(h.b0 + h.b1 + h.b2 - 1.0) > 1e-5)
                bad++;
        } else if (clear_miss) {
            misses++;
            if (got) bad++;
        }
    }
    CHECK(hits > 1000);
    CHECK(misses > 1000);
    CHECK(bad == 0);
    if (bad) fprintf(stderr, "%d of %d rays disagree with the double-precision reference\n", bad, hits + misses);
}

// ---- closed meshes ----------------------------------------------------------------------------------

typedef struct builder {
    mesh m;
    int32_t (*edges)[3]; // (a, b, midpoint) for a < b
    size_t edge_count;
} builder;

static int32_t add_pos(mesh *m, vec3 p) {
    m->positions = realloc(m->positions, (m->position_count + 1) * sizeof *m->positions);
    m->positions[m->position_count] = p;
    return (int32_t)m->position_count++;
}

static void add_tri(mesh *m, int32_t a, int32_t b, int32_t c) {
    m->triangles = realloc(m->triangles, (m->triangle_count + 1) * sizeof *m->triangles);
    mesh_triangle *t = &m->triangles[m->triangle_count++];
    *t = (mesh_triangle){{a, b, c}, -1};
}

static int32_t midpoint(builder *b, int32_t i, int32_t j) {
    int32_t lo = i < j ? i : j, hi = i < j ? j : i;
    for (size_t k = 0; k < b->edge_count; k++)
        if (b->edges[k][0] == lo && b->edges[k][1] == hi) return b->edges[k][2];
    int32_t mid = add_pos(&b->m, v3_unit(v3_scale(v3_add(b->m.positions[lo], b->m.positions[hi]), 0.5f)));
    b->edges = realloc(b->edges, (b->edge_count + 1) * sizeof *b->edges);
    b->edges[b->edge_count][0] = lo;
    b->edges[b->edge_count][1] = hi;
    b->edges[b->edge_count][2] = mid;
    b->edge_count++;
    return mid;
}

// An icosphere: the icosahedron with each triangle split in four `levels` times, vertices on the unit sphere.
static mesh icosphere(int levels) {
    builder b;
    memset(&b, 0, sizeof b);
    const float t = 1.6180339887f;
    const float v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    const int f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                          {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                          {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int i = 0; i < 12; i++) add_pos(&b.m, v3_unit(v3(v[i][0], v[i][1], v[i][2])));
    for (int i = 0; i < 20; i++) add_tri(&b.m, f[i][0], f[i][1], f[i][2]);
    for (int l = 0; l < levels; l++) {
        mesh_triangle *old = b.m.triangles;
        size_t n = b.m.triangle_count;
        b.m.triangles = NULL;
        b.m.triangle_count = 0;
        b.edge_count = 0;
        for (size_t i = 0; i < n; i++) {
            int32_t a = old[i].v[0], c = old[i].v[1], d = old[i].v[2];
            int32_t ab = midpoint(&b, a, c), bc = midpoint(&b, c, d), ca = midpoint(&b, d, a);
            add_tri(&b.m, a, ab, ca);
            add_tri(&b.m, c, bc, ab);
            add_tri(&b.m, d, ca, bc);
            add_tri(&b.m, ab, bc, ca);
        }
        free(old);
    }
    free(b.edges);
    mesh_compute_bounds(&b.m);
    return b.m;
}

static mesh cube_mesh(void) {
    mesh m;
    memset(&m, 0, sizeof m);
    for (int i = 0; i < 8; i++) add_pos(&m, v3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
    const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                          {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    for (int i = 0; i < 12; i++) add_tri(&m, f[i][0], f[i][1], f[i][2]);
    mesh_compute_bounds(&m);
    return m;
}

static bool mesh_hit_any(const mesh *m, const ray *r, float *t_out) {
    tri_ray tr = tri_ray_make(r);
    float best = INFINITY;
    bool any = false;
    for (size_t i = 0; i < m->triangle_count; i++) {
        tri_hit h;
        if (mesh_intersect_triangle(m, i, &tr, r->tmin, best, &h)) {
            any = true;
            best = h.t;
        }
    }
    *t_out = best;
    return any;
}

// Rays for which the mesh's BVH (its SIMD packets, and its scalar path) found another hit than testing every
// triangle: these rays hit edges and vertices exactly, where the packets' lanes take the double path.
static int bvh_disagreements;

// Whether the wide BVH b over m's triangles finds the hit mesh_hit_any found (t, and hit or not), by both paths.
static bool bvh_agrees(const bvh *b, const ray *r, bool found, float t) {
    hit hs, hv;
    bool fs = bvh_intersect_scalar(b, r, &hs), fv = bvh_intersect(b, r, &hv);
    bool ok = fs == found && fv == found && (!found || (hs.t == t && hv.t == t && hs.prim == hv.prim &&
                                                        hs.b1 == hv.b1 && hs.b2 == hv.b2));
    ok = ok && bvh_occluded(b, r, NULL) == found && bvh_occluded_scalar(b, r) == found;
    return ok;
}

// Fires rays from `origins` at every vertex and at points along every edge; returns how many escaped. Each ray
// also goes through the mesh's BVH (bvh_agrees), whose disagreements are counted in bvh_disagreements.
static int fire_at_vertices_and_edges(const mesh *m, const vec3 *origins, int norigins, int *fired) {
    static const float params[] = {0.5f, 0.25f, 1e-3f, 0.999f, 0.3333333f};
    int escaped = 0;
    bvh b;
    bvh_input in = {.mesh = m};
    CHECK(bvh_build(&b, &in, NULL, true));
    for (int o = 0; o < norigins; o++) {
        for (size_t i = 0; i < m->position_count; i++) {
            ray r = mkray(origins[o], v3_sub(m->positions[i], origins[o]));
            float t;
            bool found = mesh_hit_any(m, &r, &t);
            if (!found) escaped++;
            if (!bvh_agrees(&b, &r, found, t)) bvh_disagreements++;
            (*fired)++;
        }
        for (size_t i = 0; i < m->triangle_count; i++)
            for (int e = 0; e < 3; e++) {
                vec3 a = m->positions[m->triangles[i].v[e]], c = m->positions[m->triangles[i].v[(e + 1) % 3]];
                for (size_t k = 0; k < sizeof params / sizeof params[0]; k++) {
                    ray r = mkray(origins[o], v3_sub(v3_lerp(a, c, params[k]), origins[o]));
                    float t;
                    bool found = mesh_hit_any(m, &r, &t);
                    if (!found) escaped++;
                    if (!bvh_agrees(&b, &r, found, t)) bvh_disagreements++;
                    (*fired)++;
                }
            }
    }
    bvh_release(&b);
    return escaped;
}

static void test_watertight_icosphere(void) {
    mesh m = icosphere(2);
    CHECK(m.triangle_count == 320);
    CHECK(m.position_count == 162);
    // An awkward placement: rotated about a skew axis, scaled unevenly, moved off the origin.
    mat4 s = mat4_scale(v3(1.3f, 0.7f, 1.1f)), rot = mat4_rotate(v3(0.3f, 1, 0.2f), 37.0f),
         tr = mat4_translate(v3(3.1f, -2.7f, 0.9f));
    mat4 rs = mat4_mul(&rot, &s), all = mat4_mul(&tr, &rs);
    transform x;
    CHECK(transform_make(&all, &x));
    mesh_apply_transform(&m, &x);
    vec3 centre = mat4_apply_point(&all, v3(0, 0, 0));
    vec3 origins[6] = {centre};
    rng r = rng_for_sample(3, 4, 5);
    for (int i = 1; i < 6; i++)
        origins[i] = mat4_apply_point(&all, v3_scale(rand_point(&r, -1, 1), 0.4f));
    int fired = 0;
    int escaped = fire_at_vertices_and_edges(&m, origins, 6, &fired);
    CHECK(fired > 5000);
    CHECK(escaped == 0);
    if (escaped) fprintf(stderr, "icosphere: %d of %d rays escaped\n", escaped, fired);
    mesh_free(&m);
    // From outside, aimed at vertices that face the origin (a silhouette vertex may be grazed and missed once
    // the direction is rounded): every ray enters. On the unit sphere the normal is the position.
    m = icosphere(2);
    vec3 outside[3] = {v3(5, 1, -2), v3(-0.5f, 0.3f, 7), v3(0.01f, -3, 0.02f)};
    int fired_out = 0, escaped_out = 0;
    for (int o = 0; o < 3; o++)
        for (size_t i = 0; i < m.position_count; i++) {
            vec3 p = m.positions[i];
            if (v3_dot(p, v3_unit(v3_sub(outside[o], p))) < 0.2f) continue;
            ray ry = mkray(outside[o], v3_sub(p, outside[o]));
            float t;
            if (!mesh_hit_any(&m, &ry, &t)) escaped_out++;
            fired_out++;
        }
    CHECK(fired_out > 100);
    CHECK(escaped_out == 0);
    mesh_free(&m);
}

static void test_watertight_cube(void) {
    mesh m = cube_mesh();
    vec3 origins[8] = {v3(0, 0, 0)};
    rng r = rng_for_sample(11, 0, 0);
    for (int i = 1; i < 8; i++) origins[i] = rand_point(&r, -0.9f, 0.9f);
    // Axis-aligned rays along the cube's faces and edges are the classic leak.
    origins[1] = v3(0, 0, 0.5f);
    int fired = 0;
    int escaped = fire_at_vertices_and_edges(&m, origins, 8, &fired);
    CHECK(fired > 1000);
    CHECK(escaped == 0);
    // The exact centre of every face (a diagonal) and exactly at the corners from the centre.
    for (int axis = 0; axis < 3; axis++)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            vec3 d = v3(axis == 0 ? (float)sgn : 0, axis == 1 ? (float)sgn : 0, axis == 2 ? (float)sgn : 0);
            ray ry = mkray(v3(0, 0, 0), d);
            float t;
            CHECK(mesh_hit_any(&m, &ry, &t));
            CHECK_NEAR(t, 1.0, 1e-6);
        }
    mesh_free(&m);
}

static void test_watertight_box(void) {
    quad q[6];
    vec3 lo = v3(0.1f, 0.2f, 0.3f), hi = v3(0.7f, 1.3f, 0.9f);
    CHECK(quad_box(hi, lo, 0, q));
    vec3 mid = v3_scale(v3_add(lo, hi), 0.5f);
    for (int i = 0; i < 6; i++) {
        // Outward normals, corners exactly on the box.
        vec3 centre = v3_scale(v3_add(q[i].p[0], q[i].p[2]), 0.5f);
        CHECK(v3_dot(q[i].normal, v3_sub(centre, mid)) > 0.0f);
        for (int k = 0; k < 4; k++) {
            vec3 p = q[i].p[k];
            CHECK((p.x == lo.x || p.x == hi.x) && (p.y == lo.y || p.y == hi.y) && (p.z == lo.z || p.z == hi.z));
        }
    }
    rng r = rng_for_sample(5, 5, 5);
    int fired = 0, escaped = 0;
    for (int o = 0; o < 10; o++) {
        vec3 origin = o == 0 ? mid : v3(rng_range(&r, lo.x, hi.x), rng_range(&r, lo.y, hi.y), rng_range(&r, lo.z, hi.z));
        for (int i = 0; i < 6; i++)
            for (int k = 0; k < 4; k++)
                for (int s = 0; s <= 20; s++) {
                    vec3 a = q[i].p[k], b = q[i].p[(k + 1) % 4];
                    ray ry = mkray(origin, v3_sub(v3_lerp(a, b, (float)s / 20.0f), origin));
                    tri_ray tr = tri_ray_make(&ry);
                    bool struck = false;
                    for (int j = 0; j < 6 && !struck; j++) {
                        quad_hit h;
                        struck = quad_intersect(&q[j], &tr, 0, INFINITY, &h);
                    }
                    fired++;
                    if (!struck) escaped++;
                }
    }
    CHECK(fired > 5000);
    CHECK(escaped == 0);
    CHECK(!quad_box(v3(0, 0, 0), v3(1, 0, 1), 0, q)); // flat
}

static void test_quad(void) {
    quad q;
    CHECK(quad_make(v3(0, 0, 0), v3(2, 0, 0), v3(0, 3, 0), 7, &q));
    CHECK_NEAR(q.area, 6.0, 1e-6);
    CHECK_NEAR(q.normal.z, 1.0, 0);
    CHECK(q.material == 7);
    CHECK(q.magnitude == 3.0f); // the largest |coordinate| of its corners (spawn offsets scale with it)
    // Corners that are moved after quad_make (snapped to a box, transformed) keep the magnitude true.
    quad box[6], moved;
    CHECK(quad_box(v3(-5, 0.5f, 1), v3(1, 2, 4), 0, box));
    for (int i = 0; i < 6; i++) CHECK(box[i].magnitude == (i == 1 ? 4.0f : 5.0f));
    mat4 m = mat4_translate(v3(0, -10, 0));
    CHECK(quad_transform(&q, &m, &moved) && moved.magnitude == 10.0f);
    // Boxes whose far corners q + u + v round off the box until snapped: the magnitude is the snapped corners'.
    rng g = rng_for_sample(9, 9, 9);
    int checked = 0;
    for (int t = 0; t < 200; t++) {
        vec3 a = v3(rng_range(&g, -3, 3), rng_range(&g, -3, 3), rng_range(&g, -3, 3));
        vec3 b = v3_add(a, v3(rng_range(&g, 0.1f, 3), rng_range(&g, 0.1f, 3), rng_range(&g, 0.1f, 3)));
        if (!quad_box(a, b, 0, box)) continue;
        for (int i = 0; i < 6; i++) {
            float want = 0.0f;
            for (int k = 0; k < 4; k++)
                want = fmaxf(want, fmaxf(fabsf(box[i].p[k].x), fmaxf(fabsf(box[i].p[k].y), fabsf(box[i].p[k].z))));
            CHECK(box[i].magnitude == want);
            checked++;
        }
    }
    CHECK(checked == 1200);
    ray r = mkray(v3(0.5f, 1.5f, -1), v3(0, 0, 1));
    tri_ray tr = tri_ray_make(&r);
    quad_hit h;
    CHECK(quad_intersect(&q, &tr, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 1.0, 1e-6);
    CHECK_NEAR(h.alpha, 0.25, 1e-6);
    CHECK_NEAR(h.beta, 0.5, 1e-6);
    r = mkray(v3(0.2f, 2.7f, 2), v3(0, 0, -1)); // in the second triangle, from behind
    tr = tri_ray_make(&r);
    CHECK(quad_intersect(&q, &tr, 0, INFINITY, &h));
    CHECK_NEAR(h.t, 2.0, 1e-6);
    CHECK_NEAR(h.alpha, 0.1, 1e-6);
    CHECK_NEAR(h.beta, 0.9, 1e-6);
    r = mkray(v3(2.1f, 1, -1), v3(0, 0, 1));
    tr = tri_ray_make(&r);
    CHECK(!quad_intersect(&q, &tr, 0, INFINITY, &h));
    bounds3 b = quad_bounds(&q);
    CHECK(b.lo.x == 0 && b.hi.x == 2 && b.hi.y == 3 && b.lo.z == 0 && b.hi.z == 0);
    CHECK(!quad_make(v3(0, 0, 0), v3(1, 1, 0), v3(2, 2, 0), 0, &q));
    CHECK(!quad_make(v3(0, 0, 0), v3(INFINITY, 0, 0), v3(0, 1, 0), 0, &q));
    // The book's Cornell light: (213,554,227) + a (130,0,0) + b (0,0,105): u x v points down into the room.
    CHECK(quad_make(v3(213, 554, 227), v3(130, 0, 0), v3(0, 0, 105), 0, &q));
    CHECK_NEAR(q.normal.y, -1.0, 0);
}

static bool same_point(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Transformed quads: corners as points, the front kept under a mirror, degenerate results refused.
static void test_quad_transform(void) {
    quad q, w;
    CHECK(quad_make(v3(0, 0, 0), v3(2, 0, 0), v3(0, 3, 0), 5, &q));
    mat4 t = mat4_translate(v3(1, 2, 3));
    CHECK(quad_transform(&q, &t, &w));
    CHECK(same_point(w.p[0], v3(1, 2, 3)) && same_point(w.p[2], v3(3, 5, 3)));
    CHECK(w.material == 5 && w.normal.z == 1.0f && w.area == 6.0f);
    // A mirror in x leaves the +z side in front, but would flip u x v to -z unless u and v swap.
    mat4 mx = mat4_scale(v3(-1, 1, 1));
    CHECK(quad_transform(&q, &mx, &w));
    CHECK(w.normal.z == 1.0f);
    CHECK(same_point(w.p[1], v3(0, 3, 0)) && same_point(w.p[3], v3(-2, 0, 0)));
    // A mirror in z takes the front side along: the normal follows it to -z.
    mat4 mz = mat4_scale(v3(1, 1, -1));
    CHECK(quad_transform(&q, &mz, &w));
    CHECK(w.normal.z == -1.0f);
    // The corners of a transformed box are the transformed corners, so shared corners stay shared.
    quad box[6], moved[6];
    CHECK(quad_box(v3(0, 0, 0), v3(1, 1, 1), 0, box));
    mat4 rot = mat4_rotate(v3(1, 1, 0), 30);
    bool same = true;
    for (int i = 0; i < 6; i++) {
        same = same && quad_transform(&box[i], &rot, &moved[i]);
        for (int k = 0; k < 4; k++) same = same && same_point(moved[i].p[k], mat4_apply_point(&rot, box[i].p[k]));
    }
    CHECK(same);
    mat4 flat = mat4_scale(v3(1, 0, 1)); // the xy quad becomes a segment
    CHECK(!quad_transform(&q, &flat, &w));
}

static void test_shading(void) {
    mesh m;
    memset(&m, 0, sizeof m);
    vec3 pos[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    vec3 nrm[3] = {v3_unit(v3(-1, -1, 1)), v3_unit(v3(1, 0, 1)), v3_unit(v3(0, 1, 1))};
    uv2 uvs[3] = {{0.1f, 0.2f}, {0.9f, 0.2f}, {0.1f, 0.8f}};
    m.positions = pos;
    m.position_count = 3;
    m.normals = nrm;
    m.normal_count = 3;
    m.uvs = uvs;
    m.uv_count = 3;
    mesh_triangle t = {{0, 1, 2}, -1};
    mesh_corners normal_corners = {{0, 1, 2}}, uv_corners = {{0, 1, 2}};
    m.triangles = &t;
    m.normal_corners = &normal_corners;
    m.uv_corners = &uv_corners;
    m.triangle_count = 1;
    tri_hit h = {1.0f, 0.5f, 0.25f, 0.25f};
    mesh_shading s = mesh_shade(&m, 0, &h);
    vec3 expect = v3_unit(v3_add(v3_add(v3_scale(nrm[0], 0.5f), v3_scale(nrm[1], 0.25f)), v3_scale(nrm[2], 0.25f)));
    CHECK_NEAR(s.ns.x, expect.x, 1e-6);
    CHECK_NEAR(s.ns.y, expect.y, 1e-6);
    CHECK_NEAR(s.ns.z, expect.z, 1e-6);
    CHECK_NEAR(s.ng.z, 1.0, 0);
    CHECK_NEAR(s.u, 0.5 * 0.1 + 0.25 * 0.9 + 0.25 * 0.1, 1e-6);
    CHECK_NEAR(s.v, 0.5 * 0.2 + 0.25 * 0.2 + 0.25 * 0.8, 1e-6);
    // Vertex normals that point the other way turn the geometric normal with them.
    for (int i = 0; i < 3; i++) nrm[i] = v3_neg(nrm[i]);
    s = mesh_shade(&m, 0, &h);
    CHECK_NEAR(s.ng.z, -1.0, 0);
    // Without normals and uvs: geometric normal and barycentric (u, v).
    normal_corners.i[1] = -1;
    uv_corners.i[2] = -1;
    s = mesh_shade(&m, 0, &h);
    CHECK_NEAR(s.ns.z, 1.0, 0);
    CHECK_NEAR(s.u, 0.25, 0);
    CHECK_NEAR(s.v, 0.25, 0);
}

static void test_compute_normals(void) {
    mesh m = icosphere(1);
    CHECK(mesh_compute_normals(&m));
    CHECK(m.normal_count == m.position_count);
    double worst = 0;
    for (size_t i = 0; i < m.position_count; i++)
        worst = fmax(worst, 1.0 - v3_dot(m.normals[i], v3_unit(m.positions[i]))); // a sphere's normal is its position
    CHECK(worst < 0.01);
    // Without normals of its own, a triangle's are its vertices': indexed like the positions, no index stored.
    CHECK(m.smooth && m.smooth_base == 0 && m.normal_corners == NULL);
    for (size_t i = 0; i < m.triangle_count; i++)
        for (int k = 0; k < 3; k++) CHECK(mesh_triangle_normals(&m, i).i[k] == m.triangles[i].v[k]);
    bounds3 b = m.bounds;
    CHECK_NEAR(b.hi.y, 1.0, 1e-6);
    CHECK_NEAR(b.lo.y, -1.0, 1e-6);
    // A second call leaves every triangle's normals as they are (each has complete ones now).
    CHECK(mesh_compute_normals(&m));
    CHECK(m.smooth && m.smooth_base == 0 && m.normal_count == 2 * m.position_count);
    mesh_free(&m);
    // Some triangles with normals of their own keep them; the others get their vertices' smooth normals.
    m = icosphere(0);
    m.normals = malloc(sizeof *m.normals);
    m.normal_corners = malloc(m.triangle_count * sizeof *m.normal_corners);
    CHECK(m.normals && m.normal_corners);
    if (!m.normals || !m.normal_corners) return;
    m.normals[0] = v3(0, 1, 0);
    m.normal_count = 1;
    for (size_t i = 0; i < m.triangle_count; i++)
        m.normal_corners[i] = i % 2 ? (mesh_corners){{0, 0, 0}} : (mesh_corners){{0, -1, 0}};
    CHECK(mesh_compute_normals(&m));
    CHECK(!m.smooth && m.normal_count == 1 + m.position_count);
    for (size_t i = 0; i < m.triangle_count; i++) {
        mesh_corners n = mesh_triangle_normals(&m, i);
        for (int k = 0; k < 3; k++) CHECK(n.i[k] == (i % 2 ? 0 : 1 + m.triangles[i].v[k]));
    }
    // Flat shading drops them all.
    mesh_drop_normals(&m);
    CHECK(m.normal_count == 0 && mesh_triangle_normals(&m, 0).i[0] == -1);
    mesh_free(&m);
}

int main(void) {
    test_analytic();
    test_random_against_reference();
    test_watertight_icosphere();
    test_watertight_cube();
    test_watertight_box();
    CHECK(bvh_disagreements == 0);
    if (bvh_disagreements) fprintf(stderr, "%d rays: the BVH disagreed with testing every triangle\n", bvh_disagreements);
    test_quad();
    test_quad_transform();
    test_shading();
    test_compute_normals();
    return check_summary();
}
