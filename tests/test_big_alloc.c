// test_big_alloc.c — big_alloc: small arrays aligned as asked, large ones on 2 MiB boundaries with their length
// rounded up to whole 2 MiB pages (all of it writable), nothing for 0 bytes or a length that cannot be rounded.
#include "check.h"
#include "core/big_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int main(void) {
    CHECK(big_alloc(64, 0) == NULL);
    CHECK(big_alloc(64, SIZE_MAX) == NULL);
    CHECK(big_alloc(64, SIZE_MAX - BIG_ALLOC_HUGE + 1) == NULL);
    const size_t sizes[] = {1, 63, 64, 4096, BIG_ALLOC_HUGE - 1, BIG_ALLOC_HUGE, BIG_ALLOC_HUGE + 1, 5 * BIG_ALLOC_HUGE - 7};
    const size_t aligns[] = {16, 32, 64};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t j = 0; j < sizeof aligns / sizeof *aligns; j++) {
            size_t n = sizes[i], a = aligns[j];
            unsigned char *p = big_alloc(a, n);
            CHECK(p != NULL);
            if (!p) continue;
            size_t want = n >= BIG_ALLOC_HUGE ? BIG_ALLOC_HUGE : a;
            CHECK((uintptr_t)p % want == 0);
            // The rounded length is the block's: every byte of it may be written (AddressSanitizer would object).
            size_t len = n >= BIG_ALLOC_HUGE ? (n + BIG_ALLOC_HUGE - 1) / BIG_ALLOC_HUGE * BIG_ALLOC_HUGE
                                             : (n + a - 1) / a * a;
            memset(p, 0x5a, len);
            CHECK(p[0] == 0x5a && p[len - 1] == 0x5a);
            free(p);
        }
    return check_summary();
}
