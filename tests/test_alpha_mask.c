// test_alpha_mask.c — alpha masks (glTF alphaMode MASK, pbr "alpha" and "alpha_cutoff"): image textures keep the
// alpha of a PNG (RGBA, grey + alpha) and of an RGBA pixel array; a quad with a checker of opaque and clear cells in
// front of a lit wall shows the wall through the clear cells, lit through them (shadow rays pass the cuts too), in
// the path tracer and Whitted's, with the same bytes for any thread count; a mask that cuts nothing renders the bytes
// of no mask; the number of cut hits one query steps through is bounded.
#include "check.h"
#include "glint.h"
#include "integrator/alpha_mask.h"
#include "io/image_read.h"
#include "material/texture.h"
#include "scene/scene.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GLINT_SOURCE_DIR
#define GLINT_SOURCE_DIR ".."
#endif

enum { SIZE = 32 };

// A texture's alpha at texel centres and between them; images without alpha and other kinds are opaque.
static void test_texture_alpha(void) {
    image_rgb img = {2, 1, calloc(6, sizeof(float)), malloc(2 * sizeof(float))};
    if (!img.alpha) return;
    img.alpha[0] = 0.0f, img.alpha[1] = 1.0f;
    texture t = texture_image(img, FILTER_BILINEAR);
    CHECK_NEAR(texture_alpha(&t, 0.25f, 0.5f), 0.0f, 0.0); // the left texel's centre
    CHECK_NEAR(texture_alpha(&t, 0.75f, 0.5f), 1.0f, 0.0); // the right's
    CHECK_NEAR(texture_alpha(&t, 0.5f, 0.5f), 0.5f, 1e-6); // half way
    t.filter = FILTER_NEAREST;
    CHECK(texture_alpha(&t, 0.49f, 0.5f) == 0.0f && texture_alpha(&t, 0.51f, 0.5f) == 1.0f);
    texture_free(&t);
    texture opaque = texture_image((image_rgb){1, 1, calloc(3, sizeof(float)), NULL}, FILTER_BILINEAR);
    CHECK(texture_alpha(&opaque, 0.5f, 0.5f) == 1.0f);
    texture_free(&opaque);
    texture solid = texture_solid(v3s(0.5f));
    CHECK(texture_alpha(&solid, 0.5f, 0.5f) == 1.0f);
}

// A w x h PNG of the given libpng format (8-bit) in memory, written by libpng; NULL on failure.
static unsigned char *png_bytes(int w, int h, png_uint_32 format, const unsigned char *pixels, size_t *size) {
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = (png_uint_32)w, img.height = (png_uint_32)h, img.format = format;
    png_alloc_size_t n = 0;
    if (!png_image_write_to_memory(&img, NULL, &n, 0, pixels, 0, NULL)) return NULL;
    unsigned char *out = malloc(n);
    if (out && !png_image_write_to_memory(&img, out, &n, 0, pixels, 0, NULL)) {
        free(out);
        return NULL;
    }
    *size = n;
    return out;
}

// An RGBA PNG keeps its alpha (byte / 255, whatever the colour decoding), and so does a grey + alpha one; a PNG
// whose alpha is 255 everywhere, and one without alpha, get no alpha plane.
static void test_png_alpha(void) {
    image_rgb img;
    glint_error err;
    CHECK(image_read(GLINT_SOURCE_DIR "/tests/data/models/checker-rgba.png", IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK(img.width == 4 && img.height == 4 && img.alpha != NULL);
    for (int y = 0; img.alpha && y < 4; y++)
        for (int x = 0; x < 4; x++) CHECK(img.alpha[y * 4 + x] == ((x + y) % 2 == 0 ? 1.0f : 0.0f));
    image_rgb_free(&img);
    const unsigned char ga[] = {10, 0, 200, 51}, rgba[] = {1, 2, 3, 255, 4, 5, 6, 255}, rgb[] = {1, 2, 3, 4, 5, 6};
    size_t n = 0;
    unsigned char *png = png_bytes(2, 1, PNG_FORMAT_GA, ga, &n);
    CHECK(png && image_read_memory("ga", png, n, IMAGE_DECODE_LINEAR, &img, &err) == GLINT_OK);
    CHECK(img.alpha && img.alpha[0] == 0.0f && img.alpha[1] == (float)(51 / 255.0) &&
          img.pixels[3] == (float)(200 / 255.0));
    image_rgb_free(&img);
    free(png);
    png = png_bytes(2, 1, PNG_FORMAT_RGBA, rgba, &n);
    CHECK(png && image_read_memory("opaque", png, n, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK(img.pixels && !img.alpha);
    image_rgb_free(&img);
    free(png);
    png = png_bytes(2, 1, PNG_FORMAT_RGB, rgb, &n);
    CHECK(png && image_read_memory("rgb", png, n, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK(img.pixels && !img.alpha);
    image_rgb_free(&img);
    free(png);
}

// One call of the scene API with JSON parameters: kind "render", "camera", "material", "object" or "light".
static void add(glint_scene *s, const char *kind, const char *name, const char *json) {
    glint_params *p;
    glint_error err;
    if (glint_params_parse(json, &p, &err) != GLINT_OK) {
        fprintf(stderr, "%s: %s\n", json, err.message);
        CHECK(0);
        return;
    }
    glint_status st = strcmp(kind, "material") == 0 ? glint_scene_add_material(s, name, p, &err)
                      : strcmp(kind, "object") == 0 ? glint_scene_add_object(s, p, &err)
                      : strcmp(kind, "light") == 0  ? glint_scene_add_light(s, p, &err)
                      : strcmp(kind, "camera") == 0 ? glint_scene_set_camera(s, p, &err)
                                                    : glint_scene_set_render(s, p, &err);
    if (st != GLINT_OK) fprintf(stderr, "%s: %s\n", json, err.message);
    CHECK(st == GLINT_OK);
    glint_params_free(p);
}

// The test scene: a 2 x 2 quad at z = 0 facing the camera (at z = 10), of material `leaf` (JSON), which may use the
// texture "chk": a 4 x 4 checker of opaque (dark) and clear cells from an RGBA pixel array; a white wall at z = -1;
// a directional light along -z; `layers` quads of a fully cut black material in front of the leaf.
static glint_scene *checker_scene(const char *integrator, const char *leaf, int layers) {
    glint_scene *s;
    glint_error err;
    CHECK(glint_scene_new(NULL, &s, &err) == GLINT_OK);
    char render[160];
    snprintf(render, sizeof render, "{\"integrator\": \"%s\", \"width\": %d, \"height\": %d, \"spp\": 4, "
             "\"background\": [0, 0, 0]}", integrator, SIZE, SIZE);
    add(s, "render", NULL, render);
    add(s, "camera", NULL, "{\"type\": \"lookat\", \"lookfrom\": [0, 0, 10], \"lookat\": [0, 0, 0], \"vfov\": 12}");
    uint8_t rgba[4 * 4 * 4];
    for (int i = 0; i < 16; i++) {
        rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = 20;
        rgba[4 * i + 3] = (i % 4 + i / 4) % 2 == 0 ? 255 : 0;
    }
    glint_pixels px = {4, 4, 4, NULL, rgba};
    glint_params *opt;
    CHECK(glint_params_parse("{\"filter\": \"nearest\"}", &opt, &err) == GLINT_OK);
    CHECK(glint_scene_add_image(s, "chk", &px, opt, &err) == GLINT_OK);
    glint_params_free(opt);
    add(s, "material", "leaf", leaf);
    add(s, "material", "wall", "{\"type\": \"lambertian\", \"albedo\": 0.8}");
    if (layers) add(s, "material", "veil", "{\"type\": \"pbr\", \"base_color\": 0, \"alpha\": 0, \"alpha_cutoff\": 0.5}");
    add(s, "object", NULL, "{\"type\": \"quad\", \"q\": [-1, -1, 0], \"u\": [2, 0, 0], \"v\": [0, 2, 0], \"material\": \"leaf\"}");
    add(s, "object", NULL, "{\"type\": \"quad\", \"q\": [-3, -3, -1], \"u\": [6, 0, 0], \"v\": [0, 6, 0], \"material\": \"wall\"}");
    for (int k = 0; k < layers; k++) {
        char q[200];
        snprintf(q, sizeof q, "{\"type\": \"quad\", \"q\": [-2, -2, %g], \"u\": [4, 0, 0], \"v\": [0, 4, 0], "
                 "\"material\": \"veil\"}", 1.0 + 0.01 * k);
        add(s, "object", NULL, q);
    }
    add(s, "light", NULL, "{\"type\": \"directional\", \"direction\": [0, 0, 1], \"intensity\": 3}");
    return s;
}

static float *render(const glint_scene *s, int threads) {
    float *rgb = malloc((size_t)SIZE * SIZE * 3 * sizeof *rgb);
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = threads;
    opt.rgb_out = rgb;
    glint_error err;
    if (!rgb || glint_render(s, &opt, NULL, NULL, NULL, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "render failed: %s\n", err.message);
        free(rgb);
        return NULL;
    }
    return rgb;
}

// The mean of the channels of the pixel that sees the centre of checker cell (cx, cy) (row cy from the top).
static float cell_value(const float *rgb, int cx, int cy) {
    double half = 10.0 * tan(6.0 * 3.14159265358979 / 180.0); // half the view's height at z = 0
    double x = -0.75 + 0.5 * cx, y = 0.75 - 0.5 * cy;
    int i = (int)floor(SIZE / 2.0 + x / half * SIZE / 2.0), j = (int)floor(SIZE / 2.0 - y / half * SIZE / 2.0);
    const float *p = rgb + 3 * ((size_t)j * SIZE + (size_t)i);
    return (p[0] + p[1] + p[2]) / 3.0f;
}

static const char *const LEAF = "{\"type\": \"pbr\", \"base_color\": \"chk\", \"alpha\": \"chk\", \"alpha_cutoff\": 0.5}";

// Clear cells show the wall, lit through them (the shadow ray from the wall crosses the same cell): 0.8 x 3 / pi in
// the path tracer; opaque cells show the dark quad (its specular layer reflects a little of the light).
static void test_checker(const char *integrator) {
    glint_scene *s = checker_scene(integrator, LEAF, 0);
    CHECK(s->materials[0].alpha_texture == 0 && s->textures[0].image.alpha != NULL); // the pixel array's alpha kept
    float *rgb = render(s, 2);
    int right = 0;
    for (int cy = 0; rgb && cy < 4; cy++)
        for (int cx = 0; cx < 4; cx++) {
            float v = cell_value(rgb, cx, cy);
            bool clear = (cx + cy) % 2 != 0;
            if (clear ? v > 0.5f : v < 0.3f) right++;
            else fprintf(stderr, "%s: cell (%d, %d) %s: %g\n", integrator, cx, cy, clear ? "clear" : "opaque", (double)v);
        }
    CHECK(right == 16);
    // The same bytes for any number of threads.
    float *one = render(s, 1), *three = render(s, 3);
    CHECK(rgb && one && three && memcmp(rgb, one, (size_t)SIZE * SIZE * 3 * sizeof *rgb) == 0 &&
          memcmp(rgb, three, (size_t)SIZE * SIZE * 3 * sizeof *rgb) == 0);
    free(rgb), free(one), free(three);
    glint_scene_free(s);
}

// A mask that cuts nothing (alpha 1 everywhere) takes the masked queries, one ray at a time, but renders the bytes
// of no mask (traced with camera packets where the tree allows them).
static void test_uncut_mask_same_bytes(const char *integrator) {
    glint_scene *plain = checker_scene(integrator, "{\"type\": \"pbr\", \"base_color\": \"chk\"}", 0);
    glint_scene *masked = checker_scene(integrator, "{\"type\": \"pbr\", \"base_color\": \"chk\", \"alpha\": 1, "
                                        "\"alpha_cutoff\": 0.5}", 0);
    CHECK(!alpha_scene_masked(plain) && alpha_scene_masked(masked));
    float *a = render(plain, 2), *b = render(masked, 2);
    CHECK(a && b && memcmp(a, b, (size_t)SIZE * SIZE * 3 * sizeof *a) == 0);
    free(a), free(b);
    glint_scene_free(plain);
    glint_scene_free(masked);
}

// ALPHA_MAX_LAYERS cut hits are stepped through, and the next hit counts whatever its alpha. Through a clear cell
// behind 63 fully cut layers the camera ray makes 64 cuts (the layers and the cell) and sees the lit wall; behind 64
// layers the clear cell itself is the 65th hit, and counts (dark).
static void test_layer_bound(const char *integrator) {
    _Static_assert(ALPHA_MAX_LAYERS == 64, "the test's counts");
    glint_scene *s = checker_scene(integrator, LEAF, 63);
    float *rgb = render(s, 2);
    CHECK(rgb && cell_value(rgb, 1, 0) > 0.5f);
    free(rgb);
    glint_scene_free(s);
    s = checker_scene(integrator, LEAF, 64);
    rgb = render(s, 2);
    CHECK(rgb && cell_value(rgb, 1, 0) < 0.3f);
    free(rgb);
    glint_scene_free(s);
}

// An emissive surface cut away everywhere emits nothing: neither paths that pass through it nor next-event
// estimation (which samples points on it) light the floor below it.
static void test_cut_emitter_dark(void) {
    const char *lights[] = {
        "{\"type\": \"quad\", \"q\": [-1, 1, -1], \"u\": [2, 0, 0], \"v\": [0, 0, 2], \"material\": \"lamp\"}",
        "{\"type\": \"sphere\", \"center\": [0, 1.5, 0], \"radius\": 0.3, \"material\": \"lamp\"}",
        "{\"type\": \"mesh\", \"mesh\": \"tri\", \"material\": \"lamp\"}"};
    for (int i = 0; i < 3; i++) {
        glint_scene *s;
        glint_error err;
        CHECK(glint_scene_new(NULL, &s, &err) == GLINT_OK);
        add(s, "render", NULL, "{\"integrator\": \"path\", \"width\": 16, \"height\": 16, \"spp\": 4, "
            "\"background\": [0, 0, 0]}");
        add(s, "camera", NULL, "{\"type\": \"lookat\", \"lookfrom\": [0, 4, 4], \"lookat\": [0, 0, 0], \"vfov\": 40}");
        add(s, "material", "lamp", "{\"type\": \"pbr\", \"emission\": 10, \"alpha\": 0, \"alpha_cutoff\": 0.5}");
        float xyz[] = {-1, 1, -1, 1, 1, -1, 0, 1, 1};
        uint32_t tri[] = {0, 1, 2}; // facing down
        glint_mesh_data m = {.vertex_count = 3, .positions = xyz, .triangle_count = 1, .indices = tri};
        CHECK(glint_scene_add_mesh(s, "tri", &m, &err) == GLINT_OK);
        add(s, "object", NULL, lights[i]);
        add(s, "object", NULL, "{\"type\": \"quad\", \"q\": [-3, 0, -3], \"u\": [0, 0, 6], \"v\": [6, 0, 0], "
            "\"material\": {\"type\": \"lambertian\", \"albedo\": 0.8}}");
        float *rgb = malloc(16 * 16 * 3 * sizeof *rgb);
        glint_render_options opt;
        memset(&opt, 0, sizeof opt);
        opt.threads = 2;
        opt.rgb_out = rgb;
        CHECK(rgb && glint_render(s, &opt, NULL, NULL, NULL, NULL, &err) == GLINT_OK);
        float peak = 0.0f;
        for (int k = 0; rgb && k < 16 * 16 * 3; k++) peak = fmaxf(peak, rgb[k]);
        if (peak != 0.0f) fprintf(stderr, "cut emitter %d lights the scene: %g\n", i, (double)peak);
        CHECK(peak == 0.0f);
        free(rgb);
        glint_scene_free(s);
    }
}

int main(void) {
    test_cut_emitter_dark();
    test_texture_alpha();
    test_png_alpha();
    const char *integrators[] = {"path", "whitted"};
    for (int i = 0; i < 2; i++) {
        test_checker(integrators[i]);
        test_uncut_mask_same_bytes(integrators[i]);
        test_layer_bound(integrators[i]);
    }
    return check_summary();
}
