// model_read.c — glTF 2.0 and PLY files through assimp's C API, checked and turned into glint records (model_read.h).
#include "io/model_read.h"
#include "io/ply_fast.h"

#include "core/file_read.h"
#include "core/filepath.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GLINT_HAVE_ASSIMP

bool model_read_available(void) { return false; }

glint_status model_read(const char *path, model_warning_fn warn, void *user, model_file *out, glint_error *err) {
    return model_read_ex(path, true, warn, user, out, err);
}

glint_status model_read_ex(const char *path, bool fast_ply, model_warning_fn warn, void *user, model_file *out,
                           glint_error *err) {
    (void)fast_ply;
    (void)warn;
    (void)user;
    memset(out, 0, sizeof *out);
    return status_fail(err, GLINT_ERR_INPUT,
                       "%s: glTF and PLY files are read through assimp, and this glint was built without it (install "
                       "Debian's libassimp-dev and build again); OBJ meshes need no library",
                       path);
}

#else

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/GltfMaterial.h>

#include <cjson/cJSON.h>
#include <pthread.h>
#include <sys/stat.h>

bool model_read_available(void) { return true; }

// ---------------------------------------------------------------------------------------------
// The state of one read: the files opened, the first file that could not be, what assimp's log said

typedef struct read_context {
    const char *path;
    model_file *out;
    char open_problem[700]; ///< the first file assimp asked for that glint refused, and why ("" when none)
    char dropped[300];      ///< assimp's warning that it dropped faces with out-of-range indices ("" when none)
    bool oom;
} read_context;

// assimp keeps one logger for the process: imports are serialised, and the log stream reports to the current one.
static pthread_mutex_t assimp_lock = PTHREAD_MUTEX_INITIALIZER;
static read_context *current_read;

static void assimp_log(const char *message, char *user) {
    (void)user;
    read_context *c = current_read;
    if (!c || c->dropped[0]) return;
    // assimp does not fail a file whose faces index past its vertices: it drops those faces and says so.
    bool warning = strncmp(message, "Warn", 4) == 0 || strncmp(message, "Error", 5) == 0;
    if (warning && (strstr(message, "out-of-range indices") || strstr(message, "index is out of range") ||
                    strstr(message, "indices out of range"))) {
        const char *text = strstr(message, "T0: ");
        snprintf(c->dropped, sizeof c->dropped, "%s", text ? text + 4 : message);
        size_t n = strlen(c->dropped);
        while (n && (c->dropped[n - 1] == '\n' || c->dropped[n - 1] == '\r')) c->dropped[--n] = '\0';
    }
}

// ---------------------------------------------------------------------------------------------
// Files: assimp reads through glint's descriptors (aiFileIO), never opening a path itself

typedef struct glint_file {
    struct aiFile base; // first: assimp hands back the aiFile pointer
    FILE *f;
    size_t size;
} glint_file;

static size_t file_read_proc(struct aiFile *af, char *buf, size_t size, size_t count) {
    glint_file *g = (glint_file *)af;
    return size && count ? fread(buf, size, count, g->f) : 0;
}
static size_t file_write_proc(struct aiFile *af, const char *buf, size_t size, size_t count) {
    (void)af, (void)buf, (void)size, (void)count;
    return 0;
}
static size_t file_tell_proc(struct aiFile *af) {
    long p = ftell(((glint_file *)af)->f);
    return p < 0 ? 0 : (size_t)p;
}
static size_t file_size_proc(struct aiFile *af) { return ((glint_file *)af)->size; }
static enum aiReturn file_seek_proc(struct aiFile *af, size_t offset, enum aiOrigin origin) {
    glint_file *g = (glint_file *)af;
    if (offset > (size_t)MODEL_MAX_FILE_BYTES) return aiReturn_FAILURE;
    int whence = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    return fseek(g->f, (long)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}
static void file_flush_proc(struct aiFile *af) { (void)af; }

static struct aiFile *file_open_proc(struct aiFileIO *io, const char *path, const char *mode) {
    read_context *c = (read_context *)(void *)io->UserData;
    if (!mode || mode[0] != 'r') return NULL; // glint never lets assimp write
    struct stat st;
    int problem;
    FILE *f = filepath_open_regular(path, &st, &problem);
    const char *why = f ? NULL : filepath_problem_text(problem);
    if (f && (uint64_t)st.st_size > (uint64_t)MODEL_MAX_FILE_BYTES) why = "larger than 1 GiB, the limit of a model's file";
    if (why) {
        if (f) fclose(f);
        // assimp probes for files that need not exist (Exists): the reason is kept, and said if the read fails.
        if (!c->open_problem[0]) {
            char shown[304];
            snprintf(c->open_problem, sizeof c->open_problem, "\"%s\": %s", filepath_tail(path, 300, shown, sizeof shown), why);
        }
        return NULL;
    }
    glint_file *g = calloc(1, sizeof *g);
    if (!g || !model_file_add_input(c->out, &st, path)) {
        c->oom = true;
        free(g);
        fclose(f);
        return NULL;
    }
    g->f = f;
    g->size = (size_t)st.st_size;
    g->base = (struct aiFile){file_read_proc, file_write_proc, file_tell_proc, file_size_proc, file_seek_proc,
                              file_flush_proc, NULL};
    return &g->base;
}

static void file_close_proc(struct aiFileIO *io, struct aiFile *af) {
    (void)io;
    if (!af) return;
    glint_file *g = (glint_file *)af;
    fclose(g->f);
    free(g);
}

// ---------------------------------------------------------------------------------------------
// Checking and converting what assimp made

typedef struct converter {
    const char *path;
    model_format format;
    const struct aiScene *sc;
    model_file *out;
    glint_error *err;
    model_warning_fn warn;
    void *user;
    size_t zero_area, not_triangles, singular_nodes;
    bool uv_set_warned;
} converter;

static glint_status fail_oom(converter *cv) {
    return status_fail(cv->err, GLINT_ERR_RENDER, "%s: out of memory while reading the model", cv->path);
}

static void warn(converter *cv, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(converter *cv, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    model_file_warn(cv->warn, cv->user, cv->path, fmt, ap);
    va_end(ap);
}

static bool finite3(struct aiVector3D v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/// One aiMesh as a glint mesh: its vertices as they are, its triangles checked (indices in range) and those of
/// zero area skipped. One pass over the vertices and one over the faces (assimp keeps each face's indices in an
/// allocation of its own: a second pass would miss the cache again on a large mesh).
static glint_status convert_mesh(converter *cv, unsigned index, model_mesh *out) {
    const struct aiMesh *am = cv->sc->mMeshes[index];
    mesh *m = &out->geometry;
    memset(out, 0, sizeof *out);
    if (am->mMaterialIndex >= cv->sc->mNumMaterials)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: mesh %u names material %u of %u", cv->path, index,
                           am->mMaterialIndex, cv->sc->mNumMaterials);
    out->material = am->mMaterialIndex;
    unsigned nv = am->mNumVertices, nf = am->mNumFaces;
    if (nv > (unsigned)INT32_MAX || nf > (unsigned)INT32_MAX)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: mesh %u has %u vertices and %u faces; at most 2^31 - 1 each",
                           cv->path, index, nv, nf);
    if ((nv && !am->mVertices) || (nf && !am->mFaces))
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: mesh %u has vertices without positions", cv->path, index);
    const struct aiVector3D *uvs = am->mTextureCoords[0];
    bool has_uv = uvs != NULL, has_n = am->mNormals != NULL;
    if (am->mTextureCoords[1] && !cv->uv_set_warned) {
        cv->uv_set_warned = true;
        warn(cv, "meshes with several texture coordinate sets: glint uses the first (TEXCOORD_0)");
    }
    if (nv && !(m->positions = malloc(nv * sizeof *m->positions))) return fail_oom(cv);
    if (nf && !(m->triangles = malloc(nf * sizeof *m->triangles))) return fail_oom(cv);
    if (has_n && nv && !(m->normals = malloc(nv * sizeof *m->normals))) return fail_oom(cv);
    if (has_uv && nv && !(m->uvs = malloc(nv * sizeof *m->uvs))) return fail_oom(cv);
    if (has_uv && nf && !(m->uv_corners = malloc(nf * sizeof *m->uv_corners))) return fail_oom(cv);
    for (unsigned i = 0; i < nv; i++) {
        struct aiVector3D p = am->mVertices[i];
        if (!finite3(p))
            return status_fail(cv->err, GLINT_ERR_INPUT,
                               "%s: mesh %u, vertex %u: the position (%g, %g, %g) is not finite; expected finite numbers",
                               cv->path, index, i, (double)p.x, (double)p.y, (double)p.z);
        m->positions[i] = v3(p.x, p.y, p.z);
        if (has_n) {
            if (!finite3(am->mNormals[i]))
                return status_fail(cv->err, GLINT_ERR_INPUT, "%s: mesh %u, vertex %u: the normal is not finite", cv->path,
                                   index, i);
            m->normals[i] = v3(am->mNormals[i].x, am->mNormals[i].y, am->mNormals[i].z);
        }
        if (has_uv) {
            if (!(isfinite(uvs[i].x) && isfinite(uvs[i].y)))
                return status_fail(cv->err, GLINT_ERR_INPUT,
                                   "%s: mesh %u, vertex %u: the texture coordinate is not finite", cv->path, index, i);
            m->uvs[i] = (uv2){uvs[i].x, uvs[i].y};
        }
    }
    m->position_count = nv;
    if (has_n) {
        m->normal_count = nv;
        m->smooth = true; // a vertex's normal is indexed like its position
        m->smooth_base = 0;
    }
    if (has_uv) m->uv_count = nv;
    size_t t = 0;
    for (unsigned f = 0; f < nf; f++) {
        const struct aiFace *face = &am->mFaces[f];
        const unsigned *ix = face->mIndices;
        for (unsigned k = 0; k < face->mNumIndices; k++)
            if (ix[k] >= nv)
                return status_fail(cv->err, GLINT_ERR_INPUT,
                                   "%s: mesh %u, face %u: vertex index %u is out of range (the mesh has %u vertices)",
                                   cv->path, index, f, ix[k], nv);
        if (face->mNumIndices != 3) {
            cv->not_triangles++;
            continue;
        }
        int32_t a = (int32_t)ix[0], b = (int32_t)ix[1], c = (int32_t)ix[2];
        vec3 e = v3_cross(v3_sub(m->positions[b], m->positions[a]), v3_sub(m->positions[c], m->positions[a]));
        if (e.x == 0.0f && e.y == 0.0f && e.z == 0.0f) {
            cv->zero_area++;
            continue;
        }
        m->triangles[t] = (mesh_triangle){{a, b, c}, -1};
        if (has_uv) m->uv_corners[t] = (mesh_corners){{a, b, c}};
        t++;
    }
    m->triangle_count = t;
    mesh_compute_bounds(m);
    return GLINT_OK;
}

static char *copy_string(const struct aiString *s) {
    size_t n = s->length < sizeof s->data ? s->length : sizeof s->data - 1;
    char *c = malloc(n + 1);
    if (!c) return NULL;
    memcpy(c, s->data, n);
    c[n] = '\0';
    return c;
}

// The image a texture of the material names: "*N" is embedded texture N, anything else a file beside the model.
// Images are listed once each (by name); *index is -1 when the material has no such texture.
static glint_status material_image(converter *cv, const struct aiMaterial *am, enum aiTextureType type, int32_t *index) {
    *index = -1;
    struct aiString s;
    if (aiGetMaterialTextureCount(am, type) == 0 ||
        aiGetMaterialTexture(am, type, 0, &s, NULL, NULL, NULL, NULL, NULL, NULL) != aiReturn_SUCCESS || s.length == 0)
        return GLINT_OK;
    int uv = 0;
    if (aiGetMaterialIntegerArray(am, AI_MATKEY_UVWSRC(type, 0), &uv, NULL) == aiReturn_SUCCESS && uv != 0 &&
        !cv->uv_set_warned) {
        cv->uv_set_warned = true;
        warn(cv, "a texture reads texture coordinate set %d: glint uses the first (TEXCOORD_0)", uv);
    }
    char *name = copy_string(&s);
    if (!name) return fail_oom(cv);
    model_file *m = cv->out;
    for (size_t i = 0; i < m->image_count; i++)
        if (strcmp(m->images[i].name, name) == 0 || (m->images[i].path && strcmp(m->images[i].path, name) == 0)) {
            free(name);
            *index = (int32_t)i;
            return GLINT_OK;
        }
    if (m->image_count >= MODEL_MAX_ITEMS) {
        free(name);
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: more than %d images", cv->path, MODEL_MAX_ITEMS);
    }
    model_image img = {0};
    img.name = name;
    if (name[0] == '*') {
        char *end;
        errno = 0;
        unsigned long k = strtoul(name + 1, &end, 10);
        if (*end || errno || k >= cv->sc->mNumTextures) {
            glint_status st = status_fail(cv->err, GLINT_ERR_INPUT,
                                          "%s: a material names embedded image %s, which the file does not have", cv->path, name);
            free(name);
            return st;
        }
        const struct aiTexture *tx = cv->sc->mTextures[k];
        if (tx->mHeight != 0 || !tx->pcData) {
            free(name);
            return status_fail(cv->err, GLINT_ERR_INPUT, "%s: embedded image %lu is not a compressed image file", cv->path, k);
        }
        img.size = tx->mWidth; // a compressed image's size in bytes
        if (!(img.data = malloc(img.size ? img.size : 1))) return free(name), fail_oom(cv);
        memcpy(img.data, tx->pcData, img.size);
    } else {
        // A file relative to the model's directory, its URI's %XX escapes decoded (assimp leaves them).
        size_t n = strlen(name);
        char *decoded = malloc(n + 1);
        if (!decoded) return free(name), fail_oom(cv);
        size_t j = 0;
        for (size_t i = 0; i < n; i++) {
            if (name[i] == '%' && isxdigit((unsigned char)name[i + 1]) && isxdigit((unsigned char)name[i + 2])) {
                char hex[3] = {name[i + 1], name[i + 2], 0};
                decoded[j++] = (char)strtol(hex, NULL, 16);
                i += 2;
            } else {
                decoded[j++] = name[i];
            }
        }
        decoded[j] = '\0';
        img.path = filepath_join(cv->path, filepath_dir_length(cv->path), decoded, j);
        free(decoded);
        if (!img.path) return free(name), fail_oom(cv);
    }
    model_image *grown = realloc(m->images, (m->image_count + 1) * sizeof *grown);
    if (!grown) {
        free(img.name), free(img.path), free(img.data);
        return fail_oom(cv);
    }
    m->images = grown;
    m->images[m->image_count] = img;
    *index = (int32_t)m->image_count++;
    return GLINT_OK;
}

static float clamp01(float x) { return fminf(1.0f, fmaxf(0.0f, x)); }
static float finite_or(float x, float fallback) { return isfinite(x) ? x : fallback; }

static glint_status convert_material(converter *cv, unsigned index, model_material *out) {
    const struct aiMaterial *am = cv->sc->mMaterials[index];
    memset(out, 0, sizeof *out);
    struct aiString name = {0};
    aiGetMaterialString(am, AI_MATKEY_NAME, &name);
    if (!(out->name = copy_string(&name))) return fail_oom(cv);
    // PLY has no materials: whatever assimp makes of a PLY file (a stand-in, vertex colours) is none.
    out->is_default = cv->format == MODEL_FORMAT_PLY || strcmp(out->name, AI_DEFAULT_MATERIAL_NAME) == 0;
    struct aiColor4D c;
    out->base_color = v3s(1.0f);
    out->alpha = 1.0f;
    if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS ||
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS) {
        out->base_color = v3(clamp01(finite_or(c.r, 1.0f)), clamp01(finite_or(c.g, 1.0f)), clamp01(finite_or(c.b, 1.0f)));
        out->alpha = clamp01(finite_or(c.a, 1.0f));
    }
    float f;
    out->metallic = 1.0f, out->roughness = 1.0f, out->ior = 1.5f, out->transmission = 0.0f;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_METALLIC_FACTOR, &f, NULL) == aiReturn_SUCCESS) out->metallic = clamp01(finite_or(f, 1.0f));
    if (aiGetMaterialFloatArray(am, AI_MATKEY_ROUGHNESS_FACTOR, &f, NULL) == aiReturn_SUCCESS) out->roughness = clamp01(finite_or(f, 1.0f));
    if (aiGetMaterialFloatArray(am, AI_MATKEY_REFRACTI, &f, NULL) == aiReturn_SUCCESS && isfinite(f) && f >= 1.0f && f <= 10.0f)
        out->ior = f;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_TRANSMISSION_FACTOR, &f, NULL) == aiReturn_SUCCESS)
        out->transmission = clamp01(finite_or(f, 0.0f));
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &c) == aiReturn_SUCCESS)
        out->emission = v3(fmaxf(0.0f, finite_or(c.r, 0.0f)), fmaxf(0.0f, finite_or(c.g, 0.0f)), fmaxf(0.0f, finite_or(c.b, 0.0f)));
    // KHR_materials_emissive_strength: apply_emissive_strength (assimp 5.2 does not read it).
    int two = 0;
    if (aiGetMaterialIntegerArray(am, AI_MATKEY_TWOSIDED, &two, NULL) == aiReturn_SUCCESS) out->double_sided = two != 0;
    out->alpha_cutoff = 0.5f;
    struct aiString mode;
    if (aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS) {
        if (strcmp(mode.data, "MASK") == 0) out->alpha_mode = MODEL_ALPHA_MASK;
        else if (strcmp(mode.data, "BLEND") == 0) out->alpha_mode = MODEL_ALPHA_BLEND;
    }
    if (aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_ALPHACUTOFF, &f, NULL) == aiReturn_SUCCESS && isfinite(f))
        out->alpha_cutoff = clamp01(f);
    out->normal_scale = 1.0f;
    glint_status st;
    if ((st = material_image(cv, am, aiTextureType_BASE_COLOR, &out->base_color_image)) != GLINT_OK) return st;
    if (out->base_color_image < 0 && (st = material_image(cv, am, aiTextureType_DIFFUSE, &out->base_color_image)) != GLINT_OK)
        return st;
    if ((st = material_image(cv, am, aiTextureType_UNKNOWN, &out->metallic_roughness_image)) != GLINT_OK) return st;
    if (out->metallic_roughness_image < 0 &&
        (st = material_image(cv, am, aiTextureType_METALNESS, &out->metallic_roughness_image)) != GLINT_OK)
        return st;
    if ((st = material_image(cv, am, aiTextureType_NORMALS, &out->normal_image)) != GLINT_OK) return st;
    if ((st = material_image(cv, am, aiTextureType_EMISSIVE, &out->emissive_image)) != GLINT_OK) return st;
    if ((st = material_image(cv, am, aiTextureType_TRANSMISSION, &out->transmission_image)) != GLINT_OK) return st;
    return GLINT_OK;
}

static mat4 to_mat4(const struct aiMatrix4x4 *a) {
    return (mat4){{{a->a1, a->a2, a->a3, a->a4}, {a->b1, a->b2, a->b3, a->b4}, {a->c1, a->c2, a->c3, a->c4},
                   {a->d1, a->d2, a->d3, a->d4}}};
}

static bool mat4_finite_affine(const mat4 *m) {
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(m->m[i][j])) return false;
    return m->m[3][0] == 0.0f && m->m[3][1] == 0.0f && m->m[3][2] == 0.0f && m->m[3][3] == 1.0f;
}

/// The model-space transform of the node named `name` (lights and cameras are placed by theirs); false if none.
static bool find_node(const struct aiNode *n, const char *name, mat4 parent, int depth, mat4 *out) {
    if (depth > MODEL_MAX_NODE_DEPTH) return false;
    mat4 local = to_mat4(&n->mTransformation), world = mat4_mul(&parent, &local);
    if (n->mName.length && strcmp(n->mName.data, name) == 0) {
        *out = world;
        return true;
    }
    for (unsigned i = 0; i < n->mNumChildren; i++)
        if (find_node(n->mChildren[i], name, world, depth + 1, out)) return true;
    return false;
}

/// Every (node, mesh) pair, with the node's model-space transform, depth first.
static glint_status walk_nodes(converter *cv, const struct aiNode *n, mat4 parent, int depth) {
    if (depth > MODEL_MAX_NODE_DEPTH)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: nodes nested deeper than %d", cv->path, MODEL_MAX_NODE_DEPTH);
    mat4 local = to_mat4(&n->mTransformation), world = mat4_mul(&parent, &local);
    if (!mat4_finite_affine(&world))
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: node \"%.200s\": its transform is not a finite affine matrix",
                           cv->path, n->mName.data);
    model_file *m = cv->out;
    bool singular = n->mNumMeshes && mat4_linear_det(&world) == 0.0;
    if (singular) cv->singular_nodes++; // glTF hides a node by scaling it to nothing
    for (unsigned i = 0; i < n->mNumMeshes && !singular; i++) {
        if (n->mMeshes[i] >= cv->sc->mNumMeshes)
            return status_fail(cv->err, GLINT_ERR_INPUT, "%s: node \"%.200s\" places mesh %u of %u", cv->path,
                               n->mName.data, n->mMeshes[i], cv->sc->mNumMeshes);
        if (m->placement_count >= MODEL_MAX_PLACEMENTS)
            return status_fail(cv->err, GLINT_ERR_INPUT, "%s: more than %d placed meshes", cv->path, MODEL_MAX_PLACEMENTS);
        if (m->placement_count % 64 == 0) {
            model_placement *grown = realloc(m->placements, (m->placement_count + 64) * sizeof *grown);
            if (!grown) return fail_oom(cv);
            m->placements = grown;
        }
        m->placements[m->placement_count++] = (model_placement){n->mMeshes[i], world};
    }
    for (unsigned i = 0; i < n->mNumChildren; i++) {
        glint_status st = walk_nodes(cv, n->mChildren[i], world, depth + 1);
        if (st != GLINT_OK) return st;
    }
    return GLINT_OK;
}

static vec3 from_ai(struct aiVector3D v) { return v3(v.x, v.y, v.z); }

static glint_status convert_lights(converter *cv) {
    const struct aiScene *sc = cv->sc;
    model_file *m = cv->out;
    if (!sc->mNumLights) return GLINT_OK;
    if (sc->mNumLights > MODEL_MAX_ITEMS)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: more than %d lights", cv->path, MODEL_MAX_ITEMS);
    if (!(m->lights = calloc(sc->mNumLights, sizeof *m->lights))) return fail_oom(cv);
    for (unsigned i = 0; i < sc->mNumLights; i++) {
        const struct aiLight *al = sc->mLights[i];
        model_light l = {0};
        if (al->mType == aiLightSource_POINT) l.kind = MODEL_LIGHT_POINT;
        else if (al->mType == aiLightSource_DIRECTIONAL) l.kind = MODEL_LIGHT_DIRECTIONAL;
        else if (al->mType == aiLightSource_SPOT) l.kind = MODEL_LIGHT_SPOT;
        else {
            warn(cv, "light \"%.200s\" is of a kind glint does not read (not point, spot or directional); ignored",
                 al->mName.data);
            continue;
        }
        mat4 xf;
        if (!find_node(sc->mRootNode, al->mName.data, mat4_identity(), 0, &xf) || !mat4_finite_affine(&xf)) {
            warn(cv, "light \"%.200s\" is placed by no node; ignored", al->mName.data);
            continue;
        }
        struct aiColor3D col = al->mColorDiffuse;
        l.intensity = v3(col.r, col.g, col.b);
        if (!v3_is_finite(l.intensity) || l.intensity.x < 0.0f || l.intensity.y < 0.0f || l.intensity.z < 0.0f)
            return status_fail(cv->err, GLINT_ERR_INPUT, "%s: light \"%.200s\": its intensity is not finite and >= 0",
                               cv->path, al->mName.data);
        l.position = mat4_apply_point(&xf, from_ai(al->mPosition));
        vec3 d = mat4_apply_vector(&xf, from_ai(al->mDirection));
        float len = v3_len(d);
        bool aimed = l.kind != MODEL_LIGHT_POINT; // a point light has no direction (assimp gives it none)
        if ((aimed && (!(len > 0.0f) || !isfinite(len))) || !v3_is_finite(l.position)) {
            warn(cv, "light \"%.200s\" has no direction or position after its node's transform; ignored", al->mName.data);
            continue;
        }
        l.direction = aimed ? v3_scale(d, 1.0f / len) : v3s(0.0f);
        l.inner_cone = al->mAngleInnerCone;
        l.outer_cone = al->mAngleOuterCone;
        if (l.kind == MODEL_LIGHT_SPOT &&
            !(isfinite(l.inner_cone) && isfinite(l.outer_cone) && l.inner_cone >= 0.0f && l.inner_cone < l.outer_cone &&
              l.outer_cone <= 1.5707964f))
            return status_fail(cv->err, GLINT_ERR_INPUT,
                               "%s: spot light \"%.200s\": expected 0 <= innerConeAngle < outerConeAngle <= pi/2, got "
                               "%g and %g", cv->path, al->mName.data, (double)l.inner_cone, (double)l.outer_cone);
        if (!(l.name = copy_string(&al->mName))) return fail_oom(cv);
        m->lights[m->light_count++] = l;
    }
    return GLINT_OK;
}

static glint_status convert_cameras(converter *cv) {
    const struct aiScene *sc = cv->sc;
    model_file *m = cv->out;
    if (!sc->mNumCameras) return GLINT_OK;
    if (sc->mNumCameras > MODEL_MAX_ITEMS)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: more than %d cameras", cv->path, MODEL_MAX_ITEMS);
    if (!(m->cameras = calloc(sc->mNumCameras, sizeof *m->cameras))) return fail_oom(cv);
    for (unsigned i = 0; i < sc->mNumCameras; i++) {
        const struct aiCamera *ac = sc->mCameras[i];
        mat4 xf;
        if (!find_node(sc->mRootNode, ac->mName.data, mat4_identity(), 0, &xf) || !mat4_finite_affine(&xf)) {
            warn(cv, "camera \"%.200s\" is placed by no node; ignored", ac->mName.data);
            continue;
        }
        model_camera c = {0};
        c.aspect = isfinite(ac->mAspect) && ac->mAspect > 0.0f ? ac->mAspect : 0.0f;
        // assimp 5.2 keeps glTF's yfov as mHorizontalFOV = yfov * aspectRatio, or yfov itself without an aspect.
        float h = ac->mHorizontalFOV;
        c.yfov = c.aspect > 0.0f ? h / c.aspect : h;
        if (!(isfinite(c.yfov) && c.yfov > 0.0f && c.yfov < 3.14159265f)) {
            warn(cv, "camera \"%.200s\" is not a perspective camera with a field of view in (0, pi); ignored",
                 ac->mName.data);
            continue;
        }
        // The node places the camera: assimp 5.2 also copies the node's translation into mPosition, which
        // would count it twice, so the camera sits at the node's origin (as glTF defines it).
        c.position = mat4_apply_point(&xf, v3s(0.0f));
        vec3 fwd = mat4_apply_vector(&xf, from_ai(ac->mLookAt)), up = mat4_apply_vector(&xf, from_ai(ac->mUp));
        // Up is made perpendicular to forward (a node's shear or non-uniform scale could tilt it).
        vec3 right = v3_cross(fwd, up);
        if (!v3_is_finite(c.position) || !(v3_len(fwd) > 0.0f) || !(v3_len(right) > 0.0f) ||
            !isfinite(v3_len(right))) {
            warn(cv, "camera \"%.200s\" has no view direction after its node's transform; ignored", ac->mName.data);
            continue;
        }
        c.forward = v3_unit(fwd);
        c.up = v3_unit(v3_cross(v3_unit(right), c.forward));
        if (!(c.name = copy_string(&ac->mName))) return fail_oom(cv);
        m->cameras[m->camera_count++] = c;
    }
    return GLINT_OK;
}

static glint_status convert(converter *cv) {
    const struct aiScene *sc = cv->sc;
    model_file *m = cv->out;
    if (!sc->mRootNode) return status_fail(cv->err, GLINT_ERR_INPUT, "%s: the file has no scene (no root node)", cv->path);
    if (sc->mNumMaterials > MODEL_MAX_ITEMS)
        return status_fail(cv->err, GLINT_ERR_INPUT, "%s: more than %d materials", cv->path, MODEL_MAX_ITEMS);
    if (sc->mNumMeshes && !(m->meshes = calloc(sc->mNumMeshes, sizeof *m->meshes))) return fail_oom(cv);
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        glint_status st = convert_mesh(cv, i, &m->meshes[i]);
        m->mesh_count = i + 1;
        if (st != GLINT_OK) return st;
    }
    if (sc->mNumMaterials && !(m->materials = calloc(sc->mNumMaterials, sizeof *m->materials))) return fail_oom(cv);
    for (unsigned i = 0; i < sc->mNumMaterials; i++) {
        glint_status st = convert_material(cv, i, &m->materials[i]);
        m->material_count = i + 1;
        if (st != GLINT_OK) return st;
    }
    glint_status st = walk_nodes(cv, sc->mRootNode, mat4_identity(), 0);
    if (st == GLINT_OK) st = convert_lights(cv);
    if (st == GLINT_OK) st = convert_cameras(cv);
    if (st != GLINT_OK) return st;
    if (cv->zero_area) warn(cv, "%zu triangles of zero area (collinear or repeated corners): skipped", cv->zero_area);
    if (cv->not_triangles) warn(cv, "%zu points and lines: skipped (glint renders triangles)", cv->not_triangles);
    if (cv->singular_nodes)
        warn(cv, "%zu nodes scale their meshes to nothing (a singular transform): those meshes are not placed",
             cv->singular_nodes);
    size_t placed = 0;
    for (size_t i = 0; i < m->placement_count; i++) placed += m->meshes[m->placements[i].mesh].geometry.triangle_count;
    if (placed == 0) warn(cv, "the file places no triangles");
    return GLINT_OK;
}

// ---------------------------------------------------------------------------------------------
// What assimp 5.2 does not read of a glTF file: KHR_materials_emissive_strength

/// Multiplies the emission of material i by its KHR_materials_emissive_strength, read from the file's JSON (the
/// .gltf, or a .glb's first chunk): assimp keeps glTF's materials in the file's order. A file that cannot be
/// read here was read by assimp, which reported what was wrong; nothing is changed then.
static void apply_emissive_strength(const char *path, model_file *m) {
    struct stat st;
    int problem;
    FILE *f = filepath_open_regular(path, &st, &problem);
    if (!f) return;
    size_t len;
    int errnum;
    char *data = file_read_stream(f, (size_t)st.st_size, MODEL_MAX_FILE_BYTES, &len, &errnum);
    fclose(f);
    if (!data) return;
    const char *json = data;
    size_t json_len = len;
    if (model_format_of(path) == MODEL_FORMAT_GLB) {
        // 12-byte header ("glTF", version, length), then chunk 0: length, type "JSON", the text.
        uint32_t chunk = 0;
        if (len < 20 || memcmp(data, "glTF", 4) != 0 || memcmp(data + 16, "JSON", 4) != 0) {
            free(data);
            return;
        }
        memcpy(&chunk, data + 12, 4);
        if (chunk > len - 20) {
            free(data);
            return;
        }
        json = data + 20;
        json_len = chunk;
    }
    cJSON *root = cJSON_ParseWithLength(json, json_len);
    free(data);
    const cJSON *mats = cJSON_GetObjectItemCaseSensitive(root, "materials");
    size_t i = 0;
    for (const cJSON *mat = cJSON_IsArray(mats) ? mats->child : NULL; mat && i < m->material_count; mat = mat->next, i++) {
        const cJSON *ext = cJSON_GetObjectItemCaseSensitive(mat, "extensions");
        const cJSON *es = cJSON_GetObjectItemCaseSensitive(ext, "KHR_materials_emissive_strength");
        const cJSON *k = cJSON_GetObjectItemCaseSensitive(es, "emissiveStrength");
        if (cJSON_IsNumber(k) && isfinite(k->valuedouble) && k->valuedouble >= 0.0 && k->valuedouble <= 1e6)
            m->materials[i].emission = v3_scale(m->materials[i].emission, (float)k->valuedouble);
    }
    cJSON_Delete(root);
}

glint_status model_read(const char *path, model_warning_fn warn_fn, void *user, model_file *out, glint_error *err) {
    return model_read_ex(path, true, warn_fn, user, out, err);
}

glint_status model_read_ex(const char *path, bool fast_ply, model_warning_fn warn_fn, void *user, model_file *out,
                           glint_error *err) {
    memset(out, 0, sizeof *out);
    if (model_format_of(path) == MODEL_FORMAT_NONE)
        return status_fail(err, GLINT_ERR_INPUT, "%s: not a glTF (.gltf, .glb) or PLY (.ply) file", path);
    if (model_format_of(path) == MODEL_FORMAT_PLY) {
        ply_layout layout;
        glint_status st = ply_check_header(path, &layout, err);
        if (st != GLINT_OK) return st;
        if (layout.fast && fast_ply) {
            bool taken;
            st = ply_read_fast(path, &layout, warn_fn, user, out, err, &taken);
            if (st != GLINT_OK) model_file_free(out);
            if (st != GLINT_OK || taken) return st;
        }
    }
    read_context ctx = {.path = path, .out = out};
    struct aiFileIO io = {file_open_proc, file_close_proc, (aiUserData)(void *)&ctx};
    // Polygons (PLY) become triangles; nothing else is made: no joined, generated or smoothed vertices.
    const unsigned flags = aiProcess_Triangulate;
    pthread_mutex_lock(&assimp_lock);
    current_read = &ctx;
    struct aiLogStream stream = {assimp_log, NULL};
    aiAttachLogStream(&stream);
    const struct aiScene *sc = aiImportFileEx(path, flags, &io);
    char assimp_message[600];
    snprintf(assimp_message, sizeof assimp_message, "%s", sc ? "" : aiGetErrorString());
    aiDetachLogStream(&stream);
    current_read = NULL;
    pthread_mutex_unlock(&assimp_lock);
    glint_status st = GLINT_OK;
    if (ctx.oom) {
        st = status_fail(err, GLINT_ERR_RENDER, "%s: out of memory while reading the model", path);
    } else if (!sc) {
        size_t n = strlen(assimp_message);
        while (n && (assimp_message[n - 1] == '\n' || assimp_message[n - 1] == ' ')) assimp_message[--n] = '\0';
        st = status_fail(err, GLINT_ERR_INPUT, "%s: cannot read it: %s%s%s", path, assimp_message[0] ? assimp_message : "assimp gave no reason",
                         ctx.open_problem[0] ? "; cannot open " : "", ctx.open_problem);
    } else if (ctx.dropped[0]) {
        st = status_fail(err, GLINT_ERR_INPUT, "%s: faces index vertices the file does not have (%s); expected every index "
                         "in range", path, ctx.dropped);
    } else {
        converter cv = {.path = path, .format = model_format_of(path), .sc = sc, .out = out, .err = err, .warn = warn_fn, .user = user};
        st = convert(&cv);
        if (st == GLINT_OK && model_format_of(path) != MODEL_FORMAT_PLY) apply_emissive_strength(path, out);
    }
    if (sc) aiReleaseImport(sc);
    if (st != GLINT_OK) model_file_free(out);
    return st;
}

#endif
