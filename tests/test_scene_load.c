// test_scene_load.c — good scene files parse to the expected scene structs: defaults, named and inline
// materials, both cameras, every light kind, number-or-RGB colours, key order, encodings; textures, quads,
// boxes, transforms (order, baking, instances), meshes (loaded once, MTL materials) and the issue-5 scenes.
#include "check.h"
#include "glint.h"
#include "obj_same.h"
#include "scene/scene.h"
#include "test_util.h"

#include <math.h>
#include <stdbool.h>
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
    CHECK(rs->transform == TRANSFORM_SRGB); // 8-bit output is sRGB unless the file says otherwise
    CHECK(rs->accel == ACCEL_BVH);
    CHECK(!rs->no_presplit); // pre-splitting is on unless the file turns it off
    CHECK(!rs->no_spatial);  // so are spatial splits
    CHECK(s->camera.kind == CAMERA_LOOKAT);
    CHECK_VEC(s->camera.lookfrom, 0, 0, 0);
    CHECK_VEC(s->camera.lookat, 0, 0, -1);
    CHECK_VEC(s->camera.vup, 0, 1, 0);
    CHECK_NEAR(s->camera.vfov_degrees, 90, 0);
    CHECK(s->material_count == 0 && s->sphere_count == 0 && s->light_count == 0);
    CHECK(strcmp(s->path, "good.json") == 0);
    glint_scene_free(s);
    // The default encoding: sRGB for the path tracer too, linear in paper mode (the paper's program wrote its
    // values as they are); what the file says wins, and so does an override.
    s = parse("{\"render\": {\"integrator\": \"path\"}}");
    CHECK(s && s->settings.transform == TRANSFORM_SRGB);
    glint_scene_free(s);
    s = parse("{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"paper\"}}}");
    CHECK(s && s->settings.transform == TRANSFORM_LINEAR);
    glint_scene_free(s);
    s = parse("{\"render\": {\"output\": \"gamma2\"}}");
    CHECK(s && s->settings.transform == TRANSFORM_GAMMA2);
    if (s) {
        glint_overrides o;
        glint_overrides_init(&o);
        o.output_encoding = "linear";
        glint_error err;
        CHECK(glint_scene_override(s, &o, &err) == GLINT_OK && s->settings.transform == TRANSFORM_LINEAR);
        o.output_encoding = "gamma";
        CHECK(glint_scene_override(s, &o, &err) == GLINT_ERR_INPUT);
        CHECK(strcmp(err.message, "--output-encoding: unknown encoding 'gamma', expected linear, gamma2 or srgb") == 0);
        CHECK(s->settings.transform == TRANSFORM_LINEAR); // a refused override changes nothing
    }
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
              " \"output\": \"gamma2\", \"accel\": \"bvh2\", \"presplit\": false, \"spatial_splits\": false}}");
    if (s) {
        CHECK(s->settings.no_presplit);
        CHECK(s->settings.no_spatial);
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

// Loads scenes/<name>, checking that it loads; NULL (and the message printed) when it does not.
static glint_scene *load_scene_file(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", GLINT_SOURCE_DIR, name);
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_load(path, &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "  %s\n", err.message);
    return s;
}

// The paper's scene file, as the README renders it.
static void test_paper_file(void) {
    glint_scene *s = load_scene_file("paper.json");
    if (!s) return;
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

// Parses text as a file in scenes/, so that relative paths resolve to the repository's meshes and images.
static glint_scene *parse_in_scenes(const char *text) {
    glint_scene *s = NULL;
    glint_error err = {{0}};
    glint_status st = glint_scene_parse(GLINT_SOURCE_DIR "/scenes/inline.json", text, strlen(text), &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "  unexpected error: %s\n", err.message);
    return st == GLINT_OK ? s : NULL;
}

// Index of the material with this name, or -1 (names of OBJ materials may repeat: the first counts).
static long material_named(const glint_scene *s, const char *name) { return scene_find_material(s, name); }

static void test_textures(void) {
    glint_scene *s = parse_in_scenes(
        "{\"textures\": {\n"
        "  \"tiles\": {\"type\": \"checker\", \"scale\": 0.32, \"even\": [0.2, 0.3, 0.1], \"odd\": 0.9},\n"
        "  \"plain\": {\"type\": \"checker\"},\n"
        "  \"n\": {\"type\": \"noise\", \"scale\": 4},\n"
        "  \"t\": {\"type\": \"turbulence\", \"scale\": 2, \"depth\": 5, \"color\": [1, 0.5, 0.25], \"seed\": 7},\n"
        "  \"marble\": {\"type\": \"marble\", \"scale\": 4, \"depth\": 7},\n"
        "  \"red\": {\"type\": \"solid\", \"color\": [1, 0, 0]},\n"
        "  \"hot\": {\"type\": \"solid\", \"color\": 4},\n"
        "  \"spot\": {\"type\": \"image\", \"file\": \"meshes/spot/spot_texture.png\"},\n"
        "  \"spot2\": {\"type\": \"image\", \"file\": \"meshes/spot/../spot/spot_texture.png\"}\n"
        "},\n"
        "\"materials\": {\n"
        "  \"ground\": {\"type\": \"lambertian\", \"albedo\": \"tiles\"},\n"
        "  \"steel\": {\"type\": \"metal\", \"albedo\": \"red\", \"fuzz\": 0.1},\n"
        "  \"glass\": {\"type\": \"dielectric\", \"tint\": {\"type\": \"solid\", \"color\": [0.9, 1, 0.9]}},\n"
        "  \"shiny\": {\"type\": \"phong\", \"color\": \"marble\"},\n"
        "  \"lamp\": {\"type\": \"diffuse_light\", \"emission\": \"hot\"},\n"
        "  \"plainlamp\": {\"type\": \"diffuse_light\", \"emission\": [1, 2, 3]},\n"
        "  \"cow\": {\"type\": \"lambertian\", \"albedo\": {\"type\": \"image\", \"file\": "
        "\"meshes/spot/spot_texture.png\"}},\n"
        "  \"cow2\": {\"type\": \"lambertian\", \"albedo\": \"spot2\"},\n"
        "  \"grey\": {\"type\": \"lambertian\", \"albedo\": 0.5}\n"
        "}}");
    if (!s) return;
    // One image file, three references (two names, one inline): decoded once.
    CHECK(s->texture_count == 9);
    CHECK(scene_find_texture(s, "tiles") == 0 && scene_find_texture(s, "spot") == 7);
    const texture *t = &s->textures[0];
    CHECK(t->kind == TEX_CHECKER);
    CHECK_NEAR(t->scale, 0.32, 1e-7);
    CHECK_VEC(t->even, 0.2, 0.3, 0.1);
    CHECK_VEC(t->odd, 0.9, 0.9, 0.9);
    t = &s->textures[1]; // the defaults
    CHECK(t->kind == TEX_CHECKER && t->scale == 1.0f);
    CHECK_VEC(t->even, 1, 1, 1);
    CHECK_VEC(t->odd, 0, 0, 0);
    t = &s->textures[2];
    CHECK(t->kind == TEX_NOISE && t->noise == NOISE_PLAIN && t->scale == 4.0f && t->perlin != NULL);
    CHECK_VEC(t->color, 1, 1, 1);
    t = &s->textures[3];
    CHECK(t->kind == TEX_NOISE && t->noise == NOISE_TURBULENCE && t->scale == 2.0f && t->depth == 5);
    CHECK_VEC(t->color, 1, 0.5, 0.25);
    // A different seed, different tables.
    CHECK(s->textures[2].perlin && t->perlin && memcmp(s->textures[2].perlin, t->perlin, sizeof *t->perlin) != 0);
    t = &s->textures[4];
    CHECK(t->kind == TEX_NOISE && t->noise == NOISE_MARBLE && t->depth == 7);
    CHECK(s->textures[5].kind == TEX_SOLID);
    CHECK_VEC(s->textures[5].color, 1, 0, 0);
    CHECK_VEC(s->textures[6].color, 4, 4, 4);
    t = &s->textures[7];
    CHECK(t->kind == TEX_IMAGE && t->image.width == 1024 && t->image.height == 1024 && t->image.pixels != NULL);
    CHECK(s->textures[8].kind == TEX_SOLID && s->texture_names[8] == NULL);
    CHECK_VEC(s->textures[8].color, 0.9, 1, 0.9);

    const material *m = &s->materials[material_named(s, "ground")];
    CHECK(m->kind == MAT_LAMBERTIAN && m->albedo_texture == 0);
    m = &s->materials[material_named(s, "steel")];
    CHECK(m->kind == MAT_METAL && m->albedo_texture == 5 && m->emission_texture == -1);
    m = &s->materials[material_named(s, "glass")];
    CHECK(m->kind == MAT_DIELECTRIC && m->albedo_texture == 8);
    m = &s->materials[material_named(s, "shiny")];
    CHECK(m->kind == MAT_PHONG && m->albedo_texture == 4);
    // An emission texture gives the radiance: the scalar emission stays 1.
    m = &s->materials[material_named(s, "lamp")];
    CHECK(m->kind == MAT_DIFFUSE_LIGHT && m->emission_texture == 6 && m->albedo_texture == -1);
    CHECK_VEC(m->emission, 1, 1, 1);
    m = &s->materials[material_named(s, "plainlamp")];
    CHECK(m->emission_texture == -1);
    CHECK_VEC(m->emission, 1, 2, 3);
    CHECK(s->materials[material_named(s, "cow")].albedo_texture == 7);
    CHECK(s->materials[material_named(s, "cow2")].albedo_texture == 7);
    m = &s->materials[material_named(s, "grey")];
    CHECK(m->albedo_texture == -1);
    CHECK_VEC(m->albedo, 0.5, 0.5, 0.5);
    glint_scene_free(s);
}

// Whether two vectors are bit-for-bit equal.
static bool same_vec(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

static void test_quads_and_boxes(void) {
    glint_scene *s = parse(
        "{\"materials\": {\"w\": {\"type\": \"lambertian\"}, \"l\": {\"type\": \"diffuse_light\", \"emission\": 15}},\n"
        " \"objects\": [\n"
        "  {\"type\": \"quad\", \"q\": [0, 0, 555], \"u\": [0, 0, -555], \"v\": [0, 555, 0], \"material\": \"w\"},\n"
        "  {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [165, 330, 165], \"material\": \"w\"},\n"
        "  {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [165, 330, 165], \"material\": \"w\", \"transform\":\n"
        "   [{\"rotate\": {\"axis\": [0, 1, 0], \"degrees\": 15}}, {\"translate\": [265, 0, 295]}]},\n"
        "  {\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": \"l\",\n"
        "   \"transform\": [{\"scale\": [-1, 1, 1]}]}\n"
        "]}");
    if (!s) return;
    CHECK(s->quad_count == 14 && s->sphere_count == 0 && s->instance_count == 0);
    if (s->quad_count != 14) {
        glint_scene_free(s);
        return;
    }
    const quad *q = &s->quads[0];
    CHECK_VEC(q->q, 0, 0, 555);
    CHECK_VEC(q->u, 0, 0, -555);
    CHECK_VEC(q->v, 0, 555, 0);
    CHECK_VEC(q->normal, 1, 0, 0); // the front is where u x v points: the red wall faces into the box
    CHECK_NEAR(q->area, 555.0 * 555.0, 1e-3);
    CHECK(q->material == 0);

    // The plain box: six faces, normals outwards, the box's exact coordinates at every corner.
    double area = 0.0;
    for (int i = 1; i <= 6; i++) {
        q = &s->quads[i];
        vec3 c = v3_scale(v3_add(q->p[0], q->p[2]), 0.5f);
        CHECK(v3_dot(q->normal, v3_sub(c, v3(82.5f, 165.0f, 82.5f))) > 0.0f);
        area += q->area;
        for (int k = 0; k < 4; k++) {
            vec3 p = q->p[k];
            CHECK((p.x == 0 || p.x == 165) && (p.y == 0 || p.y == 330) && (p.z == 0 || p.z == 165));
        }
    }
    CHECK_NEAR(area, 2.0 * (165.0 * 330.0 * 2.0 + 165.0 * 165.0), 1e-2);

    // The Cornell box's tall box: rotated 15 degrees about y (x' = x cos + z sin, z' = -x sin + z cos, the
    // book's rotate_y), then translated; still six outward faces sharing exactly eight corners.
    double c15 = cos(15.0 * 3.14159265358979323846 / 180.0), s15 = sin(15.0 * 3.14159265358979323846 / 180.0);
    vec3 centre = v3((float)(82.5 * c15 + 82.5 * s15 + 265.0), 165.0f, (float)(-82.5 * s15 + 82.5 * c15 + 295.0));
    vec3 corners[24];
    int distinct = 0;
    for (int i = 7; i <= 12; i++) {
        q = &s->quads[i];
        const quad *plain = &s->quads[i - 6];
        vec3 c = v3_scale(v3_add(q->p[0], q->p[2]), 0.5f);
        CHECK(v3_dot(q->normal, v3_sub(c, centre)) > 0.0f);
        CHECK_NEAR(q->area, plain->area, 1e-2 * plain->area * 1e-3);
        for (int k = 0; k < 4; k++) {
            vec3 p = plain->p[k], w = q->p[k];
            CHECK_NEAR(w.x, p.x * c15 + p.z * s15 + 265.0, 1e-3);
            CHECK_NEAR(w.y, p.y, 1e-3);
            CHECK_NEAR(w.z, -p.x * s15 + p.z * c15 + 295.0, 1e-3);
            bool seen = false;
            for (int j = 0; j < distinct && !seen; j++) seen = same_vec(corners[j], w);
            if (!seen) corners[distinct++] = w;
        }
    }
    CHECK(distinct == 8); // shared corners are bit-identical: the transformed box stays watertight

    // A mirror keeps the front: the quad in the z = 0 plane still faces +z after x -> -x.
    q = &s->quads[13];
    CHECK_VEC(q->normal, 0, 0, 1);
    CHECK(q->material == 1);
    CHECK_NEAR(q->area, 1.0, 1e-6);
    for (int k = 0; k < 4; k++) CHECK(q->p[k].x <= 0.0f && q->p[k].y >= 0.0f && q->p[k].z == 0.0f);
    glint_scene_free(s);
}

// Transform operations apply in array order: the first one to the object, each next one to the result.
static void test_transform_order(void) {
    glint_scene *s = parse(
        "{\"materials\": {\"m\": {\"type\": \"lambertian\"}},\n"
        " \"objects\": [\n"
        "  {\"type\": \"sphere\", \"center\": [1, 0, 0], \"radius\": 0.5, \"material\": \"m\", \"transform\":\n"
        "   [{\"rotate\": {\"axis\": [0, 1, 0], \"degrees\": 90}}, {\"translate\": [1, 0, 0]}]},\n"
        "  {\"type\": \"sphere\", \"center\": [1, 0, 0], \"radius\": 0.5, \"material\": \"m\", \"transform\":\n"
        "   [{\"translate\": [1, 0, 0]}, {\"rotate\": {\"axis\": [0, 1, 0], \"degrees\": 90}}]},\n"
        "  {\"type\": \"sphere\", \"center\": [1, 0, 0], \"radius\": 0.5, \"material\": \"m\", \"transform\":\n"
        "   [{\"scale\": 2}, {\"matrix\": [1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}]},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 1, 0], \"radius\": -0.5, \"material\": \"m\", \"transform\":\n"
        "   [{\"rotate\": {\"axis\": [1, 1, 1], \"degrees\": 30}}, {\"scale\": [-3, 3, 3]}]},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 1, 0], \"radius\": 0.5, \"material\": \"m\", \"transform\":\n"
        "   [{\"scale\": [1, 2, 1]}, {\"translate\": [0, 0, 4]}]},\n"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\", \"transform\": []}\n"
        "]}");
    if (!s) return;
    CHECK(s->sphere_count == 5 && s->instance_count == 1 && s->instance_sphere_count == 1);
    if (s->sphere_count == 5) {
        CHECK_VEC(s->spheres[0].center, 1, 0, -1); // (1,0,0) turned to (0,0,-1), then moved by +x
        CHECK_VEC(s->spheres[1].center, 0, 0, -2); // moved to (2,0,0), then turned
        CHECK_NEAR(s->spheres[0].radius, 0.5, 1e-7);
        CHECK_VEC(s->spheres[2].center, 7, 0, 0);
        CHECK_NEAR(s->spheres[2].radius, 1.0, 1e-7);
        // Rotation, mirror and uniform scale: still a sphere, three times larger, still hollow.
        CHECK_NEAR(s->spheres[3].radius, -1.5, 1e-5);
        CHECK_NEAR(v3_len(s->spheres[3].center), 3.0, 1e-5);
        CHECK_VEC(s->spheres[4].center, 0, 0, 0);
        CHECK_NEAR(s->spheres[4].radius, 1.0, 0);
    }
    // A non-uniform scale makes an ellipsoid: an instance of the object-space sphere.
    if (s->instance_count == 1 && s->instance_sphere_count == 1) {
        const instance *in = &s->instances[0];
        CHECK(in->kind == INSTANCE_SPHERE && in->index == 0 && in->material == 0);
        CHECK_VEC(s->instance_spheres[0].center, 0, 1, 0);
        CHECK_NEAR(s->instance_spheres[0].radius, 0.5, 0);
        CHECK(in->xf.m.m[1][1] == 2.0f && in->xf.m.m[2][3] == 4.0f && in->xf.inv.m[1][1] == 0.5f);
        CHECK_VEC(mat4_apply_point(&in->xf.m, v3(0, 1, 0)), 0, 2, 4);
    }
    glint_scene_free(s);
}

// A textured sphere under a rotation stays an instance, so that its texture turns with it.
static void test_textured_sphere_rotates(void) {
    glint_scene *s = parse(
        "{\"textures\": {\"c\": {\"type\": \"checker\"}},\n"
        " \"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": \"c\"}},\n"
        " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\",\n"
        "   \"transform\": [{\"rotate\": {\"axis\": [0, 1, 0], \"degrees\": 90}}]}]}");
    if (!s) return;
    CHECK(s->sphere_count == 0 && s->instance_count == 1 && s->instance_sphere_count == 1);
    if (s->instance_count == 1) CHECK(s->instances[0].kind == INSTANCE_SPHERE);
    glint_scene_free(s);
}

// Meshes: each file loads once however often it is placed; its MTL materials become scene materials.
static void test_meshes(void) {
    glint_scene *s = parse_in_scenes(
        "{\"materials\": {\"gold\": {\"type\": \"metal\", \"albedo\": [1, 0.8, 0.3]}},\n"
        " \"objects\": [\n"
        "  {\"type\": \"mesh\", \"file\": \"meshes/cornell-box-original/CornellBox-Original.obj\", \"face_normals\": "
        "true},\n"
        "  {\"type\": \"mesh\", \"file\": "
        "\"meshes/cornell-box-original/../cornell-box-original/CornellBox-Original.obj\",\n"
        "   \"face_normals\": true, \"material\": \"gold\", \"transform\": [{\"translate\": [3, 0, 0]}]},\n"
        "  {\"type\": \"mesh\", \"file\": \"meshes/cornell-box-original/CornellBox-Original.obj\"}\n"
        "]}");
    if (s) {
        // Two spellings of one file, placed twice with flat normals: one mesh; smooth normals: another.
        CHECK(s->mesh_count == 2 && s->instance_count == 3);
        if (s->mesh_count == 2 && s->instance_count == 3) {
            const instance *in = s->instances;
            CHECK(in[0].kind == INSTANCE_MESH && in[0].index == 0 && in[0].material == -1);
            CHECK(in[1].kind == INSTANCE_MESH && in[1].index == 0 && in[1].material == scene_find_material(s, "gold"));
            CHECK(in[1].xf.m.m[0][3] == 3.0f && in[1].xf.inv.m[0][3] == -3.0f);
            CHECK(in[2].index == 1 && in[2].material == -1);
            const scene_mesh *m = &s->meshes[0];
            CHECK(m->geometry.triangle_count == 36 && m->slot_count == 8);
            CHECK(strstr(m->path, "/scenes/meshes/cornell-box-original/CornellBox-Original.obj") != NULL);
            bool flat = true, smooth = true;
            for (size_t i = 0; i < m->geometry.triangle_count; i++)
                flat = flat && mesh_triangle_normals(&m->geometry, i).i[0] == -1;
            for (size_t i = 0; i < s->meshes[1].geometry.triangle_count; i++)
                smooth = smooth && mesh_triangle_normals(&s->meshes[1].geometry, i).i[0] >= 0;
            CHECK(flat && smooth);
            // Every slot maps to a material named after the file and the MTL name.
            const char *prefix = "meshes/cornell-box-original/CornellBox-Original.obj:";
            for (size_t i = 0; i < m->slot_count; i++) {
                const char *name = s->material_names[m->slot_material[i]];
                CHECK(name && strncmp(name, prefix, strlen(prefix)) == 0);
            }
            long lamp = scene_find_material(s, "meshes/cornell-box-original/CornellBox-Original.obj:light");
            long red = scene_find_material(s, "meshes/cornell-box-original/CornellBox-Original.obj:leftWall");
            CHECK(lamp >= 0 && red >= 0);
            if (lamp >= 0 && red >= 0) {
                CHECK(s->materials[lamp].kind == MAT_DIFFUSE_LIGHT && !s->materials[lamp].two_sided);
                CHECK_VEC(s->materials[lamp].emission, 17, 12, 4);
                CHECK(s->materials[red].kind == MAT_LAMBERTIAN && s->materials[red].albedo_texture == -1);
                CHECK_VEC(s->materials[red].albedo, 0.63, 0.065, 0.05);
            }
            // Every face has a material of its own: no fallback was needed. The MTL gives `Ka` in each of its 8
            // materials, and the file is read for both meshes: one warning, once for the file.
            CHECK(s->warning_count == 1);
            if (s->warning_count == 1)
                CHECK(strcmp(s->warnings[0], GLINT_SOURCE_DIR "/scenes/meshes/cornell-box-original/"
                                             "CornellBox-Original.mtl:16: warning: MTL keys not supported: Ka; "
                                             "ignored in every material (reported once per file)") == 0);
        }
        glint_scene_free(s);
    }

    // The spider: an MTL with map_Kd images (Windows paths), two placements, four images decoded once each.
    s = parse_in_scenes(
        "{\"objects\": [\n"
        "  {\"type\": \"mesh\", \"file\": \"meshes/assimp-spider/spider.obj\"},\n"
        "  {\"type\": \"mesh\", \"file\": \"meshes/assimp-spider/spider.obj\", \"transform\": [{\"scale\": 2}]}\n"
        "]}");
    if (s) {
        CHECK(s->mesh_count == 1 && s->instance_count == 2 && s->texture_count == 4);
        if (s->mesh_count == 1) {
            const scene_mesh *m = &s->meshes[0];
            CHECK(m->slot_count == 4);
            for (size_t i = 0; i < m->slot_count; i++) {
                const material *mat = &s->materials[m->slot_material[i]];
                CHECK(mat->kind == MAT_LAMBERTIAN && mat->albedo_texture >= 0);
            }
            long body = scene_find_material(s, "meshes/assimp-spider/spider.obj:HLeibTex");
            CHECK(body >= 0);
            if (body >= 0 && s->materials[body].albedo_texture >= 0) {
                const texture *t = &s->textures[s->materials[body].albedo_texture];
                CHECK(t->kind == TEX_IMAGE && t->image.width == 249 && t->image.height == 250); // SpiderTex.jpg
            }
        }
        // The OBJ reader's warnings (zero-area faces) are kept in the scene, not printed.
        CHECK(glint_scene_warning_count(s) >= 1);
        const char *w = glint_scene_warning(s, 0);
        CHECK(w && strstr(w, "spider.obj") && strstr(w, "warning: "));
        CHECK(glint_scene_warning(s, glint_scene_warning_count(s)) == NULL);
        glint_scene_free(s);
    }

    // Spot has no materials: without a "material" its faces are grey, and the scene says so in a warning.
    // (Lit by a white background, so that the only warning is the mesh's.)
    s = parse_in_scenes("{\"objects\": [{\"type\": \"mesh\", \"file\": \"meshes/spot/spot_triangulated.obj\"}], "
                        "\"render\": {\"background\": 1}}");
    if (s) {
        CHECK(s->mesh_count == 1 && s->material_count == 1 && s->warning_count == 1);
        if (s->mesh_count == 1 && s->material_count == 1) {
            CHECK(s->meshes[0].slot_count == 0 && s->meshes[0].default_material == 0);
            CHECK(s->materials[0].kind == MAT_LAMBERTIAN && s->material_names[0] == NULL);
            CHECK(s->meshes[0].geometry.triangle_count == 5856 && s->meshes[0].geometry.uv_count == 3225);
        }
        if (s->warning_count == 1)
            CHECK(strcmp(s->warnings[0], GLINT_SOURCE_DIR "/scenes/inline.json:1:39: warning: some faces of mesh file "
                                         "\"meshes/spot/spot_triangulated.obj\" have no material (no usemtl, or one no "
                                         "material library defines); they are grey Lambertian unless the object gives "
                                         "a \"material\"") == 0);
        glint_scene_free(s);
    }
    s = parse_in_scenes(
        "{\"objects\": [{\"type\": \"mesh\", \"file\": \"meshes/spot/spot_triangulated.obj\", \"material\":"
        " {\"type\": \"lambertian\", \"albedo\": {\"type\": \"image\", \"file\": "
        "\"meshes/spot/spot_texture.png\"}}}], \"render\": {\"background\": 1}}");
    if (s) {
        CHECK(s->warning_count == 0 && s->instance_count == 1 && s->texture_count == 1);
        if (s->instance_count == 1)
            CHECK(s->instances[0].material >= 0 && s->materials[s->instances[0].material].albedo_texture == 0);
        glint_scene_free(s);
    }
}

// The issue-5 scenes: what each holds.
static void test_issue5_scenes(void) {
    glint_scene *s = load_scene_file("cornell-box.json");
    if (s) {
        const render_settings *rs = &s->settings;
        CHECK(rs->width == 600 && rs->height == 600 && rs->max_depth == 50 && rs->integrator == INTEGRATOR_PATH);
        CHECK(rs->background == BACKGROUND_CONSTANT && same_vec(rs->background_color, v3s(0.0f)));
        CHECK(rs->transform == TRANSFORM_GAMMA2);
        CHECK(s->camera.vfov_degrees == 40.0f && same_vec(s->camera.lookfrom, v3(278, 278, -800)) &&
              same_vec(s->camera.lookat, v3(278, 278, 0)));
        CHECK(s->quad_count == 12 && s->sphere_count == 1);
        if (s->quad_count == 12 && s->sphere_count == 1) {
            const quad *lamp = &s->quads[5];
            CHECK(s->materials[lamp->material].kind == MAT_DIFFUSE_LIGHT);
            CHECK_VEC(s->materials[lamp->material].emission, 15, 15, 15);
            CHECK_VEC(lamp->normal, 0, -1, 0); // the light shines down into the box
            CHECK(s->materials[s->spheres[0].material].kind == MAT_DIELECTRIC);
            CHECK_VEC(s->spheres[0].center, 190, 90, 190);
        }
        glint_scene_free(s);
    }
    s = load_scene_file("cornell-box-obj.json");
    if (s) {
        CHECK(s->mesh_count == 1 && s->instance_count == 1 && s->meshes[0].geometry.triangle_count == 36);
        glint_scene_free(s);
    }
    s = load_scene_file("bunny.json");
    if (s) {
        CHECK(s->mesh_count == 1 && s->instance_count == 1 && s->quad_count == 1 && s->texture_count == 1);
        if (s->mesh_count == 1) CHECK(s->meshes[0].geometry.triangle_count == 69451);
        if (s->instance_count == 1) CHECK(s->instances[0].material == scene_find_material(s, "clay"));
        glint_scene_free(s);
    }
    s = load_scene_file("spot.json");
    if (s) {
        CHECK(s->mesh_count == 1 && s->texture_count == 1 && s->textures[0].kind == TEX_IMAGE && s->warning_count == 0);
        glint_scene_free(s);
    }
    s = load_scene_file("spider.json");
    if (s) {
        CHECK(s->mesh_count == 1 && s->texture_count == 4);
        glint_scene_free(s);
    }
    s = load_scene_file("textures.json");
    if (s) {
        CHECK(s->texture_count == 5 && s->sphere_count == 5);
        glint_scene_free(s);
    }
}

// MTL keys glint does not use are named in one warning per MTL file, however many materials give them and however
// many OBJ files read it; a library without them warns nothing.
static void test_mtl_unsupported_keys(void) {
    if (!tmpdir_make("glint-test-scene-mtl")) return;
    char obj_a[600], obj_b[600];
    snprintf(obj_a, sizeof obj_a, "%s", tmp_path("a.obj"));
    snprintf(obj_b, sizeof obj_b, "%s", tmp_path("b.obj"));
    static const char shared[] = "# shared\nnewmtl m1\nKa 1 1 1\nKd 0.5 0.5 0.5\nbump b.png\nmap_Bump b.png\nPr 0.5\n"
                                 "newmtl m2\nKa 1 1 1\nKd 0.2 0.2 0.2\nPm 1\nillum 2\nNs 10\nNi 1.5\nd 1\n";
    static const char plain[] = "newmtl m3\nKd 0.1 0.2 0.3\nillum 2\nNs 10\nNi 1.5\nd 1\nTr 0\n";
    static const char tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    char text_a[200], text_b[200];
    snprintf(text_a, sizeof text_a, "mtllib shared.mtl\n%susemtl m1\nf 1 2 3\nusemtl m2\nf 1 2 3\n", tri);
    snprintf(text_b, sizeof text_b, "mtllib plain.mtl shared.mtl\n%susemtl m3\nf 1 2 3\nusemtl m2\nf 1 2 3\n", tri);
    CHECK(tmp_write(tmp_path("shared.mtl"), shared, strlen(shared)) && tmp_write(tmp_path("plain.mtl"), plain, strlen(plain)));
    CHECK(tmp_write(obj_a, text_a, strlen(text_a)) && tmp_write(obj_b, text_b, strlen(text_b)));
    char scene[2000];
    snprintf(scene, sizeof scene,
             "{\"render\": {\"background\": 1}, \"objects\": [{\"type\": \"mesh\", \"file\": \"%s\"}, "
             "{\"type\": \"mesh\", \"file\": \"%s\"}, {\"type\": \"mesh\", \"file\": \"%s\", \"face_normals\": true}]}",
             obj_a, obj_b, obj_a);
    glint_scene *s = parse(scene);
    if (s) {
        CHECK(s->mesh_count == 3 && s->warning_count == 1);
        char expected[1200];
        snprintf(expected, sizeof expected,
                 "%s:3: warning: MTL keys not supported: Ka, Pr, Pm, bump, map_Bump; ignored in every material "
                 "(reported once per file)",
                 tmp_path("shared.mtl"));
        for (size_t i = 0; i < s->warning_count; i++) {
            bool same = strcmp(s->warnings[i], expected) == 0;
            CHECK(same);
            if (!same) fprintf(stderr, "  warning %zu: %s\n  expected:   %s\n", i, s->warnings[i], expected);
        }
        // The keys that are used still make the materials.
        char name[700];
        snprintf(name, sizeof name, "%s:m1", obj_a);
        long m1 = scene_find_material(s, name);
        CHECK(m1 >= 0 && s->materials[m1].kind == MAT_LAMBERTIAN && s->materials[m1].albedo.x == 0.5f);
        glint_scene_free(s);
    }
    tmpdir_remove();
}

// Checks that text parses with exactly the warnings listed (NULL-terminated), in order.
static void check_warnings(const char *text, const char *const *expected) {
    glint_scene *s = parse(text);
    if (!s) return;
    size_t n = 0;
    while (expected[n]) n++;
    CHECK(s->warning_count == n);
    for (size_t i = 0; i < s->warning_count; i++) {
        bool same = i < n && strcmp(s->warnings[i], expected[i]) == 0;
        CHECK(same);
        if (!same) fprintf(stderr, "  warning %zu: %s\n  expected:   %s\n", i, s->warnings[i], i < n ? expected[i] : "(none)");
    }
    glint_scene_free(s);
}

#define NO_LIGHT                                                                                              \
    "good.json: warning: no light sources in the scene (no lights, no emitters, black background); the image " \
    "will be black"

// A scene that nothing lights says so; any light, emitter or bright background keeps it quiet.
static void test_no_light_warning(void) {
    static const char *const none[] = {NULL}, *const no_light[] = {NO_LIGHT, NULL};
    static const char *const ambient_only[] = {
        "good.json: warning: no light sources the path tracer uses (no point or directional lights, no emitters, "
        "black background; it ignores ambient lights); the image will be black",
        NULL};
    const char *ball = "\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, -3], \"radius\": 1, \"material\": "
                         "{\"type\": \"lambertian\"}}]";
    char text[1024];
    check_warnings("{}", no_light);
    snprintf(text, sizeof text, "{%s}", ball);
    check_warnings(text, no_light);
    snprintf(text, sizeof text, "{\"render\": {\"integrator\": \"path\"}, %s}", ball);
    check_warnings(text, no_light);
    snprintf(text, sizeof text,
             "{\"render\": {\"integrator\": \"path\"}, %s, \"lights\": [{\"type\": \"ambient\", \"intensity\": 1}]}",
             ball);
    check_warnings(text, ambient_only);
    // Lit: an ambient light in Whitted, a point light, a background, a sky, an emitter on a quad or in a mesh.
    snprintf(text, sizeof text, "{%s, \"lights\": [{\"type\": \"ambient\", \"intensity\": 1}]}", ball);
    check_warnings(text, none);
    snprintf(text, sizeof text,
             "{\"render\": {\"integrator\": \"path\"}, %s, \"lights\": [{\"type\": \"point\", \"intensity\": 1, "
             "\"position\": [0, 0, 0]}]}",
             ball);
    check_warnings(text, none);
    check_warnings("{\"render\": {\"integrator\": \"path\", \"background\": 0.1}}", none);
    check_warnings("{\"render\": {\"integrator\": \"path\", \"background\": \"sky\"}}", none);
    check_warnings("{\"render\": {\"integrator\": \"path\"}, \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": "
                   "[1, 0, 0], \"v\": [0, 1, 0], \"material\": {\"type\": \"diffuse_light\"}}]}",
                   none);
    // A black emitter lights nothing.
    check_warnings("{\"render\": {\"integrator\": \"path\"}, \"objects\": [{\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": "
                   "[1, 0, 0], \"v\": [0, 1, 0], \"material\": {\"type\": \"diffuse_light\", \"emission\": 0}}]}",
                   no_light);
    // Paper mode's misses are white: never black.
    check_warnings("{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"paper\"}}}", none);
}

// Paper mode names each kind of thing it drops, with how many.
static void test_paper_mode_warnings(void) {
    static const char *const expected[] = {
        "good.json: warning: paper mode sees spheres only: 2 quad objects are ignored (neither seen nor casting "
        "shadows)",
        "good.json: warning: paper mode sees spheres only: 1 box object is ignored (neither seen nor casting shadows)",
        "good.json: warning: paper mode sees spheres only: 1 instanced sphere is ignored (a transform that is not a "
        "similarity, or a transform with a textured material, makes a sphere an instance; neither seen nor casting "
        "shadows)",
        "good.json: warning: paper mode uses constant colours: 1 sphere is textured (textures are not used)",
        "good.json: warning: paper mode shades metal as a matte colour: 2 spheres are made of metal (no mirror "
        "reflection)",
        "good.json: warning: paper mode shades dielectric as a matte colour: 1 sphere is made of dielectric (no "
        "refraction or reflection)",
        "good.json: warning: paper mode shades diffuse_light as a matte colour: 1 sphere is made of diffuse_light (no "
        "emission)",
        "good.json: warning: paper mode makes highlights white: 1 sphere is given a specular_color (it is not used)",
        "good.json: warning: paper mode ignores \"background\": rays that miss everything are white, as in the "
        "paper's program",
        NULL};
    check_warnings(
        "{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"paper\"}, \"background\": \"sky\"},"
        " \"materials\": {\"m\": {\"type\": \"metal\"}, \"p\": {\"type\": \"phong\"}},"
        " \"objects\": ["
        "  {\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": \"p\"},"
        "  {\"type\": \"quad\", \"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": \"p\"},"
        "  {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": \"p\"},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 5], \"radius\": 1, \"material\": \"p\","
        "   \"transform\": [{\"scale\": [1, 2, 1]}]},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 5], \"radius\": 1, \"material\": \"m\"},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 6], \"radius\": 1, \"material\": \"m\"},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 7], \"radius\": 1, \"material\": {\"type\": \"dielectric\"}},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 8], \"radius\": 1, \"material\": {\"type\": \"diffuse_light\"}},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 9], \"radius\": 1, \"material\": {\"type\": \"lambertian\","
        "   \"albedo\": {\"type\": \"checker\"}}},"
        "  {\"type\": \"sphere\", \"center\": [0, 0, 10], \"radius\": 1, \"material\": {\"type\": \"phong\","
        "   \"specular_color\": [1, 0, 0]}}"
        " ]}",
        expected);
    // The paper's own kind of scene (white background, Phong spheres) drops nothing.
    static const char *const none[] = {NULL};
    check_warnings("{\"render\": {\"integrator\": {\"type\": \"whitted\", \"mode\": \"paper\"}, \"background\": 1},"
                   " \"objects\": "
                   "[{\"type\": \"sphere\", \"center\": [0, 0, 5], \"radius\": 1, \"material\": {\"type\": \"phong\"}}]}",
                   none);
}

// Writes a grid mesh of (n + 1)^2 vertices and 2 n^2 triangles, with a zero-area face and a face of an
// undefined vertex-normal index in the middle (a warning and an error line would fall inside a block), to path.
static bool write_grid(const char *path, int n, bool bad_line) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    for (int y = 0; y <= n; y++)
        for (int x = 0; x <= n; x++) fprintf(f, "v %d.%03d %d.5 %d\n", x, y % 1000, y, (x * y) % 7);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            int a = y * (n + 1) + x + 1, b = a + 1, c = a + n + 1, d = c + 1;
            if (y == n / 2 && x == n / 2) fprintf(f, "f %d %d %d\n# a comment\nvn 0 0 1\n", a, a, b); // no area
            if (bad_line && y == n / 2 && x == n / 2 + 1) fprintf(f, "f %d//7 %d//1 %d//1\n", a, b, c);
            fprintf(f, "f %d %d %d\nf %d %d %d %d\n", a, b, d, a, d, c, c);
        }
    return fclose(f) == 0;
}

// A mesh file large enough for the parallel reader (over 4 MiB) gives the same scene, warnings and errors on
// one thread and on several.
static void test_large_mesh_on_threads(void) {
    if (!tmpdir_make("glint-test-scene-load")) return;
    const char *obj = tmp_path("grid.obj"), *bad = tmp_path("bad.obj");
    CHECK(write_grid(obj, 420, false) && write_grid(bad, 420, true));
    FILE *f = fopen(obj, "rb");
    long size = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (f) fclose(f);
    CHECK(size > (4L << 20));
    char text[1200];
    snprintf(text, sizeof text, "{\"objects\": [{\"type\": \"mesh\", \"file\": \"%s\"}]}", obj);
    glint_scene *one = NULL, *two = NULL, *all = NULL;
    glint_error err;
    CHECK(glint_scene_parse_with("big.json", text, strlen(text), &(glint_load_options){.threads = 1}, &one, &err) ==
          GLINT_OK);
    CHECK(glint_scene_parse_with("big.json", text, strlen(text), &(glint_load_options){.threads = 2}, &two, &err) ==
          GLINT_OK);
    CHECK(glint_scene_parse_with("big.json", text, strlen(text), NULL, &all, &err) == GLINT_OK);
    if (one && two && all) {
        CHECK(one->mesh_count == 1 && two->mesh_count == 1 && all->mesh_count == 1);
        const mesh *a = &one->meshes[0].geometry;
        CHECK(a->triangle_count == 2 * 420 * 420 && a->position_count == 421 * 421);
        obj_model ma = {.mesh = *a}, mb = {.mesh = two->meshes[0].geometry}, mc = {.mesh = all->meshes[0].geometry};
        CHECK(obj_same_model(&ma, &mb, false) && obj_same_model(&ma, &mc, false));
        // The zero-area face's warning, on its line, then the scene's (no material, no light).
        size_t n = glint_scene_warning_count(one);
        CHECK(n == 3 && glint_scene_warning_count(two) == n);
        CHECK(n > 0 && strstr(glint_scene_warning(one, 0), "grid.obj:354062: warning: face has zero area") != NULL);
        for (size_t i = 0; i < n && i < glint_scene_warning_count(two); i++)
            CHECK(strcmp(glint_scene_warning(one, i), glint_scene_warning(two, i)) == 0);
    }
    glint_scene_free(one);
    glint_scene_free(two);
    glint_scene_free(all);
    // The error names the same line whichever reader found it.
    snprintf(text, sizeof text, "{\"objects\": [{\"type\": \"mesh\", \"file\": \"%s\"}]}", bad);
    char first[sizeof err.message];
    glint_scene *s = NULL;
    CHECK(glint_scene_parse_with("bad.json", text, strlen(text), &(glint_load_options){.threads = 1}, &s, &err) ==
          GLINT_ERR_INPUT && !s);
    snprintf(first, sizeof first, "%s", err.message);
    CHECK(glint_scene_parse_with("bad.json", text, strlen(text), &(glint_load_options){.threads = 2}, &s, &err) ==
          GLINT_ERR_INPUT && !s);
    CHECK(strcmp(first, err.message) == 0 && strstr(first, "bad.obj:") != NULL);
    if (strcmp(first, err.message) != 0) fprintf(stderr, "  one thread: %s\n  two threads: %s\n", first, err.message);
    tmpdir_remove();
}

int main(void) {
    test_defaults();
    test_render_settings();
    test_materials();
    test_cameras();
    test_lights();
    test_encoding_and_order();
    test_paper_file();
    test_textures();
    test_quads_and_boxes();
    test_transform_order();
    test_textured_sphere_rotates();
    test_meshes();
    test_issue5_scenes();
    test_mtl_unsupported_keys();
    test_no_light_warning();
    test_paper_mode_warnings();
    test_large_mesh_on_threads();
    return check_summary();
}
