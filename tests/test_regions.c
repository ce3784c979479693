// test_regions.c — rendering a region gives its pixels exactly as a full render does (linear floats and 8-bit
// bytes), on any thread count, with either sampler and with adaptive sampling; bad regions are refused; region PNGs merge back into the full
// image.
#include "check.h"
#include "test_load.h"
#include "glint.h"
#include "render/render.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static glint_scene *load(const char *name, long width, long height, const char *sampler, double noise_threshold) {
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = width;
    o.height = height;
    o.sampler = sampler;
    o.noise_threshold = noise_threshold;
    if (noise_threshold > 0) o.spp = 64;
    glint_scene *s = test_load(test_data_path(name), &o);
    CHECK(s != NULL);
    return s;
}

// How render() builds the BVH (stream_min_bytes, ...: the tests' knobs); zero: the defaults.
static accel_build_options build_knobs;

static glint_image *render(const glint_scene *s, int threads, int x0, int y0, int x1, int y1, glint_status *st,
                           glint_error *err) {
    render_options opt = {.threads = threads, .region = {x0, y0, x1, y1}, .accel = build_knobs};
    glint_image *img = NULL;
    *st = render_scene(s, &opt, NULL, NULL, &img, NULL, err);
    return img;
}

// Whether region (x0, y0) of `part` holds exactly full's pixels there: linear floats and display bytes.
static bool same_pixels(const glint_image *full, const glint_image *part, int x0, int y0) {
    int fw, fh, pw, ph;
    const float *frgb, *prgb;
    glint_image_info(full, &fw, &fh, &frgb);
    glint_image_info(part, &pw, &ph, &prgb);
    for (int y = 0; y < ph; y++) {
        const float *want = &frgb[((size_t)(y0 + y) * (size_t)fw + (size_t)x0) * 3u];
        if (memcmp(want, &prgb[(size_t)y * (size_t)pw * 3u], (size_t)pw * 3u * sizeof *want) != 0) return false;
        for (int x = 0; x < pw; x++)
            for (int c = 0; c < 3; c++)
                if (glint_image_byte(full, x0 + x, y0 + y, c) != glint_image_byte(part, x, y, c)) return false;
    }
    return true;
}

// A 4 x 3 split at uneven places (crossing the 16-pixel tiles), and single pixels and rows, on 1 and 3 threads.
// `streams`: the path tracer's stream loop forced (stream_min_bytes), its rays traversed together.
static void test_regions_match(const char *scene, int width, int height, bool streams, const char *sampler,
                               double noise_threshold) {
    glint_scene *s = load(scene, width, height, sampler, noise_threshold);
    CHECK(s != NULL);
    if (!s) return;
    build_knobs = (accel_build_options){.stream_min_bytes = streams ? 1 : 0, .interleave_min_bytes = streams ? 1 : 0};
    glint_status st;
    glint_error err;
    glint_image *full = render(s, 2, 0, 0, 0, 0, &st, &err);
    CHECK(st == GLINT_OK && full);
    int xs[5] = {0, 7, 17, 33, width}, ys[4] = {0, 5, 16, height};
    int mismatches = 0, parts = 0;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 4; i++) {
            glint_image *part = render(s, 1 + (i + j) % 3, xs[i], ys[j], xs[i + 1], ys[j + 1], &st, &err);
            int w = 0, h = 0;
            const float *rgb;
            if (part) glint_image_info(part, &w, &h, &rgb);
            CHECK(st == GLINT_OK && w == xs[i + 1] - xs[i] && h == ys[j + 1] - ys[j]);
            if (part && !same_pixels(full, part, xs[i], ys[j])) mismatches++;
            parts += part != NULL;
            glint_image_free(part);
        }
    CHECK(parts == 12 && mismatches == 0);
    // The whole image given as a region, one pixel, the last row.
    const int more[3][4] = {
        {0, 0, width, height}, {width - 1, height - 1, width, height}, {0, height - 1, width, height}};
    for (int k = 0; k < 3; k++) {
        glint_image *part = render(s, 2, more[k][0], more[k][1], more[k][2], more[k][3], &st, &err);
        CHECK(st == GLINT_OK && part && same_pixels(full, part, more[k][0], more[k][1]));
        glint_image_free(part);
    }
    glint_image_free(full);
    glint_scene_free(s);
    build_knobs = (accel_build_options){0};
}

// Regions that are empty or reach outside the image are input errors with their exact messages, and no image.
static void test_bad_regions(void) {
    glint_scene *s = load("tiny.json", 24, 16, NULL, -1);
    CHECK(s != NULL);
    if (!s) return;
    static const struct {
        int r[4];
        const char *message;
    } bad[] = {
        {{0, 0, 25, 16}, "--region: 0,0,25,16 is not inside the 24x16 image, expected 0 <= X0 < X1 <= 24 and "
                         "0 <= Y0 < Y1 <= 16"},
        {{-1, 0, 4, 4}, "--region: -1,0,4,4 is not inside the 24x16 image, expected 0 <= X0 < X1 <= 24 and "
                        "0 <= Y0 < Y1 <= 16"},
        {{0, 0, 24, 17}, "--region: 0,0,24,17 is not inside the 24x16 image, expected 0 <= X0 < X1 <= 24 and "
                         "0 <= Y0 < Y1 <= 16"},
        {{5, 0, 5, 4}, "--region: 5,0,5,4 is empty, expected X0 < X1 and Y0 < Y1"},
        {{0, 4, 4, 3}, "--region: 0,4,4,3 is empty, expected X0 < X1 and Y0 < Y1"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        glint_status st;
        glint_error err;
        glint_image *img = render(s, 1, bad[i].r[0], bad[i].r[1], bad[i].r[2], bad[i].r[3], &st, &err);
        CHECK(st == GLINT_ERR_INPUT && img == NULL);
        CHECK(strcmp(err.message, bad[i].message) == 0);
        if (strcmp(err.message, bad[i].message) != 0) fprintf(stderr, "got: %s\n", err.message);
    }
    glint_scene_free(s);
}

// Two region PNGs merge into exactly the full render's PNG file; a region's PNG is not a whole image's.
static void test_merge(void) {
    glint_scene *s = load("tiny.json", 24, 16, NULL, -1);
    CHECK(s != NULL);
    if (!s) return;
    glint_status st;
    glint_error err;
    glint_image *full = render(s, 2, 0, 0, 0, 0, &st, &err);
    glint_image *left = render(s, 2, 0, 0, 10, 16, &st, &err);
    glint_image *right = render(s, 2, 10, 0, 24, 16, &st, &err);
    CHECK(full && left && right);
    if (full && left && right) {
        CHECK(glint_image_write(full, "regions-full.png", GLINT_FORMAT_AUTO, &err) == GLINT_OK);
        CHECK(glint_image_write(left, "regions-left.png", GLINT_FORMAT_AUTO, &err) == GLINT_OK);
        CHECK(glint_image_write(right, "regions-right.png", GLINT_FORMAT_AUTO, &err) == GLINT_OK);
        const char *parts[] = {"regions-right.png", "regions-left.png"};
        CHECK(glint_merge("regions-merged.png", parts, 2, &err) == GLINT_OK);
        FILE *a = fopen("regions-full.png", "rb"), *b = fopen("regions-merged.png", "rb");
        CHECK(a && b);
        int ca = 0, cb = 0;
        while (a && b && (ca = getc(a)) == (cb = getc(b)) && ca != EOF) {}
        CHECK(a && b && ca == EOF && cb == EOF);
        if (a) fclose(a);
        if (b) fclose(b);
        CHECK(glint_merge("regions-merged.png", parts, 1, &err) == GLINT_ERR_INPUT);
        CHECK(strcmp(err.message, "no part covers pixel (0, 0) of the 24x16 image (160 pixels missing)") == 0);
        CHECK(glint_merge("regions-merged.pfm", parts, 2, &err) == GLINT_ERR_INPUT);
        CHECK(strcmp(err.message,
                     "regions-merged.pfm: regions-right.png is an 8-bit PNG part: its bytes are display-encoded, not "
                     "linear light, so 8-bit parts merge to .png or .ppm alone (render .exr or .pfm parts for a float "
                     "merge)") == 0);
        remove("regions-full.png");
        remove("regions-left.png");
        remove("regions-right.png");
        remove("regions-merged.png");
    }
    glint_image_free(full);
    glint_image_free(left);
    glint_image_free(right);
    glint_scene_free(s);
}

int main(void) {
    for (int i = 0; i < 2; i++) {
        const char *sampler = i ? "independent" : "sobol";
        // The path tracer: camera rays sixteen at a time, 3 passes; its stream loop (a quad ground).
        test_regions_match("tiny-path.json", 40, 30, false, sampler, -1);
        test_regions_match("tiny-path-quad.json", 40, 30, true, sampler, -1);
    }
    // Adaptive sampling (decisions from each pixel's own sums: a region cannot change them) at 64 spp, 7 passes.
    test_regions_match("tiny-path.json", 40, 30, false, "sobol", 0.05);
    test_regions_match("tiny-path-quad.json", 40, 30, true, "independent", 0.05);
    test_regions_match("tiny.json", 40, 30, false, NULL, -1); // a Whitted integrator: sample by sample
    test_bad_regions();
    test_merge();
    return check_summary();
}
