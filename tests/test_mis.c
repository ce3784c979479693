// test_mis.c — multiple importance sampling at glossy vertices (the microfacet materials and the book's fuzzed
// metal): a small Cornell box whose view is filled by a rough gold sphere, or a fuzzed metal one, renders the same
// mean with light sampling alone, BSDF sampling alone and MIS (within their standard errors), and MIS is at least
// as good per sample as the worse of the two.
#include "check.h"
#include "glint.h"
#include "render/render.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>

typedef enum { MODE_MIS, MODE_BSDF, MODE_LIGHT } mis_mode;

static uint32_t add_material(glint_scene *s, material m) { return (uint32_t)scene_add_material(s, &m, NULL); }

static void add_quad(glint_scene *s, vec3 q, vec3 u, vec3 v, uint32_t mat) {
    quad qd;
    CHECK(quad_make(q, u, v, mat, &qd));
    CHECK(scene_add_quad(s, qd));
}

// "The Rest of Your Life"'s box at 12 x 12, looking at a sphere of material `ball` on the floor.
static glint_scene *ball_cornell(int spp, uint64_t seed, material ball) {
    glint_scene *s = scene_new("test");
    render_settings *rs = &s->settings;
    rs->width = rs->height = 12;
    rs->spp = spp;
    rs->max_depth = 6;
    rs->integrator = INTEGRATOR_PATH;
    rs->background = BACKGROUND_CONSTANT;
    rs->background_color = v3s(0.0f);
    rs->seed = seed;
    // Independent samples, as the tolerances below were set with: light sampling alone at the glossy gold sphere
    // is heavy-tailed, and the two renders' difference underestimates its noise for either sampler (over four pairs
    // of seeds its mean ranged 0.094-0.135 with independent samples, 0.099-0.116 with Sobol' points, which at
    // seeds 40 and 41 fall 6.6 of these sigmas from MIS's). The test is about the MIS weights, not the sampler.
    rs->sampler = SAMPLER_INDEPENDENT;
    s->camera.kind = CAMERA_LOOKAT;
    s->camera.lookfrom = v3(278, 278, -800);
    s->camera.lookat = v3(278, 120, 278);
    s->camera.vup = v3(0, 1, 0);
    s->camera.vfov_degrees = 12;
    material red = material_default(MAT_LAMBERTIAN), white = red, green = red, lamp = material_default(MAT_DIFFUSE_LIGHT);
    red.albedo = v3(0.65f, 0.05f, 0.05f);
    white.albedo = v3s(0.73f);
    green.albedo = v3(0.12f, 0.45f, 0.15f);
    lamp.emission = v3s(15.0f);
    uint32_t r = add_material(s, red), w = add_material(s, white), g = add_material(s, green), l = add_material(s, lamp);
    add_quad(s, v3(555, 0, 0), v3(0, 0, 555), v3(0, 555, 0), g);
    add_quad(s, v3(0, 0, 555), v3(0, 0, -555), v3(0, 555, 0), r);
    add_quad(s, v3(0, 555, 0), v3(555, 0, 0), v3(0, 0, 555), w);
    add_quad(s, v3(0, 0, 555), v3(555, 0, 0), v3(0, 0, -555), w);
    add_quad(s, v3(555, 0, 555), v3(-555, 0, 0), v3(0, 555, 0), w);
    add_quad(s, v3(213, 554, 227), v3(130, 0, 0), v3(0, 0, 105), l);
    sphere sp = {v3(278, 120, 278), 120, add_material(s, ball)};
    CHECK(scene_add_sphere(s, sp));
    return s;
}

// The mean over all pixels and channels of two renders with independent seeds, and its standard error from the
// pixels' differences.
static void mean_se(mis_mode mode, int spp, material ball, double *mean, double *se) {
    const float *px[2];
    glint_image *img[2];
    int w = 0, h = 0;
    for (int k = 0; k < 2; k++) {
        glint_scene *s = ball_cornell(spp, 40 + (uint64_t)k, ball);
        render_options opt = {.threads = 0,
                              .integrator = {.no_light_sampling = mode == MODE_BSDF, .light_sampling_only = mode == MODE_LIGHT}};
        glint_error err;
        render_stats stats;
        img[k] = NULL;
        CHECK(render_scene(s, &opt, NULL, NULL, &img[k], &stats, &err) == GLINT_OK);
        glint_image_info(img[k], &w, &h, &px[k]);
        glint_scene_free(s);
    }
    double sum = 0.0, diff2 = 0.0;
    for (int i = 0; i < w * h * 3; i++) {
        sum += (double)px[0][i] + px[1][i];
        diff2 += ((double)px[0][i] - px[1][i]) * ((double)px[0][i] - px[1][i]);
    }
    *mean = sum / (2.0 * w * h * 3);
    *se = sqrt(diff2) / (2.0 * w * h * 3);
    for (int k = 0; k < 2; k++) glint_image_free(img[k]);
}

// A fuzzed metal sphere (the book's, fuzz 0.6) lit by a point light of intensity 20, or by a small emissive sphere
// of the same intensity in its place (radiance 20 / (pi r^2)), on black: its mean radiance over a 24 x 24 view.
// (Below fuzz 1 the highlight has a ring of unbounded brightness, the edge of the metal's cone of directions, and
// both means have heavy tails: at fuzz 0.3 and this size they differ by 5 %, at 48 x 48 and 1,024 spp by 1 %.)
static double lit_metal_mean(bool point_light) {
    glint_scene *s = scene_new("test");
    render_settings *rs = &s->settings;
    rs->width = rs->height = 24;
    rs->spp = 256;
    rs->max_depth = 4;
    rs->integrator = INTEGRATOR_PATH;
    rs->background = BACKGROUND_CONSTANT;
    rs->background_color = v3s(0.0f);
    rs->seed = 7;
    s->camera.kind = CAMERA_LOOKAT;
    s->camera.lookfrom = v3(0, 0, 4);
    s->camera.lookat = v3(0, 0, 0);
    s->camera.vup = v3(0, 1, 0);
    s->camera.vfov_degrees = 30;
    material metal = material_default(MAT_METAL);
    metal.albedo = v3s(0.9f);
    metal.fuzz = 0.6f;
    CHECK(scene_add_sphere(s, (sphere){v3(0, 0, 0), 1.0f, add_material(s, metal)}));
    if (point_light) {
        light l = {.kind = LIGHT_POINT, .intensity = v3s(20.0f), .position = v3(2, 2, 4)};
        CHECK(scene_add_light(s, l));
    } else {
        material lamp = material_default(MAT_DIFFUSE_LIGHT);
        float r = 0.02f;
        lamp.emission = v3s(20.0f / (3.14159265f * r * r));
        CHECK(scene_add_sphere(s, (sphere){v3(2, 2, 4), r, add_material(s, lamp)}));
    }
    render_options opt = {.threads = 0};
    glint_error err;
    render_stats stats;
    glint_image *img = NULL;
    CHECK(render_scene(s, &opt, NULL, NULL, &img, &stats, &err) == GLINT_OK);
    int w = 0, h = 0;
    const float *px;
    glint_image_info(img, &w, &h, &px);
    double sum = 0.0;
    for (int i = 0; i < w * h * 3; i++) sum += px[i];
    glint_image_free(img);
    glint_scene_free(s);
    return sum / (w * h * 3);
}

// A point light is a delta: no random direction finds it, so only light sampling at the fuzzed metal shows its
// highlight (before the metal had a density, the sphere rendered black), and it is the highlight a small sphere of
// the same intensity gives.
static void test_point_light_on_fuzzed_metal(void) {
    double point = lit_metal_mean(true), small = lit_metal_mean(false);
    printf("fuzzed metal sphere under a point light: mean %.5f; under a small sphere light of its intensity: %.5f\n",
           point, small);
    CHECK(point > 0.01);
    CHECK_NEAR(point, small, 0.03 * small);
}

int main(void) {
    material balls[4];
    char names_ball[4][64];
    static const float roughs[] = {0.15f, 0.5f}, fuzzes[] = {0.3f, 1.0f};
    for (int j = 0; j < 2; j++) {
        balls[j] = material_default(MAT_CONDUCTOR);
        CHECK(material_conductor_preset("Au", &balls[j].eta, &balls[j].k));
        balls[j].roughness = roughs[j];
        snprintf(names_ball[j], sizeof names_ball[j], "rough gold sphere (roughness %.2f)", (double)roughs[j]);
        // The book's metal: its sampling's own density (mat_metal_pdf) is what MIS weighs light samples against.
        balls[2 + j] = material_default(MAT_METAL);
        balls[2 + j].albedo = v3(0.8f, 0.6f, 0.2f);
        balls[2 + j].fuzz = fuzzes[j];
        snprintf(names_ball[2 + j], sizeof names_ball[2 + j], "the book's metal sphere (fuzz %.2f)", (double)fuzzes[j]);
    }
    for (int j = 0; j < 4; j++) {
        double m[3], se[3];
        static const int spp[3] = {64, 1024, 256};
        static const char *const names[3] = {"MIS", "BSDF sampling only", "light sampling only"};
        printf("%s in a Cornell box, mean radiance:\n", names_ball[j]);
        for (int k = 0; k < 3; k++) {
            mean_se((mis_mode)k, spp[k], balls[j], &m[k], &se[k]);
            printf("  %-22s %4d spp: %.5f +- %.5f (per-sample noise %.4f)\n", names[k], spp[k], m[k], se[k],
                   se[k] * sqrt((double)spp[k]));
        }
        for (int k = 1; k < 3; k++) CHECK_NEAR(m[k], m[0], 4.0 * sqrt(se[k] * se[k] + se[0] * se[0]));
        CHECK(se[0] < 0.03 * m[0]);
        // MIS is at least as good per sample as the worse of the two strategies alone.
        CHECK(se[0] * sqrt(64.0) <= fmax(se[1] * sqrt(1024.0), se[2] * sqrt(256.0)) * 1.1);
        // And light sampling pays: the lamp is small, BSDF sampling alone finds it seldom (were the sphere not
        // lit by light sampling, MIS would be BSDF sampling, as noisy a sample).
        CHECK(se[0] * sqrt(64.0) < 0.75 * se[1] * sqrt(1024.0));
    }
    test_point_light_on_fuzzed_metal();
    return check_summary();
}
