// image_write.h — writing a rendered image as PNG (libpng), binary or ASCII PPM, or PFM: through an unnamed
// temporary file linked into place, so that a failed, interrupted or killed write never leaves a file behind.
#ifndef GLINT_IMAGE_WRITE_H
#define GLINT_IMAGE_WRITE_H

#include "core/status.h"
#include "film/film.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/// The PNG tEXt keyword under which a region's image records "X0,Y0,X1,Y1,W,H" (W x H: the full image).
#define IMAGE_REGION_KEY "glint:region"

/// Image file formats, as glint_format lists them (the API converts; the values are the same).
typedef enum image_format {
    IMAGE_FORMAT_AUTO, ///< from the path's extension
    IMAGE_FORMAT_PNG,
    IMAGE_FORMAT_PPM,
    IMAGE_FORMAT_PPM_ASCII,
    IMAGE_FORMAT_PFM,
    IMAGE_FORMAT_EXR,
    IMAGE_FORMAT_EXR_HALF,
    IMAGE_FORMAT_HDR
} image_format;

/// The format a path's extension names ("-": PPM), IMAGE_FORMAT_AUTO when it names none.
image_format image_format_of(const char *path);
/// Writes img to path in the format (IMAGE_FORMAT_AUTO: from the extension); "-" writes PPM to standard output.
glint_status image_write(const glint_image *img, const char *path, image_format format, glint_error *err);
/// Writes AOV plane `aov` (FILM_AOV_*) of img to the .pfm file path ("PF" for albedo and normal, "Pf" for depth),
/// as image_write writes files; GLINT_ERR_INPUT for another extension or an AOV the image lacks.
glint_status image_write_aov(const glint_image *img, int aov, const char *path, glint_error *err);
/// Writes 8-bit RGB rows (3 bytes a pixel, row 0 at the top) that encode light by `transform`, as .png (with
/// the colour chunks that say so) or .ppm, chosen by the extension ("-": PPM on standard output), as image_write
/// writes files. GLINT_ERR_INPUT for another format: a float file would hold the bytes as if they were light.
glint_status image_write_rgb8(const uint8_t *rgb, int width, int height, output_transform transform,
                              const char *path, glint_error *err);
/// Checks before a render that an image can be written at path: GLINT_ERR_INPUT for an unknown extension,
/// GLINT_ERR_RENDER ("PATH: cannot write: reason") for a missing or unwritable directory or a read-only file.
glint_status image_check_path(const char *path, image_format format, glint_error *err);

/// Fills the open file f with what user describes: 0, an errno value, or -1 with the reason in why.
typedef int (*image_file_writer)(FILE *f, const void *user, char *why, size_t why_size);
/// Writes any file as images are written (the same path checks, the temporary file linked into place, nothing
/// left behind on failure): `fill` fills it. GLINT_ERR_RENDER ("PATH: cannot write: reason") on failure.
glint_status image_write_file(const char *path, image_file_writer fill, const void *user, glint_error *err);
/// image_check_path for a file of any kind: GLINT_ERR_RENDER ("PATH: cannot write: reason") for a missing or
/// unwritable directory or a read-only file.
glint_status image_check_file(const char *path, glint_error *err);

#endif
