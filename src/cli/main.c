// main.c — the glint command: parse flags, load the scene, render, write the image.
#include "glint.h"

#include <stdio.h>

int main(int argc, char **argv) {
    if (argc < 2) { fprintf(stderr, "usage: glint [options] SCENE\n"); return 2; }
    glint_error err;
    glint_scene *scene;
    if (glint_scene_load(argv[1], &scene, &err) != GLINT_OK) { fprintf(stderr, "glint: %s\n", err.message); return 2; }
    glint_render_options opt = {0};
    glint_image *img;
    glint_render_stats st;
    glint_status s = glint_render(scene, &opt, NULL, NULL, &img, &st, &err);
    glint_scene_free(scene);
    if (s != GLINT_OK) { fprintf(stderr, "glint: %s\n", err.message); glint_image_free(img); return 1; }
    s = glint_image_write(img, "out.png", GLINT_FORMAT_AUTO, &err);
    glint_image_free(img);
    return s == GLINT_OK ? 0 : 1;
}
