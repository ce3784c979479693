// preview.c — the preview window: frames converted to 8 bits on the render's progress thread, handed over through
// three buffers and drawn by SDL2 on the main thread (SDL's video functions belong to the thread that opened it).
#include "preview.h"
#include "cli.h"
#include "signals.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef GLINT_HAVE_SDL2
#include <SDL.h>
#if defined(GLINT_HAVE_X11)
#include <X11/Xlib.h>
#endif
#include <math.h>
#include <pthread.h>

enum {
    WAIT_MS = 100,          // the event loop also looks at the render and the signals this often
    MIN_WINDOW_SIDE = 256,  // a small image is shown enlarged (by a whole factor) to at least this
    CONVERT_SHARE_INV = 50, // converting a frame may take 1/50 of one core's time: skip frames beyond that
};

struct cli_preview {
    SDL_Window *window; ///< NULL once the user closed it
    SDL_Renderer *renderer;
    SDL_Texture *texture;
    int width, height;
    char name[256];
    Uint32 wake_event;  ///< an SDL user event that wakes the event loop: a new frame, the render's end
    // The live frames: the progress thread converts into `spare`, then swaps it with `ready` under the lock;
    // the main thread swaps `ready` with `shown` and uploads that. Nobody converts or uploads under the lock.
    pthread_mutex_t lock;
    uint8_t *spare, *ready, *shown;
    bool fresh;         ///< ready holds a frame not shown yet (under lock)
    bool news;          ///< spp_done and fraction changed (under lock)
    bool wakeable;      ///< the window exists: the progress thread may wake its event loop (under lock)
    bool stopping;      ///< the user closed the window during the render: it is hidden until the render ends
    int spp_done;       ///< under lock
    double fraction;    ///< under lock
    double next_convert; ///< the progress thread's: monotonic time before which live frames are skipped
    atomic_int render_done;
};

// The stop signals, blocked in every thread but the main one: SDL's and the render's threads inherit the mask
// of the thread that starts them, so a signal always lands where the event loop will see its effect.
static void block_signals(sigset_t *old) {
    sigset_t set;
    cli_stop_signals(&set);
    pthread_sigmask(SIG_BLOCK, &set, old);
}

static void restore_signals(const sigset_t *old) { pthread_sigmask(SIG_SETMASK, old, NULL); }

static bool env_set(const char *name) {
    const char *v = getenv(name);
    return v && *v;
}

static bool has_display(void) { return env_set("DISPLAY") || env_set("WAYLAND_DISPLAY"); }

// Starts SDL's video on the display the environment names: X11 for DISPLAY, else Wayland. SDL left to itself
// would fall back to a window nobody sees (its offscreen driver) when the display cannot be reached. The user's
// SDL_VIDEODRIVER, when set, is obeyed instead.
#if defined(GLINT_HAVE_X11)
// Xlib's default error handler ends the program with status 1, and SDL hands its errors on to it: a request SDL
// makes to a window the server has just destroyed (around a close) must not end a render that went well.
static int ignore_x_error(Display *d, XErrorEvent *e) {
    (void)d;
    (void)e;
    return 0;
}
#endif

// X errors no longer end the program (harmless where SDL uses another driver: no X display is opened). Called
// before SDL starts X11 too: SDL's own handler passes errors on to the one it found installed, so with this one
// installed first no X error reaches Xlib's default handler, whichever handler is in force while SDL_Quit closes
// the display (and reads the last errors, such as a wakeup sent to a window just destroyed).
static void keep_x_errors_quiet(void) {
#if defined(GLINT_HAVE_X11)
    XSetErrorHandler(ignore_x_error);
#endif
}

static bool start_video(const char **why) {
    if (env_set("SDL_VIDEODRIVER")) {
        if (SDL_Init(SDL_INIT_VIDEO) == 0) return true;
        *why = SDL_GetError();
        return false;
    }
    static const char *const drivers[][2] = {{"DISPLAY", "x11"}, {"WAYLAND_DISPLAY", "wayland"}};
    for (size_t i = 0; i < sizeof drivers / sizeof drivers[0]; i++) {
        if (!env_set(drivers[i][0])) continue;
        SDL_SetHint(SDL_HINT_VIDEODRIVER, drivers[i][1]);
        if (SDL_Init(SDL_INIT_VIDEO) == 0) return true;
        *why = SDL_GetError();
    }
    return false;
}

// The window's first size: the image at a whole enlargement up to MIN_WINDOW_SIDE, or shrunk to fit the screen.
static void window_size(int width, int height, int *w, int *h) {
    SDL_Rect usable;
    int max_w = 1920, max_h = 1080;
    if (SDL_GetDisplayUsableBounds(0, &usable) == 0 && usable.w > 0 && usable.h > 0) {
        max_w = usable.w - usable.w / 20; // room for the window's frame
        max_h = usable.h - usable.h / 10;
    }
    double s = fmin((double)max_w / width, (double)max_h / height);
    if (s >= 1.0) {
        double grow = ceil((double)MIN_WINDOW_SIDE / (width > height ? width : height));
        s = fmin(floor(s), grow > 1.0 ? grow : 1.0);
    }
    *w = (int)(width * s) > 0 ? (int)(width * s) : 1;
    *h = (int)(height * s) > 0 ? (int)(height * s) : 1;
}

static void free_frames(cli_preview *p) {
    free(p->spare);
    free(p->ready);
    free(p->shown);
}

static void destroy_window(cli_preview *p) {
    if (p->texture) SDL_DestroyTexture(p->texture);
    if (p->renderer) SDL_DestroyRenderer(p->renderer);
    if (p->window) SDL_DestroyWindow(p->window);
    p->texture = NULL;
    p->renderer = NULL;
    p->window = NULL;
}

// Opens SDL and the window; false with SDL's reason in *why.
static bool open_window(cli_preview *p, const char **why) {
    // glint's own handlers keep SIGINT and SIGTERM (the partial image is written); the software renderer draws
    // one image a few times a second without loading OpenGL and starting its driver's threads (Mesa's llvmpipe
    // starts one a core). SDL_RENDER_DRIVER and SDL_FRAMEBUFFER_ACCELERATION override.
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
    SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0"); // the window's pixels straight to X, not through OpenGL
    keep_x_errors_quiet();
    if (!start_video(why)) return false;
    keep_x_errors_quiet(); // in place of SDL's, which would pass them on to Xlib's default
    int w, h;
    window_size(p->width, p->height, &w, &h);
    p->window = SDL_CreateWindow("glint", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, w, h,
                                 SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
    if (p->window) p->renderer = SDL_CreateRenderer(p->window, -1, 0);
    if (p->renderer)
        p->texture = SDL_CreateTexture(p->renderer, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, p->width,
                                       p->height);
    if (!p->texture) {
        *why = SDL_GetError();
        destroy_window(p);
        SDL_Quit();
        return false;
    }
    SDL_UpdateTexture(p->texture, NULL, p->shown, p->width * 3); // black until the first frame
    p->wake_event = SDL_RegisterEvents(1);
    return true;
}

cli_preview *cli_preview_open(const char *name, int width, int height, bool quiet) {
    const char *why = NULL;
    cli_preview *p = NULL;
    if (!has_display()) {
        why = "no display (DISPLAY and WAYLAND_DISPLAY are unset)";
    } else if (width <= 0 || height <= 0 || !(p = calloc(1, sizeof *p))) {
        why = "out of memory";
    } else {
        size_t bytes = (size_t)width * (size_t)height * 3u;
        p->width = width;
        p->height = height;
        snprintf(p->name, sizeof p->name, "%s", name);
        p->spare = calloc(bytes, 1);
        p->ready = calloc(bytes, 1);
        p->shown = calloc(bytes, 1);
        sigset_t old;
        block_signals(&old);
        bool opened = p->spare && p->ready && p->shown && open_window(p, &why);
        restore_signals(&old);
        if (!why && !opened) why = "out of memory for its frames";
        if (opened) {
            pthread_mutex_init(&p->lock, NULL);
            atomic_init(&p->render_done, 0);
            p->wakeable = true;
            return p;
        }
    }
    if (!quiet && p) {
        const char *x = getenv("DISPLAY"), *wayland = getenv("WAYLAND_DISPLAY");
        fprintf(stderr, "glint: --preview: cannot open a window on %s '%s' (SDL: %s); rendering without a window\n",
                env_set("DISPLAY") ? "DISPLAY" : "WAYLAND_DISPLAY", env_set("DISPLAY") ? x : wayland, why);
    } else if (!quiet) {
        fprintf(stderr, "glint: --preview: %s; rendering without a window\n", why);
    }
    if (p) free_frames(p);
    free(p);
    return NULL;
}

// Draws the shown frame, centred: enlarged by a whole factor when it fits, else shrunk (smoothly) to fit.
static void draw(cli_preview *p) {
    if (!p->window) return;
    int ow, oh;
    if (SDL_GetRendererOutputSize(p->renderer, &ow, &oh) != 0 || ow <= 0 || oh <= 0) return;
    double s = fmin((double)ow / p->width, (double)oh / p->height);
    if (s >= 1.0) s = floor(s);
    SDL_SetTextureScaleMode(p->texture, s >= 1.0 ? SDL_ScaleModeNearest : SDL_ScaleModeLinear);
    int dw = (int)(p->width * s), dh = (int)(p->height * s);
    SDL_Rect dst = {(ow - dw) / 2, (oh - dh) / 2, dw > 0 ? dw : 1, dh > 0 ? dh : 1};
    SDL_SetRenderDrawColor(p->renderer, 40, 40, 40, 255);
    SDL_RenderClear(p->renderer);
    SDL_RenderCopy(p->renderer, p->texture, NULL, &dst);
    SDL_RenderPresent(p->renderer);
}

static void set_title(cli_preview *p, const char *status) {
    char title[512];
    snprintf(title, sizeof title, "%s - %s - glint", p->name, status);
    SDL_SetWindowTitle(p->window, title);
}

// Takes what the progress thread handed over: a new frame to upload, new numbers for the title.
static void refresh(cli_preview *p) {
    pthread_mutex_lock(&p->lock);
    bool fresh = p->fresh, news = p->news;
    if (fresh) {
        uint8_t *t = p->ready;
        p->ready = p->shown;
        p->shown = t;
        p->fresh = false;
    }
    int spp = p->spp_done;
    double fraction = p->fraction;
    p->news = false;
    pthread_mutex_unlock(&p->lock);
    if (!p->window) return;
    // The picture before the title: whoever reads a title knows the picture drawn before it (the tests do).
    if (fresh) {
        SDL_UpdateTexture(p->texture, NULL, p->shown, p->width * 3);
        draw(p);
    }
    if (news) {
        char status[96];
        snprintf(status, sizeof status, "%d %% - %d spp", (int)(fraction * 100.0), spp);
        set_title(p, status);
    }
}

void cli_preview_live_image(const glint_image *img, int spp_done, double fraction_done, void *user) {
    cli_preview *p = user;
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    double now = cli_now();
    bool convert = w == p->width && h == p->height && now >= p->next_convert;
    if (convert) {
        glint_image_rgb8(img, p->spare);
        double took = cli_now() - now;
        p->next_convert = now + took * CONVERT_SHARE_INV;
    }
    pthread_mutex_lock(&p->lock);
    if (convert) {
        uint8_t *t = p->spare;
        p->spare = p->ready;
        p->ready = t;
        p->fresh = true;
    }
    p->spp_done = spp_done;
    p->fraction = fraction_done;
    p->news = true;
    // Under the lock: SDL wakes a waiting event loop by sending an X event to its window, which must not be
    // one the main thread has just destroyed.
    if (p->wakeable && p->wake_event != (Uint32)-1) {
        SDL_Event ev;
        memset(&ev, 0, sizeof ev);
        ev.type = p->wake_event;
        SDL_PushEvent(&ev);
    }
    pthread_mutex_unlock(&p->lock);
}

// Closes the window of an opened preview: first the progress thread stops waking it.
static void close_window(cli_preview *p) {
    pthread_mutex_lock(&p->lock);
    p->wakeable = false;
    pthread_mutex_unlock(&p->lock);
    destroy_window(p);
}

// Handles one event; true when it asks to close the window (Esc, Q, the window's close button).
static bool wants_close(cli_preview *p, const SDL_Event *ev) {
    switch (ev->type) {
    case SDL_QUIT: return true;
    case SDL_KEYDOWN: return ev->key.keysym.sym == SDLK_ESCAPE || ev->key.keysym.sym == SDLK_q;
    case SDL_WINDOWEVENT:
        if (ev->window.event == SDL_WINDOWEVENT_CLOSE) return true;
        if (ev->window.event == SDL_WINDOWEVENT_EXPOSED || ev->window.event == SDL_WINDOWEVENT_SIZE_CHANGED) draw(p);
        return false;
    default: return false;
    }
}

// Waits up to WAIT_MS for events and handles all that came; true when one asked to close the window.
static bool pump_events(cli_preview *p) {
    SDL_Event ev;
    bool close = false;
    if (!SDL_WaitEventTimeout(&ev, WAIT_MS)) return false;
    do close |= wants_close(p, &ev);
    while (SDL_PollEvent(&ev));
    return close;
}

typedef struct render_thread {
    cli_preview *preview;
    void (*render)(void *);
    void *arg;
} render_thread;

static void *render_main(void *arg) {
    render_thread *t = arg;
    t->render(t->arg);
    atomic_store(&t->preview->render_done, 1);
    SDL_Event ev;
    memset(&ev, 0, sizeof ev);
    ev.type = t->preview->wake_event;
    if (t->preview->wake_event != (Uint32)-1) SDL_PushEvent(&ev);
    return NULL;
}

void cli_preview_run(cli_preview *p, void (*render)(void *), void *arg, glint_cancel *cancel) {
    render_thread t = {p, render, arg};
    pthread_t thread;
    sigset_t old;
    block_signals(&old);
    bool started = pthread_create(&thread, NULL, render_main, &t) == 0;
    restore_signals(&old);
    if (!started) { // no thread to be had: render here, the window shows the final image alone
        render_main(&t);
        return;
    }
    draw(p);
    set_title(p, "starting");
    while (!atomic_load(&p->render_done)) {
        if (pump_events(p) && p->window && !p->stopping) {
            glint_cancel_request(cancel); // as Ctrl-C: the render ends soon and the program writes what it has
            // Hidden, not destroyed, while the render's threads run: SDL wakes this loop from them by sending
            // an X event to the window, and one sent to a destroyed window ends the program (BadWindow).
            SDL_HideWindow(p->window);
            p->stopping = true;
        }
        refresh(p);
    }
    pthread_join(thread, NULL);
    if (p->stopping) close_window(p);
}

bool cli_preview_is_open(const cli_preview *p) { return p && p->window; }

void cli_preview_hold(cli_preview *p, const glint_image *img, const char *status, const atomic_int *signalled) {
    if (!cli_preview_is_open(p)) return;
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    if (w == p->width && h == p->height) {
        glint_image_rgb8(img, p->shown);
        SDL_UpdateTexture(p->texture, NULL, p->shown, p->width * 3);
    }
    draw(p);
    set_title(p, status);
    while (!atomic_load(signalled) && !pump_events(p)) {}
    close_window(p);
}

void cli_preview_close(cli_preview *p) {
    if (!p) return;
    close_window(p);
    SDL_Quit();
    pthread_mutex_destroy(&p->lock);
    free_frames(p);
    free(p);
}

#else // built without SDL2: --preview says so and the program renders on

cli_preview *cli_preview_open(const char *name, int width, int height, bool quiet) {
    (void)name;
    (void)width;
    (void)height;
    if (!quiet) fprintf(stderr, "glint: --preview: this glint was built without SDL2 (no window); rendering "
                                "without a window\n");
    return NULL;
}

// Never called: no preview is ever opened, so none of these is reached with a preview.
void cli_preview_live_image(const glint_image *img, int spp_done, double fraction_done, void *user) {
    (void)img;
    (void)spp_done;
    (void)fraction_done;
    (void)user;
}

void cli_preview_run(cli_preview *p, void (*render)(void *), void *arg, glint_cancel *cancel) {
    (void)p;
    (void)cancel;
    render(arg);
}

bool cli_preview_is_open(const cli_preview *p) {
    (void)p;
    return false;
}

void cli_preview_hold(cli_preview *p, const glint_image *img, const char *status, const atomic_int *signalled) {
    (void)p;
    (void)img;
    (void)status;
    (void)signalled;
}

void cli_preview_close(cli_preview *p) { (void)p; }

#endif
