// image_merge.c — glint merge: the driver (the output, the kind of the parts), what both halves share (opening a
// part, its region text, the map of covered pixels), and 8-bit region PNGs (placed by their "glint:region" chunk)
// assembled into the full PNG or PPM. Float parts are io/merge_float.c's.
#include "io/image_merge.h"
#include "core/filepath.h"
#include "film/film.h"
#include "io/exr_read.h"
#include "io/image_png.h"
#include "io/image_write.h"
#include "io/merge_float.h"
#include "io/merge_parts.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char EXPECTED_PART[] = "expected a PNG written by glint with --region";

enum {
    MAX_SIDE = MERGE_MAX_SIDE, // the largest image width and height a scene renders at: a part cannot claim more
    DEFLATE_MAX_RATIO = 1032   // the most bytes deflate (PNG's compression) makes of one byte of its stream
};

// One part: where it lies in the full image, and its 8-bit RGB rows.
typedef struct part {
    int region[4];               ///< X0, Y0, X1, Y1
    int full_width, full_height; ///< the full image it is a region of
    output_transform encoding;   ///< what its PNG colour chunks say its bytes encode (linear without any)
    uint8_t *rgb;                ///< (X1 - X0) * (Y1 - Y0) pixels, 3 bytes each
} part;

// libpng reports errors by longjmp; what the error path needs lives here, outside the function calling setjmp.
typedef struct png_reader {
    FILE *f;
    png_structp png;
    png_infop info, end;
    const char *stage;  ///< what is being read, for the message of a file that ends early
    png_uint_32 row, height;
    bool cut_short;     ///< the file ended before libpng had what it asked for
    bool libpng_failed; ///< the message is libpng's (a damaged file)
    uint64_t file_size;
    char message[IMAGE_PNG_MESSAGE]; ///< libpng's message (the error pointer), or why the file is no part
} png_reader;

// libpng's reads, so that a file that ends early says where rather than libpng's "Read Error".
static void png_on_read(png_structp png, png_bytep data, size_t length) {
    png_reader *r = png_get_io_ptr(png);
    if (fread(data, 1, length, r->f) == length) return;
    if (ferror(r->f)) png_error(png, "read error");
    r->cut_short = true;
    png_error(png, "truncated");
}

// The text of the part's region chunk, before or after the image data; NULL with r->message set when there is
// none, or two that disagree.
static const char *region_text(png_reader *r) {
    const char *where = NULL;
    png_infop infos[2] = {r->info, r->end};
    for (int k = 0; k < 2; k++) {
        png_textp text = NULL;
        int count = 0;
        png_get_text(r->png, infos[k], &text, &count);
        for (int i = 0; i < count; i++) {
            if (strcmp(text[i].key, IMAGE_REGION_KEY) != 0) continue;
            if (where && strcmp(where, text[i].text) != 0) {
                snprintf(r->message, sizeof r->message, "two %s chunks that disagree ('%.40s' and '%.40s'), %s",
                         IMAGE_REGION_KEY, where, text[i].text, EXPECTED_PART);
                return NULL;
            }
            where = text[i].text;
        }
    }
    if (!where) snprintf(r->message, sizeof r->message, "no %s chunk, %s", IMAGE_REGION_KEY, EXPECTED_PART);
    return where;
}

// The part's pixels and region chunk (before or after the image data); false with r->message set (or a libpng
// message) when it is no region PNG.
static bool png_decode_part(png_reader *r, part *p) {
    if (setjmp(png_jmpbuf(r->png))) {
        r->libpng_failed = true;
        return false;
    }
    png_set_read_fn(r->png, r, png_on_read);
    // A damaged chunk is an error, not a chunk quietly dropped (the region chunk is ancillary).
    png_set_crc_action(r->png, PNG_CRC_ERROR_QUIT, PNG_CRC_ERROR_QUIT);
    png_set_user_limits(r->png, MAX_SIDE, MAX_SIDE);
    r->stage = "its header";
    png_read_info(r->png, r->info);
    png_uint_32 w = png_get_image_width(r->png, r->info), h = png_get_image_height(r->png, r->info);
    if (png_get_bit_depth(r->png, r->info) != 8 || png_get_color_type(r->png, r->info) != PNG_COLOR_TYPE_RGB ||
        png_get_interlace_type(r->png, r->info) != PNG_INTERLACE_NONE) {
        snprintf(r->message, sizeof r->message, "not an 8-bit RGB PNG, %s", EXPECTED_PART);
        return false;
    }
    if (w > MAX_SIDE || h > MAX_SIDE) {
        snprintf(r->message, sizeof r->message, "the image is %ux%u, larger than any region (%d pixels a side)",
                 (unsigned)w, (unsigned)h, MAX_SIDE);
        return false;
    }
    // Deflate packs at most 1032 bytes into one: a file too small to hold the rows it declares is refused before
    // they are allocated (a 783 kB part once declared 16384 x 16384 pixels).
    uint64_t rows_bytes = (uint64_t)h * (1u + (uint64_t)w * 3u);
    if (r->file_size * DEFLATE_MAX_RATIO < rows_bytes) {
        snprintf(r->message, sizeof r->message, "truncated PNG: %llu bytes cannot hold %ux%u pixels",
                 (unsigned long long)r->file_size, (unsigned)w, (unsigned)h);
        return false;
    }
    // The colour chunks glint writes: sRGB, or the gAMA of gamma 2 (0.5) or of linear values (1).
    int intent;
    double gamma = 1.0;
    if (png_get_sRGB(r->png, r->info, &intent)) p->encoding = TRANSFORM_SRGB;
    else if (png_get_gAMA(r->png, r->info, &gamma) && fabs(gamma - 0.5) < 1e-4) p->encoding = TRANSFORM_GAMMA2;
    else p->encoding = TRANSFORM_LINEAR;
    p->rgb = malloc((size_t)w * h * 3u);
    if (!p->rgb) png_error(r->png, "out of memory");
    r->stage = "its image data";
    r->height = h;
    for (r->row = 0; r->row < h; r->row++) png_read_row(r->png, p->rgb + (size_t)r->row * w * 3u, NULL);
    r->stage = "the chunks after its image data";
    png_read_end(r->png, r->end);
    const char *where = region_text(r);
    if (!where) return false;
    if (!merge_parse_region(where, p->region, &p->full_width, &p->full_height)) {
        snprintf(r->message, sizeof r->message, "%s '%.64s' is not X0,Y0,X1,Y1,W,H of a region inside a W x H image "
                 "of at most %d pixels a side", IMAGE_REGION_KEY, where, MAX_SIDE);
        return false;
    }
    if (w != (png_uint_32)(p->region[2] - p->region[0]) || h != (png_uint_32)(p->region[3] - p->region[1])) {
        snprintf(r->message, sizeof r->message, "the image is %ux%u but its %s %s is %dx%d", (unsigned)w,
                 (unsigned)h, IMAGE_REGION_KEY, where, p->region[2] - p->region[0], p->region[3] - p->region[1]);
        return false;
    }
    return true;
}

// Walks the chunks after the signature: each must fit in what is left of the file, up to IEND. libpng allocates
// a text chunk's declared length before reading it (a forged 2 GB tEXt in a 300-byte part). false with the
// message written otherwise; the file is left at its start.
static bool chunks_fit(png_reader *r) {
    uint64_t at = 8;
    for (;;) {
        unsigned char head[8];
        if (fseek(r->f, (long)at, SEEK_SET) != 0 || fread(head, 1, 8, r->f) != 8) {
            snprintf(r->message, sizeof r->message, "truncated PNG: the file ends before its IEND chunk");
            return false;
        }
        uint64_t length = (uint64_t)head[0] << 24 | (uint64_t)head[1] << 16 | (uint64_t)head[2] << 8 | head[3];
        if (length > r->file_size - at - 8 || r->file_size - at - 8 - length < 4) {
            snprintf(r->message, sizeof r->message, "truncated PNG: its %.4s chunk declares %llu bytes, the file holds "
                     "%llu more", (const char *)head + 4, (unsigned long long)length,
                     (unsigned long long)(r->file_size - at - 8));
            return false;
        }
        at += 12 + length;
        if (memcmp(head + 4, "IEND", 4) == 0) break;
    }
    rewind(r->f);
    return true;
}

// Reads the region PNG open as f (file_size bytes, at its start); GLINT_ERR_INPUT ("PATH: what is wrong") when it
// is no region PNG. The file stays open.
static glint_status read_png_part(FILE *f, const char *path, uint64_t file_size, part *p, glint_error *err) {
    memset(p, 0, sizeof *p);
    png_reader r = {.f = f, .file_size = file_size};
    uint8_t signature[8];
    bool ok = fread(signature, 1, sizeof signature, r.f) == sizeof signature && png_sig_cmp(signature, 0, 8) == 0;
    if (!ok) snprintf(r.message, sizeof r.message, "not a PNG file, %s", EXPECTED_PART);
    ok = ok && chunks_fit(&r);
    if (ok) {
        rewind(r.f);
        r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, r.message, image_png_error, image_png_warning);
        r.info = r.png ? png_create_info_struct(r.png) : NULL;
        r.end = r.info ? png_create_info_struct(r.png) : NULL;
        if (!r.end) snprintf(r.message, sizeof r.message, "out of memory");
        ok = r.end && png_decode_part(&r, p);
    }
    if (!ok && r.libpng_failed && !r.cut_short && strcmp(r.message, "out of memory") != 0) {
        char said[IMAGE_PNG_MESSAGE];
        snprintf(said, sizeof said, "%s", r.message);
        snprintf(r.message, sizeof r.message, "corrupt PNG (%.160s), %s", said, EXPECTED_PART);
    }
    if (!ok && r.cut_short) {
        if (r.height > 0 && strcmp(r.stage, "its image data") == 0)
            snprintf(r.message, sizeof r.message, "truncated PNG: the file ends in its image data, at row %u of %u",
                     (unsigned)r.row + 1, (unsigned)r.height);
        else
            snprintf(r.message, sizeof r.message, "truncated PNG: the file ends in %s", r.stage);
    }
    if (r.png) png_destroy_read_struct(&r.png, r.info ? &r.info : NULL, r.end ? &r.end : NULL);
    if (ok) return GLINT_OK;
    free(p->rgb);
    p->rgb = NULL;
    snprintf(err->message, sizeof err->message, "%s: %s", path, r.message);
    // Running out of memory is a resource failure, not a bad part.
    return strcmp(r.message, "out of memory") == 0 ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
}

// ---- what both halves share ----

// ---- 8-bit parts ----

// Assembles region PNGs into the .png or .ppm output with their 8-bit values: 4 bytes a pixel of the full image
// (its bytes and which pixels are covered) and 3 a pixel of the part being read.
static glint_status merge_png(const char *output, const char *const *paths, size_t count, size_t max_bytes,
                              glint_error *err) {
    part p = {0};
    merge_cover cover = {0};
    uint8_t *rgb = NULL;
    output_transform encoding = TRANSFORM_LINEAR;
    glint_status st = GLINT_OK;
    for (size_t i = 0; i < count && st == GLINT_OK; i++) {
        struct stat sb;
        merge_kind kind;
        FILE *f = merge_open(paths[i], &sb, &kind, &st, err);
        if (!f) break;
        if (kind != MERGE_PNG) st = merge_wrong_kind(paths[i], kind, paths[0], MERGE_PNG, err);
        if (st == GLINT_OK) st = read_png_part(f, paths[i], (uint64_t)sb.st_size, &p, err);
        fclose(f);
        if (st != GLINT_OK) break;
        if (i == 0) {
            encoding = p.encoding;
            uint64_t need = (uint64_t)p.full_width * (uint64_t)p.full_height * 4u;
            if (need > max_bytes) {
                snprintf(err->message, sizeof err->message, "%s: a region of a %dx%d image, whose merge would take "
                         "%llu bytes, more than the %zu allowed", paths[i], p.full_width, p.full_height,
                         (unsigned long long)need, max_bytes);
                st = GLINT_ERR_INPUT;
            } else if (!merge_cover_init(&cover, p.full_width, p.full_height, count) ||
                       !(rgb = malloc((size_t)p.full_width * (size_t)p.full_height * 3u))) {
                snprintf(err->message, sizeof err->message, "merge: out of memory for a %dx%d image", p.full_width,
                         p.full_height);
                st = GLINT_ERR_RENDER;
            }
        } else if (p.encoding != encoding) {
            snprintf(err->message, sizeof err->message, "%s: its bytes encode light otherwise than %s's (the parts were "
                     "written with different --output-encoding)", paths[i], paths[0]);
            st = GLINT_ERR_INPUT;
        } else if (p.full_width != cover.width || p.full_height != cover.height) {
            snprintf(err->message, sizeof err->message, "%s: a region of a %dx%d image, but %s is of a %dx%d image",
                     paths[i], p.full_width, p.full_height, paths[0], cover.width, cover.height);
            st = GLINT_ERR_INPUT;
        }
        if (st == GLINT_OK) st = merge_cover_claim(&cover, paths, i, p.region, err);
        if (st == GLINT_OK) {
            size_t w = (size_t)(p.region[2] - p.region[0]);
            for (int y = p.region[1]; y < p.region[3]; y++)
                memcpy(rgb + ((size_t)y * (size_t)cover.width + (size_t)p.region[0]) * 3u,
                       p.rgb + (size_t)(y - p.region[1]) * w * 3u, w * 3u);
        }
        free(p.rgb);
        p.rgb = NULL;
    }
    if (st == GLINT_OK) st = merge_cover_check_gaps(&cover, err);
    if (st == GLINT_OK) st = image_write_rgb8(rgb, cover.width, cover.height, encoding, output, err);
    merge_cover_free(&cover);
    free(rgb);
    return st;
}

// ---- the driver ----

glint_status image_merge_limited(const char *output, const char *const *paths, size_t count, size_t max_bytes,
                                 glint_error *err) {
    if (count == 0) {
        snprintf(err->message, sizeof err->message, "merge: no parts given, expected one file per region");
        return GLINT_ERR_INPUT;
    }
    glint_status st = image_check_path(output, IMAGE_FORMAT_AUTO, err);
    if (st != GLINT_OK) return st;
    for (size_t i = 0; i < count; i++)
        if (filepath_same_target(output, paths[i])) {
            snprintf(err->message, sizeof err->message, "%s: cannot write: it is the part %s, which would be lost",
                     output, paths[i]);
            return GLINT_ERR_INPUT;
        }
    // The first part says whether the merge is of 8-bit or float values; the output must be of the same kind.
    struct stat sb;
    merge_kind first = MERGE_UNKNOWN;
    FILE *f = merge_open(paths[0], &sb, &first, &st, err);
    if (!f) return st;
    fclose(f);
    if (first != MERGE_PNG && !merge_kind_float(first))
        return merge_wrong_kind(paths[0], first, paths[0], first, err);
    image_format format = image_format_of(output);
    bool eight_bit_output = format == IMAGE_FORMAT_PNG || format == IMAGE_FORMAT_PPM;
    if (merge_kind_float(first) && eight_bit_output) {
        snprintf(err->message, sizeof err->message, "%s: %s is %s: float parts merge to .exr, .pfm or .hdr, not to "
                 "8-bit values (render PNG parts for an 8-bit merge)", output, paths[0], merge_kind_name(first));
        return GLINT_ERR_INPUT;
    }
    if (!merge_kind_float(first) && !eight_bit_output) {
        snprintf(err->message, sizeof err->message, "%s: %s is %s: its bytes are display-encoded, not linear light, "
                 "so 8-bit parts merge to .png or .ppm alone (render .exr or .pfm parts for a float merge)", output,
                 paths[0], merge_kind_name(first));
        return GLINT_ERR_INPUT;
    }
    if (merge_kind_float(first)) return merge_float(output, format, paths, count, first, max_bytes, err);
    return merge_png(output, paths, count, max_bytes, err);
}

glint_status image_merge(const char *output, const char *const *paths, size_t count, glint_error *err) {
    return image_merge_limited(output, paths, count, SIZE_MAX, err);
}
