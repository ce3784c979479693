// test_path.c — the path integrator against scenes whose exact radiance is known (furnaces, a sky-lit
// plane, point and directional lights), its depth limit and ray counts, robustness on a huge sphere,
// convergence as 1/sqrt(spp), and byte-identical images for any thread count.
#include "check.h"
#include "glint.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

// An empty path-traced scene with a look-at camera.
static glint_scene *new_scene(int w, int h, int spp, int depth, vec3 from, vec3 at, vec3 up, float vfov) {
    glint_scene *s = scene_new("test");
    render_settings *rs = &s->settings;
    rs->width = w;
    rs->height = h;
    rs->spp = spp;
    rs->max_depth = depth;
    rs->integrator = INTEGRATOR_PATH;
    rs->background = BACKGROUND_CONSTANT;
    rs->background_color = v3s(1.0f);
    s->camera.kind = CAMERA_LOOKAT;
    s->camera.lookfrom = from;
    s->camera.lookat = at;
    s->camera.vup = up;
    s->camera.vfov_degrees = vfov;
    return s;
}

static uint32_t add_material(glint_scene *s, material m) { return (uint32_t)scene_add_material(s, &m, NULL); }

static void add_sphere(glint_scene *s, vec3 c, float r, uint32_t mat) {
    sphere sp = {c, r, mat};
    CHECK(scene_add_sphere(s, sp));
}

static material lambertian(float a) {
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = v3s(a);
    return m;
}

// Renders with the given thread count; the image's linear pixels stay valid until glint_image_free.
static glint_image *render(glint_scene *s, int threads, glint_render_stats *stats) {
    glint_render_options opt = {threads};
    glint_image *img = NULL;
    glint_error err;
    glint_render_stats local;
    if (!stats) stats = &local;
    glint_status st = glint_render(s, &opt, NULL, NULL, &img, stats, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "render: %s\n", err.message);
    CHECK(stats->discarded_samples == 0);
    return img;
}

static const float *pixels(const glint_image *img, int *w, int *h) {
    const float *rgb;
    glint_image_info(img, w, h, &rgb);
    return rgb;
}

// Largest |pixel - value| over every channel of every pixel.
static double max_deviation(const glint_image *img, double value) {
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    double worst = 0.0;
    for (long i = 0; i < (long)w * h * 3; i++) worst = fmax(worst, fabs(rgb[i] - value));
    return worst;
}

// White furnace: in a uniform background of radiance 1, albedo-1 Lambertian and clear glass objects
// conserve energy exactly, so every sample (not only every pixel mean) is 1 unless the depth limit cuts it.
static void test_white_furnace(void) {
    glint_scene *s = new_scene(24, 24, 8, 50, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 90);
    add_sphere(s, v3(-0.6f, 0, -2), 0.5f, add_material(s, lambertian(1.0f)));
    material glass = material_default(MAT_DIELECTRIC);
    uint32_t g = add_material(s, glass);
    add_sphere(s, v3(0.6f, 0, -2), 0.5f, g);
    add_sphere(s, v3(0, 0.8f, -2.5f), 0.5f, g); // a hollow glass shell
    add_sphere(s, v3(0, 0.8f, -2.5f), -0.4f, g);
    glint_image *img = render(s, 1, NULL);
    CHECK_NEAR(max_deviation(img, 1.0), 0.0, 1e-5);
    glint_image_free(img);
    glint_scene_free(s);

    // Concave arrangements: touching albedo-1 spheres, and one inside a glass ball (rays bounce between them).
    s = new_scene(24, 24, 8, 1000, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 90);
    uint32_t white = add_material(s, lambertian(1.0f));
    add_sphere(s, v3(-0.5f, 0, -2), 0.5f, white);
    add_sphere(s, v3(0.5f, 0, -2), 0.5f, white);
    add_sphere(s, v3(0, -100.5f, -2), 100, white);
    g = add_material(s, glass);
    add_sphere(s, v3(0, 1.2f, -2.5f), 0.7f, g);
    add_sphere(s, v3(0, 1.2f, -2.5f), 0.3f, white);
    img = render(s, 1, NULL);
    CHECK_NEAR(max_deviation(img, 1.0), 0.0, 1e-5);
    glint_image_free(img);
    glint_scene_free(s);
}

// A convex object in a uniform background: one scatter, then escape, so a sample on a Lambertian of
// albedo a (or a mirror of albedo a) returns exactly a. Also checks the ray count and the depth limit.
static void test_convex_albedo(void) {
    for (int k = 0; k < 2; k++) {
        glint_scene *s = new_scene(16, 16, 4, 50, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 60);
        material m = lambertian(0.5f);
        if (k == 1) {
            m = material_default(MAT_METAL);
            m.albedo = v3s(0.5f);
        }
        add_sphere(s, v3(0, 0, -2), 0.6f, add_material(s, m));
        glint_render_stats st;
        glint_image *img = render(s, 1, &st);
        int w, h;
        const float *rgb = pixels(img, &w, &h);
        CHECK_NEAR(rgb[((h / 2) * w + w / 2) * 3], 0.5, 1e-6); // centre: on the sphere
        CHECK_NEAR(rgb[0], 1.0, 1e-6);                         // corner: the background
        // Every sample is 0.5 (hit) or 1 (miss): count the hits from the pixel means; each hit is 2 rays.
        double hits = 0.0;
        bool in_range = true;
        for (int i = 0; i < w * h; i++) {
            hits += 2.0 * (1.0 - rgb[i * 3]) * s->settings.spp;
            in_range = in_range && rgb[i * 3] >= 0.5f - 1e-6f && rgb[i * 3] <= 1.0f + 1e-6f;
        }
        CHECK(in_range);
        CHECK(st.samples == (uint64_t)(w * h * s->settings.spp));
        CHECK_NEAR((double)st.rays, (double)st.samples + hits, 0.01);
        glint_image_free(img);

        // max_depth counts rays: 1 = the camera ray only (a hit gives black), 0 = nothing at all.
        s->settings.max_depth = 1;
        img = render(s, 1, &st);
        rgb = pixels(img, &w, &h);
        CHECK_NEAR(rgb[((h / 2) * w + w / 2) * 3], 0.0, 0);
        CHECK_NEAR(rgb[0], 1.0, 1e-6);
        CHECK(st.rays == st.samples);
        glint_image_free(img);
        s->settings.max_depth = 0;
        img = render(s, 1, &st);
        CHECK_NEAR(max_deviation(img, 0.0), 0.0, 0);
        CHECK(st.rays == 0);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Spawned rays must not re-hit their own surface: looking down at the book's radius-1000 ground (albedo
// 0.5) in a uniform background, every sample is exactly 0.5; a self-hit would give 0.25 or 0.
static void test_huge_sphere_robust(void) {
    glint_scene *s = new_scene(48, 27, 16, 50, v3(13, 2, 3), v3(0, 0, 0), v3(0, 1, 0), 20);
    s->camera.lookat = v3(6, 0, 1.5f); // every pixel sees the ground (the top row looks 5.7 degrees down)
    add_sphere(s, v3(0, -1000, 0), 1000, add_material(s, lambertian(0.5f)));
    glint_image *img = render(s, 1, NULL);
    CHECK_NEAR(max_deviation(img, 0.5), 0.0, 1e-6);
    glint_image_free(img);
    glint_scene_free(s);
}

// A Lambertian plane under the book's sky, seen from straight above: one bounce with density cos/pi gives
// E[dir.y] = 2/3, so the radiance is albedo * lerp(horizon, zenith, 0.5 (1 + 2/3)) (uniform hemisphere
// sampling would give 3/4 in place of 5/6).
static void test_sky_plane(void) {
    glint_scene *s = new_scene(32, 32, 16, 50, v3(0, 1, 0), v3(0, 0, 0), v3(0, 0, -1), 30);
    s->settings.background = BACKGROUND_SKY;
    add_sphere(s, v3(0, -1000, 0), 1000, add_material(s, lambertian(0.5f)));
    glint_image *img = render(s, 1, NULL);
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    double mean[3] = {0, 0, 0};
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++) mean[c] += (double)rgb[i * 3 + c] / (w * h);
    double t = 0.5 * (1.0 + 2.0 / 3.0);
    const double zenith[3] = {0.5, 0.7, 1.0};
    // Per-sample standard deviation is at most 0.03: 16384 samples give 2.3e-4; allow 5 sigma.
    for (int c = 0; c < 3; c++) CHECK_NEAR(mean[c], 0.5 * ((1 - t) + t * zenith[c]), 1.2e-3);
    glint_image_free(img);
    glint_scene_free(s);
}

// Next-event estimation: a Lambertian plane (black background) lit by a point light straight above the
// viewed point gives albedo/pi * I / d^2; a directional light gives albedo/pi * E * cos; an occluder
// between point and light gives black.
static void test_lights(void) {
    for (int k = 0; k < 4; k++) {
        glint_scene *s = new_scene(8, 8, 4, 50, v3(0, 1, 0), v3(0, 0, 0), v3(0, 0, -1), 2);
        s->settings.background_color = v3s(0.0f);
        add_sphere(s, v3(0, -1000, 0), 1000, add_material(s, lambertian(0.5f)));
        light l = {0};
        double expect;
        if (k == 0 || k == 1) {
            l.kind = LIGHT_POINT;
            l.intensity = v3s(10.0f);
            l.position = v3(0, 2, 0);
            expect = 0.5 / PI * 10.0 / 4.0;
            if (k == 1) {
                add_sphere(s, v3(0, 1.5f, 0), 0.1f, add_material(s, lambertian(1.0f)));
                expect = 0.0;
            }
        } else {
            l.kind = LIGHT_DIRECTIONAL;
            l.intensity = v3s(2.0f);
            l.direction = k == 2 ? v3(0, 3, 0) : v3(1, 1, 0);
            expect = 0.5 / PI * 2.0 * (k == 2 ? 1.0 : sqrt(0.5));
        }
        CHECK(scene_add_light(s, l));
        light ambient = {0};
        ambient.kind = LIGHT_AMBIENT; // ignored by the path tracer
        ambient.intensity = v3s(0.5f);
        CHECK(scene_add_light(s, ambient));
        glint_render_stats st;
        glint_image *img = render(s, 1, &st);
        // The footprint is ~0.03 wide, so 1/d^3 varies by < 0.05% over the image.
        CHECK_NEAR(max_deviation(img, expect), 0.0, 1e-3 * expect + 1e-7);
        // One shadow ray a sample from the plane (the occluder's lit side may add a few of its own).
        CHECK(k == 1 ? st.shadow_rays >= st.samples : st.shadow_rays == st.samples);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Emitters: seen from outside (front) they show their emission; from inside only when two-sided, or when
// the sphere has a negative radius (its outward normal points in).
static void test_emission(void) {
    const struct { float radius; bool two_sided; bool camera_inside; double expect; } cases[] = {
        {0.5f, false, false, 3.0}, {5.0f, false, true, 0.0}, {5.0f, true, true, 3.0}, {-5.0f, false, true, 3.0}};
    for (int k = 0; k < 4; k++) {
        glint_scene *s = new_scene(4, 4, 2, 50, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 5);
        s->settings.background_color = v3s(0.0f);
        material m = material_default(MAT_DIFFUSE_LIGHT);
        m.emission = v3s(3.0f);
        m.two_sided = cases[k].two_sided;
        add_sphere(s, cases[k].camera_inside ? v3(0, 0, 0) : v3(0, 0, -3), cases[k].radius, add_material(s, m));
        glint_image *img = render(s, 1, NULL);
        CHECK_NEAR(max_deviation(img, cases[k].expect), 0.0, 1e-6);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// A small scene with every material, a sky and defocus blur (for convergence and determinism).
static glint_scene *mixed_scene(int w, int h, int spp, uint64_t seed) {
    glint_scene *s = new_scene(w, h, spp, 50, v3(0, 0.5f, 1), v3(0, 0, -1), v3(0, 1, 0), 70);
    s->settings.background = BACKGROUND_SKY;
    s->settings.seed = seed;
    s->camera.defocus_angle_degrees = 2.0f;
    s->camera.focus_distance = 2.0f;
    add_sphere(s, v3(0, -100.5f, -1), 100, add_material(s, lambertian(0.5f)));
    material brown = material_default(MAT_LAMBERTIAN);
    brown.albedo = v3(0.4f, 0.2f, 0.1f);
    add_sphere(s, v3(-1, 0, -1), 0.5f, add_material(s, brown));
    material glass = material_default(MAT_DIELECTRIC);
    add_sphere(s, v3(0, 0, -1), 0.5f, add_material(s, glass));
    material metal = material_default(MAT_METAL);
    metal.albedo = v3(0.8f, 0.6f, 0.2f);
    metal.fuzz = 0.3f;
    add_sphere(s, v3(1, 0, -1), 0.5f, add_material(s, metal));
    return s;
}

static double rms_difference(const glint_image *a, const glint_image *b) {
    int w, h;
    const float *pa = pixels(a, &w, &h), *pb = pixels(b, &w, &h);
    double sum = 0.0;
    for (long i = 0; i < (long)w * h * 3; i++) sum += (pa[i] - pb[i]) * (double)(pa[i] - pb[i]);
    return sqrt(sum / (w * h * 3));
}

// Monte Carlo error falls like 1/sqrt(spp): the least-squares slope of log RMS error (against an
// independent high-spp render) over log spp lies in [-0.65, -0.35].
static void test_convergence(void) {
    glint_scene *ref_scene = mixed_scene(16, 9, 2048, 1);
    glint_image *ref = render(ref_scene, 0, NULL);
    const int spps[] = {4, 16, 64, 256};
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 4;
    for (int i = 0; i < n; i++) {
        glint_scene *s = mixed_scene(16, 9, spps[i], 2);
        glint_image *img = render(s, 0, NULL);
        double x = log(spps[i]), y = log(rms_difference(img, ref));
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        glint_image_free(img);
        glint_scene_free(s);
    }
    double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    if (slope < -0.65 || slope > -0.35) fprintf(stderr, "convergence slope %.3f\n", slope);
    CHECK(slope >= -0.65 && slope <= -0.35);
    glint_image_free(ref);
    glint_scene_free(ref_scene);
}

// The same bytes for 1 and 2 threads and for two runs.
static void test_determinism(void) {
    glint_image *imgs[3];
    const int threads[3] = {1, 2, 1};
    for (int i = 0; i < 3; i++) {
        glint_scene *s = mixed_scene(40, 23, 3, 7); // 40x23: partial tiles at the edges
        imgs[i] = render(s, threads[i], NULL);
        glint_scene_free(s);
    }
    int w, h;
    const float *p0 = pixels(imgs[0], &w, &h);
    CHECK(memcmp(p0, pixels(imgs[1], &w, &h), sizeof(float) * 3 * (size_t)(w * h)) == 0);
    CHECK(memcmp(p0, pixels(imgs[2], &w, &h), sizeof(float) * 3 * (size_t)(w * h)) == 0);
    bool same_bytes = true;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) same_bytes = same_bytes && glint_image_byte(imgs[0], x, y, c) == glint_image_byte(imgs[1], x, y, c);
    CHECK(same_bytes);
    // A different seed gives a different image.
    glint_scene *s = mixed_scene(40, 23, 3, 8);
    glint_image *other = render(s, 1, NULL);
    CHECK(memcmp(p0, pixels(other, &w, &h), sizeof(float) * 3 * (size_t)(w * h)) != 0);
    glint_image_free(other);
    glint_scene_free(s);
    for (int i = 0; i < 3; i++) glint_image_free(imgs[i]);
}

int main(void) {
    test_white_furnace();
    test_convex_albedo();
    test_huge_sphere_robust();
    test_sky_plane();
    test_lights();
    test_emission();
    test_convergence();
    test_determinism();
    return check_summary();
}
