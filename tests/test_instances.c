// test_instances.c — instanced and non-instanced copies render identical images: a mesh file
// placed three times (one shared BVH) against three files with the same content (three BVHs); an identity transform
// against none; a box of world-space quads against the same triangles as a mesh; a translated mesh against
// one whose vertices were moved in the file; a sphere under a similarity (baked into a sphere) against the
// sphere written out; and a sphere under a non-uniform scale (an ellipsoid instance) against the analytic
// ellipsoid. Scenes are JSON text parsed with glint_scene_parse, meshes small OBJ files in a temporary
// directory; images are 48x32 at 4 spp, path-traced and colour-Whitted, with every acceleration structure.
#include "glint.h"
#include "check.h"
#include "test_util.h"
#include "camera/camera.h"
#include "core/rng.h"
#include "integrator/integrator.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const accels[] = {"bvh", "bvh2", "none"};
enum { ACCEL_KINDS = 3 };

/// The integrators the comparisons run: the path tracer and the colour Whitted ray tracer.
typedef enum which { PATH, WHITTED, INTEGRATORS } which;
static const char *const integrator_json[] = {"'path'", "{'type': 'whitted', 'mode': 'color'}"};
static const char *const integrator_name[] = {"path", "whitted"};

// ---- files ----------------------------------------------------------------------------------------------

// Unlike tmp_write, each of opening and closing is a check of its own.
static void write_text(const char *name, const char *text) {
    FILE *f = fopen(tmp_path(name), "wb");
    CHECK(f != NULL);
    if (!f) return;
    fputs(text, f);
    CHECK(fclose(f) == 0);
}

// The gem: an octahedron of "radius" 0.5 (every coordinate 0 or +-0.5, exact in float), counter-clockwise
// faces seen from outside, two MTL materials (a diffuse upper half, a metal lower half), smooth normals
// computed by the loader (the file has none). (dx, dy, dz) moves every vertex: a pre-translated copy.
static void write_gem(const char *name, double dx, double dy, double dz) {
    static const double p[6][3] = {{0.5, 0, 0}, {-0.5, 0, 0}, {0, 0.5, 0}, {0, -0.5, 0}, {0, 0, 0.5}, {0, 0, -0.5}};
    char text[2048];
    size_t k = (size_t)snprintf(text, sizeof text, "# test gem\nmtllib gem.mtl\no gem\n");
    // %.9g prints these dyadic sums exactly; strtof reads them back exactly.
    for (int i = 0; i < 6; i++)
        k += (size_t)snprintf(text + k, sizeof text - k, "v %.9g %.9g %.9g\n", p[i][0] + dx, p[i][1] + dy,
                              p[i][2] + dz);
    snprintf(text + k, sizeof text - k,
             "usemtl warm\nf 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nusemtl steel\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n");
    write_text(name, text);
}

static void write_files(void) {
    write_text("gem.mtl", "newmtl warm\nKd 0.7 0.35 0.2\nnewmtl steel\nillum 3\nKd 0.1 0.1 0.1\nKs 0.8 0.8 0.75\n"
                          "Ns 200\n");
    write_gem("gem.obj", 0, 0, 0);
    write_gem("gem-copy.obj", 0, 0, 0);
    write_gem("gem-copy2.obj", 0, 0, 0);
    write_gem("gem-moved.obj", 0.75, 0.25, -0.5);
}

// ---- scenes and renders ---------------------------------------------------------------------------------

// The scene texts below write JSON's double quotes as single quotes, for legibility; this turns them back.
static void json_quotes(char *text) {
    for (char *p = text; *p; p++)
        if (*p == '\'') *p = '"';
}

// The stage every comparison shares: a checkered ground quad, an emissive quad shining down (sampled by the
// path tracer), a mirror and a glass sphere that show the objects again, a sky, and the paper's lights (used by
// Whitted; the path tracer adds point and directional lights by next-event estimation). `objects` is appended.
static glint_scene *parse_scene(const char *objects, which integ, const char *structure) {
    char text[8192];
    int n = snprintf(
        text, sizeof text,
        "{'render': {'width': 48, 'height': 32, 'spp': 4, 'seed': 11, 'max_depth': %d, 'integrator': %s,\n"
        "            'background': 'sky', 'output': 'gamma2', 'accel': '%s'},\n"
        " 'camera': {'type': 'lookat', 'lookfrom': [0, 1.5, 4], 'lookat': [0, 0.25, -0.5], 'vfov': 45},\n"
        " 'textures': {'tiles': {'type': 'checker', 'scale': 0.5, 'even': 0.8, 'odd': [0.2, 0.3, 0.4]}},\n"
        " 'materials': {\n"
        "   'ground': {'type': 'lambertian', 'albedo': 'tiles'},\n"
        "   'mirror': {'type': 'metal', 'albedo': [0.8, 0.8, 0.7]},\n"
        "   'glass': {'type': 'dielectric', 'ior': 1.5},\n"
        "   'paint': {'type': 'phong', 'color': [0.2, 0.5, 0.8], 'specular': 50, 'reflective': 0.25},\n"
        "   'lamp': {'type': 'diffuse_light', 'emission': 4}},\n"
        " 'objects': [\n"
        "   {'type': 'quad', 'q': [-4, -0.75, 4], 'u': [8, 0, 0], 'v': [0, 0, -8], 'material': 'ground'},\n"
        "   {'type': 'quad', 'q': [-0.5, 2.5, -0.5], 'u': [1, 0, 0], 'v': [0, 0, 1], 'material': 'lamp'},\n"
        "   {'type': 'sphere', 'center': [-1.75, 0.25, -2], 'radius': 0.75, 'material': 'mirror'},\n"
        "   {'type': 'sphere', 'center': [1.75, 0, -1.5], 'radius': 0.5, 'material': 'glass'},\n"
        "   %s],\n"
        " 'lights': [{'type': 'ambient', 'intensity': 0.1},\n"
        "            {'type': 'point', 'intensity': 0.6, 'position': [2, 3, 2]},\n"
        "            {'type': 'directional', 'intensity': 0.3, 'direction': [1, 2, 1]}]}\n",
        integ == PATH ? 6 : 4, integrator_json[integ], structure, objects);
    CHECK(n > 0 && (size_t)n < sizeof text);
    json_quotes(text);
    glint_scene *s = NULL;
    glint_error err;
    glint_status st = glint_scene_parse(tmp_path("scene.json"), text, strlen(text), &s, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return NULL;
    }
    // The files are clean: no face without a material, nothing skipped.
    CHECK(glint_scene_warning_count(s) == 0);
    for (size_t i = 0; i < glint_scene_warning_count(s); i++) fprintf(stderr, "  %s\n", glint_scene_warning(s, i));
    return s;
}

static glint_image *render(glint_scene *s) {
    if (!s) return NULL;
    glint_render_options opt = {.threads = 1};
    glint_image *img = NULL;
    glint_render_stats stats;
    glint_error err;
    glint_status st = glint_render(s, &opt, NULL, NULL, &img, &stats, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "  %s\n", err.message);
    CHECK(stats.discarded_samples == 0);
    return img;
}

// The linear floats of two images of the same size (false when either is missing or the sizes differ).
static bool both_pixels(const glint_image *a, const glint_image *b, int *w, int *n, const float **pa, const float **pb) {
    if (!a || !b) return false;
    int wa, ha, wb, hb;
    glint_image_info(a, &wa, &ha, pa);
    glint_image_info(b, &wb, &hb, pb);
    *w = wa;
    *n = wa * ha * 3;
    return wa == wb && ha == hb;
}

// Whether two images hold the same linear floats, bit for bit (the 8-bit output is then the same too).
static bool identical(const glint_image *a, const glint_image *b, const char *what) {
    int wa, n;
    const float *pa, *pb;
    if (!both_pixels(a, b, &wa, &n, &pa, &pb)) return false;
    for (int i = 0; i < n; i++)
        if (memcmp(&pa[i], &pb[i], sizeof pa[i]) != 0) {
            fprintf(stderr, "  %s: pixel (%d, %d) channel %d: %.9g vs %.9g\n", what, i / 3 % wa, i / 3 / wa, i % 3,
                    (double)pa[i], (double)pb[i]);
            return false;
        }
    return true;
}

// Whether two images agree but for float rounding: at most 1 channel value in 200 differs by more than 1e-4
// relative (a ray that grazes an edge may take another path), and none by more than 0.05 relative.
static bool nearly_identical(const glint_image *a, const glint_image *b, const char *what) {
    int wa, n, off = 0;
    const float *pa, *pb;
    if (!both_pixels(a, b, &wa, &n, &pa, &pb)) return false;
    (void)wa;
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        double d = fabs((double)pa[i] - (double)pb[i]) / fmax(1e-3, fabs((double)pa[i]));
        off += d > 1e-4;
        worst = fmax(worst, d);
    }
    bool ok = off * 200 <= n && worst <= 0.05;
    if (!ok) fprintf(stderr, "  %s: %d of %d values differ by > 1e-4, the most by %.3g\n", what, off, n, worst);
    return ok;
}

// Renders the scenes with objects `a` and with objects `b` for each integrator and structure and checks that
// each pair is identical (or nearly_identical when `rounding`: the scenes place the same triangles in ways whose
// ray distances may round differently); every image must also be the same for every structure (brute force
// included).
static void check_same_images(const char *a, const char *b, const char *what, bool rounding) {
    for (int integ = 0; integ < INTEGRATORS; integ++) {
        glint_image *first = NULL;
        for (int k = 0; k < ACCEL_KINDS; k++) {
            char label[160];
            snprintf(label, sizeof label, "%s, %s, accel %s", what, integrator_name[integ], accels[k]);
            glint_scene *sa = parse_scene(a, (which)integ, accels[k]), *sb = parse_scene(b, (which)integ, accels[k]);
            glint_image *ia = render(sa), *ib = render(sb);
            bool same = rounding ? nearly_identical(ia, ib, label) : identical(ia, ib, label);
            CHECK(same);
            if (!same) fprintf(stderr, "  ^ %s\n", label);
            if (k == 0) first = ia;
            else {
                CHECK(identical(first, ia, label));
                glint_image_free(ia);
            }
            glint_image_free(ib);
            glint_scene_free(sa);
            glint_scene_free(sb);
        }
        glint_image_free(first);
    }
}

// ---- the comparisons ------------------------------------------------------------------------------------

#define T1 "[{'rotate': {'axis': [1, 1, 0], 'degrees': 30}}, {'translate': [-0.75, 0.5, 0]}]"
#define T2 "[{'scale': [0.5, 1, 0.75]}, {'rotate': {'axis': [0, 1, 0], 'degrees': -20}}, " \
           "{'translate': [0.75, 0.25, -0.5]}]"
#define T3 "[{'translate': [0, 1.25, -1.5]}]"

// (a) One mesh file placed three times (one mesh, one BVH shared by the instances, rays moved to object space)
// against three files with the same content (three meshes, each placed once and so flattened into the world
// BVH in world space; each file's MTL materials its own scene materials): the same image but for the rounding
// of ray distances, which are computed in object space for the one and in world space for the other.
static void test_shared_and_separate_meshes(void) {
    const char *shared = "{'type': 'mesh', 'file': 'gem.obj', 'transform': " T1 "},\n"
                         "{'type': 'mesh', 'file': 'gem.obj', 'transform': " T2 "},\n"
                         "{'type': 'mesh', 'file': 'gem.obj', 'material': 'paint', 'transform': " T3 "}";
    const char *separate = "{'type': 'mesh', 'file': 'gem.obj', 'transform': " T1 "},\n"
                           "{'type': 'mesh', 'file': 'gem-copy.obj', 'transform': " T2 "},\n"
                           "{'type': 'mesh', 'file': 'gem-copy2.obj', 'material': 'paint', 'transform': " T3 "}";
    glint_scene *s = parse_scene(shared, PATH, "bvh");
    CHECK(s && s->mesh_count == 1 && s->instance_count == 3);
    glint_scene_free(s);
    s = parse_scene(separate, PATH, "bvh");
    CHECK(s && s->mesh_count == 3 && s->instance_count == 3);
    glint_scene_free(s);
    check_same_images(shared, separate, "shared vs separate meshes", true);
}

// (b) A mesh under a transform that composes to the identity (rotations by multiples of 90 degrees and scales
// by powers of two are exact in float) against the same file with no transform and with an empty one.
static void test_identity_transform(void) {
    const char *none = "{'type': 'mesh', 'file': 'gem.obj'}";
    const char *empty = "{'type': 'mesh', 'file': 'gem.obj', 'transform': []}";
    const char *composed =
        "{'type': 'mesh', 'file': 'gem.obj', 'transform': [{'rotate': {'axis': [0, 1, 0], 'degrees': 90}}, "
        "{'scale': 2}, {'rotate': {'axis': [0, 1, 0], 'degrees': -90}}, {'scale': 0.5}]}";
    glint_scene *s = parse_scene(composed, WHITTED, "bvh");
    CHECK(s && s->instance_count == 1);
    if (s && s->instance_count == 1) {
        bool exact = true;
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                exact = exact && s->instances[0].xf.m.m[i][j] == (i == j ? 1.0f : 0.0f) &&
                        s->instances[0].xf.inv.m[i][j] == (i == j ? 1.0f : 0.0f);
        CHECK(exact); // the premise of the comparison: the composed matrix is exactly the identity
        // What scene_add_instance caches of the transform, for shading.
        CHECK(s->instances[0].stretch == 1.0f && s->instances[0].keeps_directions);
    }
    glint_scene_free(s);
    s = parse_scene("{'type': 'mesh', 'file': 'gem.obj', 'transform': [{'rotate': {'axis': [0, 0, 1], 'degrees': 90}},"
                    " {'scale': [2, 1, 1]}]}",
                    WHITTED, "bvh");
    CHECK(s && s->instance_count == 1);
    if (s && s->instance_count == 1) {
        const instance *in = &s->instances[0];
        CHECK(in->stretch == mat4_stretch(&in->xf.m) && in->stretch > 1.9f && in->stretch < 2.1f);
        CHECK(!in->keeps_directions);
    }
    glint_scene_free(s);
    check_same_images(composed, none, "identity transform vs none", false);
    check_same_images(empty, none, "empty transform vs none", false);
}

// (b') Non-instanced against instanced: a box of six world-space quads against a mesh of the same twelve
// triangles (each quad's (p0, p1, p2) and (p0, p2, p3), the triangles quad_intersect tests, in the same
// winding), flat-shaded. The box is centred at the origin so that every corner's largest coordinate is 0.5:
// the spawned-ray offset, which scales with the primitive's largest coordinate (four corners of a quad, three
// of a triangle), is then the same for both; its normals are axis vectors, exact either way.
static void test_box_against_mesh(void) {
    const char *box = "{'type': 'box', 'min': [-0.5, -0.25, -0.5], 'max': [0.5, 0.25, 0.5], 'material': 'paint'}";
    glint_scene *s = parse_scene(box, PATH, "bvh");
    CHECK(s && s->quad_count == 8); // ground, lamp, six faces
    if (!s || s->quad_count != 8) {
        glint_scene_free(s);
        return;
    }
    char text[4096];
    size_t k = (size_t)snprintf(text, sizeof text, "# the box's faces as triangles\n");
    for (size_t q = 2; q < 8; q++)
        for (int c = 0; c < 4; c++) {
            vec3 p = s->quads[q].p[c];
            k += (size_t)snprintf(text + k, sizeof text - k, "v %.9g %.9g %.9g\n", (double)p.x, (double)p.y,
                                  (double)p.z);
        }
    for (int q = 0; q < 6; q++)
        k += (size_t)snprintf(text + k, sizeof text - k, "f %d %d %d\nf %d %d %d\n", 4 * q + 1, 4 * q + 2, 4 * q + 3,
                              4 * q + 1, 4 * q + 3, 4 * q + 4);
    CHECK(k < sizeof text);
    write_text("box.obj", text);
    glint_scene_free(s);
    check_same_images(box, "{'type': 'mesh', 'file': 'box.obj', 'material': 'paint', 'face_normals': true}",
                      "box of quads vs mesh", false);
}

// The largest difference between two images' linear values relative to max(1, |value|), and between their
// 8-bit values.
static void image_difference(const glint_image *a, const glint_image *b, double *max_rel, int *max_byte) {
    int w, h;
    const float *pa, *pb;
    glint_image_info(a, &w, &h, &pa);
    glint_image_info(b, &w, &h, &pb);
    *max_rel = 0.0;
    *max_byte = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                int i = 3 * (y * w + x) + c;
                double rel = fabs((double)pa[i] - pb[i]) / fmax(1.0, fabs((double)pa[i]));
                int d = abs((int)glint_image_byte(a, x, y, c) - (int)glint_image_byte(b, x, y, c));
                if (!(rel <= *max_rel)) *max_rel = rel; // (a NaN sticks)
                if (d > *max_byte) *max_byte = d;
            }
}

// (c) A mesh translated by (0.75, 0.25, -0.5) against a file whose vertices were moved by the same offset.
// Every vertex, the offset and the camera's eye are small dyadic numbers, so the world-space vertices, the
// object-space camera origin and both ray-triangle tests are computed without rounding: camera rays hit at
// the same t, the same triangle, with the same normals (edge vectors are exact differences either way).
// Spawned rays may differ in their last bits, for two principled reasons: their object-space origins
// o - offset are rounded, and their offset from the surface scales with the primitive's largest coordinate
// in object space (the error of intersecting it there), which for the translated copy is that of the
// untranslated vertices. So the linear values may differ by float rounding (the path tracer's do, by about
// 1e-7; the Whitted images come out identical), and 8-bit values by one step where that straddles a
// rounding boundary (none do here). A secondary ray whose hit changes with the last bit of its origin
// (one grazing an edge) would show up as a large difference. (The ground lies at y = -0.75, between the
// checker's planes y = -1 and -0.5: a ground at a checker plane would take its colour from rounding.)
static void test_translation_against_moved_vertices(void) {
    const char *moved = "{'type': 'mesh', 'file': 'gem.obj', 'transform': [{'translate': [0.75, 0.25, -0.5]}]},\n"
                        "{'type': 'mesh', 'file': 'gem.obj', 'material': 'paint'}";
    const char *baked = "{'type': 'mesh', 'file': 'gem-moved.obj'},\n"
                        "{'type': 'mesh', 'file': 'gem.obj', 'material': 'paint'}";
    for (int integ = 0; integ < INTEGRATORS; integ++)
        for (int k = 0; k < ACCEL_KINDS; k++) {
            glint_scene *sa = parse_scene(moved, (which)integ, accels[k]);
            glint_scene *sb = parse_scene(baked, (which)integ, accels[k]);
            glint_image *ia = render(sa), *ib = render(sb);
            if (ia && ib) {
                double max_rel;
                int max_byte;
                image_difference(ia, ib, &max_rel, &max_byte);
                if (!(max_rel <= 1e-5) || max_byte > 1)
                    fprintf(stderr, "  translated vs moved vertices, %s, accel %s: relative difference %g, 8-bit %d\n",
                            integrator_name[integ], accels[k], max_rel, max_byte);
                CHECK(max_rel <= 1e-5);
                CHECK(max_byte <= 1);
            }
            glint_image_free(ia);
            glint_image_free(ib);
            glint_scene_free(sa);
            glint_scene_free(sb);
        }
}

// (d) Spheres under similarities are baked into spheres: a scale by 2, a rotation by 90 degrees about z and a
// translation (exact in float), and a mirror of a hollow glass shell (the radii's signs are kept), against the
// spheres written out. Neither becomes an instance. (A baked sphere keeps no rotation: a textured sphere's
// texture coordinates stay those of the unrotated sphere, so a rotated image-textured globe does not turn.)
static void test_similarity_spheres(void) {
    const char *placed =
        "{'type': 'sphere', 'center': [0.25, 0, 0], 'radius': 0.5, 'material': 'paint', 'transform': "
        "[{'scale': 2}, {'rotate': {'axis': [0, 0, 1], 'degrees': 90}}, {'translate': [0.5, 0, -1]}]},\n"
        "{'type': 'sphere', 'center': [0.5, 0, 0], 'radius': 0.5, 'material': 'glass', 'transform': "
        "[{'scale': [-1, 1, 1]}, {'translate': [-0.5, 0.25, 0.75]}]},\n"
        "{'type': 'sphere', 'center': [0.5, 0, 0], 'radius': -0.375, 'material': 'glass', 'transform': "
        "[{'scale': [-1, 1, 1]}, {'translate': [-0.5, 0.25, 0.75]}]}";
    const char *plain = "{'type': 'sphere', 'center': [0.5, 0.5, -1], 'radius': 1, 'material': 'paint'},\n"
                        "{'type': 'sphere', 'center': [-1, 0.25, 0.75], 'radius': 0.5, 'material': 'glass'},\n"
                        "{'type': 'sphere', 'center': [-1, 0.25, 0.75], 'radius': -0.375, 'material': 'glass'}";
    glint_scene *s = parse_scene(placed, PATH, "bvh");
    CHECK(s && s->sphere_count == 5 && s->instance_count == 0);
    glint_scene_free(s);
    check_same_images(placed, plain, "similarity-transformed spheres vs spheres", false);
}

// (e) A sphere under a non-uniform scale is an ellipsoid instance. Its silhouette is checked against the
// analytic ellipsoid: an emitter of radiance 1 on a black background, seen directly (Whitted: one ray through
// each pixel centre; path tracer, depth 1: four jittered rays a pixel, each 0 or 1). Each of those camera rays
// is rebuilt here and intersected with the ellipsoid in double; the rendered value must be exactly the
// analytic count, except for rays that graze the silhouette to within 1e-4 of its size (float rounding of the
// transform decides those). The scale, rotation and translation are applied in double from their definitions.
static void test_ellipsoid_silhouette(void) {
    static const double scale[3] = {1.5, 0.75, 1}, degrees = 30, move[3] = {0.25, 0, -0.5};
    const double pi = 3.14159265358979323846, ca = cos(degrees * pi / 180), sa = sin(degrees * pi / 180);
    for (int integ = 0; integ < INTEGRATORS; integ++)
        for (int k = 0; k < ACCEL_KINDS; k++) {
            char text[2048];
            snprintf(text, sizeof text,
                     "{'render': {'width': 64, 'height': 48, 'spp': %d, 'max_depth': 1, 'seed': 5, "
                     "'integrator': %s, 'accel': '%s'},\n"
                     " 'camera': {'type': 'lookat', 'lookfrom': [0, 0, 5], 'lookat': [0, 0, 0], 'vfov': 30},\n"
                     " 'objects': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1,\n"
                     "   'material': {'type': 'diffuse_light', 'emission': 1},\n"
                     "   'transform': [{'scale': [1.5, 0.75, 1]}, {'rotate': {'axis': [0, 0, 1], 'degrees': 30}},"
                     " {'translate': [0.25, 0, -0.5]}]}]}\n",
                     integ == PATH ? 4 : 1, integrator_json[integ], accels[k]);
            json_quotes(text);
            glint_scene *s = NULL;
            glint_error err;
            CHECK(glint_scene_parse(tmp_path("ellipsoid.json"), text, strlen(text), &s, &err) == GLINT_OK);
            if (!s) continue;
            CHECK(s->sphere_count == 0 && s->instance_count == 1 && s->instances[0].kind == INSTANCE_SPHERE);
            glint_image *img = render(s);
            if (!img) {
                glint_scene_free(s);
                continue;
            }
            int w, h;
            const float *rgb;
            glint_image_info(img, &w, &h, &rgb);
            camera cam = s->camera; // as the render frame prepares it
            camera_prepare(&cam, w, h);
            int covered = 0, analytic = 0, mismatches = 0, grazing = 0;
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    int hits = 0, spp = s->settings.spp, near = 0;
                    for (int j = 0; j < spp; j++) {
                        // The camera ray of sample j, drawn exactly as the integrators draw it.
                        rng r = rng_for_stream(integrator_stream(&s->settings),
                                               rng_pixel_key(s->settings.seed, (uint64_t)y * (uint64_t)w + (uint64_t)x),
                                               (uint64_t)j);
                        float fx = (float)x + 0.5f, fy = (float)y + 0.5f; // Whitted's one ray: the centre
                        if (spp > 1) {
                            fx = (float)x + rng_float(&r);
                            fy = (float)y + rng_float(&r);
                        }
                        ray cr = camera_ray(&cam, fx, fy, &r);
                        // World to the unit sphere's space: undo the translation, the rotation, then the scale.
                        double o[3] = {cr.o.x - move[0], cr.o.y - move[1], cr.o.z - move[2]};
                        double d[3] = {cr.d.x, cr.d.y, cr.d.z};
                        double oo[3] = {(ca * o[0] + sa * o[1]) / scale[0], (-sa * o[0] + ca * o[1]) / scale[1],
                                        o[2] / scale[2]};
                        double dd[3] = {(ca * d[0] + sa * d[1]) / scale[0], (-sa * d[0] + ca * d[1]) / scale[1],
                                        d[2] / scale[2]};
                        // Distance of the (infinite) line from the centre: |o x d| / |d|; the eye is outside and the
                        // ellipsoid in front of it, so the ray hits exactly when that distance is below 1.
                        double cx = oo[1] * dd[2] - oo[2] * dd[1], cy = oo[2] * dd[0] - oo[0] * dd[2],
                               cz = oo[0] * dd[1] - oo[1] * dd[0];
                        double dd2 = dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2];
                        double dist = sqrt((cx * cx + cy * cy + cz * cz) / dd2);
                        hits += dist < 1.0;
                        near += fabs(dist - 1.0) < 1e-4;
                    }
                    float want = (float)hits / (float)spp, got = rgb[3 * (y * w + x)];
                    covered += got > 0.0f;
                    analytic += hits > 0;
                    if (got != want) {
                        if (near) grazing++;
                        else if (mismatches++ < 5)
                            fprintf(stderr, "  ellipsoid, %s, accel %s: pixel (%d, %d) is %g, analytic %g\n",
                                    integrator_name[integ], accels[k], x, y, (double)got, (double)want);
                    }
                }
            CHECK(mismatches == 0);
            CHECK(grazing <= 2);
            CHECK(analytic > 600); // half-axes of about 24 and 12 pixels: a real silhouette was compared
            CHECK(abs(covered - analytic) <= grazing);
            glint_image_free(img);
            glint_scene_free(s);
        }
}

int main(void) {
    if (!tmpdir_make("glint-test-instances")) return 1;
    write_files();
    test_shared_and_separate_meshes();
    test_identity_transform();
    test_box_against_mesh();
    test_translation_against_moved_vertices();
    test_similarity_spheres();
    test_ellipsoid_silhouette();
    tmpdir_remove();
    return check_summary();
}
