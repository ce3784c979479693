// preview.h — the preview window (--preview): the image as it converges, drawn by SDL2 on the main thread while
// the render runs on another, in the display encoding of the output file.
#ifndef GLINT_CLI_PREVIEW_H
#define GLINT_CLI_PREVIEW_H

#include "glint.h"

#include <stdatomic.h>
#include <stdbool.h>

/// A preview window and the frames handed to it.
typedef struct cli_preview cli_preview;

/// Opens a window for a width x height image, titled after `name` (the scene file's name); NULL, having said why
/// on stderr unless `quiet`, when there is no window to be had: a glint built without SDL2, no display
/// (DISPLAY and WAYLAND_DISPLAY unset), or SDL cannot open one. The program then renders without a window.
cli_preview *cli_preview_open(const char *name, int width, int height, bool quiet);

/// A glint_live_image_fn (user: the preview): converts the image into the window's next frame, skipping calls so
/// that converting takes at most about 2 % of one core, and wakes the window's thread.
void cli_preview_live_image(const glint_image *img, int spp_done, double fraction_done, void *user);

/// Runs render(arg) on a thread of its own (the stop signals blocked there, so that this thread alone hears
/// them) while this thread runs the window: Esc or closing the window requests `cancel` (the render's token) and closes it.
/// Returns when render has returned.
void cli_preview_run(cli_preview *p, void (*render)(void *), void *arg, glint_cancel *cancel);

/// Whether the window is still open (neither closed by the user nor unavailable).
bool cli_preview_is_open(const cli_preview *p);

/// Shows the final image with `status` in the title and waits until the window is closed, Esc or Q is pressed,
/// or *signalled becomes non-zero (a stop signal arrived).
void cli_preview_hold(cli_preview *p, const glint_image *img, const char *status, const atomic_int *signalled);

/// Closes the window and frees the preview (NULL is allowed).
void cli_preview_close(cli_preview *p);

#endif
