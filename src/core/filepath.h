// filepath.h — file paths as the readers of scene, OBJ and MTL files need them: a file named inside another
// file is relative to that file's directory unless it is absolute. POSIX paths ('/' separators).
// (The prefix is filepath_, not path_: path_ belongs to the path tracer.)
#ifndef GLINT_FILEPATH_H
#define GLINT_FILEPATH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
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
/// Opens `path` for reading if it is a regular file, checked on the opened descriptor (opened without blocking,
/// so a FIFO with no writer cannot hang the open). NULL with *problem a filepath_problem value otherwise (an
/// errno value, EISDIR for a directory, -1 for a device, FIFO or socket). *st holds the file's status.
FILE *filepath_open_regular(const char *path, struct stat *st, int *problem);
/// The file a write at `path` lands in: path itself or, when it is a symbolic link (a chain of them), the file
/// the chain finally names (which may not exist yet). NULL with *error set (ELOOP, ENOMEM, a readlink errno).
char *filepath_final(const char *path, int *error);
/// Whether writing at a and at b would write one file: the same existing file (by device and inode, whatever
/// the names and links), or, for a name that does not exist yet, the same name in the same directory
/// ("x.pfm", "./x.pfm", "d/../x.pfm").
bool filepath_same_target(const char *a, const char *b);
/// The text of a filepath_problem value: strerror's, or "not a regular file" for -1.
const char *filepath_problem_text(int problem);
/// `path` for a message, at most `limit` bytes of it: when longer, "..." and its last bytes (the file name
/// and the directories nearest it, where a misspelling matters), cut on a UTF-8 boundary. Returns buf.
const char *filepath_tail(const char *path, size_t limit, char *buf, size_t size);

#endif
