// fuzz_checkpoint.c — libFuzzer target for the checkpoint reader (render/checkpoint.c, --resume). The first byte
// of an input says what a forger would do to the rest: bit 0, make its identity this harness's render (so that
// the reader goes on to the planes); bit 1, recompute both checksums (they are unkeyed FNV-1a, anyone can). Any
// file must be read into the planes with counts <= its spp and finite, non-negative sums, or refused with a
// message naming it; never a crash, an overflow, a leak or undefined behaviour.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_checkpoint NEWDIR tests/fuzz/corpus_checkpoint
#include "fuzz_file.h"
#include "core/hash.h"
#include "render/checkpoint.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum { W = 6, H = 4, N = W * H, HEADER = 96, ENTRY = 24, MAX_FILE = 1 << 20 };

// The render this harness resumes: what checkpoint_identity_of would give for a 6x4 scene "fuzz.json".
static const checkpoint_identity ID = {"fuzz.json", 42, 7, W, H, 5, 1, 0, 0, 2, 1, {0, 0, W, H}};

static void put32(uint8_t *p, int32_t v) { memcpy(p, &v, 4); }

// The checkpoint header's fields the identity covers (checkpoint.c's struct header, in this machine's order).
static void make_identity(uint8_t *f) {
    memcpy(f + 16, &ID.scene_hash, 8);
    memcpy(f + 24, &ID.seed, 8);
    const int32_t fields[] = {ID.width, ID.height, ID.max_depth, ID.integrator, ID.whitted_mode, ID.accel,
                              ID.encoding, ID.light_sampling, ID.region[0], ID.region[1], ID.region[2], ID.region[3]};
    for (int i = 0; i < 12; i++) put32(f + 32 + 4 * i, fields[i]);
}

// The header checksum after the table, the data checksum at the end, as checkpoint_write computes them.
static void fix_checksums(uint8_t *f, size_t size) {
    uint32_t planes, name_bytes;
    memcpy(&planes, f + 88, 4);
    memcpy(&name_bytes, f + 92, 4);
    uint64_t table = HEADER + (uint64_t)name_bytes + (uint64_t)planes * ENTRY;
    if (planes > 64 || name_bytes > 4096 || table + 16 > size) return;
    uint64_t h = hash_bytes(HASH_START, f, (size_t)table);
    memcpy(f + table, &h, 8);
    h = hash_bytes(HASH_START, f + table + 8, size - (size_t)table - 16);
    memcpy(f + size - 8, &h, 8);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1 || size > MAX_FILE) return 0;
    static uint8_t file[MAX_FILE];
    size_t n = size - 1;
    memcpy(file, data + 1, n);
    if ((data[0] & 1) && n >= HEADER) make_identity(file);
    if ((data[0] & 2) && n >= HEADER) fix_checksums(file, n);
    const char *path = fuzz_file(file, n, "f.ckp");
    static uint32_t counts[N];
    static double sums[N * 3];
    memset(counts, 0xAB, sizeof counts);
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, counts}, {"rgb", CHECKPOINT_F64, 3, sums}};
    int spp = 0;
    glint_error err;
    if (checkpoint_read(path, &ID, planes, 2, &spp, &err) == GLINT_OK) {
        if (spp < 1) __builtin_trap();
        for (int i = 0; i < N; i++)
            if (counts[i] > (uint32_t)spp) __builtin_trap();
        for (int i = 0; i < N * 3; i++)
            if (!(sums[i] >= 0.0 && isfinite(sums[i]))) __builtin_trap();
    } else if (memchr(err.message, '\0', sizeof err.message) == NULL || strncmp(err.message, path, strlen(path)) != 0) {
        __builtin_trap();
    }
    return 0;
}
