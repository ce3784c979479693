// map_read.h — high-dynamic-range images for environment maps: the file is opened once (a regular file,
// checked on the opened descriptor), its type told by its first bytes, and read by exr_read or hdr_read.
#ifndef GLINT_MAP_READ_H
#define GLINT_MAP_READ_H

#include "core/status.h"
#include "core/image_rgb.h"

/// Largest map accepted, in pixels (16384 x 8192: 1.5 GiB of floats): a file must not exhaust memory.
#define MAP_READ_MAX_PIXELS ((size_t)1 << 27)

/// Which formats a read accepts.
typedef enum map_kind { MAP_ANY, MAP_EXR, MAP_HDR } map_kind;

/// Reads the OpenEXR or Radiance .hdr image at path (told apart by the first bytes, not the name; `kind` may
/// insist on one) into linear RGB floats. On failure returns GLINT_ERR_INPUT ("path: what is wrong": cannot
/// open, not a regular file, not such an image, truncated or corrupt, too large; GLINT_ERR_RENDER when memory
/// runs out) and leaves *out empty.
glint_status map_read(const char *path, map_kind kind, image_rgb *out, glint_error *err);

#endif
