// test_sampler.c — the Sobol' sampler converges to what independent samples converge to: for every path-traced
// scene in scenes/, at a small size, the image mean with "sobol" lies within the noise of the mean with
// "independent" (the noise measured from two independent renders of different seeds); the Whitted scenes ignore the
// sampler, byte for byte.
#include "check.h"
#include "test_load.h"
#include "glint.h"
#include "scene/scene.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 32, H = 24, SPP = 64 };

// The scene at W x H and SPP samples with the given sampler and seed, rendered on two threads; NULL on failure.
static glint_image *render(const char *path, const char *sampler, long seed, bool *path_traced) {
    glint_scene *s = test_load(path, NULL);
    if (!s) return NULL;
    *path_traced = s->settings.integrator == INTEGRATOR_PATH;
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = W;
    o.height = H;
    o.spp = *path_traced ? SPP : 1;
    o.seed = seed;
    o.sampler = sampler;
    glint_image *img = NULL;
    glint_render_options opt = {.threads = 2};
    glint_error err;
    if (glint_scene_override(s, &o, &err) != GLINT_OK || glint_render(s, &opt, NULL, NULL, &img, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        glint_image_free(img);
        img = NULL;
    }
    glint_scene_free(s);
    return img;
}

// A pixel's value: the sum of its channels.
static double pixel(const float *rgb, int i) { return (double)rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]; }

static void test_scene(const char *name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/scenes/%s", GLINT_SOURCE_DIR, name);
    bool path_traced = false;
    glint_image *sobol = render(path, "sobol", 1, &path_traced);
    glint_image *ind1 = render(path, "independent", 1, &path_traced);
    glint_image *ind2 = path_traced ? render(path, "independent", 2, &path_traced) : NULL;
    CHECK(sobol && ind1 && (ind2 || !path_traced));
    if (!sobol || !ind1 || (path_traced && !ind2)) goto done;
    const float *a, *b, *c = NULL;
    int w, h;
    glint_image_info(sobol, &w, &h, &a);
    glint_image_info(ind1, &w, &h, &b);
    if (!path_traced) { // the Whitted integrators draw PCG32 whatever the sampler says
        CHECK(memcmp(a, b, (size_t)w * (size_t)h * 3 * sizeof *a) == 0);
        goto done;
    }
    glint_image_info(ind2, &w, &h, &c);
    // Pixels' errors are independent (per-pixel seeds and shuffles): the variance of the image mean of one render
    // is the sum of its pixels' variances over P^2, and the difference of two independent renders' pixel p has
    // twice pixel p's variance.
    double mean_sobol = 0, mean_ind = 0, d2 = 0;
    int n = w * h;
    for (int i = 0; i < n; i++) {
        mean_sobol += pixel(a, i) / n;
        mean_ind += pixel(b, i) / n;
        d2 += (pixel(b, i) - pixel(c, i)) * (pixel(b, i) - pixel(c, i));
    }
    double se = sqrt(d2 / 2.0) / n; // one render's standard error, independent samples (Sobol's is lower)
    double allowed = 6.0 * sqrt(2.0) * se + 1e-4 * fabs(mean_ind);
    printf("%-30s mean sobol %.5f, independent %.5f (standard error %.5f): %.2f sigma\n", name, mean_sobol, mean_ind,
           se, se > 0 ? fabs(mean_sobol - mean_ind) / (sqrt(2.0) * se) : 0.0);
    if (!(fabs(mean_sobol - mean_ind) <= allowed)) fprintf(stderr, "%s: the means differ beyond the noise\n", name);
    CHECK(fabs(mean_sobol - mean_ind) <= allowed);
done:
    glint_image_free(sobol);
    glint_image_free(ind1);
    glint_image_free(ind2);
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

int main(void) {
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/scenes", GLINT_SOURCE_DIR);
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    if (!d) return check_summary();
    char *names[256];
    int count = 0;
    for (struct dirent *e; (e = readdir(d)) && count < 256;) {
        size_t len = strlen(e->d_name);
        if (len > 5 && strcmp(e->d_name + len - 5, ".json") == 0) names[count++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, (size_t)count, sizeof names[0], by_name);
    CHECK(count > 10);
    for (int i = 0; i < count; i++) {
        test_scene(names[i]);
        free(names[i]);
    }
    return check_summary();
}
