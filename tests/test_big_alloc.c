// test_big_alloc.c — big_alloc: small arrays keep their alignment, large ones start on a huge page and hold every
// byte asked for, and sizes that would overflow when rounded to whole pages are refused.
#include "check.h"
#include "core/big_alloc.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static void test_small(void) {
    unsigned char *p = big_alloc(64, 64 * 100);
    CHECK(p != NULL && (uintptr_t)p % 64 == 0);
    memset(p, 0xab, 64 * 100);
    CHECK(p[0] == 0xab && p[64 * 100 - 1] == 0xab);
    free(p);
}

static void test_large(void) {
    size_t bytes = BIG_ALLOC_PAGE * 2 + 32 * 3; // not whole pages: the last one is rounded up
    unsigned char *p = big_alloc(32, bytes);
    CHECK(p != NULL && (uintptr_t)p % BIG_ALLOC_PAGE == 0);
    for (size_t i = 0; i < bytes; i += 4096) p[i] = (unsigned char)(i >> 12);
    p[bytes - 1] = 7;
    bool kept = p[bytes - 1] == 7;
    for (size_t i = 0; i < bytes; i += 4096) kept = kept && p[i] == (unsigned char)(i >> 12);
    CHECK(kept);
    free(p);
}

static void test_overflow(void) { CHECK(big_alloc(32, SIZE_MAX - 31) == NULL); }

int main(void) {
    test_small();
    test_large();
    test_overflow();
    return check_summary();
}
