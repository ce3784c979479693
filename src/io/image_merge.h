// image_merge.h — assembling the files of rendered regions into the full image (glint merge): 8-bit PNG parts
// into PNG or PPM, float parts (OpenEXR, or PFM with their region files) into OpenEXR, PFM or Radiance HDR.
#ifndef GLINT_IMAGE_MERGE_H
#define GLINT_IMAGE_MERGE_H

#include "core/status.h"

#include <stddef.h>

/// Reads the region files `parts`, checks that they tile one full image exactly, and writes it to output:
/// PNG parts (each with its IMAGE_REGION_KEY chunk) to .png or .ppm with their 8-bit values; OpenEXR parts
/// (placed by their data windows) and PFM parts (placed by their region files, PATH.region) to .exr, .pfm or .hdr
/// with their float values. GLINT_ERR_INPUT naming the part for a bad part, 8-bit and float parts together, an
/// output of the other kind, a different full size or set of channels, an overlap or a gap; GLINT_ERR_RENDER for
/// memory and writing.
glint_status image_merge(const char *output, const char *const *parts, size_t count, glint_error *err);

/// image_merge, refusing (GLINT_ERR_INPUT) a merge whose full image would take more than max_bytes (the parts'
/// pixels and the map of covered pixels): for tests and fuzzing, where a forged part must not take gigabytes.
glint_status image_merge_limited(const char *output, const char *const *parts, size_t count, size_t max_bytes,
                                 glint_error *err);

#endif
