// test_filepath.c — directory part, absolute test and joining of the paths scene and OBJ files name.
#include "check.h"
#include "core/filepath.h"

#include <stdlib.h>
#include <string.h>

static void test_dir_length(void) {
    CHECK(filepath_dir_length("scenes/a.json") == 7);
    CHECK(filepath_dir_length("a.json") == 0);
    CHECK(filepath_dir_length("") == 0);
    CHECK(filepath_dir_length("/a") == 1);
    CHECK(filepath_dir_length("x/y/z/") == 6);
}

static void test_absolute(void) {
    CHECK(filepath_is_absolute("/a", 2));
    CHECK(!filepath_is_absolute("a/b", 3));
    CHECK(!filepath_is_absolute("", 0));
    CHECK(!filepath_is_absolute("/a", 0)); // only the given bytes count
}

static void check_join(const char *dir, size_t dir_len, const char *rel, const char *expected) {
    char *p = filepath_join(dir, dir_len, rel, strlen(rel));
    CHECK(p && strcmp(p, expected) == 0);
    free(p);
}

static void test_join(void) {
    check_join("scenes/a.json", 7, "tex.png", "scenes/tex.png");
    check_join("a.json", 0, "tex.png", "tex.png");
    check_join("scenes/a.json", 7, "/abs/tex.png", "/abs/tex.png");
    check_join("scenes/", 7, "../x", "scenes/../x"); // joined as written, not normalised
    // rel need not be NUL-terminated: only rel_len bytes are taken.
    char *p = filepath_join("d/", 2, "file.objXYZ", 8);
    CHECK(p && strcmp(p, "d/file.obj") == 0);
    free(p);
}

int main(void) {
    test_dir_length();
    test_absolute();
    test_join();
    return check_summary();
}
