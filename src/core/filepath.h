// filepath.h — file paths as the readers of scene, OBJ and MTL files need them: a file named inside another
// file is relative to that file's directory unless it is absolute. POSIX paths ('/' separators).
// (The prefix is filepath_, not path_: path_ belongs to the path tracer.)
#ifndef GLINT_FILEPATH_H
#define GLINT_FILEPATH_H

#include <stdbool.h>
#include <stddef.h>

/// The length of the directory part of `path`, up to and including its last '/': 7 for "scenes/a.json",
/// 0 for "a.json".
size_t filepath_dir_length(const char *path);
/// Whether `path` (len bytes) is absolute: it starts with '/'.
bool filepath_is_absolute(const char *path, size_t len);
/// A new NUL-terminated string: rel[0, rel_len) as it is when absolute, else the first dir_len bytes of
/// `dir` followed by it. NULL when out of memory; free with free().
char *filepath_join(const char *dir, size_t dir_len, const char *rel, size_t rel_len);

#endif
