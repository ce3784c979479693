// model_read.h — glTF 2.0 (.gltf with its .bin and images, .glb) and PLY (ASCII and binary) files read through the
// Open Asset Import Library (assimp, Debian's libassimp-dev, its C API) into plain glint records: triangle meshes,
// the nodes that place them, glTF metallic-roughness materials, embedded images, punctual lights and cameras.
//
// assimp parses; glint checks what it hands back before anything is built from it (model_read.c): every file is
// opened by glint (a regular file, checked on its descriptor: a FIFO or a device never hangs the load, a missing
// .bin names itself) and is at most MODEL_MAX_FILE_BYTES; every index is in range (assimp drops faces with
// out-of-range indices with a warning: glint refuses the file, as it refuses an OBJ index out of range); every
// position, normal, texture coordinate and node transform is finite; counts stay within the MODEL_MAX_* limits.
// Faces of zero area and points and lines are skipped, with one warning each per file (as the OBJ reader does).
//
// assimp's post-processing is kept to triangulating polygons (PLY): no joined, generated or smoothed vertices,
// so the file's vertices and normals are the mesh's. assimp stores glTF texture coordinates with v up (it flips
// glTF's top-left origin), which is glint's convention (v = 1 is the image's top row).
//
// The simplest binary PLY files (little-endian, float vertex properties, triangles with a uchar count and 32-bit
// indices: what scanners and exporters write for large meshes) are read by glint itself (io/ply_fast.h), to the same
// records with the same checks and messages as through assimp (test_model_read compares the two): assimp's generic
// PLY tables took twice the time glint's OBJ reader takes for the same mesh. Every other PLY goes through assimp.
//
// Built without assimp (GLINT_HAVE_ASSIMP undefined), model_read refuses every file with a message that says so.
#ifndef GLINT_MODEL_READ_H
#define GLINT_MODEL_READ_H

#include "io/model_file.h"

/// Whether this glint was built with assimp.
bool model_read_available(void);
/// Reads a model file. On failure returns GLINT_ERR_INPUT (GLINT_ERR_RENDER when memory runs out) with a message
/// that starts with the file's path, and *out is empty.
glint_status model_read(const char *path, model_warning_fn warn, void *user, model_file *out, glint_error *err);
/// model_read, with (fast_ply) or without glint's own reading of the simplest binary PLY files (little-endian float
/// vertices, triangles only: io/ply_fast.h; every other file goes through assimp). The tests read a
/// file both ways and compare.
glint_status model_read_ex(const char *path, bool fast_ply, model_warning_fn warn, void *user, model_file *out,
                           glint_error *err);

#endif
