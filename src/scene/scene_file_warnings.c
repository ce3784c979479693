// scene_file_warnings.c — warnings about what a loaded scene will not show: no light at all, what paper mode
// drops, media under the Whitted integrator.
#include "scene/scene_file_common.h"

#include <stdio.h>

// Whether material index m emits (a diffuse_light with some emission, or an emission texture).
static bool emits(const glint_scene *s, int64_t m) {
    if (m < 0 || (size_t)m >= s->material_count) return false;
    const material *mt = &s->materials[m];
    if (mt->kind == MAT_PBR) return v3_max_comp(mt->emission) > 0.0f;
    return mt->kind == MAT_DIFFUSE_LIGHT && (mt->emission_texture >= 0 || v3_max_comp(mt->emission) > 0.0f);
}

// Whether any object of the scene uses an emitting material (meshes: any of their materials).
static bool any_emitter(const glint_scene *s) {
    for (size_t i = 0; i < s->sphere_count; i++)
        if (emits(s, s->spheres[i].material)) return true;
    for (size_t i = 0; i < s->moving_sphere_count; i++)
        if (emits(s, s->moving_spheres[i].material)) return true;
    for (size_t i = 0; i < s->quad_count; i++)
        if (emits(s, s->quads[i].material)) return true;
    for (size_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        if (in->material >= 0) {
            if (emits(s, in->material)) return true;
        } else if (in->kind == INSTANCE_SPHERE) {
            if (emits(s, s->instance_spheres[in->index].material)) return true;
        } else {
            const scene_mesh *m = &s->meshes[in->index];
            if (emits(s, m->default_material)) return true;
            for (size_t k = 0; k < m->slot_count; k++)
                if (emits(s, m->slot_material[k])) return true;
        }
    }
    return false;
}

// Whether the background can light anything: a sky, an environment map, or a constant colour that is not black.
static bool background_lights(const render_settings *rs) {
    if (rs->background == BACKGROUND_ENVMAP) return true;
    if (rs->background == BACKGROUND_SKY) return v3_max_comp(rs->sky_horizon) > 0.0f || v3_max_comp(rs->sky_zenith) > 0.0f;
    return v3_max_comp(rs->background_color) > 0.0f;
}

// Warns when nothing can light the image: the integrator's lights, emitters and the background. Paper mode
// never renders black (its misses are white). The path tracer ignores ambient lights, so those alone are
// named.
static void warn_no_light(sf_loader *ld) {
    const glint_scene *s = ld->scene;
    const render_settings *rs = &s->settings;
    if (rs->integrator == INTEGRATOR_WHITTED && rs->whitted_mode == WHITTED_PAPER) return;
    size_t ambient = 0;
    for (size_t i = 0; i < s->light_count; i++) ambient += s->lights[i].kind == LIGHT_AMBIENT;
    bool path = rs->integrator == INTEGRATOR_PATH;
    size_t lights = path ? s->light_count - ambient : s->light_count;
    if (lights > 0 || background_lights(rs) || any_emitter(s)) return;
    char msg[512];
    if (path && ambient > 0)
        snprintf(msg, sizeof msg,
                 "%s: warning: no light sources the path tracer uses (no point or directional lights, no emitters, "
                 "black background; it ignores ambient lights); the image will be black",
                 ld->r.name);
    else
        snprintf(msg, sizeof msg,
                 "%s: warning: no light sources in the scene (no lights, no emitters, black background); the image "
                 "will be black",
                 ld->r.name);
    sf_add_warning(ld, msg);
}

// Keeps "NAME: warning: paper mode <what>: N <noun>(s) is/are <rest>" when n > 0.
static void warn_paper(sf_loader *ld, size_t n, const char *what, const char *noun, const char *rest) {
    if (n == 0) return;
    char msg[512];
    snprintf(msg, sizeof msg, "%s: warning: paper mode %s: %zu %s%s %s %s", ld->r.name, what, n, noun,
             n == 1 ? "" : "s", n == 1 ? "is" : "are", rest);
    sf_add_warning(ld, msg);
}

// Paper mode sees the world-space spheres and their materials' constant colours, Phong parameters and
// nothing else (whitted.c): one warning per kind of thing it drops.
static void warn_paper_mode(sf_loader *ld) {
    const glint_scene *s = ld->scene;
    if (s->settings.integrator != INTEGRATOR_WHITTED || s->settings.whitted_mode != WHITTED_PAPER) return;
    static const char sees[] = "sees spheres only";
    warn_paper(ld, ld->object_counts[SF_OBJECT_QUAD], sees, "quad object", "ignored (neither seen nor casting shadows)");
    warn_paper(ld, ld->object_counts[SF_OBJECT_BOX], sees, "box object", "ignored (neither seen nor casting shadows)");
    warn_paper(ld, ld->object_counts[SF_OBJECT_MESH], sees, "mesh object", "ignored (neither seen nor casting shadows)");
    warn_paper(ld, s->moving_sphere_count, sees, "moving sphere", "ignored (neither seen nor casting shadows)");
    size_t placed = 0;
    for (size_t i = 0; i < s->instance_count; i++) placed += s->instances[i].kind == INSTANCE_SPHERE;
    warn_paper(ld, placed, sees, "instanced sphere",
               "ignored (a transform that is not a similarity, or a transform with a textured material, makes a "
               "sphere an instance; neither seen nor casting shadows)");
    size_t textured = 0, kinds[MAT_KIND_COUNT] = {0};
    for (size_t i = 0; i < s->sphere_count; i++) {
        const material *m = &s->materials[s->spheres[i].material];
        textured += m->albedo_texture >= 0 || m->emission_texture >= 0;
        kinds[m->kind]++;
    }
    warn_paper(ld, textured, "uses constant colours", "sphere", "textured (textures are not used)");
    warn_paper(ld, kinds[MAT_METAL], "shades metal as a matte colour", "sphere", "made of metal (no mirror reflection)");
    warn_paper(ld, kinds[MAT_DIELECTRIC], "shades dielectric as a matte colour", "sphere",
               "made of dielectric (no refraction or reflection)");
    warn_paper(ld, kinds[MAT_DIFFUSE_LIGHT], "shades diffuse_light as a matte colour", "sphere",
               "made of diffuse_light (no emission)");
    warn_paper(ld, kinds[MAT_CONDUCTOR] + kinds[MAT_ROUGH_DIELECTRIC] + kinds[MAT_PBR],
               "shades the microfacet materials as a matte colour", "sphere",
               "made of conductor, rough_dielectric or pbr (no reflection or refraction)");
    size_t tinted = 0;
    for (size_t i = 0; i < s->sphere_count; i++) tinted += s->materials[s->spheres[i].material].has_specular_color;
    warn_paper(ld, tinted, "makes highlights white", "sphere", "given a specular_color (it is not used)");
    // The program's rays that miss everything are white, whatever the scene's background says: a background
    // other than white (as the paper's scene says) or the default black is not what the image will show.
    const render_settings *rs = &s->settings;
    vec3 bg = rs->background_color;
    bool constant = rs->background == BACKGROUND_CONSTANT;
    bool white = constant && bg.x == 1.0f && bg.y == 1.0f && bg.z == 1.0f;
    if (!white && !(constant && v3_max_comp(bg) == 0.0f)) {
        char msg[512];
        snprintf(msg, sizeof msg, "%s: warning: paper mode ignores \"background\": rays that miss everything are white, "
                 "as in the paper's program", ld->r.name);
        sf_add_warning(ld, msg);
    }
}

// The Whitted integrators see surfaces only (docs/scene-format.md): media in a Whitted scene are not rendered.
static void warn_whitted_media(sf_loader *ld) {
    const glint_scene *s = ld->scene;
    if (s->settings.integrator != INTEGRATOR_WHITTED || s->medium_count == 0) return;
    char msg[512];
    snprintf(msg, sizeof msg,
             "%s: warning: the Whitted integrator ignores participating media: %zu %s not rendered (the path "
             "integrator renders them)",
             ld->r.name, s->medium_count, s->medium_count == 1 ? "medium is" : "media are");
    sf_add_warning(ld, msg);
}

void sf_warn_unseen(sf_loader *ld) {
    warn_no_light(ld);
    warn_paper_mode(ld);
    warn_whitted_media(ld);
}
