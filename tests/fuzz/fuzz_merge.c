// fuzz_merge.c — libFuzzer target for glint merge's part reader (io/image_merge.c): the input is one region PNG
// merged on its own. Any bytes must give a merged image (a part that covers its whole image) or a message naming
// the part or the output; never a crash, a leak or undefined behaviour, and never an output from a refused part.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_merge NEWDIR tests/fuzz/corpus_merge
#include "fuzz_file.h"
#include "io/image_merge.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

// The width and height an IHDR first in the file declares (0 when there is none there).
static uint64_t declared_pixels(const uint8_t *data, size_t size) {
    if (size < 24 || memcmp(data + 12, "IHDR", 4) != 0) return 0;
    uint32_t w = (uint32_t)data[16] << 24 | (uint32_t)data[17] << 16 | (uint32_t)data[18] << 8 | data[19];
    uint32_t h = (uint32_t)data[20] << 24 | (uint32_t)data[21] << 16 | (uint32_t)data[22] << 8 | data[23];
    return (uint64_t)w * h;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    // Parts of up to 16384 x 16384 are real, and take a gigabyte or two: tests/cli/hostile.sh merges a large one
    // under a memory limit. Here they would only fill AddressSanitizer's quarantine, so they are left out.
    if (declared_pixels(data, size) > (uint64_t)1024 * 1024) return 0;
    char part[128], out[128];
    snprintf(part, sizeof part, "%s", fuzz_file(data, size, "part.png"));
    snprintf(out, sizeof out, "%s", fuzz_path("merged.png"));
    unlink(out);
    const char *parts[] = {part};
    glint_error err;
    glint_status st = image_merge(out, parts, 1, &err);
    struct stat sb;
    bool written = stat(out, &sb) == 0;
    if (st == GLINT_OK ? !written : written) __builtin_trap();
    if (st != GLINT_OK && (memchr(err.message, '\0', sizeof err.message) == NULL || err.message[0] == '\0'))
        __builtin_trap();
    return 0;
}
