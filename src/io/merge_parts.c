// merge_parts.c — what both halves of glint merge share (merge_parts.h): the kinds of part and opening one,
// the region text, and the map of the pixels the parts placed so far.
#include "io/merge_parts.h"
#include "core/filepath.h"
#include "io/exr_read.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

// A decimal integer in [0, INT_MAX] at *p, advanced past it; false when there is none or it is larger.
static bool parse_int(const char **p, int *out) {
    if (**p < '0' || **p > '9') return false;
    long long v = 0;
    for (; **p >= '0' && **p <= '9'; (*p)++)
        if ((v = v * 10 + (**p - '0')) > INT_MAX) return false;
    *out = (int)v;
    return true;
}

bool merge_parse_region(const char *text, int region[4], int *full_width, int *full_height) {
    int v[6];
    for (int i = 0; i < 6; i++)
        if (!parse_int(&text, &v[i]) || *text++ != (i < 5 ? ',' : '\0')) return false;
    memcpy(region, v, 4 * sizeof *region);
    *full_width = v[4];
    *full_height = v[5];
    return v[0] < v[2] && v[1] < v[3] && v[2] <= v[4] && v[3] <= v[5] && v[4] <= MERGE_MAX_SIDE && v[5] <= MERGE_MAX_SIDE;
}

const char *merge_kind_name(merge_kind kind) {
    switch (kind) {
    case MERGE_PNG: return "an 8-bit PNG part";
    case MERGE_EXR: return "a float OpenEXR part";
    case MERGE_PFM: return "a float PFM part";
    case MERGE_PPM: return "a PPM";
    case MERGE_HDR: return "a Radiance .hdr";
    case MERGE_UNKNOWN: break;
    }
    return "not a region part";
}

bool merge_kind_float(merge_kind kind) { return kind == MERGE_EXR || kind == MERGE_PFM; }

// The kind of a file by its first bytes (size of them).
static merge_kind kind_of(const unsigned char *head, size_t size) {
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    bool space = size >= 3 && (head[2] == ' ' || head[2] == '\t' || head[2] == '\n' || head[2] == '\r');
    if (size >= 8 && memcmp(head, png, 8) == 0) return MERGE_PNG;
    if (exr_read_is_exr(head, size)) return MERGE_EXR;
    if (space && head[0] == 'P' && (head[1] == 'F' || head[1] == 'f')) return MERGE_PFM;
    if (space && head[0] == 'P' && (head[1] == '6' || head[1] == '3')) return MERGE_PPM;
    if ((size >= 10 && memcmp(head, "#?RADIANCE", 10) == 0) || (size >= 6 && memcmp(head, "#?RGBE", 6) == 0))
        return MERGE_HDR;
    return MERGE_UNKNOWN;
}

FILE *merge_open(const char *path, struct stat *st, merge_kind *kind, glint_status *status, glint_error *err) {
    int problem = 0;
    FILE *f = filepath_open_regular(path, st, &problem);
    if (!f) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, filepath_problem_text(problem));
        *status = problem == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
        return NULL;
    }
    unsigned char head[16];
    size_t got = fread(head, 1, sizeof head, f);
    rewind(f);
    *kind = kind_of(head, got);
    *status = GLINT_OK;
    return f;
}

glint_status merge_wrong_kind(const char *path, merge_kind kind, const char *first_path, merge_kind first,
                              glint_error *err) {
    if (kind == MERGE_UNKNOWN || kind == MERGE_PPM || kind == MERGE_HDR)
        snprintf(err->message, sizeof err->message, "%s: %s%s, expected a PNG, OpenEXR or PFM file written by glint "
                 "with --region", path, merge_kind_name(kind),
                 kind == MERGE_UNKNOWN ? "" : ", which has no room for where a region lies");
    else
        snprintf(err->message, sizeof err->message, "%s: %s, but %s is %s: a merge takes 8-bit parts (to .png or "
                 ".ppm) or float parts (to .exr, .pfm or .hdr), not both", path, merge_kind_name(kind), first_path,
                 merge_kind_name(first));
    return GLINT_ERR_INPUT;
}

bool merge_cover_init(merge_cover *c, int width, int height, size_t count) {
    c->width = width;
    c->height = height;
    c->covered = calloc((size_t)width * (size_t)height, 1);
    c->regions = calloc(count, sizeof *c->regions);
    return c->covered && c->regions;
}

void merge_cover_free(merge_cover *c) {
    free(c->covered);
    free(c->regions);
    c->covered = NULL;
    c->regions = NULL;
}

static bool region_contains(const int r[4], int x, int y) { return x >= r[0] && x < r[2] && y >= r[1] && y < r[3]; }

glint_status merge_cover_claim(merge_cover *c, const char *const *paths, size_t i, const int region[4],
                               glint_error *err) {
    memcpy(c->regions[i], region, sizeof c->regions[i]);
    size_t w = (size_t)(region[2] - region[0]);
    for (int y = region[1]; y < region[3]; y++) {
        const uint8_t *row = c->covered + (size_t)y * (size_t)c->width + (size_t)region[0];
        const uint8_t *hit = memchr(row, 1, w);
        if (!hit) continue;
        int x = region[0] + (int)(hit - row);
        size_t j = 0;
        while (j < i && !region_contains(c->regions[j], x, y)) j++;
        snprintf(err->message, sizeof err->message, "%s: overlaps %s at pixel (%d, %d)", paths[i], paths[j], x, y);
        return GLINT_ERR_INPUT;
    }
    for (int y = region[1]; y < region[3]; y++)
        memset(c->covered + (size_t)y * (size_t)c->width + (size_t)region[0], 1, w);
    return GLINT_OK;
}

glint_status merge_cover_check_gaps(const merge_cover *c, glint_error *err) {
    size_t n = (size_t)c->width * (size_t)c->height;
    const uint8_t *gap = memchr(c->covered, 0, n);
    if (!gap) return GLINT_OK;
    size_t first = (size_t)(gap - c->covered), missing = 0;
    for (size_t i = first; i < n; i++) missing += !c->covered[i];
    snprintf(err->message, sizeof err->message, "no part covers pixel (%zu, %zu) of the %dx%d image (%zu pixels "
             "missing)", first % (size_t)c->width, first / (size_t)c->width, c->width, c->height, missing);
    return GLINT_ERR_INPUT;
}
