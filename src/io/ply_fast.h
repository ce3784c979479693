// ply_fast.h — PLY files before and instead of assimp: every PLY header is checked against the file's size before
// anything reads the body (assimp allocates what a header declares), and the simplest binary layout (little-endian,
// float vertex properties, triangles with a uchar count and 32-bit indices: what scanners and exporters write for
// large meshes) is read here into the same records, with the same checks and messages, as assimp's path gives
// (test_model_read compares the two): assimp's generic PLY tables took twice the time glint's OBJ reader takes.
#ifndef GLINT_PLY_FAST_H
#define GLINT_PLY_FAST_H

#include "io/model_file.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum { PLY_MAX_HEADER = 64 << 10 }; ///< bytes of a PLY header, at most

/// The layout of the PLY files glint reads itself (ply_read_fast): binary little-endian, the element "vertex" of
/// float properties (x, y, z; optionally nx, ny, nz and a texture coordinate pair; others skipped) and then the
/// element "face" of one list property (uchar count, 32-bit indices) whose every face is a triangle.
typedef struct ply_layout {
    bool fast;              ///< the header is of that layout
    size_t header_bytes;    ///< where the body starts
    uint32_t vertices, faces;
    unsigned stride;        ///< bytes of a vertex
    int pos[3], nrm[3], uv[2]; ///< byte offsets in a vertex, -1 when absent
} ply_layout;

/// Refuses a PLY file whose header declares more elements than its body could hold: every element needs at least
/// its properties' bytes (binary; a list at least its count) or two characters a property (ASCII: a digit and a
/// separator). A forged count would otherwise have assimp allocate gigabytes before it finds the file short.
/// Fills *layout (layout->fast: glint reads the body itself).
glint_status ply_check_header(const char *path, ply_layout *layout, glint_error *err);
/// Reads a PLY file of the fast layout into *out as the assimp path would (one mesh placed once, its material
/// none): the same vertices, triangles, checks and warnings, without assimp's generic element tables (which take
/// most of a large file's load). *taken is false, and *out empty, when a face is not a triangle: assimp reads the
/// file then (its triangulation).
glint_status ply_read_fast(const char *path, const ply_layout *l, model_warning_fn warn, void *user, model_file *out,
                           glint_error *err, bool *taken);

#endif
