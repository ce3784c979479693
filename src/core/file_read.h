// file_read.h — reading the rest of an open file into memory, with a size limit checked while reading, so
// that a huge or endless stream (a FIFO, /dev/zero) is refused one byte past the limit, not when memory runs out.
#ifndef GLINT_FILE_READ_H
#define GLINT_FILE_READ_H

#include <stddef.h>
#include <stdio.h>

/// Reads f to its end into a NUL-terminated buffer (length in *len), starting with room for `initial` bytes
/// (the file's size when known) and doubling. NULL on failure, with *errnum EFBIG (more than max bytes),
/// ENOMEM (out of memory) or the read's errno; the caller closes f and frees the buffer.
char *file_read_stream(FILE *f, size_t initial, size_t max, size_t *len, int *errnum);

#endif
