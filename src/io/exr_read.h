// exr_read.h — reading OpenEXR images (scanline or tiled, any compression, half/float/uint channels) through
// OpenEXR's core C API (Debian's libopenexr-dev): linear RGB floats for environment maps (exr_read_open; files are
// opened, checked and told apart by io/map_read.h), and any channels at their data window's place for
// glint merge (exr_part_*). Both read through the descriptor of a file the caller opened and checked, and check
// the header before anything is allocated and every chunk against the file's size before it is decoded.
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

/// How a channel stores its values.
typedef enum exr_channel_type { EXR_CHANNEL_UINT, EXR_CHANNEL_HALF, EXR_CHANNEL_FLOAT } exr_channel_type;

/// One channel of an open file's first part.
typedef struct exr_channel {
    const char *name;      ///< valid while the file is open
    exr_channel_type type;
    bool subsampled;       ///< fewer samples than pixels along x or y
} exr_channel;

/// The header of an open file's first part. Windows are X0, Y0, X1, Y1 with X1 and Y1 exclusive.
typedef struct exr_part_info {
    int parts;                 ///< the parts the file holds (only the first is read)
    int display[4];            ///< the display window: the full image
    int data[4];               ///< the data window: the pixels the file holds
    int channel_count;
    const exr_channel *channels; ///< channel_count of them, in the file's (sorted) order
} exr_part_info;

/// Opaque: an OpenEXR file open for exr_part_decode.
typedef struct exr_part exr_part;

/// Opens the OpenEXR file open as f (read through its descriptor; path names it in messages) and checks its
/// first part's header: flat storage (scanline or tiled), a data window of 1 to max_pixels pixels. Fills *info.
/// On failure returns GLINT_ERR_INPUT ("path: what is wrong"; GLINT_ERR_RENDER when memory runs out), *out NULL.
glint_status exr_part_open(FILE *f, const char *path, size_t max_pixels, exr_part **out, exr_part_info *info,
                           glint_error *err);

/// Where the values of one channel go, as floats: data-window pixel (x, y) at base[y * line_stride + x *
/// pixel_stride] (strides in floats). A NULL base skips the channel.
typedef struct exr_channel_target {
    float *base;
    size_t pixel_stride, line_stride;
} exr_channel_target;

/// Decodes every chunk of the first part (blocks of scanlines, or the tiles of the full-resolution level), each
/// checked to lie inside the data window and the file, channel i into targets[i] (half and uint converted to
/// float exactly). GLINT_ERR_INPUT ("path: corrupt OpenEXR data: why") for a damaged or truncated file.
glint_status exr_part_decode(exr_part *p, const exr_channel_target *targets, glint_error *err);

/// Closes the file's reader (the FILE stays open); NULL is allowed.
void exr_part_close(exr_part *p);

#endif
