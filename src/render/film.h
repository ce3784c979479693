// film.h — the image being rendered: linear RGB per pixel, and its display encoding.
#ifndef GLINT_FILM_H
#define GLINT_FILM_H

#include "glint.h"
#include "scene/scene.h"

#include <stdint.h>

struct glint_image {
    int width, height;
    float *rgb;                 ///< linear RGB, 3 floats a pixel, row 0 at the top
    output_transform transform; ///< how rgb becomes 8-bit values
};

/// A black image; NULL when out of memory.
glint_image *film_new(int width, int height, output_transform encoding);

/// Display encoding of one linear value: transform, clamp to [0,1], round to nearest of 0..255.
uint8_t film_encode(float linear, output_transform encoding);

#endif
