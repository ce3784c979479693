// test_sphere.c — ray–sphere intersection: the ordinary cases, open-interval bounds, negative radii, and
// the precision of large spheres far from the origin (against the same roots solved in double).
#include "check.h"
#include "geometry/sphere.h"

#include <stdbool.h>

static ray mkray(vec3 o, vec3 d) {
    ray r;
    r.o = o;
    r.d = d;
    r.tmin = 0.0f;
    r.tmax = INFINITY;
    return r;
}

// Nearest root in (tmin, inf) of |o + t d - c| = |r|, in double with the stable quadratic, for reference.
static bool reference_t(vec3 o, vec3 d, vec3 c, double radius, double tmin, double *t) {
    double f[3] = {(double)o.x - c.x, (double)o.y - c.y, (double)o.z - c.z};
    double dd[3] = {d.x, d.y, d.z};
    double a = dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2];
    double b = -(f[0] * dd[0] + f[1] * dd[1] + f[2] * dd[2]);
    double l[3], l2 = 0.0, f2 = 0.0;
    for (int i = 0; i < 3; i++) {
        l[i] = f[i] + dd[i] * (b / a);
        l2 += l[i] * l[i];
        f2 += f[i] * f[i];
    }
    double disc = radius * radius - l2;
    if (disc < 0.0) return false;
    double q = b + copysign(sqrt(a * disc), b);
    double t0 = (f2 - radius * radius) / q, t1 = q / a;
    if (t0 > t1) { double x = t0; t0 = t1; t1 = x; }
    if (t0 > tmin) { *t = t0; return true; }
    if (t1 > tmin) { *t = t1; return true; }
    return false;
}

static void test_outside_inside(void) {
    ray r = mkray(v3(0, 0, 0), v3(0, 0, 1));
    float t = -1.0f;
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 4.0, 0);
    // Unnormalised direction: t scales inversely.
    r.d = v3(0, 0, 2);
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 2.0, 1e-6);
    // From the centre, the ray leaves through the far side.
    r = mkray(v3(0, 0, 5), v3(0, 0.6f, 0.8f));
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 1.0, 1e-6);
    // From inside but off centre: the only root ahead.
    r = mkray(v3(0, 0, 4.5f), v3(0, 0, -1));
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 0.5, 1e-6);
}

static void test_tangent_and_miss(void) {
    float t = -1.0f;
    ray r = mkray(v3(1, 0, 0), v3(0, 0, 1)); // grazes the sphere at (1, 0, 5)
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 5.0, 1e-5);
    r.o = v3(1.001f, 0, 0);
    CHECK(!sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
    r = mkray(v3(0, 0, 0), v3(1, 0, 0));
    CHECK(!sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &t));
}

static void test_behind(void) {
    float t = -1.0f;
    ray r = mkray(v3(0, 0, 0), v3(0, 0, 1));
    CHECK(!sphere_intersect(v3(0, 0, -5), 1.0f, &r, r.tmin, r.tmax, &t));
    CHECK(!sphere_intersect(v3(0, 0, -5), -1.0f, &r, r.tmin, r.tmax, &t));
}

static void test_negative_radius(void) {
    ray r = mkray(v3(0, 0, 0), v3(0, 0, 1));
    float tp = -1.0f, tn = -2.0f;
    CHECK(sphere_intersect(v3(0, 0, 5), 1.0f, &r, r.tmin, r.tmax, &tp));
    CHECK(sphere_intersect(v3(0, 0, 5), -1.0f, &r, r.tmin, r.tmax, &tn));
    CHECK(tp == tn);
    sphere pos = {v3(0, 0, 5), 1.0f, 0}, neg = {v3(0, 0, 5), -1.0f, 0};
    vec3 p = ray_at(&r, tn); // (0, 0, 4)
    vec3 n_out = sphere_normal(&pos, p), n_in = sphere_normal(&neg, p);
    CHECK_NEAR(n_out.z, -1.0, 1e-6); // away from the centre
    CHECK_NEAR(n_in.z, 1.0, 1e-6);   // towards the centre
    CHECK_NEAR(v3_len(n_in), 1.0, 1e-6);
}

// Both ends of the interval are open: a root equal to tmin or tmax does not count.
static void test_bounds_exclusive(void) {
    ray r = mkray(v3(0, 0, 0), v3(0, 0, 1)); // roots exactly 4 and 6
    vec3 c = v3(0, 0, 5);
    float t = -1.0f;
    CHECK(sphere_intersect(c, 1.0f, &r, 4.0f, INFINITY, &t));
    CHECK_NEAR(t, 6.0, 0);
    CHECK(!sphere_intersect(c, 1.0f, &r, 0.0f, 4.0f, &t));
    CHECK(!sphere_intersect(c, 1.0f, &r, 4.0f, 6.0f, &t));
    CHECK(!sphere_intersect(c, 1.0f, &r, 6.0f, INFINITY, &t));
    CHECK(sphere_intersect(c, 1.0f, &r, 3.999f, 4.001f, &t));
    CHECK_NEAR(t, 4.0, 0);
    CHECK(sphere_intersect(c, 1.0f, &r, 5.999f, 6.001f, &t));
    CHECK_NEAR(t, 6.0, 0);
}

// The paper's ground: radius 5000 centred at (0, -5001, 0), its top one unit below the origin.
static void test_large_far_sphere(void) {
    vec3 c = v3(0, -5001, 0);
    const float radius = 5000.0f;
    vec3 origins[] = {v3(0, 0, 0), v3(0, 0, 0), v3(0.3f, 0.2f, 0.58f), v3(-40, 30, -200), v3(7, 0.5f, 3)};
    vec3 dirs[] = {v3(0, -1, 0), v3(0.1f, -0.3f, 0.58f), v3(-0.2f, -0.35f, 1), v3(0.3f, -0.15f, 1), v3(0, -1, 1)};
    for (size_t i = 0; i < sizeof origins / sizeof origins[0]; i++) {
        ray r = mkray(origins[i], dirs[i]);
        float t = -1.0f;
        double want = 0.0;
        CHECK(reference_t(r.o, r.d, c, radius, 0.0, &want));
        CHECK(sphere_intersect(c, radius, &r, r.tmin, r.tmax, &t));
        CHECK_NEAR(t / want, 1.0, 1e-3);
        // The hit point is on the sphere to within float resolution of its coordinates.
        vec3 p = ray_at(&r, t);
        double dx = (double)p.x - c.x, dy = (double)p.y - c.y, dz = (double)p.z - c.z;
        CHECK_NEAR(sqrt(dx * dx + dy * dy + dz * dz), radius, 2e-3);
    }
    // Straight down from the origin the ground is exactly one unit away.
    ray r = mkray(v3(0, 0, 0), v3(0, -1, 0));
    float t = -1.0f;
    CHECK(sphere_intersect(c, radius, &r, r.tmin, r.tmax, &t));
    CHECK_NEAR(t, 1.0, 1e-3);
}

// A radius-1000 ground and rays that start just above it, as shadow and reflected rays do. In float the
// origin's offset from the centre is only known to half an ulp of 1000 (3e-5), which bounds how well t can be
// known from very close to the surface: t must be right to 1e-4 relative plus that resolution along the
// ray, and the hit point must lie on the sphere to a few ulps.
static void test_ground_from_just_above(void) {
    vec3 c = v3(0, -1000, 0);
    const float radius = 1000.0f;
    const double ulp = 0x1.0p-14; // spacing of floats in [512, 1024)
    float t = -1.0f;
    // Leaving the surface upwards or sideways: no hit, even with tmin 0.
    ray up = mkray(v3(3, 1e-3f, 2), v3(0.2f, 1, 0.1f));
    CHECK(!sphere_intersect(c, radius, &up, 0.0f, INFINITY, &t));
    ray level = mkray(v3(0, 1e-3f, 0), v3(1, 0, 0));
    CHECK(!sphere_intersect(c, radius, &level, 0.0f, INFINITY, &t));
    // Going down at shallow and steep angles from heights 1e-3 .. 1, against the double-precision root.
    float heights[] = {1e-3f, 1e-2f, 0.1f, 1.0f};
    vec3 dirs[] = {v3(1, -0.01f, 0), v3(1, -0.1f, 0.5f), v3(0, -1, 0), v3(0.3f, -1, -0.2f)};
    for (size_t i = 0; i < sizeof heights / sizeof heights[0]; i++)
        for (size_t j = 0; j < sizeof dirs / sizeof dirs[0]; j++) {
            ray r = mkray(v3(2, heights[i], -1), dirs[j]);
            double want = 0.0;
            bool expect = reference_t(r.o, r.d, c, radius, 0.0, &want); // shallow rays from higher up miss
            bool hit = sphere_intersect(c, radius, &r, 0.0f, INFINITY, &t);
            CHECK(hit == expect);
            if (!hit || !expect) continue;
            CHECK_NEAR(t, want, 1e-4 * want + 2.0 * ulp / fabs((double)r.d.y));
            vec3 p = ray_at(&r, t);
            double dx = (double)p.x - c.x, dy = (double)p.y - c.y, dz = (double)p.z - c.z;
            CHECK_NEAR(sqrt(dx * dx + dy * dy + dz * dz), radius, 4.0 * ulp);
        }
    // Straight down from height h the ground is h away, to the float resolution at 1000.
    ray down = mkray(v3(0, 1e-3f, 0), v3(0, -1, 0));
    CHECK(sphere_intersect(c, radius, &down, 0.0f, INFINITY, &t));
    CHECK_NEAR(t, 1e-3, ulp);
    // A shadow ray spawned 1e-3 above the ground towards a light 5 units up and away is not blocked by it.
    ray shadow = mkray(v3(4, 1e-3f - 0.008f, 0), v3(3, 5, 1)); // the surface at x = 4 is 0.008 below y = 0
    CHECK(!sphere_intersect(c, radius, &shadow, 0.001f, 1.0f, &t));
}

int main(void) {
    test_outside_inside();
    test_tangent_and_miss();
    test_behind();
    test_negative_radius();
    test_bounds_exclusive();
    test_large_far_sphere();
    test_ground_from_just_above();
    return check_summary();
}
