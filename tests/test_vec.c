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

// f_min/f_max agree with fminf/fmaxf, NaN operands included (a NaN yields the other operand).
static void test_min_max(void) {
    const float vals[] = {-2.0f, -0.5f, 0.0f, 1.0f, 3.5f, INFINITY, -INFINITY, NAN};
    int n = (int)(sizeof vals / sizeof vals[0]), bad = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            float a = vals[i], b = vals[j], lo = f_min(a, b), hi = f_max(a, b), flo = fminf(a, b), fhi = fmaxf(a, b);
            if (!(lo == flo || (isnan(lo) && isnan(flo))) || !(hi == fhi || (isnan(hi) && isnan(fhi)))) bad++;
        }
    CHECK(bad == 0);
    vec3 m = v3_max(v3(1, NAN, -3), v3(NAN, 2, -4));
    CHECK(m.x == 1 && m.y == 2 && m.z == -3);
    CHECK(v3_max_comp(v3(-1, 5, 2)) == 5 && v3_max_comp(v3(NAN, -1, -2)) == -1);
}

int main(void) {
    test_min_max();
    test_basic_ops();
    test_reflect();
    test_refract();
    test_schlick();
    test_basis();
    return check_summary();
}
