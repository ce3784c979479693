// test_motion.c — motion blur: transforms interpolated between two poses (slerp), boxes that hold a moving
// primitive at every time of the shutter, every acceleration structure agreeing with brute force at random
// times, blurred images equal to the mean of stills at evenly spread times (a moving sphere; an ellipsoid
// turning by slerp), the same bytes for 1 and 2 threads, and the Whitted integrators at the shutter's opening.
#include "check.h"
#include "glint.h"
#include "accel/accel.h"
#include "geometry/motion.h"
#include "render/frame.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t lcg_state = 0x853c49e6748fea9bULL;

// Uniform in [lo, hi), from a test-local generator (the renderer's streams are not involved).
static float urand(float lo, float hi) {
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (float)(lcg_state >> 40) * 0x1p-24f;
}

static double mat_diff(const mat4 *a, const mat4 *b) {
    double d = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) d = fmax(d, fabs((double)a->m[i][j] - b->m[i][j]));
    return d;
}

// T R S built from parts, the order the scene file's operations [scale, rotate, translate] make.
static mat4 trs(vec3 t, vec3 axis, float degrees, vec3 s) {
    mat4 sc = mat4_scale(s), ro = mat4_rotate(axis, degrees), tr = mat4_translate(t);
    mat4 rs = mat4_mul(&ro, &sc);
    return mat4_mul(&tr, &rs);
}

// The poses come back at times 0 and 1, and in between translation and scale are linear and the rotation
// turns at a constant rate about its axis (slerp), for angles up to nearly a half turn; mirrors keep their side.
static void test_interpolation(void) {
    const float angles[] = {30.0f, 90.0f, 170.0f};
    for (int k = 0; k < 3; k++) {
        vec3 axis = v3_unit(v3(1, 2, -0.5f));
        mat4 m0 = trs(v3(1, -2, 3), axis, 10.0f, v3(1, 2, 0.5f));
        mat4 m1 = trs(v3(-3, 4, 0), axis, 10.0f + angles[k], v3(3, 1, 0.5f));
        motion mo;
        CHECK(motion_make(&m0, &m1, &mo));
        transform xf;
        motion_at(&mo, 0.0f, &xf);
        CHECK(mat_diff(&xf.m, &m0) < 1e-5);
        motion_at(&mo, 1.0f, &xf);
        CHECK(mat_diff(&xf.m, &m1) < 1e-4);
        for (int i = 1; i < 8; i++) {
            float t = (float)i / 8.0f;
            motion_at(&mo, t, &xf);
            mat4 want = trs(v3(1 - 4 * t, -2 + 6 * t, 3 - 3 * t), axis, 10.0f + angles[k] * t, v3(1 + 2 * t, 2 - t, 0.5f));
            CHECK(mat_diff(&xf.m, &want) < 1e-4);
            mat4 id = mat4_mul(&xf.m, &xf.inv), one = mat4_identity();
            CHECK(mat_diff(&id, &one) < 1e-5);
        }
    }
    // Mirrored at both ends: fine; mirrored at one end only: every motion between would flatten the object.
    mat4 mirror = mat4_scale(v3(-1, 1, 1)), id = mat4_identity();
    mat4 turned = mat4_rotate(v3(0, 1, 0), 60.0f), mirror_turned = mat4_mul(&turned, &mirror);
    motion mo;
    CHECK(motion_make(&mirror, &mirror_turned, &mo));
    transform xf;
    motion_at(&mo, 0.5f, &xf);
    mat4 half = mat4_rotate(v3(0, 1, 0), 30.0f), want = mat4_mul(&half, &mirror);
    CHECK(mat_diff(&xf.m, &want) < 1e-5);
    CHECK(!motion_make(&id, &mirror, &mo));
}

// motion_bounds holds the object box's corners and inner points under the transform at every time of the
// shutter: large rotations (up to 179 degrees, where the arc bulges far beyond both end boxes), shears, scales.
static void test_bounds(void) {
    int outside = 0, points = 0;
    for (int round = 0; round < 300; round++) {
        vec3 a0 = v3(urand(-1, 1), urand(-1, 1), urand(-1, 1)), a1 = v3(urand(-1, 1), urand(-1, 1), urand(-1, 1));
        if (round % 3 == 0) a1 = a0; // one axis: the plain turn
        float sign = round % 5 == 0 ? -1.0f : 1.0f;
        mat4 m0 = trs(v3(urand(-5, 5), urand(-5, 5), urand(-5, 5)), a0, urand(-180, 180),
                      v3(sign * urand(0.2f, 3), urand(0.2f, 3), urand(0.2f, 3)));
        mat4 m1 = trs(v3(urand(-5, 5), urand(-5, 5), urand(-5, 5)), a1, urand(-180, 180),
                      v3(sign * urand(0.2f, 3), urand(0.2f, 3), urand(0.2f, 3)));
        if (round % 4 == 1) { // a shear after the turn
            mat4 shear = mat4_identity();
            shear.m[0][1] = urand(-1, 1);
            m1 = mat4_mul(&shear, &m1);
        }
        motion mo;
        if (!motion_make(&m0, &m1, &mo)) {
            CHECK(false);
            continue;
        }
        vec3 lo = v3(urand(-3, 3), urand(-3, 3), urand(-3, 3));
        bounds3 ob = {lo, v3_add(lo, v3(urand(0.01f, 4), urand(0.01f, 4), urand(0.01f, 4)))};
        float t0 = round % 2 ? 0.0f : urand(0, 0.5f), t1 = round % 2 ? 1.0f : urand(0.5f, 1);
        bounds3 wb = motion_bounds(&mo, ob, t0, t1);
        for (int i = 0; i <= 200; i++) {
            float t = i == 200 ? t1 : t0 + (t1 - t0) * urand(0, 1);
            transform xf;
            motion_at(&mo, t, &xf);
            for (int c = 0; c < 12; c++) {
                vec3 p = c < 8 ? v3((c & 1) ? ob.hi.x : ob.lo.x, (c & 2) ? ob.hi.y : ob.lo.y, (c & 4) ? ob.hi.z : ob.lo.z)
                               : v3(urand(ob.lo.x, ob.hi.x), urand(ob.lo.y, ob.hi.y), urand(ob.lo.z, ob.hi.z));
                vec3 w = mat4_apply_point(&xf.m, p);
                points++;
                outside += !(w.x >= wb.lo.x && w.x <= wb.hi.x && w.y >= wb.lo.y && w.y <= wb.hi.y && w.z >= wb.lo.z &&
                             w.z <= wb.hi.z);
            }
        }
    }
    if (outside) fprintf(stderr, "motion_bounds: %d of %d points outside\n", outside, points);
    CHECK(outside == 0);
}

static glint_scene *parse(const char *text) {
    glint_scene *s = NULL;
    glint_error err;
    if (scene_file_parse("motion.json", text, strlen(text), 0, &s, &err) != GLINT_OK) {
        fprintf(stderr, "parse: %s\n", err.message);
        CHECK(false);
        return NULL;
    }
    return s;
}

// A scene text of many moving spheres, moving ellipsoids (sphere instances under transform and transform2),
// and static spheres, with the given shutter.
static char *moving_scene(float open, float close) {
    size_t cap = 1 << 20, n = 0;
    char *t = malloc(cap);
    n += (size_t)snprintf(t + n, cap - n,
                          "{\"render\": {\"width\": 32, \"height\": 24, \"integrator\": \"path\"},"
                          " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, 20], \"shutter\": [%g, %g]},"
                          " \"materials\": {\"m\": {\"type\": \"lambertian\"}}, \"objects\": [",
                          (double)open, (double)close);
    for (int i = 0; i < 300; i++) {
        vec3 c = v3(urand(-8, 8), urand(-8, 8), urand(-8, 8)), d = v3(urand(-2, 2), urand(-2, 2), urand(-2, 2));
        float r = urand(0.05f, 0.6f);
        const char *sep = i ? ", " : "";
        if (i % 3 == 0)
            n += (size_t)snprintf(t + n, cap - n,
                                  "%s{\"type\": \"sphere\", \"center\": [%g, %g, %g], \"center2\": [%g, %g, %g], "
                                  "\"radius\": %g, \"material\": \"m\"}",
                                  sep, c.x, c.y, c.z, c.x + d.x, c.y + d.y, c.z + d.z, r);
        else if (i % 3 == 1)
            n += (size_t)snprintf(t + n, cap - n,
                                  "%s{\"type\": \"sphere\", \"center\": [0.2, 0, 0], \"radius\": %g, \"material\": \"m\", "
                                  "\"transform\": [{\"scale\": [2, 0.5, 1]}, {\"rotate\": {\"axis\": [%g, 1, 0], "
                                  "\"degrees\": %g}}, {\"translate\": [%g, %g, %g]}], "
                                  "\"transform2\": [{\"scale\": [1, 0.5, 2]}, {\"rotate\": {\"axis\": [0, 1, %g], "
                                  "\"degrees\": %g}}, {\"translate\": [%g, %g, %g]}]}",
                                  sep, r, urand(-1, 1), urand(-180, 180), c.x, c.y, c.z, urand(-1, 1), urand(-180, 180),
                                  c.x + d.x, c.y + d.y, c.z + d.z);
        else
            n += (size_t)snprintf(t + n, cap - n, "%s{\"type\": \"sphere\", \"center\": [%g, %g, %g], \"radius\": %g, "
                                  "\"material\": \"m\"}", sep, c.x, c.y, c.z, r);
    }
    for (int i = 0; i < 40; i++) { // moving copies of a small OBJ cube: meshes under transform and transform2
        vec3 c = v3(urand(-8, 8), urand(-8, 8), urand(-8, 8)), d = v3(urand(-2, 2), urand(-2, 2), urand(-2, 2));
        n += (size_t)snprintf(t + n, cap - n,
                              ", {\"type\": \"mesh\", \"file\": \"%s\", \"material\": \"m\", "
                              "\"transform\": [{\"scale\": %g}, {\"rotate\": {\"axis\": [1, %g, 0], \"degrees\": %g}}, "
                              "{\"translate\": [%g, %g, %g]}], \"transform2\": [{\"scale\": [%g, 0.3, 0.4]}, "
                              "{\"rotate\": {\"axis\": [0, 1, %g], \"degrees\": %g}}, {\"translate\": [%g, %g, %g]}]}",
                              GLINT_SOURCE_DIR "/tests/data/obj/tinyobjloader/cube.obj", urand(0.2f, 0.5f), urand(-1, 1),
                              urand(-180, 180), c.x, c.y, c.z, urand(0.2f, 0.6f), urand(-1, 1), urand(-180, 180),
                              c.x + d.x, c.y + d.y, c.z + d.z);
    }
    snprintf(t + n, cap - n, "]}");
    return t;
}

// The BVHs (wide, binary) and brute force find the same nearest hit, and agree on occlusion, for rays at random
// times aimed at where a moving primitive is at that time (so that most of them hit something that moves).
static void test_accel_agreement(void) {
    const float shutters[2][2] = {{0.0f, 1.0f}, {0.3f, 0.6f}};
    for (int sh = 0; sh < 2; sh++) {
        char *text = moving_scene(shutters[sh][0], shutters[sh][1]);
        glint_scene *s = parse(text);
        free(text);
        if (!s) return;
        CHECK(s->moving_sphere_count == 100 && s->motion_count == 140 && s->mesh_count == 1);
        size_t moving[140], nm = 0; // the moving instances: 100 ellipsoids, 40 cubes
        for (size_t j = 0; j < s->instance_count; j++)
            if (s->instances[j].motion && nm < 140) moving[nm++] = j;
        CHECK(nm == 140);
        accel *a[3];
        glint_error err;
        const accel_kind kinds[3] = {ACCEL_NONE, ACCEL_BVH, ACCEL_BVH2};
        for (int k = 0; k < 3; k++) {
            s->settings.accel = kinds[k];
            a[k] = frame_accel_build(s, NULL, &err);
            CHECK(a[k] != NULL);
        }
        int differ = 0, hits = 0, moving_hits = 0;
        for (int i = 0; i < 20000; i++) {
            float time = shutters[sh][0] + (shutters[sh][1] - shutters[sh][0]) * urand(0, 1);
            vec3 target;
            if (i % 2 == 0) {
                target = moving_sphere_center(&s->moving_spheres[(size_t)i / 2 % 100], time);
            } else { // the centre of a moving ellipsoid or cube at that time
                const instance *in = &s->instances[moving[(size_t)i / 2 % nm]];
                transform xf;
                motion_at(&s->motions[in->motion - 1], time, &xf);
                bounds3 ob = s->meshes[0].geometry.bounds;
                vec3 oc = in->kind == INSTANCE_SPHERE ? s->instance_spheres[in->index].center
                                                      : v3_scale(v3_add(ob.lo, ob.hi), 0.5f);
                target = mat4_apply_point(&xf.m, oc);
            }
            target = v3_add(target, v3(urand(-0.3f, 0.3f), urand(-0.3f, 0.3f), urand(-0.3f, 0.3f)));
            vec3 o = v3(urand(-12, 12), urand(-12, 12), urand(-12, 12));
            ray r = {o, v3_unit(v3_sub(target, o)), 0.0f, INFINITY, time};
            hit h[3];
            bool f[3], occ[3];
            for (int j = 0; j < 3; j++) {
                f[j] = accel_intersect(a[j], &r, &h[j]);
                occ[j] = accel_occluded(a[j], &r);
            }
            hits += f[0];
            moving_hits += f[0] && (h[0].kind == HIT_MOVING_SPHERE || h[0].instance != HIT_NO_INSTANCE);
            for (int j = 1; j < 3; j++) {
                bool same = f[j] == f[0] && occ[j] == occ[0] && occ[0] == f[0] &&
                            (!f[0] || (h[j].t == h[0].t && h[j].kind == h[0].kind && h[j].prim == h[0].prim &&
                                       h[j].instance == h[0].instance));
                differ += !same;
            }
        }
        if (differ) fprintf(stderr, "accel agreement (shutter %d): %d differences\n", sh, differ);
        CHECK(differ == 0);
        printf("accel agreement (shutter %d): %d of 20000 rays hit, %d on moving objects\n", sh, hits, moving_hits);
        CHECK(hits > 15000 && moving_hits > 12000);
        for (int k = 0; k < 3; k++) accel_free(a[k]);
        glint_scene_free(s);
    }
}

static glint_image *render(const glint_scene *s, int threads) {
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = threads;
    glint_image *img = NULL;
    glint_error err;
    glint_render_stats stats;
    glint_status st = glint_render(s, &opt, NULL, NULL, &img, &stats, &err);
    CHECK(st == GLINT_OK && stats.discarded_samples == 0);
    if (st != GLINT_OK) fprintf(stderr, "render: %s\n", err.message);
    return img;
}

enum { W = 32, H = 24, BLOCK = 4, STILLS = 32 };

// Means of the BLOCK x BLOCK blocks of an image's first channel (the scenes are grey).
static void block_means(const glint_image *img, double *out) {
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    for (int by = 0; by < H / BLOCK; by++)
        for (int bx = 0; bx < W / BLOCK; bx++) {
            double sum = 0.0;
            for (int y = 0; y < BLOCK; y++)
                for (int x = 0; x < BLOCK; x++) sum += rgb[3 * ((by * BLOCK + y) * w + bx * BLOCK + x)];
            out[by * (W / BLOCK) + bx] = sum / (BLOCK * BLOCK);
        }
}

/// Writes a scene's text: blurred over the shutter [0, 1] (still false), or the still at `time`.
typedef void (*scene_text_fn)(char *buf, size_t size, int spp, double time, bool still);

// A sphere moving right and up (center -> center2); its stills use the shutter [t, t].
static void moving_sphere_text(char *buf, size_t size, int spp, double time, bool still) {
    snprintf(buf, size,
             "{\"render\": {\"width\": 32, \"height\": 24, \"spp\": %d, \"integrator\": \"path\", \"background\": 1, "
             "\"max_depth\": 8}, \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, 6], \"vfov\": 40, "
             "\"shutter\": [%.17g, %.17g]}, \"objects\": [{\"type\": \"sphere\", \"center\": [-1.2, -0.3, 0], "
             "\"center2\": [1.0, 0.5, 0], \"radius\": 0.8, \"material\": {\"type\": \"lambertian\", \"albedo\": 0.5}}]}",
             spp, still ? time : 0.0, still ? time : 1.0);
}

// An ellipsoid turning by 120 degrees about the view axis while it moves right (transform -> transform2); its
// stills place it with the scene file's own rotation, by the angle slerp must reach at that time, 120 t.
static void turning_text(char *buf, size_t size, int spp, double time, bool still) {
    int n = snprintf(buf, size,
                     "{\"render\": {\"width\": 32, \"height\": 24, \"spp\": %d, \"integrator\": \"path\", "
                       "\"background\": 1, \"max_depth\": 8}, \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, 6], "
                       "\"vfov\": 40, \"shutter\": [0, 1]}, \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], "
                       "\"radius\": 1, \"material\": {\"type\": \"lambertian\", \"albedo\": 0.5}, ",
                     spp);
    if (n < 0 || (size_t)n >= size) return;
    if (still)
        snprintf(buf + n, size - (size_t)n,
                 "\"transform\": [{\"scale\": [1.6, 0.4, 0.4]}, {\"rotate\": {\"axis\": [0, 0, 1], \"degrees\": %.17g}}, "
                 "{\"translate\": [%.17g, 0, 0]}]}]}",
                 120.0 * time, -0.4 + 0.8 * time);
    else
        snprintf(buf + n, size - (size_t)n,
                 "\"transform\": [{\"scale\": [1.6, 0.4, 0.4]}, {\"translate\": [-0.4, 0, 0]}], "
                 "\"transform2\": [{\"scale\": [1.6, 0.4, 0.4]}, {\"rotate\": {\"axis\": [0, 0, 1], \"degrees\": 120}}, "
                 "{\"translate\": [0.4, 0, 0]}]}]}");
}

// The blurred image (spp samples a pixel) against the mean of STILLS stills at the midpoints of STILLS equal
// time steps (spp / 4 samples each), block by block. The scenes are convex Lambertian (albedo 0.5) shapes
// before a white background: every sample is 0.5 or 1 (sigma <= 0.25), so a block mean's noise is
// 0.25 / sqrt(samples in it); the stills' midpoint rule misplaces each of a pixel's edge crossings (a step of
// 0.5) by at most half a time step, 1 / (2 STILLS), and a pixel sees at most two here. The tolerance is 5 sigma
// of the difference plus that bound. The blurred image must also differ from the first still (the blur is there).
static void blur_against_stills(scene_text_fn make, const char *what) {
    enum { BLOCKS = (W / BLOCK) * (H / BLOCK) };
    const int spp = 256;
    char text[2048];
    double blurred[BLOCKS], mean[BLOCKS] = {0}, first[BLOCKS];
    make(text, sizeof text, spp, 0.0, false);
    glint_scene *s = parse(text);
    if (!s) return;
    glint_image *img = render(s, 0);
    block_means(img, blurred);
    glint_image_free(img);
    glint_scene_free(s);
    for (int k = 0; k < STILLS; k++) {
        double here[BLOCKS];
        make(text, sizeof text, spp / 4, (k + 0.5) / STILLS, true);
        s = parse(text);
        if (!s) return;
        img = render(s, 0);
        block_means(img, here);
        glint_image_free(img);
        glint_scene_free(s);
        for (int b = 0; b < BLOCKS; b++) mean[b] += here[b] / STILLS;
        if (k == 0) memcpy(first, here, sizeof first);
    }
    double n = BLOCK * BLOCK;
    double sigma = sqrt(0.0625 / (n * spp) + 0.0625 / (n * (spp / 4) * STILLS));
    double tol = 5.0 * sigma + 2.0 * 0.5 / (2.0 * STILLS), worst = 0.0, blur = 0.0;
    for (int b = 0; b < BLOCKS; b++) {
        worst = fmax(worst, fabs(blurred[b] - mean[b]));
        blur = fmax(blur, fabs(blurred[b] - first[b]));
    }
    printf("%s: largest block difference %.4f (tolerance %.4f); from the first still: %.4f\n", what, worst, tol, blur);
    CHECK(worst <= tol);
    CHECK(blur > 0.1);
}

// Same bytes for 1 and 2 threads: the book's bouncing spheres (moving spheres) and the moving ellipsoids.
static void test_threads(void) {
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_load(GLINT_SOURCE_DIR "/scenes/rtiow2-bouncing-spheres.json", &s, &err) == GLINT_OK);
    if (!s) return;
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = 96;
    o.height = 54;
    o.spp = 4;
    CHECK(glint_scene_override(s, &o, &err) == GLINT_OK);
    char *text = moving_scene(0.0f, 1.0f);
    glint_scene *m = parse(text);
    free(text);
    glint_scene *scenes[2] = {s, m};
    for (int k = 0; k < 2; k++) {
        if (!scenes[k]) continue;
        glint_image *a = render(scenes[k], 1), *b = render(scenes[k], 2);
        int w, h;
        const float *pa, *pb;
        glint_image_info(a, &w, &h, &pa);
        glint_image_info(b, &w, &h, &pb);
        CHECK(memcmp(pa, pb, (size_t)w * (size_t)h * 3 * sizeof *pa) == 0);
        glint_image_free(a);
        glint_image_free(b);
        glint_scene_free(scenes[k]);
    }
}

// The Whitted integrators see the scene as it is when the shutter opens: a sphere moving from x = 0 (time 0)
// to x = 2 (time 1) under the shutter [0.5, 1] renders as a still sphere at x = 1 (centre(0.5) = 1 exactly),
// up to the rounding of the two paths' hit points; and it is not the sphere at x = 0.
static void test_whitted_at_shutter_open(void) {
    const char *fmt[3] = {
        "{\"render\": {\"width\": 32, \"height\": 24, \"background\": 0.2}, \"camera\": {\"type\": \"lookat\", "
        "\"lookfrom\": [1, 0, 6], \"vfov\": 40, \"shutter\": [0.5, 1]}, \"lights\": [{\"type\": \"point\", "
        "\"intensity\": 1, \"position\": [3, 4, 5]}], \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], "
        "\"center2\": [2, 0, 0], \"radius\": 1, \"material\": {\"type\": \"phong\", \"specular\": 20}}]}",
        "{\"render\": {\"width\": 32, \"height\": 24, \"background\": 0.2}, \"camera\": {\"type\": \"lookat\", "
        "\"lookfrom\": [1, 0, 6], \"vfov\": 40}, \"lights\": [{\"type\": \"point\", \"intensity\": 1, "
        "\"position\": [3, 4, 5]}], \"objects\": [{\"type\": \"sphere\", \"center\": [1, 0, 0], \"radius\": 1, "
        "\"material\": {\"type\": \"phong\", \"specular\": 20}}]}",
        "{\"render\": {\"width\": 32, \"height\": 24, \"background\": 0.2}, \"camera\": {\"type\": \"lookat\", "
        "\"lookfrom\": [1, 0, 6], \"vfov\": 40}, \"lights\": [{\"type\": \"point\", \"intensity\": 1, "
        "\"position\": [3, 4, 5]}], \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
        "\"material\": {\"type\": \"phong\", \"specular\": 20}}]}"};
    const float *px[3];
    glint_image *img[3];
    int w = 0, h = 0;
    for (int k = 0; k < 3; k++) {
        glint_scene *s = parse(fmt[k]);
        if (!s) return;
        img[k] = render(s, 1);
        glint_image_info(img[k], &w, &h, &px[k]);
        glint_scene_free(s);
    }
    double same = 0.0, other = 0.0;
    for (int i = 0; i < w * h * 3; i++) {
        same = fmax(same, fabs((double)px[0][i] - px[1][i]));
        other = fmax(other, fabs((double)px[0][i] - px[2][i]));
    }
    CHECK(same < 1e-3);
    CHECK(other > 0.1);
    for (int k = 0; k < 3; k++) glint_image_free(img[k]);
}

// The book's bouncing spheres as the scene file gives them: 100 still spheres (ground, metal, glass, the big
// three), 384 small diffuse ones moving up by 0..0.5 while the shutter [0, 1] is open, the checker ground.
static void test_bouncing_spheres_scene(void) {
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_load(GLINT_SOURCE_DIR "/scenes/rtiow2-bouncing-spheres.json", &s, &err) == GLINT_OK);
    if (!s) return;
    CHECK(s->sphere_count == 100 && s->moving_sphere_count == 384 && s->instance_count == 0);
    CHECK(s->camera.shutter_open == 0.0f && s->camera.shutter_close == 1.0f);
    CHECK(s->camera.defocus_angle_degrees == 0.02f && s->camera.focus_distance == 10.0f);
    CHECK(s->settings.background == BACKGROUND_CONSTANT && s->settings.background_color.x == 0.7f &&
          s->settings.background_color.y == 0.8f && s->settings.background_color.z == 1.0f);
    const material *ground = &s->materials[s->spheres[0].material];
    CHECK(s->spheres[0].radius == 1000.0f && ground->albedo_texture >= 0 &&
          s->textures[ground->albedo_texture].kind == TEX_CHECKER);
    int up = 0;
    for (size_t i = 0; i < s->moving_sphere_count; i++) {
        const moving_sphere *m = &s->moving_spheres[i];
        up += m->motion.x == 0.0f && m->motion.z == 0.0f && m->motion.y > 0.0f && m->motion.y <= 0.5f &&
              m->center.y == 0.2f && m->radius == 0.2f && s->materials[m->material].kind == MAT_LAMBERTIAN;
    }
    CHECK(up == 384);
    // The layout's first moving sphere (grid cell (-11, -10)), digit for digit.
    CHECK(s->moving_spheres[0].center.x == (float)-10.501427040016278 &&
          s->moving_spheres[0].motion.y == (float)0.5178558638319373 - 0.2f);
    glint_scene_free(s);
}

int main(void) {
    test_interpolation();
    test_bounds();
    test_accel_agreement();
    blur_against_stills(moving_sphere_text, "moving sphere (center2)");
    blur_against_stills(turning_text, "turning ellipsoid (transform2, slerp)");
    test_threads();
    test_whitted_at_shutter_open();
    test_bouncing_spheres_scene();
    return check_summary();
}
