// test_envmap.c — environment lights: the direction-to-texel mapping and its documented orientation, the
// sampling distribution (its density agrees with the texel it draws from, and importance-sampled estimates
// of the map's integral are exact in expectation and tight), .hdr files read through the scene reader, and
// a diffuse plane under an environment converging to its closed-form radiance with and without light sampling.
#include "check.h"
#include "test_util.h"

#include "glint.h"
#include "light/envmap.h"
#include "render/render.h"
#include "scene/scene.h"

#include <math.h>
#include <stb_image_write.h>

static const double PI = 3.14159265358979323846;

// A W x H map whose texel (c, r) holds (c, r, 1) + base, so that a lookup says which texel it read.
static image_rgb index_image(int w, int h, float base) {
    image_rgb img = {w, h, malloc((size_t)w * (size_t)h * 3 * sizeof(float)), NULL};
    for (int r = 0; r < h; r++)
        for (int c = 0; c < w; c++) {
            float *p = &img.pixels[((size_t)r * (size_t)w + (size_t)c) * 3];
            p[0] = (float)c + base;
            p[1] = (float)r + base;
            p[2] = 1.0f;
        }
    return img;
}

static bool texel_is(const envmap *e, vec3 d, int col, int row) {
    vec3 l = envmap_radiance(e, v3_unit(d));
    return l.x == (float)col && l.y == (float)row;
}

// The orientation light/envmap.h documents: the centre looks towards -z, the top row is +y, +x is three
// quarters of the way across, +z at the edges; rotate turns it about +y (the centre towards -x at 90).
static void test_orientation(void) {
    envmap e = envmap_make(index_image(8, 4, 0.0f), 1.0f, 0.0f);
    CHECK(texel_is(&e, v3(0, 0.01f, -1), 4, 1));  // just above the horizon, straight ahead
    CHECK(texel_is(&e, v3(0, -0.01f, -1), 4, 2)); // just below
    CHECK(envmap_radiance(&e, v3(0, 1, 0)).y == 0.0f); // the zenith: the top row
    CHECK(texel_is(&e, v3(0.01f, -1, 0), 6, 3));  // the nadir: the bottom row
    CHECK(texel_is(&e, v3(1, 0.1f, -0.001f), 5, 1)); // +x: three quarters across (the border of columns 5, 6)
    CHECK(texel_is(&e, v3(1, 0.1f, 0.001f), 6, 1));
    CHECK(texel_is(&e, v3(-1, 0.1f, 0.001f), 1, 1)); // -x: a quarter across (the border of columns 1, 2)
    CHECK(texel_is(&e, v3(-1, 0.1f, -0.001f), 2, 1));
    CHECK(texel_is(&e, v3(0.001f, 0.1f, 1), 7, 1));   // +z: the right edge, and just past it the left
    CHECK(texel_is(&e, v3(-0.001f, 0.1f, 1), 0, 1));
    envmap_free(&e);
    envmap r = envmap_make(index_image(8, 4, 0.0f), 2.0f, 90.0f);
    vec3 l = envmap_radiance(&r, v3_unit(v3(-1, 0.01f, -0.001f)));
    CHECK(l.x == 8.0f && l.y == 2.0f); // the centre texel (4, 1), doubled by the scale, now seen towards -x
    envmap_free(&r);
}

// The density envmap_sample reports is the one envmap_pdf gives its direction, and the importance-sampled
// integral of the map's radiance over the sphere equals the exact sum of texel radiance times solid angle.
static void test_sampling(float degrees) {
    const int w = 16, h = 8;
    image_rgb img = index_image(w, h, 0.25f);
    img.pixels[(2 * w + 5) * 3 + 0] = 500.0f; // a small bright "sun" the distribution must find
    envmap e = envmap_make(img, 1.5f, degrees);
    envmap_sampler s;
    CHECK(envmap_sampler_build(&s, &e));
    double exact = 0.0; // integral of the red channel over the sphere
    for (int r = 0; r < h; r++)
        for (int c = 0; c < w; c++) {
            double omega = (2.0 * PI / w) * (cos(PI * r / h) - cos(PI * (r + 1) / h));
            exact += 1.5 * e.image.pixels[((size_t)r * w + (size_t)c) * 3] * omega;
        }
    rng g = rng_for_sample(3, 1, 4);
    const int n = 200000;
    double sum = 0.0, sum2 = 0.0;
    int pdf_mismatch = 0, not_unit = 0, radiance_mismatch = 0;
    for (int i = 0; i < n; i++) {
        vec3 wi, le;
        float pdf;
        if (!envmap_sample(&s, &e, rng_float(&g), rng_float(&g), &wi, &pdf, &le)) continue;
        double f = le.x / pdf;
        sum += f;
        sum2 += f * f;
        float p2 = envmap_pdf(&s, &e, wi);
        pdf_mismatch += fabsf(p2 - pdf) > 1e-3f * pdf;
        not_unit += fabsf(v3_len(wi) - 1.0f) > 1e-5f;
        vec3 l2 = envmap_radiance(&e, wi);
        radiance_mismatch += l2.x != le.x; // the texel drawn is the texel the direction looks up
    }
    double mean = sum / n, se = sqrt((sum2 / n - mean * mean) / n);
    printf("envmap integral (rotate %g): %.5f +- %.5f, exact %.5f; pdf mismatches %d, radiance mismatches %d\n",
           (double)degrees, mean, se, exact, pdf_mismatch, radiance_mismatch);
    CHECK_NEAR(mean, exact, 5.0 * se + 1e-9);
    CHECK(se < 0.002 * exact); // importance sampling by brightness: far tighter than uniform sampling
    CHECK(pdf_mismatch < n / 1000); // only directions on a texel's border can disagree, by rounding
    CHECK(radiance_mismatch < n / 1000);
    CHECK(not_unit == 0);
    envmap_sampler_release(&s);
    envmap_free(&e);
    // A black map has nothing to sample.
    image_rgb black = {2, 1, calloc(6, sizeof(float)), NULL};
    envmap b = envmap_make(black, 1.0f, 0.0f);
    CHECK(!envmap_sampler_build(&s, &b));
    envmap_free(&b);
}

// An up-facing Lambertian plane of albedo rho under an environment, seen from above: its radiance is
// rho / pi times the irradiance, here from a map that is L in one texel of the upper hemisphere and dim
// elsewhere above the horizon, black below: L dphi (sin^2 theta1 - sin^2 theta0) / 2 for the texel.
static void test_plane_under_envmap(void) {
    const int w = 8, h = 4;
    const double rho = 0.5, sun = 40.0, sky = 0.5;
    double exact = 0.0;
    for (int r = 0; r < h / 2; r++)
        for (int c = 0; c < w; c++) {
            double t0 = PI * r / h, t1 = PI * (r + 1) / h;
            double l = (r == 1 && c == 3) ? sun : sky;
            exact += rho / PI * l * (2.0 * PI / w) * (sin(t1) * sin(t1) - sin(t0) * sin(t0)) / 2.0;
        }
    double mean[2], se[2];
    for (int nee = 0; nee < 2; nee++) {
        glint_scene *s = scene_new("envmap-plane");
        s->settings.width = s->settings.height = 32;
        s->settings.spp = nee ? 16 : 128;
        s->settings.max_depth = 2; // the plane and then the sky: nothing else to bounce off
        s->settings.integrator = INTEGRATOR_PATH;
        s->settings.background = BACKGROUND_ENVMAP;
        s->camera.lookfrom = v3(0, 1, 0.001f);
        s->camera.lookat = v3(0, 0, 0);
        s->camera.vfov_degrees = 1.0f;
        image_rgb img = {w, h, calloc((size_t)w * h * 3, sizeof(float)), NULL};
        for (int r = 0; r < h / 2; r++)
            for (int c = 0; c < w; c++)
                for (int k = 0; k < 3; k++)
                    img.pixels[((size_t)r * w + (size_t)c) * 3 + (size_t)k] = (float)((r == 1 && c == 3) ? sun : sky);
        s->environment = envmap_make(img, 1.0f, 30.0f); // rotating the map changes nothing for a flat plane
        material m = material_default(MAT_LAMBERTIAN);
        m.albedo = v3s((float)rho);
        long mi = scene_add_material(s, &m, NULL);
        quad q;
        CHECK(quad_make(v3(-5, 0, 5), v3(10, 0, 0), v3(0, 0, -10), (uint32_t)mi, &q));
        CHECK(scene_add_quad(s, q));
        render_options opt = {.threads = 0, .integrator = {.no_light_sampling = !nee}};
        glint_image *out = NULL;
        render_stats st;
        glint_error err;
        CHECK(render_scene(s, &opt, NULL, NULL, &out, &st, &err) == GLINT_OK);
        int iw, ih;
        const float *rgb;
        glint_image_info(out, &iw, &ih, &rgb);
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < iw * ih; i++) {
            sum += rgb[i * 3];
            sum2 += (double)rgb[i * 3] * rgb[i * 3];
        }
        mean[nee] = sum / (iw * ih);
        se[nee] = sqrt(fmax(0.0, sum2 / (iw * ih) - mean[nee] * mean[nee]) / (iw * ih - 1));
        printf("plane under an envmap: %s: %.5f +- %.5f (exact %.5f), %llu shadow rays\n",
               nee ? "light sampling + MIS" : "BSDF sampling only", mean[nee], se[nee], exact,
               (unsigned long long)st.shadow_rays);
        CHECK(nee ? st.shadow_rays > 0 : st.shadow_rays == 0);
        CHECK(se[nee] < 0.01 * exact);
        CHECK_NEAR(mean[nee], exact, 5.0 * se[nee]);
        glint_image_free(out);
        scene_free(s);
    }
    CHECK(se[1] * sqrt(16.0) < 0.5 * se[0] * sqrt(128.0)); // per sample, light sampling is far less noisy
}

// The sampler's directions land in each texel as often as its density says: a chi-square test of the counts per
// texel against the texel's probability, envmap_pdf at its centre times the solid angle per unit (u, v) area
// there, 2 pi^2 sin(theta) / (W H) (directions are uniform in (u, v) within a texel, as in pbrt).
static void test_sampling_chi_square(void) {
    enum { W = 16, H = 8, N = 400000 };
    image_rgb img = index_image(W, H, 0.25f);
    img.pixels[(3 * W + 11) * 3 + 2] = 40.0f; // a bright texel (blue: red and green still say where it is)
    envmap e = envmap_make(img, 1.0f, 0.0f);
    envmap_sampler s;
    CHECK(envmap_sampler_build(&s, &e));
    static double count[H][W];
    memset(count, 0, sizeof count);
    rng g = rng_for_sample(11, 2, 5);
    for (int i = 0; i < N; i++) {
        vec3 wi, le;
        float pdf;
        if (!envmap_sample(&s, &e, rng_float(&g), rng_float(&g), &wi, &pdf, &le)) continue;
        vec3 l = envmap_radiance(&e, wi); // the index image says which texel the direction lies in
        int c = (int)lrintf(l.x - 0.25f), r = (int)lrintf(l.y - 0.25f);
        if (c >= 0 && c < W && r >= 0 && r < H) count[r][c] += 1.0;
    }
    double chi2 = 0.0, total = 0.0;
    int wrong_centre = 0;
    for (int r = 0; r < H; r++)
        for (int c = 0; c < W; c++) {
            double theta = PI * (r + 0.5) / H, phi = 2.0 * PI * ((c + 0.5) / W - 0.5);
            vec3 d = v3((float)(sin(theta) * sin(phi)), (float)cos(theta), (float)(-sin(theta) * cos(phi)));
            vec3 at = envmap_radiance(&e, d);
            wrong_centre += at.x != (float)c + 0.25f || at.y != (float)r + 0.25f;
            double expect = N * envmap_pdf(&s, &e, d) * 2.0 * PI * PI * sin(theta) / (W * H);
            total += expect;
            chi2 += (count[r][c] - expect) * (count[r][c] - expect) / expect;
        }
    printf("envmap sampling: chi-square %.1f over %d texels (%d dof), expected counts sum to %.0f of %d\n", chi2, W * H,
           W * H - 1, total, N);
    CHECK(wrong_centre == 0);
    CHECK_NEAR(total, N, 1e-3 * N);
    CHECK(chi2 < 200.0); // p < 1e-4 at 127 degrees of freedom is about 190
    envmap_sampler_release(&s);
    envmap_free(&e);
}

// A scene file names an .hdr file (read through stb_image) with its scale and rotation; bad files and
// values are errors with file:line:col.
static void test_scene_file(void) {
    float px[4 * 2 * 3];
    for (int i = 0; i < 24; i++) px[i] = (float)(i % 7) * 0.5f;
    CHECK(stbi_write_hdr(tmp_path("sky.hdr"), 4, 2, 3, px) != 0);
    CHECK(tmp_write(tmp_path("fake.hdr"), "P3\n1 1\n255\n0 0 0\n", 17));
    const char *good = "{\"render\": {\"integrator\": \"path\", \"background\": {\"type\": \"envmap\", \"file\": \"sky.hdr\","
                       " \"scale\": 2, \"rotate\": 45}}}";
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_parse(tmp_path("scene.json"), good, strlen(good), &s, &err) == GLINT_OK);
    if (s) {
        CHECK(s->settings.background == BACKGROUND_ENVMAP);
        CHECK(s->environment.image.width == 4 && s->environment.image.height == 2);
        CHECK(s->environment.scale == 2.0f);
        CHECK_NEAR(s->environment.rotate_cos, cos(PI / 4), 1e-6);
        glint_image *img = NULL;
        glint_render_options opt = {.threads = 1};
        CHECK(glint_scene_override(s, &(glint_overrides){8, 4, 2, 3, 1, NULL, NULL, NULL, -1.0}, &err) == GLINT_OK);
        CHECK(glint_render(s, &opt, NULL, NULL, &img, NULL, &err) == GLINT_OK);
        glint_image_free(img);
        glint_scene_free(s);
    }
    static const struct {
        const char *text, *message;
    } bad[] = {
        {"{\"render\": {\"background\": {\"type\": \"envmap\", \"file\": \"missing.hdr\"}}}",
         "1:54: environment map file \"missing.hdr\""},
        {"{\"render\": {\"background\": {\"type\": \"envmap\", \"file\": \"fake.hdr\"}}}",
         "1:54: environment map \"fake.hdr\": not an OpenEXR or Radiance .hdr image (expected a file starting with "
         "the bytes 76 2f 31 01, \"#?RADIANCE\" or \"#?RGBE\")"},
        {"{\"render\": {\"background\": {\"type\": \"envmap\", \"file\": \"sky.hdr\", \"scale\": -1}}}",
         "\"scale\""},
        {"{\"render\": {\"background\": {\"type\": \"envmap\"}}}", "missing required key \"file\""},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s = NULL;
        glint_status st = glint_scene_parse(tmp_path("scene.json"), bad[i].text, strlen(bad[i].text), &s, &err);
        bool ok = st == GLINT_ERR_INPUT && !s && strstr(err.message, bad[i].message) != NULL;
        if (!ok) fprintf(stderr, "bad envmap %zu: %s\n", i, err.message);
        CHECK(ok);
        glint_scene_free(s);
    }
}

int main(void) {
    if (!tmpdir_make("glint-envmap")) return 1;
    test_orientation();
    test_sampling(0.0f);
    test_sampling(-70.0f);
    test_sampling_chi_square();
    test_plane_under_envmap();
    test_scene_file();
    tmpdir_remove();
    return check_summary();
}
