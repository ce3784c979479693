// image_write.c — PNG, PPM and PFM output, written to a temporary file and renamed into place.
#include "io/image_write.h"
#include "film/film.h"

#include <png.h>

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static const char SUPPORTED_FORMATS[] = "expected .png, .ppm or .pfm (or - for PPM on standard output)";

// ---- choosing the format ----

// The format `requested`, or the one the path's extension names; GLINT_ERR_INPUT with a message otherwise.
static glint_status resolve_format(const char *path, glint_format requested, glint_format *out, glint_error *err) {
    if (requested != GLINT_FORMAT_AUTO) { *out = requested; return GLINT_OK; }
    if (strcmp(path, "-") == 0) { *out = GLINT_FORMAT_PPM; return GLINT_OK; }
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base) {
        snprintf(err->message, sizeof err->message, "%s: no file extension to choose the image format from, %s", path,
                 SUPPORTED_FORMATS);
        return GLINT_ERR_INPUT;
    }
    if (strcasecmp(dot, ".png") == 0) *out = GLINT_FORMAT_PNG;
    else if (strcasecmp(dot, ".ppm") == 0) *out = GLINT_FORMAT_PPM;
    else if (strcasecmp(dot, ".pfm") == 0) *out = GLINT_FORMAT_PFM;
    else {
        snprintf(err->message, sizeof err->message, "%s: unknown image format '%s', %s", path, dot, SUPPORTED_FORMATS);
        return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

// ---- encoders: each writes the whole image to f and returns 0, or an errno value (or -1: see why) ----

static int fail_errno(void) { return errno ? errno : EIO; }

// One row of display-encoded 8-bit RGB.
static void encode_row(const glint_image *img, int y, uint8_t *row) {
    const float *src = &img->rgb[(size_t)y * (size_t)img->width * 3u];
    for (size_t i = 0; i < (size_t)img->width * 3u; i++) row[i] = film_encode(src[i], img->transform);
}

static int write_ppm_binary(FILE *f, const glint_image *img) {
    uint8_t *row = malloc((size_t)img->width * 3u);
    if (!row) return ENOMEM;
    errno = 0;
    int rc = fprintf(f, "P6\n%d %d\n255\n", img->width, img->height) < 0 ? fail_errno() : 0;
    for (int y = 0; y < img->height && rc == 0; y++) {
        encode_row(img, y, row);
        if (fwrite(row, 3, (size_t)img->width, f) != (size_t)img->width) rc = fail_errno();
    }
    free(row);
    return rc;
}

// ASCII P3 as the seeds print it: a header, then one "r g b" line per pixel.
static int write_ppm_ascii(FILE *f, const glint_image *img) {
    uint8_t *row = malloc((size_t)img->width * 3u);
    if (!row) return ENOMEM;
    errno = 0;
    int rc = fprintf(f, "P3\n%d %d\n255\n", img->width, img->height) < 0 ? fail_errno() : 0;
    for (int y = 0; y < img->height && rc == 0; y++) {
        encode_row(img, y, row);
        for (int x = 0; x < img->width && rc == 0; x++)
            if (fprintf(f, "%d %d %d\n", row[3 * x], row[3 * x + 1], row[3 * x + 2]) < 0) rc = fail_errno();
    }
    free(row);
    return rc;
}

// Portable float map: linear RGB floats, little-endian (scale -1.0), rows from the bottom up.
static int write_pfm(FILE *f, const glint_image *img) {
    size_t n = (size_t)img->width * 3u;
    uint8_t *row = malloc(n * 4u);
    if (!row) return ENOMEM;
    errno = 0;
    int rc = fprintf(f, "PF\n%d %d\n-1.0\n", img->width, img->height) < 0 ? fail_errno() : 0;
    for (int y = img->height - 1; y >= 0 && rc == 0; y--) {
        const float *src = &img->rgb[(size_t)y * n];
        for (size_t i = 0; i < n; i++) {
            uint32_t bits;
            memcpy(&bits, &src[i], sizeof bits);
            // Byte by byte, so the file is little-endian whatever the machine.
            for (unsigned b = 0; b < 4; b++) row[4 * i + b] = (uint8_t)(bits >> (8 * b));
        }
        if (fwrite(row, 4, n, f) != n) rc = fail_errno();
    }
    free(row);
    return rc;
}

// libpng reports errors by longjmp; everything the error path needs lives here, outside the function
// that calls setjmp, so nothing it reads can be clobbered.
typedef struct png_writer {
    FILE *f;
    png_structp png;
    png_infop info;
    uint8_t *row;
    int write_errno;      ///< errno of a failed fwrite, 0 if libpng failed for another reason
    char message[256];    ///< libpng's message
} png_writer;

static void png_on_error(png_structp png, png_const_charp msg) {
    png_writer *w = png_get_error_ptr(png);
    snprintf(w->message, sizeof w->message, "%s", msg);
    png_longjmp(png, 1);
}

static void png_on_warning(png_structp png, png_const_charp msg) { (void)png; (void)msg; }

static void png_on_write(png_structp png, png_bytep data, size_t length) {
    png_writer *w = png_get_io_ptr(png);
    errno = 0;
    if (fwrite(data, 1, length, w->f) != length) {
        w->write_errno = fail_errno();
        png_error(png, "write failed");
    }
}

static void png_on_flush(png_structp png) { (void)png; } // the caller flushes once at the end

static bool png_encode(png_writer *w, const glint_image *img) {
    if (setjmp(png_jmpbuf(w->png))) return false;
    png_set_write_fn(w->png, w, png_on_write, png_on_flush);
    png_set_IHDR(w->png, w->info, (png_uint_32)img->width, (png_uint_32)img->height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(w->png, w->info);
    for (int y = 0; y < img->height; y++) {
        encode_row(img, y, w->row);
        png_write_row(w->png, w->row);
    }
    png_write_end(w->png, NULL);
    return true;
}

// 8-bit RGB PNG without colour-space chunks: viewers show the bytes as sRGB, exactly as they show the PPM.
static int write_png(FILE *f, const glint_image *img, char *why, size_t why_size) {
    png_writer w = {.f = f};
    w.row = malloc((size_t)img->width * 3u);
    w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &w, png_on_error, png_on_warning);
    w.info = w.png ? png_create_info_struct(w.png) : NULL;
    int rc = 0;
    if (!w.row || !w.info) rc = ENOMEM;
    else if (!png_encode(&w, img)) {
        rc = w.write_errno;
        if (rc == 0) { snprintf(why, why_size, "PNG encoder: %s", w.message); rc = -1; }
    }
    if (w.png) png_destroy_write_struct(&w.png, w.info ? &w.info : NULL);
    free(w.row);
    return rc;
}

static int write_format(FILE *f, const glint_image *img, glint_format format, char *why, size_t why_size) {
    switch (format) {
    case GLINT_FORMAT_PNG: return write_png(f, img, why, why_size);
    case GLINT_FORMAT_PPM_ASCII: return write_ppm_ascii(f, img);
    case GLINT_FORMAT_PFM: return write_pfm(f, img);
    case GLINT_FORMAT_PPM:
    case GLINT_FORMAT_AUTO: break;
    }
    return write_ppm_binary(f, img);
}

// ---- files ----

static glint_status cannot_write(const char *path, int rc, const char *why, glint_error *err) {
    snprintf(err->message, sizeof err->message, "%s: cannot write: %s", path, rc == -1 ? why : strerror(rc));
    return GLINT_ERR_RENDER;
}

// "dir/.name.tmp-XXXXXX" next to path, so that rename() stays within one file system; NULL when out of memory.
// The name part is cut so that the whole fits in NAME_MAX bytes, as the output's own name does.
static char *temp_name_for(const char *path) {
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path) + 1 : 0;
    const char *base = path + dir_len;
    size_t base_len = strlen(base), most = NAME_MAX - (sizeof ".tmp-XXXXXX" - 1) - 1;
    if (base_len > most) base_len = most;
    size_t n = dir_len + 1 + base_len + sizeof ".tmp-XXXXXX";
    char *tmp = malloc(n);
    if (tmp) snprintf(tmp, n, "%.*s.%.*s.tmp-XXXXXX", (int)dir_len, path, (int)base_len, base);
    return tmp;
}

// The mode a newly created file gets (0666 less the umask); mkstemp's 0600 would hide the image from others.
static mode_t new_file_mode(void) {
    mode_t mask = umask(0);
    umask(mask);
    return 0666 & ~mask;
}

static glint_status write_stdout(const glint_image *img, glint_format format, glint_error *err) {
    char why[300] = "";
    int rc = write_format(stdout, img, format, why, sizeof why);
    errno = 0;
    if (rc == 0 && fflush(stdout) != 0) rc = fail_errno();
    return rc == 0 ? GLINT_OK : cannot_write("standard output", rc, why, err);
}

glint_status image_write(const glint_image *img, const char *path, glint_format format, glint_error *err) {
    glint_status st = resolve_format(path, format, &format, err);
    if (st != GLINT_OK) return st;
    if (strcmp(path, "-") == 0) return write_stdout(img, format, err);

    char *tmp = temp_name_for(path);
    if (!tmp) return cannot_write(path, ENOMEM, "", err);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        int e = errno;
        free(tmp);
        return cannot_write(path, e, "", err);
    }
    char why[300] = "";
    int rc = 0;
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        rc = fail_errno();
        close(fd);
    } else {
        rc = write_format(f, img, format, why, sizeof why);
        errno = 0;
        if (rc == 0 && fflush(f) != 0) rc = fail_errno();
        if (rc == 0 && fchmod(fd, new_file_mode()) != 0) rc = fail_errno();
        // On disk before it takes the image's name: a crash leaves the old file or the new one, never half.
        if (rc == 0 && fsync(fd) != 0 && errno != EINVAL) rc = fail_errno();
        if (fclose(f) != 0 && rc == 0) rc = fail_errno();
    }
    if (rc == 0 && rename(tmp, path) != 0) rc = fail_errno();
    if (rc != 0) unlink(tmp); // a failed write leaves nothing behind
    free(tmp);
    return rc == 0 ? GLINT_OK : cannot_write(path, rc, why, err);
}

glint_status image_check_path(const char *path, glint_format format, glint_error *err) {
    glint_status st = resolve_format(path, format, &format, err);
    if (st != GLINT_OK || strcmp(path, "-") == 0) return st;
    struct stat sb;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode)) return cannot_write(path, EISDIR, "", err);
    // Create and remove a temporary file exactly where the image will go: the one test that sees every reason.
    char *tmp = temp_name_for(path);
    if (!tmp) return cannot_write(path, ENOMEM, "", err);
    int fd = mkstemp(tmp);
    int e = errno;
    if (fd >= 0) {
        close(fd);
        unlink(tmp);
    }
    free(tmp);
    return fd >= 0 ? GLINT_OK : cannot_write(path, e, "", err);
}
