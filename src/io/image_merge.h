// image_merge.h — assembling the PNG files of rendered regions into the full image (glint merge).
#ifndef GLINT_IMAGE_MERGE_H
#define GLINT_IMAGE_MERGE_H

#include "core/status.h"

#include <stddef.h>

/// Reads the region PNGs `parts` (each with its IMAGE_REGION_KEY chunk), checks that they tile one full image
/// exactly, and writes it to output (.png or .ppm) with the parts' 8-bit values. GLINT_ERR_INPUT naming the
/// part for a bad part, a different full size, an overlap or a gap; GLINT_ERR_RENDER for memory and writing.
glint_status image_merge(const char *output, const char *const *parts, size_t count, glint_error *err);

#endif
