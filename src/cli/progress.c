// progress.c — the progress bar (percentage, elapsed time, ETA) and the closing statistics line, on stderr (the
// bar on another terminal stream if asked).
#include "cli.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

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

// The terminal's width in columns (TIOCGWINSZ on the bar's stream), asked at every draw so that a resize is
// followed; 80 when it does not say.
static int terminal_columns(FILE *f) {
    struct winsize ws;
    if (ioctl(fileno(f), TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
    return 80;
}

// Follows the rate of work (fraction per second) from report to report, smoothed over about RATE_SECONDS:
// measured on the render itself (from the first report on, so the scene preparation and BVH build before it
// do not count), over all of it at first, then weighted towards the recent past as the cost of a sample
// changes (passes of 16, 16, 32, ... or 1, 1, 2, ... samples: early ones pay more per sample for visiting every
// tile).
static void update_rate(cli_progress *p, double now, double fraction) {
    enum { RATE_SECONDS = 5 };
    if (p->last_time > 0.0 && now > p->last_time && fraction >= p->last_fraction) {
        double dt = now - p->last_time, r = (fraction - p->last_fraction) / dt;
        p->measured += dt;
        // Weight of the newest interval: all of the measure so far at first (a plain mean), then dt / RATE_SECONDS.
        double w = dt / (p->measured < RATE_SECONDS ? p->measured : RATE_SECONDS);
        p->rate += (w < 1.0 ? w : 1.0) * (r - p->rate);
    }
    p->last_time = now;
    p->last_fraction = fraction;
}

void cli_progress_draw(double fraction, void *user) {
    enum { MIN_MEASURE_SECONDS = 1 }; // no ETA before a second of rendering has been measured
    cli_progress *p = user;
    FILE *out = p->stream ? p->stream : stderr;
    if (!(fraction > 0.0)) fraction = 0.0;
    if (fraction > 1.0) fraction = 1.0;
    double now = cli_now();
    update_rate(p, now, fraction);
    char el[32], eta[32] = "?", tail[96];
    format_duration(now - p->start, el, sizeof el);
    if (fraction >= 1.0) format_duration(0.0, eta, sizeof eta);
    else if (p->measured >= MIN_MEASURE_SECONDS && p->rate > 0.0)
        format_duration((1.0 - fraction) / p->rate, eta, sizeof eta);
    int percent = (int)(fraction * 100.0);
    int tail_len = snprintf(tail, sizeof tail, "] %3d%%  %s elapsed, ETA %s", percent, el, eta);
    // Never the last column: a character there makes some terminals wrap, and the bar must stay on one line.
    int room = terminal_columns(out) - 1;
    int width = room - 1 - tail_len; // "[" + bar + tail
    if (width > BAR_WIDTH) width = BAR_WIDTH;
    // \r returns to the line's start and ESC[K clears what a longer previous line left behind.
    if (width >= 5) {
        char bar[BAR_WIDTH + 1];
        int filled = (int)(fraction * width);
        for (int i = 0; i < width; i++) bar[i] = i < filled ? '#' : '-';
        fprintf(out, "\r[%.*s%s\033[K", width, bar, tail);
    } else { // too narrow for a bar: the numbers alone, cut to fit
        int n = snprintf(tail, sizeof tail, "%3d%% ETA %s", percent, eta);
        fprintf(out, "\r%.*s\033[K", n < room ? n : (room > 0 ? room : 0), tail);
    }
    fflush(out);
    p->drawn = true;
}

void cli_progress_clear(cli_progress *p) {
    if (!p->drawn) return;
    FILE *out = p->stream ? p->stream : stderr;
    fputs("\r\033[K", out);
    fflush(out);
    p->drawn = false;
}

void cli_progress_finish(cli_progress *p) {
    if (!p->drawn) return;
    cli_progress_draw(1.0, p);
    FILE *out = p->stream ? p->stream : stderr;
    fputc('\n', out);
    fflush(out);
    p->drawn = false;
}

// Four significant figures without an exponent (0.7314, 11.24, 734.2, 1234): the benchmarks take their ratios from
// this line, and three figures (11.2) would round a rate by up to 0.5 %, a step as large as what they measure.
static void format_rate(double v, char *buf, size_t size) {
    snprintf(buf, size, v >= 999.95 ? "%.0f" : v >= 99.995 ? "%.1f" : v >= 9.9995 ? "%.2f" : "%.3f", v);
}

void cli_print_stats(const cli_program *prog, const glint_render_stats *st, const char *output, double write_seconds) {
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
    fprintf(stderr, "%s: %.3f s wall, %s Msamples/s, %s Mrays/s (%d thread%s), %s, build %s", prog->name,
            st->wall_seconds, samples, rays, st->threads, st->threads == 1 ? "" : "s", bvh, build);
    if (st->discarded_samples > 0)
        fprintf(stderr, ", %" PRIu64 " NaN/infinite sample%s discarded", st->discarded_samples,
                st->discarded_samples == 1 ? "" : "s");
    if (!output) fputs("; no image", stderr);
    else if (strcmp(output, "-") == 0) fputs("; image on standard output", stderr);
    else fprintf(stderr, "; image %s", output);
    if (output && write_seconds >= 0.0) fprintf(stderr, ", written in %.3f s", write_seconds);
    fputc('\n', stderr);
}

bool cli_warn_discarded(const cli_program *prog, const glint_render_stats *st) {
    if (st->discarded_samples == 0) return false;
    // samples counts every sample taken, the dropped ones included
    double share = st->samples ? (double)st->discarded_samples / (double)st->samples : 1.0;
    fprintf(stderr, "%s: warning: %llu of %llu samples (%.1f %%) were NaN or infinite and were dropped\n", prog->name,
            (unsigned long long)st->discarded_samples, (unsigned long long)st->samples, 100.0 * share);
    return share > CLI_MAX_DISCARDED_SHARE;
}

void cli_print_interrupted(const cli_program *prog, const glint_image *img, uint64_t samples, const char *output) {
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    // The mean to one decimal when it is a whole number; else to as many digits as it takes not to look
    // whole (255 of 256 pixels done: 0.996, not 1.0).
    unsigned long long pixels = (unsigned long long)w * (unsigned long long)h, done = samples;
    double mean = (double)done / (double)pixels;
    char shown[32];
    int digits = 1;
    snprintf(shown, sizeof shown, "%.1f", mean);
    while (done % pixels && digits < 12 && fmod(strtod(shown, NULL), 1.0) == 0.0)
        snprintf(shown, sizeof shown, "%.*f", ++digits, mean);
    fprintf(stderr, "%s: interrupted; writing the %s samples per pixel completed so far to %s\n", prog->name, shown,
            output);
}
