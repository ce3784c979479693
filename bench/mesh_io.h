// mesh_io.h — the benchmark's mesh tools (subdivide.c, decimate.c): a triangle mesh in memory, read from and
// written to OBJ files of `v` and `f` lines. Not part of glint: the tools are built by bench/run.sh alone.
#ifndef BENCH_MESH_IO_H
#define BENCH_MESH_IO_H

#include <stddef.h>
#include <stdint.h>

typedef struct mesh_vertex {
    double p[3];
} mesh_vertex;

typedef struct mesh_tri {
    uint32_t v[3];
} mesh_tri;

/// A growable triangle mesh; zero-initialise it, free it with mesh_free.
typedef struct meshbuf {
    mesh_vertex *verts;
    size_t nv, capv;
    mesh_tri *tris;
    size_t nt, capt;
} meshbuf;

/// Prints "TOOL: WHAT" on stderr and exits with status 1 (TOOL set by mesh_tool_name).
_Noreturn void mesh_die(const char *what);
/// Names the tool in mesh_die's and the reader's messages.
void mesh_tool_name(const char *name);
/// Appends a vertex; returns its index.
uint32_t mesh_add_vertex(meshbuf *m, const double p[3]);
/// Appends the triangle (a, b, c).
void mesh_add_tri(meshbuf *m, uint32_t a, uint32_t b, uint32_t c);
/// Reads the `v` and `f` lines of an OBJ file (every index form, negative indices, polygons fanned from their
/// first corner) into M, ignoring everything else; exits with a message naming the line on bad input.
void mesh_read_obj(const char *path, meshbuf *m);
/// Writes M as an OBJ file: the comment line "# HEADER: V vertices, T triangles", then `v` and `f` lines.
void mesh_write_obj(const char *path, const meshbuf *m, const char *header);
/// A 64-bit mixing function (murmur3's finaliser) for the tools' open-addressing tables.
uint64_t mesh_hash64(uint64_t x);
/// Frees M's arrays and empties it.
void mesh_free(meshbuf *m);

#endif
