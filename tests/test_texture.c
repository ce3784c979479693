// test_texture.c — solid, checker, Perlin noise and image textures; PNG and JPEG (baseline and progressive)
// files written here with libpng/libjpeg and read back; sRGB decoding; bilinear filtering and wrapping.
#include "check.h"
#include "test_util.h"
#include "core/rng.h"
#include "io/image_read.h"
#include "material/texture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jpeglib.h>
#include <png.h>

// The 8-bit sRGB code nearest to a linear value, to compare lossy JPEG results in the file's own units.
static int to_srgb8(float linear) {
    double c = linear <= 0.0031308 ? linear * 12.92 : 1.055 * pow(linear, 1 / 2.4) - 0.055;
    return (int)lround(fmin(1.0, fmax(0.0, c)) * 255.0);
}

static void test_srgb(void) {
    CHECK(image_srgb_to_linear(0) == 0.0f);
    CHECK(image_srgb_to_linear(255) == 1.0f);
    CHECK_NEAR(image_srgb_to_linear(128), 0.2158605, 1e-6);
    CHECK_NEAR(image_srgb_to_linear(10), 10.0 / 255.0 / 12.92, 1e-9); // the linear toe
    for (int i = 1; i < 256; i++) CHECK(image_srgb_to_linear((unsigned char)i) > image_srgb_to_linear((unsigned char)(i - 1)));
    for (int i = 0; i < 256; i++) CHECK(to_srgb8(image_srgb_to_linear((unsigned char)i)) == i);
}

static void test_solid_and_checker(void) {
    texture s = texture_solid(v3(0.1f, 0.2f, 0.3f));
    vec3 c = texture_value(&s, 0.5f, 0.5f, v3(1, 2, 3));
    CHECK(c.x == 0.1f && c.y == 0.2f && c.z == 0.3f);
    texture t = texture_checker(1.0f, v3(1, 1, 1), v3(0, 0, 0));
    CHECK(texture_value(&t, 0, 0, v3(0.5f, 0.5f, 0.5f)).x == 1.0f);   // 0+0+0 even
    CHECK(texture_value(&t, 0, 0, v3(1.5f, 0.5f, 0.5f)).x == 0.0f);   // 1 odd
    CHECK(texture_value(&t, 0, 0, v3(-0.5f, 0.5f, 0.5f)).x == 0.0f);  // -1 odd
    CHECK(texture_value(&t, 0, 0, v3(-0.5f, -0.5f, 0.5f)).x == 1.0f); // -2 even
    CHECK(texture_value(&t, 0, 0, v3(1.5f, 1.5f, 1.5f)).x == 0.0f);   // 3 odd
    texture t2 = texture_checker(2.0f, v3(1, 1, 1), v3(0, 0, 0));
    CHECK(texture_value(&t2, 0, 0, v3(1.5f, 0, 0)).x == 1.0f);
    CHECK(texture_value(&t2, 0, 0, v3(2.5f, 0, 0)).x == 0.0f);
    // Huge or non-finite points give one of the two colours, never a crash.
    float h = texture_value(&t, 0, 0, v3(1e30f, -3e38f, 7)).x;
    CHECK(h == 0.0f || h == 1.0f);
    h = texture_value(&t, 0, 0, v3(NAN, INFINITY, 0)).x;
    CHECK(h == 0.0f || h == 1.0f);
}

static void test_noise(void) {
    texture a, b, other;
    CHECK(texture_noise(NOISE_PLAIN, 4.0f, 7, v3(1, 1, 1), 42, &a));
    CHECK(texture_noise(NOISE_PLAIN, 4.0f, 7, v3(1, 1, 1), 42, &b));
    CHECK(texture_noise(NOISE_PLAIN, 4.0f, 7, v3(1, 1, 1), 43, &other));
    rng r = rng_for_sample(1, 1, 1);
    int same = 1, differ = 0;
    double sum = 0, maxabs = 0;
    const int n = 20000;
    for (int i = 0; i < n; i++) {
        vec3 p = v3(rng_range(&r, -50, 50), rng_range(&r, -50, 50), rng_range(&r, -50, 50));
        vec3 va = texture_value(&a, 0, 0, p), vb = texture_value(&b, 0, 0, p), vo = texture_value(&other, 0, 0, p);
        same &= va.x == vb.x;
        differ += va.x != vo.x;
        sum += va.x;
        float raw = perlin_noise(a.perlin, p);
        maxabs = fmax(maxabs, fabs(raw));
        // Continuity: a tiny step changes the value a tiny amount.
        CHECK(fabsf(perlin_noise(a.perlin, v3_add(p, v3s(1e-4f))) - raw) < 1e-2f);
    }
    CHECK(same);                  // deterministic: the same seed, the same tables
    CHECK(differ > n / 2);        // another seed, another pattern
    CHECK(maxabs <= 1.0);         // gradient noise with unit gradients stays within [-1, 1]
    CHECK(maxabs > 0.4);
    CHECK_NEAR(sum / n, 0.5, 0.02); // 0.5 (1 + noise) averages to about 0.5
    // Zero at every lattice point: all eight corner weights vanish or meet a zero offset.
    CHECK(perlin_noise(a.perlin, v3(3, -7, 12)) == 0.0f);
    CHECK(perlin_noise(a.perlin, v3(0, 0, 0)) == 0.0f);
    CHECK(perlin_noise(a.perlin, v3(NAN, 0, 0)) == 0.0f);
    CHECK(isfinite(perlin_noise(a.perlin, v3(3e38f, -3e38f, 1e20f))));
    // Turbulence is the absolute value of the octave sum.
    vec3 p = v3(0.3f, 1.7f, -2.2f);
    CHECK_NEAR(perlin_turbulence(a.perlin, p, 1), fabs(perlin_noise(a.perlin, p)), 0);
    CHECK_NEAR(perlin_turbulence(a.perlin, p, 2),
               fabs(perlin_noise(a.perlin, p) + 0.5 * perlin_noise(a.perlin, v3_scale(p, 2))), 1e-6);
    // The marble: 0.5 (1 + sin(scale z + 10 turb(p, depth))) times the colour.
    texture m;
    CHECK(texture_noise(NOISE_MARBLE, 4.0f, 7, v3(1, 0.5f, 0.25f), 42, &m));
    vec3 mv = texture_value(&m, 0, 0, p);
    double expect = 0.5 * (1 + sin(4.0 * p.z + 10.0 * perlin_turbulence(m.perlin, p, 7)));
    CHECK_NEAR(mv.x, expect, 1e-5);
    CHECK_NEAR(mv.y, 0.5 * expect, 1e-5);
    CHECK(isfinite(texture_value(&m, 0, 0, v3(NAN, 1, 1)).x));
    texture tu;
    CHECK(texture_noise(NOISE_TURBULENCE, 2.0f, 5, v3(1, 1, 1), 42, &tu));
    CHECK_NEAR(texture_value(&tu, 0, 0, p).x, perlin_turbulence(tu.perlin, v3_scale(p, 2.0f), 5), 0);
    texture_free(&a);
    texture_free(&b);
    texture_free(&other);
    texture_free(&m);
    texture_free(&tu);
    CHECK(a.kind == TEX_SOLID && a.perlin == NULL);
}

// A w x h image whose texel (x, y) is (x, y, 10 + x + y) / 16: every texel differs.
static image_rgb ramp(int w, int h) {
    image_rgb img = {w, h, malloc((size_t)w * (size_t)h * 3 * sizeof(float)), NULL};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float *p = img.pixels + ((size_t)y * (size_t)w + (size_t)x) * 3;
            p[0] = (float)x / 16;
            p[1] = (float)y / 16;
            p[2] = (float)(10 + x + y) / 16;
        }
    return img;
}

static void test_bilinear(void) {
    texture t = texture_image(ramp(4, 2), FILTER_BILINEAR);
    // Texel centres give exactly the texel; v = 1 is the top row (row 0).
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++) {
            vec3 c = texture_value(&t, ((float)x + 0.5f) / 4, 1.0f - ((float)y + 0.5f) / 2, v3s(0));
            CHECK(c.x == (float)x / 16 && c.y == (float)y / 16 && c.z == (float)(10 + x + y) / 16);
        }
    // Halfway between two centres: their mean.
    vec3 c = texture_value(&t, 0.25f, 0.75f, v3s(0)); // between x = 0 and 1, row 0
    CHECK_NEAR(c.x, 0.5 / 16, 1e-7);
    CHECK_NEAR(c.y, 0.0, 1e-7);
    // Repeat wrapping: u = 0 lies between the last and the first column; u + 1 and u - 1 are u.
    c = texture_value(&t, 0.0f, 0.75f, v3s(0));
    CHECK_NEAR(c.x, (3.0 / 16 + 0.0) / 2, 1e-7);
    vec3 c1 = texture_value(&t, 0.3f, 0.6f, v3s(0)), c2 = texture_value(&t, 1.3f, -0.4f, v3s(0)),
         c3 = texture_value(&t, -0.7f, 2.6f, v3s(0));
    CHECK_NEAR(c1.x, c2.x, 1e-6);
    CHECK_NEAR(c1.y, c2.y, 1e-6);
    CHECK_NEAR(c1.x, c3.x, 1e-6);
    CHECK_NEAR(c1.z, c3.z, 1e-6);
    // Non-finite coordinates are treated as 0.
    c = texture_value(&t, NAN, INFINITY, v3s(0));
    CHECK(isfinite(c.x) && isfinite(c.y) && isfinite(c.z));
    texture_free(&t);
    // A texture without pixels shows the book's cyan.
    texture empty = texture_image((image_rgb){0, 0, NULL, NULL}, FILTER_BILINEAR);
    c = texture_value(&empty, 0.5f, 0.5f, v3s(0));
    CHECK(c.x == 0.0f && c.y == 1.0f && c.z == 1.0f);
    // Odd sizes: centres are exact to rounding.
    texture o = texture_image(ramp(3, 5), FILTER_BILINEAR);
    c = texture_value(&o, 2.5f / 3, 1.0f - 3.5f / 5, v3s(0));
    CHECK_NEAR(c.x, 2.0 / 16, 1e-6);
    CHECK_NEAR(c.y, 3.0 / 16, 1e-6);
    texture_free(&o);
}

static bool write_png(const char *path, const void *pixels, int w, int h, png_uint_32 format) {
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = (png_uint_32)w;
    img.height = (png_uint_32)h;
    img.format = format;
    return png_image_write_to_file(&img, path, 0, pixels, 0, NULL) != 0;
}

static void test_png(void) {
    const unsigned char rgb[2 * 3 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128, 10, 20, 30, 0, 0, 0};
    const char *path = tmp_path("rgb.png");
    CHECK(write_png(path, rgb, 3, 2, PNG_FORMAT_RGB));
    image_rgb img;
    glint_error err;
    CHECK(image_read(path, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK(img.width == 3 && img.height == 2);
    for (int i = 0; i < 18; i++) CHECK(img.pixels[i] == image_srgb_to_linear(rgb[i]));
    image_rgb_free(&img);
    CHECK(img.pixels == NULL && img.width == 0);
    // Grey with alpha: the grey goes to all three channels, alpha is dropped.
    const unsigned char ga[4] = {200, 255, 50, 0};
    path = tmp_path("ga.png");
    CHECK(write_png(path, ga, 2, 1, PNG_FORMAT_GA));
    CHECK(image_read(path, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK(img.width == 2 && img.height == 1);
    CHECK(img.pixels[0] == image_srgb_to_linear(200) && img.pixels[2] == image_srgb_to_linear(200));
    CHECK(img.pixels[3] == image_srgb_to_linear(50));
    image_rgb_free(&img);
    // A 16-bit linear PNG (gAMA 1.0): libpng converts it to sRGB bytes, which decode back to about 0.5.
    const png_uint_16 lin[3] = {32768, 16384, 65535};
    path = tmp_path("linear16.png");
    CHECK(write_png(path, lin, 1, 1, PNG_FORMAT_LINEAR_RGB));
    CHECK(image_read(path, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    CHECK_NEAR(img.pixels[0], 0.5, 0.01);
    CHECK_NEAR(img.pixels[1], 0.25, 0.01);
    CHECK_NEAR(img.pixels[2], 1.0, 0.0);
    image_rgb_free(&img);
    // Decoded by io/, sampled by the texture, which takes the pixels.
    CHECK(image_read(tmp_path("rgb.png"), IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
    texture t = texture_image(img, FILTER_BILINEAR);
    // Width 3: texel centres are exact only to rounding (and a fused multiply-add rounds differently).
    vec3 c = texture_value(&t, 0.5f / 3, 0.75f, v3s(0)); // top-left texel: red
    CHECK_NEAR(c.x, 1.0, 1e-6);
    CHECK_NEAR(c.y, 0.0, 1e-6);
    CHECK_NEAR(c.z, 0.0, 1e-6);
    c = texture_value(&t, 0.5f / 3, 0.25f, v3s(0)); // bottom-left: grey 128
    CHECK_NEAR(c.x, image_srgb_to_linear(128), 1e-6);
    texture_free(&t);
}

static bool write_jpeg(const char *path, const unsigned char *rgb, int w, int h, bool progressive) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 100, TRUE);
    for (int i = 0; i < 3; i++) c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1; // no chroma subsampling
    if (progressive) jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = (JSAMPROW)(uintptr_t)(rgb + (size_t)c.next_scanline * (size_t)w * 3);
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return fclose(f) == 0;
}

// Whether a JPEG file's frame header (the first SOFn segment, found by walking the marker segments) is
// progressive (SOF2); false for anything that is not a JPEG.
static bool is_progressive(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    static unsigned char d[1 << 18];
    size_t n = fread(d, 1, sizeof d, f);
    fclose(f);
    if (n < 4 || d[0] != 0xff || d[1] != 0xd8) return false;
    for (size_t i = 2; i + 4 <= n && d[i] == 0xff;) {
        unsigned char m = d[i + 1];
        if (m >= 0xc0 && m <= 0xcf && m != 0xc4 && m != 0xc8 && m != 0xcc) return m == 0xc2;
        i += 2 + ((size_t)d[i + 2] << 8 | d[i + 3]);
    }
    return false;
}

static void test_jpeg(void) {
    // Four flat 8x8 blocks: red, green, blue, grey. Flat blocks survive quality-100 JPEG almost exactly.
    enum { W = 16, H = 16 };
    static const unsigned char colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 128, 128}};
    unsigned char rgb[W * H * 3];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) memcpy(rgb + (y * W + x) * 3, colours[(y / 8) * 2 + x / 8], 3);
    for (int progressive = 0; progressive <= 1; progressive++) {
        const char *path = tmp_path(progressive ? "progressive.jpg" : "baseline.jpg");
        CHECK(write_jpeg(path, rgb, W, H, progressive));
        CHECK(is_progressive(path) == (bool)progressive);
        image_rgb img;
        glint_error err;
        CHECK(image_read(path, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK);
        CHECK(img.width == W && img.height == H);
        int worst = 0;
        for (int i = 0; i < W * H * 3; i++) worst = abs(to_srgb8(img.pixels[i]) - rgb[i]) > worst ? abs(to_srgb8(img.pixels[i]) - rgb[i]) : worst;
        CHECK(worst <= 3);
        image_rgb_free(&img);
    }
}

static void test_real_files(void) {
    static const struct { const char *file; int w, h; bool progressive; } files[] = {
        {"spot/spot_texture.png", 1024, 1024, false},
        {"assimp-spider/SpiderTex.jpg", 249, 250, false},
        {"assimp-spider/drkwood2.jpg", 768, 768, false},
        {"assimp-spider/engineflare1.jpg", 128, 128, true},
        {"assimp-spider/wal67ar_small.jpg", 250, 250, false},
        {"assimp-spider/wal69ar_small.jpg", 250, 250, false},
    };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/tests/data/obj/%s", GLINT_SOURCE_DIR, files[i].file);
        CHECK(is_progressive(path) == files[i].progressive);
        image_rgb img;
        glint_error err;
        glint_status st = image_read(path, IMAGE_DECODE_SRGB, &img, &err);
        CHECK(st == GLINT_OK);
        if (st != GLINT_OK) {
            fprintf(stderr, "%s\n", err.message);
            continue;
        }
        CHECK(img.width == files[i].w && img.height == files[i].h);
        bool in_range = true;
        double sum = 0;
        size_t n = (size_t)img.width * (size_t)img.height * 3;
        for (size_t k = 0; k < n; k++) {
            in_range &= img.pixels[k] >= 0.0f && img.pixels[k] <= 1.0f;
            sum += img.pixels[k];
        }
        CHECK(in_range);
        CHECK(sum > 0.01 * (double)n); // not all black
        image_rgb_free(&img);
    }
}

static void write_bytes(const char *path, const void *data, size_t n) { (void)tmp_write(path, data, n); }

// Makes the baseline frame header (SOF0) of a JPEG declare side x side pixels; false when it has none.
static bool patch_jpeg_size(unsigned char *jpg, size_t n, unsigned side) {
    for (size_t i = 2; i + 9 < n && jpg[i] == 0xff; i += 2 + ((size_t)jpg[i + 2] << 8 | jpg[i + 3]))
        if (jpg[i + 1] == 0xc0) {
            jpg[i + 5] = jpg[i + 7] = (unsigned char)(side >> 8); // height, then width, big-endian
            jpg[i + 6] = jpg[i + 8] = (unsigned char)(side & 0xffu);
            return true;
        }
    return false;
}

// The CRC-32 of PNG chunks (ISO 3309, the polynomial 0xEDB88320 bit by bit): patched headers need a new one.
static uint32_t crc32_png(const unsigned char *p, size_t n) {
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = c & 1u ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

static void check_error(const char *path, const char *expected_suffix) {
    image_rgb img = {7, 7, NULL, NULL};
    glint_error err;
    glint_status st = image_read(path, IMAGE_DECODE_SRGB, &img, &err);
    CHECK(st == GLINT_ERR_INPUT);
    CHECK(img.pixels == NULL && img.width == 0);
    char expect[512];
    snprintf(expect, sizeof expect, "%s: %s", path, expected_suffix);
    bool ok = strncmp(err.message, expect, strlen(expect)) == 0;
    CHECK(ok);
    if (!ok) fprintf(stderr, "got      '%s'\nexpected '%s...'\n", err.message, expect);
}

static void test_errors(void) {
    check_error(tmp_path("missing.png"), "cannot open: No such file or directory");
    check_error(tmpdir, "cannot open: not a regular file");
    write_bytes(tmp_path("text.png"), "hello, world", 12);
    check_error(tmp_path("text.png"), "not a PNG or JPEG image, expected a file starting with a PNG or JPEG signature");
    write_bytes(tmp_path("empty.jpg"), "", 0);
    check_error(tmp_path("empty.jpg"), "not a PNG or JPEG image, expected a file starting with a PNG or JPEG signature");
    // A PNG cut after its header, and a JPEG whose header is garbage.
    FILE *f = fopen(tmp_path("rgb.png"), "rb");
    unsigned char buf[64];
    size_t n = f ? fread(buf, 1, 40, f) : 0;
    if (f) fclose(f);
    write_bytes(tmp_path("cut.png"), buf, n);
    check_error(tmp_path("cut.png"), "cannot decode PNG: ");
    const unsigned char bad_jpeg[] = {0xff, 0xd8, 0xff, 0xe0, 0x00, 0x02, 0xff, 0xc0, 0x00, 0x03, 0x01, 0x01, 0x01};
    write_bytes(tmp_path("bad.jpg"), bad_jpeg, sizeof bad_jpeg);
    check_error(tmp_path("bad.jpg"), "cannot decode JPEG: ");
    // A JPEG whose frame header claims 65000 x 65000 pixels is refused before libjpeg allocates anything.
    f = fopen(tmp_path("baseline.jpg"), "rb");
    static unsigned char jpg[1 << 16];
    n = f ? fread(jpg, 1, sizeof jpg, f) : 0;
    if (f) fclose(f);
    CHECK(patch_jpeg_size(jpg, n, 65000));
    write_bytes(tmp_path("huge.jpg"), jpg, n);
    check_error(tmp_path("huge.jpg"), "image size 65000x65000 is not supported, expected at most 16777216 pixels");
    // The same header declaring 8192 x 8192 (2^26 pixels, 1 GiB to decode): over IMAGE_READ_MAX_PIXELS.
    CHECK(patch_jpeg_size(jpg, n, 8192));
    write_bytes(tmp_path("bomb.jpg"), jpg, n);
    check_error(tmp_path("bomb.jpg"), "image size 8192x8192 is not supported, expected at most 16777216 pixels");
    // A PNG bomb: a small image whose header (with its checksum redone) declares 8192 x 8192.
    static const unsigned char grey[4] = {0, 64, 128, 255};
    CHECK(write_png(tmp_path("small.png"), grey, 2, 2, PNG_FORMAT_GRAY));
    static unsigned char png[4096];
    f = fopen(tmp_path("small.png"), "rb");
    n = f ? fread(png, 1, sizeof png, f) : 0;
    if (f) fclose(f);
    CHECK(n > 33 && memcmp(png + 12, "IHDR", 4) == 0);
    const unsigned char side[4] = {0, 0, 0x20, 0};
    memcpy(png + 16, side, 4);
    memcpy(png + 20, side, 4);
    uint32_t crc = crc32_png(png + 12, 17); // over the chunk type and its 13 bytes of data
    for (int k = 0; k < 4; k++) png[29 + k] = (unsigned char)(crc >> (24 - 8 * k));
    write_bytes(tmp_path("bomb.png"), png, n);
    check_error(tmp_path("bomb.png"), "image size 8192x8192 is not supported, expected at most 16777216 pixels");
    // A file over IMAGE_READ_MAX_FILE_BYTES (sparse, no disk space used) is refused before it is read.
    f = fopen(tmp_path("huge.png"), "wb");
    CHECK(f && fwrite(png, 1, 8, f) == 8 && ftruncate(fileno(f), (off_t)IMAGE_READ_MAX_FILE_BYTES + 1) == 0);
    if (f) fclose(f);
    check_error(tmp_path("huge.png"), "the image file is larger than 268435456 bytes (256 MiB)");
    remove(tmp_path("huge.png"));
    glint_error err;
    image_rgb img;
    CHECK(image_read(tmp_path("missing.png"), IMAGE_DECODE_SRGB, &img, &err) == GLINT_ERR_INPUT);
    // From memory: the name appears in messages.
    CHECK(image_read_memory("mem.png", (const unsigned char *)"xx", 2, IMAGE_DECODE_SRGB, &img, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "mem.png: not a PNG or JPEG image, expected a file starting with a PNG or JPEG signature") == 0);
}

// Book 2's program: nearest texel, raw bytes / 255, given Perlin tables, turbulence of the scaled point.
static void test_book2_variants(void) {
    texture t = texture_image(ramp(4, 2), FILTER_NEAREST);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++) { // anywhere inside a texel gives exactly that texel
            vec3 c = texture_value(&t, ((float)x + 0.9f) / 4, 1.0f - ((float)y + 0.1f) / 2, v3s(0));
            CHECK(c.x == (float)x / 16 && c.y == (float)y / 16);
        }
    vec3 edge = texture_value(&t, nextafterf(1.0f, 0.0f), 0.0f, v3s(0)); // stays in the last column, bottom row
    CHECK(edge.x == 3.0f / 16 && edge.y == 1.0f / 16);
    texture_free(&t);
    // Linear decoding: the byte over 255, no sRGB curve.
    const unsigned char rgb[3] = {128, 10, 255};
    const char *path = tmp_path("raw.png");
    CHECK(write_png(path, rgb, 1, 1, PNG_FORMAT_RGB));
    image_rgb img;
    glint_error err;
    CHECK(image_read(path, IMAGE_DECODE_LINEAR, &img, &err) == GLINT_OK);
    CHECK(img.pixels[0] == (float)(128 / 255.0) && img.pixels[1] == (float)(10 / 255.0) && img.pixels[2] == 1.0f);
    image_rgb_free(&img);
    // Given tables are used as they are: one gradient everywhere makes noise a known function.
    perlin tables;
    for (int i = 0; i < 256; i++) {
        tables.gradient[i] = v3(1, 0, 0);
        tables.perm_x[i] = tables.perm_y[i] = tables.perm_z[i] = (uint8_t)(255 - i);
    }
    texture n;
    CHECK(texture_noise_tables(NOISE_MARBLE_SCALED, 0.5f, 3, v3(1, 1, 1), &tables, &n));
    CHECK(n.perlin->perm_x[0] == 255 && n.perlin->gradient[7].x == 1.0f);
    vec3 p = v3(0.3f, 1.7f, -2.2f), s = v3_scale(p, 0.5f);
    // With every gradient (1, 0, 0) the noise is the smoothed-weight sum of (u - di) over the corners.
    float u = s.x - floorf(s.x), uu = u * u * (3 - 2 * u);
    CHECK_NEAR(perlin_noise(n.perlin, s), (1 - uu) * u + uu * (u - 1), 1e-6);
    double expect = 0.5 * (1 + sin(s.z + 10.0 * perlin_turbulence(n.perlin, s, 3)));
    CHECK_NEAR(texture_value(&n, 0, 0, p).x, expect, 1e-5);
    texture_free(&n);
}

int main(void) {
    if (!tmpdir_make("glint-test-texture")) return 1;
    test_srgb();
    test_solid_and_checker();
    test_noise();
    test_bilinear();
    test_png();
    test_jpeg();
    test_real_files();
    test_errors();
    test_book2_variants();
    tmpdir_remove();
    return check_summary();
}
