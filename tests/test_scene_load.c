// test_scene_load.c — good scene files parse to the expected scene structs: defaults, named and inline
// materials, both cameras, every light kind, number-or-RGB colours, key order, encodings.
#include "check.h"
#include "glint.h"
#include "scene/scene.h"

#include <string.h>

#define CHECK_VEC(v, X, Y, Z)             \
    do {                                  \
        CHECK_NEAR((v).x, (X), 1e-6);     \
        CHECK_NEAR((v).y, (Y), 1e-6);     \
        CHECK_NEAR((v).z, (Z), 1e-6);     \
    } while (0)

// Parses text that must be valid; prints the message otherwise.
static glint_scene *parse(const char *text) {
    glint_scene *s = NULL;
    glint_error err = {{0}};
    glint_status st = glint_scene_parse("good.json", text, strlen(text), &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "  unexpected error: %s\n", err.message);
    return st == GLINT_OK ? s : NULL;
}

static void test_defaults(void) {
    glint_scene *s = parse("{}");
    if (!s) return;
    const render_settings *rs = &s->settings;
    CHECK(rs->width == 400 && rs->height == 225);
    CHECK(rs->spp == 1);
    CHECK(rs->max_depth == 3);
    CHECK(rs->seed == 0);
    CHECK(rs->integrator == INTEGRATOR_WHITTED && rs->whitted_mode == WHITTED_COLOR);
    CHECK(rs->background == BACKGROUND_CONSTANT);
    CHECK_VEC(rs->background_color, 0, 0, 0);
    CHECK(rs->transform == TRANSFORM_LINEAR);
    CHECK(rs->accel == ACCEL_BVH);
    CHECK(s->camera.kind == CAMERA_LOOKAT);
    CHECK_VEC(s->camera.lookfrom, 0, 0, 0);
    CHECK_VEC(s->camera.lookat, 0, 0, -1);
    CHECK_VEC(s->camera.vup, 0, 1, 0);
    CHECK_NEAR(s->camera.vfov_degrees, 90, 0);
    CHECK(s->material_count == 0 && s->sphere_count == 0 && s->light_count == 0);
    CHECK(strcmp(s->path, "good.json") == 0);
    glint_scene_free(s);

    // Empty sections are fine too.
    s = parse("{\"render\": {}, \"materials\": {}, \"objects\": [], \"lights\": []}");
    if (s) CHECK(s->settings.width == 400 && s->sphere_count == 0);
    glint_scene_free(s);
}

static void test_render_settings(void) {
    glint_scene *s = parse("{\"render\": {\"width\": 768, \"height\": 1e2, \"spp\": 16, \"seed\": 9007199254740992,"
                           " \"integrator\": \"path\", \"background\": 0.25, \"output\": \"srgb\", "
                           "\"accel\": \"none\"}}");
    if (s) {
        const render_settings *rs = &s->settings;
        CHECK(rs->width == 768);
        CHECK(rs->height == 100); // 1e2 is an integral number
        CHECK(rs->spp == 16);
        CHECK(rs->seed == 9007199254740992ULL);
        CHECK(rs->integrator == INTEGRATOR_PATH);
        CHECK(rs->max_depth == 50); // the path tracer's default
        CHECK(rs->background == BACKGROUND_CONSTANT);
        CHECK_VEC(rs->background_color, 0.25, 0.25, 0.25);
        CHECK(rs->transform == TRANSFORM_SRGB);
        CHECK(rs->accel == ACCEL_NONE);
    }
    glint_scene_free(s);

    s = parse("{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"paper\"}, \"background\": [1, 0.5, 0],"
              " \"output\": \"gamma2\", \"accel\": \"bvh2\"}}");
    if (s) {
        CHECK(s->settings.integrator == INTEGRATOR_WHITTED && s->settings.whitted_mode == WHITTED_PAPER);
        CHECK(s->settings.max_depth == 3);
        CHECK_VEC(s->settings.background_color, 1, 0.5, 0);
        CHECK(s->settings.transform == TRANSFORM_GAMMA2);
        CHECK(s->settings.accel == ACCEL_BVH2);
    }
    glint_scene_free(s);

    // An explicit depth wins over the integrator's default; 0 is allowed (direct hits only).
    s = parse("{\"render\": {\"integrator\": {\"type\": \"path\"}, \"max_depth\": 0, \"background\": \"sky\"}}");
    if (s) {
        CHECK(s->settings.integrator == INTEGRATOR_PATH && s->settings.max_depth == 0);
        CHECK(s->settings.background == BACKGROUND_SKY);
        CHECK_VEC(s->settings.sky_horizon, 1, 1, 1);
        CHECK_VEC(s->settings.sky_zenith, 0.5, 0.7, 1);
    }
    glint_scene_free(s);

    s = parse("{\"render\": {\"background\": {\"type\": \"sky\", \"horizon\": [0.9, 0.8, 0.7], \"zenith\": 2}}}");
    if (s) {
        CHECK(s->settings.background == BACKGROUND_SKY);
        CHECK_VEC(s->settings.sky_horizon, 0.9, 0.8, 0.7);
        CHECK_VEC(s->settings.sky_zenith, 2, 2, 2);
    }
    glint_scene_free(s);

    s = parse("{\"render\": {\"background\": {\"type\": \"constant\", \"color\": [0, 0, 3]}, \"width\": 16384, "
              "\"height\": 1,"
              " \"spp\": 1000000, \"max_depth\": 10000}}");
    if (s) {
        CHECK(s->settings.background == BACKGROUND_CONSTANT);
        CHECK_VEC(s->settings.background_color, 0, 0, 3);
        CHECK(s->settings.width == 16384 && s->settings.height == 1);
        CHECK(s->settings.spp == 1000000 && s->settings.max_depth == 10000);
    }
    glint_scene_free(s);
}

static void test_materials(void) {
    glint_scene *s = parse(
        "{\"materials\": {\n"
        "  \"red\": {\"type\": \"phong\", \"color\": [1, 0, 0], \"specular\": 9900, \"reflective\": 0.2},\n"
        "  \"shiny\": {\"type\": \"phong\", \"color\": 0.5, \"specular_color\": [1, 1, 1]},\n"
        "  \"plain\": {\"type\": \"phong\"},\n"
        "  \"ground\": {\"type\": \"lambertian\", \"albedo\": [0.5, 0.5, 0.5]},\n"
        "  \"steel\": {\"type\": \"metal\", \"albedo\": [0.7, 0.6, 0.5], \"fuzz\": 0.3},\n"
        "  \"glass\": {\"type\": \"dielectric\", \"ior\": 1.33, \"tint\": [0.9, 1, 0.9]},\n"
        "  \"clear\": {\"type\": \"dielectric\"},\n"
        "  \"lamp\": {\"type\": \"diffuse_light\", \"emission\": 15, \"two_sided\": true},\n"
        "  \"caf\\u00e9\": {\"type\": \"lambertian\"}\n"
        "},\n"
        "\"objects\": [\n"
        "  {\"type\": \"sphere\", \"center\": [0, -1, 3], \"radius\": 1, \"material\": \"red\"},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 1, 0], \"radius\": 0.5,\n"
        "   \"material\": {\"type\": \"lambertian\", \"albedo\": [0.4, 0.2, 0.1]}},\n"
        "  {\"type\": \"sphere\", \"center\": [1, 2, 3], \"radius\": -0.4, \"material\": \"caf\xc3\xa9\"},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 2, \"material\": \"glass\"}\n"
        "]}");
    if (!s) return;
    CHECK(s->material_count == 10); // nine named, one inline
    long red = scene_find_material(s, "red"), glass = scene_find_material(s, "glass");
    CHECK(red == 0);
    const material *m = &s->materials[0];
    CHECK(m->kind == MAT_PHONG);
    CHECK_VEC(m->albedo, 1, 0, 0);
    CHECK(m->specular == 9900);
    CHECK_NEAR(m->reflective, 0.2, 1e-7);
    CHECK(!m->has_specular_color);
    m = &s->materials[1];
    CHECK(m->kind == MAT_PHONG && m->has_specular_color);
    CHECK_VEC(m->albedo, 0.5, 0.5, 0.5);
    CHECK_VEC(m->specular_color, 1, 1, 1);
    m = &s->materials[2]; // every parameter at material_default's value
    material def = material_default(MAT_PHONG);
    CHECK(m->specular == def.specular && m->reflective == def.reflective);
    CHECK_VEC(m->albedo, def.albedo.x, def.albedo.y, def.albedo.z);
    m = &s->materials[3];
    CHECK(m->kind == MAT_LAMBERTIAN);
    CHECK_VEC(m->albedo, 0.5, 0.5, 0.5);
    m = &s->materials[4];
    CHECK(m->kind == MAT_METAL);
    CHECK_VEC(m->albedo, 0.7, 0.6, 0.5);
    CHECK_NEAR(m->fuzz, 0.3, 1e-7);
    m = &s->materials[glass];
    CHECK(m->kind == MAT_DIELECTRIC);
    CHECK_NEAR(m->ior, 1.33, 1e-6);
    CHECK_VEC(m->albedo, 0.9, 1, 0.9);
    m = &s->materials[6];
    CHECK(m->kind == MAT_DIELECTRIC);
    CHECK_NEAR(m->ior, 1.5, 1e-7);
    CHECK_VEC(m->albedo, 1, 1, 1); // clear glass
    m = &s->materials[7];
    CHECK(m->kind == MAT_DIFFUSE_LIGHT && m->two_sided);
    CHECK_VEC(m->emission, 15, 15, 15);
    CHECK(scene_find_material(s, "caf\xc3\xa9") == 8); // "\u00e9" is unescaped to UTF-8

    CHECK(s->sphere_count == 4);
    CHECK(s->spheres[0].material == 0);
    CHECK_VEC(s->spheres[0].center, 0, -1, 3);
    CHECK_NEAR(s->spheres[0].radius, 1, 0);
    // The inline material is appended, anonymous, after the named ones.
    CHECK(s->spheres[1].material == 9);
    CHECK(s->material_names[9] == NULL);
    CHECK(s->materials[9].kind == MAT_LAMBERTIAN);
    CHECK_VEC(s->materials[9].albedo, 0.4, 0.2, 0.1);
    CHECK_NEAR(s->spheres[2].radius, -0.4, 1e-7); // negative: a hollow shell
    CHECK(s->spheres[2].material == 8);
    CHECK(s->spheres[3].material == (uint32_t)glass);
    glint_scene_free(s);
}

static void test_cameras(void) {
    // The paper's camera.
    glint_scene *s = parse("{\"camera\": {\"type\": \"viewport\", \"position\": [0, 0, 0], \"viewport\": [1, "
                           "1], \"distance\": 0.58}}");
    if (s) {
        const camera *c = &s->camera;
        CHECK(c->kind == CAMERA_VIEWPORT);
        CHECK(c->position[0] == 0 && c->position[1] == 0 && c->position[2] == 0);
        CHECK(c->viewport_width == 1 && c->viewport_height == 1);
        CHECK(c->distance == 0.58); // kept in double: the paper's image is reproduced exactly
    }
    glint_scene_free(s);

    s = parse("{\"camera\": {\"type\": \"viewport\"}}");
    if (s) {
        const camera *c = &s->camera;
        CHECK(c->kind == CAMERA_VIEWPORT);
        CHECK(c->position[2] == 0 && c->viewport_width == 1 && c->viewport_height == 1 && c->distance == 1);
    }
    glint_scene_free(s);

    s = parse("{\"camera\": {\"type\": \"viewport\", \"position\": [1, 2, -3], \"viewport\": [1.6, 0.9], "
              "\"distance\": 2}}");
    if (s) {
        const camera *c = &s->camera;
        CHECK(c->position[0] == 1 && c->position[1] == 2 && c->position[2] == -3);
        CHECK(c->viewport_width == 1.6 && c->viewport_height == 0.9);
        CHECK(c->distance == 2);
    }
    glint_scene_free(s);

    // The book's final camera.
    s = parse("{\"camera\": {\"type\": \"lookat\", \"lookfrom\": [13, 2, 3], \"lookat\": [0, 0, 0], \"vup\": [0, 1, 0],"
              " \"vfov\": 20, \"defocus_angle\": 0.6, \"focus_distance\": 10}}");
    if (s) {
        const camera *c = &s->camera;
        CHECK(c->kind == CAMERA_LOOKAT);
        CHECK_VEC(c->lookfrom, 13, 2, 3);
        CHECK_VEC(c->lookat, 0, 0, 0);
        CHECK_VEC(c->vup, 0, 1, 0);
        CHECK_NEAR(c->vfov_degrees, 20, 0);
        CHECK_NEAR(c->defocus_angle_degrees, 0.6, 1e-7);
        CHECK_NEAR(c->focus_distance, 10, 0);
    }
    glint_scene_free(s);

    // The blog's camera looks along +z with +y down.
    s = parse("{\"camera\": {\"type\": \"lookat\", \"lookat\": [0, 0, 1], \"vup\": [0, -1, 0]}}");
    if (s) {
        CHECK_VEC(s->camera.lookfrom, 0, 0, 0);
        CHECK_VEC(s->camera.lookat, 0, 0, 1);
        CHECK_VEC(s->camera.vup, 0, -1, 0);
        CHECK_NEAR(s->camera.vfov_degrees, 90, 0);
        CHECK(s->camera.defocus_angle_degrees == 0 && s->camera.focus_distance == 0);
    }
    glint_scene_free(s);
}

static void test_lights(void) {
    glint_scene *s = parse("{\"lights\": [\n"
                           "  {\"type\": \"ambient\", \"intensity\": 0.2},\n"
                           "  {\"type\": \"point\", \"intensity\": [0.6, 0.5, 0.4], \"position\": [2, 1, 0]},\n"
                           "  {\"type\": \"directional\", \"intensity\": 0.2, \"direction\": [1, 4, 4]},\n"
                           "  {\"type\": \"point\", \"intensity\": 100, \"position\": [-1, 0.5, 1e3]}\n"
                           "]}");
    if (!s) return;
    CHECK(s->light_count == 4);
    CHECK(s->lights[0].kind == LIGHT_AMBIENT);
    CHECK_VEC(s->lights[0].intensity, 0.2, 0.2, 0.2);
    CHECK(s->lights[1].kind == LIGHT_POINT);
    CHECK_VEC(s->lights[1].intensity, 0.6, 0.5, 0.4);
    CHECK_VEC(s->lights[1].position, 2, 1, 0);
    CHECK(s->lights[2].kind == LIGHT_DIRECTIONAL);
    CHECK_VEC(s->lights[2].intensity, 0.2, 0.2, 0.2);
    CHECK_VEC(s->lights[2].direction, 1, 4, 4); // not normalised, as in the paper
    CHECK_VEC(s->lights[3].intensity, 100, 100, 100);
    CHECK_VEC(s->lights[3].position, -1, 0.5, 1000);
    glint_scene_free(s);
}

// Key order is free (objects may come before the materials they use); CRLF, a byte-order mark and
// escaped keys are all plain JSON.
static void test_encoding_and_order(void) {
    glint_scene *s = parse("\xEF\xBB\xBF{\r\n"
                           "  \"objects\": [{\"material\": \"m\", \"radius\": 2, \"center\": [1, 2, 3], "
                           "\"type\": \"sphere\"}],\r\n"
                           "  \"materials\": {\"m\": {\"albedo\": 0.25, \"type\": \"lambertian\"}},\r\n"
                           "  \"rend\\u0065r\": {\"wi\\u0064th\": 32}\r\n"
                           "}\r\n");
    if (!s) return;
    CHECK(s->sphere_count == 1 && s->spheres[0].material == 0);
    CHECK_VEC(s->materials[0].albedo, 0.25, 0.25, 0.25);
    CHECK(s->settings.width == 32);
    glint_scene_free(s);
}

// The paper's scene file, as the README renders it.
static void test_paper_file(void) {
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_load(GLINT_SOURCE_DIR "/scenes/paper.json", &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return;
    }
    CHECK(s->settings.width == 768 && s->settings.height == 768);
    CHECK(s->settings.integrator == INTEGRATOR_WHITTED && s->settings.whitted_mode == WHITTED_PAPER);
    CHECK(s->camera.kind == CAMERA_VIEWPORT);
    CHECK_NEAR(s->camera.distance, 0.58, 1e-12);
    CHECK(s->sphere_count == 4 && s->light_count == 3);
    if (s->sphere_count == 4) {
        CHECK_VEC(s->spheres[3].center, 0, -5001, 0);
        CHECK_NEAR(s->spheres[3].radius, 5000, 0);
        CHECK(s->materials[s->spheres[0].material].specular == 9900);
    }
    glint_scene_free(s);
}

int main(void) {
    test_defaults();
    test_render_settings();
    test_materials();
    test_cameras();
    test_lights();
    test_encoding_and_order();
    test_paper_file();
    return check_summary();
}
