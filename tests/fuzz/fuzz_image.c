// fuzz_image.c — libFuzzer target for the texture image reader (PNG and JPEG through libpng and libjpeg):
// any bytes must give an image or a message, never a crash, a leak or undefined behaviour.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_image NEWDIR tests/fuzz/corpus_image
#include "io/image_read.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    image_rgb img;
    glint_error err;
    if (image_read_memory("fuzz.img", data, size, IMAGE_DECODE_SRGB, &img, &err) == GLINT_OK) {
        if (img.width <= 0 || img.height <= 0 || !img.pixels) __builtin_trap();
        size_t n = (size_t)img.width * (size_t)img.height * 3;
        // Every decoded value is a linear intensity in [0, 1].
        for (size_t i = 0; i < n; i++)
            if (!(img.pixels[i] >= 0.0f && img.pixels[i] <= 1.0f)) __builtin_trap();
        image_rgb_free(&img);
    } else if (img.pixels || memchr(err.message, '\0', sizeof err.message) == NULL || err.message[0] == '\0') {
        __builtin_trap();
    }
    return 0;
}
