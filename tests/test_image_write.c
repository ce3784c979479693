// test_image_write.c — every image format written through glint_image_write and read back; the
// temporary-file-and-rename contract: failures leave neither a half image nor a temporary file behind.
#include "glint.h"
#include "check.h"
#include "test_util.h"
#include "film/film.h"

#include <png.h>

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

enum { W = 37, H = 19 }; // odd sizes, so rows and orientation errors show

// Number of entries in the test directory (without . and ..): catches any leftover temporary file.
static int dir_entries(void) {
    DIR *d = opendir(tmpdir);
    if (!d) return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
    closedir(d);
    return n;
}

static uint8_t *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 20;
    uint8_t *buf = malloc(cap);
    *size = buf ? fread(buf, 1, cap, f) : 0;
    fclose(f);
    return buf;
}

// Linear values covering black, mid-grey, the clamp at both ends, NaN and a gradient.
static glint_image *test_image(output_transform encoding) {
    glint_image *img = film_image_new(W, H, encoding);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                float v = (float)(x * 3 + c) / (float)(W * 3) + (float)y * 0.01f;
                if (x == 0) v = -0.5f;
                if (x == 1) v = 2.5f;
                if (x == 2 && y == 0) v = NAN;
                img->rgb[((size_t)y * W + (size_t)x) * 3 + (size_t)c] = v;
            }
    return img;
}

// Parses "MAGIC\nW H\nMAXVAL\n" (PPM) or "PF\nW H\nSCALE\n" (PFM); returns the header length or 0.
static size_t parse_header(const uint8_t *buf, size_t size, const char *magic, int *w, int *h, char *third,
                           size_t third_size) {
    char text[64];
    size_t n = size < sizeof text - 1 ? size : sizeof text - 1;
    memcpy(text, buf, n);
    text[n] = '\0';
    int consumed = 0;
    char m[4];
    if (sscanf(text, "%2s\n%d %d\n%15s%n", m, w, h, third, &consumed) != 4 || strcmp(m, magic) != 0) return 0;
    (void)third_size;
    return (size_t)consumed + 1; // the single whitespace after the last header field
}

static void test_ppm_binary(void) {
    glint_image *img = test_image(TRANSFORM_GAMMA2);
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("a.ppm"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    size_t size;
    uint8_t *buf = read_file(tmp_path("a.ppm"), &size);
    CHECK(buf != NULL);
    int w = 0, h = 0;
    char maxval[16];
    size_t off = buf ? parse_header(buf, size, "P6", &w, &h, maxval, sizeof maxval) : 0;
    CHECK(off == strlen("P6\n37 19\n255\n"));
    CHECK(w == W && h == H && strcmp(maxval, "255") == 0);
    CHECK(size == off + (size_t)W * H * 3);
    int mismatches = 0;
    for (int y = 0; y < H && buf && size == off + (size_t)W * H * 3; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++)
                if (buf[off + ((size_t)y * W + (size_t)x) * 3 + (size_t)c] != glint_image_byte(img, x, y, c))
                    mismatches++;
    CHECK(mismatches == 0);
    // The bytes are the display encoding: clamped, NaN black, sqrt(0.25) = 0.5 -> 128.
    CHECK(glint_image_byte(img, 0, 0, 0) == 0 && glint_image_byte(img, 1, 0, 0) == 255);
    CHECK(glint_image_byte(img, 2, 0, 0) == 0);
    CHECK(film_encode(0.25f, TRANSFORM_GAMMA2) == 128 && film_encode(0.5f, TRANSFORM_LINEAR) == 128);
    free(buf);
    glint_image_free(img);
}

static void test_ppm_ascii(void) {
    glint_image *img = test_image(TRANSFORM_LINEAR);
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("b.ppm"), GLINT_FORMAT_PPM_ASCII, &err) == GLINT_OK);
    FILE *f = fopen(tmp_path("b.ppm"), "r");
    CHECK(f != NULL);
    if (!f) return;
    char magic[4] = "";
    int w = 0, h = 0, maxval = 0;
    CHECK(fscanf(f, "%3s %d %d %d", magic, &w, &h, &maxval) == 4);
    CHECK(strcmp(magic, "P3") == 0 && w == W && h == H && maxval == 255);
    int mismatches = 0, values = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                int v;
                if (fscanf(f, "%d", &v) != 1) { mismatches++; continue; }
                values++;
                if (v != glint_image_byte(img, x, y, c)) mismatches++;
            }
    int extra;
    CHECK(fscanf(f, "%d", &extra) == EOF);
    CHECK(values == W * H * 3 && mismatches == 0);
    fclose(f);
    glint_image_free(img);
}

static void test_pfm(void) {
    glint_image *img = test_image(TRANSFORM_SRGB);
    img->rgb[((size_t)(H - 1) * W) * 3] = 1e30f; // values beyond 1 survive in a float format
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("c.pfm"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    size_t size;
    uint8_t *buf = read_file(tmp_path("c.pfm"), &size);
    int w = 0, h = 0;
    char scale[16] = "";
    size_t off = buf ? parse_header(buf, size, "PF", &w, &h, scale, sizeof scale) : 0;
    CHECK(off == strlen("PF\n37 19\n-1.0\n"));
    CHECK(w == W && h == H && strcmp(scale, "-1.0") == 0); // negative scale: little-endian
    CHECK(size == off + (size_t)W * H * 12);
    int mismatches = 0;
    for (int row = 0; row < H && buf && size == off + (size_t)W * H * 12; row++) {
        int y = H - 1 - row; // PFM rows run from the bottom up
        for (int i = 0; i < W * 3; i++) {
            const uint8_t *p = &buf[off + ((size_t)row * W * 3 + (size_t)i) * 4];
            uint32_t bits = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
            uint32_t want;
            memcpy(&want, &img->rgb[(size_t)y * W * 3 + (size_t)i], sizeof want);
            if (bits != want) mismatches++;
        }
    }
    CHECK(mismatches == 0);
    free(buf);
    glint_image_free(img);
}

static void test_png(void) {
    glint_image *img = test_image(TRANSFORM_SRGB);
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("d.png"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    CHECK(glint_image_write(img, tmp_path("e.PNG"), GLINT_FORMAT_AUTO, &err) == GLINT_OK); // any case
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&pi, tmp_path("d.png")) != 0);
    CHECK(pi.width == W && pi.height == H);
    CHECK((pi.format & PNG_FORMAT_FLAG_COLOR) && !(pi.format & PNG_FORMAT_FLAG_ALPHA));
    pi.format = PNG_FORMAT_RGB;
    uint8_t *pixels = malloc(PNG_IMAGE_SIZE(pi));
    CHECK(pixels && png_image_finish_read(&pi, NULL, pixels, 0, NULL) != 0);
    int mismatches = 0;
    for (int y = 0; y < H && pixels; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++)
                if (pixels[((size_t)y * W + (size_t)x) * 3 + (size_t)c] != glint_image_byte(img, x, y, c))
                    mismatches++;
    CHECK(mismatches == 0);
    free(pixels);
    // Rewriting replaces the file in one step; the signature is PNG's.
    CHECK(glint_image_write(img, tmp_path("d.png"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    size_t size;
    uint8_t *buf = read_file(tmp_path("d.png"), &size);
    CHECK(buf && size > 8 && memcmp(buf, "\x89PNG\r\n\x1a\n", 8) == 0);
    free(buf);
    glint_image_free(img);
}

// The colour chunks a PNG carries: whether it says sRGB, and its gAMA (file gamma) value.
static bool png_colour_chunks(const char *path, bool *srgb, double *gamma) {
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    bool ok = info != NULL;
    if (ok && setjmp(png_jmpbuf(png))) ok = false;
    else if (ok) {
        png_init_io(png, f);
        png_read_info(png, info);
        int intent;
        *srgb = png_get_sRGB(png, info, &intent) != 0;
        *gamma = 0.0;
        if (!png_get_gAMA(png, info, gamma)) *gamma = -1.0;
        ok = png_get_valid(png, info, PNG_INFO_cHRM) != 0; // the primaries are stated too
    }
    png_destroy_read_struct(&png, info ? &info : NULL, NULL);
    fclose(f);
    return ok;
}

// Each encoding writes the chunk that says what the bytes mean: sRGB (with its gAMA of 1/2.2), or the gAMA of
// the power law the bytes follow (1/2 for gamma 2, 1 for linear), each with the sRGB primaries in cHRM.
static void test_png_colour_chunks(void) {
    static const struct {
        output_transform encoding;
        bool srgb;
        double gamma;
    } cases[] = {{TRANSFORM_SRGB, true, 0.45455}, {TRANSFORM_GAMMA2, false, 0.5}, {TRANSFORM_LINEAR, false, 1.0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        glint_image *img = test_image(cases[i].encoding);
        glint_error err;
        CHECK(glint_image_write(img, tmp_path("c.png"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
        bool srgb = false;
        double gamma = 0.0;
        CHECK(png_colour_chunks(tmp_path("c.png"), &srgb, &gamma));
        CHECK(srgb == cases[i].srgb);
        CHECK_NEAR(gamma, cases[i].gamma, 1e-5);
        glint_image_free(img);
    }
    unlink(tmp_path("c.png")); // the tests after this one count the directory's files
}

// Decoding a byte gives a value that encodes back to exactly that byte, under every encoding (what glint merge
// relies on to keep the parts' bytes).
static void test_decode_round_trip(void) {
    const output_transform encodings[] = {TRANSFORM_LINEAR, TRANSFORM_GAMMA2, TRANSFORM_SRGB};
    int bad = 0;
    for (int e = 0; e < 3; e++)
        for (int v = 0; v < 256; v++) bad += film_encode(film_decode((uint8_t)v, encodings[e]), encodings[e]) != v;
    CHECK(bad == 0);
}

static void test_mode(void) {
    glint_image *img = film_image_new(2, 2, TRANSFORM_LINEAR);
    mode_t mask = umask(022);
    glint_error err;
    CHECK(glint_image_write(img, tmp_path("mode.ppm"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    struct stat sb;
    CHECK(stat(tmp_path("mode.ppm"), &sb) == 0 && (sb.st_mode & 0777) == 0644); // not mkstemp's 0600
    umask(mask);
    glint_image_free(img);
}

static void test_errors(void) {
    glint_image *img = test_image(TRANSFORM_LINEAR);
    glint_error err;
    int before = dir_entries();
    char expected[1200];

    CHECK(glint_image_write(img, tmp_path("x.jpg"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_INPUT);
    snprintf(expected, sizeof expected,
             "%s: unknown image format '.jpg', expected .png, .ppm, .pfm, .exr or .hdr (or - for PPM on standard output)",
             tmp_path("x.jpg"));
    CHECK(strcmp(err.message, expected) == 0);
    CHECK(glint_image_check_path(tmp_path("x.jpg"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_INPUT);
    CHECK(glint_image_write(img, tmp_path("noext"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "no file extension") != NULL);
    CHECK(glint_image_write(img, tmp_path(".png"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_INPUT);

    CHECK(glint_image_write(img, tmp_path("missing/x.png"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_RENDER);
    snprintf(expected, sizeof expected, "%s: cannot write: No such file or directory", tmp_path("missing/x.png"));
    CHECK(strcmp(err.message, expected) == 0);
    CHECK(glint_image_check_path(tmp_path("missing/x.png"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_RENDER);
    CHECK(strcmp(err.message, expected) == 0);
    CHECK(glint_image_check_path(tmp_path("ok.png"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    CHECK(glint_image_check_path("-", GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    CHECK(dir_entries() == before); // the checks created nothing

    // A directory where the image should go: the temporary file is written, the rename fails, and the
    // temporary file must be gone again.
    CHECK(mkdir(tmp_path("taken.ppm"), 0755) == 0);
    CHECK(mkdir(tmp_path("taken.ppm/inside"), 0755) == 0);
    before = dir_entries();
    CHECK(glint_image_check_path(tmp_path("taken.ppm"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_RENDER);
    CHECK(strstr(err.message, "cannot write: Is a directory") != NULL);
    CHECK(glint_image_write(img, tmp_path("taken.ppm"), GLINT_FORMAT_AUTO, &err) == GLINT_ERR_RENDER);
    CHECK(strstr(err.message, "taken.ppm: cannot write: ") != NULL);
    CHECK(dir_entries() == before);
    rmdir(tmp_path("taken.ppm/inside"));
    rmdir(tmp_path("taken.ppm"));

    // A write that fails half-way (the file-size limit): no half image, no temporary file, the old image kept.
    CHECK(glint_image_write(img, tmp_path("full.ppm"), GLINT_FORMAT_AUTO, &err) == GLINT_OK);
    before = dir_entries();
    struct rlimit old, small;
    getrlimit(RLIMIT_FSIZE, &old);
    small = old;
    small.rlim_cur = 100; // below every format's size, PNG included
    signal(SIGXFSZ, SIG_IGN); // make the oversized write fail with EFBIG instead of killing the test
    CHECK(setrlimit(RLIMIT_FSIZE, &small) == 0);
    const glint_format formats[] = {GLINT_FORMAT_PPM, GLINT_FORMAT_PPM_ASCII, GLINT_FORMAT_PFM, GLINT_FORMAT_PNG};
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        CHECK(glint_image_write(img, tmp_path("full.ppm"), formats[i], &err) == GLINT_ERR_RENDER);
        CHECK(strstr(err.message, "full.ppm: cannot write: File too large") != NULL);
    }
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, SIG_DFL);
    CHECK(dir_entries() == before);
    size_t size;
    uint8_t *buf = read_file(tmp_path("full.ppm"), &size);
    CHECK(buf && size == strlen("P6\n37 19\n255\n") + (size_t)W * H * 3);
    free(buf);
    glint_image_free(img);
}

int main(void) {
    if (!tmpdir_make("glint-image-test")) return 1;
    test_ppm_binary();
    test_ppm_ascii();
    test_pfm();
    test_png();
    test_png_colour_chunks();
    test_decode_round_trip();
    test_mode();
    test_errors();
    CHECK(dir_entries() == 7); // a.ppm b.ppm c.pfm d.png e.PNG mode.ppm full.ppm, and nothing else
    tmpdir_remove();
    return check_summary();
}
