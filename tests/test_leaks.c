// test_leaks.c — no light leaks through closed mirrors: a camera inside a closed mirror box or sphere (metal,
// albedo 1) under a white background must see exact black, at every scale, depth and integrator.
#include "check.h"
#include "glint.h"

#include <stdio.h>
#include <string.h>

// The scales the enclosures are built at: from a millimetre box to one ten kilometres wide.
static const double SCALES[] = {1e-3, 1e-2, 1.0, 100.0, 1e4};
// Depths: the Whitted default's neighbourhood, and the largest the format allows.
static const int DEPTHS[] = {2, 10000};
static const char *const INTEGRATORS[] = {"\"whitted\"", "\"path\""};

// Renders the scene text; returns how many pixel channels are not exactly 0 (-1 when it cannot render).
static long lit_channels(const char *text) {
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_parse("leak.json", text, strlen(text), &s, &err) != GLINT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return -1;
    }
    glint_render_options opt = {.threads = 2};
    glint_image *img = NULL;
    glint_render_stats stats;
    long lit = -1;
    if (glint_render(s, &opt, NULL, NULL, &img, &stats, &err) == GLINT_OK) {
        int w, h;
        const float *rgb;
        glint_image_info(img, &w, &h, &rgb);
        lit = 0;
        for (size_t i = 0; i < (size_t)w * (size_t)h * 3u; i++) lit += rgb[i] != 0.0f;
    } else {
        fprintf(stderr, "  render failed: %s\n", err.message);
    }
    glint_image_free(img);
    glint_scene_free(s);
    return lit;
}

// The render settings every enclosure shares: a small image, white background, the given depth and
// integrator.
static int settings(char *buf, size_t n, const char *integrator, int depth) {
    return snprintf(buf, n,
                    "{\"render\":{\"width\":10,\"height\":10,\"spp\":4,\"max_depth\":%d,\"integrator\":%s,"
                    "\"background\":1},\"materials\":{\"mirror\":{\"type\":\"metal\",\"albedo\":1}},",
                    depth, integrator);
}

// Renders the enclosure described by `objects` (with camera `camera`) under every integrator and depth and
// checks that it is black; `what` names it in failure messages.
static void check_black(const char *what, double scale, const char *camera, const char *objects) {
    for (size_t i = 0; i < sizeof INTEGRATORS / sizeof *INTEGRATORS; i++)
        for (size_t d = 0; d < sizeof DEPTHS / sizeof *DEPTHS; d++) {
            char text[2048];
            int k = settings(text, sizeof text, INTEGRATORS[i], DEPTHS[d]);
            snprintf(text + k, sizeof text - (size_t)k, "%s,%s}", camera, objects);
            long lit = lit_channels(text);
            CHECK(lit == 0);
            if (lit != 0)
                fprintf(stderr, "  %s at scale %g, integrator %s, depth %d: %ld lit channels\n", what, scale,
                        INTEGRATORS[i], DEPTHS[d], lit);
        }
}

// A camera off-centre in a closed mirror box (six quads sharing their edges exactly), looking at an edge
// region so that reflections meet faces near edges and corners (the issue's scene, scaled).
static void test_mirror_box(void) {
    for (size_t i = 0; i < sizeof SCALES / sizeof *SCALES; i++) {
        double k = SCALES[i];
        char camera[512], objects[512];
        snprintf(camera, sizeof camera,
                 "\"camera\":{\"type\":\"lookat\",\"lookfrom\":[%.9g,%.9g,%.9g],\"lookat\":[%.9g,%.9g,%.9g],"
                 "\"vfov\":70}",
                 0.1 * k, 0.2 * k, 0.3 * k, 0.3 * k, -0.2 * k, -k);
        snprintf(objects, sizeof objects,
                 "\"objects\":[{\"type\":\"box\",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g],"
                 "\"material\":\"mirror\"}]",
                 -k, -k, -k, k, k, k);
        check_black("mirror box", k, camera, objects);
    }
}

// A camera inside a mirror sphere seen from within: an enclosing sphere (positive radius, hit from inside)
// and the same with a negative radius (the normal turned inward), neither centred on the camera.
static void test_mirror_sphere(void) {
    for (size_t i = 0; i < sizeof SCALES / sizeof *SCALES; i++)
        for (int sign = 1; sign >= -1; sign -= 2) {
            double k = SCALES[i];
            char camera[512], objects[512];
            snprintf(camera, sizeof camera,
                     "\"camera\":{\"type\":\"lookat\",\"lookfrom\":[%.9g,%.9g,%.9g],\"lookat\":[%.9g,%.9g,%.9g],"
                     "\"vfov\":90}",
                     0.3 * k, -0.1 * k, 0.2 * k, 0.5 * k, 0.4 * k, -k);
            snprintf(objects, sizeof objects,
                     "\"objects\":[{\"type\":\"sphere\",\"center\":[%.9g,%.9g,%.9g],\"radius\":%.9g,"
                     "\"material\":\"mirror\"}]",
                     0.05 * k, 0.1 * k, -0.07 * k, sign * k);
            check_black(sign > 0 ? "enclosing mirror sphere" : "negative-radius mirror sphere", k, camera, objects);
        }
}

int main(void) {
    test_mirror_box();
    test_mirror_sphere();
    return check_summary();
}
