// hdr_read.h — reading Radiance RGBE (.hdr) images into linear RGB floats, through stb_image (Debian's
// libstb-dev), for environment maps.
#ifndef GLINT_HDR_READ_H
#define GLINT_HDR_READ_H

#include "glint.h"
#include "core/image_rgb.h"

#include <stdbool.h>
#include <stddef.h>

/// Largest environment map accepted, in pixels (16384 x 8192, 1.5 GiB of floats): a file must not exhaust memory.
#define HDR_READ_MAX_PIXELS ((size_t)1 << 27)

/// Whether the first bytes of a file are a Radiance signature ("#?RADIANCE" or "#?RGBE").
bool hdr_read_is_radiance(const unsigned char *head, size_t size);
/// Reads a Radiance .hdr file (recognised by its "#?RADIANCE" or "#?RGBE" signature). On failure returns
/// GLINT_ERR_INPUT ("path: what is wrong"; GLINT_ERR_RENDER when memory runs out) and leaves *out empty.
glint_status hdr_read(const char *path, image_rgb *out, glint_error *err);

#endif
