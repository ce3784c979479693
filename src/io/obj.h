// obj.h — a strict, fast Wavefront OBJ reader producing a glint triangle mesh, its material slots and what its MTL
// libraries say about them.
//
// OBJ: `v x y z [w | r g b [a]]` (extra numbers ignored), `vt u [v [w]]`, `vn x y z`, and faces `f` of 3 or
// more corners in any of the forms v, v/vt, v//vn, v/vt/vn, with positive (1-based) or negative (relative)
// indices that must refer to elements defined earlier in the file. Faces are triangulated: convex ones
// (after projection on the plane of their Newell normal) as a fan from their first corner, concave ones by
// ear clipping (up to OBJ_MAX_EAR_CLIP corners; larger concave faces become a fan with a warning, larger
// faces that are convex but for the rounding of their corners to float a fan without one). `o`, `g`,
// `s` are accepted and ignored, `usemtl` switches the material, `mtllib` reads material libraries relative
// to the OBJ file's directory (several names on one line allowed). CRLF line endings, tabs and `#` comments
// (a token starting with `#` ends the line) are accepted; `\` line continuation is not.
//
// Material libraries are read by the MTL reader (mtl.h) into plain records; every `usemtl` slot carries its
// record's values (obj_material.mtl), and the scene turns them into glint materials (scene_file_mesh.c).
//
// Errors (the load fails; the message is "file:line: what is wrong, expected what"): malformed or
// non-finite numbers, index 0 or out of range, too few/many numbers, faces with fewer than 3 corners,
// malformed face corners, statements missing their argument, MTL values out of range, more than 2^31 - 1
// elements. Limits (errors too; they bound memory by the file, not by what it declares): OBJ files up to
// OBJ_MAX_FILE_BYTES (2 GiB), MTL files up to MTL_MAX_FILE_BYTES (64 MiB), lines up to OBJ_MAX_LINE_BYTES
// (32 MiB), faces up to OBJ_MAX_FACE_CORNERS (2^20) corners; the OBJ_MAX_* limits are defined in the reader's
// private headers (obj_parser.h, obj_text.h). Running out of memory fails the load with GLINT_ERR_RENDER and
// "out of memory" in the message; every other failure is GLINT_ERR_INPUT.
// Warnings (reported through the callback, counted; the load goes on):
//   - a face of zero area (collinear or repeated corners): skipped;
//   - a material library that cannot be opened (missing, a directory, or not a regular file such as a
//     device or FIFO): its materials are undefined;
//   - `usemtl` of a name no library defines: the slot stays with defined = false, so the scene can
//     substitute the material the scene file gives the mesh (or its grey fallback);
//   - the MTL reader's warnings (mtl.h): a texture file that cannot be found (diffuse_map is NULL), a material
//     defined again, unsupported MTL statements;
//   - unsupported statements (`l`, `p`, curves, ...): ignored, reported once per keyword;
//   - a file without faces.
// The MTL keys glint reads and does not use (`Ka`, `bump`, ...) are not warnings of the reader: each library
// records them (obj_library.unsupported) and the scene warns once per file.
#ifndef GLINT_OBJ_H
#define GLINT_OBJ_H

#include "core/status.h"
#include "geometry/mesh.h"
#include "io/mtl.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// One material slot of a mesh, in the order of first `usemtl`; mesh_triangle.material indexes these.
typedef struct obj_material {
    char *name;        ///< the `usemtl` / `newmtl` name
    bool defined;      ///< false: no material library defines it; `mtl` is zeroed (illum -1)
    mtl_values mtl;    ///< what the first library that defines the name says about it
    char *diffuse_map; ///< map_Kd as a path usable from the current directory; NULL when absent or missing
    long line;         ///< OBJ line of the first `usemtl`
} obj_material;

/// A material library a model read, each once.
typedef struct obj_library {
    char *path;            ///< as opened
    uint32_t unsupported;  ///< mtl_library.unsupported: bit k, the file gives key mtl_unsupported_key_name(k)
    long unsupported_line; ///< the line of the first of them; 0 when there is none
} obj_library;

/// A loaded OBJ file.
typedef struct obj_model {
    mesh mesh;                  ///< triangles; material -1 for faces before any `usemtl`
    obj_material *materials;    ///< slots used by the faces
    size_t material_count;
    size_t warning_count;       ///< warnings reported (including those not passed to a callback)
    size_t zero_area_faces;     ///< faces skipped for having no area
    obj_library *libraries;     ///< the material library files read, in the order of their first `mtllib`
    size_t library_count;
} obj_model;

/// Receives each warning, formatted "file:line: warning: what happened; what is done instead"; in the file's order,
/// one call at a time, though not always on the caller's thread (a large file is read on several).
typedef void (*obj_warning_fn)(const char *message, void *user);

/// Options of a load; a NULL pointer or a zeroed struct means: no callback, files opened.
typedef struct obj_options {
    obj_warning_fn warn; ///< NULL: warnings are only counted
    void *user;          ///< passed to warn
    bool skip_files;     ///< do not open material libraries or check textures (fuzzing, in-memory use)
    bool statements_only; ///< read every line as a statement, never by a fast path (tests compare the two)
    int threads;          ///< threads that read a large file (obj_load; the model is the same for any number):
                          ///< 0 or 1 one, -1 all online CPUs
    size_t parallel_min;  ///< (tests) files from this size up are read on `threads` threads, in blocks of this
                          ///< size (at least 16 bytes); 0: files from 4 MiB, blocks of 1 MiB
} obj_options;

/// Loads an OBJ file and its material libraries. On failure returns GLINT_ERR_INPUT (GLINT_ERR_RENDER when
/// memory runs out) and a message in *err, and *out is empty. On success free *out with obj_model_free().
glint_status obj_load(const char *path, const obj_options *opt, obj_model *out, glint_error *err);
/// The same from memory; `name` names the file in messages and gives the directory for `mtllib`.
glint_status obj_parse(const char *name, const char *text, size_t length, const obj_options *opt, obj_model *out,
                       glint_error *err);
/// Frees what a successful load returned and leaves *m empty.
void obj_model_free(obj_model *m);

#endif
