// test_scenes.c — every scene file in scenes/ loads, and every path-traced one renders at a tiny size; the
// seeds' scenes carry the seeds' own settings and come out the right way up.
#include "check.h"
#include "glint.h"
#include "scene/scene.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include "io/model_read.h"

#include <stdlib.h>
#include <string.h>

static glint_scene *load(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", GLINT_SOURCE_DIR, name);
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_load(path, &s, &err) != GLINT_OK) {
        fprintf(stderr, "%s\n", err.message);
        return NULL;
    }
    return s;
}

static bool vec_is(vec3 v, float x, float y, float z) { return v.x == x && v.y == y && v.z == z; }

// The settings of each of the seeds' scenes, as the seeds give them.
typedef struct expected {
    const char *file;
    int width, height, spp, max_depth;
    output_transform transform;
    bool sky;           ///< else a white constant background
    vec3 lookfrom, lookat, vup;
    float vfov, defocus, focus;
    size_t spheres;
} expected;

static const expected seeds_scenes[] = {
    {"howard-default.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20, 0, 0, 4},
    {"howard-final.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20, 0, 0, 530},
    {"howard-lambertian.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {0, 1, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0, 0, 2},
    {"howard-metal.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {0, 1, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0, 0, 3},
    {"howard-dielectric.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0, 0, 3},
    {"howard-hollow-sphere.json", 720, 405, 100, 50, TRANSFORM_GAMMA2, true, {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0, 0,
     4},
    {"rtiow-final.json", 1200, 675, 500, 50, TRANSFORM_GAMMA2, true, {13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20, 0.6f, 10,
     487},
    {"blog-three-spheres.json", 200, 200, 40, 100, TRANSFORM_LINEAR, false, {0, 0, 0}, {0, 0, 1}, {0, -1, 0}, 90, 0, 0,
     4},
};

// Counts spheres of a material kind, and those with a negative radius.
static size_t count_kind(const glint_scene *s, material_kind kind) {
    size_t n = 0;
    for (size_t i = 0; i < s->sphere_count; i++) n += s->materials[s->spheres[i].material].kind == kind;
    return n;
}

static void test_seed_settings(void) {
    for (size_t k = 0; k < sizeof seeds_scenes / sizeof seeds_scenes[0]; k++) {
        const expected *e = &seeds_scenes[k];
        glint_scene *s = load(e->file);
        CHECK(s != NULL);
        if (!s) continue;
        const render_settings *rs = &s->settings;
        const camera *c = &s->camera;
        bool ok = rs->width == e->width && rs->height == e->height && rs->spp == e->spp &&
                  rs->max_depth == e->max_depth && rs->transform == e->transform &&
                  rs->integrator == INTEGRATOR_PATH && s->sphere_count == e->spheres;
        ok = ok && (e->sky ? rs->background == BACKGROUND_SKY && vec_is(rs->sky_horizon, 1, 1, 1) &&
                                 vec_is(rs->sky_zenith, 0.5f, 0.7f, 1.0f)
                           : rs->background == BACKGROUND_CONSTANT && vec_is(rs->background_color, 1, 1, 1));
        ok = ok && c->kind == CAMERA_LOOKAT && vec_is(c->lookfrom, e->lookfrom.x, e->lookfrom.y, e->lookfrom.z) &&
             vec_is(c->lookat, e->lookat.x, e->lookat.y, e->lookat.z) && vec_is(c->vup, e->vup.x, e->vup.y, e->vup.z) &&
             c->vfov_degrees == e->vfov && c->defocus_angle_degrees == e->defocus &&
             (e->focus == 0 || c->focus_distance == e->focus);
        if (!ok) fprintf(stderr, "%s: settings differ from the seed's\n", e->file);
        CHECK(ok);
        glint_scene_free(s);
    }

    // Spot checks of the objects.
    glint_scene *s = load("howard-hollow-sphere.json");
    if (s) {
        CHECK(s->spheres[1].radius == -0.4f && s->materials[s->spheres[1].material].kind == MAT_DIELECTRIC);
        CHECK(s->materials[s->spheres[1].material].ior == 1.5f && fabsf(s->spheres[2].center.x - 1.01f) < 1e-6f);
        glint_scene_free(s);
    }
    s = load("howard-final.json");
    if (s) {
        // 526 small spheres: the grid's Lambertian, metal and glass ones, all of radius 0.2 at height 0.2.
        size_t small = 0;
        for (size_t i = 0; i < s->sphere_count; i++) small += s->spheres[i].radius == 0.2f && s->spheres[i].center.y == 0.2f;
        CHECK(small == 526);
        CHECK(count_kind(s, MAT_LAMBERTIAN) + count_kind(s, MAT_METAL) + count_kind(s, MAT_DIELECTRIC) == 530);
        glint_scene_free(s);
    }
    s = load("rtiow-final.json");
    if (s) {
        CHECK(s->spheres[0].radius == 1000.0f && s->spheres[0].center.y == -1000.0f);
        const material *m = &s->materials[s->spheres[1].material];
        CHECK(m->kind == MAT_METAL && fabs(m->fuzz - 0.1676113777793944) < 1e-7);
        glint_scene_free(s);
    }
    s = load("blog-three-spheres.json");
    if (s) {
        CHECK(s->spheres[3].center.y == 100.5f && s->spheres[3].radius == 100.0f);
        CHECK(vec_is(s->materials[s->spheres[1].material].albedo, 1, 0, 1));
        CHECK(vec_is(s->materials[s->spheres[3].material].albedo, 0.1f, 0.9f, 0.1f));
        glint_scene_free(s);
    }
}

// Renders a loaded scene at 32x18 (or 18x18 when square), 2 samples a pixel, on one thread.
static glint_image *render_tiny(glint_scene *s, const char *name) {
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = s->settings.width == s->settings.height ? 18 : 32;
    o.height = 18;
    o.spp = 2;
    glint_error err;
    CHECK(glint_scene_override(s, &o, &err) == GLINT_OK);
    glint_render_options opt = {.threads = 1};
    glint_image *img = NULL;
    glint_render_stats st;
    glint_status status = glint_render(s, &opt, NULL, NULL, &img, &st, &err);
    if (status != GLINT_OK) fprintf(stderr, "%s: %s\n", name, err.message);
    CHECK(status == GLINT_OK);
    CHECK(st.discarded_samples == 0);
    return img;
}

// Mean of channel c over rows [y0, y1).
static double rows_mean(const glint_image *img, int y0, int y1, int c) {
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    double sum = 0.0;
    for (int y = y0; y < y1; y++)
        for (int x = 0; x < w; x++) sum += rgb[((size_t)y * (size_t)w + (size_t)x) * 3 + (size_t)c];
    return sum / ((y1 - y0) * w);
}

static int ends_with(const char *s, const char *suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

// Every scene file loads; every path-traced one renders to finite, not all-black pixels.
static void test_all_scenes(void) {
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/scenes", GLINT_SOURCE_DIR);
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    if (!d) return;
    int rendered = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!ends_with(e->d_name, ".json")) continue;
        // Scenes of glTF models (gltf-*.json) need assimp, an optional dependency.
        if (!model_read_available() && strncmp(e->d_name, "gltf-", 5) == 0) continue;
        glint_scene *s = load(e->d_name);
        if (!s) fprintf(stderr, "%s does not load\n", e->d_name);
        CHECK(s != NULL);
        if (!s || s->settings.integrator != INTEGRATOR_PATH) {
            glint_scene_free(s);
            continue;
        }
        glint_image *img = render_tiny(s, e->d_name);
        if (img) {
            int w, h;
            const float *rgb;
            glint_image_info(img, &w, &h, &rgb);
            bool finite = true;
            double sum = 0.0;
            for (long i = 0; i < (long)w * h * 3; i++) {
                finite = finite && isfinite(rgb[i]) && rgb[i] >= 0.0f;
                sum += rgb[i];
            }
            if (!finite || !(sum > 0.0)) fprintf(stderr, "%s: non-finite, negative or all-black pixels\n", e->d_name);
            CHECK(finite && sum > 0.0);
            rendered++;
        }
        glint_image_free(img);
        glint_scene_free(s);
    }
    closedir(d);
    CHECK(rendered >= (int)(sizeof seeds_scenes / sizeof seeds_scenes[0]));
}

// Up is up: Howard's grey ground (y = -100.5) fills the bottom of the image under the blue-white sky,
// and the blog's green ground (at +y, which its camera shows downwards) fills the bottom of a white image.
static void test_orientation(void) {
    glint_scene *s = load("howard-lambertian.json");
    if (s) {
        glint_image *img = render_tiny(s, "howard-lambertian.json");
        // Sky at the top is bluish (blue > red); the grey ground at the bottom is darker than the sky.
        CHECK(rows_mean(img, 0, 3, 2) > rows_mean(img, 0, 3, 0) + 0.05);
        CHECK(rows_mean(img, 15, 18, 2) < rows_mean(img, 0, 3, 2) - 0.2);
        glint_image_free(img);
        glint_scene_free(s);
    }
    s = load("blog-three-spheres.json");
    if (s) {
        glint_image *img = render_tiny(s, "blog-three-spheres.json");
        CHECK(rows_mean(img, 0, 3, 0) > 0.99 && rows_mean(img, 0, 3, 2) > 0.99); // white background above
        CHECK(rows_mean(img, 15, 18, 1) > 2.0 * rows_mean(img, 15, 18, 0));     // green ground below
        glint_image_free(img);
        glint_scene_free(s);
    }
}

int main(void) {
    test_seed_settings();
    test_all_scenes();
    test_orientation();
    return check_summary();
}
