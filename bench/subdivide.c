// subdivide.c — the benchmark's mesh generator: 4:1 midpoint subdivision of a triangle mesh read from an OBJ
// file, LEVELS times (each level quadruples the triangles), written as an OBJ of `v` and `f` lines.
//
// usage: subdivide IN.obj OUT.obj LEVELS
//
// Reads `v` and `f` lines (every index form, negative indices, polygons fanned from their first corner) and
// ignores everything else. Each triangle (a, b, c) becomes (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)
// with the edge midpoints shared by the two triangles of an edge, so a closed mesh stays closed and the
// winding is kept. The surface does not change shape (the points are midpoints): what grows is the number of
// triangles, which is what the benchmark measures. bench/run.sh builds this file (with mesh_io.c) with the
// system compiler.
#include <stdio.h>
#include <stdlib.h>

#include "mesh_io.h"

// Open-addressing table from an edge (its two vertex indices, smaller first) to its midpoint's index.
typedef struct edge_table {
    uint64_t *keys; // (lo << 32 | hi) + 1; 0 = empty
    uint32_t *mid;
    size_t mask;
} edge_table;

static uint32_t midpoint(edge_table *t, meshbuf *m, uint32_t a, uint32_t b) {
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t key = ((uint64_t)lo << 32 | hi) + 1;
    for (size_t i = mesh_hash64(key) & t->mask;; i = (i + 1) & t->mask) {
        if (t->keys[i] == key) return t->mid[i];
        if (t->keys[i] == 0) {
            double p[3];
            for (int c = 0; c < 3; c++) p[c] = 0.5 * (m->verts[lo].p[c] + m->verts[hi].p[c]);
            t->keys[i] = key;
            return t->mid[i] = mesh_add_vertex(m, p);
        }
    }
}

static void subdivide(meshbuf *m) {
    size_t nt = m->nt, size = 1;
    while (size < 4 * nt) size *= 2; // at most 3 nt edges: the table stays under 3/4 full
    edge_table t = {calloc(size, sizeof *t.keys), malloc(size * sizeof *t.mid), size - 1};
    mesh_tri *old = m->tris;
    if (!t.keys || !t.mid) mesh_die("out of memory");
    m->tris = NULL;
    m->nt = m->capt = 0;
    for (size_t i = 0; i < nt; i++) {
        uint32_t a = old[i].v[0], b = old[i].v[1], c = old[i].v[2];
        uint32_t ab = midpoint(&t, m, a, b), bc = midpoint(&t, m, b, c), ca = midpoint(&t, m, c, a);
        mesh_add_tri(m, a, ab, ca);
        mesh_add_tri(m, ab, b, bc);
        mesh_add_tri(m, ca, bc, c);
        mesh_add_tri(m, ab, bc, ca);
    }
    free(old);
    free(t.keys);
    free(t.mid);
}

int main(int argc, char **argv) {
    mesh_tool_name("subdivide");
    if (argc != 4) {
        fprintf(stderr, "usage: subdivide IN.obj OUT.obj LEVELS\n");
        return 2;
    }
    char *end;
    long levels = strtol(argv[3], &end, 10);
    if (end == argv[3] || *end || levels < 0 || levels > 6) {
        fprintf(stderr, "subdivide: LEVELS must be an integer in 0..6\n");
        return 2;
    }
    meshbuf m = {0};
    mesh_read_obj(argv[1], &m);
    if (m.nt == 0) mesh_die("no faces in the input");
    size_t in = m.nt;
    for (long i = 0; i < levels; i++) subdivide(&m);
    char header[4200];
    snprintf(header, sizeof header, "%s subdivided 4:1 %ld times by bench/subdivide.c", argv[1], levels);
    mesh_write_obj(argv[2], &m, header);
    fprintf(stderr, "subdivide: %zu -> %zu triangles, %zu vertices\n", in, m.nt, m.nv);
    mesh_free(&m);
    return 0;
}
