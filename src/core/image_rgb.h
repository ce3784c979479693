// image_rgb.h — a decoded image in memory (linear RGB floats, and alpha where the file has it): what image files decode to and image
// textures sample, so that textures need not know about files.
#ifndef GLINT_IMAGE_RGB_H
#define GLINT_IMAGE_RGB_H

/// A decoded image: width x height pixels of linear RGB (3 floats each), row 0 at the top, and the coverage of
/// each pixel (alpha, 1 float each) when the file has a channel for it that is not 1 everywhere.
typedef struct image_rgb {
    int width, height;
    float *pixels; ///< owned; NULL for an empty image
    float *alpha;  ///< owned, width x height values in [0, 1] (never premultiplied into pixels); NULL: opaque
} image_rgb;

/// Frees the pixels and the alpha plane and leaves an empty image.
void image_rgb_free(image_rgb *img);

#endif
