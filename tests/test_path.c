// test_path.c — the path integrator against scenes whose exact radiance is known (furnaces, a sky-lit
// plane, point and directional lights, a plane under a quad light or a triangle light), its depth limit and
// ray counts, textures, emitting quads, light sampling of emissive mesh triangles (the OBJ Cornell box's
// noise), robustness on a huge sphere, big quads and transformed meshes, convergence as 1/sqrt(spp), and
// byte-identical images for any thread count.
#include "check.h"
#include "glint.h"
#include "accel/bvh.h"
#include "integrator/light_sampler.h"
#include "render/frame.h"
#include "render/render.h"
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

static void add_quad(glint_scene *s, vec3 q, vec3 u, vec3 v, uint32_t mat) {
    quad qd;
    CHECK(quad_make(q, u, v, mat, &qd));
    CHECK(scene_add_quad(s, qd));
}

static uint32_t add_texture(glint_scene *s, texture t) {
    long i = scene_add_texture(s, &t, NULL);
    CHECK(i >= 0);
    return (uint32_t)i;
}

static bool without_nee; // the next render() samples no area lights (set by the scene builders)
static unsigned with_aovs; // the AOV planes (glint_aov bits) the next render() makes
static accel_build_options build_knobs; // how the next render() builds its BVH (stream_min_bytes, ...)

static material lambertian(float a) {
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = v3s(a);
    return m;
}

// The closed-form light tests' set-up: a Lambertian floor of albedo rho seen from just below the light
// (added by the caller) at y = 1, black background, with or without light sampling.
static glint_scene *plane_under_light(int nee, float rho) {
    glint_scene *s = new_scene(48, 48, nee ? 16 : 256, 50, v3(0, 0.8f, 0.6f), v3(0, 0, 0), v3(0, 1, 0), 1);
    s->settings.background_color = v3s(0.0f);
    without_nee = !nee;
    add_quad(s, v3(-5, 0, 5), v3(10, 0, 0), v3(0, 0, -10), add_material(s, lambertian(rho)));
    return s;
}

// Renders with the given thread count, without next-event estimation towards area lights when the scene's
// builder set without_nee (the choice holds for that one render); the image's linear pixels stay valid until
// glint_image_free.
static glint_image *render(glint_scene *s, int threads, render_stats *stats) {
    render_options opt = {.threads = threads, .aovs = with_aovs, .integrator = {.no_light_sampling = without_nee},
                          .accel = build_knobs};
    without_nee = false;
    with_aovs = 0;
    build_knobs = (accel_build_options){0};
    glint_image *img = NULL;
    glint_error err;
    render_stats local;
    if (!stats) stats = &local;
    glint_status st = render_scene(s, &opt, NULL, NULL, &img, stats, &err);
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
        render_stats st;
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
// The scene of test_sky_plane, the plane made by add_plane: its image's mean against the exact radiance.
static void check_sky_plane(void (*add_plane)(glint_scene *s, uint32_t mat)) {
    glint_scene *s = new_scene(32, 32, 16, 50, v3(0, 1, 0), v3(0, 0, 0), v3(0, 0, -1), 30);
    s->settings.background = BACKGROUND_SKY;
    add_plane(s, add_material(s, lambertian(0.5f)));
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

static void add_ground_sphere(glint_scene *s, uint32_t mat) { add_sphere(s, v3(0, -1000, 0), 1000, mat); }

static void test_sky_plane(void) { check_sky_plane(add_ground_sphere); }

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
                // A black occluder: a white one would pass light on by way of the plane outside its shadow,
                // which a few samples find or not depending on the random numbers.
                add_sphere(s, v3(0, 1.5f, 0), 0.1f, add_material(s, lambertian(0.0f)));
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
        render_stats st;
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


// Every pixel of an spp-1 image is exactly one of the given colours (each sample is one path); counts how
// many pixels are each. False when some pixel is none of them.
static bool pixels_in(const glint_image *img, const vec3 *colors, int n, long *count) {
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    for (int k = 0; k < n; k++) count[k] = 0;
    for (int i = 0; i < w * h; i++) {
        int k = 0;
        while (k < n && !(rgb[i * 3] == colors[k].x && rgb[i * 3 + 1] == colors[k].y && rgb[i * 3 + 2] == colors[k].z)) k++;
        if (k == n) {
            fprintf(stderr, "pixel %d = (%.9g, %.9g, %.9g) is none of the expected colours\n", i, rgb[i * 3],
                    rgb[i * 3 + 1], rgb[i * 3 + 2]);
            return false;
        }
        count[k]++;
    }
    return true;
}

// A textured Lambertian in the white furnace: a checker sphere and a checker quad (convex: one scatter,
// then the background) give every sample exactly the albedo of the checker cell it hit, and both cells show.
static void test_textured_furnace(void) {
    const vec3 even = v3(0.2f, 0.4f, 0.6f), odd = v3(0.9f, 0.5f, 0.1f);
    for (int quad_kind = 0; quad_kind < 2; quad_kind++) {
        glint_scene *s = new_scene(32, 32, 1, 50, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 40);
        material m = lambertian(0.7f); // replaced by the texture
        m.albedo_texture = (int32_t)add_texture(s, texture_checker(0.25f, even, odd));
        uint32_t mat = add_material(s, m);
        if (quad_kind) add_quad(s, v3(-3, -3, -2), v3(6, 0, 0), v3(0, 6, -0.5f), mat);
        else add_sphere(s, v3(0, 0, -3), 1.2f, mat);
        glint_image *img = render(s, 1, NULL);
        const vec3 colors[3] = {even, odd, v3s(1.0f)};
        long count[3];
        CHECK(pixels_in(img, colors, 3, count));
        CHECK(count[0] > 32 * 32 / 8 && count[1] > 32 * 32 / 8); // both cells are seen, many times
        CHECK(quad_kind ? count[2] == 0 : count[2] > 0);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Emitting quads: the front side (where u x v points) shows the emission, the back only when two-sided;
// an emission texture multiplies the emission. Black background, so nothing else adds light.
static void test_quad_emission(void) {
    const struct { bool flip, two_sided, textured; float expect[3]; } cases[] = {
        {false, false, false, {3, 3, 3}},
        {true, false, false, {0, 0, 0}},
        {true, true, false, {3, 3, 3}},
        {false, false, true, {1.5f, 3, 6}},
    };
    for (int k = 0; k < 4; k++) {
        glint_scene *s = new_scene(4, 4, 2, 50, v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0), 20);
        s->settings.background_color = v3s(0.0f);
        material m = material_default(MAT_DIFFUSE_LIGHT);
        m.emission = v3s(3.0f);
        m.two_sided = cases[k].two_sided;
        if (cases[k].textured) m.emission_texture = (int32_t)add_texture(s, texture_solid(v3(0.5f, 1.0f, 2.0f)));
        uint32_t mat = add_material(s, m);
        vec3 u = v3(4, 0, 0), v = v3(0, 4, 0); // u x v = +z: towards the camera
        if (cases[k].flip) add_quad(s, v3(-2, -2, -3), v, u, mat);
        else add_quad(s, v3(-2, -2, -3), u, v, mat);
        glint_image *img = render(s, 1, NULL);
        int w, h;
        const float *rgb = pixels(img, &w, &h);
        double worst = 0.0;
        for (int i = 0; i < w * h; i++)
            for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(rgb[i * 3 + c] - cases[k].expect[c]));
        CHECK_NEAR(worst, 0.0, 1e-6);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Form factor from a point to a parallel rectangle a x b at height h with one corner straight above it.
static double corner_form_factor(double a, double b, double h) {
    double x = a / h, y = b / h, sx = sqrt(1.0 + x * x), sy = sqrt(1.0 + y * y);
    return (x / sx * atan(y / sx) + y / sy * atan(x / sy)) / (2.0 * PI);
}

// Mean of every channel of every pixel, and its standard error from the spread of the pixel means (the
// pixels are independent estimates of the same value).
static void image_mean(const glint_image *img, double *mean, double *stderr_of_mean) {
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    int n = w * h;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; i++) {
        double v = rgb[i * 3 + 1];
        sum += v;
        sum2 += v * v;
    }
    *mean = sum / n;
    *stderr_of_mean = sqrt(fmax(0.0, sum2 / n - *mean * *mean) / (n - 1));
}

// A Lambertian plane (albedo rho, black background) under a square light of radiance Le facing it: at the
// point below the light's centre the radiance is rho Le F, F the form factor of the square (four corner
// rectangles). Light sampling with MIS and BSDF sampling alone must both converge to it: an error in a pdf,
// a missing cosine or a double-counted light would be off by far more than the tolerance. Light sampling
// must also be much less noisy. Second layout: the square split into two halves of radiance 2 and 6 (lights
// chosen by power), the brighter one two-sided and turned upside down (its back faces the plane).
static void test_quad_light_irradiance(void) {
    const double rho = 0.5, half = 0.5, height = 1.0, fc = corner_form_factor(half, half, height);
    const float h = (float)height, a = (float)half;
    for (int layout = 0; layout < 2; layout++) {
        double exact = layout ? rho * (2.0 * 2.0 * fc + 6.0 * 2.0 * fc) : rho * 4.0 * 4.0 * fc;
        double mean[2], se[2];
        for (int nee = 0; nee < 2; nee++) {
            // The camera looks at the plane's centre from below the light: a 1-degree view spans about 0.02,
            // where the irradiance varies by less than 1e-4 relative.
            glint_scene *s = plane_under_light(nee, (float)rho);
            material lamp = material_default(MAT_DIFFUSE_LIGHT);
            if (layout == 0) {
                lamp.emission = v3s(4.0f);
                // u x v = (1,0,0) x (0,0,1) = (0,-1,0): the front faces down, towards the plane.
                add_quad(s, v3(-a, h, -a), v3(2 * a, 0, 0), v3(0, 0, 2 * a), add_material(s, lamp));
            } else {
                lamp.emission = v3s(2.0f);
                add_quad(s, v3(-a, h, -a), v3(a, 0, 0), v3(0, 0, 2 * a), add_material(s, lamp));
                lamp.emission = v3s(6.0f);
                lamp.two_sided = true;
                add_quad(s, v3(0, h, -a), v3(0, 0, 2 * a), v3(a, 0, 0), add_material(s, lamp)); // faces up
            }
            render_stats st;
            glint_image *img = render(s, 0, &st);
            image_mean(img, &mean[nee], &se[nee]);
            printf("quad light %d: %s: %.5f +- %.5f (exact %.5f), %llu rays, %llu shadow rays\n", layout,
                   nee ? "light sampling + MIS" : "BSDF sampling only", mean[nee], se[nee], exact,
                   (unsigned long long)st.rays, (unsigned long long)st.shadow_rays);
            CHECK(nee ? st.shadow_rays == st.samples : st.shadow_rays == 0); // one light sample at the plane
            CHECK(se[nee] < 0.003 * exact); // the comparison is tight enough to mean something
            CHECK_NEAR(mean[nee], exact, 5.0 * se[nee]);
            glint_image_free(img);
            glint_scene_free(s);
        }
        CHECK_NEAR(mean[0], mean[1], 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
        CHECK(se[1] * sqrt(16.0) < 0.5 * se[0] * sqrt(256.0)); // per sample, light sampling is far less noisy
    }
}

// A Lambertian plane (albedo rho, black background) under emissive spheres: a sphere of radiance Le whose
// centre is at distance D from a point, seen at angle theta from its normal and entirely above its horizon,
// gives it irradiance pi Le (R / D)^2 cos(theta), so the radiance there is rho Le (R / D)^2 cos(theta).
// Light sampling (cones towards the spheres, chosen by power) with MIS, and BSDF sampling alone, must both
// converge to it. Second layout: a dimmer sphere off to the side too, and the bright one a hollow shell
// (negative radius: its emitting side faces inwards, so it lights nothing outside it but its back: black).
static void test_sphere_light_irradiance(void) {
    const double rho = 0.5, radius = 0.6, height = 1.5, side_x = 2.0, side_r = 0.3;
    const double side_d2 = side_x * side_x + height * height;
    const double side = rho * 2.0 * (side_r * side_r / side_d2) * (height / sqrt(side_d2));
    for (int layout = 0; layout < 2; layout++) {
        double exact = rho * 4.0 * (radius / height) * (radius / height);
        if (layout) exact = side; // the shell emits inwards only
        double mean[2], se[2];
        for (int nee = 0; nee < 2; nee++) {
            glint_scene *s = plane_under_light(nee, (float)rho);
            material lamp = material_default(MAT_DIFFUSE_LIGHT);
            lamp.emission = v3s(4.0f);
            add_sphere(s, v3(0, (float)height, 0), layout ? (float)-radius : (float)radius, add_material(s, lamp));
            if (layout) {
                lamp.emission = v3s(2.0f);
                add_sphere(s, v3((float)side_x, (float)height, 0), (float)side_r, add_material(s, lamp));
            }
            render_stats st;
            glint_image *img = render(s, 0, &st);
            image_mean(img, &mean[nee], &se[nee]);
            printf("sphere light %d: %s: %.5f +- %.5f (exact %.5f), %llu rays, %llu shadow rays\n", layout,
                   nee ? "light sampling + MIS" : "BSDF sampling only", mean[nee], se[nee], exact,
                   (unsigned long long)st.rays, (unsigned long long)st.shadow_rays);
            CHECK(nee ? st.shadow_rays > 0 : st.shadow_rays == 0);
            CHECK(se[nee] < (layout ? 0.02 : 0.01) * exact); // tight enough to mean something
            CHECK_NEAR(mean[nee], exact, 5.0 * se[nee]);
            glint_image_free(img);
            glint_scene_free(s);
        }
        CHECK_NEAR(mean[0], mean[1], 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
        if (layout == 0) CHECK(se[1] * sqrt(16.0) < 0.5 * se[0] * sqrt(256.0)); // light sampling: far less noise
    }
}

// The cone sampling of a sphere light: every direction it draws meets the sphere at the distance it says,
// and the cone's density integrates to 1 over the cone (its solid angle times the density).
static void test_sphere_cone_sampling(void) {
    const sphere sp = {v3(0.3f, 2.0f, -0.5f), 0.75f, 0};
    const vec3 p = v3(0.1f, -1.0f, 0.2f);
    rng g = rng_for_sample(11, 0, 0);
    int bad = 0;
    float pdf = 0.0f;
    for (int i = 0; i < 10000; i++) {
        vec3 wi;
        float dist;
        if (!light_sphere_sample(&sp, p, rng_float(&g), rng_float(&g), &wi, &dist, &pdf)) { bad++; continue; }
        vec3 x = v3_fma(p, wi, dist);
        bad += fabsf(v3_len(v3_sub(x, sp.center)) - sp.radius) > 1e-4f || fabsf(v3_len(wi) - 1.0f) > 1e-5f;
    }
    CHECK(bad == 0);
    double d = v3_len(v3_sub(sp.center, p)), cos_max = sqrt(1.0 - sp.radius * sp.radius / (d * d));
    CHECK_NEAR(pdf * 2.0 * PI * (1.0 - cos_max), 1.0, 1e-4);
    CHECK_NEAR(light_sphere_pdf(&sp, p), pdf, 1e-6 * pdf);
    vec3 wi;
    float dist;
    CHECK(!light_sphere_sample(&sp, sp.center, 0.5f, 0.5f, &wi, &dist, &pdf)); // inside: no cone
    CHECK(light_sphere_pdf(&sp, sp.center) == 0.0f);
}

// The Cornell box of "The Rest of Your Life" (its box axis-aligned, a white sphere beside it) at 12 x 12:
// light sampling changes the noise, not the mean, so both estimators' image means agree within their
// standard errors (about 1%: this checks a scene of many bounces; the plane under a light above is the
// precise test).
static glint_scene *tiny_cornell(int spp, bool nee, uint64_t seed) {
    // Looking below the light (at its own pixels both estimators are as noisy as the jitter across its edge).
    glint_scene *s = new_scene(12, 12, spp, 50, v3(278, 278, -800), v3(278, 150, 0), v3(0, 1, 0), 30);
    s->settings.background_color = v3s(0.0f);
    without_nee = !nee;
    s->settings.seed = seed;
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
    quad box[6];
    CHECK(quad_box(v3(130, 0, 65), v3(295, 165, 230), w, box));
    for (int i = 0; i < 6; i++) CHECK(scene_add_quad(s, box[i]));
    add_sphere(s, v3(370, 90, 370), 90, w);
    return s;
}

// The green channel's mean over two renders of one scene with different seeds (freed here), and the standard
// error of that mean from the two renders' pixel differences.
static void green_mean_se(glint_image *img[2], double *mean, double *se) {
    int w, h;
    const float *a = pixels(img[0], &w, &h), *b = pixels(img[1], &w, &h);
    double sum = 0.0, diff2 = 0.0;
    for (int i = 0; i < w * h; i++) {
        sum += (double)a[i * 3 + 1] + b[i * 3 + 1];
        diff2 += ((double)a[i * 3 + 1] - b[i * 3 + 1]) * ((double)a[i * 3 + 1] - b[i * 3 + 1]);
    }
    *mean = sum / (2.0 * w * h);
    *se = sqrt(diff2) / (2.0 * w * h);
    for (int k = 0; k < 2; k++) glint_image_free(img[k]);
}

// The tiny box rendered twice with independent seeds: the mean of the green channel over both, and its
// standard error from the pixels' differences (each pixel's variance is about (a - b)^2 / 2).
static void cornell_mean(int spp, bool nee, double *mean, double *se) {
    glint_image *img[2];
    for (int k = 0; k < 2; k++) {
        glint_scene *s = tiny_cornell(spp, nee, 100 + (uint64_t)k);
        img[k] = render(s, 0, NULL);
        glint_scene_free(s);
    }
    green_mean_se(img, mean, se);
}

static void test_cornell_estimators_agree(void) {
    double mean[2], se[2];
    cornell_mean(1024, false, &mean[0], &se[0]);
    cornell_mean(32, true, &mean[1], &se[1]);
    printf("tiny cornell box, green channel mean: BSDF sampling %.5f +- %.5f, light sampling %.5f +- %.5f\n",
           mean[0], se[0], mean[1], se[1]);
    CHECK(se[0] < 0.02 * mean[0] && se[1] < 0.02 * mean[1]);
    CHECK_NEAR(mean[0], mean[1], 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
    CHECK(se[1] * sqrt(32.0) < 0.25 * se[0] * sqrt(1024.0)); // per sample, a quarter of the noise at most
}

// Mean and standard error of the green channel over two seeds of a small Cornell box with a glass sphere,
// the sphere marked "importance" (book 3's mixture density) or not.
static void glass_cornell_mean(bool importance, double *mean, double *se) {
    glint_image *img[2];
    for (int k = 0; k < 2; k++) {
        char text[2048];
        snprintf(text, sizeof text,
                 "{\"render\": {\"width\": 20, \"height\": 20, \"spp\": 256, \"max_depth\": 12, \"seed\": %d, "
                 "\"integrator\": \"path\"},"
                 " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [278, 278, -800], \"lookat\": [278, 278, 0], "
                 "\"vfov\": 40},"
                 " \"materials\": {\"w\": {\"type\": \"lambertian\", \"albedo\": 0.73}, \"g\": {\"type\": "
                 "\"lambertian\", \"albedo\": [0.12, 0.45, 0.15]}, \"l\": {\"type\": \"diffuse_light\", "
                 "\"emission\": 15}, \"glass\": {\"type\": \"dielectric\", \"ior\": 1.5}},"
                 " \"objects\": [{\"type\": \"quad\", \"q\": [555, 0, 0], \"u\": [0, 0, 555], \"v\": [0, 555, 0], "
                 "\"material\": \"g\"}, {\"type\": \"quad\", \"q\": [0, 0, 555], \"u\": [0, 0, -555], \"v\": [0, 555, 0], "
                 "\"material\": \"w\"}, {\"type\": \"quad\", \"q\": [0, 0, 555], \"u\": [555, 0, 0], \"v\": [0, 0, -555], "
                 "\"material\": \"w\"}, {\"type\": \"quad\", \"q\": [0, 555, 0], \"u\": [555, 0, 0], \"v\": [0, 0, 555], "
                 "\"material\": \"w\"}, {\"type\": \"quad\", \"q\": [213, 554, 227], \"u\": [130, 0, 0], \"v\": [0, 0, 105], "
                 "\"material\": \"l\"}, {\"type\": \"sphere\", \"center\": [278, 120, 278], \"radius\": 110, "
                 "\"material\": \"glass\", \"importance\": %s}]}",
                 7 + k, importance ? "true" : "false");
        glint_scene *sc = NULL;
        glint_error err;
        CHECK(glint_scene_parse("glass-cornell.json", text, strlen(text), &sc, &err) == GLINT_OK);
        if (!sc) {
            fprintf(stderr, "%s\n", err.message);
            *mean = *se = 0.0;
            return;
        }
        CHECK(sc->importance_sphere_count == (importance ? 1u : 0u));
        img[k] = render(sc, 0, NULL);
        glint_scene_free(sc);
    }
    green_mean_se(img, mean, se);
}

// Book 3's glass sphere "sampled as a light": diffuse bounces draw half their directions towards it, weighted
// by the mixture density. The estimate must not move (the same mean as the plain estimator, within noise).
static void test_importance_sphere(void) {
    double mean[2], se[2];
    glass_cornell_mean(false, &mean[0], &se[0]);
    glass_cornell_mean(true, &mean[1], &se[1]);
    printf("glass cornell box, green channel mean: plain %.5f +- %.5f, glass sphere as importance target %.5f +- %.5f\n",
           mean[0], se[0], mean[1], se[1]);
    CHECK(mean[0] > 0.0 && se[0] < 0.03 * mean[0] && se[1] < 0.03 * mean[1]);
    CHECK_NEAR(mean[0], mean[1], 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
}

// Places a mesh of the given vertices and triangles (counter-clockwise seen from outside, no normals or
// texture coordinates) once, with the object-to-world matrix m.
static void add_mesh_instance(glint_scene *s, const vec3 *pos, int np, const int (*tri)[3], int nt, uint32_t mat,
                              mat4 m) {
    scene_mesh sm;
    memset(&sm, 0, sizeof sm);
    mesh *g = &sm.geometry;
    g->position_count = (size_t)np;
    g->triangle_count = (size_t)nt;
    g->positions = malloc((size_t)np * sizeof *g->positions);
    g->triangles = malloc((size_t)nt * sizeof *g->triangles);
    if (!g->positions || !g->triangles) abort();
    for (int i = 0; i < np; i++) g->positions[i] = pos[i];
    for (int i = 0; i < nt; i++) {
        mesh_triangle t = {{tri[i][0], tri[i][1], tri[i][2]}, -1};
        g->triangles[i] = t;
    }
    mesh_compute_bounds(g);
    sm.default_material = mat;
    long mi = scene_add_mesh(s, &sm);
    CHECK(mi >= 0);
    instance in;
    in.kind = INSTANCE_MESH;
    in.index = (uint32_t)mi;
    in.material = -1;
    in.motion = 0; // it does not move
    CHECK(transform_make(&m, &in.xf));
    CHECK(scene_add_instance(s, in));
}

static void add_ground_quad(glint_scene *s, uint32_t mat) {
    add_quad(s, v3(-50, 0, 50), v3(100, 0, 0), v3(0, 0, -100), mat);
}

// The lean vertex at quads and meshes (surface_at_flat, the direction n + u left unnormalised), which scenes
// without lights take: in the white furnace an open box of albedo-1 Lambertian quads holding flat-shaded
// tetrahedra (one placed once, flattened into the world BVH; one placed twice, its BVH shared) conserves energy,
// so every sample is 1; and test_sky_plane's plane as a quad gives the same exact radiance.
static void test_lean_quads_and_meshes(void) {
    glint_scene *s = new_scene(24, 24, 8, 1000, v3(0, 1.2f, 1.5f), v3(0, 0.3f, -1), v3(0, 1, 0), 70);
    uint32_t white = add_material(s, lambertian(1.0f));
    add_quad(s, v3(-2, 0, 1), v3(4, 0, 0), v3(0, 0, -4), white);     // floor, facing up
    add_quad(s, v3(-2, 0, -3), v3(4, 0, 0), v3(0, 2, 0), white);     // back wall
    add_quad(s, v3(-2, 0, 1), v3(0, 0, -4), v3(0, 2, 0), white);     // left wall, facing +x
    add_quad(s, v3(2, 0, -3), v3(0, 0, 4), v3(0, 2, 0), white);      // right wall, facing -x
    const vec3 pos[4] = {v3(-0.5f, 0, -0.5f), v3(0.5f, 0, -0.5f), v3(0, 0, 0.5f), v3(0, 0.8f, 0)};
    const int tri[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    add_mesh_instance(s, pos, 4, tri, 4, white, mat4_translate(v3(-0.9f, 0, -1.2f)));
    add_mesh_instance(s, pos, 4, tri, 4, white, mat4_translate(v3(0.9f, 0, -1.8f)));
    add_mesh_instance(s, pos, 4, tri, 4, white, mat4_translate(v3(0.9f, 0, -0.6f)));
    glint_image *img = render(s, 1, NULL);
    CHECK_NEAR(max_deviation(img, 1.0), 0.0, 1e-5);
    glint_image_free(img);
    glint_scene_free(s);
    check_sky_plane(add_ground_quad);
}

// The plane under a square light of test_quad_light_irradiance, the light now two emissive triangles of a
// mesh instance: the same exact radiance rho Le F with light sampling and with BSDF sampling alone. Layouts:
// world-space vertices wound to face down; a unit square in the xy plane (facing +z) placed by a scale, a
// rotation and a translation; the first mesh under a mirror (x -> -x), whose emitting side is where the
// hit's transformed normal points (down), not where the world-space winding does.
static void test_triangle_light_irradiance(void) {
    const double rho = 0.5, half = 0.5, height = 1.0, fc = corner_form_factor(half, half, height);
    const double exact = rho * 4.0 * 4.0 * fc;
    const float h = (float)height, a = (float)half;
    const vec3 world_square[4] = {{-a, h, -a}, {a, h, -a}, {a, h, a}, {-a, h, a}}; // (p1-p0) x (p2-p0) is -y
    const vec3 unit_square[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};      // +z
    const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int layout = 0; layout < 3; layout++) {
        double mean[2], se[2];
        for (int nee = 0; nee < 2; nee++) {
            glint_scene *s = plane_under_light(nee, (float)rho);
            material lamp = material_default(MAT_DIFFUSE_LIGHT);
            lamp.emission = v3s(4.0f);
            uint32_t lm = add_material(s, lamp);
            if (layout == 1) {
                // Rotating +90 degrees about x takes (x, y, 0) to (x, 0, y) and +z to -y: facing down.
                mat4 sc = mat4_scale(v3s(2 * a)), rot = mat4_rotate(v3(1, 0, 0), 90.0f);
                mat4 tr = mat4_translate(v3(-a, h, -a)), rs = mat4_mul(&rot, &sc);
                add_mesh_instance(s, unit_square, 4, tris, 2, lm, mat4_mul(&tr, &rs));
            } else {
                add_mesh_instance(s, world_square, 4, tris, 2, lm, layout ? mat4_scale(v3(-1, 1, 1)) : mat4_identity());
            }
            render_stats st;
            glint_image *img = render(s, 0, &st);
            image_mean(img, &mean[nee], &se[nee]);
            printf("triangle light %d: %s: %.5f +- %.5f (exact %.5f), %llu rays, %llu shadow rays\n", layout,
                   nee ? "light sampling + MIS" : "BSDF sampling only", mean[nee], se[nee], exact,
                   (unsigned long long)st.rays, (unsigned long long)st.shadow_rays);
            CHECK(nee ? st.shadow_rays == st.samples : st.shadow_rays == 0); // one light sample at the plane
            CHECK(se[nee] < 0.003 * exact);
            CHECK_NEAR(mean[nee], exact, 5.0 * se[nee]);
            glint_image_free(img);
            glint_scene_free(s);
        }
        CHECK_NEAR(mean[0], mean[1], 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
        CHECK(se[1] * sqrt(16.0) < 0.5 * se[0] * sqrt(256.0)); // per sample, light sampling is far less noisy
    }
}

// The Cornell box from the real OBJ/MTL (scenes/cornell-box-obj.json, its light a Ke pair of triangles) at
// 24 x 24, with the given samples per pixel, depth, seed and light sampling or not.
static glint_image *cornell_obj(int spp, int depth, uint64_t seed, bool nee) {
    char path[4096];
    snprintf(path, sizeof path, "%s/scenes/cornell-box-obj.json", GLINT_SOURCE_DIR);
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_load(path, &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        exit(1);
    }
    s->settings.width = s->settings.height = 24;
    s->settings.spp = spp;
    s->settings.max_depth = depth;
    s->settings.seed = seed;
    without_nee = !nee;
    glint_image *img = render(s, 0, NULL);
    glint_scene_free(s);
    return img;
}

// The OBJ Cornell box's noise: the RMS difference between two seeds' images, over the pixels that do not
// see the light itself (found by a depth-1 render: there both estimators are as noisy as the jitter across
// the light's edge), must fall by a clear factor when the emissive triangles are sampled. (Their means are
// not compared: at 4 spp BSDF sampling's is carried by rare hits of the small light; the plane under a
// triangle light above checks that both estimators converge to the same value.)
static void test_cornell_obj_noise(void) {
    glint_image *direct = cornell_obj(64, 1, 1, false);
    int w, h;
    const float *mask = pixels(direct, &w, &h);
    double rms[2];
    for (int nee = 0; nee < 2; nee++) {
        glint_image *img[2] = {cornell_obj(4, 50, 7, nee), cornell_obj(4, 50, 8, nee)};
        const float *a = pixels(img[0], &w, &h), *b = pixels(img[1], &w, &h);
        double diff2 = 0.0;
        long n = 0;
        for (long i = 0; i < (long)w * h; i++) {
            if (mask[i * 3] + mask[i * 3 + 1] + mask[i * 3 + 2] > 0.0f) continue;
            for (int c = 0; c < 3; c++) {
                double d = (double)a[i * 3 + c] - b[i * 3 + c];
                diff2 += d * d;
            }
            n++;
        }
        CHECK(n > w * h / 2);
        rms[nee] = sqrt(diff2 / (3.0 * (double)n));
        for (int k = 0; k < 2; k++) glint_image_free(img[k]);
    }
    glint_image_free(direct);
    printf("cornell-box-obj 24x24 at 4 spp, off the light: RMS difference of two seeds %.4f with BSDF sampling, "
           "%.4f with light sampling (%.1fx less)\n",
           rms[0], rms[1], rms[0] / rms[1]);
    CHECK(rms[1] * 4.0 < rms[0]);
}

// Spawned rays must not re-hit their own surface on big flat geometry either. Big floors seen around the
// origin, where the hit points are small but the primitive's corners are large: a 2000-wide quad (flat, and
// tilted so that its coordinates are not exact), a unit square mesh scaled to 2000 and tilted by its
// instance, and a square mesh whose object-space coordinates are large (1000..3000) translated back to the
// origin. Far from the origin: a box of quads and an octahedron mesh under a rotating, scaling transform.
// Convex, albedo 0.5, white background: each spp-1 pixel is exactly 0.5 (hit) or 1 (miss); a self-hit
// would give 0.25 or 0.
static void test_flat_robust(void) {
    const vec3 square[4] = {{-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}};
    const vec3 far_square[4] = {{1000, 0, -1000}, {1000, 0, 1000}, {3000, 0, 1000}, {3000, 0, -1000}};
    const int square_tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
    const vec3 octahedron[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    int octahedron_tris[8][3];
    for (int i = 0; i < 8; i++) {
        // Face (±x, ±y, ±z), wound so that its normal points outwards.
        int sx = i & 1, sy = (i >> 1) & 1, sz = (i >> 2) & 1;
        bool flip = (sx + sy + sz) & 1;
        octahedron_tris[i][0] = sx;
        octahedron_tris[i][1] = flip ? 4 + sz : 2 + sy;
        octahedron_tris[i][2] = flip ? 2 + sy : 4 + sz;
    }
    for (int k = 0; k < 6; k++) {
        bool near = k < 4;
        vec3 from = near ? v3(3, 2, 3) : v3(900, 700, -500), at = near ? v3(0, 0, 0) : v3(500, 300, -300);
        glint_scene *s = new_scene(64, 36, 1, 50, from, at, v3(0, 1, 0), near ? 20 : 30);
        uint32_t mat = add_material(s, lambertian(0.5f));
        if (k == 0) add_quad(s, v3(-1000, 0, -1000), v3(0, 0, 2000), v3(2000, 0, 0), mat);
        if (k == 1) add_quad(s, v3(-1000, -17.3f, -1000), v3(0, 14.6f, 2000), v3(2000, 20, 0), mat);
        if (k == 2) {
            mat4 sc = mat4_scale(v3(2000, 1, 2000)), rot = mat4_rotate(v3(1, 0, 0.4f), 1.3f);
            add_mesh_instance(s, square, 4, square_tris, 2, mat, mat4_mul(&rot, &sc));
        }
        if (k == 3) add_mesh_instance(s, far_square, 4, square_tris, 2, mat, mat4_translate(v3(-2000, 0, 0)));
        if (k == 4) {
            quad box[6];
            CHECK(quad_box(v3(350, 150, -450), v3(650, 450, -150), mat, box));
            for (int i = 0; i < 6; i++) CHECK(scene_add_quad(s, box[i]));
        }
        if (k == 5) {
            mat4 sc = mat4_scale(v3(150, 200, 170)), rot = mat4_rotate(v3(1, 1, 0.3f), 33.0f);
            mat4 tr = mat4_translate(v3(500, 300, -300)), rs = mat4_mul(&rot, &sc);
            add_mesh_instance(s, octahedron, 6, (const int (*)[3])octahedron_tris, 8, mat, mat4_mul(&tr, &rs));
        }
        glint_image *img = render(s, 1, NULL);
        const vec3 colors[2] = {v3s(0.5f), v3s(1.0f)};
        long count[2];
        CHECK(pixels_in(img, colors, 2, count));
        CHECK(count[0] > 64 * 36 / 4);
        if (!(count[0] > 64 * 36 / 4)) fprintf(stderr, "flat robustness case %d\n", k);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// Quad lights, textures and instances keep images byte-identical for 1 and 2 threads.
static void test_determinism_quads(void) {
    glint_image *imgs[2];
    for (int i = 0; i < 2; i++) {
        glint_scene *s = tiny_cornell(3, true, 11);
        s->settings.width = 20;
        s->settings.height = 15;
        imgs[i] = render(s, i + 1, NULL);
        glint_scene_free(s);
    }
    int w, h;
    const float *p0 = pixels(imgs[0], &w, &h);
    CHECK(memcmp(p0, pixels(imgs[1], &w, &h), sizeof(float) * 3 * (size_t)(w * h)) == 0);
    for (int i = 0; i < 2; i++) glint_image_free(imgs[i]);
}

// Scenes for the ray streams. Kind 0, lean (no lights to sample, no media): the mixed spheres with a flattened
// mesh (a tetrahedron, mirrored), a ground quad, a textured quad and an emissive quad. Kind 1, lean: the tiny
// Cornell box's quads and a tetrahedron with no sphere, so that the world BVH holds triangle packets alone.
// Kind 2: that box with its sphere, its light sampled (next-event estimation) and a point light. Kind 3: kind 2
// in a chromatic fog, with a denser box of it around the tetrahedron.
static glint_scene *stream_scene(int kind, int depth) {
    bool triangles_only = kind >= 1;
    static const vec3 tetra[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    glint_scene *s;
    if (triangles_only) {
        s = tiny_cornell(5, kind == 2, 3);
        if (kind == 1) s->sphere_count = 0; // the box's sphere goes: quads and triangles only
        light l = {.kind = LIGHT_POINT, .intensity = v3s(20000.0f), .position = v3(100, 400, 200)};
        if (kind >= 2) CHECK(scene_add_light(s, l));
        if (kind == 3) {
            medium fog = {.shape = MEDIUM_BOX, .lo = v3s(-1), .hi = v3s(556), .sigma_s = v3(5e-4f, 1e-3f, 2e-3f),
                          .sigma_t = v3(1e-3f, 1.5e-3f, 2e-3f), .albedo_texture = -1, .g = 0.3f};
            CHECK(scene_add_medium(s, fog));
            fog.lo = v3(280, 180, 80);
            fog.hi = v3(440, 340, 240);
            fog.sigma_s = v3(0.02f, 0.01f, 0.005f);
            fog.sigma_t = v3s(0.02f);
            CHECK(scene_add_medium(s, fog));
        }
        mat4 at = mat4_translate(v3(300, 200, 100)), size = mat4_scale(v3s(120));
        add_mesh_instance(s, tetra, 4, faces, 4, 0, mat4_mul(&at, &size));
    } else {
        s = mixed_scene(40, 23, 5, 9);
        without_nee = true;
        // The ground sphere would be a huge sphere, which the BVH tests after the tree for every ray (no streams):
        // a ground quad instead.
        s->spheres[0] = s->spheres[--s->sphere_count];
        add_quad(s, v3(-5, -0.5f, 1), v3(10, 0, 0), v3(0, 0, -10), 0);
        material lamp = material_default(MAT_DIFFUSE_LIGHT), metal = material_default(MAT_METAL);
        lamp.emission = v3s(4.0f);
        add_quad(s, v3(-3, 2, -4), v3(6, 0, 0), v3(0, 0, 2), add_material(s, lamp));
        material checker = material_default(MAT_LAMBERTIAN);
        checker.albedo_texture = (int)add_texture(s, texture_checker(0.25f, v3s(0.9f), v3(0.1f, 0.2f, 0.5f)));
        add_quad(s, v3(-2, -0.5f, -3), v3(4, 0, 0), v3(0, 2, 0), add_material(s, checker));
        mat4 at = mat4_translate(v3(-0.4f, -0.4f, -0.6f)), size = mat4_scale(v3(-0.4f, 0.4f, 0.4f));
        add_mesh_instance(s, tetra, 4, faces, 4, add_material(s, metal), mat4_mul(&at, &size));
    }
    s->settings.max_depth = depth;
    return s;
}

// The path tracer's streams (path_render_tile_stream_*, forced on small scenes by stream_min_bytes) give the same
// bytes as its paths one by one, with their rays traversed together (forced by interleave_min_bytes) on 1 and 3
// threads and one by one, at depth limits 1, 3 and 50, with and without lights and media, and so do their AOVs. In
// the box of quads and triangles only (kind 1) the streams take their camera rays' hits from packets
// (stream_camera_packets): a path given another lane's first hit fails here. The lean scenes (kinds 0 and 1) also
// with the independent sampler: its lean stream loop is a copy of its own (path_render_tile_stream_lean_pcg).
static void test_streams_same_bytes(void) {
    enum { VARIANTS = 4 }; // paths one by one; streams together on 1 and 3 threads; streams one by one
    for (int run = 0; run < 6; run++) {
        int kind = run % 4;
        sampler_kind sampler = run < 4 ? SAMPLER_SOBOL : SAMPLER_INDEPENDENT;
        for (int d = 0; d < 4; d++) {
            bool aovs = d == 3; // depth 50 again, with every AOV
            const int depths[4] = {1, 3, 50, 50};
            glint_image *img[VARIANTS];
            for (int i = 0; i < VARIANTS; i++) {
                glint_scene *s = stream_scene(kind, depths[d]);
                s->settings.sampler = sampler;
                accel_build_options knobs = {.stream_min_bytes = i == 0 ? SIZE_MAX : 1,
                                             .interleave_min_bytes = i == 3 ? SIZE_MAX : 1};
                if (i == 1 || i == 3) { // the structure this scene renders with does stream (with the SIMD traversal)
                    glint_error err;
                    accel_build_options one = knobs;
                    one.threads = 1;
                    accel *a = frame_accel_build(s, &one, &err);
                    CHECK(a && accel_streams(a) == BVH_SIMD && accel_interleaves(a) == (i == 1 && BVH_SIMD));
                    accel_free(a);
                }
                with_aovs = aovs ? GLINT_AOV_ALL : 0;
                build_knobs = knobs;
                img[i] = render(s, i == 2 ? 3 : 1, NULL);
                glint_scene_free(s);
            }
            int w, h;
            const float *p0 = pixels(img[0], &w, &h);
            CHECK((d == 0 && kind == 1) || max_deviation(img[0], 0.0) > 0.0); // the lean box is dark at depth 1
            size_t bytes = sizeof(float) * 3 * (size_t)(w * h);
            for (int i = 1; i < VARIANTS; i++) {
                CHECK(memcmp(p0, pixels(img[i], &w, &h), bytes) == 0);
                for (unsigned a = 1; aovs && a < GLINT_AOV_ALL; a <<= 1) {
                    int ch = 0;
                    const float *p = glint_image_aov(img[0], (glint_aov)a, &ch);
                    const float *q = glint_image_aov(img[i], (glint_aov)a, NULL);
                    CHECK(p && q && memcmp(p, q, sizeof(float) * (size_t)ch * (size_t)(w * h)) == 0);
                }
            }
            for (int i = 0; i < VARIANTS; i++) glint_image_free(img[i]);
        }
    }
}

int main(void) {
    test_streams_same_bytes();
    test_importance_sphere();
    test_sphere_cone_sampling();
    test_sphere_light_irradiance();
    test_white_furnace();
    test_convex_albedo();
    test_huge_sphere_robust();
    test_sky_plane();
    test_lights();
    test_emission();
    test_textured_furnace();
    test_quad_emission();
    test_quad_light_irradiance();
    test_cornell_estimators_agree();
    test_flat_robust();
    test_triangle_light_irradiance();
    test_lean_quads_and_meshes();
    test_cornell_obj_noise();
    test_convergence();
    test_determinism();
    test_determinism_quads();
    return check_summary();
}
