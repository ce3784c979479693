// hdr_read.c — Radiance .hdr files through stb_image. stb trusts what it reads: a run of length zero makes it
// loop for ever and a short file decodes as black, without an error. So the header is parsed and the whole pixel
// stream walked here first, by stb's own rules (flat pixels, or new-style run-length scanlines), every size
// checked against the bytes present; stb decodes only a stream known to be complete, and allocates only then.
#include "io/hdr_read.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image.h>

enum { LINE_BYTES = 1024 }; // as stb's header buffer: a longer line is cut there, and the rest skipped

bool hdr_read_is_radiance(const unsigned char *head, size_t size) {
    return (size >= 10 && memcmp(head, "#?RADIANCE", 10) == 0) || (size >= 6 && memcmp(head, "#?RGBE", 6) == 0);
}

typedef struct hdr_scan {
    FILE *f;
    const char *path;
    glint_error *err;
    uint64_t size, at; ///< the file's size; bytes read so far
} hdr_scan;

static int next_byte(hdr_scan *s) {
    int c = getc_unlocked(s->f);
    if (c != EOF) s->at++;
    return c;
}

// One header line without its newline (cut at LINE_BYTES - 1 bytes); false at the end of the file.
static bool read_line(hdr_scan *s, char line[LINE_BYTES]) {
    size_t n = 0;
    int c = next_byte(s);
    if (c == EOF) return false;
    for (; c != EOF && c != '\n'; c = next_byte(s))
        if (n < LINE_BYTES - 1) line[n++] = (char)c;
    line[n] = '\0';
    return true;
}

static glint_status refuse(hdr_scan *s, const char *what) {
    snprintf(s->err->message, sizeof s->err->message, "%s: %s, expected a Radiance .hdr image", s->path, what);
    return GLINT_ERR_INPUT;
}

// A decimal count of the size line at *p (advanced past it), clamped to INT32_MAX + 1; -1 when there is none.
static long long parse_count(const char **p) {
    if (**p < '0' || **p > '9') return -1;
    long long v = 0;
    for (; **p >= '0' && **p <= '9'; (*p)++) v = v > INT32_MAX ? v : v * 10 + (**p - '0');
    return v;
}

// The header: the signature line, variables up to an empty line (FORMAT must be RGBE), then "-Y H +X W".
static glint_status read_header(hdr_scan *s, int *width, int *height) {
    char line[LINE_BYTES];
    if (!read_line(s, line) || (strcmp(line, "#?RADIANCE") != 0 && strcmp(line, "#?RGBE") != 0))
        return refuse(s, "the signature line is not \"#?RADIANCE\" or \"#?RGBE\" alone");
    bool rgbe = false;
    for (;;) {
        if (!read_line(s, line)) return refuse(s, "the header ends before its empty line and size line");
        if (!line[0]) break;
        if (strcmp(line, "FORMAT=32-bit_rle_rgbe") == 0) rgbe = true;
        else if (strncmp(line, "FORMAT=", 7) == 0) return refuse(s, "a format other than 32-bit_rle_rgbe (XYZE?)");
    }
    if (!rgbe) return refuse(s, "no FORMAT=32-bit_rle_rgbe line in the header");
    if (!read_line(s, line)) return refuse(s, "no size line after the header");
    const char *p = line;
    long long h = -1, w = -1;
    if (strncmp(p, "-Y ", 3) == 0) {
        p += 3;
        h = parse_count(&p);
        while (*p == ' ') p++;
        if (strncmp(p, "+X ", 3) == 0) {
            p += 3;
            w = parse_count(&p);
        }
    }
    while (*p == ' ' || *p == '\r') p++;
    if (h < 0 || w < 0 || *p) {
        char what[200];
        snprintf(what, sizeof what, "the size line \"%.64s\" is not \"-Y HEIGHT +X WIDTH\" (the usual top-down "
                 "orientation, the only one read)", line);
        return refuse(s, what);
    }
    if (h == 0 || w == 0 || (unsigned long long)w * (unsigned long long)h > MAP_READ_MAX_PIXELS) {
        snprintf(s->err->message, sizeof s->err->message, "%s: the size line \"%.64s\" declares %s; 1 to %zu pixels "
                 "are allowed", s->path, line, h == 0 || w == 0 ? "no pixels" : "more pixels than that",
                 (size_t)MAP_READ_MAX_PIXELS);
        return GLINT_ERR_INPUT;
    }
    *width = (int)w;
    *height = (int)h;
    return GLINT_OK;
}

// Flat pixels from the byte at `from` on: 4 a pixel, all there.
static glint_status check_flat(hdr_scan *s, uint64_t from, int width, int height) {
    uint64_t need = (uint64_t)width * (uint64_t)height * 4u, have = s->size > from ? s->size - from : 0;
    if (have >= need) return GLINT_OK;
    snprintf(s->err->message, sizeof s->err->message, "%s: truncated .hdr image: %llu bytes of pixels, expected "
             "%llu (%dx%d flat RGBE pixels)", s->path, (unsigned long long)have, (unsigned long long)need, width,
             height);
    return GLINT_ERR_INPUT;
}

static glint_status truncated_at(hdr_scan *s, int row, int height) {
    snprintf(s->err->message, sizeof s->err->message, "%s: truncated .hdr image: the file ends in scanline %d of %d",
             s->path, row + 1, height);
    return GLINT_ERR_INPUT;
}

static glint_status corrupt_at(hdr_scan *s, int row, const char *what) {
    snprintf(s->err->message, sizeof s->err->message, "%s: corrupt .hdr image: scanline %d: %s", s->path, row + 1,
             what);
    return GLINT_ERR_INPUT;
}

// One run-length scanline's four channels (after its 4-byte start): runs and dumps that fill exactly `width`.
static glint_status check_rle_line(hdr_scan *s, int row, int width, int height) {
    unsigned char dump[128];
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < width;) {
            int count = next_byte(s);
            if (count == EOF) return truncated_at(s, row, height);
            bool run = count > 128;
            if (run) count -= 128;
            if (count == 0) return corrupt_at(s, row, "a run of length zero");
            if (count > width - i) return corrupt_at(s, row, "a run past the end of the scanline");
            if (run ? next_byte(s) == EOF : fread(dump, 1, (size_t)count, s->f) != (size_t)count)
                return truncated_at(s, row, height);
            if (!run) s->at += (uint64_t)count;
            i += count;
        }
    return GLINT_OK;
}

// The pixel stream as stb reads it: flat when the width is outside [8, 32768) or the first scanline does not
// start with the run-length mark (2, 2, width); otherwise every scanline is run-length encoded.
static glint_status check_pixels(hdr_scan *s, int width, int height) {
    if (width < 8 || width >= 32768) return check_flat(s, s->at, width, height);
    for (int row = 0; row < height; row++) {
        uint64_t line_start = s->at;
        int b[4];
        for (int i = 0; i < 4; i++)
            if ((b[i] = next_byte(s)) == EOF) return row == 0 ? check_flat(s, line_start, width, height)
                                                               : truncated_at(s, row, height);
        if (b[0] != 2 || b[1] != 2 || (b[2] & 0x80)) {
            if (row == 0) return check_flat(s, line_start, width, height);
            return corrupt_at(s, row, "not run-length encoded, unlike the scanlines before it");
        }
        if ((b[2] << 8 | b[3]) != width) return corrupt_at(s, row, "its length is not the image's width");
        glint_status st = check_rle_line(s, row, width, height);
        if (st != GLINT_OK) return st;
    }
    return GLINT_OK;
}

glint_status hdr_read_open(FILE *f, const char *path, image_rgb *out, glint_error *err) {
    *out = (image_rgb){0};
    struct stat st;
    if (fstat(fileno(f), &st) != 0) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    hdr_scan s = {f, path, err, (uint64_t)st.st_size, 0};
    int w = 0, h = 0;
    glint_status status = read_header(&s, &w, &h);
    if (status == GLINT_OK) status = check_pixels(&s, w, h);
    if (status == GLINT_OK && ferror(f)) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno ? errno : EIO));
        status = GLINT_ERR_INPUT;
    }
    if (status != GLINT_OK) return status;
    rewind(f);
    int channels = 0;
    float *pixels = stbi_loadf_from_file(f, &w, &h, &channels, 3);
    if (!pixels) {
        const char *why = stbi_failure_reason();
        bool oom = why && strstr(why, "outofmem") != NULL;
        snprintf(err->message, sizeof err->message, "%s: %s: %s", path, oom ? "out of memory" : "corrupt .hdr image",
                 why ? why : "unknown error");
        return oom ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    // Radiance values are linear already; a non-finite or negative one would poison every sample that sees it.
    size_t n = (size_t)w * (size_t)h * 3u;
    for (size_t i = 0; i < n; i++)
        if (!(pixels[i] >= 0.0f) || pixels[i] > 3.4e38f) pixels[i] = 0.0f;
    // stb allocates with malloc, so the pixels are freed as every image_rgb is.
    out->width = w;
    out->height = h;
    out->pixels = pixels;
    return GLINT_OK;
}
