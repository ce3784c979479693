// fuzz_hdr.c — libFuzzer target for Radiance .hdr environment maps (io/hdr_read: checked here, decoded by stb_image), as fuzz_map.h says.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_hdr NEWDIR tests/fuzz/corpus_hdr
#include "fuzz_map.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return fuzz_map(data, size, MAP_HDR); }
