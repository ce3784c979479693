// big_alloc.c — large arrays on huge pages where the system offers them.
#define _DEFAULT_SOURCE // madvise and MADV_HUGEPAGE are not POSIX: <sys/mman.h> declares them for this
#include "core/big_alloc.h"

#include <stdint.h>
#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

void *big_alloc(size_t align, size_t bytes) {
    if (bytes < BIG_ALLOC_PAGE) return aligned_alloc(align, bytes);
    if (bytes > SIZE_MAX - (BIG_ALLOC_PAGE - 1)) return NULL;
    size_t size = (bytes + BIG_ALLOC_PAGE - 1) & ~(BIG_ALLOC_PAGE - 1); // whole pages: the last one huge too
    void *p = aligned_alloc(BIG_ALLOC_PAGE, size);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p) (void)madvise(p, size, MADV_HUGEPAGE); // refused (no THP, or "never"): 4 KB pages, the same bytes
#endif
    return p;
}
