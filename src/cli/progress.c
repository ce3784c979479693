// progress.c — the progress bar (percentage, elapsed time, ETA) and the closing statistics line, on stderr.
#include "cli.h"

#include <inttypes.h>
#include <stdio.h>
#include <time.h>

enum { BAR_WIDTH = 30 };

double cli_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// "12.3 s" below a minute, "4:05" below an hour, "1:02:03" beyond.
static void format_duration(double seconds, char *buf, size_t size) {
    if (seconds < 59.95) {
        snprintf(buf, size, "%.1f s", seconds);
        return;
    }
    long t = (long)(seconds + 0.5);
    if (t < 3600) snprintf(buf, size, "%ld:%02ld", t / 60, t % 60);
    else snprintf(buf, size, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
}

void cli_progress_draw(double fraction, void *user) {
    cli_progress *p = user;
    if (!(fraction > 0.0)) fraction = 0.0;
    if (fraction > 1.0) fraction = 1.0;
    double elapsed = cli_now() - p->start;
    char bar[BAR_WIDTH + 1];
    int filled = (int)(fraction * BAR_WIDTH);
    for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '#' : '-';
    bar[BAR_WIDTH] = '\0';
    char el[32], eta[32] = "?";
    format_duration(elapsed, el, sizeof el);
    // Samples cost about the same everywhere, so the rate so far predicts the rest.
    if (fraction > 0.0) format_duration(elapsed * (1.0 - fraction) / fraction, eta, sizeof eta);
    // \r returns to the line's start and ESC[K clears what a longer previous line left behind.
    fprintf(stderr, "\r[%s] %3d%%  %s elapsed, ETA %s\033[K", bar, (int)(fraction * 100.0), el, eta);
    fflush(stderr);
    p->drawn = true;
}

void cli_progress_clear(cli_progress *p) {
    if (!p->drawn) return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    p->drawn = false;
}

// Three significant figures without an exponent: 0.731, 11.2, 734.
static void format_rate(double v, char *buf, size_t size) {
    snprintf(buf, size, v >= 99.95 ? "%.0f" : v >= 9.995 ? "%.1f" : "%.2f", v);
}

void cli_print_stats(const glint_render_stats *st) {
    // Rates over the render loop alone (as the Embree yardstick counts): scene preparation, the BVH build
    // in the first place, is reported on its own.
    double wall = st->render_seconds > 1e-9 ? st->render_seconds : 1e-9;
    char samples[32], rays[32], bvh[96], build[32];
    format_rate((double)st->samples / wall * 1e-6, samples, sizeof samples);
    // Every ray query counts, closest-hit and shadow alike (the benchmarks' definition of rays/s).
    format_rate((double)(st->rays + st->shadow_rays) / wall * 1e-6, rays, sizeof rays);
    if (st->bvh_nodes > 0 || st->bvh_leaves > 0) // a small scene may be one leaf and no inner node
        snprintf(bvh, sizeof bvh, "BVH %" PRIu64 " nodes %" PRIu64 " leaves depth %" PRIu64, st->bvh_nodes,
                 st->bvh_leaves, st->bvh_depth);
    else snprintf(bvh, sizeof bvh, "no BVH (brute force)");
    if (st->build_seconds < 1.0) snprintf(build, sizeof build, "%.1f ms", st->build_seconds * 1e3);
    else snprintf(build, sizeof build, "%.2f s", st->build_seconds);
    fprintf(stderr, "glint: %.3f s wall, %s Msamples/s, %s Mrays/s (%d thread%s), %s, build %s", st->wall_seconds,
            samples, rays, st->threads, st->threads == 1 ? "" : "s", bvh, build);
    if (st->discarded_samples > 0)
        fprintf(stderr, ", %" PRIu64 " NaN/infinite sample%s discarded", st->discarded_samples,
                st->discarded_samples == 1 ? "" : "s");
    fputc('\n', stderr);
}

bool cli_warn_discarded(const glint_render_stats *st) {
    if (st->discarded_samples == 0) return false;
    // samples counts every sample taken, the dropped ones included
    double share = st->samples ? (double)st->discarded_samples / (double)st->samples : 1.0;
    fprintf(stderr, "glint: warning: %llu of %llu samples (%.1f %%) were NaN or infinite and were dropped\n",
            (unsigned long long)st->discarded_samples, (unsigned long long)st->samples, 100.0 * share);
    return share > CLI_MAX_DISCARDED_SHARE;
}
