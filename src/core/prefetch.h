// prefetch.h — hints that bring memory into the cache before it is used, for loops that reach far-apart
// elements of large arrays (a mesh's vertices) whose indices are known a little ahead. Hints only: they
// change no result, and compile to nothing where the compiler has no such builtin.
#ifndef GLINT_PREFETCH_H
#define GLINT_PREFETCH_H

/// Starts loading the cache line at p for reading.
static inline void prefetch_read(const void *p) {
#if defined(__GNUC__)
    __builtin_prefetch(p, 0);
#else
    (void)p;
#endif
}

/// Starts loading the cache line at p for writing.
static inline void prefetch_write(const void *p) {
#if defined(__GNUC__)
    __builtin_prefetch(p, 1);
#else
    (void)p;
#endif
}

#endif
