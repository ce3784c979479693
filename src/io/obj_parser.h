// obj_parser.h — private to the OBJ reader (obj.c, obj_fast.c, obj_statements.c, obj_polygon.c, obj_model.c): its
// limits, the state of one file being read, and the steps its three readers of a line (statements, fast paths, the
// parallel pre-scan) share, so that they store exactly the same mesh from the same text. Calls run one way:
// obj.c -> obj_fast.c -> obj_statements.c -> obj_polygon.c -> obj_model.c, each calling only files to its right.
#ifndef GLINT_OBJ_PARSER_H
#define GLINT_OBJ_PARSER_H

#include "core/strmap.h"
#include "io/obj.h"
#include "io/obj_text.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/// Concave faces with more corners than this are fan-triangulated (ear clipping is quadratic).
#define OBJ_MAX_EAR_CLIP 256
/// Largest OBJ file read, in bytes (2 GiB): a mesh takes memory in proportion to its file.
#define OBJ_MAX_FILE_BYTES ((size_t)1 << 31)
/// Most corners of one face (2^20): triangulating a face takes 36 bytes of scratch memory per corner.
#define OBJ_MAX_FACE_CORNERS (1 << 20)

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

// obj_fast.c: the readers of a file and of its lines

/// The open OBJ file f, of `size` bytes, read line by line (on several threads when it is large and the options
/// allow it). False on a parse failure (message set, *errnum 0) or a read failure (*errnum: the read's errno,
/// EFBIG past OBJ_MAX_FILE_BYTES, ENOMEM).
bool obj_read_open_file(obj_parser *ps, FILE *f, size_t size, int *errnum);
/// Every line of (a part of) an OBJ text, counting on from ps->rep.line: by a fast path when it takes the
/// line, else as a statement.
bool obj_lines(obj_parser *ps, const char *text, size_t length);

// obj_statements.c: the general reader of a line

/// One line read as a statement (the general reader: every form the format allows, every message).
bool obj_statement(obj_parser *ps, obj_cursor *c);

// obj_polygon.c: faces into triangles

/// Splits the face of n corners in ps->corners into triangles: fan when convex, ear clipping when concave.
bool obj_triangulate(obj_parser *ps, size_t n);
/// A face of three corners: skipped, with a warning, when it has no area.
bool obj_triangle_face(obj_parser *ps, const obj_corner *k);

// obj_model.c: the model as it is built

/// "too many <what>, expected at most ..."; always false.
bool obj_too_many(obj_reporter *r, const char *what);
/// Stores a position: the last step of both the statements and the fast paths.
bool obj_add_position(obj_parser *ps, const float *v);
/// Stores a normal.
bool obj_add_normal(obj_parser *ps, const float *v);
/// Stores a texture coordinate of `count` numbers (v = 0 when only u is given).
bool obj_add_texcoord(obj_parser *ps, const float *v, int count);
/// Makes material name[0, n) the current one (`usemtl`), opening a slot for it at its first use.
bool obj_use_material(obj_parser *ps, const char *name, size_t n);
/// Gives each slot its definition from the libraries read, or warns and leaves it undefined.
bool obj_resolve_materials(obj_parser *ps);

#endif
