// thread_pool.h — a few threads that run the items of one job at a time with the calling thread (a
// "parallel for"): for work that splits into independent pieces, such as the chunks of a BVH build.
//
// Usage:
//     thread_pool *p = thread_pool_start(threads);   // NULL: out of memory (run the items serially instead)
//     thread_pool_run(p, count, fn, ctx);            // fn(ctx, 0) ... fn(ctx, count - 1), returns when all are done
//     thread_pool_stop(p);
// or, for a job the pool's threads run while the caller does other work: thread_pool_post, then thread_pool_wait.
// Items are handed out in index order, each to whichever thread asks first; what an item computes must not
// depend on which thread runs it. Idle threads sleep on a condition variable, never spin.
#ifndef GLINT_THREAD_POOL_H
#define GLINT_THREAD_POOL_H

#include <stddef.h>

/// A running pool (opaque).
typedef struct thread_pool thread_pool;

/// One item of a job: ctx is the job's, item in [0, count).
typedef void (*thread_pool_fn)(void *ctx, size_t item);

/// The CPUs this process may run on (its affinity mask: taskset, cgroups, an MPI binding; else the online
/// CPUs), at least 1, at most 1024: what a thread count of 0 means, everywhere in glint.
int thread_pool_online_cpus(void);
/// Starts a pool of `threads` threads counting the caller (threads - 1 are created; fewer when the system
/// refuses more, which only costs speed). NULL when out of memory.
thread_pool *thread_pool_start(int threads);
/// Threads that run a job's items, the caller included.
int thread_pool_size(const thread_pool *p);
/// Runs fn(ctx, i) for every i in [0, count) on the pool's threads and the caller, and returns once all have
/// returned. Called by one thread at a time (the pool's owner), never from inside an item.
void thread_pool_run(thread_pool *p, size_t count, thread_pool_fn fn, void *ctx);
/// Posts a job that the pool's threads alone run (the caller goes on: glint-mpi's crew talks to other processes
/// meanwhile); thread_pool_wait returns once every item has returned. One job at a time.
void thread_pool_post(thread_pool *p, size_t count, thread_pool_fn fn, void *ctx);
/// Waits for the job thread_pool_post posted (at once when none was).
void thread_pool_wait(thread_pool *p);
/// Ends the pool's threads and frees it (NULL is allowed).
void thread_pool_stop(thread_pool *p);

#endif
