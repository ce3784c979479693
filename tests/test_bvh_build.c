// test_bvh_build.c — the parallel BVH build makes the serial build's tree, byte for byte (nodes, references,
// wide nodes and leaf packets), for any number of threads; queries on it agree with brute force; a build
// stopped from another thread returns false and frees everything (the sanitizer build checks the leaks); the wide
// tree follows the SAH cover plan.
#include "accel/accel.h"
#include "accel/bvh.h"
#include "accel/tri_split.h"
#include "core/rng.h"
#include "glint.h"
#include "render/frame.h"

#include "check.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const int THREAD_COUNTS[] = {1, 2, 3, 8};
enum { THREAD_COUNT_N = sizeof THREAD_COUNTS / sizeof THREAD_COUNTS[0] };

static float urand(rng *g, float lo, float hi) { return rng_range(g, lo, hi); }

// An empty mesh with room for `positions` corners and `triangles` triangles; false (and nothing held) when out of
// memory.
static bool mesh_with_room(mesh *m, size_t positions, size_t triangles) {
    memset(m, 0, sizeof *m);
    m->position_count = positions;
    m->triangle_count = triangles;
    m->positions = malloc(positions * sizeof *m->positions);
    m->triangles = malloc(triangles * sizeof *m->triangles);
    if (m->positions && m->triangles) return true;
    mesh_free(m);
    return false;
}

// A soup of n random triangles in [-10, 10]^3: mostly small, some long slivers, exact duplicates (equal
// centroids), degenerate ones, and clusters that share one centroid (ranges that no axis can split).
static bool make_soup(rng *g, size_t n, mesh *m) {
    if (!mesh_with_room(m, 3 * n, n)) return false;
    for (size_t i = 0; i < n; i++) {
        vec3 *p = &m->positions[3 * i];
        float kind = rng_float(g);
        if (kind < 0.05f && i > 0) { // a copy of the previous triangle
            for (int j = 0; j < 3; j++) p[j] = p[j - 3];
        } else if (kind < 0.08f) { // around one point: all share a centroid
            float s = urand(g, 0.01f, 1.0f);
            p[0] = v3(3 + s, 3, 3);
            p[1] = v3(3 - s, 3 + s, 3);
            p[2] = v3(3, 3 - s, 3);
        } else {
            vec3 c = v3(urand(g, -10, 10), urand(g, -10, 10), urand(g, -10, 10));
            float size = kind < 0.1f ? 5.0f : (kind < 0.12f ? 0.0f : 0.2f);
            for (int j = 0; j < 3; j++)
                p[j] = v3_add(c, v3(urand(g, -size, size), urand(g, -size, size), urand(g, -size, size)));
        }
        for (int j = 0; j < 3; j++) m->triangles[i].v[j] = (int32_t)(3 * i + (size_t)j);
        m->triangles[i].material = -1;
    }
    mesh_compute_bounds(m);
    return true;
}

// n spheres as in the book's final scene: a huge ground, small spheres on a grid with jitter, a few big
// ones, some nested and duplicated.
static sphere *make_spheres(rng *g, size_t n) {
    sphere *s = malloc(n * sizeof *s);
    if (!s) return NULL;
    size_t side = (size_t)sqrt((double)n) + 1;
    for (size_t i = 0; i < n; i++) {
        float x = (float)(i % side) - (float)side / 2, z = (float)(i / side) - (float)side / 2;
        s[i] = (sphere){v3(x + urand(g, 0, 0.9f), 0.2f, z + urand(g, 0, 0.9f)), 0.2f, 0};
        float kind = rng_float(g);
        if (i == 0) s[i] = (sphere){v3(0, -1000, 0), 1000.0f, 0};
        else if (kind < 0.02f) s[i].radius = urand(g, 1.0f, 4.0f);
        else if (kind < 0.05f) s[i] = s[i - 1];
        else if (kind < 0.08f) s[i].radius = -0.15f;
    }
    return s;
}

// Whether two wide nodes hold the same bytes (the padding at their end excepted).
static bool same_wnodes(const bvh_wnode *a, const bvh_wnode *b, size_t n) {
    for (size_t i = 0; i < n; i++)
        if (memcmp(a[i].box, b[i].box, sizeof a[i].box) != 0 || memcmp(a[i].child, b[i].child, sizeof a[i].child) != 0)
            return false;
    return true;
}

// Whether two builds are the same bytes: statistics, references, binary nodes, wide nodes and packets.
static bool same_bvh(const bvh *a, const bvh *b) {
    if (a->stats.nodes != b->stats.nodes || a->stats.leaves != b->stats.leaves || a->stats.depth != b->stats.depth ||
        a->ref_count != b->ref_count || a->node2_count != b->node2_count || a->wnode_count != b->wnode_count ||
        a->slot_count != b->slot_count || a->root != b->root || a->front != b->front)
        return false;
    return (!a->ref_count || memcmp(a->refs, b->refs, a->ref_count * sizeof *a->refs) == 0) &&
           (!a->node2_count || memcmp(a->nodes2, b->nodes2, a->node2_count * sizeof *a->nodes2) == 0) &&
           same_wnodes(a->wnodes, b->wnodes, a->wnode_count) &&
           (!a->slot_count || memcmp(a->slots, b->slots, a->slot_count * sizeof *a->slots) == 0);
}

// Builds `in` on every thread count (wide and binary, with parallel_min: 0 the default) and checks that each tree
// is the one thread's.
static void check_same_trees(const char *what, bvh_input in, size_t parallel_min) {
    accel_build_options opt = {.parallel_min = parallel_min};
    for (int wide = 0; wide <= 1; wide++) {
        bvh one;
        opt.threads = 1;
        CHECK(bvh_build(&one, &in, &opt, wide));
        // A wide build keeps only what the wide traversal reads; the binary one keeps its nodes and references.
        CHECK(wide ? !one.nodes2 && !one.refs && one.slots : one.nodes2 && one.refs && !one.slots);
        for (int t = 1; t < THREAD_COUNT_N; t++) {
            bvh many;
            opt.threads = THREAD_COUNTS[t];
            CHECK(bvh_build(&many, &in, &opt, wide));
            bool same = same_bvh(&one, &many);
            CHECK(same);
            if (!same)
                fprintf(stderr, "%s (%s, parallel_min %zu): %d threads build another tree than 1\n", what,
                        wide ? "wide" : "binary", parallel_min, THREAD_COUNTS[t]);
            bvh_release(&many);
        }
        bvh_release(&one);
    }
}

static bool same_hit(bool fa, const hit *a, bool fb, const hit *b) {
    if (fa != fb) return false;
    return !fa || (a->prim == b->prim && a->kind == b->kind && a->instance == b->instance &&
                   memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(&a->b1, &b->b1, sizeof a->b1) == 0 &&
                   memcmp(&a->b2, &b->b2, sizeof a->b2) == 0);
}

// Rays from around [-12, 12]^3, half of them aimed at a random point of the scene's box.
static ray random_ray(rng *g, const mesh *m, const sphere *spheres, size_t sphere_count) {
    ray r = {v3(urand(g, -12, 12), urand(g, 0.5f, 12), urand(g, -12, 12)), v3(0, 0, 1), 0.0f, INFINITY, 0.0f};
    vec3 target = v3(urand(g, -10, 10), urand(g, -1, 3), urand(g, -10, 10));
    float aim = rng_float(g);
    if (m && aim < 0.5f) target = m->positions[rng_u32(g) % m->position_count];
    else if (spheres && aim < 0.5f) target = spheres[1 + rng_u32(g) % (sphere_count - 1)].center;
    else if (aim < 0.7f) r.o.y = target.y = 100.0f; // above everything, looking past it
    r.d = v3_sub(target, r.o);
    if (v3_len2(r.d) < 1e-6f) r.d = v3(0, 1, 0);
    if (rng_float(g) < 0.3f) r.tmax = urand(g, 1.0f, 20.0f);
    return r;
}

// The accel built on `threads` threads against brute force, closest and any hit, on `rays` random rays.
static void check_queries(const char *what, const geometry_arrays *in, int threads, int rays, uint64_t seed) {
    glint_error err;
    accel_build_options opt = {.threads = threads};
    accel *a = accel_build(in, ACCEL_BVH, &opt, &err);
    accel *a2 = accel_build(in, ACCEL_BVH2, &opt, &err);
    accel *an = accel_build(in, ACCEL_NONE, &opt, &err); // brute force, flattening what the BVHs flatten
    CHECK(a && a2 && an);
    if (!a || !a2 || !an) {
        accel_free(a);
        accel_free(a2);
        accel_free(an);
        return;
    }
    rng g = rng_for_sample(seed, 1, 2);
    int bad = 0, hits = 0;
    for (int i = 0; i < rays; i++) {
        ray r = random_ray(&g, in->mesh_count ? in->meshes[0] : NULL, in->spheres, in->sphere_count);
        hit hb, hw, h2;
        memset(&hb, 0, sizeof hb);
        memset(&hw, 0, sizeof hw);
        memset(&h2, 0, sizeof h2);
        bool fb = accel_intersect(an, &r, &hb), fw = accel_intersect(a, &r, &hw), f2 = accel_intersect(a2, &r, &h2);
        hits += fb;
        bool ok = same_hit(fb, &hb, fw, &hw) && same_hit(fb, &hb, f2, &h2) && accel_occluded(a, &r) == fb &&
                  accel_occluded(a2, &r) == fb;
        if (!ok && bad++ < 3)
            fprintf(stderr, "%s, %d threads: ray %d: brute force %d prim %u t %.9g, bvh %d prim %u t %.9g, bvh2 %d prim %u\n",
                    what, threads, i, fb, hb.prim, (double)hb.t, fw, hw.prim, (double)hw.t, f2, h2.prim);
    }
    CHECK(bad == 0);
    CHECK(hits > 0 && hits < rays); // both outcomes exercised
    // Packets of 1 to ACCEL_COHERENT rays near one ray (one origin, directions a little apart, now and then one
    // pointing elsewhere, a limited tmax or a NaN): the same hits as one ray at a time.
    int packet_bad = 0, packets = 0;
    for (int i = 0; i < rays / 4; i++) {
        ray base = random_ray(&g, in->mesh_count ? in->meshes[0] : NULL, in->spheres, in->sphere_count);
        int n = 1 + i % ACCEL_COHERENT;
        ray pr[ACCEL_COHERENT];
        hit ph[ACCEL_COHERENT], one;
        bool pf[ACCEL_COHERENT];
        float spread = i % 3 == 0 ? 0.3f : 0.01f;
        for (int k = 0; k < n; k++) {
            pr[k] = base;
            pr[k].d = v3_add(base.d, v3_scale(v3(urand(&g, -1, 1), urand(&g, -1, 1), urand(&g, -1, 1)),
                                              spread * sqrtf(v3_len2(base.d))));
            if (rng_float(&g) < 0.05f) pr[k].d = v3_neg(pr[k].d);
            if (rng_float(&g) < 0.1f) pr[k].tmax = urand(&g, 0.5f, 10.0f);
            if (rng_float(&g) < 0.01f) pr[k].o.x = NAN;
        }
        memset(ph, 0, sizeof ph);
        accel_intersect_coherent(a, n, pr, ph, pf);
        for (int k = 0; k < n; k++) {
            memset(&one, 0, sizeof one);
            bool f1 = accel_intersect(a, &pr[k], &one);
            if (!same_hit(f1, &one, pf[k], &ph[k]) && packet_bad++ < 3)
                fprintf(stderr, "%s: packet %d ray %d: one ray %d prim %u t %.9g, packet %d prim %u t %.9g\n", what, i, k,
                        f1, one.prim, (double)one.t, pf[k], ph[k].prim, (double)ph[k].t);
        }
        packets++;
    }
    CHECK(packets > 0 && packet_bad == 0);
    accel_free(a);
    accel_free(a2);
    accel_free(an);
}

// ~300k triangles with the default thresholds: the parallel top, its partition and the subtrees.
static void check_soup(void) {
    rng g = rng_for_sample(11, 300, 0);
    mesh m;
    CHECK(make_soup(&g, 300000, &m));
    check_same_trees("soup of 300k triangles", (bvh_input){.mesh = &m}, 0);
    const mesh *meshes[1] = {&m};
    instance inst = {.kind = INSTANCE_MESH, .xf = transform_identity(), .material = -1};
    geometry_arrays in = {.meshes = meshes, .mesh_count = 1, .instances = &inst, .instance_count = 1};
    check_queries("soup of 300k triangles", &in, 3, 100, 5);
    mesh_free(&m);
}

static float box_half_area3(bounds3 b) {
    vec3 d = v3_sub(b.hi, b.lo);
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

// tri_split: well-shaped triangles at any orientation are left whole, slivers across their box cut up to three times;
// the pieces' boxes lie in the triangle's box, are smaller together than it, and hold every point of the triangle.
static void check_tri_split(void) {
    rng g = rng_for_sample(21, 0, 0);
    for (int i = 0; i < 2000; i++) { // equilateral triangles, randomly turned and placed
        vec3 a = v3(urand(&g, -1, 1), urand(&g, -1, 1), urand(&g, -1, 1));
        vec3 b = v3(urand(&g, -1, 1), urand(&g, -1, 1), urand(&g, -1, 1));
        if (v3_len2(a) < 1e-3f || v3_len2(b) < 1e-3f) continue;
        vec3 u = v3_unit(a), w = v3_unit(v3_cross(a, b)), v = v3_cross(w, u); // orthonormal u, v in the plane
        vec3 c = v3(urand(&g, -50, 50), urand(&g, -50, 50), urand(&g, -50, 50));
        float s = urand(&g, 0.01f, 10.0f), h = s * 0.8660254f;
        vec3 p0 = c, p1 = v3_fma(c, u, s), p2 = v3_fma(v3_fma(c, u, 0.5f * s), v, h);
        CHECK(tri_split_levels(p0, p1, p2) == 0);
    }
    CHECK(tri_split_levels(v3(0, 0, 0), v3(1, 1, 1), v3(2, 2, 2)) == 0); // degenerate
    CHECK(tri_split_levels(v3(0, 0, 0), v3(10, 0, 0), v3(0, 0.01f, 0)) == 0); // long, but along an axis: a tight box
    int cut = 0;
    for (int i = 0; i < 500; i++) { // long slivers across their boxes
        vec3 p0 = v3(urand(&g, -5, 5), urand(&g, -5, 5), urand(&g, -5, 5));
        vec3 e = v3(urand(&g, 1, 4), urand(&g, 1, 4), urand(&g, -4, -1));
        vec3 p1 = v3_add(p0, e), p2 = v3_add(p0, v3(urand(&g, -0.01f, 0.01f), urand(&g, -0.01f, 0.01f), 0.02f));
        int levels = tri_split_levels(p0, p1, p2);
        CHECK(levels >= 1 && levels <= TRI_SPLIT_MAX_LEVELS);
        cut += levels == TRI_SPLIT_MAX_LEVELS;
        bounds3 piece[1 << TRI_SPLIT_MAX_LEVELS];
        int n = tri_split_bounds(p0, p1, p2, levels, piece);
        CHECK(n == 1 << levels);
        bounds3 whole = bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), p0), p1), p2);
        float pieces_area = 0.0f; // the pieces' boxes are far smaller together than the triangle's (half areas)
        for (int k = 0; k < n; k++) {
            CHECK(piece[k].lo.x >= whole.lo.x && piece[k].lo.y >= whole.lo.y && piece[k].lo.z >= whole.lo.z);
            CHECK(piece[k].hi.x <= whole.hi.x && piece[k].hi.y <= whole.hi.y && piece[k].hi.z <= whole.hi.z);
            pieces_area += box_half_area3(piece[k]);
        }
        CHECK(pieces_area < 0.75f * box_half_area3(whole));
        for (int j = 0; j < 200; j++) { // points of the triangle, in double: each in some piece's box
            double a = rng_float(&g), b = rng_float(&g);
            if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
            if (j == 0) a = 0.0, b = 0.0; // the corners too
            if (j == 1) a = 1.0, b = 0.0;
            if (j == 2) a = 0.0, b = 1.0;
            double q[3] = {p0.x + a * ((double)p1.x - p0.x) + b * ((double)p2.x - p0.x),
                           p0.y + a * ((double)p1.y - p0.y) + b * ((double)p2.y - p0.y),
                           p0.z + a * ((double)p1.z - p0.z) + b * ((double)p2.z - p0.z)};
            bool inside = false;
            for (int k = 0; k < n && !inside; k++) {
                const float lo[3] = {piece[k].lo.x, piece[k].lo.y, piece[k].lo.z};
                const float hi[3] = {piece[k].hi.x, piece[k].hi.y, piece[k].hi.z};
                bool in = true;
                for (int ax = 0; ax < 3; ax++)
                    in = in && q[ax] >= (double)lo[ax] - 1e-12 && q[ax] <= (double)hi[ax] + 1e-12;
                inside = in;
            }
            CHECK(inside);
        }
    }
    CHECK(cut > 0);
}

// A mesh of n triangles, each with corners of its own, of which the first `slivers` lie across their boxes (each asks
// for a split) and the rest are right isosceles ones in the xy plane (none asks), spread along x.
static bool make_mixed_slivers(size_t n, size_t slivers, mesh *m) {
    if (!mesh_with_room(m, 3 * n, n)) return false;
    for (size_t t = 0; t < n; t++) {
        vec3 o = v3((float)t * 0.5f, 0.0f, 0.0f), *p = &m->positions[3 * t];
        p[0] = o;
        if (t < slivers) {
            p[1] = v3_add(o, v3(2.0f, 3.0f, -2.5f));
            p[2] = v3_add(o, v3(0.01f, 0.0f, 0.02f));
        } else {
            p[1] = v3_add(o, v3(0.4f, 0.0f, 0.0f));
            p[2] = v3_add(o, v3(0.0f, 0.4f, 0.0f));
        }
        m->triangles[t] = (mesh_triangle){{(int32_t)(3 * t), (int32_t)(3 * t + 1), (int32_t)(3 * t + 2)}, -1};
    }
    mesh_compute_bounds(m);
    return true;
}

// Only a mesh whose typical triangle asks for a split is pre-split (tri_split_mesh_wants): a minority of slivers
// leaves the tree as it is without pre-splitting, a majority cuts them; an empty mesh wants nothing.
static void check_split_choice(void) {
    mesh empty;
    memset(&empty, 0, sizeof empty);
    CHECK(!tri_split_mesh_wants(&empty));
    const struct {
        size_t n, slivers;
        bool wants;
    } cases[] = {{10, 0, false}, {10, 4, false}, {10, 5, true}, {10, 10, true}, {20000, 7000, false},
                 {20000, 13000, true}, {1, 1, true}};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        mesh m;
        CHECK(make_mixed_slivers(cases[i].n, cases[i].slivers, &m));
        if (!m.positions) continue;
        CHECK(tri_split_mesh_wants(&m) == cases[i].wants);
        bvh split, whole;
        CHECK(bvh_build(&split, &(bvh_input){.mesh = &m}, NULL, true));
        CHECK(bvh_build(&whole, &(bvh_input){.mesh = &m}, &(accel_build_options){.no_presplit = true}, true));
        if (cases[i].wants && cases[i].slivers >= 1000) CHECK(split.stats.leaves > whole.stats.leaves);
        if (!cases[i].wants) CHECK(split.stats.leaves == whole.stats.leaves && split.stats.nodes == whole.stats.nodes);
        bvh_release(&split);
        bvh_release(&whole);
        mesh_free(&m);
    }
}

// Spatial splits (bvh_spatial.h) on a model like a CAD part: small triangles, and among them long, thin ones lying
// across the model (too few for the mesh to be pre-split, tri_split_mesh_wants). The tree cuts some (more leaves
// than without spatial splits), is the same for any number of threads, and finds the hits brute force finds.
static void check_spatial(void) {
    enum { SMALL = 12000, LONG = 6000 };
    mesh m;
    bool room = mesh_with_room(&m, 3 * (SMALL + LONG), SMALL + LONG);
    CHECK(room);
    if (!room) return;
    rng g = rng_for_sample(31, 0, 0);
    for (size_t t = 0; t < SMALL + LONG; t++) {
        vec3 *p = &m.positions[3 * t];
        if (t < SMALL) { // a small triangle anywhere in the model
            p[0] = v3(urand(&g, -8, 8), urand(&g, -1, 3), urand(&g, -8, 8));
            p[1] = v3_add(p[0], v3(urand(&g, 0.1f, 0.3f), urand(&g, -0.1f, 0.1f), 0.0f));
            p[2] = v3_add(p[0], v3(0.0f, urand(&g, -0.1f, 0.1f), urand(&g, 0.1f, 0.3f)));
        } else { // a long, thin one from one side of the model to the other, slanted
            p[0] = v3(urand(&g, -8, -6), urand(&g, -1, 3), urand(&g, -8, 8));
            p[1] = v3_add(p[0], v3(14.0f, urand(&g, -1, 1), urand(&g, -3, 3)));
            p[2] = v3_add(p[0], v3(0.05f, 0.05f, 0.05f));
        }
        m.triangles[t] = (mesh_triangle){{(int32_t)(3 * t), (int32_t)(3 * t + 1), (int32_t)(3 * t + 2)}, -1};
    }
    mesh_compute_bounds(&m);
    CHECK(!tri_split_mesh_wants(&m));
    bvh cut, whole;
    CHECK(bvh_build(&cut, &(bvh_input){.mesh = &m}, NULL, true));
    CHECK(bvh_build(&whole, &(bvh_input){.mesh = &m}, &(accel_build_options){.no_spatial = true}, true));
    CHECK(cut.stats.leaves > whole.stats.leaves);
    bvh_release(&cut);
    bvh_release(&whole);
    check_same_trees("long triangles among small ones", (bvh_input){.mesh = &m}, 0);
    check_same_trees("long triangles among small ones", (bvh_input){.mesh = &m}, 64);
    const mesh *meshes[1] = {&m};
    instance inst = {.kind = INSTANCE_MESH, .xf = transform_identity(), .material = -1};
    geometry_arrays in = {.meshes = meshes, .mesh_count = 1, .instances = &inst, .instance_count = 1};
    check_queries("long triangles among small ones", &in, 1, 3000, 8);
    check_queries("long triangles among small ones", &in, 2, 3000, 9);
    mesh_free(&m);
}

// A sphere of slivers (bands from pole to pole, many thin segments): pre-split, so the BVH holds more leaves than
// without, the same tree for any number of threads, and the same hits as brute force.
static void check_slivers(void) {
    enum { BANDS = 4, SEGMENTS = 3000 };
    mesh m;
    bool room = mesh_with_room(&m, (BANDS + 1) * SEGMENTS, 2 * BANDS * SEGMENTS);
    CHECK(room);
    if (!room) return;
    for (int i = 0; i <= BANDS; i++)
        for (int j = 0; j < SEGMENTS; j++) {
            double th = 3.14159265358979 * i / BANDS, ph = 2 * 3.14159265358979 * j / SEGMENTS;
            m.positions[i * SEGMENTS + j] =
                v3((float)(5 * sin(th) * cos(ph)), (float)(5 * cos(th)), (float)(5 * sin(th) * sin(ph)));
        }
    size_t t = 0;
    for (int i = 0; i < BANDS; i++)
        for (int j = 0; j < SEGMENTS; j++) {
            int32_t a = i * SEGMENTS + j, b = i * SEGMENTS + (j + 1) % SEGMENTS, c = a + SEGMENTS, d = b + SEGMENTS;
            m.triangles[t++] = (mesh_triangle){{a, c, b}, -1};
            m.triangles[t++] = (mesh_triangle){{b, c, d}, -1};
        }
    mesh_compute_bounds(&m);
    bvh split, whole;
    CHECK(bvh_build(&split, &(bvh_input){.mesh = &m}, NULL, true));
    CHECK(bvh_build(&whole, &(bvh_input){.mesh = &m}, &(accel_build_options){.no_presplit = true}, true));
    CHECK(split.stats.leaves > 2 * whole.stats.leaves);
    bvh_release(&split);
    bvh_release(&whole);
    check_same_trees("sphere of slivers", (bvh_input){.mesh = &m}, 4096);
    const mesh *meshes[1] = {&m};
    instance inst = {.kind = INSTANCE_MESH, .xf = transform_identity(), .material = -1};
    geometry_arrays in = {.meshes = meshes, .mesh_count = 1, .instances = &inst, .instance_count = 1};
    check_queries("sphere of slivers", &in, 2, 3000, 7);
    mesh_free(&m);
}

static void check_sphere_scene(void) {
    rng g = rng_for_sample(12, 100, 0);
    size_t n = 100000;
    sphere *s = make_spheres(&g, n);
    CHECK(s != NULL);
    if (!s) return;
    geometry_arrays in = {.spheres = s, .sphere_count = n};
    check_same_trees("100k spheres", (bvh_input){.geometry = &in}, 0);
    check_queries("100k spheres", &in, 8, 300, 6);
    free(s);
}

// Small scenes split in parallel down to ranges of a few primitives (parallel_min): chunks of one or two
// primitives, wrong-side segments that cross chunks, ranges already partitioned, reversed or all on one
// centroid.
static void check_small(void) {
    const size_t sizes[] = {2, 3, 7, 64, 1000, 5000};
    const size_t mins[] = {1, 2, 8, 100};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t j = 0; j < sizeof mins / sizeof *mins; j++) {
            rng g = rng_for_sample(13, sizes[i], mins[j]);
            mesh m;
            CHECK(make_soup(&g, sizes[i], &m));
            char what[64];
            snprintf(what, sizeof what, "soup of %zu triangles", sizes[i]);
            check_same_trees(what, (bvh_input){.mesh = &m}, mins[j]);
            // Sorted along x, then reversed: every partition finds its sides in order, or all on the wrong one.
            for (size_t t = 0; t < m.triangle_count; t++)
                for (int k = 0; k < 3; k++) m.positions[3 * t + (size_t)k].x = (float)t + (float)k * 0.25f;
            check_same_trees("sorted soup", (bvh_input){.mesh = &m}, mins[j]);
            for (size_t t = 0; t < m.triangle_count; t++)
                for (int k = 0; k < 3; k++) m.positions[3 * t + (size_t)k].x = -(float)t - (float)k * 0.25f;
            check_same_trees("reversed soup", (bvh_input){.mesh = &m}, mins[j]);
            // Every triangle on one centroid: halved ranges down to the leaves.
            for (size_t t = 0; t < m.position_count; t++) m.positions[t] = m.positions[t % 3];
            check_same_trees("coincident soup", (bvh_input){.mesh = &m}, mins[j]);
            mesh_free(&m);
            sphere *s = make_spheres(&g, sizes[i] + 1);
            CHECK(s != NULL);
            if (s) {
                geometry_arrays some = {.spheres = s, .sphere_count = sizes[i] + 1};
                check_same_trees("spheres", (bvh_input){.geometry = &some}, mins[j]);
            }
            free(s);
        }
}

typedef struct stopper {
    atomic_int *stop;
    long delay_us;
} stopper;

static void *stop_later(void *arg) {
    const stopper *s = arg;
    struct timespec ts = {s->delay_us / 1000000, (s->delay_us % 1000000) * 1000};
    nanosleep(&ts, NULL);
    atomic_store(s->stop, 1);
    return NULL;
}

// A stop requested from another thread while the threads build: false, the bvh empty, nothing leaked.
static void check_stop(void) {
    rng g = rng_for_sample(14, 1, 0);
    mesh m;
    CHECK(make_soup(&g, 200000, &m));
    const long delays_us[] = {0, 200, 1000, 5000, 20000};
    int stopped = 0;
    for (size_t i = 0; i < sizeof delays_us / sizeof *delays_us; i++) {
        atomic_int stop = 0;
        stopper s = {&stop, delays_us[i]};
        pthread_t thread;
        bool started = pthread_create(&thread, NULL, stop_later, &s) == 0;
        CHECK(started);
        if (!started) break;
        if (delays_us[i] == 0) pthread_join(thread, NULL); // stopped before it starts
        bvh b;
        accel_build_options opt = {.stop = &stop, .threads = 3, .parallel_min = i % 2 ? 1000 : 0};
        bool built = bvh_build(&b, &(bvh_input){.mesh = &m}, &opt, i % 2 == 0);
        if (delays_us[i] != 0) pthread_join(thread, NULL);
        if (!built) {
            stopped++;
            CHECK(b.wnodes == NULL && b.nodes2 == NULL && b.refs == NULL && b.slots == NULL);
        } else {
            bvh_release(&b); // finished before the stop came
        }
    }
    CHECK(stopped >= 1);
    mesh_free(&m);
}

// A floor (a large quad) is padded on each axis by that axis's own magnitude, and it has a leaf of its own even
// where triangles lie on it: its box is as thin as its height needs, so a ray spawned off it (offset by 2^-21 of
// the quad's magnitude, spawn.h) starts above every box the floor is in and tests nothing there. The queries
// (check_queries) still find every hit, ties included.
static void check_floor_leaf(void) {
    quad floor;
    CHECK(quad_make(v3(-50.0f, 0.25f, 50.0f), v3(100.0f, 0.0f, 0.0f), v3(0.0f, 0.0f, -100.0f), 0, &floor));
    rng g = rng_for_sample(14, 1, 0);
    mesh m;
    CHECK(make_soup(&g, 300, &m));
    for (size_t i = 0; i < m.position_count; i++) // small triangles lying just above the floor
        m.positions[i] = v3(m.positions[i].x * 0.1f, 0.26f + fabsf(m.positions[i].y) * 0.01f, m.positions[i].z * 0.1f);
    mesh_compute_bounds(&m);
    bvh b;
    geometry_arrays ground = {.quads = &floor, .quad_count = 1};
    CHECK(bvh_build(&b, &(bvh_input){.geometry = &ground, .mesh = &m}, NULL, true));
    int floor_leaves = 0;
    float spawned = 0.25f + 0x1p-21f * 50.0f; // a point off the floor, as spawn_point_of offsets it
    for (size_t w = 0; w < b.wnode_count; w++)
        for (int i = 0; i < BVH_WIDTH; i++) {
            uint32_t c = b.wnodes[w].child[i];
            if (c == BVH_EMPTY || !(c & BVH_LEAF)) continue;
            const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)&b.slots[c & ~BVH_LEAF];
            bool has_floor = false, has_other = false;
            for (;; hd += hd->slots) {
                if (hd->kind == PRIM_QUAD) has_floor = true;
                else has_other = true;
                if (hd->last) break;
            }
            if (!has_floor) continue;
            floor_leaves++;
            CHECK(!has_other); // the floor's leaf holds nothing else
            CHECK(b.wnodes[w].box[4][i] >= 0.25f && b.wnodes[w].box[4][i] < spawned);
            CHECK(b.wnodes[w].box[1][i] <= 0.25f && b.wnodes[w].box[4][i] - b.wnodes[w].box[1][i] <= 0x1p-18f);
        }
    CHECK(floor_leaves == 1);
    bvh_release(&b);
    instance inst = {.kind = INSTANCE_MESH, .xf = transform_identity(), .material = -1};
    const mesh *meshes[1] = {&m};
    geometry_arrays in = {.quads = &floor, .quad_count = 1, .meshes = meshes, .mesh_count = 1, .instances = &inst,
                          .instance_count = 1};
    check_queries("a floor under triangles", &in, 2, 3000, 8);
    mesh_free(&m);
}

// The wide tree of a real mesh follows the cover plan (plan_cover): the Stanford bunny's 69,451 triangles in 1,938
// wide nodes; opening the largest child first, as the collapse once did, made 3,321 of no lower SAH cost.
static void check_cover_plan(void) {
    char path[4096];
    snprintf(path, sizeof path, "%s/bench/scenes/bunny-yardstick.json", GLINT_SOURCE_DIR);
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_load(path, &s, &err) == GLINT_OK);
    if (!s) return;
    accel *a = frame_accel_build(s, &(accel_build_options){.threads = 2}, &err);
    CHECK(a != NULL);
    accel_stats st;
    if (a) accel_get_stats(a, &st);
    CHECK(a && st.nodes <= 2000);
    accel_free(a);
    glint_scene_free(s);
}

int main(void) {
    check_cover_plan();
    check_floor_leaf();
    check_small();
    check_tri_split();
    check_split_choice();
    check_spatial();
    check_slivers();
    check_soup();
    check_sphere_scene();
    check_stop();
    return check_summary();
}
