// test_vec.c — vector maths, reflection and refraction directions.
#include "check.h"
#include "core/vec.h"

static void test_basic_ops(void) {
    vec3 a = v3(1, 2, 3), b = v3(4, -5, 6);
    CHECK_NEAR(v3_dot(a, b), 12.0, 0);
    vec3 c = v3_cross(a, b);
    CHECK_NEAR(c.x, 27.0, 0);
    CHECK_NEAR(c.y, 6.0, 0);
    CHECK_NEAR(c.z, -13.0, 0);
    CHECK_NEAR(v3_dot(c, a), 0.0, 1e-5);
    CHECK_NEAR(v3_len(v3_unit(b)), 1.0, 1e-6);
    vec3 f = v3_fma(a, b, 2.0f);
    CHECK_NEAR(f.x, 9.0, 0);
    CHECK_NEAR(f.y, -8.0, 0);
    CHECK_NEAR(f.z, 15.0, 0);
}

static void test_reflect(void) {
    vec3 r = v3_reflect(v3_unit(v3(1, -1, 0)), v3(0, 1, 0));
    CHECK_NEAR(r.x, sqrt(0.5), 1e-6);
    CHECK_NEAR(r.y, sqrt(0.5), 1e-6);
    CHECK_NEAR(r.z, 0.0, 0);
}

static void test_refract(void) {
    // 45 degrees into glass (eta = 1/1.5): sin(theta_t) = sin(45)/1.5 (Snell).
    vec3 in = v3_unit(v3(1, -1, 0));
    vec3 t = v3_refract(in, v3(0, 1, 0), 1.0f / 1.5f);
    CHECK_NEAR(v3_len(t), 1.0, 1e-6);
    CHECK_NEAR(t.x, sqrt(0.5) / 1.5, 1e-6);
    CHECK(t.y < 0.0f);
    // Normal incidence passes straight through.
    vec3 s = v3_refract(v3(0, -1, 0), v3(0, 1, 0), 1.0f / 1.5f);
    CHECK_NEAR(s.x, 0.0, 1e-7);
    CHECK_NEAR(s.y, -1.0, 1e-7);
}

static void test_schlick(void) {
    CHECK_NEAR(schlick_reflectance(1.0f, 1.5f), 0.04, 1e-6); // ((1-1.5)/(1+1.5))^2
    CHECK_NEAR(schlick_reflectance(0.0f, 1.5f), 1.0, 1e-6);
}

static void test_basis(void) {
    vec3 ns[] = {v3(0, 0, 1), v3(0, 0, -1), v3_unit(v3(1, 2, 3)), v3(1, 0, 0)};
    for (int i = 0; i < 4; i++) {
        vec3 t, b;
        v3_basis(ns[i], &t, &b);
        CHECK_NEAR(v3_dot(t, ns[i]), 0.0, 1e-6);
        CHECK_NEAR(v3_dot(b, ns[i]), 0.0, 1e-6);
        CHECK_NEAR(v3_dot(t, b), 0.0, 1e-6);
        CHECK_NEAR(v3_len(t), 1.0, 1e-6);
    }
}

int main(void) {
    test_basic_ops();
    test_reflect();
    test_refract();
    test_schlick();
    test_basis();
    return check_summary();
}
