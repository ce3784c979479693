// image_write.c — PNG, PPM, PFM, EXR and HDR output (and AOV planes as PFM), written to an unnamed temporary
// file and linked into place.
// O_TMPFILE is Linux's: <fcntl.h> declares it only for _GNU_SOURCE (without it, the named fallback is used).
#define _GNU_SOURCE
#include "io/image_write.h"
#include "core/filepath.h"
#include "core/hash.h"
#include "core/trace.h"
#include "film/film.h"
#include "io/exr_write.h"
#include "io/image_png.h"
#include "io/pfm_region.h"

#include <png.h>
#include <stb_image_write.h>

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static const char SUPPORTED_FORMATS[] =
    "expected .png, .ppm, .pfm, .exr or .hdr (or - for PPM on standard output)";

// ---- choosing the format ----

// The format `requested`, or the one the path's extension names; GLINT_ERR_INPUT with a message otherwise.
static glint_status resolve_format(const char *path, image_format requested, image_format *out, glint_error *err) {
    if (requested != IMAGE_FORMAT_AUTO) { *out = requested; return GLINT_OK; }
    if (strcmp(path, "-") == 0) { *out = IMAGE_FORMAT_PPM; return GLINT_OK; }
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base) {
        snprintf(err->message, sizeof err->message, "%s: no file extension to choose the image format from, %s", path,
                 SUPPORTED_FORMATS);
        return GLINT_ERR_INPUT;
    }
    if (strcasecmp(dot, ".png") == 0) *out = IMAGE_FORMAT_PNG;
    else if (strcasecmp(dot, ".ppm") == 0) *out = IMAGE_FORMAT_PPM;
    else if (strcasecmp(dot, ".pfm") == 0) *out = IMAGE_FORMAT_PFM;
    else if (strcasecmp(dot, ".exr") == 0) *out = IMAGE_FORMAT_EXR;
    else if (strcasecmp(dot, ".hdr") == 0) *out = IMAGE_FORMAT_HDR;
    else {
        snprintf(err->message, sizeof err->message, "%s: unknown image format '%s', %s", path, dot, SUPPORTED_FORMATS);
        return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

image_format image_format_of(const char *path) {
    image_format format = IMAGE_FORMAT_AUTO;
    glint_error scratch;
    return resolve_format(path, IMAGE_FORMAT_AUTO, &format, &scratch) == GLINT_OK ? format : IMAGE_FORMAT_AUTO;
}

// ---- encoders: each writes the whole image to f and returns 0, or an errno value (or -1: see why) ----

static int fail_errno(void) { return errno ? errno : EIO; }

// What the 8-bit encoders write: a float image encoded row by row, or rows already 8-bit (the merge of 8-bit
// region parts, which never holds the image as floats).
typedef struct rows8 {
    int width, height;
    output_transform transform; ///< what the bytes encode (PNG colour chunks)
    const glint_image *img;     ///< the float image to encode, or NULL
    const uint8_t *bytes;       ///< or the bytes themselves, 3 a pixel, row 0 at the top
} rows8;

static rows8 rows8_of(const glint_image *img) { return (rows8){img->width, img->height, img->transform, img, NULL}; }

// One row of display-encoded 8-bit RGB.
static const uint8_t *rows8_row(const rows8 *src, int y, uint8_t *row) {
    size_t n = (size_t)src->width * 3u;
    if (src->bytes) return src->bytes + (size_t)y * n;
    const float *from = &src->img->rgb[(size_t)y * n];
    for (size_t i = 0; i < n; i++) row[i] = film_encode(from[i], src->transform);
    return row;
}

static int write_ppm_binary(FILE *f, const rows8 *src) {
    uint8_t *row = malloc((size_t)src->width * 3u);
    if (!row) return ENOMEM;
    errno = 0;
    int rc = fprintf(f, "P6\n%d %d\n255\n", src->width, src->height) < 0 ? fail_errno() : 0;
    for (int y = 0; y < src->height && rc == 0; y++)
        if (fwrite(rows8_row(src, y, row), 3, (size_t)src->width, f) != (size_t)src->width) rc = fail_errno();
    free(row);
    return rc;
}

// ASCII P3 as the seeds print it: a header, then one "r g b" line per pixel.
static int write_ppm_ascii(FILE *f, const rows8 *src) {
    uint8_t *row = malloc((size_t)src->width * 3u);
    if (!row) return ENOMEM;
    errno = 0;
    int rc = fprintf(f, "P3\n%d %d\n255\n", src->width, src->height) < 0 ? fail_errno() : 0;
    for (int y = 0; y < src->height && rc == 0; y++) {
        const uint8_t *px = rows8_row(src, y, row);
        for (int x = 0; x < src->width && rc == 0; x++)
            if (fprintf(f, "%d %d %d\n", px[3 * x], px[3 * x + 1], px[3 * x + 2]) < 0) rc = fail_errno();
    }
    free(row);
    return rc;
}

// Portable float map of a plane of `channels` (3: "PF", RGB; 1: "Pf", grey) floats a pixel: little-endian
// (scale -1.0), rows from the bottom up. *hash becomes the FNV-1a hash of the bytes written (for a region's
// region file).
static int write_pfm_plane(FILE *f, const glint_image *img, const float *plane, int channels, uint64_t *hash) {
    size_t n = (size_t)img->width * (size_t)channels;
    uint8_t *row = malloc(n * 4u);
    if (!row) return ENOMEM;
    char header[64];
    int len = snprintf(header, sizeof header, "P%c\n%d %d\n-1.0\n", channels == 1 ? 'f' : 'F', img->width,
                       img->height);
    *hash = hash_bytes(HASH_START, header, (size_t)len);
    errno = 0;
    int rc = fwrite(header, 1, (size_t)len, f) != (size_t)len ? fail_errno() : 0;
    for (int y = img->height - 1; y >= 0 && rc == 0; y--) {
        const float *src = &plane[(size_t)y * n];
        for (size_t i = 0; i < n; i++) {
            uint32_t bits;
            memcpy(&bits, &src[i], sizeof bits);
            // Byte by byte, so the file is little-endian whatever the machine.
            for (unsigned b = 0; b < 4; b++) row[4 * i + b] = (uint8_t)(bits >> (8 * b));
        }
        *hash = hash_bytes(*hash, row, n * 4u);
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
    char message[IMAGE_PNG_MESSAGE]; ///< libpng's message (the error pointer)
} png_writer;

void image_png_error(png_structp png, png_const_charp msg) {
    snprintf(png_get_error_ptr(png), IMAGE_PNG_MESSAGE, "%s", msg);
    png_longjmp(png, 1);
}

void image_png_warning(png_structp png, png_const_charp msg) { (void)png; (void)msg; }

static void png_on_write(png_structp png, png_bytep data, size_t length) {
    png_writer *w = png_get_io_ptr(png);
    errno = 0;
    if (fwrite(data, 1, length, w->f) != length) {
        w->write_errno = fail_errno();
        png_error(png, "write failed");
    }
}

static void png_on_flush(png_structp png) { (void)png; } // the caller flushes once at the end

static bool png_encode(png_writer *w, const rows8 *src) {
    if (setjmp(png_jmpbuf(w->png))) return false;
    png_set_write_fn(w->png, w, png_on_write, png_on_flush);
    png_set_IHDR(w->png, w->info, (png_uint_32)src->width, (png_uint_32)src->height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    const glint_image *img = src->img;
    // The colour chunks say how the bytes were encoded, so that viewers decode them right: sRGB (with the
    // gAMA and cHRM that stand for it), or the plain power law of gamma 2 or linear, on sRGB primaries.
    if (src->transform == TRANSFORM_SRGB) {
        png_set_sRGB_gAMA_and_cHRM(w->png, w->info, PNG_sRGB_INTENT_PERCEPTUAL);
    } else {
        png_set_gAMA(w->png, w->info, src->transform == TRANSFORM_GAMMA2 ? 0.5 : 1.0);
        png_set_cHRM(w->png, w->info, 0.3127, 0.3290, 0.64, 0.33, 0.30, 0.60, 0.15, 0.06);
    }
    // A region records where it lies, so that glint_merge can place it; a whole image's bytes stay as they were.
    char key[] = IMAGE_REGION_KEY, where[6 * 12];
    png_text text = {.compression = PNG_TEXT_COMPRESSION_NONE, .key = key, .text = where};
    if (img && film_image_is_region(img)) {
        snprintf(where, sizeof where, "%d,%d,%d,%d,%d,%d", img->x0, img->y0, img->x0 + img->width,
                 img->y0 + img->height, img->full_width, img->full_height);
        png_set_text(w->png, w->info, &text, 1);
    }
    png_write_info(w->png, w->info);
    for (int y = 0; y < src->height; y++) png_write_row(w->png, rows8_row(src, y, w->row));
    png_write_end(w->png, NULL);
    return true;
}

// 8-bit RGB PNG without colour-space chunks: viewers show the bytes as sRGB, exactly as they show the PPM.
static int write_png(FILE *f, const rows8 *src, char *why, size_t why_size) {
    png_writer w = {.f = f};
    w.row = malloc((size_t)src->width * 3u);
    w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, w.message, image_png_error, image_png_warning);
    w.info = w.png ? png_create_info_struct(w.png) : NULL;
    int rc = 0;
    if (!w.row || !w.info) rc = ENOMEM;
    else if (!png_encode(&w, src)) {
        rc = w.write_errno;
        if (rc == 0) { snprintf(why, why_size, "PNG encoder: %s", w.message); rc = -1; }
    }
    if (w.png) png_destroy_write_struct(&w.png, w.info ? &w.info : NULL);
    free(w.row);
    return rc;
}

// stb_image_write's callback: everything goes to the file, and a short write is remembered.
static void hdr_on_write(void *user, void *data, int size) {
    FILE **f = user;
    if (*f && fwrite(data, 1, (size_t)size, *f) != (size_t)size) *f = NULL;
}

// Radiance RGBE (.hdr) through stb_image_write: linear values, run-length encoded scanlines.
static int write_hdr(FILE *f, const glint_image *img) {
    FILE *out = f;
    if (!stbi_write_hdr_to_func(hdr_on_write, &out, img->width, img->height, 3, img->rgb)) return EIO;
    return out ? 0 : (errno ? errno : EIO);
}

// Writes the image in `format`, or, for aov >= 0 (FILM_AOV_*), that AOV plane as a PFM; a PFM's bytes are
// hashed into *pfm_hash.
static int write_format(FILE *f, const glint_image *img, image_format format, int aov, uint64_t *pfm_hash, char *why,
                        size_t why_size) {
    if (aov >= 0) return write_pfm_plane(f, img, img->aov[aov], film_aov_channels(aov), pfm_hash);
    rows8 src = rows8_of(img);
    switch (format) {
    case IMAGE_FORMAT_PNG: return write_png(f, &src, why, why_size);
    case IMAGE_FORMAT_PPM_ASCII: return write_ppm_ascii(f, &src);
    case IMAGE_FORMAT_PFM: return write_pfm_plane(f, img, img->rgb, 3, pfm_hash);
    case IMAGE_FORMAT_EXR: return exr_write(f, img, false, why, why_size);
    case IMAGE_FORMAT_EXR_HALF: return exr_write(f, img, true, why, why_size);
    case IMAGE_FORMAT_HDR: return write_hdr(f, img);
    case IMAGE_FORMAT_PPM:
    case IMAGE_FORMAT_AUTO: break;
    }
    return write_ppm_binary(f, &src);
}

// ---- files ----

static glint_status cannot_write(const char *path, int rc, const char *why, glint_error *err) {
    snprintf(err->message, sizeof err->message, "%s: cannot write: %s", path, rc == -1 ? why : strerror(rc));
    return GLINT_ERR_RENDER;
}

// "dir/.name.tmp-XXXXXX" next to path, so that rename() stays within one file system; NULL when out of memory.
// The name part is cut so that the whole fits in NAME_MAX bytes, as the output's own name does.
static char *temp_name_for(const char *path) {
    size_t dir_len = filepath_dir_length(path);
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

// Why the image cannot replace what is at `target` (0: nothing there, or a file it may replace; -1: see why).
// Only a regular file is replaced: a device, FIFO or socket would itself be replaced by a regular file (root can
// rename over /dev/null). A read-only file is refused, as cp refuses it, even for root, who could replace it:
// its mode says the owner wants it kept.
static int check_existing(const char *target, char *why, size_t why_size) {
    struct stat sb;
    if (lstat(target, &sb) != 0) return 0;
    if (S_ISDIR(sb.st_mode)) return EISDIR;
    if (!S_ISREG(sb.st_mode)) {
        snprintf(why, why_size, "it is %s, not a regular file; glint writes only regular files (- for standard "
                 "output)", S_ISFIFO(sb.st_mode) ? "a FIFO" : S_ISSOCK(sb.st_mode) ? "a socket"
                 : S_ISCHR(sb.st_mode) || S_ISBLK(sb.st_mode) ? "a device" : "a special file");
        return -1;
    }
    if ((sb.st_mode & 0222) == 0 || (access(target, W_OK) != 0 && errno == EACCES)) {
        snprintf(why, why_size, "the file is read-only");
        return -1;
    }
    return 0;
}

// Where the image goes and whether it may: *target is the file to replace (see final_path), which must not be
// a directory or a read-only file. GLINT_ERR_RENDER ("PATH: cannot write: reason") otherwise.
static glint_status prepare_target(const char *path, char **target, glint_error *err) {
    int e = 0;
    *target = filepath_final(path, &e);
    if (!*target) return cannot_write(path, e, "", err);
    char why[160] = "";
    int rc = check_existing(*target, why, sizeof why);
    if (rc == 0) return GLINT_OK;
    free(*target);
    *target = NULL;
    return cannot_write(path, rc, why, err);
}

// Opens a file without a name (Linux O_TMPFILE) in the directory of `target`: until it is linked it is no
// file in any directory, so a kill at any moment, SIGKILL included, leaves nothing behind. -1 with errno;
// EOPNOTSUPP, EISDIR (kernels before 3.11) or EINVAL where the system or the file system cannot.
static int open_unnamed(const char *target) {
#ifdef O_TMPFILE
    // Linking it later needs /proc/self/fd (linkat with AT_EMPTY_PATH needs a privilege).
    if (access("/proc/self/fd", X_OK) != 0) {
        errno = EOPNOTSUPP;
        return -1;
    }
    size_t n = filepath_dir_length(target);
    char *dir = malloc(n + 2);
    if (!dir) return -1;
    if (n) snprintf(dir, n + 2, "%.*s", (int)n, target);
    else snprintf(dir, n + 2, ".");
    int fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666); // the umask applies, as to any new file
    int e = errno;
    free(dir);
    errno = e;
    return fd;
#else
    (void)target;
    errno = EOPNOTSUPP;
    return -1;
#endif
}

static bool unnamed_unsupported(int e) { return e == EOPNOTSUPP || e == EISDIR || e == EINVAL; }

// A temporary file beside target: unnamed where the system can, named (*tmp, mkstemp) otherwise.
static int open_temp(const char *target, char **tmp) {
    *tmp = NULL;
    int fd = open_unnamed(target);
    if (fd >= 0 || !unnamed_unsupported(errno)) return fd;
    *tmp = temp_name_for(target);
    if (!*tmp) {
        errno = ENOMEM;
        return -1;
    }
    fd = mkstemp(*tmp);
    if (fd < 0) {
        int e = errno;
        free(*tmp);
        *tmp = NULL;
        errno = e;
        return -1;
    }
    if (fchmod(fd, new_file_mode()) != 0) { // before any byte is written: the fallback is no less tidy
        int e = errno;
        close(fd);
        unlink(*tmp);
        free(*tmp);
        *tmp = NULL;
        errno = e;
        return -1;
    }
    return fd;
}

// Gives the unnamed file fd the name target, in one step when nothing is there yet. Otherwise it is linked
// under a temporary name and renamed over the old file (link cannot replace): the old file or the new one
// is there at every moment, and only a kill between those two calls could leave the temporary name behind.
// 0 or an errno value.
static int publish_unnamed(int fd, const char *target) {
    char proc[64];
    snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
    if (linkat(AT_FDCWD, proc, AT_FDCWD, target, AT_SYMLINK_FOLLOW) == 0) return 0;
    if (errno != EEXIST) return fail_errno();
    char *tmp = temp_name_for(target);
    if (!tmp) return ENOMEM;
    size_t x = strlen(tmp) - 6; // the XXXXXX
    static const char digits[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    unsigned long seed = (unsigned long)getpid() * 2654435761u ^ (unsigned long)fd;
    int rc = EEXIST;
    for (int attempt = 0; attempt < 100 && rc == EEXIST; attempt++) {
        unsigned long r = seed + (unsigned long)attempt * 0x9e3779b9u;
        for (size_t i = 0; i < 6; i++, r /= 36) tmp[x + i] = digits[r % 36];
        rc = linkat(AT_FDCWD, proc, AT_FDCWD, tmp, AT_SYMLINK_FOLLOW) == 0 ? 0 : fail_errno();
    }
    if (rc == 0 && rename(tmp, target) != 0) {
        rc = fail_errno();
        unlink(tmp);
    }
    free(tmp);
    return rc;
}

static glint_status write_stdout(const glint_image *img, image_format format, glint_error *err) {
    char why[300] = "";
    uint64_t hash;
    int rc = write_format(stdout, img, format, -1, &hash, why, sizeof why);
    errno = 0;
    if (rc == 0 && fflush(stdout) != 0) rc = fail_errno();
    return rc == 0 ? GLINT_OK : cannot_write("standard output", rc, why, err);
}

// The writer of the image (aov < 0) or of one AOV plane (as PFM) in one format, for image_write_file.
typedef struct image_job {
    const glint_image *img;
    image_format format;
    int aov;
    uint64_t *pfm_hash; ///< receives the hash of a PFM's bytes
} image_job;

static int write_image_job(FILE *f, const void *user, char *why, size_t why_size) {
    const image_job *job = user;
    return write_format(f, job->img, job->format, job->aov, job->pfm_hash, why, why_size);
}

// The text of a region file, for image_write_file.
static int write_text_job(FILE *f, const void *user, char *why, size_t why_size) {
    (void)why;
    (void)why_size;
    size_t n = strlen(user);
    errno = 0;
    return fwrite(user, 1, n, f) == n ? 0 : fail_errno();
}

// Writes PATH.region beside the PFM of a region at path, whose bytes hash to `hash` (see io/pfm_region.h).
static glint_status write_pfm_region(const glint_image *img, const char *path, uint64_t hash, glint_error *err) {
    size_t n = strlen(path) + sizeof PFM_REGION_SUFFIX;
    char *side = malloc(n), text[PFM_REGION_MAX_BYTES];
    if (!side) return cannot_write(path, ENOMEM, "", err);
    snprintf(side, n, "%s%s", path, PFM_REGION_SUFFIX);
    int region[4] = {img->x0, img->y0, img->x0 + img->width, img->y0 + img->height};
    pfm_region_text(text, sizeof text, region, img->full_width, img->full_height, hash);
    glint_status st = image_write_file(side, write_text_job, text, err);
    free(side);
    return st;
}

// Writes the image (aov < 0) or one AOV plane to the file path, through a temporary file; the PFM of a region
// is followed by its region file, PATH.region, that glint merge places it by.
static glint_status write_file(const glint_image *img, const char *path, image_format format, int aov,
                               glint_error *err) {
    uint64_t hash = 0;
    image_job job = {img, format, aov, &hash};
    glint_status st = image_write_file(path, write_image_job, &job, err);
    bool pfm = aov >= 0 || format == IMAGE_FORMAT_PFM;
    if (st == GLINT_OK && pfm && film_image_is_region(img)) st = write_pfm_region(img, path, hash, err);
    return st;
}

glint_status image_write_file(const char *path, image_file_writer fill, const void *user, glint_error *err) {
    char *target = NULL, *tmp = NULL;
    glint_status st = prepare_target(path, &target, err);
    if (st != GLINT_OK) return st;
    int fd = open_temp(target, &tmp);
    if (fd < 0) {
        int e = errno;
        free(target);
        return cannot_write(path, e, "", err);
    }
    char why[300] = "";
    int rc = 0;
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        rc = fail_errno();
        close(fd);
    } else {
        rc = fill(f, user, why, sizeof why);
        errno = 0;
        if (rc == 0 && fflush(f) != 0) rc = fail_errno();
        // On disk before it takes the image's name: a crash leaves the old file or the new one, never half.
        if (rc == 0 && fsync(fd) != 0 && errno != EINVAL) rc = fail_errno();
        if (rc == 0 && !tmp) rc = publish_unnamed(fd, target); // needs the descriptor open
        if (fclose(f) != 0 && rc == 0) rc = fail_errno();
    }
    if (rc == 0 && tmp && rename(tmp, target) != 0) rc = fail_errno();
    if (rc != 0 && tmp) unlink(tmp); // a failed write leaves nothing behind
    free(tmp);
    free(target);
    return rc == 0 ? GLINT_OK : cannot_write(path, rc, why, err);
}

// Writes the image (aov < 0; "-": standard output) or one AOV plane, as an "image write" event on the calling
// thread's trace when there is one.
static glint_status write_traced(const glint_image *img, const char *path, image_format format, int aov,
                                 glint_error *err) {
    static const char *const formats[] = {"auto", "PNG", "PPM", "PPM (ASCII)", "PFM", "EXR", "EXR (half)", "HDR"};
    static const char *const aovs[FILM_AOV_COUNT] = {"albedo", "normal", "depth", "samples"};
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = strcmp(path, "-") == 0 ? write_stdout(img, format, err) : write_file(img, path, format, aov, err);
    if (!lane) return st;
    const char *kind = (unsigned)format < sizeof formats / sizeof *formats ? formats[format] : "?";
    const char *plane = aov >= 0 && aov < FILM_AOV_COUNT ? aovs[aov] : "colour";
    trace_add(lane, &(trace_event){"image write", "io", began, trace_clock(), 3,
                                   {{"file", 0, path}, {"format", 0, kind}, {"plane", 0, plane}}});
    return st;
}

glint_status image_write(const glint_image *img, const char *path, image_format format, glint_error *err) {
    glint_status st = resolve_format(path, format, &format, err);
    if (st != GLINT_OK) return st;
    return write_traced(img, path, format, -1, err);
}

glint_status image_write_aov(const glint_image *img, int aov, const char *path, glint_error *err) {
    static const char *const names[FILM_AOV_COUNT] = {"albedo", "normal", "depth", "samples"};
    image_format format;
    glint_status st = resolve_format(path, IMAGE_FORMAT_AUTO, &format, err);
    if (st != GLINT_OK) return st;
    if (format != IMAGE_FORMAT_PFM || strcmp(path, "-") == 0) {
        snprintf(err->message, sizeof err->message, "%s: an AOV is written as PFM alone, expected a .pfm file "
                 "(OpenEXR files hold the AOVs as channels beside the colour)", path);
        return GLINT_ERR_INPUT;
    }
    if (aov < 0 || aov >= FILM_AOV_COUNT || !img->aov[aov]) {
        snprintf(err->message, sizeof err->message, "%s: the image has no %s AOV, expected a render that asked "
                 "for it (glint_render_options.aovs)", path, aov >= 0 && aov < FILM_AOV_COUNT ? names[aov] : "such");
        return GLINT_ERR_INPUT;
    }
    return write_traced(img, path, format, aov, err);
}

// The 8-bit writer of rows8 in PNG or PPM, for image_write_file.
typedef struct rows8_job {
    const rows8 *src;
    image_format format;
} rows8_job;

static int write_rows8_job(FILE *f, const void *user, char *why, size_t why_size) {
    const rows8_job *job = user;
    if (job->format == IMAGE_FORMAT_PNG) return write_png(f, job->src, why, why_size);
    return job->format == IMAGE_FORMAT_PPM_ASCII ? write_ppm_ascii(f, job->src) : write_ppm_binary(f, job->src);
}

glint_status image_write_rgb8(const uint8_t *rgb, int width, int height, output_transform transform,
                              const char *path, glint_error *err) {
    image_format format;
    glint_status st = resolve_format(path, IMAGE_FORMAT_AUTO, &format, err);
    if (st != GLINT_OK) return st;
    if (format != IMAGE_FORMAT_PNG && format != IMAGE_FORMAT_PPM) {
        snprintf(err->message, sizeof err->message, "%s: 8-bit values are written as .png or .ppm alone; a float "
                 "format would hold them as if they were linear light", path);
        return GLINT_ERR_INPUT;
    }
    rows8 src = {width, height, transform, NULL, rgb};
    rows8_job job = {&src, format};
    if (strcmp(path, "-") != 0) return image_write_file(path, write_rows8_job, &job, err);
    char why[300] = "";
    int rc = write_rows8_job(stdout, &job, why, sizeof why);
    errno = 0;
    if (rc == 0 && fflush(stdout) != 0) rc = fail_errno();
    return rc == 0 ? GLINT_OK : cannot_write("standard output", rc, why, err);
}

glint_status image_check_path(const char *path, image_format format, glint_error *err) {
    glint_status st = resolve_format(path, format, &format, err);
    if (st != GLINT_OK || strcmp(path, "-") == 0) return st;
    return image_check_file(path, err);
}

glint_status image_check_file(const char *path, glint_error *err) {
    char *target = NULL, *tmp = NULL;
    glint_status st = prepare_target(path, &target, err);
    if (st != GLINT_OK) return st;
    // Create and remove a temporary file exactly where the file will go: the one test that sees every reason.
    int fd = open_temp(target, &tmp);
    int e = errno;
    if (fd >= 0) {
        close(fd);
        if (tmp) unlink(tmp);
    }
    free(tmp);
    free(target);
    return fd >= 0 ? GLINT_OK : cannot_write(path, e, "", err);
}
