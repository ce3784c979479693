// image_read.h — decoding PNG and JPEG (baseline and progressive) files into linear RGB floats.
#ifndef GLINT_IMAGE_READ_H
#define GLINT_IMAGE_READ_H

#include "glint.h"
#include "core/image_rgb.h"

#include <stddef.h>

/// Largest image accepted, in pixels (8192 x 8192): a texture must not exhaust memory.
#define IMAGE_READ_MAX_PIXELS ((size_t)1 << 26)

/// Reads a PNG or JPEG file (recognised by its first bytes, not its name), decodes sRGB to linear.
/// On failure returns GLINT_ERR_INPUT with "path: what is wrong" in *err and leaves *out empty.
glint_status image_read(const char *path, image_rgb *out, glint_error *err);
/// The same from memory; `name` is used in messages.
glint_status image_read_memory(const char *name, const unsigned char *data, size_t size, image_rgb *out,
                               glint_error *err);
/// The linear value of an 8-bit sRGB-encoded component (the exact sRGB curve).
float image_srgb_to_linear(unsigned char c);

#endif
