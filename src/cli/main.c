// main.c — the glint command: parse flags, load the scene, render with a progress bar, write the image;
// SIGINT/SIGTERM stop the render and keep the samples completed so far.
#include "cli.h"
#include "glint.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs a lock-free atomic int");

static atomic_int first_signal; // the signal that asked the render to stop, 0 while none has

// First SIGINT/SIGTERM: ask the render to stop (it then writes what it has). Second: die at once, by the
// signal's default action, so the shell sees the usual status. No temporary file can be left behind then:
// none exists while rendering, and signals are blocked while the image is written.
static void on_signal(int sig) {
    int expected = 0;
    if (atomic_compare_exchange_strong(&first_signal, &expected, sig)) {
        glint_request_stop();
        return;
    }
    static const char msg[] = "\nglint: interrupted again, aborting\n";
    ssize_t ignored = write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)ignored;
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, NULL);
    raise(sig); // delivered as soon as this handler returns
}

// Installed even when the signal was inherited as ignored (as `glint ... &` in a script does to SIGINT),
// so that a harness can always interrupt a render and get its partial image.
static void install_signal_handlers(void) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

// Holds SIGINT/SIGTERM back while a file is being written, so that a rename never races an abort.
static void block_stop_signals(void) {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
}

// The conventional status of a program stopped by a signal: 128 + its number (130 for SIGINT).
static int interrupted_status(void) {
    int sig = atomic_load(&first_signal);
    return 128 + (sig ? sig : SIGINT);
}

static int exit_code(glint_status st) { return st == GLINT_ERR_INPUT ? 2 : 1; }

// Reads standard input as a scene: at most GLINT_MAX_SCENE_BYTES + 1 bytes, one more than a scene may have,
// so that a larger input (even an endless one) is refused without reading or holding the rest. NULL on
// failure, with the message in *err and the status in *st (GLINT_ERR_RENDER when memory runs out).
static char *read_stdin(size_t *length, glint_status *st, glint_error *err) {
    const size_t most = GLINT_MAX_SCENE_BYTES + 1;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, stdin);
        if (n < cap || cap == most) break;
        size_t bigger = cap > most / 2 ? most : cap * 2;
        char *grown = realloc(buf, bigger);
        if (!grown) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap = bigger;
    }
    *st = GLINT_ERR_INPUT;
    if (!buf || (ferror(stdin) && errno == ENOMEM)) {
        snprintf(err->message, sizeof err->message, "standard input: out of memory while reading the scene");
        *st = GLINT_ERR_RENDER;
    } else if (ferror(stdin)) {
        snprintf(err->message, sizeof err->message, "standard input: cannot read the scene");
    } else if (n > GLINT_MAX_SCENE_BYTES) {
        snprintf(err->message, sizeof err->message, "standard input: the scene is larger than %zu bytes (%zu MiB)",
                 GLINT_MAX_SCENE_BYTES, GLINT_MAX_SCENE_BYTES >> 20);
    } else {
        *length = n;
        return buf;
    }
    free(buf);
    return NULL;
}

static glint_status load_scene(const char *path, glint_scene **scene, glint_error *err) {
    if (strcmp(path, "-") != 0) return glint_scene_load(path, scene, err);
    size_t length = 0;
    glint_status st;
    char *text = read_stdin(&length, &st, err);
    if (!text) return st;
    st = glint_scene_parse("<stdin>", text, length, scene, err);
    free(text);
    return st;
}

int main(int argc, char **argv) {
    cli_options opt;
    cli_action action = cli_parse(argc, argv, &opt);
    if (action != CLI_RUN) return (int)action;

    glint_error err;
    glint_format format = opt.ascii_ppm ? GLINT_FORMAT_PPM_ASCII : GLINT_FORMAT_AUTO;
    // Before the render, not after it: a typo in -o must not cost a long render.
    glint_status st = glint_image_check_path(opt.output, format, &err);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        return exit_code(st);
    }

    install_signal_handlers();
    glint_scene *scene = NULL;
    st = load_scene(opt.scene_path, &scene, &err);
    if (st == GLINT_OK) st = glint_scene_override(scene, &opt.overrides, &err);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_scene_free(scene);
        return exit_code(st);
    }
    // The library never prints: what it worked around in mesh files is reported here, unless --quiet.
    for (size_t i = 0; !opt.quiet && i < glint_scene_warning_count(scene); i++)
        fprintf(stderr, "glint: %s\n", glint_scene_warning(scene, i));
    if (atomic_load(&first_signal)) { // stopped before the render began: there is nothing to write
        glint_scene_free(scene);
        return interrupted_status();
    }

    cli_progress bar = {.start = cli_now(), .drawn = false};
    bool show_progress = !opt.quiet && isatty(STDERR_FILENO);
    glint_render_options ropt = {.threads = opt.threads};
    glint_image *img = NULL;
    glint_render_stats stats;
    memset(&stats, 0, sizeof stats);
    st = glint_render(scene, &ropt, show_progress ? cli_progress_draw : NULL, &bar, &img, &stats, &err);
    glint_scene_free(scene);
    cli_progress_clear(&bar);
    if (st != GLINT_OK && st != GLINT_ERR_INTERRUPTED) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_image_free(img);
        return exit_code(st);
    }
    if (!opt.quiet) cli_print_stats(&stats);

    bool interrupted = st == GLINT_ERR_INTERRUPTED;
    if (interrupted && stats.samples == 0) {
        if (!opt.quiet) fprintf(stderr, "glint: interrupted before any sample was rendered, no image written\n");
        glint_image_free(img);
        return interrupted_status();
    }
    if (interrupted && !opt.quiet) {
        int w, h;
        const float *rgb;
        glint_image_info(img, &w, &h, &rgb);
        // The mean to one decimal when it is a whole number; else to as many digits as it takes not to look
        // whole (255 of 256 pixels done: 0.996, not 1.0).
        unsigned long long pixels = (unsigned long long)w * (unsigned long long)h, done = stats.samples;
        double mean = (double)done / (double)pixels;
        char shown[32];
        int digits = 1;
        snprintf(shown, sizeof shown, "%.1f", mean);
        while (done % pixels && digits < 12 && fmod(strtod(shown, NULL), 1.0) == 0.0)
            snprintf(shown, sizeof shown, "%.*f", ++digits, mean);
        fprintf(stderr, "glint: interrupted; writing the %s samples per pixel completed so far to %s\n", shown, opt.output);
    }

    if (strcmp(opt.output, "-") != 0) block_stop_signals();
    st = glint_image_write(img, opt.output, format, &err);
    glint_image_free(img);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        return exit_code(st);
    }
    return interrupted ? interrupted_status() : 0;
}
