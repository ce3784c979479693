// image_png.h — libpng's error and warning callbacks, shared by the PNG writer and the region reader (io only).
#ifndef GLINT_IMAGE_PNG_H
#define GLINT_IMAGE_PNG_H

#include <png.h>

/// Size of the message buffer image_png_error writes to.
#define IMAGE_PNG_MESSAGE 256

/// libpng error callback: copies libpng's message into the error pointer (a char[IMAGE_PNG_MESSAGE]) and jumps
/// back to the caller's setjmp; libpng reports errors only this way.
void image_png_error(png_structp png, png_const_charp msg);
/// libpng warning callback: ignored, since the library prints nothing.
void image_png_warning(png_structp png, png_const_charp msg);

#endif
