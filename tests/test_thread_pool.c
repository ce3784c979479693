// test_thread_pool.c — every item of every job runs exactly once, on pools of any size, over many jobs in a
// row (a thread that wakes late must never run an item twice or with another job's function).
#include "core/thread_pool.h"

#include "check.h"

#include <stdatomic.h>
#include <stdlib.h>

typedef struct job {
    atomic_int *runs; ///< per item
    int add;
} job;

static void count_item(void *ctx, size_t item) {
    const job *j = ctx;
    atomic_fetch_add(&j->runs[item], j->add);
}

static void other_item(void *ctx, size_t item) {
    const job *j = ctx;
    atomic_fetch_add(&j->runs[item], 1000 * j->add);
}

static void check_pool(int threads) {
    thread_pool *p = thread_pool_start(threads);
    CHECK(p != NULL);
    if (!p) return;
    CHECK(thread_pool_size(p) >= 1 && thread_pool_size(p) <= (threads > 1 ? threads : 1));
    enum { MAX_ITEMS = 97, JOBS = 2000 };
    atomic_int runs[MAX_ITEMS];
    int bad = 0;
    for (int r = 0; r < JOBS; r++) {
        size_t count = (size_t)(r * 7919) % MAX_ITEMS; // 0 included: nothing runs
        for (size_t i = 0; i < MAX_ITEMS; i++) atomic_init(&runs[i], 0);
        job j = {runs, 1 + r % 3};
        thread_pool_run(p, count, r % 2 ? count_item : other_item, &j);
        int want = r % 2 ? j.add : 1000 * j.add;
        for (size_t i = 0; i < MAX_ITEMS; i++) bad += atomic_load(&runs[i]) != (i < count ? want : 0);
    }
    CHECK(bad == 0);
    thread_pool_stop(p);
}

// A posted job runs on the pool's threads alone while the caller goes on; wait returns once all items returned.
static atomic_int posted_sum;
static void add_item(void *ctx, size_t item) {
    (void)ctx;
    atomic_fetch_add(&posted_sum, (int)item + 1);
}

static void test_post(void) {
    thread_pool *p = thread_pool_start(3);
    CHECK(p != NULL);
    if (!p) return;
    atomic_store(&posted_sum, 0);
    thread_pool_post(p, 100, add_item, NULL);
    thread_pool_wait(p);
    CHECK(atomic_load(&posted_sum) == 5050);
    thread_pool_wait(p); // nothing posted: returns at once
    thread_pool_run(p, 10, add_item, NULL); // the pool still runs ordinary jobs
    CHECK(atomic_load(&posted_sum) == 5050 + 55);
    thread_pool_stop(p);
}

int main(void) {
    test_post();
    CHECK(thread_pool_online_cpus() >= 1);
    thread_pool_stop(NULL);
    const int sizes[] = {0, 1, 2, 3, 8};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) check_pool(sizes[i]);
    return check_summary();
}
