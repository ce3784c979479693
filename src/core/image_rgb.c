// image_rgb.c — releasing a decoded image.
#include "core/image_rgb.h"

#include <stdlib.h>

void image_rgb_free(image_rgb *img) {
    free(img->pixels);
    free(img->alpha);
    img->pixels = img->alpha = NULL;
    img->width = img->height = 0;
}
