// big_alloc.h — memory for large arrays that are read at random for the whole render (a BVH's nodes and leaf
// packets): on 2 MiB pages where the system offers transparent huge pages for regions that ask (Linux's
// madvise(MADV_HUGEPAGE)), so that a walk through a tree of tens of megabytes does not miss the TLB at nearly every
// step. Freed with free().
#ifndef GLINT_BIG_ALLOC_H
#define GLINT_BIG_ALLOC_H

#include <stddef.h>

/// Arrays of at least this many bytes are put on huge pages (one 2 MiB page).
#define BIG_ALLOC_HUGE ((size_t)2 << 20)

/// `bytes` of memory aligned to `align` (a power of two, at most BIG_ALLOC_HUGE), not yet touched: an array of at
/// least BIG_ALLOC_HUGE bytes is aligned to 2 MiB, its length rounded up to whole 2 MiB pages and advised onto huge
/// pages (advice only: where the system ignores it, ordinary pages). NULL when out of memory or for 0 bytes.
void *big_alloc(size_t align, size_t bytes);

#endif
