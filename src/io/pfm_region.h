// pfm_region.h — what glint merge needs of PFM parts: the PFM header, and the region file glint writes beside the
// PFM of a region (PFM has no room for an offset or a comment): PATH.region holds where the image lies and the
// FNV-1a hash of the PFM's bytes, so that a region file left beside another PFM (renamed, re-rendered, written by
// another program) is refused rather than placing pixels where they do not belong.
#ifndef GLINT_PFM_REGION_H
#define GLINT_PFM_REGION_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// What is appended to a region PFM's path to name the region file beside it: "part.pfm" -> "part.pfm.region".
#define PFM_REGION_SUFFIX ".region"
/// The largest region file read: its two lines take at most 103 bytes.
#define PFM_REGION_MAX_BYTES 128

/// The region file's text: "glint:region=X0,Y0,X1,Y1,W,H\nfnv1a64=HASH\n" (W x H: the full image; HASH: the
/// 64-bit FNV-1a hash of the PFM file's bytes as 16 lowercase hexadecimal digits). Returns snprintf's count.
int pfm_region_text(char *buf, size_t size, const int region[4], int full_width, int full_height, uint64_t hash);
/// Splits a region file's text (size bytes, not NUL-terminated) into its region text ("X0,Y0,X1,Y1,W,H", copied
/// NUL-terminated into region, at most region_size - 1 bytes) and its hash; false when it is not exactly the two
/// lines pfm_region_text writes.
bool pfm_region_split(const char *text, size_t size, char *region, size_t region_size, uint64_t *hash);

/// A PFM header: "PF" (RGB) or "Pf" (grey), the width, the height and the scale (negative: little-endian
/// values), separated by whitespace, one whitespace byte after the scale, then the rows from the bottom up.
typedef struct pfm_header {
    int width, height;
    int channels;        ///< 3 for "PF", 1 for "Pf"
    bool little_endian;  ///< the scale is negative
    double scale;
    size_t bytes;        ///< the header's length: where the values begin
} pfm_header;

/// The longest header pfm_parse_header reads.
#define PFM_HEADER_MAX_BYTES 64

/// Parses the header at the start of head (size bytes of the file). false, with what is wrong in why, when it is
/// not a PFM header (or longer than PFM_HEADER_MAX_BYTES, or its numbers are out of range).
bool pfm_parse_header(const unsigned char *head, size_t size, pfm_header *h, char *why, size_t why_size);

#endif
