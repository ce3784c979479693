// big_alloc.h — memory for large arrays read at random (a BVH's wide nodes and leaf packets): from 2 MB up, aligned
// to 2 MB and offered to the kernel for huge pages (Linux's transparent huge pages, which glint asks for by
// madvise), so that a traversal's scattered reads are translated by far fewer TLB entries. Freed with free().
#ifndef GLINT_BIG_ALLOC_H
#define GLINT_BIG_ALLOC_H

#include <stddef.h>

/// The size of the pages asked for, and the size from which an array gets them.
#define BIG_ALLOC_PAGE ((size_t)2 << 20)

/// `bytes` (a multiple of `align`, a power of two) aligned to `align`, or NULL when memory runs out; from
/// BIG_ALLOC_PAGE up, aligned to BIG_ALLOC_PAGE, rounded up to whole pages and advised as huge pages (a hint: where
/// the system refuses it, ordinary pages serve).
void *big_alloc(size_t align, size_t bytes);

#endif
