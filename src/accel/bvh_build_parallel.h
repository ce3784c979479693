// bvh_build_parallel.h — the binary BVH built on every thread of a pool (private to the build;
// bvh_build_parallel.c): the tree of the serial bvh_build_range, for any number of threads.
#ifndef GLINT_BVH_BUILD_PARALLEL_H
#define GLINT_BVH_BUILD_PARALLEL_H

#include "accel/bvh_sah.h"
#include "core/thread_pool.h"

/// A build over fewer than 2 * PARALLEL_MIN primitives runs on one thread (threads would cost more than they save);
/// accel_build_options.parallel_min replaces it in tests.
enum { PARALLEL_MIN = 1 << 15 };

/// Builds the tree of bvh_build_range(bd, 0, n, 0, NULL) into bd->nodes on the pool's threads; false when out of
/// memory.
bool bvh_build_parallel(builder *bd, size_t n, thread_pool *pool, size_t parallel_min);

#endif
