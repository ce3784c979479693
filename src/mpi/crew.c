// crew.c — one rank's render threads between an inbox and an outbox of units.
#include "mpi/crew.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

// One of the crew's threads (an item of its pool's job): takes units from the inbox until the crew closes.
static void crew_main(void *arg, size_t index) {
    crew *c = arg;
    crew_thread *self = &c->threads[index];
    for (;;) {
        pthread_mutex_lock(&c->lock);
        while (!c->inbox && !c->closing) pthread_cond_wait(&c->work, &c->lock);
        if (c->closing) { // the end of the render, or a stop: what is still queued is not wanted
            pthread_mutex_unlock(&c->lock);
            return;
        }
        unit *u = c->inbox;
        c->inbox = u->next;
        if (!c->inbox) c->inbox_tail = NULL;
        pthread_mutex_unlock(&c->lock);

        memset(&u->stats, 0, sizeof u->stats);
        u->complete = !atomic_load(c->stop) &&
                      tiles_render_pass(c->grid, c->integrator, u->tile, u->pass, u->sums, u->means, c->stop,
                                        &u->stats, &self->samples);

        pthread_mutex_lock(&c->lock);
        u->next = c->outbox;
        c->outbox = u;
        pthread_cond_signal(&c->finished);
        pthread_mutex_unlock(&c->lock);
    }
}

unit *crew_unit_new(void) { return aligned_alloc(_Alignof(unit), sizeof(unit)); }

bool crew_start(crew *c, const tiles *grid, const integrator *it, const atomic_int *stop, int threads) {
    memset(c, 0, sizeof *c);
    c->grid = grid;
    c->integrator = it;
    c->stop = stop;
    c->threads = aligned_alloc(64, sizeof(crew_thread) * (size_t)threads);
    if (!c->threads) return false;
    memset(c->threads, 0, sizeof(crew_thread) * (size_t)threads);
    pthread_mutex_init(&c->lock, NULL);
    pthread_cond_init(&c->work, NULL);
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC); // crew_take's timeouts follow the monotonic clock
    pthread_cond_init(&c->finished, &attr);
    pthread_condattr_destroy(&attr);
    for (int i = 0; i < threads; i++) atomic_init(&c->threads[i].samples, 0);
    // A pool of `threads` threads besides this one, which talks to the other ranks meanwhile.
    c->pool = thread_pool_start(threads + 1);
    c->thread_count = c->pool ? thread_pool_size(c->pool) - 1 : 0;
    if (c->thread_count > 0) {
        thread_pool_post(c->pool, (size_t)c->thread_count, crew_main, c);
        return true;
    }
    crew_close(c);
    return false;
}

void crew_give(crew *c, unit *u) {
    u->next = NULL;
    pthread_mutex_lock(&c->lock);
    if (c->inbox_tail) c->inbox_tail->next = u;
    else c->inbox = u;
    c->inbox_tail = u;
    c->queued++;
    pthread_cond_signal(&c->work);
    pthread_mutex_unlock(&c->lock);
}

unit *crew_take(crew *c, double seconds) {
    pthread_mutex_lock(&c->lock);
    if (!c->outbox && seconds > 0.0) {
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        long ns = until.tv_nsec + (long)(seconds * 1e9);
        until.tv_sec += ns / 1000000000L;
        until.tv_nsec = ns % 1000000000L;
        int rc = 0;
        while (!c->outbox && rc != ETIMEDOUT) rc = pthread_cond_timedwait(&c->finished, &c->lock, &until);
    }
    unit *done = c->outbox;
    c->outbox = NULL;
    for (unit *u = done; u; u = u->next) c->queued--;
    pthread_mutex_unlock(&c->lock);
    return done;
}

int crew_queued(crew *c) {
    pthread_mutex_lock(&c->lock);
    int n = c->queued;
    pthread_mutex_unlock(&c->lock);
    return n;
}

static void free_units(unit *u) {
    while (u) {
        unit *next = u->next;
        free(u);
        u = next;
    }
}

void crew_close(crew *c) {
    pthread_mutex_lock(&c->lock);
    c->closing = true;
    pthread_cond_broadcast(&c->work);
    pthread_mutex_unlock(&c->lock);
    if (c->pool && c->thread_count > 0) thread_pool_wait(c->pool);
    thread_pool_stop(c->pool);
    c->pool = NULL;
    free_units(c->inbox);
    free_units(c->outbox);
    c->inbox = c->inbox_tail = c->outbox = NULL;
    pthread_cond_destroy(&c->finished);
    pthread_cond_destroy(&c->work);
    pthread_mutex_destroy(&c->lock);
    free(c->threads);
    c->threads = NULL;
    c->thread_count = 0;
}
