// test_array.c — array_reserve: the doubling policy, kept contents, and refusal of sizes that overflow.
#include "check.h"
#include "core/array.h"

#include <stdint.h>
#include <stdlib.h>

static void test_growth(void) {
    int *items = NULL;
    size_t capacity = 0;
    CHECK(array_reserve((void **)&items, &capacity, 0, sizeof *items));
    CHECK(items == NULL && capacity == 0); // nothing needed, nothing allocated
    CHECK(array_reserve((void **)&items, &capacity, 1, sizeof *items));
    CHECK(capacity == ARRAY_MIN_CAPACITY);
    for (int i = 0; i < 1000; i++) {
        size_t before = capacity;
        CHECK(array_reserve((void **)&items, &capacity, (size_t)i + 1, sizeof *items));
        CHECK(capacity >= (size_t)i + 1);
        // The capacity changes only when full, and then doubles.
        CHECK(capacity == before || (before <= (size_t)i && capacity == before * 2));
        items[i] = i;
    }
    CHECK(capacity == 1024);
    bool kept = true;
    for (int i = 0; i < 1000; i++) kept = kept && items[i] == i;
    CHECK(kept);
    // A jump past several doublings lands on the first power-of-two multiple that holds it.
    CHECK(array_reserve((void **)&items, &capacity, 5000, sizeof *items));
    CHECK(capacity == 8192);
    free(items);
}

static void test_overflow(void) {
    double *items = NULL;
    size_t capacity = 0;
    CHECK(!array_reserve((void **)&items, &capacity, SIZE_MAX / sizeof *items + 1, sizeof *items));
    CHECK(items == NULL && capacity == 0);
    CHECK(!array_reserve((void **)&items, &capacity, SIZE_MAX, 2));
    CHECK(items == NULL && capacity == 0);
}

int main(void) {
    test_growth();
    test_overflow();
    return check_summary();
}
