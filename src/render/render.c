// render.c — the render stage: progressive sample passes over tiles handed out through an atomic counter to
// N threads, each pixel's samples drawn from generators seeded by (seed, pixel, sample) alone, so any thread
// count gives the same bytes, and a stop request leaves every pixel at the mean of its completed samples.
#include "render/render.h"
#include "core/clock.h"
#include "film/film.h"
#include "render/frame.h"
#include "render/tiles.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum {
    MAX_THREADS = 256,
    MAX_PASSES = TILES_MAX_PASSES,
    PROGRESS_INTERVAL_MS = 200, // progress callbacks at most five times a second
    PASS_RUN = 1,
    PASS_SKIP = 2,
};

// Set by render_request_stop (possibly from a signal handler), polled before every sample, cleared when a
// render returns: a request made while no render runs stops the next one at once.
static _Alignas(64) atomic_int stop_requested; // read before every sample: a line of its own

void render_request_stop(void) { atomic_store(&stop_requested, 1); }

static bool stop_is_requested(void) { return atomic_load_explicit(&stop_requested, memory_order_relaxed) != 0; }

// Work is a sequence of items, item = pass * tile_count + tile (render/tiles.h). Pass p renders samples
// [pass_start[p], pass_start[p+1]) of every pixel of the tile, adding them to the running sums in sample
// order, so the final mean is bit for bit the plain sum over samples 0..spp-1 divided by spp.
typedef struct render_job {
    const glint_scene *scene;
    const integrator *integrator;
    film film;
    tiles grid;                    ///< the region's tiles and the sample passes
    uint64_t total_samples;        ///< the region's pixels * spp
    atomic_int next_item;
    atomic_int *tile_passes;       ///< passes completed by each tile; pass p of a tile waits for p
    atomic_int waiters;            ///< workers blocked in wait_for_tile
    atomic_int stopping;           ///< a worker saw the stop request; waiters must give up
    double deadline;               ///< clock_seconds() after which no new pass starts (0: no time limit)
    atomic_int pass_decision[MAX_PASSES]; ///< under a time limit: 0 undecided, PASS_RUN or PASS_SKIP
    pthread_mutex_t lock;
    pthread_cond_t tile_finished;
} render_job;

// One worker's state, on cache lines of its own: the counters that worker writes never share a line.
typedef struct worker {
    thread_stats stats;                           ///< the worker's counters, copied here when it ends
    _Alignas(64) _Atomic uint64_t samples_done;   ///< read by the progress thread while the worker runs
    render_job *job;
    pthread_t thread;
} worker;

// The progress reporter: a helper thread that wakes a few times a second and sums the workers' counters,
// so reports are time-based whatever the size of a tile or pass.
typedef struct progress_state {
    render_job *job;
    worker *workers;
    int worker_count;
    glint_progress_fn fn;
    void *user;
    bool finished;
    pthread_mutex_t lock;
    pthread_cond_t wake;
} progress_state;

// Renders one pass of one tile; false when stopped part-way (pixels not reached keep the previous pass's mean).
static bool render_tile(render_job *job, int tile, int pass, thread_stats *ts, _Atomic uint64_t *progress) {
    int r[4];
    tiles_rect(&job->grid, tile, r);
    tile_pass tp;
    tp.x0 = r[0];
    tp.y0 = r[1];
    tp.x1 = r[2];
    tp.y1 = r[3];
    tp.k0 = job->grid.pass_start[pass];
    tp.k1 = job->grid.pass_start[pass + 1];
    tp.stop = &stop_requested;
    film_tile ft;
    film_tile_begin(&ft, &job->film, tp.x0, tp.y0, tp.x1, tp.y1, tp.k0, tp.k1, ts, progress);
    return job->integrator->render_tile(job->integrator, &tp, &ft, ts);
}

// Wakes the workers waiting for a tile; the waiters count (sequentially consistent, as is the tile store
// before it) spares the mutex when, as nearly always, nobody waits.
static void wake_waiters(render_job *job) {
    if (atomic_load(&job->waiters) == 0) return;
    pthread_mutex_lock(&job->lock);
    pthread_cond_broadcast(&job->tile_finished);
    pthread_mutex_unlock(&job->lock);
}

// Blocks until the tile has finished `pass` passes; false when the render is stopping instead. Only waits
// when fewer tiles than threads remain between a tile's consecutive passes.
static bool wait_for_tile(render_job *job, int tile, int pass) {
    if (atomic_load(&job->tile_passes[tile]) >= pass) return true;
    pthread_mutex_lock(&job->lock);
    atomic_fetch_add(&job->waiters, 1);
    while (atomic_load(&job->tile_passes[tile]) < pass && !atomic_load(&job->stopping))
        pthread_cond_wait(&job->tile_finished, &job->lock);
    atomic_fetch_sub(&job->waiters, 1);
    pthread_mutex_unlock(&job->lock);
    return atomic_load(&job->tile_passes[tile]) >= pass;
}

// Under a time limit, whether pass `pass` runs: the worker that takes its first tile decides, by the clock,
// once for everyone (items are handed out in order, so no tile of a pass is taken before its first); the
// others wait for that decision. Every pixel thus ends with the same passes: the image of a shorter render.
static bool pass_may_run(render_job *job, int pass, int tile) {
    if (tile == 0)
        atomic_store(&job->pass_decision[pass], clock_seconds() > job->deadline ? PASS_SKIP : PASS_RUN);
    int d;
    while ((d = atomic_load(&job->pass_decision[pass])) == 0) {
        if (stop_is_requested()) return false;
        sched_yield();
    }
    return d == PASS_RUN;
}

static void *worker_main(void *arg) {
    worker *w = arg;
    render_job *job = w->job;
    thread_stats local = {0}; // on this thread's stack: the hot counters are never shared
    int items = job->grid.pass_count * job->grid.tile_count;
    for (;;) {
        if (stop_is_requested()) break;
        int item = atomic_fetch_add(&job->next_item, 1);
        if (item >= items) break;
        int pass = item / job->grid.tile_count, tile = item % job->grid.tile_count;
        if (job->deadline > 0.0 && pass > 0 && !pass_may_run(job, pass, tile)) break;
        if (!wait_for_tile(job, tile, pass)) break;
        if (!render_tile(job, tile, pass, &local, &w->samples_done)) break;
        atomic_store(&job->tile_passes[tile], pass + 1);
        wake_waiters(job);
    }
    // Whoever leaves early releases the waiters: the tiles they wait for may never finish now.
    if (stop_is_requested()) {
        pthread_mutex_lock(&job->lock);
        atomic_store(&job->stopping, 1);
        pthread_cond_broadcast(&job->tile_finished);
        pthread_mutex_unlock(&job->lock);
    }
    w->stats = local;
    return NULL;
}

static uint64_t samples_so_far(const progress_state *p) {
    uint64_t n = 0;
    for (int i = 0; i < p->worker_count; i++)
        n += atomic_load_explicit(&p->workers[i].samples_done, memory_order_relaxed);
    return n;
}

static void *progress_main(void *arg) {
    progress_state *p = arg;
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    pthread_mutex_lock(&p->lock);
    while (!p->finished) {
        next.tv_nsec += PROGRESS_INTERVAL_MS * 1000000L;
        if (next.tv_nsec >= 1000000000L) { next.tv_sec++; next.tv_nsec -= 1000000000L; }
        int rc = 0;
        while (!p->finished && rc != ETIMEDOUT) rc = pthread_cond_timedwait(&p->wake, &p->lock, &next);
        if (p->finished) break;
        // Call out without the lock: a slow terminal must not hold up the end of the render.
        pthread_mutex_unlock(&p->lock);
        p->fn((double)samples_so_far(p) / (double)p->job->total_samples, p->user);
        pthread_mutex_lock(&p->lock);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

// Starts the progress thread; false (and no progress reports but the last) when it cannot be started.
static bool progress_start(progress_state *p, pthread_t *thread) {
    pthread_condattr_t attr;
    if (pthread_condattr_init(&attr) != 0) return false;
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    int rc = pthread_cond_init(&p->wake, &attr);
    pthread_condattr_destroy(&attr);
    if (rc != 0) return false;
    pthread_mutex_init(&p->lock, NULL);
    if (pthread_create(thread, NULL, progress_main, p) == 0) return true;
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
    return false;
}

static void progress_stop(progress_state *p, pthread_t thread) {
    pthread_mutex_lock(&p->lock);
    p->finished = true;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(thread, NULL);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
}

static int online_cpus(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

// Sets up the job's passes, tiles and film over the (checked) region; false when out of memory.
static bool job_init(render_job *job, const glint_scene *s, const integrator *it, const int region[4]) {
    const render_settings *rs = &s->settings;
    memset(job, 0, sizeof *job);
    job->scene = s;
    job->integrator = it;
    tiles_init(&job->grid, region, rs->spp);
    job->total_samples =
        (uint64_t)(region[2] - region[0]) * (uint64_t)(region[3] - region[1]) * (uint64_t)rs->spp;
    atomic_init(&job->next_item, 0);
    atomic_init(&job->waiters, 0);
    atomic_init(&job->stopping, 0);
    for (int p = 0; p < MAX_PASSES; p++) atomic_init(&job->pass_decision[p], 0);
    if (!film_init(&job->film, region, rs->width, rs->height, rs->spp, job->grid.pass_count, rs->transform))
        return false;
    job->tile_passes = malloc((size_t)job->grid.tile_count * sizeof *job->tile_passes);
    if (!job->tile_passes) {
        film_release(&job->film);
        return false;
    }
    for (int i = 0; i < job->grid.tile_count; i++) atomic_init(&job->tile_passes[i], 0);
    pthread_mutex_init(&job->lock, NULL);
    pthread_cond_init(&job->tile_finished, NULL);
    return true;
}

static void job_free(render_job *job) {
    pthread_cond_destroy(&job->tile_finished);
    pthread_mutex_destroy(&job->lock);
    free(job->tile_passes);
    film_release(&job->film);
}

glint_status render_scene(const glint_scene *s, const render_options *opt, glint_progress_fn progress, void *user,
                          glint_image **out, glint_render_stats *stats, glint_error *err) {
    *out = NULL;
    double t0 = clock_seconds();
    int region[4];
    glint_status st = tiles_resolve_region(&s->settings, opt ? opt->region : NULL, region, err);
    if (st != GLINT_OK) return st;
    render_frame frame;
    st = frame_build(&frame, s, opt ? &opt->integrator : NULL, &stop_requested, err);
    if (st == GLINT_ERR_INTERRUPTED) { // stopped while the BVH was built: no sample, a black image
        atomic_store(&stop_requested, 0);
        if (stats) memset(stats, 0, sizeof *stats);
        film f;
        if (!film_init(&f, region, s->settings.width, s->settings.height, 1, 1, s->settings.transform)) {
            snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image", region[2] - region[0],
                     region[3] - region[1]);
            return GLINT_ERR_RENDER;
        }
        *out = film_take_image(&f);
        return st;
    }
    if (st != GLINT_OK) return st;
    double t_built = clock_seconds();
    int threads = opt && opt->threads > 0 ? opt->threads : online_cpus();
    if (threads > MAX_THREADS) threads = MAX_THREADS;

    render_job job;
    bool job_ready = job_init(&job, s, frame.integrator, region);
    if (job_ready && opt && opt->time_limit > 0.0) job.deadline = t_built + opt->time_limit;
    worker *workers = job_ready ? aligned_alloc(64, sizeof(worker) * (size_t)threads) : NULL;
    if (!workers) {
        if (job_ready) job_free(&job);
        frame_release(&frame);
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image on %d threads",
                 region[2] - region[0], region[3] - region[1], threads);
        return GLINT_ERR_RENDER;
    }
    memset(workers, 0, sizeof(worker) * (size_t)threads);
    for (int i = 0; i < threads; i++) {
        workers[i].job = &job;
        atomic_init(&workers[i].samples_done, 0);
    }

    progress_state prog = {.job = &job, .workers = workers, .worker_count = threads, .fn = progress, .user = user};
    pthread_t prog_thread;
    bool prog_running = progress && progress_start(&prog, &prog_thread);

    int started = 0; // worker threads 1..started run; the calling thread is worker 0
    for (int i = 1; i < threads; i++) {
        if (pthread_create(&workers[i].thread, NULL, worker_main, &workers[i]) != 0) break;
        started = i;
    }
    worker_main(&workers[0]);
    for (int i = 1; i <= started; i++) pthread_join(workers[i].thread, NULL);
    if (prog_running) progress_stop(&prog, prog_thread);

    thread_stats total = {0};
    for (int i = 0; i <= started; i++) {
        total.rays += workers[i].stats.rays;
        total.shadow_rays += workers[i].stats.shadow_rays;
        total.discarded_samples += workers[i].stats.discarded_samples;
        total.samples += workers[i].stats.samples;
    }
    if (progress) progress((double)total.samples / (double)job.total_samples, user);
    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->rays = total.rays;
        stats->shadow_rays = total.shadow_rays;
        stats->discarded_samples = total.discarded_samples;
        stats->samples = total.samples;
        accel_stats as;
        accel_get_stats(frame.accel, &as);
        stats->bvh_nodes = as.nodes;
        stats->bvh_leaves = as.leaves;
        stats->bvh_depth = as.depth;
        stats->build_seconds = as.build_seconds > 0 ? as.build_seconds : t_built - t0;
        double t_end = clock_seconds();
        stats->wall_seconds = t_end - t0;
        stats->render_seconds = t_end - t_built;
        stats->threads = started + 1;
    }
    // A time limit ends the render after a whole pass: every pixel has the samples of the passes that ran.
    int passes_run = job.grid.pass_count;
    for (int p = 1; job.deadline > 0.0 && p < job.grid.pass_count; p++)
        if (atomic_load(&job.pass_decision[p]) == PASS_SKIP) {
            passes_run = p;
            break;
        }
    uint64_t pixels = job.total_samples / (uint64_t)s->settings.spp; // of the region rendered
    bool timed_out =
        passes_run < job.grid.pass_count && total.samples == pixels * (uint64_t)job.grid.pass_start[passes_run];
    if (stats) stats->spp = s->settings.spp;
    if (stats) stats->spp_done = total.samples == job.total_samples ? s->settings.spp
                                 : timed_out                      ? job.grid.pass_start[passes_run]
                                                                  : 0;
    free(workers);
    *out = film_take_image(&job.film);
    job_free(&job);
    frame_release(&frame);
    atomic_store(&stop_requested, 0); // this render has answered any stop request made so far
    if (total.samples < job.total_samples && !timed_out) {
        snprintf(err->message, sizeof err->message, "interrupted after %llu of %llu samples",
                 (unsigned long long)total.samples, (unsigned long long)job.total_samples);
        return GLINT_ERR_INTERRUPTED;
    }
    return GLINT_OK;
}
