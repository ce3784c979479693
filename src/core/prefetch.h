// prefetch.h — hints that bring memory into the cache before it is used, for loops that reach far-apart
// elements of large arrays (a mesh's vertices) whose indices are known a little ahead. Hints only: they
// change no result, and compile to nothing where the compiler has no such builtin. A function made only of
// prefetches has no effect gcc can see: unless it is inlined early, gcc takes it for pure and deletes the call
// (gcc 12 dropped every prefetch of mesh_prefetch_shade so). So these, and every helper made only of them
// (mesh_prefetch_shade, surface_prefetch), are always_inline.
#ifndef GLINT_PREFETCH_H
#define GLINT_PREFETCH_H

/// Starts loading the cache line at p for reading.
static inline __attribute__((always_inline)) void prefetch_read(const void *p) {
#if defined(__GNUC__)
    __builtin_prefetch(p, 0);
#else
    (void)p;
#endif
}

/// Starts loading the cache line at p for writing.
static inline __attribute__((always_inline)) void prefetch_write(const void *p) {
#if defined(__GNUC__)
    __builtin_prefetch(p, 1);
#else
    (void)p;
#endif
}

#endif
