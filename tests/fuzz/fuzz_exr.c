// fuzz_exr.c — libFuzzer target for OpenEXR environment maps (io/exr_read through OpenEXRCore), as fuzz_map.h says.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_exr NEWDIR tests/fuzz/corpus_exr
#include "fuzz_map.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) { return fuzz_map(data, size, MAP_EXR); }
