// test_exr.c — HDR output: an EXR written by glint reads back through the OpenEXR library itself with the
// channels R, G, B, the image's size and exactly its linear values (to half precision for half files); a
// Radiance .hdr reads back through stb_image within RGBE's precision; bad paths fail with messages.
#include "check.h"
#include "test_util.h"

#include "glint.h"
#include "film/film.h"
#include "io/map_read.h"

#include <math.h>
#include <openexr.h>

// A small image with values across many magnitudes, zero included.
static glint_image *test_image(void) {
    glint_image *img = film_image_new(7, 5, TRANSFORM_SRGB);
    for (int i = 0; img && i < 7 * 5 * 3; i++) img->rgb[i] = (i % 11 == 0) ? 0.0f : ldexpf(1.0f + 0.37f * (float)i, i % 9 - 4);
    return img;
}

// Reads an EXR back through the core library: channel names in file order (sorted), size, and RGB floats.
static bool read_exr(const char *path, int *w, int *h, char names[4], exr_pixel_type_t *type, float *rgb) {
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS) return false;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    int32_t lines = 0;
    bool ok = exr_get_data_window(ctx, 0, &dw) == EXR_ERR_SUCCESS && exr_get_channels(ctx, 0, &chl) == EXR_ERR_SUCCESS &&
              exr_get_scanlines_per_chunk(ctx, 0, &lines) == EXR_ERR_SUCCESS && chl->num_channels == 3;
    if (ok) {
        *w = dw.max.x - dw.min.x + 1;
        *h = dw.max.y - dw.min.y + 1;
        for (int c = 0; c < 3; c++) names[c] = chl->entries[c].name.str[0];
        names[3] = '\0';
        *type = chl->entries[0].pixel_type;
    }
    for (int y = 0; ok && y < *h; y += lines) {
        exr_chunk_info_t ci;
        exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
        ok = exr_read_scanline_chunk_info(ctx, 0, dw.min.y + y, &ci) == EXR_ERR_SUCCESS &&
             exr_decoding_initialize(ctx, 0, &ci, &dec) == EXR_ERR_SUCCESS;
        for (int16_t c = 0; ok && c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            int k = ch->channel_name[0] == 'R' ? 0 : ch->channel_name[0] == 'G' ? 1 : 2;
            ch->decode_to_ptr = (uint8_t *)(rgb + (size_t)(ci.start_y - dw.min.y) * (size_t)*w * 3u + (size_t)k);
            ch->user_pixel_stride = (int32_t)(3 * sizeof(float));
            ch->user_line_stride = (int32_t)(3 * sizeof(float) * (size_t)*w);
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

static void test_exr(glint_format format, exr_pixel_type_t want_type, double tolerance) {
    glint_image *img = test_image();
    glint_error err;
    const char *path = tmp_path("out.exr");
    CHECK(glint_image_write(img, path, format, &err) == GLINT_OK);
    int w = 0, h = 0;
    char names[4] = "";
    exr_pixel_type_t type = EXR_PIXEL_UINT;
    float back[7 * 5 * 3];
    memset(back, 0, sizeof back);
    CHECK(read_exr(path, &w, &h, names, &type, back));
    CHECK(w == 7 && h == 5);
    CHECK(strcmp(names, "BGR") == 0); // EXR keeps its channels sorted by name
    CHECK(type == want_type);
    int bad = 0;
    for (int i = 0; i < 7 * 5 * 3; i++) {
        double a = img->rgb[i], b = back[i];
        if (tolerance == 0.0 ? memcmp(&img->rgb[i], &back[i], sizeof back[i]) != 0 : fabs(a - b) > tolerance * fabs(a))
            bad++;
    }
    CHECK(bad == 0);
    glint_image_free(img);
    unlink(path);
}

static void test_hdr(void) {
    glint_image *img = test_image();
    glint_error err;
    const char *path = tmp_path("out.hdr");
    CHECK(glint_image_write(img, path, GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    image_rgb back;
    CHECK(map_read(path, MAP_HDR, &back, &err) == GLINT_OK);
    CHECK(back.width == 7 && back.height == 5);
    int bad = 0;
    for (int p = 0; back.pixels && p < 7 * 5; p++) {
        // RGBE shares one exponent per pixel: each channel is within 1/256 of the pixel's largest one.
        double peak = fmax(img->rgb[p * 3], fmax(img->rgb[p * 3 + 1], img->rgb[p * 3 + 2]));
        for (int c = 0; c < 3; c++) bad += fabs((double)img->rgb[p * 3 + c] - back.pixels[p * 3 + c]) > peak / 128.0;
    }
    CHECK(bad == 0);
    image_rgb_free(&back);
    glint_image_free(img);
    unlink(path);
}

static void test_errors(void) {
    glint_image *img = test_image();
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("missing/out.exr"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_RENDER);
    CHECK(strstr(err.message, "cannot write") != NULL);
    CHECK(glint_image_check_path(tmp_path("out.tiff"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "expected .png, .ppm, .pfm, .exr or .hdr") != NULL);
    glint_image_free(img);
}

int main(void) {
    if (!tmpdir_make("glint-exr")) return 1;
    test_exr(GLINT_FORMAT_AUTO, EXR_PIXEL_FLOAT, 0.0);
    test_exr(GLINT_FORMAT_EXR_HALF, EXR_PIXEL_HALF, 1.0 / 1024.0);
    test_hdr();
    test_errors();
    tmpdir_remove();
    return check_summary();
}
