// image_read.h — decoding PNG and JPEG (baseline and progressive) files into linear RGB floats.
#ifndef GLINT_IMAGE_READ_H
#define GLINT_IMAGE_READ_H

#include "core/status.h"
#include "core/image_rgb.h"

#include <stddef.h>

/// Largest image accepted, in pixels (2^24: 16 M, e.g. 8192 x 2048 or 4096 x 4096), checked against the
/// size the file declares before anything is allocated: decoding takes up to 20 bytes per pixel (linear
/// RGB floats, a float alpha plane when the PNG has one, and its 8-bit RGBA copy), 320 MiB at the limit.
#define IMAGE_READ_MAX_PIXELS ((size_t)1 << 24)
/// Largest image file read, in bytes (256 MiB): more than any PNG or JPEG within the pixel limit needs.
#define IMAGE_READ_MAX_FILE_BYTES ((size_t)256 << 20)

/// How 8-bit values become linear floats: through the sRGB curve (what image files mean), or byte / 255 (what
/// some programs do, e.g. book 2's earth texture).
typedef enum image_decode { IMAGE_DECODE_SRGB, IMAGE_DECODE_LINEAR } image_decode;

/// Reads a PNG or JPEG file (recognised by its first bytes, not its name) into floats as `decode` says; a PNG's
/// alpha channel (linear, byte / 255) goes to out->alpha unless it is opaque everywhere.
/// On failure returns GLINT_ERR_INPUT with "path: what is wrong" in *err and leaves *out empty;
/// GLINT_ERR_RENDER with "path: out of memory ..." when memory runs out.
glint_status image_read(const char *path, image_decode decode, image_rgb *out, glint_error *err);
/// The same from memory; `name` is used in messages.
glint_status image_read_memory(const char *name, const unsigned char *data, size_t size, image_decode decode,
                               image_rgb *out, glint_error *err);
/// The linear value of an 8-bit sRGB-encoded component (the exact sRGB curve).
float image_srgb_to_linear(unsigned char c);

#endif
