// obj_parser.h — private to the OBJ reader (obj.c, obj_fast.c, obj_polygon.c): the state of one file being read,
// and the steps its three readers of a line (statements, fast paths, the parallel pre-scan) share, so that they
// store exactly the same mesh from the same text.
#ifndef GLINT_OBJ_PARSER_H
#define GLINT_OBJ_PARSER_H

#include "core/strmap.h"
#include "io/obj.h"
#include "io/obj_text.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// One face corner: indices (0-based) of its position, texture coordinate and normal; -1 when absent.
typedef struct obj_corner {
    int32_t v, t, n;
} obj_corner;

/// Triangles the fast path has read and not yet added, so that their corners' positions, far apart in a
/// large mesh, reach the cache while the next lines are read.
enum { OBJ_QUEUED_TRIANGLES = 8 };

/// A triangle read by the fast path, waiting in obj_parser.queue.
typedef struct obj_queued_triangle {
    obj_corner k[3];
    long line;
} obj_queued_triangle;

/// The reader of one OBJ file.
typedef struct obj_parser {
    obj_reporter rep;
    obj_model *model;
    const obj_options *opt;
    size_t pos_cap, nrm_cap, uv_cap, tri_cap, slot_cap;
    size_t nrm_corner_cap, uv_corner_cap; ///< of the mesh's normal_corners and uv_corners
    obj_corner *corners;                  ///< the corners of the face being read
    size_t corner_cap;
    double *px, *py;  ///< a face projected on its plane, for triangulation
    int *next, *prev; ///< the remaining polygon while ear clipping
    size_t scratch_cap;
    int32_t material;   ///< current slot, -1 before any usemtl
    strmap slots;       ///< material name -> slot in model->materials
    mtl_record *defs;   ///< everything the material libraries define, the first definition of each name
    size_t def_count, def_cap;
    strmap def_names;   ///< material name -> index in defs
    obj_library *libs;  ///< libraries read so far, so that a repeated mtllib is read once
    size_t lib_count, lib_cap;
    const char *dir;    ///< the OBJ file's name: its first dir_len bytes are its directory
    size_t dir_len;
    long first_zero_line;
    bool warned_fan, warned_bad_polygon;
    obj_queued_triangle queue[OBJ_QUEUED_TRIANGLES]; ///< a ring, oldest at queue_head
    int queue_head, queue_count;
} obj_parser;

// obj.c: statements, material slots and libraries, the start and end of a file

/// Readies the parser for the first line of file `name`.
void obj_begin(obj_parser *ps, const char *name, const obj_options *opt, obj_model *out, glint_error *err);
/// After the last line (ok) or a failure (!ok): gives the materials their definitions, says what is left to
/// say, frees the parser's scratch, and on failure the model too.
glint_status obj_end(obj_parser *ps, bool ok);
/// One line read as a statement (the general reader: every form the format allows, every message).
bool obj_statement(obj_parser *ps, obj_cursor *c);
/// "too many <what>, expected at most ..."; always false.
bool obj_too_many(obj_reporter *r, const char *what);
/// Stores a position: the last step of both the statements and the fast paths.
bool obj_add_position(obj_parser *ps, const float *v);
/// Stores a normal.
bool obj_add_normal(obj_parser *ps, const float *v);
/// Stores a texture coordinate of `count` numbers (v = 0 when only u is given).
bool obj_add_texcoord(obj_parser *ps, const float *v, int count);

// obj_polygon.c: faces into triangles

/// Splits the face of n corners in ps->corners into triangles: fan when convex, ear clipping when concave.
bool obj_triangulate(obj_parser *ps, size_t n);
/// A face of three corners: skipped, with a warning, when it has no area.
bool obj_triangle_face(obj_parser *ps, const obj_corner *k);

// obj_fast.c: fast paths and the file readers

/// Every line of (a part of) an OBJ text, counting on from ps->rep.line: by a fast path when it takes the
/// line, else as a statement.
bool obj_lines(obj_parser *ps, const char *text, size_t length);

#endif
