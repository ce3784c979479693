// test_aov.c — AOVs (albedo, normal, depth): values on scenes whose answers are known analytically (a wall
// facing the camera, a wall seen in a perfect mirror, a light, a sphere) for the path tracer and both Whitted
// modes; the colour unchanged by asking for AOVs; the same planes for any thread count and in a region; EXR
// channels and PFM files read back with exactly the planes' values (EXR through OpenEXR's own C library).
#include "check.h"
#include "test_util.h"

#include "glint.h"
#include "camera/camera.h"
#include "core/rng.h"
#include "integrator/integrator_common.h"
#include "film/film.h"
#include "scene/scene.h"

#include <math.h>
#include <openexr.h>
#include <stdint.h>

enum { W = 24, H = 16 };

static glint_scene *parse(const char *text) {
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_parse("aov.json", text, strlen(text), &s, &err) != GLINT_OK) {
        fprintf(stderr, "scene: %s\n", err.message);
        return NULL;
    }
    return s;
}

static glint_image *render(const glint_scene *s, unsigned aovs, int threads, const int region[4]) {
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = threads;
    opt.aovs = aovs;
    if (region) memcpy(opt.region, region, sizeof opt.region);
    glint_image *img = NULL;
    glint_error err;
    if (glint_render(s, &opt, NULL, NULL, &img, NULL, &err) != GLINT_OK) fprintf(stderr, "render: %s\n", err.message);
    return img;
}

static const float *plane(const glint_image *img, glint_aov aov) { return glint_image_aov(img, aov, NULL); }

// A sample's camera ray as the integrator makes it: the path tracer's jittered one, or (spp 1, Whitted) the
// pixel centre's; for the paper's viewport camera, the ray from the eye through the pixel's viewport point.
static ray sample_ray(const camera *cam, const glint_scene *s, bool centre, int x, int y, int k) {
    uint64_t key = rng_pixel_key(s->settings.seed, (uint64_t)y * W + (uint64_t)x);
    rng r = rng_for_stream(integrator_stream(&s->settings), key, (uint64_t)k);
    if (cam->kind == CAMERA_VIEWPORT) {
        double v[3];
        camera_viewport_point(cam, (double)x, (double)y + 1.0, v); // pixel (x, y) is film point (x, y + 1)
        ray out = {v3((float)cam->position[0], (float)cam->position[1], (float)cam->position[2]),
                   v3((float)v[0], (float)v[1], (float)v[2]), 0.0f, INFINITY, 0.0f};
        return out;
    }
    if (centre) return camera_ray(cam, (float)x + 0.5f, (float)y + 0.5f, &r);
    return camera_sample_ray(cam, x, y, &r);
}

// Every pixel sees the plane z = plane_z with the given albedo and normal (facing the camera): the albedo and
// normal planes hold exactly those, and the depth plane the mean distance to the plane along the pixel's rays.
static void check_wall(const char *what, const glint_scene *s, const glint_image *img, bool centre, float plane_z,
                       vec3 albedo, vec3 normal) {
    camera cam = s->camera;
    camera_prepare(&cam, W, H);
    const float *a = plane(img, GLINT_AOV_ALBEDO), *n = plane(img, GLINT_AOV_NORMAL), *z = plane(img, GLINT_AOV_DEPTH);
    CHECK(a && n && z);
    if (!a || !n || !z) return;
    int bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t p = (size_t)y * W + (size_t)x;
            double want_depth = 0.0;
            int spp = s->settings.spp;
            for (int k = 0; k < spp; k++) {
                ray r = sample_ray(&cam, s, centre, x, y, k);
                double t = ((double)plane_z - r.o.z) / r.d.z;
                want_depth += t * sqrt((double)r.d.x * r.d.x + (double)r.d.y * r.d.y + (double)r.d.z * r.d.z);
            }
            want_depth /= spp;
            float want_a[3] = {albedo.x, albedo.y, albedo.z}, want_n[3] = {normal.x, normal.y, normal.z};
            bool ok = fabs(z[p] - want_depth) <= 1e-5 * want_depth;
            for (int c = 0; c < 3; c++)
                ok = ok && fabsf(a[p * 3 + (size_t)c] - want_a[c]) <= 1e-6f && fabsf(n[p * 3 + (size_t)c] - want_n[c]) <= 1e-6f;
            if (!ok && bad++ < 3)
                fprintf(stderr, "%s: pixel (%d, %d): albedo %g %g %g normal %g %g %g depth %.7g, expected depth %.7g\n",
                        what, x, y, a[p * 3], a[p * 3 + 1], a[p * 3 + 2], n[p * 3], n[p * 3 + 1], n[p * 3 + 2], z[p],
                        want_depth);
        }
    CHECK(bad == 0);
}

#define WALL_SCENE(integrator, spp, material, objects)                                                          \
    "{\"render\": {\"width\": 24, \"height\": 16, \"spp\": " spp ", \"max_depth\": 4, \"seed\": 5,"              \
    " \"integrator\": " integrator ", \"background\": [0.2, 0.4, 0.6]},"                                            \
    " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"vfov\": 50},"           \
    " \"materials\": {" material "}, \"objects\": [" objects "]}"

// A Lambertian wall at z = -2 facing the camera, filling the view.
#define WALL "{\"type\": \"quad\", \"q\": [-10, -10, -2], \"u\": [20, 0, 0], \"v\": [0, 20, 0], \"material\": \"wall\"}"

static void test_wall(void) {
    static const char *const integrators[] = {"\"path\"", "\"whitted\""};
    for (int i = 0; i < 2; i++) {
        char text[2048];
        snprintf(text, sizeof text,
                 WALL_SCENE("%s", "%s", "\"wall\": {\"type\": \"lambertian\", \"albedo\": [0.3, 0.5, 0.7]}", WALL),
                 i == 0 ? "4" : "1", integrators[i]); // spp comes first in the text
        glint_scene *s = parse(text);
        CHECK(s != NULL);
        if (!s) continue;
        glint_image *img = render(s, GLINT_AOV_ALL, 2, NULL);
        CHECK(img != NULL);
        if (img) check_wall(integrators[i], s, img, i == 1, -2.0f, v3(0.3f, 0.5f, 0.7f), v3(0, 0, 1));
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// A perfect mirror (metal, fuzz 0, albedo 0.5) at z = -2 reflects a Lambertian wall behind the camera: the path
// tracer looks past the mirror, so the albedo is the wall's tinted by the mirror and the normal the wall's;
// the depth is the mirror's. The Whitted integrators record the mirror itself.
static void test_mirror(void) {
    const char *text = WALL_SCENE(
        "\"path\"", "4",
        "\"mirror\": {\"type\": \"metal\", \"albedo\": 0.5, \"fuzz\": 0},"
        " \"wall\": {\"type\": \"lambertian\", \"albedo\": [0.2, 0.4, 0.8]}",
        "{\"type\": \"quad\", \"q\": [-10, -10, -2], \"u\": [20, 0, 0], \"v\": [0, 20, 0], \"material\": \"mirror\"},"
        " {\"type\": \"quad\", \"q\": [-10, -10, 1], \"u\": [0, 20, 0], \"v\": [20, 0, 0], \"material\": \"wall\"}");
    glint_scene *s = parse(text);
    CHECK(s != NULL);
    if (!s) return;
    glint_image *img = render(s, GLINT_AOV_ALL, 2, NULL);
    CHECK(img != NULL);
    if (img) check_wall("mirror", s, img, false, -2.0f, v3(0.1f, 0.2f, 0.4f), v3(0, 0, -1));
    glint_image_free(img);
    glint_scene_free(s);
}

// A light's albedo is its emission scaled to a largest channel of 1.
static void test_emitter(void) {
    const char *text = WALL_SCENE("\"path\"", "2", "\"wall\": {\"type\": \"diffuse_light\", \"emission\": [4, 2, 1]}",
                                  WALL);
    glint_scene *s = parse(text);
    CHECK(s != NULL);
    if (!s) return;
    glint_image *img = render(s, GLINT_AOV_ALL, 1, NULL);
    CHECK(img != NULL);
    if (img) check_wall("emitter", s, img, false, -2.0f, v3(1.0f, 0.5f, 0.25f), v3(0, 0, 1));
    glint_image_free(img);
    glint_scene_free(s);
}

#define SPHERE_SCENE(integrator, spp, background)                                                               \
    "{\"render\": {\"width\": 24, \"height\": 16, \"spp\": " spp ", \"max_depth\": 4, \"seed\": 9,"              \
    " \"integrator\": " integrator background "},"                                                                 \
    " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"vfov\": 40},"           \
    " \"lights\": [{\"type\": \"point\", \"position\": [2, 3, 1], \"intensity\": 5}],"                             \
    " \"materials\": {\"clay\": {\"type\": \"lambertian\", \"albedo\": [0.6, 0.3, 0.1]}},"                         \
    " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0.2, -3], \"radius\": 1, \"material\": \"clay\"}]}"

static const char *const SPHERE_PATH = SPHERE_SCENE("\"path\"", "4", ", \"background\": [0.2, 0.4, 0.6]");

// A sphere (centre (0, 0.2, cz), radius 1, albedo (0.6, 0.3, 0.1)) against the background `bg`: each pixel's
// planes against the sphere met analytically (in double) by the pixel's rays; pixels with a ray that grazes
// the outline are skipped, where float and double may disagree about hit or miss.
static void check_sphere(const char *what, const glint_scene *s, const glint_image *img, bool centre, vec3 bg,
                         double cz) {
    camera cam = s->camera;
    camera_prepare(&cam, W, H);
    const float *a = plane(img, GLINT_AOV_ALBEDO), *n = plane(img, GLINT_AOV_NORMAL), *z = plane(img, GLINT_AOV_DEPTH);
    CHECK(a && n && z);
    if (!a || !n || !z) return;
    const double cx = 0.0, cy = 0.2, albedo[3] = {0.6, 0.3, 0.1}, back[3] = {bg.x, bg.y, bg.z};
    int bad = 0, checked = 0, hits = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int spp = s->settings.spp, hit_count = 0;
            double want_a[3] = {0, 0, 0}, want_n[3] = {0, 0, 0}, depth = 0.0;
            bool grazing = false;
            for (int k = 0; k < spp; k++) {
                ray r = sample_ray(&cam, s, centre, x, y, k);
                double o[3] = {r.o.x - cx, r.o.y - cy, r.o.z - cz}, d[3] = {r.d.x, r.d.y, r.d.z};
                double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], od = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
                double oo = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
                double disc = od * od - dd * (oo - 1.0);
                if (fabs(disc) < 1e-2 * dd) grazing = true;
                if (disc < 0.0) {
                    for (int c = 0; c < 3; c++) want_a[c] += back[c];
                    continue;
                }
                double t = (-od - sqrt(disc)) / dd;
                hit_count++;
                depth += t * sqrt(dd);
                for (int c = 0; c < 3; c++) {
                    want_a[c] += albedo[c];
                    want_n[c] += o[c] + t * d[c]; // radius 1: the point is the unit normal
                }
            }
            if (grazing) continue;
            checked++;
            hits += hit_count > 0;
            size_t p = (size_t)y * W + (size_t)x;
            bool ok = hit_count ? fabs(z[p] - depth / hit_count) <= 1e-4 * z[p] : isinf(z[p]) && z[p] > 0;
            for (int c = 0; c < 3; c++)
                ok = ok && fabs(a[p * 3 + (size_t)c] - want_a[c] / spp) <= 1e-6 &&
                     fabs(n[p * 3 + (size_t)c] - want_n[c] / spp) <= 1e-4;
            if (!ok && bad++ < 3)
                fprintf(stderr, "%s: pixel (%d, %d): albedo %g %g %g normal %g %g %g depth %.7g\n", what, x, y, a[p * 3],
                        a[p * 3 + 1], a[p * 3 + 2], n[p * 3], n[p * 3 + 1], n[p * 3 + 2], z[p]);
        }
    CHECK(bad == 0);
    CHECK(checked > W * H / 2 && hits > 20 && hits < checked); // both the sphere and the background were checked
}

// The paper's viewport camera (the eye at the origin, looking along +z) and the sphere in front of it: depths
// are measured from the eye, in colour mode too, whose rays start on the viewport.
#define VIEWPORT_SCENE(mode)                                                                                    \
    "{\"render\": {\"width\": 24, \"height\": 16, \"spp\": 1, \"max_depth\": 3, \"seed\": 9,"              \
    " \"integrator\": {\"type\": \"whitted\", \"mode\": \"" mode "\"}},"                                          \
    " \"camera\": {\"type\": \"viewport\", \"position\": [0, 0, 0], \"viewport\": [1.5, 1], \"distance\": 1},"   \
    " \"lights\": [{\"type\": \"point\", \"position\": [2, 3, 1], \"intensity\": 0.8}],"                        \
    " \"materials\": {\"clay\": {\"type\": \"phong\", \"color\": [0.6, 0.3, 0.1], \"specular\": 10}},"            \
    " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0.2, 3], \"radius\": 1, \"material\": \"clay\"}]}"

static void test_sphere(void) {
    struct {
        const char *text;
        bool centre;
        vec3 bg;
        double cz;
    } cases[] = {
        {SPHERE_PATH, false, {0.2f, 0.4f, 0.6f}, -3.0},
        {SPHERE_SCENE("\"whitted\"", "1", ", \"background\": [0.2, 0.4, 0.6]"), true, {0.2f, 0.4f, 0.6f}, -3.0},
        // The paper's program sees a white background.
        {SPHERE_SCENE("{\"type\": \"whitted\", \"mode\": \"paper\"}", "1", ""), true, {1.0f, 1.0f, 1.0f}, -3.0},
        {VIEWPORT_SCENE("paper"), true, {1.0f, 1.0f, 1.0f}, 3.0},
        {VIEWPORT_SCENE("color"), true, {0.0f, 0.0f, 0.0f}, 3.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        glint_scene *s = parse(cases[i].text);
        CHECK(s != NULL);
        if (!s) continue;
        glint_image *img = render(s, GLINT_AOV_ALL, 2, NULL);
        CHECK(img != NULL);
        char what[32];
        snprintf(what, sizeof what, "sphere %zu", i);
        if (img) check_sphere(what, s, img, cases[i].centre, cases[i].bg, cases[i].cz);
        // Asking for AOVs changes nothing in the colour.
        glint_image *plain = render(s, 0, 2, NULL);
        CHECK(plain && img && memcmp(plain->rgb, img->rgb, (size_t)W * H * 3 * sizeof(float)) == 0);
        CHECK(plain && !plane(plain, GLINT_AOV_ALBEDO) && !plane(plain, GLINT_AOV_NORMAL) && !plane(plain, GLINT_AOV_DEPTH));
        glint_image_free(plain);
        glint_image_free(img);
        glint_scene_free(s);
    }
}

// The planes are the same bytes for any thread count, and a region's are the full render's pixels.
static void test_determinism(void) {
    glint_scene *s = parse(SPHERE_PATH);
    CHECK(s != NULL);
    if (!s) return;
    glint_image *one = render(s, GLINT_AOV_ALL, 1, NULL), *two = render(s, GLINT_AOV_ALL, 2, NULL);
    const int region[4] = {5, 3, 17, 11};
    glint_image *part = render(s, GLINT_AOV_NORMAL | GLINT_AOV_DEPTH, 2, region);
    CHECK(one && two && part);
    if (one && two && part) {
        for (int i = 0; i < 3; i++) {
            glint_aov aov = (glint_aov)(1 << i);
            int ch = 0;
            const float *p1 = glint_image_aov(one, aov, &ch), *p2 = glint_image_aov(two, aov, NULL);
            CHECK(ch == (i == 2 ? 1 : 3));
            CHECK(p1 && p2 && memcmp(p1, p2, (size_t)W * H * (size_t)ch * sizeof(float)) == 0);
            const float *pr = glint_image_aov(part, aov, NULL);
            if (i == 0) {
                CHECK(pr == NULL); // not asked for
                continue;
            }
            int bad = 0;
            for (int y = region[1]; pr && y < region[3]; y++)
                for (int x = region[0]; x < region[2]; x++) {
                    size_t at = ((size_t)(y - region[1]) * (size_t)(region[2] - region[0]) + (size_t)(x - region[0]));
                    bad += memcmp(&pr[at * (size_t)ch], &p1[((size_t)y * W + (size_t)x) * (size_t)ch],
                                  (size_t)ch * sizeof(float)) != 0;
                }
            CHECK(pr && bad == 0);
        }
    }
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.aovs = 16; // no such AOV
    glint_image *img = NULL;
    glint_error err;
    CHECK(glint_render(s, &opt, NULL, NULL, &img, NULL, &err) == GLINT_ERR_INPUT && img == NULL);
    glint_image_free(one);
    glint_image_free(two);
    glint_image_free(part);
    glint_scene_free(s);
}

// ---- files ----

enum { MAX_CHANNELS = 16 };

/// An EXR read back: windows, and each channel's name, type and values (data window size, row 0 at the top).
typedef struct exr_back {
    exr_attr_box2i_t data, display;
    int count;
    char names[MAX_CHANNELS][16];
    exr_pixel_type_t types[MAX_CHANNELS];
    float *values[MAX_CHANNELS];
} exr_back;

static bool read_exr(const char *path, exr_back *b) {
    memset(b, 0, sizeof *b);
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS) return false;
    const exr_attr_chlist_t *chl = NULL;
    int32_t lines = 0;
    bool ok = exr_get_data_window(ctx, 0, &b->data) == EXR_ERR_SUCCESS &&
              exr_get_display_window(ctx, 0, &b->display) == EXR_ERR_SUCCESS &&
              exr_get_channels(ctx, 0, &chl) == EXR_ERR_SUCCESS &&
              exr_get_scanlines_per_chunk(ctx, 0, &lines) == EXR_ERR_SUCCESS && chl->num_channels <= MAX_CHANNELS;
    int w = b->data.max.x - b->data.min.x + 1, h = b->data.max.y - b->data.min.y + 1;
    for (int c = 0; ok && c < chl->num_channels; c++) {
        snprintf(b->names[c], sizeof b->names[c], "%s", chl->entries[c].name.str);
        b->types[c] = chl->entries[c].pixel_type;
        b->values[c] = calloc((size_t)w * (size_t)h, sizeof(float));
        ok = b->values[c] != NULL;
        b->count = c + 1;
    }
    for (int y = 0; ok && y < h; y += lines) {
        exr_chunk_info_t ci;
        exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
        ok = exr_read_scanline_chunk_info(ctx, 0, b->data.min.y + y, &ci) == EXR_ERR_SUCCESS &&
             exr_decoding_initialize(ctx, 0, &ci, &dec) == EXR_ERR_SUCCESS;
        for (int16_t c = 0; ok && c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            float *dst = b->values[c]; // the pipeline lists the channels in the header's order
            ch->decode_to_ptr = (uint8_t *)(dst + (size_t)(ci.start_y - b->data.min.y) * (size_t)w);
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)(sizeof(float) * (size_t)w);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
        }
        ok = ok && exr_decoding_choose_default_routines(ctx, 0, &dec) == EXR_ERR_SUCCESS &&
             exr_decoding_run(ctx, 0, &dec) == EXR_ERR_SUCCESS;
        exr_decoding_destroy(ctx, &dec);
    }
    exr_finish(&ctx);
    return ok;
}

static void exr_back_free(exr_back *b) {
    for (int c = 0; c < b->count; c++) free(b->values[c]);
}

static const float *channel(const exr_back *b, const char *name, exr_pixel_type_t *type) {
    for (int c = 0; c < b->count; c++)
        if (strcmp(b->names[c], name) == 0) {
            if (type) *type = b->types[c];
            return b->values[c];
        }
    return NULL;
}

// Reads a little-endian PFM: its kind ('F' or 'f'), size and floats.
static float *read_pfm(const char *path, char *kind, int *w, int *h) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    float *v = NULL;
    double scale = 0;
    if (fscanf(f, "P%c %d %d %lf", kind, w, h, &scale) == 4 && fgetc(f) == '\n' && scale < 0) {
        size_t n = (size_t)*w * (size_t)*h * (*kind == 'F' ? 3u : 1u);
        v = malloc(n * sizeof *v);
        if (v && fread(v, sizeof *v, n, f) != n) {
            free(v);
            v = NULL;
        }
    }
    fclose(f);
    return v;
}

// Whether channel `name` holds, for every pixel, component c of a plane of `stride` floats a pixel (bit for bit,
// or to half precision).
static bool channel_matches(const exr_back *b, const char *name, const float *plane_data, int stride, int c,
                            size_t pixels, bool half) {
    const float *v = channel(b, name, NULL);
    if (!v) return false;
    for (size_t p = 0; p < pixels; p++) {
        float want = plane_data[p * (size_t)stride + (size_t)c];
        if (half ? !(fabsf(v[p] - want) <= fabsf(want) / 1024.0f || (isinf(want) && v[p] == want))
                 : memcmp(&v[p], &want, sizeof want) != 0)
            return false;
    }
    return true;
}

static void test_exr(void) {
    glint_scene *s = parse(SPHERE_PATH);
    CHECK(s != NULL);
    if (!s) return;
    glint_image *img = render(s, GLINT_AOV_ALL, 2, NULL);
    CHECK(img != NULL);
    if (!img) {
        glint_scene_free(s);
        return;
    }
    glint_error err;
    static const char *const sorted[] = {"B",        "G",        "R",        "Z",        "albedo.B", "albedo.G",
                                         "albedo.R", "normal.X", "normal.Y", "normal.Z", "samples"};
    size_t pixels = (size_t)W * H;
    for (int half = 0; half < 2; half++) {
        const char *path = tmp_path(half ? "half.exr" : "float.exr");
        CHECK(glint_image_write(img, path, half ? GLINT_FORMAT_EXR_HALF : GLINT_FORMAT_AUTO, &err) == GLINT_OK);
        exr_back b;
        CHECK(read_exr(path, &b));
        CHECK(b.count == 11);
        for (int c = 0; c < b.count && c < 11; c++) CHECK(strcmp(b.names[c], sorted[c]) == 0);
        CHECK(b.data.min.x == 0 && b.data.min.y == 0 && b.data.max.x == W - 1 && b.data.max.y == H - 1);
        exr_pixel_type_t type = EXR_PIXEL_UINT;
        CHECK(channel(&b, "Z", &type) && type == EXR_PIXEL_FLOAT); // depth stays 32-bit in a half file
        CHECK(channel(&b, "samples", &type) && type == EXR_PIXEL_FLOAT); // and so does the sample count
        CHECK(channel(&b, "albedo.G", &type) && type == (half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT));
        const float *albedo = plane(img, GLINT_AOV_ALBEDO), *normal = plane(img, GLINT_AOV_NORMAL);
        CHECK(channel_matches(&b, "albedo.R", albedo, 3, 0, pixels, half));
        CHECK(channel_matches(&b, "albedo.B", albedo, 3, 2, pixels, half));
        CHECK(channel_matches(&b, "normal.X", normal, 3, 0, pixels, half));
        CHECK(channel_matches(&b, "normal.Z", normal, 3, 2, pixels, half));
        CHECK(channel_matches(&b, "Z", plane(img, GLINT_AOV_DEPTH), 1, 0, pixels, false));
        CHECK(channel_matches(&b, "samples", plane(img, GLINT_AOV_SAMPLES), 1, 0, pixels, false));
        if (!half) {
            // The colour channels hold exactly the PFM's values (PFM rows run from the bottom up).
            const char *pfm = tmp_path("beauty.pfm");
            CHECK(glint_image_write(img, pfm, GLINT_FORMAT_AUTO, &err) == GLINT_OK);
            char kind = 0;
            int w = 0, h = 0;
            float *v = read_pfm(pfm, &kind, &w, &h);
            CHECK(v && kind == 'F' && w == W && h == H);
            int bad = 0;
            static const char *const rgb[3] = {"R", "G", "B"};
            for (int c = 0; v && c < 3; c++) {
                const float *ch = channel(&b, rgb[c], NULL);
                for (int y = 0; ch && y < H; y++)
                    for (int x = 0; x < W; x++)
                        bad += memcmp(&ch[(size_t)y * W + (size_t)x], &v[((size_t)(H - 1 - y) * W + (size_t)x) * 3 + (size_t)c],
                                      sizeof(float)) != 0;
            }
            CHECK(bad == 0);
            free(v);
        }
        exr_back_free(&b);
    }
    glint_image_free(img);

    // A region: its data window inside the full display window, its AOV values those of its pixels.
    const int region[4] = {3, 5, 20, 13};
    glint_image *part = render(s, GLINT_AOV_DEPTH, 2, region);
    CHECK(part != NULL);
    const char *path = tmp_path("region.exr");
    CHECK(part && glint_image_write(part, path, GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    exr_back b;
    CHECK(read_exr(path, &b));
    CHECK(b.count == 4 && strcmp(b.names[3], "Z") == 0);
    CHECK(b.display.min.x == 0 && b.display.min.y == 0 && b.display.max.x == W - 1 && b.display.max.y == H - 1);
    CHECK(b.data.min.x == 3 && b.data.min.y == 5 && b.data.max.x == 19 && b.data.max.y == 12);
    if (part) CHECK(channel_matches(&b, "Z", plane(part, GLINT_AOV_DEPTH), 1, 0, 17u * 8u, false));
    if (part) CHECK(channel_matches(&b, "G", part->rgb, 3, 1, 17u * 8u, false));
    exr_back_free(&b);
    glint_image_free(part);
    glint_scene_free(s);
}

static void test_pfm(void) {
    glint_scene *s = parse(SPHERE_PATH);
    CHECK(s != NULL);
    if (!s) return;
    glint_image *img = render(s, GLINT_AOV_ALBEDO | GLINT_AOV_DEPTH, 1, NULL);
    CHECK(img != NULL);
    if (!img) {
        glint_scene_free(s);
        return;
    }
    glint_error err;
    static const struct { glint_aov aov; const char *name; char kind; int ch; } files[] = {
        {GLINT_AOV_ALBEDO, "out.albedo.pfm", 'F', 3}, {GLINT_AOV_DEPTH, "out.depth.pfm", 'f', 1}};
    for (int i = 0; i < 2; i++) {
        const char *path = tmp_path(files[i].name);
        CHECK(glint_image_write_aov(img, files[i].aov, path, &err) == GLINT_OK);
        char kind = 0;
        int w = 0, h = 0;
        float *v = read_pfm(path, &kind, &w, &h);
        CHECK(v && kind == files[i].kind && w == W && h == H);
        const float *p = plane(img, files[i].aov);
        int bad = 0;
        for (int y = 0; v && y < H; y++)
            bad += memcmp(&v[(size_t)(H - 1 - y) * W * (size_t)files[i].ch], &p[(size_t)y * W * (size_t)files[i].ch],
                          (size_t)W * (size_t)files[i].ch * sizeof(float)) != 0;
        CHECK(bad == 0);
        free(v);
    }
    // Not asked for, not a PFM, not one AOV: input errors, and no file.
    CHECK(glint_image_write_aov(img, GLINT_AOV_NORMAL, tmp_path("n.pfm"), &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "has no normal AOV") != NULL);
    CHECK(access(tmp_path("n.pfm"), F_OK) != 0);
    CHECK(glint_image_write_aov(img, GLINT_AOV_ALBEDO, tmp_path("a.png"), &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "expected a .pfm file") != NULL);
    CHECK(glint_image_write_aov(img, GLINT_AOV_ALL, tmp_path("all.pfm"), &err) == GLINT_ERR_INPUT);
    CHECK(glint_image_aov(img, GLINT_AOV_ALL, NULL) == NULL);
    glint_image_free(img);
    glint_scene_free(s);
}

int main(void) {
    if (!tmpdir_make("glint-aov")) return 1;
    test_wall();
    test_mirror();
    test_emitter();
    test_sphere();
    test_determinism();
    test_exr();
    test_pfm();
    tmpdir_remove();
    return check_summary();
}
