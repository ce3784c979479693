// merge_float.h — glint merge's float half: OpenEXR parts (placed by their data windows) and PFM parts (by their
// region files) assembled into .exr, .pfm or .hdr (merge_float.c); image_merge.c hands such parts over.
#ifndef GLINT_MERGE_FLOAT_H
#define GLINT_MERGE_FLOAT_H

#include "io/merge_parts.h"

/// Assembles float parts (the first of kind first_kind) into output, in format (IMAGE_FORMAT_EXR, _PFM or _HDR),
/// as image_merge_limited says.
glint_status merge_float(const char *output, image_format format, const char *const *paths, size_t count,
                         merge_kind first_kind, size_t max_bytes, glint_error *err);

#endif
