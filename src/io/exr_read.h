// exr_read.h — reading OpenEXR images (scanline or tiled, any compression, half/float/uint channels) into
// linear RGB floats through OpenEXR's core C API (Debian's libopenexr-dev), for environment maps.
#ifndef GLINT_EXR_READ_H
#define GLINT_EXR_READ_H

#include "glint.h"
#include "core/image_rgb.h"

#include <stdbool.h>
#include <stddef.h>

/// Largest image accepted, in pixels (as hdr_read): a file must not exhaust memory.
#define EXR_READ_MAX_PIXELS ((size_t)1 << 27)

/// Whether the first bytes of a file are OpenEXR's magic number (0x76, 0x2f, 0x31, 0x01).
bool exr_read_is_exr(const unsigned char *head, size_t size);

/// Reads the first part of an OpenEXR file: its data window's R, G and B channels (a Y-only file is grey);
/// the channels may be half, float or uint, the part scanline or tiled (the full-resolution level). On
/// failure returns GLINT_ERR_INPUT ("path: what is wrong"; GLINT_ERR_RENDER when memory runs out) and
/// leaves *out empty.
glint_status exr_read(const char *path, image_rgb *out, glint_error *err);

#endif
