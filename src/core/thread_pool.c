// thread_pool.c — the pool's threads: they sleep until a job is posted, take its items one by one under the
// lock, and the last item to finish wakes the caller.
// sched_getaffinity and CPU_COUNT are Linux's: <sched.h> declares them only for _GNU_SOURCE.
#define _GNU_SOURCE
#include "core/thread_pool.h"

#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

struct thread_pool {
    pthread_mutex_t lock;
    pthread_cond_t wake; ///< a job was posted, or the pool is stopping
    pthread_cond_t done; ///< the job's last item finished
    // The current job; items are claimed under the lock, so that a thread that wakes late can never take an
    // item of one job with the function of another.
    thread_pool_fn fn;
    void *ctx;
    size_t count, next, finished;
    bool quit;
    pthread_t *threads;
    int started;
};

int thread_pool_online_cpus(void) {
    // The CPUs this process may run on (taskset, cgroups, an MPI launcher's binding): threads beyond them would
    // only take turns. All online CPUs where the mask is unknown.
    cpu_set_t set;
    long n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
    if (n <= 0) n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (n > 1024 ? 1024 : (int)n) : 1;
}

// Runs items of the current job until none is left to claim; called and returns with the lock held.
static void run_items(thread_pool *p) {
    while (p->next < p->count) {
        size_t item = p->next++;
        thread_pool_fn fn = p->fn;
        void *ctx = p->ctx;
        pthread_mutex_unlock(&p->lock);
        fn(ctx, item);
        pthread_mutex_lock(&p->lock);
        if (++p->finished == p->count) pthread_cond_signal(&p->done);
    }
}

static void *worker_main(void *arg) {
    thread_pool *p = arg;
    pthread_mutex_lock(&p->lock);
    while (!p->quit) {
        run_items(p);
        if (!p->quit) pthread_cond_wait(&p->wake, &p->lock);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

thread_pool *thread_pool_start(int threads) {
    thread_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    int extra = threads > 1 ? threads - 1 : 0;
    p->threads = extra ? malloc((size_t)extra * sizeof *p->threads) : NULL;
    if (extra && !p->threads) {
        free(p);
        return NULL;
    }
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int i = 0; i < extra; i++) {
        if (pthread_create(&p->threads[i], NULL, worker_main, p) != 0) break; // fewer threads: slower, not wrong
        p->started++;
    }
    return p;
}

int thread_pool_size(const thread_pool *p) { return p->started + 1; }

void thread_pool_run(thread_pool *p, size_t count, thread_pool_fn fn, void *ctx) {
    if (count == 0) return;
    pthread_mutex_lock(&p->lock);
    p->fn = fn;
    p->ctx = ctx;
    p->count = count;
    p->next = p->finished = 0;
    if (count > 1) pthread_cond_broadcast(&p->wake);
    run_items(p);
    while (p->finished < p->count) pthread_cond_wait(&p->done, &p->lock);
    p->count = p->next = p->finished = 0; // no job: a thread that wakes now finds nothing to take
    pthread_mutex_unlock(&p->lock);
}

void thread_pool_post(thread_pool *p, size_t count, thread_pool_fn fn, void *ctx) {
    pthread_mutex_lock(&p->lock);
    p->fn = fn;
    p->ctx = ctx;
    p->count = count;
    p->next = p->finished = 0;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

void thread_pool_wait(thread_pool *p) {
    pthread_mutex_lock(&p->lock);
    while (p->finished < p->count) pthread_cond_wait(&p->done, &p->lock);
    p->count = p->next = p->finished = 0;
    pthread_mutex_unlock(&p->lock);
}

void thread_pool_stop(thread_pool *p) {
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    p->quit = true;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
    for (int i = 0; i < p->started; i++) pthread_join(p->threads[i], NULL);
    pthread_cond_destroy(&p->done);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
    free(p->threads);
    free(p);
}
