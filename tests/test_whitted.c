// test_whitted.c — the Whitted integrator: the paper's Fig. 8 against the golden image of an independent
// implementation, and the colour mode on tiny scenes whose exact value is known (spheres, quads, textures,
// emitters).
#include "check.h"
#include "glint.h"
#include "film/film.h"
#include "scene/scene.h"

#include <stdlib.h>
#include <string.h>

// ---- helpers ---------------------------------------------------------------------------------------

// The paper's viewport camera (eye at the origin, 1 x 1 viewport at distance d) over a w x h image.
static glint_scene *tiny_scene(int w, int h, double distance, whitted_mode mode) {
    glint_scene *s = scene_new("<test>");
    if (!s) abort();
    s->settings.width = w;
    s->settings.height = h;
    s->settings.whitted_mode = mode;
    s->settings.max_depth = 3;
    s->camera.kind = CAMERA_VIEWPORT;
    s->camera.viewport_width = s->camera.viewport_height = 1.0;
    s->camera.distance = distance;
    return s;
}

static uint32_t add_phong(glint_scene *s, vec3 colour, int specular, float reflective) {
    material m = material_default(MAT_PHONG);
    m.albedo = colour;
    m.specular = specular;
    m.reflective = reflective;
    long i = scene_add_material(s, &m, NULL);
    if (i < 0) abort();
    return (uint32_t)i;
}

static uint32_t add_material(glint_scene *s, material m) {
    long i = scene_add_material(s, &m, NULL);
    if (i < 0) abort();
    return (uint32_t)i;
}

static void add_sphere(glint_scene *s, vec3 c, float r, uint32_t mat) {
    sphere sp = {c, r, mat};
    if (!scene_add_sphere(s, sp)) abort();
}

static void add_light(glint_scene *s, light_kind kind, vec3 intensity, vec3 v) {
    light l = {0};
    l.kind = kind;
    l.intensity = intensity;
    if (kind == LIGHT_POINT) l.position = v;
    if (kind == LIGHT_DIRECTIONAL) l.direction = v;
    if (!scene_add_light(s, l)) abort();
}

static void add_quad(glint_scene *s, vec3 q, vec3 u, vec3 v, uint32_t mat) {
    quad qd;
    if (!quad_make(q, u, v, mat, &qd) || !scene_add_quad(s, qd)) abort();
}

static int32_t add_texture(glint_scene *s, texture t) {
    long i = scene_add_texture(s, &t, NULL);
    if (i < 0) abort();
    return (int32_t)i;
}

static glint_image *render(glint_scene *s, int threads, glint_render_stats *stats) {
    glint_render_options opt = {.threads = threads};
    glint_image *img = NULL;
    glint_error err;
    glint_render_stats local;
    glint_status st = glint_render(s, &opt, NULL, NULL, &img, stats ? stats : &local, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "render failed: %s\n", err.message);
    return img;
}

// Linear RGB of pixel (x, y).
static vec3 pixel(const glint_image *img, int x, int y) {
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    const float *p = &rgb[((size_t)y * (size_t)w + (size_t)x) * 3u];
    return v3(p[0], p[1], p[2]);
}

// In a 2 x 2 image the paper's viewport camera sends pixel (1, 0) along the axis (0, 0, 1) exactly.
enum { AXIS_X = 1, AXIS_Y = 0 };

// ---- the film reproduces the paper mode's bytes --------------------------------------------------------

static void test_byte_round_trip(void) {
    int bad = 0;
    for (int b = 0; b < 256; b++)
        if (film_encode((float)b / 255.0f, TRANSFORM_LINEAR) != b) bad++;
    CHECK(bad == 0);
}

// ---- the golden test: scenes/paper.json against the independent reference ------------------------------

// Reads a binary P6 with maxval 255; NULL on any problem.
static unsigned char *read_p6(const char *path, int *w, int *h) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    int maxval = 0;
    unsigned char *data = NULL;
    if (fscanf(f, "P6 %d %d %d", w, h, &maxval) == 3 && maxval == 255 && *w > 0 && *h > 0 && *w <= 16384 &&
        *h <= 16384 && fgetc(f) != EOF) {
        size_t n = (size_t)*w * (size_t)*h * 3u;
        data = malloc(n);
        if (data && fread(data, 1, n, f) != n) {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    return data;
}

// Compares every channel of img with the golden image; returns the fraction within +-1 and sets *exact.
static double compare_golden(const glint_image *img, const unsigned char *golden, int w, int h, double *exact) {
    size_t same = 0, near = 0, total = (size_t)w * (size_t)h * 3u;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                int a = glint_image_byte(img, x, y, c), b = golden[((size_t)y * (size_t)w + (size_t)x) * 3u + (size_t)c];
                same += a == b;
                near += abs(a - b) <= 1;
            }
    *exact = (double)same / (double)total;
    return (double)near / (double)total;
}

// The paper's scene built through the scene API, as scenes/paper.json describes it (at size x size).
static glint_scene *paper_scene_in_c(int size, whitted_mode mode) {
    glint_scene *s = tiny_scene(size, size, 0.58, mode);
    s->settings.background_color = v3s(1.0f);
    add_sphere(s, v3(0, -1, 3), 1.0f, add_phong(s, v3(1, 0, 0), 9900, 0.2f));
    add_sphere(s, v3(-2, 1, 3), 1.0f, add_phong(s, v3(0, 0, 1), 5, 0.0f));
    add_sphere(s, v3(2, 1, 3), 1.0f, add_phong(s, v3(0, 1, 0), 50, 0.5f));
    add_sphere(s, v3(0, -5001, 0), 5000.0f, add_phong(s, v3(1, 1, 0), 1000, 0.01f));
    add_light(s, LIGHT_AMBIENT, v3s(0.2f), v3s(0));
    add_light(s, LIGHT_POINT, v3s(0.6f), v3(2, 1, 0));
    add_light(s, LIGHT_DIRECTIONAL, v3s(0.2f), v3(1, 4, 4));
    return s;
}

// Renders paper_scene_in_c(size, mode) and compares it with the golden image at `path` (checked to be
// size x size): the fractions of channels within +-1 and exact; false when there is nothing to compare.
static bool paper_in_c_against_golden(const char *path, int size, whitted_mode mode, double *near, double *exact) {
    int gw = 0, gh = 0;
    unsigned char *golden = read_p6(path, &gw, &gh);
    CHECK(golden != NULL && gw == size && gh == size);
    if (!golden || gw != size || gh != size) {
        free(golden);
        return false;
    }
    glint_scene *s = paper_scene_in_c(size, mode);
    glint_image *img = render(s, 2, NULL);
    bool rendered = img != NULL;
    if (rendered) *near = compare_golden(img, golden, gw, gh, exact);
    glint_image_free(img);
    glint_scene_free(s);
    free(golden);
    return rendered;
}

static void test_paper_golden(void) {
    int gw = 0, gh = 0;
    unsigned char *golden = read_p6(GLINT_SOURCE_DIR "/tests/golden/paper.ppm", &gw, &gh);
    CHECK(golden != NULL);
    if (!golden) return;
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_load(GLINT_SOURCE_DIR "/scenes/paper.json", &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) {
        fprintf(stderr, "loading scenes/paper.json: %s\n", err.message);
        free(golden);
        return;
    }
    int w, h;
    glint_scene_size(s, &w, &h);
    CHECK(w == gw && h == gh);
    glint_render_stats stats;
    glint_image *img = render(s, 2, &stats);
    if (img && w == gw && h == gh) {
        double exact, near = compare_golden(img, golden, w, h, &exact);
        printf("paper.json vs golden: %.4f%% of channels exact, %.4f%% within +-1\n", 100.0 * exact, 100.0 * near);
        CHECK(near >= 0.999);
        CHECK(exact >= 0.999);
        // One camera ray per pixel, plus reflections; a shadow ray per non-ambient light and hit.
        CHECK(stats.rays >= (uint64_t)w * (uint64_t)h);
        CHECK(stats.shadow_rays > 0);
    }
    glint_image_free(img);
    glint_scene_free(s);
    free(golden);
}

// The colour mode on the paper's scene against tests/golden/color_reference.py, a plain double-precision
// implementation of the same model ("Computer Graphics from Scratch"): they may differ only where float
// and double disagree about a grazing ray.
static void test_color_golden(void) {
    double near, exact;
    if (!paper_in_c_against_golden(GLINT_SOURCE_DIR "/tests/golden/paper-color-256.ppm", 256, WHITTED_COLOR, &near,
                                   &exact))
        return;
    printf("colour mode vs reference: %.4f%% of channels exact, %.4f%% within +-1\n", 100.0 * exact, 100.0 * near);
    CHECK(near >= 0.999);
    CHECK(exact >= 0.99);
}

// The paper mode through the scene API alone, so that a loader problem and an integrator problem are told
// apart: the same image as the golden one.
static void test_paper_in_c(void) {
    double near, exact;
    if (!paper_in_c_against_golden(GLINT_SOURCE_DIR "/tests/golden/paper.ppm", 768, WHITTED_PAPER, &near, &exact))
        return;
    CHECK(near >= 0.999);
    CHECK(exact >= 0.999);
}

// ---- paper mode on tiny scenes -------------------------------------------------------------------------

// Only ambient light on a red sphere: each channel is trunc(255 * 0.2) = 51, or 0.
static void test_paper_ambient(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_PAPER);
    add_sphere(s, v3(0, 0, 3), 1.0f, add_phong(s, v3(1, 0, 0), 500, 0.0f));
    add_light(s, LIGHT_AMBIENT, v3s(0.2f), v3s(0));
    glint_image *img = render(s, 1, NULL);
    if (img) {
        CHECK(glint_image_byte(img, AXIS_X, AXIS_Y, 0) == 51);
        CHECK(glint_image_byte(img, AXIS_X, AXIS_Y, 1) == 0);
        CHECK(glint_image_byte(img, AXIS_X, AXIS_Y, 2) == 0);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// A miss is white in paper mode, whatever the background setting.
static void test_paper_miss(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_PAPER);
    s->settings.background_color = v3(0.1f, 0.2f, 0.3f);
    add_sphere(s, v3(0, 10, 3), 1.0f, add_phong(s, v3(1, 0, 0), 500, 0.0f));
    glint_image *img = render(s, 1, NULL);
    if (img)
        for (int c = 0; c < 3; c++) CHECK(glint_image_byte(img, AXIS_X, AXIS_Y, c) == 255);
    glint_image_free(img);
    glint_scene_free(s);
}

// ---- colour mode ---------------------------------------------------------------------------------------

// A single lit sphere seen along the axis: albedo * (ambient + diffuse), with a point light at the eye
// (N.L / |L| = 1) and RGB intensities.
static void test_color_lit_sphere(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    vec3 albedo = v3(0.5f, 0.25f, 1.0f);
    uint32_t m = add_phong(s, albedo, -1, 0.0f);
    add_sphere(s, v3(0, 0, 3), 1.0f, m);
    add_light(s, LIGHT_AMBIENT, v3(0.2f, 0.1f, 0.3f), v3s(0));
    add_light(s, LIGHT_POINT, v3(0.6f, 0.5f, 0.4f), v3(0, 0, 0));
    glint_image *img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.5 * (0.2 + 0.6), 1e-6);
        CHECK_NEAR(p.y, 0.25 * (0.1 + 0.5), 1e-6);
        CHECK_NEAR(p.z, 1.0 * (0.3 + 0.4), 1e-6);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// Same sphere lit by a directional light at 45 degrees (diffuse factor 1/sqrt 2), first unobstructed,
// then with a small sphere on the shadow ray: only the ambient term remains.
static void test_color_shadow(void) {
    for (int blocked = 0; blocked < 2; blocked++) {
        glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        uint32_t m = add_phong(s, v3(1.0f, 0.5f, 0.25f), -1, 0.0f);
        add_sphere(s, v3(0, 0, 3), 1.0f, m);
        if (blocked) add_sphere(s, v3(0, 1.5f, 0.5f), 0.3f, m); // on P + t (0, 1, -1), off the camera ray
        add_light(s, LIGHT_AMBIENT, v3s(0.2f), v3s(0));
        add_light(s, LIGHT_DIRECTIONAL, v3s(0.6f), v3(0, 1, -1));
        glint_image *img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            double i = blocked ? 0.2 : 0.2 + 0.6 / sqrt(2.0);
            CHECK_NEAR(p.x, 1.0 * i, 1e-6);
            CHECK_NEAR(p.y, 0.5 * i, 1e-6);
            CHECK_NEAR(p.z, 0.25 * i, 1e-6);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// A highlight straight back at the eye: specular term 1 times the highlight colour (albedo by default).
static void test_color_highlight(void) {
    for (int own = 0; own < 2; own++) {
        glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        material m = material_default(MAT_PHONG);
        m.albedo = v3(0.5f, 0.0f, 0.0f);
        m.specular = 10;
        if (own) {
            m.specular_color = v3(0.0f, 0.0f, 1.0f);
            m.has_specular_color = true;
        }
        add_sphere(s, v3(0, 0, 3), 1.0f, add_material(s, m));
        add_light(s, LIGHT_DIRECTIONAL, v3s(0.5f), v3(0, 0, -1));
        glint_image *img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            // diffuse 0.5 * albedo + specular 0.5 * highlight colour
            CHECK_NEAR(p.x, own ? 0.25 : 0.5, 1e-5);
            CHECK_NEAR(p.y, 0.0, 1e-6);
            CHECK_NEAR(p.z, own ? 0.5 : 0.0, 1e-5);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// A reflective sphere shows a red sphere behind the eye: local (1 - rfl) + rfl * red, and a metal mirror
// shows albedo * red. Ambient-only lighting keeps the values exact.
static void test_color_reflection(void) {
    for (int metal = 0; metal < 2; metal++) {
        glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        uint32_t mirror;
        if (metal) {
            material m = material_default(MAT_METAL);
            m.albedo = v3(0.5f, 0.5f, 0.8f);
            m.fuzz = 0.7f; // ignored by the Whitted integrator
            mirror = add_material(s, m);
        } else {
            mirror = add_phong(s, v3(0, 0, 1), -1, 0.5f);
        }
        add_sphere(s, v3(0, 0, 3), 1.0f, mirror);
        add_sphere(s, v3(0, 0, -3), 1.0f, add_phong(s, v3(1, 0, 0), -1, 0.0f));
        add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
        glint_image *img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            CHECK_NEAR(p.x, 0.5, 1e-6);
            CHECK_NEAR(p.y, 0.0, 1e-6);
            CHECK_NEAR(p.z, metal ? 0.0 : 0.5, 1e-6);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// A reflected ray that escapes returns the background; with no depth left, no reflection is traced.
static void test_color_reflection_background(void) {
    for (int depth = 0; depth < 2; depth++) {
        glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        s->settings.max_depth = depth;
        s->settings.background_color = v3(0.0f, 0.4f, 0.0f);
        add_sphere(s, v3(0, 0, 3), 1.0f, add_phong(s, v3(1, 0, 0), -1, 0.25f));
        add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
        glint_image *img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            CHECK_NEAR(p.x, depth ? 0.75 : 1.0, 1e-6);
            CHECK_NEAR(p.y, depth ? 0.25 * 0.4 : 0.0, 1e-6);
            CHECK_NEAR(p.z, 0.0, 1e-6);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Glass at normal incidence: Fresnel R = ((n - 1)/(n + 1))^2 = 0.04 at each surface and the ray goes straight
// through to a green sphere; reflections at the front and (bouncing inside) the back surface go out to a
// blue background. With depth 3: green T^2, blue R + T^2 R (T = 1 - R); with a deep budget the geometric
// series T^2 / (1 - R^2) and R + T^2 R / (1 - R^2), less the branches under the weight cut-off (< 1e-4).
static void test_color_refraction(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    s->settings.background_color = v3(0, 0, 1);
    material glass = material_default(MAT_DIELECTRIC);
    glass.ior = 1.5f;
    add_sphere(s, v3(0, 0, 3), 1.0f, add_material(s, glass));
    add_sphere(s, v3(0, 0, 8), 1.0f, add_phong(s, v3(0, 1, 0), -1, 0.0f));
    add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
    const double r = 0.04, t = 1.0 - r;
    glint_image *img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.0, 1e-6);
        CHECK_NEAR(p.y, t * t, 1e-6);
        CHECK_NEAR(p.z, r + t * t * r, 1e-6);
    }
    glint_image_free(img);
    s->settings.max_depth = 20;
    img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.0, 1e-6);
        CHECK_NEAR(p.y, t * t / (1.0 - r * r), 1e-4);
        CHECK_NEAR(p.z, r + t * t * r / (1.0 - r * r), 1e-4);
    }
    glint_image_free(img);
    // A tinted glass colours what is seen through it (tint once per pass through a surface pair).
    s->materials[0].albedo = v3(1.0f, 0.5f, 1.0f);
    img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK(p.y < 0.3f);
        CHECK(p.y > 0.2f);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// Total internal reflection: from inside glass (n = 1.5) at 60 degrees to the normal, sin 60 * 1.5 > 1, so
// the ray is reflected with weight 1 and never sees the white background outside.
static void test_color_total_internal_reflection(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    s->settings.max_depth = 1;
    s->settings.background_color = v3(1, 1, 1);
    material glass = material_default(MAT_DIELECTRIC);
    glass.ior = 1.5f;
    // The axis ray (from (0,0,1) along +z) leaves this sphere at (0,0,5), where the outward normal is
    // (0, sin 60, cos 60): the centre is (0,0,5) - R * normal.
    float radius = 10.0f, sin60 = 0.8660254f;
    add_sphere(s, v3(0, -radius * sin60, 5.0f - radius * 0.5f), radius, add_material(s, glass));
    glint_image *img = render(s, 1, NULL);
    if (img) {
        // The reflected ray stays inside and meets the glass again with no depth left: black. A refracted
        // ray would have seen the white background.
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.0, 0);
        CHECK_NEAR(p.y, 0.0, 0);
        CHECK_NEAR(p.z, 0.0, 0);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// Rays that meet nothing see the background: a constant colour, or the sky's blend by direction.
static void test_color_background(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    s->settings.background_color = v3(0.25f, 0.5f, 0.75f);
    glint_image *img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.25, 0);
        CHECK_NEAR(p.y, 0.5, 0);
        CHECK_NEAR(p.z, 0.75, 0);
    }
    glint_image_free(img);
    s->settings.background = BACKGROUND_SKY;
    img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y); // horizontal ray: halfway between horizon and zenith
        CHECK_NEAR(p.x, 0.75, 1e-6);
        CHECK_NEAR(p.y, 0.85, 1e-6);
        CHECK_NEAR(p.z, 1.0, 1e-6);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// Enormous depth budgets stay bounded: a hollow glass sphere (branches below the weight cut-off are
// dropped), and the eye inside a perfect mirror ball, 10000 bounces a sample, in both modes, without
// overflowing the stack.
static void test_deep_recursion(void) {
    glint_scene *s = tiny_scene(4, 4, 1.0, WHITTED_COLOR);
    s->settings.max_depth = 10000;
    material glass = material_default(MAT_DIELECTRIC);
    uint32_t g = add_material(s, glass);
    add_sphere(s, v3(0, 0, 3), 1.0f, g);
    add_sphere(s, v3(0, 0, 3), -0.9f, g);
    add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
    glint_image *img = render(s, 1, NULL);
    CHECK(img != NULL);
    glint_image_free(img);
    glint_scene_free(s);

    for (int paper = 0; paper < 2; paper++) {
        s = tiny_scene(4, 4, 1.0, paper ? WHITTED_PAPER : WHITTED_COLOR);
        s->settings.max_depth = 10000;
        material mirror = material_default(paper ? MAT_PHONG : MAT_METAL);
        mirror.albedo = v3s(1.0f);
        mirror.reflective = 1.0f;
        add_sphere(s, v3(0, 0, -20), 100.0f, add_material(s, mirror));
        add_light(s, LIGHT_AMBIENT, v3s(0.5f), v3s(0));
        glint_render_stats stats;
        img = render(s, 1, &stats);
        CHECK(img != NULL);
        CHECK(stats.rays == 16u * 10001u); // every bounce stays inside the ball
        if (img) {
            // Paper: a perfect mirror's intensity is what it reflects, all the way down: 0.5 -> byte 127.
            // Colour: metal has no local term, and the last bounce has no depth left: black.
            CHECK(glint_image_byte(img, 0, 0, 0) == (paper ? 127 : 0));
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}


// ---- colour mode on quads, textures and emitters -----------------------------------------------------

// A quad facing the camera (the ray meets its back: u x v = +z) shades like the sphere: albedo * (ambient +
// diffuse) with a point light at the eye; a quad across the shadow ray of a directional light leaves only
// the ambient term; a metal quad mirrors a red sphere behind the eye.
static void test_color_quad(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    add_quad(s, v3(-1, -1, 3), v3(2, 0, 0), v3(0, 2, 0), add_phong(s, v3(0.5f, 0.25f, 1.0f), -1, 0.0f));
    add_light(s, LIGHT_AMBIENT, v3(0.2f, 0.1f, 0.3f), v3s(0));
    add_light(s, LIGHT_POINT, v3(0.6f, 0.5f, 0.4f), v3(0, 0, 0));
    glint_image *img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.5 * (0.2 + 0.6), 1e-6);
        CHECK_NEAR(p.y, 0.25 * (0.1 + 0.5), 1e-6);
        CHECK_NEAR(p.z, 1.0 * (0.3 + 0.4), 1e-6);
    }
    glint_image_free(img);
    glint_scene_free(s);

    for (int blocked = 0; blocked < 2; blocked++) {
        s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        uint32_t m = add_phong(s, v3(1.0f, 0.5f, 0.25f), -1, 0.0f);
        add_quad(s, v3(-1, -1, 3), v3(0, 2, 0), v3(2, 0, 0), m); // u x v = -z: the ray meets the front
        if (blocked) add_quad(s, v3(-0.5f, 1.5f, 0), v3(1, 0, 0), v3(0, 0, 2.9f), m); // crosses P + t (0, 1, -1)
        add_light(s, LIGHT_AMBIENT, v3s(0.2f), v3s(0));
        add_light(s, LIGHT_DIRECTIONAL, v3s(0.6f), v3(0, 1, -1));
        img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            double i = blocked ? 0.2 : 0.2 + 0.6 / sqrt(2.0);
            CHECK_NEAR(p.x, 1.0 * i, 1e-6);
            CHECK_NEAR(p.y, 0.5 * i, 1e-6);
            CHECK_NEAR(p.z, 0.25 * i, 1e-6);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }

    s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    material metal = material_default(MAT_METAL);
    metal.albedo = v3(0.5f, 0.5f, 0.8f);
    add_quad(s, v3(-1, -1, 3), v3(2, 0, 0), v3(0, 2, 0), add_material(s, metal));
    add_sphere(s, v3(0, 0, -3), 1.0f, add_phong(s, v3(1, 0, 0), -1, 0.0f));
    add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
    img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.5, 1e-6);
        CHECK_NEAR(p.y, 0.0, 1e-6);
        CHECK_NEAR(p.z, 0.0, 1e-6);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// Textures give the surface colour: a solid texture on a sphere replaces its albedo (lit as in
// test_color_lit_sphere), and a checker on a quad gives the two pixels that see different cells their own
// colours (pixel (1, 0) sees (0, 0, 3): cells 0 + 0 + 1, odd; pixel (0, 0) sees (-1.5, 0, 3): -1 + 0 + 1, even).
static void test_color_textures(void) {
    glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    material m = material_default(MAT_PHONG);
    m.albedo = v3s(0.9f);
    m.albedo_texture = add_texture(s, texture_solid(v3(0.5f, 0.25f, 1.0f)));
    add_sphere(s, v3(0, 0, 3), 1.0f, add_material(s, m));
    add_light(s, LIGHT_AMBIENT, v3(0.2f, 0.1f, 0.3f), v3s(0));
    add_light(s, LIGHT_POINT, v3(0.6f, 0.5f, 0.4f), v3(0, 0, 0));
    glint_image *img = render(s, 1, NULL);
    if (img) {
        vec3 p = pixel(img, AXIS_X, AXIS_Y);
        CHECK_NEAR(p.x, 0.5 * (0.2 + 0.6), 1e-6);
        CHECK_NEAR(p.y, 0.25 * (0.1 + 0.5), 1e-6);
        CHECK_NEAR(p.z, 1.0 * (0.3 + 0.4), 1e-6);
    }
    glint_image_free(img);
    glint_scene_free(s);

    s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
    material lam = material_default(MAT_LAMBERTIAN);
    const vec3 even = v3(0.1f, 0.2f, 0.3f), odd = v3(0.7f, 0.6f, 0.5f);
    lam.albedo_texture = add_texture(s, texture_checker(2.0f, even, odd));
    add_quad(s, v3(-4, -4, 3), v3(8, 0, 0), v3(0, 8, 0), add_material(s, lam));
    add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
    img = render(s, 1, NULL);
    if (img) {
        vec3 a = pixel(img, AXIS_X, AXIS_Y), b = pixel(img, 0, 0);
        CHECK(a.x == odd.x && a.y == odd.y && a.z == odd.z);
        CHECK(b.x == even.x && b.y == even.y && b.z == even.z);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

// An emitter returns its emission (times its emission texture) on its front side, or on both when
// two-sided; its back side is black, not the background.
static void test_color_emitter(void) {
    const struct { bool front, two_sided, textured; float expect[3]; } cases[] = {
        {true, false, false, {2, 2, 2}}, {false, false, false, {0, 0, 0}}, {false, true, false, {2, 2, 2}},
        {true, false, true, {1, 2, 4}}};
    for (int k = 0; k < 4; k++) {
        glint_scene *s = tiny_scene(2, 2, 1.0, WHITTED_COLOR);
        s->settings.background_color = v3(0.3f, 0.3f, 0.3f);
        material m = material_default(MAT_DIFFUSE_LIGHT);
        m.emission = v3s(2.0f);
        m.two_sided = cases[k].two_sided;
        if (cases[k].textured) m.emission_texture = add_texture(s, texture_solid(v3(0.5f, 1.0f, 2.0f)));
        uint32_t mat = add_material(s, m);
        // u x v = -z faces the camera.
        if (cases[k].front) add_quad(s, v3(-1, -1, 3), v3(0, 2, 0), v3(2, 0, 0), mat);
        else add_quad(s, v3(-1, -1, 3), v3(2, 0, 0), v3(0, 2, 0), mat);
        add_light(s, LIGHT_AMBIENT, v3s(1.0f), v3s(0));
        glint_image *img = render(s, 1, NULL);
        if (img) {
            vec3 p = pixel(img, AXIS_X, AXIS_Y);
            CHECK_NEAR(p.x, cases[k].expect[0], 1e-6);
            CHECK_NEAR(p.y, cases[k].expect[1], 1e-6);
            CHECK_NEAR(p.z, cases[k].expect[2], 1e-6);
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Paper mode is the paper's program: spheres only. A quad in front of the sphere changes no byte.
static void test_paper_ignores_quads(void) {
    glint_image *img[2];
    for (int k = 0; k < 2; k++) {
        glint_scene *s = paper_scene_in_c(32, WHITTED_PAPER);
        if (k) add_quad(s, v3(-5, -5, 1.5f), v3(10, 0, 0), v3(0, 10, 0), add_phong(s, v3(1, 1, 1), -1, 0.0f));
        img[k] = render(s, 1, NULL);
        glint_scene_free(s);
    }
    int same = 0;
    if (img[0] && img[1])
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 32; x++)
                for (int c = 0; c < 3; c++) same += glint_image_byte(img[0], x, y, c) == glint_image_byte(img[1], x, y, c);
    CHECK(same == 32 * 32 * 3);
    for (int k = 0; k < 2; k++) glint_image_free(img[k]);
}

// A checker on a floor quad at exactly y = 0, a cell boundary: each pixel is one of the two colours exactly
// (ambient light 1 shows the albedo), and no pixel differs from all four of its neighbours (salt-and-pepper
// noise, from hit points rounding to either side of y = 0, would).
static void test_color_checker_on_cell_boundary(void) {
    const char *text =
        "{\"render\": {\"width\": 64, \"height\": 64, \"spp\": 1},"
        " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0.3, 4, 0.7], \"lookat\": [0.3, 0, -3.7], \"vfov\": 60},"
        " \"materials\": {\"floor\": {\"type\": \"lambertian\", \"albedo\": {\"type\": \"checker\", \"scale\": 1,"
        "  \"even\": 0.8, \"odd\": 0.3}}},"
        " \"objects\": [{\"type\": \"quad\", \"q\": [-50, 0, -50], \"u\": [100, 0, 0], \"v\": [0, 0, 100],"
        "  \"material\": \"floor\"}],"
        " \"lights\": [{\"type\": \"ambient\", \"intensity\": 1}]}";
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_parse("checker.json", text, strlen(text), &s, &err) == GLINT_OK);
    if (!s) return;
    glint_image *img = render(s, 2, NULL);
    if (img) {
        int other = 0, isolated = 0;
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 64; x++) {
                vec3 c = pixel(img, x, y);
                bool even = c.x == 0.8f && c.y == 0.8f && c.z == 0.8f, odd = c.x == 0.3f && c.y == 0.3f && c.z == 0.3f;
                other += !even && !odd;
                if (x == 0 || y == 0 || x == 63 || y == 63) continue;
                float k = c.x;
                isolated += pixel(img, x - 1, y).x != k && pixel(img, x + 1, y).x != k && pixel(img, x, y - 1).x != k &&
                            pixel(img, x, y + 1).x != k;
            }
        CHECK(other == 0);
        CHECK(isolated == 0);
        if (isolated) fprintf(stderr, "  %d isolated pixels on the checkered floor\n", isolated);
    }
    glint_image_free(img);
    glint_scene_free(s);
}

int main(void) {
    test_byte_round_trip();
    test_paper_ambient();
    test_paper_miss();
    test_color_lit_sphere();
    test_color_checker_on_cell_boundary();
    test_color_shadow();
    test_color_highlight();
    test_color_reflection();
    test_color_reflection_background();
    test_color_refraction();
    test_color_total_internal_reflection();
    test_color_background();
    test_deep_recursion();
    test_color_quad();
    test_color_textures();
    test_color_emitter();
    test_paper_ignores_quads();
    test_paper_in_c();
    test_color_golden();
    test_paper_golden();
    return check_summary();
}
