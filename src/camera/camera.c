// camera.c — primary rays: the paper's viewport camera and the book's look-at camera with defocus blur.
#include "camera/camera.h"
#include "core/sampling.h"

#include <math.h>

camera camera_default(void) {
    camera c = {0};
    c.kind = CAMERA_LOOKAT;
    c.viewport_width = c.viewport_height = c.distance = 1.0;
    c.lookfrom = v3(0, 0, 0);
    c.lookat = v3(0, 0, -1);
    c.vup = v3(0, 1, 0);
    c.vfov_degrees = 90.0f;
    c.defocus_angle_degrees = 0.0f;
    c.focus_distance = 0.0f; // 0 = |lookfrom - lookat|
    return c;
}

void camera_prepare(camera *c, int width, int height) {
    c->image_width = width;
    c->image_height = height;
    if (c->kind == CAMERA_VIEWPORT) {
        // Film point (fx, fy) maps to the viewport at ((fx - W/2) Vw/W, (H/2 - fy) Vh/H, d).
        c->origin = v3((float)c->position[0], (float)c->position[1], (float)c->position[2]);
        c->pixel_du = v3((float)(c->viewport_width / width), 0, 0);
        c->pixel_dv = v3(0, (float)(-c->viewport_height / height), 0);
        c->pixel00 = v3_add(c->origin, v3((float)(-c->viewport_width / 2), (float)(c->viewport_height / 2),
                                         (float)c->distance));
        return;
    }
    const float pi = 3.14159265358979f;
    float focus = c->focus_distance > 0.0f ? c->focus_distance : v3_len(v3_sub(c->lookfrom, c->lookat));
    float h = tanf(c->vfov_degrees * pi / 360.0f);
    float vh = 2.0f * h * focus;
    float vw = vh * (float)width / (float)height;
    vec3 w = v3_unit(v3_sub(c->lookfrom, c->lookat));
    vec3 u = v3_unit(v3_cross(c->vup, w));
    vec3 v = v3_cross(w, u);
    c->origin = c->lookfrom;
    c->pixel_du = v3_scale(u, vw / (float)width);
    c->pixel_dv = v3_scale(v, -vh / (float)height);
    // Upper-left corner of the film on the focus plane.
    vec3 corner = v3_sub(c->lookfrom, v3_scale(w, focus));
    corner = v3_sub(corner, v3_scale(u, vw / 2));
    corner = v3_add(corner, v3_scale(v, vh / 2));
    c->pixel00 = corner;
    float radius = focus * tanf(c->defocus_angle_degrees * pi / 360.0f);
    c->defocus_u = v3_scale(u, radius);
    c->defocus_v = v3_scale(v, radius);
}

void camera_viewport_point(const camera *c, double fx, double fy, double out[3]) {
    double gx = fx - c->image_width / 2.0, gy = c->image_height / 2.0 - fy;
    out[0] = gx * c->viewport_width / c->image_width;
    out[1] = gy * c->viewport_height / c->image_height;
    out[2] = c->distance;
}
