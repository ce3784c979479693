// image_merge.c — glint merge: region PNGs (placed by their "glint:region" chunk) assembled into the full image.
#include "io/image_merge.h"
#include "film/film.h"
#include "io/image_png.h"
#include "io/image_write.h"

#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char EXPECTED_PART[] = "expected a PNG written by glint with --region";

enum { MAX_SIDE = 16384 }; // the largest image width and height a scene renders at: a part cannot claim more

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
    png_infop info;
    png_bytep *rows;
    char message[IMAGE_PNG_MESSAGE]; ///< libpng's message (the error pointer), or why the file is no part
} png_reader;

// Parses "X0,Y0,X1,Y1,W,H" strictly (six decimal integers, nothing else) into p; false when it is not that.
static bool parse_region(const char *text, part *p) {
    int n = -1;
    int *r = p->region;
    if (sscanf(text, "%d,%d,%d,%d,%d,%d%n", &r[0], &r[1], &r[2], &r[3], &p->full_width, &p->full_height, &n) != 6 ||
        n < 0 || text[n] != '\0')
        return false;
    return r[0] >= 0 && r[1] >= 0 && r[0] < r[2] && r[1] < r[3] && r[2] <= p->full_width &&
           r[3] <= p->full_height && p->full_width <= MAX_SIDE && p->full_height <= MAX_SIDE;
}

// The part's chunk and pixels; false with r->message set (or a libpng message) when it is no region PNG.
static bool png_decode_part(png_reader *r, part *p) {
    if (setjmp(png_jmpbuf(r->png))) return false;
    png_init_io(r->png, r->f);
    png_read_info(r->png, r->info);
    png_uint_32 w = png_get_image_width(r->png, r->info), h = png_get_image_height(r->png, r->info);
    if (png_get_bit_depth(r->png, r->info) != 8 || png_get_color_type(r->png, r->info) != PNG_COLOR_TYPE_RGB ||
        png_get_interlace_type(r->png, r->info) != PNG_INTERLACE_NONE) {
        snprintf(r->message, sizeof r->message, "not an 8-bit RGB PNG, %s", EXPECTED_PART);
        return false;
    }
    // The colour chunks glint writes: sRGB, or the gAMA of gamma 2 (0.5) or of linear values (1).
    int intent;
    double gamma = 1.0;
    if (png_get_sRGB(r->png, r->info, &intent)) p->encoding = TRANSFORM_SRGB;
    else if (png_get_gAMA(r->png, r->info, &gamma) && fabs(gamma - 0.5) < 1e-4) p->encoding = TRANSFORM_GAMMA2;
    else p->encoding = TRANSFORM_LINEAR;
    png_textp text = NULL;
    int count = 0;
    png_get_text(r->png, r->info, &text, &count);
    const char *where = NULL;
    for (int i = 0; i < count; i++)
        if (strcmp(text[i].key, IMAGE_REGION_KEY) == 0) where = text[i].text;
    if (!where) {
        snprintf(r->message, sizeof r->message, "no %s chunk, %s", IMAGE_REGION_KEY, EXPECTED_PART);
        return false;
    }
    if (!parse_region(where, p)) {
        snprintf(r->message, sizeof r->message, "%s '%.64s' is not X0,Y0,X1,Y1,W,H of a region inside a W x H image",
                 IMAGE_REGION_KEY, where);
        return false;
    }
    if (w != (png_uint_32)(p->region[2] - p->region[0]) || h != (png_uint_32)(p->region[3] - p->region[1])) {
        snprintf(r->message, sizeof r->message, "the image is %ux%u but its %s %s is %dx%d", (unsigned)w,
                 (unsigned)h, IMAGE_REGION_KEY, where, p->region[2] - p->region[0], p->region[3] - p->region[1]);
        return false;
    }
    p->rgb = malloc((size_t)w * h * 3u);
    r->rows = malloc(h * sizeof *r->rows);
    if (!p->rgb || !r->rows) png_error(r->png, "out of memory");
    for (png_uint_32 y = 0; y < h; y++) r->rows[y] = p->rgb + (size_t)y * w * 3u;
    png_read_image(r->png, r->rows);
    return true;
}

// Reads one part; GLINT_ERR_INPUT ("PATH: what is wrong") when it cannot be read or is no region PNG.
static glint_status read_part(const char *path, part *p, glint_error *err) {
    memset(p, 0, sizeof *p);
    png_reader r = {.f = fopen(path, "rb")};
    if (!r.f) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    uint8_t signature[8];
    bool ok = fread(signature, 1, sizeof signature, r.f) == sizeof signature && png_sig_cmp(signature, 0, 8) == 0;
    if (!ok) snprintf(r.message, sizeof r.message, "not a PNG file, %s", EXPECTED_PART);
    if (ok) {
        rewind(r.f);
        r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, r.message, image_png_error, image_png_warning);
        r.info = r.png ? png_create_info_struct(r.png) : NULL;
        if (!r.info) snprintf(r.message, sizeof r.message, "out of memory");
        ok = r.info && png_decode_part(&r, p);
    }
    if (r.png) png_destroy_read_struct(&r.png, r.info ? &r.info : NULL, NULL);
    free(r.rows);
    fclose(r.f);
    if (ok) return GLINT_OK;
    free(p->rgb);
    p->rgb = NULL;
    snprintf(err->message, sizeof err->message, "%s: %s", path, r.message);
    // Running out of memory is a resource failure, not a bad part.
    return strcmp(r.message, "out of memory") == 0 ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
}

static bool region_contains(const int r[4], int x, int y) { return x >= r[0] && x < r[2] && y >= r[1] && y < r[3]; }

// Copies part i into the image, marking its pixels in `covered`; GLINT_ERR_INPUT naming the earlier part it
// overlaps.
static glint_status place_part(const char *const *paths, const part *parts, size_t i, glint_image *img,
                               uint8_t *covered, glint_error *err, const float decoded[256]) {
    const part *p = &parts[i];
    int w = p->region[2] - p->region[0];
    for (int y = p->region[1]; y < p->region[3]; y++)
        for (int x = p->region[0]; x < p->region[2]; x++) {
            size_t at = (size_t)y * (size_t)img->width + (size_t)x;
            if (covered[at]) {
                size_t j = 0;
                while (j < i && !region_contains(parts[j].region, x, y)) j++;
                snprintf(err->message, sizeof err->message, "%s: overlaps %s at pixel (%d, %d)", paths[i], paths[j],
                         x, y);
                return GLINT_ERR_INPUT;
            }
            covered[at] = 1;
            const uint8_t *src = &p->rgb[((size_t)(y - p->region[1]) * (size_t)w + (size_t)(x - p->region[0])) * 3u];
            // A value that encodes back to exactly these bytes, under the parts' encoding: the bytes pass unchanged,
            // and the merged PNG says what they encode, as the parts did.
            for (int c = 0; c < 3; c++) img->rgb[at * 3u + (size_t)c] = decoded[src[c]];
        }
    return GLINT_OK;
}

// GLINT_ERR_INPUT naming the first pixel (in row order) that no part covers, if any.
static glint_status check_gaps(const glint_image *img, const uint8_t *covered, glint_error *err) {
    size_t n = (size_t)img->width * (size_t)img->height, missing = 0, first = 0;
    for (size_t i = n; i-- > 0;)
        if (!covered[i]) {
            missing++;
            first = i;
        }
    if (missing == 0) return GLINT_OK;
    snprintf(err->message, sizeof err->message, "no part covers pixel (%zu, %zu) of the %dx%d image (%zu pixels "
             "missing)", first % (size_t)img->width, first / (size_t)img->width, img->width, img->height, missing);
    return GLINT_ERR_INPUT;
}

// Whether path names a PFM file, which would hold the parts' 8-bit values as if they were linear radiance.
static bool is_pfm_path(const char *path) {
    size_t n = strlen(path);
    return n > 4 && strcasecmp(path + n - 4, ".pfm") == 0;
}

glint_status image_merge(const char *output, const char *const *parts_paths, size_t count, glint_error *err) {
    if (count == 0) {
        snprintf(err->message, sizeof err->message, "merge: no parts given, expected one PNG per region");
        return GLINT_ERR_INPUT;
    }
    if (is_pfm_path(output)) {
        snprintf(err->message, sizeof err->message, "%s: merge writes the parts' 8-bit values, expected .png or .ppm",
                 output);
        return GLINT_ERR_INPUT;
    }
    part *parts = calloc(count, sizeof *parts);
    if (!parts) {
        snprintf(err->message, sizeof err->message, "merge: out of memory");
        return GLINT_ERR_RENDER;
    }
    glint_image *img = NULL;
    uint8_t *covered = NULL;
    float decoded[256]; // byte -> a value encoding back to it, under the parts' encoding
    glint_status st = GLINT_OK;
    for (size_t i = 0; i < count && st == GLINT_OK; i++) {
        st = read_part(parts_paths[i], &parts[i], err);
        if (st != GLINT_OK) break;
        const part *p = &parts[i];
        if (i == 0) {
            img = film_image_new(p->full_width, p->full_height, p->encoding);
            for (int v = 0; v < 256; v++) decoded[v] = film_decode((uint8_t)v, p->encoding);
            covered = calloc((size_t)p->full_width * (size_t)p->full_height, 1);
            if (!img || !covered) {
                snprintf(err->message, sizeof err->message, "merge: out of memory for a %dx%d image", p->full_width,
                         p->full_height);
                st = GLINT_ERR_RENDER;
                break;
            }
        } else if (p->encoding != img->transform) {
            snprintf(err->message, sizeof err->message, "%s: its bytes encode light otherwise than %s's (the parts were "
                     "written with different --output-encoding)", parts_paths[i], parts_paths[0]);
            st = GLINT_ERR_INPUT;
            break;
        } else if (p->full_width != img->width || p->full_height != img->height) {
            snprintf(err->message, sizeof err->message, "%s: a region of a %dx%d image, but %s is of a %dx%d image",
                     parts_paths[i], p->full_width, p->full_height, parts_paths[0], img->width, img->height);
            st = GLINT_ERR_INPUT;
            break;
        }
        st = place_part(parts_paths, parts, i, img, covered, err, decoded);
        // The pixels are in the image now; the region stays for the overlap message of a later part.
        free(parts[i].rgb);
        parts[i].rgb = NULL;
    }
    if (st == GLINT_OK) st = check_gaps(img, covered, err);
    if (st == GLINT_OK) st = image_write(img, output, GLINT_FORMAT_AUTO, err);
    for (size_t i = 0; i < count; i++) free(parts[i].rgb);
    free(parts);
    free(covered);
    film_image_free(img);
    return st;
}
