// exr_read.h — reading OpenEXR images (scanline or tiled, any compression, half/float/uint channels) into
// linear RGB floats through OpenEXR's core C API (Debian's libopenexr-dev), for environment maps. Files are
// opened, checked and told apart by io/map_read.h.
#ifndef GLINT_EXR_READ_H
#define GLINT_EXR_READ_H

#include "core/image_rgb.h"
#include "io/map_read.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/// Whether the first bytes of a file are OpenEXR's magic number (0x76, 0x2f, 0x31, 0x01).
bool exr_read_is_exr(const unsigned char *head, size_t size);

/// Reads the first part of the OpenEXR file open as f (read through its descriptor, from any position; path
/// names it in messages): its data window's R, G and B channels, or a Y channel alone as grey (a Y beside R, G
/// and B is ignored); half, float or uint channels; scanline or tiled (the full-resolution level); at most
/// MAP_READ_MAX_PIXELS. On failure returns GLINT_ERR_INPUT ("path: what is wrong"; GLINT_ERR_RENDER when memory
/// runs out) and leaves *out empty.
glint_status exr_read_open(FILE *f, const char *path, image_rgb *out, glint_error *err);

#endif
