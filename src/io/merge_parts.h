// merge_parts.h — what the two halves of glint merge share (io/image_merge.c: the driver and 8-bit PNG parts;
// io/merge_float.c: OpenEXR and PFM parts): the kinds of part, opening one, reading a region's text, and the map
// of the pixels the parts placed so far (overlaps and gaps).
#ifndef GLINT_MERGE_PARTS_H
#define GLINT_MERGE_PARTS_H

#include "core/status.h"
#include "io/image_write.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/stat.h>

/// The largest width and height a scene renders at: no part may claim a larger full image.
enum { MERGE_MAX_SIDE = 16384 };

/// What a part's first bytes say it is.
typedef enum merge_kind {
    MERGE_UNKNOWN, ///< none of the below
    MERGE_PNG,     ///< 8-bit: placed by its glint:region chunk
    MERGE_EXR,     ///< float: placed by its data window
    MERGE_PFM,     ///< float: placed by its region file
    MERGE_PPM,     ///< no room for a position: refused by name
    MERGE_HDR      ///< likewise
} merge_kind;

/// What a kind of part is called in messages ("an 8-bit PNG part", "a float OpenEXR part", ...).
const char *merge_kind_name(merge_kind kind);
/// Whether parts of this kind hold floats (OpenEXR, PFM).
bool merge_kind_float(merge_kind kind);

/// Opens a part (a regular file, checked on the descriptor) and tells its kind by its first bytes; the file is
/// left at its start. NULL with "PATH: cannot read: why" otherwise (*status GLINT_ERR_RENDER when memory ran
/// out, else GLINT_ERR_INPUT).
FILE *merge_open(const char *path, struct stat *st, merge_kind *kind, glint_status *status, glint_error *err);

/// The message, and GLINT_ERR_INPUT, for part `path` of kind `kind` that cannot join parts of kind `first` (the
/// kind of the part `first_path`): 8-bit and float parts together, or a file that is no region part at all.
glint_status merge_wrong_kind(const char *path, merge_kind kind, const char *first_path, merge_kind first,
                              glint_error *err);

/// Parses "X0,Y0,X1,Y1,W,H" strictly (six decimal integers, nothing else) into region and the full size; false
/// when it is not that, or not a non-empty region inside a W x H image of at most MERGE_MAX_SIDE a side.
bool merge_parse_region(const char *text, int region[4], int *full_width, int *full_height);

/// The pixels of a full image the parts placed so far.
typedef struct merge_cover {
    int width, height;
    uint8_t *covered;  ///< width * height flags
    int (*regions)[4]; ///< every part's region, for naming the part another overlaps
} merge_cover;

/// A cover of a width x height image for count parts; false when out of memory.
bool merge_cover_init(merge_cover *c, int width, int height, size_t count);
void merge_cover_free(merge_cover *c);
/// Places part i (paths[i]) at region: GLINT_ERR_INPUT naming the earlier part it overlaps, and the first pixel
/// (in row order) that both cover.
glint_status merge_cover_claim(merge_cover *c, const char *const *paths, size_t i, const int region[4],
                               glint_error *err);
/// GLINT_ERR_INPUT naming the first pixel (in row order) that no part covers, if any.
glint_status merge_cover_check_gaps(const merge_cover *c, glint_error *err);

#endif
