// filepath.h — file paths as the readers of scene, OBJ and MTL files need them: a file named inside another
// file is relative to that file's directory unless it is absolute. POSIX paths ('/' separators).
// (The prefix is filepath_, not path_: path_ belongs to the path tracer.)
#ifndef GLINT_FILEPATH_H
#define GLINT_FILEPATH_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/stat.h>

/// The length of the directory part of `path`, up to and including its last '/': 7 for "scenes/a.json",
/// 0 for "a.json".
size_t filepath_dir_length(const char *path);
/// Whether `path` (len bytes) is absolute: it starts with '/'.
bool filepath_is_absolute(const char *path, size_t len);
/// A new NUL-terminated string: rel[0, rel_len) as it is when absolute, else the first dir_len bytes of
/// `dir` followed by it. NULL when out of memory; free with free().
char *filepath_join(const char *dir, size_t dir_len, const char *rel, size_t rel_len);
/// Why `path` cannot be read as a file: 0 for a regular file (*st then holds it), an errno value (EISDIR for
/// a directory), or -1 for a special file (device, FIFO, socket), which could block or never end.
int filepath_problem(const char *path, struct stat *st);
/// The text of a filepath_problem value: strerror's, or "not a regular file" for -1.
const char *filepath_problem_text(int problem);
/// `path` for a message, at most `limit` bytes of it: when longer, "..." and its last bytes (the file name
/// and the directories nearest it, where a misspelling matters), cut on a UTF-8 boundary. Returns buf.
const char *filepath_tail(const char *path, size_t limit, char *buf, size_t size);

#endif
