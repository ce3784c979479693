// main.c — the glint command: parse flags, load the scene, render with a progress bar, write the image;
// SIGINT/SIGTERM/SIGHUP stop the render and keep the samples completed so far.
#include "cli.h"
#include "glint.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs a lock-free atomic int");

static atomic_int first_signal; // the signal that asked the render to stop, 0 while none has
static atomic_int loading;      // 1 while the scene is read: a signal then ends the program at once
static bool quiet_signals;      // --quiet, set before the handlers are installed

// The signals that stop a render: Ctrl-C, kill, and the terminal going away (the session ending).
static const int STOP_SIGNALS[] = {SIGINT, SIGTERM, SIGHUP};
enum { STOP_SIGNAL_COUNT = sizeof STOP_SIGNALS / sizeof STOP_SIGNALS[0] };

// While loading: nothing exists yet to write or to clean up, and the read may be blocked on a FIFO or a pipe
// that never ends, so say what happened and leave at once. During the render, the first signal asks it to
// stop (it then writes what it has); the second dies at once, by the signal's default action, so the shell
// sees the usual status. No temporary file can be left behind then: none exists while rendering, and signals
// are blocked while the image is written.
static void on_signal(int sig) {
    if (atomic_load(&loading)) {
        static const char msg[] = "glint: interrupted while loading the scene\n";
        if (!quiet_signals) {
            ssize_t ignored = write(STDERR_FILENO, msg, sizeof msg - 1);
            (void)ignored;
        }
        _exit(128 + sig);
    }
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
    for (int i = 0; i < STOP_SIGNAL_COUNT; i++) sigaction(STOP_SIGNALS[i], &sa, NULL);
}

// Holds the stop signals back while a file is being written, so that a rename never races an abort.
static void block_stop_signals(void) {
    sigset_t set;
    sigemptyset(&set);
    for (int i = 0; i < STOP_SIGNAL_COUNT; i++) sigaddset(&set, STOP_SIGNALS[i]);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
}

// The conventional status of a program stopped by a signal: 128 + its number (130 for SIGINT).
static int interrupted_status(void) {
    int sig = atomic_load(&first_signal);
    return 128 + (sig ? sig : SIGINT);
}

static const char NOTHING_RENDERED[] = "glint: interrupted before any sample was rendered, no image written\n";

static int exit_code(glint_status st) { return st == GLINT_ERR_INPUT ? 2 : 1; }

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "merge") == 0) return cli_merge(argc, argv);
    cli_options opt;
    cli_action action = cli_parse(&CLI_GLINT, argc, argv, &opt);
    if (action != CLI_RUN) return (int)action;

    glint_error err;
    glint_format format = opt.ascii_ppm ? GLINT_FORMAT_PPM_ASCII : opt.half ? GLINT_FORMAT_EXR_HALF : GLINT_FORMAT_AUTO;
    // Before the render, not after it: a typo in -o must not cost a long render.
    glint_status st = glint_image_check_path(opt.output, format, &err);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        return exit_code(st);
    }
    if (cli_output_is_scene(opt.output, opt.scene_path)) {
        fprintf(stderr, "glint: %s: cannot write: it is the scene file, which would be lost\n", opt.output);
        return exit_code(GLINT_ERR_INPUT);
    }

    quiet_signals = opt.quiet;
    atomic_store(&loading, 1);
    install_signal_handlers();
    glint_scene *scene = NULL;
    st = cli_load_scene(opt.scene_path, &scene, &err);
    atomic_store(&loading, 0);
    if (st == GLINT_OK) st = glint_scene_override(scene, &opt.overrides, &err);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_scene_free(scene);
        return exit_code(st);
    }
    // Nor any other file the scene was read from: a mesh, a texture, an environment map.
    if (glint_scene_reads_file(scene, opt.output)) {
        fprintf(stderr, "glint: %s: cannot write: the scene reads it (a mesh, texture or environment map), which "
                        "would be lost\n", opt.output);
        glint_scene_free(scene);
        return exit_code(GLINT_ERR_INPUT);
    }
    // The library never prints: what it worked around in mesh files is reported here, unless --quiet.
    for (size_t i = 0; !opt.quiet && i < glint_scene_warning_count(scene); i++)
        fprintf(stderr, "glint: %s\n", glint_scene_warning(scene, i));
    if (atomic_load(&first_signal)) { // stopped before the render began: there is nothing to write
        glint_scene_free(scene);
        if (!opt.quiet) fprintf(stderr, "%s", NOTHING_RENDERED);
        return interrupted_status();
    }

    cli_progress bar = {.start = cli_now(), .drawn = false};
    bool show_progress = !opt.quiet && isatty(STDERR_FILENO);
    glint_render_options ropt = {.threads = opt.threads, .time_limit = (double)opt.time_limit};
    memcpy(ropt.region, opt.region, sizeof ropt.region);
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
    bool interrupted = st == GLINT_ERR_INTERRUPTED;
    if (!opt.quiet) cli_print_stats(&CLI_GLINT, &stats, interrupted && stats.samples == 0 ? NULL : opt.output);
    // A render that lost more than a small share of its samples is wrong, but its image is still written.
    bool lost = cli_warn_discarded(&CLI_GLINT, &stats);
    if (st == GLINT_OK && stats.spp_done < stats.spp && !opt.quiet)
        fprintf(stderr, "glint: time limit of %ld s reached: %d of %d samples per pixel rendered\n", opt.time_limit,
                stats.spp_done, stats.spp);

    if (interrupted && stats.samples == 0) {
        if (!opt.quiet) fprintf(stderr, "%s", NOTHING_RENDERED);
        glint_image_free(img);
        return interrupted_status();
    }
    if (interrupted && !opt.quiet) cli_print_interrupted(&CLI_GLINT, img, stats.samples, opt.output);

    if (strcmp(opt.output, "-") != 0) block_stop_signals();
    st = glint_image_write(img, opt.output, format, &err);
    glint_image_free(img);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        return exit_code(st);
    }
    return interrupted ? interrupted_status() : lost ? 1 : 0;
}
