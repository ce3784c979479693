// pfm_region.c — the PFM header as glint merge reads it, and the text of the region file beside a region's PFM.
#include "io/pfm_region.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char REGION_KEY[] = "glint:region=";
static const char HASH_KEY[] = "fnv1a64=";

int pfm_region_text(char *buf, size_t size, const int region[4], int full_width, int full_height, uint64_t hash) {
    return snprintf(buf, size, "%s%d,%d,%d,%d,%d,%d\n%s%016" PRIx64 "\n", REGION_KEY, region[0], region[1], region[2],
                    region[3], full_width, full_height, HASH_KEY, hash);
}

bool pfm_region_split(const char *text, size_t size, char *region, size_t region_size, uint64_t *hash) {
    size_t key = sizeof REGION_KEY - 1, hkey = sizeof HASH_KEY - 1;
    if (size < key || memcmp(text, REGION_KEY, key) != 0) return false;
    const char *start = text + key, *end = text + size;
    const char *nl = memchr(start, '\n', (size_t)(end - start));
    if (!nl || (size_t)(nl - start) >= region_size || memchr(start, '\0', (size_t)(nl - start))) return false;
    memcpy(region, start, (size_t)(nl - start));
    region[nl - start] = '\0';
    const char *h = nl + 1;
    // Exactly "fnv1a64=" and 16 lowercase hexadecimal digits, a newline, and nothing after it.
    if ((size_t)(end - h) != hkey + 17 || memcmp(h, HASH_KEY, hkey) != 0 || h[hkey + 16] != '\n') return false;
    uint64_t v = 0;
    for (size_t i = 0; i < 16; i++) {
        char c = h[hkey + i];
        int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
        if (d < 0) return false;
        v = v << 4 | (uint64_t)d;
    }
    *hash = v;
    return true;
}

static bool is_space(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// A decimal integer in [1, INT_MAX] at head[*at], advanced past it and the whitespace after it (at least one).
static bool parse_size(const unsigned char *head, size_t size, size_t *at, int *out) {
    long long v = 0;
    size_t start = *at;
    for (; *at < size && head[*at] >= '0' && head[*at] <= '9'; (*at)++)
        if ((v = v * 10 + (head[*at] - '0')) > INT_MAX) return false;
    if (*at == start || v == 0 || *at >= size || !is_space(head[*at])) return false;
    while (*at < size && is_space(head[*at])) (*at)++;
    *out = (int)v;
    return true;
}

bool pfm_parse_header(const unsigned char *head, size_t size, pfm_header *h, char *why, size_t why_size) {
    memset(h, 0, sizeof *h);
    if (size > PFM_HEADER_MAX_BYTES) size = PFM_HEADER_MAX_BYTES;
    if (size < 3 || head[0] != 'P' || (head[1] != 'F' && head[1] != 'f') || !is_space(head[2])) {
        snprintf(why, why_size, "not a PFM file (expected \"PF\" or \"Pf\" and a newline first)");
        return false;
    }
    h->channels = head[1] == 'F' ? 3 : 1;
    size_t at = 2;
    while (at < size && is_space(head[at])) at++;
    if (!parse_size(head, size, &at, &h->width) || !parse_size(head, size, &at, &h->height)) {
        snprintf(why, why_size, "its header has no width and height (expected two positive integers after \"P%c\")",
                 head[1]);
        return false;
    }
    // The scale: a decimal number, then exactly one whitespace byte before the values.
    char number[PFM_HEADER_MAX_BYTES + 1];
    size_t n = 0;
    for (; at < size && strchr("0123456789+-.eE", head[at]) && head[at]; at++) number[n++] = (char)head[at];
    number[n] = '\0';
    char *end = NULL;
    errno = 0;
    h->scale = n ? strtod(number, &end) : 0.0;
    if (n == 0 || *end != '\0' || errno != 0 || !isfinite(h->scale) || h->scale == 0.0 || at >= size ||
        !is_space(head[at])) {
        snprintf(why, why_size, "its header has no scale (expected a non-zero number and a newline after the size)");
        return false;
    }
    h->little_endian = h->scale < 0.0;
    h->bytes = at + 1;
    return true;
}
