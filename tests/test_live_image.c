// test_live_image.c — what a preview window is given: glint_image_rgb8 encodes exactly as glint_image_byte (every
// float near each change of byte, a sweep of the rest, the odd values) under every encoding; the live image
// callback of glint_render hears the render while it runs and once at the end, with the final image, and is
// heard again after a stop.
#include "check.h"
#include "film/film.h"
#include "glint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SWEEP_STRIDE = 256, ROW = 1024 };

static float bits_float(uint32_t u) {
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

// Encodes n values through glint_image_rgb8 (the values as a ROW-wide image) and compares every byte with
// film_encode; returns the number that differ.
static size_t mismatches(const float *values, size_t n, output_transform enc) {
    size_t rows = (n + ROW - 1) / ROW, differ = 0;
    glint_image *img = film_image_new(ROW, (int)rows, enc);
    uint8_t *bytes = malloc(rows * ROW * 3u);
    if (!img || !bytes) {
        film_image_free(img);
        free(bytes);
        return n + 1;
    }
    for (size_t i = 0; i < n; i++) img->rgb[i] = values[i];
    glint_image_rgb8(img, bytes);
    for (size_t i = 0; i < n; i++)
        if (bytes[i] != film_encode(values[i], enc)) {
            uint32_t u;
            memcpy(&u, &values[i], sizeof u);
            if (differ++ < 5)
                fprintf(stderr, "encoding %d: %.9g (0x%08x) gives %u, film_encode %u\n", (int)enc, (double)values[i],
                        (unsigned)u, bytes[i], film_encode(values[i], enc));
        }
    film_image_free(img);
    free(bytes);
    return differ;
}

// Every SWEEP_STRIDE-th float in [0, 1.0f], then every float of each stride where the byte changes: the whole
// neighbourhood of each of the 255 thresholds, so an off-by-one float anywhere near one is found.
static void test_rgb8_exact(output_transform enc) {
    const uint32_t one = 0x3F800000u;
    size_t n = one / SWEEP_STRIDE + 1;
    float *sweep = malloc(n * sizeof *sweep);
    float *near = malloc(256u * SWEEP_STRIDE * 2u * sizeof *near);
    if (!sweep || !near) {
        CHECK(sweep && near); // out of memory
        free(sweep);
        free(near);
        return;
    }
    for (size_t i = 0; i < n; i++) sweep[i] = bits_float((uint32_t)(i * SWEEP_STRIDE));
    CHECK(mismatches(sweep, n, enc) == 0);
    size_t m = 0, changes = 0;
    for (size_t i = 1; i < n && m + SWEEP_STRIDE <= 256u * SWEEP_STRIDE * 2u; i++) {
        if (film_encode(sweep[i], enc) == film_encode(sweep[i - 1], enc)) continue;
        changes++;
        for (uint32_t u = (uint32_t)((i - 1) * SWEEP_STRIDE); u <= (uint32_t)(i * SWEEP_STRIDE); u++)
            near[m++] = bits_float(u);
    }
    CHECK(changes >= 255); // every byte is reached: each change of byte was looked at float by float
    CHECK(mismatches(near, m, enc) == 0);
    // The odd values: zeros, negatives, NaN, infinities, subnormals, 1 and its neighbours, beyond 1.
    const float odd[] = {0.0f, -0.0f, -1.0f, -INFINITY, NAN, -NAN, INFINITY, 1e-45f, 1e-39f, 1.0f,
                         nextafterf(1.0f, 0.0f), nextafterf(1.0f, 2.0f), 1.5f, 255.0f, 3e38f, 0.0031308f, 0.5f};
    CHECK(mismatches(odd, sizeof odd / sizeof odd[0], enc) == 0);
    free(sweep);
    free(near);
}

typedef struct heard {
    int calls, last_spp, spp_went_down, wrong_size, spp_not_a_pass, width, height;
    double last_fraction;
    uint8_t *last_bytes; ///< the image of the latest call, encoded
    glint_cancel *stop_at_first; ///< requested from the first call (NULL: none)
} heard;

static void on_image(const glint_image *img, int spp_done, double fraction, void *user) {
    heard *h = user;
    int w, hh;
    const float *rgb;
    glint_image_info(img, &w, &hh, &rgb);
    if (w != h->width || hh != h->height) h->wrong_size++;
    else glint_image_rgb8(img, h->last_bytes);
    if (spp_done < h->last_spp) h->spp_went_down++;
    if (spp_done != 0 && (spp_done & (spp_done - 1)) != 0 && spp_done != 48) h->spp_not_a_pass++;
    h->last_spp = spp_done;
    h->last_fraction = fraction;
    h->calls++;
    if (h->stop_at_first) glint_cancel_request(h->stop_at_first);
}

static glint_scene *tiny(long width, long height, long spp) {
    glint_scene *scene = NULL;
    glint_error err;
    if (glint_scene_load(GLINT_SOURCE_DIR "/tests/data/tiny.json", &scene, &err) != GLINT_OK) {
        fprintf(stderr, "%s\n", err.message);
        return NULL;
    }
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = width;
    o.height = height;
    o.spp = spp;
    glint_scene_override(scene, &o, &err);
    return scene;
}

// A whole render: the callback hears it end at every sample (48 spp: passes 1, 2, 4, ..., 32, 48), with the
// bytes the returned image has.
static void test_live_render(void) {
    glint_scene *scene = tiny(64, 48, 48);
    CHECK(scene != NULL);
    if (!scene) return;
    heard h = {.width = 64, .height = 48, .last_bytes = calloc(64 * 48 * 3, 1)};
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = 2;
    opt.live_image = on_image;
    opt.live_user = &h;
    glint_image *img = NULL;
    glint_render_stats stats;
    glint_status st = glint_render(scene, &opt, NULL, NULL, &img, &stats, NULL);
    CHECK(st == GLINT_OK);
    CHECK(h.calls >= 1);
    CHECK(h.last_spp == 48);
    CHECK(h.last_fraction == 1.0);
    CHECK(h.wrong_size == 0);
    CHECK(h.spp_went_down == 0);
    CHECK(h.spp_not_a_pass == 0);
    size_t differ = 0;
    for (int y = 0; img && y < 48; y++)
        for (int x = 0; x < 64; x++)
            for (int c = 0; c < 3; c++) differ += h.last_bytes[(y * 64 + x) * 3 + c] != glint_image_byte(img, x, y, c);
    CHECK(img && differ == 0);
    glint_image_free(img);
    glint_scene_free(scene);
    free(h.last_bytes);
}

// A render stopped from the callback (as a preview window's Esc does): the callback is heard once more at the
// end, and the render returns its partial image.
static void test_live_stop(void) {
    glint_scene *scene = tiny(64, 48, 1000000);
    CHECK(scene != NULL);
    if (!scene) return;
    glint_cancel *cancel = glint_cancel_new();
    heard h = {.width = 64, .height = 48, .last_bytes = calloc(64 * 48 * 3, 1), .stop_at_first = cancel};
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.cancel = cancel;
    opt.live_image = on_image;
    opt.live_user = &h;
    glint_image *img = NULL;
    glint_status st = glint_render(scene, &opt, NULL, NULL, &img, NULL, NULL);
    CHECK(st == GLINT_ERR_INTERRUPTED);
    CHECK(img != NULL);
    CHECK(h.calls >= 2); // the call that asked to stop, and the last one
    CHECK(h.last_fraction < 1.0);
    CHECK(h.spp_went_down == 0);
    glint_image_free(img);
    glint_scene_free(scene);
    free(h.last_bytes);
    glint_cancel_free(cancel);
}

int main(void) {
    test_rgb8_exact(TRANSFORM_LINEAR);
    test_rgb8_exact(TRANSFORM_GAMMA2);
    test_rgb8_exact(TRANSFORM_SRGB);
    test_live_render();
    test_live_stop();
    return check_summary();
}
