// image_rgb.h — a decoded image in memory (linear RGB floats): what image files decode to and image
// textures sample, so that textures need not know about files.
#ifndef GLINT_IMAGE_RGB_H
#define GLINT_IMAGE_RGB_H

/// A decoded image: width x height pixels of linear RGB (3 floats each), row 0 at the top.
typedef struct image_rgb {
    int width, height;
    float *pixels; ///< owned; NULL for an empty image
} image_rgb;

/// Frees the pixels and leaves an empty image.
void image_rgb_free(image_rgb *img);

#endif
