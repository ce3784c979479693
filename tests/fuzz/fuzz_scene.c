// fuzz_scene.c — libFuzzer target for the scene reader: any bytes must give a scene or a message, never
// a crash, a leak, a hang or undefined behaviour. Build with -DGLINT_FUZZ=ON and CC=clang.
#include "glint.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    glint_scene *scene = NULL;
    glint_error err;
    glint_status st = glint_scene_parse("fuzz.json", (const char *)data, size, &scene, &err);
    // Every failure is reported with a status, a message and no scene.
    if (st != GLINT_OK &&
        (scene != NULL || memchr(err.message, '\0', sizeof err.message) == NULL || err.message[0] == '\0'))
        __builtin_trap();
    if (st == GLINT_OK) {
        int w, h;
        glint_scene_size(scene, &w, &h);
        if (w < 1 || h < 1) __builtin_trap();
    }
    glint_scene_free(scene);
    return 0;
}
