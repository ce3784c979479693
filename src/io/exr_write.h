// exr_write.h — OpenEXR output through the library's C API (Debian's libopenexr-dev, openexr.h): linear RGB
// as 32-bit float or 16-bit half channels "R", "G", "B", and the image's AOVs as "albedo.R/G/B", "normal.X/Y/Z"
// and "Z" (always 32-bit), ZIP-compressed scanlines; a region's data window lies inside the full display window.
#ifndef GLINT_EXR_WRITE_H
#define GLINT_EXR_WRITE_H

#include "core/status.h"
#include "film/film.h"

#include <stdbool.h>
#include <stdio.h>

/// Writes img to the open, seekable file f as an EXR (half: 16-bit channels, else 32-bit float). 0 on success,
/// else an errno value, with what went wrong in why.
int exr_write(FILE *f, const glint_image *img, bool half, char *why, size_t why_size);

#endif
