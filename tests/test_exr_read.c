// test_exr_read.c — OpenEXR input for environment maps: files glint writes (float and half) read back
// exactly; a tiled, luminance-only file with an offset data window (written here through OpenEXR's core API)
// reads as grey; an environment map given as .exr lights a scene as the same map in .hdr does; bad files fail
// with messages.
#include "check.h"
#include "test_util.h"

#include "glint.h"
#include "film/film.h"
#include "io/map_read.h"
#include "scene/scene.h"

#include <math.h>
#include <openexr.h>
#include <stb_image_write.h>

// A small image with values across many magnitudes, zero included.
static glint_image *test_image(void) {
    glint_image *img = film_image_new(7, 5, TRANSFORM_LINEAR);
    for (int i = 0; img && i < 7 * 5 * 3; i++) img->rgb[i] = (i % 11 == 0) ? 0.0f : ldexpf(1.0f + 0.37f * (float)i, i % 9 - 4);
    return img;
}

static void test_round_trip(glint_format format, double tolerance) {
    glint_image *img = test_image();
    glint_error err;
    const char *path = tmp_path("rgb.exr");
    CHECK(glint_image_write(img, path, format, &err) == GLINT_OK);
    image_rgb back;
    CHECK(map_read(path, MAP_EXR, &back, &err) == GLINT_OK);
    CHECK(back.width == 7 && back.height == 5);
    int bad = 0;
    for (int i = 0; back.pixels && i < 7 * 5 * 3; i++)
        bad += tolerance == 0.0 ? back.pixels[i] != img->rgb[i]
                                : fabs((double)back.pixels[i] - img->rgb[i]) > tolerance * img->rgb[i];
    CHECK(bad == 0);
    image_rgb_free(&back);
    glint_image_free(img);
}

// Writes a w x h luminance-only (Y), half-float file in 4x4 tiles whose data window starts at (x0, y0);
// pixel (x, y) of the window holds value(x, y).
static bool write_tiled_y(const char *path, int x0, int y0, int w, int h, const float *values) {
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int part = 0;
    exr_attr_box2i_t window;
    window.min.x = x0;
    window.min.y = y0;
    window.max.x = x0 + w - 1;
    window.max.y = y0 + h - 1;
    exr_attr_v2f_t center;
    center.x = center.y = 0.0f;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, "y", EXR_STORAGE_TILED, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr(ctx, part, &window, &window, 1.0f, &center, 1.0f, EXR_LINEORDER_INCREASING_Y,
                                          EXR_COMPRESSION_PIZ);
    if (rv == EXR_ERR_SUCCESS) rv = exr_set_tile_descriptor(ctx, part, 4, 4, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_channel(ctx, part, "Y", EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
    for (int ty = 0; rv == EXR_ERR_SUCCESS && ty * 4 < h; ty++)
        for (int tx = 0; rv == EXR_ERR_SUCCESS && tx * 4 < w; tx++) {
            exr_chunk_info_t ci;
            exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
            rv = exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &ci);
            if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_initialize(ctx, part, &ci, &enc);
            if (rv != EXR_ERR_SUCCESS) break;
            exr_coding_channel_info_t *ch = &enc.channels[0];
            ch->encode_from_ptr = (const uint8_t *)(values + (size_t)(ty * 4) * (size_t)w + (size_t)(tx * 4));
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)(sizeof(float) * (size_t)w);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            rv = exr_encoding_choose_default_routines(ctx, part, &enc);
            if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, &enc);
            exr_encoding_destroy(ctx, &enc);
        }
    exr_result_t rf = exr_finish(&ctx);
    return rv == EXR_ERR_SUCCESS && rf == EXR_ERR_SUCCESS;
}

static void test_tiled_grey(void) {
    enum { W = 10, H = 7 }; // edge tiles are partial
    float values[W * H];
    for (int i = 0; i < W * H; i++) values[i] = (float)(i % 13) * 0.25f; // exact in half
    const char *path = tmp_path("y.exr");
    CHECK(write_tiled_y(path, -3, 2, W, H, values));
    image_rgb back;
    glint_error err;
    glint_status st = map_read(path, MAP_EXR, &back, &err);
    if (st != GLINT_OK) fprintf(stderr, "%s\n", err.message);
    CHECK(st == GLINT_OK);
    CHECK(back.width == W && back.height == H);
    int bad = 0;
    for (int i = 0; back.pixels && i < W * H; i++)
        for (int c = 0; c < 3; c++) bad += back.pixels[i * 3 + c] != values[i];
    CHECK(bad == 0);
    image_rgb_free(&back);
}

static void test_errors(void) {
    image_rgb img;
    glint_error err;
    CHECK(map_read(tmp_path("missing.exr"), MAP_EXR, &img, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "cannot open") != NULL && img.pixels == NULL);
    CHECK(tmp_write(tmp_path("fake.exr"), "P3\n1 1\n255\n0 0 0\n", 17));
    CHECK(map_read(tmp_path("fake.exr"), MAP_EXR, &img, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "not an OpenEXR image") != NULL);
    // A valid file cut short: the header or the chunks are missing.
    glint_image *src = test_image();
    CHECK(glint_image_write(src, tmp_path("whole.exr"), GLINT_FORMAT_EXR, &err) == GLINT_OK);
    glint_image_free(src);
    FILE *f = fopen(tmp_path("whole.exr"), "rb");
    unsigned char buf[4096];
    size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f) fclose(f);
    CHECK(n > 400);
    size_t cuts[] = {4, 40, 300, n - 20};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        CHECK(tmp_write(tmp_path("cut.exr"), (const char *)buf, cuts[i]));
        glint_status st = map_read(tmp_path("cut.exr"), MAP_EXR, &img, &err);
        CHECK(st == GLINT_ERR_INPUT && img.pixels == NULL);
        CHECK(strncmp(err.message, tmp_path("cut.exr"), strlen(tmp_path("cut.exr"))) == 0);
    }
}

// The same map as .exr and .hdr: the scene reads either (told apart by content), and the renders agree as
// closely as RGBE's precision allows.
static void test_envmap_scene(void) {
    float px[8 * 4 * 3];
    for (int i = 0; i < 8 * 4 * 3; i++) px[i] = 0.25f + (float)(i % 5) * 0.5f; // exact in RGBE
    glint_image *img = film_image_new(8, 4, TRANSFORM_LINEAR);
    memcpy(img->rgb, px, sizeof px);
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("sky.exr"), GLINT_FORMAT_EXR_HALF, &err) == GLINT_OK);
    glint_image_free(img);
    CHECK(stbi_write_hdr(tmp_path("sky.hdr"), 8, 4, 3, px) != 0);
    glint_image *out[2] = {NULL, NULL};
    const char *files[2] = {"sky.exr", "sky.hdr"};
    for (int k = 0; k < 2; k++) {
        char text[512];
        snprintf(text, sizeof text,
                 "{\"render\": {\"width\": 8, \"height\": 6, \"spp\": 4, \"integrator\": \"path\", \"background\": "
                 "{\"type\": \"envmap\", \"file\": \"%s\", \"rotate\": 30}}, \"objects\": [{\"type\": \"sphere\", "
                 "\"center\": [0, 0, -3], \"radius\": 1, \"material\": {\"type\": \"lambertian\", \"albedo\": 0.5}}]}",
                 files[k]);
        glint_scene *s = NULL;
        CHECK(glint_scene_parse(tmp_path("scene.json"), text, strlen(text), &s, &err) == GLINT_OK);
        glint_render_options opt = {.threads = 1};
        if (s) CHECK(glint_render(s, &opt, NULL, NULL, &out[k], NULL, &err) == GLINT_OK);
        glint_scene_free(s);
    }
    int bad = 0;
    for (int i = 0; out[0] && out[1] && i < 8 * 6 * 3; i++) bad += out[0]->rgb[i] != out[1]->rgb[i];
    CHECK(out[0] && out[1] && bad == 0);
    glint_image_free(out[0]);
    glint_image_free(out[1]);
}

int main(void) {
    if (!tmpdir_make("glint-exr-read")) return 1;
    test_round_trip(GLINT_FORMAT_EXR, 0.0);
    test_round_trip(GLINT_FORMAT_EXR_HALF, 1.0 / 1024.0);
    test_tiled_grey();
    test_errors();
    test_envmap_scene();
    tmpdir_remove();
    return check_summary();
}
