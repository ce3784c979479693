// test_strmap.c — the string map: FNV-1a values, lookups by pointer and length, replacement, growth.
#include "check.h"
#include "core/strmap.h"

#include <stdio.h>
#include <string.h>

static void test_hash(void) {
    // Published FNV-1a 64-bit values.
    CHECK(strmap_hash("", 0) == UINT64_C(0xcbf29ce484222325));
    CHECK(strmap_hash("a", 1) == UINT64_C(0xaf63dc4c8601ec8c));
    CHECK(strmap_hash("foobar", 6) == UINT64_C(0x85944171f73967e8));
}

static void test_get_put(void) {
    strmap m = {0};
    size_t v = 99;
    CHECK(!strmap_get(&m, "red", 3, &v));
    CHECK(v == 99);
    CHECK(strmap_put(&m, "red", 3, 0));
    CHECK(strmap_put(&m, "green", 5, 1));
    CHECK(strmap_get(&m, "red", 3, &v) && v == 0);
    CHECK(strmap_get(&m, "green", 5, &v) && v == 1);
    // Keys are byte ranges: a prefix or a longer string is another key, and no NUL is needed.
    CHECK(!strmap_get(&m, "re", 2, NULL));
    CHECK(!strmap_get(&m, "reddish", 7, NULL));
    CHECK(strmap_get(&m, "reddish", 3, &v) && v == 0);
    // The empty string is a key like any other.
    CHECK(!strmap_get(&m, "", 0, NULL));
    CHECK(strmap_put(&m, "", 0, 7));
    CHECK(strmap_get(&m, "x", 0, &v) && v == 7);
    // Putting a key again replaces its value.
    CHECK(strmap_put(&m, "red", 3, 42));
    CHECK(strmap_get(&m, "red", 3, &v) && v == 42);
    CHECK(m.count == 3);
    strmap_free(&m);
    CHECK(m.slots == NULL && m.capacity == 0 && m.count == 0);
    CHECK(!strmap_get(&m, "red", 3, NULL));
}

static void test_many(void) {
    enum { N = 5000 };
    static char keys[N][16];
    strmap m = {0};
    bool ok = true;
    for (size_t i = 0; i < N; i++) {
        snprintf(keys[i], sizeof keys[i], "name%zu", i);
        ok = ok && strmap_put(&m, keys[i], strlen(keys[i]), i);
        // The table stays at most half full, with a power-of-two capacity.
        ok = ok && m.count * 2 <= m.capacity && (m.capacity & (m.capacity - 1)) == 0;
    }
    CHECK(ok);
    CHECK(m.count == N);
    bool found = true;
    for (size_t i = 0; i < N; i++) {
        size_t v;
        found = found && strmap_get(&m, keys[i], strlen(keys[i]), &v) && v == i;
    }
    CHECK(found);
    CHECK(!strmap_get(&m, "name5000", 8, NULL));
    strmap_free(&m);
}

int main(void) {
    test_hash();
    test_get_put();
    test_many();
    return check_summary();
}
