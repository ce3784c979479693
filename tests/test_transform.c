// test_transform.c — affine matrices: determinants, similarity detection, inverses, rotations of known vectors,
// normals under non-uniform scale, composition order, transformed rays and bounding boxes, baked mesh transforms.
#include "check.h"
#include "core/rng.h"
#include "geometry/mesh.h"
#include "geometry/transform.h"

#include <string.h>

static void check_identity(const mat4 *m, double tol) {
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) CHECK_NEAR(m->m[i][j], i == j ? 1.0 : 0.0, tol);
}

static mat4 random_affine(rng *r) {
    vec3 axis = v3(rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
    mat4 rot = mat4_rotate(axis, rng_range(r, -360, 360));
    mat4 s = mat4_scale(v3(rng_range(r, 0.2f, 3), rng_range(r, -3, -0.2f), rng_range(r, 0.2f, 3)));
    mat4 t = mat4_translate(v3(rng_range(r, -50, 50), rng_range(r, -50, 50), rng_range(r, -50, 50)));
    mat4 rs = mat4_mul(&rot, &s);
    return mat4_mul(&t, &rs);
}

static void test_inverse(void) {
    rng r = rng_for_sample(1, 2, 3);
    for (int k = 0; k < 200; k++) {
        mat4 m = random_affine(&r), inv;
        CHECK(mat4_invert(&m, &inv));
        mat4 a = mat4_mul(&inv, &m), b = mat4_mul(&m, &inv);
        check_identity(&a, 2e-5);
        check_identity(&b, 2e-4); // translations up to 50 make this product's last column less exact
    }
    mat4 id = mat4_identity(), inv;
    CHECK(mat4_invert(&id, &inv));
    check_identity(&inv, 0);
    // Singular and non-affine matrices have no (affine) inverse; the output is left alone.
    mat4 flat = mat4_scale(v3(1, 0, 1));
    inv = mat4_translate(v3(9, 9, 9));
    CHECK(!mat4_invert(&flat, &inv));
    CHECK(inv.m[0][3] == 9.0f);
    mat4 proj = mat4_identity();
    proj.m[3][2] = 1.0f;
    CHECK(!mat4_is_affine(&proj));
    CHECK(!mat4_invert(&proj, &inv));
    mat4 nan = mat4_identity();
    nan.m[1][2] = NAN;
    CHECK(!mat4_is_affine(&nan));
    transform t;
    CHECK(!transform_make(&flat, &t));
    mat4 tiny = mat4_scale(v3(1e-39f, 1, 1)); // the inverse, 1e39, overflows a float
    CHECK(!mat4_invert(&tiny, &inv));
}

static void test_rotation(void) {
    // Quarter turns are exact: x -> y about z, y -> z about x, z -> x about y.
    mat4 rz = mat4_rotate(v3(0, 0, 1), 90), rx = mat4_rotate(v3(2, 0, 0), 90), ry = mat4_rotate(v3(0, 1, 0), 90);
    vec3 a = mat4_apply_vector(&rz, v3(1, 0, 0));
    CHECK(a.x == 0.0f && a.y == 1.0f && a.z == 0.0f);
    a = mat4_apply_vector(&rx, v3(0, 1, 0));
    CHECK(a.x == 0.0f && a.y == 0.0f && a.z == 1.0f);
    a = mat4_apply_vector(&ry, v3(0, 0, 1));
    CHECK(a.x == 1.0f && a.y == 0.0f && a.z == 0.0f);
    mat4 half = mat4_rotate(v3(0, 1, 0), -180);
    a = mat4_apply_vector(&half, v3(1, 2, 3));
    CHECK(a.x == -1.0f && a.y == 2.0f && a.z == -3.0f);
    // 120 degrees about (1,1,1) cycles the axes.
    mat4 cyc = mat4_rotate(v3(1, 1, 1), 120);
    a = mat4_apply_vector(&cyc, v3(1, 0, 0));
    CHECK_NEAR(a.x, 0, 1e-6);
    CHECK_NEAR(a.y, 1, 1e-6);
    CHECK_NEAR(a.z, 0, 1e-6);
    // The Cornell box's 15 degrees about y: (1,0,0) -> (cos 15, 0, -sin 15).
    mat4 r15 = mat4_rotate(v3(0, 1, 0), 15);
    a = mat4_apply_vector(&r15, v3(1, 0, 0));
    CHECK_NEAR(a.x, cos(15 * 3.14159265358979323846 / 180), 1e-7);
    CHECK_NEAR(a.z, -sin(15 * 3.14159265358979323846 / 180), 1e-7);
    // Rotations keep lengths and the axis itself.
    rng r = rng_for_sample(9, 9, 9);
    for (int k = 0; k < 100; k++) {
        vec3 axis = v3(rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
        mat4 m = mat4_rotate(axis, rng_range(&r, -720, 720));
        vec3 v = v3(rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
        CHECK_NEAR(v3_len(mat4_apply_vector(&m, v)), v3_len(v), 1e-5);
        vec3 ax = mat4_apply_vector(&m, axis);
        CHECK_NEAR(ax.x, axis.x, 1e-5);
        CHECK_NEAR(ax.y, axis.y, 1e-5);
        CHECK_NEAR(ax.z, axis.z, 1e-5);
    }
    // A zero axis is no rotation.
    mat4 none = mat4_rotate(v3(0, 0, 0), 45);
    check_identity(&none, 0);
}

static void test_normals(void) {
    // The plane x + y = 0 has normal (1,1,0)/sqrt2 and tangents (1,-1,0), (0,0,1). Scale x by 4: the tangent
    // becomes (4,-1,0) and the true normal is (1,4,0)/sqrt17, which M^-T gives (M itself would give (4,1,0)).
    mat4 s = mat4_scale(v3(4, 1, 1));
    transform t;
    CHECK(transform_make(&s, &t));
    vec3 n = v3_unit(mat4_apply_normal(&t.inv, v3(1, 1, 0)));
    vec3 tangent = mat4_apply_vector(&t.m, v3(1, -1, 0));
    CHECK_NEAR(v3_dot(n, tangent), 0.0, 1e-6);
    CHECK_NEAR(n.x, 1 / sqrt(17), 1e-6);
    CHECK_NEAR(n.y, 4 / sqrt(17), 1e-6);
    // The same for random affine maps and random tangent pairs.
    rng r = rng_for_sample(4, 4, 4);
    for (int k = 0; k < 100; k++) {
        mat4 m = random_affine(&r);
        CHECK(transform_make(&m, &t));
        vec3 u = v3(rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
        vec3 v = v3(rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
        vec3 nn = v3_unit(mat4_apply_normal(&t.inv, v3_cross(u, v)));
        CHECK_NEAR(v3_dot(nn, v3_unit(mat4_apply_vector(&m, u))), 0.0, 1e-4);
        CHECK_NEAR(v3_dot(nn, v3_unit(mat4_apply_vector(&m, v))), 0.0, 1e-4);
    }
}

static void test_compose(void) {
    // transform_compose(a, b) applies b first: rotate (1,0,0) to (0,1,0), then move by (5,0,0).
    mat4 rm = mat4_rotate(v3(0, 0, 1), 90), tm = mat4_translate(v3(5, 0, 0));
    transform rot, tr;
    CHECK(transform_make(&rm, &rot));
    CHECK(transform_make(&tm, &tr));
    transform both = transform_compose(&tr, &rot);
    vec3 p = mat4_apply_point(&both.m, v3(1, 0, 0));
    CHECK(p.x == 5.0f && p.y == 1.0f && p.z == 0.0f);
    vec3 back = mat4_apply_point(&both.inv, p);
    CHECK_NEAR(back.x, 1, 1e-6);
    CHECK_NEAR(back.y, 0, 1e-6);
    // Vectors ignore the translation.
    vec3 v = mat4_apply_vector(&both.m, v3(1, 0, 0));
    CHECK(v.x == 0.0f && v.y == 1.0f);
    transform id = transform_identity();
    transform same = transform_compose(&id, &both);
    CHECK(memcmp(&same, &both, sizeof same) == 0);
    mat4 tp = mat4_transpose(&tm);
    CHECK(tp.m[3][0] == 5.0f && tp.m[0][3] == 0.0f);
}

static void test_ray(void) {
    // A world ray taken to object space keeps its t: the hit point maps back to the same world point.
    rng r = rng_for_sample(6, 6, 6);
    for (int k = 0; k < 50; k++) {
        mat4 m = random_affine(&r);
        transform t;
        CHECK(transform_make(&m, &t));
        ray w = {v3(1, 2, 3), v3_unit(v3(-1, 0.5f, 0.25f)), 0.001f, 100.0f, 0.0f};
        ray o = mat4_apply_ray(&t.inv, &w);
        CHECK(o.tmin == w.tmin && o.tmax == w.tmax);
        vec3 world_hit = ray_at(&w, 7.5f), object_hit = ray_at(&o, 7.5f);
        vec3 again = mat4_apply_point(&t.m, object_hit);
        CHECK_NEAR(again.x, world_hit.x, 1e-3);
        CHECK_NEAR(again.y, world_hit.y, 1e-3);
        CHECK_NEAR(again.z, world_hit.z, 1e-3);
    }
}

static void test_bounds(void) {
    bounds3 b = {v3(-1, 0, 2), v3(3, 1, 5)};
    rng r = rng_for_sample(8, 8, 8);
    for (int k = 0; k < 100; k++) {
        mat4 m = random_affine(&r);
        bounds3 tb = mat4_apply_bounds(&m, b);
        // Holds every transformed corner, and is touched by them on every side (tight).
        bounds3 corners = bounds3_empty();
        for (int c = 0; c < 8; c++) {
            vec3 p = v3(c & 1 ? b.hi.x : b.lo.x, c & 2 ? b.hi.y : b.lo.y, c & 4 ? b.hi.z : b.lo.z);
            vec3 q = mat4_apply_point(&m, p);
            CHECK(q.x >= tb.lo.x && q.y >= tb.lo.y && q.z >= tb.lo.z);
            CHECK(q.x <= tb.hi.x && q.y <= tb.hi.y && q.z <= tb.hi.z);
            corners = bounds3_add(corners, q);
        }
        CHECK_NEAR(corners.lo.x, tb.lo.x, 1e-3);
        CHECK_NEAR(corners.hi.y, tb.hi.y, 1e-3);
        CHECK_NEAR(corners.hi.z, tb.hi.z, 1e-3);
    }
    CHECK(bounds3_is_empty(bounds3_empty()));
    mat4 m = mat4_translate(v3(1, 1, 1));
    CHECK(bounds3_is_empty(mat4_apply_bounds(&m, bounds3_empty())));
    bounds3 u = bounds3_union(bounds3_empty(), b);
    CHECK(memcmp(&u, &b, sizeof b) == 0);
}

static void test_mesh_transform(void) {
    vec3 pos[3] = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)};
    vec3 nrm[1] = {v3(0, 0, 1)};
    mesh m;
    memset(&m, 0, sizeof m);
    m.positions = pos;
    m.position_count = 3;
    m.normals = nrm;
    m.normal_count = 1;
    mesh_triangle tri = {{0, 1, 2}, -1};
    mesh_corners tri_normals = {{0, 0, 0}};
    m.triangles = &tri;
    m.normal_corners = &tri_normals;
    m.triangle_count = 1;
    // A mirror in z: the normal flips, and so must the winding, or the geometric normal would not follow.
    mat4 mirror = mat4_scale(v3(2, 1, -1));
    transform t;
    CHECK(transform_make(&mirror, &t));
    mesh_apply_transform(&m, &t);
    CHECK(nrm[0].z == -1.0f);
    CHECK(tri.v[1] == 2 && tri.v[2] == 1);
    tri_hit h = {1, 1.0f / 3, 1.0f / 3, 1.0f / 3};
    mesh_shading s = mesh_shade(&m, 0, &h);
    CHECK_NEAR(s.ng.z, -1.0, 0);
    CHECK(m.bounds.hi.x == 2.0f && m.bounds.lo.z == 0.0f);
}

// The linear determinant: the product of scale factors, with the sign of a mirror; translation does not count.
static void test_linear_det(void) {
    mat4 s = mat4_scale(v3(2, 3, 4)), t = mat4_translate(v3(10, -20, 30));
    CHECK(mat4_linear_det(&s) == 24.0);
    mat4 ts = mat4_mul(&t, &s);
    CHECK(mat4_linear_det(&ts) == 24.0);
    mat4 mirror = mat4_scale(v3(-1, 1, 1));
    CHECK(mat4_linear_det(&mirror) == -1.0);
    rng r = rng_for_sample(4, 5, 6);
    for (int k = 0; k < 100; k++) {
        // det(a b) = det(a) det(b), and a rotation's determinant is 1.
        mat4 a = random_affine(&r), b = random_affine(&r), ab = mat4_mul(&a, &b);
        double da = mat4_linear_det(&a), db = mat4_linear_det(&b);
        CHECK_NEAR(mat4_linear_det(&ab), da * db, 1e-4 * fabs(da * db));
        mat4 rot = mat4_rotate(v3(rng_range(&r, -1, 1), 1, rng_range(&r, -1, 1)), rng_range(&r, -360, 360));
        CHECK_NEAR(mat4_linear_det(&rot), 1.0, 1e-5);
    }
    mat4 flat = mat4_scale(v3(1, 0, 1));
    CHECK(mat4_linear_det(&flat) == 0.0);
}

// Similarities (rotation, mirror, uniform scale, any translation) are recognised with their scale; others not.
static void test_similarity_scale(void) {
    double s = 0;
    mat4 id = mat4_identity();
    CHECK(mat4_similarity_scale(&id, &s) && s == 1.0);
    mat4 rot = mat4_rotate(v3(1, 2, 3), 37), sc = mat4_scale(v3(-2.5f, 2.5f, 2.5f)), t = mat4_translate(v3(5, 6, 7));
    mat4 rs = mat4_mul(&rot, &sc), trs = mat4_mul(&t, &rs);
    CHECK(mat4_similarity_scale(&trs, &s));
    CHECK_NEAR(s, 2.5, 1e-6);
    mat4 stretch = mat4_scale(v3(1, 1, 1.01f));
    s = -1;
    CHECK(!mat4_similarity_scale(&stretch, &s));
    CHECK(s == -1); // untouched when false
    // A shear keeps column lengths equal but not orthogonal.
    mat4 shear = mat4_identity();
    shear.m[0][1] = 0.5f;
    shear.m[1][0] = 0.5f;
    CHECK(!mat4_similarity_scale(&shear, &s));
}

int main(void) {
    test_linear_det();
    test_similarity_scale();
    test_inverse();
    test_rotation();
    test_normals();
    test_compose();
    test_ray();
    test_bounds();
    test_mesh_transform();
    return check_summary();
}
