// test_media.c — participating media: the Henyey–Greenstein phase function and its sampling (normalisation,
// chi-square, moments), boundary segments and the transmittance of slabs, spheres and transformed boundaries
// against exp(-sigma_t d), the free-flight estimator against the analytic answer for a homogeneous slab
// (chromatic and grey), and whole renders: furnaces with media (every pixel 1), an absorbing slab, point and
// directional lights through an absorbing medium (closed form), next-event estimation through media against
// phase sampling alone (same mean, less noise), the Cornell smoke scene byte-identical for 1 and 2 threads.
#include "check.h"
#include "glint.h"
#include "medium/medium.h"
#include "render/render.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static medium box_medium(vec3 lo, vec3 hi, vec3 sigma_a, vec3 sigma_s, float g) {
    medium m = {0};
    m.shape = MEDIUM_BOX;
    m.lo = lo;
    m.hi = hi;
    m.sigma_s = sigma_s;
    m.sigma_t = v3_add(sigma_a, sigma_s);
    m.albedo_texture = -1;
    m.g = g;
    return m;
}

static medium sphere_medium(vec3 c, float r, vec3 sigma_a, vec3 sigma_s, float g) {
    medium m = box_medium(v3s(0), v3s(0), sigma_a, sigma_s, g);
    m.shape = MEDIUM_SPHERE;
    m.center = c;
    m.radius = r;
    return m;
}

// Places m by the object-to-world matrix xf.
static void place(medium *m, mat4 xf) {
    transform t;
    CHECK(transform_make(&xf, &t));
    m->transformed = true;
    m->to_object = t.inv;
}

static bool rel_near(double a, double b, double tol) { return fabs(a - b) <= tol * fabs(b) + 1e-7; }

// ---------------------------------------------------------------------------------------------
// The phase function

// HG integrates to 1; its samples follow it in cos theta (chi-square over 20 bins), their mean cosine is g and
// their azimuth is uniform (no mean sideways component).
static void test_phase_hg(void) {
    // The isotropic shortcut returns what the formula gives (through it with a g too small to change its terms).
    for (int i = 0; i <= 20; i++) {
        float c = -1.0f + 0.1f * (float)i;
        CHECK(phase_hg(0.0f, c) == phase_hg(1e-30f, c));
    }
    const float gs[] = {0.0f, 0.5f, -0.3f, 0.85f};
    vec3 d = v3_unit(v3(0.3f, -0.5f, 0.81f));
    for (size_t k = 0; k < sizeof gs / sizeof gs[0]; k++) {
        float g = gs[k];
        double integral = 0.0;
        const int steps = 200000;
        for (int i = 0; i < steps; i++) integral += 2.0 * PI * phase_hg(g, (float)(-1.0 + (i + 0.5) * 2.0 / steps)) * 2.0 / steps;
        CHECK_NEAR(integral, 1.0, 1e-3);

        enum { BINS = 20, N = 200000 };
        double expect[BINS] = {0}, count[BINS] = {0};
        for (int b = 0; b < BINS; b++)
            for (int i = 0; i < 1000; i++) {
                double c = -1.0 + (b + (i + 0.5) / 1000.0) * 2.0 / BINS;
                expect[b] += 2.0 * PI * phase_hg(g, (float)c) * (2.0 / BINS / 1000.0) * N;
            }
        rng r = rng_for_sample(7, k, 0);
        double sum_cos = 0.0, sum_cos2 = 0.0, bad_len = 0.0;
        vec3 side = v3s(0.0f);
        for (int i = 0; i < N; i++) {
            float a = rng_float(&r), b = rng_float(&r);
            vec3 w = phase_hg_sample(g, d, a, b);
            bad_len = fmax(bad_len, fabs(v3_len(w) - 1.0));
            double c = v3_dot(w, d);
            int bin = (int)((c + 1.0) * 0.5 * BINS);
            count[bin < 0 ? 0 : bin >= BINS ? BINS - 1 : bin]++;
            sum_cos += c;
            sum_cos2 += c * c;
            side = v3_add(side, v3_sub(w, v3_scale(d, (float)c)));
        }
        double chi2 = 0.0;
        for (int b = 0; b < BINS; b++) chi2 += (count[b] - expect[b]) * (count[b] - expect[b]) / expect[b];
        double mean = sum_cos / N, se = sqrt((sum_cos2 / N - mean * mean) / N);
        printf("HG g = %+.2f: chi-square %.1f (19 dof), mean cos %.4f +- %.4f\n", (double)g, chi2, mean, se);
        CHECK(chi2 < 50.0); // p = 0.0001 at 19 degrees of freedom is 47.4... with a little room for the fixed seed
        CHECK(fabs(mean - g) < 4.0 * se + 1e-4);
        CHECK(bad_len < 1e-5);
        CHECK(v3_len(side) / N < 0.01);
    }
}

// ---------------------------------------------------------------------------------------------
// Segments and transmittance

static void check_tr(vec3 got, vec3 sigma_t, double length) {
    CHECK(rel_near(got.x, exp(-sigma_t.x * length), 1e-5));
    CHECK(rel_near(got.y, exp(-sigma_t.y * length), 1e-5));
    CHECK(rel_near(got.z, exp(-sigma_t.z * length), 1e-5));
}

static void test_transmittance(void) {
    vec3 sa = v3(0.3f, 0.7f, 1.1f), ss = v3(0.2f, 0.1f, 0.0f), st = v3_add(sa, ss);
    medium slab = box_medium(v3(0, -100, -100), v3(2, 100, 100), sa, ss, 0);
    // Straight through, obliquely, starting inside, stopping inside, and with a direction of length 2.
    check_tr(medium_transmittance(&slab, 1, v3(-1, 0, 0), v3(1, 0, 0), 0, INFINITY), st, 2.0);
    vec3 oblique = v3_unit(v3(1, 0.5f, 0));
    check_tr(medium_transmittance(&slab, 1, v3(-1, 0, 0), oblique, 0, INFINITY), st, 2.0 * sqrt(1.25));
    check_tr(medium_transmittance(&slab, 1, v3(0.5f, 0, 0), v3(1, 0, 0), 0, INFINITY), st, 1.5);
    check_tr(medium_transmittance(&slab, 1, v3(-1, 0, 0), v3(1, 0, 0), 0, 1.5f), st, 0.5);
    check_tr(medium_transmittance(&slab, 1, v3(-1, 0, 0), v3(2, 0, 0), 0, INFINITY), st, 2.0);
    // Beside it, behind the origin, and a ray parallel to its faces outside it: nothing at all.
    vec3 one = medium_transmittance(&slab, 1, v3(-1, 200, 0), v3(1, 0, 0), 0, INFINITY);
    CHECK(one.x == 1.0f && one.y == 1.0f && one.z == 1.0f);
    one = medium_transmittance(&slab, 1, v3(3, 0, 0), v3(1, 0, 0), 0, INFINITY);
    CHECK(one.x == 1.0f && one.y == 1.0f && one.z == 1.0f);
    one = medium_transmittance(&slab, 1, v3(3, 0, 0), v3(0, 1, 0), 0, INFINITY);
    CHECK(one.x == 1.0f && one.y == 1.0f && one.z == 1.0f);
    // A sphere's chord, from outside and from its centre (the inside of a glass sphere sharing the boundary).
    medium ball = sphere_medium(v3(1, 2, 3), 2, sa, ss, 0);
    check_tr(medium_transmittance(&ball, 1, v3(-5, 2.5f, 3), v3(1, 0, 0), 0, INFINITY), st, 2.0 * sqrt(4.0 - 0.25));
    check_tr(medium_transmittance(&ball, 1, v3(1, 2, 3), v3_unit(v3(1, 1, 1)), 0, INFINITY), st, 2.0);
    float t0, t1;
    CHECK(medium_segment(&ball, v3(-5, 2, 3), v3(1, 0, 0), 0, INFINITY, &t0, &t1) && t0 == 4.0f && t1 == 8.0f);
    // The huge fog sphere of book 2 around the camera.
    medium fog = sphere_medium(v3(0, 0, 0), 5000, v3s(0), v3s(1e-4f), 0);
    check_tr(medium_transmittance(&fog, 1, v3(478, 278, -600), v3(0, 1, 0), 0, INFINITY), v3s(1e-4f),
             sqrt(5000.0 * 5000.0 - 478.0 * 478.0 - 600.0 * 600.0) - 278.0);
    // An ellipsoid (a sphere scaled by 3 along x) and a box rotated 90 degrees about y: x -> z' = -x.
    medium ell = sphere_medium(v3(0, 0, 0), 1, sa, ss, 0);
    place(&ell, mat4_scale(v3(3, 1, 1)));
    check_tr(medium_transmittance(&ell, 1, v3(-10, 0, 0), v3(1, 0, 0), 0, INFINITY), st, 6.0);
    medium turned = box_medium(v3(0, 0, 0), v3(2, 1, 1), sa, ss, 0);
    place(&turned, mat4_rotate(v3(0, 1, 0), 90));
    check_tr(medium_transmittance(&turned, 1, v3(0.5f, 0.5f, -5), v3(0, 0, 1), 0, INFINITY), st, 2.0);
    one = medium_transmittance(&turned, 1, v3(1.5f, 0.5f, -5), v3(0, 0, 1), 0, INFINITY);
    CHECK(one.x == 1.0f);
    // A sphere in world space takes a path of its own (in scalars): the same segments, bit for bit, as the same
    // sphere placed by the identity (through object space), on rays from inside, outside, near its boundary,
    // with unit and other directions and clipped intervals.
    medium placed = ball;
    place(&placed, mat4_identity());
    rng g = rng_for_sample(7, 1, 2);
    int differ = 0;
    for (int i = 0; i < 20000; i++) {
        vec3 o = v3(rng_range(&g, -4, 6), rng_range(&g, -3, 7), rng_range(&g, -2, 8));
        if (i % 4 == 0) o = v3_add(v3(1, 2, 3), v3_scale(v3_unit(v3(rng_range(&g, -1, 1), rng_range(&g, -1, 1), 0.5f)), 2));
        vec3 d = v3_unit(v3_sub(v3(rng_range(&g, -1, 3), rng_range(&g, 0, 4), rng_range(&g, 1, 5)), o));
        if (i % 3 == 0) d = v3_scale(d, rng_range(&g, 0.1f, 10.0f));
        float lo = i % 5 == 0 ? rng_range(&g, 0, 2) : 0.0f, hi = i % 2 ? rng_range(&g, 0, 8) : INFINITY;
        float a0 = -1, a1 = -1, b0 = -1, b1 = -1;
        bool a = medium_segment(&ball, o, d, lo, hi, &a0, &a1);
        bool b = medium_segment(&placed, o, d, lo, hi, &b0, &b1);
        if (a != b || (a && (a0 != b0 || a1 != b1))) differ++;
    }
    CHECK(differ == 0);
    // Overlapping media multiply: the slab and the sphere along one line.
    medium both[2] = {slab, ball};
    vec3 tr = medium_transmittance(both, 2, v3(-5, 2, 3), v3(1, 0, 0), 0, INFINITY);
    CHECK(rel_near(tr.y, exp(-st.y * 2.0) * exp(-st.y * 4.0), 1e-5));
}

// ---------------------------------------------------------------------------------------------
// Free flights

typedef struct moments {
    double sum[3], sum2[3];
} moments;

static void add(moments *m, vec3 v) {
    for (int c = 0; c < 3; c++) {
        double x = v3_comp(v, c);
        m->sum[c] += x;
        m->sum2[c] += x * x;
    }
}

// Whether the mean of the n samples in m agrees with `exact` in every channel (within 4 standard errors).
static bool agrees(const moments *m, double n, const double exact[3], const char *what) {
    bool ok = true;
    for (int c = 0; c < 3; c++) {
        double mean = m->sum[c] / n, se = sqrt(fmax(m->sum2[c] / n - mean * mean, 0.0) / n);
        bool good = fabs(mean - exact[c]) <= 4.0 * se + 1e-6;
        if (!good) fprintf(stderr, "%s[%d]: %.6f +- %.6f, exact %.6f\n", what, c, mean, se, exact[c]);
        ok = ok && good;
    }
    return ok;
}

// The free-flight estimator through a homogeneous slab of thickness 1.5 (chromatic sigma_t and sigma_s):
// the expected weight of passing is the transmittance, of scattering sigma_s / sigma_t (1 - T), and of
// scattering in the first half of the slab sigma_s / sigma_t (1 - T(half)); a surface in the slab stops it.
static void test_free_flight(void) {
    vec3 ss = v3(0.4f, 0.5f, 0.5f), st = v3(0.5f, 1.0f, 2.0f);
    medium slab = box_medium(v3(0, -100, -100), v3(1.5f, 100, 100), v3_sub(st, ss), ss, 0);
    const double n = 400000;
    moments pass, scat, half, stop;
    memset(&pass, 0, sizeof pass), memset(&scat, 0, sizeof scat), memset(&half, 0, sizeof half), memset(&stop, 0, sizeof stop);
    rng r = rng_for_sample(3, 1, 2);
    bool on_ray = true;
    for (int i = 0; i < (int)n; i++) {
        medium_path mp = medium_path_start(), mq = medium_path_start();
        medium_event e = medium_sample(&slab, 1, NULL, v3(-1, 0.25f, 0), v3(1, 0, 0), INFINITY, &mp, &r);
        add(&pass, e.scattered ? v3s(0) : e.weight);
        add(&scat, e.scattered ? e.weight : v3s(0));
        add(&half, e.scattered && e.p.x < 0.75f ? e.weight : v3s(0));
        if (e.scattered) on_ray = on_ray && e.p.x >= 0.0f && e.p.x <= 1.5f && e.p.y == 0.25f && e.p.z == 0.0f;
        medium_event s = medium_sample(&slab, 1, NULL, v3(-1, 0, 0), v3(1, 0, 0), 1.5f, &mq, &r);
        add(&stop, s.scattered ? v3s(0) : s.weight);
    }
    double t_pass[3], t_scat[3], t_half[3], t_stop[3];
    for (int c = 0; c < 3; c++) {
        double sc = v3_comp(st, c), a = v3_comp(ss, c) / sc;
        t_pass[c] = exp(-sc * 1.5);
        t_scat[c] = a * (1.0 - t_pass[c]);
        t_half[c] = a * (1.0 - exp(-sc * 0.75));
        t_stop[c] = exp(-sc * 0.5);
    }
    printf("free flight: pass %.4f %.4f %.4f (exact %.4f %.4f %.4f)\n", pass.sum[0] / n, pass.sum[1] / n,
           pass.sum[2] / n, t_pass[0], t_pass[1], t_pass[2]);
    CHECK(agrees(&pass, n, t_pass, "pass"));
    CHECK(agrees(&scat, n, t_scat, "scatter"));
    CHECK(agrees(&half, n, t_half, "scatter in the first half"));
    CHECK(agrees(&stop, n, t_stop, "pass up to a surface"));
    CHECK(on_ray);

    // Grey (book 2's constant_medium): weights exactly 1 when passing and the albedo when scattering.
    medium grey = box_medium(v3(0, -1, -1), v3(1, 1, 1), v3(0.3f, 0.5f, 0.8f), v3(0.7f, 0.5f, 0.2f), 0);
    medium_path gp = medium_path_start();
    bool exact = true;
    int scattered = 0;
    for (int i = 0; i < 10000; i++) {
        medium_event e = medium_sample(&grey, 1, NULL, v3(-1, 0, 0), v3(1, 0, 0), INFINITY, &gp, &r);
        vec3 want = e.scattered ? v3(0.7f, 0.5f, 0.2f) : v3s(1.0f);
        scattered += e.scattered;
        exact = exact && fabsf(e.weight.x - want.x) <= 1e-7f && fabsf(e.weight.y - want.y) <= 1e-7f &&
                fabsf(e.weight.z - want.z) <= 1e-7f;
    }
    CHECK(exact);
    CHECK(fabs(scattered / 10000.0 - (1.0 - exp(-1.0))) < 0.02);
    CHECK(gp.ratio.x == 1.0f && gp.ratio.y == 1.0f && gp.ratio.z == 1.0f && gp.hero >= 0);
    // No medium on the ray: weight exactly 1, no random number drawn, no channel chosen.
    rng before = r;
    medium_path none = medium_path_start();
    medium_event e = medium_sample(&grey, 1, NULL, v3(-1, 5, 0), v3(1, 0, 0), INFINITY, &none, &r);
    CHECK(!e.scattered && e.weight.x == 1.0f && e.weight.y == 1.0f && e.weight.z == 1.0f);
    CHECK(r.state == before.state && none.hero == -1);

    // A path through a chromatic slab many times (as in a thick cloud): its weight, the balance heuristic
    // over the channels of the whole path, stays at most 3 per channel (times the albedo, 0.8 here), where
    // per-flight MIS would multiply factors above 1 flight after flight.
    medium cloud = box_medium(v3(0, -1, -1), v3(1, 1, 1), v3(0.1f, 0.4f, 1.6f), v3(0.4f, 1.6f, 6.4f), 0);
    double worst = 0.0;
    for (int i = 0; i < 2000; i++) {
        medium_path cp = medium_path_start();
        vec3 w = v3s(1.0f);
        for (int k = 0; k < 30; k++) {
            medium_event c = medium_sample(&cloud, 1, NULL, v3(-1, 0, 0), v3(1, 0, 0), INFINITY, &cp, &r);
            w = v3_mul(w, c.weight);
        }
        worst = fmax(worst, v3_max_comp(w));
    }
    printf("30 flights through a chromatic slab: largest weight %.3f\n", worst);
    CHECK(worst <= 3.0 * 1.0001);
}

// ---------------------------------------------------------------------------------------------
// Renders

static glint_scene *new_scene(int w, int h, int spp, int depth, vec3 from, vec3 at, float vfov, float background) {
    glint_scene *s = scene_new("test");
    render_settings *rs = &s->settings;
    rs->width = w;
    rs->height = h;
    rs->spp = spp;
    rs->max_depth = depth;
    rs->integrator = INTEGRATOR_PATH;
    rs->background = BACKGROUND_CONSTANT;
    rs->background_color = v3s(background);
    s->camera.kind = CAMERA_LOOKAT;
    s->camera.lookfrom = from;
    s->camera.lookat = at;
    s->camera.vup = v3(0, 1, 0);
    s->camera.vfov_degrees = vfov;
    return s;
}

static uint32_t add_material(glint_scene *s, material m) { return (uint32_t)scene_add_material(s, &m, NULL); }

static material lambertian(float a) {
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = v3s(a);
    return m;
}

static glint_image *render(const glint_scene *s, int threads, bool nee, render_stats *stats) {
    render_options opt = {.threads = threads, .integrator = {.no_light_sampling = !nee}};
    glint_image *img = NULL;
    glint_error err;
    render_stats local;
    if (!stats) stats = &local;
    glint_status st = render_scene(s, &opt, NULL, NULL, &img, stats, &err);
    if (st != GLINT_OK) fprintf(stderr, "render: %s\n", err.message);
    CHECK(st == GLINT_OK);
    CHECK(stats->discarded_samples == 0);
    return img;
}

static const float *pixels(const glint_image *img, int *w, int *h) {
    const float *rgb;
    glint_image_info(img, w, h, &rgb);
    return rgb;
}

// Mean of channel c (-1: all channels) and the standard error of that mean over the pixels.
static double image_mean(const glint_image *img, int c, double *se) {
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    double sum = 0.0, sum2 = 0.0;
    long n = 0;
    for (long i = 0; i < (long)w * h; i++)
        for (int k = 0; k < 3; k++) {
            if (c >= 0 && k != c) continue;
            double x = rgb[i * 3 + k];
            sum += x;
            sum2 += x * x;
            n++;
        }
    double mean = sum / (double)n;
    if (se) *se = sqrt(fmax(sum2 / (double)n - mean * mean, 0.0) / (double)n);
    return mean;
}

static double max_deviation(const glint_image *img, double value) {
    int w, h;
    const float *rgb = pixels(img, &w, &h);
    double worst = 0.0;
    for (long i = 0; i < (long)w * h * 3; i++) worst = fmax(worst, fabs(rgb[i] - value));
    return worst;
}

// Furnaces: under a uniform radiance of 1, media of albedo 1 (a fog around the camera, smoke inside a glass
// sphere sharing its boundary, a box of smoke through a white sphere) with albedo-1 surfaces scatter every
// path on without loss. Grey media keep every sample exactly 1; chromatic media (sigma_t differing by
// channel, albedo 1 in each) and forward-scattering HG media keep every pixel at 1 within noise, and so does
// a uniform environment map, which next-event estimation samples from inside the media.
static void test_furnaces(void) {
    for (int variant = 0; variant < 3; variant++) {
        glint_scene *s = new_scene(24, 24, variant ? 32 : 8, 100000, v3(0, 0.2f, 3), v3(0, 0, 0), 60, 1.0f);
        uint32_t white = add_material(s, lambertian(1.0f)), glass = add_material(s, material_default(MAT_DIELECTRIC));
        sphere a = {v3(-0.7f, 0, 0), 0.5f, white}, b = {v3(0.7f, 0, 0), 0.5f, glass};
        CHECK(scene_add_sphere(s, a) && scene_add_sphere(s, b));
        vec3 chroma = variant ? v3(0.5f, 1.0f, 2.0f) : v3s(1.0f);
        float g = variant == 2 ? 0.7f : 0.0f;
        CHECK(scene_add_medium(s, sphere_medium(v3(0, 0, 0), 50, v3s(0), v3_scale(chroma, 0.05f), g)));
        CHECK(scene_add_medium(s, sphere_medium(v3(0.7f, 0, 0), 0.5f, v3s(0), v3_scale(chroma, 3.0f), g)));
        CHECK(scene_add_medium(s, box_medium(v3(-1, -0.3f, -0.3f), v3(-0.4f, 0.3f, 0.3f), v3s(0), v3_scale(chroma, 2.0f), -g)));
        if (variant == 2) { // a uniform environment map of radiance 1, sampled at every diffuse or medium vertex
            image_rgb img = {8, 4, malloc(8 * 4 * 3 * sizeof(float)), NULL};
            for (int i = 0; i < 8 * 4 * 3; i++) img.pixels[i] = 1.0f;
            s->settings.background = BACKGROUND_ENVMAP;
            s->environment = envmap_make(img, 1.0f, 0.0f);
        }
        render_stats st;
        glint_image *img = render(s, 2, true, &st);
        double se, mean = image_mean(img, -1, &se);
        double dev = max_deviation(img, 1.0);
        printf("furnace with media (%s): mean %.5f +- %.5f, largest pixel deviation %.4f, %llu rays, %llu shadow rays\n",
               variant == 0 ? "grey" : variant == 1 ? "chromatic" : "HG g 0.7, envmap", mean, se, dev,
               (unsigned long long)st.rays, (unsigned long long)st.shadow_rays);
        if (variant == 0) CHECK_NEAR(dev, 0.0, 1e-5);
        else {
            CHECK(fabs(mean - 1.0) < 4.0 * se + 1e-3);
            CHECK(dev < 1.0);
        }
        if (variant == 2) CHECK(st.shadow_rays > 0);
        glint_image_free(img);
        scene_free(s);
    }
}

// A purely absorbing slab 2 thick between a camera looking straight at it and a white background: the
// image is exp(-sigma_a 2) per channel.
static void test_absorbing_slab(void) {
    glint_scene *s = new_scene(16, 16, 64, 50, v3(0, 0, 5), v3(0, 0, 0), 0.5f, 1.0f);
    vec3 sa = v3(0.2f, 0.5f, 1.0f);
    CHECK(scene_add_medium(s, box_medium(v3(-10, -10, -1), v3(10, 10, 1), sa, v3s(0), 0)));
    glint_image *img = render(s, 1, true, NULL);
    for (int c = 0; c < 3; c++) {
        double se, mean = image_mean(img, c, &se), exact = exp(-2.0 * v3_comp(sa, c));
        printf("absorbing slab, channel %d: %.5f +- %.5f, exact %.5f\n", c, mean, se, exact);
        CHECK(fabs(mean - exact) < 4.0 * se + 2e-4);
    }
    glint_image_free(img);
    scene_free(s);
}

// A Lambertian floor (albedo rho) lit by a point light 1 above it, all inside an absorbing medium, seen from
// h above it: rho / pi I exp(-sigma_a) exp(-sigma_a h); and by a directional light through the medium's top,
// 3 above the floor: rho / pi E exp(-3 sigma_a) exp(-sigma_a h).
static void test_lights_through_absorber(void) {
    const float rho = 0.5f, sa = 0.4f, h = 0.5f;
    for (int kind = 0; kind < 2; kind++) {
        glint_scene *s = new_scene(8, 8, 256, 2, v3(0, h, 0.0001f), v3(0, 0, 0), 0.5f, 0.0f);
        quad q;
        CHECK(quad_make(v3(-5, 0, 5), v3(10, 0, 0), v3(0, 0, -10), add_material(s, lambertian(rho)), &q));
        CHECK(scene_add_quad(s, q));
        CHECK(scene_add_medium(s, box_medium(v3(-10, -1, -10), v3(10, 3, 10), v3s(sa), v3s(0), 0)));
        light l = {0};
        l.kind = kind ? LIGHT_DIRECTIONAL : LIGHT_POINT;
        l.intensity = v3s(2.0f);
        l.position = v3(0, 1, 0);
        l.direction = v3(0, 1, 0);
        CHECK(scene_add_light(s, l));
        glint_image *img = render(s, 1, true, NULL);
        double se, mean = image_mean(img, 1, &se);
        double exact = rho / PI * 2.0 * exp(-sa * (kind ? 3.0 : 1.0)) * exp(-sa * h);
        printf("%s light through an absorber: %.5f +- %.5f, exact %.5f\n", kind ? "directional" : "point", mean, se,
               exact);
        CHECK(fabs(mean - exact) < 4.0 * se + 1e-3 * exact);
        glint_image_free(img);
        scene_free(s);
    }
}

// A small smoky box under a quad light: light sampling through the medium (at surfaces and at scattering
// points, shadow rays carrying transmittance) against phase and BSDF sampling alone. Same mean; less noise,
// measured as the RMS difference between two seeds' images at the same sample count.
static void test_nee_through_media(void) {
    double mean[2], se[2], rms[2];
    for (int nee = 0; nee < 2; nee++) {
        glint_image *img[2];
        for (int seed = 0; seed < 2; seed++) {
            glint_scene *s = new_scene(24, 24, 64, 50, v3(0, 0.8f, 3.2f), v3(0, 0.8f, 0), 30, 0.0f); // the light out of view
            s->settings.seed = (uint64_t)seed + 11;
            uint32_t white = add_material(s, lambertian(0.7f));
            material lamp = material_default(MAT_DIFFUSE_LIGHT);
            lamp.emission = v3s(30.0f);
            quad q;
            // A floor, a back wall and the light (facing down) over a box of smoke with an HG phase function.
            CHECK(quad_make(v3(-1, 0, 1), v3(2, 0, 0), v3(0, 0, -2), white, &q) && scene_add_quad(s, q));
            CHECK(quad_make(v3(-1, 0, -1), v3(2, 0, 0), v3(0, 2, 0), white, &q) && scene_add_quad(s, q));
            CHECK(quad_make(v3(-0.15f, 1.9f, -0.15f), v3(0.3f, 0, 0), v3(0, 0, 0.3f), add_material(s, lamp), &q) &&
                  scene_add_quad(s, q));
            CHECK(scene_add_medium(s, box_medium(v3(-0.6f, 0, -0.6f), v3(0.6f, 1.2f, 0.6f), v3(0.1f, 0.2f, 0.3f),
                                                 v3(1.2f, 1.0f, 0.8f), 0.4f)));
            img[seed] = render(s, 2, nee, NULL);
            scene_free(s);
        }
        mean[nee] = image_mean(img[0], -1, &se[nee]);
        int w, h;
        const float *a = pixels(img[0], &w, &h), *b = pixels(img[1], &w, &h);
        double d2 = 0.0;
        for (long i = 0; i < (long)w * h * 3; i++) d2 += (a[i] - b[i]) * (a[i] - b[i]);
        rms[nee] = sqrt(d2 / (w * h * 3));
        glint_image_free(img[0]);
        glint_image_free(img[1]);
    }
    printf("smoke under a quad light, 64 spp: phase/BSDF sampling %.4f +- %.4f (RMS difference of two seeds %.4f), "
           "light sampling %.4f +- %.4f (%.4f)\n",
           mean[0], se[0], rms[0], mean[1], se[1], rms[1]);
    CHECK(fabs(mean[0] - mean[1]) < 4.0 * sqrt(se[0] * se[0] + se[1] * se[1]));
    CHECK(rms[1] < 0.5 * rms[0]);
}

// scenes/cornell-smoke.json: book 2's layout read as written, and the same bytes for 1 and 2 threads.
static void test_cornell_smoke(void) {
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_load(GLINT_SOURCE_DIR "/scenes/cornell-smoke.json", &s, &err) == GLINT_OK);
    if (!s) {
        fprintf(stderr, "%s\n", err.message);
        return;
    }
    CHECK(s->medium_count == 2 && s->quad_count == 6);
    CHECK(s->media[0].shape == MEDIUM_BOX && s->media[0].transformed && s->media[0].sigma_t.y == 0.01f &&
          s->media[0].sigma_s.x == 0.0f);
    CHECK(s->media[1].sigma_s.x == 0.01f && s->media[1].g == 0.0f && s->media[1].albedo_texture == -1);
    s->settings.width = s->settings.height = 40;
    s->settings.spp = 4;
    glint_image *one = render(s, 1, true, NULL), *two = render(s, 2, true, NULL);
    int w, h;
    const float *a = pixels(one, &w, &h), *b = pixels(two, &w, &h);
    CHECK(memcmp(a, b, (size_t)w * h * 3 * sizeof(float)) == 0);
    double mean = image_mean(one, -1, NULL);
    CHECK(mean > 0.05 && mean < 1.0);
    glint_image_free(one);
    glint_image_free(two);
    scene_free(s);
}

// The scene file's media: the book's form with a texture albedo and the coefficient form, each value where it
// belongs; and the Whitted integrator's warning that it ignores them.
static void test_scene_file(void) {
    const char *text =
        "{\"render\": {\"integrator\": \"path\", \"background\": 1}, \"textures\": {\"t\": {\"type\": \"checker\", \"scale\": 2}},\n"
        " \"objects\": [\n"
        "  {\"type\": \"constant_medium\", \"density\": 0.2, \"albedo\": \"t\",\n"
        "   \"boundary\": {\"type\": \"sphere\", \"center\": [1, 2, 3], \"radius\": 4}},\n"
        "  {\"type\": \"homogeneous_medium\", \"sigma_a\": [0.1, 0.2, 0.3], \"sigma_s\": 0.5, \"g\": -0.25,\n"
        "   \"boundary\": {\"type\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 2, 3], \"transform\": [{\"scale\": 2}]}}\n"
        " ]}";
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_parse("media.json", text, strlen(text), &s, &err) == GLINT_OK);
    if (!s) {
        fprintf(stderr, "%s\n", err.message);
        return;
    }
    CHECK(s->medium_count == 2);
    const medium *a = &s->media[0], *b = &s->media[1];
    CHECK(a->shape == MEDIUM_SPHERE && a->radius == 4.0f && a->center.z == 3.0f && !a->transformed);
    CHECK(a->albedo_texture == 0 && a->sigma_t.x == 0.2f && a->g == 0.0f);
    CHECK(b->shape == MEDIUM_BOX && b->transformed && b->hi.z == 3.0f && b->g == -0.25f);
    CHECK(fabsf(b->sigma_t.z - 0.8f) < 1e-6f && b->sigma_s.y == 0.5f);
    CHECK(glint_scene_warning_count(s) == 0);
    float t0, t1; // the box scaled by 2: x in [0, 2]
    CHECK(medium_segment(b, v3(-1, 1, 1), v3(1, 0, 0), 0, INFINITY, &t0, &t1) && t0 == 1.0f && t1 == 3.0f);
    scene_free(s);

    const char *whitted = "{\"objects\": [{\"type\": \"constant_medium\", \"density\": 1,"
                          " \"boundary\": {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}}]}";
    CHECK(glint_scene_parse("w.json", whitted, strlen(whitted), &s, &err) == GLINT_OK);
    if (s) {
        bool found = false;
        for (size_t i = 0; i < glint_scene_warning_count(s); i++)
            found = found || strcmp(glint_scene_warning(s, i),
                                    "w.json: warning: the Whitted integrator ignores participating media: 1 medium is "
                                    "not rendered (the path integrator renders them)") == 0;
        CHECK(found);
        scene_free(s);
    }
}

int main(void) {
    test_phase_hg();
    test_transmittance();
    test_free_flight();
    test_scene_file();
    test_furnaces();
    test_absorbing_slab();
    test_lights_through_absorber();
    test_nee_through_media();
    test_cornell_smoke();
    return check_summary();
}
