// merge_float.c — glint merge of float parts: OpenEXR regions (placed by their data windows, every channel glint
// writes) and PFM regions (placed by the region file beside each) decoded straight into the full image's float
// planes, each value exactly as the part holds it, then written as OpenEXR, PFM or Radiance HDR.
#include "core/filepath.h"
#include "core/hash.h"
#include "film/film.h"
#include "io/exr_read.h"
#include "io/image_write.h"
#include "io/merge_float.h"
#include "io/merge_parts.h"
#include "io/pfm_region.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char EXPECTED_EXR[] = "expected an OpenEXR file written by glint with --region";
static const char EXPECTED_PFM[] = "expected a PFM written by glint with --region";

// The channels a float part may hold: those glint writes, each at its place in the image's planes (plane 0 the
// colour, then FILM_AOV_* + 1), and the grey values of a "Pf" PFM (an AOV plane written alone, such as depth),
// which the merge keeps in the one-float depth plane.
enum { PLANE_COLOUR, PLANE_ALBEDO, PLANE_NORMAL, PLANE_DEPTH, PLANE_SAMPLES, PLANE_COUNT };
_Static_assert(PLANE_COUNT == FILM_AOV_COUNT + 1 && PLANE_SAMPLES == FILM_AOV_SAMPLES + 1, "a plane for each AOV");
typedef struct known_channel {
    const char *name;
    int plane, component;
} known_channel;
static const known_channel KNOWN[] = {
    {"R", PLANE_COLOUR, 0},        {"G", PLANE_COLOUR, 1},        {"B", PLANE_COLOUR, 2},
    {"albedo.R", PLANE_ALBEDO, 0}, {"albedo.G", PLANE_ALBEDO, 1}, {"albedo.B", PLANE_ALBEDO, 2},
    {"normal.X", PLANE_NORMAL, 0}, {"normal.Y", PLANE_NORMAL, 1}, {"normal.Z", PLANE_NORMAL, 2},
    {"Z", PLANE_DEPTH, 0},         {"samples", PLANE_SAMPLES, 0}, {"the grey values of a Pf PFM", PLANE_DEPTH, 0}};
enum { KNOWN_COUNT = sizeof KNOWN / sizeof KNOWN[0], KNOWN_DEPTH = 9, KNOWN_SAMPLES = 10, KNOWN_GREY = 11 };
static const unsigned COLOUR_BITS = 7u, GREY_BIT = 1u << KNOWN_GREY;

// Floats a pixel of a plane.
static int plane_stride(int plane) { return plane == PLANE_DEPTH || plane == PLANE_SAMPLES ? 1 : 3; }

// One float part being read: where it lies, what it holds, and its open reader.
typedef struct float_part {
    merge_kind kind;
    int region[4];               ///< X0, Y0, X1, Y1
    int full_width, full_height; ///< the full image it is a region of
    unsigned channels;           ///< bits of KNOWN
    bool half;                   ///< every channel but Z is 16-bit half
    exr_part *exr;               ///< OpenEXR: the open reader
    exr_part_info info;          ///< OpenEXR: its header
    int *known;                  ///< OpenEXR: the KNOWN index of each of the file's channels
    pfm_header pfm;              ///< PFM: its header
} float_part;

// ---- OpenEXR parts ----

// Reads an OpenEXR part's header: one part, a display window of at most MERGE_MAX_SIDE a side from (0, 0), the data
// window inside it, and only the channels glint writes (full resolution, half or float), in whole groups.
static glint_status open_exr_part(FILE *f, const char *path, float_part *p, glint_error *err) {
    glint_status st = exr_part_open(f, path, (size_t)MERGE_MAX_SIDE * MERGE_MAX_SIDE, &p->exr, &p->info, err);
    if (st != GLINT_OK) return st;
    const exr_part_info *in = &p->info;
    const int *d = in->display, *w = in->data;
    if (in->parts != 1) {
        snprintf(err->message, sizeof err->message, "%s: an OpenEXR file of %d parts, %s (a single-part image)", path,
                 in->parts, EXPECTED_EXR);
        return GLINT_ERR_INPUT;
    }
    if (d[0] != 0 || d[1] != 0 || d[2] < 1 || d[3] < 1 || d[2] > MERGE_MAX_SIDE || d[3] > MERGE_MAX_SIDE) {
        snprintf(err->message, sizeof err->message, "%s: its display window is not a full image from (0, 0) of at "
                 "most %d pixels a side, %s", path, MERGE_MAX_SIDE, EXPECTED_EXR);
        return GLINT_ERR_INPUT;
    }
    if (w[0] < 0 || w[1] < 0 || w[2] > d[2] || w[3] > d[3]) {
        snprintf(err->message, sizeof err->message, "%s: its data window (%d,%d)-(%d,%d) is not inside its %dx%d "
                 "display window, %s", path, w[0], w[1], w[2] - 1, w[3] - 1, d[2], d[3], EXPECTED_EXR);
        return GLINT_ERR_INPUT;
    }
    memcpy(p->region, w, sizeof p->region);
    p->full_width = d[2];
    p->full_height = d[3];
    p->known = calloc((size_t)in->channel_count + 1u, sizeof *p->known);
    if (!p->known) {
        snprintf(err->message, sizeof err->message, "%s: out of memory", path);
        return GLINT_ERR_RENDER;
    }
    p->half = true;
    for (int c = 0; c < in->channel_count; c++) {
        const exr_channel *ch = &in->channels[c];
        int k = 0;
        while (k < KNOWN_GREY && strcmp(KNOWN[k].name, ch->name) != 0) k++;
        if (k == KNOWN_GREY) {
            snprintf(err->message, sizeof err->message, "%s: channel '%.64s' is not one glint writes (R, G, B, "
                     "albedo.R/G/B, normal.X/Y/Z, Z, samples), %s", path, ch->name, EXPECTED_EXR);
            return GLINT_ERR_INPUT;
        }
        if (ch->subsampled || ch->type == EXR_CHANNEL_UINT) {
            snprintf(err->message, sizeof err->message, "%s: channel %s is %s, %s", path, ch->name,
                     ch->subsampled ? "subsampled" : "of unsigned integers", EXPECTED_EXR);
            return GLINT_ERR_INPUT;
        }
        p->known[c] = k;
        p->channels |= 1u << k;
        if (k != KNOWN_DEPTH && k != KNOWN_SAMPLES && ch->type != EXR_CHANNEL_HALF) p->half = false;
    }
    // Whole groups: R, G and B always; the three of albedo and of normal, or none.
    for (int k = 0; k < KNOWN_DEPTH; k += 3) {
        unsigned group = 7u << k, held = p->channels & group;
        if (held == group || (held == 0 && k > 0)) continue;
        int missing = k;
        while (p->channels & (1u << missing)) missing++;
        snprintf(err->message, sizeof err->message, "%s: no channel %s%s, %s", path, KNOWN[missing].name,
                 k == 0 ? "" : " beside the others of its group", EXPECTED_EXR);
        return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

// Decodes an OpenEXR part's channels into the planes of the full image.
static glint_status decode_exr_part(float_part *p, float *const planes[PLANE_COUNT], int full_width,
                                    glint_error *err) {
    exr_channel_target *targets = calloc((size_t)p->info.channel_count + 1u, sizeof *targets);
    if (!targets) {
        snprintf(err->message, sizeof err->message, "merge: out of memory");
        return GLINT_ERR_RENDER;
    }
    for (int c = 0; c < p->info.channel_count; c++) {
        const known_channel *k = &KNOWN[p->known[c]];
        size_t stride = (size_t)plane_stride(k->plane), line = stride * (size_t)full_width;
        size_t at = (size_t)p->region[1] * line + (size_t)p->region[0] * stride + (size_t)k->component;
        targets[c] = (exr_channel_target){planes[k->plane] + at, stride, line};
    }
    glint_status st = exr_part_decode(p->exr, targets, err);
    free(targets);
    return st;
}

// ---- PFM parts ----

// Reads PATH.region beside a PFM part into p's region, and the hash it records of the PFM's bytes.
static glint_status read_region_file(const char *path, float_part *p, uint64_t *hash, glint_error *err) {
    size_t n = strlen(path) + sizeof PFM_REGION_SUFFIX;
    char *side = malloc(n), text[PFM_REGION_MAX_BYTES + 1], region[PFM_REGION_MAX_BYTES];
    if (!side) {
        snprintf(err->message, sizeof err->message, "%s: out of memory", path);
        return GLINT_ERR_RENDER;
    }
    snprintf(side, n, "%s%s", path, PFM_REGION_SUFFIX);
    struct stat st;
    int problem = 0;
    FILE *f = filepath_open_regular(side, &st, &problem);
    glint_status status = !f && problem == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    size_t got = f ? fread(text, 1, sizeof text, f) : 0;
    if (!f && problem == ENOENT)
        snprintf(err->message, sizeof err->message, "%s: no region file %s beside it: a PFM has no room for where a "
                 "region lies, so glint writes it beside the PFM of a region (--region)", path, side);
    else if (!f)
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", side, filepath_problem_text(problem));
    else if (got > PFM_REGION_MAX_BYTES || !pfm_region_split(text, got, region, sizeof region, hash))
        snprintf(err->message, sizeof err->message, "%s: not a region file, expected the two lines glint writes "
                 "beside a region's PFM: glint:region=X0,Y0,X1,Y1,W,H and fnv1a64= with 16 hexadecimal digits", side);
    else if (!merge_parse_region(region, p->region, &p->full_width, &p->full_height))
        snprintf(err->message, sizeof err->message, "%s: glint:region '%.64s' is not X0,Y0,X1,Y1,W,H of a region "
                 "inside a W x H image of at most %d pixels a side", side, region, MERGE_MAX_SIDE);
    else
        status = GLINT_OK;
    if (f) fclose(f);
    free(side);
    return status;
}

// The FNV-1a hash of the whole file f; false when it cannot be read.
static bool hash_file(FILE *f, uint64_t *hash) {
    unsigned char block[1 << 16];
    uint64_t h = HASH_START;
    rewind(f);
    size_t got;
    while ((got = fread(block, 1, sizeof block, f)) > 0) h = hash_bytes(h, block, got);
    *hash = h;
    return !ferror(f);
}

// Reads a PFM part's region file and header, and checks that the region file was written for these bytes.
static glint_status open_pfm_part(FILE *f, const char *path, uint64_t file_size, float_part *p, glint_error *err) {
    uint64_t recorded = 0, actual = 0;
    glint_status st = read_region_file(path, p, &recorded, err);
    if (st != GLINT_OK) return st;
    unsigned char head[PFM_HEADER_MAX_BYTES];
    size_t got = fread(head, 1, sizeof head, f);
    char why[160];
    if (!pfm_parse_header(head, got, &p->pfm, why, sizeof why)) {
        snprintf(err->message, sizeof err->message, "%s: %s, %s", path, why, EXPECTED_PFM);
        return GLINT_ERR_INPUT;
    }
    const pfm_header *h = &p->pfm;
    int w = p->region[2] - p->region[0], hgt = p->region[3] - p->region[1];
    if (h->scale != 1.0 && h->scale != -1.0) {
        snprintf(err->message, sizeof err->message, "%s: its scale is %g, %s (scale 1 or -1: values as they are)",
                 path, h->scale, EXPECTED_PFM);
        return GLINT_ERR_INPUT;
    }
    // The values the header declares must be the rest of the file, before the file is hashed: a short file is
    // truncated, whatever its region file says.
    uint64_t values = (uint64_t)h->width * (uint64_t)h->height * (uint64_t)h->channels * 4u;
    uint64_t held = file_size - h->bytes;
    if (held != values) {
        snprintf(err->message, sizeof err->message, "%s: %s PFM: its %dx%d pixels take %llu bytes after the header, "
                 "the file holds %llu", path, held < values ? "truncated" : "oversized", h->width, h->height,
                 (unsigned long long)values, (unsigned long long)held);
        return GLINT_ERR_INPUT;
    }
    if (!hash_file(f, &actual)) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno ? errno : EIO));
        return GLINT_ERR_INPUT;
    }
    if (actual != recorded) {
        snprintf(err->message, sizeof err->message, "%s: its region file %s%s was written for another file (its "
                 "fnv1a64 %016llx is not the hash of these bytes, %016llx): a part renamed, re-rendered or changed "
                 "without it", path, path, PFM_REGION_SUFFIX, (unsigned long long)recorded, (unsigned long long)actual);
        return GLINT_ERR_INPUT;
    }
    if (h->width != w || h->height != hgt) {
        snprintf(err->message, sizeof err->message, "%s: the image is %dx%d but its region file's region is %dx%d",
                 path, h->width, h->height, w, hgt);
        return GLINT_ERR_INPUT;
    }
    p->channels = h->channels == 3 ? COLOUR_BITS : GREY_BIT;
    p->half = false;
    return GLINT_OK;
}

// Decodes a PFM part's rows (from the bottom up, little- or big-endian) into its plane of the full image.
static glint_status decode_pfm_part(FILE *f, const char *path, const float_part *p, float *const planes[PLANE_COUNT],
                                    int full_width, glint_error *err) {
    const pfm_header *h = &p->pfm;
    size_t n = (size_t)h->width * (size_t)h->channels;
    unsigned char *row = malloc(n * 4u);
    if (!row) {
        snprintf(err->message, sizeof err->message, "merge: out of memory");
        return GLINT_ERR_RENDER;
    }
    float *plane = planes[h->channels == 3 ? PLANE_COLOUR : PLANE_DEPTH];
    bool ok = fseek(f, (long)h->bytes, SEEK_SET) == 0;
    for (int r = 0; ok && r < h->height; r++) {
        ok = fread(row, 4, n, f) == n;
        int y = p->region[1] + h->height - 1 - r;
        float *out = plane + ((size_t)y * (size_t)full_width + (size_t)p->region[0]) * (size_t)h->channels;
        for (size_t i = 0; ok && i < n; i++) {
            const unsigned char *b = row + 4 * i;
            uint32_t bits = h->little_endian
                                ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24
                                : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 | (uint32_t)b[0] << 24;
            memcpy(&out[i], &bits, sizeof bits);
        }
    }
    free(row);
    if (ok) return GLINT_OK;
    // The size was checked: only a file changed while it was read ends early.
    snprintf(err->message, sizeof err->message, "%s: truncated PFM: the file ended while it was read", path);
    return GLINT_ERR_INPUT;
}

// ---- the merge ----

// The planes a set of channels fills: (1 << PLANE_*) bits.
static unsigned planes_of(unsigned channels) {
    unsigned planes = 0;
    for (int k = 0; k < KNOWN_COUNT; k++)
        if (channels & (1u << k)) planes |= 1u << KNOWN[k].plane;
    return planes;
}

// Checks part i against the first (full size, channels) and the output's format; p is part i.
static glint_status check_part(const char *output, image_format format, const char *const *paths, size_t i,
                               const float_part *p, const float_part *first, glint_error *err) {
    if (i > 0 && (p->full_width != first->full_width || p->full_height != first->full_height)) {
        snprintf(err->message, sizeof err->message, "%s: a region of a %dx%d image, but %s is of a %dx%d image",
                 paths[i], p->full_width, p->full_height, paths[0], first->full_width, first->full_height);
        return GLINT_ERR_INPUT;
    }
    if (i > 0 && p->channels != first->channels) {
        // The first channel one holds and the other lacks.
        unsigned diff = p->channels ^ first->channels;
        int k = 0;
        while (!(diff & (1u << k))) k++;
        bool here = (p->channels & (1u << k)) != 0;
        snprintf(err->message, sizeof err->message, "%s: %s channel %s, which %s %s: the parts of a merge hold the "
                 "same channels (rendered with the same --aov, written in the same format)", paths[i],
                 here ? "holds" : "lacks", KNOWN[k].name, paths[0], here ? "lacks" : "holds");
        return GLINT_ERR_INPUT;
    }
    if (i == 0 && (p->channels & GREY_BIT) && format != IMAGE_FORMAT_PFM) {
        snprintf(err->message, sizeof err->message, "%s: %s is a grey PFM (Pf, an AOV such as depth): grey parts "
                 "merge to .pfm alone", output, paths[0]);
        return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

glint_status merge_float(const char *output, image_format format, const char *const *paths, size_t count,
                         merge_kind first_kind, size_t max_bytes, glint_error *err) {
    float_part first = {0};
    merge_cover cover = {0};
    float *planes[PLANE_COUNT] = {NULL};
    bool half = true;
    glint_status st = GLINT_OK;
    for (size_t i = 0; i < count && st == GLINT_OK; i++) {
        struct stat sb;
        merge_kind kind;
        float_part p = {0};
        FILE *f = merge_open(paths[i], &sb, &kind, &st, err);
        if (!f) break;
        if (!merge_kind_float(kind)) st = merge_wrong_kind(paths[i], kind, paths[0], first_kind, err);
        else if (kind == MERGE_EXR) st = open_exr_part(f, paths[i], &p, err);
        else st = open_pfm_part(f, paths[i], (uint64_t)sb.st_size, &p, err);
        if (st == GLINT_OK) st = check_part(output, format, paths, i, &p, &first, err);
        if (st == GLINT_OK && i == 0) {
            first = p;
            first.exr = NULL;
            first.known = NULL;
            // The full image's planes, as floats, and the map of covered pixels: nothing else grows with it.
            unsigned used = planes_of(p.channels);
            uint64_t pixels = (uint64_t)p.full_width * (uint64_t)p.full_height, floats = 0;
            for (int k = 0; k < PLANE_COUNT; k++)
                if (used & (1u << k)) floats += (uint64_t)plane_stride(k);
            uint64_t need = pixels * (floats * sizeof(float) + 1u);
            if (need > max_bytes) {
                snprintf(err->message, sizeof err->message, "%s: a region of a %dx%d image, whose merge would take "
                         "%llu bytes, more than the %zu allowed", paths[i], p.full_width, p.full_height,
                         (unsigned long long)need, max_bytes);
                st = GLINT_ERR_INPUT;
            }
            bool ok = st == GLINT_OK && merge_cover_init(&cover, p.full_width, p.full_height, count);
            for (int k = 0; ok && k < PLANE_COUNT; k++)
                if (used & (1u << k)) ok = (planes[k] = calloc(pixels * (uint64_t)plane_stride(k), sizeof(float)));
            if (st == GLINT_OK && !ok) {
                snprintf(err->message, sizeof err->message, "merge: out of memory for a %dx%d image of %llu float "
                         "channels (%llu bytes)", p.full_width, p.full_height, (unsigned long long)floats,
                         (unsigned long long)need);
                st = GLINT_ERR_RENDER;
            }
        }
        if (st == GLINT_OK) st = merge_cover_claim(&cover, paths, i, p.region, err);
        if (st == GLINT_OK && kind == MERGE_EXR) st = decode_exr_part(&p, planes, cover.width, err);
        if (st == GLINT_OK && kind == MERGE_PFM) st = decode_pfm_part(f, paths[i], &p, planes, cover.width, err);
        half = half && p.half;
        exr_part_close(p.exr);
        free(p.known);
        fclose(f);
    }
    if (st == GLINT_OK) st = merge_cover_check_gaps(&cover, err);
    if (st == GLINT_OK) {
        // The merged image: a whole image, so no region file is written beside a PFM of it.
        glint_image img = {.width = cover.width, .height = cover.height, .rgb = planes[PLANE_COLOUR],
                           .transform = TRANSFORM_LINEAR, .full_width = cover.width, .full_height = cover.height};
        for (int a = 0; a < FILM_AOV_COUNT; a++) img.aov[a] = planes[a + 1];
        if (first.channels & GREY_BIT) st = image_write_aov(&img, FILM_AOV_DEPTH, output, err);
        else if (format == IMAGE_FORMAT_EXR) st = image_write(&img, output, half ? IMAGE_FORMAT_EXR_HALF : format, err);
        else st = image_write(&img, output, format, err);
    }
    merge_cover_free(&cover);
    for (int k = 0; k < PLANE_COUNT; k++) free(planes[k]);
    return st;
}
