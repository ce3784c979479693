// hdr_read.h — reading Radiance RGBE (.hdr) images into linear RGB floats, through stb_image (Debian's
// libstb-dev), for environment maps. Files are opened, checked and told apart by io/map_read.h.
#ifndef GLINT_HDR_READ_H
#define GLINT_HDR_READ_H

#include "core/image_rgb.h"
#include "io/map_read.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/// Whether the first bytes of a file are a Radiance signature ("#?RADIANCE" or "#?RGBE").
bool hdr_read_is_radiance(const unsigned char *head, size_t size);
/// Reads the Radiance .hdr file open as f, from its start (path names it in messages): header and pixel stream
/// are checked whole before anything is decoded or allocated, at most MAP_READ_MAX_PIXELS. On failure returns
/// GLINT_ERR_INPUT ("path: what is wrong": truncated, corrupt run lengths, an unsupported orientation or format,
/// too large; GLINT_ERR_RENDER when memory runs out) and leaves *out empty.
glint_status hdr_read_open(FILE *f, const char *path, image_rgb *out, glint_error *err);

#endif
