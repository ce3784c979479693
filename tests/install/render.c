// render.c — a client of the installed library that uses <glint.h> alone: parse (with load options), render,
// check, write, free.
#include <glint.h>

#include <stdio.h>
#include <string.h>

// A tiny path-traced scene under the book's sky: every pixel sees the sky or a lit sphere, so an image
// with no bright pixel means the library rendered nothing.
static const char SCENE[] =
    "{\n"
    "  \"render\": {\"width\": 32, \"height\": 24, \"spp\": 4, \"max_depth\": 4, \"seed\": 1,\n"
    "             \"integrator\": \"path\", \"background\": \"sky\", \"output\": \"gamma2\"},\n"
    "  \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0.5, 2], \"lookat\": [0, 0, -1], \"vfov\": 60},\n"
    "  \"materials\": {\"blue\": {\"type\": \"lambertian\", \"albedo\": [0.2, 0.3, 0.8]}},\n"
    "  \"objects\": [\n"
    "    {\"type\": \"sphere\", \"center\": [0, 0, -1], \"radius\": 0.5, \"material\": \"blue\"},\n"
    "    {\"type\": \"sphere\", \"center\": [0, -100.5, -1], \"radius\": 100, \"material\": \"blue\"}\n"
    "  ]\n"
    "}\n";

static int fail(const char *what, const glint_error *err) {
    fprintf(stderr, "render: %s: %s\n", what, err ? err->message : "");
    return 1;
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: render OUTPUT.ppm\n");
        return 2;
    }
    printf("glint %s\n", glint_version());
    glint_error err;
    glint_scene *scene = NULL;
    glint_load_options load = {.threads = 2};
    if (glint_scene_parse_with("inline.json", SCENE, strlen(SCENE), &load, &scene, &err) != GLINT_OK)
        return fail("glint_scene_parse_with", &err);
    int width = 0, height = 0;
    glint_scene_size(scene, &width, &height);
    if (width != 32 || height != 24) {
        glint_scene_free(scene);
        return fail("glint_scene_size: not the scene's 32x24", NULL);
    }

    glint_render_options opt = {.threads = 2};
    glint_render_stats stats;
    glint_image *img = NULL;
    glint_status st = glint_render(scene, &opt, NULL, NULL, &img, &stats, &err);
    glint_scene_free(scene);
    if (st != GLINT_OK) {
        glint_image_free(img);
        return fail("glint_render", &err);
    }

    int bright = 0;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++)
            for (int c = 0; c < 3; c++) bright += glint_image_byte(img, x, y, c) > 16;
    if (bright == 0) {
        glint_image_free(img);
        return fail("the image is all black", NULL);
    }

    st = glint_image_write(img, argv[1], GLINT_FORMAT_AUTO, &err);
    glint_image_free(img);
    if (st != GLINT_OK) return fail("glint_image_write", &err);
    printf("%dx%d, %d of %d channels bright, %llu samples, written to %s\n", width, height, bright,
           width * height * 3, (unsigned long long)stats.samples, argv[1]);
    return 0;
}
