// scene_file_materials.c — the scene file's "textures" and "materials": every texture and material kind,
// colour parameters given as numbers or textures, and the cache of image files decoded into textures.
#include "scene/scene_file_common.h"
#include "core/array.h"
#include "core/filepath.h"
#include "core/trace.h"
#include "io/image_read.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---------------------------------------------------------------------------------------------
// Image files, each decoded once

// The message of a library that starts with the path it was given, without that "path: " prefix.
static const char *strip_path(const char *message, const char *path) {
    size_t n = strlen(path);
    return strncmp(message, path, n) == 0 && message[n] == ':' && message[n + 1] == ' ' ? message + n + 2 : message;
}

/// The scene texture of image file `path` (id), decoded on first use; `where` is blamed for failures, and
/// `prefix` (may be "") opens their message.
bool sf_load_image(sf_loader *ld, size_t where, const char *prefix, const char *written, const char *path,
                   sf_file_id id, image_decode decode, texture_filter filter, uint32_t *index) {
    for (size_t i = 0; i < ld->image_count; i++)
        if (ld->images[i].id.dev == id.dev && ld->images[i].id.ino == id.ino && ld->images[i].decode == decode &&
            ld->images[i].filter == filter) {
            *index = ld->images[i].texture;
            return true;
        }
    if (ld->scene->texture_count >= SF_MAX_ITEMS)
        return jr_fail_at(&ld->r, where, "too many textures (the limit is %d)", SF_MAX_ITEMS);
    if (!scene_add_input(ld->scene, (uint64_t)id.dev, (uint64_t)id.ino, path)) return sf_fail_oom(ld);
    // The file is decoded here (io/), and the texture module only takes the pixels.
    image_rgb img;
    glint_error err;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = image_read(path, decode, &img, &err);
    if (lane) trace_add(lane, &(trace_event){"texture read", "load", began, trace_clock(), 1, {{"file", 0, path}}});
    if (st != GLINT_OK) {
        char note[420], shown[304];
        jr_fail_at(&ld->r, where, "%simage file \"%s\"%s: %s", prefix, filepath_tail(written, 300, shown, sizeof shown),
                   sf_resolved_note(written, path, note, sizeof note), strip_path(err.message, path));
        ld->r.status = st; // running out of memory stays a resource failure
        return false;
    }
    texture t = texture_image(img, filter);
    long i = scene_add_texture(ld->scene, &t, NULL);
    if (i < 0 || !array_reserve((void **)&ld->images, &ld->image_cap, ld->image_count + 1, sizeof *ld->images))
        return sf_fail_oom(ld);
    ld->images[ld->image_count++] = (sf_image_entry){id, decode, filter, (uint32_t)i};
    *index = (uint32_t)i;
    return true;
}

// ---------------------------------------------------------------------------------------------
// Textures: add a row to texture_types (name, keys, reader) for a new kind.

static const char *const solid_keys[] = {"type", "color", NULL};
static const char *const checker_keys[] = {"type", "scale", "even", "odd", NULL};
static const char *const noise_keys[] = {"type", "scale", "color", "seed", "perlin", NULL};
static const char *const turbulence_keys[] = {"type", "scale", "depth", "color", "seed", "perlin", NULL};
static const char *const marble_keys[] = {"type",   "scale",  "depth", "color",
                                          "seed",   "perlin", "scaled_turbulence", NULL};
static const char *const image_keys[] = {"type", "file", "encoding", "filter", NULL};
static const char *const perlin_keys[] = {"gradients", "perm_x", "perm_y", "perm_z", NULL};

/// Adds the texture a texture object describes (or finds the one already loaded from the same image);
/// `name` is NULL for inline textures.
typedef bool (*texture_reader)(sf_loader *ld, const jr_obj *o, int variant, const char *name, uint32_t *index);

static bool add_texture(sf_loader *ld, const jr_obj *o, texture *t, const char *name, uint32_t *index) {
    if (ld->scene->texture_count >= SF_MAX_ITEMS) {
        texture_free(t);
        return jr_fail_at(&ld->r, jr_offset(&ld->r, o->self.tok), "too many textures (the limit is %d)", SF_MAX_ITEMS);
    }
    long i = scene_add_texture(ld->scene, t, name);
    if (i < 0) return sf_fail_oom(ld);
    *index = (uint32_t)i;
    return true;
}

static bool read_solid(sf_loader *ld, const jr_obj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    vec3 c;
    if (!jr_read_color(&ld->r, o, "color", true, &JR_NONNEG, &c)) return false;
    texture t = texture_solid(c);
    return add_texture(ld, o, &t, name, index);
}

static bool read_checker(sf_loader *ld, const jr_obj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    float scale = 1.0f;
    vec3 even = v3s(1.0f), odd = v3s(0.0f);
    if (!jr_read_float(&ld->r, o, "scale", false, &JR_POSITIVE, &scale) ||
        !jr_read_color(&ld->r, o, "even", false, &JR_NONNEG, &even) || !jr_read_color(&ld->r, o, "odd", false, &JR_NONNEG, &odd))
        return false;
    // The checker divides by the scale: a subnormal one would overflow 1/scale.
    if (!isfinite(1.0f / scale)) {
        const jr_member *m = jr_get(o, "scale");
        char got[96];
        return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok), "\"scale\" must be at least %g, got %s", (double)FLT_MIN,
                          jr_describe(&ld->r, m->val, got, sizeof got));
    }
    texture t = texture_checker(scale, even, odd);
    return add_texture(ld, o, &t, name, index);
}

static const jr_numspec NUM_GRADIENT = {-1e6, 1e6, JR_FLOAT, "a number in [-1e6, 1e6]"};

// "perlin": {"gradients": 256 [x, y, z], "perm_x"/"perm_y"/"perm_z": 256 integers in [0, 255]}: the tables a
// program drew, so that its noise can be reproduced exactly.
static bool read_perlin_tables(sf_loader *ld, jr_val v, perlin *out) {
    jr_obj o;
    if (!jr_open(&ld->r, v, "perlin", perlin_keys, &o)) return false;
    const char *const *names = perlin_keys;
    uint8_t *perms[3] = {out->perm_x, out->perm_y, out->perm_z};
    for (int table = 0; table < 4; table++) {
        const jr_member *m;
        if (!jr_lookup(&ld->r, &o, names[table], true, &m)) return false;
        char got[96];
        if (!cJSON_IsArray(m->val.item) || cJSON_GetArraySize(m->val.item) != 256)
            return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok), "\"%s\" must be an array of 256 %s, got %s",
                              names[table], table == 0 ? "vectors [x, y, z]" : "integers in [0, 255]",
                              jr_describe(&ld->r, m->val, got, sizeof got));
        jr_iter it = jr_iter_begin(&ld->r, m->val);
        jr_val e;
        int r;
        for (int i = 0; (r = jr_iter_next(&ld->r, &it, NULL, &e)) > 0; i++) {
            double n;
            if (table == 0) {
                if (!jr_check_vec3(&ld->r, e, names[table], &NUM_GRADIENT, &out->gradient[i])) return false;
            } else {
                if (!jr_check_number(&ld->r, e, names[table], i, &JR_NONNEG, &n)) return false;
                if (n != floor(n) || n > 255)
                    return jr_fail_at(&ld->r, jr_offset(&ld->r, e.tok), "%s[%d] must be an integer in [0, 255], got %s",
                                      names[table], i, jr_describe(&ld->r, e, got, sizeof got));
                perms[table - 1][i] = (uint8_t)n;
            }
        }
        if (r < 0) return false;
    }
    return true;
}

static bool read_noise(sf_loader *ld, const jr_obj *o, int variant, const char *name, uint32_t *index) {
    float scale = 1.0f;
    vec3 color = v3s(1.0f);
    long long depth = 7, seed = 0;
    bool scaled_turbulence = false;
    if (!jr_read_float(&ld->r, o, "scale", false, &JR_POSITIVE, &scale) ||
        !jr_read_int(&ld->r, o, "depth", false, 1, SF_MAX_NOISE_DEPTH, &depth) ||
        !jr_read_color(&ld->r, o, "color", false, &JR_NONNEG, &color) ||
        !jr_read_int(&ld->r, o, "seed", false, 0, 9007199254740992LL, &seed) ||
        !jr_read_bool(&ld->r, o, "scaled_turbulence", &scaled_turbulence))
        return false;
    noise_kind kind = variant == NOISE_MARBLE && scaled_turbulence ? NOISE_MARBLE_SCALED : (noise_kind)variant;
    const jr_member *tables = jr_get(o, "perlin");
    texture t;
    if (tables) {
        perlin *p = malloc(sizeof *p);
        if (!p) return sf_fail_oom(ld);
        bool ok = read_perlin_tables(ld, tables->val, p);
        if (ok && !texture_noise_tables(kind, scale, (int)depth, color, p, &t)) {
            free(p);
            return sf_fail_oom(ld);
        }
        free(p);
        if (!ok) return false;
    } else if (!texture_noise(kind, scale, (int)depth, color, (uint64_t)seed, &t))
        return sf_fail_oom(ld);
    return add_texture(ld, o, &t, name, index);
}

const char *const sf_image_encodings[2] = {"srgb", "linear"}, *const sf_image_filters[2] = {"bilinear", "nearest"};

static bool read_image(sf_loader *ld, const jr_obj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    char *path;
    sf_file_id id;
    jr_val where;
    int encoding = ld->linear_images ? 1 : 0, filter = 0;
    if (!jr_read_enum(&ld->r, o, "encoding", sf_image_encodings, 2, &encoding) ||
        !jr_read_enum(&ld->r, o, "filter", sf_image_filters, 2, &filter))
        return false;
    if (!sf_read_file_path(ld, o, "file", "image", &path, &id, &where)) return false;
    size_t before = ld->scene->texture_count;
    bool ok = sf_load_image(ld, jr_offset(&ld->r, where.tok), "", where.item->valuestring, path, id,
                            encoding ? IMAGE_DECODE_LINEAR : IMAGE_DECODE_SRGB,
                            filter ? FILTER_NEAREST : FILTER_BILINEAR, index);
    free(path);
    // A newly decoded image takes the name it was first defined under (an image given twice loads once).
    if (ok && name && ld->scene->texture_count > before && !ld->scene->texture_names[*index]) {
        size_t n = strlen(name) + 1;
        char *copy = malloc(n);
        if (!copy) return sf_fail_oom(ld);
        memcpy(copy, name, n);
        ld->scene->texture_names[*index] = copy;
    }
    return ok;
}

static const struct texture_type {
    const char *name;
    const char *const *keys;
    texture_reader read;
    int variant; ///< noise: its noise_kind
} texture_types[] = {
    {"solid", solid_keys, read_solid, 0},
    {"checker", checker_keys, read_checker, 0},
    {"noise", noise_keys, read_noise, NOISE_PLAIN},
    {"turbulence", turbulence_keys, read_noise, NOISE_TURBULENCE},
    {"marble", marble_keys, read_noise, NOISE_MARBLE},
    {"image", image_keys, read_image, 0},
};
#define TEXTURE_TYPES (sizeof texture_types / sizeof texture_types[0])

/// Reads a texture object and adds it to the scene (named or anonymous); *index is its number.
bool sf_read_texture(sf_loader *ld, jr_val v, const char *what, const char *name, uint32_t *index) {
    size_t t;
    if (!jr_open_typed(&ld->r, v, what, texture_types, TEXTURE_TYPES, sizeof texture_types[0], &t)) return false;
    jr_obj o;
    return jr_open(&ld->r, v, what, texture_types[t].keys, &o) &&
           texture_types[t].read(ld, &o, texture_types[t].variant, name, index);
}

// The largest colour component a texture can give (images are in [0, 1]).
static float texture_peak(const texture *t) {
    vec3 c = t->kind == TEX_CHECKER ? v3_max(t->even, t->odd) : t->kind == TEX_IMAGE ? v3s(1.0f) : t->color;
    return fmaxf(c.x, fmaxf(c.y, c.z));
}

/// A material colour parameter: a number or [r, g, b] (into *color), or a texture, by name or inline (into
/// *tex). Textures used where components must be at most 1 (albedo) must not exceed 1 either.
static bool read_material_color(sf_loader *ld, const jr_obj *o, const char *key, const jr_numspec *sp, vec3 *color,
                                int32_t *tex) {
    const jr_member *m = jr_get(o, key);
    if (!m) return true;
    jr_val v = m->val;
    char got[96];
    if (cJSON_IsNumber(v.item) || (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3))
        return jr_check_color(&ld->r, v, key, sp, color);
    uint32_t index;
    if (cJSON_IsString(v.item)) {
        const sf_name *s = sf_names_find(&ld->textures, v.item->valuestring);
        if (!s) return sf_fail_undefined(ld, v, &ld->textures, "texture");
        index = s->index;
    } else if (cJSON_IsObject(v.item)) {
        char what[96 + SCENE_MAX_NAME];
        snprintf(what, sizeof what, "the texture \"%s\" of %s", key, o->what);
        if (!sf_read_texture(ld, v, what, NULL, &index)) return false;
    } else {
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must be %s, an array of 3 such numbers [r, g, b], a texture name or a texture object, "
                          "got %s",
                          key, sp->desc, jr_describe(&ld->r, v, got, sizeof got));
    }
    float peak = texture_peak(&ld->scene->textures[index]);
    if (peak > sp->hi)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must stay in [0, %g], but this texture has colour components up to %g", key, sp->hi,
                          (double)peak);
    *tex = (int32_t)index;
    return true;
}

bool sf_read_color_or_texture(sf_loader *ld, const jr_obj *o, const char *key, const jr_numspec *sp, vec3 *color,
                              int32_t *tex) {
    return read_material_color(ld, o, key, sp, color, tex);
}

// ---------------------------------------------------------------------------------------------
// Materials: add a row to material_types (name, kind, keys, reader) for a new kind.

static const char *const lambertian_keys[] = {"type", "albedo", NULL};
static const char *const metal_keys[] = {"type", "albedo", "fuzz", NULL};
static const char *const dielectric_keys[] = {"type", "ior", "tint", NULL};
static const char *const phong_keys[] = {"type", "color", "specular", "reflective", "specular_color", NULL};
static const char *const diffuse_light_keys[] = {"type", "emission", "two_sided", NULL};
static const char *const conductor_keys[] = {"type", "roughness", "anisotropy", "eta", "k", "metal", "f0", NULL};
static const char *const rough_dielectric_keys[] = {"type", "ior", "roughness", "tint", NULL};
static const char *const pbr_keys[] = {"type",         "base_color", "metallic",          "roughness", "ior",
                                       "transmission", "emission",   "emission_strength", "normal_map", "alpha",
                                       "alpha_cutoff", NULL};

// Every colour parameter but Phong's specular_color may be a texture (read_material_color).
static bool read_lambertian(sf_loader *ld, const jr_obj *o, material *m) {
    return read_material_color(ld, o, "albedo", &JR_UNIT, &m->albedo, &m->albedo_texture);
}

static bool read_metal(sf_loader *ld, const jr_obj *o, material *m) {
    return read_material_color(ld, o, "albedo", &JR_UNIT, &m->albedo, &m->albedo_texture) &&
           jr_read_float(&ld->r, o, "fuzz", false, &JR_UNIT, &m->fuzz);
}

static bool read_dielectric(sf_loader *ld, const jr_obj *o, material *m) {
    return jr_read_float(&ld->r, o, "ior", false, &JR_POSITIVE, &m->ior) &&
           read_material_color(ld, o, "tint", &JR_UNIT, &m->albedo, &m->albedo_texture);
}

static bool read_phong(sf_loader *ld, const jr_obj *o, material *m) {
    long long specular = m->specular;
    if (!read_material_color(ld, o, "color", &JR_UNIT, &m->albedo, &m->albedo_texture) ||
        !jr_read_int(&ld->r, o, "specular", false, -1, INT_MAX, &specular) ||
        !jr_read_float(&ld->r, o, "reflective", false, &JR_UNIT, &m->reflective) ||
        !jr_read_color(&ld->r, o, "specular_color", false, &JR_UNIT, &m->specular_color))
        return false;
    m->specular = (int)specular;
    m->has_specular_color = jr_get(o, "specular_color") != NULL;
    return true;
}

// A texture as "emission" scales the default emission 1: the texture's colour is the emitted radiance.
static bool read_diffuse_light(sf_loader *ld, const jr_obj *o, material *m) {
    return read_material_color(ld, o, "emission", &JR_NONNEG, &m->emission, &m->emission_texture) &&
           jr_read_bool(&ld->r, o, "two_sided", &m->two_sided);
}

// A texture given by name or inline for `key` of o (v): its scene index.
static bool read_texture_ref(sf_loader *ld, const jr_obj *o, const char *key, jr_val v, uint32_t *index) {
    if (cJSON_IsString(v.item)) {
        const sf_name *s = sf_names_find(&ld->textures, v.item->valuestring);
        if (!s) return sf_fail_undefined(ld, v, &ld->textures, "texture");
        *index = s->index;
        return true;
    }
    char what[96 + SCENE_MAX_NAME];
    snprintf(what, sizeof what, "the texture \"%s\" of %s", key, o->what);
    // Every texture given this way holds data, not colour (metallic, roughness, transmission, normals): linear.
    ld->linear_images = true;
    bool ok = sf_read_texture(ld, v, what, NULL, index);
    ld->linear_images = false;
    return ok;
}

/// A scalar material parameter in [0, 1]: a number (into *value), or a texture by name or inline whose `channel`
/// (0 red, 1 green, 2 blue) gives it at each point (into *tex; *value becomes 1, the factor it multiplies).
static bool read_material_scalar(sf_loader *ld, const jr_obj *o, const char *key, const char *channel, float *value,
                                 int32_t *tex) {
    const jr_member *m = jr_get(o, key);
    if (!m) return true;
    jr_val v = m->val;
    if (cJSON_IsNumber(v.item)) return jr_read_float(&ld->r, o, key, false, &JR_UNIT, value);
    char got[96];
    if (!cJSON_IsString(v.item) && !cJSON_IsObject(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must be a number in [0, 1], a texture name or a texture object (its %s channel), got %s",
                          key, channel, jr_describe(&ld->r, v, got, sizeof got));
    uint32_t index;
    if (!read_texture_ref(ld, o, key, v, &index)) return false;
    float peak = texture_peak(&ld->scene->textures[index]);
    if (peak > 1.0f)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must stay in [0, 1], but this texture has colour components up to %g", key,
                          (double)peak);
    *value = 1.0f;
    *tex = (int32_t)index;
    return true;
}

// A conductor's Fresnel reflectance comes from one of: "metal" (a preset), "eta" with "k", or "f0"; by default
// the "Al" preset (material_default).
static bool read_conductor(sf_loader *ld, const jr_obj *o, material *m) {
    if (!jr_read_float(&ld->r, o, "roughness", false, &JR_UNIT, &m->roughness)) return false;
    static const jr_numspec below_one = {0.0, 1.0, JR_FLOAT | JR_HI_OPEN, "a number in [0, 1)"};
    if (!jr_read_float(&ld->r, o, "anisotropy", false, &below_one, &m->anisotropy)) return false;
    const jr_member *metal = jr_get(o, "metal"), *eta = jr_get(o, "eta"), *k = jr_get(o, "k"), *f0 = jr_get(o, "f0");
    int ways = (metal != NULL) + (eta || k) + (f0 != NULL);
    if (ways > 1)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, o->self.tok),
                          "a conductor takes one of \"metal\", \"eta\" with \"k\", or \"f0\", not several");
    if (metal) {
        char got[96], names[160] = "";
        if (cJSON_IsString(metal->val.item) && material_conductor_preset(metal->val.item->valuestring, &m->eta, &m->k))
            return true;
        for (size_t i = 0; material_conductor_preset_name(i); i++) {
            size_t n = strlen(names);
            snprintf(names + n, sizeof names - n, "%s\"%s\"", i ? ", " : "", material_conductor_preset_name(i));
        }
        return jr_fail_at(&ld->r, jr_offset(&ld->r, metal->val.tok), "\"metal\" must be one of %s, got %s", names,
                          jr_describe(&ld->r, metal->val, got, sizeof got));
    }
    if (eta || k) {
        if (!eta || !k)
            return jr_fail_at(&ld->r, jr_offset(&ld->r, (eta ? eta : k)->val.tok),
                              "a conductor's \"eta\" and \"k\" come together: \"%s\" is missing", eta ? "k" : "eta");
        return jr_read_color(&ld->r, o, "eta", false, &JR_POSITIVE, &m->eta) &&
               jr_read_color(&ld->r, o, "k", false, &JR_NONNEG, &m->k);
    }
    if (f0) {
        m->fresnel = FRESNEL_SCHLICK_F0;
        return jr_read_color(&ld->r, o, "f0", false, &JR_UNIT, &m->f0);
    }
    return true;
}

static bool read_rough_dielectric(sf_loader *ld, const jr_obj *o, material *m) {
    return jr_read_float(&ld->r, o, "ior", false, &JR_POSITIVE, &m->ior) &&
           jr_read_float(&ld->r, o, "roughness", false, &JR_UNIT, &m->roughness) &&
           read_material_color(ld, o, "tint", &JR_UNIT, &m->albedo, &m->albedo_texture);
}

// An alpha mask (glTF alphaMode MASK): "alpha_cutoff" in [0, 1] turns it on; "alpha" is a number in [0, 1] or a
// texture whose alpha channel gives it (an image without alpha gives 1), and needs the cutoff (no blending here).
static bool read_alpha_mask(sf_loader *ld, const jr_obj *o, material *m) {
    const jr_member *alpha = jr_get(o, "alpha");
    if (alpha && !jr_get(o, "alpha_cutoff"))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, alpha->val.tok),
                          "\"alpha\" needs \"alpha_cutoff\": glint cuts surfaces where alpha < alpha_cutoff (an alpha "
                          "mask) and does not blend");
    if (!jr_read_float(&ld->r, o, "alpha_cutoff", false, &JR_UNIT, &m->alpha_cutoff)) return false;
    if (!alpha) return true;
    jr_val v = alpha->val;
    if (cJSON_IsNumber(v.item)) return jr_read_float(&ld->r, o, "alpha", false, &JR_UNIT, &m->alpha);
    char got[96];
    if (!cJSON_IsString(v.item) && !cJSON_IsObject(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"alpha\" must be a number in [0, 1], a texture name or a texture object (its alpha "
                          "channel), got %s", jr_describe(&ld->r, v, got, sizeof got));
    uint32_t index;
    if (!read_texture_ref(ld, o, "alpha", v, &index)) return false;
    m->alpha = 1.0f;
    m->alpha_texture = (int32_t)index;
    return true;
}

// glTF 2.0's metallic-roughness material: the textures' channels are glTF's (metallic B, roughness G, transmission R).
static bool read_pbr(sf_loader *ld, const jr_obj *o, material *m) {
    float strength = 1.0f;
    if (!read_material_color(ld, o, "base_color", &JR_UNIT, &m->albedo, &m->albedo_texture) ||
        !read_material_scalar(ld, o, "metallic", "blue", &m->metallic, &m->metallic_texture) ||
        !read_material_scalar(ld, o, "roughness", "green", &m->roughness, &m->roughness_texture) ||
        !jr_read_float(&ld->r, o, "ior", false, &JR_POSITIVE, &m->ior) ||
        !read_material_scalar(ld, o, "transmission", "red", &m->transmission, &m->transmission_texture) ||
        !read_material_color(ld, o, "emission", &JR_NONNEG, &m->emission, &m->emission_texture) ||
        !jr_read_float(&ld->r, o, "emission_strength", false, &JR_NONNEG, &strength))
        return false;
    // A texture as "emission" scales the emission 1, as diffuse_light's; the strength scales both (glTF's
    // KHR_materials_emissive_strength).
    if (m->emission_texture >= 0 && v3_max_comp(m->emission) <= 0.0f) m->emission = v3s(1.0f);
    m->emission = v3_scale(m->emission, strength);
    if (!read_alpha_mask(ld, o, m)) return false;
    const jr_member *nm = jr_get(o, "normal_map");
    if (nm) {
        char got[96];
        if (!cJSON_IsString(nm->val.item) && !cJSON_IsObject(nm->val.item))
            return jr_fail_at(&ld->r, jr_offset(&ld->r, nm->val.tok),
                              "\"normal_map\" must be a texture name or a texture object, got %s",
                              jr_describe(&ld->r, nm->val, got, sizeof got));
        uint32_t index;
        if (!read_texture_ref(ld, o, "normal_map", nm->val, &index)) return false;
        m->normal_texture = (int32_t)index;
    }
    return true;
}

typedef bool (*material_reader)(sf_loader *ld, const jr_obj *o, material *m);

static const struct material_type {
    const char *name;
    material_kind kind;
    const char *const *keys;
    material_reader read;
} material_types[] = {
    {"lambertian", MAT_LAMBERTIAN, lambertian_keys, read_lambertian},
    {"metal", MAT_METAL, metal_keys, read_metal},
    {"dielectric", MAT_DIELECTRIC, dielectric_keys, read_dielectric},
    {"phong", MAT_PHONG, phong_keys, read_phong},
    {"diffuse_light", MAT_DIFFUSE_LIGHT, diffuse_light_keys, read_diffuse_light},
    {"conductor", MAT_CONDUCTOR, conductor_keys, read_conductor},
    {"rough_dielectric", MAT_ROUGH_DIELECTRIC, rough_dielectric_keys, read_rough_dielectric},
    {"pbr", MAT_PBR, pbr_keys, read_pbr},
};
#define MATERIAL_TYPES (sizeof material_types / sizeof material_types[0])

/// Reads a material object and adds it to the scene (named or anonymous); *index is its number.
bool sf_read_material(sf_loader *ld, jr_val v, const char *what, const char *name, uint32_t *index) {
    size_t t;
    if (!jr_open_typed(&ld->r, v, what, material_types, MATERIAL_TYPES, sizeof material_types[0], &t)) return false;
    const struct material_type *mt = &material_types[t];
    material m = material_default(mt->kind);
    jr_obj o;
    if (!jr_open(&ld->r, v, what, mt->keys, &o) || !mt->read(ld, &o, &m)) return false;
    if (ld->scene->material_count >= SF_MAX_ITEMS)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "too many materials (the limit is %d)", SF_MAX_ITEMS);
    long i = scene_add_material(ld->scene, &m, name);
    if (i < 0) return sf_fail_oom(ld);
    *index = (uint32_t)i;
    return true;
}

/// The "material" of an object: a name defined in "materials", or an inline material object.
bool sf_read_material_ref(sf_loader *ld, const jr_obj *o, const char *owner, uint32_t *index) {
    const jr_member *m;
    if (!jr_lookup(&ld->r, o, "material", true, &m)) return false;
    jr_val v = m->val;
    char got[96];
    if (cJSON_IsObject(v.item)) {
        char what[96];
        snprintf(what, sizeof what, "the material of %s", owner);
        return sf_read_material(ld, v, what, NULL, index);
    }
    if (!cJSON_IsString(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"material\" must be the name of a material in \"materials\" or a material object, got %s",
                          jr_describe(&ld->r, v, got, sizeof got));
    const sf_name *s = sf_names_find(&ld->materials, v.item->valuestring);
    if (s) {
        *index = s->index;
        return true;
    }
    return sf_fail_undefined(ld, v, &ld->materials, "material");
}
