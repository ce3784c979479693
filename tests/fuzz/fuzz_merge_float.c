// fuzz_merge_float.c — libFuzzer target for glint merge's float parts (io/merge_float.c, io/exr_read.c's part
// reader, io/pfm_region.c): the input is one part merged on its own. An input starting with OpenEXR's magic
// number is an OpenEXR part merged to .exr. Any other input is a PFM part: the bytes up to the first NUL are its
// region file (PART.region; none without a NUL) and the rest the PFM, merged to .pfm; a region file ending in
// "fnv1a64=0000000000000000\n" gets the PFM's real hash in its place, so that inputs reach the PFM reader past
// the hash. Any bytes must give a merged image (a part that covers its whole image) or a message; never a crash,
// a leak or undefined behaviour, and never an output from a refused part.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_merge_float NEWDIR tests/fuzz/corpus_merge_float
#include "core/hash.h"
#include "fuzz_file.h"
#include "io/exr_read.h"
#include "io/image_merge.h"

#include <inttypes.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

// A merge of at most this much memory: parts of up to 16384 x 16384 are real and take gigabytes (tests/cli/
// merge_float.sh merges one under a memory limit); here they would only fill AddressSanitizer's quarantine.
enum { FUZZ_MERGE_BYTES = 64 << 20 };

static const char PLACEHOLDER[] = "fnv1a64=0000000000000000\n";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char part[128], side[160], out[128];
    bool exr = exr_read_is_exr(data, size);
    snprintf(side, sizeof side, "%s", fuzz_path("part.pfm.region"));
    unlink(side);
    if (exr) {
        snprintf(part, sizeof part, "%s", fuzz_file(data, size, "part.exr"));
    } else {
        const uint8_t *nul = memchr(data, '\0', size);
        const uint8_t *pfm = nul ? nul + 1 : data;
        size_t pfm_size = size - (size_t)(pfm - data);
        snprintf(part, sizeof part, "%s", fuzz_file(pfm, pfm_size, "part.pfm"));
        if (nul) {
            size_t n = (size_t)(nul - data), p = sizeof PLACEHOLDER - 1;
            char text[512];
            if (n >= sizeof text) n = sizeof text - 1;
            memcpy(text, data, n);
            text[n] = '\0';
            if (n >= p && memcmp(text + n - p, PLACEHOLDER, p) == 0)
                snprintf(text + n - p, sizeof text - (n - p), "fnv1a64=%016" PRIx64 "\n",
                         hash_bytes(HASH_START, pfm, pfm_size));
            fuzz_file((const uint8_t *)text, strlen(text), "part.pfm.region");
        }
    }
    snprintf(out, sizeof out, "%s", fuzz_path(exr ? "merged.exr" : "merged.pfm"));
    unlink(out);
    const char *parts[] = {part};
    glint_error err;
    glint_status st = image_merge_limited(out, parts, 1, FUZZ_MERGE_BYTES, &err);
    struct stat sb;
    bool written = stat(out, &sb) == 0;
    if (st == GLINT_OK ? !written : written) __builtin_trap();
    if (st != GLINT_OK && (memchr(err.message, '\0', sizeof err.message) == NULL || err.message[0] == '\0'))
        __builtin_trap();
    return 0;
}
