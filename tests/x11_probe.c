// x11_probe.c — what tests/cli/preview.sh needs of an X server: find glint's window by its title, read its title,
// compare its pixels with an image file, count its lit pixels, press a key in it and close it as a window
// manager would. Talks to the server through Xlib only (libx11, which SDL2 brings), reads PNG through libpng.
//
//   x11_probe find TEXT SECONDS        prints the id of a viewable window whose title contains TEXT
//   x11_probe title WIN TEXT SECONDS   waits until the window's title contains TEXT; prints the title
//   x11_probe compare WIN FILE.png     0 when the image's pixels appear in the window exactly, at some offset (within
//                                      5 s: the picture reaches the server on its own path, perhaps after the title)
//   x11_probe grab WIN FILE.ppm        writes the window's pixels as a binary PPM (to look at after a failure)
//   x11_probe lit WIN MIN SECONDS      waits until more than MIN of the window's pixels are brighter than 48 in a
//                                      channel; prints how many are
//   x11_probe key WIN NAME             presses and releases the key NAME (an X keysym name: Escape, q)
//   x11_probe close WIN                asks the window to close (WM_DELETE_WINDOW), as a title bar's button does
// Exit status: 0 success, 1 not found, timed out or different, 2 usage or X errors.
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <png.h>

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int ignore_errors(Display *d, XErrorEvent *e) {
    (void)d;
    (void)e;
    return 0; // a window may vanish between two requests: the next poll will see it
}

static void sleep_ms(long ms) {
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// The window's title (UTF-8 _NET_WM_NAME as SDL sets it, else WM_NAME) into buf; false when it has none.
static bool window_title(Display *d, Window w, char *buf, size_t size) {
    Atom utf8 = XInternAtom(d, "UTF8_STRING", False), net_name = XInternAtom(d, "_NET_WM_NAME", False);
    Atom type;
    int format;
    unsigned long n, left;
    unsigned char *data = NULL;
    buf[0] = '\0';
    if (XGetWindowProperty(d, w, net_name, 0, 1024, False, utf8, &type, &format, &n, &left, &data) == Success && data) {
        snprintf(buf, size, "%s", (char *)data);
        XFree(data);
        return true;
    }
    char *name = NULL;
    if (XFetchName(d, w, &name) && name) {
        snprintf(buf, size, "%s", name);
        XFree(name);
        return true;
    }
    return false;
}

// Searches the tree under `w` (a window manager may reparent) for a viewable window whose title holds text.
static Window find_window(Display *d, Window w, const char *text, int depth) {
    char title[1024];
    XWindowAttributes a;
    if (depth > 0 && XGetWindowAttributes(d, w, &a) && a.map_state == IsViewable &&
        window_title(d, w, title, sizeof title) && strstr(title, text))
        return w;
    Window root, parent, *children = NULL, found = 0;
    unsigned int n = 0;
    if (depth < 3 && XQueryTree(d, w, &root, &parent, &children, &n)) {
        for (unsigned int i = 0; i < n && !found; i++) found = find_window(d, children[i], text, depth + 1);
        if (children) XFree(children);
    }
    return found;
}

// The window's pixels as 8-bit RGB (malloc'ed), its size in *w, *h; NULL when it cannot be read.
static uint8_t *grab(Display *d, Window win, int *w, int *h) {
    XWindowAttributes a;
    if (!XGetWindowAttributes(d, win, &a) || a.map_state != IsViewable) return NULL;
    XImage *img = XGetImage(d, win, 0, 0, (unsigned)a.width, (unsigned)a.height, AllPlanes, ZPixmap);
    if (!img) return NULL;
    uint8_t *rgb = malloc((size_t)a.width * (size_t)a.height * 3u);
    unsigned long masks[3] = {img->red_mask, img->green_mask, img->blue_mask};
    for (int y = 0; rgb && y < a.height; y++)
        for (int x = 0; x < a.width; x++) {
            unsigned long px = XGetPixel(img, x, y);
            for (int c = 0; c < 3; c++) {
                unsigned long m = masks[c], v = px & m;
                while (m && !(m & 1)) m >>= 1, v >>= 1;
                rgb[((size_t)y * (size_t)a.width + (size_t)x) * 3u + (size_t)c] = (uint8_t)(m ? v * 255 / m : 0);
            }
        }
    XDestroyImage(img);
    *w = a.width;
    *h = a.height;
    return rgb;
}

// Whether the image (iw x ih) equals the window's pixels at (ox, oy); counts the differing pixels.
static long differences(const uint8_t *win, int ww, const uint8_t *im, int iw, int ih, int ox, int oy, long stop) {
    long n = 0;
    for (int y = 0; y < ih && n < stop; y++)
        n += memcmp(win + ((size_t)(y + oy) * (size_t)ww + (size_t)ox) * 3u, im + (size_t)y * (size_t)iw * 3u,
                    (size_t)iw * 3u) != 0;
    return n;
}

// The 8-bit RGB values stored in a PNG file, as they are: no gamma conversion (libpng's simplified API would
// convert a linear file's values to sRGB). NULL when it is no 8-bit RGB PNG.
static uint8_t *read_png_rgb8(const char *path, int *w, int *h) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile rgb = NULL;
    if (info && !setjmp(png_jmpbuf(png))) {
        png_init_io(png, f);
        png_read_png(png, info, PNG_TRANSFORM_STRIP_16 | PNG_TRANSFORM_STRIP_ALPHA | PNG_TRANSFORM_EXPAND, NULL);
        png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
        png_bytepp rows = png_get_rows(png, info);
        if (png_get_color_type(png, info) == PNG_COLOR_TYPE_RGB && (rgb = malloc((size_t)width * height * 3u))) {
            for (png_uint_32 y = 0; y < height; y++) memcpy(rgb + (size_t)y * width * 3u, rows[y], (size_t)width * 3u);
            *w = (int)width;
            *h = (int)height;
        }
    }
    png_destroy_read_struct(&png, info ? &info : NULL, NULL);
    fclose(f);
    return rgb;
}

static int compare(Display *d, Window win, const char *path) {
    int ww, wh, iw, ih;
    uint8_t *im = read_png_rgb8(path, &iw, &ih);
    if (!im) {
        fprintf(stderr, "x11_probe: %s: cannot read it as an 8-bit RGB PNG\n", path);
        return 2;
    }
    // The window's pixels until they match (the last grab is judged): a renderer may present after the title.
    uint8_t *pix = NULL;
    for (double end = now_seconds() + 5.0;;) {
        free(pix);
        pix = grab(d, win, &ww, &wh);
        if (!pix || ww < iw || wh < ih || now_seconds() > end) break;
        bool same = false;
        for (int oy = 0; oy <= wh - ih && !same; oy++)
            for (int ox = 0; ox <= ww - iw && !same; ox++) same = differences(pix, ww, im, iw, ih, ox, oy, 1) == 0;
        if (same) break;
        sleep_ms(50);
    }
    int status = 1;
    if (!pix) fprintf(stderr, "x11_probe: cannot read the window's pixels\n");
    else if (ww < iw || wh < ih) fprintf(stderr, "x11_probe: the window (%dx%d) is smaller than %s (%dx%d)\n", ww, wh, path, iw, ih);
    else {
        long best = -1;
        int bx = 0, by = 0;
        for (int oy = 0; oy <= wh - ih && best != 0; oy++)
            for (int ox = 0; ox <= ww - iw && best != 0; ox++) {
                long n = differences(pix, ww, im, iw, ih, ox, oy, best < 0 ? ih + 1 : best);
                if (best < 0 || n < best) best = n, bx = ox, by = oy;
            }
        if (best == 0) {
            printf("the window (%dx%d) shows %s (%dx%d) exactly at +%d+%d\n", ww, wh, path, iw, ih, bx, by);
            status = 0;
        } else {
            fprintf(stderr, "x11_probe: the window (%dx%d) does not show %s (%dx%d): at best %ld rows differ (+%d+%d)\n",
                    ww, wh, path, iw, ih, best, bx, by);
        }
    }
    free(pix);
    free(im);
    return status;
}

static int lit(Display *d, Window win, long min, double seconds) {
    long n = -1;
    for (double end = now_seconds() + seconds;; sleep_ms(50)) {
        int w, h;
        uint8_t *pix = grab(d, win, &w, &h);
        if (!pix) return 2;
        n = 0;
        for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
            n += pix[3 * i] > 48 || pix[3 * i + 1] > 48 || pix[3 * i + 2] > 48;
        free(pix);
        if (n > min || now_seconds() > end) break;
    }
    printf("%ld\n", n);
    return n > min ? 0 : 1;
}

static int grab_to_file(Display *d, Window win, const char *path) {
    int w, h;
    uint8_t *pix = grab(d, win, &w, &h);
    FILE *f = pix ? fopen(path, "wb") : NULL;
    bool ok = f && fprintf(f, "P6\n%d %d\n255\n", w, h) > 0 && fwrite(pix, 3, (size_t)w * (size_t)h, f) == (size_t)w * (size_t)h;
    if (f && fclose(f) != 0) ok = false;
    free(pix);
    return ok ? 0 : 2;
}

static int key(Display *d, Window win, const char *name) {
    KeySym sym = XStringToKeysym(name);
    if (sym == NoSymbol) return 2;
    XSetInputFocus(d, win, RevertToParent, CurrentTime);
    XKeyEvent e;
    memset(&e, 0, sizeof e);
    e.display = d;
    e.window = win;
    e.root = DefaultRootWindow(d);
    e.same_screen = True;
    e.keycode = XKeysymToKeycode(d, sym);
    e.time = CurrentTime;
    e.type = KeyPress;
    XSendEvent(d, win, True, KeyPressMask, (XEvent *)&e);
    e.type = KeyRelease;
    XSendEvent(d, win, True, KeyReleaseMask, (XEvent *)&e);
    XSync(d, False);
    return 0;
}

static int close_window(Display *d, Window win) {
    XEvent e;
    memset(&e, 0, sizeof e);
    e.xclient.type = ClientMessage;
    e.xclient.window = win;
    e.xclient.message_type = XInternAtom(d, "WM_PROTOCOLS", False);
    e.xclient.format = 32;
    e.xclient.data.l[0] = (long)XInternAtom(d, "WM_DELETE_WINDOW", False);
    e.xclient.data.l[1] = CurrentTime;
    XSendEvent(d, win, False, NoEventMask, &e);
    XSync(d, False);
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: x11_probe find TEXT SECONDS | title WIN TEXT SECONDS | compare WIN FILE.png | "
                        "grab WIN FILE.ppm | lit WIN MIN SECONDS | key WIN NAME | close WIN\n");
        return 2;
    }
    Display *d = XOpenDisplay(NULL);
    if (!d) {
        fprintf(stderr, "x11_probe: cannot open the display\n");
        return 2;
    }
    XSetErrorHandler(ignore_errors);
    const char *cmd = argv[1];
    int status = 2;
    if (strcmp(cmd, "find") == 0 && argc == 4) {
        double end = now_seconds() + atof(argv[3]);
        Window w = 0;
        while (!(w = find_window(d, DefaultRootWindow(d), argv[2], 0)) && now_seconds() < end) sleep_ms(50);
        if (w) printf("%lu\n", (unsigned long)w);
        status = w ? 0 : 1;
    } else if (strcmp(cmd, "title") == 0 && argc == 5) {
        Window w = strtoul(argv[2], NULL, 0);
        double end = now_seconds() + atof(argv[4]);
        char title[1024];
        bool ok;
        while (!(ok = window_title(d, w, title, sizeof title) && strstr(title, argv[3])) && now_seconds() < end)
            sleep_ms(50);
        printf("%s\n", title);
        status = ok ? 0 : 1;
    } else if (strcmp(cmd, "compare") == 0 && argc == 4) {
        status = compare(d, strtoul(argv[2], NULL, 0), argv[3]);
    } else if (strcmp(cmd, "grab") == 0 && argc == 4) {
        status = grab_to_file(d, strtoul(argv[2], NULL, 0), argv[3]);
    } else if (strcmp(cmd, "lit") == 0 && argc == 5) {
        status = lit(d, strtoul(argv[2], NULL, 0), atol(argv[3]), atof(argv[4]));
    } else if (strcmp(cmd, "key") == 0 && argc == 4) {
        status = key(d, strtoul(argv[2], NULL, 0), argv[3]);
    } else if (strcmp(cmd, "close") == 0 && argc == 3) {
        status = close_window(d, strtoul(argv[2], NULL, 0));
    } else {
        fprintf(stderr, "x11_probe: unknown command or wrong arguments: %s\n", cmd);
    }
    XCloseDisplay(d);
    return status;
}
