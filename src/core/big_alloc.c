// big_alloc.c — large arrays on huge pages (big_alloc.h).
// madvise and MADV_HUGEPAGE are not POSIX: <sys/mman.h> declares them for _DEFAULT_SOURCE.
#define _DEFAULT_SOURCE
#include "core/big_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

void *big_alloc(size_t align, size_t bytes) {
    if (bytes == 0 || bytes > SIZE_MAX - BIG_ALLOC_HUGE) return NULL;
    if (bytes < BIG_ALLOC_HUGE) return aligned_alloc(align, (bytes + align - 1) & ~(align - 1));
    size_t size = (bytes + BIG_ALLOC_HUGE - 1) & ~(BIG_ALLOC_HUGE - 1);
    void *p = aligned_alloc(BIG_ALLOC_HUGE, size);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Before the first touch: the pages are then made huge as they are first written. A refusal changes nothing.
    if (p) (void)madvise(p, size, MADV_HUGEPAGE);
#endif
    return p;
}
