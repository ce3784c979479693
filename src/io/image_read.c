// image_read.c — PNG (libpng's simplified API) and JPEG (libjpeg, any scan mode) to linear RGB floats (and PNG's
// alpha, where it has one).
#include "io/image_read.h"

#include <stdbool.h>
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <jpeglib.h>
#include <jerror.h>
#include <png.h>

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void set_error(glint_error *err, const char *fmt, ...) {
    if (!err) return;
    va_list ap;
    va_start(ap, fmt);
    status_vformat(err->message, sizeof err->message, "", fmt, ap);
    va_end(ap);
}

float image_srgb_to_linear(unsigned char c) {
    double x = c / 255.0;
    return (float)(x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4));
}

// The float of each byte value under `decode`.
static void decode_table(image_decode decode, float table[256]) {
    for (int i = 0; i < 256; i++)
        table[i] = decode == IMAGE_DECODE_LINEAR ? (float)(i / 255.0) : image_srgb_to_linear((unsigned char)i);
}

// Whether a w x h image is within IMAGE_READ_MAX_PIXELS; sets the message when it is not.
static bool size_ok(const char *name, size_t w, size_t h, glint_error *err) {
    if (w > 0 && h > 0 && w <= IMAGE_READ_MAX_PIXELS && h <= IMAGE_READ_MAX_PIXELS / w) return true;
    set_error(err, "%s: image size %zux%zu is not supported, expected at most %zu pixels", name, w, h,
              (size_t)IMAGE_READ_MAX_PIXELS);
    return false;
}

// Checks the size and allocates the float pixels into *out: GLINT_ERR_INPUT (with a message) when too
// large, GLINT_ERR_RENDER when out of memory.
static glint_status alloc_pixels(const char *name, size_t w, size_t h, float **out, glint_error *err) {
    *out = NULL;
    if (!size_ok(name, w, h, err)) return GLINT_ERR_INPUT;
    *out = malloc(w * h * 3 * sizeof **out);
    if (*out) return GLINT_OK;
    set_error(err, "%s: out of memory for a %zux%zu image", name, w, h);
    return GLINT_ERR_RENDER;
}

// "name: out of memory" with GLINT_ERR_RENDER: running out of memory is a resource failure, not bad input.
static glint_status out_of_memory(const char *name, glint_error *err) {
    set_error(err, "%s: out of memory", name);
    return GLINT_ERR_RENDER;
}

// libpng's simplified API reports its allocation failures only in words: "Out of memory", "...: out of memory".
static bool png_out_of_memory(const png_image *img) { return strstr(img->message, "ut of memory") != NULL; }

static glint_status decode_png(const char *name, const unsigned char *data, size_t size, image_decode decode,
                              image_rgb *out, glint_error *err) {
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, data, size)) {
        glint_status st = png_out_of_memory(&img) ? out_of_memory(name, err) : GLINT_ERR_INPUT;
        if (st == GLINT_ERR_INPUT) set_error(err, "%s: cannot decode PNG: %s", name, img.message);
        png_image_free(&img);
        return st;
    }
    // 8-bit sRGB RGBA whatever the file holds (palette, grey, 16 bit); the alpha channel (RGBA, grey + alpha, a
    // tRNS chunk) is kept only when the file has one (alpha masks; image_rgb.alpha).
    bool has_alpha = (img.format & PNG_FORMAT_FLAG_ALPHA) != 0;
    img.format = PNG_FORMAT_RGBA;
    float *pixels;
    glint_status st = alloc_pixels(name, img.width, img.height, &pixels, err);
    if (st != GLINT_OK) { png_image_free(&img); return st; }
    size_t n = (size_t)img.width * img.height;
    unsigned char *buf = malloc(n * 4);
    if (!buf) {
        free(pixels);
        png_image_free(&img);
        return out_of_memory(name, err);
    }
    if (!png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        st = png_out_of_memory(&img) ? out_of_memory(name, err) : GLINT_ERR_INPUT;
        if (st == GLINT_ERR_INPUT) set_error(err, "%s: cannot decode PNG: %s", name, img.message);
        free(buf);
        free(pixels);
        png_image_free(&img);
        return st;
    }
    float table[256];
    decode_table(decode, table);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) pixels[i * 3 + c] = table[buf[i * 4 + c]];
    // Alpha is coverage, never sRGB-encoded: byte / 255. An alpha channel that is 255 everywhere costs nothing.
    float *alpha = NULL;
    bool translucent = false;
    for (size_t i = 0; has_alpha && i < n && !translucent; i++) translucent = buf[i * 4 + 3] != 255;
    if (translucent) {
        if (!(alpha = malloc(n * sizeof *alpha))) {
            free(buf);
            free(pixels);
            png_image_free(&img);
            return out_of_memory(name, err);
        }
        for (size_t i = 0; i < n; i++) alpha[i] = (float)(buf[i * 4 + 3] / 255.0);
    }
    free(buf);
    out->width = (int)img.width;
    out->height = (int)img.height;
    out->pixels = pixels;
    out->alpha = alpha;
    png_image_free(&img);
    return GLINT_OK;
}

// libjpeg reports fatal errors through error_exit, which must not return: jump back to the decoder.
typedef struct jpeg_state {
    struct jpeg_decompress_struct cinfo;
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
    unsigned char *row;
    float *pixels;
} jpeg_state;

static void jpeg_fail(j_common_ptr cinfo) {
    jpeg_state *st = (jpeg_state *)cinfo->client_data;
    (*cinfo->err->format_message)(cinfo, st->message);
    longjmp(st->jump, 1);
}

// Corrupt-data warnings would go to stderr; a texture decodes as well as it can, silently.
static void jpeg_quiet(j_common_ptr cinfo) { (void)cinfo; }

static glint_status decode_jpeg(const char *name, const unsigned char *data, size_t size, image_decode decode,
                               image_rgb *out, glint_error *err) {
    jpeg_state *st = calloc(1, sizeof *st);
    if (!st) return out_of_memory(name, err);
    st->cinfo.err = jpeg_std_error(&st->mgr);
    st->mgr.error_exit = jpeg_fail;
    st->mgr.output_message = jpeg_quiet;
    if (setjmp(st->jump)) {
        glint_status failed = st->mgr.msg_code == JERR_OUT_OF_MEMORY ? out_of_memory(name, err) : GLINT_ERR_INPUT;
        if (failed == GLINT_ERR_INPUT) set_error(err, "%s: cannot decode JPEG: %s", name, st->message);
        jpeg_destroy_decompress(&st->cinfo);
        free(st->row);
        free(st->pixels);
        free(st);
        return failed;
    }
    jpeg_create_decompress(&st->cinfo);
    st->cinfo.client_data = st;
    jpeg_mem_src(&st->cinfo, data, (unsigned long)size);
    jpeg_read_header(&st->cinfo, TRUE);
    st->cinfo.out_color_space = JCS_RGB; // grey and YCbCr alike come out as RGB
    size_t w = st->cinfo.image_width, h = st->cinfo.image_height;
    // Check the size before jpeg_start_decompress, which allocates whole-image buffers for progressive files.
    glint_status status = GLINT_ERR_INPUT;
    if (size_ok(name, w, h, err)) {
        jpeg_start_decompress(&st->cinfo);
        w = st->cinfo.output_width;
        h = st->cinfo.output_height;
        if (st->cinfo.output_components != 3)
            set_error(err, "%s: cannot decode JPEG: %d colour components, expected 3", name, st->cinfo.output_components);
        else if ((status = alloc_pixels(name, w, h, &st->pixels, err)) == GLINT_OK && !(st->row = malloc(w * 3)))
            status = out_of_memory(name, err);
    }
    if (status != GLINT_OK) {
        jpeg_destroy_decompress(&st->cinfo);
        free(st->row);
        free(st->pixels);
        free(st);
        return status;
    }
    float table[256];
    decode_table(decode, table);
    // Progressive files need nothing special here: libjpeg buffers all scans and hands out final rows.
    while (st->cinfo.output_scanline < h) {
        size_t y = st->cinfo.output_scanline;
        JSAMPROW rows[1] = {st->row};
        if (jpeg_read_scanlines(&st->cinfo, rows, 1) != 1) break;
        float *dst = st->pixels + y * w * 3;
        for (size_t i = 0; i < w * 3; i++) dst[i] = table[st->row[i]];
    }
    jpeg_finish_decompress(&st->cinfo);
    jpeg_destroy_decompress(&st->cinfo);
    out->width = (int)w;
    out->height = (int)h;
    out->pixels = st->pixels;
    free(st->row);
    free(st);
    return GLINT_OK;
}

glint_status image_read_memory(const char *name, const unsigned char *data, size_t size, image_decode decode,
                               image_rgb *out, glint_error *err) {
    *out = (image_rgb){0};
    static const unsigned char png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (size >= 8 && memcmp(data, png_magic, 8) == 0) return decode_png(name, data, size, decode, out, err);
    if (size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff)
        return decode_jpeg(name, data, size, decode, out, err);
    set_error(err, "%s: not a PNG or JPEG image, expected a file starting with a PNG or JPEG signature", name);
    return GLINT_ERR_INPUT;
}

glint_status image_read(const char *path, image_decode decode, image_rgb *out, glint_error *err) {
    *out = (image_rgb){0};
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOMEM) return out_of_memory(path, err);
        set_error(err, "%s: cannot open: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    // Directories, devices and pipes are not images (and /dev/zero would never end).
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        set_error(err, "%s: cannot open: not a regular file", path);
        fclose(f);
        return GLINT_ERR_INPUT;
    }
    // Read up to one byte past the limit, so that a file that grew since fstat is noticed too.
    size_t cap = 1 << 16, len = 0, most = IMAGE_READ_MAX_FILE_BYTES + 1;
    bool too_large = (unsigned long long)st.st_size > IMAGE_READ_MAX_FILE_BYTES;
    unsigned char *buf = too_large ? NULL : malloc(cap);
    while (buf) {
        len += fread(buf + len, 1, cap - len, f);
        if (len < cap || cap == most) break;
        size_t grown_cap = cap > most / 2 ? most : cap * 2;
        unsigned char *bigger = realloc(buf, grown_cap);
        if (!bigger) { free(buf); buf = NULL; break; }
        buf = bigger;
        cap = grown_cap;
    }
    bool failed = buf && ferror(f);
    fclose(f);
    if (too_large || len > IMAGE_READ_MAX_FILE_BYTES) {
        set_error(err, "%s: the image file is larger than %zu bytes (%zu MiB)", path, (size_t)IMAGE_READ_MAX_FILE_BYTES,
                  (size_t)IMAGE_READ_MAX_FILE_BYTES >> 20);
        free(buf);
        return GLINT_ERR_INPUT;
    }
    if (!buf) {
        set_error(err, "%s: out of memory while reading", path);
        return GLINT_ERR_RENDER;
    }
    if (failed) {
        set_error(err, "%s: read error", path);
        free(buf);
        return GLINT_ERR_INPUT;
    }
    glint_status status = image_read_memory(path, buf, len, decode, out, err);
    free(buf);
    return status;
}
